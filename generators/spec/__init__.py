"""The cam spec: one declaration per parameter (:mod:`.params`); the sections, the CamSpec model,
its validation and TOML in/out (:mod:`.model`); the built-in examples (:mod:`.examples`); the
reference generated from the declarations (:mod:`.reference`, docs/spec.md).  This package
re-exports :mod:`cam_workbench.generators.spec.model`'s names.
"""
from .model import (  # noqa: F401
    REQUIRED, Param, param, params_of, LAWS, CLOSED_FORM_LAWS, BSPLINE_FIELDS, SPAN_TOL_DEG, LIFT_FIELDS,
    CamSection, FollowerSection, MotionSegment, PitchSection, STEEL_MODULUS, MaterialSection,
    ChecksSection, DEFAULT_SEGMENTS, DXF_VERSIONS, DrawingSection, WORK_OFFSETS,
    MAX_COMMANDS_PER_REV, MachiningSection, OBJECTIVES, OPTIMISE_ALGORITHMS, OPTIMISE_VARIABLES,
    OptimiseSection, DynamicsSection, EcamSection, ECAM_TABLES, SECTIONS, CamSpec, validate, MAX_MOTION_SEGMENTS, optimise_variables,
    optimise_control_rows, load_spec, MAX_SPEC_BYTES, default_spec, DEFAULT_SPEC_DICT, to_toml,
    dict_to_toml, spec_digest,
)

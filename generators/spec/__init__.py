"""The cam spec: the declarations (:mod:`.params`), one module per TOML table (``cam``, ``follower``,
``motion``, ``pitch``, ``groove``, ``conjugate``, ``material``, ``checks``, ``drawing``, ``machining``,
``optimise``, ``dynamics`` with ``train``'s rules, ``ecam``), the root :class:`CamSpec` and the rules across
tables (:mod:`.model`), TOML in/out (:mod:`.toml_io`), the default cam (:mod:`.default`), the built-in
examples and the generated reference.  ``cam_workbench.generators.spec`` re-exports the public names below.
"""
from .cam import CamSection  # noqa: F401
from .checks import ChecksSection  # noqa: F401
from .default import DEFAULT_SPEC_DICT, default_spec  # noqa: F401
from .drawing import DXF_VERSIONS, DrawingSection  # noqa: F401
from .dynamics import DynamicsSection  # noqa: F401
from .ecam import ECAM_TABLES, EcamSection  # noqa: F401
from .follower import FollowerSection  # noqa: F401
from .machining import MAX_COMMANDS_PER_REV, WORK_OFFSETS, MachiningSection  # noqa: F401
from .material import STEEL_MODULUS, MaterialSection  # noqa: F401
from .model import LIFT_FIELDS, SECTIONS, CamSpec, validate  # noqa: F401
from .motion import BSPLINE_FIELDS, CLOSED_FORM_LAWS, LAWS, MAX_MOTION_SEGMENTS, SPAN_TOL_DEG, MotionSegment  # noqa: F401
from .optimise import (  # noqa: F401
    OBJECTIVES, OPTIMISE_ALGORITHMS, OPTIMISE_VARIABLES, OptimiseSection, optimise_control_rows,
    optimise_variables,
)
from .params import REQUIRED, Param, param, params_of  # noqa: F401
from .pitch import DEFAULT_SEGMENTS, PitchSection  # noqa: F401
from .toml_io import MAX_SPEC_BYTES, dict_to_toml, load_spec, spec_digest, to_toml  # noqa: F401

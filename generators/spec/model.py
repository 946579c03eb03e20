"""The spec's root: :class:`CamSpec`, which assembles the tables (``SECTIONS``: one module per TOML
table, :mod:`~cam_workbench.generators.spec.cam` … :mod:`~cam_workbench.generators.spec.ecam`), loads each
table into its dataclass against its declarations, and :func:`validate`, the rules across tables (then
each table's own rules and the kinds'); ``LIFT_FIELDS``, the fields in the follower's lift unit.

The field names and rules are the contract of ``shared/CAM_SPEC.md``; the project's
own reference is ``docs/spec.md``, generated from the tables' declarations by
``python -m cam_workbench.generators.spec.reference``.  Text in and out:
:mod:`~cam_workbench.generators.spec.toml_io`; the built-in default: :mod:`~cam_workbench.generators.spec.default`.

Conventions: lengths in ``units`` ("mm" or "in"), angles in degrees, speed in rpm.
"""
from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping

from ..bodies.features import validate_features
from ..errors import SpecError, fmt_apart
from ..kinds import body_of, follower_class_of
from .cam import CamSection
from .checks import ChecksSection
from .conjugate import ConjugateSection
from .drawing import DrawingSection, validate_drawing
from .dynamics import DynamicsSection
from .ecam import EcamSection, validate_ecam
from .follower import FollowerSection, validate_face, validate_follower_motion
from .groove import GrooveSection
from .linkage import LinkageSection, validate_linkage
from .indexer import INDEXER_FIELDS, INDEXER_ROLLER_BOUND, INDEXER_SIZE_FIELDS, IndexerSection, indexer_size
from .machining import MachiningSection, validate_machining
from .material import MaterialSection
from .motion import MotionSegment, inline_table_files, validate_motion
from .optimise import OptimiseSection, validate_optimise
from .params import REQUIRED, param, params_of
from .pitch import PitchSection, validate_pitch
from .train import validate_dynamics


#: Fields whose unit is the follower's lift unit (``Follower.lift_unit``): a length (``units``) for
#: translating followers, degrees of arm rotation for oscillating ones, whatever ``units`` says.
#: Their declarations say unit "length"; readers that convert units (the FreeCAD properties) read this.
LIFT_FIELDS = ("motion[].lift", "pitch.tolerance", "motion[].control_y", "motion[].points", "motion[].table",
               "motion[].table_tolerance", "motion[].start_velocity", "motion[].end_velocity",
               "motion[].start_acceleration", "motion[].end_acceleration", "motion[].start_jerk",
               "motion[].end_jerk")


#: Spec sections: TOML name → (dataclass, is an array of tables, required).  A new section
#: is a dataclass declared with ``param`` fields, an entry here and a field of CamSpec.
SECTIONS: dict[str, tuple[type, bool, bool]] = {
    "cam": (CamSection, False, True),
    "follower": (FollowerSection, False, True),
    "motion": (MotionSegment, True, True),
    "pitch": (PitchSection, False, False),
    "groove": (GrooveSection, False, False),
    "conjugate": (ConjugateSection, False, False),
    "material": (MaterialSection, False, False),
    "checks": (ChecksSection, False, False),
    "drawing": (DrawingSection, False, False),
    "machining": (MachiningSection, False, False),
    "optimise": (OptimiseSection, False, False),
    "dynamics": (DynamicsSection, False, False),
    "ecam": (EcamSection, False, False),
    "indexer": (IndexerSection, False, False),
    "linkage": (LinkageSection, False, False),
}


@dataclass(frozen=True, kw_only=True)
class CamSpec:
    """A complete, validated plate-cam description.  Build with :func:`load_spec`,
    :meth:`from_dict`, :meth:`from_kwargs` or :func:`default_spec`."""

    units: str = param("Length unit of the whole spec", kind="str", choices=("mm", "in"),
                       default="mm", group="Cam")
    cam: CamSection
    follower: FollowerSection
    motion: tuple[MotionSegment, ...]
    pitch: PitchSection = field(default_factory=PitchSection)
    groove: GrooveSection = field(default_factory=GrooveSection)
    conjugate: ConjugateSection = field(default_factory=ConjugateSection)
    material: MaterialSection = field(default_factory=MaterialSection)
    checks: ChecksSection = field(default_factory=ChecksSection)
    drawing: DrawingSection = field(default_factory=DrawingSection)
    machining: MachiningSection = field(default_factory=MachiningSection)
    optimise: OptimiseSection = field(default_factory=OptimiseSection)
    dynamics: DynamicsSection = field(default_factory=DynamicsSection)
    ecam: EcamSection = field(default_factory=EcamSection)
    indexer: IndexerSection = field(default_factory=IndexerSection)
    linkage: LinkageSection = field(default_factory=LinkageSection)

    # ---- construction -------------------------------------------------------------
    @classmethod
    def from_dict(cls, data: Mapping[str, Any], *, base_dir: str | Path | None = None) -> "CamSpec":
        """Build and validate a spec from the TOML structure as nested dicts/lists.

        ``base_dir``: the folder a ``motion[].table_file`` is relative to (:func:`load_spec` gives
        the spec file's; default the working directory).  The file is read into ``table``."""
        if not isinstance(data, Mapping):
            raise SpecError("spec", f"must be a table of sections, got {type(data).__name__}")
        _reject_unknown("", data, {"units", *SECTIONS})
        data = inline_table_files(data, base_dir)
        data = _indexer_defaults(_cylindrical_defaults(data))
        values: dict[str, Any] = {"units": params_of(CamSpec)["units"].check("units", data.get("units", "mm"))}
        for name, (section_cls, is_list, required) in SECTIONS.items():
            if name not in data:
                if required:
                    raise SpecError(name, "section is required")
                continue
            raw = data[name]
            if is_list:
                if not isinstance(raw, (list, tuple)) or not raw:
                    raise SpecError(name, f"must be a non-empty list of [[{name}]] tables")
                values[name] = tuple(_load_section(section_cls, m, f"{name}[{i}]") for i, m in enumerate(raw))
            else:
                values[name] = _load_section(section_cls, raw, name)
        spec = cls(**values)
        validate(spec)
        return spec

    @classmethod
    def from_kwargs(cls, **sections: Any) -> "CamSpec":
        """Same as :meth:`from_dict` with the top-level keys as keyword arguments."""
        return cls.from_dict(sections)

    def to_dict(self) -> dict[str, Any]:
        """The spec as the TOML structure (None-valued optional fields left out)."""
        out: dict[str, Any] = {"units": self.units}
        for f in dataclasses.fields(self):
            if f.name == "units":
                continue
            v = getattr(self, f.name)
            if isinstance(v, tuple):
                out[f.name] = [_section_dict(s) for s in v]
            else:
                out[f.name] = _section_dict(v)
        return out

    def replace(self, **changes: Any) -> "CamSpec":
        """A validated copy with dotted-path changes, e.g. ``replace(**{"cam.base_radius": 30})``
        or ``replace(**{"motion[1].lift": 12})``."""
        data = self.to_dict()
        for path, value in changes.items():
            _set_path(data, path, value)
        follow_derived_fields(data, changes)
        return CamSpec.from_dict(data)

    # ---- derived quantities ---------------------------------------------------------
    @property
    def is_roller(self) -> bool:
        return self.follower.kind == "roller"

    @property
    def roller_radius(self) -> float:
        """Roller radius, 0 for a knife edge."""
        return self.follower.roller_radius if self.is_roller else 0.0

    @property
    def prime_offset(self) -> float:
        """s₀ = √(R_b² − e²): distance along the follower line from the axis to the pitch point at zero lift."""
        return math.sqrt(self.cam.base_radius**2 - self.follower.offset**2)

    @property
    def max_lift(self) -> float:
        """Largest follower displacement of the program."""
        level, top = 0.0, 0.0
        for seg in self.motion:
            if seg.kind == "rise":
                level += seg.lift or 0.0
            elif seg.kind == "return":
                level -= seg.lift or 0.0
            top = max(top, level)
        return top


def _section_dict(obj: Any) -> dict[str, Any]:
    out = {}
    for f in dataclasses.fields(obj):
        v = getattr(obj, f.name)
        if v is None:
            continue
        if dataclasses.is_dataclass(v):
            v = _section_dict(v)
        elif isinstance(v, tuple):
            v = [(_section_dict(x) if dataclasses.is_dataclass(x) else
                  (list(x) if isinstance(x, tuple) else x)) for x in v]
        out[f.name] = v
    return out


def _set_path(data: dict[str, Any], path: str, value: Any) -> None:
    """Set the field at a dotted ``path`` (``cam.base_radius``, ``motion[1].lift``) in the spec's
    TOML structure; a path that does not fit the structure is a SpecError naming it."""
    if not isinstance(path, str) or not path:
        raise SpecError(str(path) or "--set", "is not a valid field path (write e.g. cam.base_radius=30)")
    parts = path.split(".")
    node: Any = data
    where = ""
    for i, part in enumerate(parts):
        m = re.fullmatch(r"([A-Za-z_]\w*)(?:\[(\d+)\])?", part)
        if not m:
            raise SpecError(path, "is not a valid field path (write e.g. cam.base_radius or motion[1].lift)")
        key, idx = m.group(1), m.group(2)
        last = i == len(parts) - 1
        if not isinstance(node, dict):
            raise SpecError(path, f"{where or 'the spec'} is a value, not a table: it has no field {key!r}")
        here = f"{where}.{key}" if where else key
        if idx is not None:
            node = node.setdefault(key, [])
            if not isinstance(node, list):
                raise SpecError(path, f"{here} is not a list: write {here}.FIELD without an index")
            k = int(idx)
            if k >= len(node):
                raise SpecError(path, f"index {k} is out of range (there are {len(node)})")
            here = f"{here}[{k}]"
            if last:
                node[k] = value
            else:
                node = node[k]
        elif last:
            if value is None:
                node.pop(key, None)
            else:
                node[key] = value
        else:
            nxt = node.setdefault(key, {})
            if isinstance(nxt, list):
                raise SpecError(path, f"{here} is a list of tables: write {here}[i].{parts[i + 1]}")
            node = nxt
        where = here


def follow_derived_fields(data: dict[str, Any], changes: Mapping[str, Any]) -> None:
    """In a spec dict whose ``changes`` (dotted paths) were just set, make the fields a body derives
    follow (in place): a cylindrical cam's :func:`follow_cylinder_fields`, an indexer's
    :func:`follow_indexer_size`."""
    follow_cylinder_fields(data, changes)
    follow_indexer_size(data, changes)


def follow_cylinder_fields(data: dict[str, Any], changes: Mapping[str, Any]) -> None:
    """In a spec dict of a cylindrical cam whose ``changes`` (dotted paths) set cam.cylinder_radius or
    cam.length but not cam.base_radius or cam.thickness, make those follow (in place): they are the
    same numbers (the body's rules)."""
    cam = data.get("cam")
    if not isinstance(cam, dict) or cam.get("body") != "cylindrical":
        return
    for k, src in (("base_radius", "cylinder_radius"), ("thickness", "length")):
        if f"cam.{src}" in changes and f"cam.{k}" not in changes and src in cam:
            cam[k] = cam[src]


def _cylindrical_defaults(data: Mapping[str, Any]) -> Mapping[str, Any]:
    """A cylindrical cam's ``cam.base_radius`` and ``cam.thickness`` are its ``cylinder_radius`` and
    ``length``: filled in when absent (a copy); when given they must agree (the body's rules)."""
    cam = data.get("cam")
    if not isinstance(cam, Mapping) or cam.get("body") != "cylindrical":
        return data
    pairs = (("base_radius", "cylinder_radius"), ("thickness", "length"))
    for k, src in pairs:
        if src not in cam:
            raise SpecError(f"cam.{src}", "is required for a cylindrical cam")
    fill = {k: cam[src] for k, src in pairs if k not in cam}
    if not fill:
        return data
    out = dict(data)
    out["cam"] = {**cam, **fill}
    return out


def _indexer_defaults(data: Mapping[str, Any]) -> Mapping[str, Any]:
    """An indexer's ``cam.base_radius`` is derived from ``[indexer]`` (:func:`.indexer.indexer_size`):
    filled in when absent (a copy); when given it must agree (the bodies' rules)."""
    cam = data.get("cam")
    if not isinstance(cam, Mapping) or cam.get("body") not in INDEXER_FIELDS or "base_radius" in cam:
        return data
    table = data.get("indexer")
    table = table if isinstance(table, Mapping) else {}
    for name in INDEXER_SIZE_FIELDS[cam["body"]]:
        if name not in table:
            raise SpecError(f"indexer.{name}", f'is required for cam.body = "{cam["body"]}"')
    size = indexer_size(cam["body"], table)
    if size is None:
        return data                 # the [indexer] rules name what is wrong
    if not size > 0:
        # e.g. a globoid whose root globoid reaches past the cam axis (waist C − root_radius ≤ 0)
        fields = INDEXER_SIZE_FIELDS[cam["body"]]
        raise SpecError(f"indexer.{fields[-1]}", f"leaves no cam: the size cam.base_radius derives from "
                        f"{', '.join('indexer.' + f for f in fields)} is {size:.6g} mm, must be > 0")
    fol = data.get("follower")
    rr = fol.get("roller_radius") if isinstance(fol, Mapping) else None
    words = INDEXER_ROLLER_BOUND.get(cam["body"])
    if words is not None and isinstance(rr, (int, float)) and not isinstance(rr, bool) and rr >= size:
        # the rule cam.base_radius > follower.roller_radius, in the indexer's words (it derives R_b)
        raise SpecError("follower.roller_radius", f"must be < {words} {size:.6g} (from [indexer]), got "
                        f"{fmt_apart(rr, size)}: a smaller roller or a larger indexer.centre_distance")
    out = dict(data)
    out["cam"] = {**cam, "base_radius": size}
    return out


def follow_indexer_size(data: dict[str, Any], changes: Mapping[str, Any]) -> None:
    """In a spec dict of an indexer whose ``changes`` do not set ``cam.base_radius``, drop it (in
    place): it is derived again from the ``[indexer]`` table as changed."""
    cam = data.get("cam")
    if isinstance(cam, dict) and cam.get("body") in INDEXER_FIELDS and "cam.base_radius" not in changes:
        cam.pop("base_radius", None)


def _reject_unknown(prefix: str, data: Mapping[str, Any], known: set[str]) -> None:
    for key in data:
        if key not in known:
            path = f"{prefix}.{key}" if prefix else str(key)
            raise SpecError(path, f"unknown field (known fields: {', '.join(sorted(known))})")


#: section class → its rules checked before its fields' own (``fn(data, path)``, SpecError naming the field)
PRECHECKS: dict[type, Callable[[Mapping[str, Any], str], None]] = {MotionSegment: MotionSegment.precheck}


def _load_section(cls: type, data: Any, path: str) -> Any:
    """Load one section table into its dataclass, checking every declared parameter."""
    if not isinstance(data, Mapping):
        raise SpecError(path, f"must be a table, got {data!r}")
    decl = params_of(cls)
    _reject_unknown(path, data, set(decl))
    precheck = PRECHECKS.get(cls)
    if precheck is not None:
        precheck(data, path)
    values = {}
    for name, p in decl.items():
        fpath = f"{path}.{name}"
        if name in data:
            values[name] = p.check(fpath, data[name])
        elif p.default is REQUIRED:
            raise SpecError(fpath, "is required")
        elif p.optional:
            values[name] = None
    return cls(**values)


# ---- cross-field validation ----------------------------------------------------------
def validate(spec: CamSpec) -> None:
    """Check every rule of CAM_SPEC.md that involves more than one field; raise SpecError."""
    cam, fol = spec.cam, spec.follower
    if fol.kind == "roller" and not fol.roller_radius > 0:
        raise SpecError("follower.roller_radius", f"must be > 0 for a roller follower, got {fmt_apart(fol.roller_radius, 0)}")
    validate_follower_motion(spec)
    validate_face(spec)
    if not abs(fol.offset) < cam.base_radius:
        raise SpecError("follower.offset",
                        f"|offset| must be < cam.base_radius ({fmt_apart(cam.base_radius, abs(fol.offset))}), got "
                        f"{fmt_apart(fol.offset, math.copysign(cam.base_radius, fol.offset))}")
    if body_of(spec).roller_within_base:
        if spec.is_roller and not cam.base_radius > fol.roller_radius:
            raise SpecError("cam.base_radius",
                            f"must be > follower.roller_radius ({fmt_apart(fol.roller_radius, cam.base_radius)}), got "
                            f"{fmt_apart(cam.base_radius, fol.roller_radius)}")
        r_surface = cam.base_radius - spec.roller_radius
        if not cam.bore_diameter < 2 * r_surface:
            raise SpecError("cam.bore_diameter",
                            f"must be < 2 × smallest cam-surface radius = 2 × (cam.base_radius {cam.base_radius:g} − "
                            f"follower.roller_radius {spec.roller_radius:g}) = {fmt_apart(2 * r_surface, cam.bore_diameter)}, "
                            f"got {fmt_apart(cam.bore_diameter, 2 * r_surface)}: a smaller bore or roller, or a larger base "
                            "radius")
    validate_motion(spec)
    follower_class_of(spec).validate(spec)     # the kinds' own rules, then the features every body shares
    body_of(spec).validate(spec)
    validate_features(spec)
    validate_pitch(spec)
    validate_drawing(spec)
    validate_machining(spec)
    validate_optimise(spec)
    validate_dynamics(spec)                    # the train's rules (and, when enabled, its data)
    validate_ecam(spec)
    validate_linkage(spec)                     # the follower-to-tool linkage over the motion


__all__ = ["CamSpec", "validate", "SECTIONS", "LIFT_FIELDS"]

"""Spec fields ↔ FreeCAD properties, generated from the one spec declaration.

Every declared spec field (``cam_workbench.generators.spec.params.params_of`` over ``cam_workbench.generators.spec.SECTIONS``)
becomes one property of the feature; its type, group, tooltip, unit and bounds come from
the field's :class:`~cam_workbench.generators.spec.params.Param`, nothing is written twice.  A field added to
the spec later appears on new features and is added to old ones when they are restored.

Naming: ``cam.base_radius`` → ``CamBaseRadius``; top-level ``units`` → ``Units``; a field of
an array-of-tables section (``motion[i].lift``) is one list property per field
(``MotionLift``), one entry per row ("parallel lists").

Units: every dimensional value is stored in ONE fixed unit, whatever the spec's ``units``
(:data:`UNIT_STORAGE`): lengths, forces, stresses and feeds are FreeCAD quantities
(``App::PropertyLength``/``Distance``, ``Force``, ``Pressure``, ``Speed``: FreeCAD's internal
mm, mN, kPa, mm/s; type "340 lbf" or "250 ksi" and FreeCAD converts), angles are degrees,
masses kg and spring rates N/mm (FreeCAD 0.20 has no property type for these; the tooltip
says so).  List properties hold plain numbers in the same storage units.  The spec's
``units`` only chooses the unit of the spec that is handed to ``generators`` (and of reports
and exports): switching ``Units`` never changes the cam.  Unit kinds that are the same in both
unit systems (rpm, seconds) are plain numbers.  Torques, torsional spring rates and moments of
inertia (an oscillating arm's load) are plain numbers in N·mm, N·mm/rad and kg·mm².

Lifts: the fields of ``cam_workbench.generators.spec.LIFT_FIELDS`` (``motion[].lift``, ``pitch.tolerance``)
are in the follower's lift unit (``Follower.lift_unit``, from ``FollowerMotion`` and
``FollowerKind``): a length as above for a translating follower, degrees of arm rotation for
an oscillating one — stored as degrees whatever ``Units`` says, ``PitchTolerance`` then an
``App::PropertyAngle`` (its type follows the follower: :func:`sync_lift_unit`).

Absent optional values (``None``): a number whose bounds exclude 0 stores 0, a string
stores "", a list of numbers stores nothing; any other optional field gets a companion
boolean ``<Property>Enabled``.  An optional section with required fields gets a boolean
``<Section>Enabled``.
"""
from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass
from typing import Any, Iterator

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.followers import follower_class
from cam_workbench.generators.spec.params import REQUIRED, Param, params_of, unit_name
from cam_workbench.generators.spec import LIFT_FIELDS, SECTIONS, CamSpec, default_spec
from cam_workbench.generators.spec.model import follow_indexer_size

MM_PER_INCH = 25.4
#: 1 lbf in N (exact by definition: 0.45359237 kg × 9.80665 m/s²).
LBF_N = 4.4482216152605
#: Unit kind → (FreeCAD property type, "" = plain number (lengths: chosen by the bounds),
#: storage unit, stored value per unit of a mm spec, per unit of an inch spec).
UNIT_STORAGE: dict[str, tuple[str, str, float, float]] = {
    "length": ("", "mm", 1.0, MM_PER_INCH),
    "force": ("App::PropertyForce", "mN", 1e3, LBF_N * 1e3),                      # N, lbf
    "stress": ("App::PropertyPressure", "kPa", 1e3, LBF_N / MM_PER_INCH**2 * 1e3),  # MPa, psi
    "feed": ("App::PropertySpeed", "mm/s", 1.0 / 60.0, MM_PER_INCH / 60.0),        # mm/min, in/min
    "mass": ("", "kg", 1.0, LBF_N / (MM_PER_INCH * 1e-3)),                         # kg, lbf·s²/in
    "stiffness": ("", "N/mm", 1.0, LBF_N / MM_PER_INCH),                           # N/mm, lbf/in
    "density": ("", "kg/mm³", 1.0, 0.45359237 / MM_PER_INCH**3),                   # kg/mm³, lb/in³
    "torque": ("", "N·mm", 1.0, LBF_N * MM_PER_INCH),                               # N·mm, lbf·in
    "torsional_stiffness": ("", "N·mm/rad", 1.0, LBF_N * MM_PER_INCH),              # N·mm/rad, lbf·in/rad
    # lbf·in·s² = (lbf·s²/in)·in²: the mass factor × (25.4 mm)²
    "inertia": ("", "kg·mm²", 1.0, LBF_N / (MM_PER_INCH * 1e-3) * MM_PER_INCH**2),  # kg·mm², lbf·in·s²
    # a motion segment's end velocity, acceleration, jerk per radian: lift units, stored as lengths
    "reduced_velocity": ("", "mm/rad", 1.0, MM_PER_INCH),
    "reduced_acceleration": ("", "mm/rad²", 1.0, MM_PER_INCH),
    "reduced_jerk": ("", "mm/rad³", 1.0, MM_PER_INCH),
}
#: Unit kinds that feature version 3 kept as plain numbers in the spec's units (converted by
#: :func:`migrate_lift_and_torque_units`).
_V3_PLAIN_KINDS = ("torque", "torsional_stiffness", "inertia")
#: Property type of a non-list field by value kind (float fields are refined by unit).
_LIST_TYPES = {"float": "App::PropertyFloatList", "int": "App::PropertyIntegerList",
               "str": "App::PropertyStringList", "bool": "App::PropertyBoolList",
               "floats": "App::PropertyStringList", "points": "App::PropertyStringList"}
_INT_MAX = 2**31 - 1
_FLOAT_MAX = 1e300
#: Marks a field that is not optional (so it needs no "absent" representation).
_NOT_OPTIONAL = object()


def camel(name: str) -> str:
    """``base_radius`` → ``BaseRadius``."""
    return "".join(part[:1].upper() + part[1:] for part in name.split("_"))


def _is_optional(p: Param) -> bool:
    return p.optional or (p.default is None)


def _nonnegative(p: Param) -> bool:
    return (p.ge is not None and p.ge >= 0) or (p.gt is not None and p.gt >= 0)


def _absent_value(p: Param, is_list: bool) -> Any:
    """The stored value meaning "absent" (None) for an optional field, None when the field
    needs a companion flag, or ``_NOT_OPTIONAL``."""
    if not _is_optional(p):
        return _NOT_OPTIONAL
    if p.kind in ("float", "int"):
        zero_invalid = (p.gt is not None and p.gt >= 0) or (p.ge is not None and p.ge > 0)
        return (0.0 if p.kind == "float" else 0) if zero_invalid else None
    if p.kind == "str":
        return "" if not (p.choices and "" in p.choices) else None
    if p.kind == "floats":
        return "" if is_list else ()
    if p.kind == "points":
        return ""
    return None


@dataclass(frozen=True)
class FieldProperty:
    """One spec field and the FreeCAD property that holds it."""

    section: str          # "" for top-level fields of CamSpec
    field: str
    param: Param
    is_list: bool         # a field of an array-of-tables section: one list entry per row
    name: str             # property name
    group: str            # property group
    type: str             # FreeCAD property type
    absent: Any           # stored value meaning None, None if a flag is needed, or _NOT_OPTIONAL

    @property
    def path(self) -> str:
        """Spec path, e.g. ``cam.base_radius`` or ``motion[].lift``."""
        if not self.section:
            return self.field
        return f"{self.section}[].{self.field}" if self.is_list else f"{self.section}.{self.field}"

    @property
    def flag(self) -> str | None:
        """Companion boolean (list) property marking the value as given, if one is needed."""
        return f"{self.name}Enabled" if self.absent is None else None

    @property
    def is_length(self) -> bool:
        return self.param.unit == "length" and self.param.kind in ("float", "floats")

    @property
    def is_lift(self) -> bool:
        """In the follower's lift unit (``cam_workbench.generators.spec.LIFT_FIELDS``): a length, or the arm's
        degrees for an oscillating follower."""
        return self.path in LIFT_FIELDS

    def type_for(self, lift: str = "length") -> str:
        """The property type for a follower whose lifts are of unit kind ``lift`` ("length",
        "angle"): an angle for a lift field of an oscillating follower, else :attr:`type`."""
        if self.is_lift and lift == "angle" and not self.is_list:
            return "App::PropertyAngle"
        return self.type

    @property
    def is_quantity(self) -> bool:
        """Held as a FreeCAD quantity (read through ``.Value``)."""
        return self.type in _QUANTITY_TYPES

    def factor(self, units: str, lift: str = "length") -> float:
        """Stored value per unit of the spec's ``units`` ("mm" or "in"); 1 for values stored as
        the spec gives them (degrees, and a lift in the arm's degrees: ``lift`` = "angle")."""
        if self.param.kind not in ("float", "floats", "points") or self.param.unit not in UNIT_STORAGE:
            return 1.0
        if self.is_lift and lift == "angle":
            return 1.0
        _type, _store, mm, inch = UNIT_STORAGE[self.param.unit]
        return inch if units == "in" else mm

    def unit_text(self) -> str:
        """How the value is stored and what the spec gets (for the tooltip)."""
        p = self.param
        mm, inch = unit_name(p.unit, "mm"), unit_name(p.unit, "in")
        if self.is_lift:
            conv = f"{mm} for mm specs, {inch} for inch specs"
            if self.is_list:
                return (f"the follower's lift: length in mm (the spec gets {conv}) for a translating "
                        "follower, degrees of arm rotation for an oscillating one (whatever Units says)")
            return (f"the follower's lift: a length, a FreeCAD quantity (type e.g. \"0.0004 {inch}\"; the spec "
                    f"gets {conv}) for a translating follower, an angle in degrees for an oscillating one "
                    "(the property's type follows FollowerMotion)")
        if p.kind in ("float", "floats") and p.unit in UNIT_STORAGE:
            kind = p.unit.replace("_", " ")
            conv = f"{mm} for mm specs, {inch} for inch specs"
            if self.is_quantity or (self.is_length and not self.is_list):
                return (f"{kind}, a FreeCAD quantity (type e.g. \"12 {inch}\"); the spec gets "
                        f"{conv}")
            store = UNIT_STORAGE[p.unit][1]
            return f"{kind} in {store}; the spec gets {conv}"
        if mm != inch:
            return f"{mm} for mm specs, {inch} for inch specs"
        if p.unit == "angle":
            return "degrees"
        return mm

    def tooltip(self) -> str:
        p = self.param
        unit = self.unit_text()
        parts = [p.doc + "."]
        facts = [f"spec field {self.path}"]
        if unit:
            facts.append(f"unit: {unit}")
        if p.rule_text():
            facts.append(f"rule: {p.rule_text()}")
        if self.absent is not _NOT_OPTIONAL and self.absent is not None:
            facts.append(f"{_absent_text(self.absent)} = not given")
        if self.is_list:
            facts.append("one entry per row; edit with the motion editor")
            if p.kind == "floats":
                facts.append("numbers separated by commas")
            if p.kind == "points":
                facts.append("rows \"angle, lift\" separated by semicolons (angles in degrees, lifts stored "
                             "as lengths in mm)")
        parts.append("(" + "; ".join(facts) + ")")
        return " ".join(parts)


_QUANTITY_TYPES = {"App::PropertyLength", "App::PropertyDistance", "App::PropertyAngle",
                   "App::PropertyForce", "App::PropertyPressure", "App::PropertySpeed"}


def _absent_text(v: Any) -> str:
    return '""' if v == "" else "empty" if v == () else str(v)


def _scalar_type(p: Param) -> str:
    if p.kind == "float":
        if p.unit == "length":
            return "App::PropertyLength" if _nonnegative(p) else "App::PropertyDistance"
        if p.unit == "angle":
            return "App::PropertyAngle"
        if p.unit in UNIT_STORAGE and UNIT_STORAGE[p.unit][0]:
            return UNIT_STORAGE[p.unit][0]
        if any(b is not None for b in (p.gt, p.ge, p.lt, p.le)):
            return "App::PropertyFloatConstraint"
        return "App::PropertyFloat"
    if p.kind == "int":
        return "App::PropertyIntegerConstraint"
    if p.kind == "str":
        return "App::PropertyEnumeration" if p.choices else "App::PropertyString"
    if p.kind == "bool":
        return "App::PropertyBool"
    if p.kind == "floats":
        return "App::PropertyFloatList"
    if p.kind == "points":
        return "App::PropertyString"
    raise TypeError(f"no FreeCAD property type for spec kind {p.kind!r}")


@functools.cache
def field_properties() -> tuple[FieldProperty, ...]:
    """Every spec field with its property, in declaration order (top level first); made once
    (from the spec's declarations, which do not change while FreeCAD runs)."""
    out = []
    for name, p in params_of(CamSpec).items():
        out.append(FieldProperty("", name, p, False, camel(name), p.group or "Cam",
                                 _scalar_type(p), _absent_value(p, False)))
    for section, (cls, is_list, _required) in SECTIONS.items():
        for name, p in params_of(cls).items():
            ptype = _LIST_TYPES[p.kind] if is_list else _scalar_type(p)
            out.append(FieldProperty(section, name, p, is_list, camel(section) + camel(name),
                                     p.group or camel(section), ptype, _absent_value(p, is_list)))
    names = [f.name for f in out]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise RuntimeError(f"spec fields map to the same FreeCAD property: {sorted(dup)}")
    return tuple(out)


def section_flag(section: str) -> str | None:
    """``<Section>Enabled`` for an optional section with required fields, else None."""
    cls, is_list, required = SECTIONS[section]
    if required or is_list:
        return None
    if any(p.default is REQUIRED for p in params_of(cls).values()):
        return camel(section) + "Enabled"
    return None


def list_sections() -> list[str]:
    return [s for s, (_c, is_list, _r) in SECTIONS.items() if is_list]


@functools.cache
def properties_of_section(section: str) -> tuple[FieldProperty, ...]:
    """The properties of one spec section (``""``: the top level), in declaration order."""
    return tuple(f for f in field_properties() if f.section == section)


# ---- adding properties -----------------------------------------------------------------
def ensure_properties(obj: Any, initial: dict[str, Any] | None = None) -> list[str]:
    """Add every spec property (and flag) that ``obj`` lacks; return the names added.

    Args:
        initial: spec dict giving the values of a new feature (e.g. ``default_spec().to_dict()``).
            None when upgrading an old feature: a field the old file did not have takes the
            value the spec gives an absent field (its declared default), so the cam is unchanged.
    """
    added: list[str] = []
    existing = set(obj.PropertiesList)
    rows_now = {s: _current_rows(obj, s) for s in list_sections()}
    units = _units_of(initial)
    lift = lift_unit_of_data(initial) if initial is not None else lift_unit_of(obj)
    for fp in field_properties():
        if fp.name not in existing:
            obj.addProperty(fp.type_for(lift), fp.name, fp.group, fp.tooltip())
            added.append(fp.name)
            if fp.is_list:
                n = rows_now[fp.section]
                rows = _initial_rows(fp.section, initial, n)
                _set_list(obj, fp, [r.get(fp.field) for r in rows], units, lift)
                obj.setEditorMode(fp.name, 1)  # read-only in the editor: use the motion editor
            else:
                _init_scalar(obj, fp, _initial_value(fp, initial), units, lift)
        if fp.flag and fp.flag not in existing:
            ptype = "App::PropertyBoolList" if fp.is_list else "App::PropertyBool"
            obj.addProperty(ptype, fp.flag, fp.group, f"{fp.name} is given (else the spec leaves "
                                                        f"{fp.path} out)")
            added.append(fp.flag)
            if fp.is_list:
                obj.setEditorMode(fp.flag, 1)
                rows = _initial_rows(fp.section, initial, rows_now[fp.section])
                setattr(obj, fp.flag, [r.get(fp.field) is not None for r in rows])
            else:
                setattr(obj, fp.flag, _initial_value(fp, initial) is not None)
    for section in SECTIONS:
        flag = section_flag(section)
        if flag and flag not in existing:
            obj.addProperty("App::PropertyBool", flag, camel(section),
                            f"Include the [{section}] section in the spec")
            setattr(obj, flag, bool(initial and section in initial))
            added.append(flag)
    refresh_choices(obj, existing)
    return added


def refresh_choices(obj: Any, names: set[str]) -> None:
    """Give the choice properties among ``names`` the choices their fields declare now: FreeCAD
    saves an enumeration's list with the document, so a choice added since (``drawing.curves =
    "cubic"``) would be missing from an older file.  The stored value is kept (a choice is never
    renamed, only added)."""
    for fp in field_properties():
        if fp.type != "App::PropertyEnumeration" or fp.is_list or fp.name not in names:
            continue
        choices = ([""] if fp.absent == "" else []) + list(fp.param.choices or ())
        if list(obj.getEnumerationsOfProperty(fp.name)) != choices:
            value = getattr(obj, fp.name)
            setattr(obj, fp.name, choices)
            setattr(obj, fp.name, value)


def _units_of(data: dict[str, Any] | None) -> str:
    return "in" if data and data.get("units") == "in" else "mm"


def lift_unit(motion: str, kind: str) -> str:
    """The unit kind of a follower's lifts ("length" or "angle"), read from its class
    (``Follower.lift_unit``); "length" for a combination the library does not know (the
    spec's validation names it)."""
    try:
        return follower_class(motion or "translating", kind).lift_unit
    except KeyError:
        return "length"


def lift_unit_of_data(data: dict[str, Any] | None) -> str:
    """The lift unit of a spec dict's follower (the default spec's when it has none)."""
    fol = (data or {}).get("follower") or default_spec().to_dict()["follower"]
    return lift_unit(fol.get("motion") or "translating", fol.get("kind", "roller"))


def lift_unit_of(obj: Any) -> str:
    """The lift unit of the feature's follower (``FollowerMotion``, ``FollowerKind``)."""
    return lift_unit(str(getattr(obj, "FollowerMotion", "") or "translating"),
                     str(getattr(obj, "FollowerKind", "roller")))


def sync_lift_unit(obj: Any, lift: str | None = None) -> list[str]:
    """Give the lift fields' scalar properties (``PitchTolerance``) the type of the follower's
    lift unit — a length quantity, or an angle for an oscillating follower — keeping the number
    (and the editor mode); return the properties whose type changed.  The list entries
    (``MotionLift``) are plain numbers and need no change."""
    lift = lift or lift_unit_of(obj)
    changed = []
    for fp in field_properties():
        if not fp.is_lift or fp.is_list or fp.name not in obj.PropertiesList:
            continue
        want = fp.type_for(lift)
        if obj.getTypeIdOfProperty(fp.name) == want:
            continue
        value = float(_value(getattr(obj, fp.name)))
        mode = obj.getEditorMode(fp.name)
        obj.removeProperty(fp.name)
        obj.addProperty(want, fp.name, fp.group, fp.tooltip())
        if mode:
            obj.setEditorMode(fp.name, mode)
        setattr(obj, fp.name, value)
        changed.append(fp.name)
    return changed


def _current_rows(obj: Any, section: str) -> int | None:
    for fp in properties_of_section(section):
        if fp.name in obj.PropertiesList:
            return len(getattr(obj, fp.name))
    return None


def _initial_rows(section: str, initial: dict[str, Any] | None, n_now: int | None) -> list[dict]:
    if n_now is not None:  # the section exists: a new field gets its default on every row
        return [{} for _ in range(n_now)]
    data = initial if initial is not None else default_spec().to_dict()
    return [dict(r) for r in data.get(section, [])]


def _initial_value(fp: FieldProperty, initial: dict[str, Any] | None) -> Any:
    if initial is not None:
        table = initial if not fp.section else initial.get(fp.section, {})
        if fp.field in table:
            return table[fp.field]
    p = fp.param
    if p.default is REQUIRED:
        if initial is None and fp.section and fp.section in default_spec().to_dict():
            # a required field new to an old file: there is no value that keeps the cam as it
            # was; take the default spec's so the document still builds
            return default_spec().to_dict()[fp.section].get(fp.field)
        return None
    return p.default


def _init_scalar(obj: Any, fp: FieldProperty, value: Any, units: str, lift: str = "length") -> None:
    p = fp.param
    if fp.type == "App::PropertyEnumeration":
        choices = list(p.choices or ())
        if fp.absent == "":
            choices = [""] + choices
        setattr(obj, fp.name, choices)
    elif fp.type == "App::PropertyIntegerConstraint":
        lo = 0 if fp.absent == 0 else int(p.ge if p.ge is not None else
                                          (p.gt + 1 if p.gt is not None else -_INT_MAX))
        hi = int(p.le if p.le is not None else (p.lt - 1 if p.lt is not None else _INT_MAX))
        v = _stored_scalar(fp, value, units, lift)
        setattr(obj, fp.name, (int(min(max(v, lo), hi)), lo, hi, 1))
        return
    elif fp.type == "App::PropertyFloatConstraint":
        lo = 0.0 if fp.absent == 0 else _stored_bound(fp, p.ge if p.ge is not None else p.gt, -_FLOAT_MAX)
        hi = _stored_bound(fp, p.le if p.le is not None else p.lt, _FLOAT_MAX)
        v = _stored_scalar(fp, value, units, lift)
        setattr(obj, fp.name, (float(min(max(v, lo), hi)), lo, hi, 1.0))
        return
    setattr(obj, fp.name, _stored_scalar(fp, value, units, lift))


def _stored_bound(fp: FieldProperty, bound: float | None, none: float) -> float:
    """A spec bound as a bound of the stored value: 0 and unit-free bounds carry over; a
    bound of a converted unit depends on ``Units``, so the spec's validation enforces it."""
    if bound is None:
        return none
    if bound == 0 or fp.factor("mm") == fp.factor("in") == 1.0:
        return float(bound)
    return none


# ---- spec values ↔ stored values -----------------------------------------------------------
def _zero(fp: FieldProperty) -> Any:
    k = fp.param.kind
    if k == "str":
        return fp.param.choices[0] if fp.param.choices else ""
    return {"float": 0.0, "int": 0, "bool": False, "floats": (), "points": ""}[k]


def _stored_scalar(fp: FieldProperty, value: Any, units: str, lift: str = "length") -> Any:
    if value is None:
        return fp.absent if fp.absent not in (None, _NOT_OPTIONAL) else _zero(fp)
    f = fp.factor(units, lift)
    if fp.param.kind == "floats":
        return [float(v) * f for v in value]
    if fp.param.kind == "float":
        return float(value) * f
    return value


def _stored_item(fp: FieldProperty, value: Any, units: str, lift: str = "length") -> Any:
    if value is None:
        return fp.absent if fp.absent not in (None, _NOT_OPTIONAL) else _zero(fp)
    k = fp.param.kind
    f = fp.factor(units, lift)
    if k == "floats":
        return ", ".join(repr(float(v) * f) for v in value)
    if k == "points":
        return format_points(value, f)
    if k == "float":
        return float(value) * f
    return value


def _set_list(obj: Any, fp: FieldProperty, values: list[Any], units: str, lift: str = "length") -> None:
    setattr(obj, fp.name, [_stored_item(fp, v, units, lift) for v in values])


def unscale(stored: float, factor: float) -> float:
    """The spec value whose stored value (value × ``factor``) is ``stored``.

    Among the doubles nearest to stored/factor that map back to ``stored`` exactly, the one
    with the shortest decimal form, so that a typed 12.7 (or 340 lbf) comes back as 12.7; when
    none does (a value typed in FreeCAD in another unit), stored/factor rounded to 15
    significant digits (a change below 1e-15 relative)."""
    if factor == 1.0:
        return stored
    y = stored / factor
    short = float(f"{y:.15g}")
    cands = {c for c in (short, y, math.nextafter(y, -math.inf), math.nextafter(y, math.inf))
             if c * factor == stored}
    if not cands:
        return short
    return min(cands, key=lambda c: (len(repr(c)), abs(c - y)))


def _value(raw: Any) -> Any:
    return float(raw.Value) if hasattr(raw, "Value") else raw  # a FreeCAD Quantity


def _read_scalar(obj: Any, fp: FieldProperty, units: str, lift: str = "length") -> Any:
    raw = getattr(obj, fp.name)
    if fp.flag and not getattr(obj, fp.flag):
        return None
    raw = _value(raw)
    if fp.param.kind == "floats":
        raw = tuple(float(v) for v in raw)
    if fp.absent is not _NOT_OPTIONAL and fp.absent is not None and raw == fp.absent:
        return None
    f = fp.factor(units, lift)
    if fp.param.kind == "floats":
        return tuple(unscale(v, f) for v in raw)
    if fp.param.kind == "float":
        return unscale(float(raw), f)
    return raw


def parse_floats(text: str, path: str) -> tuple[float, ...]:
    """"0.3772, 0.4424, …" → floats (commas or spaces between them).

    Raises:
        SpecError: an entry is not a number (named by its index, e.g. ``control_x[2]``)."""
    items = [t for t in re.split(r"[,;\s]+", text.strip()) if t]
    out = []
    for i, t in enumerate(items):
        try:
            v = float(t)
        except ValueError:
            raise SpecError(f"{path}[{i}]", f"must be a number, got {t!r}") from None
        if not math.isfinite(v):
            raise SpecError(f"{path}[{i}]", f"must be a finite number, got {t!r}")
        out.append(v)
    return tuple(out)


def format_points(rows: Any, factor: float = 1.0) -> str:
    """[[angle, lift], …] as the text of a list property entry: "0.0, 0.0; 30.0, 5.2" (the lift
    column × ``factor``: its storage unit)."""
    return "; ".join(f"{float(a)!r}, {float(b) * factor!r}" for a, b in rows)


def parse_points(text: str, path: str, factor: float = 1.0) -> tuple[tuple[float, float], ...]:
    """"0, 0; 30, 5.2" → ((0.0, 0.0), (30.0, 5.2)) with the lift column / ``factor``.

    Raises:
        SpecError: a row is not two numbers (named by its index, e.g. ``table[2]``)."""
    out = []
    for i, row in enumerate(r for r in text.split(";") if r.strip()):
        vals = parse_floats(row, f"{path}[{i}]")
        if len(vals) != 2:
            raise SpecError(f"{path}[{i}]", f"must be two numbers \"angle, lift\", got {row.strip()!r}")
        out.append((vals[0], unscale(vals[1], factor)))
    return tuple(out)


def format_floats(values: Any) -> str:
    """Floats as the comma-separated text of a list property entry (shortest exact form)."""
    return ", ".join(repr(float(v)) for v in values)


def _read_item(fp: FieldProperty, raw: Any, given: bool, units: str, path: str,
               lift: str = "length") -> Any:
    if not given:
        return None
    f = fp.factor(units, lift)
    if fp.param.kind == "floats":
        text = str(raw).strip()
        if not text:
            return None if fp.absent == "" else ()
        return tuple(unscale(v, f) for v in parse_floats(text, path))
    if fp.param.kind == "points":
        text = str(raw).strip()
        return parse_points(text, path, f) if text else None
    if fp.absent is not _NOT_OPTIONAL and fp.absent is not None and raw == fp.absent:
        return None
    if fp.param.kind == "float":
        return unscale(float(raw), f)
    return raw


def read_rows(obj: Any, section: str, units: str | None = None, lift: str | None = None
              ) -> list[dict[str, Any]]:
    """The rows of an array-of-tables section as spec dicts (values in the spec's units,
    absent optional values left out).

    Raises:
        SpecError: the parallel lists have different lengths, or a list entry is not a number.
    """
    if units is None:
        units = units_of(obj)
    if lift is None:
        lift = lift_unit_of(obj)
    fps = properties_of_section(section)
    lengths = {fp.name: len(getattr(obj, fp.name)) for fp in fps}
    lengths.update({fp.flag: len(getattr(obj, fp.flag)) for fp in fps if fp.flag})
    n = lengths[fps[0].name]
    for name, m in lengths.items():
        if m != n:
            raise SpecError(section, f"the {camel(section)} lists disagree: {name} has {m} entries, "
                                     f"{fps[0].name} has {n}")
    rows: list[dict[str, Any]] = [{} for _ in range(n)]
    for fp in fps:
        values = list(getattr(obj, fp.name))
        given = list(getattr(obj, fp.flag)) if fp.flag else [True] * n
        for i in range(n):
            v = _read_item(fp, values[i], given[i], units, f"{section}[{i}].{fp.field}", lift)
            if v is not None:
                rows[i][fp.field] = v
    return rows


def write_rows(obj: Any, section: str, rows: list[dict[str, Any]], units: str | None = None,
               lift: str | None = None) -> None:
    """Store the rows of an array-of-tables section (spec dicts, values in spec units; lifts
    in the lift unit ``lift``, default the feature's follower's)."""
    if units is None:
        units = units_of(obj)
    if lift is None:
        lift = lift_unit_of(obj)
    for fp in properties_of_section(section):
        _set_list(obj, fp, [r.get(fp.field) for r in rows], units, lift)
        if fp.flag:
            setattr(obj, fp.flag, [r.get(fp.field) is not None for r in rows])


def units_of(obj: Any) -> str:
    """The feature's spec units, "mm" or "in"."""
    return "in" if getattr(obj, "Units", "mm") == "in" else "mm"


def units_scale(obj: Any) -> float:
    """mm per spec length unit for the feature's current ``Units``."""
    return MM_PER_INCH if units_of(obj) == "in" else 1.0


def spec_dict(obj: Any) -> dict[str, Any]:
    """The spec held by the feature's properties, as the TOML structure (not yet validated).

    An indexer's ``cam.base_radius`` is left out: it is derived from ``[indexer]``
    (:func:`cam_workbench.generators.spec.model.follow_indexer_size`), and the stored
    ``CamBaseRadius`` is the one of the ``[indexer]`` values the feature was made with."""
    units = units_of(obj)
    lift = lift_unit_of(obj)
    data: dict[str, Any] = {}
    for fp in field_properties():
        if fp.section == "":
            v = _read_scalar(obj, fp, units, lift)
            if v is not None:
                data[fp.field] = v
    for section, (_cls, is_list, _required) in SECTIONS.items():
        flag = section_flag(section)
        if flag and not getattr(obj, flag):
            continue
        if is_list:
            data[section] = read_rows(obj, section, units, lift)
            continue
        table = {}
        for fp in properties_of_section(section):
            v = _read_scalar(obj, fp, units, lift)
            if v is not None:
                table[fp.field] = v
        data[section] = table
    follow_indexer_size(data, {})
    return data


def spec_of(obj: Any) -> CamSpec:
    """The validated spec of the feature.

    Raises:
        SpecError: a property breaks a rule (the field is the spec path).
    """
    return CamSpec.from_dict(spec_dict(obj))


def write_spec(obj: Any, spec: CamSpec | dict[str, Any]) -> None:
    """Set every spec property of ``obj`` from a spec (or its dict)."""
    data = spec.to_dict() if isinstance(spec, CamSpec) else spec
    units = _units_of(data)
    lift = lift_unit_of_data(data)
    sync_lift_unit(obj, lift)
    by_section: dict[str, list[FieldProperty]] = {}
    for fp in field_properties():
        by_section.setdefault(fp.section, []).append(fp)
    for fp in by_section.pop(""):
        _write_scalar(obj, fp, data.get(fp.field), units, lift)
    for section, fps in by_section.items():
        flag = section_flag(section)
        if flag:
            setattr(obj, flag, section in data)
        if SECTIONS[section][1]:
            write_rows(obj, section, list(data.get(section, [])), units, lift)
            continue
        table = data.get(section, {})
        for fp in fps:
            value = table.get(fp.field)
            if value is None and not _is_optional(fp.param) and fp.param.default is not REQUIRED:
                value = fp.param.default
            _write_scalar(obj, fp, value, units, lift)


def _write_scalar(obj: Any, fp: FieldProperty, value: Any, units: str, lift: str = "length") -> None:
    if fp.flag:
        setattr(obj, fp.flag, value is not None)
    stored = _stored_scalar(fp, value, units, lift)
    setattr(obj, fp.name, stored)


# ---- documents of feature version 1 -----------------------------------------------------------
#: Unit kinds that version 1 kept as plain numbers in the spec's units.
_V1_PLAIN_KINDS = ("force", "stress", "feed", "mass", "stiffness", "density")


def migrate_optional_choices(obj: Any) -> list[str]:
    """Feature version 2 → 3: choice fields that became optional — ``machining.rotary_line``,
    absent meaning "by the follower's kind" since oscillating followers arrived — get their ""
    (absent) choice, keeping the stored value.  Such a document's follower is translating (they
    came with version 3), for which an absent rotary line is the follower's own line: its
    stored "follower" (the default then) becomes absent, so the spec reads as that cam's TOML
    file does, and the cam is unchanged.  Returns nothing (no value changes meaning)."""
    for fp in field_properties():
        if (fp.type != "App::PropertyEnumeration" or fp.absent != "" or fp.is_list
                or fp.name not in obj.PropertiesList):
            continue
        choices = [""] + list(fp.param.choices or ())
        if list(obj.getEnumerationsOfProperty(fp.name)) != choices:
            value = getattr(obj, fp.name)
            setattr(obj, fp.name, choices)
            setattr(obj, fp.name, value if value in choices else "")
    if "MachiningRotaryLine" in obj.PropertiesList and obj.MachiningRotaryLine == "follower":
        obj.MachiningRotaryLine = ""          # a version-2 document's follower is translating
    return []


def migrate_plain_numbers(obj: Any) -> list[str]:
    """Feature version 1 → 2: forces, stresses, feeds (plain numbers in the spec's units then)
    become FreeCAD quantities, masses and spring rates are stored in kg and N/mm; the values
    are converted with the document's ``Units`` so the spec is unchanged.  Returns the
    properties converted.  Properties the file does not have are left to
    :func:`ensure_properties`."""
    units = units_of(obj)
    existing = set(obj.PropertiesList)
    done = []
    for fp in field_properties():
        if fp.name not in existing or fp.param.unit not in _V1_PLAIN_KINDS:
            continue
        old = getattr(obj, fp.name)
        f = fp.factor(units)
        if fp.is_list:
            setattr(obj, fp.name, [float(v) * f for v in old])  # FloatList: same type
        else:
            old = float(_value(old))
            if obj.getTypeIdOfProperty(fp.name) != fp.type:
                mode = obj.getEditorMode(fp.name)
                obj.removeProperty(fp.name)
                obj.addProperty(fp.type, fp.name, fp.group, fp.tooltip())
                if mode:
                    obj.setEditorMode(fp.name, mode)
            setattr(obj, fp.name, old * f)
        done.append(fp.name)
    return done


def migrate_lift_and_torque_units(obj: Any) -> list[str]:
    """Feature version 3 → 4: what version 3 stored by the spec's ``units`` alone gets the unit
    of what it is, so the spec is unchanged —

    * torques, torsional spring rates and arm inertias (plain numbers in the spec's units then,
      lbf·in for an inch document) are stored in N·mm, N·mm/rad and kg·mm²;
    * an oscillating follower's lifts (``MotionLift``: the arm's degrees, which version 3 scaled
      by 25.4 in an inch document as if they were inches) are stored as degrees, and
      ``PitchTolerance`` (a length quantity then) becomes an angle holding the degrees.

    Returns the properties converted (only those whose stored number or type changes)."""
    units = units_of(obj)
    lift = lift_unit_of(obj)
    existing = set(obj.PropertiesList)
    done = []
    for fp in field_properties():
        if fp.name not in existing:
            continue
        if fp.param.unit in _V3_PLAIN_KINDS and not fp.is_list:
            f = fp.factor(units)
            if f != 1.0:
                setattr(obj, fp.name, float(_value(getattr(obj, fp.name))) * f)
                done.append(fp.name)
        elif fp.is_lift and lift == "angle":
            f_old = fp.factor(units, "length")   # version 3 stored the degrees as lengths
            if fp.is_list:
                if f_old != 1.0 and any(str(v).strip() for v in getattr(obj, fp.name)):
                    setattr(obj, fp.name, [_unscale_entry(fp, v, f_old) for v in getattr(obj, fp.name)])
                    done.append(fp.name)
                continue
            old = float(_value(getattr(obj, fp.name)))
            sync_lift_unit(obj, lift)
            setattr(obj, fp.name, unscale(old, f_old))
            done.append(fp.name)
    return done


def _unscale_entry(fp: FieldProperty, v: Any, factor: float) -> Any:
    """A list property's entry stored × ``factor`` brought back to the spec's number (a float, a
    "1.0, 2.0" value list or a "0, 0; 30, 5.2" points text; empty entries stay empty)."""
    if fp.param.kind == "float":
        return unscale(float(v), factor)
    text = str(v).strip()
    if not text:
        return v
    if fp.param.kind == "points":
        return format_points(parse_points(text, fp.path, factor))
    return ", ".join(repr(unscale(x, factor)) for x in parse_floats(text, fp.path))


def refresh_tooltips(obj: Any) -> None:
    """Set every spec property's tooltip and group to the current declaration's (they are
    stored in the document and would otherwise keep an older wording or group)."""
    existing = set(obj.PropertiesList)
    for fp in field_properties():
        for name, tip in ((fp.name, fp.tooltip()), (fp.flag, None)):
            if name is None or name not in existing:
                continue
            if tip is not None and hasattr(obj, "setDocumentationOfProperty"):
                obj.setDocumentationOfProperty(name, tip)
            if hasattr(obj, "setGroupOfProperty") and obj.getGroupOfProperty(name) != fp.group:
                obj.setGroupOfProperty(name, fp.group)


# ---- messages ------------------------------------------------------------------------------
_PATH = re.compile(r"^(\w+)(?:\[(\d*)\])?(?:\.(\w+))?$")


def describe_field(path: str) -> str:
    """A spec path as the user sees it in FreeCAD: ``motion[3].angle`` →
    ``MotionAngle[3] (motion[3].angle)``; unknown paths are returned unchanged."""
    m = _PATH.match(path)
    if not m:
        return path
    head, index, field = m.group(1), m.group(2), m.group(3)
    for fp in field_properties():
        if (fp.section == "" and field is None and fp.field == head) or \
                (fp.section == head and fp.field == field):
            suffix = f"[{index}]" if index else ""
            return f"{fp.name}{suffix} ({path})"
    if head in SECTIONS and field is None:
        return f"{camel(head)} ({path})"
    return path


def field_property(path: str) -> FieldProperty:
    """The property of a spec field given by its path (``optimise.base_radius_min``)."""
    section, _, field = path.rpartition(".")
    for fp in field_properties():
        if fp.section == section and fp.field == field:
            return fp
    raise KeyError(path)


def field_tooltip(path: str) -> str:
    """The tooltip of a spec field's property (its declaration's doc, unit and rule) with the
    property's name, for widgets that edit the field elsewhere (the optimiser panel)."""
    fp = field_property(path)
    return f"{fp.name}: {fp.tooltip()}"


def iter_property_names() -> Iterator[str]:
    """Every property (and flag) name this module manages."""
    for fp in field_properties():
        yield fp.name
        if fp.flag:
            yield fp.flag
    for section in SECTIONS:
        if section_flag(section):
            yield section_flag(section)  # type: ignore[misc]


__all__ = ["FieldProperty", "LBF_N", "MM_PER_INCH", "UNIT_STORAGE", "camel", "describe_field",
           "ensure_properties", "field_properties", "field_property", "field_tooltip", "format_floats", "iter_property_names",
           "lift_unit", "lift_unit_of", "lift_unit_of_data", "migrate_lift_and_torque_units",
           "migrate_plain_numbers", "parse_floats", "read_rows", "refresh_tooltips", "spec_dict",
           "spec_of", "sync_lift_unit", "unscale", "units_of", "units_scale", "write_rows", "write_spec"]

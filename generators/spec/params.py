"""One declaration per spec parameter: unit, default, bounds, choices and a one-line doc.

Every spec dataclass field is declared with :func:`param`.  The loader validates
against these declarations, and the CLI help, the FreeCAD properties and
``docs/spec.md`` are generated from them, so nothing is written twice.
"""
from __future__ import annotations

import dataclasses
import math
import operator
from dataclasses import dataclass
from typing import Any

from ..errors import SpecError, fmt_apart

#: Unit kinds.  The concrete unit of a kind depends on the spec's ``units``.
UNIT_NAMES: dict[str, dict[str, str]] = {
    "length": {"mm": "mm", "in": "in"},
    "angle": {"mm": "deg", "in": "deg"},
    "speed": {"mm": "rpm", "in": "rpm"},
    "force": {"mm": "N", "in": "lbf"},
    "mass": {"mm": "kg", "in": "lbf·s²/in"},
    "stiffness": {"mm": "N/mm", "in": "lbf/in"},
    "stress": {"mm": "MPa", "in": "psi"},
    "time": {"mm": "s", "in": "s"},
    "feed": {"mm": "mm/min", "in": "in/min"},
    "spindle": {"mm": "rpm", "in": "rpm"},
    "density": {"mm": "kg/mm³", "in": "lb/in³"},
    "torque": {"mm": "N·mm", "in": "lbf·in"},
    "torsional_stiffness": {"mm": "N·mm/rad", "in": "lbf·in/rad"},
    "inertia": {"mm": "kg·mm²", "in": "lbf·in·s²"},
    # reduced (per radian of cam rotation) follower velocity, acceleration, jerk: lift units
    # (length, or degrees of arm rotation for an oscillating follower) per rad^n
    "reduced_velocity": {"mm": "mm/rad", "in": "in/rad"},
    "reduced_acceleration": {"mm": "mm/rad²", "in": "in/rad²"},
    "reduced_jerk": {"mm": "mm/rad³", "in": "in/rad³"},
    "": {"mm": "", "in": ""},
}


#: Largest magnitude of a value of each unit kind (in the spec's units): far beyond any real
#: cam, small enough that the geometry, the solvers and the G-code stay finite and readable.
MAX_MAGNITUDE: dict[str, float] = {
    "length": 1.0e5, "angle": 1.0e4, "speed": 1.0e5, "force": 1.0e9, "mass": 1.0e6, "stiffness": 1.0e9,
    "stress": 1.0e12, "time": 1.0e3, "feed": 1.0e6, "spindle": 1.0e6, "density": 1.0e3, "torque": 1.0e12,
    "torsional_stiffness": 1.0e12, "inertia": 1.0e12, "reduced_velocity": 1.0e7, "reduced_acceleration": 1.0e9,
    "reduced_jerk": 1.0e11, "": 1.0e9,
}
#: Most rows of a "points" field (a motion table, a polynomial's interior points).
MAX_POINT_ROWS = 20000
#: Smallest magnitude of a strictly positive value (``gt=0``) of each unit kind: below it a
#: G-code word or a geometric tolerance rounds to nothing.
MIN_POSITIVE: dict[str, float] = {"length": 1.0e-9, "feed": 1.0e-3, "spindle": 1.0, "speed": 1.0e-6,
                                  "time": 1.0e-6}
#: Largest value of an integer field that declares no bound of its own.
MAX_INT = 1_000_000


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


REQUIRED: Any = _Required()


@dataclass(frozen=True)
class Param:
    """Declaration of one spec field.

    Attributes:
        doc: one-line description (shown in CLI help, FreeCAD tooltips, docs).
        kind: value type: "float", "int", "str", "bool", "floats" (list of floats),
            "points" (list of [cam angle in degrees, lift] rows; ``unit`` is the lift's).
        unit: unit kind (a key of :data:`UNIT_NAMES`), "" for dimensionless.
        default: default value, or :data:`REQUIRED`.
        choices: allowed values for "str" fields.
        gt, ge, lt, le: numeric bounds (exclusive / inclusive).
        optional: the field may be absent (None) without a default.
        group: FreeCAD property group.
        bound_note: why the bounds are what they are, in a few words (shown with the rule in
            messages and docs), e.g. the math that needs a minimum.
    """

    doc: str
    kind: str = "float"
    unit: str = ""
    default: Any = REQUIRED
    choices: tuple[str, ...] | None = None
    gt: float | None = None
    ge: float | None = None
    lt: float | None = None
    le: float | None = None
    optional: bool = False
    group: str = ""
    bound_note: str = ""

    def rule_text(self) -> str:
        """The bounds/choices of this parameter in words (for docs)."""
        parts = []
        if self.choices:
            parts.append("one of " + ", ".join(f'"{c}"' for c in self.choices))
        for op, v in (("> ", self.gt), ("≥ ", self.ge), ("< ", self.lt), ("≤ ", self.le)):
            if v is not None:
                parts.append(f"{op}{_fmt(v)}")
        text = ", ".join(parts)
        return f"{text} ({self.bound_note})" if text and self.bound_note else text

    def check(self, path: str, value: Any) -> Any:
        """Coerce and validate ``value`` for the field at ``path``; raise SpecError."""
        if value is None:
            if self.optional or self.default is None:
                return None
            raise SpecError(path, "is required")
        k = self.kind
        if k == "float":
            value = _as_float(path, value)
        elif k == "int":
            if isinstance(value, bool) or not isinstance(value, (int, float)) or (
                isinstance(value, float) and not value.is_integer()
            ):
                raise SpecError(path, f"must be an integer, got {_short(value)}")
            value = int(value)
        elif k == "str":
            if not isinstance(value, str):
                raise SpecError(path, f"must be a string, got {_short(value)}")
            bad = next((c for c in value if ord(c) < 32 or 127 <= ord(c) < 160), None)
            if bad is not None:
                raise SpecError(path, f"must not contain control characters (found {bad!r})")
            if self.choices and value not in self.choices:
                raise SpecError(
                    path, f"must be one of {', '.join(repr(c) for c in self.choices)}, got {value!r}"
                )
        elif k == "bool":
            if not isinstance(value, bool):
                raise SpecError(path, f"must be true or false, got {_short(value)}")
        elif k == "floats":
            if not isinstance(value, (list, tuple)):
                raise SpecError(path, f"must be a list of numbers, got {_short(value)}")
            if len(value) > 1000:
                raise SpecError(path, f"must have at most 1000 entries, got {len(value)}")
            value = tuple(_as_float(f"{path}[{i}]", v) for i, v in enumerate(value))
        elif k == "points":
            if not isinstance(value, (list, tuple)):
                raise SpecError(path, f"must be a list of [angle, lift] rows, got {_short(value)}")
            if len(value) > MAX_POINT_ROWS:
                raise SpecError(path, f"must have at most {MAX_POINT_ROWS} rows, got {len(value)}")
            rows = []
            for i, row in enumerate(value):
                if not isinstance(row, (list, tuple)) or len(row) != 2:
                    raise SpecError(f"{path}[{i}]", f"must be an [angle, lift] pair, got {_short(row)}")
                a, b = (_as_float(f"{path}[{i}][{j}]", v) for j, v in enumerate(row))
                top = MAX_MAGNITUDE.get(self.unit, MAX_MAGNITUDE[""])
                if abs(a) > MAX_MAGNITUDE["angle"] or abs(b) > top:
                    raise SpecError(f"{path}[{i}]", f"must be within ±{MAX_MAGNITUDE['angle']:g}° and ±{top:g}, "
                                                    f"got {_short(row)}")
                rows.append((a, b))
            value = tuple(rows)
        if k in ("float", "int"):
            self._check_bounds(path, value)
        return value

    def _check_bounds(self, path: str, v: float) -> None:
        if self.kind == "int":
            top = self.le if self.le is not None else MAX_INT
            if v > top and self.le is None:
                raise SpecError(path, f"must be ≤ {_fmt(top, v)}, got {_fmt(v, top)}")
        else:
            top = MAX_MAGNITUDE.get(self.unit, MAX_MAGNITUDE[""])
            if abs(v) > top:
                raise SpecError(path, f"must be within ±{fmt_apart(top, abs(v))}, got "
                                      f"{fmt_apart(v, math.copysign(top, v))}")
            low = MIN_POSITIVE.get(self.unit)
            if low is not None and self.gt == 0 and 0 < v < low:
                raise SpecError(path, f"must be ≥ {fmt_apart(low, v)} (a smaller value rounds to nothing), got "
                                      f"{fmt_apart(v, low)}")
        for op, bound, holds in (("> ", self.gt, operator.gt), ("≥ ", self.ge, operator.ge),
                                 ("< ", self.lt, operator.lt), ("≤ ", self.le, operator.le)):
            if bound is not None and not holds(v, bound):
                raise SpecError(path, f"must be {op}{_fmt(bound, v)}{self._why()}, got {_fmt(v, bound)}")

    def _why(self) -> str:
        return f" ({self.bound_note})" if self.bound_note else ""


def _as_float(path: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SpecError(path, f"must be a number, got {_short(value)}")
    try:
        v = float(value)
    except OverflowError:
        raise SpecError(path, f"must be a finite number, got an integer of {len(str(value))} digits") from None
    if not math.isfinite(v):
        raise SpecError(path, f"must be a finite number, got {value!r}")
    return v


def _short(value: Any, limit: int = 60) -> str:
    """repr of a value for a one-line message, cut to ``limit`` characters."""
    text = repr(value)
    return text if len(text) <= limit else text[:limit] + "…"


def _fmt(v: float, other: float | None = None) -> str:
    """``v`` for a message (with ``other``: with the digits that tell it apart, :func:`fmt_apart`)."""
    try:
        return f"{v:g}" if other is None else fmt_apart(v, other)
    except OverflowError:           # an integer beyond float range
        return f"an integer of {len(str(v))} digits"


def param(doc: str, **kw: Any) -> Any:
    """A dataclass field carrying its :class:`Param` declaration in ``metadata["param"]``."""
    if kw.get("optional") and "default" not in kw:
        kw["default"] = None
    p = Param(doc=doc, **kw)
    if p.default is REQUIRED:
        return dataclasses.field(metadata={"param": p})
    return dataclasses.field(default=p.default, metadata={"param": p})


def params_of(cls: type) -> dict[str, Param]:
    """The declared parameters of a spec dataclass, in declaration order."""
    return {
        f.name: f.metadata["param"] for f in dataclasses.fields(cls) if "param" in f.metadata
    }


def unit_name(kind: str, units: str) -> str:
    """Concrete unit label of a unit kind for the spec's ``units`` ("mm" or "in")."""
    return UNIT_NAMES.get(kind, {}).get(units, "")

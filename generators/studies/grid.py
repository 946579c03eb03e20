"""Grids of spec fields: ``--vary FIELD=START:STOP:COUNT`` and its relatives, and the spec at
each grid point.

An axis sets one or more dotted spec fields to the same value at each of its values::

    motion[1].lift=5:30:6                  # 5, 10, 15, 20, 25, 30 (numpy.linspace, ends included)
    motion[1].lift,motion[3].lift=5:30:6   # rise and return together (the program must close)
    motion[1].law=cycloidal,harmonic       # a categorical field: the values listed
    follower.roller_radius=4,6,8           # numbers listed

A grid is the Cartesian product of its axes, the first axis varying slowest (the order of
:func:`itertools.product`).  ``balance`` names a dwell's ``motion[k].angle`` that takes up what the
other spans leave of 360° at every point (so that a rise's angle can vary alone).
"""
from __future__ import annotations

import itertools
import math
import re
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import numpy as np

from ..errors import SpecError, fmt_apart
from ..spec.model import SECTIONS, CamSpec, _set_path
from ..spec.params import params_of
from ..spec.model import follow_derived_fields

#: most points a grid may have (a typo such as 5:30:6000 is refused before any work)
MAX_POINTS = 100_000
_RANGE = re.compile(r"^\s*([-+0-9.eE]+)\s*:\s*([-+0-9.eE]+)\s*:\s*(\d+)\s*$")


@dataclass(frozen=True)
class Axis:
    """One axis of a grid: ``fields`` all set to each of ``values`` in turn."""

    fields: tuple[str, ...]
    values: tuple[Any, ...]

    @property
    def name(self) -> str:
        """The axis' column in tables: its first field."""
        return self.fields[0]

    @property
    def numeric(self) -> bool:
        return all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in self.values)

    def text(self) -> str:
        return f"{','.join(self.fields)}={','.join(_fmt(v) for v in self.values)}"


def _fmt(v: Any) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)


def _scalar(text: str) -> Any:
    """One listed value: true/false, an integer, a number, or text."""
    low = text.strip().lower()
    if low in ("true", "false"):
        return low == "true"
    for conv in (int, float):
        try:
            return conv(text)
        except ValueError:
            pass
    return text.strip().strip('"')


def parse_vary(text: str, option: str = "--vary") -> Axis:
    """An :class:`Axis` from ``FIELD[,FIELD…]=START:STOP:COUNT`` or ``FIELD[,FIELD…]=V1,V2,…``.

    Raises:
        SpecError: naming ``option`` and the rule broken.
    """
    if "=" not in text:
        raise SpecError(option, f"{text!r}: write FIELD=START:STOP:COUNT or FIELD=V1,V2,… "
                                "(e.g. motion[1].lift=5:30:6)")
    left, right = text.split("=", 1)
    fields = tuple(f.strip() for f in left.split(",") if f.strip())
    if not fields:
        raise SpecError(option, f"{text!r}: no field named before '='")
    if len(set(fields)) != len(fields):
        raise SpecError(option, f"{text!r}: a field is named twice")
    m = _RANGE.match(right)
    if m:
        try:
            start, stop = float(m.group(1)), float(m.group(2))
        except ValueError:
            raise SpecError(option, f"{text!r}: START and STOP must be numbers") from None
        count = int(m.group(3))
        if count < 1:
            raise SpecError(option, f"{text!r}: COUNT must be ≥ 1, got {count}")
        if not (math.isfinite(start) and math.isfinite(stop)):
            raise SpecError(option, f"{text!r}: START and STOP must be finite")
        vals = np.linspace(start, stop, count) if count > 1 else np.array([start])
        ints = all(re.fullmatch(r"[-+]?\d+", g) for g in (m.group(1), m.group(2)))
        values: tuple[Any, ...] = tuple(int(round(v)) if ints and float(v).is_integer() else float(v)
                                        for v in vals)
    else:
        if ":" in right and not any(c.isalpha() for c in right):
            raise SpecError(option, f"{text!r}: a range is START:STOP:COUNT with a whole COUNT")
        items = [v for v in right.split(",")]
        if not right.strip() or any(not v.strip() for v in items):
            raise SpecError(option, f"{text!r}: an empty value")
        values = tuple(_scalar(v) for v in items)
    return Axis(fields, values)


def check_field(spec: CamSpec, path: str, option: str = "--vary") -> None:
    """Refuse a dotted path that names no field of ``spec`` (before any work): ``cam.base_radius``,
    ``motion[1].lift`` (the segment must exist), ``units``.

    Raises:
        SpecError: naming ``option``, the path and the known fields.
    """
    if path == "units":
        return
    m = re.fullmatch(r"([A-Za-z_]\w*)(?:\[(\d+)\])?\.([A-Za-z_]\w*)", path)
    if not m:
        raise SpecError(option, f"{path!r} is not a spec field (write e.g. cam.base_radius or motion[1].lift)")
    section, idx, name = m.group(1), m.group(2), m.group(3)
    if section not in SECTIONS:
        raise SpecError(option, f"{path!r}: no section {section!r} (sections: {', '.join(SECTIONS)})")
    cls, is_list, _ = SECTIONS[section]
    if is_list:
        if idx is None:
            raise SpecError(option, f"{path!r}: {section} is a list of tables: write {section}[i].{name}")
        n = len(getattr(spec, section))
        if int(idx) >= n:
            raise SpecError(option, f"{path!r}: index {idx} is out of range (the spec has {n} {section} segments)")
    elif idx is not None:
        raise SpecError(option, f"{path!r}: {section} is not a list: write {section}.{name}")
    known = params_of(cls)
    if name not in known:
        raise SpecError(option, f"{path!r}: unknown field (fields of {section}: {', '.join(sorted(known))})")


@dataclass(frozen=True)
class Grid:
    """The Cartesian product of ``axes`` (first axis slowest); ``balance``: the dwell angle that
    takes up the rest of 360° at every point (``motion[k].angle``), or None."""

    axes: tuple[Axis, ...]
    balance: str | None = None

    @property
    def size(self) -> int:
        return math.prod(len(a.values) for a in self.axes)

    @property
    def columns(self) -> tuple[str, ...]:
        return tuple(a.name for a in self.axes)

    def points(self) -> list[dict[str, Any]]:
        """Every point as {axis column: value}, in grid order."""
        return [dict(zip(self.columns, combo)) for combo in itertools.product(*(a.values for a in self.axes))]

    def changes(self, point: Mapping[str, Any]) -> dict[str, Any]:
        """The spec changes of a point: every field of every axis set to the axis' value."""
        return {f: point[a.name] for a in self.axes for f in a.fields}

    def check(self, spec: CamSpec, fixed: Sequence[str] = ()) -> None:
        """Refuse, before any work, a grid that cannot be run on ``spec``: unknown fields, a field
        on two axes, a field in ``fixed`` (what the study itself sets, e.g. the sized radius), too
        many points, a ``balance`` that is not a dwell's angle or is also varied.

        Raises:
            SpecError: naming the option and the rule.
        """
        if not self.axes:
            raise SpecError("--vary", "give at least one --vary FIELD=…")
        seen: set[str] = set()
        for a in self.axes:
            for f in a.fields:
                check_field(spec, f)
                if f in seen:
                    raise SpecError("--vary", f"{f} is varied twice")
                if f in fixed:
                    raise SpecError("--vary", f"{f} is what the study sets itself: it cannot be varied")
                seen.add(f)
        if self.size > MAX_POINTS:
            raise SpecError("--vary", f"the grid has {self.size} points, at most {MAX_POINTS}")
        if self.balance is not None:
            m = re.fullmatch(r"motion\[(\d+)\]\.angle", self.balance)
            if not m:
                raise SpecError("--balance", f"{self.balance!r}: must be a dwell's angle, motion[k].angle")
            k = int(m.group(1))
            if k >= len(spec.motion) or spec.motion[k].kind != "dwell":
                raise SpecError("--balance", f"{self.balance}: motion[{k}] is not a dwell of the spec")
            if self.balance in seen:
                raise SpecError("--balance", f"{self.balance} is also varied")

    def spec_at(self, spec: CamSpec, point: Mapping[str, Any]) -> CamSpec:
        """The validated spec at ``point`` (SpecError naming the field if a rule breaks there)."""
        return apply_changes(spec, self.changes(point), self.balance)


def apply_changes(spec: CamSpec, changes: Mapping[str, Any], balance: str | None = None) -> CamSpec:
    """``spec`` with dotted-path ``changes``; with ``balance`` (a dwell's ``motion[k].angle``)
    that dwell set to 360° minus every other span.  Validated (SpecError naming the field)."""
    if not changes and balance is None:
        return spec
    data = spec.to_dict()
    for path, value in changes.items():
        _set_path(data, path, value)
    follow_derived_fields(data, changes)
    if balance is not None:
        k = int(re.fullmatch(r"motion\[(\d+)\]\.angle", balance).group(1))  # type: ignore[union-attr]
        rest = 0.0
        for i, seg in enumerate(data["motion"]):
            if i != k:
                a = seg.get("angle")
                if not isinstance(a, (int, float)) or isinstance(a, bool):
                    raise SpecError(f"motion[{i}].angle", f"must be a number, got {a!r}")
                rest += float(a)
        if not 360.0 - rest > 0:
            raise SpecError(balance, f"the other spans sum to {fmt_apart(rest, 360.0)}°: nothing of 360° is left for "
                            "this dwell")
        data["motion"][k]["angle"] = 360.0 - rest
    return CamSpec.from_dict(data)

"""Segments whose ends are set by their neighbours: polynomial, constant-velocity and table laws,
and the boundary values the program carries between segments.

Every segment end has, for each derivative n = 1 (velocity), 2 (acceleration), 3 (jerk), one of

* a **fixed** value: a dwell's 0, a closed-form or B-spline law's own end derivative, or a value
  the spec gives (``start_velocity`` …);
* **match**: the value the neighbour has at the shared junction (n ≤ the end's continuity,
  ``start_continuity``/``end_continuity``, default 2);
* **free**: whatever the segment comes out with once solved (n above the continuity; a
  constant-velocity end without a blend: s′ = V, s″ = s‴ = 0).

A segment with "match" entries is solved once its neighbours' values there are known: a fixed
value at once, a free one when that neighbour is solved, and 0 when the neighbour also only
matches (neither side sets the value: as next to a dwell).  The segments are solved in passes
until all are; a cycle of segments each waiting for the other is an error naming the field
that would break it.  Position is always continuous: each segment starts at its predecessor's
end level.

Each solved segment is a :class:`~cam_workbench.generators.motion.bspline_law.BSplineLift` (θ(u) linear), so the
rest of the program reads it as it reads the thesis' B-spline lifts.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from ..errors import SpecError, fmt_apart
from .bspline_law import BSplineLift, lift_from_segment
from .law_library import segment_law
from .laws import CLOSED_FORM_LAWS, LawName, evaluate_law
from .polynomial import (Condition, ConditionError, bezier_lift, cruise_pieces, piecewise_lift,
                         power_coefficients, solve_conditions)
from .table import DEFAULT_TABLE_ORDER, DEFAULT_TOLERANCE_FRACTION, TableError, fit_table

#: Laws whose ends take their neighbours' values (to their continuity).
MATCHING_LAWS = ("polynomial", "constant_velocity", "table")
DEFAULT_CONTINUITY = 2
ORDER_NAMES = {0: "position", 1: "velocity", 2: "acceleration", 3: "jerk"}
END_FIELDS = {(0, 1): "start_velocity", (0, 2): "start_acceleration", (0, 3): "start_jerk",
              (1, 1): "end_velocity", (1, 2): "end_acceleration", (1, 3): "end_jerk"}
_END = ("start", "end")


@dataclass
class _Plan:
    index: int
    seg: Any
    path: str
    start: float
    span: float
    level: float
    lift: float                    # signed
    entries: list[dict[int, tuple]] = field(default_factory=lambda: [{}, {}])
    solved: bool = False
    values: list[list[float]] = field(default_factory=lambda: [[0.0] * 4, [0.0] * 4])
    curve: BSplineLift | None = None
    info: dict[str, Any] | None = None
    law: Any = None                # the law the program carries (a LawName for a parametric law)
    promise: tuple[int, int] = (3, 3)

    @property
    def low(self) -> float:
        return min(self.level, self.level + self.lift)


@dataclass(frozen=True)
class BuiltSegments:
    """What :func:`build_segments` gives the program, per segment."""

    curves: tuple[BSplineLift | None, ...]
    promises: tuple[tuple[int, int], ...]
    infos: tuple[dict[str, Any] | None, ...]
    #: the laws the program carries: the segments' names, a parametric law as a LawName
    laws: tuple[Any, ...] = ()


def continuity_of(seg: Any, end: int) -> int:
    v = seg.start_continuity if end == 0 else seg.end_continuity
    return DEFAULT_CONTINUITY if v is None else int(v)


def law_promise(law: str | None, curve: BSplineLift | None = None) -> tuple[int, int]:
    """The (start, end) order of continuity a law promises at its ends (a dwell: 3, i.e. no limit
    of its own; a closed form: its continuity next to a dwell at a rest end, and at a quick-return
    law's turning end the acceleration carried into the reversing neighbour,
    :attr:`~.laws.NormalisedLaw.promises`; a B-spline lift of order k: k − 2; a matching law: its
    default continuity)."""
    if law is None:
        return 3, 3
    if isinstance(law, LawName):
        return law.law.promises
    if law in CLOSED_FORM_LAWS:
        return CLOSED_FORM_LAWS[law].promises
    if law == "bspline" and curve is not None:
        return min(curve.order - 2, 3), min(curve.order - 2, 3)
    return DEFAULT_CONTINUITY, DEFAULT_CONTINUITY


def build_segments(segments: Sequence[Any], starts: np.ndarray, spans: np.ndarray, levels: np.ndarray,
                   lifts: np.ndarray) -> BuiltSegments:
    """Solve every segment of the program (see the module docstring).

    Raises:
        SpecError: naming the field: conditions that do not determine a polynomial, a blend that
            does not fit, a table fit outside its tolerance, a segment that takes s below 0, or
            neighbours each waiting for the other.
    """
    plans = [_Plan(k, seg, f"motion[{k}]", float(starts[k]), float(spans[k]), float(levels[k]), float(lifts[k]))
             for k, seg in enumerate(segments)]
    for p in plans:
        _plan_entries(p)
    n = len(plans)
    while True:
        progress = False
        pending = [p for p in plans if not p.solved]
        if not pending:
            break
        for p in pending:
            inputs = _inputs(p, plans, n)
            if inputs is None:
                continue
            _solve(p, inputs)
            p.solved = True
            progress = True
        if not progress:
            raise _deadlock(pending, plans, n)
    return BuiltSegments(tuple(p.curve for p in plans), tuple(p.promise for p in plans),
                         tuple(p.info for p in plans), tuple(p.law for p in plans))


# ---- entries -----------------------------------------------------------------------------------
def _plan_entries(p: _Plan) -> None:
    seg = p.seg
    law = p.law = segment_law(seg, p.path)             # a parametric law made of its fields
    if law is None:                                    # dwell
        p.entries = [{n: ("fixed", 0.0) for n in (1, 2, 3)} for _ in _END]
        p.values = [[p.level, 0.0, 0.0, 0.0], [p.level, 0.0, 0.0, 0.0]]
        p.solved = True
        return
    if law not in MATCHING_LAWS:                       # closed form or B-spline: its own ends
        if law == "bspline":
            p.curve = lift_from_segment(seg, p.path, p.start, p.span)
            y = p.curve.evaluate(np.array([0.0, p.span]))
            h = abs(p.lift)
            vals = [[p.low + h * y[0][i]] + [h * y[d][i] for d in (1, 2, 3)] for i in (0, 1)]
            p.promise = law_promise(law, p.curve)
        else:
            f = evaluate_law(law, np.array([0.0, 1.0]))
            vals = [[p.level + p.lift * f[0][i]] + [p.lift * f[d][i] / p.span**d for d in (1, 2, 3)]
                    for i in (0, 1)]
            p.promise = law_promise(law)
        p.values = vals
        p.entries = [{n: ("fixed", vals[e][n]) for n in (1, 2, 3)} for e in (0, 1)]
        p.solved = True
        return
    p.promise = (continuity_of(seg, 0), continuity_of(seg, 1))
    for e in (0, 1):
        cont = p.promise[e]
        blend = (seg.start_blend if e == 0 else seg.end_blend) or 0.0
        for n in (1, 2, 3):
            given = getattr(seg, END_FIELDS[(e, n)])
            if law == "constant_velocity" and blend <= 0:
                p.entries[e][n] = ("free",)           # s′ = V, s″ = s‴ = 0 once V is known
            elif given is not None:
                p.entries[e][n] = ("fixed", float(given))
            elif n <= cont:
                p.entries[e][n] = ("match",)
            else:
                p.entries[e][n] = ("free",)


def _neighbour(p: _Plan, e: int, plans: list[_Plan], n: int) -> tuple[_Plan, int]:
    """(neighbour plan, its end) across end ``e`` of ``p`` (the program is cyclic)."""
    if e == 0:
        return plans[(p.index - 1) % n], 1
    return plans[(p.index + 1) % n], 0


def _inputs(p: _Plan, plans: list[_Plan], n: int) -> dict[tuple[int, int], float] | None:
    """The values of ``p``'s matched entries, or None while a neighbour is not solved yet."""
    out = {}
    for e in (0, 1):
        q, qe = _neighbour(p, e, plans, n)
        for order, entry in p.entries[e].items():
            if entry[0] == "fixed":
                out[(e, order)] = entry[1]
            elif entry[0] == "match":
                if q.solved:
                    out[(e, order)] = q.values[qe][order]
                    continue
                other = q.entries[qe][order]
                if other[0] == "fixed":
                    out[(e, order)] = other[1]
                elif other[0] == "match":
                    out[(e, order)] = 0.0          # neither side sets it: as next to a dwell
                else:
                    return None                    # wait until the neighbour is solved
    return out


def _deadlock(pending: list[_Plan], plans: list[_Plan], n: int) -> SpecError:
    p = pending[0]
    for e in (0, 1):
        q, qe = _neighbour(p, e, plans, n)
        for order, entry in p.entries[e].items():
            if entry[0] == "match" and not q.solved and q.entries[qe][order][0] == "free":
                fld = END_FIELDS[(e, order)]
                return SpecError(
                    f"{p.path}.{fld}",
                    f"the {ORDER_NAMES[order]} at the {_END[e]} takes {q.path}'s, which itself waits for this "
                    f"segment's: give {p.path}.{fld} (or {q.path}.{END_FIELDS[(qe, order)]}), or lower a continuity")
    return SpecError(p.path, "its end values depend on segments that depend on it")


# ---- solving -----------------------------------------------------------------------------------
def _solve(p: _Plan, inputs: dict[tuple[int, int], float]) -> None:
    seg = p.seg
    try:
        if seg.law == "polynomial":
            _solve_polynomial(p, inputs)
        elif seg.law == "constant_velocity":
            _solve_cruise(p, inputs)
        else:
            _solve_table(p, inputs)
    except ConditionError as exc:
        raise SpecError(exc.field or f"{p.path}.law", str(exc)) from None
    except TableError as exc:
        raise SpecError(f"{p.path}.{exc.where}" if exc.where else f"{p.path}.table", str(exc)) from None
    y = p.curve.evaluate(np.array([0.0, p.span]))
    h = abs(p.lift)
    p.values = [[p.low + h * y[0][i]] + [h * y[d][i] for d in (1, 2, 3)] for i in (0, 1)]
    _check_nonnegative(p)


def _end_conditions(p: _Plan, inputs: dict[tuple[int, int], float]) -> list[Condition]:
    conds = []
    for e in (0, 1):
        for order in (1, 2, 3):
            if (e, order) in inputs:
                entry = p.entries[e][order]
                fld = (f"{p.path}.{END_FIELDS[(e, order)]}" if entry[0] == "fixed"
                       else f"{p.path}.{_END[e]}_continuity")
                conds.append(Condition(float(e), order, inputs[(e, order)], fld))
    return conds


def _solve_polynomial(p: _Plan, inputs: dict[tuple[int, int], float]) -> None:
    seg = p.seg
    conds = [Condition(0.0, 0, p.level, f"{p.path}.law"), Condition(1.0, 0, p.level + p.lift, f"{p.path}.lift")]
    conds += _end_conditions(p, inputs)
    span_deg = seg.angle
    seen: dict[float, int] = {}
    for i, (a, s) in enumerate(seg.points or ()):
        fld = f"{p.path}.points[{i}]"
        if not 0.0 < a < span_deg:
            raise SpecError(fld, f"angle {fmt_apart(a, 0.0 if a <= 0 else span_deg)}° must lie inside the segment "
                                 f"(0 < angle < {fmt_apart(span_deg, a)}°, "
                                 "degrees from the segment start)")
        if a in seen:
            raise SpecError(fld, f"angle {a:g}° repeats points[{seen[a]}]: one lift per angle")
        seen[a] = i
        conds.append(Condition(a / span_deg, 0, float(s), fld))
    # a condition's field names it in messages; the conditions themselves are ordered by end
    bern = solve_conditions(conds, p.span)
    p.curve = bezier_lift(bern, p.span, p.low, abs(p.lift))
    p.info = {"law": "polynomial", "degree": len(bern) - 1, "conditions": len(conds),
              "coefficients": [float(c) for c in power_coefficients(bern)],
              "coefficients_basis": "s = Σ a_k x^k, x = (θ − θ_start)/span"}


def _solve_cruise(p: _Plan, inputs: dict[tuple[int, int], float]) -> None:
    seg = p.seg
    b = [math.radians(seg.start_blend or 0.0), math.radians(seg.end_blend or 0.0)]
    conts = p.promise
    outer: list[list[tuple[int, float, str]]] = [[], []]
    for e in (0, 1):
        if b[e] > 0:
            if conts[e] < 1:
                raise SpecError(f"{p.path}.{_END[e]}_continuity",
                                f"a blend needs continuity ≥ 1 (it blends the velocity), got {conts[e]}")
            outer[e] = [(n, inputs[(e, n)], f"{p.path}.{_END[e]}_continuity") for n in range(1, conts[e] + 1)]
    if not b[0] + b[1] < p.span:
        raise SpecError(f"{p.path}.end_blend" if b[1] > 0 else f"{p.path}.start_blend",
                        f"start_blend + end_blend = {seg.start_blend or 0:g}° + {seg.end_blend or 0:g}° = "
                        f"{fmt_apart((seg.start_blend or 0) + (seg.end_blend or 0), seg.angle)}° must be less than the "
                        f"segment's angle {fmt_apart(seg.angle, (seg.start_blend or 0) + (seg.end_blend or 0))}° (the "
                        "constant-velocity part)")
    velocity, pieces = cruise_pieces(p.span, p.lift, b[0], b[1], outer[0], outer[1], conts[0], conts[1], p.level)
    if not velocity * p.lift > 0:
        raise SpecError(f"{p.path}.start_blend" if b[0] > 0 else f"{p.path}.end_blend",
                        f"the blends take the whole lift and more: the cruise velocity would be {velocity:.4g} "
                        f"per rad, against the {seg.kind}'s direction; shorter blends or a longer segment")
    p.curve = piecewise_lift(pieces, p.low, abs(p.lift))
    p.info = {"law": "constant_velocity", "velocity": velocity,
              "start_blend_deg": seg.start_blend or 0.0, "end_blend_deg": seg.end_blend or 0.0,
              "cruise_from_deg": math.degrees(p.start + b[0]),
              "cruise_to_deg": math.degrees(p.start + p.span - b[1]),
              "blend_degrees": [len(c) - 1 for (_a, _b, c) in pieces if len(c) > 2]}


def _solve_table(p: _Plan, inputs: dict[tuple[int, int], float]) -> None:
    seg = p.seg
    rows = np.asarray(seg.table, dtype=float).reshape(-1, 2)
    origin = seg.table_start if seg.table_start is not None else 0.0
    ang = rows[:, 0] - origin
    tol_deg = 1e-9 * max(1.0, seg.angle)
    inside = (ang >= -tol_deg) & (ang <= seg.angle + tol_deg)
    if seg.table_start is None and not inside.all():
        i = int(np.flatnonzero(~inside)[0])
        raise SpecError(f"{p.path}.table[{i}]",
                        f"angle {fmt_apart(rows[i, 0], 0.0 if rows[i, 0] < 0 else seg.angle)}° lies outside the segment "
                        f"(0 … {fmt_apart(seg.angle, rows[i, 0])}°, degrees from its start; "
                        "give table_start to take a segment's rows out of a longer table)")
    idx = np.flatnonzero(inside)
    if np.any(np.diff(rows[idx, 0]) <= 0):
        j = int(idx[np.flatnonzero(np.diff(rows[idx, 0]) <= 0)[0] + 1])
        raise SpecError(f"{p.path}.table[{j}]", f"angles must increase: {fmt_apart(rows[j, 0], rows[j - 1, 0])}° after "
                        f"{fmt_apart(rows[j - 1, 0], rows[j, 0])}°")
    order = seg.order or DEFAULT_TABLE_ORDER
    cons = [(0.0, 0, p.level), (1.0, 0, p.level + p.lift)]
    cons += [(float(e), n, v) for (e, n), v in sorted(inputs.items())]
    if idx.size < 2:
        raise SpecError(f"{p.path}.table", f"has {idx.size} point(s) within the segment; a fit needs at least 2")
    tol = seg.table_tolerance if seg.table_tolerance is not None else DEFAULT_TOLERANCE_FRACTION * abs(p.lift)
    theta = np.clip(np.radians(ang[idx]), 0.0, p.span)
    fit = fit_table(theta, rows[idx, 1], p.span, p.low, abs(p.lift), order, cons, tol)
    p.curve = fit.lift
    p.info = {"law": "table", "points": fit.points, "spans": fit.spans, "order": fit.order,
              "max_error": fit.max_error, "max_error_at_deg": math.degrees(p.start + fit.at),
              "rms_error": fit.rms_error, "tolerance": fit.tolerance}


def _check_nonnegative(p: _Plan) -> None:
    """s ≥ 0 over the segment (the program's rule): exact when every control lift is ≥ 0 (the
    convex hull), else sampled at 256 parameters per knot span."""
    c = p.curve
    h = abs(p.lift)
    scale = max(h, abs(p.level), 1e-300)
    if p.low + h * float(np.min(c.y)) >= -1e-9 * scale:
        return
    u = np.linspace(0.0, c.u_max, 256 * max(1, int(round(c.u_max))) + 1)
    th, yy = c.parametric(u, 0)
    s = p.low + h * yy[0]
    j = int(np.argmin(s))
    if s[j] >= -1e-9 * scale:
        return
    seg = p.seg
    given = [f for f in END_FIELDS.values() if getattr(seg, f, None) is not None]
    if seg.law == "polynomial":
        fld = "points" if seg.points else (given[0] if given else "law")
    elif seg.law == "constant_velocity":
        fld = "start_blend" if seg.start_blend else "end_blend" if seg.end_blend else "law"
    else:
        fld = "table"
    raise SpecError(f"{p.path}.{fld}",
                    f"the {seg.law} segment goes to s = {s[j]:.4g} at {math.degrees(p.start + th[0][j]):.4g}° "
                    "(cam angle): s must stay ≥ 0")


# ---- polynomial points as design variables --------------------------------------------------------
def polynomial_point_basis(seg: Any, path: str, span: float) -> np.ndarray:
    """(m, d + 1): the Bernstein coefficients of a polynomial segment's s per unit of each of its
    m interior points' lifts (``seg.points[i][1]``, lift units).

    The SVAJ conditions are linear, s = s_fixed + Σ_i s_i·φ_i, and their matrix depends only on
    which derivatives are conditioned where (the ends' fixed and matched entries, the points'
    angles), not on the values: φ_i is the solution with point i's value 1 and every other right-hand
    side 0.  ``span`` is the segment's angle [rad]."""
    p = _Plan(0, seg, path, 0.0, span, 0.0, 1.0)
    _plan_entries(p)
    conds = [Condition(0.0, 0, 0.0, f"{path}.law"), Condition(1.0, 0, 0.0, f"{path}.lift")]
    for e in (0, 1):
        for order in (1, 2, 3):
            if p.entries[e][order][0] != "free":
                conds.append(Condition(float(e), order, 0.0, f"{path}.{END_FIELDS[(e, order)]}"))
    pts = list(seg.points or ())
    base = len(conds)
    conds += [Condition(a / seg.angle, 0, 0.0, f"{path}.points[{i}]") for i, (a, _s) in enumerate(pts)]
    out = []
    for i in range(len(pts)):
        unit = list(conds)
        c = unit[base + i]
        unit[base + i] = Condition(c.x, 0, 1.0, c.field)
        out.append(solve_conditions(unit, span))
    return np.array(out).reshape(len(pts), -1)


def polynomial_dependants(segments: Sequence[Any], k: int) -> list[tuple[int, int, int]]:
    """The (neighbour row, its end 0/1, derivative order) whose value is taken from polynomial
    segment ``k``'s solved (free) end value: a neighbour law that matches a derivative segment ``k``
    leaves free changes with ``k``'s points."""
    n = len(segments)
    plans = [_Plan(j, seg, f"motion[{j}]", 0.0, 1.0, 0.0, 1.0) for j, seg in enumerate(segments)]
    for q in plans:
        if q.seg.law in MATCHING_LAWS:          # the others' ends are their own (never "match")
            _plan_entries(q)
    p = plans[k]
    out = []
    for e in (0, 1):
        q, qe = _neighbour(p, e, plans, n)
        if q.index == k or q.seg.law not in MATCHING_LAWS:
            continue
        for order, entry in p.entries[e].items():
            if entry[0] == "free" and q.entries[qe].get(order, ("fixed",))[0] == "match":
                out.append((q.index, qe, order))
    return out

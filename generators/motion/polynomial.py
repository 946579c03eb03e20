"""Polynomial motion segments from boundary conditions (Norton's SVAJ method) and
constant-velocity segments with polynomial blends.

Norton, *Cam Design and Manufacturing Handbook*, ch. 3 and 5: list the conditions a segment
must meet — s, s′, s″ (and s‴) at its ends, and s at interior points — and solve for the
polynomial of the lowest degree that meets them: N conditions, degree N − 1.  Zero velocity and
acceleration at both ends of a rise of height h give the 3-4-5 polynomial, zero jerk as well the
4-5-6-7 one.

The polynomial is solved and kept in Bernstein form on x = (θ − θ₀)/β ∈ [0, 1] (well conditioned
where the power basis is not), which *is* the B-spline lift law of one knot span (a Bézier segment:
order d + 1, clamped knots 0 and 1, θ(u) linear): :func:`bezier_lift` hands it to the rest of the
program as a :class:`~cam_workbench.generators.motion.bspline_law.BSplineLift`, so the checks, areas, cutting
time and optimiser read it exactly as they read the thesis' B-spline lifts.

A constant-velocity segment (:func:`cruise_pieces`) is a line s′ = V with optional blends at its
ends: each blend is the lowest-degree polynomial that starts with the neighbour's s, s′, s″ (s‴)
and ends with s′ = V, s″ = 0 (s‴ = 0) — a quartic (degree 6 for jerk continuity).  V follows from
the lift: every blend's rise is linear in V.

Derivatives are with respect to θ in radians; values are in lift units (per radian^n).
"""
from __future__ import annotations

from dataclasses import dataclass
from math import comb

import numpy as np

from ..curves.basis import basis_matrix
from .bspline_law import BSplineLift

#: Largest degree of a polynomial segment (its conditions: both ends and the interior points).
MAX_DEGREE = 24
#: Relative smallest singular value below which the conditions do not determine a polynomial.
SINGULAR_RCOND = 1e-13


@dataclass(frozen=True)
class Condition:
    """One condition on a polynomial segment: d^order s/dθ^order = value at normalised x."""

    x: float        # position in the segment, 0 … 1
    order: int      # 0 = s, 1 = s′, 2 = s″, 3 = s‴
    value: float    # lift units per rad^order
    field: str      # the spec field it comes from (for messages)


class ConditionError(ValueError):
    """The conditions do not determine a polynomial (message; the offending spec field)."""

    def __init__(self, field: str, message: str):
        super().__init__(message)
        self.field = field


def bezier_knots(degree: int) -> np.ndarray:
    return np.concatenate([np.zeros(degree + 1), np.ones(degree + 1)])


def bernstein_rows(degree: int, x: np.ndarray, order: int) -> np.ndarray:
    """(len(x), degree + 1): d^order/dx^order of the Bernstein polynomials B_j,degree at x."""
    return basis_matrix(bezier_knots(degree), degree, degree + 1, np.atleast_1d(np.asarray(x, float)), order)


def solve_conditions(conditions: list[Condition], span: float) -> np.ndarray:
    """Bernstein coefficients (degree N − 1) of the polynomial s(x) meeting the N conditions
    (derivatives per radian: d^n s/dθ^n = β^−n d^n s/dx^n).

    Raises:
        ConditionError: the conditions contradict each other or leave the polynomial undetermined
            (named by the field of the last condition involved).
    """
    n = len(conditions)
    degree = n - 1
    if degree > MAX_DEGREE:
        raise ConditionError(conditions[-1].field,
                             f"{n} conditions need a polynomial of degree {degree}; at most {MAX_DEGREE}")
    a = np.empty((n, n))
    b = np.empty(n)
    for i, c in enumerate(conditions):
        a[i] = bernstein_rows(degree, np.array([c.x]), c.order)[0]
        b[i] = c.value * span**c.order
    # equilibrate the rows (a derivative row of a Bernstein basis grows like degree^order)
    scale = np.max(np.abs(a), axis=1)
    scale[scale == 0] = 1.0
    a /= scale[:, None]
    b /= scale
    sv = np.linalg.svd(a, compute_uv=False)
    if sv[-1] <= SINGULAR_RCOND * sv[0]:
        raise ConditionError(_gap_field(conditions),
                             "these conditions do not determine a polynomial (a derivative is given "
                             "where a lower one at the same end is left free, or points coincide)")
    return np.linalg.solve(a, b)


def _gap_field(conditions: list[Condition]) -> str:
    """The field of a condition that sits above a free lower derivative at the same end (a
    Birkhoff gap), else the last condition's."""
    for end in (0.0, 1.0):
        orders = sorted(c.order for c in conditions if c.x == end)
        for c in conditions:
            if c.x == end and any(o not in orders for o in range(c.order)):
                return c.field
    return conditions[-1].field


def power_coefficients(bernstein: np.ndarray) -> np.ndarray:
    """Power-basis coefficients a_k of Σ c_j B_j,d(x) = Σ a_k x^k:
    a_k = C(d, k) Σ_{i ≤ k} (−1)^(k−i) C(k, i) c_i."""
    d = len(bernstein) - 1
    out = np.zeros(d + 1)
    for k in range(d + 1):
        out[k] = comb(d, k) * sum((-1) ** (k - i) * comb(k, i) * bernstein[i] for i in range(k + 1))
    return out


def elevate(bernstein: np.ndarray, degree: int) -> np.ndarray:
    """Bernstein coefficients of the same polynomial written with ``degree`` ≥ its own."""
    c = np.asarray(bernstein, dtype=float)
    while len(c) - 1 < degree:
        d = len(c) - 1
        i = np.arange(1, d + 1)
        mid = (i / (d + 1)) * c[:-1] + (1 - i / (d + 1)) * c[1:]
        c = np.concatenate([[c[0]], mid, [c[-1]]])
    return c


def bezier_lift(bernstein: np.ndarray, span: float, low: float, height: float) -> BSplineLift:
    """The polynomial s(x) = Σ c_j B_j(x) on a segment of ``span`` rad as a B-spline lift (one
    Bézier span, θ(u) = β·u) with normalised lifts y = (s − low)/height."""
    d = len(bernstein) - 1
    return BSplineLift(d + 1, np.linspace(0.0, span, d + 1), (np.asarray(bernstein) - low) / height)


def piecewise_lift(pieces: list[tuple[float, float, np.ndarray]], low: float, height: float) -> BSplineLift:
    """Polynomial pieces (θ_a, θ_b [rad from the segment start], Bernstein coefficients of s on
    [θ_a, θ_b]) joined end to end as one B-spline lift: every piece raised to the largest degree p,
    one knot span per piece (u = 0, 1, …, P; interior knots of multiplicity p) and θ(u) linear on
    each span — exactly the pieces, whatever their lengths."""
    p = max(max(len(c) - 1 for _a, _b, c in pieces), 1)
    xs, ys = [], []
    for i, (ta, tb, c) in enumerate(pieces):
        ce = elevate(c, p)
        xe = np.linspace(ta, tb, p + 1)
        if i:
            ce, xe = ce[1:], xe[1:]
        xs.append(xe)
        ys.append(ce)
    count = len(pieces)
    knots = np.concatenate([np.zeros(p + 1)] + [np.full(p, float(j)) for j in range(1, count)]
                           + [np.full(p + 1, float(count))])
    y = (np.concatenate(ys) - low) / height
    return BSplineLift(p + 1, np.concatenate(xs), y, None if count == 1 else knots)


# ---- constant velocity with blended ends ---------------------------------------------------------
def blend_conditions(side: str, outer: list[tuple[int, float, str]], velocity: float, order: int
                     ) -> list[Condition]:
    """Conditions of one blend on its own x ∈ [0, 1]: at the outer end (the neighbour's side) s
    relative 0 and the given derivatives ``outer`` = [(order, value, field)], at the inner end
    s′ = V, s″ = 0 … up to ``order``.  ``side`` "start": outer at x = 0; "end": outer at x = 1
    (then the relative s = 0 is put at the inner end)."""
    xo, xi = (0.0, 1.0) if side == "start" else (1.0, 0.0)
    conds = [Condition(xi if side == "end" else xo, 0, 0.0, "")]
    conds += [Condition(xo, n, v, f) for n, v, f in outer]
    conds += [Condition(xi, n, velocity if n == 1 else 0.0, "") for n in range(1, order + 1)]
    return conds


def cruise_pieces(span: float, lift: float, start_blend: float, end_blend: float,
                  start_outer: list[tuple[int, float, str]], end_outer: list[tuple[int, float, str]],
                  start_order: int, end_order: int, level: float
                  ) -> tuple[float, list[tuple[float, float, np.ndarray]]]:
    """(cruise velocity V [lift/rad], pieces as for :func:`piecewise_lift`) of a constant-velocity
    segment of signed ``lift`` over ``span`` rad starting at s = ``level``: blends of
    ``start_blend``/``end_blend`` rad (0: none) meeting the neighbours' derivatives ``*_outer``
    and the line s′ = V to ``*_order``.  Each blend's rise is a + b·V (its conditions are linear),
    so V = (lift − a₁ − a₂)/(b₁ + b₂ + line length)."""
    line = span - start_blend - end_blend
    parts = []
    for side, width, outer, order in (("start", start_blend, start_outer, start_order),
                                      ("end", end_blend, end_outer, end_order)):
        if width <= 0:
            parts.append(None)
            continue
        c0 = solve_conditions(blend_conditions(side, outer, 0.0, order), width)
        c1 = solve_conditions(blend_conditions(side, [(n, 0.0, f) for n, _v, f in outer], 1.0, order), width)
        parts.append((width, c0, c1))
    a = sum(p[1][-1] - p[1][0] for p in parts if p is not None)
    b = line + sum(p[2][-1] - p[2][0] for p in parts if p is not None)
    velocity = (lift - a) / b
    pieces: list[tuple[float, float, np.ndarray]] = []
    s = level
    t = 0.0
    for which, part in zip(("start", "end"), parts):
        if which == "end" and line > 0:
            pieces.append((t, t + line, np.array([s, s + velocity * line])))
            s += velocity * line
            t += line
        if part is None:
            continue
        width, c0, c1 = part
        c = c0 + velocity * c1
        c = c - c[0] + s
        pieces.append((t, t + width, c))
        s = c[-1]
        t += width
    return velocity, pieces

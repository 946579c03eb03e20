"""Polynomial motion segments' interior points as design variables (``optimise.variables``:
``points``, ``motion[k].points``).

A ``law = "polynomial"`` rise/return is the lowest-degree polynomial meeting its SVAJ conditions
(Norton; :mod:`cam_workbench.generators.motion.polynomial`), kept as Bernstein coefficients c — which the program
reads as a one-span B-spline lift with θ(u) linear.  The conditions are linear in their values, so
with the angles of the points fixed

    c(q) = c(q₀) + Φᵀ (q − q₀),      q = the points' lifts s_i [lift units],

Φ (m × (d + 1)) from :func:`cam_workbench.generators.motion.segments.polynomial_point_basis` (unit right-hand
sides).  A :class:`PointBlock` is that affine map behind the interface of a B-spline
:class:`~cam_workbench.generators.optimise.space.LiftBlock` (``arrays``, ``y_jac``, ``x_cols``, ``y_cols``), so the
smooth model's kinematics, checks, integrals and exact gradients take it unchanged:
∂y/∂q = Φᵀ / h (normalised lifts y = (c − low)/h).

Bounds: each s_i within the segment's lift range [low, low + h] (and within
``optimise.point_shift_max`` of its start when given), widened to contain the start.

Monotonic lift: on a rise s′ ≥ 0, on a return s′ ≤ 0 (the design check "oscillation"), imposed as
linear rows (s′ is linear in q) on the Bernstein coefficients of s′ raised to degree
:data:`MONOTONIC_DEGREE`: those coefficients are samples of s′ at x = j/D in the limit (they converge
to s′(j/D) as O(1/D)), and their signs bound s′'s everywhere (the convex hull) — so the rows are
sufficient, never let s′ dip between samples as plain sampling would, and cost at most O(1/D) of the
feasible set (a rise whose s′ just touches 0 inside is approached to within that).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SpecError
from ..motion.bspline_law import BSplineLift
from ..motion.polynomial import elevate
from ..motion.program import MotionProgram
from ..motion.segments import ORDER_NAMES, polynomial_dependants, polynomial_point_basis
from ..spec.model import CamSpec

#: Degree to which s′ is raised for the monotonic-lift rows (D + 1 rows per segment, less the ends).
MONOTONIC_DEGREE = 128


class ControlPolygon:
    """What the smooth model reads of a rise/return's control polygon ``x`` (angles from the segment
    start [rad]): shared by the B-spline blocks (:class:`~cam_workbench.generators.optimise.space.LiftBlock`) and
    :class:`PointBlock`."""

    x: np.ndarray

    @property
    def n_points(self) -> int:
        return int(self.x.shape[0])

    @property
    def span(self) -> float:
        return float(self.x[-1])


@dataclass(frozen=True)
class PointBlock(ControlPolygon):
    """One polynomial rise/return whose point lifts are design variables (module docstring)."""

    motion_index: int
    kind: str                  # "rise" or "return"
    order: int                 # polynomial degree + 1
    x: np.ndarray              # (d+1,) control angles from the segment start [rad] (θ(u) linear)
    y: np.ndarray              # (d+1,) normalised Bernstein coefficients at the start
    angles_deg: np.ndarray     # (m,) the points' angles from the segment start [deg], fixed
    s0: np.ndarray             # (m,) the points' starting lifts [lift units]
    y_cols: np.ndarray         # (m,) positions in p of the lifts
    y_map: np.ndarray          # (d+1, m) ∂y/∂s_i = Φᵀ/h
    low: float                 # the segment's lower level [lift units]
    height: float              # |lift| [lift units]

    x_cols = np.array([], dtype=int)      # the angles are never varied

    @property
    def y_jac(self) -> np.ndarray:
        """(d+1, m): ∂y/∂(the block's variables)."""
        return self.y_map

    def arrays(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Control x and y (d+1 each) at design ``p`` (any dtype: complex for tests)."""
        return self.x.astype(p.dtype), self.y + self.y_map @ (p[self.y_cols] - self.s0)

    def lifts(self, p: np.ndarray) -> np.ndarray:
        """The points' lifts s_i [lift units] at design ``p``."""
        return np.asarray(p[self.y_cols], dtype=float)

    def monotonic_rows(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """(A, c) with A·p ≤ c ⇔ −sgn × every Bernstein coefficient of s′ raised to degree
        :data:`MONOTONIC_DEGREE` ≤ 0, in units of h/β (s′ = (h/β)·d·Σ Δy_j B_j,d−1(x)); rows that
        no variable moves (the ends, whose s′ the conditions fix) are left out."""
        sgn = 1.0 if self.kind == "rise" else -1.0
        d = self.order - 1
        diff = d * (np.eye(d + 1)[1:] - np.eye(d + 1)[:-1])            # (d, d+1): y → Bernstein of y′
        raise_to = max(MONOTONIC_DEGREE, d - 1)
        elev = np.column_stack([elevate(e, raise_to) for e in np.eye(d)])   # (D+1, d)
        m = elev @ diff                                                  # (D+1, d+1)
        a_local = -sgn * (m @ self.y_map)
        c = sgn * (m @ (self.y - self.y_map @ self.s0))
        keep = np.max(np.abs(a_local), axis=1) > 1e-12 * max(1.0, float(np.max(np.abs(a_local))))
        a = np.zeros((int(keep.sum()), n))
        a[:, self.y_cols] = a_local[keep]
        return a, c[keep]


def point_block(spec: CamSpec, program: MotionProgram, k: int, first_col: int) -> PointBlock:
    """The :class:`PointBlock` of polynomial row ``k`` with its variables from column ``first_col``.

    Raises:
        SpecError: ``optimise.variables`` — a neighbour law takes one of the segment's solved end
            values (it would move with the points): give that end value or lower a continuity.
    """
    seg = spec.motion[k]
    deps = polynomial_dependants(spec.motion, k)
    if deps:
        j, e, order = deps[0]
        end = ("start", "end")[1 - e]
        raise SpecError("optimise.variables",
                        f"motion[{k}].points: motion[{j}] takes its {ORDER_NAMES[order]} from motion[{k}]'s {end}, "
                        f"which the points move; give motion[{k}].{end}_{ORDER_NAMES[order]} or lower "
                        f"motion[{j}]'s continuity")
    curve = program.curves[k]
    span = float(program.spans[k])
    height = abs(float(program.lifts[k]))
    low = float(min(program.levels[k], program.levels[k] + program.lifts[k]))
    phi = polynomial_point_basis(seg, f"motion[{k}]", span)          # (m, d+1)
    if phi.shape[1] != curve.n_points:                                # the program's own solve
        raise SpecError(f"motion[{k}].points", "the polynomial's degree does not match its conditions")
    pts = np.asarray(seg.points, dtype=float).reshape(-1, 2)
    kind = "rise" if program.lifts[k] > 0 else "return"
    cols = np.arange(first_col, first_col + pts.shape[0])
    return PointBlock(k, kind, curve.order, curve.x.copy(), curve.y.copy(), pts[:, 0].copy(), pts[:, 1].copy(),
                      cols, phi.T / height, low, height)


def point_bounds(block: PointBlock, shift_max: float | None) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) of the block's lifts: the segment's lift range, within ``shift_max`` of the
    start when given (the caller widens them to contain the start)."""
    lo = np.full(block.s0.shape, block.low)
    hi = np.full(block.s0.shape, block.low + block.height)
    if shift_max is not None:
        lo = np.maximum(lo, block.s0 - shift_max)
        hi = np.minimum(hi, block.s0 + shift_max)
    return lo, hi


def curve_at(block: PointBlock, p: np.ndarray) -> BSplineLift:
    """The segment's lift law at design ``p`` (one Bézier span, as the program holds it)."""
    x, y = block.arrays(np.asarray(p, dtype=float))
    return BSplineLift(block.order, x, y)

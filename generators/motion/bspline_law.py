"""B-spline lift curves (thesis §2.5–2.7): a rise or return as the parametric B-spline

    θ(u) = Σ P_ix N_i,k(u),   y(u) = Σ P_iy N_i,k(u)            (thesis Eq. 2.28–2.29)

of order k (degree k − 1) with n + 1 control points and the uniform clamped knots of
thesis Eq. 2.12, u ∈ [0, n − k + 2].  θ is in radians measured from the segment start
here (the spec also accepts the thesis' absolute angles, :mod:`cam_workbench.generators.spec`); y is the
normalised lift (a rise runs 0 → 1, a return 1 → 0; the follower displacement is
level + L·y for a rise).

Boundary conditions (thesis §2.7): P₀ and P_n sit at the segment ends, and the first and
last k − 1 control points share the end level, which makes dy/dθ … d^(k−2)y/dθ^(k−2)
vanish at both ends (for the thesis' k = 5: velocity, acceleration and jerk).

Derivatives with respect to θ are exact (thesis Eq. 2.37–2.39); θ(u) is inverted by
vectorised Newton iteration kept inside a bracket (bisection when Newton leaves it),
which converges for every polygon whose control θ increase (then θ'(u) > 0).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from ..curves.basis import basis_derivatives, find_span
from ..errors import SpecError, fmt_apart

#: Default order k (degree k − 1) and control-point count, as in the thesis (§2.7, §2.8).
DEFAULT_ORDER = 5
DEFAULT_POINTS = 11


def clamped_uniform_knots(n_points: int, order: int) -> np.ndarray:
    """Thesis Eq. 2.12: t_i = 0 (i < k), i − k + 1 (k ≤ i ≤ n), n − k + 2 (i > n), 0 ≤ i ≤ n + k."""
    n, k = n_points - 1, order
    i = np.arange(n + k + 1)
    return np.where(i < k, 0.0, np.where(i > n, float(n - k + 2), (i - k + 1).astype(float)))


def fixed_end_points(order: int) -> int:
    """Control points at each end that share the end level (thesis §2.7: 4 for k = 5),
    so that derivatives 1 … k − 2 vanish there."""
    return order - 1


@dataclass(frozen=True)
class BSplineLift:
    """One rise or return as a parametric B-spline (θ(u), y(u)).

    Attributes:
        order: k (degree k − 1).
        x: (n+1,) control-point cam angles [rad] from the segment start; x[0] = 0, x[-1] = span.
        y: (n+1,) control-point normalised lifts.
        knots: (n + k + 1,) knot vector; default (None) the thesis' uniform clamped knots
            (Eq. 2.12).  Piecewise laws (a constant-velocity segment with blended ends,
            :mod:`cam_workbench.generators.motion.segments`) give clamped knots of their own.
    """

    order: int
    x: np.ndarray
    y: np.ndarray
    knots: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "x", np.asarray(self.x, dtype=float))
        object.__setattr__(self, "y", np.asarray(self.y, dtype=float))
        if self.knots is None:
            object.__setattr__(self, "knots", clamped_uniform_knots(len(self.x), self.order))
        else:
            knots = np.asarray(self.knots, dtype=float)
            if knots.shape != (len(self.x) + self.order,):
                raise ValueError(f"{len(self.x)} control points of order {self.order} need "
                                 f"{len(self.x) + self.order} knots, got {knots.shape[0]}")
            object.__setattr__(self, "knots", knots)

    @cached_property
    def _linear_breaks(self) -> tuple[np.ndarray, np.ndarray] | None:
        """(u, θ) at the distinct knots when θ(u) is linear on every knot span (the lifts solved or
        fitted with θ(u) linear: :mod:`cam_workbench.generators.motion.segments`), else None.  Exact test: θ(u) of
        degree p equals the chord on a span iff it does at p + 1 points of it."""
        ub = np.unique(self.knots)
        p = self.degree
        frac = np.linspace(0.0, 1.0, p + 1)[1:-1] if p > 1 else np.array([])
        u = (ub[:-1, None] + (ub[1:] - ub[:-1])[:, None] * frac[None, :]).ravel()
        th = self.parametric(np.concatenate([ub, u]), 0)[0][0]
        tb, tu = th[:ub.shape[0]], th[ub.shape[0]:]
        if np.any(np.diff(tb) <= 0):
            return None
        chord = np.interp(u, ub, tb)
        if np.any(np.abs(tu - chord) > 1e-13 * max(abs(self.span), 1e-300)):
            return None
        return ub, tb

    @property
    def degree(self) -> int:
        return self.order - 1

    @property
    def n_points(self) -> int:
        return int(self.x.shape[0])

    @property
    def span(self) -> float:
        """Segment span [rad]."""
        return float(self.x[-1] - self.x[0])

    @property
    def u_max(self) -> float:
        """Parameter range end n − k + 2 (thesis §2.5)."""
        return float(self.knots[-1])

    # ---- parametric evaluation -----------------------------------------------------
    def parametric(self, u: np.ndarray, nder: int = 3) -> tuple[np.ndarray, np.ndarray]:
        """(θ^(d)(u), y^(d)(u)) for d = 0..nder, each of shape (nder + 1, len(u))
        (thesis Eq. 2.28–2.36 with L = 1)."""
        span, ders = basis_derivatives(self.knots, self.degree, u, nder)
        idx = span[:, None] - self.degree + np.arange(self.degree + 1)[None, :]
        th = np.einsum("ndj,nj->dn", ders, self.x[idx])
        yy = np.einsum("ndj,nj->dn", ders, self.y[idx])
        return th, yy

    @cached_property
    def _table(self) -> tuple[np.ndarray, np.ndarray]:
        """θ on a grid of 32 parameters per knot span (starting guesses and brackets)."""
        u = np.linspace(0.0, self.u_max, 32 * max(1, int(round(self.u_max))) + 1)
        return u, self.parametric(u, 0)[0][0]

    def u_of_theta(self, theta: np.ndarray, tol: float = 1e-15, max_iter: int = 100) -> np.ndarray:
        """Solve θ(u) = θ for u, vectorised: Newton from a tabulated guess, kept inside the
        table's bracket (bisection whenever a Newton step would leave it).  θ is clipped to
        the segment [x₀, x_n]."""
        theta = np.clip(np.atleast_1d(np.asarray(theta, dtype=float)), self.x[0], self.x[-1])
        breaks = self._linear_breaks
        if breaks is not None:              # θ(u) linear per span: no iteration
            return np.interp(theta, breaks[1], breaks[0])
        ut, tt = self._table
        j = np.clip(np.searchsorted(tt, theta, side="right"), 1, len(tt) - 1)
        lo, hi = ut[j - 1].copy(), ut[j].copy()
        tlo, thi = tt[j - 1], tt[j]
        with np.errstate(divide="ignore", invalid="ignore"):
            frac = np.where(thi > tlo, (theta - tlo) / (thi - tlo), 0.5)
        u = lo + np.clip(frac, 0.0, 1.0) * (hi - lo)
        scale = max(abs(self.span), 1.0)
        active = np.ones(theta.shape, dtype=bool)
        for _ in range(max_iter):
            idx = np.flatnonzero(active)
            ua = u[idx]
            th, _ = self.parametric(ua, 1)
            g = th[0] - theta[idx]
            # keep the bracket: θ increasing, so g > 0 means the root is below u
            hi[idx] = np.where(g > 0, ua, hi[idx])
            lo[idx] = np.where(g <= 0, ua, lo[idx])
            with np.errstate(divide="ignore", invalid="ignore"):
                un = ua - g / th[1]
            bad = ~np.isfinite(un) | (un < lo[idx]) | (un > hi[idx])
            un = np.where(bad, 0.5 * (lo[idx] + hi[idx]), un)
            hit = np.abs(g) <= 2 * np.finfo(float).eps * scale
            un = np.where(hit, ua, un)
            done = hit | (np.abs(un - ua) <= tol * self.u_max)
            u[idx] = un
            active[idx[done]] = False
            if not active.any():
                break
        return u

    def evaluate(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """y and dy/dθ, d²y/dθ², d³y/dθ³ [per rad] at cam angles ``theta`` [rad, from the
        segment start] — thesis Eq. 2.37–2.39 at the parameter u solving θ(u) = θ.  When θ(u) is
        linear on every knot span, y is evaluated per span as a polynomial in θ (Horner, centred on
        the span: the same numbers without the basis recursion)."""
        theta = np.asarray(theta, dtype=float)
        if self._power_table is not None:
            return tuple(v.reshape(theta.shape) for v in self._evaluate_power(theta.ravel()))  # type: ignore
        u = self.u_of_theta(theta.ravel())
        return tuple(v.reshape(theta.shape) for v in self.derivatives_at(u))  # type: ignore[return-value]

    @cached_property
    def _power_table(self) -> tuple[np.ndarray, np.ndarray, list[np.ndarray]] | None:
        """(θ at the distinct knots, θ at the span centres, per derivative order n = 0…3 the
        (spans, p + 1 − n) coefficients of d^n y/dθ^n as a polynomial in θ − θ_centre), or None
        unless θ(u) is linear on every span."""
        breaks = self._linear_breaks
        if breaks is None:
            return None
        ub, tb = breaks
        p = self.degree
        mid_u = 0.5 * (ub[:-1] + ub[1:])
        slope = np.diff(tb) / np.diff(ub)                        # dθ/du on each span
        ders = self.parametric(mid_u, p)[1]                        # (p + 1, spans): d^m y/du^m
        m = np.arange(p + 1)
        fact = np.array([math.factorial(int(k)) for k in m], dtype=float)
        c = (ders / fact[:, None] / slope[None, :] ** m[:, None]).T  # in θ − θ_mid
        tables = []
        for n in range(4):
            if n > p:
                tables.append(np.zeros((c.shape[0], 1)))
                continue
            k = np.arange(p + 1 - n)
            falling = np.array([math.perm(int(j + n), n) for j in k], dtype=float)
            tables.append(c[:, n:] * falling[None, :])
        return tb, np.interp(mid_u, ub, tb), tables

    def _evaluate_power(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        tb, mid, tables = self._power_table  # type: ignore[misc]
        theta = np.clip(theta, self.x[0], self.x[-1])
        j = np.clip(np.searchsorted(tb, theta, side="right") - 1, 0, tb.shape[0] - 2)
        d = theta - mid[j]
        out = []
        for coef in tables:
            rows = coef[j]
            acc = rows[:, -1].copy()
            for m in range(coef.shape[1] - 2, -1, -1):
                acc = acc * d + rows[:, m]
            out.append(acc)
        return tuple(out)  # type: ignore[return-value]

    def derivatives_at(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(y, y', y'', y''') with respect to θ at parameters u (thesis Eq. 2.37–2.39)."""
        th, yy = self.parametric(np.atleast_1d(u), 3)
        t1, t2, t3 = th[1], th[2], th[3]
        y1, y2, y3 = yy[1], yy[2], yy[3]
        d1 = y1 / t1                                                        # Eq. 2.37
        d2 = (t1 * y2 - y1 * t2) / t1**3                                    # Eq. 2.38
        d3 = (t1 * (t1 * y3 - y1 * t3) - 3 * t2 * (t1 * y2 - y1 * t2)) / t1**5  # Eq. 2.39
        return yy[0], d1, d2, d3

    def theta_at(self, u: np.ndarray) -> np.ndarray:
        """θ(u) [rad from the segment start]."""
        return self.parametric(np.atleast_1d(u), 0)[0][0]

    def node_parameters(self, count: int) -> np.ndarray:
        """``count`` equally spaced parameters over [0, n − k + 2] (the thesis' check nodes,
        §5.3: 70 equal intervals per rise or return)."""
        return np.linspace(0.0, self.u_max, count)

    def theta_derivative_coefficients(self) -> np.ndarray:
        """Control coefficients of θ'(u) (a B-spline of order k − 1):
        c_i = (k − 1)(x_{i+1} − x_i)/(t_{i+k} − t_{i+1}).  All positive ⇒ θ increasing."""
        k = self.order
        t = self.knots
        n = self.n_points
        with np.errstate(divide="ignore", invalid="ignore"):
            return (k - 1) * np.diff(self.x) / (t[k:n + k - 1] - t[1:n])


# ---- from a spec segment --------------------------------------------------------------
_FRAME_UNIT = {"relative_deg": "°", "absolute_rad": " rad"}


def lift_from_segment(seg: Any, path: str, start: float, span: float) -> BSplineLift:
    """The :class:`BSplineLift` of a ``law = "bspline"`` motion segment, checking its control
    polygon; raises :class:`~cam_workbench.generators.errors.SpecError` naming the field and control point.

    Args:
        seg: the motion segment (``order``, ``control_x``, ``control_y``, ``control_frame``,
            ``control_start``, ``kind``).
        path: the segment's field path, e.g. ``motion[1]``.
        start: the segment's start in the program [rad].
        span: the segment's span [rad].
    """
    k = seg.order or DEFAULT_ORDER
    if seg.control_x is None:
        raise SpecError(f"{path}.control_x", 'is required for law = "bspline" '
                        "(the cam angles of the interior control points P1 … P(n−1))")
    if seg.control_y is None:
        raise SpecError(f"{path}.control_y", 'is required for law = "bspline" '
                        f"(the normalised lifts of the free control points P{k - 1} … P(n−{k - 1}))")
    nfix = fixed_end_points(k)
    cx = np.asarray(seg.control_x, dtype=float)
    cy = np.asarray(seg.control_y, dtype=float)
    n = cx.shape[0] + 1                      # control points P0 … Pn
    if n + 1 < 2 * nfix:
        raise SpecError(f"{path}.control_x",
                        f"has {cx.shape[0]} interior control points; order {k} needs at least "
                        f"{2 * nfix - 2} (k − 1 = {nfix} control points sit at each end level)")
    frame = seg.control_frame or "relative_deg"
    if seg.control_start is not None and frame != "absolute_rad":
        raise SpecError(f"{path}.control_start", 'is only used with control_frame = "absolute_rad"')
    if frame == "relative_deg":
        origin_user = 0.0
        xr = np.deg2rad(cx)
        to_user = np.rad2deg
    else:
        origin_user = np.deg2rad(seg.control_start) if seg.control_start is not None else start
        xr = cx - origin_user
        to_user = lambda v: v + origin_user  # noqa: E731
    x = np.concatenate([[0.0], xr, [span]])
    y_start, y_end = (0.0, 1.0) if seg.kind == "rise" else (1.0, 0.0)
    n_free = n + 1 - 2 * nfix
    if cy.shape[0] == n_free:
        y = np.concatenate([np.full(nfix, y_start), cy, np.full(nfix, y_end)])
    elif cy.shape[0] == n - 1:
        y = np.concatenate([[y_start], cy, [y_end]])
        for i in list(range(1, nfix)) + list(range(n - nfix + 1, n)):
            want = y_start if i < nfix else y_end
            if abs(y[i] - want) > 1e-9:
                end = "first" if i < nfix else "last"
                raise SpecError(
                    f"{path}.control_y[{i - 1}]",
                    f"control point P{i} must be at y = {want:g}: the {end} k − 1 = {nfix} control "
                    f"points of a {seg.kind} sit at its {'start' if i < nfix else 'end'} level so that "
                    f"velocity … derivative {k - 2} vanish there (got {fmt_apart(y[i], want)})")
    else:
        raise SpecError(
            f"{path}.control_y",
            f"has {cy.shape[0]} values; with {n + 1} control points of order {k} give "
            + (f"the {n_free} free lifts (P{nfix} … P{n - nfix})" if n_free else "[] (none is free)")
            + f" or all {n - 1} interior ones (P1 … P{n - 1}): control_x's {n - 1} angles and the segment's two "
            "ends are the control points")
    lift = BSplineLift(k, x, y)
    _check_theta_increasing(lift, f"{path}.control_x", frame, to_user)
    return lift


def _check_theta_increasing(lift: BSplineLift, path: str, frame: str, to_user) -> None:
    """θ(u) must increase: exact when every control θ increases (θ'(u) is then a positive
    combination of B-splines); otherwise θ'(u) is sampled 64 times per knot span and the
    control point of the non-increasing step nearest to its minimum is named — the earlier of its
    two points when that one is the odd one out (not before the point after next either)."""
    c = lift.theta_derivative_coefficients()
    if np.all(c > 0):
        return
    u = np.linspace(0.0, lift.u_max, 64 * int(round(lift.u_max)) + 1)
    th, _ = lift.parametric(u, 1)
    jmin = int(np.argmin(th[1]))
    if th[1][jmin] > 0:
        return
    # coefficients of θ' whose B-splines (order k − 1, knots t[1:-1]) are non-zero at u*
    span = int(find_span(lift.knots, lift.degree, np.array([u[jmin]]))[0])
    cand = np.arange(max(span - lift.degree, 0), min(span, len(c) - 1) + 1)
    i = int(cand[np.argmin(c[cand])]) if cand.size else int(np.argmin(c))
    n = lift.n_points - 1
    unit = _FRAME_UNIT[frame]
    xs = to_user(lift.x)
    if 1 <= i and i + 2 <= n and xs[i] >= xs[i + 2] and not xs[i + 1] <= xs[i - 1]:
        # P(i) is the odd one out (not before P(i+2) either, while P(i+1) is after P(i−1)): control_x[i−1]
        field, msg = f"{path}[{i - 1}]", (f"θ(u) must increase, but control point P{i} "
                                          f"({fmt_apart(xs[i], xs[i + 1])}{unit}) is not before P{i + 1} "
                                          f"({fmt_apart(xs[i + 1], xs[i])}{unit}) nor P{i + 2} "
                                          f"({fmt_apart(xs[i + 2], xs[i])}{unit})")
    elif i + 1 < n:      # P(i+1) is a listed point: control_x[i]
        field, msg = f"{path}[{i}]", (f"θ(u) must increase, but control point P{i + 1} "
                                      f"({fmt_apart(xs[i + 1], xs[i])}{unit}) is not after P{i} "
                                      f"({fmt_apart(xs[i], xs[i + 1])}{unit})")
        if i == 0:
            msg += " — P0 is the segment start"
    else:                # the last listed point passes the segment end Pn
        field, msg = f"{path}[{i - 1}]", (f"θ(u) must increase, but control point P{i} "
                                          f"({fmt_apart(xs[i], xs[n])}{unit}) is not before the segment end "
                                          f"P{n} ({fmt_apart(xs[n], xs[i])}{unit})")
    raise SpecError(field, msg)

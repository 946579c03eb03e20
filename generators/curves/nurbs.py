"""Neutral NURBS curve data — the one geometry type every kernel adaptor consumes
(OCP ``Geom_BSplineCurve``, FreeCAD ``Part.BSplineCurve``, ezdxf ``SPLINE``).

Poles are 2-D (x, y) in spec length units; ``knots`` is the full (clamped) knot
vector of length n_poles + degree + 1; weights are positive.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .bezier import bernstein_basis



@dataclass(frozen=True)
class NurbsCurve:
    """A planar rational B-spline.

    Attributes:
        degree: polynomial degree p.
        knots: full knot vector (n + p + 1,), non-decreasing, clamped.
        poles: (n, 2) control points.
        weights: (n,) positive weights (all ones for a polynomial curve).
    """

    degree: int
    knots: np.ndarray
    poles: np.ndarray
    weights: np.ndarray

    @property
    def n_poles(self) -> int:
        return int(self.poles.shape[0])

    @property
    def is_rational(self) -> bool:
        w = self.weights
        return bool(np.ptp(w) > 1e-12 * np.max(np.abs(w)))

    @property
    def is_closed(self) -> bool:
        return bool(np.allclose(self.poles[0], self.poles[-1], rtol=0, atol=1e-12 * self.size))

    @property
    def size(self) -> float:
        return float(np.max(np.abs(self.poles)))

    @property
    def domain(self) -> tuple[float, float]:
        p = self.degree
        return float(self.knots[p]), float(self.knots[-p - 1])

    def distinct_knots(self) -> tuple[np.ndarray, np.ndarray]:
        """(unique knots, multiplicities) — the form OCCT and FreeCAD take."""
        u, mult = np.unique(self.knots, return_counts=True)
        return u, mult

    @cached_property
    def _bezier_spans(self) -> tuple[np.ndarray, np.ndarray] | None:
        """(span knots (S+1,), homogeneous Bézier control points (S, p+1, 3)) when every
        interior knot has multiplicity p (a chain of Bézier spans), else None."""
        p = self.degree
        u, mult = self.distinct_knots()
        if not (mult[0] == p + 1 and mult[-1] == p + 1 and np.all(mult[1:-1] == p)):
            return None
        hom = np.hstack([self.poles * self.weights[:, None], self.weights[:, None]])
        s = len(u) - 1
        idx = np.arange(s)[:, None] * p + np.arange(p + 1)[None, :]
        return u, hom[idx]

    def _homogeneous(self, u: np.ndarray, derivative: bool = False
                     ) -> tuple[np.ndarray, np.ndarray | None]:
        """Homogeneous points (and d/du) at parameters ``u``."""
        bz = self._bezier_spans
        p = self.degree
        if bz is None:
            hom = np.hstack([self.poles * self.weights[:, None], self.weights[:, None]])
            if derivative:
                return _bspline_eval_and_derivative(p, self.knots, hom, u)
            span = np.minimum(np.maximum(np.searchsorted(self.knots, u, side="right") - 1, p), self.n_poles - 1)
            return _de_boor(p, self.knots, hom, u, span), None
        knots, ctrl = bz
        k = np.minimum(np.maximum(np.searchsorted(knots, u, side="right") - 1, 0), len(knots) - 2)
        h = knots[k + 1] - knots[k]
        t = (u - knots[k]) / h
        c = ctrl[k]                                            # (N, p+1, 3)
        val = np.einsum("nk,nkc->nc", bernstein_basis(p, t), c)
        if not derivative:
            return val, None
        dc = p * np.diff(c, axis=1) / h[:, None, None]
        der = np.einsum("nk,nkc->nc", bernstein_basis(p - 1, t), dc)
        return val, der

    def evaluate(self, u: np.ndarray) -> np.ndarray:
        """Points (len(u), 2), vectorised over u (Bernstein form on Bézier-structured
        curves, rational de Boor otherwise)."""
        u = np.atleast_1d(np.asarray(u, dtype=float))
        out, _ = self._homogeneous(u)
        return out[:, :2] / out[:, 2:3]

    def sample(self, per_span: int = 32) -> tuple[np.ndarray, np.ndarray]:
        """Parameters and points sampling every non-empty knot span uniformly (end included)."""
        u_knots = np.unique(self.knots[self.degree:-self.degree])
        fr = np.arange(per_span) / per_span
        u = (u_knots[:-1, None] + np.diff(u_knots)[:, None] * fr[None, :]).ravel()
        u = np.append(u, u_knots[-1])
        return u, self.evaluate(u)

    def area(self, gauss_points: int = 24) -> float:
        """Signed enclosed area ½∮(x dy − y dx) by Gauss–Legendre on every knot span
        (positive for counter-clockwise).  Rational spans are not polynomials, but 24
        points per span integrate them to ~1e-15 relative for smooth cams.  The default rule's
        value is computed once per curve (the curve is immutable)."""
        return self._area24 if gauss_points == 24 else self._gauss_area(gauss_points)

    @cached_property
    def _area24(self) -> float:
        return self._gauss_area(24)

    def _gauss_area(self, gauss_points: int) -> float:
        xg, wg = np.polynomial.legendre.leggauss(gauss_points)
        u_knots = np.unique(self.knots[self.degree:-self.degree])
        a, b = u_knots[:-1], u_knots[1:]
        u = (0.5 * (b - a)[:, None] * (xg[None, :] + 1) + a[:, None]).ravel()
        pts, der = self.evaluate_with_derivative(u)
        integrand = pts[:, 0] * der[:, 1] - pts[:, 1] * der[:, 0]
        w = (0.5 * (b - a)[:, None] * wg[None, :]).ravel()
        return 0.5 * float(np.sum(integrand * w))

    def evaluate_with_derivative(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Points and first derivatives d/du (quotient rule on the homogeneous curve)."""
        u = np.atleast_1d(np.asarray(u, dtype=float))
        pw, dpw = self._homogeneous(u, derivative=True)
        assert dpw is not None
        pts = pw[:, :2] / pw[:, 2:3]
        der = (dpw[:, :2] - pts * dpw[:, 2:3]) / pw[:, 2:3]
        return pts, der

    def bezier_pieces(self) -> list["NurbsCurve"]:
        """The Bézier spans of a curve whose interior knots all have full multiplicity
        (= degree), exactly (poles and weights shared, nothing refitted); otherwise [self].

        Kernels integrate single Bézier edges exactly (OCCT: ~1e-15) but multi-span
        edges poorly (~1e-3 measured on a 60-span degree-9 profile)."""
        bz = self._bezier_spans
        if bz is None:
            return [self]
        knots, _ = bz
        p = self.degree
        pieces = []
        for k in range(len(knots) - 1):
            sl = slice(k * p, k * p + p + 1)
            kv = np.concatenate([np.full(p + 1, knots[k]), np.full(p + 1, knots[k + 1])])
            pieces.append(NurbsCurve(p, kv, self.poles[sl], self.weights[sl]))
        return pieces

    def reversed(self) -> "NurbsCurve":
        """Same curve traversed the other way."""
        lo, hi = self.domain
        return NurbsCurve(self.degree, (lo + hi) - self.knots[::-1], self.poles[::-1].copy(),
                          self.weights[::-1].copy())


def _bspline_eval_and_derivative(p: int, t: np.ndarray, ctrl: np.ndarray, u: np.ndarray
                                 ) -> tuple[np.ndarray, np.ndarray]:
    """Value and first derivative of a (non-rational) B-spline with control points ``ctrl``."""
    n = ctrl.shape[0]
    span = np.clip(np.searchsorted(t, u, side="right") - 1, p, n - 1)
    # derivative curve: degree p−1, control points p (P_{i+1} − P_i)/(t_{i+p+1} − t_{i+1})
    dt = t[p + 1:n + p] - t[1:n]
    dctrl = np.zeros((n - 1, ctrl.shape[1]))
    ok = dt > 0
    dctrl[ok] = p * (ctrl[1:][ok] - ctrl[:-1][ok]) / dt[ok, None]
    val = _de_boor(p, t, ctrl, u, span)
    der = _de_boor(p - 1, t[1:-1], dctrl, u, span - 1)
    return val, der


def _de_boor(p: int, t: np.ndarray, ctrl: np.ndarray, u: np.ndarray, span: np.ndarray) -> np.ndarray:
    idx = span[:, None] - p + np.arange(p + 1)[None, :]
    d = ctrl[idx].astype(float)
    for r in range(1, p + 1):
        j = np.arange(r, p + 1)
        i = span[:, None] - p + j[None, :]
        left = t[i]
        right = t[i + p - r + 1]
        denom = right - left
        alpha = np.where(denom > 0, (u[:, None] - left) / np.where(denom > 0, denom, 1.0), 0.0)
        d[:, j] = (1 - alpha)[..., None] * d[:, j - 1] + alpha[..., None] * d[:, j]
    return d[:, p]


def from_rational_beziers(num: np.ndarray, den: np.ndarray) -> NurbsCurve:
    """Join S rational Bézier segments of degree p end to end into one NURBS with
    knots 0,1,…,S (multiplicity p inside) — exactly, without knot removal.

    Args:
        num: (S, p+1) complex weighted control points (w_k·P_k, as x + iy).
        den: (S, p+1) positive weights w_k.  Consecutive segments must share their
            end point and end weight (as the offset of a C¹ curve does); the shared
            pole takes the average of the two.
    """
    s, p1 = den.shape
    p = p1 - 1
    pts = num / den
    poles = np.empty(s * p + 1, dtype=complex)
    weights = np.empty(s * p + 1)
    poles[: s * p].reshape(s, p)[:] = pts[:, :p]
    weights[: s * p].reshape(s, p)[:] = den[:, :p]
    # shared poles: average the end of segment k−1 and the start of segment k
    poles[p: s * p: p] = 0.5 * (pts[:-1, p] + pts[1:, 0])
    weights[p: s * p: p] = 0.5 * (den[:-1, p] + den[1:, 0])
    poles[-1] = pts[-1, p]
    weights[-1] = den[-1, p]
    knots = np.concatenate([np.zeros(p + 1), np.repeat(np.arange(1, s), p), np.full(p + 1, float(s))])
    return NurbsCurve(p, knots, np.column_stack([poles.real, poles.imag]), weights)


def from_polynomial_beziers(ctrl: np.ndarray) -> NurbsCurve:
    """Join S polynomial Bézier segments (S, p+1) complex into one (non-rational) NURBS."""
    return from_rational_beziers(ctrl, np.ones(ctrl.shape, dtype=float))

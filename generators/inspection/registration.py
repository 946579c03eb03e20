"""Measured points against the exact profile: closest-point projection onto the profile NURBS and
the rigid registration of the points' frame to the part's frame.

Projection: the foot point of a point p on the curve C(u) solves f(u) = C′(u)·(C(u) − p) = 0;
Newton's method f′ = |C′|² + C″·(C − p), every point at once, seeded at the nearest vertex of a
dense sample of the curve (or at the previous foot point while the registration iterates).  C,
C′ and C″ are exact: the quotient rule on the rational Bézier spans of the profile NURBS.

Registration: the pose (α, t) maps a measured point m to the part's frame, x = e^{iα}·m + t
(rotation about the cam axis, then an in-plane shift).  Gauss–Newton on the signed normal
distances d_i = N_i·(x_i − C(u_i)) (point-to-curve ICP: the foot points are projected again
at every step), with ∂d/∂α = N·i(x − t), ∂d/∂t = (N_x, N_y), and iteratively reweighted least
squares: Huber weights (k = 1.345σ) until the pose settles, then Tukey's biweight (c = 4.685σ),
σ = 1.4826·median|d| (the MAD scale about the zero the fit aims at).  A point whose biweight is
zero (|d| > 4.685σ) is an outlier: it no longer moves the pose, and it is reported.

Datums (ISO 1101 / ISO 5459 words): ``"none"`` — the profile zone floats: rotation and shift
fitted; ``"bore"`` — the bore's axis is datum A and the points' origin: the shift is held at 0,
the rotation fitted; ``"bore_and_angle"`` — datum A and an angular datum (keyway, timing mark):
the points are in the part's frame already and nothing is fitted.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..curves.approx import nearest_vertex
from ..curves.bezier import bernstein_basis
from ..curves.nurbs import NurbsCurve
from ..errors import SpecError
from ..pitch.bspline import bezier_form

#: how a registration may move the points (see the module docstring)
DATUMS = ("none", "bore", "bore_and_angle")
#: Huber's and Tukey's tuning constants (95 % efficiency at the normal distribution)
HUBER_K = 1.345
TUKEY_C = 4.685
#: MAD → σ of a normal distribution
MAD_SCALE = 1.4826
#: dense samples per knot span that seed the projection
SEED_PER_SPAN = 48
#: coarse rotations tried before the fit when the rotation is free (5° apart), and the
#: point-to-point ICP steps that improve each
COARSE_ROTATIONS = 72
COARSE_ICP_STEPS = 12
#: points the coarse search scores (a subsample of the cloud)
COARSE_POINTS = 400


@dataclass(frozen=True)
class Projection:
    """Foot points of points on the profile.

    Attributes:
        u: (N,) curve parameters of the foot points.
        foot: (N,) foot points (complex, part frame).
        normal: (N,) unit outward normals there (complex).
        distance: (N,) signed normal distance, + outside the material's boundary (material outside).
        iterations: Newton iterations taken.
    """

    u: np.ndarray
    foot: np.ndarray
    normal: np.ndarray
    distance: np.ndarray
    iterations: int


class ProfileProjector:
    """Closest-point projection onto a closed profile NURBS (vectorised over points).

    The curve is read as its chain of rational Bézier spans (:func:`bezier_form`, exact), so that
    one Bernstein evaluation gives C, C′ and C″ (quotient rule on the homogeneous curve).

    Args:
        curve: the closed profile (spec lengths).
        per_span: dense samples per knot span for the seed.
    """

    def __init__(self, curve: NurbsCurve, per_span: int = SEED_PER_SPAN):
        self.curve = curve
        lo, hi = curve.domain
        self.lo, self.period = lo, hi - lo
        pieces = bezier_form(curve).bezier_pieces()
        self.knots = np.array([pc.domain[0] for pc in pieces] + [pieces[-1].domain[1]])
        self.hom = np.stack([np.column_stack([pc.poles * pc.weights[:, None], pc.weights]) for pc in pieces])
        self.degree = curve.degree
        u, pts = curve.sample(per_span)
        self.seed_u = u[:-1]
        self.seed_pts = pts[:-1, 0] + 1j * pts[:-1, 1]
        # outward normal = side·i·T: the interior lies left of a counter-clockwise curve
        self.side = -1.0 if curve.area() > 0 else 1.0
        self.step = float(np.min(np.diff(u)))
        self.size = float(np.max(np.abs(self.seed_pts)))

    def wrap(self, u: np.ndarray) -> np.ndarray:
        """Parameters taken into the closed curve's domain."""
        return self.lo + np.mod(u - self.lo, self.period)

    def derivatives(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """C(u), C′(u), C″(u) as complex arrays (u wrapped into the domain)."""
        u = self.wrap(np.asarray(u, dtype=float))
        p = self.degree
        k = np.clip(np.searchsorted(self.knots, u, side="right") - 1, 0, len(self.knots) - 2)
        h = self.knots[k + 1] - self.knots[k]
        t = (u - self.knots[k]) / h
        c = self.hom[k]                                                   # (N, p+1, 3)
        d1 = p * np.diff(c, axis=1) / h[:, None, None]
        d2 = (p - 1) * np.diff(d1, axis=1) / h[:, None, None]
        a = np.einsum("nk,nkc->nc", bernstein_basis(p, t), c)
        b = np.einsum("nk,nkc->nc", bernstein_basis(p - 1, t), d1)
        e = np.einsum("nk,nkc->nc", bernstein_basis(p - 2, t), d2)
        w, dw, ddw = a[:, 2], b[:, 2], e[:, 2]
        pt = (a[:, 0] + 1j * a[:, 1]) / w
        dpt = ((b[:, 0] + 1j * b[:, 1]) - pt * dw) / w
        ddpt = ((e[:, 0] + 1j * e[:, 1]) - 2 * dpt * dw - pt * ddw) / w
        return pt, dpt, ddpt

    def point_and_tangent(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """C(u) and C′(u) as complex arrays."""
        pt, dpt, _ = self.derivatives(u)
        return pt, dpt

    def project(self, points: np.ndarray, u0: np.ndarray | None = None, tol: float = 1e-13,
                max_iter: int = 40) -> Projection:
        """Foot points of ``points`` (complex) on the curve: Newton on u from ``u0`` or, without it,
        from the nearest dense sample (no loop over points)."""
        points = np.asarray(points, dtype=complex)
        u = self.seed_u[nearest_vertex(points, self.seed_pts)] if u0 is None else self.wrap(np.asarray(u0, dtype=float))
        it = 0
        for it in range(1, max_iter + 1):
            c, d1, d2 = self.derivatives(u)
            r = c - points
            f = (np.conj(d1) * r).real
            df = np.abs(d1) ** 2 + (np.conj(d2) * r).real
            step = np.clip(f / np.where(df > 0, df, np.abs(d1) ** 2), -self.step, self.step)
            u = self.wrap(u - step)
            if np.max(np.abs(step)) <= tol * max(1.0, self.period):
                break
        c, d1, _ = self.derivatives(u)
        normal = self.side * 1j * d1 / np.abs(d1)
        return Projection(u, c, normal, (np.conj(normal) * (points - c)).real, it)


@dataclass(frozen=True)
class Registration:
    """The pose of the measured points in the part's frame and what the fit saw.

    Attributes:
        datum: "none", "bore" or "bore_and_angle".
        rotation: α [rad]: x = e^{iα}·m + t.
        shift: t (complex, spec lengths).
        projection: the registered points' foot points and signed deviations.
        points: the registered points x (complex, part frame).
        outliers: (N,) bool: Tukey weight zero at the final pose.
        scale: σ of the final fit (MAD of the deviations, spec lengths).
        iterations: Gauss–Newton steps taken.
        converged: the last step moved the points by no more than ``tol``·size (True when nothing is fitted).
        weights: (N,) the final IRLS weights.
        std: standard uncertainty of (α [rad], t_x, t_y) from the final fit, σ·√diag((JᵀWJ)⁻¹)
            (None for what the datum holds).
    """

    datum: str
    rotation: float
    shift: complex
    projection: Projection
    points: np.ndarray
    outliers: np.ndarray
    scale: float
    iterations: int
    converged: bool
    weights: np.ndarray
    std: tuple[float | None, float | None, float | None]


def robust_scale(d: np.ndarray, floor: float) -> float:
    """σ = 1.4826·median|d| (about zero), at least ``floor``."""
    return max(MAD_SCALE * float(np.median(np.abs(d))), floor)


def huber_weights(d: np.ndarray, sigma: float) -> np.ndarray:
    a = np.abs(d)
    k = HUBER_K * sigma
    return np.where(a <= k, 1.0, k / np.maximum(a, k))


def tukey_weights(d: np.ndarray, sigma: float) -> np.ndarray:
    z = d / (TUKEY_C * sigma)
    return np.where(np.abs(z) < 1.0, (1.0 - z * z) ** 2, 0.0)


def coarse_pose(projector: ProfileProjector, m: np.ndarray, datum: str) -> tuple[float, complex]:
    """A starting pose: the identity and a rotation every 5° (datum "none": with the points'
    centroid moved onto the profile's; "bore": about the origin), each improved by point-to-point
    ICP on a subsample against the dense profile polygon (closed-form Procrustes steps on the 80 %
    nearest pairs, all candidates at once); the one whose points lie nearest (median) wins."""
    step = max(1, len(m) // COARSE_POINTS)
    sub = m[::step]
    poly = projector.seed_pts
    edge = np.abs(np.roll(poly, -1) - poly)
    centroid = complex(np.sum(0.5 * (poly + np.roll(poly, -1)) * edge) / np.sum(edge))
    rot = np.append(np.exp(2j * np.pi * np.arange(COARSE_ROTATIONS) / COARSE_ROTATIONS), 1.0)
    free_shift = datum == "none"
    shift = np.where(np.arange(len(rot)) < COARSE_ROTATIONS, centroid - rot * np.mean(sub), 0.0) if free_shift \
        else np.zeros(len(rot), dtype=complex)
    keep = max(3, int(0.8 * len(sub)))
    for _ in range(COARSE_ICP_STEPS):
        x = rot[:, None] * sub[None, :] + shift[:, None]
        near = poly[nearest_vertex(x.ravel(), poly)].reshape(x.shape)
        # the 80 % nearest pairs of every candidate (outliers and far points left out)
        nearest = np.argsort(np.abs(x - near), axis=1)[:, :keep]
        xs = np.take_along_axis(x, nearest, axis=1)
        ys = np.take_along_axis(near, nearest, axis=1)
        if free_shift:
            xc, yc = xs.mean(axis=1), ys.mean(axis=1)
            turn = np.exp(1j * np.angle(np.sum(np.conj(xs - xc[:, None]) * (ys - yc[:, None]), axis=1)))
            rot, shift = turn * rot, turn * (shift - xc) + yc
        else:
            turn = np.exp(1j * np.angle(np.sum(np.conj(xs) * ys, axis=1)))
            rot = turn * rot
    x = rot[:, None] * sub[None, :] + shift[:, None]
    cost = np.median(np.abs(x - poly[nearest_vertex(x.ravel(), poly)].reshape(x.shape)), axis=1)
    k = int(np.argmin(cost))
    return float(np.angle(rot[k])), complex(shift[k])


def register(projector: ProfileProjector, points: np.ndarray, datum: str = "none", *,
             tol: float = 1e-13, max_iter: int = 100) -> Registration:
    """Register ``points`` (complex, the measuring frame) to the profile: robust Gauss–Newton
    (see the module docstring).

    Raises:
        SpecError: an unknown datum, or fewer points than the fit needs.
    """
    if datum not in DATUMS:
        raise SpecError("datum", f"must be one of {', '.join(DATUMS)}, got {datum!r}")
    m = np.asarray(points, dtype=complex)
    free = {"none": 3, "bore": 1, "bore_and_angle": 0}[datum]
    if len(m) < max(free + 1, 3):
        raise SpecError("points", f"{len(m)} points: at least {max(free + 1, 3)} are needed")
    floor = 1e-9 * projector.size      # σ of a noise-free cloud: 0.05 µm on a 50 mm cam
    alpha, shift = (0.0, 0j) if free == 0 else coarse_pose(projector, m, datum)
    robust = huber_weights
    pr: Projection | None = None
    it = 0
    converged = free == 0
    for it in range(1, (max_iter if free else 0) + 1):
        x = np.exp(1j * alpha) * m + shift
        pr = projector.project(x, None if pr is None else pr.u)
        d = pr.distance
        sigma = robust_scale(d, floor)
        w = robust(d, sigma)
        cols = [(np.conj(pr.normal) * 1j * (x - shift)).real]
        if free == 3:
            cols += [pr.normal.real, pr.normal.imag]
        jac = np.column_stack(cols)
        jw = jac * w[:, None]
        delta = np.linalg.lstsq(jw.T @ jac, -(jw.T @ d), rcond=None)[0]
        alpha += float(delta[0])
        if free == 3:
            shift += complex(delta[1], delta[2])
        move = abs(float(delta[0])) * projector.size + (float(np.hypot(delta[1], delta[2])) if free == 3 else 0.0)
        if robust is huber_weights and move < 1e-7 * projector.size:
            robust = tukey_weights           # settled: the redescending loss now rejects the outliers
        elif move <= tol * projector.size:
            converged = True
            break
    x = np.exp(1j * alpha) * m + shift
    pr = projector.project(x, None if pr is None else pr.u)
    sigma = robust_scale(pr.distance, floor)
    w = tukey_weights(pr.distance, sigma)
    alpha = float(np.angle(np.exp(1j * alpha)))
    return Registration(datum, alpha, shift, pr, x, w == 0.0, sigma, it, converged, w,
                        pose_std(pr, x - shift, w, sigma, free))


def pose_std(pr: Projection, turned: np.ndarray, w: np.ndarray, sigma: float, free: int
             ) -> tuple[float | None, float | None, float | None]:
    """σ·√diag((JᵀWJ)⁻¹) of the fitted pose parameters (α, t_x, t_y); None for the held ones
    (``turned``: the points rotated, before the shift)."""
    if free == 0:
        return None, None, None
    cols = [(np.conj(pr.normal) * 1j * turned).real] + ([pr.normal.real, pr.normal.imag] if free == 3 else [])
    jac = np.column_stack(cols)
    std = [float(v) for v in sigma * np.sqrt(np.diag(np.linalg.pinv((jac * w[:, None]).T @ jac)))]
    return (std[0], std[1], std[2]) if free == 3 else (std[0], None, None)

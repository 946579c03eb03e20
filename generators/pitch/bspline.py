"""The pitch curve as a periodic B-spline fitted to the true pitch curve
(``pitch.representation = "bspline"``), and the profile as its roller offset.

The true pitch curve P(θ) = Rot(−δθ)(e, s₀ + s(θ)) is sampled densely and fitted by least
squares with a periodic quintic B-spline C(θ) whose knots are cam angles: the motion-segment
boundaries are knots, and ``pitch.segments`` (or the count that meets ``pitch.tolerance``) knot
spans are shared among the motion segments in proportion to their spans.  Its accuracy is the
paper's measure (as the PH curve's): max |s_actual − s| where s_actual comes from the follower
line meeting C (paper Eq. 13).

The exact roller offset of C is not a polynomial curve.  Kernels that have offset curves build
it exactly (OCCT: ``Geom_OffsetCurve``, :mod:`cam_workbench.kernel.solids`); for everything else
(STEP, DXF, checks) :func:`fit_offset` gives a B-spline fitted to it, and the error of both
against the true profile is measured (:func:`profile_errors`).

Neutral curves (:class:`~cam_workbench.generators.curves.nurbs.NurbsCurve`) are parametrised by v = θ·N/(2π) on
[0, N], N the number of knot spans, so that "segment k, ξ" ↔ v = k + ξ as for the PH spline
(a linear change of the knots leaves a B-spline's shape unchanged).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from math import factorial
from typing import Callable

import numpy as np

from ..curves.basis import basis_derivatives
from ..errors import SolveError, SpecError
from ..followers.base import Follower
from ..kinds import follower_of, register_pitch
from ..curves.bezier import BezierChain, bernstein_from_power
from .contact import Contact
from ..motion.program import MotionProgram
from ..curves.nurbs import NurbsCurve
from ..spec.model import CamSpec
from ..spec.pitch import DEFAULT_SEGMENTS, MAX_SEGMENTS
from .queries import PitchQueries

TWO_PI = 2.0 * np.pi
DEGREE = 5
FIT_SAMPLES_PER_SPAN = 12
MAX_SPANS = MAX_SEGMENTS


# ---- periodic B-splines ------------------------------------------------------------------
@dataclass(frozen=True)
class PeriodicBSpline:
    """A closed periodic B-spline C(u), u ∈ [0, period), with N knot spans and N complex poles.

    The knot vector is the breaks extended periodically, t_j = b_(j mod N) + period·⌊j/N⌋;
    pole i belongs to the basis function starting at t_i (so C(u) on span k uses poles
    k − p … k, indices modulo N)."""

    degree: int
    breaks: np.ndarray          # (N+1,) 0 = b_0 < … < b_N = period
    poles: np.ndarray           # (N,) complex

    @property
    def n_spans(self) -> int:
        return int(self.breaks.shape[0] - 1)

    @property
    def period(self) -> float:
        return float(self.breaks[-1] - self.breaks[0])

    @property
    def extended_knots(self) -> np.ndarray:
        """t_{−p} … t_{N+p} (N + 2p + 1 knots)."""
        n, p, b = self.n_spans, self.degree, self.breaks
        j = np.arange(-p, n + p + 1)
        return b[j % n] + self.period * np.floor_divide(j, n)

    def basis(self, u: np.ndarray, nder: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """(pole indices (len, p+1) modulo N, basis derivatives (len, nder+1, p+1)) at u."""
        u = np.mod(np.asarray(u, dtype=float), self.period) + self.breaks[0]
        span, ders = basis_derivatives(self.extended_knots, self.degree, u, nder)
        idx = (span[:, None] - self.degree + np.arange(self.degree + 1)[None, :]) % self.n_spans
        return idx, ders

    def evaluate(self, u: np.ndarray, nder: int = 0) -> list[np.ndarray]:
        """[C(u), C′(u), …] up to ``nder`` derivatives (complex), vectorised: Horner on the
        per-span polynomials of :attr:`_power_form`."""
        u = np.mod(np.atleast_1d(np.asarray(u, dtype=float)) - self.breaks[0], self.period) + self.breaks[0]
        b = self.breaks
        k = np.clip(np.searchsorted(b, u, side="right") - 1, 0, self.n_spans - 1)
        h = b[k + 1] - b[k]
        t = (u - b[k]) / h
        coeffs = self._power_form[k]                       # (len, p+1), lowest power first
        out = []
        for d in range(nder + 1):
            c = coeffs[:, d:]
            if d:
                c = c * _falling(np.arange(d, self.degree + 1), d)[None, :]
            val = c[:, -1].copy()
            for j in range(c.shape[1] - 2, -1, -1):
                val = val * t + c[:, j]
            out.append(val / h**d)
        return out

    @cached_property
    def _power_form(self) -> np.ndarray:
        """(N, p+1) complex monomial coefficients of each span in t = (u − b_k)/(b_{k+1} − b_k):
        the Taylor coefficients C^(d)(b_k)·h_k^d/d! from the basis derivatives at b_k."""
        p = self.degree
        idx, ders = self.basis(self.breaks[:-1], p)
        taylor = np.einsum("ndj,nj->nd", ders, self.poles[idx])            # C^(d)(b_k)
        h = np.diff(self.breaks)[:, None] ** np.arange(p + 1)[None, :]
        return taylor * h / np.array([factorial(d) for d in range(p + 1)])[None, :]

    def to_nurbs(self, scale: float = 1.0) -> NurbsCurve:
        """The same closed curve as a clamped (non-periodic) NURBS on [0, period]·scale —
        exactly: the seam is clamped by knot insertion (Boehm), interior knots stay simple."""
        p, n = self.degree, self.n_spans
        knots = self.extended_knots
        ctrl = self.poles[np.arange(n + p) % n]
        b0, b1 = self.breaks[0], self.breaks[-1]
        for u in (b0, b1):
            for _ in range(p):
                knots, ctrl = insert_knot(knots, ctrl, p, u)
        # keep the knots [b0]*(p+1) … [b1]*(p+1) and their poles
        first = int(np.searchsorted(knots, b0, side="left"))
        last = int(np.searchsorted(knots, b1, side="right"))
        kv = knots[first:last]
        poles = ctrl[first:first + len(kv) - p - 1]
        return NurbsCurve(p, kv * scale, np.column_stack([poles.real, poles.imag]), np.ones(len(poles)))


def _falling(n: np.ndarray, d: int) -> np.ndarray:
    """n (n − 1) … (n − d + 1)."""
    out = np.ones_like(n, dtype=float)
    for i in range(d):
        out = out * (n - i)
    return out


def insert_knot(knots: np.ndarray, ctrl: np.ndarray, p: int, u: float) -> tuple[np.ndarray, np.ndarray]:
    """Boehm's insertion of the knot u once (Piegl & Tiller A5.1, one insertion), into the
    span that ends at u when u is already a knot (so the last span's end works too)."""
    k = int(np.searchsorted(knots, u, side="left") - 1)
    new = np.empty(ctrl.shape[0] + 1, dtype=ctrl.dtype)
    new[: k - p + 1] = ctrl[: k - p + 1]
    new[k + 1:] = ctrl[k:]
    i = np.arange(k - p + 1, k + 1)
    denom = knots[i + p] - knots[i]
    a = np.where(denom > 0, (u - knots[i]) / np.where(denom > 0, denom, 1.0), 0.0)
    new[i] = a * ctrl[i] + (1 - a) * ctrl[i - 1]
    return np.insert(knots, k + 1, u), new


def least_squares_periodic(breaks: np.ndarray, degree: int, u: np.ndarray, data: np.ndarray,
                           ) -> PeriodicBSpline:
    """The periodic B-spline on ``breaks`` minimising Σ|C(u_s) − data_s|² (sparse normal
    equations: the matrix is cyclic banded)."""
    import scipy.sparse as sp  # deferred: scipy.sparse, a B-spline pitch curve's fit alone
    from scipy.sparse.linalg import spsolve  # deferred: scipy.sparse

    shell = PeriodicBSpline(degree, breaks, np.zeros(len(breaks) - 1, dtype=complex))
    idx, ders = shell.basis(u, 0)
    n = shell.n_spans
    rows = np.repeat(np.arange(u.shape[0]), degree + 1)
    a = sp.csr_matrix((ders[:, 0, :].ravel(), (rows, idx.ravel())), shape=(u.shape[0], n))
    ata = (a.T @ a).tocsc()
    rhs = a.T @ np.column_stack([data.real, data.imag])
    sol = spsolve(ata, rhs)
    sol = np.asarray(sol).reshape(n, 2)
    return PeriodicBSpline(degree, breaks, sol[:, 0] + 1j * sol[:, 1])


# ---- the pitch curve -------------------------------------------------------------------
def knot_breaks(program: MotionProgram, spans: int) -> np.ndarray:
    """Knot cam angles [rad]: every motion-segment boundary, and ``spans`` spans shared
    among the segments in proportion to their angle (largest remainder, ≥ 1 each), equally
    spaced inside each segment."""
    frac = program.spans / TWO_PI * spans
    counts = np.maximum(np.floor(frac).astype(int), 1)
    while counts.sum() < spans:
        k = int(np.argmax(frac - counts))
        counts[k] += 1
    while counts.sum() > spans and counts.max() > 1:
        k = int(np.argmax(np.where(counts > 1, counts - frac, -np.inf)))
        counts[k] -= 1
    parts = [program.starts[k] + program.spans[k] * np.arange(c) / c for k, c in enumerate(counts)]
    return np.append(np.concatenate(parts), TWO_PI)


def true_pitch(program: MotionProgram, geometry: Follower, theta: np.ndarray) -> np.ndarray:
    """The design curve of the design intent (complex, cam frame): the pitch curve P(θ), or a
    flat face's contact points."""
    return geometry.points(theta, program.evaluate(theta))


def fit_pitch(program: MotionProgram, geometry: Follower, spans: int) -> PeriodicBSpline:
    """Least-squares periodic quintic fit of the true pitch curve on :func:`knot_breaks`,
    12 samples per knot span."""
    breaks = knot_breaks(program, spans)
    fr = (np.arange(FIT_SAMPLES_PER_SPAN) + 0.5) / FIT_SAMPLES_PER_SPAN
    u = (breaks[:-1, None] + np.diff(breaks)[:, None] * fr[None, :]).ravel()
    u = np.concatenate([u, breaks[:-1]])
    return least_squares_periodic(breaks, DEGREE, u, true_pitch(program, geometry, u))


class _SegmentView:
    """The fitted curve seen through (segment, ξ) pairs, segment k ↔ θ ∈ 2π[k, k+1]/N — the
    interface of :class:`~cam_workbench.generators.curves.ph_spline.PHSpline` that the geometry checks use."""

    iterations = None
    residual = None
    closing_sign = None

    def __init__(self, curve: PeriodicBSpline):
        self.curve = curve
        self.M = curve.n_spans

    def _u(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        return (np.asarray(seg) + np.asarray(xi, dtype=float)) * TWO_PI / self.M

    def point(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        return self.curve.evaluate(self._u(seg, xi))[0]

    def first_derivative(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        return self.curve.evaluate(self._u(seg, xi), 1)[1] * TWO_PI / self.M

    def curvature(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        """Signed curvature (+ turning left)."""
        _, d1, d2 = self.curve.evaluate(self._u(seg, xi), 2)
        return (np.conj(d1) * d2).imag / np.abs(d1) ** 3

    @property
    def arc_length(self) -> float:
        xg, wg = np.polynomial.legendre.leggauss(16)
        b = self.curve.breaks
        u = (0.5 * np.diff(b)[:, None] * (xg[None, :] + 1) + b[:-1, None]).ravel()
        w = (0.5 * np.diff(b)[:, None] * wg[None, :]).ravel()
        return float(np.sum(np.abs(self.curve.evaluate(u, 1)[1]) * w))


@register_pitch
@dataclass(frozen=True)
class BSplinePitchCurve(PitchQueries):
    """A fitted periodic B-spline pitch curve, queried like :class:`~cam_workbench.generators.pitch.PitchCurve`."""

    curve: PeriodicBSpline
    program: MotionProgram
    follower: Follower
    spline: _SegmentView = field(init=False, repr=False)
    #: pitch.representation
    representation = "bspline"
    #: no exact offsets: the profile is a fitted offset, its error measured
    exact = False
    #: the representation in words
    words = "periodic B-spline"

    def __post_init__(self) -> None:
        object.__setattr__(self, "spline", _SegmentView(self.curve))

    @property
    def M(self) -> int:
        return self.curve.n_spans

    @property
    def angles(self) -> np.ndarray:
        """Knot cam angles [rad] (the B-spline's "junctions")."""
        return self.curve.breaks[:-1]

    @property
    def junction_parameters(self) -> np.ndarray:
        """Parameters of the knot points on the neutral curves (:meth:`to_nurbs`)."""
        return self.angles * self.parameter_scale

    @property
    def parameter_scale(self) -> float:
        """v = θ·scale: the neutral curves' parameter (see the module docstring)."""
        return self.M / TWO_PI

    def to_nurbs(self) -> NurbsCurve:
        return self.curve.to_nurbs(self.parameter_scale)

    @property
    def exact_offsets(self) -> bool:
        """Offsets of a general B-spline are not rational: outputs use fitted offsets."""
        return False

    @cached_property
    def segments(self) -> BezierChain:
        """The curve as one Bézier segment per knot span (exact: the spans' polynomials),
        segment k bounded by :attr:`solver_angles` k and k + 1."""
        return BezierChain(bernstein_from_power(self.curve._power_form))

    @cached_property
    def solver_angles(self) -> np.ndarray:
        """(M,) cam angles [rad] at which the follower touches the knot points (closed form,
        as :meth:`cam_angle_of_point`), kept within half a turn of the knot angles — the fit
        does not pass exactly through the true points, so these differ from :attr:`angles` by
        the fit's error."""
        ctrl = self.segments.ctrl
        q = ctrl[:, 0]
        dq = ctrl[:, 1] - ctrl[:, 0]
        cross = self.follower.cam_angle_of(q, dq)
        b = self.angles
        return b + (np.mod(cross - b + np.pi, TWO_PI) - np.pi)

    def contact(self, theta: np.ndarray, tol: float = 1e-14, max_iter: int = 30) -> Contact:
        """Paper Eq. 13 (generalised to the follower kind) on the B-spline, Newton from u = θ
        (the fit's parameter is the cam angle, so the root is close)."""
        theta = np.asarray(theta, dtype=float)
        rot = np.exp(1j * self.follower.sense * theta)
        fol = self.follower
        u = theta.copy()
        for _ in range(max_iter):
            c, d, dd = self.curve.evaluate(u, 2)
            g, dg, _ = fol.contact_residual(rot * c, rot * d, rot * dd)
            step = g / dg
            u = u - np.clip(step, -0.1, 0.1)
            if np.max(np.abs(step)) < tol:
                break
        else:
            bad = int(np.argmax(np.abs(step)))
            raise SolveError(f"no single contact between the follower and the B-spline pitch curve near cam angle "
                             f"{np.rad2deg(theta[bad]) % 360:.3f}° (Newton did not converge)")
        c, d = self.curve.evaluate(u, 1)
        v = np.mod(u, TWO_PI) * self.parameter_scale
        seg = np.minimum(v.astype(int), self.M - 1)
        return Contact(seg=seg, xi=v - seg, point=c, Y=(rot * c).imag, iterations=0,
                       lift=fol.lift_at(rot * c, rot * d))



def build_bspline_pitch(spec: CamSpec, progress: Callable[[int, float], None] | None = None
                        ) -> BSplinePitchCurve:
    """The spec's B-spline pitch curve: ``pitch.segments`` knot spans (default 60), or the
    fewest spans whose max deviation is ≤ ``pitch.tolerance`` (doubling, then bisection:
    the deviation falls steadily with the span count, unlike the PH interpolant's)."""
    program = MotionProgram.from_spec(spec)
    geometry = follower_of(spec)
    n_min = max(8, len(program.starts))

    def make(n: int) -> BSplinePitchCurve:
        return BSplinePitchCurve(fit_pitch(program, geometry, n), program, geometry)

    tol = spec.pitch.tolerance
    if tol is None:
        return make(max(spec.pitch.segments or DEFAULT_SEGMENTS, n_min))
    lo, hi = n_min - 1, n_min
    while True:
        pc = make(hi)
        dev = pc.max_deviation()[0]
        if progress is not None:
            progress(hi, dev)
        if dev <= tol:
            break
        lo, hi = hi, 2 * hi
        if hi > MAX_SPANS:
            raise SpecError("pitch.tolerance", f"no B-spline with up to {MAX_SPANS} spans reaches {tol:g}")
    best = pc
    while hi - lo > 1:
        mid = (lo + hi) // 2
        pc = make(mid)
        dev = pc.max_deviation()[0]
        if progress is not None:
            progress(mid, dev)
        if dev <= tol:
            hi, best = mid, pc
        else:
            lo = mid
    return best


# ---- the roller offset --------------------------------------------------------------------
def offset_points(curve: PeriodicBSpline, u: np.ndarray, distance: float) -> np.ndarray:
    """C(u) + d·n(u), n the unit left normal of C (d > 0: left of the direction of travel)."""
    c, d = curve.evaluate(u, 1)
    return c + distance * 1j * d / np.abs(d)


def fit_offset(curve: PeriodicBSpline, distance: float, refine: int = 1) -> PeriodicBSpline:
    """A periodic quintic B-spline fitted (least squares) to the exact offset of ``curve`` at
    signed ``distance``, on the same knots subdivided ``refine`` times."""
    b = curve.breaks
    fine = np.append((b[:-1, None] + np.diff(b)[:, None] * (np.arange(refine) / refine)[None, :]).ravel(), b[-1])
    fr = (np.arange(FIT_SAMPLES_PER_SPAN) + 0.5) / FIT_SAMPLES_PER_SPAN
    u = np.concatenate([(fine[:-1, None] + np.diff(fine)[:, None] * fr[None, :]).ravel(), fine[:-1]])
    return least_squares_periodic(fine, curve.degree, u, offset_points(curve, u, distance))


def true_profile(program: MotionProgram, geometry: Follower, roller_radius: float,
                 theta: np.ndarray, nder: int = 0) -> list[np.ndarray]:
    """The true cam profile Q(θ) = C(θ) + r·(inward unit normal) of the design curve C (the pitch
    curve; r the roller radius, 0 for a knife edge or a flat face) and, with ``nder`` = 1, Q′(θ),
    from the follower's exact C′, C″."""
    k = program.evaluate(theta)
    d = geometry.sense
    p, dp, ddp = geometry.derivatives(theta, k, 2)
    speed = np.abs(dp)
    t = dp / speed
    inward = -1j * d * t
    q = p + roller_radius * inward
    if nder == 0:
        return [q]
    # d(t)/dθ = i κ_s |P′| t with signed curvature κ_s = Im(conj(P′)P″)/|P′|³
    kappa = (np.conj(dp) * ddp).imag / speed**3
    dq = dp + roller_radius * (-1j * d) * (1j * kappa * speed * t)
    return [q, dq]


def distance_to_true_profile(points: np.ndarray, theta0: np.ndarray, program: MotionProgram,
                             geometry: Follower, roller_radius: float, iterations: int = 8
                             ) -> np.ndarray:
    """Distance from each point to the true profile: the foot point Q(θ) with
    (Q(θ) − X)·Q′(θ) = 0 found by Gauss–Newton from θ₀ (vectorised)."""
    th = np.asarray(theta0, dtype=float).copy()
    for _ in range(iterations):
        q, dq = true_profile(program, geometry, roller_radius, th, 1)
        step = ((q - points) * np.conj(dq)).real / np.abs(dq) ** 2
        th = th - np.clip(step, -0.05, 0.05)
    q = true_profile(program, geometry, roller_radius, th)[0]
    return np.abs(q - points)


def distance_to_offset(points: np.ndarray, u0: np.ndarray, curve: PeriodicBSpline, distance: float,
                       iterations: int = 8) -> np.ndarray:
    """Distance from each point to the exact offset O(u) = C(u) + d·i·C′/|C′| of ``curve``: foot
    points by Gauss–Newton from u₀, with O′ = C′·(1 − d·κ) (κ the signed curvature of C)."""
    u = np.asarray(u0, dtype=float).copy()
    for _ in range(iterations):
        c, d1, d2 = curve.evaluate(u, 2)
        speed = np.abs(d1)
        kappa = (np.conj(d1) * d2).imag / speed**3
        o = c + distance * 1j * d1 / speed
        do = d1 * (1 - distance * kappa)
        u = u - np.clip(((o - points) * np.conj(do)).real / np.abs(do) ** 2, -0.05, 0.05)
    return np.abs(offset_points(curve, u, distance) - points)


@dataclass(frozen=True)
class ProfileErrors:
    """Max distance from the true profile (the exact roller offset of the true pitch curve) of
    the kernel's exact offset of the fitted pitch curve and of the fitted offset B-spline."""

    exact_offset: float
    exact_offset_at_deg: float
    fitted_offset: float
    fitted_offset_at_deg: float
    fitted_vs_exact_offset: float


def profile_errors(pitch: BSplinePitchCurve, profile_fit: PeriodicBSpline, roller_radius: float,
                   inward: float, samples_per_span: int = 24) -> ProfileErrors:
    """Measure the profile errors on ``samples_per_span`` points per knot span of the pitch fit
    (ends included) and per span of the profile fit."""
    c = pitch.curve
    fr = np.arange(samples_per_span) / samples_per_span
    u = (c.breaks[:-1, None] + np.diff(c.breaks)[:, None] * fr[None, :]).ravel()
    exact = offset_points(c, u, inward)
    d_exact = distance_to_true_profile(exact, u, pitch.program, pitch.geometry, roller_radius)
    b = profile_fit.breaks
    uf = (b[:-1, None] + np.diff(b)[:, None] * fr[None, :]).ravel()
    fitted = profile_fit.evaluate(uf)[0]
    d_fit = distance_to_true_profile(fitted, uf, pitch.program, pitch.geometry, roller_radius)
    d_between = distance_to_offset(fitted, uf, c, inward)
    i, j = int(np.argmax(d_exact)), int(np.argmax(d_fit))
    return ProfileErrors(float(d_exact[i]), float(np.rad2deg(u[i]) % 360), float(d_fit[j]),
                         float(np.rad2deg(uf[j]) % 360), float(np.max(d_between)))


def built_profile_error(profile: NurbsCurve, pitch, roller_radius: float, per_span: int = 16
                        ) -> tuple[float, float]:
    """(max distance of a built profile NURBS from the true profile, cam angle [deg] there),
    for either pitch representation: profile parameter v ↔ pitch (segment ⌊v⌋, ξ = v − ⌊v⌋),
    whose cam angle starts the foot-point search."""
    v, pts = profile.sample(per_span)
    z = pts[:, 0] + 1j * pts[:, 1]
    seg = np.minimum(v.astype(int), pitch.M - 1)
    theta0 = np.deg2rad(pitch.cam_angle_at(seg, v - seg))
    d = distance_to_true_profile(z, theta0, pitch.program, pitch.geometry, roller_radius)
    k = int(np.argmax(d))
    return float(d[k]), float(np.rad2deg(theta0[k]) % 360.0)


def bezier_form(curve: NurbsCurve) -> NurbsCurve:
    """The same curve with every interior knot raised to multiplicity = degree (Boehm knot
    insertion, exact): a chain of Bézier spans, which kernels integrate exactly and STEP
    writes span by span (``NurbsCurve.bezier_pieces`` then splits it without refitting)."""
    p = curve.degree
    knots = curve.knots.astype(float)
    hom = np.column_stack([curve.poles * curve.weights[:, None], curve.weights])
    for u in np.unique(knots[p + 1:-p - 1]):
        while np.count_nonzero(knots == u) < p:
            k = int(np.searchsorted(knots, u, side="right") - 1)
            i = np.arange(k - p + 1, k + 1)
            a = np.where(knots[i + p] > knots[i], (u - knots[i]) / (knots[i + p] - knots[i]), 0.0)
            new = np.empty((hom.shape[0] + 1, 3))
            new[: k - p + 1] = hom[: k - p + 1]
            new[k + 1:] = hom[k:]
            new[i] = a[:, None] * hom[i] + (1 - a[:, None]) * hom[i - 1]
            hom = new
            knots = np.insert(knots, k + 1, u)
    w = hom[:, 2]
    return NurbsCurve(p, knots, hom[:, :2] / w[:, None], w)

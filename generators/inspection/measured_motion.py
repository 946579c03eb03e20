"""What the follower does on the measured part: its s, v, a from the measured profile.

1. A smoothing fit: a periodic quintic B-spline δ(u) on uniform knots of the profile parameter
   (j knot spans in every span of the design curve, so that each piece of the curve sees one
   polynomial of δ), fitted by least squares to the inliers' deviations; a weak third-difference
   penalty keeps it defined across gaps in the data.  Its knot spacing sets the shortest wave it
   follows: j is chosen by generalised cross-validation up to a shortest wave the caller allows.
2. The measured profile Q_m(u) = Q(u) + δ(u)·N(u) (Q the exact profile, N its outward normal),
   and the follower's design curve on it, D_m = Q_m + r·N_m, with N_m the measured profile's own
   normal (r = the design's profile inset: the roller radius; 0 for a knife edge or a flat face).
   Q_m′ = Q′ + δ′N + δN′, N′ = −side·κ|Q′|T (κ the signed curvature, T the unit tangent).
3. The design's own contact solve (paper Eq. 13 generalised to the follower kind:
   :meth:`Follower.contact_solver` on a chain of Bézier segments, as :meth:`PitchCurve.solver`)
   on the measured design curve written as such a chain: every segment of the design's pitch
   curve split exactly into j pieces (de Casteljau), raised to degree 9, plus the change
   D_m − D interpolated by a degree-9 polynomial at Chebyshev–Lobatto nodes on each piece
   (D_m − D is analytic there: one polynomial of δ, one of the design curve).  Δs(θ) is that lift
   minus the design's own (:meth:`PitchQueries.actual_displacement`);
   :attr:`MeasuredMotion.design_reproduction` is the same chain built with δ = 0 against the
   design's own solve.
4. Δv = ω·Δs′, Δa = ω²·Δs″ by central differences on a uniform grid of cam angles; the measured
   motion is the designed one (the motion program) plus these.  The design's own pitch-curve
   error (report.json ``pitch.max_deviation``) is not part of Δs.
"""
from __future__ import annotations

from dataclasses import dataclass
from math import comb
from typing import Any

import numpy as np

from ..curves.bezier import BezierChain, bernstein_basis, bernstein_from_power, elevate
from ..pitch.bspline import PeriodicBSpline
from ..pitch.contact import power_coeffs
from ..errors import SpecError
from ..tolerance.sensitivity import moved_design_curve
from .registration import ProfileProjector

TWO_PI = 2.0 * np.pi
DEGREE = 5
#: the shortest wave the smoothing fit follows by default [deg of the profile parameter's turn]
DEFAULT_WAVELENGTH_DEG = 6.0
#: knot spans of the smoothing spline per shortest wavelength
SPANS_PER_WAVE = 4
#: the smoothing fit needs this many points per knot span, at least
POINTS_PER_SPAN = 4
#: degree of the measured design curve's pieces
CHAIN_DEGREE = 9
#: cam angles of the motion grid
MOTION_SAMPLES = 8192
#: the smoothing fit's third-difference penalty, relative to the normal matrix's mean diagonal
PENALTY = 1e-6


@dataclass(frozen=True)
class SmoothedDeviation:
    """δ(u): the smoothing fit of the deviations over the profile parameter (spec lengths)."""

    spline: PeriodicBSpline
    #: knot spans in each segment of the design curve
    pieces: int
    #: the shortest wave it follows [deg]: SPANS_PER_WAVE knot spans
    wavelength_deg: float
    #: the shortest wave it was allowed to follow [deg] (``wavelength_deg`` of the call, as spans go)
    shortest_allowed_deg: float
    points: int
    rms_residual: float

    @property
    def spans(self) -> int:
        return self.spline.n_spans

    def __call__(self, u: np.ndarray, nder: int = 0) -> list[np.ndarray]:
        """[δ, δ′, …] at profile parameters ``u``."""
        return [v.real for v in self.spline.evaluate(u, nder)]


def smooth_deviation(u: np.ndarray, d: np.ndarray, lo: float, period: float, segments: int,
                     wavelength_deg: float = DEFAULT_WAVELENGTH_DEG) -> SmoothedDeviation:
    """The periodic quintic smoothing fit of deviations ``d`` at profile parameters ``u`` (see the
    module docstring): j knot spans in each of the design curve's ``segments``, j chosen by
    generalised cross-validation (GCV = n·RSS/(n − K)², K = j·segments coefficients; Craven & Wahba
    1979) among 1 … the smallest j giving SPANS_PER_WAVE spans per ``wavelength_deg`` (and at most
    one span per POINTS_PER_SPAN points): noise-free waves get every span allowed, noise fewer.

    Raises:
        SpecError: ``wavelength_deg`` not in (0, 360], or too few points for the fit.
    """
    if not (np.isfinite(wavelength_deg) and 0 < wavelength_deg <= 360):
        raise SpecError("wavelength", f"must be in (0, 360] degrees, got {wavelength_deg!r}")
    wanted = int(np.ceil(SPANS_PER_WAVE * 360.0 / wavelength_deg / segments))
    most = min(wanted, len(d) // (POINTS_PER_SPAN * segments))
    if most < 1:
        raise SpecError("points", f"{len(d)} inlying points are too few for the smoothing fit over the design "
                                  f"curve's {segments} segments (at least {POINTS_PER_SPAN * segments})")
    fits = [_fit(u, d, lo, period, j * segments) for j in range(1, most + 1)]
    n = len(d)
    gcv = [n * rss / (n - spline.n_spans) ** 2 for spline, rss in fits]
    j = int(np.argmin(gcv)) + 1
    spline, rss = fits[j - 1]
    return SmoothedDeviation(spline, j, SPANS_PER_WAVE * 360.0 / spline.n_spans, SPANS_PER_WAVE * 360.0 / (most * segments),
                             int(n), float(np.sqrt(rss / n)))


def _fit(u: np.ndarray, d: np.ndarray, lo: float, period: float, spans: int) -> tuple[PeriodicBSpline, float]:
    """(the penalised least-squares periodic quintic on ``spans`` uniform spans, its residual sum of squares)."""
    breaks = lo + period * np.arange(spans + 1) / spans
    shell = PeriodicBSpline(DEGREE, breaks, np.zeros(spans, dtype=complex))
    idx, ders = shell.basis(u, 0)
    b = ders[:, 0, :]
    ata = np.zeros((spans, spans))
    rows_idx, cols_idx = np.broadcast_arrays(idx[:, :, None], idx[:, None, :])
    np.add.at(ata, (rows_idx, cols_idx), b[:, :, None] * b[:, None, :])
    rhs = np.bincount(idx.ravel(), weights=(b * d[:, None]).ravel(), minlength=spans)
    # periodic third differences: a weak penalty that only matters where the data leave a gap
    diff = np.zeros((spans, spans))
    rows = np.arange(spans)
    for k, c in enumerate((-1.0, 3.0, -3.0, 1.0)):
        diff[rows, (rows + k) % spans] += c
    lam = PENALTY * float(np.mean(np.diag(ata)))
    coef = np.linalg.solve(ata + lam * diff.T @ diff, rhs)
    res = d - np.einsum("nk,nk->n", b, coef[idx])
    return PeriodicBSpline(DEGREE, breaks, coef.astype(complex)), float(np.sum(res * res))


@dataclass(frozen=True)
class MeasuredMotion:
    """The follower's motion on the measured part against the designed motion.

    Attributes:
        theta: (n,) cam angles [rad], uniform over the turn.
        designed: (s, s′, s″) of the motion program there [lift units, per rad].
        error: (Δs, Δs′, Δs″) the measured part adds [lift units, per rad].
        omega: cam speed [rad/s].
        smoothing: the deviation's smoothing fit.
        curve_spans: Bézier pieces of the measured design curve.
        design_reproduction: max |lift on the chain built with δ = 0 − the design's own lift| [lift units].
        designed_peak: the motion program's largest |v| and |a| at ω (``MotionProgram.maxima``: report.json's
            ``motion.max_velocity`` and ``max_acceleration``).
    """

    theta: np.ndarray
    designed: tuple[np.ndarray, np.ndarray, np.ndarray]
    error: tuple[np.ndarray, np.ndarray, np.ndarray]
    omega: float
    smoothing: SmoothedDeviation
    curve_spans: int
    design_reproduction: float
    designed_peak: dict[str, float]

    def series(self) -> dict[str, np.ndarray]:
        """θ [deg] and the designed and measured s, v, a at the cam's speed (lift units, /s, /s²)."""
        w = self.omega
        (s, ds, d2s), (e, de, d2e) = self.designed, self.error
        return {"theta_deg": np.rad2deg(self.theta), "s": s, "v": w * ds, "a": w * w * d2s,
                "s_measured": s + e, "v_measured": w * (ds + de), "a_measured": w * w * (d2s + d2e),
                "ds": e, "dv": w * de, "da": w * w * d2e}

    def summary(self, lift_unit: str) -> dict[str, Any]:
        """The numbers of inspection.json's ``motion`` section (``lift_unit``: "mm", "in" or "deg")."""
        sr = self.series()
        deg = sr["theta_deg"]

        def peak(key: str) -> dict[str, float]:
            k = int(np.argmax(np.abs(sr[key])))
            return {"max_abs": float(abs(sr[key][k])), "at_deg": float(deg[k])}

        designed_a = self.designed_peak["acceleration"]
        da = peak("da")
        return {
            "speed_rpm": float(self.omega * 60.0 / TWO_PI), "omega_rad_s": float(self.omega),
            "units": {"displacement": lift_unit, "velocity": f"{lift_unit}/s", "acceleration": f"{lift_unit}/s²"},
            "samples": int(len(self.theta)),
            "smoothing": {"spans": self.smoothing.spans, "wavelength_deg": self.smoothing.wavelength_deg,
                          "shortest_allowed_deg": self.smoothing.shortest_allowed_deg,
                          "points": self.smoothing.points, "rms_residual": self.smoothing.rms_residual},
            "curve_spans": self.curve_spans, "design_reproduction": self.design_reproduction,
            "displacement_error": peak("ds"), "velocity_error": peak("dv"),
            "acceleration_error": {**da, "fraction_of_designed_peak": da["max_abs"] / designed_a if designed_a > 0 else None},
            "designed_peak": {"velocity": self.designed_peak["velocity"], "acceleration": designed_a},
            "measured_peak": {"velocity": peak("v_measured")["max_abs"], "acceleration": peak("a_measured")["max_abs"],
                              "acceleration_at_deg": peak("a_measured")["at_deg"]},
        }


def contact_angles(design: Any, u: np.ndarray) -> np.ndarray:
    """Cam angles [rad, 0..2π) at which the follower touches the profile's points at parameters
    ``u`` (profile and design curve share the parameter: span k ↔ segment k); the inverse of
    :func:`contact_parameters`."""
    seg = np.minimum(np.floor(u).astype(int), design.pitch.M - 1)
    return np.deg2rad(design.pitch.cam_angle_at(seg, u - seg))


def contact_parameters(design: Any, theta: np.ndarray) -> np.ndarray:
    """Profile parameters u of the points the follower touches at cam angles θ [rad]: segment +
    ξ of the design's own contact solve (paper Eq. 13); the inverse of :func:`contact_angles`."""
    c = design.pitch.contact(np.asarray(theta, dtype=float))
    return c.seg + c.xi


def design_curve_points(projector: ProfileProjector, u: np.ndarray, inset: float,
                        delta: list[np.ndarray] | None) -> np.ndarray:
    """The follower's design curve over the (measured) profile at parameters ``u``: Q_m + r·N_m
    (``delta`` = [δ, δ′] at u, None: the exact profile; :func:`moved_design_curve`)."""
    q, dq, d2q = projector.derivatives(u)
    if delta is None:
        return q + inset * projector.side * 1j * dq / np.abs(dq)
    speed = np.abs(dq)
    t = dq / speed
    kappa = (np.conj(dq) * d2q).imag / speed**3
    n = projector.side * 1j * t
    dn = -projector.side * kappa * speed * t
    return moved_design_curve(q, dq, n, dn, delta[0], delta[1], inset, projector.side)


def split_segments(ctrl: np.ndarray, pieces: int) -> np.ndarray:
    """Bézier segments (M, n+1) split exactly into ``pieces`` equal parameter pieces each:
    (M·pieces, n+1), piece i of segment k the curve on ξ ∈ [i, i+1]/pieces, reparametrised to [0, 1]."""
    n = ctrl.shape[1] - 1
    power = power_coeffs(ctrl)                                      # (M, n+1), lowest first
    h = 1.0 / pieces
    a = np.arange(pieces) * h
    # ξ = a + h·t: c′_m = Σ_{k ≥ m} c_k·C(k, m)·a^(k−m)·h^m
    k, m = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
    binom = np.vectorize(comb)(k, m) * (k >= m)
    mats = binom[None] * np.where(k >= m, a[:, None, None] ** np.maximum(k - m, 0)[None], 0.0) * h ** m[None]
    sub = np.einsum("sk,ikm->sim", power, mats).reshape(-1, n + 1)
    return bernstein_from_power(sub)


def measured_chain(design: Any, projector: ProfileProjector, smoothing: SmoothedDeviation,
                   with_deviation: bool = True) -> BezierChain:
    """The follower's design curve on the measured profile as a chain of degree-9 Bézier pieces
    (see the module docstring); ``with_deviation`` False: the design's own curve, split alike."""
    j = smoothing.pieces
    base = elevate(split_segments(np.asarray(design.pitch.segments.ctrl, dtype=complex), j), CHAIN_DEGREE)
    if not with_deviation:
        return BezierChain(base)
    t = 0.5 * (1.0 - np.cos(np.pi * np.arange(CHAIN_DEGREE + 1) / CHAIN_DEGREE))   # Chebyshev–Lobatto
    u = (np.arange(base.shape[0])[:, None] + t[None, :]) / j + projector.lo
    flat = u.ravel()
    inset = float(design.profile_inset)
    change = (design_curve_points(projector, flat, inset, smoothing(flat, 1))
              - design_curve_points(projector, flat, inset, None)).reshape(u.shape)
    basis = bernstein_basis(CHAIN_DEGREE, t)                        # (nodes, n+1)
    return BezierChain(base + np.linalg.solve(basis, change.T).T)


def chain_angles(design: Any, chain: BezierChain, pieces: int) -> np.ndarray:
    """Cam angles [rad] at which the follower touches the chain's piece starts (closed form,
    :meth:`Follower.cam_angle_of`), kept within half a turn of the design's junction angles
    interpolated — as :attr:`PitchCurve.solver_angles`."""
    a = np.asarray(design.pitch.solver_angles, dtype=float)
    nxt = np.append(a[1:], a[0] + TWO_PI)
    b = (a[:, None] + (nxt - a)[:, None] * (np.arange(pieces) / pieces)[None, :]).ravel()
    cross = design.follower.cam_angle_of(chain.ctrl[:, 0], chain.ctrl[:, 1] - chain.ctrl[:, 0])
    return b + (np.mod(cross - b + np.pi, TWO_PI) - np.pi)


def chain_lift(design: Any, chain: BezierChain, pieces: int, theta: np.ndarray) -> np.ndarray:
    """The follower's lift on ``chain`` at cam angles θ: the design's contact solver."""
    return design.follower.contact_solver(chain, chain_angles(design, chain, pieces)).solve(theta).lift


def measured_motion(design: Any, projector: ProfileProjector, smoothing: SmoothedDeviation,
                    samples: int = MOTION_SAMPLES) -> MeasuredMotion:
    """The follower's motion on the profile deviated by ``smoothing`` (see the module docstring)."""
    program = design.program
    j = smoothing.pieces
    theta = TWO_PI * np.arange(samples) / samples
    s_design = design.pitch.actual_displacement(theta)
    chain = measured_chain(design, projector, smoothing)
    e = chain_lift(design, chain, j, theta) - s_design
    reproduction = float(np.max(np.abs(chain_lift(design, measured_chain(design, projector, smoothing, False), j, theta)
                                       - s_design)))
    h = TWO_PI / samples
    de = (np.roll(e, -1) - np.roll(e, 1)) / (2 * h)
    d2e = (np.roll(e, -1) - 2 * e + np.roll(e, 1)) / (h * h)
    k = program.evaluate(theta)
    omega = design.spec.cam.speed_rpm * TWO_PI / 60.0
    return MeasuredMotion(theta, (k.s, k.ds, k.d2s), (e, de, d2e), float(omega), smoothing, chain.M, reproduction,
                          program.maxima(omega))

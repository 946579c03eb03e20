"""How a profile error moves the follower: the first-order kinematic gain, the contact-loss
amplitude past which the follower stops seeing a wave, and the exact perturbed contact solve.

**The error.**  e(θ) is the profile's normal deviation (outward: material added) at the point the
follower touches at cam angle θ in the design — the point whose normal carries the contact at θ.
A wave of n waves per turn is e(θ) = A·cos(nθ + φ).

**First order.**  Moving the profile outward by e along its normal moves the design curve (a
roller's pitch curve, its offset by r_r; a knife's or a face's curve itself) outward by e along the
same normal, to first order in e: the offset of c + e·n is c + (e + r)·n − r·e′·t + O(e²), and the
tangential term slides along the curve.  The follower answers with δq = e·∂q/∂n, and by virtual
work ∂q/∂n is the normal contact force per unit of the follower's generalised load
(:meth:`Follower.force_per_load`: 1/cos φ for a translating knife or roller, 1/(L·cos φ) for an
oscillating arm, 1 for a translating flat face, 1/lever for an oscillating face).  In the spec's
lift units (arm degrees for an oscillating follower)

    δs(θ) = g(θ)·e(θ),   g = force_per_load / lift_scale,
    δa(θ) = ω²·d²(δs)/dθ² = ω²·(g″e + 2g′e′ + g e″).

For the wave, δa = ω²·A·Re(Z_n(θ)·e^{i(nθ+φ)}), Z_n = g″ − n²g + 2in·g′, so the largest |δa| over
the cycle and over the wave's phase is ω²·A·max_θ|Z_n(θ)| — exactly, with no search over φ.

**Where first order stops: contact loss.**  The follower sees the whole wave only while the wavy
profile keeps a curvature the follower can touch everywhere.  With σ the profile's arc length
the normal displacement changes the profile's signed curvature (+ convex) by
δκ = −(κ²e + e_σσ) (first order), and a follower of contact radius r_c (the roller radius; 0 for a
knife edge; ∞ for a flat face, a straight line) follows while κ + δκ > −1/r_c.  For the wave,
κ²e + e_σσ = A·Re(W_n e^{i(nθ+φ)}) with W_n = κ² − n²/σ_θ² − i·n·σ_θθ/σ_θ³ (σ_θ = dσ/dθ), so the
largest amplitude the follower follows at every phase is

    A_max(n) = min_θ (κ + 1/r_c) / |W_n(θ)|,

≈ (λ/2π)²·(κ + 1/r_c) for a short wave of wavelength λ = 2π·σ_θ/n along the profile — the wave's
curvature A(2π/λ)² reaching the roller's plus the profile's own.  Above A_max a roller bridges the
valleys and a face rides on the crests: the follower leaves the profile there and the first-order
δs (and the acceleration it predicts) no longer holds.  A knife edge has no such limit.

**Exact.**  :func:`perturbed_lift` builds the wavy profile, its exact offset by the roller radius,
the closed PH spline through it, and re-runs the design's own contact solve
(:meth:`PitchCurve.actual_displacement`) — the code path an inspection of a measured part uses.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from ..curves.ph_spline import solve_closed_ph_spline
from ..errors import SpecError
from ..followers.base import Follower
from ..motion.program import MotionProgram
from ..pitch.ph import PitchCurve

TWO_PI = 2.0 * np.pi
#: samples of the gain over the cycle (the gain varies at the motion's scale, not the wave's)
GAIN_SAMPLES = 8192
#: step [rad] of the five-point stencil that gives the gain's θ-derivatives (error ∝ h⁴)
STENCIL_STEP = 1e-3


def contact_radius(follower: Follower) -> float:
    """r_c: the radius of the follower's contact surface — the roller radius (0 for a knife edge)
    when the design curve is a pitch curve, ∞ for a flat face (its design curve the profile)."""
    return float(follower.profile_offset) if follower.design_curve == "pitch" else float("inf")


def _stencil(f: Callable[[np.ndarray], np.ndarray], theta: np.ndarray, h: float = STENCIL_STEP
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(f, f′, f″) at θ by the five-point central stencil (f evaluated once on all five offsets)."""
    v = f(theta[None, :] + h * np.arange(-2, 3)[:, None])
    d1 = (v[0] - 8 * v[1] + 8 * v[3] - v[4]) / (12 * h)
    d2 = (-v[0] + 16 * v[1] - 30 * v[2] + 16 * v[3] - v[4]) / (12 * h * h)
    return v[2], d1, d2


@dataclass(frozen=True)
class Sensitivity:
    """The follower's first-order answer to a profile error, sampled over one turn.

    Attributes:
        theta: (N,) uniform cam angles [rad], 0 … 2π (2π excluded).
        gain, gain_d1, gain_d2: g = ∂s/∂e [spec lift units per length] and its θ-derivatives.
        curvature: κ, the profile's signed curvature [1/length] (+ convex) at the contact.
        arc_rate, arc_rate_d1: σ_θ = dσ/dθ [length/rad] of the profile and its θ-derivative.
        contact_radius: r_c [length] (inf for a flat face).
        omega: cam speed [rad/s].
        peak_acceleration: the design's largest |s″|·ω² [lift units/s²].
    """

    theta: np.ndarray
    gain: np.ndarray
    gain_d1: np.ndarray
    gain_d2: np.ndarray
    curvature: np.ndarray
    arc_rate: np.ndarray
    arc_rate_d1: np.ndarray
    contact_radius: float
    omega: float
    peak_acceleration: float

    def follower_error(self, e: np.ndarray, e1: np.ndarray, e2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(δs [lift units], δa [lift units/s²]) at :attr:`theta` for a profile error with values
        e, e′, e″ (θ-derivatives) there."""
        ds = self.gain * e
        da = self.omega**2 * (self.gain_d2 * e + 2 * self.gain_d1 * e1 + self.gain * e2)
        return ds, da

    def wave_error(self, amplitude: float, n: int, phase: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """(δs, δa) of the wave e = A·cos(nθ + φ)."""
        arg = n * self.theta + phase
        c, s = np.cos(arg), np.sin(arg)
        return self.follower_error(amplitude * c, -amplitude * n * s, -amplitude * n * n * c)

    def peak_per_amplitude(self, waves: np.ndarray) -> np.ndarray:
        """ω²·max_θ|Z_n(θ)| for each wave count n: the largest |δa| [lift units/s²] per unit
        amplitude [length] over the cycle and the wave's phase."""
        n = np.asarray(waves, dtype=float)
        out = np.empty(n.shape)
        for lo in range(0, n.size, 32):                  # blocks of wave counts: (32, N) at a time
            m = n.ravel()[lo:lo + 32, None]
            z2 = (self.gain_d2 - m * m * self.gain) ** 2 + (2 * m * self.gain_d1) ** 2
            out.ravel()[lo:lo + 32] = np.sqrt(np.max(z2, axis=1))
        return self.omega**2 * out

    def contact_loss_amplitude(self, waves: np.ndarray) -> np.ndarray:
        """A_max(n) [length]: the largest wave amplitude the follower follows at every phase (inf
        for a knife edge)."""
        n = np.asarray(waves, dtype=float)
        margin = self.curvature + 1.0 / self.contact_radius if self.contact_radius > 0 else np.inf
        out = np.empty(n.shape)
        sig, sig1 = self.arc_rate, self.arc_rate_d1
        for lo in range(0, n.size, 32):
            m = n.ravel()[lo:lo + 32, None]
            w = np.hypot(self.curvature**2 - m * m / sig**2, m * sig1 / sig**3)
            with np.errstate(divide="ignore"):
                out.ravel()[lo:lo + 32] = np.min(margin / w, axis=1)
        return out


def sensitivity(design: Any, speed_rpm: float, samples: int = GAIN_SAMPLES) -> Sensitivity:
    """The first-order sensitivity of ``design``'s follower (a plane cam: its design curve and
    follower) at cam speed ``speed_rpm`` [rpm].

    Raises:
        SpecError: a design that is not a plane cam ("cam.body").
    """
    if not design.plane:
        raise SpecError("cam.body", "the tolerance study reads a plane cam's profile and follower; this body has "
                        f"none ({design.instead_of_plane_curves})")
    program: MotionProgram = design.program
    fol: Follower = design.follower
    theta = TWO_PI * np.arange(samples) / samples
    r_off = float(fol.profile_offset)

    def gain(t: np.ndarray) -> np.ndarray:
        return np.asarray(fol.force_per_load(program.evaluate(t)), dtype=float) / fol.lift_scale

    def arc_rate(t: np.ndarray) -> np.ndarray:
        v, w = fol.tangents(program.evaluate(t))
        speed = np.abs(v)
        # σ_θ of the profile, the design curve moved inward by r_off: |C′|·(1 − r_off/ρ), ρ signed
        return speed + r_off * fol.sense * (np.conj(v) * w).imag / speed**2

    g, g1, g2 = _stencil(gain, theta)
    sig, sig1, _ = _stencil(arc_rate, theta)
    rho = fol.radius_of_curvature(program.evaluate(theta))
    omega = speed_rpm * TWO_PI / 60.0
    return Sensitivity(theta, g, g1, g2, 1.0 / (rho - r_off), sig, sig1, contact_radius(fol), omega,
                       program.maxima(omega)["acceleration"])


def design_frame(follower: Follower, program: MotionProgram, theta: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(C, t̂, N, κ_C·|C′|) at cam angles θ: the design-curve point (cam frame), its unit tangent
    (direction of increasing θ), its outward unit normal N = iδt̂ and the rate dN/dθ = κ_C|C′|·t̂."""
    k = program.evaluate(theta)
    c, dc = follower.derivatives(theta, k, 1)
    t = dc / np.abs(dc)
    rho = follower.radius_of_curvature(k)
    return c, t, 1j * follower.sense * t, np.abs(dc) / rho


def junctions(program: MotionProgram, segments: int) -> np.ndarray:
    """About ``segments`` junction angles [rad], spread over the motion segments in proportion to
    their spans and starting at each segment's start: the C² spline's junctions fall where the
    motion's higher derivatives jump."""
    counts = np.maximum(1, np.round(segments * np.asarray(program.spans) / TWO_PI).astype(int))
    return np.concatenate([a + w * np.arange(m) / m for a, w, m in zip(program.starts, program.spans, counts)])


def moved_design_curve(p: np.ndarray, dp: np.ndarray, normal: np.ndarray, dnormal: np.ndarray, e: np.ndarray,
                       de: np.ndarray, inset: float, side: float) -> np.ndarray:
    """The follower's design curve over a profile moved by e along its outward normal, exactly:
    P̃ + r·side·i·P̃′/|P̃′| with P̃ = P + e·N, P̃′ = P′ + e′·N + e·N′ (the offset along the moved
    profile's own normal).

    Args:
        p, dp: profile points P and derivatives P′ (complex, any parameter).
        normal, dnormal: the outward unit normal N = side·i·P′/|P′| and its derivative N′.
        e, de: the normal deviation e [length, outward +] and e′ in the same parameter.
        inset: r, the design curve's distance from the profile (roller radius; 0 for a knife or face).
        side: ±1, N's turn from the tangent.
    """
    pm = p + e * normal
    dpm = dp + de * normal + e * dnormal
    return pm + inset * side * 1j * dpm / np.abs(dpm)


def perturbed_lift(design: Any, error: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]],
                   theta: np.ndarray, segments: int) -> tuple[np.ndarray, np.ndarray]:
    """(nominal lift, lift on the wavy profile) [spec lift units] at cam angles ``theta``, both
    from the design's own contact solve on closed PH splines through about ``segments`` junctions
    (:func:`junctions`):
    the nominal design curve, and the exact design curve of the profile moved by e(θ) along its
    normal (``error(θ)`` → (e, e′)) — for a roller the wavy profile's exact offset by the roller
    radius, P̃ + r·Ñ with Ñ the wavy profile's own normal.

    The difference of the two is the exact δs up to the splines' interpolation of the wave
    (small when ``segments`` ≫ the wave count; both splines share the junction angles)."""
    fol: Follower = design.follower
    program: MotionProgram = design.program
    angles = junctions(program, segments)
    c, t, n, dn = design_frame(fol, program, angles)
    r = float(fol.profile_offset)
    k = program.evaluate(angles)
    speed = np.abs(fol.derivatives(angles, k, 1)[1])
    e, e1 = error(angles)
    # the nominal profile P = C − r·N, P′ = t̂·(|C′| − r·κ|C′|), N′ = κ|C′|·t̂
    q = moved_design_curve(c - r * n, t * (speed - r * dn), n, dn * t, e, e1, r, fol.sense)
    nominal = PitchCurve(solve_closed_ph_spline(c), angles, program, fol)
    wavy = PitchCurve(solve_closed_ph_spline(q), angles, program, fol)
    return nominal.actual_displacement(theta), wavy.actual_displacement(theta)


__all__ = ["Sensitivity", "contact_radius", "design_frame", "junctions", "moved_design_curve", "perturbed_lift",
           "sensitivity"]

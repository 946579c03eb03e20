"""Profile tolerance against the follower's acceleration, both ways (first-order model of
:mod:`.sensitivity`).

**Forward** (:func:`tolerance_chart`): for the target "acceleration error ≤ X of the designed peak
a_peak at cam speed ω", the largest profile tolerance t (ISO 1101 profile of a line: a zone ±t/2
about the nominal profile, so a wave of amplitude A = t/2), worst case over the wave's phase, for
each wave count n = 1 … n_max:

    t_a(n) = 2·X·a_peak / (ω²·max_θ|Z_n(θ)|),

and the contact limit t_c(n) = 2·A_max(n), past which the follower no longer sees the wave at all
phases; the tolerance is the smaller of the two, and ``governed_by`` says which.

**Reverse** (:func:`measured_error`): a measured normal deviation e(θ) (cam angles and deviations,
any order, one turn) is resampled uniformly (periodic linear interpolation; a uniform input is
taken as is), its harmonics e = Σ A_n·cos(nθ + φ_n) read off the FFT, and the acceleration error of
each harmonic and of their sum found in the time domain by differentiating δs = g·e twice
(product rule, the harmonics' derivatives exact).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import SpecError
from .sensitivity import Sensitivity

TWO_PI = 2.0 * np.pi


@dataclass(frozen=True)
class ToleranceChart:
    """The largest profile tolerance per wave count (lengths in spec units).

    Attributes:
        waves: (n_max,) wave counts 1 … n_max.
        acceleration_limit: X, the allowed acceleration error as a fraction of the designed peak.
        allowed_acceleration: X·a_peak [lift units/s²].
        peak_per_amplitude: ω²·max|Z_n| [lift units/s² per length of amplitude].
        acceleration_tolerance: t_a(n) [length] (zone width).
        contact_tolerance: t_c(n) = 2·A_max(n) [length] (inf for a knife edge).
        tolerance: min(t_a, t_c) [length].
        governed_by: "acceleration" or "contact" per n.
    """

    waves: np.ndarray
    acceleration_limit: float
    allowed_acceleration: float
    peak_per_amplitude: np.ndarray
    acceleration_tolerance: np.ndarray
    contact_tolerance: np.ndarray
    tolerance: np.ndarray
    governed_by: tuple[str, ...]


def tolerance_chart(sens: Sensitivity, acceleration_limit: float, max_waves: int) -> ToleranceChart:
    """The chart t(n), n = 1 … ``max_waves``, for an acceleration error ≤ ``acceleration_limit``
    (a fraction, 0.05 for 5 %) of the designed peak.

    Raises:
        SpecError: ``acceleration_limit`` not in (0, 1] or ``max_waves`` not in 1 … 10000.
    """
    check_limits(acceleration_limit, max_waves)
    n = np.arange(1, max_waves + 1)
    allowed = acceleration_limit * sens.peak_acceleration
    peak = sens.peak_per_amplitude(n)
    t_a = 2.0 * allowed / peak
    t_c = 2.0 * sens.contact_loss_amplitude(n)
    tol = np.minimum(t_a, t_c)
    gov = tuple("acceleration" if a <= c else "contact" for a, c in zip(t_a, t_c))
    return ToleranceChart(n, acceleration_limit, allowed, peak, t_a, t_c, tol, gov)


def check_limits(acceleration_limit: float, max_waves: int) -> None:
    """The study's own inputs.

    Raises:
        SpecError: naming ``acceleration_limit`` or ``max_waves`` and the rule.
    """
    check_acceleration_limit(acceleration_limit)
    check_waves(max_waves)


def check_acceleration_limit(acceleration_limit: float) -> None:
    """Raises SpecError naming ``acceleration_limit`` unless it is a fraction in (0, 1]."""
    if not (np.isfinite(acceleration_limit) and 0.0 < acceleration_limit <= 1.0):
        raise SpecError("acceleration_limit", f"must be a fraction in (0, 1] of the designed peak acceleration, "
                        f"got {acceleration_limit!r}")


def check_waves(max_waves: int) -> None:
    """Raises SpecError naming ``max_waves`` unless it is a whole number in 1 … 10000."""
    if isinstance(max_waves, bool) or not isinstance(max_waves, (int, np.integer)) or not 1 <= max_waves <= 10000:
        raise SpecError("max_waves", f"must be a whole number of waves per turn in 1 … 10000, got {max_waves!r}")


@dataclass(frozen=True)
class Harmonic:
    """One harmonic of a measured deviation and the acceleration error it alone causes.

    Attributes:
        waves: n (0: a uniform size error).
        amplitude: A_n [length] (≥ 0).
        phase_deg: φ_n [deg] in e = A_n·cos(nθ + φ_n).
        peak_acceleration_error: max_θ|δa_n| [lift units/s²].
        contact_loss_amplitude: A_max(n) [length] (inf: no limit); ``followed``: A_n < A_max(n).
    """

    waves: int
    amplitude: float
    phase_deg: float
    peak_acceleration_error: float
    contact_loss_amplitude: float

    @property
    def followed(self) -> bool:
        return self.amplitude < self.contact_loss_amplitude

    def summary(self, designed_peak: float) -> dict[str, Any]:
        """Its numbers as plain values, the peak error also as a percentage of ``designed_peak``
        [lift units/s²]; an infinite contact-loss amplitude as None."""
        amax = self.contact_loss_amplitude
        return {"waves": self.waves, "amplitude": self.amplitude, "phase_deg": self.phase_deg,
                "peak_acceleration_error": self.peak_acceleration_error,
                "percent_of_designed_peak": 100.0 * self.peak_acceleration_error / designed_peak,
                "contact_loss_amplitude": float(amax) if np.isfinite(amax) else None, "followed": self.followed}


@dataclass(frozen=True)
class MeasuredError:
    """The predicted acceleration error of a measured profile deviation.

    Attributes:
        theta: (K,) uniform cam angles [rad] the deviation was resampled to.
        deviation: (K,) the resampled normal deviation [length].
        harmonics: n = 0 … K//2 (the FFT's, n_max capped by ``max_waves``).
        lift_error: (K,) δs [lift units] of the reconstructed deviation.
        acceleration_error: (K,) δa [lift units/s²].
        peak_acceleration_error, at_deg: max|δa| and its cam angle [deg].
        designed_peak: a_peak [lift units/s²].
    """

    theta: np.ndarray
    deviation: np.ndarray
    harmonics: tuple[Harmonic, ...]
    lift_error: np.ndarray
    acceleration_error: np.ndarray
    peak_acceleration_error: float
    at_deg: float
    designed_peak: float

    @property
    def percent(self) -> float:
        """max|δa| as a percentage of the designed peak acceleration."""
        return 100.0 * self.peak_acceleration_error / self.designed_peak


def resample(theta_deg: np.ndarray, deviation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(θ_k = 2πk/K [rad], e(θ_k)): the deviation on K uniform angles over one turn, K the number
    of distinct measured angles, by periodic linear interpolation (exact for a uniform input
    starting at 0°).

    Raises:
        SpecError: ``deviation`` (arrays of unequal length, fewer than 4 distinct angles, not finite).
    """
    th = np.asarray(theta_deg, dtype=float).ravel()
    e = np.asarray(deviation, dtype=float).ravel()
    if th.shape != e.shape:
        raise SpecError("deviation", f"needs one deviation per cam angle (got {th.size} angles, {e.size} deviations)")
    if not (np.all(np.isfinite(th)) and np.all(np.isfinite(e))):
        raise SpecError("deviation", "cam angles and deviations must be finite numbers")
    th = np.mod(th, 360.0)
    th, idx = np.unique(th, return_index=True)
    e = e[idx]
    if th.size < 4:
        raise SpecError("deviation", f"needs at least 4 distinct cam angles over the turn, got {th.size}")
    k = th.size
    grid = 360.0 * np.arange(k) / k
    return np.deg2rad(grid), np.interp(grid, th, e, period=360.0)


def measured_error(sens: Sensitivity, theta_deg: np.ndarray, deviation: np.ndarray,
                   max_waves: int | None = None) -> MeasuredError:
    """The acceleration error of a measured normal deviation ``deviation`` [length, outward +] at
    cam angles ``theta_deg`` [deg] (the angle at which the follower touches the measured point).

    The deviation is resampled (:func:`resample`), split into harmonics n = 0 … min(K//2,
    ``max_waves``) by the FFT, and δs = g·e, δa = ω²(g″e + 2g′e′ + ge″) evaluated at the
    sensitivity's angles for each harmonic and their sum.

    Raises:
        SpecError: bad ``deviation`` or ``max_waves``.
    """
    if max_waves is not None:
        check_waves(max_waves)
    grid, e = resample(theta_deg, deviation)
    k = grid.size
    top = k // 2 if max_waves is None else min(k // 2, max_waves)
    c = np.fft.rfft(e)[: top + 1] / k
    n = np.arange(top + 1)
    amp = 2.0 * np.abs(c)
    amp[0] = abs(c[0].real)
    if k % 2 == 0 and top == k // 2:
        amp[top] = abs(c[top].real)          # the Nyquist term is real: e = c·cos(Kθ/2)
    phase = np.angle(c)                      # 0 or π for the real n = 0 and Nyquist terms
    th = sens.theta
    ds = np.zeros_like(th)
    da = np.zeros_like(th)
    peaks = np.empty(n.size)
    for lo in range(0, n.size, 32):          # blocks of harmonics, rows (≤ 32, N)
        m = n[lo:lo + 32, None]
        arg = m * th[None, :] + phase[lo:lo + 32, None]
        ec, es = amp[lo:lo + 32, None] * np.cos(arg), amp[lo:lo + 32, None] * np.sin(arg)
        ds_n, da_n = sens.follower_error(ec, -m * es, -m * m * ec)
        ds += ds_n.sum(axis=0)
        da += da_n.sum(axis=0)
        peaks[lo:lo + 32] = np.max(np.abs(da_n), axis=1)
    amax = sens.contact_loss_amplitude(n)
    harmonics = tuple(Harmonic(int(m), float(a), float(np.rad2deg(p)), float(pk), float(x))
                      for m, a, p, pk, x in zip(n, amp, phase, peaks, amax))
    j = int(np.argmax(np.abs(da)))
    return MeasuredError(grid, e, harmonics, ds, da, float(abs(da[j])), float(np.rad2deg(th[j])),
                         sens.peak_acceleration)


__all__ = ["Harmonic", "MeasuredError", "ToleranceChart", "check_acceleration_limit", "check_limits", "check_waves", "measured_error", "resample",
           "tolerance_chart"]

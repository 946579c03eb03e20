"""The tolerance study's reverse on the measured part: the deviation's harmonics over the cam
angle and the acceleration error each predicts to first order (:mod:`..tolerance`), beside the
measured motion's (:mod:`.measured_motion`), and the tolerance the study gives at a limit.

**e(θ).**  Both modules read the same deviation: the normal deviation, outward + (material left
on), at the point the follower touches at cam angle θ.  The inspection's smoothing fit δ(u) is
over the profile parameter; the design's own contact solve gives the parameter u(θ) touched at
each of :data:`SAMPLES` uniform cam angles (:func:`.measured_motion.contact_parameters`), so
e(θ) = δ(u(θ)) there exactly, and the FFT reads its harmonics with no resampling.  It is the
same δ the measured motion runs through the contact solve, on the same grid of cam angles.

**Which waves.**  Harmonics n = 0 … 2·K (at most :data:`SAMPLES`/2), K the smoothing spline's knot spans: a spline of K spans
holds waves up to K/2 per turn of its own, and its images about K (a 23-wave fit on 60 spans also
holds 37 and 83 waves, 10⁻³ and less of the amplitude) are part of the motion it gives.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..tolerance.sensitivity import sensitivity
from ..tolerance.study import MeasuredError, ToleranceChart, check_acceleration_limit, measured_error, tolerance_chart
from .measured_motion import MOTION_SAMPLES, SmoothedDeviation, contact_parameters

#: uniform cam angles of e(θ): the measured motion's grid
SAMPLES = MOTION_SAMPLES
#: harmonics listed in the summary, the largest amplitudes first
LISTED = 8


@dataclass(frozen=True)
class DeviationHarmonics:
    """The measured deviation's harmonics and their predicted acceleration error.

    Attributes:
        measured: the tolerance study's reverse of e(θ) = δ(u(θ)) (harmonics n = 0 … ``max_waves``).
        max_waves: the largest wave count read (2 × the smoothing spline's knot spans, at most samples/2).
        speed_rpm: the cam speed [rpm] (``cam.speed_rpm``: the measured motion's).
        chart: the tolerance chart t(n), n = 1 … ``max_waves``, at the user's acceleration limit, or None.
    """

    measured: MeasuredError
    max_waves: int
    speed_rpm: float
    chart: ToleranceChart | None

    def largest(self, count: int = LISTED) -> list[int]:
        """Wave counts of the ``count`` largest amplitudes, largest first."""
        amp = np.array([h.amplitude for h in self.measured.harmonics])
        return [int(self.measured.harmonics[i].waves) for i in np.argsort(-amp, kind="stable")[:count]]

    def summary(self) -> dict[str, Any]:
        """The numbers of inspection.json's ``harmonics`` section (spec lengths; acceleration in
        lift units/s²; tolerances are zone widths t, a wave of amplitude A needing t ≥ 2A)."""
        m, c = self.measured, self.chart
        listed = []
        for n in self.largest():
            h = m.harmonics[n].summary(m.designed_peak)
            if c is not None and n >= 1:
                t = float(c.tolerance[n - 1])
                h |= {"tolerance": t, "governed_by": c.governed_by[n - 1], "within_tolerance": 2.0 * h["amplitude"] <= t}
            listed.append(h)
        out: dict[str, Any] = {
            "samples": int(m.theta.size), "max_waves": self.max_waves, "speed_rpm": self.speed_rpm,
            "predicted_acceleration_error": {"max_abs": m.peak_acceleration_error, "at_deg": m.at_deg,
                                             "percent_of_designed_peak": m.percent},
            "largest": listed,
        }
        if c is not None:
            k = int(np.argmin(c.tolerance))
            out["limit"] = {"acceleration_limit": c.acceleration_limit, "allowed_acceleration_error": c.allowed_acceleration,
                            "within": m.peak_acceleration_error <= c.allowed_acceleration,
                            "tightest": {"waves": int(c.waves[k]), "tolerance": float(c.tolerance[k]),
                                         "governed_by": c.governed_by[k]}}
        return out


def deviation_harmonics(design: Any, smoothing: SmoothedDeviation, acceleration_limit: float | None = None,
                        samples: int = SAMPLES) -> DeviationHarmonics:
    """The harmonics of the smoothed deviation over the contact cam angle and the acceleration
    error they predict at ``cam.speed_rpm`` (see the module docstring); with
    ``acceleration_limit`` (a fraction of the designed peak) the tolerance chart there too.

    Raises:
        SpecError: ``acceleration_limit`` not in (0, 1].
    """
    if acceleration_limit is not None:
        check_acceleration_limit(acceleration_limit)
    top = min(2 * smoothing.spans, samples // 2)
    rpm = float(design.spec.cam.speed_rpm)
    theta = 2.0 * np.pi * np.arange(samples) / samples
    sens = sensitivity(design, rpm, samples)
    m = measured_error(sens, np.rad2deg(theta), smoothing(contact_parameters(design, theta))[0], top)
    chart = None if acceleration_limit is None else tolerance_chart(sens, acceleration_limit, top)
    return DeviationHarmonics(m, top, rpm, chart)


__all__ = ["LISTED", "SAMPLES", "DeviationHarmonics", "deviation_harmonics"]

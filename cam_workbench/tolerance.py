"""Profile tolerances that mean something, from Python (docs/tolerances.md).

    from cam_workbench.tolerance import tolerance_study
    study = tolerance_study(spec, acceleration_limit=0.05, max_waves=200)   # 5 % of the peak
    study.summary()["chart"]["tolerance"]       # the largest tolerance zone t [length] for n = 1 … 200
    study.svg()                                 # the chart
    m = study.measured(theta_deg, deviation)    # a measured part: its harmonics and acceleration error

The mathematics is :mod:`cam_workbench.generators.tolerance`; ``cam-workbench tolerance`` and the
FreeCAD command "Tolerance study…" call :func:`tolerance_study` and show :meth:`ToleranceStudy.summary`.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from cam_workbench.exporters.chart_svg import svg
from cam_workbench.exporters.tolerance_chart import tolerance_figure
from cam_workbench.generators.cam_design import design_cam
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec import CamSpec, spec_digest
from cam_workbench.generators.tolerance.sensitivity import Sensitivity, sensitivity
from cam_workbench.generators.tolerance.study import (MeasuredError, ToleranceChart, check_limits, measured_error,
                                                      tolerance_chart)

#: the wave counts the printed table shows (those ≤ max_waves), besides the tightest
TABLE_WAVES = (1, 2, 3, 5, 10, 20, 50, 100, 200, 500, 1000)


def _finite(v: float) -> float | None:
    return float(v) if np.isfinite(v) else None


@dataclass(frozen=True)
class ToleranceStudy:
    """The tolerance chart of one cam at one speed, and the reverse for measured parts.

    Attributes:
        spec: the cam's spec.
        design: its design (the follower and the motion the study reads).
        speed_rpm: the cam speed of the study [rpm].
        sensitivity: the first-order model (:class:`~cam_workbench.generators.tolerance.sensitivity.Sensitivity`).
        chart: t(n) (:class:`~cam_workbench.generators.tolerance.study.ToleranceChart`).
    """

    spec: CamSpec
    design: Any
    speed_rpm: float
    sensitivity: Sensitivity
    chart: ToleranceChart

    @property
    def lift_unit(self) -> str:
        """The follower's lift unit: the spec's length unit, or "deg" for an arm."""
        return "deg" if self.design.follower.lift_unit == "angle" else self.spec.units

    def measured(self, theta_deg: np.ndarray, deviation: np.ndarray, max_waves: int | None = None) -> MeasuredError:
        """The acceleration error of a measured normal deviation [length, outward +] at cam angles
        [deg] (where the follower touches each measured point): its harmonics, δs and δa."""
        return measured_error(self.sensitivity, theta_deg, deviation, max_waves)

    def measured_summary(self, m: MeasuredError) -> dict[str, Any]:
        """A measured part's numbers as plain values (spec units; acceleration in lift units/s²)."""
        return {"samples": int(m.theta.size), "peak_acceleration_error": m.peak_acceleration_error,
                "at_deg": m.at_deg, "percent_of_designed_peak": m.percent, "designed_peak_acceleration": m.designed_peak,
                "max_lift_error": float(np.max(np.abs(m.lift_error))),
                "harmonics": [h.summary(m.designed_peak) for h in m.harmonics]}

    @cached_property
    def _summary(self) -> dict[str, Any]:
        c, s, fol = self.chart, self.sensitivity, self.design.follower
        lu = self.lift_unit
        tight = int(np.argmin(c.tolerance))
        rows = [int(n) - 1 for n in TABLE_WAVES if n <= c.waves[-1]]
        if tight not in rows:
            rows = sorted(rows + [tight])
        entry = lambda i: {"waves": int(c.waves[i]), "tolerance": float(c.tolerance[i]),  # noqa: E731
                           "acceleration_tolerance": float(c.acceleration_tolerance[i]),
                           "contact_tolerance": _finite(c.contact_tolerance[i]), "governed_by": c.governed_by[i]}
        return {
            "units": self.spec.units,
            "spec_digest": spec_digest(self.spec),
            "cam": self.design.label(),
            "follower": fol.name,
            "lift_unit": lu,
            "acceleration_unit": f"{lu}/s²",
            "speed_rpm": self.speed_rpm,
            "omega": s.omega,
            "acceleration_limit": c.acceleration_limit,
            "designed_peak_acceleration": s.peak_acceleration,
            "allowed_acceleration_error": c.allowed_acceleration,
            "contact_radius": _finite(s.contact_radius),
            "gain": {"min": float(np.min(s.gain)), "max": float(np.max(s.gain)),
                     "unit": f"{lu}/{self.spec.units}"},
            "tightest": entry(tight),
            "table": [entry(i) for i in rows],
            "chart": {"waves": c.waves.tolist(), "tolerance": c.tolerance.tolist(),
                      "acceleration_tolerance": c.acceleration_tolerance.tolist(),
                      "contact_tolerance": [_finite(v) for v in c.contact_tolerance],
                      "governed_by": list(c.governed_by),
                      "peak_acceleration_per_amplitude": c.peak_per_amplitude.tolist()},
        }

    def summary(self) -> dict[str, Any]:
        """tolerance.json's numbers (spec units; tolerances are zone widths t, the wave amplitude t/2)."""
        return self._summary

    def svg(self) -> str:
        """The chart t(n) as SVG text."""
        return svg(tolerance_figure(self.summary()), "tolerance")


def tolerance_study(spec: CamSpec, acceleration_limit: float = 0.05, max_waves: int = 200,
                    speed_rpm: float | None = None, design: Any = None) -> ToleranceStudy:
    """The tolerance study of ``spec``'s cam: for an acceleration error ≤ ``acceleration_limit``
    (a fraction of the designed peak) at ``speed_rpm`` (default ``cam.speed_rpm``), the largest
    profile tolerance per wave count n = 1 … ``max_waves``; ``design``: the cam already designed.

    Raises:
        SpecError: bad ``acceleration_limit``, ``max_waves`` or ``speed_rpm``; a body that is not a
            plane cam.
        GeometryError: the cam cannot be made.
    """
    check_limits(acceleration_limit, max_waves)
    rpm = spec.cam.speed_rpm if speed_rpm is None else float(speed_rpm)
    if not (np.isfinite(rpm) and rpm > 0):
        raise SpecError("speed_rpm", f"must be a cam speed > 0 rpm, got {speed_rpm!r}")
    design = design_cam(spec) if design is None else design
    sens = sensitivity(design, rpm)
    return ToleranceStudy(spec, design, rpm, sens, tolerance_chart(sens, acceleration_limit, max_waves))


__all__ = ["TABLE_WAVES", "ToleranceStudy", "tolerance_study"]

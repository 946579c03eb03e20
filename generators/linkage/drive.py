"""The follower's motion derived from a motion program given at the tool: :class:`LinkedProgram`
(the inverse linkage applied to the tool program, exactly), and :func:`tool_report`, report.json's
``linkage`` section.

``scale`` converts the program's lift unit into the linkage's: π/180 for a program in degrees
(an oscillating follower), 1 for a length.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..curves.extrema import refine_max
from ..motion.program import Kinematics, MotionProgram
from .base import Linkage


@dataclass(frozen=True)
class LinkedProgram(MotionProgram):
    """The follower's program whose tool, through ``linkage``, follows ``tool`` (the spec's
    [[motion]] given at the tool): s = q/scale with (q, q′, q″, q‴) = linkage.inverse(scale·tool
    jet).  Segments, laws and their parameter maps are the tool program's; ``levels`` and
    ``lifts`` are the follower's (a dwell of the tool is a dwell of the follower)."""

    tool: MotionProgram | None = None
    linkage: Any = None
    scale: float = 1.0

    @classmethod
    def compose(cls, tool: MotionProgram, linkage: Linkage, scale: float) -> "LinkedProgram":
        """The follower program of the tool program ``tool`` through ``linkage``."""
        n = len(tool.starts)
        idx = np.arange(n)
        c = float(scale)
        p0 = tool.evaluate(tool.starts, idx).s * c
        p1 = tool.evaluate(tool.starts + tool.spans, idx).s * c
        q0 = linkage.inverse(p0, 0 * p0, 0 * p0, 0 * p0)[0] / c
        q1 = linkage.inverse(p1, 0 * p1, 0 * p1, 0 * p1)[0] / c
        return cls(**{**{f: getattr(tool, f) for f in tool.__dataclass_fields__},
                      "levels": q0, "lifts": q1 - q0, "tool": tool, "linkage": linkage, "scale": c})

    def evaluate(self, theta: np.ndarray | float, segment: np.ndarray | None = None) -> Kinematics:
        """s, s′, s″, s‴ of the follower: the inverse linkage of the tool's, exactly."""
        assert self.tool is not None
        k = self.tool.evaluate(theta, segment)
        c = self.scale
        q = self.linkage.inverse(c * k.s, c * k.ds, c * k.d2s, c * k.d3s)
        return Kinematics(k.theta, q[0] / c, q[1] / c, q[2] / c, q[3] / c)

    def report(self) -> dict[str, Any]:
        """The tool program's segments and junctions (what the spec gave), marked as the tool's."""
        assert self.tool is not None
        return {**self.tool.report(), "given_at": "tool"}


def tool_report(linkage: Linkage, program: MotionProgram, scale: float, omega: float,
                motion_at: str, limit_deg: float | None, lift_unit: str) -> dict[str, Any]:
    """report.json's ``linkage`` section: the linkage's summary, where the motion is given, the
    tool's largest |p|, |v|, |a| (true: per s, per s²; in the lift unit) and their cam angles
    [deg], the smallest effective transmission angle min(μ, 180° − μ) and its cam angle, the toggles
    [lift unit].  ``program``: the follower's program; ``scale``: lift unit → linkage unit."""
    th = program.dense_angles()

    def jet(t: np.ndarray) -> tuple[np.ndarray, ...]:
        k = program.evaluate(t)
        return tuple(v / scale for v in linkage.forward(*(scale * x for x in (k.s, k.ds, k.d2s, k.d3s))))

    out: dict[str, Any] = {**linkage.summary(), "motion_at": motion_at, "tool_unit": lift_unit}
    for name, order, power in (("displacement", 0, 0), ("velocity", 1, 1), ("acceleration", 2, 2)):
        f = (lambda t, o=order: np.abs(jet(t)[o]))
        at, v = refine_max(f, th, f(th))
        out[f"max_{name}"] = float(v) * omega ** power
        out[f"max_{name}_at_deg"] = float(np.rad2deg(at) % 360.0)
    mu = transmission_extreme(linkage, program, th, scale)
    out["min_transmission_angle_deg"] = None if mu is None else mu[0]
    out["min_transmission_angle_at_deg"] = None if mu is None else mu[1]
    out["min_transmission_angle_limit_deg"] = limit_deg if mu is not None else None
    out["toggles"] = [float(v) / scale for v in linkage.toggles()]
    return out


def transmission_extreme(linkage: Linkage, program: MotionProgram, theta: np.ndarray, scale: float,
                         segment: np.ndarray | None = None) -> tuple[float, float] | None:
    """(smallest effective transmission angle min(μ, 180° − μ) [deg], its cam angle [deg]) over the
    cam angles ``theta`` [rad], refined by golden section; None for a linkage without one."""
    def eff(t: np.ndarray, seg: np.ndarray | None = None) -> np.ndarray:
        mu = linkage.transmission_angle(scale * program.evaluate(t, seg).s)
        return None if mu is None else np.minimum(mu, np.pi - mu)
    first = eff(theta, segment)
    if first is None:
        return None
    at, v = refine_max(lambda t: -eff(t), theta, -first)
    return float(np.rad2deg(-v)), float(np.rad2deg(at) % 360.0)


__all__ = ["LinkedProgram", "tool_report", "transmission_extreme"]

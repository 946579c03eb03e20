"""Machining settings of a designed cam with every default resolved (`[machining]`), and
the tool-size check that decides whether a tool can cut the profile at all.

Defaults that depend on the spec's units or on the built geometry are resolved here,
once, so the tool paths and the G-code read plain numbers:

* tool radius: the roller radius (the tool centre then runs on the pitch curve); for a
  knife edge min(R_b/10, ½·smallest concave profile radius);
* feed 300 mm/min (12 in/min), plunge feed/3, safe height 5 mm (0.2 in), chord
  tolerance 0.005 mm (0.0002 in), depth = cam thickness, lead radius = tool radius;
* rotary speed = cam.speed_rpm;
* compensation "centre" (tool-centre coordinates), Fanuc program number 1000.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..cam_design import CamDesign
from ..errors import GeometryError, fmt_apart
from ..kinds import body_of

_UNIT_DEFAULTS = {
    "mm": {"feed_rate": 300.0, "safe_height": 5.0, "chord_tolerance": 0.005},
    "in": {"feed_rate": 12.0, "safe_height": 0.2, "chord_tolerance": 0.0002},
}


@dataclass(frozen=True)
class MachiningPlan:
    """Resolved `[machining]` values (spec units; times in s; speeds in rpm)."""

    units: str
    tool_radius: float
    tool_number: int
    spindle_rpm: float
    feed_rate: float
    plunge_rate: float
    sample_period: float
    rotary_speed_rpm: float
    depth: float
    passes: int
    safe_height: float
    chord_tolerance: float
    contour: str
    lead_radius: float
    milling: str
    rotary_line: str
    work_offset: str
    line_numbers: bool
    coolant: bool
    program: str
    dialect: str
    roller_radius: float
    #: "centre" (tool-centre coordinates) or "controller" (the part's contour under G41/G42)
    compensation: str
    #: a Fanuc program's O number
    program_number: int

    @property
    def z_levels(self) -> np.ndarray:
        """Depth of each pass (negative, top face at Z = 0), last = −depth."""
        return -self.depth * np.arange(1, self.passes + 1) / self.passes

    @property
    def centre_offset(self) -> float:
        """How far the tool centre runs outside the pitch curve: tool radius − roller radius
        (negative when the tool is smaller than the roller)."""
        return self.tool_radius - self.roller_radius


def smallest_concave_profile_radius(design: CamDesign) -> tuple[float, float]:
    """(smallest concave radius of curvature of the profile, cam angle [deg] where it occurs);
    (inf, nan) for a profile without concave parts.  The profile is the pitch curve moved
    inward by the roller radius, so its concave radii are the pitch curve's plus the roller
    radius (as-built curvature, sampled on every PH segment; the design's own roller: a conjugate
    pair's second cam has its own)."""
    cs = design.curvature_samples
    concave = cs.radius < 0
    if not concave.any():
        return float("inf"), float("nan")
    rad = np.where(concave, -cs.radius, np.inf) + design.follower.profile_offset
    k = int(np.argmin(rad))
    return float(rad[k]), float(cs.cam_angle_deg[k])


def check_tool_fits(design: CamDesign, tool_radius: float) -> None:
    """A tool cuts the profile without gouging only if its radius is below the smallest
    concave radius of curvature of the profile.

    Raises:
        GeometryError: ``gouge``, naming the cam angle of the tightest concave point.
    """
    rho, at = smallest_concave_profile_radius(design)
    if tool_radius >= rho:
        raise GeometryError(
            "gouge",
            f"machining.tool_radius {fmt_apart(tool_radius, rho)} would gouge the profile at cam angle {at:.2f}°, "
            f"where its concave radius of curvature is only {fmt_apart(rho, tool_radius, 4)} (use a tool radius < "
            f"{fmt_apart(rho, tool_radius, 4)})",
            at)


def machining_plan(design: CamDesign) -> MachiningPlan:
    """The spec's `[machining]` with defaults resolved; checks that the tool fits.

    Raises:
        GeometryError: the tool would gouge a concave part of the profile.
    """
    spec = design.spec
    mc = spec.machining
    d = _UNIT_DEFAULTS[spec.units]
    body = body_of(spec).machining_defaults(spec)
    if mc.tool_radius is not None:
        tool = mc.tool_radius
    elif body["tool_radius"] is not None:
        tool = body["tool_radius"]
    elif spec.is_roller:
        tool = spec.roller_radius
    else:
        rho, _ = smallest_concave_profile_radius(design)
        tool = min(spec.cam.base_radius / 10, 0.5 * rho)
    check_tool_fits(design, tool)
    feed = mc.feed_rate if mc.feed_rate is not None else d["feed_rate"]
    return MachiningPlan(
        units=spec.units,
        tool_radius=float(tool),
        tool_number=mc.tool_number,
        spindle_rpm=mc.spindle_rpm,
        feed_rate=float(feed),
        plunge_rate=float(mc.plunge_rate if mc.plunge_rate is not None else feed / 3),
        sample_period=mc.sample_period,
        rotary_speed_rpm=float(mc.rotary_speed_rpm if mc.rotary_speed_rpm is not None else spec.cam.speed_rpm),
        depth=float(mc.depth if mc.depth is not None else body["depth"]),
        passes=mc.passes,
        safe_height=float(mc.safe_height if mc.safe_height is not None else d["safe_height"]),
        chord_tolerance=float(mc.chord_tolerance if mc.chord_tolerance is not None else d["chord_tolerance"]),
        contour=mc.contour,
        lead_radius=float(mc.lead_radius if mc.lead_radius is not None else tool),
        milling=mc.milling,
        rotary_line=mc.rotary_line or ("axis" if design.follower.pivoted else "follower"),
        work_offset=mc.work_offset,
        line_numbers=mc.line_numbers,
        coolant=mc.coolant,
        program=mc.program,
        dialect=mc.dialect,
        roller_radius=spec.roller_radius,
        compensation=mc.compensation or "centre",
        program_number=mc.program_number if mc.program_number is not None else 1000,
    )

"""The spec's `[machining]` table: :class:`MachiningSection` (tool, feeds, passes, the interpolator's
sample period, the G-code dialect), its choices and its rules.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import SpecError, fmt_apart
from .params import param

if TYPE_CHECKING:  # types only: the spec's root imports this module
    from .model import CamSpec


WORK_OFFSETS = ("G54", "G55", "G56", "G57", "G58", "G59")
#: Most interpolator commands per revolution (memory bound).
MAX_COMMANDS_PER_REV = 10_000_000


@dataclass(frozen=True, kw_only=True)
class MachiningSection:
    """`[machining]`: how the cam is cut — tool, feeds, passes, the interpolator's sample period and the G-code dialect."""

    tool_radius: float | None = param(
        "Cutter (or grinding-wheel) radius. Default: the roller radius (the tool centre then runs on the "
        "pitch curve); for a knife edge base_radius/10 or half the smallest concave profile radius, "
        "whichever is smaller", unit="length", gt=0, optional=True, group="Machining")
    tool_number: int = param("Tool number: T word, tool change M6 and length offset G43 H",
                             kind="int", ge=1, default=1, group="Machining")
    spindle_rpm: float = param("Tool spindle speed (S word), clockwise (M3)", unit="spindle", gt=0,
                               default=3000.0, group="Machining")
    feed_rate: float | None = param("Contour feed rate of the XY program; default 300 mm/min (12 in/min)",
                                    unit="feed", gt=0, optional=True, group="Machining")
    plunge_rate: float | None = param("Feed rate of plunges and of the XC radial infeed; default feed_rate/3",
                                      unit="feed", gt=0, optional=True, group="Machining")
    sample_period: float = param(
        "Interpolator sample period Δt: one command (one G93 block of the XC program) per Δt (paper: 1 ms)",
        unit="time", gt=0, default=0.001, group="Machining")
    rotary_speed_rpm: float | None = param(
        "Cam speed on the machine's C axis while the interpolator's commands run (XC program, command "
        "table, interpolator report); default cam.speed_rpm", unit="speed", gt=0, optional=True,
        group="Machining")
    depth: float | None = param("Total cutting depth below the top face (Z = 0); default cam.thickness",
                                unit="length", gt=0, optional=True, group="Machining")
    passes: int = param("Number of equal depth passes", kind="int", ge=1, le=1000, default=1,
                        group="Machining")
    safe_height: float | None = param("Clearance height above the top face for rapid moves; "
                                      "default 5 mm (0.2 in)", unit="length", gt=0, optional=True,
                                      group="Machining")
    chord_tolerance: float | None = param(
        "Largest distance of the emitted arcs/lines (and of the XC blocks) from the exact tool-centre "
        "path; default 0.005 mm (0.0002 in)", unit="length", gt=0, optional=True, group="Machining")
    contour: str = param("XY contour moves: G02/G03 biarcs or G01 chords", kind="str",
                         choices=("arcs", "lines"), default="arcs", group="Machining")
    lead_radius: float | None = param(
        "Radius of the tangent lead-in/lead-out arcs (XY) and length of the radial approach (XC); "
        "default the tool radius", unit="length", gt=0, optional=True, group="Machining")
    milling: str = param("Outside contour milled climb or conventional (spindle clockwise, M3)", kind="str",
                         choices=("climb", "conventional"), default="climb", group="Machining")
    rotary_line: str | None = param(
        "XC program: the tool centre moves on the follower's own line (machine Y = −offset, C = cam "
        "angle) or on a line through the C axis (two-axis X–C machines); default the follower's line for a "
        "translating follower, the C axis for an oscillating one (which has no line)", kind="str",
        choices=("follower", "axis"), optional=True, group="Machining")
    work_offset: str = param("Work coordinate system: origin on the cam axis, Z = 0 on the top face",
                             kind="str", choices=WORK_OFFSETS, default="G54", group="Machining")
    line_numbers: bool = param("Number the blocks (N10, N20, …)", kind="bool", default=False,
                               group="Machining")
    coolant: bool = param("Flood coolant (M8) while cutting", kind="bool", default=False, group="Machining")
    program: str = param("Program that `build` writes to cam.nc: XY contour milling or XC rotary",
                         kind="str", choices=("xy", "xc"), default="xy", group="Machining")
    dialect: str = param("G-code dialect of cam.nc", kind="str", choices=("linuxcnc",),
                         default="linuxcnc", group="Machining")


def validate_machining(spec: CamSpec) -> None:
    mc = spec.machining
    if mc.rotary_line == "follower" and spec.follower.motion != "translating":
        raise SpecError("machining.rotary_line", '"follower" needs a translating follower\'s line of motion; an '
                        'oscillating arm has none: use "axis" (the default for an oscillating follower)')
    rpm = mc.rotary_speed_rpm if mc.rotary_speed_rpm is not None else spec.cam.speed_rpm
    step = 360.0 * rpm / 60.0 * mc.sample_period
    # (a coarse step is not an error here: it only matters for the XC program, whose
    # blocks are checked against machining.chord_tolerance when it is made)
    if 360.0 / step > MAX_COMMANDS_PER_REV:
        raise SpecError("machining.sample_period",
                        f"gives {fmt_apart(360.0 / step, MAX_COMMANDS_PER_REV, 4)} commands per revolution at {rpm:g} "
                        f"rpm; must be ≤ {MAX_COMMANDS_PER_REV:,}: a longer period (or a faster "
                        "machining.rotary_speed_rpm)")
    if mc.chord_tolerance is not None and mc.chord_tolerance < 1e-7 * spec.cam.base_radius:
        low = 1e-7 * spec.cam.base_radius
        raise SpecError("machining.chord_tolerance", f"must be ≥ 1e-7 × cam.base_radius ({fmt_apart(low, mc.chord_tolerance)}), "
                                                     f"got {fmt_apart(mc.chord_tolerance, low)}")
    if mc.chord_tolerance is not None and not mc.chord_tolerance < spec.cam.base_radius / 100:
        raise SpecError("machining.chord_tolerance",
                        f"must be < 1% of cam.base_radius ({fmt_apart(spec.cam.base_radius / 100, mc.chord_tolerance)}), "
                        f"got {fmt_apart(mc.chord_tolerance, spec.cam.base_radius / 100)}")

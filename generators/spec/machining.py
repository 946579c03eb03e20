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
#: G-code dialects of the programs (exporters/gcode_dialects.py holds what each one writes)
DIALECTS = ("linuxcnc", "fanuc", "sinumerik")
#: where the XY program's coordinates lie: on the tool centre, or on the part under G41/G42
COMPENSATIONS = ("centre", "controller")
#: Sinumerik's G58/G59 are programmable (axial) offsets, not settable work offsets
SINUMERIK_WORK_OFFSETS = ("G54", "G55", "G56", "G57")
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
    program: str = param("Program that `build` writes to cam.nc: XY contour milling, XC rotary or 2-axis wire EDM "
                         "(a plate cam)",
                         kind="str", choices=("xy", "xc", "wire_edm"), default="xy", group="Machining")
    dialect: str = param("G-code dialect of cam.nc: LinuxCNC (RS274/NGC), Fanuc-style (O number, % tape marks, "
                         "decimal points on every coordinate) or Siemens Sinumerik (; comments, G71/G70, T D M6); "
                         "the differences: docs/machining.md", kind="str", choices=DIALECTS,
                         default="linuxcnc", group="Machining")
    compensation: str | None = param(
        "XY contour program: \"centre\" the tool-centre path (no cutter compensation), or \"controller\" the "
        "part's own contour under G41/G42 (D = tool number; the control's tool table holds the radius, so wear "
        "is adjusted at the machine); default \"centre\"", kind="str", choices=COMPENSATIONS, optional=True,
        group="Machining")
    program_number: int | None = param("Program number of a \"fanuc\" program (its O word, O0001–O9999; the other dialects have none); default 1000",
                                       kind="int", ge=1, le=9999, optional=True, group="Machining")
    # ---- roughing from a round blank (XY program) ----
    blank_diameter: float | None = param(
        "Diameter of the round blank the XY program starts from (centred on the cam axis): when given, the "
        "program first roughs the stock down to finish_allowance around the profile — concentric passes "
        "stepover apart at every depth pass — then runs the finishing contour; absent: the finishing contour "
        "only (a plate cam)", unit="length", gt=0, optional=True, group="Machining")
    stepover: float | None = param("Roughing step-over: radial distance between concentric roughing passes as "
                                   "a fraction of the tool diameter; default 0.5", ge=0.05, le=1.0, optional=True,
                                   group="Machining")
    finish_allowance: float | None = param(
        "Stock the roughing passes leave on the profile for the finishing contour; default 0.2 mm (0.008 in)",
        unit="length", ge=0, optional=True, group="Machining")
    # ---- 2-axis wire EDM (machining.program = "wire_edm") ----
    wire_diameter: float | None = param("Wire EDM: wire diameter; default 0.25 mm (0.01 in)", unit="length",
                                        gt=0, optional=True, group="Machining")
    spark_gap: float | None = param("Wire EDM: spark gap (overcut) between the wire and the part; default "
                                    "0.02 mm (0.0008 in)", unit="length", ge=0, optional=True, group="Machining")
    skim_passes: int | None = param("Wire EDM: skim (trim) passes after the main cut, each in the opposite "
                                    "direction of the one before; default 0", kind="int", ge=0, le=10, optional=True,
                                    group="Machining")
    skim_stock: float | None = param(
        "Wire EDM: stock each skim pass removes (the main cut runs skim_passes × skim_stock outside the final "
        "wire path, each skim one skim_stock closer); default 0.03 mm (0.0012 in)", unit="length", gt=0,
        optional=True, group="Machining")
    tab_width: float | None = param(
        "Wire EDM: length of the holding tab (measured along the wire path) left uncut by the main cut and "
        "the skims and cut last, after a program stop; default 2 mm (0.08 in)", unit="length", gt=0,
        optional=True, group="Machining")
    start_hole: float | None = param(
        "Wire EDM: distance of the start hole (where the wire is threaded) from the wire path, on the "
        "outward normal at the entry point (the middle of the longest dwell); default lead_radius",
        unit="length", gt=0, optional=True, group="Machining")
    wire_compensation: str | None = param(
        "Wire EDM: \"path\" — the program carries the wire-centre path (the profile offset by wire radius + "
        "spark gap); \"controller\" — the program carries the part contour and G41.1 D = 2 × (wire "
        "radius + spark gap) offsets it; default \"path\"", kind="str", choices=("path", "controller"),
        optional=True, group="Machining")


def validate_machining(spec: CamSpec) -> None:
    mc = spec.machining
    if mc.program == "wire_edm" and spec.cam.body != "plate":
        raise SpecError("machining.program", f'"wire_edm" cuts a plate cam\'s outside profile; cam.body is '
                        f'"{spec.cam.body}": use "xy" or "xc"')
    if mc.blank_diameter is not None and spec.cam.body != "plate":
        raise SpecError("machining.blank_diameter", f'roughing from a round blank is for a plate cam; cam.body '
                        f'is "{spec.cam.body}": leave machining.blank_diameter out')
    if mc.program == "wire_edm" and mc.dialect != "linuxcnc":
        raise SpecError("machining.dialect", f'the wire EDM program is written for "linuxcnc"; got "{mc.dialect}"')
    if mc.blank_diameter is not None and mc.compensation == "controller" and mc.program == "xy":
        raise SpecError("machining.blank_diameter", 'the roughing program runs on tool-centre paths: roughing '
                        'from a blank needs machining.compensation = "centre"')
    if mc.program == "wire_edm" and mc.wire_compensation == "controller" and (mc.skim_passes or 0) > 0:
        raise SpecError("machining.skim_passes", 'skims need machining.wire_compensation = "path" (each skim '
                        'reverses direction and has its own offset: the program carries each wire path); '
                        f'got {mc.skim_passes} with "controller"')
    if mc.compensation == "controller" and mc.program != "xy":
        raise SpecError("machining.compensation", '"controller" (G41/G42) needs the XY contour program '
                        '(machining.program = "xy"): cutter compensation along a rotary axis is not standard G-code; '
                        'use "centre" for the XC program')
    if mc.dialect == "sinumerik" and mc.work_offset not in SINUMERIK_WORK_OFFSETS:
        raise SpecError("machining.work_offset", f'must be one of {", ".join(SINUMERIK_WORK_OFFSETS)} for the '
                        f'"sinumerik" dialect (its {mc.work_offset} is a programmable offset, not a work '
                        f'coordinate system), got "{mc.work_offset}"')
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

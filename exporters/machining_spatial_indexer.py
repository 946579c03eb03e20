"""A spatial indexer's machining outputs: the 4-axis generating program of its cam (``cam.nc``,
:func:`cam_workbench.exporters.gcode_spatial_indexer.spatial_program`) and report.json's
``machining`` section, registered in :data:`cam_workbench.exporters.machining_outputs.PROGRAMS` for
:class:`~cam_workbench.generators.bodies.indexing.spatial_kind.SpatialIndexerDesign` (``cam.body`` =
"barrel_indexer" and "globoidal_indexer").

The program (gcode_spatial_indexer's module docstring holds the machine, frames and signs): a flat
end mill in place of roller 0 follows the roller's motion relative to the cam — A the input angle,
C the turret angle, X Y Z the tool tip in the frame of the cam's STEP solid (``cam.step``) renamed
(X = its z, along the cam axis, Y = its x, towards the turret axis, Z = its y, up along the turret
axis; origin = cam.step's: on the cam axis, X0 on the cam's end face z = 0, the cam spanning
0 ≤ X ≤ W = ``cam.thickness``, the turret axis the vertical X = W/2, Y = C) — in roughing sweeps
at equal depth levels from the rib's top to its root, then one climb-milled finishing sweep per
roller side at the final depth.  Four axes move: barrel X Y A and Z between levels (C only turns
the vertical tool about its own axis), globoidal X Y A C (Z = 0).

``[machining]`` → :func:`spatial_program`'s options (mm, mm/min relative to the cam, rpm):

* ``tool_radius`` → ``tool_radius`` (default the roller radius; smaller leaves r_r − R_t of stock
  on every flank; larger is refused by spatial_program, naming it);
* ``tool_number``, ``spindle_rpm`` → the same (spec defaults 1, 3000 rpm);
* ``feed_rate`` → ``feed`` (default :data:`DEFAULT_FEED` = 150 mm/min, the generating program's:
  the cutter's axis relative to the cam, G93 inverse time);
* ``plunge_rate`` → ``plunge_feed`` (default feed_rate/3, along the tool's axis);
* ``passes`` → ``passes``: the roughing sweeps' depth levels, equal steps from the rib's top to
  the root; the spec's default 1 stands for the generating program's own levels of 3 mm each
  (``stepdown``: a roller-sized cutter is not plunged the rib's whole depth in one sweep);
* ``chord_tolerance`` → ``tolerance`` (default :data:`DEFAULT_TOLERANCE` = 0.005 mm: the moves'
  measured chord error of the cutter's pose within 0.9 of it, ``G64 P`` the rest);
* ``safe_height`` → ``safe_height`` (default :data:`DEFAULT_SAFE_HEIGHT` = 5 mm: barrel the tip
  above the rib's top cylinder, globoidal the tip inside the tip globoid's sphere about the turret);
* the largest A step is :data:`STEP_DEG` = 1° (no spec field; moves are halved until within the
  tolerance); ``contour`` either value (every move is a G1: the XY biarcs "arcs" names are the
  plate programs'); ``dialect`` "linuxcnc" (its only value).

Refused, naming the field (settings this program cannot honour, never left out unsaid):
``program`` "xc" (the plate cams' XC rotary program), ``depth`` (the depth is the rib's, from
its top to the root), ``lead_radius`` (plunges and retracts run along the tool's axis, no lead
arcs), ``milling`` "conventional" (each finishing sweep is climb-milled for its side with M3),
``work_offset`` other than G54, ``line_numbers``, ``coolant`` (no M8 yet), and the interpolator's
and XC program's ``rotary_line``, ``rotary_speed_rpm`` and a ``sample_period`` other than its
default (no interpolator, no command table).

No interpolator: report.json's ``interpolator`` is None and there is no command table.  With the
report's ``summary`` the program's header also quotes its pressure angle, the checks' verdict and
the spec digest (taken from ``summary`` only); without it, that the checks are not stated.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

from cam_workbench.generators.bodies.indexing.spatial_kind import SpatialIndexerDesign
from cam_workbench.generators.checks.claims import checks_verdict
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec.machining import MachiningSection
from cam_workbench.generators.spec.params import params_of

from .atomic import OutputSet
from .gcode import GcodeWriter
from .gcode_spatial_indexer import LAMBDAS, SpatialProgram, spatial_program
from .machining_outputs import FILES, PROGRAMS

#: defaults of the [machining] fields left out (mm/min, mm, mm), as spatial_program has them
DEFAULT_FEED, DEFAULT_SAFE_HEIGHT, DEFAULT_TOLERANCE = 150.0, 5.0, 0.005
#: the largest A step of a sweep [deg] (spatial_program's default; no spec field)
STEP_DEG = 1.0
#: the program's file (report.json ``files["gcode"]``)
FILE = FILES["gcode"]
#: the first block after spatial_program's header comments (the report's lines go before it)
_FIRST_BLOCK = "G21 "


@dataclass
class SpatialMachiningOutputs:
    """A spatial indexer's machining output: the generating program (``cam.nc``) and the report
    section (no second program, no interpolator, no command table)."""

    program: SpatialProgram
    gcode: str
    machining_summary: dict[str, Any]
    interpolator_summary: Any = None
    second_gcode: str | None = None

    @property
    def commands_csv(self) -> str:
        raise SpecError("--mode", "a spatial indexer has no interpolator command table (its cam is cut by the "
                        "4-axis generating program, cam.nc)")

    @property
    def files(self) -> dict[str, str]:
        """report.json ``files``: ``gcode`` the program."""
        return {"gcode": FILE}

    def write(self, out: OutputSet) -> None:
        """Add ``cam.nc`` to ``out`` (committed with the others, or not at all)."""
        out.add_text(FILE, self.gcode)


def _refuse_unsupported(spec: Any) -> None:
    mc = spec.machining
    if mc.program != "xy":
        raise SpecError("machining.program", f'"{mc.program}": a spatial indexer\'s cam is cut by its own 4-axis '
                        "generating program; leave machining.program at its default")
    if mc.depth is not None:
        raise SpecError("machining.depth", "a spatial indexer's cut reaches from the rib's top to its root "
                        "(indexer.root_radius): leave it out")
    if mc.lead_radius is not None:
        raise SpecError("machining.lead_radius", "a spatial indexer's program plunges and retracts along the tool's "
                        "axis, without lead arcs: leave it out")
    if mc.milling != "climb":
        raise SpecError("machining.milling", f'"{mc.milling}": a spatial indexer\'s finishing sweeps are each '
                        'climb-milled for their roller side with M3 ("climb")')
    if mc.work_offset != "G54":
        raise SpecError("machining.work_offset", f"{mc.work_offset}: a spatial indexer's program uses G54 only")
    if mc.line_numbers:
        raise SpecError("machining.line_numbers", "a spatial indexer's program is written without block numbers")
    if mc.coolant:
        raise SpecError("machining.coolant", "a spatial indexer's program does not switch coolant (M8) yet")
    if mc.rotary_line is not None:
        raise SpecError("machining.rotary_line", "applies to the XC program of a plate cam; a spatial indexer's "
                        "program has no tool line: leave it out")
    if mc.rotary_speed_rpm is not None:
        raise SpecError("machining.rotary_speed_rpm", "applies to the interpolator; a spatial indexer has none "
                        "(G93 feeds relative to the cam instead): leave it out")
    if mc.sample_period != params_of(MachiningSection)["sample_period"].default:
        raise SpecError("machining.sample_period", "applies to the interpolator; a spatial indexer has none: "
                        "leave it out")


def program_options(spec: Any) -> dict[str, Any]:
    """The keywords of :func:`~cam_workbench.exporters.gcode_spatial_indexer.spatial_program` from
    the spec's ``[machining]`` (module docstring; mm, mm/min, rpm, deg).

    Raises:
        SpecError: a field the program cannot honour, named (``machining.<field>``)."""
    _refuse_unsupported(spec)
    mc = spec.machining
    feed = DEFAULT_FEED if mc.feed_rate is None else float(mc.feed_rate)
    return {
        "tool_radius": None if mc.tool_radius is None else float(mc.tool_radius),
        "feed": feed,
        "plunge_feed": feed / 3.0 if mc.plunge_rate is None else float(mc.plunge_rate),
        "passes": None if int(mc.passes) == 1 else int(mc.passes),
        "step_deg": STEP_DEG,
        "tolerance": DEFAULT_TOLERANCE if mc.chord_tolerance is None else float(mc.chord_tolerance),
        "spindle_rpm": float(mc.spindle_rpm),
        "tool_number": int(mc.tool_number),
        "safe_height": DEFAULT_SAFE_HEIGHT if mc.safe_height is None else float(mc.safe_height),
    }


def report_comments(summary: Mapping[str, Any] | None) -> list[str]:
    """The header's comment lines quoting report.json (``summary``'s numbers only): the pressure
    angle [deg] with its limit, the checks' verdict and the spec digest; without ``summary``, that
    the checks are not stated."""
    w = GcodeWriter(False)
    if summary is None:
        w.comment("design checks: not stated [program written without the report summary]")
        return w.lines[1:]
    pa = summary["pressure_angle"]
    checks = summary["checks"]
    limit = checks["results"]["pressure_angle"]["limit"]
    at = "" if pa["at_deg"] is None else f" at {pa['at_deg']:.2f} deg"
    lim = "" if limit is None else f" [limit {limit:g} deg]"
    w.comment(f"pressure angle: max {pa['max_deg']:.2f} deg{at}{lim}")
    w.comment(checks_verdict(checks))
    w.comment(f"spec digest: {summary['spec_digest']}")
    return w.lines[1:]


def program_text(prog: SpatialProgram, summary: Mapping[str, Any] | None) -> str:
    """``prog``'s text with :func:`report_comments` at the end of its header."""
    lines = prog.text.split("\n")
    at = next(i for i, line in enumerate(lines) if line.startswith(_FIRST_BLOCK))
    return "\n".join(lines[:at] + report_comments(summary) + lines[at:])


@PROGRAMS.register(SpatialIndexerDesign)
def spatial_indexer_outputs(design: SpatialIndexerDesign, summary: dict[str, Any] | None = None
                            ) -> SpatialMachiningOutputs:
    """The generating program of a barrel or globoidal indexer's cam and report.json's ``machining``
    (mm, deg, mm/min); ``summary`` is the report's summary so far (the header quotes its numbers).

    Raises:
        SpecError: a ``[machining]`` setting the program cannot honour (module docstring), or one
            :func:`~cam_workbench.exporters.gcode_spatial_indexer.spatial_program` refuses (a tool
            larger than the roller, a tolerance too small for 4-decimal words).
        SolveError: no roller side engaged, or the cutter never clear of the blank.
    """
    opts = program_options(design.spec)
    prog = spatial_program(design.geometry, **opts)
    text = program_text(prog, summary)
    barrel = prog.kind == "barrel"
    generating = prog.summary()
    generating.pop("lines")                 # the file's lines are gcode_lines (the report's lines added)
    mach: dict[str, Any] = {
        "program": "generating 4-axis",
        "dialect": "linuxcnc",
        "file": FILE,
        "axes": "X Y Z A C words, LinuxCNC trivkins XYZAC, A and C unwrapped; "
                + ("X Y A cut, Z steps between depth levels, C turns the vertical tool about its own axis only "
                   "[drop it on an X-Y-Z-A mill]" if barrel else
                   "X Y A C cut, Z = 0; C swivels the horizontal tool about the vertical through its tip"),
        "what": "a generating program: a flat end mill in place of roller 0 follows the roller's motion relative "
                "to the cam over about two turns of the cam, so one sweep cuts every roller's groove; roughing "
                "sweeps at equal depth levels from the rib's top to its root, then one finishing sweep per roller "
                "side at the final depth, each climb-milled for its side",
        "frames": "machine = cam.step's frame renamed [at A = 0]: X = its z along the cam axis, Y = its x from the "
                  "cam axis towards the turret axis, Z = its y up along the turret axis; origin = cam.step's: on "
                  "the cam axis, X0 on the cam's end face z = 0 [the cam spans X = 0 to cam.thickness, the turret "
                  "axis is the vertical X = cam.thickness/2, Y = the centre distance: generating.cam_x_range_mm, "
                  "generating.turret_axis_xy_mm]; A = the input angle [deg, the cam turned about +X], C = the "
                  "turret angle [deg, clockwise seen from +Z]; X Y Z = the tool tip",
        "tool_radius": prog.tool_radius,
        "tool_number": opts["tool_number"],
        "roller_radius": prog.roller_radius,
        "stock": prog.stock,
        "spindle_rpm": opts["spindle_rpm"],
        "feed_rate": prog.feed,
        "plunge_rate": prog.plunge_feed,
        "feed_mode": "G93 inverse time: the cutter's axis ends travel relative to the cam at feed_rate",
        "passes": len(prog.levels),
        "safe_height": opts["safe_height"],
        "milling": "climb",
        "chord_tolerance": prog.tolerance,
        "g64_p": prog.blend,
        "step_deg": opts["step_deg"],
        "gcode_lines": text.count("\n"),
        "path_error": {"value": prog.chord_error, "unit": "mm", "tolerance": prog.tolerance,
                       "limit": prog.budget, "points_per_move": LAMBDAS + 1,
                       "what": f"the cutter's axis as written [4 decimals, interpolated linearly as LinuxCNC does] "
                               f"vs roller 0's exact axis at the input angle A, over the axis' reach, {LAMBDAS + 1} "
                               "points per move; G64 P blending on top, within the tolerance"},
        "exact": "nothing: linear moves within path_error of the roller's exact motion",
        "generating": generating,
    }
    return SpatialMachiningOutputs(prog, text, mach)


__all__ = ["DEFAULT_FEED", "DEFAULT_SAFE_HEIGHT", "DEFAULT_TOLERANCE", "FILE", "STEP_DEG",
           "SpatialMachiningOutputs", "program_options", "program_text", "report_comments",
           "spatial_indexer_outputs"]

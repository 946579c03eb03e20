"""A parallel indexer's machining outputs: one LinuxCNC XY finishing-contour program per cam plate
(``cam0.nc``, ``cam1.nc``, …: :func:`cam_workbench.exporters.gcode_indexer.indexer_programs`) and
report.json's ``machining`` section, registered in
:data:`cam_workbench.exporters.machining_outputs.PROGRAMS` for
:class:`~cam_workbench.generators.bodies.indexing.parallel_kind.ParallelIndexerDesign`.

``[machining]`` → the programs: ``tool_radius`` (default the roller radius, as for a plate cam),
``tool_number``, ``spindle_rpm``, ``feed_rate`` (default 300 mm/min), ``depth`` (default the
plate's thickness), ``safe_height`` (default 5 mm), ``chord_tolerance`` (default 0.005 mm: the
written path's measured distance from the exact tool-centre path, the rest ``G64 P``),
``lead_radius`` (default the tool radius) and ``milling``.  The plates are cut by XY contouring
only; settings these programs cannot honour are refused naming the field (``program`` "xc",
``contour`` "lines", ``passes`` > 1, a ``plunge_rate`` other than feed_rate/3, a ``work_offset``
other than G54, ``line_numbers``, ``coolant``) rather than left out of the program unsaid.

No interpolator (the cams are not turned against a follower line): report.json's
``interpolator`` is None and there is no command table.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from cam_workbench.generators.bodies.indexing.parallel_kind import ParallelIndexerDesign
from cam_workbench.generators.errors import SpecError

from .atomic import OutputSet
from .gcode_indexer import IndexerProgram, indexer_programs
from .machining_outputs import PROGRAMS

#: defaults of the [machining] fields left out (mm, mm/min), as the plate cams' XY program has them
DEFAULT_FEED, DEFAULT_SAFE_HEIGHT, DEFAULT_TOLERANCE = 300.0, 5.0, 0.005


@dataclass
class IndexerMachiningOutputs:
    """A parallel indexer's machining output: one program per cam plate and the report section.

    ``gcode`` is the first plate's program and ``second_gcode`` the second's (what ``cam-workbench
    gcode`` prints, ``--cam second`` the second plate); ``write`` adds every plate's file."""

    programs: tuple[IndexerProgram, ...]
    machining_summary: dict[str, Any]
    interpolator_summary: Any = None

    @property
    def gcode(self) -> str:
        return self.programs[0].text

    @property
    def second_gcode(self) -> str | None:
        return self.programs[1].text if len(self.programs) > 1 else None

    @property
    def commands_csv(self) -> str:
        raise SpecError("--mode", "a parallel indexer has no interpolator command table (its plates are cut by XY "
                        "contour programs, cam0.nc, cam1.nc, …)")

    @property
    def files(self) -> dict[str, str]:
        """report.json ``files``: ``gcode`` the first plate's program, ``gcode_cam<k>`` the others'."""
        return {("gcode" if p.cam == 0 else f"gcode_cam{p.cam}"): p.name for p in self.programs}

    def write(self, out: OutputSet) -> None:
        for p in self.programs:
            out.add_text(p.name, p.text)


def _refuse_unsupported(spec: Any) -> None:
    mc = spec.machining
    if mc.program != "xy":
        raise SpecError("machining.program", f'"{mc.program}": a parallel indexer\'s plates are cut by XY contour '
                        'programs only ("xy")')
    if mc.contour != "arcs":
        raise SpecError("machining.contour", f'"{mc.contour}": a parallel indexer\'s contour programs are written '
                        'with G02/G03 arcs only ("arcs")')
    if mc.passes != 1:
        raise SpecError("machining.passes", f"{mc.passes}: a parallel indexer's plate is cut in one pass to "
                        "machining.depth")
    feed = DEFAULT_FEED if mc.feed_rate is None else float(mc.feed_rate)
    if mc.plunge_rate is not None and not math.isclose(mc.plunge_rate, feed / 3.0, rel_tol=1e-12):
        raise SpecError("machining.plunge_rate", f"a parallel indexer's programs plunge at feed_rate/3 = "
                        f"{feed / 3.0:g} mm/min: leave it out")
    if mc.work_offset != "G54":
        raise SpecError("machining.work_offset", f"{mc.work_offset}: a parallel indexer's programs use G54 only")
    if mc.line_numbers:
        raise SpecError("machining.line_numbers", "a parallel indexer's programs are written without block numbers")
    if mc.coolant:
        raise SpecError("machining.coolant", "a parallel indexer's programs do not switch coolant (M8) yet")


def program_options(spec: Any) -> dict[str, Any]:
    """The keywords of :func:`~cam_workbench.exporters.gcode_indexer.indexer_programs` from the
    spec's ``[machining]`` (tool radius included; SpecError naming a field it cannot honour)."""
    _refuse_unsupported(spec)
    mc = spec.machining
    return {
        "tool_radius": float(spec.follower.roller_radius if mc.tool_radius is None else mc.tool_radius),
        "depth": None if mc.depth is None else float(mc.depth),
        "feed": DEFAULT_FEED if mc.feed_rate is None else float(mc.feed_rate),
        "tolerance": DEFAULT_TOLERANCE if mc.chord_tolerance is None else float(mc.chord_tolerance),
        "spindle_rpm": float(mc.spindle_rpm),
        "tool_number": int(mc.tool_number),
        "safe_height": DEFAULT_SAFE_HEIGHT if mc.safe_height is None else float(mc.safe_height),
        "lead_radius": None if mc.lead_radius is None else float(mc.lead_radius),
        "climb": mc.milling == "climb",
    }


@PROGRAMS.register(ParallelIndexerDesign)
def indexer_outputs(design: ParallelIndexerDesign, summary: dict[str, Any] | None = None
                    ) -> IndexerMachiningOutputs:
    """The cam plates' XY contour programs of a parallel indexer and report.json's ``machining``.

    Raises:
        SpecError: a ``[machining]`` setting these programs cannot honour (module docstring), or
            one :func:`~cam_workbench.exporters.gcode_indexer.indexer_programs` refuses (a tool
            too large for a concave flank, a tolerance too small for 4 decimals, …).
    """
    opts = program_options(design.spec)
    rt = opts.pop("tool_radius")
    programs = tuple(indexer_programs(design.geometry, design.cams_body, rt, **opts))
    lead = rt if opts["lead_radius"] is None else opts["lead_radius"]
    plates = [{**p.summary(), "gcode_lines": p.text.count("\n")} for p in programs]
    worst = max(programs, key=lambda p: p.path_error)
    mach: dict[str, Any] = {
        "program": "xy",
        "dialect": "linuxcnc",
        "what": "one XY finishing-contour program per cam plate, each plate cut alone from its own blank in the cam "
                "frame at input angle 0 (origin on the input axis, +X towards the turret axis, Z0 on the plate's "
                "top face)",
        "files": [p.name for p in programs],
        "tool_radius": rt,
        "tool_number": opts["tool_number"],
        "tool_centre_offset": rt,
        "spindle_rpm": opts["spindle_rpm"],
        "feed_rate": opts["feed"],
        "plunge_rate": opts["feed"] / 3.0,
        "depth": programs[0].depth,
        "passes": 1,
        "safe_height": opts["safe_height"],
        "lead_radius": lead,
        "milling": "climb" if opts["climb"] else "conventional",
        "chord_tolerance": programs[0].tolerance,
        "g64_p": programs[0].blend,
        "gcode_lines": sum(p["gcode_lines"] for p in plates),
        # the written contour (rounded, as LinuxCNC interpolates it) vs the exact tool-centre path: the
        # exact profile offset outward by the tool radius (dwell arc, flank offsets, the arc round the tip)
        "path_error": {"value": worst.path_error, "cam": worst.cam, "unit": "mm",
                       "tolerance": programs[0].tolerance,
                       "what": "the written contour (4 decimals, as interpolated) vs the exact tool-centre path "
                               "(the exact profile offset outward by the tool radius), measured two-sided"},
        "biarc_error": {"value": max(p.biarc_error for p in programs), "unit": "mm",
                        "what": "the flanks' G02/G03 biarcs vs the exact flank offset, before rounding"},
        "exact": "the dwell arcs (G02/G03 about the input axis) and the tip arcs; the flanks are biarcs within "
                 "biarc_error",
        "min_concave_radius": min(p.min_concave_radius for p in programs),
        "plates": plates,
    }
    return IndexerMachiningOutputs(programs, mach)

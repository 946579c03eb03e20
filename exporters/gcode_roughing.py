"""The XY program that makes a plate cam from a round blank: the roughing passes of
:mod:`cam_workbench.generators.machining.roughing` at every depth level, then the finishing contour
of :mod:`cam_workbench.generators.machining.toolpath` (as ``contour_program`` writes it), in one
program — the header, blocks and dialect of :mod:`cam_workbench.exporters.gcode`.

Per depth level: a rapid to the plunge point outside the blank on the entry ray, the plunge,
the in-feed along the ray to the outermost pass, each pass (G01 chords of the level set, G02/G03
arcs on the circle where the tool only touches the blank), a step-in along the ray to the next
pass, and the retract.  Tool-centre coordinates (G40): the passes' offsets include the tool
radius.  The header states the roughing and the whole program's time estimate
(:func:`cam_workbench.generators.machining.cutting_time.contour_time`, as report.json).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

from cam_workbench.generators.cam_design import CamDesign
from cam_workbench.generators.machining import MachiningPlan
from cam_workbench.generators.machining.cutting_time import ContourTime, contour_time, roughing_time
from cam_workbench.generators.machining.roughing import RoughingPath, roughing_path
from cam_workbench.generators.machining.toolpath import ContourPath, contour_path

from .gcode import (GCODE_DECIMALS, cam_comments, exact_word, finishing_passes, fmt, move_blocks, program_footer,
                    program_header, writer_for, xy_words)


def roughing_program(design: CamDesign, plan: MachiningPlan, rough: RoughingPath, path: ContourPath,
                     times: tuple[ContourTime, ContourTime], *, summary: Mapping[str, Any] | None = None,
                     which: str | None = None) -> str:
    """The roughing-then-finishing XY program (text); ``times``: (roughing, whole program) time
    estimates; ``summary`` and ``which`` as for :func:`cam_workbench.exporters.gcode.contour_program`."""
    u = plan.units
    d = GCODE_DECIMALS[u]
    w = writer_for(plan)
    cam_comments(w, design, plan, "XY roughing from a round blank, then contour milling", summary, which=which)
    rough_t, whole_t = times
    w.comment(f"blank: diameter {2 * rough.blank_radius:g} {u} on the cam axis; roughing "
              f"{len(rough.passes)} concentric pass[es] per level, step-over {rough.stepover:g} {u}, leaving "
              f"{rough.allowance:g} {u} on the profile")
    w.comment(f"roughing tool centre from {fmt(rough.passes[0].offset, d)} to {fmt(rough.passes[-1].offset, d)} {u} "
              "from the profile")
    w.comment(f"roughing passes: G01 chords within {rough.tolerance:g} {u} of the {exact_word(design)}offsets, "
              f"G02/G03 on the circle r = {fmt(rough.blank_radius + plan.tool_radius, d)} {u} where the tool only "
              f"touches the blank; plunge outside the blank at {rough.entry_angle_deg:.2f} deg, step-in along that ray")
    kind = "G02/G03 biarcs" if plan.contour == "arcs" else "G01 chords"
    w.comment(f"finishing contour: {path.loop.n} moves as {kind} [{path.n_arcs} arcs, {path.n_lines} lines], max "
              f"distance from the {exact_word(design)}tool-centre path {path.max_distance:.3g} {u}, tolerance "
              f"{path.tolerance:g} {u}")
    w.comment(f"{plan.milling} milling, {'clockwise' if path.clockwise else 'counter-clockwise'}, "
              f"entry at cam angle {path.entry_angle_deg:.2f} deg on lead arcs of radius {plan.lead_radius:g} {u}; "
              f"{plan.passes} level[s] to depth {plan.depth:g} {u}")
    w.comment(f"time estimate: roughing {rough_t.time:.1f} s, whole program {whole_t.time:.1f} s "
              "[feed moves and blocks; rapids excluded]")
    program_header(w, plan)
    safe = w.num(plan.safe_height, d)
    feed = f" F{w.num(plan.feed_rate, 3)}"
    w.block(f"G0 Z{safe}")
    levels = rough.z_levels.shape[0]
    for level, z in enumerate(rough.z_levels, start=1):
        w.comment(f"roughing level {level} of {levels} at Z{fmt(z, d)}")
        w.block(f"G0 {xy_words(w, rough.approach, d)}")
        w.block(f"G1 Z{w.num(z, d)} F{w.num(plan.plunge_rate, 3)}")
        w.comment("in-feed")
        w.block(f"G1 {xy_words(w, rough.passes[0].loop.start[0], d)}{feed}")
        for k, p in enumerate(rough.passes):
            w.comment(f"rough pass {k + 1} of {len(rough.passes)}: {fmt(p.offset, d)} {u} from the profile")
            for line in move_blocks(w, p.loop, d):
                w.block(line)
            if k + 1 < len(rough.passes):
                w.comment("step-in")
                w.block(f"G1 {xy_words(w, rough.passes[k + 1].loop.start[0], d)}")
        w.block(f"G0 Z{safe}")
    finishing_passes(w, plan, path, d)
    program_footer(w, plan)
    return w.text()


@dataclass(frozen=True)
class RoughedContour:
    """The roughing passes and the finishing contour of one XY program, with its time estimates."""

    rough: RoughingPath
    finish: ContourPath
    rough_time: ContourTime
    whole_time: ContourTime

    def summary(self) -> dict[str, Any]:
        """report.json ``machining.xy``: the finishing contour's numbers and ``roughing``."""
        return {**self.finish.summary(),
                "roughing": {**self.rough.summary(), "time_s": self.rough_time.time,
                             "program_time_s": self.whole_time.time}}


def roughing_xy_program(design: CamDesign, plan: MachiningPlan, *, summary: Mapping[str, Any] | None = None,
                        which: str | None = None) -> tuple[str, RoughedContour]:
    """(the roughing-then-finishing program's text, its paths and times) of ``design`` from
    ``machining.blank_diameter``; ``summary`` and ``which`` as for :func:`roughing_program`."""
    rough = roughing_path(design, plan)
    finish = contour_path(design, plan)
    bt = design.spec.optimise.block_time
    both = RoughedContour(rough, finish, roughing_time(rough, plan, bt), contour_time(design, plan, bt))
    return roughing_program(design, plan, rough, finish, (both.rough_time, both.whole_time), summary=summary,
                            which=which), both

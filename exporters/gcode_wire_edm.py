"""The 2-axis wire EDM program of a plate cam (LinuxCNC's RS274/NGC; the geometry and the order of
the cuts: :mod:`cam_workbench.generators.machining.wire_edm`).

XY only — no Z word, no plunge: the wire is threaded through the plate.  LinuxCNC has no wire
EDM words, so the program uses stand-ins a LinuxCNC-driven EDM maps to its generator: **M3 /
M5 = generator (spark) on / off** and **M8 / M9 = flushing on / off**; ``F`` is
``machining.feed_rate``, the most the generator's gap servo may feed.  M00 stops before the tab
cut so the part can be secured.  ``wire_compensation = "controller"``: G41.1 (the main cut runs
clockwise, the wire on the left of the part contour) with ``D`` = 2 × (wire radius + spark gap),
LinuxCNC's compensation by a diameter given in the block, switched on along the straight lead-in
and off (G40) at the end.
"""
from __future__ import annotations

import dataclasses
from typing import Any, Mapping

from cam_workbench.generators.cam_design import CamDesign
from cam_workbench.generators.machining import MachiningPlan
from cam_workbench.generators.machining.toolpath import BLEND_SHARE
from cam_workbench.generators.machining.wire_edm import WireEdmPath

from .gcode import GCODE_DECIMALS, cam_comments, exact_word, fmt, move_blocks, writer_for, xy_words


def wire_edm_program(design: CamDesign, plan: MachiningPlan, path: WireEdmPath, *,
                     summary: Mapping[str, Any] | None = None) -> str:
    """The wire EDM program (text); ``summary`` as for
    :func:`cam_workbench.exporters.gcode.contour_program`."""
    u = plan.units
    d = GCODE_DECIMALS[u]
    w = writer_for(plan)
    controller = path.compensation == "controller"
    final = path.final_offset
    comp_text = (f"G41.1 D{fmt(2 * final, d + 1)}: the control offsets the part contour by the wire radius + "
                 "spark gap" if controller else "no cutter compensation [the program carries the wire path]")
    wire = dataclasses.replace(plan, tool_radius=path.wire_radius)     # the header's "tool" is the wire
    cam_comments(w, design, wire, "2-axis wire EDM", summary,
                  tool_text=(f"the wire, spark gap {path.spark_gap:g} {u}: "
                             f"wire centre {fmt(final, d + 1)} {u} from the profile"),
                  compensation_text=comp_text)
    skims = len(path.cuts) - 2
    w.comment(f"cuts: main at {fmt(path.cuts[0].offset, d + 1)} {u} from the profile, {skims} skim[s] each "
              f"{path.skim_stock:g} {u} closer and reversing direction, the tab at "
              f"{fmt(path.cuts[-1].offset, d + 1)} {u}")
    w.comment(f"{'part contour' if controller else 'wire path'}: G02/G03 biarcs or G01 chords within "
              f"{path.max_distance:.3g} {u} of the {exact_word(design)}offsets, tolerance {path.tolerance:g} {u}")
    w.comment(f"start hole at X{fmt(path.start_hole.real, d)} Y{fmt(path.start_hole.imag, d)}; entry at cam angle "
              f"{path.entry_angle_deg:.2f} deg; main cut clockwise; holding tab {path.tab_width:g} {u} along the wire "
              "path, cut last")
    w.comment("stand-ins: M3/M5 generator on/off, M8/M9 flushing on/off; F = the most the gap servo may feed")
    dia = w.dialect
    w.block(f"{dia.units[plan.units]} {dia.modal}")
    w.block(plan.work_offset)
    blend = dia.blending(BLEND_SHARE * plan.chord_tolerance, d + 1)
    if blend is not None:
        w.block(blend)
    w.comment("start hole: thread the wire here")
    w.block(f"G0 {xy_words(w, path.start_hole, d)}")
    w.block("M8")
    w.block("M3")
    w.comment("lead-in")
    lead = f"G1 {xy_words(w, path.entry, d)} F{w.num(plan.feed_rate, 3)}"
    w.block(f"G41.1 D{w.num(2 * final, d + 1)} {lead}" if controller else lead)
    for cut in path.cuts:
        if cut.role == "tab":
            w.comment("stop: secure the part before the tab is cut")
            w.block("M0")
        if cut.link is not None:
            w.comment(f"onto the {cut.role} path")
            w.block(f"G1 {xy_words(w, cut.link, d)}")
        w.comment("tab" if cut.role == "tab" else f"{cut.role} cut" if cut.role == "main" else cut.role)
        for line in move_blocks(w, cut.moves, d):
            w.block(line)
    if controller:
        w.block("G40")
    w.block("M5")
    w.block("M9")
    w.block("M30")
    return w.text()

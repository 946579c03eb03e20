"""A cylindrical cam's machining outputs: the 4-axis X-Z-A groove program (``cam.nc``,
:func:`cylindrical_program`) and its report section, registered in
:data:`cam_workbench.exporters.machining_outputs.PROGRAMS` for :class:`~cam_workbench.generators.bodies.cylindrical.CylindricalDesign`.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

from cam_workbench.generators import __version__
from cam_workbench.generators.bodies.cylindrical import CylindricalDesign
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.machining.cylindrical import cylindrical_path
from cam_workbench.generators.machining.toolpath import BLEND_SHARE

from .atomic import OutputSet
from .gcode import GCODE_DECIMALS, UNITS_WORD, GcodeWriter, fmt
from .machining_outputs import FILES, PROGRAMS


@dataclass
class CylindricalMachiningOutputs:
    """A cylindrical cam's machining output: the 4-axis X-Z-A program (``cam.nc``) and its report
    section (no interpolator, no command table: the cam is not turned against a follower line)."""

    path: Any
    gcode: str
    machining_summary: dict[str, Any]
    interpolator_summary: Any = None
    second_gcode: str | None = None

    @property
    def commands_csv(self) -> str:
        raise SpecError("--mode", "a cylindrical cam has no interpolator command table (its program is the 4-axis "
                        "X-Z-A one)")

    @property
    def files(self) -> dict[str, str]:
        return {"gcode": FILES["gcode"]}

    def write(self, out: OutputSet) -> None:
        out.add_text(FILES["gcode"], self.gcode)


@PROGRAMS.register(CylindricalDesign)
def cylindrical_outputs(design: Any, summary: dict[str, Any] | None = None
                        ) -> CylindricalMachiningOutputs:
    """The groove program of a cylindrical cam (:mod:`cam_workbench.generators.machining.cylindrical`)."""
    path = cylindrical_path(design)
    gcode = cylindrical_program(design, path, summary=summary)
    return CylindricalMachiningOutputs(path, gcode, {**path.summary(), "gcode_lines": gcode.count("\n")})


def cylindrical_program(design: Any, path: Any, *, summary: Mapping[str, Any] | None = None) -> str:
    """The 4-axis X-Z-A program that mills a cylindrical cam's groove (text): the cam's axis along
    X, the tool's axis radial along Z (Z = the tool tip's distance from the cam axis), A the cam's
    rotation [deg]; at every depth level the passes of ``path``
    (:class:`cam_workbench.generators.machining.cylindrical.CylindricalPath`), the two walls last, each a full
    turn of G1 moves in inverse time (G93: F = 1 / the move's time, the feed along the developed
    path at the pitch radius), entered by a plunge at the middle of the longest dwell."""
    spec = design.spec
    lay = design.layout
    u = path.units
    d = GCODE_DECIMALS[u]
    w = GcodeWriter(path.line_numbers)
    w.comment(f"cam_workbench {__version__}: cylindrical cam, 4-axis X-Z-A groove milling")
    w.comment(f"cylinder: pitch radius {lay.pitch_radius:g} {u}, outer radius {lay.outer_radius:g} {u}, length "
              f"{lay.length:g} {u}, {spec.cam.direction}; groove {path.groove_width:g} {u} wide to radius "
              f"{lay.bottom_radius:g} {u}")
    oscillating = lay.path.pivoted
    lu = "deg of arm" if oscillating else u
    motion = " / ".join(f"{m.kind} {m.angle:g} deg" + (f" {m.lift:g} {lu} {m.law}" if m.lift is not None else "")
                        for m in spec.motion)
    w.comment(f"motion: {motion}")
    if oscillating:
        w.comment(f"follower: oscillating roller, radial pivot {lay.path.pivot_distance:g} {u} upstream along the "
                  f"circumference, arm {lay.path.arm_length:g} {u}: the tool follows the roller centre's developed arc")
    w.comment("machine: X along the cam axis [X = cam z], Z radial [tool tip distance from the cam axis, Z0 on "
              "the axis], A = cam rotation in deg [A = theta for a ccw cam]; the tool stands where the roller does")
    w.comment(f"tool radius {path.tool_radius:g} {u}; {len(path.passes)} passes per level at tool-centre offsets "
              + ", ".join(fmt(p.offset, d) for p in path.passes) + f" {u} from the developed pitch curve")
    w.comment(f"G1 chords within {max(p.chord_error for p in path.passes):.3g} {u} of the tool-centre paths "
              f"[tolerance {path.chord_tolerance:g} {u}]; finishing walls within "
              f"{max(path.finish_wall_deviation['bottom_radius'], path.finish_wall_deviation['outer_radius']):.3g} "
              f"{u} of the exact walls; plunge at cam angle {path.entry_deg:.2f} deg")
    if summary is not None and isinstance(summary.get("body"), Mapping):
        we = summary["body"].get("wall_error")
        if isinstance(we, Mapping):
            w.comment(f"solid: wall faces within {we['value']:.3g} {u} of the exact walls")
    w.block(f"{UNITS_WORD[u]} G90 G17 G40 G49 G80 G94")
    w.block(path.work_offset)
    w.block(f"G64 P{fmt(BLEND_SHARE * path.chord_tolerance, d + 1)}")
    w.block(f"T{path.tool_number} M6")
    w.block(f"G43 H{path.tool_number}")
    w.block(f"S{fmt(path.spindle_rpm, 1)} M3")
    if path.coolant:
        w.block("M8")
    safe = fmt(path.safe_z, d)
    w.block(f"G0 Z{safe}")
    rp = lay.pitch_radius
    for level, z in enumerate(path.z_levels, start=1):
        for k, p in enumerate(path.passes, start=1):
            w.comment(f"level {level}, pass {k}: {p.role.replace('_', ' ')} [offset {fmt(p.offset, d)}]")
            a0 = p.a[0]
            w.block(f"G0 X{fmt(p.x[0], d)} A{fmt(a0, d)}")
            w.block("G93")
            w.block(f"G1 Z{fmt(z, d)} F{fmt(path.plunge_rate / max(path.safe_z - z, 1e-9), 5)}")
            dx = np.diff(p.x)
            da = np.deg2rad(np.diff(p.a))
            length = np.hypot(dx, rp * da)
            inv = path.feed_rate / np.maximum(length, 1e-9)
            for x, a, f in zip(p.x[1:], p.a[1:], inv):
                w.block(f"G1 X{fmt(x, d)} A{fmt(a, d)} F{fmt(f, 3)}")
            w.block("G94")
            w.block(f"G0 Z{safe}")
    if path.coolant:
        w.block("M9")
    w.block("M5")
    w.block("M30")
    return w.text()

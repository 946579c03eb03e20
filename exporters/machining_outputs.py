"""Everything ``build`` writes about machining, computed before anything is written:
the G-code program (``cam.nc``), the command table (``commands.csv``), the interpolator
plots, and the ``interpolator`` and ``machining`` sections of report.json.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from generators.cam_design import CamDesign
from generators.machining.interpolator import InterpolatorAccuracy, interpolator_accuracy
from generators.machining import MachiningPlan, machining_plan
from generators.machining.toolpath import contour_path, rotary_path, tool_centre_fit_error

from .atomic import OutputSet
from .commands_csv import commands_csv_text
from .gcode import contour_program, groove_program, rotary_program
from .interpolator_plots import PLOT_FILES, deviation_figure, kinematics_figure, write_png

FILES = {"gcode": "cam.nc", "commands": "commands.csv"}


@dataclass
class MachiningOutputs:
    """Texts and figures ready to be committed, and their report sections."""

    plan: MachiningPlan
    accuracy: InterpolatorAccuracy
    gcode: str
    commands_csv: str
    figures: dict[str, Any] = field(repr=False)
    interpolator_summary: dict[str, Any]
    machining_summary: dict[str, Any]

    @property
    def files(self) -> dict[str, str]:
        """report.json ``files`` entries."""
        out = dict(FILES)
        out.update({f"plot_{k}": PLOT_FILES[k] for k in self.figures})
        return out

    def write(self, out: OutputSet) -> None:
        """Add every file to ``out`` (committed with the others, or not at all)."""
        out.add_text(FILES["gcode"], self.gcode)
        out.add_text(FILES["commands"], self.commands_csv)
        for key, fig in self.figures.items():
            out.add(PLOT_FILES[key], lambda p, f=fig: write_png(f, p))


def machining_outputs(design: CamDesign, plots: bool = True, summary: dict[str, Any] | None = None
                      ) -> MachiningOutputs:
    """Compute the machining outputs of ``design`` (its spec's ``[machining]``); ``summary`` is
    the report's summary so far (the G-code header quotes its numbers).

    Raises:
        GeometryError: the tool would gouge the profile, or the XC line misses the tool path.
        SpecError: a machining setting cannot be met (lead radius, sample period).
    """
    spec = design.spec
    plan = machining_plan(design)
    acc = interpolator_accuracy(design.pitch, plan.rotary_speed_rpm, plan.sample_period)
    if design.spec.cam.body == "groove":
        from generators.machining.groove import groove_path

        if plan.program != "xy":
            from generators.errors import SpecError

            raise SpecError("machining.program", 'a groove is milled with the XY program ("xy"); the XC rotary '
                            "program cuts a plate cam's outside profile")
        path = groove_path(design, plan)
        gcode = groove_program(design, plan, path, summary=summary)
    elif plan.program == "xy":
        path = contour_path(design, plan)
        gcode = contour_program(design, plan, path, summary=summary)
    else:
        path = rotary_path(design, plan, acc.commands)
        gcode = rotary_program(design, plan, path, summary=summary)
    interp = acc.summary()
    tol = spec.pitch.tolerance
    interp["pitch_tolerance"] = tol
    interp["within_pitch_tolerance"] = None if tol is None else bool(interp["max_deviation"] <= tol)
    mach: dict[str, Any] = {
        "program": plan.program,
        "dialect": plan.dialect,
        "tool_radius": plan.tool_radius,
        "tool_centre_offset": plan.centre_offset,
        "chord_tolerance": plan.chord_tolerance,
        "depth": plan.depth,
        "passes": plan.passes,
        "gcode_lines": gcode.count("\n"),
        # distance of the tool-centre curve from the exact offset of the pitch curve (0: exact)
        "tool_centre_fit_error": tool_centre_fit_error(design, plan),
        plan.program: path.summary(),
    }
    figures = {}
    if plots:
        figures = {
            "deviation": deviation_figure(acc, spec.units, design.pitch.deviation(),
                                          design.pitch.angles),
            "kinematics": kinematics_figure(acc, design.program, spec.units),
        }
    return MachiningOutputs(plan=plan, accuracy=acc, gcode=gcode,
                            commands_csv=commands_csv_text(acc.commands, spec.units), figures=figures,
                            interpolator_summary=interp, machining_summary=mach)

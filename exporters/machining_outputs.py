"""Everything ``build`` writes about machining, computed before anything is written:
the G-code program (``cam.nc``), the command table (``commands.csv``) and the ``interpolator`` and ``machining`` sections of report.json.

A conjugate pair gets two programs, one per cam, both of ``machining.program``: ``cam.nc``
cuts the first cam, ``cam2.nc`` the second — each as its own plate (Z0 on that cam's top face,
the cam frame seen from +Z, the same tool), the second's XC program on a line through the C
axis.  Report: ``machining.second_cam``.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, Callable, Mapping, Protocol

from cam_workbench.generators.cam_design import CamDesign
from cam_workbench.generators.kinds import own_tool_path
from cam_workbench.generators.kinds.by_class import ByClass
from cam_workbench.generators.machining.interpolator import InterpolatorAccuracy, interpolator_accuracy
from cam_workbench.generators.machining import MachiningPlan, machining_plan
from cam_workbench.generators.machining.plan import check_tool_fits
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.machining.toolpath import rotary_path, tool_centre_fit_error
from cam_workbench.generators.machining.wire_edm import wire_edm_path

from .atomic import OutputSet
from .commands_csv import commands_csv_text
from .gcode import groove_program, rotary_program, xy_program
from .gcode_roughing import roughing_xy_program
from .gcode_wire_edm import wire_edm_program

FILES = {"gcode": "cam.nc", "commands": "commands.csv"}
#: a conjugate pair's second cam's program
SECOND_FILE = "cam2.nc"


@dataclass
class MachiningOutputs:
    """Texts ready to be committed, and their report sections."""

    plan: MachiningPlan
    accuracy: InterpolatorAccuracy
    gcode: str
    commands_csv: str
    interpolator_summary: dict[str, Any]
    machining_summary: dict[str, Any]
    #: a conjugate pair's second cam's program (``cam2.nc``), else None
    second_gcode: str | None = None

    @property
    def files(self) -> dict[str, str]:
        """report.json ``files`` entries."""
        out = dict(FILES)
        if self.second_gcode is not None:
            out["gcode_second"] = SECOND_FILE
        return out

    def write(self, out: OutputSet) -> None:
        """Add every file to ``out`` (committed with the others, or not at all)."""
        out.add_text(FILES["gcode"], self.gcode)
        if self.second_gcode is not None:
            out.add_text(SECOND_FILE, self.second_gcode)
        out.add_text(FILES["commands"], self.commands_csv)


class BodyMachining(Protocol):
    """What a body's machining outputs are: made by a function registered in :data:`PROGRAMS` for
    its design class, ``fn(design, summary)``; they answer these members."""

    gcode: str
    interpolator_summary: Any
    machining_summary: dict[str, Any]
    second_gcode: str | None

    @property
    def commands_csv(self) -> str: ...

    @property
    def files(self) -> dict[str, str]: ...

    def write(self, out: OutputSet) -> None: ...


#: design class → ``fn(design, summary) -> BodyMachining`` (the plane cams' here; a body's
#: own in its module, imported by :mod:`cam_workbench.exporters` when it loads)
PROGRAMS: ByClass[Callable[..., BodyMachining]] = ByClass("the machining program")


def machining_outputs(design: Any, summary: dict[str, Any] | None = None) -> BodyMachining:
    """Compute the machining outputs of ``design`` (its spec's ``[machining]``), by its body's
    function in :data:`PROGRAMS`; ``summary`` is the report's summary so far (the G-code header
    quotes its numbers).

    Raises:
        GeometryError: the tool would gouge the profile, or the XC line misses the tool path.
        SpecError: a machining setting cannot be met (lead radius, sample period); a dialect or
            cutter compensation other than LinuxCNC's tool-centre programs for a body whose
            programs have no other (:data:`DIALECT_PROGRAMS`).
        NotAvailable: the design's body registers no machining program.
    """
    make = PROGRAMS.of(design)
    if make not in DIALECT_PROGRAMS:
        _linuxcnc_centre_only(design.spec)
    return make(design, summary=summary)


def _linuxcnc_centre_only(spec: Any) -> None:
    """Refuse ``machining.dialect`` / ``machining.compensation`` other than the defaults for a body
    whose programs are written for LinuxCNC on tool-centre paths only.

    Raises:
        SpecError: naming the field.
    """
    mc = spec.machining
    if mc.dialect != "linuxcnc":
        raise SpecError("machining.dialect", f'a {spec.cam.body} cam\'s programs are written for LinuxCNC only '
                        f'("linuxcnc"), got "{mc.dialect}"')
    if mc.compensation not in (None, "centre"):
        raise SpecError("machining.compensation", f'a {spec.cam.body} cam\'s programs run on tool-centre paths '
                        f'only ("centre"), got "{mc.compensation}"')


@PROGRAMS.register(CamDesign)
def plane_outputs(design: CamDesign, summary: dict[str, Any] | None = None
                  ) -> MachiningOutputs:
    """A plane cam's machining outputs: the contour (XY) or rotary (XC) program of its profile
    (a groove's passes along its own path), a conjugate pair's second program, the command table
    and the interpolator's accuracy (its figures are the report's)."""
    spec = design.spec
    plan = machining_plan(design)
    acc = interpolator_accuracy(design.pitch, plan.rotary_speed_rpm, plan.sample_period)
    own_path = own_tool_path(design.spec)
    if own_path is not None:                        # a body milled along its own path (a groove's passes)
        path = own_path(design, plan)
        gcode = groove_program(design, plan, path, summary=summary)
    elif plan.program == "wire_edm":
        path = wire_edm_path(design, plan)
        gcode = wire_edm_program(design, plan, path, summary=summary)
    elif plan.program == "xy" and spec.machining.blank_diameter is not None:
        gcode, path = roughing_xy_program(design, plan, summary=summary, which=_first_cam_words(design))
    elif plan.program == "xy":
        gcode, path = xy_program(design, plan, summary=summary, which=_first_cam_words(design))
    else:
        path = rotary_path(design, plan, acc.commands)
        gcode = rotary_program(design, plan, path, summary=summary, which=_first_cam_words(design))
    second = _second_cam_program(design, plan, acc, summary)
    interp = acc.summary()
    tol = spec.pitch.tolerance
    interp["pitch_tolerance"] = tol
    interp["within_pitch_tolerance"] = None if tol is None else bool(interp["max_deviation"] <= tol)
    mach: dict[str, Any] = {
        "program": plan.program,
        "dialect": plan.dialect,
        "compensation": plan.compensation,
        "tool_radius": plan.tool_radius,
        "tool_centre_offset": plan.centre_offset,
        "chord_tolerance": plan.chord_tolerance,
        "depth": plan.depth,
        "passes": plan.passes,
        "lead_radius": plan.lead_radius,
        "gcode_lines": gcode.count("\n"),
        # distance of the tool-centre curve from the exact offset of the pitch curve (0: exact)
        "tool_centre_fit_error": tool_centre_fit_error(design, plan),
        plan.program: path.summary(),
    }
    if second is not None:
        mach["second_cam"] = second[1]
    return MachiningOutputs(plan=plan, accuracy=acc, gcode=gcode,
                            commands_csv=commands_csv_text(acc.commands, spec.units),
                            interpolator_summary=interp, machining_summary=mach,
                            second_gcode=None if second is None else second[0])


#: the body programs written in every dialect of ``machining.dialect``, with either compensation
DIALECT_PROGRAMS = (plane_outputs,)


def second_cam_of(design: CamDesign) -> CamDesign | None:
    """The second cam of a body that has one (a conjugate pair), else None."""
    body = design.body
    return None if body is None else body.extra.get("second_cam")


def _first_cam_words(design: CamDesign) -> str | None:
    if second_cam_of(design) is None:
        return None
    return f"the first cam of the conjugate pair, 0 <= z <= {design.spec.cam.thickness:g}; the second is in {SECOND_FILE}"


def _second_cam_program(design: CamDesign, plan: MachiningPlan, acc: InterpolatorAccuracy,
                        summary: Mapping[str, Any] | None) -> tuple[str, dict[str, Any]] | None:
    """(``cam2.nc``'s text, ``machining.second_cam``) for a conjugate pair, else None: the
    second cam cut with the same tool and settings, its own roller's offset, the XC program on a
    line through the C axis.

    Raises:
        GeometryError: the tool would gouge the second cam.
    """
    second = second_cam_of(design)
    if second is None:
        return None

    spec = design.spec
    plan2 = dataclasses.replace(plan, roller_radius=second.follower.profile_offset, rotary_line="axis")
    check_tool_fits(second, plan2.tool_radius)
    s2 = None
    body = summary.get("body") if summary is not None else None
    if isinstance(body, Mapping) and isinstance(body.get("second_cam"), Mapping):
        s2 = {**body["second_cam"], "units": spec.units, "checks": summary.get("checks"),
              "spec_digest": summary.get("spec_digest")}
    # where the second cam is: report.json's body.second_cam.z (the spec's gap and thickness without it)
    z0, z1 = s2["z"] if s2 is not None else (-spec.conjugate.gap - spec.cam.thickness, -spec.conjugate.gap)
    which = (f"the second cam of the conjugate pair, {z0:g} <= z <= {z1:g}: cut as its own plate, Z0 on its "
             "top face [the face towards the first cam], the cam frame seen from +Z as for the first cam")
    if plan.program == "xy":
        text, path = xy_program(second, plan2, summary=s2, which=which)
    else:
        path = rotary_path(second, plan2, acc.commands)
        text = rotary_program(second, plan2, path, summary=s2, which=which)
    return text, {"file": SECOND_FILE, "roller_radius": plan2.roller_radius, "tool_radius": plan2.tool_radius,
                  "tool_centre_offset": plan2.centre_offset, "rotary_line": plan2.rotary_line
                  if plan.program == "xc" else None, "gcode_lines": text.count("\n"),
                  "tool_centre_fit_error": tool_centre_fit_error(second, plan2), plan.program: path.summary()}

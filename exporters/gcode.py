"""G-code programs for a designed cam, in the dialect of ``machining.dialect`` (LinuxCNC's RS274/NGC,
Fanuc-style or Siemens Sinumerik: :mod:`cam_workbench.exporters.gcode_dialects` holds every word that
differs; a writer made for a :class:`~cam_workbench.exporters.gcode_dialects.Dialect` writes them).

Programs from the geometry made in ``cam_workbench.generators.machining.toolpath`` (the exact
offset of the pitch curve for a PH pitch curve):

* ``xy`` — contour milling, ``machining.compensation = "centre"``: the tool-centre path (pitch
  curve offset by tool radius − roller radius) as G02/G03 biarcs or G01 chords, tangent lead
  arcs, depth passes;
* ``xy`` with ``"controller"``: the part's own contour (the profile) as biarcs or chords under the
  control's cutter compensation G41/G42 (D = tool number; the tool table holds the radius),
  switched on along a straight approach line before a tangent lead arc and off along a straight
  line after the lead-out arc;
* ``xc`` — rotary: the cam on a C axis, one G93 inverse-time block per interpolator
  command, so each block takes the sample period Δt (F = 1/Δt in 1/min);
* a groove's passes (tool-centre paths only).

Every program starts with comments — the cam's parameters and, given the summary dict that
becomes report.json (``summary=``), its spec digest, pitch deviation, profile error, largest
pressure angle and the design-checks verdict with the failed checks' names; without it only
what the design itself says, and no verdict — then a header (units G21/G20, G90, G17, G40,
G49, G80, G94, work offset, path blending (LinuxCNC's G64 P tolerance = 10 % of the chord
tolerance), tool change, tool-length offset, spindle), and ends with M5/M30.  Coordinates: 4
decimals in mm, 5 in inches; C in degrees with 4 decimals.
"""
from __future__ import annotations

from typing import Any, Callable, Iterable, Mapping

from cam_workbench.generators import __version__
from cam_workbench.generators.curves.approx import Path2D
from cam_workbench.generators.cam_design import CamDesign
from cam_workbench.generators.checks.claims import checks_verdict, pitch_text, profile_claim
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.machining import MachiningPlan, machining_plan
from cam_workbench.generators.machining.toolpath import (BLEND_SHARE, ContourPath, PartContourPath, RotaryPath,
                                                         contour_path, part_contour_path, rotary_path)

from .gcode_dialects import LINUXCNC, Dialect, dialect_of, fmt

MODES = ("xy", "xc")
GCODE_DECIMALS = {"mm": 4, "in": 5}
UNITS_WORD = LINUXCNC.units


class GcodeWriter:
    """Collects blocks in ``dialect`` (its opening and closing lines, comments and numbers);
    numbers them when asked (N10, N20, …); ``program_number``: the O word of a dialect that has one."""

    def __init__(self, numbered: bool, dialect: Dialect = LINUXCNC, program_number: int = 1000):
        self.dialect = dialect
        self.lines: list[str] = (["%"] if dialect.tape_marks else []) + (
            [f"O{program_number:04d}"] if dialect.program_number else [])
        self.numbered = numbered
        self.n = 0

    def block(self, text: str) -> None:
        if self.numbered:
            self.n += 10
            text = f"N{self.n} {text}"
        self.lines.append(text)

    def comment(self, text: str) -> None:
        self.block(self.dialect.comment(text))

    def num(self, value: float, decimals: int) -> str:
        """A coordinate or feed word's number in the dialect."""
        return self.dialect.number(value, decimals)

    def text(self) -> str:
        return "\n".join(self.lines + (["%"] if self.dialect.tape_marks else [])) + "\n"


def writer_for(plan: MachiningPlan) -> GcodeWriter:
    """A writer in ``plan``'s dialect (its line numbers and program number)."""
    return GcodeWriter(plan.line_numbers, dialect_of(plan.dialect), plan.program_number)


def exact_word(design: CamDesign) -> str:
    """ "exact " where the tool-centre path is the exact offset of a PH pitch curve, else "". """
    return "exact " if design.pitch.exact else ""


def cam_comments(w: GcodeWriter, design: CamDesign, plan: MachiningPlan, mode_text: str,
                  summary: Mapping[str, Any] | None = None, tool_text: str | None = None,
                  which: str | None = None, compensation_text: str = "no cutter compensation") -> None:
    spec = design.spec
    u = spec.units
    lu = "deg" if design.follower.lift_unit == "angle" else u
    w.comment(f"cam_workbench {__version__}: {design.spec.cam.body} cam, {mode_text}")
    for note in w.dialect.notes:
        w.comment(note)
    if which:
        w.comment(which)
    w.comment(f"cam: {_radius_text(spec, summary)}, thickness {spec.cam.thickness:g} {u}, {spec.cam.direction}, "
              f"follower: {summary['follower']['label'] if summary is not None else design.follower.label()} [{u}]")
    motion = " / ".join(
        f"{m.kind} {m.angle:g} deg" + (f" {m.lift:g} {lu} {m.law}" if m.lift is not None else "")
        for m in spec.motion)
    w.comment(f"motion: {motion}")
    if summary is not None:
        pt = summary["pitch"]
        w.comment(f"pitch: {pitch_text(summary)}, max follower deviation {pt['max_deviation']:.3g} {lu} at "
                  f"{pt['max_deviation_at_deg']:.2f} deg")
        claim = profile_claim(summary, spec.is_roller, u)
        w.comment(f"profile: {claim.text}; max error {summary['profile']['max_error']:.3g} {u} from the "
                  "design-intent profile")
        pa = summary["pressure_angle"]
        checks = summary.get("checks")
        res = checks.get("results", {}).get("pressure_angle", {}) if isinstance(checks, Mapping) else {}
        lim = f" [limit {res['limit']:g} deg]" if isinstance(res, Mapping) and res.get("limit") is not None else ""
        w.comment(f"pressure angle: max {pa['max_deg']:.2f} deg at {pa['at_deg']:.2f} deg{lim}")
        if isinstance(checks, Mapping) and "passed" in checks:
            w.comment(checks_verdict(checks))
        w.comment(f"spec digest: {summary.get('spec_digest', '-')}")
    else:
        kind = (f"C2 PH quintic spline, M = {design.pitch.M} segments" if design.pitch.exact
                else f"fitted periodic B-spline, {design.pitch.M} knot spans")
        w.comment(f"pitch: {kind}, max follower deviation {design.max_deviation[0]:.3g} {lu}")
        w.comment("design checks: not stated [program written without the report summary]")
    curve = "pitch curve" if design.follower.design_curve == "pitch" else "profile"
    w.comment(f"tool T{plan.tool_number}: radius {plan.tool_radius:g} {u}; "
              + (tool_text or f"tool centre = {curve} offset outward by {plan.centre_offset:g} {u}")
              + f"; {compensation_text}")
    w.comment(f"work offset {plan.work_offset}: origin on the cam axis, Z0 on the top face")


def _radius_text(spec: Any, summary: Mapping[str, Any] | None) -> str:
    """The cam's radii for the header: with ``summary`` (report.json's numbers of this cam — a
    conjugate pair's second cam has its own) its base circle (``profile.base_circle_radius``, the
    profile at zero lift) and, where the summary holds the spec, R_b (``cam.base_radius``, the prime
    circle); without, only the spec's R_b, named as the spec field."""
    u = spec.units
    if summary is None:
        return f"cam.base_radius {spec.cam.base_radius:.6g} {u}"
    base = f"base circle radius {summary['profile']['base_circle_radius']:.6g} {u} [the profile at zero lift]"
    sp = summary.get("spec")
    if isinstance(sp, Mapping):
        return f"base radius R_b {sp['cam']['base_radius']:.6g} {u} [prime circle], {base}"
    return base


def program_header(w: GcodeWriter, plan: MachiningPlan) -> None:
    dia = w.dialect
    w.block(f"{dia.units[plan.units]} {dia.modal}")
    w.block(plan.work_offset)
    blend = dia.blending(BLEND_SHARE * plan.chord_tolerance, GCODE_DECIMALS[plan.units] + 1)
    if blend is not None:
        w.block(blend)
    for block in dia.tool(plan.tool_number):
        w.block(block)
    w.block(f"S{dia.spindle(plan.spindle_rpm)} M3")
    if plan.coolant:
        w.block("M8")


def program_footer(w: GcodeWriter, plan: MachiningPlan) -> None:
    """After the last pass (which ends at the safe height): coolant and spindle off, end."""
    if plan.coolant:
        w.block("M9")
    w.block("M5")
    w.block("M30")


def xy_words(w: GcodeWriter, p: complex, d: int) -> str:
    return f"X{w.num(p.real, d)} Y{w.num(p.imag, d)}"


def move_block(w: GcodeWriter, path: Path2D, i: int, d: int) -> str:
    """One G1/G2/G3 block for element ``i`` (I, J incremental from its start, as every dialect
    here takes them: LinuxCNC under G91.1, Fanuc and Sinumerik by default)."""
    xy = xy_words(w, path.end[i], d)
    if not path.is_arc[i]:
        return f"G1 {xy}"
    ij = path.center[i] - path.start[i]
    return f"{'G3' if path.ccw[i] else 'G2'} {xy} I{w.num(ij.real, d)} J{w.num(ij.imag, d)}"


def move_blocks(w: GcodeWriter, path: Path2D, d: int) -> Iterable[str]:
    for i in range(path.n):
        yield move_block(w, path, i, d)


def contour_program(design: CamDesign, plan: MachiningPlan, path: ContourPath, *,
                    summary: Mapping[str, Any] | None = None, which: str | None = None) -> str:
    """The XY contour-milling program (text); ``summary`` (the dict that becomes
    report.json) adds its key numbers and checks verdict to the header comments; ``which``: a
    comment saying which cam of a body this is (a conjugate pair's)."""
    u = plan.units
    d = GCODE_DECIMALS[u]
    w = writer_for(plan)
    cam_comments(w, design, plan, "XY contour milling", summary, which=which)
    kind = "G02/G03 biarcs" if plan.contour == "arcs" else "G01 chords"
    w.comment(f"path: {path.loop.n} moves as {kind} [{path.n_arcs} arcs, {path.n_lines} lines], "
              f"max distance from the {exact_word(design)}tool-centre path {path.max_distance:.3g} {u}, tolerance "
              f"{path.tolerance:g} {u}")
    w.comment(f"{plan.milling} milling, {'clockwise' if path.clockwise else 'counter-clockwise'}, "
              f"entry at cam angle {path.entry_angle_deg:.2f} deg on lead arcs of radius {plan.lead_radius:g} {u}; "
              f"{plan.passes} pass[es] to depth {plan.depth:g} {u}")
    program_header(w, plan)
    w.block(f"G0 Z{w.num(plan.safe_height, d)}")
    finishing_passes(w, plan, path, d)
    program_footer(w, plan)
    return w.text()


def finishing_passes(w: GcodeWriter, plan: MachiningPlan, path: ContourPath, d: int) -> None:
    """The tool-centre contour's depth passes: at each Z level a rapid to the lead-in's start, a
    plunge, the lead-in arc, the contour, the lead-out arc and a rapid up to the safe height."""
    safe = w.num(plan.safe_height, d)
    start = path.lead_in.start[0]
    for p, z in enumerate(path.z_levels, start=1):
        w.comment(f"pass {p} of {plan.passes} at Z{fmt(z, d)}")
        w.block(f"G0 {xy_words(w, start, d)}")
        w.block(f"G1 Z{w.num(z, d)} F{w.num(plan.plunge_rate, 3)}")
        w.comment("lead-in")
        w.block(move_block(w, path.lead_in, 0, d) + f" F{w.num(plan.feed_rate, 3)}")
        w.comment("contour")
        for line in move_blocks(w, path.loop, d):
            w.block(line)
        w.comment("lead-out")
        w.block(move_block(w, path.lead_out, 0, d))
        w.block(f"G0 Z{safe}")


def compensated_contour_program(design: CamDesign, plan: MachiningPlan, path: PartContourPath, *,
                                summary: Mapping[str, Any] | None = None, which: str | None = None) -> str:
    """The XY contour-milling program on the part's own contour under the control's cutter
    compensation (text): per pass, a plunge outside, G41/G42 switched on along the straight
    approach line, the tangent lead-in arc, the contour, the lead-out arc, G40 along the exit
    line; ``summary`` and ``which`` as for :func:`contour_program`."""
    u = plan.units
    d = GCODE_DECIMALS[u]
    w = writer_for(plan)
    dia = w.dialect
    comp = dia.compensation(path.side, plan.tool_number)
    cam_comments(w, design, plan, "XY contour milling", summary, which=which,
                  tool_text="the program runs on the part contour [the cam profile]",
                  compensation_text=f"cutter compensation {comp} [tool {path.side} of the path]: the control's "
                                    f"tool table must hold tool {plan.tool_number}'s radius R = "
                                    f"{plan.tool_radius:g} {u} [adjust it there for wear]")
    kind = "G02/G03 biarcs" if plan.contour == "arcs" else "G01 chords"
    centre = path.centre
    w.comment(f"path: {path.loop.n} moves as {kind} [{path.n_arcs} arcs, {path.n_lines} lines], max distance "
              f"from the exact part contour {path.max_distance:.3g} {u}, tolerance {centre.tolerance:g} {u}")
    w.comment(f"{plan.milling} milling, {'clockwise' if centre.clockwise else 'counter-clockwise'}, entry at cam "
              f"angle {centre.entry_angle_deg:.2f} deg: approach line and lead arc of radius "
              f"{plan.lead_radius + plan.tool_radius:g} {u} on the part [tool centre on radius {plan.lead_radius:g} "
              f"{u}]; {plan.passes} pass[es] to depth {plan.depth:g} {u}")
    program_header(w, plan)
    safe = w.num(plan.safe_height, d)
    w.block(f"G0 Z{safe}")
    for p, z in enumerate(centre.z_levels, start=1):
        w.comment(f"pass {p} of {plan.passes} at Z{fmt(z, d)}")
        w.block(f"G0 {xy_words(w, path.approach.start[0], d)}")
        w.block(f"G1 Z{w.num(z, d)} F{w.num(plan.plunge_rate, 3)}")
        w.comment("approach, cutter compensation on")
        w.block(f"{comp} {move_block(w, path.approach, 0, d)} F{w.num(plan.feed_rate, 3)}")
        w.comment("lead-in")
        w.block(move_block(w, path.lead_in, 0, d))
        w.comment("contour")
        for line in move_blocks(w, path.loop, d):
            w.block(line)
        w.comment("lead-out")
        w.block(move_block(w, path.lead_out, 0, d))
        w.comment("exit, cutter compensation off")
        w.block(f"G40 {move_block(w, path.exit, 0, d)}")
        w.block(f"G0 Z{safe}")
    program_footer(w, plan)
    return w.text()


#: ``machining.compensation`` → (the XY contour's path, the program that writes it)
CONTOUR_PROGRAMS: dict[str, tuple[Callable[..., Any], Callable[..., str]]] = {
    "centre": (contour_path, contour_program),
    "controller": (part_contour_path, compensated_contour_program),
}


def xy_program(design: CamDesign, plan: MachiningPlan, *, summary: Mapping[str, Any] | None = None,
               which: str | None = None) -> tuple[str, ContourPath | PartContourPath]:
    """(the XY contour program's text, its path) for ``plan.compensation`` (:data:`CONTOUR_PROGRAMS`);
    ``summary`` and ``which`` as for :func:`contour_program`."""
    make_path, write = CONTOUR_PROGRAMS[plan.compensation]
    path = make_path(design, plan)
    return write(design, plan, path, summary=summary, which=which), path


def groove_program(design: CamDesign, plan: MachiningPlan, path: Any, *,
                   summary: Mapping[str, Any] | None = None) -> str:
    """The XY program that mills a groove cam's groove (text): at every depth level, the passes of
    ``path`` (:class:`cam_workbench.generators.machining.groove.GroovePath`) from the middle out, the two walls
    last; each pass entered by a plunge at the middle of the longest dwell.

    Raises:
        SpecError: ``machining.compensation`` "controller": a groove's passes are tool-centre paths.
    """
    if plan.compensation != "centre":
        raise SpecError("machining.compensation", '"controller" (G41/G42) is for an outside contour; a groove is '
                        'milled in passes on tool-centre paths between its walls: use "centre"')
    u = plan.units
    d = GCODE_DECIMALS[u]
    w = writer_for(plan)
    cam_comments(w, design, plan, "XY groove milling", summary,
                  tool_text="tool centres on exact offsets of the pitch curve [the passes below]")
    kind = "G02/G03 biarcs" if plan.contour == "arcs" else "G01 chords"
    w.comment(f"groove {path.groove_width:g} {u} wide, {path.depth:g} {u} deep; tool radius {plan.tool_radius:g} {u}; "
              f"{len(path.passes)} passes per level at tool-centre offsets "
              + ", ".join(fmt(p.offset, d) for p in path.passes) + f" {u} from the pitch curve")
    w.comment(f"{kind}, max distance from the {exact_word(design)}tool-centre paths {path.max_distance:.3g} {u}, "
              f"tolerance {path.tolerance:g} {u}; {plan.milling} milling; plunge (centre-cutting end mill) at "
              f"cam angle {path.entry_angle_deg:.2f} deg; {len(path.z_levels)} level[s] to depth {plan.depth:g} {u}")
    program_header(w, plan)
    safe = w.num(plan.safe_height, d)
    w.block(f"G0 Z{safe}")
    for level, z in enumerate(path.z_levels, start=1):
        for k, p in enumerate(path.passes, start=1):
            start = p.loop.start[0]
            w.comment(f"level {level}, pass {k}: {p.role.replace('_', ' ')} [offset {fmt(p.offset, d)}]")
            w.block(f"G0 {xy_words(w, start, d)}")
            w.block(f"G1 Z{w.num(z, d)} F{w.num(plan.plunge_rate, 3)}")
            lines = list(move_blocks(w, p.loop, d))
            w.block(lines[0] + f" F{w.num(plan.feed_rate, 3)}")
            for line in lines[1:]:
                w.block(line)
            w.block(f"G0 Z{safe}")
    program_footer(w, plan)
    return w.text()


def rotary_program(design: CamDesign, plan: MachiningPlan, path: RotaryPath, *,
                   summary: Mapping[str, Any] | None = None, which: str | None = None) -> str:
    """The XC rotary program (text): G93 inverse-time blocks, one per interpolator command;
    ``summary`` and ``which`` as for :func:`contour_program`."""
    u = plan.units
    d = GCODE_DECIMALS[u]
    w = writer_for(plan)
    cam_comments(w, design, plan, "XC rotary machining", summary, which=which)
    cmds = path.commands
    w.comment(f"interpolator: {cmds.n} commands per revolution, dt = {plan.sample_period:g} s, "
              f"{plan.rotary_speed_rpm:g} rpm, {cmds.step_deg:.4g} deg per block; blocks within "
              f"{path.max_deviation:.3g} {u} of the {exact_word(design)}tool-centre path")
    line = "the follower line" if plan.rotary_line == "follower" else "a line through the C axis"
    w.comment(f"machine: X along {line} [away from the C axis], Y = {fmt(path.y, d)}, "
              "C positive = cam counter-clockwise seen from +Z; at C0 the cam's +Y lies along +X")
    if path.from_commands:
        w.comment("tool radius = roller radius: X = s0 + s_actual, the follower's own position")
    w.comment(f"G93 inverse time: F = 1/block time [1/min] so each block takes dt; "
              f"{plan.passes} pass[es] to depth {plan.depth:g} {u}")
    program_header(w, plan)
    safe = w.num(plan.safe_height, d)
    x_out = path.x[0] + plan.lead_radius
    w.block(f"G0 Z{safe}")
    y_word = f" Y{w.num(path.y, d)}" if plan.rotary_line == "follower" else ""
    w.block(f"G0 X{w.num(x_out, d)}{y_word} C{w.num(0.0, 4)}")
    f_block = 60.0 / path.durations
    sense = 1.0 if cmds.sense > 0 else -1.0
    xs = [w.num(v, d) for v in path.x]
    f_words = [w.num(v, 3) for v in f_block]
    for p, z in enumerate(path.z_levels, start=1):
        c0 = sense * 360.0 * (p - 1)
        cs = [w.num(c0 + v, 4) for v in path.c_deg]
        w.comment(f"pass {p} of {plan.passes} at Z{fmt(z, d)}")
        w.block(f"G1 Z{w.num(z, d)} F{w.num(plan.plunge_rate, 3)}")
        w.comment("infeed")
        w.block(f"G1 X{xs[0]}")
        w.comment("revolution")
        w.block("G93")
        for k in range(path.n_blocks):
            w.block(f"G1 X{xs[k + 1]} C{cs[k + 1]} F{f_words[k]}")
        w.block("G94")
        w.comment("retract")
        w.block(f"G1 X{w.num(x_out, d)} F{w.num(plan.plunge_rate, 3)}")
        w.block(f"G0 Z{safe}")
    program_footer(w, plan)
    return w.text()


def gcode_text(design: CamDesign, mode: str, plan: MachiningPlan | None = None, *,
               summary: Mapping[str, Any] | None = None) -> str:
    """The program of ``mode`` ("xy" or "xc") for ``design`` (plan resolved from its spec if
    omitted; ``summary`` as for :func:`contour_program`)."""
    plan = plan or machining_plan(design)
    if mode == "xy":
        return xy_program(design, plan, summary=summary)[0]
    if mode == "xc":
        return rotary_program(design, plan, rotary_path(design, plan), summary=summary)
    raise ValueError(f"mode must be one of {MODES}, got {mode!r}")

"""G-code programs for a designed cam (RS274/NGC as LinuxCNC reads it).

Two programs, both from the tool-centre geometry made in ``cam_workbench.generators.machining.toolpath`` (the exact
offset of the pitch curve for a PH pitch curve):

* ``xy`` — contour milling: the tool-centre path (pitch curve offset by tool radius −
  roller radius) as G02/G03 biarcs or G01 chords, tangent lead arcs, depth passes;
* ``xc`` — rotary: the cam on a C axis, one G93 inverse-time block per interpolator
  command, so each block takes the sample period Δt (F = 1/Δt in 1/min).

Every program starts with comments — the cam's parameters and, given the summary dict that
becomes report.json (``summary=``), its spec digest, pitch deviation, profile error, largest
pressure angle and the design-checks verdict with the failed checks' names; without it only
what the design itself says, and no verdict — then a header (units G21/G20, G90, G17, G40,
G49, G80, G94, work offset, G64 P path-blending tolerance = 10 % of the chord tolerance, tool
change, tool-length offset, spindle), and ends with M5/M30.  Coordinates are tool-centre coordinates (no
cutter compensation): 4 decimals in mm, 5 in inches; C in degrees with 4 decimals.

Dialect "linuxcnc" only.  A Fanuc program would differ in: an ``O`` program number after
the leading ``%``; no ``G64 P`` (Fanuc's G64 takes no tolerance; use G05.1/AI contour
control instead); ``G91.1`` does not exist (I/J are always incremental); comments limited
to upper case; G93 is an option on many Fanuc controls.
"""
from __future__ import annotations

from typing import Any, Iterable, Mapping

from cam_workbench.generators import __version__
from cam_workbench.generators.curves.approx import Path2D
from cam_workbench.generators.cam_design import CamDesign
from cam_workbench.generators.checks.claims import checks_verdict, pitch_text, profile_claim
from cam_workbench.generators.machining import MachiningPlan, machining_plan
from cam_workbench.generators.machining.toolpath import BLEND_SHARE, ContourPath, RotaryPath, contour_path, rotary_path

MODES = ("xy", "xc")
_DECIMALS = {"mm": 4, "in": 5}
_UNITS_WORD = {"mm": "G21", "in": "G20"}


def fmt(value: float, decimals: int) -> str:
    """A G-code number: fixed decimals, trailing zeros and a negative zero removed."""
    text = f"{value:.{decimals}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


class _Writer:
    """Collects blocks; numbers them when asked (N10, N20, …)."""

    def __init__(self, numbered: bool):
        self.lines: list[str] = ["%"]
        self.numbered = numbered
        self.n = 0

    def block(self, text: str) -> None:
        if self.numbered:
            self.n += 10
            text = f"N{self.n} {text}"
        self.lines.append(text)

    def comment(self, text: str) -> None:
        self.block(f"({_comment_text(text)})")

    def text(self) -> str:
        return "\n".join(self.lines + ["%"]) + "\n"


def _comment_text(text: str) -> str:
    """ASCII without parentheses (LinuxCNC ends a comment at the first ')')."""
    repl = {"°": " deg", "≤": "<=", "≥": ">=", "−": "-", "×": "x", "Δ": "d", "θ": "theta", "µ": "u",
            "(": "[", ")": "]", "–": "-", "²": "^2", "³": "^3"}
    out = "".join(repl.get(ch, ch) for ch in text)
    out = out.encode("ascii", "replace").decode("ascii")
    # (MSG, (DEBUG, (PRINT, (LOG, (PROBE… are LinuxCNC commands, not comments
    if out.split(",")[0].strip().upper() in ("MSG", "DEBUG", "PRINT", "LOG", "LOGOPEN", "LOGAPPEND",
                                             "LOGCLOSE", "PROBEOPEN", "PROBECLOSE", "ABORT"):
        out = "- " + out
    return out


def _exact_word(design: CamDesign) -> str:
    """ "exact " where the tool-centre path is the exact offset of a PH pitch curve, else "". """
    return "exact " if design.pitch.exact else ""


def _cam_comments(w: _Writer, design: CamDesign, plan: MachiningPlan, mode_text: str,
                  summary: Mapping[str, Any] | None = None, tool_text: str | None = None,
                  which: str | None = None) -> None:
    spec = design.spec
    u = spec.units
    lu = "deg" if design.follower.lift_unit == "angle" else u
    w.comment(f"cam_workbench {__version__}: {design.spec.cam.body} cam, {mode_text}")
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
              + "; no cutter compensation")
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


def _header(w: _Writer, plan: MachiningPlan) -> None:
    w.block(f"{_UNITS_WORD[plan.units]} G90 G17 G40 G49 G80 G94 G91.1")
    w.block(plan.work_offset)
    w.block(f"G64 P{fmt(BLEND_SHARE * plan.chord_tolerance, _DECIMALS[plan.units] + 1)}")
    w.block(f"T{plan.tool_number} M6")
    w.block(f"G43 H{plan.tool_number}")
    w.block(f"S{fmt(plan.spindle_rpm, 1)} M3")
    if plan.coolant:
        w.block("M8")


def _footer(w: _Writer, plan: MachiningPlan) -> None:
    """After the last pass (which ends at the safe height): coolant and spindle off, end."""
    if plan.coolant:
        w.block("M9")
    w.block("M5")
    w.block("M30")


def _move(path: Path2D, i: int, d: int) -> str:
    """One G1/G2/G3 block for element ``i`` (I, J incremental from its start)."""
    end = path.end[i]
    xy = f"X{fmt(end.real, d)} Y{fmt(end.imag, d)}"
    if not path.is_arc[i]:
        return f"G1 {xy}"
    ij = path.center[i] - path.start[i]
    return f"{'G3' if path.ccw[i] else 'G2'} {xy} I{fmt(ij.real, d)} J{fmt(ij.imag, d)}"


def _moves(path: Path2D, d: int) -> Iterable[str]:
    for i in range(path.n):
        yield _move(path, i, d)


def contour_program(design: CamDesign, plan: MachiningPlan, path: ContourPath, *,
                    summary: Mapping[str, Any] | None = None, which: str | None = None) -> str:
    """The XY contour-milling program (text); ``summary`` (the dict that becomes
    report.json) adds its key numbers and checks verdict to the header comments; ``which``: a
    comment saying which cam of a body this is (a conjugate pair's)."""
    u = plan.units
    d = _DECIMALS[u]
    w = _Writer(plan.line_numbers)
    _cam_comments(w, design, plan, "XY contour milling", summary, which=which)
    kind = "G02/G03 biarcs" if plan.contour == "arcs" else "G01 chords"
    w.comment(f"path: {path.loop.n} moves as {kind} [{path.n_arcs} arcs, {path.n_lines} lines], "
              f"max distance from the {_exact_word(design)}tool-centre path {path.max_distance:.3g} {u}, tolerance "
              f"{path.tolerance:g} {u}")
    w.comment(f"{plan.milling} milling, {'clockwise' if path.clockwise else 'counter-clockwise'}, "
              f"entry at cam angle {path.entry_angle_deg:.2f} deg on lead arcs of radius {plan.lead_radius:g} {u}; "
              f"{plan.passes} pass[es] to depth {plan.depth:g} {u}")
    _header(w, plan)
    safe = fmt(plan.safe_height, d)
    start = path.lead_in.start[0]
    w.block(f"G0 Z{safe}")
    for p, z in enumerate(path.z_levels, start=1):
        w.comment(f"pass {p} of {plan.passes} at Z{fmt(z, d)}")
        w.block(f"G0 X{fmt(start.real, d)} Y{fmt(start.imag, d)}")
        w.block(f"G1 Z{fmt(z, d)} F{fmt(plan.plunge_rate, 3)}")
        w.comment("lead-in")
        w.block(_move(path.lead_in, 0, d) + f" F{fmt(plan.feed_rate, 3)}")
        w.comment("contour")
        for line in _moves(path.loop, d):
            w.block(line)
        w.comment("lead-out")
        w.block(_move(path.lead_out, 0, d))
        w.block(f"G0 Z{safe}")
    _footer(w, plan)
    return w.text()


def groove_program(design: CamDesign, plan: MachiningPlan, path: Any, *,
                   summary: Mapping[str, Any] | None = None) -> str:
    """The XY program that mills a groove cam's groove (text): at every depth level, the passes of
    ``path`` (:class:`cam_workbench.generators.machining.groove.GroovePath`) from the middle out, the two walls
    last; each pass entered by a plunge at the middle of the longest dwell."""
    u = plan.units
    d = _DECIMALS[u]
    w = _Writer(plan.line_numbers)
    _cam_comments(w, design, plan, "XY groove milling", summary,
                  tool_text="tool centres on exact offsets of the pitch curve [the passes below]")
    kind = "G02/G03 biarcs" if plan.contour == "arcs" else "G01 chords"
    w.comment(f"groove {path.groove_width:g} {u} wide, {path.depth:g} {u} deep; tool radius {plan.tool_radius:g} {u}; "
              f"{len(path.passes)} passes per level at tool-centre offsets "
              + ", ".join(fmt(p.offset, d) for p in path.passes) + f" {u} from the pitch curve")
    w.comment(f"{kind}, max distance from the {_exact_word(design)}tool-centre paths {path.max_distance:.3g} {u}, "
              f"tolerance {path.tolerance:g} {u}; {plan.milling} milling; plunge (centre-cutting end mill) at "
              f"cam angle {path.entry_angle_deg:.2f} deg; {len(path.z_levels)} level[s] to depth {plan.depth:g} {u}")
    _header(w, plan)
    safe = fmt(plan.safe_height, d)
    w.block(f"G0 Z{safe}")
    for level, z in enumerate(path.z_levels, start=1):
        for k, p in enumerate(path.passes, start=1):
            start = p.loop.start[0]
            w.comment(f"level {level}, pass {k}: {p.role.replace('_', ' ')} [offset {fmt(p.offset, d)}]")
            w.block(f"G0 X{fmt(start.real, d)} Y{fmt(start.imag, d)}")
            w.block(f"G1 Z{fmt(z, d)} F{fmt(plan.plunge_rate, 3)}")
            lines = list(_moves(p.loop, d))
            w.block(lines[0] + f" F{fmt(plan.feed_rate, 3)}")
            for line in lines[1:]:
                w.block(line)
            w.block(f"G0 Z{safe}")
    _footer(w, plan)
    return w.text()


def rotary_program(design: CamDesign, plan: MachiningPlan, path: RotaryPath, *,
                   summary: Mapping[str, Any] | None = None, which: str | None = None) -> str:
    """The XC rotary program (text): G93 inverse-time blocks, one per interpolator command;
    ``summary`` and ``which`` as for :func:`contour_program`."""
    u = plan.units
    d = _DECIMALS[u]
    w = _Writer(plan.line_numbers)
    _cam_comments(w, design, plan, "XC rotary machining", summary, which=which)
    cmds = path.commands
    w.comment(f"interpolator: {cmds.n} commands per revolution, dt = {plan.sample_period:g} s, "
              f"{plan.rotary_speed_rpm:g} rpm, {cmds.step_deg:.4g} deg per block; blocks within "
              f"{path.max_deviation:.3g} {u} of the {_exact_word(design)}tool-centre path")
    line = "the follower line" if plan.rotary_line == "follower" else "a line through the C axis"
    w.comment(f"machine: X along {line} [away from the C axis], Y = {fmt(path.y, d)}, "
              "C positive = cam counter-clockwise seen from +Z; at C0 the cam's +Y lies along +X")
    if path.from_commands:
        w.comment("tool radius = roller radius: X = s0 + s_actual, the follower's own position")
    w.comment(f"G93 inverse time: F = 1/block time [1/min] so each block takes dt; "
              f"{plan.passes} pass[es] to depth {plan.depth:g} {u}")
    _header(w, plan)
    safe = fmt(plan.safe_height, d)
    x_out = path.x[0] + plan.lead_radius
    w.block(f"G0 Z{safe}")
    y_word = f" Y{fmt(path.y, d)}" if plan.rotary_line == "follower" else ""
    w.block(f"G0 X{fmt(x_out, d)}{y_word} C0")
    f_block = 60.0 / path.durations
    sense = 1.0 if cmds.sense > 0 else -1.0
    xs = [fmt(v, d) for v in path.x]
    f_words = [fmt(v, 3) for v in f_block]
    for p, z in enumerate(path.z_levels, start=1):
        c0 = sense * 360.0 * (p - 1)
        cs = [fmt(c0 + v, 4) for v in path.c_deg]
        w.comment(f"pass {p} of {plan.passes} at Z{fmt(z, d)}")
        w.block(f"G1 Z{fmt(z, d)} F{fmt(plan.plunge_rate, 3)}")
        w.comment("infeed")
        w.block(f"G1 X{xs[0]}")
        w.comment("revolution")
        w.block("G93")
        for k in range(path.n_blocks):
            w.block(f"G1 X{xs[k + 1]} C{cs[k + 1]} F{f_words[k]}")
        w.block("G94")
        w.comment("retract")
        w.block(f"G1 X{fmt(x_out, d)} F{fmt(plan.plunge_rate, 3)}")
        w.block(f"G0 Z{safe}")
    _footer(w, plan)
    return w.text()


def gcode_text(design: CamDesign, mode: str, plan: MachiningPlan | None = None, *,
               summary: Mapping[str, Any] | None = None) -> str:
    """The program of ``mode`` ("xy" or "xc") for ``design`` (plan resolved from its spec if
    omitted; ``summary`` as for :func:`contour_program`)."""
    plan = plan or machining_plan(design)
    if mode == "xy":
        return contour_program(design, plan, contour_path(design, plan), summary=summary)
    if mode == "xc":
        return rotary_program(design, plan, rotary_path(design, plan), summary=summary)
    raise ValueError(f"mode must be one of {MODES}, got {mode!r}")

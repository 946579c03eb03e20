"""Every printed number of every command, held to report.json, for every built-in example (issue 20,
item 2: one source for every printed number).

Each command is run as a user runs it (``python -m cam_workbench.cli``), its standard output read as
text, and every line that holds a digit must be one of the lines below — a template that reads like
the printout, with each number replaced by the report.json path it shows (``{pitch.max_deviation}``).
A printed number agrees when it is the report's value rounded to the digits printed; a line with a
digit that no template accounts for fails the test, so a number printed from anywhere else cannot go
unnoticed.  The same for the G-code headers (``cam.nc``, ``cam2.nc``: XY, the XC program of
``gcode --mode xc``, the cylindrical X-Z-A program, a parallel indexer's plate programs and a barrel
or globoidal indexer's generating program) and the DXF title block read with ezdxf.

Placeholders: ``{path}`` a number at the path (list items by index: ``body.second_cam.z.0``),
``{abs:path}`` its magnitude, ``{len:path}`` the length of a list, ``{str:path}`` the text itself,
``{u}`` the length unit, ``{any}`` text that holds no report number (a folder name); ``{path|.3f}``:
the number printed in that format (trailing zeros dropped), where a number like "32" could otherwise
stand for 31.95.  Paths starting
with ``_`` are computed here from report.json (a verdict's counts, the motion program in words).

Each example is built once (``build``, the folder reused by the other tests); ``check``, ``dxf``,
``dynamics``, ``optimise`` (a small budget, two examples), ``sweep --size`` (three points) and
``gcode --mode xc`` are run beside it.
"""
from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
from dataclasses import dataclass
from html.parser import HTMLParser
from pathlib import Path
from typing import Any, Callable

import pytest

from cam_workbench.generators import __version__
from cam_workbench.generators.spec.examples import EXAMPLES, example_spec

from .conftest import ROOT, requires_ocp

CLI = [sys.executable, "-m", "cam_workbench.cli"]
NAMES = list(EXAMPLES)
#: the parallel indexers: report.json has no pitch, profile, curvature, areas or interpolator (its
#: indexer, body, pressure_angle, drive and one program per plate instead)
INDEXER = [n for n in NAMES if EXAMPLES[n]["cam"].get("body") == "parallel_indexer"]
#: the spatial indexers (barrel, globoidal): report.json's indexer.geometry (the rib's radii, the
#: roller's span t), pressure_angle over the driving line and every contact, one generating program
SPATIAL = [n for n in NAMES if EXAMPLES[n]["cam"].get("body") in ("barrel_indexer", "globoidal_indexer")]
PLANE = [n for n in NAMES if not n.startswith("cylindrical") and n not in INDEXER and n not in SPATIAL]
#: a number as the outputs print it (the G-code's and rich's minus signs included)
NUMBER = r"[-−+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?"
PLACEHOLDER = re.compile(r"\{([^{}]+)\}")


def cli(*args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT), COLUMNS="250")       # rich: no wrapped table rows
    return subprocess.run([*CLI, *args], capture_output=True, text=True, env=env)


# ---- numbers and templates -------------------------------------------------------------------
def lookup(report: Any, path: str) -> Any:
    node = report
    for part in path.split("."):
        node = node[int(part)] if isinstance(node, list) else node[part]
    return node


def agrees(token: str, value: Any) -> bool:
    """``token`` (a printed number) is ``value`` rounded to the digits printed: within half a unit
    of its last digit (a ``g`` format's dropped zeros only make that unit larger)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return False
    text = token.replace("−", "-")
    mantissa, _, exponent = text.lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    half = 0.5 * 10.0 ** (int(exponent or 0) - decimals)
    return abs(float(text) - value) <= half * (1 + 1e-9) + 1e-12 * abs(value)


def formatted(token: str, value: Any, fmt: str) -> bool:
    """``token`` is ``value`` in the format ``fmt`` (fixed decimals with the trailing zeros dropped)."""
    if not isinstance(value, (int, float)):
        return False
    text = format(value, fmt)
    if fmt.endswith("f") and "." in text:
        text = text.rstrip("0").rstrip(".")
    return token.replace("−", "-") == ("0" if text == "-0" else text)


@dataclass
class Template:
    """One printed line, its numbers named by report.json paths; ``required``: the output must have it."""

    text: str
    required: bool = False

    def compile(self, report: dict) -> tuple[re.Pattern, list[tuple[str, str, str]]] | None:
        """(the line's regex, [(kind, path, format)] of its number groups); None when a ``str:`` path
        is not in the report (the line is not this cam's)."""
        parts, specs, pos = [], [], 0
        text = self.text.replace("{u}", "{str:units}")
        for m in PLACEHOLDER.finditer(text):
            parts.append(re.escape(text[pos:m.start()]))
            pos = m.end()
            field, _, fmt = m.group(1).partition("|")
            kind, _, path = field.rpartition(":")
            if path == "any":
                parts.append(r".+?")
            elif kind == "str":
                try:
                    parts.append(re.escape(str(lookup(report, path))))
                except (KeyError, IndexError, TypeError):
                    return None
            else:
                parts.append(f"({NUMBER})")
                specs.append((kind, path, fmt))
        parts.append(re.escape(text[pos:]))
        return re.compile("".join(parts)), specs


def expected(report: dict, kind: str, path: str) -> Any:
    v = lookup(report, path)
    return {"": lambda: v, "abs": lambda: abs(v), "len": lambda: len(v)}[kind]()


def held_to(text: str, templates: list[Template], report: dict, what: str,
            skip: Callable[[str], bool] = lambda line: False) -> list[str]:
    """The problems of ``text`` against ``templates`` and ``report``: every line with a digit (but
    the ``skip`` ones) is a template with the report's numbers; every required template is there."""
    compiled = [(t, t.compile(report)) for t in templates]
    found: set[int] = set()
    problems = []
    for line in text.splitlines():
        line = line.rstrip()
        if not re.search(r"\d", line) or skip(line):
            continue
        for i, (t, c) in enumerate(compiled):
            if c is None:
                continue
            m = c[0].fullmatch(line)
            if m is None:
                continue
            found.add(i)
            for token, (kind, path, fmt) in zip(m.groups(), c[1]):
                try:
                    want = expected(report, kind, path)
                except (KeyError, IndexError, TypeError):
                    problems.append(f"{what}: {line!r}: report.json has no {path}")
                    continue
                if not (formatted(token, want, fmt) if fmt else agrees(token, want)):
                    problems.append(f"{what}: {line!r}: {token} is not report.json's {path} = {want!r}")
            break
        else:
            problems.append(f"{what}: a printed line no report.json path accounts for: {line!r}")
    problems += [f"{what}: missing line {t.text!r}" for i, (t, c) in enumerate(compiled)
                 if t.required and i not in found]
    return problems


def derived(report: dict) -> dict:
    """report.json with what a printout derives from it under ``_`` keys: counts, texts."""
    r = dict(report)
    checks = r.get("checks") or {}
    statuses = [v["status"] for v in (checks.get("results") or {}).values()]
    r["_checked"], r["_skipped"] = statuses.count("pass"), statuses.count("skipped")
    files = r.get("files") or {}
    r["_files"] = ", ".join(v for v in files.values() if isinstance(v, str))
    r["_plots"] = ", ".join(files.get("plots") or [])
    spec = r.get("spec") or {}
    lu = "deg" if (r.get("motion") or {}).get("lift_unit") == "deg" else r["units"]
    r["_lu"] = lu
    if spec.get("motion"):
        arm = " of arm" if r.get("body", {}).get("kind") == "cylindrical" and lu == "deg" else ""
        r["_motion"] = " / ".join(f"{m['kind']} {m['angle']:g} deg" + (f" {m['lift']:g} {lu}{arm} {m['law']}"
                                                                       if m.get("lift") is not None else "")
                                  for m in spec["motion"])
        r["_direction"] = spec["cam"]["direction"]
    if "drawing" in r and isinstance(r["drawing"].get("profile_curve"), str):
        r["_profile_curve"] = r["drawing"]["profile_curve"].replace("(", "[").replace(")", "]")
    r["_version"] = __version__
    r["_digest16"] = str(r.get("spec_digest", ""))[:16]
    others = {k: v for k, v in (r.get("drawing") or {}).get("max_error_by_layer", {}).items() if k != "PROFILE"}
    if others:
        r["_others"], r["_others_max"] = ", ".join(others), max(others.values())
    if "finish_wall_deviation" in (r.get("machining") or {}):
        f = r["machining"]["finish_wall_deviation"]
        r["_finish"] = max(f["bottom_radius"], f["outer_radius"])
    geo = (r.get("indexer") or {}).get("geometry")
    if geo and "per_cam" in geo:
        # a parallel indexer: each plate's dwell arc (the roller centres' dwell radius less the roller),
        # the dwell's span
        r["_dwell_arc"] = [c["dwell_radius_mm"] - geo["roller_radius_mm"] for c in geo["per_cam"]]
        r["_dwell_span"] = 360.0 - geo["index_angle_deg"]
    elif geo:
        # a barrel or globoidal indexer: the rollers' length, the cutter's swing alpha at C = 0 (roller
        # 0 half a station short of 180°), each finishing sweep's climb share in per cent
        r["_roller_length"] = geo["roller_end"] - geo["roller_start"]
        r["_alpha0"] = 180.0 - 0.5 * 360.0 / geo["stations"]
        sweeps = ((r.get("machining") or {}).get("generating") or {}).get("sweeps") or []
        r["_climb_percent"] = [None if s["climb_share"] is None else 100.0 * s["climb_share"] for s in sweeps]
    if geo:
        # the drive's Hertz stress in MPa
        drive = r["indexer"].get("drive") or {}
        if "contact_stress_peak_Pa" in drive:
            r["_hertz_mpa"] = drive["contact_stress_peak_Pa"] / 1e6
    return r


def assert_held(problems: list[str]) -> None:
    assert not problems, "\n".join(problems)


# ---- the builds (once per example) ---------------------------------------------------------------
@dataclass
class Built:
    folder: Path
    stdout: str
    report: dict


@pytest.fixture(scope="session")
def builds(tmp_path_factory) -> Callable[[str], Built]:
    done: dict[str, Built] = {}
    root = tmp_path_factory.mktemp("printed")

    def get(name: str) -> Built:
        if name not in done:
            out = root / name
            res = cli("build", "--plots", "--example", name, "-o", str(out))     # every file, PNGs too
            assert res.returncode == 0, res.stderr
            done[name] = Built(out, res.stdout, json.loads((out / "report.json").read_text(encoding="utf-8")))
        return done[name]

    return get


# ---- build -----------------------------------------------------------------------------------------
BUILD_PLANE = [
    Template("cam written to {any}: {str:_files}, {len:files.plots} plots", True),
    Template("  follower (lengths in {u}): {str:follower.label}", True),
    Template("  {str:follower.curve}: PH quintic spline, M = {pitch.segments}, max deviation {pitch.max_deviation} "
             "{str:_lu} at {pitch.max_deviation_at_deg}°; profile within {profile.max_error} {u} of the true one", True),
    Template("  pressure angle: max {pressure_angle.max_deg}° at {pressure_angle.at_deg}°", True),
    Template("  curvature: min {str:follower.curve} radius {curvature.min_pitch_radius} {u}, min profile radius "
             "{curvature.min_profile_radius} {u} at {curvature.at_deg}°", True),
    # the two areas named apart, as report.json names them
    Template("  cross-section (top face) {area} {u}² (report.json area); thesis Eq. 4.21 area ½∮(R_b + s)² dθ "
             "{areas.thesis_eq_4_21} {u}² (areas.thesis_eq_4_21), volume {volume} {u}³"),
    Template("  cross-section (top face) {area} {u}² (report.json area); area inside the {str:follower.curve} "
             "{areas.pitch_curve} {u}² (areas.pitch_curve), volume {volume} {u}³"),
    Template("  DXF PROFILE: SPLINE = the {str:drawing.profile_curve} ({str:drawing.file_version})"),
    Template("  DXF PROFILE: polynomial cubic SPLINE of {drawing.profile_poles} poles, max distance "
             "{drawing.profile_max_error} {u} from the profile NURBS (the {str:drawing.profile_curve}) (tolerance "
             "{drawing.chord_tolerance} {u}, {str:drawing.file_version}); {str:_others} drawn alike, within "
             "{_others_max} {u} of theirs"),
    Template("  interpolator: {interpolator.commands} commands (Δt = {interpolator.sample_period} s), max deviation "
             "{interpolator.max_deviation} {str:_lu}; max v {interpolator.velocity.max}, a "
             "{interpolator.acceleration.max}, j {interpolator.jerk.max} ({str:interpolator.differencing} "
             "differences)", True),
    Template("  warning: {str:interpolator.warning}"),
    Template("  cam.nc: {str:machining.program} program, tool radius {machining.tool_radius} {u}, "
             "{machining.gcode_lines} lines", True),
    # a conjugate pair: the second cam's own numbers
    Template("  second cam (z {body.second_cam.z.0} to {body.second_cam.z.1} {u}): "
             "{str:body.second_cam.follower.label}; max deviation {body.second_cam.pitch.max_deviation} {str:_lu}, pressure angle max "
             "{body.second_cam.pressure_angle.max_deg}° at {body.second_cam.pressure_angle.at_deg}°"),
    Template("  distance error between the rollers: max {body.roller_distance_error.max} {u} at "
             "{body.roller_distance_error.at_deg}° (the two curves' deviations "
             "{body.roller_distance_error.first_cam_deviation} + {body.roller_distance_error.second_cam_deviation} "
             "{str:_lu})"),
    Template("  cam2.nc: the second cam's {str:machining.program} program, {machining.second_cam.gcode_lines} lines"),
]

BUILD_CYLINDRICAL = [
    Template("cam written to {any}: {str:_files}, {len:files.plots} plots", True),
    Template("  {str:body.kind} cam: pitch radius {body.pitch_radius} {u}, outer radius {body.outer_radius} {u}, "
             "length {body.length} {u}; groove {body.groove_width} {u} wide, {body.groove_depth} {u} deep", True),
    Template("  pressure angle: max {pressure_angle.max_deg}° at {pressure_angle.at_deg}° (pitch radius), "
             "{pressure_angle.bottom_max_deg}° at the groove's bottom", True),
    Template("  wall faces within {body.wall_error.value} {u} of the exact walls ({body.wall_error.faces} faces, "
             "{body.wall_error.points} points)", True),
    Template("  volume {volume} {u}³ (kernel {solid.volume_rel_diff} relative)", True),
    Template("  cam.nc: 4-axis X-Z-A program, tool radius {machining.tool_radius} {u}, {machining.gcode_lines} lines",
             True),
    Template("  cam.dxf: developed walls as cubic splines within {drawing.developed_fit_error.value} {u} of the exact "
             "walls (pitch line {drawing.developed_fit_error.pitch_line} {u}), side and end views", True),
]


BUILD_INDEXER = [
    Template("cam written to {any}: {str:_files}, {len:files.plots} plots", True),
    Template("  {str:body.kind} (lengths in {u}): {str:follower.label}", True),
    Template("  turret: {indexer.geometry.stations} stations, C = {indexer.geometry.centre_distance_mm} {u}, R_p = "
             "{indexer.geometry.pitch_radius_mm} {u}, r_r = {indexer.geometry.roller_radius_mm} {u}; {body.cams} "
             "plates {body.plate_thickness} {u} thick, gap {body.gap} {u}; {str:indexer.geometry.law} index over "
             "{indexer.geometry.index_angle_deg}° of input from {indexer.geometry.index_start_deg}°", True),
    Template("  clearance: smallest gap of an idle roller to a cam {indexer.geometry.clearance_mm} {u} (cam "
             "{indexer.geometry.clearance_cam}, roller {indexer.geometry.clearance_roller})", True),
    # the flanks are fitted, never called exact
    Template("  flanks: cubic B-splines fitted within {body.flank_fit_error.value} {str:body.flank_fit_error.unit} of "
             "the offset of the roller loci (measured, not exact; the dwell arcs are exact arcs); largest cam radius "
             "{body.outer_radius} {u}", True),
    Template("  turret angle recovered from the built profiles: max error {indexer.motion_from_geometry.max_error_rad} "
             "rad from the law ({indexer.motion_from_geometry.samples} input angles, "
             "{indexer.motion_from_geometry.undetermined_samples} where the profiles alone do not fix it)", True),
    Template("  volume {volume} {u}³ (kernel {solid.volume_rel_diff} relative)", True),
]
#: the drive's line (``indexer.drive``: when report.json has it), and its roller life when it has that
INDEXER_DRIVE = ("  drive at {indexer.drive.input_speed_rpm} rpm: index {indexer.drive.index_time_s} s, peak output "
                 "acceleration {indexer.drive.output_acceleration_peak_rad_s2} rad/s², peak input torque "
                 "{indexer.drive.input_torque_peak_Nm} N·m, peak normal force {indexer.drive.normal_force_peak_N} N, "
                 "peak Hertz stress {_hertz_mpa} MPa")
INDEXER_L10 = ", roller life L10 {indexer.drive.l10_hours} h"
#: the carrying contact's pressure angle (with the check's limit when it has one) and the whole index's
INDEXER_PRESSURE_ANGLE = ("  pressure angle: max {pressure_angle.max_deg}° at {pressure_angle.at_deg}° (the contact "
                          "carrying the output torque{limit}); over the whole index {pressure_angle.index_max_deg}° "
                          "at {pressure_angle.index_max_at_deg}°")
#: each plate's program (``machining.plates.<k>``)
INDEXER_PROGRAM = ("  {{str:machining.plates.{k}.file}}: XY contour of cam {{machining.plates.{k}.cam}}, tool radius "
                   "{{machining.plates.{k}.tool_radius_mm}} {{u}}, {{machining.plates.{k}.gcode_lines}} lines, within "
                   "{{machining.plates.{k}.path_error_mm}} {{u}} of the exact tool-centre path")


#: a barrel or globoidal indexer's lines (commands/build_spatial_indexer.py): report.json's
#: indexer.geometry, pressure_angle, body.flank_fit_error, indexer.motion_from_geometry, volume, solid,
#: indexer.drive (INDEXER_DRIVE, the same words) and machining
BUILD_SPATIAL = [
    Template("cam written to {any}: {str:_files}, {len:files.plots} plots", True),
    Template("  {str:body.kind} (lengths in {u}): {str:follower.label}", True),
    Template("  turret: {indexer.geometry.stations} stations, C = {indexer.geometry.centre_distance} {u}, r_r = "
             "{indexer.geometry.roller_radius} {u} over t = {indexer.geometry.roller_start}–"
             "{indexer.geometry.roller_end} {u}; {rib}, cam {indexer.geometry.cam_width} {u} long; "
             "{str:indexer.geometry.law} index over {indexer.geometry.index_angle_deg}° of input from "
             "{indexer.geometry.index_start_deg}°", True),
    Template("  pressure angle: max {pressure_angle.max_deg}° at {pressure_angle.at_deg}° (the driving contact "
             "line{limit}); over every engaged contact {pressure_angle.contacts_max_deg}° at "
             "{pressure_angle.contacts_max_at_deg}°", True),
    Template("  rib: thinnest {indexer.geometry.min_rib_thickness.value_mm} {u} at "
             "{indexer.geometry.min_rib_thickness.at_deg}°; flank regularity margin at least "
             "{indexer.geometry.min_regularity_margin.value_1} (at {indexer.geometry.min_regularity_margin.at_deg}°)",
             True),
    # the flanks are fitted surfaces, never called exact
    Template("  flanks: bicubic B-spline surfaces fitted within {body.flank_fit_error.value} "
             "{str:body.flank_fit_error.unit} of the rollers' exact envelope (measured, not exact)", True),
    Template("  turret angle recovered from the flank surfaces: max error {indexer.motion_from_geometry.max_error_rad} "
             "rad from the law ({indexer.motion_from_geometry.samples} input angles)", True),
    Template("  volume {volume} {u}³ by a grid of the exact envelope (OCCT {solid.volume_rel_diff} relative)", True),
    Template("  {str:machining.file}: {str:machining.program} program (LinuxCNC XYZAC), tool radius "
             "{machining.tool_radius} {u}, {machining.passes} depth levels, {machining.gcode_lines} lines, the "
             "cutter's axis within {machining.path_error.value} {u} of the roller's exact axis", True),
]
#: the rib's words of each spatial indexer's turret line (report.json ``indexer.geometry.type``)
SPATIAL_RIB = {
    "BarrelIndexer": "R_p = {indexer.geometry.pitch_radius} {u}; rib between the cylinders "
                     "{indexer.geometry.root_radius}–{indexer.geometry.outer_radius} {u}",
    "GloboidalIndexer": "rib between the globoids {indexer.geometry.tip_radius}–{indexer.geometry.root_radius} {u}",
}


def spatial_build_templates(report: dict) -> list[Template]:
    """A spatial indexer's build lines: its rib's words, the pressure angle's limit when the check
    has one, the drive's line (with the roller life) when report.json has a drive."""
    rib = SPATIAL_RIB[report["indexer"]["geometry"]["type"]]
    limit = report["checks"]["results"].get("pressure_angle", {}).get("limit")
    t = [Template(x.text.replace("{rib}", rib).replace(
        "{limit}", "" if limit is None else ", limit {checks.results.pressure_angle.limit}°"), x.required)
        for x in BUILD_SPATIAL]
    drive = report["indexer"].get("drive")
    if drive:
        t.append(Template(INDEXER_DRIVE + (INDEXER_L10 if drive.get("l10_hours") is not None else ""), True))
    return t


def build_templates(name: str, report: dict) -> list[Template]:
    """The build's lines of ``name``'s body: a parallel indexer's drive line when its report.json
    has a drive (with the roller life when it has one), a line per plate's program."""
    if name in PLANE:
        return list(BUILD_PLANE)
    if name in SPATIAL:
        return spatial_build_templates(report)
    if name not in INDEXER:
        return list(BUILD_CYLINDRICAL)
    t = list(BUILD_INDEXER)
    limit = report["checks"]["results"].get("pressure_angle", {}).get("limit")
    t.append(Template(INDEXER_PRESSURE_ANGLE.replace(
        "{limit}", "" if limit is None else ", limit {checks.results.pressure_angle.limit}°"), True))
    drive = report["indexer"].get("drive")
    if drive:
        t.append(Template(INDEXER_DRIVE + (INDEXER_L10 if drive.get("l10_hours") is not None else ""), True))
    t += [Template(INDEXER_PROGRAM.format(k=k), True) for k in range(len(report["machining"]["plates"]))]
    return t


def remedy_templates(report: dict, prefix: str) -> list[Template]:
    """The line of each failing check's remedy (report.json ``checks.results[name].remedy``): the
    field, its value and the command, as report.json holds them."""
    out = []
    for name, r in report["checks"]["results"].items():
        if r.get("remedy"):
            rem = f"checks.results.{name}.remedy"
            out.append(Template(f"{prefix}{name}: {{str:{rem}.field}} = {{{rem}.value}} {{str:{rem}.unit}} passes every "
                                f"check (the smallest that does, by bisection to {{{rem}.tolerance}} {{u}}; the rest "
                                f"held) → --set {{str:{rem}.field}}={{{rem}.value}}", True))
    return out


@requires_ocp
@pytest.mark.parametrize("name", NAMES)
def test_build_summary(builds, name):
    b = builds(name)
    r = derived(b.report)
    templates = build_templates(name, r) + remedy_templates(r, "    remedy ")
    assert_held(held_to(b.stdout, templates, r, f"build {name}"))
    if name in INDEXER or name in SPATIAL:
        # the verdict as the other bodies print it; the flanks' line never says they are exact
        verdict = "all pass" if r["checks"]["passed"] else f"FAILED {', '.join(r['checks']['failed'])}"
        assert f"  design checks: {verdict}" in b.stdout.splitlines()
        flanks = next(line for line in b.stdout.splitlines() if line.startswith("  flanks: "))
        assert "fitted within" in flanks and "not exact" in flanks
    # every file the summary line names is in the folder (a cylindrical cam's plots too)
    for f in [*(v for v in r["files"].values() if isinstance(v, str)), *r["files"]["plots"]]:
        assert (b.folder / f).is_file(), f


# ---- the G-code headers ----------------------------------------------------------------------------
def header(text: str) -> str:
    """The comment lines before the program's first block."""
    lines = text.splitlines()
    out = []
    for line in lines[1:]:
        if not line.startswith("("):
            break
        out.append(line)
    return "\n".join(out)


def program_templates(cam: str, program: str) -> list[Template]:
    """The header of a plane cam's program; ``cam``: the report path of the cam's own numbers
    ("" for the first cam, "body.second_cam." for a conjugate pair's second), ``program``: xy or xc
    (``m``: its machining section)."""
    m = "machining." if not cam else "machining.second_cam."
    c = cam
    t = [
        Template("(cam_workbench {str:_version}: {str:spec.cam.body} cam, "
                 + ("XY {any} milling)" if program == "xy" else "XC rotary machining)"), True),
        Template("(motion: {str:_motion})", True),
        Template(f"(pitch: C^2 PH quintic spline, M = {{{c}pitch.segments}} segments, max follower deviation "
                 f"{{{c}pitch.max_deviation}} {{str:_lu}} at {{{c}pitch.max_deviation_at_deg}} deg)"),
        Template(f"(pitch: C^2 PH quintic spline, M = {{{c}pitch.segments}} segments through the face's contact "
                 f"points, max follower deviation {{{c}pitch.max_deviation}} {{str:_lu}} at "
                 f"{{{c}pitch.max_deviation_at_deg}} deg)"),
        Template(f"(profile: exact rational offset of the PH pitch curve [NURBS degree {{{c}profile.degree}}, "
                 f"rational]; max error {{{c}profile.max_error}} {{u}} from the design-intent profile)"),
        Template(f"(profile: PH quintic spline through the exact contact points of the face [NURBS degree "
                 f"{{{c}profile.degree}}, polynomial], max error {{{c}profile.max_error}} {{u}} from the true envelope; "
                 f"max error {{{c}profile.max_error}} {{u}} from the design-intent profile)"),
        Template(f"(pressure angle: max {{{c}pressure_angle.max_deg}} deg at {{{c}pressure_angle.at_deg}} deg "
                 "[limit {checks.results.pressure_angle.limit} deg])", True),
        Template("(design checks: all pass [{_checked} checked])"),
        Template("(design checks: all pass [{_checked} checked, {_skipped} skipped])"),
        Template("(spec digest: {str:spec_digest})", True),
        Template(f"(tool T{{spec.machining.tool_number}}: radius {{{m}tool_radius}} {{u}}; tool centre = "
                 f"{{any}} offset outward by {{{m}tool_centre_offset}} {{u}}; no cutter compensation)"),
        Template("(tool T{spec.machining.tool_number}: radius {machining.tool_radius} {u}; tool centres on exact "
                 "offsets of the pitch curve [the passes below]; no cutter compensation)"),
        Template("(work offset {str:spec.machining.work_offset}: origin on the cam axis, Z0 on the top face)", True),
    ]
    if not cam:
        # the first cam: R_b (the spec's prime circle) and its own base circle
        t.append(Template("(cam: base radius R_b {spec.cam.base_radius|.6g} {u} [prime circle], base circle radius "
                          "{profile.base_circle_radius|.6g} {u} [the profile at zero lift], thickness "
                          "{spec.cam.thickness|g} {u}, {str:_direction}, follower: {str:follower.label} [{u}])", True))
        t.append(Template("(the first cam of the conjugate pair, {body.first_cam.z.0} <= z <= {body.first_cam.z.1}; "
                          "the second is in {str:machining.second_cam.file})"))
    else:
        # the second cam of a pair: its own base circle and roller, never the pair's R_b
        t.append(Template("(cam: base circle radius {body.second_cam.profile.base_circle_radius|.6g} {u} [the profile "
                          "at zero lift], thickness {spec.cam.thickness|g} {u}, {str:_direction}, follower: "
                          "{str:body.second_cam.follower.label} [{u}])", True))
        t.append(Template("(the second cam of the conjugate pair, {body.second_cam.z.0} <= z <= {body.second_cam.z.1}: "
                          "cut as its own plate, Z0 on its top face [the face towards the first cam], the cam frame "
                          "seen from +Z as for the first cam)", True))
    if program == "xy":
        p = m + "xy."
        t += [
            Template(f"(path: {{{p}moves}} moves as G02/G03 biarcs [{{{p}arcs}} arcs, {{{p}lines}} lines], max "
                     f"distance from the exact tool-centre path {{{p}max_distance}} {{u}}, tolerance "
                     f"{{{p}chord_tolerance}} {{u}})"),
            Template(f"({{any}} milling, {{any}}, entry at cam angle {{{p}entry_at_deg}} deg on lead arcs of radius "
                     f"{{machining.lead_radius}} {{u}}; {{{p}passes}} pass[es] to depth {{machining.depth}} {{u}})"),
            # a groove cam's passes
            Template("(groove {machining.xy.groove_width} {u} wide, {machining.xy.depth} {u} deep; tool radius "
                     "{machining.tool_radius} {u}; {machining.xy.passes_per_level} passes per level at tool-centre "
                     "offsets {machining.xy.offsets.0}, {machining.xy.offsets.1} {u} from the pitch curve)"),
            Template("(G02/G03 biarcs, max distance from the exact tool-centre paths {machining.xy.max_distance} {u}, "
                     "tolerance {machining.xy.chord_tolerance} {u}; climb milling; plunge [centre-cutting end mill] at "
                     "cam angle {machining.xy.entry_at_deg} deg; {machining.xy.levels} level[s] to depth "
                     "{machining.depth} {u})"),
        ]
    else:
        p = m + "xc."
        t += [
            Template(f"(interpolator: {{interpolator.commands}} commands per revolution, dt = "
                     f"{{interpolator.sample_period}} s, {{interpolator.speed_rpm}} rpm, {{{p}step_deg}} deg per block; "
                     f"blocks within {{{p}max_deviation}} {{u}} of the exact tool-centre path)", True),
            Template(f"(machine: X along {{any}} [away from the C axis], Y = {{{p}machine_y}}, C positive = cam "
                     "counter-clockwise seen from +Z; at C0 the cam's +Y lies along +X)", True),
            Template(f"(G93 inverse time: F = 1/block time [1/min] so each block takes dt; {{{p}passes}} pass[es] to "
                     "depth {machining.depth} {u})", True),
            Template("(tool radius = roller radius: X = s0 + s_actual, the follower's own position)"),
        ]
    return t


CYLINDRICAL_HEADER = [
    Template("(cam_workbench {str:_version}: cylindrical cam, 4-axis X-Z-A groove milling)", True),
    Template("(cylinder: pitch radius {body.pitch_radius} {u}, outer radius {body.outer_radius} {u}, length "
             "{body.length} {u}, {str:_direction}; groove {machining.groove_width} {u} wide to radius "
             "{body.bottom_radius} {u})", True),
    Template("(motion: {str:_motion})", True),
    Template("(follower: oscillating roller, radial pivot {follower.pivot_distance} {u} upstream along the "
             "circumference, arm {follower.arm_length} {u}: the tool follows the roller centre's developed arc)"),
    Template("(machine: X along the cam axis [X = cam z], Z radial [tool tip distance from the cam axis, Z0 on the "
             "axis], A = cam rotation in deg [A = theta for a ccw cam]; the tool stands where the roller does)", True),
    Template("(tool radius {machining.tool_radius} {u}; {machining.passes_per_level} passes per level at tool-centre "
             "offsets {machining.offsets.0}, {machining.offsets.1}, {machining.offsets.2} {u} from the developed "
             "pitch curve)", True),
    Template("(G1 chords within {machining.max_chord_error} {u} of the tool-centre paths [tolerance "
             "{machining.chord_tolerance} {u}]; finishing walls within {_finish} {u} of the exact walls; plunge at "
             "cam angle {machining.entry_at_deg} deg)", True),
    Template("(solid: wall faces within {body.wall_error.value} {u} of the exact walls)", True),
]


#: a parallel indexer's program header, plate ``#`` (report.json ``machining.plates.#``: gcode_indexer.py)
INDEXER_HEADER = [
    Template("(cam_workbench {str:_version}: parallel indexer cam {machining.plates.#.cam} of {body.cams}, XY "
             "finishing contour)", True),
    Template("(indexer: N = {indexer.geometry.stations} stations, beta = {indexer.geometry.index_angle_deg} deg index "
             "angle, law {str:indexer.geometry.law}, C = {indexer.geometry.centre_distance_mm} {u}, R_p = "
             "{indexer.geometry.pitch_radius_mm} {u}, r_r = {indexer.geometry.roller_radius_mm} {u}, {body.cams} cams, "
             "index start {indexer.geometry.index_start_deg} deg)", True),
    Template("(cam {machining.plates.#.cam}: plate {body.plate_thickness} {u} thick, cut alone from its own blank in "
             "the cam frame at input angle 0: origin on the input axis, +X towards the turret axis, Z0 on the top "
             "face)", True),
    Template("(tool T{machining.tool_number}: radius {machining.plates.#.tool_radius_mm} {u}; tool centre = the "
             "profile offset outward by {machining.tool_centre_offset} {u}; no cutter compensation; smallest concave "
             "profile radius {machining.plates.#.min_concave_radius_mm} {u})"),
    Template("(tool T{machining.tool_number}: radius {machining.plates.#.tool_radius_mm} {u}; tool centre = the "
             "profile offset outward by {machining.tool_centre_offset} {u}; no cutter compensation; smallest concave "
             "profile radius none [convex])"),
    Template("(dwell: exact arc of radius {machining.plates.#.dwell_arc_radius_mm} {u} = r_d - r_r + tool radius "
             "about the origin, {_dwell_span} deg)", True),
    Template("(lobe tip X' = [{machining.plates.#.tip_mm.0}, {machining.plates.#.tip_mm.1}]: the tool rolls round "
             "the corner on an arc of the tool radius {machining.plates.#.tool_radius_mm} {u} about it)", True),
    Template("(flanks: G02/G03 biarcs, measured biarc error {machining.plates.#.biarc_error_mm} {u} against the "
             "analytic tool-centre offset L + [tool radius - r_r]*n of the flank from the law, not against the "
             "body's B-spline flank)", True),
    Template("(flank fit error {machining.plates.#.flank_fit_error_mm} {u}: the body's B-spline flanks [DXF, STEP] "
             "from the profile L - r_r*n)", True),
    Template("(path: {machining.plates.#.moves} moves [{machining.plates.#.arcs} arcs, {machining.plates.#.lines} "
             "lines], as written [4 decimals] max distance {machining.plates.#.path_error_mm} {u} from the analytic "
             "tool-centre path, tolerance {machining.plates.#.tolerance_mm} {u} [G64 P{machining.plates.#.g64_p_mm} "
             "blending on top])", True),
    Template("({str:machining.milling} milling, {any}, entry at the middle of the dwell on lead arcs of radius "
             "{machining.lead_radius} {u}; {machining.passes} pass to depth {machining.plates.#.depth_mm} {u})", True),
]


def indexer_header(k: int) -> list[Template]:
    """The header of plate ``k``'s program, its numbers at ``machining.plates.<k>``."""
    return [Template(t.text.replace("machining.plates.#.", f"machining.plates.{k}."), t.required)
            for t in INDEXER_HEADER]


#: a spatial indexer's generating program's header (gcode_spatial_indexer.py, machining_spatial_indexer.py):
#: report.json's indexer.geometry and machining (``G``: machining.generating); a comment wrapped onto
#: "(  …)" lines is read joined (:func:`joined`)
G = "machining.generating."
SPATIAL_HEADER = [
    Template("(cam_workbench {str:_version}: {str:indexer.type} indexer cam, X-Y-Z-A-C generating program: the "
             "cutter follows roller 0's motion relative to the cam)", True),
    Template("(indexer: N = {indexer.geometry.stations} stations, beta = {indexer.geometry.index_angle_deg} deg index "
             "angle, law {str:indexer.geometry.law}, C = {indexer.geometry.centre_distance} {u}, r_r = "
             "{machining.roller_radius} {u}, rollers t = {indexer.geometry.roller_start}-{indexer.geometry.roller_end} "
             "{u}, width {indexer.geometry.cam_width} {u}, index start {indexer.geometry.index_start_deg} deg, {rib})",
             True),
    Template("(machine: cam.step's frame renamed: X along the cam axis [X = z of cam.step], Y = x towards the turret "
             "axis, Z = y up along the turret axis [the vertical X{machining.generating.turret_axis_xy_mm.0} "
             "Y{machining.generating.turret_axis_xy_mm.1}]; origin = cam.step's: on the cam axis, X0 on the cam's end "
             "face z = 0 [the cam spans X{machining.generating.cam_x_range_mm.0} to "
             "X{machining.generating.cam_x_range_mm.1}]; trivkins XYZAC, A and C unwrapped)", True),
    Template("(A = input angle theta in deg, the cam turned about +X right-handed; C = turret angle psi in deg, the "
             f"cutter swung clockwise seen from +Z, alpha = {{_alpha0}} + C deg; A runs over {{{G}a_range_deg.0}} to "
             f"{{{G}a_range_deg.1}}, C over {{{G}c_range_deg.0}} to {{{G}c_range_deg.1}})", True),
    # the barrel's vertical tool and the globoid's horizontal one (Z = 0): "W/2" is a symbol, not a number
    Template("(X Y Z = tool tip; tool vertical, tip down at height t on the roller's axis: X = W/2 + R_p sin alpha, "
             "Y = C + R_p cos alpha, Z = t; C turns the tool about its own axis only [drop it on an XYZA mill])"),
    Template("(X Y Z = tool tip; tool horizontal along the roller's axis, spindle towards the turret axis, tip at t "
             "from it: X = W/2 + t sin alpha, Y = C + t cos alpha, Z = 0; C swivels the head about the vertical through "
             "the tip; no G43: the tool length lies in XY)"),
    Template("(tool T{machining.tool_number}: flat end mill radius {machining.tool_radius} {u} = the roller's "
             "radius)"),
    Template("(tool T{machining.tool_number}: flat end mill radius {machining.tool_radius} {u}, stock "
             "{machining.stock} {u} left on every flank [roller radius {machining.roller_radius} {u}])"),
    Template(f"(depth levels: tip at t = {{levels}} {{u}} on the roller's axis [{{len:{G}levels_t_mm}} roughing "
             f"sweeps over A {{{G}a_range_deg.0}} to {{{G}a_range_deg.1}}, entered and left clear of the blank]; "
             f"safe: tip at t = {{{G}safe_t_mm}} {{u}})", True),
    Template(f"(path: {{{G}moves}} G1 moves in {{len:{G}sweeps}} sweeps, A steps {{{G}step_deg.0}} to "
             f"{{{G}step_deg.1}} deg; measured chord error {{machining.path_error.value}} {{u}} [the cutter's axis "
             f"vs roller 0's axis at theta = A, over t = {{{G}reach_t_mm.0}}-{{{G}reach_t_mm.1}} {{u}}, "
             "{machining.path_error.points_per_move} points per move, written words], limit "
             "{machining.path_error.limit} {u}, tolerance "
             "{machining.path_error.tolerance} {u} with G64 P{machining.g64_p}; linear interpolation, not exact)",
             True),
    Template("(feed: G93 inverse time, F = {machining.feed_rate} {u}/min / the move's cam-frame travel of the "
             "cutter's axis ends; plunges {machining.plunge_rate} {u}/min along the tool's axis)", True),
    Template("(pressure angle: max {pressure_angle.max_deg} deg at {pressure_angle.at_deg} deg [limit "
             "{checks.results.pressure_angle.limit} deg])"),
    Template("(pressure angle: max {pressure_angle.max_deg} deg at {pressure_angle.at_deg} deg)"),
    Template("(design checks: all pass [{_checked} checked])"),
    Template("(design checks: all pass [{_checked} checked, {_skipped} skipped])"),
    Template("(spec digest: {str:spec_digest})", True),
]
#: the rib's words of each spatial indexer's ``indexer:`` line (report.json ``indexer.geometry.type``)
SPATIAL_HEADER_RIB = {
    "BarrelIndexer": "R_p = {indexer.geometry.pitch_radius} {u}, rib radii {indexer.geometry.root_radius}-"
                     "{indexer.geometry.outer_radius} {u}",
    "GloboidalIndexer": "tip/root globoids {indexer.geometry.tip_radius}/{indexer.geometry.root_radius} {u}",
}
#: a finishing sweep's line (``machining.generating.sweeps.#k``, ``engaged_deg.#side``; #way: forward
#: or backward as the sweep's ``forward`` says), its climb share in per cent
SPATIAL_FINISHING = (f"(finishing side {{{G}sweeps.#k.side}}: engaged over A {{{G}engaged_deg.#side.0}} to "
                     f"{{{G}engaged_deg.#side.1}} deg of roller 0's locus, swept #way: climb on {{_climb_percent.#k}} "
                     "% of its contact)")


def joined(text: str) -> str:
    """A program header with each comment wrapped onto "(  …)" lines joined to the one it continues."""
    out: list[str] = []
    for line in text.splitlines():
        if line.startswith("(  ") and out:
            out[-1] = out[-1][:-1] + " " + line[3:]
        else:
            out.append(line)
    return "\n".join(out)


def spatial_header(report: dict) -> list[Template]:
    """The header of a spatial indexer's cam.nc: its rib's words, its depth levels, a line per
    finishing sweep (its side, which way it sweeps, its climb share in per cent)."""
    g = report["machining"]["generating"]
    rib = SPATIAL_HEADER_RIB[report["indexer"]["geometry"]["type"]]
    levels = ", ".join(f"{{{G}levels_t_mm.{k}}}" for k in range(len(g["levels_t_mm"])))
    t = [Template(x.text.replace("{rib}", rib).replace("{levels}", levels), x.required) for x in SPATIAL_HEADER]
    t += [Template(SPATIAL_FINISHING.replace("#k", str(k)).replace("#side", str(sw["side"]))
                   .replace("#way", "forward" if sw["forward"] else "backward"), True)
          for k, sw in enumerate(g["sweeps"]) if sw["role"] == "finishing"]
    return t


@requires_ocp
@pytest.mark.parametrize("name", NAMES)
def test_gcode_headers_of_the_build(builds, name):
    """cam.nc (and a conjugate pair's cam2.nc: its own base circle, roller and pressure angle; a
    parallel indexer's cam0.nc, cam1.nc, …: each plate's own numbers; a spatial indexer's generating
    program: report.json's machining and machining.generating)."""
    b = builds(name)
    r = derived(b.report)
    if name in INDEXER:
        plates = r["machining"]["plates"]
        assert [p["file"] for p in plates] == r["machining"]["files"] == [f"cam{k}.nc" for k in range(len(plates))]
        assert [p["cam"] for p in plates] == list(range(r["body"]["cams"]))
        for k, p in enumerate(plates):
            text = header((b.folder / p["file"]).read_text())
            assert_held(held_to(text, indexer_header(k), r, f"{name} {p['file']}"))
        return
    if name in SPATIAL:
        # one generating program, its finishing sweeps climb-milled
        assert r["files"]["gcode"] == r["machining"]["file"] == "cam.nc"
        text = joined(header((b.folder / "cam.nc").read_text()))
        assert_held(held_to(text, spatial_header(r), r, f"{name} cam.nc"))
        return
    if name not in PLANE:
        assert_held(held_to(header((b.folder / "cam.nc").read_text()), CYLINDRICAL_HEADER, r, f"{name} cam.nc"))
        return
    assert_held(held_to(header((b.folder / "cam.nc").read_text()), program_templates("", "xy"), r, f"{name} cam.nc"))
    if "second_cam" in r["machining"]:
        text = header((b.folder / r["machining"]["second_cam"]["file"]).read_text())
        assert_held(held_to(text, program_templates("body.second_cam.", "xy"), r, f"{name} cam2.nc"))


def _xc_report(name: str) -> dict:
    """report.json's numbers of the example's XC program: the pipeline ``gcode`` runs, in this process."""
    from cam_workbench.pipeline import run_pipeline

    spec = example_spec(name).replace(**{"machining.program": "xc"})
    return json.loads(json.dumps(run_pipeline(spec, solid=False, drawing=False).summary))


@pytest.mark.parametrize("name", [n for n in NAMES
                                  if (n in PLANE and n != "groove") or n in INDEXER or n in SPATIAL])
def test_gcode_xc_headers(name):
    """``gcode --mode xc`` (and ``--cam second`` of a conjugate pair) against the XC pipeline's numbers;
    a parallel indexer's plates have XY contour programs only, a spatial indexer its generating program
    only: ``--mode xc`` is refused (exit 2, the field named, nothing on standard output)."""
    if name in SPATIAL:
        res = cli("gcode", "--example", name, "--mode", "xc")
        assert res.returncode == 2, (res.returncode, res.stderr)
        assert res.stdout == ""
        assert res.stderr.startswith('error: machining.program: "xc": ') and "generating program" in res.stderr, \
            res.stderr
        return
    if name in INDEXER:
        res = cli("gcode", "--example", name, "--mode", "xc")
        assert res.returncode == 2, (res.returncode, res.stderr)
        assert res.stdout == ""
        assert res.stderr.startswith('error: machining.program: "xc": ') and 'XY contour programs only ("xy")' in \
            res.stderr, res.stderr
        return
    r = derived(_xc_report(name))
    res = cli("gcode", "--example", name, "--mode", "xc")
    assert res.returncode == 0, res.stderr
    assert_held(held_to(header(res.stdout), program_templates("", "xc"), r, f"{name} xc"))
    if "second_cam" in r["machining"]:
        res = cli("gcode", "--example", name, "--mode", "xc", "--cam", "second")
        assert res.returncode == 0, res.stderr
        assert_held(held_to(header(res.stdout), program_templates("body.second_cam.", "xc"), r, f"{name} xc cam2"))


def test_second_cam_header_is_not_the_pairs_base_radius():
    """The defect the issue found: cam2.nc said "base radius 40 mm" (the pair's spec value) for a cam
    whose profile's base circle is 60.5 mm."""
    r = _xc_report("conjugate")
    res = cli("gcode", "--example", "conjugate", "--cam", "second")
    cam_line = next(line for line in res.stdout.splitlines() if line.startswith("(cam: "))
    base = r["body"]["second_cam"]["profile"]["base_circle_radius"]
    assert abs(base - 60.502) < 1e-3
    assert f"base circle radius {base:.6g} mm" in cam_line and "40 mm" not in cam_line, cam_line


# ---- the DXF title block ----------------------------------------------------------------------------
def title_block(path: Path) -> tuple[dict[str, str], list[list[str]], list[str]]:
    """({label: value} of the two-cell rows, the motion table's rows, the other texts) of the TITLE
    layer, cells paired by baseline and ordered left to right."""
    import ezdxf

    msp = ezdxf.readfile(path).modelspace()
    rows: dict[float, list[tuple[float, str]]] = {}
    for t in msp.query('TEXT[layer=="TITLE"]'):
        rows.setdefault(round(t.dxf.insert.y, 6), []).append((t.dxf.insert.x, t.dxf.text))
    pairs, table, other = {}, [], []
    for cells in rows.values():
        texts = [c for _, c in sorted(cells)]
        if len(texts) == 2:
            pairs[texts[0]] = texts[1]
        elif len(texts) == 6:
            table.append(texts)
        else:
            other += texts
    return pairs, table, other


TITLE_PLANE = {
    "THICKNESS": ["{spec.cam.thickness|.3f} {u}"],
    "UNITS / SCALE": ["{u} / 1:1"],
    "FOLLOWER": ["{str:_FOLLOWER}"],
    # the base circle is report.json's (a groove's profile is the inner wall: R_b − roller − clearance/2)
    "BASE RADIUS R_b": ["{spec.cam.base_radius|.3f} (BASE CIRCLE R{profile.base_circle_radius|.3f})"],
    "BORE": ["Ø{spec.cam.bore_diameter|.3f}"],
    "ROTATION": ["{str:_DIRECTION}, {spec.cam.speed_rpm} RPM"],
    "PITCH CURVE": ["C2 PH QUINTIC SPLINE, M = {pitch.segments} SEGMENTS",
                    "C2 PH QUINTIC SPLINE, M = {pitch.segments} SEGMENTS THROUGH THE FACE'S CONTACT POINTS"],
    "PROFILE NURBS": ["RATIONAL B-SPLINE, DEGREE {profile.degree}, {profile.poles} POLES",
                      "B-SPLINE, DEGREE {profile.degree}, {profile.poles} POLES"],
    "DRAWN AS (LAYER PROFILE)": ["POLYNOMIAL CUBIC SPLINE, {drawing.profile_poles} POLES"],
    "DRAWN PROFILE ERROR": ["MAX {drawing.profile_max_error} {u} FROM THE EXACT PROFILE (TOL. {drawing.chord_tolerance})",
                            "MAX {drawing.profile_max_error} {u} FROM THE PROFILE NURBS (TOL. {drawing.chord_tolerance})"],
    "OTHER CURVES, DRAWN ALIKE": ["{str:_others}: MAX {_others_max} {u}"],
    "PROFILE FIT ERROR": ["{profile.max_error} {u} FROM THE EXACT ENVELOPE OF THE FACE"],
    "PROFILE MAX ERROR": ["{profile.max_error} {u} FROM THE DESIGN-INTENT PROFILE"],
    "MAX FOLLOWER DEVIATION": ["{pitch.max_deviation} {str:_LU} AT {pitch.max_deviation_at_deg}°"],
    "MAX PRESSURE ANGLE": ["{pressure_angle.max_deg}° AT {pressure_angle.at_deg}° (LIMIT "
                           "{checks.results.pressure_angle.limit}°)"],
    "MIN PROFILE RADIUS OF CURV.": ["{curvature.min_profile_radius|.3f} AT {curvature.at_deg}°"],
    "LARGEST RADIUS": ["{profile.max_radius|.3f}"],
    "AREA / VOLUME": ["{area} {u}2 / {volume} {u}3"],
    "SECOND CAM (LAYER PROFILE_2)": ["Z {body.second_cam.z.0|.3f} TO {body.second_cam.z.1|.3f}: {str:_FOLLOWER2}"],
    "SECOND CAM MAX ERROR": ["{body.second_cam.profile.max_error} {u} FROM ITS DESIGN-INTENT PROFILE"],
    "SECOND CAM LARGEST RADIUS": ["{body.second_cam.profile.max_radius|.3f}"],
    "SECOND CAM PRESSURE ANGLE": ["{body.second_cam.pressure_angle.max_deg}° AT "
                                  "{body.second_cam.pressure_angle.at_deg}°"],
    "ROLLER DISTANCE ERROR": ["{body.roller_distance_error.max} {u} AT {body.roller_distance_error.at_deg}° (PH "
                              "DEVIATIONS {body.roller_distance_error.first_cam_deviation} + "
                              "{body.roller_distance_error.second_cam_deviation} {str:_LU})"],
    "DESIGN CHECKS": ["ALL PASS ({_checked} CHECKED)", "ALL PASS ({_checked} CHECKED, {_skipped} SKIPPED)",
                      "FAILED: {any}"],
    "SPEC DIGEST (SHA-256)": ["{str:spec_digest}"],
    "SOFTWARE": ["cam_workbench {str:_version}"],
}

TITLE_CYLINDRICAL = {
    "CAM": ["CYLINDRICAL (BARREL), {str:_DIRECTION}, {spec.cam.speed_rpm} RPM"],
    "UNITS": ["{str:_UNITS}, SCALE 1:1"],
    "PITCH / OUTER / GROOVE BOTTOM RADIUS": ["{body.pitch_radius|.3f} / {body.outer_radius|.3f} / "
                                             "{body.bottom_radius|.3f}"],
    "LENGTH / BORE DIAMETER": ["{body.length|.3f} / {spec.cam.bore_diameter|.3f}"],
    "GROOVE WIDTH / DEPTH": ["{body.groove_width|.3f} / {body.groove_depth|.3f}"],
    "LIFT RANGE Z": ["{body.lift_range.0|.3f} TO {body.lift_range.1|.3f}"],
    "FOLLOWER": ["{str:_FOLLOWER}"],
    "WALLS (WALL_LOWER, WALL_UPPER)": ["CUBIC SPLINES, NOT EXACT: FIT ERROR {drawing.developed_fit_error.value} {u}"],
    "PITCH LINE (PITCH)": ["CUBIC SPLINES, NOT EXACT: FIT ERROR {drawing.developed_fit_error.pitch_line} {u}"],
    "PRESSURE ANGLE": ["{pressure_angle.max_deg} DEG AT R_P, {pressure_angle.bottom_max_deg} DEG AT R_B"],
    "SPEC DIGEST": ["{str:_digest16}"],
    "CAM-WORKBENCH": ["{str:_version}"],
}


#: a parallel indexer's rows (drawing_indexer.py): report.json's indexer.geometry, body, pressure_angle,
#: the checks, the drawn SPLINEs' error and where the turret is drawn
TITLE_INDEXER = {
    "STATIONS N": ["{indexer.geometry.stations}"],
    "INDEX ANGLE BETA": ["{indexer.geometry.index_angle_deg}°"],
    "INDEX START": ["{indexer.geometry.index_start_deg}° OF INPUT"],
    "CENTRE DISTANCE C": ["{indexer.geometry.centre_distance_mm} {u}"],
    "TURRET PITCH RADIUS R_p": ["{indexer.geometry.pitch_radius_mm} {u}"],
    "ROLLER RADIUS r_r": ["{indexer.geometry.roller_radius_mm} {u}"],
    "CAMS": ["{body.cams} PLATES {body.plate_thickness} {u} THICK, GAP {body.gap} {u}"],
    "BORE": ["Ø{body.bore_diameter} {u}"],
    "LARGEST CAM RADIUS": ["{body.outer_radius} {u}"],
    "DWELL ARCS": [],             # one arc radius per plate: made in the test
    # fitted, NOT exact: the measured error
    "FLANKS": ["FITTED CUBIC B-SPLINES, NOT EXACT: FIT ERROR {body.flank_fit_error.value} "
               "{str:body.flank_fit_error.unit} FROM THE EXACT OFFSET (MEASURED)"],
    "DRAWN FLANK SPLINES": ["THE BODY'S OWN (NO REFIT): {drawing.drawn_flank_error.value} {u} FROM THE EXACT OFFSET "
                            "({drawing.drawn_flank_error.points_per_span} POINTS PER SPAN)"],
    "PRESSURE ANGLE (LOAD-CARRYING)": ["{pressure_angle.max_deg}° AT {pressure_angle.at_deg}° OF INPUT (LIMIT "
                                       "{checks.results.pressure_angle.limit}°)",
                                       "{pressure_angle.max_deg}° AT {pressure_angle.at_deg}° OF INPUT"],
    "MAX DRIVING PRESSURE ANGLE": ["{pressure_angle.index_max_deg}° AT {pressure_angle.index_max_at_deg}° OF INPUT"],
    "VOLUME": ["{volume} {u}3"],
    "DESIGN CHECKS": ["ALL PASS ({_checked} CHECKED)", "ALL PASS ({_checked} CHECKED, {_skipped} SKIPPED)",
                      "FAILED: {any}"],
    "DRAWN AT": ["INPUT ANGLE {drawing.drawn_at.input_angle_deg}°, TURRET ANGLE "
                 "{drawing.drawn_at.turret_angle_deg}°; INPUT TURNS CCW, TURRET CW"],
    "UNITS / SCALE": ["{u} / 1:1"],
    "SPEC DIGEST (SHA-256)": ["{str:spec_digest}"],
    "SOFTWARE": ["cam_workbench {str:_version}"],
}


#: a spatial indexer's rows (drawing_spatial_indexer.py title_rows): report.json's indexer.geometry,
#: body, pressure_angle, the checks, the flank surfaces' and the drawn traces' errors as quoted
#: (rounded up: drawing.*.quoted), where the turret is drawn
TITLE_SPATIAL = {
    "STATIONS N": ["{indexer.geometry.stations}"],
    "INDEX ANGLE BETA": ["{indexer.geometry.index_angle_deg}°"],
    "INDEX START": ["{indexer.geometry.index_start_deg}° OF INPUT"],
    "CENTRE DISTANCE C": ["{indexer.geometry.centre_distance} {u}"],
    "TURRET PITCH RADIUS R_p": ["{indexer.geometry.pitch_radius} {u}"],                       # a barrel's
    "RIB RADII": ["ROOT {indexer.geometry.root_radius} {u}, TOP {indexer.geometry.outer_radius} {u}"],
    "RIB GLOBOIDS": ["TIP {indexer.geometry.tip_radius} {u}, ROOT {indexer.geometry.root_radius} {u} ABOUT THE "
                     "TURRET AXIS"],                                                            # a globoid's
    "ROLLER RADIUS r_r": ["{indexer.geometry.roller_radius} {u}"],
    "ROLLER LENGTH": ["{_roller_length} {u}, t = {indexer.geometry.roller_start} TO {indexer.geometry.roller_end} {u}"],
    "CAM WIDTH W": ["{indexer.geometry.cam_width} {u}"],
    "BORE": ["Ø{body.bore_diameter} {u}"],
    "PRESSURE ANGLE (DRIVING)": ["{pressure_angle.max_deg}° AT {pressure_angle.at_deg}° OF INPUT (LIMIT "
                                 "{checks.results.pressure_angle.limit}°)",
                                 "{pressure_angle.max_deg}° AT {pressure_angle.at_deg}° OF INPUT"],
    "PRESSURE ANGLE (ANY CONTACT)": ["{pressure_angle.contacts_max_deg}° AT {pressure_angle.contacts_max_at_deg}° OF "
                                     "INPUT (NOT CHECKED)"],
    "MIN REGULARITY MARGIN": ["{indexer.geometry.min_regularity_margin.value_1} AT "
                              "{indexer.geometry.min_regularity_margin.at_deg}° OF INPUT"],
    "MIN RIB THICKNESS": ["{indexer.geometry.min_rib_thickness.value_mm} {u} AT "
                          "{indexer.geometry.min_rib_thickness.at_deg}° OF INPUT"],
    # fitted, NOT exact: the measured error as quoted
    "FLANK SURFACES": ["FITTED BICUBIC B-SPLINES, NOT EXACT: FIT ERROR {drawing.flank_fit_error.quoted|.3e} "
                       "{str:body.flank_fit_error.unit} FROM THE EXACT ENVELOPE (MEASURED)"],
    "FLANK TRACES": ["FITTED CUBIC SPLINES, NOT EXACT: {drawing.drawn_trace_error.quoted|.3e} {u} FROM THE EXACT "
                     "ENVELOPE (MEASURED, {drawing.drawn_trace_error.points_per_span} POINTS PER SPAN)"],
    "ROOT TRACES": ["FLANKS CONTINUED BELOW THE ROLLERS' ENDS (t < {indexer.geometry.roller_start} {u})"],
    "TURRET MOTION FROM FLANKS": ["{indexer.motion_from_geometry.max_error_rad} rad FROM THE LAW "
                                  "({indexer.motion_from_geometry.samples} INPUT ANGLES)"],
    "DESIGN CHECKS": ["ALL PASS ({_checked} CHECKED)", "ALL PASS ({_checked} CHECKED, {_skipped} SKIPPED)",
                      "FAILED: {any}"],
    "DRAWN AT": ["INPUT ANGLE {drawing.drawn_at.input_angle_deg}°, TURRET ANGLE "
                 "{drawing.drawn_at.turret_angle_deg}°"],
    "UNITS / SCALE": ["{u} / 1:1"],
    "SPEC DIGEST (SHA-256)": ["{str:spec_digest}"],
    "SOFTWARE": ["cam_workbench {str:_version}"],
}


@requires_ocp
@pytest.mark.parametrize("name", NAMES)
def test_dxf_title_block(builds, name):
    b = builds(name)
    r = derived(b.report)
    r.update(_FOLLOWER=str(r["follower"]["label"]).upper(), _DIRECTION=r["_direction"].upper(),
             _LU="DEG" if r["_lu"] == "deg" else r["units"], _UNITS=r["units"].upper())
    if "second_cam" in (r.get("body") or {}):
        r["_FOLLOWER2"] = str(r["body"]["second_cam"]["follower"]["label"]).upper()
    pairs, motion, other = title_block(b.folder / "cam.dxf")
    rules = (TITLE_PLANE if name in PLANE else TITLE_INDEXER if name in INDEXER else TITLE_SPATIAL if name in SPATIAL
             else TITLE_CYLINDRICAL)
    if name in SPATIAL:
        # the flank surfaces fitted, not exact; the traces (a barrel's) too, or said not drawn
        assert pairs["FLANK SURFACES"].startswith("FITTED") and "NOT EXACT" in pairs["FLANK SURFACES"]
        traces = r["drawing"]["drawn_trace_error"]["value"]
        assert (pairs["FLANK TRACES"] == "NOT DRAWN (THE FLANKS ARE SURFACES)" if traces is None
                else "NOT EXACT" in pairs["FLANK TRACES"]), pairs["FLANK TRACES"]
    if name in INDEXER:
        # each plate's dwell arc in turn; the flanks say they are fitted, not exact
        arcs = " / ".join(f"{{_dwell_arc.{k}}}" for k in range(len(r["_dwell_arc"])))
        rules = {**rules, "DWELL ARCS": [f"EXACT ARCS R {arcs} {{u}}, {{_dwell_span}}° EACH"]}
        assert pairs["FLANKS"].startswith("FITTED") and "NOT EXACT" in pairs["FLANKS"]
    problems = []
    for label, value in pairs.items():
        if not re.search(r"\d", value):
            continue
        assert label in rules, f"{name}: a title-block row no rule covers: {label}: {value}"
        problems += held_to(value, [Template(t) for t in rules[label]], r, f"{name} DXF {label}")
    if name in PLANE:
        assert pairs["BASE RADIUS R_b"] and pairs["AREA / VOLUME"]
        # the base circle drawn and dimensioned is report.json's too (a groove's inner wall: 31.95, not 32)
        import ezdxf

        msp = ezdxf.readfile(b.folder / "cam.dxf").modelspace()
        base = r["profile"]["base_circle_radius"]
        assert [c.dxf.radius for c in msp.query('CIRCLE[layer=="BASE_CIRCLE"]')] == [pytest.approx(base, abs=1e-9)]
        dims = [d for d in msp.query("DIMENSION") if "BASE CIRCLE" in d.dxf.text]
        assert len(dims) == 1 and dims[0].get_measurement() == pytest.approx(base, abs=1e-9)
        # the motion table: each segment's start, end and lift, as report.json's motion.segments has them
        segs = r["motion"]["segments"]
        assert [row[0] for row in motion[1:]] == [str(s["index"]) for s in segs]
        for row, seg, m in zip(motion[1:], segs, r["spec"]["motion"]):
            assert agrees(row[2], seg["start_deg"]) and agrees(row[3], seg["start_deg"] + seg["span_deg"]), row
            assert row[4] == "-" if m.get("lift") is None else agrees(row[4], m["lift"]), row
    assert not [t for t in other if re.search(r"\d", t)], other
    assert_held(problems)


# ---- dxf ---------------------------------------------------------------------------------------------
DXF_LINES = [
    Template("drawing written to {any}", True),
    Template("  PROFILE: SPLINE = the {str:drawing.profile_curve} ({str:drawing.file_version})"),
    Template("  PROFILE: polynomial cubic SPLINE of {drawing.profile_poles} poles, max distance "
             "{drawing.profile_max_error} {u} from the profile NURBS (the {str:drawing.profile_curve}) (tolerance "
             "{drawing.chord_tolerance} {u}, {str:drawing.file_version}); {str:_others} drawn alike, within "
             "{_others_max} {u} of theirs"),
    Template("  WALL_LOWER, WALL_UPPER: {drawing.splines} cubic SPLINEs with the PITCH line, fitted to the developed "
             "walls at the outer radius: max fit error {drawing.developed_fit_error.value} {u} (pitch line "
             "{drawing.developed_fit_error.pitch_line} {u}), not exact (tolerance {drawing.chord_tolerance} {u}, "
             "{str:drawing.file_version})"),
    # a spatial indexer (dxf_cmd.describe on drawing.drawn_trace_error): a barrel's traces, a globoid's none
    Template("  {str:drawing.kind} indexer's views: circles, arcs and lines exact; {drawing.splines} flank traces as "
             "cubic SPLINEs within {drawing.drawn_trace_error.value} {u} of the exact envelope (measured, not exact); "
             "the flank surfaces' fit error {drawing.flank_fit_error.value} {u} quoted in the title block "
             "({str:drawing.file_version})"),
    Template("  {str:drawing.kind} indexer's views: circles, arcs and lines exact; no flank traces (the flanks are "
             "surfaces); the flank surfaces' fit error {drawing.flank_fit_error.value} {u} quoted in the title block "
             "({str:drawing.file_version})"),
]


@requires_ocp
@pytest.mark.parametrize("name", NAMES)
def test_dxf_command(builds, name, tmp_path):
    b = builds(name)
    res = cli("dxf", "--example", name, "-o", str(tmp_path / "cam.dxf"))
    assert res.returncode == 0, res.stderr
    assert_held(held_to(res.stdout, DXF_LINES, derived(b.report), f"dxf {name}"))
    if name in SPATIAL:          # the describe line is there, its numbers held above
        assert f"  {b.report['drawing']['kind']} indexer's views: " in res.stdout


# ---- check -------------------------------------------------------------------------------------------
def rich_tables(text: str) -> tuple[dict[str, list[list[str]]], str]:
    """({title: rows of cells} of rich's tables, the text outside them)."""
    tables: dict[str, list[list[str]]] = {}
    rest, title, rows = [], None, None
    lines = text.splitlines()
    for i, line in enumerate(lines):
        if line.startswith("┏"):
            title = lines[i - 1].strip()         # the title stays in the text (centred): it may hold a number
            rest[-1] = title
            rows = tables.setdefault(title, [])
        elif line.startswith("┃") or line.startswith("┡") or line.startswith("└"):
            continue
        elif line.startswith("│") and rows is not None:
            rows.append([c.strip() for c in line.strip("│").split("│")])
        else:
            rest.append(line)
    return tables, "\n".join(rest)


def check_cell(cell: str, value: Any, unit: str) -> bool:
    """A check table's value or limit cell ("21.223°", "144.8269 MPa", "≤ 30.000°", "—")."""
    if value is None:
        return cell == "—"
    m = re.fullmatch(rf"(?:[≤≥<>] )?({NUMBER})(°| (.+))?", cell)
    if not m:
        return False
    shown_unit = "deg" if m.group(2) == "°" else (m.group(3) or "")
    return agrees(m.group(1), value) and shown_unit == unit


#: the check table's title by report.json ``checks.sampling``: a parallel indexer's checks sample the
#: input's turn ("per_turn"), the other bodies' each rise and return
CHECK_TITLES = {
    "per_turn": Template("design checks ({checks.samples_per_turn} input angles over the turn)", True),
}
CHECK_TITLE = Template("design checks ({checks.samples_per_segment} samples per rise/return, refined extrema)", True)

CHECK_LINES = [
    Template("thesis Eq. 4.21 area ½∮(R_b + s)² dθ: {areas.thesis_eq_4_21} {u}² (report.json areas.thesis_eq_4_21); "
             "cross-section (profile − bore): {areas.built_cross_section} {u}² (areas.built_cross_section)"),
    Template("area inside the {str:follower.curve}: {areas.pitch_curve} {u}² (report.json areas.pitch_curve); "
             "cross-section (profile − bore): {areas.built_cross_section} {u}² (areas.built_cross_section)"),
    Template("all checks pass — checks written to {any}/report.json"),
    Template("failed: {any} — checks written to {any}/report.json"),
]


def held_check_tables(stdout: str, report: dict, what: str) -> list[str]:
    tables, rest = rich_tables(stdout)
    checks = report["checks"]
    title = CHECK_TITLES.get(checks.get("sampling"), CHECK_TITLE)
    problems = held_to(rest, [title] + CHECK_LINES + remedy_templates(report, "remedy "), derived(report), what,
                       skip=lambda line: line.endswith("/report.json"))
    rows = next(v for k, v in tables.items() if k.startswith("design checks"))
    assert [row[0] for row in rows] == [f"{n} ({r['kind']})" for n, r in checks["results"].items()], rows
    for row, (n, r) in zip(rows, checks["results"].items()):
        unit = r["unit"]
        if not check_cell(row[1], r["value"], unit):
            problems.append(f"{what}: {n} value {row[1]!r} is not report.json's {r['value']!r} {unit}")
        if not (row[2] == "—" if r["at_deg"] is None else row[2].endswith("°") and agrees(row[2][:-1], r["at_deg"])):
            problems.append(f"{what}: {n} at {row[2]!r} is not report.json's {r['at_deg']!r}")
        if not check_cell(row[3], r["limit"], unit):
            problems.append(f"{what}: {n} limit {row[3]!r} is not report.json's {r['limit']!r}")
        if row[4].split()[0] != r["status"]:
            problems.append(f"{what}: {n} status {row[4]!r} is not report.json's {r['status']!r}")
    ext = tables.get("extremes (largest magnitude, signed)", [])
    assert len(ext) == len(checks["extremes"])
    for row, (n, e) in zip(ext, checks["extremes"].items()):
        assert row[0] == n.replace("_", " ")
        if not (check_cell(row[1], e["value"], e["unit"]) and agrees(row[2][:-1], e["at_deg"])):
            problems.append(f"{what}: extreme {n} {row[1:]} is not report.json's {e}")
    junctions = tables.get("segment junctions (continuity of s, s′, s″, s‴)", [])
    assert len(junctions) == len(report["motion"]["junctions"])
    names = ("s", "velocity", "acceleration", "jerk")
    for row, j in zip(junctions, report["motion"]["junctions"]):
        ok = agrees(row[0][:-1], j["at_deg"]) and row[2] == f"C{j['order']}" and row[3] == f"C{j['promised']}"
        if j["order"] < 3:
            first = names[j["order"] + 1]
            m = re.fullmatch(rf"{first} ({NUMBER}) .+", row[4])
            ok = ok and m is not None and agrees(m.group(1), j["jumps"][first])
        if not ok:
            problems.append(f"{what}: junction {row} is not report.json's {j}")
    return problems


@requires_ocp
@pytest.mark.parametrize("name", NAMES)
def test_check_table(builds, name, tmp_path):
    """``check``'s table, extremes, junctions and areas: report.json's (the one it writes, whose
    checks are the build's)."""
    b = builds(name)
    res = cli("check", "--example", name, "-o", str(tmp_path))
    assert res.returncode in (0, 3), res.stderr
    report = json.loads((tmp_path / "report.json").read_text(encoding="utf-8"))
    assert report["checks"] == b.report["checks"]
    assert_held(held_check_tables(res.stdout, report, f"check {name}"))


# ---- a check without a limit is not passed ---------------------------------------------------------
@pytest.fixture(scope="module")
def no_limit(tmp_path_factory):
    """The default cam without material.allowable_stress: its contact stress has no limit."""
    from cam_workbench.generators.spec import to_toml

    d = tmp_path_factory.mktemp("nolimit")
    data = example_spec("default").to_dict()
    data["material"].pop("allowable_stress")
    from cam_workbench.generators.spec import CamSpec

    path = d / "cam.toml"
    path.write_text(to_toml(CamSpec.from_dict(data)), encoding="utf-8")
    return path


def test_a_check_without_a_limit_is_skipped_everywhere(no_limit, tmp_path):
    from cam_workbench.freecad.check_design import check_rows

    res = cli("check", str(no_limit), "-o", str(tmp_path))
    assert res.returncode == 0, res.stderr
    report = json.loads((tmp_path / "report.json").read_text(encoding="utf-8"))
    r = report["checks"]["results"]["contact_stress"]
    assert r["limit"] is None and r["value"] > 0
    assert r["status"] == "skipped" and "material.allowable_stress" in r["note"]
    # the check table: the value, no limit, "skipped" with the note
    tables, _ = rich_tables(res.stdout)
    row = next(row for row in next(iter(tables.values())) if row[0] == "contact_stress (max)")
    assert row[3] == "—" and row[4].startswith("skipped (no limit: material.allowable_stress")
    assert "pass" not in row[4]
    assert_held(held_check_tables(res.stdout, report, "check without a limit"))
    # FreeCAD's Check design dialog: the same status and note
    cells = {c.name: c.cells() for c in check_rows(report["checks"])}
    assert cells["contact_stress"][4] == "skipped" and cells["contact_stress"][5] == r["note"]


@requires_ocp
def test_a_check_without_a_limit_in_report_html(no_limit, tmp_path):
    res = cli("report", "--plots", str(no_limit), "-o", str(tmp_path))
    assert res.returncode == 0, res.stderr
    page = Page.read(tmp_path / "report.html")
    cell = page.cells["checks.results.contact_stress.status"]
    assert cell["text"] == "skipped" and cell["class"] == "skip"
    report = json.loads((tmp_path / "report.json").read_text(encoding="utf-8"))
    assert_held(page.held_to(report, "report.html without a limit"))
    # the report's one printed line names its files only
    assert_held(held_to(res.stdout, [Template("report written to {any}/: report.html, report.json, {str:_plots}",
                                              True)], derived(report), "report"))


@pytest.mark.parametrize("name", ["cylindrical", "cylindrical_oscillating"])
def test_cylindrical_bottom_pressure_angle_has_no_limit_and_is_not_passed(name):
    from cam_workbench import Cam

    r = Cam.example(name).checks()["results"]["pressure_angle_bottom"]
    assert r["limit"] is None and r["status"] == "skipped" and r["note"].startswith("no limit")


# ---- report.html -------------------------------------------------------------------------------------
class Page(HTMLParser):
    """report.html's cells that name a report.json path (``data-key``), with their text."""

    def __init__(self) -> None:
        super().__init__()
        self.cells: dict[str, dict[str, Any]] = {}
        #: every row label a report.json path is shown under
        self.labels: dict[str, list[str]] = {}
        self._cell: dict[str, Any] | None = None
        self._row: list[str] = []

    @classmethod
    def read(cls, path: Path) -> "Page":
        p = cls()
        p.feed(path.read_text(encoding="utf-8"))
        p.close()
        return p

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "tr":
            self._row = []
        if tag == "td":
            self._cell = {"key": a.get("data-key"), "value": a.get("data-value"), "class": a.get("class", ""),
                          "text": ""}

    def handle_data(self, data):
        if self._cell is not None:
            self._cell["text"] += data

    def handle_endtag(self, tag):
        if tag == "td" and self._cell is not None:
            c, self._cell = self._cell, None
            self._row.append(c["text"].strip())
            if c["key"]:
                c["text"] = c["text"].strip()
                self.labels.setdefault(c["key"], []).append(self._row[0] if len(self._row) > 1 else "")
                self.cells.setdefault(c["key"], c)

    def held_to(self, report: dict, what: str) -> list[str]:
        """Every number cell is report.json's value at its key, shown to 6 digits."""
        problems = []
        for key, c in self.cells.items():
            try:
                want = lookup(report, key)
            except (KeyError, IndexError, TypeError):
                problems.append(f"{what}: {key} is not in report.json")
                continue
            if c["value"] is None or isinstance(want, (bool, str)) or want is None:
                continue
            if float(c["value"]) != want or not agrees(c["text"], want):
                problems.append(f"{what}: {key} shows {c['text']!r} ({c['value']}), report.json {want!r}")
        return problems


@requires_ocp
@pytest.mark.parametrize("name", NAMES)
def test_report_html(builds, name):
    b = builds(name)
    page = Page.read(b.folder / "report.html")
    assert_held(page.held_to(b.report, f"{name} report.html"))
    for n, r in b.report["checks"]["results"].items():
        assert page.cells[f"checks.results.{n}.status"]["text"] == r["status"]
    if name in PLANE:
        # the two areas named apart: the cross-section is report.json's area, the others its areas
        assert "cross-section (top face)" in page.labels["area"]
        thesis = b.report["areas"]["thesis_eq_4_21"]
        if thesis is not None:
            assert page.labels["areas.thesis_eq_4_21"] == ["thesis Eq. 4.21 area ½∮(R_b + s)² dθ"]
        assert page.labels["areas.pitch_curve"] == [f"area inside the {b.report['follower']['curve']}"]
    if name in INDEXER:
        # the numbers the build prints are on the page too (held above to report.json), under their names;
        # the flanks fitted within their measured error, never "exact"
        for key in ("indexer.geometry.stations", "indexer.geometry.centre_distance_mm",
                    "indexer.geometry.pitch_radius_mm", "indexer.geometry.roller_radius_mm",
                    "checks.results.pressure_angle.value", "checks.results.pressure_angle.at_deg",
                    "indexer.geometry.max_driving_pressure_angle_deg", "indexer.geometry.clearance_mm",
                    "body.flank_fit_error.value", "body.outer_radius", "indexer.motion_from_geometry.max_error_rad",
                    "volume", "machining.tool_radius", "machining.gcode_lines"):
            assert page.cells[key]["value"] is not None, key
        drive = b.report["indexer"].get("drive") or {}
        for key in ("index_time_s", "output_acceleration_peak_rad_s2", "input_torque_peak_Nm", "normal_force_peak_N",
                    "contact_stress_peak_Pa", "l10_hours"):
            if drive.get(key) is not None:
                assert page.cells[f"indexer.drive.{key}"]["value"] is not None, key
        fit = page.labels["body.flank_fit_error.value"]
        assert len(fit) == 1 and fit[0].startswith("flanks: fitted within") and "not exact" in fit[0], fit


# ---- dynamics -----------------------------------------------------------------------------------------
#: the train's data each example needs (the examples give none: it is the user's machine)
TRAIN = {"oscillating": ["dynamics.torsional_stiffness=2e6"],
         "cylindrical": ["dynamics.stiffness=2000", "dynamics.mass=0.5"]}
DYNAMICS_NAMES = ["default", "oscillating", "flat", "packaging", "groove", "conjugate", "cylindrical"]

DYNAMICS_LINES = [
    Template("follower dynamics at {dynamics.speed_rpm} rpm", True),
    Template("jump speed: {dynamics.jump_speed.rpm} rpm ({dynamics.jump_speed.ratio_to_speed} × the analysis speed); "
             "rigid follower: {dynamics.jump_speed.rigid_rpm} rpm; sweep {dynamics.jump_speed.sweep_from_rpm}–"
             "{dynamics.jump_speed.sweep_to_rpm} rpm, {dynamics.jump_speed.sweep_points} speeds"),
    Template("jump speed: not found — {str:dynamics.jump_speed.note}; rigid follower: {dynamics.jump_speed.rigid_rpm} "
             "rpm"),
    Template("steady state: {any}, {dynamics.steady_state.revolutions} revolutions"),
    Template("steady state: {any}, {dynamics.steady_state.revolutions} revolutions — NOT periodic yet"),
    Template("steady state: {any}, {dynamics.steady_state.revolutions} revolutions — NOT periodic yet "
             "({str:dynamics.steady_state.note})"),
    Template("form closure: the load changes wall at {str:_changes} (dynamic force; positive share "
             "{dynamics.contact.drive.positive_share}, negative share {dynamics.contact.drive.negative_share})"),
    Template("the follower LEAVES the cam ({dynamics.contact.off_cam_deg}° of the revolution) — written to {any}"),
    Template("the follower stays on the cam — written to {any}"),
]

DYNAMICS_ROWS = {
    "natural frequency of the train": ("model.natural_frequency_hz", None),
    "natural frequency / cam frequency": ("model.frequency_ratio", None),
    "smallest contact force (dynamic)": ("contact.min_force", "contact.min_force_at_deg"),
    "largest contact force (dynamic)": ("contact.max_force", "contact.max_force_at_deg"),
    "smallest contact force (rigid)": ("contact.rigid_min_force", "contact.rigid_min_force_at_deg"),
    "largest contact force (rigid)": ("contact.rigid_max_force", "contact.rigid_max_force_at_deg"),
    "largest displacement error |q − s|": ("error.max", "error.at_deg"),
    "largest vibration": ("error.max_vibration", "error.vibration_at_deg"),
    "camshaft torque max (rigid)": ("torque.rigid.max", "torque.rigid.max_at_deg"),
    "camshaft torque max (dynamic)": ("torque.dynamic.max", "torque.dynamic.max_at_deg"),
    "camshaft torque RMS (dynamic)": ("torque.dynamic.rms", None),
    "work per revolution (dynamic)": ("torque.dynamic.work_per_revolution", None),
    "off the cam": ("contact.off_cam_deg", None),
    "largest gap": ("contact.max_gap", "contact.max_gap_at_deg"),
    "largest landing speed": ("contact.max_landing_speed", None),
}


@pytest.mark.parametrize("name", DYNAMICS_NAMES)
def test_dynamics(name, tmp_path):
    train = TRAIN.get(name, ["dynamics.stiffness=2000"])
    res = cli("dynamics", "--example", name, *(a for t in train for a in ("--set", t)), "-o", str(tmp_path))
    assert res.returncode in (0, 3), res.stderr
    report = json.loads((tmp_path / "report.json").read_text(encoding="utf-8"))
    d = report["dynamics"]
    r = derived(report)
    if "drive" in d["contact"]:
        r["_changes"] = ", ".join(f"{a:.6g}°" for a in d["contact"]["drive"]["changes_at_deg"]) or "nowhere"
    tables, rest = rich_tables(res.stdout)
    problems = held_to(rest, DYNAMICS_LINES, r, f"dynamics {name}")
    rows = tables[f"follower dynamics at {d['speed_rpm']:.6g} rpm"]
    for quantity, value, unit, at in rows:
        path, at_path = DYNAMICS_ROWS[quantity]
        if not (value == "—" if lookup(d, path) is None else agrees(value, lookup(d, path))):
            problems.append(f"dynamics {name}: {quantity} {value} is not report.json's dynamics.{path}")
        if at_path is None:
            assert at == "—", (quantity, at)
        elif not agrees(at.rstrip("°"), lookup(d, at_path)):
            problems.append(f"dynamics {name}: {quantity} at {at} is not report.json's dynamics.{at_path}")
    for row, rv in zip(tables.get("residual vibration", []), d["residual_vibration"]):
        if not (agrees(row[2].split()[0], rv["amplitude"]) and agrees(row[3].rstrip("°"), rv["at_deg"])
                and row[0] == f"motion[{rv['after']}] {rv['kind']}"):
            problems.append(f"dynamics {name}: residual vibration {row} is not report.json's {rv}")
    assert len(tables.get("residual vibration", [])) == len(d["residual_vibration"])
    assert_held(problems)


def test_dynamics_summary_keeps_the_speed_exact():
    """``Cam().dynamics().summary()`` gave ``speed_rpm 59.99999999999999`` (rpm → rad/s → rpm)."""
    from cam_workbench import Cam

    cam = Cam()
    assert cam.dynamics(stiffness=2000, sweep=False).summary()["speed_rpm"] == 60.0
    s = cam.dynamics(77.7, stiffness=2000, sweep=False).summary()
    assert s["speed_rpm"] == 77.7


# ---- optimise -----------------------------------------------------------------------------------------
OPTIMISE_LINES = [
    # the objective named as report.json's areas name it, with the path that holds it
    Template("objective area (thesis Eq. 4.21 area ½∮(R_b + s)² dθ, report.json areas.thesis_eq_4_21): "
             "{optimise.initial_value} → {areas.thesis_eq_4_21} {u}² ({abs:optimise.reduction_percent} % {any}) in "
             "{optimise.evaluations} evaluations, {optimise.time_s} s"),
    Template("objective area (area inside the pitch curve, report.json areas.pitch_curve): {optimise.initial_value} → "
             "{areas.pitch_curve} {u}² ({abs:optimise.reduction_percent} % {any}) in {optimise.evaluations} "
             "evaluations, {optimise.time_s} s"),
    Template("the optimised cam's cross-section (top face): {area} {u}² (report.json area)", True),
    Template("status: {str:optimise.status}"),
    Template("message: {str:optimise.message}"),
    Template("start infeasible: {str:optimise.initial_violations.0.name} = {optimise.initial_violations.0.value} "
             "{str:optimise.initial_violations.0.unit} at {optimise.initial_violations.0.at_deg}° (limit "
             "{optimise.initial_violations.0.limit} {str:optimise.initial_violations.0.unit})"),
    Template("  {str:optimise.variables.0.name}{any}{optimise.variables.0.initial} →{any}{optimise.variables.0.final}"),
    Template("  {str:optimise.variables.1.name}{any}{optimise.variables.1.initial} →{any}{optimise.variables.1.final}"),
    Template("  {str:optimise.variables.2.name}{any}{optimise.variables.2.initial} →{any}{optimise.variables.2.final}"),
    Template("  closest to its limit: {str:optimise.worst_constraint.name} = {optimise.worst_constraint.value} "
             "{str:optimise.worst_constraint.unit} at {optimise.worst_constraint.at_deg}° (limit "
             "{optimise.worst_constraint.limit})"),
    Template("written to {any}/: {str:_files}, {len:files.plots} plots"),
]


@requires_ocp
@pytest.mark.parametrize("name", ["paper", "oscillating"])
def test_optimise(name, tmp_path):
    res = cli("optimise", "--plots", "--example", name, "--max-evaluations", "40", "-o", str(tmp_path))
    assert res.returncode in (0, 3), res.stderr
    report = json.loads((tmp_path / "report.json").read_text(encoding="utf-8"))
    opt = report["optimise"]
    key = "areas.thesis_eq_4_21" if name == "paper" else "areas.pitch_curve"
    # report.json names the objective, and its final value is the optimised cam's number at that path
    assert opt["objective_key"] == key and opt["objective_label"] in res.stdout
    assert opt["final_value"] == pytest.approx(lookup(report, key), rel=1e-12)
    assert opt["final_value"] != pytest.approx(report["area"], rel=1e-3)      # not the cross-section
    assert_held(held_to(res.stdout, OPTIMISE_LINES, derived(report), f"optimise {name}",
                        skip=lambda line: line.startswith("written to ")))
    html = (tmp_path / "report.html").read_text(encoding="utf-8")
    assert f"report.json <code>{key}</code>" in html


# ---- sweep --size -------------------------------------------------------------------------------------
def test_sweep_size_prints_the_radius_to_the_tolerance(tmp_path):
    """The smallest R_b "to 0.01 mm" is printed with two decimals, and it is the CSV's value (and the
    chart's): a multiple of the tolerance that passed the checks."""
    import csv

    res = cli("sweep", "--vary", "motion[1].lift,motion[3].lift=15:25:3", "--size", "base_radius", "--workers", "0",
              "-o", str(tmp_path))
    assert res.returncode == 0, res.stderr
    rows = list(csv.DictReader((tmp_path / "sizing.csv").open(encoding="utf-8")))
    tables, rest = rich_tables(res.stdout)
    table = tables["smallest base radius (mm, to 0.01)"]
    assert len(table) == len(rows) == 3
    for printed, row in zip(table, rows):
        assert printed[0] == f"{float(row['motion[1].lift']):g}"
        assert printed[1] == f"{float(row['min_base_radius']):.2f}"               # the tolerance's digits
        assert float(row["min_base_radius"]) == round(float(row["min_base_radius"]), 2)
        assert float(row["min_base_radius"]) - float(row["failing_radius"]) == pytest.approx(0.01, abs=1e-9)
        assert printed[2] == row["binding_checks"]
        assert float(row["check_pressure_angle"]) <= 30.0                     # the radius printed passes


# ---- repr() ---------------------------------------------------------------------------------------------
REPR_NUMBERS = {
    "default": ["R_b = 40", "r = 8", "offset e = 0", "thickness 10", "M = 60", "translating roller", "plate cam"],
    "paper": ["R_b = 22.3607", "r = 5", "offset e = 10", "M = 60"],
    "oscillating": ["oscillating roller", "pivot d = 60", "arm L = 45", "r = 8", "R_b = 40"],
    "flat": ["translating flat face", "R_b = 40"],
    "packaging": ["R_b = 60", "thickness 12", "M = 133"],
    "groove": ["groove cam", "Ø150", "groove 16.1 wide, 8 deep", "r = 8"],
    "conjugate": ["conjugate cam", "offset e = 5", "second roller r = 6", "106", "gap 3"],
    "cylindrical": ["cylindrical cam", "translating roller r = 5", "pitch radius 40", "length 60", "groove 10.05 wide"],
    "cylindrical_oscillating": ["cylindrical cam", "oscillating roller r = 5", "pivot d = 50", "arm L = 50",
                                "length 50"],
    "parallel_indexer": ["parallel_indexer cam", "turret of 8 stations × 2 planes", "rollers r = 10 on R_p = 50, C = 120",
                         "index 120°", "2 plates 16 thick"],
    "barrel_indexer": ["barrel_indexer cam", "turret of 6 stations", "rollers r = 12 over t = 27–45", "C 52",
                       "index 240°", "R_p 60", "rib radii 25–40", "length 80"],
    "globoidal_indexer": ["globoidal_indexer cam", "turret of 12 stations", "rollers r = 12 over t = 74–96",
                          "C 150", "index 120°", "rib globoids 76–100", "width 56"],
}


@pytest.mark.parametrize("name", NAMES)
def test_repr_names_body_follower_and_numbers(name):
    from cam_workbench import Cam

    text = repr(Cam.example(name))
    assert text.startswith("Cam(") and "lengths in mm" in text
    for part in REPR_NUMBERS[name]:
        assert part in text, (part, text)
    if name == "oscillating":
        assert "e =" not in text and "e=" not in text
    if name in ("conjugate", "cylindrical", "parallel_indexer"):     # docs/python.md quotes them
        doc = " ".join((ROOT / "docs" / "python.md").read_text(encoding="utf-8").split())
        assert f"`{text}`" in doc


# ---- the examples, listed everywhere ------------------------------------------------------------------
def test_every_example_is_listed_where_examples_are_named():
    from cam_workbench import Cam
    from cam_workbench.generators.spec.examples import DESCRIPTIONS
    from cam_workbench.generators.spec.reference import render

    help_text = " ".join(cli("build", "--help").stdout.split())
    docs = {p: (ROOT / "docs" / p).read_text(encoding="utf-8") for p in ("cli.md", "python.md")}
    spec_md = (ROOT / "docs" / "spec.md").read_text(encoding="utf-8")
    assert spec_md == render()
    for name in NAMES:
        assert f"'{name}' ({' '.join(DESCRIPTIONS[name].split())})" in help_text, name
        assert f"| `{name}` | {DESCRIPTIONS[name]} |" in spec_md
        for p, text in docs.items():
            assert f"`{name}`" in text, (p, name)
        assert f'"{name}"' in Cam.example.__doc__, name

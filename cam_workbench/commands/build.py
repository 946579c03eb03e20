"""``cam-workbench build``: the solid as STEP, the drawing as DXF, the design numbers as
report.json and the report as report.html with its figures (one OutputSet: all or nothing)."""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Callable

from cam_workbench.generators.checks.areas import area_label
from cam_workbench.generators.bodies.cylindrical import CylindricalBody
from cam_workbench.generators.bodies.plane import PlaneCamBody
from cam_workbench.generators.kinds import body_named, pitch_named
from cam_workbench.generators.kinds.by_class import ByClass
from cam_workbench.generators.studies.remedies import remedy_lines

from . import build_indexer, build_spatial_indexer
from .common import write_cam
from .dxf_cmd import describe as describe_dxf


def run(args: argparse.Namespace) -> int:
    report, out = write_cam(args, "build")
    _print_summary(report, out)
    return 0


#: body class → its summary printer ``fn(report, out)``; a body with none gets :func:`_print_any_summary`
SUMMARIES: ByClass[Callable[[dict, Path], None]] = ByClass("build's summary")


def _print_summary(s: dict, out: Path) -> None:
    printer = SUMMARIES.for_class(body_named(s["body"]["kind"])) or _print_any_summary
    printer(s, out)


def _files_line(s: dict, out: Path) -> None:
    f = s["files"]
    plots = f.get("plots", [])
    print(f"cam written to {out}/: {', '.join(v for v in f.values() if isinstance(v, str))}"
          + (f", {len(plots)} plots" if plots else ""))


def _print_any_summary(s: dict, out: Path) -> None:
    """What every body's report.json holds: the files, the volume, the checks' verdict."""
    _files_line(s, out)
    print(f"  {s['body']['kind']} cam, volume {s['volume']:.6g} {s['units']}³")
    ck = s["checks"]
    print("  design checks: " + ("all pass" if ck["passed"] else f"FAILED {', '.join(ck['failed'])}"))
    _print_remedies(ck)


@SUMMARIES.register(PlaneCamBody)
def _print_plane_summary(s: dict, out: Path) -> None:
    """A plane cam's: its pitch curve, profile, pressure angle, curvature, areas and drawing."""
    u = s["units"]
    lu = s["motion"]["lift_unit"]
    p = s["pitch"]
    fol = s["follower"]
    _files_line(s, out)
    print(f"  follower (lengths in {u}): {fol['label']}")
    kind = ("PH quintic spline, M" if pitch_named(p["representation"]).exact
            else f"periodic B-spline (degree {p['degree']}), knot spans")
    print(f"  {fol['curve']}: {kind} = {p['segments']}, max deviation {p['max_deviation']:.3g} {lu}"
          f" at {p['max_deviation_at_deg']:.2f}°; profile within {s['profile']['max_error']:.3g} {u} of the true one")
    print(f"  pressure angle: max {s['pressure_angle']['max_deg']:.2f}° at {s['pressure_angle']['at_deg']:.2f}°")
    c = s["curvature"]
    print(f"  curvature: min {fol['curve']} radius {c['min_pitch_radius']:.4g} {u}, "
          f"min profile radius {c['min_profile_radius']:.4g} {u} at {c['at_deg']:.2f}°")
    print(f"  {area_text(s)}, volume {s['volume']:.6g} {u}³")
    print("  DXF " + describe_dxf(s["drawing"], u))
    ck = s["checks"]
    print("  design checks: " + ("all pass" if ck["passed"] else
                                 f"FAILED {', '.join(ck['failed'])} (see `cam-workbench check`)"))
    _print_remedies(ck)
    cont = ck["results"].get("continuity")
    if cont and cont["status"] == "fail":
        print(f"  warning: a segment junction breaks its laws' promise: {cont['note']}")
    if "dynamics" in s:
        d = s["dynamics"]
        c, jp = d["contact"], d.get("jump_speed")
        jump = "" if jp is None else (f"; jump speed {jp['rpm']:.5g} rpm" if jp["rpm"] is not None
                                      else f"; jump speed: {jp['note']}")
        print(f"  dynamics at {d['speed_rpm']:.5g} rpm: "
              + ("the follower stays on the cam" if c["kept"] else f"the follower LEAVES the cam for {c['off_cam_deg']:.4g}°")
              + f", smallest contact force {c['min_force']:.4g} {c['unit']} (rigid {c['rigid_min_force']:.4g}){jump} "
              "(see `cam-workbench dynamics`)")
    it = s["interpolator"]
    print(f"  interpolator: {it['commands']} commands (Δt = {it['sample_period']:g} s), max deviation "
          f"{it['max_deviation']:.3g} {lu}; max v {it['velocity']['max']:.5g}, a {it['acceleration']['max']:.5g}, "
          f"j {it['jerk']['max']:.5g} ({it['differencing']} differences)")
    if it.get("warning"):
        print(f"  warning: {it['warning']}")
    m = s["machining"]
    print(f"  cam.nc: {m['program']} program, tool radius {m['tool_radius']:g} {u}, {m['gcode_lines']} lines")
    body = s.get("body") or {}
    second = body.get("second_cam")
    if isinstance(second, dict):
        err = body["roller_distance_error"]
        print(f"  second cam (z {second['z'][0]:g} to {second['z'][1]:g} {u}): {second['follower']['label']}; max "
              f"deviation {second['pitch']['max_deviation']:.3g} {lu}, pressure angle max "
              f"{second['pressure_angle']['max_deg']:.2f}° at {second['pressure_angle']['at_deg']:.2f}°")
        print(f"  distance error between the rollers: max {err['max']:.3g} {u} at {err['at_deg']:.2f}° "
              f"(the two curves' deviations {err['first_cam_deviation']:.3g} + {err['second_cam_deviation']:.3g} {lu})")
        m2 = m.get("second_cam") or {}
        if m2:
            print(f"  {m2['file']}: the second cam's {m['program']} program, {m2['gcode_lines']} lines")


def _print_remedies(checks: dict) -> None:
    """A line per failing check: report.json's ``checks.results[name].remedy``."""
    for line in remedy_lines(checks):
        print(f"    remedy {line}")


def area_text(s: dict) -> str:
    """report.json's areas named apart, as report.json names them: ``area`` (the built
    cross-section) and the design-intent ``areas`` — the thesis' Eq. 4.21 area where the
    follower has one, else the area inside its design curve."""
    u = s["units"]
    areas = s["areas"]
    key = "thesis_eq_4_21" if areas.get("thesis_eq_4_21") is not None else "pitch_curve"
    return (f"{area_label('area')} {s['area']:.6g} {u}² (report.json area); "
            f"{area_label(key, s['follower']['curve'])} {areas[key]:.6g} {u}² (areas.{key})")


@SUMMARIES.register(CylindricalBody)
def _print_cylinder_summary(s: dict, out: Path) -> None:
    """A cylindrical cam's: its cylinder and groove, walls, pressure angles, program and drawing."""
    u = s["units"]
    b = s["body"]
    _files_line(s, out)
    print(f"  {b['kind']} cam: pitch radius {b['pitch_radius']:g} {u}, outer radius {b['outer_radius']:g} {u}, "
          f"length {b['length']:g} {u}; groove {b['groove_width']:g} {u} wide, {b['groove_depth']:g} {u} deep")
    pa = s["pressure_angle"]
    print(f"  pressure angle: max {pa['max_deg']:.2f}° at {pa['at_deg']:.2f}° (pitch radius), "
          f"{pa['bottom_max_deg']:.2f}° at the groove's bottom")
    we = b.get("wall_error")
    if we:
        print(f"  wall faces within {we['value']:.3g} {u} of the exact walls ({we['faces']} faces, {we['points']} points)")
    sol = s.get("solid") or {}
    print(f"  volume {s['volume']:.6g} {u}³ (kernel {sol.get('volume_rel_diff', float('nan')):+.2e} relative)")
    ck = s["checks"]
    print("  design checks: " + ("all pass" if ck["passed"] else f"FAILED {', '.join(ck['failed'])}"))
    _print_remedies(ck)
    m = s.get("machining") or {}
    if m:
        print(f"  cam.nc: 4-axis X-Z-A program, tool radius {m['tool_radius']:g} {u}, {m['gcode_lines']} lines")
    dr = s.get("drawing") or {}
    fit = dr.get("developed_fit_error")
    if fit:
        print(f"  cam.dxf: developed walls as cubic splines within {fit['value']:.3g} {u} of the exact walls "
              f"(pitch line {fit['pitch_line']:.3g} {u}), side and end views")


@SUMMARIES.register(build_indexer.BODY)
def _print_indexer_summary(s: dict, out: Path) -> None:
    """A parallel indexer's (:mod:`.build_indexer`'s lines): its turret, pressure angles, clearance,
    fitted flanks, recovered turret angle, volume and drive, the checks' verdict, each plate's program."""
    _files_line(s, out)
    for line in build_indexer.body_lines(s):
        print(line)
    ck = s["checks"]
    print("  design checks: " + ("all pass" if ck["passed"] else f"FAILED {', '.join(ck['failed'])}"))
    _print_remedies(ck)
    for line in build_indexer.program_lines(s):
        print(line)


@SUMMARIES.register(build_spatial_indexer.BODY)
def _print_spatial_indexer_summary(s: dict, out: Path) -> None:
    """A barrel or globoidal indexer's (:mod:`.build_spatial_indexer`'s lines): its turret and rib,
    pressure angles, fitted flanks, recovered turret angle, volume and drive, the checks' verdict,
    its 4-axis program."""
    _files_line(s, out)
    for line in build_spatial_indexer.body_lines(s):
        print(line)
    ck = s["checks"]
    print("  design checks: " + ("all pass" if ck["passed"] else f"FAILED {', '.join(ck['failed'])}"))
    _print_remedies(ck)
    for line in build_spatial_indexer.program_lines(s):
        print(line)

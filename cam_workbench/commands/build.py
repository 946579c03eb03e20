"""``cam-workbench build``: the solid as STEP, the drawing as DXF, the design numbers as
report.json and the report as report.html with its plots (one OutputSet: all or nothing)."""
from __future__ import annotations

import argparse
from pathlib import Path

from exporters.atomic import OutputSet
from exporters.dxf import build_dxf
from exporters.machining_outputs import machining_outputs
from exporters.step import write_step
from generators.errors import GeometryError

from .. import occ_build
from .common import add_spec_arguments, design_for, spec_from_args
from .dxf_cmd import describe as describe_dxf
from .report_cmd import add_report_files, base_summary, plot_count, plot_progress


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "build", help="build the cam: cam.step, cam.dxf, cam.nc, commands.csv, report.json, report.html, plots",
        description="Design the cam (PH pitch curve, exact profile, design checks) and write "
                    "cam.step (the solid, in the spec's units), cam.dxf (the drawing, see [drawing]), "
                    "cam.nc (machining.program: xy or xc), commands.csv (the interpolator's commands), "
                    "report.json, report.html and the report's plots (plot_*.png) into the output folder. "
                    "Nothing is written if the spec is bad or the cam cannot be made.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    p.add_argument("-o", "--output", default="out", metavar="OUT",
                   help="output folder (created if needed; default: out)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    spec = spec_from_args(args)
    design = design_for(spec)
    shape = occ_build.cam_solid(design)
    # pitch.representation = "bspline": the kernel solid's profile is OCCT's exact offset curve,
    # which STEP cannot hold; the file gets the fitted offset B-spline (design.profile)
    step_shape = shape if design.bspline is None else occ_build.cam_solid(design, exact_offset=False)
    for s in {id(shape): shape, id(step_shape): step_shape}.values():
        if not occ_build.is_valid(s) or occ_build.count_solids(s) != 1:
            raise GeometryError("kernel", "OCCT reports the cam solid as invalid")
    summary = base_summary(design, shape)
    if design.bspline is not None:
        summary["solid"]["profile"] = "exact offset of the fitted pitch B-spline (Geom_OffsetCurve)"
        summary["solid"]["step_profile"] = "fitted offset B-spline (profile.max_error)"
        summary["solid"]["step_cross_section_area"] = occ_build.face_area(
            occ_build.planar_face_at(step_shape, design.spec.cam.thickness))
    # computed before anything is written; its plots come with the report (report.html + PNG)
    machining = machining_outputs(design, plots=False)
    summary["interpolator"] = machining.interpolator_summary
    summary["machining"] = machining.machining_summary
    doc, dxf_info = build_dxf(design, summary)
    summary["drawing"] = dxf_info.summary()
    out = Path(args.output)
    files = {"step": "cam.step", "dxf": "cam.dxf", **machining.files}
    prog, cb = plot_progress(plot_count(design, summary))
    with prog, OutputSet(out) as o:
        o.add(files["step"], lambda p: write_step(step_shape, p, spec.units))
        o.add(files["dxf"], lambda p: doc.saveas(str(p)))
        machining.write(o)
        report = add_report_files(o, design, summary, files, progress=cb)
    _print_summary(report, out)
    return 0


def _print_summary(s: dict, out: Path) -> None:
    u = s["units"]
    p = s["pitch"]
    f = s["files"]
    print(f"cam written to {out}/: {', '.join(v for v in f.values() if isinstance(v, str))}, "
          f"{len(f['plots'])} plots")
    kind = ("PH quintic spline, M" if p["representation"] == "ph"
            else f"periodic B-spline (degree {p['degree']}), knot spans")
    print(f"  pitch: {kind} = {p['segments']}, max deviation {p['max_deviation']:.3g} {u}"
          f" at {p['max_deviation_at_deg']:.2f}°; profile within {s['profile']['max_error']:.3g} {u} of the true one")
    print(f"  pressure angle: max {s['pressure_angle']['max_deg']:.2f}° at {s['pressure_angle']['at_deg']:.2f}°")
    c = s["curvature"]
    print(f"  curvature: min pitch radius {c['min_pitch_radius']:.4g} {u}, "
          f"min profile radius {c['min_profile_radius']:.4g} {u} at {c['at_deg']:.2f}°")
    print(f"  area {s['area']:.6g} {u}², volume {s['volume']:.6g} {u}³ "
          f"(thesis Eq. 4.21 area inside the pitch curve: {s['areas']['thesis_eq_4_21']:.6g} {u}²)")
    print("  DXF " + describe_dxf(s["drawing"], u))
    ck = s["checks"]
    print("  design checks: " + ("all pass" if ck["passed"] else
                                 f"FAILED {', '.join(ck['failed'])} (see `cam-workbench check`)"))
    it = s["interpolator"]
    print(f"  interpolator: {it['commands']} commands (Δt = {it['sample_period']:g} s), max deviation "
          f"{it['max_deviation']:.3g} {u}; max v {it['velocity']['max']:.5g}, a {it['acceleration']['max']:.5g}, "
          f"j {it['jerk']['max']:.5g} ({it['differencing']} differences)")
    if it.get("warning"):
        print(f"  warning: {it['warning']}")
    m = s["machining"]
    print(f"  cam.nc: {m['program']} program, tool radius {m['tool_radius']:g} {u}, {m['gcode_lines']} lines")

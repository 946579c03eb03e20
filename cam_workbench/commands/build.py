"""``cam-workbench build``: the solid as STEP and the design numbers as report.json."""
from __future__ import annotations

import argparse
from pathlib import Path

from exporters.atomic import OutputSet
from exporters.machining_outputs import machining_outputs
from exporters.report_json import report_json_text
from exporters.step import write_step
from generators.cam_design import design_cam
from generators.errors import GeometryError

from .. import occ_build
from .common import add_spec_arguments, progress_reporter, spec_from_args


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "build", help="build the cam: cam.step, report.json, cam.nc, commands.csv, plots",
        description="Design the cam (PH pitch curve, exact profile, buildability checks) and write "
                    "cam.step (the solid, in the spec's units) and report.json into the output folder, "
                    "with the machining program cam.nc (machining.program: xy or xc), the interpolator's "
                    "command table commands.csv and its accuracy plots (PNG). "
                    "Nothing is written if the spec is bad or the cam cannot be made.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    p.add_argument("-o", "--output", default="out", metavar="OUT",
                   help="output folder (created if needed; default: out)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    spec = spec_from_args(args)
    if spec.pitch.tolerance is not None:
        prog, cb = progress_reporter("choosing M for pitch.tolerance")
        with prog:
            design = design_cam(spec, progress=cb)
    else:
        design = design_cam(spec)
    shape = occ_build.cam_solid(design)
    if not occ_build.is_valid(shape) or occ_build.count_solids(shape) != 1:
        raise GeometryError("kernel", "OCCT reports the cam solid as invalid")
    summary = design.summary()
    summary["solid"] = solid_summary(shape, design.spec.cam.thickness)
    machining = machining_outputs(design)
    summary["interpolator"] = machining.interpolator_summary
    summary["machining"] = machining.machining_summary
    out = Path(args.output)
    files = {"step": "cam.step", "report": "report.json", **machining.files}
    with OutputSet(out) as o:
        o.add(files["step"], lambda p: write_step(shape, p, spec.units))
        machining.write(o)
        o.add_text(files["report"], report_json_text(summary, files))
    _print_summary({**summary, "files": files}, out)
    return 0


def solid_summary(shape: object, thickness: float) -> dict[str, float | int | bool]:
    """What the kernel says about the built solid (a cross-check of the exact numbers)."""
    face = occ_build.planar_face_at(shape, thickness)
    return {
        "valid": occ_build.is_valid(shape),
        "solids": occ_build.count_solids(shape),
        "kernel_volume": occ_build.kernel_volume(shape),
        "cross_section_area": occ_build.face_area(face),
    }


def _print_summary(s: dict, out: Path) -> None:
    u = s["units"]
    p = s["pitch"]
    print(f"cam written to {out}/: {', '.join(s['files'].values())}")
    print(f"  pitch: PH quintic spline, M = {p['segments']}, max deviation {p['max_deviation']:.3g} {u}"
          f" at {p['max_deviation_at_deg']:.2f}°")
    print(f"  pressure angle: max {s['pressure_angle']['max_deg']:.2f}° at {s['pressure_angle']['at_deg']:.2f}°")
    c = s["curvature"]
    print(f"  curvature: min pitch radius {c['min_pitch_radius']:.4g} {u}, "
          f"min profile radius {c['min_profile_radius']:.4g} {u} at {c['at_deg']:.2f}°")
    print(f"  area {s['area']:.6g} {u}², volume {s['volume']:.6g} {u}³")
    it = s["interpolator"]
    print(f"  interpolator: {it['commands']} commands (Δt = {it['sample_period']:g} s), max deviation "
          f"{it['max_deviation']:.3g} {u}; max v {it['velocity']['max']:.5g}, a {it['acceleration']['max']:.5g}, "
          f"j {it['jerk']['max']:.5g} ({it['differencing']} differences)")
    if it.get("warning"):
        print(f"  warning: {it['warning']}")
    m = s["machining"]
    print(f"  cam.nc: {m['program']} program, tool radius {m['tool_radius']:g} {u}, {m['gcode_lines']} lines")

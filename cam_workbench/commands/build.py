"""``cam-workbench build``: the solid as STEP and the design numbers as report.json."""
from __future__ import annotations

import argparse
from pathlib import Path

from exporters.atomic import OutputSet
from exporters.report_json import report_json_text
from exporters.step import write_step
from generators.cam_design import design_cam
from generators.errors import GeometryError

from .. import occ_build
from .common import add_spec_arguments, progress_reporter, spec_from_args


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "build", help="build the cam: cam.step and report.json",
        description="Design the cam (PH pitch curve, exact profile, buildability checks) and write "
                    "cam.step (the solid, in the spec's units) and report.json into the output folder. "
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
    # pitch.representation = "bspline": the kernel solid's profile is OCCT's exact offset curve,
    # which STEP cannot hold; the file gets the fitted offset B-spline (design.profile)
    step_shape = shape if design.bspline is None else occ_build.cam_solid(design, exact_offset=False)
    for s in {id(shape): shape, id(step_shape): step_shape}.values():
        if not occ_build.is_valid(s) or occ_build.count_solids(s) != 1:
            raise GeometryError("kernel", "OCCT reports the cam solid as invalid")
    summary = design.summary()
    summary["solid"] = solid_summary(shape, design.spec.cam.thickness)
    if design.bspline is not None:
        summary["solid"]["profile"] = "exact offset of the fitted pitch B-spline (Geom_OffsetCurve)"
        summary["solid"]["step_profile"] = "fitted offset B-spline (profile.max_error)"
        summary["solid"]["step_cross_section_area"] = occ_build.face_area(
            occ_build.planar_face_at(step_shape, design.spec.cam.thickness))
    out = Path(args.output)
    files = {"step": "cam.step", "report": "report.json"}
    with OutputSet(out) as o:
        o.add(files["step"], lambda p: write_step(step_shape, p, spec.units))
        o.add_text(files["report"], report_json_text(summary, files))
    _print_summary(summary, out)
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
    print(f"cam written to {out}/: cam.step, report.json")
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
    ck = s["checks"]
    print("  design checks: " + ("all pass" if ck["passed"] else
                                 f"FAILED {', '.join(ck['failed'])} (see `cam-workbench check`)"))

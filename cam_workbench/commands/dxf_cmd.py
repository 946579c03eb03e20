"""``cam-workbench dxf``: the manufacturing drawing (cam.dxf) alone."""
from __future__ import annotations

import argparse
from pathlib import Path

from cam_workbench.exporters.atomic import OutputSet, atomic_path
from cam_workbench.exporters.output_rule import check_output_file
from cam_workbench.generators.spec.params import params_of
from cam_workbench.generators.spec import DrawingSection, spec_digest

from . import add_command
from ..pipeline import run_pipeline
from .common import add_output_arguments, add_spec_arguments, admit_output, design_for, output_claim, spec_from_args

_DECL = params_of(DrawingSection)


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "dxf",
        description="Design the cam and write its manufacturing drawing as DXF: the profile (layer PROFILE) "
                    "as a polynomial cubic SPLINE within drawing.chord_tolerance of the profile NURBS, which "
                    "every DXF reader draws (the default, --curves cubic); as that NURBS itself (--curves "
                    "spline: the exact rational offset, degree 9, for a PH pitch curve, which LibreCAD and "
                    "many CAM programs drop; for pitch.representation = \"bspline\" a fitted B-spline, its "
                    "measured error printed); or as arcs or a polyline within the tolerance for machines "
                    "that read no splines. The measured distance is printed and stated in the title block. "
                    "Also the pitch curve, base and prime circles, bore, centre lines, dimensions and a "
                    "title block with the motion table. The spec's [drawing] section sets the defaults.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    p.add_argument("--curves", choices=_DECL["curves"].choices, default=None,
                   help=f"{_DECL['curves'].doc} (default: the spec's drawing.curves)")
    p.add_argument("--tolerance", type=float, default=None, metavar="TOL",
                   help=f"{_DECL['chord_tolerance'].doc}, in the spec's units "
                        "(default: the spec's drawing.chord_tolerance)")
    p.add_argument("--dxf-version", choices=_DECL["dxf_version"].choices, default=None,
                   help=f"{_DECL['dxf_version'].doc} (default: the spec's drawing.dxf_version)")
    add_output_arguments(p, "out", "a .dxf file name (written, replacing a file of that name), or a folder "
                                   "to write cam.dxf into")
    p.set_defaults(run=run)


def output_file(arg: str) -> Path:
    """``-o`` names the file when it ends in .dxf, otherwise the folder for cam.dxf."""
    out = Path(arg)
    return out if out.suffix.lower() == ".dxf" else out / "cam.dxf"


def run(args: argparse.Namespace) -> int:
    spec = spec_from_args(args)
    changes = {}
    if args.curves is not None:
        changes["drawing.curves"] = args.curves
    if args.tolerance is not None:
        changes["drawing.chord_tolerance"] = args.tolerance
    if args.dxf_version is not None:
        changes["drawing.dxf_version"] = args.dxf_version
    if changes:
        spec = spec.replace(**changes)
    named_file = Path(args.output).suffix.lower() == ".dxf"
    if named_file:
        check_output_file(args.output, digest=spec_digest(spec))
    else:
        admit_output(args, spec, "dxf", (output_file(args.output).name,))
    # the drawing stage `build` runs, with the design numbers its title block quotes
    outputs = run_pipeline(spec, solid=False, machining=False, drawing=True, design=design_for(spec))
    doc, info = outputs.dxf
    target = output_file(args.output)
    if named_file:
        with atomic_path(target) as tmp:          # a file the user named
            doc.saveas(str(tmp))
    else:                                         # an output folder: cam_workbench.exporters.output_rule
        with OutputSet(target.parent, output_claim(args, spec, "dxf")) as o:
            o.add(target.name, lambda p: doc.saveas(str(p)))
    print(f"drawing written to {target}")
    print("  " + describe(info.summary(), spec.units))
    return 0


def describe(d: dict, units: str) -> str:
    """One line on how the curves went into the DXF (for the CLI), from report.json's ``drawing``
    section: "exact" only where the profile NURBS is exact (``profile_curve`` says what it is; a
    fitted profile comes with its measured error), and for drawn approximations their measured
    distance from the NURBS — the profile's, then the largest of the other curves'."""
    fit = d.get("developed_fit_error")
    if fit is not None:            # a cylindrical cam: the developed walls and pitch line, fitted
        kind = {"cubic": f"{d['splines']} cubic SPLINEs", "arcs": f"{d['entities']} arcs and lines",
                "polyline": f"{d['entities']} polylines"}[d["curves"]]
        return (f"WALL_LOWER, WALL_UPPER: {kind} with the PITCH line, fitted to the developed walls at the outer "
                f"radius: max fit error {fit['value']:.3g} {units} (pitch line {fit['pitch_line']:.3g} {units}), "
                f"not exact (tolerance {d['chord_tolerance']:g} {units}, {d['file_version']})")
    curve = d.get("profile_curve")
    if d["curves"] == "spline":
        what = curve if curve else ("exact profile NURBS" if d.get("exact") else "profile NURBS")
        return f"PROFILE: SPLINE = the {what} ({d['file_version']})"
    kind = {"cubic": f"polynomial cubic SPLINE of {d['profile_poles']} poles",
            "arcs": f"{d['profile_arcs']} arcs + {d['profile_lines']} lines",
            "polyline": f"closed polyline of {d['profile_lines']} segments"}[d["curves"]]
    of = f"the profile NURBS (the {curve})" if curve else "the profile NURBS"
    others = {k: v for k, v in d.get("max_error_by_layer", {}).items() if k != "PROFILE"}
    rest = (f"; {', '.join(others)} drawn alike, within {max(others.values()):.3g} {units} of theirs"
            if others else "")
    return (f"PROFILE: {kind}, max distance {d['profile_max_error']:.3g} {units} from {of} "
            f"(tolerance {d['chord_tolerance']:g} {units}, {d['file_version']}){rest}")

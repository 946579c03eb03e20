"""``cam-workbench dxf``: the manufacturing drawing (cam.dxf) alone."""
from __future__ import annotations

import argparse
from pathlib import Path

from cam_workbench.exporters.atomic import OutputSet, atomic_path
from cam_workbench.exporters.output_rule import check_output_file
from cam_workbench.generators.spec import spec_digest

from ..pipeline import run_pipeline
from .common import admit_output, design_for, output_claim, spec_from_args


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
    trace = d.get("drawn_trace_error")
    if trace is not None:          # a barrel or globoidal indexer: views, the flanks' traces (barrel) fitted
        fit = d["flank_fit_error"]
        drawn = ("no flank traces (the flanks are surfaces)" if trace["value"] is None else
                 f"{d['splines']} flank traces as cubic SPLINEs within {trace['value']:.3g} {units} of the exact "
                 "envelope (measured, not exact)")
        return (f"{d['kind']} indexer's views: circles, arcs and lines exact; {drawn}; the flank surfaces' fit "
                f"error {fit['value']:.3g} {units} quoted in the title block ({d['file_version']})")
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

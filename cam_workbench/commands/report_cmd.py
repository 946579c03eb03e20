"""``cam-workbench report``: report.html (self-contained, inline SVG plots), the plots as PNG
and report.json.  ``build`` writes the same files through :func:`add_report_files`."""
from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import numpy as np

from exporters.atomic import OutputSet
from exporters.report_html import Series, render_report, report_plots
from exporters.report_json import report_json_text
from generators.cam_design import CamDesign
from generators.errors import GeometryError

from .. import occ_build
from .common import add_spec_arguments, design_for, spec_from_args

HTML_NAME = "report.html"
JSON_NAME = "report.json"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "report", help="write the design report: report.html, plot PNGs, report.json",
        description="Design the cam and write its report: report.html (one self-contained file: the spec, "
                    "the cam with its follower, s/v/a/j, pressure angle, radius of curvature, interpolation "
                    "error, accuracy figures), the plots as PNG files and report.json, whose numbers the "
                    "HTML tables show. Nothing is written if the spec is bad or the cam cannot be made.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    p.add_argument("-o", "--output", default="out", metavar="OUT",
                   help="output folder (created if needed; default: out)")
    p.set_defaults(run=run)


def solid_summary(shape: object, thickness: float) -> dict[str, float | int | bool]:
    """What the kernel says about the built solid (a cross-check of the exact numbers)."""
    face = occ_build.planar_face_at(shape, thickness)
    return {
        "valid": occ_build.is_valid(shape),
        "solids": occ_build.count_solids(shape),
        "kernel_volume": occ_build.kernel_volume(shape),
        "cross_section_area": occ_build.face_area(face),
    }


def optional_series(design: CamDesign, report: dict[str, Any]) -> dict[str, Series]:
    """θ-series for the report's "Contact force and stress" figure: the driving force
    (thesis Eq. 3.5) and Hertz stress (Eq. 3.6) from the design checks' state model, when the
    spec gives the follower a load (preload, spring or mass); otherwise nothing."""
    from generators.design_checks import StateModel, check_samples
    from generators.params import unit_name

    spec = design.spec
    model = StateModel(spec, design.program)
    if not model.has_load:
        return {}
    cs = check_samples(design.program, "dense", spec.checks.samples)
    st = model.state(cs.theta, cs.segment)
    deg = np.rad2deg(cs.theta)
    out = {"contact_force": Series(deg, st.force, "driving force F (thesis Eq. 3.5)",
                                   unit_name("force", spec.units), spec.checks.min_force, "min")}
    if spec.is_roller:
        out["contact_stress"] = Series(deg, st.stress, "Hertz contact stress (thesis Eq. 3.6)",
                                       unit_name("stress", spec.units), spec.material.allowable_stress, "max")
    return out


def add_report_files(out: OutputSet, design: CamDesign, summary: dict[str, Any], files: dict[str, Any],
                     progress: Any = None) -> dict[str, Any]:
    """Add report.json, report.html and the plot PNGs to ``out``; ``files`` (name → file) is
    completed with them and stored in report.json.  Returns the report as written."""
    series = optional_series(design, summary)
    names = [p.png_name for p in report_plots(design, summary, series)]
    files = dict(files, report=JSON_NAME, html=HTML_NAME, plots=names)
    text = report_json_text(summary, files)
    report = json.loads(text)  # the HTML shows exactly what the JSON holds
    html_text, pngs = render_report(design, report, series, progress=progress)
    out.add_text(JSON_NAME, text)
    out.add_text(HTML_NAME, html_text)
    for name in names:
        out.add_bytes(name, pngs[name])
    return report


def base_summary(design: CamDesign, shape: Any | None = None) -> dict[str, Any]:
    """design.summary() with the spec itself and, given the solid, the kernel's check."""
    summary = design.summary()
    summary["spec"] = design.spec.to_dict()
    if shape is not None:
        solid = solid_summary(shape, design.spec.cam.thickness)
        # how far the kernel's integrals are from the exact (Green's theorem) numbers
        solid["volume_rel_diff"] = solid["kernel_volume"] / summary["volume"] - 1.0
        solid["area_rel_diff"] = solid["cross_section_area"] / summary["area"] - 1.0
        summary["solid"] = solid
    return summary


def plot_count(design: CamDesign, summary: dict[str, Any]) -> int:
    """How many figures the report of ``summary`` will draw."""
    return len(report_plots(design, summary, optional_series(design, summary)))


def plot_progress(total: int) -> tuple[Any, Any]:
    """A rich progress bar over the report's figures, and its callback."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    prog = Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
                    TimeElapsedColumn(), transient=True)
    task = prog.add_task("report", total=total)
    started = [False]

    def callback(title: str) -> None:
        if started[0]:
            prog.advance(task)
        started[0] = True
        prog.update(task, description=f"plotting: {title}")

    return prog, callback


def run(args: argparse.Namespace) -> int:
    spec = spec_from_args(args)
    design = design_for(spec)
    shape = occ_build.cam_solid(design)
    if not occ_build.is_valid(shape) or occ_build.count_solids(shape) != 1:
        raise GeometryError("kernel", "OCCT reports the cam solid as invalid")
    summary = base_summary(design, shape)
    out = Path(args.output)
    prog, cb = plot_progress(plot_count(design, summary))
    with prog, OutputSet(out) as o:
        report = add_report_files(o, design, summary, {}, progress=cb)
    print(f"report written to {out}/: {HTML_NAME}, {JSON_NAME}, " + ", ".join(report["files"]["plots"]))
    return 0

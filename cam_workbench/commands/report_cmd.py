"""``cam-workbench report``: report.html (self-contained, inline SVG figures), report.json and
with ``--plots`` the figures as PNG — the report ``build`` writes, from the same pipeline (:mod:`cam_workbench.pipeline`)."""
from __future__ import annotations

import argparse

from cam_workbench.exporters.report_pages import HTML_NAME, JSON_NAME

from . import add_command
from .common import add_output_arguments, add_plots_argument, add_spec_arguments, write_cam


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "report",
        description="Design the cam and write its report: report.html (one self-contained file: the spec, "
                    "the cam with its follower, s/v/a/j, pressure angle, radius of curvature, interpolation "
                    "error, accuracy figures) and report.json, whose numbers the HTML tables show; with --plots "
                    "the figures as PNG files too. Nothing is written if the spec is bad or the cam cannot be made.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    add_output_arguments(p, "out")
    add_plots_argument(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    # the same numbers as `build` (every stage runs); only the report files are written
    report, out = write_cam(args, "report", report_only=True)
    print(f"report written to {out}/: " + ", ".join([HTML_NAME, JSON_NAME, *report["files"]["plots"]]))
    return 0

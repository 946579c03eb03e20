"""``cam-workbench report``: report.html (self-contained, inline SVG figures), report.json and
with ``--plots`` the figures as PNG — the report ``build`` writes, from the same pipeline (:mod:`cam_workbench.pipeline`)."""
from __future__ import annotations

import argparse

from cam_workbench.exporters.report_pages import HTML_NAME, JSON_NAME

from .common import write_cam


def run(args: argparse.Namespace) -> int:
    # the same numbers as `build` (every stage runs); only the report files are written
    report, out = write_cam(args, "report", report_only=True)
    print(f"report written to {out}/: " + ", ".join([HTML_NAME, JSON_NAME, *report["files"]["plots"]]))
    return 0

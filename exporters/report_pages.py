"""The report's page of each body: which figures it draws and how, registered per design class.

The report is report.json (every number) and report.html (the page showing them, its figures
inline as SVG), and on request each figure also as a PNG (``plots``).  What the page holds depends on the body: the plane
cams' page (:mod:`.report_html`) and the cylindrical cam's (:mod:`.report_cylindrical`) each
register a :class:`ReportPage` maker in :data:`REPORT_PAGES` for their design class;
:func:`add_report_files` writes any of them the same way.
"""
from __future__ import annotations

import json
from typing import Any, Callable, Protocol

from cam_workbench.generators.kinds.by_class import ByClass

from .atomic import OutputSet
from .chart_png import require_png
from .report_json import report_json_text

#: the report's file names
JSON_NAME = "report.json"
HTML_NAME = "report.html"


class ReportPage(Protocol):
    """A body's report page for one designed cam (made by its maker in :data:`REPORT_PAGES`)."""

    #: the PNG names of its figures, in the page's order
    figures: list[str]

    def render(self, report: dict[str, Any], progress: Callable[[str], None] | None, pngs: bool = False
               ) -> tuple[str, dict[str, bytes]]:
        """(the HTML text, {PNG name: bytes} — empty without ``pngs``) showing ``report``
        (report.json's content)."""


#: design class → ``maker(design, summary, dynamics) -> ReportPage`` (``dynamics``: the
#: :class:`~cam_workbench.generators.dynamics.DynamicsResult` behind ``summary["dynamics"]``, or None)
REPORT_PAGES: ByClass[Callable[[Any, dict[str, Any], Any], ReportPage]] = ByClass("the report page")


def report_page(design: Any, summary: dict[str, Any], dynamics: Any = None) -> ReportPage:
    """The report page of ``design`` by its body's maker.

    Raises:
        NotAvailable: the design's body registers no report page.
    """
    return REPORT_PAGES.of(design)(design, summary, dynamics)


def add_report_files(out: OutputSet, page: ReportPage, summary: dict[str, Any], files: dict[str, Any],
                     progress: Callable[[str], None] | None = None, plots: bool = False) -> dict[str, Any]:
    """Add report.json, report.html and, with ``plots``, the page's figures as PNG files to ``out``;
    ``files`` (name → file) is completed with them (``plots``: the PNG names, [] without) and
    stored in report.json.  Returns the report as written (the HTML shows exactly what the JSON
    holds).

    Raises:
        MissingDependency: ``plots`` without CairoSVG (before anything is added).
    """
    if plots:
        require_png()
    files = dict(files, report=JSON_NAME, html=HTML_NAME, plots=list(page.figures) if plots else [])
    text = report_json_text(summary, files)
    report = json.loads(text)
    html_text, pngs = page.render(report, progress, plots)
    out.add_text(JSON_NAME, text)
    out.add_text(HTML_NAME, html_text)
    for name in files["plots"]:
        out.add_bytes(name, pngs[name])
    return report


__all__ = ["HTML_NAME", "JSON_NAME", "REPORT_PAGES", "ReportPage", "add_report_files", "report_page"]

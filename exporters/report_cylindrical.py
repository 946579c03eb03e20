"""report.html of a cylindrical (barrel) cam: the checks' verdict and table, the body's numbers
(radii, groove, the walls' measured errors, the drawing's and the program's errors) and two
figures — the cylinder with its walls beside the developed view, and the pressure angle at the
pitch and the bottom radius over the cycle.  Every number on the page is read from report.json
(``data-key`` names the field), as in the plane cams' report (:mod:`cam_workbench.exporters.report_html`)."""
from __future__ import annotations

import html
from typing import Any, Callable, Mapping

from cam_workbench.generators.bodies.cylindrical import CylindricalDesign

from . import chart_png, chart_svg, plots_cylindrical
from .report_cells import quantity_table
from .report_html import CSS
from .report_pages import REPORT_PAGES
from .report_sections import checks_section

#: (name of the PNG, title) of the figures
FIGURES = (("plot_cylinder.png", "The cylinder and the developed view"),
           ("plot_pressure_angle.png", "Pressure angle over the cycle"))


def render_cylindrical_report(design: Any, report: Mapping[str, Any],
                              progress: Callable[[str], None] | None = None,
                              pngs: bool = False) -> tuple[str, dict[str, bytes]]:
    """The HTML text and, with ``pngs``, the PNG files ({name: bytes}) of a cylindrical cam's report."""
    makers = {"plot_cylinder.png": lambda: plots_cylindrical.cylindrical_figure(design),
              "plot_pressure_angle.png": lambda: plots_cylindrical.cylindrical_pressure_angle_figure(
                  design, report["checks"]["results"]["pressure_angle"].get("limit"))}
    svgs, files = {}, {}
    for name, title in FIGURES:
        if progress is not None:
            progress(title)
        svgs[name] = chart_svg.svg(makers[name](), name[5:-4])
        if pngs:
            files[name] = chart_png.png_bytes(svgs[name])
    return _page(report, svgs), files


@REPORT_PAGES.register(CylindricalDesign)
class CylindricalPage:
    """A cylindrical cam's report page (:func:`render_cylindrical_report`): its two figures."""

    figures = [name for name, _ in FIGURES]

    def __init__(self, design: Any, summary: Mapping[str, Any], dynamics: Any = None) -> None:
        self.design = design

    def render(self, report: dict[str, Any], progress: Callable[[str], None] | None, pngs: bool = False
               ) -> tuple[str, dict[str, bytes]]:
        return render_cylindrical_report(self.design, report, progress=progress, pngs=pngs)


def _page(report: Mapping[str, Any], svgs: Mapping[str, str]) -> str:
    u = report.get("units", "")
    body = report.get("body") or {}
    fol = report.get("follower") or {}
    lu = (report.get("motion") or {}).get("lift_unit", u)
    rule = ((report.get("solid") or {}).get("volume_rule") or {}).get("what", "OCCT's integration")
    rows = [
        ("follower", "follower.label", "", None),
        ("pitch radius R_p", "body.pitch_radius", u, None),
        ("outer radius R_o", "body.outer_radius", u, None),
        ("groove bottom radius R_b", "body.bottom_radius", u, None),
        ("length", "body.length", u, None),
        ("groove width (2r + clearance)", "body.groove_width", u, None),
        ("groove depth", "body.groove_depth", u, None),
        ("largest lift", "motion.max_lift", lu, None),
        ("volume (exact: closed form)", "volume", f"{u}³", None),
        (f"OCCT solid vs the exact volume (relative; measured by {rule}: not exact)", "solid.volume_rel_diff", "",
         None),
        ("… what the check allows that measure (relative)", "solid.volume_rule.allowed", "", None),
        ("wall data vs the exact walls", "body.wall_fit_error.value", u, None),
        ("built wall faces vs the exact walls", "body.wall_error.value", u, None),
        ("DXF developed walls vs the exact curves", "drawing.developed_fit_error.value", u, None),
        ("G-code chords vs the tool path", "machining.max_chord_error", u, None),
        ("finished wall vs the exact wall at R_b (radial tool offset)", "machining.finish_wall_deviation.bottom_radius",
         u, None),
        ("finished wall vs the exact wall at R_o", "machining.finish_wall_deviation.outer_radius", u, None),
        ("smallest radius of curvature of the developed centre line",
         "body.min_developed_curvature_radius.value", u, "body.min_developed_curvature_radius.at_deg"),
        ("material from the groove to the bore", "body.walls.groove_bottom_to_bore", u, None),
        ("material from the groove to the end z = 0", "body.walls.bottom_to_end", u, None),
        ("material from the groove to the end z = L", "body.walls.top_to_end", u, None),
    ]
    title = f"Cylindrical cam — {fol.get('label', '')}"
    figs = "".join(f'<figure id="fig-{name[5:-4]}" data-png="{name}">{svgs[name]}<figcaption>{html.escape(t)} '
                   f'({name})</figcaption></figure>' for name, t in FIGURES)
    approx = html.escape(str(body.get("approximation", "")))
    return ("<!doctype html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + html.escape(title)
            + f"</title><style>{CSS}</style></head><body><main>"
            f"<h1>{html.escape(title)}</h1><p class=\"sub\">cam_workbench report (report.json's numbers)</p>"
            '<h2 id="checks">Design checks</h2>' + checks_section(report)
            + '<h2 id="body">The cylinder</h2>' + quantity_table(report, rows)
            + f'<p class="note">{approx}</p>'
            + '<h2 id="figures">Figures</h2>' + figs
            + "</main></body></html>\n")

"""report.html of a spatial indexer (``cam.body`` = "barrel_indexer", "globoidal_indexer"): the
checks' verdict and table (the shared :func:`~cam_workbench.exporters.report_sections.checks_section`,
failing rows red), the indexer's geometry (stations, index, C, the rollers, the rib's radii, its
engagement windows, the pressure angles, the regularity margin and the rib's thickness), how closely
the built flanks hold the envelope (the fitted B-spline surfaces' measured error — fitted, never
exact), the turret's motion with the turret angle recovered from the flank surfaces, the drive
(times, output motion, torques, power, normal force, Hertz stress, the roller's life, the law's
characteristic values: the parallel indexer's :func:`~.report_indexer.drive_section`) and four
figures — the rib, the turret and its rollers in the fixed frame at mid-index
(:func:`.plots_spatial_indexer.spatial_picture`), the turret's motion
(:func:`.plots_spatial_indexer.spatial_motion_chart`), the driving contact's pressure angle over the
index against the limit (:func:`pressure_angle_chart`) and, with a load, the drive over the index
(:func:`.report_indexer.drive_chart`).  Every number in a table is read from report.json
(``data-key`` names the field), as in the parallel indexer's report (:mod:`.report_indexer`)."""
from __future__ import annotations

import html
import math
from typing import Any, Callable, Mapping

import numpy as np

from cam_workbench.generators.bodies.indexing.spatial import SpatialDesign
from cam_workbench.generators.bodies.indexing.spatial_kind import SpatialIndexerDesign

from . import plots_spatial_indexer
from .chart import Chart, Curve, Note, Panel, Rule
from .report_cells import has, lookup, num_cell, quantity_table
from .report_indexer import (drive_chart, drive_section, dynamics_section, figure_html, motion_rows, outputs_sections,
                             page_html, render_figures)
from .report_pages import REPORT_PAGES
from .report_sections import checks_section

#: (name of the PNG, title) of every figure the page can have, in the page's order
FIGURES = (("plot_indexer.png", "The cam's rib, the turret and its rollers in the fixed frame (mid-index)"),
           ("plot_pressure_angle.png", "Pressure angle of the driving contact over the index against the limit"),
           ("plot_motion.png", "The turret's motion and the driving pressure angle over the input turn"),
           ("plot_torque.png", "The drive over the index: torques, input power, normal force, Hertz stress"))
_TITLES = dict(FIGURES)
_GEO = "indexer.geometry"
_MG = "indexer.motion_from_geometry"
_Rows = list[tuple[str, str, str, str | None]]


def _figure_names(design: SpatialIndexerDesign) -> list[str]:
    """The PNG names of ``design``'s figures: the drive's only when the spec gives a load."""
    return [name for name, _ in FIGURES if name != "plot_torque.png" or design.drive is not None]


def _kind(design: SpatialDesign) -> str:
    return type(design.indexer).__name__.replace("Indexer", "").lower()


# ---- the figures ----------------------------------------------------------------------------------
def contacts_angle(design: SpatialDesign) -> np.ndarray:
    """At each input angle ``design.theta`` the largest pressure angle [rad] over every engaged
    contact (each engaged roller side's largest along its in-band length; NaN where none is
    engaged) — what the ``pressure_angle_contacts`` check reports at its largest, not checked."""
    i = np.arange(design.theta.size)
    out = np.full(design.theta.size, -np.inf)
    for si, sheet in enumerate(design.sheets):
        line = np.where(sheet.in_band, sheet.pressure_angle, -np.inf).max(axis=1)
        for ji, j in enumerate(design.rollers.tolist()):
            out = np.where(design.engaged[ji, si], np.maximum(out, line[design.row(j, i)]), out)
    return np.where(np.isfinite(out), out, np.nan)


def pressure_angle_chart(design: SpatialIndexerDesign, report: Mapping[str, Any]) -> Chart:
    """The driving contact's pressure angle [deg] over the index (``geometry.driving_angle``; x: θ −
    θ_s [deg]) with the limit ``indexer.max_pressure_angle`` and the check's value at its angle (both
    read from report.json's ``checks.results.pressure_angle``), and the largest over every engaged
    contact (:func:`contacts_angle`, reported, not checked) dashed."""
    g = design.geometry
    ix = g.indexer
    x = np.degrees(g.theta - float(ix.index_start))
    beta = math.degrees(float(ix.index_angle))
    over = (x >= -1e-9) & (x <= beta + 1e-9)
    drive = np.where(over, np.degrees(g.driving_angle), np.nan)
    every = np.where(over, np.degrees(contacts_angle(g)), np.nan)
    p = Panel(xlabel="input angle θ − θ_s [deg]", ylabel="pressure angle [deg]", xlim=(0.0, beta), height=200.0,
              legend="below", legend_columns=2,
              title=f"{_kind(g)} indexer: N = {int(ix.stations)}, β = {beta:g}°, {ix.law}")
    p.add(Curve(x, every, color="#7f8c8d", width=1.0, dash="--",
                label="largest over every engaged contact (reported, not checked)", gid="contacts-angle"),
          Curve(x, drive, color="#6a1b9a", width=1.5, label="driving contact (the check)", gid="driving-angle"))
    check = report["checks"]["results"].get("pressure_angle") or {}
    limit = check.get("limit")
    if isinstance(limit, (int, float)):
        p.add(Rule("y", float(limit), color="#b03a2e", width=1.0, dash="--", label=f"limit {limit:g}°",
                   gid="pressure-angle-limit"))
    value, at = check.get("value"), check.get("at_deg")
    if isinstance(value, (int, float)) and isinstance(at, (int, float)):
        start = float(lookup(report, f"{_GEO}.index_start_deg"))
        xa = (float(at) - start) % 360.0
        right = xa > 0.5 * beta
        p.add(Curve(np.array([xa]), np.array([float(value)]), line=False, marker="o", size=6.0,
                    color="#b03a2e", label="the check: the driving contact's largest", gid="pressure-angle-check"),
              Note(xa, float(value), f"{float(value):.2f}° at θ − θ_s = {xa:.1f}°", dx=-6.0 if right else 6.0,
                   dy=-6.0, valign="top", anchor="end" if right else "start", boxed=True))
    return Chart.stack([p], width=640.0)


def render_spatial_indexer_report(design: SpatialIndexerDesign, report: Mapping[str, Any],
                                  progress: Callable[[str], None] | None = None,
                                  pngs: bool = False) -> tuple[str, dict[str, bytes]]:
    """The HTML text and, with ``pngs``, the PNG files ({name: bytes}) of a spatial indexer's report."""
    g = design.geometry
    mid = float(g.indexer.index_start) + 0.5 * float(g.indexer.index_angle)
    makers = {"plot_indexer.png": lambda: plots_spatial_indexer.spatial_picture(g, mid),
              "plot_pressure_angle.png": lambda: pressure_angle_chart(design, report),
              "plot_motion.png": lambda: plots_spatial_indexer.spatial_motion_chart(g),
              "plot_torque.png": lambda: drive_chart(design, report)}
    svgs, files = render_figures(_figure_names(design), makers, _TITLES, progress, pngs)
    return _page(report, svgs), files


@REPORT_PAGES.register(SpatialIndexerDesign)
class SpatialIndexerPage:
    """A barrel or globoidal indexer's report page (:func:`render_spatial_indexer_report`): three
    figures, four with a load (the drive's)."""

    def __init__(self, design: SpatialIndexerDesign, summary: Mapping[str, Any], dynamics: Any = None) -> None:
        self.design = design
        self.figures = _figure_names(design)

    def render(self, report: dict[str, Any], progress: Callable[[str], None] | None, pngs: bool = False
               ) -> tuple[str, dict[str, bytes]]:
        return render_spatial_indexer_report(self.design, report, progress=progress, pngs=pngs)


# ---- the page -------------------------------------------------------------------------------------
def _figure(name: str, svgs: Mapping[str, str]) -> str:
    return figure_html(name, svgs, _TITLES)


def _geometry_rows(barrel: bool) -> _Rows:
    geo = _GEO
    if barrel:
        rib = [("pitch radius R_p of the rollers' axes about the turret axis", f"{geo}.pitch_radius", "mm", None),
               ("root cylinder radius (about the cam axis)", f"{geo}.root_radius", "mm", None),
               ("outer cylinder radius, the rib's top (about the cam axis)", f"{geo}.outer_radius", "mm", None)]
    else:
        rib = [("tip globoid radius, the rib's top (about the turret axis)", f"{geo}.tip_radius", "mm", None),
               ("root globoid radius (about the turret axis)", f"{geo}.root_radius", "mm", None)]
    return [
        ("stations N", f"{geo}.stations", "", None),
        ("law of the index", f"{geo}.law", "", None),
        ("turret advance per turn (360°/N)", "motion.advance_deg", "deg", None),
        ("index angle β", f"{geo}.index_angle_deg", "deg", None),
        ("index start θ_s", f"{geo}.index_start_deg", "deg", None),
        ("centre distance C (cam axis to turret axis)", f"{geo}.centre_distance", "mm", None),
        ("roller radius r_r", f"{geo}.roller_radius", "mm", None),
        ("rollers' half cone angle γ (0: cylindrical; else r_r is the radius at the working length's middle)",
         f"{geo}.roller_cone_angle_deg", "deg", None),
        ("conical roller's radius at t₀", f"{geo}.roller_radius_start", "mm", None),
        ("… at t₁", f"{geo}.roller_radius_end", "mm", None),
        ("cone's apex on the roller's axis at t", f"{geo}.roller_cone_apex_t", "mm", None),
        ("rollers' working length along their axes: from t₀", f"{geo}.roller_start", "mm", None),
        ("… to t₁", f"{geo}.roller_end", "mm", None),
        *rib,
        ("cam's length along its axis (cam.thickness)", f"{geo}.cam_width", "mm", None),
        ("bore diameter", "body.bore_diameter", "mm", None),
        ("input angles sampled over the turn", f"{geo}.samples", "", None),
        ("points along each roller", f"{geo}.lengths", "", None),
        ("fewest roller sides engaged at an input angle", f"{geo}.engaged_per_angle.min", "", None),
        ("most roller sides engaged at an input angle", f"{geo}.engaged_per_angle.max", "", None),
        ("turret held both ways at every input angle (locked)", f"{geo}.locked", "", None),
        ("largest pressure angle of the driving contact over the index", f"{geo}.max_driving_pressure_angle.value_deg",
         "deg", f"{geo}.max_driving_pressure_angle.at_deg"),
        ("… as the check compares it", "checks.results.pressure_angle.value", "deg",
         "checks.results.pressure_angle.at_deg"),
        ("largest pressure angle over every engaged contact (reported, not checked)",
         f"{geo}.max_pressure_angle.value_deg", "deg", f"{geo}.max_pressure_angle.at_deg"),
        ("… while the turret moves", f"{geo}.max_index_pressure_angle.value_deg", "deg",
         f"{geo}.max_index_pressure_angle.at_deg"),
        ("smallest regularity margin μ of the flanks (> 0: no undercut)", f"{geo}.min_regularity_margin.value_1", "",
         f"{geo}.min_regularity_margin.at_deg"),
        ("smallest thickness of the rib between its flanks", f"{geo}.min_rib_thickness.value_mm", "mm",
         f"{geo}.min_rib_thickness.at_deg"),
    ]


def _windows_table(report: Mapping[str, Any]) -> str:
    """Each engagement window (report.json ``indexer.geometry.windows``): roller, side, from, to."""
    key = f"{_GEO}.windows"
    windows = lookup(report, key) if has(report, key) else []
    if not isinstance(windows, list) or not windows:
        return ""
    rows = "".join(f"<tr>{num_cell(report, f'{key}.{i}.roller_index')}{num_cell(report, f'{key}.{i}.side')}"
                   f"{num_cell(report, f'{key}.{i}.from_deg')}{num_cell(report, f'{key}.{i}.to_deg')}</tr>"
                   for i in range(len(windows)))
    return ('<h3>Engagement windows (input angles where a roller side touches the rib; side +1 holds the '
            'turret back, side −1 drives it on)</h3><table class="q" id="windows"><tr><th>roller j</th>'
            "<th>side</th><th>from input angle [deg]</th><th>to input angle [deg]</th></tr>" + rows + "</table>")


def _accuracy_rows(report: Mapping[str, Any]) -> _Rows:
    rows: _Rows = [
        ("flanks: fitted within (largest distance of the fitted bicubic B-spline flank surfaces from the exact "
         "envelope of the rollers, measured between their nodes; measured, not exact)",
         "body.flank_fit_error.value", "mm", None),
        ("tolerance the flank surfaces are fitted to", "body.surfaces.tolerance_mm", "mm", None),
    ]
    flanks = lookup(report, "body.surfaces.flanks") if has(report, "body.surfaces.flanks") else []
    for i, f in enumerate(flanks if isinstance(flanks, list) else []):
        side = f.get("side") if isinstance(f, Mapping) else None
        what = {1: "side +1, holds the turret", -1: "side −1, drives the turret"}.get(side, f"side {side}")
        k = f"body.surfaces.flanks.{i}"
        rows += [(f"flank {i} ({what}): largest distance from the exact envelope (measured)", f"{k}.max_error_mm",
                  "mm", None),
                 (f"flank {i}: … along the envelope's normal (measured)", f"{k}.max_normal_error_mm", "mm", None),
                 (f"flank {i}: nodes along τ", f"{k}.nodes_tau", "", None),
                 (f"flank {i}: nodes along t", f"{k}.nodes_t", "", None),
                 (f"flank {i}: points measured", f"{k}.check_points", "", None)]
    return rows


def _page(report: Mapping[str, Any], svgs: Mapping[str, str]) -> str:
    fol = report.get("follower") or {}
    body = report.get("body") or {}
    kind = str((report.get("indexer") or {}).get("type", ""))
    barrel = kind == "barrel"
    title = f"{kind.capitalize()} indexer — {fol.get('label', '')}"
    recovered_rows = [
        ("turret angle recovered from the flank surfaces vs the law: largest error", f"{_MG}.max_error_rad", "rad",
         None),
        ("… input angles compared", f"{_MG}.samples", "", None),
    ]
    mg = (report.get("indexer") or {}).get("motion_from_geometry") or {}
    fit = body.get("flank_fit_error") or {}
    flank_note = (f'<p class="note" id="flank-claim" data-exact="false">The flanks are fitted, not exact '
                  f"(measured: {html.escape(str(fit.get('what', '')))}); "
                  f"{html.escape(str(body.get('approximation', '')))}.</p>")
    recovered_note = (f'<p class="note" id="recovered">The recovered turret angle: '
                      f"{html.escape(str(mg.get('what', '')))}.</p>")
    return page_html(title, '<h2 id="checks">Design checks</h2>' + checks_section(report)
                     + _figure("plot_pressure_angle.png", svgs)
                     + '<h2 id="indexer">The indexer</h2>' + _figure("plot_indexer.png", svgs)
                     + quantity_table(report, _geometry_rows(barrel)) + _windows_table(report)
                     + '<h2 id="accuracy">How closely the built flanks hold the envelope</h2>'
                     + quantity_table(report, _accuracy_rows(report)) + flank_note
                     + '<h2 id="motion">The turret\'s motion</h2>' + quantity_table(report, motion_rows(report))
                     + "<h3>The turret angle recovered from the flanks</h3>" + quantity_table(report, recovered_rows)
                     + recovered_note + _figure("plot_motion.png", svgs)
                     + '<h2 id="drive">The drive</h2>' + drive_section(report, _figure("plot_torque.png", svgs))
                     + dynamics_section(report) + outputs_sections(report))


__all__ = ["FIGURES", "SpatialIndexerPage", "contacts_angle", "pressure_angle_chart", "render_spatial_indexer_report"]

"""report.html of a parallel (plate-cam) indexer: the checks' verdict and table (the shared
:func:`~cam_workbench.exporters.report_sections.checks_section`, failing rows red), the indexer's
numbers (stations, index, C, R_p, r_r, the plates, the clearance, each cam's radii), how closely the
built profiles hold the law (the flanks' fit error, the turret angle recovered from the profiles),
the drive (times, output motion, torques, power, normal force, Hertz stress, the roller's life,
the law's characteristic values) and four figures — the cams, turret and rollers in the fixed
frame (:func:`.plots_indexer.indexer_picture`), the turret's motion (:func:`.plots_indexer.indexer_motion_chart`),
the driving and holding pressure angles over the index against the limit, and the drive's torques,
power, normal force and stress over the index.  Every number in a table is read from report.json
(``data-key`` names the field), as in the plane cams' report
(:mod:`cam_workbench.exporters.report_html`)."""
from __future__ import annotations

import html
import math
from typing import Any, Callable, Mapping

import numpy as np

from cam_workbench.generators.bodies.indexing.parallel_kind import ParallelIndexerDesign

from . import chart_png, chart_svg, plots_indexer
from .chart import Chart, Curve, Note, Panel, Rule
from .report_cells import format_number, has, lookup, quantity_table, scalars_table
from .report_html import CSS
from .report_pages import REPORT_PAGES
from .report_sections import checks_section

#: (name of the PNG, title) of every figure the page can have, in the page's order
FIGURES = (("plot_indexer.png", "The cams, the turret and its rollers in the fixed frame (mid-index)"),
           ("plot_pressure_angle.png", "Pressure angles over the index against the limit"),
           ("plot_motion.png", "The turret's motion and the driving pressure angle over the input turn"),
           ("plot_torque.png", "The drive over the index: torques, input power, normal force, Hertz stress"))
_TITLES = dict(FIGURES)
_DRIVE = "indexer.drive"
_GEO = "indexer.geometry"


def _figure_names(design: ParallelIndexerDesign) -> list[str]:
    """The PNG names of ``design``'s figures: the drive's only when the spec gives a load."""
    return [name for name, _ in FIGURES if name != "plot_torque.png" or design.drive is not None]


# ---- the figures ----------------------------------------------------------------------------------
def pressure_angle_chart(design: ParallelIndexerDesign, report: Mapping[str, Any]) -> Chart:
    """The driving and the holding-back contact's pressure angles [deg] over the index (x: θ − θ_s
    [deg]), the limit ``indexer.max_pressure_angle`` and the check's value at its angle (both read
    from report.json's ``checks.results.pressure_angle``)."""
    g = design.geometry
    ix = g.indexer
    x = np.degrees(g.theta - float(ix.index_start))
    beta = math.degrees(float(ix.index_angle))
    over = (x >= -1e-9) & (x <= beta + 1e-9)
    drive = np.where(over, np.degrees(g.driving_angle), np.nan)
    hold = np.where(over, np.degrees(g.holding_angle), np.nan)
    p = Panel(xlabel="input angle θ − θ_s [deg]", ylabel="pressure angle [deg]", xlim=(0.0, beta), height=200.0,
              legend="below", legend_columns=3,
              title=f"parallel indexer: N = {int(ix.stations)}, β = {beta:g}°, {ix.law}")
    p.add(Curve(x, drive, color="#6a1b9a", width=1.5, label="driving contact (pushes the turret on)",
                gid="driving-angle"),
          Curve(x, hold, color="#2e7d32", width=1.2, dash="--", label="holding contact (holds it back)",
                gid="holding-angle"))
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
                    color="#b03a2e", label="the check: carrying contact's largest", gid="pressure-angle-check"),
              Note(xa, float(value), f"{float(value):.2f}° at θ − θ_s = {xa:.1f}°", dx=-6.0 if right else 6.0,
                   dy=-6.0, valign="top", anchor="end" if right else "start", boxed=True))
    return Chart.stack([p], width=640.0)


def drive_chart(design: ParallelIndexerDesign, report: Mapping[str, Any]) -> Chart:
    """The drive over the index (x: the input angle from the index start θ − θ_s [deg]): the output
    and input torques [N·m], the input power [W], the carrying contact's normal force [N] and Hertz
    stress [MPa] (with ``material.allowable_stress``); the peaks marked as report.json holds them."""
    d = design.drive
    dr = lookup(report, _DRIVE)
    x = np.degrees(d.theta)
    beta = math.degrees(float(d.load.index_angle))

    def panel(ylabel: str, title: str = "", last: bool = False, ylim: tuple[float, float] | None = None) -> Panel:
        return Panel(ylabel=ylabel, xlim=(0.0, beta), ylim=ylim, height=125.0, title=title, xticklabels=last,
                     xlabel="input angle θ − θ_s [deg]" if last else "", legend="below", legend_columns=3)

    def peak(key: str, at_key: str, unit: str, color: str, gid: str, scale: float = 1.0) -> list[Curve]:
        v, at = dr.get(key), dr.get(at_key)
        if not isinstance(v, (int, float)) or not isinstance(at, (int, float)):
            return []
        return [Curve(np.array([float(at)]), np.array([float(v) * scale]), line=False, marker="o", size=5.0,
                      color=color, label=f"peak {format_number(float(v) * scale)} {unit} at {float(at):.1f}°",
                      gid=gid)]

    torque = panel("torque [N·m]", f"drive at {d.load.input_speed:g} rpm, J = {d.load.inertia:g} kg·m², "
                                   f"T_f = {d.load.friction_torque:g} N·m ({d.load.law})")
    torque.add(Rule("y", 0.0, color="#7f8c8d", width=0.6, dash="-"),
               Curve(x, d.torque_out, color="#1f3b5c", width=1.5, label="output T_out", gid="torque-out"),
               Curve(x, d.torque_in, color="#a05a00", width=1.3, dash="--", label="input T_in", gid="torque-in"),
               *peak("output_torque_peak_Nm", "output_torque_peak_at_deg", "N·m", "#1f3b5c", "torque-out-peak"))
    power = panel("input power [W]")
    power.add(Rule("y", 0.0, color="#7f8c8d", width=0.6, dash="-"),
              Curve(x, d.power_in, color="#c0392b", width=1.4, label="P_in = T_in·ω_in", gid="power-in"))
    force = panel("normal force [N]")
    force.add(Curve(x, d.normal_force, color="#2e7d32", width=1.4, label="carrying contact's F_n",
                    gid="normal-force"),
              *peak("normal_force_peak_N", "normal_force_peak_at_deg", "N", "#2e7d32", "normal-force-peak"))
    mpa = d.contact_stress / 1e6
    allow = (report["checks"]["results"].get("contact_stress") or {}).get("limit")
    top = [float(np.max(mpa[np.isfinite(mpa)], initial=0.0))]
    if isinstance(allow, (int, float)):
        top.append(float(allow))
    stress = panel("Hertz stress [MPa]", last=True, ylim=(0.0, 1.12 * max(max(top), 1e-9)))
    stress.add(Curve(x, mpa, color="#6a1b9a", width=1.4, label="carrying contact's stress", gid="contact-stress"),
               *peak("contact_stress_peak_Pa", "contact_stress_peak_at_deg", "MPa", "#6a1b9a", "contact-stress-peak",
                     1e-6))
    if isinstance(allow, (int, float)):
        stress.add(Rule("y", float(allow), color="#b03a2e", dash="--", label=f"allowable {allow:g} MPa",
                        gid="stress-limit"))
    return Chart.stack([torque, power, force, stress], width=640.0)


def render_indexer_report(design: ParallelIndexerDesign, report: Mapping[str, Any],
                          progress: Callable[[str], None] | None = None,
                          pngs: bool = False) -> tuple[str, dict[str, bytes]]:
    """The HTML text and, with ``pngs``, the PNG files ({name: bytes}) of a parallel indexer's report."""
    g = design.geometry
    mid = float(g.indexer.index_start) + 0.5 * float(g.indexer.index_angle)
    makers = {"plot_indexer.png": lambda: plots_indexer.indexer_picture(g, mid),
              "plot_pressure_angle.png": lambda: pressure_angle_chart(design, report),
              "plot_motion.png": lambda: plots_indexer.indexer_motion_chart(g),
              "plot_torque.png": lambda: drive_chart(design, report)}
    svgs, files = render_figures(_figure_names(design), makers, _TITLES, progress, pngs)
    return _page(report, svgs), files


@REPORT_PAGES.register(ParallelIndexerDesign)
class ParallelIndexerPage:
    """A parallel indexer's report page (:func:`render_indexer_report`): three figures, four with a
    load (the drive's)."""

    def __init__(self, design: ParallelIndexerDesign, summary: Mapping[str, Any], dynamics: Any = None) -> None:
        self.design = design
        self.figures = _figure_names(design)

    def render(self, report: dict[str, Any], progress: Callable[[str], None] | None, pngs: bool = False
               ) -> tuple[str, dict[str, bytes]]:
        return render_indexer_report(self.design, report, progress=progress, pngs=pngs)


# ---- the page -------------------------------------------------------------------------------------
def render_figures(names: list[str], makers: Mapping[str, Callable[[], Chart]], titles: Mapping[str, str],
                   progress: Callable[[str], None] | None, pngs: bool) -> tuple[dict[str, str], dict[str, bytes]]:
    """(SVG text, with ``pngs`` PNG bytes) of each figure of ``names`` (PNG names, the page's order),
    drawn by ``makers[name]()``; ``progress`` is told each one's title from ``titles`` before it is
    drawn."""
    svgs, files = {}, {}
    for name in names:
        if progress is not None:
            progress(titles[name])
        svgs[name] = chart_svg.svg(makers[name](), name[5:-4])
        if pngs:
            files[name] = chart_png.png_bytes(svgs[name])
    return svgs, files


def page_html(title: str, sections: str) -> str:
    """The report page: an HTML document titled ``title`` (its ``<title>`` and ``<h1>``; the plane
    cams' report's :data:`~.report_html.CSS`) holding ``sections`` (HTML) after the sub-heading."""
    return ("<!doctype html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + html.escape(title)
            + f"</title><style>{CSS}</style></head><body><main>"
            f"<h1>{html.escape(title)}</h1><p class=\"sub\">cam_workbench report (report.json's numbers)</p>"
            + sections + "</main></body></html>\n")


def motion_rows(report: Mapping[str, Any]) -> list[tuple[str, str, str, str | None]]:
    """The turret's motion table: the advance per index and the largest |velocity|, |acceleration|
    and |jerk|, in report.json's ``motion.lift_unit`` (deg when not given) and its /s, /s², /s³."""
    lu = (report.get("motion") or {}).get("lift_unit", "deg")
    return [
        ("turret advance per index", "motion.advance_deg", lu, None),
        ("max |turret velocity|", "motion.max_velocity", f"{lu}/s", None),
        ("max |turret acceleration|", "motion.max_acceleration", f"{lu}/s²", None),
        ("max |turret jerk|", "motion.max_jerk", f"{lu}/s³", None),
    ]


def figure_html(name: str, svgs: Mapping[str, str], titles: Mapping[str, str]) -> str:
    """The ``<figure>`` of the PNG name ``name`` (id ``fig-<name without plot_ and .png>``) holding
    its SVG from ``svgs`` and its caption from ``titles``; "" when ``svgs`` has none."""
    if name not in svgs:
        return ""
    return (f'<figure id="fig-{name[5:-4]}" data-png="{name}">{svgs[name]}<figcaption>'
            f"{html.escape(titles[name])} ({name})</figcaption></figure>")


def _figure(name: str, svgs: Mapping[str, str]) -> str:
    return figure_html(name, svgs, _TITLES)


def dynamics_section(report: Mapping[str, Any]) -> str:
    """report.json's ``dynamics.turret`` (the output train at speed, docs/indexing.md "Dynamics") as a
    table; "" when the report has no dynamics (``dynamics.enabled`` off)."""
    if not has(report, "dynamics.turret"):
        return ""
    t = "dynamics.turret"
    rows = [
        ("analysis speed", "dynamics.speed_rpm", "rpm", None),
        ("output inertia J", f"{t}.output_inertia", "kg·mm²", None),
        ("turret shaft's torsional stiffness k_t", f"{t}.torsional_stiffness", "N·mm/rad", None),
        ("damping ratio ζ", f"{t}.damping_ratio", "", None),
        ("natural frequency f_n", f"{t}.natural_frequency_hz", "Hz", None),
        ("index time t_i", f"{t}.index_time_s", "s", None),
        ("f_n·t_i", f"{t}.fn_ti", "", None),
        ("largest angle error |φ − ψ|", f"{t}.angle_error.max", "deg", f"{t}.angle_error.at_deg"),
        ("peak torsional deflection |ψ − φ|", f"{t}.deflection.max_arcmin", "arcmin", f"{t}.deflection.at_deg"),
        ("peak shaft torque (dynamic)", f"{t}.shaft_torque.max", "N·mm", f"{t}.shaft_torque.at_deg"),
        ("peak shaft torque (rigid J·ψ̈)", f"{t}.shaft_torque.rigid_max", "N·mm", f"{t}.shaft_torque.rigid_max_at_deg"),
        ("residual vibration entering the dwell", f"{t}.residual_vibration.amplitude_arcmin", "arcmin", None),
    ]
    dwells = lookup(report, f"{t}.residual_vibration.dwells")
    rows += [(f"dwell {i}: residual vibration at its end", f"{t}.residual_vibration.dwells.{i}.amplitude_at_end_arcmin",
              "arcmin", None) for i in range(len(dwells) if isinstance(dwells, list) else 0)]
    return ('<h2 id="dynamics">The output train at speed</h2><p class="note">The output\'s inertia on the turret '
            "shaft's torsional stiffness, driven by the cam through stiff rollers (docs/indexing.md).</p>"
            + quantity_table(report, rows) + section_notes(report, t))


def section_notes(report: Mapping[str, Any], section: str) -> str:
    """The ``*_note`` strings of a report.json section, each as a note naming its key."""
    node = lookup(report, section) if has(report, section) else None
    if not isinstance(node, Mapping):
        return ""
    return "".join(f'<p class="note" data-key="{section}.{k}">{html.escape(str(v))}</p>'
                   for k, v in node.items() if k.endswith("_note") and isinstance(v, str))


def _indexer_rows(report: Mapping[str, Any]) -> list[tuple[str, str, str, str | None]]:
    geo = _GEO
    rows = [
        ("stations N", f"{geo}.stations", "", None),
        ("plates (cams)", "body.cams", "", None),
        ("law of the index", f"{geo}.law", "", None),
        ("turret advance per turn (360°/N)", "motion.advance_deg", "deg", None),
        ("index angle β", f"{geo}.index_angle_deg", "deg", None),
        ("index start θ_s", f"{geo}.index_start_deg", "deg", None),
        ("centre distance C", f"{geo}.centre_distance_mm", "mm", None),
        ("turret pitch radius R_p", f"{geo}.pitch_radius_mm", "mm", None),
        ("roller radius r_r", f"{geo}.roller_radius_mm", "mm", None),
        ("plate thickness", "body.plate_thickness", "mm", None),
        ("gap between the plates", "body.gap", "mm", None),
        ("spacer radius", "body.spacer_radius", "mm", None),
        ("bore diameter", "body.bore_diameter", "mm", None),
        ("largest cam radius", "body.outer_radius", "mm", None),
        ("volume (plates and spacers)", "volume", "mm³", None),
        ("smallest gap of an idle roller to a cam (clearance)", f"{geo}.clearance_mm", "mm", None),
        ("gap at the hand-over between the rollers", f"{geo}.handover_gap_mm", "mm", None),
        ("turret held both ways at every input angle (locked)", f"{geo}.locked", "", None),
        ("largest driving pressure angle over the index", f"{geo}.max_driving_pressure_angle_deg", "deg",
         f"{geo}.max_driving_pressure_angle_at_deg"),
        ("… of the contact carrying the torque (the check)", "checks.results.pressure_angle.value", "deg",
         "checks.results.pressure_angle.at_deg"),
        ("worst holding pressure angle, forward", f"{geo}.worst_forward_pressure_angle_deg", "deg",
         f"{geo}.worst_forward_at_deg"),
        ("worst holding pressure angle, backward", f"{geo}.worst_backward_pressure_angle_deg", "deg",
         f"{geo}.worst_backward_at_deg"),
        ("smallest driving moment arm about the turret axis", f"{geo}.min_driving_arm_mm", "mm", None),
    ]
    cams = lookup(report, f"{geo}.per_cam") if has(report, f"{geo}.per_cam") else []
    for i, _ in enumerate(cams if isinstance(cams, list) else []):
        c = f"{geo}.per_cam.{i}"
        rows += [(f"cam {i}: dwell radius", f"{c}.dwell_radius_mm", "mm", None),
                 (f"cam {i}: tip radius", f"{c}.tip_radius_mm", "mm", None),
                 (f"cam {i}: cross-over radius", f"{c}.crossover_radius_mm", "mm", None),
                 (f"cam {i}: largest pressure angle on its profile", f"{c}.max_pressure_angle_deg", "deg", None),
                 (f"cam {i}: smallest convex profile radius of curvature", f"{c}.min_convex_profile_radius_mm", "mm",
                  None)]
    return rows


def _accuracy_rows() -> list[tuple[str, str, str, str | None]]:
    mg = "indexer.motion_from_geometry"
    return [
        ("flanks: fitted within (largest distance of the fitted B-splines from the exact offset of the roller "
         "loci; measured, not exact)", "body.flank_fit_error.value", "mm", None),
        ("turret angle recovered from the built profiles vs the law: largest error", f"{mg}.max_error_rad", "rad",
         None),
        ("… largest slack of the recovered contact", f"{mg}.max_slack_rad", "rad", None),
        ("… input angles", f"{mg}.samples", "", None),
        ("… of them where the profiles alone do not fix the turret angle (not compared)",
         f"{mg}.undetermined_samples", "", None),
    ]


def drive_rows() -> list[tuple[str, str, str, str | None]]:
    d = _DRIVE
    return [
        ("input speed", f"{d}.input_speed_rpm", "rpm", None),
        ("index time", f"{d}.index_time_s", "s", None),
        ("dwell time", f"{d}.dwell_time_s", "s", None),
        ("contact efficiency η", f"{d}.efficiency", "", None),
        ("peak output velocity", f"{d}.output_velocity_peak_rad_s", "rad/s", None),
        ("peak output acceleration", f"{d}.output_acceleration_peak_rad_s2", "rad/s²", None),
        ("peak output torque T_out", f"{d}.output_torque_peak_Nm", "N·m", f"{d}.output_torque_peak_at_deg"),
        ("peak input torque T_in", f"{d}.input_torque_peak_Nm", "N·m", f"{d}.input_torque_peak_at_deg"),
        ("peak input power", f"{d}.input_power_peak_W", "W", None),
        ("mean input power over the index", f"{d}.input_power_mean_index_W", "W", None),
        ("peak normal force on a roller", f"{d}.normal_force_peak_N", "N", f"{d}.normal_force_peak_at_deg"),
        ("peak Hertz contact stress", f"{d}.contact_stress_peak_Pa", "Pa", f"{d}.contact_stress_peak_at_deg"),
        ("… as the check compares it (at the cam angle)", "checks.results.contact_stress.value", "MPa",
         "checks.results.contact_stress.at_deg"),
        ("roller's equivalent load P", f"{d}.roller_equivalent_load_N", "N", None),
        ("roller revolutions per index", f"{d}.roller_revolutions_per_index", "", None),
        ("roller life exponent p", f"{d}.roller_life_exponent", "", None),
        ("roller rating life L10", f"{d}.l10_million_rev", "million rev", None),
        ("roller rating life L10 (one index per input turn)", f"{d}.l10_hours", "h", None),
    ]


def law_rows() -> list[tuple[str, str, str, str | None]]:
    c = f"{_DRIVE}.characteristics"
    return [
        ("law", f"{c}.law", "", None),
        ("velocity coefficient C_v", f"{c}.C_v", "", None),
        ("… at x = θ/β", f"{c}.x_v", "", None),
        ("acceleration coefficient C_a", f"{c}.C_a", "", None),
        ("… at x = θ/β", f"{c}.x_a", "", None),
        ("jerk coefficient C_j", f"{c}.C_j", "", None),
        ("… at x = θ/β", f"{c}.x_j", "", None),
        ("torque index", f"{c}.torque_index", "", None),
        ("Q", f"{c}.Q", "", None),
        ("… at x = θ/β", f"{c}.x_Q", "", None),
    ]


#: report.json's sections of the other outputs (written by their layers when they are made), in page order
_OUTPUTS = (("solid", "The solid (OCCT)"), ("drawing", "The drawing (DXF)"), ("machining", "The machining program"))


def outputs_sections(report: Mapping[str, Any]) -> str:
    """Every scalar of the solid's, the drawing's and the machining's sections that report.json has."""
    return "".join(f'<h2 id="{key}">{html.escape(title)}</h2>' + scalars_table(report, key)
                   for key, title in _OUTPUTS if isinstance(report.get(key), Mapping) and report[key])


def drive_section(report: Mapping[str, Any], torque_figure: str) -> str:
    """The body of an indexer's drive section from report.json's ``indexer.drive`` (the drive's
    table, the roller's rolling, the drive's notes, the law's characteristic values, then
    ``torque_figure``), or the note that no load is given."""
    if not has(report, f"{_DRIVE}.index_time_s"):
        return ('<p class="note" id="no-drive">No load is given (indexer.output_inertia): the drive is not '
                "sized.</p>")
    return (quantity_table(report, drive_rows())
            + '<p class="note">The drive\'s angles (last column) are input angles from the start of the '
              "index, θ − θ_s (the check's: the cam angle). The roller's rolling: "
              f'<span data-key="{_DRIVE}.roller_rolling">'
              f"{html.escape(str(lookup(report, _DRIVE).get('roller_rolling', '')))}</span>.</p>"
            + section_notes(report, _DRIVE)
            + "<h3>The law's characteristic values</h3>" + quantity_table(report, law_rows())
            + torque_figure)


def _page(report: Mapping[str, Any], svgs: Mapping[str, str]) -> str:
    fol = report.get("follower") or {}
    body = report.get("body") or {}
    title = f"Parallel indexer — {fol.get('label', '')}"
    mg = report.get("indexer", {}).get("motion_from_geometry") or {}
    fit = body.get("flank_fit_error") or {}
    accuracy_note = (f'<p class="note" id="flank-claim" data-exact="false">The flanks are fitted, not exact '
                     f"(measured: {html.escape(str(fit.get('what', '')))}); "
                     f"{html.escape(str(body.get('approximation', '')))}. The recovered turret angle: "
                     f"{html.escape(str(mg.get('what', '')))}.</p>")
    drive = drive_section(report, _figure("plot_torque.png", svgs))
    return page_html(title, '<h2 id="checks">Design checks</h2>' + checks_section(report)
                     + _figure("plot_pressure_angle.png", svgs)
                     + '<h2 id="indexer">The indexer</h2>' + _figure("plot_indexer.png", svgs)
                     + quantity_table(report, _indexer_rows(report))
                     + '<h2 id="accuracy">How closely the built profiles hold the law</h2>'
                     + quantity_table(report, _accuracy_rows()) + accuracy_note
                     + '<h2 id="motion">The turret\'s motion</h2>' + quantity_table(report, motion_rows(report))
                     + _figure("plot_motion.png", svgs)
                     + '<h2 id="drive">The drive</h2>' + drive + dynamics_section(report) + outputs_sections(report))

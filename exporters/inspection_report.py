"""The inspection of a made cam as files: inspection.json (every number), deviations.csv (every
point), motion.csv (the designed and measured s, v, a), the figures — the deviation as a colour
map on the profile, the deviation against the cam angle, the measured against the designed
motion — and inspection.html, whose tables are inspection.json's cells (:mod:`.report_cells`).

:func:`rows` are the quantities the HTML tables and the command's printout show, each read from
inspection.json by its dotted path; :func:`harmonic_columns` the columns of the table of the
deviation's largest harmonics (``harmonics.largest``)."""
from __future__ import annotations

import html
from typing import Any, Mapping

import numpy as np

from cam_workbench.generators import __version__
from cam_workbench.generators.inspection import InspectionResult
from cam_workbench.generators.inspection.measured_motion import contact_angles

from .chart import Chart, Curve, Panel, Rule, angle_panel
from .chart_svg import svg
from .plots import COLORS, small_unit
from .report_cells import has, lookup, num_cell, quantity_table
from .report_html import CSS
from .report_json import report_json_text

JSON_NAME = "inspection.json"
HTML_NAME = "inspection.html"
POINTS_CSV = "deviations.csv"
MOTION_CSV = "motion.csv"
#: figure name → file stem (``<stem>.svg``, and ``<stem>.png`` when CairoSVG is there)
FIGURES = {"map": "deviation_map", "angle": "deviation_angle", "motion": "measured_motion"}
#: at most this many points are drawn in the deviation-against-angle figure (every k-th beyond)
DRAWN_POINTS = 20000
#: the colour map's classes, most negative (material missing) to most positive (material left on)
PALETTE = ("#2166ac", "#4393c3", "#92c5de", "#c6dbef", "#9e9e9e", "#fcbba1", "#f4a582", "#d6604d", "#b2182b")


def rows(report: Mapping[str, Any]) -> list[tuple[str, str, str, str | None]]:
    """(label, inspection.json path, unit, path of its cam angle or None) of every quantity shown,
    in the order shown; rows whose path is absent are left out by the readers."""
    u = report["units"]
    mu = report["motion"]["units"]
    out = [
        ("points", "points.count", "", None),
        ("datum", "registration.datum", "", None),
        ("rotation α (x = Rot(α)·m + t)", "registration.rotation_deg", "deg", None),
        ("shift t_x", "registration.shift_x", u, None),
        ("shift t_y", "registration.shift_y", u, None),
        ("standard uncertainty of α", "registration.rotation_std_deg", "deg", None),
        ("standard uncertainty of t_x", "registration.shift_std_x", u, None),
        ("standard uncertainty of t_y", "registration.shift_std_y", u, None),
        ("robust scale σ (MAD)", "registration.scale", u, None),
        ("outliers (|d| > 4.685σ)", "registration.outliers", "", None),
        ("largest deviation (all points)", "deviation.all_points.max", u, "deviation.all_points.max_at_deg"),
        ("smallest deviation (all points)", "deviation.all_points.min", u, "deviation.all_points.min_at_deg"),
        ("largest deviation (inliers)", "deviation.inliers.max", u, "deviation.inliers.max_at_deg"),
        ("smallest deviation (inliers)", "deviation.inliers.min", u, "deviation.inliers.min_at_deg"),
        ("RMS deviation (inliers)", "deviation.inliers.rms", u, None),
        ("profile tolerance t", "tolerance.tolerance", u, None),
        ("profile verdict (zone ±t/2)", "tolerance.verdict", "", None),
        ("points outside the zone", "tolerance.outside", "", None),
        ("inliers outside the zone", "tolerance.outside_inliers", "", None),
        ("zone used, max |d|/(t/2)", "tolerance.used", "", None),
        ("cam speed", "motion.speed_rpm", "rpm", None),
        ("smoothing: shortest wave allowed", "motion.smoothing.shortest_allowed_deg", "deg", None),
        ("smoothing: shortest wave followed (GCV)", "motion.smoothing.wavelength_deg", "deg", None),
        ("smoothing: RMS residual", "motion.smoothing.rms_residual", u, None),
        ("largest displacement error |Δs|", "motion.displacement_error.max_abs", mu["displacement"],
         "motion.displacement_error.at_deg"),
        ("largest velocity error |Δv|", "motion.velocity_error.max_abs", mu["velocity"], "motion.velocity_error.at_deg"),
        ("largest acceleration error |Δa|", "motion.acceleration_error.max_abs", mu["acceleration"],
         "motion.acceleration_error.at_deg"),
        ("|Δa| / designed peak acceleration", "motion.acceleration_error.fraction_of_designed_peak", "", None),
        ("designed peak acceleration", "motion.designed_peak.acceleration", mu["acceleration"], None),
        ("measured peak acceleration", "motion.measured_peak.acceleration", mu["acceleration"],
         "motion.measured_peak.acceleration_at_deg"),
        ("harmonics read (n = 0 … n_max)", "harmonics.max_waves", "", None),
        ("predicted |δa|, first order from the harmonics", "harmonics.predicted_acceleration_error.max_abs",
         mu["acceleration"], "harmonics.predicted_acceleration_error.at_deg"),
        ("predicted |δa| / designed peak", "harmonics.predicted_acceleration_error.percent_of_designed_peak", "%", None),
        ("acceleration limit (share of the designed peak)", "harmonics.limit.acceleration_limit", "", None),
        ("predicted |δa| within the limit", "harmonics.limit.within", "", None),
        ("tightest tolerance t at the limit (n ≤ n_max)", "harmonics.limit.tightest.tolerance", u, None),
        ("… at waves per turn", "harmonics.limit.tightest.waves", "", None),
    ]
    return [r for r in out if has(report, r[1]) and lookup(report, r[1]) is not None]


def harmonic_columns(report: Mapping[str, Any]) -> list[tuple[str, str, str]]:
    """(header, key within a harmonic of ``harmonics.largest``, unit) of the harmonics table's
    columns; the tolerance's columns only with an acceleration limit."""
    u = report["units"]
    acc = report["motion"]["units"]["acceleration"]
    cols = [("waves n", "waves", ""), ("amplitude A", "amplitude", u), ("phase φ", "phase_deg", "deg"),
            ("predicted |δa|", "peak_acceleration_error", acc), ("of designed peak", "percent_of_designed_peak", "%"),
            ("followed (A < A_max)", "followed", ""), ("tolerance t(n)", "tolerance", u),
            ("2A ≤ t(n)", "within_tolerance", "")]
    listed = report["harmonics"]["largest"]
    return [c for c in cols if any(c[1] in h for h in listed)]


def inspection_json_text(summary: Mapping[str, Any], files: Mapping[str, str]) -> str:
    """inspection.json: the summary with the files written (NaN/inf as null)."""
    return report_json_text(dict(summary), dict(files))


def deviations_csv(result: InspectionResult) -> str:
    """Every point: as measured, registered, its foot point's profile parameter and cam angle, its
    deviation (+ material outside), the robust weight and the outlier flag (spec units, degrees)."""
    reg = result.registration
    pr = reg.projection
    head = "index,x,y,x_part,y_part,u,cam_angle_deg,deviation,weight,outlier"
    cols = np.column_stack([np.arange(len(pr.u)), result.measured[:, 0], result.measured[:, 1], reg.points.real,
                            reg.points.imag, pr.u, result.deviations.cam_angle_deg, pr.distance, reg.weights,
                            reg.outliers.astype(int)])
    lines = [head] + [f"{int(r[0])}," + ",".join(repr(float(v)) for v in r[1:-1]) + f",{int(r[-1])}" for r in cols]
    return "\n".join(lines) + "\n"


def motion_csv(result: InspectionResult) -> str:
    """The designed and measured s, v, a over the turn at the cam's speed (lift units, /s, /s²)."""
    sr = result.motion.series()
    keys = ("theta_deg", "s", "s_measured", "v", "v_measured", "a", "a_measured")
    cols = np.column_stack([sr[k] for k in keys])
    return "\n".join([",".join(keys)] + [",".join(repr(float(v)) for v in r) for r in cols]) + "\n"


def deviation_map_figure(result: InspectionResult, report: Mapping[str, Any], per_span: int = 64) -> Chart:
    """The smoothed deviation δ(u) as colours on the exact profile (classes of equal width out to
    the largest |δ|, or to t/2 when a tolerance is given and larger), the outliers as crosses."""
    scale, unit = small_unit(report["units"])
    curve = result.design.profile
    u, pts = curve.sample(per_span)
    delta = result.motion.smoothing(u)[0]
    tol = report.get("tolerance")
    limit = max(float(np.max(np.abs(delta))), 0.5 * tol["tolerance"] if tol else 0.0) or 1.0
    edges = np.linspace(-limit, limit, len(PALETTE) + 1)
    cls = np.clip(np.searchsorted(edges, 0.5 * (delta[:-1] + delta[1:]), side="right") - 1, 0, len(PALETTE) - 1)
    panel = Panel(equal=True, legend="right", xlabel=f"x [{report['units']}]", ylabel=f"y [{report['units']}]",
                  height=360.0, title="deviation δ on the profile (+ material outside)")
    for k, color in enumerate(PALETTE):
        on = np.flatnonzero(cls == k)
        if not on.size:
            continue
        # each sample interval of class k as its own two-point piece, NaN between pieces
        x = np.column_stack([pts[on, 0], pts[on + 1, 0], np.full(on.size, np.nan)]).ravel()
        y = np.column_stack([pts[on, 1], pts[on + 1, 1], np.full(on.size, np.nan)]).ravel()
        panel.add(Curve(x, y, color=color, width=3.0,
                        label=f"{edges[k] * scale:+.3g} … {edges[k + 1] * scale:+.3g} {unit}", gid=f"map-class-{k}"))
    out = result.registration.points[result.registration.outliers]
    if out.size:
        panel.add(Curve(out.real, out.imag, color=COLORS["fail"], marker="+", line=False, size=5.0,
                        label=f"outliers ({out.size})", gid="map-outliers"))
    return Chart.stack([panel], width=640.0)


def deviation_angle_figure(result: InspectionResult, report: Mapping[str, Any]) -> Chart:
    """Every point's deviation against the cam angle at which the follower touches it (every k-th
    point beyond :data:`DRAWN_POINTS`), the smoothing fit, and the tolerance zone ±t/2."""
    scale, unit = small_unit(report["units"])
    dev = result.deviations
    step = max(1, -(-len(dev.value) // DRAWN_POINTS))
    order = np.argsort(dev.cam_angle_deg)[::step]
    inl = order[~dev.outliers[order]]
    outl = order[dev.outliers[order]]
    every = "every point" if step == 1 else f"every {step}th point"
    tol = report.get("tolerance")
    # the view: the inliers and the zone (outliers far off would flatten them)
    span = np.concatenate([dev.value[dev.inliers], tol["zone"] if tol else []]) * scale
    lo, hi = (float(np.min(span)), float(np.max(span))) if span.size else (-1.0, 1.0)
    pad = 0.15 * (hi - lo) or 1.0
    ylim = (lo - pad, hi + pad)
    ax = angle_panel(ylabel=f"deviation [{unit}]", xlabel="cam angle θ [deg]", legend="below", legend_columns=3,
                     height=220.0, ylim=ylim, title=f"normal deviation at the cam angle of contact ({every})")
    ax.add(Curve(dev.cam_angle_deg[inl], dev.value[inl] * scale, color=COLORS["profile"], marker=".", line=False,
                 size=2.0, label="points", gid="angle-points"))
    if outl.size:
        beyond = int(np.count_nonzero((dev.value[dev.outliers] * scale < ylim[0]) | (dev.value[dev.outliers] * scale > ylim[1])))
        ax.add(Curve(dev.cam_angle_deg[outl], dev.value[outl] * scale, color=COLORS["fail"], marker="+", line=False,
                     size=4.0, label=f"outliers ({int(np.count_nonzero(dev.outliers))}, {beyond} beyond the view)",
                     gid="angle-outliers"))
    u, _ = result.design.profile.sample(64)
    th = np.rad2deg(contact_angles(result.design, u))
    k = np.argsort(th)
    ax.add(Curve(th[k], result.motion.smoothing(u)[0][k] * scale, color=COLORS["built"], width=1.2,
                 label=f"smoothing fit ({report['motion']['smoothing']['wavelength_deg']:.3g}° waves)", gid="angle-fit"))
    if tol:
        lo, hi = tol["zone"]
        ax.add(Rule("y", lo * scale, color=COLORS["limit"], width=0.9, dash="--", gid="angle-zone-low"),
               Rule("y", hi * scale, color=COLORS["limit"], width=0.9, dash="--", gid="angle-zone-high",
                    label=f"zone ±t/2 = ±{0.5 * tol['tolerance'] * scale:.4g} {unit}"))
    return Chart.stack([ax], width=640.0)


def motion_figure(result: InspectionResult, report: Mapping[str, Any]) -> Chart:
    """The designed (dashed) and the measured part's s, v, a at the cam's speed, and the
    acceleration error with its largest value marked."""
    sr = result.motion.series()
    mu = report["motion"]["units"]
    deg = sr["theta_deg"]
    panels = []
    for key, name, unit in (("s", "s", mu["displacement"]), ("v", "v", mu["velocity"]), ("a", "a", mu["acceleration"])):
        ax = angle_panel(ylabel=f"{name} [{unit}]", legend="upper right", height=120.0, xticklabels=False)
        ax.add(Curve(deg, sr[key], color="#7f7f7f", width=0.9, dash="--", label="designed"),
               Curve(deg, sr[f"{key}_measured"], color=COLORS[name], width=1.0, label="measured part",
                     gid=f"motion-{name}"))
        panels.append(ax)
    da = report["motion"]["acceleration_error"]
    ax = angle_panel(ylabel=f"Δa [{mu['acceleration']}]", xlabel="cam angle θ [deg]", height=120.0)
    ax.add(Curve(deg, sr["da"], color=COLORS["a"], width=1.0, gid="motion-da"),
           Curve(np.array([da["at_deg"]]), np.array([sr["da"][int(np.argmax(np.abs(sr["da"])))]]), marker="o",
                 line=False, size=5.0, color=COLORS["fail"], gid="motion-da-max",
                 label=f"|Δa| max {da['max_abs']:.4g} {mu['acceleration']} at {da['at_deg']:.2f}°"))
    ax.legend = "upper right"
    panels.append(ax)
    return Chart.stack(panels, width=640.0, title=f"the follower on the measured part at {report['motion']['speed_rpm']:.4g} rpm")


def figures(result: InspectionResult, report: Mapping[str, Any]) -> dict[str, Chart]:
    """The three figures by name (:data:`FIGURES`)."""
    return {"map": deviation_map_figure(result, report), "angle": deviation_angle_figure(result, report),
            "motion": motion_figure(result, report)}


def figure_svgs(charts: Mapping[str, Chart]) -> dict[str, str]:
    """Each figure's SVG text."""
    return {name: svg(chart, f"insp-{name}") for name, chart in charts.items()}


def inspection_html(report: Mapping[str, Any], svgs: Mapping[str, str]) -> str:
    """inspection.html: one self-contained page (inline SVG, no scripts) of inspection.json's
    numbers (``report``) and the figures' SVG (``svgs``)."""
    table = rows(report)
    tol = report.get("tolerance")
    verdict = ("" if not tol else
               f'<p><span class="verdict {"fail" if tol["verdict"] == "fail" else "pass"}" data-key="tolerance.verdict">'
               f"{html.escape(tol['verdict'].replace('_', ' '))}</span> — every point within ±t/2 = "
               f"±{0.5 * tol['tolerance']:.6g} {html.escape(report['units'])} of the exact profile "
               "(ISO 1101 profile of a line)</p>")

    def section(*keys: str) -> str:
        return quantity_table(report, [r for r in table if r[1].split(".")[0] in keys])

    listed = report["harmonics"]["largest"]
    columns = harmonic_columns(report)
    head = "".join(f"<th>{html.escape(h)}{f' [{html.escape(un)}]' if un else ''}</th>" for h, _k, un in columns)
    cells = "".join("<tr>" + "".join(num_cell(report, f"harmonics.largest.{i}.{k}") if k in h else "<td></td>"
                                     for _h, k, _u in columns) + "</tr>" for i, h in enumerate(listed))
    harmonics = (f'<p>The smoothing fit of the deviation at {report["harmonics"]["samples"]} cam angles of contact, '
                 "split into harmonics; each one's acceleration error to first order (docs/tolerances.md), and "
                 "the first-order error of their sum beside the measured motion's.</p>"
                 + section("harmonics") + f'<table class="q" id="harmonics-table"><tr>{head}</tr>{cells}</table>')
    body = [
        ("registration", "Registration", section("points", "registration")),
        ("deviation", "Deviation", f'<figure id="fig-map">{svgs["map"]}<figcaption>The smoothing fit of the normal '
                                   "deviation in colour on the exact profile; crosses: the points the robust fit "
                                   "flagged as outliers.</figcaption></figure>"
                                   f'<figure id="fig-angle">{svgs["angle"]}</figure>'
                                   + verdict + section("deviation", "tolerance")),
        ("motion", "The follower on this part", f'<figure id="fig-motion">{svgs["motion"]}<figcaption>The same '
                                                "contact solve as the design, on the measured profile; Δa is what "
                                                "the cam's user feels.</figcaption></figure>"
                                                + section("motion")),
        ("harmonics", "Harmonics of the deviation", harmonics),
    ]
    nav = "".join(f'<a href="#{sid}">{html.escape(t)}</a>' for sid, t, _ in body)
    text = "\n".join(f'<section id="{sid}"><h2>{html.escape(t)}</h2>\n{b}\n</section>' for sid, t, b in body)
    title = "Inspection of a made cam"
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{title}</title>\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
            f"<style>{CSS}</style>\n</head>\n<body>\n<main>\n<h1>{title}</h1>\n"
            f"<p class=\"sub\">{html.escape(report['cam'])} · made by cam_workbench {html.escape(__version__)}</p>\n"
            f"<nav>{nav}</nav>\n{text}\n</main>\n</body>\n</html>\n")


__all__ = ["FIGURES", "HTML_NAME", "JSON_NAME", "MOTION_CSV", "POINTS_CSV", "deviation_angle_figure",
           "deviation_map_figure", "deviations_csv", "figure_svgs", "figures", "harmonic_columns", "inspection_html",
           "inspection_json_text", "motion_csv", "motion_figure", "rows"]

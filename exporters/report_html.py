"""``report.html``: the design report as one self-contained file (inline SVG plots, inline
CSS, no scripts, nothing loaded from elsewhere), plus the same plots as PNG files.

Every number in a table is the value of ``report.json`` at the path in the cell's
``data-key`` (``data-value`` holds it exactly, the text shows it to 6 digits), so the
page and the JSON cannot disagree.

Sections appear when their data is present:

==============================  ============================================================
always                          the cam drawing with the follower, key numbers, the spec and
                                motion table, s/v/a/j, pressure angle, radius of curvature,
                                interpolation error and the accuracy figures
``report["drawing"]``           the DXF: how the profile was written and its measured error
``report["checks"]``            the design checks as report.json holds them
                                (``DesignChecks.to_dict()``): the verdict is its ``passed``
                                and ``failed`` verbatim, one table row per entry of
                                ``results`` (value, comparison, limit, cam angle, status,
                                note; failing rows red), ``extremes`` as a second table;
                                then the buildability verdicts (from the other sections)
``series["contact_force"]``,    contact force and Hertz stress over the cycle (figure): a
``series["contact_stress"]``    :class:`Series` each (arrays are not put in report.json)
``report["interpolator"]``      the rotational interpolator's commands (paper §3.2): the
                                follower motion they give (finite differences at Δt) against
                                the design, their deviation, and the maxima as in Table 2
``report["dynamics"]``          the follower train at speed: verdict (``contact.kept``), its
                                numbers, residual vibration; with the :class:`DynamicsResult`
                                (``dynamics=``) the force/torque/error figure and the
                                jump-speed curve
``report["body"]["second_cam"]``  a conjugate pair: both cams with both rollers, the second
                                cam's numbers, the lift errors of both built pitch curves and
                                the distance error between the rollers (figures and table)
``report["optimise"]``          optimiser: its scalar entries as a table and, when
                                ``"history"`` is a list of ``{"iteration", "objective",
                                "max_violation"}``, the convergence figure
==============================  ============================================================
"""
from __future__ import annotations

import html
import math
import re
from dataclasses import dataclass
from typing import Any, Callable, Iterable, Mapping, Sequence

import numpy as np

from cam_workbench.generators import __version__
from cam_workbench.generators.bodies.conjugate import roller_distance_error
from cam_workbench.generators.kinds import drawing_title
from cam_workbench.generators.cam_design import CamDesign
from cam_workbench.generators.checks.areas import area_label
from cam_workbench.generators.checks.claims import checks_verdict, pitch_text, profile_claim
from cam_workbench.generators.checks.design import limit_sign
from cam_workbench.generators.machining.interpolator import interpolator_accuracy
from cam_workbench.generators.spec.params import params_of, unit_name
from cam_workbench.generators.spec import SECTIONS, CamSpec, to_toml
from cam_workbench.generators.studies.remedies import remedy_line

from . import interpolator_plots, plots


@dataclass(frozen=True)
class Series:
    """A quantity over the cam cycle for the report (e.g. contact force).

    Attributes:
        theta_deg: cam angles [deg].
        values: the quantity at those angles.
        label: what it is ("contact force").
        unit: its unit ("N").
        limit: allowed value drawn as a line, or None.
        limit_kind: "max" or "min" (how the limit bounds the values).
    """

    theta_deg: np.ndarray
    values: np.ndarray
    label: str
    unit: str
    limit: float | None = None
    limit_kind: str | None = None


@dataclass(frozen=True)
class Plot:
    """One figure of the report: its key (file ``plot_<key>.png``, element ``fig-<key>``)."""

    key: str
    title: str
    caption: str
    make: Callable[[], Any]

    @property
    def png_name(self) -> str:
        return f"plot_{self.key}.png"


FORCE_STRESS_KEYS = ("contact_force", "contact_stress")


def report_plots(design: CamDesign, report: Mapping[str, Any],
                 series: Mapping[str, Series] | None = None, dynamics: Any = None) -> list[Plot]:
    """The figures this report will have, in order (optional ones only with their data);
    ``dynamics``: the :class:`cam_workbench.generators.dynamics.DynamicsResult` behind ``report["dynamics"]``."""
    series = series or {}
    u = design.spec.units
    fol = design.follower.describe()
    curve = fol["curve"]
    flat = fol["design_curve"] == "profile"
    pa_check = check_result(report, "pressure_angle")
    cv_check = check_result(report, "cusp" if flat else "curvature")
    small = plots.small_unit(u, design.follower.lift_unit)[1]
    ph = design.pitch.exact
    built = f"PH {curve}" if ph else f"fitted B-spline {curve}"
    claim = profile_claim(report, design.spec.is_roller, u) if "profile" in report else None
    prof_words = (f"The profile (filled) is the {claim.text}. Also drawn:" if claim else "The profile (filled),")
    ticks = "PH junctions" if ph else "B-spline knots"
    out = [
        Plot("cam", "The cam and its follower",
             f"{prof_words} " + ("the face's contact points (dashed), the base circle and the bore"
                                 if flat else f"the {curve} traced by the follower point (dashed), the prime and "
                                 "base circles and the bore") +
             f"; the follower ({fol['label']}) is drawn where it stands at 75° of cam rotation"
             + (", with its arm and pivot." if design.follower.pivoted else "."),
             lambda: plots.cam_drawing_figure(design)),
        Plot("kinematics", "Follower motion",
             f"Displacement, velocity, acceleration and jerk at {design.spec.cam.speed_rpm:g} rpm from the "
             "closed-form motion laws (design intent); grey lines separate the motion segments.",
             lambda: plots.kinematics_figure(design)),
        Plot("pressure_angle", "Pressure angle",
             f"φ {fol['pressure_angle_text']} over the cycle, and the pressure angle of the "
             f"built {built} at its curvature samples (they lie on the design curve). Dashed: the limit "
             "±checks.max_pressure_angle of the pressure_angle check; the marked point is the check's "
             "value at its cam angle (report.json checks.results.pressure_angle).",
             lambda: plots.pressure_angle_figure(design, check=pa_check)),
        Plot("curvature", "Radius of curvature",
             (f"Signed radius of curvature of the profile, {fol['curvature_text']}, positive where convex; "
              f"dots: the built {built}. A flat face needs ρ > 0 everywhere: the dashed line at 0 is the cusp "
              "check's limit and the marked point its value at its cam angle."
              if flat else
              f"Signed radius of curvature, positive where convex: {curve} ({fol['curvature_text']}) and "
              f"profile (ρ − roller radius); dots: the built {built}. Dashed: the curvature check's limit "
              "(checks.undercut_factor × roller radius) for the convex pitch radius; the profile undercuts "
              "where the convex pitch radius falls below the roller radius. The marked point is the "
              "curvature check's value at its cam angle.") + " The axis is clipped where the curve straightens.",
             lambda: plots.curvature_figure(design, check=cv_check)),
        Plot("deviation", "Interpolation error",
             f"s_actual − s [{small}]: the follower {'rotation' if fol['lift_unit'] == 'angle' else 'displacement'} "
             f"the built {curve} ({pitch_text(report) if 'pitch' in report else built}) gives (the follower "
             "touching the curve, paper Eq. 13 generalised) minus the design's, every "
             f"{360 / _deviation_count(design):.3g}°; ticks: {ticks}.",
             lambda: plots.deviation_figure(design)),
    ]
    panels = [series[k] for k in FORCE_STRESS_KEYS if k in series]
    if panels:
        out.append(Plot(
            "force_stress", "Contact force and stress",
            "Over the cycle: " + "; ".join(f"{p.label} [{p.unit}]" for p in panels) +
            ". Dashed: the allowed value.",
            lambda: plots.series_figure(
                [(p.theta_deg, p.values, f"{p.label} [{p.unit}]", p.limit, p.limit_kind) for p in panels],
                design)))
    it_rep = report.get("interpolator")
    if isinstance(it_rep, Mapping):
        acc_cache: dict[str, Any] = {}

        def accuracy() -> Any:
            if "acc" not in acc_cache:
                acc_cache["acc"] = interpolator_accuracy(design.pitch, float(it_rep["speed_rpm"]),
                                                         float(it_rep["sample_period"]))
            return acc_cache["acc"]

        out.append(Plot(
            "interpolator_kinematics", "Follower motion from the machining commands",
            f"s, v, a and j the follower gets from the interpolator's commands (every "
            f"{float(it_rep['step_deg']):.3g}°, finite differences at Δt = {float(it_rep['sample_period']):g} s, "
            f"{it_rep.get('differencing', 'backward')} differences as the paper's Figs. 4 and 6) over the "
            "exact curves of the motion laws.",
            lambda: interpolator_plots.kinematics_figure(accuracy(), design.program,
                                                         "deg" if fol["lift_unit"] == "angle" else u)))
        out.append(Plot(
            "interpolator_deviation", "Displacement error at the commands",
            f"s_actual − s [{small}] at every command (paper Figs. 5, 7, 8)" +
            ("; it vanishes at the PH junctions." if ph else "; ticks: the B-spline knots."),
            lambda: interpolator_plots.deviation_figure(accuracy(), "deg" if fol["lift_unit"] == "angle" else u,
                                                        junction_angles=design.pitch.angles,
                                                        junction_label=ticks)))
    dyn = report.get("dynamics")
    if dynamics is not None and isinstance(dyn, Mapping):
        u_small = plots.small_unit(u, design.follower.lift_unit)[1]
        out.append(Plot(
            "dynamics", "Follower dynamics at speed",
            f"One steady-state revolution at {float(dyn['speed_rpm']):.4g} rpm of the follower train as a spring–mass–"
            "damper (docs/dynamics.md): the normal contact force and the camshaft torque of the rigid follower "
            f"(dashed) and of the elastic train, and the displacement error q − s [{u_small}] with its vibration "
            "about the quasi-static deflection. Shaded: off the cam. The marked point is report.json's "
            "dynamics.contact.min_force at its cam angle.",
            lambda: plots.dynamics_figure(dynamics, dyn)))
        if isinstance(dyn.get("jump_speed"), Mapping):
            out.append(Plot(
                "jump_speed", "Jump speed",
                "The smallest contact force over a revolution of the periodic steady state against the cam "
                "speed (the sweep of dynamics.sweep_points speeds); the jump speed is where it first reaches 0 "
                "(refined by Brent's method between two speeds of the sweep). Lines: the analysis speed, the jump "
                "speed and the rigid follower's.",
                lambda: plots.jump_speed_figure(dynamics, dyn)))
    second = _second_cam(design, report)
    if second is not None:
        err_cache: dict[str, Any] = {}

        def error() -> Any:
            if "err" not in err_cache:
                err_cache["err"] = roller_distance_error(design.pitch, second.pitch)
            return err_cache["err"]

        out.append(Plot(
            "conjugate", "The conjugate pair",
            "Seen from +Z: the first cam (blue) over the second (below it, orange), each the exact offset of its "
            "own PH pitch curve (dashed: the first roller's centre, dash-dotted: the second's), and the follower "
            "with both rollers where it stands at 75° of cam rotation.",
            lambda: plots.conjugate_figure(design, second)))
        out.append(Plot(
            "roller_distance", "Distance error between the rollers",
            f"Top: the lift each built pitch curve gives the follower minus the design's [{small}] (each curve's "
            "PH deviation, the follower touching it: Eq. 13 generalised). Bottom: the distance error between the "
            "rollers that follows — the second roller's centre where the first cam puts the follower minus where "
            "the second cam wants it, along its path (report.json body.roller_distance_error).",
            lambda: plots.roller_distance_figure(design, error())))
    hist = _history(report)
    if hist is not None:
        it, obj, viol = hist
        name = str(report["optimise"].get("objective", "objective"))
        out.append(Plot("convergence", "Optimiser convergence",
                        f"Objective ({name}) per iteration" +
                        (" and the largest constraint violation." if viol is not None else "."),
                        lambda: plots.convergence_figure(it, obj, name, viol)))
    return out


def _second_cam(design: CamDesign, report: Mapping[str, Any]) -> CamDesign | None:
    """A conjugate pair's second cam (designed), when the report has its numbers."""
    body = report.get("body")
    if design.body is None or not isinstance(body, Mapping) or not isinstance(body.get("second_cam"), Mapping):
        return None
    return design.body.extra.get("second_cam")


def render_report(design: CamDesign, report: Mapping[str, Any], series: Mapping[str, Series] | None = None,
                  *, progress: Callable[[str], None] | None = None,
                  dynamics: Any = None) -> tuple[str, dict[str, bytes]]:
    """The HTML text and the PNG files ({name: bytes}) of the report.

    Args:
        design: the designed cam (for the plots).
        report: the report.json content (as written: parse the JSON text, so the HTML
            shows exactly what the file holds).
        series: optional θ-series (see the module docstring).
        progress: called with each figure's title before it is drawn.
        dynamics: the DynamicsResult behind ``report["dynamics"]`` (its figures).
    """
    figures: dict[str, str] = {}
    pngs: dict[str, bytes] = {}
    plot_list = report_plots(design, report, series, dynamics)
    for p in plot_list:
        if progress is not None:
            progress(p.title)
        fig = p.make()
        try:
            figures[p.key] = _inline_svg(plots.figure_bytes(fig, "svg").decode("utf-8"), p.key)
            pngs[p.png_name] = plots.figure_bytes(fig, "png", dpi=130)
        finally:
            plots.close(fig)
    return _page(design, report, plot_list, figures), pngs


# ---- page ----------------------------------------------------------------------------------
CSS = """
body{font-family:"DejaVu Sans",Helvetica,Arial,sans-serif;color:#1c2833;margin:0;background:#f4f6f8}
main{max-width:1120px;margin:0 auto;padding:24px 32px;background:#fff}
h1{margin:0 0 4px;font-size:26px}h2{margin:34px 0 10px;font-size:19px;border-bottom:2px solid #1f3b5c;
padding-bottom:3px}h3{font-size:15px;margin:18px 0 6px}
.sub{color:#566573;margin:0 0 14px}
nav{font-size:13px;margin:8px 0 0;line-height:1.8}nav a{color:#1f3b5c;margin-right:12px}
table{border-collapse:collapse;font-size:13px;margin:6px 0 12px}
th,td{border:1px solid #d5d8dc;padding:3px 8px;text-align:left;vertical-align:top}
th{background:#eaf0f6}tr:nth-child(even) td{background:#fafbfc}
td.num{text-align:right;font-family:"DejaVu Sans Mono",Menlo,monospace;white-space:nowrap}
td.pass{background:#d5f5e3 !important;color:#145a32;font-weight:bold}
td.fail{background:#fadbd8 !important;color:#78281f;font-weight:bold}
tr.fail td{background:#fadbd8 !important;color:#78281f}td.skip{background:#fef5e7 !important;color:#7e5109}
.grid{display:grid;grid-template-columns:1.15fr 1fr;gap:24px;align-items:start}
figure{margin:8px 0 18px}figcaption{font-size:12.5px;color:#424949;margin-top:2px}
svg.plot{width:100%;height:auto;display:block}
pre{background:#f8f9f9;border:1px solid #d5d8dc;padding:8px;font-size:12px;overflow-x:auto}
.verdict{display:inline-block;padding:4px 10px;border-radius:4px;font-weight:bold}
.verdict.pass,.verdict.buildable{background:#d5f5e3;color:#145a32}
.verdict.fail,.verdict.unbuildable{background:#fadbd8;color:#78281f}
.note{font-size:12.5px;color:#566573}a.plain{text-decoration:none}
"""


def _page(design: CamDesign, report: Mapping[str, Any], plot_list: Sequence[Plot],
          figures: Mapping[str, str]) -> str:
    spec = design.spec
    dr = spec.drawing
    u = report.get("units", spec.units)
    fig = {p.key: _figure(p, figures[p.key]) for p in plot_list}
    sections: list[tuple[str, str, str]] = []  # (id, title, body)

    lu = report.get("motion", {}).get("lift_unit", u)
    key_rows = [
        ("follower", "follower.label", "", None),
        ("base radius R_b (prime circle)", "spec.cam.base_radius", u, None),
        ("base circle radius (the profile at zero lift)", "profile.base_circle_radius", u, None),
        ("smallest profile radius (built)", "profile.min_radius", u, None),
        ("largest profile radius", "profile.max_radius", u, "profile.max_radius_at_deg"),
        ("follower offset e", "follower.offset", u, None),
        ("arm pivot distance d", "follower.pivot_distance", u, None),
        ("arm length L", "follower.arm_length", u, None),
        ("arm angle at zero lift ψ₀", "follower.arm_angle_at_zero_lift_deg", "deg", None),
        ("face offset from the pivot f", "follower.face_offset", u, None),
        ("face normal angle at zero lift β₀", "follower.face_angle_at_zero_lift_deg", "deg", None),
        ("roller radius", "spec.follower.roller_radius", u, None),
        ("bore diameter", "spec.cam.bore_diameter", u, None),
        ("thickness", "spec.cam.thickness", u, None),
        (area_label("area"), "area", f"{u}²", None),
        *_area_rows(report, u),
        ("volume", "volume", f"{u}³", None),
        ("max pressure angle", "pressure_angle.max_deg", "deg", "pressure_angle.at_deg"),
        ("min profile radius of curvature", "curvature.min_profile_radius", u, "curvature.at_deg"),
        ("max follower deviation", "pitch.max_deviation", lu, "pitch.max_deviation_at_deg"),
    ]
    if not spec.is_roller:
        key_rows = [r for r in key_rows if r[1] != "spec.follower.roller_radius"]
    claim = profile_claim(report, spec.is_roller, u) if "profile" in report else None
    sections.append(("cam", "The cam", f'<div class="grid"><div>{fig["cam"]}</div><div>'
                     f'{_verdict(report)}{_quantity_table(report, key_rows)}</div></div>'))
    sections.append(("spec", "Specification", _spec_section(spec, report)))
    motion_rows = [
        ("largest lift", "motion.max_lift", lu, None),
        ("max |velocity|", "motion.max_velocity", f"{lu}/s", None),
        ("max |acceleration|", "motion.max_acceleration", f"{lu}/s²", None),
        ("max |jerk|", "motion.max_jerk", f"{lu}/s³", None),
    ]
    sections.append(("motion", "Follower motion", fig["kinematics"] + _quantity_table(report, motion_rows)
                     + _segments_table(report, lu) + _junctions_table(report, lu)))
    pa_rows = [
        ("max |φ| (design)", "pressure_angle.max_deg", "deg", "pressure_angle.at_deg"),
        ("signed φ at that angle", "pressure_angle.signed_deg", "deg", None),
        ("max |φ| (built curve)", "pressure_angle.as_built.max_deg", "deg", "pressure_angle.as_built.at_deg"),
    ]
    sections.append(("pressure", "Pressure angle", fig["pressure_angle"] + _quantity_table(report, pa_rows)))
    cv_rows = [
        (f"min convex {report.get('follower', {}).get('curve', 'pitch curve')} radius (design)",
         "curvature.min_pitch_radius", u, "curvature.at_deg"),
        ("min convex profile radius (design)", "curvature.min_profile_radius", u, "curvature.at_deg"),
        ("min concave pitch radius (design)", "curvature.min_concave_pitch_radius", u, None),
        ("min convex pitch radius (built)", "curvature.as_built.min_pitch_radius", u, "curvature.as_built.at_deg"),
        ("min convex profile radius (built)", "curvature.as_built.min_profile_radius", u,
         "curvature.as_built.at_deg"),
        ("min concave pitch radius (built)", "curvature.as_built.min_concave_pitch_radius", u, None),
    ]
    sections.append(("curvature", "Radius of curvature", fig["curvature"] + _quantity_table(report, cv_rows)))
    acc_rows = [
        ("max |s_actual − s|", "pitch.max_deviation", lu, "pitch.max_deviation_at_deg"),
        ("target deviation (pitch.tolerance)", "pitch.tolerance", lu, None),
        ("PH segments M" if design.pitch.exact else "B-spline knot spans", "pitch.segments", "",
         None),
        ("Newton iterations of the spline solve", "pitch.newton_iterations", "", None),
        ("Newton residual (relative)", "pitch.newton_residual", "", None),
        ("pitch-curve arc length" + (" (closed form, PH)" if design.pitch.exact else ""),
         "pitch.arc_length", u, None),
        ("profile NURBS degree", "profile.degree", "", None),
        ("profile NURBS rational", "profile.rational", "", None),
        ("profile poles", "profile.poles", "", None),
        ("profile: max distance from the design-intent profile", "profile.max_error", u,
         "profile.max_error_at_deg"),
        ("profile: fitted offset vs the exact offset of the fitted pitch B-spline",
         "profile.fitted_vs_kernel_offset", u, None),
        ("profile: exact offset of the fitted pitch B-spline vs the design-intent profile",
         "profile.kernel_offset.max_error", u, "profile.kernel_offset.max_error_at_deg"),
        ("solid: OCCT volume", "solid.kernel_volume", f"{u}³", None),
        ("solid: volume of the profile NURBS (Green's theorem × thickness)", "volume", f"{u}³", None),
        ("solid: OCCT cross-section area", "solid.cross_section_area", f"{u}²", None),
        ("solid: cross-section of the profile NURBS (Green's theorem)", "area", f"{u}²", None),
        ("solid: OCCT volume / Green's theorem − 1", "solid.volume_rel_diff", "", None),
        ("solid: OCCT cross-section / Green's theorem − 1", "solid.area_rel_diff", "", None),
    ]
    acc_note = ""
    if claim is not None:
        where = ("so the only approximation in the geometry is the pitch curve's interpolation of the "
                 "motion, measured above" if claim.exact else
                 "so the geometry carries both the pitch curve's interpolation error and the fit's error, "
                 "each measured above")
        acc_note = (f'<p class="note" id="profile-claim" data-exact="{str(claim.exact).lower()}">The profile '
                    f"is the {html.escape(claim.text)}, {where}. OCCT's numbers are an independent check of "
                    "the built solid.</p>")
    sections.append(("accuracy", "Interpolation error and accuracy",
                     fig["deviation"] + _quantity_table(report, acc_rows) + acc_note))
    if _second_cam(design, report) is not None:        # a pair: its figure and numbers
        lu2 = "deg" if report["body"]["roller_distance_error"]["lift_unit"] == "deg" else u
        cj_rows = [
            ("second roller", "body.second_cam.follower.label", "", None),
            ("second cam from z", "body.second_cam.z.0", u, None),
            ("second cam to z", "body.second_cam.z.1", u, None),
            ("axial gap", "body.gap", u, None),
            ("spacer diameter", "body.spacer_diameter", u, None),
            ("second cam: max |φ| (design)", "body.second_cam.pressure_angle.max_deg", "deg",
             "body.second_cam.pressure_angle.at_deg"),
            ("second cam: max |φ| (built curve)", "body.second_cam.pressure_angle.as_built.max_deg", "deg",
             "body.second_cam.pressure_angle.as_built.at_deg"),
            ("second cam: min convex pitch radius", "body.second_cam.curvature.min_pitch_radius", u,
             "body.second_cam.curvature.at_deg"),
            ("second cam: min convex profile radius", "body.second_cam.curvature.min_profile_radius", u,
             "body.second_cam.curvature.at_deg"),
            ("second cam: smallest radius", "body.second_cam.profile.min_radius", u, None),
            ("second cam: largest radius", "body.second_cam.profile.max_radius", u,
             "body.second_cam.profile.max_radius_at_deg"),
            ("second cam: PH segments M", "body.second_cam.pitch.segments", "", None),
            ("second cam: max |s_actual − s|", "body.second_cam.pitch.max_deviation", lu2,
             "body.second_cam.pitch.max_deviation_at_deg"),
            ("second cam: profile's max distance from the design-intent profile",
             "body.second_cam.profile.max_error", u, "body.second_cam.profile.max_error_at_deg"),
            ("distance error between the rollers: max", "body.roller_distance_error.max", u,
             "body.roller_distance_error.at_deg"),
            ("largest interference", "body.roller_distance_error.largest_interference", u, None),
            ("largest play", "body.roller_distance_error.largest_play", u, None),
            ("max |s₁ − s₂| (lift)", "body.roller_distance_error.lift_max", lu2,
             "body.roller_distance_error.lift_at_deg"),
            ("bound: first + second cam's max deviation", "body.roller_distance_error.lift_bound", lu2, None),
            ("share of the turn the first cam drives", "body.drive.first_cam_share", "", None),
            ("share of the turn the second cam drives", "body.drive.second_cam_share", "", None),
        ]
        sections.append(("conjugate", "Conjugate cams", fig["conjugate"] + _quantity_table(report, cj_rows)
                         + fig["roller_distance"]))
    if "force_stress" in fig:
        sections.append(("force", "Contact force and stress", fig["force_stress"]))
    if isinstance(report.get("dynamics"), Mapping):
        sections.append(("dynamics", "Follower dynamics", _dynamics_section(report, fig)))
    if "interpolator_kinematics" in fig:
        ip_rows = [
            ("cam speed", "interpolator.speed_rpm", "rpm", None),
            ("sample period Δt", "interpolator.sample_period", "s", None),
            ("cam rotation per command", "interpolator.step_deg", "deg", None),
            ("commands per revolution", "interpolator.commands", "", None),
            ("max |s_actual − s| at the commands", "interpolator.max_deviation", lu,
             "interpolator.max_deviation_at_deg"),
            ("max |v| from the commands", "interpolator.velocity.max", f"{lu}/s", "interpolator.velocity.at_deg"),
            ("max |v| desired", "interpolator.velocity.desired_max", f"{lu}/s", None),
            ("max |a| from the commands", "interpolator.acceleration.max", f"{lu}/s²",
             "interpolator.acceleration.at_deg"),
            ("max |a| desired", "interpolator.acceleration.desired_max", f"{lu}/s²", None),
            ("increase of max |a| [%]", "interpolator.acceleration.increase_percent", "%", None),
            ("max |j| from the commands", "interpolator.jerk.max", f"{lu}/s³", "interpolator.jerk.at_deg"),
            ("max |j| desired", "interpolator.jerk.desired_max", f"{lu}/s³", None),
            ("increase of max |j| [%]", "interpolator.jerk.increase_percent", "%", None),
        ]
        note = report["interpolator"].get("warning")
        warn = f'<p class="note"><b>warning:</b> {html.escape(str(note))}</p>' if note else ""
        sections.append(("interpolator", "Machining commands (rotational PH interpolator)",
                         fig["interpolator_kinematics"] + _quantity_table(report, ip_rows) +
                         fig["interpolator_deviation"] + warn))
    # the verdicts come right after the cam, before the curves they are judged on
    verdicts = [("buildability", "Buildability", _buildability_section(report))]
    if isinstance(report.get("checks"), Mapping):
        verdicts.insert(0, ("checks", "Design checks", _checks_section(report)))
    sections[1:1] = verdicts
    if isinstance(report.get("optimise"), Mapping):
        body = _objective_note(report) + _scalars_table(report, "optimise", exclude=("history",))
        sections.append(("optimise", "Optimiser", fig.get("convergence", "") + body))
    if isinstance(report.get("drawing"), Mapping):
        sections.append(("drawing", "Manufacturing drawing (DXF)", _drawing_section(report)))
    if isinstance(report.get("files"), Mapping):
        sections.append(("files", "Files", _files_section(report)))

    title = html.escape(drawing_title(spec))
    sub = [str(report.get("follower", {}).get("name", spec.follower.kind)) + " follower",
           f"{len(spec.motion)} motion segments",
           "pitch curve: " + (pitch_text(report) if "pitch" in report else str(spec.pitch.representation)),
           f"units {u}"]
    ident = [f"part {html.escape(dr.part_number)}" if dr.part_number else "",
             f"material {html.escape(dr.material)}" if dr.material else "",
             f"by {html.escape(dr.author)}" if dr.author else ""]
    nav = "".join(f'<a href="#{sid}">{html.escape(t)}</a>' for sid, t, _ in sections)
    body = "\n".join(f'<section id="{sid}"><h2>{html.escape(t)}</h2>\n{b}\n</section>' for sid, t, b in sections)
    return (
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
        f"<title>{title} — cam design report</title>\n"
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<style>{CSS}</style>\n</head>\n<body>\n<main>\n"
        f"<h1>{title}</h1>\n<p class=\"sub\">{html.escape(' · '.join(sub))}"
        f"{' · ' + ' · '.join(x for x in ident if x) if any(ident) else ''}"
        f" · made by cam_workbench {html.escape(__version__)}</p>\n"
        f"<nav>{nav}</nav>\n{body}\n</main>\n</body>\n</html>\n"
    )


def _figure(p: Plot, svg: str) -> str:
    return (f'<figure id="fig-{p.key}" data-png="{p.png_name}">{svg}'
            f"<figcaption>{html.escape(p.caption)}</figcaption></figure>")


# ---- numbers -------------------------------------------------------------------------------
def lookup(report: Mapping[str, Any], key: str) -> Any:
    """The value at a dotted path (list indices as numbers): ``spec.motion.1.lift``."""
    node: Any = report
    for part in key.split("."):
        if isinstance(node, list):
            node = node[int(part)]
        elif isinstance(node, Mapping) and part in node:
            node = node[part]
        else:
            raise KeyError(key)
    return node


def _has(report: Mapping[str, Any], key: str) -> bool:
    try:
        lookup(report, key)
        return True
    except (KeyError, IndexError, ValueError):
        return False


def format_number(v: Any) -> str:
    """How a number is shown: 6 significant digits (integers and booleans as they are)."""
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            return str(v)
        return f"{v:.6g}"
    return html.escape(str(v))


def _num_cell(report: Mapping[str, Any], key: str) -> str:
    v = lookup(report, key)
    if isinstance(v, str):
        return f'<td data-key="{key}">{html.escape(v)}</td>'
    data = "null" if v is None else ("true" if v is True else "false" if v is False else repr(v))
    return f'<td class="num" data-key="{key}" data-value="{data}">{format_number(v)}</td>'


def _quantity_table(report: Mapping[str, Any], rows: Iterable[tuple[str, str, str, str | None]]) -> str:
    """Rows (label, key, unit, key of the cam angle or None); rows whose key is absent are left out."""
    out = ['<table class="q"><tr><th>quantity</th><th>value</th><th>unit</th><th>at cam angle [deg]</th></tr>']
    for label, key, unit, at in rows:
        if not _has(report, key):
            continue
        at_cell = _num_cell(report, at) if at and _has(report, at) else "<td></td>"
        out.append(f"<tr><td>{html.escape(label)}</td>{_num_cell(report, key)}<td>{html.escape(unit)}</td>"
                   f"{at_cell}</tr>")
    out.append("</table>")
    return "".join(out)


def _area_rows(report: Mapping[str, Any], u: str) -> list[tuple[str, str, str, None]]:
    """Key-number rows of report.json's design-intent ``areas`` the cam has (the thesis' Eq. 4.21
    area, the areas inside the design curve and the profile), each named as :data:`AREA_LABELS` names it."""
    areas = report.get("areas")
    if not isinstance(areas, Mapping):
        return []
    curve = str(report.get("follower", {}).get("curve", "pitch curve"))
    return [(area_label(k, curve), f"areas.{k}", f"{u}²", None) for k in ("thesis_eq_4_21", "pitch_curve", "profile")
            if isinstance(areas.get(k), (int, float))]


def _objective_note(report: Mapping[str, Any]) -> str:
    """What the optimiser minimised, named as report.json names it (``objective_label``, and the
    path ``objective_key`` where the optimised cam's value is), apart from the cross-section."""
    opt = report["optimise"]
    key = opt.get("objective_key")
    where = f" (report.json <code>{html.escape(str(key))}</code>)" if key else ""
    return (f'<p class="note" id="objective">Objective <b>{html.escape(str(opt.get("objective")))}</b>: '
            f'{html.escape(str(opt.get("objective_label", "")))}{where}; the cam\'s cross-section is report.json '
            "<code>area</code>.</p>")


def _scalars_table(report: Mapping[str, Any], section: str, exclude: Sequence[str] = ()) -> str:
    """Every scalar of ``report[section]`` (nested dicts flattened) as key/value rows."""
    rows = []

    def walk(node: Any, path: str) -> None:
        if isinstance(node, Mapping):
            for k, v in node.items():
                if path == section and k in exclude:
                    continue
                walk(v, f"{path}.{k}")
        elif not isinstance(node, list):
            label = path[len(section) + 1:].replace("_", " ")
            rows.append(f"<tr><td>{html.escape(label)}</td>{_num_cell(report, path)}</tr>")

    walk(report[section], section)
    return '<table class="kv"><tr><th>item</th><th>value</th></tr>' + "".join(rows) + "</table>"


def check_result(report: Mapping[str, Any], name: str) -> Mapping[str, Any] | None:
    """report.json's ``checks.results[name]``, or None when the report has no such check."""
    checks = report.get("checks")
    if not isinstance(checks, Mapping) or not isinstance(checks.get("results"), Mapping):
        return None
    r = checks["results"].get(name)
    return r if isinstance(r, Mapping) else None


def _deviation_count(design: CamDesign) -> int:
    """Samples of the deviation figure (the pitch curve's own rule when it has one)."""
    count = getattr(design.pitch, "deviation_count", None)
    if count is not None:
        return int(count())
    return len(design.pitch.deviation()[0])


def _checks_section(report: Mapping[str, Any]) -> str:
    """The verdict, one row per check of ``checks.results`` and the extremes table."""
    checks = report["checks"]
    results = checks.get("results") if isinstance(checks.get("results"), Mapping) else {}
    mode = ("the thesis' 71 nodes per rise/return" if checks.get("sampling") == "thesis71"
            else f"{checks.get('samples_per_segment')} samples per rise/return, refined extrema")
    out = [_verdict(report),
           f'<p class="note">Sampling: {html.escape(mode)} ({html.escape(str(checks.get("points")))} points). '
           "Limits from the spec's [checks], [material] and follower load.</p>",
           '<table class="checks"><tr><th>check</th><th>value</th><th>rule</th><th>limit</th><th>unit</th>'
           "<th>at cam angle [deg]</th><th>status</th><th>note</th></tr>"]
    for name, r in results.items():
        prefix = f"checks.results.{name}"
        status = str(r.get("status"))
        kind = str(r.get("kind"))
        sign = limit_sign(name, kind) if r.get("limit") is not None else ""
        cls = {"fail": "fail", "pass": "pass", "skipped": "skip"}.get(status, "")
        desc = html.escape(str(r.get("description", "")))
        out.append(
            f'<tr class="check {cls}" data-check="{html.escape(name)}" data-status="{html.escape(status)}">'
            f'<td title="{desc}"><code>{html.escape(name)}</code> <span class="note">({html.escape(kind)}: '
            f"{desc})</span></td>"
            f"{_num_cell(report, prefix + '.value')}"
            f'<td class="sign" data-sign="{html.escape(sign)}">{html.escape(sign)}</td>'
            f"{_num_cell(report, prefix + '.limit')}"
            f"<td>{html.escape(str(r.get('unit', '')))}</td>"
            f"{_num_cell(report, prefix + '.at_deg')}"
            f'<td class="{cls}" data-key="{prefix}.status">{html.escape(status)}</td>'
            f'<td data-key="{prefix}.note">{html.escape(str(r.get("note", "")))}</td></tr>')
    out.append("</table>")
    out.append(_remedies(results))
    ext = checks.get("extremes")
    if isinstance(ext, Mapping) and ext:
        out.append("<h3>Extremes (largest magnitude, signed: the thesis' maximum values)</h3>")
        out.append('<table class="extremes"><tr><th>quantity</th><th>value</th><th>unit</th>'
                   "<th>at cam angle [deg]</th></tr>")
        for name, e in ext.items():
            prefix = f"checks.extremes.{name}"
            at = _num_cell(report, prefix + ".at_deg") if "at_deg" in e else "<td></td>"
            out.append(f"<tr><td>{html.escape(name.replace('_', ' '))}</td>{_num_cell(report, prefix + '.value')}"
                       f"<td>{html.escape(str(e.get('unit', '')))}</td>{at}</tr>")
        out.append("</table>")
    return "".join(out)


def _remedies(results: Mapping[str, Any]) -> str:
    """What makes each failing check pass (report.json's ``checks.results[name].remedy``, the line
    ``cam-workbench check`` prints under its table)."""
    items = [f'<li data-key="checks.results.{html.escape(name)}.remedy"><code>{html.escape(name)}</code>: '
             f"{html.escape(remedy_line(name, r['remedy'])[len(name) + 2:])}</li>"
             for name, r in results.items() if isinstance(r, Mapping) and isinstance(r.get("remedy"), Mapping)]
    if not items:
        return ""
    return ('<h3>To pass (the nearest change of one field, everything else held)</h3><ul class="remedies">'
            + "".join(items) + "</ul>")


#: report.json motion.segments keys of the solved laws, shown per segment: (key, label, unit kind)
_SEGMENT_DETAILS = (
    ("degree", "polynomial degree", ""), ("conditions", "conditions", ""),
    ("velocity", "cruise velocity", "/rad"), ("start_blend_deg", "start blend", "deg"),
    ("end_blend_deg", "end blend", "deg"), ("points", "table points", ""), ("spans", "knot spans", ""),
    ("order", "B-spline order", ""), ("max_error", "fit: max |s_fit − s_i|", "lift"),
    ("max_error_at_deg", "at cam angle", "deg"), ("rms_error", "fit: rms error", "lift"),
    ("tolerance", "table_tolerance", "lift"),
)


def _segments_table(report: Mapping[str, Any], lu: str) -> str:
    """The motion segments whose laws were solved or fitted (polynomial, constant_velocity, table):
    what they came out as (report.json ``motion.segments``)."""
    segs = report.get("motion", {}).get("segments")
    if not isinstance(segs, list):
        return ""
    rows = []
    for i, seg in enumerate(segs):
        if seg.get("law") not in ("polynomial", "constant_velocity", "table"):
            continue
        for key, label, unit in _SEGMENT_DETAILS:
            if key in seg:
                u = lu if unit == "lift" else (lu + unit if unit.startswith("/") else unit)
                rows.append(f"<tr><td>{i}</td><td>{html.escape(str(seg['law']))}</td><td>{html.escape(label)}</td>"
                            f"{_num_cell(report, f'motion.segments.{i}.{key}')}<td>{html.escape(u)}</td></tr>")
        if "coefficients" in seg:
            coef = ", ".join(f"{c:.6g}" for c in seg["coefficients"])
            rows.append(f"<tr><td>{i}</td><td>polynomial</td><td>coefficients a₀ … a_d of s = Σ a_k x^k, "
                        f"x = (θ − θ_start)/span</td><td class=\"coef\">"
                        f"{html.escape(coef)}</td><td>{html.escape(lu)}</td></tr>")
    if not rows:
        return ""
    return ("<h3>Solved and fitted segments</h3>"
            '<table class="segments"><tr><th>#</th><th>law</th><th>quantity</th><th>value</th><th>unit</th></tr>'
            + "".join(rows) + "</table>")


def _junctions_table(report: Mapping[str, Any], lu: str) -> str:
    """report.json ``motion.junctions``: one row per segment boundary with the jumps of s′, s″, s‴,
    the order of continuity reached and the order the laws promise."""
    junctions = report.get("motion", {}).get("junctions")
    if not isinstance(junctions, list) or not junctions:
        return ""
    out = ["<h3>Segment junctions</h3>",
           '<p class="note">Jumps are right − left of s′, s″, s‴ (per radian) where one segment ends and the '
           "next starts; C<i>n</i>: s … s<sup>(n)</sup> continuous. A junction fails when it reaches less than "
           "the laws on either side promise (the <code>continuity</code> check).</p>",
           '<table class="junctions"><tr><th>at cam angle [deg]</th><th>from → to</th>'
           f"<th>Δs′ [{html.escape(lu)}/rad]</th><th>Δs″ [{html.escape(lu)}/rad²]</th>"
           f"<th>Δs‴ [{html.escape(lu)}/rad³]</th><th>reached C<i>n</i></th><th>promised C<i>n</i></th><th>met</th></tr>"]
    for i, j in enumerate(junctions):
        pre = f"motion.junctions.{i}"
        ok = bool(j.get("ok"))
        cls = "pass" if ok else "fail"
        out.append(
            f'<tr class="{cls}">{_num_cell(report, pre + ".at_deg")}'
            f"<td>motion[{j.get('from')}] {html.escape(str(j.get('from_law')))} → motion[{j.get('to')}] "
            f"{html.escape(str(j.get('to_law')))}</td>"
            f"{_num_cell(report, pre + '.jumps.velocity')}{_num_cell(report, pre + '.jumps.acceleration')}"
            f"{_num_cell(report, pre + '.jumps.jerk')}{_num_cell(report, pre + '.order')}"
            f"{_num_cell(report, pre + '.promised')}"
            f"{_num_cell(report, pre + '.ok')}</tr>")
    out.append("</table>")
    return "".join(out)


def _dynamics_section(report: Mapping[str, Any], fig: Mapping[str, str]) -> str:
    """report.json's ``dynamics`` section: the verdict, the numbers, residual vibration, figures."""
    d = report["dynamics"]
    kept = d["contact"]["kept"] is True
    speed = format_number(d["speed_rpm"])
    text = (f"the follower stays on the cam at {speed} rpm" if kept else
            f"the follower LEAVES the cam at {speed} rpm")
    out = [f'<p><span class="verdict {"pass" if kept else "fail"}" id="dynamics-verdict" '
           f'data-key="dynamics.contact.kept" data-value="{"true" if kept else "false"}">{html.escape(text)}</span></p>']
    m = d["model"]
    fu = d["contact"]["unit"]
    lu = d["error"]["unit"]
    tu = d["torque"]["unit"]
    rows = [
        ("analysis speed", "dynamics.speed_rpm", "rpm", None),
        ("effective " + ("inertia" if m["coordinate"] == "arm angle" else "mass"), "dynamics.model.mass",
         m["mass_unit"], None),
        ("train stiffness k_f", "dynamics.model.stiffness", m["stiffness_unit"], None),
        ("return spring rate", "dynamics.model.spring_rate", m["stiffness_unit"], None),
        ("preload", "dynamics.model.preload", m["preload_unit"], None),
        ("damping ratio ζ", "dynamics.model.damping_ratio", "", None),
        ("natural frequency of the train on the cam", "dynamics.model.natural_frequency_hz", "Hz", None),
        ("natural frequency / cam frequency", "dynamics.model.frequency_ratio", "", None),
        ("samples per revolution", "dynamics.model.samples", "", None),
        ("smallest contact force (dynamic)", "dynamics.contact.min_force", fu, "dynamics.contact.min_force_at_deg"),
        ("largest contact force (dynamic)", "dynamics.contact.max_force", fu, "dynamics.contact.max_force_at_deg"),
        ("smallest contact force (rigid follower)", "dynamics.contact.rigid_min_force", fu,
         "dynamics.contact.rigid_min_force_at_deg"),
        ("largest contact force (rigid follower)", "dynamics.contact.rigid_max_force", fu,
         "dynamics.contact.rigid_max_force_at_deg"),
        ("cam rotation with the follower off the cam", "dynamics.contact.off_cam_deg", "deg", None),
        ("largest gap off the cam", "dynamics.contact.max_gap", lu, "dynamics.contact.max_gap_at_deg"),
        ("largest landing speed", "dynamics.contact.max_landing_speed", f"{lu}/s", None),
        ("largest displacement error |q − s|", "dynamics.error.max", lu, "dynamics.error.at_deg"),
        ("largest vibration about the quasi-static deflection", "dynamics.error.max_vibration", lu,
         "dynamics.error.vibration_at_deg"),
        ("jump speed", "dynamics.jump_speed.rpm", "rpm", None),
        ("jump speed / analysis speed", "dynamics.jump_speed.ratio_to_speed", "", None),
        ("rigid follower's jump speed", "dynamics.jump_speed.rigid_rpm", "rpm", None),
        ("sweep from", "dynamics.jump_speed.sweep_from_rpm", "rpm", None),
        ("sweep to", "dynamics.jump_speed.sweep_to_rpm", "rpm", None),
        ("sweep speeds", "dynamics.jump_speed.sweep_points", "", None),
        ("camshaft torque, largest (rigid)", "dynamics.torque.rigid.max", tu, "dynamics.torque.rigid.max_at_deg"),
        ("camshaft torque, smallest (rigid)", "dynamics.torque.rigid.min", tu, "dynamics.torque.rigid.min_at_deg"),
        ("camshaft torque, RMS (rigid)", "dynamics.torque.rigid.rms", tu, None),
        ("work per revolution (rigid)", "dynamics.torque.rigid.work_per_revolution", tu, None),
        ("camshaft torque, largest (dynamic)", "dynamics.torque.dynamic.max", tu,
         "dynamics.torque.dynamic.max_at_deg"),
        ("camshaft torque, smallest (dynamic)", "dynamics.torque.dynamic.min", tu,
         "dynamics.torque.dynamic.min_at_deg"),
        ("camshaft torque, RMS (dynamic)", "dynamics.torque.dynamic.rms", tu, None),
        ("work per revolution (dynamic: the damper's and the landings' losses)",
         "dynamics.torque.dynamic.work_per_revolution", tu, None),
        ("revolutions run (0: periodic solve)", "dynamics.steady_state.revolutions", "", None),
        ("steady state reached", "dynamics.steady_state.periodic", "", None),
    ]
    out.append(fig.get("dynamics", ""))
    out.append(_quantity_table(report, rows))
    notes = [f'<span data-key="dynamics.steady_state.method">{html.escape(str(d["steady_state"]["method"]))}</span>']
    jp = d.get("jump_speed")
    if isinstance(jp, Mapping) and jp.get("note"):
        notes.append(f'<span data-key="dynamics.jump_speed.note">{html.escape(str(jp["note"]))}</span>')
    out.append('<p class="note">' + ". ".join(notes) + ".</p>")
    res = d.get("residual_vibration") or []
    if res:
        out.append("<h3>Residual vibration after each rise and return</h3>")
        out.append('<table class="residual"><tr><th>after</th><th>into</th><th>largest vibration</th><th>unit</th>'
                   "<th>at cam angle [deg]</th></tr>")
        for i, r in enumerate(res):
            key = f"dynamics.residual_vibration.{i}"
            out.append(f"<tr><td>motion[{int(r['after'])}] ({html.escape(str(r['kind']))})</td>"
                       f"<td>motion[{int(r['next'])}] ({html.escape(str(r['next_kind']))})</td>"
                       f"{_num_cell(report, key + '.amplitude')}<td>{html.escape(lu)}</td>"
                       f"{_num_cell(report, key + '.at_deg')}</tr>")
        out.append("</table>")
    out.append(fig.get("jump_speed", ""))
    return "".join(out)


def _verdict(report: Mapping[str, Any]) -> str:
    """report.json's checks.passed / checks.failed, verbatim (nothing when there are no checks)."""
    checks = report.get("checks")
    if not isinstance(checks, Mapping) or "passed" not in checks:
        return ""
    ok = checks["passed"] is True
    failed = html.escape(",".join(str(n) for n in checks.get("failed") or []))
    return (f'<p><a class="plain" href="#checks"><span class="verdict {"pass" if ok else "fail"}" data-key="checks.passed" '
            f'data-value="{"true" if ok else "false"}" data-failed="{failed}">'
            f"{html.escape(checks_verdict(checks))}</span></a></p>")


def buildability_rows(report: Mapping[str, Any]) -> list[tuple[str, str, str]]:
    """(item, value, status "pass"/"fail"/"") of the buildability verdicts, from report.json.

    The undercut, self-intersection and bore checks raise before any report is written
    (``design_cam``), so a report exists only for a cam that passed them; the numbers shown
    are the margins they were judged on."""
    u = report.get("units", "")
    lu = report.get("motion", {}).get("lift_unit", u)
    rows: list[tuple[str, str, str]] = []
    prof = report.get("profile", {})
    cv = report.get("curvature", {})
    flat = report.get("follower", {}).get("design_curve") == "profile"
    if "min_profile_radius" in cv:
        v = cv["min_profile_radius"]
        what = ("cusp: smallest radius of curvature of the profile > 0" if flat else
                "undercut: smallest convex profile radius of curvature > 0")
        rows.append((what, f"{format_number(v)} {u}", "pass" if v > 0 else "fail"))
    rows.append(("profile self-intersection", "none found (design_cam refuses a crossing profile)", "pass"))
    spec = report.get("spec", {})
    bore = spec.get("cam", {}).get("bore_diameter") if isinstance(spec, Mapping) else None
    if "min_radius" in prof and bore is not None:
        ok = prof["min_radius"] > bore / 2
        rows.append(("bore inside the profile: smallest profile radius > bore radius",
                     f"{format_number(prof['min_radius'])} > {format_number(bore / 2)} {u}", "pass" if ok else "fail"))
    pt = report.get("pitch", {})
    if pt.get("tolerance") is not None:
        ok = pt["max_deviation"] <= pt["tolerance"]
        rows.append(("pitch curve within pitch.tolerance",
                     f"{format_number(pt['max_deviation'])} ≤ {format_number(pt['tolerance'])} {lu}",
                     "pass" if ok else "fail"))
    solid = report.get("solid")
    if isinstance(solid, Mapping) and "valid" in solid:
        ok = solid["valid"] is True and solid.get("solids") == 1
        rows.append(("OCCT: valid, one solid", f"valid {format_number(solid['valid'])}, "
                     f"{format_number(solid.get('solids'))} solid(s)", "pass" if ok else "fail"))
    it = report.get("interpolator")
    if isinstance(it, Mapping) and it.get("within_pitch_tolerance") is not None:
        ok = it["within_pitch_tolerance"] is True
        rows.append(("machining commands within pitch.tolerance", format_number(it["max_deviation"]) + f" {lu}",
                     "pass" if ok else "fail"))
    return rows


def _buildability_section(report: Mapping[str, Any]) -> str:
    rows = buildability_rows(report)
    ok = all(st != "fail" for _, _, st in rows)
    # "buildable"/"unbuildable", not "pass"/"fail": the class "verdict pass" is the design checks'
    # verdict alone, so a reader (or a script) never takes a buildable cam for one that passes
    out = [f'<p><span class="verdict {"buildable" if ok else "unbuildable"}" id="buildable-verdict">'
           f'{"buildable: every buildability check passes" if ok else "NOT buildable: see the red rows"}'
           "</span></p>",
           '<table class="build"><tr><th>check</th><th>value</th><th>status</th></tr>']
    for item, value, st in rows:
        out.append(f'<tr class="{st}"><td>{html.escape(item)}</td><td>{html.escape(value)}</td>'
                   f'<td class="{st}">{st or "—"}</td></tr>')
    out.append("</table>")
    return "".join(out)


def _spec_section(spec: CamSpec, report: Mapping[str, Any]) -> str:
    """Tables of every spec field (values from report["spec"]), the motion table, the TOML."""
    out = []
    if "spec" in report:
        units = spec.units
        rows = [("units", "spec.units", "")]
        for name, (cls, is_list, _req) in SECTIONS.items():
            if is_list:
                continue
            for field, p in params_of(cls).items():
                if _has(report, f"spec.{name}.{field}"):
                    rows.append((f"{name}.{field}", f"spec.{name}.{field}", unit_name(p.unit, units)))
        out.append('<table class="spec"><tr><th>field</th><th>value</th><th>unit</th></tr>')
        for label, key, unit in rows:
            out.append(f"<tr><td><code>{html.escape(label)}</code></td>{_num_cell(report, key)}"
                       f"<td>{html.escape(unit)}</td></tr>")
        out.append("</table>")
        motion = report["spec"].get("motion", [])
        out.append("<h3>Motion program</h3>")
        out.append('<table class="motion"><tr><th>#</th><th>kind</th><th>from [deg]</th><th>span [deg]</th>'
                   f"<th>lift [{html.escape(units)}]</th><th>law</th><th>junctions</th></tr>")
        start = 0.0
        for i, seg in enumerate(motion):
            cells = []
            for f in ("angle", "lift", "law", "junctions"):
                key = f"spec.motion.{i}.{f}"
                cells.append(_num_cell(report, key) if _has(report, key) else "<td>—</td>")
            out.append(f"<tr><td>{i}</td><td>{html.escape(str(seg.get('kind')))}</td>"
                       f'<td class="num">{start:g}</td>{"".join(cells)}</tr>')
            start += float(seg.get("angle", 0.0))
        out.append("</table>")
    out.append("<details><summary>The spec as TOML</summary><pre>" + html.escape(to_toml(spec)) +
               "</pre></details>")
    return "".join(out)


DRAWING_LABELS = {
    "file_version": "DXF version", "insunits": "$INSUNITS (4 = mm, 1 = inch)",
    "curves": "profile written as", "chord_tolerance": "chord tolerance",
    "profile_entities": "PROFILE entities", "profile_arcs": "PROFILE arcs", "profile_lines": "PROFILE lines",
    "profile_max_error": "PROFILE entities: max distance from the profile NURBS (two-sided, measured; "
                         "0 for a SPLINE, which is the NURBS data itself)",
    "profile_min_arc_radius": "smallest arc radius",
    "pitch_max_error": "PITCH entities: max distance from the pitch-curve NURBS",
    "profile_poles": "PROFILE SPLINE control points",
    "max_error_by_layer": "entities: max distance from the NURBS they stand for, by layer",
    "exact": "PROFILE is exact (the exact offset of the pitch curve, or the pitch curve itself)",
    "profile_curve": "the profile NURBS is",
    "profile_fit_error": "profile NURBS: max distance from the exact curve it was fitted to",
    "pitch_curve": "the pitch curve is",
}


def _drawing_section(report: Mapping[str, Any]) -> str:
    d = report["drawing"]
    out = ['<table class="kv"><tr><th>item</th><th>value</th></tr>']
    for k, v in d.items():
        label = DRAWING_LABELS.get(k, k.replace('_', ' '))
        for sub in (v if isinstance(v, Mapping) else [None]):     # a dict: one row per entry
            key = f"drawing.{k}" + (f".{sub}" if sub is not None else "")
            out.append(f"<tr><td>{html.escape(label + (f': {sub}' if sub is not None else ''))}</td>"
                       f"{_num_cell(report, key)}</tr>")
    out.append("</table>")
    spline = {"spline": "The SPLINE on PROFILE carries the degree, knots, control points and weights of the "
                        "profile NURBS" + (f" (the {html.escape(str(d['profile_curve']))})"
                                           if d.get("profile_curve") else "") + ".",
              "cubic": "The SPLINEs are polynomial cubics within the chord tolerance of the NURBS: every DXF "
                       "reader draws them."}.get(str(d.get("curves")), "")
    out.append('<p class="note">Layers: PROFILE, PITCH, BASE_CIRCLE, PRIME_CIRCLE, BORE, CENTERLINES, '
               f"DIMENSIONS, TITLE (title block with the key numbers, the checks verdict and the motion "
               f"table). {spline}</p>")
    return "".join(out)


def _files_section(report: Mapping[str, Any]) -> str:
    out = ["<table><tr><th>file</th><th>content</th></tr>"]
    for k, v in report["files"].items():
        names = v if isinstance(v, list) else [v]
        for n in names:
            out.append(f"<tr><td><code>{html.escape(str(n))}</code></td><td>{html.escape(k)}</td></tr>")
    out.append("</table>")
    return "".join(out)


def _history(report: Mapping[str, Any]) -> tuple[np.ndarray, np.ndarray, np.ndarray | None] | None:
    opt = report.get("optimise")
    if not isinstance(opt, Mapping) or not isinstance(opt.get("history"), list) or not opt["history"]:
        return None
    h = [x for x in opt["history"] if isinstance(x, Mapping) and isinstance(x.get("objective"), (int, float))]
    if not h:
        return None
    it = np.array([x.get("iteration", i) for i, x in enumerate(h)], dtype=float)
    obj = np.array([x["objective"] for x in h], dtype=float)
    viol = None
    if all(isinstance(x.get("max_violation"), (int, float)) for x in h):
        viol = np.array([x["max_violation"] for x in h], dtype=float)
    return it, obj, viol


# ---- SVG -----------------------------------------------------------------------------------
_ID = re.compile(r'id="([^"]+)"')
_REF = re.compile(r'(id="|url\(#|href="#)([^"\)]+)')


def _inline_svg(svg: str, prefix: str) -> str:
    """Matplotlib's SVG made fit for inlining: no XML prolog, scalable, and its ids made
    unique per figure (several figures define the same glyph and clip ids)."""
    svg = svg[svg.index("<svg"):]
    ids = set(_ID.findall(svg))

    def scoped(m: re.Match) -> str:
        return m.group(1) + (f"{prefix}-{m.group(2)}" if m.group(2) in ids else m.group(2))

    svg = _REF.sub(scoped, svg)
    head_end = svg.index(">")
    head = re.sub(r'\s(width|height)="[^"]*"', "", svg[:head_end])
    return head + ' class="plot" role="img"' + svg[head_end:]

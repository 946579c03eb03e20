"""``report.html``: the design report as one self-contained file (inline SVG figures, inline
CSS, no scripts, nothing loaded from elsewhere), and on request the same figures as PNG files.

Each figure is a :class:`~cam_workbench.exporters.chart.Chart` built from the design's numbers,
drawn once as SVG (:mod:`cam_workbench.exporters.chart_svg`, no matplotlib); a PNG is that SVG
rasterised (:mod:`cam_workbench.exporters.chart_png`).

Every number in a table is the value of ``report.json`` at the path in the cell's
``data-key`` (``data-value`` holds it exactly, the text shows it to 6 digits), so the
page and the JSON cannot disagree (the cells: :mod:`cam_workbench.exporters.report_cells`).
This module draws the figures and assembles the page; each section is one view of
:mod:`cam_workbench.exporters.report_sections` (``VIEWS``, in page order).

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
from dataclasses import dataclass
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from cam_workbench.generators import __version__
from cam_workbench.generators.kinds import drawing_title
from cam_workbench.generators.bodies.conjugate import roller_distance_error
from cam_workbench.generators.cam_design import CamDesign
from cam_workbench.generators.checks.design import StateModel, check_samples
from cam_workbench.generators.checks.claims import pitch_text, profile_claim
from cam_workbench.generators.machining.interpolator import interpolator_accuracy
from cam_workbench.generators.spec.params import unit_name

from . import chart_png, chart_svg, interpolator_plots, plots, plots_dynamics
from .chart import Chart
from .report_cells import check_result
from .report_pages import REPORT_PAGES
from .report_sections import PageData, page_sections


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
    """One figure of the report: its key (file ``plot_<key>.png``, element ``fig-<key>``) and the
    function making its chart."""

    key: str
    title: str
    caption: str
    make: Callable[[], Chart]

    @property
    def png_name(self) -> str:
        return f"plot_{self.key}.png"


FORCE_STRESS_KEYS = ("contact_force", "contact_stress")


def report_plots(design: CamDesign, report: Mapping[str, Any],
                 series: Mapping[str, Series] | None = None, dynamics: Any = None) -> list[Plot]:
    """The figures this report will have, in order (optional ones only with their data);
    ``dynamics``: the :class:`cam_workbench.generators.dynamics.DynamicsResult` behind ``report["dynamics"]``."""
    return (_design_plots(design, report) + _force_plots(design, series or {})
            + _interpolator_plots(design, report) + _dynamics_plots(design, report, dynamics)
            + _conjugate_plots(design, report) + _convergence_plots(report))


def _ticks(design: CamDesign) -> str:
    """What the deviation figures' ticks mark."""
    return "PH junctions" if design.pitch.exact else "B-spline knots"


def _design_plots(design: CamDesign, report: Mapping[str, Any]) -> list[Plot]:
    """The figures every report has: the cam, the motion, the pressure angle, the curvature and
    the interpolation error."""
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
    ticks = _ticks(design)
    return [
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
             f"{360 / design.pitch.deviation_count():.3g}°; ticks: {ticks}.",
             lambda: plots.deviation_figure(design)),
    ]


def _force_plots(design: CamDesign, series: Mapping[str, Series]) -> list[Plot]:
    """Contact force and Hertz stress over the cycle, when the report has their series."""
    out: list[Plot] = []
    panels = [series[k] for k in FORCE_STRESS_KEYS if k in series]
    if panels:
        out.append(Plot(
            "force_stress", "Contact force and stress",
            "Over the cycle: " + "; ".join(f"{p.label} [{p.unit}]" for p in panels) +
            ". Dashed: the allowed value.",
            lambda: plots.series_figure(
                [(p.theta_deg, p.values, f"{p.label} [{p.unit}]", p.limit, p.limit_kind) for p in panels],
                design)))
    return out


def _interpolator_plots(design: CamDesign, report: Mapping[str, Any]) -> list[Plot]:
    """The follower motion the machining commands give, and their displacement error."""
    u = design.spec.units
    fol = design.follower.describe()
    small = plots.small_unit(u, design.follower.lift_unit)[1]
    ph = design.pitch.exact
    ticks = _ticks(design)
    out: list[Plot] = []
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
    return out


def _dynamics_plots(design: CamDesign, report: Mapping[str, Any], dynamics: Any) -> list[Plot]:
    """The follower train at speed and the jump speed, with the DynamicsResult behind report.json's section."""
    u = design.spec.units
    out: list[Plot] = []
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
            lambda: plots_dynamics.dynamics_figure(dynamics, dyn)))
        if isinstance(dyn.get("jump_speed"), Mapping):
            out.append(Plot(
                "jump_speed", "Jump speed",
                "The smallest contact force over a revolution of the periodic steady state against the cam "
                "speed (the sweep of dynamics.sweep_points speeds); the jump speed is where it first reaches 0 "
                "(refined by Brent's method between two speeds of the sweep). Lines: the analysis speed, the jump "
                "speed and the rigid follower's.",
                lambda: plots_dynamics.jump_speed_figure(dynamics, dyn)))
    return out


def _conjugate_plots(design: CamDesign, report: Mapping[str, Any]) -> list[Plot]:
    """A conjugate pair: both cams, and the distance error between the rollers."""
    small = plots.small_unit(design.spec.units, design.follower.lift_unit)[1]
    out: list[Plot] = []
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
    return out


def _convergence_plots(report: Mapping[str, Any]) -> list[Plot]:
    """The optimiser's convergence, when report.json's ``optimise`` has a history."""
    out: list[Plot] = []
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


def optional_series(design: CamDesign) -> dict[str, Series]:
    """θ-series for the report's "Contact force and stress" figure: the driving force
    (thesis Eq. 3.5) and Hertz stress (Eq. 3.6) from the design checks' state model, when the
    spec gives the follower a load (preload, spring or mass); otherwise nothing."""
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


@REPORT_PAGES.register(CamDesign)
class PlanePage:
    """A plane cam's report page (:func:`render_report`): its figures (:func:`report_plots`, the
    contact force and stress with :func:`optional_series`) known before it is drawn."""

    def __init__(self, design: CamDesign, summary: Mapping[str, Any], dynamics: Any = None) -> None:
        self.design, self.dynamics = design, dynamics
        self.series = optional_series(design)
        self.figures = [p.png_name for p in report_plots(design, summary, self.series, dynamics)]

    def render(self, report: dict[str, Any], progress: Callable[[str], None] | None, pngs: bool = False
               ) -> tuple[str, dict[str, bytes]]:
        return render_report(self.design, report, self.series, progress=progress, dynamics=self.dynamics,
                             pngs=pngs)


def render_report(design: CamDesign, report: Mapping[str, Any], series: Mapping[str, Series] | None = None,
                  *, progress: Callable[[str], None] | None = None,
                  dynamics: Any = None, pngs: bool = False) -> tuple[str, dict[str, bytes]]:
    """The HTML text and, with ``pngs``, the figures as PNG files ({name: bytes}).

    Args:
        design: the designed cam (for the figures).
        report: the report.json content (as written: parse the JSON text, so the HTML
            shows exactly what the file holds).
        series: optional θ-series (see the module docstring).
        progress: called with each figure's title before it is drawn.
        dynamics: the DynamicsResult behind ``report["dynamics"]`` (its figures).
        pngs: rasterise each figure's SVG to PNG too.

    Raises:
        MissingDependency: ``pngs`` without CairoSVG.
    """
    figures: dict[str, str] = {}
    files: dict[str, bytes] = {}
    plot_list = report_plots(design, report, series, dynamics)
    for p in plot_list:
        if progress is not None:
            progress(p.title)
        figures[p.key] = chart_svg.svg(p.make(), p.key)
        if pngs:
            files[p.png_name] = chart_png.png_bytes(figures[p.key])
    return _page(design, report, plot_list, figures), files


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
    """The page: title, the line under it, the navigation and the sections
    (:func:`cam_workbench.exporters.report_sections.page_sections`)."""
    spec = design.spec
    dr = spec.drawing
    u = report.get("units", spec.units)
    fig = {p.key: _figure(p, figures[p.key]) for p in plot_list}
    sections = page_sections(PageData(spec, report, fig))
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

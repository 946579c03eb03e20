"""Figures of a designed cam as data: each function returns a :class:`.chart.Chart` (panels of
curves, filled loops, lines and notes in data coordinates) that :mod:`.chart_svg` draws — no
plotting library is loaded to build one.

Figures take plain results from ``generators`` (a :class:`CamDesign`, arrays) and never
compute geometry themselves beyond sampling it.  Angles on the axes are cam degrees
from the program start; lengths are in the spec's units.  The follower dynamics' figures are
in :mod:`.plots_dynamics`.

==============================  =======================================================
figure                          what it shows
==============================  =======================================================
:func:`cam_figure`              cam drawing beside s, v, a, j (the README picture)
:func:`cam_drawing_figure`      the cam with its pitch curve, circles and the follower
:func:`cam_panel`               that drawing as one panel (for a figure of several)
:func:`conjugate_figure`        a conjugate pair: both cams, pitch curves and rollers
:func:`roller_distance_figure`  a conjugate pair's lift errors and the distance error between the rollers
:func:`kinematics_figure`       s, v, a, j over the cycle at the spec's speed
:func:`pressure_angle_figure`   φ(θ) (thesis Eq. 3.4) and the built curve's φ
:func:`curvature_figure`        radius of curvature of pitch curve and profile (Eq. 3.7)
:func:`deviation_figure`        interpolation error s_actual − s (paper Fig. 5/7)
:func:`series_figure`           any θ-series (contact force, Hertz stress …) with limits
:func:`convergence_figure`      an optimiser's objective and constraint violation
:func:`picture`                 the figure that shows a designed cam at a glance (the API's picture in Jupyter)
==============================  =======================================================
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Callable, Mapping, Sequence

import numpy as np

from cam_workbench.generators.cam_design import CamDesign
from cam_workbench.generators.checks.design import limit_sign
from cam_workbench.generators.kinds import body_of
from cam_workbench.generators.kinds.by_class import ByClass
from cam_workbench.generators.motion import MotionProgram

from .chart import Area, Chart, Curve, Mark, Note, Panel, Rule, angle_panel, css_color, segment_marks

if TYPE_CHECKING:
    from cam_workbench.generators.bodies.conjugate import RollerDistanceError

SERIES_COLORS = ("#2e7d32", "#c0392b", "#6a1b9a", "#1f3b5c")
COLORS = {"profile": "#1f3b5c", "pitch": "#c0392b", "follower": "#8a6212", "s": "#1f3b5c",
          "v": "#2e7d32", "a": "#c0392b", "j": "#6a1b9a", "built": "#e67e22", "limit": "#b03a2e",
          "fail": "#c0392b", "pass": "#1e8449"}
#: the filled cam (material) and the cam's cuts, the follower's roller
MATERIAL = "#b8c7d9"
ROLLER_FILL = "#e6b85c"
BLACK = "#000000"

#: SVG ids (a mark's ``gid``) of the drawn check limits and check points, for readers of the
#: figure: ``limit-<check>`` (``-upper``/``-lower`` for a ± limit) and ``point-<check>``
LIMIT_GID = "limit-{name}"
POINT_GID = "point-{name}"

#: width [pt] of a chart of stacked line panels and of a drawing; a drawing panel's height [pt]
LINE_WIDTH = 640.0
DRAWING_WIDTH = 480.0
DRAWING_HEIGHT = 420.0
#: the room [pt] a panel's tick labels and axis label take from its share of the figure's height
_MARGIN = 30.0
THETA_LABEL = "cam angle θ [deg]"
#: line width [pt] of a follower's segment by its role
SEGMENT_WIDTHS = {"stem": 3.0, "arm": 3.0, "face": 2.2, "yoke": 3.0}


def _height(inches: float, rows: int = 1) -> float:
    """A panel's height [pt]: its share of a figure ``inches`` tall with ``rows`` panels."""
    return round(inches * 72.0 / rows - _MARGIN)


def _is_ph(design: CamDesign) -> bool:
    """The pitch curve has exact offsets (a PH spline: ``exact``)."""
    return design.pitch.exact


def _pitch_words(design: CamDesign) -> str:
    return "PH quintic spline" if _is_ph(design) else "fitted B-spline"


def _xy(z: np.ndarray) -> np.ndarray:
    """Complex points → N×2."""
    z = np.asarray(z, dtype=complex)
    return np.column_stack([z.real, z.imag])


_T = np.linspace(0, 2 * np.pi, 400)


def _circle(radius: float, centre: complex = 0j) -> np.ndarray:
    """A circle as N×2 points."""
    return _xy(centre + radius * np.exp(1j * _T))


def _line(xy: np.ndarray, **style: Any) -> Curve:
    """A Curve through N×2 points."""
    return Curve(xy[:, 0], xy[:, 1], **style)


def _dot(x: float, y: float, **style: Any) -> Curve:
    """A single marker at (x, y) (``marker`` "o" unless given)."""
    style.setdefault("marker", "o")
    return Curve(np.array([float(x)]), np.array([float(y)]), line=False, **style)


def _cycle_panel(program: MotionProgram | None, *, labels: bool = False, last: bool = True,
                 **kw: Any) -> Panel:
    """A panel over the cam cycle with the motion segments' boundaries (and, with ``labels``,
    their kinds on top); the x axis labelled on the ``last`` panel of a stack only."""
    if program is None:
        rules: list[Rule] = []
        tops: list[tuple[float, str]] = []
    else:
        rules, tops = segment_marks(np.rad2deg(program.boundaries), program.kinds if labels else None)
    panel = angle_panel(xlabel=THETA_LABEL if last else "", xticklabels=last, top_labels=tops, **kw)
    panel.add(*rules)
    return panel


def _side_note(x: float, y: float, text: str, size: float = 8.0, color: str = "#1c2833") -> Note:
    """``text`` beside the point (x, y): right of it, or left of it in the cycle's last third."""
    right = x > 240
    return Note(x, y, text, color=color, size=size, dx=-8 if right else 8, dy=0,
                anchor="end" if right else "start", valign="middle")


# ---- the cam -----------------------------------------------------------------------------
def cam_panel(design: CamDesign, follower_angle_deg: float = 75.0) -> Panel:
    """The cam in its own frame: profile (filled), pitch (or contact) curve, prime and base
    circles, bore, and the follower — roller, stem, arm and pivot, or face, as the follower
    draws itself (:meth:`cam_workbench.generators.followers.base.Follower.sketch`) — where it is at
    ``follower_angle_deg`` of cam rotation."""
    spec = design.spec
    u = spec.units
    fol = design.follower
    desc = fol.describe()
    flat = fol.design_curve == "profile"
    _, prof = design.profile.sample(32)
    _, pitch = design.pitch_nurbs.sample(32)
    rr = fol.profile_offset
    if flat:
        prof_label = f"cam (profile = {'PH spline' if _is_ph(design) else 'fitted B-spline'} through the contact points)"
    elif _is_ph(design):
        prof_label = "cam (exact offset NURBS profile)" if rr > 0 else "cam (profile = PH pitch curve)"
    else:
        prof_label = "cam (fitted offset B-spline profile)" if rr > 0 else "cam (profile = fitted B-spline)"
    body = design.body
    drawn_body = body is not None and not body.plain_plate
    marks: list[Mark] = []
    if drawn_body:
        marks.extend(_body_top(design, prof_label))
    else:
        marks.append(Area([prof[:, :2]], fill=MATERIAL, edge=COLORS["profile"], width=1.2, label=prof_label))
    rb = spec.cam.base_radius
    if not flat:
        marks.append(_line(_circle(rb), color=css_color("0.45"), width=0.8, dash=":", label="prime circle"))
    if rr > 0 or flat:
        marks.append(_line(_circle(rb - rr), color=css_color("0.6"), width=0.6, dash="-.", label="base circle"))
    if spec.cam.bore_diameter > 0 and not drawn_body:
        marks.append(Area([_circle(spec.cam.bore_diameter / 2)], fill="white", edge=COLORS["profile"], width=1.0))
    marks.append(_dot(0.0, 0.0, marker="+", color=BLACK, size=10))
    th = np.deg2rad(follower_angle_deg)
    k = design.program.evaluate(np.array([th]))
    lift_len = spec.max_lift * (rb * fol.lift_scale if fol.lift_unit == "angle" else 1.0)
    sk = fol.sketch(th, k, lift_len + 2 * max(rr, 0.1 * rb), spec.follower.face_width)
    for c, r in sk.circles:
        marks.append(Area([_circle(r, c)], fill=ROLLER_FILL, alpha=0.9))
        marks.append(_line(_circle(r, c), color=COLORS["follower"], width=1.0))
    label: str | None = f"follower at θ = {follower_angle_deg:g}°"
    for a, b, role in sk.segments:
        marks.append(_line(_xy(np.array([a, b])), color=COLORS["follower"], width=SEGMENT_WIDTHS[role], label=label))
        label = None
    if not flat:
        marks.append(_line(pitch[:, :2], color=COLORS["pitch"], width=0.9, dash="--",
                           label=f"pitch curve ({_pitch_words(design)})"))
    if sk.pivot is not None:
        marks.append(_dot(sk.pivot.real, sk.pivot.imag, size=7, face="white", edge=COLORS["follower"], edge_width=1.5,
                          color=COLORS["follower"], label="pivot"))
    marks.append(_dot(sk.point.real, sk.point.imag, color=COLORS["pitch"], size=3))
    title = (f"{spec.cam.body} cam, {desc['label']} {u}\n"
             + (f"M = {design.pitch.M} PH segments" if _is_ph(design) else f"{design.pitch.M} B-spline knot spans"))
    return Panel(marks, xlabel=f"x [{u}]", ylabel=f"y [{u}]", title=title, equal=True, legend="lower left",
                 height=DRAWING_HEIGHT)


def _body_top(design: CamDesign, prof_label: str) -> list[Area]:
    """The body seen from +Z: every prism region that reaches the top face, in the body's order —
    material filled, cuts (a groove between its walls, the bore with its keyway, holes, the timing
    mark) white — each prism's outer loop and holes one even-odd area; the first material region
    labelled as the body draws itself (a groove's walls as the exact offsets they are)."""
    body = design.body
    top = body.z_range[1]
    out: list[Area] = []
    first_add = True
    for prism in body.prisms:
        if not prism.z0 < top <= prism.z1 + 1e-12:
            continue
        loops = [_xy(prism.outer.points())] + [_xy(h.points()) for h in prism.holes]
        add = prism.op == "add"
        label = None
        if add and first_add:
            label = body_of(design.spec).drawing_label or prof_label
            first_add = False
        out.append(Area(loops, fill=MATERIAL if add else "white", edge=COLORS["profile"], width=1.0, label=label))
    return out


def cam_drawing_figure(design: CamDesign, follower_angle_deg: float = 75.0) -> Chart:
    """The cam with the follower (see :func:`cam_panel`)."""
    return Chart.stack([cam_panel(design, follower_angle_deg)], width=DRAWING_WIDTH)


def conjugate_figure(design: CamDesign, second: CamDesign, follower_angle_deg: float = 75.0) -> Chart:
    """A conjugate pair seen from +Z: the first cam (filled) over the second (below it, outlined
    in orange), both pitch curves, and the follower at ``follower_angle_deg`` with both rollers —
    the yoke joining them, or both arms on their pivot."""
    spec = design.spec
    u = spec.units
    _, p1 = design.profile.sample(32)
    _, p2 = second.profile.sample(32)
    marks: list[Mark] = [
        Area([p2[:, :2]], fill="#f3d9b1", edge="#a05a00", width=1.1, label="second cam (below the first)"),
        Area([p1[:, :2]], fill=MATERIAL, alpha=0.85, label="first cam"),
        _line(p1[:, :2], color=COLORS["profile"], width=1.2),
    ]
    for d, style, name in ((design, "--", "first"), (second, "-.", "second")):
        _, q = d.pitch_nurbs.sample(32)
        marks.append(_line(q[:, :2], color=COLORS["pitch"], width=0.8, dash=style, label=f"{name} pitch curve (PH)"))
    if spec.cam.bore_diameter > 0:
        marks.append(Area([_circle(spec.cam.bore_diameter / 2)], fill="white", edge=COLORS["profile"], width=1.0))
    th = np.deg2rad(follower_angle_deg)
    k = design.program.evaluate(np.array([th]))
    size = spec.max_lift * (spec.cam.base_radius * design.follower.lift_scale
                            if design.follower.lift_unit == "angle" else 1.0) + 2 * design.follower.profile_offset
    label: str | None = f"follower at θ = {follower_angle_deg:g}°"
    for fol in (design.follower, second.follower):
        sk = fol.sketch(th, k, size)
        for c, r in sk.circles:
            marks.append(Area([_circle(r, c)], fill=ROLLER_FILL, alpha=0.9))
            marks.append(_line(_circle(r, c), color=COLORS["follower"], width=1.0))
        for a, b, _role in sk.segments:
            marks.append(_line(_xy(np.array([a, b])), color=COLORS["follower"], width=3.0, label=label))
            label = None
        if sk.pivot is not None:
            marks.append(_dot(sk.pivot.real, sk.pivot.imag, size=7, face="white", edge=COLORS["follower"],
                              width=1.5, color=COLORS["follower"]))
        marks.append(_dot(sk.point.real, sk.point.imag, color=COLORS["pitch"], size=3))
    marks.append(_dot(0.0, 0.0, marker="+", color=BLACK, size=10))
    title = (f"conjugate cams, {design.follower.describe()['label']} {u}\nand the "
             f"{second.follower.label()} {u}")
    panel = Panel(marks, xlabel=f"x [{u}]", ylabel=f"y [{u}]", title=title, equal=True, legend="lower left",
                  height=DRAWING_HEIGHT)
    return Chart.stack([panel], width=DRAWING_WIDTH)


def roller_distance_figure(design: CamDesign, error: RollerDistanceError) -> Chart:
    """A conjugate pair over the cycle: each built pitch curve's lift error s_actual − s (its PH
    deviation) and the distance error between the rollers that follows from them
    (:class:`cam_workbench.generators.bodies.conjugate.RollerDistanceError`), with the bound the two
    deviations set."""
    u = design.spec.units
    scale, unit = small_unit(u, design.follower.lift_unit)
    lscale, lunit = _small_length_scale(u)
    deg = np.rad2deg(error.theta)
    s = design.program.s(error.theta)
    h = _height(5.6, 2)
    top = _cycle_panel(design.program, labels=True, last=False, ylabel=f"lift error [{unit}]", legend="lower left",
                       height=h)
    top.add(Curve(deg, (error.s1 - s) * scale, color=COLORS["s"], width=0.8, label="first cam: s₁ − s"),
            Curve(deg, (error.s2 - s) * scale, color=COLORS["a"], width=0.8, label="second cam: s₂ − s"))
    bottom = _cycle_panel(design.program, ylabel=f"distance error [{lunit}]\n+ interference, − play", height=h)
    k = int(np.argmax(np.abs(error.distance)))
    x, y = float(deg[k]), float(error.distance[k] * lscale)
    bottom.add(Curve(deg, error.distance * lscale, color=COLORS["j"], width=0.9),
               _dot(x, y, size=4, color=COLORS["a"]),
               _side_note(x, y, f"max |error| = {abs(error.distance[k]) * lscale:.4g} {lunit} at {x:.2f}°"),
               Rule("y", 0.0, color=css_color("0.3"), width=0.6, dash="-"))
    return Chart.stack([top, bottom], width=LINE_WIDTH)


def _kinematic_series(design: CamDesign, n: int = 3601) -> tuple[np.ndarray, list[tuple[np.ndarray, str, str]]]:
    spec = design.spec
    u = "deg" if design.follower.lift_unit == "angle" else spec.units
    th = np.linspace(0, 2 * np.pi, n)
    k = design.program.evaluate(th)
    omega = spec.cam.speed_rpm * 2 * np.pi / 60
    return np.rad2deg(th), [(k.s, f"s [{u}]", "s"), (k.ds * omega, f"v [{u}/s]", "v"),
                            (k.d2s * omega**2, f"a [{u}/s²]", "a"), (k.d3s * omega**3, f"j [{u}/s³]", "j")]


def cam_figure(design: CamDesign, follower_angle_deg: float = 75.0) -> Chart:
    """Drawing of the cam (profile, pitch curve, base and prime circles, bore, the follower at
    ``follower_angle_deg`` of cam rotation) beside its s, v, a, j diagrams over one turn."""
    deg, series = _kinematic_series(design)
    motion = []
    for i, (y, label, key) in enumerate(series):
        last = i == len(series) - 1
        motion.append(angle_panel(
            marks=[Curve(deg, y, color=COLORS[key], width=1.0)], ylabel=label,
            xticks=list(np.arange(0.0, 361.0, 60.0)), xticklabels=last, xlabel=THETA_LABEL if last else "",
            title=f"follower motion at {design.spec.cam.speed_rpm:g} rpm" if i == 0 else "", height=95.0))
    return Chart([[cam_panel(design, follower_angle_deg)], motion], width=792.0, widths=(1.0, 1.25))


# ---- curves over the cycle -----------------------------------------------------------------
def kinematics_figure(design: CamDesign) -> Chart:
    """Displacement, velocity, acceleration and jerk of the follower over one turn at the
    spec's speed (design intent, closed-form laws), with the motion segments marked."""
    deg, series = _kinematic_series(design)
    panels = []
    for i, (y, label, key) in enumerate(series):
        panel = _cycle_panel(design.program, labels=i == 0, last=i == len(series) - 1, ylabel=label,
                             height=_height(7.5, 4))
        k = int(np.argmax(np.abs(y)))
        up = bool(y[k] > 0)
        panel.add(Curve(deg, y, color=COLORS[key], width=1.1),
                  _dot(deg[k], y[k], size=3, color=COLORS[key]),
                  Note(float(deg[k]), float(y[k]), f"max |{key}| = {abs(y[k]):.4g}", size=7, dx=6,
                       dy=-4 if up else 4, valign="top" if up else "bottom"))
        panels.append(panel)
    return Chart.stack(panels, width=LINE_WIDTH, title=f"follower motion at {design.spec.cam.speed_rpm:g} rpm")


def _check_point(name: str, check: Mapping[str, Any], y: float, text: str, below: bool) -> list[Mark]:
    """A check's value at its cam angle (red when it fails), labelled with the angle."""
    status = str(check.get("status"))
    fails = status == "fail"
    color = COLORS["fail"] if fails else COLORS["pass"]
    x = float(check["at_deg"])
    right = x > 240
    return [_dot(x, y, size=6, color=color, face=color, edge=BLACK, width=0.6, gid=POINT_GID.format(name=name)),
            Note(x, y, text + (" — FAILS" if fails else ""), color=color, size=8, dx=-10 if right else 10,
                 dy=-12 if below else 10, anchor="end" if right else "start", valign="top" if below else "bottom",
                 bold=fails, boxed=True)]


def pressure_angle_figure(design: CamDesign, limit_deg: float | None = None,
                          check: Mapping[str, Any] | None = None) -> Chart:
    """Pressure angle φ(θ) of the design (thesis Eq. 3.4) and of the built pitch curve
    (samples), with the allowed limit ±limit as dashed lines and the largest |φ| marked at
    its cam angle.

    Args:
        design: the designed cam.
        limit_deg: the limit [deg] when no ``check`` is given.
        check: report.json's ``checks.results.pressure_angle`` (value, at_deg, limit,
            status): its limit is drawn and its point marked (red when it fails), so the
            figure shows the numbers of the report.
    """
    th = np.linspace(0, 2 * np.pi, 3601)
    deg = np.rad2deg(th)
    phi = np.rad2deg(design.geometry.pressure_angle(design.program.evaluate(th)))
    at, phi_b = design.as_built_pressure_angles()
    order = np.argsort(at)
    if check is not None and check.get("limit") is not None:
        limit_deg = float(check["limit"])
    top = max(float(np.max(np.abs(phi))), limit_deg or 0.0) * 1.18
    panel = _cycle_panel(design.program, labels=True, ylabel="pressure angle φ [deg]", ylim=(-top, top),
                         legend="below", legend_columns=3, height=_height(3.8))
    panel.add(Curve(deg, phi, color=COLORS["s"], width=1.4, label="design (thesis Eq. 3.4)"),
              Curve(at[order][::24], phi_b[order][::24], color=COLORS["built"], line=False, marker="o", size=2.6,
                    face="none", width=0.7, label=f"built {_pitch_words(design)} (samples)"))
    if limit_deg is not None:
        for sgn, tag in ((1, "upper"), (-1, "lower")):
            panel.add(Rule("y", sgn * limit_deg, color=COLORS["limit"], width=1.0, dash="--",
                           gid=LIMIT_GID.format(name="pressure_angle") + "-" + tag,
                           label=f"limit |φ| ≤ {limit_deg:g}° (checks.max_pressure_angle)" if sgn > 0 else None),
                      # the limit's value outside the allowed band: above the upper line, below the lower
                      Note(2.0, sgn * limit_deg, f" {'+' if sgn > 0 else '−'}{limit_deg:g}°", color=COLORS["limit"],
                           size=7, dx=0, dy=0, valign="bottom" if sgn > 0 else "top"))
    if check is not None and check.get("value") is not None and check.get("at_deg") is not None:
        # the check reports |φ|; the curve is signed: mark it on the side where φ is
        x = float(check["at_deg"])
        sign = 1.0 if np.interp(x, deg, phi) >= 0 else -1.0
        y = sign * float(check["value"])
        panel.add(*_check_point("pressure_angle", check, y, f"max |φ| = {float(check['value']):.2f}° at {x:.2f}°",
                                y > 0))
    else:
        k = int(np.argmax(np.abs(phi)))
        x, y = float(deg[k]), float(phi[k])
        panel.add(_dot(x, y, size=4, color=COLORS["a"]),
                  _side_note(x, y, f"max |φ| = {abs(y):.2f}° at {x:.1f}°"))
    return Chart.stack([panel], width=LINE_WIDTH)


def curvature_figure(design: CamDesign, check: Mapping[str, Any] | None = None) -> Chart:
    """Signed radius of curvature (+ convex) of the pitch curve (thesis Eq. 3.7) and of the
    profile (ρ − roller radius), with the built curve's samples; the axis is clipped
    where the curve straightens (|ρ| → ∞).

    ``check`` is report.json's ``checks.results.curvature``: its limit (undercut factor ×
    roller radius, a lower bound on the convex pitch radius) is drawn dashed and its value
    marked at its cam angle (red when it fails)."""
    spec = design.spec
    u = spec.units
    rr = spec.roller_radius
    flat = design.follower.design_curve == "profile"
    th = np.linspace(0, 2 * np.pi, 3601)
    rho = design.follower.radius_of_curvature(design.program.evaluate(th))
    cs = design.curvature_samples
    order = np.argsort(cs.cam_angle_deg)
    convex = rho[rho > 0]
    concave = -rho[rho < 0]
    top = 3.0 * spec.cam.base_radius
    if convex.size:
        top = max(top, 1.3 * float(np.min(convex)) + rr)
    if concave.size:
        top = max(top, 1.3 * float(np.min(concave)) + rr)
    limit = None if check is None or check.get("limit") is None else float(check["limit"])
    if limit is not None:
        top = max(top, 1.3 * limit)
    deg = np.rad2deg(th)

    # outside ±top the curve is nearly straight: leave gaps instead of drawing ±∞ jumps
    def cut(r: np.ndarray) -> np.ndarray:
        return np.where(np.abs(r) <= top, r, np.nan)

    panel = _cycle_panel(design.program, labels=True, ylabel=f"radius of curvature [{u}]  (+ convex)",
                         ylim=(-top, top), legend="below", legend_columns=3, height=_height(3.8))
    panel.add(Curve(deg, cut(rho), color=COLORS["pitch"], width=1.3,
                    label="profile (the face's envelope)" if flat else "pitch curve"))
    if rr > 0:
        # offsetting inward by r shrinks convex radii and grows concave ones: ρ − r either way
        panel.add(Curve(deg, cut(rho - rr), color=COLORS["profile"], width=1.3, label="profile (ρ − roller radius)"))
    xs, ys = cs.cam_angle_deg[order][::12], cut(cs.radius[order][::12])
    shown = np.isfinite(ys)
    panel.add(Curve(xs[shown], ys[shown], color=css_color("0.35"), line=False, marker="o", size=2.4, face="none",
                    width=0.6, label=f"built {_pitch_words(design)} (samples)"))
    name = "cusp" if flat else "curvature"
    if limit is not None and check is not None:
        sign = limit_sign(name, str(check.get("kind", "min")))
        panel.add(Rule("y", limit, color=COLORS["limit"], width=1.0, dash="--", gid=LIMIT_GID.format(name=name),
                       label=(f"cusp limit: ρ {sign} {limit:g} {u}" if flat else
                              f"curvature limit: convex pitch ρ {sign} {limit:g} {u} "
                              f"({spec.checks.undercut_factor:g} × roller radius)")))
    if rr > 0:
        panel.add(Rule("y", rr, color=css_color("0.45"), width=0.9, dash=":", gid=LIMIT_GID.format(name="undercut"),
                       label=f"roller radius {rr:g} {u} (undercut below)"))
    panel.add(Rule("y", 0.0, color=css_color("0.3"), width=0.6, dash="-"))
    if check is not None and check.get("value") is not None and check.get("at_deg") is not None:
        v = float(check["value"])
        panel.add(*_check_point(name, check, v, f"min {'' if flat else 'convex pitch '}ρ = {v:.4g} {u} at "
                                f"{float(check['at_deg']):.2f}°", False))
    elif convex.size:
        k = int(np.argmin(np.where(rho > 0, rho, np.inf)))
        x, y = float(deg[k]), float(rho[k])
        panel.add(_dot(x, y, size=4, color=COLORS["pitch"]),
                  Note(x, y, f"min convex ρ = {y:.4g} {u} at {x:.1f}°", size=8, dx=8, dy=-10, valign="bottom"))
    return Chart.stack([panel], width=LINE_WIDTH)


def _small_length_scale(units: str) -> tuple[float, str]:
    return (1e3, "µm") if units == "mm" else (1e6, "µin")


def small_unit(units: str, lift_unit: str = "length") -> tuple[float, str]:
    """(factor, unit) in which lift errors are shown: µm/µin, or arc seconds for an arm's angle."""
    return (3600.0, "arcsec") if lift_unit == "angle" else _small_length_scale(units)


def deviation_figure(design: CamDesign) -> Chart:
    """Interpolation error s_actual(θ) − s(θ) of the built pitch curve (paper Eq. 13,
    as the paper's Figs. 5 and 7), with the PH junction (or B-spline knot) angles marked."""
    th, dev = design.pitch.deviation()
    scale, unit = small_unit(design.spec.units, design.follower.lift_unit)
    deg = np.rad2deg(th)
    k = int(np.argmax(np.abs(dev)))
    x, y = float(deg[k]), float(dev[k] * scale)
    j = np.rad2deg(design.pitch.angles)
    panel = _cycle_panel(design.program, labels=True, ylabel=f"s_actual − s [{unit}]", legend="lower left",
                         height=_height(3.4))
    panel.add(Curve(deg, dev * scale, color=COLORS["s"], width=0.8),
              _dot(x, y, size=4, color=COLORS["a"]),
              Note(x, y, f"max |s_actual − s| = {abs(y):.4g} {unit} at {x:.2f}°", size=8, dx=8, dy=0),
              Curve(j, np.zeros_like(j), color=css_color("0.4"), line=False, marker="|", size=5,
                    label=(f"PH junctions (M = {design.pitch.M})" if _is_ph(design)
                           else f"B-spline knots ({design.pitch.M} spans)")))
    return Chart.stack([panel], width=LINE_WIDTH)


def series_figure(panels: Sequence[tuple[np.ndarray, np.ndarray, str, float | None, str | None]],
                  design: CamDesign | None = None) -> Chart:
    """Stacked θ-series, one panel each: (θ [deg], values, y label, limit or None, limit kind
    "max"/"min" or None) — e.g. contact force and Hertz stress with their allowed values."""
    n = len(panels)
    program = None if design is None else design.program
    out = []
    for i, (deg, y, label, limit, kind) in enumerate(panels):
        panel = _cycle_panel(program, labels=i == 0, last=i == n - 1, ylabel=label,
                             height=_height(2.6 * n + 0.6, n))
        panel.add(Curve(np.asarray(deg, dtype=float), np.asarray(y, dtype=float),
                        color=SERIES_COLORS[i % len(SERIES_COLORS)], width=1.1))
        if limit is not None:
            panel.add(Rule("y", float(limit), color=COLORS["limit"], width=0.9, dash="--",
                           text=f" {kind or 'limit'} {limit:.4g}"))
        out.append(panel)
    return Chart.stack(out, width=LINE_WIDTH)


def convergence_figure(iterations: np.ndarray, objective: np.ndarray, objective_label: str,
                       violation: np.ndarray | None = None) -> Chart:
    """An optimiser's history: objective per iteration and, when given, the largest
    constraint violation (log scale; ≤ 0 shown at the bottom as satisfied)."""
    rows = 2 if violation is not None else 1
    h = _height(2.6 * rows + 0.4, rows)
    it = np.asarray(iterations, dtype=float)
    panels = [Panel([Curve(it, np.asarray(objective, dtype=float), color=COLORS["s"], width=1.0, marker="o",
                           size=2.5)], ylabel=objective_label, xticklabels=rows == 1, height=h)]
    if violation is not None:
        floor = 1e-12
        v = np.maximum(np.asarray(violation, dtype=float), floor)
        panels.append(Panel([Curve(it, v, color=COLORS["a"], width=1.0, marker="o", size=2.5)],
                            ylabel="max constraint violation", logy=True, height=h))
    panels[-1].xlabel = "iteration"
    return Chart.stack(panels, width=LINE_WIDTH)


#: the figure that shows a design at a glance, ``fn(design, follower_angle_deg) -> Chart``, by the
#: design's class (:func:`picture`): the plane cams' here, a body's own in its module
PICTURES: ByClass[Callable[..., Chart]] = ByClass("the cam's picture")
PICTURES.register(CamDesign)(cam_figure)


def picture(design: object, follower_angle_deg: float = 75.0) -> Chart | None:
    """The figure that shows a designed cam at a glance — the Python API's picture in Jupyter:
    a cam of plane curves beside its motion (:func:`cam_figure`), a cylindrical cam's cylinder
    beside its developed view (:func:`cam_workbench.exporters.plots_cylindrical.cylindrical_figure`)
    — or None for a design of a class nothing registered in :data:`PICTURES`."""
    figure = PICTURES.for_class(type(design))
    return None if figure is None else figure(design, follower_angle_deg)

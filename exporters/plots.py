"""Matplotlib figures of a designed cam (Agg backend, written atomically as PNG or SVG).

Figures take plain results from ``generators`` (a :class:`CamDesign`, arrays) and never
compute geometry themselves beyond sampling it.  Angles on the axes are cam degrees
from the program start; lengths are in the spec's units.

=========================  =======================================================
figure                     what it shows
=========================  =======================================================
:func:`cam_figure`         cam drawing beside s, v, a, j (the README picture)
:func:`cam_drawing_figure` the cam with its pitch curve, circles and the follower
:func:`conjugate_figure`   a conjugate pair: both cams, pitch curves and rollers
:func:`roller_distance_figure`  a conjugate pair's lift errors and the distance error between the rollers
:func:`kinematics_figure`  s, v, a, j over the cycle at the spec's speed
:func:`pressure_angle_figure`  φ(θ) (thesis Eq. 3.4) and the built curve's φ
:func:`curvature_figure`   radius of curvature of pitch curve and profile (Eq. 3.7)
:func:`deviation_figure`   interpolation error s_actual − s (paper Fig. 5/7)
:func:`series_figure`      any θ-series (contact force, Hertz stress …) with limits
:func:`convergence_figure` an optimiser's objective and constraint violation
:func:`dynamics_figure`    contact force, camshaft torque and displacement error at speed
:func:`jump_speed_figure`  smallest contact force against the cam speed (the jump speed)
:func:`picture`            the figure that shows a designed cam at a glance (the API's picture in Jupyter)
=========================  =======================================================
"""
from __future__ import annotations

import io
import os
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from cam_workbench.generators.cam_design import CamDesign
from cam_workbench.generators.checks.design import limit_sign
from cam_workbench.generators.kinds import body_of
from cam_workbench.generators.kinds.by_class import ByClass

from .atomic import atomic_path

SERIES_COLORS = ("#2e7d32", "#c0392b", "#6a1b9a", "#1f3b5c")
COLORS = {"profile": "#1f3b5c", "pitch": "#c0392b", "follower": "#8a6212", "s": "#1f3b5c",
          "v": "#2e7d32", "a": "#c0392b", "j": "#6a1b9a", "built": "#e67e22", "limit": "#b03a2e",
          "fail": "#c0392b", "pass": "#1e8449"}

#: SVG ids (matplotlib ``gid``) of the drawn check limits and check points, for readers of the
#: SVG: ``limit-<check>`` (``-upper``/``-lower`` for a ± limit) and ``point-<check>``
LIMIT_GID = "limit-{name}"
POINT_GID = "point-{name}"


def _is_ph(design: CamDesign) -> bool:
    """The pitch curve has exact offsets (a PH spline: ``exact``)."""
    return design.pitch.exact


def _pitch_words(design: CamDesign) -> str:
    return "PH quintic spline" if _is_ph(design) else "fitted B-spline"


def _plt() -> Any:
    import matplotlib  # deferred: matplotlib, loaded when a figure is drawn

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # deferred: matplotlib, loaded when a figure is drawn

    return plt


def save_figure(fig: Any, path: str | os.PathLike[str], dpi: int = 150) -> Path:
    """Save a figure atomically; the format follows the suffix (.png, .svg, .pdf)."""
    target = Path(path)
    with atomic_path(target) as tmp:
        fig.savefig(tmp, dpi=dpi, format=target.suffix.lstrip(".") or "png", bbox_inches="tight")
    _plt().close(fig)
    return target


def figure_bytes(fig: Any, fmt: str, dpi: int = 150) -> bytes:
    """The figure as PNG or SVG bytes (SVG text keeps glyphs as paths: no font files needed)."""
    import matplotlib  # deferred: matplotlib, loaded when a figure is drawn

    buf = io.BytesIO()
    with matplotlib.rc_context({"svg.fonttype": "path", "svg.hashsalt": "cam_workbench"}):
        fig.savefig(buf, format=fmt, dpi=dpi, bbox_inches="tight", metadata=_metadata(fmt))
    return buf.getvalue()


def close(fig: Any) -> None:
    _plt().close(fig)


def _metadata(fmt: str) -> dict[str, Any]:
    # no creation dates: the same design gives the same files
    if fmt == "svg":
        return {"Date": None, "Creator": "cam_workbench"}
    if fmt == "png":
        return {"Software": "cam_workbench"}
    return {}


def _segment_marks(ax: Any, design: CamDesign, labels: bool = False) -> None:
    """Thin vertical lines at the motion-segment boundaries (and their kinds on top)."""
    prog = design.program
    b = np.rad2deg(prog.boundaries)
    for x in b[1:-1]:
        ax.axvline(x, color="0.75", lw=0.6, zorder=0)
    if labels:
        for k, kind in enumerate(prog.kinds):
            ax.text(0.5 * (b[k] + b[k + 1]), 1.02, kind, transform=ax.get_xaxis_transform(),
                    ha="center", va="bottom", fontsize=7, color="0.35")


def _angle_axis(ax: Any, last: bool = True) -> None:
    ax.set_xlim(0, 360)
    ax.set_xticks(np.arange(0, 361, 30))
    ax.grid(alpha=0.25)
    ax.tick_params(labelsize=7)
    if last:
        ax.set_xlabel("cam angle θ [deg]", fontsize=8)
    else:
        ax.tick_params(labelbottom=False)


# ---- the cam -----------------------------------------------------------------------------
def draw_cam(ax: Any, design: CamDesign, follower_angle_deg: float = 75.0) -> None:
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
    if drawn_body:
        _draw_body_top(ax, design, prof_label)
    else:
        ax.fill(prof[:, 0], prof[:, 1], color="#b8c7d9", zorder=1, label=prof_label)
        ax.plot(prof[:, 0], prof[:, 1], color=COLORS["profile"], lw=1.2, zorder=2)
    if not flat:
        ax.plot(pitch[:, 0], pitch[:, 1], "--", color=COLORS["pitch"], lw=0.9, zorder=7,
                label=f"pitch curve ({_pitch_words(design)})")
    t = np.linspace(0, 2 * np.pi, 400)
    rb = spec.cam.base_radius
    if not flat:
        ax.plot(rb * np.cos(t), rb * np.sin(t), ":", color="0.45", lw=0.8, label="prime circle")
    if rr > 0 or flat:
        r0 = rb - rr
        ax.plot(r0 * np.cos(t), r0 * np.sin(t), "-.", color="0.6", lw=0.6, label="base circle")
    if spec.cam.bore_diameter > 0 and not drawn_body:
        rbore = spec.cam.bore_diameter / 2
        ax.fill(rbore * np.cos(t), rbore * np.sin(t), color="white", zorder=3)
        ax.plot(rbore * np.cos(t), rbore * np.sin(t), color=COLORS["profile"], lw=1.0, zorder=4)
    th = np.deg2rad(follower_angle_deg)
    k = design.program.evaluate(np.array([th]))
    lift_len = spec.max_lift * (rb * fol.lift_scale if fol.lift_unit == "angle" else 1.0)
    sk = fol.sketch(th, k, lift_len + 2 * max(rr, 0.1 * rb), spec.follower.face_width)
    label = f"follower at θ = {follower_angle_deg:g}°"
    for c, r in sk.circles:
        ax.fill(c.real + r * np.cos(t), c.imag + r * np.sin(t), color="#e6b85c", alpha=0.9, zorder=5)
        ax.plot(c.real + r * np.cos(t), c.imag + r * np.sin(t), color=COLORS["follower"], lw=1.0, zorder=6)
    for a, b, role in sk.segments:
        lw = {"stem": 3, "arm": 3, "face": 2.2, "yoke": 3}[role]
        ax.plot([a.real, b.real], [a.imag, b.imag], color=COLORS["follower"], lw=lw, zorder=6,
                solid_capstyle="round", label=label)
        label = None
    if sk.pivot is not None:
        ax.plot([sk.pivot.real], [sk.pivot.imag], "o", ms=7, mfc="white", mec=COLORS["follower"], mew=1.5,
                zorder=8, label="pivot")
    ax.plot([sk.point.real], [sk.point.imag], "o", color=COLORS["pitch"], ms=3, zorder=8)
    ax.plot([0], [0], "+", color="k", ms=10)
    ax.set_aspect("equal")
    ax.set_title(f"{spec.cam.body} cam, {desc['label']} {u}\n"
                 + (f"M = {design.pitch.M} PH segments" if _is_ph(design) else
                    f"{design.pitch.M} B-spline knot spans"), fontsize=9)
    ax.set_xlabel(f"x [{u}]")
    ax.set_ylabel(f"y [{u}]")
    ax.legend(loc="lower left", fontsize=7, framealpha=0.9)
    ax.grid(alpha=0.2)


def _draw_body_top(ax: Any, design: CamDesign, prof_label: str) -> None:
    """The body seen from +Z: every prism region that reaches the top face, material filled and
    cuts (a groove between its walls, the bore with its keyway, holes, the timing mark) white, in
    the body's order; a groove's walls labelled as the exact offsets they are."""
    from matplotlib.patches import PathPatch  # deferred: matplotlib, loaded when a figure is drawn
    from matplotlib.path import Path as MplPath

    body = design.body
    top = body.z_range[1]
    first_add = True
    for prism in body.prisms:
        if not prism.z0 < top <= prism.z1 + 1e-12:
            continue
        loops = [prism.outer.points()] + [h.points()[::-1] for h in prism.holes]
        verts = np.concatenate([np.column_stack([p.real, p.imag]) for p in loops])
        codes = np.concatenate([[MplPath.MOVETO] + [MplPath.LINETO] * (len(p) - 1) for p in loops])
        add = prism.op == "add"
        label = None
        if add and first_add:
            label = body_of(design.spec).drawing_label or prof_label
            first_add = False
        ax.add_patch(PathPatch(MplPath(verts, codes), facecolor="#b8c7d9" if add else "white",
                               edgecolor=COLORS["profile"], lw=1.0, zorder=1 if add else 3, label=label))
    ax.autoscale_view()


def conjugate_figure(design: CamDesign, second: CamDesign, follower_angle_deg: float = 75.0) -> Any:
    """A conjugate pair seen from +Z: the first cam (filled) over the second (below it, hatched
    outline), both pitch curves, and the follower at ``follower_angle_deg`` with both rollers —
    the yoke joining them, or both arms on their pivot."""
    plt = _plt()
    spec = design.spec
    u = spec.units
    fig, ax = plt.subplots(figsize=(6.8, 6.8))
    t = np.linspace(0, 2 * np.pi, 400)
    _, p1 = design.profile.sample(32)
    _, p2 = second.profile.sample(32)
    ax.fill(p2[:, 0], p2[:, 1], color="#f3d9b1", zorder=1, label="second cam (below the first)")
    ax.plot(p2[:, 0], p2[:, 1], color="#a05a00", lw=1.1, zorder=2)
    ax.fill(p1[:, 0], p1[:, 1], color="#b8c7d9", alpha=0.85, zorder=3, label="first cam")
    ax.plot(p1[:, 0], p1[:, 1], color=COLORS["profile"], lw=1.2, zorder=4)
    for d, style, name in ((design, "--", "first"), (second, "-.", "second")):
        _, q = d.pitch_nurbs.sample(32)
        ax.plot(q[:, 0], q[:, 1], style, color=COLORS["pitch"], lw=0.8, zorder=5,
                label=f"{name} pitch curve (PH)")
    if spec.cam.bore_diameter > 0:
        rb = spec.cam.bore_diameter / 2
        ax.fill(rb * np.cos(t), rb * np.sin(t), color="white", zorder=6)
        ax.plot(rb * np.cos(t), rb * np.sin(t), color=COLORS["profile"], lw=1.0, zorder=6)
    th = np.deg2rad(follower_angle_deg)
    k = design.program.evaluate(np.array([th]))
    size = spec.max_lift * (spec.cam.base_radius * design.follower.lift_scale
                            if design.follower.lift_unit == "angle" else 1.0) + 2 * design.follower.profile_offset
    label = f"follower at θ = {follower_angle_deg:g}°"
    for fol in (design.follower, second.follower):
        sk = fol.sketch(th, k, size)
        for c, r in sk.circles:
            ax.fill(c.real + r * np.cos(t), c.imag + r * np.sin(t), color="#e6b85c", alpha=0.9, zorder=7)
            ax.plot(c.real + r * np.cos(t), c.imag + r * np.sin(t), color=COLORS["follower"], lw=1.0, zorder=8)
        for a, b, _role in sk.segments:
            ax.plot([a.real, b.real], [a.imag, b.imag], color=COLORS["follower"], lw=3, zorder=8,
                    solid_capstyle="round", label=label)
            label = None
        if sk.pivot is not None:
            ax.plot([sk.pivot.real], [sk.pivot.imag], "o", ms=7, mfc="white", mec=COLORS["follower"], mew=1.5,
                    zorder=9)
        ax.plot([sk.point.real], [sk.point.imag], "o", color=COLORS["pitch"], ms=3, zorder=9)
    ax.plot([0], [0], "+", color="k", ms=10)
    ax.set_aspect("equal")
    ax.set_title(f"conjugate cams, {design.follower.describe()['label']} {u}\nand the "
                 f"{second.follower.label()} {u}", fontsize=8.5)
    ax.set_xlabel(f"x [{u}]")
    ax.set_ylabel(f"y [{u}]")
    ax.legend(loc="lower left", fontsize=7, framealpha=0.9)
    ax.grid(alpha=0.2)
    return fig


def roller_distance_figure(design: CamDesign, error: Any) -> Any:
    """A conjugate pair over the cycle: each built pitch curve's lift error s_actual − s (its PH
    deviation) and the distance error between the rollers that follows from them
    (:class:`cam_workbench.generators.bodies.conjugate.RollerDistanceError`), with the bound the two
    deviations set."""
    plt = _plt()
    u = design.spec.units
    scale, unit = small_unit(u, design.follower.lift_unit)
    lscale, lunit = _small_length_scale(u)
    deg = np.rad2deg(error.theta)
    s = design.program.s(error.theta)
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 5.6), sharex=True)
    _segment_marks(a1, design, labels=True)
    a1.plot(deg, (error.s1 - s) * scale, color=COLORS["s"], lw=0.8, label="first cam: s₁ − s")
    a1.plot(deg, (error.s2 - s) * scale, color=COLORS["a"], lw=0.8, label="second cam: s₂ − s")
    a1.set_ylabel(f"lift error [{unit}]", fontsize=8)
    a1.legend(fontsize=7, loc="lower left")
    _angle_axis(a1, last=False)
    _segment_marks(a2, design)
    a2.plot(deg, error.distance * lscale, color=COLORS["j"], lw=0.9)
    k = int(np.argmax(np.abs(error.distance)))
    a2.plot([deg[k]], [error.distance[k] * lscale], "o", ms=4, color=COLORS["a"])
    right = deg[k] > 240
    a2.annotate(f"max |error| = {abs(error.distance[k]) * lscale:.4g} {lunit} at {deg[k]:.2f}°",
                (deg[k], error.distance[k] * lscale), xytext=(-8 if right else 8, 0), textcoords="offset points",
                fontsize=8, va="center", ha="right" if right else "left")
    a2.axhline(0, color="0.3", lw=0.6)
    a2.set_ylabel(f"distance error [{lunit}]\n+ interference, − play", fontsize=8)
    _angle_axis(a2)
    fig.tight_layout()
    return fig


def cam_drawing_figure(design: CamDesign, follower_angle_deg: float = 75.0) -> Any:
    """The cam with the follower (see :func:`draw_cam`)."""
    fig, ax = _plt().subplots(figsize=(6.5, 6.5))
    draw_cam(ax, design, follower_angle_deg)
    return fig


def _kinematic_series(design: CamDesign, n: int = 3601) -> tuple[np.ndarray, list[tuple[np.ndarray, str, str]]]:
    spec = design.spec
    u = "deg" if design.follower.lift_unit == "angle" else spec.units
    th = np.linspace(0, 2 * np.pi, n)
    k = design.program.evaluate(th)
    omega = spec.cam.speed_rpm * 2 * np.pi / 60
    return np.rad2deg(th), [(k.s, f"s [{u}]", "s"), (k.ds * omega, f"v [{u}/s]", "v"),
                            (k.d2s * omega**2, f"a [{u}/s²]", "a"), (k.d3s * omega**3, f"j [{u}/s³]", "j")]


def cam_figure(design: CamDesign, follower_angle_deg: float = 75.0) -> Any:
    """Drawing of the cam (profile, pitch curve, base and prime circles, bore, the follower at
    ``follower_angle_deg`` of cam rotation) beside its s, v, a, j diagrams over one turn."""
    plt = _plt()
    spec = design.spec
    fig, (ax, axk) = plt.subplots(1, 2, figsize=(11, 5), gridspec_kw={"width_ratios": [1, 1.25]})
    draw_cam(ax, design, follower_angle_deg)
    deg, series = _kinematic_series(design)
    axk.remove()
    gs = ax.get_gridspec()
    sub = gs[1].subgridspec(4, 1, hspace=0.08)
    for i, (y, label, key) in enumerate(series):
        a = fig.add_subplot(sub[i])
        a.plot(deg, y, color=COLORS[key], lw=1.0)
        a.set_ylabel(label, fontsize=8)
        a.grid(alpha=0.25)
        a.set_xlim(0, 360)
        a.set_xticks(np.arange(0, 361, 60))
        if i < 3:
            a.tick_params(labelbottom=False)
        else:
            a.set_xlabel("cam angle θ [deg]")
        a.tick_params(labelsize=7)
        if i == 0:
            a.set_title(f"follower motion at {spec.cam.speed_rpm:g} rpm", fontsize=9)
    return fig


# ---- curves over the cycle -----------------------------------------------------------------
def kinematics_figure(design: CamDesign) -> Any:
    """Displacement, velocity, acceleration and jerk of the follower over one turn at the
    spec's speed (design intent, closed-form laws), with the motion segments marked."""
    plt = _plt()
    deg, series = _kinematic_series(design)
    fig, axes = plt.subplots(4, 1, figsize=(9, 7.5), sharex=True)
    for i, (ax, (y, label, key)) in enumerate(zip(axes, series)):
        _segment_marks(ax, design, labels=i == 0)
        ax.plot(deg, y, color=COLORS[key], lw=1.1)
        ax.set_ylabel(label, fontsize=8)
        k = int(np.argmax(np.abs(y)))
        ax.plot([deg[k]], [y[k]], "o", ms=3, color=COLORS[key])
        ax.annotate(f"max |{key}| = {abs(y[k]):.4g}", (deg[k], y[k]), xytext=(6, -4 if y[k] > 0 else 4),
                    textcoords="offset points", fontsize=7, va="top" if y[k] > 0 else "bottom")
        _angle_axis(ax, last=i == 3)
    fig.suptitle(f"follower motion at {design.spec.cam.speed_rpm:g} rpm", fontsize=10)
    fig.tight_layout()
    return fig


def _check_point(ax: Any, name: str, check: Mapping[str, Any], y: float, text: str, below: bool) -> None:
    """Mark a check's value at its cam angle (red when it fails), labelled with the angle."""
    status = str(check.get("status"))
    color = COLORS["fail"] if status == "fail" else COLORS["pass"]
    x = float(check["at_deg"])
    ax.plot([x], [y], "o", ms=6, mfc=color, mec="k", mew=0.6, zorder=9, gid=POINT_GID.format(name=name))
    right = x > 240
    ax.annotate(text + (" — FAILS" if status == "fail" else ""), (x, y), xytext=(-10 if right else 10, -12 if below else 10),
                textcoords="offset points", fontsize=8, color=color, ha="right" if right else "left",
                va="top" if below else "bottom", fontweight="bold" if status == "fail" else "normal", zorder=10,
                bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.85})


def pressure_angle_figure(design: CamDesign, limit_deg: float | None = None,
                          check: Mapping[str, Any] | None = None) -> Any:
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
    plt = _plt()
    th = np.linspace(0, 2 * np.pi, 3601)
    phi = np.rad2deg(design.geometry.pressure_angle(design.program.evaluate(th)))
    at, phi_b = design.as_built_pressure_angles()
    order = np.argsort(at)
    fig, ax = plt.subplots(figsize=(9, 3.8))
    _segment_marks(ax, design, labels=True)
    ax.plot(np.rad2deg(th), phi, color=COLORS["s"], lw=1.4, label="design (thesis Eq. 3.4)", zorder=2)
    ax.plot(at[order][::24], phi_b[order][::24], "o", ms=2.6, mfc="none", mew=0.7, color=COLORS["built"],
            label=f"built {_pitch_words(design)} (samples)", zorder=3)
    if check is not None and check.get("limit") is not None:
        limit_deg = float(check["limit"])
    if limit_deg is not None:
        for sgn, tag in ((1, "upper"), (-1, "lower")):
            ax.axhline(sgn * limit_deg, color=COLORS["limit"], ls="--", lw=1.0,
                       gid=LIMIT_GID.format(name="pressure_angle") + "-" + tag,
                       label=f"limit |φ| ≤ {limit_deg:g}° (checks.max_pressure_angle)" if sgn > 0 else None)
            ax.text(2, sgn * limit_deg, f" {'+' if sgn > 0 else '−'}{limit_deg:g}°", color=COLORS["limit"],
                    fontsize=7, va="bottom" if sgn > 0 else "top")
    if check is not None and check.get("value") is not None and check.get("at_deg") is not None:
        # the check reports |φ|; the curve is signed: mark it on the side where φ is
        x = float(check["at_deg"])
        sign = 1.0 if np.interp(x, np.rad2deg(th), phi) >= 0 else -1.0
        y = sign * float(check["value"])
        _check_point(ax, "pressure_angle", check, y, f"max |φ| = {float(check['value']):.2f}° at {x:.2f}°", y > 0)
    else:
        k = int(np.argmax(np.abs(phi)))
        ax.plot([np.rad2deg(th[k])], [phi[k]], "o", color=COLORS["a"], ms=4)
        right = np.rad2deg(th[k]) > 240
        ax.annotate(f"max |φ| = {abs(phi[k]):.2f}° at {np.rad2deg(th[k]):.1f}°", (np.rad2deg(th[k]), phi[k]),
                    xytext=(-8 if right else 8, 0), textcoords="offset points", fontsize=8, va="center",
                    ha="right" if right else "left")
    top = max(float(np.max(np.abs(phi))), limit_deg or 0.0) * 1.18
    ax.set_ylim(-top, top)
    ax.set_ylabel("pressure angle φ [deg]", fontsize=8)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3, frameon=False)
    _angle_axis(ax)
    fig.tight_layout()
    return fig


def curvature_figure(design: CamDesign, check: Mapping[str, Any] | None = None) -> Any:
    """Signed radius of curvature (+ convex) of the pitch curve (thesis Eq. 3.7) and of the
    profile (ρ − roller radius), with the built curve's samples; the axis is clipped
    where the curve straightens (|ρ| → ∞).

    ``check`` is report.json's ``checks.results.curvature``: its limit (undercut factor ×
    roller radius, a lower bound on the convex pitch radius) is drawn dashed and its value
    marked at its cam angle (red when it fails)."""
    plt = _plt()
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
    fig, ax = plt.subplots(figsize=(9, 3.8))
    _segment_marks(ax, design, labels=True)
    deg = np.rad2deg(th)

    # outside ±top the curve is nearly straight: leave gaps instead of drawing ±∞ jumps
    def cut(r: np.ndarray) -> np.ndarray:
        return np.where(np.abs(r) <= top, r, np.nan)

    ax.plot(deg, cut(rho), color=COLORS["pitch"], lw=1.3,
            label="profile (the face's envelope)" if flat else "pitch curve", zorder=2)
    if rr > 0:
        # offsetting inward by r shrinks convex radii and grows concave ones: ρ − r either way
        ax.plot(deg, cut(rho - rr), color=COLORS["profile"], lw=1.3, label="profile (ρ − roller radius)",
                zorder=2)
    ax.plot(cs.cam_angle_deg[order][::12], cut(cs.radius[order][::12]), "o", ms=2.4, mfc="none", mew=0.6,
            color="0.35", label=f"built {_pitch_words(design)} (samples)", zorder=3)
    name = "cusp" if flat else "curvature"
    if limit is not None:
        sign = limit_sign(name, str(check.get("kind", "min")))  # type: ignore[union-attr]
        ax.axhline(limit, color=COLORS["limit"], ls="--", lw=1.0, gid=LIMIT_GID.format(name=name),
                   label=(f"cusp limit: ρ {sign} {limit:g} {u}" if flat else
                          f"curvature limit: convex pitch ρ {sign} {limit:g} {u} "
                          f"({spec.checks.undercut_factor:g} × roller radius)"))
    if rr > 0:
        ax.axhline(rr, color="0.45", ls=":", lw=0.9, gid=LIMIT_GID.format(name="undercut"),
                   label=f"roller radius {rr:g} {u} (undercut below)")
    ax.axhline(0, color="0.3", lw=0.6)
    if check is not None and check.get("value") is not None and check.get("at_deg") is not None:
        v = float(check["value"])
        _check_point(ax, name, check, v,
                     f"min {'' if flat else 'convex pitch '}ρ = {v:.4g} {u} at {float(check['at_deg']):.2f}°", False)
    elif convex.size:
        k = int(np.argmin(np.where(rho > 0, rho, np.inf)))
        ax.plot([deg[k]], [rho[k]], "o", ms=4, color=COLORS["pitch"])
        ax.annotate(f"min convex ρ = {rho[k]:.4g} {u} at {deg[k]:.1f}°", (deg[k], rho[k]),
                    xytext=(8, -10), textcoords="offset points", fontsize=8)
    ax.set_ylim(-top, top)
    ax.set_ylabel(f"radius of curvature [{u}]  (+ convex)", fontsize=8)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3, frameon=False)
    _angle_axis(ax)
    fig.tight_layout()
    return fig


def _small_length_scale(units: str) -> tuple[float, str]:
    return (1e3, "µm") if units == "mm" else (1e6, "µin")


def small_unit(units: str, lift_unit: str = "length") -> tuple[float, str]:
    """(factor, unit) in which lift errors are shown: µm/µin, or arc seconds for an arm's angle."""
    return (3600.0, "arcsec") if lift_unit == "angle" else _small_length_scale(units)


def deviation_figure(design: CamDesign) -> Any:
    """Interpolation error s_actual(θ) − s(θ) of the built pitch curve (paper Eq. 13,
    as the paper's Figs. 5 and 7), with the PH junction (or B-spline knot) angles marked."""
    plt = _plt()
    th, dev = design.pitch.deviation()
    scale, unit = small_unit(design.spec.units, design.follower.lift_unit)
    deg = np.rad2deg(th)
    fig, ax = plt.subplots(figsize=(9, 3.4))
    _segment_marks(ax, design, labels=True)
    ax.plot(deg, dev * scale, color=COLORS["s"], lw=0.8)
    k = int(np.argmax(np.abs(dev)))
    ax.plot([deg[k]], [dev[k] * scale], "o", ms=4, color=COLORS["a"])
    ax.annotate(f"max |s_actual − s| = {abs(dev[k]) * scale:.4g} {unit} at {deg[k]:.2f}°",
                (deg[k], dev[k] * scale), xytext=(8, 0), textcoords="offset points", fontsize=8, va="center")
    j = np.rad2deg(design.pitch.angles)
    ax.plot(j, np.zeros_like(j), "|", color="0.4", ms=5,
            label=f"PH junctions (M = {design.pitch.M})" if _is_ph(design) else f"B-spline knots ({design.pitch.M} spans)")
    ax.set_ylabel(f"s_actual − s [{unit}]", fontsize=8)
    ax.legend(fontsize=7, loc="lower left")
    _angle_axis(ax)
    fig.tight_layout()
    return fig


def series_figure(panels: Sequence[tuple[np.ndarray, np.ndarray, str, float | None, str | None]],
                  design: CamDesign | None = None) -> Any:
    """Stacked θ-series, one panel each: (θ [deg], values, y label, limit or None, limit kind
    "max"/"min" or None) — e.g. contact force and Hertz stress with their allowed values."""
    plt = _plt()
    n = len(panels)
    fig, axes = plt.subplots(n, 1, figsize=(9, 2.6 * n + 0.6), sharex=True, squeeze=False)
    for i, (ax, (deg, y, label, limit, kind)) in enumerate(zip(axes[:, 0], panels)):
        if design is not None:
            _segment_marks(ax, design, labels=i == 0)
        ax.plot(deg, y, color=SERIES_COLORS[i % len(SERIES_COLORS)], lw=1.1)
        if limit is not None:
            ax.axhline(limit, color=COLORS["limit"], ls="--", lw=0.9)
            ax.text(2, limit, f" {kind or 'limit'} {limit:.4g}", color=COLORS["limit"], fontsize=7,
                    va="bottom")
        ax.set_ylabel(label, fontsize=8)
        _angle_axis(ax, last=i == n - 1)
    fig.tight_layout()
    return fig


def convergence_figure(iterations: np.ndarray, objective: np.ndarray, objective_label: str,
                       violation: np.ndarray | None = None) -> Any:
    """An optimiser's history: objective per iteration and, when given, the largest
    constraint violation (log scale; ≤ 0 shown at the bottom as satisfied)."""
    plt = _plt()
    rows = 2 if violation is not None else 1
    fig, axes = plt.subplots(rows, 1, figsize=(9, 2.6 * rows + 0.4), sharex=True, squeeze=False)
    ax = axes[0, 0]
    ax.plot(iterations, objective, "-o", ms=2.5, lw=1.0, color=COLORS["s"])
    ax.set_ylabel(objective_label, fontsize=8)
    ax.grid(alpha=0.25)
    ax.tick_params(labelsize=7)
    if violation is not None:
        ax2 = axes[1, 0]
        v = np.asarray(violation, dtype=float)
        floor = 1e-12
        ax2.semilogy(iterations, np.maximum(v, floor), "-o", ms=2.5, lw=1.0, color=COLORS["a"])
        ax2.set_ylabel("max constraint violation", fontsize=8)
        ax2.grid(alpha=0.25)
        ax2.tick_params(labelsize=7)
    axes[-1, 0].set_xlabel("iteration", fontsize=8)
    fig.tight_layout()
    return fig


# ---- follower dynamics -------------------------------------------------------------------------
#: SVG ids of the dynamics figures' marks: the operating speed, the jump speeds, the smallest force
DYNAMICS_GIDS = {"speed": "dyn-speed", "jump": "dyn-jump-speed", "rigid_jump": "dyn-rigid-jump-speed",
                 "min_force": "dyn-min-force"}


def _program_marks(ax: Any, program: Any, labels: bool = False) -> None:
    b = np.rad2deg(program.boundaries)
    for x in b[1:-1]:
        ax.axvline(x, color="0.75", lw=0.6, zorder=0)
    if labels:
        for k, kind in enumerate(program.kinds):
            ax.text(0.5 * (b[k] + b[k + 1]), 1.02, kind, transform=ax.get_xaxis_transform(),
                    ha="center", va="bottom", fontsize=7, color="0.35")


def _off_cam(ax: Any, deg: np.ndarray, on_cam: np.ndarray) -> None:
    """Shade where the follower is off the cam."""
    off = ~np.asarray(on_cam, bool)
    if off.any():
        ax.fill_between(deg, 0, 1, where=off, transform=ax.get_xaxis_transform(), color=COLORS["a"],
                        alpha=0.12, lw=0, label="off the cam")


def dynamics_figure(result: Any, section: Mapping[str, Any]) -> Any:
    """The follower train over one steady-state revolution (:class:`cam_workbench.generators.dynamics.DynamicsResult`):
    the normal contact force, rigid and dynamic; the camshaft torque, rigid and dynamic; the
    displacement error q − s and its vibration about the quasi-static deflection. ``section`` is
    report.json's ``dynamics`` section: the marked smallest force is its value at its angle."""
    plt = _plt()
    deg = result.theta_deg
    c = section["contact"]
    scale, unit = small_unit(result.units, result.lift_unit)
    fig, axes = plt.subplots(3, 1, figsize=(9, 8.2), sharex=True)
    ax = axes[0]
    _program_marks(ax, result.program, labels=True)
    _off_cam(ax, deg, result.on_cam)
    ax.plot(deg, result.rigid_force, color="0.45", lw=0.9, ls="--", label="rigid follower")
    ax.plot(deg, result.force, color=COLORS["s"], lw=1.1, label=f"dynamic at {section['speed_rpm']:.4g} rpm")
    ax.axhline(0.0, color=COLORS["limit"], lw=0.8, ls=":")
    ax.plot([c["min_force_at_deg"]], [c["min_force"]], "o", ms=5, mfc=COLORS["fail" if not c["kept"] else "pass"],
            mec="k", mew=0.6, gid=DYNAMICS_GIDS["min_force"], zorder=9)
    ax.annotate(f"min {c['min_force']:.4g} {c['unit']} at {c['min_force_at_deg']:.1f}°",
                (c["min_force_at_deg"], c["min_force"]), xytext=(8, 8), textcoords="offset points", fontsize=7)
    ax.set_ylabel(f"contact force [{c['unit']}]", fontsize=8)
    ax.legend(fontsize=7, loc="upper right")
    _angle_axis(ax, last=False)
    ax = axes[1]
    _program_marks(ax, result.program)
    _off_cam(ax, deg, result.on_cam)
    tu = section["torque"]["unit"]
    ax.plot(deg, result.rigid_torque, color="0.45", lw=0.9, ls="--", label="rigid")
    ax.plot(deg, result.torque, color=COLORS["a"], lw=1.1, label="dynamic")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_ylabel(f"camshaft torque [{tu}]", fontsize=8)
    ax.legend(fontsize=7, loc="upper right")
    _angle_axis(ax, last=False)
    ax = axes[2]
    _program_marks(ax, result.program)
    _off_cam(ax, deg, result.on_cam)
    ax.plot(deg, result.error * scale, color=COLORS["v"], lw=1.0, label="q − s")
    ax.plot(deg, result.vibration * scale, color=COLORS["j"], lw=0.8, label="vibration about the quasi-static deflection")
    ax.set_ylabel(f"displacement error [{unit}]", fontsize=8)
    ax.legend(fontsize=7, loc="lower right")
    _angle_axis(ax)
    fig.tight_layout()
    return fig


def jump_speed_figure(result: Any, section: Mapping[str, Any]) -> Any:
    """The jump-speed curve: the smallest contact force over the cycle against the cam speed, with
    the analysis speed and the jump speeds (dynamic and rigid) of report.json's ``dynamics``
    section marked."""
    plt = _plt()
    jp = section["jump_speed"]
    sweep = jp["sweep"]
    fig, ax = plt.subplots(figsize=(9, 3.8))
    ax.plot(sweep["speeds_rpm"], sweep["min_force"], "-o", ms=2, lw=1.0, color=COLORS["s"],
            label="smallest contact force over a revolution (< 0: the cam would have to pull)")
    ax.axhline(0.0, color=COLORS["limit"], lw=0.8, ls=":")
    ax.axvline(section["speed_rpm"], color=COLORS["v"], lw=1.0, gid=DYNAMICS_GIDS["speed"],
               label=f"analysis speed {section['speed_rpm']:.4g} rpm")
    if jp["rpm"] is not None:
        ax.axvline(jp["rpm"], color=COLORS["a"], lw=1.2, ls="--", gid=DYNAMICS_GIDS["jump"],
                   label=f"jump speed {jp['rpm']:.5g} rpm")
    if jp["rigid_rpm"] is not None and jp["sweep_from_rpm"] <= jp["rigid_rpm"] <= jp["sweep_to_rpm"]:
        ax.axvline(jp["rigid_rpm"], color="0.45", lw=0.9, ls=":", gid=DYNAMICS_GIDS["rigid_jump"],
                   label=f"rigid follower's {jp['rigid_rpm']:.5g} rpm")
    ax.set_xlabel("cam speed [rpm]", fontsize=8)
    ax.set_ylabel(f"min contact force [{section['contact']['unit']}]", fontsize=8)
    ax.grid(alpha=0.25)
    ax.tick_params(labelsize=7)
    ax.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    return fig


#: the figure that shows a design at a glance, ``fn(design, follower_angle_deg)``, by the design's
#: class (:func:`picture`): the plane cams' here, a body's own in its module
PICTURES: ByClass[Callable[..., Any]] = ByClass("the cam's picture")
PICTURES.register(CamDesign)(cam_figure)


def picture(design: Any, follower_angle_deg: float = 75.0) -> Any:
    """The figure that shows a designed cam at a glance — the Python API's picture in Jupyter:
    a cam of plane curves beside its motion (:func:`cam_figure`), a cylindrical cam's cylinder
    beside its developed view (:func:`cam_workbench.exporters.plots_cylindrical.cylindrical_figure`)
    — or None for a design of a class nothing registered in :data:`PICTURES`."""
    figure = PICTURES.for_class(type(design))
    return None if figure is None else figure(design, follower_angle_deg)

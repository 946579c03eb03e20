"""Figures of the rotational interpolator's accuracy (as the paper's Figures 4–8):
the follower-displacement error of the commands, and the follower's s, v, a, j from the
commands (finite differences at Δt) against the design intent.

Figures take plain results from ``cam_workbench.generators.machining.interpolator`` and only
describe them as :class:`~.chart.Chart` s (drawn by :mod:`.chart_svg`); they draw nothing themselves.
"""
from __future__ import annotations

import numpy as np

from cam_workbench.generators.machining.interpolator import DEFAULT_SCHEME, InterpolatorAccuracy
from cam_workbench.generators.motion import MotionProgram

from .chart import Chart, Curve, Panel, Rule, angle_panel, css_color


_ANGLE_LABEL = "cam angle θ [deg]"


def _error_scale(units: str) -> tuple[float, str]:
    """µm, µin — or arc seconds when the lift is an arm angle ("deg")."""
    return {"mm": (1e3, "µm"), "in": (1e6, "µin"), "deg": (3600.0, "arcsec")}[units]


def deviation_figure(acc: InterpolatorAccuracy, units: str = "mm",
                     dense: tuple[np.ndarray, np.ndarray] | None = None,
                     junction_angles: np.ndarray | None = None, junction_label: str = "PH junctions") -> Chart:
    """s_actual − s at every command (and, if given, densely sampled), with the largest error and
    the junctions marked (``junction_label``: "PH junctions", where the error vanishes, or the knots
    of a fitted B-spline)."""
    c = acc.commands
    scale, label = _error_scale(units)
    ax = angle_panel(xlabel=_ANGLE_LABEL, ylabel=f"s_actual − s [{label}]", legend="right", height=230.0,
                     title=f"follower displacement error of the interpolated commands "
                           f"(Δt = {c.sample_period * 1e3:g} ms, {c.speed_rpm:g} rpm)")
    if dense is not None:
        ax.add(Curve(np.rad2deg(dense[0]), dense[1] * scale, color=css_color("0.7"), width=0.8,
                     label=f"dense ({len(dense[0])} samples)"))
    ax.add(Curve(np.rad2deg(c.theta), c.deviation * scale, color="#1f3b5c", marker=".", line=False, size=2.0,
                 label=f"commands ({c.n}, every {c.step_deg:.3g}°)"))
    dev, at = acc.max_deviation
    k = int(np.argmax(np.abs(c.deviation)))
    ax.add(Curve(np.array([at]), np.array([c.deviation[k] * scale]), color="#c0392b", marker="o", line=False,
                 size=8.0, face="none", label=f"max {dev * scale:.4g} {label} at {at:.2f}°"))
    if junction_angles is not None:
        ax.add(Curve(np.rad2deg(junction_angles), np.zeros_like(junction_angles), color="#2e7d32", marker="|",
                     line=False, size=8.0, label=junction_label))
    ax.add(Rule("y", 0.0, color="#000000", width=0.5, dash="-"))
    return Chart.stack([ax], width=760.0)


def kinematics_figure(acc: InterpolatorAccuracy, program: MotionProgram, units: str = "mm",
                      scheme: str = DEFAULT_SCHEME) -> Chart:
    """s, v, a, j of the follower from the commands (finite differences at Δt, ``scheme``;
    the other scheme's jerk as a thin line) over the exact curves of the motion program."""
    c = acc.commands
    fd = acc.differences[scheme]
    other = [s for s in acc.differences if s != scheme]
    th = np.linspace(0.0, 2 * np.pi, 7201)
    k = program.evaluate(th)
    w = c.omega
    deg = np.rad2deg(th)
    rows = [
        ("s", f"s [{units}]", k.s, np.rad2deg(c.theta), c.s_actual),
        ("v", f"v [{units}/s]", k.ds * w, np.rad2deg(fd.v_theta), fd.v),
        ("a", f"a [{units}/s²]", k.d2s * w**2, np.rad2deg(fd.a_theta), fd.a),
        ("j", f"j [{units}/s³]", k.d3s * w**3, np.rad2deg(fd.j_theta), fd.j),
    ]
    mx = acc.maxima(scheme)
    names = {"v": "velocity", "a": "acceleration", "j": "jerk"}
    panels: list[Panel] = []
    for i, (key, label, exact, x_cmd, y_cmd) in enumerate(rows):
        last = i == len(rows) - 1
        ax = angle_panel(ylabel=label, legend="right", height=150.0, xlabel=_ANGLE_LABEL if last else "",
                         xticklabels=last)
        ax.add(Curve(deg, exact, color=css_color("0.55"), width=2.2, label="desired (closed-form motion law)"))
        cmd_label = "from the commands" if key == "s" else f"from the commands ({scheme} differences)"
        if key in names:
            value, _ = mx[names[key]]
            cmd_label += f", max {value:.5g}"
        ax.add(Curve(np.mod(x_cmd, 360.0), y_cmd, color="#c0392b", marker=".", line=False, size=1.6,
                     label=cmd_label))
        if key == "j" and other:
            alt = acc.differences[other[0]]
            ax.add(Curve(np.mod(np.rad2deg(alt.j_theta), 360.0), alt.j, color="#1f77b4", width=0.6, alpha=0.8,
                         label=f"{other[0]} differences, max {np.max(np.abs(alt.j)):.5g}"))
        panels.append(ax)
    panels[0].title = (f"follower kinematics from the interpolated commands "
                       f"(Δt = {c.sample_period * 1e3:g} ms, {c.speed_rpm:g} rpm)")
    return Chart.stack(panels, width=860.0)

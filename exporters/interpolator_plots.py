"""Figures of the rotational interpolator's accuracy (as the paper's Figures 4–8):
the follower-displacement error of the commands, and the follower's s, v, a, j from the
commands (finite differences at Δt) against the design intent.

Figures take plain results from ``cam_workbench.generators.machining.interpolator`` and only plot them.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from cam_workbench.generators.machining.interpolator import DEFAULT_SCHEME, InterpolatorAccuracy
from cam_workbench.generators.motion import MotionProgram

PLOT_FILES = {"deviation": "interpolator_deviation.png", "kinematics": "interpolator_kinematics.png"}


def _plt() -> Any:
    import matplotlib  # deferred: matplotlib, loaded when a figure is drawn

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # deferred: matplotlib, loaded when a figure is drawn

    return plt


def _error_scale(units: str) -> tuple[float, str]:
    """µm, µin — or arc seconds when the lift is an arm angle ("deg")."""
    return {"mm": (1e3, "µm"), "in": (1e6, "µin"), "deg": (3600.0, "arcsec")}[units]


def deviation_figure(acc: InterpolatorAccuracy, units: str = "mm",
                     dense: tuple[np.ndarray, np.ndarray] | None = None,
                     junction_angles: np.ndarray | None = None, junction_label: str = "PH junctions") -> Any:
    """s_actual − s at every command (and, if given, densely sampled), with the junctions
    marked (``junction_label``: "PH junctions", where the error vanishes, or the knots of a
    fitted B-spline)."""
    plt = _plt()
    c = acc.commands
    scale, label = _error_scale(units)
    fig, ax = plt.subplots(figsize=(9, 3.6))
    if dense is not None:
        ax.plot(np.rad2deg(dense[0]), dense[1] * scale, color="0.7", lw=0.8,
                label=f"dense ({len(dense[0])} samples)")
    deg = np.rad2deg(c.theta)
    ax.plot(deg, c.deviation * scale, ".", ms=2.0, color="#1f3b5c",
            label=f"commands ({c.n}, every {c.step_deg:.3g}°)")
    dev, at = acc.max_deviation
    k = int(np.argmax(np.abs(c.deviation)))
    ax.plot([at], [c.deviation[k] * scale], "o", mfc="none", color="#c0392b", ms=8,
            label=f"max {dev * scale:.4g} {label} at {at:.2f}°")
    if junction_angles is not None:
        ax.plot(np.rad2deg(junction_angles), np.zeros_like(junction_angles), "|", color="#2e7d32", ms=8,
                label=junction_label)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlim(0, 360)
    ax.set_xticks(np.arange(0, 361, 30))
    ax.set_xlabel("cam angle θ [deg]")
    ax.set_ylabel(f"s_actual − s [{label}]")
    ax.set_title(f"follower displacement error of the interpolated commands "
                 f"(Δt = {c.sample_period * 1e3:g} ms, {c.speed_rpm:g} rpm)", fontsize=10)
    ax.grid(alpha=0.25)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    return fig


def kinematics_figure(acc: InterpolatorAccuracy, program: MotionProgram, units: str = "mm",
                      scheme: str = DEFAULT_SCHEME) -> Any:
    """s, v, a, j of the follower from the commands (finite differences at Δt, ``scheme``;
    the other scheme's jerk dashed) over the exact curves of the motion program."""
    plt = _plt()
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
    fig, axes = plt.subplots(4, 1, figsize=(12, 9), sharex=True)
    mx = acc.maxima(scheme)
    names = {"v": "velocity", "a": "acceleration", "j": "jerk"}
    for ax, (key, label, exact, x_cmd, y_cmd) in zip(axes, rows):
        ax.plot(deg, exact, color="0.55", lw=2.2, label="desired (closed-form motion law)")
        cmd_label = "from the commands" if key == "s" else f"from the commands ({scheme} differences)"
        if key in names:
            value, _ = mx[names[key]]
            cmd_label += f", max {value:.5g}"
        ax.plot(np.mod(x_cmd, 360.0), y_cmd, ".", ms=1.6, color="#c0392b", label=cmd_label)
        if key == "j" and other:
            alt = acc.differences[other[0]]
            ax.plot(np.mod(np.rad2deg(alt.j_theta), 360.0), alt.j, "-", lw=0.6, color="#1f77b4", alpha=0.8,
                    label=f"{other[0]} differences, max {np.max(np.abs(alt.j)):.5g}")
        ax.set_ylabel(label)
        ax.grid(alpha=0.25)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    axes[-1].set_xlim(0, 360)
    axes[-1].set_xticks(np.arange(0, 361, 30))
    axes[-1].set_xlabel("cam angle θ [deg]")
    axes[0].set_title(f"follower kinematics from the interpolated commands "
                      f"(Δt = {c.sample_period * 1e3:g} ms, {c.speed_rpm:g} rpm)", fontsize=10)
    fig.tight_layout()
    return fig


def write_png(fig: Any, path: str | os.PathLike[str], dpi: int = 130) -> Path:
    """Write a figure as PNG to ``path`` as given (for :class:`cam_workbench.exporters.atomic.OutputSet`, whose
    temporary names do not end in .png) and close it."""
    fig.savefig(path, format="png", dpi=dpi, bbox_inches="tight")
    _plt().close(fig)
    return Path(path)

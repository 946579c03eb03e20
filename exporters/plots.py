"""Matplotlib figures of a designed cam (Agg backend, written atomically as PNG or SVG).

Figures take plain results from ``generators`` (a :class:`CamDesign`) and never compute
geometry themselves beyond sampling it.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from generators.cam_design import CamDesign

from .atomic import atomic_path


def _plt() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig: Any, path: str | os.PathLike[str], dpi: int = 150) -> Path:
    """Save a figure atomically; the format follows the suffix (.png, .svg, .pdf)."""
    target = Path(path)
    with atomic_path(target) as tmp:
        fig.savefig(tmp, dpi=dpi, format=target.suffix.lstrip(".") or "png", bbox_inches="tight")
    _plt().close(fig)
    return target


def cam_figure(design: CamDesign, follower_angle_deg: float = 75.0) -> Any:
    """Drawing of the cam (profile, pitch curve, base and prime circles, bore, the follower at
    ``follower_angle_deg`` of cam rotation) beside its s, v, a, j diagrams over one turn."""
    plt = _plt()
    spec = design.spec
    u = spec.units
    fig, (ax, axk) = plt.subplots(1, 2, figsize=(11, 5), gridspec_kw={"width_ratios": [1, 1.25]})
    _, prof = design.profile.sample(32)
    _, pitch = design.pitch_nurbs.sample(32)
    ax.fill(prof[:, 0], prof[:, 1], color="#b8c7d9", zorder=1, label="cam (exact NURBS profile)")
    ax.plot(prof[:, 0], prof[:, 1], color="#1f3b5c", lw=1.2, zorder=2)
    ax.plot(pitch[:, 0], pitch[:, 1], "--", color="#c0392b", lw=0.9, zorder=7,
            label="pitch curve (PH quintic spline)")
    t = np.linspace(0, 2 * np.pi, 400)
    rb = spec.cam.base_radius
    ax.plot(rb * np.cos(t), rb * np.sin(t), ":", color="0.45", lw=0.8, label="prime circle")
    if spec.cam.bore_diameter > 0:
        rbore = spec.cam.bore_diameter / 2
        ax.fill(rbore * np.cos(t), rbore * np.sin(t), color="white", zorder=3)
        ax.plot(rbore * np.cos(t), rbore * np.sin(t), color="#1f3b5c", lw=1.0, zorder=4)
    # the follower drawn in the cam frame at the chosen cam angle
    th = np.deg2rad(follower_angle_deg)
    geo = design.geometry
    s = design.program.s(np.array([th]))[0]
    p = geo.pitch_points(np.array([th]), np.array([s]))[0]
    axis_dir = np.exp(-1j * geo.sense * th) * 1j
    r = spec.roller_radius
    if r > 0:
        ax.fill(p.real + r * np.cos(t), p.imag + r * np.sin(t), color="#e6b85c", alpha=0.9, zorder=5)
        ax.plot(p.real + r * np.cos(t), p.imag + r * np.sin(t), color="#8a6212", lw=1.0, zorder=6)
    stem = np.array([p, p + axis_dir * (spec.max_lift + 2 * max(r, 0.1 * rb))])
    ax.plot(stem.real, stem.imag, color="#8a6212", lw=3, zorder=6, solid_capstyle="round",
            label=f"follower at θ = {follower_angle_deg:g}°")
    ax.plot([p.real], [p.imag], "o", color="#c0392b", ms=3, zorder=8)
    ax.plot([0], [0], "+", color="k", ms=10)
    ax.set_aspect("equal")
    ax.set_title(f"plate cam, {spec.follower.kind} follower, e = {spec.follower.offset:g} {u}, "
                 f"M = {design.pitch.M} PH segments", fontsize=9)
    ax.set_xlabel(f"x [{u}]")
    ax.set_ylabel(f"y [{u}]")
    ax.legend(loc="lower left", fontsize=7, framealpha=0.9)
    ax.grid(alpha=0.2)

    th_all = np.linspace(0, 2 * np.pi, 3601)
    k = design.program.evaluate(th_all)
    omega = spec.cam.speed_rpm * 2 * np.pi / 60
    deg = np.rad2deg(th_all)
    series = [(k.s, f"s [{u}]"), (k.ds * omega, f"v [{u}/s]"), (k.d2s * omega**2, f"a [{u}/s²]"),
              (k.d3s * omega**3, f"j [{u}/s³]")]
    axk.remove()
    gs = ax.get_gridspec()
    sub = gs[1].subgridspec(4, 1, hspace=0.08)
    for i, (y, label) in enumerate(series):
        a = fig.add_subplot(sub[i])
        a.plot(deg, y, color=["#1f3b5c", "#2e7d32", "#c0392b", "#6a1b9a"][i], lw=1.0)
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

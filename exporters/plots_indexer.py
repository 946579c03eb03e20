"""Figures of a parallel (plate-cam) indexer as :class:`~.chart.Chart` s: the cams, turret and rollers in
the fixed frame at an input angle (:func:`indexer_picture`), and the turret's motion with the driving
pressure angle over the input turn (:func:`indexer_motion_chart`).

Frames and signs are those of :mod:`cam_workbench.generators.bodies.indexing.parallel`: the input axis O
at the origin, the turret axis P = (C, 0); the cams turn counter-clockwise by θ (a cam-frame point q is
at Rot(θ)·q), the turret clockwise by ψ(θ).  Lengths in mm, angles on the axes and in the notes in
degrees.

SVG ids (a mark's ``gid``): ``cam-<k>`` the filled profile of cam k, ``roller-<k>-<j>`` the outline of
plane k's roller j, ``engaged-<k>-<j>`` the fill of a roller its cam holds at that θ,
``turret-pitch-circle``, ``input-axis``, ``turret-axis``, ``turret-angle`` (the note);
``psi``, ``dpsi``, ``d2psi``, ``driving-angle`` the motion chart's curves.
"""
from __future__ import annotations

import math

import numpy as np

from cam_workbench.generators.bodies.indexing.parallel import TWO_PI, ParallelDesign, roller_state, turret_angle
from cam_workbench.generators.bodies.indexing.parallel_kind import ParallelIndexerDesign

from .chart import Area, Chart, Curve, Mark, Note, Panel, Rule, Shade, angle_panel, css_color
from .plots import PICTURES

#: fill and edge of cam k (k modulo 3)
CAM_FILLS = ("#b8c7d9", "#f3d9b1", "#c8e6c9")
CAM_EDGES = ("#1f3b5c", "#a05a00", "#2e7d32")
ENGAGED_FILL = "#e6b85c"
_CIRCLE = np.linspace(0.0, TWO_PI, 121)


def _rot(theta: float, pts: np.ndarray) -> np.ndarray:
    """Points (..., 2) turned counter-clockwise by ``theta`` [rad]."""
    c, s = math.cos(theta), math.sin(theta)
    return np.stack([c * pts[..., 0] - s * pts[..., 1], s * pts[..., 0] + c * pts[..., 1]], axis=-1)


def _circle(centre: np.ndarray, radius: float) -> np.ndarray:
    return np.column_stack([centre[0] + radius * np.cos(_CIRCLE), centre[1] + radius * np.sin(_CIRCLE)])


def engaged_rollers(design: ParallelDesign, theta: float) -> dict[int, set[int]]:
    """Cam k → the indices j of its plane's rollers it holds at input angle ``theta`` [rad]: in the
    m-th turn from θ_s the locus' roller 0 is the turret's roller m mod N, roller 1 the next one;
    each is held in its engagement window (:attr:`IndexCam.windows`)."""
    ix = design.indexer
    n, ts = int(ix.stations), float(ix.index_start)
    m = math.floor((theta - ts) / TWO_PI)
    t = theta - TWO_PI * m
    out: dict[int, set[int]] = {}
    for cam in design.cams:
        held = set()
        for r, (lo, hi) in enumerate(cam.windows):
            if lo <= t <= hi:
                held.add((m + r) % n)
        out[cam.index] = held
    return out


def indexer_panel(design: ParallelDesign, theta: float = 0.0) -> Panel:
    """The indexer in the fixed frame at input angle ``theta`` [rad] (see :func:`indexer_picture`)."""
    ix = design.indexer
    n, rr, rp, c_dist = int(ix.stations), float(ix.roller_radius), float(ix.pitch_radius), float(ix.centre_distance)
    psi = float(turret_angle(ix, np.array([theta]))[0][0])
    held = engaged_rollers(design, theta)
    marks: list[Mark] = []
    for cam in design.cams:
        k = cam.index
        marks.append(Area([_rot(theta, cam.profile)], fill=CAM_FILLS[k % 3], edge=CAM_EDGES[k % 3], width=1.1,
                          alpha=0.6, label=f"cam {k} (plane {k})", gid=f"cam-{k}"))
    p_fix = np.array([c_dist, 0.0])
    marks.append(Curve(*_circle(p_fix, rp).T, color=css_color("0.45"), width=0.8, dash="-.",
                       label="turret pitch circle R_p", gid="turret-pitch-circle"))
    engaged_label: str | None = "engaged roller"
    for cam in design.cams:
        k = cam.index
        centres, _, _ = roller_state(ix, k, np.arange(n), np.full(n, float(theta)))
        spokes = np.full((3 * n, 2), np.nan)
        spokes[0::3], spokes[1::3] = p_fix, centres
        marks.append(Curve(spokes[:, 0], spokes[:, 1], color=CAM_EDGES[k % 3], width=0.4, alpha=0.5))
        for j, c in enumerate(centres):
            ring = _circle(c, rr)
            on = j in held[k]
            if on:
                marks.append(Area([ring], fill=ENGAGED_FILL, alpha=0.95, label=engaged_label, gid=f"engaged-{k}-{j}"))
                engaged_label = None
            marks.append(Curve(ring[:, 0], ring[:, 1], color=CAM_EDGES[k % 3], width=1.8 if on else 0.8,
                               label=f"plane {k}'s rollers" if j == 0 else None, gid=f"roller-{k}-{j}"))
    marks.append(Curve(np.array([0.0, c_dist]), np.array([0.0, 0.0]), color=css_color("0.55"), width=0.6, dash="--"))
    for x, name, gid in ((0.0, "O: input axis (turns CCW)", "input-axis"),
                         (c_dist, "P: turret axis (turns CW)", "turret-axis")):
        marks.append(Curve(np.array([x]), np.array([0.0]), line=False, marker="+", color="#000000", size=10, gid=gid))
        marks.append(Note(x, 0.0, name, size=7.0, dx=4.0, dy=-9.0, anchor="start", valign="top"))
    r_cam = max(float(np.max(np.hypot(*c.profile.T))) for c in design.cams)
    marks.append(Note(-r_cam, max(r_cam, rp + rr), f"θ = {math.degrees(theta):.2f}°, turret ψ(θ) = "
                      f"{math.degrees(psi):.4f}° (clockwise)", size=8.0, dx=0.0, dy=0.0, anchor="start",
                      valign="top", boxed=True, gid="turret-angle"))
    title = (f"parallel indexer: N = {int(ix.stations)}, β = {math.degrees(float(ix.index_angle)):g}°, {ix.law}, "
             f"C = {c_dist:g}, R_p = {rp:g}, r_r = {rr:g} mm, {len(design.cams)} cams\n"
             f"fixed frame at input angle θ = {math.degrees(theta):g}°")
    return Panel(marks, xlabel="x [mm]", ylabel="y [mm]", title=title, equal=True, legend="below",
                 legend_columns=3, height=360.0)


def indexer_picture(design: ParallelDesign, theta: float = 0.0) -> Chart:
    """The indexer in the fixed frame at input angle ``theta`` [rad]: each cam's profile turned by θ
    (filled, one colour per cam), the turret's pitch circle, every roller of every plane (the ones
    their cam holds filled and drawn thick), the input and turret axes, and a note with ψ(θ) [deg]."""
    return Chart.stack([indexer_panel(design, theta)], width=640.0)


@PICTURES.register(ParallelIndexerDesign)
def indexer_design_picture(design: ParallelIndexerDesign, follower_angle_deg: float = 75.0) -> Chart:
    """The Python API's picture of a designed parallel indexer: :func:`indexer_picture` at the input
    angle ``follower_angle_deg`` [deg] (:data:`cam_workbench.exporters.plots.PICTURES`)."""
    return indexer_picture(design.geometry, math.radians(follower_angle_deg))


def indexer_motion_chart(design: ParallelDesign) -> Chart:
    """The turret's angle ψ [deg], ψ' = dψ/dθ [–] and ψ'' [1/rad] over the input turn, and the driving
    pressure angle [deg] (``design.driving_angle``) over the index; x: the input angle from the index
    start θ − θ_s [deg], the index shaded."""
    ix = design.indexer
    x = np.degrees(design.theta - float(ix.index_start))
    beta = math.degrees(float(ix.index_angle))
    series = ((np.degrees(design.psi), "turret angle ψ [deg]", "psi", CAM_EDGES[0]),
              (design.dpsi, "ψ' = dψ/dθ [–]", "dpsi", "#2e7d32"),
              (design.d2psi, "ψ'' [1/rad]", "d2psi", "#c0392b"))
    panels = []
    for i, (y, label, gid, color) in enumerate(series):
        p = angle_panel(ylabel=label, xticklabels=False, height=110.0,
                        title=(f"parallel indexer: N = {int(ix.stations)}, β = {beta:g}°, {ix.law}" if i == 0 else ""))
        p.add(Shade([(0.0, beta)], color=CAM_EDGES[0], alpha=0.08, label="index" if i == 0 else None),
              Curve(x, y, color=color, width=1.5, gid=gid))
        panels.append(p)
    over = x <= beta + 1e-9
    phi = np.where(over, np.degrees(design.driving_angle), np.nan)
    p = angle_panel(xlabel="input angle θ − θ_s [deg]", ylabel="driving pressure\nangle [deg]", height=130.0)
    p.add(Shade([(0.0, beta)], color=CAM_EDGES[0], alpha=0.08), Curve(x, phi, color="#6a1b9a", width=1.5,
                                                                       gid="driving-angle"))
    if np.isfinite(phi).any():
        i_max = int(np.nanargmax(phi))
        p.add(Rule("y", float(phi[i_max]), color="#b03a2e", width=0.8, dash=":"),
              Note(float(x[i_max]), float(phi[i_max]), f"max {phi[i_max]:.2f}° at {x[i_max]:.1f}°", dy=-4.0,
                   valign="top"))
    panels.append(p)
    return Chart.stack(panels, width=640.0)


__all__ = ["CAM_EDGES", "CAM_FILLS", "engaged_rollers", "indexer_motion_chart", "indexer_panel", "indexer_picture"]

"""Figures of the follower train's dynamics as :class:`~.chart.Chart` s: one steady-state revolution
at speed (:func:`dynamics_figure`) and the jump-speed sweep (:func:`jump_speed_figure`).

The marks that stand for report.json's numbers carry the ids of :data:`DYNAMICS_GIDS`
(:meth:`~.chart.Chart.marks`), so a reader of the figure or of its SVG can find them.
"""
from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from cam_workbench.generators.dynamics import DynamicsResult

from .chart import Chart, Curve, Note, Panel, Rule, Shade, angle_panel, css_color, segment_marks
from .plots import COLORS, small_unit

#: SVG ids of the dynamics figures' marks: the operating speed, the jump speeds, the smallest force
DYNAMICS_GIDS = {"speed": "dyn-speed", "jump": "dyn-jump-speed", "rigid_jump": "dyn-rigid-jump-speed",
                 "min_force": "dyn-min-force"}

_RIGID = css_color("0.45")


def off_cam_spans(deg: np.ndarray, on_cam: np.ndarray) -> list[tuple[float, float]]:
    """The (first, last) angles of every run of samples where the follower is off the cam."""
    off = ~np.asarray(on_cam, dtype=bool)
    edges = np.flatnonzero(np.diff(np.r_[False, off, False].astype(np.int8)))
    return [(float(deg[i]), float(deg[j - 1])) for i, j in zip(edges[::2], edges[1::2])]


def _angle_panel(result: DynamicsResult, ylabel: str, legend: str, last: bool, labels: bool = False) -> Panel:
    """A panel over the cycle with the program's segment boundaries (and, with ``labels``, the
    segments' kinds on top) and the spans off the cam shaded."""
    rules, kinds = segment_marks(np.rad2deg(result.program.boundaries), result.program.kinds if labels else None)
    ax = angle_panel(ylabel=ylabel, legend=legend, top_labels=kinds, xlabel="cam angle θ [deg]" if last else "",
                     xticklabels=last)
    ax.add(*rules)
    spans = off_cam_spans(result.theta_deg, result.on_cam)
    if spans:
        ax.add(Shade(spans, color=COLORS["a"], alpha=0.12, label="off the cam"))
    return ax


def dynamics_figure(result: DynamicsResult, section: Mapping[str, Any]) -> Chart:
    """The follower train over one steady-state revolution (:class:`cam_workbench.generators.dynamics.DynamicsResult`):
    the normal contact force, rigid and dynamic; the camshaft torque, rigid and dynamic; the
    displacement error q − s and its vibration about the quasi-static deflection. ``section`` is
    report.json's ``dynamics`` section: the marked smallest force is its value at its angle."""
    deg = result.theta_deg
    c = section["contact"]
    scale, unit = small_unit(result.units, result.lift_unit)
    turret = result.turret                              # an indexer's output train: the shaft torque
    force = _angle_panel(result, f"{'shaft torque' if turret else 'contact force'} [{c['unit']}]", "upper right",
                         last=False, labels=True)
    force.add(Curve(deg, result.rigid_force, color=_RIGID, width=0.9, dash="--",
                    label="rigid shaft (J·ψ̈)" if turret else "rigid follower"),
              Curve(deg, result.force, color=COLORS["s"], width=1.1, label=f"dynamic at {section['speed_rpm']:.4g} rpm"),
              Rule("y", 0.0, color=COLORS["limit"], width=0.8, dash=":"),
              Curve(np.array([c["min_force_at_deg"]]), np.array([c["min_force"]]), marker="o", line=False, size=5.0,
                    color=COLORS["fail" if not c["kept"] else "pass"], edge="#000000", gid=DYNAMICS_GIDS["min_force"]),
              Note(c["min_force_at_deg"], c["min_force"], f"min {c['min_force']:.4g} {c['unit']} at "
                   f"{c['min_force_at_deg']:.1f}°", size=7.0, dx=8.0, dy=8.0, valign="bottom"))
    torque = _angle_panel(result, f"camshaft torque [{section['torque']['unit']}]", "upper right", last=False)
    torque.add(Curve(deg, result.rigid_torque, color=_RIGID, width=0.9, dash="--", label="rigid"),
               Curve(deg, result.torque, color=COLORS["a"], width=1.1, label="dynamic"),
               Rule("y", 0.0, color=css_color("0.6"), width=0.6, dash="-"))
    error = _angle_panel(result, f"{'angle' if turret else 'displacement'} error [{unit}]", "lower right", last=True)
    error.add(Curve(deg, result.error * scale, color=COLORS["v"], width=1.0, label="φ − ψ" if turret else "q − s"),
              Curve(deg, result.vibration * scale, color=COLORS["j"], width=0.8,
                    label="vibration about the quasi-static deflection"))
    return Chart.stack([force, torque, error])


def jump_speed_figure(result: DynamicsResult, section: Mapping[str, Any]) -> Chart:
    """The jump-speed curve: the smallest contact force over the cycle against the cam speed, with
    the analysis speed and the jump speeds (dynamic and rigid) of report.json's ``dynamics``
    section marked (``result`` is not drawn: the sweep is the section's)."""
    jp = section["jump_speed"]
    sweep = jp["sweep"]
    ax = Panel(xlabel="cam speed [rpm]", ylabel=f"min contact force [{section['contact']['unit']}]",
               legend="lower left", height=220.0)
    ax.add(Curve(np.asarray(sweep["speeds_rpm"], dtype=float), np.asarray(sweep["min_force"], dtype=float),
                 color=COLORS["s"], width=1.0, marker="o", size=2.0,
                 label="smallest contact force over a revolution (< 0: the cam would have to pull)"),
           Rule("y", 0.0, color=COLORS["limit"], width=0.8, dash=":"),
           Rule("x", section["speed_rpm"], color=COLORS["v"], width=1.0, dash="-", gid=DYNAMICS_GIDS["speed"],
                label=f"analysis speed {section['speed_rpm']:.4g} rpm"))
    if jp["rpm"] is not None:
        ax.add(Rule("x", jp["rpm"], color=COLORS["a"], width=1.2, dash="--", gid=DYNAMICS_GIDS["jump"],
                    label=f"jump speed {jp['rpm']:.5g} rpm"))
    if jp["rigid_rpm"] is not None and jp["sweep_from_rpm"] <= jp["rigid_rpm"] <= jp["sweep_to_rpm"]:
        ax.add(Rule("x", jp["rigid_rpm"], color=_RIGID, width=0.9, dash=":", gid=DYNAMICS_GIDS["rigid_jump"],
                    label=f"rigid follower's {jp['rigid_rpm']:.5g} rpm"))
    return Chart.stack([ax])

"""A machine's figures as data (:class:`.chart.Chart`, drawn by :mod:`.chart_svg`, rasterised by
:mod:`.chart_png`): the timing diagram and the camshaft torque with the flywheel's energy.

==========================  ==================================================================
figure                      what it shows
==========================  ==================================================================
:func:`timing_chart`        displacement, velocity, acceleration of every follower against the
                            machine angle (one row per quantity, one colour per cam), each rise
                            and return labelled ("pusher rise"); a cam driving a linkage also
                            its tool's (dashed, "<cam> tool"); and every tool point's x, y
:func:`torque_chart`        each cam's camshaft torque and their sum; the energy E(θ) with ΔE
==========================  ==================================================================

SVG ids (``gid``): ``timing-<cam>-s``, ``-v``, ``-a``, the tool's ``timing-<cam>-tool-s``, ``-tool-v``,
``-tool-a`` (a cam with a linkage) and ``-tool-x``/``-tool-y`` for the curves,
``event-<cam>-<segment>`` for an event's label, ``torque-<cam>``, ``torque-total``, ``energy``.
"""
from __future__ import annotations

from typing import Any, Mapping, Sequence

import numpy as np

from cam_workbench.generators.machine.analysis import MachineResult
from cam_workbench.generators.machine.torque import JOULES_PER_TORQUE_RAD

from .chart import Chart, Curve, Note, Panel, Rule, angle_panel

#: one colour per cam, in the machine's order (repeating after eight)
CAM_COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2")
TOTAL_COLOR = "#1c2833"


def cam_color(i: int) -> str:
    """The colour of the machine's ``i``-th cam."""
    return CAM_COLORS[i % len(CAM_COLORS)]


def _closed(theta_deg: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The periodic samples with the turn's end (360°) appended."""
    return np.append(theta_deg, 360.0), np.append(y, y[0])


def timing_chart(result: MachineResult, summary: Mapping[str, Any]) -> Chart:
    """The timing diagram: rows s, v, a over the machine angle, one labelled curve per cam and,
    dashed, one per tool a linkage drives ("<cam> tool"); a last row with every tool point's x, y
    in the machine plane; each rise/return marked at its start and end in the cam's colour and
    labelled with its name from machine.json's ``events``."""
    deg = result.theta_deg
    units = sorted({t.lift_unit for t in result.timings})
    lift = " or ".join(units)
    rows = [("s", f"displacement [{lift}]", "displacement"), ("v", f"velocity [{lift}/s]", "velocity"),
            ("a", f"acceleration [{lift}/s²]", "acceleration")]
    panels = []
    for r, (key, ylabel, title) in enumerate(rows):
        p = angle_panel(ylabel=ylabel, height=150.0, xticklabels=True,
                        legend="right" if r == 0 else None,
                        title=f"{summary['machine']['name']}: timing at {summary['machine']['speed_rpm']:.6g} rpm"
                        if r == 0 else "")
        for i, (t, cam) in enumerate(zip(result.timings, summary["cams"])):
            x, y = _closed(deg, getattr(t, key))
            label = f"{t.name} ({t.lift_unit}, phase {cam['phase_deg']:.6g}°)" if r == 0 else None
            p.add(Curve(x, y, color=cam_color(i), width=1.3, label=label, gid=f"timing-{t.name}-{key}"))
            tool = getattr(t, f"tool_{key}")
            if tool is not None:
                x, y = _closed(deg, tool)
                label = f"{t.name} tool ({t.lift_unit}, {cam['linkage']['kind']})" if r == 0 else None
                p.add(Curve(x, y, color=cam_color(i), width=1.1, dash="--", label=label,
                            gid=f"timing-{t.name}-tool-{key}"))
        if key == "s":
            _event_marks(p, result, summary)
        if r == len(rows) - 1:
            p.xlabel = "machine angle [deg]"
        panels.append(p)
    tools = [(i, t) for i, t in enumerate(result.timings) if t.tool is not None]
    if tools:
        p = angle_panel(ylabel="tool point [" + summary["units"] + "]", height=150.0, legend="right",
                        xlabel="machine angle [deg]")
        for i, t in tools:
            for k, (axis, dash) in enumerate((("x", "-"), ("y", ":"))):
                x, y = _closed(deg, t.tool[:, k])
                p.add(Curve(x, y, color=cam_color(i), dash=dash, label=f"{t.name} tool {axis}",
                            gid=f"timing-{t.name}-tool-{axis}"))
        panels[-1].xlabel = ""
        panels.append(p)
    return Chart.stack(panels, width=760.0)


def _event_marks(p: Panel, result: MachineResult, summary: Mapping[str, Any]) -> None:
    """Each rise/return's start and end as thin rules in its cam's colour, its name written at
    its middle on the follower's curve."""
    for i, (t, cam) in enumerate(zip(result.timings, summary["cams"])):
        for e in cam["events"]:
            a, b = e["start_deg"], e["end_deg"]
            for at in (a, b):
                p.add(Rule("x", float(at), color=cam_color(i), width=0.5, dash=":"))
            span = (b - a) % 360.0
            mid = (a + 0.5 * span) % 360.0
            y = float(np.interp(mid, *_closed(result.theta_deg, t.s)))
            p.add(Note(mid, y, e["label"], color=cam_color(i), size=7.5, dx=0.0, dy=6.0, anchor="middle",
                       valign="bottom", boxed=True, gid=f"event-{t.name}-{e['segment']}"))


def torque_chart(result: MachineResult, summary: Mapping[str, Any]) -> Chart:
    """The camshaft torque: each cam's (thin, its colour) and the machine's total (thick), the
    mean as a rule; below, the energy E(θ) = ∫(T − T_mean)dθ whose range ΔE sizes the flywheel."""
    deg = result.theta_deg
    tq = summary["torque"]
    fw = summary["flywheel"]
    unit = tq["unit"]
    p = angle_panel(ylabel=f"camshaft torque [{unit}]", height=200.0, legend="right",
                    title=f"camshaft torque: max {tq['max']:.6g}, min {tq['min']:.6g}, RMS {tq['rms']:.6g} {unit}")
    for i, t in enumerate(result.timings):
        x, y = _closed(deg, result.torques[i])
        p.add(Curve(x, y, color=cam_color(i), width=1.0, label=t.name, gid=f"torque-{t.name}"))
    x, y = _closed(deg, result.total)
    p.add(Curve(x, y, color=TOTAL_COLOR, width=2.0, label="total", gid="torque-total"))
    p.add(Rule("y", float(tq["mean"]), color="#7f8c8d", width=0.8, label=f"mean {tq['mean']:.6g}", gid="torque-mean"))
    j = _joules(summary)
    e = result.flywheel.energy * j
    q = angle_panel(ylabel="E(θ) [J]", height=140.0, xlabel="machine angle [deg]",
                    title=f"flywheel: ΔE {fw['energy_fluctuation_J']:.6g} J, I {fw['inertia_kg_m2']:.6g} kg·m² "
                          f"at C_s {fw['speed_fluctuation']:.6g}")
    x, y = _closed(deg, e)
    q.add(Curve(x, y, color=TOTAL_COLOR, width=1.3, gid="energy"))
    for at, word in ((fw["energy_max_at_deg"], "max"), (fw["energy_min_at_deg"], "min")):
        val = float(np.interp(at, x, y))
        q.add(Curve(np.array([at]), np.array([val]), marker="o", line=False, color="#c0392b", size=4.0,
                    gid=f"energy-{word}"))
    return Chart.stack([p, q], width=760.0)


def _joules(summary: Mapping[str, Any]) -> float:
    """J per (torque unit × rad), from machine.json's numbers (ΔE in J over ΔE in torque units)."""
    return JOULES_PER_TORQUE_RAD[summary["units"]]


def figure_names() -> Sequence[str]:
    """The machine's figure files, SVG and PNG of each."""
    return ("timing.svg", "timing.png", "torque.svg", "torque.png")


__all__ = ["CAM_COLORS", "cam_color", "figure_names", "timing_chart", "torque_chart"]

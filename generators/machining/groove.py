"""Milling a groove cam's groove (XY, the cam fixed on the table): a tool smaller than the groove
runs along exact offsets of the pitch curve — the roughing passes between the walls, then one
finishing pass against each wall — at every depth level.

The groove is the band between the pitch curve's offsets at ±w/2 (w = 2r + clearance); a tool of
radius R_t < w/2 touches the inner wall when its centre runs on the offset at −(w/2 − R_t) and the
outer wall on +(w/2 − R_t).  Those tool-centre curves are exact rational NURBS offsets of a PH pitch
curve (fitted B-splines for a B-spline pitch curve, with their error measured), emitted as biarcs
or chords within the chord tolerance (:func:`cam_workbench.generators.machining.toolpath.fit_contour`).  Passes
between the walls are spaced at most 1.6·R_t apart so that neighbours overlap.

Directions follow ``machining.milling`` with spindle M3: climb milling runs the pass against the
inner wall clockwise (an outside contour) and the pass against the outer wall counter-clockwise
(an inside contour); conventional milling the other way.  Each level is entered by a plunge at the
middle of the longest dwell (a centre-cutting end mill).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..bodies.groove import GrooveBody, groove_depth, half_width
from ..curves.approx import Path2D
from ..curves.nurbs import NurbsCurve
from ..errors import SpecError, fmt_apart
from ..kinds import register_tool_path
from .plan import MachiningPlan
from .toolpath import entry_junction, fit_contour, reverse_path, _roll

#: largest distance between neighbouring passes, in tool radii (they overlap by 0.4 R_t)
STEPOVER = 1.6


@dataclass(frozen=True)
class GroovePass:
    """One closed pass: its tool-centre curve (outward offset ``offset`` of the pitch curve),
    the fitted moves from the entry point round and back, and what it is for."""

    offset: float
    role: str              # "rough", "inner_wall" or "outer_wall"
    curve: NurbsCurve
    loop: Path2D
    clockwise: bool
    max_distance: float


@dataclass(frozen=True)
class GroovePath:
    """Every pass of every depth level (cam frame = machine XY, spec units)."""

    passes: tuple[GroovePass, ...]
    z_levels: np.ndarray
    entry_angle_deg: float
    tolerance: float
    groove_width: float
    depth: float

    @property
    def max_distance(self) -> float:
        return max(p.max_distance for p in self.passes)

    def summary(self) -> dict[str, Any]:
        """Numbers for report.json (spec units, degrees)."""
        return {"passes_per_level": len(self.passes), "levels": int(self.z_levels.shape[0]),
                "offsets": [p.offset for p in self.passes], "roles": [p.role for p in self.passes],
                "moves": int(sum(p.loop.n for p in self.passes)), "max_distance": self.max_distance,
                "chord_tolerance": self.tolerance, "entry_at_deg": self.entry_angle_deg,
                "groove_width": self.groove_width, "depth": self.depth}


def groove_offsets(half: float, tool_radius: float) -> np.ndarray:
    """Tool-centre offsets of the passes, middle first, the two walls last."""
    span = half - tool_radius
    n = max(2, int(math.ceil(2 * span / (STEPOVER * tool_radius))) + 1)
    d = np.linspace(-span, span, n)
    inner = d[1:-1]
    order = np.argsort(np.abs(inner), kind="stable")
    return np.concatenate([inner[order], [-span, span]])


@register_tool_path(GrooveBody.kind)
def groove_path(design, plan: MachiningPlan) -> GroovePath:
    """The groove's passes for ``plan`` (see the module docstring).

    Raises:
        SpecError: ``machining.program`` other than "xy"; ``machining.tool_radius`` — the tool is
            not smaller than the groove.
    """
    if plan.program != "xy":
        raise SpecError("machining.program", 'a groove is milled with the XY program ("xy"); the XC rotary '
                        "program cuts a plate cam's outside profile")
    spec = design.spec
    w2 = half_width(spec)
    rt = plan.tool_radius
    if not rt < w2:
        raise SpecError("machining.tool_radius", f"must be < half the groove width (w/2 = {fmt_apart(w2, rt)}) to "
                        f"mill the groove, got {fmt_apart(rt, w2)}")
    k = entry_junction(design.pitch)
    u_entry = float(design.pitch.junction_parameters[k])
    passes = []
    span = w2 - rt
    for d in groove_offsets(w2, rt):
        curve = design.pitch_nurbs if d == 0 else design.pitch_offset_curve(float(d))
        path, dist = fit_contour(curve, plan.chord_tolerance, arcs=plan.contour == "arcs")
        role = "inner_wall" if d == -span else "outer_wall" if d == span else "rough"
        # climb milling (M3): the inner wall like an outside contour (clockwise), the outer like an inside one
        clockwise = (d <= 0) == (plan.milling == "climb")
        if clockwise != (curve.area() < 0):
            path = reverse_path(path)
        p = curve.evaluate(np.array([u_entry]))[0]
        entry = complex(p[0], p[1])
        path = _roll(path, int(np.argmin(np.abs(path.start - entry))))
        passes.append(GroovePass(float(d), role, curve, path, clockwise, dist))
    return GroovePath(tuple(passes), plan.z_levels, float(np.rad2deg(design.pitch.angles[k])), plan.chord_tolerance,
                      2 * w2, groove_depth(spec))

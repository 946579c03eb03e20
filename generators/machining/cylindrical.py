"""Milling a cylindrical cam's groove on a 4-axis (X, Z, A) machine: the cam's axis along machine X,
the tool's axis radial (machine Z, pointing at the cam axis: Z = the tool tip's distance from the
cam axis, Z0 on the axis), A the cam's rotation about its axis [deg].

The developed pitch curve C_Rp is the roller centre's path (``generators/bodies/cylinder_path.py``): for a
translating follower (R_p·φ(θ), z₀ + s), for an oscillating one the arm's arc in the developed pitch
plane.  The tool sits where the roller sits: at machine A the cam has turned by A (A = θ for a ccw cam, −θ for
cw), so the cam-frame polar angle under the tool is ψ = π/2 − A.  A tool centre line at (ψ_t, z_t)
is reached with A = 90° − ψ_t (unwrapped, continuous over the turn) and X = z_t.

Passes (every depth level; a tool of radius R_t < w/2, default ¾·w/2): along the developed pitch
curve C_Rp and its offsets at the pitch radius by d (|d| ≤ w/2 − R_t), the two walls last
(d = ∓(w/2 − R_t): the lower wall, then the upper).  A move is a straight line in (X, A): a helix on
every cylinder, a straight chord in every developed plane; the points are spaced so that every chord
is within ``machining.chord_tolerance`` of the tool-centre path at the cylinder's outer radius (the
largest chord error of the radii the tool reaches).  Each pass is entered by a plunge at the middle
of the longest dwell (a centre-cutting end mill) and runs one full turn.

What is approximate: a radial tool offset from the pitch curve cuts the exact wall only at the
pitch radius — at radius ρ its section runs along the scaled path (ρ/R_p·x_t, z_t), while the exact
wall is the offset of C_ρ; the finishing passes' deviation from the exact walls at the groove's bottom
and top radii is computed (``finish_wall_deviation``) and reported.  A tool of the groove's width
(d = 0) has none.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..bodies.cylindrical import CylinderLayout
from ..errors import SpecError, fmt_apart
from .groove import groove_offsets
from .plan import _UNIT_DEFAULTS
from ..bodies.cylindrical import wall_points


@dataclass(frozen=True)
class CylPass:
    offset: float
    role: str                   # "rough", "lower_wall", "upper_wall"
    x: np.ndarray               # machine X (cam z) of the tool centre line, the points of the pass
    a: np.ndarray               # machine A [deg]
    chord_error: float


@dataclass(frozen=True)
class CylindricalPath:
    """Every pass of every level of a cylindrical cam's groove (spec units, degrees)."""

    passes: tuple[CylPass, ...]
    z_levels: np.ndarray         # machine Z of the tool tip per level (radius from the cam axis)
    tool_radius: float
    tool_number: int
    spindle_rpm: float
    feed_rate: float
    plunge_rate: float
    safe_z: float
    chord_tolerance: float
    entry_deg: float
    groove_width: float
    finish_wall_deviation: dict
    units: str
    coolant: bool
    line_numbers: bool
    work_offset: str

    def summary(self) -> dict[str, Any]:
        return {"program": "xza", "machine": "4-axis X, Z, A: cam axis along X, tool axis radial along Z "
                "(Z = distance of the tool tip from the cam axis), A = cam rotation [deg]",
                "tool_radius": self.tool_radius, "passes_per_level": len(self.passes),
                "levels": [float(z) for z in self.z_levels], "offsets": [p.offset for p in self.passes],
                "roles": [p.role for p in self.passes], "moves": int(sum(len(p.x) - 1 for p in self.passes)),
                "chord_tolerance": self.chord_tolerance,
                "max_chord_error": max(p.chord_error for p in self.passes), "entry_at_deg": self.entry_deg,
                "groove_width": self.groove_width, "finish_wall_deviation": self.finish_wall_deviation}


def _centre_path(lay: CylinderLayout, program, d: float, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(ψ_t, z_t) of the tool centre line offset by d (+: towards +z) from C_Rp, at cam angles θ
    (C_Rp: the roller centre's developed path at the pitch radius, translating or oscillating)."""
    rp = lay.pitch_radius
    x, z = lay.centre_line(program, theta, rp).offset(lay.sense, d)
    return x / rp, z


def _chord_error(lay, program, d, theta, radius) -> float:
    """Largest distance, in the developed plane at ``radius``, of the path's midpoints from the chords."""
    psi, z = _centre_path(lay, program, d, theta)
    pm, zm = _centre_path(lay, program, d, (theta[:-1] + theta[1:]) / 2)
    a = np.column_stack([radius * psi[:-1], z[:-1]])
    b = np.column_stack([radius * psi[1:], z[1:]])
    m = np.column_stack([radius * pm, zm])
    ab = b - a
    t = np.clip(np.sum((m - a) * ab, axis=1) / np.maximum(np.sum(ab * ab, axis=1), 1e-300), 0, 1)
    return float(np.max(np.linalg.norm(m - (a + t[:, None] * ab), axis=1)))


def _entry_angle(program) -> float:
    """Middle of the longest dwell (else 0) [rad]."""
    dwell = [k for k, law in enumerate(program.laws) if law is None]
    if not dwell:
        return 0.0
    k = max(dwell, key=lambda i: program.spans[i])
    return float(program.starts[k] + program.spans[k] / 2)


def finish_deviation(lay: CylinderLayout, program, rt: float, radius: float, n: int = 4000) -> float:
    """Largest |distance of the exact wall at ``radius`` from the finishing tool's centre path there|
    − R_t, over both walls (0 at the pitch radius)."""
    from scipy.spatial import cKDTree  # deferred: scipy.spatial, this measure alone

    span = lay.half_width - rt
    th = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    worst = 0.0
    dense = np.linspace(0.0, 2 * np.pi, 20 * n, endpoint=False)
    for side in (-1, 1):
        psi, z = _centre_path(lay, program, side * span, dense)
        pts = np.column_stack([radius * psi, z])
        w = wall_points(lay, program, side, th, np.full(th.shape, radius))
        wpsi = np.arctan2(w[:, 1], w[:, 0])
        # unwrap the wall's angle next to the centre path's
        ref = lay.centre_line(program, th, radius).x / radius
        wpsi = ref + ((wpsi - ref + np.pi) % (2 * np.pi) - np.pi)
        q = np.column_stack([radius * wpsi, w[:, 2]])
        # the path is periodic in x with 2πρ: query with the copies
        period = 2 * np.pi * radius
        allp = np.concatenate([pts + [s * period, 0] for s in (-1, 0, 1)])
        dist, _ = cKDTree(allp).query(q)
        worst = max(worst, float(np.max(np.abs(dist - rt))))
    return worst


def cylindrical_path(design) -> CylindricalPath:
    """The passes of ``design`` (a CylindricalDesign) for its spec's ``[machining]``.

    Raises:
        SpecError: ``machining.tool_radius`` not smaller than half the groove; ``machining.program``
        "xc" (the rotary plate program) asked of a cylindrical cam.
    """
    spec = design.spec
    mc = spec.machining
    lay = design.layout
    prog = design.program
    dflt = _UNIT_DEFAULTS[spec.units]
    w2 = lay.half_width
    rt = mc.tool_radius if mc.tool_radius is not None else 0.75 * w2
    if not rt < w2:
        raise SpecError("machining.tool_radius", f"must be < half the groove width (w/2 = {fmt_apart(w2, rt)}) to "
                        f"mill the groove, got {fmt_apart(rt, w2)}")
    if mc.program != "xy":
        raise SpecError("machining.program", "a cylindrical cam is milled by its own 4-axis X-Z-A program; leave "
                        "machining.program at its default")
    tol = float(mc.chord_tolerance if mc.chord_tolerance is not None else dflt["chord_tolerance"])
    depth = lay.outer_radius - lay.bottom_radius
    total = float(mc.depth) if mc.depth is not None else depth
    if total > depth + 1e-12:
        raise SpecError("machining.depth", f"must be ≤ groove.depth ({fmt_apart(depth, total)}) for a cylindrical "
                        f"cam, got {fmt_apart(total, depth)}")
    levels = lay.outer_radius - total * np.arange(1, mc.passes + 1) / mc.passes
    entry = _entry_angle(prog)
    passes = []
    span = w2 - rt
    offsets = [float(v) for v in groove_offsets(w2, rt)]
    if 0.0 not in offsets:                # the first pass always runs along the pitch curve itself
        offsets.insert(0, 0.0)
    for d in offsets:
        n = 720
        while True:
            th = entry + np.linspace(0.0, 2 * np.pi, n + 1)
            err = max(_chord_error(lay, prog, d, th, lay.outer_radius), _chord_error(lay, prog, d, th, lay.bottom_radius))
            if err <= tol or n > 200000:
                break
            n = int(n * max(1.5, math.sqrt(err / tol) * 1.1))
        psi, z = _centre_path(lay, prog, d, th)
        a = np.rad2deg(np.unwrap(np.pi / 2 - psi))
        role = "lower_wall" if d == -span else "upper_wall" if d == span else "rough"
        passes.append(CylPass(d, role, z, a, err))
    dev = {"bottom_radius": finish_deviation(lay, prog, rt, lay.bottom_radius),
           "outer_radius": finish_deviation(lay, prog, rt, lay.outer_radius),
           "unit": spec.units,
           "what": "finishing passes' wall vs the exact wall (a radial tool offset at the pitch radius)"}
    feed = float(mc.feed_rate if mc.feed_rate is not None else dflt["feed_rate"])
    return CylindricalPath(tuple(passes), levels, float(rt), mc.tool_number, mc.spindle_rpm, feed,
                           float(mc.plunge_rate if mc.plunge_rate is not None else feed / 3),
                           lay.outer_radius + float(mc.safe_height if mc.safe_height is not None else dflt["safe_height"]),
                           tol, float(np.rad2deg(entry)), 2 * w2, dev, spec.units, mc.coolant, mc.line_numbers,
                           mc.work_offset)

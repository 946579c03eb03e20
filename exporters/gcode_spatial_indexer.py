"""LinuxCNC generating programs for the cam of a SPATIAL indexer — the barrel (cylindrical-cam)
indexer or the globoidal (roller-gear) indexer of
:mod:`cam_workbench.generators.bodies.indexing.spatial` (its module docstring holds the frames and
signs used here: the fixed frame, cam axis z, turret axis through P = (C, 0, 0) along +y, the
turret angle ψ(θ), roller j's axis c(t) = a + t·d).

The method: GENERATING.  A cutter of the roller's radius r_r (an end mill, flat end) takes the
place of roller 0 and follows roller 0's motion relative to the cam: the cam turns through the
input angle θ, the cutter's axis lies on the roller's axis and swings with the turret.  Roller j at
input angle θ has the pose of roller 0 at θ + 2πj (ψ(θ + 2πj) = ψ(θ) + j·T, T = 2π/N), so ONE
continuous sweep of roller 0's locus τ ↦ pose(τ) — the cam turning about two turns while the turret
indexes through the cam — cuts every roller's groove; the cam is what is left.

Machine (5 words X Y Z A C, LinuxCNC ``trivkins`` coordinates XYZAC, mm and degrees)
    * Machine frame = the frame of the cam's STEP solid (``cam.step``,
      :class:`cam_workbench.kernel.spatial_indexer.SpatialSolids`: the design's frame moved up by
      W/2 along the cam axis, so the cam spans 0 ≤ z ≤ W = ``cam.thickness`` like every body's
      solid) at A = 0, renamed: X = z (along the cam axis, from the STEP's z = 0 end face), Y = x
      (along the common perpendicular, from the cam axis towards the turret axis), Z = y (parallel
      to the turret axis, up).  Right-handed.  Origin (G54) O = the STEP solid's origin: on the cam
      axis, in the plane of the cam's end face z = 0 (the cam occupies 0 ≤ X ≤ W) — the one origin
      of cam.step in a CAM system and of cam.nc on the machine.  In the indexer's fixed frame of
      spatial.py (centred on the cam's middle plane) a point (x, y, z) is at X = z + W/2, Y = x,
      Z = y.  The cam axis is the machine X axis; the turret axis is the vertical line X = W/2,
      Y = C (the turret's plane, the cam's middle plane, is X = W/2).
    * A = the input angle θ in degrees: the cam is turned by A about +X, right-handed
      (counter-clockwise seen from +X).  A point q = (x_s, y_s, z_s) of cam.step (the cam frame
      moved up by W/2) is at X = z_s, Y = x_s·cos A − y_s·sin A, Z = x_s·sin A + y_s·cos A; at
      A = 0 the program's coordinates are cam.step's renamed (its x axis along machine +Y, its y
      axis along +Z, its z axis along +X).  A is NOT reduced to a turn: a sweep runs
      A = τ over about two turns, and the rapids between sweeps turn it back by hundreds of
      degrees, so A must be an unwrapped rotary axis (no ``WRAPPED_ROTARY``) with limits beyond
      the range the header quotes (every G1 turns it by ≤ ``step_deg`` ≤ 90°).
    * C = the turret angle ψ in degrees, the direction the turret indexes: positive C swings the
      cutter CLOCKWISE seen from +Z (about −Z; set the C joint's sign so).  The cutter stands where
      roller 0 stands when the turret is at ψ = C: at α = 180° − 180°/N + C (α the turret's polar
      angle, from +Y towards +X; at C = 0 roller 0's pose on the dwell).  Along a sweep C = ψ(A)
      continuous over turns (C = ψ(θ) + j·360°/N for roller j at input angle θ = A − 360°·j).
    * X, Y, Z = the TOOL TIP (the controlled point), the tool's axis along the roller's, d(C):
        barrel:    d = +Z: the tool vertical, spindle above, tip down; the tip at height t_k on
                   roller 0's axis: X = W/2 + R_p·sin α, Y = C + R_p·cos α, Z = t_k.  The tool's axis is
                   parallel to the turret axis, so C only turns the tool about its own axis: an
                   X-Y-Z-A vertical mill runs the program with the C words removed (or C a dummy
                   axis).  G43 H<tool> is the usual tool length along Z.
        globoidal: d = (sin α, cos α, 0): the tool horizontal and radial on the turret, the
                   spindle towards the turret axis, the tip pointing away from it at distance t_k
                   from P: X = W/2 + t_k·sin α, Y = C + t_k·cos α, Z = 0.  C swivels the head about the
                   vertical through the tool tip (a head whose pivot is the tip, or a tool-centre-
                   point kinematics; a head pivoting at a distance L behind the tip needs
                   X −= L·sin α, Y −= L·cos α in a post).  LinuxCNC's G43 offsets Z only, so this
                   program uses no tool-length offset (G49).
      In cam.step's frame the cutter's axis at (X, Y, Z, A, C) is the line
      Rz(−A)·((Y, Z, X) + s·d_f(C)) with d_f = (0, 1, 0) (barrel) or (cos α, 0, sin α)
      (globoidal) in the fixed frame; in the design's cam frame of spatial.py (z centred) it is
      Rz(−A)·((Y, Z, X − W/2) + s·d_f(C)) — which is what the tests rebuild from rs274's output,
      and they hold the cutter inside the band 0 ≤ z ≤ W of cam.step read through OCP.

Passes (one tool, radius R_t = r_r by default)
    * Depth levels: the tip's parameter t_k on the roller's axis steps from the rib's top to the
      final depth, ⌈depth/stepdown⌉ levels (or ``passes``), the last at the final depth:
        barrel:    from R_top (the rib's top cylinder) down to t = R_root; the flat end lies in the
                   plane y = t, at distance ≥ t from the cam axis: it never cuts below the root
                   (the floor it leaves between the ribs reaches the root cylinder where the end
                   covers the plane x = 0, i.e. |x_a| ≤ R_t for the axis at x = x_a, and stays
                   above it elsewhere);
        globoidal: from √(R_tip² − R_t²) (the end's corner meets the tip globoid) out to
                   √(R_root² − R_t²) (the corner reaches the root globoid, never beyond it).
      Every level is a ROUGHING sweep over the whole range [τ_in, τ_out] where the cutter (at the
      final depth, down to its tip) meets the blank — the rib's band (barrel ρ ≤ R_top, globoidal
      g ≥ R_tip, 0 ≤ X ≤ W) grown by 2 mm, tested at points of the cutter's surface ≤ 1.6 mm
      apart, τ on a 0.5° grid — so each sweep starts and ends with the cutter clear of the blank,
      where the next level is plunged (zigzag: forward, backward, …).
    * FINISHING: at the final depth one sweep per roller side s (+1, −1) over the input angles
      where that side is engaged (``design.sheet(s).in_band`` on roller 0's locus, one design row
      beyond at each end; every window (j, s, θ_from, θ_to) of ``design.windows`` is inside it as
      τ = θ + 2πj), run in the direction that makes it CLIMB milling with M3 for that side: the
      side's contact normal n (into the rib), the tool's direction e (spindle → tip) and the
      cutter's velocity v relative to the cam satisfy n·(e × v) > 0 (the share of the side's
      engaged contact points where it holds is quoted).  A roller-sized cutter in its groove
      touches both sides; the other side is then conventionally milled — the finishing sweeps are
      the roughing's last path again, each for its own side's climb, plunged and retracted along
      the tool axis inside the cut groove.
    * A tool radius R_t < r_r follows the same axis path: the cutter of radius R_t is the roller's
      surface offset by (r_r − R_t)·cos γ along its normal (a cylinder's by r_r − R_t), and the
      envelope of an offset surface in a rigid motion is the offset of its envelope — a uniform
      stock of (r_r − R_t)·cos γ on every flank (for a finishing cutter of r_r, or grinding).
      R_t > r_r is refused.
    * Conical rollers (``roller_cone_angle`` γ ≠ 0): the cutter is a tapered end mill of the
      roller's cone — radius R_t + (t − t_m)·tan γ at the roller's axis parameter t, R_t at the
      working length's middle t_m (the header gives its radius at the tip of the final depth); a
      globoid's cutter with γ > 0 widens towards its tip (a dovetail cutter).  The axis path is
      the roller's, as for a cylinder.

Sampling and what is measured (never exact)
    The G1 moves interpolate X, Y, Z, A and C linearly (trivkins), the exact relative pose is
    roller 0's axis at input angle θ = A (``roller_axis``/``roller_pose`` of spatial.py, ψ from
    ``turret_angle``).  A sweep is sampled on the input angle: the law's ends (kinks of ψ'', to
    the 0.0001° grid) are samples, each piece is divided in steps ≤ ``step_deg``, and every move whose CHORD ERROR is
    above (1 − BLEND_SHARE)·tolerance is halved until none is.  The chord error of a move is the
    largest distance, at 17 points λ = 0, 1/16, …, 1 of it, between the cutter's axis points as
    written (rounded words, linearly interpolated) and the roller's exact axis points at the same
    A, over the axis' reach t ∈ [min(t0, final depth), max(t1, rib's top)] (an affine function of
    t: its ends bound it) — it contains the rounding of the written words (4 decimals in mm and
    in degrees; A is sampled on the 0.0001° grid, so A is written exactly and C = ψ(A) to
    0.00005°).  The rest of the tolerance, ``G64 P`` = BLEND_SHARE·tolerance, is the controller's
    blending (LinuxCNC states that tolerance for X, Y, Z: where the blending of A and C matters,
    G61 turns blending off).
    Plunges and retracts run along the tool's axis at a fixed A.

Feeds: G93 inverse time on every G1: the moves mix linear and rotary axes, and under G94 LinuxCNC
reads F as X-Y-Z length per minute — the cam's turning, most of the cutter's motion relative to
the cam (all of it on the dwell, where only A moves), would not count.  F = feed / L with L the
longer cam-frame travel of the two ends of the cutter's axis reach over the move (polylines
through the 17 measuring points): the cutter's axis moves relative to the cam at ≤ ``feed``
mm/min on average over each move (its relative speed |w| = |Da + t·Dd| is convex in t: the reach's
ends are its fastest points).  Plunges at ``plunge_feed`` (default feed/3).

Safe: the tip retracted along the tool's axis to t_safe — barrel R_top + safe_height (above the
blank for any A); globoidal √(R_tip² − R_t²) − safe_height (the whole cutter inside the sphere of
radius R_tip about P, i.e. nearer the circle P traces than the tip globoid: clear for any A).
Rapids between sweeps go from safe pose to safe pose.  The first rapid assumes the tool starts
clear of the cam (above it for the barrel: ``G0 Z`` first; on the turret-axis side for the
globoidal).

Not here: a post for other controls (Fanuc/Siemens need their own rotary-axis and inverse-time
words, a TCP mode for the globoidal's horizontal tool), a dedicated roughing tool, the cam's hub
and bore, collision checks of the holder and spindle against the cam (only the cutter's flute
part is considered).
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from cam_workbench.generators import __version__
from cam_workbench.generators.bodies.indexing.spatial import (BarrelIndexer, GloboidalIndexer, SpatialDesign,
                                                             contact_lines, roller_alpha, roller_axis, turret_angle)
from cam_workbench.generators.errors import SolveError, SpecError
from cam_workbench.generators.machining.toolpath import BLEND_SHARE

from .atomic import write_text_atomic
from .gcode import GcodeWriter, fmt

Array = np.ndarray
TWO_PI = 2.0 * math.pi
#: decimals of the written words (mm and degrees)
DECIMALS = 4
#: A is sampled on this grid [deg] (so it is written exactly)
A_QUANTUM = 10.0 ** -DECIMALS
#: points per move (λ = k/LAMBDAS, k = 0 … LAMBDAS) at which the chord error is measured
LAMBDAS = 16
#: the blank's growth [mm] when finding where the cutter is clear of it
CLEARANCE = 2.0
#: the τ grid [deg] of that search
_SCAN_DEG = 0.5
#: the cutter's surface samples: angles round it, spacing along it [mm]
_RING = 48
_ALONG = 1.0
_MAX_ROUNDS = 40
#: LinuxCNC reads lines of at most 255 characters: longer comments are split
_COMMENT_WIDTH = 200


@dataclass(frozen=True)
class Sweep:
    """One sweep of the cutter along roller 0's locus.

    role: "roughing" or "finishing"; level: 1-based depth level; side: the roller side a
    finishing sweep is for (+1, −1; None for roughing); forward: A increasing; a_from, a_to: A
    [deg] at its start and end; tip_t: the tip's parameter t on the roller's axis [mm]; ticks:
    the sampled A in units of A_QUANTUM (ascending); words: the written X, Y, Z, A, C (rounded),
    in cutting order, (n, 5); chord_error: the largest measured chord error of its moves [mm];
    climb: for a finishing sweep, the share of its side's engaged contact points milled climb."""

    role: str
    level: int
    side: int | None
    forward: bool
    a_from: float
    a_to: float
    tip_t: float
    ticks: Array
    words: Array
    chord_error: float
    climb: float | None

    @property
    def moves(self) -> int:
        return int(self.words.shape[0] - 1)


@dataclass(frozen=True)
class SpatialProgram:
    """A spatial indexer's generating program and what was measured (mm, degrees).

    kind: "barrel" or "globoidal"; text: the program; tool_radius R_t, roller_radius r_r (at the
    working length's middle for a cone), cone_angle γ [deg] (0: a flat end mill; else the tapered
    cutter's half angle), tip_radius: the cutter's radius at its tip at the final depth [mm],
    stock = (r_r − R_t)·cos γ left on every flank; tolerance, budget = (1 − BLEND_SHARE)·tolerance (the
    moves' chord-error limit), blend = G64 P; chord_error: the largest measured chord error of
    every cutting move (module docs); levels: the tip's t per depth level (the last the final
    depth); safe_t: the retracted tip's t; reach: (t_lo, t_hi), the axis' reach the error is
    measured over; a_range: (τ_in, τ_out) [deg], the roughing sweeps' A; engaged: {side: (from,
    to)} [deg], roller 0's engaged locus per side (one design row beyond its ends); sweeps; moves
    (G1 moves of the sweeps), plunges, lines (of the text); step_deg: (smallest, largest) A step
    of the sweeps; c_range: (min, max) C [deg]; cam_x_range: (0, W), the cam's extent along
    machine X (cam.step's z, module docs); turret_axis: (X, Y) of the vertical turret axis [mm],
    (W/2, C)."""

    kind: str
    text: str
    tool_radius: float
    roller_radius: float
    cone_angle: float
    tip_radius: float
    stock: float
    tolerance: float
    budget: float
    blend: float
    chord_error: float
    levels: tuple[float, ...]
    safe_t: float
    reach: tuple[float, float]
    a_range: tuple[float, float]
    engaged: dict
    sweeps: tuple[Sweep, ...]
    moves: int
    plunges: int
    lines: int
    step_deg: tuple[float, float]
    c_range: tuple[float, float]
    feed: float
    plunge_feed: float
    cam_x_range: tuple[float, float]
    turret_axis: tuple[float, float]

    def summary(self) -> dict[str, Any]:
        """Plain numbers (mm, deg)."""
        return {"kind": self.kind, "machine": "X-Y-Z-A-C trivkins in cam.step's frame: X = cam axis [cam.step's z, "
                "X0 its z = 0 end face], Y = cam.step's x, Z = cam.step's y = turret axis direction, "
                "A = input angle, C = turret angle, X Y Z = tool tip",
                "cam_x_range_mm": list(self.cam_x_range), "turret_axis_xy_mm": list(self.turret_axis),
                "tool_radius_mm": self.tool_radius, "roller_radius_mm": self.roller_radius,
                "tool_cone_angle_deg": self.cone_angle, "tool_tip_radius_mm": self.tip_radius,
                "stock_mm": self.stock, "tolerance_mm": self.tolerance, "chord_budget_mm": self.budget,
                "g64_p_mm": self.blend, "chord_error_mm": self.chord_error, "levels_t_mm": list(self.levels),
                "safe_t_mm": self.safe_t, "reach_t_mm": list(self.reach), "a_range_deg": list(self.a_range),
                "engaged_deg": {str(k): list(v) for k, v in self.engaged.items()},
                "sweeps": [{"role": s.role, "level": s.level, "side": s.side, "forward": s.forward,
                            "a_from_deg": s.a_from, "a_to_deg": s.a_to, "tip_t_mm": s.tip_t, "moves": s.moves,
                            "chord_error_mm": s.chord_error, "climb_share": s.climb} for s in self.sweeps],
                "moves": self.moves, "plunges": self.plunges, "lines": self.lines,
                "step_deg": list(self.step_deg), "c_range_deg": list(self.c_range),
                "feed_mm_per_min": self.feed, "plunge_feed_mm_per_min": self.plunge_feed}


# ---- the machine mapping -------------------------------------------------------------------------

def _kind(ix: Any) -> str:
    if isinstance(ix, BarrelIndexer):
        return "barrel"
    if isinstance(ix, GloboidalIndexer):
        return "globoidal"
    raise SpecError("indexer", f"must be a BarrelIndexer or a GloboidalIndexer, got {type(ix).__name__}")


def _alpha_of_c(ix: Any, c_deg: Array) -> Array:
    """α [rad] of the cutter's axis at machine C [deg]: roller 0's at turret angle ψ = C."""
    return roller_alpha(ix, 0, np.radians(c_deg))


def exact_axis(ix: Any, tau: Array, t: Array) -> Array:
    """Roller 0's axis points a + t·d (fixed frame, (..., K, 3)) at input angles ``tau`` [rad]."""
    psi, _, _ = turret_angle(ix, np.asarray(tau, dtype=float))
    a, _, _, d, _, _ = ix.roller_pose(roller_alpha(ix, 0, psi))
    t = np.asarray(t, dtype=float)
    return a[..., None, :] + t[:, None] * d[..., None, :]


def x_origin(ix: Any) -> float:
    """Machine X [mm] of the design's (fixed frame's) z = 0, the cam's middle plane and the turret's
    plane: W/2, the shift of the STEP solid (the cam spans 0 ≤ X ≤ W, module docs)."""
    return 0.5 * float(ix.cam_width)


def machine_words(ix: Any, tau: Array, tip_t: float) -> Array:
    """The exact words X, Y, Z, A, C (..., 5) [mm, deg] putting the tool tip at parameter
    ``tip_t`` of roller 0's axis at input angles ``tau`` [rad] (module docs: X = z + W/2,
    Y = x, Z = y of the fixed frame)."""
    tau = np.asarray(tau, dtype=float)
    psi, _, _ = turret_angle(ix, tau)
    a, _, _, d, _, _ = ix.roller_pose(roller_alpha(ix, 0, psi))
    tip = a + tip_t * d
    return np.stack([tip[..., 2] + x_origin(ix), tip[..., 0], tip[..., 1], np.degrees(tau), np.degrees(psi)],
                    axis=-1)


def cutter_axis(ix: Any, words: Array, tip_t: float, t: Array) -> Array:
    """The cutter's axis points (fixed frame, (..., K, 3)) at the roller-axis parameters ``t`` for
    machine words X, Y, Z, A, C (..., 5), the tip being at parameter ``tip_t`` (the inverse of the
    mapping: fixed (x, y, z) = (Y, Z, X − W/2), the axis direction d(C))."""
    words = np.asarray(words, dtype=float)
    tip = np.stack([words[..., 1], words[..., 2], words[..., 0] - x_origin(ix)], axis=-1)
    _, _, _, d, _, _ = ix.roller_pose(_alpha_of_c(ix, words[..., 4]))
    s = np.asarray(t, dtype=float) - tip_t
    return tip[..., None, :] + s[:, None] * np.broadcast_to(d, tip.shape)[..., None, :]


def _to_cam(theta: Array, q: Array) -> Array:
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([c * q[..., 0] + s * q[..., 1], -s * q[..., 0] + c * q[..., 1], q[..., 2]], axis=-1)


# ---- geometry of the cut -------------------------------------------------------------------------

@dataclass(frozen=True)
class _Cut:
    kind: str
    rt: float
    t_top: float          # the tip's t where the cutter starts to cut the blank
    t_final: float        # the final depth
    t_safe: float
    reach: tuple[float, float]
    spindle_sign: float   # e = spindle → tip = spindle_sign·d


def _cut(ix: Any, rt: float, safe: float) -> _Cut:
    kind = _kind(ix)
    t0, t1 = float(ix.roller_start), float(ix.roller_end)
    if kind == "barrel":
        top, final = float(ix.outer_radius), float(ix.root_radius)
        t_safe = top + safe
        sign = -1.0
    else:
        top = math.sqrt(float(ix.tip_radius) ** 2 - rt ** 2)
        final = math.sqrt(float(ix.root_radius) ** 2 - rt ** 2)
        t_safe = top - safe
        if t_safe <= 0:
            raise SpecError("machining.safe_height", f"{safe:g} mm would retract the tip past the turret axis "
                                                     f"(the tip globoid leaves {top:.6g} mm): use less")
        sign = 1.0
    reach = (min(t0, final, top), max(t1, final, top))
    return _Cut(kind, rt, top, final, t_safe, reach, sign)


def _cutter_samples(ix: Any, cut: _Cut, alpha: Array, delta: float) -> Array:
    """Points on the surface of the cutter at its final depth (fixed frame, (..., P, 3)) over the
    part of its length that can reach the blank grown by ``delta``."""
    a, _, _, d, _, _ = ix.roller_pose(alpha)
    d = np.broadcast_to(d, a.shape)
    if cut.kind == "barrel":
        s0, s1 = cut.t_final, float(ix.outer_radius) + delta
        e1 = np.broadcast_to(np.array([1.0, 0.0, 0.0]), a.shape)
        e2 = np.broadcast_to(np.array([0.0, 0.0, 1.0]), a.shape)
    else:
        inner = max(float(ix.tip_radius) - delta, 0.0)
        s0, s1 = math.sqrt(max(inner ** 2 - cut.rt ** 2, 0.0)), cut.t_final
        e1 = np.broadcast_to(np.array([0.0, 1.0, 0.0]), a.shape)
        e2 = np.stack([-np.sin(alpha), np.zeros_like(alpha), np.cos(alpha)], axis=-1)
    phi = np.linspace(0.0, TWO_PI, _RING, endpoint=False)
    s = np.linspace(s0, s1, max(int(math.ceil((s1 - s0) / _ALONG)) + 1, 2))
    side_s, side_p = np.meshgrid(s, phi, indexing="ij")
    radii = cut.rt * np.ones(side_s.size)
    ss = side_s.ravel()
    pp = side_p.ravel()
    # the flat end at the tip: rings
    for r in np.linspace(0.0, cut.rt, 7)[:-1]:
        ss = np.append(ss, np.full(_RING, cut.t_final))
        pp = np.append(pp, phi)
        radii = np.append(radii, np.full(_RING, r))
    return (a[..., None, :] + ss[:, None] * d[..., None, :]
            + (radii * np.cos(pp))[:, None] * e1[..., None, :] + (radii * np.sin(pp))[:, None] * e2[..., None, :])


def _in_blank(ix: Any, q: Array, delta: float) -> Array:
    """Whether points ``q`` (any frame turning about the cam axis) lie in the blank grown by ``delta``."""
    rho = np.hypot(q[..., 0], q[..., 1])
    inside_w = np.abs(q[..., 2]) <= 0.5 * float(ix.cam_width) + delta
    if isinstance(ix, BarrelIndexer):
        return inside_w & (rho <= float(ix.outer_radius) + delta)
    c = float(ix.centre_distance)
    g = np.hypot(c - rho, q[..., 2])
    return inside_w & (rho < c) & (g >= float(ix.tip_radius) - delta)


def _cutter_meets_blank(ix: Any, cut: _Cut, tau: Array) -> Array:
    out = np.zeros(tau.size, dtype=bool)
    for b in range(0, tau.size, 256):
        tt = tau[b:b + 256]
        psi, _, _ = turret_angle(ix, tt)
        pts = _cutter_samples(ix, cut, roller_alpha(ix, 0, psi), CLEARANCE)
        out[b:b + 256] = _in_blank(ix, pts, CLEARANCE).any(axis=-1)
    return out


def _engaged_range(design: SpatialDesign, side: int) -> tuple[float, float]:
    """(τ_from, τ_to) [rad] of roller 0's locus over which side ``side`` is engaged, one design
    row beyond each end (the locus is periodic: a run over the period's seam is joined)."""
    sh = design.sheet(side)
    n = int(design.indexer.stations)
    period = TWO_PI * n
    tau = sh.tau[:-1]                              # the last row repeats the first, a period on
    eng = sh.in_band[:-1].any(axis=1)
    if not eng.any():
        raise SolveError(f"side {side:+d} of the rollers is never engaged: nothing to finish")
    if eng.all():
        raise SolveError(f"side {side:+d} of roller 0 is engaged all along its locus: no place to enter the cut")
    f = int(np.argmin(eng))                        # a row out of engagement: start the period there
    order = (f + np.arange(tau.size)) % tau.size
    t_rot = tau[order] + period * (order < f)
    e_rot = eng[order]
    idx = np.nonzero(e_rot)[0]
    i0, i1 = int(idx[0]) - 1, int(idx[-1]) + 1     # i0 ≥ 0: row 0 is out of engagement
    t_hi = t_rot[i1] if i1 < t_rot.size else t_rot[0] + period
    return float(t_rot[i0]), float(t_hi)


def _climb_share(design: SpatialDesign, side: int, cut: _Cut) -> float:
    """Share of side ``side``'s engaged contact points (roller 0's locus rows × design t) where
    sweeping FORWARD (A increasing) is climb milling with M3: n·(e × w) > 0."""
    ix = design.indexer
    sh = design.sheet(side)
    rows = np.nonzero(sh.in_band.any(axis=1))[0]
    tau = sh.tau[rows]
    ax = roller_axis(ix, 0, tau)
    da = ax.da + np.stack([ax.a[..., 1], -ax.a[..., 0], np.zeros(tau.size)], axis=-1)
    dd = ax.dd + np.stack([ax.d[..., 1], -ax.d[..., 0], np.zeros(tau.size)], axis=-1)
    w = da[:, None, :] + design.t[None, :, None] * dd[:, None, :]
    cl = contact_lines(ix, 0, tau, design.t, side)
    e = cut.spindle_sign * np.broadcast_to(ax.d[:, None, :], w.shape)
    climb = np.einsum("...i,...i->...", cl.normals_fixed, np.cross(e, w)) > 0
    band = sh.in_band[rows]
    return float(np.count_nonzero(climb & band) / max(np.count_nonzero(band), 1))


# ---- sampling and measuring ----------------------------------------------------------------------

def _round(words: Array) -> Array:
    return np.round(words, DECIMALS)


def _measure(ix: Any, words: Array, tip_t: float, reach: tuple[float, float]) -> tuple[Array, Array]:
    """(chord error, cam-frame travel) of every move between consecutive written ``words`` (n, 5):
    at λ = k/LAMBDAS the interpolated words' cutter axis vs roller 0's exact axis at the same A,
    at both ends of ``reach``; the travel the longer polyline of those two axis points."""
    lam = np.linspace(0.0, 1.0, LAMBDAS + 1)
    w = words[:-1, None, :] + lam[None, :, None] * (words[1:] - words[:-1])[:, None, :]      # (m, L, 5)
    t = np.array(reach, dtype=float)
    got = cutter_axis(ix, w, tip_t, t)                                                       # (m, L, 2, 3)
    want = exact_axis(ix, np.radians(w[..., 3]), t)
    err = np.linalg.norm(got - want, axis=-1).max(axis=(1, 2))
    cam = _to_cam(np.radians(w[..., 3])[..., None], got)
    travel = np.linalg.norm(np.diff(cam, axis=1), axis=-1).sum(axis=1).max(axis=1)
    return err, travel


def _initial_ticks(ix: Any, a0: int, a1: int, step_deg: float) -> Array:
    """Ticks (A in A_QUANTUM units) from a0 to a1: the law's ends inside, each piece in equal steps
    ≤ step_deg."""
    ts, beta = math.degrees(float(ix.index_start)), math.degrees(float(ix.index_angle))
    lo, hi = a0 * A_QUANTUM, a1 * A_QUANTUM
    ends = []
    for m in range(int(math.floor((lo - ts) / 360.0)) - 1, int(math.ceil((hi - ts) / 360.0)) + 1):
        for x in (ts + 360.0 * m, ts + beta + 360.0 * m):
            k = int(round(x / A_QUANTUM))
            if a0 < k < a1:
                ends.append(k)
    knots = np.array(sorted({a0, a1, *ends}), dtype=np.int64)
    per = int(round(step_deg / A_QUANTUM))
    out = [knots[:1]]
    for p, q in zip(knots[:-1], knots[1:]):
        n = max(int(math.ceil((q - p) / per)), 1)
        out.append(np.round(p + (q - p) * np.arange(1, n + 1) / n).astype(np.int64))
    return np.unique(np.concatenate(out))


def _sample(ix: Any, a0: int, a1: int, tip_t: float, step_deg: float, budget: float,
            reach: tuple[float, float]) -> tuple[Array, Array, Array, Array]:
    """Ticks, written words (ascending A), chord errors and travels of a sweep from A = a0 to a1
    (ticks), moves halved until every chord error is ≤ budget."""
    ticks = _initial_ticks(ix, a0, a1, step_deg)
    for _ in range(_MAX_ROUNDS):
        words = _round(machine_words(ix, np.radians(ticks * A_QUANTUM), tip_t))
        words[:, 3] = ticks * A_QUANTUM                       # A exactly on its grid
        err, travel = _measure(ix, words, tip_t, reach)
        bad = err > budget
        if not bad.any():
            return ticks, words, err, travel
        mids = (ticks[:-1][bad] + ticks[1:][bad]) // 2
        if np.any(mids <= ticks[:-1][bad]):
            break
        ticks = np.union1d(ticks, mids)
    raise SolveError(f"the moves stay {float(err.max()):.3g} mm from the roller's exact relative pose, above "
                     f"{budget:.3g} mm, at A steps of {A_QUANTUM:g} deg: use a larger machining.chord_tolerance")


# ---- the program ---------------------------------------------------------------------------------

def _positive(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) \
            or not math.isfinite(value) or value <= 0:
        raise SpecError(name, f"must be a finite number > 0, got {value!r}")
    return float(value)


def spatial_program(design: SpatialDesign, *, tool_radius: float | None = None, feed: float = 150.0,
                    plunge_feed: float | None = None, stepdown: float = 3.0, passes: int | None = None,
                    step_deg: float = 1.0, tolerance: float = 0.005, spindle_rpm: float = 2000.0,
                    tool_number: int = 1, safe_height: float = 5.0) -> SpatialProgram:
    """The generating program of ``design``'s cam (a :class:`SpatialDesign` of
    :func:`design_barrel` or :func:`design_globoidal`), see the module docstring.

    ``tool_radius`` (default the roller's r_r; smaller leaves r_r − R_t of stock on the flanks),
    ``stepdown`` (depth per level along the tool's axis; ``passes`` sets the number of levels
    instead), ``tolerance`` (the chord error of the cutter's relative pose plus G64 P) and
    ``safe_height`` in mm; ``feed``, ``plunge_feed`` (default feed/3) in mm/min relative to the
    cam; ``step_deg`` the largest A step [deg].

    Raises:
        SpecError: ``machining.tool_radius`` larger than the roller's (it would cut the ribs) or
            not > 0; ``machining.chord_tolerance`` too small for 4-decimal words; the other
            options (``machining.feed_rate``, ``machining.stepdown``, ``machining.passes``,
            ``machining.step_deg``, ``machining.safe_height``, ``machining.spindle_rpm``) not > 0
            (``step_deg`` ≤ 90).
        SolveError: no side engaged, or the cutter never clear of the blank along the locus."""
    ix = design.indexer
    kind = _kind(ix)
    rr = float(ix.roller_radius)
    rt = rr if tool_radius is None else _positive("machining.tool_radius", tool_radius)
    if rt > rr + 1e-9:
        raise SpecError("machining.tool_radius",
                        f"{rt:g} mm is larger than the roller's radius {rr:g} mm: following the roller's axis it "
                        f"would cut {rt - rr:.6g} mm into both flanks of every rib; use ≤ {rr:g} mm")
    rt = min(rt, rr)
    tol = _positive("machining.chord_tolerance", tolerance)
    feed = _positive("machining.feed_rate", feed)
    pfeed = feed / 3.0 if plunge_feed is None else _positive("machining.plunge_rate", plunge_feed)
    step = _positive("machining.step_deg", step_deg)
    if step > 90.0:
        raise SpecError("machining.step_deg", f"must be ≤ 90 deg (a move must turn A by < 180 deg), got {step:g}")
    if step < 10 * A_QUANTUM:
        raise SpecError("machining.step_deg", f"must be ≥ {10 * A_QUANTUM:g} deg, got {step:g}")
    _positive("machining.spindle_rpm", spindle_rpm)
    safe = _positive("machining.safe_height", safe_height)
    cut = _cut(ix, rt, safe)
    budget = (1.0 - BLEND_SHARE) * tol
    span = cut.reach[1] - cut.reach[0]
    reserve = 0.5 * 10.0 ** -DECIMALS * (math.sqrt(3.0) + (math.radians(1.0) * span if kind == "globoidal" else 0.0))
    if budget < 4.0 * reserve:
        raise SpecError("machining.chord_tolerance",
                        f"{tol:g} mm leaves too little once {DECIMALS}-decimal words take {reserve:.2g} mm: use at "
                        f"least {4.0 * reserve / (1.0 - BLEND_SHARE):.2g} mm")
    depth = abs(cut.t_final - cut.t_top)
    if passes is not None:
        if isinstance(passes, bool) or not isinstance(passes, (int, np.integer)) or passes < 1:
            raise SpecError("machining.passes", f"must be an integer ≥ 1, got {passes!r}")
        n_levels = int(passes)
    else:
        n_levels = max(int(math.ceil(depth / _positive("machining.stepdown", stepdown) - 1e-9)), 1)
    levels = tuple(float(cut.t_top + (cut.t_final - cut.t_top) * k / n_levels) for k in range(1, n_levels + 1))

    # -- where: the sides' engaged locus, the cutter's range in the blank
    period = TWO_PI * int(ix.stations)
    eng = {s: _engaged_range(design, s) for s in (1, -1)}
    lo1, hi1 = eng[1]
    lo2, hi2 = eng[-1]
    shift = period * round(((lo2 + hi2) - (lo1 + hi1)) / (2.0 * period))
    eng[-1] = (lo2 - shift, hi2 - shift)
    hull = (min(eng[1][0], eng[-1][0]), max(eng[1][1], eng[-1][1]))
    g = math.radians(_SCAN_DEG)
    ends = []
    for direction, start in ((-1.0, hull[0]), (1.0, hull[1])):
        found = None
        for chunk in range(int(math.ceil(period / TWO_PI))):
            tau = start + direction * g * np.arange(chunk * 720, (chunk + 1) * 720)
            clear = ~_cutter_meets_blank(ix, cut, tau)
            if clear.any():
                found = float(tau[int(np.argmax(clear))])
                break
        if found is None:
            raise SolveError("the cutter never leaves the blank along roller 0's locus: no place to enter the cut")
        ends.append(found)
    a_in = int(math.floor(math.degrees(ends[0]) / A_QUANTUM))
    a_out = int(math.ceil(math.degrees(ends[1]) / A_QUANTUM))

    # -- the sweeps
    sweeps: list[Sweep] = []

    def add(role: str, level: int, side: int | None, a0: int, a1: int, tip_t: float, forward: bool,
            climb: float | None) -> None:
        ticks, words, err, travel = _sample(ix, a0, a1, tip_t, step, budget, cut.reach)
        if not forward:
            words = words[::-1]
        sweeps.append(Sweep(role, level, side, forward, float((a0 if forward else a1) * A_QUANTUM),
                            float((a1 if forward else a0) * A_QUANTUM), tip_t, ticks, words, float(err.max()),
                            climb))
        travels.append(travel[::-1] if not forward else travel)

    travels: list[Array] = []
    for k, t_k in enumerate(levels, start=1):
        add("roughing", k, None, a_in, a_out, t_k, k % 2 == 1, None)
    here = sweeps[-1].a_to
    fin = []
    for s in (1, -1):
        share = _climb_share(design, s, cut)
        f0 = max(int(math.floor(math.degrees(eng[s][0]) / A_QUANTUM)), a_in)
        f1 = min(int(math.ceil(math.degrees(eng[s][1]) / A_QUANTUM)), a_out)
        forward = share >= 0.5
        start = (f0 if forward else f1) * A_QUANTUM
        fin.append((abs(start - here), s, f0, f1, forward, max(share, 1.0 - share)))
    for _, s, f0, f1, forward, share in sorted(fin):
        add("finishing", n_levels, s, f0, f1, cut.t_final, forward, share)

    moves = sum(sw.moves for sw in sweeps)
    chord = max(sw.chord_error for sw in sweeps)
    all_words = np.concatenate([sw.words for sw in sweeps])
    steps = np.concatenate([np.diff(sw.ticks) for sw in sweeps]) * A_QUANTUM
    prog = SpatialProgram(
        kind=kind, text="", tool_radius=rt, roller_radius=rr, cone_angle=math.degrees(float(ix.roller_cone_angle)),
        tip_radius=rt - rr + float(ix.radius_at(cut.t_final)),
        stock=(rr - rt) * math.cos(float(ix.roller_cone_angle)), tolerance=tol, budget=budget,
        blend=BLEND_SHARE * tol, chord_error=chord, levels=levels, safe_t=cut.t_safe, reach=cut.reach,
        a_range=(a_in * A_QUANTUM, a_out * A_QUANTUM),
        engaged={s: (math.degrees(v[0]), math.degrees(v[1])) for s, v in eng.items()}, sweeps=tuple(sweeps),
        moves=moves, plunges=0, lines=0, step_deg=(float(steps.min()), float(steps.max())),
        c_range=(float(all_words[:, 4].min()), float(all_words[:, 4].max())), feed=feed, plunge_feed=pfeed,
        cam_x_range=(0.0, 2.0 * x_origin(ix)), turret_axis=(x_origin(ix), float(ix.centre_distance)))
    text, plunges = _program_text(design, prog, cut, travels, spindle_rpm=float(spindle_rpm),
                                  tool_number=int(tool_number))
    return SpatialProgram(**{**prog.__dict__, "text": text, "plunges": plunges, "lines": text.count("\n")})


class _Comments(GcodeWriter):
    """A writer whose comments longer than _COMMENT_WIDTH continue on further comment lines
    (split between words)."""

    def comment(self, text: str) -> None:
        words, line = text.split(" "), ""
        for word in words:
            if line and len(line) + 1 + len(word) > _COMMENT_WIDTH:
                super().comment(line)
                line = "  " + word
            else:
                line = f"{line} {word}" if line else word
        super().comment(line)


def _xyz(w: Array) -> str:
    d = DECIMALS
    return f"X{fmt(w[0], d)} Y{fmt(w[1], d)} Z{fmt(w[2], d)}"


def _all(w: Array) -> str:
    d = DECIMALS
    return f"{_xyz(w)} A{fmt(w[3], d)} C{fmt(w[4], d)}"


def _at(ix: Any, a_deg: float, tip_t: float) -> Array:
    """Written words with the tip at ``tip_t`` at A = ``a_deg`` (on the A grid)."""
    w = _round(machine_words(ix, np.radians(np.array([a_deg])), tip_t))[0]
    w[3] = a_deg
    return w


def _program_text(design: SpatialDesign, p: SpatialProgram, cut: _Cut, travels: list[Array], *,
                  spindle_rpm: float, tool_number: int) -> tuple[str, int]:
    ix = design.indexer
    n = int(ix.stations)
    t_st = 360.0 / n
    w = _Comments(False)
    barrel = p.kind == "barrel"
    w.comment(f"cam_workbench {__version__}: {p.kind} indexer cam, X-Y-Z-A-C generating program: the cutter "
              f"follows roller 0's motion relative to the cam")
    common = (f"N = {n} stations, beta = {math.degrees(float(ix.index_angle)):.6g} deg index angle, law {ix.law}, "
              f"C = {float(ix.centre_distance):.6g} mm, r_r = {p.roller_radius:.6g} mm, rollers t = "
              f"{float(ix.roller_start):.6g}-{float(ix.roller_end):.6g} mm, width {float(ix.cam_width):.6g} mm, "
              f"index start {math.degrees(float(ix.index_start)):.6g} deg")
    if barrel:
        w.comment(f"indexer: {common}, R_p = {float(ix.pitch_radius):.6g} mm, rib radii "
                  f"{float(ix.root_radius):.6g}-{float(ix.outer_radius):.6g} mm")
    else:
        w.comment(f"indexer: {common}, tip/root globoids {float(ix.tip_radius):.6g}/{float(ix.root_radius):.6g} mm")
    w.comment("machine: cam.step's frame renamed: X along the cam axis [X = z of cam.step], Y = x towards the "
              f"turret axis, Z = y up along the turret axis [the vertical X{fmt(p.turret_axis[0], DECIMALS)} "
              f"Y{fmt(p.turret_axis[1], DECIMALS)}]; origin = cam.step's: on the cam axis, X0 on the cam's end face "
              f"z = 0 [the cam spans X{fmt(p.cam_x_range[0], DECIMALS)} to X{fmt(p.cam_x_range[1], DECIMALS)}]; "
              "trivkins XYZAC, A and C unwrapped")
    w.comment("A = input angle theta in deg, the cam turned about +X right-handed; C = turret angle psi in deg, "
              f"the cutter swung clockwise seen from +Z, alpha = {180.0 - t_st / 2:.6g} + C deg; A runs over "
              f"{p.a_range[0]:.4f} to {p.a_range[1]:.4f}, C over {p.c_range[0]:.4f} to {p.c_range[1]:.4f}")
    if barrel:
        w.comment("X Y Z = tool tip; tool vertical, tip down at height t on the roller's axis: X = W/2 + R_p sin alpha, "
                  "Y = C + R_p cos alpha, Z = t; C turns the tool about its own axis only [drop it on an XYZA mill]")
    else:
        w.comment("X Y Z = tool tip; tool horizontal along the roller's axis, spindle towards the turret axis, tip "
                  "at t from it: X = W/2 + t sin alpha, Y = C + t cos alpha, Z = 0; C swivels the head about the "
                  "vertical through the tip; no G43: the tool length lies in XY")
    stock = (f", stock {p.stock:.6g} mm left on every flank [roller radius {p.roller_radius:g} mm]"
             if p.stock > 0 else " = the roller's radius")
    if p.cone_angle == 0.0:
        w.comment(f"tool T{tool_number}: flat end mill radius {p.tool_radius:g} mm{stock}")
    else:
        w.comment(f"tool T{tool_number}: tapered end mill, half angle {p.cone_angle:.6g} deg, radius {p.tool_radius:g} "
                  f"mm at the roller's middle t = {0.5 * (float(ix.roller_start) + float(ix.roller_end)):.6g} mm, "
                  f"{p.tip_radius:.6g} mm at its tip at the final depth [the roller's cone]"
                  + (stock if p.stock > 0 else ""))
    lv = ", ".join(f"{t:.4f}" for t in p.levels)
    w.comment(f"depth levels: tip at t = {lv} mm on the roller's axis [{len(p.levels)} roughing sweeps over A "
              f"{p.a_range[0]:.4f} to {p.a_range[1]:.4f}, entered and left clear of the blank]; safe: tip at "
              f"t = {p.safe_t:.4f} mm")
    for sw in p.sweeps:
        if sw.role == "finishing":
            lo, hi = p.engaged[sw.side]
            w.comment(f"finishing side {sw.side:+d}: engaged over A {lo:.2f} to {hi:.2f} deg of roller 0's locus, "
                      f"swept {'forward' if sw.forward else 'backward'}: climb on {100.0 * sw.climb:.1f} % of its "
                      f"contact")
    w.comment(f"path: {p.moves} G1 moves in {len(p.sweeps)} sweeps, A steps {p.step_deg[0]:.4f} to "
              f"{p.step_deg[1]:.4f} deg; measured chord error {p.chord_error:.3g} mm [the cutter's axis vs roller "
              f"0's axis at theta = A, over t = {p.reach[0]:.4f}-{p.reach[1]:.4f} mm, {LAMBDAS + 1} points per "
              f"move, written words], limit {p.budget:.3g} mm, tolerance {p.tolerance:g} mm with "
              f"G64 P{fmt(p.blend, DECIMALS + 1)}; linear interpolation, not exact")
    w.comment(f"feed: G93 inverse time, F = {p.feed:g} mm/min / the move's cam-frame travel of the cutter's axis "
              f"ends; plunges {p.plunge_feed:g} mm/min along the tool's axis")
    w.block("G21 G90 G17 G40 G49 G80 G94")
    w.block("G54")
    w.block(f"G64 P{fmt(p.blend, DECIMALS + 1)}")
    w.block(f"T{tool_number} M6")
    if barrel:
        w.block(f"G43 H{tool_number}")
    w.block(f"S{fmt(spindle_rpm, 1)} M3")
    d = DECIMALS
    plunges = 0
    first = p.sweeps[0]
    w0 = _at(ix, first.a_from, cut.t_safe)
    w.comment("approach: safe pose at the first sweep's start")
    if barrel:
        w.block(f"G0 Z{fmt(w0[2], d)}")
    w.block(f"G0 {_all(w0)}")
    w.block("G93")
    cur_t = cut.t_safe
    cur_a = first.a_from
    for sw, travel in zip(p.sweeps, travels):
        if sw.role == "roughing":
            w.comment(f"roughing level {sw.level} of {len(p.levels)}: tip at t = {sw.tip_t:.4f} mm, "
                      f"{'forward' if sw.forward else 'backward'}, A {sw.a_from:.4f} to {sw.a_to:.4f}")
        else:
            w.comment(f"finishing side {sw.side:+d}: tip at t = {sw.tip_t:.4f} mm, "
                      f"{'forward' if sw.forward else 'backward'} [climb], A {sw.a_from:.4f} to {sw.a_to:.4f}")
        if sw.a_from != cur_a:
            if cur_t != cut.t_safe:
                w.block(f"G0 {_xyz(_at(ix, cur_a, cut.t_safe))}")
            w.block(f"G0 {_all(_at(ix, sw.a_from, cut.t_safe))}")
            cur_t, cur_a = cut.t_safe, sw.a_from
        if cur_t != sw.tip_t:
            a = _at(ix, cur_a, cur_t)
            b = sw.words[0]
            length = float(np.linalg.norm(b[:3] - a[:3]))
            w.block(f"G1 {_xyz(b)} F{fmt(p.plunge_feed / max(length, 1e-9), d)}")
            plunges += 1
        for word, dist in zip(sw.words[1:], travel):
            w.block(f"G1 {_all(word)} F{fmt(p.feed / max(float(dist), 1e-9), d)}")
        cur_t, cur_a = sw.tip_t, sw.a_to
    w.comment("retract")
    w.block(f"G0 {_xyz(_at(ix, cur_a, cut.t_safe))}")
    w.block("G94")
    w.block("M5")
    w.block("M2")
    return w.text(), plunges


def write_spatial_program(design: SpatialDesign, path: str | os.PathLike[str], **options: Any) -> SpatialProgram:
    """Write :func:`spatial_program` (``options`` its keywords) to ``path`` atomically."""
    prog = spatial_program(design, **options)
    write_text_atomic(Path(path), prog.text)
    return prog


__all__ = ["A_QUANTUM", "DECIMALS", "LAMBDAS", "SpatialProgram", "Sweep", "cutter_axis", "exact_axis",
           "machine_words", "spatial_program", "write_spatial_program", "x_origin"]

"""A spatial (barrel or globoidal) indexer's drive sized from its built geometry:
:func:`.sizing.drive_sizing` over the index with the moment arms, cam radii and contact lengths of
the contact lines that carry the load, the geometry's millimetres turned into the sizing's metres.

Frames and signs are those of :mod:`.spatial`.  The model, per input angle θ of the design's index:

* **Candidates.**  Every roller's side −1 contact line (the rib pushes the roller forward: it
  drives the turret) and side +1 line (it holds the turret back), sampled on a uniform grid of
  the roller's working length [t0, t1] (16× the design's t spacing, so the design's samples are
  among them).  A line is ENGAGED where some sample lies in the rib's band (``in_band`` of the
  cam-frame point); its engaged part is its in-band samples.
* **Moment arm about the turret axis.**  The cam pushes the roller with a force F_n along −N (N
  the roller's outward surface normal, into the rib: ``normals_fixed``; the radial n for a
  cylinder) at the contact point p (``points_fixed``, fixed frame).  Its moment about the turret
  axis (through P along +y) in the turret's turning sense ψ (about −y) is F_n·ŷ·((p − P) × N):
  positive on side −1, negative on side +1.  The arm of a point is that moment per unit force with
  the sign that makes it positive on both sides: h = −s·ŷ·((p − P) × N) for side s (barrel:
  R_p·|N·τ|; globoid: (t + k·r(t))·|N·τ|, t·|n·τ| for a cylinder) [mm].
* **Load along the line: uniform.**  A roller on a line contact shares the load along its
  length in proportion to the local approach; to first order (rigid roller and rib, the line
  straight within its Hertz half-width) the approach is the same along the line, so the load
  per unit roller length is uniform over the engaged part.  The line's effective arm is then the
  mean of h over the engaged samples, each weighted by the length of roller it stands for (its
  grid cell, halved at the roller's ends): T_out = F_n·h̄ exactly for that load distribution.
  (The best point's arm would under-state F_n wherever the arm varies along the line — the
  globoid's arm grows with t — and the worst point's would over-state it.)
* **Which line carries the load.**  Where two lines of a side are engaged (the hand-overs) the
  split between them is statically indeterminate; as for the parallel indexer
  (:mod:`.parallel_drive`) the whole load is put on the one with the largest effective arm.
  The forward (side −1) line carries it where T_out ≥ 0, the holding (side +1) line where
  T_out < 0.
* **Hertz: the flank's radius across the roller's generator.**  Let G(x, θ) be the signed
  distance (|∇G| = 1, > 0 outside the roller) of a cam-frame point x from the roller — the cylinder
  r_r, or the cone r(t) = r_r + (t − t_m)·k, k = tan γ — at input angle θ.  The flank is the
  envelope G = 0, G_θ = 0, and for a unit tangent v at a contact point the relative normal
  curvature of roller and flank (the sum of their curvatures, each + convex) is
  κ_rel(v) = (v·∇G_θ)²/G_θθ.  On the roller G_θ = −N·V = −f (:mod:`.spatial`'s meshing function),
  so with s_φ = r·e (e = d × n, the roller's rolling direction, across its generator) and
  s_t = q·g (g = (d + k·n)/q the generator, q = √(1 + k²)): e·∇G_θ = −f_φ/r, g·∇G_θ = −f_t/q; and the
  cam point, seen from the roller, moves with −V (V = V_e·e + V_g·g at a contact), so
  G_θθ = −f_θ + V_e·f_φ/r + V_g·f_t/q = Δ/(r·q) — Litvin's Δ, since (V × s_t)·N = q·V_e,
  (V × s_φ)·N = −r·V_g and (s_φ × s_t)·N = r·q.  Hence, for the cylinder and the cone alike,

      κ_rel(e) = f_φ²·q/(r·Δ) = 1/(r(t)·μ),        μ = Δ/(q·f_φ²) the design's margin.

  The roller's own normal curvature across its generator is cos γ/r(t) (its normal-section radius
  r/cos γ: Meusnier, n·N = cos γ), so the flank's (+ convex, − concave, as
  :func:`..followers.load.hertz_stress` takes it) is

      κ_c = 1/(r·μ) − cos γ/r = (1 − μ·cos γ)/(r·μ),    r_c = r·μ/(1 − μ·cos γ)  (∞ where μ·cos γ = 1)

  — r_r·μ/(1 − μ) for a cylinder (μ = 1 − r_r/ρ for a planar path of radius ρ gives the familiar
  1/r_r + 1/(ρ − r_r)).  For a cone the tempting "roller's curvature/μ", cos γ/(r·μ), is short by
  the factor 1/cos γ (checked against finite differences of the envelope: tests/test_spatial_cone_drive.py).
  Of the engaged part of the loaded line the sample with the largest relative curvature 1/(r·μ)
  (the smallest r·μ — for a cylinder the smallest μ — hence the largest pressure under a uniform
  line load) is taken, and the Hertz stress is that of two parallel cylinders there: the
  roller's normal-section radius r(t)/cos γ (``roller_radius``; r_r for a cylinder) against r_c, so
  that 1/(r/cos γ) + 1/r_c = κ_rel(e).  (Not the roller's radius at the line's load centroid: that
  would pair the roller of one point with the flank of another.)  Not modelled: the contact line's
  obliquity to the roller's generator (the relative curvature across the line is κ_rel(e) over cos²
  of the line's angle to the generator, the load per unit line length cos of it times that per unit
  roller length: the pressure grows by 1/√cos; the obliquity is measured and reported,
  ``max_obliquity``).
* **Contact length.**  The Hertz length is the engaged length of the loaded line (the roller
  length along its axis its engaged samples stand for) where that is shorter than
  ``roller_width`` (also along the axis), else ``roller_width``, measured along the roller's
  generator: times q = 1/cos γ (1 for a cylinder).  A line that is cut by the rib's band carries
  the load on its engaged part only.  (The sizing's Hertz stress, computed with ``roller_width``
  and r_r, is replaced by this one.)
* **Rolling (bearing life).**  The loaded roller rolls without slip at its load's centroid: its
  spin relative to the turret is ω_s = −e·w/r(t) − Ω·d per radian of input (e = d × n with n the
  radial direction at the point, ``radial``; w = Da + t·Dd the axis point's velocity relative to
  the cam, Ω = −ψ'·ŷ − k the turret's angular velocity relative to the cam;
  e·(w + (Ω + ω_s·d) × r(t)·n) = 0), averaged over the engaged samples with the load's weights.
  The sizing is passed ``contact_arc`` = r_r·∫|ω_s| dθ with ``roller_radius`` r_r, so the roller's
  revolutions are ∫|ω_s| dθ/2π whatever its shape.  Elsewhere on the line it slips (spin-sliding),
  which the life does not count.
* **Pitch radius.**  :class:`.sizing.IndexLoad` takes one; it is used by the sizing only for its
  defaults, which are all given here: R_p for the barrel, the middle of the working length
  (t0 + t1)/2 for the globoid.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...followers.load import hertz_stress
from .sizing import DriveSizing, IndexLoad, drive_sizing
from .spatial import BarrelIndexer, SpatialDesign, SpatialIndexer, contact_lines, roller_axis, turret_angle

Array = np.ndarray
MM = 1e-3
#: fine samples of the working length per design sample interval
_REFINE = 16
_Y = np.array([0.0, 1.0, 0.0])
#: |1 − μ|/μ below which the flank's section is flat (its radius ∞)
_FLAT = 1e-12


@dataclass(frozen=True)
class LoadedLines:
    """One side's load-carrying contact line at each θ of the index (arrays of θ's shape).

    side: −1 (forward, driving) or +1 (holding back).  roller: the roller j carrying the load.
    count: how many of this side's lines are engaged (where 0 — never in a locked design —
    roller means nothing and the other arrays are NaN).  arm [mm]: the effective moment arm about the turret axis
    per unit normal force (> 0).  cam_radius [mm]: the flank's signed normal-section radius across
    the roller's generator (+ convex; in the plane normal to the roller's axis for a cylinder) at
    the engaged sample of largest relative curvature 1/(r·μ).  margin: the smallest regularity
    margin μ on the engaged part.  length [mm]: the engaged length along the roller's axis (t).
    spin [rad/rad]: the roller's spin relative to the turret per radian of input.  obliquity [rad]:
    the largest angle, on the engaged part, between the contact line and the roller's generator
    (its axis for a cylinder; NaN where fewer than two samples).  roller_radius [mm]: the roller's
    normal-section radius r(t)/cos γ across its generator at cam_radius's sample (r_r for a
    cylinder), the Hertz stress's roller radius."""

    side: int
    roller: Array
    count: Array
    arm: Array
    cam_radius: Array
    margin: Array
    length: Array
    spin: Array
    obliquity: Array
    roller_radius: Array


@dataclass(frozen=True)
class SpatialContacts:
    """The index's load-carrying contacts of a spatial design.

    theta [rad]: the design's input angles over the index, from its start (θ − θ_s ∈ [0, β]).
    t [mm] (K,): the samples of the roller's working length; weights [mm] (K,): the roller length
    each stands for.  forward (side −1), holding (side +1): :class:`LoadedLines`."""

    theta: Array
    t: Array
    weights: Array
    forward: LoadedLines
    holding: LoadedLines

    def summary(self) -> dict[str, Any]:
        """Plain numbers (mm, degrees) over the index: each side's smallest arm and engaged length,
        smallest and largest cam radius, largest obliquity, and the most lines engaged at once."""
        out: dict[str, Any] = {"units": {"length": "mm", "angle": "deg"}}
        for name, ln in (("forward", self.forward), ("holding", self.holding)):
            r = ln.cam_radius
            out[name] = {
                "side": ln.side,
                "min_arm_mm": float(np.min(ln.arm)),
                "max_arm_mm": float(np.max(ln.arm)),
                "min_engaged_length_mm": float(np.min(ln.length)),
                "min_margin": float(np.min(ln.margin)),
                "min_abs_cam_radius_mm": float(np.min(np.abs(r))),
                "concave": bool(np.any(r < 0)),
                "max_obliquity_deg": _plain(math.degrees(float(np.nanmax(ln.obliquity)))
                                            if np.isfinite(ln.obliquity).any() else math.nan),
                "max_lines_engaged": int(np.max(ln.count)),
            }
        return out


def _plain(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def _cross_k(q: Array) -> Array:
    """k × q."""
    return np.stack([-q[..., 1], q[..., 0], np.zeros_like(q[..., 0])], axis=-1)


def _dot(a: Array, b: Array) -> Array:
    return np.einsum("...i,...i->...", a, b)


def _lines(ix: SpatialIndexer, theta: Array, rollers: Array, t: Array, wts: Array, side: int) -> LoadedLines:
    """Side ``side``'s lines of every roller at input angles ``theta`` (absolute, rad), and the
    one that carries the load at each (module docs)."""
    k = ix.taper
    cos_g = math.cos(math.atan(k))
    th = theta[:, None]
    rj = rollers[None, :]
    cl = contact_lines(ix, rj, th, t, side)                                  # (S, J, K)
    ax = roller_axis(ix, rj, th)                                             # (S, J, 3)
    band = ix.in_band(cl.points)
    p, big_n, n, r = cl.points_fixed, cl.normals_fixed, cl.radial, cl.radius    # fixed frame; r(t) (S, J, K)
    e = (Ellipsis, None, slice(None))
    tk = t[:, None]
    pc = np.array([float(ix.centre_distance), 0.0, 0.0])
    arm_pt = -side * _dot(np.cross(p - pc, big_n), _Y)                       # (S, J, K)
    # the roller's no-slip spin at each sample (module docs): Ω·d = −ψ'·d_y − d_z
    _, dpsi, _ = turret_angle(ix, theta)
    omega_d = -dpsi[:, None] * ax.d[..., 1] - ax.d[..., 2]                  # (S, J)
    w = (ax.da - _cross_k(ax.a))[e] + tk * (ax.dd - _cross_k(ax.d))[e]
    ed = np.cross(ax.d[e], n)
    spin_pt = -_dot(ed, w) / r - omega_d[..., None]
    wb = np.where(band, wts, 0.0)
    total = wb.sum(axis=2)                                                   # (S, J) engaged length
    engaged = total > 0
    with np.errstate(invalid="ignore", divide="ignore"):
        arm = np.where(engaged, np.where(band, wb * arm_pt, 0.0).sum(axis=2) / total, np.nan)
        spin = np.where(engaged, np.where(band, wb * spin_pt, 0.0).sum(axis=2) / total, np.nan)
    mu = np.where(band, cl.margin, np.inf).min(axis=2)
    # the Hertz sample: the largest relative curvature 1/(r·μ) on the engaged part (module docs)
    hz = np.argmin(np.where(band, r * cl.margin, np.inf), axis=2)            # (S, J)
    mu_h = np.take_along_axis(cl.margin, hz[..., None], axis=2)[..., 0]
    r_h = np.take_along_axis(r, hz[..., None], axis=2)[..., 0]
    # obliquity: the angle between the line's tangent (from neighbouring in-band samples) and the
    # roller's generator g = (d + k·n)/q at the first of them (d for a cylinder)
    seg = np.diff(p, axis=2)
    gen = (ax.d[e] + k * n[..., :-1, :]) / math.hypot(1.0, k)
    both = band[..., 1:] & band[..., :-1]
    cos_ob = np.abs(_dot(seg, gen)) / np.linalg.norm(seg, axis=-1)
    ob = np.where(both, np.arccos(np.clip(cos_ob, 0.0, 1.0)), -np.inf).max(axis=2)
    ob = np.where(np.isfinite(ob), ob, np.nan)
    pick = np.argmax(np.where(engaged, arm, -np.inf), axis=1)                # (S,)
    rows = np.arange(theta.size)
    has = engaged[rows, pick]
    mu_p = np.where(has, mu[rows, pick], np.nan)
    mu_c = np.where(has, mu_h[rows, pick], np.nan)
    r_c = np.where(has, r_h[rows, pick], np.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        kappa = (1.0 - mu_c * cos_g) / (r_c * mu_c)                          # the flank's curvature, + convex
        # a flat section (μ·cos γ = 1 to rounding) is ∞, not 1/(a rounding error)
        radius = np.where(np.abs(kappa) * r_c <= _FLAT, np.inf, 1.0 / kappa)
    return LoadedLines(side, rollers[pick], engaged.sum(axis=1), arm[rows, pick], radius, mu_p,
                       np.where(has, total[rows, pick], np.nan), spin[rows, pick], ob[rows, pick], r_c / cos_g)


def spatial_contacts(design: SpatialDesign) -> SpatialContacts:
    """The load-carrying contact lines of ``design`` over its index (module docs): for each of the
    design's input angles in [θ_s, θ_s + β], the forward (side −1) and holding (side +1) line with
    the largest effective arm about the turret axis, its arm, flank radius, engaged length,
    rolling spin and obliquity."""
    ix = design.indexer
    ts, beta = float(ix.index_start), float(ix.index_angle)
    theta = design.theta[: design.index_rows + 1]
    k = _REFINE * (design.t.size - 1) + 1
    t0, t1 = float(ix.roller_start), float(ix.roller_end)
    t = np.linspace(t0, t1, k)
    wts = np.full(k, (t1 - t0) / (k - 1))
    wts[[0, -1]] *= 0.5
    rollers = np.asarray(design.rollers)
    fwd = _lines(ix, theta, rollers, t, wts, -1)
    hold = _lines(ix, theta, rollers, t, wts, 1)
    return SpatialContacts(np.minimum(theta - ts, beta), t, wts, fwd, hold)


def spatial_drive(design: SpatialDesign, *, input_speed: float, inertia: float, roller_width: float,
                  roller_rating: float, friction_torque: float = 0.0, **more: float) -> DriveSizing:
    """The drive of the barrel or globoidal ``design`` at ``input_speed`` [rev/min] turning an
    output of ``inertia`` [kg·m²] against ``friction_torque`` [N·m], the rollers ``roller_width``
    [mm] wide on bearings of dynamic rating ``roller_rating`` [N]; ``more``: the other fields of
    :class:`.sizing.IndexLoad` (moduli, Poisson ratios, ``life_exponent``, ``efficiency``).  Over
    the design's input angles in the index, with the arms, flank radii, contact lengths and
    rolling of :func:`spatial_contacts` (module docs); θ of the result is from the index's start."""
    ix = design.indexer
    c = spatial_contacts(design)
    rr = float(ix.roller_radius) * MM
    pitch = float(ix.pitch_radius) if isinstance(ix, BarrelIndexer) else 0.5 * (float(ix.roller_start) +
                                                                               float(ix.roller_end))
    load = IndexLoad(stations=int(ix.stations), index_angle=float(ix.index_angle), input_speed=input_speed,
                     inertia=inertia, friction_torque=friction_torque, law=ix.law, pitch_radius=pitch * MM,
                     roller_radius=rr, roller_width=roller_width * MM, roller_rating=roller_rating, **more)
    f, h = c.forward, c.holding
    geometry = dict(theta=c.theta, arm=f.arm * MM, cam_radius=f.cam_radius * MM, arm_back=h.arm * MM,
                    cam_radius_back=h.cam_radius * MM)
    first = drive_sizing(load, **geometry)
    back = first.torque_out < 0
    # the loaded roller's rolled arc (trapezoids of |ω_s| over θ) [m]
    spin = np.abs(np.where(back, h.spin, f.spin))
    arc = rr * np.concatenate([[0.0], np.cumsum(0.5 * (spin[1:] + spin[:-1]) * np.diff(c.theta))])
    sized = drive_sizing(load, contact_arc=arc, **geometry)
    # the Hertz line: the loaded part's length along the roller's generator (q × its axial length)
    length = np.minimum(np.where(back, h.length, f.length), float(roller_width)) * math.hypot(1.0, ix.taper) * MM
    stress = hertz_stress(sized.normal_force, np.where(back, h.roller_radius, f.roller_radius) * MM,
                          np.where(back, h.cam_radius, f.cam_radius) * MM, length,
                          float(load.e_cam), float(load.nu_cam), float(load.e_roller), float(load.nu_roller))
    i_s = int(np.argmax(stress))
    return dataclasses.replace(
        sized, contact_stress=stress, contact_stress_peak=float(stress[i_s]),
        contact_stress_peak_at=float(c.theta[i_s]),
        rolling_note="from the kinematics: the loaded roller rolls without slip at its engaged line's load "
                     "centroid (spin relative to the turret)")

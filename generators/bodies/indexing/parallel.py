"""Kinematic geometry of a parallel (plate-cam) indexer: the cams' pitch curves and profiles, which
roller each cam holds when, the lobe tips, clearance, locking, pressure angles and moment arms.

Units: lengths in mm, angles in radians (degrees only in :meth:`ParallelDesign.summary`).

Frames and signs (enough to recompute everything from these lines):

* Fixed frame: the input (cam) axis O at the origin, the turret axis P = (C, 0) parallel to it;
  x from O towards P, y completing a right-handed frame with z towards the viewer.  Angles are
  counter-clockwise (CCW) from +x.  e(a) = (cos a, sin a); J rotates a vector by +90°:
  J(x, y) = (−y, x); the cross product of plane vectors is a × b = a_x b_y − a_y b_x.
* The input angle θ turns the cams CCW: a point q of the cam frame is at Rot(θ)·q in the fixed
  frame (the cam frame coincides with the fixed frame at θ = 0).
* The turret angle ψ ≥ 0 is its CLOCKWISE rotation (the turret turns against the input, like a
  meshing gear): ψ(θ) = T·(m + F(u)), T = 2π/N, m = ⌊(θ − θ_s)/2π⌋ whole turns,
  u = clip((θ − θ_s − 2πm)/β, 0, 1); F = ``evaluate_law(law, u)``; ψ' = dψ/dθ = T·F'/β.
* n_c cams (planes) k = 0 … n_c − 1.  Roller j of plane k (j = 0 … N−1) is at angle
  α_kj = a_k + T·j − ψ about P, centre P + R_p·e(α_kj), with
  a_k = π + (n_c − 1 − 2k)·π/(N·n_c): plane k is plane 0 turned clockwise by 2πk/(N·n_c), and at
  the dwell (ψ ≡ 0 mod T) the rollers a_k straddle the line OP symmetrically (n_c = 2: plane 0's
  at π + π/(2N), below OP; plane 1's at π − π/(2N), above; n_c = 3: one on OP).
* Cam k works only on plane k's rollers (different axial planes).  In the turn θ ∈ [θ_s, θ_s+2π]
  roller j = 0 is the outgoing roller (held at a_k on the dwell before the index, pushed away) and
  j = 1 the incoming one (it ends at a_k and is held through the dwell after the index); the
  others are idle.
* One locus: in the cam frame roller 0's centre is L_k(τ) = Rot(−τ)·(P + R_p·e(a_k − ψ(τ))) for
  every real τ, and roller j at input angle θ is at L_k(θ − 2πj).  Cam k's pitch curve is L_k on
  [τ_in, τ_out]: the incoming piece τ ∈ [τ_in, θ_s − 2π + β], the dwell arc
  τ ∈ [θ_s − 2π + β, θ_s] (a circle about O of radius r_d,k = |P + R_p·e(a_k)|), the outgoing
  piece τ ∈ [θ_s, τ_out]; L_k(τ_in) = L_k(τ_out) = X_k, the crossover (the lobe's pitch tip).
  With τ increasing the pitch curve runs clockwise in the cam frame; its outward unit normal is
  n = J·L'/|L'|, in the fixed frame n ∝ p + J·p' (p the roller centre, p' = dp/dθ).
* The profile is the inward offset Q = L − r_r·n of the pitch curve, trimmed where the offsets of
  the two flanks cross: the profile tip X'_k = Q(τ'_in) = Q(τ'_out), a corner.  A roller touches
  the cam only on the trimmed profile, so cam k holds roller 0 for θ ∈ [θ_s, τ'_out] and roller 1
  for θ ∈ [τ'_in + 2π, θ_s + 2π] (its engagement windows); between the crossover and the tip the
  roller pivots past the corner without touching.
* Radii of curvature are signed, convex +: the pitch curve's ρ = −|L'|³/(L' × L''), the
  profile's ρ − r_r (an undercut where a convex pitch ρ < r_r).
* Contact force on the roller: along n, magnitude F ≥ 0 (a cam only pushes).  Moment arm about P
  arm_P = −(p − P) × n: the torque per unit force turning the turret FORWARD (clockwise), + for a
  contact that drives the turret on, − for one that holds it back.  Moment arm about O
  arm_O = p × n: the input torque per unit force the cam needs (CCW).  Virtual work:
  arm_O = arm_P·ψ'.  Pressure angle: the angle between the force line n and the roller centre's
  path (the tangent of the turret's pitch circle), cos φ = |arm_P|/R_p, in [0, π/2].

Catalogue-like geometry: parallel indexers (Camco, Sankyo) span N = 2–12 and β = 90°–330°.  With
r_r ≈ 0.2·R_p and the modified sine law the crossover exists for C/R_p above about 2.0 at
β = 120° (N = 4–12), 1.5 at β = 180° and 1.2 at β = 270°, up to C/R_p ≈ 3 (a longer C lowers the
lobe and the pressure angles but needs a bigger cam); the default, N = 8, β = 120°, C = 120 mm,
R_p = 50 mm, r_r = 10 mm, two cams, is valid.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...errors import SpecError
from ...motion.laws import LAW_FUNCTIONS, NormalisedLaw, evaluate_law, is_law, law_name
from .fields import integer, number

Array = np.ndarray
TWO_PI = 2.0 * math.pi
#: chord sag of the sampled pitch and profile polylines [mm] (the polyline's distance from the curve)
CHORD_TOL = 1e-5
_BLOCK = 96
#: samples bounds of one sampled piece
_MIN_PIECE, _MAX_PIECE = 401, 200_001
#: rows of θ handled at once where an array grows as (θ samples) × (polyline vertices)


@dataclass(frozen=True)
class ParallelIndexer:
    """A parallel indexer (validated on construction: a bad field raises :class:`SpecError`
    named ``indexer.<field>``).

    Attributes:
        stations: N, the turret's stops per turn (integer ≥ 2); it turns by 2π/N per index.
        index_angle: β [rad], the input angle of the index, 0 < β < 2π.
        law: the index's motion law, a key of ``LAW_FUNCTIONS`` or a
            :class:`~cam_workbench.generators.motion.laws.NormalisedLaw` (a motion program's rise).
        centre_distance: C [mm], input axis to turret axis.
        pitch_radius: R_p [mm], the turret's roller pitch radius, < C.
        roller_radius: r_r [mm], < R_p·sin(π/N) (neighbouring rollers of a plane apart).
        cams: n_c, the cam plates (2 or 3), each with its own plane of N rollers.
        index_start: θ_s [rad], the input angle where the index starts.
    """

    stations: int = 8
    index_angle: float = 2.0 * math.pi / 3.0
    law: str | NormalisedLaw = "modified_sine"
    centre_distance: float = 120.0
    pitch_radius: float = 50.0
    roller_radius: float = 10.0
    cams: int = 2
    index_start: float = 0.0

    def __post_init__(self) -> None:
        _validate(self)

    @property
    def station_angle(self) -> float:
        """T = 2π/N [rad], the turret's turn per index."""
        return TWO_PI / int(self.stations)

    def dwell_angle(self, cam: int) -> float:
        """a_k [rad]: the angle about P of plane ``cam``'s held roller at the dwell."""
        n, nc = int(self.stations), int(self.cams)
        return math.pi + (nc - 1 - 2 * cam) * math.pi / (n * nc)

    def dwell_radius(self, cam: int) -> float:
        """r_d,k [mm]: the radius about O of cam ``cam``'s dwell arc."""
        a = self.dwell_angle(cam)
        return math.hypot(self.centre_distance + self.pitch_radius * math.cos(a), self.pitch_radius * math.sin(a))


def _validate(ix: ParallelIndexer) -> None:
    """The rules of :class:`ParallelIndexer` (SpecError naming the first field that breaks one)."""
    n = integer("stations", ix.stations, "an integer ≥ 2", lambda v: v >= 2)
    beta = number("index_angle", ix.index_angle)
    if not 0 < beta < TWO_PI:
        raise SpecError("indexer.index_angle", f"must be in (0, 2π) rad (a dwell must remain), got {beta!r}")
    if not is_law(ix.law):
        raise SpecError("indexer.law", f"unknown law {ix.law!r}; one of {', '.join(sorted(LAW_FUNCTIONS))} "
                        "or a NormalisedLaw (a motion program's rise)")
    c = number("centre_distance", ix.centre_distance)
    rp = number("pitch_radius", ix.pitch_radius)
    rr = number("roller_radius", ix.roller_radius)
    for name, v in (("centre_distance", c), ("pitch_radius", rp), ("roller_radius", rr)):
        if v <= 0:
            raise SpecError(f"indexer.{name}", f"must be > 0 mm, got {v!r}")
    integer("cams", ix.cams, "2 or 3", lambda v: v in (2, 3))
    number("index_start", ix.index_start)
    if not rp < c:
        raise SpecError("indexer.pitch_radius", f"must be < indexer.centre_distance ({c!r} mm), got {rp!r}")
    gap = rp * math.sin(math.pi / n)
    if not rr < gap:
        raise SpecError("indexer.roller_radius",
                        f"must be < R_p·sin(π/N) = {gap:.6g} mm (neighbouring rollers touch), got {rr!r}")
    r_d = min(ix.dwell_radius(k) for k in range(int(ix.cams)))
    if not rr < r_d:
        raise SpecError("indexer.roller_radius",
                        f"must be < the dwell radius {r_d:.6g} mm (the dwell profile would reach the input axis),"
                        f" got {rr!r} — increase indexer.centre_distance")


# ---------------------------------------------------------------------------------------------
# kinematics

def turret_angle(ix: ParallelIndexer, theta: Array) -> tuple[Array, Array, Array]:
    """ψ [rad] (clockwise, continuous over turns, 0 at the dwell before the index of the turn
    starting at θ_s), ψ' and ψ'' (per rad of input) at input angles ``theta`` [rad]."""
    theta = np.asarray(theta, dtype=float)
    t_st, beta = ix.station_angle, float(ix.index_angle)
    rel = theta - float(ix.index_start)
    turns = np.floor(rel / TWO_PI)
    x = (rel - TWO_PI * turns) / beta
    inside = (x >= 0.0) & (x <= 1.0)
    f, f1, f2, _ = evaluate_law(ix.law, np.clip(x, 0.0, 1.0))
    psi = t_st * (turns + f)
    return psi, np.where(inside, t_st * f1 / beta, 0.0), np.where(inside, t_st * f2 / beta**2, 0.0)


def _J(v: Array) -> Array:
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def _cross(a: Array, b: Array) -> Array:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _rot(angle: Array, v: Array) -> Array:
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def roller_state(ix: ParallelIndexer, cam: int, roller: Array, theta: Array) -> tuple[Array, Array, Array]:
    """Fixed-frame centre p [mm] of plane ``cam``'s roller(s) ``roller`` at ``theta`` [rad] and its
    derivatives p', p'' per rad of input (broadcast over roller and theta; last axis x, y)."""
    psi, d1, d2 = turret_angle(ix, theta)
    alpha = ix.dwell_angle(cam) + ix.station_angle * np.asarray(roller, dtype=float) - psi
    e = np.stack([np.cos(alpha), np.sin(alpha)], axis=-1)
    je = _J(e)
    rp = float(ix.pitch_radius)
    p = np.array([float(ix.centre_distance), 0.0]) + rp * e
    dp = -rp * d1[..., None] * je
    ddp = -rp * (d2[..., None] * je + (d1**2)[..., None] * e)
    return p, dp, ddp


def locus(ix: ParallelIndexer, cam: int, tau: Array) -> dict[str, Array]:
    """Cam ``cam``'s roller-centre locus L(τ) in the cam frame, with L', the outward normal and the
    pitch radius of curvature (convex +), all analytic in the law's F', F''."""
    tau = np.asarray(tau, dtype=float)
    p, dp, ddp = roller_state(ix, cam, 0, tau)
    v1 = dp - _J(p)                       # Rot(τ)·L'
    v2 = ddp - 2.0 * _J(dp) - p           # Rot(τ)·L''
    speed = np.hypot(v1[..., 0], v1[..., 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = -speed**3 / _cross(v1, v2)
        n_fixed = _J(v1) / speed[..., None]
    return {"point": _rot(-tau, p), "d1": _rot(-tau, v1), "normal": _rot(-tau, n_fixed), "speed": speed,
            "rho": rho, "p": p, "dp": dp, "n_fixed": n_fixed}


# ---------------------------------------------------------------------------------------------
# results

@dataclass(frozen=True)
class PitchPiece:
    """A piece of a cam's pitch curve (cam frame): ``role`` "incoming", "dwell" or "outgoing";
    ``tau`` [rad] the locus parameter (roller 0's input angle there; roller 1 passes at τ + 2π),
    ``points`` [mm], outward unit ``normals``, pitch radius of curvature ``radius`` [mm, convex +].
    The dwell piece is the exact circle of radius r_d about O (its samples are for drawing)."""

    role: str
    tau: Array
    points: Array
    normals: Array
    radius: Array


@dataclass(frozen=True)
class IndexCam:
    """One cam plate k of a parallel indexer (cam frame, mm, rad; see the module's conventions).

    Attributes:
        index: k.
        dwell_angle: a_k [rad] about P of the held roller; dwell_radius: r_d,k [mm].
        pieces: the pitch curve's pieces, incoming, dwell, outgoing, from X round to X.
        crossover: X [mm], the loci's crossing; crossover_tau: (τ_in, τ_out) [rad] with
            L(τ_in) = L(τ_out) = X (τ_in in the previous turn).
        tip: X' [mm], the profile's corner; tip_tau: (τ'_in, τ'_out).
        profile: closed polyline of the profile [mm], (M, 2), clockwise from X' (first = last);
            profile_normals: outward unit normals (the pitch curve's); profile_radius [mm] signed,
            convex +; profile_tau: the locus parameter of each vertex.
        windows: ((θ_s, τ'_out), (τ'_in + 2π, θ_s + 2π)) [rad]: the input angles at which this
            cam holds roller 0 (outgoing), roller 1 (incoming, then through the dwell).
        engaged, pressure_angle, arm_p, arm_o, contact_radius: on the design's θ grid, (S, 2) for
            roller 0 and roller 1; NaN where that roller is not engaged.  pressure_angle [rad];
            arm_p, arm_o [mm] (the module's signs); contact_radius: the profile's radius there.
    """

    index: int
    dwell_angle: float
    dwell_radius: float
    pieces: tuple[PitchPiece, ...]
    crossover: Array
    crossover_tau: tuple[float, float]
    tip: Array
    tip_tau: tuple[float, float]
    profile: Array
    profile_normals: Array
    profile_radius: Array
    profile_tau: Array
    windows: tuple[tuple[float, float], tuple[float, float]]
    engaged: Array
    pressure_angle: Array
    arm_p: Array
    arm_o: Array
    contact_radius: Array


@dataclass(frozen=True)
class Clearance:
    """Smallest gap [mm] between a roller of a cam's plane not engaged with it and the cam profile,
    over the turn, and where: ``theta`` [rad], ``cam``, ``roller`` (j).  ``gap`` covers the idle
    rollers (j ≥ 2, and roller 0 once the index is over); ``handover_gap`` the outgoing roller
    between leaving the tip and the index's end and the incoming roller before it arrives (a gap
    that opens from 0 at the tip: only its sign matters).  ok: both > −1e-6 mm and gap > 0."""

    gap: float
    theta: float
    cam: int
    roller: int
    handover_gap: float
    handover_theta: float
    ok: bool


@dataclass(frozen=True)
class Locking:
    """Positive drive: at every input angle some engaged contact pushes the turret forward and
    some other holds it back (arm_P > 0 and < 0).  ``forward_angle``/``backward_angle``: the worst
    (largest), over the turn, of the best such contact's pressure angle [rad] (π/2 where none) and
    the input angles [rad] where they happen.  ok: both < π/2."""

    forward_angle: float
    forward_theta: float
    backward_angle: float
    backward_theta: float
    ok: bool


@dataclass(frozen=True)
class ParallelDesign:
    """A parallel indexer's geometry on ``theta``, the input grid θ_s + [0, 2π] (S samples, rad).

    psi, dpsi, d2psi: the turret's motion; cams: the :class:`IndexCam` of each plate.
    driving_angle: the pressure angle [rad] of the best forward-pushing contact at each θ (NaN
    where none); driving_arm [mm] its arm_P, driving_cam, driving_roller which contact it is,
    driving_radius [mm] the profile's radius of curvature there; holding_angle, holding_arm
    [mm] (|arm_P|), holding_radius [mm]: the same of the best holding-back contact (arm_P < 0), the
    one that carries the load where the output decelerates.  clearance, locked: verdicts."""

    indexer: ParallelIndexer
    theta: Array
    psi: Array
    dpsi: Array
    d2psi: Array
    cams: tuple[IndexCam, ...]
    driving_angle: Array
    driving_arm: Array
    driving_cam: Array
    driving_roller: Array
    driving_radius: Array
    holding_angle: Array
    holding_arm: Array
    holding_radius: Array
    clearance: Clearance
    locked: Locking

    @property
    def valid(self) -> bool:
        """Clearance and locking verdicts both pass."""
        return bool(self.clearance.ok and self.locked.ok)

    def summary(self) -> dict[str, Any]:
        """Plain numbers: angles in degrees (keys ``*_deg``), lengths in mm (``*_mm``)."""
        ix = self.indexer
        beta = float(ix.index_angle)
        rel = self.theta - float(ix.index_start)
        idx = (rel >= 0) & (rel <= beta)
        da = np.where(idx, self.driving_angle, np.nan)
        i_max = int(np.nanargmax(da)) if np.isfinite(da).any() else 0
        cams = []
        for c in self.cams:
            prof_r = c.profile_radius[np.isfinite(c.profile_radius)]
            convex = prof_r[prof_r > 0]
            pa = c.pressure_angle[np.isfinite(c.pressure_angle)]
            cams.append({
                "cam": c.index,
                "dwell_radius_mm": c.dwell_radius,
                "crossover_mm": [float(v) for v in c.crossover],
                "crossover_radius_mm": float(np.hypot(*c.crossover)),
                "tip_mm": [float(v) for v in c.tip],
                "tip_radius_mm": float(np.hypot(*c.tip)),
                "outgoing_window_deg": [math.degrees(v) for v in c.windows[0]],
                "incoming_window_deg": [math.degrees(v) for v in c.windows[1]],
                "max_pressure_angle_deg": math.degrees(float(pa.max())) if pa.size else float("nan"),
                "min_convex_profile_radius_mm": float(convex.min()) if convex.size else float("nan"),
                "profile_points": int(c.profile.shape[0]),
            })
        return {
            "units": {"length": "mm", "angle": "deg"},
            "stations": int(ix.stations),
            "cams": int(ix.cams),
            "law": law_name(ix.law),
            "index_angle_deg": math.degrees(beta),
            "index_start_deg": math.degrees(float(ix.index_start)),
            "centre_distance_mm": float(ix.centre_distance),
            "pitch_radius_mm": float(ix.pitch_radius),
            "roller_radius_mm": float(ix.roller_radius),
            "max_driving_pressure_angle_deg": math.degrees(float(da[i_max])) if np.isfinite(da).any() else float("nan"),
            "max_driving_pressure_angle_at_deg": math.degrees(float(self.theta[i_max])),
            "min_driving_arm_mm": float(np.nanmin(np.where(idx, self.driving_arm, np.nan))),
            "clearance_mm": self.clearance.gap,
            "clearance_at_deg": math.degrees(self.clearance.theta),
            "clearance_cam": self.clearance.cam,
            "clearance_roller": self.clearance.roller,
            "handover_gap_mm": self.clearance.handover_gap,
            "clearance_ok": self.clearance.ok,
            "locked": self.locked.ok,
            "worst_forward_pressure_angle_deg": math.degrees(self.locked.forward_angle),
            "worst_forward_at_deg": math.degrees(self.locked.forward_theta),
            "worst_backward_pressure_angle_deg": math.degrees(self.locked.backward_angle),
            "worst_backward_at_deg": math.degrees(self.locked.backward_theta),
            "valid": self.valid,
            "per_cam": cams,
        }


# ---------------------------------------------------------------------------------------------
# construction

def _segment_crossings(a: Array, b: Array) -> tuple[Array, Array, Array, Array]:
    """Crossings of polylines a (n, 2) and b (m, 2): segment indices i, j and fractions s, t."""
    p, r = a[:-1, None, :], (a[1:] - a[:-1])[:, None, :]
    q, s = b[None, :-1, :], (b[1:] - b[:-1])[None, :, :]
    den = _cross(r, s)
    qp = q - p
    with np.errstate(divide="ignore", invalid="ignore"):
        t_a = _cross(qp, s) / den
        t_b = _cross(qp, r) / den
    hit = (den != 0) & (t_a >= 0) & (t_a <= 1) & (t_b >= 0) & (t_b <= 1)
    i, j = np.nonzero(hit)
    return i, j, t_a[i, j], t_b[i, j]


def _newton_pair(fun, x0: Array, y0: Array, lo: tuple[float, float], hi: tuple[float, float]):
    """Solve fun(x, y) = (g, dg/dx, dg/dy) = 0 in 2D by Newton from (x0, y0) (clipped to the box);
    returns (x, y, |g|)."""
    x, y = float(x0), float(y0)
    res = math.inf
    for _ in range(40):
        g, gx, gy = fun(x, y)
        res = float(np.hypot(*g))
        det = gx[0] * gy[1] - gx[1] * gy[0]
        if not np.isfinite(det) or det == 0:
            break
        dx = (g[0] * gy[1] - g[1] * gy[0]) / det
        dy = (gx[0] * g[1] - gx[1] * g[0]) / det
        x = min(max(x - dx, lo[0]), hi[0])
        y = min(max(y - dy, lo[1]), hi[1])
        if abs(dx) + abs(dy) < 1e-15:
            g, _, _ = fun(x, y)
            res = float(np.hypot(*g))
            break
    return x, y, res


def _grid(ix: ParallelIndexer, cam: int, lo: float, hi: float, offset: bool) -> Array:
    """τ samples of [lo, hi] dense enough for a chord sag ≤ CHORD_TOL on the pitch curve and on
    its offset (sag ≈ (|Q'|·Δτ)²/(8|ρ_Q|), |Q'| = |L'|·|1 − r_r/ρ|, ρ_Q = ρ − r_r)."""
    trial = np.linspace(lo, hi, 2001)
    loc = locus(ix, cam, trial)
    rr = float(ix.roller_radius)
    rho = np.abs(loc["rho"])
    need = loc["speed"] ** 2 / (8.0 * rho)                           # pitch: Δτ² · need ≤ tol
    if offset:
        rq = np.abs(loc["rho"] - rr)
        need = np.maximum(need, loc["speed"] ** 2 * rq / (8.0 * np.maximum(rho, 1e-300) ** 2))
    need = float(np.nanmax(np.where(np.isfinite(need), need, 0.0)))
    n = int(np.clip(math.ceil((hi - lo) * math.sqrt(need / CHORD_TOL)) + 1, _MIN_PIECE, _MAX_PIECE))
    return np.linspace(lo, hi, n)


def _deg(x: float) -> str:
    return f"{math.degrees(x):.6g}°"


def _build_cam(ix: ParallelIndexer, k: int, theta: Array) -> IndexCam:
    """Cam k's pitch curve, crossover, profile and contacts on the grid ``theta``."""
    ts, beta = float(ix.index_start), float(ix.index_angle)
    rr, rp = float(ix.roller_radius), float(ix.pitch_radius)
    in_lo, in_hi = ts - TWO_PI, ts - TWO_PI + beta
    out_lo, out_hi = ts, ts + beta

    # -- the crossover X: L(τ_in) = L(τ_out), the crossing of least parameter span (innermost loop)
    t_in = np.linspace(in_lo, in_hi, 801)
    t_out = np.linspace(out_lo, out_hi, 801)
    pin, pout = locus(ix, k, t_in)["point"], locus(ix, k, t_out)["point"]
    i, j, sa, sb = _segment_crossings(pin, pout)
    # the pieces share their dwell-side end points only when β ≈ 2π; drop touching at those ends
    ta = t_in[i] + sa * (t_in[1] - t_in[0])
    tb = t_out[j] + sb * (t_out[1] - t_out[0])
    keep = ~((ta >= in_hi - 1e-9) & (tb <= out_lo + 1e-9))
    ta, tb = ta[keep], tb[keep]
    if ta.size == 0:
        raise SpecError("indexer.centre_distance",
                        f"no crossover: cam {k}'s rollers' loci do not meet during the index "
                        f"(input angles {_deg(out_lo)}–{_deg(out_hi)}) — increase indexer.centre_distance "
                        f"or indexer.index_angle, or reduce indexer.stations")
    m = int(np.argmin(tb - ta))

    def pitch_eq(x: float, y: float):
        loc = locus(ix, k, np.array([x, y]))
        return loc["point"][0] - loc["point"][1], loc["d1"][0], -loc["d1"][1]

    tau1, tau2, res = _newton_pair(pitch_eq, ta[m], tb[m], (in_lo, out_lo), (in_hi, out_hi))
    if not res < 1e-9:
        raise SpecError("indexer.centre_distance",
                        f"cam {k}: the crossover of the rollers' loci near input angle {_deg(tb[m])} does not "
                        f"converge (|ΔX| = {res:.3g} mm) — increase indexer.centre_distance")
    x_pt = locus(ix, k, np.array([tau2]))["point"][0]

    # -- the profile tip X': Q(τ'_in) = Q(τ'_out), Q = L − r_r·n, Q' = L'·(1 − r_r/ρ)
    def prof(tau: Array) -> tuple[Array, Array]:
        loc = locus(ix, k, tau)
        return loc["point"] - rr * loc["normal"], loc["d1"] * (1.0 - rr / loc["rho"])[..., None]

    c_in = np.linspace(tau1, in_hi, 801)
    c_out = np.linspace(out_lo, tau2, 801)
    i, j, sa, sb = _segment_crossings(prof(c_in)[0], prof(c_out)[0])
    ta = c_in[i] + sa * (c_in[1] - c_in[0])
    tb = c_out[j] + sb * (c_out[1] - c_out[0])
    keep = ~((ta >= in_hi - 1e-9) & (tb <= out_lo + 1e-9))
    ta, tb = ta[keep], tb[keep]
    if ta.size == 0:
        raise SpecError("indexer.roller_radius",
                        f"cam {k}: the profile's flanks do not meet (the roller swallows the lobe near input "
                        f"angle {_deg(tau2)}) — reduce indexer.roller_radius")
    m = int(np.argmin(tb - ta))

    def tip_eq(x: float, y: float):
        q, d = prof(np.array([x, y]))
        return q[0] - q[1], d[0], -d[1]

    tau_a, tau_b, res = _newton_pair(tip_eq, ta[m], tb[m], (tau1, out_lo), (in_hi, tau2))
    if not res < 1e-9:
        raise SpecError("indexer.roller_radius",
                        f"cam {k}: the profile tip near input angle {_deg(tb[m])} does not converge "
                        f"(|ΔX'| = {res:.3g} mm) — reduce indexer.roller_radius")

    # -- sampled pieces: pitch (to X) and profile (to X')
    r_d = ix.dwell_radius(k)
    n_arc = int(np.clip(math.ceil((TWO_PI - beta) / math.sqrt(8.0 * CHORD_TOL / max(r_d - rr, 1e-9))) + 1,
                        _MIN_PIECE, _MAX_PIECE))
    t_dw = np.linspace(in_hi, out_lo, n_arc)
    pieces = []
    for role, tau in (("incoming", _grid(ix, k, tau1, in_hi, False)), ("dwell", t_dw),
                      ("outgoing", _grid(ix, k, out_lo, tau2, False))):
        loc = locus(ix, k, tau)
        pieces.append(PitchPiece(role, tau, loc["point"], loc["normal"], loc["rho"]))
    g_in = _grid(ix, k, tau_a, in_hi, True)
    g_out = _grid(ix, k, out_lo, tau_b, True)
    tau_p = np.concatenate([g_in, t_dw[1:-1], g_out])
    loc = locus(ix, k, tau_p)
    rho = loc["rho"]
    if not (np.all(np.isfinite(loc["speed"])) and loc["speed"].min() > 0):
        i0 = int(np.argmin(loc["speed"]))
        raise SpecError("indexer.centre_distance",
                        f"cam {k}: the pitch curve has a cusp at input angle {_deg(tau_p[i0] % TWO_PI)} — "
                        f"increase indexer.centre_distance or indexer.index_angle")
    under = (rho > 0) & (rho <= rr)
    if under.any():
        i0 = int(np.argmax(under))
        raise SpecError("indexer.roller_radius",
                        f"cam {k}: undercut at input angle {_deg(tau_p[i0] % TWO_PI)}: the pitch curve's radius of "
                        f"curvature {rho[i0]:.6g} mm ≤ roller radius {rr:.6g} mm — reduce indexer.roller_radius "
                        f"or increase indexer.index_angle")
    profile = loc["point"] - rr * loc["normal"]
    tip = 0.5 * (profile[0] + profile[-1])
    profile[0] = profile[-1] = tip
    profile_radius = rho - rr

    # -- simple closed curves: star-shaped about O, polar angle strictly decreasing (clockwise)
    joined = (np.concatenate([pieces[0].points[:-1], pieces[1].points[:-1], pieces[2].points]),
              np.concatenate([pieces[0].tau[:-1], pieces[1].tau[:-1], pieces[2].tau]))
    for name, pts, tt in (("pitch curve", *joined), ("profile", profile, tau_p)):
        ang = np.unwrap(np.arctan2(pts[:, 1], pts[:, 0]))
        step = np.diff(ang)
        total = ang[0] - ang[-1]
        if not (np.all(step < 0) and abs(total - TWO_PI) < 1e-6):
            bad = int(np.argmax(step >= 0)) if (step >= 0).any() else 0
            raise SpecError("indexer.centre_distance",
                            f"cam {k}: the {name} is not a simple curve about the input axis (it turns back near "
                            f"input angle {_deg(tt[bad] % TWO_PI)}) — increase indexer.centre_distance or "
                            f"indexer.index_angle")

    # -- contacts on the grid: roller 0 on [θ_s, τ'_out], roller 1 on [τ'_in + 2π, θ_s + 2π]
    windows = ((ts, tau_b), (tau_a + TWO_PI, ts + TWO_PI))
    engaged = np.stack([(theta >= windows[0][0]) & (theta <= windows[0][1]),
                        (theta >= windows[1][0]) & (theta <= windows[1][1])], axis=-1)
    pa = np.full(engaged.shape, np.nan)
    arm_p, arm_o, c_rad = pa.copy(), pa.copy(), pa.copy()
    for jr in (0, 1):
        loc_j = locus(ix, k, theta - TWO_PI * jr)
        ap, ao = _arms(ix, k, jr, theta, loc_j)
        e = engaged[:, jr]
        arm_p[e, jr], arm_o[e, jr] = ap[e], ao[e]
        pa[e, jr] = np.arccos(np.clip(np.abs(ap[e]) / rp, 0.0, 1.0))
        c_rad[e, jr] = loc_j["rho"][e] - rr
    cam = IndexCam(k, ix.dwell_angle(k), r_d, tuple(pieces), x_pt, (tau1, tau2), tip, (tau_a, tau_b),
                   profile, loc["normal"], profile_radius, tau_p, windows, engaged, pa, arm_p, arm_o, c_rad)
    return cam


def _arms(ix: ParallelIndexer, k: int, jr: int, theta: Array, loc: dict) -> tuple[Array, Array]:
    """arm_P and arm_O [mm] of roller ``jr``'s contact normal at ``theta`` (fixed frame)."""
    p, n = loc["p"], loc["n_fixed"]
    pc = p - np.array([float(ix.centre_distance), 0.0])
    return -_cross(pc, n), _cross(p, n)


def _distances(points: Array, poly: Array) -> tuple[Array, Array]:
    """Unsigned distance [mm] of ``points`` (n, 2) to the closed polyline ``poly`` (m, 2, last
    vertex = first), and the index of the nearest point's segment.

    The nearest vertex (a k-d tree) and the two segments at it: the profile's vertices are spaced
    far closer than the rollers come to it, so the nearest point lies on one of them."""
    from scipy.spatial import cKDTree  # deferred: scipy.spatial, an indexer's clearance alone

    m = poly.shape[0] - 1
    _, i = cKDTree(poly[:-1]).query(points)
    segs = np.stack([(i - 1) % m, i], axis=1)                      # (n, 2) candidate segments
    a = poly[segs]
    d = poly[segs + 1] - a
    q = points[:, None, :] - a
    t = np.clip(np.einsum("pij,pij->pi", q, d) / np.einsum("pij,pij->pi", d, d), 0.0, 1.0)
    r = q - t[..., None] * d
    dist = np.einsum("pij,pij->pi", r, r)
    best = np.argmin(dist, axis=1)
    rows = np.arange(points.shape[0])
    return np.sqrt(dist[rows, best]), segs[rows, best]


def _inside(points: Array, poly: Array) -> Array:
    """Whether ``points`` lie inside the closed polyline ``poly``, star-shaped about O with polar
    angle decreasing along it."""
    ang = np.unwrap(np.arctan2(poly[:, 1], poly[:, 0]))[::-1]
    pa = np.arctan2(points[:, 1], points[:, 0])
    pa = ang[0] + np.mod(pa - ang[0], TWO_PI)
    # the boundary's radius at the point's polar angle, linear along each chord's direction
    i = np.clip(np.searchsorted(ang, pa) - 1, 0, ang.size - 2)
    p0 = poly[::-1][i]
    p1 = poly[::-1][i + 1]
    u = np.stack([np.cos(pa), np.sin(pa)], axis=-1)
    d = p1 - p0
    den = _cross(u, d)
    with np.errstate(divide="ignore", invalid="ignore"):
        r_b = np.where(den != 0, _cross(p0, d) / den, np.maximum(np.hypot(*p0.T), np.hypot(*p1.T)))
    return np.hypot(points[:, 0], points[:, 1]) < r_b


def _clearance(ix: ParallelIndexer, cams: tuple[IndexCam, ...], theta: Array) -> Clearance:
    """The gaps between the cams and their planes' rollers that they do not hold (module docs)."""
    n = int(ix.stations)
    ts, beta, rr = float(ix.index_start), float(ix.index_angle), float(ix.roller_radius)
    best = (math.inf, 0.0, 0, 0)
    hand = (math.inf, 0.0)
    roll = np.arange(n)
    for c in cams:
        p, _, _ = roller_state(ix, c.index, roll[None, :], theta[:, None])      # (S, N, 2)
        q = _rot(-theta[:, None], p)
        idle = np.ones(q.shape[:2], dtype=bool)
        idle[:, 0] = theta > ts + beta
        idle[:, 1] = False
        handover = np.zeros_like(idle)
        handover[:, 0] = (theta > c.windows[0][1]) & (theta <= ts + beta)
        handover[:, 1] = theta < c.windows[1][0]
        r_max = float(np.hypot(c.profile[:, 0], c.profile[:, 1]).max())
        near = np.hypot(q[..., 0], q[..., 1]) < r_max + rr + float(ix.pitch_radius)
        for mask, is_idle in ((idle & near, True), (handover, False)):
            si, ri = np.nonzero(mask)
            if si.size == 0:
                continue
            pts = q[si, ri]
            dist, _ = _distances(pts, c.profile)
            gap = np.where(_inside(pts, c.profile), -dist, dist) - rr
            g = int(np.argmin(gap))
            if is_idle and gap[g] < best[0]:
                best = (float(gap[g]), float(theta[si[g]]), c.index, int(ri[g]))
            if not is_idle and gap[g] < hand[0]:
                hand = (float(gap[g]), float(theta[si[g]]))
        # idle rollers far from the cam: their gap is at least |q| − r_max − r_r
        far = idle & ~near
        if far.any():
            lb = float((np.hypot(q[..., 0], q[..., 1])[far] - r_max - rr).min())
            if lb < best[0]:
                best = (lb, best[1], best[2], best[3])
    ok = best[0] > 0 and (hand[0] > -1e-6 or not math.isfinite(hand[0]))
    return Clearance(best[0], best[1], best[2], best[3], hand[0], hand[1], bool(ok))


def _locking(ix: ParallelIndexer, cams: tuple[IndexCam, ...], theta: Array) -> tuple[Locking, dict]:
    """Forward and backward constraint at each θ and the driving contact (module docs)."""
    arms = np.concatenate([c.arm_p for c in cams], axis=1)                  # (S, 2·n_c)
    rad = np.concatenate([c.contact_radius for c in cams], axis=1)
    rp = float(ix.pitch_radius)
    fwd = np.where(np.isfinite(arms) & (arms > 0), arms, -np.inf)
    bwd = np.where(np.isfinite(arms) & (arms < 0), -arms, -np.inf)
    i_f, i_b = np.argmax(fwd, axis=1), np.argmax(bwd, axis=1)
    rows = np.arange(theta.size)
    f_best, b_best = fwd[rows, i_f], bwd[rows, i_b]
    ang_f = np.where(np.isfinite(f_best), np.arccos(np.clip(f_best / rp, 0, 1)), math.pi / 2)
    ang_b = np.where(np.isfinite(b_best), np.arccos(np.clip(b_best / rp, 0, 1)), math.pi / 2)
    wf, wb = int(np.argmax(ang_f)), int(np.argmax(ang_b))
    ok = bool(ang_f[wf] < math.pi / 2 and ang_b[wb] < math.pi / 2)
    has = np.isfinite(f_best)
    drive = {"driving_angle": np.where(has, ang_f, np.nan), "driving_arm": np.where(has, f_best, np.nan),
             "driving_cam": np.where(has, i_f // 2, -1), "driving_roller": np.where(has, i_f % 2, -1),
             "driving_radius": np.where(has, rad[rows, i_f], np.nan)}
    held = np.isfinite(b_best)
    drive.update({"holding_angle": np.where(held, ang_b, np.nan), "holding_arm": np.where(held, b_best, np.nan),
                  "holding_radius": np.where(held, rad[rows, i_b], np.nan)})
    return Locking(float(ang_f[wf]), float(theta[wf]), float(ang_b[wb]), float(theta[wb]), ok), drive


def design_parallel(ix: ParallelIndexer, samples: int = 721, strict: bool = True) -> ParallelDesign:
    """The parallel indexer's cams and contacts on ``samples`` input angles θ_s + [0, 2π].

    Raises SpecError (naming the field to change, with the input angle) when the geometry cannot be
    built: no crossover, a cusp, an undercut, a pitch curve or profile that is not simple; with
    ``strict`` also when the turret is not positively driven or a roller touches a cam it is not
    engaged with (otherwise those verdicts are returned in ``clearance`` and ``locked``)."""
    s = integer("samples", samples, "an integer ≥ 8", lambda v: v >= 8)
    theta = float(ix.index_start) + np.linspace(0.0, TWO_PI, s)
    psi, d1, d2 = turret_angle(ix, theta)
    with np.errstate(all="ignore"):
        cams = tuple(_build_cam(ix, k, theta) for k in range(int(ix.cams)))
        lock, drive = _locking(ix, cams, theta)
        clear = _clearance(ix, cams, theta)
    if strict and not lock.ok:
        which, at = (("forward", lock.forward_theta) if lock.forward_angle >= math.pi / 2
                     else ("backward", lock.backward_theta))
        raise SpecError("indexer.centre_distance",
                        f"the turret is not positively driven: no cam holds it {which} at input angle {_deg(at)} "
                        f"— increase indexer.centre_distance or indexer.index_angle")
    if strict and not clear.ok:
        if clear.gap <= 0:
            raise SpecError("indexer.roller_radius",
                            f"roller {clear.roller} of cam {clear.cam}'s plane hits the cam at input angle "
                            f"{_deg(clear.theta)} (gap {clear.gap:.6g} mm) — reduce indexer.roller_radius or "
                            f"increase indexer.centre_distance")
        raise SpecError("indexer.roller_radius",
                        f"a roller leaving or reaching a lobe tip cuts the cam at input angle "
                        f"{_deg(clear.handover_theta)} (gap {clear.handover_gap:.6g} mm) — reduce "
                        f"indexer.roller_radius or increase indexer.centre_distance")
    return ParallelDesign(ix, theta, psi, d1, d2, cams, drive["driving_angle"], drive["driving_arm"],
                          drive["driving_cam"], drive["driving_roller"], drive["driving_radius"],
                          drive["holding_angle"], drive["holding_arm"], drive["holding_radius"], clear, lock)


# ---------------------------------------------------------------------------------------------
# the turret angle from the built profiles alone

@dataclass(frozen=True)
class RecoveredAngle:
    """The turret angle found from the profiles: ``psi`` [rad] at ``theta`` [rad], and ``slack``
    [rad], the width of the turret angles no roller's circle crosses any profile at (≈ 0, or
    slightly negative, where the cams lock the turret; > 0 where it could move freely)."""

    theta: Array
    psi: Array
    slack: Array


def _closed_pitch(ix: ParallelIndexer, cam: IndexCam) -> tuple[Array, Array]:
    """The roller-centre curve of the BUILT profile: each vertex pushed out by r_r along its
    normal, closed round the tip X' by the arc of radius r_r about it (the roller pivoting on the
    corner); points and unit tangents (clockwise)."""
    rr = float(ix.roller_radius)
    pts = cam.profile + rr * cam.profile_normals
    n_b, n_a = cam.profile_normals[-1], cam.profile_normals[0]
    a_b, a_a = math.atan2(n_b[1], n_b[0]), math.atan2(n_a[1], n_a[0])
    sweep = (a_b - a_a) % TWO_PI                   # the normal turns clockwise from n_B to n_A
    ang = a_b - sweep * np.linspace(0.0, 1.0, 65)[1:-1]
    arc_n = np.stack([np.cos(ang), np.sin(ang)], axis=-1)
    normals = np.concatenate([cam.profile_normals, arc_n, n_a[None]])
    pts = np.concatenate([pts, cam.profile[0] + rr * arc_n, pts[:1]])
    return pts, -_J(normals)


def _hermite_crossings(pts: Array, tan: Array, centre: Array, radius: float) -> tuple[Array, Array, Array]:
    """Where the circles (``centre`` (S, 2), ``radius``) cross the closed curve through ``pts``
    with unit tangents ``tan``, cubic Hermite between vertices: (row, point, tangent)."""
    rows, segs = [], []
    for s in range(0, centre.shape[0], _BLOCK):          # blocks of θ, for memory
        f = np.hypot(pts[None, :, 0] - centre[s:s + _BLOCK, None, 0],
                     pts[None, :, 1] - centre[s:s + _BLOCK, None, 1]) - radius
        r, i = np.nonzero((f[:, :-1] > 0) != (f[:, 1:] > 0))
        rows.append(r + s)
        segs.append(i)
    row, seg = np.concatenate(rows), np.concatenate(segs)
    a, b = pts[seg], pts[seg + 1]
    h = np.hypot(*(b - a).T)[:, None]
    ta, tb = tan[seg] * h, tan[seg + 1] * h
    c = centre[row]
    fa = np.hypot(*(a - c).T) - radius
    fb = np.hypot(*(b - c).T) - radius
    u = (fa / (fa - fb))[:, None]
    for _ in range(8):                                    # Newton on |H(u) − c|² = radius²
        u2, u3 = u * u, u * u * u
        hp = (2 * u3 - 3 * u2 + 1) * a + (u3 - 2 * u2 + u) * ta + (-2 * u3 + 3 * u2) * b + (u3 - u2) * tb
        dh = (6 * u2 - 6 * u) * a + (3 * u2 - 4 * u + 1) * ta + (-6 * u2 + 6 * u) * b + (3 * u2 - 2 * u) * tb
        g = np.einsum("ij,ij->i", hp - c, hp - c) - radius**2
        dg = 2.0 * np.einsum("ij,ij->i", hp - c, dh)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(dg != 0, g / dg, 0.0)
        u = np.clip(u - step[:, None], 0.0, 1.0)
    u2, u3 = u * u, u * u * u
    hp = (2 * u3 - 3 * u2 + 1) * a + (u3 - 2 * u2 + u) * ta + (-2 * u3 + 3 * u2) * b + (u3 - u2) * tb
    dh = (6 * u2 - 6 * u) * a + (3 * u2 - 4 * u + 1) * ta + (-6 * u2 + 6 * u) * b + (3 * u2 - 2 * u) * tb
    return row, hp, dh


def output_angle_from_profile(design: ParallelDesign, theta: Array) -> RecoveredAngle:
    """The turret angle ψ [rad] at input angles ``theta`` [rad] found from the built profiles alone
    (their vertices, normals and r_r; not the law): ψ where the rollers' circles are tangent to the
    profiles, i.e. where a roller centre lies on the profile's outward offset by r_r.

    For each θ and cam, the turret pitch circle (in the cam frame) crosses the offset curve
    (cubic Hermite between vertices, from the stored normals) at entry/exit angles; mapped to ψ
    modulo T = 2π/N through every roller of the plane, each inside arc is a ψ interval no roller may
    be at.  ψ is the middle of the widest gap left between the intervals of all cams (its width is
    ``slack``), placed in the turn [0, T] by the index timing (ψ ≈ T·(θ − θ_s)/β, 0 before, T after)."""
    ix = design.indexer
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    t_st, rp = ix.station_angle, float(ix.pitch_radius)
    p_fix = np.array([float(ix.centre_distance), 0.0])
    centre = _rot(-theta, np.broadcast_to(p_fix, (theta.size, 2)))      # P in the cam frame, (S, 2)
    starts, lengths = [], []
    for cam in design.cams:
        pts, tan = _closed_pitch(ix, cam)
        row, hp, dh = _hermite_crossings(pts, tan, centre, rp)
        rel = hp - centre[row]
        gamma = np.arctan2(rel[:, 1], rel[:, 0])
        # the roller at cam-frame angle γ about P has ψ ≡ a_k − θ − γ (mod T); entering the cam
        # as ψ grows where the curve's tangent and the radial direction agree (T·e ≥ 0)
        psi_full = np.mod(cam.dwell_angle - theta[row] - gamma, TWO_PI)
        cos_t = np.einsum("ij,ij->i", dh, rel) / (np.hypot(*dh.T) * np.hypot(*rel.T))
        order = np.lexsort((psi_full, row))
        row, psi_full, cos_t = row[order], psi_full[order], cos_t[order]
        count = np.bincount(row, minlength=theta.size)
        first = np.concatenate([[0], np.cumsum(count)[:-1]])
        rank = np.arange(row.size) - first[row]
        # entries and exits alternate round the circle: take the sense of each row's most
        # transversal crossing (a grazing one, a roller on OP at the dwell, cannot tell)
        by_t = np.lexsort((-np.abs(cos_t), row))
        lead = by_t[first[count > 0]]
        lead_of = np.zeros(theta.size, dtype=int)
        lead_of[row[lead]] = lead
        lead_row = lead_of[row]
        entry = (cos_t[lead_row] >= 0) == ((rank - rank[lead_row]) % 2 == 0)
        nxt = np.where(rank + 1 < count[row], np.arange(row.size) + 1, first[row])
        length = np.mod(psi_full[nxt] - psi_full, TWO_PI)
        length = np.where(count[row] == 1, TWO_PI, length)
        kmax = int(count.max()) if count.size else 0
        st = np.full((theta.size, max(kmax, 1)), np.inf)
        ln = np.full_like(st, -np.inf)
        st[row[entry], rank[entry]] = np.mod(psi_full[entry], t_st)
        ln[row[entry], rank[entry]] = length[entry]
        starts.append(st)
        lengths.append(ln)
    st = np.concatenate(starts, axis=1)
    ln = np.concatenate(lengths, axis=1)
    st3 = np.concatenate([st - t_st, st, st + t_st], axis=1)
    with np.errstate(invalid="ignore"):
        en3 = st3 + np.concatenate([ln, ln, ln], axis=1)
    order = np.argsort(st3, axis=1)
    st3 = np.take_along_axis(st3, order, axis=1)
    en3 = np.take_along_axis(en3, order, axis=1)
    en3 = np.where(np.isfinite(st3), en3, -np.inf)
    reach = np.maximum.accumulate(en3, axis=1)
    gap = st3[:, 1:] - reach[:, :-1]
    ok = (reach[:, :-1] >= 0) & (reach[:, :-1] < t_st) & np.isfinite(st3[:, 1:])
    gap = np.where(ok, gap, -np.inf)
    mid = 0.5 * (reach[:, :-1] + st3[:, 1:])
    rel_t = np.mod(theta - float(ix.index_start), TWO_PI)
    guess = t_st * np.clip(rel_t / float(ix.index_angle), 0.0, 1.0)
    # a symmetric cam set also locks the turret half a station off (each plane's rollers on the
    # other's dwell arcs); of the gaps that lock, the one nearest the index timing
    with np.errstate(invalid="ignore"):
        off = np.abs(np.mod(mid - guess[:, None] + 0.5 * t_st, t_st) - 0.5 * t_st)
    locks = gap >= np.max(gap, axis=1, keepdims=True) - 1e-6
    best = np.argmin(np.where(locks, off, np.inf), axis=1)
    rows = np.arange(theta.size)
    slack = gap[rows, best]
    psi = np.where(np.isfinite(slack), mid[rows, best], np.nan)
    psi = psi + t_st * np.round((guess - psi) / t_st)
    return RecoveredAngle(theta, psi, np.where(np.isfinite(slack), slack, np.nan))

"""Kinematic geometry of the two SPATIAL indexers — the barrel (cylindrical-cam) indexer and the
globoidal (roller-gear) indexer: the rollers' contact lines with the cam's rib, the rib's two flank
surfaces as envelopes of the rollers, which roller touches which flank when, pressure angles, the
envelope's regularity (undercut), the rib's thickness and the turret angle recovered from the
flank surfaces alone.

Units: lengths in mm, angles in radians (degrees only in :meth:`SpatialDesign.summary`).

Frames and signs (enough to recompute everything from these lines):

* Fixed frame: the input (cam) axis is the z axis through O; the turret axis is the line through
  P = (C, 0, 0) along +y.  The axes are at right angles, C apart along x, and do not meet.
  u(α) = (cos α, 0, sin α) and τ(α) = du/dα = (−sin α, 0, cos α) are the turret's radial and
  tangential directions in its plane y = 0 (which holds the cam axis); α = π points from P at the
  cam axis.  k = (0, 0, 1).
* The input angle θ turns the cam counter-clockwise about +z: a point q of the cam frame is at
  Rz(θ)·q in the fixed frame (the frames coincide at θ = 0).
* The turret angle ψ ≥ 0 turns the turret about −y, i.e. every roller's α grows by ψ:
  ψ(θ) = T·(m + F(u)), T = 2π/N, m = ⌊(θ − θ_s)/2π⌋, u = clip((θ − θ_s − 2πm)/β, 0, 1),
  F = ``evaluate_law(law, u)``; ψ' = T·F'/β, ψ'' = T·F''/β² (0 on the dwell).
* Roller j (any integer; j and j + N are the same roller) sits at α_j(θ) = π + T·(j − ½) + ψ(θ): at
  the dwell rollers 0 and 1 straddle the rib symmetrically about α = π (roller 0 at +z, roller 1 at
  −z); through an index roller 0 moves from π − T/2 to π + T/2, roller 1 leaves, roller −1 comes in.
  Since ψ(θ + 2π) = ψ(θ) + T, roller j at θ has the pose of roller 0 at θ + 2πj: one locus,
  τ ↦ pose of roller 0 at input angle τ, carries every roller ("τ = θ + 2πj").
* Roller axis (fixed frame) c(t) = a + t·d, the roller the cylinder of radius r_r about it for
  t ∈ [t0, t1] (``roller_start``, ``roller_end``) — or, with a cone angle γ ≠ 0
  (``roller_cone_angle``), the cone of radius r(t) = r_r + (t − t_m)·k, k = tan γ, t_m = (t0 + t1)/2
  (r_r the radius at the working length's middle; γ > 0 widens the roller away from the turret
  axis — apex at t_m − r_r/k; on the globoidal turret γ = atan(r_r/t_m) puts it at P):
    barrel:    a = P + R_p·u(α) (on the plane y = 0), d = +y: the roller stands on the turret's face
               (beyond y = t1) and points at the cam; t is the height above the plane y = 0.
    globoidal: a = P, d = u(α): the roller is radial on the turret, t the distance from P.
* Relative motion in the cam frame: for a fixed-frame vector field q(θ), the cam frame sees
  Rz(−θ)·q, whose θ-derivative is Rz(−θ)·Dq with Dq = q' − k × q (and D²q = q'' − 2k × q' +
  k × (k × q)); the scalars below are rotation invariant and computed in the fixed frame.
* Relative angular velocity of the turret seen from the cam: Ω = −ψ'·ŷ − k (fixed frame, per rad
  of input), so Dd = Ω × d, and DΩ = −ψ''·ŷ − ψ'·x̂.
* Meshing: a roller point s = c(t) + r(t)·n (n ⟂ d, |n| = 1, the roller's radial direction) is on
  the cam's surface when N·V = 0, N = (n − k·d)/q, q = √(1 + k²), the roller's outward unit
  normal, and V = w + r·Ω × n its velocity relative to the cam, w(θ, t) = Da + t·Dd the axis
  point's; the roller's spin drops out (a surface of revolution).  With w̃ = w − k·r·(d × Ω) and
  m = d × w̃ this reads n·w̃ = k·(d·w), so n = (k·(d·w)/|m|)·(m × d)/|m| ± √(1 − (k·(d·w)/|m|)²)·m/|m|
  — for a cylinder (k = 0) n = ±m/|m|, m = d × w: each roller has two contact lines, its two sides
  (a cone none where k·|d·w| > |m|).
* Sides: side s = +1 is the one with m·τ(α_j) > 0 (n·τ > 0) — the side facing roller j + 1 — and side −1 the
  one facing roller j − 1.  The rib between rollers j and j + 1 has roller j's side +1 and roller
  j + 1's side −1 as its flanks.  On side +1 the rib pushes the roller backwards (α decreasing): it
  holds the turret; on side −1 it drives it forward.  The flank's outward unit normal (from the
  rib into the roller) is −N.
* Pressure angle: the angle between the contact normal N and the roller axis point's path in the
  fixed frame (direction τ(α), for both indexers): arccos |N·τ| ∈ [0, π/2].
* Band (the rib's material extent; a contact point q of the cam frame, ρ its distance to the cam
  axis, z its axial coordinate): |z| ≤ W/2 (``cam_width``) and
    barrel:    root_radius ≤ ρ ≤ outer_radius (the cylinders of the rib's root and top);
    globoidal: tip_radius ≤ g ≤ root_radius with g = √((C − ρ)² + z²), ρ < C (the root and tip
               globoids: tori about the circle P traces about the cam axis).
  A roller side is ENGAGED at θ while some point of its contact line lies in the band; the flank
  surfaces are the contact lines' points in the band.
* Regularity: the envelope Σ(θ, t) (the contact point in the cam frame) is singular where
  Σ_θ × Σ_t = 0.  With the meshing function f(t, φ, θ) = N·V (φ the angle of n about d) and the
  roller's surface derivatives s_t = d + k·n, s_φ = r·(d × n), Litvin's determinant
  Δ = f_φ·(V × s_t)·N − f_θ·(s_φ × s_t)·N − f_t·(V × s_φ)·N, (s_φ × s_t)·N = r·q, equals
  f_φ·(Σ_θ × Σ_t)·N, where f_t = N·(Dd + k·Ω × n), f_φ = (d × n)·V/q + r·N·(Ω × (d × n)),
  f_θ = (Ω × N)·V + N·(D²a + t·D²d + r·(DΩ × n + Ω × (Ω × n))).  The margin μ = Δ/(q·f_φ²) is
  dimensionless; for a cylinder it is −r_r·Ψ/|m|² with Litvin's limit function
  Ψ = n·(D²a + t·D²d) − 2(d·w)(n·Dd) + r_r(n·Dd)² − |m|²/r_r, and 1 − r_r/ρ for a roller on the
  concave side of a planar path of radius ρ: μ > 0 is a regular envelope, μ ≤ 0 an undercut.
* Rib thickness: the distance from a point of a flank (side +1 of the pose τ) to the nearest
  point, on its rib side (along +N), of the other flank (side −1) among the poses τ + 2π ± π/2.

Grid: the input angles θ_s + [0, 2π] (``samples``) hold the index's ends θ_s and θ_s + β; the
locus is sampled on τ = θ + 2πj for the N rollers j = j_lo … j_lo + N − 1, j_lo = −⌊(N − 1)/2⌋
(row (j − j_lo)·(S − 1) + i is roller j at θ_i), and t on ``lengths`` points of [t0, t1].

Catalogue-like geometry.  Barrel: N = 4–8 with β = 180°–300°; the axes' offset C ≈ R_p·cos(π/N)
puts the dwell's rollers square to the cam; rollers ≈ 0.2·R_p; the idle rollers (α ≈ π ± 3T/2)
must clear the rib (outer radius < C − R_p·cos(3π/N) − r_r, or outside the cam width).  The default,
N = 6, β = 240°, R_p = 60, C = 52, r_r = 12, rollers over t = 27–45, rib radii 25–40, width 80 mm,
is valid: 2–3 roller sides engaged, the driving contact's pressure angle ≤ 49° (the leaving roller's
last contact reaches ≈ 74°), regularity margin ≥ 0.55.  Globoidal: N = 6–16, β = 90°–300°, C ≈ 1.5×
the rollers' outer end, and a width that holds the dwell's two rollers' inner sides and leaves their
outer sides out (t1·sin(T/2) − r_r·cos(T/2) < W/2 < t0·sin(T/2) + r_r·cos(T/2)); the default,
N = 12, β = 120°, C = 150, rollers r_r = 12 over t = 74–96, rib globoids 76–100, width 56 mm, is
valid: 2–3 sides engaged, pressure angles ≤ 38°, margin ≥ 0.72.  A wider cam leaves lands beyond
the outer rollers (each dwell roller then runs in a groove: 4–5 sides engaged).
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...errors import SpecError
from ...motion.laws import LAW_FUNCTIONS, NormalisedLaw, evaluate_law, is_law, law_name
from .fields import integer, number

Array = np.ndarray
TWO_PI = 2.0 * math.pi
#: |d × w| [mm/rad] below which a contact line is undefined (the axis point slides along the axis)
_TINY_SPEED = 1e-9
#: |n·τ| below which a contact cannot move the turret (pressure angle 90°)
_TINY_COS = 1e-6
#: rows of the Lagrange stencil of :func:`output_angle_from_surface` (degree 6)
_STENCIL = 7


# ---------------------------------------------------------------------------------------------
# parameters

def _positive(ix: Any, names: tuple[str, ...]) -> dict[str, float]:
    out = {}
    for name in names:
        v = number(name, getattr(ix, name))
        if v <= 0:
            raise SpecError(f"indexer.{name}", f"must be > 0 mm, got {v!r}")
        out[name] = v
    return out


def _common(ix: Any) -> None:
    integer("stations", ix.stations, "an integer in [2, 64]", lambda v: 2 <= v <= 64)
    beta = number("index_angle", ix.index_angle)
    if not 0 < beta < TWO_PI:
        raise SpecError("indexer.index_angle", f"must be in (0, 2π) rad (a dwell must remain), got {beta!r}")
    if not is_law(ix.law):
        raise SpecError("indexer.law", f"unknown law {ix.law!r}; one of {', '.join(sorted(LAW_FUNCTIONS))} "
                        "or a NormalisedLaw (a motion program's rise)")
    number("index_start", ix.index_start)


def _unit(alpha: Array) -> tuple[Array, Array]:
    c, s = np.cos(alpha), np.sin(alpha)
    z = np.zeros_like(c)
    return np.stack([c, z, s], axis=-1), np.stack([-s, z, c], axis=-1)


class _Rollers:
    """The rollers' shape, shared by both indexers: a cylinder of radius r_r, or a cone of half
    angle γ (``roller_cone_angle``) whose radius is r_r at the working length's middle."""

    @property
    def taper(self) -> float:
        """k = tan γ: the roller's radius grows by k mm per mm of t (0: a cylinder)."""
        return math.tan(float(self.roller_cone_angle))  # type: ignore[attr-defined]

    def radius_at(self, t: Array) -> Array:
        """r(t) = r_r + (t − t_m)·tan γ [mm], the roller's radius at axis parameters ``t`` [mm]."""
        mid = 0.5 * (float(self.roller_start) + float(self.roller_end))  # type: ignore[attr-defined]
        return float(self.roller_radius) + (np.asarray(t, dtype=float) - mid) * self.taper  # type: ignore[attr-defined]

    @property
    def largest_radius(self) -> float:
        """The roller's largest radius over [t0, t1] [mm]."""
        return float(np.max(self.radius_at(np.array([float(self.roller_start), float(self.roller_end)]))))  # type: ignore[attr-defined]


def _cone(ix: Any, v: dict[str, float]) -> None:
    """The cone angle's rules: |γ| < 45°, r(t) > 0 over the working length."""
    g = number("roller_cone_angle", ix.roller_cone_angle)
    if not abs(g) < 0.25 * math.pi:
        raise SpecError("indexer.roller_cone_angle", f"must be in (−45°, 45°), got {math.degrees(g)!r}°")
    ends = ix.radius_at(np.array([v["roller_start"], v["roller_end"]]))
    if not (ends > 0).all():
        raise SpecError("indexer.roller_cone_angle",
                        f"the cone ends at a point within the working length (radii {ends[0]:.6g} / {ends[1]:.6g} "
                        f"mm at t0 / t1) — use a smaller |indexer.roller_cone_angle| or a larger "
                        f"follower.roller_radius, got {math.degrees(g)!r}°")


@dataclass(frozen=True)
class BarrelIndexer(_Rollers):
    """A barrel (cylindrical-cam) indexer (validated on construction: a bad field raises
    :class:`SpecError` named ``indexer.<field>``).  See the module's conventions.

    Attributes:
        stations: N (integer 2–64); the turret turns by 2π/N per index.
        index_angle: β [rad], 0 < β < 2π.  law: a key of ``LAW_FUNCTIONS`` or a
            :class:`~cam_workbench.generators.motion.laws.NormalisedLaw` (a motion program's rise).
        centre_distance: C [mm], the axes' offset (x of the turret axis).
        pitch_radius: R_p [mm], the rollers' circle about the turret axis.
        roller_radius: r_r [mm].  roller_start, roller_end: t0 < t1 [mm], the roller's working
            length, heights above the plane y = 0 through the cam axis.
        root_radius, outer_radius: the rib's root and top cylinders [mm] (root < outer ≤ t1,
            root < t0: the roller's end clears the root).
        cam_width: W [mm], the cam's length along its axis, centred on z = 0.
        index_start: θ_s [rad].
        roller_cone_angle: γ [rad], |γ| < π/4: 0 cylindrical rollers, else conical (module docs).
    """

    stations: int = 6
    index_angle: float = 4.0 * math.pi / 3.0
    law: str | NormalisedLaw = "modified_sine"
    centre_distance: float = 52.0
    pitch_radius: float = 60.0
    roller_radius: float = 12.0
    roller_start: float = 27.0
    roller_end: float = 45.0
    root_radius: float = 25.0
    outer_radius: float = 40.0
    cam_width: float = 80.0
    index_start: float = 0.0
    roller_cone_angle: float = 0.0

    def __post_init__(self) -> None:
        _common(self)
        v = _positive(self, ("centre_distance", "pitch_radius", "roller_radius", "roller_start", "roller_end",
                             "root_radius", "outer_radius", "cam_width"))
        n = int(self.stations)
        if not v["roller_start"] < v["roller_end"]:
            raise SpecError("indexer.roller_end", f"must be > indexer.roller_start ({v['roller_start']!r} mm), "
                                                  f"got {v['roller_end']!r}")
        if not v["root_radius"] < v["outer_radius"]:
            raise SpecError("indexer.outer_radius", f"must be > indexer.root_radius ({v['root_radius']!r} mm), "
                                                    f"got {v['outer_radius']!r}")
        if not v["root_radius"] < v["roller_start"]:
            raise SpecError("indexer.roller_start",
                            f"must be > indexer.root_radius ({v['root_radius']!r} mm: the roller's end would cut "
                            f"the rib's root), got {v['roller_start']!r}")
        if not v["outer_radius"] <= v["roller_end"]:
            raise SpecError("indexer.roller_end",
                            f"must be ≥ indexer.outer_radius ({v['outer_radius']!r} mm: the rollers must cover the "
                            f"rib's height), got {v['roller_end']!r}")
        _cone(self, v)
        gap = v["pitch_radius"] * math.sin(math.pi / n)
        if not self.largest_radius < gap:
            raise SpecError("indexer.roller_radius",
                            f"the roller's largest radius must be < R_p·sin(π/N) = {gap:.6g} mm (neighbouring "
                            f"rollers touch), got {self.largest_radius!r}")

    @property
    def station_angle(self) -> float:
        """T = 2π/N [rad]."""
        return TWO_PI / int(self.stations)

    def roller_pose(self, alpha: Array) -> tuple[Array, Array, Array, Array, Array, Array]:
        """a, d and their α-derivatives a_α, a_αα, d_α, d_αα (fixed frame, mm) of a roller at ``alpha``."""
        u, tau = _unit(np.asarray(alpha, dtype=float))
        rp = float(self.pitch_radius)
        a = np.array([float(self.centre_distance), 0.0, 0.0]) + rp * u
        d = np.broadcast_to(np.array([0.0, 1.0, 0.0]), u.shape)
        zero = np.zeros_like(u)
        return a, rp * tau, -rp * u, d, zero, zero

    def in_band(self, q: Array) -> Array:
        """Whether cam-frame points ``q`` (..., 3) [mm] lie in the rib's extent (module docs)."""
        rho = np.hypot(q[..., 0], q[..., 1])
        return ((rho >= float(self.root_radius)) & (rho <= float(self.outer_radius))
                & (np.abs(q[..., 2]) <= 0.5 * float(self.cam_width)))


@dataclass(frozen=True)
class GloboidalIndexer(_Rollers):
    """A globoidal (roller-gear) indexer with cylindrical rollers (validated on construction: a
    bad field raises :class:`SpecError` named ``indexer.<field>``).  See the module's conventions.

    Attributes:
        stations: N (integer 2–64).  index_angle: β [rad].  law: a key of ``LAW_FUNCTIONS`` or a
            :class:`~cam_workbench.generators.motion.laws.NormalisedLaw`.
        centre_distance: C [mm], the common perpendicular of the axes.
        roller_radius: r_r [mm].  roller_start, roller_end: t0 < t1 [mm], the roller's working
            length as distances from P along the roller's axis; √(t1² + r_r²) < root_radius.
        tip_radius, root_radius: the rib's tip and root globoids [mm] (distances from the circle P
            traces about the cam axis), t0 ≤ tip < root < C.
        cam_width: W [mm], the cam's length along its axis, centred on z = 0.
        index_start: θ_s [rad].
        roller_cone_angle: γ [rad], |γ| < π/4: 0 cylindrical rollers, else conical (module docs);
            r_r is then the radius at the working length's middle and √(t1² + r(t1)²) < root_radius.
    """

    stations: int = 12
    index_angle: float = 2.0 * math.pi / 3.0
    law: str | NormalisedLaw = "modified_sine"
    centre_distance: float = 150.0
    roller_radius: float = 12.0
    roller_start: float = 74.0
    roller_end: float = 96.0
    tip_radius: float = 76.0
    root_radius: float = 100.0
    cam_width: float = 56.0
    index_start: float = 0.0
    roller_cone_angle: float = 0.0

    def __post_init__(self) -> None:
        _common(self)
        v = _positive(self, ("centre_distance", "roller_radius", "roller_start", "roller_end", "tip_radius",
                             "root_radius", "cam_width"))
        n = int(self.stations)
        if not v["roller_start"] < v["roller_end"]:
            raise SpecError("indexer.roller_end", f"must be > indexer.roller_start ({v['roller_start']!r} mm), "
                                                  f"got {v['roller_end']!r}")
        if not v["tip_radius"] < v["root_radius"]:
            raise SpecError("indexer.root_radius", f"must be > indexer.tip_radius ({v['tip_radius']!r} mm), "
                                                   f"got {v['root_radius']!r}")
        if not v["root_radius"] < v["centre_distance"]:
            raise SpecError("indexer.root_radius",
                            f"must be < indexer.centre_distance ({v['centre_distance']!r} mm: the cam's waist), "
                            f"got {v['root_radius']!r}")
        if not v["roller_start"] <= v["tip_radius"]:
            raise SpecError("indexer.roller_start",
                            f"must be ≤ indexer.tip_radius ({v['tip_radius']!r} mm: the rollers must cover the "
                            f"rib's height), got {v['roller_start']!r}")
        _cone(self, v)
        corner = math.hypot(v["roller_end"], float(self.radius_at(v["roller_end"])))
        if not corner < v["root_radius"]:
            raise SpecError("indexer.roller_end",
                            f"the roller's end reaches {corner:.6g} mm from P, must be < indexer.root_radius "
                            f"({v['root_radius']!r} mm) — reduce indexer.roller_end, got {v['roller_end']!r}")
        ends = (v["roller_start"], v["roller_end"])
        gaps = [t * math.sin(math.pi / n) - float(self.radius_at(t)) for t in ends]
        if not min(gaps) > 0:
            t = ends[int(np.argmin(gaps))]
            raise SpecError("indexer.roller_radius",
                            f"the roller's radius {float(self.radius_at(t)):.6g} mm at t = {t:g} mm must be < "
                            f"t·sin(π/N) = {t * math.sin(math.pi / n):.6g} mm (neighbouring rollers touch), "
                            f"got {v['roller_radius']!r}")

    @property
    def station_angle(self) -> float:
        """T = 2π/N [rad]."""
        return TWO_PI / int(self.stations)

    def roller_pose(self, alpha: Array) -> tuple[Array, Array, Array, Array, Array, Array]:
        """a, d and their α-derivatives a_α, a_αα, d_α, d_αα (fixed frame, mm) of a roller at ``alpha``."""
        u, tau = _unit(np.asarray(alpha, dtype=float))
        a = np.broadcast_to(np.array([float(self.centre_distance), 0.0, 0.0]), u.shape)
        zero = np.zeros_like(u)
        return a, zero, zero, u, tau, -u

    def in_band(self, q: Array) -> Array:
        """Whether cam-frame points ``q`` (..., 3) [mm] lie in the rib's extent (module docs)."""
        rho = np.hypot(q[..., 0], q[..., 1])
        c = float(self.centre_distance)
        g = np.hypot(c - rho, q[..., 2])
        return ((rho < c) & (g >= float(self.tip_radius)) & (g <= float(self.root_radius))
                & (np.abs(q[..., 2]) <= 0.5 * float(self.cam_width)))


SpatialIndexer = BarrelIndexer | GloboidalIndexer


# ---------------------------------------------------------------------------------------------
# kinematics

def turret_angle(ix: SpatialIndexer, theta: Array) -> tuple[Array, Array, Array]:
    """ψ [rad] (continuous over turns, 0 on the dwell before the index starting at θ_s), ψ' and
    ψ'' (per rad of input) at input angles ``theta`` [rad]."""
    theta = np.asarray(theta, dtype=float)
    t_st, beta = ix.station_angle, float(ix.index_angle)
    rel = theta - float(ix.index_start)
    turns = np.floor(rel / TWO_PI)
    x = (rel - TWO_PI * turns) / beta
    inside = (x >= 0.0) & (x <= 1.0)
    f, f1, f2, _ = evaluate_law(ix.law, np.clip(x, 0.0, 1.0))
    return t_st * (turns + f), np.where(inside, t_st * f1 / beta, 0.0), np.where(inside, t_st * f2 / beta**2, 0.0)


def roller_alpha(ix: SpatialIndexer, roller: Array, psi: Array) -> Array:
    """α_j = π + T·(j − ½) + ψ [rad] of roller(s) ``roller`` at turret angle ``psi``."""
    return math.pi + ix.station_angle * (np.asarray(roller, dtype=float) - 0.5) + np.asarray(psi, dtype=float)


@dataclass(frozen=True)
class RollerAxis:
    """A roller's axis c(t) = a + t·d in the FIXED frame at input angles θ, with the θ-derivatives
    [mm, mm/rad, mm/rad²] (d is a unit vector): a, da, d2a, d, dd, d2d, each (..., 3); alpha [rad]
    and tau = τ(α), the unit direction of the axis points' path; omega = Ω = −ψ'·ŷ − k, the turret's
    angular velocity relative to the cam (fixed-frame components, per rad of input), and its
    cam-frame derivative domega = DΩ = −ψ''·ŷ − ψ'·x̂."""

    alpha: Array
    a: Array
    da: Array
    d2a: Array
    d: Array
    dd: Array
    d2d: Array
    tau: Array
    omega: Array
    domega: Array


def roller_axis(ix: SpatialIndexer, roller: Array, theta: Array) -> RollerAxis:
    """Roller ``roller``'s axis and its derivatives at input angles ``theta`` (broadcast)."""
    psi, d1, d2 = turret_angle(ix, theta)
    alpha = roller_alpha(ix, roller, psi)
    a, a_al, a_alal, d, d_al, d_alal = ix.roller_pose(alpha)
    p1, p2 = d1[..., None], d2[..., None]
    _, tau = _unit(alpha)
    zero, one = np.zeros_like(alpha), np.ones_like(alpha)
    d1b, d2b = np.broadcast_to(d1, alpha.shape), np.broadcast_to(d2, alpha.shape)
    omega = np.stack([zero, -d1b, -one], axis=-1)
    domega = np.stack([-d1b, -d2b, zero], axis=-1)
    return RollerAxis(alpha, a, a_al * p1, a_alal * p1**2 + a_al * p2, d, d_al * p1, d_alal * p1**2 + d_al * p2,
                      tau, omega, domega)


def _cam_d(q: Array, dq: Array) -> Array:
    """Dq = q' − k × q: a fixed-frame field's θ-derivative as the cam frame sees it (rotated back)."""
    return dq + np.stack([q[..., 1], -q[..., 0], np.zeros_like(q[..., 0])], axis=-1)


def _cam_d2(q: Array, dq: Array, d2q: Array) -> Array:
    """D²q = q'' − 2k × q' + k × (k × q)."""
    kq = np.stack([q[..., 0], q[..., 1], np.zeros_like(q[..., 0])], axis=-1)
    return d2q + 2.0 * np.stack([dq[..., 1], -dq[..., 0], np.zeros_like(dq[..., 0])], axis=-1) - kq


def to_cam(theta: Array, q: Array) -> Array:
    """Fixed-frame vectors ``q`` (..., 3) at input angles ``theta`` as cam-frame vectors: Rz(−θ)·q."""
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([c * q[..., 0] + s * q[..., 1], -s * q[..., 0] + c * q[..., 1], q[..., 2]], axis=-1)


def _dot(a: Array, b: Array) -> Array:
    return np.einsum("...i,...i->...", a, b)


@dataclass(frozen=True)
class ContactLines:
    """Contact lines of one roller side on a (θ, t) grid, shape (..., K): ``points`` and the
    roller's outward unit surface ``normals`` N (the contact normal; n for a cylinder) in the CAM
    frame [mm]; ``points_fixed``, ``normals_fixed`` in the fixed frame; ``radial`` the fixed-frame
    unit n from the roller's axis to the point and ``radius`` r(t) [mm] there; ``pressure_angle``
    [rad]; ``margin`` μ (regularity, > 0 regular); ``speed`` |m| [mm/rad]; ``cos_drive`` = N·τ (≥ 0
    on side +1, ≤ 0 on side −1 where well defined).  NaN where a conical roller has no contact."""

    side: int
    points: Array
    normals: Array
    points_fixed: Array
    normals_fixed: Array
    radial: Array
    radius: Array
    pressure_angle: Array
    margin: Array
    speed: Array
    cos_drive: Array


def contact_lines(ix: SpatialIndexer, roller: Array, theta: Array, t: Array, side: int) -> ContactLines:
    """Side ``side`` (±1)'s contact lines of roller(s) ``roller`` at input angles ``theta`` (shape
    B after broadcasting) at axis parameters ``t`` [mm], (K,) — the same K for every θ — or
    (B…, K), its own per θ (it broadcasts over θ's axes): arrays (B…, K).  The meshing, the normal
    and the margin are the module docs' (cylinder and cone alike)."""
    if side not in (1, -1):
        raise SpecError("indexer.side", f"must be +1 or −1, got {side!r}")
    theta = np.asarray(theta, dtype=float)
    ax = roller_axis(ix, roller, theta)
    th = np.broadcast_to(theta, ax.alpha.shape)
    t = np.asarray(t, dtype=float)
    k = ix.taper
    q = math.hypot(1.0, k)
    e = (Ellipsis, None, slice(None))                      # broadcast (B…, 3) over t → (B…, K, 3)
    tk = t[:, None]
    r = np.asarray(ix.radius_at(t), dtype=float)
    rk = r[..., None]
    Da, Dd = _cam_d(ax.a, ax.da), _cam_d(ax.d, ax.dd)
    D2a, D2d = _cam_d2(ax.a, ax.da, ax.d2a), _cam_d2(ax.d, ax.dd, ax.d2d)
    om, dom = ax.omega[e], ax.domega[e]
    w = Da[e] + tk * Dd[e]
    d = ax.d[e]
    dw = _dot(d, w)
    m = np.cross(d, w - k * rk * np.cross(d, om))
    speed = np.linalg.norm(m, axis=-1)
    tau = ax.tau[e]
    with np.errstate(divide="ignore", invalid="ignore"):
        sgn = np.where(_dot(m, tau) >= 0, 1.0, -1.0) * side
        mh = m / speed[..., None]
        cphi = k * dw / speed
        n = cphi[..., None] * np.cross(mh, d) + (sgn * np.sqrt(1.0 - cphi**2))[..., None] * mh
        big_n = (n - k * d) / q
        om_n = np.cross(om, n)
        n_phi = np.cross(d, n)
        v = w + rk * om_n
        f_t = _dot(big_n, Dd[e] + k * om_n)
        f_phi = _dot(n_phi, v) / q + r * _dot(big_n, np.cross(om, n_phi))
        f_th = _dot(np.cross(om, big_n), v) + _dot(big_n, D2a[e] + tk * D2d[e]
                                                 + rk * (np.cross(dom, n) + np.cross(om, om_n)))
        delta = (f_phi * _dot(np.cross(v, d + k * n), big_n) - f_th * r * q
                 - f_t * r * _dot(np.cross(v, n_phi), big_n))
        margin = delta / (q * f_phi**2)
    cos_drive = _dot(big_n, tau)
    pa = np.arccos(np.clip(np.abs(cos_drive), 0.0, 1.0))
    p = ax.a[e] + tk * d + rk * n
    thb = th[..., None]
    return ContactLines(side, to_cam(thb, p), to_cam(thb, big_n), p, big_n, n, np.broadcast_to(r, pa.shape), pa,
                        margin, speed, cos_drive)


# ---------------------------------------------------------------------------------------------
# results

@dataclass(frozen=True)
class FlankSheet:
    """One side's contact lines over the locus grid (the rib's flank of that side where
    ``in_band``): rows R of ``tau`` [rad] (roller j at θ_i is row (j − j_lo)·(S − 1) + i), columns
    K of the design's ``t``.  points, normals (the roller's outward unit normal n; the flank's
    outward normal is −n) in the cam frame (R, K, 3); pressure_angle [rad], margin, in_band (R, K)."""

    side: int
    tau: Array
    points: Array
    normals: Array
    pressure_angle: Array
    margin: Array
    in_band: Array


@dataclass(frozen=True)
class Extremum:
    """A value and where: input angle ``theta`` [rad] in θ_s + [0, 2π], ``roller`` j, ``side``
    (±1) and the axis parameter ``t`` [mm] (NaN values where nothing is engaged)."""

    value: float
    theta: float
    roller: int
    side: int
    t: float


@dataclass(frozen=True)
class SpatialDesign:
    """A spatial indexer's geometry on ``theta`` (S input angles θ_s + [0, 2π], rad).

    psi, dpsi, d2psi: the turret's motion.  t: the axis parameters (K,) [mm].  rollers: the
    roller numbers j (J = N of them, from j_lo).  sheets: the side +1 and side −1
    :class:`FlankSheet`.  engaged: (J, 2, S) — roller j's side (+1, −1) touches the rib at θ_i.
    windows: (j, side, θ_from, θ_to) [rad] runs of engagement over the turn.  max_pressure_angle
    (over every engaged contact), max_index_pressure_angle (while the turret moves): Extremum.
    driving_angle (S,) [rad]: of the engaged side −1 (driving) contact lines at θ, the one whose
    largest pressure angle along its in-band length is least — that angle (NaN where none drives);
    max_driving_angle: its largest over the index (t NaN: a whole line).  min_margin
    (regularity), min_rib_thickness [mm]: :class:`Extremum`.  locked: at every θ some engaged
    contact drives the turret forward (side −1) and some holds it back (side +1)."""

    indexer: SpatialIndexer
    theta: Array
    psi: Array
    dpsi: Array
    d2psi: Array
    t: Array
    rollers: Array
    sheets: tuple[FlankSheet, FlankSheet]
    engaged: Array
    windows: tuple[tuple[int, int, float, float], ...]
    max_pressure_angle: Extremum
    max_index_pressure_angle: Extremum
    driving_angle: Array
    max_driving_angle: Extremum
    min_margin: Extremum
    min_rib_thickness: Extremum
    locked: bool
    index_rows: int

    def sheet(self, side: int) -> FlankSheet:
        """The flank sheet of side ``side`` (±1)."""
        return self.sheets[0 if side == 1 else 1]

    def row(self, roller: int, i: Array) -> Array:
        """Sheet row(s) of roller ``roller`` at θ-sample(s) ``i``."""
        return (int(roller) - int(self.rollers[0])) * (self.theta.size - 1) + np.asarray(i)

    def summary(self) -> dict[str, Any]:
        """Plain numbers: angles in degrees (``*_deg``), lengths in mm (``*_mm``)."""
        ix = self.indexer

        def ext(e: Extremum, scale, unit: str) -> dict[str, Any]:
            return {f"value_{unit}": _plain(scale(e.value)), "at_deg": _plain(math.degrees(e.theta)),
                    "roller_index": e.roller, "side": e.side, "t_mm": _plain(e.t)}

        fields = {k: (v if isinstance(v, (int, str)) else law_name(v) if k == "law" else float(v))
                  for k, v in vars(ix).items()}
        for k in ("index_angle", "index_start", "roller_cone_angle"):
            fields[k + "_deg"] = math.degrees(fields.pop(k))
        return {
            "units": {"length": "mm", "angle": "deg"},
            "type": type(ix).__name__,
            **fields,
            "samples": int(self.theta.size),
            "lengths": int(self.t.size),
            "windows": [{"roller_index": j, "side": s, "from_deg": math.degrees(a), "to_deg": math.degrees(b)}
                        for j, s, a, b in self.windows],
            "engaged_per_angle": {"min": int(self.engaged.sum(axis=(0, 1)).min()),
                                  "max": int(self.engaged.sum(axis=(0, 1)).max())},
            "max_pressure_angle": ext(self.max_pressure_angle, math.degrees, "deg"),
            "max_index_pressure_angle": ext(self.max_index_pressure_angle, math.degrees, "deg"),
            "max_driving_pressure_angle": ext(self.max_driving_angle, math.degrees, "deg"),
            "min_regularity_margin": ext(self.min_margin, float, "1"),
            "min_rib_thickness": ext(self.min_rib_thickness, float, "mm"),
            "locked": bool(self.locked),
        }


def _plain(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


# ---------------------------------------------------------------------------------------------
# construction

def _deg(x: float) -> str:
    return f"{math.degrees(x):.6g}°"


def _theta_grid(ix: SpatialIndexer, samples: int) -> tuple[Array, int]:
    """S input angles over θ_s + [0, 2π], the index [θ_s, θ_s + β] on its own uniform piece
    (so that the law's ends are samples); the index's row count n1."""
    beta = float(ix.index_angle)
    n1 = int(np.clip(round((samples - 1) * beta / TWO_PI), 2, samples - 3))
    ts = float(ix.index_start)
    th = np.concatenate([ts + np.linspace(0.0, beta, n1 + 1), ts + np.linspace(beta, TWO_PI, samples - n1)[1:]])
    return th, n1


def _extremum(values: Array, mask: Array, take_max: bool, theta: Array, j_lo: int, t: Array, side_of) -> Extremum:
    """The largest (or smallest) of ``values`` (2, R, K) where ``mask``, and where."""
    v = np.where(mask, values, -np.inf if take_max else np.inf)
    if not mask.any():
        return Extremum(math.nan, math.nan, 0, 0, math.nan)
    flat = int(np.argmax(v) if take_max else np.argmin(v))
    s_i, r, k = np.unravel_index(flat, v.shape)
    m = theta.size - 1
    j, i = divmod(int(r), m)
    return Extremum(float(v[s_i, r, k]), float(theta[i]), j + j_lo, side_of(int(s_i)), float(t[k]))


def _runs(mask: Array, theta: Array) -> list[tuple[float, float]]:
    """(θ_from, θ_to) of the runs of True in ``mask`` over ``theta``."""
    if not mask.any():
        return []
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    starts, ends = np.nonzero(edges == 1)[0], np.nonzero(edges == -1)[0] - 1
    return [(float(theta[a]), float(theta[b])) for a, b in zip(starts, ends)]


def _rib_thickness(pts_p: Array, nrm_p: Array, ok_p: Array, pts_m: Array, ok_m: Array, per_turn: int) -> tuple[Array, Array]:
    """For each side +1 point, the distance to the nearest side −1 point in front of it (along +n)
    among the rows r + per_turn ± per_turn/4 at least (module docs); NaN where none.  Rows of
    queries in blocks, each against a k-d tree of the rows that can face it."""
    from scipy.spatial import cKDTree  # deferred: scipy.spatial, the rib thickness's nearest points

    rows, k_t = ok_p.shape
    out = np.full((rows, k_t), np.nan)
    where = np.full((rows, k_t), -1, dtype=int)
    excl = per_turn // 4
    block = max(per_turn // 2, 1)
    flat_m = pts_m.reshape(-1, 3)
    ok_flat = ok_m.reshape(-1)
    for b in range(0, rows, block):
        q_rows = np.arange(b, min(b + block, rows))
        sel = ok_p[q_rows]
        if not sel.any():
            continue
        lo, hi = q_rows[-1] + excl, min(b + 2 * per_turn - excl, rows)
        if hi <= lo:
            continue
        idx = np.arange(lo * k_t, hi * k_t)
        idx = idx[ok_flat[idx]]
        if idx.size == 0:
            continue
        tree = cKDTree(flat_m[idx])
        qi, qk = np.nonzero(sel)
        qr = q_rows[qi]
        q = pts_p[qr, qk]
        kk = min(8, idx.size)
        dist, nb = tree.query(q, k=kk)
        dist, nb = dist.reshape(q.shape[0], kk), nb.reshape(q.shape[0], kk)
        front = _dot(flat_m[idx[nb]] - q[:, None, :], nrm_p[qr, qk][:, None, :]) > 0
        dist = np.where(front, dist, np.inf)
        best = np.argmin(dist, axis=1)
        dmin = dist[np.arange(q.shape[0]), best]
        good = np.isfinite(dmin)
        out[qr[good], qk[good]] = dmin[good]
        where[qr[good], qk[good]] = idx[nb[np.arange(q.shape[0]), best]][good]
    return out, where


def _design(ix: SpatialIndexer, samples: int, lengths: int, strict: bool) -> SpatialDesign:
    s = integer("samples", samples, "an integer ≥ 16", lambda v: v >= 16)
    kt = integer("lengths", lengths, "an integer ≥ 2", lambda v: v >= 2)
    n = int(ix.stations)
    theta, n1 = _theta_grid(ix, s)
    psi, d1, d2 = turret_angle(ix, theta)
    j_lo = -((n - 1) // 2)
    rollers = np.arange(j_lo, j_lo + n)
    m_turn = s - 1
    # the locus grid: τ = θ_i + 2πj, rows without the repeated turn ends
    tau = (theta[None, :-1] + TWO_PI * rollers[:, None]).reshape(-1)
    tau = np.concatenate([tau, [theta[-1] + TWO_PI * rollers[-1]]])
    t = np.linspace(float(ix.roller_start), float(ix.roller_end), kt)
    sheets, cls = [], []
    for side in (1, -1):
        # roller 0 at input angle τ is the locus' pose τ
        cl = contact_lines(ix, 0, tau, t, side)
        band = ix.in_band(cl.points)
        cls.append(cl)
        sheets.append(FlankSheet(side, tau, cl.points, cl.normals, cl.pressure_angle, cl.margin, band))
    band2 = np.stack([sh.in_band for sh in sheets])                          # (2, R, K)
    row_any = band2.any(axis=2)                                              # (2, R)
    rows_ji = (np.arange(n)[:, None] * m_turn + np.arange(s)[None, :])       # (J, S)
    engaged = np.stack([row_any[0][rows_ji], row_any[1][rows_ji]], axis=1)  # (J, 2, S)

    def side_of(k: int) -> int:
        return 1 if k == 0 else -1

    def at(r: int) -> tuple[float, int]:
        j, i = divmod(int(r), m_turn)
        return float(theta[i]), int(j + j_lo)

    # -- well-defined contact lines where engaged
    speed = np.stack([c.speed for c in cls])
    cosd = np.stack([np.abs(c.cos_drive) for c in cls])
    bad = band2 & ~(np.isfinite(speed) & (speed > _TINY_SPEED))
    if bad.any():
        si, r, _ = np.unravel_index(int(np.argmax(bad)), bad.shape)
        th, j = at(r)
        raise SpecError("indexer.index_angle",
                        f"roller {j}'s contact line (side {side_of(si):+d}) is undefined at input angle {_deg(th)} "
                        f"(its axis slides along itself relative to the cam) — change indexer.index_angle or "
                        f"indexer.centre_distance")
    flat = band2 & (cosd < _TINY_COS)
    if flat.any():
        si, r, _ = np.unravel_index(int(np.argmax(flat)), flat.shape)
        th, j = at(r)
        raise SpecError("indexer.index_angle",
                        f"roller {j} (side {side_of(si):+d}) meets the rib at a pressure angle of 90° at input angle "
                        f"{_deg(th)} — increase indexer.index_angle or indexer.centre_distance")
    # one turn's rows (the locus repeats every N turns) for the extremes
    margin = np.stack([c.margin for c in cls])
    min_margin = _extremum(margin, band2, False, theta, j_lo, t, side_of)
    if not min_margin.value > 0:
        raise SpecError("indexer.roller_radius",
                        f"undercut: the rib's flank (side {min_margin.side:+d}, roller {min_margin.roller}, "
                        f"t = {min_margin.t:.6g} mm) is singular at input angle {_deg(min_margin.theta)} "
                        f"(regularity margin {min_margin.value:.3g}) — reduce indexer.roller_radius or increase "
                        f"indexer.index_angle")
    pa = np.stack([c.pressure_angle for c in cls])
    max_pa = _extremum(pa, band2, True, theta, j_lo, t, side_of)
    moving = np.zeros(tau.size, dtype=bool)
    moving[rows_ji[:, 1:n1]] = True                                          # rows inside the index
    max_ipa = _extremum(pa, band2 & moving[None, :, None], True, theta, j_lo, t, side_of)

    # the driving contact at each θ: of the engaged side −1 lines, the one whose worst point (over
    # its in-band t) has the smallest pressure angle
    line_pa = np.where(sheets[1].in_band, pa[1], -np.inf).max(axis=1)[rows_ji]          # (J, S)
    line_pa = np.where(engaged[:, 1, :], line_pa, np.inf)
    drive_j = np.argmin(line_pa, axis=0)
    driving = line_pa[drive_j, np.arange(s)]
    driving = np.where(np.isfinite(driving), driving, np.nan)
    idx_i = np.arange(1, n1)
    if np.isfinite(driving[idx_i]).any():
        w = int(idx_i[np.nanargmax(driving[idx_i])])
        max_drive = Extremum(float(driving[w]), float(theta[w]), int(rollers[drive_j[w]]), -1, math.nan)
    else:
        max_drive = Extremum(math.nan, math.nan, 0, 0, math.nan)

    thick, _ = _rib_thickness(sheets[0].points, sheets[0].normals, sheets[0].in_band, sheets[1].points,
                              sheets[1].in_band, m_turn)
    have = np.isfinite(thick)
    if have.any():
        r, k = np.unravel_index(int(np.nanargmin(np.where(have, thick, np.nan))), thick.shape)
        th, j = at(r)
        rib = Extremum(float(thick[r, k]), th, j, 1, float(t[k]))
    else:
        rib = Extremum(math.nan, math.nan, 0, 0, math.nan)
    if strict and not (have.any() and rib.value > 0):
        raise SpecError("indexer.roller_radius",
                        "no rib is left between neighbouring rollers" + (
                            f" at input angle {_deg(rib.theta)}" if have.any() else "") +
                        " — reduce indexer.roller_radius or increase indexer.stations' spacing (indexer.pitch_radius)")

    fwd = engaged[:, 1, :].any(axis=0)
    back = engaged[:, 0, :].any(axis=0)
    locked = bool(fwd.all() and back.all())
    if strict and not locked:
        i0 = int(np.argmax(~(fwd & back)))
        which = "forward" if not fwd[i0] else "backward"
        raise SpecError("indexer.cam_width",
                        f"the turret is not positively driven: no roller touches the rib {which} at input angle "
                        f"{_deg(theta[i0])} — increase indexer.cam_width or the rib's radial extent")
    windows = []
    for ji, j in enumerate(rollers):
        for si, side in enumerate((1, -1)):
            for a, b in _runs(engaged[ji, si], theta):
                windows.append((int(j), side, a, b))
    return SpatialDesign(ix, theta, psi, d1, d2, t, rollers, (sheets[0], sheets[1]), engaged, tuple(windows),
                         max_pa, max_ipa, driving, max_drive, min_margin, rib, locked, n1)


def design_barrel(ix: BarrelIndexer, samples: int = 721, lengths: int = 9, strict: bool = True) -> SpatialDesign:
    """The barrel indexer's flanks, engagement, pressure angles, regularity and rib thickness on
    ``samples`` input angles θ_s + [0, 2π] and ``lengths`` points of each roller's axis.

    Raises SpecError (naming the field to change, with the input angle) for an undefined contact,
    a 90° pressure angle or an undercut on an engaged contact, and with ``strict`` for no rib or a
    turret not positively driven."""
    if not isinstance(ix, BarrelIndexer):
        raise SpecError("indexer", f"must be a BarrelIndexer, got {type(ix).__name__}")
    return _design(ix, samples, lengths, strict)


def design_globoidal(ix: GloboidalIndexer, samples: int = 721, lengths: int = 9, strict: bool = True) -> SpatialDesign:
    """The globoidal indexer's flanks, engagement, pressure angles, regularity and rib thickness
    (as :func:`design_barrel`)."""
    if not isinstance(ix, GloboidalIndexer):
        raise SpecError("indexer", f"must be a GloboidalIndexer, got {type(ix).__name__}")
    return _design(ix, samples, lengths, strict)


# ---------------------------------------------------------------------------------------------
# the turret angle from the flank surfaces alone

@dataclass(frozen=True)
class RecoveredAngle:
    """The turret angle found from the flank surfaces: ``psi`` [rad] at ``theta`` [rad] (the
    median over the engaged rollers' sides and the t columns), ``spread`` [rad] (largest minus
    smallest of those estimates) and ``count`` (how many)."""

    theta: Array
    psi: Array
    spread: Array
    count: Array


def _lagrange(u: Array) -> tuple[Array, Array, Array]:
    """Lagrange basis on the nodes 0 … 6 at ``u`` and its first two derivatives, (..., 7)."""
    nodes = np.arange(_STENCIL, dtype=float)
    coef = np.linalg.inv(np.vander(nodes, increasing=True))        # column m: basis m's coefficients
    p = np.arange(_STENCIL)
    uu = u[..., None]
    with np.errstate(divide="ignore", invalid="ignore"):
        pw = uu ** p
        pw1 = np.where(p > 0, p * uu ** np.maximum(p - 1, 0), 0.0)
        pw2 = np.where(p > 1, p * (p - 1) * uu ** np.maximum(p - 2, 0), 0.0)
    return pw @ coef, pw1 @ coef, pw2 @ coef


def output_angle_from_surface(design: SpatialDesign, theta: Array) -> RecoveredAngle:
    """The turret angle ψ [rad] at input angles ``theta`` [rad] found from the sampled flank
    surfaces alone (their points, their normals and the roller's shape; not the law): the ψ at
    which the roller — the cylinder r_r, or the cone r(t) — is tangent to the flank.

    Every roller side engaged at θ (rows τ = θ + 2πj of its sheet in the band) and every t column
    gives an estimate: the flank's column near τ is the degree-6 Lagrange curve through 7 sampled
    rows inside one piece (index or dwell: the law's ends are rows, so no stencil straddles a
    kink).  A first ψ puts the roller's axis through the point pushed back by r(t) along the sampled
    normal; then Newton on D(ψ) = min over the curve of (ρ − r(s)) = 0, ρ and s the point's
    distance from the roller's axis and its axial coordinate (ρ − r(s) = ρ − r_0 − k·s, r_0 = r(0):
    q times the distance to the cone's side), with dD/dψ from the envelope theorem.  θ outside θ_s + [0, 2π] uses the cam's periodicity."""
    ix = design.indexer
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    ts, t_st, k = float(ix.index_start), ix.station_angle, ix.taper
    r0 = float(ix.radius_at(0.0))
    r_col = ix.radius_at(design.t)                                              # (K,)
    turns = np.floor((theta - ts) / TWO_PI)
    th = theta - TWO_PI * turns
    m_turn = design.theta.size - 1
    n1 = design.index_rows
    rollers = design.rollers
    q_n, j_n, k_n = theta.size, rollers.size, design.t.size
    # the rows' parameter within a turn, by piece: [0, n1] the index, [n1, m_turn] the dwell
    base = design.theta
    i_in = np.searchsorted(base, th, side="right") - 1
    i_in = np.clip(i_in, 0, m_turn - 1)
    in_index = i_in < n1
    p_lo = np.where(in_index, 0, n1)
    p_hi = np.where(in_index, n1, m_turn)
    start = np.clip(i_in - _STENCIL // 2, p_lo, p_hi - (_STENCIL - 1))          # (Q,) first stencil row in-turn
    h = (base[p_hi] - base[p_lo]) / (p_hi - p_lo)
    u0 = (th - base[start]) / h                                                 # target in stencil coordinates
    ests = []
    for sheet in design.sheets:
        rows0 = (rollers[None, :] - rollers[0]) * m_turn + start[:, None]       # (Q, J)
        ok_all = sheet.in_band[rows0[..., None] + np.arange(_STENCIL)].all(axis=2)   # (Q, J, K)
        qi, ji = np.nonzero(ok_all.any(axis=2))                                  # the engaged pairs only
        ok = ok_all[qi, ji]                                                      # (P, K)
        rows = rows0[qi, ji][:, None] + np.arange(_STENCIL)                      # (P, 7)
        pts = sheet.points[rows]                                                 # (P, 7, K, 3)
        nrm = sheet.normals[rows]
        thq = np.broadcast_to(th[qi][:, None], ok.shape)
        jq = np.broadcast_to(rollers[ji][:, None].astype(float), ok.shape)
        uq = np.broadcast_to(u0[qi][:, None], ok.shape)
        # -- first ψ: the axis through the sampled point pushed back by r_r along the normal
        lag, _, _ = _lagrange(uq)
        p_at = np.einsum("pkm,pmkc->pkc", lag, pts)
        n_at = np.einsum("pkm,pmkc->pkc", lag, nrm)
        axis_pt = p_at - r_col[:, None] * n_at / np.linalg.norm(n_at, axis=-1, keepdims=True)
        c, s = np.cos(thq), np.sin(thq)
        fx = c * axis_pt[..., 0] - s * axis_pt[..., 1]                           # back to the fixed frame
        alpha = np.arctan2(axis_pt[..., 2], fx - float(ix.centre_distance))
        guess = t_st * np.clip((th[qi] - ts) / float(ix.index_angle), 0.0, 1.0)
        psi = alpha - roller_alpha(ix, jq, 0.0)
        psi = psi + TWO_PI * np.round((guess[:, None] - psi) / TWO_PI)
        # -- tangency: Newton on D(ψ) = min_u ρ(u) − r(s(u))
        u = uq.copy()
        for _ in range(4):
            al = roller_alpha(ix, jq, psi)
            a, a_al, _, d, d_al, _ = ix.roller_pose(al)
            a, a_al, d, d_al = (to_cam(thq, v) for v in (a, a_al, d, d_al))
            for _ in range(6):
                lag, lag1, lag2 = _lagrange(u)
                g = np.einsum("pkm,pmkc->pkc", lag, pts)
                g1 = np.einsum("pkm,pmkc->pkc", lag1, pts)
                g2 = np.einsum("pkm,pmkc->pkc", lag2, pts)
                q = g - a
                qd, g1d = _dot(q, d), _dot(g1, d)
                perp = q - qd[..., None] * d
                rho = np.linalg.norm(perp, axis=-1)
                with np.errstate(divide="ignore", invalid="ignore"):
                    # h = ρ − k·s; h' = perp·Γ'/ρ − k·Γ'·d, h'' = ((|Γ'|² − (Γ'·d)²) + perp·Γ'')/ρ − (perp·Γ')²/ρ³ − k·Γ''·d
                    pg1 = _dot(perp, g1)
                    e1 = pg1 / rho - k * g1d
                    e2 = (_dot(g1, g1) - g1d**2 + _dot(perp, g2)) / rho - pg1**2 / rho**3 - k * _dot(g2, d)
                    step = np.where(e2 > 0, e1 / e2, 0.0)
                u = np.clip(u - np.nan_to_num(step), 0.0, _STENCIL - 1.0)
            lag, _, _ = _lagrange(u)
            q = np.einsum("pkm,pmkc->pkc", lag, pts) - a
            sa = _dot(q, d)
            perp = q - sa[..., None] * d
            dist = np.linalg.norm(perp, axis=-1)
            with np.errstate(divide="ignore", invalid="ignore"):
                nh = perp / dist[..., None]
                slope = -_dot(nh, a_al + sa[..., None] * d_al) - k * (_dot(q, d_al) - _dot(a_al, d))
                step = np.where(np.abs(slope) > 0, (dist - r0 - k * sa) / slope, 0.0)
            psi = psi - np.nan_to_num(step)
        full = np.full((q_n, j_n, k_n), np.nan)
        full[qi, ji] = np.where(ok, psi, np.nan)
        ests.append(full.reshape(q_n, j_n * k_n))
    est = np.concatenate(ests, axis=1)
    count = np.isfinite(est).sum(axis=1)
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)          # all-NaN rows: nothing engaged
        med = np.nanmedian(est, axis=1)
        spread = np.nanmax(est, axis=1) - np.nanmin(est, axis=1)
    return RecoveredAngle(theta, med + t_st * turns, spread, count)

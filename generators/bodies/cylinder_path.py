"""The roller centre's developed path on a cylindrical cam, and the developed centre line C_ρ it gives.

Developed pitch plane (fixed frame): at the pitch radius R_p the roller centre's position is
(u, Z) — u the arc length along the circumference from the +Y generator (fixed polar angle π/2),
positive in the direction the cam's surface moves under the roller (fixed polar angle
π/2 + δu/R_p, δ = +1 for a ccw cam, −1 for cw), Z the axial position (0 ≤ Z ≤ cam.length).

**Translating follower** (``TranslatingPath``): u = 0, Z = z₀ + s(θ), z₀ = (L_cyl − s_max)/2.

**Oscillating follower** (``OscillatingPath``, the definition of issue 14 part 3): the arm swings about
a pivot whose axis is radial (perpendicular to the cam axis, on the +Y side of the fixed frame); its
motion is taken in the developed pitch plane — the roller centre runs on a circular arc of radius
L = ``follower.arm_length`` about the developed pivot, wrapped onto the pitch cylinder, and the roller's
axis stays radial.  The pivot sits at (u, Z) = (−d, Z_p), d = ``follower.pivot_distance`` ≥ 0 its
distance along the circumference from the +Y generator, upstream of the roller (the cam surface
drags the roller away from the pivot: a trailing arm).  With the arm angle β measured from +u
towards +Z,

    P(θ) = (−d + L cos β, Z_p + L sin β),   β = β_m + (s(θ) − s_max/2)·π/180   (s in degrees),

β_m = arccos(d/L) ∈ [0, π/2): at mid-lift the roller centre is on the +Y generator (u = 0);
d = L puts the arm along the circumference at mid-lift (the symmetric swing).  A positive lift turns
the arm towards +Z.  Z_p = L_cyl/2 − L sin β_m cos(h/2) (h = s_max in rad) centres the roller's axial
travel Z ∈ [Z_p + L sin β_min, Z_p + L sin β_max], of length 2d·sin(h/2), on the cylinder.
The rules: d ≤ L (else the arm cannot reach the generator) and β_max = β_m + h/2 < 90° (else the
arm turns past the perpendicular to the cam axis and the axial motion reverses).

**Cam frame, developed at radius ρ**: with φ(θ) = π/2 − δθ and k = ρ/R_p,

    C_ρ(θ) = (x, z) = (ρ φ(θ) + δ k u(θ), Z(θ)),
    C_ρ′ = (−δ q, Z′),  q = k (R_p − u′),     C_ρ″ = (δ k u″, Z″),

the walls are C_ρ's offsets by ±w/2 along n = (δ Z′, q)/√(q² + Z′²) (+: towards +z).  The
translating follower is the special case u = 0, Z = z₀ + s.  All derivatives are exact, from the
motion program's s, s′, s″ (per radian of cam angle).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

DEG = math.pi / 180.0


@dataclass(frozen=True)
class PathKinematics:
    """The roller centre in the developed pitch plane (fixed frame) and its θ-derivatives
    (lengths in spec units, per radian of cam angle)."""

    u: np.ndarray
    du: np.ndarray
    d2u: np.ndarray
    z: np.ndarray
    dz: np.ndarray
    d2z: np.ndarray
    #: unit direction (u, Z) in which the roller centre moves with the lift (the follower's own
    #: motion: along the cam axis, or perpendicular to the arm)
    tu: np.ndarray
    tz: np.ndarray


class RollerPath(Protocol):
    """A follower's developed roller-centre path (see the module docstring)."""

    motion: str
    #: the roller swings on an arm (its lift an angle)
    pivoted: bool

    def evaluate(self, k) -> PathKinematics:
        """The path at the motion program's kinematics ``k`` (s, s′, s″ arrays)."""
        ...

    def z_range(self) -> tuple[float, float]:
        """Smallest and largest axial position Z of the roller centre."""
        ...

    def describe(self) -> dict:
        """Report numbers of the path."""
        ...


@dataclass(frozen=True)
class TranslatingPath:
    """u = 0, Z = z₀ + s (s in length units)."""

    z0: float
    max_lift: float
    motion = "translating"
    pivoted = False

    def evaluate(self, k) -> PathKinematics:
        s = np.asarray(k.s, dtype=float)
        zero = np.zeros_like(s)
        return PathKinematics(zero, zero, zero, self.z0 + s, np.asarray(k.ds, dtype=float),
                              np.asarray(k.d2s, dtype=float), zero, np.ones_like(s))

    def z_range(self) -> tuple[float, float]:
        return self.z0, self.z0 + self.max_lift

    def describe(self) -> dict:
        return {"motion": "translating", "z0": self.z0}


@dataclass(frozen=True)
class OscillatingPath:
    """The arm about a radial pivot at developed (−d, Z_p); β = β_m + (s − s_max/2)·π/180 [rad]."""

    pivot_distance: float       # d
    arm_length: float           # L
    max_lift: float             # s_max [deg]
    pivot_z: float              # Z_p
    motion = "oscillating"
    pivoted = True

    @staticmethod
    def of(pivot_distance: float, arm_length: float, max_lift_deg: float, length: float) -> "OscillatingPath":
        """The path of an arm (d, L) swinging s_max degrees on a cylinder of ``length``, centred."""
        bm = mid_arm_angle(pivot_distance, arm_length)
        zp = length / 2 - arm_length * math.sin(bm) * math.cos(DEG * max_lift_deg / 2)
        return OscillatingPath(pivot_distance, arm_length, max_lift_deg, zp)

    @property
    def beta_mid(self) -> float:
        """β_m = arccos(d/L) [rad]: the arm angle at mid-lift."""
        return mid_arm_angle(self.pivot_distance, self.arm_length)

    def beta(self, s: np.ndarray) -> np.ndarray:
        """Arm angle β [rad] from +u towards +Z at lift s [deg]."""
        return self.beta_mid + DEG * (np.asarray(s, dtype=float) - self.max_lift / 2)

    def evaluate(self, k) -> PathKinematics:
        b = self.beta(k.s)
        b1 = DEG * np.asarray(k.ds, dtype=float)
        b2 = DEG * np.asarray(k.d2s, dtype=float)
        c, s = np.cos(b), np.sin(b)
        L = self.arm_length
        return PathKinematics(-self.pivot_distance + L * c, -L * s * b1, -L * (c * b1 * b1 + s * b2),
                              self.pivot_z + L * s, L * c * b1, L * (c * b2 - s * b1 * b1), -s, c)

    def z_range(self) -> tuple[float, float]:
        h = DEG * self.max_lift
        L, bm = self.arm_length, self.beta_mid
        return self.pivot_z + L * math.sin(bm - h / 2), self.pivot_z + L * math.sin(bm + h / 2)

    def describe(self) -> dict:
        h = DEG * self.max_lift
        return {"motion": "oscillating", "pivot": [-self.pivot_distance, self.pivot_z],
                "pivot_distance": self.pivot_distance, "arm_length": self.arm_length,
                "arm_angle_at_mid_lift_deg": math.degrees(self.beta_mid),
                "arm_angle_range_deg": [math.degrees(self.beta_mid - h / 2), math.degrees(self.beta_mid + h / 2)],
                "axial_travel": 2 * self.pivot_distance * math.sin(h / 2),
                "frame": "developed pitch plane: u along the circumference from the +Y generator in the direction "
                         "the surface moves, Z axial; the pivot at (−d, Z_p), its axis radial"}


def mid_arm_angle(pivot_distance: float, arm_length: float) -> float:
    """β_m = arccos(d/L) [rad] (NaN when d > L: the arm cannot reach the +Y generator)."""
    c = pivot_distance / arm_length
    return math.acos(c) if 0.0 <= c <= 1.0 else float("nan")


@dataclass(frozen=True)
class CentreLine:
    """C_ρ(θ) developed at radius ρ in the cam frame (x = ρ·ψ, z) with C′ and C″ (per radian of θ)."""

    x: np.ndarray
    z: np.ndarray
    dx: np.ndarray
    dz: np.ndarray
    d2x: np.ndarray
    d2z: np.ndarray

    @property
    def speed(self) -> np.ndarray:
        """|C′|."""
        return np.hypot(self.dx, self.dz)

    def normal(self, sense: int) -> tuple[np.ndarray, np.ndarray]:
        """Unit normal towards +z: (δ z′, −δ x′)/|C′|."""
        n = self.speed
        return sense * self.dz / n, -sense * self.dx / n

    def offset(self, sense: int, d) -> tuple[np.ndarray, np.ndarray]:
        """(x, z) of the offset by d along :meth:`normal`."""
        nx, nz = self.normal(sense)
        return self.x + d * nx, self.z + d * nz

    def curvature(self) -> np.ndarray:
        """Unsigned curvature |x′z″ − z′x″|/|C′|³."""
        return np.abs(self.dx * self.d2z - self.dz * self.d2x) / self.speed ** 3


def centre_line(pitch_radius: float, sense: int, phi: np.ndarray, pk: PathKinematics, rho) -> CentreLine:
    """C_ρ of the module docstring: ``phi`` = φ(θ), ``pk`` the path at the same θ, ``rho`` broadcast
    against them (e.g. θ along axis 0 with shapes (n, 1), ρ of shape (m,))."""
    k = np.asarray(rho, dtype=float) / pitch_radius
    return CentreLine(rho * phi + sense * k * pk.u, pk.z + 0 * k, -sense * k * (pitch_radius - pk.du), pk.dz + 0 * k,
                      sense * k * pk.d2u, pk.d2z + 0 * k)


def expand(pk: PathKinematics) -> PathKinematics:
    """Every array given a trailing axis (θ along axis 0, to broadcast against radii)."""
    return PathKinematics(*(np.asarray(getattr(pk, f))[..., None] for f in PathKinematics.__dataclass_fields__))


def pressure_angle(pitch_radius: float, pk: PathKinematics, rho) -> np.ndarray:
    """Signed pressure angle [rad] at radius ρ: between the groove's normal (at ρ) and the direction the
    roller's section at ρ moves with the follower (developed at ρ: (k·t_u, t_Z), k = ρ/R_p).
    Translating: atan(s′/ρ); oscillating at R_p: atan((L β′ + R_p sin β)/(R_p cos β))."""
    k = np.asarray(rho, dtype=float) / pitch_radius
    nu, nz = pk.dz, k * (pitch_radius - pk.du)          # the normal in fixed developed components (unnormalised)
    tu, tz = k * pk.tu, pk.tz
    return np.arctan2(nu * tz - nz * tu, nu * tu + nz * tz)

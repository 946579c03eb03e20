"""Oscillating knife-edge and roller followers: the follower point turns about a pivot on an arm.

Fixed frame (CAM_SPEC.md "Follower motion and kinds"): the pivot D sits at (d, 0), the arm has
length L, and at arm angle ψ the follower point (knife tip or roller centre) is

    A(ψ) = D + L·e^{iψ},   ψ = ψ₀ − s(θ)   (s the arm rotation, degrees in the spec),

with ψ₀ ∈ (0, π) the arm angle at zero lift, where A lies on the prime circle |A| = R_b
(cos ψ₀ = (R_b² − d² − L²)/(2dL); y > 0): a positive lift moves A away from the cam axis.
In the cam frame P(θ) = Rot(−δθ)·A(s(θ)).  The follower point moves perpendicular to the
arm, w = −i·e^{iψ}; the pressure angle is between the pitch-curve normal and w.

The built curve touches the follower where it meets the circle of radius L about the pivot
(the paper's Eq. 13 generalised): g = (|q − D|² − L²)/(2L) = 0, and the lift is ψ₀ − arg(q − D).

Load: the arm's moment of inertia I about the pivot, a preload torque T_L and a spring torque
rate k_t hold the arm on the cam; the torque the cam must supply is T = T_L + k_t·s + I·s″ω²
(s in rad) and the normal contact force is T over its lever L·cos φ about the pivot.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import SpecError, fmt_apart
from ..kinds import body_of, register_follower
from ..motion.program import Kinematics
from ..spec.model import CamSpec
from ..studies.plan import Plan
from .base import Follower, FollowerSketch, LoadSpec, ToolMount, refuse_lift_beyond
from .load import MASS_FORCE_FACTOR, hertz_stress

DEG = math.pi / 180.0


def zero_lift_arm_angle(prime_radius: float, pivot_distance: float, arm_length: float) -> float:
    """ψ₀ [rad] in (0, π): |D + L e^{iψ₀}| = R_b (NaN when the arm cannot reach the circle)."""
    d, L, r = pivot_distance, arm_length, prime_radius
    c = (r * r - d * d - L * L) / (2 * d * L)
    return math.acos(c) if -1.0 < c < 1.0 else float("nan")


@register_follower
@dataclass(frozen=True)
class OscillatingFollower(Follower):
    """An oscillating knife edge or roller (lengths in spec units; ψ₀ in rad)."""

    pivot_distance: float
    arm_length: float
    base_radius: float       # R_b: the prime circle (roller centre / knife tip at zero lift)
    sense: int
    roller_radius: float
    load: LoadSpec = field(default=LoadSpec())
    kinds = (("oscillating", "knife"), ("oscillating", "roller"))
    pivoted = True
    motion = "oscillating"
    lift_scale = DEG
    lift_unit = "angle"
    pressure_angle_text = "between the pitch-curve normal and the roller centre's velocity, perpendicular to the arm"
    curvature_text = "from the exact derivatives of the arm's path"

    @classmethod
    def validate(cls, spec: CamSpec) -> None:
        """On a plane cam the arm must reach the prime circle and must not turn onto the line
        through the pivot and the cam axis within the lift (a body that is not plane rules its arm
        itself)."""
        if not body_of(spec).plane:
            return
        fol, rb = spec.follower, spec.cam.base_radius
        d, L = fol.pivot_distance, fol.arm_length
        if not abs(d - L) < rb < d + L:
            raise SpecError("follower.arm_length",
                            f"the arm cannot reach the prime circle: needs |pivot_distance − arm_length| < "
                            f"cam.base_radius < pivot_distance + arm_length (|d − L| = {fmt_apart(abs(d - L), rb)}, "
                            f"d + L = {fmt_apart(d + L, rb)}, R_b = {fmt_apart(rb, abs(d - L) if rb <= abs(d - L) else d + L)})")
        refuse_lift_beyond(spec, cls.from_spec(spec).lift_extent(), "arm")

    @classmethod
    def remedy_plans(cls, spec: CamSpec, check: str) -> list[Plan]:
        """The pivot distance and the base radius, each short of where the arm stops reaching the
        prime circle."""
        fol = spec.follower
        d, arm, rb = fol.pivot_distance, fol.arm_length, spec.cam.base_radius
        return [Plan("follower.pivot_distance", "nearest", bounds=(0.0, arm + rb)),
                Plan("cam.base_radius", "nearest", bounds=(abs(d - arm), d + arm))]

    @classmethod
    def from_spec(cls, spec: CamSpec) -> "OscillatingFollower":
        f = spec.follower
        return cls(f.pivot_distance, f.arm_length, spec.cam.base_radius, 1 if spec.cam.direction == "ccw" else -1,
                   spec.roller_radius,
                   LoadSpec(f.preload_torque, f.spring_torque_rate, f.arm_inertia, MASS_FORCE_FACTOR[spec.units]))

    @property
    def prime_radius(self) -> float:  # type: ignore[override]
        return self.base_radius

    @property
    def load_lever(self) -> float:  # type: ignore[override]
        return self.arm_length

    @property
    def psi0(self) -> float:
        """Arm angle at zero lift [rad]."""
        return zero_lift_arm_angle(self.base_radius, self.pivot_distance, self.arm_length)

    @property
    def pivot(self) -> complex:
        return complex(self.pivot_distance, 0.0)

    @property
    def contact(self) -> str:  # type: ignore[override]
        return "roller" if self.roller_radius > 0 else "knife"

    @property
    def contact_words(self) -> str:  # type: ignore[override]
        return "roller" if self.roller_radius > 0 else "knife-edge"

    @property
    def has_contact_stress(self) -> bool:  # type: ignore[override]
        return self.roller_radius > 0

    @property
    def profile_offset(self) -> float:  # type: ignore[override]
        return self.roller_radius

    def tool_mount(self) -> ToolMount:
        """The follower point on its arm: about the pivot (d, 0) at the arm length L, the arm at ψ₀ at
        zero lift and at ψ₀ − s (ratio −1)."""
        return ToolMount((float(self.pivot_distance), 0.0), float(self.psi0), float(self.arm_length), -1.0)

    def arm_angle(self, s: np.ndarray) -> np.ndarray:
        """ψ [rad] at lift s [deg]."""
        return self.psi0 - DEG * np.asarray(s, dtype=float)

    def fixed(self, k: Kinematics, nder: int = 0) -> list[np.ndarray]:
        e = np.exp(1j * self.arm_angle(k.s))
        L = self.arm_length
        out = [self.pivot + L * e]
        if nder >= 1:
            a_s = -1j * L * e                         # dA/ds (s in rad)
            out.append(a_s * DEG * np.asarray(k.ds, dtype=float))
        if nder >= 2:
            v, a = DEG * np.asarray(k.ds, dtype=float), DEG * np.asarray(k.d2s, dtype=float)
            out.append(-L * e * v * v + a_s * a)      # A_ss s′² + A_s s″
        return out

    def velocity_direction_at(self, q: np.ndarray) -> np.ndarray:
        r = q - self.pivot
        return -1j * r / np.abs(r)

    def contact_residual(self, q, dq, d2q):
        r = q - self.pivot
        L = self.arm_length
        return ((r.real**2 + r.imag**2 - L * L) / (2 * L), (np.conj(r) * dq).real / L,
                (np.conj(r) * (1j * self.sense) * q).real / L)

    def lift_at(self, q, dq):
        psi = np.angle(q - self.pivot)
        return (np.mod(self.psi0 - psi + np.pi, 2 * np.pi) - np.pi) / DEG

    def cam_angle_of(self, p, dp):
        r = np.abs(p)
        d, L = self.pivot_distance, self.arm_length
        alpha = np.arccos(np.clip((r * r + d * d - L * L) / (2 * r * d), -1.0, 1.0))
        return self.sense * (alpha - np.angle(p))

    def torque(self, k: Kinematics, omega: float) -> np.ndarray:
        """T = T_L + k_t·s + I·s″ω² [torque unit] (s, s″ in rad)."""
        ld = self.load
        return ld.preload + ld.rate * DEG * k.s + ld.inertia * ld.mass_force * DEG * k.d2s * omega**2

    def contact_force(self, k: Kinematics, omega: float, phi: np.ndarray | None = None) -> np.ndarray:
        phi = self.pressure_angle(k) if phi is None else phi
        return self.torque(k, omega) / (self.arm_length * np.cos(phi))

    def contact_stress(self, force, k, length, moduli, rho=None):
        if self.roller_radius <= 0:
            return super().contact_stress(force, k, length, moduli)
        rho = self.radius_of_curvature(k) if rho is None else rho
        return hertz_stress(force, self.roller_radius, rho - self.roller_radius, length, *moduli)

    def describe(self) -> dict[str, Any]:
        return {**super().describe(), "pivot_distance": self.pivot_distance, "arm_length": self.arm_length,
                "arm_angle_at_zero_lift_deg": math.degrees(self.psi0)}

    def label(self) -> str:
        what = f"roller r = {self.roller_radius:g}" if self.roller_radius > 0 else "knife edge"
        return f"oscillating {what}, pivot d = {self.pivot_distance:g}, arm L = {self.arm_length:g}"

    def sketch(self, theta, k, size, face_width=None):
        p = complex(self.points(np.array([theta]), k)[0])
        pivot = self._to_cam(theta, self.pivot)
        r = self.roller_radius
        return FollowerSketch(p, ((p, r),) if r > 0 else (), ((pivot, p, "arm"),), pivot)

    def lift_extent(self) -> float:
        return math.degrees(self.psi0)

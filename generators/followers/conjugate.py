"""The second roller of a conjugate follower: a point fixed to the first follower's moving body,
behind the same interface as every follower (:class:`cam_workbench.generators.followers.base.Follower`).

A conjugate (dual) cam pair drives one follower through two rollers, each on its own cam: the
first cam pushes the follower one way, the second the other way, so no spring is needed.  The
second roller's centre is rigidly attached to the follower, so in the fixed frame it is a
complex-affine image of the first follower point F₁ (the same map at every lift):

    F₂ = a·F₁ + b

* **translating yoke** (:class:`YokeRoller`): a = 1, b = −i·D — the second roller on the same
  line of motion x = e, ``conjugate.roller_distance`` D below the first, on the other side of the
  cam axis (F₂ = (e, s₀ + s − D), below the axis for every lift);
* **oscillating arm pair** (:class:`ArmPairRoller`): a = (L₂/L₁)·e^{iγ}, b = D_p(1 − a) — the
  second arm, ``conjugate.arm_length`` L₂ long, at the fixed angle γ = ``conjugate.arm_angle``
  from the first about the same pivot D_p: A₂ = D_p + L₂·e^{i(ψ₀ + γ − s)}, on the other side of
  the line through the pivot and the cam axis.

As the lift s grows the first roller moves away from the cam axis and the second towards it, so
each cam drives the follower in its own direction.  Everything else follows from the map:
F₂ and its θ-derivatives (a·F₁_θ, a·F₁_θθ), the second cam's pitch curve C₂(θ) = Rot(−δθ)·F₂(θ),
its pressure angle against the direction the second roller's centre moves (the body's motion:
+Y for the yoke, perpendicular to the arm about the pivot — the first follower's
:meth:`velocity_direction_at` at that point), its radius of curvature.  The built second
curve drives the follower back through the first follower's contact residual at F₁ = (q − b)/a
(Eq. 13 generalised), and its lift is the first follower's lift there: both rollers' lifts are
in the same units, and their difference is the distance error between the rollers
(:mod:`cam_workbench.generators.bodies.conjugate`).

Loads: the generalised force the follower needs, Q (the force along the line of motion for a
translating follower, the torque about the pivot for an arm), is taken by the first cam where
Q > 0 and by the second where Q < 0.  By virtual work each contact force is Q over the rate at
which its roller centre moves along the contact normal: F₁ = Q/(|∂F₁/∂s|·cos φ₁) and
F₂ = −Q/(|a|·|∂F₁/∂s|·cos φ₂) = −F₁·cos φ₁/(|a|·cos φ₂).  A negative contact force of a cam means
the other cam drives there.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..kinds import follower_of
from ..motion.program import Kinematics
from .base import Follower, FollowerSketch, ToolMount
from .load import hertz_stress

DEG = math.pi / 180.0


@dataclass(frozen=True)
class SecondRoller(Follower):
    """The second roller: F₂ = a·F₁ + b in the fixed frame (see the module docstring).

    Attributes:
        first: the first follower (a translating or oscillating roller).
        a, b: the affine map of the fixed frame that carries the first roller's centre to the
            second's (the same at every lift: a rigid attachment, scaled along an arm).
        roller_radius: the second roller's radius.
    """

    first: Follower
    a: complex
    b: complex
    roller_radius: float

    # ---- what the second roller shares with the first ---------------------------------------
    @property
    def motion(self) -> str:  # type: ignore[override]
        return self.first.motion

    @property
    def sense(self) -> int:  # type: ignore[override]
        return self.first.sense

    @property
    def lift_scale(self) -> float:  # type: ignore[override]
        return self.first.lift_scale

    @property
    def lift_unit(self) -> str:  # type: ignore[override]
        return self.first.lift_unit

    @property
    def load(self):  # type: ignore[override]
        return self.first.load

    contact = "roller"
    contact_words = "roller"
    has_contact_stress = True
    design_curve = "pitch"

    @property
    def pivoted(self) -> bool:  # type: ignore[override]
        return self.first.pivoted

    @property
    def profile_offset(self) -> float:  # type: ignore[override]
        return self.roller_radius

    @property
    def prime_radius(self) -> float:  # type: ignore[override]
        """Distance of the second roller's centre from the cam axis at zero lift."""
        return float(abs(self.map(self.first.fixed(_zero_lift(), 0)[0])[0]))

    # ---- the map ---------------------------------------------------------------------------
    def map(self, f1: np.ndarray) -> np.ndarray:
        """F₂ = a·F₁ + b (fixed frame)."""
        return self.a * np.asarray(f1) + self.b

    def unmap(self, q: np.ndarray) -> np.ndarray:
        """F₁ = (q − b)/a: the first follower point whose second roller is at q."""
        return (np.asarray(q) - self.b) / self.a

    def fixed(self, k: Kinematics, nder: int = 0) -> list[np.ndarray]:
        f = self.first.fixed(k, nder)
        return [self.map(f[0])] + [self.a * d for d in f[1:]]

    def tool_mount(self) -> ToolMount:
        """The second roller's centre: the first follower's mount carried by the map F₂ = a·F₁ + b (its
        origin mapped, its direction turned by arg a, its radius scaled by |a|; the yoke's a = 1, the arm
        pair's pivot a fixed point of the map)."""
        m = self.first.tool_mount()
        o = self.a * complex(*m.origin) + self.b
        return ToolMount((float(o.real), float(o.imag)), float(m.direction + np.angle(self.a)),
                         float(abs(self.a) * m.radius), m.ratio)

    def velocity_direction_at(self, q: np.ndarray) -> np.ndarray:
        # every point of the follower's body moves as the body does: along +Y (yoke), about the pivot (arm)
        return self.first.velocity_direction_at(q)

    # ---- the built curve drives the follower -----------------------------------------------
    def contact_residual(self, q, dq, d2q):
        # g₂(q) = g₁((q − b)/a); the roller kinds' residuals read q alone, so their ξ-derivative is the
        # directional derivative ∇g₁·q′: the same call along ∂q₁/∂θ = iδq/a gives ∂g₂/∂θ
        q1 = self.unmap(q)
        g, g_xi, _ = self.first.contact_residual(q1, dq / self.a, None)
        _, g_th, _ = self.first.contact_residual(q1, 1j * self.sense * q / self.a, None)
        return g, g_xi, g_th

    def lift_at(self, q, dq):
        return self.first.lift_at(self.unmap(q), dq / self.a)

    # ---- loads -----------------------------------------------------------------------------
    def contact_force(self, k: Kinematics, omega: float, phi: np.ndarray | None = None) -> np.ndarray:
        """F₂ = −F₁·cos φ₁/(|a|·cos φ₂): positive where the second cam drives (the first cam's
        contact force negative)."""
        phi2 = self.pressure_angle(k) if phi is None else phi
        phi1 = self.first.pressure_angle(k)
        f1 = self.first.contact_force(k, omega, phi1)
        return -f1 * np.cos(phi1) / (abs(self.a) * np.cos(phi2))

    def contact_stress(self, force, k, length, moduli, rho=None):
        rho = self.radius_of_curvature(k) if rho is None else rho
        return hertz_stress(force, self.roller_radius, rho - self.roller_radius, length, *moduli)

    @property
    def has_load(self) -> bool:
        return self.first.has_load

    def lift_extent(self) -> float:
        return self.first.lift_extent()

    def describe(self) -> dict[str, Any]:
        return {**super().describe(), "roller_radius": self.roller_radius, "of": self.first.name}


@dataclass(frozen=True)
class YokeRoller(SecondRoller):
    """The second roller of a translating yoke: on the first's line of motion x = e, the roller
    distance D below the first (a = 1, b = −iD)."""

    roller_distance: float = 0.0
    offset: float = 0.0          # the line of motion x = e (shared with the first roller)

    pressure_angle_text = ("between the contact normal and the line of motion, for each roller on its cam "
                           "(thesis Eq. 3.4 for the first)")

    @classmethod
    def of(cls, first: Follower, roller_distance: float, roller_radius: float) -> "YokeRoller":
        return cls(first, 1.0 + 0j, -1j * roller_distance, roller_radius, roller_distance, first.offset)

    @property
    def name(self) -> str:
        return "translating roller (second of a yoke)"

    def cam_angle_of(self, p, dp):
        # Re(e^{iδθ}p) = e with Im < 0: the second roller is below the cam axis
        r = np.abs(p)
        return self.sense * (-np.arccos(np.clip(self.offset / r, -1.0, 1.0)) - np.angle(p))

    def label(self) -> str:
        return (f"yoke's second roller r = {self.roller_radius:g} on the line x = {self.offset:g}, "
                f"{self.roller_distance:g} below the first")

    def describe(self) -> dict[str, Any]:
        return {**super().describe(), "roller_distance": self.roller_distance, "offset": self.offset}

    def sketch(self, theta, k, size, face_width=None):
        p2 = complex(self.points(np.array([theta]), k)[0])
        p1 = complex(self.first.points(np.array([theta]), k)[0])
        return FollowerSketch(p2, ((p2, self.roller_radius),), ((p2, p1, "yoke"),))


@dataclass(frozen=True)
class ArmPairRoller(SecondRoller):
    """The second arm of an oscillating arm pair: the pivot D_p shared, the arm at the fixed angle
    γ from the first and L₂ long (a = (L₂/L₁)e^{iγ}, b = D_p(1 − a))."""

    arm_angle: float = 0.0       # γ [rad]
    arm_length: float = 0.0      # L₂
    pivot_distance: float = 0.0

    pressure_angle_text = ("between the contact normal and the roller centre's velocity, perpendicular to its "
                           "arm, for each roller on its cam")

    @classmethod
    def of(cls, first: Follower, arm_angle_deg: float, arm_length: float, roller_radius: float) -> "ArmPairRoller":
        d = first.pivot_distance
        a = arm_length / first.arm_length * np.exp(1j * arm_angle_deg * DEG)
        return cls(first, complex(a), complex(d * (1 - a)), roller_radius, arm_angle_deg * DEG, arm_length, d)

    @property
    def pivot(self) -> complex:
        return complex(self.pivot_distance, 0.0)

    @property
    def name(self) -> str:
        return "oscillating roller (second arm)"

    def cam_angle_of(self, p, dp):
        # |e^{iδθ}p − D_p| = L₂ on the second arm's side of the line through the pivot and the axis (y < 0)
        r = np.abs(p)
        d, L = self.pivot_distance, self.arm_length
        alpha = np.arccos(np.clip((r * r + d * d - L * L) / (2 * r * d), -1.0, 1.0))
        return self.sense * (-alpha - np.angle(p))

    def label(self) -> str:
        return (f"second arm's roller r = {self.roller_radius:g}, at {math.degrees(self.arm_angle):g}° from the "
                f"first, arm L = {self.arm_length:g}")

    def describe(self) -> dict[str, Any]:
        return {**super().describe(), "arm_angle_deg": math.degrees(self.arm_angle), "arm_length": self.arm_length,
                "pivot_distance": self.pivot_distance}

    def sketch(self, theta, k, size, face_width=None):
        p2 = complex(self.points(np.array([theta]), k)[0])
        pivot = self._to_cam(theta, self.pivot)
        return FollowerSketch(p2, ((p2, self.roller_radius),), ((pivot, p2, "arm"),), pivot)


def _zero_lift() -> Kinematics:
    z = np.zeros(1)
    return Kinematics(z, z, z, z, z)


def second_roller_of(spec) -> SecondRoller:
    """The second roller of a conjugate spec (cam.body = "conjugate"), from its first follower: on
    the arm pair of a pivoted follower, else on the translating yoke."""
    first = follower_of(spec)
    c = spec.conjugate
    r2 = c.roller_radius if c.roller_radius is not None else spec.follower.roller_radius
    if first.pivoted:
        return ArmPairRoller.of(first, c.arm_angle, c.arm_length if c.arm_length is not None else spec.follower.arm_length,
                                r2)
    return YokeRoller.of(first, c.roller_distance, r2)

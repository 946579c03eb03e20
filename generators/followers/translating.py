"""Translating knife-edge and roller followers.

Cam frame: origin on the rotation axis; the follower line is x = e in the fixed frame.
With Y = s₀ + s(θ), s₀ = √(R_b² − e²), the follower point at cam angle θ in the cam frame
is (CAM_SPEC.md; paper Eq. 10)

    P(θ) = Rot(−δθ)·(e, Y),   δ = +1 for "ccw", −1 for "cw".

Points are returned as complex numbers x + iy.  The pressure angle and the radius of
curvature are the thesis' closed forms (Eq. 3.4 and 3.7), which the generic formulas of
:mod:`cam_workbench.generators.followers.base` reproduce; the built curve meets the follower where
Re(e^{iδθ}·r(ξ)) = e (paper Eq. 13), solved by :class:`cam_workbench.generators.pitch.contact.FollowerLineSolver`.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..kinds import register_follower
from ..motion.program import Kinematics
from ..pitch.contact import FollowerLineSolver
from ..spec.model import CamSpec
from ..studies.plan import Plan
from .base import Follower, FollowerSketch, LoadSpec, ToolMount
from .load import MASS_FORCE_FACTOR, hertz_stress


@register_follower
@dataclass(frozen=True)
class TranslatingFollower(Follower):
    """A translating knife edge or roller: the plain numbers that fix the follower point
    (offset e, s₀, rotation sign δ, roller radius) and its load."""

    offset: float
    s0: float
    sense: int  # +1 ccw, −1 cw
    roller_radius: float
    load: LoadSpec = field(default=LoadSpec())
    kinds = (("translating", "knife"), ("translating", "roller"))
    pivoted = False
    motion = "translating"
    pressure_angle_text = "φ = atan((s′ − e)/(s₀ + s)) (thesis Eq. 3.4)"
    curvature_text = "thesis Eq. 3.7"

    @classmethod
    def remedy_plans(cls, spec: CamSpec, check: str) -> list[Plan]:
        """The base radius; the offset too for the pressure angle."""
        out = [Plan("cam.base_radius", "smallest")]
        if check == "pressure_angle":
            rb = spec.cam.base_radius
            out.append(Plan("follower.offset", "nearest", bounds=(-rb, rb)))
        return out

    @classmethod
    def from_spec(cls, spec: CamSpec) -> "TranslatingFollower":
        f = spec.follower
        return cls(f.offset, spec.prime_offset, 1 if spec.cam.direction == "ccw" else -1, spec.roller_radius,
                   LoadSpec(f.preload, f.spring_rate, f.mass, MASS_FORCE_FACTOR[spec.units]))

    # ---- the Follower interface ----------------------------------------------------------
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

    @property
    def prime_radius(self) -> float:  # type: ignore[override]
        return float(np.hypot(self.offset, self.s0))

    def fixed(self, k: Kinematics, nder: int = 0) -> list[np.ndarray]:
        out = [self.offset + 1j * (self.s0 + np.asarray(k.s))]
        if nder >= 1:
            out.append(1j * np.asarray(k.ds, dtype=float))
        if nder >= 2:
            out.append(1j * np.asarray(k.d2s, dtype=float))
        return out

    def velocity_direction_at(self, q: np.ndarray) -> np.ndarray:
        return np.full(np.shape(q), 1j)

    def tool_mount(self) -> ToolMount:
        """The follower point (e, s₀) at zero lift, sliding along +y: (e, s₀ + s)."""
        return ToolMount((float(self.offset), float(self.s0)), 0.5 * np.pi)

    def pressure_angle(self, k: Kinematics) -> np.ndarray:
        """Pressure angle φ [rad] = atan((s' − e)/(s₀ + s)) (thesis Eq. 3.4), signed;
        e is the effective offset (−e for cw)."""
        e = self.effective_offset
        return np.arctan2(k.ds - e, self.s0 + k.s)

    def radius_of_curvature(self, k: Kinematics) -> np.ndarray:
        """Signed radius of curvature of the pitch curve (thesis Eq. 3.7):

            ρ = (Y² + (s'−e)²)^{3/2} / (Y² + (s'−e)(2s'−e) − Y·s''),  Y = s₀ + s,

        positive where the pitch curve is convex, negative where concave."""
        e = self.effective_offset
        y = self.s0 + k.s
        v = k.ds - e
        num = (y * y + v * v) ** 1.5
        den = y * y + v * (2 * k.ds - e) - y * k.d2s
        with np.errstate(divide="ignore"):
            return num / den

    def contact_residual(self, q, dq, d2q):
        # paper Eq. 13: Re(q) = e; ∂q/∂θ = iδq
        return q.real - self.offset, dq.real, -self.sense * q.imag

    def lift_at(self, q, dq):
        return q.imag - self.s0

    def cam_angle_of(self, p, dp):
        # Re(e^{iδθ}p) = e with Im > 0, in closed form
        r = np.abs(p)
        return self.sense * (np.arccos(np.clip(self.offset / r, -1.0, 1.0)) - np.angle(p))

    def contact_solver(self, chain: Any, angles: np.ndarray) -> Any:
        return FollowerLineSolver(chain, angles, self.offset, self.sense, lift_origin=self.s0)

    def kinematic_state(self, k: Kinematics) -> tuple[np.ndarray, np.ndarray]:
        return self.pressure_angle(k), self.radius_of_curvature(k)

    def contact_force(self, k: Kinematics, omega: float, phi: np.ndarray | None = None) -> np.ndarray:
        """F = (P_L + k·s + M_f·s″ω²)/cos φ (thesis Eq. 3.5, with the spring rate)."""
        ld = self.load
        phi = self.pressure_angle(k) if phi is None else phi
        return (ld.preload + ld.rate * k.s + ld.inertia * ld.mass_force * k.d2s * omega**2) / np.cos(phi)

    def contact_stress(self, force, k, length, moduli, rho=None):
        if self.roller_radius <= 0:
            return super().contact_stress(force, k, length, moduli)
        rho = self.radius_of_curvature(k) if rho is None else rho
        return hertz_stress(force, self.roller_radius, rho - self.roller_radius, length, *moduli)

    def describe(self) -> dict[str, Any]:
        return {**super().describe(), "offset": self.offset, "prime_offset": self.s0}

    def label(self) -> str:
        what = f"roller r = {self.roller_radius:g}" if self.roller_radius > 0 else "knife edge"
        return f"translating {what}, offset e = {self.offset:g}"

    def sketch(self, theta, k, size, face_width=None):
        p = complex(self.points(np.array([theta]), k)[0])
        up = self._to_cam(theta, 1j)
        r = self.roller_radius
        return FollowerSketch(p, ((p, r),) if r > 0 else (), ((p, p + up * size, "stem"),))

    # ---- the thesis' names (kept for the code written against them) ------------------------
    @property
    def effective_offset(self) -> float:
        """The offset seen by the pressure-angle and curvature formulas: e for ccw, −e for cw
        (turning the cam the other way mirrors the mechanism)."""
        return self.offset * self.sense

    def pitch_points(self, theta: np.ndarray, s: np.ndarray) -> np.ndarray:
        """P(θ) as complex numbers (θ in rad, s in length)."""
        return np.exp(-1j * self.sense * np.asarray(theta)) * (self.offset + 1j * (self.s0 + np.asarray(s)))

    def pitch_radius_of_curvature(self, k: Kinematics) -> np.ndarray:
        return self.radius_of_curvature(k)


#: The name of the class before the follower interface (one release).
FollowerGeometry = TranslatingFollower



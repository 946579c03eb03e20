"""Translating follower geometry from the motion program (the design intent).

Cam frame: origin on the rotation axis; the follower line is x = e in the fixed
frame.  With Y = s₀ + s(θ), s₀ = √(R_b² − e²), the follower point at cam angle θ
in the cam frame is (CAM_SPEC.md; paper Eq. 10)

    P(θ) = Rot(−δθ)·(e, Y),   δ = +1 for "ccw", −1 for "cw".

Points are returned as complex numbers x + iy.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..motion.program import Kinematics, MotionProgram
from ..spec.model import CamSpec


@dataclass(frozen=True)
class FollowerGeometry:
    """The plain numbers that fix the follower point: offset e, s₀, rotation sign δ."""

    offset: float
    s0: float
    sense: int  # +1 ccw, −1 cw
    roller_radius: float

    @classmethod
    def from_spec(cls, spec: CamSpec) -> "FollowerGeometry":
        return cls(spec.follower.offset, spec.prime_offset,
                   1 if spec.cam.direction == "ccw" else -1, spec.roller_radius)

    @property
    def effective_offset(self) -> float:
        """The offset seen by the pressure-angle and curvature formulas: e for ccw, −e for cw
        (turning the cam the other way mirrors the mechanism)."""
        return self.offset * self.sense

    def pitch_points(self, theta: np.ndarray, s: np.ndarray) -> np.ndarray:
        """P(θ) as complex numbers (θ in rad, s in length)."""
        return np.exp(-1j * self.sense * np.asarray(theta)) * (self.offset + 1j * (self.s0 + np.asarray(s)))

    def pressure_angle(self, k: Kinematics) -> np.ndarray:
        """Pressure angle φ [rad] = atan((s' − e)/(s₀ + s)) (thesis Eq. 3.4), signed;
        e is the effective offset (−e for cw)."""
        e = self.effective_offset
        return np.arctan2(k.ds - e, self.s0 + k.s)

    def pitch_radius_of_curvature(self, k: Kinematics) -> np.ndarray:
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


def design_pitch(spec: CamSpec, theta: np.ndarray) -> tuple[np.ndarray, Kinematics]:
    """Pitch points and kinematics of the design intent at angles ``theta`` [rad]."""
    prog = MotionProgram.from_spec(spec)
    geo = FollowerGeometry.from_spec(spec)
    k = prog.evaluate(theta)
    return geo.pitch_points(theta, k.s), k

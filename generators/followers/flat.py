"""Flat-faced followers, translating and oscillating: the cam profile is the envelope of the
face's positions, and the design curve is the profile itself (the contact points).

A face is a line of the fixed frame with outward unit normal n = e^{iβ} (pointing away from
the cam) at distance h from the cam axis: {x : Re(n̄x) = h}.  Both β and h depend on the lift:

* translating (CAM_SPEC.md): the face is perpendicular to the line of motion (+Y) and touches
  the base circle R_b at zero lift — β = π/2, h = R_b + s;
* oscillating: the face is the line at distance f (``face_offset``) from the pivot D = (d, 0),
  turning with the arm, pivot on the face's outer side — h = d·cos β − f, β = β₀ − s with
  cos β₀ = (R_b + f)/d, β₀ ∈ (0, π) (the contact on the upper side, as for the other followers).

Seen from the cam, the face's normal angle is γ(θ) = β(s(θ)) − δθ, and the envelope of the lines
Re(e^{−iγ}x) = h(γ) is the support-function curve (e.g. Kreyszig, Differential Geometry §4)

    X = h·e^{iγ} + h_γ·i·e^{iγ},   dX/dγ = (h + h_γγ)·i·e^{iγ},

so the profile's radius of curvature is ρ = h + h_γγ — for the translating face the classic
ρ = R_b + s + s″ — and the profile has a cusp where ρ ≤ 0.  The contact sits at h_γ along the
face from the foot of the normal through the cam axis: x = δ·s′ for the translating face.

The built curve drives the face back: at a point q of the built curve (fixed frame) with unit
tangent t, the outward normal is iδt; the translating face touches where that normal is +Y,
the oscillating face where the face line through q passes at f from the pivot.
"""
from __future__ import annotations

import math
from abc import abstractmethod
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import SpecError, fmt_apart
from ..kinds import body_of, register_follower
from ..motion.program import Kinematics
from ..spec.model import CamSpec
from ..studies.plan import Plan
from .base import Follower, FollowerSketch, LoadSpec, ToolMount, arm_moment, refuse_lift_beyond
from .load import MASS_FORCE_FACTOR, hertz_stress

DEG = math.pi / 180.0


@dataclass(frozen=True)
class FaceTerms:
    """The face and the envelope terms at a set of cam angles (θ-derivatives; s in rad or length)."""

    n: np.ndarray          # outward unit normal e^{iβ} (fixed frame)
    h: np.ndarray          # distance of the face from the cam axis
    h_gamma: np.ndarray    # h_γ: the contact's position along the face (direction i·n)
    rho: np.ndarray        # h + h_γγ: the profile's signed radius of curvature
    gamma_t: np.ndarray    # dγ/dθ
    gamma_tt: np.ndarray   # d²γ/dθ²
    rho_t: np.ndarray | None = None


class FlatFaceFollower(Follower):
    """The envelope machinery shared by the flat faces; a kind gives β(s), h(s) and derivatives."""

    contact = "flat"
    contact_words = "flat-faced"
    has_contact_stress = True
    design_curve = "profile"
    profile_offset = 0.0
    contact_order = 2
    curvature_text = "ρ = h + h_γγ of the face's envelope"

    @abstractmethod
    def face(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(β, β_s, h, h_s, h_ss, h_sss) at internal lifts s (β_ss = 0 for both kinds)."""

    def terms(self, k: Kinematics, third: bool = False) -> FaceTerms:
        c = self.lift_scale
        s, v, a = c * np.asarray(k.s, float), c * np.asarray(k.ds, float), c * np.asarray(k.d2s, float)
        beta, b_s, h, h_s, h_ss, h_sss = self.face(s)
        d = self.sense
        g1 = b_s * v - d                     # γ_θ
        g2 = b_s * a                         # γ_θθ
        h1 = h_s * v                         # h_θ
        h2 = h_ss * v * v + h_s * a          # h_θθ
        hg = h1 / g1                         # h_γ
        hgg = (h2 * g1 - h1 * g2) / g1**3    # h_γγ
        rho = h + hgg
        rho_t = None
        if third:
            j = c * np.asarray(k.d3s, float)
            g3 = b_s * j
            h3 = h_sss * v**3 + 3 * h_ss * v * a + h_s * j
            rho_t = h1 + (h3 * g1 - h1 * g3) / g1**3 - 3 * g2 * (h2 * g1 - h1 * g2) / g1**4
        return FaceTerms(np.exp(1j * beta), h, hg, rho, g1, g2, rho_t)

    def fixed(self, k: Kinematics, nder: int = 0) -> list[np.ndarray]:
        t = self.terms(k, third=nder >= 2)
        d = self.sense
        f0 = t.h * t.n + t.h_gamma * 1j * t.n
        out = [f0]
        if nder >= 1:
            v = t.rho * t.gamma_t * 1j * t.n
            f1 = v + 1j * d * f0
            out.append(f1)
        if nder >= 2:
            w = (t.rho_t * t.gamma_t + t.rho * t.gamma_tt) * 1j * t.n - t.rho * t.gamma_t**2 * t.n
            out.append(w + 2j * d * f1 + f0)
        return out

    def radius_of_curvature(self, k: Kinematics) -> np.ndarray:
        """ρ = h + h_γγ (signed: ≤ 0 is a cusp, which a flat face cannot make)."""
        return self.terms(k).rho

    def kinematic_state(self, k: Kinematics) -> tuple[np.ndarray, np.ndarray]:
        return self.pressure_angle(k), self.radius_of_curvature(k)

    def contact_stress(self, force, k, length, moduli, rho=None):
        # a cylinder of the profile's radius on a plane (flat on convex)
        rho = self.radius_of_curvature(k) if rho is None else rho
        return hertz_stress(force, np.inf, rho, length, *moduli)

    @abstractmethod
    def face_position(self, k: Kinematics) -> np.ndarray:
        """Where the contact sits on the face, measured from the face's reference point
        (spec length units): the stem (translating) or the foot of the pivot (oscillating)."""

    @property
    def face_centre(self) -> float | None:
        """Position of the face's centre on the same scale (None: not given)."""
        return None


@register_follower
@dataclass(frozen=True)
class TranslatingFlatFollower(FlatFaceFollower):
    """A translating flat face perpendicular to the line of motion x = e (the stem)."""

    base_radius: float
    offset: float
    sense: int
    load: LoadSpec = field(default=LoadSpec())
    kinds = (("translating", "flat"),)
    pivoted = False
    motion = "translating"
    #: the profile's radius of curvature (the cusp check's words)
    cusp_formula = "R_b + s + s″"
    #: where positions along the face are measured from
    face_origin = "stem"
    pressure_angle_text = "0: the face's normal is the line of motion"
    curvature_text = "ρ = R_b + s + s″ (the face's envelope)"

    @classmethod
    def from_spec(cls, spec: CamSpec) -> "TranslatingFlatFollower":
        f = spec.follower
        return cls(spec.cam.base_radius, f.offset, 1 if spec.cam.direction == "ccw" else -1,
                   LoadSpec(f.preload, f.spring_rate, f.mass, MASS_FORCE_FACTOR[spec.units]))

    @property
    def prime_radius(self) -> float:  # type: ignore[override]
        return self.base_radius

    def face(self, s):
        z = np.zeros_like(s)
        return np.full_like(s, np.pi / 2), z, self.base_radius + s, np.ones_like(s), z, z

    def velocity_direction_at(self, q: np.ndarray) -> np.ndarray:
        return np.full(np.shape(q), 1j)

    def tool_mount(self) -> ToolMount:
        """The face's centre, its foot on the stem: (e, R_b) at zero lift, sliding along +y."""
        return ToolMount((float(self.offset), float(self.base_radius)), 0.5 * np.pi)

    def pressure_angle(self, k: Kinematics) -> np.ndarray:
        """0: the face's normal is the line of motion."""
        return np.zeros(np.shape(k.s))

    def contact_residual(self, q, dq, d2q):
        # the outward normal iδt is +Y where the tangent is horizontal: g = −δ·Im(q′)
        d = self.sense
        return -d * dq.imag, -d * d2q.imag, -dq.real

    def lift_at(self, q, dq):
        return q.imag - self.base_radius

    def cam_angle_of(self, p, dp):
        a = np.angle(1j * self.sense * dp)
        return self.sense * (np.pi / 2 - a)

    def contact_force(self, k: Kinematics, omega: float, phi: np.ndarray | None = None) -> np.ndarray:
        """F = P_L + k·s + M_f·s″ω² (thesis Eq. 3.5 with φ = 0)."""
        ld = self.load
        return ld.preload + ld.rate * k.s + ld.inertia * ld.mass_force * k.d2s * omega**2

    def face_position(self, k: Kinematics) -> np.ndarray:
        """x = δ·s′ of the contact, from the stem x = e."""
        return self.sense * np.asarray(k.ds, float) - self.offset

    @property
    def face_centre(self) -> float | None:
        return 0.0

    def describe(self) -> dict[str, Any]:
        return {**super().describe(), "offset": self.offset, "base_radius": self.base_radius}

    def label(self) -> str:
        return f"translating flat face, offset e = {self.offset:g}"

    def sketch(self, theta, k, size, face_width=None):
        c = complex(self.points(np.array([theta]), k)[0])
        h = self.base_radius + float(np.asarray(k.s).ravel()[0])
        w = face_width or 2 * abs(float(np.asarray(self.face_position(k)).ravel()[0])) + 0.5 * size
        a, b, foot = self.offset - w / 2 + 1j * h, self.offset + w / 2 + 1j * h, self.offset + 1j * h
        cam = lambda z: self._to_cam(theta, z)  # noqa: E731
        return FollowerSketch(c, (), ((cam(a), cam(b), "face"), (cam(foot), cam(foot + 1j * size), "stem")))


def zero_lift_face_angle(base_radius: float, pivot_distance: float, face_offset: float) -> float:
    """β₀ [rad] in (0, π): the face at f from the pivot touches the base circle (NaN if it cannot)."""
    c = (base_radius + face_offset) / pivot_distance
    return math.acos(c) if -1.0 < c < 1.0 else float("nan")


@register_follower
@dataclass(frozen=True)
class OscillatingFlatFollower(FlatFaceFollower):
    """An oscillating flat face: the line at ``face_offset`` from the pivot, turning with the arm;
    ``arm_length`` (optional) places the face's centre along it from the foot of the pivot."""

    pivot_distance: float
    face_offset: float
    base_radius: float
    sense: int
    arm_length: float | None = None
    load: LoadSpec = field(default=LoadSpec())
    kinds = (("oscillating", "flat"),)
    pivoted = True
    motion = "oscillating"
    cusp_formula = "h + h_γγ"
    face_origin = "foot of the pivot"
    lift_scale = DEG
    lift_unit = "angle"
    pressure_angle_text = "between the face's normal and the contact point's velocity about the pivot, atan(f/t)"

    @classmethod
    def validate(cls, spec: CamSpec) -> None:
        """On a plane cam the face must touch the base circle and must not turn onto the line
        through the pivot and the cam axis within the lift."""
        if not body_of(spec).plane:
            return
        fol, rb = spec.follower, spec.cam.base_radius
        d, f = fol.pivot_distance, fol.face_offset or 0.0
        if not abs(rb + f) < d:
            raise SpecError("follower.pivot_distance",
                            f"the face at face_offset {f:g} from the pivot cannot touch the base circle: needs "
                            f"|cam.base_radius + face_offset| = {fmt_apart(abs(rb + f), d)} < pivot_distance, got "
                            f"{fmt_apart(d, abs(rb + f))}")
        refuse_lift_beyond(spec, cls.from_spec(spec).lift_extent(), "face")

    @classmethod
    def remedy_plans(cls, spec: CamSpec, check: str) -> list[Plan]:
        """The face must reach the base circle, |R_b + face_offset| < d (its arm_length, optional,
        only places the face's centre): the pivot distance and the base radius within that."""
        fol = spec.follower
        d, f, rb = fol.pivot_distance, fol.face_offset or 0.0, spec.cam.base_radius
        return [Plan("follower.pivot_distance", "nearest", bounds=(abs(rb + f), math.inf)),
                Plan("cam.base_radius", "nearest", bounds=(max(0.0, -d - f), d - f))]

    @classmethod
    def from_spec(cls, spec: CamSpec) -> "OscillatingFlatFollower":
        f = spec.follower
        return cls(f.pivot_distance, f.face_offset or 0.0, spec.cam.base_radius,
                   1 if spec.cam.direction == "ccw" else -1, f.arm_length,
                   LoadSpec(f.preload_torque, f.spring_torque_rate, f.arm_inertia, MASS_FORCE_FACTOR[spec.units]))

    @property
    def prime_radius(self) -> float:  # type: ignore[override]
        return self.base_radius

    @property
    def load_lever(self) -> float:  # type: ignore[override]
        return self.pivot_distance

    @property
    def beta0(self) -> float:
        return zero_lift_face_angle(self.base_radius, self.pivot_distance, self.face_offset)

    @property
    def pivot(self) -> complex:
        return complex(self.pivot_distance, 0.0)

    def tool_mount(self) -> ToolMount:
        """The face's centre, a point of the arm's body: ``arm_length`` along the face from the foot of
        the pivot (the zero-lift contact's place, d·sin β₀, when not given), the foot at f from the
        pivot along −n; it turns about the pivot (d, 0) with the face, β = β₀ − s (ratio −1)."""
        c = self.arm_length if self.arm_length is not None else self.pivot_distance * math.sin(self.beta0)
        z = complex(-self.face_offset, c)          # in the face's frame: n = 1, along the face i
        return ToolMount((float(self.pivot_distance), 0.0), float(self.beta0 + np.angle(z)), float(abs(z)), -1.0)

    def face(self, s):
        beta = self.beta0 - s
        d = self.pivot_distance
        cb, sb = np.cos(beta), np.sin(beta)
        # h = d cos β − f, β_s = −1: h_s = d sin β, h_ss = −d cos β, h_sss = −d sin β
        return beta, -np.ones_like(s), d * cb - self.face_offset, d * sb, -d * cb, -d * sb

    def velocity_direction_at(self, q: np.ndarray) -> np.ndarray:
        r = q - self.pivot
        return -1j * r / np.abs(r)

    def contact_residual(self, q, dq, d2q):
        d = self.sense
        sp = np.abs(dq)
        t = dq / sp
        r = self.pivot - q
        along = (np.conj(t) * r).real
        kappa = (np.conj(t) * d2q).imag / sp
        return (d * (np.conj(t) * r).imag - self.face_offset, -d * kappa * along,
                -(np.conj(t) * self.pivot).real)

    def lift_at(self, q, dq):
        beta = np.angle(1j * self.sense * dq)
        return (np.mod(self.beta0 - beta + np.pi, 2 * np.pi) - np.pi) / DEG

    def cam_angle_of(self, p, dp):
        n = 1j * self.sense * dp / np.abs(dp)
        support = (np.conj(n) * p).real
        beta = np.arccos(np.clip((support + self.face_offset) / self.pivot_distance, -1.0, 1.0))
        return self.sense * (beta - np.angle(n))

    def torque(self, k: Kinematics, omega: float) -> np.ndarray:
        """T = T_L + k_t·s + I·s″ω² [torque unit] (s, s″ in rad)."""
        ld = self.load
        return ld.preload + ld.rate * DEG * k.s + ld.inertia * ld.mass_force * DEG * k.d2s * omega**2

    def contact_force(self, k: Kinematics, omega: float, phi: np.ndarray | None = None) -> np.ndarray:
        t = self.terms(k)
        point = t.h * t.n + t.h_gamma * 1j * t.n
        return self.torque(k, omega) / arm_moment(point, t.n, self.pivot)

    def face_position(self, k: Kinematics) -> np.ndarray:
        """t = h_γ + d·sin β: the contact's distance along the face from the foot of the pivot."""
        t = self.terms(k)
        beta = np.angle(t.n)
        return t.h_gamma + self.pivot_distance * np.sin(beta)

    @property
    def face_centre(self) -> float | None:
        return self.arm_length

    def describe(self) -> dict[str, Any]:
        return {**super().describe(), "pivot_distance": self.pivot_distance, "face_offset": self.face_offset,
                "arm_length": self.arm_length, "face_angle_at_zero_lift_deg": math.degrees(self.beta0)}

    def label(self) -> str:
        return (f"oscillating flat face, pivot d = {self.pivot_distance:g}, face offset f = {self.face_offset:g}"
                + (f", face centre at {self.arm_length:g}" if self.arm_length is not None else ""))

    def sketch(self, theta, k, size, face_width=None):
        t = self.terms(k)
        n = complex(t.n.ravel()[0])
        u = 1j * n
        foot = self.pivot - self.face_offset * n
        pos = float(np.asarray(self.face_position(k)).ravel()[0])
        centre = self.arm_length if self.arm_length is not None else pos
        w = face_width or 2 * max(abs(pos - centre), 0.25 * size) + 0.5 * size
        c = complex(self.points(np.array([theta]), k)[0])
        cam = lambda z: self._to_cam(theta, z)  # noqa: E731
        a, b = foot + (centre - w / 2) * u, foot + (centre + w / 2) * u
        return FollowerSketch(c, (), ((cam(a), cam(b), "face"), (cam(self.pivot), cam(foot + centre * u), "arm")),
                              cam(self.pivot))

    def lift_extent(self) -> float:
        return math.degrees(self.beta0)

"""The follower interface: everything the pitch construction, the checks, the interpolator,
the tool paths, the optimiser, the report and the FreeCAD feature need to know about a
follower kind, behind one class (:class:`Follower`).

A follower turns the motion program s(θ) into the **design curve** — the curve the cam is
built from, interpolated by the PH spline (or fitted by the B-spline):

* knife edge and roller: the path of the follower point (knife tip, roller centre), the
  *pitch curve*; the cam profile is its inward offset by :attr:`Follower.profile_offset`
  (the roller radius; 0 for a knife edge);
* flat face: the contact points of the face — the profile itself (offset 0), the envelope of
  the face's positions.

Frames (CAM_SPEC.md): the fixed frame has the cam axis at the origin; the cam frame turns
with the cam, so a point F of the fixed frame at cam angle θ is C = Rot(−δθ)·F in the cam
frame (δ = +1 for a ccw cam, −1 for cw).  Points are complex numbers x + iy.  Each kind gives
the design point in the fixed frame, F(θ), and its total θ-derivatives (through s, s′, …);
everything else follows here:

    C′ = Rot(−δθ)·V,   V = F_θ − iδF                (the tangent, seen in the fixed frame)
    C″ = Rot(−δθ)·W,   W = F_θθ − 2iδF_θ − F
    ρ  = |V|³ / (−δ·Im(V̄W))                         (+ convex: a ccw cam's curve runs clockwise)
    tan φ = (V·w) / (δ·V·(−iw))                     (w: direction in which the follower's
                                                     material point at the contact moves as s grows)

which reproduce the thesis' Eq. 3.4 and 3.7 for a translating follower.

The built curve drives the follower back through :meth:`Follower.contact_residual` — the
paper's Eq. 13 generalised: at cam angle θ the built curve, turned into the fixed frame,
q(ξ) = Rot(δθ)·r(ξ), touches the follower where g(q, q′, q″) = 0 — and :meth:`lift_at` reads
the lift off the touching point.
"""
from __future__ import annotations

import dataclasses
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..errors import SpecError, fmt_apart
from ..motion.program import Kinematics
from ..pitch.contact import ContactSolver
from ..studies.plan import Plan

TWO_PI = 2.0 * np.pi


@dataclass(frozen=True)
class LoadSpec:
    """The follower train's load, as the spec gives it (spec units).

    Translating: ``preload`` P_L [force], ``rate`` k [force/length], ``inertia`` M_f [mass].
    Oscillating: ``preload`` T_L [torque], ``rate`` k_t [torque/rad], ``inertia`` I [mass·length²].
    ``mass_force``: the factor that turns mass × length/s² into force (10⁻³ N for kg·mm/s², 1 lbf
    for lbf·s²/in·in/s²)."""

    preload: float = 0.0
    rate: float = 0.0
    inertia: float = 0.0
    mass_force: float = 1.0

    @property
    def any(self) -> bool:
        return self.preload > 0 or self.rate > 0 or self.inertia > 0


@dataclass(frozen=True)
class FollowerSketch:
    """The follower drawn where it is at one cam angle, in the cam frame (spec lengths): plain
    geometry that the plots, the DXF drawing and the FreeCAD feature draw.

    Attributes:
        point: the follower point (roller centre, knife tip) or a flat face's contact point.
        circles: (centre, radius) of the roller.
        segments: (start, end, role) with role "stem", "arm" or "face".
        pivot: the arm's pivot (oscillating followers), else None.
    """

    point: complex
    circles: tuple[tuple[complex, float], ...] = ()
    segments: tuple[tuple[complex, complex, str], ...] = ()
    pivot: complex | None = None


@dataclass(frozen=True)
class ToolMount:
    """The follower's own point — where a tool rides by default — in the cam's fixed frame (the cam's
    axis at the origin, spec lengths): its place at zero lift and how the lift moves it, as a lever
    p = ``ratio``·q of the follower coordinate q = ``lift_scale``·s (docs/machine.md, "The tool").

    Attributes:
        origin: (x, y) a translating follower's point at zero lift; an oscillating follower's pivot.
        direction: [rad, counter-clockwise from +x] a translating follower's direction of motion
            (positive lift), or the direction from the pivot to the point at zero lift.
        radius: [length] the point's distance from the pivot (0 for a translating follower).
        ratio: p per unit q: 1 for a translating follower (the point at origin + q·(cos, sin)(direction));
            −1 for an arm whose angle is ψ₀ − s (the point at origin + radius·(cos, sin)(direction − q)).
    """

    origin: tuple[float, float]
    direction: float
    radius: float = 0.0
    ratio: float = 1.0


class Follower(ABC):
    """A follower kind (one module each: translating, oscillating, flat).

    Attributes:
        motion: "translating" or "oscillating".
        contact: "knife", "roller" or "flat".
        sense: +1 for a ccw cam, −1 for cw.
        profile_offset: inward distance from the design curve to the cam profile (the roller
            radius; 0 for a knife edge and a flat face).
        lift_scale: spec lift units → internal units (1 for lengths, π/180 for arm degrees).
        lift_unit: "length" or "angle" (the unit kind of lifts, deviations and s′, s″).
        design_curve: "pitch" (knife, roller: the follower point's path) or "profile" (flat face).
        load: the follower train's load.

    Declared by every registered class (:func:`cam_workbench.generators.kinds.register_follower`):
    ``kinds``, the (follower.motion, follower.kind) pairs it serves; ``pivoted``, whether the
    follower turns about a pivot (its lift an angle, its geometry an arm's); ``modules``, further
    modules of the kind.
    """

    kinds: ClassVar[tuple[tuple[str, str], ...]]
    pivoted: ClassVar[bool]
    modules: ClassVar[tuple[str, ...]] = ()
    motion: str
    contact: str
    sense: int
    profile_offset: float = 0.0
    lift_scale: float = 1.0
    lift_unit: str = "length"
    design_curve: str = "pitch"
    load: LoadSpec = LoadSpec()
    #: the dynamics drive an indexer's output train (its inertia is ``load.inertia``), not a follower
    turret: bool = False

    @classmethod
    def validate(cls, spec: Any) -> None:
        """The kind's own geometric rules (called by the spec's validation, after the motion
        program's; none unless the kind declares them).

        Raises:
            SpecError: naming the field and the rule.
        """

    @classmethod
    def remedy_plans(cls, spec: Any, check: str) -> list:
        """The fields (:class:`cam_workbench.generators.studies.plan.Plan`) that move a failing size
        ``check`` (pressure angle, curvature, undercut, …) of a plane cam with this follower."""
        return [Plan("cam.base_radius", "smallest")]

    # ---- the design curve ----------------------------------------------------------------
    @abstractmethod
    def fixed(self, k: Kinematics, nder: int = 0) -> list[np.ndarray]:
        """[F, F_θ, F_θθ][: nder + 1]: the design point in the fixed frame and its total
        θ-derivatives, from the kinematics ``k`` (spec lift units)."""

    def points(self, theta: np.ndarray, k: Kinematics) -> np.ndarray:
        """Design-curve points C(θ) in the cam frame (complex)."""
        return np.exp(-1j * self.sense * np.asarray(theta)) * self.fixed(k, 0)[0]

    def derivatives(self, theta: np.ndarray, k: Kinematics, nder: int = 1) -> list[np.ndarray]:
        """[C, C′, C″][: nder + 1] in the cam frame (θ-derivatives)."""
        rot = np.exp(-1j * self.sense * np.asarray(theta))
        f = self.fixed(k, nder)
        d = self.sense
        out = [rot * f[0]]
        if nder >= 1:
            out.append(rot * (f[1] - 1j * d * f[0]))
        if nder >= 2:
            out.append(rot * (f[2] - 2j * d * f[1] - f[0]))
        return out

    def tangents(self, k: Kinematics) -> tuple[np.ndarray, np.ndarray]:
        """(V, W): C′ and C″ turned into the fixed frame (see the module docstring)."""
        f = self.fixed(k, 2)
        d = self.sense
        return f[1] - 1j * d * f[0], f[2] - 2j * d * f[1] - f[0]

    def radius_of_curvature(self, k: Kinematics) -> np.ndarray:
        """Signed radius of curvature ρ of the design curve (+ convex, − concave)."""
        v, w = self.tangents(k)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.abs(v) ** 3 / (-self.sense * (np.conj(v) * w).imag)

    def kinematic_state(self, k: Kinematics) -> tuple[np.ndarray, np.ndarray]:
        """(pressure angle φ [rad], radius of curvature ρ) at once, from one evaluation of the
        design point's derivatives (the checks evaluate both at every sample)."""
        f = self.fixed(k, 2)
        d = self.sense
        v = f[1] - 1j * d * f[0]
        w = f[2] - 2j * d * f[1] - f[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            rho = np.abs(v) ** 3 / (-d * (np.conj(v) * w).imag)
        return self.pressure_angle_of(v, self.velocity_direction_at(f[0])), rho

    def profile_radius(self, k: Kinematics) -> np.ndarray:
        """Signed radius of curvature of the cam profile: ρ − profile_offset."""
        return self.radius_of_curvature(k) - self.profile_offset

    @abstractmethod
    def velocity_direction_at(self, q: np.ndarray) -> np.ndarray:
        """w: unit direction (fixed frame) in which the follower's material point at the
        contact point q moves as the lift grows."""


    def pressure_angle(self, k: Kinematics) -> np.ndarray:
        """Signed pressure angle φ [rad], |φ| < 90°: between the contact normal and the
        direction the follower's contact point moves."""
        v = self.fixed(k, 1)
        return self.pressure_angle_of(v[1] - 1j * self.sense * v[0], self.velocity_direction_at(v[0]))

    def pressure_angle_of(self, tangent: np.ndarray, w: np.ndarray) -> np.ndarray:
        """φ [rad] from the curve's tangent (fixed frame, direction of increasing θ) and the
        contact point's direction of motion: tan φ = (V·w)/(δ·V·(−iw))."""
        along = (np.conj(w) * tangent).real
        across = self.sense * (np.conj(-1j * w) * tangent).real
        return np.arctan2(along * np.sign(across + (across == 0)), np.abs(across))

    # ---- the built curve drives the follower (Eq. 13 generalised) ------------------------
    @abstractmethod
    def contact_residual(self, q: np.ndarray, dq: np.ndarray, d2q: np.ndarray
                         ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(g, ∂g/∂ξ, ∂g/∂θ) at points q(ξ) of the built curve turned into the fixed frame,
        with dq, d2q its ξ-derivatives: g = 0 where the follower touches the curve."""

    @abstractmethod
    def lift_at(self, q: np.ndarray, dq: np.ndarray) -> np.ndarray:
        """The lift [spec lift units] the follower has when it touches the built curve at the
        fixed-frame point q (tangent dq)."""

    @abstractmethod
    def cam_angle_of(self, p: np.ndarray, dp: np.ndarray) -> np.ndarray:
        """Cam angle θ [rad] (unwrapped) at which the follower touches a design-curve point p
        of the cam frame whose tangent (direction of increasing θ) is dp."""

    def contact_solver(self, chain: Any, angles: np.ndarray) -> Any:
        """A solver of :meth:`contact_residual` on a closed chain of Bézier segments whose
        segment k is touched between cam angles ``angles[k]`` and ``angles[k+1]``."""
        return ContactSolver(chain, angles, self)

    # ---- loads ----------------------------------------------------------------------------
    @abstractmethod
    def contact_force(self, k: Kinematics, omega: float, phi: np.ndarray | None = None) -> np.ndarray:
        """Normal contact force [force unit] that keeps the follower on the cam at cam speed
        ``omega`` [rad/s] (thesis Eq. 3.5 for a translating follower; ≤ 0: it leaves); ``phi``:
        the pressure angle at ``k`` when already known."""

    def force_per_load(self, k: Kinematics) -> np.ndarray:
        """The normal contact force [force unit] per unit of the follower's generalised load — the
        unit of ``load.preload``: a force along the line of motion (translating), a torque about the
        pivot (oscillating) — at the design contact of ``k``: 1/cos φ, 1/(L·cos φ), 1/lever, …

        It is :meth:`contact_force` of this follower loaded by a unit preload alone, so every kind
        gives it through its own force law (the dynamics read it: :mod:`cam_workbench.generators.dynamics`)."""
        unit = dataclasses.replace(self, load=LoadSpec(preload=1.0, mass_force=self.load.mass_force))
        return np.asarray(unit.contact_force(k, 0.0), dtype=float)

    def contact_stress(self, force: np.ndarray, k: Kinematics, length: float, moduli: tuple,
                       rho: np.ndarray | None = None) -> np.ndarray:
        """Hertz contact stress for the contact ``force`` (NaN where not defined); ``rho``: the
        design curve's radius of curvature at ``k`` when already known."""
        return np.full(np.shape(force), np.nan)

    #: the highest ξ-derivative of the built curve :meth:`contact_residual` reads (1: q, q′; 2: q″ too)
    contact_order = 1

    #: the lever [length] that turns the follower's generalised load into a force (1: a
    #: translating follower's load is a force; an arm's torque over its arm length or pivot distance)
    load_lever: float = 1.0

    @property
    def has_load(self) -> bool:
        return self.load.any

    # ---- the tool it carries (docs/machine.md, "The tool") ----------------------------------
    @abstractmethod
    def tool_mount(self) -> ToolMount:
        """The follower's own point at zero lift and how the lift moves it (:class:`ToolMount`):
        where a machine's tool without a ``[linkage]`` and without ``[cam.tool]`` origin/direction
        rides — the point :meth:`fixed` gives (roller centre, knife tip), or a point of the face's
        body on a flat face."""

    # ---- drawing ---------------------------------------------------------------------------
    @abstractmethod
    def sketch(self, theta: float, k: Kinematics, size: float, face_width: float | None = None) -> FollowerSketch:
        """The follower at cam angle θ [rad] with the kinematics ``k`` there (length-1 arrays):
        ``size`` sets the drawn length of a stem; ``face_width`` the drawn face (flat faces)."""

    def _to_cam(self, theta: float, z: complex) -> complex:
        return complex(np.exp(-1j * self.sense * theta) * z)

    # ---- description -----------------------------------------------------------------------
    #: the contact in words ("roller", "knife-edge", "flat-faced")
    contact_words: ClassVar[str]
    #: a Hertz contact stress is defined (:meth:`contact_stress`; not for a knife edge)
    has_contact_stress: ClassVar[bool]

    @property
    def name(self) -> str:
        """E.g. "translating roller", "oscillating flat-faced"."""
        return f"{self.motion} {self.contact_words}"

    @property
    def base_circle_radius(self) -> float:
        """Radius of the cam's base circle (the profile at zero lift)."""
        return self.prime_radius - self.profile_offset

    prime_radius: float = 0.0

    def describe(self) -> dict[str, Any]:
        """Plain numbers of the follower for report.json (spec units; angles in degrees) and
        ``label``, the one-line wording every output prints (spec lengths, no unit)."""
        return {"motion": self.motion, "kind": self.contact, "name": self.name,
                "lift_unit": self.lift_unit, "design_curve": self.design_curve, "label": self.label(),
                "curve": "pitch curve" if self.design_curve == "pitch" else "contact curve",
                "pressure_angle_text": self.pressure_angle_text, "curvature_text": self.curvature_text}

    #: how the pressure angle is defined, in words (for the report's captions)
    pressure_angle_text = "between the contact normal and the direction the follower's contact point moves"
    #: how the design curve's radius of curvature is found, in words
    curvature_text = "from the curve's exact first and second θ-derivatives"

    def label(self) -> str:
        """E.g. "translating roller r = 8, offset e = 0" (lengths in spec units)."""
        return self.name

    def lift_extent(self) -> float:
        """The largest lift the geometry allows (spec lift units), inf when unbounded."""
        return float("inf")


def refuse_lift_beyond(spec: Any, extent: float, what: str) -> None:
    """The highest level the motion program reaches must stay below ``extent`` [spec lift units],
    the largest lift the follower's geometry allows (``what``: "arm", "face").

    Raises:
        SpecError: naming the segment whose lift first reaches the top.
    """
    level, top, at = 0.0, 0.0, 0
    for i, seg in enumerate(spec.motion):
        level += (seg.lift or 0.0) * (1 if seg.kind == "rise" else -1 if seg.kind == "return" else 0)
        if level > top:
            top, at = level, i
    if not top < extent:
        raise SpecError(f"motion[{at}].lift",
                        f"the {what} would turn {fmt_apart(top, extent)}° and reach the line through the pivot and the "
                        f"cam axis at {fmt_apart(extent, top, 4)}°: the lift must stay below it (a smaller lift, or move "
                        "the pivot)")


def arm_moment(contact_point: np.ndarray, normal: np.ndarray, pivot: complex) -> np.ndarray:
    """|(C − D) × n|: the lever of a force along the unit normal ``normal`` through the point
    C about the pivot D."""
    return np.abs((np.conj(contact_point - pivot) * normal).imag)

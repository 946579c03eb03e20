"""A planar four-bar between an oscillating follower and the tool: the follower's arm drives the
crank, the tool is the output rocker.

Frames (docs/linkages.md): the *ground frame* has its origin at the crank pivot O₂ and its x axis
towards the rocker pivot O₄ = (d, 0); the machine frame puts O₂ at ``origin`` and turns the ground
frame by ``frame_angle`` γ (counter-clockwise).  Angles in the ground frame, counter-clockwise:
crank θ₂ (O₂→A), coupler θ₃ (A→B), rocker θ₄ (O₄→B).  Loop closure (Norton, *Design of
Machinery*, §4.5, Eq. 4.5):  a·e^{iθ₂} + b·e^{iθ₃} − c·e^{iθ₄} − d = 0.

The crank is the follower's arm: θ₂ = ``crank_offset`` − q (q the follower's arm rotation, rad),
since the arm turns clockwise as the follower lifts (ψ = ψ₀ − s, docs/followers.md).  The tool
coordinate is the rocker's rotation from its angle at q = 0:  p = θ₄ − θ₄(0), wrapped to [−π, π).

Position, closed form (the circle–circle intersection, equivalent to Freudenstein's equation
K₁cos θ₄ − K₂cos θ₂ + K₃ = cos(θ₂ − θ₄), K₁ = d/a, K₂ = d/c, K₃ = (a² − b² + c² + d²)/(2ac),
Norton Eq. 4.8–4.10):  with e = |A − O₄|,  θ₄ = arg(A − O₄) + σ·acos((c² + e² − b²)/(2ce)).
The branch σ = ``branch`` (+1 or −1) is the side of the line O₄→A on which B lies (+1: left,
counter-clockwise about O₄); it can change only where coupler and rocker are collinear — a toggle.
The inverse drives the same linkage from the rocker (θ₄ given):  with f = |B − O₂|,
θ₂ = arg(B − O₂) + τ·acos((a² + f² − b²)/(2af)), τ the side of O₂→B on which A lies at q = 0.

Derivatives (exact, implicit differentiation of the loop closure, orders 1–3, with the input's
own θ-derivatives: the chain rule to third order): see :func:`loop_jet`.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from .base import Jet, points, wrap_pi


def loop_jet(r1: float, t1: np.ndarray, x: tuple[np.ndarray, np.ndarray, np.ndarray],
             r2: float, t2: np.ndarray, r3: float, t3: np.ndarray
             ) -> tuple[tuple[np.ndarray, ...], tuple[np.ndarray, ...]]:
    """θ-derivatives (orders 1–3) of the angles t2, t3 of the loop r1·z1 + r2·z2 − r3·z3 = const
    (z_k = e^{i t_k}) given t1's derivatives ``x``.

    Differentiating n times, the unknown n-th derivatives enter as i·t⁽ⁿ⁾·z and the rest is known:
    r2·u⁽ⁿ⁾·z2 − r3·w⁽ⁿ⁾·z3 = S; multiplying by z̄2 (z̄3) and taking imaginary parts gives
    w⁽ⁿ⁾ = −Im(S z̄2)/(r3 sin(t3 − t2)),  u⁽ⁿ⁾ = Im(S z̄3)/(r2 sin(t2 − t3)).
    (dⁿe^{it}/dθⁿ: i t′ e; (i t″ − t′²) e; (i t‴ − 3t′t″ − i t′³) e.)  Singular where t2 ∥ t3."""
    z1, z2, z3 = np.exp(1j * t1), np.exp(1j * t2), np.exp(1j * t3)
    x1, x2, x3 = x
    s23 = np.sin(t2 - t3)

    def solve(known: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        S = 1j * known                       # r2 u z2 − r3 w z3 = −i·(−known)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.imag(S * np.conj(z3)) / (r2 * s23), np.imag(S * np.conj(z2)) / (r3 * s23)

    u1, w1 = solve(r1 * 1j * x1 * z1)
    u2, w2 = solve(r1 * (1j * x2 - x1 ** 2) * z1 - r2 * u1 ** 2 * z2 + r3 * w1 ** 2 * z3)
    u3, w3 = solve(r1 * (1j * x3 - 3 * x1 * x2 - 1j * x1 ** 3) * z1
                   + r2 * (-3 * u1 * u2 - 1j * u1 ** 3) * z2 - r3 * (-3 * w1 * w2 - 1j * w1 ** 3) * z3)
    return (u1, u2, u3), (w1, w2, w3)


def _intersect(centre_to_known: np.ndarray, r_known: float, r_free: float, sign: float) -> np.ndarray:
    """The angle at the centre of the free link (length ``r_free``) towards the joint it shares with
    a link of length ``r_known`` whose far end is at ``centre_to_known`` (complex, from this
    centre): arg + sign·acos((r_free² + e² − r_known²)/(2 r_free e)); NaN where it cannot assemble."""
    e = np.abs(centre_to_known)
    with np.errstate(divide="ignore", invalid="ignore"):
        c = (r_free ** 2 + e ** 2 - r_known ** 2) / (2.0 * r_free * e)
    c = np.where(np.abs(c) <= 1.0, c, np.nan)
    return np.angle(centre_to_known) + sign * np.arccos(c)


@dataclass(frozen=True)
class FourBar:
    """Ground d, crank a, coupler b, rocker c [mm]; ``crank_offset`` [rad]: θ₂ at q = 0;
    ``branch`` σ = ±1; ``origin`` [mm] and ``frame_angle`` γ [rad]: the ground frame in the machine
    plane; ``tool_radius`` [mm]: the tool point's distance from O₄ along the rocker (None: B)."""

    ground: float
    crank: float
    coupler: float
    rocker: float
    crank_offset: float = 0.0
    branch: int = 1
    origin: tuple[float, float] = (0.0, 0.0)
    frame_angle: float = 0.0
    tool_radius: float | None = None
    kind: ClassVar[str] = "four_bar"
    angular_input_only: ClassVar[bool] = True

    def __post_init__(self) -> None:
        if not min(self.ground, self.crank, self.coupler, self.rocker) > 0:
            raise ValueError("a four-bar's links must all be longer than 0")
        if self.branch not in (1, -1):
            raise ValueError(f"branch must be +1 or −1, got {self.branch!r}")

    # ---- positions -------------------------------------------------------------------------
    def theta2(self, q: Any) -> np.ndarray:
        """Crank angle θ₂ = crank_offset − q [rad] (ground frame; the arm turns clockwise as it lifts)."""
        return self.crank_offset - np.asarray(q, dtype=float)

    def theta4_of(self, theta2: Any) -> np.ndarray:
        """Rocker angle θ₄ [rad] at crank angle θ₂ on this branch (NaN: cannot assemble)."""
        a_pt = self.crank * np.exp(1j * np.asarray(theta2, dtype=float))
        return _intersect(a_pt - self.ground, self.coupler, self.rocker, self.branch)

    @property
    def theta4_ref(self) -> float:
        """θ₄ at q = 0 [rad] (NaN when the linkage cannot assemble there)."""
        return float(self.theta4_of(np.array(self.crank_offset)))

    @property
    def inverse_branch(self) -> int:
        """τ: the side of the line O₂→B on which A lies at q = 0 (+1 left)."""
        a_pt = self.crank * np.exp(1j * self.crank_offset)
        b_pt = self.ground + self.rocker * np.exp(1j * self.theta4_ref)
        return 1 if np.imag(np.conj(b_pt) * a_pt) >= 0 else -1

    def theta2_of(self, theta4: Any) -> np.ndarray:
        """Crank angle θ₂ [rad] at rocker angle θ₄ (the four-bar driven from the rocker)."""
        b_pt = self.ground + self.rocker * np.exp(1j * np.asarray(theta4, dtype=float))
        return _intersect(b_pt, self.coupler, self.crank, self.inverse_branch)

    def angles(self, q: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(θ₂, θ₃, θ₄) [rad] at follower coordinate q."""
        t2 = self.theta2(q)
        t4 = self.theta4_of(t2)
        a_pt = self.crank * np.exp(1j * t2)
        b_pt = self.ground + self.rocker * np.exp(1j * t4)
        return t2, np.angle(b_pt - a_pt), t4

    # ---- the Linkage protocol -----------------------------------------------------------------
    def forward(self, q: Any, q1: Any, q2: Any, q3: Any) -> Jet:
        """(p, p′, p″, p‴): p = θ₄ − θ₄(0) wrapped to [−π, π) and its exact θ-derivatives."""
        t2, t3, t4 = self.angles(q)
        x = tuple(-np.asarray(v, dtype=float) + 0.0 * t2 for v in (q1, q2, q3))       # θ₂⁽ⁿ⁾ = −q⁽ⁿ⁾
        _, (w1, w2, w3) = loop_jet(self.crank, t2, x, self.coupler, t3, self.rocker, t4)  # type: ignore[arg-type]
        return wrap_pi(t4 - self.theta4_ref), w1, w2, w3

    def inverse(self, p: Any, p1: Any, p2: Any, p3: Any) -> Jet:
        """(q, q′, q″, q‴) of the tool jet: the four-bar driven from the rocker (loop
        c·e^{iθ₄} + b·e^{i(θ₃+π)} − a·e^{iθ₂} = −d), q wrapped to [−π, π)."""
        t4 = np.asarray(p, dtype=float) + self.theta4_ref
        t2 = self.theta2_of(t4)
        a_pt = self.crank * np.exp(1j * t2)
        b_pt = self.ground + self.rocker * np.exp(1j * t4)
        t3r = np.angle(a_pt - b_pt)                       # θ₃ + π: from B to A
        x = tuple(np.asarray(v, dtype=float) + 0.0 * t4 for v in (p1, p2, p3))
        _, (w1, w2, w3) = loop_jet(self.rocker, t4, x, self.coupler, t3r, self.crank, t2)  # type: ignore[arg-type]
        return wrap_pi(self.crank_offset - t2), -w1, -w2, -w3

    def _machine(self, z: np.ndarray) -> np.ndarray:
        return points(complex(*self.origin) + np.exp(1j * self.frame_angle) * z)

    def joints(self, q: Any) -> dict[str, np.ndarray]:
        """``crank_pivot`` O₂, ``crank_joint`` A, ``rocker_joint`` B, ``rocker_pivot`` O₄ and
        ``tool`` in the machine plane [mm]."""
        t2, _, t4 = self.angles(q)
        one = np.ones_like(t2)
        r = self.rocker if self.tool_radius is None else self.tool_radius
        return {"crank_pivot": self._machine(0j * one), "crank_joint": self._machine(self.crank * np.exp(1j * t2)),
                "rocker_joint": self._machine(self.ground + self.rocker * np.exp(1j * t4)),
                "rocker_pivot": self._machine(self.ground + 0j * one),
                "tool": self._machine(self.ground + r * np.exp(1j * t4))}

    def tool_point(self, q: Any) -> np.ndarray:
        """O₄ + tool_radius·e^{iθ₄} in the machine plane [mm]."""
        return self.joints(q)["tool"]

    def transmission_angle(self, q: Any) -> np.ndarray:
        """μ ∈ [0, π]: the angle at B between coupler and rocker (law of cosines:
        cos μ = (b² + c² − e²)/(2bc), e = |A − O₄|)."""
        _, t3, t4 = self.angles(q)
        return np.arccos(np.clip(np.cos(t4 - t3), -1.0, 1.0))

    def toggles(self) -> np.ndarray:
        """q where coupler and rocker are collinear (|A − O₄| = b + c or |b − c|: the driving crank
        cannot pass), from a² + d² − 2ad cos θ₂ = e²; sorted, in [−π, π)."""
        a, b, c, d = self.crank, self.coupler, self.rocker, self.ground
        return np.unique(np.round(wrap_pi(self.crank_offset - self._collinear(a, d, (b + c, abs(b - c)), -1.0)), 15))

    def tool_toggles(self) -> np.ndarray:
        """p where crank and coupler are collinear (|B − O₂| = a + b or |a − b|: the rocker's limit
        positions; driven from the rocker the linkage cannot pass), from c² + d² + 2cd cos θ₄ = f²."""
        a, b, c, d = self.crank, self.coupler, self.rocker, self.ground
        return np.unique(np.round(wrap_pi(self._collinear(c, d, (a + b, abs(a - b)), 1.0) - self.theta4_ref), 15))

    @staticmethod
    def _collinear(r: float, d: float, lengths: tuple[float, float], sign: float) -> np.ndarray:
        """The link angles [rad] where the opposite diagonal is one of ``lengths``:
        sign·(l² − r² − d²)/(2rd) = cos(angle), both roots."""
        cos = sign * (np.array(lengths) ** 2 - r * r - d * d) / (2.0 * r * d)
        cos = cos[np.abs(cos) <= 1.0]
        return np.concatenate([np.arccos(cos), -np.arccos(cos)])

    @property
    def grashof(self) -> bool:
        """Grashof's condition s + l ≤ p + q (Norton Eq. 2.8): some link turns fully."""
        links = sorted((self.ground, self.crank, self.coupler, self.rocker))
        return links[0] + links[3] <= links[1] + links[2]

    def summary(self) -> dict[str, Any]:
        """The lengths [mm], angles [deg], branch, Grashof class and the toggles [deg of q]."""
        deg = np.rad2deg
        return {"kind": self.kind, "ground": self.ground, "crank": self.crank, "coupler": self.coupler,
                "rocker": self.rocker, "crank_offset_deg": float(deg(self.crank_offset)), "branch": self.branch,
                "origin": [float(v) for v in self.origin], "frame_angle_deg": float(deg(self.frame_angle)),
                "tool_radius": self.rocker if self.tool_radius is None else self.tool_radius,
                "grashof": self.grashof, "rocker_angle_at_zero_deg": float(deg(self.theta4_ref)),
                "toggles_deg": [float(v) for v in deg(self.toggles())],
                "tool_toggles_deg": [float(v) for v in deg(self.tool_toggles())]}

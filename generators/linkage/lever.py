"""A lever of ratio r between the follower and the tool: p = r·q exactly.

On a translating follower q and p are displacements [mm]: the tool slides along the direction
``direction`` through ``pivot``, its point at pivot + p·(cos, sin)(direction).  On an oscillating
follower q and p are rotations [rad] (the tool turns r times the arm's rotation — a lever of
ratio r about its own pivot, or a gear sector): the tool's point sits at ``radius`` from
``pivot`` at the angle direction + p.  The ratio is exact in both cases (an ideal lever: a pin in
a slot on a translating follower is only approximately linear; the spec says ideal).

The drawn bar (:meth:`Lever.joints`, translating only): given the follower's line — the point
``input_point`` I₀ where the follower pushes the lever at q = 0 and its direction of motion
``input_direction`` d (:meth:`Lever.on_follower`) — and a tool line parallel to it (u = c·d,
c = ±1), the lever is ONE straight bar through three points: the input I(q) = I₀ + q·d, the fixed
fulcrum F and the tool T(q) = pivot + r·q·u.  With k = r·c, T − F = k·(I − F) for every q when
F = (pivot − k·I₀)/(1 − k): k > 1 puts F beyond the input (the tool on the far side, moving the
same way), k < 0 between input and tool (a reversing lever).  k = 1 needs no fulcrum (a rigid
rod).  The bar turns about F as it must; its ends sliding exactly along their lines is the ideal.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, ClassVar

import numpy as np

from .base import Jet, points


@dataclass(frozen=True)
class Lever:
    """p = ratio·q (``angular``: q, p in rad, else mm); ``pivot`` [mm], ``direction`` [rad]
    (the tool's line, or its arm at p = 0), ``radius`` [mm]: the tool point's distance from the
    pivot on an angular lever; ``input_point`` [mm] and ``input_direction`` [rad]: where the
    follower pushes the lever at q = 0 and its line of motion (None: not attached; drawing only,
    see the module docstring)."""

    ratio: float
    angular: bool = False
    pivot: tuple[float, float] = (0.0, 0.0)
    direction: float = 0.0
    radius: float = 0.0
    input_point: tuple[float, float] | None = None
    input_direction: float | None = None
    kind: ClassVar[str] = "lever"
    angular_input_only: ClassVar[bool] = False

    def __post_init__(self) -> None:
        if not (np.isfinite(self.ratio) and self.ratio != 0.0):
            raise ValueError(f"a lever's ratio must be finite and non-zero, got {self.ratio!r}")

    def forward(self, q: Any, q1: Any, q2: Any, q3: Any) -> Jet:
        """(r·q, r·q′, r·q″, r·q‴)."""
        r = self.ratio
        return tuple(r * np.asarray(v, dtype=float) for v in (q, q1, q2, q3))  # type: ignore[return-value]

    def inverse(self, p: Any, p1: Any, p2: Any, p3: Any) -> Jet:
        """(p/r, p′/r, p″/r, p‴/r)."""
        r = self.ratio
        return tuple(np.asarray(v, dtype=float) / r for v in (p, p1, p2, p3))  # type: ignore[return-value]

    def tool_point(self, q: Any) -> np.ndarray:
        """pivot + p·u(direction) (translating) or pivot + radius·u(direction + p) (angular) [mm]."""
        p = self.ratio * np.asarray(q, dtype=float)
        o = complex(*self.pivot)
        z = o + self.radius * np.exp(1j * (self.direction + p)) if self.angular else \
            o + p * np.exp(1j * self.direction)
        return points(z)

    def on_follower(self, origin: tuple[float, float], direction: float) -> "Lever":
        """This lever attached to a translating follower whose point is at ``origin`` [mm] at zero
        lift and moves along ``direction`` [rad]: the input point I₀ is the foot of the
        perpendicular from ``pivot`` (the tool's point at q = 0) to the follower's line, so the
        bar crosses the stem square.  The maps are unchanged; only :meth:`joints` differs."""
        o = complex(*origin)
        d = np.exp(1j * direction)
        foot = o + float(np.real((complex(*self.pivot) - o) * np.conj(d))) * d
        return replace(self, input_point=(float(foot.real), float(foot.imag)), input_direction=float(direction))

    def _bar_factor(self) -> float | None:
        """k = r·c (u = c·d) when the lever is attached and the tool's line is parallel to the
        follower's; None otherwise (angular, not attached, or the lines cross)."""
        if self.angular or self.input_point is None or self.input_direction is None:
            return None
        cross = np.sin(self.direction - self.input_direction)
        if abs(cross) > 1e-9:
            return None
        return float(self.ratio * np.sign(np.cos(self.direction - self.input_direction)))

    def joints(self, q: Any) -> dict[str, np.ndarray]:
        """[mm]: attached (:meth:`on_follower`) with the tool's line parallel to the follower's,
        ``input`` I(q) = I₀ + q·d, ``fulcrum`` F and ``tool`` — collinear, T − F = k·(I − F) (no
        ``fulcrum`` when k = 1); otherwise ``pivot`` and ``tool``."""
        tool = self.tool_point(q)
        k = self._bar_factor()
        if k is None:
            return {"pivot": np.broadcast_to(np.array(self.pivot, dtype=float), tool.shape).copy(), "tool": tool}
        assert self.input_point is not None and self.input_direction is not None
        i0 = complex(*self.input_point)
        out = {"input": points(i0 + np.asarray(q, dtype=float) * np.exp(1j * self.input_direction))}
        if abs(1.0 - k) > 1e-12:
            f = (complex(*self.pivot) - k * i0) / (1.0 - k)
            out["fulcrum"] = np.broadcast_to(np.array([f.real, f.imag]), tool.shape).copy()
        out["tool"] = tool
        return out

    def transmission_angle(self, q: Any) -> None:
        """None: a lever has no coupler."""
        return None

    def toggles(self) -> np.ndarray:
        """None exist: an empty array."""
        return np.zeros(0)

    def summary(self) -> dict[str, Any]:
        """kind, ratio, whether angular, pivot [mm], direction [deg], radius [mm]."""
        return {"kind": self.kind, "ratio": self.ratio, "angular": self.angular,
                "pivot": [float(v) for v in self.pivot], "direction_deg": float(np.rad2deg(self.direction)),
                "radius": self.radius if self.angular else None}

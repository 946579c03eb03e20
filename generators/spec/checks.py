"""The spec's `[checks]` table: :class:`ChecksSection` (limits and sampling of the design checks).
"""
from __future__ import annotations

from dataclasses import dataclass

from .params import param


@dataclass(frozen=True, kw_only=True)
class ChecksSection:
    """`[checks]`: limits and sampling of the design checks (thesis Ch. 3 and §5.3)."""

    max_pressure_angle: float = param(
        "Largest allowed magnitude of the pressure angle (thesis Eq. 3.4, 5.5; designers often allow 30°)",
        unit="angle", gt=0, lt=90, default=30.0, group="Checks")
    undercut_factor: float = param(
        "Safety factor on the roller radius: the convex pitch radius of curvature must be ≥ "
        "factor × roller radius (thesis Eq. 5.7 uses 1.5)", ge=1, default=1.5, group="Checks")
    min_force: float = param(
        "The driving force (thesis Eq. 3.5) must stay above this; 0 = no separation",
        unit="force", default=0.0, group="Checks")
    convex: bool = param(
        "The pitch curve must be convex everywhere (curvature κ = 1/ρ ≥ 0): the thesis' Eq. 5.7–5.8 "
        "read with the signed radius of curvature, whose concave parts violate 1.5·r_f − ρ ≤ 0",
        kind="bool", default=False, group="Checks")
    sampling: str = param(
        "\"dense\": `samples` equally spaced cam angles per rise/return (ends included) and "
        "refined extrema; \"thesis71\": the thesis' 71 nodes per rise/return (70 equal "
        "intervals of the B-spline parameter u; of θ for closed-form laws), no refinement",
        kind="str", choices=("dense", "thesis71"), default="dense", group="Checks")
    samples: int = param("Samples per rise or return in dense sampling (ends included)",
                         kind="int", ge=11, le=100001, default=1001, group="Checks")
    min_continuity: int | None = param(
        "Order of continuity every segment junction must reach (1 velocity, 2 acceleration, 3 jerk "
        "continuous), besides what the two laws there promise (absent: only their promise; 2 is Norton's "
        "fundamental law of cam design, which a harmonic rise next to a dwell breaks)",
        kind="int", ge=1, le=3, optional=True, group="Checks")

"""The spec's `[conjugate]` table: :class:`ConjugateSection` (the second cam and roller of a
conjugate pair).
"""
from __future__ import annotations

from dataclasses import dataclass

from .params import param


@dataclass(frozen=True, kw_only=True)
class ConjugateSection:
    """`[conjugate]`: the second cam and roller of a conjugate (dual) cam pair (cam.body = "conjugate")."""

    roller_distance: float | None = param(
        "Translating yoke: distance between the two roller centres along the follower's line of motion; the "
        "second roller sits on the other side of the cam axis", unit="length", gt=0, optional=True,
        group="Conjugate")
    arm_angle: float | None = param(
        "Oscillating arm pair: angle from the first arm to the second about the same pivot, counter-clockwise "
        "positive seen from +Z; the second arm lies on the other side of the line through the pivot and the "
        "cam axis", unit="angle", optional=True, group="Conjugate")
    arm_length: float | None = param(
        "Oscillating arm pair: length of the second arm, pivot to the second roller's centre (default: "
        "follower.arm_length)", unit="length", gt=0, optional=True, group="Conjugate")
    roller_radius: float | None = param("Radius of the second roller (default: follower.roller_radius)",
                                        unit="length", gt=0, optional=True, group="Conjugate")
    gap: float = param("Axial gap between the cams: the first cam spans 0 ≤ z ≤ cam.thickness, the second "
                       "−gap − cam.thickness ≤ z ≤ −gap; 0 (face to face) or at least 0.01 mm (0.0004 in)", unit="length", ge=0, default=0.0, group="Conjugate")
    spacer_diameter: float | None = param(
        "Diameter of the spacer that fills the gap and joins the cams into one solid (default: inside both "
        "cams' smallest radius, around the mounting holes)", unit="length", gt=0, optional=True,
        group="Conjugate")

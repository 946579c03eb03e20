"""The spec's `[groove]` table: :class:`GrooveSection` (a groove cam's groove).
"""
from __future__ import annotations

from dataclasses import dataclass

from .params import param


@dataclass(frozen=True, kw_only=True)
class GrooveSection:
    """`[groove]`: the groove of a groove (face) cam."""

    depth: float | None = param("Depth of the groove cut into the disc's top face (default: ⅔ of the "
                                "thickness)", unit="length", gt=0, optional=True, group="Groove")
    clearance: float | None = param(
        "Added to the roller's diameter: the groove width is 2·roller_radius + clearance (default 0.05 mm, "
        "0.002 in)", unit="length", ge=0, optional=True, group="Groove")
    min_wall: float | None = param(
        "Smallest material allowed between the groove and the rim, and between the groove and the bore (or hub "
        "holes) (default 3 mm, 0.12 in)", unit="length", ge=0, optional=True, group="Groove")

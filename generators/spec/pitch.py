"""The spec's `[pitch]` table: :class:`PitchSection`, the junction counts (``MAX_SEGMENTS``,
``DEFAULT_SEGMENTS``) and the rules of segments, tolerance and ``motion[].junctions``.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import SpecError, fmt_apart
from .params import param

if TYPE_CHECKING:  # types only: the spec's root imports this module
    from .model import CamSpec


#: Most junctions of a PH pitch curve (or knot spans of a B-spline one) over 360°: pitch.segments,
#: the tolerance search's M, motion[].junctions.
MAX_SEGMENTS = 20000


@dataclass(frozen=True, kw_only=True)
class PitchSection:
    """`[pitch]`: how the pitch curve is represented."""

    representation: str = param("Pitch curve representation: C² PH quintic spline (exact rational "
                                "offset) or a periodic quintic B-spline fitted to the true pitch curve (kernel offset curve)",
                                kind="str", choices=("ph", "bspline"), default="ph", group="Pitch")
    segments: int | None = param(
        "Uniform junction count M over 360° (junction spacing 360°/M; for a B-spline pitch: its "
        "knot spans); default 60 when neither segments, tolerance nor motion[].junctions is given",
        kind="int", ge=8, le=MAX_SEGMENTS, optional=True, group="Pitch",
    )
    tolerance: float | None = param(
        "Target max follower-displacement deviation: chooses the smallest uniform M (B-spline: "
        "span count) that meets it; exclusive with segments",
        unit="length", gt=0, optional=True, group="Pitch",
    )


DEFAULT_SEGMENTS = 60


def validate_pitch(spec: CamSpec) -> None:
    pt = spec.pitch
    if pt.tolerance is not None and pt.tolerance < 1e-9 * spec.cam.base_radius:
        low = 1e-9 * spec.cam.base_radius
        raise SpecError("pitch.tolerance", f"must be ≥ 1e-9 × cam.base_radius ({fmt_apart(low, pt.tolerance)}): "
                                           f"below that the deviation is rounding noise, got {fmt_apart(pt.tolerance, low)}")
    if pt.segments is not None and pt.tolerance is not None:
        raise SpecError("pitch.tolerance", "is exclusive with pitch.segments: give one of them")
    if pt.representation == "bspline" and spec.motion[0].junctions is not None:
        raise SpecError("motion[0].junctions", 'sets PH junctions; not used with pitch.representation = "bspline"')
    if spec.motion[0].junctions is not None:
        total = sum(seg.junctions or 0 for seg in spec.motion)
        if pt.tolerance is not None:
            raise SpecError("pitch.tolerance", "is exclusive with motion[].junctions")
        if pt.segments is not None and pt.segments != total:
            raise SpecError("pitch.segments",
                            f"is {pt.segments} but motion[].junctions sum to {total}: give one of them")
        if total < 8:
            raise SpecError("motion[].junctions", f"sum to {total}, must be ≥ 8")

"""Pitch curves: the C² PH quintic spline (:mod:`.ph`), the periodic B-spline (:mod:`.bspline`),
what both answer alike — lift, deviation, contact angles (:mod:`.queries`) — and the
follower-path contact solve (:mod:`.contact`).  ``cam_workbench.generators.pitch`` re-exports
:mod:`cam_workbench.generators.pitch.ph`.
"""
from .ph import (  # noqa: F401
    TWO_PI, DEFAULT_STEP_DEG, MAX_TOLERANCE_SEGMENTS, junction_angles, PitchCurve,
    build_pitch_for_segments, segments_for_tolerance, build_pitch,
)

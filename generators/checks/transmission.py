"""The transmission-angle check of a four-bar between the follower and the tool ([linkage],
docs/linkages.md): the smallest effective transmission angle min(μ, 180° − μ) over the cam turn
must stay at or above ``linkage.min_transmission_angle`` (default 40°; Norton, *Design of
Machinery*, §3.3).  A linkage without a coupler (a lever) adds no check."""
from __future__ import annotations

from typing import Any

import numpy as np

from ..linkage.drive import transmission_extreme
from ..motion.program import MotionProgram
from ..spec.linkage import linkage_of
from ..spec.model import CamSpec

DESCRIPTION = "smallest transmission angle min(μ, 180° − μ) of the four-bar to the tool (Norton §3.3)"


def linkage_checks(spec: CamSpec, program: MotionProgram, theta: np.ndarray,
                   segment: np.ndarray | None = None) -> list[dict[str, Any]]:
    """The linkage's checks at the sample cam angles ``theta`` [rad] (refined), each as the fields
    of a :class:`~.design.CheckResult` (name, description, kind, value, at_deg, limit, unit,
    status): [] without a linkage or without a coupler."""
    drive = linkage_of(spec)
    if drive is None:
        return []
    ext = transmission_extreme(drive.linkage, program, theta, drive.scale, segment)
    if ext is None:
        return []
    value, at = ext
    lim = drive.min_transmission_deg
    return [{"name": "transmission_angle", "description": DESCRIPTION, "kind": "min", "value": value,
             "at_deg": at, "limit": lim, "unit": "deg", "status": "pass" if value >= lim else "fail"}]

"""A field to search when a check fails (the remedies' search plan): plain data the kinds hand
the remedies (:mod:`cam_workbench.generators.studies.remedies`) — a body or a follower kind says
which of its fields move which check (``remedy_plans``)."""
from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Plan:
    """One field to search for a check: ``search`` "smallest" (the sizing bisection), "nearest"
    (both sides of the spec's value, short of ``bounds``) or "needed" (the check's value)."""

    field: str
    search: str
    evaluation: str = "checks"              # "checks" | "design" | "body" (the body's own checks)
    bounds: tuple[float, float] = (-math.inf, math.inf)

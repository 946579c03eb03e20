"""Machining: the plan (:mod:`.plan`), the rotational PH interpolator (:mod:`.interpolator`),
exact tool paths (:mod:`.toolpath`) and the thesis' cutting time (:mod:`.cutting_time`).
``cam_workbench.generators.machining`` re-exports :mod:`cam_workbench.generators.machining.plan`.
"""
from .plan import (  # noqa: F401
    MachiningPlan, smallest_concave_profile_radius, check_tool_fits, machining_plan,
)
from . import groove as _groove_path  # noqa: F401,E402  (registers the groove's tool path)

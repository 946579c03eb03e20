"""Motion design: the closed-form laws, the B-spline lift law and the motion program.
``cam_workbench.generators.motion`` re-exports :mod:`cam_workbench.generators.motion.program`.
"""
from .program import (  # noqa: F401
    TWO_PI, Kinematics, MotionProgram, wrap_angle,
)

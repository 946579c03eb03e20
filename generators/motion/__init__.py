"""Motion design: the closed-form laws, the B-spline lift law and the motion program.
``generators.motion`` re-exports :mod:`generators.motion.program`.
"""
from .program import (  # noqa: F401
    TWO_PI, Kinematics, MotionProgram, wrap_angle,
)

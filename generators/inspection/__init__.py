"""Inspection of a made cam: measured profile points registered to the exact profile, their normal
deviations and profile-tolerance verdict (ISO 1101), and the follower's motion on the measured part
(docs/inspection.md)."""
from .deviation import VERDICTS, Deviations, profile_verdict
from .measured_motion import MeasuredMotion, SmoothedDeviation, measured_motion, smooth_deviation
from .part import InspectionResult, inspect_design
from .registration import DATUMS, ProfileProjector, Registration, register

__all__ = ["DATUMS", "VERDICTS", "Deviations", "InspectionResult", "MeasuredMotion", "ProfileProjector",
           "Registration", "SmoothedDeviation", "inspect_design", "measured_motion", "profile_verdict", "register",
           "smooth_deviation"]

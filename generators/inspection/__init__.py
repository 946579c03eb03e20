"""Inspection of a made cam: measured profile points registered to the exact profile, their normal
deviations and profile-tolerance verdict (ISO 1101), the follower's motion on the measured part,
and the deviation's harmonics with the acceleration error each predicts (the tolerance study's
reverse; docs/inspection.md)."""
from .deviation import VERDICTS, Deviations, profile_verdict
from .harmonics import DeviationHarmonics, deviation_harmonics
from .measured_motion import MeasuredMotion, SmoothedDeviation, measured_motion, smooth_deviation
from .part import InspectionResult, inspect_design
from .registration import DATUMS, ProfileProjector, Registration, register

__all__ = ["DATUMS", "VERDICTS", "DeviationHarmonics", "Deviations", "InspectionResult", "MeasuredMotion",
           "ProfileProjector", "Registration", "SmoothedDeviation", "deviation_harmonics", "inspect_design",
           "measured_motion", "profile_verdict", "register", "smooth_deviation"]

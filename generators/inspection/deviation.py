"""The normal deviation of a measured profile and its profile-of-a-line verdict (ISO 1101).

The deviation of a point is its signed distance from the exact profile along the profile's
outward normal at the foot point: + where the point lies outside the designed boundary (material
left on), − inside (material removed).  A profile tolerance t (ISO 1101, profile of a line) puts
every point of the measured line inside the zone between two lines ±t/2 about the exact profile
(the zone is uniform and centred on the true profile: no UZ or OZ modifiers).

With ``datum = "none"`` the zone floats (a form tolerance): the pose is the robust least-squares
fit of :mod:`.registration`, not the minimum-zone fit of ISO 1101's form evaluation.  A minimum
zone can only be narrower, so a "pass" here is a pass by the standard too, and a "fail" by a margin
below that difference could pass a minimum-zone evaluation: the verdict is conservative.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import SpecError

#: the verdicts (:func:`profile_verdict`)
VERDICTS = ("pass", "pass_excluding_outliers", "fail")


@dataclass(frozen=True)
class Deviations:
    """The measured points' deviations from the exact profile.

    Attributes:
        value: (N,) signed normal deviation [spec length], + material outside.
        cam_angle_deg: (N,) the cam angle [deg, 0..360) at which the follower touches each foot point.
        outliers: (N,) bool: flagged by the registration's robust fit.
    """

    value: np.ndarray
    cam_angle_deg: np.ndarray
    outliers: np.ndarray

    @property
    def inliers(self) -> np.ndarray:
        return ~self.outliers

    def summary(self) -> dict[str, Any]:
        """Largest and smallest deviation (with their cam angles), mean, RMS and the range, over
        every point and over the inliers (spec lengths; angles in degrees)."""
        return {"all_points": _stats(self.value, self.cam_angle_deg),
                "inliers": _stats(self.value[self.inliers], self.cam_angle_deg[self.inliers])}


def _stats(d: np.ndarray, at: np.ndarray) -> dict[str, Any]:
    if d.size == 0:
        return {"count": 0}
    i, j, k = int(np.argmax(d)), int(np.argmin(d)), int(np.argmax(np.abs(d)))
    return {"count": int(d.size), "max": float(d[i]), "max_at_deg": float(at[i]), "min": float(d[j]),
            "min_at_deg": float(at[j]), "max_abs": float(abs(d[k])), "max_abs_at_deg": float(at[k]),
            "mean": float(np.mean(d)), "rms": float(np.sqrt(np.mean(d * d))), "range": float(d[i] - d[j])}


def check_tolerance(tolerance: float) -> float:
    """``tolerance`` as a float.

    Raises:
        SpecError: it is not a positive finite length.
    """
    t = float(tolerance)
    if not (np.isfinite(t) and t > 0):
        raise SpecError("tolerance", f"the profile tolerance must be a positive length, got {tolerance!r}")
    return t


def profile_verdict(dev: Deviations, tolerance: float) -> dict[str, Any]:
    """The profile-of-a-line verdict for tolerance ``tolerance`` (the zone's full width t): "pass"
    when every point lies within ±t/2; "pass_excluding_outliers" when only points the registration
    flagged as outliers lie outside (they may be dust or probe errors — or a defect: look at them);
    "fail" when an inlier lies outside.

    Raises:
        SpecError: ``tolerance`` is not a positive number.
    """
    half = 0.5 * check_tolerance(tolerance)
    outside = np.abs(dev.value) > half
    inliers_out = int(np.count_nonzero(outside & dev.inliers))
    all_out = int(np.count_nonzero(outside))
    verdict = "pass" if all_out == 0 else "pass_excluding_outliers" if inliers_out == 0 else "fail"
    return {"tolerance": float(tolerance), "zone": [-half, half], "verdict": verdict,
            "outside": all_out, "outside_inliers": inliers_out,
            "used": float(np.max(np.abs(dev.value)) / half),
            "used_by_inliers": float(np.max(np.abs(dev.value[dev.inliers])) / half) if dev.inliers.any() else None}

"""The inspection of a made cam: measured profile points registered to the design, their normal
deviations and profile-tolerance verdict, the follower's motion on the measured part, and the
deviation's harmonics with the acceleration error each predicts (:func:`inspect_design`; the
modules of this package say how each is found).

Which profile: a plane cam's ``design.profile`` — a plate cam's outline; for a groove cam the
profile NURBS is the groove's inner wall and for a conjugate pair the first cam's profile, and the
follower's motion is computed as on that one curve (the roller centre at the design's profile
inset from it).  A design without a plane profile (cylindrical cams, indexers) is refused.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import SpecError
from ..tolerance.study import check_acceleration_limit
from .deviation import Deviations, check_tolerance, profile_verdict
from .harmonics import DeviationHarmonics, deviation_harmonics
from .measured_motion import DEFAULT_WAVELENGTH_DEG, MeasuredMotion, contact_angles, measured_motion, smooth_deviation
from .registration import ProfileProjector, Registration, register


@dataclass(frozen=True)
class InspectionResult:
    """A measured part against its design (spec units; angles in degrees in :meth:`summary`).

    Attributes:
        design: the design (a plane cam's :class:`~cam_workbench.generators.cam_design.CamDesign`).
        measured: (N, 2) the points as given (the measuring frame; z dropped).
        z: (N,) their z, or None.
        registration: the pose and the robust fit.
        deviations: signed normal deviations, contact angles, outlier flags.
        motion: the follower's motion on the measured part.
        harmonics: the smoothed deviation's harmonics over the cam angle and the acceleration error
            they predict (the tolerance study's reverse), with its tolerance at the user's limit.
        tolerance: the profile tolerance t, or None (no verdict).
    """

    design: Any
    measured: np.ndarray
    z: np.ndarray | None
    registration: Registration
    deviations: Deviations
    motion: MeasuredMotion
    harmonics: DeviationHarmonics
    tolerance: float | None

    @property
    def verdict(self) -> dict[str, Any] | None:
        """The profile-of-a-line verdict (:func:`.deviation.profile_verdict`), None without a tolerance."""
        return None if self.tolerance is None else profile_verdict(self.deviations, self.tolerance)

    def summary(self) -> dict[str, Any]:
        """Every number of inspection.json (without the ``files`` section)."""
        design = self.design
        reg = self.registration
        lift_unit = "deg" if design.follower.lift_unit == "angle" else design.spec.units
        points: dict[str, Any] = {"count": int(len(self.measured)), "z_given": self.z is not None}
        if self.z is not None:
            points |= {"z_min": float(np.min(self.z)), "z_max": float(np.max(self.z))}
        return {
            "units": design.spec.units,
            "cam": design.label(),
            "points": points,
            "registration": {
                "datum": reg.datum,
                "rotation_deg": float(np.rad2deg(reg.rotation)), "rotation_rad": reg.rotation,
                "shift_x": float(reg.shift.real), "shift_y": float(reg.shift.imag),
                "rotation_std_deg": None if reg.std[0] is None else float(np.rad2deg(reg.std[0])),
                "shift_std_x": reg.std[1], "shift_std_y": reg.std[2],
                "iterations": reg.iterations, "converged": reg.converged, "scale": reg.scale,
                "projection_iterations": reg.projection.iterations,
                "outliers": int(np.count_nonzero(reg.outliers)),
                "outlier_indices": [int(i) for i in np.flatnonzero(reg.outliers)],
            },
            "deviation": self.deviations.summary(),
            "tolerance": self.verdict,
            "motion": self.motion.summary(lift_unit),
            "harmonics": self.harmonics.summary(),
        }


def refuse_without_profile(design: Any) -> None:
    """A design without a plane profile cannot be inspected here (SpecError naming cam.body)."""
    if not design.plane:
        raise SpecError("cam.body", f"inspection measures a plane cam's profile; a {design.spec.cam.body} cam has "
                                    f"none: {design.instead_of_plane_curves}")


def checked_points(points: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """(x + iy, z or None) of an (N, 2) or (N, 3) array of finite numbers.

    Raises:
        SpecError: another shape, a value not finite, or fewer than 3 points.
    """
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise SpecError("points", f"must be an (N, 2) or (N, 3) array of x, y[, z], got shape {pts.shape}")
    if not np.all(np.isfinite(pts)):
        raise SpecError("points", f"point {int(np.argwhere(~np.isfinite(pts))[0, 0])} is not finite")
    if len(pts) < 3:
        raise SpecError("points", f"{len(pts)} points: at least 3 are needed")
    return pts[:, 0] + 1j * pts[:, 1], (pts[:, 2] if pts.shape[1] == 3 else None)


def inspect_design(design: Any, points: np.ndarray, *, tolerance: float | None = None, datum: str = "none",
                   wavelength_deg: float = DEFAULT_WAVELENGTH_DEG,
                   acceleration_limit: float | None = None) -> InspectionResult:
    """Inspect a made cam from measured profile points.

    Args:
        design: the designed cam (``design_cam(spec)``).
        points: (N, 2) or (N, 3) measured x, y[, z] in the spec's units, in any frame for
            ``datum = "none"``; with the bore's axis at the origin for "bore"; in the part's frame for
            "bore_and_angle" (:mod:`.registration`).
        tolerance: the profile tolerance t (zone ±t/2), or None for no verdict.
        datum: "none", "bore" or "bore_and_angle".
        wavelength_deg: the shortest wave of the deviation the motion follows [deg].
        acceleration_limit: the allowed acceleration error as a fraction of the designed peak
            (0.05 for 5 %): the tolerance study's chart at ``cam.speed_rpm`` joins the harmonics;
            None: no chart.

    Raises:
        SpecError: no plane profile, bad points, datum, tolerance, wavelength or acceleration limit.
    """
    refuse_without_profile(design)
    m, z = checked_points(points)
    if tolerance is not None:
        tolerance = check_tolerance(tolerance)
    if acceleration_limit is not None:
        check_acceleration_limit(acceleration_limit)
    projector = ProfileProjector(design.profile)
    reg = register(projector, m, datum)
    pr = reg.projection
    dev = Deviations(pr.distance, np.rad2deg(contact_angles(design, pr.u)), reg.outliers)
    keep = ~reg.outliers
    smooth = smooth_deviation(pr.u[keep], pr.distance[keep], projector.lo, projector.period, design.pitch.M,
                              wavelength_deg)
    motion = measured_motion(design, projector, smooth)
    harmonics = deviation_harmonics(design, smooth, acceleration_limit)
    return InspectionResult(design, np.column_stack([m.real, m.imag]), z, reg, dev, motion, harmonics, tolerance)

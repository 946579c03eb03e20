"""What every pitch curve answers the same way, whatever its representation (the PH spline of
:mod:`.ph`, the fitted periodic B-spline of :mod:`.bspline`): the follower's lift on the built
curve and its deviation from the motion (the paper's accuracy measure, Eq. 13), and the cam angle
at which a point of the curve touches the follower.

A representation supplies ``M`` (segments or knot spans), ``program``, ``follower``, ``spline``
(points and derivatives at segment k, ξ ∈ [0, 1]), ``segments`` and ``solver_angles`` (the
Bézier segments the contact solve runs on, and the cam angles bounding them) and ``contact(θ)``.
"""
from __future__ import annotations

from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:                    # annotations only: the representations import these themselves
    from ..followers import Follower
    from ..motion.program import MotionProgram
    from .contact import Contact, FollowerLineSolver

TWO_PI = 2.0 * np.pi
#: the deviation's default sample spacing [deg]
DEFAULT_STEP_DEG = 0.02


class PitchQueries:
    """The members a pitch curve shares with every other representation (a base class of the
    frozen dataclasses :class:`~.ph.PitchCurve` and :class:`~.bspline.BSplinePitchCurve`)."""

    program: MotionProgram
    follower: Follower

    @property
    def geometry(self) -> Follower:
        """The follower (the name before the follower interface)."""
        return self.follower

    def contact(self, theta: np.ndarray) -> Contact:
        """Eq. 13 at cam angles θ [rad]: each representation solves it on its own curve."""
        raise NotImplementedError

    def solver(self) -> FollowerLineSolver:
        """Eq. 13 solver (generalised to the follower kind) on :attr:`segments`."""
        return self.follower.contact_solver(self.segments, self.solver_angles)  # type: ignore[attr-defined]

    def actual_displacement(self, theta: np.ndarray) -> np.ndarray:
        """s_actual(θ): the lift the built curve gives the follower [spec lift units]."""
        return self.contact(theta).lift

    def sampled_displacement(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """(θ = 2π k/n [rad], s_actual(θ)) at ``n`` equally spaced angles, solved once per curve and
        count (read only): the design's deviation, its checks and a conjugate pair's roller distance
        error read the same solve."""
        if n not in self._displacements:
            th = TWO_PI * np.arange(n) / n
            lift = self.actual_displacement(th)
            th.flags.writeable = lift.flags.writeable = False      # shared: read only
            self._displacements[n] = (th, lift)
        return self._displacements[n]

    @cached_property
    def _displacements(self) -> dict[int, tuple[np.ndarray, np.ndarray]]:
        return {}

    def deviation_count(self, step_deg: float = DEFAULT_STEP_DEG) -> int:
        """Number of equally spaced deviation samples over 360°: every ``step_deg``, ≥ 8 per
        segment (PH segment or knot span)."""
        return max(int(np.ceil(360.0 / step_deg - 1e-9)), 8 * self.M)  # type: ignore[attr-defined]

    def deviation(self, step_deg: float = DEFAULT_STEP_DEG, n: int | None = None
                  ) -> tuple[np.ndarray, np.ndarray]:
        """(θ samples [rad], s_actual − s) over the cycle, at ``n`` equally spaced angles
        (default from ``step_deg``)."""
        th, lift = self.sampled_displacement(n or self.deviation_count(step_deg))
        return th, lift - self.program.s(th)

    def max_deviation(self, step_deg: float = DEFAULT_STEP_DEG, n: int | None = None
                      ) -> tuple[float, float]:
        """(max |s_actual − s|, cam angle in degrees where it occurs)."""
        th, dev = self.deviation(step_deg, n)
        k = int(np.argmax(np.abs(dev)))
        return float(abs(dev[k])), float(np.rad2deg(th[k]))

    def cam_angle_of_point(self, pts: np.ndarray, tangents: np.ndarray | None = None) -> np.ndarray:
        """Cam angle [deg, 0..360) at which a point of the curve (complex, cam frame; with its
        tangent in the direction of increasing θ for a flat face) touches the follower, in
        closed form (:meth:`Follower.cam_angle_of`)."""
        if tangents is None:
            if self.follower.design_curve != "pitch":
                raise ValueError("a flat face's contact angle needs the curve's tangent too")
            tangents = np.ones_like(pts)
        return np.mod(np.rad2deg(self.follower.cam_angle_of(pts, tangents)), 360.0)

    def cam_angle_at(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        """Cam angle [deg, 0..360) at which the curve's point (segment, ξ) touches the follower."""
        spline = self.spline  # type: ignore[attr-defined]
        return self.cam_angle_of_point(spline.point(seg, xi), spline.first_derivative(seg, xi))

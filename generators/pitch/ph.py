"""The PH pitch curve of a spec: junction angles and points (paper Eq. 9–11), the
closed C² PH quintic spline through them, and its accuracy against the motion.

Accuracy is the paper's measure: ``max_deviation`` = max over θ of
|s_actual(θ) − s(θ)|, where s_actual comes from the follower line meeting the
built curve (Eq. 13), sampled at least every 0.1° (default 0.02°, and at least
8 samples per PH segment).
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Callable

import numpy as np

from ..errors import SpecError
from ..followers.base import Follower
from ..kinds import follower_of, register_pitch
from .contact import Contact
from ..motion.program import MotionProgram
from ..curves.ph_spline import PHSpline, solve_closed_ph_spline
from ..spec.model import CamSpec
from ..spec.pitch import DEFAULT_SEGMENTS, MAX_SEGMENTS
from .queries import DEFAULT_STEP_DEG, PitchQueries

TWO_PI = 2.0 * np.pi
MAX_TOLERANCE_SEGMENTS = MAX_SEGMENTS


def junction_angles(spec: CamSpec, segments: int | None = None) -> np.ndarray:
    """Junction cam angles θ_0 = 0 < θ_1 < … < θ_{M−1} [rad] (θ_M = 2π closes the curve).

    Uniform (paper Eq. 11) with ``segments`` or ``pitch.segments``; otherwise per motion
    segment from ``motion[].junctions`` (the paper's non-uniform case 3).
    """
    if segments is None and spec.motion[0].junctions is not None:
        prog = MotionProgram.from_spec(spec)
        parts = [prog.starts[k] + prog.spans[k] * np.arange(seg.junctions) / seg.junctions
                 for k, seg in enumerate(spec.motion)]
        return np.concatenate(parts)
    m = segments or spec.pitch.segments or DEFAULT_SEGMENTS
    return TWO_PI * np.arange(m) / m


@register_pitch
@dataclass(frozen=True)
class PitchCurve(PitchQueries):
    """A solved PH design curve (the pitch curve of a knife edge or roller, the profile of a
    flat face) with everything needed to query it."""

    spline: PHSpline
    angles: np.ndarray            # junction angles [rad]
    program: MotionProgram
    follower: Follower
    #: pitch.representation
    representation = "ph"
    #: exact rational offsets: the profile is the pitch curve's exact offset, its arc length closed form
    exact = True
    #: the representation in words
    words = "PH quintic spline"

    @property
    def M(self) -> int:
        return self.spline.M

    @property
    def segments(self) -> PHSpline:
        """The curve as Bézier segments bounded by :attr:`angles` (here the PH spline itself)."""
        return self.spline

    @property
    def junction_parameters(self) -> np.ndarray:
        """Parameters of the junction points on the neutral curves (segment k starts at k)."""
        return np.arange(self.M, dtype=float)

    @property
    def exact_offsets(self) -> bool:
        """Offsets of this curve are exact rational NURBS (PH: yes)."""
        return True

    @cached_property
    def solver_angles(self) -> np.ndarray:
        """(M,) cam angles [rad] at which the follower touches the junction points, kept within
        half a turn of the junction angles: the junction angles themselves for a knife edge or a
        roller (the junction points lie on the follower's path); for a flat face the angles at
        which the face meets the built curve's tangent there (the spline interpolates the contact
        points, not their tangents, so these differ from :attr:`angles` by the curve's error)."""
        m = self.M
        q = self.spline.point(np.arange(m), np.zeros(m))
        dq = self.spline.first_derivative(np.arange(m), np.zeros(m))
        cross = self.follower.cam_angle_of(q, dq)
        b = self.angles
        return b + (np.mod(cross - b + np.pi, TWO_PI) - np.pi)

    def contact(self, theta: np.ndarray) -> Contact:
        """Eq. 13 solution at cam angles θ [rad]."""
        return self.solver().solve(theta)



def build_pitch_curve(program: MotionProgram, follower: Follower, angles: np.ndarray) -> PitchCurve:
    """The closed C² PH spline through the follower's design points at the junction ``angles``
    [rad] (paper Eq. 9–11), as a :class:`PitchCurve` — from plain values, no spec: the pitch curve
    of any follower (the second roller of a conjugate pair too)."""
    angles = np.asarray(angles, dtype=float)
    q = follower.points(angles, program.evaluate(angles))
    return PitchCurve(solve_closed_ph_spline(q), angles, program, follower)


def build_pitch_for_segments(spec: CamSpec, segments: int | None = None,
                             follower: Follower | None = None) -> PitchCurve:
    """The PH pitch curve with a given uniform M (or the spec's junctions); ``follower``: another
    follower than the spec's own (the second roller of a conjugate pair)."""
    return build_pitch_curve(MotionProgram.from_spec(spec), follower or follower_of(spec),
                             junction_angles(spec, segments))


def segments_for_tolerance(
    spec: CamSpec, tolerance: float, *, step_deg: float = DEFAULT_STEP_DEG,
    progress: Callable[[int, float], None] | None = None, follower: Follower | None = None,
) -> tuple[PitchCurve, float, float]:
    """Smallest uniform M ≥ 8 whose max deviation is ≤ ``tolerance``.

    Deviation is not monotonic in M (junctions that fall on motion-segment boundaries
    help), so every M is tried in increasing order; a coarse screen on every 5th of the
    final samples (so its maximum can only be lower) rejects most M cheaply and only
    survivors are checked on all samples.

    Returns:
        (pitch curve, its max deviation, cam angle [deg] of the max).

    Raises:
        SpecError: no M up to 20000 meets the tolerance.
    """
    for m in range(8, MAX_TOLERANCE_SEGMENTS + 1):
        pc = build_pitch_for_segments(spec, m, follower)
        n_coarse = -(-pc.deviation_count(step_deg) // 5)
        coarse, _ = pc.max_deviation(n=n_coarse)
        if progress is not None:
            progress(m, coarse)
        if coarse > tolerance:
            continue
        dev, at = pc.max_deviation(n=5 * n_coarse)
        if dev <= tolerance:
            return pc, dev, at
    raise SpecError("pitch.tolerance",
                    f"no uniform segment count up to {MAX_TOLERANCE_SEGMENTS} reaches {tolerance:g}")


def build_pitch(spec: CamSpec, progress: Callable[[int, float], None] | None = None) -> PitchCurve:
    """The spec's PH pitch curve: by ``pitch.tolerance``, ``pitch.segments``, junctions, or M = 60."""
    if spec.pitch.tolerance is not None:
        return segments_for_tolerance(spec, spec.pitch.tolerance, progress=progress)[0]
    return build_pitch_for_segments(spec)

"""The follower motion program s(θ): dwells, rises and returns, multi-level.

θ is the cam angle in **radians** from the program start, taken modulo 2π;
s is in spec length units; s', s'', s''' are derivatives with respect to θ
(length/rad, length/rad², length/rad³) — the thesis' "reduced" quantities.
Multiply by ω, ω², ω³ (rad/s) for true velocity, acceleration and jerk.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, Any

import numpy as np

from ..kinds import body_of
from .bspline_law import BSplineLift
from .characteristics import law_characteristics
from .laws import CLOSED_FORM_LAWS, LawName, NormalisedLaw, evaluate_law
from .vdi2143 import classify_program
from .segments import build_segments, law_promise

if TYPE_CHECKING:  # types only: the spec sits above the motion program
    from ..spec.model import CamSpec
    from ..spec.motion import MotionSegment

TWO_PI = 2.0 * np.pi


@dataclass(frozen=True)
class Kinematics:
    """s and its first three θ-derivatives at a set of cam angles (arrays of equal shape)."""

    theta: np.ndarray
    s: np.ndarray
    ds: np.ndarray
    d2s: np.ndarray
    d3s: np.ndarray


@dataclass(frozen=True)
class MotionProgram:
    """A motion program over one cam turn: segment start angles (rad), spans (rad), start levels,
    kinds.  It closes (s(2π) = s(0)) or, for an indexer's turret, advances: s(2π) = s(0) +
    ``advance`` (the turret's turn per index), the next turn starting where this one ends.

    Build it with :meth:`from_spec` (or :meth:`from_segments`).
    """

    starts: np.ndarray   # (n,) segment start angles [rad]
    spans: np.ndarray    # (n,) segment spans [rad]
    levels: np.ndarray   # (n,) s at the start of each segment
    lifts: np.ndarray    # (n,) signed lift: +h rise, −h return, 0 dwell
    laws: tuple[str | None, ...]
    kinds: tuple[str, ...]
    #: per segment: the B-spline lift of a law = "bspline" segment (thesis §2.6) and of the laws
    #: solved from boundary conditions or fitted (polynomial, constant_velocity, table:
    #: :mod:`cam_workbench.generators.motion.segments`, θ(u) linear), else None
    curves: tuple[BSplineLift | None, ...] = ()
    #: per segment: the order of continuity its (start, end) promise (:func:`law_promise`);
    #: empty: derived from the laws
    promises: tuple[tuple[int, int], ...] = ()
    #: per segment: what a solved law came out as (polynomial degree and coefficients, cruise
    #: velocity, table fit error), else None
    infos: tuple[dict[str, Any] | None, ...] = ()
    #: s(2π) − s(0) in lift units: 0 for a cam's follower, 360/N for an indexer's turret
    advance: float = 0.0

    @classmethod
    def from_spec(cls, spec: CamSpec) -> "MotionProgram":
        """The program of a validated spec (advancing by what its body declares:
        ``Body.motion_advance``); with ``[linkage] motion_at = "tool"`` the follower's program the
        inverse linkage derives from the tool's (``LinkageSection.program_of``)."""
        return spec.linkage.program_of(spec, cls.from_segments(spec.motion, body_of(spec).motion_advance(spec)))

    @classmethod
    def from_segments(cls, segments: tuple[MotionSegment, ...] | list[MotionSegment],
                      advance: float = 0.0) -> "MotionProgram":
        """The program of the motion segments advancing by ``advance`` per turn (solved once per
        distinct program: cached).

        Raises:
            SpecError: a segment that cannot be solved (see :func:`build_segments`)."""
        return _program(tuple(segments), float(advance))

    @classmethod
    def _build(cls, segments: tuple[MotionSegment, ...], advance: float = 0.0) -> "MotionProgram":
        spans_deg = np.array([s.angle for s in segments], dtype=float)
        # Close exactly: spans are validated to sum to 360 within 1e-9°.
        spans = np.deg2rad(spans_deg) * (TWO_PI / np.deg2rad(spans_deg.sum()))
        starts = np.concatenate([[0.0], np.cumsum(spans)[:-1]])
        signed = np.array([
            (s.lift or 0.0) * (1 if s.kind == "rise" else -1 if s.kind == "return" else 0)
            for s in segments
        ])
        levels = np.concatenate([[0.0], np.cumsum(signed)[:-1]])
        built = build_segments(segments, starts, spans, levels, signed)
        return cls(starts, spans, levels, signed, built.laws,
                   tuple(s.kind for s in segments), built.curves, built.promises, built.infos, advance)

    def promise(self, k: int) -> tuple[int, int]:
        """(start, end) order of continuity segment ``k``'s law promises."""
        if self.promises:
            return self.promises[k]
        return law_promise(self.laws[k], self.curves[k] if self.curves else None)

    def junctions(self) -> list["Junction"]:
        """Every segment boundary (the last segment's end meets the first's start at 0°, less the
        ``advance``): the one-sided s, s′, s″, s‴ on both sides, their jumps, the order of
        continuity reached and the order the two laws promise."""
        n = len(self.starts)
        right_seg = np.arange(n)
        left_seg = (right_seg - 1) % n
        kl = self.evaluate(np.where(right_seg == 0, TWO_PI, self.starts), left_seg)
        kr = self.evaluate(self.starts, right_seg)
        left = np.stack([kl.s - np.where(right_seg == 0, self.advance, 0.0), kl.ds, kl.d2s, kl.d3s], axis=1)
        right = np.stack([kr.s, kr.ds, kr.d2s, kr.d3s], axis=1)
        jump = right - left
        # a jump counts when above 1e-6 of the larger side or of the adjacent segments' scale |h|/β^n
        ref = np.zeros((n, 4))
        for side in (left_seg, right_seg):
            h = np.abs(self.lifts[side])
            beta = self.spans[side]
            ref = np.maximum(ref, h[:, None] / beta[:, None] ** np.arange(4)[None, :])
        tol = 1e-6 * np.maximum(np.maximum(np.abs(left), np.abs(right)), ref)
        ok = np.abs(jump) <= tol
        out = []
        for j in range(n):
            a, b = int(left_seg[j]), int(right_seg[j])
            reached = -1
            for order in range(4):
                if not ok[j, order]:
                    break
                reached = order
            promised = min(self.promise(a)[1], self.promise(b)[0])
            out.append(Junction(j, a, b, float(np.rad2deg(self.starts[j])), self.laws[a], self.laws[b],
                                tuple(float(v) for v in left[j]), tuple(float(v) for v in right[j]),
                                tuple(float(v) for v in jump[j]), reached, promised))
        return out

    @property
    def boundaries(self) -> np.ndarray:
        """Segment boundary angles [rad], from 0 to 2π inclusive."""
        return np.concatenate([self.starts, [TWO_PI]])

    def segment_of(self, theta: np.ndarray) -> np.ndarray:
        """Index of the motion segment containing each θ (θ reduced modulo 2π)."""
        t = wrap_angle(theta)
        return np.minimum(np.maximum(np.searchsorted(self.starts, t, side="right") - 1, 0), len(self.starts) - 1)

    def evaluate(self, theta: np.ndarray | float, segment: np.ndarray | None = None) -> Kinematics:
        """s, s', s'', s''' at cam angles ``theta`` [rad] (any shape), exactly: closed forms, or the
        B-spline law's parametric formulas (thesis Eq. 2.37–2.39) at the inverted θ(u).

        ``segment`` (same shape, optional) evaluates each θ with that motion segment's law —
        the one-sided value at a segment end, where a law's jerk (or a harmonic's
        acceleration) jumps; by default the segment containing θ is used."""
        theta = np.asarray(theta, dtype=float)
        t = wrap_angle(theta)
        idx = self.segment_of(t) if segment is None else np.asarray(segment)
        if segment is not None:
            # θ = 2π at the end of the last segment must not wrap to 0
            t = np.where((idx == len(self.starts) - 1) & (t < self.starts[-1]), t + TWO_PI, t)
        s = self.levels[idx].astype(float).copy()
        ds = np.zeros_like(t)
        d2s = np.zeros_like(t)
        d3s = np.zeros_like(t)
        for k, law in enumerate(self.laws):
            if law is None:
                continue
            m = idx == k
            if not m.any():
                continue
            beta = self.spans[k]
            h = self.lifts[k]  # signed: a return is s = level − h·f
            curve = self.curves[k] if self.curves else None
            if curve is not None:
                # y runs 0 → 1 on a rise, 1 → 0 on a return: f = y or 1 − y; derivatives per rad
                y, y1, y2, y3 = curve.evaluate(np.minimum(np.maximum(t[m] - self.starts[k], 0.0), beta))
                sign = 1.0 if h > 0 else -1.0
                s[m] += h * (y if h > 0 else 1.0 - y)
                ds[m] = sign * h * y1
                d2s[m] = sign * h * y2
                d3s[m] = sign * h * y3
                continue
            # np.minimum/np.maximum: np.clip's dispatch costs more than the clipping on small arrays
            x = np.minimum(np.maximum((t[m] - self.starts[k]) / beta, 0.0), 1.0)
            f, f1, f2, f3 = evaluate_law(law, x)
            s[m] += h * f
            ds[m] = h * f1 / beta
            d2s[m] = h * f2 / beta**2
            d3s[m] = h * f3 / beta**3
        return Kinematics(theta, s, ds, d2s, d3s)

    def report(self) -> dict[str, Any]:
        """report.json's ``motion.segments`` (each segment's span, levels, promised continuity, what
        a solved law came out as and, for a rise or return, its law's characteristic values
        ``characteristics`` (:meth:`~.characteristics.LawCharacteristics.summary`) and VDI 2143
        motion task ``vdi2143`` (:func:`~.vdi2143.classify_program`)) and ``motion.junctions``
        (:meth:`junctions`)."""
        segs = []
        tasks = classify_program(self)
        for k in range(len(self.starts)):
            entry: dict[str, Any] = {
                "index": k, "kind": self.kinds[k], "law": str(self.laws[k] or "dwell"),
                "start_deg": float(np.rad2deg(self.starts[k])), "span_deg": float(np.rad2deg(self.spans[k])),
                "start_level": float(self.levels[k]), "end_level": float(self.levels[k] + self.lifts[k]),
                "promised_continuity": list(self.promise(k)),
            }
            info = self.infos[k] if self.infos else None
            if info:
                entry.update({key: v for key, v in info.items() if key != "law"})
            if self.laws[k] is not None and self.lifts[k]:
                entry["characteristics"] = law_characteristics(self.segment_law(k)).summary()
                entry["vdi2143"] = tasks[k]
            segs.append(_plain(entry))
        return {"segments": segs, "junctions": [j.to_dict() for j in self.junctions()]}

    def segment_law(self, k: int) -> "str | NormalisedLaw":
        """Rise or return ``k``'s normalised law: a closed form's name, a parametric law
        (:class:`~.laws.LawName`), else the segment normalised from the program
        (:meth:`~.laws.NormalisedLaw.from_segment`)."""
        law = self.laws[k]
        if isinstance(law, LawName) or law in CLOSED_FORM_LAWS:
            return law
        return NormalisedLaw.from_segment(self, k)

    def s(self, theta: np.ndarray | float) -> np.ndarray:
        """Follower displacement only."""
        return self.evaluate(theta).s

    def maxima(self, omega: float, samples_per_segment: int = 4001) -> dict[str, float]:
        """Largest |v|, |a|, |j| (true, per second) for cam speed ``omega`` [rad/s], sampled
        densely in every rise/return including the segment ends."""
        th = self.dense_angles(samples_per_segment)
        k = self.evaluate(th)
        return {
            "velocity": float(np.max(np.abs(k.ds)) * omega),
            "acceleration": float(np.max(np.abs(k.d2s)) * omega**2),
            "jerk": float(np.max(np.abs(k.d3s)) * omega**3),
        }

    def dense_angles(self, samples_per_segment: int = 1001) -> np.ndarray:
        """Angles [rad] sampling every rise/return with ``samples_per_segment`` points
        (ends included) and every dwell at its ends."""
        parts = []
        for k in range(len(self.starts)):
            n = samples_per_segment if self.laws[k] is not None else 2
            parts.append(self.starts[k] + self.spans[k] * np.linspace(0.0, 1.0, n))
        return np.concatenate(parts)


def _plain(v: Any) -> Any:
    """numpy scalars and arrays in a report entry as plain Python numbers and lists."""
    if isinstance(v, dict):
        return {k: _plain(x) for k, x in v.items()}
    if isinstance(v, (list, tuple, np.ndarray)):
        return [_plain(x) for x in v]
    if isinstance(v, np.integer):
        return int(v)
    if isinstance(v, np.floating):
        return float(v)
    return v


@lru_cache(maxsize=64)
def _program(segments: tuple[MotionSegment, ...], advance: float) -> MotionProgram:
    return MotionProgram._build(segments, advance)


@dataclass(frozen=True)
class Junction:
    """Where segment ``left`` ends and segment ``right`` starts.

    ``values_left``/``values_right`` are (s, s′, s″, s‴) on either side, ``jumps`` right − left;
    ``order`` is the highest n with s … s^(n) continuous (−1: s itself jumps; 3: up to the jerk,
    the highest derivative the program carries); ``promised`` the lower of the orders the two
    laws promise at this end (:func:`~cam_workbench.generators.motion.segments.law_promise`)."""

    index: int
    left: int
    right: int
    at_deg: float
    law_left: str | None
    law_right: str | None
    values_left: tuple[float, float, float, float]
    values_right: tuple[float, float, float, float]
    jumps: tuple[float, float, float, float]
    order: int
    promised: int

    @property
    def ok(self) -> bool:
        return self.order >= self.promised

    def to_dict(self) -> dict[str, Any]:
        names = ("s", "velocity", "acceleration", "jerk")
        return {"index": self.index, "at_deg": self.at_deg, "from": self.left, "to": self.right,
                "from_law": str(self.law_left or "dwell"), "to_law": str(self.law_right or "dwell"),
                "left": dict(zip(names, self.values_left)), "right": dict(zip(names, self.values_right)),
                "jumps": dict(zip(names, self.jumps)), "order": self.order, "promised": self.promised,
                "ok": self.ok}


def wrap_angle(theta: np.ndarray | float) -> np.ndarray:
    """θ reduced to [0, 2π) [rad]: ``np.mod`` alone returns 2π itself for tiny negative θ
    (−1e-17 rounds to 2π), which would put the start of the program at its end."""
    t = np.mod(np.asarray(theta, dtype=float), TWO_PI)
    return np.where(t >= TWO_PI, 0.0, t)

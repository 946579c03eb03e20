"""The spec's `[[motion]]` tables: :class:`MotionSegment`, the laws and their fields, the shortest
span, reading ``table_file`` into ``table``, and the rules of the motion program (spans sum to 360°,
the program closes, each law's fields).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

from ..errors import SpecError, fmt_apart
from ..kinds import body_of
from ..motion.bspline_law import lift_from_segment
from ..motion.law_library import PARAMETRIC_LAWS
from ..motion import laws as motion_laws
from ..motion.program import MotionProgram
from ..motion.table import TableError, read_csv
from .params import param
from .pitch import MAX_SEGMENTS

if TYPE_CHECKING:  # types only: the spec's root imports this module
    from .model import CamSpec


#: The laws implemented by :mod:`cam_workbench.generators.motion.laws` (closed forms: the rest-to-rest
#: laws and the quick-return laws "quick_return_out", "quick_return_in").
CLOSED_FORM_LAWS = tuple(motion_laws.CLOSED_FORM_LAWS)
#: Every law a motion segment may name: the closed forms; "bspline", the thesis' parametric B-spline
#: (:mod:`cam_workbench.generators.motion.bspline_law`), shaped by control points; "polynomial",
#: "constant_velocity" and "table", solved from boundary conditions or fitted to points
#: (:mod:`cam_workbench.generators.motion.segments`); the parametric closed forms.
LAWS = (*CLOSED_FORM_LAWS, "bspline", "polynomial", "constant_velocity", "table", *PARAMETRIC_LAWS)
#: The parametric closed forms (:mod:`cam_workbench.generators.motion.law_library`): "scca",
#: "modified_sine_cv", "modified_trapezoid_cv", "triple_harmonic", "poly345_throw", "poly4567_throw".
PARAMETRIC_LAW_NAMES = tuple(PARAMETRIC_LAWS)
#: Motion-segment fields that only a law = "bspline" segment may have.
BSPLINE_FIELDS = ("order", "control_x", "control_y", "control_frame", "control_start")
#: Motion-segment fields of the laws solved from boundary conditions, with the laws that take them.
SEGMENT_LAW_FIELDS: dict[str, tuple[str, ...]] = {
    "start_continuity": ("polynomial", "constant_velocity", "table"),
    "end_continuity": ("polynomial", "constant_velocity", "table"),
    "start_velocity": ("polynomial", "table"), "end_velocity": ("polynomial", "table"),
    "start_acceleration": ("polynomial", "table"), "end_acceleration": ("polynomial", "table"),
    "start_jerk": ("polynomial", "table"), "end_jerk": ("polynomial", "table"),
    "points": ("polynomial",),
    "start_blend": ("constant_velocity",), "end_blend": ("constant_velocity",),
    "table": ("table",), "table_file": ("table",), "table_start": ("table",), "table_tolerance": ("table",),
    "order": ("bspline", "table"),
    **{f: tuple(name for name, law in PARAMETRIC_LAWS.items() if f in law.fields)
       for f in dict.fromkeys(f for law in PARAMETRIC_LAWS.values() for f in law.fields)},
}

SPAN_TOL_DEG = 1e-9
#: Smallest motion-segment span [deg]: the finest junction spacing of a pitch curve, 360°/MAX_SEGMENTS.
#: A shorter segment (or blend) can lie between two junctions of every pitch curve the project builds.
MIN_SPAN_DEG = 360.0 / MAX_SEGMENTS
#: Why a span (a motion segment, a blend) has that minimum, in the rule's words.
MIN_SPAN_NOTE = (f"360°/{MAX_SEGMENTS}: the finest junction spacing of the pitch curve; a shorter span can lie "
                 "between two junctions")


@dataclass(frozen=True, kw_only=True)
class MotionSegment:
    """One `[[motion]]` entry: a dwell, rise or return over `angle` degrees of cam rotation."""

    kind: str = param("Segment type", kind="str", choices=("dwell", "rise", "return"), group="Motion")
    angle: float = param("Span of the segment in cam degrees; all spans sum to 360",
                         unit="angle", ge=MIN_SPAN_DEG, group="Motion", bound_note=MIN_SPAN_NOTE)
    lift: float | None = param("Rise or fall height of the segment (rise/return only; > 0)",
                               unit="length", gt=0, optional=True, group="Motion")
    law: str | None = param(
        "Motion law (rise/return only): a closed form (\"quick_return_out\" runs from rest into a turning "
        "point with the acceleration carried over the top, \"quick_return_in\" out of one into rest: a rise "
        "straight into a return), \"bspline\" (control points), \"polynomial\" (the "
        "lowest-degree polynomial meeting the end conditions and points), \"constant_velocity\" (with blended "
        "ends), \"table\" (a B-spline fitted to (angle, lift) points), or a parametric closed form: \"scca\" "
        "(Norton's sine-constant-cosine family), \"modified_sine_cv\" and \"modified_trapezoid_cv\" (with a "
        "constant-velocity middle), \"triple_harmonic\", \"poly345_throw\" and \"poly4567_throw\" (velocity peak "
        "moved)", kind="str", choices=LAWS,
        optional=True, group="Motion")
    junctions: int | None = param(
        "Number of PH segments spanning this motion segment (non-uniform junction spacing, "
        "as the paper's case 3); when any segment has it, all must",
        kind="int", ge=1, le=MAX_SEGMENTS, optional=True, group="Motion",
    )
    @staticmethod
    def precheck(data: Mapping[str, Any], path: str) -> None:
        """Before the fields' own rules: a dwell has no lift or law (a dwell's ``lift = 0``
        is told to leave it out, not that it must be > 0)."""
        if data.get("kind") == "dwell":
            for name in ("lift", "law"):
                if name in data:
                    raise SpecError(f"{path}.{name}", "must be absent for a dwell")
        if "table" in data and "table_file" in data:
            raise SpecError(f"{path}.table_file", "is exclusive with table: give the points inline or as a file")

    # ---- law = "bspline" (thesis §2.5–2.7) ----
    order: int | None = param(
        "B-spline order k (degree k − 1) of a law = \"bspline\" segment; the first and last k − 1 "
        "control points sit at the end levels, so derivatives 1 … k − 2 vanish at both ends; "
        "default 5 (the thesis: zero velocity, acceleration and jerk). With law = \"table\": the "
        "fit's order (≥ 4 for C²; default 5)",
        kind="int", ge=3, le=10, optional=True, group="Motion",
    )
    control_x: tuple[float, ...] | None = param(
        "Cam angles of the B-spline's interior control points P1 … P(n−1) in control_frame "
        "(P0 and Pn sit at the segment's start and end, so there are n + 1 = len + 2 points); "
        "must increase so that θ(u) increases (thesis B(k): the rise's or return's P_ix)",
        kind="floats", optional=True, group="Motion",
    )
    control_y: tuple[float, ...] | None = param(
        "Normalised lifts of the control points (a rise goes 0 → 1, a return 1 → 0): either only "
        "the free ones P(k−1) … P(n−k+1) (thesis: P4, P5, P6), or all interior points P1 … P(n−1), "
        "whose fixed entries must then be at the end levels",
        kind="floats", optional=True, group="Motion",
    )
    control_frame: str | None = param(
        "Frame of control_x: \"relative_deg\" = degrees from the segment start (default); "
        "\"absolute_rad\" = radians of absolute cam angle, as the thesis lists them",
        kind="str", choices=("relative_deg", "absolute_rad"), optional=True, group="Motion",
    )
    control_start: float | None = param(
        "With control_frame = \"absolute_rad\": the segment's start as an absolute cam angle in the "
        "control points' frame; default its start in this program (the sum of the spans before "
        "it). For designs whose cycle starts elsewhere (thesis Examples 4 and 6 start at −20°)",
        unit="angle", optional=True, group="Motion",
    )
    # ---- laws solved from boundary conditions: polynomial, constant_velocity, table ----
    start_continuity: int | None = param(
        "Polynomial, constant_velocity, table: derivatives of s the segment's start takes from the previous "
        "segment's end — 1 velocity, 2 and acceleration (default), 3 and jerk, 0 none (free). Between dwells "
        "a polynomial with 2 at both ends is the 3-4-5 law, with 3 the 4-5-6-7 law",
        kind="int", ge=0, le=3, optional=True, group="Motion")
    end_continuity: int | None = param(
        "As start_continuity, for the segment's end and the next segment's start",
        kind="int", ge=0, le=3, optional=True, group="Motion")
    start_velocity: float | None = param(
        "Polynomial, table: s′ at the segment's start, per radian of cam rotation (lift units/rad); absent: "
        "the previous segment's (to start_continuity) or free",
        unit="reduced_velocity", optional=True, group="Motion")
    end_velocity: float | None = param(
        "Polynomial, table: s′ at the segment's end (lift units/rad); absent: the next segment's or free",
        unit="reduced_velocity", optional=True, group="Motion")
    start_acceleration: float | None = param(
        "Polynomial, table: s″ at the segment's start (lift units/rad²); absent: the previous segment's or free",
        unit="reduced_acceleration", optional=True, group="Motion")
    end_acceleration: float | None = param(
        "Polynomial, table: s″ at the segment's end (lift units/rad²); absent: the next segment's or free",
        unit="reduced_acceleration", optional=True, group="Motion")
    start_jerk: float | None = param(
        "Polynomial, table: s‴ at the segment's start (lift units/rad³); absent: the previous segment's "
        "(start_continuity 3) or free",
        unit="reduced_jerk", optional=True, group="Motion")
    end_jerk: float | None = param(
        "Polynomial, table: s‴ at the segment's end (lift units/rad³); absent: the next segment's "
        "(end_continuity 3) or free",
        unit="reduced_jerk", optional=True, group="Motion")
    points: tuple[tuple[float, float], ...] | None = param(
        "Polynomial: interior points [[angle, s], …] the polynomial passes through: degrees from the segment "
        "start (strictly inside it) and the follower displacement s there (lift units, measured from zero "
        "lift like the program)",
        kind="points", unit="length", optional=True, group="Motion")
    start_blend: float | None = param(
        "Constant velocity: angle over which the start blends from the previous segment's motion into the "
        "constant velocity (a polynomial meeting both to start_continuity); absent: no blend",
        unit="angle", ge=MIN_SPAN_DEG, optional=True, group="Motion", bound_note=MIN_SPAN_NOTE)
    end_blend: float | None = param(
        "Constant velocity: angle over which the constant velocity blends into the next segment's motion "
        "(to end_continuity); absent: no blend",
        unit="angle", ge=MIN_SPAN_DEG, optional=True, group="Motion", bound_note=MIN_SPAN_NOTE)
    table: tuple[tuple[float, float], ...] | None = param(
        "Table: [[angle, s], …] points the segment's B-spline is fitted to: degrees from the segment start "
        "(or from table_start) and the follower displacement s (lift units, from zero lift)",
        kind="points", unit="length", optional=True, group="Motion")
    table_file: str | None = param(
        "Table: a CSV file of angle, s rows (comma, semicolon or space separated; a header line and # "
        "comments skipped), relative to the spec file; read into `table` when the spec is loaded",
        kind="str", optional=True, group="Motion")
    table_start: float | None = param(
        "Table: the table angle at which this segment starts; rows outside the segment are then ignored, so "
        "one table of a whole cycle can serve several segments (absent: angles from the segment start, "
        "and every row must lie inside it)",
        unit="angle", optional=True, group="Motion")
    # ---- parametric closed forms (cam_workbench.generators.motion.law_library) ----
    scca_b: float | None = param(
        "SCCA: fraction of the rise taken by the two sine ramps of the acceleration (b; b + c + d = 1; "
        "modified trapezoid 0.25, modified sine 0.25, cycloidal 0.5; 0: the acceleration jumps at the ends)",
        unit="", ge=0, le=1, optional=True, group="Motion")
    scca_c: float | None = param(
        "SCCA: fraction of the rise at constant acceleration (c; b + c + d = 1; modified trapezoid 0.5, "
        "constant acceleration 1)",
        unit="", ge=0, le=1, optional=True, group="Motion")
    scca_d: float | None = param(
        "SCCA: fraction of the rise taken by the cosine part of the acceleration through the crossover "
        "(d; b + c + d = 1; modified sine 0.75, simple harmonic 1)",
        unit="", ge=0, le=1, optional=True, group="Motion")
    cruise_fraction: float | None = param(
        "SCCA (optional, default 0), modified_sine_cv, modified_trapezoid_cv (required): fraction of the "
        "segment's angle at constant velocity in its middle; the law's accelerating and decelerating halves "
        "share the rest",
        unit="", ge=0, lt=1, optional=True, group="Motion")
    harmonic_1: float | None = param(
        "Triple harmonic: amplitude a₁ of f″ = a₁ sin 2πx + a₂ sin 4πx + a₃ sin 6πx (per unit rise over the "
        "unit interval; a₃ follows from f(1) = 1); default 9π/4 (with a₂ = 0: zero jerk at the ends and the "
        "crossover), 2π is the cycloidal law",
        unit="", optional=True, group="Motion")
    harmonic_2: float | None = param(
        "Triple harmonic: amplitude a₂ of the second harmonic (default 0)",
        unit="", optional=True, group="Motion")
    velocity_peak_at: float | None = param(
        "poly345_throw, poly4567_throw: where the velocity peaks, as a fraction of the segment's angle "
        "(0.5: the symmetric 3-4-5 or 4-5-6-7 law; below: a fast start and a slow end)",
        unit="", gt=0, lt=1, optional=True, group="Motion")
    table_tolerance: float | None = param(
        "Table: largest allowed distance |s_fit − s| of the fit from a table point (default 0.1% of the "
        "lift); the fewest knot spans meeting it are used",
        unit="length", gt=0, optional=True, group="Motion")


def inline_table_files(data: Mapping[str, Any], base_dir: str | Path | None) -> Mapping[str, Any]:
    """``data`` with every ``motion[i].table_file`` read into ``motion[i].table`` (a copy; the
    spec then holds the points themselves, so its TOML, digest and reports do not depend on the file)."""
    motion = data.get("motion")
    if not isinstance(motion, (list, tuple)) or not any(
            isinstance(m, Mapping) and "table_file" in m for m in motion):
        return data
    rows = []
    for i, m in enumerate(motion):
        if isinstance(m, Mapping) and "table_file" in m:
            path = f"motion[{i}].table_file"
            name = m["table_file"]
            if not isinstance(name, str) or not name.strip():
                raise SpecError(path, f"must be a file name, got {name!r}")
            if "table" in m:
                raise SpecError(path, "is exclusive with table: give the points inline or as a file")
            f = Path(name).expanduser()
            if not f.is_absolute():
                f = Path(base_dir or ".") / f
            try:
                table = read_csv(f)
            except TableError as exc:
                raise SpecError(path, str(exc)) from None
            m = {k: v for k, v in m.items() if k != "table_file"}
            m["table"] = [list(r) for r in table]
        rows.append(m)
    out = dict(data)
    out["motion"] = rows
    return out


MAX_MOTION_SEGMENTS = 100


def validate_motion(spec: CamSpec) -> None:
    if len(spec.motion) > MAX_MOTION_SEGMENTS:
        raise SpecError("motion", f"has {len(spec.motion)} segments, at most {MAX_MOTION_SEGMENTS}")
    total = 0.0
    level = 0.0
    lifts = []
    for i, seg in enumerate(spec.motion):
        p = f"motion[{i}]"
        start_deg = total
        total += seg.angle
        if seg.kind != "dwell" and seg.law is None:      # before the fields that depend on the law
            raise SpecError(f"{p}.law", f"is required for a {seg.kind} (one of {', '.join(LAWS)})")
        if seg.law != "bspline":
            for name in BSPLINE_FIELDS:
                if getattr(seg, name) is not None and seg.law not in SEGMENT_LAW_FIELDS.get(name, ()):
                    raise SpecError(f"{p}.{name}", 'must be absent unless law = "bspline"'
                                    + (' or "table"' if name == "order" else ""))
        for name, laws in SEGMENT_LAW_FIELDS.items():
            if name not in BSPLINE_FIELDS and getattr(seg, name) is not None and seg.law not in laws:
                raise SpecError(f"{p}.{name}", "applies to law = " + " or ".join(f'"{w}"' for w in laws)
                                + (f" only, not {seg.law!r}" if seg.law else " only"))
        if seg.kind == "dwell":
            if seg.lift is not None:
                raise SpecError(f"{p}.lift", "must be absent for a dwell")
            if seg.law is not None:
                raise SpecError(f"{p}.law", "must be absent for a dwell")
            continue
        if seg.lift is None:
            raise SpecError(f"{p}.lift", f"is required for a {seg.kind}")
        if not seg.lift > 0:
            raise SpecError(f"{p}.lift", f"must be > 0 for a {seg.kind}, got {seg.lift:g}")
        if seg.law == "bspline":
                    lift_from_segment(seg, p, math.radians(start_deg), math.radians(seg.angle))
        if seg.law == "table":
            if seg.table is None:
                raise SpecError(f"{p}.table", 'is required for law = "table" (inline [[angle, s], …] rows, '
                                "or table_file)")
            if seg.order is not None and seg.order < 4:
                raise SpecError(f"{p}.order", f"a table fit needs order ≥ 4 (C² inside the segment), got {seg.order}")
        lifts.append(seg.lift)
        before = level
        level += seg.lift if seg.kind == "rise" else -seg.lift
        scale = max(lifts)
        if level < -1e-9 * scale:
            raise SpecError(f"{p}.lift",
                            f"the follower would go {-level:g} below zero lift (s must stay ≥ 0): the segments "
                            f"before it leave it at {fmt_apart(before, seg.lift)}, this {seg.kind} falls "
                            f"{fmt_apart(seg.lift, before)}")
    if abs(total - 360.0) > SPAN_TOL_DEG:
        raise _span_sum_error(spec.motion, total)
    advance = body_of(spec).motion_advance(spec)       # 0: the program closes; an indexer's turret advances
    if not lifts:
        raise SpecError("motion", "needs at least one rise" + (" and one return" if advance == 0 else ""))
    if abs(level - advance) > 1e-9 * max(lifts):
        if advance == 0:
            raise SpecError("motion",
                            f"program does not close: total rise − total fall = {level:g}, must be 0")
        raise SpecError("motion", f"the turret must advance by {advance:g}° per input turn (360°/indexer.stations): "
                        f"total rise − total fall = {fmt_apart(level, advance)}")
    # the laws solved from boundary conditions or fitted, s ≥ 0 inside every segment, the program's
    # junction values (cam_workbench.generators.motion.segments): errors name the field
    MotionProgram.from_segments(spec.motion, advance)
    has_j = [seg.junctions is not None for seg in spec.motion]
    if any(has_j) and not all(has_j):
        missing = has_j.index(False)
        raise SpecError(f"motion[{missing}].junctions",
                        "is required on every segment when any segment gives junctions")


def _span_sum_error(motion: tuple[MotionSegment, ...], total: float) -> SpecError:
    """The spans sum to ``total`` ≠ 360°: the error names the span that, changed by the
    difference, has the fewest decimals (at most 6) — the odd one out, as 119.99999999 among 30,
    120, 60, 120, 30 — with the value that closes the cycle; on a tie (350 instead of 360 among
    whole degrees), or when no span would read as a typed number, it names the last span and
    suggests nothing."""
    diff = 360.0 - total
    decimals = {}
    for k, seg in enumerate(motion):
        fixed = seg.angle + diff
        text = f"{fixed:.9f}".rstrip("0")
        places = len(text.split(".")[1])
        if fixed >= MIN_SPAN_DEG and places <= 6:     # a value a person would type
            decimals[k] = (places, text.rstrip("."))
    rule = f"spans sum to {fmt_apart(total, 360.0)}°, must be 360°"
    fewest = min((d for d, _ in decimals.values()), default=None)
    odd = [k for k, (d, _) in decimals.items() if d == fewest]
    if len(odd) == 1 and len(motion) > 1:
        return SpecError(f"motion[{odd[0]}].angle", f"{rule} ({decimals[odd[0]][1]} here makes them 360°)")
    return SpecError(f"motion[{len(motion) - 1}].angle", rule)

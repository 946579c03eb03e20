"""The spec's `[optimise]` table: :class:`OptimiseSection`, the objectives, algorithms and design
variables it names, how ``optimise.variables`` resolves (:func:`optimise_variables`,
:func:`optimise_control_rows`), which follower and body fields can vary, and its rules.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import SpecError, fmt_apart
from ..kinds import body_of
from .params import param

if TYPE_CHECKING:  # types only: the spec's root imports this module
    from .model import CamSpec



#: Objectives of the optimiser (thesis Ch. 5): the thesis' cam area (Eq. 4.21, inside the pitch
#: curve), the true profile cross-section, the thesis' cutting time (Eq. 4.4–4.20), the time of the
#: project's own XY G-code contour, and the largest |s″| or |φ| (smoothest cam).
OBJECTIVES = ("area", "profile_area", "machining_time", "gcode_time", "peak_acceleration",
              "peak_pressure_angle", "outer_diameter")
#: Objectives of a body's own optimiser beyond :data:`OBJECTIVES`, taken only by a body that declares
#: them (``Body.optimise_objectives``): an indexer's cam's outer radius and peak roller load (the parallel
#: indexer's :mod:`cam_workbench.generators.optimise.indexer`, the barrel and globoidal indexers'
#: :mod:`cam_workbench.generators.optimise.spatial_indexer`).
BODY_OBJECTIVES = ("size", "normal_force")
OPTIMISE_ALGORITHMS = ("auto", "slsqp", "mma", "ccsaq", "cobyla", "bobyqa", "isres")
#: Names that ``optimise.variables`` may list.
OPTIMISE_VARIABLES = ("base_radius", "offset", "pivot_distance", "arm_length", "face_offset", "control_x",
                      "control_y", "control_points", "points", "outer_diameter", "clearance", "cylinder_radius",
                      "orientation")
#: The design variables that are the cam body's own (a groove cam's disc and groove), in order.
BODY_VARIABLES = ("outer_diameter", "clearance")
#: A cylindrical cam's design variables (its own optimiser: :mod:`cam_workbench.generators.optimise.cylindrical`).
CYLINDER_VARIABLES = ("cylinder_radius", "outer_diameter", "clearance")
#: The design variables that are follower fields, in the design vector's order.
FOLLOWER_VARIABLES = ("offset", "pivot_distance", "arm_length", "face_offset")


@dataclass(frozen=True, kw_only=True)
class OptimiseSection:
    """`[optimise]`: what `cam-workbench optimise` minimises, over which design variables, and how (thesis Ch. 5–7)."""

    objective: str = param(
        "Cost function: \"area\" = thesis Eq. 4.21 for a translating knife edge or roller (½∮(R_b + s)² dθ, "
        "the area inside the pitch curve for e = 0), for every other follower the exact area inside its "
        "design curve (an oscillating knife/roller's pitch curve, a flat face's profile); \"profile_area\" = "
        "the true cam cross-section inside the profile; "
        "\"machining_time\" = the thesis' cutting time (Eq. 4.4–4.20); \"gcode_time\" = the time of this "
        "project's XY G-code contour; \"peak_acceleration\" / \"peak_pressure_angle\" = the largest |s″| / |φ|; "
        "machining_time needs a translating follower; \"outer_diameter\" = a groove cam's disc diameter "
        "(cam.body = \"groove\", with outer_diameter among the variables) or a cylindrical cam's cylinder (its "
        "only objective); \"size\" / \"normal_force\" = an indexer's cam's outer radius / peak roller "
        "load (a parallel, barrel or globoidal indexer's only objectives, \"area\" taken as \"size\"; "
        "normal_force needs indexer.output_inertia)",
        kind="str", choices=OBJECTIVES + BODY_OBJECTIVES, default="area", group="Optimise")
    variables: str = param(
        "Design variables, comma-separated: base_radius, offset (translating followers), pivot_distance and "
        "arm_length (oscillating followers; a flat face's arm_length, its centre, when given), face_offset "
        "(oscillating flat face), control_x, control_y (control_points = both: every free control coordinate "
        "of each B-spline rise/return; motion[k].control_x, motion[k].control_y, motion[k].control_points: "
        "those of segment k only), points (the lifts s of the interior points of every law = \"polynomial\" "
        "rise/return that has points; motion[k].points: segment k's), orientation (the blank on the NC table; "
        "machining_time only), outer_diameter and clearance (a groove cam's cam.outer_diameter and "
        "groove.clearance: cam.body = \"groove\"; a cylindrical cam's: cylinder_radius, outer_diameter, "
        "clearance, \"auto\" = the first two); \"auto\" = "
        "the cam's size, base_radius, and control_points (+ orientation for machining_time); the follower's "
        "position (offset; pivot_distance, arm_length, face_offset) and polynomial points only when named (the "
        "machine often fixes the one, the designer's requirements the other)",
        kind="str", default="auto", group="Optimise")
    algorithm: str = param(
        "nlopt algorithm: \"auto\" = SLSQP (exact gradients) for smooth objectives; for machining_time "
        "and gcode_time SLSQP on a smooth size surrogate, then BOBYQA with the thesis' exterior penalty "
        "(Eq. 5.14–5.15); slsqp/mma/ccsaq (gradient), cobyla (derivative-free, constraints), bobyqa "
        "(derivative-free, exterior penalty), isres (global, seeded)",
        kind="str", choices=OPTIMISE_ALGORITHMS, default="auto", group="Optimise")
    multistart: int = param("Extra local runs from random starting designs (seeded); the best feasible "
                            "result wins", kind="int", ge=0, le=1000, default=0, group="Optimise")
    seed: int = param("Seed of the random starts and of ISRES", kind="int", ge=0, default=1, group="Optimise")
    max_evaluations: int = param("Most objective evaluations of one solver run", kind="int", ge=10,
                                 default=3000, group="Optimise")
    xtol_rel: float = param("Stop when a step changes every scaled variable by less than this (relative)",
                            gt=0, lt=1, default=1e-7, group="Optimise")
    ftol_rel: float = param("Stop when a step changes the objective by less than this (relative)",
                            gt=0, lt=1, default=1e-10, group="Optimise")
    constraint_margin: float = param(
        "Every normalised constraint g ≤ 0 (thesis Eq. 5.2–5.13) is imposed as g ≤ −margin, so the result "
        "passes the dense checks strictly", ge=0, lt=0.1, default=1e-4, group="Optimise")
    windows: int = param(
        "Each rise/return is split into this many equal windows of its parameter (u of a B-spline, θ "
        "otherwise); the largest value of every check in a window, found on 13 samples and refined, is one "
        "constraint (dwells: one each). MMA and CCSAQ use at most 8 (nlopt's dual subproblem slows steeply with "
        "the number of constraints)", kind="int", ge=4, le=2000, default=80, group="Optimise")
    refine_rounds: int = param("Re-solves with twice the windows while the final dense check still fails "
                               "(MMA and CCSAQ: at most once)",
                               kind="int", ge=0, le=8, default=2, group="Optimise")
    base_radius_min: float | None = param(
        "Lower bound of cam.base_radius (default: half the initial, at least roller radius + bore radius)",
        unit="length", gt=0, optional=True, group="Optimise")
    base_radius_max: float | None = param("Upper bound of cam.base_radius (default: twice the initial)",
                                          unit="length", gt=0, optional=True, group="Optimise")
    offset_max: float | None = param("Bound of |follower.offset| (default: half the base-radius lower bound; "
                                     "to keep e fixed, leave offset out of variables)",
                                     unit="length", gt=0, optional=True, group="Optimise")
    pivot_distance_min: float | None = param(
        "Lower bound of follower.pivot_distance (oscillating followers; default: half the initial)",
        unit="length", gt=0, optional=True, group="Optimise")
    pivot_distance_max: float | None = param(
        "Upper bound of follower.pivot_distance (oscillating followers; default: twice the initial)",
        unit="length", gt=0, optional=True, group="Optimise")
    arm_length_min: float | None = param(
        "Lower bound of follower.arm_length (oscillating followers; default: half the initial)",
        unit="length", gt=0, optional=True, group="Optimise")
    arm_length_max: float | None = param(
        "Upper bound of follower.arm_length (oscillating followers; default: twice the initial)",
        unit="length", gt=0, optional=True, group="Optimise")
    face_offset_max: float | None = param(
        "Bound of |follower.face_offset| (oscillating flat face; default: half the base-radius lower bound, or "
        "|face_offset| of the starting design when larger)", unit="length", gt=0, optional=True,
        group="Optimise")
    outer_diameter_min: float | None = param(
        "Lower bound of a groove cam's cam.outer_diameter (default: half the initial)", unit="length", gt=0,
        optional=True, group="Optimise")
    outer_diameter_max: float | None = param(
        "Upper bound of a groove cam's cam.outer_diameter (default: twice the initial)", unit="length", gt=0,
        optional=True, group="Optimise")
    clearance_min: float | None = param(
        "Lower bound of a groove cam's groove.clearance (default 0; the fit the roller needs in its groove "
        "belongs here)", unit="length", ge=0, optional=True, group="Optimise")
    clearance_max: float | None = param(
        "Upper bound of a groove cam's groove.clearance (default: twice the initial)", unit="length", gt=0,
        optional=True, group="Optimise")
    point_shift_max: float | None = param(
        "Bound of how far each polynomial interior point's lift (variables points, motion[k].points) may move "
        "from its starting value (default: no bound but the segment's own lift range, from its lower to its "
        "upper level)", unit="length", gt=0, optional=True, group="Optimise")
    control_gap: float = param(
        "Smallest angle between consecutive control-point angles of a B-spline rise/return (keeps θ(u) "
        "increasing: thesis §2.7)", unit="angle", gt=0, default=0.5, group="Optimise")
    penalty: float = param("Initial exterior-penalty multiplier r_p (thesis Eq. 5.14; ×10 per round)",
                           gt=0, default=10.0, group="Optimise")
    penalty_rounds: int = param("Rounds of the exterior-penalty method (bobyqa)", kind="int", ge=1, le=20,
                                default=6, group="Optimise")
    machining_tolerance: float | None = param(
        "ε of the thesis' cutting-time model: the axis-parallel tool path stays within ε outside the "
        "curve (thesis Eq. 4.4, 4.17; its examples 0.01 in); default 0.01 in / 0.25 mm",
        unit="length", gt=0, optional=True, group="Optimise")
    turn_time: float = param("Time per turn of the thesis' tool path (thesis Eq. 4.20: 0.4 s)", unit="time",
                             ge=0, default=0.4, group="Optimise")
    blank_orientation: float = param(
        "Blank orientation on the NC table for the thesis' cutting time: angle from the machine's +X axis to "
        "the cam's θ = 0 line (thesis B(3))", unit="angle", default=0.0, group="Optimise")
    block_time: float = param("Time added per motion block of the G-code contour (acceleration, block "
                              "processing) for objective gcode_time", unit="time", ge=0, default=0.05,
                              group="Optimise")


_SEGMENT_VARIABLE = re.compile(r"^motion\[(\d+)\]\.(control_x|control_y|control_points|points)$")


def _point_rows(spec: CamSpec) -> set[int]:
    """Motion rows with law = "polynomial" and interior points (whose lifts can be varied)."""
    return {k for k, seg in enumerate(spec.motion) if seg.law == "polynomial" and seg.points}


def _parse_variables(spec: CamSpec) -> tuple[set[str], dict[str, set[int]]]:
    """(kinds, motion rows per per-segment kind: B-spline ``control_x``/``control_y``, polynomial
    ``points``) of ``optimise.variables``."""
    opt = spec.optimise
    text = opt.variables.strip()
    bspline_rows = {k for k, seg in enumerate(spec.motion) if seg.law == "bspline"}
    point_rows = _point_rows(spec)
    rows: dict[str, set[int]] = {"control_x": set(), "control_y": set(), "points": set()}
    if text == "auto":
        # the cam's size; the follower's position (offset, pivot, arm) is the machine's: only when named
        names = {"base_radius"}
        rows = {"control_x": set(bspline_rows), "control_y": set(bspline_rows), "points": set()}
        if opt.objective == "machining_time":
            names.add("orientation")
    else:
        names = set()
        for tok in text.replace(";", ",").split(","):
            tok = tok.strip()
            if not tok:
                continue
            m = _SEGMENT_VARIABLE.match(tok)
            if m:
                k = int(m.group(1))
                exists = k < len(spec.motion)
                what = (f"has law = {spec.motion[k].law!r}" if exists and spec.motion[k].law
                        else "is a dwell" if exists else f"does not exist ({len(spec.motion)} segments)")
                if m.group(2) == "points":
                    if k not in point_rows:
                        if exists and spec.motion[k].law == "polynomial":
                            what = "has no interior points (give motion[k].points)"
                        raise SpecError("optimise.variables",
                                        f"{tok}: motion[{k}] {what}; only a law = \"polynomial\" rise or return "
                                        "with interior points has point lifts to vary")
                    rows["points"].add(k)
                    continue
                if k not in bspline_rows:
                    raise SpecError("optimise.variables",
                                    f"{tok}: motion[{k}] {what}; only a law = \"bspline\" rise or return has control points")
                kinds = ("control_x", "control_y") if m.group(2) == "control_points" else (m.group(2),)
                for kind in kinds:
                    rows[kind].add(k)
                continue
            if tok not in OPTIMISE_VARIABLES:
                raise SpecError("optimise.variables",
                                f"unknown design variable {tok!r} (known: auto, {', '.join(OPTIMISE_VARIABLES)}, "
                                "motion[k].control_x / control_y / control_points / points)")
            if tok in ("control_points", "control_x", "control_y"):
                if not bspline_rows:
                    raise SpecError("optimise.variables",
                                    'control points need a law = "bspline" rise or return (other laws have none)')
                for kind in (("control_x", "control_y") if tok == "control_points" else (tok,)):
                    rows[kind] |= bspline_rows
            elif tok == "points":
                if not point_rows:
                    raise SpecError("optimise.variables",
                                    'points need a law = "polynomial" rise or return with interior points '
                                    "(motion[k].points)")
                rows["points"] |= point_rows
            else:
                names.add(tok)
    names |= {kind for kind, ks in rows.items() if ks}
    return names, rows


def optimise_variables(spec: CamSpec) -> tuple[str, ...]:
    """The design-variable kinds of ``optimise.variables`` resolved ("auto", "control_points"
    and the per-segment ``motion[k].…`` forms expanded), in the order base_radius, offset,
    control_x, control_y, orientation."""
    names, _rows = _parse_variables(spec)
    return tuple(n for n in ("base_radius", *FOLLOWER_VARIABLES, "control_x", "control_y", "points",
                             *BODY_VARIABLES, "cylinder_radius", "orientation") if n in names)


def optimise_control_rows(spec: CamSpec) -> dict[str, tuple[int, ...]]:
    """The motion rows whose control angles (``"control_x"``) and lifts (``"control_y"``), or
    polynomial point lifts (``"points"``), are design variables, by ``optimise.variables`` (every
    B-spline row for ``control_x`` etc.)."""
    _names, rows = _parse_variables(spec)
    return {kind: tuple(sorted(ks)) for kind, ks in rows.items()}


def follower_variable_rule(spec: CamSpec, name: str) -> str | None:
    """Why the follower field ``name`` cannot be a design variable of ``spec``'s follower (the
    rules of ``[follower]``: offset for translating followers, pivot_distance and arm_length for
    oscillating ones, face_offset for an oscillating flat face), or None when it can."""
    fol = spec.follower
    if name == "offset" and fol.motion != "translating":
        return ("offset applies to translating followers only: an oscillating follower's position is "
                "pivot_distance and arm_length (vary those)")
    if name in ("pivot_distance", "arm_length", "face_offset") and fol.motion != "oscillating":
        return (f'{name} applies to oscillating followers only (follower.motion = "oscillating"); a '
                "translating follower's position is its offset")
    if name == "face_offset" and fol.kind != "flat":
        return 'face_offset applies to oscillating flat faces only (follower.kind = "flat")'
    if name == "arm_length" and fol.kind == "flat" and fol.arm_length is None:
        return ("arm_length of a flat face places the face's centre along the arm: give follower.arm_length "
                "to vary it")
    return None


def body_variable_rule(spec: CamSpec, name: str) -> str | None:
    """Why the body field ``name`` (outer_diameter, clearance) cannot be a design variable of
    ``spec``'s body, or None when it can (a groove cam: its disc and its groove)."""
    body = spec.cam.body
    if name == "cylinder_radius":
        return None if body == "cylindrical" else (
            f'cylinder_radius is a cylindrical cam\'s (cam.body = "cylindrical"); this cam\'s body is "{body}"')
    if name not in BODY_VARIABLES or body in ("groove", "cylindrical"):
        return None
    return (f'{name} is a groove cam\'s (cam.body = "groove": the disc\'s cam.outer_diameter, '
            f'groove.clearance); this cam\'s body is "{body}", which has none')


def validate_optimise(spec: CamSpec) -> None:
    opt = spec.optimise
    if opt.objective in BODY_OBJECTIVES and opt.objective not in body_of(spec).optimise_objectives:
        raise SpecError("optimise.objective", f'{opt.objective} is an objective of a body that declares it (an '
                        f'indexer\'s: parallel, barrel or globoidal); this cam\'s body is "{spec.cam.body}"')
    names = optimise_variables(spec)
    if not names:
        raise SpecError("optimise.variables", "names no design variable")
    for name in names:
        rule = follower_variable_rule(spec, name) or body_variable_rule(spec, name)
        if rule:
            raise SpecError("optimise.variables", rule)
    if opt.objective == "outer_diameter" and spec.cam.body != "cylindrical":
        if spec.cam.body != "groove":
            raise SpecError("optimise.objective",
                            f'outer_diameter is a groove cam\'s disc or a cylindrical cam\'s cylinder (cam.body = '
                            f'"groove" or "cylindrical"); this cam\'s body is "{spec.cam.body}"')
        if "outer_diameter" not in names:
            raise SpecError("optimise.variables",
                            "objective outer_diameter needs outer_diameter among the variables")
    for name in ("outer_diameter", "clearance"):
        lo_b, hi_b = getattr(opt, f"{name}_min"), getattr(opt, f"{name}_max")
        if lo_b is not None and hi_b is not None and not lo_b < hi_b:
            raise SpecError(f"optimise.{name}_max", f"must be > optimise.{name}_min ({fmt_apart(lo_b, hi_b)}), got "
                            f"{fmt_apart(hi_b, lo_b)}")
    fol = spec.follower
    if opt.objective == "machining_time" and fol.motion != "translating":
        raise SpecError("optimise.objective",
                        "machining_time is the thesis' cutting-time model of the curve r = R_b + s(θ) of a "
                        "translating follower; an oscillating follower's lift is an arm angle: use gcode_time")
    if opt.objective == "peak_pressure_angle" and (fol.motion, fol.kind) == ("translating", "flat"):
        raise SpecError("optimise.objective",
                        "peak_pressure_angle: a translating flat face's pressure angle is 0 everywhere")
    for name in ("pivot_distance", "arm_length"):
        lo_b, hi_b = getattr(opt, f"{name}_min"), getattr(opt, f"{name}_max")
        if lo_b is not None and hi_b is not None and not lo_b < hi_b:
            raise SpecError(f"optimise.{name}_max", f"must be > optimise.{name}_min ({fmt_apart(lo_b, hi_b)}), got "
                            f"{fmt_apart(hi_b, lo_b)}")
    if "orientation" in names and opt.objective != "machining_time":
        raise SpecError("optimise.variables",
                        "orientation only changes objective = \"machining_time\" (the thesis' cutting time)")
    lo = opt.base_radius_min
    hi = opt.base_radius_max
    if lo is not None and hi is not None and not lo < hi:
        raise SpecError("optimise.base_radius_max", f"must be > optimise.base_radius_min ({fmt_apart(lo, hi)}), got "
                        f"{fmt_apart(hi, lo)}")
    if lo is not None and spec.is_roller and not lo > spec.follower.roller_radius:
        raise SpecError("optimise.base_radius_min",
                        f"must be > follower.roller_radius ({fmt_apart(spec.follower.roller_radius, lo)}), got "
                        f"{fmt_apart(lo, spec.follower.roller_radius)}")
    if opt.offset_max is not None and lo is not None and not opt.offset_max < lo:
        raise SpecError("optimise.offset_max", f"must be < optimise.base_radius_min ({fmt_apart(lo, opt.offset_max)}), "
                        f"got {fmt_apart(opt.offset_max, lo)}")
    if opt.algorithm in ("slsqp", "mma", "ccsaq") and opt.objective in ("machining_time", "gcode_time"):
        raise SpecError("optimise.algorithm",
                        f"{opt.algorithm} needs gradients, but {opt.objective} is discontinuous (whole turns/"
                        "blocks): use auto, bobyqa, cobyla or isres")

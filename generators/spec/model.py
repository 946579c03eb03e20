"""The cam spec: typed dataclasses, loading from TOML / dict / keywords, and validation.

The field names and rules are the contract of ``shared/CAM_SPEC.md``; the project's
own reference is ``docs/spec.md``, generated from the declarations below by
``python -m cam_workbench.generators.spec.reference``.

Conventions: lengths in ``units`` ("mm" or "in"), angles in degrees, speed in rpm.
"""
from __future__ import annotations

import dataclasses
import hashlib
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib  # type: ignore[no-redef]

from ..bodies.features import validate_features
from ..errors import SpecError, fmt_apart
from ..kinds import body_of, follower_class_of
from ..motion.bspline_law import lift_from_segment
from ..motion.program import MotionProgram
from ..motion.table import TableError, read_csv
from .params import REQUIRED, Param, param, params_of
from .train import validate_dynamics

LAWS = ("cycloidal", "harmonic", "modified_sine", "modified_trapezoid", "poly345", "poly4567", "bspline",
        "polynomial", "constant_velocity", "table")
#: The laws implemented by :mod:`cam_workbench.generators.motion.laws` (closed forms); "bspline" is the thesis'
#: parametric B-spline (:mod:`cam_workbench.generators.motion.bspline_law`), shaped by control points;
#: "polynomial", "constant_velocity" and "table" are solved from boundary conditions or fitted to
#: points (:mod:`cam_workbench.generators.motion.segments`).
CLOSED_FORM_LAWS = LAWS[:6]
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
}

SPAN_TOL_DEG = 1e-9
#: Most junctions of a PH pitch curve (or knot spans of a B-spline one) over 360°: pitch.segments,
#: the tolerance search's M, motion[].junctions.
MAX_SEGMENTS = 20000
#: Smallest motion-segment span [deg]: the finest junction spacing of a pitch curve, 360°/MAX_SEGMENTS.
#: A shorter segment (or blend) can lie between two junctions of every pitch curve the project builds.
MIN_SPAN_DEG = 360.0 / MAX_SEGMENTS
#: Why a span (a motion segment, a blend) has that minimum, in the rule's words.
MIN_SPAN_NOTE = (f"360°/{MAX_SEGMENTS}: the finest junction spacing of the pitch curve; a shorter span can lie "
                 "between two junctions")
#: cam bodies (CAM_SPEC.md "Cam bodies") and keyway standards
BODIES = ("plate", "groove", "conjugate", "cylindrical")
KEYWAYS = ("DIN6885", "ANSI")
#: Fields whose unit is the follower's lift unit (``Follower.lift_unit``): a length (``units``) for
#: translating followers, degrees of arm rotation for oscillating ones, whatever ``units`` says.
#: Their declarations say unit "length"; readers that convert units (the FreeCAD properties) read this.
LIFT_FIELDS = ("motion[].lift", "pitch.tolerance", "motion[].control_y", "motion[].points", "motion[].table",
               "motion[].table_tolerance", "motion[].start_velocity", "motion[].end_velocity",
               "motion[].start_acceleration", "motion[].end_acceleration", "motion[].start_jerk",
               "motion[].end_jerk")


@dataclass(frozen=True, kw_only=True)
class CamSection:
    """`[cam]`: the cam body and its rotation."""

    base_radius: float = param(
        "Base radius R_b: radius of the circle traced by the follower point (knife tip or roller centre) at zero lift",
        unit="length", gt=0, group="Cam",
    )
    thickness: float = param("Extrusion depth of the plate (solid from z = 0 to z = thickness)",
                             unit="length", gt=0, group="Cam")
    bore_diameter: float = param("Diameter of the central hole; 0 for a solid disc",
                                 unit="length", ge=0, default=0.0, group="Cam")
    direction: str = param("Rotation direction of the cam viewed from +Z",
                           kind="str", choices=("ccw", "cw"), default="ccw", group="Cam")
    speed_rpm: float = param("Constant angular speed of the cam", unit="speed", gt=0,
                             default=60.0, group="Cam")
    # ---- the body and its features (CAM_SPEC.md "Cam bodies") ----
    body: str = param(
        "The cam body: \"plate\" (the outside profile, a spring keeps the follower on it), \"groove\" (a "
        "disc with the roller running in a groove cut into its top face: positive drive) or \"conjugate\" (two "
        "plate cams on one shaft driving one follower through two rollers: positive drive, see [conjugate]) or "
        "\"cylindrical\" (a barrel cam: a groove around a cylinder, the follower moving along the cam axis or "
        "swinging on an arm about a radial pivot; "
        "see cam.cylinder_radius, cam.length and [groove])",
        kind="str",
        choices=BODIES, default="plate", group="Cam")
    outer_diameter: float | None = param(
        "Groove cam: diameter of the disc; cylindrical cam: the cylinder's outer diameter (default: the pitch "
        "radius at mid-depth of the groove, 2·cylinder_radius + groove.depth)", unit="length", gt=0, optional=True,
        group="Cam")
    cylinder_radius: float | None = param(
        "Cylindrical cam: pitch radius R_p of the groove on the cylinder (the pressure angle tan φ = s′/R_p is "
        "checked there); cam.base_radius takes this value", unit="length", gt=0, optional=True, group="Cam")
    length: float | None = param(
        "Cylindrical cam: axial length of the cylinder (0 ≤ z ≤ length); cam.thickness takes this value",
        unit="length", gt=0, optional=True, group="Cam")
    hub_diameter: float | None = param("Hub diameter (the hub stands below the plate, bored as it is)",
                                       unit="length", gt=0, optional=True, group="Cam")
    hub_length: float | None = param("Hub length along the cam axis", unit="length", gt=0, optional=True,
                                     group="Cam")
    keyway: str | None = param(
        "Keyway in the bore sized from the bore diameter by a standard: \"DIN6885\" (DIN 6885-1 parallel "
        "key) or \"ANSI\" (ANSI B17.1 square key); or give keyway_width and keyway_depth", kind="str",
        choices=KEYWAYS, optional=True, group="Cam")
    keyway_width: float | None = param("Keyway width (explicit keyway)", unit="length", gt=0, optional=True,
                                       group="Cam")
    keyway_depth: float | None = param("Keyway depth from the bore at its centre line (explicit keyway)",
                                       unit="length", gt=0, optional=True, group="Cam")
    mounting_holes: int = param("Number of mounting holes on the mounting circle (0: none)", kind="int", ge=0,
                                le=64, default=0, group="Cam")
    mounting_hole_diameter: float | None = param("Mounting hole diameter", unit="length", gt=0, optional=True,
                                                 group="Cam")
    mounting_circle_diameter: float | None = param("Diameter of the circle the mounting holes' centres lie on",
                                                   unit="length", gt=0, optional=True, group="Cam")
    timing_mark: bool = param("Engrave a radial timing mark on the top face where the follower is at θ = 0",
                              kind="bool", default=False, group="Cam")
    timing_mark_width: float | None = param("Width of the timing mark (default 0.5 mm, 0.02 in)", unit="length", gt=0,
                                            optional=True, group="Cam")
    timing_mark_depth: float | None = param("Depth of the timing mark (default 0.2 mm, 0.008 in)", unit="length",
                                            gt=0, optional=True, group="Cam")


@dataclass(frozen=True, kw_only=True)
class FollowerSection:
    """`[follower]`: a translating follower whose line of motion is parallel to +Y at x = offset."""

    kind: str = param("Follower contact: a roller, a knife edge or a flat face", kind="str",
                      choices=("roller", "knife", "flat"), group="Follower")
    motion: str = param(
        "How the follower moves: along a straight line (translating) or turning about a pivot on an arm "
        "(oscillating; motion[].lift is then the arm's rotation in degrees)", kind="str",
        choices=("translating", "oscillating"), default="translating", group="Follower")
    offset: float = param("Follower offset e (signed, translating followers): its line of motion is x = e",
                          unit="length", default=0.0, group="Follower")
    roller_radius: float = param("Roller radius (roller followers; ignored for a knife edge)",
                                 unit="length", ge=0, default=0.0, group="Follower")
    roller_width: float | None = param(
        "Roller width in contact with the cam; the Hertz contact length is the smaller of this "
        "and cam.thickness (default: cam.thickness)",
        unit="length", gt=0, optional=True, group="Follower")
    mass: float = param(
        "Mass M_f of the follower train moving with the follower (thesis Eq. 3.5; the thesis' "
        "\"0.02 slugs\" is 0.02 lbf·s²/in)", unit="mass", ge=0, default=0.0, group="Follower load")
    preload: float = param(
        "Force P_L pressing the follower onto the cam at zero lift (spring preload, load, "
        "friction: thesis Eq. 3.5)", unit="force", ge=0, default=0.0, group="Follower load")
    spring_rate: float = param(
        "Return-spring rate k: the load is P_L + k·s at lift s (0: constant load, as the thesis)",
        unit="stiffness", ge=0, default=0.0, group="Follower load")
    # ---- oscillating followers (CAM_SPEC.md "Follower motion and kinds") ----
    pivot_distance: float | None = param(
        "Oscillating: distance d from the cam axis to the arm's pivot, which sits at (d, 0) in the fixed frame; "
        "cylindrical cam: the radial pivot's distance along the circumference (developed at the pitch radius) "
        "from the +Y generator, where the roller centre is at mid-lift (pivot upstream of the roller)",
        unit="length", gt=0, optional=True, group="Follower arm")
    arm_length: float | None = param(
        "Oscillating: arm length L from the pivot to the roller centre / knife tip; for a flat face the "
        "position of the face's centre along it (default: the middle of the contact's travel); cylindrical "
        "cam: ≥ pivot_distance, the arm's arc in the developed pitch plane",
        unit="length", gt=0, optional=True, group="Follower arm")
    face_offset: float | None = param(
        "Oscillating flat face: distance from the pivot to the face line, positive with the face between "
        "the pivot and the cam (default 0: the face passes through the pivot)",
        unit="length", optional=True, group="Follower arm")
    face_width: float | None = param(
        "Flat face: its width, centred on the stem (translating) or on arm_length (oscillating); "
        "checked against the width the contact needs (absent: the width needed is reported, the face_width "
        "check skipped)", unit="length", gt=0, optional=True, group="Follower")
    arm_inertia: float = param(
        "Oscillating: moment of inertia I of the arm and everything turning with it about the pivot",
        unit="inertia", ge=0, default=0.0, group="Follower load")
    preload_torque: float = param(
        "Oscillating: torque T_L pressing the arm onto the cam at zero lift (spring preload)",
        unit="torque", ge=0, default=0.0, group="Follower load")
    spring_torque_rate: float = param(
        "Oscillating: return-spring torque rate k_t: the torque is T_L + k_t·s at arm rotation s [rad]",
        unit="torsional_stiffness", ge=0, default=0.0, group="Follower load")


@dataclass(frozen=True, kw_only=True)
class MotionSegment:
    """One `[[motion]]` entry: a dwell, rise or return over `angle` degrees of cam rotation."""

    kind: str = param("Segment type", kind="str", choices=("dwell", "rise", "return"), group="Motion")
    angle: float = param("Span of the segment in cam degrees; all spans sum to 360",
                         unit="angle", ge=MIN_SPAN_DEG, group="Motion", bound_note=MIN_SPAN_NOTE)
    lift: float | None = param("Rise or fall height of the segment (rise/return only; > 0)",
                               unit="length", gt=0, optional=True, group="Motion")
    law: str | None = param(
        "Motion law (rise/return only): a closed form, \"bspline\" (control points), \"polynomial\" (the "
        "lowest-degree polynomial meeting the end conditions and points), \"constant_velocity\" (with blended "
        "ends) or \"table\" (a B-spline fitted to (angle, lift) points)", kind="str", choices=LAWS,
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
    table_tolerance: float | None = param(
        "Table: largest allowed distance |s_fit − s| of the fit from a table point (default 0.1% of the "
        "lift); the fewest knot spans meeting it are used",
        unit="length", gt=0, optional=True, group="Motion")


@dataclass(frozen=True, kw_only=True)
class GrooveSection:
    """`[groove]`: the groove of a groove (face) cam."""

    depth: float | None = param("Depth of the groove cut into the disc's top face (default: ⅔ of the "
                                "thickness)", unit="length", gt=0, optional=True, group="Groove")
    clearance: float | None = param(
        "Added to the roller's diameter: the groove width is 2·roller_radius + clearance (default 0.05 mm, "
        "0.002 in)", unit="length", ge=0, optional=True, group="Groove")
    min_wall: float | None = param(
        "Smallest material allowed between the groove and the rim, and between the groove and the bore (or hub "
        "holes) (default 3 mm, 0.12 in)", unit="length", ge=0, optional=True, group="Groove")


@dataclass(frozen=True, kw_only=True)
class ConjugateSection:
    """`[conjugate]`: the second cam and roller of a conjugate (dual) cam pair (cam.body = "conjugate")."""

    roller_distance: float | None = param(
        "Translating yoke: distance between the two roller centres along the follower's line of motion; the "
        "second roller sits on the other side of the cam axis", unit="length", gt=0, optional=True,
        group="Conjugate")
    arm_angle: float | None = param(
        "Oscillating arm pair: angle from the first arm to the second about the same pivot, counter-clockwise "
        "positive seen from +Z; the second arm lies on the other side of the line through the pivot and the "
        "cam axis", unit="angle", optional=True, group="Conjugate")
    arm_length: float | None = param(
        "Oscillating arm pair: length of the second arm, pivot to the second roller's centre (default: "
        "follower.arm_length)", unit="length", gt=0, optional=True, group="Conjugate")
    roller_radius: float | None = param("Radius of the second roller (default: follower.roller_radius)",
                                        unit="length", gt=0, optional=True, group="Conjugate")
    gap: float = param("Axial gap between the cams: the first cam spans 0 ≤ z ≤ cam.thickness, the second "
                       "−gap − cam.thickness ≤ z ≤ −gap; 0 (face to face) or at least 0.01 mm (0.0004 in)", unit="length", ge=0, default=0.0, group="Conjugate")
    spacer_diameter: float | None = param(
        "Diameter of the spacer that fills the gap and joins the cams into one solid (default: inside both "
        "cams' smallest radius, around the mounting holes)", unit="length", gt=0, optional=True,
        group="Conjugate")


@dataclass(frozen=True, kw_only=True)
class PitchSection:
    """`[pitch]`: how the pitch curve is represented."""

    representation: str = param("Pitch curve representation: C² PH quintic spline (exact rational "
                                "offset) or a periodic quintic B-spline fitted to the true pitch curve (kernel offset curve)",
                                kind="str", choices=("ph", "bspline"), default="ph", group="Pitch")
    segments: int | None = param(
        "Uniform junction count M over 360° (junction spacing 360°/M; for a B-spline pitch: its "
        "knot spans); default 60 when neither segments, tolerance nor motion[].junctions is given",
        kind="int", ge=8, le=MAX_SEGMENTS, optional=True, group="Pitch",
    )
    tolerance: float | None = param(
        "Target max follower-displacement deviation: chooses the smallest uniform M (B-spline: "
        "span count) that meets it; exclusive with segments",
        unit="length", gt=0, optional=True, group="Pitch",
    )


#: Young's modulus used when [material] gives none: steel, the thesis' 29×10⁶ psi (Ch. 7,
#: SAE 1010) = 199 948 MPa, in the spec's stress unit.
STEEL_MODULUS = {"in": 29.0e6, "mm": 29.0e6 * 6.894757293168361e-3}


@dataclass(frozen=True, kw_only=True)
class MaterialSection:
    """`[material]`: elastic constants of cam and follower for the Hertz contact stress (thesis Eq. 3.6)."""

    cam_modulus: float | None = param(
        "Young's modulus E_c of the cam (default: steel, 29×10⁶ psi = 199 948 MPa)",
        unit="stress", gt=0, optional=True, group="Material")
    cam_poisson: float = param("Poisson's ratio ν_c of the cam (thesis: 0.29, SAE 1010)",
                               ge=0, lt=0.5, default=0.29, group="Material")
    follower_modulus: float | None = param(
        "Young's modulus E_f of the roller (default: steel, 29×10⁶ psi = 199 948 MPa)",
        unit="stress", gt=0, optional=True, group="Material")
    follower_poisson: float = param("Poisson's ratio ν_f of the roller", ge=0, lt=0.5,
                                    default=0.29, group="Material")
    allowable_stress: float | None = param(
        "Allowable Hertz contact stress S_d (thesis Eq. 5.13; its examples: 250 000 psi); "
        "absent: the stress is reported, and the contact_stress check is skipped (not passed)",
        unit="stress", gt=0, optional=True, group="Material")

    def modulus(self, which: str, units: str) -> float:
        """E of "cam" or "follower" in the spec's stress unit (steel when not given)."""
        v = self.cam_modulus if which == "cam" else self.follower_modulus
        return STEEL_MODULUS[units] if v is None else v


@dataclass(frozen=True, kw_only=True)
class ChecksSection:
    """`[checks]`: limits and sampling of the design checks (thesis Ch. 3 and §5.3)."""

    max_pressure_angle: float = param(
        "Largest allowed magnitude of the pressure angle (thesis Eq. 3.4, 5.5; designers often allow 30°)",
        unit="angle", gt=0, lt=90, default=30.0, group="Checks")
    undercut_factor: float = param(
        "Safety factor on the roller radius: the convex pitch radius of curvature must be ≥ "
        "factor × roller radius (thesis Eq. 5.7 uses 1.5)", ge=1, default=1.5, group="Checks")
    min_force: float = param(
        "The driving force (thesis Eq. 3.5) must stay above this; 0 = no separation",
        unit="force", default=0.0, group="Checks")
    convex: bool = param(
        "The pitch curve must be convex everywhere (curvature κ = 1/ρ ≥ 0): the thesis' Eq. 5.7–5.8 "
        "read with the signed radius of curvature, whose concave parts violate 1.5·r_f − ρ ≤ 0",
        kind="bool", default=False, group="Checks")
    sampling: str = param(
        "\"dense\": `samples` equally spaced cam angles per rise/return (ends included) and "
        "refined extrema; \"thesis71\": the thesis' 71 nodes per rise/return (70 equal "
        "intervals of the B-spline parameter u; of θ for closed-form laws), no refinement",
        kind="str", choices=("dense", "thesis71"), default="dense", group="Checks")
    samples: int = param("Samples per rise or return in dense sampling (ends included)",
                         kind="int", ge=11, le=100001, default=1001, group="Checks")
    min_continuity: int | None = param(
        "Order of continuity every segment junction must reach (1 velocity, 2 acceleration, 3 jerk "
        "continuous), besides what the two laws there promise (absent: only their promise; 2 is Norton's "
        "fundamental law of cam design, which a harmonic rise next to a dwell breaks)",
        kind="int", ge=1, le=3, optional=True, group="Checks")


DEFAULT_SEGMENTS = 60

#: DXF versions the drawing can be written as (ezdxf's names); R12 has no SPLINE entity.
DXF_VERSIONS = ("R12", "R2000", "R2004", "R2007", "R2010", "R2013", "R2018")


@dataclass(frozen=True, kw_only=True)
class DrawingSection:
    """`[drawing]`: the DXF manufacturing drawing (cam.dxf) and the report's title."""

    curves: str = param(
        "How the profile, pitch curve and the body's other curves are written: \"cubic\" a polynomial "
        "(non-rational) cubic SPLINE within chord_tolerance, which every DXF reader draws; \"spline\" the profile NURBS "
        "itself (for a PH pitch curve the exact rational offset, degree 9, which LibreCAD and many CAM and "
        "laser programs drop without a word); \"arcs\" tangent arcs (biarcs, ARC/LINE entities) or "
        "\"polyline\" one closed polyline within chord_tolerance, for machines that read no splines",
        kind="str", choices=("cubic", "spline", "arcs", "polyline"), default="cubic", group="Drawing")
    chord_tolerance: float = param(
        "Largest distance of the drawn curves from the NURBS they stand for (curves = cubic, arcs or "
        "polyline; measured and stated in the title block)",
        unit="length", gt=0, default=0.001, group="Drawing")
    dxf_version: str = param(
        "DXF version of cam.dxf; R12 (for old CAM software) needs curves = arcs or polyline",
        kind="str", choices=DXF_VERSIONS, default="R2010", group="Drawing")
    title: str | None = param("Drawing and report title; default: the body's name (\"Plate cam\", \"Groove "
                              "cam\", \"Conjugate cam pair\", \"Cylindrical cam\"), which the drawing's title "
                              "block adds to a title that does not say it", kind="str", optional=True,
                              group="Drawing")
    part_number: str = param("Part or drawing number in the title block", kind="str", default="",
                             group="Drawing")
    author: str = param("Drawn by (title block)", kind="str", default="", group="Drawing")
    material: str = param("Material and treatment note in the title block, e.g. \"AISI 1045, 50 HRC\"",
                          kind="str", default="", group="Drawing")
    title_block: bool = param("Draw the title block with the key parameters and the motion table",
                              kind="bool", default=True, group="Drawing")
    dimensions: bool = param("Draw dimensions: bore diameter, base-circle radius, largest radius, "
                             "thickness note", kind="bool", default=True, group="Drawing")
    text_height: float | None = param(
        "Height of the drawing's text and arrows; default: the largest profile diameter / 36",
        unit="length", gt=0, optional=True, group="Drawing")
    spline_closed_flag: bool = param(
        "Set the DXF 'closed' bit on the profile SPLINE (AutoCAD's habit for closed clamped "
        "splines); off by default because CadQuery's DXF importer reads that bit as 'periodic' "
        "and drops the spline. The curve is closed either way (first pole = last pole)",
        kind="bool", default=False, group="Drawing")


WORK_OFFSETS = ("G54", "G55", "G56", "G57", "G58", "G59")
#: Most interpolator commands per revolution (memory bound).
MAX_COMMANDS_PER_REV = 10_000_000


@dataclass(frozen=True, kw_only=True)
class MachiningSection:
    """`[machining]`: how the cam is cut — tool, feeds, passes, the interpolator's sample period and the G-code dialect."""

    tool_radius: float | None = param(
        "Cutter (or grinding-wheel) radius. Default: the roller radius (the tool centre then runs on the "
        "pitch curve); for a knife edge base_radius/10 or half the smallest concave profile radius, "
        "whichever is smaller", unit="length", gt=0, optional=True, group="Machining")
    tool_number: int = param("Tool number: T word, tool change M6 and length offset G43 H",
                             kind="int", ge=1, default=1, group="Machining")
    spindle_rpm: float = param("Tool spindle speed (S word), clockwise (M3)", unit="spindle", gt=0,
                               default=3000.0, group="Machining")
    feed_rate: float | None = param("Contour feed rate of the XY program; default 300 mm/min (12 in/min)",
                                    unit="feed", gt=0, optional=True, group="Machining")
    plunge_rate: float | None = param("Feed rate of plunges and of the XC radial infeed; default feed_rate/3",
                                      unit="feed", gt=0, optional=True, group="Machining")
    sample_period: float = param(
        "Interpolator sample period Δt: one command (one G93 block of the XC program) per Δt (paper: 1 ms)",
        unit="time", gt=0, default=0.001, group="Machining")
    rotary_speed_rpm: float | None = param(
        "Cam speed on the machine's C axis while the interpolator's commands run (XC program, command "
        "table, interpolator report); default cam.speed_rpm", unit="speed", gt=0, optional=True,
        group="Machining")
    depth: float | None = param("Total cutting depth below the top face (Z = 0); default cam.thickness",
                                unit="length", gt=0, optional=True, group="Machining")
    passes: int = param("Number of equal depth passes", kind="int", ge=1, le=1000, default=1,
                        group="Machining")
    safe_height: float | None = param("Clearance height above the top face for rapid moves; "
                                      "default 5 mm (0.2 in)", unit="length", gt=0, optional=True,
                                      group="Machining")
    chord_tolerance: float | None = param(
        "Largest distance of the emitted arcs/lines (and of the XC blocks) from the exact tool-centre "
        "path; default 0.005 mm (0.0002 in)", unit="length", gt=0, optional=True, group="Machining")
    contour: str = param("XY contour moves: G02/G03 biarcs or G01 chords", kind="str",
                         choices=("arcs", "lines"), default="arcs", group="Machining")
    lead_radius: float | None = param(
        "Radius of the tangent lead-in/lead-out arcs (XY) and length of the radial approach (XC); "
        "default the tool radius", unit="length", gt=0, optional=True, group="Machining")
    milling: str = param("Outside contour milled climb or conventional (spindle clockwise, M3)", kind="str",
                         choices=("climb", "conventional"), default="climb", group="Machining")
    rotary_line: str | None = param(
        "XC program: the tool centre moves on the follower's own line (machine Y = −offset, C = cam "
        "angle) or on a line through the C axis (two-axis X–C machines); default the follower's line for a "
        "translating follower, the C axis for an oscillating one (which has no line)", kind="str",
        choices=("follower", "axis"), optional=True, group="Machining")
    work_offset: str = param("Work coordinate system: origin on the cam axis, Z = 0 on the top face",
                             kind="str", choices=WORK_OFFSETS, default="G54", group="Machining")
    line_numbers: bool = param("Number the blocks (N10, N20, …)", kind="bool", default=False,
                               group="Machining")
    coolant: bool = param("Flood coolant (M8) while cutting", kind="bool", default=False, group="Machining")
    program: str = param("Program that `build` writes to cam.nc: XY contour milling or XC rotary",
                         kind="str", choices=("xy", "xc"), default="xy", group="Machining")
    dialect: str = param("G-code dialect of cam.nc", kind="str", choices=("linuxcnc",),
                         default="linuxcnc", group="Machining")



#: Objectives of the optimiser (thesis Ch. 5): the thesis' cam area (Eq. 4.21, inside the pitch
#: curve), the true profile cross-section, the thesis' cutting time (Eq. 4.4–4.20), the time of the
#: project's own XY G-code contour, and the largest |s″| or |φ| (smoothest cam).
OBJECTIVES = ("area", "profile_area", "machining_time", "gcode_time", "peak_acceleration",
              "peak_pressure_angle", "outer_diameter")
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
        "only objective)",
        kind="str", choices=OBJECTIVES, default="area", group="Optimise")
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


#: Where the jump-speed sweep starts by default: this fraction of its top speed.
SWEEP_LOW_FRACTION = 0.05
#: Formats of `cam-workbench ecam` and the tables each can write (the first is its default).
ECAM_TABLES: dict[str, tuple[str, ...]] = {
    "csv": ("points",),
    "codesys": ("xyva", "poly5"),
    "beckhoff": ("motion_function", "position_table"),
    "lenze": ("points",),
}


@dataclass(frozen=True, kw_only=True)
class DynamicsSection:
    """`[dynamics]`: the follower train as a spring–mass–damper at speed — dynamic contact force, separation, the jump speed, residual vibration and the camshaft torque (docs/dynamics.md)."""

    enabled: bool = param(
        "Analyse the dynamics in build, report, check and Cam.report() (report.json's dynamics section, the "
        "report's figures); `cam-workbench dynamics` analyses them whatever this says",
        kind="bool", default=False, group="Dynamics")
    speed_rpm: float | None = param("Cam speed of the analysis (default cam.speed_rpm)", unit="speed", gt=0,
                                    optional=True, group="Dynamics")
    mass: float | None = param(
        "Translating: effective mass of the follower train (default follower.mass); count about a third of the "
        "return spring's own mass", unit="mass", gt=0, optional=True, group="Dynamics")
    arm_inertia: float | None = param(
        "Oscillating: effective moment of inertia of the arm train about the pivot (default follower.arm_inertia)",
        unit="inertia", gt=0, optional=True, group="Dynamics")
    stiffness: float | None = param(
        "Translating: stiffness k_f of the follower train between the cam contact and the lumped mass (roller, "
        "pin, stem, rocker); required for the dynamics of a translating follower",
        unit="stiffness", gt=0, optional=True, group="Dynamics")
    torsional_stiffness: float | None = param(
        "Oscillating: torsional stiffness of the arm train about the pivot between the cam contact and the lumped "
        "inertia; required for the dynamics of an oscillating follower",
        unit="torsional_stiffness", gt=0, optional=True, group="Dynamics")
    damping_ratio: float = param(
        "Damping ratio ζ of the follower train: a damper c = 2ζ·√(m·(k_f + k)) beside the train's spring",
        ge=0, lt=1, default=0.05, group="Dynamics")
    revolutions: int = param(
        "Most cam revolutions of the time integration when the follower leaves the cam (it stops as soon as one "
        "revolution repeats the one before)", kind="int", ge=1, le=1000, default=40, group="Dynamics")
    samples: int | None = param(
        "Samples per cam revolution of the periodic solve (default: 16 per natural period, at least 4096)",
        kind="int", ge=256, le=1048576, optional=True, group="Dynamics")
    sweep_min_rpm: float | None = param(
        f"Lowest cam speed of the jump-speed sweep (default {SWEEP_LOW_FRACTION:g} × sweep_max_rpm)",
        unit="speed", gt=0, optional=True, group="Dynamics")
    sweep_max_rpm: float | None = param(
        "Highest cam speed of the jump-speed sweep (default twice the rigid follower's jump speed, at least "
        "twice the analysis speed)", unit="speed", gt=0, optional=True, group="Dynamics")
    sweep_points: int = param("Cam speeds of the jump-speed sweep (0: no sweep)", kind="int", ge=0, le=10000,
                              default=100, group="Dynamics")


@dataclass(frozen=True, kw_only=True)
class EcamSection:
    """`[ecam]`: electronic-cam tables for servo motion controllers, written by `cam-workbench ecam` (docs/ecam.md)."""

    format: str = param("Table format: a CSV of θ, s, s′, s″, s‴; CODESYS SoftMotion; Beckhoff TwinCAT NC Camming; "
                        "Lenze Global Drive Cam Loader", kind="str", choices=tuple(ECAM_TABLES), default="csv",
                        group="Ecam")
    table: str = param(
        "Which table of the format: codesys \"xyva\" (SMC_CAMXYVA points) or \"poly5\" (CamBuilder Poly5 "
        "segments); beckhoff \"motion_function\" (MC_MotionFunctionPoint, 5th-order polynomials) or "
        "\"position_table\" (master/slave positions); csv and lenze \"points\"; \"auto\": the format's first",
        kind="str", choices=("auto", "points", "xyva", "poly5", "motion_function", "position_table"),
        default="auto", group="Ecam")
    step: float = param("Master step between table points in cam degrees", unit="angle", ge=0.001, le=90,
                        default=1.0, group="Ecam")
    boundaries: bool = param(
        "Also put a point at every motion-segment boundary (where a law's acceleration or jerk may jump); the "
        "table is then not equidistant unless the boundaries fall on the step", kind="bool", default=True,
        group="Ecam")
    name: str = param("Name of the cam in the PLC code (an IEC 61131-3 identifier)", kind="str", default="Cam",
                      group="Ecam")


#: Spec sections: TOML name → (dataclass, is an array of tables, required).  A new section
#: is a dataclass declared with ``param`` fields, an entry here and a field of CamSpec.
SECTIONS: dict[str, tuple[type, bool, bool]] = {
    "cam": (CamSection, False, True),
    "follower": (FollowerSection, False, True),
    "motion": (MotionSegment, True, True),
    "pitch": (PitchSection, False, False),
    "groove": (GrooveSection, False, False),
    "conjugate": (ConjugateSection, False, False),
    "material": (MaterialSection, False, False),
    "checks": (ChecksSection, False, False),
    "drawing": (DrawingSection, False, False),
    "machining": (MachiningSection, False, False),
    "optimise": (OptimiseSection, False, False),
    "dynamics": (DynamicsSection, False, False),
    "ecam": (EcamSection, False, False),
}


@dataclass(frozen=True, kw_only=True)
class CamSpec:
    """A complete, validated plate-cam description.  Build with :func:`load_spec`,
    :meth:`from_dict`, :meth:`from_kwargs` or :func:`default_spec`."""

    units: str = param("Length unit of the whole spec", kind="str", choices=("mm", "in"),
                       default="mm", group="Cam")
    cam: CamSection
    follower: FollowerSection
    motion: tuple[MotionSegment, ...]
    pitch: PitchSection = field(default_factory=PitchSection)
    groove: GrooveSection = field(default_factory=GrooveSection)
    conjugate: ConjugateSection = field(default_factory=ConjugateSection)
    material: MaterialSection = field(default_factory=MaterialSection)
    checks: ChecksSection = field(default_factory=ChecksSection)
    drawing: DrawingSection = field(default_factory=DrawingSection)
    machining: MachiningSection = field(default_factory=MachiningSection)
    optimise: OptimiseSection = field(default_factory=OptimiseSection)
    dynamics: DynamicsSection = field(default_factory=DynamicsSection)
    ecam: EcamSection = field(default_factory=EcamSection)

    # ---- construction -------------------------------------------------------------
    @classmethod
    def from_dict(cls, data: Mapping[str, Any], *, base_dir: str | Path | None = None) -> "CamSpec":
        """Build and validate a spec from the TOML structure as nested dicts/lists.

        ``base_dir``: the folder a ``motion[].table_file`` is relative to (:func:`load_spec` gives
        the spec file's; default the working directory).  The file is read into ``table``."""
        if not isinstance(data, Mapping):
            raise SpecError("spec", f"must be a table of sections, got {type(data).__name__}")
        _reject_unknown("", data, {"units", *SECTIONS})
        data = _inline_table_files(data, base_dir)
        data = _cylindrical_defaults(data)
        values: dict[str, Any] = {"units": params_of(CamSpec)["units"].check("units", data.get("units", "mm"))}
        for name, (section_cls, is_list, required) in SECTIONS.items():
            if name not in data:
                if required:
                    raise SpecError(name, "section is required")
                continue
            raw = data[name]
            if is_list:
                if not isinstance(raw, (list, tuple)) or not raw:
                    raise SpecError(name, f"must be a non-empty list of [[{name}]] tables")
                values[name] = tuple(_load_section(section_cls, m, f"{name}[{i}]") for i, m in enumerate(raw))
            else:
                values[name] = _load_section(section_cls, raw, name)
        spec = cls(**values)
        validate(spec)
        return spec

    @classmethod
    def from_kwargs(cls, **sections: Any) -> "CamSpec":
        """Same as :meth:`from_dict` with the top-level keys as keyword arguments."""
        return cls.from_dict(sections)

    def to_dict(self) -> dict[str, Any]:
        """The spec as the TOML structure (None-valued optional fields left out)."""
        out: dict[str, Any] = {"units": self.units}
        for f in dataclasses.fields(self):
            if f.name == "units":
                continue
            v = getattr(self, f.name)
            if isinstance(v, tuple):
                out[f.name] = [_section_dict(s) for s in v]
            else:
                out[f.name] = _section_dict(v)
        return out

    def replace(self, **changes: Any) -> "CamSpec":
        """A validated copy with dotted-path changes, e.g. ``replace(**{"cam.base_radius": 30})``
        or ``replace(**{"motion[1].lift": 12})``."""
        data = self.to_dict()
        for path, value in changes.items():
            _set_path(data, path, value)
        follow_cylinder_fields(data, changes)
        return CamSpec.from_dict(data)

    # ---- derived quantities ---------------------------------------------------------
    @property
    def is_roller(self) -> bool:
        return self.follower.kind == "roller"

    @property
    def roller_radius(self) -> float:
        """Roller radius, 0 for a knife edge."""
        return self.follower.roller_radius if self.is_roller else 0.0

    @property
    def prime_offset(self) -> float:
        """s₀ = √(R_b² − e²): distance along the follower line from the axis to the pitch point at zero lift."""
        return math.sqrt(self.cam.base_radius**2 - self.follower.offset**2)

    @property
    def max_lift(self) -> float:
        """Largest follower displacement of the program."""
        level, top = 0.0, 0.0
        for seg in self.motion:
            if seg.kind == "rise":
                level += seg.lift or 0.0
            elif seg.kind == "return":
                level -= seg.lift or 0.0
            top = max(top, level)
        return top


def _section_dict(obj: Any) -> dict[str, Any]:
    out = {}
    for f in dataclasses.fields(obj):
        v = getattr(obj, f.name)
        if v is None:
            continue
        if dataclasses.is_dataclass(v):
            v = _section_dict(v)
        elif isinstance(v, tuple):
            v = [(_section_dict(x) if dataclasses.is_dataclass(x) else
                  (list(x) if isinstance(x, tuple) else x)) for x in v]
        out[f.name] = v
    return out


def _set_path(data: dict[str, Any], path: str, value: Any) -> None:
    """Set the field at a dotted ``path`` (``cam.base_radius``, ``motion[1].lift``) in the spec's
    TOML structure; a path that does not fit the structure is a SpecError naming it."""
    if not isinstance(path, str) or not path:
        raise SpecError(str(path) or "--set", "is not a valid field path (write e.g. cam.base_radius=30)")
    parts = path.split(".")
    node: Any = data
    where = ""
    for i, part in enumerate(parts):
        m = re.fullmatch(r"([A-Za-z_]\w*)(?:\[(\d+)\])?", part)
        if not m:
            raise SpecError(path, "is not a valid field path (write e.g. cam.base_radius or motion[1].lift)")
        key, idx = m.group(1), m.group(2)
        last = i == len(parts) - 1
        if not isinstance(node, dict):
            raise SpecError(path, f"{where or 'the spec'} is a value, not a table: it has no field {key!r}")
        here = f"{where}.{key}" if where else key
        if idx is not None:
            node = node.setdefault(key, [])
            if not isinstance(node, list):
                raise SpecError(path, f"{here} is not a list: write {here}.FIELD without an index")
            k = int(idx)
            if k >= len(node):
                raise SpecError(path, f"index {k} is out of range (there are {len(node)})")
            here = f"{here}[{k}]"
            if last:
                node[k] = value
            else:
                node = node[k]
        elif last:
            if value is None:
                node.pop(key, None)
            else:
                node[key] = value
        else:
            nxt = node.setdefault(key, {})
            if isinstance(nxt, list):
                raise SpecError(path, f"{here} is a list of tables: write {here}[i].{parts[i + 1]}")
            node = nxt
        where = here


def follow_cylinder_fields(data: dict[str, Any], changes: Mapping[str, Any]) -> None:
    """In a spec dict of a cylindrical cam whose ``changes`` (dotted paths) set cam.cylinder_radius or
    cam.length but not cam.base_radius or cam.thickness, make those follow (in place): they are the
    same numbers (the body's rules)."""
    cam = data.get("cam")
    if not isinstance(cam, dict) or cam.get("body") != "cylindrical":
        return
    for k, src in (("base_radius", "cylinder_radius"), ("thickness", "length")):
        if f"cam.{src}" in changes and f"cam.{k}" not in changes and src in cam:
            cam[k] = cam[src]


def _cylindrical_defaults(data: Mapping[str, Any]) -> Mapping[str, Any]:
    """A cylindrical cam's ``cam.base_radius`` and ``cam.thickness`` are its ``cylinder_radius`` and
    ``length``: filled in when absent (a copy); when given they must agree (the body's rules)."""
    cam = data.get("cam")
    if not isinstance(cam, Mapping) or cam.get("body") != "cylindrical":
        return data
    pairs = (("base_radius", "cylinder_radius"), ("thickness", "length"))
    for k, src in pairs:
        if src not in cam:
            raise SpecError(f"cam.{src}", "is required for a cylindrical cam")
    fill = {k: cam[src] for k, src in pairs if k not in cam}
    if not fill:
        return data
    out = dict(data)
    out["cam"] = {**cam, **fill}
    return out


def _inline_table_files(data: Mapping[str, Any], base_dir: str | Path | None) -> Mapping[str, Any]:
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


def _reject_unknown(prefix: str, data: Mapping[str, Any], known: set[str]) -> None:
    for key in data:
        if key not in known:
            path = f"{prefix}.{key}" if prefix else str(key)
            raise SpecError(path, f"unknown field (known fields: {', '.join(sorted(known))})")


def _load_section(cls: type, data: Any, path: str) -> Any:
    """Load one section table into its dataclass, checking every declared parameter."""
    if not isinstance(data, Mapping):
        raise SpecError(path, f"must be a table, got {data!r}")
    decl = params_of(cls)
    _reject_unknown(path, data, set(decl))
    precheck = getattr(cls, "precheck", None)
    if precheck is not None:
        precheck(data, path)
    values = {}
    for name, p in decl.items():
        fpath = f"{path}.{name}"
        if name in data:
            values[name] = p.check(fpath, data[name])
        elif p.default is REQUIRED:
            raise SpecError(fpath, "is required")
        elif p.optional:
            values[name] = None
    return cls(**values)


# ---- cross-field validation ----------------------------------------------------------
def validate(spec: CamSpec) -> None:
    """Check every rule of CAM_SPEC.md that involves more than one field; raise SpecError."""
    cam, fol = spec.cam, spec.follower
    if fol.kind == "roller" and not fol.roller_radius > 0:
        raise SpecError("follower.roller_radius", f"must be > 0 for a roller follower, got {fmt_apart(fol.roller_radius, 0)}")
    _validate_follower_motion(spec)
    _validate_face(spec)
    if not abs(fol.offset) < cam.base_radius:
        raise SpecError("follower.offset",
                        f"|offset| must be < cam.base_radius ({fmt_apart(cam.base_radius, abs(fol.offset))}), got "
                        f"{fmt_apart(fol.offset, math.copysign(cam.base_radius, fol.offset))}")
    if spec.is_roller and not cam.base_radius > fol.roller_radius:
        raise SpecError("cam.base_radius",
                        f"must be > follower.roller_radius ({fmt_apart(fol.roller_radius, cam.base_radius)}), got "
                        f"{fmt_apart(cam.base_radius, fol.roller_radius)}")
    r_surface = cam.base_radius - spec.roller_radius
    if not cam.bore_diameter < 2 * r_surface:
        raise SpecError("cam.bore_diameter",
                        f"must be < 2 × smallest cam-surface radius = 2 × (cam.base_radius {cam.base_radius:g} − "
                        f"follower.roller_radius {spec.roller_radius:g}) = {fmt_apart(2 * r_surface, cam.bore_diameter)}, "
                        f"got {fmt_apart(cam.bore_diameter, 2 * r_surface)}: a smaller bore or roller, or a larger base "
                        "radius")
    _validate_motion(spec)
    follower_class_of(spec).validate(spec)     # the kinds' own rules, then the features every body shares
    body_of(spec).validate(spec)
    validate_features(spec)
    _validate_pitch(spec)
    _validate_drawing(spec)
    _validate_machining(spec)
    _validate_optimise(spec)
    validate_dynamics(spec)                    # the train's rules (and, when enabled, its data)
    _validate_ecam(spec)


#: The most points an e-cam table may have (CODESYS counts its elements in an INT).
MAX_ECAM_POINTS = 200_000
_IEC_IDENTIFIER = re.compile(r"^[A-Za-z_][A-Za-z0-9_]{0,63}$")


def _validate_ecam(spec: CamSpec) -> None:
    ec = spec.ecam
    if ec.table != "auto" and ec.table not in ECAM_TABLES[ec.format]:
        raise SpecError("ecam.table", f"{ec.table!r} is not a table of ecam.format = {ec.format!r} (its tables: "
                        f"{', '.join(ECAM_TABLES[ec.format])})")
    if not _IEC_IDENTIFIER.match(ec.name) or "__" in ec.name:
        raise SpecError("ecam.name", f"must be an IEC 61131-3 identifier (a letter or _, then letters, digits, "
                        f"single underscores; at most 64 characters), got {ec.name!r}")
    points = math.ceil(360.0 / ec.step - 1e-9) + 1
    if points > MAX_ECAM_POINTS:
        raise SpecError("ecam.step", f"gives {points} table points; at most {MAX_ECAM_POINTS}")


#: fields that only one follower motion may have (a typo or a leftover must not be ignored)
TRANSLATING_ONLY = {"mass": "arm_inertia", "preload": "preload_torque", "spring_rate": "spring_torque_rate"}
OSCILLATING_ONLY = ("pivot_distance", "arm_length", "face_offset", "arm_inertia", "preload_torque",
                    "spring_torque_rate")


def _validate_follower_motion(spec: CamSpec) -> None:
    fol = spec.follower
    if fol.motion == "translating":
        for name in OSCILLATING_ONLY:
            v = getattr(fol, name)
            if v is not None and v != 0:
                raise SpecError(f"follower.{name}", 'applies to oscillating followers only (follower.motion = '
                                '"oscillating")')
        return
    if fol.offset != 0:
        raise SpecError("follower.offset", "applies to translating followers only: an oscillating follower's "
                        "position is follower.pivot_distance and follower.arm_length")
    for name, instead in TRANSLATING_ONLY.items():
        if getattr(fol, name) != 0:
            raise SpecError(f"follower.{name}", f"applies to translating followers only: for an oscillating "
                            f"arm give follower.{instead}")
    if fol.pivot_distance is None:
        raise SpecError("follower.pivot_distance", "is required for an oscillating follower")
    if fol.kind != "flat" and fol.arm_length is None:
        raise SpecError("follower.arm_length", f"is required for an oscillating {fol.kind} follower")
    if fol.kind != "flat" and fol.face_offset is not None:
        raise SpecError("follower.face_offset", "applies to flat-faced followers only")


def _validate_face(spec: CamSpec) -> None:
    if spec.follower.kind != "flat" and spec.follower.face_width is not None:
        raise SpecError("follower.face_width", "applies to flat-faced followers only")


MAX_MOTION_SEGMENTS = 100


def _validate_motion(spec: CamSpec) -> None:
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
    if not lifts:
        raise SpecError("motion", "needs at least one rise and one return")
    if abs(level) > 1e-9 * max(lifts):
        raise SpecError("motion",
                        f"program does not close: total rise − total fall = {level:g}, must be 0")
    # the laws solved from boundary conditions or fitted, s ≥ 0 inside every segment, the program's
    # junction values (cam_workbench.generators.motion.segments): errors name the field
    MotionProgram.from_segments(spec.motion)
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


def _validate_pitch(spec: CamSpec) -> None:
    pt = spec.pitch
    if pt.tolerance is not None and pt.tolerance < 1e-9 * spec.cam.base_radius:
        low = 1e-9 * spec.cam.base_radius
        raise SpecError("pitch.tolerance", f"must be ≥ 1e-9 × cam.base_radius ({fmt_apart(low, pt.tolerance)}): "
                                           f"below that the deviation is rounding noise, got {fmt_apart(pt.tolerance, low)}")
    if pt.segments is not None and pt.tolerance is not None:
        raise SpecError("pitch.tolerance", "is exclusive with pitch.segments: give one of them")
    if pt.representation == "bspline" and spec.motion[0].junctions is not None:
        raise SpecError("motion[0].junctions", 'sets PH junctions; not used with pitch.representation = "bspline"')
    if spec.motion[0].junctions is not None:
        total = sum(seg.junctions or 0 for seg in spec.motion)
        if pt.tolerance is not None:
            raise SpecError("pitch.tolerance", "is exclusive with motion[].junctions")
        if pt.segments is not None and pt.segments != total:
            raise SpecError("pitch.segments",
                            f"is {pt.segments} but motion[].junctions sum to {total}: give one of them")
        if total < 8:
            raise SpecError("motion[].junctions", f"sum to {total}, must be ≥ 8")


def _validate_drawing(spec: CamSpec) -> None:
    dr = spec.drawing
    if dr.chord_tolerance is not None and dr.chord_tolerance < 1e-7 * spec.cam.base_radius:
        low = 1e-7 * spec.cam.base_radius
        raise SpecError("drawing.chord_tolerance", f"must be ≥ 1e-7 × cam.base_radius ({fmt_apart(low, dr.chord_tolerance)}), "
                                                   f"got {fmt_apart(dr.chord_tolerance, low)}")
    if dr.dxf_version == "R12" and dr.curves in ("cubic", "spline"):
        raise SpecError("drawing.dxf_version",
                        "R12 has no SPLINE entity: use drawing.curves = \"arcs\" or \"polyline\" with R12")


def _validate_machining(spec: CamSpec) -> None:
    mc = spec.machining
    if mc.rotary_line == "follower" and spec.follower.motion != "translating":
        raise SpecError("machining.rotary_line", '"follower" needs a translating follower\'s line of motion; an '
                        'oscillating arm has none: use "axis" (the default for an oscillating follower)')
    rpm = mc.rotary_speed_rpm if mc.rotary_speed_rpm is not None else spec.cam.speed_rpm
    step = 360.0 * rpm / 60.0 * mc.sample_period
    # (a coarse step is not an error here: it only matters for the XC program, whose
    # blocks are checked against machining.chord_tolerance when it is made)
    if 360.0 / step > MAX_COMMANDS_PER_REV:
        raise SpecError("machining.sample_period",
                        f"gives {fmt_apart(360.0 / step, MAX_COMMANDS_PER_REV, 4)} commands per revolution at {rpm:g} "
                        f"rpm; must be ≤ {MAX_COMMANDS_PER_REV:,}: a longer period (or a faster "
                        "machining.rotary_speed_rpm)")
    if mc.chord_tolerance is not None and mc.chord_tolerance < 1e-7 * spec.cam.base_radius:
        low = 1e-7 * spec.cam.base_radius
        raise SpecError("machining.chord_tolerance", f"must be ≥ 1e-7 × cam.base_radius ({fmt_apart(low, mc.chord_tolerance)}), "
                                                     f"got {fmt_apart(mc.chord_tolerance, low)}")
    if mc.chord_tolerance is not None and not mc.chord_tolerance < spec.cam.base_radius / 100:
        raise SpecError("machining.chord_tolerance",
                        f"must be < 1% of cam.base_radius ({fmt_apart(spec.cam.base_radius / 100, mc.chord_tolerance)}), "
                        f"got {fmt_apart(mc.chord_tolerance, spec.cam.base_radius / 100)}")


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


def _validate_optimise(spec: CamSpec) -> None:
    opt = spec.optimise
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


# ---- loading ---------------------------------------------------------------------
def load_spec(source: str | Path | Mapping[str, Any]) -> CamSpec:
    """Load a spec from a TOML file path, TOML text, or a dict.

    Raises:
        SpecError: a rule is broken; the message names the field and the rule.
    """
    if isinstance(source, Mapping):
        return CamSpec.from_dict(source)
    text: str
    p = Path(source) if not (isinstance(source, str) and "\n" in source) else None
    if p is not None:
        try:
            if p.stat().st_size > MAX_SPEC_BYTES:
                raise SpecError(str(source), f"is larger than {MAX_SPEC_BYTES // 1000} kB: not a cam spec")
            raw = p.read_bytes()
        except FileNotFoundError:
            raise SpecError(str(source), "file not found") from None
        except OSError as exc:
            raise SpecError(str(source), f"cannot be read ({exc.strerror})") from None
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise SpecError(str(source), f"is not UTF-8 text (byte {exc.start}): a TOML spec is UTF-8") from None
    else:
        text = str(source)
    where = str(p) if p else "spec"
    if "\x00" in text:
        raise SpecError(where, "holds NUL bytes: not a TOML text")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(where, f"is not valid TOML ({exc})") from None
    except RecursionError:
        raise SpecError(where, "is nested too deeply to be a cam spec") from None
    return CamSpec.from_dict(data, base_dir=p.parent if p is not None else None)


#: A spec file larger than this is refused before it is read.
MAX_SPEC_BYTES = 1_000_000


def default_spec() -> CamSpec:
    """The built-in default cam (``make demo``'s): the paper's motion program — cycloidal 20 mm
    rise and return over 120° with 30°/60°/30° dwells (Jahanpour & Dolatabadi 2014, Table 1) —
    on a 40 mm base radius with a radial 8 mm roller, 10 mm thick, 12 mm bore, a follower of
    0.5 kg held by a 20 N preload and a 1 N/mm spring, at 60 rpm, contact stress limited to
    1000 MPa.  It passes every design check.  The paper's own case-2 cam (e = 10 mm, which
    fails the 30° pressure-angle limit) is ``cam_workbench.generators.spec.examples.example_spec("paper")``."""
    return CamSpec.from_dict(DEFAULT_SPEC_DICT)


DEFAULT_SPEC_DICT: dict[str, Any] = {
    "units": "mm",
    "cam": {"base_radius": 40.0, "thickness": 10.0, "bore_diameter": 12.0,
            "direction": "ccw", "speed_rpm": 60.0},
    "follower": {"kind": "roller", "offset": 0.0, "roller_radius": 8.0,
                 "mass": 0.5, "preload": 20.0, "spring_rate": 1.0},
    "motion": [
        {"kind": "dwell", "angle": 30.0},
        {"kind": "rise", "angle": 120.0, "lift": 20.0, "law": "cycloidal"},
        {"kind": "dwell", "angle": 60.0},
        {"kind": "return", "angle": 120.0, "lift": 20.0, "law": "cycloidal"},
        {"kind": "dwell", "angle": 30.0},
    ],
    "pitch": {"representation": "ph", "segments": 60},
    "material": {"allowable_stress": 1000.0},
}


def to_toml(spec: CamSpec) -> str:
    """Serialise a spec as TOML text (readable by :func:`load_spec`)."""
    return dict_to_toml(spec.to_dict())


def dict_to_toml(data: Mapping[str, Any]) -> str:
    """A small TOML writer for the spec's structure: scalars, lists, tables, arrays of tables."""
    lines: list[str] = []
    scalars = {k: v for k, v in data.items() if not isinstance(v, (Mapping, list)) or
               (isinstance(v, list) and not (v and isinstance(v[0], Mapping)))}
    for k, v in scalars.items():
        lines.append(f"{k} = {_toml_value(v)}")
    for k, v in data.items():
        if k in scalars:
            continue
        if isinstance(v, Mapping):
            lines.append("")
            lines.append(f"[{k}]")
            lines.extend(_toml_table_body(v, k))
        else:
            for item in v:
                lines.append("")
                lines.append(f"[[{k}]]")
                lines.extend(_toml_table_body(item, k))
    return "\n".join(lines).lstrip("\n") + "\n"


def _toml_table_body(table: Mapping[str, Any], prefix: str) -> list[str]:
    out, subs = [], []
    for k, v in table.items():
        if isinstance(v, Mapping):
            subs.append((k, v))
        else:
            out.append(f"{k} = {_toml_value(v)}")
    for k, v in subs:
        out.append("")
        out.append(f"[{prefix}.{k}]")
        out.extend(_toml_table_body(v, f"{prefix}.{k}"))
    return out


def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v) if math.isfinite(v) else ("inf" if v > 0 else "-inf" if v < 0 else "nan")
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {v!r} as TOML")


__all__ = [
    "CamSpec", "CamSection", "FollowerSection", "MotionSegment", "PitchSection", "MaterialSection",
    "ChecksSection", "MachiningSection", "DrawingSection", "OptimiseSection", "DynamicsSection", "EcamSection",
    "ECAM_TABLES", "Param",
    "load_spec", "default_spec", "to_toml", "validate", "LAWS", "DEFAULT_SEGMENTS", "SECTIONS",
    "spec_digest",
]


def spec_digest(spec: CamSpec) -> str:
    """SHA-256 of the spec's canonical TOML without ``[checks]``, ``[optimise]``, ``[dynamics]`` and
    ``[ecam]`` (how to check, optimise, analyse or export, not what):
    names the cam a report was made from."""
    data = spec.to_dict()
    for how in ("checks", "optimise", "dynamics", "ecam"):
        data.pop(how, None)
    return hashlib.sha256(dict_to_toml(data).encode("utf-8")).hexdigest()

"""The conjugate (dual) cam pair: two plate cams on one shaft driving one follower through two
rollers, so the follower is held both ways without a spring (form closure).

The first cam is the spec's own plate cam (its PH pitch curve, the exact offset by the roller
radius).  The second roller is fixed to the same follower body (:mod:`cam_workbench.generators.followers.conjugate`:
on the yoke, ``conjugate.roller_distance`` below the first on its line of motion; or on a second
arm at ``conjugate.arm_angle`` about the same pivot); its centre's path in the cam frame is the
second cam's pitch curve, built as the first's — the C² PH quintic spline through the second
roller's centres at the same junction angles (its own uniform count when ``pitch.tolerance``
chooses it) — and the second cam's profile is its exact rational offset by the second roller's
radius.  Both cams are designed from the same motion, so with exact curves both rollers touch
at every angle; the built curves' errors leave a **distance error between the rollers**: at cam
angle θ the first cam puts the follower at lift s₁(θ) (its roller touching the built first
pitch curve: Eq. 13 generalised), the second cam at s₂(θ); where they differ the follower
cannot touch both — its second roller is |F₂(s₁) − F₂(s₂)| from where the second cam wants it,
along its path (+: interference, the cams squeeze the follower; −: play).  It is bounded by the
sum of the two curves' own deviations (s₁ − s₂ = (s₁ − s) − (s₂ − s)) and reported against them.

Layout (cam frame): the first cam spans 0 ≤ z ≤ cam.thickness (its top face carries the timing
mark), the second −gap − thickness ≤ z ≤ −gap, a spacer disc fills the gap (when there is one)
and joins them into one solid, the hub stands below the second cam; bore, keyway and mounting
holes go through everything.  Which cam drives where: the first while the follower needs a push
away from the cam axis (its contact force positive), the second while it must be pulled back.
"""
from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from ..cam_design import CamDesign, profile_offset_distance, refuse_undercut
from ..checks.buildability import check_bore, check_self_intersection, check_undercut, pitch_curvature_samples
from ..curves.offsets import offset_nurbs, pitch_nurbs
from ..errors import GeometryError, SpecError, fmt_apart
from ..followers.conjugate import second_roller_of
from ..followers.oscillating import zero_lift_arm_angle
from ..kinds import follower_class_of, pitch_of, register_body
from ..motion.program import Kinematics
from ..pitch.ph import build_pitch_curve, segments_for_tolerance
from ..spec.optimise import OBJECTIVES
from .base import BodyGeometry, Loop, Prism
from .features import bore_extent, bore_loop, hub_prism, mounting_holes, resolved, timing_mark, zero_angle
from .groove import force_sides
from .plane import PlaneCamBody
from .plate import feature_checks, profile_radius_along

#: the suffix of the second cam's check names (``pressure_angle_cam2``, …)
SECOND = "cam2"


@register_body
class ConjugateBody(PlaneCamBody):
    """Two plate cams stacked on one shaft, each driving its own roller of one follower."""

    kind = "conjugate"
    plane = True
    roller_within_base = True
    dynamics_train = "follower"
    #: the field that sizes the cam
    size_field = "cam.base_radius"
    #: the legend of the body's first added region in the cam drawing (None: the profile's)
    drawing_label = None
    #: the objectives its optimiser serves (optimise.objective; outer_diameter: a groove's disc)
    optimise_objectives = tuple(o for o in OBJECTIVES if o != "outer_diameter")
    #: the optimiser's design variables this body adds (optimise.variables)
    optimise_variables = ()
    own_fields = ()
    modules = ("cam_workbench.generators.followers.conjugate",)
    title = "Conjugate cam pair"
    #: the two cams hold the follower both ways (form closure): it cannot leave them
    closure = "form"
    #: which side drives (the follower dynamics' form-closure note)
    drive_note = ("the two cams hold the follower both ways; the cam that drives changes where the contact force "
                  "changes sign (positive: pushing the follower away from the cam axis, the first cam; "
                  "negative: the second cam)")

    @staticmethod
    def validate(spec) -> None:
        validate_conjugate(spec)

    @staticmethod
    def refuse_foreign(spec) -> None:
        refuse_stray_fields(spec)

    @staticmethod
    def profile_inset(spec) -> float:
        return 0.0

    @staticmethod
    def machining_defaults(spec) -> dict[str, float | None]:
        """Each cam is cut as a plate cam: the whole thickness, a tool of the roller's size."""
        return {"depth": spec.cam.thickness, "tool_radius": None}

    @staticmethod
    def label(spec) -> str:
        """The numbers that identify a conjugate pair (spec lengths, no unit): R_b, each cam's thickness,
        the gap, and the second roller in its own words."""
        return (f"R_b = {spec.cam.base_radius:g}, two cams {spec.cam.thickness:g} thick, gap {spec.conjugate.gap:g}; "
                f"{second_roller_of(spec).label()}")

    @staticmethod
    def further_followers(spec) -> tuple:
        """The second roller, whose contact with the second cam the design checks cover too."""
        return ((SECOND, second_roller_of(spec)),)

    @staticmethod
    def reverse_contact_stress(model, force: np.ndarray, rho: np.ndarray) -> np.ndarray:
        """Where a cam's contact force is negative the other cam drives: this cam's roller is
        unloaded (0); the other cam's own checks report the stress there."""
        return np.zeros(np.shape(force))

    @staticmethod
    def geometry(design) -> BodyGeometry:
        spec = design.spec
        cam = spec.cam
        t, gap = cam.thickness, spec.conjugate.gap
        second = second_cam(design)
        bore = bore_loop(spec)
        holes = (bore,) if bore else ()
        z2 = (-gap - t, 0.0 - gap)
        # the keyway and holes must leave material in both cams (SpecError naming the field)
        features = feature_checks(design, lambda a: np.minimum(profile_radius_along(design.profile, a),
                                                               profile_radius_along(second.profile, a)),
                                  "profiles")
        prisms = [Prism(Loop.nurbs(design.profile, "profile"), holes, 0.0, t, "add", "plate"),
                  Prism(Loop.nurbs(second.profile, "profile_2"), holes, z2[0], z2[1], "add", "plate_2")]
        r_sp = spacer_radius(design, second) if gap > 0 else None
        if r_sp is not None:
            prisms.append(Prism(Loop.circle(r_sp, role="spacer"), holes, -gap, 0.0, "add", "spacer"))
        hub = hub_prism(spec, z_top=z2[0])
        if hub is not None:
            prisms.append(hub)
        prisms += _holes(spec, r_sp, z2, t)
        w_mark = resolved(spec, "cam", "timing_mark_width")
        mark = timing_mark(spec, zero_angle(design), bore_extent(spec) + 1.5 * w_mark,
                           design.min_profile_radius - 1.5 * w_mark, t)
        if mark is not None:
            prisms.append(mark)
        return BodyGeometry("conjugate", tuple(prisms), {
            "second_cam": second, "spacer_radius": r_sp, "features": features,
            # further curves a drawing shows, by layer
            "drawing_curves": {"PITCH_2": second.pitch_nurbs}})

    @staticmethod
    def report(design, geometry: BodyGeometry) -> dict[str, Any]:
        """The pair's numbers: each cam's place, radii and sections, the spacer, the distance error
        between the rollers and which cam drives where (nothing to refuse: the second cam's
        refusals are its design's, in :meth:`geometry`)."""
        spec = design.spec
        t, gap = spec.cam.thickness, spec.conjugate.gap
        second = geometry.extra["second_cam"]
        r_sp = geometry.extra["spacer_radius"]
        sections = second.cam_sections()
        fol2 = second.follower
        sections["profile"]["base_circle_radius"] = fol2.prime_radius - fol2.profile_offset
        out: dict[str, Any] = {
            "closure": "form",
            "gap": gap,
            "spacer_diameter": None if r_sp is None else 2 * r_sp,
            "first_cam": {"z": [0.0, t], "roller_radius": design.follower.profile_offset,
                          "profile_area": design.profile_area, "min_radius": design.min_profile_radius,
                          "max_radius": design.max_profile_radius()[0]},
            "second_cam": {"z": [-gap - t, -gap], "roller_radius": fol2.profile_offset,
                           "profile_area": second.profile_area, "min_radius": second.min_profile_radius,
                           "max_radius": sections["profile"]["max_radius"], **sections},
            "roller_distance_error": roller_distance_error(design.pitch, second.pitch).summary(spec.units),
            "drive": drive_cams(design),
            **geometry.extra["features"],
        }
        return out


def second_cam(design):
    """The second cam of a conjugate design: a :class:`~cam_workbench.generators.cam_design.CamDesign` of the
    second roller — its PH pitch curve (the first's junction angles, or its own uniform count
    for ``pitch.tolerance``), the exact offset by its roller radius, its buildability checks.

    Raises:
        GeometryError: the second cam undercuts, crosses itself or is cut by the bore (the
            message says "second cam", with the cam angle).
    """
    spec = design.spec
    fol = second_roller_of(spec)
    r2 = fol.roller_radius
    try:
        if design.checks is not None:
            refuse_undercut(design.checks, r2, f"undercut_{SECOND}", f"curvature_{SECOND}")
        if spec.pitch.tolerance is not None:
            pitch = segments_for_tolerance(spec, spec.pitch.tolerance, follower=fol)[0]
        else:
            pitch = build_pitch_curve(design.program, fol, design.pitch.angles)
        cs = pitch_curvature_samples(pitch)
        check_undercut(pitch, r2, cs)
        profile = offset_nurbs(pitch.spline, profile_offset_distance(pitch, r2))
        check_self_intersection(profile, pitch)
        rmin = check_bore(profile, pitch, spec.cam.bore_diameter)
    except GeometryError as exc:
        raise GeometryError(exc.kind, f"second cam: {exc}", exc.angle_deg) from None
    return CamDesign(spec=spec, pitch=pitch, pitch_nurbs=pitch_nurbs(pitch.spline), profile=profile,
                     max_deviation=pitch.max_deviation(), min_profile_radius=rmin, curvature_samples=cs,
                     checks=design.checks)


def spacer_radius(design, second) -> float:
    """The spacer's radius: ``conjugate.spacer_diameter``/2, else 0.9 × the smaller of the two
    cams' smallest radius — moved between the mounting holes' outer edge and that radius when
    the circle would cut through the holes.

    Raises:
        SpecError: ``conjugate.spacer_diameter`` — it leaves no material around the bore, or
            reaches beyond a cam's profile.
    """
    spec = design.spec
    cam = spec.cam
    r_min = min(design.min_profile_radius, second.min_profile_radius)
    given = spec.conjugate.spacer_diameter
    if given is None:
        r = 0.9 * r_min
        if cam.mounting_holes:
            rc, rh = cam.mounting_circle_diameter / 2, cam.mounting_hole_diameter / 2
            if rc - rh <= r <= rc + rh:
                r = 0.5 * (rc + rh + r_min)
    else:
        r = given / 2
        if not r < r_min:
            raise SpecError("conjugate.spacer_diameter", f"must stay inside both cams: their smallest radius is "
                            f"{r_min:.4g} (diameter {fmt_apart(2 * r_min, given, 4)}), got {fmt_apart(given, 2 * r_min)}")
    reach = bore_extent(spec)
    if not r > reach:
        raise SpecError("conjugate.spacer_diameter", f"must leave material around the bore and keyway (they reach "
                        f"{fmt_apart(reach, r, 4)} from the axis), got a spacer of diameter {fmt_apart(2 * r, 2 * reach, 4)}")
    return float(r)


def _holes(spec, r_sp: float | None, z2: tuple[float, float], t: float) -> list[Prism]:
    """The mounting holes through both cams (and the spacer, when they lie inside it)."""
    cam = spec.cam
    if not cam.mounting_holes:
        return []
    rc, rh = cam.mounting_circle_diameter / 2, cam.mounting_hole_diameter / 2
    if r_sp is None or rc + rh < r_sp:
        return mounting_holes(spec, z2[0], t)
    if rc - rh > r_sp:
        second = [dataclasses.replace(p, role=p.role + "_2") for p in mounting_holes(spec, *z2)]
        return mounting_holes(spec, 0.0, t) + second
    edge = rc - rh if r_sp - (rc - rh) < (rc + rh) - r_sp else rc + rh        # the nearer edge of the holes
    raise SpecError("conjugate.spacer_diameter", f"the spacer's rim (radius {fmt_apart(r_sp, edge, 4)}) cuts through "
                    f"the mounting holes ({fmt_apart(rc - rh, r_sp, 4)} to {fmt_apart(rc + rh, r_sp, 4)} from the "
                    "axis): a spacer inside or outside them")


# ---- the distance error between the rollers ---------------------------------------------------
@dataclasses.dataclass(frozen=True)
class RollerDistanceError:
    """The two built cams against each other over the cycle.

    Attributes:
        theta: (n,) cam angles [rad].
        s1, s2: the lifts the built first and second pitch curves give the follower [lift units].
        distance: (n,) signed distance error [length]: the second roller's centre where the first
            cam puts the follower minus where the second cam wants it, along its path
            (+ interference, − play).
        dev1, dev2: (max |s − s_design|, cam angle [deg]) of each built curve.
        lift_unit: "length" or "angle".
    """

    theta: np.ndarray
    s1: np.ndarray
    s2: np.ndarray
    distance: np.ndarray
    dev1: tuple[float, float]
    dev2: tuple[float, float]
    lift_unit: str

    def summary(self, units: str) -> dict[str, Any]:
        """The report's numbers; ``units`` is the spec's length unit ("mm" or "in"): the distance
        error's unit, and the lift error's unless the lift is an arm angle (then "deg")."""
        k = int(np.argmax(np.abs(self.distance)))
        dl = self.s1 - self.s2
        j = int(np.argmax(np.abs(dl)))
        return {
            "max": float(abs(self.distance[k])), "at_deg": float(np.rad2deg(self.theta[k])),
            "largest_interference": float(max(np.max(self.distance), 0.0)),
            "largest_play": float(max(-np.min(self.distance), 0.0)),
            "lift_max": float(abs(dl[j])), "lift_at_deg": float(np.rad2deg(self.theta[j])),
            "unit": units, "lift_unit": "deg" if self.lift_unit == "angle" else units,
            "first_cam_deviation": self.dev1[0], "second_cam_deviation": self.dev2[0],
            # |s₁ − s₂| ≤ |s₁ − s| + |s₂ − s|: the lift error is bounded by the two curves' deviations
            "lift_bound": self.dev1[0] + self.dev2[0],
            "samples": int(self.theta.shape[0]),
            "note": "+ interference (the cams squeeze the follower), − play; along the second roller's path",
        }


def roller_distance_error(first, second, n: int | None = None) -> RollerDistanceError:
    """Both rollers' lifts from their built PH pitch curves (the contact solve, every 0.02° and at
    least 8 samples per segment of either curve) and the distance error between the rollers."""
    n = n or max(first.deviation_count(), second.deviation_count())
    th, s1 = first.sampled_displacement(n)
    s2 = second.sampled_displacement(n)[1]
    fol2 = second.follower
    z = np.zeros_like(th)
    at1 = fol2.fixed(Kinematics(th, s1, z, z, z))[0]
    at2 = fol2.fixed(Kinematics(th, s2, z, z, z))[0]
    dist = np.sign(s1 - s2) * np.abs(at1 - at2)
    s = first.program.s(th)
    d1, d2 = s1 - s, s2 - s
    i, j = int(np.argmax(np.abs(d1))), int(np.argmax(np.abs(d2)))
    return RollerDistanceError(th, s1, s2, dist, (float(abs(d1[i])), float(np.rad2deg(th[i]))),
                               (float(abs(d2[j])), float(np.rad2deg(th[j]))), fol2.lift_unit)


def drive_cams(design) -> dict[str, Any]:
    """Which cam drives the follower where (:func:`cam_workbench.generators.bodies.groove.force_sides`): the
    first while the follower needs a push away from the cam axis, the second while it must be
    pulled back."""
    sides = force_sides(design)
    return {"changes_at_deg": sides["changes_at_deg"], "first_cam_share": sides["positive_share"],
            "second_cam_share": sides["negative_share"],
            "note": "the first cam drives while the follower needs a push away from the cam axis, the second while "
                    "it must be pulled back" if design.follower.has_load
            else "no follower load given: the force is the inertia's alone"}


# ---- the spec's rules --------------------------------------------------------------------------
#: the thinnest spacer between the cams [mm] (conjugate.gap is 0 or at least this)
MIN_GAP_MM = 0.01


def validate_conjugate(spec) -> None:
    """The conjugate body's own rules (called by the spec's validation): a roller follower on PH
    pitch curves; the second roller's position given for the follower's motion and placed so
    that it stays on the other side of the cam axis (the yoke) or of the line through the pivot
    and the axis (the arm pair), clear of the axis by its radius and the bore.

    Raises:
        SpecError: naming the field and the rule.
    """
    fol, c = spec.follower, spec.conjugate
    if not spec.is_roller:
        raise SpecError("cam.body", f'a conjugate pair needs a roller follower, got follower.kind = "{fol.kind}"')
    if not pitch_of(spec).exact:
        raise SpecError("pitch.representation", 'a conjugate pair is built on PH pitch curves (exact offsets): "ph"')
    smallest = MIN_GAP_MM if spec.units == "mm" else MIN_GAP_MM / 25.4
    if 0 < c.gap < smallest:
        raise SpecError("conjugate.gap", f"must be 0 (the cams face to face) or at least {fmt_apart(smallest, c.gap)} "
                        f"{spec.units} (a thinner spacer cannot be made), got {fmt_apart(c.gap, smallest)}")
    r2 = c.roller_radius if c.roller_radius is not None else fol.roller_radius
    clear = r2 + spec.cam.bore_diameter / 2          # the second roller's centre must stay this far from the axis
    h = spec.max_lift
    if not follower_class_of(spec).pivoted:
        for name in ("arm_angle", "arm_length"):
            if getattr(c, name) is not None:
                raise SpecError(f"conjugate.{name}", "applies to an oscillating arm pair only: a translating yoke's "
                                "second roller is placed by conjugate.roller_distance")
        if c.roller_distance is None:
            raise SpecError("conjugate.roller_distance", "is required for a translating follower (the yoke's "
                            "distance between the roller centres)")
        e, s0 = fol.offset, spec.prime_offset
        below = c.roller_distance - s0 - h           # the second roller's centre below the axis, top of the lift
        need = s0 + h + math.sqrt(max(clear * clear - e * e, 0.0))
        if not (below > 0 and math.hypot(e, below) > clear):
            raise SpecError("conjugate.roller_distance", f"the second roller does not fit on the other side of the cam: "
                            f"at the top of the lift its centre is "
                            f"{fmt_apart(math.hypot(e, below) if below > 0 else 0.0, clear, 4)} "
                            f"from the cam axis, it needs more than its radius {r2:g} + the bore's radius "
                            f"{spec.cam.bore_diameter / 2:g}: roller_distance > {fmt_apart(need, c.roller_distance, 4)} "
                            f"(got {fmt_apart(c.roller_distance, need)})")
        return
    if c.roller_distance is not None:
        raise SpecError("conjugate.roller_distance", "applies to a translating yoke only: an oscillating arm pair's "
                        "second roller is placed by conjugate.arm_angle (and conjugate.arm_length)")
    if c.arm_angle is None:
        raise SpecError("conjugate.arm_angle", "is required for an oscillating follower (the angle from the first "
                        "arm to the second about the pivot)")
    psi0 = math.degrees(zero_lift_arm_angle(spec.cam.base_radius, fol.pivot_distance, fol.arm_length))
    psi2 = (psi0 + c.arm_angle + 180.0) % 360.0 - 180.0   # the second arm's angle at zero lift, in [−180°, 180°)
    lo = (-180.0 + h - psi0 + 180.0) % 360.0 - 180.0     # the allowed arm angles, from lo to lo + 180° − h
    if not (-180.0 + h < psi2 < 0.0):
        raise SpecError("conjugate.arm_angle", f"the second arm must stay on the other side of the line through the "
                        f"pivot and the cam axis over the whole lift: its angle ψ₀ + arm_angle = "
                        f"{fmt_apart(psi2, 0.0 if psi2 >= 0 else -180.0 + h, 4)}° must lie "
                        f"in ({-180.0 + h:.4g}°, 0°) (ψ₀ = {psi0:.4g}°, largest lift {h:g}°): arm_angle between "
                        f"{lo:.4g}° and {lo + 180.0 - h:.4g}° (modulo 360°)")
    L2 = c.arm_length if c.arm_length is not None else fol.arm_length
    reach = abs(fol.pivot_distance + L2 * complex(math.cos(math.radians(psi2 - h)), math.sin(math.radians(psi2 - h))))
    if not reach > clear:
        raise SpecError("conjugate.arm_angle", f"the second roller does not fit: at the top of the lift its centre is "
                        f"{fmt_apart(reach, clear, 4)} from the cam axis, it needs more than its radius {r2:g} + the bore's radius "
                        f"{spec.cam.bore_diameter / 2:g} (a smaller |arm_angle|, or a longer conjugate.arm_length)")


#: the [conjugate] fields a spec may give only for cam.body = "conjugate"
CONJUGATE_ONLY = ("roller_distance", "arm_angle", "arm_length", "roller_radius", "spacer_diameter")


def refuse_stray_fields(spec) -> None:
    """[conjugate] fields on another body are an error (a leftover must not be silently ignored)."""
    c = spec.conjugate
    for name in CONJUGATE_ONLY:
        if getattr(c, name) is not None:
            raise SpecError(f"conjugate.{name}", 'applies to conjugate cams only (cam.body = "conjugate")')
    if c.gap != 0:
        raise SpecError("conjugate.gap", 'applies to conjugate cams only (cam.body = "conjugate")')

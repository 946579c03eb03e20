"""The groove (face) cam: a disc of ``cam.outer_diameter`` with a groove cut ``groove.depth`` into
its top face, in which the roller runs — positive drive, no spring needed.

The groove's walls are the pitch curve's offsets at ±w/2, w = 2·roller_radius + groove.clearance:
for a PH pitch curve both are exact rational NURBS (degree 9), the inner wall being the design's
profile (:attr:`CamDesign.profile`, offset inward by r + c/2 because :meth:`GrooveBody.profile_inset`
adds c/2).  Checks (refusals with the cam angle): material between the outer wall and the rim,
between the inner wall and the bore (and keyway, holes) ≥ ``groove.min_wall``; the outer wall's
undercut where the pitch curve's concave radius of curvature is below w/2.  Reported: which wall
drives the follower where — the inner wall while the contact force pushes the follower out, the
outer wall while it must pull it in (the force changes sign where the inertia beats the load).
"""
from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import GeometryError, SpecError, fmt_apart
from ..checks.buildability import min_radius
from ..checks.design import StateModel
from ..followers.load import hertz_stress
from ..kinds import register_body
from ..spec.optimise import BODY_VARIABLES, OBJECTIVES
from .base import BodyGeometry, Loop, Prism
from .features import bore_extent, bore_loop, plate_features, resolved
from .plane import PlaneCamBody
from .plate import feature_checks, profile_radius_along


def half_width(spec) -> float:
    """w/2 = roller radius + clearance/2."""
    return spec.roller_radius + resolved(spec, "groove", "clearance") / 2


def groove_depth(spec) -> float:
    return spec.groove.depth if spec.groove.depth is not None else 2.0 / 3.0 * spec.cam.thickness


@register_body
class GrooveBody(PlaneCamBody):
    """A disc with the groove in its top face."""

    kind = "groove"
    plane = True
    roller_within_base = True
    dynamics_train = "follower"
    #: the field that sizes the cam
    size_field = "cam.base_radius"
    #: the legend of the body's first added region in the cam drawing (None: the profile's)
    drawing_label = "groove cam (walls: the pitch curve's exact offsets ±(r + c/2))"
    #: the objectives its optimiser serves (optimise.objective; outer_diameter: a groove's disc)
    optimise_objectives = OBJECTIVES
    #: the optimiser's design variables this body adds (optimise.variables)
    optimise_variables = BODY_VARIABLES
    own_fields = ("outer_diameter",)
    modules = ("cam_workbench.generators.machining.groove",)
    title = "Groove cam"
    #: the groove holds the roller both ways (form closure): it cannot leave the cam
    closure = "form"
    #: which side drives (the follower dynamics' form-closure note)
    drive_note = ("the groove holds the roller both ways; the wall that drives changes where the contact force "
                  "changes sign (positive: pushing the follower away from the cam axis, the inner wall; "
                  "negative: the outer wall)")

    @staticmethod
    def validate(spec) -> None:
        validate_groove(spec)

    @staticmethod
    def profile_inset(spec) -> float:
        return resolved(spec, "groove", "clearance") / 2

    @staticmethod
    def machining_defaults(spec) -> dict[str, float | None]:
        """The groove's depth, and a tool ¾ of the groove's half width (it must be narrower than
        the groove to finish both walls)."""
        return {"depth": groove_depth(spec), "tool_radius": 0.75 * half_width(spec)}

    @staticmethod
    def label(spec) -> str:
        """The numbers that identify a groove cam (spec lengths, no unit): R_b, the disc and the groove."""
        return (f"R_b = {spec.cam.base_radius:g}, disc Ø{spec.cam.outer_diameter:g} × {spec.cam.thickness:g}, "
                f"groove {2 * half_width(spec):g} wide, {groove_depth(spec):g} deep")

    @staticmethod
    def reverse_contact_stress(model, force: np.ndarray, rho: np.ndarray) -> np.ndarray:
        """Hertz stress where the force is negative, taken by the groove's outer wall: the roller
        (radius r) against a surface of signed radius −(ρ + r) (concave where the pitch curve is
        convex)."""
        r = model.follower.profile_offset
        return hertz_stress(-force, r, -(rho + r), model.contact_length, *model.moduli)

    @staticmethod
    def geometry(design) -> BodyGeometry:
        spec = design.spec
        t = spec.cam.thickness
        r_out = spec.cam.outer_diameter / 2
        bore = bore_loop(spec)
        inner = design.profile
        outer = design.pitch_offset_curve(half_width(spec))
        prisms = [Prism(Loop.circle(r_out, role="rim"), (bore,) if bore else (), 0.0, t, "add", "disc"),
                  Prism(Loop.nurbs(outer, "groove_outer"), (Loop.nurbs(inner, "groove_inner"),), t - groove_depth(spec),
                        t, "cut", "groove")]
        prisms += plate_features(design, t)
        return BodyGeometry("groove", tuple(prisms), {"outer_wall": outer})

    @staticmethod
    def check(design, geometry: BodyGeometry) -> dict[str, Any]:
        spec = design.spec
        min_wall = resolved(spec, "groove", "min_wall")
        w2 = half_width(spec)
        out: dict[str, Any] = {"groove_width": 2 * w2, "groove_depth": groove_depth(spec),
                               "outer_diameter": spec.cam.outer_diameter}
        #: the failing wall checks, in order: (name, kind, message, cam angle)
        failures: list[tuple[str, str, str, float]] = []
        # the outer wall folds where the pitch curve's concave radius is below w/2
        cs = design.curvature_samples
        concave = cs.radius < 0
        if concave.any():
            k = int(np.argmin(np.where(concave, -cs.radius, np.inf)))
            out["min_concave_pitch_radius"] = float(-cs.radius[k])
            if -cs.radius[k] <= w2:
                failures.append(("outer_wall_undercut", "undercut",
                                 f"the groove's outer wall is undercut at cam angle {cs.cam_angle_deg[k]:.2f}°: "
                                 f"concave pitch radius {fmt_apart(-cs.radius[k], w2, 4)} ≤ half the groove width "
                                 f"{w2:g} — a smaller roller or a gentler motion", float(cs.cam_angle_deg[k])))
        # material to the rim, at the largest radius of the outer wall
        outer = geometry.extra["outer_wall"]
        u, pts = outer.sample(64)
        r = np.hypot(pts[:, 0], pts[:, 1])
        k = int(np.argmax(r))
        rim = spec.cam.outer_diameter / 2 - float(r[k])
        at_rim = cam_angle_at_parameter(design, float(u[k]))
        out["rim_wall"] = {"value": rim, "at_deg": at_rim}
        if rim < min_wall:
            failures.append(("rim_wall", "wall", f"the groove leaves {fmt_apart(rim, min_wall, 4)} of material to the "
                             f"rim at cam angle {at_rim:.2f}°, less than groove.min_wall {fmt_apart(min_wall, rim, 4)}: a "
                             "larger cam.outer_diameter", at_rim))
        # material to the bore (and keyway)
        r_in, u_in = min_radius(design.profile)
        at_bore = cam_angle_at_parameter(design, u_in)
        bore_wall = r_in - bore_extent(spec)
        out["bore_wall"] = {"value": bore_wall, "at_deg": at_bore}
        if bore_wall < min_wall:
            failures.append(("bore_wall", "wall", f"the groove leaves {fmt_apart(bore_wall, min_wall, 4)} of material "
                             f"to the bore at cam angle {at_bore:.2f}°, less than groove.min_wall "
                             f"{fmt_apart(min_wall, bore_wall, 4)}", at_bore))
        if failures:
            _, kind, message, at = failures[0]
            raise GeometryError(kind, message, at, checks=tuple(f[0] for f in failures))
        out.update(feature_checks(design, lambda a: profile_radius_along(design.profile, a), "groove's inner wall"))
        out["drive"] = drive_sides(design)
        return out


def cam_angle_at_parameter(design, u: float) -> float:
    """Cam angle [deg] at which the follower is at the point of parameter ``u`` of a curve that
    shares the pitch curve's parameter (its offsets: knot span k ↔ segment k)."""
    m = design.pitch.M
    seg = min(int(u), m - 1)
    return float(design.pitch.cam_angle_at(np.array([seg]), np.array([min(max(u - seg, 0.0), 1.0)]))[0])


def force_sides(design) -> dict[str, Any]:
    """Where the contact force needed to follow the motion is positive (pushing the follower away
    from the cam axis) and where negative (pulling it back): the cam angles [deg] where it changes
    sign (the zero crossings, interpolated linearly between samples every 0.05°) and each sign's
    share of the turn (a zero force counts as positive)."""
    model = StateModel(design.spec, design.program)
    th = np.linspace(0.0, 2 * np.pi, 7201)
    k = design.program.evaluate(th)
    f = design.follower.contact_force(k, model.omega)
    sign = np.sign(f)
    sign[sign == 0] = 1
    flips = np.nonzero(sign[1:] != sign[:-1])[0]
    # linear interpolation of the zero crossing
    at = th[flips] - f[flips] * (th[flips + 1] - th[flips]) / (f[flips + 1] - f[flips])
    return {"changes_at_deg": [float(np.rad2deg(a)) for a in at],
            "positive_share": float(np.mean(sign[:-1] > 0)), "negative_share": float(np.mean(sign[:-1] < 0))}


def drive_sides(design) -> dict[str, Any]:
    """Which wall drives the follower where: the inner wall while the contact force needed to
    follow the motion is positive (pushing the follower out), the outer wall while it is negative;
    the cam angles [deg] where it changes side and each wall's share of the turn."""
    sides = force_sides(design)
    return {"changes_at_deg": sides["changes_at_deg"],
            "inner_wall_share": sides["positive_share"], "outer_wall_share": sides["negative_share"],
            "note": "the inner wall drives while the force pushes the follower out, the outer wall while it pulls it in"
            if design.follower.has_load else "no follower load given: the force is the inertia's alone"}


def validate_groove(spec) -> None:
    """The groove body's own rules (called by the spec's validation)."""
    if not spec.is_roller:
        raise SpecError("cam.body", f'a groove needs a roller follower, got follower.kind = "{spec.follower.kind}"')
    if spec.cam.outer_diameter is None:
        raise SpecError("cam.outer_diameter", "is required for a groove cam")
    if spec.groove.depth is not None and not spec.groove.depth < spec.cam.thickness:
        raise SpecError("groove.depth", f"must be < cam.thickness ({fmt_apart(spec.cam.thickness, spec.groove.depth)}), "
                        f"got {fmt_apart(spec.groove.depth, spec.cam.thickness)}")

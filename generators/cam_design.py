"""From a spec to everything a solid, a drawing or a report needs: the one call the
upper layers make (:func:`design_cam`).

The result holds plain values: the solved PH pitch curve, the exact profile NURBS,
and the numbers of ``report.json`` (units of the spec; angles in degrees).
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any, Callable

import numpy as np

from .bodies.base import BodyGeometry
from .checks.areas import area_summary
from .checks.design import DesignChecks, run_checks
from .curves.extrema import refine_max
from .followers.base import Follower
from .kinds import body_of, pitch_of
from .checks.buildability import (CurvatureSamples, check_bore, check_self_intersection,
                              check_undercut, pitch_curvature_samples)
from .motion.program import MotionProgram
from .curves.nurbs import NurbsCurve
from .curves.offsets import offset_nurbs, pitch_nurbs
from .pitch.ph import PitchCurve, build_pitch
from .pitch.bspline import (PeriodicBSpline, ProfileErrors, build_bspline_pitch, built_profile_error,
                            fit_offset, profile_errors)
from .errors import GeometryError
from .spec.model import CamSpec
from .spec.toml_io import spec_digest

DESIGN_SAMPLES_PER_SEGMENT = 2001
#: knot spans of the fitted offset B-spline per span of the fitted pitch B-spline: with 2 its
#: error is ~1 % of the exact offset's (1 span per span: up to 1.7× the exact offset's error)
OFFSET_REFINE = 2


@dataclass(frozen=True)
class CamDesign:
    """A designed plate cam (no CAD kernel involved).

    Attributes:
        spec: the validated spec.
        pitch: the solved PH pitch curve.
        pitch_nurbs: the pitch curve as exact degree-5 NURBS.
        profile: the cam profile as exact NURBS (degree-9 rational offset for a roller;
            the pitch curve itself for a knife edge), traversed as the pitch curve is.
        max_deviation: (value, cam angle [deg]) of |s_actual − s|.
        min_profile_radius: smallest distance of the profile from the axis.
    """

    spec: CamSpec
    pitch: PitchCurve
    pitch_nurbs: NurbsCurve
    profile: NurbsCurve
    max_deviation: tuple[float, float]
    min_profile_radius: float
    curvature_samples: CurvatureSamples = field(repr=False)
    #: pitch.representation = "bspline": the fitted curves and their errors (else None)
    bspline: "BSplineProfile | None" = field(default=None, repr=False)
    #: the design checks of the spec (``report.json`` ``checks``; the ones ``check`` prints)
    checks: DesignChecks | None = field(default=None, repr=False)
    #: the body (plate, groove, …) as prisms of exact loops, and what its checks measured
    #: (``check``: they refuse what cannot be made, so they run with the design)
    body: BodyGeometry | None = field(default=None, repr=False)
    body_checked: dict = field(default_factory=dict, repr=False)
    #: a plane cam (:class:`cam_workbench.generators.kinds.protocols.Design`): pitch curve, profile, prisms
    plane = True
    #: what stands for a pitch curve and a profile in the cam's plane where a design has none (words
    #: for the API's refusal, naming what to use instead); "": a plane cam has them
    instead_of_plane_curves = ""

    @property
    def program(self) -> MotionProgram:
        return self.pitch.program

    @property
    def geometry(self) -> Follower:
        """The follower (the name before the follower interface)."""
        return self.pitch.follower

    @property
    def follower(self) -> Follower:
        return self.pitch.follower

    def label(self) -> str:
        """One line that identifies the cam: its body, its follower (motion, contact and numbers, as
        ``Follower.label()`` words them), the body's numbers and the pitch curve's spans (spec units)."""
        spec = self.spec
        curve = self.follower.describe()["curve"]
        pitch = (f"PH quintic {curve}, M = {self.pitch.M}" if self.pitch.exact
                 else f"B-spline {curve}, {self.pitch.M} knot spans")
        return (f"{spec.cam.body} cam, lengths in {spec.units}: {self.follower.label()}; {body_of(spec).label(spec)}; "
                f"{pitch}")

    @cached_property
    def body_report(self) -> dict:
        """report.json's ``body`` numbers: what the body's checks measured, then what the body
        reports without refusing anything (``report``: a conjugate pair's second cam, computed when
        first asked — a FreeCAD recompute never asks)."""
        if self.body is None:
            return dict(self.body_checked)
        return {**self.body_checked, **body_of(self.spec).report(self, self.body)}

    def profile_ccw(self) -> NurbsCurve:
        """The profile oriented counter-clockwise (positive area), as solid builders want it."""
        return self.profile if self.profile.area() > 0 else self.profile.reversed()

    @property
    def profile_area(self) -> float:
        """Area enclosed by the profile (Green's theorem on the exact NURBS)."""
        return abs(self.profile.area())

    @property
    def area(self) -> float:
        """Area of the top face (z = thickness): for a plate cam the profile minus the bore (and keyway,
        holes, timing mark); for a groove cam the disc minus the bore and the groove."""
        if self.body is None:
            r = self.spec.cam.bore_diameter / 2
            return self.profile_area - np.pi * r * r
        return self.body.face_area_at(self.spec.cam.thickness)

    @property
    def volume(self) -> float:
        """The body's exact volume (Green's theorem on its loops × heights)."""
        if self.body is None:
            return self.area * self.spec.cam.thickness
        return self.body.volume

    def pitch_offset_curve(self, outward: float) -> NurbsCurve:
        """The pitch curve offset outward by ``outward`` (inward when negative): the exact rational
        NURBS for a PH pitch curve, a B-spline fitted to the exact offset for a B-spline one."""
        if self.bspline is None:
            return offset_nurbs(self.pitch.spline, profile_offset_distance(self.pitch, -outward))
        fit = fit_offset(self.pitch.curve, self.pitch.follower.sense * outward, refine=OFFSET_REFINE)
        return fit.to_nurbs(self.pitch.parameter_scale)

    def max_profile_radius(self, per_span: int = 64) -> tuple[float, complex, float]:
        """Largest distance of the profile from the axis [length]: (radius, the profile point
        as x + iy, the cam angle [deg] at which the follower touches that point).

        Sampled on every knot span, then refined by golden section (not sampling-limited)."""
        prof = self.profile

        def radius(u: np.ndarray) -> np.ndarray:
            p = prof.evaluate(u)
            return np.hypot(p[:, 0], p[:, 1])

        u, pts = prof.sample(per_span)
        u_max, r_max = refine_max(radius, u, np.hypot(pts[:, 0], pts[:, 1]))
        p = prof.evaluate(np.array([u_max]))[0]
        # profile and pitch curve share the parameter: knot span k is PH segment k
        seg = min(int(u_max), self.pitch.M - 1)
        at = float(self.pitch.cam_angle_at(np.array([seg]), np.array([u_max - seg]))[0])
        return float(r_max), complex(p[0], p[1]), at

    def design_kinematics(self, samples_per_segment: int = DESIGN_SAMPLES_PER_SEGMENT):
        """Dense angles [rad] and the motion's kinematics there (design intent)."""
        th = self.program.dense_angles(samples_per_segment)
        return th, self.program.evaluate(th)

    @property
    def profile_inset(self) -> float:
        """How far inside the pitch curve the profile NURBS lies: the follower's roller radius,
        plus the body's own inset (half a groove's clearance)."""
        return self.follower.profile_offset + body_of(self.spec).profile_inset(self.spec)

    def summary(self) -> dict[str, Any]:
        """The numbers of ``report.json`` (without the ``files`` section)."""
        spec = self.spec
        geo = self.geometry
        sections = self.cam_sections()
        maxima = self.program.maxima(spec.cam.speed_rpm * 2 * np.pi / 60)
        return {
            "units": spec.units,
            "spec_digest": spec_digest(spec),
            **{k: sections[k] for k in ("pitch", "pressure_angle", "curvature", "follower")},
            "motion": {
                "lift_unit": "deg" if geo.lift_unit == "angle" else spec.units,
                # the follower's (with [linkage] motion_at = "tool", derived; else spec.max_lift)
                "max_lift": max(0.0, float(np.max(self.program.levels + self.program.lifts))),
                "max_velocity": maxima["velocity"],
                "max_acceleration": maxima["acceleration"],
                "max_jerk": maxima["jerk"],
                **self.program.report(),
            },
            "profile": sections["profile"],
            "area": self.area,
            "volume": self.volume,
            "areas": {
                # design intent (motion + follower), thesis Eq. 4.21–4.27 and exact
                **area_summary(spec, self.program),
                # the built profile (exact NURBS, Green's theorem)
                "built_profile": self.profile_area,
                "built_cross_section": self.area,
            },
            "checks": self.design_checks.to_dict(),
            "body": _plain({**self.body_report, "volume": self.volume, "top_face_area": self.area})
            if self.body is not None else None,
        }

    def cam_sections(self) -> dict[str, Any]:
        """The report sections of this cam's own curves: ``pitch``, ``pressure_angle``,
        ``curvature``, ``follower`` and ``profile`` (for a conjugate pair, each cam's)."""
        spec = self.spec
        geo = self.geometry
        th, k = self.design_kinematics()
        prog = self.program

        def abs_phi(t: np.ndarray) -> np.ndarray:
            return np.abs(geo.pressure_angle(prog.evaluate(t)))

        def neg_convex(t: np.ndarray) -> np.ndarray:
            rho_t = geo.radius_of_curvature(prog.evaluate(t))
            return -np.where(rho_t > 0, rho_t, np.inf)

        def neg_concave(t: np.ndarray) -> np.ndarray:
            rho_t = geo.radius_of_curvature(prog.evaluate(t))
            return -np.where(rho_t < 0, -rho_t, np.inf)

        th_p, _ = refine_max(abs_phi, th, abs_phi(th))
        phi_signed = float(np.rad2deg(geo.pressure_angle(prog.evaluate(np.array([th_p])))[0]))
        th_c, neg_rc = refine_max(neg_convex, th, neg_convex(th))
        _, neg_rcc = refine_max(neg_concave, th, neg_concave(th))
        cs = self.curvature_samples
        b_convex = np.where(cs.radius > 0, cs.radius, np.inf)
        ib = int(np.argmin(b_convex))
        b_concave = np.where(cs.radius < 0, -cs.radius, np.inf)
        rr = self.profile_inset            # the profile's (for a groove: the inner wall's) inset
        phi_b, at_b = self._as_built_pressure_angle()
        curvature: dict[str, Any] = {
            "min_pitch_radius": -neg_rc,
            "min_profile_radius": -neg_rc - rr,
            "at_deg": float(np.rad2deg(th_c) % 360.0),
            "min_concave_pitch_radius": _finite_or_none(-neg_rcc),
            "as_built": {
                "min_pitch_radius": float(b_convex[ib]),
                "min_profile_radius": float(b_convex[ib] - rr),
                "at_deg": float(cs.cam_angle_deg[ib]),
                "min_concave_pitch_radius": _finite_or_none(float(np.min(b_concave))),
            },
        }
        return {
            "pitch": {
                "representation": spec.pitch.representation,
                "segments": self.pitch.M,
                "max_deviation": self.max_deviation[0],
                "max_deviation_at_deg": self.max_deviation[1],
                "tolerance": spec.pitch.tolerance,
                "newton_iterations": self.pitch.spline.iterations,
                "newton_residual": self.pitch.spline.residual,
                "closing_sign": self.pitch.spline.closing_sign,
                "arc_length": self.pitch.spline.arc_length,
                **({"degree": self.bspline.pitch_curve.degree, "poles": self.pitch_nurbs.n_poles,
                    "periodic_poles": self.bspline.pitch_curve.n_spans}
                   if self.bspline is not None else {}),
            },
            "pressure_angle": {
                "max_deg": abs(phi_signed),
                "signed_deg": phi_signed,
                "at_deg": float(np.rad2deg(th_p) % 360.0),
                "as_built": {"max_deg": phi_b, "at_deg": at_b},
            },
            "curvature": curvature,
            "follower": geo.describe(),
            "profile": self._profile_summary(),
        }

    @property
    def design_checks(self) -> DesignChecks:
        """The design checks (computed once, when the cam was designed)."""
        return self.checks if self.checks is not None else run_checks(self.spec, program=self.program)

    def _profile_summary(self) -> dict[str, Any]:
        rr = self.profile_inset
        r_max, _, r_max_at = self.max_profile_radius()
        err, at = built_profile_error(self.profile, self.pitch, rr)
        out: dict[str, Any] = {
            "degree": self.profile.degree,
            "poles": self.profile.n_poles,
            "rational": self.profile.is_rational,
            "min_radius": self.min_profile_radius,
            "max_radius": r_max,
            "max_radius_at_deg": r_max_at,
            "base_circle_radius": self.spec.cam.base_radius - rr,
            # distance of the built profile from the true one (the roller offset of the design pitch curve)
            "max_error": err,
            "max_error_at_deg": at,
        }
        if self.bspline is not None:
            e = self.bspline.errors
            out["kernel_offset"] = {
                "description": "exact offset of the fitted pitch B-spline (OCCT Geom_OffsetCurve)",
                "distance": self.bspline.offset_distance,
                "max_error": e.exact_offset, "max_error_at_deg": e.exact_offset_at_deg,
            }
            out["fitted_vs_kernel_offset"] = e.fitted_vs_exact_offset
        return out

    def as_built_pressure_angles(self) -> tuple[np.ndarray, np.ndarray]:
        """Pressure angle of the built curve at the curvature samples: (cam angle [deg],
        signed φ [deg]) — its tangent, turned into the fixed frame at the cam angle where the
        follower touches it, against the direction the follower's contact point moves."""
        geo = self.geometry
        cs = self.curvature_samples
        rot = np.exp(1j * geo.sense * np.deg2rad(cs.cam_angle_deg))
        tangent = rot * self.pitch.spline.first_derivative(cs.seg, cs.xi)
        phi = np.rad2deg(geo.pressure_angle_of(tangent, geo.velocity_direction_at(rot * cs.point)))
        return cs.cam_angle_deg, phi

    def _as_built_pressure_angle(self) -> tuple[float, float]:
        at, phi = self.as_built_pressure_angles()
        k = int(np.argmax(np.abs(phi)))
        return float(abs(phi[k])), float(at[k])


def _plain(d: Any) -> Any:
    """A dict of numbers and lists as JSON can hold them (curves and arrays left out)."""
    if isinstance(d, dict):
        return {k: _plain(v) for k, v in d.items() if not isinstance(v, (NurbsCurve, np.ndarray))}
    if isinstance(d, (list, tuple)):
        return [_plain(v) for v in d]
    if isinstance(d, (np.floating, np.integer)):
        return d.item()
    return d


def _finite_or_none(v: float) -> float | None:
    return v if np.isfinite(v) else None


def profile_offset_distance(pitch: PitchCurve, roller_radius: float) -> float:
    """Signed (left-positive) offset distance that moves the pitch curve inward by the roller radius."""
    clockwise = pitch_nurbs(pitch.spline).area() < 0
    return -roller_radius if clockwise else roller_radius


@dataclass(frozen=True)
class BSplineProfile:
    """What a ``pitch.representation = "bspline"`` design adds: the fitted periodic pitch curve,
    the signed offset distance a kernel applies to it for the exact roller offset, the fitted
    offset B-spline (``CamDesign.profile``), and their measured errors."""

    pitch_curve: PeriodicBSpline
    offset_distance: float
    profile_curve: PeriodicBSpline
    errors: ProfileErrors


def refuse_undercut(checks: DesignChecks, roller_radius: float, name: str = "undercut",
                    curvature: str = "curvature") -> None:
    """Raise the design checks' own undercut failure as a GeometryError (the numbers and the
    cam angle ``cam-workbench check`` prints), so that a cam is never built past it; ``name`` and
    ``curvature``: the checks of another cam of the body (a conjugate pair's second cam)."""
    try:
        r = checks[name]
    except KeyError:
        return
    if r.status != "fail":
        return
    parts = []
    at = r.at_deg
    if r.value is not None and r.value <= 0:
        at = checks[curvature].at_deg        # where the convex pitch radius is smallest
        parts.append(f"undercut at cam angle {at:.3f}°: roller radius {roller_radius:g} ≥ smallest convex "
                     f"pitch radius of curvature {r.value + roller_radius:.6g} (cam surface {r.value:.6g})")
    if r.note:
        parts.append(r.note if parts else f"undercut at cam angle {r.at_deg:.3f}°: {r.note}")
    raise GeometryError("undercut", f"{'; '.join(parts)} — use a smaller roller, a larger base radius or a "
                        "gentler motion", at)


def refuse_cusp(checks: DesignChecks) -> None:
    """Raise a flat face's failed cusp check as a GeometryError with its cam angle: the face's
    envelope folds over itself there and no cam can give the motion."""
    try:
        r = checks["cusp"]
    except KeyError:
        return
    if r.status == "fail":
        raise GeometryError("cusp", f"cusp at cam angle {r.at_deg:.3f}°: the profile's radius of curvature "
                            f"{r.value:.6g} ≤ 0 ({r.description.split('ρ = ')[-1].split(' (')[0]}) — a flat face "
                            "cannot make it: a larger base radius or a gentler motion", r.at_deg)


def checked_intent(spec: CamSpec) -> DesignChecks:
    """The design checks of the design intent, refusing (GeometryError with the cam angle) what no
    pitch curve can make — an undercut roller, a flat face's cusp — before any curve is built."""
    checks = run_checks(spec, program=MotionProgram.from_spec(spec))
    refuse_undercut(checks, spec.roller_radius)
    refuse_cusp(checks)
    return checks


def with_body(design: CamDesign) -> CamDesign:
    """The design with its body built and checked (refusals: GeometryError with the cam angle, or a
    SpecError naming a feature's field)."""
    body = body_of(design.spec)
    geometry = body.geometry(design)
    checked = body.check(design, geometry)
    return replace(design, body=geometry, body_checked={"kind": body.kind, **checked})


def profile_inset(spec: CamSpec) -> float:
    """How far inside the pitch curve the profile NURBS lies: the roller radius, plus the body's
    own inset (half a groove's clearance)."""
    return spec.roller_radius + body_of(spec).profile_inset(spec)


def _design_bspline(spec: CamSpec, progress: Callable[[int, float], None] | None) -> CamDesign:
    checks = checked_intent(spec)
    pitch = build_bspline_pitch(spec, progress)
    cs = pitch_curvature_samples(pitch)
    rr = profile_inset(spec)
    check_undercut(pitch, rr, cs)
    pn = pitch.to_nurbs()
    inward = -pitch.geometry.sense * rr
    fit = fit_offset(pitch.curve, inward, refine=OFFSET_REFINE) if rr > 0 else pitch.curve
    profile = fit.to_nurbs(pitch.parameter_scale) if rr > 0 else pn
    check_self_intersection(profile, pitch)
    rmin = check_bore(profile, pitch, spec.cam.bore_diameter)
    errors = profile_errors(pitch, fit, rr, inward)
    return with_body(CamDesign(spec=spec, pitch=pitch, pitch_nurbs=pn, profile=profile,  # type: ignore[arg-type]
                               max_deviation=pitch.max_deviation(), min_profile_radius=rmin,
                               curvature_samples=cs, bspline=BSplineProfile(pitch.curve, inward, fit, errors),
                               checks=checks))


def design_cam(spec: CamSpec, *, progress: Callable[[int, float], None] | None = None) -> Any:
    """The designed cam of ``spec``, as its body designs it (``Body.design``): a :class:`CamDesign`
    for a plane cam, the body's own design otherwise (both answer the Design protocol,
    :class:`cam_workbench.generators.kinds.protocols.Design`).

    Raises:
        SpecError: bad input (already raised when the spec was loaded).
        GeometryError: undercut, self-intersection or a bore through the profile, with the cam angle.
        SolveError: the PH spline did not converge.
    """
    return body_of(spec).design(spec, progress=progress)


def design_plane(spec: CamSpec, *, progress: Callable[[int, float], None] | None = None) -> CamDesign:
    """Build the pitch curve and exact profile of a plane cam's ``spec``, run the buildability
    checks and build its body (the plane-cam bodies' ``design``).

    Raises:
        GeometryError: undercut, self-intersection or a bore through the profile, with the cam angle.
        SolveError: the PH spline did not converge.
    """
    if not pitch_of(spec).exact:      # a fitted pitch curve: its offset is fitted too
        return _design_bspline(spec, progress)
    checks = checked_intent(spec)
    pitch = build_pitch(spec, progress=progress)
    cs = pitch_curvature_samples(pitch)
    rr = profile_inset(spec)
    check_undercut(pitch, rr, cs)
    pn = pitch_nurbs(pitch.spline)
    if rr > 0:
        profile = offset_nurbs(pitch.spline, profile_offset_distance(pitch, rr))
    else:
        profile = pn
    check_self_intersection(profile, pitch)
    rmin = check_bore(profile, pitch, spec.cam.bore_diameter)
    dev = pitch.max_deviation()
    return with_body(CamDesign(spec=spec, pitch=pitch, pitch_nurbs=pn, profile=profile, max_deviation=dev,
                               min_profile_radius=rmin, curvature_samples=cs, checks=checks))

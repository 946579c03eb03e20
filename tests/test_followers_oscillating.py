"""Oscillating knife-edge and roller followers against computations written for the test.

The pitch curve is rebuilt here from the pivot/arm geometry alone (law of cosines for the arm
angle at zero lift, the arm turned by the lift, the point turned into the cam frame); the
pressure angle from the curve's numerical tangent (5-point central differences) against the
direction perpendicular to the arm; the radius of curvature from numerical first and second
derivatives; the built curve's arm-angle error by intersecting the built NURBS (evaluated by
scipy, sampled and bisected) with the circle of the arm about the pivot.  None of the
project's follower code is used for the reference values."""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest
from scipy.interpolate import BSpline

from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.followers import OscillatingFollower, follower_of
from cam_workbench.generators.motion import MotionProgram
from cam_workbench.generators.spec import DEFAULT_SPEC_DICT, CamSpec


def spec_dict(kind="roller", d=60.0, L=45.0, rb=40.0, lift=15.0, direction="ccw", law="cycloidal", **extra):
    s = copy.deepcopy(DEFAULT_SPEC_DICT)
    s["cam"].update(base_radius=rb, direction=direction, bore_diameter=10.0)
    f = {"kind": kind, "motion": "oscillating", "pivot_distance": d, "arm_length": L,
         "arm_inertia": 2000.0, "preload_torque": 800.0, "spring_torque_rate": 500.0, **extra}
    if kind == "roller":
        f.setdefault("roller_radius", 8.0)
    s["follower"] = f
    for m in s["motion"]:
        if "lift" in m:
            m["lift"] = lift
            m["law"] = law
    return s


def reference_pitch(spec: CamSpec, theta: np.ndarray) -> np.ndarray:
    """P(θ) from the geometry: ψ₀ by the law of cosines, ψ = ψ₀ − s (deg → rad), A = D + L e^{iψ},
    P = Rot(∓θ)·A."""
    f = spec.follower
    d, L, rb = f.pivot_distance, f.arm_length, spec.cam.base_radius
    psi0 = math.acos((rb * rb - d * d - L * L) / (2 * d * L))
    s = MotionProgram.from_spec(spec).s(theta)
    psi = psi0 - np.radians(s)
    ax, ay = d + L * np.cos(psi), L * np.sin(psi)
    sign = 1 if spec.cam.direction == "ccw" else -1
    c, sn = np.cos(theta), -sign * np.sin(theta)
    return (ax * c - ay * sn) + 1j * (ax * sn + ay * c)


def numeric_derivatives(fun, theta, h=1e-4):
    """5-point central first and second derivatives."""
    f2, f1, f0, g1, g2 = (fun(theta + k * h) for k in (-2, -1, 0, 1, 2))
    d1 = (f2 - 8 * f1 + 8 * g1 - g2) / (12 * h)
    d2 = (-f2 + 16 * f1 - 30 * f0 + 16 * g1 - g2) / (12 * h * h)
    return f0, d1, d2


CASES = [dict(), dict(direction="cw"), dict(kind="knife"), dict(d=70.0, L=55.0, rb=35.0, lift=20.0, law="poly345"),
         dict(d=50.0, L=30.0, rb=30.0, lift=10.0, law="harmonic", direction="cw")]


@pytest.mark.parametrize("case", CASES, ids=[str(c) for c in CASES])
def test_design_curve_pressure_angle_and_curvature(case):
    spec = CamSpec.from_dict(spec_dict(**case))
    fol = follower_of(spec)
    assert isinstance(fol, OscillatingFollower)
    prog = MotionProgram.from_spec(spec)
    # inside the rise/return (away from the dwell ends, where s‴ jumps)
    theta = np.concatenate([np.linspace(0.7, 2.4, 40), np.linspace(3.8, 5.6, 40)])
    k = prog.evaluate(theta)
    p, d1, d2 = numeric_derivatives(lambda t: reference_pitch(spec, t), theta)
    assert np.max(np.abs(fol.points(theta, k) - p)) < 1e-12 * spec.cam.base_radius
    # pressure angle: the curve normal against the direction perpendicular to the arm
    sign = 1 if spec.cam.direction == "ccw" else -1
    rot = np.exp(1j * sign * theta)
    tangent = rot * d1
    a = rot * p                                   # the follower point, fixed frame
    arm = (a - spec.follower.pivot_distance) / spec.follower.arm_length
    w = -1j * arm                                 # A moves this way as the lift grows
    normal = 1j * tangent / np.abs(tangent)
    ref_phi = np.degrees(np.arccos(np.clip(np.abs((np.conj(normal) * w).real), 0, 1)))
    phi = np.degrees(np.abs(fol.pressure_angle(k)))
    assert np.max(np.abs(phi - ref_phi)) < 1e-6
    # radius of curvature, signed + convex (the curve runs clockwise for a ccw cam)
    kappa = (np.conj(d1) * d2).imag / np.abs(d1) ** 3
    ref_rho = -sign / kappa
    rho = fol.radius_of_curvature(k)
    assert np.max(np.abs(rho / ref_rho - 1)) < 1e-5


def _built_lift(design, theta: float) -> float:
    """Arm angle where the built pitch NURBS meets the arm's circle about the pivot, found here:
    the NURBS evaluated by scipy, sign changes of |q − D| − L located on a dense sample and
    bisected; the root nearest the design point is the contact."""
    spec = design.spec
    f = spec.follower
    nurbs = design.pitch_nurbs
    w = np.asarray(nurbs.weights)
    hom = np.column_stack([nurbs.poles[:, 0] * w, nurbs.poles[:, 1] * w, w])
    spl = BSpline(np.asarray(nurbs.knots, float), hom, nurbs.degree)
    t0, t1 = nurbs.knots[nurbs.degree], nurbs.knots[-nurbs.degree - 1]
    sign = 1 if spec.cam.direction == "ccw" else -1
    rot = np.exp(1j * sign * theta)

    def point(u):
        v = spl(u)
        return rot * (v[..., 0] + 1j * v[..., 1]) / v[..., 2]

    def g(u):
        return np.abs(point(u) - f.pivot_distance) - f.arm_length

    u = np.linspace(t0, t1, 20001)
    gv = g(u)
    roots = []
    for i in np.nonzero(np.sign(gv[:-1]) != np.sign(gv[1:]))[0]:
        a, b = u[i], u[i + 1]
        for _ in range(80):
            m = 0.5 * (a + b)
            if np.sign(g(m)) == np.sign(g(a)):
                a = m
            else:
                b = m
        roots.append(0.5 * (a + b))
    want = rot * reference_pitch(spec, np.array([theta]))[0]          # the design point, fixed frame
    q = min((point(r) for r in roots), key=lambda z: abs(z - want))
    d, L, rb = f.pivot_distance, f.arm_length, spec.cam.base_radius
    psi0 = math.acos((rb * rb - d * d - L * L) / (2 * d * L))
    return math.degrees(psi0 - np.angle(q - d))


@pytest.mark.parametrize("case", [dict(), dict(direction="cw", kind="knife")])
def test_max_deviation_is_the_arm_angle_error_of_the_built_curve(case):
    spec = CamSpec.from_dict(spec_dict(**case))
    design = design_cam(spec)
    prog = design.program
    theta = np.radians([17.0, 61.3, 95.0, 150.0, 201.7, 250.0, 299.9, 333.3])
    built = np.array([_built_lift(design, t) for t in theta])
    ours = design.pitch.actual_displacement(theta)
    assert np.max(np.abs(ours - built)) < 1e-9
    dev, at = design.max_deviation
    assert np.max(np.abs(built - prog.s(theta))) <= dev + 1e-12
    # the arm-angle error is small but not zero (the PH curve interpolates, between junctions)
    assert 1e-7 < dev < 1e-3


def test_junction_points_lie_on_the_exact_path():
    spec = CamSpec.from_dict(spec_dict())
    design = design_cam(spec)
    pc = design.pitch
    pts = pc.spline.point(np.arange(pc.M), np.zeros(pc.M))
    assert np.max(np.abs(pts - reference_pitch(spec, pc.angles))) < 1e-9
    assert np.max(np.abs(pc.actual_displacement(pc.angles) - pc.program.s(pc.angles))) < 1e-9


def test_roller_profile_is_the_exact_offset():
    spec = CamSpec.from_dict(spec_dict())
    design = design_cam(spec)
    assert design.profile.is_rational and design.profile.degree == 9
    u, pts = design.profile.sample(16)
    z = pts[:, 0] + 1j * pts[:, 1]
    dense = design.pitch_nurbs.sample(400)[1]
    dense = dense[:, 0] + 1j * dense[:, 1]
    dist = np.min(np.abs(z[:, None] - dense[None, ::1]), axis=1)
    assert np.max(np.abs(dist - 8.0)) < 2e-4        # chords of the dense polyline sit ~1e-4 inside


def test_load_is_the_torque_over_its_lever():
    """F = (T_L + k_t s + I s″ω²)/(L cos φ), from the spec's numbers here."""
    spec = CamSpec.from_dict(spec_dict())
    fol = follower_of(spec)
    prog = MotionProgram.from_spec(spec)
    theta = np.linspace(0.6, 2.5, 7)
    k = prog.evaluate(theta)
    omega = 60.0 * 2 * math.pi / 60
    torque = 800.0 + 500.0 * np.radians(k.s) + 2000.0 * 1e-3 * np.radians(k.d2s) * omega**2
    force = torque / (45.0 * np.cos(fol.pressure_angle(k)))
    assert np.allclose(fol.contact_force(k, omega), force, rtol=1e-13)


@pytest.mark.parametrize("change,field,words", [
    (dict(L=10.0), "follower.arm_length", "cannot reach the prime circle"),
    (dict(d=200.0), "follower.arm_length", "cannot reach the prime circle"),
    (dict(lift=40.0, d=60.0, L=45.0, rb=100.0), "motion[1].lift", "line through the pivot and the cam axis"),
    (dict(offset=3.0), "follower.offset", "translating followers only"),
    (dict(mass=1.0), "follower.mass", "follower.arm_inertia"),
])
def test_bad_geometry_names_the_field(change, field, words):
    extra = {k: change.pop(k) for k in ("offset", "mass") if k in change}
    d = spec_dict(**change, **extra)
    with pytest.raises(SpecError) as info:
        CamSpec.from_dict(d)
    assert info.value.field == field and words in str(info.value), str(info.value)


def test_oscillating_needs_pivot_and_arm():
    d = spec_dict()
    del d["follower"]["pivot_distance"]
    with pytest.raises(SpecError, match="follower.pivot_distance: is required"):
        CamSpec.from_dict(d)
    d = spec_dict()
    d["follower"] = {"kind": "roller", "roller_radius": 8.0, "pivot_distance": 60.0}
    with pytest.raises(SpecError, match="follower.pivot_distance: applies to oscillating followers only"):
        CamSpec.from_dict(d)

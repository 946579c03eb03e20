"""Flat-faced followers against closed forms and computations written for the test.

Translating face (Shigley & Uicker, *Theory of Machines and Mechanisms*, the flat-faced
follower's profile equations; Norton, *Cam Design and Manufacturing Handbook* §7): the contact
lies s′ along the face from the line of motion, the profile point in the cam frame is
Rot(∓θ)·(±s′, R_b + s) and its radius of curvature is ρ = R_b + s + s″ — checked here with the
harmonic and cycloidal laws written out in closed form.  Oscillating face: the envelope is
rebuilt as the intersection of neighbouring face lines (θ ± h) turned into the cam frame, and
the pressure angle from the face's normal against the velocity of the contact point about the
pivot.  The built PH profile's lift error is measured by finding the built curve's support
point in the face's direction (scipy's NURBS evaluation, dense sampling, golden-section)."""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest
from scipy.interpolate import BSpline
from scipy.optimize import minimize_scalar

from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import GeometryError, SpecError
from cam_workbench.generators.followers import follower_of
from cam_workbench.generators.motion import MotionProgram
from cam_workbench.generators.spec import DEFAULT_SPEC_DICT, CamSpec

H, RB = 20.0, 40.0


def translating(law="harmonic", direction="ccw", rb=RB, **fol):
    s = copy.deepcopy(DEFAULT_SPEC_DICT)
    s["cam"].update(base_radius=rb, direction=direction)
    s["follower"] = {"kind": "flat", "mass": 0.5, "preload": 20.0, "spring_rate": 1.0, **fol}
    for m in s["motion"]:
        if "lift" in m:
            m["lift"], m["law"] = H, law
    return s


def oscillating(d=70.0, f=5.0, rb=RB, lift=12.0, direction="ccw", law="cycloidal", **fol):
    s = copy.deepcopy(DEFAULT_SPEC_DICT)
    s["cam"].update(base_radius=rb, direction=direction)
    s["follower"] = {"kind": "flat", "motion": "oscillating", "pivot_distance": d, "face_offset": f,
                     "arm_inertia": 2000.0, "preload_torque": 800.0, **fol}
    for m in s["motion"]:
        if "lift" in m:
            m["lift"], m["law"] = lift, law
    return s


def rise_closed_form(law: str, theta: np.ndarray):
    """s, s′, s″ of the default program's rise (30°–150°, 20 mm) written out here."""
    beta = math.radians(120.0)
    x = (theta - math.radians(30.0)) / beta
    if law == "harmonic":
        return (H / 2 * (1 - np.cos(np.pi * x)), H * np.pi / (2 * beta) * np.sin(np.pi * x),
                H * np.pi**2 / (2 * beta**2) * np.cos(np.pi * x))
    return (H * (x - np.sin(2 * np.pi * x) / (2 * np.pi)), H / beta * (1 - np.cos(2 * np.pi * x)),
            2 * np.pi * H / beta**2 * np.sin(2 * np.pi * x))


@pytest.mark.parametrize("law", ["harmonic", "cycloidal"])
@pytest.mark.parametrize("direction", ["ccw", "cw"])
def test_translating_face_closed_forms(law, direction):
    spec = CamSpec.from_dict(translating(law, direction))
    fol = follower_of(spec)
    theta = np.linspace(math.radians(31), math.radians(149), 57)
    s, v, a = rise_closed_form(law, theta)
    k = MotionProgram.from_spec(spec).evaluate(theta)
    d = 1 if direction == "ccw" else -1
    contact = np.exp(-1j * d * theta) * (d * v + 1j * (RB + s))
    assert np.max(np.abs(fol.points(theta, k) - contact)) < 1e-12 * RB
    assert np.max(np.abs(fol.radius_of_curvature(k) - (RB + s + a))) < 1e-11 * RB
    assert np.max(np.abs(fol.pressure_angle(k))) == 0.0
    assert np.allclose(fol.face_position(k), d * v)
    # F = P_L + k s + M_f s″ω² (φ = 0), 0.5 kg × mm/s² = 5e-4 N
    omega = 2 * math.pi
    assert np.allclose(fol.contact_force(k, omega), 20.0 + 1.0 * s + 0.5e-3 * a * omega**2, rtol=1e-13)


def test_translating_face_cusp_refused_with_the_cam_angle():
    """ρ = R_b + s + s″ < 0 somewhere for a small base circle: the cam cannot be made; the
    refusal quotes the cam angle of the smallest ρ, found here by the closed form."""
    rb = 2.0          # ρ = R_b + s + s″ dips to 2 + 20 − 22.5 at the top of the harmonic rise
    spec = CamSpec.from_dict(translating("harmonic", rb=rb) | {"cam": {"base_radius": rb, "thickness": 10.0}})
    theta = np.linspace(0, 2 * np.pi, 200001)
    k = MotionProgram.from_spec(spec).evaluate(theta)
    rho = rb + k.s + k.d2s
    at = math.degrees(theta[np.argmin(rho)])
    assert rho.min() < 0
    with pytest.raises(GeometryError) as info:
        design_cam(spec)
    assert info.value.kind == "cusp" and abs(info.value.angle_deg - at) < 0.05, str(info.value)
    assert "cusp at cam angle" in str(info.value)


def envelope_reference(spec: CamSpec, theta: np.ndarray, h: float = 1e-5) -> np.ndarray:
    """Cam-frame contact points of the oscillating face: the face lines at θ − h and θ + h
    (pivot (d, 0), face at f from it, normal e^{iβ}, β = β₀ − s, cos β₀ = (R_b + f)/d) turned into
    the cam frame, intersected."""
    fl = spec.follower
    d, f, rb = fl.pivot_distance, fl.face_offset, spec.cam.base_radius
    beta0 = math.acos((rb + f) / d)
    prog = MotionProgram.from_spec(spec)
    sign = 1 if spec.cam.direction == "ccw" else -1

    def line(t):
        beta = beta0 - np.radians(prog.s(t))
        gamma = beta - sign * t                   # the normal seen from the cam
        return gamma, d * np.cos(beta) - f        # Re(e^{−iγ} x) = h

    g1, h1 = line(theta - h)
    g2, h2 = line(theta + h)
    det = np.cos(g1) * np.sin(g2) - np.sin(g1) * np.cos(g2)
    x = (h1 * np.sin(g2) - h2 * np.sin(g1)) / det
    y = (np.cos(g1) * h2 - np.cos(g2) * h1) / det
    return x + 1j * y


@pytest.mark.parametrize("case", [dict(), dict(direction="cw"), dict(f=-4.0, d=60.0, law="poly345"),
                                  dict(f=0.0, lift=8.0, law="modified_sine")])
def test_oscillating_face_envelope_and_pressure_angle(case):
    spec = CamSpec.from_dict(oscillating(**case))
    fol = follower_of(spec)
    theta = np.concatenate([np.linspace(0.7, 2.4, 30), np.linspace(3.8, 5.6, 30)])
    k = MotionProgram.from_spec(spec).evaluate(theta)
    ref = envelope_reference(spec, theta)
    assert np.max(np.abs(fol.points(theta, k) - ref)) < 1e-6
    # pressure angle: face normal against the contact point's velocity about the pivot
    fl = spec.follower
    beta = math.acos((RB + fl.face_offset) / fl.pivot_distance) - np.radians(k.s)
    n = np.exp(1j * beta)
    sign = 1 if spec.cam.direction == "ccw" else -1
    c = np.exp(1j * sign * theta) * ref
    vel = -1j * (c - fl.pivot_distance)
    dot = np.conj(n) * vel
    ref_phi = np.degrees(np.arctan2(np.abs(dot.imag), np.abs(dot.real)))
    assert np.max(np.abs(np.degrees(np.abs(fol.pressure_angle(k))) - ref_phi)) < 1e-4
    if fl.face_offset:
        assert ref_phi.max() > 1.0          # an offset face has a pressure angle
    # radius of curvature from the reference envelope's numerical derivatives
    hh = 2e-4
    p = [envelope_reference(spec, theta + j * hh) for j in (-1, 0, 1)]
    d1 = (p[2] - p[0]) / (2 * hh)
    d2 = (p[2] - 2 * p[1] + p[0]) / hh**2
    rho_ref = np.abs(d1) ** 3 / np.abs((np.conj(d1) * d2).imag)
    assert np.max(np.abs(fol.radius_of_curvature(k) / rho_ref - 1)) < 2e-3


def _support_lift(design, theta: float) -> float:
    """The lift the built profile gives a translating face at θ: the largest y of the built
    NURBS turned by θ, minus R_b (scipy evaluation, dense sampling, then golden section)."""
    nurbs = design.profile
    w = np.asarray(nurbs.weights)
    hom = np.column_stack([nurbs.poles[:, 0] * w, nurbs.poles[:, 1] * w, w])
    spl = BSpline(np.asarray(nurbs.knots, float), hom, nurbs.degree)
    sign = 1 if design.spec.cam.direction == "ccw" else -1
    rot = np.exp(1j * sign * theta)

    def y(u):
        v = spl(u)
        return ((rot * (v[..., 0] + 1j * v[..., 1]) / v[..., 2])).imag

    t0, t1 = nurbs.knots[nurbs.degree], nurbs.knots[-nurbs.degree - 1]
    u = np.linspace(t0, t1, 40001)
    j = int(np.argmax(y(u)))
    res = minimize_scalar(lambda x: -y(x), bounds=(u[max(j - 1, 0)], u[min(j + 1, len(u) - 1)]),
                          method="bounded", options={"xatol": 1e-13})
    return float(-res.fun) - design.spec.cam.base_radius


@pytest.mark.parametrize("direction", ["ccw", "cw"])
def test_translating_face_built_profile_lift_error(direction):
    spec = CamSpec.from_dict(translating("cycloidal", direction))
    design = design_cam(spec)
    theta = np.radians([10.0, 47.0, 88.8, 140.0, 180.0, 215.0, 271.0, 330.0])
    built = np.array([_support_lift(design, t) for t in theta])
    assert np.max(np.abs(design.pitch.actual_displacement(theta) - built)) < 1e-8
    dev, _ = design.max_deviation
    assert np.max(np.abs(built - design.program.s(theta))) <= dev + 1e-9
    assert dev < 2e-3                    # M = 60
    assert design.profile.degree == 5 and not design.profile.is_rational   # the PH curve is the profile


def test_face_width_check():
    """The contact travels from min δs′ to max δs′ (closed form); a face narrower than
    2·max|δs′ − e| fails the check, a wider one passes."""
    beta = math.radians(120.0)
    vmax = 2 * H / beta                   # cycloidal peak s′
    need = 2 * vmax
    spec = CamSpec.from_dict(translating("cycloidal", face_width=need * 0.99))
    r = design_cam(spec).checks["face_width"]
    assert r.status == "fail" and abs(r.value - need) < 1e-6 * need
    spec = CamSpec.from_dict(translating("cycloidal", face_width=need * 1.01))
    assert design_cam(spec).checks["face_width"].status == "pass"


def test_oscillating_face_bad_input():
    with pytest.raises(SpecError, match="follower.pivot_distance: the face at face_offset"):
        CamSpec.from_dict(oscillating(d=40.0, f=5.0))
    with pytest.raises(SpecError, match=r"motion\[1\].lift: the face would turn"):
        CamSpec.from_dict(oscillating(d=45.0, f=0.0, lift=30.0))
    with pytest.raises(SpecError, match="follower.face_width: applies to flat-faced followers only"):
        d = oscillating()
        d["follower"].update(kind="roller", roller_radius=5.0, arm_length=40.0)
        d["follower"].pop("face_offset")
        d["follower"]["face_width"] = 10.0
        CamSpec.from_dict(d)

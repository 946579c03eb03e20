"""Design checks (thesis Ch. 3) against hand calculations and closed forms computed here,
independently of cam_workbench.generators.checks.design: Hertz stress (Eq. 3.6) convex and concave,
pressure angle (Eq. 3.4), driving force (Eq. 3.5 with a spring), oscillation, curvature
(Eq. 3.7 against the curvature of the pitch points by finite differences), undercut, the
mm/inch equivalence of forces and stresses, and the optimiser's constraint arrays."""
import copy
import math

import numpy as np
import pytest

from cam_workbench.generators.checks.design import (StateModel, check_samples, constraint_arrays, envelope_points,
                                                    run_checks)
from cam_workbench.generators.followers.load import hertz_stress
from cam_workbench.generators.spec.examples import PAPER_SPEC_DICT, example_spec
from cam_workbench.generators.spec import CamSpec, load_spec

from .conftest import ROOT

FIXTURES = ROOT / "tests" / "fixtures"
LBF = 4.4482216152605          # N
INCH = 25.4                    # mm
PSI = 6.894757293168361e-3     # MPa


def test_hertz_convex_hand_calculation():
    """Thesis Eq. 3.6, by hand: F = 500 lbf, r_f = 0.425 in, r_c = 3.000 in (convex),
    t = 0.25 in, steel E = 29×10⁶ psi, ν = 0.29 for both bodies.

        1 − ν²          = 1 − 0.0841                      = 0.9159
        Δ               = 2 × 0.9159 / 29×10⁶             = 6.31655×10⁻⁸ in²/lbf
        1/r_f + 1/r_c   = 2.352941 + 0.333333             = 2.686275 /in
        π t Δ           = π × 0.25 × 6.31655×10⁻⁸         = 4.96101×10⁻⁸ in³/lbf
        S²              = 500 × 2.686275 / 4.96101×10⁻⁸   = 2.70739×10¹⁰ psi²
        S               =                                    164 541 psi

    Second method (Shigley's half-width form): b = √(2F/(πt) · Δ/(1/d₁ + 1/d₂)) = 7.7381×10⁻³ in,
    p_max = 2F/(π b t) = 164 541 psi."""
    s = hertz_stress(np.array([500.0]), 0.425, np.array([3.0]), 0.25, 29e6, 0.29, 29e6, 0.29)[0]
    assert s == pytest.approx(164_541, abs=1.0)
    b = math.sqrt(2 * 500 / (math.pi * 0.25) * 6.316551724e-8 / (1 / 0.85 + 1 / 6.0))
    assert b == pytest.approx(7.7381e-3, rel=1e-4)
    assert s == pytest.approx(2 * 500 / (math.pi * b * 0.25), rel=1e-9)


def test_hertz_concave_hand_calculation():
    """The same with a concave cam surface of radius 3.000 in (r_c = −3.000 in): the roller sits
    in a hollow, 1/r_f + 1/r_c = 2.352941 − 0.333333 = 2.019608 /in,
    S² = 500 × 2.019608 / 4.96101×10⁻⁸ = 2.03548×10¹⁰ psi², S = 142 670 psi."""
    s = hertz_stress(np.array([500.0]), 0.425, np.array([-3.0]), 0.25, 29e6, 0.29, 29e6, 0.29)[0]
    assert s == pytest.approx(142_670, abs=1.0)
    # flat cam: 1/r_c = 0; no contact force: no stress; roller larger than the hollow: inf
    flat = hertz_stress(np.array([500.0, -5.0, 500.0]), 0.425, np.array([np.inf, 3.0, -0.4]),
                        0.25, 29e6, 0.29, 29e6, 0.29)
    assert flat[0] == pytest.approx(math.sqrt(500 * (1 / 0.425) / 4.961008123e-8), rel=1e-9)
    assert flat[1] == 0.0 and flat[2] == np.inf


def test_hertz_in_si_units_is_the_same_stress():
    """2224.11 N, 10.795 mm, 76.2 mm, 6.35 mm, 199 948 MPa → 1134.47 MPa = 164 541 psi."""
    s = hertz_stress(np.array([500 * LBF]), 0.425 * INCH, np.array([3.0 * INCH]), 0.25 * INCH,
                     29e6 * PSI, 0.29, 29e6 * PSI, 0.29)[0]
    assert s == pytest.approx(164_541.4153 * PSI, rel=1e-9)


def radial_harmonic(e=0.0, **follower):
    d = copy.deepcopy(PAPER_SPEC_DICT)
    d["cam"].update(base_radius=40.0, bore_diameter=0.0, speed_rpm=300.0)
    d["follower"] = {"kind": "roller", "offset": e, "roller_radius": 6.0, **follower}
    d["motion"] = [{"kind": "rise", "angle": 100.0, "lift": 15.0, "law": "harmonic"},
                   {"kind": "dwell", "angle": 80.0},
                   {"kind": "return", "angle": 120.0, "lift": 15.0, "law": "cycloidal"},
                   {"kind": "dwell", "angle": 60.0}]
    return d


def harmonic_cycloidal(theta):
    """s, s′, s″ of radial_harmonic() in closed form (θ in rad), written out here."""
    b1, b2, h = math.radians(100), math.radians(120), 15.0
    s, v, a = np.zeros_like(theta), np.zeros_like(theta), np.zeros_like(theta)
    r = theta <= b1
    x = theta[r] / b1
    s[r] = h / 2 * (1 - np.cos(np.pi * x))
    v[r] = h * np.pi / (2 * b1) * np.sin(np.pi * x)
    a[r] = h * np.pi**2 / (2 * b1**2) * np.cos(np.pi * x)
    dw = (theta > b1) & (theta < math.radians(180))
    s[dw] = h
    rt = (theta >= math.radians(180)) & (theta <= math.radians(300))
    x = (theta[rt] - math.radians(180)) / b2
    s[rt] = h * (1 - x + np.sin(2 * np.pi * x) / (2 * np.pi))
    v[rt] = -h / b2 * (1 - np.cos(2 * np.pi * x))
    a[rt] = -h / b2**2 * 2 * np.pi * np.sin(2 * np.pi * x)
    return s, v, a


@pytest.mark.parametrize("e", [0.0, 7.5, -4.0])
def test_pressure_angle_against_closed_form(e):
    spec = CamSpec.from_dict(radial_harmonic(e))
    th = np.linspace(0, 2 * np.pi, 2_000_001)
    s, v, _ = harmonic_cycloidal(th)
    phi = np.degrees(np.arctan((v - e) / (math.sqrt(40.0**2 - e**2) + s)))
    j = int(np.argmax(np.abs(phi)))
    r = run_checks(spec)["pressure_angle"]
    assert r.value == pytest.approx(abs(phi[j]), abs=1e-7)
    assert r.at_deg == pytest.approx(math.degrees(th[j]), abs=1e-3)
    # the thesis' 71 equally spaced nodes of a closed-form law
    nodes = np.concatenate([np.linspace(0, math.radians(100), 71), np.linspace(math.radians(180),
                                                                               math.radians(300), 71)])
    s, v, _ = harmonic_cycloidal(nodes)
    phi71 = np.degrees(np.arctan((v - e) / (math.sqrt(40.0**2 - e**2) + s)))
    assert run_checks(spec, sampling="thesis71")["pressure_angle"].value == pytest.approx(
        np.max(np.abs(phi71)), abs=1e-12)


def test_driving_force_with_spring_against_closed_form():
    """F = (P_L + k·s + M·s″ω²)/cos φ (thesis Eq. 3.5 plus a spring), mm spec: M in kg and
    s″ω² in mm/s², so the inertia term is M·s″ω²/1000 N."""
    spec = CamSpec.from_dict(radial_harmonic(3.0, mass=2.5, preload=60.0, spring_rate=1.5))
    th = np.linspace(0, 2 * np.pi, 2_000_001)
    s, v, a = harmonic_cycloidal(th)
    omega = 300 * 2 * math.pi / 60
    phi = np.arctan((v - 3.0) / (math.sqrt(40.0**2 - 9.0) + s))
    force = (60.0 + 1.5 * s + 2.5 * a * omega**2 / 1000) / np.cos(phi)
    j = int(np.argmin(force))
    checks = run_checks(spec)
    r = checks["separation"]
    assert r.value == pytest.approx(force[j], abs=1e-7) and r.status == "pass"
    assert r.at_deg == pytest.approx(math.degrees(th[j]), abs=2e-3)
    assert checks.extremes["force"]["value"] == pytest.approx(np.max(np.abs(force)), rel=1e-10)
    # a smaller preload separates
    low = run_checks(spec.replace(**{"follower.preload": 10.0}))
    assert low["separation"].status == "fail" and low["separation"].value < 0


def test_no_load_skips_force_and_stress():
    checks = run_checks(CamSpec.from_dict(radial_harmonic()))
    assert checks["separation"].status == "skipped" and checks["contact_stress"].status == "skipped"
    assert "force" not in checks.extremes
    knife = copy.deepcopy(radial_harmonic(preload=10.0))
    knife["follower"] = {"kind": "knife", "preload": 10.0}
    kc = run_checks(CamSpec.from_dict(knife))
    assert kc["contact_stress"].status == "skipped" and "knife" in kc["contact_stress"].note
    assert [r.name for r in kc.results] == ["pressure_angle", "separation", "oscillation",
                                            "contact_stress", "curvature"]


def test_mm_spec_and_inch_spec_give_the_same_physics():
    """Thesis Example 5 in inches (lbf, lbf·s²/in, psi) and the same cam in SI-mm (N, kg, MPa)."""
    inch = load_spec(FIXTURES / "thesis_ex5_final.toml").replace(**{"follower.spring_rate": 150.0})
    d = inch.to_dict()
    d["units"] = "mm"
    for k in ("base_radius", "thickness"):
        d["cam"][k] *= INCH
    for k in ("offset", "roller_radius"):
        d["follower"][k] *= INCH
    d["follower"]["mass"] *= LBF / 0.0254           # lbf·s²/in → kg
    d["follower"]["preload"] *= LBF
    d["follower"]["spring_rate"] *= LBF / INCH
    for k in ("cam_modulus", "follower_modulus", "allowable_stress"):
        d["material"][k] *= PSI
    for m in d["motion"]:
        if "lift" in m:
            m["lift"] *= INCH
    mm = CamSpec.from_dict(d)
    a, b = run_checks(inch), run_checks(mm)
    assert b["separation"].value == pytest.approx(a["separation"].value * LBF, rel=1e-9)
    assert b.extremes["force"]["value"] == pytest.approx(a.extremes["force"]["value"] * LBF, rel=1e-9)
    assert b["contact_stress"].value == pytest.approx(a["contact_stress"].value * PSI, rel=1e-9)
    assert b["pressure_angle"].value == pytest.approx(a["pressure_angle"].value, rel=1e-12)
    assert b["curvature"].value == pytest.approx(a["curvature"].value * INCH, rel=1e-9)
    for r1, r2 in zip(a.results, b.results):
        assert r1.status == r2.status and r1.at_deg == pytest.approx(r2.at_deg, abs=1e-6)


def test_oscillation_fails_for_an_overshooting_bspline_rise():
    d = radial_harmonic()
    d["motion"][0] = {"kind": "rise", "angle": 100.0, "lift": 15.0, "law": "bspline",
                      "control_x": [10, 14, 18, 40, 60, 70, 82, 88, 94], "control_y": [0.2, 1.4, 1.2]}
    spec = CamSpec.from_dict(d)
    r = run_checks(spec)["oscillation"]
    assert r.status == "fail" and r.value < 0 and 0 < r.at_deg < 100
    # independently: s overshoots the lift inside the rise
    th = np.radians(np.linspace(0, 100, 20001))
    from cam_workbench.generators.motion import MotionProgram

    assert MotionProgram.from_spec(spec).s(th).max() > 15.0 + 1e-6
    assert run_checks(CamSpec.from_dict(radial_harmonic()))["oscillation"].status == "pass"


def curvature_from_points(spec, n=36_000):
    """Signed radius of curvature of the pitch points P(θ) = Rot(−θ)(e, s₀ + s) by central
    differences of the points themselves (no Eq. 3.7): + where the cam is convex.  0.01°
    steps balance truncation and rounding (≈ 1e-7 relative)."""
    th = np.linspace(0, 2 * np.pi, n, endpoint=False)
    s, _, _ = harmonic_cycloidal(th)
    e = spec.follower.offset
    p = np.exp(-1j * th) * (e + 1j * (math.sqrt(spec.cam.base_radius**2 - e * e) + s))
    h = th[1] - th[0]
    d1 = (np.roll(p, -1) - np.roll(p, 1)) / (2 * h)
    d2 = (np.roll(p, -1) - 2 * p + np.roll(p, 1)) / h**2
    kappa = (np.conj(d1) * d2).imag / np.abs(d1) ** 3     # + turning left; the pitch curve runs clockwise
    return th, -1.0 / kappa


def test_curvature_and_undercut_against_the_pitch_points():
    base = CamSpec.from_dict(radial_harmonic(2.0))
    th, rho = curvature_from_points(base)
    rho_min = float(np.min(np.where(rho > 0, rho, np.inf)))
    r = run_checks(base)["curvature"]
    assert r.value == pytest.approx(rho_min, rel=3e-7)
    assert r.at_deg == pytest.approx(math.degrees(th[np.argmin(np.where(rho > 0, rho, np.inf))]), abs=0.05)
    # roller between ρ_min/1.5 and ρ_min: the safety factor fails, the true undercut does not
    mid = run_checks(base.replace(**{"follower.roller_radius": rho_min / 1.2}))
    assert mid["curvature"].status == "fail" and mid["undercut"].status == "pass"
    assert mid["curvature"].limit == pytest.approx(1.5 * rho_min / 1.2)
    assert mid["undercut"].value == pytest.approx(rho_min - rho_min / 1.2, rel=1e-6)
    # roller beyond ρ_min: undercut
    big = run_checks(base.replace(**{"follower.roller_radius": rho_min * 1.02}))
    assert big["undercut"].status == "fail" and big["undercut"].value < 0
    # a different safety factor moves the limit
    lax = run_checks(base.replace(**{"follower.roller_radius": rho_min / 1.2, "checks.undercut_factor": 1.1}))
    assert lax["curvature"].status == "pass"


def test_stress_at_a_concave_point_uses_the_concave_radius():
    """Where the pitch curve is concave (ρ < 0) the cam surface is concave with radius
    |ρ| + r_f: S² = F(1/r_f − 1/(|ρ| + r_f))/(π t Δ), written out here.  The paper's cam
    (the default spec) is concave in its return."""
    d = copy.deepcopy(PAPER_SPEC_DICT)
    d["follower"].update(mass=1.0, preload=200.0, roller_width=6.0)
    d["material"] = {"cam_modulus": 2.0e5, "follower_modulus": 2.1e5, "cam_poisson": 0.3,
                     "follower_poisson": 0.28, "allowable_stress": 2000.0}
    spec = CamSpec.from_dict(d)
    model = StateModel(spec)
    cs = check_samples(model.program)
    st = model.state(cs.theta, cs.segment)
    concave = np.flatnonzero(st.pitch_radius < 0)
    assert concave.size > 10
    j = concave[len(concave) // 2]
    rc = abs(st.pitch_radius[j]) + 5.0
    delta = (1 - 0.3**2) / 2.0e5 + (1 - 0.28**2) / 2.1e5
    want = math.sqrt(st.force[j] * (1 / 5.0 - 1 / rc) / (math.pi * 6.0 * delta))   # t = min(10, 6)
    assert st.stress[j] == pytest.approx(want, rel=1e-12)


def test_envelope_points_lie_on_the_built_profile():
    from cam_workbench.generators import design_cam

    spec = example_spec("paper")
    design = design_cam(spec)
    model = StateModel(spec)
    th = np.linspace(0, 2 * np.pi, 721)
    env = envelope_points(model, th)
    pitch = model.geometry.pitch_points(th, model.program.s(th))
    assert np.allclose(np.abs(env - pitch), spec.roller_radius, atol=1e-12)
    assert np.all(np.abs(env) < np.abs(pitch))
    assert distance_to_curve(design.profile, env).max() < 2e-4   # the PH profile's deviation (M = 60)


def distance_to_curve(curve, pts, per_span=64):
    """Distance from each point (complex) to a NurbsCurve: nearest sample, then a vectorised
    golden-section search between its neighbours."""
    u, smp = curve.sample(per_span)
    z = smp[:, 0] + 1j * smp[:, 1]
    j = np.concatenate([np.argmin(np.abs(c[:, None] - z[None, :]), axis=1) for c in np.array_split(pts, 20)])
    lo, hi = u[np.maximum(j - 1, 0)], u[np.minimum(j + 1, len(u) - 1)]

    def dist(t):
        q = curve.evaluate(t)
        return np.abs(q[:, 0] + 1j * q[:, 1] - pts)

    g = (math.sqrt(5) - 1) / 2
    for _ in range(80):
        a, b = hi - g * (hi - lo), lo + g * (hi - lo)
        left = dist(a) < dist(b)
        hi, lo = np.where(left, b, hi), np.where(left, lo, a)
    return dist(0.5 * (lo + hi))


def test_constraint_arrays_agree_with_the_checks():
    spec = load_spec(FIXTURES / "thesis_ex5_final.toml")
    for sampling in ("thesis71", "dense"):
        s = spec.replace(**{"checks.sampling": sampling})
        ca = constraint_arrays(s)
        checks = run_checks(s)
        assert set(ca.g) == {"oscillation", "pressure_angle", "curvature", "undercut", "separation",
                             "contact_stress"}
        for name, g in ca.g.items():
            assert g.shape == ca.theta.shape
            assert (np.max(g) <= 1e-12) == (checks[name].status == "pass"), name
        # the separation constraint's worst node is the check's minimum force
        j = int(np.argmax(ca.g["separation"]))
        assert math.degrees(ca.theta[j]) == pytest.approx(checks["separation"].at_deg, abs=0.2)

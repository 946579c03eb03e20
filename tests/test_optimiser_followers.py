"""The optimiser for every follower kind (issue 13): oscillating knife/roller, translating and
oscillating flat faces.

Against computations that do not use the optimiser's model:

* the model's pressure angle, force, radius of curvature and stress at its nodes against the design
  checks' own state model (the follower classes, a second code path), and its areas/lengths against
  ``cam_workbench.generators.checks.areas`` (the followers' exact F, V);
* every constraint's, integral's and geometry row's gradient (R_b, pivot distance, arm length, face
  offset, control points) against complex-step derivatives of the values;
* a known answer: a translating flat face with only R_b free ends at the smallest cusp-free base
  radius, max over θ of −(s + s″) — written out here in closed form (harmonic: h(π²/(2β²) − 1)) or
  minimised by scipy (cycloidal) — plus the margin;
* an oscillating roller with only R_b free ends at the smallest R_b whose dense pressure angle is
  at the limit (brentq on ``run_checks``);
* optimised oscillating and flat cams pass the dense ``run_checks`` and are smaller than their start;
* the geometry (|d − L| < R_b < d + L, the lift below the line through the pivot) holds wherever the
  solver ends, and the model stays finite where it does not.

Before this change the optimiser used the translating formulas for every kind: the flat-face case
below ended "infeasible" at R_b = 42.9 (cusp), the oscillating ones read arm degrees as lengths.
"""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from cam_workbench.generators import load_spec
from cam_workbench.generators.checks.areas import pitch_area, pitch_length, profile_area, thesis_area
from cam_workbench.generators.checks.design import StateModel, run_checks
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.optimise import optimise
from cam_workbench.generators.optimise.kinds import force_reference
from cam_workbench.generators.optimise.model import SmoothModel
from cam_workbench.generators.optimise.space import DesignSpace
from cam_workbench.generators.spec import DEFAULT_SPEC_DICT, CamSpec

from .conftest import ROOT

FIXTURES = ROOT / "tests" / "fixtures"


# ---- specs ---------------------------------------------------------------------------------------
def oscillating_roller(kind="roller", d=60.0, L=45.0, rb=40.0, lift=15.0, direction="ccw", law="cycloidal",
                       **extra):
    s = copy.deepcopy(DEFAULT_SPEC_DICT)
    s["cam"].update(base_radius=rb, direction=direction, bore_diameter=10.0)
    f = {"kind": kind, "motion": "oscillating", "pivot_distance": d, "arm_length": L,
         "arm_inertia": 2000.0, "preload_torque": 800.0, "spring_torque_rate": 500.0, **extra}
    if kind == "roller":
        f.setdefault("roller_radius", 8.0)
    s["follower"] = f
    for m in s["motion"]:
        if "lift" in m:
            m["lift"], m["law"] = lift, law
    return s


def oscillating_flat(d=70.0, f=5.0, rb=40.0, lift=12.0, direction="ccw", law="cycloidal", **fol):
    s = copy.deepcopy(DEFAULT_SPEC_DICT)
    s["cam"].update(base_radius=rb, direction=direction)
    s["follower"] = {"kind": "flat", "motion": "oscillating", "pivot_distance": d, "face_offset": f,
                     "arm_inertia": 2000.0, "preload_torque": 800.0, **fol}
    for m in s["motion"]:
        if "lift" in m:
            m["lift"], m["law"] = lift, law
    return s


def translating_flat(rb=40.0, direction="ccw", law="harmonic", **fol):
    s = copy.deepcopy(DEFAULT_SPEC_DICT)
    s["cam"].update(base_radius=rb, direction=direction)
    s["follower"] = {"kind": "flat", "mass": 0.5, "preload": 20.0, "spring_rate": 1.0, **fol}
    for m in s["motion"]:
        if "lift" in m:
            m["lift"], m["law"] = 20.0, law
    return s


def bspline_variant(follower: dict, lift: float) -> CamSpec:
    """Thesis Example 5's initial B-spline rise and return (inch spec) with another follower: the
    control points' chain through the new kinds."""
    data = load_spec(FIXTURES / "thesis_ex5_initial.toml").to_dict()
    data["follower"] = follower
    for m in data["motion"]:
        if "lift" in m:
            m["lift"] = lift
    data["material"]["allowable_stress"] = 400000.0
    return CamSpec.from_dict(data)


OSC_ROLLER_BSPLINE = {"kind": "roller", "motion": "oscillating", "pivot_distance": 6.0, "arm_length": 4.5,
                      "roller_radius": 0.425, "arm_inertia": 0.3, "preload_torque": 1200.0,
                      "spring_torque_rate": 100.0}
OSC_FLAT_BSPLINE = {"kind": "flat", "motion": "oscillating", "pivot_distance": 8.0, "face_offset": 0.4,
                    "arm_length": 5.0, "face_width": 6.0, "arm_inertia": 0.3, "preload_torque": 1200.0}
TRANS_FLAT_BSPLINE = {"kind": "flat", "offset": 0.1, "face_width": 4.0, "mass": 0.02, "preload": 340.0,
                      "spring_rate": 20.0}

#: (name, spec, variables): every kind, both directions, every geometric variable
GRADIENT_CASES = [
    ("oscillating roller", CamSpec.from_dict(oscillating_roller()), "base_radius, pivot_distance, arm_length"),
    ("oscillating knife cw", CamSpec.from_dict(oscillating_roller("knife", direction="cw", law="poly345")),
     "base_radius, pivot_distance, arm_length"),
    ("translating flat cw", CamSpec.from_dict(translating_flat(direction="cw", offset=2.0, face_width=60.0)),
     "base_radius, offset"),
    ("oscillating flat, centred", CamSpec.from_dict(oscillating_flat(arm_length=30.0, face_width=60.0)),
     "base_radius, pivot_distance, face_offset, arm_length"),
    ("oscillating flat cw, no centre", CamSpec.from_dict(oscillating_flat(direction="cw", face_width=60.0)),
     "base_radius, pivot_distance, face_offset"),
    ("oscillating roller, B-spline", bspline_variant(OSC_ROLLER_BSPLINE, 15.0), "auto"),
    ("oscillating flat, B-spline", bspline_variant(OSC_FLAT_BSPLINE, 12.0),
     "base_radius, pivot_distance, face_offset, arm_length, control_points"),
    ("translating flat, B-spline", bspline_variant(TRANS_FLAT_BSPLINE, 1.0), "auto"),
]
IDS = [c[0] for c in GRADIENT_CASES]


def _with_checks(spec: CamSpec, variables: str) -> CamSpec:
    return spec.replace(**{"optimise.variables": variables, "checks.convex": True,
                           "material.allowable_stress": spec.material.allowable_stress or 1000.0})


# ---- the model against the follower classes ---------------------------------------------------------
@pytest.mark.parametrize("name, spec, variables", GRADIENT_CASES, ids=IDS)
def test_model_values_are_the_followers_own(name, spec, variables):
    """φ, F, ρ (κ), S at the model's nodes against the design checks' state model at the same cam
    angles (the follower classes), and the model's areas and lengths against checks.areas."""
    spec = _with_checks(spec, variables)
    space = DesignSpace(spec)
    model = SmoothModel(space, samples=41)
    p = space.p0
    th = model.node_thetas(p)
    seg = np.concatenate([np.full(sn.params.size, sn.index) for sn in model.segments])
    st = StateModel(spec).state(th, seg)
    geo = model.design_scalars(p)
    phi = np.concatenate([np.broadcast_to(model.local(geo, k.s, k.v, k.a, False)["phi"][0], k.s.shape)
                          for k in (model.kinematics(sn, sn.params, p, False) for sn in model.segments)])
    assert np.max(np.abs(phi - st.pressure_angle)) < 1e-12
    cons = model.constraints(p, grad=False)
    force = spec.checks.min_force - cons["separation"][0] * force_reference(spec)
    assert np.max(np.abs(force - st.force)) < 1e-12 * np.max(np.abs(st.force))
    if "cusp" in cons:                  # a flat face: ρG³ of the profile, G = 1 + δs′ [rad/rad] (1: translating)
        sense = 1 if spec.cam.direction == "ccw" else -1
        big_g = 1 + sense * math.radians(1) * st.kin.ds if spec.follower.motion == "oscillating" else 1.0
        rho = -cons["cusp"][0] * spec.cam.base_radius / big_g**3
        assert np.max(np.abs(rho - st.pitch_radius)) < 1e-12 * spec.cam.base_radius * 10
    if "curvature" in cons:
        kappa = (cons["curvature"][0] + 1) / (spec.checks.undercut_factor * spec.roller_radius)
        assert np.max(np.abs(kappa - 1 / st.pitch_radius)) < 1e-12 / spec.cam.base_radius
    if "contact_stress" in cons:             # where the follower presses (F ≤ 0: S = 0, separation says it)
        on = st.force > 0
        stress = np.sqrt(cons["contact_stress"][0][on] + 1) * spec.material.allowable_stress
        assert on.any() and np.max(np.abs(stress / st.stress[on] - 1)) < 1e-12
    if "pressure_angle" in cons:
        limit = math.radians(spec.checks.max_pressure_angle)
        assert np.allclose(cons["pressure_angle"][0], (st.pressure_angle / limit) ** 2 - 1, atol=1e-12)
    assert model.integral(p, "pitch_area", False)[0] == pytest.approx(pitch_area(spec), rel=1e-12)
    assert model.integral(p, "pitch_length", False)[0] == pytest.approx(pitch_length(spec), rel=1e-12)
    assert model.profile_area(p, False)[0] == pytest.approx(profile_area(spec), rel=1e-12)


@pytest.mark.parametrize("name, spec, variables", GRADIENT_CASES, ids=IDS)
def test_gradients_match_complex_step(name, spec, variables):
    """Every constraint family (at fixed nodes), integral and geometry row: the model's exact partials
    (hand-derived chain from the control points, forward-mode jets for the follower formulas) against
    complex-step derivatives of the values (h = 1e-30: exact to rounding)."""
    spec = _with_checks(spec, variables)
    space = DesignSpace(spec)
    model = SmoothModel(space, samples=31)
    p = space.p0.copy()
    n = p.size
    assert n >= 2

    def cstep(fn):
        return np.array([np.atleast_1d(fn(p.astype(complex) + 1e-30j * np.eye(n)[i])).imag / 1e-30
                         for i in range(n)]).T

    cons = model.constraints(p)
    assert cons
    for fam, (_vals, jac) in cons.items():
        ref = cstep(lambda q, fam=fam: model.constraints(q, grad=False, families=(fam,))[fam][0])
        assert np.max(np.abs(jac - ref)) <= 1e-11 * max(np.max(np.abs(ref)), 1e-300), fam
    for which in ("pitch_area", "pitch_length"):
        _v, g = model.integral(p, which)
        ref = cstep(lambda q, w=which: model.integral(q, w, grad=False)[0])
        assert np.max(np.abs(g - ref)) <= 1e-12 * np.max(np.abs(ref)), which
    # the geometry rows (oscillating kinds); the window maxima's gradients are the constraints'
    # partials at the maximisers (envelope theorem) — a complex step through the windows' argmax
    # is ill-posed where a check is flat (near-ties flip by rounding)
    geo = model.design_scalars(p)
    rows, gjac = model.kind.geometry_rows(geo)
    assert rows.size == (2 if spec.follower.motion == "oscillating" else 0)
    if rows.size:
        assert np.all(rows < 0)
        ng = len(geo)
        ref = np.array([model.kind.geometry_rows(tuple(np.asarray(geo, complex) + 1e-30j * np.eye(ng)[i]),
                                                 False)[0].imag / 1e-30 for i in range(ng)]).T
        assert np.max(np.abs(gjac - ref)) <= 1e-14 * np.max(np.abs(ref))


def test_the_window_maxima_reach_the_dense_check_extremes():
    """Oscillating roller and flat faces: the solver's constraints (window maxima, refined) equal
    the extremes the dense design checks find (refined in θ) to 1e-8 (the margin is 1e-4)."""
    for d, ext in ((oscillating_roller(), {}), (oscillating_flat(face_width=60.0, arm_length=30.0), {}),
                   (translating_flat(face_width=60.0), {"material.allowable_stress": 1000.0})):
        spec = CamSpec.from_dict(d).replace(**ext)
        space = DesignSpace(spec)
        model = SmoothModel(space)
        vals, _ = model.window_max(space.p0, tuple((f, 1.0) for f in model.families), grad=False, windows=80)
        per = vals.size // len(model.families)
        top = {f: float(np.max(vals[i * per:(i + 1) * per])) for i, f in enumerate(model.families)}
        checks = run_checks(spec)
        if "pressure_angle" in top:
            assert top["pressure_angle"] == pytest.approx((checks["pressure_angle"].value / 30.0) ** 2 - 1, abs=1e-8)
        assert top["separation"] == pytest.approx(-checks["separation"].value / force_reference(spec), abs=1e-8)
        if "curvature" in top:
            assert top["curvature"] == pytest.approx(1.5 * 8.0 / checks["curvature"].value - 1, abs=1e-8)
        if "cusp" in top and spec.follower.motion == "translating":      # G = 1: the rows are ρ and t
            assert top["cusp"] == pytest.approx(-checks["cusp"].value / spec.cam.base_radius, abs=1e-8)
            width = max(top["face_hi"], top["face_lo"])
            assert (width + 1) * spec.follower.face_width == pytest.approx(checks["face_width"].value, abs=1e-7)
        elif "cusp" in top:     # oscillating face: ρG³ and (t − c ∓ w/2)G, G > 0: the same verdicts
            assert (top["cusp"] < 0) == (checks["cusp"].status == "pass") and top["turning"] < 0
            face_ok = max(top["face_hi"], top["face_lo"]) <= 0
            assert face_ok == (checks["face_width"].status == "pass")


# ---- known answers -----------------------------------------------------------------------------------
def _flat_cusp_spec(law: str, direction: str) -> CamSpec:
    s = copy.deepcopy(DEFAULT_SPEC_DICT)
    s["cam"].update(base_radius=100.0, direction=direction)
    s["follower"] = {"kind": "flat"}             # no load: the cusp is the only check that binds
    s["motion"] = [{"kind": "dwell", "angle": 90}, {"kind": "rise", "angle": 60, "lift": 20.0, "law": law},
                   {"kind": "dwell", "angle": 120}, {"kind": "return", "angle": 90, "lift": 20.0, "law": law}]
    s["optimise"] = {"base_radius_min": 10.0}
    return CamSpec.from_dict(s)


def _smallest_cusp_free_radius(law: str) -> float:
    """max over θ of −(s + s″) of the program above, written out here.  Harmonic, rise over β:
    s + s″ = h/2 + (h/2)(π²/β² − 1) cos πx is least at the rise's end: h(1 − π²/(2β²)); the 90°
    return is gentler.  Cycloidal: s + s″ = h(x − sin 2πx/2π) + (2πh/β²) sin 2πx, minimised by
    scipy on the rise (60°) and the return (90°, s = h(1 − x + sin 2πx/2π), s″ = −(2πh/β²) sin 2πx)."""
    h = 20.0
    worst = 0.0
    for beta, rise in ((math.radians(60), True), (math.radians(90), False)):
        if law == "harmonic":
            worst = max(worst, -h * (1 - math.pi**2 / (2 * beta**2)))
            continue
        k = 2 * math.pi * h / beta**2
        if rise:
            f = lambda x: h * (x - math.sin(2 * math.pi * x) / (2 * math.pi)) + k * math.sin(2 * math.pi * x)  # noqa: E731
        else:
            f = lambda x: h * (1 - x + math.sin(2 * math.pi * x) / (2 * math.pi)) - k * math.sin(2 * math.pi * x)  # noqa: E731
        grid = np.linspace(0, 1, 2001)
        j = int(np.argmin([f(x) for x in grid]))
        r = minimize_scalar(f, bounds=(grid[max(j - 1, 0)], grid[min(j + 1, 2000)]), method="bounded",
                            options={"xatol": 1e-13})
        worst = max(worst, -r.fun)
    return worst


@pytest.mark.parametrize("law, direction", [("harmonic", "ccw"), ("cycloidal", "cw")])
def test_translating_flat_face_smallest_base_radius_without_a_cusp(law, direction):
    """variables = base_radius on a translating flat face: R_b* = max −(s + s″) (70 mm for the
    harmonic 20 mm over 60°) plus the constraint margin (ρ ≥ 1e-4 × the initial R_b)."""
    spec = _flat_cusp_spec(law, direction)
    res = optimise(spec, variables="base_radius")
    expect = _smallest_cusp_free_radius(law) + spec.optimise.constraint_margin * spec.cam.base_radius
    if law == "harmonic":
        assert _smallest_cusp_free_radius(law) == pytest.approx(70.0, rel=1e-14)
    assert res.spec.cam.base_radius == pytest.approx(expect, abs=1e-6 * spec.cam.base_radius)
    assert res.feasible and res.status in ("converged", "stopped")
    assert res.checks["cusp"].value == pytest.approx(1e-2, abs=1e-4)
    # "area" of a flat face is the area inside its profile (½∮(h² − h_γ²) dγ), not the thesis' formula
    assert res.value == pytest.approx(pitch_area(res.spec), rel=1e-12)
    assert res.value < thesis_area(res.spec)


def test_oscillating_roller_smallest_base_radius_for_the_pressure_angle():
    """Only R_b free: the optimum is the smallest R_b whose dense pressure angle is 30°·√(1 − margin),
    found independently by brentq on run_checks."""
    spec = CamSpec.from_dict(oscillating_roller())
    res = optimise(spec, variables="base_radius")
    assert res.feasible and res.status in ("converged", "stopped")
    target = 30.0 * math.sqrt(1 - spec.optimise.constraint_margin)

    def excess(r):
        return run_checks(spec.replace(**{"cam.base_radius": r}))["pressure_angle"].value - target

    r_ref = brentq(excess, 21.0, 40.0, xtol=1e-10)
    assert res.spec.cam.base_radius == pytest.approx(r_ref, rel=1e-5)
    assert res.worst_constraint()["name"] == "pressure_angle"


# ---- optimised cams --------------------------------------------------------------------------------
def _assert_valid_result(res, start):
    checks = run_checks(res.spec)                  # the dense, independent re-check
    assert checks.passed, checks.failed
    assert res.feasible and res.status in ("converged", "stopped", "budget exhausted")
    assert res.solver_status and res.solver_status in res.message
    assert res.value < res.initial_value
    assert load_spec(res.spec.to_dict()) == res.spec          # a valid spec (the arm reaches the circle)
    # the start is the user's, not moved (only [optimise] settings may differ)
    assert (res.initial_spec.cam, res.initial_spec.follower, res.initial_spec.motion) == (
        start.cam, start.follower, start.motion)


#: an oscillating follower's position as design variables (named: "auto" holds it)
ARM = "base_radius, pivot_distance, arm_length"


@pytest.mark.parametrize("kind", ["roller", "knife"])
def test_oscillating_cam_with_its_arm_is_smaller_and_passes(kind):
    """R_b, pivot distance and arm length: a smaller cam (area inside the pitch curve, exact)
    that passes every dense check; pivot and arm stay in their default bounds [½, 2] × the start."""
    spec = CamSpec.from_dict(oscillating_roller(kind))
    res = optimise(spec, variables=ARM)
    _assert_valid_result(res, spec)
    names = [v["name"] for v in res.report()["variables"]]
    assert names == ["cam.base_radius", "follower.pivot_distance", "follower.arm_length"]
    assert res.value == pytest.approx(pitch_area(res.spec), rel=1e-12)
    assert res.initial_value == pytest.approx(pitch_area(spec), rel=1e-12)
    assert res.report()["areas"]["final"]["thesis_eq_4_21"] is None
    f = res.spec.follower
    assert 30.0 <= f.pivot_distance <= 120.0 and 22.5 <= f.arm_length <= 90.0
    assert abs(f.pivot_distance - f.arm_length) < res.spec.cam.base_radius < f.pivot_distance + f.arm_length


@pytest.mark.parametrize("spec_dict, held", [
    ({**DEFAULT_SPEC_DICT, "follower": {**DEFAULT_SPEC_DICT["follower"], "offset": 5.0}}, ("offset",)),
    (oscillating_roller(), ("pivot_distance", "arm_length")),
    (oscillating_flat(face_width=40.0), ("pivot_distance", "face_offset")),
    (translating_flat(face_width=50.0, offset=1.0), ("offset",)),
])
def test_auto_moves_only_the_cams_size(spec_dict, held):
    """``optimise.variables = "auto"``: the base radius only; the follower's position — fixed by the
    machine as a rule — stays the user's (issue 20)."""
    spec = CamSpec.from_dict(spec_dict)
    space = DesignSpace(spec)
    assert space.labels == ("cam.base_radius",)
    res = optimise(spec, max_evaluations=300)
    assert [v["name"] for v in res.report()["variables"]] == ["cam.base_radius"]
    for name in held:
        assert getattr(res.spec.follower, name) == getattr(spec.follower, name)
    assert res.feasible and res.status_text.startswith("every check passes — ")


def test_oscillating_roller_bspline_control_points():
    """An oscillating roller on thesis Example 5's B-spline lifts (15° of arm): R_b, d, L and every
    control point; the area goes down and every dense check passes."""
    spec = bspline_variant(OSC_ROLLER_BSPLINE, 15.0)
    res = optimise(spec, max_evaluations=400, variables=ARM + ", control_points")
    _assert_valid_result(res, spec)
    assert len(res.variables) == 3 + 2 * 12


def test_oscillating_flat_face_with_its_face_width():
    """An oscillating flat face whose contact must stay on a 40 mm face centred on the travel (no
    arm_length): R_b, pivot distance and face offset; the face width check passes at its limit."""
    spec = CamSpec.from_dict(oscillating_flat(face_width=40.0))
    res = optimise(spec, variables="base_radius, pivot_distance, face_offset")
    _assert_valid_result(res, spec)
    assert [v["name"] for v in res.report()["variables"]] == [
        "cam.base_radius", "follower.pivot_distance", "follower.face_offset"]
    fw = res.checks["face_width"]
    assert fw.value <= 40.0
    assert res.value == pytest.approx(pitch_area(res.spec), rel=1e-12)


def test_translating_flat_face_auto():
    spec = CamSpec.from_dict(translating_flat(face_width=50.0, offset=1.0))
    res = optimise(spec)
    _assert_valid_result(res, spec)
    assert res.checks["face_width"].value <= 50.0


# ---- geometry ---------------------------------------------------------------------------------------
def test_the_model_is_finite_where_the_arm_cannot_reach():
    """Design points outside the follower's geometry (R_b < |d − L|, an arm turned past the line
    through the pivot) give finite rows: the geometry rows positive with their gradients, never an
    exception; the space says why such a design is not a spec."""
    from cam_workbench.generators.optimise.objectives import make_objective
    from cam_workbench.generators.optimise.problem import ScaledProblem

    spec = CamSpec.from_dict(oscillating_roller()).replace(**{"optimise.pivot_distance_max": 200.0,
                                                              "optimise.variables": ARM})
    space = DesignSpace(spec)
    model = SmoothModel(space)
    prob = ScaledProblem(space, model, make_objective("area", model), 1e-4, 1.0, 16)
    # R_b < d − L; R_b > d + L; the arm at 7° of the line through the pivot for a 15° lift
    for p, field in (([20.0, 200.0, 45.0], "follower.arm_length"), ([80.0, 30.0, 22.5], "follower.arm_length"),
                     ([52.4, 30.0, 22.5], "motion[1].lift")):
        z = space.to_z(np.array(p))
        fs, df, g, jac, _fp, viol = prob.evaluate(z, True)
        assert math.isfinite(fs) and np.all(np.isfinite(df))
        assert np.all(np.isfinite(g)) and np.all(np.isfinite(jac)) and viol > 0
        geo_rows, geo_jac = model.kind.geometry_rows(tuple(p))
        assert np.max(geo_rows) > 0 and np.all(np.isfinite(geo_jac)) and np.any(geo_jac != 0)
        assert not space.is_valid(np.array(p)) and space.invalid_reason(np.array(p)).startswith(field)


def test_wide_bounds_never_end_outside_the_geometry():
    """Bounds that hold many invalid arms: the run ends on a valid, dense-feasible design."""
    spec = CamSpec.from_dict(oscillating_roller()).replace(**{
        "optimise.pivot_distance_min": 20.0, "optimise.pivot_distance_max": 200.0,
        "optimise.arm_length_min": 10.0, "optimise.arm_length_max": 150.0, "optimise.base_radius_min": 15.0})
    res = optimise(spec, max_evaluations=500, variables=ARM)
    assert space_valid(res.spec)
    assert res.feasible


def space_valid(spec: CamSpec) -> bool:
    f = spec.follower
    return abs(f.pivot_distance - f.arm_length) < spec.cam.base_radius < f.pivot_distance + f.arm_length


# ---- bad input --------------------------------------------------------------------------------------
@pytest.mark.parametrize("spec_dict, changes, field, words", [
    (oscillating_roller(), {"optimise.variables": "base_radius, offset"}, "optimise.variables",
     "offset applies to translating followers only"),
    (translating_flat(), {"optimise.variables": "pivot_distance"}, "optimise.variables",
     "pivot_distance applies to oscillating followers only"),
    (DEFAULT_SPEC_DICT, {"optimise.variables": "arm_length"}, "optimise.variables",
     "arm_length applies to oscillating followers only"),
    (oscillating_roller(), {"optimise.variables": "face_offset"}, "optimise.variables",
     "face_offset applies to oscillating flat faces only"),
    (oscillating_flat(), {"optimise.variables": "arm_length"}, "optimise.variables",
     "give follower.arm_length to vary it"),
    (oscillating_roller(), {"optimise.objective": "machining_time"}, "optimise.objective",
     "use gcode_time"),
    (translating_flat(), {"optimise.objective": "peak_pressure_angle"}, "optimise.objective", "0 everywhere"),
    (oscillating_roller(), {"optimise.pivot_distance_min": 50.0, "optimise.pivot_distance_max": 40.0},
     "optimise.pivot_distance_max", "must be > optimise.pivot_distance_min"),
])
def test_variables_that_do_not_fit_the_follower_are_refused(spec_dict, changes, field, words):
    with pytest.raises(SpecError) as info:
        CamSpec.from_dict(spec_dict).replace(**changes)
    assert info.value.field == field and words in info.value.rule


@pytest.mark.parametrize("bound, value, start", [
    ("optimise.pivot_distance_min", 65.0, "(60 mm)"), ("optimise.pivot_distance_max", 55.0, "(60 mm)"),
    ("optimise.arm_length_min", 50.0, "(45 mm)"), ("optimise.arm_length_max", 40.0, "(45 mm)"),
])
def test_a_bound_that_excludes_the_start_is_refused(bound, value, start):
    spec = CamSpec.from_dict(oscillating_roller()).replace(**{bound: value})
    with pytest.raises(SpecError) as info:
        optimise(spec, variables=ARM)
    assert info.value.field == bound and start in info.value.rule and f"got {value:g}" in info.value.rule


def test_face_offset_bound_and_default_bounds_contain_the_start():
    spec = CamSpec.from_dict(oscillating_flat(f=-25.0)).replace(
        **{"optimise.variables": "base_radius, pivot_distance, face_offset"})
    space = DesignSpace(spec)
    assert space.labels == ("cam.base_radius", "follower.pivot_distance", "follower.face_offset")
    assert list(space.p0) == [40.0, 70.0, -25.0]
    assert space.lower[2] == -25.0 and space.upper[2] == 25.0           # widened to |f₀|
    assert space.lower[1] == 35.0 and space.upper[1] == 140.0
    with pytest.raises(SpecError) as info:
        optimise(spec.replace(**{"optimise.face_offset_max": 10.0}))
    assert info.value.field == "optimise.face_offset_max"
    assert "|follower.face_offset| of the starting design (25 mm), got 10" in info.value.rule

"""Polynomial segments' interior point lifts as optimiser design variables (``points``,
``motion[k].points``): the affine SVAJ basis against an independent power-basis solve, exact
gradients against complex-step and finite differences, a known optimum against a brute-force scan
done here, the monotonic-lift rows, the spec written back, CLI = API, and bad names refused."""
import json
import math

import numpy as np
import pytest

from cam_workbench.generators import load_spec, to_toml
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.optimise import optimise
from cam_workbench.generators.optimise.model import SmoothModel
from cam_workbench.generators.optimise.space import DesignSpace
from cam_workbench.generators.spec import CamSpec

from .conftest import requires_ocp
from .test_cli import run

H = 10.0           # rise [mm]
BETA_DEG = 120.0   # rise angle


def cam(points=((60.0, 4.0),), variables="motion[1].points", objective="peak_acceleration", **extra):
    """Dwell 30°, a polynomial rise of 10 mm over 120° through ``points``, dwell 30°, a cycloidal return
    over 180° (its peak |s″| = 2πh/β² = 6.37 mm/rad², below the rise's)."""
    return CamSpec.from_dict({
        "cam": {"base_radius": 40.0, "thickness": 5.0},
        "follower": {"kind": "roller", "roller_radius": 5.0},
        "motion": [{"kind": "dwell", "angle": 30},
                   {"kind": "rise", "angle": BETA_DEG, "lift": H, "law": "polynomial",
                    "points": [list(p) for p in points]},
                   {"kind": "dwell", "angle": 30},
                   {"kind": "return", "angle": 180, "lift": H, "law": "cycloidal"}],
        "optimise": {"variables": variables, "objective": objective, **extra}})


def poly_through(points):
    """Independent SVAJ solve in the power basis on x ∈ [0, 1]: s = v = a = 0 at x = 0, s = H and
    v = a = 0 at x = 1, s(x_i) = s_i — the lowest degree, 5 + len(points)."""
    n = 6 + len(points)
    rows, rhs = [], []
    k = np.arange(n)

    def der(x, d):
        c = np.array([math.perm(int(j), d) if j >= d else 0 for j in k], float)
        return c * np.where(k >= d, float(x) ** np.maximum(k - d, 0), 0.0)

    for x, d, v in [(0, 0, 0), (0, 1, 0), (0, 2, 0), (1, 0, H), (1, 1, 0), (1, 2, 0)]:
        rows.append(der(x, d)), rhs.append(v)
    for a, s in points:
        rows.append(der(a / BETA_DEG, 0)), rhs.append(s)
    return np.polynomial.Polynomial(np.linalg.solve(np.array(rows), np.array(rhs)))


def peak_acc(q):
    """max |s″| [mm/rad²] of the rise through (60°, q), on 20001 samples."""
    x = np.linspace(0, 1, 20001)
    return float(np.max(np.abs(poly_through([(60.0, q)]).deriv(2)(x)))) / math.radians(BETA_DEG) ** 2


def test_basis_matches_an_independent_power_basis_solve():
    """program_at(p) = the polynomial solved here from the same conditions, for new point lifts."""
    spec = cam(points=((40.0, 2.0), (80.0, 7.5)))
    space = DesignSpace(spec)
    assert space.labels == ("motion[1].points[0]", "motion[1].points[1]")
    p = np.array([3.1, 6.2])
    prog = space.program_at(p)
    th = np.linspace(0, math.radians(BETA_DEG), 301)
    s, v, a = (prog.curves[1].evaluate(th)[d] for d in range(3))
    ref = poly_through([(40.0, 3.1), (80.0, 6.2)])
    x = th / math.radians(BETA_DEG)
    assert np.max(np.abs(H * s - ref(x))) < 1e-10 * H
    assert np.max(np.abs(H * a - ref.deriv(2)(x) / math.radians(BETA_DEG) ** 2)) < 1e-8
    # the spec written back holds the new lifts at the same angles, and builds the same motion
    back = space.spec_at(p)
    assert back.motion[1].points == ((40.0, 3.1), (80.0, 6.2))
    again = DesignSpace(load_spec(to_toml(back)).replace(**{"optimise.variables": "points"})).program
    assert np.max(np.abs(again.curves[1].y - prog.curves[1].y)) < 1e-12


def test_gradients_exact_against_complex_step_and_finite_differences():
    spec = cam(points=((40.0, 3.0), (80.0, 7.0)), variables="base_radius, points", objective="area",
               **{}).replace(**{"follower.spring_rate": 20.0, "follower.preload": 30.0, "follower.mass": 0.5})
    space = DesignSpace(spec)
    model = SmoothModel(space, samples=41)
    p = space.p0.copy()
    cons = model.constraints(p)
    worst = 0.0
    for fam, (vals, jac) in cons.items():
        cs = []
        for i in range(p.size):
            pc = p.astype(complex)
            pc[i] += 1e-30j
            cs.append(model.constraints(pc, grad=False, families=(fam,))[fam][0].imag / 1e-30)
        cs = np.array(cs).T
        worst = max(worst, float(np.max(np.abs(jac - cs)) / max(np.max(np.abs(cs)), 1e-300)))
    assert worst < 1e-10
    area, g = model.integral(p, "thesis_area")
    h = 1e-5
    fd = np.array([(model.integral(p + h * e, "thesis_area", False)[0]
                    - model.integral(p - h * e, "thesis_area", False)[0]) / (2 * h) for e in np.eye(p.size)])
    assert np.max(np.abs(g - fd) / np.abs(fd)) < 1e-7
    # the point columns are not zero (the points move the lift)
    assert np.all(np.abs(g[1:]) > 1e-3)


def test_peak_acceleration_optimum_is_the_symmetric_point_of_a_brute_force_scan():
    """A rise symmetric about its middle with its one point there: peak |s″| is convex in the
    point's lift and symmetric about H/2, so H/2 (the 3-4-5 law) is the optimum.  The scan here
    (independent polynomial, 1-D grid then refined) finds it; the optimiser from s = 4 as well."""
    qs = np.linspace(0.5, 9.5, 91)
    vals = np.array([peak_acc(q) for q in qs])
    q_scan = qs[int(np.argmin(vals))]
    fine = np.linspace(q_scan - 0.1, q_scan + 0.1, 201)
    fv = np.array([peak_acc(q) for q in fine])
    q_scan, v_scan = fine[int(np.argmin(fv))], float(np.min(fv))
    assert q_scan == pytest.approx(H / 2, abs=1e-3)
    res = optimise(cam())
    assert res.feasible and res.checks.passed
    q = float(res.design[0])
    assert q == pytest.approx(q_scan, abs=2e-3)
    assert res.value == pytest.approx(v_scan, rel=1e-5)
    assert res.value < res.initial_value
    assert res.spec.motion[1].points[0][0] == 60.0 and res.spec.motion[1].points[0][1] == pytest.approx(q, abs=1e-12)


def test_area_pushes_the_lifts_down_to_the_monotonic_limit():
    """Minimising the area lowers the points until the rise would stop being monotonic.  Reference:
    a brute-force grid here over both lifts (independent polynomials), keeping the designs whose s′ ≥ 0
    on 4001 angles, ranked by ∫(R_b + s)² dθ over the rise (the rest of the cam does not move)."""
    res = optimise(cam(points=((40.0, 3.0), (80.0, 7.0)), variables="points", objective="area"))
    assert res.checks.passed
    pts = res.spec.motion[1].points
    x = np.linspace(0, 1, 4001)
    w = np.full(x.size, x[1])
    w[[0, -1]] /= 2
    base = poly_through([(40.0, 0.0), (80.0, 0.0)])
    phi = [poly_through([(40.0, 1.0), (80.0, 0.0)]) - base, poly_through([(40.0, 0.0), (80.0, 1.0)]) - base]
    s_b, v_b = base(x), base.deriv(1)(x)
    s_1, s_2 = phi[0](x), phi[1](x)
    v_1, v_2 = phi[0].deriv(1)(x), phi[1].deriv(1)(x)

    def best_on(q1s, q2s):
        q1, q2 = np.meshgrid(q1s, q2s, indexing="ij")
        q1, q2 = q1.ravel(), q2.ravel()
        ok = np.min(v_b[None] + q1[:, None] * v_1[None] + q2[:, None] * v_2[None], axis=1) >= -1e-9
        s = s_b[None] + q1[ok, None] * s_1[None] + q2[ok, None] * s_2[None]
        cost = ((40.0 + s) ** 2 * w).sum(axis=1)
        i = int(np.argmin(cost))
        return q1[ok][i], q2[ok][i], cost[i]

    q1, q2, _ = best_on(np.linspace(0, 5, 101), np.linspace(2, 9, 141))
    q1, q2, c_grid = best_on(np.linspace(q1 - 0.05, q1 + 0.05, 101), np.linspace(q2 - 0.05, q2 + 0.05, 101))
    s_opt = base(x) + pts[0][1] * s_1 + pts[1][1] * s_2
    c_opt = ((40.0 + s_opt) ** 2 * w).sum()
    assert float(np.min(base.deriv(1)(x) + pts[0][1] * v_1 + pts[1][1] * v_2)) >= -1e-9
    # the rows are sufficient (Bernstein hull of s′ raised to degree 128), so a little conservative:
    # here s′ touches 0 inside the rise, where the hull converges slowest — 0.2 % of this area
    assert c_grid <= c_opt <= c_grid * (1 + 2.5e-3)
    assert pts[0][1] == pytest.approx(q1, abs=0.02) and pts[1][1] == pytest.approx(q2, abs=0.2)
    assert pts[0][1] < 3.0 and pts[1][1] < 7.0


def test_point_shift_max_bounds_the_lifts():
    space = DesignSpace(cam(points=((40.0, 3.0), (80.0, 7.0)), point_shift_max=0.5))
    assert np.allclose(space.lower, [2.5, 6.5]) and np.allclose(space.upper, [3.5, 7.5])
    wide = DesignSpace(cam(points=((40.0, 3.0), (80.0, 7.0))))
    assert np.allclose(wide.lower, [0.0, 0.0]) and np.allclose(wide.upper, [H, H])
    res = optimise(cam(points=((40.0, 3.0), (80.0, 7.0)), variables="points", objective="area",
                       point_shift_max=0.2))
    assert np.allclose([p[1] for p in res.spec.motion[1].points], [2.8, 6.8], atol=1e-6)


@pytest.mark.parametrize("variables, says", [
    ("motion[0].points", "motion[0] is a dwell"),
    ("motion[3].points", "motion[3] has law = 'cycloidal'"),
    ("motion[7].points", "motion[7] does not exist (4 segments)"),
    ("motion[1].control_y", 'only a law = "bspline" rise or return has control points'),
    ("point", "unknown design variable 'point'"),
])
def test_bad_variable_names_are_refused(variables, says):
    with pytest.raises(SpecError) as exc:
        cam(variables=variables)
    assert exc.value.field == "optimise.variables" and says in exc.value.rule


def test_points_need_a_polynomial_with_points():
    spec = cam(variables="base_radius")
    with pytest.raises(SpecError) as exc:
        spec.replace(**{"motion[1].points": None, "optimise.variables": "motion[1].points"})
    assert exc.value.field == "optimise.variables" and "has no interior points" in exc.value.rule
    with pytest.raises(SpecError) as exc:
        spec.replace(**{"motion[1].points": None, "optimise.variables": "points"})
    assert exc.value.field == "optimise.variables" and "motion[k].points" in exc.value.rule


def test_a_neighbour_taking_a_free_end_value_is_refused():
    """A polynomial return that matches the rise's jerk (continuity 3) while the rise leaves its
    jerk free: the return would move with the rise's points."""
    spec = CamSpec.from_dict({
        "cam": {"base_radius": 40.0, "thickness": 5.0}, "follower": {"kind": "roller", "roller_radius": 5.0},
        "motion": [{"kind": "dwell", "angle": 60},
                   {"kind": "rise", "angle": 150, "lift": H, "law": "polynomial", "points": [[75.0, 5.0]]},
                   {"kind": "return", "angle": 150, "lift": H, "law": "polynomial", "start_continuity": 3}]})
    with pytest.raises(SpecError) as exc:
        DesignSpace(spec.replace(**{"optimise.variables": "motion[1].points"}))
    assert exc.value.field == "optimise.variables"
    assert "motion[2] takes its jerk from motion[1]'s end" in exc.value.rule
    assert "motion[1].end_jerk" in exc.value.rule


def test_cli_bad_variable_exits_2_naming_the_field(tmp_path):
    path = tmp_path / "poly.toml"
    path.write_text(to_toml(cam()))
    out = tmp_path / "never"
    res = run("optimise", str(path), "--variables", "motion[3].points", "-o", str(out))
    assert res.returncode == 2 and "optimise.variables" in res.stderr
    assert "Traceback" not in res.stderr and not out.exists()


@requires_ocp
def test_cli_and_api_give_the_same_result(tmp_path):
    path = tmp_path / "poly.toml"
    path.write_text(to_toml(cam(variables="base_radius", objective="area")))
    out = tmp_path / "opt"
    res = run("optimise", str(path), "--set", "optimise.variables=motion[1].points", "--set",
              "optimise.objective=peak_acceleration", "-o", str(out))
    assert res.returncode == 0, res.stderr
    rep = json.loads((out / "report.json").read_text())["optimise"]
    api = optimise(cam())
    [var] = rep["variables"]
    assert var["name"] == "motion[1].points[0]" and var["final"] == pytest.approx(float(api.design[0]), abs=1e-12)
    assert rep["final_value"] == pytest.approx(api.value, rel=1e-12)
    back = load_spec(out / "optimised.toml")
    assert back.motion[1].points == api.spec.motion[1].points
    assert f"{var['name']:28s} {var['initial']:12.6g} → {var['final']:12.6g}" in res.stdout


def test_docs_quote_the_measured_numbers():
    """docs/optimiser.md's polynomial-points paragraph quotes these runs."""
    from .conftest import ROOT

    doc = " ".join((ROOT / "docs" / "optimiser.md").read_text(encoding="utf-8").split())
    peak = optimise(cam())
    assert (f"ends at s = {peak.design[0]:.3f} mm" in doc
            and f"peak |s″| {peak.value:.4f} mm/rad² against {peak.initial_value:.4f}" in doc)
    assert f"in {peak.evaluations} evaluations" in doc
    area = optimise(cam(points=((40.0, 3.0), (80.0, 7.0)), variables="points", objective="area"))
    assert f"to {area.design[0]:.3f} and {area.design[1]:.3f} mm ({area.evaluations} evaluations" in doc

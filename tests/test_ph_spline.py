"""The closed C² PH quintic spline: interpolation, C² continuity (including the closing
junction), the PH property |r'| = σ, exact arc length against quadrature, and the
solution against an independent solver (scipy's MINPACK on the real 2M-equation system)."""
import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import root

from cam_workbench.generators.curves import bezier
from cam_workbench.generators.errors import SolveError
from cam_workbench.generators.followers.translating import FollowerGeometry
from cam_workbench.generators.motion import MotionProgram
from cam_workbench.generators.curves.ph_spline import residual, solve_closed_ph_spline, starting_approximation
from cam_workbench.generators.spec import default_spec

from .conftest import paper_case


def junctions(spec, m):
    th = 2 * np.pi * np.arange(m) / m
    prog, geo = MotionProgram.from_spec(spec), FollowerGeometry.from_spec(spec)
    return geo.pitch_points(th, prog.s(th))


CASES = [(default_spec(), 60), (paper_case(1), 60), (paper_case(2), 37),
         (default_spec().replace(**{"cam.direction": "cw"}), 90)]


@pytest.fixture(params=range(len(CASES)), ids=["case2_roller", "case1", "case2_M37", "cw_M90"])
def spline(request):
    spec, m = CASES[request.param]
    return solve_closed_ph_spline(junctions(spec, m))


def test_interpolates_junctions(spline):
    q = spline.junctions
    scale = np.max(np.abs(q))
    assert np.max(np.abs(spline.ctrl[:, 0] - q)) <= 1e-12 * scale
    assert np.max(np.abs(spline.ctrl[:, 5] - np.roll(q, -1))) <= 1e-12 * scale


def test_c2_at_every_junction_including_closing(spline):
    m = spline.M
    k = np.arange(m)
    nxt = (k + 1) % m
    one, zero = np.ones(m), np.zeros(m)
    d1_end = spline.first_derivative(k, one)
    d1_start = spline.first_derivative(nxt, zero)
    d2_end = spline.second_derivative(k, one)
    d2_start = spline.second_derivative(nxt, zero)
    s1 = np.max(np.abs(d1_end))
    s2 = np.max(np.abs(d2_end))
    assert np.max(np.abs(d1_end - d1_start)) <= 1e-12 * s1
    assert np.max(np.abs(d2_end - d2_start)) <= 1e-11 * s2


def test_pythagorean_hodograph_speed(spline):
    seg = np.repeat(np.arange(spline.M), 11)
    xi = np.tile(np.linspace(0, 1, 11), spline.M)
    # |r'| from the control points (derivative of the Bézier form) against σ = |w|²
    d = bezier.evaluate_at(bezier.derivative(spline.ctrl), seg, xi)
    assert np.allclose(np.abs(d), spline.speed(seg, xi), rtol=1e-12, atol=0)


def test_arc_length_matches_quadrature(spline):
    dctrl = bezier.derivative(spline.ctrl)
    total = 0.0
    for k in range(spline.M):
        total += quad(lambda x: abs(bezier.evaluate(dctrl[k], np.array(x))), 0, 1, epsabs=0, epsrel=1e-13)[0]
    assert spline.arc_length == pytest.approx(total, rel=1e-12)


def test_closing_sign_is_minus_for_a_cam():
    sp = solve_closed_ph_spline(junctions(default_spec(), 60))
    assert sp.closing_sign == -1
    assert sp.residual < 1e-14


def test_against_independent_minpack_solution():
    q = junctions(paper_case(2), 24)
    sp = solve_closed_ph_spline(q)
    z0, sign = starting_approximation(q)
    dq = np.roll(q, -1) - q

    def real_system(x):
        z = x[:24] + 1j * x[24:]
        f = residual(z, dq, sign)
        return np.concatenate([f.real, f.imag])

    sol = root(real_system, np.concatenate([z0.real, z0.imag]), method="hybr", tol=1e-13)
    assert np.max(np.abs(sol.fun)) < 1e-10 * 60 * np.max(np.abs(dq))
    z_ind = sol.x[:24] + 1j * sol.x[24:]
    assert np.max(np.abs(z_ind - sp.z)) <= 1e-10 * np.max(np.abs(sp.z))
    dense = solve_closed_ph_spline(q, method="dense")
    assert np.max(np.abs(dense.z - sp.z)) <= 1e-12 * np.max(np.abs(sp.z))


def test_paper_eq3_from_first_principles():
    """∫₀¹ w² for w = (½(a+b), b, ½(b+c)) equals (3a²+27b²+3c²+ac+13ab+13bc)/60 (paper Eq. 3)."""
    rng = np.random.default_rng(1)
    a, b, c = rng.normal(size=3) + 1j * rng.normal(size=3)
    w = np.array([(a + b) / 2, b, (b + c) / 2])
    integral = quad(lambda x: (bezier.evaluate(w, np.array(x)) ** 2).real, 0, 1, epsabs=1e-15)[0] + 1j * \
        quad(lambda x: (bezier.evaluate(w, np.array(x)) ** 2).imag, 0, 1, epsabs=1e-15)[0]
    eq3 = (3 * a * a + 27 * b * b + 3 * c * c + a * c + 13 * a * b + 13 * b * c) / 60
    assert abs(integral - eq3) < 1e-13


def test_large_spline_converges():
    sp = solve_closed_ph_spline(junctions(default_spec(), 20000))
    assert sp.residual < 1e-13 and sp.iterations <= 6


def test_degenerate_input_is_a_clear_error():
    with pytest.raises(SolveError, match="all equal"):
        solve_closed_ph_spline(np.zeros(10, dtype=complex))
    with pytest.raises(SolveError, match="at least 3"):
        solve_closed_ph_spline(np.array([0, 1], dtype=complex))


def test_non_convergence_is_reported():
    q = junctions(default_spec(), 60)
    with pytest.raises(SolveError, match="did not converge"):
        solve_closed_ph_spline(q, max_iter=1)

"""The B-spline lift law (thesis §2.5–2.7): basis and derivatives against scipy's
``BSpline``, the uniform clamped knots of Eq. 2.12, the zero end derivatives of §2.7,
s′ … s‴ by Eq. 2.37–2.39 against finite differences of the inverted curve, the θ(u)
inversion, other orders and more control points, and both spec frames."""
import copy
import math

import numpy as np
import pytest
from scipy.interpolate import BSpline

from cam_workbench.generators.curves.basis import basis_matrix
from cam_workbench.generators.motion.bspline_law import BSplineLift, clamped_uniform_knots, fixed_end_points
from cam_workbench.generators.motion import MotionProgram
from cam_workbench.generators.spec import CamSpec

EX5_RISE_X = [0.3772, 0.4424, 0.5148, 1.2282, 1.5945, 1.9231, 2.1345, 2.2648, 2.5848]
EX5_RISE_Y = [0.0772, 0.6242, 0.9094]
EX5_RET_X = [3.2859, 3.3433, 3.3922, 3.9976, 4.4062, 4.9349, 5.2382, 5.5314, 5.6768]
EX5_RET_Y = [0.9390, 0.2445, 0.0544]


def random_lift(order: int, n_points: int, span: float = 2.0, seed: int = 0) -> BSplineLift:
    rng = np.random.default_rng(seed)
    steps = rng.uniform(0.3, 1.0, n_points - 1)
    x = np.concatenate([[0.0], np.cumsum(steps)]) * span / steps.sum()
    nfix = fixed_end_points(order)
    y = np.concatenate([np.zeros(nfix), np.sort(rng.uniform(0.05, 0.95, n_points - 2 * nfix)),
                        np.ones(nfix)])
    return BSplineLift(order, x, y)


def test_knots_are_thesis_eq_2_12():
    """n = 10, k = 5: t = 0,0,0,0,0,1,2,3,4,5,6,7,7,7,7,7 and u ∈ [0, n − k + 2] = [0, 7]."""
    t = clamped_uniform_knots(11, 5)
    assert t.tolist() == [0] * 5 + [1, 2, 3, 4, 5, 6] + [7] * 5
    assert BSplineLift(5, np.linspace(0, 1, 11), np.r_[[0] * 4, .2, .5, .8, [1] * 4]).u_max == 7


@pytest.mark.parametrize("order,n_points", [(5, 11), (3, 7), (4, 9), (6, 14), (7, 20), (5, 25)])
def test_curve_and_derivatives_match_scipy(order, n_points):
    lift = random_lift(order, n_points, seed=order * 100 + n_points)
    u = np.linspace(0, lift.u_max, 997)
    th, yy = lift.parametric(u, 3)
    deg = order - 1
    for coords, ours in ((lift.x, th), (lift.y, yy)):
        ref = BSpline(lift.knots, coords, deg)
        for d in range(4):
            want = ref(u) if d == 0 else (ref.derivative(d)(u) if d <= deg else np.zeros_like(u))
            assert np.max(np.abs(ours[d] - want)) <= 1e-11 * max(1.0, np.max(np.abs(want)))
    # the sensitivity matrix (thesis Ch. 6) is the basis itself
    m = basis_matrix(lift.knots, deg, n_points, u, der=1)
    assert np.allclose(m @ lift.x, th[1], atol=1e-12)


def test_inversion_is_exact_and_vectorised():
    lift = random_lift(5, 15, span=math.radians(150))
    th = np.concatenate([np.linspace(0, lift.span, 200_001), [0.0, lift.span, 1e-300]])
    u = lift.u_of_theta(th)
    assert np.max(np.abs(lift.theta_at(u) - th)) < 4e-15
    assert u[-3] == 0.0 and u[-2] == pytest.approx(lift.u_max, abs=1e-14)


@pytest.mark.parametrize("order,n_points", [(5, 11), (4, 9), (6, 13), (5, 19)])
def test_end_derivatives_vanish(order, n_points):
    """Thesis §2.7: k − 1 control points at each end level make derivatives 1 … k − 2 vanish."""
    lift = random_lift(order, n_points)
    y, d1, d2, d3 = lift.derivatives_at(np.array([0.0, lift.u_max]))
    assert y.tolist() == pytest.approx([0.0, 1.0], abs=1e-15)
    zero = [d1, d2, d3][: order - 2]
    for d in zero:
        assert np.max(np.abs(d)) < 1e-12
    if order == 4:   # a cubic's jerk does not vanish at the ends
        assert np.min(np.abs(d3)) > 1e-3


def fd(f, x, h, order):
    """Central finite differences (4th-order accurate) of f at x."""
    if order == 1:
        return (-f(x + 2 * h) + 8 * f(x + h) - 8 * f(x - h) + f(x - 2 * h)) / (12 * h)
    if order == 2:
        return (-f(x + 2 * h) + 16 * f(x + h) - 30 * f(x) + 16 * f(x - h) - f(x - 2 * h)) / (12 * h * h)
    return (-f(x + 3 * h) + 8 * f(x + 2 * h) - 13 * f(x + h) + 13 * f(x - h) - 8 * f(x - 2 * h)
            + f(x - 3 * h)) / (8 * h**3)


def test_theta_derivatives_match_finite_differences_of_the_inverted_curve():
    """Eq. 2.37–2.39 against differences of y(θ) computed by inversion only (away from knots,
    where y(θ) is smooth)."""
    lift = BSplineLift(5, np.r_[0.0, EX5_RISE_X, math.radians(150)], np.r_[[0] * 4, EX5_RISE_Y, [1] * 4])
    th = np.linspace(0.1, lift.span - 0.1, 57)
    knots_theta = lift.theta_at(np.arange(1, 7))
    th = th[np.min(np.abs(th[:, None] - knots_theta[None, :]), axis=1) > 0.05]
    y, d1, d2, d3 = lift.evaluate(th)
    yf = lambda t: lift.evaluate(t)[0]  # noqa: E731
    assert np.max(np.abs(fd(yf, th, 1e-3, 1) - d1)) < 1e-9
    assert np.max(np.abs(fd(yf, th, 2e-3, 2) - d2)) < 1e-6
    assert np.max(np.abs(fd(yf, th, 5e-3, 3) - d3)) < 1e-3 * np.max(np.abs(d3))


def test_linear_theta_gives_plain_derivatives():
    """Control θ at c × the Greville abscissae make θ(u) = c·u exactly (linear precision), so
    d^m y/dθ^m = y^(m)(u)/c^m — scipy's derivatives, no chain rule."""
    k, n = 5, 12
    t = clamped_uniform_knots(n, k)
    greville = np.array([t[i + 1:i + k].mean() for i in range(n)])
    c = 0.3
    y = np.r_[[0] * 4, 0.1, 0.4, 0.7, 0.9, [1] * 4]
    lift = BSplineLift(k, c * greville, y)
    ref = BSpline(t, y, k - 1)
    u = np.linspace(0.01, lift.u_max - 0.01, 301)
    vals = lift.evaluate(c * u)
    for m in range(4):
        want = (ref(u) if m == 0 else ref.derivative(m)(u)) / c**m
        assert np.max(np.abs(vals[m] - want)) < 1e-9 * max(1, np.max(np.abs(want)))


def ex5_spec_dict():
    return {
        "units": "in",
        "cam": {"base_radius": 3.7344, "thickness": 0.25, "speed_rpm": 800.0},
        "follower": {"kind": "roller", "offset": 0.0001, "roller_radius": 0.425},
        "motion": [
            {"kind": "rise", "angle": 150.0, "lift": 1.0, "law": "bspline", "control_frame": "absolute_rad",
             "control_x": EX5_RISE_X, "control_y": EX5_RISE_Y},
            {"kind": "dwell", "angle": 30.0},
            {"kind": "return", "angle": 150.0, "lift": 1.0, "law": "bspline", "control_frame": "absolute_rad",
             "control_x": EX5_RET_X, "control_y": EX5_RET_Y},
            {"kind": "dwell", "angle": 30.0},
        ],
    }


def test_program_against_scipy_curve():
    """MotionProgram.s at θ(u) (scipy) equals L·y(u) (scipy), for the rise and the return:
    the inversion inside the program is checked against a curve built without it."""
    spec = CamSpec.from_dict(ex5_spec_dict())
    prog = MotionProgram.from_spec(spec)
    for k, xs, ys, start, y0, y1 in ((0, EX5_RISE_X, EX5_RISE_Y, 0.0, 0, 1),
                                     (2, EX5_RET_X, EX5_RET_Y, math.pi, 1, 0)):
        x = np.r_[start, xs, start + math.radians(150)]
        y = np.r_[[y0] * 4, ys, [y1] * 4]
        t = clamped_uniform_knots(11, 5)
        u = np.linspace(0, 7, 5001)
        theta = BSpline(t, x, 4)(u)
        s = prog.evaluate(theta, np.full(u.shape, k)).s
        assert np.max(np.abs(s - BSpline(t, y, 4)(u))) < 1e-13


def test_program_is_continuous_with_zero_end_derivatives():
    prog = MotionProgram.from_spec(CamSpec.from_dict(ex5_spec_dict()))
    b = prog.boundaries
    for th in b[:-1]:
        for eps in (1e-9, -1e-9):
            k = prog.evaluate(np.array([th + eps]))
            assert abs(k.ds[0]) < 1e-12 and abs(k.d2s[0]) < 1e-9 and abs(k.d3s[0]) < 1e-5
    assert prog.s(np.radians([150.0, 180.0, 330.0])).tolist() == pytest.approx([1.0, 1.0, 0.0], abs=1e-15)


def test_relative_degree_frame_equals_thesis_absolute_radians():
    """The same control points given as degrees from the segment start and as the thesis'
    radians of absolute cam angle give the same motion."""
    d = ex5_spec_dict()
    rel = copy.deepcopy(d)
    for seg, start in ((rel["motion"][0], 0.0), (rel["motion"][2], 180.0)):
        seg["control_x"] = [math.degrees(x) - start for x in seg["control_x"]]
        seg.pop("control_frame")
    a = MotionProgram.from_spec(CamSpec.from_dict(d))
    b = MotionProgram.from_spec(CamSpec.from_dict(rel))
    th = np.linspace(0, 2 * np.pi, 3001)
    ka, kb = a.evaluate(th), b.evaluate(th)
    for f in ("s", "ds", "d2s", "d3s"):
        assert np.allclose(getattr(ka, f), getattr(kb, f), rtol=0, atol=1e-10)


def test_all_interior_y_equals_free_y_and_control_start():
    d = ex5_spec_dict()
    full = copy.deepcopy(d)
    full["motion"][0]["control_y"] = [0, 0, 0] + EX5_RISE_Y + [1, 1, 1]
    full["motion"][2]["control_y"] = [1, 1, 1] + EX5_RET_Y + [0, 0, 0]
    moved = copy.deepcopy(d)                 # the same cam described from a frame starting at -20°
    moved["motion"][0].update(control_start=-20.0,
                              control_x=[x - math.radians(20) for x in EX5_RISE_X])
    th = np.linspace(0, 2 * np.pi, 2001)
    ref = MotionProgram.from_spec(CamSpec.from_dict(d)).evaluate(th)
    for other in (full, moved):
        k = MotionProgram.from_spec(CamSpec.from_dict(other)).evaluate(th)
        assert np.allclose(k.s, ref.s, atol=1e-12) and np.allclose(k.d3s, ref.d3s, atol=1e-8)


def test_more_points_and_other_orders_in_a_spec():
    d = {"cam": {"base_radius": 40.0, "thickness": 8.0},
         "follower": {"kind": "roller", "roller_radius": 5.0},
         "motion": [
             {"kind": "rise", "angle": 120, "lift": 10.0, "law": "bspline", "order": 6,
              "control_x": [8, 12, 16, 20, 40, 60, 80, 100, 104, 108, 112, 116],
              "control_y": [0.2, 0.4, 0.6, 0.8]},
             {"kind": "dwell", "angle": 60},
             {"kind": "return", "angle": 120, "lift": 10.0, "law": "bspline", "order": 4,
              "control_x": [10, 20, 50, 70, 90, 105, 115], "control_y": [0.7, 0.4, 0.2]},
             {"kind": "dwell", "angle": 60}]}
    spec = CamSpec.from_dict(d)
    prog = MotionProgram.from_spec(spec)
    assert [c.order if c else None for c in prog.curves] == [6, None, 4, None]
    assert prog.curves[0].n_points == 14 and prog.curves[2].n_points == 9
    b = prog.boundaries
    k = prog.evaluate(np.array([b[0] + 1e-12, b[1] - 1e-12, b[2] + 1e-12, b[3] - 1e-12]))
    assert np.allclose(k.s, [0, 10, 10, 0], atol=1e-9)
    assert np.max(np.abs(k.ds)) < 1e-9 and np.max(np.abs(k.d2s)) < 1e-6
    # order 6 also zeroes the jerk; the cubic return does not
    assert abs(k.d3s[0]) < 1e-3 and abs(k.d3s[2]) > 1e-2

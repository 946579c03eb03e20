"""Lines, arcs and cubic splines within a tolerance of the exact profile (for G-code and DXF):
two-sided distance measured densely, closed paths, tangent continuity of biarcs, an exact circle
reproduced by arcs of its own radius, and a polynomial cubic within the tolerance of the exact
rational circle."""
import numpy as np
import pytest

from cam_workbench.generators.curves.approx import fit_biarcs, flatten, max_distance, polyline_path
from cam_workbench.generators.curves.nurbs import NurbsCurve


@pytest.mark.parametrize("tol", [1e-2, 1e-3, 1e-4])
def test_biarcs_within_tolerance_and_tangent_continuous(default_design, tol):
    curve = default_design.profile
    path = fit_biarcs(curve, tol)
    assert max_distance(path, curve) <= tol
    assert abs(path.end[-1] - path.start[0]) < 1e-12
    assert np.max(np.abs(path.end[:-1] - path.start[1:])) < 1e-12
    arc = path.is_arc
    assert np.allclose(np.abs(path.end - path.center)[arc], path.radius[arc], rtol=1e-9)
    # tangent directions at every joint agree (G¹)
    def tangent(z, c, ccw):
        return 1j * (z - c) * np.where(ccw, 1, -1)
    t_end = np.where(arc, tangent(path.end, path.center, path.ccw), path.end - path.start)
    t_start = np.where(arc, tangent(path.start, path.center, path.ccw), path.end - path.start)
    t_end, t_start = t_end / np.abs(t_end), t_start / np.abs(t_start)
    assert np.max(np.abs(t_end - np.roll(t_start, -1))) < 1e-7
    # arc length of the path converges to the curve's
    length = default_design.profile.sample(400)[1]
    poly = length[:, 0] + 1j * length[:, 1]
    assert path.length == pytest.approx(np.sum(np.abs(np.diff(poly))), rel=5 * tol)


@pytest.mark.parametrize("tol", [1e-2, 1e-3, 1e-4])
def test_polyline_within_tolerance(default_design, tol):
    curve = default_design.profile
    u, pts = flatten(curve, tol)
    assert abs(pts[-1] - pts[0]) < 1e-12
    assert max_distance(polyline_path(u, pts), curve) <= tol
    assert np.all(np.diff(u) > 0)


def test_fewer_elements_for_looser_tolerance(default_design):
    c = default_design.profile
    assert fit_biarcs(c, 1e-4).n > fit_biarcs(c, 1e-2).n / 2  # arcs come in pairs
    assert len(flatten(c, 1e-4)[0]) > 4 * len(flatten(c, 1e-2)[0])


def test_circle_is_reproduced_exactly_by_arcs():
    # exact rational quadratic circle of radius 7 (4 spans)
    w = np.sqrt(0.5)
    poles = np.array([[7, 0], [7, 7], [0, 7], [-7, 7], [-7, 0], [-7, -7], [0, -7], [7, -7], [7, 0]], float)
    weights = np.array([1, w, 1, w, 1, w, 1, w, 1])
    knots = np.array([0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 4], float)
    circle = NurbsCurve(2, knots, poles, weights)
    path = fit_biarcs(circle, 1e-6)
    assert np.allclose(path.radius, 7.0, rtol=1e-12)
    assert np.allclose(path.center, 0.0, atol=1e-11)
    assert path.n == 8 and np.all(path.ccw)
    assert path.length == pytest.approx(2 * np.pi * 7, rel=1e-12)


def test_distance_is_measured_right_at_the_seam(default_design):
    """A fine polyline (1e-5) has many vertices within one curve-sample spacing of the seam;
    the measured distance must not see a phantom gap there (it did before the closed
    polyline wrapped round: 1.8e-3 reported for a 8e-6 polyline)."""
    c = default_design.profile
    u, pts = flatten(c, 1e-5)
    d = max_distance(polyline_path(u, pts), c)
    assert d <= 1e-5
    assert d == pytest.approx(max_distance(polyline_path(u, pts), c, samples_per_span=2000), rel=0.05)


# ---- fit_cubic -------------------------------------------------------------------------------
def _rational_circle(r: float) -> "NurbsCurve":
    """The full circle of radius r as the standard 9-pole rational quadratic (exact)."""
    from cam_workbench.generators.curves.nurbs import NurbsCurve

    w = np.sqrt(0.5)
    poles = r * np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], float)
    weights = np.array([1, w, 1, w, 1, w, 1, w, 1])
    knots = np.array([0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 4], float)
    return NurbsCurve(2, knots, poles, weights)


@pytest.mark.parametrize("tol", [1e-2, 1e-4, 1e-6])
def test_fit_cubic_of_a_circle_stays_within_tol_of_it(tol):
    """A polynomial cubic of the exact rational circle: every point within tol of the circle
    (| |p| − r |, the closed form), closed, C¹ at its triple knots, and its measured distance
    what curve_distance reports."""
    from cam_workbench.generators.curves.approx import curve_distance, fit_cubic

    r = 25.0
    circle = _rational_circle(r)
    cubic = fit_cubic(circle, tol)
    assert cubic.degree == 3 and not cubic.is_rational and cubic.is_closed
    u = np.linspace(0, 4, 200001)
    p, d = cubic.evaluate_with_derivative(u)
    radial = np.abs(np.hypot(p[:, 0], p[:, 1]) - r)
    assert radial.max() <= tol
    assert curve_distance(cubic, circle) == pytest.approx(radial.max(), rel=2e-2)
    # the derivative is continuous across every knot (C¹), the tangent across the seam
    knots = np.unique(cubic.knots)[1:-1]
    _, left = cubic.evaluate_with_derivative(knots - 1e-9)
    _, right = cubic.evaluate_with_derivative(knots + 1e-9)
    assert np.max(np.abs(left - right)) <= 1e-6 * r
    assert np.allclose(d[0], d[-1], rtol=0, atol=1e-9 * r)
    # fewer poles for a looser tolerance, more for a tighter one (error ~ h⁴)
    if tol == 1e-6:
        assert cubic.n_poles > fit_cubic(circle, 1e-2).n_poles

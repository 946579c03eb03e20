"""Exact rational offsets: sampled points of the offset NURBS lie exactly at the offset
distance along the pitch normal; the NURBS evaluated by scipy's independent B-spline code
agrees with ours; weights are positive and the curve is closed."""
import numpy as np
import pytest
from scipy.interpolate import BSpline

from cam_workbench.generators.curves.offsets import offset_nurbs, pitch_nurbs
from cam_workbench.generators.curves.ph_spline import solve_closed_ph_spline

from .test_ph_spline import junctions
from cam_workbench.generators.spec import default_spec


@pytest.fixture(scope="module")
def spline():
    return solve_closed_ph_spline(junctions(default_spec(), 60))


@pytest.mark.parametrize("d", [-5.0, -0.3, 2.0, 7.5])
def test_offset_points_are_exactly_at_distance_along_normal(spline, d):
    curve = offset_nurbs(spline, d)
    assert curve.degree == 9 and curve.is_rational and curve.is_closed
    assert np.all(curve.weights > 0)
    u, pts = curve.sample(17)
    seg = np.minimum(u.astype(int), spline.M - 1)
    xi = u - seg
    base = spline.point(seg, xi)
    tangent = spline.first_derivative(seg, xi)
    normal = 1j * tangent / np.abs(tangent)  # left normal
    expected = base + d * normal
    got = pts[:, 0] + 1j * pts[:, 1]
    assert np.max(np.abs(got - expected)) <= 1e-9 * abs(d)


def test_nurbs_evaluation_against_scipy_bspline(spline):
    curve = offset_nurbs(spline, -5.0)
    hom = np.column_stack([curve.poles * curve.weights[:, None], curve.weights])
    sp = BSpline(curve.knots, hom, curve.degree)
    u = np.linspace(0, spline.M, 3001)
    h = sp(u)
    ref = h[:, :2] / h[:, 2:3]
    assert np.max(np.abs(curve.evaluate(u) - ref)) <= 1e-12 * curve.size
    pts, der = curve.evaluate_with_derivative(u[1:-1] + 1e-3)
    dh = sp.derivative()(u[1:-1] + 1e-3)
    hh = sp(u[1:-1] + 1e-3)
    ref_der = (dh[:, :2] - hh[:, :2] / hh[:, 2:3] * dh[:, 2:3]) / hh[:, 2:3]
    assert np.max(np.abs(der - ref_der)) <= 1e-10 * np.max(np.abs(ref_der))


def test_pitch_nurbs_reproduces_the_spline(spline):
    curve = pitch_nurbs(spline)
    assert curve.degree == 5 and not curve.is_rational
    u = np.linspace(0, spline.M, 2001)[:-1]
    seg = u.astype(int)
    ref = spline.point(seg, u - seg)
    got = curve.evaluate(u)
    assert np.max(np.abs(got[:, 0] + 1j * got[:, 1] - ref)) <= 1e-12 * curve.size


def test_offset_area_follows_steiner_formula(spline):
    """Area of an inward offset of a convex-enough closed curve: A(d) = A − L·d + π d²."""
    a0 = abs(pitch_nurbs(spline).area())
    length = spline.arc_length
    for d in (1.0, 3.0, 5.0):
        inward = offset_nurbs(spline, -d)  # the pitch curve runs clockwise: right is inside
        assert abs(inward.area()) == pytest.approx(a0 - length * d + np.pi * d * d, rel=1e-12)


def test_profile_radius_of_curvature_is_pitch_radius_minus_roller(default_design):
    """Curvature of the offset NURBS itself (central differences of its own derivative) against
    ρ_profile = ρ_pitch − r (offset-curve relation), at points away from the junctions."""
    d = default_design
    r = d.spec.roller_radius
    u = (np.arange(d.pitch.M)[:, None] + np.linspace(0.1, 0.9, 9)[None, :]).ravel()
    h = 1e-5
    _, d1 = d.profile.evaluate_with_derivative(u)
    _, d1p = d.profile.evaluate_with_derivative(u + h)
    _, d1m = d.profile.evaluate_with_derivative(u - h)
    d2 = (d1p - d1m) / (2 * h)
    kappa = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(d1[:, 0], d1[:, 1]) ** 3
    seg = u.astype(int)
    rho_pitch = -d.geometry.sense / d.pitch.spline.curvature(seg, u - seg)
    rho_profile = -d.geometry.sense / kappa
    assert np.allclose(rho_profile, rho_pitch - r, rtol=1e-6)

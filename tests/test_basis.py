"""The B-spline basis and the clamped cubic interpolation (generators.curves.basis) against SciPy's
own (``scipy.interpolate.BSpline.design_matrix`` and ``make_interp_spline``: an independent
implementation), and the drawings' cubic fit held to its tolerance."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from cam_workbench.generators.curves.basis import basis_matrix, interpolating_cubic

interpolate = pytest.importorskip("scipy.interpolate")


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 24), st.integers(0, 2**32 - 1))
def test_clamped_cubic_is_scipys(n, seed):
    rng = np.random.default_rng(seed)
    x = np.linspace(0.0, 1.0, n + 1)
    y = rng.normal(size=(n + 1, 3, 2))
    d0, d1 = rng.normal(size=(3, 2)), rng.normal(size=(3, 2))
    knots, coef = interpolating_cubic(x, y, d0, d1)
    ref = interpolate.make_interp_spline(x, y, k=3, bc_type=([(1, d0)], [(1, d1)]))
    np.testing.assert_allclose(knots, ref.t, rtol=0, atol=0)
    np.testing.assert_allclose(coef, ref.c, rtol=1e-12, atol=1e-12 * np.abs(ref.c).max())
    u = rng.uniform(0.0, 1.0, 50)
    ours = np.einsum("ij,j...->i...", basis_matrix(knots, 3, n + 3, u), coef)
    np.testing.assert_allclose(ours, ref(u), rtol=1e-12, atol=1e-12 * np.abs(ref.c).max())


@pytest.mark.parametrize("degree", [2, 3, 5])
def test_basis_matrix_is_scipys_design_matrix(degree):
    knots = np.concatenate([np.zeros(degree + 1), np.sort(np.random.default_rng(1).uniform(0, 1, 9)),
                            np.ones(degree + 1)])
    n = len(knots) - degree - 1
    u = np.linspace(0.0, 1.0, 101)[:-1]
    ref = interpolate.BSpline.design_matrix(u, knots, degree).toarray()
    np.testing.assert_allclose(basis_matrix(knots, degree, n, u), ref, atol=1e-14)


@settings(max_examples=80, deadline=None)
@given(st.integers(3, 400), st.integers(1, 300), st.floats(0.0, 3.0), st.integers(0, 2**32 - 1))
def test_nearest_vertex_is_the_brute_force_one(n, m, spread, seed):
    """The grid search (with its k-d tree fallback) finds a vertex as near as the nearest of all."""
    from cam_workbench.generators.curves.approx import nearest_vertex

    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0, 2 * np.pi, n))
    poly = (10 + rng.uniform(-1, 1)) * np.exp(1j * t) * (1 + 0.2 * np.cos(3 * t))
    x = poly[rng.integers(0, n, m)] + spread * (rng.normal(size=m) + 1j * rng.normal(size=m))
    k = nearest_vertex(x, poly)
    brute = np.min(np.abs(x[:, None] - poly[None, :]), axis=1)
    np.testing.assert_array_equal(np.abs(x - poly[k]), brute)

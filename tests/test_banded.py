"""The cyclic tridiagonal solver (cyclic reduction in numpy, LAPACK's pivoting banded solve for a
system that is not diagonally dominant) against numpy's dense LU solve of the same matrix, built
here from the three bands and the two corners."""
import numpy as np
from hypothesis import given, settings, strategies as st

from cam_workbench.generators.curves.banded import solve_cyclic_tridiagonal, solve_tridiagonal


def cyclic_matrix(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    n = b.shape[0]
    m = np.zeros((n, n), dtype=np.result_type(a, b, c))
    i = np.arange(n)
    m[i, i] += b
    m[i, (i - 1) % n] += a
    m[i, (i + 1) % n] += c
    return m


@settings(max_examples=150, deadline=None)
@given(n=st.integers(3, 300), k=st.integers(1, 3), seed=st.integers(0, 2**32 - 1),
       complex_=st.booleans(), margin=st.floats(0.0, 2.0), one_d=st.booleans())
def test_cyclic_solve_matches_dense(n, k, seed, complex_, margin, one_d):
    rng = np.random.default_rng(seed)

    def draw(size):
        v = rng.normal(size=size)
        return v + 1j * rng.normal(size=size) if complex_ else v

    a, c = draw(n), draw(n)
    phase = np.exp(1j * rng.uniform(0, 2 * np.pi, n)) if complex_ else rng.choice([-1.0, 1.0], n)
    # diagonally dominant by `margin` (0: only just), the case cyclic reduction takes
    b = (np.abs(a) + np.abs(c) + margin + 1e-3) * phase
    r = draw((n,) if one_d else (n, k))
    x = solve_cyclic_tridiagonal(a, b, c, r)
    ref = np.linalg.solve(cyclic_matrix(a, b, c), r)
    assert x.shape == r.shape
    assert np.allclose(x, ref, rtol=1e-9, atol=1e-9 * np.abs(ref).max())


@settings(max_examples=60, deadline=None)
@given(n=st.integers(3, 120), seed=st.integers(0, 2**32 - 1))
def test_not_dominant_goes_to_the_pivoting_solve(n, seed):
    rng = np.random.default_rng(seed)
    a, b, c = rng.normal(size=n), 0.05 * rng.normal(size=n), rng.normal(size=n)
    m = cyclic_matrix(a, b, c)
    if np.linalg.cond(m) > 1e8:
        return
    r = rng.normal(size=n)
    x = solve_cyclic_tridiagonal(a, b, c, r)
    assert np.allclose(m @ x, r, atol=1e-8 * np.abs(r).max() * np.linalg.cond(m))


def test_tridiagonal_ignores_the_outer_corners():
    """a[0] and c[n−1] are outside the matrix: whatever they hold, the solution is the same."""
    rng = np.random.default_rng(7)
    n = 9
    a, c = rng.normal(size=n), rng.normal(size=n)
    b = np.abs(a) + np.abs(c) + 1
    r = rng.normal(size=(n, 2))
    x1 = solve_tridiagonal(a, b, c, r)
    a[0], c[-1] = 1e6, -1e6
    x2 = solve_tridiagonal(a, b, c, r)
    m = np.diag(b) + np.diag(a[1:], -1) + np.diag(c[:-1], 1)
    assert np.allclose(x1, np.linalg.solve(m, r)) and np.array_equal(x1, x2)

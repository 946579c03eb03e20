"""B-spline basis functions, vectorised over the parameters (Piegl & Tiller, *The NURBS Book*,
A2.1 and A2.3): the non-zero functions and their derivatives at many parameters, and the dense
collocation matrix a fit or a sensitivity needs."""
from __future__ import annotations

import numpy as np


def find_span(knots: np.ndarray, degree: int, u: np.ndarray) -> np.ndarray:
    """Knot span index i with t_i ≤ u < t_{i+1} (the last non-empty span at the right end)."""
    n = len(knots) - degree - 2
    return np.clip(np.searchsorted(knots, u, side="right") - 1, degree, n)


def basis_derivatives(knots: np.ndarray, degree: int, u: np.ndarray, nder: int
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Non-zero B-spline basis functions and their derivatives at many parameters.

    Piegl & Tiller, *The NURBS Book*, A2.3, vectorised over ``u``.

    Returns:
        span (N,): the knot span of each u; the non-zero functions are N_{span−p … span}.
        ders (N, nder + 1, p + 1): ders[:, d, j] = d^d/du^d N_{span−p+j, p}(u).
    """
    p = degree
    u = np.atleast_1d(np.asarray(u, dtype=float))
    m = u.shape[0]
    span = find_span(knots, p, u)
    ndu = np.zeros((m, p + 1, p + 1))
    ndu[:, 0, 0] = 1.0
    left = np.zeros((m, p + 1))
    right = np.zeros((m, p + 1))
    for j in range(1, p + 1):
        left[:, j] = u - knots[span + 1 - j]
        right[:, j] = knots[span + j] - u
        saved = np.zeros(m)
        for r in range(j):
            ndu[:, j, r] = right[:, r + 1] + left[:, j - r]
            temp = ndu[:, r, j - 1] / ndu[:, j, r]
            ndu[:, r, j] = saved + right[:, r + 1] * temp
            saved = left[:, j - r] * temp
        ndu[:, j, j] = saved
    nd = min(nder, p)
    ders = np.zeros((m, nder + 1, p + 1))
    ders[:, 0, :] = ndu[:, :, p]
    for r in range(p + 1):
        a = np.zeros((m, 2, p + 1))
        a[:, 0, 0] = 1.0
        s1, s2 = 0, 1
        for k in range(1, nd + 1):
            d = np.zeros(m)
            rk, pk = r - k, p - k
            if r >= k:
                a[:, s2, 0] = a[:, s1, 0] / ndu[:, pk + 1, rk]
                d = a[:, s2, 0] * ndu[:, rk, pk]
            j1 = 1 if rk >= -1 else -rk
            j2 = k - 1 if r - 1 <= pk else p - r
            for j in range(j1, j2 + 1):
                a[:, s2, j] = (a[:, s1, j] - a[:, s1, j - 1]) / ndu[:, pk + 1, rk + j]
                d = d + a[:, s2, j] * ndu[:, rk + j, pk]
            if r <= pk:
                a[:, s2, k] = -a[:, s1, k - 1] / ndu[:, pk + 1, r]
                d = d + a[:, s2, k] * ndu[:, r, pk]
            ders[:, k, r] = d
            s1, s2 = s2, s1
    fac = float(p)
    for k in range(1, nd + 1):
        ders[:, k, :] *= fac
        fac *= p - k
    return span, ders


def basis_matrix(knots: np.ndarray, degree: int, n_points: int, u: np.ndarray, der: int = 0
                 ) -> np.ndarray:
    """Dense (len(u), n_points) matrix of d^der/du^der N_i(u) — the sensitivity of a
    B-spline's value (or derivative) to each control coordinate (thesis Ch. 6)."""
    span, ders = basis_derivatives(knots, degree, u, der)
    out = np.zeros((span.shape[0], n_points))
    cols = span[:, None] - degree + np.arange(degree + 1)[None, :]
    np.put_along_axis(out, cols, ders[:, der, :], axis=1)
    return out


def interpolating_cubic(x: np.ndarray, y: np.ndarray, d0: np.ndarray, d1: np.ndarray
                        ) -> tuple[np.ndarray, np.ndarray]:
    """The clamped cubic spline through (x_i, y_i) with the first derivatives ``d0`` at x_0 and
    ``d1`` at x_n: (its knots [x0 ×4, x_1 … x_{n−1}, x_n ×4], its n + 3 coefficients).

    ``y`` is (n + 1, …) and ``d0``, ``d1`` are (…): many curves on the same abscissae at once (one
    collocation matrix, one solve).  The linear system is the interpolation conditions and the two
    end slopes (de Boor, *A Practical Guide to Splines*, ch. XII)."""
    x = np.asarray(x, dtype=float)
    n = x.size - 1
    knots = np.concatenate([np.full(3, x[0]), x, np.full(3, x[-1])])
    rows = np.vstack([basis_matrix(knots, 3, n + 3, x[:1], 1), basis_matrix(knots, 3, n + 3, x, 0),
                      basis_matrix(knots, 3, n + 3, x[-1:], 1)])
    y = np.asarray(y, dtype=float)
    rhs = np.concatenate([np.asarray(d0, dtype=float)[None], y, np.asarray(d1, dtype=float)[None]])
    coef = np.linalg.solve(rows, rhs.reshape(n + 3, -1)).reshape((n + 3,) + y.shape[1:])
    return knots, coef

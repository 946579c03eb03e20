"""O(n) solver for cyclic (periodic) tridiagonal systems, real or complex.

Row i reads  a[i]·x[i−1] + b[i]·x[i] + c[i]·x[i+1] = r[i]  with indices modulo n.
The two corner entries are removed by a rank-one Sherman–Morrison correction and
the remaining tridiagonal system (two right-hand sides) is solved by cyclic reduction
(Numerical Recipes §2.7, "cyclic"; Golub & Van Loan §4.3.11 for the reduction): ⌈log₂ n⌉
levels, each a few whole-array operations, in numpy alone.  Like the Thomas algorithm it does
not pivot, which is stable for diagonally dominant matrices — the PH spline's Jacobians and the
cubic spline's (1, 4, 1) rows are; a system that is not goes to LAPACK's pivoting banded solver.
"""
from __future__ import annotations

import numpy as np


def solve_cyclic_tridiagonal(a: np.ndarray, b: np.ndarray, c: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Solve the cyclic tridiagonal system; ``r`` may be (n,) or (n, k)."""
    n = b.shape[0]
    if n < 3:
        raise ValueError("cyclic tridiagonal systems need n ≥ 3")
    dtype = np.result_type(a, b, c, r)
    alpha = c[-1]  # bottom-left corner: row n−1, column 0
    beta = a[0]    # top-right corner:   row 0,   column n−1
    gamma = -b[0] if b[0] != 0 else -1.0
    bb = np.array(b, dtype=dtype)
    bb[0] -= gamma
    bb[-1] -= alpha * beta / gamma
    sub = np.zeros(n, dtype=dtype)
    sub[1:] = a[1:]
    sup = np.zeros(n, dtype=dtype)
    sup[:-1] = c[:-1]
    r2 = np.asarray(r, dtype=dtype)
    rhs_1d = r2.ndim == 1
    if rhs_1d:
        r2 = r2[:, None]
    u = np.zeros((n, 1), dtype=dtype)
    u[0, 0] = gamma
    u[-1, 0] = alpha
    sol = solve_tridiagonal(sub, bb, sup, np.hstack([r2, u]))
    x, z = sol[:, :-1], sol[:, -1]
    fact_z = z[0] + beta * z[-1] / gamma
    fact_x = x[0] + beta * x[-1] / gamma
    x = x - np.outer(z, fact_x / (1.0 + fact_z))
    return x[:, 0] if rhs_1d else x


def solve_tridiagonal(a: np.ndarray, b: np.ndarray, c: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Solve a[i]·x[i−1] + b[i]·x[i] + c[i]·x[i+1] = r[i] (a[0] and c[n−1] ignored); ``r`` is (n, k).

    Cyclic reduction when every row is diagonally dominant (|b| ≥ |a| + |c|), else LAPACK's
    banded solver with partial pivoting."""
    a = a.copy()
    c = c.copy()
    a[0] = 0
    c[-1] = 0
    if np.all(np.abs(b) >= np.abs(a) + np.abs(c)):
        return _cyclic_reduction(a, b, c, r)
    from scipy.linalg import solve_banded  # deferred: scipy.linalg, a system that is not diagonally dominant
    ab = np.zeros((3, b.shape[0]), dtype=np.result_type(a, b, c, r))
    ab[0, 1:] = c[:-1]
    ab[1] = b
    ab[2, :-1] = a[1:]
    return solve_banded((1, 1), ab, r, check_finite=False)


def _cyclic_reduction(a: np.ndarray, b: np.ndarray, c: np.ndarray, r: np.ndarray) -> np.ndarray:
    # Each level eliminates the even-indexed unknowns from the odd rows (with their neighbours,
    # rows i−1 and i+1), solves the half-size system of the odd unknowns, then recovers the even
    # ones from their own rows.  An odd n is padded with the row x = 0.
    n = b.shape[0]
    if n == 1:
        return r / b[:, None]
    if n % 2:
        a, b, c = (np.append(v, fill) for v, fill in ((a, 0), (b, 1), (c, 0)))
        r = np.vstack([r, np.zeros((1, r.shape[1]), dtype=r.dtype)])
    lo, mid, hi = slice(0, None, 2), slice(1, None, 2), slice(2, None, 2)
    alpha = a[mid] / b[lo]                                       # row i−1 (even, always present)
    gamma = np.zeros_like(alpha)
    gamma[:-1] = c[mid][:-1] / b[hi]                             # row i+1 (even; none after the last)
    a_hi = np.zeros_like(alpha)
    a_hi[:-1] = a[hi]
    c_hi = np.zeros_like(alpha)
    c_hi[:-1] = c[hi]
    r_hi = np.zeros((alpha.shape[0], r.shape[1]), dtype=r.dtype)
    r_hi[:-1] = r[hi]
    x_odd = _cyclic_reduction(-alpha * a[lo], b[mid] - alpha * c[lo] - gamma * a_hi, -gamma * c_hi,
                              r[mid] - alpha[:, None] * r[lo] - gamma[:, None] * r_hi)
    x = np.empty_like(r)
    x[mid] = x_odd
    left = np.zeros_like(x[lo])
    left[1:] = x_odd[:left.shape[0] - 1]
    right = np.zeros_like(x[lo])
    right[:x_odd.shape[0]] = x_odd
    x[lo] = (r[lo] - a[lo][:, None] * left - c[lo][:, None] * right) / b[lo][:, None]
    return x[:n]

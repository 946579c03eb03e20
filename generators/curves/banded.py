"""O(n) solver for cyclic (periodic) tridiagonal systems, real or complex.

Row i reads  a[i]·x[i−1] + b[i]·x[i] + c[i]·x[i+1] = r[i]  with indices modulo n.
The two corner entries are removed by a rank-one Sherman–Morrison correction and
the remaining tridiagonal system (two right-hand sides) goes to LAPACK's banded
solver (Numerical Recipes §2.7, "cyclic").
"""
from __future__ import annotations

import numpy as np
from scipy.linalg import solve_banded


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
    ab = np.zeros((3, n), dtype=dtype)
    ab[0, 1:] = c[:-1]
    ab[1] = bb
    ab[2, :-1] = a[1:]
    r2 = np.asarray(r, dtype=dtype)
    rhs_1d = r2.ndim == 1
    if rhs_1d:
        r2 = r2[:, None]
    u = np.zeros((n, 1), dtype=dtype)
    u[0, 0] = gamma
    u[-1, 0] = alpha
    sol = solve_banded((1, 1), ab, np.hstack([r2, u]), overwrite_ab=True, overwrite_b=True,
                       check_finite=False)
    x, z = sol[:, :-1], sol[:, -1]
    fact_z = z[0] + beta * z[-1] / gamma
    fact_x = x[0] + beta * x[-1] / gamma
    x = x - np.outer(z, fact_x / (1.0 + fact_z))
    return x[:, 0] if rhs_1d else x

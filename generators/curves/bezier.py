"""Bernstein-form polynomials, vectorised over many segments.

Coefficients are arrays of shape (..., n+1) (real or complex); the last axis is the
Bernstein index.  These are the exact operations used to build PH quintics and their
rational offsets: evaluation, derivative, product, degree elevation.
"""
from __future__ import annotations

from math import comb

import numpy as np


def bernstein_basis(n: int, t: np.ndarray) -> np.ndarray:
    """B_{k,n}(t) for k = 0..n; shape t.shape + (n+1,)."""
    t = np.asarray(t, dtype=float)[..., None]
    k = np.arange(n + 1)
    binom = np.array([comb(n, i) for i in range(n + 1)], dtype=float)
    return binom * t**k * (1.0 - t) ** (n - k)


def evaluate(coeffs: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Evaluate Bernstein polynomials; ``coeffs`` (S, n+1), ``t`` (S,) or (S, K) per segment."""
    n = coeffs.shape[-1] - 1
    t = np.asarray(t, dtype=float)
    basis = bernstein_basis(n, t)
    if t.ndim == coeffs.ndim - 1:
        return np.einsum("...k,...k->...", basis, coeffs)
    return np.einsum("sqk,sk->sq", basis, coeffs)


def evaluate_at(coeffs: np.ndarray, seg: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Evaluate segment ``seg[j]`` of ``coeffs`` at ``t[j]`` for each j (Horner-free de Casteljau-free
    direct Bernstein sum; exact to rounding for the low degrees used here)."""
    n = coeffs.shape[-1] - 1
    basis = bernstein_basis(n, t)
    return np.einsum("jk,jk->j", basis, coeffs[seg])


def derivative(coeffs: np.ndarray) -> np.ndarray:
    """Coefficients of the derivative (degree n−1)."""
    n = coeffs.shape[-1] - 1
    return n * np.diff(coeffs, axis=-1)


def elevate(coeffs: np.ndarray, to_degree: int) -> np.ndarray:
    """Degree elevation from n to ``to_degree`` (exact)."""
    n = coeffs.shape[-1] - 1
    m = to_degree
    if m == n:
        return coeffs.copy()
    if m < n:
        raise ValueError("cannot lower the degree")
    # c'_k = Σ_j C(n,j) C(m−n,k−j) / C(m,k) c_j
    mat = np.zeros((n + 1, m + 1))
    for k in range(m + 1):
        for j in range(max(0, k - (m - n)), min(n, k) + 1):
            mat[j, k] = comb(n, j) * comb(m - n, k - j) / comb(m, k)
    return coeffs @ mat


def product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Bernstein coefficients of the product of two polynomials (degrees n and m → n+m)."""
    n = a.shape[-1] - 1
    m = b.shape[-1] - 1
    dtype = np.result_type(a, b)
    out = np.zeros(np.broadcast_shapes(a.shape[:-1], b.shape[:-1]) + (n + m + 1,), dtype=dtype)
    for j in range(n + 1):
        for k in range(m + 1):
            out[..., j + k] += comb(n, j) * comb(m, k) / comb(n + m, j + k) * a[..., j] * b[..., k]
    return out


def integrate(coeffs: np.ndarray, start: np.ndarray | float = 0.0) -> np.ndarray:
    """Antiderivative (degree n+1) with value ``start`` at t = 0."""
    n = coeffs.shape[-1] - 1
    c = np.cumsum(coeffs, axis=-1) / (n + 1)
    start = np.asarray(start)[..., None]
    zero = np.zeros(coeffs.shape[:-1] + (1,), dtype=np.result_type(coeffs, float))
    return np.concatenate([zero, c], axis=-1) + start


def bernstein_from_power(power: np.ndarray) -> np.ndarray:
    """Bernstein coefficients (..., n+1) of polynomials given by monomial coefficients
    (..., n+1), lowest power first: b_j = Σ_{k≤j} C(j,k)/C(n,k)·a_k."""
    n = power.shape[-1] - 1
    mat = np.zeros((n + 1, n + 1))
    for j in range(n + 1):
        for k in range(j + 1):
            mat[k, j] = comb(j, k) / comb(n, k)
    return power @ mat


class BezierChain:
    """A closed chain of M polynomial Bézier segments r_k(ξ), ξ ∈ [0, 1] (complex control
    points ``ctrl`` (M, n+1)), queried by (segment, ξ) pairs as :class:`PHSpline` is —
    the form in which the pitch-curve consumers (Eq. 13 solves, the interpolator, curvature
    samples) read any polynomial pitch curve."""

    iterations = None
    residual = None
    closing_sign = None

    def __init__(self, ctrl: np.ndarray):
        self.ctrl = np.asarray(ctrl, dtype=complex)
        self._d1 = derivative(self.ctrl)
        self._d2 = derivative(self._d1)

    @property
    def M(self) -> int:
        return int(self.ctrl.shape[0])

    @property
    def degree(self) -> int:
        return int(self.ctrl.shape[1] - 1)

    def point(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        return evaluate_at(self.ctrl, np.asarray(seg), np.asarray(xi, dtype=float))

    def first_derivative(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        """dr/dξ."""
        return evaluate_at(self._d1, np.asarray(seg), np.asarray(xi, dtype=float))

    def second_derivative(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        return evaluate_at(self._d2, np.asarray(seg), np.asarray(xi, dtype=float))

    def curvature(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        """Signed curvature (positive turning left)."""
        d1 = self.first_derivative(seg, xi)
        d2 = self.second_derivative(seg, xi)
        return (np.conj(d1) * d2).imag / np.abs(d1) ** 3

    @property
    def arc_length(self) -> float:
        """Arc length by 16-point Gauss–Legendre quadrature on every segment."""
        xg, wg = np.polynomial.legendre.leggauss(16)
        xi = np.tile(0.5 * (xg + 1.0), self.M)
        seg = np.repeat(np.arange(self.M), xg.shape[0])
        return float(np.sum(np.abs(self.first_derivative(seg, xi)) * np.tile(0.5 * wg, self.M)))

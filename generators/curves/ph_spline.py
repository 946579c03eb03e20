"""Closed C² Pythagorean-hodograph (PH) quintic spline through M junction points.

Segment k (k = 0..M−1) runs from q_k to q_{k+1} (q_M = q_0) over ξ ∈ [0, 1] with
hodograph r'_k(ξ) = w_k(ξ)², w_k quadratic in Bernstein form with coefficients
(paper Eq. 2, 4)

    w₀ = ½(z_{k−1} + z_k),  w₁ = z_k,  w₂ = ½(z_k + z_{k+1}),

and the closing identifications z_{−1} = ς·z_{M−1}, z_M = ς·z_0 (ς = ±1, the
closing sign: ς = −1 for a curve that turns once, as every cam pitch curve does).
The interpolation conditions ∫₀¹ r'_k = Δq_k give the cyclic quadratic system
(paper Eq. 3, 5)

    f_k = 3z_{k−1}² + 27z_k² + 3z_{k+1}² + z_{k−1}z_{k+1} + 13z_{k−1}z_k + 13z_k z_{k+1} − 60Δq_k = 0,

solved by complex Newton iteration.  f is holomorphic in z, so the Jacobian is a
complex cyclic tridiagonal matrix and each Newton step is one O(M) banded solve
(:mod:`cam_workbench.generators.curves.banded`).  The starting approximation follows Farouki, Kuspa,
Manni & Sestini (Numer. Algor. 27, 2001): z_k ≈ √(r'(½)) of the periodic C² cubic
spline through the same points, with the square-root branches made continuous.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import bezier
from .banded import solve_cyclic_tridiagonal
from ..errors import SolveError


@dataclass(frozen=True)
class PHSpline:
    """A closed C² PH quintic spline: M segments, each an exact quintic in Bernstein form.

    Attributes:
        junctions: (M,) complex junction points q_0..q_{M−1}.
        z: (M,) complex Newton unknowns.
        closing_sign: ς (±1).
        w: (M, 3) complex Bernstein coefficients of w_k(ξ).
        ctrl: (M, 6) complex Bézier control points of r_k(ξ).
        iterations: Newton iterations used.
        residual: max |f_k| / (60·max|Δq|) at the solution.
    """

    junctions: np.ndarray
    z: np.ndarray
    closing_sign: int
    w: np.ndarray
    ctrl: np.ndarray
    iterations: int
    residual: float

    @property
    def M(self) -> int:
        return int(self.z.shape[0])

    @property
    def hodograph(self) -> np.ndarray:
        """(M, 5) Bernstein coefficients of r'_k = w_k² (degree 4)."""
        return hodograph_coeffs(self.w)

    @property
    def sigma(self) -> np.ndarray:
        """(M, 5) Bernstein coefficients of the parametric speed σ_k = |w_k|² (degree 4)."""
        return sigma_coeffs(self.w)

    # ---- evaluation at (segment, ξ) pairs -----------------------------------------
    def point(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        """r_{seg}(ξ) as complex numbers."""
        return bezier.evaluate_at(self.ctrl, np.asarray(seg), np.asarray(xi, dtype=float))

    def first_derivative(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        """r'(ξ) = w(ξ)²."""
        w = bezier.evaluate_at(self.w, np.asarray(seg), np.asarray(xi, dtype=float))
        return w * w

    def second_derivative(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        """r''(ξ) = 2 w w'."""
        seg = np.asarray(seg)
        xi = np.asarray(xi, dtype=float)
        w = bezier.evaluate_at(self.w, seg, xi)
        dw = bezier.evaluate_at(bezier.derivative(self.w), seg, xi)
        return 2.0 * w * dw

    def speed(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        """σ(ξ) = |r'(ξ)| = |w(ξ)|² (exact, polynomial)."""
        w = bezier.evaluate_at(self.w, np.asarray(seg), np.asarray(xi, dtype=float))
        return (w * w.conjugate()).real

    def curvature(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        """Signed curvature κ = 2 Im(w̄ w')/σ² (positive turning left)."""
        seg = np.asarray(seg)
        xi = np.asarray(xi, dtype=float)
        w = bezier.evaluate_at(self.w, seg, xi)
        dw = bezier.evaluate_at(bezier.derivative(self.w), seg, xi)
        sig = (w * w.conjugate()).real
        return 2.0 * (w.conjugate() * dw).imag / sig**2

    def segment_arc_lengths(self) -> np.ndarray:
        """Exact arc length of each segment: ∫₀¹ σ dξ = Σσ_j / 5."""
        return self.sigma.sum(axis=1) / 5.0

    @property
    def arc_length(self) -> float:
        """Exact total arc length."""
        return float(self.segment_arc_lengths().sum())

    def sample(self, per_segment: int = 32) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Dense samples (seg, ξ, point); ξ ∈ [0, 1) per segment, segments in order."""
        xi = np.tile(np.arange(per_segment) / per_segment, self.M)
        seg = np.repeat(np.arange(self.M), per_segment)
        return seg, xi, self.point(seg, xi)


def hodograph_coeffs(w: np.ndarray) -> np.ndarray:
    """Bernstein coefficients (degree 4) of w² for quadratic w with coefficients (w0, w1, w2)."""
    w0, w1, w2 = w[..., 0], w[..., 1], w[..., 2]
    return np.stack([w0 * w0, w0 * w1, (2 * w1 * w1 + w0 * w2) / 3, w1 * w2, w2 * w2], axis=-1)


def sigma_coeffs(w: np.ndarray) -> np.ndarray:
    """Bernstein coefficients (degree 4) of |w|² (paper Eq. 1: σ = u² + v²)."""
    w0, w1, w2 = w[..., 0], w[..., 1], w[..., 2]
    c = np.conjugate
    return np.stack([
        (w0 * c(w0)).real, (w0 * c(w1)).real, (2 * (w1 * c(w1)).real + (w0 * c(w2)).real) / 3,
        (w1 * c(w2)).real, (w2 * c(w2)).real,
    ], axis=-1)


# ---- the solver ------------------------------------------------------------------------
def _neighbours(z: np.ndarray, sign: int) -> tuple[np.ndarray, np.ndarray]:
    zp = np.roll(z, 1)
    zn = np.roll(z, -1)
    zp[0] *= sign
    zn[-1] *= sign
    return zp, zn


def residual(z: np.ndarray, dq: np.ndarray, sign: int) -> np.ndarray:
    """f_k of paper Eq. 3/5 for all k."""
    a, c = _neighbours(z, sign)
    b = z
    return 3 * a * a + 27 * b * b + 3 * c * c + a * c + 13 * a * b + 13 * b * c - 60 * dq


def jacobian_bands(z: np.ndarray, sign: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The three cyclic bands of ∂f/∂z: (sub, diag, super), corner signs included."""
    a, c = _neighbours(z, sign)
    b = z
    sub = 6 * a + c + 13 * b
    diag = 54 * b + 13 * a + 13 * c
    sup = 6 * c + a + 13 * b
    sub[0] *= sign
    sup[-1] *= sign
    return sub, diag, sup


def _dense_jacobian(z: np.ndarray, sign: int) -> np.ndarray:
    sub, diag, sup = jacobian_bands(z, sign)
    m = z.shape[0]
    jac = np.zeros((m, m), dtype=complex)
    idx = np.arange(m)
    jac[idx, idx] = diag
    jac[idx, (idx - 1) % m] += sub
    jac[idx, (idx + 1) % m] += sup
    return jac


def starting_approximation(q: np.ndarray) -> tuple[np.ndarray, int]:
    """z⁰ and the closing sign from the periodic C² cubic spline (Farouki et al. 2001)."""
    m = q.shape[0]
    ones = np.ones(m)
    rhs = 3.0 * (np.roll(q, -1) - np.roll(q, 1))
    d = solve_cyclic_tridiagonal(ones, 4 * ones, ones, rhs)
    dq = np.roll(q, -1) - q
    mid = 1.5 * dq - 0.25 * (d + np.roll(d, -1))  # cubic Hermite r'(½)
    root = np.sqrt(mid.astype(complex))
    # Make the square-root branch continuous: flip where consecutive roots disagree.
    flips = (root[1:] * np.conjugate(root[:-1])).real < 0
    signs = np.concatenate([[1.0], np.cumprod(np.where(flips, -1.0, 1.0))])
    z0 = root * signs
    closing = 1 if (z0[-1] * np.conjugate(z0[0])).real > 0 else -1
    return z0, closing


def solve_closed_ph_spline(
    q: np.ndarray,
    *,
    max_iter: int = 60,
    tol: float = 1e-13,
    method: str = "banded",
    z0: np.ndarray | None = None,
    closing_sign: int | None = None,
) -> PHSpline:
    """Solve for the closed C² PH quintic spline through junction points ``q`` (complex, (M,)).

    Args:
        q: junction points q_0..q_{M−1}; the spline returns to q_0.
        max_iter: Newton iteration limit.
        tol: convergence when the Newton step is below ``tol``·max|z|.
        method: "banded" (O(M) per step) or "dense" (O(M³) reference).
        z0, closing_sign: optional starting point (default: Farouki et al.'s).

    Raises:
        SolveError: Newton did not converge (the message gives the residual).
    """
    q = np.asarray(q, dtype=complex)
    m = q.shape[0]
    if m < 3:
        raise SolveError(f"a closed PH spline needs at least 3 junction points, got {m}")
    dq = np.roll(q, -1) - q
    scale = 60.0 * float(np.max(np.abs(dq)))
    if not scale > 0:
        raise SolveError("junction points are all equal")
    if z0 is None or closing_sign is None:
        z_start, sign = starting_approximation(q)
    else:
        z_start, sign = np.asarray(z0, dtype=complex), int(closing_sign)
    z = z_start.copy()
    f = residual(z, dq, sign)
    fnorm = float(np.max(np.abs(f)))
    it = 0
    converged = False
    for it in range(1, max_iter + 1):
        if method == "banded":
            sub, diag, sup = jacobian_bands(z, sign)
            step = solve_cyclic_tridiagonal(sub, diag, sup, -f)
        elif method == "dense":
            step = np.linalg.solve(_dense_jacobian(z, sign), -f)
        else:
            raise ValueError(f"unknown method {method!r}")
        # Damped Newton: halve the step while the residual grows (rarely needed).
        lam = 1.0
        for _ in range(30):
            z_new = z + lam * step
            f_new = residual(z_new, dq, sign)
            fn_new = float(np.max(np.abs(f_new)))
            if fn_new <= fnorm or fn_new <= 1e-15 * scale:
                break
            lam *= 0.5
        z, f, fnorm = z_new, f_new, fn_new
        if float(np.max(np.abs(lam * step))) <= tol * float(np.max(np.abs(z))):
            converged = True
            break
    rel = fnorm / scale
    if not converged or not np.isfinite(rel) or rel > 1e-10:
        raise SolveError(
            f"PH spline Newton iteration did not converge in {it} steps "
            f"(relative residual {rel:.3g}); the junction points may be too irregular "
            f"(try more pitch.segments)"
        )
    return build_spline(q, z, sign, iterations=it, residual=rel)


def build_spline(q: np.ndarray, z: np.ndarray, sign: int, *, iterations: int = 0,
                 residual: float = 0.0) -> PHSpline:
    """Assemble the segment coefficients from solved z (paper Eq. 2, 4, 6)."""
    zp, zn = _neighbours(z, sign)
    w = np.stack([(zp + z) / 2, z, (z + zn) / 2], axis=-1)
    ctrl = bezier.integrate(hodograph_coeffs(w), start=q)  # r_k(ξ) = q_k + ∫ w² (Eq. 6)
    return PHSpline(junctions=q, z=z, closing_sign=sign, w=w, ctrl=ctrl,
                    iterations=iterations, residual=residual)

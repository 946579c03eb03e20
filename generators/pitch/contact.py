"""Where the follower line meets the PH pitch curve: paper Eq. 13–14, vectorised.

At cam angle θ the point r(ξ) of the pitch curve lies under the follower when,
after turning the cam by θ,

    Re(e^{iδθ}·r(ξ)) = e          (δ = +1 ccw, −1 cw; paper Eq. 13 for δ = +1)

and the follower point is then (e, Y) with Y = Im(e^{iδθ}·r(ξ)), i.e. the actual
displacement is s_actual = Y − s₀.  Newton's method (paper Eq. 14) is applied to
every sample at once; the segment is looked up by ``searchsorted`` on the junction
angles, and samples whose root leaves [0, 1] move to the neighbouring segment.
"""
from __future__ import annotations

from dataclasses import dataclass
from math import comb

import numpy as np

from ..errors import SolveError
from ..curves.bezier import BezierChain
from ..curves.ph_spline import PHSpline

TWO_PI = 2.0 * np.pi


def power_coeffs(ctrl: np.ndarray) -> np.ndarray:
    """Monomial coefficients c_0..c_n (lowest first) of Bernstein segments (S, n+1)."""
    n = ctrl.shape[-1] - 1
    mat = np.zeros((n + 1, n + 1))
    for j in range(n + 1):          # Bernstein index
        for k in range(j, n + 1):   # power
            mat[j, k] = comb(n, k) * comb(k, j) * (-1) ** (k - j)
    return ctrl @ mat


def horner(coeffs: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Evaluate rows of monomial coefficients (N, n+1) at x (N,)."""
    out = coeffs[:, -1].copy()
    for k in range(coeffs.shape[1] - 2, -1, -1):
        out = out * x + coeffs[:, k]
    return out


@dataclass(frozen=True)
class Contact:
    """Solution of Eq. 13 at each sample: segment index, parameter ξ, the point r(ξ)
    in the cam frame, the line coordinate Y (a line solve: s_actual = Y − s₀ for a translating
    follower) and the follower's lift s_actual [spec lift units] where the solver knows it."""

    seg: np.ndarray
    xi: np.ndarray
    point: np.ndarray
    Y: np.ndarray | None
    iterations: int
    lift: np.ndarray | None = None


class FollowerLineSolver:
    """Precomputed monomial forms of a chain of Bézier segments (the PH spline, or a
    B-spline pitch curve in Bézier form) for fast vectorised Eq. 13 solves.

    Args:
        spline: the closed pitch curve as Bézier segments: ``ctrl`` (M, n+1) complex and ``M``.
        junction_angles: (M,) cam angles [rad] of junctions q_0..q_{M−1}, increasing from 0.
        offset: follower offset e.
        sense: +1 for a ccw cam, −1 for cw.
    """

    def __init__(self, spline: "PHSpline | BezierChain", junction_angles: np.ndarray, offset: float, sense: int,
                 lift_origin: float | None = None):
        self.spline = spline
        self.lift_origin = lift_origin   # s₀: the lift is Y − s₀ (None: a machine line, no lift)
        ang = np.asarray(junction_angles, dtype=float)
        self.angles = np.append(ang, ang[0] + TWO_PI)
        self.offset = float(offset)
        self.sense = int(sense)
        self._pc = power_coeffs(spline.ctrl)                  # r(ξ), degree n (5 for PH)
        self._deg = self._pc.shape[1] - 1
        self._dpc = self._pc[:, 1:] * np.arange(1, self._deg + 1)  # r'(ξ), degree n − 1
        self._size = np.max(np.abs(spline.ctrl), axis=1)     # bound of |r(ξ)| on each segment

    def wrap(self, theta: np.ndarray) -> np.ndarray:
        """θ taken modulo 2π into [θ_0, θ_0 + 2π) (θ_0 ≈ 0: the angle the first junction is touched)."""
        a0 = self.angles[0]
        t = np.mod(np.asarray(theta, dtype=float) - a0, TWO_PI) + a0
        return np.where(t >= a0 + TWO_PI, t - TWO_PI, t)

    def segment_of(self, theta: np.ndarray) -> np.ndarray:
        """Segment whose junction angles bracket θ (θ taken modulo 2π)."""
        return self._segment_of_wrapped(self.wrap(theta))

    def _segment_of_wrapped(self, t: np.ndarray) -> np.ndarray:
        return np.clip(np.searchsorted(self.angles, t, side="right") - 1, 0, self.spline.M - 1)

    def solve(self, theta: np.ndarray, xi0: np.ndarray | None = None, seg: np.ndarray | None = None,
              tol: float = 1e-14, max_iter: int = 30) -> Contact:
        """Solve Eq. 13 for every θ [rad]; optional starting ξ and segment per sample
        (the previous command's root, paper's ξ⁽⁰⁾_{i,k} = ξ_{i,k−1})."""
        theta = np.asarray(theta, dtype=float)
        t = self.wrap(theta)
        if seg is None:
            seg = self._segment_of_wrapped(t)
        seg = np.asarray(seg).copy()
        if xi0 is None:
            a0, a1 = self.angles[seg], self.angles[seg + 1]
            xi = (t - a0) / (a1 - a0)
        else:
            xi = np.asarray(xi0, dtype=float).copy()
        rot = np.exp(1j * self.sense * t)
        total_iter = 0
        for _attempt in range(4):
            xi, it = self._newton(seg, xi, rot, tol, max_iter)
            total_iter = max(total_iter, it)
            low = xi < -1e-9
            high = xi > 1 + 1e-9
            if not (low.any() or high.any()):
                break
            m = self.spline.M
            seg = np.where(low, (seg - 1) % m, np.where(high, (seg + 1) % m, seg))
            xi = np.where(low, xi + 1.0, np.where(high, xi - 1.0, xi))
        else:
            bad = int(np.argmax((xi < -1e-9) | (xi > 1 + 1e-9)))
            raise SolveError(
                f"the follower line does not meet the pitch curve near cam angle "
                f"{np.rad2deg(t[bad]):.4f}° (root not bracketed in any segment)")
        xi = np.clip(xi, 0.0, 1.0)
        pts = horner(self._pc[seg], xi)
        y = (rot * pts).imag
        lift = None if self.lift_origin is None else y - self.lift_origin
        return Contact(seg=seg, xi=xi, point=pts, Y=y, iterations=total_iter, lift=lift)

    def residual_ends(self, theta: np.ndarray, seg: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(g at ξ = 0, g at ξ = 1, the rounding scale of g) of segment ``seg`` at θ: Eq. 13's
        residual must change sign over a segment whose ends bracket the root."""
        rot = np.exp(1j * self.sense * np.asarray(theta, dtype=float))
        c = self.spline.ctrl[seg]
        g0 = (rot * c[:, 0]).real - self.offset
        g1 = (rot * c[:, -1]).real - self.offset
        return g0, g1, 1e-12 * (np.abs(c[:, 0]) + np.abs(c[:, -1]) + abs(self.offset))

    def _newton(self, seg: np.ndarray, xi: np.ndarray, rot: np.ndarray, tol: float, max_iter: int
                ) -> tuple[np.ndarray, int]:
        # Turning the segment by θ makes Eq. 13 a real polynomial (a quintic for PH) in ξ: its coefficients
        # a_j = Re(e^{iδθ} c_j) are formed once, then each Newton step (Eq. 14) is two
        # real Horner evaluations, rows contiguous (6, N).
        a = (rot * self._pc[seg].T).real
        da = a[1:] * np.arange(1, self._deg + 1)[:, None]
        e = self.offset
        floor = 16 * np.finfo(float).eps * (self._size[seg] + abs(e))
        active = np.ones(xi.shape, dtype=bool)
        it = 0
        for it in range(1, max_iter + 1):
            g = _horner_rows(a, xi) - e                 # paper Eq. 13 residual
            dg = _horner_rows(da, xi)                   # paper Eq. 14 denominator
            with np.errstate(divide="ignore", invalid="ignore"):
                step = np.where(active, g / dg, 0.0)
            if not np.all(np.isfinite(step)):
                bad = int(np.argmax(~np.isfinite(step)))
                raise SolveError(f"Eq. 13 Newton step is singular in PH segment {int(seg[bad])}")
            step = np.clip(step, -0.5, 0.5)
            xi = xi - step
            # converged: step below tol, or residual at the rounding floor of |r|
            active = (np.abs(step) > tol) & (np.abs(g) > floor)
            if not active.any():
                break
        else:
            bad = int(np.argmax(active))
            raise SolveError(f"Eq. 13 Newton iteration did not converge in PH segment {int(seg[bad])}")
        return xi, it


def _horner_rows(coeffs: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Evaluate polynomials stored as rows of coefficients (n+1, N), lowest first, at x (N,)."""
    out = coeffs[-1].copy()
    for k in range(coeffs.shape[0] - 2, -1, -1):
        out *= x
        out += coeffs[k]
    return out


class ContactSolver(FollowerLineSolver):
    """Eq. 13 generalised to any follower kind (:class:`cam_workbench.generators.followers.base.Follower`): at
    cam angle θ the chain turned into the fixed frame, q(ξ) = e^{iδθ}·r(ξ), touches the follower
    where the kind's residual g(q, q′, q″) = 0; Newton's method on ξ for every sample at once,
    the segment found by ``searchsorted`` on the angles at which its ends are touched, moving to
    the neighbouring segment when the root leaves [0, 1] (as :class:`FollowerLineSolver`)."""

    def __init__(self, spline: "PHSpline | BezierChain", junction_angles: np.ndarray, follower):
        super().__init__(spline, junction_angles, 0.0, follower.sense)
        self.follower = follower
        self._d2pc = self._dpc[:, 1:] * np.arange(1, self._deg)          # r″(ξ)

    def _eval(self, seg: np.ndarray, xi: np.ndarray, rot: np.ndarray):
        q = rot * horner(self._pc[seg], xi)
        dq = rot * horner(self._dpc[seg], xi)
        if self.follower.contact_order < 2 or not self._d2pc.shape[1]:
            return q, dq, None                     # the kind's residual reads q and q′ only
        return q, dq, rot * horner(self._d2pc[seg], xi)

    def _newton(self, seg, xi, rot, tol, max_iter):
        fol = self.follower
        # residuals are lengths (or lengths × ξ-derivatives): their rounding floor
        floor = 256 * np.finfo(float).eps * (self._deg * self._size[seg] + abs(fol.prime_radius))
        # the segments' polynomials turned by θ once, as contiguous rows (n+1, N)
        c0 = (rot * self._pc[seg].T).copy()
        c1 = (rot * self._dpc[seg].T).copy()
        c2 = (rot * self._d2pc[seg].T).copy() if fol.contact_order >= 2 and self._d2pc.shape[1] else None
        active = np.ones(xi.shape, dtype=bool)
        it = 0
        for it in range(1, max_iter + 1):
            q, dq = _horner_rows(c0, xi), _horner_rows(c1, xi)
            d2q = _horner_rows(c2, xi) if c2 is not None else None
            g, dg, _ = fol.contact_residual(q, dq, d2q)
            with np.errstate(divide="ignore", invalid="ignore"):
                step = np.where(active, g / dg, 0.0)
            if not np.all(np.isfinite(step)):
                bad = int(np.argmax(~np.isfinite(step)))
                raise SolveError(f"the follower touches the built curve tangentially near cam angle "
                                 f"{self._angle_deg(rot[bad]):.3f}° (segment {int(seg[bad])}): no simple contact there")
            step = np.clip(step, -0.5, 0.5)
            xi = xi - step
            active = (np.abs(step) > tol) & (np.abs(g) > floor)
            if not active.any():
                break
        else:
            bad = int(np.argmax(active))
            raise SolveError(f"no single contact between the follower and the built curve near cam angle "
                             f"{self._angle_deg(rot[bad]):.3f}° (segment {int(seg[bad])}, Newton did not converge)")
        return xi, it

    def _angle_deg(self, rot: complex) -> float:
        return float(np.rad2deg(np.angle(rot) * self.sense) % 360.0)

    def solve(self, theta, xi0=None, seg=None, tol=1e-14, max_iter=40):
        c = super().solve(theta, xi0, seg, tol, max_iter)
        rot = np.exp(1j * self.sense * self.wrap(theta))
        q, dq, _ = self._eval(c.seg, c.xi, rot)
        return Contact(seg=c.seg, xi=c.xi, point=c.point, Y=None, iterations=c.iterations,
                       lift=self.follower.lift_at(q, dq))

    def residual_ends(self, theta, seg):
        rot = np.exp(1j * self.sense * np.asarray(theta, dtype=float))
        g = []
        for x in (0.0, 1.0):
            q, dq, d2q = self._eval(seg, np.full(np.shape(seg), x), rot)
            g.append(self.follower.contact_residual(q, dq, d2q)[0])
        c = self.spline.ctrl[seg]
        return g[0], g[1], 1e-10 * (np.abs(c[:, 0]) + np.abs(c[:, -1]))

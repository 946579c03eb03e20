"""The smooth part of the optimisation problem: every design check as normalised constraints
g ≤ 0 at nodes, and the smooth objectives, each with its exact gradient (design sensitivity
analysis, thesis Ch. 6, derived afresh — the thesis' printed formulas have typos).

Sampling.  Each B-spline rise/return is sampled at fixed parameters u (the thesis' choice, §5.3);
then every checked quantity is an explicit function of the control points, and its sensitivity is
the chain

    control coordinates → θ^(d)(u) = Σ P_ix N_i^(d)(u), y^(d)(u) = Σ P_iy N_i^(d)(u)
      → s, s′ = L y′_u/θ′_u, s″ = L (θ′ y″ − y′ θ″)/θ′³            (thesis Eq. 2.37–2.38)
      → φ, ρ (as κ = 1/ρ), F, S                                     (Eq. 3.4–3.7)
      → g                                                           (Eq. 5.5–5.13)

with ∂/∂P of N^(d)(u) = the basis matrices.  Other laws are sampled at fixed θ, dwells at one
point.  :meth:`SmoothModel.constraints` evaluates at fixed nodes (the tests' complex-step
reference); the solver sees :meth:`SmoothModel.window_max`: the largest value of every check in
each of ``optimise.windows`` equal parameter windows, refined between the samples, so that the
constraints are the dense maxima and not values at nodes.

Constraints (normalised as :func:`cam_workbench.generators.checks.design.constraint_arrays`):

=================  ====================================================
pressure_angle     (φ/φ_max)² − 1                       (Eq. 5.5)
curvature          f·r_f·κ − 1, κ = 1/ρ (smooth through inflections)   (Eq. 5.7)
convexity          −κ·R_b (``checks.convex``: Eq. 5.7 with signed ρ)
separation         (F_min − F)/P_L                      (Eq. 5.10)
contact_stress     S²/S_d² − 1                          (Eq. 5.13)
=================  ====================================================

S² = F (1/r_f + 1/(ρ − r_f))/(π t Δ) = F / (π t Δ r_f (1 − r_f κ)); for r_f κ above 0.9
(far outside the curvature constraint's feasible region) the factor 1/(1 − r_f κ) is continued
linearly so that an infeasible iterate never divides by zero.

Every value is computed with operations that accept complex numbers, so the tests check the
analytic gradients against complex-step derivatives (exact to rounding).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from typing import Any

import numpy as np

from ..bodies.features import bore_extent, resolved
from ..curves.basis import basis_derivatives, basis_matrix
from ..motion.laws import evaluate_law
from .kinds import KindModel
from .space import DesignSpace

#: Gauss–Legendre nodes per knot span (B-spline) or per segment (other laws) for the integrals.
GAUSS_PER_SPAN = 16
GAUSS_PER_SEGMENT = 64


def basis_matrices(knots: np.ndarray, degree: int, n_points: int, u: np.ndarray, nder: int
                   ) -> tuple[np.ndarray, ...]:
    """(N, N′, …, N^(nder)) as dense (len(u), n_points) matrices from one evaluation of the
    basis functions (the sensitivities of θ^(d)(u), y^(d)(u) to each control coordinate)."""
    span, ders = basis_derivatives(knots, degree, u, nder)
    cols = span[:, None] - degree + np.arange(degree + 1)[None, :]
    out = []
    for d in range(nder + 1):
        m = np.zeros((span.shape[0], n_points))
        np.put_along_axis(m, cols, ders[:, d, :], axis=1)
        out.append(m)
    return tuple(out)


class Lift(Enum):
    """How a motion segment's lift is given, as the model samples it."""

    #: a parametric curve (θ(u), s(u)): a B-spline lift law (Teoh 1989), sampled in u
    CURVE = "curve"
    #: a closed form s(θ − start)
    CLOSED_FORM = "closed form"
    #: no lift (one node)
    DWELL = "dwell"


@dataclass
class SegmentNodes:
    """Sample parameters of one motion segment: u (a parametric curve) or θ − start (others)."""

    index: int
    law: Lift
    params: np.ndarray
    block: Any = None         # LiftBlock for a varied B-spline segment
    cache: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Kin:
    """s, s′, s″ and θ′(t) at nodes with their derivatives with respect to p (rows × n)."""

    s: np.ndarray
    v: np.ndarray
    a: np.ndarray
    t1: np.ndarray
    ds: np.ndarray | None
    dv: np.ndarray | None
    da: np.ndarray | None
    dt1: np.ndarray | None


class SmoothModel:
    """Constraints and smooth objectives of a :class:`DesignSpace` at any design p."""

    def __init__(self, space: DesignSpace, samples: int | None = None):
        """``samples``: fixed nodes per rise/return for :meth:`constraints` (tests, reports)."""
        self.space = space
        spec = space.spec
        self.spec = spec
        prog = space.program
        self.program = prog
        samples = samples or 201
        #: the follower kind's checks and integrands (:mod:`cam_workbench.generators.optimise.kinds`)
        self.kind: KindModel = space.kind
        self.sense = self.kind.sense
        self.rr = self.kind.rr
        self.families = list(self.kind.families)
        # B-spline blocks and polynomial point blocks share one interface (arrays, y_jac, x_cols, y_cols)
        blocks = {b.motion_index: b for b in (*space.blocks, *space.point_blocks)}
        self.segments: list[SegmentNodes] = []
        for k in range(len(prog.starts)):
            curve = prog.curves[k] if prog.curves else None
            if prog.laws[k] is None:
                self.segments.append(SegmentNodes(k, Lift.DWELL, np.array([0.0])))
            elif curve is not None:
                self.segments.append(SegmentNodes(k, Lift.CURVE, np.linspace(0.0, curve.u_max, samples),
                                                  blocks.get(k)))
            else:
                self.segments.append(SegmentNodes(k, Lift.CLOSED_FORM, np.linspace(0.0, prog.spans[k], samples)))
        self._gauss = [self._gauss_params(sn) for sn in self.segments]

    # ---- parameters --------------------------------------------------------------------------
    def _gauss_params(self, sn: SegmentNodes) -> tuple[np.ndarray, np.ndarray]:
        """Gauss parameters and weights (in the segment's parameter) for the integrals."""
        prog = self.program
        if sn.law is Lift.DWELL:
            return np.array([0.0]), np.array([prog.spans[sn.index]])
        if sn.law is Lift.CURVE:
            curve = prog.curves[sn.index]
            xg, wg = np.polynomial.legendre.leggauss(GAUSS_PER_SPAN)
            br = np.unique(curve.knots)
            lo, hi = br[:-1], br[1:]
            t = (0.5 * (hi - lo)[:, None] * (xg[None, :] + 1) + lo[:, None]).ravel()
            w = (0.5 * (hi - lo)[:, None] * wg[None, :]).ravel()
            return t, w
        beta = prog.spans[sn.index]
        xg, wg = np.polynomial.legendre.leggauss(GAUSS_PER_SEGMENT)
        return 0.5 * beta * (xg + 1), 0.5 * beta * wg

    # ---- kinematics at parameters -----------------------------------------------------------
    def kinematics(self, sn: SegmentNodes, params: np.ndarray, p: np.ndarray, grad: bool,
                   key: str | None = None) -> Kin:
        """s, s′, s″, θ′ at ``params`` of segment ``sn`` for design ``p`` (with d/dp when ``grad``);
        ``key`` caches the basis matrices of a fixed parameter set."""
        prog = self.program
        k = sn.index
        m = params.shape[0]
        nv = self.space.n
        dtype = np.result_type(p.dtype, float)
        zeros = (lambda: np.zeros((m, nv), dtype=dtype)) if grad else (lambda: None)
        if sn.law is Lift.DWELL:
            one = np.ones(m, dtype=dtype)
            return Kin(prog.levels[k] * one, 0 * one, 0 * one, one, zeros(), zeros(), zeros(), zeros())
        if sn.law is Lift.CLOSED_FORM:
            cache = sn.cache.get(key) if key else None
            if cache is None:
                f, f1, f2, _ = evaluate_law(prog.laws[k], params / prog.spans[k])
                beta, h = prog.spans[k], prog.lifts[k]
                cache = (prog.levels[k] + h * f, h * f1 / beta, h * f2 / beta**2)
                if key:
                    sn.cache[key] = cache
            s, v, a = (c.astype(dtype) for c in cache)
            return Kin(s, v, a, np.ones(m, dtype=dtype), zeros(), zeros(), zeros(), zeros())
        curve = prog.curves[k]
        bm = sn.cache.get(key) if key else None
        if bm is None:
            bm = basis_matrices(curve.knots, curve.degree, curve.n_points, params, 2)
            if key:
                sn.cache[key] = bm
        b0, b1, b2 = bm
        blk = sn.block
        if blk is not None:
            x, y = blk.arrays(p)
        else:
            x, y = curve.x.astype(dtype), curve.y.astype(dtype)
        lift = abs(prog.lifts[k])
        base = prog.levels[k] if prog.lifts[k] > 0 else prog.levels[k] - lift
        t1, t2 = b1 @ x, b2 @ x
        y0, y1, y2 = b0 @ y, b1 @ y, b2 @ y
        n2 = t1 * y2 - y1 * t2
        s = base + lift * y0
        v = lift * y1 / t1                                   # thesis Eq. 2.37
        a = lift * n2 / t1**3                                # thesis Eq. 2.38
        if not grad:
            return Kin(s, v, a, t1, None, None, None, None)
        ds, dv, da, dt1 = zeros(), zeros(), zeros(), zeros()
        if blk is not None and blk.x_cols.size:
            b1i, b2i = b1[:, 1:-1], b2[:, 1:-1]
            cols = blk.x_cols
            dt1[:, cols] = b1i
            dv[:, cols] = -lift * (y1 / t1**2)[:, None] * b1i
            da[:, cols] = lift * (((y2 / t1**3) - 3 * n2 / t1**4)[:, None] * b1i - (y1 / t1**3)[:, None] * b2i)
        if blk is not None and blk.y_cols.size:
            jy = blk.y_jac                       # ∂y/∂p[y_cols]: a selection, or a polynomial's Φᵀ/h
            cols = blk.y_cols
            c0, c1, c2 = b0 @ jy, b1 @ jy, b2 @ jy
            ds[:, cols] = lift * c0
            dv[:, cols] = lift * c1 / t1[:, None]
            da[:, cols] = lift * (t1[:, None] * c2 - t2[:, None] * c1) / (t1**3)[:, None]
        return Kin(s, v, a, t1, ds, dv, da, dt1)

    # ---- the checks at nodes ------------------------------------------------------------------
    def local(self, geo: tuple, s: np.ndarray, v: np.ndarray, a: np.ndarray, grad: bool = True
              ) -> dict[str, tuple[np.ndarray, ...]]:
        """Every constraint family, the pressure angle ``phi`` and ``a`` = s″ at points with
        (s, s′, s″), as (g, ∂g/∂geo₀, …, ∂g/∂s, ∂g/∂s′, ∂g/∂s″) — geo the follower kind's geometric
        scalars (:attr:`DesignSpace.geometry_names`; translating: R_b and the spec's offset e);
        without ``grad`` the values only (a 1-tuple)."""
        return self.kind.local(geo, s, v, a, grad)

    def design_scalars(self, p: np.ndarray) -> tuple[Any, ...]:
        """The geometric scalars of design p (variables from p, the others the spec's)."""
        return self.space.geometry(p)

    def constraints(self, p: np.ndarray, grad: bool = True, families: tuple[str, ...] | None = None
                    ) -> dict[str, tuple[np.ndarray, np.ndarray | None]]:
        """Each family's values at every node (segments in order) and, with ``grad``, its
        Jacobian (nodes × n)."""
        families = families or tuple(self.families)
        geo = self.design_scalars(p)
        parts: dict[str, list] = {f: [] for f in families}
        for sn in self.segments:
            kin = self.kinematics(sn, sn.params, p, grad, key="nodes")
            loc = self.local(geo, kin.s, kin.v, kin.a, grad)
            for f in families:
                g = loc[f]
                parts[f].append((g[0], self._chain(g, kin) if grad else None))
        out = {}
        for f in families:
            vals = np.concatenate([np.broadcast_to(x[0], (x[0].shape[0],)) for x in parts[f]])
            jac = np.vstack([x[1] for x in parts[f]]) if grad else None
            out[f] = (vals, jac)
        return out

    def _chain(self, g: tuple, kin: Kin) -> np.ndarray:
        """d g/dp from the local partials and the kinematic sensitivities."""
        m = kin.s.shape[0]

        def col(x: Any) -> np.ndarray:
            return np.broadcast_to(x, (m,))[:, None]

        ng = len(self.space.geometry_cols)
        jac = col(g[ng + 1]) * kin.ds + col(g[ng + 2]) * kin.dv + col(g[ng + 3]) * kin.da
        for j, c in enumerate(self.space.geometry_cols):
            if c is not None:
                jac[:, c] += np.broadcast_to(g[1 + j], (m,))
        return jac

    def node_thetas(self, p: np.ndarray) -> np.ndarray:
        """Cam angles [rad] of the nodes at design p (segments in order)."""
        out = []
        for sn in self.segments:
            out.append(self.theta_at(sn, sn.params, p))
        return np.concatenate(out)

    def theta_at(self, sn: SegmentNodes, params: np.ndarray, p: np.ndarray) -> np.ndarray:
        start = self.program.starts[sn.index]
        if sn.law is Lift.CURVE:
            curve = self.program.curves[sn.index]
            x = sn.block.arrays(np.asarray(p, dtype=float))[0] if sn.block is not None else curve.x
            return start + basis_matrix(curve.knots, curve.degree, curve.n_points, params, 0) @ x
        return start + params

    # ---- objectives -----------------------------------------------------------------------
    def integral(self, p: np.ndarray, which: str, grad: bool = True) -> tuple[Any, np.ndarray | None]:
        """Closed-curve integrals over 0…2π with their gradients, from the follower kind's
        integrand per dθ (:meth:`KindModel.integrand`):

        * ``thesis_area``: ½∮(R_b + s)² dθ (thesis Eq. 4.21–4.27, translating knife/roller; exact:
          ½ r² θ′ is a polynomial in u on each knot span);
        * ``pitch_area``: the area inside the design curve, ½|∮ F × V dθ| (translating:
          ½∮(e² + (s₀ + s)²) dθ; a flat face: ½∮ h ρ |dγ|);
        * ``pitch_length``: ∮ |V| dθ, the design curve's length (translating:
          √((s₀ + s)² + (s′ − δe)²));
        * ``thesis_length``: ∮ √((R_b + s)² + s′²) dθ (the length of the thesis' machining curve;
          translating followers).
        """
        geo = self.design_scalars(p)
        ng = len(geo)
        total = 0.0
        gsum = np.zeros(self.space.n, dtype=np.result_type(p.dtype, float)) if grad else None
        cols = self.space.geometry_cols
        for sn, (t, w) in zip(self.segments, self._gauss):
            kin = self.kinematics(sn, t, p, grad, key="gauss")
            g = self.kind.integrand(which, geo, kin.s, kin.v, kin.a, grad)
            f = np.broadcast_to(g[0], kin.s.shape)
            total = total + np.sum(w * f * kin.t1)
            if grad:
                wt = w * kin.t1
                m = kin.s.shape[0]
                gs, gv, ga = (np.broadcast_to(x, (m,)) for x in g[ng + 1:ng + 4])
                gseg = ((wt * gs)[:, None] * kin.ds + (wt * gv)[:, None] * kin.dv + (wt * ga)[:, None] * kin.da
                        + (w * f)[:, None] * kin.dt1).sum(axis=0)
                for j, c in enumerate(cols):
                    if c is not None:
                        gseg[c] += np.sum(wt * g[1 + j])
                gsum = gsum + gseg
        return total, gsum

    def profile_area(self, p: np.ndarray, grad: bool = True) -> tuple[Any, np.ndarray | None]:
        """Area inside the roller profile: A_pitch − r_f·L_pitch + π r_f² (Steiner)."""
        a, ga = self.integral(p, "pitch_area", grad)
        length, gl = self.integral(p, "pitch_length", grad)
        rr = self.rr
        return a - rr * length + np.pi * rr * rr, (ga - rr * gl) if grad else None

    # ---- constraints as window maxima (the solver's view) ------------------------------------
    def check_rows(self, p: np.ndarray, grad: bool = True, windows: int = 40,
                   extra: tuple[tuple[str, float], ...] = ()
                   ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray, np.ndarray | None]:
        """Every constraint row of the checks at design p: the window maxima of each family
        (:meth:`window_max`), the face-span rows of a flat face checked without a given centre
        (max t − min t ≤ width as t_i/w + max(−t/w) − 1 and max(t/w) − t_j/w − 1 over the windows)
        and the follower's geometry rows (:meth:`KindModel.geometry_rows`).  ``extra`` channels (an
        epigraph's) are window-maximised in the same pass and returned apart.

        Returns (rows, Jacobian, extra rows, extra Jacobian)."""
        fams = [f for f in self.families if not f.startswith("face_span")]
        span = [f for f in self.families if f.startswith("face_span")]
        channels = tuple((f, 1.0) for f in fams + span)
        groove = self._groove_channels()
        vals, jac = self.window_max(p, channels + groove + tuple(extra), grad, windows)
        per = vals.size // (len(channels) + len(groove) + len(extra))
        nc = per * len(fams)
        rows: list[np.ndarray] = [vals[:nc]]
        jacs: list[np.ndarray] = [jac[:nc]] if grad else []
        if span:
            hi, lo = vals[nc:nc + per], vals[nc + per:nc + 2 * per]
            with np.errstate(invalid="ignore"):
                i, j = int(np.argmax(hi.real)), int(np.argmax(lo.real))
            rows += [hi + lo[j] - 1.0, hi[i] + lo - 1.0]
            if grad:
                jh, jl = jac[nc:nc + per], jac[nc + per:nc + 2 * per]
                jacs += [jh + jl[j][None, :], jh[i][None, :] + jl]
        if groove:
            at = per * len(channels)
            gv_, gj_ = self._groove_rows(p, vals[at:at + 3 * per], jac[at:at + 3 * per] if grad else None, grad)
            rows.append(gv_)
            if grad:
                jacs.append(gj_)
        geo = self.design_scalars(p)
        gv, gj = self.kind.geometry_rows(geo, grad)
        if gv.size:
            rows.append(gv)
            if grad:
                full = np.zeros((gv.size, self.space.n), dtype=np.result_type(gj.dtype, float))
                for k, c in enumerate(self.space.geometry_cols):
                    if c is not None:
                        full[:, c] += gj[:, k]
                jacs.append(full)
        top = per * (len(channels) + len(groove))
        return (np.concatenate(rows), np.vstack(jacs) if grad else None, vals[top:],
                jac[top:] if grad else None)

    # ---- a groove cam's body rows ---------------------------------------------------------------
    def _groove_channels(self) -> tuple[tuple[str, float], ...]:
        """The window channels of a groove cam's rows when a body variable is in the design: the
        pitch radius ±R/R_ref and −κ·R_ref (R_ref = the starting base radius)."""
        if not self.space.body_cols:
            return ()
        ref = self.kind.length_ref
        return (("pitch_radius", 1.0 / ref), ("pitch_radius", -1.0 / ref), ("kappa", -ref))

    def _groove_rows(self, p: np.ndarray, vals: np.ndarray, jac: np.ndarray | None, grad: bool
                     ) -> tuple[np.ndarray, np.ndarray | None]:
        """A groove cam's rows per window (w = 2r + c the groove width, D the disc):

        * rim:      (R + r + c/2 + min_wall)/(D/2) − 1 ≤ 0   (the outer wall's largest radius is the
          pitch curve's + w/2 exactly: there the normal is radial)
        * bore:     (bore + min_wall + r + c/2 − R)/R_ref ≤ 0 (likewise for the inner wall's smallest)
        * undercut: −κ (r + c/2) − 1 ≤ 0                      (the outer wall folds where the concave
          pitch radius is below w/2)

        ``vals``/``jac``: the window maxima of :meth:`_groove_channels`, channel-major."""
        sp = self.space
        spec = self.spec
        ref = self.kind.length_ref
        per = vals.size // 3
        r_hi, r_lo, k_c = vals[:per] * ref, vals[per:2 * per] * ref, vals[2 * per:] / ref
        diam = sp.body_value(p, "outer_diameter")
        half = self.rr + 0.5 * sp.body_value(p, "clearance")
        wall = resolved(spec, "groove", "min_wall")
        rim_num = r_hi + half + wall
        rim = rim_num / (0.5 * diam) - 1.0
        bore = (bore_extent(spec) + wall + half + r_lo) / ref
        under = k_c * half - 1.0
        out = np.concatenate([rim, bore, under])
        if not grad:
            return out, None
        j_hi, j_lo, j_k = jac[:per], jac[per:2 * per], jac[2 * per:]
        d_rim = j_hi * ref / (0.5 * diam)
        d_bore = j_lo.copy()
        d_under = j_k * half / ref
        cc = sp.body_cols.get("clearance")
        if cc is not None:
            d_rim[:, cc] += 0.5 / (0.5 * diam)
            d_bore[:, cc] += 0.5 / ref
            d_under[:, cc] += 0.5 * k_c
        cd = sp.body_cols.get("outer_diameter")
        if cd is not None:
            d_rim[:, cd] -= rim_num / (0.5 * diam * diam)
        return out, np.vstack([d_rim, d_bore, d_under])

    def window_max(self, p: np.ndarray, channels: tuple[tuple[str, float], ...], grad: bool = True,
                   windows: int = 40, per_window: int = 12) -> tuple[np.ndarray, np.ndarray | None]:
        """The largest value of each channel (``(name, factor)``: factor × the local quantity
        ``name`` of :meth:`local`) in every window of every rise/return — ``windows`` equal
        parameter windows per segment, each sampled at ``per_window`` + 1 points and its maximum
        refined by the vertex of the parabola through the best sample and its neighbours — and at
        every dwell.  The gradient of a window's maximum is the partial derivative at the
        maximiser (envelope theorem: d/dp max_u g(u, p) = ∂g/∂p at u*).

        Returns (values (rows,), Jacobian (rows × n)); rows ordered channel-major."""
        geo = self.design_scalars(p)
        vals_out: list[list[np.ndarray]] = [[] for _ in channels]
        jac_out: list[list[np.ndarray]] = [[] for _ in channels]
        for sn in self.segments:
            if sn.law is Lift.DWELL:
                kin = self.kinematics(sn, sn.params, p, grad, key="nodes")
                loc = self.local(geo, kin.s, kin.v, kin.a, grad)
                for c, (name, fac) in enumerate(channels):
                    g = loc[name]
                    vals_out[c].append(fac * np.broadcast_to(g[0], (1,)))
                    if grad:
                        jac_out[c].append(fac * self._chain(g, kin))
                continue
            end = float(sn.params[-1])
            key = f"grid{windows}x{per_window}"
            grid = sn.cache.get(key + "t")
            if grid is None:
                edges = np.linspace(0.0, end, windows + 1)
                frac = np.linspace(0.0, 1.0, per_window + 1)
                grid = (edges[:-1, None] + (edges[1:] - edges[:-1])[:, None] * frac[None, :])
                sn.cache[key + "t"] = grid
            kin = self.kinematics(sn, grid.ravel(), p, False, key=key)
            loc = self.local(geo, kin.s, kin.v, kin.a, False)
            h = grid[:, 1] - grid[:, 0]
            rows = np.arange(windows)
            picks = []
            for name, fac in channels:
                g = (fac * np.broadcast_to(loc[name][0], kin.s.shape)).reshape(grid.shape).real
                j = np.argmax(g, axis=1)
                jm = np.clip(j, 1, per_window - 1)
                g0, g1, g2 = g[rows, jm - 1], g[rows, jm], g[rows, jm + 1]
                den = g0 - 2 * g1 + g2
                with np.errstate(divide="ignore", invalid="ignore"):
                    off = np.where(den < 0, 0.5 * (g0 - g2) / den, 0.0)
                off = np.clip(np.nan_to_num(off), -1.0, 1.0)
                interior = (j > 0) & (j < per_window)
                t_star = np.where(interior, grid[rows, jm] + off * h, grid[rows, j])
                picks.append((t_star, grid[rows, j], h, grid[:, 0], grid[:, -1]))
            # a second parabola on t* ± h/4 (the first vertex is good to O(h³))
            t_mid = np.concatenate([pk[0] for pk in picks])
            dt = np.concatenate([pk[2] for pk in picks]) / 4
            lo_b = np.concatenate([pk[3] for pk in picks])
            hi_b = np.concatenate([pk[4] for pk in picks])
            t_lo, t_hi = np.maximum(t_mid - dt, lo_b), np.minimum(t_mid + dt, hi_b)
            kin3 = self.kinematics(sn, np.concatenate([t_lo, t_mid, t_hi]), p, False)
            loc3 = self.local(geo, kin3.s, kin3.v, kin3.a, False)
            nw = t_mid.size
            refined = []
            for c, (name, fac) in enumerate(channels):
                g3 = (fac * np.broadcast_to(loc3[name][0], (3 * nw,))).real
                sl = slice(c * windows, (c + 1) * windows)
                g0, g1, g2 = g3[:nw][sl], g3[nw:2 * nw][sl], g3[2 * nw:][sl]
                a0, a1, a2 = t_lo[sl], t_mid[sl], t_hi[sl]
                full = (a2 - a1 > 0) & (a1 - a0 > 0) & np.isclose(a2 - a1, a1 - a0)
                den = g0 - 2 * g1 + g2
                with np.errstate(divide="ignore", invalid="ignore"):
                    off = np.where(full & (den < 0), 0.5 * (g0 - g2) / den, 0.0)
                off = np.clip(np.nan_to_num(off), -1.0, 1.0)
                refined.append((a1 + off * (a2 - a1), picks[c][1]))
            picks = refined
            # the maximisers, all channels at once; keep the better of vertex and best sample
            t_all = np.concatenate([np.concatenate([a, b]) for a, b in picks])
            kin2 = self.kinematics(sn, t_all, p, grad)
            loc2 = self.local(geo, kin2.s, kin2.v, kin2.a, grad)
            m2 = kin2.s.shape[0]
            for c, (name, fac) in enumerate(channels):
                g = loc2[name]
                v = (fac * np.broadcast_to(g[0], (m2,)))[2 * c * windows:2 * (c + 1) * windows]
                take = np.where(v[:windows].real >= v[windows:].real, rows, rows + windows)
                vals_out[c].append(v[take])
                if grad:
                    idx = 2 * c * windows + take
                    g_sub = tuple(np.broadcast_to(x, (m2,))[idx] for x in g)
                    kin_sub = Kin(*(None if f is None else f[idx] for f in
                                    (kin2.s, kin2.v, kin2.a, kin2.t1, kin2.ds, kin2.dv, kin2.da, kin2.dt1)))
                    jac_out[c].append(fac * self._chain(g_sub, kin_sub))
        vals = np.concatenate([np.concatenate(v) for v in vals_out])
        jac = np.vstack([np.vstack(j) for j in jac_out]) if grad else None
        return vals, jac

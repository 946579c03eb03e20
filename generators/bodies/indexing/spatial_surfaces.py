"""The rib flanks of the spatial (barrel and globoidal) indexers as B-spline surfaces: tensor-product
cubic × cubic surfaces interpolating the exact envelope points of :mod:`.spatial`, refined until
their distance from the exact envelope, measured on dense check grids, is within a tolerance.

Units: lengths in mm, angles in radians (degrees only in :meth:`FlankSurfaces.summary`).

Parameters.  A flank of side s (±1) is the envelope of the roller locus' side s (see
:mod:`.spatial`: τ ↦ the pose of roller 0 at input angle τ carries every roller, roller j at θ being
τ = θ + 2πj), so one surface per side carries the flank of every rib: S(u, v) with u = τ [rad]
along the locus and v = t [mm] along the roller's axis, in the CAM frame.  Its exact counterpart
P(τ, t) = ``contact_lines(ix, 0, τ, t, s).points``.

Domain.  t spans the roller's whole length [t0, t1].  τ spans the design's engagement of that
side: the one cyclic run of locus rows of ``design.sheet(s).in_band`` (any t) — the complement of
its longest gap over the locus' period 2πN — widened by one design row at each end (the exact edge
of the band lies between an in-band row and the next one out).

Fit.  The input's law makes ψ''' (cycloidal, modified sine, …) or ψ'' (harmonic) jump at the
index's ends, and P depends on ψ' through the meshing normal, so P's second (or first)
τ-derivative jumps at τ = θ_s + 2πm and θ_s + β + 2πm.  Those τ are nodes and split the τ range
into pieces; each piece is interpolated on its own uniform nodes by a not-a-knot cubic (its second
and penultimate nodes are not knots), and the pieces are joined at a triple knot (C0 in the
representation; the data make the join C1 or C2 geometrically).  The t direction is one
not-a-knot piece on uniform nodes.  Not-a-knot rather than exact end derivatives: ∂P/∂τ needs ψ''
through the normal's derivative, which :func:`.spatial.contact_lines` does not give; the fit uses
the exact points alone.  Collocation then gives the poles: Q = A_τ⁻¹ · P(nodes) · A_tᵀ⁻¹ (weights 1).

Error.  On every node cell the check points are a 5 × 5 sub-grid at fractions 0, ¼, ½, ¾, 1 in
each direction (so every cell's midpoint and its edges' midpoints), compared with the exact point
at the same (τ, t): the parametric error |S(τ, t) − P(τ, t)| bounds the distance from S(τ, t) to
the exact envelope; its component along the exact normal, |(S − P)·n|, is the geometric distance
to first order (the tangential part slides along the surface).  The error's largest value inside a
cell lies between check points (≈ 8 % above their largest here): within a cell the error vector
S − P is smooth (P minus a cubic patch — quartic to leading order in each parameter), so its
tensor quartic interpolant through the 5 × 5 samples stands for it; its maximum is searched on a
33 × 33 sub-grid of the cells whose sampled error is at least half the largest, then on a 33 × 33
grid 1/32² apart about the best point of the leading cells.  The reported maxima (and where) are
those of the interpolant (≥ the samples'; within 1e-3 of dense exact sampling in the tests).
Refinement doubles the nodes of every τ piece whose τ error (check points between τ nodes on the
t nodes) exceeds half the tolerance, and the t nodes when the t error (between t nodes on the τ
nodes) does, until the largest error is within the tolerance; else :class:`SpecError`
``indexer.fit_tolerance``.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...curves.basis import basis_derivatives, basis_matrix
from ...errors import SpecError
from .spatial import TWO_PI, SpatialDesign, SpatialIndexer, contact_lines

Array = np.ndarray
#: default tolerance [mm] (1 µm)
DEFAULT_TOLERANCE = 1e-3
#: check points per node cell and direction (fractions 0, ¼, ½, ¾; 1 is the next cell's 0)
_SUB = 4
#: the error model's grid per cell and direction, the cells per block, the cells zoomed into
_FINE = 33
_BLOCK = 2048
_ZOOM = 64
#: initial τ node spacing [rad] and t intervals
_H_TAU = math.radians(5.0)
_T_CELLS = 4
#: refinement limits: passes, τ nodes, t nodes
_PASSES = 10
_MAX_TAU_NODES = 2049
_MAX_T_NODES = 33


# ---------------------------------------------------------------------------------------------
# the neutral surface

@dataclass(frozen=True)
class BSplineSurface:
    """A tensor-product (rational) B-spline surface — the neutral data a CAD adaptor consumes
    (OCCT ``Geom_BSplineSurface``, FreeCAD ``Part.BSplineSurface``).

    Attributes:
        degree_u, degree_v: the degrees p, q.
        knots_u, knots_v: full clamped knot vectors (nu + p + 1,), (nv + q + 1,).
        poles: (nu, nv, 3) control points [mm].
        weights: (nu, nv) positive weights (all ones for a polynomial surface).
    """

    degree_u: int
    degree_v: int
    knots_u: Array
    knots_v: Array
    poles: Array
    weights: Array

    @property
    def shape(self) -> tuple[int, int]:
        """(nu, nv): the poles' counts."""
        return int(self.poles.shape[0]), int(self.poles.shape[1])

    @property
    def domain(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """((u0, u1), (v0, v1)): the parameter ranges."""
        p, q = self.degree_u, self.degree_v
        return ((float(self.knots_u[p]), float(self.knots_u[-p - 1])),
                (float(self.knots_v[q]), float(self.knots_v[-q - 1])))

    @property
    def is_rational(self) -> bool:
        """Whether the weights differ."""
        w = self.weights
        return bool(np.ptp(w) > 1e-12 * np.max(np.abs(w)))

    def distinct_knots(self) -> tuple[Array, Array, Array, Array]:
        """(u knots, their multiplicities, v knots, their multiplicities) — the form OCCT and FreeCAD take."""
        u, mu = np.unique(self.knots_u, return_counts=True)
        v, mv = np.unique(self.knots_v, return_counts=True)
        return u, mu, v, mv

    def evaluate(self, u: Array, v: Array) -> Array:
        """Points S(u, v) (..., 3) [mm] at parameters ``u``, ``v`` (broadcast together; each
        clipped to its domain)."""
        u, v = np.broadcast_arrays(np.asarray(u, dtype=float), np.asarray(v, dtype=float))
        shape = u.shape
        (u0, u1), (v0, v1) = self.domain
        uu, vv = np.clip(u.ravel(), u0, u1), np.clip(v.ravel(), v0, v1)
        p, q = self.degree_u, self.degree_v
        su, bu = basis_derivatives(self.knots_u, p, uu, 0)
        sv, bv = basis_derivatives(self.knots_v, q, vv, 0)
        iu = su[:, None] - p + np.arange(p + 1)
        iv = sv[:, None] - q + np.arange(q + 1)
        hom = np.concatenate([self.poles * self.weights[..., None], self.weights[..., None]], axis=-1)
        g = hom[iu[:, :, None], iv[:, None, :]]                                  # (M, p+1, q+1, 4)
        h = np.einsum("mi,mj,mijc->mc", bu[:, 0, :], bv[:, 0, :], g)
        return (h[:, :3] / h[:, 3:]).reshape(shape + (3,))

    def evaluate_grid(self, u: Array, v: Array) -> Array:
        """Points (len(u), len(v), 3) [mm] on the grid ``u`` × ``v`` (1-D, inside the domain)."""
        nv = self.shape[1]
        p = self.degree_u
        su, bu = basis_derivatives(self.knots_u, p, np.asarray(u, dtype=float), 0)
        bv = basis_matrix(self.knots_v, self.degree_v, nv, np.asarray(v, dtype=float))
        hom = np.concatenate([self.poles * self.weights[..., None], self.weights[..., None]], axis=-1)
        rows = np.einsum("ai,aijc->ajc", bu[:, 0, :], hom[su[:, None] - p + np.arange(p + 1)])   # (A, nv, 4)
        h = np.matmul(bv[None], rows)                                                           # (A, B, 4)
        return h[..., :3] / h[..., 3:]


def _knots(pieces: list[Array]) -> Array:
    """The clamped cubic knot vector interpolating at the nodes of consecutive ``pieces`` (each an
    increasing node array, the next starting where it ends): not-a-knot in each piece, a triple knot
    at each join.  Poles: one per distinct node."""
    parts = [np.full(4, pieces[0][0])]
    for k, x in enumerate(pieces):
        parts.append(x[2:-2])
        parts.append(np.full(4 if k == len(pieces) - 1 else 3, x[-1]))
    return np.concatenate(parts)


def _interpolate(tau_pieces: list[Array], t_nodes: Array, points: Array) -> BSplineSurface:
    """The cubic × cubic surface through ``points`` (Mτ, Mt, 3) on the nodes (the τ pieces
    joined, t)."""
    tau = np.concatenate([tau_pieces[0]] + [x[1:] for x in tau_pieces[1:]])
    ku, kv = _knots(tau_pieces), _knots([t_nodes])
    au = basis_matrix(ku, 3, tau.size, tau)
    av = basis_matrix(kv, 3, t_nodes.size, t_nodes)
    mu, mv = tau.size, t_nodes.size
    x = np.linalg.solve(au, points.reshape(mu, mv * 3)).reshape(mu, mv, 3)
    poles = np.linalg.solve(av, x.transpose(1, 0, 2).reshape(mv, mu * 3)).reshape(mv, mu, 3).transpose(1, 0, 2)
    return BSplineSurface(3, 3, ku, kv, np.ascontiguousarray(poles), np.ones((mu, mv)))


# ---------------------------------------------------------------------------------------------
# results

@dataclass(frozen=True)
class FlankSurface:
    """One side's flank surface and how well it matches the exact envelope.

    side: ±1.  surface: :class:`BSplineSurface`, u = τ [rad], v = t [mm], cam frame.
    tau_range [rad], t_range [mm]: its domain.  breaks: the interior τ [rad] where the pieces join
    (the law's ends).  tau_nodes, t_nodes: the interpolation nodes (the surface passes through the
    exact points there).  max_error [mm]: the largest parametric error |S − P| over the check
    points, at ``max_error_at`` (τ [rad], t [mm]); max_normal_error [mm], at
    ``max_normal_error_at``: the largest |(S − P)·n|.  passes: fits made.  check_points: how many
    points the last measurement used.  fit_seconds: the wall time of the fit and its checks (not in
    :meth:`summary`: report.json holds no timings)."""

    side: int
    surface: BSplineSurface
    tau_range: tuple[float, float]
    t_range: tuple[float, float]
    breaks: Array
    tau_nodes: Array
    t_nodes: Array
    max_error: float
    max_error_at: tuple[float, float]
    max_normal_error: float
    max_normal_error_at: tuple[float, float]
    passes: int
    check_points: int
    fit_seconds: float

    def summary(self) -> dict[str, Any]:
        """Plain numbers (degrees, mm)."""
        return {
            "side": self.side,
            "tau_from_deg": math.degrees(self.tau_range[0]), "tau_to_deg": math.degrees(self.tau_range[1]),
            "t_from_mm": self.t_range[0], "t_to_mm": self.t_range[1],
            "breaks_deg": [math.degrees(float(b)) for b in self.breaks],
            "nodes_tau": int(self.tau_nodes.size), "nodes_t": int(self.t_nodes.size),
            "poles_u": self.surface.shape[0], "poles_v": self.surface.shape[1],
            "max_error_mm": self.max_error,
            "max_error_at": {"tau_deg": math.degrees(self.max_error_at[0]), "t_mm": self.max_error_at[1]},
            "max_normal_error_mm": self.max_normal_error,
            "max_normal_error_at": {"tau_deg": math.degrees(self.max_normal_error_at[0]),
                                    "t_mm": self.max_normal_error_at[1]},
            "passes": self.passes, "check_points": self.check_points,
        }


@dataclass(frozen=True)
class FlankSurfaces:
    """The rib's two flank surfaces (side +1, side −1) of a spatial indexer, fitted to
    ``tolerance`` [mm]."""

    indexer: SpatialIndexer
    tolerance: float
    flanks: tuple[FlankSurface, FlankSurface]

    def flank(self, side: int) -> FlankSurface:
        """The flank surface of side ``side`` (±1)."""
        return self.flanks[0 if side == 1 else 1]

    def summary(self) -> dict[str, Any]:
        """Plain numbers (JSON-safe): lengths in mm, angles in degrees."""
        return {"units": {"length": "mm", "angle": "deg"}, "type": type(self.indexer).__name__,
                "tolerance_mm": self.tolerance, "degree": [3, 3],
                "flanks": [f.summary() for f in self.flanks]}


# ---------------------------------------------------------------------------------------------
# construction

def flank_tau_range(design: SpatialDesign, side: int) -> tuple[float, float]:
    """The τ range [rad] of side ``side``'s flank: the design's cyclic run of in-band locus rows
    (the complement of the longest gap over the locus' period), widened by one row at each end."""
    sheet = design.sheet(side)
    engaged = sheet.in_band.any(axis=1)[:-1]                 # the last row repeats the first a period on
    period = TWO_PI * design.rollers.size
    n_rows = engaged.size
    if not engaged.any() or engaged.all():
        raise SpecError("indexer.cam_width", f"the side {side:+d} flank is "
                        + ("nowhere" if not engaged.any() else "everywhere") + " in the rib's band")
    on = np.flatnonzero(engaged)
    gaps = np.diff(np.concatenate([on, [on[0] + n_rows]]))
    k = int(np.argmax(gaps))
    first = int(on[(k + 1) % on.size]) - 1
    last = first + 1 + int(n_rows - gaps[k]) + 1

    def tau_of(r: int) -> float:
        turns, i = divmod(r, n_rows)
        return float(sheet.tau[i]) + period * turns

    return tau_of(first), tau_of(last)


def _breaks(ix: SpatialIndexer, lo: float, hi: float) -> Array:
    """The law's ends θ_s + 2πm, θ_s + β + 2πm strictly inside (lo, hi) [rad]."""
    ts, beta = float(ix.index_start), float(ix.index_angle)
    m = np.arange(math.floor((lo - ts) / TWO_PI) - 1, math.ceil((hi - ts) / TWO_PI) + 2)
    b = np.sort(np.concatenate([ts + TWO_PI * m, ts + beta + TWO_PI * m]))
    eps = 1e-9 * max(1.0, abs(lo), abs(hi))
    return b[(b > lo + eps) & (b < hi - eps)]


def _check_params(nodes: Array) -> tuple[Array, Array]:
    """Check parameters at fractions 0, 1/_SUB, … of every node cell, plus the last node; and each
    one's cell (−1 on a node)."""
    s = np.arange(_SUB) / _SUB
    x = (nodes[:-1, None] + s[None, :] * np.diff(nodes)[:, None]).ravel()
    cell = np.where(s[None, :] > 0, np.arange(nodes.size - 1)[:, None], -1).ravel()
    return np.concatenate([x, nodes[-1:]]), np.concatenate([cell, [-1]])


def _lagrange(x: Array) -> Array:
    """(..., _SUB + 1): the Lagrange basis on the fractions k/_SUB (degree _SUB) at fractions ``x``."""
    s = np.arange(_SUB + 1) / _SUB
    num = np.asarray(x, dtype=float)[..., None, None] - s                      # (..., k, m)
    den = s[:, None] - s[None, :]
    same = np.eye(_SUB + 1, dtype=bool)
    return np.prod(np.where(same, 1.0, num / np.where(same, 1.0, den)), axis=-1)


def _model_max(values: Array, tau_c: Array, t_c: Array) -> tuple[float, float, float]:
    """The largest |value| of the per-cell tensor interpolant (degree _SUB) of ``values`` (Mτ, Mt,
    C), sampled at the check parameters ``tau_c``, ``t_c`` (_SUB per cell and the last node); and
    where (τ [rad], t [mm]).  The interpolant is evaluated on a _FINE × _FINE grid of the cells
    whose sampled largest is at least half the overall, then on a _FINE × _FINE grid 1/_FINE²
    apart around the best grid point of each cell within 1 % of the best (the _ZOOM best)."""
    mag = np.linalg.norm(values, axis=-1)
    n_u, n_v = (mag.shape[0] - 1) // _SUB, (mag.shape[1] - 1) // _SUB
    iu = _SUB * np.arange(n_u)[:, None] + np.arange(_SUB + 1)                  # (Cu, 5)
    iv = _SUB * np.arange(n_v)[:, None] + np.arange(_SUB + 1)
    cell = mag[iu[:, :, None, None], iv[None, None, :, :]].max(axis=(1, 3))     # (Cu, Cv)
    cu, cv = np.nonzero(cell >= 0.5 * cell.max())
    frac = np.linspace(0.0, 1.0, _FINE)
    lag = _lagrange(frac)
    peak, pa, pb = [], [], []
    for b in range(0, cu.size, _BLOCK):
        blk = values[iu[cu[b:b + _BLOCK]][:, :, None], iv[cv[b:b + _BLOCK]][:, None, :]]   # (P, 5, 5, C)
        fine = np.linalg.norm(np.einsum("ak,pklc,bl->pabc", lag, blk, lag, optimize=True), axis=-1)
        flat = fine.reshape(fine.shape[0], -1)
        k = np.argmax(flat, axis=1)
        peak.append(flat[np.arange(k.size), k])
        pa.append(k // _FINE)
        pb.append(k % _FINE)
    peak, pa, pb = np.concatenate(peak), np.concatenate(pa), np.concatenate(pb)
    top = np.argsort(-peak)[:_ZOOM]
    top = top[peak[top] >= 0.99 * peak[top[0]]]
    # zoom: ±1/(_FINE − 1) about each candidate's grid maximum
    step = np.linspace(-1.0, 1.0, _FINE) / (_FINE - 1)
    fu = np.clip(frac[pa[top]][:, None] + step, 0.0, 1.0)                           # (K, F)
    fv = np.clip(frac[pb[top]][:, None] + step, 0.0, 1.0)
    blk = values[iu[cu[top]][:, :, None], iv[cv[top]][:, None, :]]
    fine = np.linalg.norm(np.einsum("pak,pklc,pbl->pabc", _lagrange(fu), blk, _lagrange(fv), optimize=True),
                          axis=-1)
    p, a, c = np.unravel_index(int(np.argmax(fine)), fine.shape)
    u0, u1 = tau_c[iu[cu[top[p]], 0]], tau_c[iu[cu[top[p]], -1]]
    v0, v1 = t_c[iv[cv[top[p]], 0]], t_c[iv[cv[top[p]], -1]]
    return float(fine[p, a, c]), float(u0 + fu[p, a] * (u1 - u0)), float(v0 + fv[p, c] * (v1 - v0))


def _fit(ix: SpatialIndexer, side: int, edges: Array, t_range: tuple[float, float], tolerance: float
         ) -> FlankSurface:
    """Fit and refine side ``side``'s surface over the τ pieces between ``edges`` (module docs)."""
    start = time.perf_counter()
    lengths = np.diff(edges)
    cells = np.maximum(3, np.ceil(lengths / _H_TAU)).astype(int)
    t_cells = _T_CELLS
    half = 0.5 * tolerance
    passes = 0
    while True:
        passes += 1
        pieces = [np.linspace(a, b, c + 1) for a, b, c in zip(edges[:-1], edges[1:], cells)]
        tau = np.concatenate([pieces[0]] + [x[1:] for x in pieces[1:]])
        t = np.linspace(t_range[0], t_range[1], t_cells + 1)
        surf = _interpolate(pieces, t, contact_lines(ix, 0, tau, t, side).points)
        tc, tau_cell = _check_params(tau)
        vc, t_cell = _check_params(t)
        exact = contact_lines(ix, 0, tc, vc, side)
        diff = surf.evaluate_grid(tc, vc) - exact.points
        err = np.linalg.norm(diff, axis=-1)
        worst, w_tau, w_t = _model_max(diff, tc, vc)
        if worst <= tolerance:
            break
        # τ error: between τ nodes, on the t nodes; by piece
        piece_of_cell = np.repeat(np.arange(cells.size), cells)
        e_tau = np.zeros(cells.size)
        rows = tau_cell >= 0
        np.maximum.at(e_tau, piece_of_cell[tau_cell[rows]], err[rows][:, t_cell < 0].max(axis=1))
        e_t = float(err[tau_cell < 0][:, t_cell >= 0].max())
        more_tau = e_tau > half
        more_t = e_t > half
        if not more_tau.any() and not more_t:
            more_tau = e_tau >= 0.5 * e_tau.max()
            more_t = e_t >= e_tau.max()
        new_cells = np.where(more_tau, 2 * cells, cells)
        new_t = 2 * t_cells if more_t else t_cells
        if passes >= _PASSES or new_cells.sum() + 1 > _MAX_TAU_NODES or new_t + 1 > _MAX_T_NODES:
            raise SpecError("indexer.fit_tolerance",
                            f"the side {side:+d} flank's B-spline surface reached {worst * 1e3:.4g} µm from the "
                            f"exact envelope (at τ = {math.degrees(w_tau):.6g}°, t = {w_t:.6g} mm) with "
                            f"{tau.size}×{t.size} nodes after {passes} passes, must be ≤ {tolerance * 1e3:.4g} µm "
                            f"— increase the tolerance")
        cells, t_cells = new_cells, new_t
    normal, n_tau, n_t = _model_max(np.einsum("...i,...i->...", diff, exact.normals)[..., None], tc, vc)
    return FlankSurface(side, surf, (float(edges[0]), float(edges[-1])), (float(t_range[0]), float(t_range[1])),
                        edges[1:-1].copy(), tau, t, worst, (w_tau, w_t), normal, (n_tau, n_t), passes, int(err.size),
                        time.perf_counter() - start)


def flank_surfaces(design: SpatialDesign, tolerance: float = DEFAULT_TOLERANCE) -> FlankSurfaces:
    """The rib's two flanks (side +1, side −1) of a barrel or globoidal ``design`` as cubic ×
    cubic B-spline surfaces S(τ, t) in the cam frame, within ``tolerance`` [mm] of the exact
    envelope at every check point (module docs).

    Raises SpecError ``indexer.fit_tolerance`` for a tolerance that is not a positive number or
    is not reached (naming the error reached), ``indexer.cam_width`` for a flank never (or always)
    in the band."""
    if isinstance(tolerance, bool) or not isinstance(tolerance, (int, float, np.integer, np.floating)) \
            or not math.isfinite(tolerance) or tolerance <= 0:
        raise SpecError("indexer.fit_tolerance", f"must be a positive number of mm, got {tolerance!r}")
    ix = design.indexer
    t_range = (float(ix.roller_start), float(ix.roller_end))
    flanks = []
    for side in (1, -1):
        lo, hi = flank_tau_range(design, side)
        edges = np.concatenate([[lo], _breaks(ix, lo, hi), [hi]])
        flanks.append(_fit(ix, side, edges, t_range, float(tolerance)))
    return FlankSurfaces(ix, float(tolerance), (flanks[0], flanks[1]))

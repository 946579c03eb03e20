"""The volume of a spatial (barrel or globoidal) indexer's cam, integrated on a grid of the exact
envelope — an independent number for the OCCT solid of
:func:`cam_workbench.kernel.spatial_indexer.spatial_solid` to be held against (a wrong solid cannot
hide its volume).

Units: lengths in mm, volumes in mm³, angles in radians.

The solid (the kernel module's docs): the CORE — the root cylinder ρ ≤ root (barrel), or the
revolution of ρ ≤ C − √(root² − z²) (globoid) over |z| ≤ W/2, less a bore — and the RIB: the part of
the band (barrel root ≤ ρ ≤ outer, globoid tip ≤ g ≤ root, |z| ≤ W/2; :mod:`.spatial`) between the
two flank sheets on the side the roller's normal n points to.  Each flank is the exact envelope
(:func:`.spatial.contact_lines`, the locus parameter τ and the roller's axis parameter t), continued
beyond the roller's ends straight along the root surface's normal: barrel at constant (φ, z),
globoid at constant (φ, β) — β the angle about the circle P traces.

Coordinates of the cam frame: r (barrel ρ; globoid g = √((C − ρ)² + z²), the distance from the circle
P traces), φ = atan2(y, x) and a (barrel z; globoid β = atan2(z, C − ρ), so z = g·sin β and
ρ = C − g·cos β).  The volume element is ρ·dr·dφ·da (barrel) or ρ·g·dr·dφ·dβ (globoid), and its
a-primitive F(a) = r·a (barrel) or r·(C·β − r·sin β) (globoid).

Construction (:func:`cam_volume`):

* the core by its closed form (less π·r_b²·W for a bore of radius r_b);
* the rib: the midpoint rule over n_r levels of r (the band's radial extent) and n_φ uniform
  columns of φ over [0, 2π); along each column (r_k, φ_j), exactly between the flanks' crossings
  a_c (each with the sign s_c of n·e_a: +1 where the rib begins, going up a, −1 where it ends):
  L = Σ s_c·(F(a_max) − F(a_c)) + [lowest crossing has s = −1]·(F(a_max) − F(−a_max)), a_max = W/2
  (barrel) or asin(W/(2r)) (globoid); the crossings must alternate in sign (checked);
* the crossings: each flank's τ range (:func:`.spatial_surfaces.flank_tau_range`) widened until its
  end rows, with their continuations, lie outside the band at every level; rows of exact contact
  lines on uniform τ nodes (one per two column spacings, plus the law's ends) and :data:`T_NODES`
  points of t; a row's point at level r_k by 4-point Lagrange interpolation in r along its contact
  line (r grows along every contact line: checked), its end point's (φ, a) beyond either end (the
  continuation); along τ the level's trace is a graph a(φ) (φ monotone: checked), read by the cubic
  Hermite interpolant with three-point slopes at every column φ_j + 2πm each interval of it spans.

Error: the grid (levels, columns and τ nodes together) at spacing h and h/2.  The midpoint rules
converge as h² once asymptotic (Richardson: the finer's error ≈ |V(h/2) − V(h)|/3), but the r rule
is not yet regular at these grids (the flank's continuation below the roller starts at a level that
varies along the rib: successive differences fall by 1–5×), so the ``error`` reported is the whole
difference |V(h/2) − V(h)| (it bounds the finer's error whenever the convergence is at least first
order), at least :data:`ERROR_FLOOR` of the rib; the ``value`` is the finer grid's.

Measured (defaults 128 × 720 and 256 × 1440; ``design_barrel(BarrelIndexer(), 361, 9)`` /
``design_globoidal(GloboidalIndexer(), 361, 9)``): ~0.6 s each; error 0.032 / 0.28 mm³ (1.2e-7 /
4.2e-7 of the cam), actual 0.003 / 0.06 mm³ (against 512 × 1440); OCCT's adaptive volume of the
solid (ε = 1e-6 per face) within +1.0e-7 / −8e-9 of the value.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .spatial import TWO_PI, BarrelIndexer, GloboidalIndexer, SpatialDesign, contact_lines
from .spatial_surfaces import flank_tau_range

Array = np.ndarray

#: the coarse grid's levels of r and columns of φ (the fine grid doubles both)
LEVELS = 128
COLUMNS = 720
#: τ nodes per φ column spacing (the τ step is 2π/(columns·TAU_PER_COLUMN))
TAU_PER_COLUMN = 0.5
#: points of t along each contact line
T_NODES = 25
#: the widening of a flank's τ range: step [rad] and the most searched [rad]
WIDEN_STEP = math.radians(1.0)
MAX_WIDEN = math.radians(120.0)
#: the smallest error reported, relative to the rib's volume: the contact lines' interpolation in r
#: (T_NODES = 25 differs from 49 by < 1e-8 of the rib, measured), not refined with the grid
ERROR_FLOOR = 2e-8


class RibNotBounded(RuntimeError):
    """The flanks, continued below the rollers to the root, do not bound a rib: ``closes`` — they
    cross out of order (the rib closes up between neighbouring rollers); otherwise a flank leaves the
    band (or the cam's end faces) before it reaches the root."""

    def __init__(self, message: str, closes: bool) -> None:
        super().__init__(message)
        self.closes = closes


@dataclass(frozen=True)
class VolumeEstimate:
    """The cam's volume: ``value`` = ``core`` + ``rib`` [mm³] (the finer grid's), ``error`` [mm³] the
    estimate of |value − exact| from the two grids (module docs), ``what`` one line on how."""

    value: float
    core: float
    rib: float
    error: float
    what: str


def _is_barrel(ix) -> bool:
    return isinstance(ix, BarrelIndexer)


def core_volume(ix, bore_radius: float = 0.0) -> float:
    """The core's volume [mm³] by its closed form, less a bore of ``bore_radius``."""
    h = 0.5 * float(ix.cam_width)
    bore = math.pi * float(bore_radius) ** 2 * 2.0 * h
    if _is_barrel(ix):
        return math.pi * float(ix.root_radius) ** 2 * 2.0 * h - bore
    c, rr = float(ix.centre_distance), float(ix.root_radius)

    def prim(z: float) -> float:          # ∫ π (C − √(R² − z²))² dz
        s = math.sqrt(rr**2 - z**2)
        return math.pi * ((c**2 + rr**2) * z - z**3 / 3.0 - c * (z * s + rr**2 * math.asin(z / rr)))

    return prim(h) - prim(-h) - bore


def _radial_range(ix) -> tuple[float, float]:
    if _is_barrel(ix):
        return float(ix.root_radius), float(ix.outer_radius)
    return float(ix.tip_radius), float(ix.root_radius)


def _a_max(ix, r: Array) -> Array:
    h = 0.5 * float(ix.cam_width)
    if _is_barrel(ix):
        return np.full_like(r, h)
    return np.arcsin(h / r)


def _primitive(ix, r: Array, a: Array) -> Array:
    """F(a) at levels r (broadcast): the a-primitive of the volume element per dr·dφ."""
    if _is_barrel(ix):
        return r * a
    return r * (float(ix.centre_distance) * a - r * np.sin(a))


def _lines(ix, side: int, tau: Array, t: Array, check: bool = True) -> tuple[Array, Array, Array, Array]:
    """(r, φ, a, s) of side ``side``'s exact contact lines at rows ``tau`` and points ``t`` (R, K):
    φ continuous along τ and along t; s the sign of n·e_a; with ``check``, r must grow along t."""
    cl = contact_lines(ix, 0, tau, t, side)
    q, n = cl.points, cl.normals
    rho = np.hypot(q[..., 0], q[..., 1])
    phi = np.arctan2(q[..., 1], q[..., 0])
    if _is_barrel(ix):
        r, a = rho, q[..., 2]
        na = n[..., 2]
    else:
        c = float(ix.centre_distance)
        r, a = np.hypot(c - rho, q[..., 2]), np.arctan2(q[..., 2], c - rho)
        sb, cb = np.sin(a), np.cos(a)
        na = sb * (n[..., 0] * q[..., 0] + n[..., 1] * q[..., 1]) / rho + cb * n[..., 2]
    phi = np.unwrap(phi, axis=0)
    phi = phi - TWO_PI * np.round((phi - phi[:, :1]) / TWO_PI)
    if check and not (np.diff(r, axis=1) > 0).all():
        raise RibNotBounded(f"the side {side:+d} contact lines' radial coordinate does not grow along t", False)
    return r, phi, a, np.sign(na)


def _at_levels(r: Array, phi: Array, a: Array, s: Array, levels: Array) -> tuple[Array, Array, Array]:
    """Each row's point at each level (R, N): (φ, a) by 4-point Lagrange interpolation in r, the end
    point's beyond either end of the line; s of the nearest point."""
    rows, k = r.shape
    count = (r[:, None, :] < levels[None, :, None]).sum(axis=2)                  # (R, N) nodes below
    j0 = np.clip(count - 2, 0, k - 4)
    idx = j0[..., None] + np.arange(4)                                            # (R, N, 4)
    ri = np.take_along_axis(r[:, None, :], idx, axis=2)
    x = levels[None, :, None]
    w = np.ones(idx.shape)
    for m in range(4):
        for n in range(4):
            if m != n:
                w[..., m] *= (x[..., 0] - ri[..., n]) / (ri[..., m] - ri[..., n])
    ph = np.einsum("rnm,rnm->rn", w, np.take_along_axis(phi[:, None, :], idx, axis=2))
    aa = np.einsum("rnm,rnm->rn", w, np.take_along_axis(a[:, None, :], idx, axis=2))
    below, above = levels[None, :] <= r[:, :1], levels[None, :] >= r[:, -1:]
    ph = np.where(below, phi[:, :1], np.where(above, phi[:, -1:], ph))
    aa = np.where(below, a[:, :1], np.where(above, a[:, -1:], aa))
    near = np.clip(count, 0, k - 1)                                               # the node at/above the level
    prev = np.clip(count - 1, 0, k - 1)
    pick = np.where(np.abs(np.take_along_axis(r, prev, axis=1) - levels[None, :])
                    < np.abs(np.take_along_axis(r, near, axis=1) - levels[None, :]), prev, near)
    return ph, aa, np.take_along_axis(s, pick, axis=1)


def _law_breaks(ix, lo: float, hi: float) -> Array:
    ts, beta = float(ix.index_start), float(ix.index_angle)
    m = np.arange(math.floor((lo - ts - beta) / TWO_PI), math.ceil((hi - ts) / TWO_PI) + 1)
    b = np.concatenate([ts + TWO_PI * m, ts + beta + TWO_PI * m])
    return np.sort(b[(b > lo) & (b < hi)])


def _outside(ix, side: int, tau: Array, t: Array, levels: Array) -> Array:
    """Whether each row τ (with its continuations) lies outside the band at every level."""
    r, phi, a, s = _lines(ix, side, tau, t, check=False)
    _, aa, _ = _at_levels(r, phi, a, s, levels)
    out = (np.abs(aa) > _a_max(ix, levels)[None, :]).all(axis=1)
    # rows whose r does not grow along t (far outside the band, where the rollers no longer meet the
    # rib): outside when every point is, and its ends' continuations at the levels beyond them are
    odd = ~(np.diff(r, axis=1) > 0).all(axis=1)
    points_out = (np.abs(a) > _a_max(ix, np.maximum(r, 0.5 * float(ix.cam_width) + 1e-9))).all(axis=1)
    return np.where(odd, points_out & out, out)


def _tau_range(design: SpatialDesign, side: int, t: Array) -> tuple[float, float]:
    """The flank's τ range widened until its end rows lie outside the band at every level."""
    ix = design.indexer
    lo, hi = flank_tau_range(design, side)
    r0, r1 = _radial_range(ix)
    check = np.linspace(r0, r1, 65)
    steps = WIDEN_STEP * np.arange(1, int(round(MAX_WIDEN / WIDEN_STEP)) + 1)
    ends = []
    for start, direction in ((lo, -1.0), (hi, 1.0)):
        out = _outside(ix, side, start + direction * steps, t, check)
        # the first row from which on (outwards) every row is outside
        inside = np.flatnonzero(~out)
        first = 0 if inside.size == 0 else int(inside[-1]) + 1
        if first >= steps.size:
            raise RibNotBounded(f"the side {side:+d} flank does not leave the band within "
                                f"{math.degrees(MAX_WIDEN):g}° of its τ range", False)
        ends.append(start + direction * steps[min(first + 2, steps.size - 1)])
    return ends[0], ends[1]


def _tau_nodes(ix, lo: float, hi: float, step: float) -> Array:
    """Uniform τ nodes over [lo, hi] with the law's ends added (nodes closer than step/4 to one dropped)."""
    n = max(int(math.ceil((hi - lo) / step)), 8)
    u = np.linspace(lo, hi, n + 1)
    b = _law_breaks(ix, lo, hi)
    if b.size:
        d = np.abs(u[:, None] - b[None, :]).min(axis=1)
        u = np.sort(np.concatenate([u[d >= 0.25 * (hi - lo) / n], b]))
    return u


def _hermite_slopes(x: Array, y: Array) -> Array:
    """Three-point slopes dy/dx at the nodes (axis 0), one-sided at the ends."""
    h = np.diff(x, axis=0)
    d = np.diff(y, axis=0) / h
    m = np.empty_like(y)
    m[1:-1] = (h[1:] * d[:-1] + h[:-1] * d[1:]) / (h[1:] + h[:-1])
    m[0], m[-1] = d[0], d[-1]
    return m


def _crossings(ph: Array, aa: Array, sg: Array, dphi: float) -> tuple[Array, Array, Array, Array]:
    """A side's crossings with the columns φ = (c + ½)·dφ (c any integer: every turn) at every level,
    enumerated per interval of the traces ph, aa, sg (R, N) (φ monotone along R): flat arrays of the
    level k, the column number c, a and s."""
    d = np.diff(ph, axis=0)
    inc = (d > 0).all(axis=0)
    dec = (d < 0).all(axis=0)
    if not (inc | dec).all():
        k = int(np.flatnonzero(~(inc | dec))[0])
        raise RibNotBounded(f"a flank's trace on the level {k} of r is not a graph over φ", True)
    ph = np.where(dec[None, :], ph[::-1], ph)           # increasing along the rows
    aa = np.where(dec[None, :], aa[::-1], aa)
    sg = np.where(dec[None, :], sg[::-1], sg)
    slope = _hermite_slopes(ph, aa)
    # the columns c_lo … c_hi with x_c = (c + ½)·dφ in [x_i, x_{i+1}) of each interval
    c_lo = np.ceil(ph[:-1] / dphi - 0.5).astype(np.int64)
    c_hi = np.ceil(ph[1:] / dphi - 0.5).astype(np.int64)
    count = (c_hi - c_lo).reshape(-1)
    total = int(count.sum())
    cell = np.repeat(np.arange(count.size), count)                      # flat (interval, level) index
    first = np.cumsum(count) - count
    c = c_lo.reshape(-1)[cell] + (np.arange(total) - first[cell])
    i, k = np.divmod(cell, ph.shape[1])
    x0, x1 = ph[i, k], ph[i + 1, k]
    h = x1 - x0
    u = ((c + 0.5) * dphi - x0) / h
    u2, u3 = u * u, u * u * u
    val = ((2 * u3 - 3 * u2 + 1) * aa[i, k] + (u3 - 2 * u2 + u) * h * slope[i, k]
           + (-2 * u3 + 3 * u2) * aa[i + 1, k] + (u3 - u2) * h * slope[i + 1, k])
    sign = np.where(u < 0.5, sg[i, k], sg[i + 1, k])
    return k, c, val, sign


def _rib(design: SpatialDesign, n_r: int, n_phi: int, ranges: dict[int, tuple[float, float]], t: Array) -> float:
    """The rib's volume [mm³] on the grid of n_r levels and n_phi columns (module docs)."""
    ix = design.indexer
    r0, r1 = _radial_range(ix)
    dphi = TWO_PI / n_phi
    levels = r0 + (np.arange(n_r) + 0.5) * (r1 - r0) / n_r
    step = dphi / TAU_PER_COLUMN
    parts = []
    for side in (1, -1):
        tau = _tau_nodes(ix, *ranges[side], step)
        r, phi, a, s = _lines(ix, side, tau, t)
        parts.append(_crossings(*_at_levels(r, phi, a, s, levels), dphi))
    k, c, a, s = (np.concatenate([p[m] for p in parts]) for m in range(4))
    a_max = _a_max(ix, levels)
    keep = np.abs(a) <= a_max[k]
    k, c, a, s = k[keep], c[keep], a[keep], s[keep]
    column = k * n_phi + np.mod(c, n_phi)                                            # the flat (level, φ) column
    order = np.lexsort((a, column))
    col_sorted, s_sorted = column[order], s[order]
    same = col_sorted[1:] == col_sorted[:-1]
    bad = same & ~(s_sorted[1:] * s_sorted[:-1] < 0)
    if bad.any():
        kk, jj = divmod(int(col_sorted[1:][bad][0]), n_phi)
        raise RibNotBounded(f"the flanks' crossings do not alternate (r = {levels[kk]:.6g} mm, "
                            f"φ = {math.degrees((jj + 0.5) * dphi):.4g}°)", True)
    lowest = np.concatenate([[True], ~same])
    count = np.bincount(column, minlength=n_r * n_phi)
    if (count == 0).any():
        kk, jj = divmod(int(np.flatnonzero(count == 0)[0]), n_phi)
        raise RibNotBounded(f"no flank crosses the column r = {levels[kk]:.6g} mm, "
                            f"φ = {math.degrees((jj + 0.5) * dphi):.4g}°", False)
    top = _primitive(ix, levels, a_max)
    full = top - _primitive(ix, levels, -a_max)
    # L = Σ s·(F(a_max) − F(a)) + [the lowest crossing ends the rib]·(F(a_max) − F(−a_max)), per column
    below = s_sorted[lowest] < 0
    length = (np.bincount(column, weights=s * (top[k] - _primitive(ix, levels[k], a)), minlength=n_r * n_phi).sum()
              + full[col_sorted[lowest][below] // n_phi].sum())
    return float(length * (r1 - r0) / n_r * dphi)


def cam_volume(design: SpatialDesign, bore_radius: float = 0.0, *, levels: int = LEVELS,
               columns: int = COLUMNS) -> VolumeEstimate:
    """The cam's volume (core + rib, less a bore of ``bore_radius`` mm) integrated on the exact
    envelope (module docs): the grid of ``levels`` × ``columns`` and the one twice as fine; the
    finer's value, the error estimated from the two.

    Raises:
        ValueError: ``bore_radius`` outside [0, the core's least radius); too coarse a grid.
        TypeError: not a barrel or globoidal design.
        RuntimeError: the flanks do not bound a rib the grid can read (a trace not a graph over φ,
            crossings that do not alternate, a flank that does not leave the band)."""
    ix = design.indexer
    if not isinstance(ix, (BarrelIndexer, GloboidalIndexer)):
        raise TypeError(f"a barrel or globoidal design is needed, got {type(ix).__name__}")
    rb = float(bore_radius)
    inner = float(ix.root_radius) if _is_barrel(ix) else float(ix.centre_distance) - float(ix.root_radius)
    if not (math.isfinite(rb) and 0.0 <= rb < inner):
        raise ValueError(f"bore_radius must be in [0, {inner:g}) mm (the core's least radius), got {bore_radius!r}")
    if not (int(levels) >= 4 and int(columns) >= 16):
        raise ValueError(f"the grid needs levels ≥ 4 and columns ≥ 16, got {levels!r} × {columns!r}")
    if not _is_barrel(ix) and not 0.5 * float(ix.cam_width) < float(ix.tip_radius):
        raise ValueError("the globoid's half width must be below its tip radius")
    t = np.linspace(float(ix.roller_start), float(ix.roller_end), T_NODES)
    ranges = {side: _tau_range(design, side, t) for side in (1, -1)}
    coarse = _rib(design, int(levels), int(columns), ranges, t)
    fine = _rib(design, 2 * int(levels), 2 * int(columns), ranges, t)
    core = core_volume(ix, rb)
    error = max(abs(fine - coarse), ERROR_FLOOR * abs(fine))
    what = (f"the core's closed form plus the rib integrated on the exact envelope ({2 * int(levels)} levels of r × "
            f"{2 * int(columns)} columns of φ; error: the difference from {int(levels)} × {int(columns)})")
    return VolumeEstimate(core + fine, core, fine, error, what)


__all__ = ["VolumeEstimate", "cam_volume", "core_volume"]

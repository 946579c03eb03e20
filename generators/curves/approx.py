"""Lines, circular arcs and cubic splines that stay within a tolerance of an exact NURBS curve:
what G-code (G01/G02/G03) and DXF readers that take no rational or high-degree splines need.

The fitters subdivide adaptively, all pieces of a level at once (vectorised):

* :func:`flatten` — a polyline (chords) whose distance from the curve is ≤ ``tol``;
* :func:`fit_biarcs` — tangent-continuous arc pairs (biarcs) with their end points
  and end tangents on the curve, distance ≤ ``tol``;
* :func:`fit_cubic` — a non-rational cubic B-spline (C¹, C² inside each knot span of the curve)
  through points of the curve, with the curve's own derivatives at its knots, within ``tol``.

The distance is measured at ``checks`` interior samples of every piece; fitting aims
at ``safety``·tol so the true maximum between samples stays inside ``tol``
(:func:`max_distance` measures it independently and densely).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .basis import basis_matrix, interpolating_cubic
from .nurbs import NurbsCurve


@dataclass(frozen=True)
class Path2D:
    """A chain of straight lines and circular arcs in the plane (complex coordinates).

    Attributes:
        start, end: (N,) complex end points of each element.
        center: (N,) complex arc centres; NaN for straight lines.
        ccw: (N,) bool, arc turning counter-clockwise (G03) or clockwise (G02).
        u0, u1: (N,) curve parameters of the element's ends (for reporting).
    """

    start: np.ndarray
    end: np.ndarray
    center: np.ndarray
    ccw: np.ndarray
    u0: np.ndarray
    u1: np.ndarray

    @property
    def n(self) -> int:
        return int(self.start.shape[0])

    @property
    def is_arc(self) -> np.ndarray:
        return ~np.isnan(self.center.real)

    @property
    def radius(self) -> np.ndarray:
        return np.where(self.is_arc, np.abs(self.start - self.center), np.inf)

    def sweep(self) -> np.ndarray:
        """Signed sweep angle of each arc [rad] (+ ccw), 0 for lines."""
        a0 = np.angle(self.start - self.center)
        a1 = np.angle(self.end - self.center)
        d = np.mod(a1 - a0, 2 * np.pi)
        sweep = np.where(self.ccw, d, d - 2 * np.pi)
        return np.where(self.is_arc, sweep, 0.0)

    def lengths(self) -> np.ndarray:
        return np.where(self.is_arc, np.abs(self.sweep()) * np.where(self.is_arc, self.radius, 0.0),
                        np.abs(self.end - self.start))

    @property
    def length(self) -> float:
        return float(np.sum(self.lengths()))

    def sample(self, per_element: int = 16) -> np.ndarray:
        """Points along the path, ``per_element`` per element (start included, end of the last)."""
        t = np.arange(per_element) / per_element
        arc = self.is_arc
        pts = np.empty((self.n, per_element), dtype=complex)
        line_pts = self.start[:, None] + (self.end - self.start)[:, None] * t[None, :]
        c = np.where(arc, self.center, 0)
        ang = np.angle(self.start - c)[:, None] + self.sweep()[:, None] * t[None, :]
        arc_pts = c[:, None] + np.where(arc, self.radius, 0)[:, None] * np.exp(1j * ang)
        pts[:] = np.where(arc[:, None], arc_pts, line_pts)
        return np.append(pts.ravel(), self.end[-1])


def _curve_points(curve: NurbsCurve, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    p, d = curve.evaluate_with_derivative(u)
    return p[:, 0] + 1j * p[:, 1], d[:, 0] + 1j * d[:, 1]


def _initial_breaks(curve: NurbsCurve) -> np.ndarray:
    return np.unique(curve.knots[curve.degree:-curve.degree])


def _point_segment_distance(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ab = b - a
    den = np.where(np.abs(ab) > 0, np.abs(ab) ** 2, 1.0)
    t = np.clip(((x - a) * np.conj(ab)).real / den, 0.0, 1.0)
    return np.abs(x - (a + t * ab))


def flatten(curve: NurbsCurve, tol: float, checks: int = 16, safety: float = 0.8,
            max_levels: int = 40) -> tuple[np.ndarray, np.ndarray]:
    """Polyline approximation: (parameters (K,), points (K,) complex), first = last point
    for a closed curve, every chord within ``tol`` of the curve."""
    if tol <= 0:
        raise ValueError("tol must be > 0")
    breaks = _initial_breaks(curve)
    a, b = breaks[:-1], breaks[1:]
    done_a, done_b = [], []
    frac = (np.arange(1, checks + 1) / (checks + 1))[None, :]
    for _ in range(max_levels):
        if a.size == 0:
            break
        u = a[:, None] + (b - a)[:, None] * frac
        pts, _ = _curve_points(curve, u.ravel())
        pa, _ = _curve_points(curve, a)
        pb, _ = _curve_points(curve, b)
        dist = _point_segment_distance(pts.reshape(u.shape), pa[:, None], pb[:, None]).max(axis=1)
        ok = dist <= safety * tol
        done_a.append(a[ok])
        done_b.append(b[ok])
        mid = 0.5 * (a[~ok] + b[~ok])
        a, b = np.concatenate([a[~ok], mid]), np.concatenate([mid, b[~ok]])
    else:
        raise RuntimeError("flatten did not reach the tolerance")
    starts = np.sort(np.concatenate(done_a))
    params = np.append(starts, breaks[-1])
    pts, _ = _curve_points(curve, params)
    return params, pts


@dataclass(frozen=True)
class _Arcs:
    center: np.ndarray
    ccw: np.ndarray


def _arc_through(p: np.ndarray, t: np.ndarray, q: np.ndarray) -> _Arcs:
    """Arc starting at p with unit tangent t and ending at q (NaN centre when straight)."""
    n = 1j * t
    chord = q - p
    den = 2.0 * (n * np.conj(chord)).real
    straight = np.abs(den) <= 1e-12 * np.abs(chord)
    s = np.abs(chord) ** 2 / np.where(straight, 1.0, den)
    center = np.where(straight, np.nan + 0j, p + s * n)
    return _Arcs(center, s > 0)


def _biarcs(p0: np.ndarray, t0: np.ndarray, p1: np.ndarray, t1: np.ndarray
            ) -> tuple[np.ndarray, _Arcs, _Arcs, np.ndarray]:
    """Equal-tangent-length biarcs (Ryan Juckett's construction): joint point and two arcs."""
    v = p1 - p0
    t = t0 + t1
    vt = (v * np.conj(t)).real
    vv = (v * np.conj(v)).real
    denom = 2.0 * (1.0 - (t0 * np.conj(t1)).real)
    parallel = np.abs(denom) < 1e-12
    vt1 = (v * np.conj(t1)).real
    d_par = vv / np.where(np.abs(vt1) > 0, 4 * vt1, 1.0)
    with np.errstate(invalid="ignore"):
        d_gen = (-vt + np.sqrt(vt * vt + denom * vv)) / np.where(parallel, 1.0, denom)
    d = np.where(parallel, d_par, d_gen)
    pm = 0.5 * (p0 + p1 + d * (t0 - t1))
    first = _arc_through(p0, t0, pm)
    back = _arc_through(p1, -t1, pm)           # built from the far end, then reversed
    second = _Arcs(back.center, ~back.ccw)
    return pm, first, second, d


def _distance_to_arc(x: np.ndarray, a: np.ndarray, b: np.ndarray, arc: _Arcs) -> np.ndarray:
    """Distance of points x (N, K) to the arc/line from a to b (N,)."""
    c = arc.center[:, None]
    is_arc = ~np.isnan(arc.center.real)[:, None]
    r = np.abs(a[:, None] - np.where(is_arc, c, 0))
    d_circle = np.abs(np.abs(x - np.where(is_arc, c, 0)) - r)
    d_line = _point_segment_distance(x, a[:, None], b[:, None])
    return np.where(is_arc, d_circle, d_line)


def fit_biarcs(curve: NurbsCurve, tol: float, checks: int = 16, safety: float = 0.8,
               max_levels: int = 40) -> Path2D:
    """Biarc approximation of ``curve`` within ``tol``: G¹ chain of arcs (lines where straight)."""
    if tol <= 0:
        raise ValueError("tol must be > 0")
    breaks = _initial_breaks(curve)
    a, b = breaks[:-1], breaks[1:]
    keep: list[tuple[np.ndarray, ...]] = []
    frac = (np.arange(1, checks + 1) / (checks + 1))[None, :]
    for _ in range(max_levels):
        if a.size == 0:
            break
        pa, da = _curve_points(curve, a)
        pb, db = _curve_points(curve, b)
        ta, tb = da / np.abs(da), db / np.abs(db)
        pm, arc1, arc2, d = _biarcs(pa, ta, pb, tb)
        u = a[:, None] + (b - a)[:, None] * frac
        x, _ = _curve_points(curve, u.ravel())
        x = x.reshape(u.shape)
        # which arc a sample belongs to: before or after the joint along the joint tangent
        tm = np.where(np.isnan(arc1.center.real), pm - pa, 1j * (pm - arc1.center) * np.where(arc1.ccw, 1, -1))
        tm = tm / np.where(np.abs(tm) > 0, np.abs(tm), 1.0)
        before = ((x - pm[:, None]) * np.conj(tm[:, None])).real <= 0
        dist = np.where(before, _distance_to_arc(x, pa, pm, arc1), _distance_to_arc(x, pm, pb, arc2))
        ok = (dist.max(axis=1) <= safety * tol) & np.isfinite(d) & (d > 0)
        if ok.any():
            keep.append((a[ok], b[ok], pa[ok], pm[ok], pb[ok], arc1.center[ok], arc1.ccw[ok],
                         arc2.center[ok], arc2.ccw[ok]))
        mid = 0.5 * (a[~ok] + b[~ok])
        a, b = np.concatenate([a[~ok], mid]), np.concatenate([mid, b[~ok]])
    else:
        raise RuntimeError("biarc fitting did not reach the tolerance")
    cols = [np.concatenate(c) for c in zip(*keep)]
    a, b, pa, pm, pb, c1, w1, c2, w2 = cols
    order = np.argsort(a)
    a, b, pa, pm, pb, c1, w1, c2, w2 = (v[order] for v in (a, b, pa, pm, pb, c1, w1, c2, w2))
    um = 0.5 * (a + b)
    start = np.column_stack([pa, pm]).ravel()
    end = np.column_stack([pm, pb]).ravel()
    center = np.column_stack([c1, c2]).ravel()
    ccw = np.column_stack([w1, w2]).ravel()
    u0 = np.column_stack([a, um]).ravel()
    u1 = np.column_stack([um, b]).ravel()
    return Path2D(start, end, center, ccw, u0, u1)


def fit_cubic(curve: NurbsCurve, tol: float, checks: int = 16, safety: float = 0.8,
              max_levels: int = 12) -> NurbsCurve:
    """Non-rational cubic B-spline within ``tol`` of ``curve``, in the curve's own parameter.

    On every knot span [a, b] of ``curve`` the cubic interpolates n + 1 equally spaced points
    of the curve with the curve's own first derivatives at a and b (the clamped cubic spline,
    error O(h⁴) for smooth spans); n is doubled on the spans where max |cubic(u) − curve(u)|
    at ``checks`` points per cubic span exceeds ``safety``·tol.  The spans meet at triple knots
    with equal derivatives on both sides (C¹; the exact curve's own continuity at a knot may be
    lower than C² — an offset's — which a global C² cubic could only follow at O(h²)).  A closed
    curve gives a closed cubic (first pole = last pole)."""
    if tol <= 0:
        raise ValueError("tol must be > 0")
    breaks = _initial_breaks(curve)
    a, b = breaks[:-1], breaks[1:]
    n_span = np.ones(a.size, dtype=int)
    chunks: list[tuple[int, np.ndarray, np.ndarray]] = []     # (n, spans, their poles (n+3, g, 2))
    todo = np.arange(a.size)
    for _ in range(max_levels):
        if todo.size == 0:
            break
        failed = []
        for n in np.unique(n_span[todo]):
            g = todo[n_span[todo] == n]
            t = np.linspace(0.0, 1.0, n + 1)[:, None]
            u = a[g] * (1 - t) + b[g] * t                       # (n+1, g): exact ends a, b
            p, d = curve.evaluate_with_derivative(u.ravel())
            p = p.reshape(n + 1, g.size, 2)
            d = d.reshape(n + 1, g.size, 2) * (b[g] - a[g])[None, :, None]   # d/dt on [0, 1]
            knots, c = interpolating_cubic(t[:, 0], p, d[0], d[-1])
            c[0], c[-1] = p[0], p[-1]                             # the end points, to the last bit
            fr = np.linspace(0.0, 1.0, checks * n + 1)[:, None]
            fit = np.einsum("ij,j...->i...", basis_matrix(knots, 3, n + 3, fr[:, 0]), c)
            err = np.hypot(*np.moveaxis(fit - curve.evaluate((a[g] * (1 - fr) + b[g] * fr).ravel())
                                        .reshape(fr.size, g.size, 2), -1, 0)).max(axis=0)
            ok = err <= safety * tol
            chunks.append((int(n), g[ok], c[:, ok]))
            failed.append(g[~ok])
        todo = np.concatenate(failed) if failed else np.array([], dtype=int)
        n_span[todo] *= 2
    else:
        raise RuntimeError("cubic fitting did not reach the tolerance")
    # assemble: span s gives its poles but the last (the next span's first) and the knots
    # [its interior knots, b, b, b]; the curve's end adds the last pole and a fourth b
    size = n_span + 2
    start = np.concatenate([[0], np.cumsum(size)[:-1]])
    poles = np.empty((int(size.sum()) + 1, 2))
    knots = np.empty(int(size.sum()) + 1)
    for n, g, c in chunks:
        idx = start[g][None, :] + np.arange(n + 2)[:, None]
        poles[idx] = c[:n + 2]
        t = np.concatenate([np.linspace(0.0, 1.0, n + 1)[1:-1], [1.0, 1.0, 1.0]])[:, None]
        knots[idx] = a[g] * (1 - t) + b[g] * t
    poles[-1] = poles[0] if curve.is_closed else curve.evaluate(b[-1:])[0]
    knots[-1] = b[-1]
    knots = np.concatenate([np.full(4, a[0]), knots])
    return NurbsCurve(3, knots, poles, np.ones(len(poles)))


def curve_distance(fit: NurbsCurve, curve: NurbsCurve, samples_per_span: int = 400) -> float:
    """Two-sided distance of ``fit`` (a curve in the same parameter, e.g. :func:`fit_cubic`'s)
    from ``curve``: both sampled at the same dense parameters, each checked against the other's
    polyline (:func:`polyline_curve_distance`)."""
    u, _ = curve.sample(samples_per_span)
    p = fit.evaluate(u)
    return polyline_curve_distance(p[:, 0] + 1j * p[:, 1], curve, samples_per_span)


def polyline_path(params: np.ndarray, pts: np.ndarray) -> Path2D:
    """A :class:`Path2D` of straight lines through ``pts``."""
    n = len(pts) - 1
    return Path2D(pts[:-1], pts[1:], np.full(n, np.nan + 0j), np.zeros(n, bool), params[:-1], params[1:])


#: the most vertices a grid cell of :func:`nearest_vertex` may hold before the k-d tree is used
_CELL_CAP = 48


def nearest_vertex(x: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Index of the vertex of ``poly`` nearest to each point of ``x`` (complex arrays).

    A uniform grid of cells as wide as the longest edge: the nearest vertex of a point within
    that width of the polyline lies in its cell or the eight around it, so each point compares
    only those cells' vertices (vectorised over the points, one pass per neighbour cell and slot).
    Points with no vertex that near, and polylines whose cells crowd (very uneven spacing), are
    answered by a k-d tree instead (SciPy's, loaded only then)."""
    xy = np.column_stack([poly.real, poly.imag])
    edge = float(np.max(np.abs(np.diff(poly)))) if len(poly) > 1 else 1.0
    h = edge if edge > 0 else 1.0
    lo = xy.min(axis=0)
    cells = np.floor((xy - lo) / h).astype(np.int64)
    width = int(cells[:, 1].max()) + 3
    key = (cells[:, 0] + 1) * width + (cells[:, 1] + 1)
    order = np.argsort(key, kind="stable")
    keys, first, count = np.unique(key[order], return_index=True, return_counts=True)
    if count.max() > _CELL_CAP:
        return _kd_nearest(x, xy)
    qx = np.floor((np.column_stack([x.real, x.imag]) - lo) / h).astype(np.int64)
    best = np.full(len(x), np.inf)
    idx = np.full(len(x), -1)
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            k = (qx[:, 0] + 1 + dx) * width + (qx[:, 1] + 1 + dy)
            at = np.searchsorted(keys, k)
            hit = (at < len(keys)) & (keys[np.minimum(at, len(keys) - 1)] == k)
            at = np.minimum(at, len(keys) - 1)
            for slot in range(int(count.max())):
                ok = hit & (slot < count[at])
                v = order[np.where(ok, first[at] + slot, 0)]
                d = np.where(ok, np.abs(x - poly[v]), np.inf)
                better = d < best
                best = np.where(better, d, best)
                idx = np.where(better, v, idx)
    far = ~(best <= h)                 # nothing in the 3 × 3 cells this near: not certainly the nearest
    if far.any():
        idx[far] = _kd_nearest(x[far], xy)
    return idx


def _kd_nearest(x: np.ndarray, xy: np.ndarray) -> np.ndarray:
    from scipy.spatial import cKDTree  # deferred: scipy.spatial, far points and crowded grids alone

    return cKDTree(xy).query(np.column_stack([x.real, x.imag]))[1]


def _distance_to_polyline(x: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Distance of points x to a dense polyline: the nearest vertex (:func:`nearest_vertex`),
    then the two adjacent segments (error ~h²κ/8 for vertex spacing h).  A closed polyline (last
    vertex = first) wraps round, so points near the seam see the segments on both sides of it."""
    closed = len(poly) > 2 and abs(poly[-1] - poly[0]) <= 1e-12 * np.max(np.abs(poly))
    if closed:
        poly = poly[:-1]
    n = len(poly)
    k = nearest_vertex(x, poly)
    if closed:
        lo, hi = (k - 1) % n, (k + 1) % n
    else:
        lo, hi = np.clip(k - 1, 0, n - 1), np.clip(k + 1, 0, n - 1)
    d1 = _point_segment_distance(x, poly[lo], poly[k])
    d2 = _point_segment_distance(x, poly[k], poly[hi])
    return np.minimum(d1, d2)


def max_distance(path: Path2D, curve: NurbsCurve, samples_per_span: int = 400) -> float:
    """Two-sided check of an approximation: the larger of the max distance from dense path
    samples to the curve and from dense curve samples to the path (each against a dense
    polyline of the other, which is exact to ~1e-9 at these densities)."""
    _, cpts = curve.sample(samples_per_span)
    c = cpts[:, 0] + 1j * cpts[:, 1]
    n_spans = len(_initial_breaks(curve)) - 1
    ppts = path.sample(max(16, samples_per_span * n_spans // max(path.n, 1)))
    return float(max(_distance_to_polyline(ppts, c).max(), _distance_to_polyline(c, ppts).max()))


def polyline_curve_distance(points: np.ndarray, curve: NurbsCurve, samples_per_span: int = 400) -> float:
    """Two-sided check of a dense polyline (complex points in order) against a curve: the
    larger of the max distance from the points to the curve and from dense curve samples
    to the polyline (for paths that are neither lines nor arcs, e.g. X–C blocks seen in
    the cam frame)."""
    _, cpts = curve.sample(samples_per_span)
    c = cpts[:, 0] + 1j * cpts[:, 1]
    return float(max(_distance_to_polyline(points, c).max(), _distance_to_polyline(c, points).max()))

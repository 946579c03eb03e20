"""Figures of the SPATIAL indexers (barrel and globoidal) as :class:`~.chart.Chart` s: the cam's rib,
its root body, the turret and its rollers in the fixed frame at an input angle, seen in an
orthographic projection computed here (:func:`spatial_picture`), and the turret's motion with the
driving pressure angle over the input turn (:func:`spatial_motion_chart`).

Frames and signs are those of :mod:`cam_workbench.generators.bodies.indexing.spatial`: the cam axis
is z through O, the turret axis the line through P = (C, 0, 0) along +y; a cam-frame point q is at
Rz(θ)·q in the fixed frame.  Lengths in mm, angles in the notes and on the axes in degrees.

The view (:func:`view_basis`, :func:`project`): the screen's up is the fixed frame's +y (the turret
axis, vertical as on a dial table).  ``view = (azimuth, elevation)`` [deg] is the direction from the
scene to the viewer: the azimuth is measured in the x–z plane from +z (the cam axis) towards +x
(towards the turret axis), the elevation from that plane towards +y.  With a = azimuth, e = elevation:

* towards the viewer  v = (cos e·sin a, sin e, cos e·cos a) (a point's depth is p·v, larger nearer);
* screen right        r = (cos a, 0, −sin a);
* screen up           u = v × r = (−sin e·sin a, cos e, −sin e·cos a);

and a fixed-frame point p is drawn at (p·r, p·u).  At (0, 0) the viewer is on +z: x right, y up.

The solids (the rib's two flanks, the root body, the rollers) are filled quads drawn back to front
(a painter's algorithm on the quads' mean depth; the closed bodies' back faces culled, the rib's
flanks two-sided, their backs darker), shaded by a light from the viewer's upper left.  Outlines,
axes and contact lines are drawn over them.

The rollers (:func:`roller_mesh`): the surface of revolution of radius r(t) = r_r + (t − t_m)·tan γ
(``ix.radius_at``, γ = ``roller_cone_angle``, t_m = (t0 + t1)/2) about the axis c(t) = a + t·d for
t ∈ [t0, t1] — a cylinder of radius r_r for γ = 0, else a cone — closed by its end discs; the mantle's
outward normal is n − tan γ·d (n the radial unit vector).  Its silhouette lines are the generators
where that normal is square to the view direction v: n = ±√(1 − s²)·e1 + s·e2 with s = tan γ·(d·v)/(e2·v),
e1 = d × v/|d × v|, e2 = d × e1 (±e1 for a cylinder); none where |s| > 1 (a cone seen along its axis,
one end circle round the other).

SVG ids (a mark's ``gid``): ``rib-p-<r0>-<r1>-<k>`` / ``rib-m-<r0>-<r1>-<k>`` the quad of the side +1
/ side −1 flank sheet between its rows r0 < r1 and columns k, k + 1, corners (r0, k), (r1, k),
(r1, k + 1), (r0, k + 1) (every corner in the rib's band); ``root-outline`` the root body's end
circles and silhouette; ``roller-<j>-t0`` / ``roller-<j>-t1`` the end circles (about c(t0), c(t1),
radii r(t0), r(t1); 96 points, closed) and ``roller-<j>-sides`` the two silhouette lines of roller j
(j as in ``design.rollers``; :func:`roller_silhouettes`); ``engaged-<j>-p`` / ``engaged-<j>-m`` the
in-band contact line of roller j's side +1 / −1, present when that side touches the rib at θ;
``turret-pitch-circle`` (barrel: the rollers' circle at their ends' height t1) or ``turret-hub``
(globoid: the circle of radius t0 about P in y = 0); ``cam-axis``, ``turret-axis``; ``turret-angle``
(the note); ``psi``, ``dpsi``, ``d2psi``, ``driving-angle`` the motion chart's curves.
"""
from __future__ import annotations

import math

import numpy as np

from cam_workbench.generators.bodies.indexing.spatial import (TWO_PI, BarrelIndexer, SpatialDesign, contact_lines,
                                                             roller_axis, turret_angle)
from cam_workbench.generators.bodies.indexing.spatial_kind import SpatialIndexerDesign

from .chart import Area, Chart, Curve, Mark, Note, Panel, Shade, angle_panel, css_color
from .plots import PICTURES
from .plots_indexer import CAM_EDGES

#: default views (azimuth, elevation) [deg]: the barrel from the front and above (rollers coming down
#: into the rib), the globoid from above between the cam and the turret
BARREL_VIEW = (-72.0, 38.0)
GLOBOIDAL_VIEW = (52.0, 40.0)

#: base colours (RGB 0–1): the flank of side +1 (holds), of side −1 (drives), the root, rollers
_RIB_HOLD = np.array([0.62, 0.71, 0.84])
_RIB_DRIVE = np.array([0.55, 0.76, 0.70])
_RIB_TOP = np.array([0.72, 0.78, 0.86])
_ROOT = np.array([0.66, 0.68, 0.72])
_ROLLER = np.array([0.84, 0.84, 0.84])
_ROLLER_ENGAGED = np.array([0.93, 0.72, 0.33])
_ENGAGED_EDGE = "#a05a00"
_CONTACT = "#c0392b"
_LINE = "#1f3b5c"
#: the drawn τ rows are at most this far apart [rad]
_ROW_STEP = math.radians(2.0)
_RING = 96
#: the longest piece [mm] of the rib's top and the root body along the cam axis
_TOP_PIECE = 3.0


# ---------------------------------------------------------------------------------------------
# the view

def view_basis(view: tuple[float, float]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Screen right r, screen up u and the direction towards the viewer v (unit vectors, fixed frame)
    of ``view`` = (azimuth, elevation) [deg] (module docs: up is +y, azimuth from +z towards +x)."""
    a, e = math.radians(view[0]), math.radians(view[1])
    v = np.array([math.cos(e) * math.sin(a), math.sin(e), math.cos(e) * math.cos(a)])
    r = np.array([math.cos(a), 0.0, -math.sin(a)])
    return r, np.cross(v, r), v


def project(points: np.ndarray, view: tuple[float, float]) -> np.ndarray:
    """Orthographic projection of fixed-frame points (..., 3) [mm]: their screen points (..., 2) [mm]."""
    r, u, _ = view_basis(view)
    p = np.asarray(points, dtype=float)
    return np.stack([p @ r, p @ u], axis=-1)


def default_view(design: SpatialDesign) -> tuple[float, float]:
    """The default (azimuth, elevation) [deg] for the design's type."""
    return BARREL_VIEW if isinstance(design.indexer, BarrelIndexer) else GLOBOIDAL_VIEW


def turned(theta: float, q: np.ndarray) -> np.ndarray:
    """Cam-frame points or vectors (..., 3) in the fixed frame at input angle ``theta`` [rad]: Rz(θ)·q."""
    c, s = math.cos(theta), math.sin(theta)
    return np.stack([c * q[..., 0] - s * q[..., 1], s * q[..., 0] + c * q[..., 1], q[..., 2]], axis=-1)


def engaged_sides(design: SpatialDesign, theta: float) -> np.ndarray:
    """(J, 2) bool: roller ``design.rollers[i]``'s side (+1, −1) touches the rib at input angle
    ``theta`` [rad] — some point of its contact line (at the design's t) lies in the band."""
    ix = design.indexer
    out = np.zeros((design.rollers.size, 2), dtype=bool)
    for si, side in enumerate((1, -1)):
        cl = contact_lines(ix, design.rollers, float(theta), design.t, side)
        out[:, si] = ix.in_band(cl.points).any(axis=1)
    return out


# ---------------------------------------------------------------------------------------------
# faces

class _Faces:
    """Quads (F, 4, 3) in the fixed frame with outward normals (F, 3), base colours (F, 3), a kind
    (an index into the legend's labels), whether to cull them when they face away, and ids."""

    def __init__(self) -> None:
        self.parts: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, list]] = []

    def add(self, quads: np.ndarray, normals: np.ndarray, color: np.ndarray, kind: int, cull: bool,
            gids: list | None = None) -> None:
        f = quads.shape[0]
        if f == 0:
            return
        self.parts.append((quads, normals, np.broadcast_to(color, (f, 3)), np.full(f, kind),
                           np.full(f, cull), gids if gids is not None else [None] * f))

    def marks(self, view: tuple[float, float], labels: list[str], edges: dict[int, float]) -> list[Mark]:
        """The quads as filled :class:`Area` s, back to front (module docs)."""
        quads = np.concatenate([p[0] for p in self.parts])
        nrm = np.concatenate([p[1] for p in self.parts])
        base = np.concatenate([p[2] for p in self.parts])
        kind = np.concatenate([p[3] for p in self.parts])
        cull = np.concatenate([p[4] for p in self.parts])
        gids = [g for p in self.parts for g in p[5]]
        r, u, v = view_basis(view)
        light = -0.45 * r + 0.7 * u + 0.55 * v
        light /= np.linalg.norm(light)
        with np.errstate(invalid="ignore", divide="ignore"):
            n = nrm / np.linalg.norm(nrm, axis=-1, keepdims=True)
        n = np.nan_to_num(n)
        facing = n @ v
        keep = ~(cull & (facing < 0))
        front = facing >= 0
        lam = np.clip(np.where(front, 1.0, -1.0) * (n @ light), 0.0, 1.0)
        inten = np.round((0.55 + 0.45 * lam) * np.where(front, 1.0, 0.8) * 14.0) / 14.0
        depth = quads @ v
        order = np.argsort(depth.mean(axis=1)[keep], kind="stable")
        idx = np.nonzero(keep)[0][order]
        xy = project(quads[idx], view)
        rgb = np.clip(base[idx] * inten[idx, None], 0.0, 1.0)
        fill = [f"#{a:02x}{b:02x}{c:02x}" for a, b, c in np.round(rgb * 255).astype(int).tolist()]
        dark = {k: 0.82 if k in edges else 1.0 for k in np.unique(kind)}
        edge_rgb = np.clip(rgb * np.array([dark[k] for k in kind[idx]])[:, None], 0.0, 1.0)
        edge = [f"#{a:02x}{b:02x}{c:02x}" for a, b, c in np.round(edge_rgb * 255).astype(int).tolist()]
        widths = [edges.get(int(k), 0.8) for k in kind[idx]]
        seen: set[int] = set()
        out: list[Mark] = []
        for i, f in enumerate(idx.tolist()):
            k = int(kind[f])
            label = labels[k] if k not in seen and labels[k] else None
            seen.add(k)
            out.append(Area([xy[i]], fill=fill[i], edge=edge[i], width=widths[i], label=label, gid=gids[f]))
        return out


def _grid_quads(p: np.ndarray) -> np.ndarray:
    """The quads (…, 4, 3) of a grid of points (A, B, 3): corners (a, b), (a+1, b), (a+1, b+1), (a, b+1)."""
    return np.stack([p[:-1, :-1], p[1:, :-1], p[1:, 1:], p[:-1, 1:]], axis=-2)


def _revolution(radius, slope, z0: float, z1: float, nz: int, nphi: int = 72) -> tuple[np.ndarray, np.ndarray]:
    """A surface of revolution about z, ρ = radius(z) for z in [z0, z1], closed by its end discs: the
    quads (F, 4, 3) and outward normals (F, 3) (the ends as wedges, a repeated corner)."""
    phi = np.linspace(0.0, TWO_PI, nphi + 1)
    z = np.linspace(z0, z1, nz + 1)
    rho = radius(z)
    pts = np.stack(np.broadcast_arrays(rho[:, None] * np.cos(phi), rho[:, None] * np.sin(phi), z[:, None]), axis=-1)
    quads = _grid_quads(pts).reshape(-1, 4, 3)
    zm, pm = 0.5 * (z[:-1] + z[1:]), 0.5 * (phi[:-1] + phi[1:])
    nm = np.stack(np.broadcast_arrays(np.cos(pm)[None, :], np.sin(pm)[None, :], -slope(zm)[:, None]), axis=-1)
    caps, cap_n = [], []
    for zz, ring, sgn in ((z0, pts[0], -1.0), (z1, pts[-1], 1.0)):
        centre = np.broadcast_to(np.array([0.0, 0.0, zz]), (nphi, 3))
        caps.append(np.stack([centre, ring[:-1], ring[1:], ring[1:]], axis=1))
        cap_n.append(np.broadcast_to(np.array([0.0, 0.0, sgn]), (nphi, 3)))
    return np.concatenate([quads, *caps]), np.concatenate([nm.reshape(-1, 3), *cap_n])


def _root_shape(design: SpatialDesign):
    """The root body's radius ρ(z) and dρ/dz [mm, –] about the cam axis."""
    ix = design.indexer
    if isinstance(ix, BarrelIndexer):
        r0 = float(ix.root_radius)
        return (lambda z: np.full_like(np.asarray(z, dtype=float), r0)), (lambda z: np.zeros_like(z))
    c, rg = float(ix.centre_distance), float(ix.root_radius)
    return (lambda z: c - np.sqrt(rg**2 - np.asarray(z) ** 2)), (lambda z: np.asarray(z) / np.sqrt(rg**2 - z**2))


def _root_outline(design: SpatialDesign, view: tuple[float, float]) -> np.ndarray:
    """The root body's visible end circle(s) and silhouette curves (NaN-separated, fixed frame)."""
    radius, slope = _root_shape(design)
    half = 0.5 * float(design.indexer.cam_width)
    _, _, v = view_basis(view)
    phi = np.linspace(0.0, TWO_PI, 181)
    nan = np.full((1, 3), np.nan)
    parts = []
    for zz, sgn in ((-half, -1.0), (half, 1.0)):
        ring = np.column_stack([radius(zz) * np.cos(phi), radius(zz) * np.sin(phi), np.full_like(phi, zz)])
        seen = (np.cos(phi) * v[0] + np.sin(phi) * v[1] - slope(np.full_like(phi, zz)) * v[2] >= 0) | (sgn * v[2] > 0)
        parts += [np.where(seen[:, None], ring, np.nan), nan]
    z = np.linspace(-half, half, 121)
    amp = math.hypot(v[0], v[1])
    if amp > 1e-9:
        with np.errstate(invalid="ignore"):
            spread = np.arccos(slope(z) * v[2] / amp)          # NaN where the silhouette leaves the body
        phi0 = math.atan2(v[1], v[0])
        for sgn in (1.0, -1.0):
            ph = phi0 + sgn * spread
            parts += [np.column_stack([radius(z) * np.cos(ph), radius(z) * np.sin(ph), z]), nan]
    return np.concatenate(parts)


def _band_margin(ix, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The band's margin at cam-frame points ``q`` (..., 3) [mm] (≥ 0 inside, the band of the
    module docs of spatial.py) and the margin to the rib's top alone (barrel: the outer cylinder,
    globoid: the tip globoid)."""
    rho = np.hypot(q[..., 0], q[..., 1])
    ends = 0.5 * float(ix.cam_width) - np.abs(q[..., 2])
    if isinstance(ix, BarrelIndexer):
        top = float(ix.outer_radius) - rho
        return np.minimum(np.minimum(rho - float(ix.root_radius), top), ends), top
    c = float(ix.centre_distance)
    g = np.hypot(c - rho, q[..., 2])
    top = g - float(ix.tip_radius)
    return np.minimum(np.minimum(np.minimum(float(ix.root_radius) - g, top), ends), c - rho), top


def _clamped(points: np.ndarray, band: np.ndarray, margin: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                                              np.ndarray]:
    """Each row's (R, K, 3) points with those outside its band interval moved onto the band's edge
    (interpolated where the margin is 0); the first and last in-band columns (R,) (−1 for a row
    without band) and each row's two edge points (R, 2, 3) (NaN where the band reaches the row's end)."""
    rows, kt = band.shape
    has = band.any(axis=1)
    ka = np.where(has, np.argmax(band, axis=1), -1)
    kb = np.where(has, kt - 1 - np.argmax(band[:, ::-1], axis=1), -1)
    r = np.arange(rows)
    edges = np.full((rows, 2, 3), np.nan)
    out = points.copy()
    k = np.arange(kt)[None, :]
    for e, (kin, kout) in enumerate(((ka, ka - 1), (kb, kb + 1))):
        ok = has & (kout >= 0) & (kout < kt)
        ki, ko = kin[ok], kout[ok]
        m_in, m_out = margin[r[ok], ki], margin[r[ok], ko]
        s = np.clip(m_in / (m_in - m_out), 0.0, 1.0)[:, None]
        edges[r[ok], e] = points[r[ok], ki] + s * (points[r[ok], ko] - points[r[ok], ki])
        beyond = (k < ka[:, None]) if e == 0 else (k > kb[:, None])
        fill = np.where(np.isfinite(edges[:, e]), edges[:, e], points[r, np.maximum(kin, 0)])
        out = np.where((beyond & has[:, None])[..., None], fill[:, None, :], out)
    return out, ka, kb, edges


def _rib_faces(design: SpatialDesign, theta: float, faces: _Faces) -> list[tuple[np.ndarray, np.ndarray]]:
    """The flank sheets' quads on rows at most :data:`_ROW_STEP` apart, turned by θ: the quads with
    every corner in the band (with ids), and the strips out to the band's edge (interpolated); returns
    each sheet's top edge (cam frame, on every row; NaN off it) with the normals n there."""
    ix = design.indexer
    n_rows = design.sheets[0].tau.size
    step = float(np.max(np.diff(design.theta)))
    stride = max(1, int(_ROW_STEP // step))
    rows = np.unique(np.r_[np.arange(0, n_rows, stride), n_rows - 1])
    kk = np.arange(design.t.size - 1)
    tops = []
    for sheet, color, kind, tag in ((design.sheets[0], _RIB_HOLD, 0, "p"), (design.sheets[1], _RIB_DRIVE, 1, "m")):
        margin, top = _band_margin(ix, sheet.points)
        clamped, ka, kb, edges = _clamped(sheet.points, sheet.in_band, margin)
        # the top edge: the edge point whose active constraint is the rib's top
        m_e, top_e = _band_margin(ix, edges)          # 0 up to the chord's error at an edge point
        at_top = np.isfinite(top_e) & (top_e - m_e < 1e-3) & (np.abs(top_e) < 0.05)
        which = np.argmax(at_top, axis=1)
        any_top = at_top.any(axis=1)
        r_all = np.arange(n_rows)
        e_pts = np.where(any_top[:, None], edges[r_all, which], np.nan)
        k_near = np.where(which == 0, ka, kb)
        e_nrm = np.where(any_top[:, None], sheet.normals[r_all, np.maximum(k_near, 0)], np.nan)
        tops.append((e_pts, e_nrm))
        pts = turned(theta, clamped[rows])
        nrm = turned(theta, -sheet.normals[rows])               # the flank's outward normal −n
        band = sheet.in_band[rows]
        full = band[:-1, :-1] & band[1:, :-1] & band[:-1, 1:] & band[1:, 1:]
        a_lo, a_hi, b_lo, b_hi = ka[rows][:-1], kb[rows][:-1], ka[rows][1:], kb[rows][1:]
        both = (a_lo >= 0) & (b_lo >= 0)
        cell = kk[None, :]
        touches = ((cell >= a_lo[:, None] - 1) & (cell <= a_hi[:, None])) | \
                  ((cell >= b_lo[:, None] - 1) & (cell <= b_hi[:, None]))
        strip = both[:, None] & touches & ~full
        for mask, with_id in ((full, True), (strip, False)):
            ri, ki = np.nonzero(mask)
            quads = _grid_quads(pts)[ri, ki]
            normals = _grid_quads(nrm)[ri, ki].mean(axis=1)
            gids = ([f"rib-{tag}-{a}-{b}-{c}" for a, b, c in
                     zip(rows[ri].tolist(), rows[ri + 1].tolist(), kk[ki].tolist())] if with_id else None)
            faces.add(quads, normals, color, kind, False, gids)
    return tops


def _top_land(design: SpatialDesign, theta: float, tops: list[tuple[np.ndarray, np.ndarray]], faces: _Faces,
              columns: int = 240) -> None:
    """The rib's top (barrel: the outer cylinder, globoid: the tip globoid) between its flanks' top
    edges, as quads on ``columns`` meridians of the cam: at each meridian the edges' crossings, sorted
    along z, bound the rib where the roller normal n (which points into the rib) says so."""
    ix = design.indexer
    half = 0.5 * float(ix.cam_width)
    if isinstance(ix, BarrelIndexer):
        ro = float(ix.outer_radius)
        radius, slope = (lambda z: np.full_like(z, ro)), (lambda z: np.zeros_like(z))
    else:
        c, rt = float(ix.centre_distance), float(ix.tip_radius)
        radius, slope = (lambda z: c - np.sqrt(rt**2 - z**2)), (lambda z: z / np.sqrt(rt**2 - z**2))
    width = TWO_PI / columns
    col, zs, nzs = [], [], []
    for pts, nrm in tops:
        pa, pb, na, nb = pts[:-1], pts[1:], nrm[:-1], nrm[1:]
        ok = np.isfinite(pa[:, 0]) & np.isfinite(pb[:, 0])
        pa, pb, na, nb = pa[ok], pb[ok], na[ok], nb[ok]
        ua = np.arctan2(pa[:, 1], pa[:, 0]) / width - 0.5
        du = (np.arctan2(pb[:, 1], pb[:, 0]) / width - 0.5 - ua + columns / 2) % columns - columns / 2
        lo, hi = np.floor(np.minimum(ua, ua + du)) + 1, np.floor(np.maximum(ua, ua + du))
        for extra in range(3):                                    # a segment crosses at most a few meridians
            c_at = lo + extra
            hit = c_at <= hi
            s = (c_at[hit] - ua[hit]) / du[hit]
            col.append(c_at[hit].astype(int) % columns)
            zs.append(pa[hit, 2] + s * (pb[hit, 2] - pa[hit, 2]))
            nzs.append(na[hit, 2] + s * (nb[hit, 2] - na[hit, 2]))
    col, zs, nzs = np.concatenate(col), np.concatenate(zs), np.concatenate(nzs)
    order = np.lexsort((zs, col))
    col, zs, nzs = col[order], zs[order], nzs[order]
    same = col[:-1] == col[1:]
    inner = same & (nzs[:-1] > 0) & (nzs[1:] < 0)
    first = np.r_[True, ~same]
    last = np.r_[~same, True]
    c_run = np.concatenate([col[:-1][inner], col[first & (nzs < 0)], col[last & (nzs > 0)]])
    z_lo = np.concatenate([zs[:-1][inner], np.full(int((first & (nzs < 0)).sum()), -half), zs[last & (nzs > 0)]])
    z_hi = np.concatenate([zs[1:][inner], zs[first & (nzs < 0)], np.full(int((last & (nzs > 0)).sum()), half)])
    # the rib's end faces: the columns whose run reaches an end of the cam, from the root to the top
    root_radius, _ = _root_shape(design)
    for at_end, zz_end, sgn in ((z_lo <= -half, -half, -1.0), (z_hi >= half, half, 1.0)):
        c_end = c_run[at_end]
        ph = np.stack([c_end, c_end + 1, c_end + 1, c_end], axis=1) * width
        rr = np.array([float(root_radius(np.array(zz_end))), float(radius(np.array(zz_end)))])[[0, 0, 1, 1]]
        ends = np.stack(np.broadcast_arrays(rr * np.cos(ph), rr * np.sin(ph), zz_end), axis=-1)
        faces.add(turned(theta, ends), np.broadcast_to(np.array([0.0, 0.0, sgn]), (c_end.size, 3)), _RIB_TOP, 5,
                  True)
    # pieces at most _TOP_PIECE long along z, so that the painter's depths stay local
    pieces = np.maximum(np.ceil((z_hi - z_lo) / _TOP_PIECE), 1).astype(int)
    run = np.repeat(np.arange(c_run.size), pieces)
    part = np.arange(run.size) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    dz = (z_hi - z_lo)[run] / pieces[run]
    z_lo, z_hi, c_run = z_lo[run] + part * dz, z_lo[run] + (part + 1) * dz, c_run[run]
    phi0, phi1 = c_run * width, (c_run + 1) * width
    zz = np.stack([z_lo, z_lo, z_hi, z_hi], axis=1)
    ph = np.stack([phi0, phi1, phi1, phi0], axis=1)
    rho = radius(zz)
    quads = turned(theta, np.stack([rho * np.cos(ph), rho * np.sin(ph), zz], axis=-1))
    pm, zm = 0.5 * (phi0 + phi1), 0.5 * (z_lo + z_hi)
    normals = turned(theta, np.stack([np.cos(pm), np.sin(pm), -slope(zm)], axis=-1))
    faces.add(quads, normals, _RIB_TOP, 5, True)


def _frame(d: np.ndarray, view: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors square to the unit vectors ``d`` (J, 3), the first square to the view too."""
    _, _, v = view_basis(view)
    e1 = np.cross(d, v)
    small = np.linalg.norm(e1, axis=-1) < 1e-9
    e1[small] = np.cross(d[small], np.array([1.0, 0.0, 0.0]))
    e1 /= np.linalg.norm(e1, axis=-1, keepdims=True)
    return e1, np.cross(d, e1)


def roller_mesh(ix, a: np.ndarray, d: np.ndarray, view: tuple[float, float], rings: int = 3, meridians: int = 24
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The rollers' surfaces of revolution (module docs: radius r(t), a cone for γ ≠ 0) about the axes
    a + t·d (``a``, ``d`` (J, 3), fixed frame): the axis parameters t (T,) = ``rings`` values over
    [t0, t1] [mm], the grid points (J, T, P, 3) on ``meridians`` + 1 angles φ from the view's e1
    (the first and last the same) and the quads' outward normals (J, P − 1, 3) (n − tan γ·d at the
    middle angles; unnormalised)."""
    t = np.linspace(float(ix.roller_start), float(ix.roller_end), rings)
    radius = np.asarray(ix.radius_at(t), dtype=float)
    e1, e2 = _frame(d, view)
    phi = np.linspace(0.0, TWO_PI, meridians + 1)
    radial = np.cos(phi)[None, :, None] * e1[:, None, :] + np.sin(phi)[None, :, None] * e2[:, None, :]  # (J, P, 3)
    axis_pts = a[:, None, :] + t[None, :, None] * d[:, None, :]                                         # (J, T, 3)
    pts = axis_pts[:, :, None, :] + radius[None, :, None, None] * radial[:, None, :, :]                 # (J, T, P, 3)
    pm = 0.5 * (phi[:-1] + phi[1:])
    mid = np.cos(pm)[None, :, None] * e1[:, None, :] + np.sin(pm)[None, :, None] * e2[:, None, :]
    return t, pts, mid - ix.taper * d[:, None, :]


def roller_silhouettes(ix, a: np.ndarray, d: np.ndarray, view: tuple[float, float]) -> np.ndarray:
    """The rollers' two silhouette lines seen along ``view`` (module docs), fixed frame, (J, 5, 3):
    from t0 to t1 on one side, a NaN row, the other side — the generators at r(t0), r(t1); NaN for a
    cone seen so nearly along its axis that it has none."""
    _, _, v = view_basis(view)
    e1, e2 = _frame(d, view)
    k = ix.taper
    t0, t1 = float(ix.roller_start), float(ix.roller_end)
    r0, r1 = (float(r) for r in ix.radius_at(np.array([t0, t1])))
    if k == 0.0:
        s = np.zeros(d.shape[0])
    else:
        with np.errstate(divide="ignore", invalid="ignore"):
            s = k * (d @ v) / (e2 @ v)
    with np.errstate(invalid="ignore"):
        c = np.sqrt(1.0 - s**2)[:, None]
    out = np.full((d.shape[0], 5, 3), np.nan)
    for row, sgn in ((0, 1.0), (3, -1.0)):
        n = sgn * c * e1 + s[:, None] * e2
        out[:, row] = a + t0 * d + r0 * n
        out[:, row + 1] = a + t1 * d + r1 * n
    return out


def _roller_faces(design: SpatialDesign, a: np.ndarray, d: np.ndarray, engaged: np.ndarray,
                  view: tuple[float, float], faces: _Faces) -> None:
    """Every roller's surface (:func:`roller_mesh`: mantle and ends) as quads; the engaged ones in
    their own colour."""
    _, pts, mid = roller_mesh(design.indexer, a, d, view)
    axis_pts = np.stack([a + t * d for t in (float(design.indexer.roller_start), float(design.indexer.roller_end))],
                        axis=1)                                                                       # (J, 2, 3)
    n_phi = pts.shape[2]
    for on, color, kind in ((~engaged, _ROLLER, 3), (engaged, _ROLLER_ENGAGED, 4)):
        if not on.any():
            continue
        q = np.stack([pts[on, :-1, :-1], pts[on, 1:, :-1], pts[on, 1:, 1:], pts[on, :-1, 1:]], axis=-2)
        n = np.broadcast_to(mid[on][:, None], q.shape[:-2] + (3,))
        caps, cap_n = [], []
        for end, sgn in ((0, -1.0), (-1, 1.0)):
            ring = pts[on, end]                                                                        # (J', P, 3)
            centre = np.broadcast_to(axis_pts[on, end][:, None, :], ring[:, :-1].shape)
            caps.append(np.stack([centre, ring[:, :-1], ring[:, 1:], ring[:, 1:]], axis=2).reshape(-1, 4, 3))
            cap_n.append(np.repeat(sgn * d[on], n_phi - 1, axis=0))
        faces.add(np.concatenate([q.reshape(-1, 4, 3), *caps]), np.concatenate([n.reshape(-1, 3), *cap_n]),
                  color, kind, True)


def _curve(xy: np.ndarray, **kw) -> Curve:
    return Curve(xy[..., 0], xy[..., 1], **kw)


# ---------------------------------------------------------------------------------------------
# the picture

def spatial_panel(design: SpatialDesign, theta: float = 0.0, view: tuple[float, float] | None = None) -> Panel:
    """The indexer in the fixed frame at input angle ``theta`` [rad] (see :func:`spatial_picture`)."""
    ix = design.indexer
    view = default_view(design) if view is None else (float(view[0]), float(view[1]))
    barrel = isinstance(ix, BarrelIndexer)
    n, rr = int(ix.stations), float(ix.roller_radius)
    t0, t1, c_dist = float(ix.roller_start), float(ix.roller_end), float(ix.centre_distance)
    half = 0.5 * float(ix.cam_width)
    psi = float(turret_angle(ix, np.array([theta]))[0][0])
    axis = roller_axis(ix, design.rollers, np.full(design.rollers.size, float(theta)))
    a, d = np.asarray(axis.a, dtype=float), np.asarray(axis.d, dtype=float)
    sides = engaged_sides(design, theta)
    engaged = sides.any(axis=1)
    name = "root cylinder" if barrel else "root globoid"
    labels = ["rib flank, side +1 (holds the turret)", "rib flank, side −1 (drives the turret)",
              f"cam's {name}", "roller", "engaged roller", "rib's top"]
    faces = _Faces()
    _top_land(design, theta, _rib_faces(design, theta, faces), faces)
    radius, slope = _root_shape(design)
    q, nq = _revolution(radius, slope, -half, half, int(math.ceil(2.0 * half / _TOP_PIECE)))
    faces.add(q, nq, _ROOT, 2, True)
    _roller_faces(design, a, d, engaged, view, faces)

    marks: list[Mark] = []
    p_fix = np.array([c_dist, 0.0, 0.0])
    ring = np.linspace(0.0, TWO_PI, 181)
    unit = np.column_stack([np.cos(ring), np.zeros_like(ring), np.sin(ring)])       # u(α) about P in y = 0
    if barrel:
        rp = float(ix.pitch_radius)
        turret = p_fix + rp * unit + np.array([0.0, t1, 0.0])
        marks.append(_curve(project(turret, view), color=css_color("0.45"), width=0.8, dash="-.",
                            label=f"turret pitch circle R_p (at the rollers' ends, y = {t1:g})",
                            gid="turret-pitch-circle"))
        hub_top = p_fix + np.array([0.0, t1, 0.0])
        spoke_ends = a + t1 * d
    else:
        hub = p_fix + t0 * unit
        marks.append(Area([project(hub, view)], fill="#dfe6ee", edge=css_color("0.45"), width=0.8, alpha=0.7,
                          label=f"turret hub (radius t0 = {t0:g} about P)", gid="turret-hub"))
        hub_top = p_fix
        spoke_ends = a + t0 * d
    spokes = np.full((3 * n, 3), np.nan)
    spokes[0::3], spokes[1::3] = hub_top, spoke_ends
    marks.append(_curve(project(spokes, view), color=css_color("0.5"), width=0.5, alpha=0.7))
    marks.extend(faces.marks(view, labels, {}))
    marks.append(_curve(project(_root_outline(design, view), view), color=css_color("0.3"), width=0.6, alpha=0.8,
                        gid="root-outline"))
    # the rollers' outlines: the end circles and the two silhouette lines
    e1, e2 = _frame(d, view)
    circ = np.linspace(0.0, TWO_PI, _RING + 1)
    offs = np.cos(circ)[None, :, None] * e1[:, None, :] + np.sin(circ)[None, :, None] * e2[:, None, :]
    r_ends = [float(r) for r in ix.radius_at(np.array([t0, t1]))]
    sils = roller_silhouettes(ix, a, d, view)
    for i, j in enumerate(design.rollers.tolist()):
        on = bool(engaged[i])
        style = dict(color=_ENGAGED_EDGE if on else css_color("0.35"), width=1.3 if on else 0.6)
        for tag, tt, r_end in (("t0", t0, r_ends[0]), ("t1", t1, r_ends[1])):
            marks.append(_curve(project(a[i] + tt * d[i] + r_end * offs[i], view), gid=f"roller-{j}-{tag}", **style))
        marks.append(_curve(project(sils[i], view), gid=f"roller-{j}-sides", **style))
    # the contact lines of the engaged sides, in the band
    contact_label: str | None = "contact line (in the rib's band)"
    for si, (side, tag) in enumerate(((1, "p"), (-1, "m"))):
        cl = contact_lines(ix, design.rollers, float(theta), design.t, side)
        band = ix.in_band(cl.points)
        pts = turned(theta, cl.points)
        for i, j in enumerate(design.rollers.tolist()):
            if sides[i, si]:
                line = np.where(band[i][:, None], pts[i], np.nan)
                marks.append(_curve(project(line, view), color=_CONTACT, width=2.2, label=contact_label,
                                    gid=f"engaged-{j}-{tag}"))
                contact_label = None
    # the axes
    cam_axis = np.array([[0.0, 0.0, -half - 25.0], [0.0, 0.0, half + 25.0]])
    y_span = (0.0, t1 + 35.0) if barrel else (-45.0, 45.0)
    turret_axis = np.array([[c_dist, y_span[0], 0.0], [c_dist, y_span[1], 0.0]])
    for pts3, gid, text in ((cam_axis, "cam-axis", "input (cam) axis z, turns CCW"),
                            (turret_axis, "turret-axis", "turret axis (+y through P)")):
        xy = project(pts3, view)
        marks.append(_curve(xy, color="#000000", width=0.7, dash="-.", gid=gid))
        marks.append(Note(float(xy[1, 0]), float(xy[1, 1]), text, size=7.0, dx=3.0, dy=3.0, anchor="start",
                          valign="bottom"))
    # the drawing's extent, with room above it for the note at its upper left
    xy_all = np.concatenate([lp for m in marks if isinstance(m, Area) for lp in m.loops]
                            + [np.column_stack([m.x, m.y]) for m in marks if isinstance(m, Curve)])
    xy_all = xy_all[np.isfinite(xy_all).all(axis=1)]
    (x0, y0), (x1, y1) = xy_all.min(axis=0), xy_all.max(axis=0)
    pad = 0.03 * max(x1 - x0, y1 - y0)
    xlim, ylim = (x0 - pad, x1 + pad), (y0 - pad, y1 + pad + 0.1 * (y1 - y0))
    held = [f"{j}{'+' if sides[i, 0] else ''}{'−' if sides[i, 1] else ''}" for i, j in
            enumerate(design.rollers.tolist()) if engaged[i]]
    rel = (theta - float(ix.index_start)) % TWO_PI
    phase = "index" if rel <= float(ix.index_angle) else "dwell"
    marks.append(Note(xlim[0], ylim[1],
                      f"θ = {math.degrees(theta):.2f}° ({phase}), turret ψ(θ) = {math.degrees(psi):.4f}°\n"
                      f"engaged rollers (sides): {', '.join(held) if held else 'none'}", size=8.0, dx=0.0, dy=0.0,
                      anchor="start", valign="top", boxed=True, gid="turret-angle"))
    kind = "barrel" if barrel else "globoidal"
    cone = float(ix.roller_cone_angle)
    sizes = (f"R_p = {float(ix.pitch_radius):g}, " if barrel else "") + f"r_r = {rr:g}, t = {t0:g}–{t1:g} mm" + (
        f", cone γ = {math.degrees(cone):g}° (r = {r_ends[0]:.4g}–{r_ends[1]:.4g})" if cone != 0.0 else "")
    title = (f"{kind} indexer: N = {n}, β = {math.degrees(float(ix.index_angle)):g}°, {ix.law}, "
             f"C = {c_dist:g}, {sizes}\n"
             f"fixed frame at input angle θ = {math.degrees(theta):g}°; view azimuth {view[0]:g}°, "
             f"elevation {view[1]:g}° (up: the turret axis +y)")
    return Panel(marks, title=title, xlim=xlim, ylim=ylim, equal=True, axes=False, legend="below", legend_columns=2,
                 height=400.0)


def spatial_picture(design: SpatialDesign, theta: float = 0.0, view: tuple[float, float] | None = None) -> Chart:
    """The spatial indexer in the fixed frame at input angle ``theta`` [rad], projected
    orthographically along ``view`` = (azimuth, elevation) [deg] (module docs; None: the type's
    default, :data:`BARREL_VIEW` or :data:`GLOBOIDAL_VIEW`): the rib's two flank sheets turned by θ
    and the root body (shaded quads, back to front), every roller (a cylinder or, with a cone angle, a
    cone: :func:`roller_mesh`; the engaged ones in
    their own colour, outlined thick, with their contact lines in the band), the turret's pitch
    circle (barrel) or hub (globoid), the cam and turret axes and a note with ψ(θ) [deg]."""
    return Chart.stack([spatial_panel(design, theta, view)], width=640.0)


@PICTURES.register(SpatialIndexerDesign)
def spatial_design_picture(design: SpatialIndexerDesign, follower_angle_deg: float = 75.0) -> Chart:
    """The Python API's picture of a designed barrel or globoidal indexer (``Cam(...).picture()``,
    Jupyter): :func:`spatial_picture` of its geometry at the input angle ``follower_angle_deg``
    [deg], the type's default view (:data:`cam_workbench.exporters.plots.PICTURES`)."""
    return spatial_picture(design.geometry, math.radians(follower_angle_deg))


def spatial_motion_chart(design: SpatialDesign) -> Chart:
    """The turret's angle ψ [deg], ψ' = dψ/dθ [–] and ψ'' [1/rad] over the input turn, and the driving
    pressure angle [deg] (``design.driving_angle``) over the index; x: the input angle from the index
    start θ − θ_s [deg], the index shaded."""
    ix = design.indexer
    x = np.degrees(design.theta - float(ix.index_start))
    beta = math.degrees(float(ix.index_angle))
    kind = "barrel" if isinstance(ix, BarrelIndexer) else "globoidal"
    series = ((np.degrees(design.psi), "turret angle ψ [deg]", "psi", CAM_EDGES[0]),
              (design.dpsi, "ψ' = dψ/dθ [–]", "dpsi", "#2e7d32"),
              (design.d2psi, "ψ'' [1/rad]", "d2psi", "#c0392b"))
    panels = []
    for i, (y, label, gid, color) in enumerate(series):
        p = angle_panel(ylabel=label, xticklabels=False, height=110.0,
                        title=(f"{kind} indexer: N = {int(ix.stations)}, β = {beta:g}°, {ix.law}" if i == 0 else ""))
        p.add(Shade([(0.0, beta)], color=CAM_EDGES[0], alpha=0.08, label="index" if i == 0 else None),
              Curve(x, y, color=color, width=1.5, gid=gid))
        panels.append(p)
    over = x <= beta + 1e-9
    phi = np.where(over, np.degrees(design.driving_angle), np.nan)
    p = angle_panel(xlabel="input angle θ − θ_s [deg]", ylabel="driving pressure\nangle [deg]", height=130.0)
    p.add(Shade([(0.0, beta)], color=CAM_EDGES[0], alpha=0.08),
          Curve(x, phi, color="#6a1b9a", width=1.5, gid="driving-angle"))
    if np.isfinite(phi).any():
        i_max = int(np.nanargmax(phi))
        p.add(Note(float(x[i_max]), float(phi[i_max]), f"max {phi[i_max]:.2f}° at {x[i_max]:.1f}°", dy=-4.0,
                   valign="top"))
    panels.append(p)
    return Chart.stack(panels, width=640.0)


__all__ = ["BARREL_VIEW", "GLOBOIDAL_VIEW", "default_view", "engaged_sides", "project", "roller_mesh",
           "roller_silhouettes", "spatial_design_picture", "spatial_motion_chart", "spatial_panel", "spatial_picture",
           "turned", "view_basis"]

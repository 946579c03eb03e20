"""The spatial (barrel and globoidal) indexers' flank sheets as B-spline data: each flank's fitted
surface (:mod:`.spatial_surfaces`) continued until it cuts clean through the rib's band
(:mod:`.spatial`: barrel root ≤ ρ ≤ outer, globoid tip ≤ g ≤ root, and |z| ≤ W/2), and the numbers
the solid's construction takes from them — plain numpy: the CAD kernel
(:mod:`cam_workbench.kernel.spatial_indexer`, OCP) and the FreeCAD workbench
(:mod:`cam_workbench.freecad.part_spatial_indexer`, ``Part``) each make their faces of exactly these
poles and knots and split the band by them.

Units and frames: lengths in mm, angles in radians; every point is in the design's cam frame
(:mod:`.spatial`: the cam axis is z, the cam centred on z = 0, φ the angle about the axis); g is the
globoid's radial coordinate, the distance from the circle the turret's centre P traces about the
cam axis (radius C, the centre distance, in z = 0).

Each flank (side ±1) becomes a sheet (:func:`extended_flank`, :class:`ExtendedFlank`) — its boundary
outside the band — of B-spline faces:

* the FLANK face: the fitted surface S(τ, t) (``surfaces.flank(side)``, exactly its poles and
  knots) continued at both τ ends by pieces interpolating the exact envelope
  (:func:`~cam_workbench.generators.bodies.indexing.spatial.contact_lines`) on the same t nodes
  (not-a-knot cubics on uniform τ nodes, split at the law's ends, refined to the fit's
  tolerance), joined at triple knots — so the fitted surface is an exact sub-range of the
  face —, until the end rows, with their skirts, lie :data:`END_CLEARANCE` outside the band.
  (The fitted τ range ends one design row past the band: microns outside it on the barrel, a
  little inside it on the globoid between two of the design's t samples.)  Over the index the
  rib's flanks sweep along the cam axis: the rib is one thread that enters the band through one
  end plane |z| = W/2 and leaves through the other, a ring over the dwell in between; its two
  ends are closed by the band's end planes (its end faces lie in the cam's end faces).
* the SKIRT face: the roller reaches only from t0 to t1, short of the rib's root (barrel: the
  contact at t0 lies at ρ ≥ t0 > root; globoid: at g ≤ √(t1² + r_r²) < root), so below the
  roller's end — where no roller ever comes — the flank is continued straight along the root
  surface's normal (:func:`project_radially`): barrel radially towards the cam axis at constant z
  and φ; globoid away from the circle P traces (the root globoid's normal) at constant φ and angle
  about that circle; from the flank's root-side edge E(τ) (t = t0 barrel, t1 globoid) to
  :data:`ROOT_OVERLAP` beyond the root.  (Continuing the roller's envelope instead — a roller-sized
  cutter plunged to the root — does not reach the root where the barrel's rollers leave the cam:
  their extended contact lines run along the root cylinder at ρ ≈ root.)  The skirt is ruled
  (degree 1 across): its first pole row is the flank face's edge row (a common edge, exactly), the
  other the interpolant, on the same τ knots and nodes, of the projections of E at the nodes.
* a TOP face only where the fitted surface's top edge (barrel t1 ≥ outer, globoid t0 ≤ tip)
  is not :data:`TOP_CLEARANCE` outside the band: the same ruled continuation away from the root,
  by the edge's depth inside the band plus 2·:data:`TOP_CLEARANCE`.

Each face's ``orientation`` is the sign of (S_u × S_v)·n, n the roller's normal into the rib: a
piece of the split band is rib where its outward normal on a flank or skirt face is −n.

For the band and the core (solids of revolution) the sheets also give :func:`seam_angle`, the
angle φ of their seams — where the sheets crossing the seam's half-plane are farthest from the
cam's end planes —, and :func:`core_overlap`, how far the band that the sheets split reaches
beyond the root into the core (half the skirts' reach).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...curves.basis import basis_matrix
from .spatial import TWO_PI, BarrelIndexer, contact_lines
from .spatial_surfaces import DEFAULT_TOLERANCE, BSplineSurface, FlankSurface

Array = np.ndarray

#: how far [mm] the flank sheets' τ-end rows (flank and skirt) are taken outside the band
END_CLEARANCE = 1.0
#: the least such clearance [mm] accepted where a flank levels off nearer the band (a dwell's
#: surface of revolution just beyond the band's edge: a conical roller's, e.g.)
MIN_END_CLEARANCE = 0.25
#: how far [mm] the skirt continues the flank beyond the rib's root (into the core)
ROOT_OVERLAP = 1.0
#: the least clearance [mm] of the flank's top edge from the band before a top skirt is added
TOP_CLEARANCE = 0.5
#: the longest τ extension [rad] searched at each end of a flank
MAX_EXTENSION = math.radians(120.0)
#: the search step [rad] of the τ extension and the extension's largest node spacing
EXTENSION_STEP = math.radians(0.25)
MAX_NODE_SPACING = math.radians(2.0)
#: the search step [rad] of the band's and the core's seam angle (:func:`seam_angle`), and the half
#: width [rad] of the sector about the seam whose least end clearance it maximises
SEAM_STEP = math.radians(1.0)
SEAM_WINDOW = math.radians(5.0)


# ---------------------------------------------------------------------------------------------
# the band and the root-normal projection (cam frame)

def is_barrel(ix: Any) -> bool:
    """Whether ``ix`` is a :class:`~.spatial.BarrelIndexer` (else a globoidal indexer)."""
    return isinstance(ix, BarrelIndexer)


def band_margin(ix: Any, q: Array) -> Array:
    """The band's margin [mm] at cam-frame points ``q`` (..., 3): > 0 inside the rib's extent
    (the smallest distance-like slack of its bounds), < 0 outside."""
    rho = np.hypot(q[..., 0], q[..., 1])
    ends = 0.5 * float(ix.cam_width) - np.abs(q[..., 2])
    if is_barrel(ix):
        return np.minimum(np.minimum(rho - float(ix.root_radius), float(ix.outer_radius) - rho), ends)
    c = float(ix.centre_distance)
    g = np.hypot(c - rho, q[..., 2])
    return np.minimum(np.minimum(np.minimum(g - float(ix.tip_radius), float(ix.root_radius) - g), ends), c - rho)


def radial_coordinate(ix: Any, q: Array) -> Array:
    """ρ (barrel) or g (globoid) [mm] of cam-frame points ``q``."""
    rho = np.hypot(q[..., 0], q[..., 1])
    if is_barrel(ix):
        return rho
    return np.hypot(float(ix.centre_distance) - rho, q[..., 2])


def project_radially(ix: Any, q: Array, r: Array) -> Array:
    """Points ``q`` (..., 3) moved along the root surface's normal to the radial coordinate ``r``
    (ρ for the barrel: towards the cam axis at constant z and φ; g for the globoid: along the line
    from the nearest point of the circle P traces, at constant φ and angle about that circle)."""
    q = np.asarray(q, dtype=float)
    r = np.asarray(r, dtype=float)
    rho = np.hypot(q[..., 0], q[..., 1])
    ux, uy = q[..., 0] / rho, q[..., 1] / rho
    if is_barrel(ix):
        return np.stack([r * ux, r * uy, np.broadcast_to(q[..., 2], r.shape)], axis=-1)
    c = float(ix.centre_distance)
    centre = np.stack([c * ux, c * uy, np.zeros_like(ux)], axis=-1)
    v = q - centre
    return centre + (r / np.linalg.norm(v, axis=-1))[..., None] * v


def _root_side(ix: Any) -> int:
    """The v index (0: t0, −1: t1) of the flank's edge that faces the rib's root."""
    return 0 if is_barrel(ix) else -1


def _root_target(ix: Any) -> float:
    """The radial coordinate [mm] the skirt reaches: :data:`ROOT_OVERLAP` beyond the root (at most
    half way to the cam axis, or to the circle P traces)."""
    root = float(ix.root_radius)
    if is_barrel(ix):
        return root - min(ROOT_OVERLAP, 0.5 * root)
    return root + min(ROOT_OVERLAP, 0.5 * (float(ix.centre_distance) - root))


def _toward_root(ix: Any) -> float:
    """+1 when the radial coordinate grows towards the root (globoid), −1 when it falls (barrel)."""
    return -1.0 if is_barrel(ix) else 1.0


# ---------------------------------------------------------------------------------------------
# B-spline data

def _knots(pieces: list[Array]) -> Array:
    """Clamped cubic knots interpolating at the nodes of consecutive ``pieces`` (not-a-knot in each,
    a triple knot at each join), as :mod:`.spatial_surfaces` builds them."""
    parts = [np.full(4, pieces[0][0])]
    for k, x in enumerate(pieces):
        parts.append(x[2:-2])
        parts.append(np.full(4 if k == len(pieces) - 1 else 3, x[-1]))
    return np.concatenate(parts)


def _interpolate_rows(knots: Array, nodes: Array, values: Array) -> Array:
    """The cubic B-spline coefficients (n, …) on ``knots`` through ``values`` (n, …) at ``nodes``."""
    a = basis_matrix(knots, 3, nodes.size, nodes)
    flat = values.reshape(nodes.size, -1)
    return np.linalg.solve(a, flat).reshape(values.shape)


def _law_breaks(ix: Any, lo: float, hi: float) -> Array:
    """The law's ends θ_s + 2πm, θ_s + β + 2πm strictly inside (lo, hi) [rad]."""
    ts, beta = float(ix.index_start), float(ix.index_angle)
    m = np.arange(math.floor((min(lo, hi) - ts) / TWO_PI) - 1, math.ceil((max(lo, hi) - ts) / TWO_PI) + 2)
    b = np.sort(np.concatenate([ts + TWO_PI * m, ts + beta + TWO_PI * m]))
    a, c = min(lo, hi), max(lo, hi)
    eps = 1e-9 * max(1.0, abs(a), abs(c))
    return b[(b > a + eps) & (b < c - eps)]


def _pieces(ix: Any, lo: float, hi: float, spacing: float) -> list[Array]:
    """Uniform node pieces over [lo, hi] split at the law's ends, each ≥ 3 cells, cells ≤ ``spacing``."""
    edges = np.concatenate([[lo], _law_breaks(ix, lo, hi), [hi]])
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        cells = max(3, int(math.ceil((b - a) / spacing)))
        out.append(np.linspace(a, b, cells + 1))
    return out


@dataclass(frozen=True)
class ExtendedFlank:
    """One side's flank sheet (module docs): ``flank`` (the fitted surface continued at both
    τ ends), ``skirt`` (its ruled continuation beyond the root), ``top`` (beyond the rib's top, or
    None where the fitted surface already ends :data:`TOP_CLEARANCE` outside the band);
    ``tau_range`` [rad] of the sheet and ``given_range`` of the fitted surface; ``nodes`` the τ
    interpolation nodes; ``extension_error`` [mm]: the largest distance of the τ continuations from
    the exact envelope at their cells' midpoints (on the t nodes and between them);
    ``skirt_error`` [mm]: the largest distance of the skirts' far edges from the projections of
    their near edges, at the τ cells' midpoints; ``orientation``: per face (``"flank"``,
    ``"skirt"``, ``"top"``), the sign of (S_u × S_v)·n, n the roller's normal into the rib."""

    side: int
    flank: BSplineSurface
    skirt: BSplineSurface
    top: BSplineSurface | None
    tau_range: tuple[float, float]
    given_range: tuple[float, float]
    nodes: Array
    extension_error: float
    skirt_error: float
    orientation: dict[str, int]


def _skirt_points(ix: Any, edge: Array, target: Array, count: int = 17) -> Array:
    """Points (..., count, 3) on the lines from ``edge`` (..., 3) along the root surface's normal
    to the radial coordinates ``target`` (...)."""
    r_edge = radial_coordinate(ix, edge)
    frac = np.linspace(0.0, 1.0, count)
    r = r_edge[..., None] + frac * (np.asarray(target)[..., None] - r_edge[..., None])
    return project_radially(ix, np.broadcast_to(edge[..., None, :], r.shape + (3,)), r)


def _top_target(ix: Any, edge: Array, length: float) -> Array:
    """The radial coordinate ``length`` beyond the top-side ``edge`` points, away from the root."""
    return radial_coordinate(ix, edge) - _toward_root(ix) * length


def _row_margin(ix: Any, side: int, tau: Array, t: Array, top_length: float) -> Array:
    """The band margin [mm] of the exact flank rows at ``tau`` (t ∈ ``t``, sorted) with their root
    skirts and (``top_length`` > 0) top skirts: the largest over each row (≤ −c: the whole row and
    its continuations lie c outside the band)."""
    pts = contact_lines(ix, 0, tau, t, side).points                       # (T, K, 3)
    m = band_margin(ix, pts).max(axis=1)
    edge = pts[:, _root_side(ix)]
    root = _skirt_points(ix, edge, np.full(tau.size, _root_target(ix)))
    m = np.maximum(m, band_margin(ix, root).max(axis=1))
    if top_length > 0:
        top = pts[:, -1 - _root_side(ix)]
        m = np.maximum(m, band_margin(ix, _skirt_points(ix, top, _top_target(ix, top, top_length))).max(axis=1))
    return m


def _extension_end(ix: Any, side: int, start: float, direction: int, t: Array, top_length: float) -> float:
    """The τ [rad] beyond ``start`` (towards ``direction``) one search step past the first row
    that lies, with its continuations, :data:`END_CLEARANCE` outside the band — or, where no row
    does within :data:`MAX_EXTENSION`, the first row that comes within 0.01 mm of the largest
    clearance reached if that is at least :data:`MIN_END_CLEARANCE`."""
    steps = np.arange(1, int(MAX_EXTENSION / EXTENSION_STEP) + 1)
    tau = start + direction * EXTENSION_STEP * steps
    margin = _row_margin(ix, side, tau, t, top_length)
    out = np.flatnonzero(margin <= -END_CLEARANCE)
    if out.size == 0 and -np.nanmin(margin) >= MIN_END_CLEARANCE:
        out = np.flatnonzero(margin <= np.nanmin(margin) + 0.01)
    if out.size == 0:
        raise RuntimeError(f"the side {side:+d} flank does not leave the rib's band within "
                           f"{math.degrees(MAX_EXTENSION):g}° of τ = {math.degrees(start):.6g}° "
                           f"(at best {-margin.min():.3g} mm outside it)")
    return float(tau[min(out[0] + 1, tau.size - 1)])


def _orientation(surface: BSplineSurface, normal_at: Any) -> int:
    """sign((S_u × S_v)·n) in the middle of ``surface``'s domain, n = ``normal_at(u)``."""
    (u0, u1), (v0, v1) = surface.domain
    u, v = 0.5 * (u0 + u1), 0.5 * (v0 + v1)
    hu, hv = 1e-5 * (u1 - u0), 1e-5 * (v1 - v0)
    su = (surface.evaluate(u + hu, v) - surface.evaluate(u - hu, v)) / (2 * hu)
    sv = (surface.evaluate(u, v + hv) - surface.evaluate(u, v - hv)) / (2 * hv)
    return 1 if float(np.dot(np.cross(su, sv), normal_at(u, v))) > 0 else -1


def _ruled(knots_u: Array, first: Array, second: Array) -> BSplineSurface:
    """The surface (1 − v)·A(u) + v·B(u), v ∈ [0, 1], of two cubic curves on ``knots_u`` (poles
    ``first``, ``second``)."""
    poles = np.stack([first, second], axis=1)
    return BSplineSurface(3, 1, knots_u, np.array([0.0, 0.0, 1.0, 1.0]), poles, np.ones(poles.shape[:2]))


def _continuation(ix: Any, side: int, pieces: list[Array], t_nodes: Array, knots_v: Array
                  ) -> tuple[Array, Array, Array, float]:
    """The cubic × cubic interpolant of the exact envelope on the τ ``pieces`` × ``t_nodes``:
    (its τ knots, poles, τ nodes, largest error at the cells' midpoints [mm]); RuntimeError where
    the envelope is undefined or singular inside the band."""
    nodes = np.concatenate([pieces[0]] + [x[1:] for x in pieces[1:]])
    ku = _knots(pieces)
    cl = contact_lines(ix, 0, nodes, t_nodes, side)
    in_band = band_margin(ix, cl.points) > 0
    if not np.isfinite(cl.points).all() or (in_band & ~(cl.margin > 0)).any():
        raise RuntimeError(f"the side {side:+d} flank's envelope is undefined or singular where it is continued "
                           f"(τ {math.degrees(nodes[0]):.6g}°–{math.degrees(nodes[-1]):.6g}°)")
    rows = _interpolate_rows(ku, nodes, cl.points)                                       # τ direction
    poles = _interpolate_rows(knots_v, t_nodes, rows.transpose(1, 0, 2)).transpose(1, 0, 2)
    surf = BSplineSurface(3, 3, ku, knots_v, poles, np.ones(poles.shape[:2]))
    mid_tau = 0.5 * (nodes[:-1] + nodes[1:])
    mid_t = np.concatenate([t_nodes, 0.5 * (t_nodes[:-1] + t_nodes[1:])])
    err = np.linalg.norm(surf.evaluate_grid(mid_tau, mid_t) - contact_lines(ix, 0, mid_tau, mid_t, side).points,
                         axis=-1)
    return ku, poles, nodes, float(err.max())


def _skirt(ix: Any, surf: BSplineSurface, nodes: Array, k_edge: int, target: Any) -> tuple[BSplineSurface, float]:
    """The ruled skirt from the edge row ``k_edge`` of ``surf`` (t = its first or last t knot) to the
    interpolant of the edge's projections at the nodes onto ``target(edge points)``; and the
    largest distance [mm] of its far edge from the exact projection of its near edge at the τ
    cells' midpoints."""
    (u0, u1), (v0, v1) = surf.domain
    v_edge = v0 if k_edge == 0 else v1
    edge = surf.evaluate(nodes, np.full(nodes.size, v_edge))
    far = _interpolate_rows(surf.knots_u, nodes, project_radially(ix, edge, target(edge)))
    skirt = _ruled(surf.knots_u, surf.poles[:, k_edge], far)
    mid = 0.5 * (nodes[:-1] + nodes[1:])
    e_mid = surf.evaluate(mid, np.full(mid.size, v_edge))
    err = np.linalg.norm(skirt.evaluate(mid, np.ones(mid.size)) - project_radially(ix, e_mid, target(e_mid)), axis=-1)
    return skirt, float(err.max())


def extended_flank(ix: Any, flank: FlankSurface, tolerance: float | None = None) -> ExtendedFlank:
    """The sheet of one side (module docs); the τ continuations are refined (node spacing
    halved, up to 5 times) until they are within ``tolerance`` [mm] of the exact envelope at their
    cells' midpoints (default: the flank fit's default, 1 µm)."""
    side = flank.side
    given = flank.surface
    lo, hi = flank.tau_range
    t_nodes = np.asarray(flank.t_nodes, dtype=float)
    t_dense = np.linspace(float(flank.t_range[0]), float(flank.t_range[1]), 41)
    k_edge = _root_side(ix)
    k_top = -1 - k_edge
    # a top skirt where the exact top edge is not clear of the band (the fitted range and beyond)
    top_edge = contact_lines(ix, 0, np.linspace(lo, hi, 2001), t_dense[[k_top]], side).points[:, 0]
    top_margin = float(band_margin(ix, top_edge).max())
    top_length = max(0.0, top_margin) + 2.0 * TOP_CLEARANCE if top_margin > -TOP_CLEARANCE else 0.0
    a = _extension_end(ix, side, lo, -1, t_dense, top_length)
    b = _extension_end(ix, side, hi, 1, t_dense, top_length)
    # the τ continuations on the given t nodes: pieces [a, lo] and [hi, b], split at the law's ends
    kv = np.asarray(given.knots_v, dtype=float)
    tolerance = DEFAULT_TOLERANCE if tolerance is None else float(tolerance)
    ends = []
    for start, stop in ((a, lo), (hi, b)):
        spacing = min(MAX_NODE_SPACING, float(np.max(np.diff(flank.tau_nodes))))
        for _ in range(6):                       # halve the nodes' spacing until within the tolerance
            fit = _continuation(ix, side, _pieces(ix, start, stop, spacing), t_nodes, kv)
            if fit[3] <= tolerance:
                break
            spacing /= 2.0
        ends.append(fit)
    (lku, lpoles, lnodes, err_lo), (hku, hpoles, hnodes, err_hi) = ends
    # joined at triple knots: the given surface's poles and knots unchanged in the middle
    gku = np.asarray(given.knots_u, dtype=float)
    ku = np.concatenate([lku[:-1], gku[4:-1], hku[4:]])
    poles = np.concatenate([lpoles[:-1], given.poles, hpoles[1:]], axis=0)
    nodes = np.concatenate([lnodes[:-1], np.asarray(flank.tau_nodes, dtype=float), hnodes[1:]])
    if poles.shape[0] != ku.size - 4 or nodes.size != poles.shape[0]:
        raise RuntimeError(f"the side {side:+d} flank's continued knots and poles disagree "
                           f"({ku.size} knots, {poles.shape[0]} poles, {nodes.size} nodes)")
    surf = BSplineSurface(3, 3, ku, kv, poles, np.ones(poles.shape[:2]))
    skirt, skirt_err = _skirt(ix, surf, nodes, k_edge, lambda e: np.full(e.shape[:-1], _root_target(ix)))
    top = None
    if top_length > 0:
        top, top_err = _skirt(ix, surf, nodes, k_top, lambda e: _top_target(ix, e, top_length))
        skirt_err = max(skirt_err, top_err)

    def normal_at(t: float) -> Any:
        return lambda u, v: contact_lines(ix, 0, np.array([u]), np.array([t if t is not None else v]),
                                          side).normals[0, 0]

    orientation = {"flank": _orientation(surf, normal_at(None)),
                   "skirt": _orientation(skirt, normal_at(float(t_nodes[k_edge])))}
    if top is not None:
        orientation["top"] = _orientation(top, normal_at(float(t_nodes[k_top])))
    return ExtendedFlank(side, surf, skirt, top, (float(ku[0]), float(ku[-1])), (float(lo), float(hi)), nodes,
                         max(err_lo, err_hi), skirt_err, orientation)



def core_overlap(ix: Any) -> float:
    """How far [mm] the band that the sheets split reaches beyond the root into the core (barrel
    ρ ≥ root − d, globoid g ≤ root + d): half the skirts' reach beyond the root, so that the skirts
    still cut through it.  The rib pieces then overlap the core by that much instead of sharing its
    root surface: OCCT's fuse of two solids
    with coincident cylindrical (toroidal) faces, their seams at the same φ, loses or duplicates
    parts of the cam for some seam angles (measured: +9.7 % or only the rib), the fuse of
    overlapping solids, which cuts the skirts by the root surface, does not."""
    return 0.5 * abs(_root_target(ix) - float(ix.root_radius))


def seam_angle(ix: Any, sheets: tuple[ExtendedFlank, ...]) -> float:
    """The angle φ [rad] (a multiple of :data:`SEAM_STEP` in [0, 2π)) at which to put the seam of the
    band and of the core (both solids of revolution): where the flank sheets cross the half-planes
    φ within :data:`SEAM_WINDOW` of it farthest from the cam's end planes |z| = W/2.

    OCCT's face/face intersection can lose the short branch of a sheet's section with a periodic face
    (the band's root or outer cylinder, or torus) between the face's seam and its boundary circle in
    an end plane, where the sheet crosses the seam close to that circle — near where the rib's thread
    leaves the band through an end plane.  The splitter then does not separate the rib from the
    grooves (or the fuse with the core, whose root cylinder the rib's root face shares, comes out
    wrong).  Those places turn with the index start, so a seam at a fixed φ fails for some starts;
    the seam is put where every sheet crossing it lies clear of the ends instead."""
    h = 0.5 * float(ix.cam_width)
    bins = int(round(TWO_PI / SEAM_STEP))
    clearance = np.full(bins, h)                        # per φ bin: h − the largest |z| of the sheets in it
    for sh in sheets:
        for surface in (sh.flank, sh.skirt, sh.top):
            if surface is None:
                continue
            (u0, u1), (v0, v1) = surface.domain
            p = surface.evaluate_grid(np.linspace(u0, u1, int(math.ceil(8.0 * (u1 - u0) / SEAM_STEP)) + 1),
                                      np.linspace(v0, v1, 9)).reshape(-1, 3)
            # the points within the band's radial extent (the end planes ignored) and up to beyond its ends
            flat = np.concatenate([p[:, :2], np.zeros((p.shape[0], 1))], axis=1)
            near = (band_margin(ix, flat) > -ROOT_OVERLAP) & (np.abs(p[:, 2]) < h + END_CLEARANCE)
            p = p[near]
            k = np.floor((np.arctan2(p[:, 1], p[:, 0]) % TWO_PI) / SEAM_STEP).astype(int) % bins
            np.minimum.at(clearance, k, h - np.abs(p[:, 2]))
    half = int(round(SEAM_WINDOW / SEAM_STEP))
    window = np.min([np.roll(clearance, s) for s in range(-half, half + 1)], axis=0)
    # the bin's lower edge: the seam half-plane between bins k − 1 and k sees both; the window covers them
    return float(int(np.argmax(window)) * SEAM_STEP)


__all__ = ["END_CLEARANCE", "ROOT_OVERLAP", "TOP_CLEARANCE", "ExtendedFlank", "band_margin", "core_overlap",
           "extended_flank", "is_barrel", "project_radially", "radial_coordinate", "seam_angle"]

"""The spatial indexers' cams (barrel and globoidal) as one OCCT solid through OCP: the core (the root
cylinder, or the solid of revolution inside the root globoid) and the rib between its two flank
surfaces (:mod:`cam_workbench.generators.bodies.indexing.spatial_surfaces`), trimmed to the rib's
band (:mod:`cam_workbench.generators.bodies.indexing.spatial`: barrel root ≤ ρ ≤ outer, globoid
tip ≤ g ≤ root, and |z| ≤ W/2).

Construction (:func:`spatial_solid`; lengths in mm, angles in radians, the cam frame):

1. Each flank (side ±1) becomes a sheet that cuts clean through the band — its boundary outside
   the band — made of B-spline faces:

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
     surface's normal: barrel radially towards the cam axis at constant z and φ; globoid away from
     the circle P traces (the root globoid's normal) at constant φ and angle about that circle;
     from the flank's root-side edge E(τ) (t = t0 barrel, t1 globoid) to :data:`ROOT_OVERLAP`
     beyond the root.  (Continuing the roller's envelope instead — a roller-sized cutter plunged
     to the root — does not reach the root where the barrel's rollers leave the cam: their
     extended contact lines run along the root cylinder at ρ ≈ root.)  The skirt is ruled (degree
     1 across): its first pole row is the flank face's edge row (a common edge, exactly), the
     other the interpolant, on the same τ knots and nodes, of the projections of E at the nodes.
   * a TOP face only where the fitted surface's top edge (barrel t1 ≥ outer, globoid t0 ≤ tip)
     is not :data:`TOP_CLEARANCE` outside the band: the same ruled continuation away from the root,
     by the edge's depth inside the band plus 2·:data:`TOP_CLEARANCE`.

   Each side's faces are sewn into one shell.

2. The band — the annulus root ≤ ρ ≤ outer, |z| ≤ W/2 (barrel), or the revolution of the region
   tip ≤ g ≤ root, |z| ≤ W/2 about the cam axis (globoid), reaching :func:`core_overlap` (half the
   skirts' reach) beyond the root into the core — is split by the two sheets
   (``BRepAlgoAPI_Splitter``).  A piece is rib where the roller's normal n (into the rib) points
   into it: on each of its flank or skirt faces the piece's outward normal is −n.

3. The rib pieces are fused with the core (the root cylinder, or the revolution of
   ρ ≤ C − √(root² − z²), |z| ≤ W/2; less a bore of ``bore_radius``), which they overlap, and the
   faces lying on one surface merged (``ShapeUpgrade_UnifySameDomain``): one solid, checked by
   ``BRepCheck``.

The band and the core are solids of revolution; their seams lie at the angle :func:`seam_angle`
picks, where the sheets crossing the seam's half-plane are farthest from the cam's end planes —
not at a fixed φ: the places where the rib's thread leaves the band turn with the index start, and
OCCT's intersection of a sheet with the band's periodic faces loses a branch where the sheet crosses
the seam near an end plane (the band then does not split into rib and grooves), and its fuse of
solids sharing the root surface (as the band once did with the core) failed for some seam angles
(+9.7 % volume, or the rib alone).  Measured: the default indexers at index starts 0°, 60°, 137°,
300° give one volume to 4e-9.

Measured (default ``BarrelIndexer()`` / ``GloboidalIndexer()``, design samples 361): ~4 s / ~5 s
(the split ~2.5 s, the fuse ~1.3 s); 12 / 11 faces; edge tolerances ≤ 7e-4 mm.
"""
from __future__ import annotations

import math
import time
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, Iterator

import numpy as np

from cam_workbench.generators.bodies.indexing.spatial import (TWO_PI, BarrelIndexer, GloboidalIndexer,
                                                              SpatialDesign, contact_lines)
from cam_workbench.generators.bodies.indexing.spatial_surfaces import (DEFAULT_TOLERANCE, BSplineSurface, FlankSurface,
                                                                       FlankSurfaces)
from cam_workbench.generators.bodies.indexing.spatial_kind import SpatialIndexerDesign
from cam_workbench.generators.curves.basis import basis_matrix
from cam_workbench.generators.errors import GeometryError

from . import ocp as occ
from .solids import SOLIDS, SURFACE_VOLUME_EPS, faces_of, general_op, is_valid, kernel_volume, solids_of

Array = np.ndarray

#: how far [mm] the flank sheets' τ-end rows (flank and skirt) are taken outside the band
END_CLEARANCE = 1.0
#: how far [mm] the skirt continues the flank beyond the rib's root (into the core)
ROOT_OVERLAP = 1.0
#: the least clearance [mm] of the flank's top edge from the band before a top skirt is added
TOP_CLEARANCE = 0.5
#: the longest τ extension [rad] searched at each end of a flank
MAX_EXTENSION = math.radians(120.0)
#: the search step [rad] of the τ extension and the extension's largest node spacing
EXTENSION_STEP = math.radians(0.25)
MAX_NODE_SPACING = math.radians(2.0)
#: sewing tolerance [mm] of each side's two faces (their common edge is the same pole row)
SEW_TOLERANCE = 1e-6
#: the search step [rad] of the band's and the core's seam angle (:func:`seam_angle`), and the half
#: width [rad] of the sector about the seam whose least end clearance it maximises
SEAM_STEP = math.radians(1.0)
SEAM_WINDOW = math.radians(5.0)


# ---------------------------------------------------------------------------------------------
# the band and the root-normal projection (cam frame)

def _is_barrel(ix: Any) -> bool:
    return isinstance(ix, BarrelIndexer)


def band_margin(ix: Any, q: Array) -> Array:
    """The band's margin [mm] at cam-frame points ``q`` (..., 3): > 0 inside the rib's extent
    (the smallest distance-like slack of its bounds), < 0 outside."""
    rho = np.hypot(q[..., 0], q[..., 1])
    ends = 0.5 * float(ix.cam_width) - np.abs(q[..., 2])
    if _is_barrel(ix):
        return np.minimum(np.minimum(rho - float(ix.root_radius), float(ix.outer_radius) - rho), ends)
    c = float(ix.centre_distance)
    g = np.hypot(c - rho, q[..., 2])
    return np.minimum(np.minimum(np.minimum(g - float(ix.tip_radius), float(ix.root_radius) - g), ends), c - rho)


def radial_coordinate(ix: Any, q: Array) -> Array:
    """ρ (barrel) or g (globoid) [mm] of cam-frame points ``q``."""
    rho = np.hypot(q[..., 0], q[..., 1])
    if _is_barrel(ix):
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
    if _is_barrel(ix):
        return np.stack([r * ux, r * uy, np.broadcast_to(q[..., 2], r.shape)], axis=-1)
    c = float(ix.centre_distance)
    centre = np.stack([c * ux, c * uy, np.zeros_like(ux)], axis=-1)
    v = q - centre
    return centre + (r / np.linalg.norm(v, axis=-1))[..., None] * v


def _root_side(ix: Any) -> int:
    """The v index (0: t0, −1: t1) of the flank's edge that faces the rib's root."""
    return 0 if _is_barrel(ix) else -1


def _root_target(ix: Any) -> float:
    """The radial coordinate [mm] the skirt reaches: :data:`ROOT_OVERLAP` beyond the root (at most
    half way to the cam axis, or to the circle P traces)."""
    root = float(ix.root_radius)
    if _is_barrel(ix):
        return root - min(ROOT_OVERLAP, 0.5 * root)
    return root + min(ROOT_OVERLAP, 0.5 * (float(ix.centre_distance) - root))


def _toward_root(ix: Any) -> float:
    """+1 when the radial coordinate grows towards the root (globoid), −1 when it falls (barrel)."""
    return -1.0 if _is_barrel(ix) else 1.0


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


def surface_geom(surface: BSplineSurface) -> Any:
    """A ``Geom_BSplineSurface`` with exactly the data (poles, knots, degrees) of ``surface``
    (polynomial: the fitted flanks and their continuations carry unit weights)."""
    ku, mu, kv, mv = surface.distinct_knots()
    return occ.Geom_BSplineSurface(occ.pnt_array2(surface.poles.tolist()), occ.real_array(ku.tolist()),
                                   occ.real_array(kv.tolist()), occ.int_array(mu.tolist()), occ.int_array(mv.tolist()),
                                   surface.degree_u, surface.degree_v, False, False)


@dataclass(frozen=True)
class ExtendedFlank:
    """One side's flank sheet (module docs, step 1): ``flank`` (the fitted surface continued at both
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
    that lies, with its continuations, :data:`END_CLEARANCE` outside the band."""
    steps = np.arange(1, int(MAX_EXTENSION / EXTENSION_STEP) + 1)
    tau = start + direction * EXTENSION_STEP * steps
    margin = _row_margin(ix, side, tau, t, top_length)
    out = np.flatnonzero(margin <= -END_CLEARANCE)
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
    """The sheet of one side (module docs, step 1); the τ continuations are refined (node spacing
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


# ---------------------------------------------------------------------------------------------
# OCCT shapes

def _face(surface: BSplineSurface) -> Any:
    mk = occ.BRepBuilderAPI_MakeFace(surface_geom(surface), 1e-7)
    if not mk.IsDone():
        raise RuntimeError("OCCT could not make a face from a flank surface")
    return mk.Face()


def sheet_shell(sheet: ExtendedFlank) -> Any:
    """The sheet's faces sewn into one shell (their common edges are the same pole rows)."""
    sew = occ.BRepBuilderAPI_Sewing(SEW_TOLERANCE)
    for s in (sheet.flank, sheet.skirt, sheet.top):
        if s is not None:
            sew.Add(_face(s))
    sew.Perform()
    shape = sew.SewedShape()
    shells = []
    ex = occ.TopExp_Explorer(shape, occ.TopAbs_SHELL)
    while ex.More():
        shells.append(occ.topods_shell(ex.Current()))
        ex.Next()
    if len(shells) != 1:
        raise RuntimeError(f"the side {sheet.side:+d} flank's faces did not sew into one shell "
                           f"({len(shells)} shells)")
    return shells[0]


def _revolved(profile: list[Any], seam: float = 0.0) -> Any:
    """The solid of revolution about the cam axis of the planar region (given in the half-plane
    y = 0, x = ρ ≥ 0) bounded by the closed chain of ``profile`` edges, revolved from the half-plane
    φ = ``seam`` [rad] (the region turned there first): its faces' seam edges lie at φ = ``seam``."""
    mk = occ.BRepBuilderAPI_MakeWire()
    for e in profile:
        mk.Add(e)
    if not mk.IsDone():
        raise RuntimeError("OCCT could not join a revolved profile into a wire")
    face = occ.BRepBuilderAPI_MakeFace(mk.Wire(), True)
    if not face.IsDone():
        raise RuntimeError("OCCT could not make a revolved profile's face")
    axis = occ.gp_Ax1(occ.gp_Pnt(0, 0, 0), occ.gp_Dir(0, 0, 1))
    region = face.Face()
    if seam != 0.0:
        trsf = occ.gp_Trsf()
        trsf.SetRotation(axis, float(seam))
        region = occ.topods_face(occ.BRepBuilderAPI_Transform(region, trsf, True).Shape())
    rev = occ.BRepPrimAPI_MakeRevol(region, axis, TWO_PI, True)
    rev.Build()
    if not rev.IsDone():
        raise RuntimeError("OCCT could not revolve a profile about the cam axis")
    solids = solids_of(rev.Shape())
    if len(solids) != 1:
        raise RuntimeError("a revolved profile did not make one solid")
    return solids[0]


def _segment(a: tuple[float, float], b: tuple[float, float]) -> Any:
    return occ.BRepBuilderAPI_MakeEdge(occ.gp_Pnt(a[0], 0, a[1]), occ.gp_Pnt(b[0], 0, b[1])).Edge()


def _arc(centre_rho: float, radius: float, a: tuple[float, float], b: tuple[float, float]) -> Any:
    """The arc of the circle about (ρ = ``centre_rho``, z = 0) of ``radius`` in the half-plane y = 0
    from ``a`` to ``b`` ((ρ, z) points on it), the short way."""
    axes = occ.gp_Ax2(occ.gp_Pnt(centre_rho, 0, 0), occ.gp_Dir(0, 1, 0), occ.gp_Dir(1, 0, 0))
    circ = occ.gp_Circ(axes, radius)

    def param(p: tuple[float, float]) -> float:      # the circle's x = +ρ, y = −z
        return math.atan2(-p[1], p[0] - centre_rho) % TWO_PI

    pa, pb = occ.gp_Pnt(a[0], 0, a[1]), occ.gp_Pnt(b[0], 0, b[1])
    if (param(b) - param(a)) % TWO_PI <= math.pi:
        return occ.BRepBuilderAPI_MakeEdge(circ, pa, pb).Edge()
    return occ.topods_edge(occ.BRepBuilderAPI_MakeEdge(circ, pb, pa).Edge().Reversed())


def band_solid(ix: Any, seam: float = 0.0, overlap: float = 0.0) -> Any:
    """The rib's band as a solid (barrel: the annulus root ≤ ρ ≤ outer, |z| ≤ W/2; globoid: the
    revolution of tip ≤ g ≤ root, |z| ≤ W/2), its seam at φ = ``seam`` [rad] (:func:`seam_angle`),
    reaching ``overlap`` [mm] beyond the root into the core (barrel ρ ≥ root − overlap, globoid
    g ≤ root + overlap; :func:`core_overlap`)."""
    h = 0.5 * float(ix.cam_width)
    d = float(overlap)
    if _is_barrel(ix):
        r0, r1 = float(ix.root_radius) - d, float(ix.outer_radius)
        return _revolved([_segment((r0, -h), (r1, -h)), _segment((r1, -h), (r1, h)), _segment((r1, h), (r0, h)),
                          _segment((r0, h), (r0, -h))], seam)
    c, rt, rr = float(ix.centre_distance), float(ix.tip_radius), float(ix.root_radius) + d
    if not h < rt:
        raise RuntimeError(f"the globoid's half width {h:g} mm must be below its tip radius {rt:g} mm")
    root_lo, root_hi = (c - math.sqrt(rr**2 - h**2), -h), (c - math.sqrt(rr**2 - h**2), h)
    tip_lo, tip_hi = (c - math.sqrt(rt**2 - h**2), -h), (c - math.sqrt(rt**2 - h**2), h)
    return _revolved([_segment(root_lo, tip_lo), _arc(c, rt, tip_lo, tip_hi), _segment(tip_hi, root_hi),
                      _arc(c, rr, root_hi, root_lo)], seam)


def core_solid(ix: Any, bore_radius: float = 0.0, seam: float = 0.0) -> Any:
    """The cam's core: the root cylinder (barrel) or the revolution of ρ ≤ C − √(root² − z²)
    (globoid) over |z| ≤ W/2, less a bore of ``bore_radius`` (0: none), its seam at φ = ``seam``
    [rad] (:func:`seam_angle`)."""
    h = 0.5 * float(ix.cam_width)
    rb = float(bore_radius)
    if _is_barrel(ix):
        r0 = float(ix.root_radius)
        prof = [_segment((rb, -h), (r0, -h)), _segment((r0, -h), (r0, h)), _segment((r0, h), (rb, h))]
    else:
        c, rr = float(ix.centre_distance), float(ix.root_radius)
        lo, hi = (c - math.sqrt(rr**2 - h**2), -h), (c - math.sqrt(rr**2 - h**2), h)
        prof = [_segment((rb, -h), lo), _arc(c, rr, lo, hi), _segment(hi, (rb, h))]
    # the bore's line, or (rb = 0) the axis: OCCT revolves an edge on the axis into nothing
    prof.append(_segment((rb, h), (rb, -h)))
    return _revolved(prof, seam)


def core_overlap(ix: Any) -> float:
    """How far [mm] the band that the sheets split reaches beyond the root into the core: half the
    skirts' reach beyond the root, so that the skirts still cut through it.  The rib pieces then
    overlap the core by that much instead of sharing its root surface: OCCT's fuse of two solids
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


def _surface_key(face: Any) -> tuple[Any, ...] | None:
    """(poles u, poles v, degree v, first pole rounded) of a face's B-spline surface (None for others)."""
    surf = occ.BRepAdaptor_Surface(face)
    if surf.GetType() != occ.GeomAbs_BSplineSurface:
        return None
    bs = surf.BSpline()
    p = bs.Pole(1, 1)
    return bs.NbUPoles(), bs.NbVPoles(), bs.VDegree(), round(p.X(), 6), round(p.Y(), 6), round(p.Z(), 6)


def _geom_key(surface: BSplineSurface) -> tuple[Any, ...]:
    p = surface.poles[0, 0]
    return (surface.poles.shape[0], surface.poles.shape[1], surface.degree_v, round(float(p[0]), 6),
            round(float(p[1]), 6), round(float(p[2]), 6))


def _is_rib(piece: Any, signs: dict[tuple[Any, ...], int]) -> bool | None:
    """Whether a split piece of the band is rib: on a flank or skirt face its outward normal is −n
    (the face's orientation times the surface's (S_u × S_v)·n sign is −1); None without such a face."""
    votes = []
    for face in faces_of(piece):
        key = _surface_key(face)
        if key is None or key not in signs:
            continue
        forward = face.Orientation() != occ.TopAbs_REVERSED
        votes.append((1 if forward else -1) * signs[key] < 0)
    if not votes:
        return None
    if len(set(votes)) > 1:
        raise RuntimeError("a piece of the band is bounded by flank faces facing both ways (the flank sheets "
                           "do not separate the rib from the grooves)")
    return votes[0]


@contextmanager
def _occt(stage: str) -> Iterator[None]:
    """Turn an exception OCCT raises (``Standard_Failure`` and its kind, through OCP) while doing
    ``stage`` into a RuntimeError naming the stage."""
    try:
        yield
    except (RuntimeError, ValueError):
        raise
    except Exception as exc:  # noqa: BLE001 - OCP raises OCCT's exceptions under their own classes
        raise RuntimeError(f"OCCT failed while {stage}: {type(exc).__name__}: {exc}") from exc


def _unify(shape: Any) -> Any:
    unify = occ.ShapeUpgrade_UnifySameDomain(shape, True, True, False)
    unify.Build()
    return unify.Shape()


@dataclass(frozen=True)
class SpatialBuild:
    """What :func:`build_spatial_solid` made: the ``solid``; the two :class:`ExtendedFlank`; the band's
    pieces (``rib_pieces``, ``groove_pieces``); ``seconds`` by stage; ``seam`` [rad], the band's and
    the core's seam angle (:func:`seam_angle`)."""

    solid: Any
    sheets: tuple[ExtendedFlank, ExtendedFlank]
    rib_pieces: int
    groove_pieces: int
    seconds: dict[str, float]
    seam: float = 0.0


def build_spatial_solid(design: SpatialDesign, surfaces: FlankSurfaces, bore_radius: float = 0.0) -> SpatialBuild:
    """:func:`spatial_solid` with the intermediate results (module docs)."""
    ix = design.indexer
    if not isinstance(ix, (BarrelIndexer, GloboidalIndexer)):
        raise TypeError(f"a barrel or globoidal design is needed, got {type(ix).__name__}")
    if surfaces.indexer != ix:
        raise ValueError("the flank surfaces were fitted for another indexer than the design's")
    rb = float(bore_radius)
    inner = float(ix.root_radius) if _is_barrel(ix) else float(ix.centre_distance) - float(ix.root_radius)
    if not (math.isfinite(rb) and 0.0 <= rb < inner):
        raise ValueError(f"bore_radius must be in [0, {inner:g}) mm (the core's least radius), got {bore_radius!r}")
    clock = time.perf_counter()
    seconds: dict[str, float] = {}

    def lap(name: str) -> None:
        nonlocal clock
        now = time.perf_counter()
        seconds[name] = now - clock
        clock = now

    sheets = (extended_flank(ix, surfaces.flank(1), surfaces.tolerance),
              extended_flank(ix, surfaces.flank(-1), surfaces.tolerance))
    signs: dict[tuple[Any, ...], int] = {}
    for sh in sheets:
        signs[_geom_key(sh.flank)] = sh.orientation["flank"]
        signs[_geom_key(sh.skirt)] = sh.orientation["skirt"]
        if sh.top is not None:
            signs[_geom_key(sh.top)] = sh.orientation["top"]
    with _occt("sewing the flank sheets"):
        shells = [sheet_shell(sh) for sh in sheets]
    seam = seam_angle(ix, sheets)
    lap("sheets")
    with _occt("splitting the rib's band by the flank sheets"):
        pieces = solids_of(general_op(occ.BRepAlgoAPI_Splitter, [band_solid(ix, seam, core_overlap(ix))], shells,
                                      "split the rib's band by the flank sheets"))
    lap("split")
    ribs, grooves = [], 0
    with _occt("classifying the band's pieces"):
        for piece in pieces:
            rib = _is_rib(piece, signs)
            if rib is None:
                raise RuntimeError("a piece of the band touches no flank face: the flank sheets do not cut through "
                                   "the band")
            if rib:
                ribs.append(piece)
            else:
                grooves += 1
    if not ribs:
        raise RuntimeError(f"the flank sheets split the band into {len(pieces)} pieces and none is rib")
    lap("classify")
    with _occt("fusing the rib with the core"):
        shape = _unify(general_op(occ.BRepAlgoAPI_Fuse, [core_solid(ix, rb, seam)], ribs, "fuse the rib with the core"))
    lap("fuse")
    solids = solids_of(shape)
    if len(solids) != 1:
        raise RuntimeError(f"the cam came out as {len(solids)} solids, not one")
    solid = solids[0]
    if not is_valid(solid):
        raise RuntimeError("the cam's solid fails OCCT's check (BRepCheck_Analyzer)")
    lap("check")
    return SpatialBuild(solid, sheets, len(ribs), grooves, seconds, seam)


def spatial_solid(design: SpatialDesign, surfaces: FlankSurfaces, bore_radius: float = 0.0) -> Any:
    """The barrel or globoidal indexer's cam as one valid ``TopoDS_Solid`` (module docs): the core
    (less a bore of ``bore_radius`` mm, 0 for none) and the rib between the flank ``surfaces``
    (:func:`~cam_workbench.generators.bodies.indexing.spatial_surfaces.flank_surfaces` of
    ``design``) within the rib's band.

    Raises:
        RuntimeError: OCCT could not build it (which step, and why where known).
        ValueError: ``bore_radius`` outside [0, the core's least radius); surfaces of another indexer.
    """
    return build_spatial_solid(design, surfaces, bore_radius).solid


def _shifted(shape: Any, dz: float) -> Any:
    """``shape`` moved by ``dz`` along z."""
    trsf = occ.gp_Trsf()
    trsf.SetTranslation(occ.gp_Vec(0.0, 0.0, dz))
    return occ.BRepBuilderAPI_Transform(shape, trsf, True).Shape()


@SOLIDS.register(SpatialIndexerDesign)
class SpatialSolids:
    """The barrel or globoidal indexer's cam in the output frame: :func:`spatial_solid` (the design's
    frame, centred on z = 0) moved up by W/2 so that the cam spans 0 ≤ z ≤ W (``cam.thickness``) as
    every body's solid does; its volume held to the grid integral of the exact envelope."""

    @staticmethod
    def solid(design: Any, exact_offset: bool) -> Any:
        """The cam as one ``TopoDS_Solid`` (``exact_offset`` changes nothing: the flanks are the fitted
        surfaces, which STEP holds as they are).

        Raises:
            GeometryError: OCCT could not build it (kind "kernel", which step)."""
        spec = design.spec
        try:
            solid = spatial_solid(design.geometry, design.surfaces, 0.5 * float(spec.cam.bore_diameter))
        except RuntimeError as exc:
            raise GeometryError("kernel", f"OCCT could not build the {spec.cam.body.replace('_', ' ')}'s cam: "
                                f"{exc}") from None
        return _shifted(solid, 0.5 * float(spec.cam.thickness))

    @staticmethod
    def measures(design: Any, shape: Any) -> dict[str, Any]:
        """Nothing beyond what :meth:`verify` measures."""
        return {}

    @staticmethod
    def verify(design: Any, shape: Any, step_shape: Any) -> dict[str, Any]:
        """OCCT's adaptive volume (ε = :data:`~.solids.SURFACE_VOLUME_EPS` per face) against the core's
        closed form plus the rib integrated on a grid of the exact envelope
        (``design.volume_estimate``: :func:`~cam_workbench.generators.bodies.indexing.spatial_volume.cam_volume`), allowed their
        two errors and the flank surfaces' fit error over the flanks' area (2·A·e, A ≈ 2·W·depth
        per flank, bounded above by the band's area).

        Raises:
            GeometryError: kind "kernel", the volumes beyond the allowance."""
        spec = design.spec
        est = design.volume_estimate
        got = kernel_volume(shape, SURFACE_VOLUME_EPS)
        ix = design.geometry.indexer
        depth = (float(ix.outer_radius) - float(ix.root_radius) if _is_barrel(ix)
                 else float(ix.root_radius) - float(ix.tip_radius))
        # each flank's area is at most the band's depth times its length along the rib (< 2π·R·(turns + 1))
        reach = float(ix.outer_radius) if _is_barrel(ix) else float(ix.centre_distance) - float(ix.tip_radius)
        flank_area = 2.0 * depth * TWO_PI * reach * 2.0
        allowed = (est.error + flank_area * design.fit_error) / est.value + 2 * SURFACE_VOLUME_EPS
        rel = got / est.value - 1.0
        if not abs(rel) <= allowed:
            raise GeometryError("kernel", f"OCCT's solid of the cam has the volume {got:.10g} mm³, the grid integral of "
                                f"the exact envelope gives {est.value:.10g} mm³: {rel:+.3e} relative, beyond the "
                                f"{allowed:.2g} their errors allow — the solid is not the cam's")
        return {"kernel_volume": got, "design_volume": est.value, "volume_rel_diff": rel,
                "volume_rule": {"what": "OCCT's adaptive integration (ε = 1e-6 per face) against " + est.what,
                                "allowed": allowed},
                "frame": "the design's frame moved up by W/2: the cam spans 0 ≤ z ≤ cam.thickness"}


__all__ = ["END_CLEARANCE", "ROOT_OVERLAP", "ExtendedFlank", "SpatialBuild", "band_margin", "band_solid",
           "SpatialSolids", "build_spatial_solid", "core_overlap", "core_solid", "extended_flank", "project_radially", "radial_coordinate",
           "seam_angle", "sheet_shell", "spatial_solid", "surface_geom"]

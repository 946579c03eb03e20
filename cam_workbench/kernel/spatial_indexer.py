"""The spatial indexers' cams (barrel and globoidal) as one OCCT solid through OCP: the core (the root
cylinder, or the solid of revolution inside the root globoid) and the rib between its two flank
surfaces (:mod:`cam_workbench.generators.bodies.indexing.spatial_surfaces`), trimmed to the rib's
band (:mod:`cam_workbench.generators.bodies.indexing.spatial`: barrel root ≤ ρ ≤ outer, globoid
tip ≤ g ≤ root, and |z| ≤ W/2).

Construction (:func:`spatial_solid`; lengths in mm, angles in radians, the cam frame):

1. Each flank (side ±1) becomes a sheet that cuts clean through the band — its boundary outside
   the band: the fitted surface continued along the exact envelope at both τ ends (the FLANK
   face), its ruled SKIRT beyond the rib's root and, where the fitted surface's top edge is not
   clear of the band, its TOP face — B-spline data computed in plain numpy by
   :func:`~cam_workbench.generators.bodies.indexing.spatial_sheets.extended_flank` (that module's
   docstring gives the sheets, their constants and orientations), here made into
   ``Geom_BSplineSurface`` faces of exactly those poles and knots (:func:`surface_geom`).

   Each side's faces are sewn into one shell.

2. The band — the annulus root ≤ ρ ≤ outer, |z| ≤ W/2 (barrel), or the revolution of the region
   tip ≤ g ≤ root, |z| ≤ W/2 about the cam axis (globoid), reaching
   :func:`~cam_workbench.generators.bodies.indexing.spatial_sheets.core_overlap` (half the skirts'
   reach) beyond the root into the core — is split by the two sheets
   (``BRepAlgoAPI_Splitter``).  A piece is rib where the roller's normal n (into the rib) points
   into it: on each of its flank or skirt faces the piece's outward normal is −n.

3. The rib pieces are fused with the core (the root cylinder, or the revolution of
   ρ ≤ C − √(root² − z²), |z| ≤ W/2; less a bore of ``bore_radius``), which they overlap, and the
   faces lying on one surface merged (``ShapeUpgrade_UnifySameDomain``): one solid, checked by
   ``BRepCheck``.

The band and the core are solids of revolution; their seams lie at the angle
:func:`~cam_workbench.generators.bodies.indexing.spatial_sheets.seam_angle` picks, where the sheets
crossing the seam's half-plane are farthest from the cam's end planes — not at a fixed φ: the
places where the rib's thread leaves the band turn with the index start, and OCCT's intersection
of a sheet with the band's periodic faces loses a branch where the sheet crosses the seam near an
end plane (the band then does not split into rib and grooves), and its fuse of solids sharing the
root surface (as the band once did with the core) failed for some seam angles (+9.7 % volume, or
the rib alone).  Measured: the default indexers at index starts 0°, 60°, 137°, 300° give one
volume to 4e-9.

Measured (default ``BarrelIndexer()`` / ``GloboidalIndexer()``, design samples 361): ~4 s / ~5 s
(the split ~2.5 s, the fuse ~1.3 s); 12 / 11 faces; edge tolerances ≤ 7e-4 mm.
"""
from __future__ import annotations

import math
import time
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, Iterator

from cam_workbench.generators.bodies.indexing.spatial import TWO_PI, BarrelIndexer, GloboidalIndexer, SpatialDesign
from cam_workbench.generators.bodies.indexing.spatial_kind import SpatialIndexerDesign
from cam_workbench.generators.bodies.indexing.spatial_sheets import (ExtendedFlank, core_overlap, extended_flank,
                                                                     is_barrel, seam_angle)
from cam_workbench.generators.bodies.indexing.spatial_surfaces import BSplineSurface, FlankSurfaces
from cam_workbench.generators.errors import GeometryError

from . import ocp as occ
from .solids import SOLIDS, SURFACE_VOLUME_EPS, faces_of, general_op, is_valid, kernel_volume, solids_of

#: sewing tolerance [mm] of each side's two faces (their common edge is the same pole row)
SEW_TOLERANCE = 1e-6


def surface_geom(surface: BSplineSurface) -> Any:
    """A ``Geom_BSplineSurface`` with exactly the data (poles, knots, degrees) of ``surface``
    (polynomial: the fitted flanks and their continuations carry unit weights)."""
    ku, mu, kv, mv = surface.distinct_knots()
    return occ.Geom_BSplineSurface(occ.pnt_array2(surface.poles.tolist()), occ.real_array(ku.tolist()),
                                   occ.real_array(kv.tolist()), occ.int_array(mu.tolist()), occ.int_array(mv.tolist()),
                                   surface.degree_u, surface.degree_v, False, False)


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
    revolution of tip ≤ g ≤ root, |z| ≤ W/2), its seam at φ = ``seam`` [rad]
    (``spatial_sheets.seam_angle``), reaching ``overlap`` [mm] beyond the root into the core (barrel
    ρ ≥ root − overlap, globoid g ≤ root + overlap; ``spatial_sheets.core_overlap``)."""
    h = 0.5 * float(ix.cam_width)
    d = float(overlap)
    if is_barrel(ix):
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
    [rad] (``spatial_sheets.seam_angle``)."""
    h = 0.5 * float(ix.cam_width)
    rb = float(bore_radius)
    if is_barrel(ix):
        r0 = float(ix.root_radius)
        prof = [_segment((rb, -h), (r0, -h)), _segment((r0, -h), (r0, h)), _segment((r0, h), (rb, h))]
    else:
        c, rr = float(ix.centre_distance), float(ix.root_radius)
        lo, hi = (c - math.sqrt(rr**2 - h**2), -h), (c - math.sqrt(rr**2 - h**2), h)
        prof = [_segment((rb, -h), lo), _arc(c, rr, lo, hi), _segment(hi, (rb, h))]
    # the bore's line, or (rb = 0) the axis: OCCT revolves an edge on the axis into nothing
    prof.append(_segment((rb, h), (rb, -h)))
    return _revolved(prof, seam)



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
    """What :func:`build_spatial_solid` made: the ``solid``; the two sheets
    (``spatial_sheets.ExtendedFlank``); the band's pieces (``rib_pieces``, ``groove_pieces``);
    ``seconds`` by stage; ``seam`` [rad], the band's and the core's seam angle
    (``spatial_sheets.seam_angle``)."""

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
    inner = float(ix.root_radius) if is_barrel(ix) else float(ix.centre_distance) - float(ix.root_radius)
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
        est = design.volume_estimate
        got = kernel_volume(shape, SURFACE_VOLUME_EPS)
        ix = design.geometry.indexer
        depth = (float(ix.outer_radius) - float(ix.root_radius) if is_barrel(ix)
                 else float(ix.root_radius) - float(ix.tip_radius))
        # each flank's area is at most the band's depth times its length along the rib (< 2π·R·(turns + 1))
        reach = float(ix.outer_radius) if is_barrel(ix) else float(ix.centre_distance) - float(ix.tip_radius)
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


__all__ = ["SEW_TOLERANCE", "SpatialBuild", "SpatialSolids", "band_solid", "build_spatial_solid", "core_solid",
           "sheet_shell", "spatial_solid", "surface_geom"]

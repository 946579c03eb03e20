"""The cylindrical (barrel) cam's solid through OCP, without a boolean where its faces are known:
the body's stack of prisms (:func:`~.solids.prism_stack`, itself sewn from its levels) with its outer
cylindrical face replaced by the groove's faces, sewn into one shell (:func:`sewn_groove_solid`, 0.05 s);
the split of an annulus by the wall surfaces, cut from the stack (:func:`boolean_groove_solid`, ~1 s),
only where those faces do not close.  And the measure of the built walls against the exact ones.
Registered in :data:`cam_workbench.kernel.solids.SOLIDS` for
:class:`~cam_workbench.generators.bodies.cylindrical.CylindricalDesign`.

The groove's faces (the same in FreeCAD, :mod:`cam_workbench.freecad.part_cylindrical`):

* each wall surface's isoparametric patch R_b ≤ ρ ≤ R_o — its v-parameter is ρ, the radius of the
  exact points it interpolates, and R_b, R_o are nodes of its ρ-grid, so the patch's edges there
  interpolate exact points of those cylinders: they lie within the walls' fit error of them;
* the groove's bottom, on the cylinder R_b between the two walls' traces ρ = R_b;
* the cylinder's outer face R_o below the lower wall's trace ρ = R_o and above the upper one's,
  each bounded by the circle at that end of the stack's outer face (which they replace).

The cylinder faces get their plane curves and seam from OCCT's ``ShapeFix_Face``, each seam through
the first vertex of a trace that bounds the face; sewing joins every face along its edges
(:data:`~cam_workbench.generators.bodies.cylindrical.SEW_TOLERANCE`).
"""
from __future__ import annotations

from typing import Any

import numpy as np

from cam_workbench.generators.bodies.cylindrical import (FIX_MAX_TOLERANCE, FIX_PRECISION, SEW_TOLERANCE,
                                                          CylindricalDesign, CylindricalGeometry)

from . import ocp as occ
from .solids import SOLIDS, boolean, faces_of, general_op, prism_stack, sewn_solid, solids_of, verify_exact


def wall_surface_geom(wall: Any) -> Any:
    """A ``Geom_BSplineSurface`` with exactly the data of a body's wall surface
    (:class:`cam_workbench.generators.bodies.cylindrical.WallSurface`: full knot vectors, poles (n_u, n_v, 3))."""
    ku, mu = np.unique(wall.knots_u, return_counts=True)
    kv, mv = np.unique(wall.knots_v, return_counts=True)
    return occ.Geom_BSplineSurface(occ.pnt_array2(wall.poles.tolist()), occ.real_array(ku.tolist()),
                                   occ.real_array(kv.tolist()), occ.int_array(mu.tolist()), occ.int_array(mv.tolist()),
                                   wall.degree_u, wall.degree_v, False, False)


def wall_faces(geometry: Any) -> list[tuple[Any, Any]]:
    """(wall surface data, ``TopoDS_Face`` on its natural bounds) for every wall face."""
    out = []
    for wall in geometry.walls:
        mk = occ.BRepBuilderAPI_MakeFace(wall_surface_geom(wall), 1e-7)
        if not mk.IsDone():
            raise RuntimeError("OCCT could not make a face from a groove wall surface")
        out.append((wall, mk.Face()))
    return out


def _sewn_shell(faces: list[Any], tolerance: float = SEW_TOLERANCE) -> Any:
    sew = occ.BRepBuilderAPI_Sewing(tolerance)
    for f in faces:
        sew.Add(f)
    sew.Perform()
    return sew.SewedShape()


def _cylinder(radius: float, z0: float, z1: float) -> Any:
    ax = occ.gp_Ax2(occ.gp_Pnt(0, 0, z0), occ.gp_Dir(0, 0, 1))
    return occ.BRepPrimAPI_MakeCylinder(ax, radius, z1 - z0).Shape()


def _wire(edges: list[Any]) -> Any:
    mk = occ.BRepBuilderAPI_MakeWire()
    for e in edges:
        mk.Add(e)
    if not mk.IsDone():
        raise RuntimeError("OCCT could not join a groove wall's traces into a wire")
    return mk.Wire()


def _circle_wire(radius: float, z: float, angle: float) -> Any:
    """A full circle about the Z axis at height ``z`` as a wire, its vertex at the polar ``angle`` [rad]."""
    axes = occ.gp_Ax2(occ.gp_Pnt(0, 0, z), occ.gp_Dir(0, 0, 1), occ.gp_Dir(np.cos(angle), np.sin(angle), 0))
    return occ.BRepBuilderAPI_MakeWire(occ.BRepBuilderAPI_MakeEdge(occ.gp_Circ(axes, radius)).Edge()).Wire()


def cylinder_face(radius: float, first: Any, second: Any, angle: float) -> Any:
    """The face on the cylinder of ``radius`` [spec length] about the Z axis between two wires that
    go round it, the cylinder's seam at the polar ``angle`` [rad] (``ShapeFix_Face`` adds their plane
    curves and the seam)."""
    axes = occ.gp_Ax3(occ.gp_Pnt(0, 0, 0), occ.gp_Dir(0, 0, 1), occ.gp_Dir(np.cos(angle), np.sin(angle), 0))
    mk = occ.BRepBuilderAPI_MakeFace(occ.Geom_CylindricalSurface(axes, radius), first, True)
    mk.Add(second)
    fix = occ.ShapeFix_Face(mk.Face())
    fix.SetPrecision(FIX_PRECISION)
    fix.SetMinTolerance(FIX_PRECISION)
    fix.SetMaxTolerance(FIX_MAX_TOLERANCE)
    fix.Perform()
    return fix.Face()


def groove_faces(geometry: CylindricalGeometry) -> tuple[list[Any], dict[tuple[int, float], tuple[Any, float]]]:
    """(the walls' faces: each wall surface's patch R_b ≤ ρ ≤ R_o; per (side, radius) the wall's
    trace ρ = R_b or R_o as a wire, its edges the patches' iso-curves, with the polar angle [rad] of
    its first vertex, at θ of the first motion segment's start)."""
    lay = geometry.layout
    radii = (lay.bottom_radius, lay.outer_radius)
    faces, edges, angles = [], {}, {}
    for wall in geometry.walls:
        surface = wall_surface_geom(wall)
        u0, u1 = wall.u_range
        mk = occ.BRepBuilderAPI_MakeFace(surface, u0, u1, *radii, 1e-7)
        if not mk.IsDone():
            raise RuntimeError("OCCT could not make a face from a groove wall surface")
        faces.append(mk.Face())
        for rho in radii:
            curve = surface.VIso(rho)
            edges.setdefault((wall.side, rho), []).append(occ.BRepBuilderAPI_MakeEdge(curve, u0, u1).Edge())
            if wall.segment == 0:
                start = curve.Value(u0)
                angles[(wall.side, rho)] = float(np.arctan2(start.Y(), start.X()))
    return faces, {key: (_wire(e), angles[key]) for key, e in edges.items()}


def _outer_side(stack: Any, radius: float, z_lo: float, z_hi: float) -> tuple[list[Any], float, float] | None:
    """(the faces of ``stack`` but its outer cylindrical face — the one of ``radius`` whose circles
    lie below ``z_lo`` and above ``z_hi`` —, the heights of that face's two circles; spec lengths),
    or None when there is not one such face."""
    kept, found = [], []
    for face in faces_of(stack):
        surf = occ.BRepAdaptor_Surface(face)
        circles = []
        if surf.GetType() == occ.GeomAbs_Cylinder and abs(surf.Cylinder().Radius() - radius) <= 1e-9 * radius:
            ex = occ.TopExp_Explorer(face, occ.TopAbs_EDGE)
            while ex.More():
                curve = occ.BRepAdaptor_Curve(occ.topods_edge(ex.Current()))
                if curve.GetType() == occ.GeomAbs_Circle:
                    circles.append(curve.Circle().Location().Z())
                ex.Next()
            circles.sort()
        if len(circles) == 2 and circles[0] < z_lo and circles[1] > z_hi:
            found.append((circles[0], circles[1]))
        else:
            kept.append(face)
    if len(found) != 1:
        return None
    return kept, *found[0]


def sewn_groove_solid(design: CylindricalDesign) -> Any | None:
    """The cylindrical cam as a ``TopoDS_Solid`` sewn from the stack's faces and the groove's (see the
    module docstring), or None when they do not close into one shell (then :func:`cylindrical_solid`
    uses :func:`boolean_groove_solid`)."""
    geo = design.body
    lay = geo.layout
    z_lo, z_hi = lay.path.z_range()
    outer = _outer_side(prism_stack(geo.stack), lay.outer_radius, z_lo - lay.half_width, z_hi + lay.half_width)
    if outer is None:
        return None
    kept, z_bottom, z_top = outer
    walls, traces = groove_faces(geo)
    rb, ro = lay.bottom_radius, lay.outer_radius
    (lower_b, at_b), (upper_b, _) = traces[(-1, rb)], traces[(1, rb)]
    (lower_o, at_lo), (upper_o, at_up) = traces[(-1, ro)], traces[(1, ro)]
    # each cylinder face's seam through the first vertex of a trace that bounds it, the outer faces' circles
    # given their vertex there too: a seam elsewhere splits edges, which FreeCAD's sewing does not always join
    bands = [cylinder_face(rb, lower_b, upper_b, at_b),
             cylinder_face(ro, _circle_wire(ro, z_bottom, at_lo), lower_o, at_lo),
             cylinder_face(ro, upper_o, _circle_wire(ro, z_top, at_up), at_up)]
    return sewn_solid(kept + walls + bands, SEW_TOLERANCE, closed=True)


def boolean_groove_solid(design: CylindricalDesign) -> Any:
    """The cylindrical cam by booleans: the groove cut out of an annulus spanning a little more than
    the groove's depth (the walls' radial range) by the two walls — each one shell sewn from its
    per-segment B-spline faces — with ``BRepAlgoAPI_Splitter``; the piece between the walls (the
    one that holds the pitch point at θ = 0), cut from the body's stack of prisms."""
    geo = design.body
    lay = geo.layout
    margin = 0.5 * (lay.outer_radius - lay.bottom_radius)
    annulus = boolean(occ.BRepAlgoAPI_Cut, _cylinder(lay.outer_radius + 0.5 * (geo.wall_rho[1] - lay.outer_radius),
                                                      -margin, lay.length + margin),
                       _cylinder(lay.bottom_radius, -2 * margin, lay.length + 2 * margin))
    faces = wall_faces(geo)
    shells = [_sewn_shell([f for w, f in faces if w.side == side]) for side in (-1, 1)]
    split_shape = general_op(occ.BRepAlgoAPI_Splitter, [annulus], shells, "split the annulus by the groove walls")
    # the pitch point at θ = 0: midway between the walls
    centre = occ.gp_Pnt(*lay.centre_point(design.program, 0.0))
    groove = None
    for piece in solids_of(split_shape):
        cls = occ.BRepClass3d_SolidClassifier(piece, centre, 1e-7)
        if cls.State() == occ.TopAbs_IN:
            groove = piece
            break
    if groove is None:
        raise RuntimeError("the groove walls did not split the annulus (no piece holds the pitch point)")
    shape = boolean(occ.BRepAlgoAPI_Cut, prism_stack(geo.stack), groove)
    solids = solids_of(shape)
    return solids[0] if len(solids) == 1 else shape


def cylindrical_solid(design: CylindricalDesign) -> Any:
    """The cylindrical cam as a ``TopoDS_Solid``: the cylinder (bored and keyed, with its hub, mounting
    holes and timing mark: the body's ``stack`` of prisms) less the groove — sewn from its faces
    (:func:`sewn_groove_solid`), else by booleans (:func:`boolean_groove_solid`)."""
    solid = sewn_groove_solid(design)
    return solid if solid is not None else boolean_groove_solid(design)


def cylindrical_wall_error(design: Any, shape: Any, per_direction: int = 15) -> dict[str, Any]:
    """Distance of the built wall faces of ``shape`` from the exact walls: every B-spline face
    sampled on a grid of its own (u, v) range (OCCT's evaluator), each point's distance from the
    exact wall of its side (:meth:`CylindricalDesign.wall_distance_error`, the developed offset at
    the point's radius) — the side the wall nearer to the face's first point (the other lies a
    groove's width away)."""
    lay = design.body.layout
    grids = []
    for face in faces_of(shape):
        surf = occ.BRepAdaptor_Surface(face)
        if surf.GetType() == occ.GeomAbs_BSplineSurface:
            u = np.linspace(surf.FirstUParameter(), surf.LastUParameter(), per_direction)
            v = np.linspace(surf.FirstVParameter(), surf.LastVParameter(), per_direction)
            grids.append(np.array([(p.X(), p.Y(), p.Z()) for p in (surf.Value(a, b) for a in u for b in v)]))
    worst, n = 0.0, 0
    if grids:
        first = np.array([g[0] for g in grids])
        sides = np.where(design.wall_distance_error(-1, first) <= design.wall_distance_error(1, first), -1, 1)
        for side in (-1, 1):
            mine = [g for g, s in zip(grids, sides) if s == side]
            if not mine:
                continue
            pts = np.concatenate(mine)
            err = design.wall_distance_error(side, pts)
            rho = np.hypot(pts[:, 0], pts[:, 1])
            inside = (rho >= lay.bottom_radius - 1e-6) & (rho <= lay.outer_radius + 1e-6)
            worst = max(worst, float(np.max(err[inside])) if inside.any() else 0.0)
            n += int(inside.sum())
    return {"value": worst, "unit": design.spec.units, "faces": len(grids), "points": n,
            "what": "built B-spline wall faces (OCCT's evaluator) vs the exact walls (developed offsets at each "
                    "point's radius)"}


@SOLIDS.register(CylindricalDesign)
class CylindricalSolids:
    """The cylindrical cam's solid (:func:`cylindrical_solid`; it has no offset profile, so
    ``exact_offset`` changes nothing) and its walls' distance from the exact ones."""

    verify = staticmethod(verify_exact)

    @staticmethod
    def solid(design: Any, exact_offset: bool) -> Any:
        return cylindrical_solid(design)

    @staticmethod
    def measures(design: Any, shape: Any) -> dict[str, Any]:
        return {"wall_error": cylindrical_wall_error(design, shape)}

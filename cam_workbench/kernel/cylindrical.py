"""The cylindrical (barrel) cam's solid through OCP: its wall surfaces as OCCT B-spline faces,
the groove split out of an annulus by them and cut from the cylinder's prisms; and the measure of
the built walls against the exact ones.  Registered in :data:`cam_workbench.kernel.solids.SOLIDS`
for :class:`~cam_workbench.generators.bodies.cylindrical.CylindricalDesign`.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from cam_workbench.generators.bodies.cylindrical import CylindricalDesign

from . import ocp as occ
from .solids import SOLIDS, boolean, prism_stack, solids_of


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


def _sewn_shell(faces: list[Any], tolerance: float = 1e-6) -> Any:
    sew = occ.BRepBuilderAPI_Sewing(tolerance)
    for f in faces:
        sew.Add(f)
    sew.Perform()
    return sew.SewedShape()


def _cylinder(radius: float, z0: float, z1: float) -> Any:
    ax = occ.gp_Ax2(occ.gp_Pnt(0, 0, z0), occ.gp_Dir(0, 0, 1))
    return occ.BRepPrimAPI_MakeCylinder(ax, radius, z1 - z0).Shape()


def cylindrical_solid(design: Any) -> Any:
    """The cylindrical cam as a ``TopoDS_Solid``: the cylinder (bored and keyed, with its hub, mounting
    holes and timing mark: the body's ``stack`` of prisms) minus the groove.

    The groove is cut out of an annulus spanning a little more than the groove's depth
    (the walls' radial range) by the two walls — each one shell sewn from its per-segment
    B-spline faces — with ``BRepAlgoAPI_Splitter``; the piece between the walls (the one that holds
    the pitch point at θ = 0) is the groove, cut from the cylinder."""
    geo = design.body
    lay = geo.layout
    margin = 0.5 * (lay.outer_radius - lay.bottom_radius)
    annulus = boolean(occ.BRepAlgoAPI_Cut, _cylinder(lay.outer_radius + 0.5 * (geo.wall_rho[1] - lay.outer_radius),
                                                      -margin, lay.length + margin),
                       _cylinder(lay.bottom_radius, -2 * margin, lay.length + 2 * margin))
    faces = wall_faces(geo)
    tools = occ.ListOfShape()
    for side in (-1, 1):
        tools.Append(_sewn_shell([f for w, f in faces if w.side == side]))
    args = occ.ListOfShape()
    args.Append(annulus)
    split = occ.BRepAlgoAPI_Splitter()
    split.SetArguments(args)
    split.SetTools(tools)
    split.Build()
    if not split.IsDone():
        raise RuntimeError("OCCT could not split the annulus by the groove walls")
    # the pitch point at θ = 0: midway between the walls
    centre = occ.gp_Pnt(*lay.centre_point(design.program, 0.0))
    groove = None
    for piece in solids_of(split.Shape()):
        cls = occ.BRepClass3d_SolidClassifier(piece, centre, 1e-7)
        if cls.State() == occ.TopAbs_IN:
            groove = piece
            break
    if groove is None:
        raise RuntimeError("the groove walls did not split the annulus (no piece holds the pitch point)")
    shape = boolean(occ.BRepAlgoAPI_Cut, prism_stack(geo.stack), groove)
    solids = solids_of(shape)
    return solids[0] if len(solids) == 1 else shape


def cylindrical_wall_error(design: Any, shape: Any, per_direction: int = 15) -> dict[str, Any]:
    """Distance of the built wall faces of ``shape`` from the exact walls: every B-spline face
    sampled on a grid of its own (u, v) range (OCCT's evaluator), each point's distance from the
    exact wall of its side (:meth:`CylindricalDesign.wall_distance_error`, the developed offset at
    the point's radius) — the side told by which wall's surface the face lies on."""
    lay = design.body.layout
    worst, faces, n = 0.0, 0, 0
    fx = occ.TopExp_Explorer(shape, occ.TopAbs_FACE)
    while fx.More():
        face = occ.topods_face(fx.Current())
        surf = occ.BRepAdaptor_Surface(face)
        if surf.GetType() == occ.GeomAbs_BSplineSurface:
            u = np.linspace(surf.FirstUParameter(), surf.LastUParameter(), per_direction)
            v = np.linspace(surf.FirstVParameter(), surf.LastVParameter(), per_direction)
            pts = np.array([[surf.Value(a, b).X(), surf.Value(a, b).Y(), surf.Value(a, b).Z()] for a in u for b in v])
            err = np.minimum(design.wall_distance_error(-1, pts), design.wall_distance_error(1, pts))
            rho = np.hypot(pts[:, 0], pts[:, 1])
            inside = (rho >= lay.bottom_radius - 1e-6) & (rho <= lay.outer_radius + 1e-6)
            worst = max(worst, float(np.max(err[inside])) if inside.any() else 0.0)
            faces += 1
            n += int(inside.sum())
        fx.Next()
    return {"value": worst, "unit": design.spec.units, "faces": faces, "points": n,
            "what": "built B-spline wall faces (OCCT's evaluator) vs the exact walls (developed offsets at each "
                    "point's radius)"}


@SOLIDS.register(CylindricalDesign)
class CylindricalSolids:
    """The cylindrical cam's solid (:func:`cylindrical_solid`; it has no offset profile, so
    ``exact_offset`` changes nothing) and its walls' distance from the exact ones."""

    @staticmethod
    def solid(design: Any, exact_offset: bool) -> Any:
        return cylindrical_solid(design)

    @staticmethod
    def measures(design: Any, shape: Any) -> dict[str, Any]:
        return {"wall_error": cylindrical_wall_error(design, shape)}

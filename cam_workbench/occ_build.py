"""OCP adaptor: neutral NURBS data → OCCT edges, faces and the cam solid.

This is the only place the CadQuery/build123d side turns generator output into
B-rep; FreeCAD has its own adaptor in ``cam_workbench/freecad`` (never both OCCT
builds in one process).
"""
from __future__ import annotations

from typing import Any

import numpy as np

from generators.cam_design import CamDesign
from generators.nurbs import NurbsCurve
from generators.pitch_bspline import bezier_form


def _occ_arrays(curve: NurbsCurve, pole_array: Any, point: Any) -> tuple[Any, Any, Any, Any]:
    """OCCT arrays (poles, weights, distinct knots, multiplicities) of ``curve``; ``point(x, y)``
    makes one pole (gp_Pnt or gp_Pnt2d)."""
    from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal

    n = curve.n_poles
    poles = pole_array(1, n)
    weights = TColStd_Array1OfReal(1, n)
    for i, ((x, y), w) in enumerate(zip(curve.poles.tolist(), curve.weights.tolist()), start=1):
        poles.SetValue(i, point(x, y))
        weights.SetValue(i, w)
    u, mult = curve.distinct_knots()
    knots = TColStd_Array1OfReal(1, len(u))
    mults = TColStd_Array1OfInteger(1, len(u))
    for i, (k, m) in enumerate(zip(u.tolist(), mult.tolist()), start=1):
        knots.SetValue(i, k)
        mults.SetValue(i, int(m))
    return poles, weights, knots, mults


def nurbs_to_geom(curve: NurbsCurve, z: float = 0.0) -> Any:
    """A ``Geom_BSplineCurve`` with exactly the poles, weights, knots and degree of ``curve``."""
    from OCP.Geom import Geom_BSplineCurve
    from OCP.gp import gp_Pnt
    from OCP.TColgp import TColgp_Array1OfPnt

    poles, weights, knots, mults = _occ_arrays(curve, TColgp_Array1OfPnt, lambda x, y: gp_Pnt(x, y, z))
    if curve.is_rational:
        return Geom_BSplineCurve(poles, weights, knots, mults, curve.degree, False)
    return Geom_BSplineCurve(poles, knots, mults, curve.degree, False)


def nurbs_to_edge(curve: NurbsCurve, z: float = 0.0) -> Any:
    """A ``TopoDS_Edge`` on the exact NURBS curve."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge

    mk = BRepBuilderAPI_MakeEdge(nurbs_to_geom(curve, z))
    if not mk.IsDone():
        raise RuntimeError("OCCT could not make an edge from the NURBS profile")
    return mk.Edge()


def profile_wire(curve: NurbsCurve, z: float = 0.0) -> Any:
    """A closed wire of exact rational Bézier edges, one per knot span of ``curve``.

    One edge per PH segment rather than one multi-span edge: OCCT's mass-property
    integration is exact to ~1e-15 on Bézier edges but only ~1e-3 on a 60-span
    degree-9 edge (measured), and FreeCAD, CAD importers and our own checks all
    use those integrals.  A curve with simple interior knots (a fitted B-spline) is first
    brought to Bézier form by exact knot insertion, for the same reason."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeWire

    mk = BRepBuilderAPI_MakeWire()
    pieces = curve.bezier_pieces()
    if len(pieces) == 1 and len(np.unique(curve.knots)) > 2:
        pieces = bezier_form(curve).bezier_pieces()     # exact knot insertion, no refit
    for piece in pieces:
        mk.Add(nurbs_to_edge(piece, z))
    if not mk.IsDone():
        raise RuntimeError("OCCT could not join the profile edges into a wire")
    wire = mk.Wire()
    if not wire.Closed():
        raise RuntimeError("the profile wire is not closed")
    return wire


def circle_wire(radius: float, z: float = 0.0) -> Any:
    """A full circle about the Z axis as a wire."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire
    from OCP.gp import gp_Ax2, gp_Circ, gp_Dir, gp_Pnt

    circ = gp_Circ(gp_Ax2(gp_Pnt(0, 0, z), gp_Dir(0, 0, 1)), radius)
    return BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(circ).Edge()).Wire()


def profile_face(profile_ccw: NurbsCurve, bore_radius: float = 0.0, z: float = 0.0) -> Any:
    """The planar cam cross-section: the exact profile as the outer boundary, the bore as a hole."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.TopoDS import TopoDS

    mk = BRepBuilderAPI_MakeFace(profile_wire(profile_ccw, z), True)
    if not mk.IsDone():
        raise RuntimeError("OCCT could not make a planar face from the profile")
    if bore_radius > 0:
        mk.Add(TopoDS.Wire_s(circle_wire(bore_radius, z).Reversed()))
    return mk.Face()


def nurbs_to_geom2d(curve: NurbsCurve) -> Any:
    """A ``Geom2d_BSplineCurve`` (x, y) with exactly the data of ``curve``."""
    from OCP.Geom2d import Geom2d_BSplineCurve
    from OCP.gp import gp_Pnt2d
    from OCP.TColgp import TColgp_Array1OfPnt2d

    poles, weights, knots, mults = _occ_arrays(curve, TColgp_Array1OfPnt2d, gp_Pnt2d)
    if curve.is_rational:
        return Geom2d_BSplineCurve(poles, weights, knots, mults, curve.degree, False)
    return Geom2d_BSplineCurve(poles, knots, mults, curve.degree, False)


def offset_profile_face(design: CamDesign, z: float = 0.0) -> Any:
    """The cross-section of a ``pitch.representation = "bspline"`` cam with the profile as OCCT's
    exact offset (``Geom_OffsetCurve``) of the fitted pitch B-spline, counter-clockwise.

    One edge per knot span (trimmed from the one offset curve: OCCT integrates areas and volumes
    of multi-span edges poorly), each with its exact plane curve (``Geom2d_OffsetCurve`` of the
    same B-spline) so that BRepCheck accepts the face — the pcurves OCCT projects itself miss
    the offset by ~5e-7 and fail it."""
    from OCP.BRep import BRep_Builder
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeWire
    from OCP.Geom import Geom_OffsetCurve
    from OCP.Geom2d import Geom2d_OffsetCurve
    from OCP.gp import gp_Ax3, gp_Dir, gp_Pln, gp_Pnt
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    assert design.bspline is not None
    basis = design.pitch_nurbs
    distance = design.bspline.offset_distance            # + = left of the pitch curve's travel
    clockwise = basis.area() < 0
    if clockwise:                                        # travel reversed: left ↔ right
        basis, distance = basis.reversed(), -distance
    occ_offset = -distance                               # OCCT: + = T × Z, the right-hand side
    curve3d = Geom_OffsetCurve(nurbs_to_geom(basis, z), occ_offset, gp_Dir(0, 0, 1))
    curve2d = Geom2d_OffsetCurve(nurbs_to_geom2d(basis), occ_offset)
    mk = BRepBuilderAPI_MakeWire()
    u = np.unique(basis.knots)
    for a, b in zip(u[:-1].tolist(), u[1:].tolist()):
        mk.Add(BRepBuilderAPI_MakeEdge(curve3d, a, b).Edge())
    plane = gp_Pln(gp_Ax3(gp_Pnt(0, 0, z), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0)))   # (u, v) = (x, y)
    mf = BRepBuilderAPI_MakeFace(plane, mk.Wire(), True)
    if not mf.IsDone():
        raise RuntimeError("OCCT could not make a planar face from the offset profile")
    face = mf.Face()
    builder = BRep_Builder()
    ex = TopExp_Explorer(face, TopAbs_EDGE)
    while ex.More():
        edge = TopoDS.Edge_s(ex.Current())
        builder.UpdateEdge(edge, curve2d, face, 1e-7)
        builder.SameParameter(edge, True)
        builder.SameRange(edge, True)
        ex.Next()
    bore = design.spec.cam.bore_diameter / 2
    if bore > 0:
        mf2 = BRepBuilderAPI_MakeFace(face)
        mf2.Add(TopoDS.Wire_s(circle_wire(bore, z).Reversed()))
        face = mf2.Face()
    return face


def cam_solid(design: CamDesign, exact_offset: bool = True) -> Any:
    """The cam as a ``TopoDS_Solid``: the exact profile face extruded by the thickness, with the bore.

    For ``pitch.representation = "bspline"`` the profile is OCCT's exact offset of the fitted
    pitch B-spline (``exact_offset``) or the fitted offset B-spline ``design.profile``
    (``exact_offset=False``: what STEP can hold — OCCT's STEP writer has no mapping for
    offset curves and writes an empty model)."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism
    from OCP.gp import gp_Vec
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    if exact_offset and design.bspline is not None and design.spec.roller_radius > 0:
        face = offset_profile_face(design)
    else:
        face = profile_face(design.profile_ccw(), design.spec.cam.bore_diameter / 2)
    prism = BRepPrimAPI_MakePrism(face, gp_Vec(0, 0, design.spec.cam.thickness), True)
    shape = prism.Shape()
    exp = TopExp_Explorer(shape, TopAbs_SOLID)
    solid = TopoDS.Solid_s(exp.Current())
    return solid


def is_valid(shape: Any) -> bool:
    """OCCT's full topological and geometric check (``BRepCheck_Analyzer``)."""
    from OCP.BRepCheck import BRepCheck_Analyzer

    return bool(BRepCheck_Analyzer(shape).IsValid())


def count_solids(shape: Any) -> int:
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    exp = TopExp_Explorer(shape, TopAbs_SOLID)
    n = 0
    while exp.More():
        n += 1
        exp.Next()
    return n


def kernel_volume(shape: Any) -> float:
    """Volume by OCCT's ``BRepGProp`` (good to ~1e-5 relative on B-spline faces)."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props)
    return float(props.Mass())


def planar_face_at(shape: Any, z: float) -> Any:
    """The planar face of ``shape`` lying at height ``z``."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_Plane
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    fx = TopExp_Explorer(shape, TopAbs_FACE)
    while fx.More():
        face = TopoDS.Face_s(fx.Current())
        surf = BRepAdaptor_Surface(face)
        if surf.GetType() == GeomAbs_Plane and abs(surf.Plane().Location().Z() - z) < 1e-9:
            return face
        fx.Next()
    raise ValueError(f"no planar face at z = {z}")


def face_area(face: Any) -> float:
    """Area of a face by OCCT's ``BRepGProp.SurfaceProperties``."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    BRepGProp.SurfaceProperties_s(face, props)
    return float(props.Mass())


def face_area_shoelace(face: Any, samples_per_edge: int = 400) -> float:
    """Area of a planar face by a shoelace over its edges sampled through OCCT's own curve
    evaluator — independent of OCCT's mass properties and of our NURBS code (~1e-8)."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_REVERSED
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    total = 0.0
    ex = TopExp_Explorer(face, TopAbs_EDGE)
    while ex.More():
        edge = TopoDS.Edge_s(ex.Current())
        c = BRepAdaptor_Curve(edge)
        t = np.linspace(c.FirstParameter(), c.LastParameter(), samples_per_edge + 1)
        pts = np.array([(p.X(), p.Y()) for p in map(c.Value, t)])
        if edge.Orientation() == TopAbs_REVERSED:
            pts = pts[::-1]
        total += 0.5 * float(np.sum(pts[:-1, 0] * pts[1:, 1] - pts[1:, 0] * pts[:-1, 1]))
        ex.Next()
    return abs(total)

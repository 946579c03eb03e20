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


def nurbs_to_geom(curve: NurbsCurve, z: float = 0.0) -> Any:
    """A ``Geom_BSplineCurve`` with exactly the poles, weights, knots and degree of ``curve``."""
    from OCP.Geom import Geom_BSplineCurve
    from OCP.gp import gp_Pnt
    from OCP.TColgp import TColgp_Array1OfPnt
    from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal

    n = curve.n_poles
    poles = TColgp_Array1OfPnt(1, n)
    weights = TColStd_Array1OfReal(1, n)
    for i, ((x, y), w) in enumerate(zip(curve.poles.tolist(), curve.weights.tolist()), start=1):
        poles.SetValue(i, gp_Pnt(x, y, z))
        weights.SetValue(i, w)
    u, mult = curve.distinct_knots()
    knots = TColStd_Array1OfReal(1, len(u))
    mults = TColStd_Array1OfInteger(1, len(u))
    for i, (k, m) in enumerate(zip(u.tolist(), mult.tolist()), start=1):
        knots.SetValue(i, k)
        mults.SetValue(i, int(m))
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
    use those integrals."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeWire

    mk = BRepBuilderAPI_MakeWire()
    for piece in curve.bezier_pieces():
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


def cam_solid(design: CamDesign) -> Any:
    """The cam as a ``TopoDS_Solid``: the exact profile face extruded by the thickness, with the bore."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism
    from OCP.gp import gp_Vec
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

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

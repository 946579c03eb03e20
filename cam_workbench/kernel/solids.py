"""Neutral NURBS data → OCCT edges, faces and the cam solid (through OCP).

This is the only place the CadQuery/build123d side turns generator output into
B-rep; FreeCAD has its own adaptor in ``cam_workbench/freecad`` (never both OCCT
builds in one process).  Every OCP name comes from :mod:`cam_workbench.kernel.ocp`
(``occ.``), which knows the OCP versions; nothing here does.
"""
from __future__ import annotations

from typing import Any, Protocol

import numpy as np

from cam_workbench.generators.bodies.base import Arc, Curve, Line
from cam_workbench.generators.bodies.levels import CapXor, LevelStack, level_stack
from cam_workbench.generators.cam_design import CamDesign
from cam_workbench.generators.checks.solid import check_kernel_solid, integration_rule, surface_body
from cam_workbench.generators.curves.nurbs import NurbsCurve
from cam_workbench.generators.kinds.by_class import ByClass
from cam_workbench.generators.pitch.bspline import bezier_form

from . import ocp as occ


def _occ_arrays(curve: NurbsCurve, pole_array: Any, point: Any) -> tuple[Any, Any, Any, Any]:
    """OCCT arrays (poles, weights, distinct knots, multiplicities) of ``curve``; ``point(x, y)``
    makes one pole (gp_Pnt or gp_Pnt2d), ``pole_array`` their array (``occ.pnt_array`` or
    ``occ.pnt2d_array``)."""
    poles = pole_array([point(x, y) for x, y in curve.poles.tolist()])
    weights = occ.real_array(curve.weights.tolist())
    u, mult = curve.distinct_knots()
    return poles, weights, occ.real_array(u.tolist()), occ.int_array(mult.tolist())


def nurbs_to_geom(curve: NurbsCurve, z: float = 0.0) -> Any:
    """A ``Geom_BSplineCurve`` with exactly the poles, weights, knots and degree of ``curve``."""
    poles, weights, knots, mults = _occ_arrays(curve, occ.pnt_array, lambda x, y: occ.gp_Pnt(x, y, z))
    if curve.is_rational:
        return occ.Geom_BSplineCurve(poles, weights, knots, mults, curve.degree, False)
    return occ.Geom_BSplineCurve(poles, knots, mults, curve.degree, False)


def nurbs_to_edge(curve: NurbsCurve, z: float = 0.0) -> Any:
    """A ``TopoDS_Edge`` on the exact NURBS curve."""
    mk = occ.BRepBuilderAPI_MakeEdge(nurbs_to_geom(curve, z))
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
    mk = occ.BRepBuilderAPI_MakeWire()
    for edge in bezier_edges(curve, z):
        mk.Add(edge)
    if not mk.IsDone():
        raise RuntimeError("OCCT could not join the profile edges into a wire")
    wire = mk.Wire()
    if not wire.Closed():
        raise RuntimeError("the profile wire is not closed")
    return wire


def bezier_edges(curve: NurbsCurve, z: float = 0.0) -> list[Any]:
    """The edges of ``curve`` (open or closed), one exact rational Bézier edge per knot span (see
    :func:`profile_wire`)."""
    pieces = curve.bezier_pieces()
    if len(pieces) == 1 and len(np.unique(curve.knots)) > 2:
        pieces = bezier_form(curve).bezier_pieces()     # exact knot insertion, no refit
    return [nurbs_to_edge(piece, z) for piece in pieces]


def circle_wire(radius: float, z: float = 0.0) -> Any:
    """A full circle about the Z axis as a wire."""
    circ = occ.gp_Circ(occ.gp_Ax2(occ.gp_Pnt(0, 0, z), occ.gp_Dir(0, 0, 1)), radius)
    return occ.BRepBuilderAPI_MakeWire(occ.BRepBuilderAPI_MakeEdge(circ).Edge()).Wire()


def profile_face(profile_ccw: NurbsCurve, bore_radius: float = 0.0, z: float = 0.0) -> Any:
    """The planar cam cross-section: the exact profile as the outer boundary, the bore as a hole."""
    mk = occ.BRepBuilderAPI_MakeFace(profile_wire(profile_ccw, z), True)
    if not mk.IsDone():
        raise RuntimeError("OCCT could not make a planar face from the profile")
    if bore_radius > 0:
        mk.Add(occ.topods_wire(circle_wire(bore_radius, z).Reversed()))
    return mk.Face()


def nurbs_to_geom2d(curve: NurbsCurve) -> Any:
    """A ``Geom2d_BSplineCurve`` (x, y) with exactly the data of ``curve``."""
    poles, weights, knots, mults = _occ_arrays(curve, occ.pnt2d_array, occ.gp_Pnt2d)
    if curve.is_rational:
        return occ.Geom2d_BSplineCurve(poles, weights, knots, mults, curve.degree, False)
    return occ.Geom2d_BSplineCurve(poles, knots, mults, curve.degree, False)


def offset_profile_face(design: CamDesign, z: float = 0.0, holes: Any = None) -> Any:
    """The cross-section of a ``pitch.representation = "bspline"`` cam with the profile as OCCT's
    exact offset (``Geom_OffsetCurve``) of the fitted pitch B-spline, counter-clockwise.

    One edge per knot span (trimmed from the one offset curve: OCCT integrates areas and volumes
    of multi-span edges poorly), each with its exact plane curve (``Geom2d_OffsetCurve`` of the
    same B-spline) so that BRepCheck accepts the face — the pcurves OCCT projects itself miss
    the offset by ~5e-7 and fail it."""
    assert design.bspline is not None
    basis = design.pitch_nurbs
    distance = design.bspline.offset_distance            # + = left of the pitch curve's travel
    clockwise = basis.area() < 0
    if clockwise:                                        # travel reversed: left ↔ right
        basis, distance = basis.reversed(), -distance
    occ_offset = -distance                               # OCCT: + = T × Z, the right-hand side
    curve3d = occ.Geom_OffsetCurve(nurbs_to_geom(basis, z), occ_offset, occ.gp_Dir(0, 0, 1))
    curve2d = occ.Geom2d_OffsetCurve(nurbs_to_geom2d(basis), occ_offset)
    mk = occ.BRepBuilderAPI_MakeWire()
    u = np.unique(basis.knots)
    for a, b in zip(u[:-1].tolist(), u[1:].tolist()):
        mk.Add(occ.BRepBuilderAPI_MakeEdge(curve3d, a, b).Edge())
    # the plane's (u, v) = (x, y)
    plane = occ.gp_Pln(occ.gp_Ax3(occ.gp_Pnt(0, 0, z), occ.gp_Dir(0, 0, 1), occ.gp_Dir(1, 0, 0)))
    mf = occ.BRepBuilderAPI_MakeFace(plane, mk.Wire(), True)
    if not mf.IsDone():
        raise RuntimeError("OCCT could not make a planar face from the offset profile")
    face = mf.Face()
    builder = occ.BRep_Builder()
    ex = occ.TopExp_Explorer(face, occ.TopAbs_EDGE)
    while ex.More():
        edge = occ.topods_edge(ex.Current())
        builder.UpdateEdge(edge, curve2d, face, 1e-7)
        builder.SameParameter(edge, True)
        builder.SameRange(edge, True)
        ex.Next()
    bore = design.spec.cam.bore_diameter / 2
    hole_wires = holes if holes is not None else ([circle_wire(bore, z)] if bore > 0 else [])
    if hole_wires:
        mf2 = occ.BRepBuilderAPI_MakeFace(face)
        for w in hole_wires:
            mf2.Add(occ.topods_wire(w.Reversed()))
        face = mf2.Face()
    return face


class KernelBody(Protocol):
    """What the kernel builds of one body's design (registered in :data:`SOLIDS` for its class)."""

    @staticmethod
    def solid(design: Any, exact_offset: bool) -> Any:
        """The ``TopoDS_Solid`` (``exact_offset``: see :func:`cam_solid`)."""

    @staticmethod
    def measures(design: Any, shape: Any) -> dict[str, Any]:
        """What the solid stage measures of the built ``shape`` beyond volume and face area."""

    @staticmethod
    def verify(design: Any, shape: Any, step_shape: Any) -> dict[str, Any]:
        """report.json's ``solid`` section beyond validity: the built ``shape`` (and the STEP solid
        ``step_shape``) measured and held to the design's own numbers (:func:`verify_exact` for a
        body with exact volume and top face).

        Raises:
            GeometryError: a measure disagrees beyond what the kernel's integration allows."""


#: design class → its :class:`KernelBody` (the plane cams' here; a body's own in its kernel module,
#: imported by :mod:`cam_workbench.kernel` when it loads)
SOLIDS: ByClass[type[KernelBody]] = ByClass("the CAD kernel's solid")


def cam_solid(design: Any, exact_offset: bool = True) -> Any:
    """The cam as a ``TopoDS_Solid``, built by its body's :class:`KernelBody`.

    ``exact_offset``: a ``pitch.representation = "bspline"`` plate's profile as OCCT's exact offset
    of the fitted pitch B-spline (True) or as the fitted offset B-spline (False: what STEP can
    hold); bodies without such a profile ignore it.

    Raises:
        NotAvailable: the design's body registers no kernel builder.
    """
    return SOLIDS.of(design).solid(design, exact_offset)


def body_measures(design: Any, shape: Any) -> dict[str, Any]:
    """What the solid stage measures of a body beyond volume and face area (a cylindrical cam's
    built wall faces against the exact walls; nothing for the prism bodies)."""
    return SOLIDS.of(design).measures(design, shape)


def plane_solid(design: CamDesign, exact_offset: bool = True) -> Any:
    """A plane cam as a ``TopoDS_Solid``: its body's prisms (:mod:`cam_workbench.generators.bodies`) — for a plate
    cam the exact profile face extruded by the thickness, with the bore; any other body by
    :func:`prism_stack` (the fitted B-spline's exact offset: its prisms fused and cut in order).

    For ``pitch.representation = "bspline"`` the plate's profile is OCCT's exact offset of the fitted
    pitch B-spline (``exact_offset``) or the fitted offset B-spline ``design.profile``
    (``exact_offset=False``: what STEP can hold — OCCT's STEP writer has no mapping for
    offset curves and writes an empty model)."""
    body = design.body
    plain_plate = body is None or body.plain_plate
    kernel_offset = exact_offset and design.bspline is not None and design.spec.roller_radius > 0 and \
        (body is None or body.has("plate"))
    if plain_plate:
        if kernel_offset:
            face = offset_profile_face(design)
        else:
            face = profile_face(design.profile_ccw(), design.spec.cam.bore_diameter / 2)
        return extrude(face, 0.0, design.spec.cam.thickness)
    if not kernel_offset:
        return prism_stack(body.prisms)
    shape = None
    for prism in body.prisms:
        if prism.role == "plate":
            face = offset_profile_face(design, prism.z0, holes=[loop_wire(h, prism.z0) for h in prism.holes])
        else:
            face = region_face(prism.outer, prism.holes, prism.z0)
        solid = extrude(face, prism.z0, prism.z1)
        if shape is None:
            shape = solid
        elif prism.op == "add":
            shape = boolean(occ.BRepAlgoAPI_Fuse, shape, solid)
        else:
            shape = boolean(occ.BRepAlgoAPI_Cut, shape, solid)
    return _one_solid(shape)


def _one_solid(shape: Any) -> Any:
    """``shape`` as a ``TopoDS_Solid`` when it holds one, else itself."""
    exp = occ.TopExp_Explorer(shape, occ.TopAbs_SOLID)
    return occ.topods_solid(exp.Current()) if count_solids(shape) == 1 else shape


def verify_exact(design: Any, shape: Any, step_shape: Any) -> dict[str, Any]:
    """The ``solid`` section of a body with exact numbers (``design.volume``, ``design.area``: closed
    forms and Green's theorem): OCCT's volume and top-face area, their relative differences, the
    body's :meth:`KernelBody.measures`, all held to
    :func:`cam_workbench.generators.checks.solid.check_kernel_solid`.

    Raises:
        GeometryError: see :func:`~cam_workbench.generators.checks.solid.check_kernel_solid`."""
    t = design.spec.cam.thickness
    solid: dict[str, Any] = {
        # OCCT's fixed Gauss rule: exact on prisms of plane curves; on a surface body's B-spline
        # walls good to what cam_workbench.generators.checks.solid allows (``volume_rule`` below)
        "kernel_volume": kernel_volume(shape),
        "cross_section_area": top_face_area(shape, t),
    }
    # how far the kernel's integrals are from the exact (Green's theorem) numbers
    solid["volume_rel_diff"] = solid["kernel_volume"] / design.volume - 1.0
    solid["area_rel_diff"] = solid["cross_section_area"] / design.area - 1.0
    solid.update(body_measures(design, shape))
    allowed = check_kernel_solid(design, solid["kernel_volume"], solid["cross_section_area"], kernel="OCCT",
                                 adaptive=False, walls=solid.get("wall_error"), exact_offset=design.bspline is not None)
    if surface_body(design):
        # the volume of B-spline walls is not exact: by what rule, and the relative difference it allows
        solid["volume_rule"] = {"what": integration_rule(design, adaptive=False).text, "allowed": allowed["volume"]}
    if design.bspline is not None:
        solid["profile"] = "exact offset of the fitted pitch B-spline (Geom_OffsetCurve)"
        solid["step_profile"] = "fitted offset B-spline (profile.max_error)"
        solid["step_cross_section_area"] = top_face_area(step_shape, t)
        # the solid STEP writes: the fitted offset itself, the exact numbers' own profile
        check_kernel_solid(design, kernel_volume(step_shape), solid["step_cross_section_area"],
                           kernel="OCCT (the STEP solid)", adaptive=False)
    return solid


@SOLIDS.register(CamDesign)
class PlaneSolids:
    """The plane cams' solids: their bodies' prisms (:func:`plane_solid`); nothing further measured."""

    solid = staticmethod(plane_solid)
    verify = staticmethod(verify_exact)

    @staticmethod
    def measures(design: Any, shape: Any) -> dict[str, Any]:
        return {}


def extrude(face: Any, z0: float, z1: float) -> Any:
    """The face (made at z = z0) swept up to z1, as a solid."""
    shape = occ.BRepPrimAPI_MakePrism(face, occ.gp_Vec(0, 0, z1 - z0), True).Shape()
    exp = occ.TopExp_Explorer(shape, occ.TopAbs_SOLID)
    return occ.topods_solid(exp.Current())


def boolean(op: Any, a: Any, b: Any) -> Any:
    """``op`` (an OCCT boolean class: fuse, cut) of ``a`` and ``b``, built and checked."""
    mk = op(a, b)
    mk.Build()
    if not mk.IsDone():
        raise RuntimeError("OCCT could not combine the cam body's parts")
    return mk.Shape()


def loop_wire(loop: Any, z: float = 0.0) -> Any:
    """A closed wire of a body loop (:class:`cam_workbench.generators.bodies.Loop`): exact NURBS pieces (one edge
    per Bézier span), circular arcs and lines, in the loop's (counter-clockwise) order."""
    mk = occ.BRepBuilderAPI_MakeWire()
    for piece in loop.pieces:
        if isinstance(piece, Curve):
            for e in bezier_edges(piece.nurbs, z):
                mk.Add(e)
        elif isinstance(piece, Arc):
            c = piece.centre
            circ = occ.gp_Circ(occ.gp_Ax2(occ.gp_Pnt(c.real, c.imag, z), occ.gp_Dir(0, 0, 1)), piece.radius)
            if abs(abs(piece.a1 - piece.a0) - 2 * np.pi) < 1e-12:
                mk.Add(occ.BRepBuilderAPI_MakeEdge(circ).Edge())
            else:
                a, b = sorted((piece.a0, piece.a1))
                edge = occ.BRepBuilderAPI_MakeEdge(circ, a, b).Edge()
                mk.Add(edge if piece.a1 > piece.a0 else occ.topods_edge(edge.Reversed()))
        elif isinstance(piece, Line):
            a, b = piece.start, piece.end
            mk.Add(occ.BRepBuilderAPI_MakeEdge(occ.gp_Pnt(a.real, a.imag, z), occ.gp_Pnt(b.real, b.imag, z)).Edge())
    if not mk.IsDone():
        raise RuntimeError(f"OCCT could not join the {loop.role or 'loop'} into a wire")
    return mk.Wire()


def region_face(outer: Any, holes: Any = (), z: float = 0.0) -> Any:
    """The planar region inside ``outer`` minus ``holes`` (body loops, counter-clockwise)."""
    mk = occ.BRepBuilderAPI_MakeFace(loop_wire(outer, z), True)
    if not mk.IsDone():
        raise RuntimeError(f"OCCT could not make a planar face from the {outer.role or 'loop'}")
    for h in holes:
        mk.Add(occ.topods_wire(loop_wire(h, z).Reversed()))
    return mk.Face()


def is_valid(shape: Any) -> bool:
    """OCCT's full topological and geometric check (``BRepCheck_Analyzer``)."""
    return occ.is_valid(shape)


def count_solids(shape: Any) -> int:

    exp = occ.TopExp_Explorer(shape, occ.TopAbs_SOLID)
    n = 0
    while exp.More():
        n += 1
        exp.Next()
    return n


def kernel_volume(shape: Any, eps: float | None = None) -> float:
    """Volume by OCCT's ``BRepGProp``: its fixed Gauss rule (exact on prisms of plane curves, good to
    ~1e-5 relative on a cylindrical cam's B-spline walls: ``cam_workbench.generators.checks.solid``),
    or with ``eps`` its adaptive integration to that relative error per face."""
    props = occ.GProp_GProps()
    occ.volume_properties(shape, props, eps)
    return float(props.Mass())


#: the relative error per face asked of OCCT's adaptive volume integration on bodies that are not prisms
SURFACE_VOLUME_EPS = 1e-6


def planar_face_at(shape: Any, z: float) -> Any:
    """The planar face of ``shape`` lying at height ``z``."""
    for face in faces_of(shape):
        surf = occ.BRepAdaptor_Surface(face)
        if surf.GetType() == occ.GeomAbs_Plane and abs(surf.Plane().Location().Z() - z) < 1e-9:
            return face
    raise ValueError(f"no planar face at z = {z}")


def top_face_area(shape: Any, z: float) -> float:
    """Area of the planar faces of ``shape`` at height ``z`` whose outward normal is +Z (the top face
    seen from above: a groove cam's is two faces, the island inside the groove and the ring outside),
    by OCCT's ``BRepGProp.SurfaceProperties``."""
    total = 0.0
    for face in faces_of(shape):
        surf = occ.BRepAdaptor_Surface(face)
        if surf.GetType() == occ.GeomAbs_Plane and abs(surf.Plane().Location().Z() - z) < 1e-9:
            up = surf.Plane().Axis().Direction().Z() * (-1.0 if face.Orientation() == occ.TopAbs_REVERSED else 1.0)
            if up > 0:
                total += face_area(face)
    return total


def face_area(face: Any) -> float:
    """Area of a face by OCCT's ``BRepGProp.SurfaceProperties``."""
    props = occ.GProp_GProps()
    occ.surface_properties(face, props)
    return float(props.Mass())


def face_area_shoelace(face: Any, samples_per_edge: int = 400) -> float:
    """Area of a planar face by a shoelace over its edges sampled through OCCT's own curve
    evaluator — independent of OCCT's mass properties and of our NURBS code (~1e-8)."""
    total = 0.0
    ex = occ.TopExp_Explorer(face, occ.TopAbs_EDGE)
    while ex.More():
        edge = occ.topods_edge(ex.Current())
        c = occ.BRepAdaptor_Curve(edge)
        t = np.linspace(c.FirstParameter(), c.LastParameter(), samples_per_edge + 1)
        pts = np.array([(p.X(), p.Y()) for p in map(c.Value, t)])
        if edge.Orientation() == occ.TopAbs_REVERSED:
            pts = pts[::-1]
        total += 0.5 * float(np.sum(pts[:-1, 0] * pts[1:, 1] - pts[1:, 0] * pts[:-1, 1]))
        ex.Next()
    return abs(total)


def _explored(shape: Any, kind: Any, cast: Any) -> list[Any]:
    out = []
    exp = occ.TopExp_Explorer(shape, kind)
    while exp.More():
        out.append(cast(exp.Current()))
        exp.Next()
    return out


def solids_of(shape: Any) -> list[Any]:
    """Every ``TopoDS_Solid`` of ``shape``."""
    return _explored(shape, occ.TopAbs_SOLID, occ.topods_solid)


def faces_of(shape: Any) -> list[Any]:
    """Every ``TopoDS_Face`` of ``shape``."""
    return _explored(shape, occ.TopAbs_FACE, occ.topods_face)


def sewn_solid(faces: list[Any], tolerance: float = 1e-6, *, closed: bool = False) -> Any | None:
    """The solid bounded by ``faces`` sewn into one shell, oriented outward, or None when they sew
    into several shells — or, with ``closed``, leave a free or a multiple edge."""
    sew = occ.BRepBuilderAPI_Sewing(tolerance)
    for f in faces:
        sew.Add(f)
    sew.Perform()
    shells = _explored(sew.SewedShape(), occ.TopAbs_SHELL, occ.topods_shell)
    if len(shells) != 1 or (closed and (sew.NbFreeEdges() or sew.NbMultipleEdges())):
        return None
    mk = occ.BRepBuilderAPI_MakeSolid(shells[0])
    if not mk.IsDone():
        return None
    solid = mk.Solid()
    occ.orient_closed_solid(solid)
    return solid


def prism_stack(prisms: Any) -> Any:
    """Body prisms (:class:`cam_workbench.generators.bodies.Prism`) as one solid: sewn from their
    caps and sides where no two loops of a level cross
    (:func:`cam_workbench.generators.bodies.levels.level_stack`: no boolean but the planar ones of a
    cap where two levels' loops cross), else extruded and fused or cut in order."""
    stack = level_stack(prisms)
    if stack is not None:
        solid = sewn_levels(stack)
        if solid is not None:
            return solid
    return fused_prisms(prisms)


def general_op(op: Any, arguments: Any, tools: Any, what: str) -> Any:
    """The shape of OCCT's general boolean ``op`` (``BRepAlgoAPI_Splitter``, ``BRepAlgoAPI_Fuse``, …)
    of the shapes ``arguments`` by the shapes ``tools``.

    Raises:
        RuntimeError: OCCT does not finish (the message says ``what`` was done)."""
    args, tls = occ.ListOfShape(), occ.ListOfShape()
    for a in arguments:
        args.Append(a)
    for t in tools:
        tls.Append(t)
    builder = op()
    builder.SetArguments(args)
    builder.SetTools(tls)
    builder.Build()
    if not builder.IsDone():
        raise RuntimeError(f"OCCT could not {what} ({op.__name__})")
    return builder.Shape()


def fused_prisms(prisms: Any) -> Any:
    """Body prisms as one solid by booleans alone: each extruded and fused or cut in order."""
    shape = None
    for prism in prisms:
        solid = extrude(region_face(prism.outer, prism.holes, prism.z0), prism.z0, prism.z1)
        if shape is None:
            shape = solid
        else:
            shape = boolean(occ.BRepAlgoAPI_Fuse if prism.op == "add" else occ.BRepAlgoAPI_Cut, shape, solid)
    return _one_solid(shape)


def sewn_levels(stack: LevelStack) -> Any | None:
    """The ``TopoDS_Solid`` bounded by the caps and sides of ``stack``, sewn, or None when the faces
    do not close into one shell of the stack's exact volume (then :func:`prism_stack` uses booleans)."""
    faces = []
    for cap in stack.caps:
        if isinstance(cap, CapXor):
            below = _compound([region_face(f.outer, f.holes, cap.z) for f in cap.below])
            above = _compound([region_face(f.outer, f.holes, cap.z) for f in cap.above])
            faces += [boolean(occ.BRepAlgoAPI_Cut, below, above), boolean(occ.BRepAlgoAPI_Cut, above, below)]
        else:
            faces.append(region_face(cap.outer, cap.holes, cap.z))
    for side in stack.sides:
        faces.append(occ.BRepPrimAPI_MakePrism(loop_wire(side.loop, side.z0), occ.gp_Vec(0, 0, side.z1 - side.z0),
                                               True).Shape())
    solid = sewn_solid(faces)
    return None if solid is None else solid if abs(kernel_volume(solid) - stack.volume) <= 1e-7 * stack.volume else None


def _compound(shapes: list[Any]) -> Any:
    comp = occ.TopoDS_Compound()
    builder = occ.BRep_Builder()
    builder.MakeCompound(comp)
    for sh in shapes:
        builder.Add(comp, sh)
    return comp

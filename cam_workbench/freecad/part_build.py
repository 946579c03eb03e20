"""FreeCAD ``Part`` adaptor: neutral NURBS data → edges, wires, faces and the cam solid.

The FreeCAD twin of ``cam_workbench.kernel.solids`` (which serves CadQuery/build123d through
OCP): same geometry, FreeCAD's own OCCT.  Each Bézier span of a profile becomes one exact
``Part.BSplineCurve`` edge (poles, weights, knots and degree copied, nothing refitted):
OCCT integrates single Bézier edges exactly, so the solid's volume matches the exact
Green's-theorem value to ~1e-15 (a single 60-span edge is only good to ~1e-3).

``scale`` maps spec length units to FreeCAD's millimetres (25.4 for an inch spec).

``Part`` and ``FreeCAD`` are imported inside the builders: the module itself imports in any
Python, since :mod:`.check_design`, whose tables are read outside FreeCAD too, imports it.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from cam_workbench.generators.bodies import Arc, Curve, Line
from cam_workbench.generators.bodies.levels import CapXor, LevelStack, level_stack
from cam_workbench.generators.cam_design import CamDesign
from cam_workbench.generators.checks.solid import check_kernel_solid
from cam_workbench.generators.curves.nurbs import NurbsCurve
from cam_workbench.generators.kinds.by_class import ByClass
from cam_workbench.generators.pitch.bspline import bezier_form


def bspline_curve(curve: NurbsCurve, scale: float = 1.0, z: float = 0.0) -> Any:
    """A ``Part.BSplineCurve`` with exactly the poles, weights, knots and degree of ``curve``."""
    import Part  # deferred: Part, FreeCAD (see the module docstring)
    from FreeCAD import Vector

    poles = [Vector(float(x) * scale, float(y) * scale, z) for x, y in curve.poles.tolist()]
    knots, mults = curve.distinct_knots()
    c = Part.BSplineCurve()
    c.buildFromPolesMultsKnots(poles, [int(m) for m in mults], [float(k) for k in knots],
                               False, int(curve.degree), [float(w) for w in curve.weights])
    return c


def nurbs_wire(curve: NurbsCurve, scale: float = 1.0, z: float = 0.0) -> Any:
    """A wire of exact edges, one per Bézier span of ``curve`` (closed if the curve is).

    A curve with simple interior knots (the fitted B-splines of ``pitch.representation =
    "bspline"``) is first brought to Bézier form by exact knot insertion, as
    ``occ_build.profile_wire`` does: as one multi-span edge its solid's volume was off by
    1.3e-3 (measured on the thesis' Example 5)."""
    import Part  # deferred: Part (see the module docstring)

    pieces = curve.bezier_pieces()
    if len(pieces) == 1 and len(np.unique(curve.knots)) > 2:
        pieces = bezier_form(curve).bezier_pieces()     # exact knot insertion, no refit
    edges = [bspline_curve(piece, scale, z).toShape() for piece in pieces]
    wire = Part.Wire(edges)
    if curve.is_closed and not wire.isClosed():
        raise RuntimeError("the profile edges do not join into a closed wire")
    return wire


def circle_wire(radius: float, z: float = 0.0) -> Any:
    """A full circle of ``radius`` (mm) about the Z axis."""
    import Part  # deferred: Part, FreeCAD (see the module docstring)
    from FreeCAD import Vector

    return Part.Wire(Part.Circle(Vector(0, 0, z), Vector(0, 0, 1), radius).toShape())


def plane_face(outer: Any, holes: Any = (), z: float = 0.0) -> Any:
    """The planar face at height ``z`` [mm] bounded by the counter-clockwise wire ``outer`` and the
    counter-clockwise wires ``holes`` inside it (reversed here), on the plane z with normal +Z.

    Built on its plane directly (``Part.Face(plane, wires)``): the loops' nesting is known, so
    none of FreeCAD's face makers' sorting is needed (0.1 ms against 28 ms for a groove cam's
    caps with FaceMakerBullseye)."""
    import Part  # deferred: Part, FreeCAD (see the module docstring)
    from FreeCAD import Vector

    return Part.Face(Part.Plane(Vector(0, 0, z), Vector(0, 0, 1)), [outer] + [h.reversed() for h in holes])


def profile_face(design: CamDesign, scale: float = 1.0) -> Any:
    """The planar cross-section: the exact profile with the bore as a hole."""
    outer = nurbs_wire(design.profile_ccw(), scale)
    bore_r = design.spec.cam.bore_diameter / 2 * scale
    return plane_face(outer, [circle_wire(bore_r)] if bore_r > 0 else [])


@dataclass(frozen=True)
class PartSolid:
    """A cam's ``Part`` solid with FreeCAD's measures of it, which the feature holds against the
    design's exact numbers (``cam_workbench.generators.checks.solid.check_kernel_solid``).

    Attributes:
        shape: the solid.
        valid: FreeCAD's kernel calls it valid, and it is one solid.
        volume: its volume [mm³].
        top_area: the area of its top face [mm²] (the faces at the top height facing +Z).
        measured: how ``valid`` and ``volume`` were measured (the Check design dialog's words).
    """

    shape: Any
    valid: bool
    volume: float
    top_area: float
    measured: str


def measured_solid(shape: Any, top_z: float) -> PartSolid:
    """``shape`` measured whole: ``isValid()`` and one solid, ``Shape.Volume`` (OCCT's fixed Gauss
    rule) and :func:`top_face_area` at ``top_z`` [mm]."""
    return PartSolid(shape, bool(shape.isValid()) and len(shape.Solids) == 1, float(shape.Volume),
                     top_face_area(shape, top_z), "the solid: isValid, Shape.Volume")


def plane_solid(design: CamDesign, scale: float = 1.0) -> PartSolid:
    """A plane cam: its body's prisms (:mod:`cam_workbench.generators.bodies`) as
    ``cam_workbench.kernel.solids.cam_solid`` makes them — for a plain plate cam the profile face
    (with the bore) extruded by the thickness along +Z; a groove cam's disc with the groove between
    the exact wall offsets, a conjugate pair's two plates, hubs, keyways, holes and timing marks
    (:func:`prism_stack`).

    A plain plate is measured on its face: the linear sweep of a valid planar face along its
    normal (OCCT's ``BRepPrimAPI_MakePrism``) is a valid solid whose volume is the face's area ×
    the thickness and whose top face is the face moved, so the face's ``isValid()`` and ``Area``
    stand for the solid's (a third of the cost of measuring the solid whole); any other body is
    measured whole (:func:`measured_solid`)."""
    from FreeCAD import Vector  # deferred: FreeCAD (see the module docstring)

    body = design.body
    h = design.spec.cam.thickness * scale
    if body is None or body.plain_plate:
        face = profile_face(design, scale)
        area = float(face.Area)
        return PartSolid(face.extrude(Vector(0, 0, h)), bool(face.isValid()), area * h, area,
                         "the profile face (a linear sweep): isValid, Area × thickness")
    stack = level_stack(body.prisms)
    sewn = sewn_levels(stack, scale) if stack is not None else None
    if sewn is not None:
        solid, volume, top = sewn
        return PartSolid(solid, True, volume, top, "sewn into one closed shell of its planar caps and "
                         "vertical sides, of the exact volume (its caps' Σ z·area)")
    return measured_solid(_boolean_stack(body.prisms, scale), top_z(body.prisms, scale))


def prism_stack(prisms: Any, scale: float = 1.0) -> Any:
    """Body prisms (:class:`cam_workbench.generators.bodies.Prism`) as one solid: sewn from their
    caps and sides where no two loops of a level cross
    (:func:`cam_workbench.generators.bodies.levels.level_stack`: no boolean but the planar ones of a
    cap where two levels' loops cross), else extruded and fused or cut in order."""
    stack = level_stack(prisms)
    sewn = sewn_levels(stack, scale) if stack is not None else None
    return sewn[0] if sewn is not None else _boolean_stack(prisms, scale)


def top_z(prisms: Any, scale: float = 1.0) -> float:
    """The height [mm] of the prisms' top."""
    return max(p.z1 for p in prisms) * scale


def sewn_levels(stack: LevelStack, scale: float = 1.0) -> tuple[Any, float, float] | None:
    """(the solid bounded by the caps and sides of ``stack``, sewn; its volume [mm³]; the area of
    its top [mm²]), or None when the faces do not close into one shell of the stack's exact volume
    (then :func:`prism_stack` uses booleans).

    Each loop's wire is built once per height and shared by the cap and the side it bounds there.
    The volume is the divergence theorem with the field (0, 0, z): the vertical sides carry no
    flux, so V = Σ over the solid's planar faces of z · area · n_z (its own faces, after sewing
    and orienting; a tenth of OCCT's Gauss volume over every face).  That it is the exact volume
    to 1e-7, in one closed shell, is what makes the sewn solid the body; the top is its faces at
    the highest level facing +Z.  FreeCAD's full ``isValid()`` (the wires' self-intersection, 45 ms
    for a groove cam's 60-span walls, which the design's own loop checks already refuse) is left
    to the Check design dialog."""
    import Part  # deferred: Part, FreeCAD (see the module docstring)
    from FreeCAD import Vector

    wires: dict[tuple[int, float], Any] = {}

    def wire(loop: Any, z: float) -> Any:
        key = (id(loop), z)
        if key not in wires:
            wires[key] = loop_wire(loop, scale, z * scale)
        return wires[key]

    def face(region: Any, z: float) -> Any:
        return plane_face(wire(region.outer, z), [wire(h, z) for h in region.holes], z * scale)

    faces = []
    for cap in stack.caps:
        if isinstance(cap, CapXor):
            below = Part.makeCompound([face(f, cap.z) for f in cap.below])
            above = Part.makeCompound([face(f, cap.z) for f in cap.above])
            faces += below.cut(above).Faces + above.cut(below).Faces
        else:
            faces.append(face(cap, cap.z))
    for side in stack.sides:
        faces += wire(side.loop, side.z0).extrude(Vector(0, 0, (side.z1 - side.z0) * scale)).Faces
    sewn = Part.Compound(faces)
    sewn.sewShape()
    if len(sewn.Shells) != 1 or not sewn.Shells[0].isClosed():
        return None
    solid = Part.Solid(sewn.Shells[0])              # oriented outward (BRepLib::OrientClosedSolid)
    z_top = max(cap.z for cap in stack.caps) * scale
    volume = top = 0.0
    for f in solid.Faces:
        if f.Surface.TypeId != "Part::GeomPlane":
            continue
        u0, _u1, v0, _v1 = f.ParameterRange
        z, nz, area = f.BoundBox.ZMin, f.normalAt(u0, v0).z, f.Area
        volume += z * area * nz
        if abs(z - z_top) <= 1e-9 * max(1.0, abs(z_top)) and nz > 0:
            top += area
    exact = stack.volume * scale**3
    return (solid, float(volume), float(top)) if abs(volume - exact) <= 1e-7 * exact else None


def _boolean_stack(prisms: Any, scale: float) -> Any:
    """Body prisms extruded and fused or cut in order (same-domain faces merged)."""
    from FreeCAD import Vector  # deferred: FreeCAD (see the module docstring)

    shape = None
    for prism in prisms:
        solid = region_face(prism.outer, prism.holes, scale, prism.z0 * scale).extrude(
            Vector(0, 0, (prism.z1 - prism.z0) * scale))
        if shape is None:
            shape = solid
        else:
            shape = shape.fuse(solid) if prism.op == "add" else shape.cut(solid)
    shape = shape.removeSplitter() if len(shape.Solids) == 1 else shape
    return shape.Solids[0] if len(shape.Solids) == 1 else shape


def top_face_area(shape: Any, z: float) -> float:
    """Area [mm²] of the planar faces of ``shape`` at height ``z`` [mm] whose outward normal is +Z (the
    top face seen from above: a groove cam's is two faces), as ``occ_build.top_face_area``."""
    total = 0.0
    for f in shape.Faces:
        if f.Surface.TypeId != "Part::GeomPlane" or abs(f.BoundBox.ZMin - z) > 1e-9 or abs(f.BoundBox.ZMax - z) > 1e-9:
            continue
        u0, _u1, v0, _v1 = f.ParameterRange
        if f.normalAt(u0, v0).z > 0:           # normalAt follows the face's orientation: outward
            total += f.Area
    return total


def loop_wire(loop: Any, scale: float = 1.0, z: float = 0.0) -> Any:
    """A closed wire of a body loop (:class:`cam_workbench.generators.bodies.Loop`): exact NURBS pieces (one
    edge per Bézier span), circular arcs and lines, in the loop's (counter-clockwise) order."""
    import Part  # deferred: Part, FreeCAD (see the module docstring)
    from FreeCAD import Vector

    edges: list[Any] = []
    for piece in loop.pieces:
        if isinstance(piece, Curve):
            edges.extend(nurbs_wire(piece.nurbs, scale, z).Edges)
        elif isinstance(piece, Arc):
            c = piece.centre
            circ = Part.Circle(Vector(c.real * scale, c.imag * scale, z), Vector(0, 0, 1), piece.radius * scale)
            if abs(abs(piece.a1 - piece.a0) - 2 * np.pi) < 1e-12:
                edges.append(circ.toShape())
            else:
                a, b = sorted((piece.a0, piece.a1))
                edge = Part.ArcOfCircle(circ, float(a), float(b)).toShape()
                edges.append(edge if piece.a1 > piece.a0 else edge.reversed())
        elif isinstance(piece, Line):
            a, b = piece.start, piece.end
            edges.append(Part.LineSegment(Vector(a.real * scale, a.imag * scale, z),
                                          Vector(b.real * scale, b.imag * scale, z)).toShape())
    wire = Part.Wire(Part.__sortEdges__(edges)) if len(edges) > 1 else Part.Wire(edges)
    if not wire.isClosed():
        raise RuntimeError(f"the {loop.role or 'loop'} edges do not join into a closed wire")
    return wire


def region_face(outer: Any, holes: Any = (), scale: float = 1.0, z: float = 0.0) -> Any:
    """The planar region inside ``outer`` minus ``holes`` (body loops) at height ``z`` [mm]."""
    return plane_face(loop_wire(outer, scale, z), [loop_wire(h, scale, z) for h in holes], z)


def pitch_wire(design: CamDesign, scale: float = 1.0) -> Any:
    """The pitch curve (path of the follower point) as exact degree-5 edges, one per PH segment."""
    return nurbs_wire(design.pitch_nurbs, scale)


def base_circle_wire(design: CamDesign, scale: float = 1.0) -> Any:
    """The base (prime) circle of radius R_b traced by the follower point at zero lift."""
    return circle_wire(design.spec.cam.base_radius * scale)


def follower_size(design: CamDesign) -> float:
    """The drawn length of a stem (``Follower.sketch``'s ``size``), as the report's drawing of
    the cam takes it (``cam_workbench.exporters.plots.cam_panel``): the largest lift — as an arc on the base
    circle for an arm's degrees — plus the roller's diameter (at least a fifth of R_b)."""
    spec = design.spec
    fol = design.follower
    rb = spec.cam.base_radius
    lift_len = spec.max_lift * (rb * fol.lift_scale if fol.lift_unit == "angle" else 1.0)
    return lift_len + 2 * max(fol.profile_offset, 0.1 * rb)


def follower_shape(design: CamDesign, scale: float = 1.0, angle_deg: float = 0.0) -> Any:
    """The follower where it stands at ``angle_deg`` of cam rotation, in the cam's frame, as it
    draws itself (:meth:`cam_workbench.generators.followers.base.Follower.sketch`, which the plots and the DXF
    drawing read too): a compound of its roller circles, its segments (stem, arm, face), the
    arm's pivot (a vertex with a small circle round it) and the follower point (a vertex: the
    roller centre or knife tip on the pitch curve, a flat face's contact point), on the plane
    of the cam's top face.  No kind is named here: what is drawn is what the sketch holds."""
    import Part  # deferred: Part, FreeCAD (see the module docstring)
    from FreeCAD import Vector

    spec = design.spec
    fol = design.follower
    th = np.deg2rad(angle_deg)
    k = design.program.evaluate(np.array([th]))
    sk = fol.sketch(th, k, follower_size(design), spec.follower.face_width)
    z = spec.cam.thickness * scale
    normal = Vector(0, 0, 1)

    def at(p: complex) -> Any:
        return Vector(p.real * scale, p.imag * scale, z)

    shapes = [Part.Circle(at(c), normal, r * scale).toShape() for c, r in sk.circles]
    shapes += [Part.LineSegment(at(a), at(b)).toShape() for a, b, _role in sk.segments if abs(b - a) > 0]
    if sk.pivot is not None:
        shapes.append(Part.Circle(at(sk.pivot), normal, PIVOT_MARK * spec.cam.base_radius * scale).toShape())
        shapes.append(Part.Vertex(at(sk.pivot)))
    shapes.append(Part.Vertex(at(sk.point)))
    return Part.Compound(shapes)


#: Radius of the circle drawn round an arm's pivot, per unit of the base radius.
PIVOT_MARK = 0.04


# ---- the bodies' builders -------------------------------------------------------------------------
Rows = list[tuple[str, str, str, str]]


class FreeCADBody(Protocol):
    """What the FreeCAD feature builds and shows of one body's design (lengths × ``scale``: mm),
    registered in :data:`FREECAD_BODIES` for its design class."""

    #: the Check design dialog's words for the curvature the undercut check measures
    curvature_text: str

    @staticmethod
    def solid(design: Any, scale: float) -> PartSolid:
        """The cam as a ``Part`` solid, measured."""

    @staticmethod
    def wall_faces(design: Any, shape: Any, scale: float) -> dict[str, Any] | None:
        """``check_kernel_solid``'s ``walls``: the built solid's surface faces (None: prisms only)."""

    @staticmethod
    def verify(design: Any, built: PartSolid, scale: float) -> None:
        """Hold the ``built`` solid to the design's own numbers (:func:`verify_exact` for a body with
        an exact volume and top face).

        Raises:
            GeometryError: the solid disagrees beyond what FreeCAD's integration allows."""

    @staticmethod
    def cross_section_area(design: Any) -> float | None:
        """The exact top-face area the feature shows [spec units²] (:func:`exact_area`), or None
        where the body has none."""

    @staticmethod
    def pitch_wire(design: Any, scale: float) -> Any:
        """The path of the follower point, a reference curve."""

    @staticmethod
    def base_circle_wire(design: Any, scale: float) -> Any:
        """The circle the follower point traces at zero lift, a reference curve."""

    @staticmethod
    def follower_shape(design: Any, scale: float, angle_deg: float) -> Any:
        """The follower where it stands at ``angle_deg`` of cam rotation, a reference shape."""

    @staticmethod
    def results(design: Any, scale: float) -> tuple[int, str, float]:
        """The feature's result properties: (JunctionCount, the lift unit of its lift results,
        MaxDeviation in that unit's FreeCAD storage)."""

    @staticmethod
    def design_rows(summary: dict[str, Any]) -> Rows:
        """The Check design dialog's rows of the body's numbers, from ``design.summary()``."""

    @staticmethod
    def solid_rows(design: Any, shape: Any, scale: float) -> Rows:
        """Check design rows measuring the built solid beyond volume and validity."""


#: design class → its :class:`FreeCADBody` (the plane cams' here; a body's own in its module,
#: listed in :mod:`cam_workbench.freecad.bodies`)
FREECAD_BODIES: ByClass[type[FreeCADBody]] = ByClass("the FreeCAD feature's shapes")


def verify_exact(design: Any, built: PartSolid, scale: float) -> None:
    """The built solid's volume and top face (FreeCAD's fixed Gauss rule: no adaptive rule in its
    Python) and, for a surface body, its wall faces held to the design's exact numbers by
    :func:`cam_workbench.generators.checks.solid.check_kernel_solid`."""
    walls = FREECAD_BODIES.of(design).wall_faces(design, built.shape, scale)
    check_kernel_solid(design, built.volume / scale**3, built.top_area / scale**2, kernel="FreeCAD",
                       adaptive=False, walls=walls)


def exact_area(design: Any) -> float:
    """``design.area``: the exact top-face area (Green's theorem on the body's loops)."""
    return float(design.area)


@FREECAD_BODIES.register(CamDesign)
class PlanePart:
    """The plane cams: prisms of exact NURBS loops, the PH (or B-spline) pitch curve, the base circle."""

    curvature_text = "of the pitch curve and the profile"
    solid = staticmethod(plane_solid)
    verify = staticmethod(verify_exact)
    cross_section_area = staticmethod(exact_area)
    pitch_wire = staticmethod(pitch_wire)
    base_circle_wire = staticmethod(base_circle_wire)
    follower_shape = staticmethod(follower_shape)

    @staticmethod
    def wall_faces(design: Any, shape: Any, scale: float) -> dict[str, Any] | None:
        return None

    @staticmethod
    def results(design: Any, scale: float) -> tuple[int, str, float]:
        lift = design.follower.lift_unit
        # a lift's error in the lift's unit: mm (FreeCAD's lengths) or degrees
        return int(design.pitch.M), lift, float(design.max_deviation[0]) * (scale if lift == "length" else 1.0)

    @staticmethod
    def design_rows(summary: dict[str, Any]) -> Rows:
        return []

    @staticmethod
    def solid_rows(design: Any, shape: Any, scale: float) -> Rows:
        return []

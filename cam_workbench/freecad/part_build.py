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

from typing import Any

import numpy as np

from cam_workbench.generators.bodies import Arc, Curve, Line
from cam_workbench.generators.cam_design import CamDesign
from cam_workbench.generators.curves.nurbs import NurbsCurve
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


def profile_face(design: CamDesign, scale: float = 1.0) -> Any:
    """The planar cross-section: the exact profile with the bore as a hole."""
    import Part  # deferred: Part (see the module docstring)

    outer = nurbs_wire(design.profile_ccw(), scale)
    wires = [outer]
    bore_r = design.spec.cam.bore_diameter / 2 * scale
    if bore_r > 0:
        wires.append(circle_wire(bore_r))
    face = Part.Face(wires, "Part::FaceMakerBullseye")
    if not face.isValid():
        raise RuntimeError("FreeCAD could not make a valid face from the profile")
    return face


def cam_solid(design: CamDesign, scale: float = 1.0) -> Any:
    """The cam: its body's prisms (:mod:`cam_workbench.generators.bodies`) fused and cut in order, as
    ``cam_workbench.kernel.solids.cam_solid`` does — for a plain plate cam the profile face (with
    the bore) extruded by the thickness along +Z; a groove cam's disc with the groove between the
    exact wall offsets, a conjugate pair's two plates, hubs, keyways, holes and timing marks."""
    from FreeCAD import Vector  # deferred: FreeCAD (see the module docstring)

    body = design.body
    if body is not None and not body.prismatic:
        return cylindrical_solid(design, scale)
    if body is None or body.plain_plate:
        face = profile_face(design, scale)
        return face.extrude(Vector(0, 0, design.spec.cam.thickness * scale))
    shape = None
    for prism in body.prisms:
        solid = region_face(prism.outer, prism.holes, scale, prism.z0 * scale).extrude(
            Vector(0, 0, (prism.z1 - prism.z0) * scale))
        if shape is None:
            shape = solid
        elif prism.op == "add":
            shape = shape.fuse(solid)
        else:
            shape = shape.cut(solid)
    shape = shape.removeSplitter() if len(shape.Solids) == 1 else shape
    return shape.Solids[0] if len(shape.Solids) == 1 else shape


def prism_stack(prisms: Any, scale: float = 1.0) -> Any:
    """Body prisms (:class:`cam_workbench.generators.bodies.Prism`) extruded and fused or cut in order."""
    from FreeCAD import Vector  # deferred: FreeCAD (see the module docstring)

    shape = None
    for prism in prisms:
        solid = region_face(prism.outer, prism.holes, scale, prism.z0 * scale).extrude(
            Vector(0, 0, (prism.z1 - prism.z0) * scale))
        if shape is None:
            shape = solid
        else:
            shape = shape.fuse(solid) if prism.op == "add" else shape.cut(solid)
    return shape


# ---- the cylindrical (barrel) cam -----------------------------------------------------------
def wall_surface(wall: Any, scale: float = 1.0) -> Any:
    """A ``Part.BSplineSurface`` with exactly the data of a groove wall
    (:class:`cam_workbench.generators.bodies.cylindrical.WallSurface`: full knot vectors, poles (n_u, n_v, 3),
    degrees 5 × 5), the poles scaled to mm."""
    import Part  # deferred: Part, FreeCAD (see the module docstring)
    from FreeCAD import Vector

    ku, mu = np.unique(wall.knots_u, return_counts=True)
    kv, mv = np.unique(wall.knots_v, return_counts=True)
    poles = [[Vector(*p) for p in row] for row in (np.asarray(wall.poles, dtype=float) * scale).tolist()]
    surf = Part.BSplineSurface()
    surf.buildFromPolesMultsKnots(poles, [int(m) for m in mu], [int(m) for m in mv], [float(k) for k in ku],
                                  [float(k) for k in kv], False, False, int(wall.degree_u), int(wall.degree_v))
    return surf


def _cylinder(radius: float, z0: float, z1: float) -> Any:
    import Part  # deferred: Part, FreeCAD (see the module docstring)
    from FreeCAD import Vector

    return Part.makeCylinder(radius, z1 - z0, Vector(0, 0, z0), Vector(0, 0, 1))


def cylindrical_solid(design: Any, scale: float = 1.0) -> Any:
    """The cylindrical cam, as ``occ_build.cylindrical_solid`` builds it with OCP: the body's stack
    of prisms (the keyed, bored cylinder, its hub, mounting holes and timing mark) minus the groove
    — the piece of an annulus slightly wider than the groove's depth between the two walls (each
    one shell sewn from its per-segment B-spline faces), split by FreeCAD's general fuse and told
    by the pitch point at θ = 0 that it holds.  Lengths × ``scale`` (mm)."""
    import Part  # deferred: Part, FreeCAD (see the module docstring)
    from FreeCAD import Vector

    geo = design.body
    lay = geo.layout
    k = scale
    margin = 0.5 * (lay.outer_radius - lay.bottom_radius)
    annulus = _cylinder((lay.outer_radius + 0.5 * (geo.wall_rho[1] - lay.outer_radius)) * k, -margin * k,
                        (lay.length + margin) * k).cut(
        _cylinder(lay.bottom_radius * k, -2 * margin * k, (lay.length + 2 * margin) * k))
    shells = []
    for side in (-1, 1):
        faces = [Part.Face(wall_surface(w, k)) for w in geo.walls if w.side == side]
        sewn = Part.Compound(faces)
        sewn.sewShape(1e-6 * k)
        shells.append(sewn.Shells[0] if sewn.Shells else sewn)
    pieces = annulus.generalFuse(shells, 0.0)[0].Solids
    cx, cy, cz = lay.centre_point(design.program, 0.0)          # the roller centre at θ = 0 (its own path)
    centre = Vector(cx * k, cy * k, cz * k)
    groove = next((p for p in pieces if p.isInside(centre, 1e-7, True)), None)
    if groove is None:
        raise RuntimeError("the groove walls did not split the annulus (no piece holds the pitch point)")
    shape = prism_stack(geo.stack, k).cut(groove)
    return shape.Solids[0] if len(shape.Solids) == 1 else shape


def wall_face_points(shape: Any, per_direction: int = 15, radii: tuple[float, float] | None = None) -> Any:
    """Points (n, 3) [mm] on every B-spline face of ``shape`` (a cylindrical cam's groove walls),
    on a grid of each face's own (u, v) range, by FreeCAD's evaluator; with ``radii`` (mm) only
    those whose distance from the cam axis lies within them."""
    pts = []
    for f in shape.Faces:
        if f.Surface.TypeId != "Part::GeomBSplineSurface":
            continue
        u0, u1, v0, v1 = f.ParameterRange
        for a in np.linspace(u0, u1, per_direction).tolist():
            for b in np.linspace(v0, v1, per_direction).tolist():
                p = f.valueAt(a, b)
                pts.append((p.x, p.y, p.z))
    out = np.array(pts, dtype=float).reshape(-1, 3)
    if radii is not None:
        rho = np.hypot(out[:, 0], out[:, 1])
        out = out[(rho >= radii[0]) & (rho <= radii[1])]
    return out


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


def wall_faces(shape: Any, radii: tuple[float, float], per_direction: int = 15) -> dict[str, Any]:
    """How many B-spline (groove wall) faces ``shape`` holds and how many points of their
    ``per_direction``² grids lie between ``radii`` [mm] from the axis (the groove's depth): the
    ``faces``/``points`` of ``solid.wall_error``, its ``value`` not measured here (None)."""
    faces = sum(1 for f in shape.Faces if f.Surface.TypeId == "Part::GeomBSplineSurface")
    points = len(wall_face_points(shape, per_direction, radii))
    return {"faces": faces, "points": points, "value": None}


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
    import Part  # deferred: Part (see the module docstring)

    face = Part.Face([loop_wire(outer, scale, z)] + [loop_wire(h, scale, z) for h in holes],
                     "Part::FaceMakerBullseye")
    if not face.isValid():
        raise RuntimeError(f"FreeCAD could not make a valid face from the {outer.role or 'loop'}")
    return face


def pitch_wire(design: CamDesign, scale: float = 1.0) -> Any:
    """The pitch curve (path of the follower point) as exact degree-5 edges, one per PH segment;
    a cylindrical cam's: the roller's centre line on the pitch cylinder (:func:`cylindrical_pitch_wire`)."""
    if not design.plane:
        return cylindrical_pitch_wire(design, scale)
    return nurbs_wire(design.pitch_nurbs, scale)


def cylindrical_pitch_wire(design: Any, scale: float = 1.0, per_segment: int = 61) -> Any:
    """A cylindrical cam's pitch curve: where the roller's axis meets the pitch cylinder,
    (R_p cos φ(θ), R_p sin φ(θ), z₀ + s(θ)), one interpolating B-spline edge per motion segment
    (a reference curve for the eye; the walls are built from the exact data)."""
    import Part  # deferred: Part, FreeCAD (see the module docstring)
    from FreeCAD import Vector

    lay = design.layout
    b = design.program.boundaries
    edges = []
    for seg in range(len(design.program.starts)):
        th = np.linspace(float(b[seg]), float(b[seg + 1]), per_segment)
        c = lay.centre_line(design.program, th, lay.pitch_radius, np.full(th.shape, seg))
        psi = c.x / lay.pitch_radius                 # C_{R_p} wrapped onto the pitch cylinder
        pts = np.stack([lay.pitch_radius * np.cos(psi), lay.pitch_radius * np.sin(psi), c.z], axis=-1) * scale
        c = Part.BSplineCurve()
        c.interpolate([Vector(*p) for p in pts.tolist()])
        edges.append(c.toShape())
    return Part.Wire(edges)


def base_circle_wire(design: CamDesign, scale: float = 1.0) -> Any:
    """The base (prime) circle of radius R_b traced by the follower point at zero lift (a
    cylindrical cam's: the pitch circle R_p at the zero-lift height z₀)."""
    if not design.plane:
        return circle_wire(design.layout.pitch_radius * scale, design.layout.z0 * scale)
    return circle_wire(design.spec.cam.base_radius * scale)


def follower_size(design: CamDesign) -> float:
    """The drawn length of a stem (``Follower.sketch``'s ``size``), as the report's drawing of
    the cam takes it (``cam_workbench.exporters.plots.draw_cam``): the largest lift — as an arc on the base
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

    if not design.plane:
        return cylindrical_follower_shape(design, scale, angle_deg)
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


def cylindrical_follower_shape(design: Any, scale: float = 1.0, angle_deg: float = 0.0) -> Any:
    """A cylindrical cam's roller where it stands at ``angle_deg`` of cam rotation, in the cam's
    frame: its radial axis (from the groove's bottom to a roller's radius beyond the cylinder), the
    roller's end circles (radius r, in the planes normal to the axis at R_b and R_o) and the
    follower point (the roller's centre on the pitch cylinder, a vertex)."""
    import Part  # deferred: Part, FreeCAD (see the module docstring)
    from FreeCAD import Vector

    lay = design.layout
    r = design.spec.roller_radius
    cx, cy, z = lay.centre_point(design.program, float(np.deg2rad(angle_deg)))
    phi = float(np.arctan2(cy, cx))
    u = Vector(np.cos(phi), np.sin(phi), 0)

    def at(rho: float) -> Any:
        return Vector(rho * np.cos(phi) * scale, rho * np.sin(phi) * scale, z * scale)

    shapes = [Part.Circle(at(rho), u, r * scale).toShape() for rho in (lay.bottom_radius, lay.outer_radius)]
    shapes.append(Part.LineSegment(at(lay.bottom_radius), at(lay.outer_radius + r)).toShape())
    shapes.append(Part.Vertex(at(lay.pitch_radius)))
    return Part.Compound(shapes)


#: Radius of the circle drawn round an arm's pivot, per unit of the base radius.
PIVOT_MARK = 0.04



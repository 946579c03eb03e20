"""The cylindrical (barrel) cam in FreeCAD: its solid from the groove walls' B-spline surfaces,
its reference curves (the roller's centre line on the pitch cylinder, the pitch circle, the
radial roller) and its rows in the Check design dialog — registered in
:data:`cam_workbench.freecad.part_build.FREECAD_BODIES` for
:class:`~cam_workbench.generators.bodies.cylindrical.CylindricalDesign`.  ``Part`` and
``FreeCAD`` are imported inside the builders, as in :mod:`.part_build`.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from cam_workbench.generators.bodies.cylindrical import (FIX_MAX_TOLERANCE, FIX_PRECISION, SEW_TOLERANCE,
                                                          CylindricalDesign)

from .part_build import FREECAD_BODIES, PartSolid, Rows, exact_area, verify_exact, circle_wire, measured_solid, prism_stack


def wall_surface(wall: Any, scale: float = 1.0) -> Any:
    """A ``Part.BSplineSurface`` with exactly the data of a groove wall
    (:class:`cam_workbench.generators.bodies.cylindrical.WallSurface`: full knot vectors, poles (n_u, n_v, 3),
    degrees 5 × 5), the poles scaled to mm."""
    import Part  # deferred: Part, FreeCAD (see cam_workbench.freecad.part_build)
    from FreeCAD import Vector

    ku, mu = np.unique(wall.knots_u, return_counts=True)
    kv, mv = np.unique(wall.knots_v, return_counts=True)
    poles = [[Vector(*p) for p in row] for row in (np.asarray(wall.poles, dtype=float) * scale).tolist()]
    surf = Part.BSplineSurface()
    surf.buildFromPolesMultsKnots(poles, [int(m) for m in mu], [int(m) for m in mv], [float(k) for k in ku],
                                  [float(k) for k in kv], False, False, int(wall.degree_u), int(wall.degree_v))
    return surf




def _cylinder(radius: float, z0: float, z1: float) -> Any:
    import Part  # deferred: Part, FreeCAD (see cam_workbench.freecad.part_build)
    from FreeCAD import Vector

    return Part.makeCylinder(radius, z1 - z0, Vector(0, 0, z0), Vector(0, 0, 1))


def _turned(geometry: Any, angle: float) -> Any:
    """``geometry`` (a ``Part`` curve or surface about the Z axis) turned by ``angle`` [rad] about it."""
    from FreeCAD import Placement, Rotation, Vector  # deferred: FreeCAD (see cam_workbench.freecad.part_build)

    geometry.rotate(Placement(Vector(0, 0, 0), Rotation(Vector(0, 0, 1), float(np.rad2deg(angle)))))
    return geometry


def _circle_wire(radius: float, z: float, angle: float) -> Any:
    """A full circle [mm] about the Z axis at height ``z`` as a wire, its vertex at the polar ``angle`` [rad]."""
    import Part  # deferred: Part, FreeCAD (see cam_workbench.freecad.part_build)
    from FreeCAD import Vector

    return Part.Wire(_turned(Part.Circle(Vector(0, 0, z), Vector(0, 0, 1), radius), angle).toShape())


def cylinder_face(radius: float, first: Any, second: Any, angle: float) -> Any:
    """The face on the cylinder of ``radius`` [mm] about the Z axis between two wires that go round
    it, the cylinder's seam at the polar ``angle`` [rad], without their plane curves and the seam:
    OCCT's ``ShapeFix`` adds them (``Shape.fix``, as ``cam_workbench.kernel.cylindrical.cylinder_face``
    with OCP; :func:`sewn_groove_solid` fixes the three at once)."""
    import Part  # deferred: Part, FreeCAD (see cam_workbench.freecad.part_build)

    surface = Part.Cylinder()
    surface.Radius = radius
    face = Part.Face(_turned(surface, angle), first)
    face.addWire(second)
    return face


def _outer_side(stack: Any, radius: float, z_lo: float, z_hi: float) -> tuple[list[Any], float, float] | None:
    """(the faces of ``stack`` but its outer cylindrical face — the one of ``radius`` [mm] whose
    circles lie below ``z_lo`` and above ``z_hi`` —, the heights of that face's two circles), or None
    when there is not one such face."""
    kept, found = [], []
    for face in stack.Faces:
        circles = []
        if face.Surface.TypeId == "Part::GeomCylinder" and abs(face.Surface.Radius - radius) <= 1e-9 * radius:
            circles = sorted(e.Curve.Center.z for e in face.Edges if e.Curve.TypeId == "Part::GeomCircle")
        if len(circles) == 2 and circles[0] < z_lo and circles[1] > z_hi:
            found.append((circles[0], circles[1]))
        else:
            kept.append(face)
    return (kept, *found[0]) if len(found) == 1 else None


def sewn_groove_solid(design: Any, scale: float = 1.0) -> Any | None:
    """The cylindrical cam as ``cam_workbench.kernel.cylindrical.sewn_groove_solid`` makes it with
    OCP — the body's stack of prisms with its outer cylindrical face replaced by the groove's faces
    (each wall surface's patch R_b ≤ ρ ≤ R_o, the groove's bottom on the cylinder R_b and the outer
    cylinder below and above the groove, bounded by the walls' traces ρ = R_b and ρ = R_o), sewn
    into one shell —, or None when they do not close (then :func:`cylindrical_solid` uses
    :func:`boolean_groove_solid`).  Lengths × ``scale`` (mm)."""
    import Part  # deferred: Part, FreeCAD (see cam_workbench.freecad.part_build)

    geo = design.body
    lay = geo.layout
    k = scale
    z_lo, z_hi = lay.path.z_range()
    outer = _outer_side(prism_stack(geo.stack, k), lay.outer_radius * k, (z_lo - lay.half_width) * k,
                        (z_hi + lay.half_width) * k)
    if outer is None:
        return None
    kept, z_bottom, z_top = outer
    rb, ro = lay.bottom_radius, lay.outer_radius
    walls, traces, at = [], {}, {}
    for wall in geo.walls:
        surface = wall_surface(wall, k)            # its parameters stay θ and ρ (spec units)
        u0, u1 = wall.u_range
        walls.append(surface.toShape(u0, u1, rb, ro))
        for rho in (rb, ro):
            traces.setdefault((wall.side, rho), []).append(surface.vIso(rho).toShape(u0, u1))
            if wall.segment == 0:                  # the polar angle of the trace's first vertex
                start = surface.value(u0, rho)
                at[(wall.side, rho)] = float(np.arctan2(start.y, start.x))
    wires = {key: Part.Wire(edges) for key, edges in traces.items()}
    # each seam through the first vertex of a trace (as with OCP: kernel.cylindrical.sewn_groove_solid)
    bands = Part.Compound([cylinder_face(rb * k, wires[(-1, rb)], wires[(1, rb)], at[(-1, rb)]),
                           cylinder_face(ro * k, _circle_wire(ro * k, z_bottom, at[(-1, ro)]), wires[(-1, ro)],
                                         at[(-1, ro)]),
                           cylinder_face(ro * k, wires[(1, ro)], _circle_wire(ro * k, z_top, at[(1, ro)]),
                                         at[(1, ro)])])
    if not bands.fix(FIX_PRECISION * k, FIX_PRECISION * k, FIX_MAX_TOLERANCE * k):     # ShapeFix; valid?
        return None
    sewn = Part.Compound(kept + walls + bands.Faces)
    sewn.sewShape(SEW_TOLERANCE * k)
    if len(sewn.Shells) != 1 or not sewn.Shells[0].isClosed():
        return None
    return Part.Solid(sewn.Shells[0])              # oriented outward (BRepLib::OrientClosedSolid)


def boolean_groove_solid(design: Any, scale: float = 1.0) -> Any:
    """The cylindrical cam by booleans, as ``cam_workbench.kernel.cylindrical.boolean_groove_solid``
    makes it with OCP: the body's stack of prisms minus the groove — the piece of an annulus slightly
    wider than the groove's depth between the two walls (each one shell sewn from its per-segment
    B-spline faces), split by FreeCAD's general fuse and told by the pitch point at θ = 0 that it
    holds.  Lengths × ``scale`` (mm)."""
    import Part  # deferred: Part, FreeCAD (see cam_workbench.freecad.part_build)
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
        sewn.sewShape(SEW_TOLERANCE * k)
        shells.append(sewn.Shells[0] if sewn.Shells else sewn)
    pieces = annulus.generalFuse(shells, 0.0)[0].Solids
    cx, cy, cz = lay.centre_point(design.program, 0.0)          # the roller centre at θ = 0 (its own path)
    centre = Vector(cx * k, cy * k, cz * k)
    groove = next((p for p in pieces if p.isInside(centre, 1e-7, True)), None)
    if groove is None:
        raise RuntimeError("the groove walls did not split the annulus (no piece holds the pitch point)")
    shape = prism_stack(geo.stack, k).cut(groove)
    return shape.Solids[0] if len(shape.Solids) == 1 else shape


def cylindrical_solid(design: Any, scale: float = 1.0) -> Any:
    """The cylindrical cam, as ``cam_workbench.kernel.cylindrical.cylindrical_solid`` builds it with
    OCP: the body's stack of prisms (the keyed, bored cylinder, its hub, mounting holes and timing
    mark) less the groove — sewn from its faces (:func:`sewn_groove_solid`), else by booleans
    (:func:`boolean_groove_solid`).  Lengths × ``scale`` (mm)."""
    solid = sewn_groove_solid(design, scale)
    return solid if solid is not None else boolean_groove_solid(design, scale)


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




def wall_faces(shape: Any, radii: tuple[float, float], per_direction: int = 15) -> dict[str, Any]:
    """How many B-spline (groove wall) faces ``shape`` holds and how many points of their
    ``per_direction``² grids lie between ``radii`` [mm] from the axis (the groove's depth): the
    ``faces``/``points`` of ``solid.wall_error``, its ``value`` not measured here (None)."""
    faces = sum(1 for f in shape.Faces if f.Surface.TypeId == "Part::GeomBSplineSurface")
    points = len(wall_face_points(shape, per_direction, radii))
    return {"faces": faces, "points": points, "value": None}




def cylindrical_pitch_wire(design: Any, scale: float = 1.0, per_segment: int = 61) -> Any:
    """A cylindrical cam's pitch curve: where the roller's axis meets the pitch cylinder,
    (R_p cos φ(θ), R_p sin φ(θ), z₀ + s(θ)), one interpolating B-spline edge per motion segment
    (a reference curve for the eye; the walls are built from the exact data)."""
    import Part  # deferred: Part, FreeCAD (see cam_workbench.freecad.part_build)
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




def cylindrical_follower_shape(design: Any, scale: float = 1.0, angle_deg: float = 0.0) -> Any:
    """A cylindrical cam's roller where it stands at ``angle_deg`` of cam rotation, in the cam's
    frame: its radial axis (from the groove's bottom to a roller's radius beyond the cylinder), the
    roller's end circles (radius r, in the planes normal to the axis at R_b and R_o) and the
    follower point (the roller's centre on the pitch cylinder, a vertex)."""
    import Part  # deferred: Part, FreeCAD (see cam_workbench.freecad.part_build)
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


def cylindrical_rows(s: dict[str, Any]) -> list[tuple[str, str, str, str]]:
    """The design numbers of a cylindrical cam from its report.json (``design.summary()``)."""
    u, b = s["units"], s["body"]
    w, cr, pa, m = b["walls"], b["min_developed_curvature_radius"], s["pressure_angle"], s["motion"]
    rows = [
        ("Buildability", "undercut (developed centre line vs half the groove width)",
         f"min radius {cr['value']:.4g} {u} at {cr['at_deg']:.2f}° (radius {cr['at_radius']:.4g})", "pass"),
        ("Buildability", "groove bottom to bore", f"{w['groove_bottom_to_bore']:.4g} {u}", "pass"),
        ("Buildability", "groove to the end faces", f"{min(w['bottom_to_end'], w['top_to_end']):.4g} {u}", "pass"),
        ("Cylinder", "pitch / outer / bottom radius",
         f"{b['pitch_radius']:.6g} / {b['outer_radius']:.6g} / {b['bottom_radius']:.6g} {u}", ""),
        ("Cylinder", "length, lift range", f"{b['length']:.6g} {u}, z {b['lift_range'][0]:.6g} … "
                                           f"{b['lift_range'][1]:.6g} {u}", ""),
        ("Groove", "width × depth", f"{b['groove_width']:.6g} × {b['groove_depth']:.6g} {u}", ""),
        ("Groove", "wall surfaces", f"{b['wall_surfaces']['faces']} B-spline faces, degree "
                                    f"{b['wall_surfaces']['degree'][0]}×{b['wall_surfaces']['degree'][1]}", ""),
        ("Groove", "wall data vs exact walls", f"{b['wall_fit_error']['value']:.3g} {u}", ""),
        ("Pressure angle", "max |φ| at the pitch radius", f"{pa['max_deg']:.3f}° at {pa['at_deg']:.2f}°", ""),
        ("Pressure angle", "max |φ| at the groove's bottom",
         f"{pa['bottom_max_deg']:.3f}° at {pa['bottom_at_deg']:.2f}°", ""),
        ("Motion", "max lift", f"{m['max_lift']:.6g} {m['lift_unit']}", ""),
        ("Motion", "max velocity", f"{m['max_velocity']:.6g} {m['lift_unit']}/s", ""),
        ("Motion", "max acceleration", f"{m['max_acceleration']:.6g} {m['lift_unit']}/s²", ""),
        ("Motion", "max jerk", f"{m['max_jerk']:.6g} {m['lift_unit']}/s³", ""),
    ]
    lig = b.get("features", {}).get("hole_ligaments")
    if lig:
        rows.append(("Features", "hole ligaments (bore / groove − min wall / between)",
                     f"{lig['to_bore']:.4g} / {lig['to_outer']:.4g} / {lig['between']:.4g} {u}", "pass"))
    rows += [("Body", "end face area", f"{s['area']:.8g} {u}²", ""),
             ("Body", "volume", f"{s['volume']:.8g} {u}³", "")]
    return rows


@FREECAD_BODIES.register(CylindricalDesign)
class CylindricalPart:
    """The cylindrical cam: no PH pitch curve (its walls are B-spline surfaces of the exact
    offsets, see ``body.wall_fit_error``); its lifts are lengths along the cam axis."""

    curvature_text = "of the developed centre line, (ρ² + s′²)^{3/2}/(ρ|s″|)"
    pitch_wire = staticmethod(cylindrical_pitch_wire)
    follower_shape = staticmethod(cylindrical_follower_shape)
    design_rows = staticmethod(cylindrical_rows)
    verify = staticmethod(verify_exact)
    cross_section_area = staticmethod(exact_area)

    @staticmethod
    def solid(design: Any, scale: float) -> PartSolid:
        """The cylinder with its groove, measured whole (:func:`.part_build.measured_solid`)."""
        return measured_solid(cylindrical_solid(design, scale), design.spec.cam.thickness * scale)

    @staticmethod
    def base_circle_wire(design: Any, scale: float) -> Any:
        """The pitch circle R_p at the zero-lift height z₀."""
        return circle_wire(design.layout.pitch_radius * scale, design.layout.z0 * scale)

    @staticmethod
    def wall_faces(design: Any, shape: Any, scale: float) -> dict[str, Any] | None:
        return wall_faces(shape, _groove_radii(design, scale))

    @staticmethod
    def results(design: Any, scale: float) -> tuple[int, str, float]:
        return 0, "length", 0.0

    @staticmethod
    def solid_rows(design: Any, shape: Any, scale: float) -> Rows:
        pts = wall_face_points(shape, radii=_groove_radii(design, scale)) / scale
        err = np.minimum(design.wall_distance_error(-1, pts), design.wall_distance_error(1, pts))
        return [("FreeCAD solid", "wall faces vs exact walls",
                 f"{float(np.max(err)):.3g} {design.spec.units} ({len(pts)} points)", "")]


def _groove_radii(design: Any, scale: float) -> tuple[float, float]:
    """The groove's radial range [mm] (bottom to outer radius, widened by 1e-6)."""
    lay = design.layout
    return (lay.bottom_radius - 1e-6) * scale, (lay.outer_radius + 1e-6) * scale

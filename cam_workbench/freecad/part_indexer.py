"""The parallel indexer in FreeCAD: its cams' solid (the plates' stack of prisms), its reference
curves (each plate's roller-centre pitch curve and dwell circle) and its turret (the rollers of
every plane where they stand at the input angle), and its rows in the Check design dialog —
registered in :data:`cam_workbench.freecad.part_build.FREECAD_BODIES` for
:class:`~cam_workbench.generators.bodies.indexing.parallel_kind.ParallelIndexerDesign`.

Frames (:mod:`cam_workbench.generators.bodies.indexing.parallel`): the input axis O is the Z axis,
the turret axis P = (C, 0) at θ = 0.  As every body's reference shapes, these are drawn in the
cam's frame: the cams stay, and at an input angle θ the turret is drawn where it stands seen from
the cams — a fixed-frame point p (``roller_state``) at Rot(−θ)·p (the frame the indexer's
clearance check measures in).  Plate k spans z_k ≤ z ≤ z_k + t (the body's prism ``cam<k>``); its
pitch curve, dwell circle and rollers are drawn on its mid-plane.  ``Part`` and ``FreeCAD`` are
imported inside the builders, as in :mod:`.part_build`.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from cam_workbench.generators.bodies.indexing.from_spec import roller_width
from cam_workbench.generators.bodies.indexing.parallel import TWO_PI, locus, roller_state
from cam_workbench.generators.bodies.indexing.parallel_kind import ParallelIndexerDesign
from cam_workbench.generators.curves.basis import interpolating_cubic
from cam_workbench.generators.curves.nurbs import NurbsCurve

from .part_build import FREECAD_BODIES, PartSolid, Rows, exact_area, verify_exact, nurbs_wire, plane_solid, top_face_area, top_z

#: the pitch flanks' interpolation: first and most knot spans, and the distance [mm] from the exact
#: locus within which the drawn curve must lie (a reference curve: the solid is built from the body)
PITCH_FIRST_SPANS, PITCH_MOST_SPANS, PITCH_TOLERANCE = 16, 4096, 1e-6
_CHECK = np.linspace(0.0, 1.0, 9)[1:-1]


def plate_mid_z(design: ParallelIndexerDesign, cam: int) -> float:
    """The mid-plane height [spec units] of plate ``cam`` (its prism ``cam<k>``)."""
    p = design.body.prism(f"cam{cam}")
    return 0.5 * (p.z0 + p.z1)


def pitch_flank(design: ParallelIndexerDesign, cam: int, tau0: float, tau1: float) -> tuple[NurbsCurve, float]:
    """Plate ``cam``'s roller-centre locus L(τ) on [tau0, tau1] as a clamped cubic through L at
    uniform τ nodes with the exact L' at the ends, the spans doubled until it is within
    :data:`PITCH_TOLERANCE` of L at 7 points of every span (or :data:`PITCH_MOST_SPANS` reached: a
    reference curve, drawn anyway); (the curve, that measured distance)."""
    ix = design.geometry.indexer
    n = PITCH_FIRST_SPANS
    while True:
        x = np.linspace(tau0, tau1, n + 1)
        loc = locus(ix, cam, x)
        knots, coef = interpolating_cubic(x, loc["point"], loc["d1"][0], loc["d1"][-1])
        curve = NurbsCurve(3, knots, coef, np.ones(coef.shape[0]))
        check = (x[:-1, None] + np.diff(x)[:, None] * _CHECK[None, :]).ravel()
        err = float(np.max(np.hypot(*(curve.evaluate(check) - locus(ix, cam, check)["point"]).T)))
        if err <= PITCH_TOLERANCE or n >= PITCH_MOST_SPANS:
            return curve, err
        n *= 2


def indexer_pitch_wire(design: ParallelIndexerDesign, scale: float = 1.0) -> Any:
    """Each plate's pitch curve (the path of its rollers' centres in the cam's frame: the incoming
    flank, the dwell arc — an exact circle of radius r_d,k about O — and the outgoing flank, from the
    crossover X round to X) as one closed wire on the plate's mid-plane; a compound of the wires."""
    import Part  # deferred: Part, FreeCAD (see cam_workbench.freecad.part_build)
    from FreeCAD import Vector

    ix = design.geometry.indexer
    ts, beta = float(ix.index_start), float(ix.index_angle)
    wires = []
    for c in design.geometry.cams:
        z = plate_mid_z(design, c.index) * scale
        tau_in, tau_out = c.crossover_tau
        incoming, _ = pitch_flank(design, c.index, tau_in, ts - TWO_PI + beta)
        outgoing, _ = pitch_flank(design, c.index, ts, tau_out)
        start = locus(ix, c.index, np.array([ts]))["point"][0]        # the dwell arc's clockwise end
        a0 = math.atan2(float(start[1]), float(start[0]))
        circle = Part.Circle(Vector(0, 0, z), Vector(0, 0, 1), float(c.dwell_radius) * scale)
        arc = Part.ArcOfCircle(circle, a0, a0 + (TWO_PI - beta)).toShape()
        edges = nurbs_wire(incoming, scale, z).Edges + [arc] + nurbs_wire(outgoing, scale, z).Edges
        wire = Part.Wire(Part.__sortEdges__(edges))
        if not wire.isClosed():
            raise RuntimeError(f"cam {c.index}'s pitch curve does not close at its crossover")
        wires.append(wire)
    return Part.Compound(wires)


def indexer_dwell_circles(design: ParallelIndexerDesign, scale: float = 1.0) -> Any:
    """Each plate's dwell circle (radius r_d,k about O: where its held roller's centre stays while
    the turret dwells) on the plate's mid-plane; a compound of the circles."""
    import Part  # deferred: Part, FreeCAD (see cam_workbench.freecad.part_build)
    from FreeCAD import Vector

    return Part.Compound([Part.Wire(Part.Circle(Vector(0, 0, plate_mid_z(design, c.index) * scale), Vector(0, 0, 1),
                                                float(c.dwell_radius) * scale).toShape())
                          for c in design.geometry.cams])


def roller_centres(design: ParallelIndexerDesign, angle_deg: float) -> list[tuple[int, int, float, float]]:
    """(plane k, roller j, x, y) [spec units] of every roller's centre at the input angle
    ``angle_deg`` in the cam's frame: Rot(−θ)·``roller_state`` (planes in order, then rollers)."""
    ix = design.geometry.indexer
    th = math.radians(angle_deg)
    n = int(ix.stations)
    cos, sin = math.cos(th), math.sin(th)
    out = []
    for k in range(int(ix.cams)):
        p, _, _ = roller_state(ix, k, np.arange(n), np.full(n, th))
        for j, (x, y) in enumerate(p.tolist()):
            out.append((k, j, cos * x + sin * y, -sin * x + cos * y))
    return out


def indexer_follower_shape(design: ParallelIndexerDesign, scale: float = 1.0, angle_deg: float = 0.0) -> Any:
    """The turret where it stands at ``angle_deg`` of input rotation, in the cam's frame: every roller
    of every plane as a cylinder (radius r_r, the rollers' width ``follower.roller_width`` — default
    the plate's thickness — centred on its plate's mid-plane; the solids in the order of
    :func:`roller_centres`), the turret's pitch circle R_p about P on each plane and its axis P (a
    segment over the stack's height).  The turret's hub and roller carriers are not drawn: the spec
    gives no size or place for them."""
    import Part  # deferred: Part, FreeCAD (see cam_workbench.freecad.part_build)
    from FreeCAD import Vector

    ix = design.geometry.indexer
    k_ = scale
    rr, w = float(ix.roller_radius) * k_, roller_width(design.spec) * k_
    mids = [plate_mid_z(design, k) * k_ for k in range(int(ix.cams))]
    rollers = [Part.makeCylinder(rr, w, Vector(x * k_, y * k_, mids[k] - w / 2), Vector(0, 0, 1))
               for k, _j, x, y in roller_centres(design, angle_deg)]
    th = math.radians(angle_deg)
    c = float(ix.centre_distance)
    px, py = c * math.cos(th) * k_, -c * math.sin(th) * k_           # P = Rot(−θ)·(C, 0)
    circles = [Part.Circle(Vector(px, py, z), Vector(0, 0, 1), float(ix.pitch_radius) * k_).toShape() for z in mids]
    z0, z1 = design.body.z_range
    axis = Part.LineSegment(Vector(px, py, z0 * k_), Vector(px, py, z1 * k_)).toShape()
    return Part.Compound(rollers + circles + [axis])


def indexer_solid(design: ParallelIndexerDesign, scale: float = 1.0) -> PartSolid:
    """The plates' stack of prisms as the plane cams' bodies are built (:func:`.part_build.plane_solid`:
    sewn, its volume the caps' Σ z·area, else fused and measured whole)."""
    return plane_solid(design, scale)


def turret_motion_rows(m: dict[str, Any]) -> Rows:
    """The turret's largest velocity, acceleration and jerk from report.json's ``motion`` (in its
    ``lift_unit``/s, /s², /s³): the Check design dialog's Motion rows every indexer has."""
    return [("Motion", "max turret velocity", f"{m['max_velocity']:.6g} {m['lift_unit']}/s", ""),
            ("Motion", "max turret acceleration", f"{m['max_acceleration']:.6g} {m['lift_unit']}/s²", ""),
            ("Motion", "max turret jerk", f"{m['max_jerk']:.6g} {m['lift_unit']}/s³", "")]


def drive_rows(d: dict[str, Any] | None) -> Rows:
    """The drive's peaks (output and input torque [N·m], normal force [N], contact stress [MPa]) and
    the roller's rating life L10 [h] where report.json's ``indexer.drive`` has it; none without a
    drive (no load)."""
    if d is None:
        return []
    rows: Rows = [
        ("Drive", "output torque peak", f"{d['output_torque_peak_Nm']:.6g} N·m", ""),
        ("Drive", "input torque peak", f"{d['input_torque_peak_Nm']:.6g} N·m", ""),
        ("Drive", "normal force peak", f"{d['normal_force_peak_N']:.6g} N", ""),
        ("Drive", "contact stress peak", f"{d['contact_stress_peak_Pa'] / 1e6:.6g} MPa", ""),
    ]
    if "l10_hours" in d:
        rows.append(("Drive", "roller rating life L10", f"{d['l10_hours']:.4g} h", ""))
    return rows


def indexer_rows(s: dict[str, Any]) -> Rows:
    """The design numbers of a parallel indexer from its report.json (``design.summary()``)."""
    u, b, ig = s["units"], s["body"], s["indexer"]
    g, pa, m = ig["geometry"], s["pressure_angle"], s["motion"]
    mg = ig["motion_from_geometry"]
    rows: Rows = [
        ("Turret", "stations × planes", f"{g['stations']} × {g['cams']}", ""),
        ("Turret", "centre distance C / pitch radius R_p / roller r_r",
         f"{g['centre_distance_mm']:.6g} / {g['pitch_radius_mm']:.6g} / {g['roller_radius_mm']:.6g} {u}", ""),
        ("Turret", "index", f"{g['index_angle_deg']:.6g}° from {g['index_start_deg']:.6g}°, {g['law']}", ""),
        ("Pressure angle", "max carrying the output torque", f"{pa['max_deg']:.3f}° at {pa['at_deg']:.2f}°", ""),
        ("Pressure angle", "max driving over the index",
         f"{pa['index_max_deg']:.3f}° at {pa['index_max_at_deg']:.2f}°", ""),
        ("Buildability", "idle rollers' clearance",
         f"{g['clearance_mm']:.4g} {u} (cam {g['clearance_cam']}, roller {g['clearance_roller']})",
         "pass" if g["clearance_ok"] else "FAIL"),
        ("Buildability", "turret held both ways",
         f"worst {max(g['worst_forward_pressure_angle_deg'], g['worst_backward_pressure_angle_deg']):.3f}°",
         "pass" if g["locked"] else "FAIL"),
    ]
    for c in g["per_cam"]:
        rows.append((f"Cam {c['cam']}", "dwell radius / tip radius",
                     f"{c['dwell_radius_mm']:.6g} / {c['tip_radius_mm']:.6g} {u}", ""))
        rows.append((f"Cam {c['cam']}", "min convex profile radius",
                     f"{c['min_convex_profile_radius_mm']:.4g} {u}", ""))
    rows += [
        ("Plates", "thickness, gap, spacer radius",
         f"{b['plate_thickness']:.6g}, {b['gap']:.6g}, "
         + ("—" if b["spacer_radius"] is None else f"{b['spacer_radius']:.6g}") + f" {u}", ""),
        ("Plates", "outer radius, z range",
         f"{b['outer_radius']:.6g} {u}, z {b['z_range'][0]:.6g} … {b['z_range'][1]:.6g} {u}", ""),
        ("Plates", "flanks' B-splines vs exact offset", f"{b['flank_fit_error']['value']:.3g} {u}", ""),
        ("Motion", "turret angle from the built profiles vs the law",
         f"{math.degrees(mg['max_error_rad'] if mg['max_error_rad'] is not None else math.nan):.3g}° "
         f"({mg['samples']} input angles, {mg['undetermined_samples']} where the profiles do not fix it)", ""),
    ] + turret_motion_rows(m) + drive_rows(ig["drive"])
    rows += [("Body", "top face area", f"{s['area']:.8g} {u}²", ""),
             ("Body", "volume", f"{s['volume']:.8g} {u}³", "")]
    return rows


@FREECAD_BODIES.register(ParallelIndexerDesign)
class ParallelIndexerPart:
    """The parallel indexer: its plates as prisms (exact dwell arcs, fitted flank B-splines), no wall
    surfaces; the reference curves are each plate's pitch curve and dwell circle, the follower the
    turret's rollers; its lift is the turret's rotation (degrees)."""

    curvature_text = "of the cams' pitch curves (the rollers' centre loci), convex radius vs undercut_factor × r_r"
    pitch_wire = staticmethod(indexer_pitch_wire)
    base_circle_wire = staticmethod(indexer_dwell_circles)
    follower_shape = staticmethod(indexer_follower_shape)
    design_rows = staticmethod(indexer_rows)
    solid = staticmethod(indexer_solid)
    verify = staticmethod(verify_exact)
    cross_section_area = staticmethod(exact_area)

    @staticmethod
    def wall_faces(design: Any, shape: Any, scale: float) -> dict[str, Any] | None:
        return None

    @staticmethod
    def results(design: Any, scale: float) -> tuple[int, str, float]:
        """(0: no PH segments, "angle": the turret's rotation, the turret angle recovered from the
        built profiles against the law [deg], report.json's ``indexer.motion_from_geometry``)."""
        err = design.summary()["indexer"]["motion_from_geometry"]["max_error_rad"]
        return 0, "angle", math.nan if err is None else math.degrees(float(err))

    @staticmethod
    def solid_rows(design: Any, shape: Any, scale: float) -> Rows:
        top = top_z(design.body.prisms, scale)
        area = top_face_area(shape, top) / scale**2
        bb = shape.BoundBox
        z0, z1 = design.body.z_range
        return [("FreeCAD solid", "top face area vs exact", f"{area / design.area - 1:.2e} relative", ""),
                ("FreeCAD solid", "z range vs the plates'",
                 f"{max(abs(bb.ZMin / scale - z0), abs(bb.ZMax / scale - z1)):.2g} {design.spec.units}", "")]


__all__ = ["ParallelIndexerPart", "indexer_follower_shape", "indexer_pitch_wire", "roller_centres"]

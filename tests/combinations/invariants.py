"""Invariants of a built cam, computed independently of the project's own evaluators: the
profile NURBS evaluated by scipy on homogeneous coordinates, areas by the shoelace formula,
the solid checked by OCCT's BRepCheck_Analyzer directly, distances by brute force."""
from __future__ import annotations

import re

import numpy as np
from scipy.interpolate import BSpline

#: a clean refusal names a spec field (dotted path) or a cam angle, on one line
REFUSAL = re.compile(r"^error: (?:[A-Za-z_][\w\[\]\.\-]*|-o|--example|--set|/\S+)(?:: | )|°")


def nurbs_points(curve, n: int = 20000) -> np.ndarray:
    """Points (complex) of a NURBS curve at ``n`` equally spaced parameters: scipy's BSpline on
    the homogeneous poles, divided by the weight (not the project's evaluator)."""
    k, t = curve.degree, np.asarray(curve.knots, dtype=float)
    w = np.asarray(curve.weights, dtype=float)
    hom = np.column_stack([np.asarray(curve.poles)[:, 0] * w, np.asarray(curve.poles)[:, 1] * w, w])
    u = np.linspace(t[k], t[-k - 1], n, endpoint=False)
    v = BSpline(t, hom, k)(u)
    return (v[:, 0] + 1j * v[:, 1]) / v[:, 2]


def shoelace(points: np.ndarray) -> float:
    """|area| of the closed polygon through ``points`` (complex)."""
    x, y = points.real, points.imag
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def polyline_distance(points: np.ndarray, curve: np.ndarray) -> np.ndarray:
    """Distance of each point to the closed polyline ``curve`` (brute force, in chunks)."""
    a, b = curve, np.roll(curve, -1)
    ab = b - a
    out = np.empty(points.shape[0])
    for lo in range(0, points.shape[0], 128):
        p = points[lo:lo + 128, None]
        t = np.clip(((p - a) * np.conj(ab)).real / np.maximum(np.abs(ab) ** 2, 1e-300), 0.0, 1.0)
        out[lo:lo + 128] = np.min(np.abs(a + t * ab - p), axis=1)
    return out


def check_solid(shape) -> None:
    """One valid solid (OCCT's BRepCheck_Analyzer and a solid count, called here directly)."""
    from cam_workbench.kernel import ocp as occ

    assert occ.BRepCheck_Analyzer(shape).IsValid(), "OCCT: invalid solid"
    ex, n = occ.TopExp_Explorer(shape, occ.TopAbs_SOLID), 0
    while ex.More():
        n += 1
        ex.Next()
    assert n == 1, f"{n} solids"


def _bore_area(spec) -> float:
    """The bore, with its keyway: the circle plus a rectangle b wide out to r + t from the chord,
    minus the circular segment under it (the keyway's size from the spec, or from the standard's
    table — whose rows tests/test_bodies.py checks)."""
    from cam_workbench.generators.bodies.features import keyway_size

    r = spec.cam.bore_diameter / 2
    if r <= 0:
        return 0.0
    key = keyway_size(spec)
    if key is None:
        return float(np.pi * r * r)
    b, depth = key
    h = np.sqrt(r * r - (b / 2) ** 2)
    seg = r * r * np.arcsin(b / 2 / r) - (b / 2) * h
    return float(np.pi * r * r + b * (r + depth - h) - seg)


def top_face_area(design) -> float:
    """The cam's top face from elementary formulas and the shoelace on the exact curves: the
    profile (or a groove cam's disc, minus the groove between its walls), minus the keyed bore,
    the mounting holes and the timing mark."""
    spec = design.spec
    cam = spec.cam
    if cam.body == "groove":
        area = np.pi * (cam.outer_diameter / 2) ** 2
        area -= shoelace(nurbs_points(design.body.extra["outer_wall"])) - shoelace(nurbs_points(design.profile))
    else:
        area = shoelace(nurbs_points(design.profile))
    area -= _bore_area(spec)
    if cam.mounting_holes:
        area -= cam.mounting_holes * np.pi * (cam.mounting_hole_diameter / 2) ** 2
    if cam.timing_mark:
        area -= shoelace(design.body.prism("timing_mark").outer.points())
    return float(area)


def check_design(design, summary: dict) -> None:
    """Green's area of the profile (independent evaluation) and the features' formulas against the
    summary's area; the profile at the roller radius (plus half a groove's clearance) from the pitch
    curve; the report's verdict = run_checks."""
    from cam_workbench.generators.bodies.features import resolved
    from cam_workbench.generators.checks.design import run_checks

    spec = design.spec
    prof = nurbs_points(design.profile)
    scale = spec.cam.base_radius
    area = top_face_area(design)
    assert abs(area - summary["area"]) <= 1e-6 * scale**2, (area, summary["area"])
    if spec.cam.body == "plate" and not (spec.cam.hub_diameter or spec.cam.timing_mark):
        assert abs(summary["volume"] - area * spec.cam.thickness) <= 1e-6 * scale**2 * spec.cam.thickness
    inset = spec.roller_radius + (resolved(spec, "groove", "clearance") / 2 if spec.cam.body == "groove" else 0.0)
    pitch = nurbs_points(design.pitch_nurbs, 40000)
    d = polyline_distance(prof[::20], pitch)
    # polyline chords of the pitch curve sit inside it by ≲ L²κ/8; the fitted B-spline profile
    # is off by its own measured error
    slack = 5e-6 * scale + (summary["profile"].get("fitted_vs_kernel_offset") or 0.0) * 2
    assert np.max(np.abs(d - inset)) <= slack + 2e-5 * scale, float(np.max(np.abs(d - inset)))
    if spec.cam.body == "conjugate":
        # the second cam: its profile at its own roller's radius from its own pitch curve, and the
        # distance error between the rollers within the two curves' PH deviations
        second = design.body.extra["second_cam"]
        r2 = second.follower.profile_offset
        d2 = polyline_distance(nurbs_points(second.profile)[::20], nurbs_points(second.pitch_nurbs, 40000))
        assert np.max(np.abs(d2 - r2)) <= slack + 2e-5 * scale, float(np.max(np.abs(d2 - r2)))
        rde = summary["body"]["roller_distance_error"]
        assert rde["lift_max"] <= rde["lift_bound"] * (1 + 1e-9) + 1e-12, rde
    ck = run_checks(spec)
    assert summary["checks"]["passed"] == ck.passed and summary["checks"]["failed"] == ck.failed


def cylindrical_volume(spec) -> float:
    """A cylindrical cam's volume computed here from its definition (docs/bodies.md): the bored
    cylinder minus the groove, whose volume is w ∫ ℓ(ρ) dρ over its depth, ℓ(ρ) the length of the
    developed centre line C_ρ over a turn (the offsets' curvature terms cancel).  C_ρ′ comes from
    the roller centre's path — (0, s′) along the axis, or the arm's (−L sin β β′, L cos β β′),
    β′ = s′·π/180 — scaled by ρ/R_p along the circumference; s′ by central differences of the
    motion on a fine periodic grid (the motion program is the input, not the body's code)."""
    from cam_workbench.generators.bodies.features import resolved
    from cam_workbench.generators.motion.program import MotionProgram

    cam, fol = spec.cam, spec.follower
    rp, depth = cam.cylinder_radius, spec.groove.depth
    ro = cam.outer_diameter / 2 if cam.outer_diameter is not None else rp + depth / 2
    w = 2 * spec.roller_radius + resolved(spec, "groove", "clearance")
    n = 40000
    h = 2 * np.pi / n
    th = h * np.arange(n)
    s = MotionProgram.from_spec(spec).s(th)
    ds = (np.roll(s, -1) - np.roll(s, 1)) / (2 * h)
    if fol.motion == "translating":
        du, dz = np.zeros_like(ds), ds
    else:
        L, d, smax = fol.arm_length, fol.pivot_distance, spec.max_lift
        beta = np.arccos(d / L) + np.deg2rad(s - smax / 2)
        db = np.deg2rad(ds)
        du, dz = -L * np.sin(beta) * db, L * np.cos(beta) * db
    x, wts = np.polynomial.legendre.leggauss(12)
    rb = ro - depth
    rho = (ro + rb) / 2 + (ro - rb) / 2 * x
    ell = np.array([h * np.sum(np.hypot(r / rp * (rp - du), dz)) for r in rho])
    groove = w * (ro - rb) / 2 * float(np.sum(wts * ell))
    return float(np.pi * (ro**2 - (cam.bore_diameter / 2) ** 2) * cam.length - groove)

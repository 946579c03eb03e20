"""The cylindrical (barrel) cam: a groove around a cylinder drives a roller whose axis is radial;
the follower translates parallel to the cam axis and the lift s(θ) is its axial displacement.

Frame (the cam frame of CAM_SPEC.md): the cam axis is Z, the cylinder spans 0 ≤ z ≤ cam.length
(``cam.thickness`` is the same number), the follower's roller sits on the +Y side of the fixed
frame.  At cam angle θ the roller centre line meets the pitch cylinder (radius R_p =
``cam.cylinder_radius``) at the cam-frame polar angle φ(θ) = π/2 − δθ (δ = +1 for a ccw cam, −1 for
cw) and height z(θ) = z₀ + s(θ), z₀ = (L − s_max)/2 (the lift range centred on the cylinder).

Radii: the cylinder's outer radius R_o = ``cam.outer_diameter``/2 (default R_p + depth/2, the pitch
radius at mid-depth), the groove's bottom R_b = R_o − ``groove.depth``.

**The walls** (the issue's definition): on the cylinder of radius ρ, developed into the plane
(x = ρ·ψ, z), the groove's centre line is C_ρ(θ) = (ρ·φ(θ), z(θ)); the walls there are its offsets
by ±w/2, w = 2·roller_radius + groove.clearance, along the developed normal

    n(θ, ρ) = (δ·s′, ρ) / √(ρ² + s′²)          (+: the upper wall, towards +z),

mapped back onto the cylinder: W±(θ, ρ) = (ρ cos ψ, ρ sin ψ, z), ψ = x/ρ.  This is a surface of
θ and ρ — not ruled in general (the angular offset w·s′/(2ρ√(ρ² + s′²)) changes with ρ).  Each wall
is built as one tensor-product B-spline surface per motion segment (s is smooth inside a segment):
degree 5 in θ and in ρ, interpolating the exact points on a grid (not-a-knot), so neighbouring
faces share their boundary curves exactly (the same ρ-interpolant of the same points).  Their
distance from the exact wall is measured at points between the grid nodes (``wall_fit_error``)
and, in the OCCT solid, on the built faces (``cam_workbench.occ_build``: ``wall_error``).

**Volume** (independent of the surfaces): at radius ρ the groove's developed cross-section is
the band between the offsets ±w/2 of C_ρ, whose area over one turn is exactly w·ℓ(ρ),
ℓ(ρ) = ∫₀^2π √(ρ² + s′²) dθ (the curvature terms of the two offsets cancel); the volume element
is dx·dz·dρ, so V_groove = w ∫_{R_b}^{R_o} ℓ(ρ) dρ and the cam's V = π(R_o² − r_bore²)·L − V_groove.

**Pressure angle** of the translating follower: the angle between the groove's normal and the
axial direction, tan φ = s′/ρ (s′ per radian): reported at the pitch radius (the design check) and
at the groove's bottom (the largest).

What this body does not carry: hub, keyway, mounting holes and the timing mark (refused naming
the field); oscillating followers (refused).  Its drawing: :mod:`exporters.dxf_cylindrical`; its
follower for the force laws and the dynamics: :class:`CylindricalFollower` (tan φ = s′/R_p).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import GeometryError, SpecError
from ..followers.translating import TranslatingFollower
from .features import resolved

#: grid of the wall surfaces: θ-nodes per radian of a rise/return (at least 12 per segment), ρ-nodes
NODES_PER_RAD = 45.0
RHO_NODES = 7
DEGREE_THETA = 5
DEGREE_RHO = 5


def half_width(spec) -> float:
    """w/2 = roller radius + clearance/2."""
    return spec.roller_radius + resolved(spec, "groove", "clearance") / 2


@dataclass(frozen=True)
class CylinderLayout:
    """The cylinder's numbers (spec units)."""

    pitch_radius: float
    outer_radius: float
    bottom_radius: float
    length: float
    z0: float
    half_width: float
    sense: int                   # δ: +1 ccw, −1 cw
    bore_radius: float

    @staticmethod
    def of(spec) -> "CylinderLayout":
        cam = spec.cam
        rp = cam.cylinder_radius
        depth = spec.groove.depth
        ro = cam.outer_diameter / 2 if cam.outer_diameter is not None else rp + depth / 2
        return CylinderLayout(rp, ro, ro - depth, cam.length, (cam.length - spec.max_lift) / 2, half_width(spec),
                              1 if cam.direction == "ccw" else -1, cam.bore_diameter / 2)

    def phi(self, theta: np.ndarray) -> np.ndarray:
        """Cam-frame polar angle of the roller centre line at cam angle θ."""
        return np.pi / 2 - self.sense * np.asarray(theta, dtype=float)


def wall_points(layout: CylinderLayout, program, side: int, theta: np.ndarray, rho: np.ndarray) -> np.ndarray:
    """Exact points W_side(θ, ρ) (side +1: upper wall, −1: lower), broadcast over θ and ρ; (..., 3)."""
    theta, rho = np.broadcast_arrays(np.asarray(theta, dtype=float), np.asarray(rho, dtype=float))
    k = program.evaluate(theta)
    norm = np.hypot(rho, k.ds)
    x = rho * layout.phi(theta) + side * layout.half_width * layout.sense * k.ds / norm
    z = layout.z0 + k.s + side * layout.half_width * rho / norm
    psi = x / rho
    return np.stack([rho * np.cos(psi), rho * np.sin(psi), z], axis=-1)


def wall_distance_error(layout: CylinderLayout, program, side: int, points: np.ndarray,
                        iterations: int = 12) -> np.ndarray:
    """Distance of 3D ``points`` from the exact wall ``side`` (developed at each point's own radius):
    |dist(point, C_ρ) − w/2| with the foot point on C_ρ found by Newton's method in θ."""
    p = np.atleast_2d(points)
    rho = np.hypot(p[:, 0], p[:, 1])
    psi = np.arctan2(p[:, 1], p[:, 0])
    zp = p[:, 2]
    # start: the cam angle whose centre line passes through the point's polar angle
    theta = layout.sense * (np.pi / 2 - psi)
    for _ in range(iterations):
        k = program.evaluate(np.mod(theta, 2 * np.pi))
        dx = rho * _wrap(layout.phi(theta) - psi)            # developed x of C − P
        dz = layout.z0 + k.s - zp
        xp, zp1 = -layout.sense * rho, k.ds                  # C′
        g = dx * xp + dz * zp1
        dg = xp * xp + zp1 * zp1 + dz * k.d2s
        theta = theta - g / dg
    k = program.evaluate(np.mod(theta, 2 * np.pi))
    dx = rho * _wrap(layout.phi(theta) - psi)
    dz = layout.z0 + k.s - zp
    return np.abs(np.hypot(dx, dz) - layout.half_width)


def _wrap(a: np.ndarray) -> np.ndarray:
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


@dataclass(frozen=True)
class WallSurface:
    """One face of a wall: a non-rational tensor-product B-spline of (θ, ρ) — ``knots_u`` over θ
    [rad], ``knots_v`` over ρ, full knot vectors — and its poles (n_u, n_v, 3)."""

    side: int
    segment: int
    degree_u: int
    degree_v: int
    knots_u: np.ndarray
    knots_v: np.ndarray
    poles: np.ndarray

    def evaluate(self, u: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Points at parameters (u, v) (1-D arrays of equal length), (n, 3)."""
        from scipy.interpolate import BSpline

        nu, nv, _ = self.poles.shape
        su = BSpline(self.knots_u, self.poles.reshape(nu, nv * 3), self.degree_u, extrapolate=False)
        rows = su(np.asarray(u, dtype=float)).reshape(-1, nv, 3)
        out = np.empty((rows.shape[0], 3))
        for i in range(rows.shape[0]):        # one ρ-spline per point (test/report sampling only)
            out[i] = BSpline(self.knots_v, rows[i], self.degree_v, extrapolate=False)(float(v[i]))
        return out

    @property
    def u_range(self) -> tuple[float, float]:
        return float(self.knots_u[0]), float(self.knots_u[-1])

    @property
    def v_range(self) -> tuple[float, float]:
        return float(self.knots_v[0]), float(self.knots_v[-1])


def wall_surfaces(layout: CylinderLayout, program, rho0: float, rho1: float) -> tuple[WallSurface, ...]:
    """Both walls, one surface per motion segment each, over ρ ∈ [rho0, rho1]."""
    from scipy.interpolate import make_interp_spline

    rho = np.linspace(rho0, rho1, RHO_NODES)
    bounds = program.boundaries
    out = []
    for side in (-1, 1):
        for seg in range(len(program.starts)):
            a, b = float(bounds[seg]), float(bounds[seg + 1])
            n = max(12, int(math.ceil((b - a) * NODES_PER_RAD)) + 1)
            th = np.linspace(a, b, n)
            segs = np.full(th.shape, seg)
            k = program.evaluate(th, segs)
            pts = _points_from_kinematics(layout, side, th, k, rho)            # (n, m, 3)
            su = make_interp_spline(th, pts.reshape(n, -1), k=DEGREE_THETA)
            c = np.asarray(su.c).reshape(-1, RHO_NODES, 3)                   # (n_u, m, 3)
            sv = make_interp_spline(rho, np.transpose(c, (1, 0, 2)).reshape(RHO_NODES, -1), k=DEGREE_RHO)
            poles = np.transpose(np.asarray(sv.c).reshape(RHO_NODES, -1, 3), (1, 0, 2))
            out.append(WallSurface(side, seg, DEGREE_THETA, DEGREE_RHO, np.asarray(su.t), np.asarray(sv.t), poles))
    return tuple(out)


def _points_from_kinematics(layout, side, th, k, rho) -> np.ndarray:
    """wall_points with the kinematics already evaluated (one-sided at segment ends)."""
    r = rho[None, :]
    ds, s = k.ds[:, None], k.s[:, None]
    norm = np.hypot(r, ds)
    x = r * layout.phi(th)[:, None] + side * layout.half_width * layout.sense * ds / norm
    z = layout.z0 + s + side * layout.half_width * r / norm
    psi = x / r
    return np.stack([r * np.cos(psi), r * np.sin(psi), np.broadcast_to(z, psi.shape)], axis=-1)


def developed_length(program, rho: float, n_per_segment: int = 41) -> float:
    """ℓ(ρ) = ∫₀^2π √(ρ² + s′²) dθ, Gauss–Legendre per motion segment."""
    x, wts = np.polynomial.legendre.leggauss(n_per_segment)
    b = program.boundaries
    total = 0.0
    for seg in range(len(program.starts)):
        a, c = b[seg], b[seg + 1]
        th = (a + c) / 2 + (c - a) / 2 * x
        k = program.evaluate(th, np.full(th.shape, seg))
        total += (c - a) / 2 * float(np.sum(wts * np.hypot(rho, k.ds)))
    return total


def groove_volume(layout: CylinderLayout, program) -> float:
    """w ∫_{R_b}^{R_o} ℓ(ρ) dρ (Gauss–Legendre in ρ)."""
    x, wts = np.polynomial.legendre.leggauss(12)
    a, b = layout.bottom_radius, layout.outer_radius
    rho = (a + b) / 2 + (b - a) / 2 * x
    return 2 * layout.half_width * (b - a) / 2 * float(sum(w * developed_length(program, r) for w, r in zip(wts, rho)))


@dataclass(frozen=True)
class CylindricalGeometry:
    """The cylindrical body as plain data: the cylinder, the bore and the groove's wall surfaces.
    Not a stack of prisms (``prismatic`` False): the kernel adaptors build it with their own
    function, and its volume is the closed form above."""

    layout: CylinderLayout
    walls: tuple[WallSurface, ...]
    #: the radial range the wall surfaces span: a little beyond the groove, so that they cut through
    wall_rho: tuple[float, float]
    groove_volume: float
    kind: str = "cylindrical"
    prismatic: bool = False
    extra: dict = field(default_factory=dict)

    @property
    def volume(self) -> float:
        lay = self.layout
        return math.pi * (lay.outer_radius ** 2 - lay.bore_radius ** 2) * lay.length - self.groove_volume

    def face_area_at(self, z: float) -> float:
        """Area of the end face (z = 0 or z = length): the annulus (the groove stays inside)."""
        lay = self.layout
        return math.pi * (lay.outer_radius ** 2 - lay.bore_radius ** 2)

    @property
    def z_range(self) -> tuple[float, float]:
        return 0.0, self.layout.length

    @property
    def prisms(self) -> tuple:
        return ()

    def has(self, role: str) -> bool:
        return False

    def loops(self) -> list:
        return []


# ---- checks -----------------------------------------------------------------------------------
def developed_curvature_radius(layout: CylinderLayout, program, rho: float, th: np.ndarray) -> np.ndarray:
    """|radius of curvature| of C_ρ at θ: (ρ² + s′²)^{3/2} / (ρ·|s″|) (inf where s″ = 0)."""
    k = program.evaluate(th)
    num = np.hypot(rho, k.ds) ** 3
    den = rho * np.abs(k.d2s)
    return np.where(den > 0, num / np.where(den > 0, den, 1.0), np.inf)


def pressure_angles(layout: CylinderLayout, program, rho: float, th: np.ndarray) -> np.ndarray:
    """Signed pressure angle [deg] at radius ρ: atan(s′/ρ)."""
    return np.rad2deg(np.arctan2(program.evaluate(th).ds, rho))


def check_cylinder(spec, program, layout: CylinderLayout, refuse: bool = True) -> dict[str, Any]:
    """Undercut (refused, GeometryError with the cam angle, unless ``refuse`` is False: then the
    ``undercut`` check fails), pressure angle and walls: the body's report numbers and a ``checks``
    section in report.json's shape."""
    th = program.dense_angles(2001)
    w2 = layout.half_width
    # the wall on the concave side folds where the developed curve's radius of curvature ≤ w/2;
    # smallest at the smallest radius the walls reach
    radii = np.linspace(layout.bottom_radius, layout.outer_radius, 5)
    worst = (math.inf, 0.0, 0.0)
    for r in radii:
        rc = developed_curvature_radius(layout, program, r, th)
        i = int(np.argmin(rc))
        if rc[i] < worst[0]:
            worst = (float(rc[i]), float(np.rad2deg(th[i]) % 360), float(r))
    if worst[0] <= w2 and refuse:
        raise GeometryError("undercut", f"the groove's wall is undercut at cam angle {worst[1]:.2f}°: the developed "
                            f"centre line's radius of curvature at radius {worst[2]:.4g} is {worst[0]:.4g} ≤ half the "
                            f"groove width {w2:g} — a smaller roller, a larger cam.cylinder_radius or a gentler motion",
                            worst[1])
    phi_p = pressure_angles(layout, program, layout.pitch_radius, th)
    phi_b = pressure_angles(layout, program, layout.bottom_radius, th)
    ip, ib = int(np.argmax(np.abs(phi_p))), int(np.argmax(np.abs(phi_b)))
    limit = spec.checks.max_pressure_angle
    factor = spec.checks.undercut_factor
    results = {
        "pressure_angle": _result("Pressure angle at the pitch radius, tan φ = s′/R_p (s′ per radian)", "max",
                                  abs(float(phi_p[ip])), float(np.rad2deg(th[ip]) % 360), limit, "deg"),
        "pressure_angle_bottom": _result("Pressure angle at the groove's bottom radius, tan φ = s′/R_b", "max",
                                         abs(float(phi_b[ib])), float(np.rad2deg(th[ib]) % 360), None, "deg"),
        "undercut": _result("Smallest radius of curvature of the developed centre line (over the groove's depth), "
                            "against undercut_factor × groove half width", "min", worst[0], worst[1],
                            factor * w2, spec.units),
    }
    failed = [k for k, r in results.items() if r["status"] == "fail"]
    checks = {"passed": not failed, "failed": failed, "sampling": "dense", "samples_per_segment": 2001,
              "points": int(th.shape[0]), "results": results, "extremes": {}}
    walls = {"bottom_to_end": layout.z0 - w2, "top_to_end": layout.length - (layout.z0 + spec.max_lift + w2),
             "groove_bottom_to_bore": layout.bottom_radius - layout.bore_radius}
    pressure = {"max_deg": abs(float(phi_p[ip])), "signed_deg": float(phi_p[ip]),
                "at_deg": float(np.rad2deg(th[ip]) % 360), "at_radius": layout.pitch_radius,
                "bottom_max_deg": abs(float(phi_b[ib])), "bottom_at_deg": float(np.rad2deg(th[ib]) % 360),
                "formula": "tan φ = s′/ρ (translating follower along the cam axis, s′ per radian)"}
    return {"checks": checks, "walls": walls, "pressure_angle": pressure,
            "min_developed_curvature_radius": {"value": worst[0], "at_deg": worst[1], "at_radius": worst[2]}}


def _result(description, kind, value, at, limit, unit) -> dict[str, Any]:
    if limit is None:
        status = "pass"
    else:
        status = "pass" if (value <= limit if kind == "max" else value >= limit) else "fail"
    return {"description": description, "kind": kind, "value": value, "at_deg": at, "limit": limit, "unit": unit,
            "status": status, "passed": status == "pass", "note": ""}


# ---- the design -------------------------------------------------------------------------------
@dataclass(frozen=True)
class CylindricalDesign:
    """A designed cylindrical cam (plain values; no CAD kernel). The plane-cam members of
    :class:`~generators.cam_design.CamDesign` (pitch curve, profile) do not exist here."""

    spec: Any
    program: Any
    body: CylindricalGeometry
    body_report: dict
    checks_report: dict
    #: the cam is not a plane cam: the pipeline skips the plane-only stages (drawing, interpolator)
    plane = False
    #: no fitted B-spline pitch curve (the plane cams' ``pitch.representation = "bspline"``)
    bspline = None

    @property
    def layout(self) -> CylinderLayout:
        return self.body.layout

    @property
    def follower(self) -> "CylindricalFollower":
        """The translating roller along the cam axis (:func:`cylindrical_follower`)."""
        return cylindrical_follower(self.spec)

    @property
    def volume(self) -> float:
        return self.body.volume

    @property
    def area(self) -> float:
        return self.body.face_area_at(self.layout.length)

    def wall_points(self, side: int, theta, rho) -> np.ndarray:
        return wall_points(self.layout, self.program, side, theta, rho)

    def wall_distance_error(self, side: int, points: np.ndarray) -> np.ndarray:
        return wall_distance_error(self.layout, self.program, side, points)

    def summary(self) -> dict[str, Any]:
        from ..spec.model import spec_digest

        spec = self.spec
        maxima = self.program.maxima(spec.cam.speed_rpm * 2 * np.pi / 60)
        return {
            "units": spec.units,
            "spec_digest": spec_digest(spec),
            "pressure_angle": self.checks_report["pressure_angle"],
            "follower": {"kind": "roller", "motion": "translating", "label": f"translating roller r = "
                         f"{spec.roller_radius:g}, along the cam axis", "roller_radius": spec.roller_radius},
            "motion": {"lift_unit": spec.units, "max_lift": spec.max_lift, "max_velocity": maxima["velocity"],
                       "max_acceleration": maxima["acceleration"], "max_jerk": maxima["jerk"],
                       **self.program.report()},
            "area": self.area,
            "volume": self.volume,
            "checks": self.checks_report["checks"],
            "body": {**self.body_report, "volume": self.volume, "top_face_area": self.area},
        }


class CylindricalBody:
    """A groove around a cylinder (see the module docstring)."""

    kind = "cylindrical"
    closure = "form"
    #: the follower dynamics treat the groove as holding the roller both ways: the load changes
    #: wall where the contact force changes sign (no separation, no jump speed)
    dynamics_form_closed = True

    @staticmethod
    def own_follower(spec) -> "CylindricalFollower":
        """The follower the dynamics drive (:func:`cylindrical_follower`)."""
        return cylindrical_follower(spec)

    @staticmethod
    def profile_inset(spec) -> float:
        return resolved(spec, "groove", "clearance") / 2

    @staticmethod
    def further_followers(spec) -> tuple:
        return ()

    @staticmethod
    def design(spec) -> CylindricalDesign:
        """The cylindrical cam of ``spec`` (GeometryError: an undercut wall, with the cam angle)."""
        from ..motion.program import MotionProgram

        program = MotionProgram.from_spec(spec)
        layout = CylinderLayout.of(spec)
        report = check_cylinder(spec, program, layout)
        depth = layout.outer_radius - layout.bottom_radius
        margin = 0.25 * depth
        rho = (layout.bottom_radius - margin, layout.outer_radius + margin)
        walls = wall_surfaces(layout, program, *rho)
        vg = groove_volume(layout, program)
        geometry = CylindricalGeometry(layout, walls, rho, vg)
        fit = wall_fit_error(geometry, program)
        body_report = {
            "kind": "cylindrical", "closure": "form",
            "pitch_radius": layout.pitch_radius, "outer_radius": layout.outer_radius,
            "bottom_radius": layout.bottom_radius, "length": layout.length, "groove_width": 2 * layout.half_width,
            "groove_depth": depth, "z0": layout.z0, "lift_range": [layout.z0, layout.z0 + spec.max_lift],
            "axis": "Z (cam frame); the roller on +Y of the fixed frame, its axis radial",
            "walls": report["walls"], "min_developed_curvature_radius": report["min_developed_curvature_radius"],
            "groove_volume": vg,
            "wall_surfaces": {"faces": len(walls), "degree": [DEGREE_THETA, DEGREE_RHO],
                              "rho_range": list(rho), "nodes_per_rad": NODES_PER_RAD, "rho_nodes": RHO_NODES},
            "wall_fit_error": {"value": fit, "unit": spec.units,
                               "what": "B-spline wall data vs the exact wall, between the grid nodes"},
            "approximation": "walls: the developed centre line's offsets at ±w/2 on each cylinder (the issue's "
                             "definition), interpolated by B-spline surfaces; volume exact (closed form)",
        }
        return CylindricalDesign(spec, program, geometry, body_report, report)

    @staticmethod
    def validate(spec) -> None:
        validate_cylindrical(spec)


def wall_fit_error(geometry: CylindricalGeometry, program, per_face: int = 9) -> float:
    """Largest distance of the wall data from the exact wall at points between the grid nodes
    (θ midway between nodes, ρ midway and at the groove's bottom and top)."""
    lay = geometry.layout
    rho = np.concatenate([[lay.bottom_radius, lay.outer_radius],
                          np.linspace(*geometry.wall_rho, 2 * RHO_NODES - 1)[1::2]])
    worst = 0.0
    for s in geometry.walls:
        a, b = s.u_range
        n = max(12, int(math.ceil((b - a) * NODES_PER_RAD)) + 1)
        nodes = np.linspace(a, b, n)
        mids = (nodes[:-1] + nodes[1:]) / 2
        pick = mids[np.linspace(0, len(mids) - 1, min(per_face, len(mids))).round().astype(int)]
        # include the ends of the face where the not-a-knot conditions are weakest
        pick = np.unique(np.concatenate([pick, mids[:2], mids[-2:]]))
        u, v = np.meshgrid(pick, rho, indexing="ij")
        pts = s.evaluate(u.ravel(), v.ravel())
        worst = max(worst, float(np.max(wall_distance_error(lay, program, s.side, pts))))
    return worst


def validate_cylindrical(spec) -> None:
    """The cylindrical body's own rules (called by the spec's validation)."""
    cam, fol = spec.cam, spec.follower
    if fol.kind != "roller":
        raise SpecError("follower.kind", f'a cylindrical cam needs a roller follower, got "{fol.kind}"')
    if fol.motion != "translating":
        raise SpecError("follower.motion", 'a cylindrical cam supports a translating follower (its lift along the '
                        'cam axis) only; an oscillating one is not supported yet')
    if fol.offset != 0:
        raise SpecError("follower.offset", "does not apply to a cylindrical cam (the roller axis is radial)")
    for name in ("cylinder_radius", "length"):
        if getattr(cam, name) is None:
            raise SpecError(f"cam.{name}", "is required for a cylindrical cam")
    if cam.base_radius != cam.cylinder_radius:
        raise SpecError("cam.base_radius", f"is the pitch radius for a cylindrical cam: leave it out or give "
                        f"cam.cylinder_radius ({cam.cylinder_radius:g}), got {cam.base_radius:g}")
    if cam.thickness != cam.length:
        raise SpecError("cam.thickness", f"is the cylinder's length for a cylindrical cam: leave it out or give "
                        f"cam.length ({cam.length:g}), got {cam.thickness:g}")
    for name in ("hub_diameter", "hub_length", "keyway", "keyway_width", "keyway_depth", "mounting_hole_diameter",
                 "mounting_circle_diameter"):
        if getattr(cam, name) is not None:
            raise SpecError(f"cam.{name}", "is not supported on a cylindrical cam yet")
    if cam.mounting_holes:
        raise SpecError("cam.mounting_holes", "is not supported on a cylindrical cam yet")
    if cam.timing_mark:
        raise SpecError("cam.timing_mark", "is not supported on a cylindrical cam yet")
    if spec.groove.depth is None:
        raise SpecError("groove.depth", "is required for a cylindrical cam")
    depth = spec.groove.depth
    rp = cam.cylinder_radius
    ro = cam.outer_diameter / 2 if cam.outer_diameter is not None else rp + depth / 2
    if not ro - depth <= rp <= ro:
        raise SpecError("cam.outer_diameter", f"the pitch radius cam.cylinder_radius ({rp:g}) must lie within the "
                        f"groove's depth: outer radius {ro:g} − groove.depth {depth:g} ≤ R_p ≤ outer radius")
    min_wall = resolved(spec, "groove", "min_wall")
    rb = ro - depth
    if not rb - cam.bore_diameter / 2 >= min_wall or not rb > 0:
        raise SpecError("groove.depth", f"the groove's bottom (radius {rb:.4g}) must leave groove.min_wall "
                        f"({min_wall:g}) to the bore (radius {cam.bore_diameter / 2:g}): depth < "
                        f"{ro - cam.bore_diameter / 2 - min_wall:.4g}")
    w = 2 * half_width(spec)
    need = spec.max_lift + w + 2 * min_wall
    if not cam.length >= need:
        raise SpecError("cam.length", f"the lift range {spec.max_lift:g} plus the groove width {w:g} plus "
                        f"groove.min_wall {min_wall:g} at both ends needs cam.length ≥ {need:g}, got {cam.length:g}")


def cylinder_checks(spec) -> dict[str, Any]:
    """The cylindrical cam's design checks (report.json's ``checks`` section) without refusing an
    undercut wall (its check fails instead): what ``cam-workbench check`` shows for a cam that
    cannot be made."""
    from ..motion.program import MotionProgram

    return check_cylinder(spec, MotionProgram.from_spec(spec), CylinderLayout.of(spec), refuse=False)["checks"]



@dataclass(frozen=True)
class CylindricalFollower(TranslatingFollower):
    """The cylindrical cam's translating roller, its lift s along the cam axis; ``s0`` holds the
    pitch radius R_p.  The pressure angle is tan φ = s′/R_p (s′ per radian), so the normal contact
    force is F = Q/cos φ for the axial load Q, and the camshaft torque T = Q·s′ (virtual work)."""

    pressure_angle_text = "φ = atan(s′/R_p) (cylindrical cam: the lift along the cam axis)"

    def pressure_angle(self, k: Any) -> np.ndarray:
        """φ [rad] = atan(s′/R_p), signed."""
        return np.arctan2(k.ds, self.s0)

    def radius_of_curvature(self, k: Any) -> np.ndarray:
        """Radius of curvature [length] of the developed pitch line: (R_p² + s′²)^{3/2}/(R_p·s″)."""
        with np.errstate(divide="ignore"):
            return np.hypot(self.s0, k.ds) ** 3 / (self.s0 * k.d2s)

    def label(self) -> str:
        return f"translating roller r = {self.roller_radius:g}, along the cam axis"


def cylindrical_follower(spec) -> CylindricalFollower:
    """The follower of a cylindrical cam's spec (:class:`CylindricalFollower`)."""
    base = TranslatingFollower.from_spec(spec)
    return CylindricalFollower(0.0, spec.cam.cylinder_radius, base.sense, base.roller_radius, base.load)

"""The cylindrical (barrel) cam: a groove around a cylinder drives a roller whose axis is radial;
the follower translates parallel to the cam axis (the lift s(θ) is its axial displacement) or swings
on an arm about a radial pivot (the lift is the arm's angle in degrees).  Below, the translating
follower; the oscillating one (and the general centre line C_ρ with u, Z the roller centre's developed
path) is defined in :mod:`.cylinder_path` — every function here takes C_ρ from there, the
translating follower being its special case u = 0, Z = z₀ + s.

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
and, in the OCCT solid, on the built faces (``cam_workbench.kernel.solids``: ``wall_error``).

**Volume** (independent of the surfaces): at radius ρ the groove's developed cross-section is
the band between the offsets ±w/2 of C_ρ, whose area over one turn is exactly w·ℓ(ρ),
ℓ(ρ) = ∫₀^2π |C_ρ′| dθ = ∫₀^2π √(ρ² + s′²) dθ (the curvature terms of the two offsets cancel); the volume element
is dx·dz·dρ, so V_groove = w ∫_{R_b}^{R_o} ℓ(ρ) dρ and the cam's V = π(R_o² − r_bore²)·L − V_groove.

**Pressure angle** of the translating follower: the angle between the groove's normal and the
axial direction, tan φ = s′/ρ (s′ per radian): reported at the pitch radius (the design check) and
at the groove's bottom (the largest).
Oscillating: between the groove's normal and the roller's motion, perpendicular to the arm.

**Features** (plain data, :func:`cylinder_prisms`): the cylinder is a prism of the circle R_o
with the bore — keyed by :mod:`.features` as the plate and groove bodies are — from z = 0 to L; the
hub (``cam.hub_diameter`` × ``cam.hub_length``) stands on the z < 0 end face, bored and keyed the
same (the keyway runs the full length of body and hub); ``cam.mounting_holes`` axial holes on the
circle ``cam.mounting_circle_diameter`` go through the cylinder (0 ≤ z ≤ L) and must clear the
bore (and keyway) and stay inside R_b − ``groove.min_wall``; the timing mark is a slot
``timing_mark_depth`` deep in the end face z = L on the ray of θ = 0 (φ(0) = π/2, +Y, where the
keyway and the first hole point), from the bore to R_o less 1.5 mark widths, kept clear of the
holes as :func:`.features.timing_mark` does.  None of them meets the groove (the holes stay inside
R_b − min_wall, the mark is shallower than the groove's distance from the end face), so the exact
volume is Σ ± prism volumes (arcs and lines: closed-form areas) − V_groove.

Its drawing: :mod:`cam_workbench.exporters.dxf_cylindrical`; its follower for the force laws and the dynamics of a
translating roller: :class:`CylindricalFollower` (tan φ = s′/R_p).  What it does not carry: the
dynamics of an oscillating arm (refused naming ``follower.motion``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np


from ..checks.design import continuity_check, junction_text, unit_labels
from ..checks.status import limited_status
from ..errors import GeometryError, SpecError, fmt_apart
from ..followers.translating import TranslatingFollower
from ..kinds import follower_class_of, register_body
from ..motion.program import MotionProgram
from ..spec.optimise import CYLINDER_VARIABLES
from ..spec.toml_io import spec_digest
from ..studies.plan import Plan
from ..studies.table import checks_row
from .base import Loop, Prism
from .cylinder_path import (CentreLine, OscillatingPath, PathKinematics, RollerPath, TranslatingPath,
                            centre_line, expand, mid_arm_angle, pressure_angle)
from .features import bore_extent, bore_loop, hole_ligaments, hub_prism, mounting_holes, resolved, timing_mark

#: grid of the wall surfaces: θ-nodes per radian of a rise/return (at least 12 per segment), ρ-nodes
#: (the design's walls span R_b − depth/4 … R_o + depth/4: R_b and R_o are nodes)
NODES_PER_RAD = 45.0
RHO_NODES = 7
DEGREE_THETA = 5
DEGREE_RHO = 5
#: [spec length] the tolerances both kernels build the solid's groove faces with
#: (``cam_workbench.kernel.cylindrical``, ``cam_workbench.freecad.part_cylindrical``): the sewing's, and
#: OCCT's ``ShapeFix_Face`` precision and largest edge tolerance on the cylinder faces
SEW_TOLERANCE = 1e-6
FIX_PRECISION = 1e-7
FIX_MAX_TOLERANCE = 1e-5


def half_width(spec) -> float:
    """w/2 = roller radius + clearance/2."""
    return spec.roller_radius + resolved(spec, "groove", "clearance") / 2


@dataclass(frozen=True)
class CylinderLayout:
    """The cylinder's numbers (spec units) and the roller centre's developed path
    (:mod:`.cylinder_path`: translating or oscillating)."""

    pitch_radius: float
    outer_radius: float
    bottom_radius: float
    length: float
    z0: float                    # the roller centre's axial position at zero lift
    half_width: float
    sense: int                   # δ: +1 ccw, −1 cw
    bore_radius: float
    path: RollerPath | None = None       # None: the translating path u = 0, Z = z₀ + s

    def __post_init__(self) -> None:
        if self.path is None:
            object.__setattr__(self, "path", TranslatingPath(self.z0, math.inf))

    @staticmethod
    def of(spec) -> "CylinderLayout":
        cam = spec.cam
        rp = cam.cylinder_radius
        depth = spec.groove.depth
        ro = cam.outer_diameter / 2 if cam.outer_diameter is not None else rp + depth / 2
        if follower_class_of(spec).pivoted:
            f = spec.follower
            path: RollerPath = OscillatingPath.of(f.pivot_distance, f.arm_length, spec.max_lift, cam.length)
            z0 = path.z_range()[0]
        else:
            z0 = (cam.length - spec.max_lift) / 2
            path = TranslatingPath(z0, spec.max_lift)
        return CylinderLayout(rp, ro, ro - depth, cam.length, z0, half_width(spec),
                              1 if cam.direction == "ccw" else -1, cam.bore_diameter / 2, path)

    def phi(self, theta: np.ndarray) -> np.ndarray:
        """Cam-frame polar angle of the +Y generator (the roller centre line of a translating
        follower) at cam angle θ."""
        return np.pi / 2 - self.sense * np.asarray(theta, dtype=float)

    def centre_line(self, program, theta, rho, segment: np.ndarray | None = None) -> CentreLine:
        """The developed centre line C_ρ(θ) (and C′, C″) at cam angles θ and radii ρ, broadcast."""
        theta = np.asarray(theta, dtype=float)
        k = program.evaluate(theta, segment) if segment is not None else program.evaluate(np.mod(theta, 2 * np.pi))
        return self.centre_line_of(theta, self.path.evaluate(k), rho)

    def centre_line_of(self, theta, pk: PathKinematics, rho) -> CentreLine:
        """C_ρ from the path's kinematics ``pk`` at θ (shapes broadcast with ρ)."""
        return centre_line(self.pitch_radius, self.sense, self.phi(theta), pk, rho)

    def centre_point(self, program, theta: float) -> tuple[float, float, float]:
        """The roller centre (cam frame, 3D) at cam angle θ: on the pitch cylinder."""
        c = self.centre_line(program, np.array([theta]), self.pitch_radius)
        psi = float(c.x[0]) / self.pitch_radius
        return (self.pitch_radius * math.cos(psi), self.pitch_radius * math.sin(psi), float(c.z[0]))


def wall_points(layout: CylinderLayout, program, side: int, theta: np.ndarray, rho: np.ndarray) -> np.ndarray:
    """Exact points W_side(θ, ρ) (side +1: upper wall, −1: lower), broadcast over θ and ρ; (..., 3):
    C_ρ(θ) offset by side·w/2 along its developed normal, mapped onto the cylinder of radius ρ."""
    theta, rho = np.broadcast_arrays(np.asarray(theta, dtype=float), np.asarray(rho, dtype=float))
    c = layout.centre_line(program, theta, rho)
    x, z = c.offset(layout.sense, side * layout.half_width)
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
    rp = layout.pitch_radius
    # start: the cam angle whose centre line passes through the point's polar angle,
    # ψ = φ(θ) + δu(θ)/R_p, by fixed-point steps (|u′| < R_p)
    theta = layout.sense * (np.pi / 2 - psi)
    base = theta
    for _ in range(4):
        pk = layout.path.evaluate(program.evaluate(np.mod(theta, 2 * np.pi)))
        theta = base + pk.u / rp
    # the foot point can sit well away from that (a steep groove: the offset w/2 runs along the
    # circumference by w/2·sin φ): the nearest of a window of samples around it starts Newton
    window = np.linspace(-0.75, 0.75, 61)
    cand = theta[:, None] + window[None, :]
    cw = layout.centre_line(program, cand.ravel(), np.repeat(rho, window.size))
    d2 = ((rho[:, None] * _wrap(cw.x.reshape(cand.shape) / rho[:, None] - psi[:, None])) ** 2
          + (cw.z.reshape(cand.shape) - zp[:, None]) ** 2)
    theta = cand[np.arange(len(theta)), np.argmin(d2, axis=1)]
    for _ in range(iterations):
        c = layout.centre_line(program, theta, rho)
        dx = rho * _wrap(c.x / rho - psi)                   # developed x of C − P
        dz = c.z - zp
        g = dx * c.dx + dz * c.dz
        dg = c.dx * c.dx + c.dz * c.dz + dx * c.d2x + dz * c.d2z
        theta = theta - g / dg
    c = layout.centre_line(program, theta, rho)
    dx = rho * _wrap(c.x / rho - psi)
    dz = c.z - zp
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
        from scipy.interpolate import BSpline  # deferred: scipy.interpolate (a cylindrical cam's walls)

        nu, nv, _ = self.poles.shape
        su = BSpline(self.knots_u, self.poles.reshape(nu, nv * 3), self.degree_u, extrapolate=False)
        rows = su(np.asarray(u, dtype=float)).reshape(-1, nv, 3)
        v = np.asarray(v, dtype=float)
        out = np.empty((rows.shape[0], 3))
        for value in np.unique(v):            # one ρ-spline per distinct v, the points at it its columns
            at = np.flatnonzero(v == value)
            coef = np.transpose(rows[at], (1, 0, 2)).reshape(nv, -1)
            out[at] = BSpline(self.knots_v, coef, self.degree_v, extrapolate=False)(value).reshape(-1, 3)
        return out

    @property
    def u_range(self) -> tuple[float, float]:
        return float(self.knots_u[0]), float(self.knots_u[-1])


def wall_surfaces(layout: CylinderLayout, program, rho0: float, rho1: float) -> tuple[WallSurface, ...]:
    """Both walls, one surface per motion segment each, over ρ ∈ [rho0, rho1]."""
    from scipy.interpolate import make_interp_spline  # deferred: scipy.interpolate (a cylindrical cam's walls)

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
    """wall_points with the kinematics already evaluated (one-sided at segment ends): θ of shape
    (n,), ρ of shape (m,); (n, m, 3)."""
    c = layout.centre_line_of(th[:, None], expand(layout.path.evaluate(k)), rho[None, :])
    x, z = c.offset(layout.sense, side * layout.half_width)
    r = np.broadcast_to(rho[None, :], x.shape)
    psi = x / r
    return np.stack([r * np.cos(psi), r * np.sin(psi), np.broadcast_to(z, psi.shape)], axis=-1)


#: Gauss–Legendre nodes in ρ (ℓ(ρ) is analytic in ρ > 0) and per θ-interval of the adaptive rule
RHO_GAUSS = 12
THETA_GAUSS = 10
#: the groove volume's relative accuracy asked of the adaptive θ-rule (reached: ~1e-14, tests/test_cylindrical.py)
VOLUME_REL_TOL = 1e-14


def groove_volume(layout: CylinderLayout, program) -> float:
    """w ∫_{R_b}^{R_o} ℓ(ρ) dρ, ℓ(ρ) = ∫₀^2π |C_ρ′| dθ: Gauss–Legendre in ρ (:data:`RHO_GAUSS` nodes) and,
    per motion segment, adaptive Gauss–Legendre in θ — a law made of pieces (modified sine and
    trapezoid, a constant-velocity stroke's blends, B-spline and table lifts) has kinks in s″ or s‴
    inside its segment, where one rule over the segment is good to only ~1e-6."""
    x, wts = np.polynomial.legendre.leggauss(RHO_GAUSS)
    a, b = layout.bottom_radius, layout.outer_radius
    rho = (a + b) / 2 + (b - a) / 2 * x

    def integrand(th: np.ndarray, seg: int) -> np.ndarray:        # Σ_i w_i |C_ρi′(θ)|
        k = program.evaluate(th, np.full(th.shape, seg))
        speed = layout.centre_line_of(th[:, None], expand(layout.path.evaluate(k)), rho[None, :]).speed
        return speed @ wts

    bounds = program.boundaries
    total = sum(_adaptive_gauss(lambda th, k=seg: integrand(th, k), float(bounds[seg]), float(bounds[seg + 1]))
                for seg in range(len(program.starts)))
    return 2 * layout.half_width * (b - a) / 2 * total


def _adaptive_gauss(f, a: float, b: float, rel_tol: float = VOLUME_REL_TOL, max_depth: int = 40) -> float:
    """∫_a^b f: intervals halved until the :data:`THETA_GAUSS`-node rule on each agrees with the sum on its
    halves to ``rel_tol`` of the whole (pro rata of its length); ``f`` takes an array of points."""
    xg, wg = np.polynomial.legendre.leggauss(THETA_GAUSS)

    def rule(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        half = (hi - lo) / 2
        pts = (lo + half)[:, None] + half[:, None] * xg[None, :]
        return half * (f(pts.ravel()).reshape(pts.shape) @ wg)

    lo, hi = np.array([a]), np.array([b])
    whole = rule(lo, hi)
    scale = abs(float(whole[0])) + 1e-300
    total = 0.0
    for depth in range(max_depth + 1):
        mid = (lo + hi) / 2
        left, right = rule(lo, mid), rule(mid, hi)
        halves = left + right
        done = np.abs(halves - whole) <= rel_tol * scale * (hi - lo) / (b - a)
        if depth == max_depth:
            done[:] = True
        total += float(np.sum(halves[done]))
        keep = ~done
        if not keep.any():
            break
        lo, hi = np.concatenate([lo[keep], mid[keep]]), np.concatenate([mid[keep], hi[keep]])
        whole = np.concatenate([left[keep], right[keep]])
    return total


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
    #: the cylinder (bored, keyed), the hub, the mounting holes and the timing mark as prisms applied in
    #: order (:func:`cylinder_prisms`); the groove is cut after them
    stack: tuple[Prism, ...] = ()
    kind: str = "cylindrical"
    prismatic: bool = False
    extra: dict = field(default_factory=dict)

    @property
    def volume(self) -> float:
        """Exact volume [length³]: Σ ± the stack's prism volumes (closed-form areas × heights) − V_groove."""
        return float(sum(p.volume if p.op == "add" else -p.volume for p in self.stack)) - self.groove_volume

    def face_area_at(self, z: float) -> float:
        """Area of the planar face at height ``z`` seen from above (z = length: the end face, the
        annulus less the keyway, the holes and the timing mark; the groove stays inside)."""
        return float(sum((p.area if p.op == "add" else -p.area) for p in self.stack if p.z0 < z <= p.z1 + 1e-12))

    @property
    def z_range(self) -> tuple[float, float]:
        return min([0.0] + [p.z0 for p in self.stack]), self.layout.length

    @property
    def prisms(self) -> tuple:
        """None: the body is not a stack of prisms alone (the plane-cam readers skip it); the
        features are in :attr:`stack`."""
        return ()

    def has(self, role: str) -> bool:
        """Whether the stack holds a prism of ``role`` ("hub", "hole0", "timing_mark", …)."""
        return any(p.role == role for p in self.stack)

    def loops(self) -> list:
        return []


# ---- checks -----------------------------------------------------------------------------------
def developed_curvature_radius(layout: CylinderLayout, program, rho: float, th: np.ndarray) -> np.ndarray:
    """|radius of curvature| of C_ρ at θ: |C′|³ / |x′z″ − z′x″| (inf where that is 0); translating:
    (ρ² + s′²)^{3/2} / (ρ·|s″|)."""
    c = layout.centre_line(program, th, rho)
    num = c.speed ** 3
    den = np.abs(c.dx * c.d2z - c.dz * c.d2x)
    return np.where(den > 0, num / np.where(den > 0, den, 1.0), np.inf)


def pressure_angles(layout: CylinderLayout, program, rho: float, th: np.ndarray) -> np.ndarray:
    """Signed pressure angle [deg] at radius ρ: between the groove's normal and the roller's direction
    of motion (translating: atan(s′/ρ); oscillating: perpendicular to the arm, see
    :func:`.cylinder_path.pressure_angle`)."""
    pk = layout.path.evaluate(program.evaluate(th))
    return np.rad2deg(pressure_angle(layout.pitch_radius, pk, rho))


@dataclass(frozen=True)
class Corner:
    """A junction of the motion where the velocity jumps (``junction.order`` < 1): the developed
    centre line C_ρ turns a corner there (radius of curvature 0 on every cylinder), so the walls'
    offsets along the normals of the two sides part — by ``parting`` (spec length) at the radius
    ``at_radius``, the largest over the groove's depth — and the walls of the two segments do not meet."""

    junction: Any
    parting: float
    at_radius: float
    text: str                     # the junction in words (the continuity check's line)
    jump: str                     # the velocity's jump in words, e.g. "the velocity jumps by -1.879 mm/rad"
    fix: str                      # the spec fields that remove it


def centre_line_corners(spec, program, layout: CylinderLayout) -> list[Corner]:
    """Every corner of the groove's centre line (:class:`Corner`): the junctions whose velocity jumps,
    by :meth:`MotionProgram.junctions` (the continuity check's own analysis, 1e-6 of the values)."""
    lab = unit_labels(spec.units, "angle" if layout.path.pivoted else "length")
    radii = np.linspace(layout.bottom_radius, layout.outer_radius, 5)
    out = []
    for j in program.junctions():
        if j.order >= 1:
            continue
        at = program.starts[j.right]
        # C′ on either side (one-sided: each segment's own law), at each radius
        cl = layout.centre_line(program, np.full(radii.shape, at if j.right else 2 * np.pi), radii,
                                np.full(radii.shape, j.left))
        cr = layout.centre_line(program, np.full(radii.shape, at), radii, np.full(radii.shape, j.right))
        turn = np.abs(np.arctan2(cl.dx * cr.dz - cl.dz * cr.dx, cl.dx * cr.dx + cl.dz * cr.dz))
        parting = 2 * layout.half_width * np.sin(turn / 2)        # between the two normals' offset points
        i = int(np.argmax(parting))
        out.append(Corner(j, float(parting[i]), float(radii[i]), junction_text(j, program, lab),
                          f"the velocity jumps by {j.jumps[1]:.4g} {lab['reduced_velocity']} from motion[{j.left}] "
                          f"to motion[{j.right}]", _corner_fix(spec, j)))
    return out


def cylinder_corners(spec) -> list[Corner]:
    """:func:`centre_line_corners` of a validated spec (its program and layout)."""
    return centre_line_corners(spec, MotionProgram.from_spec(spec), CylinderLayout.of(spec))


def _corner_fix(spec, j) -> str:
    """The fields that make the velocity continuous at junction ``j``: an unblended end of a
    constant-velocity stroke takes a blend, a velocity given at the end goes; otherwise laws that
    match their neighbours."""
    left, right = spec.motion[j.left], spec.motion[j.right]
    ends = ((j.left, "end", left, left.end_blend, left.end_velocity),
            (j.right, "start", right, right.start_blend, right.start_velocity))
    blends = [f"motion[{k}].{end}_blend" for k, end, seg, blend, _v in ends
              if seg.law == "constant_velocity" and not blend]
    if blends:
        return "a blend (" + " or ".join(blends) + ")"
    given = [f"motion[{k}].{end}_velocity" for k, end, _seg, _b, v in ends if v is not None]
    if given:
        return "velocities that match the neighbour's (" + " or ".join(given) + ")"
    moving = [f"motion[{k}].law" for k in (j.left, j.right) if spec.motion[k].law is not None]
    return "laws that match their neighbours' velocity there (" + " or ".join(moving) + ")"


def check_cylinder(spec, program, layout: CylinderLayout, refuse: bool = True) -> dict[str, Any]:
    """Undercut (refused, GeometryError with the cam angle, unless ``refuse`` is False: then the
    ``undercut`` check fails), pressure angle, the motion's continuity at its junctions and the
    walls: the body's report numbers and a ``checks`` section in report.json's shape.

    A junction where the velocity jumps is a corner of the centre line (:func:`centre_line_corners`):
    radius of curvature 0, the undercut at its cam angle — the walls' offsets part there."""
    th = program.dense_angles(2001)
    w2 = layout.half_width
    oscillating = layout.path.pivoted
    if oscillating:
        # the developed centre line must advance with the cam: |u′| < R_p (else it turns back on itself)
        pk = layout.path.evaluate(program.evaluate(th))
        q = layout.pitch_radius - pk.du
        i = int(np.argmin(q))
        if not q[i] > 0:
            at = float(np.rad2deg(th[i]) % 360)
            raise GeometryError("path", f"the roller would move along the circumference faster than the cam surface "
                                f"at cam angle {at:.2f}° (the arm's tangential speed {-pk.du[i]:.4g} per rad ≥ "
                                f"cam.cylinder_radius {layout.pitch_radius:g}): a gentler motion or a shorter arm",
                                at)
    # the wall on the concave side folds where the developed curve's radius of curvature ≤ w/2;
    # smallest at the smallest radius the walls reach
    radii = np.linspace(layout.bottom_radius, layout.outer_radius, 5)
    worst = (math.inf, 0.0, 0.0)
    for r in radii:
        rc = developed_curvature_radius(layout, program, r, th)
        i = int(np.argmin(rc))
        if rc[i] < worst[0]:
            worst = (float(rc[i]), float(np.rad2deg(th[i]) % 360), float(r))
    corners = centre_line_corners(spec, program, layout)
    undercut_note = ""
    if corners:
        c = corners[0]
        worst = (0.0, c.junction.at_deg % 360.0, c.at_radius)
        undercut_note = (f"a corner of the centre line ({c.jump}): the walls' offsets part by {c.parting:.4g} "
                         f"{spec.units} at radius {c.at_radius:.4g}; no size removes it — {c.fix}"
                         + (f"; and {len(corners) - 1} more corners" if len(corners) > 1 else ""))
        if refuse:
            raise GeometryError("undercut", f"the groove's centre line turns a corner at cam angle {worst[1]:.2f}° "
                                f"— {c.text} — where its walls' offsets part by {c.parting:.4g} {spec.units} "
                                f"(radius of curvature 0 ≤ half the groove width {w2:g}): a cylindrical cam's groove "
                                f"needs the velocity continuous at every junction — {c.fix}", worst[1])
    if worst[0] <= w2 and refuse:
        raise GeometryError("undercut", f"the groove's wall is undercut at cam angle {worst[1]:.2f}°: the developed "
                            f"centre line's radius of curvature at radius {worst[2]:.4g} is {fmt_apart(worst[0], w2, 4)} ≤ half the "
                            f"groove width {w2:g} — a smaller roller, a larger cam.cylinder_radius or a gentler motion",
                            worst[1])
    phi_p = pressure_angles(layout, program, layout.pitch_radius, th)
    phi_b = pressure_angles(layout, program, layout.bottom_radius, th)
    ip, ib = _first_largest(np.abs(phi_p)), _first_largest(np.abs(phi_b))
    limit = spec.checks.max_pressure_angle
    factor = spec.checks.undercut_factor
    if oscillating:
        what_p = ("Pressure angle at the pitch radius: between the groove's normal and the roller centre's motion, "
                  "perpendicular to the arm: tan φ = (L β′ + R_p sin β)/(R_p cos β)")
        what_b = "Pressure angle at the groove's bottom radius (the roller's section there, moving with the arm)"
        formula = ("between the groove's normal and the roller's motion perpendicular to the arm (developed pitch "
                   "plane): tan φ = (L β′ + R_p sin β)/(R_p cos β), β′ per radian")
    else:
        what_p = "Pressure angle at the pitch radius, tan φ = s′/R_p (s′ per radian)"
        what_b = "Pressure angle at the groove's bottom radius, tan φ = s′/R_b"
        formula = "tan φ = s′/ρ (translating follower along the cam axis, s′ per radian)"
    results = {
        "pressure_angle": _result(what_p, "max", abs(float(phi_p[ip])), float(np.rad2deg(th[ip]) % 360), limit,
                                  "deg"),
        "pressure_angle_bottom": _result(what_b, "max", abs(float(phi_b[ib])), float(np.rad2deg(th[ib]) % 360), None,
                                         "deg", "no limit: checks.max_pressure_angle applies at the pitch radius, "
                                                "so this is reported, not checked"),
        "undercut": _result("Smallest radius of curvature of the developed centre line (over the groove's depth), "
                            "against undercut_factor × groove half width", "min", worst[0], worst[1],
                            factor * w2, spec.units, note=undercut_note),
    }
    cont = continuity_check(program, spec.checks.min_continuity,
                            unit_labels(spec.units, "angle" if oscillating else "length"))
    if cont is not None:
        results["continuity"] = cont.to_dict()
    failed = [k for k, r in results.items() if r["status"] == "fail"]
    checks = {"passed": not failed, "failed": failed, "sampling": "dense", "samples_per_segment": 2001,
              "points": int(th.shape[0]), "results": results, "extremes": {}}
    zlo, zhi = layout.path.z_range()
    walls = {"bottom_to_end": zlo - w2, "top_to_end": layout.length - (zhi + w2),
             "groove_bottom_to_bore": layout.bottom_radius - layout.bore_radius}
    pressure = {"max_deg": abs(float(phi_p[ip])), "signed_deg": float(phi_p[ip]),
                "at_deg": float(np.rad2deg(th[ip]) % 360), "at_radius": layout.pitch_radius,
                "bottom_max_deg": abs(float(phi_b[ib])), "bottom_at_deg": float(np.rad2deg(th[ib]) % 360),
                "formula": formula}
    return {"checks": checks, "walls": walls, "pressure_angle": pressure,
            "min_developed_curvature_radius": {"value": worst[0], "at_deg": worst[1], "at_radius": worst[2]}}


def _first_largest(a: np.ndarray) -> int:
    """Index of the first sample within 1e-12 (relative) of the largest: a symmetric motion's equal
    extremes are reported at the first cam angle in every numpy build (not by round-off)."""
    return int(np.argmax(a >= np.max(a) * (1 - 1e-12)))


def _result(description, kind, value, at, limit, unit, no_limit: str = "", note: str = "") -> dict[str, Any]:
    """A check's entry of report.json's ``checks.results`` (as :class:`CheckResult.to_dict`); without a
    limit it is reported, not passed ("skipped", ``no_limit`` saying why); ``note``: what the value is."""
    status = limited_status(None if limit is None else (value <= limit if kind == "max" else value >= limit))
    return {"description": description, "kind": kind, "value": value, "at_deg": at, "limit": limit, "unit": unit,
            "status": status, "passed": status != "fail", "note": no_limit if limit is None else note}


# ---- the design -------------------------------------------------------------------------------
@dataclass(frozen=True)
class CylindricalDesign:
    """A designed cylindrical cam (plain values; no CAD kernel). The plane-cam members of
    :class:`~cam_workbench.generators.cam_design.CamDesign` (pitch curve, profile) do not exist here."""

    spec: Any
    program: Any
    body: CylindricalGeometry
    body_report: dict
    checks_report: dict
    #: not a plane cam: no plane pitch curve or profile (its outputs are its own, registered per design class)
    plane = False
    #: what stands for the plane pitch curve and profile it does not have (``CamDesign.instead_of_plane_curves``)
    instead_of_plane_curves = ("its groove walls are surfaces around the cylinder: use solid() for the wall faces, "
                            "design.wall_points(side, theta, rho) for exact points of a wall, or export_dxf() "
                            "for the developed view instead")
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

    def developed_points(self, rho: float, side: int, theta: np.ndarray, segment: np.ndarray | None = None
                         ) -> np.ndarray:
        """Exact developed points (x, z), (n, 2), of the centre line C_ρ at radius ρ offset by
        side·w/2 along its normal (side 0: the centre line, +1 the upper wall, −1 the lower)."""
        lay = self.layout
        c = lay.centre_line(self.program, theta, rho, segment)      # the follower's own path (translating or arm)
        x, z = c.offset(lay.sense, side * lay.half_width)
        return np.column_stack([x, z])

    def wall_distance_error(self, side: int, points: np.ndarray) -> np.ndarray:
        return wall_distance_error(self.layout, self.program, side, points)

    def _follower(self) -> dict[str, Any]:
        r = self.spec.roller_radius
        path = self.layout.path
        if path.pivoted:
            return {"kind": "roller", "motion": path.motion, "roller_radius": r,
                    "label": f"oscillating roller r = {r:g}, pivot d = {path.pivot_distance:g}, arm L = "
                             f"{path.arm_length:g} (radial pivot, developed pitch plane)", **path.describe()}
        return {"kind": "roller", "motion": path.motion, "label": f"translating roller r = {r:g}, along the cam "
                "axis", "roller_radius": r}

    def label(self) -> str:
        """One line that identifies the cam: its body, its follower and its numbers (spec units)."""
        return (f"cylindrical cam, lengths in {self.spec.units}: {self._follower()['label']}; "
                f"{CylindricalBody.label(self.spec)}")

    def summary(self) -> dict[str, Any]:
        spec = self.spec
        maxima = self.program.maxima(spec.cam.speed_rpm * 2 * np.pi / 60)
        return {
            "units": spec.units,
            "spec_digest": spec_digest(spec),
            "pressure_angle": self.checks_report["pressure_angle"],
            "follower": self._follower(),
            "motion": {"lift_unit": "deg" if self.layout.path.pivoted else spec.units,
                       "max_lift": spec.max_lift, "max_velocity": maxima["velocity"],
                       "max_acceleration": maxima["acceleration"], "max_jerk": maxima["jerk"],
                       **self.program.report()},
            "area": self.area,
            "volume": self.volume,
            "checks": self.checks_report["checks"],
            "body": {**self.body_report, "volume": self.volume, "top_face_area": self.area},
        }


@register_body
class CylindricalBody:
    """A groove around a cylinder (see the module docstring)."""

    kind = "cylindrical"
    title = "Cylindrical cam"
    #: not a plane cam: walls are surfaces, no pitch curve or profile in a plane
    plane = False
    roller_within_base = True
    dynamics_train = "follower"
    own_fields = ("outer_diameter", "cylinder_radius", "length")
    modules = ("cam_workbench.generators.bodies.cylinder_path", "cam_workbench.generators.machining.cylindrical",
               "cam_workbench.generators.optimise.cylindrical")
    closure = "form"
    #: which side drives (the follower dynamics' form-closure note)
    drive_note = ("the groove holds the roller both ways; the wall that drives changes where the contact force "
                  "changes sign (positive: pushing the follower along +s, the lower wall; negative: the upper wall)")

    @staticmethod
    def dynamics_follower(spec) -> "CylindricalFollower":
        """The follower the dynamics drive (:func:`cylindrical_follower`)."""
        return cylindrical_follower(spec)

    @staticmethod
    def refuse_foreign(spec) -> None:
        """Rules this body puts on the specs of other bodies: none beyond its own fields."""

    @staticmethod
    def lift_unit(spec) -> str:
        """The follower's (``Follower.lift_unit``)."""
        return follower_class_of(spec).lift_unit

    @staticmethod
    def motion_advance(spec) -> float:
        """The follower's program closes: 0."""
        return 0.0

    #: the field that sizes the cam (its pitch radius)
    size_field = "cam.cylinder_radius"
    #: no plane drawing of the body (its own figures)
    drawing_label = None
    #: the objectives its own optimiser serves: the cylinder's size
    optimise_objectives = ("outer_diameter",)
    #: the optimiser's design variables (its own optimiser: cam_workbench.generators.optimise.cylindrical)
    optimise_variables = CYLINDER_VARIABLES

    @staticmethod
    def study_row(summary, base_radius: float) -> dict[str, Any]:
        """The key numbers of a designed cylindrical cam for a study's table (no plane profile:
        the cylinder's own numbers) from its summary."""
        pa, mo = summary["pressure_angle"], summary["motion"]
        body = summary["body"]
        row = {"units": summary["units"], "follower": summary["follower"]["label"],
               "base_radius": float(base_radius), "max_lift": mo["max_lift"],
               "pressure_angle_deg": pa["max_deg"], "pressure_angle_at_deg": pa["at_deg"],
               "pressure_angle_bottom_deg": pa["bottom_max_deg"],
               "min_developed_curvature_radius": body["min_developed_curvature_radius"]["value"],
               "outer_radius": body["outer_radius"], "area": summary["area"], "volume": summary["volume"]}
        row.update(checks_row(summary["checks"]))
        return row

    @staticmethod
    def own_checks(spec) -> dict[str, Any]:
        """The cylinder's design checks, refusing nothing (:func:`cylinder_checks`)."""
        return cylinder_checks(spec)

    @staticmethod
    def remedy_plans(spec, check: str) -> list[Plan]:
        """The pitch radius sizes the pressure angle and, unless the centre line turns a corner (its
        radius of curvature 0 at any size), the undercut; searched with the cylinder's own checks."""
        sized = check == "pressure_angle" or (check == "undercut" and not cylinder_corners(spec))
        return [Plan("cam.cylinder_radius", "smallest", "body")] if sized else []

    @staticmethod
    def remedy_words(spec, check: str) -> str | None:
        """An undercut at a corner of the centre line: no size removes it."""
        if check != "undercut":
            return None
        c = cylinder_corners(spec)[0]
        return (f"the groove's centre line turns a corner at {c.junction.at_deg % 360.0:.2f}° (the velocity jumps): "
                f"no size removes it — {c.fix}")

    @staticmethod
    def profile_inset(spec) -> float:
        return resolved(spec, "groove", "clearance") / 2

    @staticmethod
    def label(spec) -> str:
        """The numbers that identify a cylindrical cam (spec lengths, no unit): its radii, length and groove."""
        lay = CylinderLayout.of(spec)
        return (f"pitch radius {lay.pitch_radius:g}, outer radius {lay.outer_radius:g}, length {lay.length:g}, "
                f"groove {2 * lay.half_width:g} wide, {lay.outer_radius - lay.bottom_radius:g} deep")

    @staticmethod
    def further_followers(spec) -> tuple:
        return ()

    @staticmethod
    def design(spec, progress=None) -> CylindricalDesign:
        """The cylindrical cam of ``spec`` (GeometryError: an undercut wall, with the cam angle);
        ``progress`` is not reported (no iterative solve)."""
        program = MotionProgram.from_spec(spec)
        layout = CylinderLayout.of(spec)
        report = check_cylinder(spec, program, layout)
        depth = layout.outer_radius - layout.bottom_radius
        margin = 0.25 * depth
        rho = (layout.bottom_radius - margin, layout.outer_radius + margin)
        walls = wall_surfaces(layout, program, *rho)
        vg = groove_volume(layout, program)
        geometry = CylindricalGeometry(layout, walls, rho, vg, cylinder_prisms(spec, layout))
        fit = wall_fit_error(geometry, program)
        body_report = {
            "kind": "cylindrical", "closure": "form",
            "pitch_radius": layout.pitch_radius, "outer_radius": layout.outer_radius,
            "bottom_radius": layout.bottom_radius, "length": layout.length, "groove_width": 2 * layout.half_width,
            "groove_depth": depth, "z0": layout.z0, "lift_range": list(layout.path.z_range()), "follower_path": layout.path.describe(),
            "axis": "Z (cam frame); the roller on +Y of the fixed frame, its axis radial",
            "walls": report["walls"], "min_developed_curvature_radius": report["min_developed_curvature_radius"],
            "groove_volume": vg, "features": feature_report(spec, layout),
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


def cylinder_prisms(spec, layout: CylinderLayout) -> tuple[Prism, ...]:
    """The cylinder (circle R_o less the keyed bore, 0 ≤ z ≤ L), the hub below z = 0, the mounting
    holes through 0 ≤ z ≤ L and the timing mark in the end face z = L, as prisms in the order they
    are applied (lengths in the spec's unit).

    Raises:
        SpecError: no room for the timing mark between the bore and the holes (``cam.timing_mark``)."""
    bore = bore_loop(spec)
    out = [Prism(Loop.circle(layout.outer_radius, role="cylinder"), (bore,) if bore else (), 0.0, layout.length,
                 "add", "cylinder")]
    hub = hub_prism(spec, 0.0)
    if hub is not None:
        out.append(hub)
    out += mounting_holes(spec, 0.0, layout.length)
    mw = resolved(spec, "cam", "timing_mark_width")
    # on the ray of θ = 0: φ(0) = π/2 for either sense (the roller on +Y), as the keyway
    mark = timing_mark(spec, float(layout.phi(np.array([0.0]))[0]), bore_extent(spec) + 1.5 * mw,
                       layout.outer_radius - 1.5 * mw, layout.length)
    if mark is not None:
        out.append(mark)
    return tuple(out)


def feature_report(spec, layout: CylinderLayout) -> dict[str, Any]:
    """The material around the features (report.json ``body.features``, spec lengths): the keyway's
    reach, the mounting holes' ligaments to the bore, to R_b − groove.min_wall and to each other."""
    cam = spec.cam
    out: dict[str, Any] = {"bore_extent": bore_extent(spec)}
    if cam.hub_diameter:
        out["hub"] = {"diameter": cam.hub_diameter, "length": cam.hub_length}
    if cam.mounting_holes:
        limit = layout.bottom_radius - resolved(spec, "groove", "min_wall")
        out["hole_ligaments"] = hole_ligaments(spec, lambda a: np.full(np.shape(a), limit), bore_extent(spec))
    return out


def _validate_features(spec, rb: float, min_wall: float, w: float) -> None:
    """Hub, keyway, holes and timing mark of a cylindrical cam (SpecError naming the field)."""
    cam = spec.cam
    if (cam.keyway_width is None) != (cam.keyway_depth is None) or (cam.keyway_width is not None and cam.keyway) \
            or (cam.mounting_holes and None in (cam.mounting_hole_diameter, cam.mounting_circle_diameter)):
        return                     # the shared feature rules (bodies.features.validate_features) name the field next
    reach = bore_extent(spec)
    if (cam.keyway is not None or cam.keyway_width is not None) and not rb - reach >= min_wall:
        name = "cam.keyway_depth" if cam.keyway_width is not None else "cam.keyway"
        raise SpecError(name, f"the keyway reaches {fmt_apart(reach, rb - min_wall, 4)} from the axis: it must leave "
                        f"groove.min_wall ({min_wall:g}) to the groove's bottom (radius {rb:.4g}), reaching at most "
                        f"{fmt_apart(rb - min_wall, reach, 4)}")
    if cam.mounting_holes:
        limit = rb - min_wall
        lig = hole_ligaments(spec, lambda a: np.full(np.shape(a), limit), reach)
        rules = {"to_bore": f"must clear the bore and keyway (radius {reach:.4g})",
                 "to_outer": f"must stay inside the groove's bottom radius {rb:.4g} less groove.min_wall "
                             f"{min_wall:g} (radius {limit:.4g})",
                 "between": "must not run into each other"}
        for key, rule in rules.items():
            if not lig[key] > 0:
                raise SpecError("cam.mounting_circle_diameter", f"the mounting holes (diameter "
                                f"{cam.mounting_hole_diameter:g} on a circle of {cam.mounting_circle_diameter:g}) "
                                f"{rule}: {lig[key]:.4g} of material left")
    if cam.timing_mark:
        depth = resolved(spec, "cam", "timing_mark_depth")
        fol = spec.follower
        travel = (2 * fol.pivot_distance * math.sin(math.radians(spec.max_lift) / 2)
                  if follower_class_of(spec).pivoted else spec.max_lift)      # the roller centre's axial travel
        room = (cam.length - travel - w) / 2
        if not depth < room:
            raise SpecError("cam.timing_mark_depth", f"must be < the groove's distance from the end face "
                            f"({fmt_apart(room, depth, 4)}), got {fmt_apart(depth, room)}")


def validate_cylindrical(spec) -> None:
    """The cylindrical body's own rules (called by the spec's validation)."""
    cam, fol = spec.cam, spec.follower
    if not spec.is_roller:
        raise SpecError("follower.kind", f'a cylindrical cam needs a roller follower, got "{fol.kind}"')
    if fol.offset != 0:
        raise SpecError("follower.offset", "does not apply to a cylindrical cam (the roller axis is radial)")
    for name in ("cylinder_radius", "length"):
        if getattr(cam, name) is None:
            raise SpecError(f"cam.{name}", "is required for a cylindrical cam")
    if cam.base_radius != cam.cylinder_radius:
        raise SpecError("cam.base_radius", f"is the pitch radius for a cylindrical cam: leave it out or give "
                        f"cam.cylinder_radius ({fmt_apart(cam.cylinder_radius, cam.base_radius)}), got "
                        f"{fmt_apart(cam.base_radius, cam.cylinder_radius)}")
    if cam.thickness != cam.length:
        raise SpecError("cam.thickness", f"is the cylinder's length for a cylindrical cam: leave it out or give "
                        f"cam.length ({fmt_apart(cam.length, cam.thickness)}), got {fmt_apart(cam.thickness, cam.length)}")
    if spec.groove.depth is None:
        raise SpecError("groove.depth", "is required for a cylindrical cam")
    depth = spec.groove.depth
    rp = cam.cylinder_radius
    ro = cam.outer_diameter / 2 if cam.outer_diameter is not None else rp + depth / 2
    if not ro - depth <= rp <= ro:
        bound = ro if rp > ro else ro - depth
        raise SpecError("cam.outer_diameter", f"the pitch radius cam.cylinder_radius ({fmt_apart(rp, bound)}) must lie "
                        f"within the groove's depth: outer radius {ro:g} − groove.depth {depth:g} = "
                        f"{fmt_apart(ro - depth, rp)} ≤ R_p ≤ outer radius {fmt_apart(ro, rp)}")
    min_wall = resolved(spec, "groove", "min_wall")
    rb = ro - depth
    if not rb - cam.bore_diameter / 2 >= min_wall or not rb > 0:
        most = ro - cam.bore_diameter / 2 - min_wall
        raise SpecError("groove.depth", f"the groove's bottom (radius {rb:.4g}) must leave groove.min_wall "
                        f"({min_wall:g}) to the bore (radius {cam.bore_diameter / 2:g}): depth ≤ "
                        f"{fmt_apart(most, depth, 4)}, got {fmt_apart(depth, most)}")
    w = 2 * half_width(spec)
    if follower_class_of(spec).pivoted:
        travel = _validate_arm(spec)
        if not cam.length >= travel + w + 2 * min_wall:
            raise SpecError("cam.length", f"the roller's axial travel 2·pivot_distance·sin(lift/2) = {travel:.6g} "
                            f"plus the groove width {w:g} plus groove.min_wall {min_wall:g} at both ends needs "
                            f"cam.length ≥ {fmt_apart(travel + w + 2 * min_wall, cam.length)}, got "
                            f"{fmt_apart(cam.length, travel + w + 2 * min_wall)}")
    else:
        need = spec.max_lift + w + 2 * min_wall
        if not cam.length >= need:
            raise SpecError("cam.length", f"the lift range {spec.max_lift:g} plus the groove width {w:g} plus "
                            f"groove.min_wall {min_wall:g} at both ends needs cam.length ≥ {fmt_apart(need, cam.length)}, "
                            f"got {fmt_apart(cam.length, need)}")
    _validate_features(spec, rb, min_wall, w)
    if spec.dynamics.enabled and follower_class_of(spec).pivoted:
        raise SpecError("follower.motion", "the follower dynamics of a cylindrical cam cover a translating roller "
                        "only (an oscillating arm's train is not modelled yet)")


def _validate_arm(spec) -> float:
    """An oscillating roller on a cylindrical cam (see :mod:`.cylinder_path`): d ≤ L, the arm within
    90° of the circumference over the lift; returns the roller's axial travel 2d·sin(s_max/2)."""
    fol = spec.follower
    d, L = fol.pivot_distance, fol.arm_length
    if not d <= L:
        raise SpecError("follower.arm_length", f"the arm cannot reach the +Y generator of the pitch cylinder (the "
                        f"roller's line at mid-lift): a cylindrical cam needs arm_length ≥ pivot_distance (the pivot's "
                        f"distance along the circumference), got L = {fmt_apart(L, d)} < d = {fmt_apart(d, L)}")
    bm = math.degrees(mid_arm_angle(d, L))
    h = spec.max_lift
    if not bm + h / 2 < 90.0:
        level, top, at = 0.0, 0.0, 0
        for i, seg in enumerate(spec.motion):
            level += (seg.lift or 0.0) * (1 if seg.kind == "rise" else -1 if seg.kind == "return" else 0)
            if level > top:
                top, at = level, i
        raise SpecError(f"motion[{at}].lift", f"the arm would turn past the perpendicular to the cam axis (the "
                        f"roller's axial motion reverses): arccos(pivot_distance/arm_length) = {bm:.4g}° plus half the "
                        f"lift {h / 2:g}° = {fmt_apart(bm + h / 2, 90.0)}° must stay below 90°")
    return 2 * d * math.sin(math.radians(h) / 2)


def cylinder_checks(spec) -> dict[str, Any]:
    """The cylindrical cam's design checks (report.json's ``checks`` section) without refusing an
    undercut wall (its check fails instead): what ``cam-workbench check`` shows for a cam that
    cannot be made."""
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
    """The follower of a cylindrical cam's spec (:class:`CylindricalFollower`): a translating roller
    (an oscillating arm's force laws are not modelled: SpecError naming ``follower.motion``)."""
    if follower_class_of(spec).pivoted:
        raise SpecError("follower.motion", "the follower dynamics of a cylindrical cam cover a translating roller "
                        "only (an oscillating arm's train is not modelled yet)")
    base = TranslatingFollower.from_spec(spec)
    return CylindricalFollower(0.0, spec.cam.cylinder_radius, base.sense, base.roller_radius, base.load)

"""Tool paths that cut a designed cam, as plain geometry (the G-code text is made in
``cam_workbench.exporters.gcode``).

The tool centre must stay at the tool radius R_t from the profile, and the profile is
the pitch curve moved inward by the roller radius r, so the exact tool-centre path is
the **pitch curve offset outward by R_t − r** (by R_t for a knife edge): an exact
degree-9 rational NURBS (:func:`cam_workbench.generators.curves.offsets.offset_nurbs`), the pitch curve
itself when the tool is the roller's size.

Two ways to follow it:

* **XY contour milling** (:func:`contour_path`): the cam is fixed on the table (work
  origin on the cam axis, Z = 0 on the top face) and the tool centre runs along the
  path, emitted as biarcs (G02/G03) or chords (G01) within ``chord_tolerance``, entered
  and left on tangent quarter-circle arcs in the middle of the longest dwell, once per
  depth pass; climb milling (spindle M3) runs an outside contour clockwise.  Under the
  control's cutter compensation (:func:`part_contour_path`) the same is programmed on the part's
  own contour (the profile), entered and left by straight lines on which G41/G42 and G40 act.
* **XC rotary machining** (:func:`rotary_path`): the cam turns on a C axis at
  ``rotary_speed_rpm`` and the tool centre moves on a straight line — the follower's
  own line x = e (``rotary_line = "follower"``) or a line through the C axis (x = 0,
  ``"axis"``, a two-axis X–C grinder or lathe).  Every Δt the cam has turned
  θ_k = kωΔt (C = δ·θ_k in degrees, δ = +1 ccw) and the tool centre is where that line
  meets the tool-centre path (paper Eq. 13 on the offset curve).  With R_t = r on the
  follower's line the tool centre *is* the roller centre: X_k = s₀ + s_actual(θ_k),
  straight from the paper's commands (Eq. 15).

Machine frame of the XC program: +X along the tool's line, pointing away from the C
axis (the follower's direction of motion), Z along the cam axis, so Y = −(line
offset); positive C turns the cam counter-clockwise seen from +Z (the cam frame is
the machine frame turned by C).  At C = 0 the cam's +Y axis lies along machine +X.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from ..curves.approx import Path2D, fit_biarcs, flatten, max_distance, polyline_curve_distance, polyline_path
from ..cam_design import CamDesign, profile_offset_distance
from ..errors import GeometryError, SolveError, SpecError, fmt_apart
from ..pitch.contact import horner, power_coeffs
from .interpolator import Commands, RotationalInterpolator
from .plan import MachiningPlan
from ..curves.nurbs import NurbsCurve
from ..curves.offsets import offset_nurbs
from ..curves.ph_spline import PHSpline
from ..pitch.ph import PitchCurve
from ..followers.translating import TranslatingFollower
from ..pitch.bspline import BSplinePitchCurve, distance_to_offset, fit_offset

TWO_PI = 2.0 * np.pi
#: Fit the contour to this fraction of the chord tolerance; of the rest, BLEND_SHARE goes to
#: the controller's path blending (LinuxCNC G64 P) and the remainder covers the rounding of
#: the G-code's coordinates (4 decimals in mm, 5 in inches).
FIT_MARGIN = 0.85
BLEND_SHARE = 0.1
#: Arcs whose sagitta is below this fraction of the tolerance are emitted as lines.
FLAT_ARC = 0.05
#: knot spans of a fitted tool-centre B-spline per span of the fitted pitch B-spline
OFFSET_REFINE = 2


# ---- the exact tool-centre path -----------------------------------------------------
def outward_distance(pitch: PitchCurve, distance: float) -> float:
    """Signed (left-positive) offset distance that moves the pitch curve outward by ``distance``."""
    return profile_offset_distance(pitch, -distance)


def tool_centre_curve(design: CamDesign, plan: MachiningPlan) -> NurbsCurve:
    """The tool-centre path in the cam frame: the pitch curve offset outward by tool radius −
    roller radius, traversed as the pitch curve is.  For a PH pitch curve the exact rational
    NURBS (one span per PH segment); for a B-spline pitch curve, whose offsets are not
    rational, a B-spline fitted to its exact offset (error: :func:`tool_centre_fit_error`)."""
    d = plan.centre_offset
    if d == 0.0:
        return design.pitch_nurbs
    if design.pitch.exact_offsets:
        return offset_nurbs(design.pitch.spline, outward_distance(design.pitch, d))
    return _fitted_tool_centre(design, d).to_nurbs(design.pitch.parameter_scale)


def _fitted_tool_centre(design: CamDesign, distance: float) -> Any:
    pitch = design.pitch
    return fit_offset(pitch.curve, pitch.geometry.sense * distance, refine=OFFSET_REFINE)


def tool_centre_fit_error(design: CamDesign, plan: MachiningPlan) -> float:
    """Largest distance [length] of :func:`tool_centre_curve` from the exact offset of the pitch
    curve: 0 where the offset is exact (PH pitch curve, or tool = roller), else measured on
    the fitted B-spline (dense samples, foot points on the exact offset)."""
    d = plan.centre_offset
    if d == 0.0 or design.pitch.exact_offsets:
        return 0.0
    fit = _fitted_tool_centre(design, d)
    u = np.linspace(0.0, TWO_PI, 64 * fit.n_spans, endpoint=False)
    pts = fit.evaluate(u)[0]
    return float(np.max(distance_to_offset(pts, u, design.pitch.curve, design.pitch.geometry.sense * d)))


# ---- XY contour ---------------------------------------------------------------------
@dataclass(frozen=True)
class ContourPath:
    """One loop of the XY contour and its lead arcs (cam frame = machine XY, spec units).

    Attributes:
        curve: the exact tool-centre path.
        loop: arcs/lines in cutting order, from the entry point back to it.
        lead_in, lead_out: one tangent quarter-circle arc each (same centre).
        entry_angle_deg: cam angle of the entry point (a junction in the longest dwell).
        clockwise: the loop runs clockwise (climb milling with M3).
        max_distance: measured two-sided distance of ``loop`` from ``curve``.
        tolerance: the chord tolerance it meets.
        z_levels: depth of each pass (negative).
    """

    curve: NurbsCurve
    loop: Path2D
    lead_in: Path2D
    lead_out: Path2D
    entry_angle_deg: float
    clockwise: bool
    max_distance: float
    tolerance: float
    z_levels: np.ndarray

    @property
    def n_arcs(self) -> int:
        return int(np.count_nonzero(self.loop.is_arc))

    @property
    def n_lines(self) -> int:
        return int(self.loop.n - self.n_arcs)

    def summary(self) -> dict[str, Any]:
        """Numbers for report.json (spec units, degrees)."""
        return {"moves": self.loop.n, "arcs": self.n_arcs, "lines": self.n_lines,
                "max_distance": self.max_distance, "chord_tolerance": self.tolerance,
                "entry_at_deg": self.entry_angle_deg, "clockwise": self.clockwise,
                "length": self.loop.length, "passes": int(self.z_levels.shape[0])}


def reverse_path(path: Path2D) -> Path2D:
    """The same chain traversed backwards."""
    return Path2D(path.end[::-1].copy(), path.start[::-1].copy(), path.center[::-1].copy(),
                  ~path.ccw[::-1], path.u1[::-1].copy(), path.u0[::-1].copy())


def _roll(path: Path2D, first: int) -> Path2D:
    return Path2D(*(np.roll(v, -first) for v in (path.start, path.end, path.center, path.ccw,
                                                   path.u0, path.u1)))


def straighten_flat_arcs(path: Path2D, max_sagitta: float) -> Path2D:
    """Arcs whose sagitta R(1 − cos(sweep/2)) is at most ``max_sagitta`` become lines (a near-
    straight arc's huge I/J words carry no information and amplify rounding)."""
    sag = np.where(path.is_arc, path.radius * (1 - np.cos(np.abs(path.sweep()) / 2)), np.inf)
    flat = path.is_arc & (sag <= max_sagitta)
    center = np.where(flat, np.nan + 0j, path.center)
    return Path2D(path.start, path.end, center, np.where(flat, False, path.ccw), path.u0, path.u1)


def fit_contour(curve: NurbsCurve, tolerance: float, arcs: bool = True) -> tuple[Path2D, float]:
    """Biarcs (or chords) within ``FIT_MARGIN·tolerance`` of ``curve``, checked by the
    independent dense two-sided :func:`cam_workbench.generators.curves.approx.max_distance`; returns
    (path, measured distance)."""
    fit_tol = FIT_MARGIN * tolerance
    for _ in range(8):
        if arcs:
            path = straighten_flat_arcs(fit_biarcs(curve, fit_tol), FLAT_ARC * tolerance)
        else:
            path = polyline_path(*flatten(curve, fit_tol))
        dist = max_distance(path, curve)
        if dist <= FIT_MARGIN * tolerance:
            return path, dist
        fit_tol *= 0.6
    raise SolveError(f"could not fit the tool path within {tolerance:g}")


def entry_junction(pitch: PitchCurve) -> int:
    """The junction where the contour is entered: nearest the middle of the longest dwell
    (a circular arc, the least sensitive place for the entry mark); junction 0 without dwells."""
    prog = pitch.program
    dwell = [k for k, kind in enumerate(prog.kinds) if kind == "dwell"]
    if not dwell:
        return 0
    k = max(dwell, key=lambda i: prog.spans[i])
    mid = prog.starts[k] + prog.spans[k] / 2
    d = np.abs(np.angle(np.exp(1j * (pitch.angles - mid))))
    return int(np.argmin(d))


def points_inside(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Crossing-number test of points (K,) against a closed polygon (N,) (complex)."""
    a = polygon[None, :]
    b = np.roll(polygon, -1)[None, :]
    p = points[:, None]
    straddle = (a.imag > p.imag) != (b.imag > p.imag)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_cross = a.real + (p.imag - a.imag) * (b.real - a.real) / (b.imag - a.imag)
    return (np.count_nonzero(straddle & (p.real < x_cross), axis=1) % 2) == 1


def _arc(start: complex, end: complex, centre: complex, ccw: bool) -> Path2D:
    nan = np.array([np.nan])
    return Path2D(np.array([start]), np.array([end]), np.array([centre]), np.array([ccw]), nan, nan)


def _entry_loop(design: CamDesign, plan: MachiningPlan, curve: NurbsCurve
                ) -> tuple[Path2D, float, complex, complex, complex, bool, int]:
    """``curve`` fitted (:func:`fit_contour`), run in the milling direction and started at the entry
    junction: (path, measured distance, entry point, unit tangent there in the cutting direction,
    unit normal away from the cam, ccw sense of the lead arcs, entry junction)."""
    path, dist = fit_contour(curve, plan.chord_tolerance, arcs=plan.contour == "arcs")
    curve_cw = curve.area() < 0
    clockwise = plan.milling == "climb"
    k = entry_junction(design.pitch)
    p, d = curve.evaluate_with_derivative(np.array([float(design.pitch.junction_parameters[k])]))
    entry = complex(p[0, 0], p[0, 1])
    tangent = complex(d[0, 0], d[0, 1])
    tangent /= abs(tangent)
    if clockwise != curve_cw:
        path = reverse_path(path)
        tangent = -tangent
    first = int(np.argmin(np.abs(path.start - entry)))
    path = _roll(path, first)
    outward = 1j * tangent if clockwise else -1j * tangent    # away from the cam
    ccw = bool((np.conj(-1j * outward) * tangent).real > 0)
    return path, dist, entry, tangent, outward, ccw, k


def contour_path(design: CamDesign, plan: MachiningPlan) -> ContourPath:
    """The XY contour of ``design`` for ``plan`` (see the module docstring).

    Raises:
        SpecError: ``machining.lead_radius`` — the lead arcs would cross the contour.
    """
    curve = tool_centre_curve(design, plan)
    path, dist, entry, tangent, outward, ccw, k = _entry_loop(design, plan, curve)
    r = plan.lead_radius
    centre = entry + r * outward
    start, end = centre - r * tangent, centre + r * tangent
    lead_in, lead_out = _arc(start, entry, centre, ccw), _arc(entry, end, centre, ccw)
    check_lead_arcs(curve, centre, r, entry, ccw)
    return ContourPath(curve=curve, loop=path, lead_in=lead_in, lead_out=lead_out,
                       entry_angle_deg=float(np.rad2deg(design.pitch.angles[k])), clockwise=plan.milling == "climb",
                       max_distance=dist, tolerance=plan.chord_tolerance, z_levels=plan.z_levels)


def part_curve(design: CamDesign, plan: MachiningPlan) -> NurbsCurve:
    """The part's own contour (the cam profile) that a program under cutter compensation follows:
    :func:`tool_centre_curve` of a tool of radius 0 (the pitch curve offset inward by the roller
    radius; the pitch curve itself for a knife edge)."""
    return tool_centre_curve(design, dataclasses.replace(plan, tool_radius=0.0))


@dataclass(frozen=True)
class PartContourPath:
    """The XY contour programmed on the part for the control's cutter compensation (G41/G42):
    the profile's biarcs, entered by a straight approach line (on which the control switches
    compensation on) and a tangent lead arc, left by the symmetric arc and a straight line (on
    which it switches it off).

    With the tool radius R_t in the control's table, the tool centre runs on the exact offset of
    these moves by R_t: the lead arcs' centre is that of :class:`ContourPath`'s, their programmed
    radius lead_radius + R_t, so the tool centre follows the tool-centre program's lead arcs.

    Attributes:
        curve: the part's exact contour (:func:`part_curve`).
        loop: its arcs/lines in cutting order, from the entry point back to it.
        approach, lead_in, lead_out, exit: the line from outside to the lead arc, the lead arcs,
            the line away from the lead-out arc (each one element).
        side: "left" (G41, the tool left of the direction of travel) or "right" (G42).
        tool_radius: R_t, the radius the control's table must hold.
        centre: the tool-centre contour of the same plan (its lead arcs, entry angle, direction).
        max_distance: measured two-sided distance of ``loop`` from ``curve``.
    """

    curve: NurbsCurve
    loop: Path2D
    approach: Path2D
    lead_in: Path2D
    lead_out: Path2D
    exit: Path2D
    side: str
    tool_radius: float
    centre: ContourPath
    max_distance: float

    @property
    def n_arcs(self) -> int:
        return int(np.count_nonzero(self.loop.is_arc))

    @property
    def n_lines(self) -> int:
        return int(self.loop.n - self.n_arcs)

    def summary(self) -> dict[str, Any]:
        """Numbers for report.json (spec units, degrees): those of the programmed part contour."""
        return {"moves": self.loop.n, "arcs": self.n_arcs, "lines": self.n_lines,
                "max_distance": self.max_distance, "chord_tolerance": self.centre.tolerance,
                "entry_at_deg": self.centre.entry_angle_deg, "clockwise": self.centre.clockwise,
                "length": self.loop.length, "passes": int(self.centre.z_levels.shape[0]),
                "compensation_side": self.side}


def _line(start: complex, end: complex) -> Path2D:
    nan = np.array([np.nan])
    return Path2D(np.array([start]), np.array([end]), np.array([np.nan + 0j]), np.array([False]), nan, nan)


def part_contour_path(design: CamDesign, plan: MachiningPlan) -> PartContourPath:
    """The part's contour of ``design`` for the control's cutter compensation (see
    :class:`PartContourPath`); the approach and exit lines are as long as the programmed lead arcs'
    radius lead_radius + R_t (longer than R_t, as a compensation start-up move must be).

    Raises:
        SpecError: ``machining.lead_radius`` — the lead arcs would cross the contour.
    """
    centre_path = contour_path(design, plan)
    curve = part_curve(design, plan)
    path, dist, entry, tangent, outward, ccw, _ = _entry_loop(design, plan, curve)
    rho = plan.lead_radius + plan.tool_radius
    centre = entry + rho * outward
    start, end = centre - rho * tangent, centre + rho * tangent
    check_lead_arcs(curve, centre, rho, entry, ccw)
    turn = 1j if ccw else -1j                       # direction of motion on the arc = turn · radius vector
    into = turn * (start - centre) / rho
    out_of = turn * (end - centre) / rho
    side = "left" if (np.conj(tangent) * outward).imag > 0 else "right"
    return PartContourPath(curve=curve, loop=path, approach=_line(start - rho * into, start),
                           lead_in=_arc(start, entry, centre, ccw), lead_out=_arc(entry, end, centre, ccw),
                           exit=_line(end, end + rho * out_of), side=side, tool_radius=plan.tool_radius,
                           centre=centre_path, max_distance=dist)


def check_lead_arcs(curve: NurbsCurve, centre: complex, r: float, entry: complex, ccw: bool) -> None:
    """The lead arcs (quarter circles of radius ``r`` about ``centre`` on both sides of the
    entry point) must stay outside the closed tool-centre path, else they cut into the cam.

    Raises:
        SpecError: ``machining.lead_radius``.
    """
    a_entry = np.angle(entry - centre)
    sgn = 1.0 if ccw else -1.0
    phi = np.deg2rad(np.linspace(2.0, 90.0, 45))
    pts = centre + r * np.exp(1j * np.concatenate([a_entry - sgn * phi, a_entry + sgn * phi]))
    _, poly = curve.sample(64)
    inside = points_inside(pts, poly[:-1, 0] + 1j * poly[:-1, 1])
    if inside.any():
        raise SpecError("machining.lead_radius",
                        f"the lead-in/lead-out arcs of radius {r:g} cut into the cam contour; use a smaller "
                        "lead radius")


# ---- XC rotary ------------------------------------------------------------------------
class OffsetLineSolver:
    """Where the line x = ``line`` of the fixed frame meets the offset T = r + d·n of a PH
    spline at cam angle θ: Re(e^{iδθ}·T(ξ)) = line — paper Eq. 13 on the offset curve.

    T' = r'·(1 − d·κ) (n = i·w²/|w|² the unit left normal, κ = 2 Im(w̄w')/|w|⁴ the signed
    curvature), so Newton's step (paper Eq. 14) stays closed-form.  Segments are looked
    up by the cam angles at which the offset junction points cross the line.

    Args:
        spline: the PH pitch spline.
        distance: signed (left-positive) offset distance d.
        line: the line's x in the fixed frame (e: the follower's line; 0: through the axis).
        sense: +1 ccw, −1 cw.

    Raises:
        GeometryError: the line does not meet the offset curve exactly once per turn.
    """

    def __init__(self, spline: PHSpline, distance: float, line: float, sense: int):
        self.spline = spline
        self.d = float(distance)
        self.c = float(line)
        self.sense = int(sense)
        self._pc = power_coeffs(spline.ctrl)
        self._wc = power_coeffs(spline.w)
        self._dwc = self._wc[:, 1:] * np.arange(1, 3)
        tj = self._offset_points(np.arange(spline.M), np.zeros(spline.M))
        rad = np.abs(tj)
        if np.any(rad <= abs(self.c)):
            k = int(np.argmin(rad))
            raise GeometryError("rotary", f"the tool's line x = {self.c:g} misses the tool-centre path "
                                          f"near PH junction {k} (radius {rad[k]:.4g})")
        ang = self.sense * (np.arccos(self.c / rad) - np.angle(tj))
        self.theta0 = float(ang[0])
        rel = np.mod(ang - ang[0], TWO_PI)
        if np.any(np.diff(rel) <= 0):
            k = int(np.argmax(np.diff(rel) <= 0)) + 1
            raise GeometryError("rotary", f"the tool's line meets the tool-centre path more than once "
                                          f"near PH junction {k}",
                                float(np.rad2deg(ang[k]) % 360.0))
        self.angles = np.append(rel, TWO_PI)

    def _offset_points(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        r = horner(self._pc[seg], xi)
        w = horner(self._wc[seg], xi)
        return r + self.d * 1j * w * w / (w * w.conjugate()).real

    def solve(self, theta: np.ndarray, tol: float = 1e-14, max_iter: int = 40
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(segment, ξ, T in the cam frame, position along the line) at cam angles θ [rad]."""
        theta = np.asarray(theta, dtype=float)
        rot = np.exp(1j * self.sense * theta)
        t = np.mod(theta - self.theta0, TWO_PI)
        m = self.spline.M
        seg = np.clip(np.searchsorted(self.angles, t, side="right") - 1, 0, m - 1)
        xi = (t - self.angles[seg]) / (self.angles[seg + 1] - self.angles[seg])
        g0 = (rot * self._offset_points(seg, np.zeros_like(xi))).real - self.c
        g1 = (rot * self._offset_points(seg, np.ones_like(xi))).real - self.c
        scale = 1e-12 * (np.abs(self._pc[seg, 0]) + abs(self.d) + abs(self.c))
        bad = (g0 * g1 > 0) & (np.abs(g0) > scale) & (np.abs(g1) > scale)
        if bad.any():
            k = int(np.argmax(bad))
            raise SolveError(f"the tool's line does not cross offset segment {int(seg[k])} at cam angle "
                             f"{np.rad2deg(np.mod(theta[k], TWO_PI)):.4f}° (root not bracketed)")
        for _attempt in range(4):
            xi = self._newton(seg, xi, rot, tol, max_iter)
            low, high = xi < -1e-9, xi > 1 + 1e-9
            if not (low.any() or high.any()):
                break
            seg = np.where(low, (seg - 1) % m, np.where(high, (seg + 1) % m, seg))
            xi = np.where(low, xi + 1.0, np.where(high, xi - 1.0, xi))
        else:
            raise SolveError("the tool's line does not meet the tool-centre path in any segment")
        xi = np.clip(xi, 0.0, 1.0)
        pts = self._offset_points(seg, xi)
        return seg, xi, pts, (rot * pts).imag

    def _newton(self, seg: np.ndarray, xi: np.ndarray, rot: np.ndarray, tol: float, max_iter: int
                ) -> np.ndarray:
        pc, wc, dwc = self._pc[seg], self._wc[seg], self._dwc[seg]
        active = np.ones(xi.shape, dtype=bool)
        for _ in range(max_iter):
            r = horner(pc, xi)
            w = horner(wc, xi)
            dw = horner(dwc, xi)
            sig = (w * w.conjugate()).real
            w2 = w * w
            kappa = 2.0 * (w.conjugate() * dw).imag / sig**2
            g = (rot * (r + self.d * 1j * w2 / sig)).real - self.c
            dg = (rot * w2 * (1.0 - self.d * kappa)).real
            step = np.where(active, g / dg, 0.0)
            if not np.all(np.isfinite(step)):
                raise SolveError("Newton step on the tool-centre path is singular")
            xi = xi - np.clip(step, -0.5, 0.5)
            floor = 16 * np.finfo(float).eps * (np.abs(r) + abs(self.d) + abs(self.c))
            active = (np.abs(step) > tol) & (np.abs(g) > floor)
            if not active.any():
                return xi
        raise SolveError("Newton iteration on the tool-centre path did not converge")


def _fitted_line_positions(design: CamDesign, distance: float, line: float, theta: np.ndarray) -> np.ndarray:
    """B-spline pitch curve: position along the tool's line x = ``line`` where it meets the
    fitted tool-centre B-spline at cam angles θ (Eq. 13 on that curve)."""
    pitch = design.pitch
    machine_line = TranslatingFollower(line, 0.0, pitch.follower.sense, 0.0)   # the tool's line x = line
    centre = BSplinePitchCurve(_fitted_tool_centre(design, distance), pitch.program, machine_line)
    ang = np.append(centre.solver_angles, centre.solver_angles[0] + TWO_PI)
    if np.any(np.diff(ang) <= 0) or np.any(np.abs(centre.segments.ctrl[:, 0]) <= abs(line)):
        k = int(np.argmax(np.diff(ang) <= 0))
        raise GeometryError("rotary", f"the tool's line x = {line:g} does not meet the tool-centre path "
                                      "once per turn", float(np.rad2deg(ang[k]) % 360.0))
    return centre.solver().solve(theta).Y


@dataclass(frozen=True)
class RotaryPath:
    """The XC program's blocks: block k runs from point k to point k+1 in time durations[k].

    Attributes:
        theta: (N+1,) cam angle at the block ends [rad], θ_k = kωΔt, the last one 2π.
        c_deg: (N+1,) C axis [deg] = δ·θ (continuous, sign by the cam's direction).
        x: (N+1,) machine X: tool-centre distance along its line from the C-axis foot.
        y: machine Y (fixed) = −line offset.
        durations: (N,) block times [s]: Δt, the last one shorter when 2π/(ωΔt) is not whole.
        line_offset: x of the tool's line in the fixed frame (e or 0).
        curve: exact tool-centre path (cam frame).
        max_deviation: measured two-sided distance of the blocks (X and C interpolated
            linearly, as the controller does) from ``curve``.
        tolerance: the chord tolerance.
        from_commands: X is s₀ + s_actual of the paper's commands (tool = roller on the
            follower's line).
        commands: the interpolator's commands of the revolution.
        z_levels: depth of each pass (negative).
    """

    theta: np.ndarray
    c_deg: np.ndarray
    x: np.ndarray
    y: float
    durations: np.ndarray
    line_offset: float
    curve: NurbsCurve
    max_deviation: float
    tolerance: float
    from_commands: bool
    commands: Commands
    z_levels: np.ndarray

    @property
    def n_blocks(self) -> int:
        return int(self.durations.shape[0])

    def summary(self) -> dict[str, Any]:
        """Numbers for report.json (spec units, degrees, seconds)."""
        return {"blocks": self.n_blocks, "block_time": float(self.durations[0]),
                "step_deg": self.commands.step_deg, "max_deviation": self.max_deviation,
                "chord_tolerance": self.tolerance, "line_offset": self.line_offset, "machine_y": self.y,
                "x_from_commands": self.from_commands, "x_min": float(self.x.min()),
                "x_max": float(self.x.max()), "passes": int(self.z_levels.shape[0])}

    def cam_frame_points(self, per_block: int = 8) -> np.ndarray:
        """The blocks seen in the cam frame, ``per_block`` points each (X and C linear in time)."""
        return blocks_in_cam_frame(self.x, self.c_deg, self.line_offset, per_block)


def blocks_in_cam_frame(x: np.ndarray, c_deg: np.ndarray, line_offset: float, per_block: int = 8
                        ) -> np.ndarray:
    """Tool-centre positions in the cam frame along X–C blocks (X, C linear within a block):
    fixed-frame point (line_offset, X) turned back by C."""
    tau = np.arange(per_block) / per_block
    xs = x[:-1, None] + np.diff(x)[:, None] * tau
    cs = np.deg2rad(c_deg[:-1, None] + np.diff(c_deg)[:, None] * tau)
    pts = np.exp(-1j * cs) * (line_offset + 1j * xs)
    end = np.exp(-1j * np.deg2rad(c_deg[-1])) * (line_offset + 1j * x[-1])
    return np.append(pts.ravel(), end)


def rotary_path(design: CamDesign, plan: MachiningPlan, commands: Commands | None = None) -> RotaryPath:
    """The XC blocks of one revolution (see the module docstring); ``commands`` of the same
    speed and period are reused if given.

    Raises:
        SpecError: ``machining.rotary_speed_rpm`` — the blocks deviate from the exact path by
            more than the chord tolerance allows; the message gives a C-axis speed and a
            sample period that pass (each checked by making its blocks).
        GeometryError: the tool's line does not meet the tool-centre path once per turn.
    """
    cmds = commands
    if cmds is None or cmds.sample_period != plan.sample_period or cmds.speed_rpm != plan.rotary_speed_rpm:
        cmds = RotationalInterpolator(design.pitch).commands(plan.rotary_speed_rpm, plan.sample_period)
    curve = tool_centre_curve(design, plan)
    theta, x, line, from_commands, dev = _xc_blocks(design, plan, cmds, curve)
    if dev > FIT_MARGIN * plan.chord_tolerance:
        raise _coarse_blocks_error(design, plan, curve, cmds.step_deg, dev)
    geo = design.pitch.follower
    c_deg = geo.sense * np.rad2deg(theta)
    return RotaryPath(theta=theta, c_deg=c_deg, x=x, y=-line, durations=np.diff(theta) / cmds.omega,
                      line_offset=line, curve=curve, max_deviation=dev, tolerance=plan.chord_tolerance,
                      from_commands=from_commands, commands=cmds, z_levels=plan.z_levels)


def _xc_blocks(design: CamDesign, plan: MachiningPlan, cmds: Commands, curve: NurbsCurve
               ) -> tuple[np.ndarray, np.ndarray, float, bool, float]:
    """(block-end cam angles θ [rad] with 2π appended, machine X there, the tool line's offset,
    whether X comes straight from the commands, the blocks' measured distance from ``curve``)."""
    pitch = design.pitch
    geo = pitch.follower
    line = geo.offset if plan.rotary_line == "follower" else 0.0
    theta = np.append(cmds.theta, TWO_PI)
    # the tool centre is the roller centre on the follower's own line: X straight from the commands
    from_commands = (plan.rotary_line == "follower" and plan.centre_offset == 0.0
                     and geo.design_curve == "pitch")
    if from_commands:
        y = (np.exp(1j * geo.sense * cmds.theta) * cmds.point).imag      # s₀ + s_actual (Eq. 15)
        x = np.append(y, y[0])
    elif pitch.exact_offsets:
        solver = OffsetLineSolver(pitch.spline, outward_distance(pitch, plan.centre_offset), line, geo.sense)
        x = solver.solve(theta)[3]
    else:
        x = _fitted_line_positions(design, plan.centre_offset, line, theta)
    pts = blocks_in_cam_frame(x, geo.sense * np.rad2deg(theta), line)
    return theta, x, line, from_commands, polyline_curve_distance(pts, curve)


def _coarse_blocks_error(design: CamDesign, plan: MachiningPlan, curve: NurbsCurve, step_deg: float,
                         dev: float) -> SpecError:
    """The refusal of XC blocks too coarse for the chord tolerance, naming the C-axis speed (what a
    user changes: the grinder turns the cam slower while it cuts) with a speed that passes, and
    the sample period that would pass at this speed — both found and checked here."""
    limit = FIT_MARGIN * plan.chord_tolerance
    rpm, period = plan.rotary_speed_rpm, plan.sample_period

    def deviation(rpm_: float, period_: float) -> float:
        cmds = RotationalInterpolator(design.pitch).commands(rpm_, period_)
        return _xc_blocks(design, plan, cmds, curve)[4]

    ok_rpm = _largest_passing(rpm, dev, limit, lambda r: deviation(r, period))
    ok_period = _largest_passing(period, dev, limit, lambda t: deviation(rpm, t))
    given = design.spec.machining.rotary_speed_rpm is not None
    rule = (f"at {rpm:g} rpm{'' if given else ' (cam.speed_rpm; machining.rotary_speed_rpm is not given)'} and "
            f"machining.sample_period {period:g} s the XC blocks of {step_deg:.4g}° deviate {fmt_apart(dev, limit, 3)} "
            f"from the exact tool path, more than {FIT_MARGIN:g} × machining.chord_tolerance = "
            f"{fmt_apart(limit, dev, 3)}")
    fixes = ([f"machining.rotary_speed_rpm = {ok_rpm:g} (the C axis turning slower while it cuts; cam.speed_rpm "
              "stays the design speed)"] if ok_rpm is not None else []) + (
             [f"machining.sample_period = {ok_period:g}"] if ok_period is not None else [])
    if not fixes:
        return SpecError("machining.chord_tolerance",
                         f"{rule}, and no C-axis speed down to {rpm / SLOWEST_FRACTION:g} rpm passes: a larger "
                         "machining.chord_tolerance")
    return SpecError("machining.rotary_speed_rpm",
                     f"{rule}; {' or '.join(fixes)} passes" if len(fixes) == 1 else
                     f"{rule}; {' or '.join(fixes)}: either passes")


#: How far below the given speed (or sample period) a passing one is looked for: a factor of …
SLOWEST_FRACTION = 1000.0


def _largest_passing(value: float, dev: float, limit: float, deviation: Callable[[float], float]
                     ) -> float | None:
    """The largest value at 3 significant digits below ``value`` (a C-axis speed or a sample
    period: the block angle is proportional to either) whose blocks' deviation is ≤ ``limit``,
    checked by ``deviation(value)``; None when none down to ``value / SLOWEST_FRACTION`` passes.

    A chord's distance from a smooth curve grows with the square of its angle, so each guess
    scales the last failing value by √(limit/deviation); then the gap to the last failing value
    is bisected on 3-digit values (the deviation is not strictly monotonic in the angle:
    the last block of a turn is shorter)."""
    hi, lo, d = value, None, dev
    guess = value
    while lo is None:
        guess = _floor3(min(guess * 0.98 * np.sqrt(limit / d), guess * 0.98))
        if guess < value / SLOWEST_FRACTION:
            return None
        d = deviation(guess)
        if d <= limit:
            lo = guess
        else:
            hi = guess
    while True:
        mid = _floor3(0.5 * (lo + hi))
        if mid <= lo or mid >= hi:
            return lo
        if deviation(mid) <= limit:
            lo = mid
        else:
            hi = mid


def _floor3(v: float) -> float:
    """``v`` > 0 rounded down to 3 significant digits."""
    e = int(np.floor(np.log10(v))) - 2
    return float(f"{int(np.floor(v / 10.0**e * (1 + 1e-12)))}e{e}")

"""DXF drawing of a SPATIAL indexer (ezdxf) — the barrel (cylindrical-cam) indexer or the globoidal
(roller-gear) indexer of :mod:`cam_workbench.generators.bodies.indexing.spatial` — 1:1 in mm.

Frames and signs are the generator's: the cam axis is z through O, the turret axis the line through
P = (C, 0, 0) along +y; everything is drawn at input angle θ = 0, where the cam frame is the fixed
frame.  Every view's drawing axes (X, Y) are named below as fixed-frame directions; X × Y points at
the viewer (no view is mirrored).

Barrel indexer
    * **side view** at the origin, X = z, Y = y (the viewer on −x): the root cylinder (ρ ≤ R_root,
      length W, layer ``OUTLINE``), the rib's extent (ρ ≤ R_top over the axial range its flank
      traces reach, ``RIB``), the rollers near the cam at θ = 0 (those whose axis point lies within
      W/2 + r_max axially and R_top + r_max of the cam axis, r_max the roller's largest radius: the
      outline z_a ± r(t) for t ∈ [t0, t1] (see *Rollers* below), ``ROLLERS``), the cam axis (Y = 0)
      and the turret axis (X = 0);
    * **end view** (right of it), X = x, Y = y (the viewer on +z), centred on the cam axis at
      (``views["end"]``): the rib's top and root circles (``OUTLINE``, ``ROOT``; circles, exact),
      the same rollers (x_a ± r(t) for t ∈ [t0, t1], once for rollers that coincide in this view), the
      turret axis (X = C) and the centre distance C
      (a linear DIMENSION);
    * **developed views** (below), one at the rib's top radius R_top and one at its root radius
      R_root: X = x0 + ρ·(φ − φ_m − 2πk), Y = y0 + z with (x0, y0) = ``views["developed_top"]``
      (``views["developed_root"]``), φ the contact point's cam-frame polar angle, φ_m
      (``info.phi_mid``) the polar angle of roller 0's side −1 contact at mid-index (τ = θ_s + β/2,
      the middle of the roller) and k the turn that puts X − x0 in [−πρ, πρ]: the cylinder unrolled
      and seen from outside, the index in the middle, the seam at the window's edges.  The
      window's outline (z = ±W/2 and the seam lines) is drawn exact (``OUTLINE``); each flank's
      trace — the curve where the flank meets the cylinder ρ — is drawn on ``TRACE_TOP_P`` /
      ``TRACE_TOP_M`` / ``TRACE_ROOT_P`` / ``TRACE_ROOT_M`` (side +1 / side −1 at R_top / R_root).

Globoidal indexer
    * **contour view** at the origin: the section through the cam axis in the turret's plane
      y = 0, X = z, Y = x (the viewer on +y): the root and tip globoids' profiles (ARCs, exact: radii
      R_root, R_tip about (0, ±C), between z = ±W/2; ``OUTLINE`` and ``TIP``), the cam's end faces,
      the turret's hub circle of radius t0 about P = (0, C) (``TURRET``), every roller's section at
      θ = 0 (the outline of its axis P + t·u(α_j), t ∈ [t0, t1], ± r(t): ``ROLLERS``), the cam axis
      and the turret axis' centre mark at P, the centre distance C (a DIMENSION from O to P);
    * **end view** along the cam axis (right of it, X = x, Y = y, viewer on +z, centred at
      ``views["end"]``): the globoids' circles at the end faces (``OUTLINE`` root, ``TIP`` tip)
      and at the waist (dashed: ``HIDDEN``), the turret axis (X = C) and C dimensioned.
    * The flank traces on a pitch globoid are NOT drawn (the indexer defines no pitch globoid;
      the flanks are the surfaces of :mod:`...spatial_surfaces`, whose fit error is quoted).

Rollers.  Every view sees a roller side-on (its axis in the drawing's plane: +y in the barrel's
views, u(α_j) in the globoid's section), so its outline is exact and straight-sided: the closed
LWPOLYLINE (axis at t0 − r(t0)·e, t1 − r(t1)·e, t1 + r(t1)·e, t0 + r(t0)·e), e the drawing's unit
vector square to the axis (+X in the barrel's views) and r(t) = r_r + (t − t_m)·tan γ the roller's
radius (``ix.radius_at``; γ = ``roller_cone_angle``): a rectangle of half-width r_r for a cylinder
(γ = 0), a trapezoid for a conical roller.  The views' extents use the largest radius r_max
(``ix.largest_radius``; r_r for a cylinder).  With γ ≠ 0 the title block adds a ROLLER CONE ANGLE
row (r_r is then the radius at t_m = (t0 + t1)/2).

The flank traces (barrel).  A trace point of side s at radius ρ is the exact envelope point
``contact_lines(ix, 0, τ, t, s)`` (the generator's, in the cam frame) on the cylinder ρ: per τ, t is
the largest root of ρ(τ, t) = ρ, bracketed on a 0.25 mm grid of t and polished by Newton (central
differences in t) to 1e-9 mm.  Since the contact point's height above the plane y = 0 is t, a trace
at radius ρ has t ≤ ρ: the trace at the root radius (R_root < t0, the rollers' ends clear the root)
lies on the flank CONTINUED below the rollers' ends — the envelope of the roller's cylinder
extended (what a cutter of the roller's radius following the roller's axis down to the root
leaves); the rollers never touch it.  The traces are not taken from the fitted surfaces, whose
domain stops at t0; the top trace lies on both.  A trace is searched over the τ range of its
flank's surface (:func:`...spatial_surfaces.flank_tau_range`) widened by 5° at each end and runs
where the point exists with ∂ρ/∂t ≥ :data:`MIN_SLOPE` (the continued contact line meets the
cylinder at a workable angle; where it grazes it the continued flank folds and the trace stops), the
envelope is regular there (margin > 0) and |z| ≤ W/2; its ends on the end faces are solved
(bisection to 1e-12 rad), its other ends (a fold, the search range) are the last point of a 0.25° τ
grid inside (the default design: every end on an end face but one root trace's, at a fold).  It is cut at the law's ends (τ = θ_s + 2πm, θ_s + β + 2πm: the trace's
third derivative jumps there) and at the developed view's seam lines (solved likewise), and each
piece is a not-a-knot cubic SPLINE in the parameter τ [rad] interpolating exact points on uniform
τ nodes, at most 1° apart, doubled until the piece's MEASURED error |spline(τ) − trace(τ)| at
:data:`CHECKS` points per span (exact points again) is within :data:`TRACE_TOLERANCE`.  That
parametric error bounds the distance from the exact trace; its largest value is ``info.trace_error``
and the title block quotes it rounded up to 2 significant digits (``info.quoted_trace_error``),
beside the flank surfaces' measured fit error (``info.quoted_fit_error``).  Circles, arcs and lines
are exact.

==================  ==========================================================================
layer               content
==================  ==========================================================================
OUTLINE             the cam's outline (root cylinder / root globoid, end faces, the developed
                    windows)
RIB                 (barrel) the rib's extent in the side view
ROOT                (barrel) the root circle in the end view
TIP                 (globoid) the tip globoid's profile and circles
HIDDEN              (globoid) the globoids' waist circles in the end view
TRACE_*             (barrel) the flank traces in the developed views (SPLINE)
ROLLERS             the rollers at θ = 0
TURRET              (globoid) the turret's hub circle
CENTERLINES         the cam and turret axes, centre marks
DIMENSIONS          the centre distance C
NOTES               the views' names
TITLE               the title block
==================  ==========================================================================
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from cam_workbench.generators import __version__
from cam_workbench.generators.bodies.indexing.spatial import (TWO_PI, BarrelIndexer, GloboidalIndexer,
                                                             SpatialDesign, contact_lines, roller_alpha,
                                                             turret_angle)
from cam_workbench.generators.bodies.indexing.spatial_surfaces import FlankSurfaces
from cam_workbench.generators.curves.nurbs import NurbsCurve

from .atomic import atomic_path
from .dxf import DIMSTYLE, LAYERS, add_closed_outline, add_nurbs_spline, text_width
from .dxf_indexer import add_cross, dim_values, new_document, add_text, title_block, round_up

Array = np.ndarray

#: the traces' target error [mm] (measured, parametric)
TRACE_TOLERANCE = 1e-4
#: check points per spline span where a trace's error is measured (fractions k/CHECKS, k = 1 … CHECKS − 1)
CHECKS = 16
#: the smallest ∂ρ/∂t at a trace point (below it the continued flank grazes the cylinder)
MIN_SLOPE = 0.2
#: the τ grid [rad] where traces are searched, the initial node spacing, the t bracket grid [mm]
_GRID_STEP = math.radians(0.25)
_NODE_STEP = math.radians(1.0)
_WIDEN = math.radians(5.0)
_T_STEP = 0.25
_T_MIN = 0.25
_MAX_NODES = 8193
_NEWTON = 10
_BLOCK = 512
DEFAULT_TITLE = {"BarrelIndexer": "BARREL INDEXER CAM", "GloboidalIndexer": "GLOBOIDAL INDEXER CAM"}


def spatial_layers() -> dict[str, tuple[int, str, int]]:
    """Layer → (ACI colour, linetype, lineweight [1/100 mm]) of a spatial indexer's drawing."""
    out: dict[str, tuple[int, str, int]] = {
        "OUTLINE": LAYERS["OUTLINE"], "RIB": (7, "Continuous", 35), "ROOT": (8, "Continuous", 25),
        "TIP": (2, "Continuous", 35), "HIDDEN": (8, "DASHED", 25),
    }
    for where in ("TOP", "ROOT"):
        out[f"TRACE_{where}_P"] = (5, "Continuous", 50)
        out[f"TRACE_{where}_M"] = (3, "Continuous", 50)
    out["ROLLERS"] = (6, "Continuous", 25)
    out["TURRET"] = (5, "PHANTOM", 18)
    for name in ("CENTERLINES", "DIMENSIONS"):
        out[name] = LAYERS[name]
    out["NOTES"] = (7, "Continuous", 18)
    out["TITLE"] = LAYERS["TITLE"]
    return out


# ---------------------------------------------------------------------------------------------
# the barrel's flank traces

@dataclass(frozen=True)
class DrawnTrace:
    """One SPLINE of a flank trace: ``layer``, flank ``side`` (±1), cylinder ``radius`` [mm]; the
    parameter τ [rad] over ``tau_range`` (the knots'); ``turn`` k of the developed window;
    ``nodes`` interpolated; ``error`` [mm] its measured largest |spline(τ) − trace(τ)|; ``t_range``
    [mm] the roller-axis parameters of its points; ``min_margin`` the regularity margin's least
    value at its nodes; ``ends`` how each end was found ("end face", "seam", "law", "fold", "range")."""

    layer: str
    side: int
    radius: float
    tau_range: tuple[float, float]
    turn: int
    nodes: int
    error: float
    t_range: tuple[float, float]
    min_margin: float
    ends: tuple[str, str]
    curve: NurbsCurve = field(repr=False)


@dataclass(frozen=True)
class _Points:
    t: Array
    points: Array
    margin: Array
    ok: Array


def _contact(ix: BarrelIndexer, side: int, tau: Array, t: Array) -> tuple[Array, Array]:
    """Cam-frame contact points (B, 3) and margins (B,) at the pairs (τ_i, t_i)."""
    cl = contact_lines(ix, 0, tau, t[:, None], side)      # t (B, 1) broadcasts against θ (B,)
    return cl.points[:, 0, :], cl.margin[:, 0]


def _rho(p: Array) -> Array:
    return np.hypot(p[..., 0], p[..., 1])


def trace_points(ix: BarrelIndexer, side: int, radius: float, tau: Array, guess: Array | None = None) -> _Points:
    """The exact envelope points of side ``side`` on the cylinder ρ = ``radius`` at ``tau`` (module
    docs): t is the largest root of ρ(τ, t) = radius in (0, t1], bracketed on a grid (or from
    ``guess``), polished by Newton; ``ok`` where found with ∂ρ/∂t ≥ :data:`MIN_SLOPE` and a
    regular envelope there (margin > 0)."""
    tau = np.atleast_1d(np.asarray(tau, dtype=float))
    t1 = float(ix.roller_end)
    if guess is None:
        tg = np.arange(_T_MIN, t1 + 0.5 * _T_STEP, _T_STEP)
        t = np.full(tau.size, np.nan)
        for b in range(0, tau.size, _BLOCK):
            f = _rho(contact_lines(ix, 0, tau[b:b + _BLOCK], tg, side).points) - radius      # (B, G)
            up = (f[:, :-1] < 0) & (f[:, 1:] >= 0)
            has = up.any(axis=1)
            k = up.shape[1] - 1 - np.argmax(up[:, ::-1], axis=1)                             # the largest-t crossing
            r = np.arange(k.size)
            f0, f1 = f[r, k], f[r, k + 1]
            t[b:b + _BLOCK] = np.where(has, tg[k] + _T_STEP * f0 / (f0 - f1), np.nan)
    else:
        t = np.asarray(guess, dtype=float).copy()
    found = np.isfinite(t)
    t = np.where(found, t, 0.5 * t1)
    h = 1e-4
    n = tau.size
    tau3 = np.concatenate([tau, tau, tau])
    for it in range(_NEWTON + 1):
        p3, m3 = _contact(ix, side, tau3, np.concatenate([t, t - h, t + h]))
        r3 = _rho(p3)
        res, slope = r3[:n] - radius, (r3[2 * n:] - r3[n:2 * n]) / (2 * h)
        if it == _NEWTON or not np.any(np.abs(res[found]) > 1e-12):
            break
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(slope > 0, res / slope, 0.0)
        t = np.clip(t - np.nan_to_num(step), _T_MIN, t1)
    p, margin = p3[:n], m3[:n]
    ok = found & (np.abs(res) < 1e-9) & (slope >= MIN_SLOPE) & (margin > 0)
    return _Points(t, p, margin, ok)


def _bisect(fun: Any, a: Array, b: Array, iters: int = 60) -> Array:
    """Roots of ``fun`` (vectorised) in the brackets [a, b] (fun(a), fun(b) of opposite signs)."""
    a, b = np.asarray(a, dtype=float).copy(), np.asarray(b, dtype=float).copy()
    fa = fun(a)
    for _ in range(iters):
        m = 0.5 * (a + b)
        fm = fun(m)
        left = np.sign(fm) == np.sign(fa)
        a, fa = np.where(left, m, a), np.where(left, fm, fa)
        b = np.where(left, b, m)
        if np.max(b - a) < 1e-12:
            break
    return 0.5 * (a + b)


def _law_breaks(ix: BarrelIndexer, lo: float, hi: float) -> Array:
    ts, beta = float(ix.index_start), float(ix.index_angle)
    m = np.arange(math.floor((lo - ts) / TWO_PI) - 1, math.ceil((hi - ts) / TWO_PI) + 2)
    b = np.sort(np.concatenate([ts + TWO_PI * m, ts + beta + TWO_PI * m]))
    return b[(b > lo + 1e-9) & (b < hi - 1e-9)]


def phi_mid(ix: BarrelIndexer) -> float:
    """φ_m [rad]: the cam-frame polar angle of roller 0's side −1 contact at mid-index, at the
    middle of the roller (the developed views' centre)."""
    tau = np.array([float(ix.index_start) + 0.5 * float(ix.index_angle)])
    p = contact_lines(ix, 0, tau, np.array([0.5 * (float(ix.roller_start) + float(ix.roller_end))]), -1).points
    return float(np.arctan2(p[0, 0, 1], p[0, 0, 0]))


def flank_traces(design: SpatialDesign, surfaces: FlankSurfaces, radius: float, phi_m: float,
                 tolerance: float = TRACE_TOLERANCE) -> list[DrawnTrace]:
    """The flank traces of both sides on the cylinder ρ = ``radius`` as cubic splines in the
    developed plane (X = ρ·(φ − φ_m − 2πk), Y = z; module docs), each with its measured error."""
    ix = design.indexer
    half = 0.5 * float(ix.cam_width)
    where = "TOP" if radius >= float(ix.outer_radius) else "ROOT"
    out = []
    for side in (1, -1):
        lo, hi = surfaces.flank(side).tau_range
        lo, hi = lo - _WIDEN, hi + _WIDEN
        grid = np.linspace(lo, hi, int(math.ceil((hi - lo) / _GRID_STEP)) + 1)
        pts = trace_points(ix, side, radius, grid)
        inside = np.abs(pts.points[:, 2]) <= half
        valid = pts.ok & inside
        edges = np.diff(np.concatenate([[0], valid.astype(np.int8), [0]]))
        for i0, i1 in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1):
            if i1 - i0 < 2:
                continue
            t_of = _interp_factory(grid[i0:i1 + 1], pts.t[i0:i1 + 1])

            def z_gap(tau: Array, _s: int = side, _t=t_of) -> Array:
                return half - np.abs(trace_points(ix, _s, radius, tau, _t(tau)).points[:, 2])

            a, a_kind = float(grid[i0]), ("range" if i0 == 0 else "fold")
            if i0 > 0 and pts.ok[i0 - 1] and not inside[i0 - 1]:
                a, a_kind = float(_bisect(z_gap, np.array([grid[i0 - 1]]), np.array([grid[i0]]))[0]), "end face"
            b, b_kind = float(grid[i1]), ("range" if i1 == grid.size - 1 else "fold")
            if i1 + 1 < grid.size and pts.ok[i1 + 1] and not inside[i1 + 1]:
                b, b_kind = float(_bisect(z_gap, np.array([grid[i1]]), np.array([grid[i1 + 1]]))[0]), "end face"
            # the run's unwrapped φ (a continuous reference) and its seams
            g_tau = np.concatenate([[a], grid[i0:i1 + 1], [b]])
            g_t = np.concatenate([[t_of(np.array([a]))[0]], pts.t[i0:i1 + 1], [t_of(np.array([b]))[0]]])
            g_p = trace_points(ix, side, radius, g_tau, g_t).points
            g_phi = np.unwrap(np.arctan2(g_p[:, 1], g_p[:, 0]))
            t_of = _interp_factory(g_tau, g_t)

            def phi_of(tau: Array, _s: int = side, _t=t_of, _gt=g_tau, _gp=g_phi) -> Array:
                p = trace_points(ix, _s, radius, tau, _t(tau)).points
                raw = np.arctan2(p[:, 1], p[:, 0])
                ref = np.interp(tau, _gt, _gp)
                return raw + TWO_PI * np.round((ref - raw) / TWO_PI)

            k_lo = math.ceil((min(g_phi[0], g_phi[-1]) - phi_m - math.pi) / TWO_PI)
            k_hi = math.floor((max(g_phi[0], g_phi[-1]) - phi_m - math.pi) / TWO_PI)
            cuts = [(x, "law") for x in _law_breaks(ix, a, b)]
            for k in range(k_lo, k_hi + 1):
                seam = phi_m + math.pi + TWO_PI * k
                s = np.sign(g_phi - seam)
                j = np.flatnonzero(s[:-1] * s[1:] < 0)
                if j.size:
                    root = _bisect(lambda x, _sm=seam: phi_of(x) - _sm, g_tau[j], g_tau[j + 1])
                    cuts.extend((float(x), "seam") for x in root)
            cuts = sorted(c for c in cuts if a + 1e-9 < c[0] < b - 1e-9)
            stops = [(a, a_kind)] + cuts + [(b, b_kind)]
            for (u0, k0), (u1, k1) in zip(stops[:-1], stops[1:]):
                if u1 - u0 < 1e-9:
                    continue
                mid = phi_of(np.array([0.5 * (u0 + u1)]))[0]
                turn = int(math.floor((mid - phi_m + math.pi) / TWO_PI))
                out.append(_fit_piece(ix, side, radius, where, u0, u1, (k0, k1), turn, phi_m, t_of, phi_of,
                                      tolerance))
    return out


def _interp_factory(x: Array, y: Array) -> Any:
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    order = np.argsort(x)
    x, y = x[order], y[order]
    return lambda q: np.interp(np.asarray(q, dtype=float), x, y)


def _fit_piece(ix: BarrelIndexer, side: int, radius: float, where: str, a: float, b: float, ends: tuple[str, str],
               turn: int, phi_m: float, t_of: Any, phi_of: Any, tolerance: float) -> DrawnTrace:
    """The not-a-knot cubic through exact trace points on uniform τ nodes over [a, b], nodes
    doubled until its error measured at :data:`CHECKS` points per span is within ``tolerance``."""
    from scipy.interpolate import make_interp_spline  # deferred: scipy.interpolate, the drawn traces' cubic fits

    shift = phi_m + TWO_PI * turn

    def developed(tau: Array) -> tuple[Array, Array, Array]:
        p = trace_points(ix, side, radius, tau, t_of(tau))
        if not p.ok.all():
            raise ValueError(f"side {side:+d}'s trace at ρ = {radius:g} mm is lost inside "
                             f"[{a:.9g}, {b:.9g}] rad of τ")
        return np.column_stack([radius * (phi_of(tau) - shift), p.points[:, 2]]), p.t, p.margin

    n = max(4, int(math.ceil((b - a) / _NODE_STEP)) + 1)
    while True:
        tau = np.linspace(a, b, n)
        xy, tt, margin = developed(tau)
        sp = make_interp_spline(tau, xy, k=3)
        fr = np.arange(1, CHECKS) / CHECKS
        tc = (tau[:-1, None] + fr[None, :] * np.diff(tau)[:, None]).ravel()
        err = float(np.max(np.hypot(*(sp(tc) - developed(tc)[0]).T)))
        if err <= tolerance or 2 * n - 1 > _MAX_NODES:
            break
        n = 2 * n - 1
    layer = f"TRACE_{where}_{'P' if side == 1 else 'M'}"
    curve = NurbsCurve(3, np.asarray(sp.t, dtype=float), np.asarray(sp.c, dtype=float), np.ones(len(sp.c)))
    return DrawnTrace(layer, side, float(radius), (float(a), float(b)), turn, n, err,
                      (float(tt.min()), float(tt.max())), float(margin.min()), ends, curve)


# ---------------------------------------------------------------------------------------------
# the drawing

@dataclass(frozen=True)
class SpatialDxfInfo:
    """What :func:`spatial_drawing` drew.

    Attributes:
        kind: "barrel" or "globoidal"; layers: the layer names; views: view name → its origin
        (X, Y) in the drawing [mm] (module docs); phi_mid: φ_m [rad] of the developed views (NaN
        for a globoid); traces: the barrel's :class:`DrawnTrace` s (the SPLINEs' curves are those
        before the view's origin is added); trace_error: their largest measured error [mm] (NaN
        without traces); fit_error: the flank surfaces' largest measured error [mm];
        quoted_trace_error, quoted_fit_error: the title block's numbers (rounded up, 2 digits);
        rollers: the roller outlines drawn; text_height [mm]; rows: the title block's rows.
    """

    kind: str
    layers: tuple[str, ...]
    views: dict[str, tuple[float, float]]
    phi_mid: float
    traces: tuple[DrawnTrace, ...]
    trace_error: float
    fit_error: float
    quoted_trace_error: float
    quoted_fit_error: float
    rollers: int
    text_height: float
    rows: tuple[tuple[str, str], ...]
    units: str = "mm"
    insunits: int = 4

    def summary(self) -> dict[str, Any]:
        """Plain numbers (lengths in mm, angles in degrees)."""
        return {"units": self.units, "insunits": self.insunits, "kind": self.kind, "layers": list(self.layers),
                "views": {k: list(v) for k, v in self.views.items()},
                "phi_mid_deg": math.degrees(self.phi_mid) if math.isfinite(self.phi_mid) else None,
                "splines": len(self.traces), "rollers": self.rollers,
                "trace_error_mm": self.trace_error if self.traces else None,
                "quoted_trace_error_mm": self.quoted_trace_error if self.traces else None,
                "flank_fit_error_mm": self.fit_error, "quoted_flank_fit_error_mm": self.quoted_fit_error,
                "traces": [{"layer": d.layer, "side": d.side, "radius_mm": d.radius,
                            "tau_from_deg": math.degrees(d.tau_range[0]), "tau_to_deg": math.degrees(d.tau_range[1]),
                            "nodes": d.nodes, "error_mm": d.error, "t_from_mm": d.t_range[0], "t_to_mm": d.t_range[1],
                            "min_margin": d.min_margin, "ends": list(d.ends)} for d in self.traces],
                "circles_arcs_lines": "exact"}


def _g(v: float) -> str:
    return f"{v:.6g}"


def title_rows(design: SpatialDesign, quoted_fit: float, quoted_trace: float | None) -> list[tuple[str, str]]:
    """(label, value) rows of the title block: the indexer's parameters and the design summary's
    numbers (degrees, mm), how the flanks and their traces are represented (measured errors)."""
    ix = design.indexer
    s = design.summary()
    barrel = isinstance(ix, BarrelIndexer)
    psi0 = math.degrees(float(turret_angle(ix, np.array([0.0]))[0][0]))
    drive, margin, rib = s["max_driving_pressure_angle"], s["min_regularity_margin"], s["min_rib_thickness"]
    t0, t1 = float(ix.roller_start), float(ix.roller_end)
    rows = [
        ("TYPE", "BARREL INDEXER" if barrel else "GLOBOIDAL INDEXER"),
        ("STATIONS N", str(int(ix.stations))),
        ("INDEX ANGLE BETA", f"{_g(s['index_angle_deg'])}°"),
        ("MOTION LAW", str(ix.law).upper()),
        ("INDEX START", f"{_g(s['index_start_deg'])}° OF INPUT"),
        ("CENTRE DISTANCE C", f"{_g(s['centre_distance'])} mm"),
    ]
    if barrel:
        rows.append(("TURRET PITCH RADIUS R_p", f"{_g(s['pitch_radius'])} mm"))
    rows += [
        ("ROLLER RADIUS r_r", f"{_g(s['roller_radius'])} mm"),
    ]
    if float(ix.roller_cone_angle) != 0.0:
        r0, r1 = (float(r) for r in ix.radius_at(np.array([t0, t1])))
        rows.append(("ROLLER CONE ANGLE", f"{_g(math.degrees(float(ix.roller_cone_angle)))}°, RADIUS {_g(r0)} mm AT "
                                          f"t = {_g(t0)} TO {_g(r1)} mm AT t = {_g(t1)} (r_r AT THE MIDDLE)"))
    rows += [
        ("ROLLER LENGTH", f"{_g(t1 - t0)} mm, t = {_g(t0)} TO {_g(t1)} mm"),
        ("RIB RADII", f"ROOT {_g(s['root_radius'])} mm, TOP {_g(s['outer_radius'])} mm" if barrel else
         f"TIP GLOBOID {_g(s['tip_radius'])} mm, ROOT GLOBOID {_g(s['root_radius'])} mm"),
        ("CAM WIDTH W", f"{_g(s['cam_width'])} mm"),
        ("MAX DRIVING PRESSURE ANGLE", f"{drive['value_deg']:.4f}° AT {drive['at_deg']:.4f}° OF INPUT"),
        ("MIN REGULARITY MARGIN", f"{margin['value_1']:.4f} AT {margin['at_deg']:.4f}° OF INPUT"),
        ("MIN RIB THICKNESS", f"{rib['value_mm']:.4f} mm AT {rib['at_deg']:.4f}° OF INPUT"),
        ("FLANK SURFACES", f"BICUBIC B-SPLINES WITHIN {quoted_fit:.1e} mm OF THE EXACT ENVELOPE (MEASURED)"),
    ]
    if quoted_trace is not None:
        rows += [("FLANK TRACES", f"CUBIC SPLINES WITHIN {quoted_trace:.1e} mm OF THE EXACT ENVELOPE (MEASURED)"),
                 ("ROOT TRACES", f"FLANKS CONTINUED BELOW THE ROLLERS' ENDS (t < {_g(t0)} mm)")]
    else:
        rows.append(("FLANK TRACES", "NOT DRAWN"))
    rows += [
        ("CIRCLES, ARCS, LINES", "EXACT"),
        ("DRAWN AT", f"INPUT ANGLE 0°, TURRET ANGLE {psi0:.4f}°"),
        ("UNITS / SCALE", "mm / 1:1"),
        ("SOFTWARE", f"cam_workbench {__version__}"),
    ]
    return rows


def _rect(msp: Any, x0: float, y0: float, x1: float, y1: float, layer: str) -> None:
    add_closed_outline(msp, [(x0, y0), (x1, y0), (x1, y1), (x0, y1)], {"layer": layer})


def roller_outline(ix: BarrelIndexer | GloboidalIndexer, base: tuple[float, float], axis: tuple[float, float],
                   across: tuple[float, float]) -> list[tuple[float, float]]:
    """A roller seen side-on (module docs, *Rollers*): the drawing points base + t·axis ∓ r(t)·across
    at t0, t1, t1, t0 (``axis``, ``across`` unit vectors of the drawing, square to each other) — a
    trapezoid r(t0) … r(t1) wide, the rectangle of half-width r_r for a cylinder."""
    t0, t1 = float(ix.roller_start), float(ix.roller_end)
    b, u, v = np.asarray(base, dtype=float), np.asarray(axis, dtype=float), np.asarray(across, dtype=float)
    r0, r1 = (float(r) for r in ix.radius_at(np.array([t0, t1])))
    pts = [b + t0 * u - r0 * v, b + t1 * u - r1 * v, b + t1 * u + r1 * v, b + t0 * u + r0 * v]
    return [(float(q[0]), float(q[1])) for q in pts]


def _upright(pts: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """A barrel roller's outline from :func:`roller_outline` in the order the side and end views use:
    (t0, −), (t0, +), (t1, +), (t1, −) (counter-clockwise from the bottom left)."""
    return [pts[0], pts[3], pts[2], pts[1]]


def _line(msp: Any, a: tuple[float, float], b: tuple[float, float], layer: str) -> None:
    msp.add_line(a, b, dxfattribs={"layer": layer})


def _dimension(msp: Any, p1: tuple[float, float], p2: tuple[float, float], base: tuple[float, float], angle: float,
               h: float) -> None:
    msp.add_linear_dim(base=base, p1=p1, p2=p2, angle=angle, text="C = <>", dimstyle=DIMSTYLE,
                       override=dim_values(h), dxfattribs={"layer": "DIMENSIONS", "dimstyle": DIMSTYLE}).render()


def near_rollers(ix: BarrelIndexer) -> Array:
    """The barrel's rollers drawn at θ = 0: (M, 2) axis points (x_a, z_a) of those within W/2 + r_max
    of the cam's middle axially and R_top + r_max of the cam axis (r_max the roller's largest radius,
    r_r for a cylinder)."""
    n = int(ix.stations)
    al = roller_alpha(ix, np.arange(n), turret_angle(ix, np.array([0.0]))[0][0])
    x = float(ix.centre_distance) + float(ix.pitch_radius) * np.cos(al)
    z = float(ix.pitch_radius) * np.sin(al)
    rr = ix.largest_radius
    keep = (np.abs(z) < 0.5 * float(ix.cam_width) + rr) & (np.abs(x) < float(ix.outer_radius) + rr)
    return np.column_stack([x[keep], z[keep]])


def _barrel(msp: Any, design: SpatialDesign, surfaces: FlankSurfaces, h: float
            ) -> tuple[dict[str, tuple[float, float]], float, list[DrawnTrace], int, tuple[float, float, float, float]]:
    ix = design.indexer
    c, rr, r_max = float(ix.centre_distance), float(ix.roller_radius), ix.largest_radius
    r0, r1, half = float(ix.root_radius), float(ix.outer_radius), 0.5 * float(ix.cam_width)
    t1 = float(ix.roller_end)
    phi_m = phi_mid(ix)
    traces = flank_traces(design, surfaces, r1, phi_m) + flank_traces(design, surfaces, r0, phi_m)
    rollers = near_rollers(ix)
    # side view at the origin: X = z, Y = y
    z_lo = max(-half, min(float(np.min(tr.curve.poles[:, 1])) for tr in traces))
    z_hi = min(half, max(float(np.max(tr.curve.poles[:, 1])) for tr in traces))
    _rect(msp, -half, -r0, half, r0, "OUTLINE")
    _rect(msp, z_lo, -r1, z_hi, r1, "RIB")
    for x, z in rollers.tolist():
        add_closed_outline(msp, _upright(roller_outline(ix, (z, 0.0), (0.0, 1.0), (1.0, 0.0))), {"layer": "ROLLERS"})
    ext = 2 * h
    _line(msp, (-half - ext, 0.0), (half + ext, 0.0), "CENTERLINES")
    _line(msp, (0.0, -r1 - ext), (0.0, t1 + ext), "CENTERLINES")
    add_text(msp, "SIDE VIEW (CAM AXIS HORIZONTAL, TURRET ABOVE)", (-half, t1 + 2.5 * h), 0.7 * h, "NOTES")
    # end view: X = x, Y = y about the cam axis
    x_lo = min(-r1, float(np.min(rollers[:, 0], initial=0.0)) - r_max)
    xe = half + 6 * h - x_lo
    msp.add_circle((xe, 0.0), r1, dxfattribs={"layer": "OUTLINE"})
    msp.add_circle((xe, 0.0), r0, dxfattribs={"layer": "ROOT"})
    ends = np.unique(np.round(rollers[:, 0], 9))          # rollers at z and −z coincide seen along z
    for x in ends.tolist():
        add_closed_outline(msp, _upright(roller_outline(ix, (xe + x, 0.0), (0.0, 1.0), (1.0, 0.0))),
                           {"layer": "ROLLERS"})
    add_cross(msp, xe, 0.0, rr, "CENTERLINES")
    _line(msp, (xe - r1 - ext, 0.0), (xe + c + ext, 0.0), "CENTERLINES")
    _line(msp, (xe + c, -r1 - ext), (xe + c, t1 + ext), "CENTERLINES")
    add_text(msp, "END VIEW (ALONG THE CAM AXIS)", (xe - r1, t1 + 2.5 * h), 0.7 * h, "NOTES")
    add_text(msp, "TURRET AXIS", (xe + c + 0.4 * h, t1 + 0.6 * h), 0.7 * h, "CENTERLINES")
    y_dim = -r1 - 3 * h
    _dimension(msp, (xe, 0.0), (xe + c, 0.0), (xe + 0.5 * c, y_dim), 0.0, h)
    # the developed views below: the top radius, then the root radius
    x0 = -half + math.pi * r1
    views = {"side": (0.0, 0.0), "end": (xe, 0.0)}
    y0 = y_dim - 4 * h - half
    right = xe + c + 1.4 * h + text_width("TURRET AXIS", 0.7 * h)
    for name, rho in (("developed_top", r1), ("developed_root", r0)):
        views[name] = (x0, y0)
        _rect(msp, x0 - math.pi * rho, y0 - half, x0 + math.pi * rho, y0 + half, "OUTLINE")
        _line(msp, (x0 - math.pi * rho - ext, y0), (x0 + math.pi * rho + ext, y0), "CENTERLINES")
        what = "RIB TOP" if rho == r1 else "RIB ROOT"
        add_text(msp, f"DEVELOPED AT R {_g(rho)} mm ({what}): X = R*PHI, Y = Z; SEEN FROM OUTSIDE",
              (x0 - math.pi * rho, y0 + half + 0.8 * h), 0.7 * h, "NOTES")
        for tr in traces:
            if tr.radius == rho:
                moved = NurbsCurve(3, tr.curve.knots, tr.curve.poles + np.array([x0, y0]), tr.curve.weights)
                add_nurbs_spline(msp, moved, tr.layer)
        right = max(right, x0 + math.pi * rho + ext)
        y0 -= 2 * half + 4 * h
    bottom = y0 + half + 2 * h
    return views, phi_m, traces, int(rollers.shape[0] + ends.size), (-half - ext, right, bottom, t1 + 3.5 * h)


def _globoid(msp: Any, design: SpatialDesign, h: float
             ) -> tuple[dict[str, tuple[float, float]], int, tuple[float, float, float, float]]:
    ix = design.indexer
    n = int(ix.stations)
    c, rr, r_max = float(ix.centre_distance), float(ix.roller_radius), ix.largest_radius
    r_tip, r_root, half = float(ix.tip_radius), float(ix.root_radius), 0.5 * float(ix.cam_width)
    t0, t1 = float(ix.roller_start), float(ix.roller_end)
    ext = 2 * h
    # contour view: X = z, Y = x; P at (0, C)
    for radius, layer in ((r_root, "OUTLINE"), (r_tip, "TIP")):
        d = math.degrees(math.asin(half / radius))
        msp.add_arc((0.0, c), radius, 270.0 - d, 270.0 + d, dxfattribs={"layer": layer})
        msp.add_arc((0.0, -c), radius, 90.0 - d, 90.0 + d, dxfattribs={"layer": layer})
    rho_end = c - math.sqrt(r_root**2 - half**2)
    for z in (-half, half):
        _line(msp, (z, -rho_end), (z, rho_end), "OUTLINE")
    msp.add_circle((0.0, c), t0, dxfattribs={"layer": "TURRET"})
    al = roller_alpha(ix, np.arange(n), turret_angle(ix, np.array([0.0]))[0][0])
    for a in al.tolist():
        u = np.array([math.sin(a), math.cos(a)])          # (z, x) of u(α)
        v = np.array([u[1], -u[0]])
        add_closed_outline(msp, roller_outline(ix, (0.0, c), (u[0], u[1]), (v[0], v[1])), {"layer": "ROLLERS"})
    _line(msp, (-half - ext, 0.0), (half + ext, 0.0), "CENTERLINES")
    add_cross(msp, 0.0, c, rr, "CENTERLINES")
    add_cross(msp, 0.0, 0.0, rr, "CENTERLINES")
    add_text(msp, "CONTOUR VIEW: SECTION IN THE TURRET'S PLANE (X = Z, Y = X)", (-c, c + t1 + r_max + 2 * h), 0.7 * h,
          "NOTES")
    add_text(msp, "P: TURRET AXIS", (0.4 * h, c + 0.6 * h), 0.7 * h, "CENTERLINES")
    reach = t1 + r_max
    x_dim = -max(half, reach) - 3 * h
    _dimension(msp, (0.0, 0.0), (0.0, c), (x_dim, 0.5 * c), 90.0, h)
    # end view along the cam axis: X = x, Y = y
    rho_tip_end = c - math.sqrt(r_tip**2 - half**2)
    xe = max(half, reach) + 6 * h + rho_tip_end
    msp.add_circle((xe, 0.0), rho_end, dxfattribs={"layer": "OUTLINE"})
    msp.add_circle((xe, 0.0), rho_tip_end, dxfattribs={"layer": "TIP"})
    msp.add_circle((xe, 0.0), c - r_root, dxfattribs={"layer": "HIDDEN"})
    msp.add_circle((xe, 0.0), c - r_tip, dxfattribs={"layer": "HIDDEN"})
    add_cross(msp, xe, 0.0, rr, "CENTERLINES")
    _line(msp, (xe - rho_tip_end - ext, 0.0), (xe + c + ext, 0.0), "CENTERLINES")
    _line(msp, (xe + c, -rho_tip_end - ext), (xe + c, rho_tip_end + ext), "CENTERLINES")
    add_text(msp, "END VIEW (ALONG THE CAM AXIS)", (xe - rho_tip_end, rho_tip_end + 2.5 * h), 0.7 * h, "NOTES")
    add_text(msp, "TURRET AXIS", (xe + c + 0.4 * h, rho_tip_end + 0.6 * h), 0.7 * h, "CENTERLINES")
    y_dim = -rho_tip_end - 3 * h
    _dimension(msp, (xe, 0.0), (xe + c, 0.0), (xe + 0.5 * c, y_dim), 0.0, h)
    box = (x_dim - 3 * h, xe + c + 1.4 * h + text_width("TURRET AXIS", 0.7 * h), min(-c - ext, y_dim - 3 * h),
           c + reach + 3 * h)
    return {"contour": (0.0, 0.0), "end": (xe, 0.0)}, n, box


def spatial_drawing(design: SpatialDesign, surfaces: FlankSurfaces, title: str | None = None
                    ) -> tuple[Any, SpatialDxfInfo]:
    """(ezdxf document, what it holds) of a barrel or globoidal indexer's drawing, nothing written:
    the views of the module docstring at input angle 0, the centre distance dimensioned and a
    title block (``title``, default by the indexer's type) quoting the design's summary and the
    measured errors of the flank surfaces (``surfaces`` = ``flank_surfaces(design)``) and of the
    drawn traces; mm."""
    ix = design.indexer
    barrel = isinstance(ix, BarrelIndexer)
    if not barrel and not isinstance(ix, GloboidalIndexer):
        raise TypeError(f"not a spatial indexer's design: {type(ix).__name__}")
    if surfaces.indexer != ix:
        raise ValueError("the flank surfaces are not of this design's indexer")
    if barrel:
        span = float(ix.cam_width) + 2 * float(ix.outer_radius) + float(ix.centre_distance) + ix.largest_radius
    else:
        span = 2 * float(ix.roller_end) + 2 * float(ix.centre_distance)
    h = float(f"{span / 60:.2g}")
    doc = new_document(h)
    layers = spatial_layers()
    for name, (color, linetype, lw) in layers.items():
        doc.layers.add(name, color=color, linetype=linetype).dxf.lineweight = lw
    msp = doc.modelspace()
    if barrel:
        views, phi_m, traces, rollers, box = _barrel(msp, design, surfaces, h)
    else:
        (views, rollers, box), phi_m, traces = _globoid(msp, design, h), math.nan, []
    fit = max(f.max_error for f in surfaces.flanks)
    trace_err = max((t.error for t in traces), default=math.nan)
    q_fit = round_up(fit)
    q_trace = round_up(trace_err) if traces else math.nan
    rows = title_rows(design, q_fit, q_trace if traces else None)
    x_lo, x_hi, y_lo, y_hi = box
    title_block(msp, title or DEFAULT_TITLE[type(ix).__name__], rows, x_hi + 3 * h, y_hi, h,
                 (x_lo - 2 * h, y_lo - 2 * h))
    try:
        from ezdxf import zoom  # deferred: ezdxf, loaded when a drawing is made

        zoom.extents(msp, factor=1.05)
    except Exception:  # noqa: BLE001 - the initial view is a convenience only
        pass
    info = SpatialDxfInfo("barrel" if barrel else "globoidal", tuple(layers), views, phi_m, tuple(traces), trace_err,
                          float(fit), q_trace, q_fit, rollers, h, tuple(rows))
    return doc, info


def write_spatial_dxf(design: SpatialDesign, surfaces: FlankSurfaces, path: str | os.PathLike[str],
                      title: str | None = None) -> SpatialDxfInfo:
    """Write :func:`spatial_drawing` to ``path`` atomically (temporary file, then rename)."""
    doc, info = spatial_drawing(design, surfaces, title)
    with atomic_path(path) as tmp:
        doc.saveas(str(tmp))
    return info


__all__ = ["CHECKS", "DEFAULT_TITLE", "MIN_SLOPE", "TRACE_TOLERANCE", "DrawnTrace", "SpatialDxfInfo", "flank_traces",
           "near_rollers", "phi_mid", "spatial_drawing", "spatial_layers", "title_rows", "trace_points",
           "write_spatial_dxf"]

"""LinuxCNC XY finishing-contour programs for the cam plates of a parallel indexer, one per plate
(``cam0.nc``, ``cam1.nc``, …): each plate is cut alone, from its own blank, in the cam frame at
input angle 0 (:mod:`cam_workbench.generators.bodies.indexing.parallel`: origin on the input axis O,
+X towards the turret axis, angles counter-clockwise), Z0 on the plate's top face, mm.

The tool centre runs the OUTSIDE offset of the cam's profile loop
(:func:`~cam_workbench.generators.bodies.indexing.parallel_body.cam_loop`) by the tool radius R_t:

* the dwell part: an exact arc about O of radius (r_d − r_r) + R_t (G02/G03);
* each flank: the offset T(τ) = Q(τ) + R_t·n(τ) = L(τ) + (R_t − r_r)·n(τ) of the exact flank
  (L the roller-centre locus, n its outward normal, Q = L − r_r·n the profile,
  :func:`~cam_workbench.generators.bodies.indexing.parallel_body.offset_point`), with
  T'(τ) = L'(τ)·(1 + (R_t − r_r)/ρ(τ)); fitted by G02/G03 biarcs
  (:func:`~cam_workbench.generators.curves.approx.fit_biarcs` on a cubic guide through T at
  uniform τ with T' at the ends), the fit's distance MEASURED against T itself (dense two-sided
  samples of the analytic offset) — not against the offset of the body's B-spline flank, which
  differs from Q by the body's own flank fit error (quoted beside it);
* the lobe tip X' (a convex corner of the profile, where the flanks meet): the tool rolls round it
  on an arc of radius R_t about X', from the end of one flank's offset to the start of the other's.

Cutting: climb milling by default (spindle M3, the outside contour clockwise), entered and left on
tangent quarter-circle lead arcs at the middle of the dwell arc, one pass at Z = −depth (default the
plate's thickness).  Coordinates have 4 decimals (I/J relative to the written start point); the
path as written — rounded, arcs whose rounded end radius differs from the start radius followed
as LinuxCNC does, as a spiral — must lie within (1 − BLEND_SHARE)·tolerance of the analytic
tool-centre path (measured, two-sided); the rest, ``G64 P``, is the controller's blending.

A tool larger than the profile's smallest concave radius of curvature cannot cut it: refused
(SpecError naming ``machining.tool_radius``).
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from cam_workbench.generators import __version__
from cam_workbench.generators.bodies.indexing.parallel import TWO_PI, ParallelDesign, ParallelIndexer, locus
from cam_workbench.generators.bodies.indexing.parallel_body import IndexerBody
from cam_workbench.generators.curves.approx import Path2D, fit_biarcs, nearest_vertex
from cam_workbench.generators.curves.basis import interpolating_cubic
from cam_workbench.generators.curves.nurbs import NurbsCurve
from cam_workbench.generators.errors import SolveError, SpecError
from cam_workbench.generators.machining.toolpath import BLEND_SHARE, FLAT_ARC, reverse_path, straighten_flat_arcs

from .atomic import write_text_atomic
from .gcode import GcodeWriter, fmt

Array = np.ndarray
#: decimals of the written coordinates [mm]
DECIMALS = 4
#: the worst distance the rounding to DECIMALS moves a written arc from the arc it stands for [mm]:
#: end points and centre each within ½·10⁻⁴·√2, so the radius within twice that and a point of
#: the (spiral) arc within three times
ROUNDING_RESERVE = 3.0 * math.sqrt(2.0) * 0.5 * 10.0 ** -DECIMALS
#: share of the biarc fit tolerance the cubic guide of a flank's offset may use
_GUIDE_SHARE = 0.05
_FIRST_NODES, _MOST_NODES = 16, 4096
_CHECK = np.linspace(0.0, 1.0, 33)[1:-1]
#: spacing [mm] of the dense samples the written path is measured with (both curves)
_MEASURE_STEP = 2.5e-3
#: samples per flank-τ unit used to size the dense samples and to refine the concave radius
_TRIAL = 2001


@dataclass(frozen=True)
class IndexerProgram:
    """One cam plate's XY finishing program and what it was measured to do (mm, cam frame).

    Attributes:
        cam: k; name: the file name (``cam<k>.nc``); text: the program.
        pieces: the contour as written (rounded coordinates), in cutting order from the entry at
            the middle of the dwell: (label, Path2D) with labels "dwell arc", "outgoing flank",
            "lobe tip", "incoming flank", "dwell arc" (reversed for conventional milling);
        lead_in, lead_out: the tangent quarter-circle lead arcs as written.
        tool_radius: R_t; dwell_radius: the tool centre's dwell arc radius r_d − r_r + R_t;
        tip: X', the profile's corner (the lobe-tip arc's centre).
        biarc_error: the flanks' biarcs' largest two-sided distance from the analytic offset T
            (before rounding); path_error: the written contour's (rounded, as interpolated) from
            the whole analytic tool-centre path; flank_fit_error: the body's B-spline flanks'
            distance from the exact profile (the body's own measure).
        min_concave_radius: the profile's smallest concave radius of curvature (inf: none).
        tolerance: the path tolerance; blend: G64 P; depth: cutting depth; clockwise: the
        contour's sense (climb milling with M3).
    """

    cam: int
    name: str
    text: str
    pieces: tuple[tuple[str, Path2D], ...]
    lead_in: Path2D
    lead_out: Path2D
    tool_radius: float
    dwell_radius: float
    tip: complex
    biarc_error: float
    path_error: float
    flank_fit_error: float
    min_concave_radius: float
    tolerance: float
    blend: float
    depth: float
    clockwise: bool

    @property
    def loop(self) -> Path2D:
        """The whole contour as written, in cutting order (entry → entry)."""
        return _concat([p for _, p in self.pieces])

    def summary(self) -> dict[str, Any]:
        """Plain numbers (mm)."""
        loop = self.loop
        arcs = int(np.count_nonzero(loop.is_arc))
        return {"cam": self.cam, "file": self.name, "moves": loop.n, "arcs": arcs, "lines": loop.n - arcs,
                "tool_radius_mm": self.tool_radius, "dwell_arc_radius_mm": self.dwell_radius,
                "tip_mm": [self.tip.real, self.tip.imag], "biarc_error_mm": self.biarc_error,
                "path_error_mm": self.path_error, "flank_fit_error_mm": self.flank_fit_error,
                "min_concave_radius_mm": self.min_concave_radius, "tolerance_mm": self.tolerance,
                "g64_p_mm": self.blend, "depth_mm": self.depth, "clockwise": self.clockwise}


# ---- geometry -----------------------------------------------------------------------------------

def tool_centre_offset(ix: ParallelIndexer, cam: int, tau: Array, tool_radius: float) -> tuple[Array, Array]:
    """The tool centre on a flank, T(τ) = Q(τ) + R_t·n(τ) = L(τ) + (R_t − r_r)·n(τ) [mm], and
    T'(τ) = L'(τ)·(1 + (R_t − r_r)/ρ(τ)) [mm/rad] (cam frame; τ the locus parameter, clockwise)."""
    loc = locus(ix, cam, np.asarray(tau, dtype=float))
    d = float(tool_radius) - float(ix.roller_radius)
    return loc["point"] + d * loc["normal"], loc["d1"] * (1.0 + d / loc["rho"])[..., None]


def smallest_concave_radius(design: ParallelDesign, cam: int) -> tuple[float, float]:
    """(smallest concave radius of curvature of cam ``cam``'s profile [mm], its τ [rad]); (inf,
    nan) without concave parts.  The profile's signed radius is ρ − r_r (convex +): the design's
    samples, refined near their smallest concave value on a dense τ grid of the analytic ρ."""
    ix, c = design.indexer, design.cams[cam]
    rr = float(ix.roller_radius)
    rad = np.where(c.profile_radius < 0, -c.profile_radius, np.inf)
    if not np.isfinite(rad).any():
        return math.inf, math.nan
    i = int(np.argmin(rad))
    lo, hi = c.profile_tau[max(i - 1, 0)], c.profile_tau[min(i + 1, rad.size - 1)]
    tau = np.linspace(lo, hi, _TRIAL)
    r = -(locus(ix, cam, tau)["rho"] - rr)
    r = np.where(r > 0, r, np.inf)
    j = int(np.argmin(r))
    if r[j] < rad[i]:
        return float(r[j]), float(tau[j])
    return float(rad[i]), float(c.profile_tau[i])


def _guide(ix: ParallelIndexer, cam: int, tau0: float, tau1: float, tool_radius: float, tol: float) -> NurbsCurve:
    """A clamped cubic in τ through T at uniform nodes with T' at the ends, nodes doubled until
    within ``tol`` of T at 31 points of every span (the biarc fitter's input)."""
    n = _FIRST_NODES
    while True:
        x = np.linspace(tau0, tau1, n + 1)
        p, dp = tool_centre_offset(ix, cam, x, tool_radius)
        knots, coef = interpolating_cubic(x, p, dp[0], dp[-1])
        curve = NurbsCurve(3, knots, coef, np.ones(coef.shape[0]))
        check = (x[:-1, None] + np.diff(x)[:, None] * _CHECK[None, :]).ravel()
        exact, _ = tool_centre_offset(ix, cam, check, tool_radius)
        err = float(np.max(np.hypot(*(curve.evaluate(check) - exact).T)))
        if err <= tol:
            return curve
        if n >= _MOST_NODES:
            raise SolveError(f"cam {cam}: the tool-centre offset of a flank is {err:.3g} mm from its cubic guide "
                             f"with {n + 1} nodes, above {tol:.3g} mm")
        n *= 2


def _dense_offset(ix: ParallelIndexer, cam: int, tau0: float, tau1: float, tool_radius: float) -> Array:
    """The analytic offset T on [tau0, tau1] as complex points about ``_MEASURE_STEP`` apart."""
    trial = np.linspace(tau0, tau1, _TRIAL)
    _, dp = tool_centre_offset(ix, cam, trial, tool_radius)
    step = float(np.max(np.hypot(*dp.T))) * (tau1 - tau0)
    n = int(min(max(math.ceil(step / _MEASURE_STEP), 64), 2_000_000))
    p, _ = tool_centre_offset(ix, cam, np.linspace(tau0, tau1, n + 1), tool_radius)
    return p[:, 0] + 1j * p[:, 1]


def _arc_points(centre: complex, radius: float, a0: float, a1: float) -> Array:
    n = max(int(math.ceil(abs(a1 - a0) * radius / _MEASURE_STEP)), 8)
    return centre + radius * np.exp(1j * np.linspace(a0, a1, n + 1))


def _element(start: complex, end: complex, centre: complex, ccw: bool) -> Path2D:
    return Path2D(np.array([start]), np.array([end]), np.array([centre]), np.array([ccw]),
                  np.array([np.nan]), np.array([np.nan]))


def _concat(paths: list[Path2D]) -> Path2D:
    return Path2D(*(np.concatenate([getattr(p, f) for p in paths])
                    for f in ("start", "end", "center", "ccw", "u0", "u1")))


def _round(z: Array) -> Array:
    return np.round(z.real, DECIMALS) + 1j * np.round(z.imag, DECIMALS)


def as_written(path: Path2D) -> Path2D:
    """``path`` with the coordinates a program writes: end points rounded to :data:`DECIMALS`,
    each arc's centre = the rounded start + the rounded I/J (from that rounded start); elements
    that rounding shrinks to nothing are dropped, and an arc whose rounded sweep would differ
    from its own by more than a tenth becomes a line."""
    start, end = _round(path.start), _round(path.end)
    arc = path.is_arc
    centre = np.where(arc, start + _round(np.where(arc, path.center, 0) - start), np.nan + 0j)
    out = Path2D(start, end, centre, path.ccw & arc, path.u0, path.u1)
    bad = arc & (np.abs(out.sweep() - path.sweep()) > 0.1 * np.abs(path.sweep()))
    keep = start != end
    out = Path2D(start, end, np.where(bad, np.nan + 0j, centre), out.ccw & ~bad, path.u0, path.u1)
    return Path2D(*(getattr(out, f)[keep] for f in ("start", "end", "center", "ccw", "u0", "u1")))


def sample_as_interpolated(path: Path2D, step: float = _MEASURE_STEP) -> Array:
    """Points along ``path`` about ``step`` apart, as LinuxCNC moves: lines straight, arcs about
    their centre with the radius linear in the angle from the start radius to the end radius (a
    spiral when rounding made them differ); the last end point included."""
    arc = path.is_arc
    c = np.where(arc, path.center, 0)
    r0, r1 = np.abs(path.start - c), np.abs(path.end - c)
    sweep = path.sweep()
    length = np.where(arc, np.abs(sweep) * np.maximum(r0, r1), np.abs(path.end - path.start))
    m = np.maximum(np.ceil(length / step).astype(int), 1)
    el = np.repeat(np.arange(path.n), m)
    t = (np.arange(el.size) - np.repeat(np.cumsum(m) - m, m)) / m[el]
    a = np.angle(path.start - c)[el] + sweep[el] * t
    arc_pts = c[el] + (r0[el] + (r1 - r0)[el] * t) * np.exp(1j * a)
    line_pts = path.start[el] + (path.end - path.start)[el] * t
    return np.append(np.where(arc[el], arc_pts, line_pts), path.end[-1])


def _segment_distance(x: Array, a: Array, b: Array) -> Array:
    ab = b - a
    den = np.where(np.abs(ab) > 0, np.abs(ab) ** 2, 1.0)
    s = np.clip(((x - a) * np.conj(ab)).real / den, 0.0, 1.0)
    return np.abs(x - (a + s * ab))


def polyline_distance(x: Array, poly: Array, closed: bool) -> Array:
    """Distance [mm] of points ``x`` to the dense polyline ``poly`` (complex; ``closed``: its last
    point repeats the first): the nearest vertex, then the segments on both sides of it (repeated
    vertices dropped first, so both sides are real segments)."""
    poly = poly[np.append(True, poly[1:] != poly[:-1])]
    ring = poly[:-1] if closed else poly
    n = ring.size
    k = nearest_vertex(x, ring)
    lo, hi = ((k - 1) % n, (k + 1) % n) if closed else (np.clip(k - 1, 0, n - 1), np.clip(k + 1, 0, n - 1))
    return np.minimum(_segment_distance(x, ring[lo], ring[k]), _segment_distance(x, ring[k], ring[hi]))


def _two_sided(a: Array, b: Array, closed: bool) -> float:
    return float(max(polyline_distance(a, b, closed).max(), polyline_distance(b, a, closed).max()))


# ---- one cam ------------------------------------------------------------------------------------

@dataclass(frozen=True)
class _CamGeometry:
    """Cam k's tool-centre geometry: flank τ ranges, tip, dwell arc, analytic dense pieces."""

    cam: int
    out_tau: tuple[float, float]
    in_tau: tuple[float, float]
    tip: complex
    dwell_radius: float
    dwell_a0: float          # angle of T(θ_s) (dwell's outgoing end); the dwell runs ccw to a0 + 2π − β
    dwell_a1: float
    exact_out: Array
    exact_in: Array
    exact_loop: Array        # the whole analytic path, clockwise from the dwell's middle, closed


def _cam_geometry(design: ParallelDesign, k: int, tool_radius: float) -> _CamGeometry:
    ix = design.indexer
    c = design.cams[k]
    ts, beta = float(ix.index_start), float(ix.index_angle)
    out_tau = (ts, float(c.tip_tau[1]))
    in_tau = (float(c.tip_tau[0]), ts - TWO_PI + beta)
    tip = complex(float(c.tip[0]), float(c.tip[1]))
    radius = float(c.dwell_radius) - float(ix.roller_radius) + tool_radius
    p0, _ = tool_centre_offset(ix, k, np.array([ts]), tool_radius)
    a0 = math.atan2(float(p0[0, 1]), float(p0[0, 0]))
    a1 = a0 + (TWO_PI - beta)
    am = 0.5 * (a0 + a1)
    ex_out = _dense_offset(ix, k, *out_tau, tool_radius)
    ex_in = _dense_offset(ix, k, *in_tau, tool_radius)
    # clockwise: dwell middle → a0, outgoing flank, round the tip, incoming flank, a1 → middle
    tip_a0, tip_a1 = np.angle(ex_out[-1] - tip), np.angle(ex_in[0] - tip)
    tip_a1 = tip_a0 - np.mod(tip_a0 - tip_a1, TWO_PI)
    loop = np.concatenate([_arc_points(0j, radius, am, a0), ex_out, _arc_points(tip, tool_radius, tip_a0, tip_a1),
                           ex_in, _arc_points(0j, radius, a1, am)])
    return _CamGeometry(k, out_tau, in_tau, tip, radius, a0, a1, ex_out, ex_in, loop)


def _flank_biarcs(ix: ParallelIndexer, g: _CamGeometry, tau: tuple[float, float], exact: Array,
                  tool_radius: float, fit_tol: float, flat: float) -> tuple[Path2D, float]:
    """A flank's tool-centre offset as biarcs (τ increasing: clockwise) and their measured
    two-sided distance from the analytic offset (dense samples)."""
    guide = _guide(ix, g.cam, tau[0], tau[1], tool_radius, _GUIDE_SHARE * fit_tol)
    path = straighten_flat_arcs(fit_biarcs(guide, max((1.0 - _GUIDE_SHARE) * fit_tol - flat, 0.5 * fit_tol)), flat)
    return path, _two_sided(sample_as_interpolated(path), exact, closed=False)


def _cam_contour(design: ParallelDesign, g: _CamGeometry, tool_radius: float, fit_tol: float, flat: float
                 ) -> tuple[list[tuple[str, Path2D]], float]:
    """The contour's pieces (clockwise, from the dwell's middle; before rounding) and the biarc error."""
    ix = design.indexer
    out_path, e_out = _flank_biarcs(ix, g, g.out_tau, g.exact_out, tool_radius, fit_tol, flat)
    in_path, e_in = _flank_biarcs(ix, g, g.in_tau, g.exact_in, tool_radius, fit_tol, flat)
    am = 0.5 * (g.dwell_a0 + g.dwell_a1)
    entry = g.dwell_radius * np.exp(1j * am)
    pieces = [
        ("dwell arc", _element(entry, out_path.start[0], 0j, False)),
        ("outgoing flank", out_path),
        ("lobe tip", _element(out_path.end[-1], in_path.start[0], g.tip, False)),
        ("incoming flank", in_path),
        ("dwell arc", _element(in_path.end[-1], entry, 0j, False)),
    ]
    return pieces, max(e_out, e_in)


def _lead_arcs(entry: complex, tangent: complex, clockwise: bool, r: float) -> tuple[Path2D, Path2D]:
    """Tangent quarter circles of radius ``r`` outside the contour, into and out of ``entry``."""
    outward = 1j * tangent if clockwise else -1j * tangent
    centre = entry + r * outward
    ccw = bool((np.conj(-1j * outward) * tangent).real > 0)
    return (_element(centre - r * tangent, entry, centre, ccw), _element(entry, centre + r * tangent, centre, ccw))


def _plate_thickness(body: IndexerBody, k: int) -> float:
    for prism in body.geometry.prisms:
        if prism.role == f"cam{k}":
            return float(prism.z1 - prism.z0)
    raise ValueError(f"the body has no plate cam{k}")


def _check_positive(name: str, value: float) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) \
            or not math.isfinite(value) or value <= 0:
        raise SpecError(name, f"must be a finite number > 0, got {value!r}")
    return float(value)


# ---- the programs -------------------------------------------------------------------------------

def indexer_programs(design: ParallelDesign, body: IndexerBody, tool_radius: float, *, depth: float | None = None,
                     feed: float = 300.0, tolerance: float = 1e-3, spindle_rpm: float = 3000.0,
                     tool_number: int = 1, safe_height: float = 5.0, lead_radius: float | None = None,
                     climb: bool = True) -> list[IndexerProgram]:
    """One XY finishing-contour program per cam plate of ``design`` (its ``body`` from
    :func:`~cam_workbench.generators.bodies.indexing.parallel_body.indexer_body`), see the module
    docstring.  ``tool_radius``, ``depth`` (default: the plate thickness), ``tolerance``,
    ``safe_height``, ``lead_radius`` (default the tool radius) in mm; ``feed`` in mm/min (plunges
    at a third of it); ``climb``: climb milling (clockwise with M3), else conventional.

    Raises:
        SpecError: ``machining.tool_radius`` — a tool whose radius is not below the profile's
            smallest concave radius of curvature (or not > 0); ``machining.chord_tolerance`` — a
            tolerance too small for 4-decimal coordinates; ``machining.depth``,
            ``machining.feed_rate``, ``machining.safe_height``, ``machining.lead_radius``,
            ``machining.spindle_rpm`` — not > 0 (the lead arcs also when they would leave the
            dwell)."""
    if len(body.loops) != len(design.cams):
        raise ValueError(f"the body has {len(body.loops)} cams, the design {len(design.cams)}")
    rt = _check_positive("machining.tool_radius", tool_radius)
    tol = _check_positive("machining.chord_tolerance", tolerance)
    feed = _check_positive("machining.feed_rate", feed)
    _check_positive("machining.spindle_rpm", spindle_rpm)
    safe = _check_positive("machining.safe_height", safe_height)
    lead = rt if lead_radius is None else _check_positive("machining.lead_radius", lead_radius)
    if depth is not None:
        _check_positive("machining.depth", depth)
    budget = (1.0 - BLEND_SHARE) * tol
    flat = FLAT_ARC * tol
    fit_tol0 = budget - ROUNDING_RESERVE - flat
    if fit_tol0 < 0.25 * tol:
        need = (ROUNDING_RESERVE / (1.0 - BLEND_SHARE - FLAT_ARC - 0.25))
        raise SpecError("machining.chord_tolerance",
                        f"{tol:g} mm leaves too little for the biarcs once 4-decimal coordinates take "
                        f"{ROUNDING_RESERVE:.3g} mm: use at least {need:.2g} mm")
    programs = []
    for k in range(len(design.cams)):
        conc, at = smallest_concave_radius(design, k)
        if rt >= conc:
            raise SpecError("machining.tool_radius",
                            f"{rt:g} mm cannot cut cam {k}: its profile's smallest concave radius of curvature is "
                            f"{conc:.6g} mm (at input angle {math.degrees(at % TWO_PI):.2f} deg): use a tool radius "
                            f"< {conc:.6g} mm")
        g = _cam_geometry(design, k, rt)
        half = 0.5 * (g.dwell_a1 - g.dwell_a0)
        if math.atan2(lead, g.dwell_radius + lead) >= half:
            raise SpecError("machining.lead_radius", f"{lead:g} mm: the lead arcs would leave cam {k}'s dwell arc")
        fit_tol = fit_tol0
        for _ in range(6):
            raw, biarc_err = _cam_contour(design, g, rt, fit_tol, flat)
            if not climb:
                raw = [(label, reverse_path(p)) for label, p in reversed(raw)]
            pieces = [(label, as_written(p)) for label, p in raw]
            loop = _concat([p for _, p in pieces])
            path_err = _two_sided(sample_as_interpolated(loop), g.exact_loop, closed=True)
            if path_err <= budget:
                break
            fit_tol *= 0.6
        else:
            raise SolveError(f"cam {k}: the written contour stays {path_err:.3g} mm from the tool-centre path, "
                             f"above {budget:.3g} mm")
        entry = loop.start[0]
        tangent = 1j * entry / abs(entry) * (-1.0 if climb else 1.0)
        lead_in, lead_out = (as_written(p) for p in _lead_arcs(entry, tangent, climb, lead))
        f_in, f_out = body.fits[k]
        prog = IndexerProgram(
            cam=k, name=f"cam{k}.nc", text="", pieces=tuple(pieces), lead_in=lead_in, lead_out=lead_out,
            tool_radius=rt, dwell_radius=g.dwell_radius, tip=g.tip, biarc_error=biarc_err, path_error=path_err,
            flank_fit_error=float(max(f_in.error, f_out.error)), min_concave_radius=conc, tolerance=tol,
            blend=BLEND_SHARE * tol, depth=float(depth) if depth is not None else _plate_thickness(body, k),
            clockwise=bool(climb))
        text = _program_text(design, body, prog, feed=feed, spindle_rpm=spindle_rpm, tool_number=int(tool_number),
                             safe_height=safe, lead_radius=lead)
        programs.append(IndexerProgram(**{**prog.__dict__, "text": text}))
    return programs


def _move(path: Path2D, i: int) -> str:
    """One G1/G2/G3 block of a written (rounded) element: I, J from its written start."""
    d = DECIMALS
    end = path.end[i]
    xy = f"X{fmt(end.real, d)} Y{fmt(end.imag, d)}"
    if not path.is_arc[i]:
        return f"G1 {xy}"
    ij = path.center[i] - path.start[i]
    return f"{'G3' if path.ccw[i] else 'G2'} {xy} I{fmt(ij.real, d)} J{fmt(ij.imag, d)}"


def _program_text(design: ParallelDesign, body: IndexerBody, p: IndexerProgram, *, feed: float,
                  spindle_rpm: float, tool_number: int, safe_height: float, lead_radius: float) -> str:
    ix = design.indexer
    d = DECIMALS
    n_c = len(design.cams)
    rr = float(ix.roller_radius)
    beta = math.degrees(float(ix.index_angle))
    loop = p.loop
    arcs = int(np.count_nonzero(loop.is_arc))
    w = GcodeWriter(False)
    w.comment(f"cam_workbench {__version__}: parallel indexer cam {p.cam} of {n_c}, XY finishing contour")
    w.comment(f"indexer: N = {int(ix.stations)} stations, beta = {beta:.6g} deg index angle, law {ix.law}, "
              f"C = {float(ix.centre_distance):.6g} mm, R_p = {float(ix.pitch_radius):.6g} mm, r_r = {rr:.6g} mm, "
              f"{n_c} cams, index start {math.degrees(float(ix.index_start)):.6g} deg")
    w.comment(f"cam {p.cam}: plate {_plate_thickness(body, p.cam):g} mm thick, cut alone from its own blank in the "
              "cam frame at input angle 0: origin on the input axis, +X towards the turret axis, Z0 on the top face")
    w.comment(f"tool T{tool_number}: radius {p.tool_radius:g} mm; tool centre = the profile offset outward by "
              f"{p.tool_radius:g} mm; no cutter compensation; smallest concave profile radius "
              + (f"{p.min_concave_radius:.6g} mm" if math.isfinite(p.min_concave_radius) else "none [convex]"))
    w.comment(f"dwell: exact arc of radius {p.dwell_radius:.6g} mm = r_d - r_r + tool radius about the origin, "
              f"{360.0 - beta:.6g} deg")
    w.comment(f"lobe tip X' = [{fmt(p.tip.real, d)}, {fmt(p.tip.imag, d)}]: the tool rolls round the corner on an "
              f"arc of the tool radius {p.tool_radius:g} mm about it")
    w.comment(f"flanks: G02/G03 biarcs, measured biarc error {p.biarc_error:.3g} mm against the analytic "
              f"tool-centre offset L + [tool radius - r_r]*n of the flank from the law, not against the body's "
              f"B-spline flank")
    w.comment(f"flank fit error {p.flank_fit_error:.3g} mm: the body's B-spline flanks [DXF, STEP] from the "
              f"profile L - r_r*n")
    w.comment(f"path: {loop.n} moves [{arcs} arcs, {loop.n - arcs} lines], as written [{d} decimals] max distance "
              f"{p.path_error:.3g} mm from the analytic tool-centre path, tolerance {p.tolerance:g} mm "
              f"[G64 P{fmt(p.blend, d + 1)} blending on top]")
    w.comment(f"{'climb' if p.clockwise else 'conventional'} milling, "
              f"{'clockwise' if p.clockwise else 'counter-clockwise'}, entry at the middle of the dwell on lead arcs "
              f"of radius {lead_radius:g} mm; 1 pass to depth {p.depth:g} mm")
    w.block("G21 G90 G17 G40 G49 G80 G94 G91.1")
    w.block("G54")
    w.block(f"G64 P{fmt(p.blend, d + 1)}")
    w.block(f"T{tool_number} M6")
    w.block(f"G43 H{tool_number}")
    w.block(f"S{fmt(spindle_rpm, 1)} M3")
    safe = fmt(safe_height, d)
    start = p.lead_in.start[0]
    w.block(f"G0 Z{safe}")
    w.comment(f"pass 1 of 1 at Z{fmt(-p.depth, d)}")
    w.block(f"G0 X{fmt(start.real, d)} Y{fmt(start.imag, d)}")
    w.block(f"G1 Z{fmt(-p.depth, d)} F{fmt(feed / 3.0, 3)}")
    w.comment("lead-in")
    w.block(_move(p.lead_in, 0) + f" F{fmt(feed, 3)}")
    for label, piece in p.pieces:
        w.comment(f"contour: {label}")
        for i in range(piece.n):
            w.block(_move(piece, i))
    w.comment("lead-out")
    w.block(_move(p.lead_out, 0))
    w.block(f"G0 Z{safe}")
    w.block("M5")
    w.block("M30")
    return w.text()


def write_indexer_programs(design: ParallelDesign, body: IndexerBody, folder: str | os.PathLike[str],
                           tool_radius: float, **options: Any) -> list[IndexerProgram]:
    """Write :func:`indexer_programs` (``options`` its keywords) to ``folder``/``cam0.nc``,
    ``cam1.nc``, … each atomically (temporary file, then rename); all are made before any is
    written.  Returns the programs (their ``name`` the file's)."""
    programs = indexer_programs(design, body, tool_radius, **options)
    out = Path(folder)
    for p in programs:
        write_text_atomic(out / p.name, p.text)
    return programs


__all__ = ["DECIMALS", "IndexerProgram", "ROUNDING_RESERVE", "as_written", "indexer_programs", "polyline_distance",
           "sample_as_interpolated", "smallest_concave_radius", "tool_centre_offset", "write_indexer_programs"]

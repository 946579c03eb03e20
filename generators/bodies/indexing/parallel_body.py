"""The parallel indexer's cams as a body: each plate's profile as a closed loop of exact and fitted
pieces, the plates stacked on the input shaft and joined by a spacer into one solid (plain data,
:mod:`..base`, which every kernel adaptor builds).

Each profile (:mod:`.parallel`, cam frame, mm) is three pieces, counter-clockwise:

* the dwell part, an exact circular arc about the input axis of radius r_d − r_r, sweeping
  2π − β (the cam turns through it while the roller is held still);
* the two flanks — the inward offsets by r_r of the outgoing and incoming rollers' loci — as
  clamped cubic B-splines in the locus parameter τ, interpolating the exact offset points at
  uniform τ nodes with the exact end tangents Q'(τ); the node count doubles until the spline is
  within ``tolerance`` of the exact offset at 31 points of every knot span (the error
  measured, not assumed: :attr:`IndexerBody.fit_error`).  A flank is not a rational curve for
  the trade's laws (its points involve sin and cos of the law), so it is fitted, like the plate
  cams' B-spline pitch option, not offset exactly;
* the flanks meet at the lobe tip X' (a corner), which both interpolate.

Plates: cam k spans z_k ≤ z ≤ z_k + t with z_k = −(n_c − 1 − k)·(t + g) (t ``thickness``, g ``gap``:
the last plate's top face at z = t, as a plate cam's), less the bore; with a gap the plates are joined by a spacer disc of radius ``spacer_radius`` (default:
90 % of the smallest profile radius) through the bore, so the cams are one solid.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...curves.basis import interpolating_cubic
from ...curves.nurbs import NurbsCurve
from ...errors import SpecError
from ..base import Arc, BodyGeometry, Curve, Loop, Prism
from .parallel import TWO_PI, ParallelDesign, ParallelIndexer, locus

Array = np.ndarray
#: the flanks' fit: the first node count, the most, and the default tolerance [mm]
_FIRST_NODES, _MOST_NODES = 16, 4096
DEFAULT_TOLERANCE = 1e-4
#: how far inside a flank its end tangents are taken [rad per rad of the flank's τ range]
_END_NUDGE = 1e-9
#: where in each knot span the fit is measured (an interpolating cubic's error is a smooth bump
#: between its nodes: 31 points find its top to well under 1 % of its height)
_CHECK = np.linspace(0.0, 1.0, 33)[1:-1]


def offset_point(ix: ParallelIndexer, cam: int, tau: Array) -> tuple[Array, Array]:
    """The profile's exact point Q(τ) = L(τ) − r_r·n(τ) [mm] and Q'(τ) = L'(τ)·(1 − r_r/ρ(τ))
    (ρ the pitch curve's signed radius, convex +: an inward offset of a convex arc is shorter)."""
    loc = locus(ix, cam, tau)
    rr = float(ix.roller_radius)
    q = loc["point"] - rr * loc["normal"]
    dq = loc["d1"] * (1.0 - rr / loc["rho"])[..., None]
    return q, dq


@dataclass(frozen=True)
class FlankFit:
    """One flank's fitted B-spline (τ increasing) and its measured largest distance [mm] from
    the exact offset at the check points (31 in every knot span)."""

    curve: NurbsCurve
    error: float
    nodes: int


def fit_flank(ix: ParallelIndexer, cam: int, tau0: float, tau1: float,
              tolerance: float = DEFAULT_TOLERANCE) -> FlankFit:
    """The clamped cubic through Q at uniform τ nodes on [tau0, tau1] with Q' at the ends, the
    nodes doubled until within ``tolerance`` [mm] (SpecError naming ``indexer.fit_tolerance`` when
    even the most nodes do not reach it)."""
    n = _FIRST_NODES
    # the end tangents one-sided, from inside the flank: at a flank's end the law's acceleration may
    # jump (a harmonic law at the index's ends), and the end's τ may round to the dwell's side
    inside = _END_NUDGE * max(1.0, abs(tau1 - tau0))
    _, dq_ends = offset_point(ix, cam, np.array([tau0 + inside, tau1 - inside]))
    while True:
        x = np.linspace(tau0, tau1, n + 1)
        q, _ = offset_point(ix, cam, x)
        knots, coef = interpolating_cubic(x, q, dq_ends[0], dq_ends[1])
        curve = NurbsCurve(3, knots, coef, np.ones(coef.shape[0]))
        check = (x[:-1, None] + np.diff(x)[:, None] * _CHECK[None, :]).ravel()
        exact, _ = offset_point(ix, cam, check)
        err = float(np.max(np.hypot(*(curve.evaluate(check) - exact).T)))
        if err <= tolerance:
            return FlankFit(curve, err, n + 1)
        if n >= _MOST_NODES:
            raise SpecError("indexer.fit_tolerance", f"the flank of cam {cam} is {err:.3g} mm from its B-spline with "
                            f"{n + 1} nodes, above {tolerance:g} mm — raise the tolerance")
        n *= 2


@dataclass(frozen=True)
class IndexerBody:
    """The cams as plain data: ``geometry`` (prisms, in order), each cam's ``loops`` (counter-
    clockwise) and its flanks' ``fits``, the largest ``fit_error`` [mm], the ``spacer_radius``."""

    geometry: BodyGeometry
    loops: tuple[Loop, ...]
    fits: tuple[tuple[FlankFit, FlankFit], ...]
    fit_error: float
    spacer_radius: float | None

    @property
    def volume(self) -> float:
        """The body's exact volume from its pieces [mm³] (arcs in closed form, the fitted flanks by
        Gauss quadrature)."""
        return self.geometry.volume


def cam_loop(design: ParallelDesign, cam: int, tolerance: float = DEFAULT_TOLERANCE) -> tuple[Loop, FlankFit, FlankFit]:
    """Cam ``cam``'s profile as a counter-clockwise loop: the outgoing flank, the dwell arc and the
    incoming flank (each reversed from the τ order, which runs clockwise)."""
    ix = design.indexer
    c = design.cams[cam]
    ts, beta = float(ix.index_start), float(ix.index_angle)
    dwell_in, dwell_out = ts - TWO_PI + beta, ts            # the dwell piece's τ range
    incoming = fit_flank(ix, cam, c.tip_tau[0], dwell_in, tolerance)
    outgoing = fit_flank(ix, cam, dwell_out, c.tip_tau[1], tolerance)
    q_start, _ = offset_point(ix, cam, np.array([dwell_out]))
    radius = float(c.dwell_radius) - float(ix.roller_radius)
    a0 = math.atan2(float(q_start[0, 1]), float(q_start[0, 0]))
    arc = Arc(0j, radius, a0, a0 + (TWO_PI - beta))
    loop = Loop((Curve(outgoing.curve.reversed()), arc, Curve(incoming.curve.reversed())), role="profile")
    return loop, incoming, outgoing


def indexer_body(design: ParallelDesign, thickness: float, gap: float = 0.0, bore_diameter: float = 0.0,
                 spacer_radius: float | None = None, tolerance: float = DEFAULT_TOLERANCE) -> IndexerBody:
    """The cams of ``design`` as one body [mm]: plate k at z ∈ [z_k, z_k + t], z_k = −(n_c − 1 − k)·(t + g),
    less the bore, joined by a spacer across each gap (see the module docstring).

    Raises:
        SpecError: a size that leaves no material (naming ``cam.thickness``, ``indexer.gap``,
            ``cam.bore_diameter`` or ``indexer.spacer_diameter``)."""
    if not (math.isfinite(thickness) and thickness > 0):
        raise SpecError("cam.thickness", f"must be > 0, got {thickness!r}")
    if not (math.isfinite(gap) and gap >= 0):
        raise SpecError("indexer.gap", f"must be ≥ 0, got {gap!r}")
    loops, fits = [], []
    for k in range(len(design.cams)):
        loop, f_in, f_out = cam_loop(design, k, tolerance)
        loops.append(loop)
        fits.append((f_in, f_out))
    r_min = min(float(np.min(np.hypot(*c.profile.T))) for c in design.cams)
    r_bore = bore_diameter / 2
    if not (0 <= r_bore < r_min):
        raise SpecError("cam.bore_diameter", f"must be < the cams' smallest diameter {2 * r_min:.6g} mm, "
                        f"got {bore_diameter!r}")
    spacer = None
    if gap > 0:
        spacer = 0.9 * r_min if spacer_radius is None else float(spacer_radius)
        if not (r_bore < spacer < r_min):
            raise SpecError("indexer.spacer_diameter", f"must lie between the bore {bore_diameter:g} mm and the cams' "
                            f"smallest diameter {2 * r_min:.6g} mm, got {2 * spacer:.6g} mm")
    holes = (Loop.circle(r_bore, role="bore"),) if r_bore > 0 else ()
    prisms = []
    for k, loop in enumerate(loops):
        z0 = (k - (len(loops) - 1)) * (thickness + gap)
        prisms.append(Prism(loop, holes, z0, z0 + thickness, "add", f"cam{k}"))
        if spacer is not None and k + 1 < len(loops):
            prisms.append(Prism(Loop.circle(spacer, role="spacer"), holes, z0 + thickness, z0 + thickness + gap,
                                "add", f"spacer{k}"))
    error = max(max(a.error, b.error) for a, b in fits)
    extra = {"fit_error": error, "fit_tolerance": tolerance,
             "flank_nodes": [[a.nodes, b.nodes] for a, b in fits]}
    return IndexerBody(BodyGeometry("parallel_indexer", tuple(prisms), extra), tuple(loops), tuple(fits), error, spacer)

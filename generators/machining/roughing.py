"""Roughing a plate cam from a round blank (``machining.blank_diameter``), as plain geometry (the
G-code is made in ``cam_workbench.exporters.gcode_roughing``).

Concentric passes: pass k's tool centre runs on the **level set at distance
d_k = R_t + a + k·s from the profile** (R_t the tool radius, a = ``finish_allowance``,
s = ``stepover`` × 2R_t, k = 0, 1, …), so the last rough pass (k = 0) leaves exactly the
allowance for the finishing contour.  The level set is the exact offset of the pitch curve
outward by d_k − r (:func:`cam_workbench.generators.machining.toolpath.tool_centre_curve`:
a rational NURBS for a PH pitch curve) with its swallowtails trimmed: where a concave part of
the profile is tighter than d_k the raw offset loops back on itself, and the level set keeps
the outermost crossing (the self-intersection point).  It is followed by G01 chords within
0.85 × ``chord_tolerance`` of the exact offset.

Each pass is clipped to the circle of radius r_blank + R_t (where the tool just touches the
blank): the parts of the level set beyond it would cut air and are replaced by G02/G03 arcs
on that circle; a pass wholly beyond it is left out.  Passes are emitted while some part of
the level set lies inside that circle, so every point of the blank at a distance > a from the
profile lies within R_t of a pass (the bands [d_k − R_t, d_k + R_t] overlap because
s ≤ 2R_t, and the first pass left out lies wholly outside the blank).

Every pass starts on the **entry ray** (from the cam axis through the pitch point of the finishing
contour's entry junction, the middle of the longest dwell); at each depth the tool plunges outside the
blank on that ray (at r_blank + R_t + ``lead_radius``), feeds in along the ray to the
outermost pass, and steps in along the ray from one pass to the next.  The level sets must be
star-shaped about the cam axis (a ray from the axis meets each once) — true of a cam's
offsets in practice; otherwise a ``GeometryError``.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..cam_design import CamDesign
from ..curves.approx import Path2D, flatten
from ..errors import GeometryError, SpecError, fmt_apart
from .plan import MachiningPlan
from .toolpath import FIT_MARGIN, entry_junction, reverse_path, tool_centre_curve

#: default finish allowance per unit system
ALLOWANCE_DEFAULT = {"mm": 0.2, "in": 0.008}
#: default step-over [fraction of the tool diameter]
STEPOVER_DEFAULT = 0.5
#: most roughing passes per depth level
MAX_ROUGH_PASSES = 500


@dataclass(frozen=True)
class RoughingPass:
    """One concentric roughing pass (cam frame = machine XY, spec units).

    Attributes:
        offset: distance of the tool centre from the profile, R_t + a + k·s.
        loop: closed chain in cutting order, starting and ending on the entry ray: G01 chords of
            the level set, G02/G03 arcs where it is clipped to the blank circle.
        clipped: part of the pass runs on the blank circle (the level set leaves the blank there).
    """

    offset: float
    loop: Path2D
    clipped: bool


@dataclass(frozen=True)
class RoughingPath:
    """The roughing passes of one depth level, outermost first, and how they are entered.

    Attributes:
        blank_radius: r_blank.
        stepover: s (length).
        allowance: a.
        passes: outermost first; the last one at R_t + a.
        approach: plunge point on the entry ray, r_blank + R_t + lead radius from the axis.
        entry_angle_deg: polar angle of the entry ray [deg].
        clockwise: every pass runs clockwise (climb milling with M3).
        tolerance: the chord tolerance the chords meet (fitted to 0.85 × of it).
        z_levels: depth of each level (negative).
    """

    blank_radius: float
    stepover: float
    allowance: float
    passes: tuple[RoughingPass, ...]
    approach: complex
    entry_angle_deg: float
    clockwise: bool
    tolerance: float
    z_levels: np.ndarray

    @property
    def level_length(self) -> float:
        """Feed length of one depth level: in-feed along the ray, the passes and the step-ins."""
        return float(sum(p.loop.length for p in self.passes) + abs(self.approach - self.passes[0].loop.start[0])
                     + sum(abs(a.loop.start[0] - b.loop.start[0]) for a, b in zip(self.passes, self.passes[1:])))

    @property
    def level_blocks(self) -> int:
        """Motion blocks at feed of one depth level (plunge, in-feed, passes, step-ins)."""
        return int(2 + sum(p.loop.n for p in self.passes) + len(self.passes) - 1)

    def summary(self) -> dict[str, Any]:
        """Numbers for report.json (spec units, degrees)."""
        return {"blank_diameter": 2 * self.blank_radius, "stepover": self.stepover,
                "finish_allowance": self.allowance, "passes_per_level": len(self.passes),
                "offsets": [p.offset for p in self.passes], "clipped_passes": sum(p.clipped for p in self.passes),
                "moves_per_level": sum(p.loop.n for p in self.passes), "length_per_level": self.level_length,
                "levels": int(self.z_levels.shape[0]), "entry_at_deg": self.entry_angle_deg,
                "chord_tolerance": self.tolerance, "clockwise": self.clockwise}


def finish_allowance(design: CamDesign) -> float:
    """``machining.finish_allowance`` or its default (0.2 mm, 0.008 in)."""
    mc = design.spec.machining
    return float(mc.finish_allowance if mc.finish_allowance is not None else ALLOWANCE_DEFAULT[design.spec.units])


def roughing_path(design: CamDesign, plan: MachiningPlan) -> RoughingPath:
    """The roughing passes of ``design`` from ``machining.blank_diameter`` (module docstring).

    Raises:
        SpecError: ``machining.blank_diameter`` — absent, or the blank does not hold the profile
            plus the allowance; ``machining.stepover`` — more than :data:`MAX_ROUGH_PASSES` passes.
        GeometryError: ``roughing`` — a level set is not star-shaped about the cam axis.
    """
    mc = design.spec.machining
    if mc.blank_diameter is None:
        raise SpecError("machining.blank_diameter", "roughing needs the blank's diameter")
    r_blank = 0.5 * mc.blank_diameter
    a = finish_allowance(design)
    tool = plan.tool_radius
    fraction = mc.stepover if mc.stepover is not None else STEPOVER_DEFAULT
    step = fraction * 2 * tool
    _, prof = design.profile.sample(64)
    r_max = float(np.max(np.hypot(prof[:, 0], prof[:, 1])))
    r_min = float(np.min(np.hypot(prof[:, 0], prof[:, 1])))
    if not r_blank > r_max + a:
        need = 2 * (r_max + a)
        raise SpecError("machining.blank_diameter",
                        f"must be > 2 × (largest profile radius {r_max:.6g} + machining.finish_allowance {a:g}) = "
                        f"{fmt_apart(need, mc.blank_diameter)}: the blank must hold the cam, got "
                        f"{fmt_apart(mc.blank_diameter, need)}")
    n_est = int(np.ceil((r_blank - r_min - a) / step))
    if n_est > MAX_ROUGH_PASSES:
        raise SpecError("machining.stepover", f"{fraction:g} × the tool diameter gives about {n_est} roughing "
                        f"passes per level, more than {MAX_ROUGH_PASSES}: a larger step-over or a smaller blank")
    psi = _entry_angle(design)
    ray = np.exp(1j * psi)
    clockwise = plan.milling == "climb"
    limit = r_blank + tool                      # the tool centre where the tool just touches the blank
    passes: list[RoughingPass] = []
    for k in range(n_est + 2):
        d = tool + a + k * step
        pts = _level_set(design, plan, d)
        if np.min(np.abs(pts)) >= limit:
            break
        loop, clipped = _clip_to_circle(_start_on_ray(pts, psi), limit)
        passes.append(RoughingPass(offset=d, loop=reverse_path(loop) if clockwise else loop, clipped=clipped))
    return RoughingPath(blank_radius=r_blank, stepover=step, allowance=a, passes=tuple(reversed(passes)),
                        approach=(limit + plan.lead_radius) * ray, entry_angle_deg=float(np.rad2deg(psi)),
                        clockwise=clockwise, tolerance=plan.chord_tolerance, z_levels=plan.z_levels)


def _entry_angle(design: CamDesign) -> float:
    """Polar angle [rad] of the pitch curve's entry junction (the finishing contour's entry lies
    on the same normal; the ray through the pitch point is what the passes share)."""
    k = entry_junction(design.pitch)
    p = design.pitch_nurbs.evaluate(np.array([float(design.pitch.junction_parameters[k])]))
    return float(np.angle(complex(p[0, 0], p[0, 1])))


def _level_set(design: CamDesign, plan: MachiningPlan, distance: float) -> np.ndarray:
    """Closed polyline (first = last, counter-clockwise about the axis) of the points at
    ``distance`` from the profile: chords of the exact offset with its swallowtails trimmed.

    Raises:
        GeometryError: ``roughing`` — the level set is not star-shaped about the cam axis.
    """
    curve = tool_centre_curve(design, dataclasses.replace(plan, tool_radius=distance))
    _, pts = flatten(curve, FIT_MARGIN * plan.chord_tolerance)
    ring = pts[:-1]
    if np.sum((np.conj(ring) * np.roll(ring, -1)).imag) < 0:
        ring = ring[::-1]
    ring = np.roll(ring, -int(np.argmax(np.abs(ring))))     # the farthest point is on the level set
    for _ in range(ring.shape[0]):
        phi = np.unwrap(np.angle(np.append(ring, ring[0])))
        back = np.nonzero(np.diff(phi) <= 0)[0]
        if back.size == 0:
            break
        ring = _cut_swallowtail(ring, phi, int(back[0]))
    phi = np.unwrap(np.angle(np.append(ring, ring[0])))
    if np.any(np.diff(phi) <= 0) or abs(phi[-1] - phi[0] - 2 * np.pi) > 1e-9:
        raise GeometryError("roughing", f"the roughing pass {distance:g} from the profile is not star-shaped "
                                        "about the cam axis (a ray from the axis meets it more than once)")
    return np.append(ring, ring[0])


def _cut_swallowtail(ring: np.ndarray, phi: np.ndarray, j: int) -> np.ndarray:
    """``ring`` (closed implicitly) without the loop around the backward segment ``j``: the
    forward branch before it and the one after it cross; keep the crossing point."""
    n = ring.shape[0]
    pts = np.append(ring, ring[0])
    end = j
    while end + 1 < n and phi[end + 2] <= phi[end + 1]:
        end += 1
    lo_phi, hi_phi = phi[j + 1:end + 2].min(), phi[j:end + 1].max()
    i0 = j
    while i0 > 0 and phi[i0] > lo_phi:
        i0 -= 1
    i1 = end + 1
    while i1 < n and phi[i1] < hi_phi:
        i1 += 1
    before = np.arange(i0, j)                   # segments k: pts[k] → pts[k + 1]
    after = np.arange(end + 1, min(i1 + 1, n))
    a0, a1 = pts[before][:, None], pts[before + 1][:, None]
    b0, b1 = pts[after][None, :], pts[after + 1][None, :]
    da, db = a1 - a0, b1 - b0
    den = (np.conj(da) * db).imag
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (np.conj(b0 - a0) * db).imag / den
        u = (np.conj(b0 - a0) * da).imag / den
    hit = (den != 0) & (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1)
    if not hit.any():
        raise GeometryError("roughing", "a roughing pass loops back on itself without crossing "
                                        "(the offset is not star-shaped about the cam axis)")
    ia, ib = np.nonzero(hit)
    m = int(np.argmin(after[ib] - before[ia]))      # the innermost crossing closes the loop
    ka, kb = int(before[ia[m]]), int(after[ib[m]])
    x = a0[ia[m], 0] + t[ia[m], ib[m]] * da[ia[m], 0]
    return np.concatenate([ring[:ka + 1], [x], ring[kb + 1:]])


def _start_on_ray(pts: np.ndarray, psi: float) -> np.ndarray:
    """The closed star-shaped polyline ``pts`` re-started where it crosses the ray at angle ψ."""
    ring = pts[:-1]
    rel = np.mod(np.angle(ring) - psi, 2 * np.pi)
    k = int(np.argmin(rel))                     # first vertex at or after the ray
    ring = np.roll(ring, -k)
    prev, first = ring[-1], ring[0]
    if np.mod(np.angle(first) - psi, 2 * np.pi) == 0.0:
        start = first
    else:
        ray = np.exp(1j * psi)
        d = first - prev
        t = (np.conj(prev) * ray).imag / (np.conj(d) * ray).imag * -1.0
        start = prev + t * d
        ring = np.concatenate([[start], ring])
    return np.append(ring, start)


def _clip_to_circle(pts: np.ndarray, radius: float) -> tuple[Path2D, bool]:
    """The closed counter-clockwise polyline ``pts`` with its stretches beyond ``radius`` replaced
    by counter-clockwise arcs of that circle (centre: the axis); (path, anything clipped)."""
    a, b = pts[:-1], pts[1:]
    a_in, b_in = np.abs(a) < radius, np.abs(b) < radius
    if a_in.all() and b_in.all():
        n = a.shape[0]
        return Path2D(a, b, np.full(n, np.nan + 0j), np.zeros(n, bool), np.zeros(n), np.zeros(n)), False
    # crossing parameter of each segment with the circle: |a + t(b − a)| = radius
    d = b - a
    qa = np.abs(d) ** 2
    qb = 2 * (np.conj(a) * d).real
    qc = np.abs(a) ** 2 - radius**2
    root = np.sqrt(np.maximum(qb**2 - 4 * qa * qc, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        t_out = (-qb + root) / (2 * qa)        # leaving the disk (larger root)
        t_in = (-qb - root) / (2 * qa)         # entering it
    exits = np.nonzero(a_in & ~b_in)[0]
    entries = np.nonzero(~a_in & b_in)[0]
    x_out = a + t_out * d
    x_in = a + t_in * d
    start_on = radius * a[0] / abs(a[0])
    # each segment k gives [an arc on the circle up to where it enters the disk, its part inside]
    prev_exit = np.searchsorted(exits, entries) - 1
    arc_from = np.where(prev_exit >= 0, x_out[exits[np.maximum(prev_exit, 0)]], start_on)
    n = a.shape[0]
    has_arc = np.zeros(n, bool)
    has_arc[entries] = True
    arc_start = np.zeros(n, complex)
    arc_start[entries] = arc_from
    has_line = a_in | b_in
    line_start = np.where(a_in, a, x_in)
    line_end = np.where(b_in, b, x_out)
    nan = np.full(n, np.nan + 0j)
    starts = np.column_stack([arc_start, line_start]).ravel()
    ends = np.column_stack([x_in, line_end]).ravel()
    centres = np.column_stack([np.zeros(n, complex), nan]).ravel()
    keep = np.column_stack([has_arc, has_line]).ravel()
    starts, ends, centres = starts[keep], ends[keep], centres[keep]
    if not b_in[-1]:                             # ends beyond the circle: close on it
        last = x_out[exits[-1]] if exits.size else start_on
        starts = np.append(starts, last)
        ends = np.append(ends, radius * b[-1] / abs(b[-1]))
        centres = np.append(centres, 0j)
    arc = ~np.isnan(centres.real)
    keep = ~arc | (np.abs(ends - starts) > 0)    # an arc from a point to itself is nothing
    m = int(keep.sum())
    return Path2D(starts[keep], ends[keep], centres[keep], arc[keep], np.zeros(m), np.zeros(m)), True

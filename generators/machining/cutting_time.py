"""Machining time of a cam: the thesis' cutting-time model and the time of this project's
own XY G-code contour.

**The thesis' model** (Teoh 1989, §4.1, Eq. 4.4–4.20).  The curve is the thesis' "cam
profile" of Eq. 4.5–4.6: the point at cam angle θ lies at radius r = R_b + s(θ) and polar
angle b + θ in the machine's XY frame (b = the blank's orientation, thesis B(3)) — the pitch
curve of a radial follower; neither the roller, the offset nor the tool radius enters.  The
tool path is a staircase of moves parallel to the machine axes, entirely outside the curve:

* every rise, dwell and return is cut on its own, from its start to its end (§4.1.1), split
  into sections at the points where dX/dθ or dY/dθ vanishes, so that X and Y are monotonic
  in each section;
* in a section of positive slope dY/dX (Fig. 4.3a) the tool, on the curve at (X₀, Y₀),
  moves along X to the ε-offset curve (r + ε)(cos, sin)(b + θ) at the same Y (Eq. 4.4:
  (r(u) + ε)·sin θ(u) = Y₀), then along Y back onto the curve (Eq. 4.7: r(u)·cos θ(u) = X₁);
  a section of negative slope moves along Y first (Eq. 4.17–4.18);
* a section ends with one move along each axis onto its end point when the next step would
  pass it.

The thesis' Eq. 4.11 and 4.16 print the corner as X₁ = r(u)·cos θ(u) — the curve's own X at
the parameter solving Eq. 4.4; taken literally the second solve (Eq. 4.7) returns the same
u and the corners sit inside the tolerance band by ε·|sin|, which needs ~30× the thesis'
turn counts.  With the corner on the offset curve, X₁ = (r(u) + ε)·cos θ(u), the model gives
the thesis' path lengths to 1e-3 in and its turn counts to 0.2–4 % (README).

    S = Σ |ΔX| + |ΔY|                    (Eq. 4.19)
    T = S / feed + t_turn · N_turns      (Eq. 4.20; t_turn = 0.4 s, Table 2)

Turns are counted as the moves of the closed path (collinear consecutive moves merged): every
move ends in a turn.  Curves are tabulated at ``samples`` equal steps of each segment's
parameter (u of a B-spline lift, θ otherwise) and inverted inside the
monotonic sections, by cubic Hermite interpolation (values and derivatives); 2 000 and 40 000
samples per segment give the same turns and S within 1e-4 (tests).

**The G-code contour time** (:func:`contour_time`): cutting length / feed plus a per-block time
for the XY program of :mod:`cam_workbench.generators.machining.toolpath` (lead arcs, contour, plunges; rapids excluded).
"""
from __future__ import annotations

from bisect import bisect_left
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..motion.laws import evaluate_law
from ..motion.program import MotionProgram
from ..spec.model import CamSpec
from .plan import machining_plan
from .roughing import RoughingPath, roughing_path
from .toolpath import contour_path

#: The thesis' tolerance (0.01 in) in each unit system.
DEFAULT_TOLERANCE = {"in": 0.01, "mm": 0.25}
DEFAULT_SAMPLES = 4000


@dataclass(frozen=True)
class StaircasePath:
    """The thesis' variable-step tool path and its cutting time.

    Attributes:
        vertices: (N+1,) corner points (complex, machine XY frame), closed (last = first).
        turns: N_t, the number of turns (moves of the closed path).
        length: S [length unit] (Eq. 4.19).
        time: T [s] (Eq. 4.20).
        feed: feed rate [length/s].
        tolerance: ε [length].
        turn_time: time per turn [s].
        orientation_deg: the blank's orientation b [deg].
    """

    vertices: np.ndarray
    turns: int
    length: float
    time: float
    feed: float
    tolerance: float
    turn_time: float
    orientation_deg: float

    def summary(self) -> dict[str, Any]:
        """Numbers for report.json."""
        return {"model": "thesis Eq. 4.4-4.20 (variable-step axis-parallel path, r = R_b + s)",
                "time_s": self.time, "turns": self.turns, "path_length": self.length,
                "feed_per_s": self.feed, "tolerance": self.tolerance, "turn_time_s": self.turn_time,
                "orientation_deg": self.orientation_deg,
                "feed_time_s": self.length / self.feed, "turns_time_s": self.turns * self.turn_time}


def polar_tables(program: MotionProgram, base_radius: float, samples: int = DEFAULT_SAMPLES
                 ) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """Per motion segment: (θ, dθ/dt, r, dr/dt) at ``samples`` equal steps of its parameter t
    (u of a B-spline lift, θ otherwise), r = R_b + s (thesis Eq. 4.5–4.6).  The step is
    (t_end − t_start)/(samples − 1): u_max or the span over samples − 1."""
    out = []
    for k in range(len(program.starts)):
        a, beta = program.starts[k], program.spans[k]
        curve = program.curves[k] if program.curves else None
        h = program.lifts[k]
        if curve is not None:
            u = np.linspace(0.0, curve.u_max, samples)
            th, yy = curve.parametric(u, 1)
            lift = abs(h)
            base = program.levels[k] if h > 0 else program.levels[k] - lift
            out.append((a + th[0], th[1], base_radius + base + lift * yy[0], lift * yy[1]))
        elif program.laws[k] is not None:
            theta = np.linspace(a, a + beta, samples)
            f, f1, _, _ = evaluate_law(program.laws[k], (theta - a) / beta)
            out.append((theta, np.ones(samples), base_radius + program.levels[k] + h * f, h * f1 / beta))
        else:
            theta = np.linspace(a, a + beta, samples)
            out.append((theta, np.ones(samples), np.full(samples, base_radius + program.levels[k]),
                        np.zeros(samples)))
    return out


class _Hermite:
    """Cubic Hermite interpolation of a tabulated curve (values and derivatives at equal
    parameter steps h) — inverse of one coordinate, then the others at that parameter; the error
    is O(h⁴), so the corners sit on the curve to ~1e-12 of its size with 4 000 samples."""

    def __init__(self, key: np.ndarray, dkey: np.ndarray, h: float):
        self.key = key.tolist()
        self.mono = np.maximum.accumulate(key).tolist()     # for the bracketing search only
        self.dkey = dkey.tolist()
        self.h = h

    def solve(self, v: float) -> tuple[int, float] | None:
        """(interval k, fraction s) with key(k + s) = v, or None beyond the table."""
        mono = self.mono
        k = bisect_left(mono, v)
        if k >= len(mono):
            return None
        if k == 0:
            return 0, 0.0
        k0 = k - 1
        x0, x1 = self.key[k0], self.key[k0 + 1]
        d0, d1 = self.dkey[k0] * self.h, self.dkey[k0 + 1] * self.h
        t = (v - x0) / (x1 - x0) if x1 != x0 else 1.0
        t = min(max(t, 0.0), 1.0)
        for _ in range(4):                              # Newton on the cubic
            t2, t3 = t * t, t * t * t
            f = (2 * t3 - 3 * t2 + 1) * x0 + (t3 - 2 * t2 + t) * d0 + (-2 * t3 + 3 * t2) * x1 + (t3 - t2) * d1 - v
            df = (6 * t2 - 6 * t) * x0 + (3 * t2 - 4 * t + 1) * d0 + (-6 * t2 + 6 * t) * x1 + (3 * t2 - 2 * t) * d1
            if df == 0.0:
                break
            t_new = min(max(t - f / df, 0.0), 1.0)
            if abs(t_new - t) < 1e-15:
                t = t_new
                break
            t = t_new
        return k0, t

    @staticmethod
    def value(vals: list[float], dvals: list[float], h: float, k: int, t: float) -> float:
        if k + 1 >= len(vals):
            return vals[-1]
        t2, t3 = t * t, t * t * t
        return ((2 * t3 - 3 * t2 + 1) * vals[k] + (t3 - 2 * t2 + t) * dvals[k] * h
                + (-2 * t3 + 3 * t2) * vals[k + 1] + (t3 - t2) * dvals[k + 1] * h)


class _Moves:
    """Axis-parallel moves, merged when consecutive moves run along the same axis and way."""

    def __init__(self, start: complex):
        self.start = start
        self.axis: list[int] = []
        self.delta: list[float] = []

    def add(self, axis: int, d: float) -> None:
        if d == 0.0:
            return
        if self.axis and self.axis[-1] == axis and (self.delta[-1] > 0) == (d > 0):
            self.delta[-1] += d
        else:
            self.axis.append(axis)
            self.delta.append(d)


def staircase_moves(program: MotionProgram, base_radius: float, orientation: float, tolerance: float,
                    samples: int = DEFAULT_SAMPLES) -> tuple[np.ndarray, int, float]:
    """The thesis' tool path (module docstring) as (vertices, turns, length); ``orientation`` [rad]."""
    moves: _Moves | None = None
    value = _Hermite.value
    for k, (theta, dth, r, dr) in enumerate(polar_tables(program, base_radius, samples)):
        curve = program.curves[k] if program.curves else None
        h = (curve.u_max if curve is not None else program.spans[k]) / (samples - 1)
        al = orientation + theta
        c, s = np.cos(al), np.sin(al)
        x, y = r * c, r * s
        dx = dr * c - r * s * dth
        dy = dr * s + r * c * dth
        ro = r + tolerance
        xo, yo = ro * c, ro * s
        dxo = dr * c - ro * s * dth
        dyo = dr * s + ro * c * dth
        if moves is None:
            moves = _Moves(complex(x[0], y[0]))
        crit = {0, len(x) - 1}
        for d, coord in ((dx, x), (dy, y)):
            sg = np.sign(d)
            for i in (np.nonzero(sg[1:] * sg[:-1] < 0)[0] + 1).tolist():
                # the extremum lies between samples i − 1 and i: cut at the more extreme one, so
                # that the coordinate is monotonic on the samples of both sections
                up = sg[i - 1] > 0
                crit.add(i - 1 if (coord[i - 1] >= coord[i]) == up else i)
        cuts = sorted(crit)
        px, py = float(x[0]), float(y[0])
        for a, b in zip(cuts[:-1], cuts[1:]):
            sx = 1.0 if x[b] >= x[a] else -1.0
            sy = 1.0 if y[b] >= y[a] else -1.0
            x_first = sx * sy > 0            # dY/dX > 0: along X first (Fig. 4.3a), else Y first
            sl = slice(a, b + 1)
            if x_first:
                ap, aq, sp, sq = 0, 1, sx, sy
                p, dp, q, dq, po, dpo, qo, dqo = x, dx, y, dy, xo, dxo, yo, dyo
                cp, cq = px, py
            else:
                ap, aq, sp, sq = 1, 0, sy, sx
                p, dp, q, dq, po, dpo, qo, dqo = y, dy, x, dx, yo, dyo, xo, dxo
                cp, cq = py, px
            # sign-flipped so that the curve's coordinates increase along the section
            curve_p = _Hermite(sp * p[sl], sp * dp[sl], h)
            off_q = _Hermite(sq * qo[sl], sq * dqo[sl], h)
            qv, dqv = (sq * q[sl]).tolist(), (sq * dq[sl]).tolist()
            pov, dpov = (sp * po[sl]).tolist(), (sp * dpo[sl]).tolist()
            cp, cq = sp * cp, sq * cq
            p_end, q_end = sp * float(p[b]), sq * float(q[b])
            while True:
                # Eq. 4.4 / 4.17: where the ε-offset curve reaches the current secondary coordinate …
                hit = off_q.solve(cq)
                if hit is None:
                    break
                p1 = value(pov, dpov, h, *hit)
                if p1 >= p_end:
                    break
                # … Eq. 4.7 / 4.18: back onto the curve along the other axis
                back = curve_p.solve(p1)
                if back is None:
                    break
                q1 = value(qv, dqv, h, *back)
                if q1 <= cq:
                    break
                moves.add(ap, sp * (p1 - cp))
                moves.add(aq, sq * (q1 - cq))
                cp, cq = p1, q1
            moves.add(ap, sp * (p_end - cp))
            moves.add(aq, sq * (q_end - cq))
            px, py = float(x[b]), float(y[b])
    assert moves is not None
    axis = np.array(moves.axis)
    delta = np.array(moves.delta)
    steps = np.where(axis == 0, delta + 0j, 1j * delta)
    vertices = moves.start + np.concatenate([[0.0], np.cumsum(steps)])
    turns = len(delta) - (1 if len(delta) > 1 and axis[0] == axis[-1] and (delta[0] > 0) == (delta[-1] > 0) else 0)
    return vertices, int(turns), float(np.sum(np.abs(delta)))


def thesis_cutting_time(spec: CamSpec, program: MotionProgram | None = None, *,
                        base_radius: float | None = None, orientation_deg: float | None = None,
                        tolerance: float | None = None, feed_per_s: float | None = None,
                        turn_time: float | None = None, samples: int = DEFAULT_SAMPLES) -> StaircasePath:
    """The thesis' cutting time T = S/feed + t_turn·N_turns (Eq. 4.20) of ``spec``'s cam.

    Defaults come from the spec: ``optimise.blank_orientation``, ``optimise.machining_tolerance``
    (0.01 in / 0.25 mm), ``machining.feed_rate`` (per minute; 12 in/min or 300 mm/min when
    absent) and ``optimise.turn_time``.  ``program``/``base_radius`` override the spec's motion
    and R_b (the optimiser's inner loop)."""
    program = program or MotionProgram.from_spec(spec)
    r0 = spec.cam.base_radius if base_radius is None else base_radius
    opt = spec.optimise
    b = np.deg2rad(opt.blank_orientation if orientation_deg is None else orientation_deg)
    eps = tolerance if tolerance is not None else (opt.machining_tolerance or DEFAULT_TOLERANCE[spec.units])
    if feed_per_s is None:
        per_min = spec.machining.feed_rate if spec.machining.feed_rate is not None else \
            {"in": 12.0, "mm": 300.0}[spec.units]
        feed_per_s = per_min / 60.0
    t_turn = opt.turn_time if turn_time is None else turn_time
    vertices, turns, length = staircase_moves(program, r0, float(b), float(eps), samples)
    return StaircasePath(vertices, turns, length, length / feed_per_s + t_turn * turns, float(feed_per_s),
                         float(eps), float(t_turn), float(np.rad2deg(b)))


# ---- the project's own G-code contour -----------------------------------------------------
@dataclass(frozen=True)
class ContourTime:
    """Estimated run time of the XY contour program (``cam_workbench.exporters.gcode.contour_program``)."""

    time: float            # [s]
    cutting_length: float  # lead arcs + contour, all passes [length]
    plunge_length: float   # [length]
    blocks: int            # motion blocks at feed (plunges, lead arcs, contour moves)
    block_time: float      # [s] per block

    def summary(self) -> dict[str, Any]:
        return {"model": "cutting length / feed + plunges / plunge feed + blocks x block time (rapids excluded)",
                "time_s": self.time, "cutting_length": self.cutting_length,
                "plunge_length": self.plunge_length, "blocks": self.blocks, "block_time_s": self.block_time}


def contour_time(design: Any, plan: Any = None, block_time: float | None = None) -> ContourTime:
    """Time of the XY contour G-code of ``design``: per pass, (lead-in + contour + lead-out)/feed
    and the plunge/plunge feed, plus ``block_time`` per motion block (default
    ``optimise.block_time``); rapid moves are left out (their speed is the machine's).  With
    ``machining.blank_diameter`` the program roughs first: :func:`roughing_time` is added."""
    plan = plan or machining_plan(design)
    path = contour_path(design, plan)
    bt = design.spec.optimise.block_time if block_time is None else block_time
    passes = int(path.z_levels.shape[0])
    cut = passes * (path.loop.length + path.lead_in.length + path.lead_out.length)
    plunge = float(np.sum(plan.safe_height - path.z_levels))   # each pass plunges from the safe height
    blocks = passes * (path.loop.n + 3)
    t = cut / (plan.feed_rate / 60.0) + plunge / (plan.plunge_rate / 60.0) + blocks * bt
    finish = ContourTime(float(t), float(cut), float(plunge), int(blocks), float(bt))
    if design.spec.machining.blank_diameter is None:
        return finish
    rough = roughing_time(roughing_path(design, plan), plan, bt)
    return ContourTime(finish.time + rough.time, finish.cutting_length + rough.cutting_length,
                       finish.plunge_length + rough.plunge_length, finish.blocks + rough.blocks, float(bt))


def roughing_time(rough: RoughingPath, plan: Any, block_time: float) -> ContourTime:
    """Time of the roughing part of the XY program: per depth level, (in-feed + passes +
    step-ins)/feed and the plunge from the safe height/plunge feed, plus ``block_time`` per motion
    block at feed; rapids left out."""
    levels = int(rough.z_levels.shape[0])
    cut = levels * rough.level_length
    plunge = float(np.sum(plan.safe_height - rough.z_levels))
    blocks = levels * rough.level_blocks
    t = cut / (plan.feed_rate / 60.0) + plunge / (plan.plunge_rate / 60.0) + blocks * block_time
    return ContourTime(float(t), float(cut), float(plunge), int(blocks), float(block_time))

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
parameter (u of a B-spline lift, θ otherwise) and inverted by linear interpolation inside the
monotonic sections; 4 000 samples per segment move no turn and S by < 1e-9 against 40 000.

**The G-code contour time** (:func:`contour_time`): cutting length / feed plus a per-block time
for the XY program of :mod:`generators.toolpath` (lead arcs, contour, plunges; rapids excluded).
"""
from __future__ import annotations

from bisect import bisect_left
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from .laws import evaluate_law
from .motion import MotionProgram
from .spec import CamSpec

#: The thesis' tolerance (0.01 in) in each unit system, and its time per turn.
DEFAULT_TOLERANCE = {"in": 0.01, "mm": 0.25}
TURN_TIME = 0.4
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
    (u of a B-spline lift, θ otherwise), r = R_b + s (thesis Eq. 4.5–4.6)."""
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


def _interp(keys: Sequence[float], values: Sequence[float], v: float) -> float:
    """Linear interpolation of ``values`` at ``v`` on increasing ``keys`` (clamped)."""
    k = bisect_left(keys, v)
    if k <= 0:
        return values[0]
    if k >= len(keys):
        return values[-1]
    k0, k1 = keys[k - 1], keys[k]
    w = (v - k0) / (k1 - k0) if k1 > k0 else 1.0
    return values[k - 1] + w * (values[k] - values[k - 1])


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
    for theta, dth, r, dr in polar_tables(program, base_radius, samples):
        al = orientation + theta
        c, s = np.cos(al), np.sin(al)
        x, y = r * c, r * s
        dx = dr * c - r * s * dth
        dy = dr * s + r * c * dth
        xo, yo = (r + tolerance) * c, (r + tolerance) * s
        if moves is None:
            moves = _Moves(complex(x[0], y[0]))
        crit = {0, len(x) - 1}
        for d in (dx, dy):
            sg = np.sign(d)
            crit.update((np.nonzero(sg[1:] * sg[:-1] < 0)[0] + 1).tolist())
        cuts = sorted(crit)
        px, py = float(x[0]), float(y[0])
        for a, b in zip(cuts[:-1], cuts[1:]):
            sx = 1.0 if x[b] >= x[a] else -1.0
            sy = 1.0 if y[b] >= y[a] else -1.0
            x_first = sx * sy > 0            # dY/dX > 0: along X first (Fig. 4.3a), else Y first
            sl = slice(a, b + 1)
            if x_first:
                p, q, po, qo, sp, sq, ap, aq = x[sl], y[sl], xo[sl], yo[sl], sx, sy, 0, 1
                cp, cq = px, py
            else:
                p, q, po, qo, sp, sq, ap, aq = y[sl], x[sl], yo[sl], xo[sl], sy, sx, 1, 0
                cp, cq = py, px
            # sign-flipped so that the curve's coordinates increase along the section
            pk = np.maximum.accumulate(sp * p).tolist()
            qk = np.maximum.accumulate(sq * q).tolist()
            qv = (sq * q).tolist()
            pov = (sp * po).tolist()
            qok = np.maximum.accumulate(sq * qo).tolist()
            cp, cq = sp * cp, sq * cq
            p_end, q_end = pk[-1], qk[-1]
            while cq <= qok[-1]:
                # Eq. 4.4 / 4.17: the offset curve at the current secondary coordinate …
                p1 = _interp(qok, pov, cq)
                if p1 >= p_end:
                    break
                # … Eq. 4.7 / 4.18: back onto the curve along the other axis
                q1 = _interp(pk, qv, p1)
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
    """Estimated run time of the XY contour program (``exporters.gcode.contour_program``)."""

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
    ``optimise.block_time``); rapid moves are left out (their speed is the machine's)."""
    from .machining import machining_plan
    from .toolpath import contour_path

    plan = plan or machining_plan(design)
    path = contour_path(design, plan)
    bt = design.spec.optimise.block_time if block_time is None else block_time
    passes = int(path.z_levels.shape[0])
    cut = passes * (path.loop.length + path.lead_in.length + path.lead_out.length)
    plunge = float(np.sum(plan.safe_height - path.z_levels))   # each pass plunges from the safe height
    blocks = passes * (path.loop.n + 3)
    t = cut / (plan.feed_rate / 60.0) + plunge / (plan.plunge_rate / 60.0) + blocks * bt
    return ContourTime(float(t), float(cut), float(plunge), int(blocks), float(bt))

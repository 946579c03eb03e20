"""Electronic-cam tables from the motion program, and how far a table's own interpolation is from
the exact motion.

A servo controller replaces the mechanical cam by a table: master position X (here the cam angle
in degrees, 0 … 360), slave position Y (the follower's lift in the spec's lift unit: mm or arm
degrees) and, for polynomial tables, the slave's derivatives with respect to the master,
Y′ = dY/dX, Y″, Y‴ (per master degree: the motion program's s′ per radian × π/180, …).

Between its points the controller interpolates with its own rule:

* ``"linear"`` — a straight line between (X_i, Y_i) and (X_i+1, Y_i+1): point tables;
* ``"quintic"`` — the fifth-degree polynomial that takes Y, Y′, Y″ at both ends of the interval
  (CODESYS XYVA and Poly5 segments, Beckhoff's MOTIONFUNCTYPE_POLYNOM5_MM motion functions).

:func:`interpolation_deviation` evaluates that rule between the points the file holds (the
numbers as written) and compares it with the exact motion, densely in every interval, refining
the largest error by zooming on it: the error in Y, and in Y′ (and Y″ for the quintic).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..motion.program import MotionProgram

DEG = math.pi / 180.0
INTERPOLATIONS = ("linear", "quintic")


@dataclass(frozen=True)
class TablePoints:
    """Table points (arrays of equal length, master ascending from 0 to 360).

    Attributes:
        master: X [deg of cam rotation].
        slave: Y [spec lift unit].
        velocity, acceleration, jerk: dY/dX, d²Y/dX², d³Y/dX³ [per master degree].
        equidistant: every interval has the same length.
    """

    master: np.ndarray
    slave: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray
    equidistant: bool

    @property
    def count(self) -> int:
        return int(self.master.size)

    def replaced(self, **arrays: np.ndarray) -> "TablePoints":
        """The same table with some columns replaced (e.g. by the values as a file writes them)."""
        data = {k: getattr(self, k) for k in ("master", "slave", "velocity", "acceleration", "jerk")}
        data.update(arrays)
        steps = np.diff(data["master"])
        return TablePoints(**data, equidistant=bool(np.allclose(steps, steps[0], rtol=0, atol=1e-9)))


def table_points(program: MotionProgram, step_deg: float, boundaries: bool = True) -> TablePoints:
    """Points every ``step_deg`` cam degrees from 0 to 360 (the last interval shorter when the
    step does not divide 360) and, with ``boundaries``, at every motion-segment boundary; the
    derivatives are the motion program's exact ones at each point (at a boundary those of the
    segment that starts there; at 360° the program's start, the slave advanced by the program's
    ``advance``)."""
    n = int(math.floor(360.0 / step_deg + 1e-9))
    grid = step_deg * np.arange(n + 1)
    if boundaries:
        grid = np.concatenate([grid, np.rad2deg(program.boundaries)])
    # masters to 1e-9° (k·step and the boundaries' degrees carry float noise: 29.999999999999996)
    grid = np.unique(np.round(np.append(grid, 360.0), 9))
    grid = grid[grid <= 360.0]
    k = program.evaluate(np.deg2rad(grid))
    # an indexer's turret advances: at 360° it stands one step on from the start
    slave = np.asarray(k.s, float) + np.where(grid >= 360.0, program.advance, 0.0)
    steps = np.diff(grid)
    # + 0.0: no "-0.0" in a file
    return TablePoints(grid, slave + 0.0, k.ds * DEG + 0.0, k.d2s * DEG**2 + 0.0, k.d3s * DEG**3 + 0.0,
                       bool(np.allclose(steps, steps[0], rtol=0, atol=1e-9)))


def quintic_coefficients(x0, x1, y0, v0, a0, y1, v1, a1) -> np.ndarray:
    """Coefficients c0 … c5 (in t = (x − x0)/h, h = x1 − x0) of the quintic with the given Y, Y′, Y″
    at both ends; arrays of intervals → shape (6, n)."""
    h = x1 - x0
    V0, V1, A0, A1 = v0 * h, v1 * h, a0 * h * h, a1 * h * h
    d = y1 - y0
    c3 = 10 * d - 6 * V0 - 4 * V1 - 1.5 * A0 + 0.5 * A1
    c4 = -15 * d + 8 * V0 + 7 * V1 + 1.5 * A0 - A1
    c5 = 6 * d - 3 * V0 - 3 * V1 - 0.5 * A0 + 0.5 * A1
    return np.array([y0, V0, 0.5 * A0, c3, c4, c5])


def interpolate(points: TablePoints, x: np.ndarray, kind: str, interval: np.ndarray | None = None
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(Y, Y′, Y″) of the table's own interpolation at masters ``x`` [deg] (Y″ = 0 for linear);
    ``interval`` names each x's interval (default: found by search)."""
    X = points.master
    x = np.asarray(x, float)
    i = (np.clip(np.searchsorted(X, x, side="right") - 1, 0, X.size - 2) if interval is None
         else np.asarray(interval))
    h = X[i + 1] - X[i]
    t = (x - X[i]) / h
    if kind == "linear":
        slope = (points.slave[i + 1] - points.slave[i]) / h
        return points.slave[i] + slope * (x - X[i]), slope, np.zeros_like(x)
    c = quintic_coefficients(X[i], X[i + 1], points.slave[i], points.velocity[i], points.acceleration[i],
                             points.slave[i + 1], points.velocity[i + 1], points.acceleration[i + 1])
    y = c[0] + t * (c[1] + t * (c[2] + t * (c[3] + t * (c[4] + t * c[5]))))
    dy = c[1] + t * (2 * c[2] + t * (3 * c[3] + t * (4 * c[4] + t * 5 * c[5])))
    d2y = 2 * c[2] + t * (6 * c[3] + t * (12 * c[4] + t * 20 * c[5]))
    return y, dy / h, d2y / (h * h)


@dataclass(frozen=True)
class Deviation:
    """How far a table's interpolation is from the exact motion.

    Attributes:
        interpolation: "linear" or "quintic".
        max_error, at_deg: largest |Y_table − s| [lift unit] and its master position.
        max_velocity_error, velocity_at_deg: largest |Y′_table − s′| [lift unit per master degree].
        max_acceleration_error, acceleration_at_deg: the same for Y″ (None for linear tables,
            whose Y″ is a train of impulses at the points).
        samples_per_interval: the dense sampling before the refinement.
    """

    interpolation: str
    max_error: float
    at_deg: float
    max_velocity_error: float
    velocity_at_deg: float
    max_acceleration_error: float | None
    acceleration_at_deg: float | None
    samples_per_interval: int

    def to_dict(self) -> dict[str, Any]:
        return {"interpolation": self.interpolation, "max_error": self.max_error, "at_deg": self.at_deg,
                "max_velocity_error": self.max_velocity_error, "velocity_at_deg": self.velocity_at_deg,
                "max_acceleration_error": self.max_acceleration_error,
                "acceleration_at_deg": self.acceleration_at_deg,
                "samples_per_interval": self.samples_per_interval}


def interpolation_deviation(program: MotionProgram, points: TablePoints, kind: str,
                            samples_per_interval: int = 64, rounds: int = 4) -> Deviation:
    """The table's interpolation (``kind``) against the exact motion: sampled densely in every
    interval (vectorised), each largest error then refined by ``rounds`` zooms on its neighbours
    (the exact motion of the segment there, one-sided at the segment's ends)."""
    if kind not in INTERPOLATIONS:
        raise ValueError(f"unknown interpolation {kind!r}")
    X = points.master
    m = X.size - 1
    t = (np.arange(samples_per_interval) + 0.5) / samples_per_interval
    i = np.repeat(np.arange(m), t.size)
    x = (X[i] + (X[i + 1] - X[i]) * np.tile(t, m))
    x = np.concatenate([x, X])
    i = np.concatenate([i, np.clip(np.arange(m + 1), 0, m - 1)])
    seg_of = _segment_of(program, x)
    errs = _errors(program, points, kind, x, i, seg_of)
    out = []
    for e, order in zip(errs, range(3)):
        if e is None:
            out.append((None, None))
            continue
        j = int(np.argmax(e))
        best_x, best = float(x[j]), float(e[j])
        ii, sg = int(i[j]), int(seg_of[j])
        lo, hi = X[ii], X[ii + 1]
        seg_lo, seg_hi = np.rad2deg(program.starts[sg]), np.rad2deg(program.starts[sg] + program.spans[sg])
        lo, hi = max(lo, seg_lo), min(hi, seg_hi)
        step = (X[ii + 1] - X[ii]) / samples_per_interval
        a, b = max(lo, best_x - step), min(hi, best_x + step)
        for _ in range(rounds):
            xs = np.linspace(a, b, 33)
            ee = _errors(program, points, kind, xs, np.full(xs.shape, ii), np.full(xs.shape, sg))[order]
            k = int(np.argmax(ee))
            if ee[k] > best:
                best_x, best = float(xs[k]), float(ee[k])
            a, b = xs[max(k - 1, 0)], xs[min(k + 1, 32)]
        out.append((best, best_x))
    (e0, x0), (e1, x1), (e2, x2) = out
    return Deviation(kind, e0, x0, e1, x1, e2, x2, samples_per_interval)


def _segment_of(program: MotionProgram, x: np.ndarray) -> np.ndarray:
    """The motion segment whose law gives the exact motion at x [deg]: the one containing x (at a
    boundary the one that starts there, the side a table's next interval interpolates), the last
    one at 360°."""
    seg = program.segment_of(np.deg2rad(x))
    return np.where(x >= 360.0 - 1e-9, len(program.starts) - 1, seg)


def _errors(program: MotionProgram, points: TablePoints, kind: str, x: np.ndarray, interval: np.ndarray,
            segment: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    y, dy, d2y = interpolate(points, x, kind, interval)
    k = program.evaluate(np.deg2rad(x), segment)
    e0 = np.abs(y - k.s)
    e1 = np.abs(dy - k.ds * DEG)
    e2 = None if kind == "linear" else np.abs(d2y - k.d2s * DEG**2)
    return e0, e1, e2

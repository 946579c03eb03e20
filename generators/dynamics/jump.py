"""The jump speed: the lowest cam speed at which the follower leaves the cam.

Below it the follower stays on the cam and the train is linear, so the smallest contact force of
the periodic steady state, F_min(ω) = min_θ Q(θ; ω)·lever(θ), tells exactly when contact is first
lost: at the first ω where F_min(ω) = 0.  It is found by a sweep of ``sweep_points`` speeds (all
solved at once, :func:`cam_workbench.generators.dynamics.periodic.min_force_vs_speed`) and Brent's method
between the last speed that keeps contact and the first that does not.  A resonance narrower than
the sweep's spacing can hide between two speeds; ``dynamics.sweep_points`` sets the spacing.

The rigid follower's jump speed (k_f → ∞) is in closed form: Q = J u″ω² + P + k_s u must stay > 0,
so ω_rigid² = min over u″ < 0 of (P + k_s u)/(−J u″).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..motion.program import MotionProgram
from .model import TrainModel
from .periodic import CamInput, min_force_vs_speed

RPM = 60.0 / (2.0 * math.pi)
#: samples per revolution of the sweep at most (the lowest speeds would ask for more)
SWEEP_MAX_SAMPLES = 1 << 17


@dataclass(frozen=True)
class JumpSpeed:
    """The sweep and its result (speeds in rpm, forces in the spec's force unit).

    Attributes:
        rpm: the dynamic jump speed, None when the sweep did not bracket it (see ``note``).
        rigid_rpm: the rigid follower's, None when it keeps contact at every speed.
        speeds_rpm, min_force: the sweep: F_min at each speed.
        samples: samples per revolution of the sweep's solves.
        note: what the result means when ``rpm`` is None.
        evaluations: solves of the bisection.
    """

    rpm: float | None
    rigid_rpm: float | None
    speeds_rpm: np.ndarray
    min_force: np.ndarray
    samples: int
    note: str = ""
    evaluations: int = 0


def rigid_jump_speed(model: TrainModel, program: MotionProgram, inp: CamInput) -> float | None:
    """ω [rad/s] above which the rigid follower leaves the cam: √min((P + k_s u)/(−J u″)) over
    u″ < 0, from the samples and refined in the best one's motion segment; 0 when P + k_s u ≤ 0
    somewhere (no speed keeps contact), None when u″ never pulls (no speed loses it)."""
    hold = model.preload + model.spring_rate * inp.u
    if np.any(hold <= 0):
        return 0.0
    pull = -model.inertia * inp.d2u
    if not np.any(pull > 0):
        return None
    ratio = np.where(pull > 0, hold / np.where(pull > 0, pull, 1.0), np.inf)
    j = int(np.argmin(ratio))
    seg = int(inp.segment[j])
    a, b = program.starts[seg], program.starts[seg] + program.spans[seg]
    lo, hi = max(a, inp.theta[j] - 2 * np.pi / inp.n), min(b, inp.theta[j] + 2 * np.pi / inp.n)
    best = float(ratio[j])
    for _ in range(5):                           # zoom: 33 points a round, 16× narrower each
        t = np.linspace(lo, hi, 33)
        k = program.evaluate(t, np.full(t.shape, seg))
        u, d2u = model.lift_scale * k.s, model.lift_scale * k.d2s
        p = -model.inertia * d2u
        r = np.where(p > 0, (model.preload + model.spring_rate * u) / np.where(p > 0, p, 1.0), np.inf)
        i = int(np.argmin(r))
        best = min(best, float(r[i]))
        lo, hi = t[max(i - 1, 0)], t[min(i + 1, 32)]
    return math.sqrt(best)


def sweep_range(model: TrainModel, omega: float, rigid: float | None, lo_rpm: float | None,
                hi_rpm: float | None, low_fraction: float) -> tuple[float, float]:
    """(lowest, highest) speed [rad/s] of the sweep: the spec's, else up to twice the rigid jump
    speed (at least twice ``omega``) and down to ``low_fraction`` of that."""
    hi = hi_rpm / RPM if hi_rpm is not None else 2.0 * max(rigid or 0.0, omega)
    lo = lo_rpm / RPM if lo_rpm is not None else low_fraction * hi
    return lo, hi


def find_jump_speed(model: TrainModel, inp: CamInput, speeds: np.ndarray, rigid: float | None,
                    progress: Callable[[int, int, str], None] | None = None) -> JumpSpeed:
    """Sweep ``speeds`` [rad/s] (ascending) and bisect the first loss of contact."""
    from scipy.optimize import brentq  # deferred: scipy.optimize, the jump speed's bisection alone

    total = speeds.size + 1

    def swept(done: int, _all: int) -> None:
        if progress is not None:
            progress(done, total, "jump-speed sweep")

    fmin = min_force_vs_speed(model, inp, speeds, swept)
    lost = np.flatnonzero(fmin <= 0)
    rigid_rpm = None if rigid is None else rigid * RPM
    evals = [0]
    if lost.size == 0:
        note = f"the follower stays on the cam up to {speeds[-1] * RPM:.6g} rpm (the sweep's top)"
        rpm = None
    elif lost[0] == 0:
        note = f"the follower leaves the cam already at {speeds[0] * RPM:.6g} rpm (the sweep's lowest speed)"
        rpm = None
    else:
        i = int(lost[0])

        def f(om: float) -> float:
            evals[0] += 1
            if progress is not None:
                progress(speeds.size, total, f"bisecting the jump speed: {om * RPM:.6g} rpm")
            return float(min_force_vs_speed(model, inp, np.array([om]))[0])

        a, b = float(speeds[i - 1]), float(speeds[i])
        root = brentq(f, a, b, xtol=1e-12 * b, rtol=1e-12) if f(b) < 0 < f(a) else b
        rpm, note = root * RPM, ""
    if progress is not None:
        progress(total, total, "jump speed")
    return JumpSpeed(rpm, rigid_rpm, speeds * RPM, fmin, inp.n, note, evals[0])

"""The starts of an optimisation as plain jobs an executor can run anywhere: :class:`StartJob`,
:func:`run_start`, :class:`StartOutcome`, the random starting designs, the progress of all starts
together and the rule that ranks their results.
"""
from __future__ import annotations

import dataclasses
import math
import threading
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from ..checks.design import run_checks
from ..errors import CamError
from ..spec.model import CamSpec
from ..studies.executor import TaskContext
from .driver import StartRunner
from .problem import Cancelled, Tracker
from .result import Progress, final_value
from .space import DesignSpace


@dataclass(frozen=True)
class StartJob:
    """One local run of an optimisation, as :func:`run_start` takes it: plain values, so that it
    can run in another process or on another machine with the same result.

    ``index`` 0 is the run from the spec's own design (with the objective's phases: the size
    stand-in and the orientation scan of a machining time, ISRES first for ``isres``); index k ≥ 1
    is ``multistart``'s random start k + 1 from ``z`` (scaled variables, drawn by
    :func:`optimise` before any run, in start order)."""

    index: int
    spec: CamSpec                  # the settings applied
    z: np.ndarray | None           # the random start (scaled); None for index 0
    budget: int                    # the whole optimisation's budget (the progress bar's total)


@dataclass
class StartOutcome:
    """What one :class:`StartJob` gave: its result (None when it was cancelled), the key
    :func:`optimise` picks the best result by, and its evaluations, history and best points."""

    index: int
    p: np.ndarray | None
    key: tuple[bool, float] | None     # (fails the dense check or no finite value, final value); None: not valid
    solver_status: str
    solver_ok: bool
    messages: list[str]
    evaluations: int
    history: list[dict[str, Any]]
    best_feasible: tuple[float, np.ndarray] | None
    best_any: tuple[float, float, np.ndarray] | None
    windows: int | None
    cancelled: bool


class _CancelFlag:
    """The tracker's ``cancel`` for a job: asks the executor's task context."""

    def __init__(self, ctx: TaskContext):
        self._ctx = ctx

    def is_set(self) -> bool:
        return self._ctx.cancelled()


def run_start(job: StartJob, ctx: TaskContext) -> StartOutcome:
    """Run one start of an optimisation (the task :func:`optimise` hands its executor): every
    evaluation reports a :class:`Progress` (as a dict) through ``ctx.report``, and the run stops
    with its best points when ``ctx.cancelled()`` says so.  Its result does not depend on the
    process it runs in."""
    tracker = Tracker(job.budget, lambda p: ctx.report(dataclasses.asdict(p)), _CancelFlag(ctx))
    runner = StartRunner(job.spec, tracker)
    space = runner.space
    p: np.ndarray | None = None
    key: tuple[bool, float] | None = None
    cancelled = False
    try:
        if job.index == 0:
            p = runner.first()
        else:
            tracker.phase = f"start {job.index + 1}"
            p = runner.solve_phase(runner.obj, runner.local, space.to_p(np.asarray(job.z, dtype=float)),
                                   f"start {job.index + 1}")
        key = _pick_key(runner.cfg.objective, space, p)
    except Cancelled:
        p, key, cancelled = None, None, True
    return StartOutcome(index=job.index, p=p, key=key, solver_status=runner.last[0], solver_ok=runner.last[1],
                        messages=runner.messages, evaluations=tracker.evaluations, history=tracker.history,
                        best_feasible=tracker.best_feasible, best_any=tracker.best_any, windows=runner.windows,
                        cancelled=cancelled)


class StartsProgress:
    """The progress of every start together, for the caller's callback (called in the caller's
    thread): evaluations summed over the starts, the best feasible objective of any start."""

    def __init__(self, budget: int, progress: Callable[[Progress], Any] | None, cancel: threading.Event | None):
        self.budget = budget
        self.progress = progress
        self.cancel = cancel
        self.counts: dict[int, int] = {}
        self.bests: dict[int, float] = {}
        self.stop = False

    def on_progress(self, index: int, info: dict[str, Any]) -> None:
        self.counts[index] = int(info["evaluations"])
        if info["best"] is None:
            self.bests.pop(index, None)
        else:
            self.bests[index] = float(info["best"])
        if self.progress is None:
            return
        best = min(self.bests.values()) if self.bests else None
        if self.progress(Progress(sum(self.counts.values()), self.budget, info["phase"], info["objective"],
                                  info["max_violation"], best)) is False:
            self.stop = True

    def should_stop(self) -> bool:
        return self.stop or (self.cancel is not None and self.cancel.is_set())


def random_start(space: DesignSpace, rng: np.random.Generator, tries: int = 200) -> np.ndarray | None:
    """A random design in the box with valid control polygons (sorted angles, monotonic lifts)
    that is a valid spec (an oscillating arm reaches the prime circle: redrawn up to ``tries``
    times; None if none does)."""
    for _ in range(tries):
        z = _random_point(space, rng)
        if space.is_valid(space.to_p(z)):
            return z
    return None


def _random_point(space: DesignSpace, rng: np.random.Generator) -> np.ndarray:
    z = rng.uniform(0.0, 1.0, space.n)
    p = space.to_p(z)
    for blk in space.blocks:
        if blk.x_cols.size:
            m = blk.x_cols.size
            inc = rng.dirichlet(np.ones(m + 1))
            usable = blk.span - (m + 1) * space.gap
            p[blk.x_cols] = space.gap * np.arange(1, m + 1) + usable * np.cumsum(inc)[:-1]
        if blk.y_cols.size:
            ys = np.sort(rng.uniform(0.0, 1.0, blk.y_cols.size))
            p[blk.y_cols] = ys if blk.kind == "rise" else ys[::-1]
    return space.to_z(np.clip(p, space.lower, space.upper))


def _pick_key(objective: str, space: DesignSpace, p: np.ndarray) -> tuple[bool, float] | None:
    """How :func:`optimise` ranks a start's result: (fails the dense check or has no finite
    objective, the objective) — smaller is better; None for a design outside the follower's
    geometry (never picked)."""
    if not space.is_valid(p):
        return None
    spec = space.spec_at(p)
    try:
        value = final_value(objective, spec)
    except CamError:           # gcode_time: a candidate that cannot be built comes last
        value = math.inf
    return (not run_checks(spec).passed or not math.isfinite(value), value)


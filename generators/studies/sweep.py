"""Sweeps: every point of a :class:`~cam_workbench.generators.studies.grid.Grid` evaluated (designed and checked,
no solid), or sized (the smallest base radius meeting the checks), through an executor.

``run_sweep(spec, grid)`` returns a :class:`~cam_workbench.generators.studies.table.StudyTable` with one row per
grid point in grid order: the grid's columns, ``status``/``error``, then the key numbers
(:func:`~cam_workbench.generators.studies.table.summary_row`) or the sizing columns
(:func:`~cam_workbench.generators.studies.sizing.sizing_row`).  A point whose spec breaks a rule, or whose cam
cannot be made, is a row saying why; the others go on.  The points are handed to the executor in
consecutive pieces (:func:`~cam_workbench.generators.studies.executor.chunks`); each row depends on its point
only, so the table is the same whatever ran where.
"""
from __future__ import annotations

import threading
import time
from dataclasses import dataclass
from typing import Any, Callable

from ..errors import CamError, SpecError
from ..spec.model import CamSpec
from .executor import NOT_RUN, Executor, SerialExecutor, TaskContext, chunks
from .grid import Grid
from .sizing import SIZED_FIELD, SizingSettings, sizing_row, smallest_base_radius
from .table import StudyTable, error_row, summary_row
from ..cam_design import design_cam

FIRST_COLUMNS = ("status", "error")


@dataclass(frozen=True)
class SweepJob:
    """A piece of a sweep (plain values: it may run in another process)."""

    spec: CamSpec
    grid: Grid
    points: tuple[tuple[int, dict[str, Any]], ...]   # (grid index, point)
    sizing: SizingSettings | None                    # None: evaluate


def evaluate_point(spec: CamSpec, grid: Grid, point: dict[str, Any]) -> dict[str, Any]:
    """One grid point designed and checked (no solid): the point's columns and the key numbers,
    or the reason there are none."""
    row: dict[str, Any] = dict(point)
    try:
        s = grid.spec_at(spec, point)
    except SpecError as exc:
        return {**row, **error_row("bad input", exc)}
    try:
        d = design_cam(s)
        numbers = summary_row(d.summary(), s.cam.base_radius)
    except CamError as exc:
        return {**row, **error_row("cannot be made", exc)}
    return {**row, "status": "ok", "error": "", **numbers}


def size_point(spec: CamSpec, grid: Grid, point: dict[str, Any], settings: SizingSettings) -> dict[str, Any]:
    """One grid point sized: the smallest base radius meeting the checks (bisection)."""
    row: dict[str, Any] = dict(point)
    try:
        s = grid.spec_at(spec, point)
    except SpecError as exc:
        return {**row, **error_row("bad input", exc)}
    try:
        sz = smallest_base_radius(s, settings)
    except CamError as exc:
        return {**row, **error_row("cannot be made", exc)}
    return {**row, **sizing_row(sz)}


def sweep_task(job: SweepJob, ctx: TaskContext) -> list[tuple[int, dict[str, Any]]]:
    """The executor's task: the job's points in order, reporting ``{"done": n}`` after each; stops
    between points when the caller cancels (the rows so far are returned)."""
    out: list[tuple[int, dict[str, Any]]] = []
    for index, point in job.points:
        if ctx.cancelled():
            break
        if job.sizing is None:
            row = evaluate_point(job.spec, job.grid, point)
        else:
            row = size_point(job.spec, job.grid, point, job.sizing)
        out.append((index, row))
        ctx.report({"done": len(out)})
    return out


class Counter:
    """Completed items over a study's pieces, from the tasks' cumulative reports, for a progress
    display ``progress(done, total)`` in the caller's thread; returning False stops the study."""

    def __init__(self, total: int, progress: Callable[[int, int], Any] | None, cancel: threading.Event | None):
        self.total = total
        self.progress = progress
        self.cancel = cancel
        self.done: dict[int, int] = {}
        self.stop = False

    def on_progress(self, piece: int, info: dict[str, Any]) -> None:
        self.done[piece] = max(self.done.get(piece, 0), int(info.get("done", 0)))
        self._tell()

    def finished(self, piece: int, n: int) -> None:
        self.done[piece] = max(self.done.get(piece, 0), n)
        self._tell()

    def _tell(self) -> None:
        if self.progress is not None and self.progress(sum(self.done.values()), self.total) is False:
            self.stop = True

    def should_stop(self) -> bool:
        return self.stop or (self.cancel is not None and self.cancel.is_set())


def run_sweep(spec: CamSpec, grid: Grid, *, sizing: SizingSettings | None = None,
              executor: Executor | None = None, progress: Callable[[int, int], Any] | None = None,
              cancel: threading.Event | None = None) -> StudyTable:
    """Every point of ``grid`` on ``spec``: evaluated (``sizing`` None) or sized.

    Args:
        spec: the base spec; each point changes the grid's fields (and ``grid.balance``).
        grid: the points (checked against ``spec`` first: bad fields raise before any work).
        sizing: size each point (:func:`~cam_workbench.generators.studies.sizing.smallest_base_radius`).
        executor: where the points run (None: one after another here).
        progress: ``progress(done, total)`` as points finish (this thread); return False to stop.
        cancel: a ``threading.Event`` that stops the sweep.

    Returns:
        The table in grid order; points not run (a stop) are rows with status ``cancelled``.

    Raises:
        SpecError: a bad grid (field, option and rule named), before any work.
    """
    grid.check(spec, fixed=(SIZED_FIELD,) if sizing is not None else ())
    t0 = time.perf_counter()
    ex = executor or SerialExecutor()
    points = grid.points()
    pieces = chunks(len(points), ex.workers, most=None)
    jobs = [SweepJob(spec, grid, tuple((i, points[i]) for i in r), sizing) for r in pieces]
    counter = Counter(len(points), progress, cancel)
    results = ex.run(sweep_task, jobs, on_progress=counter.on_progress,
                     on_result=lambda k, rows: counter.finished(k, len(rows)), should_stop=counter.should_stop)
    rows: list[dict[str, Any] | None] = [None] * len(points)
    for res in results:
        if res is NOT_RUN:
            continue
        for i, row in res:
            rows[i] = row
    full = [r if r is not None else {**points[i], "status": "cancelled", "error": "the sweep was stopped first"}
            for i, r in enumerate(rows)]
    first = [*grid.columns, *FIRST_COLUMNS] + (["min_base_radius"] if sizing is not None else [])
    meta = {"kind": "sizing" if sizing is not None else "sweep",
            "axes": [a.text() for a in grid.axes], "balance": grid.balance, "points": len(points),
            "units": spec.units, "workers": ex.workers, "time_s": time.perf_counter() - t0,
            "cancelled": any(r is None for r in rows)}
    if sizing is not None:
        meta.update({"sized": SIZED_FIELD, "tolerance": sizing.tolerance(spec.units),
                     "checks": list(sizing.checks) if sizing.checks else "all"})
    return StudyTable.from_rows(full, first, meta)

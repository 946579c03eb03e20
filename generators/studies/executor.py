"""Running independent tasks: the interface the studies and the optimiser's multistart hand
their work to, and :class:`SerialExecutor`, which runs the tasks one after another in this
process (the default everywhere).

A parallel executor — Dask's, in :mod:`cam_workbench.parallel` — implements the same
interface; ``generators`` never imports it (it is passed in), so the mathematics stays free of
any engine.  The contract every executor keeps:

* ``run(fn, items, on_progress=…, on_result=…, should_stop=…)`` calls ``fn(item, ctx)`` for
  every item (anywhere: another process, another machine) and returns the results **in the
  order of** ``items``; an item that never ran (stopped before it started) gives
  :data:`NOT_RUN`.  ``fn`` must be a module-level function and ``item`` plain picklable
  values, so that a result never depends on where it ran.
* ``ctx.report(info)`` inside a task sends ``info`` (plain values) to ``on_progress(index,
  info)``, which runs in the caller's thread; a parallel executor may thin the reports out
  (not every one arrives), the serial one delivers each at once.
* ``should_stop()`` is asked in the caller's thread (between tasks, or every fraction of a
  second while tasks run); once it says True no further task starts and ``ctx.cancelled()``
  becomes True inside the running ones (at once here, within a fraction of a second on Dask),
  which then end early and return what they have.
* ``on_result(index, result)`` runs in the caller's thread as each task ends (in the order
  they end); an exception raised by a task is raised by ``run``.
"""
from __future__ import annotations

from typing import Any, Callable, Protocol, Sequence


class _NotRun:
    """The result of a task that never ran (:data:`NOT_RUN`)."""

    _instance = None

    def __new__(cls) -> "_NotRun":
        if cls._instance is None:
            cls._instance = super().__new__(cls)
        return cls._instance

    def __repr__(self) -> str:
        return "NOT_RUN"

    def __reduce__(self) -> str:
        return "NOT_RUN"


NOT_RUN = _NotRun()


class TaskContext(Protocol):
    """What a running task sees of its executor."""

    def report(self, info: Any) -> None:
        """Send progress (plain values) to the caller's ``on_progress``."""

    def cancelled(self) -> bool:
        """True once the caller asked to stop: end early and return what you have."""


class Executor(Protocol):
    """Runs independent tasks (see the module's docstring for the contract)."""

    #: how many tasks run at the same time (1 for the serial executor)
    workers: int

    def run(self, fn: Callable[[Any, TaskContext], Any], items: Sequence[Any], *,
            on_progress: Callable[[int, Any], Any] | None = None,
            on_result: Callable[[int, Any], Any] | None = None,
            should_stop: Callable[[], bool] | None = None) -> list[Any]:
        ...


class _LocalContext:
    def __init__(self, index: int, on_progress: Callable[[int, Any], Any] | None,
                 should_stop: Callable[[], bool]):
        self.index = index
        self._on_progress = on_progress
        self._should_stop = should_stop

    def report(self, info: Any) -> None:
        if self._on_progress is not None:
            self._on_progress(self.index, info)

    def cancelled(self) -> bool:
        return bool(self._should_stop())


class SerialExecutor:
    """Every task in this process, one after another, in the order given: progress arrives after
    every report and a stop is seen at once (the behaviour of a run without an executor)."""

    workers = 1

    def run(self, fn: Callable[[Any, TaskContext], Any], items: Sequence[Any], *,
            on_progress: Callable[[int, Any], Any] | None = None,
            on_result: Callable[[int, Any], Any] | None = None,
            should_stop: Callable[[], bool] | None = None) -> list[Any]:
        stop = should_stop or (lambda: False)
        results: list[Any] = [NOT_RUN] * len(items)
        for i, item in enumerate(items):
            if stop():
                break
            results[i] = fn(item, _LocalContext(i, on_progress, stop))
            if on_result is not None:
                on_result(i, results[i])
        return results

    def __repr__(self) -> str:
        return "SerialExecutor()"


def chunks(n: int, workers: int, per_worker: int = 4, most: int | None = None) -> list[range]:
    """``range(n)`` cut into consecutive pieces for ``workers`` parallel workers: about
    ``per_worker`` pieces per worker (so that a slow piece does not leave the others idle, and
    a task's fixed cost — a few milliseconds on Dask — is paid once per piece), at most ``most``
    items per piece.  Which piece an item falls in never changes its result."""
    if n <= 0:
        return []
    size = max(1, -(-n // (max(workers, 1) * per_worker)))
    if most is not None:
        size = min(size, most)
    return [range(i, min(i + size, n)) for i in range(0, n, size)]

"""Running studies and optimiser starts on Dask: a local cluster of worker processes, or an
existing cluster given by its scheduler's address.

:func:`dask_executor` gives an executor with the interface of
:mod:`cam_workbench.generators.studies.executor` (``generators`` never imports Dask; the executor is passed
in)::

    from cam_workbench.parallel import dask_executor
    from cam_workbench.generators.optimise import optimise

    with dask_executor(workers=4) as ex:                 # or scheduler="tcp://10.0.0.5:8786"
        res = optimise(spec, multistart=31, executor=ex)  # the same result as without ex

The work is CPU-bound numpy and pure Python, so the local cluster runs **processes** with one
thread each (threads would share one interpreter lock); Dask's nanny sets ``OMP_NUM_THREADS``,
``OPENBLAS_NUM_THREADS`` and ``MKL_NUM_THREADS`` to 1 in them.  Progress travels from the
tasks to the caller as Dask events (``Worker.log_event``, at most one per task every
:data:`REPORT_INTERVAL` seconds, plus each task's last), cancelling as a Dask ``Event`` that the
tasks look at every :data:`REPORT_INTERVAL` seconds; at most :data:`IN_FLIGHT` × workers tasks
are handed to the scheduler at a time, so that a stop leaves the rest unstarted and results do not
pile up in the workers' memory.  Workers of an existing cluster must import the same
cam_workbench (and numpy, scipy, nlopt, OCP for ``batch``) as the caller.  The local cluster's
workers block SIGINT: a terminal's Ctrl-C reaches only the caller (KeyboardInterrupt), which
shuts them down; they import the mathematics as they start (:data:`PRELOAD`).
"""
from __future__ import annotations

import contextlib
import logging
import math
import os
import queue
import signal
import threading
import time
import uuid
from multiprocessing import resource_tracker
from typing import Any, Callable, Iterator, Sequence

from cam_workbench.generators.errors import MissingDependency, SpecError
from cam_workbench.generators.studies.executor import NOT_RUN, TaskContext

try:
    import resource
except ImportError:                 # not POSIX (Windows): no peak memory
    resource = None  # type: ignore[assignment]

#: seconds between two progress reports of one task, and between two looks at the cancel flag
REPORT_INTERVAL = 0.2
#: tasks handed to the scheduler at a time, per worker
IN_FLIGHT = 2
INSTALL_HINT = 'pip install "cam-workbench[dask]"'
#: what a local cluster's workers import as they start: the mathematics every study's task runs
PRELOAD = "cam_workbench.generators"


def import_distributed(what: str = "running on Dask") -> Any:
    """``import distributed``, or MissingDependency naming the ``[dask]`` extra."""
    try:
        import distributed  # deferred: distributed, of the [dask] extra
    except ImportError as exc:
        raise MissingDependency(f"{what} needs Dask (dask.distributed), which is not installed: "
                                f"{INSTALL_HINT}; or --workers 0 to run in this process") from exc
    return distributed


def dask_available() -> bool:
    """Dask's distributed scheduler is importable."""
    try:
        import distributed  # noqa: F401  (deferred: distributed, of the [dask] extra)
    except ImportError:
        return False
    return True


class _DaskContext:
    """The task context on a Dask worker (pickled with the task)."""

    def __init__(self, topic: str, event_name: str, index: int):
        self.topic = topic
        self.event_name = event_name
        self.index = index
        self._sent = -math.inf
        self._held: Any = None
        self._looked = -math.inf
        self._flag = False

    def __getstate__(self) -> dict[str, Any]:
        return {"topic": self.topic, "event_name": self.event_name, "index": self.index}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__init__(state["topic"], state["event_name"], state["index"])  # type: ignore[misc]

    def report(self, info: Any) -> None:
        now = time.monotonic()
        if now - self._sent < REPORT_INTERVAL:
            self._held = info
            return
        self._send(info, now)

    def _send(self, info: Any, now: float) -> None:
        from distributed import get_worker  # deferred: distributed (this runs on a Dask worker)

        self._held = None
        self._sent = now
        get_worker().log_event(self.topic, {"i": self.index, "info": _plain(info)})

    def flush(self) -> None:
        if self._held is not None:
            self._send(self._held, time.monotonic())

    def cancelled(self) -> bool:
        if self._flag:
            return True
        now = time.monotonic()
        if now - self._looked >= REPORT_INTERVAL:
            from distributed import Event  # deferred: distributed (this runs on a Dask worker)

            self._looked = now
            self._flag = bool(Event(self.event_name).is_set())
        return self._flag


def _plain(v: Any) -> Any:
    """``v`` as msgpack's plain types (Dask events carry nothing else)."""
    if isinstance(v, dict):
        return {str(k): _plain(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    if isinstance(v, bool) or v is None or isinstance(v, str):
        return v
    if isinstance(v, int):
        return int(v)
    if isinstance(v, float):
        return float(v)
    try:
        return float(v)
    except (TypeError, ValueError):
        return str(v)


def _call(fn: Callable[[Any, TaskContext], Any], item: Any, ctx: _DaskContext) -> Any:
    """A task on a worker: nothing to do once the caller asked to stop."""
    if ctx.cancelled():
        return NOT_RUN
    try:
        return fn(item, ctx)
    finally:
        ctx.flush()


class DaskExecutor:
    """An executor (:mod:`cam_workbench.generators.studies.executor`) on a Dask client."""

    def __init__(self, client: Any, workers: int, *, address: str | None = None):
        self.client = client
        self.workers = max(1, int(workers))
        self.address = address

    def __repr__(self) -> str:
        return f"DaskExecutor(workers={self.workers}, scheduler={self.address!r})"

    def worker_memory(self) -> dict[str, dict[str, float]]:
        """Every worker's resident memory now and at its peak [MiB] (its process, by psutil and
        ``getrusage``)."""
        return self.client.run(_memory)

    def run(self, fn: Callable[[Any, TaskContext], Any], items: Sequence[Any], *,
            on_progress: Callable[[int, Any], Any] | None = None,
            on_result: Callable[[int, Any], Any] | None = None,
            should_stop: Callable[[], bool] | None = None) -> list[Any]:
        distributed = import_distributed()
        client = self.client
        token = uuid.uuid4().hex
        topic = f"cam-workbench-progress-{token}"
        event = distributed.Event(f"cam-workbench-cancel-{token}", client=client)
        events: queue.SimpleQueue = queue.SimpleQueue()     # ("progress", msg) / ("done", future)
        client.subscribe_topic(topic, lambda ev: events.put(("progress", ev[1])))
        results: list[Any] = [NOT_RUN] * len(items)
        index: dict[str, int] = {}
        pending: dict[str, Any] = {}
        next_i = 0
        stopping = False
        limit = max(IN_FLIGHT * self.workers, self.workers + 1)
        name = getattr(fn, "__name__", "task")

        def submit(i: int) -> None:
            fut = client.submit(_call, fn, items[i], _DaskContext(topic, event.name, i),
                                key=f"{name}-{token}-{i}", pure=False)
            index[fut.key] = i
            pending[fut.key] = fut
            fut.add_done_callback(lambda f: events.put(("done", f)))

        def stop() -> None:
            nonlocal stopping
            if not stopping:
                stopping = True
                event.set()

        try:
            while True:
                if not stopping and should_stop is not None and should_stop():
                    stop()
                while not stopping and next_i < len(items) and len(pending) < limit:
                    submit(next_i)
                    next_i += 1
                if not pending:
                    break
                try:
                    kind, obj = events.get(timeout=0.1)
                except queue.Empty:
                    continue
                if kind == "progress":
                    if on_progress is not None and isinstance(obj, dict) and obj.get("i") in range(len(items)):
                        on_progress(int(obj["i"]), obj["info"])
                    continue
                fut = obj
                if fut.key not in pending:
                    continue
                del pending[fut.key]
                i = index.pop(fut.key)
                if fut.status == "cancelled":
                    continue
                res = fut.result()          # a task's exception is raised here
                fut.release()
                results[i] = res
                if res is not NOT_RUN and on_result is not None:
                    on_result(i, res)
            # the progress that arrived after the last result
            while True:
                try:
                    kind, obj = events.get_nowait()
                except queue.Empty:
                    break
                if kind == "progress" and on_progress is not None and isinstance(obj, dict):
                    on_progress(int(obj["i"]), obj["info"])
        except BaseException:
            # an error, or Ctrl-C: stop the running tasks (they look at the flag), drop the rest
            with contextlib.suppress(Exception):
                event.set()
            with contextlib.suppress(Exception):
                client.cancel(list(pending.values()))
            raise
        finally:
            with contextlib.suppress(Exception):
                client.unsubscribe_topic(topic)
        return results


def _memory() -> dict[str, float]:
    import psutil  # deferred: psutil, distributed's own dependency (this runs on a Dask worker)

    rss = psutil.Process().memory_info().rss / 2**20
    peak = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024      # Linux: KiB
            if resource is not None else float("nan"))
    return {"rss_mib": rss, "peak_rss_mib": peak}


def default_workers() -> int:
    """The local cluster's default size: the CPUs this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:          # not Linux
        return max(1, os.cpu_count() or 1)


@contextlib.contextmanager
def dask_executor(workers: int | None = None, scheduler: str | None = None, *,
                  memory_limit: str | float | None = "auto") -> Iterator[DaskExecutor]:
    """A :class:`DaskExecutor` on a new local cluster of ``workers`` processes (one thread each;
    default: one per CPU), or on the existing cluster whose scheduler is at ``scheduler``
    (``tcp://host:port``; its workers' threads are the executor's ``workers``).  The local
    cluster is shut down, and the client closed, when the block ends.

    Raises:
        MissingDependency: Dask is not installed (the ``[dask]`` extra).
        SpecError: ``workers`` < 1, or no scheduler answers at ``scheduler`` (naming the option).
    """
    distributed = import_distributed()
    if workers is not None and workers < 1:
        raise SpecError("--workers", f"must be ≥ 1 for Dask (0 runs in this process), got {workers}")
    cluster = None
    held: list[int] = []            # a Ctrl-C while the local cluster started
    if scheduler:
        try:
            client = distributed.Client(scheduler, timeout="10s", set_as_default=False)
        except (OSError, TimeoutError) as exc:
            raise SpecError("--scheduler", f"no Dask scheduler answers at {scheduler} ({exc})") from None
        try:
            client.wait_for_workers(1, timeout=30)
        except (OSError, TimeoutError):
            client.close()
            raise SpecError("--scheduler", f"the Dask scheduler at {scheduler} has no workers") from None
        try:
            info = client.scheduler_info(n_workers=-1)
        except TypeError:          # before distributed 2025: every worker without asking
            info = client.scheduler_info()
        n = sum(w.get("nthreads", 1) for w in info["workers"].values())
        address = scheduler
    else:
        n = workers or default_workers()
        # no dashboard; the scheduler's own HTTP server (health, metrics) on a port the system
        # picks, not 8787: another cluster of this machine may have that
        with _sigint_held() as held:
            # each worker imports the mathematics as it starts (``preload``), not in its first
            # task: a Ctrl-C then never finds a worker inside that import, which outlives the
            # scheduler's shutdown and prints its heartbeat errors
            cluster = distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                               dashboard_address=None, memory_limit=memory_limit,
                                               silence_logs=logging.ERROR, preload=[PRELOAD],
                                               scheduler_kwargs={"dashboard_address": "127.0.0.1:0"})
            client = distributed.Client(cluster, set_as_default=False)
        address = cluster.scheduler_address
    try:
        if held:
            raise KeyboardInterrupt
        yield DaskExecutor(client, n, address=address)
    finally:
        _close_quietly(client, cluster)


@contextlib.contextmanager
def _sigint_held() -> Iterator[list[int]]:
    """The local cluster's start: SIGINT blocked in this thread, so that the threads it starts
    (the cluster's event loop, which spawns the worker processes) and the workers inherit the
    block.  A terminal's Ctrl-C goes to every process of the foreground group; blocked, it never
    reaches a worker (which would print its tracebacks), and the caller shuts the cluster down.
    In the main thread, a Ctrl-C during the start is recorded in the yielded list (and raised by
    the caller once the cluster can be closed) instead of raised inside Dask's start-up."""
    held: list[int] = []
    main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, lambda signum, frame: held.append(signum)) if main else None
    blocks = hasattr(signal, "pthread_sigmask")          # POSIX
    if blocks:
        # started by the first worker's spawn, it would unblock SIGINT in the thread that starts
        # it (CPython's ensure_running ends with SIG_UNBLOCK): start it here, before the block
        resource_tracker.ensure_running()
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT}) if blocks else None
    try:
        yield held
    finally:
        if blocks:
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)    # a pending Ctrl-C arrives now: held
        if main:
            signal.signal(signal.SIGINT, previous if previous is not None else signal.default_int_handler)


def _close_quietly(client: Any, cluster: Any) -> None:
    """Close the client and the local cluster (its workers and scheduler) without Dask's log
    lines: after a Ctrl-C the workers' running tasks and connections are cut, which Dask reports
    as errors although nothing went wrong."""
    quiet = logging.getLogger("distributed")
    level = quiet.level
    quiet.setLevel(logging.CRITICAL + 1)
    try:
        with contextlib.suppress(Exception):
            client.close()
        if cluster is not None:
            with contextlib.suppress(Exception):
                cluster.close()
    finally:
        quiet.setLevel(level)

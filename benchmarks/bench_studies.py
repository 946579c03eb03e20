"""Studies on Dask (issue 16): the speed-up of a 200-design sweep and of a 32-start multistart on
a local cluster of 1 and 2 worker processes against the run in this process, as ratios, and
the memory per worker.

    .venv/bin/python benchmarks/bench_studies.py            # 3 interleaved rounds
    .venv/bin/python benchmarks/bench_studies.py --rounds 1 # quicker

Workloads:

* **sweep**: the default cam evaluated (designed and checked, no solid) over
  lift 10…30 mm (rise and return together, 10 values) × law (cycloidal, harmonic, poly345,
  modified_sine) × rise/return angle 80…130° (5 values, the middle dwell balancing) = 200 designs;
* **multistart**: thesis Example 5 (B-spline rise and return, R_b, e and 24 control coordinates,
  minimum area) with ``multistart = 31`` (32 starts), ``max_evaluations = 40`` per start, seed 1.

Method: the clusters are started once (their start-up time is printed on its own and left out of
the ratios); then every round runs the sequential run and the 1- and 2-worker runs of each
workload one after another, the order rotating from round to round so that a change of the
machine's load does not favour one of them; the ratio is sequential / parallel of the medians over
the rounds, with the best-of beside it.  Every parallel result is checked to be the sequential
one (identical tables, identical optimised design).  The machine's load average and the CPU time
the runs got are printed, since other processes may share the cores: "CPU share" is CPU seconds
used / wall seconds (the workers' CPU from ``getrusage`` in each worker process), per process.

More workers: the last table projects the wall time for N workers from the measured time of
every task (the sweep's points, the multistart's starts, timed in the sequential run) by list
scheduling in the order the executor hands them out (the sweep: 4 pieces per worker), plus the
per-task overhead measured on Dask.  It says what N workers would give on N free cores — this
machine has 2.
"""
from __future__ import annotations

import argparse
import os
import resource
import statistics
import sys
import time
from typing import Any, Callable

import numpy as np

import _timing  # noqa: F401  (the project root on sys.path)

from cam_workbench.parallel import dask_executor
from cam_workbench.generators import load_spec
from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.generators.optimise import optimise
from cam_workbench.generators.studies.executor import SerialExecutor, chunks
from cam_workbench.generators.studies.grid import Grid, parse_vary
from cam_workbench.generators.studies.sweep import run_sweep

FIX = _timing.ROOT / "tests" / "fixtures"
GRID = Grid((parse_vary("motion[1].lift,motion[3].lift=10:30:10"),
             parse_vary("motion[1].law,motion[3].law=cycloidal,harmonic,poly345,modified_sine"),
             parse_vary("motion[1].angle,motion[3].angle=80:130:5")), balance="motion[2].angle")
MULTI = dict(multistart=31, max_evaluations=40, seed=1)


class TimingExecutor(SerialExecutor):
    """The serial executor, timing every task (for the projection)."""

    def __init__(self, workers: int = 1):
        self.workers = workers
        self.times: list[float] = []

    def run(self, fn, items, **kw):
        def timed(item, ctx):
            t = time.perf_counter()
            try:
                return fn(item, ctx)
            finally:
                self.times.append(time.perf_counter() - t)

        return super().run(timed, items, **kw)


def sweep(ex=None):
    return run_sweep(example_spec("default"), GRID, executor=ex)


def multistart(ex=None):
    return optimise(load_spec(FIX / "thesis_ex5_initial.toml"), executor=ex, **MULTI)


def _worker_cpu(ex) -> float:
    def cpu():
        r = resource.getrusage(resource.RUSAGE_SELF)
        return r.ru_utime + r.ru_stime

    return sum(ex.client.run(cpu).values())


def timed(fn: Callable[[], Any], ex=None) -> tuple[float, float, Any]:
    """(wall s, CPU s of the processes doing the work, result)."""
    c0 = time.process_time() if ex is None else _worker_cpu(ex)
    t = time.perf_counter()
    res = fn()
    wall = time.perf_counter() - t
    c1 = time.process_time() if ex is None else _worker_cpu(ex)
    return wall, c1 - c0, res


def same(a, b, kind: str) -> bool:
    if kind == "sweep":
        return a.rows == b.rows
    return np.array_equal(a.design, b.design) and a.value == b.value and a.evaluations == b.evaluations


def project(task_times: list[float], workers: int, overhead: float) -> float:
    """Wall time of list scheduling: each task to the worker free first, in order."""
    free = [0.0] * workers
    for t in task_times:
        k = int(np.argmin(free))
        free[k] += t + overhead
    return max(free)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    print(f"CPUs usable by this process: {len(os.sched_getaffinity(0))}; load average at start "
          f"{', '.join(f'{x:.2f}' for x in os.getloadavg())}\n")
    t = time.perf_counter()
    c1 = dask_executor(workers=1)
    ex1 = c1.__enter__()
    t1 = time.perf_counter() - t
    t = time.perf_counter()
    c2 = dask_executor(workers=2)
    ex2 = c2.__enter__()
    t2 = time.perf_counter() - t
    mem0 = {1: ex1.worker_memory(), 2: ex2.worker_memory()}
    try:
        configs = [("sequential", None), ("1 worker", ex1), ("2 workers", ex2)]
        works = {"sweep": sweep, "multistart": multistart}
        walls: dict[tuple[str, str], list[float]] = {}
        cpus: dict[tuple[str, str], list[float]] = {}
        ref: dict[str, Any] = {}
        identical = True
        for rnd in range(args.rounds):
            order = configs[rnd % 3:] + configs[: rnd % 3]
            for wname, fn in works.items():
                for cname, ex in order:
                    wall, cpu, res = timed(lambda: fn(ex), ex)
                    walls.setdefault((wname, cname), []).append(wall)
                    cpus.setdefault((wname, cname), []).append(cpu)
                    if cname == "sequential":
                        ref.setdefault(wname, res)
                    elif wname in ref and not same(res, ref[wname], wname):
                        identical = False
                    # the sequential result may come after a parallel one in a round: check then
                    if cname == "sequential" and wname in ref and not same(res, ref[wname], wname):
                        identical = False
            print(f"round {rnd + 1}: " + ", ".join(f"{w} {c} {walls[(w, c)][-1]:.2f} s"
                                                   for w in works for c, _ in configs), flush=True)
        mem = {1: ex1.worker_memory(), 2: ex2.worker_memory()}
        # per-task times for the projection (sequential, this process)
        tex = TimingExecutor(workers=1000)                 # one point per piece
        sweep(tex)
        point_times = list(tex.times)
        tex = TimingExecutor()
        multistart(tex)
        start_times = list(tex.times)
    finally:
        c2.__exit__(None, None, None)
        c1.__exit__(None, None, None)
    print(f"\nload average at the end {', '.join(f'{x:.2f}' for x in os.getloadavg())}; "
          f"local cluster start-up: 1 worker {t1:.1f} s, 2 workers {t2:.1f} s (not in the ratios); "
          f"every parallel result identical to the sequential one: {'yes' if identical else 'NO'}\n")
    print("| workload | run | wall median [s] | best [s] | speed-up (median) | speed-up (best) | CPU share |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for wname in works:
        seq = walls[(wname, "sequential")]
        for cname, _ in configs:
            w = walls[(wname, cname)]
            share = statistics.median(c / x for c, x in zip(cpus[(wname, cname)], w))
            print(f"| {wname} | {cname} | {statistics.median(w):.2f} | {min(w):.2f} | "
                  f"{statistics.median(seq) / statistics.median(w):.2f}× | {min(seq) / min(w):.2f}× | {share:.2f} |")
    print("\nMemory per worker process (resident set; MiB): after start-up → after the runs (peak)\n")
    print("| cluster | worker | after start-up | after the runs | peak |")
    print("|---|---|---:|---:|---:|")
    for n in (1, 2):
        for k, addr in enumerate(sorted(mem[n])):
            m0 = mem0[n].get(addr, {}).get("rss_mib", float("nan"))
            print(f"| {n} worker{'s' if n > 1 else ''} | {k + 1} | {m0:.0f} | {mem[n][addr]['rss_mib']:.0f} | "
                  f"{mem[n][addr]['peak_rss_mib']:.0f} |")
    this = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"\n(this process, which ran the sequential runs: peak {this:.0f} MiB)")
    # overhead per task on Dask: (1-worker wall − sequential wall) / tasks
    n_pieces_1 = len(chunks(GRID.size, 1))
    ov_sweep = max(0.0, (statistics.median(walls[("sweep", "1 worker")]) - statistics.median(walls[("sweep", "sequential")])) / n_pieces_1)
    ov_multi = max(0.0, (statistics.median(walls[("multistart", "1 worker")])
                         - statistics.median(walls[("multistart", "sequential")])) / len(start_times))
    print(f"\nProjection for more workers (list scheduling of the measured task times on N free cores; "
          f"Dask overhead per task as measured on 1 worker: sweep {ov_sweep * 1e3:.0f} ms per piece, "
          f"multistart {ov_multi * 1e3:.0f} ms per start; the multistart's starts take "
          f"{min(start_times):.2f}–{max(start_times):.2f} s):\n")
    print("| N workers | sweep: projected wall [s] | speed-up | multistart: projected wall [s] | speed-up |")
    print("|---:|---:|---:|---:|---:|")
    seq_sweep, seq_multi = sum(point_times), sum(start_times)
    for n in (1, 2, 4, 8, 16, 32):
        pieces = [sum(point_times[i] for i in r) for r in chunks(len(point_times), n)]
        ws = project(pieces, n, ov_sweep)
        wm = project(start_times, n, ov_multi)
        print(f"| {n} | {ws:.2f} | {seq_sweep / ws:.2f}× | {wm:.2f} | {seq_multi / wm:.2f}× |")


if __name__ == "__main__":
    sys.exit(main())

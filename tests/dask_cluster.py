"""A real Dask cluster on the loopback address for the tests: ``dask scheduler`` and two
``dask worker`` processes (one thread each), started as the ``dask`` command line starts them, on
ports the system picks (``--port 0``; the address is read from the scheduler file), each in a
session of its own so that the fixture ends exactly the processes it started (and their
children: the workers' nannies spawn the worker processes), by their process-group ids."""
from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Iterator

from .conftest import ROOT, SAFETY_S

WORKERS = 2


def _dask_command() -> list[str]:
    exe = Path(sys.executable).with_name("dask")
    return [str(exe)] if exe.exists() else ([shutil.which("dask")] if shutil.which("dask") else
                                             [sys.executable, "-m", "dask"])


def _stop(procs: list[subprocess.Popen]) -> None:
    for p in reversed(procs):
        if p.poll() is None:
            try:
                os.killpg(p.pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
    deadline = time.monotonic() + 20
    for p in reversed(procs):
        try:
            p.wait(timeout=max(0.1, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            p.wait(timeout=10)


def loopback_cluster(folder: Path) -> Iterator[str]:
    """Start the scheduler and the workers; yield the scheduler's address; stop them all."""
    folder.mkdir(parents=True, exist_ok=True)
    sched_file = folder / "scheduler.json"
    # the workers import this checkout's packages (as the tests do)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))}
    dask = _dask_command()
    procs: list[subprocess.Popen] = []
    logs = []
    try:
        log = open(folder / "scheduler.log", "w")
        logs.append(log)
        procs.append(subprocess.Popen(
            [*dask, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
             "--dashboard-address", "127.0.0.1:0",
             "--scheduler-file", str(sched_file)],
            cwd=ROOT, env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True))
        # the scheduler writes its address when it listens: waited for (SAFETY_S only against a hang)
        deadline = time.monotonic() + SAFETY_S
        address = None
        while time.monotonic() < deadline and address is None:
            if procs[0].poll() is not None:
                raise RuntimeError(f"dask scheduler exited: {(folder / 'scheduler.log').read_text()[-2000:]}")
            try:
                address = json.loads(sched_file.read_text())["address"]
            except (OSError, ValueError, KeyError):
                time.sleep(0.2)
        if address is None:
            raise RuntimeError(f"dask scheduler did not write its address within {SAFETY_S:g} s")
        for k in range(WORKERS):
            log = open(folder / f"worker{k}.log", "w")
            logs.append(log)
            procs.append(subprocess.Popen(
                [*dask, "worker", address, "--nthreads", "1", "--nworkers", "1", "--host", "127.0.0.1",
                 "--no-dashboard", "--name", f"test-worker-{k}", "--local-directory", str(folder / f"w{k}")],
                cwd=ROOT, env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True))
        from distributed import Client

        with Client(address, timeout=f"{SAFETY_S:g}s", set_as_default=False) as client:
            client.wait_for_workers(WORKERS, timeout=SAFETY_S)
        yield address
    finally:
        _stop(procs)
        for log in logs:
            log.close()

"""Shared by the benchmark scripts: the project root on sys.path and best-of-N timing."""
from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import Callable

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))


def best_of(fn: Callable[[], object], repeat: int = 3) -> float:
    """Shortest wall time [s] of ``repeat`` calls (the least disturbed by other load)."""
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def cpu_best_of(fn: Callable[[], object], repeat: int = 5) -> float:
    """Shortest process CPU time [s] of ``repeat`` calls: less disturbed than wall time when other
    processes share the cores (numpy here runs single-threaded)."""
    times = []
    for _ in range(repeat):
        t = time.process_time()
        fn()
        times.append(time.process_time() - t)
    return min(times)

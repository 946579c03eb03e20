"""Speed of the B-spline lift law's θ(u) inversion and of the design checks, as ratios against
naive per-sample methods (scipy brentq on scipy's BSpline; a Python loop over samples).

    .venv/bin/python benchmarks/bench_bspline_checks.py
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy.interpolate import BSpline
from scipy.optimize import brentq

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from cam_workbench.generators import load_spec  # noqa: E402
from cam_workbench.generators.checks.design import StateModel, check_samples, constraint_arrays, run_checks  # noqa: E402
from cam_workbench.generators.motion import MotionProgram  # noqa: E402


def best_of(fn, repeats=5):
    best = math.inf
    for _ in range(repeats):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def main() -> None:
    spec = load_spec(ROOT / "tests" / "fixtures" / "thesis_ex5_final.toml")
    lift = MotionProgram.from_spec(spec).curves[0]
    ref = BSpline(lift.knots, lift.x, lift.degree)

    print("θ(u) inversion, thesis Example 5 rise (order 5, 11 control points)")
    for n in (1_000, 10_000, 100_000):
        theta = np.linspace(0, lift.span, n)
        t_vec, u = best_of(lambda: lift.u_of_theta(theta))
        err = np.max(np.abs(lift.theta_at(u) - theta))
        m = min(n, 2000)
        sub = theta[:: max(1, n // m)][:m]
        t_loop, _ = best_of(lambda: [brentq(lambda x, th=th: ref(x) - th, 0.0, lift.u_max, xtol=1e-15)
                                     for th in sub], repeats=1)
        t_loop *= n / len(sub)
        print(f"  n = {n:7d}: vectorised Newton {t_vec * 1e3:8.2f} ms (max |θ(u) − θ| {err:.1e}); "
              f"per-sample brentq on scipy BSpline ≈ {t_loop * 1e3:9.1f} ms; ratio {t_loop / t_vec:7.1f}x")

    print("\ndesign checks, thesis Example 5")
    for sampling in ("thesis71", "dense"):
        t, _ = best_of(lambda: run_checks(spec, sampling=sampling))
        print(f"  run_checks({sampling!r:10}): {t * 1e3:7.1f} ms")
    model = StateModel(spec)
    for samples in (71, 1001, 10001):
        cs = check_samples(model.program, "dense", samples)
        t_vec, ca = best_of(lambda: constraint_arrays(spec, cs, model))
        idx = np.arange(0, len(cs.theta), max(1, len(cs.theta) // 200))
        t_loop, _ = best_of(lambda: [model.state(cs.theta[i:i + 1], cs.segment[i:i + 1]) for i in idx], repeats=1)
        t_loop *= len(cs.theta) / len(idx)
        print(f"  constraint arrays at {len(cs.theta):6d} points: {t_vec * 1e3:7.2f} ms; "
              f"a Python loop over points ≈ {t_loop * 1e3:8.1f} ms; ratio {t_loop / t_vec:6.1f}x")


if __name__ == "__main__":
    main()

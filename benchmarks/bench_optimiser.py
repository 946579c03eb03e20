"""Optimiser benchmark: thesis Examples 5–7 (minimum area) from their initial designs with the
exact sensitivities (the default) beside the same SLSQP run fed plain forward finite differences
(step 1e-7 in the scaled variables: n + 1 model evaluations per gradient), and the cost of one
evaluation of each objective.

    .venv/bin/python benchmarks/bench_optimiser.py
"""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np

import generators.optimise.run as run
from generators import load_spec
from generators.checks.areas import thesis_area
from generators.machining.cutting_time import thesis_cutting_time
from generators.optimise import optimise
from generators.optimise.model import SmoothModel

FIX = Path(__file__).resolve().parents[1] / "tests" / "fixtures"


class FiniteDifferenceProblem(run.ScaledProblem):
    """The optimiser's problem with its gradients replaced by forward differences."""

    step = 1e-7

    def evaluate(self, z, grad):
        if not grad:
            return super().evaluate(z, False)
        key = z.tobytes()
        if getattr(self, "_fd_key", None) == key:
            return self._fd_val
        fs, _, g, _, fp, v = super().evaluate(z, False)
        df = np.zeros(self.n)
        jac = np.zeros((g.size, self.n))
        for i in range(self.n):
            zi = z.copy()
            zi[i] += self.step
            f2, _, g2, _, _, _ = super().evaluate(zi, False)
            df[i] = (f2 - fs) / self.step
            jac[:, i] = (g2 - g) / self.step
        self._fd_key, self._fd_val = key, (fs, df, g, jac, fp, v)
        return self._fd_val


def counted(fn):
    def wrapper(*a, **k):
        wrapper.calls += 1
        return fn(*a, **k)
    wrapper.calls = 0
    return wrapper


def one_run(spec, finite_differences: bool):
    original_problem, original_window = run.ScaledProblem, SmoothModel.window_max
    counter = counted(original_window)
    SmoothModel.window_max = counter
    if finite_differences:
        run.ScaledProblem = FiniteDifferenceProblem
    try:
        t0 = time.perf_counter()
        res = optimise(spec, objective="area")
        dt = time.perf_counter() - t0
    finally:
        run.ScaledProblem, SmoothModel.window_max = original_problem, original_window
    return res, dt, counter.calls


def algorithms() -> None:
    """Every local solver on Example 5 (minimum area, initial design), against SLSQP."""
    print("\n## The solvers on Example 5 (minimum area, initial design, checks.convex = true)\n")
    print("| algorithm | time [s] | evaluations | windows per rise/return | area [in²] | area / SLSQP's | "
          "dense checks |")
    print("|---|---:|---:|---:|---:|---:|---|")
    spec = load_spec(FIX / "thesis_ex5_initial.toml").replace(**{"checks.convex": True})
    ref = None
    for algo in ("slsqp", "mma", "ccsaq", "cobyla", "bobyqa"):
        t0 = time.perf_counter()
        res = optimise(spec, objective="area", algorithm=algo)
        dt = time.perf_counter() - t0
        ref = res.value if ref is None else ref
        verdict = "pass" if res.feasible else "FAIL: " + ", ".join(
            f"{c.name} {c.value:.4g} {c.unit}" for c in res.checks.results if not c.passed)
        print(f"| {algo} | {dt:.1f} | {res.evaluations} | {res.details.get('windows', '—')} | {res.value:.4f} | "
              f"{res.value / ref:.4f} | {verdict} |", flush=True)


def main() -> None:
    print("## Minimum area from the thesis' initial designs (checks.convex = true), SLSQP\n")
    print("| example | gradients | time [s] | solver evaluations | model evaluations | area [in²] | "
          "dense checks | FD / exact time |")
    print("|---|---|---:|---:|---:|---:|---|---:|")
    for ex in (5, 6, 7):
        spec = load_spec(FIX / f"thesis_ex{ex}_initial.toml").replace(**{"checks.convex": True})
        exact, t_exact, m_exact = one_run(spec, False)
        fd, t_fd, m_fd = one_run(spec, True)
        for name, res, dt, m in (("exact", exact, t_exact, m_exact), ("finite differences", fd, t_fd, m_fd)):
            ratio = f"{t_fd / t_exact:.1f}×" if name != "exact" else ""
            print(f"| {ex} | {name} | {dt:.2f} | {res.evaluations} | {m} | {res.value:.4f} | "
                  f"{'pass' if res.feasible else 'FAIL: ' + ', '.join(res.checks.failed)} | {ratio} |")
    algorithms()
    spec = load_spec(FIX / "thesis_ex1_final.toml")
    print("\n## One evaluation (thesis Example 1's final design)\n")
    from generators.optimise.space import DesignSpace

    space = DesignSpace(spec.replace(**{"optimise.objective": "machining_time"}))
    model = SmoothModel(space)
    ch = tuple((f, 1.0) for f in model.families)
    for name, fn in (("constraints + Jacobian (80 windows × 2 B-splines)", lambda: model.window_max(space.p0, ch)),
                     ("constraints only", lambda: model.window_max(space.p0, ch, grad=False)),
                     ("area + gradient (Eq. 4.21–4.27)", lambda: model.integral(space.p0, "thesis_area")),
                     ("thesis cutting time (Eq. 4.4–4.20, 4 000 samples/segment)",
                      lambda: thesis_cutting_time(spec)),
                     ("thesis area, cam_area.thesis_area", lambda: thesis_area(spec))):
        fn()
        n = 20
        t0 = time.perf_counter()
        for _ in range(n):
            fn()
        print(f"- {name}: {(time.perf_counter() - t0) / n * 1e3:.2f} ms")


if __name__ == "__main__":
    main()

"""Optimiser benchmark: thesis Examples 5–7 (minimum area) from their initial designs with the
exact sensitivities (the default) beside the same SLSQP run fed plain forward finite differences
(step 1e-7 in the scaled variables: n + 1 model evaluations per gradient), the cost of one
evaluation of each objective, and every follower kind on Example 5's B-spline lifts (the
oscillating and flat kinds' exact partials against finite differences, and the cost of one
evaluation against the translating roller's).

    .venv/bin/python benchmarks/bench_optimiser.py          # everything
    .venv/bin/python benchmarks/bench_optimiser.py kinds    # the follower kinds only
    .venv/bin/python benchmarks/bench_optimiser.py variables  # body variables, polynomial points
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

import _timing  # noqa: F401  (the project root on sys.path)

import cam_workbench.generators.optimise.driver as driver
from cam_workbench.generators import load_spec
from cam_workbench.generators.checks.areas import thesis_area
from cam_workbench.generators.machining.cutting_time import thesis_cutting_time
from cam_workbench.generators.optimise import optimise
from cam_workbench.generators.optimise.model import SmoothModel
from cam_workbench.generators.optimise.problem import ScaledProblem

FIX = Path(__file__).resolve().parents[1] / "tests" / "fixtures"


class FiniteDifferenceProblem(ScaledProblem):
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


def one_run(spec, finite_differences: bool, **kw):
    original_problem, original_window = driver.ScaledProblem, SmoothModel.window_max
    counter = counted(original_window)
    SmoothModel.window_max = counter
    if finite_differences:
        driver.ScaledProblem = FiniteDifferenceProblem
    try:
        t0 = time.perf_counter()
        res = optimise(spec, objective="area", **kw)
        dt = time.perf_counter() - t0
    finally:
        driver.ScaledProblem, SmoothModel.window_max = original_problem, original_window
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


#: Example 5's B-spline lifts (1 in; 15° of arm for the oscillating kinds) with each follower kind
KINDS = {
    "translating roller": ({"kind": "roller", "offset": 0.0, "roller_radius": 0.425, "mass": 0.02,
                            "preload": 340.0}, 1.0),
    "oscillating roller": ({"kind": "roller", "motion": "oscillating", "pivot_distance": 6.0, "arm_length": 4.5,
                            "roller_radius": 0.425, "arm_inertia": 0.3, "preload_torque": 1200.0,
                            "spring_torque_rate": 100.0}, 15.0),
    "translating flat face": ({"kind": "flat", "offset": 0.1, "face_width": 4.0, "mass": 0.02, "preload": 340.0,
                               "spring_rate": 20.0}, 1.0),
    "oscillating flat face": ({"kind": "flat", "motion": "oscillating", "pivot_distance": 8.0, "face_offset": 0.4,
                               "arm_length": 5.0, "face_width": 6.0, "arm_inertia": 0.3, "preload_torque": 1200.0},
                              12.0),
}


def kind_spec(name: str):
    from cam_workbench.generators.spec import CamSpec

    follower, lift = KINDS[name]
    data = load_spec(FIX / "thesis_ex5_initial.toml").to_dict()
    data["follower"] = follower
    for m in data["motion"]:
        if "lift" in m:
            m["lift"] = lift
    data["material"]["allowable_stress"] = 400000.0
    return CamSpec.from_dict(data)


def kinds() -> None:
    """Every follower kind on Example 5's B-spline lifts (R_b, the follower's position and every
    control point free, minimum area): exact partials vs forward finite differences, and one
    evaluation of the constraints with their Jacobian against the translating roller's."""
    from cam_workbench.generators.optimise.space import DesignSpace

    print("\n## Every follower kind: Example 5's B-spline lifts, minimum area, auto variables, SLSQP\n")
    print("| follower | variables | gradients | time [s] | solver evaluations | model evaluations | area: start → "
          "optimised [in²] | dense checks | FD / exact time |")
    print("|---|---:|---|---:|---:|---:|---:|---|---:|")
    for name in KINDS:
        spec = kind_spec(name)
        exact, t_exact, m_exact = one_run(spec, False, max_evaluations=600)
        fd, t_fd, m_fd = one_run(spec, True, max_evaluations=600)
        for how, res, dt, m in (("exact", exact, t_exact, m_exact), ("finite differences", fd, t_fd, m_fd)):
            ratio = f"{t_fd / t_exact:.1f}×" if how != "exact" else ""
            verdict = "pass" if res.feasible else "FAIL: " + ", ".join(res.checks.failed)
            print(f"| {name} | {len(res.variables)} | {how} | {dt:.2f} | {res.evaluations} | {m} | "
                  f"{res.initial_value:.4f} → {res.value:.4f} | {verdict} ({res.status}) | {ratio} |", flush=True)
    print("\n### One evaluation of the constraints and their Jacobian (80 windows × 2 B-splines)\n")
    print("| follower | families | with Jacobian [ms] | / translating roller | values only [ms] | / translating roller |")
    print("|---|---|---:|---:|---:|---:|")
    ref = None
    for name in KINDS:
        space = DesignSpace(kind_spec(name))
        model = SmoothModel(space)
        t_j = best_of(lambda: model.check_rows(space.p0, True, 80), 20)
        t_v = best_of(lambda: model.check_rows(space.p0, False, 80), 20)
        ref = ref or (t_j, t_v)
        print(f"| {name} | {', '.join(model.families)} | {t_j * 1e3:.2f} | {t_j / ref[0]:.2f}× | {t_v * 1e3:.2f} | "
              f"{t_v / ref[1]:.2f}× |", flush=True)


def new_variables() -> None:
    """The cost of the design variables of issues 14–15: one evaluation of the constraint rows with
    their Jacobian with and without a groove cam's body variables (3 more window channels) and a
    polynomial rise's point lifts (the same Bézier segment, one more column), and the runs."""
    import sys as _sys

    _sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from cam_workbench.generators.optimise.space import DesignSpace
    from tests.test_optimiser_groove import groove
    from tests.test_optimiser_points import cam

    print("\n## New design variables: one evaluation of the rows + Jacobian (80 windows), and the run\n")
    print("| problem | variables | rows + Jacobian [ms] | / without | run [s] | evaluations |")
    print("|---|---|---:|---:|---:|---:|")
    cases = [("groove cam, area", groove(variables="base_radius, offset", objective="area"), None),
             ("groove cam, outer_diameter", groove(variables="base_radius, offset, outer_diameter, clearance",
                                                   objective="outer_diameter", outer_diameter_min=40.0), 0),
             ("polynomial rise, area", cam(variables="base_radius", objective="area"), None),
             ("polynomial rise, area", cam(variables="base_radius, points", objective="area"), 2)]
    ref = None
    for label, spec, against in cases:
        space = DesignSpace(spec)
        model = SmoothModel(space)
        t_j = best_of(lambda: model.check_rows(space.p0, True, 80), 20)
        if against is None:
            ref = t_j
        t0 = time.perf_counter()
        res = optimise(spec)
        dt = time.perf_counter() - t0
        ratio = f"{t_j / ref:.2f}×" if against is not None else ""
        print(f"| {label} | {', '.join(space.labels)} | {t_j * 1e3:.2f} | {ratio} | {dt:.2f} | {res.evaluations} |",
              flush=True)


def best_of(fn, repeat: int) -> float:
    fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    if sys.argv[1:] == ["kinds"]:
        kinds()
        return
    if sys.argv[1:] == ["variables"]:
        new_variables()
        return
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
    kinds()
    new_variables()
    spec = load_spec(FIX / "thesis_ex1_final.toml")
    print("\n## One evaluation (thesis Example 1's final design)\n")
    from cam_workbench.generators.optimise.space import DesignSpace

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

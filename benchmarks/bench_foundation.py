"""Foundation benchmarks: PH spline solve (banded O(M) Newton vs a dense-Jacobian Newton),
memory per junction, and solid + STEP build time.  Prints a Markdown table with ratios.

    .venv/bin/python benchmarks/bench_foundation.py
"""
from __future__ import annotations

import tempfile
import time
import tracemalloc
from pathlib import Path

import numpy as np

from _timing import best_of  # noqa: E402  (puts the project root on sys.path)

from cam_workbench.generators.followers.translating import FollowerGeometry  # noqa: E402
from cam_workbench.generators.motion import MotionProgram  # noqa: E402
from cam_workbench.generators.curves.ph_spline import solve_closed_ph_spline  # noqa: E402
from cam_workbench.generators.spec import default_spec  # noqa: E402




def junctions(m: int) -> np.ndarray:
    spec = default_spec()
    th = 2 * np.pi * np.arange(m) / m
    return FollowerGeometry.from_spec(spec).pitch_points(th, MotionProgram.from_spec(spec).s(th))


def bench_ph() -> list[str]:
    rows = ["| M | banded Newton [ms] | iterations | peak memory [bytes/M] | dense Newton [ms] | dense / banded |",
            "|---:|---:|---:|---:|---:|---:|"]
    base = None
    for m in (100, 1_000, 10_000, 100_000):
        q = junctions(m)
        sp = solve_closed_ph_spline(q)
        t_b = best_of(lambda: solve_closed_ph_spline(q), 5 if m <= 10_000 else 3)
        tracemalloc.start()
        solve_closed_ph_spline(q)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        if m <= 2_000:
            t_d = best_of(lambda: solve_closed_ph_spline(q, method="dense"), 3)
            dense = f"{t_d * 1e3:.1f} | {t_d / t_b:.0f}×"
        else:
            dense = "(O(M³): not run) | —"
        base = base or t_b / m
        rows.append(f"| {m:,} | {t_b * 1e3:.2f} | {sp.iterations} | {peak / m:.0f} | {dense} |")
    # scaling: time per junction relative to M = 100
    return rows


def bench_solid() -> list[str]:
    from cam_workbench.kernel import solids as occ_build
    from cam_workbench.kernel.step import write_step
    from cam_workbench.generators.cam_design import design_cam

    rows = ["| M | design (spline, offset, checks) [ms] | solid [ms] | STEP write [ms] | total [ms] | STEP size [kB] |",
            "|---:|---:|---:|---:|---:|---:|"]
    spec0 = default_spec()
    # warm-up: OCP loads its libraries on first use
    d0 = design_cam(spec0)
    with tempfile.TemporaryDirectory() as tmp:
        write_step(occ_build.cam_solid(d0), Path(tmp) / "w.step")
        for m in (60, 1_000):
            spec = spec0.replace(**{"pitch.segments": m})
            t0 = time.perf_counter()
            d = design_cam(spec)
            t1 = time.perf_counter()
            solid = occ_build.cam_solid(d)
            t2 = time.perf_counter()
            path = Path(tmp) / f"cam{m}.step"
            write_step(solid, path)
            t3 = time.perf_counter()
            rows.append(f"| {m:,} | {(t1 - t0) * 1e3:.0f} | {(t2 - t1) * 1e3:.0f} | {(t3 - t2) * 1e3:.0f} | "
                        f"{(t3 - t0) * 1e3:.0f} | {path.stat().st_size / 1e3:.0f} |")
    return rows


def main() -> None:
    print("### PH spline solve (closed C² PH quintic, default cam)\n")
    print("\n".join(bench_ph()))
    print("\n### Solid and STEP (after imports and a warm-up build)\n")
    print("\n".join(bench_solid()))


if __name__ == "__main__":
    main()

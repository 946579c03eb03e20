"""The thesis' seven examples (Teoh 1989, Ch. 7) optimised from their initial designs, beside the
thesis' final designs evaluated with the same formulas and the same dense checks — the README's
"thesis vs this project" table.

Examples 1–4: the thesis' cutting time (Eq. 4.4–4.20; feed 9.333e-2 in/s, 0.4 s per turn,
ε = 0.01 in), its final designs at the orientations that reproduce its path lengths (Example 2:
−B(3); Example 4: B(3) − 20°).  Examples 5–7: the area of Eq. 4.21–4.27.  Every design is checked
with the thesis' constraints (checks.convex = true: Eq. 5.7 with the signed radius of curvature),
densely.  Two runs per example: every variable free (the default bounds: R_b ∈ [½, 2] × the
initial), and R_b held at the thesis' final value.

    .venv/bin/python benchmarks/bench_thesis_examples.py
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

FIX = Path(__file__).resolve().parents[1] / "tests" / "fixtures"
sys.path.insert(0, str(FIX))

import thesis_examples  # noqa: E402

from cam_workbench.generators import load_spec  # noqa: E402
from cam_workbench.generators.checks.design import run_checks  # noqa: E402
from cam_workbench.generators.optimise import final_value, optimise  # noqa: E402

MACHINING = {"machining.feed_rate": 9.333e-2 * 60, "optimise.turn_time": 0.4, "optimise.machining_tolerance": 0.01}
PRINTED_TIME = {1: (965.55, 1530), 2: (1381.24, 2192), 3: (1377.60, 2196), 4: (676.57, 1062)}


def orientation(ex: int, which: str) -> float:
    """B(3) in this project's convention [deg]."""
    b = thesis_examples.split(ex, which)["orientation"]
    if ex == 2 and which == "final":
        b = -b
    if ex == 4:
        b -= math.radians(20.0)
    return math.degrees(b)


def spec_of(ex: int, which: str, **extra):
    changes = {"checks.convex": True}
    if ex <= 4:
        changes.update(MACHINING, **{"optimise.objective": "machining_time",
                                     "optimise.blank_orientation": orientation(ex, which)})
    changes.update(extra)
    return load_spec(FIX / f"thesis_ex{ex}_{which}.toml").replace(**changes)


def worst(checks) -> str:
    if not checks.passed:
        parts = []
        for r in checks.results:
            if r.status == "fail":
                parts.append(f"{r.name} {r.value:.4g} (limit {r.limit:g})")
        return "FAIL: " + "; ".join(parts)
    best = None
    for r in checks.results:
        if r.value is None or r.limit is None or r.status == "skipped" or r.name == "oscillation":
            continue
        scale = abs(r.limit) if r.limit else 1.0
        if r.name == "separation":
            scale = 1.0
        m = (r.limit - r.value) / scale if r.kind == "max" else (r.value - r.limit) / scale
        if best is None or m < best[0]:
            best = (m, f"{r.name} {r.value:.5g} (limit {r.limit:g})")
    return "pass; closest: " + best[1]


def main() -> None:
    print("| ex | objective | thesis final: value (this code) | thesis printed | thesis final, dense checks | "
          "run | optimised | dense checks | R_b | evaluations | time [s] |")
    print("|---|---|---:|---:|---|---|---:|---|---:|---:|---:|")
    for ex in range(1, 8):
        fin = spec_of(ex, "final")
        obj = fin.optimise.objective
        v_thesis = final_value(obj, fin)
        printed = (f"{PRINTED_TIME[ex][0]} s, {PRINTED_TIME[ex][1]} turns" if ex <= 4
                   else f"{thesis_examples.EXAMPLES[ex]['area'][1]} in²")
        thesis_checks = worst(run_checks(fin))
        runs = [("all free", spec_of(ex, "initial"), {}),
                (f"R_b = {fin.cam.base_radius:g}", spec_of(ex, "initial", **{"cam.base_radius": fin.cam.base_radius}),
                 {"variables": "offset, control_points" + (", orientation" if ex <= 4 else "")})]
        for name, start, kw in runs:
            t0 = time.perf_counter()
            res = optimise(start, **kw)
            dt = time.perf_counter() - t0
            extra = ""
            if ex <= 4:
                ct = res.details["cutting_time"]["final"]
                extra = f" ({ct['turns']} turns, {ct['path_length']:.2f} in)"
            unit = "s" if ex <= 4 else "in²"
            print(f"| {ex} | {obj} | {v_thesis:.2f} {unit} | {printed} | {thesis_checks} | {name} | "
                  f"{res.value:.2f} {unit}{extra} | {worst(res.checks)} | {res.spec.cam.base_radius:.4f} | "
                  f"{res.evaluations} | {dt:.1f} |", flush=True)


if __name__ == "__main__":
    main()

"""Follower kinds at the same M: the design (pitch curve, exact profile, checks, deviation
measured on ≥ 18 000 samples) of each kind against the translating roller's, as ratios — the
issue's target is an oscillating roller at no more than 1.5× the translating one — with the
accuracy each reaches.

    .venv/bin/python benchmarks/bench_followers.py
"""
from __future__ import annotations

import copy

from _timing import cpu_best_of

from cam_workbench.generators import design_cam
from cam_workbench.generators.spec import DEFAULT_SPEC_DICT, CamSpec


def spec(kind: str, motion: str, m: int) -> CamSpec:
    d = copy.deepcopy(DEFAULT_SPEC_DICT)
    d["pitch"] = {"representation": "ph", "segments": m}
    f: dict = {"kind": kind, "motion": motion}
    if kind == "roller":
        f["roller_radius"] = 8.0
    if motion == "oscillating":
        f["pivot_distance"] = 60.0
        if kind == "flat":
            f["face_offset"] = 5.0
        else:
            f["arm_length"] = 45.0
        f.update(arm_inertia=2000.0, preload_torque=800.0, spring_torque_rate=500.0)
        for seg in d["motion"]:
            if "lift" in seg:
                seg["lift"] = 15.0                      # arm degrees
    else:
        f.update(mass=0.5, preload=20.0, spring_rate=1.0)
    d["follower"] = f
    return CamSpec.from_dict(d)


KINDS = [("roller", "translating"), ("knife", "translating"), ("flat", "translating"),
         ("roller", "oscillating"), ("knife", "oscillating"), ("flat", "oscillating")]


def main() -> None:
    print("| M | follower | design CPU [ms] | ratio to translating roller | max deviation | profile error [mm] |")
    print("|---|---|---|---|---|---|")
    for m in (60, 240):
        specs = [spec(kind, motion, m) for kind, motion in KINDS]
        best = [float("inf")] * len(specs)
        for _ in range(7):              # interleaved, so that a burst of other load hits every kind alike
            for i, s in enumerate(specs):
                best[i] = min(best[i], cpu_best_of(lambda: design_cam(s), repeat=1))
        base = best[0]
        for (kind, motion), s, t in zip(KINDS, specs, best):
            d = design_cam(s)
            unit = "deg" if motion == "oscillating" else "mm"
            print(f"| {m} | {motion} {kind} | {1e3 * t:.1f} | {t / base:.2f}× | {d.max_deviation[0]:.2e} {unit} | "
                  f"{d.summary()['profile']['max_error']:.2e} |")


if __name__ == "__main__":
    main()

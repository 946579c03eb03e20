"""PH quintic vs periodic B-spline pitch curves (pitch.representation): poles, STEP size, profile
error against the true profile, and build time (design + kernel solid + STEP), with ratios.

    .venv/bin/python benchmarks/bench_pitch_representation.py
"""
from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from cam_workbench.kernel import solids as occ_build  # noqa: E402
from cam_workbench.kernel.step import write_step  # noqa: E402
from cam_workbench.generators import default_spec, design_cam, load_spec  # noqa: E402
from cam_workbench.generators.pitch.bspline import bezier_form  # noqa: E402


def measure(spec, repeats: int = 3) -> dict:
    best = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        d = design_cam(spec)
        t1 = time.perf_counter()
        shape = occ_build.cam_solid(d)
        step_shape = shape if d.bspline is None else occ_build.cam_solid(d, exact_offset=False)
        t2 = time.perf_counter()
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "cam.step"
            write_step(step_shape, path, spec.units)
            size = path.stat().st_size
        t3 = time.perf_counter()
        times = (t1 - t0, t2 - t1, t3 - t2)
        if best is None or sum(times) < sum(best):
            best = times
    prof = d.summary()["profile"]
    step_profile = d.profile if d.bspline is None else bezier_form(d.profile)
    return {
        "pitch_poles": d.pitch_nurbs.n_poles, "profile_poles": d.profile.n_poles,
        "step_poles": step_profile.n_poles, "step_kb": size / 1024,
        "deviation": d.max_deviation[0], "profile_error": prof["max_error"],
        "kernel_error": prof.get("kernel_offset", {}).get("max_error", prof["max_error"]),
        "design_s": best[0], "solid_s": best[1], "step_s": best[2], "M": d.pitch.M,
    }


def main() -> None:
    cams = {
        "paper case 2 (mm)": default_spec(),
        "thesis Example 5 (in)": load_spec(ROOT / "tests" / "fixtures" / "thesis_ex5_final.toml"),
    }
    print(f"{'cam':24} {'pitch':22} {'M':>5} {'pitch/profile/STEP poles':>25} {'STEP kB':>8} "
          f"{'deviation':>10} {'profile err':>11} {'kernel err':>10} {'design s':>9} {'solid s':>8} {'STEP s':>7}")
    for name, spec in cams.items():
        for how in ({"pitch.segments": 60}, {"pitch.segments": 120}, {"pitch.segments": 240},
                    {"pitch.segments": None, "pitch.tolerance": 1e-5}):
            rows = {}
            for rep in ("ph", "bspline"):
                rows[rep] = r = measure(spec.replace(**{"pitch.representation": rep, **how}))
                label = f"{rep} " + (f"tol 1e-5" if "pitch.tolerance" in how else f"{how['pitch.segments']} seg")
                poles = f"{r['pitch_poles']}/{r['profile_poles']}/{r['step_poles']}"
                print(f"{name:24} {label:22} {r['M']:5d} {poles:>25} {r['step_kb']:8.0f} {r['deviation']:10.2e} "
                      f"{r['profile_error']:11.2e} {r['kernel_error']:10.2e} {r['design_s']:9.3f} "
                      f"{r['solid_s']:8.3f} {r['step_s']:7.3f}")
            ph, bs = rows["ph"], rows["bspline"]
            print(f"{'':24} {'ratio ph/bspline':22} {'':5} "
                  f"{ph['pitch_poles'] / bs['pitch_poles']:10.2f}x pitch poles {ph['step_kb'] / bs['step_kb']:8.2f}x "
                  f"{'':10} {ph['profile_error'] / bs['profile_error']:11.2f}x {'':10} "
                  f"{ph['design_s'] / bs['design_s']:9.2f}x {ph['solid_s'] / bs['solid_s']:8.2f}x "
                  f"{ph['step_s'] / bs['step_s']:7.2f}x")


if __name__ == "__main__":
    main()

"""Interpolator and G-code benchmarks: commands per second of the vectorised rotational
interpolator (paper Eq. 13–14, one Newton sweep over all commands) against a per-sample
Python Newton loop started from the previous command's root (the paper's sequential
scheme), and the time to make each machining program.  Prints Markdown tables with ratios.

    .venv/bin/python benchmarks/bench_interpolator.py
"""
from __future__ import annotations

import cmath

import numpy as np

from _timing import best_of  # noqa: E402  (puts the project root on sys.path)

from cam_workbench.exporters.commands_csv import commands_csv_text  # noqa: E402
from cam_workbench.exporters.gcode import contour_program, rotary_program  # noqa: E402
from cam_workbench.generators.cam_design import design_cam  # noqa: E402
from cam_workbench.generators.pitch.contact import power_coeffs  # noqa: E402
from cam_workbench.generators.machining.interpolator import RotationalInterpolator  # noqa: E402
from cam_workbench.generators.machining import machining_plan  # noqa: E402
from cam_workbench.generators.spec import default_spec  # noqa: E402
from cam_workbench.generators.machining.toolpath import contour_path, rotary_path  # noqa: E402




def python_loop(pitch, theta: np.ndarray) -> np.ndarray:
    """Per-sample scalar Newton (paper Eq. 14) in plain Python, each command starting from the
    previous root and moving to the next segment when θ passes its junction angle.
    θ must increase from 0 within one turn.  Returns the follower-line coordinate Y."""
    geo = pitch.geometry
    pc = [list(map(complex, row)) for row in power_coeffs(pitch.spline.ctrl)]
    dpc = [[k * c for k, c in enumerate(row)][1:] for row in pc]
    angles = list(pitch.angles) + [2 * np.pi]
    e, sense = geo.offset, geo.sense
    seg, xi = 0, 0.0
    out = []

    def horner(c, x):
        acc = c[-1]
        for a in reversed(c[:-1]):
            acc = acc * x + a
        return acc

    for th in theta.tolist():
        while th >= angles[seg + 1]:
            seg += 1
            xi = 0.0
        rot = cmath.exp(1j * sense * th)
        for _ in range(30):
            g = (rot * horner(pc[seg], xi)).real - e
            step = g / (rot * horner(dpc[seg], xi)).real
            xi -= step
            if abs(step) < 1e-14:
                break
        out.append((rot * horner(pc[seg], xi)).imag)
    return np.array(out)


def bench_throughput() -> list[str]:
    pitch = design_cam(default_spec()).pitch
    interp = RotationalInterpolator(pitch)
    rows = ["| commands (one turn) | Δt at 60 rpm | vectorised [ms] | commands/s | Newton steps | "
            "Python loop [ms] | commands/s | vectorised / loop |",
            "|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for n in (1_000, 10_000, 100_000, 1_000_000, 4_000_000):
        theta = 2 * np.pi * np.arange(n) / n
        res = interp.solve(theta)
        t_v = best_of(lambda: interp.solve(theta), 5 if n <= 100_000 else 2)
        if n <= 100_000:
            y = python_loop(pitch, theta)
            err = np.max(np.abs(y - res.Y))
            assert err < 1e-10, err
            t_l = best_of(lambda: python_loop(pitch, theta), 3 if n <= 10_000 else 1)
            loop = f"{t_l * 1e3:.1f} | {n / t_l:,.0f} | {t_l / t_v:.0f}×"
        else:
            loop = "(not run) | — | —"
        rows.append(f"| {n:,} | {1.0 / n * 1e3:.4g} ms | {t_v * 1e3:.2f} | {n / t_v:,.0f} | {res.iterations} | "
                    f"{loop} |")
    return rows


def bench_gcode() -> list[str]:
    rows = ["| program | settings | blocks | lines | make [ms] (tool path + text) |",
            "|---|---|---:|---:|---:|"]
    cases = [
        ("XY contour", {}, "xy"),
        ("XY contour", {"machining.contour": "lines", "machining.chord_tolerance": 0.001}, "xy"),
        ("XY contour", {"machining.chord_tolerance": 0.0001, "machining.passes": 4}, "xy"),
        ("XC rotary", {}, "xc"),
        ("XC rotary", {"machining.sample_period": 0.0001}, "xc"),
        ("command table CSV", {}, "csv"),
        ("command table CSV", {"machining.sample_period": 0.0001}, "csv"),
    ]
    for name, changes, mode in cases:
        spec = default_spec().replace(**changes) if changes else default_spec()
        design = design_cam(spec)
        plan = machining_plan(design)

        def make():
            if mode == "xy":
                path = contour_path(design, plan)
                return contour_program(design, plan, path), path.loop.n * plan.passes
            if mode == "xc":
                path = rotary_path(design, plan)
                return rotary_program(design, plan, path), path.n_blocks * plan.passes
            cmds = RotationalInterpolator(design.pitch).commands(plan.rotary_speed_rpm, plan.sample_period)
            return commands_csv_text(cmds, spec.units), cmds.n

        text, blocks = make()
        t = best_of(make, 3)
        settings = ", ".join(f"{k.split('.')[-1]} = {v}" for k, v in changes.items()) or "defaults"
        rows.append(f"| {name} | {settings} | {blocks:,} | {text.count(chr(10)):,} | {t * 1e3:.0f} |")
    return rows


def main() -> None:
    print("### Rotational interpolator (default cam, M = 60; one turn sampled N times)\n")
    print("\n".join(bench_throughput()))
    print("\n### Machining programs (default cam; design already built)\n")
    print("\n".join(bench_gcode()))


if __name__ == "__main__":
    main()

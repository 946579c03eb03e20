"""Follower dynamics: the solve time per revolution and the jump-speed sweep, against a naive
per-step Python loop (classic RK4, one Python iteration per time step, written here) — as ratios,
with the accuracy each reaches.

* steady state on the cam: the periodic (harmonic) solve gives it at once; the loop integrates from
  the static equilibrium until the train's own vibration has died (e^{−ζω_n t} < 1e-9), at the same
  N steps per revolution, its drive u, u̇ sampled beforehand (the loop does the arithmetic only — the
  loop's most favourable form);
* off the cam (above the jump speed): the exact piecewise solution (a loop over phases, each phase
  vectorised) against RK4 with the contact law max(0, k_f δ + c δ̇) in the loop, both over the
  revolutions the piecewise run needed to repeat itself;
* the jump-speed sweep: every speed of the sweep solved at once (2-D FFTs) plus the bisection,
  against the loop run to steady state at each speed (timed on 3 speeds, scaled to the sweep's).

    .venv/bin/python benchmarks/bench_dynamics.py
"""
from __future__ import annotations

import math

import numpy as np
from _timing import best_of, cpu_best_of

from cam_workbench.generators.dynamics import analyse_dynamics, cam_input, periodic_response, train_model
from cam_workbench.generators.dynamics.jump import find_jump_speed, rigid_jump_speed, sweep_range
from cam_workbench.generators.followers import follower_of
from cam_workbench.generators.motion.program import MotionProgram
from cam_workbench.generators.spec import CamSpec, default_spec
from cam_workbench.generators.spec.examples import example_dict

RPM = 2 * math.pi / 60


def naive_rk4(model, inp, omega, revolutions, z0, clamp=False):
    """Classic RK4, one Python iteration per step, N steps per revolution; u, u̇ at the steps and
    half steps sampled beforehand.  Returns (q, Q) over the last revolution."""
    n = inp.n
    prog_u = np.concatenate([inp.u, inp.u[:1]])
    prog_du = np.concatenate([inp.du, inp.du[:1]]) * omega
    # the drive at half steps (linear in between is not RK4's; take the program's own values)
    half_u, half_du = naive_rk4.half
    J, kf, ks, P, c = model.inertia, model.stiffness, model.spring_rate, model.preload, model.damping
    h = 2 * math.pi / n / omega
    q, v = z0
    out_q = [0.0] * n
    out_Q = [0.0] * n

    def acc(q, v, u, du):
        d = u - q
        g = kf * d + c * (du - v)
        if clamp and (d <= 0 or g <= 0):
            g = 0.0
        return (g - P - ks * q) / J, g

    for _rev in range(revolutions):
        for j in range(n):
            u0, du0 = prog_u[j], prog_du[j]
            um, dum = half_u[j], half_du[j]
            u1, du1 = prog_u[j + 1], prog_du[j + 1]
            a1, g = acc(q, v, u0, du0)
            out_q[j], out_Q[j] = q, g
            k1q, k1v = v, a1
            k2q, k2v = v + 0.5 * h * k1v, acc(q + 0.5 * h * k1q, v + 0.5 * h * k1v, um, dum)[0]
            k3q, k3v = v + 0.5 * h * k2v, acc(q + 0.5 * h * k2q, v + 0.5 * h * k2v, um, dum)[0]
            k4q, k4v = v + h * k3v, acc(q + h * k3q, v + h * k3v, u1, du1)[0]
            q += h / 6 * (k1q + 2 * k2q + 2 * k3q + k4q)
            v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
    return np.array(out_q), np.array(out_Q)


def half_steps(program, follower, n, omega):
    th = 2 * math.pi * (np.arange(n) + 0.5) / n
    k = program.evaluate(th)
    c = follower.lift_scale
    return list(c * k.s), list(c * k.ds * omega)


def case(name: str, spec: CamSpec, rpm: float) -> None:
    fol = follower_of(spec)
    model = train_model(spec, fol)
    prog = MotionProgram.from_spec(spec)
    omega = rpm * RPM
    r = analyse_dynamics(spec, prog, speed_rpm=rpm, sweep=False, follower=fol)
    inp = r.inp
    n = inp.n
    naive_rk4.half = half_steps(prog, fol, n, omega)
    lu = "deg" if fol.lift_unit == "angle" else spec.units
    scale = 1.0 / fol.lift_scale
    T = 2 * math.pi / omega
    if r.contact_kept:
        t_fast = cpu_best_of(lambda: periodic_response(model, inp, omega), repeat=7)
        revs = max(1, math.ceil(-math.log(1e-9) / (model.damping_ratio * model.natural_frequency * T)))
        z0 = (-model.preload / model.total_stiffness, 0.0)
        t_rev = best_of(lambda: naive_rk4(model, inp, omega, 1, z0), repeat=1)
        q, _Q = naive_rk4(model, inp, omega, revs, z0)
        err = np.max(np.abs(q - r.periodic.q)) * scale
        print(f"| {name} | {rpm:g} | on the cam | {n} | {1e3 * t_fast:.2f} (periodic solve) | {1e3 * t_rev:.0f} | "
              f"{t_rev / t_fast:.0f}× | {revs} | {revs * t_rev / t_fast:.0f}× | {err:.1e} {lu} |")
    else:
        sep = r.separated
        t_fast = best_of(lambda: analyse_dynamics(spec, prog, speed_rpm=rpm, sweep=False, follower=fol), repeat=3)
        revs = sep.revolutions
        z0 = (r.periodic.q[0], r.periodic.velocity[0])
        t_loop = best_of(lambda: naive_rk4(model, inp, omega, revs, z0, clamp=True), repeat=1)
        q, _Q = naive_rk4(model, inp, omega, revs, z0, clamp=True)
        err = np.max(np.abs(q * scale - r.position))
        print(f"| {name} | {rpm:g} | off the cam ({sep.phases - 1} contact changes/rev) | {n} | "
              f"{1e3 * t_fast / revs:.2f} per rev (piecewise exact, {revs} revs) | {1e3 * t_loop / revs:.0f} | "
              f"{t_loop / t_fast:.0f}× | {revs} | {t_loop / t_fast:.0f}× | {err:.1e} {lu} |")


def sweep_case(name: str, spec: CamSpec) -> None:
    fol = follower_of(spec)
    model = train_model(spec, fol)
    prog = MotionProgram.from_spec(spec)
    dy = spec.dynamics
    omega = spec.cam.speed_rpm * RPM
    probe = cam_input(prog, fol, 4096)
    rigid = rigid_jump_speed(model, prog, probe)
    lo, hi = sweep_range(model, omega, rigid, None, None, 0.05)
    from cam_workbench.generators.dynamics.periodic import sample_count

    n = min(sample_count(model, lo), 1 << 17)
    inp = cam_input(prog, fol, n)
    speeds = np.linspace(lo, hi, dy.sweep_points)
    res = {}

    def fast():
        res["j"] = find_jump_speed(model, inp, speeds, rigid)

    t_fast = best_of(fast, repeat=3)
    jp = res["j"]
    # the loop: to steady state at each speed (3 speeds timed, scaled to the sweep + its bisection)
    naive_rk4.half = half_steps(prog, fol, n, 1.0)
    probe_speeds = speeds[[0, len(speeds) // 2, -1]]
    t_probe = 0.0
    for w in probe_speeds:
        half = half_steps(prog, fol, n, w)
        naive_rk4.half = half
        revs = max(1, math.ceil(-math.log(1e-9) / (model.damping_ratio * model.natural_frequency * 2 * math.pi / w)))
        z0 = (-model.preload / model.total_stiffness, 0.0)
        t_probe += best_of(lambda: naive_rk4(model, inp, w, revs, z0), repeat=1)
    t_naive = t_probe / 3 * (len(speeds) + jp.evaluations)
    print(f"| {name} | {len(speeds)} speeds {jp.speeds_rpm[0]:.4g}–{jp.speeds_rpm[-1]:.4g} rpm + {jp.evaluations} "
          f"bisection solves | {n} | {1e3 * t_fast:.0f} | ≈ {t_naive:.0f} s | {t_naive / t_fast:.0f}× | "
          f"{jp.rpm:.6g} rpm (rigid {jp.rigid_rpm:.6g}) |")


def main() -> None:
    default = default_spec().replace(**{"dynamics.stiffness": 2000.0})
    bouncy = default.replace(**{"follower.spring_rate": 3.0})
    osc = CamSpec.from_dict({**example_dict("oscillating"), "dynamics": {"torsional_stiffness": 2.0e6}})
    print("### Steady state per revolution\n")
    print("| cam | rpm | regime | samples/rev | ours [ms] | RK4 loop per rev [ms] | ratio per rev | revs to steady "
          "(loop) | ratio to steady state | loop vs ours |")
    print("|---|---:|---|---:|---|---:|---:|---:|---:|---|")
    case("default, k_f = 2000 N/mm", default, 60.0)
    case("default, k_f = 2000 N/mm", default, 400.0)
    case("oscillating, k_t = 2e6 N·mm/rad", osc, 60.0)
    case("default, k = 3 N/mm spring", bouncy, 700.0)
    print("\n### Jump-speed sweep and bisection\n")
    print("| cam | sweep | samples/rev | ours [ms] | RK4 loop to steady state | ratio | jump speed |")
    print("|---|---|---:|---:|---:|---:|---|")
    sweep_case("default, k_f = 2000 N/mm", default)
    sweep_case("oscillating, k_t = 2e6 N·mm/rad", osc)


if __name__ == "__main__":
    main()

"""Polynomial, constant-velocity and table segments: accuracy and speed, as ratios.

* a ``polynomial`` rise between dwells against the closed-form 3-4-5 / 4-5-6-7 laws it reproduces:
  the largest difference in s … s‴, and the time to evaluate it (a Bézier segment read as a B-spline
  lift, θ(u) inverted by Newton) against the closed form;
* a ``table`` rise: a cycloid sampled every 1°, 0.5°, 0.1°, fitted to several tolerances — the knot
  spans chosen, the errors at the points and between them (against the cycloid itself), and the time
  of the banded sparse fit against a dense least-squares fit of the same spans;
* the program's construction (solving and fitting every segment) against its cached second call.
"""
from __future__ import annotations

import math
import time

import numpy as np

from _timing import cpu_best_of  # noqa: F401  (puts the project on sys.path)

from cam_workbench.generators.motion import MotionProgram
from cam_workbench.generators.motion.bspline_law import basis_matrix, clamped_uniform_knots
from cam_workbench.generators.motion.table import _solve, fit_table
from cam_workbench.generators.spec import CamSpec

H = 10.0


def spec(rise, **extra):
    return CamSpec.from_dict({"cam": {"base_radius": 60.0, "thickness": 5.0},
                              "follower": {"kind": "roller", "roller_radius": 5.0},
                              "motion": [{"kind": "dwell", "angle": 60}, {"kind": "rise", "angle": 120, "lift": H, **rise},
                                         {"kind": "dwell", "angle": 60},
                                         {"kind": "return", "angle": 120, "lift": H, "law": "cycloidal"}], **extra})


def closed_forms() -> None:
    print("polynomial rise (120°, 10 mm) between dwells against its closed form")
    th = np.radians(np.linspace(60.0, 180.0, 100001)[1:-1])
    for closed, extra in (("poly345", {}), ("poly4567", {"start_continuity": 3, "end_continuity": 3})):
        a = MotionProgram.from_spec(spec({"law": closed}))
        b = MotionProgram.from_spec(spec({"law": "polynomial", **extra}))
        ka, kb = a.evaluate(th), b.evaluate(th)
        beta = math.radians(120.0)
        errs = [float(np.max(np.abs(getattr(kb, n) - getattr(ka, n)))) / (H / beta**i)
                for i, n in enumerate(("s", "ds", "d2s", "d3s"))]
        ta = cpu_best_of(lambda: a.evaluate(th))
        tb = cpu_best_of(lambda: b.evaluate(th))
        print(f"  {closed:9s} ({len(th)} angles): max |Δs^(n)| / (h/β^n) = " + ", ".join(f"{e:.1e}" for e in errs)
              + f"; evaluate {tb * 1e3:7.2f} ms vs closed form {ta * 1e3:6.2f} ms: ratio {tb / ta:5.1f}x")


def _dense_solve(theta, s, span, order, spans, constraints):
    """The same constrained least-squares fit with a dense collocation matrix: the constraints
    eliminated through the null space of their rows, then numpy's lstsq (a timing reference)."""
    n = spans + order - 1
    knots = clamped_uniform_knots(n, order)
    a = basis_matrix(knots, order - 1, n, theta / span * spans, 0)
    c = np.array([basis_matrix(knots, order - 1, n, np.array([x * spans]), k)[0] * (spans / span) ** k
                  for x, k, _v in constraints])
    d = np.array([v for _x, _k, v in constraints])
    _, sv, vt = np.linalg.svd(c)
    z = vt[len(constraints):].T
    c0 = np.linalg.lstsq(c, d, rcond=None)[0]
    w = np.linalg.lstsq(a @ z, s - a @ c0, rcond=None)[0]
    return c0 + z @ w


def tables() -> None:
    print("table rise: a sampled cycloid (120°, 10 mm), order 5, C2 ends; the fewest spans meeting the tolerance")
    span = math.radians(120.0)
    cons = [(0.0, 0, 0.0), (1.0, 0, H), (0.0, 1, 0.0), (0.0, 2, 0.0), (1.0, 1, 0.0), (1.0, 2, 0.0)]
    for step in (1.0, 0.1):
        ang = np.arange(0.0, 120.0 + 1e-9, step)
        x = ang / 120.0
        s = H * (x - np.sin(2 * np.pi * x) / (2 * np.pi))
        theta = np.radians(ang)
        for tol in (1e-3, 1e-5, 1e-7):
            fit = fit_table(theta, s, span, 0.0, H, 5, cons, tol)
            mid = np.radians(np.arange(step / 2, 120.0, step))
            xm = mid / span
            y = fit.lift.evaluate(mid)
            between = float(np.max(np.abs(H * y[0] - H * (xm - np.sin(2 * np.pi * xm) / (2 * np.pi)))))
            vel = float(np.max(np.abs(H * y[1] - H * (1 - np.cos(2 * np.pi * xm)) / span)) / (H / span))
            t_search = cpu_best_of(lambda: fit_table(theta, s, span, 0.0, H, 5, cons, tol), 3)
            print(f"  {len(ang):5d} points, tol {tol:.0e}: {fit.spans:4d} spans, max error at the points "
                  f"{fit.max_error:.2e}, between them {fit.max_error and between:.2e}, velocity {vel:.1e} of h/β; "
                  f"search {t_search * 1e3:6.1f} ms")
    print("one constrained least-squares solve: banded sparse KKT (this code) vs dense null-space lstsq")
    ang = np.linspace(0.0, 120.0, 5001)
    x = ang / 120.0
    s = H * (x - np.sin(2 * np.pi * x) / (2 * np.pi)) + 1e-3 * np.sin(37 * np.pi * x)
    theta = np.radians(ang)
    for spans in (50, 200, 800):
        t_sparse = cpu_best_of(lambda: _solve(theta, s, span, 5, spans, cons), 3)
        t_dense = cpu_best_of(lambda: _dense_solve(theta, s, span, 5, spans, cons), 1)
        a = _solve(theta, s, span, 5, spans, cons)[0]
        b = _dense_solve(theta, s, span, 5, spans, cons)
        print(f"  5001 points, {spans:4d} spans: sparse {t_sparse * 1e3:7.1f} ms, dense {t_dense * 1e3:8.1f} ms: "
              f"ratio {t_dense / t_sparse:6.1f}x (control values agree to {np.max(np.abs(a - b)):.1e})")


def construction() -> None:
    print("program construction (solve / fit every segment) vs the cached program")
    ang = np.arange(0.0, 120.0 + 1e-9, 0.5)
    rows = [[float(a), float(H * (a / 120 - math.sin(2 * math.pi * a / 120) / (2 * math.pi)))] for a in ang]
    for label, rise in (("polynomial", {"law": "polynomial", "points": [[40.0, 2.0], [80.0, 8.3]]}),
                        ("constant_velocity", {"law": "constant_velocity", "start_blend": 20.0, "end_blend": 20.0}),
                        ("table (241 points)", {"law": "table", "table": rows, "table_tolerance": 1e-5})):
        sp = spec(rise)
        segs = sp.motion
        first = cpu_best_of(lambda: MotionProgram._build(tuple(segs)), 3)
        cached = cpu_best_of(lambda: MotionProgram.from_segments(segs), 5)
        print(f"  {label:20s}: build {first * 1e3:7.2f} ms, cached {cached * 1e6:6.1f} µs (ratio {first / cached:7.0f}x)")


if __name__ == "__main__":
    closed_forms()
    print()
    tables()
    print()
    construction()

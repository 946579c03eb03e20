"""The rotational PH interpolator (paper §3.2, Eq. 12–15) against the paper's Table 2 and
independent computations.

Table 2 of Jahanpour & Dolatabadi (2014), Table 1 cam (dwell 30°, cycloidal rise 120° of
20 mm, dwell 60°, cycloidal return 120°, dwell 30°; h' = 20 mm; 60 rpm), knife edge,
Δt = 1 ms; acceleration and jerk are printed with a dot as thousands separator:

| case | e [mm] | M | max deviation [µm] | v [mm/s] | a [mm/s²] | j [mm/s³] |
|---|---|---|---|---|---|---|
| 1 | 0 | 60 uniform | 0.14 | 120 | 1141 | 23 200 |
| 2 | 10 | 60 uniform | 0.15 | 120 | 1144 | 23 680 |
| 3 | 10 | 64 (5° dwells, 6° rise/return) | 3.9 | 120 | 1143 | 62 243 |
"""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.optimize import brentq

from cam_workbench.generators.errors import SolveError
from cam_workbench.generators.machining.interpolator import (RotationalInterpolator, command_count, finite_differences,
                                     interpolate, interpolator_accuracy)
from cam_workbench.generators.pitch.ph import build_pitch_for_segments

from .conftest import paper_case

TABLE2 = {  # case: (deviation µm, v, a, j)
    1: (0.14, 120.0, 1141.0, 23200.0),
    2: (0.15, 120.0, 1144.0, 23680.0),
    3: (3.9, 120.0, 1143.0, 62243.0),
}


@pytest.fixture(scope="module")
def accuracy():
    return {case: interpolator_accuracy(build_pitch_for_segments(paper_case(case)), 60.0, 1e-3)
            for case in TABLE2}


@pytest.mark.parametrize("case", [1, 2])
def test_table2_uniform_cases(accuracy, case):
    """Cases 1 and 2 reproduce every printed digit of Table 2 with backward differences
    (velocity, acceleration and jerk from ∇s/Δt, ∇²s/Δt², ∇³s/Δt³ of the commands)."""
    dev_um, v, a, j = TABLE2[case]
    acc = accuracy[case]
    assert acc.commands.n == 1000 and acc.commands.step_deg == pytest.approx(0.36)
    dev, at = acc.max_deviation
    assert dev * 1e3 == pytest.approx(dev_um, abs=0.005)
    assert 30 <= at <= 150 or 210 <= at <= 330            # "related to the rise/return region"
    mx = acc.maxima("backward")
    assert mx["velocity"][0] == pytest.approx(v, abs=0.5)
    assert mx["acceleration"][0] == pytest.approx(a, abs=1.0)
    assert mx["jerk"][0] == pytest.approx(j, abs=25.0)     # 23196 / 23681 measured
    # the paper's percentages over the desired maxima (1130.9 mm/s², 21318.3 mm/s³)
    s = acc.summary()
    pct = {1: (0.88, 8.82), 2: (1.15, 11.07)}[case]
    assert s["acceleration"]["increase_percent"] == pytest.approx(pct[0], abs=0.03)
    assert s["jerk"]["increase_percent"] == pytest.approx(pct[1], abs=0.03)


def test_table2_case3_nonuniform(accuracy):
    """Case 3 (M = 64): velocity and acceleration match Table 2; the deviation (4.14 µm
    against 3.9) and the jerk (66 423 backward / 63 419 central against 62 243) come out
    ≈ 6 % higher.  Sampling does not explain it (any phase of the 0.36° command grid gives
    4.135–4.151 µm; the dense maximum is 4.151 µm), see the README."""
    acc = accuracy[3]
    dev_um, v, a, j = TABLE2[3]
    dev, at = acc.max_deviation
    assert 145 <= at <= 150                    # "changing from the rise region to the dwell region"
    assert dev * 1e3 == pytest.approx(dev_um, rel=0.07)
    mx = acc.maxima("backward")
    assert mx["velocity"][0] == pytest.approx(v, abs=0.5)
    assert mx["acceleration"][0] == pytest.approx(a, abs=1.0)
    assert mx["jerk"][0] == pytest.approx(j, rel=0.07)
    assert acc.maxima("central")["jerk"][0] == pytest.approx(j, rel=0.03)
    # the non-uniform segmentation's effect: jerk +191.9 % in the paper, ≈3× the desired here
    assert 2.5 < mx["jerk"][0] / acc.desired["jerk"] < 3.3


def test_desired_maxima_are_the_papers(accuracy):
    """§4.2: the desired cycloidal motion has max v, a, j = 120, 1130.9, 21318.3."""
    d = accuracy[1].desired
    assert d["velocity"] == pytest.approx(120.0, rel=1e-9)
    assert d["acceleration"] == pytest.approx(1130.97, abs=0.01)
    assert d["jerk"] == pytest.approx(21318.3, abs=0.1)


@pytest.mark.parametrize("direction,offset", [("ccw", 10.0), ("cw", 10.0), ("ccw", -7.0), ("cw", 0.0)])
def test_commands_match_an_independent_root_finder(direction, offset):
    """Every command solves Eq. 13: compared with scipy's brentq on the Bernstein-form curve
    (a different evaluation and a bracketing solver) for both turning senses."""
    spec = paper_case(2).replace(**{"cam.direction": direction, "follower.offset": offset,
                                    "cam.base_radius": float(np.hypot(20.0, offset))})
    pc = build_pitch_for_segments(spec)
    cmds = interpolate(pc, 60.0, 1e-3)
    geo = pc.geometry
    for k in range(0, cmds.n, 37):
        th, seg = cmds.theta[k], int(cmds.seg[k])
        rot = np.exp(1j * geo.sense * th)

        def g(xi):
            return (rot * pc.spline.point(np.array([seg]), np.array([xi]))[0]).real - geo.offset

        xi = brentq(g, 0.0, 1.0, xtol=1e-15) if g(0.0) * g(1.0) < 0 else (0.0 if abs(g(0.0)) < 1e-12 else 1.0)
        assert cmds.xi[k] == pytest.approx(xi, abs=1e-11)
        p = pc.spline.point(np.array([seg]), np.array([xi]))[0]
        assert cmds.point[k] == pytest.approx(p, abs=1e-10)
        assert cmds.s_actual[k] == pytest.approx((rot * p).imag - geo.s0, abs=1e-10)
    # the command point lies on the follower line after turning the cam (Eq. 13)
    turned = np.exp(1j * geo.sense * cmds.theta) * cmds.point
    assert np.max(np.abs(turned.real - geo.offset)) < 1e-11


def test_mirrored_mechanism_gives_the_same_motion():
    """A cw cam with offset −e is the mirror image of a ccw cam with offset e: the follower
    displacement from the commands must be identical (sign conventions of both senses)."""
    a = build_pitch_for_segments(paper_case(2))
    b = build_pitch_for_segments(paper_case(2).replace(**{"cam.direction": "cw", "follower.offset": -10.0}))
    ca, cb = interpolate(a, 60.0, 1e-3), interpolate(b, 60.0, 1e-3)
    assert np.max(np.abs(ca.s_actual - cb.s_actual)) < 1e-11
    assert np.max(np.abs(cb.point - (-np.conj(ca.point)))) < 1e-11     # mirrored in the y axis


def test_junctions_and_dwells_are_exact():
    """At the junction angles the commands hit the junction points (ξ = 0 or 1, zero
    deviation); in a dwell the commands stay on the dwell circle to 0.02 µm (a PH quintic is
    not a circle: measured 0.017 µm in the 60° dwell, against 0.15 µm in the rise)."""
    pc = build_pitch_for_segments(paper_case(2))
    it = RotationalInterpolator(pc)
    c = it.solve(pc.angles)
    at_junction = np.minimum(np.abs(c.xi), np.abs(1 - c.xi))
    assert at_junction.max() < 1e-12
    assert np.max(np.abs(c.Y - pc.geometry.s0 - pc.program.s(pc.angles))) < 1e-12
    th = np.deg2rad(np.linspace(150.0, 210.0, 601))                # the 60° dwell at full lift
    cd = it.solve(th)
    radius = np.hypot(pc.geometry.offset, pc.geometry.s0 + 20.0)
    assert np.max(np.abs(np.abs(cd.point) - radius)) < 2e-5
    assert np.max(np.abs(cd.Y - pc.geometry.s0 - 20.0)) < 2e-5


def test_matches_the_foundations_solver_everywhere():
    """The vectorised sweep (Hermite start, chunks) agrees with the foundation's solver
    started from the linear guess, on 200 001 angles including many junctions."""
    pc = build_pitch_for_segments(paper_case(3))
    th = np.linspace(-1.0, 2 * np.pi + 1.0, 200_001)
    a = RotationalInterpolator(pc).solve(th)
    b = pc.solver().solve(th)
    assert np.max(np.abs(a.Y - b.Y)) < 1e-12
    assert a.iterations <= 4


def test_command_count_and_times():
    pc = build_pitch_for_segments(paper_case(1))
    c = interpolate(pc, 60.0, 7e-3)               # 2π/(ωΔt) = 142.86: 143 commands
    assert c.n == 143 == command_count(2 * np.pi, 7e-3)
    assert np.allclose(np.diff(c.t), 7e-3) and c.t[0] == 0.0
    assert np.allclose(np.diff(c.theta), 2 * np.pi * 7e-3) and c.theta[-1] < 2 * np.pi
    assert np.all((c.xi >= 0) & (c.xi <= 1)) and np.all((c.seg >= 0) & (c.seg < 60))


def test_dense_deviation_bounds_the_command_deviation(accuracy):
    """The contract's max_deviation (every 0.02°) is what pitch.tolerance uses: the commands
    (every 0.36°) sample the same curve, so their maximum is never larger (to rounding)."""
    for case, acc in accuracy.items():
        dense, _ = build_pitch_for_segments(paper_case(case)).max_deviation()
        assert acc.max_deviation[0] <= dense * (1 + 1e-9)
        assert acc.max_deviation[0] >= 0.95 * dense


def test_finite_difference_stencils_on_polynomials():
    """Backward and central stencils: exact jerk for a cubic, exact acceleration at the stencil
    centre for a cubic, exact velocity at the centre for a quadratic."""
    dt, omega = 1e-3, 2.0
    k = np.arange(-3, 20 + 2)
    t = k * dt
    cubic = 2.0 + 3.0 * t - 4.0 * t**2 + 5.0 * t**3
    quad = 1.0 - 2.0 * t + 7.0 * t**2
    for scheme in ("backward", "central"):
        fd = finite_differences(cubic, dt, omega, 0.0, scheme)
        tj = fd.j_theta / omega
        ta = fd.a_theta / omega
        assert np.allclose(fd.j, 30.0, rtol=1e-6)
        assert np.allclose(fd.a, -8.0 + 30.0 * ta, rtol=1e-6, atol=1e-6)
        fq = finite_differences(quad, dt, omega, 0.0, scheme)
        assert np.allclose(fq.v, -2.0 + 14.0 * fq.v_theta / omega, rtol=1e-9)
        assert tj.shape == (20,)


def test_unbracketed_root_is_a_clear_error():
    """A follower line that misses part of the curve (offset beyond its smallest radius)."""
    pc = build_pitch_for_segments(paper_case(1))
    bad = dataclasses.replace(pc, follower=dataclasses.replace(pc.follower, offset=25.0))
    with pytest.raises(SolveError, match="cam angle|junction"):
        RotationalInterpolator(bad).solve(np.linspace(0, 2 * np.pi, 1000))


def test_report_section(accuracy):
    s = accuracy[2].summary()
    for key in ("speed_rpm", "sample_period", "commands", "max_deviation", "max_deviation_at_deg",
                "velocity", "acceleration", "jerk", "differencing", "schemes"):
        assert key in s
    assert s["differencing"] == "backward" and set(s["schemes"]) == {"backward", "central"}
    assert s["jerk"]["desired_max"] == pytest.approx(21318.3, abs=0.1)


@pytest.mark.parametrize("case", [1, 2])
def test_paper_tolerance_chooses_the_papers_m(case):
    """ε_all = 0.2 µm (paper §4.2): pitch.tolerance (the contract's dense deviation) picks
    M = 60, the paper's choice, and the interpolated commands of that M meet it too; M = 59
    misses it by 5× (junctions off the motion boundaries)."""
    from cam_workbench.generators.pitch.ph import segments_for_tolerance

    pc, dev, _ = segments_for_tolerance(paper_case(case), 2e-4)
    assert pc.M == 60 and dev <= 2e-4
    assert interpolator_accuracy(pc, 60.0, 1e-3).max_deviation[0] <= 2e-4
    assert build_pitch_for_segments(paper_case(case), 59).max_deviation()[0] > 1e-3


def test_coarse_steps_are_flagged_in_the_report():
    pc = build_pitch_for_segments(paper_case(2))
    assert interpolator_accuracy(pc, 60.0, 1e-3).summary()["warning"] is None
    w = interpolator_accuracy(pc, 3000.0, 1e-3).summary()["warning"]
    assert w.startswith("18° of cam rotation per command")

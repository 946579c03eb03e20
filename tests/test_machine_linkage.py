"""The machine's tools (issue 24 items 2-4): each cam's tool through its linkage (or the follower's
own point) on the machine's clock, the [[clearance]] pairs, the phase sweep — against closed
forms and poses built here, independently of the machine code."""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.machine import analyse_machine, example_machine_dict, machine_from_dict
from cam_workbench.generators.machine.clearance import Polygon, min_clearance
from cam_workbench.generators.motion.program import MotionProgram
from cam_workbench.generators.spec.model import CamSpec

from .conftest import ROOT, requires_ocp

CLI = [sys.executable, "-m", "cam_workbench.cli"]


def cli(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT), COLUMNS="250")
    return subprocess.run([*CLI, *args], capture_output=True, text=True, env=env, cwd=cwd)


@pytest.fixture(scope="module")
def example() -> Any:
    machine = machine_from_dict(example_machine_dict("three_cams"))
    return machine, analyse_machine(machine)


def cycloidal(x: np.ndarray, h: float, beta: float) -> np.ndarray:
    """The pusher's program written out: cycloidal rise h over β, dwell to 250°, cycloidal return
    over 100°, dwell (angles [rad])."""
    x = np.mod(x, 2 * np.pi)
    s = np.zeros_like(x)
    r = x < beta
    s[r] = h * (x[r] / beta - np.sin(2 * np.pi * x[r] / beta) / (2 * np.pi))
    top = (x >= beta) & (x < math.radians(250))
    s[top] = h
    ret = (x >= math.radians(250)) & (x < math.radians(350))
    u = (x[ret] - math.radians(250)) / beta
    s[ret] = h * (1 - (u - np.sin(2 * np.pi * u) / (2 * np.pi)))
    return s


def test_lever_tool_path_is_ratio_times_s_along_its_direction(example):
    machine, result = example
    t = result.timings[0]
    assert t.name == "pusher" and t.linked
    s = cycloidal(result.theta, 25.0, math.radians(100))         # phase 0: cam angle = machine angle
    np.testing.assert_allclose(t.s, s, atol=1e-9)
    np.testing.assert_allclose(t.tool[:, 0], 30.0, atol=1e-12)            # pivot (30, 90), direction 90°
    np.testing.assert_allclose(t.tool[:, 1], 90.0 + 2.0 * s, atol=1e-9)
    np.testing.assert_allclose(t.tool_s, 2.0 * s, atol=1e-9)
    np.testing.assert_allclose(t.tool_v, 2.0 * t.v, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(t.tool_angle, 0.0)


def _rocker_at(lk: dict[str, float], q_deg: Any) -> tuple[complex, np.ndarray]:
    """The four-bar's rocker pivot O₄ and rocker angles (machine plane) at follower lifts ``q_deg``
    [deg], by intersecting two circles here: the crank is the arm, turning clockwise as the arm
    lifts (θ₂ = frame_angle + crank_offset − q), and B is on the left branch (σ = +1: B on the
    left of O₄→A, the rocker angle = angle(A − O₄) + the angle at O₄)."""
    o2 = complex(lk["pivot_x"], lk["pivot_y"])
    gamma = math.radians(lk.get("frame_angle", 0.0))
    o4 = o2 + lk["ground"] * np.exp(1j * gamma)
    a = o2 + lk["crank"] * np.exp(1j * (gamma + np.radians(lk["crank_offset"] - np.asarray(q_deg, dtype=float))))
    e = np.abs(a - o4)
    cos = (lk["rocker"] ** 2 + e * e - lk["coupler"] ** 2) / (2 * lk["rocker"] * e)
    th4 = np.angle(a - o4) + np.arccos(cos)
    b = o4 + lk["rocker"] * np.exp(1j * th4)
    assert np.all(np.abs(np.abs(b - a) - lk["coupler"]) < 1e-9)                 # the loop closes
    assert np.all(((a - o4).conjugate() * (b - o4)).imag > 0)                  # B left of O₄→A
    return o4, th4


def _rocker_zero(lk: dict[str, float]) -> tuple[complex, float]:
    """O₄ and the rocker angle at zero follower lift (:func:`_rocker_at` at q = 0)."""
    o4, th4 = _rocker_at(lk, [0.0])
    return o4, float(th4[0])


def test_four_bar_tool_motion_is_the_specified_tool_motion(example):
    machine, result = example
    t = result.timings[1]
    cam = machine.cams[1]
    assert t.name == "gripper" and cam.spec.linkage.motion_at == "tool"
    x = np.mod(result.theta - math.radians(cam.phase), 2 * np.pi)
    given = MotionProgram.from_segments(cam.spec.motion).evaluate(x)       # the [[motion]] as given: the tool's
    omega = machine.omega
    np.testing.assert_allclose(t.tool_s, given.s, atol=1e-9)
    np.testing.assert_allclose(t.tool_v, given.ds * omega, atol=1e-9 * omega)
    np.testing.assert_allclose(t.tool_a, given.d2s * omega**2, atol=1e-9 * omega**2 * 10)
    # the follower's own motion is the derived one, not the tool's
    assert np.max(np.abs(t.s - given.s)) > 0.1
    # the tool point: O₄ + c·e^{i(θ₄(0) + p)}, and the frame turns by p
    lk = example_machine_dict("three_cams")["cam"][1]["spec"]["linkage"]
    o4, th0 = _rocker_zero(lk)
    z = o4 + lk["rocker"] * np.exp(1j * (th0 + np.radians(given.s)))
    np.testing.assert_allclose(t.tool[:, 0], z.real, atol=1e-9)
    np.testing.assert_allclose(t.tool[:, 1], z.imag, atol=1e-9)
    np.testing.assert_allclose(t.tool_angle, np.radians(given.s), atol=1e-12)
    # the derived arm lift, through θ₂ = offset − q and the left branch, turns the rocker by p
    _, th4 = _rocker_at(lk, t.s)
    np.testing.assert_allclose(np.angle(np.exp(1j * (th4 - th0))), np.radians(given.s), atol=1e-9)
    assert np.min(t.s) > -1e-9 and np.max(t.s) > 1.0                           # the arm lifts (≥ 0)
    entry = result.summary()["cams"][1]["linkage"]
    assert entry["motion_at"] == "tool"
    assert abs(entry["tool_motion"]["max_displacement"] - 10.0) < 1e-9


def test_follower_without_linkage_is_placed_by_its_tool_table(example):
    machine, result = example
    t = result.timings[2]
    assert not t.linked and t.tool_s is None
    np.testing.assert_allclose(t.tool[:, 0], 0.0, atol=1e-12)             # origin (0, 55), direction 90°
    np.testing.assert_allclose(t.tool[:, 1], 55.0 + t.s, atol=1e-9)


def test_oscillating_follower_without_linkage_turns_on_its_arm():
    d = example_machine_dict("three_cams")
    spec = d["cam"][1]["spec"]
    del spec["linkage"]
    d["cam"][1]["tool"].update({"origin": [5.0, -3.0], "direction": 30.0})
    d.pop("clearance")
    machine = machine_from_dict(d)
    t = analyse_machine(machine).timings[1]
    arm = spec["follower"]["arm_length"]
    ang = np.radians(30.0 + t.s)
    np.testing.assert_allclose(t.tool[:, 0], 5.0 + arm * np.cos(ang), atol=1e-9)
    np.testing.assert_allclose(t.tool[:, 1], -3.0 + arm * np.sin(ang), atol=1e-9)
    np.testing.assert_allclose(t.tool_angle, np.radians(t.s), atol=1e-12)


def test_clearance_section_is_min_clearance_of_independent_poses(example):
    machine, result = example
    sec = result.summary()["clearance"]
    row = sec["pairs"][0]
    assert row["between"] == ["pusher", "gripper"] and row["status"] == "pass" and sec["passed"]
    # poses built here: the pusher from its closed form, the jaw from the given tool motion
    deg = np.linspace(0.0, 360.0, 4 * 720 + 1)
    th = np.radians(deg)
    s = cycloidal(th, 25.0, math.radians(100))
    pa = (np.stack([np.full_like(s, 30.0), 90.0 + 2 * s], axis=1), np.zeros_like(s))
    gr = machine.cams[1]
    p = np.radians(MotionProgram.from_segments(gr.spec.motion).evaluate(np.mod(th - math.radians(gr.phase),
                                                                                 2 * np.pi)).s)
    lk = example_machine_dict("three_cams")["cam"][1]["spec"]["linkage"]
    o4, th0 = _rocker_zero(lk)
    z = o4 + lk["rocker"] * np.exp(1j * (th0 + p))
    pb = (np.stack([z.real, z.imag], axis=1), p)
    tools = example_machine_dict("three_cams")["cam"]
    ref = min_clearance(Polygon(tools[0]["tool"]["polygon"]), pa, Polygon(tools[1]["tool"]["polygon"]), pb, deg)
    assert row["distance"] <= ref.distance + 1e-9
    assert row["distance"] >= ref.distance - ref.error_bound - 1e-9
    assert abs(row["margin"] - (row["distance"] - 2.0)) < 1e-12
    # the closed form at the reported binding angle: the jaw's corners (turned by p about the jaw
    # point) against the plate, an axis-aligned 20 × 8 rectangle about (30, 90 + 2s)
    at = math.radians(row["at_deg"])
    s_at = float(cycloidal(np.array([at]), 25.0, math.radians(100))[0])
    p_at = math.radians(float(MotionProgram.from_segments(gr.spec.motion).evaluate(
        np.array([(at - math.radians(gr.phase)) % (2 * np.pi)])).s[0]))
    jaw = o4 + lk["rocker"] * np.exp(1j * (th0 + p_at))
    corners = [jaw + complex(*c) * np.exp(1j * p_at) for c in tools[1]["tool"]["polygon"]]
    gap = min(math.hypot(max(0.0, abs(c.real - 30.0) - 10.0), max(0.0, abs(c.imag - 90.0 - 2 * s_at) - 4.0))
              for c in corners)
    assert abs(row["distance"] - gap) < 1e-6


def test_a_failing_clearance_fails_the_machine_with_a_remedy():
    d = example_machine_dict("three_cams")
    d["clearance"][0]["required"] = 20.0
    s = analyse_machine(machine_from_dict(d)).summary()
    row = s["clearance"]["pairs"][0]
    assert row["status"] == "fail" and s["checks"]["failed"] == ["clearance.pusher/gripper"]
    assert not s["checks"]["passed"]
    r = row["remedy"]
    assert r["moves"] == "gripper" and abs(r["shift"] - (20.0 - row["distance"] + row["error_bound"])) < 1e-12
    assert abs(math.hypot(*r["direction"]) - 1.0) < 1e-12


def test_phase_sweep_and_its_rules(example):
    machine, _ = example
    r = analyse_machine(machine, sweep="gripper").summary()["phase_sweep"]
    assert r["cam"] == "gripper" and r["current_phase_passes"]
    assert r["pairs"][0]["other"] == "pusher"
    for bad in ("lifter", "nobody"):
        with pytest.raises(SpecError) as exc:
            analyse_machine(machine, sweep=bad)
        assert exc.value.field == "--phase-sweep"


def test_phase_sweep_finds_the_colliding_phases():
    """A 4 mm clearance: the jaw's tip clears the plate's edge by 4 mm only at some phases of the
    gripper (each reported interval's middle is checked here by analysing that phase)."""
    d = example_machine_dict("three_cams")
    d["clearance"][0]["required"] = 4.0
    m = machine_from_dict(d)
    ps = analyse_machine(m, sweep="gripper").summary()["phase_sweep"]
    row = ps["pairs"][0]
    assert row["min_clearance"] < 4.0 < row["max_clearance"]
    assert ps["intervals"] and not ps["current_phase_passes"]
    for a, b in ps["intervals"]:
        mid = ((a + b) / 2) % 360.0
        d2 = example_machine_dict("three_cams")
        d2["clearance"][0]["required"] = 4.0
        d2["cam"][1]["phase"] = mid
        assert analyse_machine(machine_from_dict(d2)).summary()["clearance"]["pairs"][0]["distance"] >= 4.0 - 0.1


BAD_CLEARANCE = {
    "not two": ({"between": ["pusher"], "required": 2.0}, "clearance[0].between"),
    "unknown cam": ({"between": ["pusher", "nobody"], "required": 2.0}, "clearance[0].between"),
    "same cam": ({"between": ["pusher", "pusher"], "required": 2.0}, "clearance[0].between"),
    "negative": ({"between": ["pusher", "gripper"], "required": -1.0}, "clearance[0].required"),
    "missing required": ({"between": ["pusher", "gripper"]}, "clearance[0].required"),
    "unknown field": ({"between": ["pusher", "gripper"], "required": 1.0, "gap": 3}, "clearance[0].gap"),
    "not a number": ({"between": ["pusher", "gripper"], "required": "2"}, "clearance[0].required"),
}


@pytest.mark.parametrize("case", sorted(BAD_CLEARANCE))
def test_bad_clearance_fields_name_the_field(case):
    entry, field = BAD_CLEARANCE[case]
    d = example_machine_dict("three_cams")
    d["clearance"] = [entry]
    with pytest.raises(SpecError) as exc:
        machine_from_dict(d)
    assert exc.value.field == field


def test_tool_placement_rules():
    d = example_machine_dict("three_cams")
    d["cam"][0]["tool"]["origin"] = [1.0, 2.0]                 # the pusher has a lever: it places the tool
    with pytest.raises(SpecError) as exc:
        machine_from_dict(d)
    assert exc.value.field == "cam[0].tool.origin"
    d = example_machine_dict("three_cams")
    d["cam"][2]["tool"]["direction"] = "up"
    with pytest.raises(SpecError) as exc:
        machine_from_dict(d)
    assert exc.value.field == "cam[2].tool.direction"
    d = example_machine_dict("three_cams")
    d["cam"][2].pop("tool")
    d["clearance"] = [{"between": ["pusher", "lifter"], "required": 1.0}]
    with pytest.raises(SpecError) as exc:
        machine_from_dict(d)
    assert exc.value.field == "clearance[0].between"


def test_every_example_cam_is_valid():
    for cam in example_machine_dict("three_cams")["cam"]:
        CamSpec.from_dict({**cam["spec"], "cam": {**cam["spec"]["cam"], "speed_rpm": 120.0}})


EXAMPLE = ROOT / "docs" / "examples" / "machine_three_cams.toml"


def _write(tmp_path: Path, required: float) -> Path:
    """The example machine file (every spec inline) with the pair's required clearance changed."""
    text = EXAMPLE.read_text(encoding="utf-8")
    assert text.count("required = 2.0") == 1
    f = tmp_path / "m.toml"
    f.write_text(text.replace("required = 2.0", f"required = {required!r}"), encoding="utf-8")
    return f


def test_cli_bad_clearance_exits_2_and_writes_nothing(tmp_path):
    out = tmp_path / "out"
    res = cli("machine", str(_write(tmp_path, -2.0)), "-o", str(out))
    assert res.returncode == 2 and "clearance[0].required" in res.stderr
    assert not out.exists()
    res = cli("machine", "--example", "three_cams", "--phase-sweep", "lifter", "-o", str(out))
    assert res.returncode == 2 and "--phase-sweep" in res.stderr
    assert not out.exists()


@requires_ocp
def test_cli_failing_clearance_exits_3_shows_fail_and_timing_has_tool_rows(tmp_path):
    out = tmp_path / "out"
    res = cli("machine", str(_write(tmp_path, 20.0)), "-o", str(out), "--phase-sweep", "gripper")
    assert res.returncode == 3, res.stderr
    report = json.loads((out / "machine.json").read_text(encoding="utf-8"))
    row = report["clearance"]["pairs"][0]
    line = next(ln for ln in res.stdout.splitlines() if ln.strip().startswith("clearance pusher/gripper"))
    assert "FAIL" in line and f"{row['distance']:.6g}" in line and f"{row['remedy']['shift']:.6g}" in line
    assert "phase sweep of gripper" in res.stdout
    page = (out / "machine.html").read_text(encoding="utf-8")
    assert 'data-key="clearance.pairs.0.status">FAIL<' in page
    assert f'data-key="clearance.pairs.0.distance" data-value="{row["distance"]!r}"' in page
    gids = {e.get("id") for e in ET.parse(out / "timing.svg").iter()} | \
           {e.get("gid") for e in ET.parse(out / "timing.svg").iter()}
    text = (out / "timing.svg").read_text(encoding="utf-8")
    for cam in ("pusher", "gripper"):
        for key in ("s", "v", "a"):
            assert f"timing-{cam}-tool-{key}" in gids or f"timing-{cam}-tool-{key}" in text
    assert "timing-lifter-tool-s" not in text


# ---- the shortest cycle (docs/clearance.md, "The shortest cycle of a machine") ---------------------------
H_SC, D_SC, RA, RB = 10.0, 30.0, 2.0, 3.0        # lift, distance of B's origin, the circles' radii [mm]


def full_harmonic() -> dict[str, Any]:
    """A radial roller rising h over 180° and returning over 180°, both harmonic: s(x) = h/2·(1 − cos x)."""
    return {"units": "mm", "cam": {"base_radius": 50.0, "thickness": 10.0, "bore_diameter": 12.0},
            "follower": {"kind": "roller", "roller_radius": 5.0, "mass": 0.2},
            "motion": [{"kind": "rise", "angle": 180.0, "lift": H_SC, "law": "harmonic"},
                       {"kind": "return", "angle": 180.0, "lift": H_SC, "law": "harmonic"}]}


def opposed(phase_b: float, required: float) -> dict[str, Any]:
    """Tool A (circle r_a) at (s_A(ψ), 0), tool B (circle r_b) at (D − s_B(ψ − φ), 0): their clearance
    is c(φ) = D − r_a − r_b − h − h·|cos(φ/2)| (the sum s_A + s_B = h − h·cos(φ/2)·cos(ψ − φ/2))."""
    return {"machine": {"name": "opposed", "speed_rpm": 60.0},
            "cam": [{"name": "a", "phase": 0.0, "spec": full_harmonic(),
                     "tool": {"circle": {"radius": RA}, "origin": [0.0, 0.0], "direction": 0.0}},
                    {"name": "b", "phase": phase_b, "spec": full_harmonic(),
                     "tool": {"circle": {"radius": RB}, "origin": [D_SC, 0.0], "direction": 180.0}}],
            "clearance": [{"between": ["a", "b"], "required": required}]}


def c_closed(phi_deg: float) -> float:
    return D_SC - RA - RB - H_SC - H_SC * abs(math.cos(math.radians(phi_deg) / 2))


def test_shortest_cycle_closed_form_limited_by_the_clearance():
    """B at 170°: its rise follows A's rise (d = 170°); the clearance (8 mm) holds down to
    φ_lo = 2·acos((D − r_a − r_b − h − 8)/h), so φ* = φ_lo, saved = 170° − φ_lo, overlap = 180° − φ_lo."""
    req = 8.0
    lo = math.degrees(2 * math.acos((D_SC - RA - RB - H_SC - req) / H_SC))
    ps = analyse_machine(machine_from_dict(opposed(170.0, req)), sweep="b").summary()["phase_sweep"]
    sc = ps["shortest_cycle"]
    # the phase's error: the sampled clearance's error bound over the slope |dc/dφ| at φ_lo [mm/deg]
    slope = H_SC / 2 * math.sin(math.radians(lo) / 2) * math.pi / 180
    tol = ps["pairs"][0]["error_bound"] / slope + 1e-9
    assert ps["pairs"][0]["error_bound"] < 1e-3
    assert sc["follows"] == {"cam": "a", "event": "a rise", "start_deg": 0.0, "end_deg": 180.0, "span_deg": 180.0}
    assert sc["motion"] == {"event": "b rise", "start_deg": 170.0}
    assert sc["phase_deg"] == pytest.approx(lo, abs=tol)
    assert sc["saved_deg"] == pytest.approx(170.0 - lo, abs=tol)
    assert sc["overlap_deg"] == pytest.approx(180.0 - lo, abs=tol)
    assert sc["current_overlap_deg"] == pytest.approx(10.0, abs=1e-9)
    assert sc["limited_by"] == "clearance" and sc["binding_pairs"] == ["a/b"]
    # the refined clearance at φ* is the closed form's there, and required to within the sweep's bound
    row = sc["clearance_at_phase"][0]
    assert row["distance"] == pytest.approx(c_closed(sc["phase_deg"]), abs=2e-6)
    assert row["distance"] >= req - ps["pairs"][0]["error_bound"] and row["distance"] == pytest.approx(req, abs=1e-3)
    # the cycle at 60 rpm: 1 s, and (360 − saved)/360 s; both cams always move: no whole-machine dwell
    assert sc["cycle_time_s"] == 1.0
    assert sc["shortest_cycle_time_s"] == pytest.approx((360.0 - sc["saved_deg"]) / 360.0, rel=1e-12)
    assert sc["cycles_per_min"] == pytest.approx(60.0 * 360.0 / (360.0 - sc["saved_deg"]), rel=1e-12)
    assert sc["machine_dwell_deg"] == 0.0 and sc["machine_dwell_at_phase_deg"] == 0.0
    assert sc["assumption_holds"] is False and "dwell of the whole machine" in sc["assumption"]


def test_shortest_cycle_closed_form_limited_by_the_order_and_a_failing_phase():
    # 4 mm: c(φ) ≥ 5 mm at every phase — B may start with A's rise (φ* = 0), its clearance c(0) = 5
    sc = analyse_machine(machine_from_dict(opposed(170.0, 4.0)), sweep="b").summary()["phase_sweep"]["shortest_cycle"]
    assert sc["limited_by"] == "order" and sc["binding_pairs"] == []
    assert sc["phase_deg"] == 0.0 and sc["saved_deg"] == 170.0 and sc["overlap_deg"] == 180.0
    assert sc["clearance_at_phase"][0]["distance"] == pytest.approx(c_closed(0.0), abs=2e-6)
    # B at 250°: its rise follows A's return (180°, d = 70°)
    sc = analyse_machine(machine_from_dict(opposed(250.0, 4.0)), sweep="b").summary()["phase_sweep"]["shortest_cycle"]
    assert sc["follows"]["event"] == "a return" and sc["saved_deg"] == pytest.approx(70.0, abs=1e-9)
    # B at 30° does not keep 8 mm (c(30°) < 8): no answer, and the note says why
    ps = analyse_machine(machine_from_dict(opposed(30.0, 8.0)), sweep="b").summary()["phase_sweep"]
    assert not ps["current_phase_passes"]
    sc = ps["shortest_cycle"]
    assert sc["phase_deg"] is None and sc["saved_deg"] is None and "does not keep every clearance" in sc["note"]


def test_whole_machine_dwell_against_the_followers_velocities(example):
    """machine_dwell_deg: the longest arc where no follower moves, here from every follower's
    velocity on a 0.01° grid (zero on a dwell), the gripper at its phase now and at φ*."""
    from cam_workbench.generators.machine import follower_timing

    machine, _ = example
    sc = analyse_machine(machine, sweep="gripper").summary()["phase_sweep"]["shortest_cycle"]
    theta = np.radians(np.arange(36000) * 0.01)

    def dwell(gripper_phase: float) -> float:
        moving = np.zeros(theta.size, bool)
        for cam in machine.cams:
            phase = gripper_phase if cam.name == "gripper" else cam.phase
            t = follower_timing(cam.name, cam.spec, phase, theta, machine.omega, None, cam.tool)
            moving |= np.abs(t.v) > 1e-9
        still = np.concatenate([~moving, ~moving])               # twice round: runs through 0°
        best = run = 0
        for flag in still:
            run = run + 1 if flag else 0
            best = max(best, run)
        return min(best, theta.size) * 0.01

    assert sc["machine_dwell_deg"] == pytest.approx(dwell(100.0), abs=0.02)
    assert sc["machine_dwell_at_phase_deg"] == pytest.approx(dwell(sc["phase_deg"]), abs=0.02)
    assert sc["dwell_gained_deg"] == sc["machine_dwell_at_phase_deg"] - sc["machine_dwell_deg"]
    assert sc["assumption_holds"] == (sc["dwell_gained_deg"] >= sc["saved_deg"] - 1e-9)


def _leaves(node: Any, prefix: str) -> dict[str, Any]:
    if isinstance(node, dict):
        return {k: v for key, val in node.items() for k, v in _leaves(val, f"{prefix}.{key}").items()}
    if isinstance(node, list):
        return {k: v for i, val in enumerate(node) for k, v in _leaves(val, f"{prefix}.{i}").items()}
    return {prefix: node}


@requires_ocp
def test_cli_shortest_cycle_html_and_printout_are_machine_json(tmp_path):
    """Every number of machine.json's shortest_cycle is a machine.html cell holding its exact value,
    and every number the printout's shortest-cycle lines show is one of them."""
    import re
    from html.parser import HTMLParser

    out = tmp_path / "out"
    res = cli("machine", "--example", "three_cams", "-o", str(out), "--phase-sweep", "gripper", "--animation", "none")
    assert res.returncode == 0, res.stderr
    report = json.loads((out / "machine.json").read_text(encoding="utf-8"))
    sc = report["phase_sweep"]["shortest_cycle"]
    assert sc["note"] is None and sc["saved_deg"] > 0

    class Cells(HTMLParser):
        def __init__(self):
            super().__init__()
            self.cells: dict[str, str] = {}

        def handle_starttag(self, tag, attrs):
            a = dict(attrs)
            if "data-key" in a and "data-value" in a:
                self.cells[a["data-key"]] = a["data-value"]

    p = Cells()
    p.feed((out / "machine.html").read_text(encoding="utf-8"))
    numbers = {k: v for k, v in _leaves(sc, "phase_sweep.shortest_cycle").items()
               if isinstance(v, float) or (isinstance(v, int) and not isinstance(v, bool))}
    assert len(numbers) > 15
    for key, value in numbers.items():
        assert p.cells.get(key) == repr(value), key
    lines = [ln for ln in res.stdout.splitlines() if "shortest cycle" in ln or ln.startswith("    cycle")]
    assert len(lines) == 2
    values = list(numbers.values()) + [report["machine"]["speed_rpm"]]
    for token in re.findall(r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?", " ".join(lines)):
        assert any(abs(float(token) - v) <= 5e-6 * max(1.0, abs(v)) for v in values), token

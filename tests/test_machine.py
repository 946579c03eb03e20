"""Many cams on one camshaft (issue 24, part 2): the machine file's rules, the timing on the
machine's clock, the camshaft torque and the flywheel against closed forms and independent
integrations written here, and the ``machine`` command's outputs (every number machine.json's)."""
from __future__ import annotations

import copy
import json
import math
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import example, given, settings, strategies as st

from cam_workbench.generators.dynamics.analysis import analyse_dynamics
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.machine import (MACHINES, analyse_machine, example_machine_dict, flywheel,
                                              follower_timing, load_machine, machine_from_dict, machine_grid)
from cam_workbench.generators.machine.torque import cam_angles, cam_torque
from cam_workbench.generators.motion.program import MotionProgram
from cam_workbench.generators.spec import spec_digest

from .conftest import ROOT, assert_unchanged, has_module, requires_ocp, snapshot

CLI = [sys.executable, "-m", "cam_workbench.cli"]
EXAMPLE = ROOT / "docs" / "examples" / "machine_three_cams.toml"
NUMBER = r"[-−+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?"


def cli(*args: str, cwd: Path | None = None, path: str | None = None) -> subprocess.CompletedProcess:
    """The CLI in a subprocess; ``path``: its PATH (e.g. one without ffmpeg)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), COLUMNS="250")
    if path is not None:
        env["PATH"] = path
    return subprocess.run([*CLI, *args], capture_output=True, text=True, env=env, cwd=cwd)


# ---- a harmonic cam, in closed form ---------------------------------------------------------------
M, P, K = 0.6, 25.0, 1.2          # kg, N, N/mm
H, BETA_DEG = 18.0, 120.0         # mm, deg


def harmonic_spec(lift: float = H, beta: float = BETA_DEG, mass: float = M, preload: float = P,
                  rate: float = K) -> dict[str, Any]:
    """A radial roller on a harmonic rise over β, dwell, harmonic return over β, dwell (R_b 60)."""
    rest = (360.0 - 2 * beta) / 2
    return {"units": "mm", "cam": {"base_radius": 60.0, "thickness": 10.0, "bore_diameter": 12.0},
            "follower": {"kind": "roller", "roller_radius": 6.0, "mass": mass, "preload": preload,
                         "spring_rate": rate},
            "motion": [{"kind": "rise", "angle": beta, "lift": lift, "law": "harmonic"},
                       {"kind": "dwell", "angle": rest},
                       {"kind": "return", "angle": beta, "lift": lift, "law": "harmonic"},
                       {"kind": "dwell", "angle": rest}]}


def harmonic_s(x: np.ndarray, lift: float = H, beta_deg: float = BETA_DEG) -> tuple[np.ndarray, ...]:
    """s, s′, s″ (per rad) of :func:`harmonic_spec`'s program at cam angles x [rad], written out."""
    b = math.radians(beta_deg)
    rest = (2 * math.pi - 2 * b) / 2
    x = np.mod(x, 2 * math.pi)
    s, ds, d2s = np.zeros_like(x), np.zeros_like(x), np.zeros_like(x)
    rise = x < b
    u = np.pi * x[rise] / b
    s[rise] = lift / 2 * (1 - np.cos(u))
    ds[rise] = lift * np.pi / (2 * b) * np.sin(u)
    d2s[rise] = lift * np.pi**2 / (2 * b * b) * np.cos(u)
    top = (x >= b) & (x < b + rest)
    s[top] = lift
    ret = (x >= b + rest) & (x < 2 * b + rest)
    u = np.pi * (x[ret] - b - rest) / b
    s[ret] = lift / 2 * (1 + np.cos(u))
    ds[ret] = -lift * np.pi / (2 * b) * np.sin(u)
    d2s[ret] = -lift * np.pi**2 / (2 * b * b) * np.cos(u)
    return s, ds, d2s


def machine_dict(*cams: tuple[str, float, dict[str, Any]], rpm: float = 90.0, **machine: Any) -> dict[str, Any]:
    return {"machine": {"name": "test", "speed_rpm": rpm, **machine},
            "cam": [{"name": n, "phase": ph, "spec": copy.deepcopy(sp)} for n, ph, sp in cams]}


# ---- torque ----------------------------------------------------------------------------------------
def test_total_torque_is_the_sum_of_each_cams_virtual_work():
    """T = F·ds/dθ per cam, F = m·s″ω² + P + k·s from the spec's numbers (kg·mm/s² → N: 10⁻³),
    each at its own angle x = θ − φ; the machine's total is their sum on the grid."""
    a = harmonic_spec()
    b = harmonic_spec(lift=10.0, beta=90.0, mass=1.5, preload=40.0, rate=0.5)
    mach = machine_from_dict(machine_dict(("a", 0.0, a), ("b", 37.25, b), rpm=90.0))
    r = analyse_machine(mach)
    w = 90.0 * 2 * math.pi / 60
    theta = 2 * math.pi * np.arange(720) / 720
    expected = np.zeros_like(theta)
    for phase, lift, beta, m, p, k in ((0.0, H, BETA_DEG, M, P, K), (37.25, 10.0, 90.0, 1.5, 40.0, 0.5)):
        s, ds, d2s = harmonic_s(theta - math.radians(phase), lift, beta)
        force = m * 1e-3 * d2s * w**2 + p + k * s
        expected += force * ds
    np.testing.assert_allclose(r.theta, theta, rtol=0, atol=1e-15)
    np.testing.assert_allclose(r.total, expected, rtol=1e-9, atol=1e-9 * np.max(np.abs(expected)))
    summary = r.summary()
    assert summary["torque"]["max"] == pytest.approx(expected.max(), rel=1e-9)
    assert summary["torque"]["rms"] == pytest.approx(math.sqrt(np.mean(expected**2)), rel=1e-9)
    assert summary["torque"]["unit"] == "N·mm"


@pytest.mark.parametrize("example", ["default", "oscillating", "flat"])
def test_cam_torque_is_the_dynamics_rigid_torque(example):
    """The machine's per-cam torque is the project's camshaft torque: analyse_dynamics' rigid
    torque (report.json dynamics.torque.rigid), at the dynamics' own samples."""
    from cam_workbench.generators.spec.examples import example_spec

    spec = example_spec(example)
    field = "dynamics.torsional_stiffness" if spec.follower.motion == "oscillating" else "dynamics.stiffness"
    dyn = analyse_dynamics(spec.replace(**{field: 1.0e6}), sweep=False)
    mine = cam_torque(spec, dyn.theta, dyn.omega)
    np.testing.assert_allclose(mine, dyn.rigid_torque, rtol=1e-12, atol=1e-9 * np.max(np.abs(dyn.rigid_torque)))


# ---- flywheel ---------------------------------------------------------------------------------------
def _trapezoid_energy(f, n: int = 400_001) -> float:
    """ΔE of a torque function by the trapezoid rule on a fine grid (independent of the code)."""
    th = np.linspace(0.0, 2 * math.pi, n)
    t = f(th)
    steps = 0.5 * (t[1:] + t[:-1]) * np.diff(th)
    mean = steps.sum() / (2 * math.pi)
    e = np.concatenate([[0.0], np.cumsum(steps - mean * np.diff(th))])
    return float(e.max() - e.min())


def test_flywheel_of_a_sine_torque_is_2_t0():
    """T = T0·sin θ: E = T0(1 − cos θ), ΔE = 2·T0; I = ΔE/(C_s·ω²)."""
    t0, w, cs = 5000.0, 4 * math.pi, 0.05     # N·mm, rad/s
    theta = machine_grid(720)
    fw = flywheel(theta, t0 * np.sin(theta), w, cs, "mm")
    assert fw.fluctuation == pytest.approx(2 * t0 * 1e-3, rel=1e-5)   # J
    assert fw.inertia == pytest.approx(2 * t0 * 1e-3 / (cs * w * w), rel=1e-5)
    assert fw.at_min_deg == pytest.approx(0.0, abs=1e-9)
    assert fw.at_max_deg == pytest.approx(180.0, abs=1e-9)


def test_flywheel_against_a_fine_trapezoid():
    """A torque with a mean and harmonics: the grid's ΔE against the fine integration here."""
    def f(th):
        return 300.0 + 2000.0 * np.sin(th) - 700.0 * np.cos(3 * th + 0.4) + 150.0 * np.sin(7 * th)

    theta = machine_grid(720)
    fw = flywheel(theta, f(theta), 10.0, 0.02, "mm")
    assert fw.fluctuation == pytest.approx(_trapezoid_energy(f) * 1e-3, rel=2e-4)
    # lbf·in: 1 lbf·in = 0.1129848290276167 J
    fw_in = flywheel(theta, f(theta), 10.0, 0.02, "in")
    assert fw_in.fluctuation == pytest.approx(_trapezoid_energy(f) * 0.1129848290276167, rel=2e-4)


def test_machine_flywheel_against_the_independent_torque():
    """The machine's flywheel from its summed torque, against the fine trapezoid of the closed-form
    torques of its two harmonic cams."""
    mach = machine_from_dict(machine_dict(("a", 0.0, harmonic_spec()), ("b", 200.0, harmonic_spec(lift=8.0)),
                                          rpm=150.0, speed_fluctuation=0.03))
    r = analyse_machine(mach)
    w = 150.0 * 2 * math.pi / 60

    def total(th):
        out = np.zeros_like(th)
        for phase, lift in ((0.0, H), (200.0, 8.0)):
            s, ds, d2s = harmonic_s(th - math.radians(phase), lift)
            out += (M * 1e-3 * d2s * w**2 + P + K * s) * ds
        return out

    de = _trapezoid_energy(total) * 1e-3
    fw = r.summary()["flywheel"]
    assert fw["energy_fluctuation_J"] == pytest.approx(de, rel=1e-3)
    assert fw["inertia_kg_m2"] == pytest.approx(de / (0.03 * w * w), rel=1e-3)


# ---- timing ------------------------------------------------------------------------------------------
@settings(max_examples=40, deadline=None)
@given(phase=st.floats(0.0, 359.999), xs=st.lists(st.floats(0.0, 359.999), min_size=1, max_size=20),
       rpm=st.floats(1.0, 600.0))
@example(phase=149.0, xs=[120.0], rpm=60.0)
def test_a_cam_with_phase_phi_is_at_s_x_at_machine_angle_phi_plus_x(phase, xs, rpm):
    spec = machine_from_dict(machine_dict(("c", phase, harmonic_spec()), rpm=rpm)).cams[0].spec
    x = np.radians(np.array(xs))
    w = rpm * 2 * math.pi / 60
    t = follower_timing("c", spec, phase, np.radians(phase) + x, w)
    s, ds, d2s = harmonic_s(x)
    np.testing.assert_allclose(t.s, s, atol=1e-9 * H)
    np.testing.assert_allclose(t.v, ds * w, atol=1e-9 * H * w)
    # a harmonic law's acceleration jumps at the segments' ends: (φ + x) − φ may land on either side
    rest = (360.0 - 2 * BETA_DEG) / 2
    ends = np.array([0.0, BETA_DEG, BETA_DEG + rest, 2 * BETA_DEG + rest, 360.0])
    away = np.abs(np.array(xs)[:, None] - ends[None, :]).min(axis=1) > 1e-6
    np.testing.assert_allclose(t.a[away], (d2s * w * w)[away], atol=1e-8 * H * w * w)


@settings(max_examples=25, deadline=None)
@given(phases=st.lists(st.floats(0.0, 359.9), min_size=1, max_size=3),
       step=st.sampled_from([0.25, 0.5, 1.0, 2.0, 5.0]))
def test_grid_events_and_cam_angles_for_any_phases(phases, step):
    """Option combinations: any phases on any grid step — the grid has 360/step points, each cam's
    events sit at phase + its segment boundaries, and the total is the sum of the cams'."""
    cams = [(f"c{i}", ph, harmonic_spec(lift=5.0 + i)) for i, ph in enumerate(phases)]
    mach = machine_from_dict(machine_dict(*cams, grid_step=step))
    r = analyse_machine(mach)
    assert r.theta.size == round(360 / step)
    np.testing.assert_allclose(r.total, np.sum(r.torques, axis=0), rtol=0, atol=0)
    rest = (360.0 - 2 * BETA_DEG) / 2
    for t, ph in zip(r.timings, phases):
        rise, ret = t.events
        assert (rise.label, ret.label) == (f"{t.name} rise", f"{t.name} return")
        assert rise.start_deg == pytest.approx(ph % 360.0, abs=1e-9)
        assert ret.start_deg == pytest.approx((ph + BETA_DEG + rest) % 360.0, abs=1e-9)
        x = cam_angles(r.theta, ph)
        assert np.all((x >= 0) & (x < 2 * math.pi))


def test_speed_absent_takes_the_machines_equal_is_accepted():
    spec = harmonic_spec()
    same = copy.deepcopy(spec)
    same["cam"]["speed_rpm"] = 90.0
    m = machine_from_dict(machine_dict(("a", 0.0, spec), ("b", 10.0, same), rpm=90.0))
    assert [c.spec.cam.speed_rpm for c in m.cams] == [90.0, 90.0]


def test_the_example_file_is_the_built_in_machine():
    assert set(MACHINES) == {"three_cams"}
    assert load_machine(EXAMPLE).to_dict() == machine_from_dict(example_machine_dict("three_cams")).to_dict()


# ---- bad machine files -------------------------------------------------------------------------------
def _toml(spec: dict[str, Any]) -> str:
    from cam_workbench.generators.spec.toml_io import dict_to_toml

    return dict_to_toml(spec)


GOOD_SPEC = harmonic_spec()
BAD_FILES = {
    "missing cam": ('[machine]\nname = "m"\nspeed_rpm = 60.0\n', "cam:"),
    "duplicate name": ('[machine]\nname = "m"\nspeed_rpm = 60.0\n[[cam]]\nname = "a"\nspec = "a.toml"\n'
                       '[[cam]]\nname = "A"\nspec = "a.toml"\n', "cam[1].name:"),
    "bad phase": ('[machine]\nname = "m"\nspeed_rpm = 60.0\n[[cam]]\nname = "a"\nspec = "a.toml"\nphase = 400.0\n',
                  "cam[0].phase:"),
    "phase not a number": ('[machine]\nname = "m"\nspeed_rpm = 60.0\n[[cam]]\nname = "a"\nspec = "a.toml"\n'
                           'phase = "late"\n', "cam[0].phase:"),
    "speed conflict": ('[machine]\nname = "m"\nspeed_rpm = 60.0\n[[cam]]\nname = "a"\nspec = "a.toml"\n'
                       '[[cam]]\nname = "b"\nspec = "a.toml"\n[[cam]]\nname = "c"\nspec = "fast.toml"\n',
                       "cam[2].spec.cam.speed_rpm:"),
    "spec path missing": ('[machine]\nname = "m"\nspeed_rpm = 60.0\n[[cam]]\nname = "a"\nspec = "nowhere.toml"\n',
                          "cam[0].spec:"),
    "bad folder name": ('[machine]\nname = "m"\nspeed_rpm = 60.0\n[[cam]]\nname = "../up"\nspec = "a.toml"\n',
                        "cam[0].name:"),
    "cam spec rule": ('[machine]\nname = "m"\nspeed_rpm = 60.0\n[[cam]]\nname = "a"\nspec = "bad.toml"\n',
                      "cam[0].spec.cam.base_radius:"),
    "unknown field": ('[machine]\nname = "m"\nspeed_rpm = 60.0\nspeed = 3\n[[cam]]\nname = "a"\nspec = "a.toml"\n',
                      "machine.speed:"),
    "tool without outline": ('[machine]\nname = "m"\nspeed_rpm = 60.0\n[[cam]]\nname = "a"\nspec = "a.toml"\n'
                             '[cam.tool]\nlabel = "x"\n', "cam[0].tool:"),
    "flat polygon": ('[machine]\nname = "m"\nspeed_rpm = 60.0\n[[cam]]\nname = "a"\nspec = "a.toml"\n'
                     '[cam.tool]\npolygon = [[0, 0], [1, 1], [2, 2]]\n', "cam[0].tool.polygon:"),
    "missing speed": ('[machine]\nname = "m"\n[[cam]]\nname = "a"\nspec = "a.toml"\n', "machine.speed_rpm:"),
}


def _bad_folder(tmp_path: Path, text: str) -> Path:
    (tmp_path / "a.toml").write_text(_toml(GOOD_SPEC), encoding="utf-8")
    fast = copy.deepcopy(GOOD_SPEC)
    fast["cam"]["speed_rpm"] = 90.0
    (tmp_path / "fast.toml").write_text(_toml(fast), encoding="utf-8")
    bad = copy.deepcopy(GOOD_SPEC)
    bad["cam"]["base_radius"] = -5.0
    (tmp_path / "bad.toml").write_text(_toml(bad), encoding="utf-8")
    (tmp_path / "m.toml").write_text(text, encoding="utf-8")
    return tmp_path / "m.toml"


@pytest.mark.parametrize("case", list(BAD_FILES))
def test_bad_machine_file_raises_naming_the_field(tmp_path, case):
    text, field = BAD_FILES[case]
    with pytest.raises(SpecError) as err:
        load_machine(_bad_folder(tmp_path, text))
    assert str(err.value).startswith(field), str(err.value)


@pytest.mark.parametrize("case", ["missing cam", "duplicate name", "bad phase", "speed conflict", "spec path missing"])
def test_cli_bad_machine_file_exits_2_and_writes_nothing(tmp_path, case):
    text, field = BAD_FILES[case]
    path = _bad_folder(tmp_path, text)
    before = snapshot(tmp_path)
    res = cli("machine", str(path), "-o", str(tmp_path / "out"))
    assert res.returncode == 2, res.stderr
    assert res.stderr.startswith(f"error: {field}"), res.stderr
    assert "Traceback" not in res.stderr
    assert_unchanged(tmp_path, before)


# ---- the command and its outputs ---------------------------------------------------------------------
@pytest.fixture(scope="module")
def built(tmp_path_factory):
    if not has_module("OCP"):
        pytest.skip("OCP (cadquery-ocp) is not installed")
    out = tmp_path_factory.mktemp("machine") / "out"
    res = cli("machine", str(EXAMPLE), "-o", str(out))
    assert res.returncode == 0, res.stderr
    return out, res.stdout, json.loads((out / "machine.json").read_text(encoding="utf-8"))


def _numbers(data: Any) -> list[float]:
    if isinstance(data, dict):
        return [x for v in data.values() for x in _numbers(v)]
    if isinstance(data, list):
        return [x for v in data for x in _numbers(v)]
    if isinstance(data, (int, float)) and not isinstance(data, bool):
        return [float(data)]
    return []


def _agrees(token: str, value: float) -> bool:
    text = token.replace("−", "-")
    mantissa, _, exponent = text.lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    half = 0.5 * 10.0 ** (int(exponent or 0) - decimals)
    return abs(float(text) - value) <= half * (1 + 1e-9) + 1e-12 * abs(value)


@requires_ocp
def test_every_printed_number_is_machine_json(built):
    out, stdout, report = built
    values = _numbers({k: v for k, v in report.items() if k != "files"})
    lines = stdout.splitlines()
    assert lines[0].startswith(f"machine 'transfer station' written to {out}/")
    for line in lines[1:]:
        for token in re.findall(NUMBER, line):
            assert any(_agrees(token, v) for v in values), f"{token!r} in {line!r} is no machine.json number"
    tq, fw = report["torque"], report["flywheel"]
    torque_line = next(ln for ln in lines if ln.strip().startswith("torque ["))
    got = re.findall(NUMBER, torque_line.split("]:")[1])
    keys = ("max", "max_at_deg", "min", "min_at_deg", "mean", "rms")
    assert len(got) == len(keys)
    for token, key in zip(got, keys):
        assert _agrees(token, tq[key]), (token, key, tq[key])
    fw_line = next(ln for ln in lines if ln.strip().startswith("flywheel:"))
    assert f"{fw['energy_fluctuation_J']:.6g} J" in fw_line and f"{fw['inertia_kg_m2']:.6g} kg·m²" in fw_line


class _Cells(HTMLParser):
    def __init__(self):
        super().__init__()
        self.cells: list[tuple[dict, str]] = []
        self.rows: list[dict] = []
        self._open: dict | None = None
        self._text = ""

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "tr":
            self.rows.append(a)
        if tag == "td" and "data-key" in a:
            self._open, self._text = a, ""

    def handle_data(self, data):
        if self._open is not None:
            self._text += data

    def handle_endtag(self, tag):
        if tag == "td" and self._open is not None:
            self.cells.append((self._open, self._text))
            self._open = None


def _lookup(report: Any, key: str) -> Any:
    node = report
    for part in key.split("."):
        node = node[int(part)] if isinstance(node, list) else node[part]
    return node


@requires_ocp
def test_html_numbers_are_machine_json_and_the_checks_are_each_cams_report(built):
    out, _stdout, report = built
    p = _Cells()
    p.feed((out / "machine.html").read_text(encoding="utf-8"))
    assert len(p.cells) > 50
    for attrs, text in p.cells:
        value = _lookup(report, attrs["data-key"])
        if "data-value" in attrs:
            assert attrs["data-value"] == ("null" if value is None else repr(value)), attrs
            if isinstance(value, float):
                assert text == f"{value:.6g}"
        else:
            assert text == str(value)
    # one row per cam and check, as each cam's own report.json says
    rows = {(r["data-cam"], r["data-check"]): r for r in p.rows if "data-check" in r}
    expected = {}
    for cam in report["cams"]:
        own = json.loads((out / cam["folder"] / "report.json").read_text(encoding="utf-8"))
        for name, res in own["checks"]["results"].items():
            expected[(cam["name"], name)] = res["status"]
    assert set(rows) == set(expected)
    for key, status in expected.items():
        assert (rows[key].get("class") == "fail") == (status == "fail")
    assert "<svg" in (out / "machine.html").read_text(encoding="utf-8")


@requires_ocp
def test_each_cam_folder_is_builds_set(built):
    out, _stdout, report = built
    machine = load_machine(EXAMPLE)
    for cam in machine.cams:
        folder = out / cam.name
        own = json.loads((folder / "report.json").read_text(encoding="utf-8"))
        assert own["spec_digest"] == spec_digest(cam.spec)
        names = {p.name for p in folder.iterdir()}
        assert {"cam.step", "cam.dxf", "cam.nc", "commands.csv", "report.json", "report.html",
                ".cam-workbench.json"} <= names
        assert own["checks"]["passed"] == report["cams"][machine.cams.index(cam)]["checks"]["passed"]


@requires_ocp
def test_timing_svg_has_one_labelled_curve_per_cam(built):
    out, _stdout, report = built
    root = ET.parse(out / "timing.svg").getroot()
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    ids = {e.get("id") for e in root.iter() if e.get("id")}
    texts = " ".join(e.text or "" for e in root.iter("{http://www.w3.org/2000/svg}text"))
    for cam in report["cams"]:
        for q in ("s", "v", "a"):
            assert f"timing-timing-{cam['name']}-{q}" in ids
        assert f"{cam['name']} ({cam['lift_unit']}, phase" in texts           # the legend's label
        for e in cam["events"]:
            assert e["label"] in texts
    assert (out / "timing.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (out / "torque.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@requires_ocp
def test_rerun_replaces_its_own_set_and_refuses_a_folder_of_yours(built, tmp_path):
    out, _stdout, _report = built
    res = cli("machine", str(EXAMPLE), "-o", str(out))           # the same machine again: its own set
    assert res.returncode == 0, res.stderr
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("keep me", encoding="utf-8")
    before = snapshot(tmp_path)
    res = cli("machine", "--example", "three_cams", "-o", str(mine))
    assert res.returncode == 2 and "notes.txt" in res.stderr
    assert_unchanged(tmp_path, before)


@requires_ocp
def test_api_build_with_a_spec_file_and_a_failing_cam(tmp_path):
    """Machine(dict) with a cam spec given as a path and one failing its pressure-angle check:
    the failing check is in machine.json's verdict and shown failing in the one checks table."""
    from cam_workbench import Machine
    from cam_workbench.generators.spec.examples import example_dict

    paper = example_dict("paper")
    paper["cam"].pop("speed_rpm")
    (tmp_path / "paper.toml").write_text(_toml(paper), encoding="utf-8")
    data = machine_dict(("good", 0.0, harmonic_spec()), rpm=60.0)
    data["cam"].append({"name": "paper", "phase": 45.0, "spec": "paper.toml"})
    report = Machine(machine_from_dict(data, base_dir=tmp_path)).build(tmp_path / "out")
    assert report["checks"]["passed"] is False
    assert "paper.pressure_angle" in report["checks"]["failed"]
    assert report["cams"][1]["spec_source"] == str((tmp_path / "paper.toml").resolve())
    html_text = (tmp_path / "out" / "machine.html").read_text(encoding="utf-8")
    assert re.search(r'<tr class="fail" data-cam="paper" data-check="pressure_angle">', html_text)


# ---- the animation (docs/animation.md) ---------------------------------------------------------------
@requires_ocp
def test_cli_writes_the_animation_gif_of_72_frames(built):
    from PIL import Image

    out, stdout, report = built
    assert report["files"]["animation"] == "machine.gif"
    assert report["animation"]["frames"] == 360 / 5.0 == 72 and report["animation"]["note"] is None
    with Image.open(out / "machine.gif") as im:
        assert im.format == "GIF" and im.n_frames == 72
    assert '<img src="machine.gif"' in (out / "machine.html").read_text(encoding="utf-8")
    assert "machine.gif" in stdout.splitlines()[0]


@requires_ocp
def test_cli_animation_none_writes_none(tmp_path):
    out = tmp_path / "out"
    res = cli("machine", "--example", "three_cams", "-o", str(out), "--animation", "none")
    assert res.returncode == 0, res.stderr
    report = json.loads((out / "machine.json").read_text(encoding="utf-8"))
    assert not list(out.glob("machine.gif")) and not list(out.glob("machine.mp4"))
    assert "animation" not in report["files"] and report["animation"]["file"] is None
    assert report["animation"]["note"] in res.stdout


def test_cli_mp4_without_ffmpeg_exits_2_and_writes_nothing(tmp_path):
    """Run where ffmpeg is not on the PATH (an empty folder is the whole PATH; the CLI is started by
    its interpreter's full path), whether or not this machine has ffmpeg."""
    (tmp_path / "empty").mkdir()
    before = snapshot(tmp_path)
    res = cli("machine", "--example", "three_cams", "-o", str(tmp_path / "out"), "--animation", "mp4",
              path=str(tmp_path / "empty"))
    assert res.returncode == 2 and "--animation" in res.stderr, res.stderr
    assert_unchanged(tmp_path, before)


@pytest.mark.parametrize("name", ["machine.gif", "Machine.MP4"])
def test_animation_file_names_are_reserved(name):
    data = machine_dict((name, 0.0, harmonic_spec()), rpm=60.0)
    with pytest.raises(SpecError, match=r"cam\[0\]\.name"):
        machine_from_dict(data)


# ---- optional dependencies, simulated missing for real (a package that raises ImportError first on the path) --
def _blocked(tmp_path: Path, *names: str) -> str:
    """A folder holding a package for each of ``names`` whose import raises ImportError: put first on
    PYTHONPATH, the subprocess sees the package missing."""
    root = tmp_path / "blocked"
    for name in names:
        (root / name).mkdir(parents=True)
        (root / name / "__init__.py").write_text(f"raise ImportError('no {name} here')\n", encoding="utf-8")
    return str(root)


def cli_without(tmp_path: Path, names: tuple[str, ...], *args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=f"{_blocked(tmp_path, *names)}{os.pathsep}{ROOT}", COLUMNS="250")
    return subprocess.run([*CLI, *args], capture_output=True, text=True, env=env)


@requires_ocp
def test_without_cairosvg_the_svg_figures_are_written_and_the_printout_says_so(tmp_path):
    out = tmp_path / "out"
    res = cli_without(tmp_path, ("cairosvg",), "machine", "--example", "three_cams", "-o", str(out),
                      "--animation", "none")
    assert res.returncode == 0, res.stderr
    report = json.loads((out / "machine.json").read_text(encoding="utf-8"))
    names = {p.name for p in out.iterdir()}
    assert {"timing.svg", "torque.svg", "machine.json", "machine.html"} <= names
    assert not {"timing.png", "torque.png"} & names
    assert "timing_png" not in report["files"] and report["files"]["timing_svg"] == "timing.svg"
    assert report["figures"]["formats"] == ["svg"] and "CairoSVG" in report["figures"]["note"]
    first = res.stdout.splitlines()[0]
    assert "timing.svg" in first and ".png" not in first
    assert f"figures: SVG ({report['figures']['note']})" in res.stdout
    # the same figures as with CairoSVG: the SVG does not depend on it
    ET.parse(out / "timing.svg")
    assert "<svg" in (out / "machine.html").read_text(encoding="utf-8")


@requires_ocp
def test_with_cairosvg_both_formats_are_listed(built):
    out, stdout, report = built
    assert report["figures"] == {"formats": ["svg", "png"], "note": None}
    assert report["files"]["timing_png"] == "timing.png" and "figures: SVG, PNG" in stdout


@requires_ocp
def test_without_matplotlib_the_default_animation_is_a_note_and_an_explicit_one_is_refused(tmp_path):
    out = tmp_path / "out"
    res = cli_without(tmp_path, ("matplotlib",), "machine", "--example", "three_cams", "-o", str(out))
    assert res.returncode == 0, res.stderr
    report = json.loads((out / "machine.json").read_text(encoding="utf-8"))
    assert report["animation"]["file"] is None and "matplotlib and Pillow" in report["animation"]["note"]
    assert not list(out.glob("machine.gif")) and report["animation"]["note"] in res.stdout
    (tmp_path / "two").mkdir()
    before = snapshot(tmp_path / "two")
    res = cli_without(tmp_path / "two", ("matplotlib",), "machine", "--example", "three_cams", "-o",
                      str(tmp_path / "two" / "out"), "--animation", "gif")
    assert res.returncode == 2 and "--animation gif" in res.stderr and "matplotlib" in res.stderr, res.stderr
    assert "Traceback" not in res.stderr
    after = snapshot(tmp_path / "two")
    assert set(after) - set(before) == {"blocked", "blocked/matplotlib", "blocked/matplotlib/__init__.py"}


# ---- spatial cams in a machine ---------------------------------------------------------------------------
SPATIAL = ("cylindrical", "parallel_indexer", "barrel_indexer", "globoidal_indexer")


def spatial_machine(body: str, phase: float = 130.0, tool: bool = False) -> dict[str, Any]:
    """A harmonic plate cam and the built-in ``body`` example at 60 rpm, phase ``phase``."""
    from cam_workbench.generators.spec.examples import example_dict

    spec = example_dict(body)
    spec["cam"]["speed_rpm"] = 60.0
    if body == "cylindrical":
        spec["follower"]["mass"] = 0.4
    data = machine_dict(("plate", 0.0, harmonic_spec()), (body.replace("_", "-"), phase, spec), rpm=60.0)
    if tool:
        data["cam"][0]["tool"] = {"circle": {"radius": 3.0}}
        data["cam"][1]["tool"] = {"circle": {"radius": 3.0}, "origin": [200.0, 0.0]}
    return data


@pytest.mark.parametrize("body", SPATIAL)
def test_spatial_cam_timing_and_torque(body):
    """A cylindrical cam or an indexer on the machine's clock: its s at machine angle θ is its
    program's s(θ − phase) (an indexer's turret in degrees), and its torque is the rigid train's
    written out here — m·s″ω² · s′ for the cylindrical cam's roller (no spring), J·ω²·u″·u′ for an
    indexer's turret (u = s·π/180; kg·mm²/s² → N·mm: 10⁻³)."""
    mach = machine_from_dict(spatial_machine(body, tool=True))
    r = analyse_machine(mach)
    spec = mach.cams[1].spec
    t = r.timings[1]
    x = cam_angles(r.theta, 130.0)
    k = MotionProgram.from_spec(spec).evaluate(x)
    np.testing.assert_allclose(t.s, k.s, rtol=0, atol=1e-12)
    w = 2 * math.pi
    if body == "cylindrical":
        assert t.lift_unit == "mm"
        # its tool slides from [cam.tool] origin (200, 0) along direction 90° by s
        np.testing.assert_allclose(t.tool, np.c_[np.full_like(k.s, 200.0), k.s], rtol=0, atol=1e-12)
        expected = 0.4 * 1e-3 * k.d2s * w**2 * k.ds
    else:
        assert t.lift_unit == "deg"
        # its tool rides the turret: the frame on the turret's axis at origin, turned by the turret's angle
        np.testing.assert_allclose(t.tool, np.tile([200.0, 0.0], (k.s.size, 1)), rtol=0, atol=1e-12)
        np.testing.assert_allclose(t.tool_angle, np.radians(k.s), rtol=0, atol=1e-12)
        c = math.pi / 180
        expected = 1e-3 * spec.indexer.output_inertia * w**2 * (c * k.d2s) * (c * k.ds)
    np.testing.assert_allclose(r.torques[1], expected, rtol=1e-9, atol=1e-9 * np.max(np.abs(expected)))
    np.testing.assert_allclose(r.total, r.torques[0] + r.torques[1], rtol=0, atol=0)
    assert [e["kind"] for e in r.summary()["cams"][1]["events"]] == [kd for kd, law in zip(
        MotionProgram.from_spec(spec).kinds, MotionProgram.from_spec(spec).laws) if law is not None]


def test_an_indexer_in_a_clearance_pair_is_refused_naming_the_field():
    data = spatial_machine("barrel_indexer", tool=True)
    data["clearance"] = [{"between": ["plate", "barrel-indexer"], "required": 1.0}]
    with pytest.raises(SpecError) as exc:
        machine_from_dict(data)
    assert exc.value.field == "clearance[0].between" and "advances 60° a turn" in exc.value.rule
    data = spatial_machine("cylindrical", tool=True)           # a cylindrical cam's tool comes back: accepted
    data["clearance"] = [{"between": ["plate", "cylindrical"], "required": 1.0}]
    r = analyse_machine(machine_from_dict(data))
    assert r.clearance is not None and r.clearance["pairs"][0]["status"] == "pass"


def test_a_cylindrical_cam_with_an_oscillating_arm_is_refused_naming_the_field():
    from cam_workbench.generators.spec.examples import example_dict

    spec = example_dict("cylindrical_oscillating")
    spec["cam"]["speed_rpm"] = 60.0
    mach = machine_from_dict(machine_dict(("plate", 0.0, harmonic_spec()), ("arm", 0.0, spec), rpm=60.0))
    with pytest.raises(SpecError) as exc:
        analyse_machine(mach)
    assert exc.value.field == "cam[1].spec.follower.motion" and "oscillating" in exc.value.rule


def write_machine(folder: Path, data: dict[str, Any]) -> Path:
    """``data`` (speed, cams with inline specs, no tools) as a machine file in ``folder``, each cam's
    spec in its own file beside it."""
    m = data["machine"]
    text = f'[machine]\nname = "{m["name"]}"\nspeed_rpm = {float(m["speed_rpm"])!r}\n'
    for c in data["cam"]:
        (folder / f"{c['name']}.toml").write_text(_toml(c["spec"]), encoding="utf-8")
        text += f'[[cam]]\nname = "{c["name"]}"\nspec = "{c["name"]}.toml"\nphase = {float(c["phase"])!r}\n'
    path = folder / "m.toml"
    path.write_text(text, encoding="utf-8")
    return path


@requires_ocp
def test_cli_a_spatial_cam_is_left_out_of_the_animation_with_a_note(tmp_path):
    from PIL import Image

    write_machine(tmp_path, spatial_machine("barrel_indexer"))
    for explicit in ((), ("--animation", "gif")):
        out = tmp_path / f"out{len(explicit)}"
        res = cli("machine", str(tmp_path / "m.toml"), "-o", str(out), *explicit)
        assert res.returncode == 0, res.stderr
        report = json.loads((out / "machine.json").read_text(encoding="utf-8"))
        an = report["animation"]
        assert an["file"] == "machine.gif" and an["left_out"] == ["barrel-indexer"]
        assert "cam[1].spec.cam.body is 'barrel_indexer'" in an["note"] and an["note"] in res.stdout
        with Image.open(out / "machine.gif") as im:
            assert im.n_frames == 72
        assert (out / "barrel-indexer" / "report.json").is_file()
        assert report["cams"][1]["lift_unit"] == "deg" and report["cams"][1]["torque"]["max"] > 0


@requires_ocp
def test_cli_no_cam_drawn_is_a_note_by_default_and_refused_when_asked(tmp_path):
    from cam_workbench.generators.spec.examples import example_dict

    spec = example_dict("cylindrical")
    spec["cam"]["speed_rpm"] = 60.0
    write_machine(tmp_path, machine_dict(("barrel", 0.0, spec), rpm=60.0))
    res = cli("machine", str(tmp_path / "m.toml"), "-o", str(tmp_path / "out"))
    assert res.returncode == 0, res.stderr
    report = json.loads((tmp_path / "out" / "machine.json").read_text(encoding="utf-8"))
    assert report["animation"]["file"] is None and report["animation"]["left_out"] == ["barrel"]
    assert "no cam is a plane cam" in report["animation"]["note"]
    before = snapshot(tmp_path)
    res = cli("machine", str(tmp_path / "m.toml"), "-o", str(tmp_path / "out2"), "--animation", "gif")
    assert res.returncode == 2 and "--animation: gif cannot be drawn" in res.stderr, res.stderr
    assert_unchanged(tmp_path, before)

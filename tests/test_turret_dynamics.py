"""An indexer's output train at speed (issue 23; generators/dynamics/turret.py, docs/indexing.md
"Dynamics"): the output's inertia J on the turret shaft's torsional stiffness k_t, driven by the
cam through stiff rollers along the turret angle ψ(θ), which advances 360°/N per turn.

Checked against what is written here, not against the code's own formulas:

* an independent integration of J φ̈ = k_t(ψ − φ) + c(ψ̇ − φ̇) in the error e = φ − ψ (scipy's
  solve_ivp, DOP853 at rtol 1e-12, piecewise over the dwell / rise / dwell so no step straddles a
  jerk jump), its periodic steady state found as the fixed point of the one-turn map — the error
  and the shaft torque at the solver's samples agree to 1e-6 of their peaks;
* the undamped train's closed form: after a cycloidal rise of h over t_i from rest the free
  vibration's amplitude is A₀ = (2πh/t_i²)·a·2|sin(ω_n t_i/2)| / (ω_n |a² − ω_n²|), a = 2π/t_i, and
  the periodic steady state (one rise per period P) carries A₀ / |2 sin(ω_n P/2)| through the dwell;
* k_t → ∞ leaves no error (the shaft torque the rigid J ψ̈);
* the residual vibration falls as f_n·t_i grows;
* the CLI and the API: report.json's ``dynamics.turret`` holds the numbers the command prints; bad
  fields exit 2 naming the field and write nothing.
"""
from __future__ import annotations

import copy
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from cam_workbench.generators.dynamics import analyse_dynamics
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.spec.examples import example_dict

from .conftest import ROOT

CLI = [sys.executable, "-m", "cam_workbench.cli"]

#: the parallel example's turret: 8 stations (h = 45°), index 120°–240° at 100 rpm (t_i = 0.2 s, P = 0.6 s),
#: J = 150000 kg·mm²
J_SPEC = 150000.0
RPM = 100.0
H = math.pi / 4
T_I = 0.2
PERIOD = 0.6
T0 = 0.2                     # the rise starts at 120° (after the first dwell)


def _spec(fn_ti: float, zeta: float, law: str = "cycloidal", **extra) -> CamSpec:
    """The parallel example with ``law`` over its index, the shaft stiff enough for f_n·t_i = ``fn_ti``."""
    d = copy.deepcopy(example_dict("parallel_indexer"))
    d["motion"][1]["law"] = law
    omega_n = 2 * math.pi * fn_ti / T_I
    d["dynamics"] = {"torsional_stiffness": J_SPEC * 1e-3 * omega_n**2, "damping_ratio": zeta, "sweep_points": 0,
                     **extra}
    return CamSpec.from_dict(d)


def _psi_dd(t: float) -> float:
    """ψ̈ [rad/s²] of the cycloidal index (written here: ψ = h(τ − sin 2πτ / 2π), τ = (t − t0)/t_i)."""
    tau = (t - T0) / T_I
    return (2 * math.pi * H / T_I**2) * math.sin(2 * math.pi * tau) if 0.0 <= tau <= 1.0 else 0.0


def _periodic_error(omega_n: float, zeta: float, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(e, ė) [rad, rad/s] of ë + 2ζω_n ė + ω_n² e = −ψ̈ in its periodic steady state, at ``times``
    within one period — solve_ivp piecewise, the fixed point of the one-turn affine map."""
    from scipy.integrate import solve_ivp

    def rhs(t, x):
        return [x[1], -2 * zeta * omega_n * x[1] - omega_n**2 * x[0] - _psi_dd(t)]

    pieces = [(0.0, T0), (T0, T0 + T_I), (T0 + T_I, PERIOD)]

    def run(x0, t_eval=np.empty(0)):
        """The state at the period's end, and at ``t_eval`` (each piece also evaluated at its end)."""
        x = np.asarray(x0, float)
        out = []
        for a, b in pieces:
            te = t_eval[(t_eval >= a) & (t_eval < b)]
            sol = solve_ivp(rhs, (a, b), x, method="DOP853", rtol=1e-12, atol=1e-15, t_eval=np.r_[te, b])
            assert sol.success, sol.message
            out.append(sol.y[:, :-1])
            x = sol.y[:, -1]
        return x, np.concatenate(out, axis=1)

    b0 = run([0.0, 0.0])[0]
    m = np.column_stack([run([1.0, 0.0])[0] - b0, run([0.0, 1.0])[0] - b0])
    x0 = np.linalg.solve(np.eye(2) - m, b0)
    return run(x0, times)[1]


def _omega_n(spec: CamSpec) -> float:
    return math.sqrt(spec.dynamics.torsional_stiffness / (J_SPEC * 1e-3))


@pytest.mark.parametrize("fn_ti, zeta", [(5.5, 0.05), (3.3, 0.1), (9.7, 0.02)])
def test_matches_an_independent_integration(fn_ti, zeta):
    """The periodic solve's error φ − ψ and shaft torque at its samples = solve_ivp's steady state."""
    spec = _spec(fn_ti, zeta)
    r = analyse_dynamics(spec)
    omega = RPM * 2 * math.pi / 60
    times = r.theta / omega
    e, de = _periodic_error(_omega_n(spec), zeta, times)
    err = np.deg2rad(r.error)
    assert np.max(np.abs(err - e)) <= 1e-6 * np.max(np.abs(e)), np.max(np.abs(err - e)) / np.max(np.abs(e))
    # the shaft torque k_t(ψ − φ) + c(ψ̇ − φ̇) [N·mm], c = 2ζ√(J k_t) with J in N·mm·s²
    k = spec.dynamics.torsional_stiffness
    c = 2 * zeta * math.sqrt(J_SPEC * 1e-3 * k)
    torque = -(k * e + c * de)
    assert np.max(np.abs(r.force - torque)) <= 1e-6 * np.max(np.abs(torque))
    # the turret advances 45° per turn: the output's angle is the turret's plus the (periodic) error
    assert r.lift[0] == 0.0 and r.lift[-1] == pytest.approx(45.0, abs=1e-9)
    assert np.allclose(r.position - r.lift, r.error, rtol=0, atol=1e-12)
    t = r.summary()["turret"]
    assert t["fn_ti"] == pytest.approx(fn_ti, rel=1e-12)
    assert t["index_time_s"] == pytest.approx(T_I, rel=1e-12)
    # the peaks: the largest sample refined by a parabola (≥ the sampled peak, within a sample's change)
    e_peak, t_peak = np.rad2deg(np.max(np.abs(e))), np.max(np.abs(torque))
    assert e_peak * (1 - 1e-6) <= t["angle_error"]["max"] <= e_peak * (1 + 1e-4)
    assert t_peak * (1 - 1e-6) <= t["shaft_torque"]["max"] <= t_peak * (1 + 1e-4)


def _undamped_residual(fn_ti: float) -> float:
    """The closed form [deg]: the undamped periodic steady state's free-vibration amplitude in the dwell."""
    omega_n = 2 * math.pi * fn_ti / T_I
    a = 2 * math.pi / T_I
    from_rest = (2 * math.pi * H / T_I**2) * a * 2 * abs(math.sin(omega_n * T_I / 2)) / (omega_n * abs(a**2 - omega_n**2))
    return math.degrees(from_rest / abs(2 * math.sin(omega_n * PERIOD / 2)))


@pytest.mark.parametrize("fn_ti", [5.5, 7.25, 12.4])
def test_undamped_residual_vibration_closed_form(fn_ti):
    rv = analyse_dynamics(_spec(fn_ti, 0.0)).summary()["turret"]["residual_vibration"]
    want = _undamped_residual(fn_ti)
    [dwell] = rv["dwells"]                    # 240° → 120°: one dwell across the turn's end
    assert dwell["from_deg"] == pytest.approx(240.0, abs=0.1) and dwell["to_deg"] == pytest.approx(120.0, abs=0.1)
    assert rv["amplitude"] == dwell["amplitude_at_start"]
    assert dwell["amplitude_at_start"] == pytest.approx(want, rel=1e-6)
    assert dwell["amplitude_at_end"] == pytest.approx(want, rel=1e-6)          # undamped: no decay
    assert dwell["max_error"] == pytest.approx(want, rel=1e-3)                 # the sampled peak
    assert rv["amplitude_arcmin"] == pytest.approx(60 * want, rel=1e-6)


def test_damped_dwell_decays_as_the_closed_form():
    """With damping the amplitude at the dwell's end is its start's times e^{−ζω_n t_dwell}."""
    spec = _spec(5.5, 0.02)
    [dwell] = analyse_dynamics(spec).summary()["turret"]["residual_vibration"]["dwells"]
    decay = math.exp(-0.02 * _omega_n(spec) * (dwell["to_deg"] + 360 - dwell["from_deg"]) / (6 * RPM))
    assert dwell["amplitude_at_end"] == pytest.approx(dwell["amplitude_at_start"] * decay, rel=1e-6)


def test_a_stiffer_shaft_leaves_less_error():
    """k_t → ∞: the error falls as 1/k_t (the quasi-static twist J ψ̈/k_t), the residual vibration
    faster still, and the shaft torque becomes the rigid J ψ̈ — of the modified sine, C_a = 4π²/(4 + π)
    = 5.5279 h/t_i² (J in N·mm·s²)."""
    rigid = J_SPEC * 1e-3 * 4 * math.pi**2 / (4 + math.pi) * H / T_I**2
    prev = None
    for fn_ti in (200.0, 2000.0):
        r = analyse_dynamics(_spec(fn_ti, 0.05, law="modified_sine"))
        d = r.summary()["turret"]
        k = r.model.stiffness
        assert d["deflection"]["max"] == pytest.approx(math.degrees(rigid / k), rel=2e-3 if fn_ti < 1000 else 2e-4)
        assert d["shaft_torque"]["max"] == pytest.approx(rigid, rel=5e-3 if fn_ti < 1000 else 5e-4)
        assert d["shaft_torque"]["rigid_max"] == pytest.approx(rigid, rel=2e-5)     # a parabola's refined peak
        if prev is not None:
            assert d["deflection"]["max"] == pytest.approx(prev["deflection"]["max"] / 100, rel=3e-3)
            assert d["residual_vibration"]["amplitude"] < 1e-3 * prev["residual_vibration"]["amplitude"]
        prev = d
    assert np.max(np.abs(r.error)) < 1e-5                      # degrees, at f_n·t_i = 2000


def test_residual_falls_as_fn_ti_grows():
    """f_n·t_i at the cycloid's worst (half-integer) ratios: the residual vibration at the station falls
    (as (f_n·t_i)⁻³, the cycloid's spectrum)."""
    ratios = [2.5, 4.5, 8.5, 16.5, 32.5]
    res = [analyse_dynamics(_spec(x, 0.02)).summary()["turret"]["residual_vibration"]["amplitude"] for x in ratios]
    assert all(a > b for a, b in zip(res, res[1:])), res
    assert res[0] / res[-1] > (ratios[-1] / ratios[0]) ** 2.5, res


def test_the_advance_does_not_leak_into_the_error():
    """The turret advances 45° per turn, yet the error φ − ψ is periodic and continuous across the turn's
    end (the mean advance is taken out of the spectrum, not left as a jump)."""
    r = analyse_dynamics(_spec(5.5, 0.05))
    assert abs(r.error[0] - r.error[-1]) < 1e-3 * np.max(np.abs(r.error))


@pytest.mark.parametrize("body", ["parallel_indexer", "barrel_indexer", "globoidal_indexer"])
def test_api_and_spec(body):
    from cam_workbench import Cam

    spec = CamSpec.from_dict({**example_dict(body), "dynamics": {"torsional_stiffness": 1e8, "enabled": True}})
    cam = Cam(spec)
    d = cam.dynamics(sweep=False).summary()
    t = d["turret"]
    assert d["contact"]["closure"] == "form" and d["contact"]["unit"] == "N·mm"
    assert d["model"]["coordinate"] == "turret angle" and d["model"]["mass"] == spec.indexer.output_inertia
    assert t["natural_frequency_hz"] == pytest.approx(math.sqrt(1e8 / (spec.indexer.output_inertia * 1e-3)) / (2 * math.pi))
    assert t["fn_ti"] == pytest.approx(t["natural_frequency_hz"] * t["index_time_s"])
    assert t["index_time_s"] == pytest.approx(math.radians(t["index_angle_deg"]) / (spec.cam.speed_rpm * math.pi / 30))
    assert "jump_speed" not in d                 # form closure: no jump
    assert d == cam.dynamics(sweep=False).summary()


@pytest.mark.parametrize("change, field", [
    ({"dynamics.enabled": True}, "dynamics.torsional_stiffness"),
    ({"dynamics.stiffness": 1000.0}, "dynamics.stiffness"),
    ({"dynamics.mass": 1.0}, "dynamics.mass"),
    ({"dynamics.arm_inertia": 10.0}, "dynamics.arm_inertia"),
    ({"dynamics.enabled": True, "dynamics.torsional_stiffness": 1e8, "indexer.output_inertia": 0.0},
     "indexer.output_inertia"),
])
def test_spec_rules(change, field):
    with pytest.raises(SpecError) as exc:
        CamSpec.from_dict(example_dict("parallel_indexer")).replace(**change)
    assert exc.value.field == field, str(exc.value)


# ---- the command line --------------------------------------------------------------------------------
def run(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT), COLUMNS="250")
    return subprocess.run([*CLI, *args], capture_output=True, text=True, env=env)


@pytest.mark.parametrize("example", ["parallel_indexer", "barrel_indexer", "globoidal_indexer"])
def test_cli_writes_the_turret_numbers(example, tmp_path):
    out = tmp_path / "out"
    res = run("dynamics", "--example", example, "--set", "dynamics.torsional_stiffness=1e8", "-o", str(out))
    assert res.returncode == 0, res.stdout + res.stderr
    d = json.loads((out / "report.json").read_text(encoding="utf-8"))["dynamics"]
    t = d["turret"]
    for key in ("natural_frequency_hz", "index_time_s", "fn_ti"):
        assert t[key] > 0
    assert t["deflection"]["max"] > 0 and t["shaft_torque"]["max"] > 0
    assert t["residual_vibration"]["dwells"] and t["residual_vibration"]["amplitude"] > 0
    # the same numbers as the API
    spec = CamSpec.from_dict({**example_dict(example), "dynamics": {"torsional_stiffness": 1e8}})
    api = analyse_dynamics(spec).summary()["turret"]
    assert api["fn_ti"] == pytest.approx(t["fn_ti"], rel=1e-12)
    assert api["shaft_torque"]["max"] == pytest.approx(t["shaft_torque"]["max"], rel=1e-12)
    # the printed table holds report.json's numbers (6 significant digits)
    lines = res.stdout.splitlines()
    row = next(line for line in lines if "f_n·t_i" in line)
    assert float(row.split("│")[2]) == pytest.approx(t["fn_ti"], rel=1e-5)
    row = next(line for line in lines if "peak shaft torque (dynamic)" in line)
    assert float(row.split("│")[2]) == pytest.approx(t["shaft_torque"]["max"], rel=1e-5)
    assert "the rollers hold the turret both ways" in res.stdout
    assert {p.name for p in out.iterdir()} >= {"report.json", "dynamics.csv", "plot_dynamics.png"}


@pytest.mark.parametrize("args, field", [
    ([], "dynamics.torsional_stiffness"),
    (["--set", "dynamics.torsional_stiffness=1e8", "--set", "dynamics.stiffness=2000"], "dynamics.stiffness"),
    (["--set", "dynamics.torsional_stiffness=-5"], "dynamics.torsional_stiffness"),
    (["--set", "dynamics.torsional_stiffness=1e8", "--set", "indexer.output_inertia=0"], "indexer.output_inertia"),
    (["--set", "dynamics.torsional_stiffness=1e8", "--set", "dynamics.damping_ratio=1.5"], "dynamics.damping_ratio"),
])
def test_cli_bad_fields_exit_2(tmp_path, args, field):
    out = tmp_path / "out"
    res = run("dynamics", "--example", "parallel_indexer", *args, "-o", str(out))
    assert res.returncode == 2, res.stdout + res.stderr
    assert res.stderr.startswith(f"error: {field}:") and res.stderr.count("\n") == 1, res.stderr
    assert not out.exists()


def test_the_docs_table_is_the_examples():
    """docs/indexing.md's "Dynamics" table quotes these numbers (k_t = 1e8 N·mm/rad, ζ = 0.05)."""
    text = (ROOT / "docs" / "indexing.md").read_text(encoding="utf-8").split("## Dynamics", 1)[1]
    for body in ("parallel_indexer", "barrel_indexer", "globoidal_indexer"):
        line = next(ln for ln in text.splitlines() if ln.startswith(f"| {body} |"))
        cells = [c.strip() for c in line.strip("|").split("|")[1:]]
        t = analyse_dynamics(CamSpec.from_dict({**example_dict(body),
                                                "dynamics": {"torsional_stiffness": 1e8}})).summary()["turret"]
        torque, rigid = cells[4].replace(")", "").split(" (")
        want = [t["natural_frequency_hz"], t["index_time_s"], t["fn_ti"], t["deflection"]["max_arcmin"],
                t["shaft_torque"]["max"], t["shaft_torque"]["rigid_max"], t["residual_vibration"]["amplitude_arcmin"]]
        for quoted, value in zip([*cells[:4], torque, rigid, cells[5]], want):
            assert float(quoted) == pytest.approx(value, rel=6e-3), (body, quoted, value)


def test_report_html_shows_report_json():
    """With dynamics.enabled the indexer's report.json holds dynamics.turret and report.html shows it."""
    import re

    from cam_workbench.exporters.report_json import report_json_text
    from cam_workbench.pipeline import _page, run_pipeline

    spec = CamSpec.from_dict({**example_dict("parallel_indexer"),
                              "dynamics": {"enabled": True, "torsional_stiffness": 1e8}})
    out = run_pipeline(spec, solid=False, machining=False, drawing=False)
    report = json.loads(report_json_text(out.summary))
    page, _ = _page(out).render(report, None)
    cells = dict(re.findall(r'data-key="(dynamics\.turret\.[\w.]+)" data-value="([^"]*)"', page))
    for key in ("fn_ti", "natural_frequency_hz", "shaft_torque.max", "residual_vibration.amplitude_arcmin",
                "deflection.max_arcmin"):
        node = report["dynamics"]["turret"]
        for part in key.split("."):
            node = node[part]
        assert float(cells[f"dynamics.turret.{key}"]) == pytest.approx(node, rel=1e-12), key

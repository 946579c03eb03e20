"""Issue 25 part 3: profile tolerances against the follower's acceleration.

Checked against closed forms written here (a translating flat face, whose gain is 1 everywhere,
and a radial roller on its dwells: δs = e, δa = −A(nω)²cos(nθ), t(n) = 2·X·a_peak/(nω)²; the
radial roller's gain 1/cos φ and its derivatives from the motion's exact s, s′, s″, s‴), against
the exact perturbed contact solve (the wavy profile's exact offset, a PH spline through it and the
design's own contact solve), and the command line against its own tolerance.json.
"""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from cam_workbench.exporters.report_cells import format_number as fmt
from cam_workbench.generators.cam_design import design_cam
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.generators.tolerance.sensitivity import perturbed_lift, sensitivity
from cam_workbench.generators.tolerance.study import measured_error, tolerance_chart
from cam_workbench.tolerance import tolerance_study

from .conftest import ROOT

TWO_PI = 2 * np.pi
CLI = [sys.executable, "-m", "cam_workbench.cli"]


@pytest.fixture(scope="module")
def designs():
    return {name: design_cam(example_spec(name)) for name in ("default", "oscillating", "flat")}


def dwell_mask(design, theta, margin=0.01):
    """Samples inside the dwells, ``margin`` rad away from their ends."""
    prog = design.program
    inside = np.zeros(theta.shape, bool)
    for a, w, law in zip(prog.starts, prog.spans, prog.laws):
        if law is None:
            inside |= (np.mod(theta - a, TWO_PI) > margin) & (np.mod(theta - a, TWO_PI) < w - margin)
    return inside


# ---- closed forms ------------------------------------------------------------------------------------
def test_radial_roller_on_its_dwells_sees_the_wave_as_it_is(designs):
    """Radial translating roller, base-circle dwell (pressure angle 0): δs = A·cos nθ and
    δa = −A(nω)²cos nθ."""
    d = designs["default"]
    s = sensitivity(d, 60.0)
    on = dwell_mask(d, s.theta)
    assert on.sum() > 1000
    for n, a in ((1, 0.01), (7, 1e-3), (150, 2e-6)):
        ds, da = s.wave_error(a, n)
        w = s.omega
        np.testing.assert_allclose(ds[on], a * np.cos(n * s.theta[on]), rtol=0, atol=1e-12 * a)
        np.testing.assert_allclose(da[on], -a * (n * w) ** 2 * np.cos(n * s.theta[on]), rtol=0,
                                   atol=1e-9 * a * (n * w) ** 2)


def roller_gain(design, theta):
    """g = 1/cos φ of a radial translating roller and its θ-derivatives, from tan φ = s′/(s₀ + s)
    and the motion's exact s, s′, s″, s‴ (written here, independent of the follower classes)."""
    k = design.program.evaluate(theta)
    y = design.follower.s0 + k.s
    u = k.ds / y
    u1 = k.d2s / y - k.ds**2 / y**2
    u2 = k.d3s / y - 3 * k.ds * k.d2s / y**2 + 2 * k.ds**3 / y**3
    g = np.sqrt(1 + u * u)
    g1 = u * u1 / g
    g2 = (u1 * u1 + u * u2) / g - (u * u1) ** 2 / g**3
    return g, g1, g2


def test_radial_roller_chart_against_the_closed_form_gain(designs):
    d = designs["default"]
    s = sensitivity(d, 60.0)
    g, g1, g2 = roller_gain(d, s.theta)
    away = np.min(np.abs((s.theta[:, None] - np.asarray(d.program.starts)[None] + np.pi) % TWO_PI - np.pi), axis=1) > 0.003
    np.testing.assert_allclose(s.gain, g, rtol=1e-13)
    np.testing.assert_allclose(s.gain_d1[away], g1[away], rtol=0, atol=1e-9)
    np.testing.assert_allclose(s.gain_d2[away], g2[away], rtol=0, atol=1e-6)
    x = 0.05
    chart = tolerance_chart(s, x, 200)
    n = np.arange(1, 201)[:, None]
    z = np.sqrt((g2 - n * n * g) ** 2 + (2 * n * g1) ** 2).max(axis=1)
    expect = 2 * x * s.peak_acceleration / (s.omega**2 * z)
    np.testing.assert_allclose(chart.acceleration_tolerance, expect, rtol=2e-5)
    # on the dwells alone |Z_n| = n², so the cycle's tolerance is no larger than 2·X·a/(nω)², and tends to it
    # divided by the largest gain 1/cos φ_max for many waves
    bound = 2 * x * s.peak_acceleration / (n[:, 0] * s.omega) ** 2
    assert np.all(chart.acceleration_tolerance <= bound * (1 + 1e-12))
    np.testing.assert_allclose(chart.acceleration_tolerance[-1], bound[-1] / g.max(), rtol=1e-4)


@settings(max_examples=30, deadline=None)
@given(n=st.integers(1, 400), rpm=st.floats(1.0, 3000.0), pct=st.floats(0.01, 100.0))
def test_flat_face_tolerance_is_the_closed_form(n, rpm, pct):
    """A translating flat face moves by e wherever it touches (gain 1): t(n) = 2·X·a_peak/(nω)²
    over the whole cycle, for any speed and limit."""
    study = tolerance_study(example_spec("flat"), acceleration_limit=pct / 100, max_waves=n, speed_rpm=rpm,
                            design=FLAT)
    w = rpm * TWO_PI / 60
    a_peak = float(np.max(np.abs(FLAT.program.evaluate(np.linspace(0, TWO_PI, 200001)).d2s))) * w * w
    c = study.summary()["chart"]
    assert study.sensitivity.peak_acceleration == pytest.approx(a_peak, rel=1e-6)
    t = 2 * (pct / 100) * study.sensitivity.peak_acceleration / (np.arange(1, n + 1) * w) ** 2
    np.testing.assert_allclose(c["acceleration_tolerance"], t, rtol=1e-12)


FLAT = design_cam(example_spec("flat"))


@settings(max_examples=20, deadline=None)
@given(n=st.integers(1, 300), amp=st.floats(1e-6, 1e-1), rpm=st.floats(1.0, 3000.0), phase=st.floats(0, 6.28))
def test_radial_roller_dwell_acceleration_any_wave(n, amp, rpm, phase):
    s = sensitivity(DEFAULT, rpm, samples=2048)
    on = dwell_mask(DEFAULT, s.theta)
    _, da = s.wave_error(amp, n, phase)
    w = rpm * TWO_PI / 60
    np.testing.assert_allclose(da[on], -amp * (n * w) ** 2 * np.cos(n * s.theta[on] + phase), rtol=0,
                               atol=1e-9 * amp * (n * w) ** 2)


DEFAULT = design_cam(example_spec("default"))


# ---- first order against the exact perturbed contact solve ----------------------------------------------
#: (example, waves) → the largest relative difference of δs and of δa (away from the motion's segment
#: boundaries, where δa jumps) between the first-order model and the exact solve, measured at A = 1 µm
#: (the difference is second order: it halves with A)
EXACT = {("default", 5): (1e-4, 5e-4), ("default", 20): (1.5e-3, 4e-3),
         ("oscillating", 5): (1e-4, 5e-4), ("oscillating", 20): (1.5e-3, 4e-3),
         ("flat", 5): (5e-4, 2e-3), ("flat", 20): (8e-3, 2e-2)}


def exact_vs_first_order(design, n, a, samples=4096, segments=5120):
    s = sensitivity(design, 60.0, samples=samples)
    s0, s1 = perturbed_lift(design, lambda t: (a * np.cos(n * t), -a * n * np.sin(n * t)), s.theta, segments)
    ds_exact = s1 - s0
    h = TWO_PI / samples
    da_exact = s.omega**2 * (np.roll(ds_exact, -1) - 2 * ds_exact + np.roll(ds_exact, 1)) / h**2
    ds, da = s.wave_error(a, n)
    b = np.asarray(design.program.starts)
    away = np.min(np.abs((s.theta[:, None] - b[None] + np.pi) % TWO_PI - np.pi), axis=1) > np.deg2rad(0.5)
    return (np.max(np.abs(ds_exact - ds)) / np.max(np.abs(ds)),
            np.max(np.abs(da_exact - da)[away]) / np.max(np.abs(da)))


@pytest.mark.parametrize("name,n", sorted(EXACT))
def test_first_order_model_against_the_exact_contact_solve(designs, name, n):
    ds_rel, da_rel = exact_vs_first_order(designs[name], n, 1e-3)
    assert ds_rel < EXACT[name, n][0] and da_rel < EXACT[name, n][1], (ds_rel, da_rel)


def test_the_difference_from_the_exact_solve_is_second_order(designs):
    big, _ = exact_vs_first_order(designs["default"], 20, 2e-3)
    small, _ = exact_vs_first_order(designs["default"], 20, 1e-3)
    assert big / small == pytest.approx(2.0, rel=0.05)


def test_contact_loss_amplitude_of_short_waves(designs):
    """For many waves A_max → min (λ/2π)²·(κ + 1/r), λ = 2π·σ_θ/n: the roller's curvature plus the
    profile's, over the wave's (written here from the design's own base circle on the dwells)."""
    d = designs["default"]
    s = sensitivity(d, 60.0)
    r = d.spec.roller_radius
    on = dwell_mask(d, s.theta)
    # on a dwell the profile is a circle of radius ρ = s₀ + s − r: σ_θ = ρ, κ = 1/ρ, |W_n| = (n² − 1)/ρ² exactly
    rho = d.follower.s0 + d.program.s(s.theta[on]) - r
    np.testing.assert_allclose(s.arc_rate[on], rho, rtol=1e-9)
    np.testing.assert_allclose(s.curvature[on], 1 / rho, rtol=1e-9)
    for n in (2, 30, 1000):
        dwell = np.min((1 / rho + 1 / r) * rho**2 / (n * n - 1))
        assert s.contact_loss_amplitude(np.array([n]))[0] <= dwell * (1 + 1e-9)
    knife = sensitivity(design_cam(example_spec("default").replace(**{"follower.kind": "knife"})), 60.0)
    assert np.isinf(knife.contact_loss_amplitude(np.array([1, 50, 500]))).all()


# ---- the reverse: a measured deviation ---------------------------------------------------------------------
WAVES = ((0, 3e-3, 0.0), (3, 2e-3, 0.4), (17, 5e-4, -1.0), (40, 1e-4, 2.0))


def synthetic(theta_deg):
    t = np.deg2rad(theta_deg)
    return sum(a * np.cos(n * t + p) for n, a, p in WAVES)


def test_measured_deviation_on_a_flat_face_gives_the_analytic_acceleration():
    s = sensitivity(FLAT, 120.0)
    rng = np.random.default_rng(3)
    th = np.arange(720) * 0.5
    order = rng.permutation(th.size)                     # any order: the angles are sorted
    m = measured_error(s, th[order], synthetic(th)[order])
    got = {h.waves: h for h in m.harmonics}
    for n, a, p in WAVES:
        assert got[n].amplitude == pytest.approx(a, rel=1e-12, abs=1e-15)
        assert np.deg2rad(got[n].phase_deg) == pytest.approx(p, abs=1e-9)
        assert got[n].peak_acceleration_error == pytest.approx(a * (n * s.omega) ** 2, rel=1e-6, abs=1e-12)
    others = [h.amplitude for h in m.harmonics if h.waves not in dict((w, 0) for w, _, _ in WAVES)]
    assert max(others) < 1e-15
    w = s.omega
    da = -w * w * sum(a * n * n * np.cos(n * s.theta + p) for n, a, p in WAVES)
    np.testing.assert_allclose(m.acceleration_error, da, rtol=0, atol=1e-9 * np.max(np.abs(da)))
    np.testing.assert_allclose(m.lift_error, synthetic(np.rad2deg(s.theta)), rtol=0, atol=1e-15)
    assert m.percent == pytest.approx(100 * np.max(np.abs(da)) / s.peak_acceleration, rel=1e-6)


def test_measured_deviation_on_the_roller_dwells(designs):
    d = designs["default"]
    s = sensitivity(d, 60.0)
    th = np.arange(1000) * 0.36
    m = measured_error(s, th, synthetic(th))
    on = dwell_mask(d, s.theta)
    da = -s.omega**2 * sum(a * n * n * np.cos(n * s.theta + p) for n, a, p in WAVES)
    np.testing.assert_allclose(m.acceleration_error[on], da[on], rtol=0, atol=1e-9 * np.max(np.abs(da)))


@pytest.mark.parametrize("theta,dev,rule", [
    ([0, 90, 180], [0, 0, 0], "at least 4 distinct cam angles"),
    ([0, 90, 180, 270], [0, 0, 0], "one deviation per cam angle"),
    ([0, 90, 180, np.nan], [0, 0, 0, 0], "finite"),
])
def test_bad_measured_deviation_names_the_field(theta, dev, rule):
    with pytest.raises(SpecError) as exc:
        measured_error(sensitivity(FLAT, 60.0, samples=512), theta, dev)
    assert exc.value.field == "deviation" and rule in exc.value.rule


# ---- API ---------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs,field", [({"acceleration_limit": 0.0}, "acceleration_limit"),
                                          ({"acceleration_limit": 1.5}, "acceleration_limit"),
                                          ({"max_waves": 0}, "max_waves"), ({"max_waves": 2.5}, "max_waves"),
                                          ({"speed_rpm": -1.0}, "speed_rpm")])
def test_api_bad_input_names_the_argument(kwargs, field):
    with pytest.raises(SpecError) as exc:
        tolerance_study(example_spec("default"), **kwargs)
    assert exc.value.field == field


def test_a_body_without_a_plane_profile_is_refused():
    with pytest.raises(SpecError) as exc:
        tolerance_study(example_spec("cylindrical"))
    assert exc.value.field == "cam.body"


def test_summary_agrees_with_the_chart_and_the_svg():
    study = tolerance_study(example_spec("default"), max_waves=60)
    d = study.summary()
    c = d["chart"]
    assert c["waves"] == list(range(1, 61))
    assert c["tolerance"] == list(np.minimum(c["acceleration_tolerance"], c["contact_tolerance"]))
    assert d["tightest"]["tolerance"] == min(c["tolerance"])
    for row in d["table"]:
        i = row["waves"] - 1
        assert row["tolerance"] == c["tolerance"][i] and row["governed_by"] == c["governed_by"][i]
    assert d["allowed_acceleration_error"] == pytest.approx(0.05 * d["designed_peak_acceleration"], rel=1e-15)
    assert d["designed_peak_acceleration"] == design_cam(example_spec("default")).summary()["motion"]["max_acceleration"]
    assert study.svg().startswith("<svg")


# ---- the command line --------------------------------------------------------------------------------------
def run(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT), COLUMNS="250")
    return subprocess.run([*CLI, *args], capture_output=True, text=True, env=env)


def test_cli_printout_is_tolerance_json(tmp_path):
    out = tmp_path / "tol"
    r = run("tolerance", "--example", "oscillating", "--acceleration-limit", "2", "--max-waves", "120",
            "--speed", "300", "-o", str(out))
    assert r.returncode == 0, r.stderr
    d = json.loads((out / "tolerance.json").read_text())
    assert (out / "tolerance.svg").read_text().startswith("<svg")
    assert d["acceleration_limit"] == 0.02 and d["speed_rpm"] == 300.0 and len(d["chart"]["waves"]) == 120
    rows = [re.split(r"\s*│\s*", ln.strip("│ ")) for ln in r.stdout.splitlines() if re.match(r"^│\s+\d", ln)]
    assert [int(x[0]) for x in rows] == [e["waves"] for e in d["table"]]
    for cells, e in zip(rows, d["table"]):
        assert cells[1:] == [fmt(e["tolerance"]), fmt(e["acceleration_tolerance"]), fmt(e["contact_tolerance"]),
                             e["governed_by"]]
    t = d["tightest"]
    assert f"tightest: t = {fmt(t['tolerance'])} {d['units']} at {t['waves']} waves per turn" in r.stdout
    assert f"{fmt(d['designed_peak_acceleration'])} deg/s²" in r.stdout
    # the API gives the same numbers
    api = tolerance_study(example_spec("oscillating"), 0.02, 120, 300.0).summary()
    assert api["chart"]["tolerance"] == d["chart"]["tolerance"]


@pytest.mark.parametrize("args,option", [(["--acceleration-limit", "0"], "--acceleration-limit"),
                                         (["--acceleration-limit", "101"], "--acceleration-limit"),
                                         (["--acceleration-limit", "nan"], "--acceleration-limit"),
                                         (["--max-waves", "0"], "--max-waves"),
                                         (["--speed", "-5"], "--speed"),
                                         (["--example", "cylindrical"], "cam.body")])
def test_cli_bad_input_exit_2_names_the_option_writes_nothing(tmp_path, args, option):
    out = tmp_path / "never"
    r = run("tolerance", *args, "-o", str(out))
    assert r.returncode == 2, r.stdout + r.stderr
    assert option in r.stderr and "Traceback" not in r.stderr
    assert not out.exists()


def test_docs_cli_md_names_every_option_of_tolerance():
    from cam_workbench.commands import parsers

    sub = next(a for a in parsers.parser()._actions if a.dest == "command").choices["tolerance"]
    text = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    entry = text[text.index("- `tolerance` "):]
    entry = entry[:entry.index("\n- ")]
    for action in sub._actions:
        for opt in action.option_strings:
            if opt.startswith("--") and opt not in ("--help", "--example", "--set", "--replace", "--output", "--source"):
                assert f"`{opt}" in entry, opt

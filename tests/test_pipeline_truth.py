"""One pipeline, one truth: both pitch representations through every stage, the numbers of
build / report / check / PlateCam equal, undercut refusals quoting the checks, the default
cam passing and the paper's cam one option away.  Independent computations are written here."""
from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from cam_workbench.generators.errors import GeometryError
from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.generators.spec import CamSpec, default_spec

from .conftest import ROOT, requires_ocp

CLI = [sys.executable, "-m", "cam_workbench.cli"]


def cli(*args: str, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run([*CLI, *args], capture_output=True, text=True, cwd=cwd or ROOT,
                          stdin=subprocess.DEVNULL)


def _true_pitch(spec: CamSpec, theta: np.ndarray) -> np.ndarray:
    """P(θ) = Rot(∓θ)·(e, s₀ + s(θ)) from docs/conventions.md, written out here (s from the program)."""
    from cam_workbench.generators.motion import MotionProgram

    s = MotionProgram.from_spec(spec).s(theta)
    e = spec.follower.offset
    s0 = np.sqrt(spec.cam.base_radius**2 - e**2)
    sense = 1 if spec.cam.direction == "ccw" else -1
    return np.exp(-1j * sense * theta) * (e + 1j * (s0 + s))


def _nearest_distance(points: np.ndarray, curve: np.ndarray) -> np.ndarray:
    """Brute-force distance of each point to a densely sampled closed curve (polyline)."""
    a = curve
    b = np.roll(curve, -1)
    ab = b - a
    out = np.empty(points.shape[0])
    for lo in range(0, points.shape[0], 256):
        p = points[lo:lo + 256, None]
        t = np.clip(((p - a) * np.conj(ab)).real / np.abs(ab) ** 2, 0.0, 1.0)
        out[lo:lo + 256] = np.min(np.abs(a + t * ab - p), axis=1)
    return out


# ---- the B-spline pitch curve through the interpolator and tool paths ---------------------
@pytest.mark.parametrize("kind,direction", [("roller", "ccw"), ("knife", "cw")])
def test_bspline_interpolator_matches_independent_contact(kind, direction):
    """The interpolator's commands on a B-spline pitch curve give the displacement the curve
    itself gives (the class's own scalar Newton on C(u), a different solver), and stay within
    the pitch curve's max deviation of the motion."""
    from cam_workbench.generators.cam_design import design_cam
    from cam_workbench.generators.machining.interpolator import interpolate

    spec = default_spec().replace(**{"pitch.representation": "bspline", "follower.kind": kind,
                                     "cam.direction": direction})
    d = design_cam(spec)
    cmds = interpolate(d.pitch, 60.0, 0.001)
    ref = d.pitch.actual_displacement(cmds.theta)
    assert np.max(np.abs(cmds.s_actual - ref)) < 1e-9
    assert np.max(np.abs(cmds.s_actual - cmds.s_desired)) <= d.max_deviation[0] * 1.05 + 1e-9


@pytest.mark.parametrize("tool_radius", [3.0, 12.0])
def test_bspline_fitted_tool_centre_error_is_measured(tool_radius):
    """A B-spline pitch curve's tool-centre path is a fitted B-spline: its reported error equals
    the distance of its points from the exact offset, computed here by brute force on the
    true pitch curve's offset (within the fit error of the pitch curve itself)."""
    from cam_workbench.generators.cam_design import design_cam
    from cam_workbench.generators.machining import machining_plan
    from cam_workbench.generators.machining.toolpath import tool_centre_curve, tool_centre_fit_error

    spec = default_spec().replace(**{"pitch.representation": "bspline", "machining.tool_radius": tool_radius})
    d = design_cam(spec)
    plan = machining_plan(d)
    curve = tool_centre_curve(d, plan)
    err = tool_centre_fit_error(d, plan)
    assert 0 < err < 1e-3
    # independent: exact outward offset of the TRUE pitch curve by R_t − r
    th = np.linspace(0, 2 * np.pi, 200_000, endpoint=False)
    p = _true_pitch(spec, th)
    dp = np.gradient(p, th)
    n_out = 1j * dp / np.abs(dp)                       # ccw cam: the pitch curve runs clockwise
    true_centre = p + (tool_radius - 8.0) * n_out
    _, pts = curve.sample(16)
    dist = _nearest_distance(pts[:, 0] + 1j * pts[:, 1], true_centre)
    assert np.max(dist) <= err + d.max_deviation[0] * 3 + 1e-5


def test_seam_profile_error_without_dwell_at_zero():
    """e = 0, rise 180° / return 180° (no dwell at 0°): the profile error is measured at the seam
    too (it read as the whole lift when θ = −1e-17 wrapped to 2π)."""
    from cam_workbench.generators.cam_design import design_cam

    d = design_cam(CamSpec.from_dict({
        "cam": {"base_radius": 40.0, "thickness": 10.0}, "follower": {"kind": "roller", "roller_radius": 5.0},
        "motion": [{"kind": "rise", "angle": 180.0, "lift": 12.7, "law": "harmonic"},
                   {"kind": "return", "angle": 180.0, "lift": 12.7, "law": "harmonic"}]}))
    err = d.summary()["profile"]["max_error"]
    assert err < 1e-4
    # independent: sampled profile points against the true profile (pitch point − r·outward normal)
    th = np.linspace(0, 2 * np.pi, 400_000, endpoint=False)
    p = _true_pitch(d.spec, th)
    dp = np.gradient(p, th)
    true_profile = p - 5.0 * 1j * dp / np.abs(dp)
    _, pts = d.profile.sample(8)
    dist = _nearest_distance(pts[:, 0] + 1j * pts[:, 1], true_profile)
    assert np.max(dist) < 1e-4
    assert abs(np.max(dist) - err) < 2e-5


# ---- undercut: build refuses with the numbers check prints -----------------------------------
def test_undercut_refusal_quotes_the_check(tmp_path):
    over = ["--set", "follower.roller_radius=37", "--set", "cam.base_radius=40", "--set", "cam.bore_diameter=0",
            "--set", "motion[1].angle=100", "--set", "motion[2].angle=80"]
    b = cli("build", *over, "-o", str(tmp_path / "b"))
    assert b.returncode == 2 and not (tmp_path / "b").exists()
    c = cli("check", *over, "-o", str(tmp_path / "c"))
    assert c.returncode == 3
    r = json.loads((tmp_path / "c" / "report.json").read_text())
    u = r["checks"]["results"]["undercut"]
    assert u["status"] == "fail"
    rho = r["checks"]["results"]["curvature"]
    assert f"undercut at cam angle {rho['at_deg']:.3f}°" in b.stderr
    assert f"smallest convex pitch radius of curvature {rho['value']:.6g}" in b.stderr
    assert f"{u['value']:.6g}" in b.stderr
    assert r["buildable"]["ok"] is False


# ---- every command reports the same numbers ------------------------------------------------
@requires_ocp
@pytest.mark.parametrize("rep", ["ph", "bspline"])
def test_build_report_check_platecam_agree(tmp_path, rep):
    from cam_workbench import PlateCam

    over = ["--set", f"pitch.representation={rep}", "--set", "machining.program=xc"]
    assert cli("build", *over, "-o", str(tmp_path / "b")).returncode == 0
    assert cli("report", *over, "-o", str(tmp_path / "r")).returncode == 0
    assert cli("check", *over, "-o", str(tmp_path / "c")).returncode == 0
    b, r, c = (json.loads((tmp_path / k / "report.json").read_text()) for k in "brc")
    for key in b:
        if key != "files":
            assert r[key] == b[key], key
            if key in c:
                assert c[key] == b[key], key
    assert {"pitch", "pressure_angle", "curvature", "profile", "checks", "areas"} <= set(c)
    api = PlateCam(default_spec().replace(**{"pitch.representation": rep, "machining.program": "xc"})).report()
    api = json.loads(json.dumps(api))
    for key in ("pitch", "pressure_angle", "curvature", "profile", "checks", "interpolator", "machining"):
        assert api[key] == b[key], key
    # the G-code command writes build's cam.nc byte for byte
    g = cli("gcode", *over, "--mode", "xc")
    assert g.stdout == (tmp_path / "b" / "cam.nc").read_text()


# ---- the default cam passes; the paper's is one option away ---------------------------------
def test_default_cam_passes_and_paper_fails_pressure_angle():
    from cam_workbench.generators.checks.design import run_checks

    d = run_checks(default_spec())
    assert d.passed, d.failed
    assert {r.name for r in d.results if r.status == "pass"} >= {
        "pressure_angle", "separation", "oscillation", "contact_stress", "curvature", "undercut"}
    p = run_checks(example_spec("paper"))
    assert p.failed == ["pressure_angle"]
    assert p["pressure_angle"].value == pytest.approx(46.24, abs=0.01)


def test_example_option_and_spec_example(tmp_path):
    r = cli("spec", "--example", "paper")
    assert r.returncode == 0
    from cam_workbench.generators.spec import load_spec

    (tmp_path / "paper.toml").write_text(r.stdout)
    assert load_spec(tmp_path / "paper.toml") == example_spec("paper")
    c = cli("check", "--example", "paper", "-o", str(tmp_path / "c"))
    assert c.returncode == 3
    bad = cli("build", "--example", "nope", "-o", str(tmp_path / "x"))
    assert bad.returncode == 2 and "--example" in bad.stderr and not (tmp_path / "x").exists()


@requires_ocp
def test_optimise_writes_the_optimised_cams_own_files(tmp_path):
    """optimise's folder holds the optimised cam's set: its cam.step is optimised.toml's cam."""
    from cam_workbench.kernel.step import read_step
    from cam_workbench.kernel import solids as occ_build
    from cam_workbench.generators.cam_design import design_cam
    from cam_workbench.generators.spec import load_spec

    r = cli("optimise", "--example", "paper", "--max-evaluations", "10", "-o", str(tmp_path / "o"))
    assert r.returncode in (0, 3), r.stderr
    opt = load_spec(tmp_path / "o" / "optimised.toml")
    shape = read_step(tmp_path / "o" / "cam.step")
    vol = occ_build.kernel_volume(shape)
    assert vol == pytest.approx(design_cam(opt).volume, rel=1e-5)
    rep = json.loads((tmp_path / "o" / "report.json").read_text())
    assert rep["spec"] == opt.to_dict()

"""The cylindrical cam through `check`, `dxf`, `dynamics`, `ecam` and `sweep`, against computations
written here (the example's cycloidal lift in closed form: tests/test_cylindrical.py ``lift``):

* check: the pressure angle at R_p and R_b is atan(s′_max/ρ) with s′_max = 2h/β; the table prints
  report.json's numbers; a failed check exits 3, an undercut fails the ``undercut`` check (exit 3);
* dxf: ezdxf's audit is clean; points of the DXF's wall SPLINEs (evaluated by ezdxf) lie at w/2 from
  the developed centre line C_ρ(θ) = (ρ(π/2 − θ), z₀ + s(θ)) at ρ = R_o within the reported fit error
  (distance by dense sampling + scipy's bounded minimisation), on the right side; the pitch line
  on C_{R_p}; the reported number is the one printed and the one in the title block;
* dynamics: the torque is the virtual-work identity T = F·cos φ·s′, tan φ = s′/R_p; the rigid force
  of a massive follower changes sign where s″ does (θ = 90°, 270°); CLI and API give the same numbers;
* ecam: the CSV of the cylindrical example equals the plate cam's with the same motion;
* sweep: cam.cylinder_radius swept, each design's pressure angle atan(s′_max/R_p).
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
from scipy import optimize

from cam_workbench.generators.checks.design import format_value
from cam_workbench.generators.spec import CamSpec, dict_to_toml
from cam_workbench.generators.spec.examples import EXAMPLES

from .conftest import ROOT, SAFETY_S, requires_ocp
from .test_cylindrical import BORE, H, L, RB, RO, RP, W2, Z0, lift

CLI = [sys.executable, "-m", "cam_workbench.cli"]
BETA = 2 * math.pi / 3
DS_MAX = 2 * H / BETA                 # the cycloidal rise's largest s′ (mm/rad), at its middle


def run(*args, cwd=None):
    env = dict(os.environ, PYTHONPATH=str(ROOT), COLUMNS="250")
    return subprocess.run([*CLI, *args], capture_output=True, text=True, cwd=cwd or ROOT, env=env)


# ---- check ----------------------------------------------------------------------------------------
def test_check_cli_numbers_and_table(tmp_path):
    res = run("check", "--example", "cylindrical", "-o", str(tmp_path / "out"))
    assert res.returncode == 0, res.stderr
    rep = json.loads((tmp_path / "out" / "report.json").read_text())
    r = rep["checks"]["results"]
    assert r["pressure_angle"]["value"] == pytest.approx(math.degrees(math.atan(DS_MAX / RP)), abs=1e-9)
    assert r["pressure_angle_bottom"]["value"] == pytest.approx(math.degrees(math.atan(DS_MAX / RB)), abs=1e-9)
    assert r["pressure_angle"]["at_deg"] == pytest.approx(90.0, abs=1e-6)
    # the undercut check: min over θ and ρ ∈ [R_b, R_o] of (ρ² + s′²)^{3/2}/(ρ|s″|), here by dense sampling
    th = np.linspace(np.deg2rad(30), np.deg2rad(150), 20001)
    x = (th - np.deg2rad(30)) / BETA
    ds = H / BETA * (1 - np.cos(2 * np.pi * x))
    d2s = H / BETA ** 2 * 2 * np.pi * np.sin(2 * np.pi * x)
    rc = min(float(np.min(np.hypot(rho, ds) ** 3 / (rho * np.maximum(np.abs(d2s), 1e-300))))
             for rho in np.linspace(RB, RO, 5))
    assert r["undercut"]["value"] == pytest.approx(rc, rel=1e-5)
    assert rep["checks"]["passed"] and "Traceback" not in res.stderr
    for name, c in r.items():           # the table prints report.json's numbers
        assert format_value(c["value"], c["unit"]) in res.stdout, name
    assert "all checks pass" in res.stdout


def test_check_api_equals_cli(tmp_path):
    from cam_workbench import Cam

    res = run("check", "--example", "cylindrical", "-o", str(tmp_path / "out"))
    rep = json.loads((tmp_path / "out" / "report.json").read_text())
    api = json.loads(json.dumps(Cam.example("cylindrical").checks()))
    assert api["results"] == rep["checks"]["results"] and res.returncode == 0


def test_check_failure_exit_3(tmp_path):
    res = run("check", "--example", "cylindrical", "--set", "checks.max_pressure_angle=20", "-o", str(tmp_path / "o"))
    assert res.returncode == 3, res.stderr
    rep = json.loads((tmp_path / "o" / "report.json").read_text())
    assert rep["checks"]["failed"] == ["pressure_angle"]


def test_check_undercut_is_a_failed_check(tmp_path):
    res = run("check", "--example", "cylindrical", "--set", "follower.roller_radius=10", "--set", "motion[1].angle=30",
              "--set", "motion[2].angle=150", "-o", str(tmp_path / "o"))
    assert res.returncode == 3, res.stderr
    rep = json.loads((tmp_path / "o" / "report.json").read_text())
    assert "undercut" in rep["checks"]["failed"] and not rep["buildable"]["ok"]
    assert "cannot be made" in res.stdout and "Traceback" not in res.stderr


def test_check_bad_input_exit_2(tmp_path):
    res = run("check", "--example", "cylindrical", "--set", "cam.length=35", "-o", str(tmp_path / "o"))
    assert res.returncode == 2 and "cam.length" in res.stderr and "Traceback" not in res.stderr
    assert not (tmp_path / "o").exists()


# ---- dxf --------------------------------------------------------------------------------------------
def _distance_to_centre_line(rho: float, pts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance of developed points (x, z) from C_ρ(θ) = (ρ(π/2 − θ), z₀ + s(θ)) and the side (+1 above)."""
    grid = np.linspace(-0.3, 2 * np.pi + 0.3, 40001)
    cx = rho * (np.pi / 2 - grid)
    cz = Z0 + lift(grid)[0]
    out, side = np.empty(len(pts)), np.empty(len(pts))
    for i, (x, z) in enumerate(pts):
        k = int(np.argmin((cx - x) ** 2 + (cz - z) ** 2))

        def d2(t, x=x, z=z):
            return (rho * (np.pi / 2 - t) - x) ** 2 + (Z0 + float(lift(np.array([t]))[0][0]) - z) ** 2

        res = optimize.minimize_scalar(d2, bounds=(grid[k - 1], grid[k + 1]), method="bounded",
                                       options={"xatol": 1e-14})
        out[i] = math.sqrt(res.fun)
        side[i] = 1 if z > Z0 + float(lift(np.array([res.x]))[0][0]) else -1
    return out, side


@pytest.fixture(scope="module")
def drawing(tmp_path_factory):
    out = tmp_path_factory.mktemp("dxf") / "cam.dxf"
    res = run("dxf", "--example", "cylindrical", "-o", str(out))
    return out, res


def test_dxf_audit_and_layers(drawing):
    import ezdxf

    path, res = drawing
    assert res.returncode == 0, res.stderr
    doc = ezdxf.readfile(str(path))
    auditor = doc.audit()
    assert not auditor.errors and not auditor.fixes
    msp = doc.modelspace()
    layers = {e.dxf.layer for e in msp}
    assert {"WALL_LOWER", "WALL_UPPER", "PITCH", "OUTLINE", "BORE", "GROOVE_BOTTOM", "TITLE"} <= layers
    circles = sorted(round(e.dxf.radius, 9) for e in msp.query("CIRCLE"))
    assert circles == [BORE, RB, RO]
    assert [e.dxf.layer for e in msp.query("CIRCLE") if abs(e.dxf.radius - RB) < 1e-9] == ["GROOVE_BOTTOM"]
    assert doc.layers.get("GROOVE_BOTTOM").dxf.linetype == "DASHED"


def _reported(res) -> tuple[float, float]:
    line = [ln for ln in res.stdout.splitlines() if "max fit error" in ln][0]
    walls = float(line.split("max fit error ")[1].split(" ")[0])
    pitch = float(line.split("(pitch line ")[1].split(" ")[0])
    return walls, pitch


def test_dxf_walls_at_half_width_from_the_developed_centre_line(drawing):
    import ezdxf

    path, res = drawing
    err_walls, err_pitch = _reported(res)
    assert 0 < err_walls < 1e-6 and 0 < err_pitch < 1e-6
    msp = ezdxf.readfile(str(path)).modelspace()
    for layer, rho, side, offset, err in (("WALL_LOWER", RO, -1, W2, err_walls), ("WALL_UPPER", RO, 1, W2, err_walls),
                                          ("PITCH", RP, 0, 0.0, err_pitch)):
        splines = msp.query(f'SPLINE[layer=="{layer}"]')
        assert len(splines) == 5, layer
        pts = []
        for sp in splines:
            tool = sp.construction_tool()
            t = np.linspace(tool.knots()[0], tool.knots()[-1], 23)
            pts.append(np.array([(p.x, p.y) for p in tool.points(t)]))
        pts = np.concatenate(pts)
        if side:
            d, s = _distance_to_centre_line(rho, pts)
        else:
            # on the line itself the distance's minimisation is flat (d² ~ Δθ²): the vertical distance at
            # the point's own x, θ = π/2 − x/ρ (the spline's x is exactly linear in θ: a cubic interpolant)
            d = np.abs(pts[:, 1] - (Z0 + lift(np.pi / 2 - pts[:, 0] / rho)[0]))
        # the reported error (3 significant digits) plus the rounding of that and of the distance solve
        assert np.max(np.abs(d - offset)) <= err * 1.01 + 1e-10, layer
        if side:
            assert np.all(s == side), layer
        # the whole turn is drawn: x from ρ(π/2 − 2π) to ρπ/2
        assert np.min(pts[:, 0]) == pytest.approx(rho * (np.pi / 2 - 2 * np.pi), abs=1e-9)
        assert np.max(pts[:, 0]) == pytest.approx(rho * np.pi / 2, abs=1e-9)


def test_dxf_title_block_quotes_the_error(drawing):
    import ezdxf

    path, res = drawing
    texts = [e.dxf.text for e in ezdxf.readfile(str(path)).modelspace().query("TEXT")]
    from cam_workbench.exporters.dxf_cylindrical import developed_curves
    from cam_workbench.generators import design_cam

    err = max(c.fit_error for c in developed_curves(design_cam(CamSpec.from_dict(EXAMPLES["cylindrical"])))
              if c.layer.startswith("WALL"))
    assert f"CUBIC SPLINES, NOT EXACT: FIT ERROR {err:.2e} mm" in texts
    assert f"{err:.3g}" in res.stdout


@requires_ocp
def test_build_report_holds_the_drawing_error(tmp_path):
    res = run("build", "--example", "cylindrical", "-o", str(tmp_path / "out"))
    assert res.returncode == 0, res.stderr
    rep = json.loads((tmp_path / "out" / "report.json").read_text())
    fit = rep["drawing"]["developed_fit_error"]
    dx = run("dxf", "--example", "cylindrical", "-o", str(tmp_path / "d.dxf"))
    assert _reported(dx) == (float(f"{fit['value']:.3g}"), float(f"{fit['pitch_line']:.3g}"))
    assert rep["files"]["dxf"] == "cam.dxf" and (tmp_path / "out" / "cam.dxf").exists()


@pytest.mark.parametrize("curves,version", [("arcs", "R2010"), ("polyline", "R12")])
def test_dxf_arcs_and_polyline_walls(tmp_path, curves, version):
    """For machines that read no splines: the walls as arcs (or one polyline per motion segment),
    within drawing.chord_tolerance of the exact walls — points of them at w/2 from the developed
    centre line within the reported error — and no SPLINE in the file (R12 has none)."""
    import ezdxf

    from cam_workbench.exporters.dxf import read_profile_path

    out = tmp_path / "c.dxf"
    res = run("dxf", "--example", "cylindrical", "--curves", curves, "--dxf-version", version, "-o", str(out))
    assert res.returncode == 0, res.stderr
    err_walls, err_pitch = _reported(res)
    assert 0 < err_walls <= 0.001 and 0 < err_pitch <= 0.001
    doc = ezdxf.readfile(str(out))
    assert not doc.audit().has_errors and len(doc.modelspace().query("SPLINE")) == 0
    if curves == "arcs":
        assert len(doc.modelspace().query('ARC[layer=="WALL_LOWER"]')) > 5
    for layer, side in (("WALL_LOWER", -1), ("WALL_UPPER", 1)):
        pts = read_profile_path(out, layer).sample(2)
        pts = pts[:: max(1, len(pts) // 60)]
        d, s = _distance_to_centre_line(RO, np.column_stack([pts.real, pts.imag]))
        assert np.max(np.abs(d - W2)) <= err_walls * 1.01 + 1e-10, layer
        assert np.all(s == side), layer


def test_api_export_dxf(tmp_path):
    import ezdxf

    from cam_workbench import Cam

    p = Cam.example("cylindrical").export_dxf(tmp_path / "c.dxf")
    assert len(ezdxf.readfile(str(p)).modelspace().query("SPLINE")) == 15


# ---- dynamics ---------------------------------------------------------------------------------------
DYN = ["--set", "dynamics.stiffness=2000", "--set", "dynamics.mass=2", "--speed", "300", "--no-sweep"]


def test_dynamics_cli_equals_api_and_virtual_work(tmp_path):
    from cam_workbench import Cam

    res = run("dynamics", "--example", "cylindrical", *DYN, "-o", str(tmp_path / "o"))
    assert res.returncode == 0, res.stderr
    cli = json.loads((tmp_path / "o" / "report.json").read_text())["dynamics"]
    # the speed through the spec, as the CLI's --speed sets it
    r = Cam.example("cylindrical", **{"dynamics.speed_rpm": 300.0}).dynamics(sweep=False, stiffness=2000.0,
                                                                                  mass=2.0)
    assert json.loads(json.dumps(r.summary())) == cli
    # virtual work: T = Q·s′ and the normal force F = Q/cos φ, tan φ = s′/R_p
    _, ds = lift(r.theta)
    phi = np.arctan(ds / RP)
    for f, t in ((r.force, r.torque), (r.rigid_force, r.rigid_torque)):
        assert np.max(np.abs(t - f * np.cos(phi) * ds)) <= 1e-9 * np.max(np.abs(t))
    # the rigid force of a massive follower without spring: m·s″·ω², its sign changes where s″ does
    assert cli["contact"]["closure"] == "form" and cli["contact"]["kept"]
    rigid = cli["contact"]["drive"]["rigid"]["changes_at_deg"]
    assert any(abs(a - 90.0) < 0.1 for a in rigid) and any(abs(a - 270.0) < 0.1 for a in rigid)
    assert "jump_speed" not in cli and "form closure: the load changes wall at" in res.stdout


def test_dynamics_enabled_in_the_spec():
    d = copy.deepcopy(EXAMPLES["cylindrical"])
    d["dynamics"] = {"enabled": True, "stiffness": 2000.0, "mass": 2.0}
    assert CamSpec.from_dict(d).dynamics.enabled


# ---- ecam ---------------------------------------------------------------------------------------
def test_ecam_equals_the_plate_cams(tmp_path):
    from cam_workbench.generators.spec import DEFAULT_SPEC_DICT

    plate = copy.deepcopy(DEFAULT_SPEC_DICT)
    plate["motion"] = copy.deepcopy(EXAMPLES["cylindrical"]["motion"])
    plate["cam"]["speed_rpm"] = EXAMPLES["cylindrical"]["cam"]["speed_rpm"]
    (tmp_path / "p.toml").write_text(dict_to_toml(plate))
    a = run("ecam", "--example", "cylindrical", "-o", str(tmp_path / "c.csv"))
    b = run("ecam", str(tmp_path / "p.toml"), "-o", str(tmp_path / "p.csv"))
    assert a.returncode == 0 and b.returncode == 0, a.stderr + b.stderr
    text = (tmp_path / "c.csv").read_text()
    assert text == (tmp_path / "p.csv").read_text() and len(text.splitlines()) > 300


# ---- sweep / batch / --set --------------------------------------------------------------------------
def test_set_cylinder_radius_moves_the_base_radius():
    from cam_workbench.generators.spec.examples import example_spec

    s = example_spec("cylindrical").replace(**{"cam.cylinder_radius": 45.0, "cam.length": 70.0})
    assert (s.cam.base_radius, s.cam.thickness) == (45.0, 70.0)


def test_sweep_cylinder_radius(tmp_path):
    import csv

    res = run("sweep", "--example", "cylindrical", "--vary", "cam.cylinder_radius=36:44:3", "--workers", "0",
              "-o", str(tmp_path / "s"))
    assert res.returncode == 0, res.stdout + res.stderr
    rows = list(csv.DictReader((tmp_path / "s" / "sweep.csv").open()))
    assert [float(r["cam.cylinder_radius"]) for r in rows] == [36.0, 40.0, 44.0]
    for r in rows:
        rp = float(r["cam.cylinder_radius"])
        assert r["status"] == "ok" and float(r["base_radius"]) == rp
        assert float(r["pressure_angle_deg"]) == pytest.approx(math.degrees(math.atan(DS_MAX / rp)), abs=1e-9)
        # the cylinder keeps its outer radius R_p + depth/2 and groove bottom R_p − depth/2
        assert float(r["outer_radius"]) == pytest.approx(rp + 4.0, abs=1e-12)


def test_sweep_size_refused(tmp_path):
    res = run("sweep", "--example", "cylindrical", "--vary", "motion[1].lift=10:20:2", "--size", "base_radius",
              "--workers", "0", "-o", str(tmp_path / "s"))
    assert res.returncode == 2 and "--size" in res.stderr and "Traceback" not in res.stderr
    assert not (tmp_path / "s").exists()


@requires_ocp
def test_batch_builds_a_cylindrical_cam(tmp_path):
    import csv

    (tmp_path / "c.toml").write_text(dict_to_toml(EXAMPLES["cylindrical"]))
    res = run("batch", str(tmp_path / "c.toml"), "--workers", "0", "-o", str(tmp_path / "b"))
    assert res.returncode == 0, res.stdout + res.stderr
    row = list(csv.DictReader((tmp_path / "b" / "summary.csv").open()))[0]
    rep = json.loads((tmp_path / "b" / "c" / "report.json").read_text())
    assert row["status"] == "ok" and float(row["pressure_angle_deg"]) == rep["pressure_angle"]["max_deg"]
    assert (tmp_path / "b" / "c" / "cam.dxf").exists() and (tmp_path / "b" / "c" / "cam.step").exists()


# ---- the README picture -------------------------------------------------------------------------------
def test_cylindrical_figure_draws_the_walls():
    import xml.etree.ElementTree as ET

    from cam_workbench.exporters import chart_svg, plots_cylindrical
    from cam_workbench.exporters.chart import Curve
    from cam_workbench.generators import design_cam

    chart = plots_cylindrical.cylindrical_figure(design_cam(CamSpec.from_dict(EXAMPLES["cylindrical"])))
    developed = chart.columns[1][0]
    walls = [m for m in developed.marks if isinstance(m, Curve) and m.color == "#1f3a5f"]
    assert len(walls) == 2
    for ln, side in zip(walls, (-1, 1)):
        pts = np.column_stack([ln.x, ln.y])[::97]
        d, s = _distance_to_centre_line(RO, pts)
        assert np.max(np.abs(d - W2)) < 1e-9 and np.all(s == side)
    ET.fromstring(chart_svg.svg(chart, "cyl"))


# ---- report.html ------------------------------------------------------------------------------------
@requires_ocp
@pytest.mark.parametrize("example", ["cylindrical", "cylindrical_oscillating"])
def test_report_page_shows_report_json(tmp_path, example):
    """report.html of a cylindrical cam: the checks' verdict is report.json's, every number cell holds
    exactly report.json's value (data-key), both figures are in the page and written as PNGs (--plots), and
    headless Chromium builds the page with both SVGs."""
    import shutil

    from cam_workbench.generators.checks.claims import checks_verdict

    from .test_report import Page, lookup

    res = run("report", "--plots", "--example", example, "-o", str(tmp_path / "r"))
    assert res.returncode == 0, res.stderr
    report = json.loads((tmp_path / "r" / "report.json").read_text())
    text = (tmp_path / "r" / "report.html").read_text(encoding="utf-8")
    page = Page()
    page.feed(text)
    assert not page.errors and not page.resources, (page.errors, page.resources)
    assert ("verdict pass" in text) == report["checks"]["passed"] and checks_verdict(report["checks"]) in text
    keys = set()
    for attrs, shown in page.cells:
        key = attrs["data-key"]
        keys.add(key)
        value = lookup(report, key)
        if "data-value" in attrs and not isinstance(value, (bool, type(None))):
            assert float(attrs["data-value"]) == value, key
            assert float(shown) == pytest.approx(value, rel=5e-6), key
        elif "data-value" not in attrs:
            assert shown == value, key
    for key in ("body.wall_error.value", "body.wall_fit_error.value", "drawing.developed_fit_error.value",
                "checks.results.pressure_angle.value", "volume", "solid.volume_rel_diff"):
        assert key in keys, key
    assert report["files"]["plots"] == ["plot_cylinder.png", "plot_pressure_angle.png"]
    for name in report["files"]["plots"]:
        assert page.figures.get(f"fig-{name[5:-4]}") == 1 and (tmp_path / "r" / name).stat().st_size > 10000
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium:   # make test installs it (as root); the page's DOM as a browser builds it
        dom = subprocess.run([chromium, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                              f"--user-data-dir={tmp_path / 'profile'}", "--dump-dom",
                              (tmp_path / "r" / "report.html").resolve().as_uri()],
                             capture_output=True, text=True, timeout=SAFETY_S)
        assert dom.returncode == 0 and dom.stdout.count("<svg") >= 2
        assert 'id="fig-cylinder"' in dom.stdout and 'id="fig-pressure_angle"' in dom.stdout

"""Inspection of a made cam (docs/inspection.md): synthetic parts made here from the design's exact
profile — a known rotation and shift, error waves of known amplitude and count along the normal,
Gaussian noise, outliers — and what the inspection finds in them: the pose, the deviation map, the
outliers, the profile verdict and the follower's motion error, each against what was put in or
against the closed-form first-order prediction derived below."""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st
from scipy.stats import norm

from cam_workbench.exporters.inspection_report import rows
from cam_workbench.exporters.report_cells import format_number, lookup
from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.inspection import DATUMS, inspect_design
from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.inspection import inspect_part, read_points, write_inspection

from .conftest import ROOT

UM = 1e-3                                   # a micrometre in mm


@pytest.fixture(scope="module")
def designs():
    """Designs by name, built once: the default (radial translating roller), the paper's offset
    roller, an oscillating roller, a translating flat face; "fine" and "paper_fine": the default with 120
    PH segments, the paper's with 240."""
    names = ("default", "paper", "oscillating", "flat")
    out = {n: design_cam(example_spec(n)) for n in names}
    out["fine"] = design_cam(example_spec("default").replace(**{"pitch.segments": 120}))
    out["paper_fine"] = design_cam(example_spec("paper").replace(**{"pitch.segments": 240}))
    return out


def synthetic_part(design, n: int, seed: int = 0, *, waves=(), noise: float = 0.0, outliers: float = 0.0,
                   rotation: float = 0.0, shift: complex = 0j):
    """Points of a made part in a measuring frame: the exact profile sampled at random parameters,
    moved along its outward normal by Σ A·cos(k·θ) (θ the cam angle at which the follower touches
    the point) plus N(0, noise²), a fraction ``outliers`` of them a further +0.5 mm, then put in a
    frame in which the part sits rotated by −rotation and shifted: m = e^{−iα}(x − t), so that the
    registration should find x = e^{iα}m + t.  Returns (points (n, 2), injected δ, θ, outlier mask)."""
    rng = np.random.default_rng(seed)
    prof = design.profile
    lo, hi = prof.domain
    u = np.sort(rng.uniform(lo, hi, n))
    p, d = prof.evaluate_with_derivative(u)
    z, dz = p[:, 0] + 1j * p[:, 1], d[:, 0] + 1j * d[:, 1]
    outward = (-1j if prof.area() > 0 else 1j) * dz / np.abs(dz)
    seg = np.minimum(np.floor(u).astype(int), design.pitch.M - 1)
    theta = np.deg2rad(design.pitch.cam_angle_at(seg, u - seg))
    delta = sum((a * np.cos(k * theta) for a, k in waves), np.zeros(n)) + rng.normal(0.0, noise, n) * (noise > 0)
    mask = rng.random(n) < outliers
    delta = delta + 0.5 * mask
    x = z + delta * outward
    m = np.exp(-1j * rotation) * (x - shift)
    return np.column_stack([m.real, m.imag]), delta, theta, mask


# ---- registration ---------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["default", "paper", "oscillating", "flat"])
@pytest.mark.parametrize("datum,rotation,shift", [("none", 2.1, 3.0 - 1.5j), ("none", -0.4, 0.2 + 0.7j),
                                                  ("bore", 1.3, 0j), ("bore_and_angle", 0.0, 0j)])
def test_registration_recovers_the_pose_noise_free(designs, name, datum, rotation, shift):
    """An exact part in any frame: the pose to 0.1 µm and 1e-6 rad, every deviation to 0.1 µm."""
    d = designs[name]
    pts, delta, _, _ = synthetic_part(d, 2000, seed=1, rotation=rotation, shift=shift)
    res = inspect_design(d, pts, datum=datum)
    reg = res.registration
    assert abs(np.angle(np.exp(1j * (reg.rotation - rotation)))) <= 1e-6
    assert abs(reg.shift - shift) <= 0.1 * UM
    assert np.max(np.abs(res.deviations.value - delta)) <= 0.1 * UM
    assert not reg.outliers.any() and reg.converged


def test_the_pose_uncertainty_is_the_fits(designs):
    """The reported standard uncertainties of α, t_x, t_y are σ·√diag((JᵀJ)⁻¹), J the rigid modes
    along the normals (∂d/∂α = N·i(x − t), ∂d/∂t = N) — computed here from the part's exact normals
    and the noise put in (within 10 %: the fit's σ is a MAD estimate, its weights Tukey's)."""
    d = designs["paper"]
    sigma = 2 * UM
    rotation, shift = 0.6, 1.0 + 2.0j
    pts, delta, _, _ = synthetic_part(d, 5000, seed=12, noise=sigma, rotation=rotation, shift=shift)
    reg = inspect_design(d, pts, datum="none").registration
    m = pts[:, 0] + 1j * pts[:, 1]
    turned = np.exp(1j * rotation) * m
    u = reg.projection.u
    _, der = d.profile.evaluate_with_derivative(u)
    dz = der[:, 0] + 1j * der[:, 1]
    normal = (-1j if d.profile.area() > 0 else 1j) * dz / np.abs(dz)
    jac = np.column_stack([(np.conj(normal) * 1j * turned).real, normal.real, normal.imag])
    expected = sigma * np.sqrt(np.diag(np.linalg.inv(jac.T @ jac)))
    assert np.array(reg.std) == pytest.approx(expected, rel=0.1)
    held = inspect_design(d, pts, datum="bore_and_angle").registration
    assert held.std == (None, None, None)


def test_smoothing_follows_waves_not_noise(designs):
    """Generalised cross-validation: noise-free waves get the finest knots allowed; noise alone the
    coarsest (one span per PH segment: 24° waves on the default's 60 segments)."""
    d = designs["default"]
    pts, *_ = synthetic_part(d, 4000, seed=11, waves=((2 * UM, 20),))
    s = inspect_design(d, pts, datum="bore_and_angle").summary()["motion"]["smoothing"]
    assert s["wavelength_deg"] == s["shortest_allowed_deg"] == 6.0
    pts, *_ = synthetic_part(d, 4000, seed=11, noise=2 * UM)
    s = inspect_design(d, pts, datum="bore_and_angle").summary()["motion"]["smoothing"]
    assert s["wavelength_deg"] == 24.0 and s["spans"] == 60


def rigid_residual(points_part, normals, residual):
    """What is left of ``residual`` (a field along the normals) after the least-squares rigid
    motion (rotation about the origin, shift) is taken out — written here, independently."""
    jac = np.column_stack([(np.conj(normals) * 1j * points_part).real, normals.real, normals.imag])
    coef, *_ = np.linalg.lstsq(jac, residual, rcond=None)
    return residual - jac @ coef


def test_deviation_map_is_the_injected_error(designs):
    """Waves of known amplitude and count: held by the datums (bore and angle: the points are in the
    part's frame) the deviation map is the injected error to 0.1 µm; registered freely, it is the
    injected error up to a rigid motion (the waves' share of the rigid modes, which a best fit
    cannot tell from a misplaced part) — and that rigid motion is small."""
    d = designs["default"]
    waves = ((4 * UM, 5), (2 * UM, 11), (1 * UM, 23))
    pts, delta, _, _ = synthetic_part(d, 4000, seed=2, waves=waves)
    held = inspect_design(d, pts, datum="bore_and_angle")
    assert np.max(np.abs(held.deviations.value - delta)) <= 0.1 * UM
    moved, *_ = synthetic_part(d, 4000, seed=2, waves=waves, rotation=0.9, shift=-2 + 4j)
    free = inspect_design(d, moved, datum="none")
    pr = free.registration.projection
    left = rigid_residual(pr.foot, pr.normal, free.deviations.value - delta)
    assert np.max(np.abs(left)) <= 0.1 * UM
    assert np.max(np.abs(free.deviations.value - delta)) <= 1.0 * UM


def test_outliers_are_flagged_and_reported(designs):
    """1 µm noise and 5 % of the points 0.5 mm off: every one of them flagged and listed, no inlier
    flagged; the pose still within 0.5 µm and 1e-5 rad; the verdict names the outliers."""
    d = designs["default"]
    pts, delta, _, mask = synthetic_part(d, 6000, seed=3, noise=1 * UM, outliers=0.05, rotation=-1.2, shift=1 + 1j)
    res = inspect_design(d, pts, datum="none", tolerance=0.02)
    reg = res.registration
    assert np.array_equal(reg.outliers, mask)
    assert abs(np.angle(np.exp(1j * (reg.rotation + 1.2)))) <= 1e-5
    assert abs(reg.shift - (1 + 1j)) <= 0.5 * UM
    s = res.summary()
    assert s["registration"]["outliers"] == int(mask.sum())
    assert s["registration"]["outlier_indices"] == [int(i) for i in np.flatnonzero(mask)]
    assert s["tolerance"]["verdict"] == "pass_excluding_outliers"
    assert s["tolerance"]["outside"] == int(mask.sum()) and s["tolerance"]["outside_inliers"] == 0
    # the robust scale 1.4826·median|d| over every point: with a fraction f of them far off, the median
    # is the inliers' |d| quantile q = 0.5/(1 − f), i.e. σ·Φ⁻¹((1 + q)/2) (5700 deviates: within 4 %)
    q = 0.5 / (1 - mask.mean())
    assert s["registration"]["scale"] == pytest.approx(1.4826 * UM * norm.ppf((1 + q) / 2), rel=0.04)


@pytest.mark.parametrize("tolerance", [0.004, 0.006, 0.0101])
def test_profile_verdict_counts_the_points_outside_the_zone(designs, tolerance):
    """ISO 1101 profile of a line: a point fails when |δ| > t/2 — counted here from the injected δ."""
    d = designs["default"]
    pts, delta, _, _ = synthetic_part(d, 3000, seed=4, waves=((2.5 * UM, 7),), noise=0.4 * UM)
    s = inspect_design(d, pts, datum="bore_and_angle", tolerance=tolerance).summary()["tolerance"]
    outside = int(np.count_nonzero(np.abs(delta) > tolerance / 2))
    assert s["outside"] == outside
    assert s["verdict"] == ("pass" if outside == 0 else "fail")
    assert s["zone"] == [-tolerance / 2, tolerance / 2]


# ---- the follower on the measured part --------------------------------------------------------------
def first_order_lift_error(design, amplitude: float, waves: int, theta: np.ndarray):
    """(Δs, Δs″) of a translating roller or knife on a profile moved by δ = A·cos(nθ) along its
    normal, to first order in A.

    The roller's centre stays at the roller radius from the profile, so the pitch curve moves by the
    same δ along the same normal (an offset moves with its curve, to first order; the normal's turn
    by δ′ only slides the point along the curve).  The follower slides along its line (direction w);
    to stay on a curve moved by δ along the normal N it moves by Δs with Δs·(N·w) = δ, and N·w = cos φ:

        Δs(θ) = A·cos(nθ)·g(θ),   g = 1/cos φ = √(1 + T²),   T = tan φ = (s′ − e)/(s₀ + s)   (thesis Eq. 3.4)

    (the contact point moves too, but the lift is stationary in it: a second-order effect).  Then

        Δs″ = A·[−n²·cos(nθ)·g − 2n·sin(nθ)·g′ + cos(nθ)·g″],
        g′ = T·T′/g,  g″ = (T′² + T·T″)/g − (T·T′)²/g³,
        T′ = (s″Y − (s′ − e)s′)/Y²,  T″ = [(s‴Y − (s′ − e)s″)Y − 2s′(s″Y − (s′ − e)s′)]/Y³,  Y = s₀ + s,

    with s, s′, s″, s‴ of the motion program (the design intent) and e the effective offset."""
    k = design.program.evaluate(theta)
    fol = design.follower
    e = fol.offset * fol.sense
    y = fol.s0 + k.s
    t = (k.ds - e) / y
    t1 = (k.d2s * y - (k.ds - e) * k.ds) / y**2
    t2 = ((k.d3s * y - (k.ds - e) * k.d2s) * y - 2 * k.ds * (k.d2s * y - (k.ds - e) * k.ds)) / y**3
    g = np.sqrt(1 + t * t)
    g1 = t * t1 / g
    g2 = (t1**2 + t * t2) / g - (t * t1) ** 2 / g**3
    c, s = np.cos(waves * theta), np.sin(waves * theta)
    return amplitude * c * g, amplitude * (-waves**2 * c * g - 2 * waves * s * g1 + c * g2)


@pytest.mark.parametrize("name,share", [("fine", 0.01), ("paper_fine", 0.02)])
@pytest.mark.parametrize("waves", [3, 8, 15])
def test_motion_error_is_the_first_order_prediction(designs, name, share, waves):
    """The follower's displacement error on a part with a 2 µm wave is A·cos(nθ)/cos φ to 0.5 % of A
    (the second-order term r·β²/2, β = 2πA/λ the wave's slope: 0.2 % of A for n = 15 on the paper's
    small cam, 9.4 mm waves under a 5 mm roller; it doubles with A, as measured), its acceleration error the closed form's ω²·Δs″ to 1 % of
    A(nω)² on the default cam, 2 % on the paper's (offset 10 mm, φ up to 46°).  The rest is the built
    PH curve's: the closed form reads the intent's s‴, the part has the PH curve's, whose error falls
    as 1/M (measured on the paper's cam, n = 3: 6.7 % at M = 60, 1.5 % at M = 240 — hence M = 120 and
    240 here); and the reported numbers are these series'."""
    d = designs[name]
    amplitude = 2 * UM
    pts, _, _, _ = synthetic_part(d, 6000, seed=5, waves=((amplitude, waves),))
    res = inspect_design(d, pts, datum="bore_and_angle")
    mm = res.motion
    ds, d2s = first_order_lift_error(d, amplitude, waves, mm.theta)
    assert np.max(np.abs(mm.error[0] - ds)) <= 5e-3 * amplitude
    # with an offset, tan φ ≠ 0 where a segment starts, and s‴'s jump there is one of Δs″ (the g″ term):
    # the central difference straddles it — compare one sample step away from the boundaries
    h = mm.theta[1] - mm.theta[0]
    edge = np.min(np.abs(np.angle(np.exp(1j * (mm.theta[:, None] - d.program.boundaries[None, :])))), axis=1)
    away = edge > 1.5 * h
    assert np.max(np.abs(mm.error[2] - d2s)[away]) <= share * amplitude * waves**2
    omega = d.spec.cam.speed_rpm * 2 * np.pi / 60
    summary = res.summary()["motion"]
    da = omega**2 * mm.error[2]
    assert summary["acceleration_error"]["max_abs"] == pytest.approx(float(np.max(np.abs(da))), rel=1e-12)
    peak = d.summary()["motion"]["max_acceleration"]                  # report.json's
    assert summary["designed_peak"]["acceleration"] == peak
    assert summary["acceleration_error"]["fraction_of_designed_peak"] == pytest.approx(
        float(np.max(np.abs(da))) / peak, rel=1e-12)
    assert summary["design_reproduction"] <= 1e-9


def test_an_exact_part_gives_the_designed_motion(designs):
    """No deviation: the measured motion is the designed one (the chain reproduces the design's solve)."""
    for name in ("default", "oscillating", "flat"):
        d = designs[name]
        pts, *_ = synthetic_part(d, 2000, seed=6)
        mm = inspect_design(d, pts, datum="bore_and_angle").motion
        assert np.max(np.abs(mm.error[0])) <= 1e-9, name
        assert np.max(np.abs(mm.error[2])) <= 1e-4, name


# ---- combinations -------------------------------------------------------------------------------------
@settings(max_examples=16, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(name=st.sampled_from(["default", "paper", "oscillating", "flat"]), datum=st.sampled_from(DATUMS),
       rotation=st.floats(-np.pi, np.pi), sx=st.floats(-5, 5), sy=st.floats(-5, 5),
       noise=st.sampled_from([0.0, 0.5 * UM]), seed=st.integers(0, 2**16))
def test_pose_noise_and_datum_combinations(designs, name, datum, rotation, sx, sy, noise, seed):
    """Any pose a datum allows, with or without noise: the pose found, every deviation the injected
    one within the noise's reach, no outlier flagged in noise-free data."""
    d = designs[name]
    rotation, shift = {"none": (rotation, complex(sx, sy)), "bore": (rotation, 0j), "bore_and_angle": (0.0, 0j)}[datum]
    pts, delta, _, _ = synthetic_part(d, 1500, seed=seed, noise=noise, rotation=rotation, shift=shift)
    res = inspect_design(d, pts, datum=datum)
    reg = res.registration
    # noise: the pose is a mean over 1500 points (σ/√N ≈ 0.013 µm), with room for the rotation's conditioning
    pose_tol = (0.1 * UM, 1e-6) if noise == 0 else (0.3 * UM, 2e-5)
    assert abs(np.angle(np.exp(1j * (reg.rotation - rotation)))) <= pose_tol[1]
    assert abs(reg.shift - shift) <= pose_tol[0]
    assert np.max(np.abs(res.deviations.value - delta)) <= 0.1 * UM + (0.5 * UM if noise else 0.0)
    if noise == 0:
        assert not reg.outliers.any()


# ---- refusals ---------------------------------------------------------------------------------------------
def test_a_design_without_a_plane_profile_is_refused():
    with pytest.raises(SpecError, match="cam.body"):
        inspect_part(example_spec("cylindrical"), np.zeros((10, 2)))


@pytest.mark.parametrize("kwargs,field", [({"datum": "keyway"}, "datum"), ({"tolerance": -0.01}, "tolerance"),
                                          ({"tolerance": float("nan")}, "tolerance"),
                                          ({"wavelength_deg": 0.0}, "wavelength")])
def test_bad_options_name_the_option(designs, kwargs, field):
    pts, *_ = synthetic_part(designs["default"], 500)
    with pytest.raises(SpecError) as err:
        inspect_part(example_spec("default"), pts, **kwargs)
    assert err.value.field == field


def test_the_parsers_datums_and_default_are_the_generators():
    from cam_workbench.commands import parsers
    from cam_workbench.generators.inspection.measured_motion import DEFAULT_WAVELENGTH_DEG

    assert parsers.INSPECTION_DATUMS == DATUMS
    sub = next(a for a in parsers.parser()._actions if a.dest == "command").choices["inspect"]
    assert next(a for a in sub._actions if a.dest == "wavelength").default == DEFAULT_WAVELENGTH_DEG


# ---- the points file and the command line ----------------------------------------------------------------
def write_csv(path, pts, header="x,y", z=None):
    lines = [header] if header else []
    for i, (x, y) in enumerate(pts):
        lines.append(f"{float(x)!r},{float(y)!r}" + ("" if z is None else f",{float(z)!r}"))
    path.write_text("\n".join(lines) + "\n")
    return path


def test_read_points_takes_a_header_comments_and_z(tmp_path):
    p = tmp_path / "p.csv"
    p.write_text("# CMM export\nX, Y, Z\n1.5,2,0.25\n\n3,4.25,0.25\n-1e1,5,0.5\n")
    assert read_points(p).tolist() == [[1.5, 2.0, 0.25], [3.0, 4.25, 0.25], [-10.0, 5.0, 0.5]]
    q = tmp_path / "q.csv"
    q.write_text("1,2\n3,4\n5,6\n")
    assert read_points(q).shape == (3, 2)


BAD_CSV = [
    ("x,y,q\n1,2,3\n3,4,5\n5,6,7\n", "line 1", "header"),
    ("1,2\n3,4,5\n5,6\n7,8\n", "line 2", "columns"),
    ("1\n2\n3\n", "line 1", "columns"),
    ("1,2\n3,abc\n5,6\n7,8\n", "line 2", "'abc' is not a finite number"),
    ("1,2\n3,nan\n5,6\n7,8\n", "line 2", "not a finite number"),
    ("x,y\n1,2\n3,4\n", "", "at least 3"),
    ("1,2,3,4\n", "line 1", "columns"),
]


@pytest.mark.parametrize("text,line,rule", BAD_CSV)
def test_a_bad_points_file_names_file_line_and_rule(tmp_path, text, line, rule):
    p = tmp_path / "bad.csv"
    p.write_text(text)
    with pytest.raises(SpecError) as err:
        read_points(p)
    assert str(p) in err.value.field and line in err.value.field and rule in err.value.rule


def cli(*args, cwd=None):
    env = dict(os.environ, PYTHONPATH=str(ROOT), COLUMNS="300")
    return subprocess.run([sys.executable, "-m", "cam_workbench.cli", *args], capture_output=True, text=True,
                          cwd=cwd, env=env)


@pytest.mark.parametrize("text,line,rule", BAD_CSV[:4] + [(None, "", "cannot be read")])
def test_cli_bad_points_exit_2_and_write_nothing(tmp_path, text, line, rule):
    p = tmp_path / "bad.csv"
    if text is not None:
        p.write_text(text)
    out = tmp_path / "out"
    res = cli("inspect", str(p), "-o", str(out), "--tolerance", "0.01")
    assert res.returncode == 2, res.stderr
    assert "Traceback" not in res.stderr and rule in res.stderr and str(p) in res.stderr
    assert not out.exists()


def test_cli_writes_the_report_and_prints_its_numbers(tmp_path, designs):
    """inspect -o: the files; the printed table is inspection.json's numbers; exit 0 within tolerance."""
    pts, delta, _, mask = synthetic_part(designs["default"], 3000, seed=7, waves=((3 * UM, 6),), noise=0.5 * UM,
                                         outliers=0.03, rotation=0.5, shift=2 - 1j)
    csv = write_csv(tmp_path / "pts.csv", pts, header="x,y,z", z=5.0)
    out = tmp_path / "out"
    res = cli("inspect", str(csv), "--tolerance", "0.02", "-o", str(out))
    assert res.returncode == 0, res.stderr
    report = json.loads((out / "inspection.json").read_text())
    for name in ("inspection.json", "inspection.html", "deviations.csv", "motion.csv", "deviation_map.svg",
                 "deviation_angle.svg", "measured_motion.svg"):
        assert (out / name).exists() and name in report["files"]
    assert report["points"] == {"count": 3000, "z_given": True, "z_min": 5.0, "z_max": 5.0}
    assert report["registration"]["outlier_indices"] == [int(i) for i in np.flatnonzero(mask)]
    assert report["tolerance"]["verdict"] == "pass_excluding_outliers"
    printed = {}
    for line in res.stdout.splitlines():
        cells = [c.strip() for c in line.split("│")]
        if len(cells) == 6:
            printed[cells[1]] = cells[2]
    shown = rows(report)
    assert len(shown) >= 20
    for label, key, _unit, _at in shown:
        assert printed[label] == format_number(lookup(report, key)), label
    # the HTML's cells carry inspection.json's exact values
    page = (out / "inspection.html").read_text()
    for _label, key, _unit, _at in shown:
        v = lookup(report, key)
        if isinstance(v, float):
            assert f'data-key="{key}" data-value="{v!r}"' in page, key
    # deviations.csv: every point's deviation as inspection found it
    table = np.genfromtxt(out / "deviations.csv", delimiter=",", names=True)
    assert np.max(np.abs(table["deviation"][~mask] - delta[~mask])) <= 3 * UM
    assert np.array_equal(table["outlier"].astype(bool), mask)


def test_cli_exit_3_when_out_of_tolerance(tmp_path, designs):
    pts, *_ = synthetic_part(designs["default"], 1000, seed=8, waves=((8 * UM, 4),))
    csv = write_csv(tmp_path / "pts.csv", pts)
    res = cli("inspect", str(csv), "--tolerance", "0.01", "--datum", "bore_and_angle")
    assert res.returncode == 3, res.stderr
    assert "profile verdict: fail" in res.stdout


def test_write_inspection_from_python(tmp_path, designs):
    pts, *_ = synthetic_part(designs["default"], 1000, seed=9, waves=((2 * UM, 4),))
    result = inspect_part(example_spec("default"), pts, tolerance=0.01, datum="bore_and_angle")
    report = write_inspection(result, tmp_path / "insp")
    assert report == json.loads((tmp_path / "insp" / "inspection.json").read_text())
    assert report["tolerance"]["verdict"] == "pass"


def test_figures_mark_the_reports_numbers(designs):
    """The figures' marks stand for inspection.json's numbers: the zone's rules at ±t/2, the largest
    acceleration error's dot, the outliers' count."""
    from cam_workbench.exporters.inspection_report import figures
    from cam_workbench.exporters.plots import small_unit

    pts, *_ = synthetic_part(designs["default"], 2000, seed=10, waves=((3 * UM, 5),), outliers=0.02)
    res = inspect_design(designs["default"], pts, tolerance=0.02)
    report = json.loads(json.dumps(res.summary()))
    charts = figures(res, report)
    scale, _ = small_unit("mm")
    assert charts["angle"].marks("angle-zone-high")[0].at == pytest.approx(0.01 * scale)
    assert charts["angle"].marks("angle-zone-low")[0].at == pytest.approx(-0.01 * scale)
    dot = charts["motion"].marks("motion-da-max")[0]
    assert float(dot.x[0]) == report["motion"]["acceleration_error"]["at_deg"]
    assert abs(float(dot.y[0])) == pytest.approx(report["motion"]["acceleration_error"]["max_abs"], rel=1e-12)
    assert len(charts["map"].marks("map-outliers")[0].x) == report["registration"]["outliers"]


# ---- docs/inspection.md -----------------------------------------------------------------------------------
DOC = ROOT / "docs" / "inspection.md"


def test_the_docs_python_runs(monkeypatch):
    monkeypatch.chdir(ROOT)
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), re.S)
    assert blocks
    for block in blocks:
        exec(compile(block, str(DOC), "exec"), {})


def test_the_docs_worked_example_prints_what_the_command_prints():
    """The table docs/inspection.md quotes is the one the command prints for its example file."""
    result = inspect_part(example_spec("default"), ROOT / "docs" / "examples" / "inspection_points.csv",
                          tolerance=0.02)
    report = json.loads(json.dumps(result.summary()))
    text = DOC.read_text(encoding="utf-8")
    quoted = text[text.index("```text\ninspection:"):]
    quoted = quoted[:quoted.index("```", 3)]
    for label, key, _unit, _at in rows(report):
        line = next(ln for ln in quoted.splitlines() if ln.strip().startswith(label + "  "))
        assert line[len(" " + label):].split()[0] == format_number(lookup(report, key)), label


def test_the_package_exports_inspect_part():
    import cam_workbench
    import cam_workbench.inspection

    assert cam_workbench.inspect_part is cam_workbench.inspection.inspect_part


# ---- the deviation's harmonics: the tolerance study's reverse on the measured part -------------------------
HARMONIC_WAVES = ((4 * UM, 5), (2 * UM, 11), (1 * UM, 23))


@pytest.mark.parametrize("name,amplitude_rel,total_rel", [("default", 1e-6, 0.005), ("oscillating", 1e-6, 0.005),
                                                          ("paper_fine", 1e-6, 0.005), ("flat", 1e-5, 0.02)])
def test_harmonics_are_the_injected_waves_and_predict_the_measured_motion(designs, name, amplitude_rel, total_rel):
    """Waves A·cos(nθ) injected along the normal at the cam angle of contact θ: the harmonics read
    from the smoothing fit are their amplitudes (measured: 2e-8 relative on the rollers, 4e-6 on the
    flat face) with phase 0, every other harmonic below 0.1 % of the smallest wave; the first-order
    acceleration error of their sum agrees with the measured motion's contact solve (measured: 0.2–0.3 %
    of the largest |Δa| on the rollers, 1.4 % on the flat face, whose gain the built curve's error moves
    most) — the first-order model's own accuracy (docs/tolerances.md)."""
    d = designs[name]
    pts, *_ = synthetic_part(d, 6000, seed=2, waves=HARMONIC_WAVES)
    res = inspect_design(d, pts, datum="bore_and_angle")
    h = res.harmonics.measured.harmonics
    for a, n in HARMONIC_WAVES:
        assert h[n].waves == n
        assert h[n].amplitude == pytest.approx(a, rel=amplitude_rel)
        assert abs(h[n].phase_deg) <= 1e-3
    injected = {n for _a, n in HARMONIC_WAVES}
    assert max(x.amplitude for x in h if x.waves not in injected) <= 1e-3 * UM
    measured = float(np.max(np.abs(res.motion.omega**2 * res.motion.error[2])))
    s = json.loads(json.dumps(res.summary()))
    predicted = s["harmonics"]["predicted_acceleration_error"]["max_abs"]
    assert predicted == pytest.approx(measured, rel=total_rel)
    assert predicted == res.harmonics.measured.peak_acceleration_error
    assert [x["waves"] for x in s["harmonics"]["largest"][:3]] == [5, 11, 23]
    assert "limit" not in s["harmonics"] and "tolerance" not in s["harmonics"]["largest"][0]


def test_harmonics_tolerance_is_the_tolerance_studys(designs):
    """With an acceleration limit, each listed harmonic's tolerance t(n) is the tolerance study's
    (``tolerance_study`` at cam.speed_rpm, computed here through the API), 'within' is 2A ≤ t(n), and
    the tightest is the chart's smallest over n = 1 … n_max."""
    from cam_workbench.tolerance import tolerance_study

    d = designs["default"]
    pts, *_ = synthetic_part(d, 4000, seed=13, waves=((3 * UM, 4), (1.5 * UM, 30)), noise=0.3 * UM)
    s = inspect_design(d, pts, datum="bore_and_angle", acceleration_limit=0.02).summary()["harmonics"]
    study = tolerance_study(d.spec, 0.02, s["max_waves"], design=d).summary()
    chart = study["chart"]["tolerance"]
    for h in s["largest"]:
        if h["waves"] >= 1:
            assert h["tolerance"] == chart[h["waves"] - 1]
            assert h["within_tolerance"] == (2 * h["amplitude"] <= h["tolerance"])
    assert s["limit"]["tightest"] == {k: study["tightest"][k] for k in ("waves", "tolerance", "governed_by")}
    assert s["limit"]["allowed_acceleration_error"] == study["allowed_acceleration_error"]
    assert s["limit"]["within"] == (s["predicted_acceleration_error"]["max_abs"] <= study["allowed_acceleration_error"])


def test_a_bad_acceleration_limit_is_refused(designs):
    pts, *_ = synthetic_part(designs["default"], 500)
    for bad in (0.0, 1.5, float("nan")):
        with pytest.raises(SpecError) as err:
            inspect_part(example_spec("default"), pts, acceleration_limit=bad)
        assert err.value.field == "acceleration_limit"


@pytest.mark.parametrize("pct", ["0", "101", "nan"])
def test_cli_bad_acceleration_limit_exit_2_and_write_nothing(tmp_path, pct):
    out = tmp_path / "out"
    res = cli("inspect", str(ROOT / "docs" / "examples" / "inspection_points.csv"), "--acceleration-limit", pct,
              "-o", str(out))
    assert res.returncode == 2 and "--acceleration-limit" in res.stderr and "Traceback" not in res.stderr
    assert not out.exists()


def test_cli_harmonics_printout_and_html_are_inspection_json(tmp_path, designs):
    """inspect --acceleration-limit: the harmonics table printed and in inspection.html holds
    inspection.json's ``harmonics.largest`` cells; its rows in the quantity table too."""
    from cam_workbench.exporters.inspection_report import harmonic_columns

    pts, *_ = synthetic_part(designs["default"], 3000, seed=14, waves=((3 * UM, 6), (1 * UM, 19)))
    csv = write_csv(tmp_path / "pts.csv", pts)
    out = tmp_path / "out"
    res = cli("inspect", str(csv), "--acceleration-limit", "5", "-o", str(out))
    assert res.returncode == 0, res.stderr
    report = json.loads((out / "inspection.json").read_text())
    listed = report["harmonics"]["largest"]
    columns = harmonic_columns(report)
    assert [c[1] for c in columns][-2:] == ["tolerance", "within_tolerance"]
    printed = [[c.strip() for c in line.split("│")[1:-1]] for line in res.stdout.splitlines()
               if line.startswith("│") and len(line.split("│")) == len(columns) + 2]
    assert printed == [[format_number(h[k]) for _h, k, _u in columns] for h in listed]
    labels = {line.split("│")[1].strip(): line.split("│")[2].strip() for line in res.stdout.splitlines()
              if len(line.split("│")) == 6}
    for label, key, _unit, _at in rows(report):
        if key.startswith("harmonics."):
            assert labels[label] == format_number(lookup(report, key)), label
    page = (out / "inspection.html").read_text()
    for i, h in enumerate(listed):
        for _h, k, _u in columns:
            v = h[k]
            data = "true" if v is True else "false" if v is False else repr(v)
            assert f'data-key="harmonics.largest.{i}.{k}" data-value="{data}"' in page
    assert f'data-key="harmonics.predicted_acceleration_error.max_abs" data-value="' \
           f'{report["harmonics"]["predicted_acceleration_error"]["max_abs"]!r}"' in page


def test_docs_cli_md_names_every_option_of_inspect():
    from cam_workbench.commands import parsers

    sub = next(a for a in parsers.parser()._actions if a.dest == "command").choices["inspect"]
    text = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    entry = text[text.index("- `inspect "):]
    entry = entry[:entry.index("\n- ")]
    for action in sub._actions:
        own = [o for o in action.option_strings if o.startswith("--") and o not in (
            "--help", "--example", "--set", "--replace", "--output", "--source")]
        for opt in own:
            assert f"`{opt}" in entry, opt

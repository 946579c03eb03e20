"""The cylindrical cam driving an oscillating roller (example ``cylindrical_oscillating``), against
computations written here from the arm's geometry (docs/bodies.md, generators/bodies/cylinder_path.py):

* the lift: the cycloidal law in closed form (degrees of arm angle), not the project's motion code;
* the roller centre in the developed pitch plane: pivot (−d, Z_p) + L·(cos β, sin β),
  β = arccos(d/L) + (s − s_max/2)·π/180, Z_p = L_cyl/2 − L sin β_m cos(h/2); in the cam frame at
  radius ρ (ccw): C_ρ(θ) = (ρ(π/2 − θ) + (ρ/R_p)·u, Z);
* wall points at exactly w/2 from C_ρ (dense sampling + scipy's bounded minimisation), at several ρ;
* the volume π(R_o² − r²)L − w∫ℓ(ρ)dρ, ℓ = ∫|C_ρ′|dθ by scipy.integrate.quad with C_ρ′ differentiated
  here by hand, against the design's and OCCT's volumes;
* the pressure angle between the groove's normal and the roller centre's motion perpendicular to the arm;
* the solid valid, STEP re-read, the CLI's build/report/gcode, the program through rs274;
* bad input: the arm that cannot reach, the arm turning past 90°, the cylinder too short.
"""
from __future__ import annotations

import copy
import json
import math
import subprocess
import sys

import numpy as np
import pytest
from scipy import integrate, optimize

from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.spec.examples import EXAMPLES

from .conftest import ROOT, requires_ocp
from .rs274 import polyline_distance, requires_rs274

RP, RO, RB, LCYL, BORE = 40.0, 44.0, 36.0, 50.0, 10.0
W2 = 5.0 + 0.05 / 2
D, ARM = 50.0, 50.0                   # pivot_distance, arm_length
H = 30.0                              # arm swing [deg]
BETA_M = math.acos(D / ARM)
ZP = LCYL / 2 - ARM * math.sin(BETA_M) * math.cos(math.radians(H) / 2)


def lift(theta):
    """s [deg], s′ [deg/rad] of the example: dwell 30, cycloidal rise 150 by 30, dwell 30, cycloidal return 150."""
    t = np.mod(np.asarray(theta, dtype=float), 2 * np.pi)
    deg = np.rad2deg(t)
    beta = np.deg2rad(150.0)
    s = np.zeros_like(t)
    ds = np.zeros_like(t)
    rise = (deg >= 30) & (deg < 180)
    x = (t - np.deg2rad(30)) / beta
    s = np.where(rise, H * (x - np.sin(2 * np.pi * x) / (2 * np.pi)), s)
    ds = np.where(rise, H / beta * (1 - np.cos(2 * np.pi * x)), ds)
    top = (deg >= 180) & (deg < 210)
    s = np.where(top, H, s)
    ret = deg >= 210
    x = (t - np.deg2rad(210)) / beta
    s = np.where(ret, H * (1 - (x - np.sin(2 * np.pi * x) / (2 * np.pi))), s)
    ds = np.where(ret, -H / beta * (1 - np.cos(2 * np.pi * x)), ds)
    return s, ds


def arm(theta):
    """β, β′ [rad, rad/rad] and the roller centre (u, Z) with (u′, Z′) in the developed pitch plane."""
    s, ds = lift(theta)
    b = BETA_M + np.deg2rad(s - H / 2)
    db = np.deg2rad(ds)
    return b, db, -D + ARM * np.cos(b), ZP + ARM * np.sin(b), -ARM * np.sin(b) * db, ARM * np.cos(b) * db


def centre_line(rho, theta, sense=1):
    """C_ρ(θ) and C_ρ′ (sense +1: ccw cam, −1: cw — the cam surface under the roller moves the other
    way round, so the roller's u and the cam angle both change sign in the cam frame's x)."""
    _, _, u, z, du, dz = arm(theta)
    k = rho / RP
    return sense * (rho * (np.pi / 2 * sense - theta) + k * u), z, -sense * k * (RP - du), dz


def wall_distance(point, sense=1):
    """(distance of a 3D point from C_ρ at its own radius) − w/2, and the side (+1: above C_ρ)."""
    x, y, z = point
    rho = math.hypot(x, y)
    psi = math.atan2(y, x)
    th0 = sense * (np.pi / 2 - psi)
    grid = th0 + np.linspace(-0.8, 0.8, 4001)

    def d2v(th):
        cx, cz, _, _ = centre_line(rho, th, sense)
        dx = rho * ((cx / rho - psi + np.pi) % (2 * np.pi) - np.pi)
        return dx ** 2 + (cz - z) ** 2

    k = int(np.argmin(d2v(grid)))
    res = optimize.minimize_scalar(lambda t: float(d2v(np.atleast_1d(t))[0]),
                                   bounds=(grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]),
                                   method="bounded", options={"xatol": 1e-13})
    _, cz, _, _ = centre_line(rho, np.atleast_1d(res.x), sense)
    return math.sqrt(res.fun) - W2, (1 if z > cz[0] else -1)


@pytest.fixture(scope="module")
def design():
    return design_cam(CamSpec.from_dict(EXAMPLES["cylindrical_oscillating"]))


def test_layout_travel_centred_and_report(design):
    b = design.body_report
    assert (b["pitch_radius"], b["outer_radius"], b["bottom_radius"], b["length"]) == (RP, RO, RB, LCYL)
    zlo, zhi = ZP + ARM * math.sin(BETA_M - math.radians(H / 2)), ZP + ARM * math.sin(BETA_M + math.radians(H / 2))
    assert b["lift_range"] == pytest.approx([zlo, zhi], abs=1e-12)
    assert (zlo + zhi) / 2 == pytest.approx(LCYL / 2, abs=1e-12)
    assert zhi - zlo == pytest.approx(2 * D * math.sin(math.radians(H / 2)), abs=1e-12)
    s = design.summary()
    assert s["follower"]["motion"] == "oscillating" and s["motion"]["lift_unit"] == "deg"
    assert s["checks"]["passed"]


def test_pressure_angle(design):
    """Between the groove's normal (Z′, q) and the roller's motion (−sin β, cos β), in the fixed
    developed pitch plane; the largest over a dense grid."""
    th = np.linspace(0, 2 * np.pi, 200001)
    b, db, _, _, du, dz = arm(th)
    n = np.stack([dz, RP - du])
    t = np.stack([-np.sin(b), np.cos(b)])
    phi = np.degrees(np.arctan2(np.abs(n[0] * t[1] - n[1] * t[0]), np.sum(n * t, axis=0)))
    pa = design.summary()["pressure_angle"]
    assert pa["max_deg"] == pytest.approx(phi.max(), abs=1e-5)
    assert pa["at_deg"] == pytest.approx(math.degrees(th[np.argmax(phi)]), abs=0.2)
    # the closed form of the docstring, at the same points
    closed = np.degrees(np.arctan(np.abs(ARM * db + RP * np.sin(b)) / (RP * np.cos(b))))
    assert np.max(np.abs(closed - phi)) < 1e-10


def test_wall_points_at_half_width(design):
    """design.wall_points at several radii: exactly w/2 from the test's C_ρ, on their side."""
    th = np.linspace(0, 2 * np.pi, 37)[:-1] + 0.013
    worst = 0.0
    for rho in (RB, 37.1, RP, 42.3, RO):
        for side in (-1, 1):
            pts = design.wall_points(side, th, np.full(th.shape, rho))
            assert np.allclose(np.hypot(pts[:, 0], pts[:, 1]), rho, atol=1e-12)
            for p in pts:
                err, sd = wall_distance(p)
                assert sd == side
                worst = max(worst, abs(err))
    assert worst <= 1e-9, worst
    # the project's own distance (Newton on C_ρ) agrees on the same points
    pts = design.wall_points(1, th, np.full(th.shape, 41.0))
    assert np.max(design.wall_distance_error(1, pts)) <= 1e-9


def test_wall_surface_data_against_the_exact_walls(design):
    worst = 0.0
    for wall in design.body.walls:
        a, b = wall.u_range
        u = np.linspace(a, b, 9)[1:-1] + 0.37 * (b - a) / 8
        for rho in (RB, 39.3, RO):
            pts = wall.evaluate(u, np.full(u.shape, rho))
            for p in pts:
                err, side = wall_distance(p)
                assert side == wall.side
                worst = max(worst, abs(err))
    assert worst <= 1e-6, worst
    assert design.body_report["wall_fit_error"]["value"] <= 1e-6


def test_undercut_curvature(design):
    """C_ρ's radius of curvature (the undercut check) against central differences of the test's C_ρ′."""
    from cam_workbench.generators.bodies.cylindrical import developed_curvature_radius

    th = np.deg2rad(np.array([40.0, 77.0, 105.0, 150.0, 171.0, 222.0, 300.0, 347.0]))
    h = 1e-5
    for rho in (RB, RO):
        _, _, dx, dz = centre_line(rho, th)
        _, _, dxp, dzp = centre_line(rho, th + h)
        _, _, dxm, dzm = centre_line(rho, th - h)
        d2x, d2z = (dxp - dxm) / (2 * h), (dzp - dzm) / (2 * h)
        expect = np.hypot(dx, dz) ** 3 / np.abs(dx * d2z - dz * d2x)
        got = developed_curvature_radius(design.layout, design.program, rho, th)
        assert np.allclose(got, expect, rtol=1e-6), (got, expect)
    rc = design.body_report["min_developed_curvature_radius"]
    assert rc["value"] > W2 and rc["at_radius"] == RB


def test_cw_cam_mirrors_the_ccw_one(design):
    """direction = "cw": the walls at w/2 from the cw centre line, the volume the ccw one's (mirror image)."""
    d = copy.deepcopy(EXAMPLES["cylindrical_oscillating"])
    d["cam"]["direction"] = "cw"
    cw = design_cam(CamSpec.from_dict(d))
    th = np.linspace(0, 2 * np.pi, 25)[:-1] + 0.021
    worst = 0.0
    for rho in (RB, RP, RO):
        for side in (-1, 1):
            for p in cw.wall_points(side, th, np.full(th.shape, rho)):
                err, sd = wall_distance(p, sense=-1)
                assert sd == side
                worst = max(worst, abs(err))
    assert worst <= 1e-9, worst
    assert cw.volume == pytest.approx(design.volume, rel=1e-12)
    assert cw.summary()["pressure_angle"]["max_deg"] == pytest.approx(design.summary()["pressure_angle"]["max_deg"],
                                                                      abs=1e-9)


def _groove_closed_form():
    def ell(rho):
        total = 0.0
        for a, b in ((0, 30), (30, 180), (180, 210), (210, 360)):
            def speed(t):
                _, _, dx, dz = centre_line(rho, np.array([t]))
                return float(math.hypot(dx[0], dz[0]))
            total += integrate.quad(speed, math.radians(a), math.radians(b), epsabs=1e-12, epsrel=1e-13)[0]
        return total
    return 2 * W2 * integrate.quad(ell, RB, RO, epsabs=1e-9, epsrel=1e-12)[0]


def test_volume_closed_form(design):
    v = math.pi * (RO ** 2 - BORE ** 2) * LCYL - _groove_closed_form()
    assert design.volume == pytest.approx(v, rel=1e-10)


@requires_ocp
def test_solid_valid_volume_walls_and_step(design, tmp_path):
    from cam_workbench.kernel import solids as occ_build
    from cam_workbench.kernel.step import read_step, write_step

    shape = occ_build.cam_solid(design)
    assert occ_build.is_valid(shape) and occ_build.count_solids(shape) == 1
    v = math.pi * (RO ** 2 - BORE ** 2) * LCYL - _groove_closed_form()
    rel = abs(occ_build.kernel_volume(shape) / v - 1)
    assert rel <= 1e-6, rel
    measured = occ_build.body_measures(design, shape)["wall_error"]
    assert measured["value"] <= 1e-6 and measured["faces"] == len(design.body.walls)
    path = tmp_path / "cylosc.step"
    write_step(shape, path, "mm")
    back = read_step(path, "mm")
    assert occ_build.is_valid(back) and occ_build.count_solids(back) == 1
    # OCCT integrates the re-read B-spline faces afresh: within its accuracy (~1e-6) of the exact volume
    assert abs(occ_build.kernel_volume(back) / v - 1) <= 1e-6
    from .test_cylindrical import bspline_face_points

    pts = bspline_face_points(back, 6, 5, RB, RO)
    worst = max(abs(wall_distance(q)[0]) for q in pts)
    assert len(pts) > 50 and worst <= 1e-6, (len(pts), worst)


@requires_rs274
def test_gcode_through_rs274(design, tmp_path):
    """Every cutting pass's tool-centre points lie |offset| from the test's developed pitch curve C_Rp."""
    from cam_workbench.exporters.machining_cylindrical import cylindrical_program
    from cam_workbench.generators.machining.cylindrical import cylindrical_path

    from .rs274 import run_rs274

    path = cylindrical_path(design)
    run = run_rs274(cylindrical_program(design, path), tmp_path, path.tool_number, 2 * path.tool_radius)
    assert run.units == "mm"
    from .test_cylindrical import _feeds

    feeds = _feeds(run.calls)
    th = np.linspace(-0.3, 2 * np.pi + 0.3, 400001)
    cx, cz, _, _ = centre_line(RP, th)
    worst = 0.0
    for level, zl in enumerate((RO - 4.0, RB), start=1):
        for k, p in enumerate(path.passes, start=1):
            tag = f"level {level}, pass {k}: {p.role.replace('_', ' ')}"
            cut = [f for f in feeds if f[1].startswith(tag) and f[0] == "STRAIGHT_FEED" and abs(f[3] - zl) < 1e-4]
            assert len(cut) > 300, (tag, len(cut))
            a = np.array([c[4] for c in cut])
            x = np.array([c[2] for c in cut])
            assert a.max() - a.min() == pytest.approx(360.0, abs=1e-3)
            xd = RP * (np.pi / 2 - np.mod(np.pi / 2 - np.deg2rad(90.0 - a), 2 * np.pi))
            dist = polyline_distance(xd + 1j * x, cx + 1j * cz)
            err = float(np.max(np.abs(dist - abs(p.offset))))
            worst = max(worst, err)
            assert err <= 1e-4, (tag, err)
            if p.role != "rough":
                assert abs(p.offset) + path.tool_radius == pytest.approx(W2, abs=1e-12)
    assert path.summary()["max_chord_error"] <= path.chord_tolerance


@requires_ocp
def test_cli_build_report_gcode(tmp_path):
    for cmd in ("build", "report", "gcode"):
        out = tmp_path / cmd
        res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", cmd, "--example", "cylindrical_oscillating",
                              "-o", str(out)], capture_output=True, text=True, cwd=ROOT)
        assert res.returncode == 0, (cmd, res.stderr)
    rep = json.loads((tmp_path / "build" / "report.json").read_text())
    assert rep["body"]["wall_error"]["value"] <= 1e-6
    assert rep["solid"]["valid"] and abs(rep["solid"]["volume_rel_diff"]) <= 1e-6
    assert (tmp_path / "build" / "cam.step").stat().st_size > 0
    text = (tmp_path / "gcode").read_text() if (tmp_path / "gcode").is_file() else \
        next((tmp_path / "gcode").glob("*.nc")).read_text()
    assert "oscillating roller" in text and "30 deg of arm" in text


def _osc(**changes):
    d = copy.deepcopy(EXAMPLES["cylindrical_oscillating"])
    for path, value in changes.items():
        sec, key = path.split(".")
        d[sec][key] = value
    return d


@pytest.mark.parametrize("changes, message", [
    ({"follower.arm_length": 40.0}, "follower.arm_length: the arm cannot reach"),
    ({"follower.pivot_distance": 5.0}, r"motion\[1\].lift: the arm would turn past the perpendicular"),
    ({"cam.length": 40.0}, "cam.length: the roller's axial travel"),
])
def test_refusals(changes, message):
    with pytest.raises(SpecError, match=message):
        CamSpec.from_dict(_osc(**changes))


def test_spec_round_trip():
    spec = CamSpec.from_dict(EXAMPLES["cylindrical_oscillating"])
    assert CamSpec.from_dict(spec.to_dict()) == spec


# ---- the other commands: check, dxf, dynamics, ecam -------------------------------------------------
def _cli(*args):
    return subprocess.run([sys.executable, "-m", "cam_workbench.cli", *args], capture_output=True, text=True,
                          cwd=ROOT)


def test_check_cli_pressure_angle_from_the_arm(tmp_path):
    """`check` of the arm on a cylinder: the pressure angle at R_p is the angle between C′ and the
    roller centre's motion perpendicular to the arm, computed here from the arm (dense sampling)."""
    res = _cli("check", "--example", "cylindrical_oscillating", "-o", str(tmp_path / "o"))
    rep = json.loads((tmp_path / "o" / "report.json").read_text())
    assert res.returncode == (0 if rep["checks"]["passed"] else 3), res.stderr
    th = np.linspace(0, 2 * np.pi, 200001)
    b, db, u, z, du, dz = arm(th)
    # groove normal (developed, fixed frame) ∝ (Z′, R_p − u′); the motion ∝ (−sin β, cos β)
    nu, nz = dz, RP - du
    tu, tz = -np.sin(b), np.cos(b)
    phi = np.degrees(np.arctan2(nu * tz - nz * tu, nu * tu + nz * tz))
    assert rep["checks"]["results"]["pressure_angle"]["value"] == pytest.approx(float(np.max(np.abs(phi))), abs=2e-3)


def test_dxf_walls_follow_the_arm(tmp_path):
    """The developed walls in the DXF (ezdxf evaluates its splines) lie at w/2 from C_{R_o} computed
    here from the arm, within the error the command reports."""
    import ezdxf

    out = tmp_path / "c.dxf"
    res = _cli("dxf", "--example", "cylindrical_oscillating", "-o", str(out))
    assert res.returncode == 0, res.stderr
    doc = ezdxf.readfile(str(out))
    assert not doc.audit().has_errors
    line = [ln for ln in res.stdout.splitlines() if "max fit error" in ln][0]
    err = float(line.split("max fit error ")[1].split(" ")[0])
    assert 0 < err < 1e-6
    grid = np.linspace(-0.3, 2 * np.pi + 0.3, 60001)
    cx, cz, _, _ = centre_line(RO, grid)
    for layer, side in (("WALL_LOWER", -1), ("WALL_UPPER", 1)):
        pts = []
        for sp in doc.modelspace().query(f'SPLINE[layer=="{layer}"]'):
            tool = sp.construction_tool()
            pts.append(np.array([(p.x, p.y) for p in tool.points(np.linspace(tool.knots()[0], tool.knots()[-1], 15))]))
        pts = np.concatenate(pts)
        for x, zz in pts:
            k = int(np.argmin((cx - x) ** 2 + (cz - zz) ** 2))

            def d2(t, x=x, zz=zz):
                ax, az, _, _ = centre_line(RO, np.atleast_1d(t))
                return float((ax[0] - x) ** 2 + (az[0] - zz) ** 2)

            r = optimize.minimize_scalar(d2, bounds=(grid[k - 1], grid[k + 1]), method="bounded",
                                         options={"xatol": 1e-14})
            assert abs(math.sqrt(r.fun) - W2) <= err * 1.01 + 1e-9, (layer, x, zz)
            assert (zz > centre_line(RO, np.atleast_1d(r.x))[1][0]) == (side > 0)


def test_dynamics_refused_naming_follower_motion_and_ecam_works(tmp_path):
    res = _cli("dynamics", "--example", "cylindrical_oscillating", "-o", str(tmp_path / "d"))
    assert res.returncode == 2 and res.stderr.strip().startswith("error: follower.motion"), res.stderr
    assert "Traceback" not in res.stderr and not (tmp_path / "d").exists()
    e = _cli("ecam", "--example", "cylindrical_oscillating", "-o", str(tmp_path / "e.csv"))
    assert e.returncode == 0, e.stderr
    assert (tmp_path / "e.csv").read_text().count("\n") > 100

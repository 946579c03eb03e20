"""The cylindrical (barrel) cam, against computations written here:

* the lift: the cycloidal law in closed form, s = h(x − sin 2πx / 2π), x = (θ − θ₀)/β — not the
  project's motion code;
* the exact wall at radius ρ: the developed centre line C_ρ(θ) = (ρ(π/2 − θ), z₀ + s(θ)) (ccw cam)
  offset by ±w/2, its distance from a point found by dense sampling plus scipy's bounded scalar
  minimisation (not the project's Newton iteration);
* the volume: π(R_o² − r²)L − w ∫ℓ(ρ)dρ with ℓ(ρ) = ∫√(ρ² + s′²)dθ by scipy.integrate.quad (the band
  between offsets ±w/2 of a curve has area w × its length), against the solid's OCCT volume;
* the solid valid, one solid, STEP written and re-read to the same volume;
* the G-code through LinuxCNC's rs274: the tool-centre points on the developed pitch curve and its
  offsets at the pitch radius, the walls' passes at w/2 − R_t;
* bad input: each refusal names its field, exit 2 from the CLI, nothing written.
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

# the example: R_p 40, R_o 44 (mid-depth pitch), R_b 36, L 60, bore 20, r 5, c 0.05
RP, RO, RB, L, BORE = 40.0, 44.0, 36.0, 60.0, 10.0
W2 = 5.0 + 0.05 / 2
H = 20.0
Z0 = (L - H) / 2


def cyl_dict(**changes):
    d = copy.deepcopy(EXAMPLES["cylindrical"])
    for path, value in changes.items():
        sec, key = path.split(".")
        if value is None:
            d[sec].pop(key, None)
        else:
            d.setdefault(sec, {})[key] = value
    return d


def lift(theta):
    """s(θ), s′(θ) of the example: dwell 30, cycloidal rise 120 by 20, dwell 60, cycloidal return 120."""
    t = np.mod(np.asarray(theta, dtype=float), 2 * np.pi)
    deg = np.rad2deg(t)
    beta = np.deg2rad(120.0)
    s = np.zeros_like(t)
    ds = np.zeros_like(t)
    rise = (deg >= 30) & (deg < 150)
    x = (t - np.deg2rad(30)) / beta
    s = np.where(rise, H * (x - np.sin(2 * np.pi * x) / (2 * np.pi)), s)
    ds = np.where(rise, H / beta * (1 - np.cos(2 * np.pi * x)), ds)
    top = (deg >= 150) & (deg < 210)
    s = np.where(top, H, s)
    ret = (deg >= 210) & (deg < 330)
    x = (t - np.deg2rad(210)) / beta
    s = np.where(ret, H * (1 - (x - np.sin(2 * np.pi * x) / (2 * np.pi))), s)
    ds = np.where(ret, -H / beta * (1 - np.cos(2 * np.pi * x)), ds)
    return s, ds


def centre_line(rho, theta):
    """Developed C_ρ(θ) of the ccw example: x = ρ(π/2 − θ), z = z₀ + s."""
    s, _ = lift(theta)
    return rho * (np.pi / 2 - theta), Z0 + s


def wall_distance(point):
    """Distance of a 3D point from the developed centre line at its own radius, minus w/2, and the
    side of the wall it lies on (+1 above the line)."""
    x, y, z = point
    rho = math.hypot(x, y)
    psi = math.atan2(y, x)
    th0 = np.pi / 2 - psi
    grid = th0 + np.linspace(-0.5, 0.5, 2001)

    def d2v(th):
        _, cz = centre_line(rho, th)
        dx = rho * (((np.pi / 2 - th) - psi + np.pi) % (2 * np.pi) - np.pi)
        return dx ** 2 + (cz - z) ** 2

    def d2(th):
        return float(d2v(np.atleast_1d(th))[0])

    k = int(np.argmin(d2v(grid)))
    res = optimize.minimize_scalar(d2, bounds=(grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]),
                                   method="bounded", options={"xatol": 1e-13})
    _, cz = centre_line(rho, np.atleast_1d(res.x))
    return math.sqrt(res.fun) - W2, (1 if z > cz[0] else -1)


@pytest.fixture(scope="module")
def design():
    return design_cam(CamSpec.from_dict(EXAMPLES["cylindrical"]))


def test_layout_and_pressure_angle(design):
    b = design.body_report
    assert (b["pitch_radius"], b["outer_radius"], b["bottom_radius"], b["length"]) == (RP, RO, RB, L)
    assert b["lift_range"] == [Z0, Z0 + H]
    # tan φ = s′/R_p: the cycloidal rise's largest s′ = 2h/β at its middle (θ = 90°)
    smax = 2 * H / np.deg2rad(120)
    pa = design.summary()["pressure_angle"]
    assert pa["max_deg"] == pytest.approx(math.degrees(math.atan(smax / RP)), abs=1e-6)
    assert pa["at_deg"] == pytest.approx(90.0, abs=0.1)
    assert pa["bottom_max_deg"] == pytest.approx(math.degrees(math.atan(smax / RB)), abs=1e-6)


def test_wall_surface_data_against_the_exact_walls(design):
    """The B-spline wall data, sampled off the interpolation nodes, at several radii."""
    worst = 0.0
    for wall in design.body.walls:
        a, b = wall.u_range
        u = np.linspace(a, b, 13)[1:-1] + 0.37 * (b - a) / 12
        for rho in (RB, 38.3, 42.7, RO):
            pts = wall.evaluate(u, np.full(u.shape, rho))
            for p in pts:
                assert math.hypot(p[0], p[1]) == pytest.approx(rho, abs=1e-6)
                err, side = wall_distance(p)
                assert side == wall.side
                worst = max(worst, abs(err))
    assert worst <= 1e-6, worst


def test_volume_closed_form(design):
    def ell(rho):
        return sum(integrate.quad(lambda t: math.hypot(rho, float(lift(t)[1])), math.radians(a), math.radians(b),
                                  epsabs=1e-12, epsrel=1e-13)[0] for a, b in ((30, 150), (210, 330))) \
            + rho * math.radians(120)
    groove = 2 * W2 * integrate.quad(ell, RB, RO, epsabs=1e-10, epsrel=1e-12)[0]
    v = math.pi * (RO ** 2 - BORE ** 2) * L - groove
    assert design.volume == pytest.approx(v, rel=1e-10)


@requires_ocp
def test_solid_valid_volume_walls_and_step(design, tmp_path):
    from cam_workbench.kernel import solids as occ_build
    from cam_workbench.kernel import ocp as occ
    from cam_workbench.kernel.step import read_step, write_step

    shape = occ_build.cam_solid(design)
    assert occ_build.is_valid(shape) and occ_build.count_solids(shape) == 1
    assert occ_build.kernel_volume(shape) == pytest.approx(design.volume, rel=2e-5)
    # bounding box: the cylinder
    box = occ.Bnd_Box()
    occ.add_to_box(shape, box, optimal=True)
    lo = occ.box_limits(box)
    assert np.allclose(lo, (-RO, -RO, 0, RO, RO, L), atol=1e-5)
    path = tmp_path / "cyl.step"
    write_step(shape, path, "mm")
    back = read_step(path, "mm")
    assert occ_build.is_valid(back) and occ_build.count_solids(back) == 1
    assert occ_build.kernel_volume(back) == pytest.approx(occ_build.kernel_volume(shape), rel=1e-7)
    # the re-read wall faces: points on them at the exact offset, checked here independently
    pts = bspline_face_points(back, 7, 7, RB, RO)
    worst = max(abs(wall_distance(q)[0]) for q in pts)
    assert len(pts) > 100 and worst <= 1e-6, (len(pts), worst)


def bspline_face_points(shape, nu: int, nv: int, r0: float, r1: float) -> list[tuple[float, float, float]]:
    """Points of every B-spline face of ``shape`` (OCCT's evaluator) on an nu × nv grid of its
    parameters, those between the radii r0 and r1 (the groove's walls)."""
    from cam_workbench.kernel import ocp as occ

    out = []
    fx = occ.TopExp_Explorer(shape, occ.TopAbs_FACE)
    while fx.More():
        surf = occ.BRepAdaptor_Surface(occ.topods_face(fx.Current()))
        if surf.GetType() == occ.GeomAbs_BSplineSurface:
            for a in np.linspace(surf.FirstUParameter(), surf.LastUParameter(), nu):
                for b in np.linspace(surf.FirstVParameter(), surf.LastVParameter(), nv):
                    q = surf.Value(a, b)
                    if r0 - 1e-9 <= math.hypot(q.X(), q.Y()) <= r1 + 1e-9:
                        out.append((q.X(), q.Y(), q.Z()))
        fx.Next()
    return out


def _feeds(calls):
    """(x, z, a) of every STRAIGHT_FEED/TRAVERSE with the comment before it."""
    out, tag = [], ""
    for name, args in calls:
        if name == "COMMENT":
            text = args.strip().strip('"')
            if not text.startswith("interpreter:"):
                tag = text
        elif name in ("STRAIGHT_FEED", "STRAIGHT_TRAVERSE"):
            v = [float(a) for a in args.split(",")]
            out.append((name, tag, v[0], v[2], v[3]))
    return out


@requires_rs274
def test_gcode_through_rs274(design, tmp_path):
    from cam_workbench.exporters.machining_cylindrical import cylindrical_program
    from cam_workbench.generators.machining.cylindrical import cylindrical_path

    from .rs274 import run_rs274

    path = cylindrical_path(design)
    run = run_rs274(cylindrical_program(design, path), tmp_path, path.tool_number, 2 * path.tool_radius)
    assert run.units == "mm"
    rt = path.tool_radius
    assert rt < W2 and path.passes[0].offset == 0
    assert [p.role for p in path.passes][-2:] == ["lower_wall", "upper_wall"]
    feeds = _feeds(run.calls)
    for level, zl in enumerate((RO - 4.0, RB), start=1):       # machining.passes = 2
        for k, p in enumerate(path.passes, start=1):
            tag = f"level {level}, pass {k}: {p.role.replace('_', ' ')}"
            cut = [f for f in feeds if f[1].startswith(tag) and f[0] == "STRAIGHT_FEED" and abs(f[3] - zl) < 1e-4]
            assert len(cut) > 300, (tag, len(cut))
            a = np.array([c[4] for c in cut])
            x = np.array([c[2] for c in cut])
            assert a.max() - a.min() == pytest.approx(360.0, abs=1e-3)        # one full turn
            # the tool centre line at A: cam-frame angle ψ = 90° − A; developed at the pitch radius it
            # must lie |offset| from C_Rp, on its side: nearest point of a dense C_Rp
            th = np.linspace(-0.3, 2 * np.pi + 0.3, 400001)
            cx, cz = centre_line(RP, th)
            # developed x of the points, brought into the curve's range (period 2πR_p)
            xd = RP * (np.pi / 2 - np.mod(np.pi / 2 - np.deg2rad(90.0 - a), 2 * np.pi))
            dist = polyline_distance(xd + 1j * x, cx + 1j * cz)
            # rs274 prints 4 decimals: X to 5e-5, A to 5e-5° (3.5e-5 mm at R_p)
            assert np.max(np.abs(dist - abs(p.offset))) <= 1e-4, tag
            if p.role != "rough":
                assert abs(p.offset) + rt == pytest.approx(W2, abs=1e-12)


def _cli(tmp_path, d):
    from cam_workbench.generators.spec import dict_to_toml

    (tmp_path / "c.toml").write_text(dict_to_toml(d))
    return subprocess.run([sys.executable, "-m", "cam_workbench.cli", "build", str(tmp_path / "c.toml"), "-o",
                           str(tmp_path / "out")], capture_output=True, text=True, cwd=ROOT)


@pytest.mark.parametrize("changes, message", [
    ({"follower.kind": "knife", "follower.roller_radius": None}, "follower.kind: a cylindrical cam needs a roller"),
    ({"cam.length": 35.0}, "cam.length: the lift range 20 plus the groove width 10.05"),
    ({"cam.outer_diameter": 88.0, "groove.depth": 33.0}, "groove.depth: the groove's bottom (radius 11)"),
    ({"groove.depth": None}, "groove.depth: is required for a cylindrical cam"),
    ({"cam.cylinder_radius": None}, "cam.cylinder_radius: is required"),
    ({"cam.length": None}, "cam.length: is required"),
    ({"cam.outer_diameter": 100.0}, "cam.outer_diameter: the pitch radius"),
    ({"cam.thickness": 12.0}, "cam.thickness: is the cylinder's length"),
    ({"follower.offset": 3.0}, "follower.offset: does not apply to a cylindrical cam"),
    ({"machining.tool_radius": 6.0}, "machining.tool_radius: must be < half the groove width"),
])
def test_refusals_through_the_cli(tmp_path, changes, message):
    d = cyl_dict(**changes)
    res = _cli(tmp_path, d)
    assert res.returncode == 2, res.stderr
    assert message in res.stderr, res.stderr
    assert "Traceback" not in res.stderr and not (tmp_path / "out").exists()


def test_oscillating_arm_that_cannot_reach_refused():
    """Oscillating followers are accepted (tests/test_cylindrical_oscillating.py); this arm is too short."""
    d = cyl_dict(**{"follower.motion": "oscillating", "follower.pivot_distance": 60.0, "follower.arm_length": 40.0})
    with pytest.raises(SpecError, match="follower.arm_length: the arm cannot reach"):
        CamSpec.from_dict(d)


def test_cylinder_fields_refused_on_other_bodies():
    from cam_workbench.generators.spec import DEFAULT_SPEC_DICT

    d = copy.deepcopy(DEFAULT_SPEC_DICT)
    d["cam"]["length"] = 50.0
    with pytest.raises(SpecError, match='cam.length: applies to cylindrical cams only'):
        CamSpec.from_dict(d)


def test_spec_round_trip():
    spec = CamSpec.from_dict(EXAMPLES["cylindrical"])
    assert spec.cam.base_radius == RP and spec.cam.thickness == L
    assert CamSpec.from_dict(spec.to_dict()) == spec


@requires_ocp
def test_cli_build_example(tmp_path):
    res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "build", "--example", "cylindrical", "-o",
                          str(tmp_path / "out")], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    rep = json.loads((tmp_path / "out" / "report.json").read_text())
    body = rep["body"]
    assert body["kind"] == "cylindrical"
    assert body["wall_error"]["value"] <= 1e-6 and body["wall_error"]["unit"] == "mm"
    assert rep["solid"]["valid"] and abs(rep["solid"]["volume_rel_diff"]) < 2e-5
    assert {"step", "gcode", "report", "html"} <= set(rep["files"])
    assert (tmp_path / "out" / "cam.step").stat().st_size > 0 and (tmp_path / "out" / "cam.nc").exists()

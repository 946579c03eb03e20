"""A cylindrical cam whose motion's velocity jumps at a junction (the API combination fuzzer, seed 12):
the groove's developed centre line turns a corner there, the walls — offsets along the normals of
the two segments — part, and the solid built from them was valid, one solid and 23 % short of the
exact volume.  Held here against computations written for the test:

* the corner: where it is (the sum of the spans before it), the constant-velocity stroke's V in closed
  form (V = h/(β − b/2) with one blend from rest), the walls' parting 2·(w/2)·sin(α/2), α = atan(V/R_b)
  — refused (GeometryError "undercut" with the cam angle and the field that removes it), its checks
  failing under ``check`` (undercut 0 at the corner, continuity C0), through the API and the CLI (exit
  2, nothing written; ``check`` exit 3);
* its neighbours: the blend at the other end, no blend, a bore, a shallower groove, cw, an
  oscillating arm, a velocity given against a dwell — the same corner, whatever the depth or the bore;
* the fix (the stroke blended at its end too): built, its volume against π R_o² L − w∫ℓ(ρ)dρ with
  ℓ(ρ) = ∫√(ρ² + s′²)dθ by scipy's quad over the lift written here (cycloid, the blended stroke
  s′ = V(3x² − 2x³), the degree-6 return through its point, solved here), and OCCT's solid to 1e-9;
* the groove volume of laws made of pieces (modified trapezoid, blends, a table, a B-spline lift)
  against scipy's quad with the pieces' ends as break points.
"""
from __future__ import annotations

import copy
import json
import math
import subprocess
import sys

import numpy as np
import pytest
from scipy import integrate

from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import GeometryError
from cam_workbench.generators.spec import CamSpec, dict_to_toml
from cam_workbench.generators.spec.examples import EXAMPLES

from .conftest import ROOT, requires_ocp

#: the fuzzer's cam (tests/combinations, seed 12)
SEED12 = {
    "units": "mm",
    "cam": {"body": "cylindrical", "cylinder_radius": 35.69945704190153, "length": 24.870149748674525,
            "bore_diameter": 0.0, "direction": "ccw", "speed_rpm": 30.0, "outer_diameter": 74.43620341680123},
    "follower": {"kind": "roller", "roller_radius": 4.349199106798089},
    "motion": [{"kind": "rise", "angle": 56.3855421686747, "lift": 4.385875767539172, "law": "cycloidal"},
               {"kind": "dwell", "angle": 82.40963855421687},
               {"kind": "rise", "angle": 144.57831325301206, "lift": 4.385875767539172, "law": "constant_velocity",
                "start_blend": 21.686746987951807},
               {"kind": "dwell", "angle": 23.132530120481928},
               {"kind": "return", "angle": 53.493975903614455, "lift": 8.771751535078344, "law": "polynomial",
                "points": [[26.746987951807228, 4.1327875530096865]]}],
    "groove": {"depth": 6.460718321889535}, "machining": {"passes": 1, "tool_radius": 2.1745995533990445},
}
H1, H = 4.385875767539172, 8.771751535078344
BETA, BLEND = 144.57831325301206, 21.686746987951807
STROKE_START = 56.3855421686747 + 82.40963855421687
STROKE_END = STROKE_START + BETA                       # 283.3735°: where the seed-12 cam's stroke meets the dwell
W2 = 4.349199106798089 + 0.05 / 2                      # the default clearance 0.05
RO = 74.43620341680123 / 2
RB = RO - 6.460718321889535


def variant(**edits) -> dict:
    """SEED12 with ``edits``: "motion.2.end_blend" = value (None removes), "cam.bore_diameter" = …"""
    d = copy.deepcopy(SEED12)
    for path, value in edits.items():
        keys = path.split(".")
        node = d
        for k in keys[:-1]:
            node = node[int(k)] if k.isdigit() else node[k]
        if value is None:
            node.pop(keys[-1], None)
        else:
            node[keys[-1]] = value
    return d


def blended() -> dict:
    return variant(**{"motion.2.end_blend": BLEND})


def parting(v: float, rho: float) -> float:
    """How far the walls' offsets part where the developed centre line (ρ·φ′, s′) = (∓ρ, s′) turns from
    slope 0 to s′ = v: 2·(w/2)·sin(α/2), α = atan(|v|/ρ)."""
    return 2 * W2 * math.sin(math.atan(abs(v) / rho) / 2)


# ---- the corner, refused -----------------------------------------------------------------------
def test_seed12_refused_at_its_corner():
    v = H1 / math.radians(BETA - BLEND / 2)            # one blend from rest rises V·b/2
    assert v == pytest.approx(1.879, abs=5e-4)
    with pytest.raises(GeometryError) as info:
        design_cam(CamSpec.from_dict(SEED12))
    exc = info.value
    msg = str(exc)
    assert exc.kind == "undercut" and exc.angle_deg == pytest.approx(STROKE_END, abs=1e-9)
    assert msg.startswith(f"the groove's centre line turns a corner at cam angle {STROKE_END:.2f}°"), msg
    assert f"velocity jumps by {-v:.4g} mm/rad" in msg, msg
    assert f"walls' offsets part by {parting(v, RB):.4g} mm" in msg, msg
    assert msg.endswith("a blend (motion[2].end_blend)"), msg


def test_seed12_checks_fail_with_the_corner():
    """What ``check`` shows of it: the undercut check's radius of curvature is 0 at the corner (no
    size removes it: the remedy names the blend, no cylinder radius is searched), the continuity C0."""
    from cam_workbench.generators.bodies.cylindrical import cylinder_checks
    from cam_workbench.generators.studies.remedies import add_remedies

    spec = CamSpec.from_dict(SEED12)
    checks = add_remedies(cylinder_checks(spec), spec)
    assert checks["failed"] == ["undercut", "continuity"]
    u = checks["results"]["undercut"]
    assert (u["value"], u["status"]) == (0.0, "fail") and u["at_deg"] == pytest.approx(STROKE_END, abs=1e-9)
    assert "a corner of the centre line" in u["note"] and "motion[2].end_blend" in u["note"]
    assert u["remedy"]["field"] is None and u["remedy"]["evaluations"] == 0
    assert u["remedy"]["text"].endswith("no size removes it — a blend (motion[2].end_blend)")
    c = checks["results"]["continuity"]
    assert (c["value"], c["limit"], c["status"]) == (0.0, 2.0, "fail")


@pytest.mark.parametrize("name, edits, at, fix", [
    ("blend at the end only", {"motion.2.start_blend": None, "motion.2.end_blend": BLEND}, STROKE_START,
     "a blend (motion[2].start_blend)"),
    ("no blend", {"motion.2.start_blend": None}, STROKE_START, "a blend (motion[2].start_blend)"),
    ("a bore", {"cam.bore_diameter": 20.0}, STROKE_END, "a blend (motion[2].end_blend)"),
    ("a shallow groove", {"groove.depth": 3.0}, STROKE_END, "a blend (motion[2].end_blend)"),
    ("the default outer diameter", {"cam.outer_diameter": None}, STROKE_END, "a blend (motion[2].end_blend)"),
    ("cw", {"cam.direction": "cw"}, STROKE_END, "a blend (motion[2].end_blend)"),
])
def test_neighbours_refused_at_the_same_corner(name, edits, at, fix):
    """The pattern is the velocity's jump, not the bore, the depth, the outer diameter or the sense."""
    with pytest.raises(GeometryError) as info:
        design_cam(CamSpec.from_dict(variant(**edits)))
    assert info.value.kind == "undercut" and info.value.angle_deg == pytest.approx(at, abs=1e-9), name
    assert str(info.value).endswith(fix), str(info.value)


def test_oscillating_arm_refused_at_the_corner():
    d = variant(**{"follower.motion": "oscillating", "follower.arm_length": 40.0, "follower.pivot_distance": 38.0,
                   "cam.length": 40.0})
    for m in d["motion"]:
        if "lift" in m:
            m["lift"] *= 2                                           # degrees of the arm
    d["motion"][4]["points"] = [[26.746987951807228, 8.2]]
    with pytest.raises(GeometryError) as info:
        design_cam(CamSpec.from_dict(d))
    assert info.value.angle_deg == pytest.approx(STROKE_END, abs=1e-9)
    assert "deg/rad" in str(info.value) and "turns a corner" in str(info.value)


def test_velocity_given_against_a_dwell_refused():
    d = copy.deepcopy(EXAMPLES["cylindrical"])
    d["motion"][1].update(law="polynomial", start_velocity=5.0)
    with pytest.raises(GeometryError) as info:
        design_cam(CamSpec.from_dict(d))
    assert info.value.angle_deg == pytest.approx(30.0, abs=1e-9)
    assert str(info.value).endswith("velocities that match the neighbour's (motion[1].start_velocity)")


def test_cli_build_refused_nothing_written_and_check_fails(tmp_path):
    (tmp_path / "c.toml").write_text(dict_to_toml(SEED12))
    res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "build", str(tmp_path / "c.toml"), "-o",
                          str(tmp_path / "out")], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: the groove's centre line turns a corner at cam angle "
                                                   "283.37°"), res.stderr
    assert "motion[2].end_blend" in lines[0] and not (tmp_path / "out").exists()
    res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "check", str(tmp_path / "c.toml"), "-o",
                          str(tmp_path / "chk")], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 3, res.stderr
    rep = json.loads((tmp_path / "chk" / "report.json").read_text())
    assert rep["checks"]["failed"] == ["undercut", "continuity"]
    assert "Traceback" not in res.stderr


# ---- the fix: blended at both ends, the exact volume --------------------------------------------------
def lift_velocity(theta_deg: np.ndarray | float) -> np.ndarray:
    """s′ [mm/rad] of the blended cam, written here: cycloidal rise, dwell, the stroke blended from and
    to rest (s′ = V(3x² − 2x³) over each blend, V = h/(β − b)), dwell, the degree-6 return (s, s′, s″
    at both ends and its interior point)."""
    t = np.atleast_1d(np.asarray(theta_deg, dtype=float)) % 360.0
    out = np.zeros_like(t)
    b0 = math.radians(56.3855421686747)
    rise = t < 56.3855421686747
    x = np.radians(t) / b0
    out = np.where(rise, H1 / b0 * (1 - np.cos(2 * np.pi * x)), out)
    v = H1 / math.radians(BETA - BLEND)
    u = t - STROKE_START
    xs, xe = u / BLEND, (BETA - u) / BLEND
    stroke = np.where(xs < 1, v * (3 * xs ** 2 - 2 * xs ** 3), np.where(xe < 1, v * (3 * xe ** 2 - 2 * xe ** 3), v))
    out = np.where((u >= 0) & (u < BETA), stroke, out)
    r0 = STROKE_END + 23.132530120481928
    span = math.radians(53.493975903614455)
    xr = (t - r0) / 53.493975903614455
    out = np.where(t >= r0, np.polyval(np.polyder(return_poly()), xr) / span, out)
    return out


def return_poly() -> np.ndarray:
    """The return's s(x), x ∈ [0, 1]: s = H, 0 at the ends with s′ = s″ = 0 there (a dwell before, a
    cycloid from rest after) and s(½) = the spec's point — 7 conditions, degree 6 (np.polyval order)."""
    rows, rhs = [], []
    for x, d, val in ((0, 0, H), (1, 0, 0.0), (0, 1, 0.0), (1, 1, 0.0), (0, 2, 0.0), (1, 2, 0.0),
                      (0.5, 0, 4.1327875530096865)):
        row = [math.factorial(k) / math.factorial(k - d) * x ** (k - d) if k >= d else 0.0 for k in range(7)]
        rows.append(row)
        rhs.append(val)
    return np.linalg.solve(np.array(rows), np.array(rhs))[::-1]


def exact_volume() -> float:
    breaks = [0.0, 56.3855421686747, STROKE_START, STROKE_START + BLEND, STROKE_END - BLEND, STROKE_END,
              STROKE_END + 23.132530120481928, 360.0]

    def ell(rho: float) -> float:
        return sum(integrate.quad(lambda t: math.hypot(rho, float(lift_velocity(math.degrees(t))[0])),
                                  math.radians(a), math.radians(b), epsabs=1e-12, epsrel=1e-13)[0]
                   for a, b in zip(breaks[:-1], breaks[1:]))
    groove = 2 * W2 * integrate.quad(ell, RB, RO, epsabs=1e-10, epsrel=1e-13)[0]
    return math.pi * RO ** 2 * SEED12["cam"]["length"] - groove


@pytest.fixture(scope="module")
def fixed_volume() -> float:
    return exact_volume()


def test_blended_lift_written_here_is_the_programs():
    """The test's own lift is the motion the spec means (so the volume below tests the body, not the law)."""
    from cam_workbench.generators.motion.program import MotionProgram

    th = np.linspace(0.0, 359.9, 3600)
    k = MotionProgram.from_spec(CamSpec.from_dict(blended())).evaluate(np.radians(th))
    np.testing.assert_allclose(k.ds, lift_velocity(th), atol=1e-9)


def test_blended_design_volume(fixed_volume):
    assert design_cam(CamSpec.from_dict(blended())).volume == pytest.approx(fixed_volume, rel=1e-12)


@requires_ocp
def test_blended_solid_has_the_exact_volume(fixed_volume, tmp_path):
    (tmp_path / "c.toml").write_text(dict_to_toml(blended()))
    res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "build", str(tmp_path / "c.toml"), "-o",
                          str(tmp_path / "out")], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    rep = json.loads((tmp_path / "out" / "report.json").read_text())
    solid = rep["solid"]
    assert solid["valid"] and solid["solids"] == 1
    # report.json's volume is OCCT's fixed Gauss rule, not exact on B-spline walls (measured -1.2e-6 here,
    # ≤ 1.4e-5 on fuzzed cams): within what the report says it allows; the solid itself is held to the exact
    # volume below, by OCCT's adaptive rule on the STEP file
    assert "fixed Gauss rule" in solid["volume_rule"]["what"]
    assert solid["kernel_volume"] == pytest.approx(fixed_volume, rel=1e-5)
    assert abs(solid["volume_rel_diff"]) <= min(1e-5, solid["volume_rule"]["allowed"])
    assert abs(solid["area_rel_diff"]) <= 1e-12
    assert solid["wall_error"]["faces"] == 10 and solid["wall_error"]["points"] > 1000
    assert rep["checks"]["passed"]
    from cam_workbench.kernel.solids import SURFACE_VOLUME_EPS, kernel_volume
    from cam_workbench.kernel.step import read_step

    back = read_step(tmp_path / "out" / "cam.step", "mm")
    assert kernel_volume(back, SURFACE_VOLUME_EPS) == pytest.approx(fixed_volume, rel=1e-9)


# ---- the groove volume of laws made of pieces ------------------------------------------------------
PIECEWISE = {
    "modified trapezoid": ([None, "modified_trapezoid", None, "modified_trapezoid", None], {}),
    "modified sine": ([None, "modified_sine", None, "modified_sine", None], {}),
    "blended stroke": ([None, "constant_velocity", None, "cycloidal", None], {"start_blend": 30.0, "end_blend": 20.0}),
}


@pytest.mark.parametrize("name", sorted(PIECEWISE))
def test_groove_volume_of_laws_made_of_pieces(name):
    """Against scipy's quad with the pieces' ends as break points (the laws' own s′, the quadrature
    written here): the body's adaptive rule to 1e-12 (one 41-node rule per segment was ~1e-7 off)."""
    from cam_workbench.generators.motion.program import MotionProgram

    laws, extra = PIECEWISE[name]
    d = copy.deepcopy(EXAMPLES["cylindrical"])
    for seg, law in zip(d["motion"], laws):
        if law is not None:
            seg["law"] = law
            if law == "constant_velocity":
                seg.update(extra)
    spec = CamSpec.from_dict(d)
    design = design_cam(spec)
    program = MotionProgram.from_spec(spec)
    lay = design.layout
    starts = np.degrees(program.boundaries)
    breaks = sorted({float(a + (b - a) * f) for a, b in zip(starts[:-1], starts[1:]) for f in np.arange(9) / 8}
                    | {starts[1] + 30.0, starts[2] - 20.0})

    def speed(t: float, rho: float) -> float:
        return math.hypot(rho, float(program.evaluate(np.array([t])).ds[0]))

    def ell(rho: float) -> float:
        return sum(integrate.quad(speed, math.radians(a), math.radians(b), args=(rho,), epsabs=1e-12,
                                  epsrel=1e-13)[0] for a, b in zip(breaks[:-1], breaks[1:]))
    groove = 2 * lay.half_width * integrate.quad(ell, lay.bottom_radius, lay.outer_radius, epsabs=1e-10,
                                                 epsrel=1e-13)[0]
    assert design.body.groove_volume == pytest.approx(groove, rel=1e-12)

"""Cam bodies and their features, against computations written for the test.

* groove walls: points of the built walls (the NURBS evaluated by scipy on homogeneous
  coordinates) lie at ±(r + c/2) from the design pitch curve (brute-force distance to a dense
  polyline of the true pitch points);
* volumes: the disc, bore, DIN 6885-1 keyway, hub and holes from their elementary formulas, the
  groove's area by the shoelace formula on dense wall points — against the body's exact volume
  and OCCT's solid (BRepGProp, good to ~1e-5 on B-spline faces);
* the keyway's size from the DIN 6885-1 / ANSI B17.1 rows written out here;
* which wall drives: a follower loaded by its inertia only changes wall where s″ changes sign —
  for cycloidal rise and return in the middle and at the ends of each (hand-computed angles);
* G-code through LinuxCNC's rs274: the finishing passes run R_t from the exact walls;
* bad input: each refusal names its field (or the cam angle), exit 2 from the CLI, nothing written.
"""
from __future__ import annotations

import copy
import math
import subprocess
import sys

import numpy as np
import pytest

from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import GeometryError, SpecError
from cam_workbench.generators.motion import MotionProgram
from cam_workbench.generators.spec import DEFAULT_SPEC_DICT, CamSpec

from .combinations.invariants import nurbs_points, polyline_distance, shoelace
from .conftest import ROOT, requires_ocp


def groove_dict(**cam):
    d = copy.deepcopy(DEFAULT_SPEC_DICT)
    d["cam"].update({"body": "groove", "outer_diameter": 150.0, "thickness": 12.0, "bore_diameter": 16.0, **cam})
    d["follower"] = {"kind": "roller", "roller_radius": 8.0, "mass": 0.5}
    d["groove"] = {"depth": 8.0, "clearance": 0.1, "min_wall": 3.0}
    return d


def true_pitch(spec, n=20000):
    th = np.linspace(0, 2 * np.pi, n, endpoint=False)
    s = MotionProgram.from_spec(spec).s(th)
    return np.exp(-1j * th) * (1j * (spec.cam.base_radius + s))      # e = 0, ccw


@pytest.mark.parametrize("rep", ["ph", "bspline"])
def test_groove_walls_at_half_the_groove_width(rep):
    d = groove_dict()
    d["pitch"] = {"representation": rep, "segments": 60}
    spec = CamSpec.from_dict(d)
    design = design_cam(spec)
    pitch = true_pitch(spec)
    w2 = 8.0 + 0.05
    inner = nurbs_points(design.profile, 6000)
    outer = nurbs_points(design.body.extra["outer_wall"], 6000)
    # the dense polyline's chords lie ≲ L²κ/8 ≈ 2e-5 inside the true curve; the PH curve is 1.2e-4 off
    slack = 2e-4 if rep == "ph" else 2e-3
    assert np.max(np.abs(polyline_distance(inner, pitch) - w2)) < slack
    assert np.max(np.abs(polyline_distance(outer, pitch) - w2)) < slack
    assert np.all(np.abs(outer) > np.abs(inner).min())


def _groove_area(design) -> float:
    return shoelace(nurbs_points(design.body.extra["outer_wall"], 40000)) - shoelace(nurbs_points(design.profile, 40000))


def _keyed_bore_area(r: float, b: float, t2: float) -> float:
    """Bore circle plus the keyway: a rectangle b wide from the chord at √(r² − (b/2)²) to r + t₂,
    minus the circular segment the rectangle overlaps."""
    h = math.sqrt(r * r - (b / 2) ** 2)
    seg = r * r * math.asin(b / 2 / r) - (b / 2) * h           # circle segment beyond the chord
    return math.pi * r * r + b * (r + t2 - h) - seg


@requires_ocp
def test_groove_cam_volume_and_solid():
    from cam_workbench.kernel import solids as occ_build

    d = groove_dict(keyway="DIN6885", hub_diameter=36.0, hub_length=14.0, mounting_holes=4,
                    mounting_hole_diameter=6.0, mounting_circle_diameter=44.0)
    spec = CamSpec.from_dict(d)
    design = design_cam(spec)
    # DIN 6885-1: a 16 mm bore (over 12 up to 17) takes a 5 mm key, hub keyway 2.3 mm deep
    bore = _keyed_bore_area(8.0, 5.0, 2.3)
    disc = math.pi * 75.0**2 - bore
    holes = 4 * math.pi * 3.0**2
    hub = (math.pi * 18.0**2 - bore) * 14.0
    expected = disc * 12.0 - _groove_area(design) * 8.0 - holes * 12.0 + hub
    assert design.volume == pytest.approx(expected, rel=2e-7)
    solid = occ_build.cam_solid(design)
    assert occ_build.is_valid(solid) and occ_build.count_solids(solid) == 1
    assert occ_build.kernel_volume(solid) == pytest.approx(expected, rel=2e-5)
    # top face: the disc minus bore, holes and groove, in pieces (inside and outside the groove)
    assert design.area == pytest.approx(disc - holes - _groove_area(design), rel=2e-7)


def test_keyway_tables():
    from cam_workbench.generators.bodies.features import keyway_size

    d = copy.deepcopy(DEFAULT_SPEC_DICT)
    for bore, b, t2 in ((12.0, 4, 1.8), (12.01, 5, 2.3), (40.0, 12, 3.3), (100.0, 28, 6.4)):
        d["cam"].update(bore_diameter=bore, base_radius=max(40.0, bore), keyway="DIN6885")
        assert keyway_size(CamSpec.from_dict(d | {"follower": {"kind": "knife"}})) == (b, t2)
    # ANSI B17.1: a 1 in bore (over 7/8 up to 1 1/4) takes a 1/4 in square key, keyseat W/2 at its side
    di = copy.deepcopy(d) | {"units": "in", "follower": {"kind": "knife"}}
    di["cam"].update(bore_diameter=1.0, base_radius=2.0, thickness=0.5, keyway="ANSI")
    for m in di["motion"]:
        if "lift" in m:
            m["lift"] = 0.5
    w, depth = keyway_size(CamSpec.from_dict(di))
    assert w == pytest.approx(0.25) and depth + 0.5 == pytest.approx(math.sqrt(0.25 - 0.125**2) + 0.125)


def test_which_wall_drives():
    """Inertia only (0.5 kg, no spring): F = M s″ω² changes sign at the middle and the ends of the
    cycloidal rise (30°–150°) and return (210°–330°); the dwells (F = 0) count as the inner wall's."""
    design = design_cam(CamSpec.from_dict(groove_dict()))
    drive = design.body_report["drive"]
    assert np.allclose(drive["changes_at_deg"], [90.0, 150.0, 210.0, 270.0], atol=0.06)
    assert drive["inner_wall_share"] + drive["outer_wall_share"] == pytest.approx(1.0)
    assert drive["outer_wall_share"] == pytest.approx(120 / 360, abs=2e-3)
    assert design.checks["separation"].status == "skipped"


def test_walls_refused_with_the_cam_angle():
    with pytest.raises(GeometryError) as info:
        design_cam(CamSpec.from_dict(groove_dict(outer_diameter=140.0)))
    # the outer wall's largest radius is at the top of the lift (dwell 150°–210°): R_b + h + w/2 = 68.05
    assert info.value.kind == "wall" and 150.0 <= info.value.angle_deg <= 210.0
    assert "1.95 of material to the rim" in str(info.value)


@pytest.mark.parametrize("change,field,words", [
    (dict(outer_diameter=None), "cam.outer_diameter", "is required for a groove cam"),
    (dict(keyway="DIN6885", keyway_width=3.0), "cam.keyway", "not both"),
    (dict(hub_diameter=30.0), "cam.hub_length", "is required"),
    (dict(mounting_holes=3), "cam.mounting_hole_diameter", "is required"),
    (dict(hub_diameter=16.0, hub_length=5.0), "cam.hub_diameter", "must leave material"),
])
def test_body_rules(change, field, words):
    d = groove_dict()
    for k, v in change.items():
        if v is None:
            d["cam"].pop(k)
        else:
            d["cam"][k] = v
    with pytest.raises(SpecError) as info:
        CamSpec.from_dict(d)
    assert info.value.field == field and words in str(info.value), str(info.value)


def test_groove_needs_a_roller_and_holes_need_material():
    d = groove_dict()
    d["follower"] = {"kind": "knife"}
    with pytest.raises(SpecError, match='cam.body: a groove needs a roller follower'):
        CamSpec.from_dict(d)
    d = groove_dict(mounting_holes=4, mounting_hole_diameter=6.0, mounting_circle_diameter=62.0)
    with pytest.raises(SpecError, match="cam.mounting_circle_diameter: the mounting holes run into"):
        design_cam(CamSpec.from_dict(d))


def test_cli_refuses_a_groove_without_a_roller(tmp_path):
    from cam_workbench.generators.spec import dict_to_toml

    d = groove_dict()
    d["follower"] = {"kind": "knife"}
    (tmp_path / "g.toml").write_text(dict_to_toml(d))
    res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "build", str(tmp_path / "g.toml"), "-o",
                          str(tmp_path / "out")], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 2 and "cam.body: a groove needs a roller" in res.stderr
    assert "Traceback" not in res.stderr and not (tmp_path / "out").exists()


@requires_ocp
def test_plate_with_features_volume():
    from cam_workbench.kernel import solids as occ_build

    d = copy.deepcopy(DEFAULT_SPEC_DICT)
    d["cam"].update(keyway_width=4.0, keyway_depth=2.0, hub_diameter=30.0, hub_length=12.0, mounting_holes=3,
                    mounting_hole_diameter=4.0, mounting_circle_diameter=40.0, timing_mark=True)
    design = design_cam(CamSpec.from_dict(d))
    bore = _keyed_bore_area(6.0, 4.0, 2.0)
    profile = shoelace(nurbs_points(design.profile, 40000))
    holes = 3 * math.pi * 2.0**2
    mark = design.body.prism("timing_mark")
    mark_area = shoelace(mark.outer.points())
    expected = (profile - bore - holes) * 10.0 + (math.pi * 15.0**2 - bore) * 12.0 - mark_area * 0.2
    assert design.volume == pytest.approx(expected, rel=1e-7)
    solid = occ_build.cam_solid(design)
    assert occ_build.is_valid(solid) and occ_build.count_solids(solid) == 1
    assert occ_build.kernel_volume(solid) == pytest.approx(expected, rel=2e-5)
    # the mark is radial where the follower is at θ = 0 (+Y for the default's radial roller), 0.5 mm wide
    pts = mark.outer.points()
    assert np.allclose(np.abs(pts.real), 0.25) and pts.imag.min() > 8.0


@pytest.mark.skipif(subprocess.run(["which", "rs274"], capture_output=True).returncode != 0,
                    reason="LinuxCNC's rs274 is not installed (Debian package linuxcnc-uspace)")
def test_groove_gcode_through_rs274(tmp_path):
    from cam_workbench.exporters.gcode import groove_program
    from cam_workbench.generators.machining import machining_plan
    from cam_workbench.generators.machining.groove import groove_path

    from .rs274 import PRINT_QUANTUM, run_rs274, sample_xy

    spec = CamSpec.from_dict(groove_dict() | {"machining": {"tool_radius": 3.0, "passes": 2}})
    design = design_cam(spec)
    plan = machining_plan(design)
    path = groove_path(design, plan)
    run = run_rs274(groove_program(design, plan, path), tmp_path, plan.tool_number, 2 * plan.tool_radius)
    assert run.units == "mm"
    # each level: passes from the middle out, the walls last; every pass closed
    roles = [p.role for p in path.passes]
    assert roles[-2:] == ["inner_wall", "outer_wall"] and len(roles) >= 3
    allowance = plan.chord_tolerance + 2 * PRINT_QUANTUM
    pitch = true_pitch(spec)
    w2 = 8.05
    for level, z in enumerate(plan.z_levels):
        for k, p in enumerate(path.passes):
            prefix = f"level {level + 1}, pass {k + 1}: {p.role.replace('_', ' ')}"
            moves = [m for m in run.motions if m.tag.startswith(prefix)]
            assert moves, (level, k, {m.tag for m in run.motions})
            cut = [m for m in moves if abs(m.end[2] - z) < 1e-9 and m.kind in ("line", "arc") and m.feed]
            pts = sample_xy(cut[1:])
            dist = polyline_distance(pts, pitch)
            # the tool centre runs |offset| from the pitch curve, on its side
            assert np.max(np.abs(dist - abs(p.offset))) <= allowance + 2e-4
            if p.role != "rough":
                # the tool's edge touches its wall: |offset| + R_t = w/2
                assert abs(abs(p.offset) + plan.tool_radius - w2) < 1e-9

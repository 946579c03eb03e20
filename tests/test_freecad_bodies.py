"""Every cam body in the ``Cam`` feature inside a real FreeCAD (``freecadcmd``).

A groove cam (mm, keyway by DIN 6885-1, hub, holes, timing mark), the same groove in inches
(ANSI B17.1 keyway), a conjugate yoke pair and a conjugate arm pair, and a plate cam with every
feature are created with ``feature.create`` — the function the GUI commands call — and
recomputed in one FreeCAD.  Each holds one valid solid whose volume is the body's exact volume
(Σ ± prism areas × heights: Green's theorem on the exact loops, computed here by the shoelace
formula on dense points of the loops, independently of the library's quadrature), whose
bounding box spans the body's z range, and the groove's walls in the solid are at ±(r + c/2)
from the pitch curve (points of FreeCAD's own B-spline faces, measured against the exact pitch
curve sampled densely).  A property change (the groove clearance) recomputes to the new width.
"""
from __future__ import annotations

import copy
import json

import numpy as np
import pytest

from cam_workbench.generators import design_cam
from cam_workbench.generators.spec import DEFAULT_SPEC_DICT, CamSpec
from cam_workbench.generators.spec.examples import example_dict

from .combinations.invariants import shoelace
from .freecad_support import fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401

pytestmark = requires_freecadcmd

MM_PER_IN = 25.4


def _specs() -> dict[str, dict]:
    groove = copy.deepcopy(DEFAULT_SPEC_DICT)
    groove["cam"].update(body="groove", outer_diameter=150.0, thickness=12.0, bore_diameter=16.0,
                         keyway="DIN6885", hub_diameter=36.0, hub_length=10.0, mounting_holes=4,
                         mounting_hole_diameter=5.0, mounting_circle_diameter=34.0, timing_mark=True)
    groove["follower"] = {"kind": "roller", "roller_radius": 8.0, "mass": 0.5}
    groove["groove"] = {"depth": 8.0, "clearance": 0.1, "min_wall": 3.0}
    inch = copy.deepcopy(groove)
    inch["units"] = "in"
    inch["cam"].update(base_radius=40.0 / MM_PER_IN, outer_diameter=6.0, thickness=0.5, bore_diameter=0.75,
                       keyway="ANSI", hub_diameter=1.5, hub_length=0.4, mounting_holes=0, timing_mark=False)
    for k in ("mounting_hole_diameter", "mounting_circle_diameter"):
        inch["cam"].pop(k)
    inch["follower"] = {"kind": "roller", "roller_radius": 0.3, "mass": 0.5}
    inch["groove"] = {"depth": 0.3, "clearance": 0.004, "min_wall": 0.1}
    for m in inch["motion"]:
        if "lift" in m:
            m["lift"] = 0.8
    yoke = copy.deepcopy(DEFAULT_SPEC_DICT)
    yoke["cam"].update(body="conjugate", bore_diameter=12.0)
    yoke["follower"] = {"kind": "roller", "roller_radius": 8.0, "offset": 5.0, "mass": 0.5}
    yoke["conjugate"] = {"roller_distance": 106.0, "roller_radius": 6.0, "gap": 3.0}
    arm = example_dict("oscillating")
    arm["cam"].update(body="conjugate", bore_diameter=12.0, direction="cw")
    arm["conjugate"] = {"arm_angle": 120.0, "arm_length": 50.0, "roller_radius": 7.0, "gap": 2.0}
    plate = copy.deepcopy(DEFAULT_SPEC_DICT)
    plate["cam"].update(keyway_width=4.0, keyway_depth=2.0, hub_diameter=30.0, hub_length=12.0, mounting_holes=3,
                        mounting_hole_diameter=4.0, mounting_circle_diameter=40.0, timing_mark=True)
    return {"groove": groove, "groove_in": inch, "yoke": yoke, "arm": arm, "plate": plate}


SPECS = _specs()

BODY = """
import FreeCAD
from cam_workbench.freecad.feature import create
specs = json.loads(SPECS)
doc = FreeCAD.newDocument("bodies")
cams = {k: create(doc, d, name=k) for k, d in specs.items()}
doc.recompute()
for k, cam in cams.items():
    s = cam.Shape
    bb = s.BoundBox if not s.isNull() else None
    wall = []
    if k.startswith("groove") and not s.isNull():
        # points on the groove's wall faces (B-spline side faces), half way down the groove
        zt = bb.ZMax
        for f in s.Faces:
            if f.Surface.TypeId in ("Part::GeomSurfaceOfExtrusion", "Part::GeomBSplineSurface"):
                u0, u1, v0, v1 = f.ParameterRange
                for i in range(40):
                    u = u0 + (u1 - u0) * (i + 0.5) / 40
                    p = f.valueAt(u, 0.5 * (v0 + v1))
                    wall.append([p.x, p.y, p.z])
    RESULT[k] = dict(status=cam.Status, null=s.isNull(), valid=(not s.isNull()) and s.isValid(),
                     solids=0 if s.isNull() else len(s.Solids), volume=0.0 if s.isNull() else s.Volume,
                     z=[bb.ZMin, bb.ZMax] if bb else None, wall=wall)
# what the recompute measured (part_build.PartSolid) beside the solid measured whole
from cam_workbench.freecad import properties as props
from cam_workbench.freecad.part_build import plane_solid, top_face_area
from cam_workbench.generators import default_spec, design_cam
measured = {k: (cam.Proxy.design, props.units_scale(cam)) for k, cam in cams.items()}
measured["plain"] = (design_cam(default_spec()), 1.0)
for k, (design, scale) in measured.items():
    built = plane_solid(design, scale)
    s = built.shape
    RESULT["measured_" + k] = dict(valid=built.valid, volume=built.volume, top=built.top_area, how=built.measured,
                                   full_valid=s.isValid() and len(s.Solids) == 1, full_volume=s.Volume,
                                   full_top=top_face_area(s, max(p.z1 for p in design.body.prisms) * scale
                                                          if design.body is not None else design.spec.cam.thickness * scale))
g = cams["groove"]
g.GrooveClearance = 0.5
doc.recompute()
RESULT["changed"] = dict(status=g.Status, volume=g.Shape.Volume, valid=g.Shape.isValid())
"""


@pytest.fixture(scope="module")
def run(tmp_path_factory, fc_home):  # noqa: F811
    tmp = tmp_path_factory.mktemp("fc_bodies")
    r = run_freecadcmd(f"SPECS = {json.dumps(json.dumps(SPECS))}\n" + BODY, tmp, fc_home).check()
    assert "Traceback" not in r.console, r.console[-3000:]
    return r.result


def _exact_volume(design) -> float:
    """Σ ± (shoelace area of the prism's loops, densely sampled) × height."""
    vol = 0.0
    for p in design.body.prisms:
        area = abs(shoelace(p.outer.points(4000))) - sum(abs(shoelace(h.points(4000))) for h in p.holes)
        vol += (1 if p.op == "add" else -1) * area * (p.z1 - p.z0)
    return vol


@pytest.mark.parametrize("name", sorted(SPECS))
def test_body_solid_volume_and_extent(run, name):
    spec = CamSpec.from_dict(SPECS[name])
    design = design_cam(spec)
    r = run[name]
    assert r["status"] == "ok" or r["status"].startswith("ok"), r["status"]
    assert r["valid"] and r["solids"] == 1, r
    k = MM_PER_IN if spec.units == "in" else 1.0
    exact = _exact_volume(design) * k**3
    # FreeCAD's OCCT integrates B-spline side faces to ~1e-5 relative (measured); the shoelace on
    # 4000 points per loop is good to ~1e-6
    assert r["volume"] == pytest.approx(exact, rel=5e-5)
    assert r["volume"] == pytest.approx(design.volume * k**3, rel=5e-5)
    z0, z1 = design.body.z_range
    assert r["z"] == pytest.approx([z0 * k, z1 * k], abs=1e-6)


@pytest.mark.parametrize("name", ["groove", "groove_in"])
def test_groove_walls_in_freecads_solid(run, name):
    """Every point of the groove's side faces is r + c/2 from the exact pitch curve (either wall)."""
    from cam_workbench.generators.motion import MotionProgram

    spec = CamSpec.from_dict(SPECS[name])
    k = MM_PER_IN if spec.units == "in" else 1.0
    th = np.linspace(0, 2 * np.pi, 200000, endpoint=False)
    s = MotionProgram.from_spec(spec).s(th)
    pitch = np.exp(-1j * th) * (1j * (spec.cam.base_radius + s)) * k      # e = 0, ccw (docs/conventions.md)
    wall = np.array(run[name]["wall"])
    assert len(wall) > 40
    pts = wall[:, 0] + 1j * wall[:, 1]
    d = np.array([np.min(np.abs(pitch - p)) for p in pts])
    half = (spec.follower.roller_radius + spec.groove.clearance / 2) * k
    # the pitch sample spacing (≈ 2π·70/2e5 mm) bounds the distance's sampling error to ~1e-6 mm
    np.testing.assert_allclose(d, half, atol=2e-4 * k)


def test_property_change_recomputes(run):
    d = copy.deepcopy(SPECS["groove"])
    d["groove"]["clearance"] = 0.5
    design = design_cam(CamSpec.from_dict(d))
    r = run["changed"]
    assert r["valid"] and r["volume"] == pytest.approx(design.volume, rel=5e-5)


@pytest.mark.parametrize("name", ["plain", *sorted(SPECS)])
def test_what_the_recompute_measures_is_the_solid(run, name):
    """The recompute's cheap measures (a plain plate's face, a sewn body's planar faces) agree with
    FreeCAD measuring the solid whole: ``isValid()``, OCCT's Gauss volume (to its ~1e-5 on B-spline
    sides) and the top faces; and a sewn body's volume is the exact one (to 1e-7, as the recompute
    demands)."""
    r = run["measured_" + name]
    assert r["valid"] and r["full_valid"], r
    assert r["volume"] == pytest.approx(r["full_volume"], rel=5e-5)
    assert r["top"] == pytest.approx(r["full_top"], rel=1e-9)
    if name != "plain":
        spec = CamSpec.from_dict(SPECS[name])
        k = MM_PER_IN if spec.units == "in" else 1.0
        assert r["volume"] == pytest.approx(_exact_volume(design_cam(spec)) * k**3, rel=2e-6)
        assert "sewn" in r["how"] or "the solid" in r["how"]
    else:
        assert "face" in r["how"]

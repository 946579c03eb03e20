"""The Cam feature inside a real FreeCAD (``freecadcmd``, Debian's 0.20.2 here).

Every test creates features through ``cam_workbench.freecad.feature.create`` — the function
the GUI command calls — and compares with the CadQuery/OCP build of the same spec computed
in this (pytest) process: two OCCT builds, two processes, one geometry.
"""
from __future__ import annotations

import copy
import json
import math

import pytest

from cam_workbench.generators.spec.examples import PAPER_SPEC_DICT
from cam_workbench.generators.spec import CamSpec

from .conftest import paper_case_dict, requires_ocp
from .freecad_support import fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401

pytestmark = requires_freecadcmd


def _specs() -> dict[str, dict]:
    cw = copy.deepcopy(PAPER_SPEC_DICT)
    cw["cam"].update(direction="cw", thickness=7.5, bore_diameter=12.0)
    cw["follower"]["offset"] = -6.0
    cw["motion"][1]["law"] = "poly345"
    cw["motion"][3]["law"] = "modified_sine"
    return {
        "default_roller": copy.deepcopy(PAPER_SPEC_DICT),
        "case1_knife": paper_case_dict(1, knife=True),
        "case3_roller": paper_case_dict(3, knife=False),
        "cw_roller": cw,
    }


BUILD_AND_MEASURE = """
import FreeCAD
from cam_workbench.freecad.feature import create
specs = json.loads(SPECS)
doc = FreeCAD.newDocument("build")
cams = {key: create(doc, d, name=key) for key, d in specs.items()}
doc.recompute()
for key, cam in cams.items():
    s = cam.Shape
    bottom = [f for f in s.Faces if f.Surface.TypeId == "Part::GeomPlane" and abs(f.CenterOfMass.z) < 1e-9]
    outer = bottom[0].OuterWire
    curves = [e.Curve for e in outer.Edges]
    RESULT[key] = {
        "status": cam.Status, "valid": s.isValid(), "solids": len(s.Solids), "volume": s.Volume,
        "bottom_faces": len(bottom), "outer_edges": len(outer.Edges),
        "outer_types": sorted({c.TypeId for c in curves}),
        "rational": [c.isRational() for c in curves],
        "degrees": sorted({c.Degree for c in curves}),
        "holes": len(bottom[0].Wires) - 1,
        "junctions": cam.JunctionCount, "area": cam.CrossSectionArea.Value,
        "children": sorted(o.Kind for o in cam.References),
        "pitch_edges": [len(o.Shape.Edges) for o in cam.References if o.Kind == "pitch curve"][0],
        "base_circle_radius": [o.Shape.Edges[0].Curve.Radius for o in cam.References if o.Kind == "base circle"][0],
    }
RESULT["forbidden_modules"] = [m for m in ("OCP", "cadquery", "build123d") if m in sys.modules]
"""


@pytest.fixture(scope="module")
def built(tmp_path_factory, fc_home):
    specs = _specs()
    body = f"SPECS = {json.dumps(json.dumps(specs))}\n" + BUILD_AND_MEASURE
    return specs, run_freecadcmd(body, tmp_path_factory.mktemp("fc_build"), fc_home).check().result


@requires_ocp
@pytest.mark.parametrize("key", list(_specs()))
def test_feature_volume_equals_cadquery_build(built, key):
    """FreeCAD's solid (FreeCAD's OCCT 7.6) has the volume of the CadQuery build (OCP's OCCT
    7.9) and of the exact Green's-theorem value, to 1e-9 relative, for the same spec."""
    from cam_workbench import PlateCam
    from cam_workbench.kernel.solids import kernel_volume

    specs, res = built
    r = res[key]
    cam = PlateCam(CamSpec.from_dict(specs[key]))
    assert r["status"] == "ok"
    assert r["valid"] and r["solids"] == 1
    assert abs(r["volume"] - cam.volume) / cam.volume < 1e-9, (r["volume"], cam.volume)
    kv = kernel_volume(cam.shape)
    assert abs(r["volume"] - kv) / kv < 1e-9, (r["volume"], kv)
    assert abs(r["area"] - cam.area) / cam.area < 1e-12
    assert res["forbidden_modules"] == []


@pytest.mark.parametrize("key", list(_specs()))
def test_profile_edges_are_exact_bezier_spans(built, key):
    """One B-spline edge per PH segment; a roller's profile is the exact degree-9 rational
    offset, a knife edge's the degree-5 polynomial pitch curve itself."""
    specs, res = built
    r = res[key]
    spec = CamSpec.from_dict(specs[key])
    assert r["outer_types"] == ["Part::GeomBSplineCurve"]
    assert r["outer_edges"] == r["junctions"]
    if spec.is_roller:
        assert all(r["rational"]) and r["degrees"] == [9]
    else:
        assert not any(r["rational"]) and r["degrees"] == [5]
    assert r["holes"] == (1 if spec.cam.bore_diameter > 0 else 0)
    assert r["bottom_faces"] == 1


def test_reference_geometry(built):
    """The pitch curve (one degree-5 edge per PH segment) and the base circle R_b are the
    cam's children."""
    specs, res = built
    for key, r in ((k, v) for k, v in res.items() if k in specs):
        assert r["children"] == ["base circle", "follower", "pitch curve"]
        assert r["pitch_edges"] == r["junctions"]
        assert r["base_circle_radius"] == pytest.approx(specs[key]["cam"]["base_radius"], rel=1e-14)


EDIT = """
import FreeCAD
from cam_workbench.freecad.feature import create
from cam_workbench.freecad import properties as P
doc = FreeCAD.newDocument("edit")
from cam_workbench.generators.spec.examples import example_dict
cam = create(doc, example_dict("paper"))  # the paper's cam: these tests check its numbers
doc.recompute()
RESULT["v0"] = cam.Shape.Volume
cam.CamThickness = 12.5
doc.recompute()
RESULT["v_thick"] = cam.Shape.Volume
cam.FollowerRollerRadius = 4.0
cam.PitchSegments = 72
doc.recompute()
RESULT["v_roller"] = cam.Shape.Volume
RESULT["edges_roller"] = len([e for e in cam.Shape.Edges if e.Curve.TypeId == "Part::GeomBSplineCurve"])
RESULT["status"] = cam.Status
RESULT["spec"] = P.spec_dict(cam)
cam.Units = "in"
doc.recompute()
RESULT["v_inch"] = cam.Shape.Volume
RESULT["spec_inch"] = P.spec_dict(cam)
RESULT["area_inch"] = cam.CrossSectionArea.Value
cam.CamBaseRadius = 30.0
cam.Placement = FreeCAD.Placement(FreeCAD.Vector(100, 0, 0), FreeCAD.Rotation())
doc.recompute()
base = [o for o in cam.References if o.Kind == "base circle"][0]
pitch = [o for o in cam.References if o.Kind == "pitch curve"][0]
RESULT["base_radius_after"] = base.Shape.Edges[0].Curve.Radius
RESULT["base_center_x"] = base.Shape.BoundBox.Center.x
RESULT["cam_bbox_xmin"] = cam.Shape.BoundBox.XMin
RESULT["states"] = [o.State for o in doc.Objects]
RESULT["second_recompute"] = doc.recompute()
"""


@requires_ocp
def test_change_properties_and_recompute(tmp_path, fc_home):
    """Thickness scales the volume exactly; a new roller radius and M give the CadQuery
    volume of the changed spec; switching Units to inches changes the spec's numbers, not
    the geometry."""
    from cam_workbench import PlateCam

    r = run_freecadcmd(EDIT, tmp_path, fc_home).check().result
    assert r["v_thick"] / r["v0"] == pytest.approx(12.5 / 10.0, rel=1e-12)
    expected = PlateCam.example("paper", **{"cam.thickness": 12.5, "follower.roller_radius": 4.0,
                                            "pitch.segments": 72}).volume
    assert abs(r["v_roller"] - expected) / expected < 1e-9
    assert r["status"] == "ok"
    # each of the 72 Bézier profile spans bounds the bottom face, the top face and one side face
    assert r["edges_roller"] >= 72 * 2
    assert r["spec"]["cam"]["thickness"] == 12.5 and r["spec"]["pitch"]["segments"] == 72
    assert abs(r["v_inch"] - r["v_roller"]) / r["v_roller"] < 1e-12
    assert r["spec_inch"]["units"] == "in"
    assert r["spec_inch"]["cam"]["thickness"] == pytest.approx(12.5 / 25.4, rel=1e-15)
    assert r["spec_inch"]["motion"][1]["lift"] == pytest.approx(20 / 25.4, rel=1e-15)
    assert r["spec_inch"]["cam"]["speed_rpm"] == 60.0  # not a length: unchanged
    # the reference curves follow the cam in one recompute, and the document settles
    assert r["base_radius_after"] == pytest.approx(30.0, rel=1e-12)
    assert r["base_center_x"] == pytest.approx(100.0, abs=1e-9)
    assert r["cam_bbox_xmin"] > 50.0
    assert r["states"] == [["Up-to-date"]] * 4 and r["second_recompute"] == 0


SAVE = """
import FreeCAD
from cam_workbench.freecad.feature import create
doc = FreeCAD.newDocument("saved")
cam = create(doc, SPEC)
cam.CamThickness = 8.0
doc.recompute()
RESULT["volume"] = cam.Shape.Volume
doc.saveAs(PATH)
"""

REOPEN = """
import FreeCAD
doc = FreeCAD.openDocument(PATH)
cam = doc.getObject("Cam")
RESULT["restored_volume"] = cam.Shape.Volume
RESULT["proxy"] = type(cam.Proxy).__module__ + "." + type(cam.Proxy).__name__
RESULT["version"] = cam.Version
cam.touch()
doc.recompute()
RESULT["status"] = cam.Status
RESULT["volume"] = cam.Shape.Volume
RESULT["valid"] = cam.Shape.isValid()
RESULT["children_valid"] = [o.Shape.isValid() and not o.Shape.isNull() for o in cam.References]
cam.CamThickness = 9.0
doc.recompute()
RESULT["volume_9"] = cam.Shape.Volume
"""


def test_save_reopen_recompute(tmp_path, fc_home):
    """A saved document reopens in a new FreeCAD process with its proxies, recomputes to the
    same volume and stays editable."""
    path = tmp_path / "cam.FCStd"
    spec = paper_case_dict(3, knife=False)
    s = run_freecadcmd(f"SPEC = {spec!r}\nPATH = {str(path)!r}\n" + SAVE, tmp_path / "a", fc_home).check().result
    assert path.exists()
    r = run_freecadcmd(f"PATH = {str(path)!r}\n" + REOPEN, tmp_path / "b", fc_home).check().result
    assert r["proxy"] == "cam_workbench.freecad.feature.CamFeature"
    assert r["version"] == 5
    assert r["status"] == "ok" and r["valid"]
    assert abs(r["restored_volume"] - s["volume"]) / s["volume"] < 1e-12
    assert abs(r["volume"] - s["volume"]) / s["volume"] < 1e-12
    assert r["children_valid"] == [True, True, True]
    assert r["volume_9"] / r["volume"] == pytest.approx(9.0 / 8.0, rel=1e-12)


MAKE_OLD = """
import FreeCAD
from cam_workbench.freecad.feature import create
doc = FreeCAD.newDocument("old")
from cam_workbench.generators.spec.examples import example_dict
cam = create(doc, example_dict("paper"))  # the paper's cam: these tests check its numbers
doc.recompute()
RESULT["volume"] = cam.Shape.Volume
# what a file written before these properties existed looks like
for name in ("PitchTolerance", "MotionJunctions", "Status", "CrossSectionArea"):
    cam.removeProperty(name)
cam.Version = 0
doc.saveAs(PATH)
"""

OPEN_OLD = """
import FreeCAD
doc = FreeCAD.openDocument(PATH)
cam = doc.getObject("Cam")
RESULT["version"] = cam.Version
RESULT["has"] = [n for n in ("PitchTolerance", "MotionJunctions", "Status", "CrossSectionArea")
                 if n in cam.PropertiesList]
RESULT["junctions"] = list(cam.MotionJunctions)
cam.touch()
doc.recompute()
RESULT["status"] = cam.Status
RESULT["volume"] = cam.Shape.Volume
"""


def test_old_file_is_upgraded_on_restore(tmp_path, fc_home):
    """onDocumentRestored adds the properties of fields an older file lacks (with the value of
    an absent field, so the cam is unchanged), bumps Version, and says so."""
    path = tmp_path / "old.FCStd"
    s = run_freecadcmd(f"PATH = {str(path)!r}\n" + MAKE_OLD, tmp_path / "a", fc_home).check().result
    r = run_freecadcmd(f"PATH = {str(path)!r}\n" + OPEN_OLD, tmp_path / "b", fc_home)
    r.check()
    res = r.result
    assert res["version"] == 5
    assert res["has"] == ["PitchTolerance", "MotionJunctions", "Status", "CrossSectionArea"]
    assert res["junctions"] == [0, 0, 0, 0, 0]  # "not given" on each of the 5 existing rows
    assert res["status"] == "ok"
    assert abs(res["volume"] - s["volume"]) / s["volume"] < 1e-12
    assert "upgraded from feature version 0" in r.console
    assert "Traceback" not in r.console


BAD = """
import FreeCAD
from cam_workbench.freecad.feature import create
doc = FreeCAD.newDocument("bad")
from cam_workbench.generators.spec.examples import example_dict
cam = create(doc, example_dict("paper"))  # the paper's cam: these tests check its numbers
doc.recompute()
good = cam.Shape.Volume
RESULT["good"] = good
def attempt(label, **changes):
    before = {k: getattr(cam, k) for k in changes}
    for k, v in changes.items():
        setattr(cam, k, v)
    FreeCAD.Console.PrintMessage(f"=== {label}\\n")
    doc.recompute()
    RESULT[label] = {"status": cam.Status, "volume": cam.Shape.Volume, "valid": cam.Shape.isValid(),
                     "invalid_state": "Invalid" in cam.State}
    for k, v in before.items():
        setattr(cam, k, v)
    doc.recompute()
    RESULT[label]["restored"] = cam.Shape.Volume
attempt("zero_radius", CamBaseRadius=0.0)
attempt("angles", MotionAngle=[30.0, 120.0, 60.0, 120.0, 20.0])
attempt("undercut", FollowerRollerRadius=21.5, CamBoreDiameter=0.0)
attempt("lists", MotionLift=[0.0, 20.0, 0.0, 20.0])
attempt("offset", FollowerOffset=30.0)
attempt("law", MotionLaw=["", "bspline", "", "cycloidal", ""])
RESULT["final_status"] = cam.Status
"""


def test_bad_values_keep_last_good_shape_and_report(tmp_path, fc_home):
    """A bad property value leaves the last good shape, sets Status, and prints one clear
    line naming the property, the spec field and the rule — never a traceback."""
    run = run_freecadcmd(BAD, tmp_path, fc_home).check()
    r, out = run.result, run.console
    good = r["good"]
    expected = {
        "zero_radius": "Cam: CamBaseRadius (cam.base_radius): must be > 0, got 0. The last good shape is kept.",
        "angles": "Cam: MotionAngle[4] (motion[4].angle): spans sum to 350°, must be 360°",
        "undercut": "Cam: the cam cannot be made:",
        "lists": "Cam: Motion (motion): the Motion lists disagree: MotionLift has 4 entries, MotionKind has 5",
        "offset": "Cam: FollowerOffset (follower.offset): |offset| must be < cam.base_radius",
        "law": 'Cam: MotionControlX[1] (motion[1].control_x): is required for law = "bspline"',
    }
    for label, line in expected.items():
        res = r[label]
        assert res["status"].startswith("error: "), (label, res)
        assert res["volume"] == good and res["valid"], label
        assert not res["invalid_state"], label
        assert res["restored"] == pytest.approx(good, rel=1e-12), label
        assert line in out, f"{label}: {line!r} not in console output:\n{out[-2000:]}"
    assert "undercut" in r["undercut"]["status"] and "°" in r["undercut"]["status"]
    assert r["final_status"] == "ok"
    assert "Traceback" not in out and "Recompute failed" not in out


ROUNDTRIP = """
import FreeCAD
from cam_workbench.generators.spec import CamSpec
from cam_workbench.freecad.feature import create
from cam_workbench.freecad import properties as P
doc = FreeCAD.newDocument("rt")
for key, d in json.loads(SPECS).items():
    spec = CamSpec.from_dict(d)
    cam = create(doc, spec, name=key)
    RESULT[key] = P.spec_of(cam) == spec
    other = create(doc, None, name=key + "_w")
    P.write_spec(other, spec)
    RESULT[key + "_written"] = P.spec_of(other) == spec
"""


def test_spec_round_trip_through_properties(tmp_path, fc_home):
    """spec → properties → spec is the identity (also for optional fields: junctions per
    segment, tolerance instead of segments, a knife follower, inches; forces, stresses, feeds,
    masses and spring rates stored in FreeCAD's units; bools; B-spline control points)."""
    tol = copy.deepcopy(PAPER_SPEC_DICT)
    tol["pitch"] = {"representation": "ph", "tolerance": 1e-3}
    inch = copy.deepcopy(PAPER_SPEC_DICT)
    inch["units"] = "in"
    inch["cam"].update(base_radius=1.0, thickness=0.375, bore_diameter=0.25)
    inch["follower"].update(offset=0.25, roller_radius=0.2)
    for seg in inch["motion"]:
        if "lift" in seg:
            seg["lift"] = 0.5
    from cam_workbench.generators.spec import load_spec

    from .conftest import ROOT

    ex5 = load_spec(ROOT / "tests/fixtures/thesis_ex5_final.toml").to_dict()  # inch, loads, B-spline law
    loaded = copy.deepcopy(PAPER_SPEC_DICT)
    loaded["follower"].update(preload=47.3, mass=0.123456789012345678, spring_rate=1.7, roller_width=6.5)
    loaded["material"] = {"allowable_stress": 812.5, "cam_modulus": 206000.0}
    loaded["machining"] = {"feed_rate": 437.0, "plunge_rate": 120.0, "coolant": True, "passes": 3}
    loaded["checks"] = {"min_force": -2.5, "sampling": "thesis71"}
    loaded["drawing"] = {"title": "Cam 7", "title_block": False, "curves": "arcs"}
    specs = {"case3": paper_case_dict(3, knife=False), "case1_knife": paper_case_dict(1),
             "tolerance": tol, "inch": inch, "ex5": ex5, "loaded": loaded}
    r = run_freecadcmd(f"SPECS = {json.dumps(json.dumps(specs))}\n" + ROUNDTRIP, tmp_path, fc_home).check().result
    for key in specs:
        assert r[key] is True, key
        assert r[key + "_written"] is True, key


UNDO = """
import FreeCAD
from cam_workbench.freecad.feature import create
from cam_workbench.freecad import motion_editor as M
from cam_workbench.generators.errors import SpecError
doc = FreeCAD.newDocument("undo")
doc.UndoMode = 1
from cam_workbench.generators.spec.examples import example_dict
cam = create(doc, example_dict("paper"))  # the paper's cam: these tests check its numbers
doc.recompute()
v0 = cam.Shape.Volume
rows = M.read_rows(cam)
RESULT["rows0"] = rows
new = [dict(r) for r in rows]
new[1].update(law="poly345", lift=15.0, angle=100.0)
new[3].update(law="harmonic", lift=15.0)
new.insert(3, {"kind": "dwell", "angle": 20.0})
undo_before = doc.UndoCount
M.apply_rows(cam, new)
RESULT["undo_steps"] = doc.UndoCount - undo_before
RESULT["undo_names"] = doc.UndoNames[:1]
RESULT["rows1"] = M.read_rows(cam)
RESULT["v1"] = cam.Shape.Volume
RESULT["status1"] = cam.Status
bad = [dict(r) for r in new]
bad[0]["angle"] = 25.0
RESULT["validate_bad"] = M.validate_rows(cam, bad)
try:
    M.apply_rows(cam, bad)
    RESULT["bad_applied"] = True
except SpecError as exc:
    RESULT["bad_applied"] = False
RESULT["undo_after_bad"] = doc.UndoCount - undo_before
doc.undo()
RESULT["rows_undone"] = M.read_rows(cam)
RESULT["v_undone"] = cam.Shape.Volume
RESULT["v0"] = v0
"""


@requires_ocp
def test_motion_program_apply_is_one_undo_step(tmp_path, fc_home):
    """The motion editor's apply writes every motion list and recomputes as ONE undo step; a
    bad program is refused (named by row) and writes nothing; one Undo restores the old
    program and shape."""
    from cam_workbench import PlateCam

    r = run_freecadcmd(UNDO, tmp_path, fc_home).check().result
    assert r["undo_steps"] == 1 and r["undo_names"] == ["Edit motion program"]
    assert len(r["rows1"]) == 6 and r["rows1"][1] == {"kind": "rise", "angle": 100.0, "lift": 15.0,
                                                      "law": "poly345"}
    assert r["status1"] == "ok"
    spec = CamSpec.from_dict({**PAPER_SPEC_DICT, "motion": r["rows1"]})
    expected = PlateCam(spec).volume
    assert abs(r["v1"] - expected) / expected < 1e-9
    assert r["validate_bad"] == "row 6, angle: spans sum to 355°, must be 360°"
    assert r["bad_applied"] is False and r["undo_after_bad"] == 1
    assert r["rows_undone"] == r["rows0"]
    assert r["v_undone"] == pytest.approx(r["v0"], rel=1e-12)


STEP = """
import FreeCAD, Part
from cam_workbench.freecad.feature import create
from cam_workbench.freecad.step_export import export_step
from cam_workbench.freecad.spec_io import export_spec, open as open_spec
doc = FreeCAD.newDocument("step")
from cam_workbench.generators.spec.examples import example_dict
cam = create(doc, example_dict("paper"))  # the paper's cam: these tests check its numbers
doc.recompute()
export_step(cam, STEP_PATH)
RESULT["volume"] = cam.Shape.Volume
back = Part.read(STEP_PATH)
RESULT["reread_volume"] = back.Volume
RESULT["reread_valid"] = back.isValid()
export_spec(cam, TOML_PATH)
cam.CamBaseRadius = 0
doc.recompute()
try:
    export_step(cam, BAD_STEP_PATH)  # still the last good solid: exported
    RESULT["bad_step"] = "written"
except ValueError as exc:
    RESULT["bad_step"] = str(exc)
try:
    export_spec(cam, BAD_TOML_PATH)
except Exception as exc:
    RESULT["bad_toml"] = f"{type(exc).__name__}: {exc}"
opened = open_spec(TOML_PATH)
RESULT["opened_volume"] = opened.Shape.Volume
RESULT["forbidden_modules"] = [m for m in ("OCP", "cadquery", "build123d") if m in sys.modules]
"""


@requires_ocp
def test_step_export_through_freecad(tmp_path, fc_home):
    """STEP written by FreeCAD's own Part (atomically) re-reads in FreeCAD and in OCP with
    the CadQuery build's volume; the spec exported as TOML opens as the same cam; a spec
    that breaks a rule writes no TOML file."""
    from cam_workbench import PlateCam
    from cam_workbench.kernel import ocp as occ
    from cam_workbench.kernel.solids import is_valid, kernel_volume

    paths = {k: str(tmp_path / n) for k, n in (("STEP_PATH", "cam.step"), ("TOML_PATH", "cam.toml"),
                                               ("BAD_STEP_PATH", "bad.step"),
                                               ("BAD_TOML_PATH", "bad.toml"))}
    head = "".join(f"{k} = {v!r}\n" for k, v in paths.items())
    r = run_freecadcmd(head + STEP, tmp_path / "run", fc_home).check().result
    cam = PlateCam.example("paper")  # the cam the script exported
    assert abs(r["reread_volume"] - cam.volume) / cam.volume < 1e-9 and r["reread_valid"]
    reader = occ.STEPControl_Reader()
    assert reader.ReadFile(paths["STEP_PATH"]) == occ.IFSelect_RetDone
    reader.TransferRoots()
    shape = reader.OneShape()
    assert is_valid(shape)
    assert abs(kernel_volume(shape) - kernel_volume(cam.shape)) / cam.volume < 1e-9
    assert r["bad_step"] == "written"
    assert r["bad_toml"] == "SpecError: cam.base_radius: must be > 0, got 0"
    assert not (tmp_path / "bad.toml").exists()
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]
    assert abs(r["opened_volume"] - cam.volume) / cam.volume < 1e-9
    assert r["forbidden_modules"] == []


CHECK = """
import FreeCAD
from cam_workbench.freecad.feature import create
from cam_workbench.freecad.check_design import design_report
doc = FreeCAD.newDocument("check")
from cam_workbench.generators.spec.examples import example_dict
cam = create(doc, example_dict("paper"))  # the paper's cam: these tests check its numbers
doc.recompute()
rep = design_report(cam)
RESULT["ok"] = rep.ok
RESULT["failed"] = rep.failed_checks
RESULT["buildable"] = rep.buildable
RESULT["rows"] = rep.rows
cam.FollowerRollerRadius = 21.5
cam.CamBoreDiameter = 0.0
rep = design_report(cam)
RESULT["undercut"] = [rep.ok, rep.error, rep.rows]
cam.FollowerRollerRadius = 5.0
cam.CamBoreDiameter = 40.0
RESULT["bad"] = [design_report(cam).ok, design_report(cam).error]
"""


def test_check_design_report(tmp_path, fc_home):
    """Check design reports the paper's cam buildable with its numbers (compared with the
    summary computed here) but failing the 30° pressure-angle limit (46.24°: the paper's
    case 2 cam), the undercut with its cam angle, and a bad field by name."""
    from cam_workbench.generators import design_cam
    from cam_workbench.generators.spec.examples import example_spec

    r = run_freecadcmd(CHECK, tmp_path, fc_home).check().result
    assert r["ok"] is False and r["failed"] == ["pressure_angle"] and r["buildable"] is True
    rows = {(g, item): (value, status) for g, item, value, status in r["rows"]}
    s = design_cam(example_spec("paper")).summary()
    assert rows[("Pitch curve", "PH quintic segments M")][0] == "60"
    assert rows[("Pressure angle", "max |φ| (design)")][0].startswith(f"{s['pressure_angle']['max_deg']:.3f}°")
    assert rows[("FreeCAD solid", "valid, one solid")] == ("yes", "pass")
    rel = float(rows[("FreeCAD solid", "kernel volume vs exact")][0].split()[0])
    assert rel < 1e-9
    ok, error, urows = r["undercut"]
    assert ok is False and "undercut" in error and "at cam angle" in error
    assert urows[0][3] == "FAIL"
    assert r["bad"][0] is False
    assert r["bad"][1].startswith("CamBoreDiameter (cam.bore_diameter): must be < 2 × smallest "
                                  "cam-surface radius"), r["bad"]


PLOT = """
import FreeCAD
from cam_workbench.freecad.feature import create, build
from cam_workbench.freecad.plots import kinematics_figure, kinematics_data, save_figure
doc = FreeCAD.newDocument("plot")
from cam_workbench.generators.spec.examples import example_dict
cam = create(doc, example_dict("paper"))  # the paper's cam: these tests check its numbers
doc.recompute()
design, scale, _ = build(cam, solid=False)
d = kinematics_data(design)
RESULT["max_v"] = float(abs(d["v"]).max())
RESULT["max_dev"] = float(abs(d["deviation"]).max())
save_figure(kinematics_figure(design), PNG)
import matplotlib
RESULT["matplotlib"] = matplotlib.__version__
"""


def test_kinematics_plot_in_freecads_python(tmp_path, artifacts, fc_home):
    """matplotlib is there in FreeCAD's Python; the plot's data agree with the closed form
    (cycloidal rise h = 20 mm over β = 120° at 60 rpm: v_max = 2h·ω/β) and the deviation
    with the design's; the PNG is kept as a test artefact."""
    from cam_workbench.generators import design_cam
    from cam_workbench.generators.spec.examples import example_spec

    png = artifacts / "freecad_kinematics.png"
    r = run_freecadcmd(f"PNG = {str(png)!r}\n" + PLOT, tmp_path, fc_home).check().result
    omega, beta = 2 * math.pi, math.radians(120)
    assert r["max_v"] == pytest.approx(2 * 20.0 * omega / beta, rel=1e-6)
    dev = design_cam(example_spec("paper")).max_deviation[0]
    assert r["max_dev"] == pytest.approx(dev, rel=0.05)
    assert png.stat().st_size > 20_000


LATER_SECTION = """
from dataclasses import dataclass
from cam_workbench.generators.spec.params import param
from cam_workbench.generators import spec as S

@dataclass(frozen=True, kw_only=True)
class Extra:
    '''`[extra]`: a section declared after the workbench was written.'''
    gain: float = param("A required gain", gt=0, group="Extra")
    clearance: float | None = param("A clearance that may be zero", unit="length", ge=0,
                                    optional=True, group="Extra")
    points: tuple = param("Lengths", kind="floats", unit="length", default=(), group="Extra")

S.SECTIONS["extra"] = (Extra, False, False)
import FreeCAD
from cam_workbench.freecad.feature import create
from cam_workbench.freecad import properties as P
doc = FreeCAD.newDocument("later")
from cam_workbench.generators.spec.examples import example_dict
cam = create(doc, example_dict("paper"))  # the paper's cam: these tests check its numbers
RESULT["props"] = sorted((n, cam.getGroupOfProperty(n), cam.getTypeIdOfProperty(n))
                         for n in cam.PropertiesList if n.startswith("Extra"))
RESULT["off"] = "extra" in P.spec_dict(cam)
cam.ExtraEnabled = True
cam.ExtraGain = 2.5
RESULT["on_absent"] = P.spec_dict(cam)["extra"]
cam.ExtraClearanceEnabled = True
cam.ExtraPoints = [25.4, 50.8]
cam.Units = "in"
RESULT["on"] = P.spec_dict(cam)["extra"]
"""


def test_a_section_declared_later_becomes_properties_in_freecad(tmp_path, fc_home):
    """A section declared after the fact (as [checks], [machining] will be) becomes grouped
    properties of a new feature; an optional section with a required field is switched by
    ``<Section>Enabled``, an optional field that may be 0 by ``<Property>Enabled``; list
    lengths convert to the spec's units."""
    r = run_freecadcmd(LATER_SECTION, tmp_path, fc_home).check().result
    assert [tuple(p) for p in r["props"]] == [
        ("ExtraClearance", "Extra", "App::PropertyLength"),
        ("ExtraClearanceEnabled", "Extra", "App::PropertyBool"),
        ("ExtraEnabled", "Extra", "App::PropertyBool"),
        ("ExtraGain", "Extra", "App::PropertyFloatConstraint"),
        ("ExtraPoints", "Extra", "App::PropertyFloatList"),
    ]
    assert r["off"] is False
    assert r["on_absent"] == {"gain": 2.5, "points": []}
    assert r["on"] == {"gain": 2.5, "clearance": 0.0, "points": [1.0, 2.0]}


FIRST_BUILD_FAILS = """
import FreeCAD
from cam_workbench.freecad.feature import create
doc = FreeCAD.newDocument("first")
cam = create(doc, SPEC)
doc.recompute()
RESULT["status"] = cam.Status
RESULT["null"] = cam.Shape.isNull()
RESULT["objects"] = [o.Name for o in doc.Objects]
"""


def test_cam_that_cannot_be_made_reports_with_angle(tmp_path, fc_home):
    """A valid spec whose cam cannot be made (undercut) reports the library's refusal — the
    cam angle where the design checks find the smallest convex pitch radius — and says there
    is no shape yet; the document keeps the feature so the user can fix it."""
    from cam_workbench.generators import design_cam
    from cam_workbench.generators.checks.design import run_checks
    from cam_workbench.generators.errors import GeometryError

    spec = copy.deepcopy(PAPER_SPEC_DICT)
    spec["cam"]["bore_diameter"] = 0.0
    spec["follower"]["roller_radius"] = 21.5
    with pytest.raises(GeometryError) as refused:  # the library's own refusal, computed here
        design_cam(CamSpec.from_dict(spec))
    at = run_checks(CamSpec.from_dict(spec))["curvature"].at_deg
    assert f"undercut at cam angle {at:.3f}°" in str(refused.value)
    run = run_freecadcmd(f"SPEC = {spec!r}\n" + FIRST_BUILD_FAILS, tmp_path, fc_home).check()
    r = run.result
    assert r["status"].startswith(f"error: the cam cannot be made: undercut at cam angle {at:.3f}°")
    assert r["null"] is True
    assert r["objects"] == ["Cam", "CamPitchCurve", "CamBaseCircle", "CamFollower"]
    assert f"Cam: the cam cannot be made: {refused.value}" in run.console
    assert "no shape yet." in run.console and "Traceback" not in run.console

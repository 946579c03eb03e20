"""Documents saved by older versions of the workbench open in the current one.

The fixtures were written by the old code itself (``tests/fixtures/freecad_old_documents.py``
says how): ``freecad_round1_default.FCStd`` by issue 6 round one (commit 341cca2, feature
version 1, before ``[material]``, ``[checks]``, ``[machining]`` and the follower's load
fields existed) and ``freecad_v1_plain_numbers.FCStd`` by main at 8d26f7b (feature version 1,
forces, stresses, feeds, masses and spring rates as plain numbers in the spec's units);
``freecad_v3_followers.FCStd`` by main at 2017c68 (feature version 3, an oscillating follower's
degrees stored as lengths, torques and inertias in the spec's units).
The expected specs are written here from what the fixture script did, and the expected
volumes come from the CadQuery build of those specs in this process.
"""
from __future__ import annotations

import json
import re

import pytest

from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.freecad import properties as P
from cam_workbench.generators.spec import load_spec

from .conftest import ROOT, requires_ocp
from .freecad_support import fc_home, requires_freecad_gui, requires_freecadcmd, run_freecad_gui, run_freecadcmd  # noqa: F401

pytestmark = requires_freecadcmd

FIXTURES = ROOT / "tests" / "fixtures"

OPEN = """
import FreeCAD, shutil
from cam_workbench.freecad import properties as P
shutil.copy(SRC, PATH)
doc = FreeCAD.openDocument(PATH)
for o in doc.Objects:
    if type(getattr(o, "Proxy", None)).__name__ != "CamFeature":
        continue
    r = RESULT[o.Name] = {"restored_volume": o.Shape.Volume, "version": o.Version,
                         "types": {n: o.getTypeIdOfProperty(n) for n in TYPES},
                         "raw": {n: float(getattr(getattr(o, n), "Value", getattr(o, n))) for n in TYPES}}
    o.touch()
r = None
doc.recompute()
for o in doc.Objects:
    if o.Name in RESULT:
        RESULT[o.Name].update(status=o.Status, volume=o.Shape.Volume, valid=o.Shape.isValid(),
                              curves_choices=o.getEnumerationsOfProperty("DrawingCurves"),
                              spec=P.spec_dict(o), tip=o.getDocumentationOfProperty("FollowerPreload"),
                              tip_thickness=o.getDocumentationOfProperty("CamThickness"))
doc.save()
FreeCAD.closeDocument(doc.Name)
FreeCAD.Console.PrintMessage("=== reopened\\n")
doc = FreeCAD.openDocument(PATH)
for o in doc.Objects:
    if o.Name in RESULT:
        RESULT[o.Name]["again"] = {"version": o.Version, "spec": P.spec_dict(o)}
"""
TYPES = ("FollowerPreload", "FollowerMass", "FollowerSpringRate", "MachiningFeedRate",
         "MaterialAllowableStress", "CamThickness")


def _open(tmp_path, fc_home, fixture: str):
    head = (f"SRC = {str(FIXTURES / fixture)!r}\nPATH = {str(tmp_path / fixture)!r}\n"
            f"TYPES = {TYPES!r}\n")
    run = run_freecadcmd(head + OPEN, tmp_path / "run", fc_home).check()
    first, _, second = run.console.partition("=== reopened")
    return run.result, first, second


def _same(spec_dict: dict, spec) -> bool:
    return json.loads(json.dumps(spec_dict)) == json.loads(json.dumps(spec.to_dict()))


#: what an old document stored for the fields whose defaults changed since: the exact SPLINE (the
#: default drawing.curves until "cubic") and the title "Plate cam" (the body's name since)
OLD_DRAWING = {"drawing.curves": "spline", "drawing.title": "Plate cam"}


NEW_TYPES = {"FollowerPreload": "App::PropertyForce", "FollowerMass": "App::PropertyFloatConstraint",
             "FollowerSpringRate": "App::PropertyFloatConstraint", "MachiningFeedRate": "App::PropertySpeed",
             "MaterialAllowableStress": "App::PropertyPressure", "CamThickness": "App::PropertyLength"}


@requires_ocp
def test_round_one_document_opens_and_gains_the_new_sections(tmp_path, fc_home):
    """Round one's document (version 1, no [material]/[checks]/[machining] properties) is
    upgraded to version 2: the new properties are added with the values an absent field has,
    so the spec — and the cam — are what was saved (CamThickness 8, rise law poly345)."""
    from cam_workbench import PlateCam

    res, first, second = _open(tmp_path, fc_home, "freecad_round1_default.FCStd")
    r = res["PlateCam"]
    expected = example_spec("paper").replace(**{"cam.thickness": 8.0, "motion[1].law": "poly345", **OLD_DRAWING})
    assert r["version"] == 5 and r["types"] == NEW_TYPES
    # a choice added since is offered; the stored one is kept
    assert r["curves_choices"] == ["cubic", "spline", "arcs", "polyline"]
    assert _same(r["spec"], expected), r["spec"]
    vol = PlateCam(expected).volume
    assert r["status"] == "ok" and r["valid"]
    assert abs(r["restored_volume"] - vol) / vol < 1e-9      # the shape stored in the file
    assert abs(r["volume"] - vol) / vol < 1e-9               # rebuilt by the current code
    line = next(x for x in first.splitlines() if x.startswith("PlateCam: upgraded from feature version 1 (added "))
    added = line.split("(added ", 1)[1].rstrip(")").split(", ")
    # the properties of every field declared after round one, and only properties of fields
    assert {"FollowerRollerWidth", "MachiningFeedRate", "ChecksMaxPressureAngle"} <= set(added), added
    assert set(added) <= set(P.iter_property_names()), set(added) - set(P.iter_property_names())
    assert "Traceback" not in first + second
    assert r["again"]["version"] == 5 and _same(r["again"]["spec"], expected)
    assert "upgraded" not in second  # saved by version 2: nothing to do
    # tooltips are stored in the document: the old wording is replaced by the current one
    assert 'a FreeCAD quantity (type e.g. "12 in")' in r["tip_thickness"]


@requires_ocp
def test_plain_number_document_is_converted_to_units(tmp_path, fc_home):
    """Version 1 kept forces, stresses, feeds, masses and spring rates as plain numbers in the
    spec's units; version 2 stores them as FreeCAD quantities / kg / N/mm.  The migration
    converts with the document's Units, so the thesis' Example 5 (inches: 340 lbf, 0.02
    lbf·s²/in, 250 000 psi) and a mm cam (50 N, 0.5 kg, 2 N/mm, 450 mm/min, 900 MPa) keep
    their specs exactly."""
    from cam_workbench import PlateCam

    res, first, second = _open(tmp_path, fc_home, "freecad_v1_plain_numbers.FCStd")
    ex5 = load_spec(FIXTURES / "thesis_ex5_final.toml").replace(**OLD_DRAWING)
    loaded = example_spec("paper").replace(**{"follower.preload": 50.0, "follower.mass": 0.5,
                                       "follower.spring_rate": 2.0, "machining.feed_rate": 450.0,
                                       "material.allowable_stress": 900.0, **OLD_DRAWING})
    for name, spec in (("Ex5", ex5), ("Loaded", loaded)):
        r = res[name]
        assert r["version"] == 5 and r["types"] == NEW_TYPES, name
        assert _same(r["spec"], spec), (name, r["spec"])
        assert _same(r["again"]["spec"], spec), name
        vol = PlateCam(spec).volume * (25.4**3 if spec.units == "in" else 1.0)  # FreeCAD: mm³
        assert r["status"] == "ok" and abs(r["volume"] - vol) / vol < 1e-9, name
        line = next(x for x in first.splitlines() if x.startswith(f"{name}: upgraded from feature version 1 ("))
        # fields declared after the file was written are added (e.g. the [optimise] section, the
        # follower kinds' fields), and only properties of fields
        added = line.split("(added ", 1)[1].split(";", 1)[0].split(", ")
        assert {"ChecksConvex", "OptimiseObjective", "FollowerMotion"} <= set(added), line
        assert set(added) <= set(P.iter_property_names()), line
        assert line.endswith("; 9 force, stress, feed, mass and spring-rate properties now in fixed units, "
                             "the spec unchanged)"), line
    # stored in FreeCAD's units: mN, kPa, mm/s; kg and N/mm
    raw = res["Ex5"]["raw"]
    assert raw["FollowerPreload"] == pytest.approx(340 * 4448.2216152605, rel=1e-15)
    assert raw["MaterialAllowableStress"] == pytest.approx(250000 * 6.894757293168361, rel=1e-15)
    assert raw["FollowerMass"] == pytest.approx(0.02 * 175.12683524647636, rel=1e-15)
    raw = res["Loaded"]["raw"]
    assert raw["FollowerPreload"] == 50000.0 and raw["MaterialAllowableStress"] == 900000.0
    assert raw["MachiningFeedRate"] == pytest.approx(7.5) and raw["FollowerSpringRate"] == 2.0
    assert "a FreeCAD quantity" in res["Ex5"]["tip"]  # tooltips follow the current declaration
    assert "Traceback" not in first + second and "upgraded" not in second


OPEN_V3 = """
import FreeCAD, shutil
from cam_workbench.freecad import properties as P
from cam_workbench.freecad.feature import add_reference, reference_of
shutil.copy(SRC, PATH)
doc = FreeCAD.openDocument(PATH)
RAW = ("FollowerArmInertia", "FollowerPreloadTorque", "FollowerSpringTorqueRate", "PitchTolerance", "MaxDeviation")
for name in ("OscIn", "FlatOsc"):
    o = doc.getObject(name)
    RESULT[name] = {"version": o.Version, "restored_volume": o.Shape.Volume, "spec": P.spec_dict(o),
                    "types": {n: o.getTypeIdOfProperty(n) for n in RAW},
                    "raw": {n: float(getattr(getattr(o, n), "Value", getattr(o, n))) for n in RAW},
                    "lifts": list(o.MotionLift), "groups": {n: o.getGroupOfProperty(n) for n in RAW[:3]},
                    "children": sorted(c.Kind for c in o.References)}
    o.touch()
doc.recompute()
for name in ("OscIn", "FlatOsc"):
    o = doc.getObject(name)
    RESULT[name].update(status=o.Status, volume=o.Shape.Volume, max_deviation=o.MaxDeviation.Value)
    # an old cam has no drawn follower: add_reference gives it one
    f = add_reference(o, "follower")
    doc.recompute()
    RESULT[name]["follower"] = {"edges": len(f.Shape.Edges), "again": add_reference(o, "follower").Name == f.Name,
                                "children": sorted(c.Kind for c in o.References), "status": o.Status}
doc.save()
FreeCAD.closeDocument(doc.Name)
FreeCAD.Console.PrintMessage("=== reopened\\n")
doc = FreeCAD.openDocument(PATH)
for name in ("OscIn", "FlatOsc"):
    o = doc.getObject(name)
    RESULT[name]["again"] = {"version": o.Version, "spec": P.spec_dict(o),
                             "follower_edges": len(reference_of(o, "follower").Shape.Edges)}
"""


def _v3_expected() -> dict:
    """The two cams ``tests/fixtures/freecad_old_documents.py`` saved with feature version 3."""
    import copy

    from cam_workbench.generators.spec import DEFAULT_SPEC_DICT

    osc = copy.deepcopy(DEFAULT_SPEC_DICT)
    osc["units"] = "in"
    osc["cam"].update(base_radius=1.6, thickness=0.4, bore_diameter=0.5)
    osc["follower"] = {"kind": "roller", "motion": "oscillating", "pivot_distance": 2.4, "arm_length": 1.8,
                       "roller_radius": 0.3, "arm_inertia": 0.02, "preload_torque": 7.0, "spring_torque_rate": 4.0}
    osc["pitch"] = {"tolerance": 0.002}
    flat = copy.deepcopy(DEFAULT_SPEC_DICT)
    flat["cam"].update(base_radius=40.0)
    flat["follower"] = {"kind": "flat", "motion": "oscillating", "pivot_distance": 70.0, "face_offset": 5.0,
                        "face_width": 60.0, "arm_inertia": 2000.0, "preload_torque": 800.0}
    for spec, lift, law in ((osc, 15.0, "harmonic"), (flat, 12.0, "cycloidal")):
        for m in spec["motion"]:
            if "lift" in m:
                m["lift"], m["law"] = lift, law
    return {"OscIn": osc, "FlatOsc": flat}


def test_v3_follower_document_is_converted(tmp_path, fc_home):
    """Version 3 (main at 2017c68) stored an oscillating follower's lifts — degrees — scaled by
    25.4 in an inch document as if they were inches, ``PitchTolerance`` as a length and torques,
    torsional rates and arm inertias as plain numbers in the spec's units.  Version 4 converts
    them so the specs — and the cams — are those saved: an inch oscillating roller (15° lifts,
    0.002° tolerance, 7 lbf·in, 0.02 lbf·in·s²) and a mm oscillating flat face; the tolerance and
    the deviation become angles, the load moves to "Follower load", and an old cam gets a drawn
    follower through ``add_reference``."""
    from cam_workbench.generators import design_cam
    from cam_workbench.generators.spec import CamSpec

    fixture = "freecad_v3_followers.FCStd"
    head = f"SRC = {str(FIXTURES / fixture)!r}\nPATH = {str(tmp_path / fixture)!r}\n"
    run = run_freecadcmd(head + OPEN_V3, tmp_path / "run", fc_home).check()
    first, _, second = run.console.partition("=== reopened")
    res = run.result
    lbf_n = 0.45359237 * 9.80665
    for name, spec in _v3_expected().items():
        r = res[name]
        expected = CamSpec.from_dict(spec).replace(**OLD_DRAWING)
        assert r["version"] == 5, name
        assert _same(r["spec"], expected), (name, r["spec"])
        assert _same(r["again"]["spec"], expected) and r["again"]["version"] == 5, name
        design = design_cam(expected)
        k = 25.4 if spec["units"] == "in" else 1.0
        vol = design.volume * k**3
        assert abs(r["restored_volume"] - vol) / vol < 1e-9, name   # the shape version 3 built
        assert r["status"] == "ok" and abs(r["volume"] - vol) / vol < 1e-9, name
        assert r["types"]["PitchTolerance"] == r["types"]["MaxDeviation"] == "App::PropertyAngle", name
        assert r["max_deviation"] == pytest.approx(design.max_deviation[0], rel=1e-9), name   # degrees
        assert r["lifts"] == [0.0, spec["motion"][1]["lift"], 0.0, spec["motion"][3]["lift"], 0.0], name
        assert set(r["groups"].values()) == {"Follower load"}, name
        assert r["children"] == ["base circle", "pitch curve"], name
        f = r["follower"]
        assert f["edges"] > 0 and f["again"] and f["status"] == "ok"
        assert f["children"] == ["base circle", "follower", "pitch curve"]
        assert r["again"]["follower_edges"] == f["edges"]
    raw = res["OscIn"]["raw"]
    assert raw["FollowerArmInertia"] == pytest.approx(0.02 * lbf_n * 0.0254e6, rel=1e-14)     # kg·mm²
    assert raw["FollowerPreloadTorque"] == pytest.approx(7.0 * lbf_n * 25.4, rel=1e-14)       # N·mm
    assert raw["FollowerSpringTorqueRate"] == pytest.approx(4.0 * lbf_n * 25.4, rel=1e-14)    # N·mm/rad
    assert raw["PitchTolerance"] == 0.002                                                      # degrees
    assert res["FlatOsc"]["raw"]["FollowerArmInertia"] == 2000.0
    # the message names the properties added since (newer fields) and counts the converted ones
    for name, count in (("OscIn", 5), ("FlatOsc", 1)):
        m = re.search(name + r": upgraded from feature version 3 \((?:added [^;\n]*; )?(\d+) lift, torque and "
                      r"arm-inertia properties now in fixed units, the spec unchanged\)", first)
        assert m and int(m.group(1)) == count, (name, [ln for ln in first.splitlines() if "upgraded" in ln])
    assert "Traceback" not in first + second and "upgraded" not in second


OPEN_V4 = """
import FreeCAD, shutil, zipfile, re
from cam_workbench.freecad import feature, properties as P
shutil.copy(SRC, PATH)
RESULT["freecad"] = ".".join(FreeCAD.Version()[:3])
doc = FreeCAD.openDocument(PATH)
for name in NAMES:
    o = doc.getObject(name)
    RESULT[name] = {"version": o.Version, "proxy": [type(o.Proxy).__module__, type(o.Proxy).__name__],
                    "is_cam": feature.is_cam(o), "restored_volume": o.Shape.Volume,
                    "children": sorted(type(c.Proxy).__name__ + " " + c.Kind for c in feature.references_of(o))}
    o.touch()
doc.recompute()
for name in NAMES:
    o = doc.getObject(name)
    RESULT[name].update(status=o.Status, volume=o.Shape.Volume, valid=o.Shape.isValid(), spec=P.spec_dict(o))
new = feature.create(doc)
doc.recompute()
RESULT["new"] = {"name": new.Name, "label": new.Label, "status": new.Status,
                 "children": [c.Name for c in feature.references_of(new)]}
doc.save()
FreeCAD.closeDocument(doc.Name)
with zipfile.ZipFile(PATH) as z:
    RESULT["saved_proxies"] = sorted(set(re.findall(r'module="([^"]+)" class="([^"]+)"',
                                                    z.read("Document.xml").decode())))
FreeCAD.Console.PrintMessage("=== reopened\\n")
doc = FreeCAD.openDocument(PATH)
for name in NAMES:
    o = doc.getObject(name)
    RESULT[name]["again"] = {"version": o.Version, "proxy": type(o.Proxy).__name__, "spec": P.spec_dict(o)}
"""
#: The cams ``tests/fixtures/freecad_old_documents.py`` saved as ``v4_plate_cam`` (main at ae6b08d),
#: and the volume tolerance of each: a plate cam's solid is exact, a cylindrical cam's walls are
#: B-spline surfaces fitted to the exact offsets (``test_freecad_cylindrical.py``: 1e-6)
V4_CAMS = {"PlateCam": ("default", 1e-9), "Cylindrical": ("cylindrical", 1e-6)}


def test_v4_plate_cam_document_opens_as_cam(tmp_path, fc_home):
    """A document saved by main before the feature was named for every body (feature version 4:
    proxies ``cam_workbench.freecad.feature.PlateCamFeature`` and ``PlateCamReference``) opens:
    each proxy is restored as a ``CamFeature`` (``CamReference``), the cam recomputes to the
    cam it was saved with — a plate cam and a cylindrical one —, the report view says what
    changed, and the saved document names the new classes only (read from its Document.xml)."""
    from cam_workbench.generators import design_cam
    from cam_workbench.generators.spec import CamSpec

    fixture = "freecad_v4_plate_cam.FCStd"
    head = (f"SRC = {str(FIXTURES / fixture)!r}\nPATH = {str(tmp_path / fixture)!r}\n"
            f"NAMES = {list(V4_CAMS)!r}\n")
    run = run_freecadcmd(head + OPEN_V4, tmp_path / "run", fc_home).check()
    first, _, second = run.console.partition("=== reopened")
    res = run.result
    print(f"FreeCAD {res['freecad']}:", *[ln for ln in first.splitlines() if ln.startswith(tuple(V4_CAMS))],
          sep="\n  ")
    for name, (example, rel) in V4_CAMS.items():
        r = res[name]
        spec = example_spec(example)
        assert r["version"] == 5 and r["is_cam"], name
        assert r["proxy"] == ["cam_workbench.freecad.feature", "CamFeature"], name
        assert r["children"] == ["CamReference base circle", "CamReference follower", "CamReference pitch curve"]
        assert _same(r["spec"], spec), (name, r["spec"])
        vol = design_cam(CamSpec.from_dict(r["spec"])).volume
        assert r["status"] == "ok" and r["valid"], (name, r["status"])
        assert abs(r["restored_volume"] - vol) / vol < rel, name     # the shape ae6b08d built
        assert abs(r["volume"] - vol) / vol < rel, name              # rebuilt by this code
        assert (f"{name}: a PlateCamFeature is now a CamFeature, the feature of every body; saved, the "
                "document needs feature version 5 or later") in first, name
        assert r["again"] == {"version": 5, "proxy": "CamFeature", "spec": r["spec"]}, name
    # a new cam in the same document takes the new name
    assert res["new"] == {"name": "Cam", "label": "Cam", "status": "ok",
                          "children": ["CamPitchCurve", "CamBaseCircle", "CamFollower"]}
    assert res["saved_proxies"] == [["cam_workbench.freecad.feature", "CamFeature"],
                                    ["cam_workbench.freecad.feature", "CamReference"]]
    assert "Traceback" not in first + second
    assert "upgraded" not in second and "now a CamFeature" not in second


GUI_V4 = r"""
import sys, shutil, zipfile, re
SRC = {src!r}
PATH = {path!r}
TOML = {toml!r}
R = RESULT
R["start_modules"] = {{m: m in sys.modules for m in ("cam_workbench", "cam_workbench.freecad.view_providers")}}
R["toml_importer"] = FreeCAD.getImportType("toml")

def proxy(o):
    p = o.ViewObject.Proxy
    return None if p is None else type(p).__name__

def views(cam):
    from cam_workbench.freecad.feature import references_of
    return [proxy(cam)] + [proxy(c) for c in references_of(cam)]

def console_cam():
    # a cam made by the API in the Python console, the workbench never activated: no view provider
    from cam_workbench.freecad.feature import create
    doc = FreeCAD.newDocument("Console")
    cam = create(doc)
    doc.recompute()
    R["console_before"] = views(cam)

def open_spec():
    # File > Open of a spec (the cylindrical example), the workbench still not activated
    def fill(w):
        R["open_dialog"] = type(w).__name__
        w.findChild(QtGui.QLineEdit, "fileNameEdit").setText(TOML)
        w.accept()
        if w.isVisible():   # never leave a modal dialog behind: the test would hang
            R["open_dialog_refused"] = True
            w.reject()
    when_modal(fill, QtGui.QFileDialog)
    FreeCADGui.runCommand("Std_Open")

def opened_spec():
    doc = FreeCAD.ActiveDocument
    if doc is None or doc.Name == "Console" or doc.getObject("Cam") is None:
        raise NotYet("the spec's document")
    cam = doc.getObject("Cam")
    R["spec_doc"] = {{"status": cam.Status, "volume": cam.Shape.Volume, "views": views(cam),
                     "objects": [o.Name for o in doc.Objects]}}
    R["console_after"] = views(FreeCAD.getDocument("Console").getObject("Cam"))  # given by the importer

def open_v4():
    shutil.copy(SRC, PATH)
    doc = FreeCAD.openDocument(PATH)
    R["v4"] = {{}}
    for name in ("PlateCam", "Cylindrical"):
        cam = doc.getObject(name)
        R["v4"][name] = {{"views": views(cam), "icon": os.path.basename(cam.ViewObject.Proxy.getIcon()),
                         "tree": [o.Name for o in cam.ViewObject.claimChildren()]}}
        cam.touch()
    doc.recompute()
    for name in ("PlateCam", "Cylindrical"):
        cam = doc.getObject(name)
        R["v4"][name].update(status=cam.Status, volume=cam.Shape.Volume, version=cam.Version)

def activate():
    FreeCADGui.activateWorkbench("CamWorkbench")
    wb = FreeCADGui.activeWorkbench()
    R["workbench"] = [wb.name(), wb.MenuText]
    R["menus"] = [a.text().replace("&", "") for a in mw.menuBar().actions()]
    tb = [t for t in mw.findChildren(QtGui.QToolBar) if t.windowTitle() == "Cam"]
    R["toolbar"] = [a.text() for a in tb[0].actions()] if tb else []

def new_cam():
    doc = FreeCAD.ActiveDocument   # the document just opened
    FreeCADGui.runCommand("CamWorkbench_NewCam")
    cam = doc.getObject("Cam")
    R["new"] = {{"document": doc.FileName == PATH, "label": cam.Label, "status": cam.Status, "views": views(cam)}}

def save():
    doc = FreeCAD.ActiveDocument
    doc.save()
    with zipfile.ZipFile(PATH) as z:
        R["saved"] = {{part: sorted(set(re.findall(r'module="([^"]+)" class="([^"]+)"', z.read(part).decode())))
                      for part in ("Document.xml", "GuiDocument.xml")}}
    R["report"] = report_text()

steps = [(console_cam, 200), (open_spec, 200), (opened_spec, 200), (open_v4, 500), (activate, 500),
         (new_cam, 500), (save, 200)]
"""


@requires_freecad_gui
def test_v4_plate_cam_document_in_the_gui(tmp_path, fc_home):
    """In the GUI: the document saved by main before the rename (its GuiDocument.xml names
    ``ViewProviderPlateCam``) opens with ``ViewProviderCam`` and the tree of each cam; the
    workbench is "Cam Workbench" with a "Cam" menu and toolbar ("New cam"); a spec opened with
    File > Open before the workbench was ever activated gets its view providers (the GUI's
    importer, ``spec_io_gui``), and so does a cam made by the API in the Python console before;
    saved, the document names only the new classes.  Start-up loads none of the package."""
    from cam_workbench.generators import design_cam
    from cam_workbench.generators.spec import to_toml

    toml = tmp_path / "cylindrical.toml"
    toml.write_text(to_toml(example_spec("cylindrical")))
    fixture = "freecad_v4_plate_cam.FCStd"
    body = GUI_V4.format(src=str(FIXTURES / fixture), path=str(tmp_path / fixture), toml=str(toml))
    run = run_freecad_gui(body, tmp_path, fc_home)
    r = run.check().result
    assert r["start_modules"] == {"cam_workbench": False, "cam_workbench.freecad.view_providers": False}
    assert "cam_workbench.freecad.spec_io_gui" in str(r["toml_importer"]), r["toml_importer"]
    assert r["console_before"] == [None, None, None, None]
    assert r["open_dialog"] == "QFileDialog" and "open_dialog_refused" not in r
    cam_views = ["ViewProviderCam"] + ["ViewProviderReference"] * 3
    spec_doc = r["spec_doc"]
    assert spec_doc["views"] == cam_views and spec_doc["status"] == "ok"
    assert spec_doc["objects"] == ["Cam", "CamPitchCurve", "CamBaseCircle", "CamFollower"]
    exact = design_cam(example_spec("cylindrical")).volume
    assert abs(spec_doc["volume"] - exact) / exact < 1e-6
    assert r["console_after"] == cam_views
    for name, (example, rel) in V4_CAMS.items():
        v = r["v4"][name]
        assert v["views"] == cam_views and v["icon"] == "Cam.svg", name
        assert v["tree"] == [f"{name}PitchCurve", f"{name}BaseCircle", f"{name}Follower"], name
        exact = design_cam(example_spec(example)).volume
        assert v["status"] == "ok" and v["version"] == 5 and abs(v["volume"] - exact) / exact < rel, name
    assert r["workbench"] == ["CamWorkbench", "Cam Workbench"]
    assert "Cam" in r["menus"]
    assert r["toolbar"][0] == "New cam"
    assert r["new"] == {"document": True, "label": "Cam", "status": "ok", "views": cam_views}
    assert r["saved"] == {"Document.xml": [["cam_workbench.freecad.feature", "CamFeature"],
                                           ["cam_workbench.freecad.feature", "CamReference"]],
                          "GuiDocument.xml": [["cam_workbench.freecad.view_providers", "ViewProviderCam"],
                                              ["cam_workbench.freecad.view_providers", "ViewProviderReference"]]}
    report = r["report"]
    assert "PlateCam: a PlateCamFeature is now a CamFeature" in report
    assert "Traceback" not in report and "Traceback" not in run.console

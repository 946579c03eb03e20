"""Documents saved by older versions of the workbench open in the current one.

The fixtures were written by the old code itself (``tests/fixtures/freecad_old_documents.py``
says how): ``freecad_round1_default.FCStd`` by issue 6 round one (commit 341cca2, feature
version 1, before ``[material]``, ``[checks]``, ``[machining]`` and the follower's load
fields existed) and ``freecad_v1_plain_numbers.FCStd`` by main at 8d26f7b (feature version 1,
forces, stresses, feeds, masses and spring rates as plain numbers in the spec's units).
The expected specs are written here from what the fixture script did, and the expected
volumes come from the CadQuery build of those specs in this process.
"""
from __future__ import annotations

import json

import pytest

from generators.spec.examples import example_spec
from cam_workbench.freecad import properties as P
from generators.spec import load_spec

from .conftest import ROOT, requires_ocp
from .freecad_support import fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401

pytestmark = requires_freecadcmd

FIXTURES = ROOT / "tests" / "fixtures"

OPEN = """
import FreeCAD, shutil
from cam_workbench.freecad import properties as P
shutil.copy(SRC, PATH)
doc = FreeCAD.openDocument(PATH)
for o in doc.Objects:
    if type(getattr(o, "Proxy", None)).__name__ != "PlateCamFeature":
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
    expected = example_spec("paper").replace(**{"cam.thickness": 8.0, "motion[1].law": "poly345"})
    assert r["version"] == 3 and r["types"] == NEW_TYPES
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
    assert r["again"]["version"] == 3 and _same(r["again"]["spec"], expected)
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
    ex5 = load_spec(FIXTURES / "thesis_ex5_final.toml")
    loaded = example_spec("paper").replace(**{"follower.preload": 50.0, "follower.mass": 0.5,
                                       "follower.spring_rate": 2.0, "machining.feed_rate": 450.0,
                                       "material.allowable_stress": 900.0})
    for name, spec in (("Ex5", ex5), ("Loaded", loaded)):
        r = res[name]
        assert r["version"] == 3 and r["types"] == NEW_TYPES, name
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

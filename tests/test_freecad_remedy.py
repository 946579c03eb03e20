"""FreeCAD's Check design says how a failing check passes (issue 20, item 3): the remedies of
report.json's ``checks.results[name].remedy``, computed inside FreeCAD's own Python (0.20 here),
each field named as its property — and a cam that cannot be made (a groove's rim wall) gets its
disc diameter.  Compared with the library's remedies computed in this (pytest) process."""
from __future__ import annotations

import json

import pytest

from cam_workbench.generators.checks.design import run_checks
from cam_workbench.generators.spec.examples import example_dict, example_spec
from cam_workbench.generators.studies.remedies import add_remedies, refusal_remedies

from .freecad_support import fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401

pytestmark = requires_freecadcmd

CHECK = """
import FreeCAD
from cam_workbench.freecad.feature import create
from cam_workbench.freecad.check_design import design_report
from cam_workbench.generators.spec.examples import example_dict
doc = FreeCAD.newDocument("remedy")
cam = create(doc, example_dict("paper"))           # 46.2° > 30°
doc.recompute()
rep = design_report(cam)
RESULT["paper"] = {"ok": rep.ok, "remedies": rep.remedies, "text": rep.text(),
                   "remedy": rep.checks_dict["results"]["pressure_angle"].get("remedy")}
groove = example_dict("groove")
groove["cam"]["outer_diameter"] = 120.0
g = create(doc, groove, name="Groove")
doc.recompute()
rep = design_report(g)
RESULT["groove"] = {"ok": rep.ok, "error": rep.error, "remedies": rep.remedies, "text": rep.text()}
"""


def test_check_design_shows_the_remedies(tmp_path, fc_home):
    r = run_freecadcmd(CHECK, tmp_path, fc_home).check().result
    paper = example_spec("paper")
    here = add_remedies(run_checks(paper).to_dict(), paper)["results"]["pressure_angle"]["remedy"]
    p = r["paper"]
    assert p["ok"] is False and p["remedy"] == json.loads(json.dumps(here))    # the library's, in FreeCAD
    assert here["command"] == "--set cam.base_radius=42.80"
    text = here["text"].replace("cam.base_radius", "CamBaseRadius (cam.base_radius)", 1)
    assert p["remedies"] == [f"pressure angle: {text}"]
    assert f"  to pass: pressure angle: {text}" in p["text"].splitlines()
    g = r["groove"]
    spec = example_spec("groove").replace(**{"cam.outer_diameter": 120.0})
    from cam_workbench.generators.cam_design import design_cam
    from cam_workbench.generators.errors import GeometryError

    with pytest.raises(GeometryError) as refused:
        design_cam(spec)
    rim = refusal_remedies(spec, refused.value)["rim_wall"]
    assert rim["field"] == "cam.outer_diameter" and rim["value"] == 142.11
    assert g["ok"] is False and "rim" in g["error"]
    assert g["remedies"] == ["rim wall: " + rim["text"].replace("cam.outer_diameter",
                                                              "CamOuterDiameter (cam.outer_diameter)", 1)]

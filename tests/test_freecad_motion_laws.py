"""The polynomial, constant-velocity and table laws in a real FreeCAD (``freecadcmd``): their list
fields (a polynomial's ``points``, a ``table``) are text rows of the motion list properties, the
feature builds the same cam as this process, and the rows survive a unit switch."""
from __future__ import annotations

import json

import pytest

from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.spec.examples import example_dict

from .conftest import requires_ocp
from .freecad_support import fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401

pytestmark = requires_freecadcmd


def _spec() -> dict:
    d = example_dict("packaging")
    d["motion"][1]["points"] = [[22.5, 1.9]]
    d["motion"][2].update(law="constant_velocity")
    d["motion"][5] = {"kind": "return", "angle": 100.0, "lift": 30.0, "law": "table", "table_tolerance": 0.01,
                      "table": [[float(a), 30.0 * (1 - (10 * (a / 100) ** 3 - 15 * (a / 100) ** 4 + 6 * (a / 100) ** 5))]
                                for a in range(0, 101, 5)]}
    return d


BODY = """
import FreeCAD
from cam_workbench.freecad.feature import create
from cam_workbench.freecad import properties as P
doc = FreeCAD.newDocument("laws")
cam = create(doc, SPEC)
doc.recompute()
RESULT["status"] = cam.Status
RESULT["volume"] = cam.Shape.Volume
RESULT["points"] = list(cam.MotionPoints)
RESULT["table"] = list(cam.MotionTable)
RESULT["spec"] = P.spec_dict(cam)
cam.Units = "in"
doc.recompute()
RESULT["volume_in"] = cam.Shape.Volume
RESULT["spec_in"] = P.spec_dict(cam)
"""


@requires_ocp
def test_feature_with_points_and_table_rows(tmp_path, fc_home):
    from cam_workbench import PlateCam

    d = _spec()
    r = run_freecadcmd(f"SPEC = {json.dumps(d)}\n" + BODY, tmp_path, fc_home).check().result
    assert r["status"] == "ok"
    assert r["points"][1] == "22.5, 1.9" and r["points"][0] == ""
    assert r["table"][5].startswith("0.0, 30.0; 5.0, ")
    back = CamSpec.from_dict(r["spec"])
    assert back == CamSpec.from_dict(d)
    expected = PlateCam(d).volume
    assert abs(r["volume"] - expected) / expected < 1e-9
    assert abs(r["volume_in"] - r["volume"]) / r["volume"] < 1e-12
    rows = r["spec_in"]["motion"][5]["table"]
    assert rows[1] == [5.0, pytest.approx(d["motion"][5]["table"][1][1] / 25.4, rel=1e-15)]

"""Polynomial point lifts in the FreeCAD optimiser (real ``freecadcmd``): the panel's functions
offer ``motion[k].points`` for a polynomial rise with interior points (and not for a cam without),
the run from the panel's settings gives the library's result, and Apply writes the new lifts into
the feature (the spec read back has them at the same angles)."""
from __future__ import annotations

import pytest

from cam_workbench.generators import load_spec, to_toml
from cam_workbench.generators.optimise import optimise

from .conftest import requires_ocp
from .freecad_support import fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401
from .test_optimiser_points import cam

BODY = """
import FreeCAD
from cam_workbench.generators.spec import to_toml
from cam_workbench.generators.spec.examples import example_dict
from cam_workbench.freecad.feature import create
from cam_workbench.freecad import optimiser as O, properties as P

doc = FreeCAD.newDocument("Poly")
doc.UndoMode = 1
cam = create(doc, SPEC, name="Poly")
doc.recompute()
spec = P.spec_of(cam)
RESULT["choices"] = [[c.token, c.count, c.enabled, c.label] for c in O.variable_choices(spec)]
text = O.variables_text(spec, ["motion[1].points"], "peak_acceleration")
RESULT["text"] = text
s = O.settings_of(spec)
s = O.Settings(**{**s.__dict__, "variables": text, "objective": "peak_acceleration"})
job = O.OptimiseJob(O.run_spec(spec, s)).start()
job.wait()
res = job.result
RESULT["error"] = job.error
RESULT["result"] = {"status": res.status, "feasible": res.feasible, "value": res.value,
                    "variables": list(res.variables), "design": [float(v) for v in res.design]}
O.apply_result(cam, res)
RESULT["after"] = to_toml(P.spec_of(cam))
RESULT["status"] = cam.Status
RESULT["sel"] = sorted(O.selected_tokens(P.spec_of(cam)))
doc2 = FreeCAD.newDocument("Plain")
plain = create(doc2, example_dict("paper"), name="Plain")
RESULT["plain"] = [c.token for c in O.variable_choices(P.spec_of(plain))]
"""


@requires_freecadcmd
@requires_ocp
def test_panel_offers_and_applies_polynomial_points(tmp_path, fc_home):
    spec = cam(variables="base_radius", objective="area")
    body = f"SPEC = {to_toml(spec)!r}\n" + BODY
    r = run_freecadcmd(body, tmp_path / "fc", fc_home).check().result
    assert r["error"] is None
    [point] = [c for c in r["choices"] if c[0] == "motion[1].points"]
    assert point[1:3] == [1, True] and "60°" in point[3]
    assert r["text"] == "motion[1].points"
    assert not any(t.endswith(".points") for t in r["plain"])
    api = optimise(spec.replace(**{"optimise.variables": "motion[1].points",
                                   "optimise.objective": "peak_acceleration"}))
    res = r["result"]
    assert res["variables"] == ["motion[1].points[0]"] and res["feasible"]
    assert res["design"][0] == pytest.approx(float(api.design[0]), abs=1e-9)
    assert res["design"][0] == pytest.approx(5.0, abs=2e-3)
    after = load_spec(r["after"])
    assert after.motion[1].points[0][0] == 60.0
    assert after.motion[1].points[0][1] == pytest.approx(res["design"][0], abs=1e-12)
    assert r["status"] == "ok" and "motion[1].points" in r["sel"]

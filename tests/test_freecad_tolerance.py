"""Issue 25 part 3 in a real FreeCAD (``freecadcmd``): the "Tolerance study…" command's study of a
cam feature is the API's (and so ``cam-workbench tolerance``'s) on the same spec — the same numbers
(FreeCAD's own numpy against the virtual environment's: 1e-9), the same rows — and the command is in
the workbench's menu."""
from __future__ import annotations

import pytest

from cam_workbench.exporters.report_cells import format_number as fmt
from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.tolerance import tolerance_study

from .freecad_support import fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401

pytestmark = requires_freecadcmd

SCRIPT = """
import FreeCAD
from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.freecad.feature import create
from cam_workbench.freecad.tolerance_panel import tolerance_report, table_rows, headline
doc = FreeCAD.newDocument("tol")
cams = {name: create(doc, example_spec(name), name=name.capitalize()) for name in ("default", "oscillating")}
doc.recompute()
for name, cam in cams.items():
    d = tolerance_report(cam, 0.03, 80)
    RESULT[name] = {"summary": d, "rows": table_rows(d), "headline": headline(d)}
cyl = create(doc, example_spec("cylindrical"), name="Barrel")
doc.recompute()
try:
    tolerance_report(cyl)
except Exception as exc:
    RESULT["refused"] = [type(exc).__name__, getattr(exc, "field", None)]
with open(__import__("os").path.join(__import__("cam_workbench").freecad.__path__[0], "commands.py")) as f:
    RESULT["commands_source"] = f.read()
"""


@pytest.fixture(scope="module")
def fc(tmp_path_factory, fc_home):  # noqa: F811
    return run_freecadcmd(SCRIPT, tmp_path_factory.mktemp("tol_run"), fc_home).check().result


@pytest.mark.parametrize("name", ["default", "oscillating"])
def test_freecad_study_is_the_apis(fc, name):
    got = fc[name]["summary"]
    want = tolerance_study(example_spec(name), 0.03, 80).summary()
    assert got["cam"] == want["cam"] and got["spec_digest"] == want["spec_digest"]
    assert [r["waves"] for r in got["table"]] == [r["waves"] for r in want["table"]]
    for key in ("tolerance", "acceleration_tolerance", "contact_tolerance"):
        assert got["chart"][key] == pytest.approx(want["chart"][key], rel=1e-9)
    assert got["chart"]["governed_by"] == want["chart"]["governed_by"]
    assert got["designed_peak_acceleration"] == pytest.approx(want["designed_peak_acceleration"], rel=1e-12)
    rows = fc[name]["rows"]
    assert [r[0] for r in rows] == [str(r["waves"]) for r in got["table"]]
    assert [r[1] for r in rows] == [fmt(r["tolerance"]) for r in got["table"]]
    assert f"tightest t = {fmt(got['tightest']['tolerance'])} mm" in fc[name]["headline"]


def test_freecad_refuses_a_body_without_a_plane_profile(fc):
    assert fc["refused"] == ["SpecError", "cam.body"]


def test_the_command_is_in_the_menu(fc):
    src = fc["commands_source"]
    assert '"CamWorkbench_ToleranceStudy": ToleranceStudy' in src and 'menu_text = "Tolerance study…"' in src

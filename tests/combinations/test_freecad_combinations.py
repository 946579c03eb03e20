"""A sample of the combinations through the FreeCAD feature (a real ``freecadcmd``): the feature
made from the spec either holds one valid solid whose volume is the library's exact
(Green's theorem) area × thickness, or reports a clean refusal in its Status — the same
refusal the library raises — never a traceback or a shape that disagrees."""
from __future__ import annotations

import json

from hypothesis import given, settings

from cam_workbench.generators.errors import CamError, SpecError
from cam_workbench.generators.spec import CamSpec

from ..freecad_support import fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401
from .conftest import examples
from .strategies import cylindrical_specs, specs

pytestmark = requires_freecadcmd

BODY = """
import FreeCAD
from cam_workbench.freecad.feature import create
doc = FreeCAD.newDocument("combo")
cam = create(doc, json.loads(SPEC), name="Cam")
doc.recompute()
s = cam.Shape
RESULT.update(status=cam.Status, null=s.isNull(),
              valid=(not s.isNull()) and s.isValid(), solids=0 if s.isNull() else len(s.Solids),
              volume=0.0 if s.isNull() else s.Volume)
if not s.isNull():
    s.exportBrep(BREP)
"""


@settings(max_examples=examples(8, 80))
@given(specs())
def test_freecad_feature_any_valid_spec(tmp_path_factory, fc_home, d):  # noqa: F811
    _feature_agrees(tmp_path_factory, fc_home, d)


@settings(max_examples=examples(3, 40))
@given(cylindrical_specs())
def test_freecad_cylindrical_any_valid_spec(tmp_path_factory, fc_home, d):  # noqa: F811
    """Cylindrical cams (translating and oscillating rollers) in the feature: FreeCAD's solid holds
    the exact volume, or the feature shows the library's refusal."""
    _feature_agrees(tmp_path_factory, fc_home, d)


def _feature_agrees(tmp_path_factory, fc_home, d) -> None:  # noqa: F811
    from cam_workbench.generators.cam_design import design_cam

    try:
        spec = CamSpec.from_dict(d)
    except SpecError as exc:
        # a drawn program the spec's rules refuse (a polynomial segment dipping below s = 0): the
        # feature's create() refuses it the same way, adding nothing (tests/test_freecad_feature.py)
        assert exc.field and str(exc).startswith(exc.field), str(exc)
        return
    try:
        design = design_cam(spec)
        refusal = None
    except CamError as exc:
        design, refusal = None, str(exc)
    tmp = tmp_path_factory.mktemp("fc_combo")
    brep = tmp / "cam.brep"
    run = run_freecadcmd(f"SPEC = {json.dumps(json.dumps(d))}\nBREP = {str(brep)!r}\n" + BODY, tmp, fc_home).check()
    r = run.result
    assert "Traceback" not in run.console, run.console[-3000:]
    if refusal is not None:
        # the feature says what the library says, and holds no shape
        assert r["status"].startswith("error:") and r["null"], r
        assert refusal.split(":")[0] in r["status"] or refusal[:60] in r["status"], (refusal, r["status"])
        return
    assert r["valid"] and r["solids"] == 1, r
    # FreeCAD models in mm whatever the spec's units; its OCCT integrates B-spline side faces
    # to ~1e-5 relative (measured)
    exact = design.volume * (25.4**3 if spec.units == "in" else 1.0)
    if getattr(design.body, "prismatic", True):
        assert abs(r["volume"] / exact - 1.0) < 5e-5, (r["volume"], exact)
    else:
        # B-spline walls: FreeCAD's Shape.Volume is OCCT's fixed Gauss rule (≈1e-4 on steep walls);
        # FreeCAD's solid, read back here from its BREP, integrated by OCCT's adaptive rule
        assert abs(r["volume"] / exact - 1.0) < 5e-4, (r["volume"], exact)
        assert abs(_adaptive_volume(brep) / exact - 1.0) < 1e-6, (_adaptive_volume(brep), exact)


def _adaptive_volume(path) -> float:
    """Volume of a BREP file by OCCT's adaptive integration (relative error 1e-7)."""
    from cam_workbench.kernel.ocp import read_brep
    from cam_workbench.kernel.solids import kernel_volume

    return kernel_volume(read_brep(path), 1e-7)

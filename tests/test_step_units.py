"""STEP files declare the spec's unit in a FRESH process (OCCT declares its STEP parameters only
when the STEP controller is initialised; set before, they were refused and inch cams came out
as millimetres), read back by OCP and by FreeCAD."""
from __future__ import annotations

import json
import shutil
import subprocess
import sys

import pytest

from .conftest import ROOT, SAFETY_S, requires_ocp

EX5 = ROOT / "tests" / "fixtures" / "thesis_ex5_final.toml"
CLI = [sys.executable, "-m", "cam_workbench.cli"]

#: reads a STEP file in mm in a new interpreter: (bounding-box z extent, volume)
READ_MM = """
import json, sys
from cam_workbench.kernel.step import read_step
from cam_workbench.kernel import ocp as occ, solids as occ_build
shape = read_step(sys.argv[1], "mm")
box = occ.Bnd_Box(); occ.add_to_box(shape, box)
x0, y0, z0, x1, y1, z1 = occ.box_limits(box)
print(json.dumps({"z": z1 - z0, "volume": occ_build.kernel_volume(shape)}))
"""


def _fresh(code: str, *args: str) -> dict:
    res = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, cwd=ROOT,
                         stdin=subprocess.DEVNULL)
    assert res.returncode == 0, res.stderr
    return json.loads(res.stdout.strip().splitlines()[-1])


@requires_ocp
@pytest.mark.parametrize("units", ["in", "mm"])
def test_step_unit_in_a_fresh_process(tmp_path, units):
    from cam_workbench.generators.cam_design import design_cam
    from cam_workbench.generators.spec import load_spec

    spec = load_spec(EX5)
    if units == "mm":
        spec = spec.replace(**{"units": "mm", "cam.base_radius": 4.5 * 25.4, "cam.thickness": 0.25 * 25.4,
                               "follower.roller_radius": 0.5 * 25.4, "cam.bore_diameter": 1.0 * 25.4,
                               **{f"motion[{i}].lift": m.lift * 25.4 for i, m in enumerate(spec.motion)
                                  if m.lift is not None}})
    (tmp_path / "cam.toml").write_text(__import__("cam_workbench.generators.spec", fromlist=["to_toml"]).to_toml(spec))
    # `build` in its own process: the first STEP that process writes
    res = subprocess.run([*CLI, "build", str(tmp_path / "cam.toml"), "-o", str(tmp_path / "o")],
                         capture_output=True, text=True, cwd=ROOT, stdin=subprocess.DEVNULL)
    assert res.returncode == 0, res.stderr
    text = (tmp_path / "o" / "cam.step").read_text()
    if units == "in":
        assert "'INCH'" in text and "CONVERSION_BASED_UNIT" in text
    else:
        assert "'INCH'" not in text and "SI_UNIT(.MILLI.,.METRE.)" in text
    got = _fresh(READ_MM, str(tmp_path / "o" / "cam.step"))
    d = design_cam(spec)
    scale = 25.4 if units == "in" else 1.0
    assert got["z"] == pytest.approx(spec.cam.thickness * scale, rel=1e-6)
    assert got["volume"] == pytest.approx(d.volume * scale**3, rel=1e-5)


@requires_ocp
@pytest.mark.skipif(shutil.which("freecadcmd") is None, reason="FreeCAD (freecadcmd) is not installed")
def test_freecad_reads_an_inch_step_at_its_size(tmp_path):
    """FreeCAD 0.20's STEP importer reads the CLI's inch file in mm at 25.4× the inch numbers."""
    from cam_workbench.generators.cam_design import design_cam
    from cam_workbench.generators.spec import load_spec

    res = subprocess.run([*CLI, "build", str(EX5), "-o", str(tmp_path / "o")], capture_output=True, text=True,
                         cwd=ROOT, stdin=subprocess.DEVNULL)
    assert res.returncode == 0, res.stderr
    script = tmp_path / "read.py"
    out = tmp_path / "fc.json"
    script.write_text(
        "import json, Part\n"
        f"s = Part.read({str(tmp_path / 'o' / 'cam.step')!r})\n"
        f"open({str(out)!r}, 'w').write(json.dumps({{'volume': s.Volume, 'z': s.BoundBox.ZLength}}))\n")
    fc = subprocess.run(["freecadcmd", str(script)], capture_output=True, text=True, timeout=SAFETY_S,
                        stdin=subprocess.DEVNULL, env={"HOME": str(tmp_path), "PATH": "/usr/bin:/bin"})
    assert out.exists(), fc.stdout + fc.stderr
    got = json.loads(out.read_text())
    spec = load_spec(EX5)
    assert got["z"] == pytest.approx(spec.cam.thickness * 25.4, rel=1e-6)
    assert got["volume"] == pytest.approx(design_cam(spec).volume * 25.4**3, rel=1e-4)


@requires_ocp
def test_step_product_is_named_for_the_body(tmp_path):
    """The STEP file's PRODUCT entity (what a CAD system's tree shows) names the cam's body, in
    the file the API's export_step() writes and in the set export() (the CLI's pipeline) writes."""
    import re

    from cam_workbench import PlateCam

    def products(path):
        return re.findall(r"PRODUCT\('([^']*)'", path.read_text())

    PlateCam().export_step(tmp_path / "plate.step")
    assert products(tmp_path / "plate.step") == ["Plate cam"]
    PlateCam.example("groove").export(tmp_path / "groove")
    assert products(tmp_path / "groove" / "cam.step") == ["Groove cam"]

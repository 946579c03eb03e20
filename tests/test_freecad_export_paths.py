"""Exports from FreeCAD to relative paths (user report: ``export(cam, "gcode_xc", "cam_xc.nc")``
said "the command line reported success but cam_xc.nc is missing").

The CLI subprocess runs in a temporary folder of its own, so a relative target must be resolved
against the FreeCAD process's working folder before it is handed over.  Run headless in a real
``freecadcmd`` whose working folder is a fresh temporary one; the files must land there and
equal the CLI's own (run here, in pytest's process, in another folder).
"""
from __future__ import annotations

import subprocess
import sys

from .conftest import SAFETY_S
from .freecad_support import cli_env, fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401

pytestmark = requires_freecadcmd

RELATIVE = """
import FreeCAD, os
from cam_workbench.freecad.feature import create
from cam_workbench.freecad import exports as E
os.chdir(WORK)
doc = FreeCAD.newDocument("rel")
cam = create(doc, None)
doc.recompute()
RESULT["cwd"] = os.getcwd()
out = {}
for key, kind, target in (("xc", "gcode_xc", "cam_xc.nc"), ("xy", "gcode_xy", "sub/cam_xy"),
                          ("dxf", "dxf", "drawing"), ("report", "report", "rep")):
    r = E.export(cam, kind, target)
    out[key] = {"path": str(r.path), "files": list(r.files)}
RESULT["out"] = out
RESULT["listing"] = sorted(os.listdir(WORK))
"""


def test_relative_targets_land_in_freecads_working_folder(tmp_path, fc_home):
    work = tmp_path / "work"
    (work / "sub").mkdir(parents=True)
    run = run_freecadcmd(f"WORK = {str(work)!r}\n" + RELATIVE, tmp_path / "run", fc_home).check()
    got = run.result["out"]
    assert got["xc"]["path"] == str(work / "cam_xc.nc")
    assert got["xy"]["path"] == str(work / "sub" / "cam_xy.nc")          # the kind's suffix added
    assert got["dxf"]["path"] == str(work / "drawing.dxf")
    assert got["report"]["path"] == str(work / "rep") and "report.json" in got["report"]["files"]
    assert run.result["listing"] == ["cam_xc.nc", "drawing.dxf", "rep", "sub"]
    cli = tmp_path / "cli"
    cli.mkdir()
    for mode, name in (("xc", "cam_xc.nc"), ("xy", "cam_xy.nc")):
        res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "gcode", "--mode", mode, "-o", name],
                             capture_output=True, text=True, cwd=cli, timeout=SAFETY_S, stdin=subprocess.DEVNULL,
                             env=cli_env())
        assert res.returncode == 0, res.stderr
    assert (work / "cam_xc.nc").read_bytes() == (cli / "cam_xc.nc").read_bytes()
    assert (work / "sub" / "cam_xy.nc").read_bytes() == (cli / "cam_xy.nc").read_bytes()
    assert (work / "rep" / "report.html").is_file()


FOLDERS = """
import FreeCAD, os, json
from cam_workbench.freecad.feature import create
from cam_workbench.freecad import exports as E
doc = FreeCAD.newDocument("rule")
cam = create(doc, None, name="Cam")
other = create(doc, None, name="Other")
other.CamBaseRadius = 45
doc.recompute()
rep = os.path.join(WORK, "rep")
def attempt(key, obj, target):
    try:
        r = E.export(obj, "report", target)
        RESULT[key] = {"ok": True, "files": list(r.files)}
    except E.ExportError as exc:
        RESULT[key] = {"ok": False, "error": str(exc)}
    m = os.path.join(target, ".cam-workbench.json")
    RESULT[key]["manifest"] = json.load(open(m)) if os.path.exists(m) else None
attempt("first", cam, rep)
cam.CamThickness = 12          # the same feature, edited: its report replaces the earlier one
doc.recompute()
attempt("edited", cam, rep)
attempt("other", other, rep)   # another cam's report into that folder: refused
attempt("mine", cam, os.path.join(WORK, "mine"))
"""


def test_report_exports_follow_the_output_rule(tmp_path, fc_home):
    """The FreeCAD report export through the CLI's output rule: the same feature's report is
    replaced after an edit (the manifest names the document and object), another feature's
    export into that folder and a folder of the user's files are refused with the CLI's message
    (no ``--replace``: the dialog has none), nothing changed."""
    work = tmp_path / "work"
    (work / "mine").mkdir(parents=True)
    (work / "mine" / "notes.txt").write_text("keep me")
    run = run_freecadcmd(f"WORK = {str(work)!r}\n" + FOLDERS, tmp_path / "run", fc_home).check()
    r = run.result
    assert r["first"]["ok"] and r["edited"]["ok"], r
    assert r["first"]["manifest"]["source"] == r["edited"]["manifest"]["source"] == "freecad:rule#Cam"
    assert r["edited"]["manifest"]["spec"]["cam"]["thickness"] == 12
    assert r["edited"]["manifest"]["spec_digest"] != r["first"]["manifest"]["spec_digest"]
    err = r["other"]["error"]
    assert err.startswith(f"Output: {work / 'rep'} holds another cam's set: the set `report` wrote for freecad:rule#Cam")
    assert "cam.base_radius 40 → 45" in err and err.endswith("choose another folder") and "--replace" not in err
    assert r["other"]["manifest"] == r["edited"]["manifest"]           # the set untouched, its time too
    assert not r["mine"]["ok"] and "notes.txt" in r["mine"]["error"] and r["mine"]["manifest"] is None
    assert sorted(p.name for p in (work / "mine").iterdir()) == ["notes.txt"]

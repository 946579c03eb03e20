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
                             capture_output=True, text=True, cwd=cli, timeout=600, stdin=subprocess.DEVNULL,
                             env=cli_env())
        assert res.returncode == 0, res.stderr
    assert (work / "cam_xc.nc").read_bytes() == (cli / "cam_xc.nc").read_bytes()
    assert (work / "sub" / "cam_xy.nc").read_bytes() == (cli / "cam_xy.nc").read_bytes()
    assert (work / "rep" / "report.html").is_file()

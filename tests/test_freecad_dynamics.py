"""Issue 15 in a real FreeCAD (``freecadcmd``): follower dynamics in Check design and the
electronic-cam table exports.

One FreeCAD run makes every case: the default cam with a 2000 N/mm follower train
(``dynamics.stiffness``; jump speed 487.47 rpm, README and docs/dynamics.md) at its 60 rpm and
at 500 rpm (above the jump speed: the follower leaves the cam), a cam whose ``DynamicsEnabled``
is switched on without a stiffness, and the e-cam exports of a cam with its own ``[ecam]``.

* Check design's Follower dynamics rows are compared with report.json of ``cam-workbench
  dynamics`` run here, in a subprocess, on the spec FreeCAD exports: the same numbers (FreeCAD's
  own numpy/scipy against the virtual environment's: 1e-9), the same cam angles, the same verdict.
* Each e-cam export (``exports.export``, the function the export dialog calls, which runs the
  installed CLI) is compared byte for byte with ``cam-workbench ecam`` run here on the original
  spec file (so properties → spec → TOML loses nothing), and the rows the dialog shows with the
  CLI's ``--json`` summary.
"""
from __future__ import annotations

import json
import subprocess
import sys

import pytest

from cam_workbench.generators.spec import default_spec, to_toml

from .conftest import ROOT, SAFETY_S
from .freecad_support import (cli_env, fc_home, requires_freecad_gui, requires_freecadcmd,  # noqa: F401
                              run_freecad_gui, run_freecadcmd)

pytestmark = requires_freecadcmd

DYN_OK = default_spec().replace(**{"dynamics.enabled": True, "dynamics.stiffness": 2000.0})
DYN_LEAVES = DYN_OK.replace(**{"dynamics.speed_rpm": 500.0})   # above the jump speed (487.47 rpm)
ECAM = default_spec().replace(**{"ecam.step": 2.0, "ecam.name": "PressCam", "ecam.format": "beckhoff",
                                 "ecam.table": "position_table"})
ECAM_KINDS = {  # kind → (--format, --table, suffix)
    "ecam_csv": ("csv", "points", ".csv"),
    "ecam_codesys_xyva": ("codesys", "xyva", ".st"),
    "ecam_codesys_poly5": ("codesys", "poly5", ".st"),
    "ecam_beckhoff_motion_function": ("beckhoff", "motion_function", ".st"),
    "ecam_beckhoff_position_table": ("beckhoff", "position_table", ".st"),
    "ecam_lenze": ("lenze", "points", ".txt"),
}

SCRIPT = """
import FreeCAD, os
from cam_workbench.generators.spec import load_spec
from cam_workbench.freecad.feature import create
from cam_workbench.freecad.check_design import design_report
from cam_workbench.freecad.spec_io import export_spec
from cam_workbench.freecad import exports as E
from cam_workbench.freecad import export_dialog as D
doc = FreeCAD.newDocument("dyn")
ok = create(doc, load_spec(SPECS["ok"]), name="DynOk")
leaves = create(doc, load_spec(SPECS["leaves"]), name="DynLeaves")
nostiff = create(doc, None, name="NoStiffness")
ecam = create(doc, load_spec(SPECS["ecam"]), name="Ecam")
doc.recompute()
nostiff.DynamicsEnabled = True          # switched on in the property editor, no DynamicsStiffness given

def dump(rep):
    return {"ok": rep.ok, "verdict": rep.verdict(), "dynamics_verdict": rep.dynamics_verdict(),
            "enabled": rep.dynamics_enabled, "error": rep.dynamics_error, "kept": rep.contact_kept,
            "n_checks": len(rep.checks), "text": rep.text(),
            "rows": [{"cells": r.cells(), "value": r.value, "at": r.at_deg, "path": r.path, "at_path": r.at_path,
                      "status": r.status} for r in rep.dynamics]}

for key, cam in (("ok", ok), ("leaves", leaves), ("nostiff", nostiff), ("plain", ecam)):
    RESULT[key] = dump(design_report(cam))
for key, cam in (("ok", ok), ("leaves", leaves)):
    export_spec(cam, os.path.join(OUT, key + ".toml"))

RESULT["ecam"] = {}
for kind in E.KINDS:
    if not E.is_ecam(kind):
        continue
    name = E.suggested(ecam, kind).name
    r = E.export(ecam, kind, os.path.join(OUT, name))
    RESULT["ecam"][kind] = {"name": name, "path": str(r.path), "files": list(r.files), "message": r.message,
                            "details": [list(x) for x in r.details], "summary": E.summary_rows(ecam, kind),
                            "suffix": E.KINDS[kind].suffix}
RESULT["groups"] = {g: list(k) for g, k in D.GROUPS.items()}
RESULT["current_kind"] = D._current_kind(ecam, D.GROUPS["ecam"])
ok.EcamFormat = "codesys"
RESULT["current_kind_auto"] = D._current_kind(ok, D.GROUPS["ecam"])
try:
    E.export(nostiff, "ecam_csv", os.path.join(OUT, "refused.csv"))
    RESULT["refused"] = None
except E.ExportError as exc:
    RESULT["refused"] = str(exc)
import FreeCADGui  # importable in freecadcmd: the command table and menu layout
from cam_workbench.freecad import commands as C
RESULT["commands"] = {n: [getattr(c, "group", ""), c.icon] for n, c in C.COMMANDS.items()}
RESULT["layout"] = list(C.LAYOUT)
RESULT["icon_dir"] = C.ICON_DIR
RESULT["listing"] = sorted(os.listdir(OUT))
"""


def _cli(*args: str, cwd) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "cam_workbench.cli", *args], capture_output=True,
                          text=True, cwd=cwd, timeout=SAFETY_S, stdin=subprocess.DEVNULL, env=cli_env())


@pytest.fixture(scope="module")
def fc(tmp_path_factory, fc_home):
    specs_dir = tmp_path_factory.mktemp("dyn_specs")
    specs = {}
    for key, spec in (("ok", DYN_OK), ("leaves", DYN_LEAVES), ("ecam", ECAM)):
        specs[key] = str(specs_dir / f"{key}.toml")
        (specs_dir / f"{key}.toml").write_text(to_toml(spec), encoding="utf-8")
    out = tmp_path_factory.mktemp("dyn_out")
    body = f"SPECS = {specs!r}\nOUT = {str(out)!r}\n" + SCRIPT
    run = run_freecadcmd(body, tmp_path_factory.mktemp("dyn_run"), fc_home).check()
    return run.result, out, specs


def _at(d, path):
    for k in path:
        d = d[k]
    return d


def _cli_dynamics(spec_file, tmp, expect_status):
    res = _cli("dynamics", str(spec_file), "-o", str(tmp), cwd=tmp)
    assert res.returncode == expect_status, res.stdout + res.stderr
    return json.loads((tmp / "report.json").read_text(encoding="utf-8"))["dynamics"]


def _assert_rows_equal_report(rows, d):
    """Every number of the dialog's rows is report.json's, at the keys the row names: to 1e-9 of
    the quantity's own scale (FreeCAD's numpy/scipy against the virtual environment's: a small
    difference of large numbers, such as the vibration about the quasi-static deflection or the
    work per revolution, carries the round-off of its operands), and shown with the same digits
    unless the 6th digit sits at its rounding edge."""
    from cam_workbench.freecad.check_design import fmt_number

    scale = {d["contact"]["unit"]: d["contact"]["max_force"], d["error"]["unit"]: d["error"]["max"],
             d["torque"]["unit"]: d["torque"]["dynamic"]["rms"]}
    numbers = 0
    for r in rows:
        if r["path"] is None:
            continue
        ref = _at(d, r["path"])
        if r["value"] is None:
            assert ref is None, r
            continue
        numbers += 1
        unit = r["cells"][2]
        assert r["value"] == pytest.approx(ref, rel=1e-9, abs=1e-9 * scale.get(unit, 0.0)), r
        shown = {fmt_number(ref * (1 + t)) for t in (-1e-9, 0.0, 1e-9)}
        if r["path"] == ["speed_rpm"]:   # the verdict, which names the speed
            assert any(r["cells"][0] == f"follower at {x} rpm (the analysis speed)" for x in shown), r
            assert r["cells"][1] == ("stays on the cam" if d["contact"]["kept"] else "LEAVES the cam"), r
        else:
            assert r["cells"][1] in shown, r
        if r["at_path"] is not None:
            assert r["at"] == pytest.approx(_at(d, r["at_path"]), abs=1e-6), r
    return numbers


def test_dynamics_rows_equal_report_json_of_the_cli(fc, tmp_path):
    """The default cam with a 2000 N/mm train at 60 rpm: the follower stays on the cam, jump
    speed 487.47 rpm (rigid 492.09) — every row equals report.json of ``cam-workbench dynamics``
    on the spec FreeCAD exported, with its unit and cam angle."""
    r, out, _specs = fc
    d = _cli_dynamics(out / "ok.toml", tmp_path, 0)
    got = r["ok"]
    assert got["enabled"] and got["error"] is None and got["kept"] is True and got["ok"] is True
    rows = got["rows"]
    n = _assert_rows_equal_report(rows, d)
    by = {row["cells"][0]: row for row in rows}
    assert n >= 20
    assert rows[0]["cells"] == ["follower at 60 rpm (the analysis speed)", "stays on the cam", "rpm", "—", "pass"]
    jump = by["jump speed (contact first lost)"]
    assert jump["cells"][1:] == ["487.468", "rpm", "—", "pass"] and jump["value"] == pytest.approx(487.47, abs=0.01)
    assert d["jump_speed"]["rpm"] == pytest.approx(487.47, abs=0.01)
    assert by["jump speed of the rigid follower"]["cells"][1] == "492.093"
    assert by["smallest contact force (dynamic)"]["cells"][2] == "N"
    assert by["camshaft torque RMS (dynamic)"]["cells"][2] == "N·mm"
    assert by["largest displacement error |q − s|"]["cells"][2] == "mm"
    for label in ("smallest contact force (rigid)", "largest contact force (dynamic)", "camshaft torque max (rigid)",
                  "camshaft torque max (dynamic)", "camshaft torque RMS (rigid)", "largest vibration"):
        assert label in by, label
    residual = [row for row in rows if row["cells"][0].startswith("residual vibration after")]
    assert len(residual) == len(d["residual_vibration"]) == 2
    assert residual[0]["cells"][0] == "residual vibration after motion[1] rise (in motion[2] dwell)"
    assert all(row["status"] != "FAIL" for row in rows)
    assert got["verdict"] == "all checks pass"
    assert "follower dynamics: the follower stays on the cam at 60 rpm" in got["text"]


def test_a_follower_leaving_the_cam_is_never_shown_as_passing(fc, tmp_path):
    """At 500 rpm (above the jump speed) the CLI exits 3 and Check design says the follower
    LEAVES the cam, in its verdict and in the table, with the same numbers."""
    r, out, _specs = fc
    d = _cli_dynamics(out / "leaves.toml", tmp_path, 3)
    got = r["leaves"]
    assert d["contact"]["kept"] is False and got["kept"] is False and got["ok"] is False
    _assert_rows_equal_report(got["rows"], d)
    first = got["rows"][0]
    assert first["cells"] == ["follower at 500 rpm (the analysis speed)", "LEAVES the cam", "rpm", "—", "FAIL"]
    assert got["dynamics_verdict"].startswith("the follower LEAVES the cam at 500 rpm (")
    assert "the follower LEAVES the cam at 500 rpm" in got["verdict"] and "all checks pass" not in got["verdict"]
    by = {row["cells"][0]: row for row in got["rows"]}
    assert by["off the cam"]["status"] == "FAIL" and by["off the cam"]["value"] == pytest.approx(
        d["contact"]["off_cam_deg"], rel=1e-9)
    assert by["jump speed (contact first lost)"]["status"] == "FAIL"
    assert "largest gap" in by and "largest landing speed" in by


def test_bad_dynamics_input_names_the_field(fc):
    """DynamicsEnabled without a stiffness: the library's message naming the property and the
    field, no traceback; the cam itself is still checked."""
    r, _out, _specs = fc
    got = r["nostiff"]
    assert got["enabled"] and got["kept"] is None and got["rows"] == [] and got["ok"] is False
    assert got["error"].startswith("DynamicsStiffness (dynamics.stiffness): is required for the dynamics of a "
                                   "translating follower"), got["error"]
    assert got["dynamics_verdict"] == "follower dynamics not analysed: " + got["error"]
    assert got["dynamics_verdict"] in got["verdict"] and got["n_checks"] > 5
    # the e-cam export of that feature is refused with the same field named, nothing written
    assert r["refused"].startswith("DynamicsStiffness (dynamics.stiffness): is required"), r["refused"]
    # without DynamicsEnabled there is no dynamics table
    assert r["plain"]["enabled"] is False and r["plain"]["rows"] == [] and "follower dynamics" not in r["plain"]["text"]


def test_ecam_exports_equal_the_clis_output(fc, tmp_path):
    """Every e-cam kind writes its file under its default name and suffix, byte-identical to
    ``cam-workbench ecam`` on the original spec; the rows the dialog shows are the CLI's summary."""
    from cam_workbench.freecad.exports import ecam_rows

    r, out, specs = fc
    assert set(r["ecam"]) == set(ECAM_KINDS)
    for kind, (fmt, table, suffix) in ECAM_KINDS.items():
        e = r["ecam"][kind]
        assert e["suffix"] == suffix and e["name"].startswith("Ecam") and e["name"].endswith(suffix), e
        target = tmp_path / e["name"]
        res = _cli("ecam", specs["ecam"], "--format", fmt, "--table", table, "--json", "-o", str(target), cwd=tmp_path)
        assert res.returncode == 0, res.stderr
        assert (out / e["name"]).read_bytes() == target.read_bytes(), kind
        assert e["files"] == [e["name"]]
        summary = json.loads(res.stdout)
        assert summary["format"] == fmt and summary["table"] == table and summary["step_deg"] == 2.0
        assert e["details"] == [list(x) for x in ecam_rows(summary)], kind
        own = summary["interpolation"] or "quintic"
        dev = summary["deviation"][own]
        assert any(k.startswith(f"{own} interpolation") and k.endswith("max deviation")
                   and v == f"{dev['max_error']:.3g} {summary['lift_unit']} at {dev['at_deg']:.4f}°"
                   for k, v in e["details"]), e["details"]
        rows = dict(map(tuple, e["summary"]))
        assert rows["Table (this export)"] == f"{fmt} {table}"
        assert rows["EcamStep"].startswith("2 ") and rows["EcamName"] == "PressCam"
    text = (out / r["ecam"]["ecam_codesys_xyva"]["name"]).read_text()
    assert "SMC_CAMXYVA" in text and "PressCam" in text
    assert (out / r["ecam"]["ecam_lenze"]["name"]).read_text().count("\n") > 180
    assert r["listing"] == sorted(["leaves.toml", "ok.toml", *(e["name"] for e in r["ecam"].values())])


def test_ecam_dialog_and_command_offer_every_kind(fc):
    """The export dialog's e-cam group offers every e-cam kind, preselected from EcamFormat and
    EcamTable; the command that opens it is in the menu, with its icon."""
    r, _out, _specs = fc
    assert r["groups"]["ecam"] == list(ECAM_KINDS)
    assert r["current_kind"] == "ecam_beckhoff_position_table"   # the Ecam cam's properties
    assert r["current_kind_auto"] == "ecam_codesys_xyva"           # table "auto": the format's first
    group, icon = r["commands"]["CamWorkbench_ExportEcam"]
    assert group == "ecam" and "CamWorkbench_ExportEcam" in r["layout"]
    from pathlib import Path

    assert (Path(r["icon_dir"]) / icon).is_file()
    assert Path(r["icon_dir"]).resolve().is_relative_to(ROOT) or (ROOT / "cam_workbench" / "freecad" / "icons" / icon).is_file()


GUI = r"""
import os
ART, OUT, SPECS = {art!r}, {out!r}, {specs!r}
R = RESULT
state = {{}}

def setup():
    mw.resize(1400, 900)
    FreeCADGui.activateWorkbench("CamWorkbench")
    menus = [m for m in mw.findChildren(QtGui.QMenu) if m.title().replace("&", "") == "Cam"]
    R["menu"] = [a.text() for a in menus[0].actions() if a.text()] if menus else []
    from cam_workbench.generators.spec import load_spec
    from cam_workbench.freecad.feature import create
    doc = FreeCAD.newDocument("Dyn")
    state["cam"] = create(doc, load_spec(SPECS["leaves"]), name="DynLeaves")
    doc.recompute()
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(state["cam"])
    FreeCADGui.runCommand("CamWorkbench_CheckDesign")

def check_dialog():
    d = [w for w in QtGui.QApplication.topLevelWidgets() if w.isVisible() and w.objectName() == "CamWorkbenchCheckDesign"]
    if not d:
        raise NotYet("check dialog")
    d = d[0]
    d.move(30, 30)
    tabs = d.findChild(QtGui.QTabWidget)
    R["tabs"] = [tabs.tabText(i) for i in range(tabs.count())]
    tabs.setCurrentIndex(R["tabs"].index("Follower dynamics"))
    t = d.findChild(QtGui.QTableWidget, "dynamics")
    R["headers"] = [t.horizontalHeaderItem(c).text() for c in range(t.columnCount())]
    R["table"] = [[t.item(r, c).text() for c in range(t.columnCount())] for r in range(t.rowCount())]
    R["fail_colour"] = t.item(0, 4).foreground().color().name()
    R["verdict"] = d.findChild(QtGui.QLabel, "dynamics_verdict").text()
    R["head"] = d.findChildren(QtGui.QLabel)[0].text()
    R["steady"] = d.findChild(QtGui.QLabel, "dynamics_steady_state").text()
    state["check"] = d

def check_shot():
    shot("freecad_gui_check_design_dynamics.png")
    state.pop("check").close()
    FreeCADGui.runCommand("CamWorkbench_ExportEcam")

def ecam_dialog():
    from cam_workbench.freecad.export_dialog import active_dialogs
    ds = [x for x in active_dialogs() if x.dialog.isVisible()]
    if not ds:
        raise NotYet("export dialog")
    d = state["export"] = ds[-1]
    R["ecam_dialog"] = {{"title": d.dialog.windowTitle(), "radios": list(d.radios), "kind": d.kind,
                        "rows": [d.values.item(r, 0).text() for r in range(d.values.rowCount())]}}
    d.radios["ecam_codesys_xyva"].setChecked(True)
    R["ecam_path"] = d.path.text()
    d.path.setText(os.path.join(OUT, "gui_xyva.st"))
    d.start()

def ecam_written():
    d = state["export"]
    if d.running or d.result is None and d.error is None:
        raise NotYet("ecam export")
    R["ecam"] = {{"status": d.status.text(), "error": d.error,
                 "details": [[d.details.item(r, c).text() for c in range(2)] for r in range(d.details.rowCount())],
                 "details_visible": d.details.isVisible()}}
    shot("freecad_gui_export_ecam.png")
    d.dialog.close()
    R["report_view"] = report_text()

steps = [(setup, 1000), (check_dialog, 500), (check_shot, 800), (ecam_dialog, 300), (ecam_written, 300)]
"""


@requires_freecad_gui
def test_dynamics_and_ecam_in_the_freecad_gui(fc, tmp_path, fc_home, artifacts):
    """In the real GUI: Check design of the 500 rpm cam has a Follower dynamics tab whose table is
    the rows the headless run computed (the follower LEAVES the cam, in red, and the dialog's
    heading says so); the e-cam export dialog offers every table, writes CODESYS XYVA through the
    CLI and shows the CLI's measured deviation."""
    r_fc, out, specs = fc
    gui_out = tmp_path / "out"
    gui_out.mkdir()
    run = run_freecad_gui(GUI.format(art=str(artifacts), out=str(gui_out), specs=specs), tmp_path, fc_home)
    r = run.check().result
    assert "Export e-cam table…" in r["menu"]
    assert r["tabs"] == ["Design checks", "Buildability and geometry", "Follower dynamics"]
    assert r["headers"] == ["quantity", "value", "unit", "at cam angle", "status"]
    assert r["table"] == [row["cells"] for row in r_fc["leaves"]["rows"]]
    assert r["table"][0][1:] == ["LEAVES the cam", "rpm", "—", "FAIL"]
    assert r["steady"].startswith("steady state: exact piecewise solution") and "4 revolutions" in r["steady"]
    assert r["fail_colour"] == "#c62828"
    assert r["verdict"].startswith("the follower LEAVES the cam at 500 rpm (")
    assert "the follower LEAVES the cam at 500 rpm" in r["head"]
    e = r["ecam_dialog"]
    assert e["title"] == "Export e-cam table — DynLeaves" and e["radios"] == list(ECAM_KINDS)
    assert e["kind"] == "ecam_csv" and e["rows"][:2] == ["Units", "Table (this export)"]
    assert r["ecam_path"].endswith("DynLeaves_codesys_xyva.st")
    assert r["ecam"]["error"] is None and r["ecam"]["status"] == f"Written: {gui_out / 'gui_xyva.st'}"
    assert r["ecam"]["details_visible"] and r["ecam"]["details"][0] == ["table", "codesys xyva"]
    assert r["ecam"]["details"][2][0] == "quintic interpolation (the controller's): max deviation"
    assert "Traceback" not in r["report_view"] and "Traceback" not in run.console
    assert "Export e-cam table (CODESYS XYVA): written" in r["report_view"]
    for name in ("freecad_gui_check_design_dynamics.png", "freecad_gui_export_ecam.png"):
        assert (artifacts / name).stat().st_size > 10_000, name

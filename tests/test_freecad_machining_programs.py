"""The machining programs chosen in FreeCAD's Machining group — G-code dialect, cutter
compensation, program (XY contour, XY roughing from a round blank, 2-axis wire EDM) — in the real
``freecadcmd`` (0.20 on the host; 1.0 and 1.1 with ``$CAM_FREECAD_ROOT``).

The properties are checked against the spec's declarations (generators/spec/machining.py): one
enumeration per choice field in the "Machining" group, with its declared choices and default, on a
new feature and on a document saved before the fields existed.  Each export is made the way the
export dialog makes it (:func:`cam_workbench.freecad.exports.export`) and must equal, byte for
byte, what the library writes for the spec FreeCAD saves (``export_spec``): once through
``cam-workbench gcode`` run here, once through the Python API (``Cam(...).outputs()``).  The
controller-compensated programs are also held to a closed form: their contour lies on the part,
whose radius on the dwells is R_b + s − r (roller follower on the cam axis), not on the tool
centre's R_b + s.  A refused combination shows the library's message with the property and the
spec field, and writes nothing (an existing file at the target is left as it was).
"""
from __future__ import annotations

import math
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from cam_workbench import Cam
from cam_workbench.freecad.properties import field_properties
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec import default_spec
from cam_workbench.generators.spec.machining import MachiningSection
from cam_workbench.generators.spec.params import params_of

from .conftest import SAFETY_S, snapshot
from .freecad_support import (cli_env, fc_home, requires_freecad_gui, requires_freecadcmd,  # noqa: F401
                              run_freecad_gui, run_freecadcmd)

pytestmark = requires_freecadcmd

#: key → (export kind, the CLI's --mode, property settings, the machining fields the spec must then hold)
PROGRAMS = {
    "fanuc": ("gcode_xy", "xy",
              {"MachiningDialect": "fanuc", "MachiningCompensation": "controller", "MachiningProgramNumber": 1234},
              {"dialect": "fanuc", "compensation": "controller", "program_number": 1234}),
    "sinumerik": ("gcode_xy", "xy",
                  {"MachiningDialect": "sinumerik", "MachiningCompensation": "controller",
                   "MachiningWorkOffset": "G55"},
                  {"dialect": "sinumerik", "compensation": "controller", "work_offset": "G55"}),
    "wire_edm": ("gcode_wire_edm", "wire_edm",
                 {"MachiningProgram": "wire_edm", "MachiningWireDiameter": 0.3, "MachiningSkimPasses": 2,
                  "MachiningSparkGap": 0.0, "MachiningTabWidth": 3.0},
                 {"program": "wire_edm", "wire_diameter": 0.3, "skim_passes": 2, "spark_gap": 0.0,
                  "tab_width": 3.0}),
    "roughing": ("gcode_xy", "xy",
                 {"MachiningBlankDiameter": 110.0, "MachiningStepover": 0.4, "MachiningFinishAllowance": 0.3},
                 {"blank_diameter": 110.0, "stepover": 0.4, "finish_allowance": 0.3}),
}
#: key → (export kind, property settings, the spec the export asks the library for: the message is its
#: SpecError's, the field shown as the property that holds it)
REFUSED = {
    # the feature's own program is XC: the feature's spec itself is refused
    "controller_xc": ("gcode_xc", {"MachiningProgram": "xc", "MachiningCompensation": "controller"},
                      {"machining.program": "xc", "machining.compensation": "controller"}),
    # an XY feature exported as the XC program: the command line refuses it
    "controller_as_xc": ("gcode_xc", {"MachiningCompensation": "controller"},
                         {"machining.program": "xc", "machining.compensation": "controller"}),
    "sinumerik_g58": ("gcode_xy", {"MachiningDialect": "sinumerik", "MachiningWorkOffset": "G58"},
                      {"machining.dialect": "sinumerik", "machining.work_offset": "G58"}),
    "wire_edm_fanuc": ("gcode_wire_edm", {"MachiningProgram": "wire_edm", "MachiningDialect": "fanuc"},
                       {"machining.program": "wire_edm", "machining.dialect": "fanuc"}),
}
#: the field each refusal must name
REFUSED_FIELD = {"controller_xc": "machining.compensation", "controller_as_xc": "machining.compensation",
                 "sinumerik_g58": "machining.work_offset", "wire_edm_fanuc": "machining.dialect"}
#: the choice fields new with the dialects, the compensation and the wire EDM, and the program
CHOICES = ("program", "dialect", "compensation", "wire_compensation")
NEW_FIELDS = ("dialect", "compensation", "program_number", "blank_diameter", "stepover", "finish_allowance",
              "wire_diameter", "spark_gap", "skim_passes", "skim_stock", "tab_width", "start_hole",
              "wire_compensation")
KEEP = "a file of the user's\n"
#: the Enabled flags of the new fields for which 0 is a value (no finish allowance, no spark gap, …)
FLAGS = [fp.flag for fp in field_properties() if fp.section == "machining" and fp.field in NEW_FIELDS and fp.flag]

SCRIPT = """
import FreeCAD, os
from cam_workbench.freecad.feature import create
from cam_workbench.freecad import exports as E, spec_io
from cam_workbench.freecad import properties as P
from cam_workbench.generators.errors import SpecError

doc = FreeCAD.newDocument("programs")
fresh = create(doc, None, name="Fresh")
doc.recompute()

def describe(obj, name):
    enum = obj.getTypeIdOfProperty(name) == "App::PropertyEnumeration"
    return {"type": obj.getTypeIdOfProperty(name), "group": obj.getGroupOfProperty(name),
            "choices": list(obj.getEnumerationsOfProperty(name)) if enum else None,
            "value": getattr(obj, name).Value if hasattr(getattr(obj, name), "Value") else getattr(obj, name)}

RESULT["props"] = {n: describe(fresh, n) for n in NAMES}
RESULT["fresh_machining"] = P.spec_dict(fresh)["machining"]

out = {}
for key, (kind, settings) in CASES.items():
    cam = create(doc, None, name=key)
    for name, value in settings.items():
        setattr(cam, name, value)
        if name + "Enabled" in cam.PropertiesList:   # a value is given with its flag ticked, as in the editor
            setattr(cam, name + "Enabled", True)
    target = os.path.join(WORK, key + ".nc")
    if key in REFUSED:
        with open(target, "w") as f:
            f.write(KEEP)
    try:
        r = E.export(cam, kind, target)
        out[key] = {"ok": True, "path": str(r.path), "files": list(r.files)}
        spec_io.export_spec(cam, os.path.join(WORK, key + ".toml"))   # the spec FreeCAD saves
    except E.ExportError as exc:
        out[key] = {"ok": False, "error": str(exc)}
RESULT["out"] = out

# a document saved before the fields existed: no such properties, MachiningDialect offering "linuxcnc" only
old = create(doc, None, name="Old")
for name in [n for n in OLD_MISSING if n in old.PropertiesList]:
    old.removeProperty(name)
old.MachiningDialect = ["linuxcnc"]
RESULT["old_before"] = [n for n in NAMES if n in old.PropertiesList]
path = os.path.join(WORK, "old.FCStd")
doc.saveAs(path)
FreeCAD.closeDocument(doc.Name)
doc = FreeCAD.openDocument(path)
old = doc.getObject("Old")
RESULT["old_props"] = {n: describe(old, n) for n in NAMES}
RESULT["old_machining"] = P.spec_dict(old)["machining"]
"""


def _declared(field: str):
    return params_of(MachiningSection)[field]


def _prop(field: str) -> str:
    return "Machining" + "".join(w.capitalize() for w in field.split("_"))


@pytest.fixture(scope="module")
def freecad_run(tmp_path_factory, fc_home):
    tmp = tmp_path_factory.mktemp("machining_programs")
    work = tmp / "work"
    work.mkdir()
    cases = {k: (kind, settings) for k, (kind, _mode, settings, _f) in PROGRAMS.items()}
    cases.update({k: (kind, settings) for k, (kind, settings, _m) in REFUSED.items()})
    names = [_prop(f) for f in NEW_FIELDS + ("program",)] + FLAGS
    missing = [n for n in names if n not in ("MachiningProgram", "MachiningDialect")]
    head = (f"WORK = {str(work)!r}\nCASES = {cases!r}\nREFUSED = {list(REFUSED)!r}\nKEEP = {KEEP!r}\n"
            f"NAMES = {names!r}\nOLD_MISSING = {missing!r}\n")
    run = run_freecadcmd(head + SCRIPT, tmp / "run", fc_home).check()
    return run.result, work


def _expected_property(field: str) -> dict:
    """The property a Machining field must have, from its declaration alone."""
    p = _declared(field)
    optional = p.optional or p.default is None
    return {"group": "Machining", "choices": ([""] if optional else []) + list(p.choices),
            "value": "" if optional else p.default}


@pytest.mark.parametrize("where", ["props", "old_props"])
def test_choice_fields_are_enumerations_with_the_declared_choices(freecad_run, where):
    """On a new feature and on a document saved before the fields existed (restored: the properties
    added, the dialect's enumeration given its new choices)."""
    result, _work = freecad_run
    if where == "old_props":
        assert sorted(result["old_before"]) == ["MachiningDialect", "MachiningProgram"]
    props = result[where]
    for field in CHOICES:
        got = props[_prop(field)]
        assert got["type"] == "App::PropertyEnumeration", field
        assert {k: got[k] for k in ("group", "choices", "value")} == _expected_property(field), field
    assert props["MachiningDialect"]["choices"] == ["linuxcnc", "fanuc", "sinumerik"]
    assert props["MachiningCompensation"]["choices"] == ["", "centre", "controller"]
    assert props["MachiningProgram"]["choices"] == ["xy", "xc", "wire_edm"]


@pytest.mark.parametrize("where", ["fresh_machining", "old_machining"])
def test_new_fields_default_to_the_declared_defaults(freecad_run, where):
    """Every new Machining property is in the group and, untouched, gives the spec the declared
    default (absent optional fields left out), the default spec's [machining] table."""
    result, _work = freecad_run
    props = result["props" if where == "fresh_machining" else "old_props"]
    for field in NEW_FIELDS:
        assert props[_prop(field)]["group"] == "Machining", field
    expected = {k: v for k, v in default_spec().to_dict()["machining"].items()}
    got = result[where]
    for field in NEW_FIELDS + ("program",):
        p = _declared(field)
        want = None if (p.optional or p.default is None) else p.default
        assert got.get(field) == want == expected.get(field), field
    assert {"MachiningFinishAllowanceEnabled", "MachiningSparkGapEnabled"} <= set(FLAGS)
    for flag in FLAGS:
        assert props[flag]["value"] is False and props[flag]["group"] == "Machining"


def _cli(spec: Path, mode: str, out: Path) -> bytes:
    res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "gcode", str(spec), "--mode", mode,
                          "-o", str(out)], capture_output=True, text=True, cwd=out.parent, timeout=SAFETY_S,
                         stdin=subprocess.DEVNULL, env=cli_env())
    assert res.returncode == 0, res.stderr
    return out.read_bytes()


@pytest.mark.parametrize("key", list(PROGRAMS))
def test_export_is_the_librarys_program_for_the_saved_spec(freecad_run, key, tmp_path):
    result, work = freecad_run
    _kind, mode, _settings, fields = PROGRAMS[key]
    got = result["out"][key]
    assert got["ok"], got
    assert got["path"] == str(work / f"{key}.nc") and got["files"] == [f"{key}.nc"]
    saved = work / f"{key}.toml"
    machining = tomllib.loads(saved.read_text())["machining"]
    assert {f: machining.get(f) for f in fields} == fields          # the properties reached the spec
    written = (work / f"{key}.nc").read_bytes()
    assert written == _cli(saved, mode, tmp_path / "cli.nc")
    assert written.decode() == Cam(str(saved)).outputs().machining.gcode


_XY = re.compile(r"X(-?\d*\.?\d*)\s+Y(-?\d*\.?\d*)")


def _compensated_contour(text: str, comment: str) -> list[tuple[float, float]]:
    """The XY end points of the moves between the block that starts G41 and the one that ends
    it (G40), without the last (the lead-out's end, off the part)."""
    lines = [ln for ln in text.splitlines() if not ln.startswith(comment)]
    start = next(i for i, ln in enumerate(lines) if ln.startswith("G41"))
    end = next(i for i, ln in enumerate(lines) if ln.startswith("G40") and i > start)
    points = [(float(m.group(1)), float(m.group(2))) for ln in lines[start + 1:end] if (m := _XY.search(ln))]
    return points[:-1]


@pytest.mark.parametrize("key, comment", [("fanuc", "("), ("sinumerik", ";")])
def test_controller_compensation_runs_on_the_part(freecad_run, key, comment):
    """Under G41 the program's contour is the cam profile: for the default cam (radial roller
    r = 8 mm, R_b = 40 mm, total lift 20 mm, dwells at both ends of the lift) its points lie between
    R_b − r = 32 mm and R_b + h − r = 52 mm from the axis and reach both (the dwells are arcs of
    those circles), within the chord tolerance 0.005 mm and the 4-decimal rounding."""
    result, work = freecad_run
    assert result["out"][key]["ok"]
    text = (work / f"{key}.nc").read_text()
    spec = default_spec()
    r, rb = spec.follower.roller_radius, spec.cam.base_radius
    h = max(seg.lift or 0.0 for seg in spec.motion)   # a dwell has none
    radii = [math.hypot(x, y) for x, y in _compensated_contour(text, comment)]
    assert len(radii) > 50
    tol = 0.005 + 1e-4
    assert min(radii) == pytest.approx(rb - r, abs=tol) and max(radii) == pytest.approx(rb + h - r, abs=tol)


def test_dialect_words(freecad_run):
    """What each dialect writes where the others differ (docs/machining.md): Fanuc's tape marks, its
    O number from MachiningProgramNumber and a decimal point on every coordinate; Sinumerik's ;
    comments, G71 and the work offset chosen."""
    _result, work = freecad_run
    fanuc = (work / "fanuc.nc").read_text().splitlines()
    assert fanuc[:2] == ["%", "O1234"] and fanuc[-1] == "%"
    blocks = [ln for ln in fanuc if ln and not ln.startswith(("(", "%"))]
    assert not [ln for ln in blocks if re.search(r"[XYZIJ]-?\d+(?![\d.])", ln)]
    assert any(ln.startswith("G41 D1 ") for ln in blocks)
    sin = (work / "sinumerik.nc").read_text().splitlines()
    assert not any(ln.startswith("(") for ln in sin) and any(ln.startswith(";") for ln in sin)
    assert "G71" in " ".join(sin).split() and "G55" in sin


@pytest.mark.parametrize("key", list(REFUSED))
def test_refused_combination_names_the_field_and_writes_nothing(freecad_run, key):
    result, work = freecad_run
    _kind, _settings, changes = REFUSED[key]
    with pytest.raises(SpecError) as library:
        default_spec().replace(**changes)
    assert library.value.field == REFUSED_FIELD[key]
    got = result["out"][key]
    assert not got["ok"], got
    assert got["error"] == f"{_prop(library.value.field.split('.')[1])} ({library.value.field}): {library.value.rule}"
    assert (work / f"{key}.nc").read_text() == KEEP                 # the file at the target untouched


def test_nothing_else_is_written(freecad_run):
    """The work folder holds the programs and the specs saved, the refused targets as they were,
    the document — no temporary file left behind."""
    _result, work = freecad_run
    want = {f"{k}.{s}" for k in PROGRAMS for s in ("nc", "toml")} | {f"{k}.nc" for k in REFUSED} | {"old.FCStd"}
    assert set(snapshot(work)) == want


GUI = r"""
import os
OUT = {out!r}
R = RESULT

def dialog():
    from cam_workbench.freecad.export_dialog import active_dialogs
    ds = [d for d in active_dialogs() if d.dialog.isVisible()]
    if not ds:
        raise NotYet("export dialog")
    return ds[-1]

def new_cam():
    FreeCADGui.activateWorkbench("CamWorkbench")
    from cam_workbench.freecad.feature import create
    doc = FreeCAD.newDocument("wire")
    cam = create(doc, None, name="Cam")
    cam.MachiningProgram = "wire_edm"
    doc.recompute()
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.runCommand("CamWorkbench_ExportGcode")

def shown():
    d = dialog()
    R["radios"] = list(d.radios)
    R["kind"] = d.kind
    R["rows"] = [d.values.item(r, 0).text() for r in range(d.values.rowCount())]
    d.path.setText(os.path.join(OUT, "wire.nc"))
    d.start()

def written():
    d = dialog()
    if d.running or d.result is None and d.error is None:
        raise NotYet("wire EDM export")
    R["status"] = d.status.text()
    from cam_workbench.freecad import spec_io
    spec_io.export_spec(FreeCAD.ActiveDocument.getObject("Cam"), os.path.join(OUT, "wire.toml"))
    R["report"] = report_text()
    d.dialog.close()

steps = [(new_cam, 500), (shown, 300), (written, 100)]
"""


@requires_freecad_gui
def test_export_dialog_offers_the_features_program(tmp_path, fc_home):
    """The G-code dialog of a feature whose MachiningProgram is "wire_edm" offers the three programs
    with the wire EDM chosen, lists the Machining values it uses (the dialect among them; the
    program is the choice itself), and writes the library's program."""
    out = tmp_path / "out"
    out.mkdir()
    run = run_freecad_gui(GUI.format(out=str(out)), tmp_path / "run", fc_home).check()
    r = run.result
    assert r["radios"] == ["gcode_xy", "gcode_xc", "gcode_wire_edm"] and r["kind"] == "gcode_wire_edm"
    assert "MachiningDialect" in r["rows"] and "MachiningWireDiameter" in r["rows"]
    assert "MachiningProgram" not in r["rows"]
    assert r["status"] == f"Written: {out / 'wire.nc'}", r["status"]
    assert "Traceback" not in r["report"]
    written = (out / "wire.nc").read_bytes()
    assert tomllib.loads((out / "wire.toml").read_text())["machining"]["program"] == "wire_edm"
    assert written == _cli(out / "wire.toml", "wire_edm", tmp_path / "cli.nc")

"""Issue 25 in a real FreeCAD (``freecadcmd``): "Inspect part…" on a cam feature is the library's
``inspect_part`` (and so ``cam-workbench inspect``'s) on the same spec and points — every number of
inspection.json the same (FreeCAD's own numpy against the virtual environment's: 1e-9), the files
written through the same exporter — and the points it puts into the document stand where the
registration puts them, in the cam's placement, coloured by the deviation class they fall in, each
with its whisker along the profile's normal.  A bad points file is refused with the library's message
naming the file and line, and adds nothing."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from cam_workbench.exporters.inspection_report import PALETTE, rows
from cam_workbench.exporters.report_cells import format_number as fmt
from cam_workbench.exporters.report_cells import lookup
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.inspection import inspect_part, inspection_files, read_points

from .conftest import ROOT
from .freecad_support import (fc_home, requires_freecad_gui, requires_freecadcmd,  # noqa: F401
                              run_freecad_gui, run_freecadcmd)

pytestmark = requires_freecadcmd

POINTS = ROOT / "docs" / "examples" / "inspection_points.csv"
TOLERANCE = 0.02
#: the cam's placement in the document: turned 90° about z and moved
PLACEMENT = ((100.0, -20.0, 5.0), 90.0)

SCRIPT = """
import FreeCAD, os
from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.freecad.feature import create
from cam_workbench.freecad.inspection_doc import inspect_feature, inspections_of, report_lines, headline
doc = FreeCAD.newDocument("insp")
cam = create(doc, example_spec("default"), name="Cam")
(x, y, z), deg = PLACEMENT
cam.Placement = FreeCAD.Placement(FreeCAD.Vector(x, y, z), FreeCAD.Rotation(FreeCAD.Vector(0, 0, 1), deg))
doc.recompute()
before = len(doc.Objects)
bad = os.path.join(os.getcwd(), "bad.csv")
with open(bad, "w") as f:
    f.write("x,y\\n1,2\\n3,abc\\n4,5\\n")
try:
    inspect_feature(cam, bad, TOLERANCE, "none")
except Exception as exc:
    RESULT["bad"] = [type(exc).__name__, str(exc), len(doc.Objects) - before]
try:
    inspect_feature(cam, POINTS, TOLERANCE, "sideways")
except Exception as exc:
    RESULT["bad_datum"] = [type(exc).__name__, str(exc), len(doc.Objects) - before]
out = os.path.join(os.getcwd(), "out")
found = inspect_feature(cam, POINTS, TOLERANCE, "none", out)
doc.recompute()
RESULT["report"] = found.report
RESULT["lines"] = report_lines(found.report)
RESULT["headline"] = headline(found.report)
RESULT["written"] = {n: open(os.path.join(out, n)).read() for n in ("inspection.json", "deviations.csv")}
g = found.group
RESULT["groups"] = [o.Name for o in inspections_of(cam)]
RESULT["group"] = {"name": g.Name, "label": g.Label, "cam": g.InspectedCam, "verdict": g.Verdict,
                   "k": g.WhiskerScale, "objects": len(doc.Objects) - before}
parts = []
for o in g.Group:
    pl = o.Placement
    subs = o.Shape.SubShapes
    parts.append({"label": o.Label,
                  "low": o.DeviationLow if "DeviationLow" in o.PropertiesList else None,
                  "high": o.DeviationHigh if "DeviationHigh" in o.PropertiesList else None,
                  "placement": [list(pl.Base), pl.Rotation.Angle, list(pl.Rotation.Axis)],
                  "vertices": [list(s.Point) for s in subs if s.ShapeType == "Vertex"],
                  "edges": [[list(s.Vertexes[0].Point), list(s.Vertexes[-1].Point)] for s in subs if s.ShapeType == "Edge"]})
RESULT["parts"] = parts
with open(os.path.join(__import__("cam_workbench").freecad.__path__[0], "commands.py")) as f:
    RESULT["commands_source"] = f.read()
""".replace("PLACEMENT", repr(PLACEMENT)).replace("TOLERANCE", repr(TOLERANCE)).replace("POINTS", repr(str(POINTS)))


@pytest.fixture(scope="module")
def fc(tmp_path_factory, fc_home):  # noqa: F811
    return run_freecadcmd(SCRIPT, tmp_path_factory.mktemp("insp_run"), fc_home).check().result


@pytest.fixture(scope="module")
def lib():
    """The library's inspection of the same spec and points (the virtual environment's numpy)."""
    result = inspect_part(example_spec("default"), POINTS, tolerance=TOLERANCE)
    report, files = inspection_files(result)
    return result, report, files


def _leaves(d, path=""):
    if isinstance(d, dict):
        for k, v in d.items():
            yield from _leaves(v, f"{path}.{k}" if path else k)
    elif isinstance(d, list):
        for i, v in enumerate(d):
            yield from _leaves(v, f"{path}[{i}]")
    else:
        yield path, d


#: quantities that measure rounding itself (the chain's reproduction of the design's lift with δ = 0,
#: about 1e-11 mm): held below a bound, not to each other
ROUNDING = {"motion.design_reproduction": 1e-10}


def _same(got, want):
    g, w = dict(_leaves(got)), dict(_leaves(want))
    assert g.keys() == w.keys()
    bad = []
    for key, value in w.items():
        if key in ROUNDING:
            ok = abs(g[key]) < ROUNDING[key] and abs(value) < ROUNDING[key]
        elif isinstance(value, float):
            ok = g[key] == pytest.approx(value, rel=1e-9, abs=1e-12)
        else:
            ok = g[key] == value
        if not ok:
            bad.append(f"{key}: {g[key]!r} != {value!r}")
    assert not bad, "\n".join(bad)


def test_the_numbers_are_inspection_jsons(fc, lib):
    _result, want, _files = lib
    got = fc["report"]
    # the same files — the PNGs only where CairoSVG is installed (the virtual environment, not FreeCAD's Python)
    assert sorted(got["files"]) == sorted(n for n in want["files"] if not n.endswith(".png") or n in got["files"])
    _same({k: v for k, v in got.items() if k != "files"}, {k: v for k, v in want.items() if k != "files"})
    # the file the FreeCAD run wrote is the same exporter's
    _same(json.loads(fc["written"]["inspection.json"]), got)
    # what the docs' worked example shows (docs/inspection.md): the pose put in, the 76 dust points
    assert got["registration"]["outliers"] == 76 and abs(got["registration"]["rotation_deg"] - 30.0) < 0.003
    assert got["tolerance"]["verdict"] == "pass_excluding_outliers"


def test_the_shown_lines_are_its_values(fc):
    report = fc["report"]
    lines = fc["lines"]
    for key, at in (("registration.rotation_deg", None), ("registration.shift_x", None),
                    ("deviation.all_points.max", "deviation.all_points.max_at_deg"),
                    ("deviation.all_points.min", "deviation.all_points.min_at_deg"),
                    ("registration.outliers", None), ("tolerance.verdict", None),
                    ("motion.acceleration_error.max_abs", "motion.acceleration_error.at_deg"),
                    ("motion.acceleration_error.fraction_of_designed_peak", None)):
        text = fmt(lookup(report, key))
        hits = [ln for ln in lines if ": " + text in ln]
        assert hits, (key, text)
        if at is not None:
            assert any(f" at {fmt(lookup(report, at))}°" in ln for ln in hits), key
    a = report["motion"]["acceleration_error"]
    assert f"{fmt(a['max_abs'])} mm/s²" in fc["headline"]
    assert f"({fmt(100 * a['fraction_of_designed_peak'])} % of the designed peak)" in fc["headline"]
    assert "pass_excluding_outliers" in fc["headline"]


def test_bad_input_is_the_librarys_message_and_adds_nothing(fc, tmp_path):
    name, text, added = fc["bad"]
    assert name == "SpecError" and added == 0
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y\n1,2\n3,abc\n4,5\n")
    with pytest.raises(SpecError) as exc:
        read_points(bad)
    fc_file = text.split(": line")[0]        # the FreeCAD run's own bad.csv
    assert text == str(exc.value).replace(str(bad), fc_file)
    assert "bad.csv: line 3" in text and "'abc' is not a finite number" in text
    assert fc["bad_datum"][0] == "SpecError" and "datum" in fc["bad_datum"][1] and fc["bad_datum"][2] == 0


def _placed(xyz: np.ndarray) -> np.ndarray:
    """The cam's placement applied (rotation about z, then the shift), written out here."""
    (bx, by, bz), deg = PLACEMENT
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.column_stack([c * xyz[:, 0] - s * xyz[:, 1] + bx, s * xyz[:, 0] + c * xyz[:, 1] + by, xyz[:, 2] + bz])


def test_the_points_stand_where_the_registration_puts_them(fc, lib):
    result, want, _files = lib
    parts = fc["parts"]
    group = fc["group"]
    assert fc["groups"] == [group["name"]] and group["cam"] == "Cam"
    assert group["verdict"] == "pass_excluding_outliers" and group["objects"] == 1 + len(parts)
    # deviations.csv (the library's columns x_part, y_part, deviation, outlier) is every point's truth
    table = np.genfromtxt(fc["written"]["deviations.csv"].splitlines(), delimiter=",", names=True)
    d, out = table["deviation"], table["outlier"].astype(bool)
    thickness = example_spec("default").cam.thickness
    xyz = _placed(np.column_stack([table["x_part"], table["y_part"], np.full(len(d), thickness)]))
    # the classes: nine of equal width out to the largest inlier |d| or t/2 (here t/2 = 0.01, the larger)
    limit = max(np.max(np.abs(d[~out])), TOLERANCE / 2)
    edges = np.linspace(-limit, limit, 10)
    classes = [p for p in parts if p["low"] is not None]
    seen = 0
    for p in classes:
        assert p["placement"][0] == pytest.approx(list(PLACEMENT[0]))
        assert p["placement"][1] == pytest.approx(math.radians(PLACEMENT[1]))
        k = int(np.argmin(np.abs(edges - p["low"])))
        assert p["low"] == pytest.approx(edges[k], rel=1e-12) and p["high"] == pytest.approx(edges[k + 1], rel=1e-12)
        mine = ~out & (d >= edges[k]) & ((d < edges[k + 1]) if k < 8 else True)
        got = np.array(p["vertices"])
        assert len(got) == np.count_nonzero(mine), p["label"]
        # each vertex is one of the class's points (matched by nearest; 1e-9 mm)
        ref = xyz[mine]
        dist = np.min(np.linalg.norm(got[:, None, :] - ref[None, :, :], axis=2), axis=1)
        assert np.max(dist) < 1e-9
        seen += len(got)
        # whiskers: from the foot point on the exact profile through the point, k × its deviation long
        w = np.array(p["edges"])
        length = np.linalg.norm(w[:, 1] - w[:, 0], axis=1)
        dk = np.abs(d[mine])
        assert np.sort(length) == pytest.approx(np.sort(group["k"] * dk[dk > 0]), rel=1e-6)
    assert seen == np.count_nonzero(~out)
    outl = [p for p in parts if p["low"] is None]
    assert len(outl) == 1 and outl[0]["label"] == "outliers: 76 points"
    assert sorted(map(tuple, np.round(outl[0]["vertices"], 9))) == sorted(map(tuple, np.round(xyz[out], 9)))
    # the whisker scale: the largest 1-2-5 number keeping the longest whisker within R_b/10 (4 mm)
    k = group["k"]
    assert k * np.max(np.abs(d[~out])) <= 4.0 < 2.5 * k * np.max(np.abs(d[~out]))
    assert round(k / 10 ** math.floor(math.log10(k)), 9) in (1.0, 2.0, 5.0)


def test_a_whisker_runs_through_its_point(fc):
    """The point lies on its whisker's line, at 1/k of the way from the foot point (the deviation
    along the normal)."""
    k = fc["group"]["k"]
    for p in fc["parts"]:
        if p["low"] is None or not p["edges"]:
            continue
        v = np.array(p["vertices"])
        w = np.array(p["edges"])
        point = w[:, 0] + (w[:, 1] - w[:, 0]) / k
        dist = np.min(np.linalg.norm(point[:, None, :] - v[None, :, :], axis=2), axis=1)
        assert np.max(dist) < 1e-9, p["label"]


def test_the_command_is_in_the_menu_after_the_tolerance_study(fc):
    src = fc["commands_source"]
    assert '"CamWorkbench_InspectPart": InspectPart' in src and 'menu_text = "Inspect part…"' in src
    layout = src[src.index("LAYOUT = ["):]
    assert layout.index('"CamWorkbench_ToleranceStudy", "CamWorkbench_InspectPart"') > 0
    assert Path(ROOT / "cam_workbench" / "freecad" / "inspection_panel.py").is_file()


GUI = """
R = RESULT
POINTS = {points!r}
BAD = {bad!r}

def activate():
    FreeCADGui.activateWorkbench("CamWorkbench")

def new_cam():
    from cam_workbench.freecad import view_providers
    from cam_workbench.freecad.feature import create
    view_providers.register()  # as every command does first
    doc = FreeCAD.newDocument("Insp")
    doc.UndoMode = 1
    create(doc, None, name="Cam")
    doc.recompute()

def refused():
    from cam_workbench.freecad.inspection_panel import run_inspection
    doc = FreeCAD.ActiveDocument
    cam = doc.getObject("Cam")
    before = len(doc.Objects)
    def close(box):
        R["warning"] = box.text()
        box.accept()
    when_modal(close, QtGui.QMessageBox)
    R["refused"] = [run_inspection(cam, BAD, 0.02, "none", None) is None, len(doc.Objects) - before]

def inspect():
    from cam_workbench.freecad.inspection_panel import run_inspection
    doc = FreeCAD.ActiveDocument
    cam = doc.getObject("Cam")
    found = run_inspection(cam, POINTS, 0.02, "none", None)
    R["group"] = found.group.Name
    R["children"] = [o.Name for o in cam.ViewObject.Proxy.claimChildren()]
    R["undo"] = doc.UndoNames
    R["colors"] = [[round(c * 255) for c in o.ViewObject.PointColor[:3]] for o in found.group.Group]
    R["labels"] = [o.Label for o in found.group.Group]
    R["report"] = found.report

def shown():
    dlgs = [d for d in mw.findChildren(QtGui.QDialog, "CamWorkbenchInspection") if d.isVisible()]
    if not dlgs:
        raise NotYet("inspection dialog")
    t = dlgs[-1].findChild(QtGui.QTableWidget, "inspection")
    R["table"] = [[t.item(i, j).text() for j in range(2)] for i in range(t.rowCount())]
    R["report_view"] = report_text()
    dlgs[-1].accept()

steps = [(activate, 500), (new_cam, 500), (refused, 300), (inspect, 500), (shown, 300)]
"""


@requires_freecad_gui
def test_inspect_part_in_the_freecad_gui(tmp_path, fc_home):  # noqa: F811
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y\n1,2\n3,abc\n")
    r = run_freecad_gui(GUI.format(points=str(POINTS), bad=str(bad)), tmp_path / "run", fc_home).check().result
    assert r["refused"] == [True, 0] and r["warning"] == f"{bad}: line 3: 'abc' is not a finite number"
    assert r["group"] in r["children"] and r["undo"] == ["Inspect part"]
    # each class in its colour of the library's palette (most negative first), the outliers in red
    want = [[int(c[i:i + 2], 16) for i in (1, 3, 5)] for c in (*PALETTE, "#d62728")]
    assert r["labels"][-1] == "outliers: 76 points" and r["colors"][-1] == want[-1]
    assert all(c in want[:-1] for c in r["colors"][:-1]) and len({tuple(c) for c in r["colors"]}) == len(r["colors"])
    report = r["report"]
    a = report["motion"]["acceleration_error"]
    assert ["largest acceleration error |Δa|", f"{fmt(a['max_abs'])} mm/s² at {fmt(a['at_deg'])}°"] in r["table"]
    assert ["profile verdict (zone ±t/2)", "pass_excluding_outliers"] in r["table"]
    assert len(r["table"]) == len(rows(report))
    assert f"({fmt(100 * a['fraction_of_designed_peak'])} % of the designed peak)" in r["report_view"]
    assert "'abc' is not a finite number" in r["report_view"]

"""A machine in a real FreeCAD (``freecadcmd``): every cam of a machine file on one camshaft, turned by the
group's ``MachineAngle`` (:mod:`cam_workbench.freecad.machine_doc`, docs/freecad.md "Machines").

The example machine (docs/examples/machine_three_cams.toml: a translating roller, an oscillating roller arm
and a translating flat face, phases 0°, 100°, 170°) is opened with ``open_machine``: one valid solid per
cam, their bores' circles on one line (the shaft), their z ranges the slots z_i = Σ_{j<i}(t_j + gap) with
no two overlapping, a shaft cylinder through the bores that meets no cam.  At machine angles φ (set and
recomputed, or stepped with ``step_machine`` as *Play* does) each cam is turned by δ·(φ − phase) and its
drawn follower stands where the mechanism puts it in the fixed frame: the follower point written out here
from docs/followers.md "Conventions" with s(θ), s′(θ) of the library's program (``design_cam`` of the
same spec, run in this process, not FreeCAD's), the roller touching the turned cam.  A bad machine file
fails with the library's own message naming the field, and adds nothing.
"""
from __future__ import annotations

import cmath
import math
from pathlib import Path

import numpy as np
import pytest

from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.machine import load_machine

from .conftest import ROOT
from .freecad_support import (fc_home, requires_freecad_gui, requires_freecadcmd,  # noqa: F401
                              run_freecad_gui, run_freecadcmd)

pytestmark = requires_freecadcmd

EXAMPLE = ROOT / "docs" / "examples" / "machine_three_cams.toml"
GAP = 5.0  # the default gap between cams [mm] (machine_doc.DEFAULT_GAP_MM), written out
#: (machine angle, how it is applied): "recompute" sets MachineAngle and recomputes, "step" is step_machine
ANGLES = [(0.0, "recompute"), (50.0, "step"), (135.0, "recompute"), (215.0, "step"), (300.0, "step"),
          (359.0, "recompute")]
REOPENED_ANGLE = 77.0
#: bad machine files: (what is changed in the example's text, the field the message names)
BAD = {
    "phase": (("phase = 100.0", "phase = 400.0"), "cam[1].phase"),
    "cam_spec": (("base_radius = 45.0", "base_radius = -45.0"), "cam[2].spec.cam.base_radius"),
}

SCRIPT = """
import os
import FreeCAD, Part
from cam_workbench.generators.errors import SpecError
from cam_workbench.freecad.feature import reference_of
from cam_workbench.freecad.machine_doc import open_machine, step_machine, is_machine

def xyz(v):
    return [v.x, v.y, v.z]

def cam_state(c):
    f = reference_of(c, "follower")
    s = c.Shape
    top = s.BoundBox.ZMax
    out = {"angle": f.FollowerAngle.Value, "base": xyz(c.Placement.Base),
           "x_axis": xyz(c.Placement.Rotation.multVec(FreeCAD.Vector(1, 0, 0))),
           "z_axis": xyz(c.Placement.Rotation.multVec(FreeCAD.Vector(0, 0, 1))),
           "vertices": [], "circles": [], "top": top}
    for e in f.Shape.childShapes():
        if e.ShapeType == "Vertex":
            out["vertices"].append(xyz(e.Point) + [e.distToShape(s)[0]])
        elif e.Curve.TypeId == "Part::GeomCircle":
            out["circles"].append({"centre": xyz(e.Curve.Center), "r": e.Curve.Radius,
                                   "touch": e.distToShape(s)[0],
                                   "centre_to_cam": Part.Vertex(e.Curve.Center).distToShape(s)[0]})
    return out

doc = FreeCAD.newDocument("machine")
g = open_machine(doc, EXAMPLE)
RESULT["group"] = {"name": g.Name, "label": g.Label, "type": g.TypeId, "phases": list(g.Phases),
                   "group": [o.Name for o in g.Group], "cams": [c.Name for c in g.Cams],
                   "gap": g.CamGap.Value, "angle": g.MachineAngle.Value}
RESULT["cams"] = []
for c in g.Cams:
    s = c.Shape
    bores = [e for e in s.Edges if e.Curve.TypeId == "Part::GeomCircle"
             and abs(e.Curve.Radius - c.CamBoreDiameter.Value / 2) < 1e-9]
    RESULT["cams"].append({"label": c.Label, "status": c.Status, "valid": s.isValid(), "solids": len(s.Solids),
                           "volume": s.Volume, "z": [s.BoundBox.ZMin, s.BoundBox.ZMax],
                           "thickness": c.CamThickness.Value, "direction": c.CamDirection,
                           "bores": [xyz(e.Curve.Center) + xyz(e.Curve.Axis) for e in bores]})
sh = g.Shaft
RESULT["shaft"] = {"radius": sh.Radius.Value, "z": [sh.Shape.BoundBox.ZMin, sh.Shape.BoundBox.ZMax],
                   "axis": xyz(sh.Placement.Rotation.multVec(FreeCAD.Vector(0, 0, 1))),
                   "base": xyz(sh.Placement.Base),
                   "common": [sh.Shape.common(c.Shape).Volume for c in g.Cams]}
RESULT["angles"] = {}
for phi, how in ANGLES:
    if how == "step":
        step_machine(g, phi)
    else:
        g.MachineAngle = phi
        doc.recompute()
    RESULT["angles"][str(phi)] = {"touched": [o.Name for o in doc.Objects if "Touched" in o.State],
                                  "status": [c.Status for c in g.Cams],
                                  "cams": [cam_state(c) for c in g.Cams]}

# saved and reopened: the group still drives its cams (step_machine recomputes the uncached cams)
path = os.path.join(OUT, "machine.FCStd")
doc.saveAs(path)
FreeCAD.closeDocument(doc.Name)
doc2 = FreeCAD.openDocument(path)
g2 = doc2.getObject(RESULT["group"]["name"])
step_machine(g2, REOPENED)
RESULT["reopened"] = {"is_machine": is_machine(g2), "status": [c.Status for c in g2.Cams],
                      "cams": [cam_state(c) for c in g2.Cams]}
FreeCAD.closeDocument(doc2.Name)

RESULT["bad"] = {}
for key, bad in BAD.items():
    d = FreeCAD.newDocument("bad_" + key)
    try:
        open_machine(d, bad)
        RESULT["bad"][key] = {"error": None}
    except SpecError as exc:
        RESULT["bad"][key] = {"error": str(exc), "field": exc.field}
    RESULT["bad"][key]["objects"] = len(d.Objects)
    FreeCAD.closeDocument(d.Name)

import FreeCADGui  # importable in freecadcmd: the command table and menu layout
from cam_workbench.freecad import commands as C
RESULT["commands"] = {n: [c.menu_text, c.needs_cam] for n, c in C.COMMANDS.items()}
RESULT["layout"] = list(C.LAYOUT)
"""


def _bad_files(folder: Path) -> dict[str, Path]:
    text = EXAMPLE.read_text(encoding="utf-8")
    out = {}
    for key, ((old, new), _field) in BAD.items():
        assert text.count(old) == 1, old
        out[key] = folder / f"bad_{key}.toml"
        out[key].write_text(text.replace(old, new), encoding="utf-8")
    return out


@pytest.fixture(scope="module")
def machine():
    """The example machine, validated and designed by the library in this process."""
    m = load_machine(EXAMPLE)
    return m, [design_cam(c.spec) for c in m.cams]


@pytest.fixture(scope="module")
def run(fc_home, tmp_path_factory):  # noqa: F811
    tmp = tmp_path_factory.mktemp("freecad_machine")
    bad = _bad_files(tmp)
    body = (f"EXAMPLE = {str(EXAMPLE)!r}\nOUT = {str(tmp)!r}\nANGLES = {ANGLES!r}\nREOPENED = {REOPENED_ANGLE!r}\n"
            f"BAD = {({k: str(v) for k, v in bad.items()})!r}\n" + SCRIPT)
    return run_freecadcmd(body, tmp, fc_home).check(), bad


# ---- the mechanism, written out here from docs/followers.md "Conventions" ----------------------
def _layout(m) -> list[tuple[float, float]]:
    """(z_start, thickness) of each cam along the shaft: z_i = Σ_{j<i} (t_j + gap) [mm]."""
    out, z = [], 0.0
    for c in m.cams:
        t = c.spec.cam.thickness  # the example is in mm
        out.append((z, t))
        z += t + GAP
    return out


def _cam_angle(phi: float, phase: float) -> float:
    return (phi - phase) % 360.0


def _follower_point(spec, design, theta_deg: float) -> complex:
    """The follower point in the fixed frame at cam angle θ: translating (e, √(R_b² − e²) + s); an
    oscillating arm's A = D + L·e^{i(ψ₀ − s)}, D = (d, 0); a translating flat face's contact (δ·s′, R_b + s).
    s and s′ from the library's program of the spec."""
    k = design.program.evaluate(np.array([math.radians(theta_deg)]))
    s, ds = float(k.s[0]), float(k.ds[0])
    fol, rb = spec.follower, spec.cam.base_radius
    delta = 1.0 if spec.cam.direction == "ccw" else -1.0
    if fol.motion == "oscillating":
        d, arm = fol.pivot_distance, fol.arm_length
        psi0 = math.acos((rb * rb - d * d - arm * arm) / (2 * d * arm))
        return d + arm * cmath.exp(1j * (psi0 - math.radians(s)))
    if fol.kind == "flat":
        return complex(delta * ds, rb + s)
    e = fol.offset or 0.0
    return complex(e, math.sqrt(rb * rb - e * e) + s)


def _check_cams(state: list[dict], m, designs, phi: float) -> None:
    for i, (c, design, st, (z0, t)) in enumerate(zip(m.cams, designs, state, _layout(m))):
        theta = _cam_angle(phi, c.phase)
        delta = 1.0 if c.spec.cam.direction == "ccw" else -1.0
        assert st["angle"] == pytest.approx(theta, abs=1e-9), (c.name, phi)
        # the cam turned by δθ about the shaft, in its slot
        assert st["base"] == pytest.approx([0.0, 0.0, z0], abs=1e-12)
        assert st["z_axis"] == pytest.approx([0.0, 0.0, 1.0], abs=1e-12)
        turned = math.degrees(math.atan2(st["x_axis"][1], st["x_axis"][0]))
        assert (turned - delta * theta + 180.0) % 360.0 - 180.0 == pytest.approx(0.0, abs=1e-9), (c.name, phi)
        # the follower point where the mechanism puts it, on the plane of the cam's top face
        want = _follower_point(c.spec, design, theta)
        pts = [(complex(v[0], v[1]), v[2], v[3]) for v in st["vertices"]]
        got = min(pts, key=lambda p: abs(p[0] - want))
        assert abs(got[0] - want) < 1e-7, (c.name, phi, got, want)
        assert got[1] == pytest.approx(z0 + t, abs=1e-9)
        assert st["top"] == pytest.approx(z0 + t, abs=1e-6)
        rr = c.spec.follower.roller_radius if c.spec.follower.kind == "roller" else 0.0
        if c.spec.follower.motion == "oscillating":   # the pivot stays put
            assert min(abs(p[0] - c.spec.follower.pivot_distance) for p in pts) < 1e-7
        # the follower touches the turned cam within the built curve's own error (the library's
        # pitch.max_deviation: a length, or the arm's degrees — as a length at the arm's end)
        dev = design.summary()["pitch"]["max_deviation"]
        if c.spec.follower.motion == "oscillating":
            dev = c.spec.follower.arm_length * math.radians(dev)
        tol = dev + 1e-6
        if rr > 0:   # the roller touches the turned cam
            roller, = [r for r in st["circles"] if abs(r["r"] - rr) < 1e-9]
            assert abs(complex(*roller["centre"][:2]) - want) < 1e-7
            assert roller["centre_to_cam"] == pytest.approx(rr, abs=tol) and roller["touch"] < tol
        else:        # a face's contact point lies on the turned cam
            assert got[2] < tol, (c.name, phi, got)


# ---- the tests ------------------------------------------------------------------------------
def test_one_valid_cam_per_machine_cam(run, machine):
    r, _bad = run
    m, _designs = machine
    g = r.result["group"]
    assert g["type"] == "App::DocumentObjectGroupPython" and g["label"] == m.machine.name
    assert g["phases"] == [c.phase for c in m.cams]
    assert len(g["cams"]) == len(m.cams) == 3 and g["gap"] == GAP
    assert set(g["cams"]) <= set(g["group"])
    assert [c["label"] for c in r.result["cams"]] == [c.name for c in m.cams]
    for c in r.result["cams"]:
        assert c["status"] == "ok" and c["valid"] and c["solids"] == 1 and c["volume"] > 0


def test_cams_on_one_shaft_without_overlap(run, machine):
    """The bores' circles (two per cam) all lie on one line, their axes along it; the cams' z ranges are
    their slots along the shaft and disjoint; the shaft runs through every bore and meets no cam."""
    r, _bad = run
    m, _designs = machine
    centres, axes = [], []
    for c in r.result["cams"]:
        assert len(c["bores"]) == 2, c["bores"]
        centres += [np.array(b[:3]) for b in c["bores"]]
        axes += [np.array(b[3:]) for b in c["bores"]]
    p0, p1 = centres[0], max(centres, key=lambda p: np.linalg.norm(p - centres[0]))
    line = (p1 - p0) / np.linalg.norm(p1 - p0)
    for p, a in zip(centres, axes):
        assert np.linalg.norm(np.cross(p - p0, line)) < 1e-9
        assert np.linalg.norm(np.cross(a, line)) < 1e-12
    zs = [c["z"] for c in r.result["cams"]]
    assert zs == [pytest.approx([z0, z0 + t], abs=1e-6) for z0, t in _layout(m)]
    for i in range(len(zs) - 1):
        assert zs[i][1] + GAP - 1e-6 < zs[i + 1][0]
    sh = r.result["shaft"]
    bore = min(c.spec.cam.bore_diameter for c in m.cams) / 2
    assert 0 < sh["radius"] < bore
    assert sh["axis"] == pytest.approx([0, 0, 1], abs=1e-12) and sh["base"][:2] == pytest.approx([0, 0], abs=1e-12)
    assert sh["z"][0] < zs[0][0] and sh["z"][1] > zs[-1][1]
    assert all(v < 1e-9 for v in sh["common"]), sh["common"]


@pytest.mark.parametrize("phi,how", ANGLES)
def test_machine_angle_turns_every_cam(run, machine, phi, how):
    """At MachineAngle φ each cam stands at θ = φ − phase: its placement turned by δθ, its follower where
    the mechanism puts it for s(θ) — whether set and recomputed or stepped as Play does (nothing left
    to recompute)."""
    r, _bad = run
    m, designs = machine
    a = r.result["angles"][str(phi)]
    assert a["status"] == ["ok"] * len(m.cams)
    assert a["touched"] == []
    _check_cams(a["cams"], m, designs, phi)


def test_reopened_machine_still_drives(run, machine):
    r, _bad = run
    m, designs = machine
    re = r.result["reopened"]
    assert re["is_machine"] and re["status"] == ["ok"] * len(m.cams)
    _check_cams(re["cams"], m, designs, REOPENED_ANGLE)


@pytest.mark.parametrize("key", list(BAD))
def test_bad_machine_file_names_the_field(run, key):
    """The library's own message (load_machine here), naming the field; nothing added to the document."""
    r, bad = run
    with pytest.raises(SpecError) as exc:
        load_machine(bad[key])
    got = r.result["bad"][key]
    assert got["error"] == str(exc.value)
    assert got["field"] == exc.value.field == BAD[key][1]
    assert BAD[key][1] in got["error"]
    assert got["objects"] == 0


def test_commands_registered(run):
    """*Open machine…* (needs no cam) and *Play machine* are workbench commands in the Cam menu."""
    r, _bad = run
    cmds, layout = r.result["commands"], r.result["layout"]
    assert cmds["CamWorkbench_OpenMachine"] == ["Open machine…", False]
    assert cmds["CamWorkbench_PlayMachine"][0] == "Play machine"
    assert {"CamWorkbench_OpenMachine", "CamWorkbench_PlayMachine"} <= set(layout)


# ---- the GUI: Open machine… through its file dialog, then Play ---------------------------------
GUI = """
R = RESULT
ART = {art!r}
EXAMPLE = {example!r}
state = {{}}

def activate():
    mw.resize(1400, 900)
    FreeCADGui.activateWorkbench("CamWorkbench")

def open_file():
    def fill(w):
        R["file_dialog"] = type(w).__name__
        w.findChild(QtGui.QLineEdit, "fileNameEdit").setText(EXAMPLE)
        w.accept()
        if w.isVisible():   # never leave a modal dialog behind
            R["file_dialog_refused"] = True
            w.reject()
    when_modal(fill, QtGui.QFileDialog)
    FreeCADGui.runCommand("CamWorkbench_OpenMachine")

def machine():
    from cam_workbench.freecad.machine_doc import machines_of
    ms = machines_of(FreeCAD.ActiveDocument)
    if not ms:
        raise NotYet("machine")
    return ms[0]

def state_of(g):
    from cam_workbench.freecad.feature import reference_of
    return {{"angle": g.MachineAngle.Value, "phases": list(g.Phases),
            "followers": [reference_of(c, "follower").FollowerAngle.Value for c in g.Cams],
            "status": [c.Status for c in g.Cams]}}

def opened():
    g = machine()
    R["opened"] = state_of(g)
    R["opened"]["labels"] = [c.Label for c in g.Cams]
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.runCommand("CamWorkbench_PlayMachine")

def push(text):
    for b in task_dock().findChildren(QtGui.QPushButton):
        if b.isVisible() and b.text() == text:
            b.click()
            return
    raise NotYet(text)

def play():
    push("Play")

def playing():
    a = machine().MachineAngle.Value
    if a < 30.0:   # the timer has not turned the camshaft far enough yet
        raise NotYet("playing")
    push("Stop")
    R["played"] = state_of(machine())
    shot("freecad_gui_machine_play.png")

def slide():
    sliders = [w for w in task_dock().findChildren(QtGui.QSlider) if w.isVisible()]
    if not sliders:
        raise NotYet("slider")
    sliders[0].setValue(200)
    R["slid"] = state_of(machine())

def close():
    button("Close").click()
    R["report"] = report_text()

steps = [(activate, 500), (open_file, 1000), (opened, 1000), (play, 200), (playing, 200), (slide, 500),
         (close, 500)]
"""


def _consistent(st: dict) -> None:
    """Every follower at φ − phase (mod 360) of the group's angle."""
    for angle, phase in zip(st["followers"], st["phases"]):
        assert angle == pytest.approx(_cam_angle(st["angle"], phase), abs=1e-9), st
    assert st["status"] == ["ok"] * len(st["phases"])


@requires_freecad_gui
def test_open_and_play_in_the_gui(tmp_path, fc_home, artifacts, machine):  # noqa: F811
    """*Open machine…* through its file dialog opens the example's cams; *Play machine*'s timer turns the
    camshaft (its followers at φ − phase all along), *Stop* halts it, the slider sets the angle."""
    m, _designs = machine
    run = run_freecad_gui(GUI.format(art=str(artifacts), example=str(EXAMPLE)), tmp_path, fc_home)
    (artifacts / "freecad_gui_machine_console.txt").write_text(run.console)
    r = run.check().result
    assert r["file_dialog"] == "QFileDialog" and "file_dialog_refused" not in r
    assert r["opened"]["labels"] == [c.name for c in m.cams] and r["opened"]["angle"] == 0.0
    _consistent(r["opened"])
    assert r["played"]["angle"] >= 30.0
    _consistent(r["played"])
    assert r["slid"]["angle"] == 200.0
    _consistent(r["slid"])
    assert "Traceback" not in r["report"] and "Error" not in r["report"], r["report"]

"""A machine in a real FreeCAD (``freecadcmd``): every cam of a machine file on one camshaft, turned by the
group's ``MachineAngle`` (:mod:`cam_workbench.freecad.machine_doc`, docs/freecad.md "Machines").

The example machine (docs/examples/machine_three_cams.toml: a translating roller, an oscillating roller arm
and a translating flat face, phases 0°, 100°, 170°) is opened with ``open_machine``: one valid solid per
cam, their bores' circles on one line (the shaft), their z ranges the slots z_i = Σ_{j<i}(t_j + gap) with
no two overlapping, a shaft cylinder through the bores that meets no cam.  At machine angles φ (set and
recomputed, or stepped with ``step_machine`` as *Play* does) each cam is turned by δ·(φ − phase) and its
drawn follower stands where the mechanism puts it in the fixed frame: the follower point written out here
from docs/followers.md "Conventions" with s(θ), s′(θ) of the library's program (``design_cam`` of the
same spec, run in this process, not FreeCAD's), the roller touching the turned cam.  What each cam moves
stands where the mechanism puts it, to 1e-6 mm: the follower part's roller, pivot and face, the linkage's
pins (the pusher's lever, the gripper's four-bar, both written out here from the spec's numbers) and the tool
(written out, and where the clearance check's own pose function ``tool_drive(...).at_machine`` puts it).
A bad machine file fails with the library's own message naming the field, and adds nothing.
"""
from __future__ import annotations

import cmath
import json
import math
from pathlib import Path

import numpy as np
import pytest

from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.machine import load_machine, tool_drive

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

def part_state(p):
    s = p.Shape
    rot = p.Placement.Rotation
    return {"label": p.Label, "type": p.TypeId, "valid": s.isValid(), "null": s.isNull(),
            "base": xyz(p.Placement.Base), "axis": xyz(rot.Axis), "angle": rot.Angle,
            "circles": [xyz(e.Curve.Center) + [e.Curve.Radius] for e in s.Edges
                        if e.Curve.TypeId == "Part::GeomCircle"],
            "vertices": [xyz(v.Point) for v in s.Vertexes], "zrange": [s.BoundBox.ZMin, s.BoundBox.ZMax]}

def parts_state(g, c):
    return {p.Role: part_state(p) for p in g.Parts if p.Cam.Name == c.Name}

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
RESULT["folders"] = [{"type": o.TypeId, "label": o.Label, "children": [x.Name for x in o.Group]}
                     for o in g.Group if o.TypeId == "App::DocumentObjectGroup"]
RESULT["parts"] = [{"name": p.Name, "label": p.Label, "type": p.TypeId, "role": p.Role, "cam": p.Cam.Name,
                    "outline": p.Outline if "Outline" in p.PropertiesList else None} for p in g.Parts]
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
                                  "cams": [cam_state(c) for c in g.Cams],
                                  "parts": [parts_state(g, c) for c in g.Cams]}

# saved and reopened: the group still drives its cams (step_machine recomputes the uncached cams)
path = os.path.join(OUT, "machine.FCStd")
doc.saveAs(path)
FreeCAD.closeDocument(doc.Name)
doc2 = FreeCAD.openDocument(path)
g2 = doc2.getObject(RESULT["group"]["name"])
step_machine(g2, REOPENED)
RESULT["reopened"] = {"is_machine": is_machine(g2), "status": [c.Status for c in g2.Cams],
                      "cams": [cam_state(c) for c in g2.Cams], "parts": [parts_state(g2, c) for c in g2.Cams],
                      "touched": [o.Name for o in doc2.Objects if "Touched" in o.State]}
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


# ---- what the cams move, written out here from the example's numbers ---------------------------
#: each cam's parts in the example: every cam has a follower and a [cam.tool]; the lifter no [linkage]
ROLES = {"pusher": ["follower", "linkage", "tool"], "gripper": ["follower", "linkage", "tool"],
         "lifter": ["follower", "tool"]}
#: pin radius and tool plate thickness as fractions of the cam's thickness (machine_parts.PIN, TOOL_PLATE)
PIN, TOOL_PLATE = 0.2, 0.25
#: positions agree with the mechanism to this [mm]
TOL = 1e-6


def _lever(spec, s: float) -> dict[str, complex]:
    """The pusher's lever (docs/linkages.md; the lever module's docstring): the stem's line x = e along +y
    pushes the bar at I = (e, P_y) + s·(0, 1) (the foot of the perpendicular from the tool's pivot P); the
    tool slides along ``direction`` (+y here, parallel to the stem) from P: T = P + r·s·(0, 1); the bar
    through both turns about the fixed fulcrum F with T − F = r·(I − F): F = (P − r·I₀)/(1 − r)."""
    link, e = spec.linkage, spec.follower.offset or 0.0
    assert link.direction == 90.0   # the tool's line parallel to the stem, as written out here
    r, p = link.ratio, complex(link.pivot_x, link.pivot_y)
    i0 = complex(e, link.pivot_y)
    return {"input": i0 + 1j * s, "fulcrum": (p - r * i0) / (1.0 - r), "tool": p + 1j * r * s}


def _four_bar(spec, s_deg: float) -> tuple[dict[str, complex], float]:
    """The gripper's four-bar (Norton §4.5; docs/linkages.md): crank pivot O₂ = (pivot_x, pivot_y), rocker
    pivot O₄ = O₂ + ground·e^{iγ}, the crank (the arm) at A = O₂ + crank·e^{i(γ + crank_offset − q)}, q the
    arm's rotation; B the point at coupler from A and rocker from O₄ on the left of O₄→A ("left"), the
    circle–circle intersection.  Returns the joints and the rocker's rotation from q = 0 [rad]."""
    link = spec.linkage
    assert link.branch == "left" and link.tool_radius is None   # B, left, as written out here
    g = math.radians(link.frame_angle)
    o2 = complex(link.pivot_x, link.pivot_y)
    o4 = o2 + link.ground * cmath.exp(1j * g)

    def at(q: float) -> tuple[complex, complex]:
        a = o2 + link.crank * cmath.exp(1j * (g + math.radians(link.crank_offset) - q))
        e = abs(a - o4)
        x = (link.rocker ** 2 + e * e - link.coupler ** 2) / (2 * e)
        return a, o4 + (a - o4) / e * complex(x, math.sqrt(link.rocker ** 2 - x * x))

    a, b = at(math.radians(s_deg))
    _, b0 = at(0.0)
    turn = (cmath.phase(b - o4) - cmath.phase(b0 - o4) + math.pi) % (2 * math.pi) - math.pi
    return {"crank_pivot": o2, "rocker_pivot": o4, "crank_joint": a, "rocker_joint": b, "tool": b}, turn


def _mechanism(c, design, phi: float) -> dict:
    """The example cam ``c``'s follower point, linkage joints and tool pose at machine angle φ, written out."""
    theta = _cam_angle(phi, c.phase)
    s = float(design.program.evaluate(np.array([math.radians(theta)])).s[0])
    spec = c.spec
    joints: dict[str, complex] = {}
    turn = 0.0
    if spec.linkage.kind == "lever":
        joints = _lever(spec, s)
        tool = joints["tool"]
    elif spec.linkage.kind == "four_bar":
        joints, turn = _four_bar(spec, s)
        tool = joints["tool"]
    else:   # the lifter: [cam.tool] origin + s·(cos, sin)(direction)
        tool = complex(*c.tool.origin) + s * cmath.exp(1j * math.radians(c.tool.direction))
    return {"point": _follower_point(spec, design, theta), "s": s, "joints": joints, "tool": tool, "turn": turn}


def _has_point(points: list, want: complex, z: float | None = None) -> bool:
    return any(abs(complex(p[0], p[1]) - want) < TOL and (z is None or abs(p[2] - z) < TOL) for p in points)


def _check_parts(parts: list[dict], m, designs, phi: float) -> None:
    for c, design, got, (z0, t) in zip(m.cams, designs, parts, _layout(m)):
        assert sorted(got) == sorted(ROLES[c.name]), (c.name, list(got))
        want = _mechanism(c, design, phi)
        fol, spec = got["follower"], c.spec
        for part in got.values():
            assert part["valid"] and not part["null"], (c.name, part["label"])
        assert fol["zrange"] == pytest.approx([z0, z0 + t], abs=1e-6)   # in the cam's slot
        # the follower: the roller about the follower point over the cam's thickness, an arm's pivot pin, a
        # flat face of face_width centred on the stem at R_b + s over the thickness
        if spec.follower.kind == "roller":
            rollers = [cc for cc in fol["circles"] if abs(cc[3] - spec.follower.roller_radius) < 1e-9]
            assert len(rollers) == 2 and sorted(cc[2] for cc in rollers) == pytest.approx([z0, z0 + t], abs=1e-9)
            for cc in rollers:
                assert abs(complex(cc[0], cc[1]) - want["point"]) < TOL, (c.name, phi, cc, want["point"])
        if spec.follower.motion == "oscillating":
            assert _has_point([cc for cc in fol["circles"] if abs(cc[3] - PIN * t) < 1e-9],
                              complex(spec.follower.pivot_distance, 0.0), z0)
        if spec.follower.kind == "flat":
            half, y = spec.follower.face_width / 2, spec.cam.base_radius + want["s"]
            for x in (-half, half):
                for z in (z0, z0 + t):
                    assert _has_point(fol["vertices"], complex(x, y), z), (c.name, phi, x, y, z)
        # the linkage: a pin (radius PIN·t, over the slot) at every joint
        if "linkage" in got:
            pins = [cc for cc in got["linkage"]["circles"] if abs(cc[3] - PIN * t) < 1e-9]
            for name, at in want["joints"].items():
                assert _has_point(pins, at, z0), (c.name, phi, name, at)
        # the tool: its frame at the tool point, turned by the tool's rotation — written out, and where the
        # clearance check's pose function puts it
        tool = got["tool"]
        poses = tool_drive(c.name, spec, c.phase, design.program, c.tool).at_machine(np.array([phi]))
        check = complex(*poses.positions[0])
        check_turn = 0.0 if poses.angles is None else float(poses.angles[0])
        assert abs(check - want["tool"]) < TOL and check_turn == pytest.approx(want["turn"], abs=1e-9)
        h = TOOL_PLATE * t
        assert abs(complex(*tool["base"][:2]) - want["tool"]) < TOL, (c.name, phi, tool["base"], want["tool"])
        assert tool["base"][2] == pytest.approx(z0 + (t - h) / 2, abs=1e-9)
        assert tool["zrange"] == pytest.approx([z0 + (t - h) / 2, z0 + (t + h) / 2], abs=1e-6)
        turned = tool["angle"] * (1.0 if tool["axis"][2] >= 0 else -1.0)
        assert (turned - want["turn"] + math.pi) % (2 * math.pi) - math.pi == pytest.approx(0.0, abs=1e-9)
        if c.tool.radius is not None:
            assert _has_point([cc for cc in tool["circles"] if abs(cc[3] - c.tool.radius) < 1e-9], want["tool"])
        else:
            for vx, vy in c.tool.polygon:
                corner = want["tool"] + complex(vx, vy) * cmath.exp(1j * want["turn"])
                assert _has_point(tool["vertices"], corner), (c.name, phi, corner)


# ---- the tests ------------------------------------------------------------------------------
def test_one_valid_cam_per_machine_cam(run, machine):
    r, _bad = run
    m, _designs = machine
    g = r.result["group"]
    assert g["type"] == "App::DocumentObjectGroupPython" and g["label"] == m.machine.name
    assert g["phases"] == [c.phase for c in m.cams]
    assert len(g["cams"]) == len(m.cams) == 3 and g["gap"] == GAP
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


def test_each_cam_with_its_parts_in_its_folder(run, machine):
    """Each cam sits in its folder "<cam> mechanism" (in the machine group) with the parts it moves, named
    after it and listed in the group's ``Parts``: its follower, its linkage (when it has one) and its tool
    (when it has a [cam.tool], whose table the tool part keeps)."""
    r, _bad = run
    m, _designs = machine
    g = r.result["group"]
    folders = r.result["folders"]
    assert [f["label"] for f in folders] == [f"{c.name} mechanism" for c in m.cams]
    parts = {p["name"]: p for p in r.result["parts"]}
    for c, cam, folder in zip(m.cams, g["cams"], folders):
        assert folder["type"] == "App::DocumentObjectGroup" and folder["children"][0] == cam
        mine = [parts[n] for n in folder["children"][1:]]
        assert [p["role"] for p in mine] == ROLES[c.name]
        assert all(p["cam"] == cam and p["type"] == "Part::Feature" for p in mine)
        assert [p["label"] for p in mine[:-1]] == [f"{c.name} {p['role']}" for p in mine[:-1]]
        tool = mine[-1]
        assert tool["label"] == f"{c.name} tool ({c.tool.label})"
        assert json.loads(tool["outline"]) == c.tool.to_dict()
    assert sorted(parts) == sorted(n for f in folders for n in f["children"][1:])
    assert set(g["group"]) == {f"{n}_Mechanism" for n in g["cams"]} | {g["name"].replace("Machine_", "", 1) + "_Shaft"}


@pytest.mark.parametrize("phi,how", ANGLES)
def test_parts_where_the_mechanism_puts_them(run, machine, phi, how):
    """At MachineAngle φ — set and recomputed, or stepped as *Play* does — every part stands where the
    mechanism puts it for s(φ − phase), to 1e-6 mm: roller, pivot, face, linkage pins, tool."""
    r, _bad = run
    m, designs = machine
    _check_parts(r.result["angles"][str(phi)]["parts"], m, designs, phi)


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
    assert re["is_machine"] and re["status"] == ["ok"] * len(m.cams) and re["touched"] == []
    _check_cams(re["cams"], m, designs, REOPENED_ANGLE)
    _check_parts(re["parts"], m, designs, REOPENED_ANGLE)


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
            "status": [c.Status for c in g.Cams],
            "colours": [[p.Role, list(p.ViewObject.ShapeColor[:3])] for p in g.Parts],
            "tools": {{p.Cam.Label: [p.Placement.Base.x, p.Placement.Base.y,
                                    p.Placement.Rotation.Angle * (1 if p.Placement.Rotation.Axis.z >= 0 else -1)]
                      for p in g.Parts if p.Role == "tool"}}}}

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


#: the parts' colours (machine_parts.COLOURS: the animation's follower, link and tool colours), written out
COLOURS = {"follower": (0.541, 0.384, 0.071), "linkage": (0.180, 0.490, 0.196), "tool": (0.416, 0.106, 0.604)}


def _consistent(st: dict, m, designs) -> None:
    """Every follower at φ − phase (mod 360) of the group's angle, every tool where the clearance check puts
    it at φ, every part in its colour (FreeCAD keeps colours to 1/255)."""
    for angle, phase in zip(st["followers"], st["phases"]):
        assert angle == pytest.approx(_cam_angle(st["angle"], phase), abs=1e-9), st
    assert st["status"] == ["ok"] * len(st["phases"])
    assert sorted(st["tools"]) == sorted(c.name for c in m.cams)
    for c, design in zip(m.cams, designs):
        poses = tool_drive(c.name, c.spec, c.phase, design.program, c.tool).at_machine(np.array([st["angle"]]))
        turn = 0.0 if poses.angles is None else float(poses.angles[0])
        x, y, angle = st["tools"][c.name]
        assert abs(complex(x, y) - complex(*poses.positions[0])) < TOL and angle == pytest.approx(turn, abs=1e-9)
    for role, colour in st["colours"]:
        assert colour == pytest.approx(COLOURS[role], abs=1 / 255), (role, colour)


@requires_freecad_gui
def test_open_and_play_in_the_gui(tmp_path, fc_home, artifacts, machine):  # noqa: F811
    """*Open machine…* through its file dialog opens the example's cams; *Play machine*'s timer turns the
    camshaft (its followers at φ − phase all along, its tools where the clearance check puts them, the parts
    in their colours), *Stop* halts it, the slider sets the angle."""
    m, designs = machine
    run = run_freecad_gui(GUI.format(art=str(artifacts), example=str(EXAMPLE)), tmp_path, fc_home)
    (artifacts / "freecad_gui_machine_console.txt").write_text(run.console)
    r = run.check().result
    assert r["file_dialog"] == "QFileDialog" and "file_dialog_refused" not in r
    assert r["opened"]["labels"] == [c.name for c in m.cams] and r["opened"]["angle"] == 0.0
    _consistent(r["opened"], m, designs)
    assert r["played"]["angle"] >= 30.0
    _consistent(r["played"], m, designs)
    assert r["slid"]["angle"] == 200.0
    _consistent(r["slid"], m, designs)
    assert "Traceback" not in r["report"] and "Error" not in r["report"], r["report"]

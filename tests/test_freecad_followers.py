"""Every follower kind in the ``Cam`` feature inside a real FreeCAD (``freecadcmd``).

An oscillating roller (the built-in example), an oscillating knife edge (inches, cw), a
translating flat face (the built-in example) and an oscillating flat face are created with
``feature.create`` — the function the GUI commands call — and recomputed in one FreeCAD; then:

- the solid's volume against the library's exact volume (Green's area × thickness) and against
  ``report.json`` of ``cam-workbench build`` run in a subprocess on the spec FreeCAD exports;
- the drawn follower (the reference child) against the mechanism computed here from the
  conventions of docs/followers.md — pivot, arm length, roller centre on the pitch point, the flat
  face's line and contact point, with the laws written out — and against the cam FreeCAD built
  (a roller touches the profile, a face is tangent to it), at two cam angles;
- Check design's rows (cusp, face width, …) against report.json's ``checks``;
- the properties of the new fields (groups, types, units), lifts in the arm's degrees, the
  ``MaxDeviation`` output in the lift's unit;
- a property change (the arm length) recomputes, an arm that cannot reach the prime circle
  leaves the library's refusal naming the field in ``Status``, a document saved and reopened.
"""
from __future__ import annotations

import cmath
import copy
import json
import math
import subprocess
import sys

import pytest

from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec import DEFAULT_SPEC_DICT, CamSpec
from cam_workbench.generators.spec.examples import example_dict

from .conftest import SAFETY_S
from .freecad_support import cli_env, fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401

pytestmark = requires_freecadcmd

MM_PER_IN = 25.4
ANGLES = (72.0, 252.0)   # cam angles the follower is drawn at: in the rise and in the return


def _specs() -> dict[str, dict]:
    knife = copy.deepcopy(DEFAULT_SPEC_DICT)
    knife["units"] = "in"
    knife["cam"].update(base_radius=1.6, thickness=0.4, bore_diameter=0.5, direction="cw")
    knife["follower"] = {"kind": "knife", "motion": "oscillating", "pivot_distance": 2.4, "arm_length": 1.8,
                         "arm_inertia": 0.02, "preload_torque": 7.0, "spring_torque_rate": 4.0}
    oflat = copy.deepcopy(DEFAULT_SPEC_DICT)
    oflat["cam"].update(base_radius=40.0, bore_diameter=12.0)
    oflat["follower"] = {"kind": "flat", "motion": "oscillating", "pivot_distance": 70.0, "face_offset": 5.0,
                         "face_width": 60.0, "arm_inertia": 2000.0, "preload_torque": 800.0}
    for spec, lift, law in ((knife, 12.0, "harmonic"), (oflat, 12.0, "cycloidal")):
        for m in spec["motion"]:
            if "lift" in m:
                m["lift"], m["law"] = lift, law
    return {"osc_roller": example_dict("oscillating"), "osc_knife": knife,
            "flat": example_dict("flat"), "osc_flat": oflat}


SPECS = _specs()

BUILD = """
import FreeCAD, Part, os
from cam_workbench.freecad.feature import create, reference_of, FOLLOWER_ANGLE
from cam_workbench.freecad import properties as P
from cam_workbench.freecad.check_design import design_report
from cam_workbench.freecad.spec_io import export_spec
specs = json.loads(SPECS)
doc = FreeCAD.newDocument("followers")
cams = {k: create(doc, d, name=k) for k, d in specs.items()}
doc.recompute()
NEW = ("FollowerMotion", "FollowerPivotDistance", "FollowerArmLength", "FollowerFaceOffset",
       "FollowerFaceOffsetEnabled", "FollowerFaceWidth", "FollowerArmInertia", "FollowerPreloadTorque",
       "FollowerSpringTorqueRate", "PitchTolerance", "MaxDeviation")

def top_wire(cam):
    s = cam.Shape
    zt = s.BoundBox.ZMax
    top = [f for f in s.Faces if f.Surface.TypeId == "Part::GeomPlane" and abs(f.CenterOfMass.z - zt) < 1e-7]
    return top[0].OuterWire

def xyz(v):
    return [v.x, v.y, v.z]

def drawn(cam):
    f = reference_of(cam, "follower")
    wire = top_wire(cam)
    out = {"circles": [], "lines": [], "vertices": [], "angle": f.FollowerAngle.Value, "kind": f.Kind,
           "label": f.Label}
    for c in f.Shape.childShapes():
        if c.ShapeType == "Vertex":
            out["vertices"].append(xyz(c.Point) + [c.distToShape(wire)[0]])
        elif c.Curve.TypeId == "Part::GeomCircle":
            cc = c.Curve
            out["circles"].append({"centre": xyz(cc.Center), "r": cc.Radius, "touch": c.distToShape(wire)[0],
                                   "centre_to_profile": Part.Vertex(cc.Center).distToShape(wire)[0]})
        else:
            a, b = c.Vertexes[0].Point, c.Vertexes[-1].Point
            out["lines"].append({"ends": [xyz(a), xyz(b)], "touch": c.distToShape(wire)[0]})
    return out

for key, cam in cams.items():
    s = cam.Shape
    r = RESULT[key] = {
        "status": cam.Status, "valid": s.isValid(), "solids": len(s.Solids), "volume": s.Volume,
        "max_deviation": [cam.MaxDeviation.Value, cam.getTypeIdOfProperty("MaxDeviation"),
                          str(cam.MaxDeviation)],
        "props": {n: [cam.getTypeIdOfProperty(n), cam.getGroupOfProperty(n), cam.getDocumentationOfProperty(n)]
                  for n in NEW},
        "children": sorted(o.Kind for o in cam.References),
        "drawn": {},
        "spec": P.spec_dict(cam),
    }
    for angle in ANGLES:
        reference_of(cam, "follower").FollowerAngle = angle
        doc.recompute()
        r["drawn"][str(angle)] = drawn(cam)
    rep = design_report(cam)
    r["report"] = {"ok": rep.ok, "failed": rep.failed_checks, "checks": rep.checks_dict, "rows": rep.rows,
                   "follower": rep.follower_text, "text": rep.text()}
    export_spec(cam, os.path.join(OUT, key + ".toml"))

# the optimiser's before/after figures show the areas the follower has (a short run)
from cam_workbench.generators.optimise import optimise
from cam_workbench.freecad import optimiser as O
for key in ("osc_roller", "flat"):
    res = optimise(P.spec_of(cams[key]).replace(**{"optimise.max_evaluations": 10}), objective="area",
                   variables="base_radius")
    RESULT[key]["figures"] = [[f.name, f.before, f.after] for f in O.figures(res)]
    RESULT[key]["areas"] = res.details["areas"]

# a property change recomputes: a longer arm
cam = cams["osc_roller"]
cam.FollowerArmLength = 50.0
doc.recompute()
RESULT["arm50"] = {"status": cam.Status, "volume": cam.Shape.Volume, "drawn": drawn(cam)}
# an arm that cannot reach the prime circle: the library's refusal, the shape kept
cam.FollowerArmLength = 10.0
doc.recompute()
RESULT["arm10"] = {"status": cam.Status, "volume": cam.Shape.Volume}
cam.FollowerArmLength = 45.0
doc.recompute()
RESULT["arm45"] = {"status": cam.Status, "volume": cam.Shape.Volume}

# switching Units never changes the cam: an arm's degrees stay degrees
knife = cams["osc_knife"]
knife.Units = "mm"
doc.recompute()
RESULT["knife_mm"] = {"spec": P.spec_dict(knife), "volume": knife.Shape.Volume, "status": knife.Status,
                      "inertia": knife.FollowerArmInertia, "torque": knife.FollowerPreloadTorque}
knife.Units = "in"
doc.recompute()
RESULT["knife_in"] = {"spec": P.spec_dict(knife), "volume": knife.Shape.Volume}

# the tolerance's property follows the follower's motion
flat = cams["flat"]
types = [flat.getTypeIdOfProperty("PitchTolerance")]
flat.FollowerMotion = "oscillating"
types.append(flat.getTypeIdOfProperty("PitchTolerance"))
flat.FollowerMotion = "translating"
types.append(flat.getTypeIdOfProperty("PitchTolerance"))
doc.recompute()
RESULT["tolerance_types"] = types
RESULT["flat_after"] = {"status": flat.Status, "spec": P.spec_dict(flat)}
for c in cams.values():
    reference_of(c, "follower").FollowerAngle = 72.0
doc.recompute()
RESULT["states"] = sorted({s for o in doc.Objects for s in o.State})
RESULT["second_recompute"] = doc.recompute()
doc.saveAs(PATH)
RESULT["forbidden_modules"] = [m for m in ("OCP", "cadquery", "build123d") if m in sys.modules]
"""

REOPEN = """
import FreeCAD
from cam_workbench.freecad.feature import reference_of
from cam_workbench.freecad import properties as P
doc = FreeCAD.openDocument(PATH)
for o in doc.Objects:
    if type(getattr(o, "Proxy", None)).__name__ != "CamFeature":
        continue
    RESULT[o.Name] = {"version": o.Version, "restored_volume": o.Shape.Volume, "spec": P.spec_dict(o),
                      "types": [o.getTypeIdOfProperty(n) for n in ("PitchTolerance", "MaxDeviation")],
                      "max_deviation": o.MaxDeviation.Value,
                      "follower_angle": reference_of(o, "follower").FollowerAngle.Value,
                      "follower_edges": len(reference_of(o, "follower").Shape.Edges)}
    o.touch()
doc.recompute()
for name, r in RESULT.items():
    o = doc.getObject(name)
    r.update(status=o.Status, volume=o.Shape.Volume, max_deviation_again=o.MaxDeviation.Value)
"""


@pytest.fixture(scope="module")
def built(tmp_path_factory, fc_home):
    tmp = tmp_path_factory.mktemp("fc_followers")
    out = tmp / "specs"
    out.mkdir()
    path = tmp / "followers.FCStd"
    head = (f"SPECS = {json.dumps(json.dumps(SPECS))}\nOUT = {str(out)!r}\nPATH = {str(path)!r}\n"
            f"ANGLES = {ANGLES!r}\n")
    run = run_freecadcmd(head + BUILD, tmp / "build", fc_home).check()
    reopened = run_freecadcmd(f"PATH = {str(path)!r}\n" + REOPEN, tmp / "reopen", fc_home).check()
    return run, reopened, out


@pytest.fixture(scope="module")
def cli_reports(built, tmp_path_factory):
    """report.json of ``cam-workbench build`` on each spec FreeCAD exported (this checkout's CLI)."""
    _run, _reopened, specs = built
    tmp = tmp_path_factory.mktemp("cli")
    reports = {}
    for key in SPECS:
        out = tmp / key
        proc = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "build", str(specs / f"{key}.toml"),
                               "-o", str(out)], capture_output=True, text=True, timeout=SAFETY_S, env=cli_env(),
                              cwd=tmp, stdin=subprocess.DEVNULL)
        assert proc.returncode == 0, proc.stdout + proc.stderr
        reports[key] = json.loads((out / "report.json").read_text())
    return reports


def _scale(key: str) -> float:
    return MM_PER_IN if SPECS[key].get("units") == "in" else 1.0


# ---- the mechanism, written out here from docs/followers.md ("Conventions") -------------------
def _law(law: str, x: float) -> tuple[float, float]:
    """f(x), f'(x) of a rise from 0 to 1 over x ∈ [0, 1]."""
    if law == "cycloidal":
        return x - math.sin(2 * math.pi * x) / (2 * math.pi), 1 - math.cos(2 * math.pi * x)
    if law == "harmonic":
        return (1 - math.cos(math.pi * x)) / 2, math.pi / 2 * math.sin(math.pi * x)
    raise ValueError(law)


def _lift(spec: dict, theta_deg: float) -> tuple[float, float]:
    """s(θ) and s′ = ds/dθ (per radian) of the default program's shape: dwell 30°, rise 120°,
    dwell 60°, return 120°, dwell 30°, with the spec's lift and law."""
    rise, ret = spec["motion"][1], spec["motion"][3]
    h, beta = rise["lift"], math.radians(120.0)
    if 30.0 <= theta_deg <= 150.0:
        f, df = _law(rise["law"], (theta_deg - 30.0) / 120.0)
        return h * f, h * df / beta
    if 210.0 <= theta_deg <= 330.0:
        f, df = _law(ret["law"], (theta_deg - 210.0) / 120.0)
        return h * (1 - f), -h * df / beta
    return (h, 0.0) if 150.0 < theta_deg < 210.0 else (0.0, 0.0)


def _expected(key: str, theta_deg: float) -> dict:
    """The follower at cam angle θ in the cam frame (mm): a fixed-frame point F is seen at
    Rot(−δθ)·F, δ = +1 for a ccw cam."""
    spec = SPECS[key]
    k = _scale(key)
    fol, rb = spec["follower"], spec["cam"]["base_radius"]
    delta = 1 if spec["cam"].get("direction", "ccw") == "ccw" else -1
    rot = cmath.exp(-1j * delta * math.radians(theta_deg))
    s, ds = _lift(spec, theta_deg)
    out = {}
    if fol.get("motion") == "oscillating" and fol["kind"] != "flat":
        d, arm = fol["pivot_distance"], fol["arm_length"]
        psi0 = math.acos((rb * rb - d * d - arm * arm) / (2 * d * arm))
        a = d + arm * cmath.exp(1j * (psi0 - math.radians(s)))
        out.update(pivot=rot * d * k, point=rot * a * k, arm=arm * k)
    elif fol.get("motion") == "oscillating":
        d, f = fol["pivot_distance"], fol["face_offset"]

        def support(t: float) -> tuple[float, float]:
            """(γ, h): the face line Re(e^{−iγ}x) = h in the cam frame at cam angle t [deg]."""
            beta = math.acos((rb + f) / d) - math.radians(_lift(spec, t)[0])
            return beta - delta * math.radians(t), d * math.cos(beta) - f

        g, h = support(theta_deg)
        e = 1e-4   # the envelope's contact point h·e^{iγ} + h_γ·i·e^{iγ}, h_γ by central differences
        (g1, h1), (g2, h2) = support(theta_deg + e), support(theta_deg - e)
        n = cmath.exp(1j * g)
        out.update(pivot=rot * d * k, normal=n, h=h * k, offset=f * k, width=fol["face_width"] * k,
                   point=(h * n + (h1 - h2) / (g1 - g2) * 1j * n) * k)
    else:  # translating flat face: the line y = R_b + s, the contact at x = δ·s′
        e = fol.get("offset", 0.0)
        y = rb + s
        out.update(point=rot * complex(delta * ds, y) * k, face=(rot * complex(e - fol["face_width"] / 2, y) * k,
                                                                 rot * complex(e + fol["face_width"] / 2, y) * k),
                   normal=rot * 1j, h=y * k)
    return out


def _c(p) -> complex:
    return complex(p[0], p[1])


# ---- the tests ------------------------------------------------------------------------------
@pytest.mark.parametrize("key", list(SPECS))
def test_volume_equals_the_library_and_the_cli(built, cli_reports, key):
    """FreeCAD's solid (its own OCCT) has the library's exact volume — Green's area of the
    NURBS profile minus the bore, × thickness — to 1e-9, and the volume (exact and OCP
    kernel's) of ``cam-workbench build`` on the spec FreeCAD exports; the spec is the one given."""
    run, _reopened, _specs_dir = built
    r = run.result[key]
    assert r["status"] == "ok" and r["valid"] and r["solids"] == 1
    exact = design_cam(CamSpec.from_dict(SPECS[key])).volume * _scale(key) ** 3
    assert abs(r["volume"] - exact) / exact < 1e-9, (r["volume"], exact)
    report = cli_reports[key]
    for cli in (report["volume"], report["solid"]["kernel_volume"]):
        cli_mm = cli * _scale(key) ** 3
        assert abs(r["volume"] - cli_mm) / cli_mm < 1e-9, (r["volume"], cli_mm)
    assert CamSpec.from_dict(r["spec"]) == CamSpec.from_dict(SPECS[key])
    assert run.result["forbidden_modules"] == []


@pytest.mark.parametrize("key", list(SPECS))
def test_max_deviation_carries_the_lifts_unit(built, cli_reports, key):
    """``MaxDeviation`` is report.json's ``pitch.max_deviation`` in the lift's unit: an angle
    (degrees) for an oscillating follower, whatever ``Units`` says; a length (mm) otherwise."""
    run, _reopened, _specs_dir = built
    value, ptype, text = run.result[key]["max_deviation"]
    report = cli_reports[key]
    if report["motion"]["lift_unit"] == "deg":
        assert ptype == "App::PropertyAngle" and (text.endswith("°") or "deg" in text), (ptype, text)
        assert value == pytest.approx(report["pitch"]["max_deviation"], rel=1e-9)
    else:
        assert ptype == "App::PropertyLength" and text.endswith("mm")
        assert value == pytest.approx(report["pitch"]["max_deviation"] * _scale(key), rel=1e-9)


@pytest.mark.parametrize("key", list(SPECS))
@pytest.mark.parametrize("angle", ANGLES)
def test_drawn_follower_is_the_mechanism(built, key, angle):
    """The follower child at FollowerAngle θ: the pivot at Rot(−δθ)·(d, 0), an arm of length L,
    the roller centre (knife tip) on the pitch point A = D + L·e^{i(ψ₀ − s)}, the roller touching
    the profile FreeCAD built; a flat face on its line (at distance f from the pivot, oscillating),
    tangent to the profile at the envelope's contact point — computed here, not by the library.
    On the plane of the cam's top face."""
    run, _reopened, _specs_dir = built
    r = run.result[key]
    dr = r["drawn"][str(angle)]
    ex = _expected(key, angle)
    spec = SPECS[key]
    k = _scale(key)
    tol = 1e-7 * k
    z = spec["cam"]["thickness"] * k
    assert dr["kind"] == "follower" and dr["angle"] == angle
    assert all(abs(v[2] - z) < 1e-9 for v in dr["vertices"])
    points = [complex(v[0], v[1]) for v in dr["vertices"]]
    assert min(abs(p - ex["point"]) for p in points) < tol, (points, ex["point"])
    # the follower point touches the profile: a roller's centre is a roller radius from it
    tip = min(dr["vertices"], key=lambda v: abs(complex(v[0], v[1]) - ex["point"]))
    rr = spec["follower"].get("roller_radius", 0.0) * k
    lines = [(_c(a), _c(b), t) for (a, b), t in ((ln["ends"], ln["touch"]) for ln in dr["lines"])]
    if "pivot" in ex:
        assert min(abs(p - ex["pivot"]) for p in points) < tol
        marks = [c for c in dr["circles"] if abs(_c(c["centre"]) - ex["pivot"]) < tol]
        assert len(marks) == 1
        arms = [(a, b) for a, b, _t in lines if abs(a - ex["pivot"]) < tol]
        assert len(arms) == 1
    if "arm" in ex:   # an arm to the roller centre / knife tip
        (a, b), = arms
        assert abs(abs(b - a) - ex["arm"]) < tol and abs(b - ex["point"]) < tol
    if rr > 0:
        roller, = [c for c in dr["circles"] if abs(c["r"] - rr) < 1e-9]
        assert abs(_c(roller["centre"]) - ex["point"]) < tol
        assert abs(roller["centre_to_profile"] - rr) < 1e-6 and roller["touch"] < 1e-6
    else:
        assert tip[3] < 1e-6   # the knife tip or the face's contact point lies on the profile
    if "normal" in ex:   # a flat face: its line, tangent to the profile
        n = ex["normal"]
        faces = [(a, b, t) for a, b, t in lines
                 if abs((n.conjugate() * a).real - ex["h"]) < tol and abs((n.conjugate() * b).real - ex["h"]) < tol]
        assert len(faces) == 1, (lines, n, ex["h"])
        a, b, touch = faces[0]
        assert touch < 1e-6
        assert abs((n.conjugate() * complex(tip[0], tip[1])).real - ex["h"]) < tol   # the contact is on the face
        if "face" in ex:   # centred on the stem, face_width wide
            fa, fb = ex["face"]
            assert min(max(abs(a - fa), abs(b - fb)), max(abs(a - fb), abs(b - fa))) < tol, ((a, b), ex["face"])
        else:
            assert abs(abs(b - a) - ex["width"]) < tol
            # the face line passes at face_offset from the pivot; the arm ends on it
            assert abs(abs((n.conjugate() * ex["pivot"]).real - ex["h"]) - ex["offset"]) < tol
            (pa, pb), = arms
            assert abs((n.conjugate() * pb).real - ex["h"]) < tol
    counts = (len(dr["circles"]), len(dr["lines"]), len(dr["vertices"]))
    assert counts == {"osc_roller": (2, 1, 2), "osc_knife": (1, 1, 2), "flat": (0, 2, 1), "osc_flat": (1, 2, 2)}[key]


def test_new_properties_groups_types_units(built):
    """The follower kinds' fields are grouped (Follower, Follower arm, Follower load), typed
    (lengths as quantities; torques, torsional rates, inertias as plain numbers with their units
    in the tooltip); an oscillating follower's tolerance is an angle, a translating one's a length."""
    run, _reopened, _specs_dir = built
    p = run.result["osc_roller"]["props"]
    assert {n: v[:2] for n, v in p.items()} == {
        "FollowerMotion": ["App::PropertyEnumeration", "Follower"],
        "FollowerPivotDistance": ["App::PropertyLength", "Follower arm"],
        "FollowerArmLength": ["App::PropertyLength", "Follower arm"],
        "FollowerFaceOffset": ["App::PropertyDistance", "Follower arm"],
        "FollowerFaceOffsetEnabled": ["App::PropertyBool", "Follower arm"],
        "FollowerFaceWidth": ["App::PropertyLength", "Follower"],
        "FollowerArmInertia": ["App::PropertyFloatConstraint", "Follower load"],
        "FollowerPreloadTorque": ["App::PropertyFloatConstraint", "Follower load"],
        "FollowerSpringTorqueRate": ["App::PropertyFloatConstraint", "Follower load"],
        "PitchTolerance": ["App::PropertyAngle", "Pitch"],
        "MaxDeviation": ["App::PropertyAngle", "Result"],
    }
    assert "kg·mm² for mm specs, lbf·in·s² for inch specs" in p["FollowerArmInertia"][2]
    assert "N·mm for mm specs, lbf·in for inch specs" in p["FollowerPreloadTorque"][2]
    assert "N·mm/rad for mm specs, lbf·in/rad for inch specs" in p["FollowerSpringTorqueRate"][2]
    assert run.result["flat"]["props"]["PitchTolerance"][0] == "App::PropertyLength"
    assert run.result["flat"]["props"]["MaxDeviation"][0] == "App::PropertyLength"
    assert run.result["tolerance_types"] == ["App::PropertyLength", "App::PropertyAngle", "App::PropertyLength"]
    assert run.result["flat_after"]["status"] == "ok"
    assert CamSpec.from_dict(run.result["flat_after"]["spec"]) == CamSpec.from_dict(SPECS["flat"])
    for key in SPECS:
        assert run.result[key]["children"] == ["base circle", "follower", "pitch curve"]


def test_units_switch_keeps_an_arms_degrees(built):
    """Switching an inch oscillating cam to mm converts lengths, torques and inertias and leaves
    the lifts in degrees (12°, not 12/25.4): the same cam, the same volume; and back."""
    run, _reopened, _specs_dir = built
    mm, inch = run.result["knife_mm"], run.result["knife_in"]
    assert mm["status"] == "ok"
    assert [m.get("lift") for m in mm["spec"]["motion"]] == [None, 12.0, None, 12.0, None]
    fol = mm["spec"]["follower"]
    assert fol["pivot_distance"] == pytest.approx(2.4 * 25.4, rel=1e-15)
    lbf_n = 0.45359237 * 9.80665
    assert fol["preload_torque"] == pytest.approx(7.0 * lbf_n * 25.4, rel=1e-14)
    assert fol["spring_torque_rate"] == pytest.approx(4.0 * lbf_n * 25.4, rel=1e-14)
    assert fol["arm_inertia"] == pytest.approx(0.02 * lbf_n * 0.0254 * 1e6, rel=1e-14)
    assert mm["inertia"] == pytest.approx(0.02 * lbf_n * 0.0254 * 1e6, rel=1e-14)   # stored kg·mm²
    v0 = run.result["osc_knife"]["volume"]
    assert abs(mm["volume"] - v0) / v0 < 1e-12 and abs(inch["volume"] - v0) / v0 < 1e-12
    assert CamSpec.from_dict(inch["spec"]) == CamSpec.from_dict(SPECS["osc_knife"])


@pytest.mark.parametrize("key", list(SPECS))
def test_check_design_rows_are_report_jsons(built, cli_reports, key):
    """Check design's rows are report.json's ``checks`` (the same function, FreeCAD's numpy):
    every check — flat faces' cusp and face width among them — with value, cam angle, limit and
    status; the follower's label is report.json's; lifts in the lift's unit."""
    run, _reopened, _specs_dir = built
    rep = run.result[key]["report"]
    cli = cli_reports[key]
    got, want = rep["checks"]["results"], cli["checks"]["results"]
    assert list(got) == list(want)
    for name, w in want.items():
        g = got[name]
        assert (g["status"], g["unit"], g["limit"], g["kind"]) == (w["status"], w["unit"], w["limit"], w["kind"]), name
        if w["value"] is None:
            assert g["value"] is None, name
        else:
            assert g["value"] == pytest.approx(w["value"], rel=1e-9, abs=1e-12), name
            # the refined extremum lies on a grid of about 2e-6° (16⁴ zooms of the samples): two
            # numpys may pick neighbouring points of a flat extremum whose values agree to 1e-9
            assert g["at_deg"] == pytest.approx(w["at_deg"], abs=1e-5), name
    flat = SPECS[key]["follower"]["kind"] == "flat"
    roller = SPECS[key]["follower"]["kind"] == "roller"
    assert ({"cusp", "face_width"} <= set(got)) == flat and ("curvature" in got) == (not flat)
    assert ("undercut" in got) == roller
    assert rep["failed"] == cli["checks"]["failed"] == [] and rep["ok"]
    units = SPECS[key].get("units", "mm")
    assert rep["follower"] == f"{cli['follower']['label']} {units}"
    assert f"follower: {cli['follower']['label']} {units}" in rep["text"]
    rows = {(g, item): value for g, item, value, _status in rep["rows"]}
    lu = cli["motion"]["lift_unit"]
    assert rows[("Motion", "max lift")] == f"{cli['motion']['max_lift']:.6g} {lu}"
    curve = cli["follower"]["curve"]
    dev = next(v for (g, item), v in rows.items() if g.lower() == curve and item.startswith("max follower"))
    assert dev.startswith(f"{cli['pitch']['max_deviation']:.3g} {lu} at ")


def test_optimiser_figures_show_the_areas_that_exist(built):
    """No thesis Eq. 4.21 area for oscillating and flat followers: the figures show the exact
    area inside the pitch curve (or a flat face's contact curve, which is its profile: one row)."""
    run, _reopened, _specs_dir = built
    for key, names in (("osc_roller", ["area inside the pitch curve", "area inside the profile",
                                       "cross-section (profile − bore)"]),
                       ("flat", ["area inside the contact curve", "cross-section (profile − bore)"])):
        figs = {f[0]: f[1:] for f in run.result[key]["figures"]}
        areas = run.result[key]["areas"]
        assert [n for n in figs if ("area" in n or "cross-section" in n) and not n.startswith("objective")] \
            == names, list(figs)
        assert areas["initial"]["thesis_eq_4_21"] is None
        first = figs[names[0]]
        assert first == [areas["initial"]["pitch_curve"], areas["final"]["pitch_curve"]]
        assert None not in first


def test_property_change_and_refusal(built):
    """A longer arm recomputes the cam (the library's volume for that spec) and redraws the arm;
    an arm that cannot reach the prime circle leaves the library's refusal, naming the field, in
    ``Status`` and keeps the last good shape; the good arm back gives the cam back."""
    run, _reopened, _specs_dir = built
    r = run.result
    spec50 = copy.deepcopy(SPECS["osc_roller"])
    spec50["follower"]["arm_length"] = 50.0
    v50 = design_cam(CamSpec.from_dict(spec50)).volume
    assert r["arm50"]["status"] == "ok" and abs(r["arm50"]["volume"] - v50) / v50 < 1e-9
    dr = r["arm50"]["drawn"]
    (a, b), = [ln["ends"] for ln in dr["lines"]]
    assert math.dist(a[:2], b[:2]) == pytest.approx(50.0, abs=1e-9)
    bad = copy.deepcopy(SPECS["osc_roller"])
    bad["follower"]["arm_length"] = 10.0
    with pytest.raises(SpecError) as refused:   # the library's own refusal, computed here
        CamSpec.from_dict(bad)
    assert refused.value.field == "follower.arm_length"
    assert r["arm10"]["status"] == f"error: FollowerArmLength (follower.arm_length): {refused.value.rule}"
    assert r["arm10"]["volume"] == r["arm50"]["volume"]
    v45 = r["osc_roller"]["volume"]
    assert r["arm45"]["status"] == "ok" and abs(r["arm45"]["volume"] - v45) / v45 < 1e-12
    assert r["states"] == ["Up-to-date"] and r["second_recompute"] == 0


def test_saved_and_reopened(built):
    """Saved and reopened: feature version 4, the same spec, the follower child with its angle,
    the tolerance and deviation as angles for oscillating followers; the stored shape and a
    recompute give the same volume, without an upgrade."""
    run, reopened, _specs_dir = built
    for key in SPECS:
        r = reopened.result[key]
        assert r["version"] == 5
        assert CamSpec.from_dict(r["spec"]) == CamSpec.from_dict(SPECS[key])
        want = "App::PropertyAngle" if SPECS[key]["follower"].get("motion") == "oscillating" else "App::PropertyLength"
        assert r["types"] == [want, want]
        assert r["follower_angle"] == 72.0 and r["follower_edges"] > 0
        v = run.result[key]["volume"]
        assert abs(r["restored_volume"] - v) / v < 1e-12 and abs(r["volume"] - v) / v < 1e-12
        assert r["status"] == "ok" and r["max_deviation_again"] == pytest.approx(r["max_deviation"], rel=1e-12)
    assert "upgraded" not in reopened.console and "Traceback" not in reopened.console

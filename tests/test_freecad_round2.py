"""Issue 6 round two in a real FreeCAD (``freecadcmd``): the properties of the new spec
sections, a B-spline cam, Check design's table, and the exports.

The exports are made by ``cam_workbench.freecad.exports.export`` — the function the export
dialogs call — and compared with the CLI run here, in pytest's process, on the original spec
file: the FreeCAD side passes its properties to the CLI as TOML, so equal files also show
that properties → spec → TOML loses nothing.  Check design's values are compared with
``run_checks`` computed here (numpy/scipy of the virtual environment vs FreeCAD's own).
"""
from __future__ import annotations

import json
import subprocess
import sys

import pytest

from cam_workbench.generators.spec import load_spec

from .conftest import ROOT, SAFETY_S, requires_ocp
from .freecad_support import cli_env, fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401

pytestmark = requires_freecadcmd

EX5 = ROOT / "tests" / "fixtures" / "thesis_ex5_final.toml"

PROPS = """
import FreeCAD
from cam_workbench.freecad.feature import create
doc = FreeCAD.newDocument("props")
cam = create(doc, EX5)
out = RESULT["props"] = {}
for n in cam.PropertiesList:
    g = cam.getGroupOfProperty(n)
    if g in ("Cam", "Follower", "Follower arm", "Follower load", "Motion", "Pitch", "Machining", "Checks",
             "Material", "Drawing", "Optimise", "Dynamics", "Ecam", "Groove", "Conjugate", "Indexer", "Indexer load",
             "Linkage"):
        v = getattr(cam, n)
        unit = v.Unit.Type if hasattr(v, "Unit") else None
        out[n] = [g, cam.getTypeIdOfProperty(n), unit, cam.getDocumentationOfProperty(n)]
RESULT["control_x"] = list(cam.MotionControlX)
RESULT["preload_user"] = cam.FollowerPreload.getValueAs("lbf").Value
RESULT["stress_user"] = cam.MaterialAllowableStress.getValueAs("MPa").Value
cam.FollowerPreload = "1.5 kN"
from cam_workbench.freecad import properties as P
RESULT["preload_spec"] = P.spec_dict(cam)["follower"]["preload"]
"""


@pytest.fixture(scope="module")
def props_run(tmp_path_factory, fc_home):
    body = f"EX5 = {str(EX5)!r}\n" + PROPS
    return run_freecadcmd(body, tmp_path_factory.mktemp("fc_props"), fc_home).check().result


def test_every_section_is_a_property_group_with_units(props_run):
    """Every declared field of every section is a property in its group, with the FreeCAD
    quantity of its unit and the declaration's doc as tooltip."""
    from cam_workbench.freecad import properties as P

    got = props_run["props"]
    for fp in P.field_properties():
        assert fp.name in got, fp.name
        group, ptype, _unit, tip = got[fp.name]
        assert (group, ptype) == (fp.group, fp.type), fp.name
        assert tip.startswith(fp.param.doc), fp.name
    groups = {g for g, *_ in got.values()}
    assert groups == {"Cam", "Follower", "Follower arm", "Follower load", "Motion", "Pitch", "Machining", "Checks",
                      "Material", "Drawing", "Optimise", "Dynamics", "Ecam", "Groove", "Conjugate", "Indexer",
                      "Indexer load", "Linkage"}
    units = {n: u for n, (_g, _t, u, _tip) in got.items() if u}
    assert units["FollowerPreload"] == "Force" and units["ChecksMinForce"] == "Force"
    assert units["MaterialAllowableStress"] == "Pressure" and units["MaterialCamModulus"] == "Pressure"
    assert units["MachiningFeedRate"] == "Velocity" and units["MachiningToolRadius"] == "Length"
    assert units["ChecksMaxPressureAngle"] == "Angle" and units["DrawingChordTolerance"] == "Length"
    assert got["DrawingTitleBlock"][1] == "App::PropertyBool" and got["MachiningCoolant"][1] == "App::PropertyBool"
    # [optimise]: the optimiser panel's defaults; an absent bound is 0
    assert got["OptimiseObjective"][1] == "App::PropertyEnumeration" and units["OptimiseBaseRadiusMin"] == "Length"
    assert "0 = not given" in got["OptimiseBaseRadiusMin"][3] and got["OptimiseMaxEvaluations"][1] == "App::PropertyIntegerConstraint"
    # the thesis' control points as FreeCAD holds them: one comma-separated string per segment
    assert props_run["control_x"][0] == "0.3772, 0.4424, 0.5148, 1.2282, 1.5945, 1.9231, 2.1345, 2.2648, 2.5848"
    assert props_run["control_x"][1] == ""
    # 340 lbf and 250 000 psi read back in FreeCAD's own units (its lbf/psi are rounded: 1e-5)
    assert props_run["preload_user"] == pytest.approx(340.0, rel=1e-5)
    assert props_run["stress_user"] == pytest.approx(250000 * 0.006894757293168361, rel=1e-5)
    # "1.5 kN" typed into an inch cam reaches the spec in lbf
    assert props_run["preload_spec"] == pytest.approx(1500 / 4.4482216152605, rel=1e-12)


BSPLINE = """
import FreeCAD
from cam_workbench.generators.spec import load_spec
from cam_workbench.freecad.feature import create
from cam_workbench.freecad import properties as P
spec = load_spec(EX5)
doc = FreeCAD.newDocument("bs")
for name, rep in (("ph", "ph"), ("bspline", "bspline")):
    cam = create(doc, spec.replace(**{"pitch.representation": rep}), name=name)
doc.recompute()
for o in doc.Objects:
    if o.Name in ("ph", "bspline"):
        prof = [e for e in o.Shape.Edges if e.Curve.TypeId == "Part::GeomBSplineCurve" and abs(e.BoundBox.ZMax) < 1e-9]
        RESULT[o.Name] = {"status": o.Status, "volume": o.Shape.Volume, "valid": o.Shape.isValid(),
                          "solids": len(o.Shape.Solids), "edges": len(prof),
                          "degrees": sorted({e.Curve.Degree for e in prof}),
                          "same_spec": P.spec_of(o) == spec.replace(**{"pitch.representation": o.Name})}
"""


@requires_ocp
def test_bspline_cam_volume_equals_the_cadquery_build(tmp_path, fc_home):
    """The thesis' Example 5 (B-spline lift law, inches) made from its spec in FreeCAD has the
    CadQuery build's volume to 1e-9.  With ``pitch.representation = "bspline"`` FreeCAD builds
    the fitted offset B-spline (``CamDesign.profile``, as STEP and DXF hold it), so it is
    compared with OCCT's solid of that same profile (``exact_offset=False``) and with its
    exact Green's-theorem volume; the kernel's exact-offset solid differs from it by the fit."""
    from cam_workbench import PlateCam
    from cam_workbench.kernel.solids import cam_solid, kernel_volume
    from cam_workbench.generators.cam_design import design_cam

    r = run_freecadcmd(f"EX5 = {str(EX5)!r}\n" + BSPLINE, tmp_path, fc_home).check().result
    spec = load_spec(EX5)
    in3 = 25.4**3
    ph = r["ph"]
    assert ph["status"] == "ok" and ph["valid"] and ph["solids"] == 1 and ph["same_spec"]
    cq = PlateCam(spec)
    assert abs(ph["volume"] / in3 - cq.volume) / cq.volume < 1e-9
    assert abs(ph["volume"] / in3 - kernel_volume(cq.shape)) / cq.volume < 1e-9
    assert ph["edges"] == 60 and ph["degrees"] == [9]
    bs = r["bspline"]
    sp = spec.replace(**{"pitch.representation": "bspline"})
    design = design_cam(sp)
    fitted = kernel_volume(cam_solid(design, exact_offset=False))
    exact_offset = kernel_volume(PlateCam(sp).shape)
    assert bs["status"] == "ok" and bs["valid"] and bs["solids"] == 1 and bs["same_spec"]
    assert abs(bs["volume"] / in3 - fitted) / fitted < 1e-9
    assert abs(bs["volume"] / in3 - design.volume) / design.volume < 1e-9
    assert abs(fitted - exact_offset) / exact_offset < 1e-9   # the fit's own error (≈ 7e-13)
    from cam_workbench.generators.pitch.bspline import bezier_form

    # one exact Bézier edge per knot span (a single multi-span edge was off by 1.3e-3)
    assert bs["edges"] == len(bezier_form(design.profile).bezier_pieces()) == 120


CHECK = """
import FreeCAD
from cam_workbench.freecad.feature import create
from cam_workbench.freecad.check_design import design_report
doc = FreeCAD.newDocument("check")
cam = create(doc, EX5)
doc.recompute()
def dump(rep):
    return {"ok": rep.ok, "failed": rep.failed_checks, "sampling": rep.sampling, "error": rep.error,
            "checks": [[c.name, c.value, c.at_deg, c.limit, c.unit, c.status, c.cells()] for c in rep.checks],
            "extremes": rep.extremes, "rows": rep.rows, "text": rep.text()}
RESULT["in"] = dump(design_report(cam))
cam.Units = "mm"
RESULT["mm"] = dump(design_report(cam))
cam.ChecksSampling = "thesis71"
RESULT["thesis71"] = dump(design_report(cam))
cam.ChecksSampling = "dense"
cam.FollowerRollerRadius = 80.0
RESULT["undercut"] = dump(design_report(cam))
"""


def test_check_design_table_equals_run_checks(tmp_path, fc_home):
    """Check design shows every result of ``run_checks`` (value, cam angle, limit, status) and
    the extremes, equal to run_checks computed here (other numpy/scipy: 1e-9); the thesis'
    Example 5 fails separation (−1.162 lbf at 120.46°, README); switching Units to mm gives
    the same physics (forces × 4.4482216152605 N/lbf); the thesis' 71 nodes are used when
    asked; a roller too large is reported as not buildable, with the cam angle."""
    from cam_workbench.generators.checks.design import run_checks

    r = run_freecadcmd(f"EX5 = {str(EX5)!r}\n" + CHECK, tmp_path, fc_home).check().result
    spec = load_spec(EX5)
    ref = run_checks(spec)
    got = r["in"]
    assert [c[0] for c in got["checks"]] == [c.name for c in ref.results]
    for (name, value, at, limit, unit, status, _cells), c in zip(got["checks"], ref.results):
        assert status == c.status and unit == c.unit and limit == c.limit, name
        if c.value is None:
            assert value is None and at is None, name
        else:
            assert value == pytest.approx(c.value, rel=1e-9, abs=1e-12), name
            assert at == pytest.approx(c.at_deg, abs=1e-6), name
    assert [e[0] for e in got["extremes"]] == list(ref.extremes)
    for name, value, at, unit in got["extremes"]:
        assert value == pytest.approx(ref.extremes[name]["value"], rel=1e-9), name
        assert at == pytest.approx(ref.extremes[name]["at_deg"], abs=1e-6) and unit == ref.extremes[name]["unit"]
    assert got["failed"] == ["separation"] and got["ok"] is False
    sep = next(c for c in got["checks"] if c[0] == "separation")
    assert sep[6][:5] == ["separation", "-1.162 lbf", "120.464°", "> 0 lbf", "fail"]
    assert got["sampling"] == "1001 samples per rise/return, refined extrema"
    assert ("FreeCAD solid", "valid, one solid", "yes", "pass") in [tuple(x) for x in got["rows"]]
    assert "design checks failed: separation" in got["text"]
    # the same cam in mm: forces in N, stresses in MPa, the same verdicts
    mm = {c[0]: c for c in r["mm"]["checks"]}
    inch = {c[0]: c for c in got["checks"]}
    assert mm["separation"][1] == pytest.approx(inch["separation"][1] * 4.4482216152605, rel=1e-9)
    assert mm["contact_stress"][1] == pytest.approx(inch["contact_stress"][1] * 0.006894757293168361, rel=1e-9)
    assert mm["pressure_angle"][1] == pytest.approx(inch["pressure_angle"][1], rel=1e-9)
    assert [c[5] for c in r["mm"]["checks"]] == [c[5] for c in got["checks"]]
    # the thesis' 71 nodes (README table: −0.709 lbf at 120.755°, in N here)
    t71 = {c[0]: c for c in r["thesis71"]["checks"]}
    ref71 = run_checks(spec, sampling="thesis71")["separation"]
    assert t71["separation"][1] == pytest.approx(ref71.value * 4.4482216152605, rel=1e-9)
    assert r["thesis71"]["sampling"] == "the thesis' 71 nodes per rise/return"
    und = r["undercut"]
    assert und["error"].startswith("the cam cannot be made (") and "at cam angle" in und["error"]
    assert "curvature" in und["failed"] or "undercut" in und["failed"]


EXPORT = """
import FreeCAD, os
from cam_workbench.freecad.feature import create
from cam_workbench.freecad import exports as E
doc = FreeCAD.newDocument("exp")
cam = create(doc, EX5, name="Ex5")
default = create(doc, None, name="Default")
doc.recompute()
RESULT["cli"] = E.find_cli().source
RESULT["cli_env"] = dict(E.find_cli().env)
def attempt(key, obj, kind, target):
    try:
        r = E.export(obj, kind, os.path.join(OUT, target))
        RESULT[key] = {"ok": True, "files": list(r.files), "path": str(r.path), "message": r.message}
    except E.ExportError as exc:
        RESULT[key] = {"ok": False, "error": str(exc), "exists": os.path.exists(os.path.join(OUT, target))}
attempt("dxf", cam, "dxf", "ex5.dxf")
attempt("xy", cam, "gcode_xy", "ex5_xy.nc")
attempt("csv", cam, "csv", "ex5.csv")
attempt("report", cam, "report_plots", "ex5_report")
attempt("xc_refused", cam, "gcode_xc", "ex5_xc.nc")
attempt("xc_default", default, "gcode_xc", "default_xc.nc")
attempt("dxf_noext", default, "dxf", "default_drawing")
default.CamBaseRadius = 0
attempt("bad_property", default, "dxf", "bad.dxf")
os.environ["CAM_WORKBENCH_CLI"] = "/nonexistent/cam-workbench"
attempt("no_cli", cam, "gcode_xy", "nocli.nc")
del os.environ["CAM_WORKBENCH_CLI"]
RESULT["forbidden_modules"] = [m for m in ("OCP", "cadquery", "build123d", "ezdxf") if m in sys.modules]
RESULT["listing"] = sorted(os.listdir(OUT))
"""


def _cli(*args: str, cwd) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "cam_workbench.cli", *args], capture_output=True,
                          text=True, cwd=cwd, timeout=SAFETY_S, stdin=subprocess.DEVNULL, env=cli_env())


@pytest.fixture(scope="module")
def exported(tmp_path_factory, fc_home):
    out = tmp_path_factory.mktemp("fc_exports")
    body = f"EX5 = {str(EX5)!r}\nOUT = {str(out)!r}\n" + EXPORT
    run = run_freecadcmd(body, tmp_path_factory.mktemp("fc_export_run"), fc_home).check()
    cli = tmp_path_factory.mktemp("cli_exports")
    for args in (("dxf", str(EX5), "-o", "ex5.dxf"), ("gcode", str(EX5), "--mode", "xy", "-o", "ex5_xy.nc"),
                 ("gcode", str(EX5), "--mode", "csv", "-o", "ex5.csv"), ("report", str(EX5), "--plots", "-o", "ex5_report"),
                 ("gcode", "--mode", "xc", "-o", "default_xc.nc"), ("dxf", "-o", "default_drawing.dxf")):
        res = _cli(*args, cwd=cli)
        assert res.returncode == 0, res.stderr
    return run.result, out, cli


def test_exports_run_the_installed_cli_and_import_no_kernel(exported):
    r, out, _cli_dir = exported
    assert r["cli"].startswith("the installation recorded in ") and r["cli"].endswith(".cam-workbench-install.json")
    assert r["cli_env"] == {"PYTHONPATH": str(ROOT)}  # the command line is this checkout's code too
    assert r["forbidden_modules"] == []
    for key in ("dxf", "xy", "csv", "report", "xc_default", "dxf_noext"):
        assert r[key]["ok"], (key, r[key])


def test_gcode_and_command_table_equal_the_clis(exported):
    """Byte-identical G-code (XY for Example 5, XC for the default cam) and command table."""
    r, out, cli = exported
    for name in ("ex5_xy.nc", "ex5.csv", "default_xc.nc"):
        assert (out / name).read_bytes() == (cli / name).read_bytes(), name
    assert (out / "ex5_xy.nc").read_text().count("G2") + (out / "ex5_xy.nc").read_text().count("G3") > 50


def test_dxf_equals_the_clis(exported):
    """The same entities in the same order with the same data, and the profile SPLINE's
    degree, knots, control points and weights bit-identical (only the header's timestamps
    and GUIDs differ between two runs of the CLI itself); ezdxf's auditor finds no error."""
    import ezdxf
    import numpy as np

    r, out, cli = exported
    assert r["dxf_noext"]["path"].endswith("default_drawing.dxf")
    for name in ("ex5.dxf", "default_drawing.dxf"):
        a, b = ezdxf.readfile(out / name), ezdxf.readfile(cli / name)
        assert not a.audit().has_errors
        ea, eb = list(a.modelspace()), list(b.modelspace())
        assert [(e.dxftype(), e.dxf.layer) for e in ea] == [(e.dxftype(), e.dxf.layer) for e in eb]
        for x, y in zip(ea, eb):
            assert x.dxfattribs() == y.dxfattribs() or x.dxftype() == "DIMENSION", (name, x.dxftype())
        sa, sb = a.modelspace().query("SPLINE"), b.modelspace().query("SPLINE")
        assert len(sa) == 2
        for x, y in zip(sa, sb):
            assert x.dxf.degree == y.dxf.degree
            assert np.array_equal(np.array(x.control_points), np.array(y.control_points))
            assert np.array_equal(np.array(x.knots), np.array(y.knots))
            assert np.array_equal(np.array(x.weights), np.array(y.weights))
        assert a.header["$INSUNITS"] == b.header["$INSUNITS"] == (1 if name == "ex5.dxf" else 4)


def test_design_report_equals_the_clis(exported):
    """report.html, report.json and every figure's PNG (the "with PNG figures" kind) byte-identical to
    ``cam-workbench report --plots``."""
    r, out, cli = exported
    files = r["report"]["files"]
    assert files[:2] == ["report.html", "report.json"] and "plot_force_stress.png" in files
    for name in files:
        assert (out / "ex5_report" / name).read_bytes() == (cli / "ex5_report" / name).read_bytes(), name
    report = json.loads((out / "ex5_report" / "report.json").read_text())
    assert report["checks"]["failed"] == ["separation"]


def test_failed_exports_write_nothing_and_say_why(exported):
    """The CLI's refusal (exit 2) reaches the user with the property that holds the field; a
    property that breaks a rule is named before the CLI runs; without a CLI the message says
    how to get one; no file (or temporary file) is left behind."""
    r, out, _cli_dir = exported
    xc = r["xc_refused"]
    assert xc["ok"] is False and xc["exists"] is False
    assert xc["error"].startswith("MachiningRotarySpeedRpm (machining.rotary_speed_rpm): at 800 rpm (cam.speed_rpm; "
                                  "machining.rotary_speed_rpm is not given) and machining.sample_period 0.001 s the XC "
                                  "blocks of 4.8° deviate 0.00206 from the exact tool path"), xc["error"]
    assert xc["error"].endswith("machining.rotary_speed_rpm = 220 (the C axis turning slower while it cuts; "
                                "cam.speed_rpm stays the design speed) or machining.sample_period = 0.000275: either "
                                "passes"), xc["error"]
    bad = r["bad_property"]
    assert bad == {"ok": False, "error": "CamBaseRadius (cam.base_radius): must be > 0, got 0", "exists": False}
    assert r["no_cli"]["ok"] is False and r["no_cli"]["error"] == (
        "$CAM_WORKBENCH_CLI names /nonexistent/cam-workbench, which does not exist")
    assert r["listing"] == ["default_drawing.dxf", "default_xc.nc", "ex5.csv", "ex5.dxf", "ex5_report", "ex5_xy.nc"]

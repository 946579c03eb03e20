"""The cylindrical (barrel) cam in the ``Cam`` feature inside a real FreeCAD (``freecadcmd``).

Two cams — the example, and the example with a DIN 6885-1 keyway, a hub, four mounting holes and the
timing mark — are created with ``feature.create`` (what the GUI command calls) and recomputed.  Each
holds one valid solid, sewn from the groove's faces (``part_cylindrical.sewn_groove_solid``: no
boolean; one B-spline face per wall surface), whose volume equals ``cam-workbench report``'s
report.json volume (run here through the CLI) and the closed form of
tests/test_cylindrical_features.py; points of FreeCAD's own
B-spline wall faces are within 1e-6 mm of the exact walls (the developed offsets at each point's
radius, measured by the library's ``wall_distance_error`` and, for a subset, by this file's
independent scipy minimisation in tests/test_cylindrical.py); the Check design rows are report.json's
``checks`` section; the body selector offers "cylindrical"; the drawn roller stands at θ = 0 where
the pitch point is; a property change recomputes to the new volume.
"""
from __future__ import annotations

import copy
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from cam_workbench.generators import design_cam
from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.spec.examples import EXAMPLES

from .conftest import ROOT
from .freecad_support import cli_env, fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401
from .test_cylindrical import RB, RO, RP, Z0, wall_distance
from .test_cylindrical_features import closed_form_volume, featured

pytestmark = requires_freecadcmd

MM_PER_IN = 25.4


def _inch() -> dict:
    """An inch cam: ANSI B17.1 keyway (a ¾ in bore: W = 3/16 in), hub, timing mark."""
    d = copy.deepcopy(EXAMPLES["cylindrical"])
    d["units"] = "in"
    d["cam"].update(cylinder_radius=1.6, length=2.4, bore_diameter=0.75, keyway="ANSI", hub_diameter=1.4,
                    hub_length=0.5, timing_mark=True)
    d["follower"]["roller_radius"] = 0.2
    d["groove"] = {"depth": 0.32, "clearance": 0.002, "min_wall": 0.12}
    for m in d["motion"]:
        if "lift" in m:
            m["lift"] = 0.8
    return d


SPECS = {"example": copy.deepcopy(EXAMPLES["cylindrical"]), "featured": featured(), "inch": _inch(),
         "oscillating": copy.deepcopy(EXAMPLES["cylindrical_oscillating"])}

BODY = """
import FreeCAD
import numpy as np
from cam_workbench.freecad.feature import create, reference_of
from cam_workbench.freecad import check_design, part_cylindrical
from cam_workbench.generators import design_cam
from cam_workbench.generators.spec import CamSpec
specs = json.loads(SPECS)
doc = FreeCAD.newDocument("cyl")
cams = {k: create(doc, d, name=k) for k, d in specs.items()}
doc.recompute()
RESULT["version"] = list(FreeCAD.Version()[:2])
for k, cam in cams.items():
    s = cam.Shape
    bb = s.BoundBox
    rep = check_design.design_report(cam)
    fol = reference_of(cam, "follower").Shape
    design = design_cam(CamSpec.from_dict(specs[k]))
    sewn = part_cylindrical.sewn_groove_solid(design, 25.4 if design.spec.units == "in" else 1.0)
    RESULT[k] = dict(status=cam.Status, valid=s.isValid(), solids=len(s.Solids), volume=s.Volume,
                     z=[bb.ZMin, bb.ZMax], wall=part_cylindrical.wall_face_points(s).tolist(),
                     checks=rep.checks_dict, cells=[c.cells() for c in rep.checks], ok=rep.ok,
                     rows=[list(r) for r in rep.rows], verdict=rep.verdict(),
                     body_choices=cam.getEnumerationsOfProperty("CamBody"),
                     sewn_volume=None if sewn is None else sewn.Volume,
                     bspline_faces=sum(f.Surface.TypeId == "Part::GeomBSplineSurface" for f in s.Faces),
                     follower_vertices=[[v.X, v.Y, v.Z] for v in fol.Vertexes],
                     follower_circles=[[e.Curve.Center.x, e.Curve.Center.y, e.Curve.Center.z, e.Curve.Radius]
                                       for e in fol.Edges if e.Curve.TypeId == "Part::GeomCircle"])
c = cams["example"]
c.GrooveClearance = 0.5
doc.recompute()
RESULT["changed"] = dict(status=c.Status, volume=c.Shape.Volume, valid=c.Shape.isValid())
"""


@pytest.fixture(scope="module")
def run(tmp_path_factory, fc_home):  # noqa: F811
    tmp = tmp_path_factory.mktemp("fc_cyl")
    r = run_freecadcmd(f"SPECS = {json.dumps(json.dumps(SPECS))}\n" + BODY, tmp, fc_home).check()
    assert "Traceback" not in r.console, r.console[-3000:]
    return r.result


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    """report.json of `cam-workbench report` for each spec."""
    from cam_workbench.generators.spec import dict_to_toml

    out = {}
    for name, d in SPECS.items():
        tmp = tmp_path_factory.mktemp(f"cli_{name}")
        (tmp / "c.toml").write_text(dict_to_toml(d))
        res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "report", str(tmp / "c.toml"), "-o",
                              str(tmp / "out")], capture_output=True, text=True, cwd=ROOT, env=cli_env())
        assert res.returncode == 0, res.stderr
        out[name] = json.loads((tmp / "out" / "report.json").read_text())
    return out


@pytest.mark.parametrize("name", sorted(SPECS))
def test_solid_volume(run, reports, name):
    r = run[name]
    assert r["status"] == "ok", r["status"]
    assert r["valid"] and r["solids"] == 1
    assert "cylindrical" in r["body_choices"]
    k = MM_PER_IN if name == "inch" else 1.0
    rel = r["volume"] / (reports[name]["volume"] * k ** 3) - 1
    print(f"FreeCAD {'.'.join(run['version'])} {name}: volume vs report.json {rel:.3e} relative")
    assert abs(rel) <= 1e-6
    # the feature's solid is the one sewn from the groove's faces (no boolean), one face per wall surface
    assert r["sewn_volume"] == pytest.approx(r["volume"], rel=1e-12)
    assert r["bspline_faces"] == len(design_cam(CamSpec.from_dict(SPECS[name])).body.walls)
    if name == "featured":
        assert r["volume"] == pytest.approx(closed_form_volume(), rel=1e-6)
        assert r["z"] == pytest.approx([-15.0, 60.0], abs=1e-6)
    elif name == "inch":
        assert r["z"] == pytest.approx([-0.5 * k, 2.4 * k], abs=1e-6)
    elif name == "oscillating":
        assert r["z"] == pytest.approx([0.0, 50.0], abs=1e-6)
    else:
        assert r["z"] == pytest.approx([0.0, 60.0], abs=1e-6)


@pytest.mark.parametrize("name", sorted(SPECS))
def test_walls_of_freecads_solid(run, name):
    design = design_cam(CamSpec.from_dict(SPECS[name]))
    lay = design.layout
    k = MM_PER_IN if name == "inch" else 1.0
    pts = np.array(run[name]["wall"]) / k                  # FreeCAD's mm → the spec's unit
    rho = np.hypot(pts[:, 0], pts[:, 1])
    pts = pts[(rho >= lay.bottom_radius - 1e-9) & (rho <= lay.outer_radius + 1e-9)]
    assert len(pts) > 500
    err = np.minimum(design.wall_distance_error(-1, pts), design.wall_distance_error(1, pts)) * k
    print(f"FreeCAD {'.'.join(run['version'])} {name}: wall faces vs exact walls {err.max():.3e} mm "
          f"({len(pts)} points)")
    assert err.max() <= 1e-6
    if name == "inch":
        return
    # a subset by an independent minimisation (scipy, the closed-form lift; the arm's path for the
    # oscillating follower: tests/test_cylindrical_oscillating.py)
    from .test_cylindrical_oscillating import wall_distance as arm_wall_distance

    own = arm_wall_distance if name == "oscillating" else wall_distance
    for p in pts[:: max(1, len(pts) // 60)]:
        assert abs(own(p)[0]) <= 1e-6


@pytest.mark.parametrize("name", sorted(SPECS))
def test_check_rows_are_report_json(run, reports, name):
    from cam_workbench.freecad.check_design import checks_table

    r = run[name]
    # FreeCAD's Python has its own numpy: the numbers agree to the last bits, not always bit for bit
    _same(r["checks"], reports[name]["checks"])
    assert r["cells"] == checks_table(reports[name]["checks"])
    assert [c[0] for c in r["cells"]] == ["pressure angle", "pressure angle bottom", "undercut"]
    assert r["ok"] and r["verdict"] == "all checks pass", r["verdict"]
    rows = {(g, i): v for g, i, v, _ in r["rows"]}
    assert rows[("FreeCAD solid", "valid, one solid")] == "yes"
    assert float(rows[("FreeCAD solid", "wall faces vs exact walls")].split()[0]) <= 1e-6


def _same(a, b, path="checks"):
    """Equal structure and strings, floats to 1e-12 relative."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and set(a) == set(b), path
        for k in a:
            _same(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _same(x, y, f"{path}[{i}]")
    elif isinstance(a, float) and not isinstance(b, bool):
        assert a == pytest.approx(b, rel=1e-12, abs=1e-12), path
    else:
        assert a == b, path


def test_roller_drawn_at_zero(run):
    """At θ = 0 the roller's centre on the pitch cylinder is at (0, R_p, z₀ + s(0)) (φ(0) = π/2; the
    example dwells at 0 there), its end circles at R_b and R_o."""
    r = run["example"]
    assert r["follower_vertices"][-1] == pytest.approx([0.0, RP, Z0], abs=1e-9)
    centres = sorted(r["follower_circles"], key=lambda c: c[1])
    np.testing.assert_allclose(centres, [[0.0, RB, Z0, 5.0], [0.0, RO, Z0, 5.0]], atol=1e-9)


def test_property_change_recomputes(run):
    d = copy.deepcopy(SPECS["example"])
    d["groove"]["clearance"] = 0.5
    design = design_cam(CamSpec.from_dict(d))
    r = run["changed"]
    assert r["status"] == "ok" and r["valid"]
    assert r["volume"] == pytest.approx(design.volume, rel=1e-6)
    assert math.isfinite(r["volume"])


def test_oscillating_roller_drawn_on_its_arc(run):
    """The arm's roller at θ = 0 (a dwell at zero lift): β = β_m − h/2, its centre at
    u = −d + L cos β along the circumference, Z = Z_p + L sin β (tests/test_cylindrical_oscillating.py's
    definition), i.e. at the polar angle π/2 + u/R_p of the pitch cylinder."""
    from .test_cylindrical_oscillating import ARM, BETA_M, D, H, RP as RPO, ZP

    b = BETA_M - math.radians(H) / 2
    u, z = -D + ARM * math.cos(b), ZP + ARM * math.sin(b)
    psi = math.pi / 2 + u / RPO
    r = run["oscillating"]
    assert r["follower_vertices"][-1] == pytest.approx([RPO * math.cos(psi), RPO * math.sin(psi), z], abs=1e-9)

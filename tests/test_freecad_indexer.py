"""The parallel indexer in the ``Cam`` feature inside a real FreeCAD (``freecadcmd``).

The example indexer (``PARALLEL_INDEXER_SPEC_DICT``: 8 stations, two plates 16 mm thick 4 mm apart)
is created with ``feature.create`` — what the GUI command and the spec importer call — and
recomputed.  Its shape is one valid solid whose volume is the design's exact volume
(``design.volume``, computed here outside FreeCAD); its ``[indexer]`` table is on the property panel
and reads back as the spec; the pitch-curve child holds each plate's closed pitch curve through its
crossover, the base-circle child each plate's dwell circle.  The follower child is the turret:
stations × planes roller cylinders, each centred on its plate's mid-plane at the centre
``parallel.roller_state`` gives for the child's ``FollowerAngle`` — in the cam's frame, as every
body's follower is drawn (the cams stay: a fixed-frame centre p is drawn at Rot(−θ)·p, the frame of
the indexer's clearance check) —; the rollers the cams hold at that angle touch the cam solid, the
others clear it.  Changing ``FollowerAngle`` moves them there; changing ``IndexerCentreDistance``
recomputes to the new design's volume (the derived ``cam.base_radius`` follows).
"""
from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest

from cam_workbench.exporters.plots_indexer import engaged_rollers
from cam_workbench.generators import design_cam
from cam_workbench.generators.bodies.indexing.parallel import locus, roller_state
from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.spec.examples import PARALLEL_INDEXER_SPEC_DICT

from .freecad_support import fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401

pytestmark = requires_freecadcmd

SPEC = copy.deepcopy(PARALLEL_INDEXER_SPEC_DICT)
#: the follower child's angles: the dwell (roller 0 of each plane held), then inside the index
ANGLES = (0.0, 150.0)
#: the changed centre distance [mm]
NEW_C = 125.0

BODY = """
import FreeCAD
from cam_workbench.freecad.feature import create, reference_of
from cam_workbench.freecad import properties as props
from cam_workbench.freecad import check_design
spec = json.loads(SPEC)
doc = FreeCAD.newDocument("indexer")
cam = create(doc, spec, name="Indexer")
doc.recompute()
RESULT["version"] = list(FreeCAD.Version()[:2])
s = cam.Shape
bb = s.BoundBox
RESULT["cam"] = dict(status=cam.Status, valid=s.isValid(), solids=len(s.Solids), volume=s.Volume,
                     z=[bb.ZMin, bb.ZMax], area=cam.CrossSectionArea.Value, junctions=cam.JunctionCount,
                     deviation=float(cam.MaxDeviation.Value),
                     deviation_type=cam.getTypeIdOfProperty("MaxDeviation"),
                     body_choices=cam.getEnumerationsOfProperty("CamBody"),
                     properties={p: (float(getattr(getattr(cam, p), "Value", getattr(cam, p)))
                                     if not isinstance(getattr(cam, p), bool) else getattr(cam, p))
                                 for p in cam.PropertiesList if p.startswith("Indexer")},
                     spec=props.spec_of(cam).to_dict())
pitch = reference_of(cam, "pitch curve").Shape
RESULT["pitch"] = [dict(closed=w.isClosed(), z=[w.BoundBox.ZMin, w.BoundBox.ZMax],
                        points=[[p.x, p.y, p.z] for p in w.discretize(Number=400)])
                   for w in pitch.Wires]
base = reference_of(cam, "base circle").Shape
RESULT["base"] = [[e.Curve.Radius, e.Curve.Center.z] for e in base.Edges]
fol = reference_of(cam, "follower")
RESULT["turret"] = {}
for angle in ANGLES:
    fol.FollowerAngle = angle
    doc.recompute()
    sh = fol.Shape
    RESULT["turret"][str(angle)] = dict(
        status=cam.Status, solids=len(sh.Solids),
        centres=[[c.CenterOfMass.x, c.CenterOfMass.y, c.CenterOfMass.z] for c in sh.Solids],
        radii=[max(f.Surface.Radius for f in c.Faces if f.Surface.TypeId == "Part::GeomCylinder")
               for c in sh.Solids],
        heights=[c.BoundBox.ZLength for c in sh.Solids],
        gaps=[s.distToShape(c)[0] for c in sh.Solids])
try:
    RESULT["check_rows"] = [list(r) for r in check_design.design_report(cam).rows]
except Exception as exc:
    RESULT["check_error"] = f"{type(exc).__name__}: {exc}"
cam.IndexerCentreDistance = NEW_C
doc.recompute()
RESULT["changed"] = dict(status=cam.Status, valid=cam.Shape.isValid(), solids=len(cam.Shape.Solids),
                         volume=cam.Shape.Volume)
"""


@pytest.fixture(scope="module")
def run(tmp_path_factory, fc_home):  # noqa: F811
    tmp = tmp_path_factory.mktemp("fc_indexer")
    head = f"SPEC = {json.dumps(json.dumps(SPEC))}\nANGLES = {ANGLES!r}\nNEW_C = {NEW_C!r}\n"
    r = run_freecadcmd(head + BODY, tmp, fc_home).check()
    assert "Traceback" not in r.console, r.console[-3000:]
    return r.result


@pytest.fixture(scope="module")
def design():
    return design_cam(CamSpec.from_dict(SPEC))


def _plate_mid(k: int) -> float:
    """Plate k's mid-plane [mm]: z_k = −(n_c − 1 − k)·(t + g), the plate on [z_k, z_k + t]."""
    t, g, nc = SPEC["cam"]["thickness"], SPEC["indexer"]["gap"], SPEC["indexer"].get("cams", 2)
    return -(nc - 1 - k) * (t + g) + t / 2


def _polyline_distance(points: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Distance of ``points`` (n, 2) from the open polyline ``poly`` (m, 2): to the segments on
    either side of each point's nearest vertex."""
    from scipy.spatial import cKDTree

    _, i = cKDTree(poly).query(points)
    best = np.full(len(points), np.inf)
    for a, b in ((np.maximum(i - 1, 0), i), (i, np.minimum(i + 1, len(poly) - 1))):
        p0, d = poly[a], poly[b] - poly[a]
        dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
        t = np.clip(np.einsum("ij,ij->i", points - p0, d) / dd, 0.0, 1.0)
        best = np.minimum(best, np.hypot(*(points - p0 - t[:, None] * d).T))
    return best


def test_one_valid_solid_of_the_exact_volume(run, design):
    r = run["cam"]
    assert r["status"] == "ok", r["status"]
    assert r["valid"] and r["solids"] == 1
    assert "parallel_indexer" in r["body_choices"]
    rel = r["volume"] / design.volume - 1
    print(f"FreeCAD {'.'.join(run['version'])}: indexer volume {r['volume']:.10g} mm³ vs design.volume "
          f"{design.volume:.10g} mm³: {rel:.3e} relative")
    assert abs(rel) <= 1e-6
    assert r["z"] == pytest.approx(list(design.body.z_range), abs=1e-6)
    assert r["area"] == pytest.approx(design.area, rel=1e-12)
    # the lift results: the turret's rotation, its error the recovered turret angle's (report.json's)
    err = design.summary()["indexer"]["motion_from_geometry"]["max_error_rad"]
    assert r["deviation_type"] == "App::PropertyAngle" and r["junctions"] == 0
    assert r["deviation"] == pytest.approx(math.degrees(err), rel=1e-6, abs=1e-12)


def test_indexer_table_is_on_the_property_panel(run):
    props = run["cam"]["properties"]
    ix = SPEC["indexer"]
    assert props["IndexerStations"] == ix["stations"]
    assert props["IndexerCentreDistance"] == pytest.approx(ix["centre_distance"])
    assert props["IndexerPitchRadius"] == pytest.approx(ix["pitch_radius"])
    assert props["IndexerGap"] == pytest.approx(ix["gap"])
    assert props["IndexerCams"] == 2
    assert props["IndexerMaxPressureAngle"] == pytest.approx(ix["max_pressure_angle"])
    # the properties read back as the spec
    want = CamSpec.from_dict(SPEC).to_dict()
    got = run["cam"]["spec"]
    assert got["indexer"] == pytest.approx(want["indexer"])
    assert got["cam"]["body"] == "parallel_indexer"
    assert got["cam"]["base_radius"] == pytest.approx(want["cam"]["base_radius"], rel=1e-12)


def test_pitch_curves_and_dwell_circles(run, design):
    ix = design.geometry.indexer
    assert len(run["pitch"]) == len(design.geometry.cams) == 2
    for c, w in zip(design.geometry.cams, run["pitch"]):
        z = _plate_mid(c.index)
        assert w["closed"] and w["z"] == pytest.approx([z, z], abs=1e-9)
        pts = np.array(w["points"])[:, :2]
        # through the crossover X (the flanks' common end) and within the exact locus' radii
        assert np.min(np.hypot(*(pts - c.crossover).T)) <= 1e-6
        dense = locus(ix, c.index, np.linspace(c.crossover_tau[0], c.crossover_tau[1], 40001))["point"]
        d = _polyline_distance(pts, dense)
        print(f"cam {c.index}: drawn pitch curve vs the exact locus {d.max():.2e} mm (400 points)")
        assert d.max() <= 1e-5          # the drawing's fit (1e-6) and the dense polyline's sag (~3e-7)
    assert np.array(sorted(run["base"])) == pytest.approx(np.array(sorted([c.dwell_radius, _plate_mid(c.index)]
                                                                         for c in design.geometry.cams)))


@pytest.mark.parametrize("angle", ANGLES)
def test_turret_rollers_where_roller_state_puts_them(run, design, angle):
    t = run["turret"][str(angle)]
    ix = design.geometry.indexer
    n, nc = int(ix.stations), int(ix.cams)
    assert t["status"] == "ok"
    assert t["solids"] == n * nc == 16
    th = math.radians(angle)
    want = []
    for k in range(nc):
        p, _, _ = roller_state(ix, k, np.arange(n), np.full(n, th))
        # the cam's frame: Rot(−θ)·p
        x, y = math.cos(th) * p[:, 0] + math.sin(th) * p[:, 1], -math.sin(th) * p[:, 0] + math.cos(th) * p[:, 1]
        want += [[xi, yi, _plate_mid(k)] for xi, yi in zip(x, y)]
    got = np.array(t["centres"])
    assert got == pytest.approx(np.array(want), abs=1e-9)
    assert t["radii"] == pytest.approx([SPEC["follower"]["roller_radius"]] * n * nc)
    assert t["heights"] == pytest.approx([SPEC["follower"]["roller_width"]] * n * nc)
    # the rollers the cams hold at θ touch the solid, the others clear it
    held = engaged_rollers(design.geometry, th)
    gaps = np.array(t["gaps"]).reshape(nc, n)
    for k in range(nc):
        for j in range(n):
            if j in held[k]:
                assert gaps[k, j] <= 1e-4, (k, j, gaps[k, j])
            else:
                assert gaps[k, j] > 1e-3, (k, j, gaps[k, j])
    print(f"θ = {angle}°: held rollers {held}, their gaps ≤ "
          f"{max(gaps[k, j] for k in held for j in held[k]):.2e} mm; the others ≥ "
          f"{min(gaps[k, j] for k in range(nc) for j in range(n) if j not in held[k]):.4g} mm")


def test_changing_the_angle_moves_the_rollers(run):
    a, b = (np.array(run["turret"][str(x)]["centres"]) for x in ANGLES)
    assert np.min(np.hypot(*(a - b)[:, :2].T)) > 1.0


def test_changed_centre_distance_recomputes(run):
    d = copy.deepcopy(SPEC)
    d["indexer"]["centre_distance"] = NEW_C
    exact = design_cam(CamSpec.from_dict(d)).volume
    r = run["changed"]
    assert r["status"] == "ok", r["status"]
    assert r["valid"] and r["solids"] == 1
    assert r["volume"] == pytest.approx(exact, rel=1e-6)
    assert abs(r["volume"] / run["cam"]["volume"] - 1) > 1e-3


def test_design_rows_are_the_summarys(design):
    from cam_workbench.freecad.part_indexer import indexer_rows

    s = design.summary()
    rows = {(g, i): v for g, i, v, _ in indexer_rows(s)}
    assert rows[("Body", "volume")] == f"{s['volume']:.8g} mm³"
    assert rows[("Pressure angle", "max carrying the output torque")].startswith(
        f"{s['pressure_angle']['max_deg']:.3f}°")
    assert rows[("Turret", "stations × planes")] == "8 × 2"


def test_check_design_report(run):
    assert "check_error" not in run, run.get("check_error")
    rows = {(g, i): v for g, i, v, _ in run["check_rows"]}
    assert rows[("FreeCAD solid", "valid, one solid")] == "yes"

"""The parallel indexer's outputs through the pipeline (``run_pipeline(spec, solid=False)``, the
stages ``build`` runs without the solid): the drawing registered in exporters/drawing_indexer.py
and the plates' programs registered in exporters/machining_indexer.py, written into an output
folder as ``build`` writes them, then read back — the DXF by ezdxf (its own B-spline and arc
evaluation), the programs by LinuxCNC's ``rs274`` (tests/rs274.py) — and held to the design's exact
profile points (``design.geometry.cams[k].profile``, offset here by the tool radius along
``profile_normals``) and to report.json's numbers.

``cam-workbench build`` always makes the solid (no option skips it), so the command line is
exercised through ``dxf`` and ``gcode``, which run the same pipeline without it."""
from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest

ezdxf = pytest.importorskip("ezdxf")

from cam_workbench.exporters.machining_outputs import machining_outputs  # noqa: E402
from cam_workbench.exporters.output_rule import spec_claim  # noqa: E402
from cam_workbench.generators.errors import SpecError  # noqa: E402
from cam_workbench.generators.kinds import body_of  # noqa: E402
from cam_workbench.generators.spec.examples import PARALLEL_INDEXER_SPEC_DICT  # noqa: E402
from cam_workbench.generators.spec.indexer import indexer_value
from cam_workbench.generators.spec.model import CamSpec  # noqa: E402
from cam_workbench.generators.spec.toml_io import load_spec, spec_digest, to_toml  # noqa: E402
from cam_workbench.pipeline import DXF_NAME, run_pipeline, write_outputs  # noqa: E402

from .conftest import ROOT, SAFETY_S  # noqa: E402
from .rs274 import polyline_distance, requires_rs274, run_rs274, sample_xy  # noqa: E402

STEP = 2.5e-3           # spacing [mm] of the dense samples of drawn curves and interpreted paths


def chord_sag(points: np.ndarray, radius: np.ndarray) -> float:
    """Largest sag [mm] of the chords of a closed polyline of points on a curve whose radius of
    curvature at the points is ``radius`` (signed; the smaller |radius| of a chord's two ends)."""
    chord = np.hypot(*np.diff(points, axis=0).T)
    r = np.minimum(np.abs(radius[:-1]), np.abs(radius[1:]))
    return float(np.max(chord ** 2 / (8 * r)))


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """The example spec written as TOML, read back, run through the pipeline without the solid
    and written into a folder as ``build`` writes its set (report.json without the HTML page)."""
    root = tmp_path_factory.mktemp("indexer_outputs")
    spec0 = CamSpec.from_dict(PARALLEL_INDEXER_SPEC_DICT)
    toml = root / "indexer.toml"
    toml.write_text(to_toml(spec0))
    spec = load_spec(toml)
    assert spec_digest(spec) == spec_digest(spec0)
    out = run_pipeline(spec, solid=False)
    folder = root / "out"
    report = write_outputs(out, folder, spec_claim(spec, "build", str(toml)), report=False)
    return spec, toml, out, folder, report


# ---- the pipeline's sections and files -----------------------------------------------------------
def test_the_pipeline_writes_the_drawing_and_one_program_per_plate(built):
    spec, _, out, folder, report = built
    n_c = indexer_value(spec, "cams")
    names = [f"cam{k}.nc" for k in range(n_c)]
    assert report["files"] == {"dxf": DXF_NAME, "gcode": "cam0.nc",
                               **{f"gcode_cam{k}": f"cam{k}.nc" for k in range(1, n_c)}, "report": "report.json"}
    for name in [DXF_NAME, *names, "report.json"]:
        assert (folder / name).is_file(), name
    # report.json holds the summary the stages filled (the interpolator: none for an indexer)
    on_disk = json.loads((folder / "report.json").read_text())
    assert on_disk["interpolator"] is None and out.summary["interpolator"] is None
    assert on_disk["machining"] == json.loads(json.dumps(out.summary["machining"]))
    assert on_disk["drawing"] == json.loads(json.dumps(out.summary["drawing"]))
    m = out.summary["machining"]
    assert m["files"] == names and [p["file"] for p in m["plates"]] == names
    assert m["tool_radius"] == spec.follower.roller_radius             # [machining] left out: the roller's
    assert m["chord_tolerance"] == 0.005 and m["depth"] == spec.cam.thickness
    assert 0 < m["path_error"]["value"] <= m["chord_tolerance"]
    assert m["path_error"]["value"] == max(p["path_error_mm"] for p in m["plates"])
    for k, name in enumerate(names):
        assert (folder / name).read_text() == out.machining.programs[k].text
    assert out.machining.gcode == out.machining.programs[0].text
    assert out.machining.second_gcode == out.machining.programs[1].text
    with pytest.raises(SpecError):
        out.machining.commands_csv
    d = out.summary["drawing"]
    assert d["exact"] is False and d["dwell_arcs"] == "exact"
    assert d["flank_fit_error"]["value"] == out.summary["body"]["flank_fit_error"]["value"]
    print(f"\nflank fit error {d['flank_fit_error']['value']:.4g} mm, drawn {d['drawn_flank_error']['value']:.4g} mm; "
          f"programs' path error {m['path_error']['value']:.4g} mm (tolerance {m['chord_tolerance']:g} mm)")


# ---- the drawing ---------------------------------------------------------------------------------
def title_rows(doc):
    """The title block's rows read back: TEXTs on one baseline, the leftmost the label."""
    by_y: dict[float, list] = {}
    for t in doc.modelspace().query('TEXT[layer=="TITLE"]'):
        by_y.setdefault(round(t.dxf.insert.y, 6), []).append(t)
    rows = {}
    for texts in by_y.values():
        if len(texts) == 2:
            label, value = sorted(texts, key=lambda t: t.dxf.insert.x)
            rows[label.dxf.text] = value.dxf.text
    return rows


def numbers(text: str) -> list[float]:
    return [float(x) for x in re.findall(r"-?\d+(?:\.\d+)?(?:e[+-]?\d+)?", text)]


def drawn_pieces(doc, layer: str) -> list[np.ndarray]:
    """Each SPLINE and ARC on ``layer`` as a dense ordered polyline (complex), by ezdxf's own evaluators."""
    out = []
    for e in doc.modelspace().query(f'*[layer=="{layer}"]'):
        if e.dxftype() == "SPLINE":
            tool = e.construction_tool()
            n = int(math.ceil(sum(abs(b - a) for a, b in zip(tool.control_points, tool.control_points[1:])) / STEP))
            pts = np.array([(v.x, v.y) for v in tool.points(np.linspace(0, tool.max_t, max(n, 1000)))])
        elif e.dxftype() == "ARC":
            a0, a1 = e.dxf.start_angle, e.dxf.end_angle
            sweep = (a1 - a0) % 360.0
            n = int(math.ceil(math.radians(sweep) * e.dxf.radius / STEP))
            pts = np.array([(v.x, v.y) for v in e.vertices(a0 + np.linspace(0, sweep, max(n, 1000)))])
        else:
            raise AssertionError(f"unexpected {e.dxftype()} on {layer}")
        out.append(pts[:, 0] + 1j * pts[:, 1])
    return out


def test_the_dxf_reads_back_clean_and_holds_each_plates_profile(built):
    spec, _, out, folder, _ = built
    doc = ezdxf.readfile(str(folder / DXF_NAME))
    auditor = doc.audit()
    assert not auditor.has_errors, [str(e.message) for e in auditor.errors]
    assert not auditor.has_fixes, [str(e.message) for e in auditor.fixes]
    assert doc.header["$INSUNITS"] == 4
    g = out.design.geometry
    fit = out.summary["body"]["flank_fit_error"]["value"]
    drawn = out.summary["drawing"]["drawn_flank_error"]["value"]
    rr = g.indexer.roller_radius
    worst = 0.0
    for k, cam in enumerate(g.cams):
        types = sorted(e.dxftype() for e in doc.modelspace().query(f'*[layer=="CAM_{k}"]'))
        assert types == ["ARC", "SPLINE", "SPLINE"]
        (arc,) = doc.modelspace().query(f'ARC[layer=="CAM_{k}"]')
        assert abs(complex(arc.dxf.center.x, arc.dxf.center.y)) < 1e-12          # the dwell: about the input axis
        assert arc.dxf.radius == pytest.approx(cam.dwell_radius - rr, abs=1e-9)
        prof = cam.profile[:, 0] + 1j * cam.profile[:, 1]
        sag = chord_sag(cam.profile, cam.profile_radius)
        pieces = drawn_pieces(doc, f"CAM_{k}")
        # the drawn pieces on the exact profile (the profile polyline's chords sag by ≤ sag) ...
        on = max(float(polyline_distance(p, prof).max()) for p in pieces)
        # ... and every exact profile point on a drawn piece
        cover = float(np.min([polyline_distance(prof, p) for p in pieces], axis=0).max())
        worst = max(worst, on, cover)
        assert on <= max(fit, drawn) + sag + 1e-7, (k, on, sag)
        assert cover <= max(fit, drawn) + 1e-6, (k, cover)
        # the check has teeth: the profile grown by 1e-5 (0.7 µm at the lobe) is not covered
        assert float(np.min([polyline_distance(prof * (1 + 1e-5), p) for p in pieces], axis=0).max()) > 10 * fit
    print(f"\nDXF profiles vs the exact profile points: {worst:.3g} mm (fit error {fit:.3g} mm)")


def test_the_title_block_quotes_report_json(built):
    spec, _, out, folder, _ = built
    doc = ezdxf.readfile(str(folder / DXF_NAME))
    rows = title_rows(doc)
    s = out.summary
    assert rows == dict(out.dxf[1].rows)
    geo, body, pa = s["indexer"]["geometry"], s["body"], s["pressure_angle"]

    def near(text, *values, rel=5e-6, abs_=0.0):
        got = numbers(text)
        assert len(got) >= len(values), text
        for x, v in zip(got, values):
            assert x == pytest.approx(v, rel=rel, abs=abs_), (text, v)

    near(rows["STATIONS N"], geo["stations"])
    near(rows["INDEX ANGLE BETA"], geo["index_angle_deg"])
    near(rows["INDEX START"], geo["index_start_deg"])
    near(rows["CENTRE DISTANCE C"], geo["centre_distance_mm"])
    near(rows["TURRET PITCH RADIUS R_p"], geo["pitch_radius_mm"])
    near(rows["ROLLER RADIUS r_r"], geo["roller_radius_mm"])
    near(rows["CAMS"], body["cams"], body["plate_thickness"], body["gap"])
    near(rows["BORE"], body["bore_diameter"])
    near(rows["LARGEST CAM RADIUS"], body["outer_radius"])
    near(rows["DWELL ARCS"], *[c["dwell_radius_mm"] - geo["roller_radius_mm"] for c in geo["per_cam"]],
         360 - geo["index_angle_deg"])
    near(rows["FLANKS"], body["flank_fit_error"]["value"], rel=5e-4)
    near(rows["DRAWN FLANK SPLINES"], s["drawing"]["drawn_flank_error"]["value"], rel=5e-4)
    near(rows["PRESSURE ANGLE (LOAD-CARRYING)"], pa["max_deg"], pa["at_deg"],
         s["checks"]["results"]["pressure_angle"]["limit"], rel=0, abs_=0.005)
    near(rows["MAX DRIVING PRESSURE ANGLE"], pa["index_max_deg"], pa["index_max_at_deg"], rel=0, abs_=0.005)
    near(rows["VOLUME"], s["volume"])
    assert rows["SPEC DIGEST (SHA-256)"] == s["spec_digest"]
    assert rows["DESIGN CHECKS"].startswith("ALL PASS") == s["checks"]["passed"]
    # "exact" only for the dwell arcs; the fitted flanks say they are not
    assert "NOT EXACT" in rows["FLANKS"]
    exact = [label for label, value in rows.items() if "EXACT" in value.replace("NOT EXACT", "").replace(
        "FROM THE EXACT OFFSET", "")]
    assert exact == ["DWELL ARCS"]


def test_drawing_settings(built):
    spec, _, out, _, _ = built
    no_title = spec.replace(**{"drawing.title_block": False, "drawing.dimensions": False})
    d2 = body_of(no_title).design(no_title)
    doc, info = run_pipeline(no_title, solid=False, machining=False, design=d2).dxf
    assert not doc.modelspace().query('*[layer=="TITLE"]') and not doc.modelspace().query("DIMENSION")
    assert not doc.audit().has_errors and info.summary()["title_block"] is False
    for field, value in (("drawing.curves", "arcs"), ("drawing.dxf_version", "R2000"), ("drawing.text_height", 3.0)):
        bad = spec.replace(**{field: value})
        with pytest.raises(SpecError) as err:
            run_pipeline(bad, solid=False, machining=False, design=body_of(bad).design(bad))
        assert err.value.field == field


# ---- the programs --------------------------------------------------------------------------------
def contour(run):
    return [m for m in run.motions if m.tag.startswith("contour:")]


def dense(motions):
    """The interpreted motions sampled about STEP apart (LinuxCNC's arcs: tests/rs274.sample_xy)."""
    parts = []
    for m in motions:
        a, b = complex(*m.start[:2]), complex(*m.end[:2])
        length = abs(b - a)
        if m.kind == "arc":
            turn = (np.angle(b - m.centre) - np.angle(a - m.centre)) * m.rotation % (2 * math.pi)
            length = turn * abs(a - m.centre)
        parts.append(sample_xy([m], max(int(length / STEP), 8))[:-1])
    parts.append(np.array([complex(*motions[-1].end[:2])]))
    return np.concatenate(parts)


def check_program(text: str, cam, rt: float, depth: float, tmp, tool_number: int = 1, clockwise: bool = True
                  ) -> tuple[float, float]:
    """Run ``text`` through rs274 and hold its contour to the exact profile points of ``cam``
    offset by ``rt``: every offset point within the program's stated tolerance of the path, and
    the path a tool radius (± that tolerance) off the profile.  Returns (tolerance, worst)."""
    tol = float(re.search(r"tolerance ([0-9.e-]+) mm \[G64", text).group(1))
    run = run_rs274(text, tmp, tool_number, 2 * rt)
    assert run.units == "mm"
    moves = contour(run)
    assert moves and {m.kind for m in moves} <= {"arc", "line"}
    assert all(abs(m.end[2] + depth) < 1e-9 for m in moves)
    pts = dense(moves)
    assert abs(pts[-1] - pts[0]) < 1e-9                                               # closed
    area = 0.5 * np.sum((np.conj(pts[:-1]) * pts[1:]).imag)
    assert (area < 0) == clockwise
    prof = cam.profile[:, 0] + 1j * cam.profile[:, 1]
    normal = cam.profile_normals[:, 0] + 1j * cam.profile_normals[:, 1]
    offset = prof + rt * normal                                                       # the exact tool centre
    sag = chord_sag(cam.profile, cam.profile_radius)
    to_path = float(polyline_distance(offset, pts).max())
    off_profile = float(np.abs(polyline_distance(pts, prof) - rt).max())
    assert to_path <= tol, (to_path, tol)
    assert off_profile <= tol + sag, (off_profile, tol, sag)
    # the check has teeth: the offset by a tool three tolerances larger is missed
    assert float(polyline_distance(prof + (rt + 3 * tol) * normal, pts).max()) > tol
    return tol, max(to_path, off_profile)


@requires_rs274
def test_each_plate_program_runs_in_rs274_within_its_tolerance_of_the_exact_profile(built, tmp_path):
    spec, _, out, folder, _ = built
    m = out.summary["machining"]
    rt = m["tool_radius"]
    worst = []
    for k, cam in enumerate(out.design.geometry.cams):
        text = (folder / f"cam{k}.nc").read_text()
        assert f"cam {k} of {indexer_value(spec, 'cams')}" in text
        folder_k = tmp_path / f"cam{k}"
        folder_k.mkdir()
        tol, err = check_program(text, cam, rt, m["depth"], folder_k)
        assert tol == m["chord_tolerance"] == m["plates"][k]["tolerance_mm"]
        # the program's own measure (against its analytic tool-centre path) agrees with this one
        assert err <= m["plates"][k]["path_error_mm"] + 5e-5
        worst.append(err)
    print(f"\nrs274 paths vs the exact profile points offset by {rt:g} mm: "
          + ", ".join(f"cam{k} {e:.3g} mm" for k, e in enumerate(worst)) + f" (tolerance {m['chord_tolerance']:g} mm)")


@requires_rs274
def test_the_machining_section_is_respected(built, tmp_path):
    spec, _, _, _, _ = built
    mc = {"machining.tool_radius": 6.0, "machining.tool_number": 3, "machining.spindle_rpm": 5000.0,
          "machining.feed_rate": 240.0, "machining.depth": 17.0, "machining.safe_height": 8.0,
          "machining.chord_tolerance": 0.002, "machining.lead_radius": 4.0, "machining.milling": "conventional"}
    spec2 = spec.replace(**mc)
    design = body_of(spec2).design(spec2)
    mach = machining_outputs(design, design.summary())
    s = mach.machining_summary
    assert (s["tool_radius"], s["tool_number"], s["spindle_rpm"], s["feed_rate"], s["plunge_rate"], s["depth"],
            s["safe_height"], s["chord_tolerance"], s["lead_radius"], s["milling"]) == (
        6.0, 3, 5000.0, 240.0, 80.0, 17.0, 8.0, 0.002, 4.0, "conventional")
    for k, cam in enumerate(design.geometry.cams):
        text = mach.programs[k].text
        for word in ("T3 M6", "G43 H3", "S5000 M3", "G0 Z8", "F80", "F240", "tolerance 0.002 mm"):
            assert word in text, word
        folder_k = tmp_path / f"cam{k}"
        folder_k.mkdir()
        run = run_rs274(text, folder_k, 3, 12.0)
        lead_in = run.tagged("lead-in")[0][0]
        assert abs(abs(complex(*lead_in.start[:2]) - lead_in.centre) - 4.0) <= 2e-4          # lead radius
        check_program(text, cam, 6.0, 17.0, folder_k, tool_number=3, clockwise=False)
    for field, value in (("machining.program", "xc"), ("machining.contour", "lines"), ("machining.passes", 2),
                         ("machining.coolant", True), ("machining.work_offset", "G55"),
                         ("machining.line_numbers", True), ("machining.plunge_rate", 50.0)):
        bad = spec.replace(**{field: value})
        with pytest.raises(SpecError) as err:
            machining_outputs(body_of(bad).design(bad))
        assert err.value.field == field


# ---- the command line ----------------------------------------------------------------------------
def cli(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", *map(str, args)], capture_output=True, text=True,
                         env=env, timeout=SAFETY_S, stdin=subprocess.DEVNULL)
    assert res.returncode == 0, res.stdout + res.stderr
    return res


def test_the_command_line_writes_the_same_drawing_and_programs(built, tmp_path):
    """``dxf`` and ``gcode`` (the pipeline without the solid) on the TOML spec give the files the
    pipeline wrote: the programs byte for byte, the drawing with the same profile entities and
    title block."""
    spec, toml, out, folder, _ = built
    for k, which in enumerate(("first", "second")):
        target = tmp_path / f"cli_cam{k}.nc"
        cli("gcode", toml, "--cam", which, "-o", target)
        assert target.read_text() == (folder / f"cam{k}.nc").read_text()
    res = cli("dxf", toml, "-o", tmp_path / "dxf")
    assert "drawing written to" in res.stdout
    a, b = ezdxf.readfile(str(tmp_path / "dxf" / DXF_NAME)), ezdxf.readfile(str(folder / DXF_NAME))
    assert title_rows(a) == title_rows(b)
    for k in range(indexer_value(spec, "cams")):
        pa, pb = drawn_pieces(a, f"CAM_{k}"), drawn_pieces(b, f"CAM_{k}")
        assert len(pa) == len(pb) and all(np.array_equal(x, y) for x, y in zip(pa, pb))

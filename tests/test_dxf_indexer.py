"""The parallel indexer's drawing (exporters.dxf_indexer) written, read back with ezdxf and held to
geometry computed here from the documented conventions (generators/bodies/indexing/parallel.py's
docstring): roller centres p = P + R_p·e(a_k + T·j − ψ), ψ from the law; the profile the inward
offset by r_r of the cam-frame locus Rot(−τ)·p, its normal by finite differences.  The flank SPLINEs
are evaluated by ezdxf's own B-spline evaluator, not ours."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

ezdxf = pytest.importorskip("ezdxf")
from ezdxf import recover  # noqa: E402

from cam_workbench.exporters.dxf_indexer import indexer_drawing, write_indexer_dxf  # noqa: E402
from cam_workbench.generators.bodies.indexing.parallel import ParallelIndexer, design_parallel  # noqa: E402
from cam_workbench.generators.bodies.indexing.parallel_body import indexer_body  # noqa: E402
from cam_workbench.generators.motion.laws import evaluate_law  # noqa: E402

CASES = {"default": {}, "three_cams": {"cams": 3},
         "beta270_shifted": {"index_angle": math.radians(270), "centre_distance": 90.0, "law": "poly4567",
                             "index_start": 0.3}}


@pytest.fixture(scope="module", params=sorted(CASES))
def drawn(request, tmp_path_factory):
    d = design_parallel(ParallelIndexer(**CASES[request.param]))
    body = indexer_body(d, thickness=18.0, gap=4.0, bore_diameter=25.0)
    path = tmp_path_factory.mktemp("dxf_indexer") / f"{request.param}.dxf"
    info = write_indexer_dxf(d, body, path, title="TEST INDEXER")
    return d, body, info, path, ezdxf.readfile(str(path))


# ---- the conventions, recomputed -----------------------------------------------------------------
def law_psi(ix, theta):
    """ψ [rad] (clockwise, continuous over turns) from the law."""
    t_st = 2 * math.pi / ix.stations
    rel = np.asarray(theta, dtype=float) - ix.index_start
    turns = np.floor(rel / (2 * math.pi))
    f, _, _, _ = evaluate_law(ix.law, np.clip((rel - 2 * math.pi * turns) / ix.index_angle, 0, 1))
    return t_st * (turns + f)


def a_k(ix, k):
    return math.pi + (ix.cams - 1 - 2 * k) * math.pi / (ix.stations * ix.cams)


def roller_centres(ix, k, theta):
    """Plane k's N roller centres in the fixed frame at input angle ``theta``."""
    al = a_k(ix, k) + 2 * math.pi * np.arange(ix.stations) / ix.stations - law_psi(ix, theta)
    return np.column_stack([ix.centre_distance + ix.pitch_radius * np.cos(al), ix.pitch_radius * np.sin(al)])


def exact_offset(ix, k, tau, h=1e-5):
    """Q(τ) = L(τ) − r_r·n(τ), L(τ) = Rot(−τ)·(P + R_p·e(a_k − ψ(τ))), n = J·L'/|L'| (L' central differences)."""
    def centre(t):
        al = a_k(ix, k) - law_psi(ix, t)
        px, py = ix.centre_distance + ix.pitch_radius * np.cos(al), ix.pitch_radius * np.sin(al)
        c, s = np.cos(t), np.sin(t)
        return np.stack([c * px + s * py, -s * px + c * py], -1)
    d = (centre(tau + h) - centre(tau - h)) / (2 * h)
    n = np.stack([-d[:, 1], d[:, 0]], -1) / np.hypot(d[:, 0], d[:, 1])[:, None]
    return centre(tau) - ix.roller_radius * n


def dwell_radius(ix, k):
    return math.hypot(ix.centre_distance + ix.pitch_radius * math.cos(a_k(ix, k)),
                      ix.pitch_radius * math.sin(a_k(ix, k)))


def quoted_error(doc):
    rows = title_rows(doc)
    m = re.fullmatch(r"CUBIC B-SPLINES WITHIN ([0-9.eE+-]+) mm OF THE EXACT OFFSET \(MEASURED\)", rows["FLANKS"])
    assert m, rows["FLANKS"]
    return float(m.group(1))


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


# ---- the file ------------------------------------------------------------------------------------
def test_the_file_reads_back_clean_in_mm(drawn):
    d, body, info, path, doc = drawn
    auditor = doc.audit()
    assert not auditor.has_errors, [str(e.message) for e in auditor.errors]
    assert not auditor.has_fixes, [str(e.message) for e in auditor.fixes]
    _, rec = recover.readfile(str(path))
    assert not rec.has_errors, [str(e.message) for e in rec.errors]
    assert doc.header["$INSUNITS"] == 4
    n_c = d.indexer.cams
    names = {layer.dxf.name for layer in doc.layers}
    assert {f"CAM_{k}" for k in range(n_c)} | {f"ROLLERS_{k}" for k in range(n_c)} | {"TURRET", "BORE", "TITLE",
                                                                                       "DIMENSIONS"} <= names
    assert set(info.layers) <= names
    assert (info.cams, info.splines, info.arcs, info.rollers) == (n_c, 2 * n_c, n_c, n_c * d.indexer.stations)


def test_the_flank_splines_are_the_body_bsplines(drawn):
    d, body, info, path, doc = drawn
    msp = doc.modelspace()
    for k, loop in enumerate(body.loops):
        splines = msp.query(f'SPLINE[layer=="CAM_{k}"]')
        curves = [p.nurbs for p in loop.pieces if hasattr(p, "nurbs")]
        assert len(splines) == len(curves) == 2
        for sp, curve in zip(splines, curves):
            assert sp.dxf.degree == curve.degree == 3
            assert np.array_equal(np.asarray(sp.knots), curve.knots)
            assert np.array_equal(np.asarray(sp.control_points)[:, :2], curve.poles)
            assert len(sp.weights) == 0 and not sp.closed and not sp.fit_point_count()


def test_the_flank_splines_lie_within_the_quoted_error_of_the_exact_offset(drawn):
    d, body, info, path, doc = drawn
    ix = d.indexer
    quoted = quoted_error(doc)
    assert quoted == info.quoted_error and quoted >= body.fit_error
    worst = 0.0
    for k in range(ix.cams):
        for sp in doc.modelspace().query(f'SPLINE[layer=="CAM_{k}"]'):
            bs = sp.construction_tool()           # ezdxf's evaluator (it rescales knots not starting at 0)
            t = np.linspace(0.0, bs.max_t, 6001)
            pts = np.array([(v.x, v.y) for v in bs.points(t)])
            k0, k1 = sp.knots[0], sp.knots[-1]
            u = k0 + (k1 - k0) * t / bs.max_t
            # the loop runs counter-clockwise, τ clockwise (the docstring): the parameter is reversed
            tau = k0 + k1 - u
            dist = np.hypot(*(pts - exact_offset(ix, k, tau)).T)
            assert dist.max() <= quoted + 1e-6
            worst = max(worst, float(dist.max()))
    assert worst >= 0.8 * quoted                   # the quoted number is the measured one, not a loose bound


def test_the_dwell_arcs_are_exact(drawn):
    d, body, info, path, doc = drawn
    ix = d.indexer
    beta = math.degrees(ix.index_angle)
    msp = doc.modelspace()
    for k in range(ix.cams):
        (arc,) = msp.query(f'ARC[layer=="CAM_{k}"]')
        assert abs(arc.dxf.center.x) + abs(arc.dxf.center.y) == 0
        assert arc.dxf.radius == pytest.approx(dwell_radius(ix, k) - ix.roller_radius, abs=1e-9)
        assert (arc.dxf.end_angle - arc.dxf.start_angle) % 360 == pytest.approx(360 - beta, abs=1e-9)
        # its ends are the exact offset's at the dwell's ends τ = θ_s (start: the cam turns CCW) and
        # θ_s − 2π + β, and the flanks' ends
        ends = np.array([[arc.dxf.radius * math.cos(math.radians(a)), arc.dxf.radius * math.sin(math.radians(a))]
                         for a in (arc.dxf.start_angle, arc.dxf.end_angle)])
        q = exact_offset(ix, k, np.array([ix.index_start, ix.index_start - 2 * math.pi + ix.index_angle]))
        assert np.abs(ends - q).max() < 1e-6
        tips = np.vstack([np.asarray(sp.control_points)[[0, -1], :2] for sp in msp.query(f'SPLINE[layer=="CAM_{k}"]')])
        for e in ends:
            assert np.hypot(*(tips - e).T).min() < 1e-9


def test_turret_rollers_bore_and_centre_distance(drawn):
    d, body, info, path, doc = drawn
    ix = d.indexer
    msp = doc.modelspace()
    (pitch,) = msp.query('CIRCLE[layer=="TURRET"]')
    assert (pitch.dxf.center.x, pitch.dxf.center.y, pitch.dxf.radius) == (ix.centre_distance, 0.0, ix.pitch_radius)
    lines = msp.query('LINE[layer=="TURRET"]')
    mids = {(round((ln.dxf.start.x + ln.dxf.end.x) / 2, 9), round((ln.dxf.start.y + ln.dxf.end.y) / 2, 9)) for ln in lines}
    assert mids == {(ix.centre_distance, 0.0)}      # the centre mark at P
    for k in range(ix.cams):
        circles = msp.query(f'CIRCLE[layer=="ROLLERS_{k}"]')
        got = np.array([(c.dxf.center.x, c.dxf.center.y) for c in circles])
        assert all(c.dxf.radius == ix.roller_radius for c in circles)
        expect = roller_centres(ix, k, 0.0)           # at θ = 0 the cam frame is the fixed frame
        assert got.shape == expect.shape
        assert np.abs(got - expect).max() < 1e-9
    (bore,) = msp.query('CIRCLE[layer=="BORE"]')
    assert bore.dxf.radius == 12.5
    (dim,) = msp.query('DIMENSION[layer=="DIMENSIONS"]')
    assert dim.get_measurement() == pytest.approx(ix.centre_distance, abs=1e-12)
    assert tuple(dim.dxf.defpoint2)[:2] == (0.0, 0.0) and tuple(dim.dxf.defpoint3)[:2] == (ix.centre_distance, 0.0)


def test_the_title_block_quotes_the_design(drawn):
    d, body, info, path, doc = drawn
    ix = d.indexer
    rows = title_rows(doc)
    assert rows == dict(info.rows)
    texts = [t.dxf.text for t in doc.modelspace().query('TEXT[layer=="TITLE"]')]
    assert "TEST INDEXER" in texts

    def number(label, unit):
        m = re.fullmatch(rf"([-0-9.e+]+) ?{unit}.*", rows[label])
        assert m, rows[label]
        return float(m.group(1))

    assert int(rows["STATIONS N"]) == ix.stations
    assert number("INDEX ANGLE BETA", "°") == pytest.approx(math.degrees(ix.index_angle), rel=5e-6)
    assert rows["MOTION LAW"].lower() == ix.law
    assert number("INDEX START", "°") == pytest.approx(math.degrees(ix.index_start), rel=5e-6, abs=1e-9)
    assert number("CENTRE DISTANCE C", "mm") == pytest.approx(ix.centre_distance, rel=5e-6)
    assert number("TURRET PITCH RADIUS R_p", "mm") == pytest.approx(ix.pitch_radius, rel=5e-6)
    assert number("ROLLER RADIUS r_r", "mm") == pytest.approx(ix.roller_radius, rel=5e-6)
    assert int(rows["CAMS"].split()[0]) == ix.cams
    m = re.fullmatch(r"EXACT ARCS R ([0-9. /]+) mm, ([0-9.]+)° EACH", rows["DWELL ARCS"])
    radii = [float(v) for v in m.group(1).split(" / ")]
    assert radii == pytest.approx([dwell_radius(ix, k) - ix.roller_radius for k in range(ix.cams)], rel=5e-6)
    assert float(m.group(2)) == pytest.approx(360 - math.degrees(ix.index_angle), rel=5e-6)
    # the flanks are fitted: "exact" names only the offset they are measured against
    assert "EXACT" not in rows["FLANKS"].replace("OF THE EXACT OFFSET", "")
    assert quoted_error(doc) >= body.fit_error
    pa = re.match(r"([0-9.]+)° AT", rows["MAX DRIVING PRESSURE ANGLE"])
    assert float(pa.group(1)) == pytest.approx(d.summary()["max_driving_pressure_angle_deg"], abs=0.006)


def test_the_document_is_built_without_writing():
    d = design_parallel(ParallelIndexer())
    body = indexer_body(d, thickness=10.0)
    doc, info = indexer_drawing(d, body)
    assert not doc.modelspace().query('CIRCLE[layer=="BORE"]')          # no bore asked
    assert info.summary()["quoted_flank_error_mm"] == info.quoted_error
    assert info.drawn_error >= body.fit_error * (1 - 1e-9)

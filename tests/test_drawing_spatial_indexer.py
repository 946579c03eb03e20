"""The barrel and globoidal indexers' drawing in the output pipeline (exporters.drawing_spatial_indexer):
``cam_drawing`` of the built-in examples, written, read back with ezdxf and held to report.json's numbers
(``design.summary()``) and, for the barrel's developed-view traces, to exact envelope points computed by
the independent check of tests/test_dxf_spatial_indexer.py (``exact_trace``: the conventions recomputed,
a grid bracket and bisection per τ).  The SPLINEs are evaluated by ezdxf's own B-spline evaluator."""
from __future__ import annotations

import dataclasses
import json
import math
import re

import numpy as np
import pytest

ezdxf = pytest.importorskip("ezdxf")

from cam_workbench.exporters import drawing_spatial_indexer as dsi  # noqa: E402  (registers the drawing)
from cam_workbench.exporters.dxf import DRAWINGS, cam_drawing  # noqa: E402
from cam_workbench.exporters.dxf_indexer import round_up  # noqa: E402
from cam_workbench.generators.cam_design import design_cam  # noqa: E402
from cam_workbench.generators.errors import SpecError  # noqa: E402
from cam_workbench.generators.spec.examples import example_spec  # noqa: E402

from .test_dxf_spatial_indexer import exact_trace  # noqa: E402
from .test_dxf_spatial_indexer import title_rows as read_rows  # noqa: E402

EXAMPLES = ("barrel_indexer", "globoidal_indexer")


def _drawn(name, tmp_path_factory):
    design = design_cam(example_spec(name))          # = Cam.example(name).design, without the CAD kernel
    summary = design.summary()                        # report.json's dict
    doc, info = cam_drawing(design, summary)
    path = tmp_path_factory.mktemp("drawing_spatial") / f"{name}.dxf"
    doc.saveas(str(path))
    return design, summary, info, ezdxf.readfile(str(path))


@pytest.fixture(scope="module")
def drawings(tmp_path_factory):
    """name → (design, summary, info, document read back), each made once."""
    cache: dict = {}

    def get(name):
        if name not in cache:
            cache[name] = _drawn(name, tmp_path_factory)
        return cache[name]

    return get


@pytest.fixture(scope="module", params=EXAMPLES)
def drawn(request, drawings):
    return drawings(request.param)


@pytest.fixture(scope="module")
def barrel(drawings):
    return drawings("barrel_indexer")


@pytest.fixture(scope="module")
def globoid_design():
    return design_cam(example_spec("globoidal_indexer"))


def with_drawing(design, **changes):
    """The design with ``[drawing]`` changed (nothing redesigned: the drawing reads only the spec's
    ``[drawing]``)."""
    spec = design.spec
    return dataclasses.replace(design, spec=dataclasses.replace(spec, drawing=dataclasses.replace(spec.drawing,
                                                                                                   **changes)))


# ---- numbers as printed ----------------------------------------------------------------------------
NUM = r"([-+]?[0-9]+(?:\.[0-9]+)?(?:e[-+][0-9]+)?)"


def as_printed(text: str, value: float) -> None:
    """``text`` is ``value`` printed: equal to it within half a unit of the printed last digit."""
    if "e" in text:
        mant, exp = text.split("e")
        digits = len(mant.split(".")[1]) if "." in mant else 0
        unit = 10.0 ** (int(exp) - digits)
    else:
        unit = 10.0 ** -(len(text.split(".")[1]) if "." in text else 0)
    assert abs(float(text) - value) <= 0.5 * unit * (1 + 1e-9), (text, value)


def quoted_bound(text: str, value: float) -> None:
    """``text`` is the measured ``value`` rounded up to 4 significant digits (a bound)."""
    assert float(text) == round_up(value, 4) and value <= float(text) <= value * (1 + 1e-3), (text, value)


def fields(rows, label, pattern):
    m = re.fullmatch(pattern, rows[label])
    assert m, (label, rows[label])
    return m.groups()


# ---- the document ----------------------------------------------------------------------------------
def test_registered_and_read_back(drawn):
    design, summary, info, doc = drawn
    assert DRAWINGS.of(design) is dsi.build_spatial_indexer_dxf
    assert not doc.audit().has_errors
    assert doc.header["$INSUNITS"] == 4 and doc.dxfversion == "AC1024"     # R2010, mm
    msp = doc.modelspace()
    s = info.summary()
    json.dumps(s, allow_nan=False)                                       # report.json's drawing section
    assert s["file_version"] == "R2010" and s["units"] == "mm" and s["written"] is True
    assert s["splines"] == len(msp.query("SPLINE")) and s["arcs"] == len(msp.query("ARC"))
    assert s["circles"] == len(msp.query("CIRCLE"))
    assert s["flank_fit_error"]["value"] == summary["body"]["flank_fit_error"]["value"] == design.fit_error
    assert s["exact"] is False and s["title_block"] is True and s["dimensions"] is True
    traced = s["kind"] == "barrel"
    assert (s["drawn_trace_error"]["value"] is not None) == traced == (s["splines"] > 0)
    assert s["curves"] == ("cubic" if traced else None)


def test_the_title_block_quotes_report_json(drawn):
    design, summary, info, doc = drawn
    rows = read_rows(doc)
    assert rows == dict(info.rows)
    titles = [t.dxf.text for t in doc.modelspace().query('TEXT[layer=="TITLE"]')]
    kind = summary["indexer"]["type"]
    assert f"{kind.upper()} INDEXER" in titles and info.title == f"{kind.upper()} INDEXER"
    geo, body, pa = summary["indexer"]["geometry"], summary["body"], summary["pressure_angle"]
    assert rows["TYPE"] == f"{kind.upper()} INDEXER"
    assert int(rows["STATIONS N"]) == geo["stations"]
    as_printed(*fields(rows, "INDEX ANGLE BETA", NUM + "°"), geo["index_angle_deg"])
    assert rows["MOTION LAW"] == geo["law"].upper()
    as_printed(*fields(rows, "INDEX START", NUM + "° OF INPUT"), geo["index_start_deg"])
    as_printed(*fields(rows, "CENTRE DISTANCE C", NUM + " mm"), geo["centre_distance"])
    as_printed(*fields(rows, "ROLLER RADIUS r_r", NUM + " mm"), geo["roller_radius"])
    length, t0, t1 = fields(rows, "ROLLER LENGTH", f"{NUM} mm, t = {NUM} TO {NUM} mm")
    as_printed(length, geo["roller_end"] - geo["roller_start"])
    as_printed(t0, geo["roller_start"])
    as_printed(t1, geo["roller_end"])
    as_printed(*fields(rows, "CAM WIDTH W", NUM + " mm"), geo["cam_width"])
    as_printed(*fields(rows, "BORE", "Ø" + NUM + " mm"), body["bore_diameter"])
    if kind == "barrel":
        as_printed(*fields(rows, "TURRET PITCH RADIUS R_p", NUM + " mm"), geo["pitch_radius"])
        root, top = fields(rows, "RIB RADII", f"ROOT {NUM} mm, TOP {NUM} mm")
        as_printed(root, geo["root_radius"])
        as_printed(top, geo["outer_radius"])
    else:
        assert "TURRET PITCH RADIUS R_p" not in rows
        tip, root = fields(rows, "RIB GLOBOIDS", f"TIP {NUM} mm, ROOT {NUM} mm ABOUT THE TURRET AXIS")
        as_printed(tip, geo["tip_radius"])
        as_printed(root, geo["root_radius"])
    lim = summary["checks"]["results"]["pressure_angle"]["limit"]
    v, at, limit = fields(rows, "PRESSURE ANGLE (DRIVING)", f"{NUM}° AT {NUM}° OF INPUT \\(LIMIT {NUM}°\\)")
    as_printed(v, pa["max_deg"])
    as_printed(at, pa["at_deg"])
    as_printed(limit, lim)
    v, at = fields(rows, "PRESSURE ANGLE (ANY CONTACT)", f"{NUM}° AT {NUM}° OF INPUT \\(NOT CHECKED\\)")
    as_printed(v, pa["contacts_max_deg"])
    as_printed(at, pa["contacts_max_at_deg"])
    v, at = fields(rows, "MIN REGULARITY MARGIN", f"{NUM} AT {NUM}° OF INPUT")
    as_printed(v, geo["min_regularity_margin"]["value_1"])
    as_printed(at, geo["min_regularity_margin"]["at_deg"])
    v, at = fields(rows, "MIN RIB THICKNESS", f"{NUM} mm AT {NUM}° OF INPUT")
    as_printed(v, geo["min_rib_thickness"]["value_mm"])
    as_printed(at, geo["min_rib_thickness"]["at_deg"])
    motion = summary["indexer"]["motion_from_geometry"]
    v, n = fields(rows, "TURRET MOTION FROM FLANKS", f"{NUM} rad FROM THE LAW \\(([0-9]+) INPUT ANGLES\\)")
    as_printed(v, motion["max_error_rad"])
    assert int(n) == motion["samples"]
    assert rows["DESIGN CHECKS"] == "ALL PASS (5 CHECKED, 1 SKIPPED)" and summary["checks"]["passed"]
    assert rows["SPEC DIGEST (SHA-256)"] == summary["spec_digest"]
    (psi,) = fields(rows, "DRAWN AT", f"INPUT ANGLE 0°, TURRET ANGLE {NUM}°")
    as_printed(psi, info.summary()["drawn_at"]["turret_angle_deg"])
    assert rows["UNITS / SCALE"] == "mm / 1:1"
    # the measured errors: quoted rounded up, the drawing section holds the same numbers
    s = info.summary()
    (fit,) = fields(rows, "FLANK SURFACES", f"FITTED BICUBIC B-SPLINES, NOT EXACT: FIT ERROR {NUM} mm FROM THE "
                                            "EXACT ENVELOPE \\(MEASURED\\)")
    quoted_bound(fit, body["flank_fit_error"]["value"])
    assert float(fit) == s["flank_fit_error"]["quoted"]
    if kind == "barrel":
        (tr,) = fields(rows, "FLANK TRACES", f"FITTED CUBIC SPLINES, NOT EXACT: {NUM} mm FROM THE EXACT ENVELOPE "
                                             "\\(MEASURED, 16 POINTS PER SPAN\\)")
        quoted_bound(tr, s["drawn_trace_error"]["value"])
        assert float(tr) == s["drawn_trace_error"]["quoted"]
        assert s["drawn_trace_error"]["value"] == max(t["error_mm"] for t in s["traces"])
    else:
        assert rows["FLANK TRACES"] == "NOT DRAWN (THE FLANKS ARE SURFACES)"
    # "EXACT" names only the reference and the circles, arcs and lines: every fitted thing says NOT EXACT
    for label, value in rows.items():
        if label != "CIRCLES, ARCS, LINES":
            assert "EXACT" not in value.replace("NOT EXACT", "").replace("THE EXACT ENVELOPE", ""), (label, value)
    assert rows["CIRCLES, ARCS, LINES"] == "EXACT"


def test_the_bore_is_drawn_and_dimensioned(drawn):
    design, summary, info, doc = drawn
    msp = doc.modelspace()
    rb = summary["body"]["bore_diameter"] / 2
    xe, ye = info.drawn.views["end"]
    (c,) = msp.query('CIRCLE[layer=="BORE"]')
    assert (c.dxf.center.x, c.dxf.center.y, c.dxf.radius) == (xe, ye, rb)
    dims = sorted(d.get_measurement() for d in msp.query('DIMENSION[layer=="DIMENSIONS"]'))
    assert pytest.approx(2 * rb, abs=1e-12) in dims
    assert pytest.approx(design.geometry.indexer.centre_distance, abs=1e-12) in dims


# ---- [drawing] -------------------------------------------------------------------------------------
def test_settings_it_cannot_honour_are_refused_naming_the_field(barrel, globoid_design):
    design = barrel[0]
    for d in (design, globoid_design):
        for changes, field in (({"dxf_version": "R2000"}, "drawing.dxf_version"),
                               ({"text_height": 3.0}, "drawing.text_height")):
            with pytest.raises(SpecError) as exc:
                cam_drawing(with_drawing(d, **changes))
            assert exc.value.field == field
    # the barrel's traces are cubic SPLINEs within their measured error
    trace_error = barrel[2].drawn.trace_error
    for changes, field in (({"curves": "arcs"}, "drawing.curves"), ({"curves": "spline"}, "drawing.curves"),
                           ({"chord_tolerance": 0.5 * trace_error}, "drawing.chord_tolerance")):
        with pytest.raises(SpecError) as exc:
            cam_drawing(with_drawing(design, **changes))
        assert exc.value.field == field
    # the globoid draws no fitted curve: exact circles, arcs and lines honour any curves / chord_tolerance
    doc, info = cam_drawing(with_drawing(globoid_design, curves="arcs", chord_tolerance=1e-6))
    assert not doc.modelspace().query("SPLINE") and info.summary()["chord_tolerance"] == 1e-6


def test_settings_it_honours(globoid_design):
    d = globoid_design
    doc, info = cam_drawing(with_drawing(d, title_block=False, dimensions=False))
    msp = doc.modelspace()
    assert not msp.query('*[layer=="TITLE"]') and not msp.query("DIMENSION") and info.rows == ()
    assert info.summary()["title_block"] is False and info.summary()["dimensions"] is False
    assert msp.query('CIRCLE[layer=="BORE"]')                           # the geometry stays
    summary = d.summary()
    summary["spec_digest"] = "THE-PASSED-SUMMARY"                       # the title block quotes what it is given
    doc, info = cam_drawing(with_drawing(d, title="Feed index", part_number="P-17", author="A. N. Other",
                                         material="16MnCr5, case hardened"), summary)
    rows = read_rows(doc)
    assert info.title == "FEED INDEX (GLOBOIDAL INDEXER)"
    assert info.title in [t.dxf.text for t in doc.modelspace().query('TEXT[layer=="TITLE"]')]
    assert (rows["PART NO."], rows["DRAWN BY"], rows["MATERIAL"]) == ("P-17", "A. N. Other", "16MnCr5, case hardened")
    assert rows["SPEC DIGEST (SHA-256)"] == "THE-PASSED-SUMMARY"


# ---- the barrel's developed traces against the exact envelope ------------------------------------
def test_the_barrel_traces_lie_within_the_quoted_error(barrel):
    design, summary, info, doc = barrel
    ix = design.geometry.indexer
    rows = read_rows(doc)
    (quoted,) = fields(rows, "FLANK TRACES", f"FITTED CUBIC SPLINES, NOT EXACT: {NUM} mm .*")
    bound = float(quoted)
    phi_m = math.radians(info.summary()["phi_mid_deg"])
    msp = doc.modelspace()
    worst, n = 0.0, 0
    for where, rho, view in (("TOP", ix.outer_radius, "developed_top"), ("ROOT", ix.root_radius, "developed_root")):
        x0, y0 = info.summary()["view_origins"][view]
        for sign, side in (("P", 1), ("M", -1)):
            splines = msp.query(f'SPLINE[layer=="TRACE_{where}_{sign}"]')
            assert splines
            for sp in splines:
                assert sp.dxf.degree == 3 and not sp.weights                  # polynomial cubics
                bs = sp.construction_tool()       # ezdxf's evaluator (it rescales knots not starting at 0)
                knots = np.unique(np.asarray(sp.knots))                       # the parameter is τ [rad]
                fr = np.arange(16) / 16                                       # 16 points per span, and the end
                tau = np.append((knots[:-1, None] + fr * np.diff(knots)[:, None]).ravel(), knots[-1])
                u = np.clip((tau - knots[0]) * bs.max_t / (knots[-1] - knots[0]), 0.0, bs.max_t)
                pts = np.array([(v.x, v.y) for v in bs.points(u)])
                phi, z = exact_trace(ix, side, rho, tau)
                x = rho * (phi - phi_m)
                x = x + 2 * math.pi * rho * np.round((pts[:, 0] - x0 - x) / (2 * math.pi * rho))
                dist = np.hypot(pts[:, 0] - x0 - x, pts[:, 1] - y0 - z)
                assert dist.max() <= bound, (where, side, dist.max())
                worst = max(worst, float(dist.max()))
                n += 1
    assert n == info.summary()["splines"] == len(msp.query("SPLINE"))
    print(f"barrel traces: worst {worst:.4e} mm of the exact envelope, quoted {bound:.4e} mm")
    assert worst >= 0.5 * bound                                              # the quoted number is the measured one


def test_conical_rollers_in_the_title_block(tmp_path):
    """A conical roller's rows quote report.json's geometry; r(t0), r(t1) recomputed here from the
    spec (r_r + (t − t_m)·tan γ)."""
    import copy

    from cam_workbench.generators.spec import CamSpec
    from cam_workbench.generators.spec.examples import GLOBOIDAL_INDEXER_SPEC_DICT

    d = copy.deepcopy(GLOBOIDAL_INDEXER_SPEC_DICT)
    d["indexer"]["roller_cone_angle"] = 8.0
    design = design_cam(CamSpec.from_dict(d))
    summary = design.summary()
    doc, info = cam_drawing(design, summary)
    doc.saveas(str(tmp_path / "cone.dxf"))
    rows = read_rows(ezdxf.readfile(str(tmp_path / "cone.dxf")))
    geo = summary["indexer"]["geometry"]
    as_printed(*fields(rows, "ROLLER RADIUS r_r", NUM + " mm AT THE MIDDLE"), 12.0)
    g, r0, t0, r1, t1 = fields(rows, "ROLLER CONE ANGLE", f"{NUM}°, RADIUS {NUM} mm AT t = {NUM} TO {NUM} mm AT t = {NUM}")
    as_printed(g, 8.0)
    k = math.tan(math.radians(8.0))
    as_printed(r0, 12.0 + (74.0 - 85.0) * k)
    as_printed(r1, 12.0 + (96.0 - 85.0) * k)
    assert (float(t0), float(t1)) == (74.0, 96.0)
    assert geo["roller_radius_start"] == pytest.approx(12.0 - 11.0 * k, abs=1e-12)


def test_cylinders_have_no_cone_row(drawn):
    rows = read_rows(drawn[3])
    assert "ROLLER CONE ANGLE" not in rows and not rows["ROLLER RADIUS r_r"].endswith("AT THE MIDDLE")

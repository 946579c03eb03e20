"""The DXF drawing, checked by real readers (LibreCAD's drawing of every example: test_dxf_librecad.py):

* ezdxf's auditor finds no errors in any variant (cubic, spline, arcs, polyline, R12, inch, closed flag);
* the default PROFILE SPLINE read back is a polynomial cubic, and ezdxf's own B-spline evaluator
  puts it within drawing.chord_tolerance of the exact offset of the PH pitch curve (computed from
  the PH spline, not from our NURBS code), at the distance report.json states, both ways;
* with ``curves = "spline"`` the PROFILE SPLINE read back has exactly the degree, knots, control
  points and weights of the NURBS profile, and ezdxf's own NURBS evaluator
  (``ezdxf.math.BSpline``) puts its points on the exact offset to 1e-9 relative;
* arcs and polyline read back from the file stay within the chord tolerance of the exact
  profile, measured both ways densely, and form a closed chain;
* CadQuery's DXF importer turns the PROFILE (and BORE) layers into faces whose areas, integrated
  with OCCT's own curve evaluator, equal the cross-section of the OCCT solid;
* layers, ``$INSUNITS``, DIMENSION measurements, the title block's motion table, its title (the
  body's name) and its texts inside their cells for every example (ezdxf's measure and the
  exporter's width bound);
* FreeCAD's DXF importer reads the exact splines and the default cubic ones;
* a PNG rendered by ezdxf's drawing add-on (matplotlib backend) is left in test-artifacts/.
"""
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from cam_workbench.exporters.dxf import LAYERS, export_dxf, read_profile_path
from cam_workbench.generators import default_spec, design_cam
from cam_workbench.generators.curves.approx import max_distance
from cam_workbench.generators.cam_design import profile_offset_distance
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec import DEFAULT_SPEC_DICT, CamSpec
from cam_workbench.generators.spec.examples import EXAMPLES, example_spec

from .conftest import ROOT, SAFETY_S, requires_ocp

ezdxf = pytest.importorskip("ezdxf")

INCH = {"units": "in", "cam.thickness": 0.5, "cam.base_radius": 2.0, "follower.offset": 0.3,
        "follower.roller_radius": 0.25, "cam.bore_diameter": 0.5, "motion[1].lift": 0.8,
        "motion[3].lift": 0.8, "drawing.chord_tolerance": 5e-5}

SPLINE = {"drawing.curves": "spline"}

VARIANTS = {
    "cubic": {},
    "cubic_knife": {"follower.kind": "knife", "cam.direction": "cw", "cam.bore_diameter": 8.0},
    "cubic_inch": INCH,
    "spline": SPLINE,
    "arcs": {"drawing.curves": "arcs"},
    "polyline": {"drawing.curves": "polyline"},
    "arcs_r12": {"drawing.curves": "arcs", "drawing.dxf_version": "R12"},
    "polyline_r12": {"drawing.curves": "polyline", "drawing.dxf_version": "R12"},
    "spline_closed_flag": {**SPLINE, "drawing.spline_closed_flag": True},
    "inch": {**INCH, **SPLINE},
    "knife_cw": {**SPLINE, "follower.kind": "knife", "cam.direction": "cw", "cam.bore_diameter": 8.0},
}


@pytest.fixture(scope="module")
def drawings(tmp_path_factory):
    """{variant: (design, path, info)} written once."""
    folder = tmp_path_factory.mktemp("dxf")
    out = {}
    for name, changes in VARIANTS.items():
        design = design_cam(default_spec().replace(**changes))
        path = folder / f"{name}.dxf"
        out[name] = (design, path, export_dxf(design, path))
    return out


def _exact_profile_points(design, t):
    """Points of the exported (ccw) profile at its parameters t, from the PH spline and the
    offset definition p(ξ) + d·i·p'(ξ)/|p'(ξ)| — no NURBS code involved."""
    pitch = design.pitch
    reversed_ = design.profile.area() < 0
    u = pitch.M - t if reversed_ else t
    seg = np.minimum(np.floor(u).astype(int), pitch.M - 1)
    xi = u - seg
    p = pitch.spline.point(seg, xi)
    d = profile_offset_distance(pitch, design.spec.roller_radius) if design.spec.roller_radius > 0 else 0.0
    dp = pitch.spline.first_derivative(seg, xi)
    return p + d * 1j * dp / np.abs(dp)


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_audit_finds_no_errors(drawings, name):
    _, path, _ = drawings[name]
    doc = ezdxf.readfile(path)
    auditor = doc.audit()
    assert not auditor.has_errors, [str(e.message) for e in auditor.errors]
    assert not auditor.has_fixes, [str(e.message) for e in auditor.fixes]
    layers = {layer.dxf.name for layer in doc.layers}
    assert set(LAYERS) <= layers
    msp = doc.modelspace()
    used = {e.dxf.layer for e in msp}
    # the body's layers (a groove's outer wall and rim, holes, hub, timing mark) carry entities
    # only when the body has them; tests/test_bodies.py holds those against the body
    body_only = {"PROFILE_OUTER", "OUTLINE", "HOLES", "HUB", "TIMING_MARK", "PROFILE_2", "PITCH_2", "SPACER"}
    expected = set(LAYERS) - body_only - ({"PRIME_CIRCLE"} if "knife" in name else set())
    assert expected <= used


@pytest.mark.parametrize("name", ["spline", "spline_closed_flag", "inch", "knife_cw"])
def test_spline_is_the_nurbs_data_and_ezdxf_evaluates_it_on_the_exact_offset(drawings, name):
    design, path, _ = drawings[name]
    doc = ezdxf.readfile(path)
    splines = doc.modelspace().query('SPLINE[layer=="PROFILE"]')
    assert len(splines) == 1
    sp = splines[0]
    c = design.profile_ccw()
    assert sp.dxf.degree == c.degree == (9 if design.spec.is_roller else 5)
    assert np.array_equal(np.array(sp.knots), c.knots)
    cps = np.array(sp.control_points)
    assert np.array_equal(cps[:, :2], c.poles) and np.all(cps[:, 2] == 0)
    if c.is_rational:
        assert np.array_equal(np.array(sp.weights), c.weights)
    else:
        assert len(sp.weights) == 0
    assert sp.closed == design.spec.drawing.spline_closed_flag
    assert np.array_equal(cps[0], cps[-1])  # closed by its data: clamped ends meet

    # ezdxf's own evaluator, on the data as read back
    bs = ezdxf.math.BSpline(sp.control_points, order=sp.dxf.degree + 1, knots=sp.knots,
                            weights=sp.weights if len(sp.weights) else None)
    lo, hi = float(c.knots[0]), float(c.knots[-1])
    t = np.linspace(lo, hi, 6001)
    pts = np.array([(v.x, v.y) for v in bs.points(t)])
    ez = pts[:, 0] + 1j * pts[:, 1]
    exact = _exact_profile_points(design, t)
    size = np.max(np.abs(exact))
    assert np.max(np.abs(ez - exact)) <= 1e-9 * size
    # and the area it encloses (shoelace on 6001 points) is the design's
    assert 0.5 * np.sum((np.conj(ez[:-1]) * ez[1:]).imag) == pytest.approx(design.profile_area, rel=1e-5)


def test_pitch_spline_is_degree_5_polynomial(drawings):
    design, path, _ = drawings["spline"]
    sp = ezdxf.readfile(path).modelspace().query('SPLINE[layer=="PITCH"]')[0]
    assert sp.dxf.degree == 5 and len(sp.weights) == 0
    bs = ezdxf.math.BSpline(sp.control_points, order=6, knots=sp.knots)
    t = np.linspace(0, design.pitch.M, 2001)
    pts = np.array([(v.x, v.y) for v in bs.points(t)])
    z = pts[:, 0] + 1j * pts[:, 1]
    # every point is on the pitch curve: at the prime-circle radius or beyond, and the
    # follower sits on it at the cam angle given by the point (s_actual − s is tiny)
    th = np.deg2rad(design.pitch.cam_angle_of_point(z))
    s_design = design.program.s(th)
    r_expected = np.abs(design.geometry.pitch_points(th, s_design))
    assert np.max(np.abs(np.abs(z) - r_expected)) <= 1.01 * design.max_deviation[0]


def _two_sided(a, b):
    """Largest distance between two dense point chains (complex), each against the other's chords."""
    from .librecad import distance_to_segments

    return max(float(np.max(distance_to_segments(a, [b]))), float(np.max(distance_to_segments(b, [a]))))


@pytest.mark.parametrize("name", ["cubic", "cubic_knife", "cubic_inch"])
def test_cubic_spline_is_within_tolerance_of_the_exact_profile(drawings, name):
    """The default: PROFILE and PITCH are polynomial cubic SPLINEs (no weights, degree 3) that
    ezdxf's own evaluator puts within chord_tolerance of the exact curves — the profile computed
    from the PH spline and the offset definition — at the distance report.json states."""
    design, path, info = drawings[name]
    tol = design.spec.drawing.chord_tolerance
    msp = ezdxf.readfile(path).modelspace()
    (sp,) = msp.query('SPLINE[layer=="PROFILE"]')
    assert sp.dxf.degree == 3 and len(sp.weights) == 0 and not sp.dxf.flags & sp.RATIONAL
    cps = np.array(sp.control_points)
    assert np.array_equal(cps[0], cps[-1]) and len(cps) == info.profile.poles == info.summary()["profile_poles"]
    bs = ezdxf.math.BSpline(sp.control_points, order=4, knots=sp.knots)
    drawn = np.array([(v.x, v.y) for v in bs.points(np.linspace(sp.knots[0], sp.knots[-1], 40001))])
    drawn = drawn[:, 0] + 1j * drawn[:, 1]
    exact = _exact_profile_points(design, np.linspace(0, design.pitch.M, 40001))
    err = _two_sided(drawn, exact)
    assert err <= tol
    d = info.summary()
    assert d["profile_max_error"] == pytest.approx(err, rel=1e-3, abs=1e-6 * tol)
    assert d["curves"] == "cubic" and d["chord_tolerance"] == tol and d["exact"] is False
    # the pitch curve alike, against the PH curve's own points
    (pp,) = msp.query('SPLINE[layer=="PITCH"]')
    assert pp.dxf.degree == 3 and len(pp.weights) == 0
    bp = ezdxf.math.BSpline(pp.control_points, order=4, knots=pp.knots)
    dp = np.array([(v.x, v.y) for v in bp.points(np.linspace(pp.knots[0], pp.knots[-1], 40001))])
    u = np.linspace(0, design.pitch.M, 40001)
    seg = np.minimum(np.floor(u).astype(int), design.pitch.M - 1)
    ph = design.pitch.spline.point(seg, u - seg)
    err_p = _two_sided(dp[:, 0] + 1j * dp[:, 1], ph)
    assert err_p <= tol and d["pitch_max_error"] == pytest.approx(err_p, rel=1e-3, abs=1e-6 * tol)
    assert d["max_error_by_layer"] == {"PROFILE": d["profile_max_error"], "PITCH": d["pitch_max_error"]}


@pytest.mark.parametrize("tol", [1e-2, 1e-5])
def test_cubic_tolerance_is_honoured_at_other_values(tmp_path, tol):
    design = design_cam(default_spec().replace(**{"drawing.chord_tolerance": tol}))
    info = export_dxf(design, tmp_path / "c.dxf")
    (sp,) = ezdxf.readfile(tmp_path / "c.dxf").modelspace().query('SPLINE[layer=="PROFILE"]')
    bs = ezdxf.math.BSpline(sp.control_points, order=4, knots=sp.knots)
    drawn = np.array([(v.x, v.y) for v in bs.points(np.linspace(sp.knots[0], sp.knots[-1], 40001))])
    err = _two_sided(drawn[:, 0] + 1j * drawn[:, 1], _exact_profile_points(design, np.linspace(0, design.pitch.M, 40001)))
    assert err <= tol and info.profile.max_error == pytest.approx(err, rel=1e-3, abs=1e-6 * tol)
    if tol < 1e-4:   # a tight tolerance takes more poles than the coarsest fit (3 per PH segment + 1)
        assert len(sp.control_points) > 3 * design.pitch.M + 1


@pytest.mark.parametrize("name", ["arcs", "polyline", "arcs_r12", "polyline_r12", "inch"])
def test_arcs_and_polyline_within_chord_tolerance(drawings, name):
    design, path, info = drawings[name]
    if name == "inch":  # the inch variant is a spline file: approximate it here
        design = design_cam(design.spec.replace(**{"drawing.curves": "arcs"}))
        path = path.with_name("inch_arcs.dxf")
        info = export_dxf(design, path)
    tol = design.spec.drawing.chord_tolerance
    back = read_profile_path(path)
    exact = design.profile_ccw()
    err = max_distance(back, exact)
    assert err <= tol
    assert info.profile.max_error == pytest.approx(err, rel=1e-3, abs=1e-3 * tol)
    assert err > tol / 20  # a real approximation, not a trivially dense one
    # closed chain: every end point meets another element's end point
    ends = np.concatenate([back.start, back.end])
    d = np.abs(ends[:, None] - ends[None, :]) + np.eye(len(ends)) * 1e9
    assert np.max(np.min(d, axis=1)) < 1e-9 * np.max(np.abs(ends))
    doc = ezdxf.readfile(path)
    assert len(doc.modelspace().query("SPLINE")) == 0  # nothing a spline-less machine cannot read
    if info.curves == "arcs":
        assert len(doc.modelspace().query('ARC[layer=="PROFILE"]')) == info.profile.arcs > 0
    else:
        kind = "POLYLINE" if "r12" in name else "LWPOLYLINE"
        assert len(doc.modelspace().query(f'{kind}[layer=="PROFILE"]')) == 1


@pytest.mark.parametrize("tol", [1e-2, 1e-4])
def test_tolerance_is_honoured_at_other_values(tmp_path, tol):
    for curves in ("arcs", "polyline"):
        design = design_cam(default_spec().replace(**{"drawing.curves": curves, "drawing.chord_tolerance": tol}))
        export_dxf(design, tmp_path / "c.dxf")
        assert max_distance(read_profile_path(tmp_path / "c.dxf"), design.profile_ccw()) <= tol


def test_units_header(drawings):
    assert ezdxf.readfile(drawings["cubic"][1]).header["$INSUNITS"] == 4    # mm
    assert ezdxf.readfile(drawings["inch"][1]).header["$INSUNITS"] == 1     # inch
    assert drawings["arcs_r12"][2].insunits is None                         # R12 has no $INSUNITS
    assert ezdxf.readfile(drawings["arcs_r12"][1]).dxfversion == "AC1009"


@pytest.mark.parametrize("name", ["cubic", "inch", "arcs_r12"])
def test_dimensions_measure_the_cam(drawings, name):
    design, path, _ = drawings[name]
    dims = ezdxf.readfile(path).modelspace().query('DIMENSION[layer=="DIMENSIONS"]')
    got = sorted((d.dimtype, round(d.get_measurement(), 9)) for d in dims)
    spec = design.spec
    r_max = design.max_profile_radius()[0]
    expected = sorted([(3, round(spec.cam.bore_diameter, 9)),
                       (4, round(spec.cam.base_radius - spec.roller_radius, 9)),
                       (4, round(r_max, 9))])
    assert got == expected
    # the largest radius is what a dense sample of the exact profile gives
    _, pts = design.profile.sample(400)
    assert r_max == pytest.approx(np.max(np.hypot(pts[:, 0], pts[:, 1])), rel=1e-9)
    texts = " ".join(t.dxf.text for t in ezdxf.readfile(path).modelspace().query('TEXT[layer=="DIMENSIONS"]'))
    assert "THICKNESS" in texts and f"{spec.cam.thickness:g}" in texts
    # readers that draw DIMENSION entities themselves (LibreCAD) read the style's table entry and
    # the header, not ezdxf's per-entity overrides: both hold the drawing's text height, scale 1
    doc = ezdxf.readfile(path)
    h = doc.header["$DIMTXT"]
    assert h == pytest.approx(drawings[name][2].text_height) and doc.header["$DIMLFAC"] == 1.0
    assert doc.header["$DIMSTYLE"] == "CAM" and all(d.dxf.dimstyle == "CAM" for d in dims)
    style = doc.dimstyles.get("CAM")
    assert style.dxf.dimtxt == style.dxf.dimasz == h and style.dxf.dimlfac == 1.0


def test_title_block_has_parameters_and_motion_table(tmp_path):
    spec = default_spec().replace(**{"drawing.part_number": "CW-0042", "drawing.author": "A. Fitter",
                                     "drawing.material": "AISI 1045, 50 HRC", "drawing.title": "Feed cam"})
    design = design_cam(spec)
    export_dxf(design, tmp_path / "t.dxf")
    texts = [t.dxf.text for t in ezdxf.readfile(tmp_path / "t.dxf").modelspace().query('TEXT[layer=="TITLE"]')]
    joined = "\n".join(texts)
    for word in ("FEED CAM (PLATE CAM)", "CW-0042", "A. Fitter", "AISI 1045, 50 HRC", "MOTION PROGRAM",
                 "RATIONAL B-SPLINE, DEGREE 9", "EXACT OFFSET OF THE PH PITCH CURVE", "POLYNOMIAL CUBIC SPLINE"):
        assert word in joined
    assert texts.count("CYCLOIDAL") == 2 and texts.count("DWELL") == 3
    assert "RISE" in texts and "RETURN" in texts and "330" in texts


#: each body's name, the title of a drawing whose spec gives none
BODY_TITLES = {"plate": "PLATE CAM", "groove": "GROOVE CAM", "conjugate": "CONJUGATE CAM PAIR",
               "cylindrical": "CYLINDRICAL CAM", "parallel_indexer": "PARALLEL INDEXER", "barrel_indexer": "BARREL INDEXER",
               "globoidal_indexer": "GLOBOIDAL INDEXER"}


def _title_block_rows(msp):
    """(title, {label: value}) of a title block: its largest TEXT, the rest paired by baseline."""
    texts = list(msp.query('TEXT[layer=="TITLE"]'))
    title = max(texts, key=lambda t: t.dxf.height)
    rows: dict[float, list] = {}
    for t in texts:
        if t is not title:
            rows.setdefault(round(t.dxf.insert.y, 6), []).append((t.dxf.insert.x, t.dxf.text))
    return title.dxf.text, {sorted(c)[0][1]: sorted(c)[1][1] for c in rows.values() if len(c) == 2}


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_every_example_is_titled_by_its_body_and_its_texts_fit_their_cells(name, tmp_path):
    """The title is the body's name (``cam.body``); every TEXT of the title block lies inside the
    rectangle of the title block's lines round its insertion point, measured by ezdxf's font
    metrics and by the exporter's width bound (LibreCAD's drawing of them: test_dxf_librecad.py);
    a conjugate pair's rows say which cam each is."""
    from ezdxf import bbox

    from cam_workbench.pipeline import drawing_stage
    from cam_workbench.exporters.dxf import text_width

    from .librecad import title_cells

    spec = example_spec(name)
    design = design_cam(spec)
    doc, _ = drawing_stage(design, design.summary())
    doc.saveas(tmp_path / "d.dxf")
    doc = ezdxf.readfile(tmp_path / "d.dxf")
    msp = doc.modelspace()
    title, rows = _title_block_rows(msp)
    assert title == BODY_TITLES[spec.cam.body]
    texts = {t.dxf.handle: t for t in msp.query('TEXT[layer=="TITLE"]')}
    cells = title_cells(doc)
    assert set(cells) == set(texts)
    for handle, (text, (x0, y0, x1, y1)) in cells.items():
        t = texts[handle]
        box = bbox.extents([t], fast=False)
        assert x0 < box.extmin.x and box.extmax.x < x1 and y0 < box.extmin.y and box.extmax.y < y1, (text, box)
        assert t.dxf.insert.x + text_width(text, t.dxf.height) < x1, text
    if spec.cam.body == "conjugate":
        assert rows["PROFILE"].startswith("FIRST CAM: ") and rows["SECOND CAM PROFILE"].startswith("EXACT OFFSET")
    # a title of the user's own keeps the body's name beside it, unless it says it
    for given, shown in (("Feed cam", f"FEED CAM ({BODY_TITLES[spec.cam.body]})"),
                         (BODY_TITLES[spec.cam.body].lower(), BODY_TITLES[spec.cam.body])):
        titled = design_cam(spec.replace(**{"drawing.title": given}))
        doc, _ = drawing_stage(titled, titled.summary())
        assert _title_block_rows(doc.modelspace())[0] == shown


def test_no_title_block_no_dimensions(tmp_path):
    design = design_cam(default_spec().replace(**{"drawing.title_block": False, "drawing.dimensions": False}))
    export_dxf(design, tmp_path / "b.dxf")
    msp = ezdxf.readfile(tmp_path / "b.dxf").modelspace()
    assert len(msp.query('*[layer=="TITLE"]')) == 0 and len(msp.query("DIMENSION")) == 0


@requires_ocp
@pytest.mark.parametrize("name", ["cubic", "spline", "arcs", "polyline", "inch", "knife_cw"])
def test_cadquery_import_gives_the_solids_cross_section(drawings, name):
    """CadQuery's importDXF(PROFILE) and (BORE) give faces whose area difference is the OCCT
    solid's cross-section (spline: to 1e-9, using OCCT's curve evaluator in a Gauss rule per
    knot span; cubic/arcs/polyline: within the measured distance × perimeter)."""
    import cadquery as cq

    from cam_workbench.kernel import solids as occ_build

    design, path, info = drawings[name]
    faces = cq.importers.importDXF(str(path), include=["PROFILE"]).vals()
    assert len(faces) == 1
    face = faces[0]
    assert face.isValid()
    solid = occ_build.cam_solid(design)
    section = occ_build.face_area(occ_build.planar_face_at(solid, design.spec.cam.thickness))
    r_bore = design.spec.cam.bore_diameter / 2
    if r_bore > 0:
        bore = cq.importers.importDXF(str(path), include=["BORE"]).vals()
        assert len(bore) == 1 and bore[0].Area() == pytest.approx(math.pi * r_bore**2, rel=1e-12)
    perimeter = design.pitch.spline.arc_length + 2 * math.pi * design.spec.roller_radius
    if info.curves == "spline":
        area = _occt_green_area(face)
        assert area - math.pi * r_bore**2 == pytest.approx(section, rel=1e-9)
        assert area == pytest.approx(design.profile_area, rel=1e-9)
        # OCCT's own face area on one 60-span degree-9 edge is only good to ~1e-4 (measured)
        assert face.Area() == pytest.approx(area, rel=1e-3)
    elif info.curves == "cubic":   # a many-span edge too: Green's theorem with OCCT's evaluator
        assert abs(_occt_green_area(face) - math.pi * r_bore**2 - section) <= info.profile.max_error * perimeter
    else:
        assert abs(face.Area() - math.pi * r_bore**2 - section) <= info.profile.max_error * perimeter


def _occt_green_area(face):
    """½∮(x dy − y dx) over the face's outer wire with OCCT's curve evaluator (D1), 24 Gauss
    points per knot span — exact for these spans to rounding."""
    from cam_workbench.kernel import ocp as occ

    xg, wg = np.polynomial.legendre.leggauss(24)
    total = 0.0
    ex = occ.TopExp_Explorer(face.outerWire().wrapped, occ.TopAbs_EDGE)
    while ex.More():
        c = occ.BRepAdaptor_Curve(occ.topods_edge(ex.Current()))
        if c.GetType() == occ.GeomAbs_BSplineCurve:
            bs = c.BSpline()
            knots = np.array([bs.Knot(i) for i in range(1, bs.NbKnots() + 1)])
        else:
            knots = np.linspace(c.FirstParameter(), c.LastParameter(), 2)
        for a, b in zip(knots[:-1], knots[1:]):
            for x, w in zip(xg, wg):
                t = 0.5 * (b - a) * (x + 1) + a
                p, v = occ.gp_Pnt(), occ.gp_Vec()
                c.D1(t, p, v)
                total += 0.25 * (b - a) * w * (p.X() * v.Y() - p.Y() * v.X())
        ex.Next()
    return abs(total)


@pytest.mark.parametrize("name", ["cubic", "spline", "arcs"])
def test_render_png_with_ezdxf_drawing_addon(drawings, artifacts, name):
    """Render the drawing as a person would see it in a DXF viewer; left in test-artifacts/."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from ezdxf.addons.drawing import Frontend, RenderContext
    from ezdxf.addons.drawing.matplotlib import MatplotlibBackend

    _, path, _ = drawings[name]
    doc = ezdxf.readfile(path)
    fig = plt.figure(figsize=(16, 10))
    ax = fig.add_axes([0, 0, 1, 1])
    Frontend(RenderContext(doc), MatplotlibBackend(ax)).draw_layout(doc.modelspace(), finalize=True)
    fig.set_size_inches(16, 10)  # the backend resizes the figure to the drawing's aspect
    out = artifacts / f"dxf_{name}.png"
    fig.savefig(out, dpi=120, facecolor="black")
    plt.close(fig)
    img = plt.imread(out)
    assert img.shape[1] > 1500 and img.shape[0] > 500
    assert img[..., :3].std() > 0.05  # not a blank page


# ---- spec rules of [drawing] -------------------------------------------------------------
def _with_drawing(**kw):
    d = {k: v for k, v in DEFAULT_SPEC_DICT.items()}
    d["drawing"] = kw
    return d


DRAWING_RULES = [
    ({"curves": "nurbs"}, "drawing.curves", "must be one of"),
    ({"chord_tolerance": 0.0}, "drawing.chord_tolerance", "must be > 0"),
    ({"chord_tolerance": "fine"}, "drawing.chord_tolerance", "must be a number"),
    ({"dxf_version": "R14"}, "drawing.dxf_version", "must be one of"),
    ({"dxf_version": "R12"}, "drawing.dxf_version", "R12 has no SPLINE entity"),
    ({"dxf_version": "R12", "curves": "spline"}, "drawing.dxf_version", "R12 has no SPLINE entity"),
    ({"dxf_version": "R12", "curves": "cubic"}, "drawing.dxf_version", "R12 has no SPLINE entity"),
    ({"title": 7}, "drawing.title", "must be a string"),
    ({"text_height": -1.0}, "drawing.text_height", "must be > 0"),
    ({"title_block": "yes"}, "drawing.title_block", "must be true or false"),
    ({"spline_closed_flag": 1}, "drawing.spline_closed_flag", "must be true or false"),
    ({"author": 7}, "drawing.author", "must be a string"),
    ({"colour": "red"}, "drawing.colour", "unknown field"),
]


@pytest.mark.parametrize("changes,field,words", DRAWING_RULES, ids=[r[1] + ":" + r[2] for r in DRAWING_RULES])
def test_drawing_rules(changes, field, words):
    with pytest.raises(SpecError) as info:
        CamSpec.from_dict(_with_drawing(**changes))
    assert info.value.field == field and words in str(info.value)


def test_drawing_defaults_and_r12_with_arcs_is_fine():
    spec = CamSpec.from_dict(_with_drawing(dxf_version="R12", curves="polyline"))
    assert spec.drawing.curves == "polyline"
    d = default_spec().drawing
    assert (d.curves, d.chord_tolerance, d.dxf_version, d.spline_closed_flag) == ("cubic", 0.001, "R2010", False)
    assert d.title is None   # the body's name


# ---- CLI -------------------------------------------------------------------------------------
CLI = [sys.executable, "-m", "cam_workbench.cli"]


def run(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([*CLI, *args], capture_output=True, text=True, env=env)


def test_cli_dxf_arcs_to_file(tmp_path):
    target = tmp_path / "shop" / "part.dxf"
    res = run("dxf", "--curves", "arcs", "--tolerance", "0.005", "-o", str(target))
    assert res.returncode == 0, res.stderr
    assert "arcs" in res.stdout and "tolerance 0.005 mm" in res.stdout
    assert sorted(p.name for p in target.parent.iterdir()) == ["part.dxf"]
    design = design_cam(default_spec())
    assert max_distance(read_profile_path(target), design.profile_ccw()) <= 0.005


def test_cli_dxf_default_folder(tmp_path):
    res = run("dxf", "-o", str(tmp_path / "o"))
    assert res.returncode == 0, res.stderr
    doc = ezdxf.readfile(tmp_path / "o" / "cam.dxf")
    assert not doc.audit().has_errors
    (sp,) = doc.modelspace().query('SPLINE[layer=="PROFILE"]')
    design = design_cam(default_spec())
    info = export_dxf(design, tmp_path / "again.dxf")
    # the line says what the file holds, with the measured distance report.json states
    assert (f"PROFILE: polynomial cubic SPLINE of {len(sp.control_points)} poles, max distance "
            f"{info.profile.max_error:.3g} mm from the profile NURBS (the exact rational offset of the PH pitch "
            f"curve (NURBS degree 9, rational)) (tolerance 0.001 mm, R2010); PITCH drawn alike, within "
            f"{info.pitch.max_error:.3g} mm of theirs") in res.stdout


def test_cli_dxf_exact_spline_on_request(tmp_path):
    res = run("dxf", "--curves", "spline", "-o", str(tmp_path / "e.dxf"))
    assert res.returncode == 0, res.stderr
    assert "PROFILE: SPLINE = the exact rational offset of the PH pitch curve (NURBS degree 9, rational)" in res.stdout
    (sp,) = ezdxf.readfile(tmp_path / "e.dxf").modelspace().query('SPLINE[layer=="PROFILE"]')
    assert sp.dxf.degree == 9 and len(sp.weights) > 0


@pytest.mark.parametrize("args,message", [
    (["--dxf-version", "R12"], "drawing.dxf_version: R12 has no SPLINE entity"),
    (["--tolerance", "-1", "--curves", "arcs"], "drawing.chord_tolerance: must be > 0"),
    (["--set", "motion[4].angle=20"], "motion[4].angle: spans sum to 350°"),
])
def test_cli_dxf_bad_input_writes_nothing(tmp_path, args, message):
    res = run("dxf", *args, "-o", str(tmp_path / "o"))
    assert res.returncode == 2 and message in res.stderr and "Traceback" not in res.stderr
    assert not (tmp_path / "o").exists()


def test_cli_dxf_help_reads_declarations():
    res = run("dxf", "--help")
    assert res.returncode == 0
    assert "{cubic,spline,arcs,polyline}" in res.stdout and "chord" in res.stdout


FREECADCMD = __import__("shutil").which("freecadcmd")

FREECAD_READ = """
import json, FreeCAD, Import
doc = FreeCAD.newDocument("d")
Import.readDXF({path!r})
doc.recompute()
out = []
for o in doc.Objects:
    sh = getattr(o, "Shape", None)
    if sh is None or sh.isNull():
        continue
    for e in sh.Edges:
        c = e.Curve
        if c.TypeId == "Part::GeomBSplineCurve":
            out.append(dict(degree=c.Degree, poles=c.NbPoles, rational=c.isRational(),
                            closed=e.isClosed(), length=e.Length,
                            points=[(p.x, p.y) for p in e.discretize(Distance=0.05)]))
print("RESULT" + json.dumps(out))
"""


@pytest.mark.skipif(FREECADCMD is None, reason="freecadcmd (Debian freecad-python3) is not installed")
@pytest.mark.parametrize("name", ["spline", "spline_closed_flag"])
def test_freecad_dxf_importer_reads_the_exact_splines(drawings, tmp_path, name):
    """FreeCAD's own DXF importer (a real CAD reader, OCCT 7.6) gets the degree-9 rational profile
    and the degree-5 pitch curve, closed, in mm ($INSUNITS), with the lengths the PH curve gives
    exactly: pitch = its arc length, profile = arc length − 2π·roller radius (inward offset of
    a closed convex-turning curve)."""
    design, path, _ = drawings[name]
    script = tmp_path / "read.py"
    script.write_text(FREECAD_READ.format(path=str(path)))
    res = subprocess.run([FREECADCMD, str(script)], capture_output=True, text=True, timeout=SAFETY_S)
    line = next((x for x in res.stdout.splitlines() if x.startswith("RESULT")), None)
    assert line, res.stdout[-2000:] + res.stderr[-2000:]
    curves = sorted(json.loads(line[6:]), key=lambda c: c["degree"])
    assert [(c["degree"], c["rational"], c["closed"]) for c in curves] == [(5, False, True), (9, True, True)]
    assert curves[1]["poles"] == design.profile.n_poles and curves[0]["poles"] == design.pitch_nurbs.n_poles
    arc = design.pitch.spline.arc_length
    assert curves[0]["length"] == pytest.approx(arc, rel=1e-9)
    assert curves[1]["length"] == pytest.approx(arc - 2 * math.pi * design.spec.roller_radius, rel=1e-9)


@pytest.mark.skipif(FREECADCMD is None, reason="freecadcmd (Debian freecad-python3) is not installed")
def test_freecad_dxf_importer_reads_the_cubic_splines(drawings, tmp_path):
    """FreeCAD's DXF importer reads the default drawing's profile and pitch curve as closed
    polynomial cubics with the file's poles, and the points FreeCAD puts on them (its own
    discretisation, every 0.05 mm) lie within report.json's distance of the exact curves: the
    profile from the PH spline and the offset definition, the pitch curve the PH spline's points."""
    design, path, info = drawings["cubic"]
    script = tmp_path / "read.py"
    script.write_text(FREECAD_READ.format(path=str(path)))
    res = subprocess.run([FREECADCMD, str(script)], capture_output=True, text=True, timeout=300)
    line = next((x for x in res.stdout.splitlines() if x.startswith("RESULT")), None)
    assert line, res.stdout[-2000:] + res.stderr[-2000:]
    curves = json.loads(line[6:])
    assert [(c["degree"], c["rational"], c["closed"]) for c in curves] == [(3, False, True)] * 2
    assert sorted(c["poles"] for c in curves) == sorted([info.profile.poles, info.pitch.poles])
    t = np.linspace(0, design.pitch.M, 40001)
    seg = np.minimum(np.floor(t).astype(int), design.pitch.M - 1)
    exact = {"PROFILE": _exact_profile_points(design, t), "PITCH": design.pitch.spline.point(seg, t - seg)}
    from .librecad import distance_to_segments

    for c in curves:
        z = np.array(c["points"]) @ np.array([1, 1j])
        # which curve: the one FreeCAD's points lie on
        layer = min(exact, key=lambda k: float(np.median(distance_to_segments(z, [exact[k]]))))
        stated = info.profile.max_error if layer == "PROFILE" else info.pitch.max_error
        assert float(np.max(distance_to_segments(z, [exact[layer]]))) <= stated * 1.001 + 1e-9, layer


def test_cam_export_dxf(tmp_path):
    from cam_workbench import Cam

    cam = Cam(**{"drawing.curves": "arcs"})
    path = cam.export_dxf(tmp_path / "c.dxf")
    assert max_distance(read_profile_path(path), cam.design.profile_ccw()) <= cam.spec.drawing.chord_tolerance

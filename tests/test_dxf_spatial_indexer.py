"""The spatial indexers' drawing (exporters.dxf_spatial_indexer) written, read back with ezdxf and held to
geometry computed here from the documented conventions (generators/bodies/indexing/spatial.py's
docstring): ψ from the law, roller 0's axis c(t) = a + t·d at input angle τ (barrel: a = P + R_p·u(α),
d = +y), seen in the cam frame as Rz(−τ)·c; the meshing normal n ⟂ d and ⟂ the axis point's velocity
relative to the cam (central differences in τ), the side by n·τ(α); the contact point c + r_r·n and its
(ρ, φ, z).  The trace at a radius is found here by bracketing ρ(t) = radius on a grid of t (the
largest crossing) and bisecting, per τ.  The SPLINEs are evaluated by ezdxf's own B-spline evaluator."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

ezdxf = pytest.importorskip("ezdxf")
from ezdxf import recover  # noqa: E402

from cam_workbench.exporters.dxf_spatial_indexer import spatial_drawing, write_spatial_dxf  # noqa: E402
from cam_workbench.generators.bodies.indexing.spatial import (BarrelIndexer, GloboidalIndexer,  # noqa: E402
                                                             design_barrel, design_globoidal)
from cam_workbench.generators.bodies.indexing.spatial_surfaces import flank_surfaces  # noqa: E402
from cam_workbench.generators.motion.laws import evaluate_law  # noqa: E402

CASES = {"barrel": (design_barrel, BarrelIndexer), "globoidal": (design_globoidal, GloboidalIndexer)}


def _drawn(name, tmp_path_factory):
    make, kind = CASES[name]
    d = make(kind())
    surfaces = flank_surfaces(d)
    path = tmp_path_factory.mktemp("dxf_spatial") / f"{name}.dxf"
    info = write_spatial_dxf(d, surfaces, path, title="TEST SPATIAL INDEXER")
    return d, surfaces, info, path, ezdxf.readfile(str(path))


@pytest.fixture(scope="module", params=sorted(CASES))
def drawn(request, tmp_path_factory):
    return _drawn(request.param, tmp_path_factory)


@pytest.fixture(scope="module")
def barrel(tmp_path_factory):
    return _drawn("barrel", tmp_path_factory)


@pytest.fixture(scope="module")
def globoid(tmp_path_factory):
    return _drawn("globoidal", tmp_path_factory)


# ---- the conventions, recomputed -----------------------------------------------------------------
def law_psi(ix, theta):
    t_st = 2 * math.pi / ix.stations
    rel = np.asarray(theta, dtype=float) - ix.index_start
    turns = np.floor(rel / (2 * math.pi))
    f, _, _, _ = evaluate_law(ix.law, np.clip((rel - 2 * math.pi * turns) / ix.index_angle, 0, 1))
    return t_st * (turns + f)


def alpha(ix, j, theta):
    return math.pi + 2 * math.pi / ix.stations * (np.asarray(j, dtype=float) - 0.5) + law_psi(ix, theta)


def rz_minus(theta, v):
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([c * v[..., 0] + s * v[..., 1], -s * v[..., 0] + c * v[..., 1], v[..., 2]], -1)


def barrel_axis_cam(ix, tau, t):
    """Roller 0's axis point at input angle τ and height t in the cam frame, (..., 3)."""
    al = alpha(ix, 0, tau)
    a = np.stack([ix.centre_distance + ix.pitch_radius * np.cos(al), t + 0 * al, ix.pitch_radius * np.sin(al)], -1)
    return rz_minus(tau, a)


def contact(ix, side, tau, t, h=1e-5):
    """The exact contact point (cam frame) of roller 0's side ``side`` at (τ, t) (broadcast)."""
    tau, t = np.broadcast_arrays(np.asarray(tau, dtype=float), np.asarray(t, dtype=float))
    w = (barrel_axis_cam(ix, tau + h, t) - barrel_axis_cam(ix, tau - h, t)) / (2 * h)
    d = rz_minus(tau, np.broadcast_to([0.0, 1.0, 0.0], tau.shape + (3,)))
    m = np.cross(d, w)
    n = m / np.linalg.norm(m, axis=-1, keepdims=True)
    al = alpha(ix, 0, tau)
    tang = rz_minus(tau, np.stack([-np.sin(al), 0 * al, np.cos(al)], -1))
    n = n * (side * np.sign(np.einsum("...i,...i->...", n, tang)))[..., None]
    return barrel_axis_cam(ix, tau, t) + ix.roller_radius * n


def exact_trace(ix, side, radius, tau):
    """(φ, z) of side ``side``'s contact with ρ = radius at each τ: t the largest root of ρ(t) = radius
    (grid bracket, then bisection)."""
    tg = np.arange(0.25, ix.roller_end + 1e-9, 0.5)
    rho = np.hypot(*contact(ix, side, tau[:, None], tg[None, :])[..., :2].transpose(2, 0, 1)) - radius
    up = (rho[:, :-1] < 0) & (rho[:, 1:] >= 0)
    assert up.any(axis=1).all()
    k = up.shape[1] - 1 - np.argmax(up[:, ::-1], axis=1)
    lo, hi = tg[k], tg[k + 1]
    for _ in range(55):
        mid = 0.5 * (lo + hi)
        below = np.hypot(*contact(ix, side, tau, mid)[..., :2].T) < radius
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    q = contact(ix, side, tau, 0.5 * (lo + hi))
    return np.arctan2(q[:, 1], q[:, 0]), q[:, 2]


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


def quoted(rows, label):
    m = re.fullmatch(r"(?:BI)?CUBIC B?-?SPLINES? (?:SURFACES )?WITHIN ([0-9.eE+-]+) mm OF THE EXACT ENVELOPE "
                     r"\(MEASURED\)", rows[label])
    assert m, rows[label]
    return float(m.group(1))


def rectangles(msp, layer):
    return [np.array([tuple(v)[:2] for v in e.get_points("xy")]) for e in msp.query(f'LWPOLYLINE[layer=="{layer}"]')]


def same_rectangle(pts, corners):
    return pts.shape == (4, 2) and np.abs(np.sort(pts, axis=0) - np.sort(np.asarray(corners), axis=0)).max() < 1e-9


# ---- the file ------------------------------------------------------------------------------------
def test_the_file_reads_back_clean_in_mm(drawn):
    d, surfaces, info, path, doc = drawn
    auditor = doc.audit()
    assert not auditor.has_errors, [str(e.message) for e in auditor.errors]
    _, rec = recover.readfile(str(path))
    assert not rec.has_errors, [str(e.message) for e in rec.errors]
    assert doc.header["$INSUNITS"] == 4
    names = {layer.dxf.name for layer in doc.layers}
    assert set(info.layers) <= names
    msp = doc.modelspace()
    splines = msp.query("SPLINE")
    assert len(splines) == len(info.traces)
    if info.kind == "barrel":
        assert len(splines) >= 4
        for where in ("TOP", "ROOT"):
            for s in ("P", "M"):
                assert msp.query(f'SPLINE[layer=="TRACE_{where}_{s}"]')
    else:
        assert len(splines) == 0 and math.isnan(info.phi_mid)


def test_the_title_block_quotes_the_design(drawn):
    d, surfaces, info, path, doc = drawn
    ix, s = d.indexer, d.summary()
    rows = title_rows(doc)
    assert rows == dict(info.rows)
    assert "TEST SPATIAL INDEXER" in [t.dxf.text for t in doc.modelspace().query('TEXT[layer=="TITLE"]')]

    def num(label, unit=""):
        m = re.fullmatch(rf"([-0-9.e+]+) ?{unit}.*", rows[label])
        assert m, rows[label]
        return float(m.group(1))

    barrel = isinstance(ix, BarrelIndexer)
    assert rows["TYPE"] == ("BARREL INDEXER" if barrel else "GLOBOIDAL INDEXER")
    assert int(rows["STATIONS N"]) == s["stations"]
    assert num("INDEX ANGLE BETA", "°") == pytest.approx(s["index_angle_deg"], rel=5e-6)
    assert rows["MOTION LAW"].lower() == s["law"]
    assert num("CENTRE DISTANCE C", "mm") == pytest.approx(s["centre_distance"], rel=5e-6)
    assert num("ROLLER RADIUS r_r", "mm") == pytest.approx(s["roller_radius"], rel=5e-6)
    assert num("CAM WIDTH W", "mm") == pytest.approx(s["cam_width"], rel=5e-6)
    m = re.fullmatch(r"([0-9.]+) mm, t = ([0-9.]+) TO ([0-9.]+) mm", rows["ROLLER LENGTH"])
    assert [float(v) for v in m.groups()] == pytest.approx(
        [s["roller_end"] - s["roller_start"], s["roller_start"], s["roller_end"]], rel=5e-6)
    if barrel:
        assert num("TURRET PITCH RADIUS R_p", "mm") == pytest.approx(s["pitch_radius"], rel=5e-6)
        m = re.fullmatch(r"ROOT ([0-9.]+) mm, TOP ([0-9.]+) mm", rows["RIB RADII"])
        assert [float(v) for v in m.groups()] == pytest.approx([s["root_radius"], s["outer_radius"]], rel=5e-6)
    else:
        assert "TURRET PITCH RADIUS R_p" not in rows
        m = re.fullmatch(r"TIP GLOBOID ([0-9.]+) mm, ROOT GLOBOID ([0-9.]+) mm", rows["RIB RADII"])
        assert [float(v) for v in m.groups()] == pytest.approx([s["tip_radius"], s["root_radius"]], rel=5e-6)
    for label, key, unit in (("MAX DRIVING PRESSURE ANGLE", "max_driving_pressure_angle", "deg"),
                             ("MIN REGULARITY MARGIN", "min_regularity_margin", "1"),
                             ("MIN RIB THICKNESS", "min_rib_thickness", "mm")):
        m = re.fullmatch(r"([0-9.]+)(?:°| mm)? AT ([0-9.]+)° OF INPUT", rows[label])
        assert m, rows[label]
        assert float(m.group(1)) == pytest.approx(s[key][f"value_{unit}"], abs=5.1e-5)
        assert float(m.group(2)) == pytest.approx(s[key]["at_deg"], abs=5.1e-5)
    # fitted things are quoted with their measured errors; "EXACT" names only the reference and the
    # circles, arcs and lines
    fit = max(f.max_error for f in surfaces.flanks)
    q_fit = quoted(rows, "FLANK SURFACES")
    assert fit <= q_fit <= 1.1 * fit and q_fit == info.quoted_fit_error
    if barrel:
        q_tr = quoted(rows, "FLANK TRACES")
        assert q_tr == info.quoted_trace_error and info.trace_error <= q_tr <= 1.1 * info.trace_error
    else:
        assert rows["FLANK TRACES"] == "NOT DRAWN"
    for label, value in rows.items():
        if label != "CIRCLES, ARCS, LINES":
            assert "EXACT" not in value.replace("OF THE EXACT ENVELOPE", ""), (label, value)
    assert rows["CIRCLES, ARCS, LINES"] == "EXACT"


# ---- the barrel's developed traces ---------------------------------------------------------------
def test_phi_mid_is_roller_0s_driving_contact_at_mid_index(barrel):
    d, surfaces, info, path, doc = barrel
    ix = d.indexer
    q = contact(ix, -1, np.array([ix.index_start + ix.index_angle / 2]),
                np.array([(ix.roller_start + ix.roller_end) / 2]))
    assert info.phi_mid == pytest.approx(math.atan2(q[0, 1], q[0, 0]), abs=1e-8)


def test_the_developed_windows(barrel):
    d, surfaces, info, path, doc = barrel
    ix = d.indexer
    rects = rectangles(doc.modelspace(), "OUTLINE")
    half = ix.cam_width / 2
    for name, rho in (("developed_top", ix.outer_radius), ("developed_root", ix.root_radius)):
        x0, y0 = info.views[name]
        corners = [(x0 + sx * math.pi * rho, y0 + sy * half) for sx in (-1, 1) for sy in (-1, 1)]
        assert sum(same_rectangle(r, corners) for r in rects) == 1, name


def test_the_traces_lie_within_the_quoted_error_of_the_exact_envelope(barrel):
    d, surfaces, info, path, doc = barrel
    ix = d.indexer
    q_tr = quoted(title_rows(doc), "FLANK TRACES")
    half = ix.cam_width / 2
    worst = 0.0
    msp = doc.modelspace()
    for where, rho, view in (("TOP", ix.outer_radius, "developed_top"), ("ROOT", ix.root_radius, "developed_root")):
        x0, y0 = info.views[view]
        for sign, side in (("P", 1), ("M", -1)):
            splines = msp.query(f'SPLINE[layer=="TRACE_{where}_{sign}"]')
            assert len(splines) >= 2
            for sp in splines:
                assert sp.dxf.degree == 3 and not sp.weights and not sp.closed
                bs = sp.construction_tool()          # ezdxf's evaluator (it rescales knots not starting at 0)
                u = np.linspace(0.0, bs.max_t, 1501)
                pts = np.array([(v.x, v.y) for v in bs.points(u)])
                k0, k1 = sp.knots[0], sp.knots[-1]
                tau = k0 + (k1 - k0) * u / bs.max_t  # the parameter is τ [rad]
                phi, z = exact_trace(ix, side, rho, tau)
                x = rho * (phi - info.phi_mid)
                x = x + 2 * math.pi * rho * np.round((pts[:, 0] - x0 - x) / (2 * math.pi * rho))
                dist = np.hypot(pts[:, 0] - x0 - x, pts[:, 1] - y0 - z)
                assert dist.max() <= q_tr + 1e-9, (where, side, dist.max())
                worst = max(worst, float(dist.max()))
                # inside the window: |X − x0| ≤ πρ, |z| ≤ W/2
                assert np.all(np.abs(pts[:, 0] - x0) <= math.pi * rho + 1e-6)
                assert np.all(np.abs(pts[:, 1] - y0) <= half + 1e-6)
    assert worst >= 0.5 * q_tr                       # the quoted number is the measured one


def test_trace_ends_on_end_faces_and_seams_and_pieces_join(barrel):
    d, surfaces, info, path, doc = barrel
    ix = d.indexer
    half = ix.cam_width / 2
    faces = 0
    for tr in info.traces:
        rho = tr.radius
        x0, y0 = info.views["developed_top" if rho == ix.outer_radius else "developed_root"]
        ends = tr.curve.poles[[0, -1]]                     # clamped: the curve's end points
        for e, kind in zip(ends, tr.ends):
            if kind == "end face":
                assert abs(abs(e[1]) - half) < 1e-6
                faces += 1
            elif kind == "seam":
                assert abs(abs(e[0]) - math.pi * rho) < 1e-6
        # the SPLINE in the file is the curve moved to its view
        (sp,) = [s for s in doc.modelspace().query(f'SPLINE[layer=="{tr.layer}"]')
                 if len(s.knots) == tr.curve.knots.size and np.array_equal(np.asarray(s.knots), tr.curve.knots)]
        assert np.abs(np.asarray(sp.control_points)[:, :2] - tr.curve.poles - [x0, y0]).max() < 1e-9
    assert faces >= 6
    # consecutive pieces of a trace meet (at a law's end in place, at a seam across the window)
    by = {}
    for tr in info.traces:
        by.setdefault(tr.layer, []).append(tr)
    for pieces in by.values():
        pieces.sort(key=lambda tr: tr.tau_range[0])
        for a, b in zip(pieces[:-1], pieces[1:]):
            if a.tau_range[1] != b.tau_range[0]:
                continue
            pa, pb = a.curve.poles[-1], b.curve.poles[0]
            gap = pa - pb
            gap[0] -= 2 * math.pi * a.radius * (b.turn - a.turn)
            assert np.abs(gap).max() < 1e-6, (a.layer, a.tau_range, b.tau_range)


# ---- circles, arcs, rollers, axes, dimension ------------------------------------------------------
def test_the_barrel_views(barrel):
    d, surfaces, info, path, doc = barrel
    ix = d.indexer
    msp = doc.modelspace()
    xe, ye = info.views["end"]
    circles = {(c.dxf.layer, c.dxf.center.x, c.dxf.center.y, c.dxf.radius) for c in msp.query("CIRCLE")}
    assert circles == {("OUTLINE", xe, ye, ix.outer_radius), ("ROOT", xe, ye, ix.root_radius)}
    # the rollers near the cam at θ = 0: side view (z ± r_r × [t0, t1]) and end view (x ± r_r × [t0, t1])
    al = alpha(ix, np.arange(ix.stations), 0.0)
    x, z = ix.centre_distance + ix.pitch_radius * np.cos(al), ix.pitch_radius * np.sin(al)
    near = (np.abs(z) < ix.cam_width / 2 + ix.roller_radius) & (np.abs(x) < ix.outer_radius + ix.roller_radius)
    assert near.sum() == 2
    rects = rectangles(msp, "ROLLERS")
    ends = np.unique(np.round(x[near], 9))               # the dwell's rollers at ±z coincide along z
    assert len(rects) == near.sum() + ends.size == info.rollers
    r, t0, t1 = ix.roller_radius, ix.roller_start, ix.roller_end
    for xa, za in zip(x[near], z[near]):
        side = [(za - r, t0), (za + r, t0), (za + r, t1), (za - r, t1)]
        end = [(xe + xa - r, t0), (xe + xa + r, t0), (xe + xa + r, t1), (xe + xa - r, t1)]
        assert sum(same_rectangle(p, side) for p in rects) == 1
        assert sum(same_rectangle(p, end) for p in rects) == 1
    # the side view: the root cylinder and the rib's extent (the traces reach both end faces)
    half = ix.cam_width / 2
    outl = rectangles(msp, "OUTLINE")
    assert sum(same_rectangle(p, [(-half, -ix.root_radius), (half, -ix.root_radius), (half, ix.root_radius),
                                   (-half, ix.root_radius)]) for p in outl) == 1
    (rib,) = rectangles(msp, "RIB")
    assert same_rectangle(rib, [(-half, -ix.outer_radius), (half, -ix.outer_radius), (half, ix.outer_radius),
                                (-half, ix.outer_radius)])
    # the axes: the turret axis at z = 0 (side view) and x = C (end view), vertical; the cam axis y = 0
    lines = [(ln.dxf.start, ln.dxf.end) for ln in msp.query('LINE[layer=="CENTERLINES"]')]
    vertical_x = {round(a.x, 9) for a, b in lines if a.x == b.x and abs(a.y - b.y) > ix.outer_radius}
    assert {0.0, round(xe + ix.centre_distance, 9)} <= vertical_x
    assert any(a.y == b.y == 0.0 and a.x < -half and b.x > half for a, b in lines)
    (dim,) = msp.query('DIMENSION[layer=="DIMENSIONS"]')
    assert dim.get_measurement() == pytest.approx(ix.centre_distance, abs=1e-12)
    assert tuple(dim.dxf.defpoint2)[:2] == (xe, ye) and tuple(dim.dxf.defpoint3)[:2] == (xe + ix.centre_distance, ye)


def test_the_globoid_views(globoid):
    d, surfaces, info, path, doc = globoid
    ix = d.indexer
    msp = doc.modelspace()
    c, half = ix.centre_distance, ix.cam_width / 2
    # contour view: the globoids' profiles, arcs about (0, ±C) between z = ±W/2
    arcs = msp.query("ARC")
    assert len(arcs) == 4
    for layer, radius in (("OUTLINE", ix.root_radius), ("TIP", ix.tip_radius)):
        got = sorted((a.dxf.center.y, a.dxf.start_angle, a.dxf.end_angle) for a in arcs
                     if a.dxf.layer == layer and a.dxf.radius == radius and a.dxf.center.x == 0.0)
        dd = math.degrees(math.asin(half / radius))
        assert np.allclose(got, [(-c, 90 - dd, 90 + dd), (c, 270 - dd, 270 + dd)], rtol=0, atol=1e-9)
        for a in arcs:
            if a.dxf.layer == layer:
                for p in (a.start_point, a.end_point):       # the arcs end on the end faces z = ±W/2
                    assert abs(abs(p.x) - half) < 1e-9
    # rollers: every roller's section in the plane y = 0 at θ = 0 (X = z, Y = x)
    rects = rectangles(msp, "ROLLERS")
    assert len(rects) == ix.stations == info.rollers
    for al in alpha(ix, np.arange(ix.stations), 0.0):
        u, v = np.array([math.sin(al), math.cos(al)]), np.array([math.cos(al), -math.sin(al)])
        p = np.array([0.0, c])
        corners = [p + t * u + s * ix.roller_radius * v for t in (ix.roller_start, ix.roller_end) for s in (-1, 1)]
        assert sum(same_rectangle(r, corners) for r in rects) == 1
    # circles: the hub about P; the end view's globoid circles at the end faces and the waist
    xe, ye = info.views["end"]
    got = sorted((cc.dxf.layer, round(cc.dxf.center.x, 9), cc.dxf.center.y, round(cc.dxf.radius, 9))
                 for cc in msp.query("CIRCLE"))
    expect = sorted([("TURRET", 0.0, c, ix.roller_start),
                     ("OUTLINE", round(xe, 9), ye, round(c - math.sqrt(ix.root_radius**2 - half**2), 9)),
                     ("TIP", round(xe, 9), ye, round(c - math.sqrt(ix.tip_radius**2 - half**2), 9)),
                     ("HIDDEN", round(xe, 9), ye, round(c - ix.root_radius, 9)),
                     ("HIDDEN", round(xe, 9), ye, round(c - ix.tip_radius, 9))])
    assert got == expect
    dims = msp.query('DIMENSION[layer=="DIMENSIONS"]')
    assert len(dims) == 2
    for dim in dims:
        assert dim.get_measurement() == pytest.approx(c, abs=1e-12)
    pts = {(tuple(dim.dxf.defpoint2)[:2], tuple(dim.dxf.defpoint3)[:2]) for dim in dims}
    assert pts == {((0.0, 0.0), (0.0, c)), ((xe, ye), (xe + c, ye))}


def test_the_document_is_built_without_writing_and_checks_its_inputs():
    d = design_globoidal(GloboidalIndexer())
    s = flank_surfaces(d)
    doc, info = spatial_drawing(d, s)
    assert info.summary()["quoted_flank_fit_error_mm"] == info.quoted_fit_error
    assert any(t.dxf.text == "GLOBOIDAL INDEXER CAM" for t in doc.modelspace().query('TEXT[layer=="TITLE"]'))
    other = flank_surfaces(design_globoidal(GloboidalIndexer(cam_width=54.0)))
    with pytest.raises(ValueError):
        spatial_drawing(d, other)


# ---- conical rollers: the outlines are the cone seen side-on --------------------------------------
# the spec numbers: a barrel with γ = 8° (r_r = 12 at the middle of t = 27 … 45) and a globoid whose
# cone's apex is at P (γ = atan(12/85), r_r = 12 at the middle of t = 74 … 96: r(t) = 12·t/85)
CONES = {"barrel": (design_barrel, BarrelIndexer, dict(roller_radius=12.0, roller_start=27.0, roller_end=45.0,
                                                        roller_cone_angle=math.radians(8.0))),
         "globoidal": (design_globoidal, GloboidalIndexer, dict(roller_radius=12.0, roller_start=74.0, roller_end=96.0,
                                                               roller_cone_angle=math.atan(12 / 85)))}


def cone_radius(name, t):
    """r(t) from the spec numbers alone (spatial.py's docs: r_r at the working length's middle)."""
    if name == "barrel":
        return 12.0 + (t - (27.0 + 45.0) / 2) * math.tan(math.radians(8.0))
    return 12.0 * t / 85.0                                 # the globoid's cone: its apex at P


@pytest.fixture(scope="module", params=sorted(CONES))
def conical(request, tmp_path_factory):
    make, kind, fields = CONES[request.param]
    d = make(kind(**fields))
    surfaces = flank_surfaces(d)
    path = tmp_path_factory.mktemp("dxf_spatial_cone") / f"{request.param}.dxf"
    info = write_spatial_dxf(d, surfaces, path)
    return request.param, d, info, ezdxf.readfile(str(path))


def same_outline(pts, corners, tol=1e-9):
    """The closed outline ``pts`` is the polygon ``corners`` (the same cyclic sequence, either way round)."""
    corners = np.asarray(corners, dtype=float)
    if pts.shape != corners.shape:
        return False
    for seq in (corners, corners[::-1]):
        for k in range(len(seq)):
            if np.abs(pts - np.roll(seq, k, axis=0)).max() < tol:
                return True
    return False


def test_conical_rollers_are_drawn_as_trapezoids(conical):
    name, d, info, doc = conical
    ix = d.indexer
    msp = doc.modelspace()
    t0, t1 = ix.roller_start, ix.roller_end
    r0, r1 = cone_radius(name, t0), cone_radius(name, t1)
    assert r1 - r0 > 2.5                                    # a visible taper: not the cylinder's rectangle
    outlines = rectangles(msp, "ROLLERS")
    assert all(o.shape == (4, 2) for o in outlines)
    if name == "barrel":
        # side view X = z, Y = y and end view X = x (+ xe), Y = y: the axis along +Y, the cone ± r(t) across it
        xe, _ = info.views["end"]
        al = alpha(ix, np.arange(ix.stations), 0.0)
        x, z = ix.centre_distance + ix.pitch_radius * np.cos(al), ix.pitch_radius * np.sin(al)
        r_max = max(r0, r1)
        near = (np.abs(z) < ix.cam_width / 2 + r_max) & (np.abs(x) < ix.outer_radius + r_max)
        ends = np.unique(np.round(x[near], 9))
        assert near.sum() >= 1 and len(outlines) == near.sum() + ends.size == info.rollers
        for xa, za in zip(x[near], z[near]):
            for c in (za, xe + xa):
                corners = [(c - r0, t0), (c + r0, t0), (c + r1, t1), (c - r1, t1)]
                assert sum(same_outline(o, corners) for o in outlines) == 1, (c, corners)
    else:
        # contour view X = z, Y = x: P at (0, C), the axis along u(α_j) = (sin α, cos α), across v
        assert len(outlines) == ix.stations == info.rollers
        p = np.array([0.0, ix.centre_distance])
        for al in alpha(ix, np.arange(ix.stations), 0.0):
            u, v = np.array([math.sin(al), math.cos(al)]), np.array([math.cos(al), -math.sin(al)])
            corners = [p + t0 * u - r0 * v, p + t1 * u - r1 * v, p + t1 * u + r1 * v, p + t0 * u + r0 * v]
            assert sum(same_outline(o, corners) for o in outlines) == 1, al
            # the globoid's cone has its apex at P: its sides run through P
            for sgn in (-1, 1):
                a, b = corners[0 if sgn < 0 else 3], corners[1 if sgn < 0 else 2]
                e, f = b - a, p - a
                assert abs(e[0] * f[1] - e[1] * f[0]) < 1e-9 * np.linalg.norm(e) * np.linalg.norm(f)
    # every roller lies inside the sheet's border (the views are sized with the largest radius)
    border = max(rectangles(msp, "TITLE"), key=lambda o: np.ptp(o[:, 0]) * np.ptp(o[:, 1]))
    lo, hi = border.min(axis=0), border.max(axis=0)
    for o in outlines:
        assert np.all(o >= lo) and np.all(o <= hi)
    # the title block names the cone: γ and the radii at the ends
    rows = title_rows(doc)
    m = re.fullmatch(r"([0-9.]+)°, RADIUS ([0-9.]+) mm AT t = ([0-9.]+) TO ([0-9.]+) mm AT t = ([0-9.]+) "
                     r"\(r_r AT THE MIDDLE\)", rows["ROLLER CONE ANGLE"])
    assert m, rows["ROLLER CONE ANGLE"]
    gamma = 8.0 if name == "barrel" else math.degrees(math.atan(12 / 85))
    assert [float(g) for g in m.groups()] == pytest.approx([gamma, r0, t0, r1, t1], rel=5e-6)
    assert float(re.match(r"[0-9.]+", rows["ROLLER RADIUS r_r"]).group()) == 12.0


def test_cylindrical_rollers_have_no_cone_row(drawn):
    d, surfaces, info, path, doc = drawn
    assert "ROLLER CONE ANGLE" not in title_rows(doc)

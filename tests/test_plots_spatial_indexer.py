"""The spatial indexers' figures (exporters.plots_spatial_indexer) rendered by chart_svg and read back: the
SVG parses; the rib's quads are the flank sheets' points turned by θ and projected along the documented
view (up +y, azimuth from +z towards +x, elevation towards +y — the matrices rebuilt here); the
rollers' end circles are centred where generators/bodies/indexing/spatial.py's conventions put the
roller axis (recomputed here from the law); the roller sides marked engaged are the design's; the
motion chart's ψ, ψ', ψ'' are the law's — for both default designs, in the index and in the dwell."""
from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from cam_workbench.exporters.chart import Area, Curve
from cam_workbench.exporters.chart_svg import svg
from cam_workbench.exporters.plots_spatial_indexer import (BARREL_VIEW, GLOBOIDAL_VIEW, roller_mesh,
                                                          spatial_motion_chart, spatial_picture)
from cam_workbench.generators.bodies.indexing.spatial import (BarrelIndexer, GloboidalIndexer, design_barrel,
                                                              design_globoidal)
from cam_workbench.generators.motion.laws import evaluate_law

SVG = "{http://www.w3.org/2000/svg}"


@pytest.fixture(scope="module", params=["barrel", "globoidal"])
def design(request):
    if request.param == "barrel":
        return design_barrel(BarrelIndexer())
    return design_globoidal(GloboidalIndexer())


def law(ix, theta):
    """ψ [rad] (continuous over turns), ψ', ψ'' from the law."""
    t_st = 2 * math.pi / ix.stations
    rel = np.asarray(theta, dtype=float) - ix.index_start
    turns = np.floor(rel / (2 * math.pi))
    u = (rel - 2 * math.pi * turns) / ix.index_angle
    f, f1, f2, _ = evaluate_law(ix.law, np.clip(u, 0, 1))
    inside = (u >= 0) & (u <= 1)
    return t_st * (turns + f), np.where(inside, t_st * f1 / ix.index_angle, 0), \
        np.where(inside, t_st * f2 / ix.index_angle**2, 0)


def projector(view):
    """(right, up): screen axes of the view (azimuth a from +z towards +x, elevation e towards +y, up +y)."""
    a, e = np.radians(view)
    toward = np.array([math.cos(e) * math.sin(a), math.sin(e), math.cos(e) * math.cos(a)])
    right = np.array([math.cos(a), 0.0, -math.sin(a)])
    up = np.cross(toward, right)
    assert up[1] > 0 and abs(right @ up) < 1e-12
    return np.stack([right, up], axis=1)                       # (3, 2): p @ M = screen point


def rz(theta):
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def roller_axis_here(ix, j, theta):
    """a, d (fixed frame) of roller j at θ from the module's conventions."""
    t_st = 2 * math.pi / ix.stations
    al = math.pi + t_st * (j - 0.5) + float(law(ix, theta)[0])
    u = np.array([math.cos(al), 0.0, math.sin(al)])
    p = np.array([ix.centre_distance, 0.0, 0.0])
    if isinstance(ix, BarrelIndexer):
        return p + ix.pitch_radius * u, np.array([0.0, 1.0, 0.0])
    return p, u


def cases(design):
    """(θ, grid index, view): mid-index, late index, dwell (default view) and one given view."""
    n1, s = design.index_rows, design.theta.size
    default = BARREL_VIEW if isinstance(design.indexer, BarrelIndexer) else GLOBOIDAL_VIEW
    out = [(i, None, default) for i in (n1 // 2, (4 * n1) // 5, (n1 + s) // 2)]
    out.append((n1 // 3, (30.0, 20.0), (30.0, 20.0)))
    return [(float(design.theta[i]), i, given, view) for i, given, view in out]


def test_the_picture_reads_back_as_the_design_at_theta(design):
    ix = design.indexer
    rr = ix.roller_radius
    j_lo = int(design.rollers[0])
    for theta, i, given, view in cases(design):
        chart = spatial_picture(design, theta, given)
        root = ET.fromstring(svg(chart, "sx"))                     # well-formed XML
        ids = {e.get("id") for e in root.iter() if e.get("id")}
        m = projector(view)
        rot = rz(theta)
        # the rib's quads: the sheets' points turned by θ and projected; every corner in the band
        n_quads = 0
        for mark in chart.panels[0].marks:
            hit = re.fullmatch(r"rib-([pm])-(\d+)-(\d+)-(\d+)", mark.gid or "")
            if not hit:
                continue
            sheet = design.sheets[0 if hit.group(1) == "p" else 1]
            r0, r1, k = (int(hit.group(g)) for g in (2, 3, 4))
            rows, cols = np.array([r0, r1, r1, r0]), np.array([k, k, k + 1, k + 1])
            assert r0 < r1 and sheet.in_band[rows, cols].all()
            expect = (sheet.points[rows, cols] @ rot.T) @ m
            assert isinstance(mark, Area) and np.allclose(mark.loops[0], expect, rtol=0, atol=1e-9)
            n_quads += 1
        assert n_quads > 200
        assert f"sx-rib-p-{r0}-{r1}-{k}" in ids or f"sx-rib-m-{r0}-{r1}-{k}" in ids
        # the rollers' end circles: centred on the axis at t0 and t1, radius r_r in 3D (an ellipse here)
        for j in design.rollers.tolist():
            a, d = roller_axis_here(ix, j, theta)
            for tag, t in (("t0", ix.roller_start), ("t1", ix.roller_end)):
                (ring,) = chart.marks(f"roller-{j}-{tag}")
                assert isinstance(ring, Curve) and f"sx-roller-{j}-{tag}" in ids
                pts = np.column_stack([ring.x, ring.y])[:-1]
                assert np.allclose(pts.mean(axis=0), (a + t * d) @ m, atol=1e-9)
                # the ellipse's half axes: r_r across the projected axis, r_r·|d·toward| along it
                span = np.linalg.norm(pts - (a + t * d) @ m, axis=1)
                assert span.max() == pytest.approx(rr, rel=1e-3)
        # the engaged sides: those the design marks at that sample
        marked = {(j, s) for j in design.rollers.tolist() for s, tag in ((1, "p"), (-1, "m"))
                  if chart.marks(f"engaged-{j}-{tag}")}
        expect = {(int(j), s) for jj, j in enumerate(design.rollers) for si, s in enumerate((1, -1))
                  if design.engaged[int(j) - j_lo, si, i]}
        assert marked == expect and expect
        for j, s in marked:
            assert f"sx-engaged-{j}-{'p' if s == 1 else 'm'}" in ids
        note = "\n".join(t.text for t in root.iter(f"{SVG}text") if t.get("data-gid") == "turret-angle")
        psi = float(re.search(r"ψ\(θ\) = ([-0-9.]+)°", note).group(1))
        assert psi == pytest.approx(math.degrees(float(law(ix, theta)[0])), abs=6e-5)
        turret = "sx-turret-pitch-circle" if isinstance(ix, BarrelIndexer) else "sx-turret-hub"
        assert {turret, "sx-cam-axis", "sx-turret-axis", "sx-root-outline"} <= ids


def test_the_engaged_set_changes_through_the_turn(design):
    """Across the samples above, the marked set is not constant (rollers come in and leave)."""
    sets = []
    for theta, _, given, _ in cases(design)[:3]:
        chart = spatial_picture(design, theta, given)
        sets.append(frozenset(mk.gid for p in chart.panels for mk in p.marks
                              if (mk.gid or "").startswith("engaged-")))
    assert len(set(sets)) > 1


def test_the_motion_chart_is_the_law(design):
    ix = design.indexer
    chart = spatial_motion_chart(design)
    root = ET.fromstring(svg(chart, "m"))
    ids = {e.get("id") for e in root.iter() if e.get("id")}
    x = np.degrees(design.theta - ix.index_start)
    psi, d1, d2 = law(ix, design.theta)
    for gid, expect in (("psi", np.degrees(psi)), ("dpsi", d1), ("d2psi", d2)):
        (c,) = chart.marks(gid)
        assert f"m-{gid}" in ids
        assert np.allclose(c.x, x, atol=1e-12)
        assert np.allclose(c.y, expect, rtol=1e-12, atol=1e-12)
    assert float(np.degrees(psi[-1])) == pytest.approx(360 / ix.stations, abs=1e-9)
    (c,) = chart.marks("driving-angle")
    over = x <= math.degrees(ix.index_angle)
    assert np.all(np.isnan(c.y[~over]))
    assert np.allclose(c.y[over], np.degrees(design.driving_angle[over]), equal_nan=True)
    y = c.y[np.isfinite(c.y)]
    assert y.size > 0.9 * over.sum() and np.all((y >= 0) & (y < 90))


# ---- conical rollers ------------------------------------------------------------------------------
# the spec numbers: a barrel with γ = 8° (r_r = 12 at the middle of t = 27 … 45) and a globoid whose
# cone's apex is at P (γ = atan(12/85), r_r = 12 at the middle of t = 74 … 96: r(t) = 12·t/85)
CONES = {"barrel-cone": (design_barrel, BarrelIndexer, dict(roller_radius=12.0, roller_start=27.0, roller_end=45.0,
                                                             roller_cone_angle=math.radians(8.0)),
                         lambda t: 12.0 + (t - 36.0) * math.tan(math.radians(8.0)), math.tan(math.radians(8.0))),
         "globoidal-cone": (design_globoidal, GloboidalIndexer, dict(roller_radius=12.0, roller_start=74.0,
                                                                     roller_end=96.0,
                                                                     roller_cone_angle=math.atan(12 / 85)),
                            lambda t: 12.0 * np.asarray(t) / 85.0, 12 / 85)}


CYLINDERS = {"barrel": (design_barrel, BarrelIndexer, {}, lambda t: np.full_like(np.asarray(t, dtype=float), 12.0),
                        0.0),
             "globoidal": (design_globoidal, GloboidalIndexer, {},
                           lambda t: np.full_like(np.asarray(t, dtype=float), 12.0), 0.0)}


def _rollers_case(name):
    make, kind, fields, radius, taper = {**CYLINDERS, **CONES}[name]
    return make(kind(**fields)), radius, taper


@pytest.fixture(scope="module", params=sorted(CONES))
def cone(request):
    return _rollers_case(request.param)


@pytest.fixture(scope="module", params=sorted(CYLINDERS) + sorted(CONES))
def any_roller(request):
    """The default designs (cylinders of radius r_r = 12, no taper) and the conical ones."""
    return _rollers_case(request.param)


def test_the_conical_pictures_build_and_their_end_circles_have_the_cones_radii(cone):
    design, radius, taper = cone
    ix = design.indexer
    theta = float(design.theta[design.index_rows // 2])
    for given in (None, (30.0, 20.0)):
        chart = spatial_picture(design, theta, given)
        ET.fromstring(svg(chart, "c"))
        view = given or (BARREL_VIEW if isinstance(ix, BarrelIndexer) else GLOBOIDAL_VIEW)
        m = projector(view)
        for j in design.rollers.tolist():
            a, d = roller_axis_here(ix, j, theta)
            for tag, t in (("t0", ix.roller_start), ("t1", ix.roller_end)):
                (ring,) = chart.marks(f"roller-{j}-{tag}")
                pts = np.column_stack([ring.x, ring.y])[:-1]
                assert np.allclose(pts.mean(axis=0), (a + t * d) @ m, atol=1e-9)
                span = np.linalg.norm(pts - (a + t * d) @ m, axis=1)
                assert span.max() == pytest.approx(float(radius(t)), rel=1e-9)
        assert "cone γ" in chart.panels[0].title


def test_the_roller_silhouettes_touch_both_end_circles(any_roller):
    """Each silhouette line's ends lie on the projected end circles (radii r(t0), r(t1)) and the line is
    tangent to both there; a cone seen within γ of its axis has none."""
    design, radius, taper = any_roller
    ix = design.indexer
    t0, t1 = ix.roller_start, ix.roller_end
    for theta, _, given, view in cases(design)[:2]:
        chart = spatial_picture(design, theta, given)
        m = projector(view)
        toward = np.cross(m[:, 0], m[:, 1])                         # right × up: towards the viewer
        drawn = 0
        for j in design.rollers.tolist():
            a, d = roller_axis_here(ix, j, theta)
            (sides,) = chart.marks(f"roller-{j}-sides")
            xy = np.column_stack([sides.x, sides.y])
            assert np.isnan(xy[2]).all()
            along = abs(d @ toward)
            if taper * along > np.linalg.norm(np.cross(d, toward)):
                assert np.isnan(xy).all()
                continue
            b1 = np.cross(d, [1.0, 0.0, 0.0] if abs(d[0]) < 0.9 else [0.0, 0.0, 1.0])
            b1 /= np.linalg.norm(b1)
            b2 = np.cross(d, b1)
            basis = np.column_stack([b1 @ m, b2 @ m])               # the circle's (cos, sin) → screen
            for p0, p1 in (xy[:2], xy[3:]):
                line = p1 - p0
                for q, t in ((p0, t0), (p1, t1)):
                    cs = np.linalg.solve(basis, q - (a + t * d) @ m) / float(radius(t))
                    assert np.hypot(*cs) == pytest.approx(1.0, abs=1e-9)            # on the end circle
                    tangent = basis @ np.array([-cs[1], cs[0]])
                    sin = (line[0] * tangent[1] - line[1] * tangent[0]) / np.linalg.norm(line) \
                        / np.linalg.norm(tangent)
                    assert abs(sin) < 1e-9                                            # tangent to it
                drawn += 1
        assert drawn >= design.rollers.size


def test_the_roller_mesh_is_the_cone(any_roller):
    """roller_mesh: every grid point at distance r(t) from its roller's axis at axis parameter t, the
    rings at t0 … t1, and the mantle's normals square to the generators, pointing outwards."""
    design, radius, taper = any_roller
    ix = design.indexer
    theta = float(design.theta[design.index_rows // 3])
    axes = [roller_axis_here(ix, j, theta) for j in design.rollers.tolist()]
    a, d = np.array([p for p, _ in axes]), np.array([q for _, q in axes])
    t, pts, normals = roller_mesh(ix, a, d, (30.0, 20.0))
    assert t[0] == ix.roller_start and t[-1] == ix.roller_end and pts.shape[:2] == (a.shape[0], t.size)
    rel = pts - a[:, None, None, :]
    s = np.einsum("jtpc,jc->jtp", rel, d)
    assert np.allclose(s, t[None, :, None], rtol=0, atol=1e-9)
    dist = np.linalg.norm(rel - s[..., None] * d[:, None, None, :], axis=-1)
    assert np.allclose(dist, radius(t)[None, :, None], rtol=0, atol=1e-9)
    gen = pts[:, -1] - pts[:, 0]                                    # the generators (J, P, 3)
    mid_gen = 0.5 * (gen[:, :-1] + gen[:, 1:])
    nh = normals / np.linalg.norm(normals, axis=-1, keepdims=True)
    assert np.abs(np.einsum("jpc,jpc->jp", nh, mid_gen / np.linalg.norm(mid_gen, axis=-1, keepdims=True))).max() \
        < 0.05                                                      # square to the faces (a chord's error)
    radial = 0.5 * (rel[:, 0, :-1] + rel[:, 0, 1:]) - t[0] * d[:, None, :]
    assert (np.einsum("jpc,jpc->jp", nh, radial) > 0).all()
    # the normal's axial part: −tan γ per unit of radial part
    ax = np.einsum("jpc,jc->jp", normals, d)
    rad = np.linalg.norm(normals - ax[..., None] * d[:, None, :], axis=-1)
    assert np.allclose(ax / rad, -taper, atol=1e-12)

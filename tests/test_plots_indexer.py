"""The parallel indexer's figures (exporters.plots_indexer) rendered by chart_svg and read back: the SVG
parses; the cams' outlines, read through the panel's own tick marks, are the profiles turned by θ; the
roller circles are where the conventions put them (generators/bodies/indexing/parallel.py's
docstring, recomputed here); the rollers that touch their cam are the ones marked engaged; the motion
chart's curves are the law's."""
from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from cam_workbench.exporters.chart import Area, Curve
from cam_workbench.exporters.chart_svg import svg
from cam_workbench.exporters.plots_indexer import indexer_motion_chart, indexer_picture
from cam_workbench.generators.bodies.indexing.parallel import ParallelIndexer, design_parallel
from cam_workbench.generators.motion.laws import evaluate_law

SVG = "{http://www.w3.org/2000/svg}"
CASES = {"default": {}, "three_cams": {"cams": 3},
         "beta270_shifted": {"index_angle": math.radians(270), "centre_distance": 90.0, "law": "poly4567",
                             "index_start": 0.3}}


@pytest.fixture(scope="module", params=sorted(CASES))
def design(request):
    return design_parallel(ParallelIndexer(**CASES[request.param]))


def thetas(ix):
    """Input angles [rad]: in the index, in the next turn's index, in the dwell after it."""
    ts, b = ix.index_start, ix.index_angle
    return [ts + 0.3 * b, ts + 2 * math.pi + 0.55 * b, ts + b + 0.5 * (2 * math.pi - b)]


def law(ix, theta):
    """ψ [rad] (clockwise, continuous over turns), ψ', ψ'' from the law."""
    t_st = 2 * math.pi / ix.stations
    rel = np.asarray(theta, dtype=float) - ix.index_start
    turns = np.floor(rel / (2 * math.pi))
    u = (rel - 2 * math.pi * turns) / ix.index_angle
    f, f1, f2, _ = evaluate_law(ix.law, np.clip(u, 0, 1))
    inside = (u >= 0) & (u <= 1)
    return t_st * (turns + f), np.where(inside, t_st * f1 / ix.index_angle, 0), \
        np.where(inside, t_st * f2 / ix.index_angle**2, 0)


def roller_centres(ix, k, theta):
    a_k = math.pi + (ix.cams - 1 - 2 * k) * math.pi / (ix.stations * ix.cams)
    al = a_k + 2 * math.pi * np.arange(ix.stations) / ix.stations - law(ix, theta)[0]
    return np.column_stack([ix.centre_distance + ix.pitch_radius * np.cos(al), ix.pitch_radius * np.sin(al)])


def turned(theta, pts):
    c, s = math.cos(theta), math.sin(theta)
    return np.column_stack([c * pts[:, 0] - s * pts[:, 1], s * pts[:, 0] + c * pts[:, 1]])


def polyline_distance(pts, poly):
    a, d = poly[:-1], np.diff(poly, axis=0)
    q = pts[:, None, :] - a[None]
    t = np.clip((q * d).sum(-1) / (d * d).sum(1), 0, 1)
    r = q - t[..., None] * d
    return np.sqrt((r * r).sum(-1).min(1))


def axis(root, pid, which):
    """Data value from an SVG coordinate through the panel's ticks (their data-value); and the scale."""
    pos, val = [], []
    for g in root.iter(f"{SVG}g"):
        if re.fullmatch(rf"{pid}-{which}tick-\d+", g.get("id", "")):
            line = g.find(f"{SVG}line")
            pos.append(float(line.get("x1" if which == "x" else "y1")))
            val.append(float(g.get("data-value")))
    a, b = np.polyfit(pos, val, 1)
    return (lambda p: a * np.asarray(p) + b), abs(a)


def path_points(d):
    return np.array([(float(x), float(y)) for x, y in re.findall(r"[ML]([-\d.]+) ([-\d.]+)", d)])


def test_the_picture_reads_back_as_the_design_at_theta(design):
    ix = design.indexer
    rr = ix.roller_radius
    for theta in thetas(ix):
        chart = indexer_picture(design, theta)
        root = ET.fromstring(svg(chart, "ix"))                     # well-formed XML
        xm, sx = axis(root, "ix-p0", "x")
        ym, sy = axis(root, "ix-p0", "y")
        assert sx == pytest.approx(sy, rel=1e-3)                    # equal aspect
        tol = 0.012 * sx                                            # 2-decimal points, 3-decimal ticks
        el = {e.get("id"): e for e in root.iter() if e.get("id")}
        touching = {}
        for cam in design.cams:
            k = cam.index
            expect = turned(theta, cam.profile)
            (area,) = chart.marks(f"cam-{k}")
            assert isinstance(area, Area) and np.allclose(area.loops[0], expect, rtol=0, atol=1e-12)
            px = path_points(el[f"ix-cam-{k}"].get("d"))
            got = np.column_stack([xm(px[:, 0]), ym(px[:, 1])])
            assert got.shape == expect.shape and np.abs(got - expect).max() < tol
            centres = roller_centres(ix, k, theta)
            for j, c in enumerate(centres):
                (ring,) = chart.marks(f"roller-{k}-{j}")
                assert isinstance(ring, Curve)
                pts = np.column_stack([ring.x, ring.y])[:-1]
                assert np.allclose(pts.mean(0), c, atol=1e-9)
                assert np.allclose(np.hypot(*(pts - c).T), rr, atol=1e-9)
                svg_pts = path_points(el[f"ix-roller-{k}-{j}"].get("d"))[:-1]
                svg_c = np.array([xm(svg_pts[:, 0]).mean(), ym(svg_pts[:, 1]).mean()])
                assert np.abs(svg_c - c).max() < tol
            # the rollers whose circles touch the cam's profile (in the cam frame: Rot(−θ))
            gap = polyline_distance(turned(-theta, centres), cam.profile) - rr
            touching[k] = {j for j in range(ix.stations) if abs(gap[j]) < 1e-4}
        marked = {k: {j for j in range(ix.stations) if chart.marks(f"engaged-{k}-{j}")} for k in touching}
        assert marked == touching and any(marked.values())
        for k, js in marked.items():
            for j in js:
                assert f"ix-engaged-{k}-{j}" in el
        note = next(t.text for t in root.iter(f"{SVG}text") if t.get("data-gid") == "turret-angle")
        psi = float(re.search(r"ψ\(θ\) = ([-0-9.]+)°", note).group(1))
        assert psi == pytest.approx(math.degrees(float(law(ix, theta)[0])), abs=6e-5)
        assert "ix-turret-pitch-circle" in el and "ix-input-axis" in el and "ix-turret-axis" in el


def test_the_motion_chart_is_the_law(design):
    ix = design.indexer
    chart = indexer_motion_chart(design)
    root = ET.fromstring(svg(chart, "m"))
    el = {e.get("id") for e in root.iter() if e.get("id")}
    x = np.degrees(design.theta - ix.index_start)
    psi, d1, d2 = law(ix, design.theta)
    for gid, expect in (("psi", np.degrees(psi)), ("dpsi", d1), ("d2psi", d2)):
        (c,) = chart.marks(gid)
        assert f"m-{gid}" in el
        assert np.allclose(c.x, x, atol=1e-12)
        assert np.allclose(c.y, expect, rtol=1e-12, atol=1e-12)
    assert float(np.degrees(psi[-1])) == pytest.approx(360 / ix.stations, abs=1e-9)
    (c,) = chart.marks("driving-angle")
    over = x <= math.degrees(ix.index_angle)
    assert np.all(np.isnan(c.y[~over]))
    assert np.allclose(c.y[over], np.degrees(design.driving_angle[over]), equal_nan=True)
    y = c.y[np.isfinite(c.y)]
    assert y.size > 0.9 * over.sum() and np.all((y >= 0) & (y < 90))
    # the SVG curve read back through the last panel's ticks: its points are the finite ones, in order
    xm, sx = axis(root, "m-p3", "x")
    ym, sy = axis(root, "m-p3", "y")
    pts = path_points(root.find(".//*[@id='m-driving-angle']").get("d"))
    ok = np.isfinite(c.y)
    assert pts.shape == (ok.sum(), 2)
    assert np.abs(xm(pts[:, 0]) - x[ok]).max() < 0.01 * sx
    assert np.abs(ym(pts[:, 1]) - c.y[ok]).max() < 0.01 * sy

"""The figures' drawing (exporters.chart, chart_svg, chart_png): ticks, the SVG's coordinates read
back into data through its own tick marks, NaN gaps, equal aspect, ids, and the PNG."""
from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from cam_workbench.exporters.chart import Area, Chart, Curve, Note, Panel, Rule, Shade, angle_panel, css_color
from cam_workbench.exporters.chart_svg import nice_ticks, svg, tick_labels

SVG = "{http://www.w3.org/2000/svg}"


@settings(max_examples=200, deadline=None)
@given(st.floats(-1e6, 1e6), st.floats(1e-6, 1e6))
def test_ticks_are_round_and_inside(lo, span):
    assume(span > 1e-4 * abs(lo))                 # a range a figure shows (not a float's last digits)
    hi = lo + span
    t = nice_ticks(lo, hi)
    assert t.size >= 2
    assert t.min() >= lo - 1e-9 * span and t.max() <= hi + 1e-9 * span
    step = np.diff(t)
    assert np.allclose(step, step[0], rtol=1e-9, atol=8 * np.spacing(np.max(np.abs(t))))
    mant = step[0] / 10.0 ** math.floor(math.log10(step[0]) + 1e-12)
    assert min(abs(mant - m) for m in (1, 2, 2.5, 5, 10)) < 1e-6
    labels = tick_labels(t)
    assert len(set(labels)) == len(labels)       # enough decimals to tell the ticks apart


def test_tick_labels_read_as_their_values():
    assert tick_labels([0, 30, 60]) == ["0", "30", "60"]
    assert tick_labels([-0.5, 0.0, 0.5]) == ["−0.5", "0.0", "0.5"]
    assert tick_labels([0.0, 2.5, 5.0]) == ["0.0", "2.5", "5.0"]
    assert css_color("0.45") == "#737373" and css_color("k") == "#000000" and css_color("#abc") == "#abc"


def _axis(root, pid, axis):
    """Data value from an SVG coordinate, fitted to the panel's ticks (their data-value)."""
    pos, val = [], []
    for g in root.iter(f"{SVG}g"):
        if re.fullmatch(rf"{pid}-{axis}tick-\d+", g.get("id", "")):
            line = g.find(f"{SVG}line")
            pos.append(float(line.get("x1" if axis == "x" else "y1")))
            val.append(float(g.get("data-value")))
    a, b = np.polyfit(pos, val, 1)
    return lambda p: a * np.asarray(p) + b


def _path_points(d):
    """Sub-paths of an M/L path as arrays of points."""
    subs = []
    for cmd, x, y in re.findall(r"([ML])([-\d.]+) ([-\d.]+)", d):
        if cmd == "M":
            subs.append([])
        subs[-1].append((float(x), float(y)))
    return [np.array(s) for s in subs]


def test_curve_rule_point_read_back_through_the_ticks():
    x = np.linspace(0, 360, 721)
    y = 12.5 * np.sin(np.deg2rad(2 * x)) + 3.0
    y_gap = y.copy()
    y_gap[300:320] = np.nan
    chart = Chart.stack([angle_panel(marks=[
        Curve(x, y_gap, gid="curve"), Rule("y", 7.25, gid="lim"), Rule("x", 123.0, gid="vline"),
        Curve(np.array([45.0]), np.array([15.5]), marker="o", line=False, gid="pt"),
        Note(45.0, 15.5, "max & <15.5>"), Shade([(200.0, 230.0)], label="off"),
    ], ylabel="y [mm]", legend="upper right")])
    text = svg(chart, "t")
    root = ET.fromstring(text)                              # well-formed XML
    xm, ym = _axis(root, "t-p0", "x"), _axis(root, "t-p0", "y")
    el = {e.get("id"): e for e in root.iter() if e.get("id")}
    subs = _path_points(el["t-curve"].get("d"))
    assert len(subs) == 2                                   # the NaN run breaks the line
    pts = np.vstack(subs)
    keep = np.isfinite(y_gap)
    assert np.max(np.abs(xm(pts[:, 0]) - x[keep])) < 0.01   # 2 decimals of a point
    assert np.max(np.abs(ym(pts[:, 1]) - y[keep])) < 0.01
    lim = el["t-lim"]
    assert lim.get("y1") == lim.get("y2") and ym(float(lim.get("y1"))) == pytest.approx(7.25, abs=1e-3)
    assert xm(float(el["t-vline"].get("x1"))) == pytest.approx(123.0, abs=1e-3)
    c = el["t-pt"].find(f"{SVG}circle")
    assert xm(float(c.get("cx"))) == pytest.approx(45.0, abs=1e-3)
    assert ym(float(c.get("cy"))) == pytest.approx(15.5, abs=1e-3)
    assert "max &amp; &lt;15.5&gt;" in text and "<script" not in text and "href" not in text


def test_equal_aspect_and_holes():
    t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    ring = Area([np.c_[40 * np.cos(t), 25 * np.sin(t)], np.c_[5 * np.cos(t), 5 * np.sin(t)]], gid="cam")
    chart = Chart.stack([Panel(marks=[ring], equal=True, height=300)], width=500)
    root = ET.fromstring(svg(chart, "e"))
    xm, ym = _axis(root, "e-p0", "x"), _axis(root, "e-p0", "y")
    sx = abs(xm(1.0) - xm(0.0))
    sy = abs(ym(1.0) - ym(0.0))
    assert sx == pytest.approx(sy, rel=1e-3)                # one unit as long on both axes
    el = next(e for e in root.iter() if e.get("id") == "e-cam")
    assert el.get("fill-rule") == "evenodd" and el.get("d").count("Z") == 2


def test_log_axis_and_columns():
    it = np.arange(1.0, 11.0)
    chart = Chart([[Panel(marks=[Curve(it, 10.0 ** -it, marker="o")], logy=True)],
                   [Panel(marks=[Curve(it, it)]), Panel(marks=[Curve(it, -it)], xlabel="i")]], widths=(1, 2))
    root = ET.fromstring(svg(chart, "c"))
    ids = {e.get("id") for e in root.iter() if e.get("id")}
    assert {"c-p0", "c-p1", "c-p2"} <= ids
    vals = sorted(float(g.get("data-value")) for g in root.iter(f"{SVG}g")
                  if re.fullmatch(r"c-p0-ytick-\d+", g.get("id", "")))
    assert all(abs(math.log10(v) - round(math.log10(v))) < 1e-12 for v in vals)   # decades


def test_png_is_the_svg_rasterised():
    pytest.importorskip("cairosvg")
    from cam_workbench.exporters.chart_png import SCALE, png_bytes

    chart = Chart.stack([angle_panel(marks=[Curve(np.array([0.0, 360.0]), np.array([0.0, 1.0]))])], width=400)
    png = png_bytes(chart)
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    width = int.from_bytes(png[16:20], "big")
    assert width == round(400 * SCALE)

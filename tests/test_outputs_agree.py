"""Every output tells the truth and agrees with report.json.

Three cams: the paper's (--example paper: its pressure_angle check fails, 46.24° > 30°), a passing one
(cam.base_radius = 60) and one with a fitted B-spline pitch curve.  Each output is read
back as a user's tool would read it — the HTML parsed, the DXF read with ezdxf, the G-code
and the CLI's table as text, the SVG plots' paths and tick labels — and held against the
numbers of report.json (never against an earlier output):

* the HTML verdict is checks.passed/failed verbatim, one row per check with its value,
  comparison, limit, cam angle and status, failing rows red;
* a failing check shows as failing in the HTML, the DXF title block, the G-code header,
  ``cam-workbench check``'s table and FreeCAD's check table; a passing cam nowhere fails;
* nothing of a B-spline-pitch cam claims "exact" or "rational" unless qualified;
* the plots' dashed limit lines sit at the checks' limits and the marked points at the
  checks' values and cam angles (read back through the axis tick labels);
* DIMENSION texts never overlap the DXF title block, for cams of several sizes and units.
"""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from html.parser import HTMLParser

import numpy as np
import pytest

from cam_workbench.freecad.check_design import checks_table
from cam_workbench.exporters.dxf import build_dxf
from cam_workbench.exporters.gcode import contour_program, rotary_program
from cam_workbench.exporters.report_html import render_report
from cam_workbench.generators import default_spec, design_cam
from cam_workbench.generators.machining import machining_plan
from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.machining.toolpath import contour_path, rotary_path

from .conftest import ROOT, requires_ocp

ezdxf = pytest.importorskip("ezdxf")
from ezdxf import bbox  # noqa: E402

CLI = [sys.executable, "-m", "cam_workbench.cli"]

#: the comparison each check's value must satisfy against its limit (cam_workbench.generators.checks.design:
#: pressure angle and stress are upper bounds; separation F > min_force and the undercut
#: ρ − r_f > 0 are strict; oscillation, curvature and convexity pass at the limit)
EXPECTED_SIGN = {"pressure_angle": "≤", "contact_stress": "≤", "separation": ">", "undercut": ">",
                 "oscillation": "≥", "curvature": "≥", "convexity": "≥"}


def run(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT), COLUMNS="250")
    return subprocess.run([*CLI, *args], capture_output=True, text=True, env=env)


# ---- the cams ------------------------------------------------------------------------------
def _built(tmp_path_factory, name, *sets, example="default"):
    out = tmp_path_factory.mktemp(name) / "out"
    args = ["--example", example, *[a for s in sets for a in ("--set", s)]]
    res = run("build", *args, "-o", str(out))
    assert res.returncode == 0, res.stderr
    return out


@pytest.fixture(scope="module")
def failing(tmp_path_factory):
    """`cam-workbench build` of the paper's cam (--example paper: its pressure angle fails)."""
    return _built(tmp_path_factory, "failing", example="paper")


@pytest.fixture(scope="module")
def passing(tmp_path_factory):
    return _built(tmp_path_factory, "passing", "cam.base_radius=60")


@pytest.fixture(scope="module")
def bspline(tmp_path_factory):
    """A B-spline pitch cam, its report and drawing written the way report_cmd does
    (design_cam + summary → report.json text → render_report; build_dxf)."""
    out = tmp_path_factory.mktemp("bspline")
    spec = default_spec().replace(**{"pitch.representation": "bspline"})
    design = design_cam(spec)
    summary = design.summary()
    summary["spec"] = spec.to_dict()
    doc, info = build_dxf(design, summary)
    summary["drawing"] = info.summary()
    report = json.loads(json.dumps(summary))
    text, pngs = render_report(design, report)
    (out / "report.json").write_text(json.dumps(report))
    (out / "report.html").write_text(text)
    doc.saveas(str(out / "cam.dxf"))
    return out


def _report(folder):
    return json.loads((folder / "report.json").read_text())


# ---- reading the HTML ------------------------------------------------------------------------
class Page(HTMLParser):
    """The check rows (tr[data-check]), the verdict span and the visible text."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.rows: dict[str, dict] = {}
        self.verdict: dict | None = None
        self.text: list[str] = []
        self._row: dict | None = None
        self._cell: dict | None = None
        self._verdict_text: list[str] | None = None
        self._skip = 0

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag in ("style", "script"):
            self._skip += 1
        if tag == "tr" and "data-check" in a:
            self._row = {"attrs": a, "cells": []}
            self.rows[a["data-check"]] = self._row
        if tag == "td" and self._row is not None:
            self._cell = {"attrs": a, "text": ""}
            self._row["cells"].append(self._cell)
        if tag == "span" and a.get("data-key") == "checks.passed":
            self.verdict = {"attrs": a, "text": ""}
            self._verdict_text = []

    def handle_endtag(self, tag):
        if tag in ("style", "script"):
            self._skip -= 1
        if tag == "tr":
            self._row = None
        if tag == "td":
            self._cell = None
        if tag == "span" and self._verdict_text is not None:
            self.verdict["text"] = "".join(self._verdict_text)
            self._verdict_text = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell["text"] += data
        if self._verdict_text is not None:
            self._verdict_text.append(data)
        if not self._skip:
            self.text.append(data)

    def handle_comment(self, data):
        self.text.append(data)  # matplotlib writes every SVG text as a comment beside its glyphs


def _page(folder) -> Page:
    p = Page()
    p.feed((folder / "report.html").read_text(encoding="utf-8"))
    p.close()
    return p


def _expected_verdict(checks):
    if checks["passed"]:
        assert checks["failed"] == []
        return "all pass"
    return "FAILED: " + ", ".join(checks["failed"])


@pytest.mark.parametrize("cam", ["failing", "passing", "bspline"])
@requires_ocp
def test_html_verdict_and_check_rows_equal_report_json(cam, request):
    folder = request.getfixturevalue(cam)
    checks = _report(folder)["checks"]
    page = _page(folder)
    v = page.verdict
    assert v is not None
    assert v["attrs"]["data-value"] == ("true" if checks["passed"] else "false")
    assert v["attrs"]["data-failed"] == ",".join(checks["failed"])
    assert _expected_verdict(checks) in v["text"]
    assert ("verdict pass" if checks["passed"] else "verdict fail") in v["attrs"]["class"]
    assert list(page.rows) == list(checks["results"])  # one row per check, in order; no "results"/"extremes" rows
    for name, r in checks["results"].items():
        row = page.rows[name]
        cells = {c["attrs"].get("data-key", c["attrs"].get("class", "")): c for c in row["cells"]}
        pre = f"checks.results.{name}"
        for field in ("value", "limit", "at_deg"):
            cell = cells[f"{pre}.{field}"]
            if r[field] is None:
                assert cell["attrs"]["data-value"] == "null" and cell["text"] == "—"
            else:
                assert float(cell["attrs"]["data-value"]) == r[field]
                assert cell["text"] == f"{r[field]:.6g}"            # the printed precision: 6 digits
        sign = cells["sign"]["text"]
        assert sign == ("" if r["limit"] is None else EXPECTED_SIGN[name])
        assert cells[f"{pre}.status"]["text"] == r["status"]
        assert cells[f"{pre}.note"]["text"] == r["note"]
        red = "fail" in row["attrs"]["class"].split()
        assert red == (r["status"] == "fail") == (name in checks["failed"])
        assert row["attrs"]["data-status"] == r["status"]


# ---- a failing check everywhere ---------------------------------------------------------------
def _title_block(path):
    """{label: value} of the DXF title block, paired by baseline (label column, value column)."""
    msp = ezdxf.readfile(path).modelspace()
    texts = [(round(t.dxf.insert.y, 6), t.dxf.insert.x, t.dxf.text) for t in msp.query('TEXT[layer=="TITLE"]')]
    rows: dict[float, list] = {}
    for y, x, text in texts:
        rows.setdefault(y, []).append((x, text))
    out = {}
    for cells in rows.values():
        if len(cells) == 2:
            (_, label), (_, value) = sorted(cells)
            out[label] = value
    return out


def _gcode_header(text):
    return [ln[1:-1] for ln in text.splitlines() if ln.startswith("(") and ln.endswith(")")]


def _programs(folder):
    """Both programs of the built cam, with report.json as their summary."""
    report = _report(folder)
    design = design_cam(CamSpec.from_dict(report["spec"]))
    plan = machining_plan(design)
    return (contour_program(design, plan, contour_path(design, plan), summary=report),
            rotary_program(design, plan, rotary_path(design, plan), summary=report))


def _cli_check_rows(folder, *sets, example="default"):
    """{check: [value, at, limit, status]} from `cam-workbench check`'s printed table."""
    res = run("check", "--example", example, *[a for s in sets for a in ("--set", s)],
              "-o", str(folder.parent / "check"))
    rows = {}
    for line in res.stdout.splitlines():
        if line.startswith("│"):
            cells = [c.strip() for c in line.strip("│").split("│")]
            m = re.match(r"(\w+) \((max|min)\)", cells[0])
            if m and len(cells) == 5:
                rows[m.group(1)] = cells[1:]
    return res, rows


@requires_ocp
def test_failing_check_fails_in_every_output(failing):
    report = _report(failing)
    checks = report["checks"]
    assert checks["passed"] is False and checks["failed"] == ["pressure_angle"]
    pa = checks["results"]["pressure_angle"]
    assert pa["value"] > pa["limit"] == 30.0 and pa["status"] == "fail"
    # HTML: the row is red, the verdict names it
    page = _page(failing)
    assert "fail" in page.rows["pressure_angle"]["attrs"]["class"].split()
    assert "design checks FAILED: pressure_angle" in page.verdict["text"]
    # DXF title block (the file build wrote)
    tb = _title_block(failing / "cam.dxf")
    assert tb["DESIGN CHECKS"] == "FAILED: pressure_angle"
    assert tb["MAX PRESSURE ANGLE"] == (f"{report['pressure_angle']['max_deg']:.2f}° AT "
                                        f"{report['pressure_angle']['at_deg']:.2f}° (LIMIT 30°)")
    assert tb["SPEC DIGEST (SHA-256)"] == report["spec_digest"]
    assert tb["PROFILE MAX ERROR"].startswith(f"{report['profile']['max_error']:.3e} mm")
    assert tb["MAX FOLLOWER DEVIATION"].startswith(f"{report['pitch']['max_deviation']:.3e} mm")
    # G-code headers
    for text in _programs(failing):
        head = _gcode_header(text)
        assert "design checks FAILED: pressure_angle" in head
        assert f"spec digest: {report['spec_digest']}" in head
        assert any(h.startswith(f"pressure angle: max {report['pressure_angle']['max_deg']:.2f} deg") for h in head)
        assert any(f"max follower deviation {report['pitch']['max_deviation']:.3g} mm" in h for h in head)
        assert any(f"max error {report['profile']['max_error']:.3g} mm" in h for h in head)
    # CLI check table (exit 3)
    res, rows = _cli_check_rows(failing, example="paper")
    assert res.returncode == 3
    assert rows["pressure_angle"][3].startswith("fail")
    assert rows["pressure_angle"][0] == f"{pa['value']:.3f}°" and rows["pressure_angle"][1] == f"{pa['at_deg']:.3f}°"
    assert rows["pressure_angle"][2] == "≤ 30.000°"
    assert "failed: pressure_angle" in res.stdout
    for name, r in checks["results"].items():
        assert rows[name][3].split()[0] == r["status"]
    # FreeCAD's check table, from the same dict
    table = {row[0]: row for row in checks_table(checks)}
    assert table["pressure angle"][4] == "fail"
    assert table["pressure angle"][1] == f"{pa['value']:.3f}°" and table["pressure angle"][3] == "≤ 30.000°"
    for name, r in checks["results"].items():
        row = table[name.replace("_", " ")]
        assert row[4] == r["status"] and row[5] == r["note"]
        if r["limit"] is not None:
            assert row[3].startswith(EXPECTED_SIGN[name] + " ")


@requires_ocp
def test_passing_cam_fails_nowhere(passing):
    report = _report(passing)
    checks = report["checks"]
    assert checks["passed"] is True and checks["failed"] == []
    page = _page(passing)
    assert page.verdict["attrs"]["class"] == "verdict pass" and "all pass" in page.verdict["text"]
    assert not any("fail" in r["attrs"]["class"].split() for r in page.rows.values())
    assert _title_block(passing / "cam.dxf")["DESIGN CHECKS"].startswith("ALL PASS")
    for text in _programs(passing):
        assert any(h.startswith("design checks: all pass") for h in _gcode_header(text))
        assert "FAILED" not in text
    res, rows = _cli_check_rows(passing, "cam.base_radius=60")
    assert res.returncode == 0 and all(r[3].split()[0] in ("pass", "skipped") for r in rows.values())
    assert [r[4] for r in checks_table(checks)] == [r["status"] for r in checks["results"].values()]


def test_gcode_without_summary_makes_no_claims(default_design):
    plan = machining_plan(default_design)
    text = contour_program(default_design, plan, contour_path(default_design, plan))
    head = _gcode_header(text)
    assert "design checks: not stated [program written without the report summary]" in head
    assert not any("all pass" in h or "FAILED" in h or "digest" in h for h in head)


# ---- no unqualified "exact" for a fitted B-spline ---------------------------------------------
#: phrases in which "exact" is true of a fitted cam: the reference a measured error is taken from
QUALIFIED = [r"not exact", r"exact offset of the fitted pitch b-spline", r"exact curve it was fitted to",
             r"profile is exact \(the exact offset of the pitch curve, or the pitch curve itself\)",
             r"exact curves of the motion laws"]


def _unqualified(text: str, word: str) -> list[str]:
    low = text.lower()
    for q in QUALIFIED:
        low = re.sub(q, "", low)
    return [low[max(0, m.start() - 60):m.end() + 60] for m in re.finditer(word, low)]


@requires_ocp
def test_bspline_outputs_claim_no_exactness(bspline):
    report = _report(bspline)
    prof = report["profile"]
    assert report["pitch"]["representation"] == "bspline" and prof["rational"] is False
    err = prof["fitted_vs_kernel_offset"]
    assert err > 0
    # HTML (tables, captions, the SVG plots' texts)
    page = _page(bspline)
    text = " ".join(page.text)
    assert not _unqualified(text, "exact"), _unqualified(text, "exact")[:3]
    # "rational" only as the table row saying it is not
    assert [m for m in _unqualified(text, "rational") if "profile nurbs rational" not in m] == []
    assert f"max error {err:.3g} mm from the exact offset of the fitted pitch B-spline" in text
    assert report["drawing"]["exact"] is False and report["drawing"]["profile_fit_error"] == err
    # DXF texts: title block, notes, dimension blocks
    doc = ezdxf.readfile(bspline / "cam.dxf")
    dxf_text = " ".join(e.dxf.text for e in doc.modelspace().query("TEXT MTEXT"))
    for blk in doc.blocks:
        dxf_text += " " + " ".join(e.dxf.text for e in blk if e.dxftype() in ("TEXT", "MTEXT"))
    assert not _unqualified(dxf_text, "exact"), _unqualified(dxf_text, "exact")[:3]
    assert "rational" not in dxf_text.lower()
    tb = _title_block(bspline / "cam.dxf")
    assert tb["PROFILE"] == "FITTED OFFSET, NOT EXACT"
    assert tb["PROFILE NURBS"] == f"B-SPLINE, DEGREE {prof['degree']}, {prof['poles']} POLES"
    # drawn as a cubic spline (the default), its distance measured from that NURBS, not called exact
    assert tb["DRAWN PROFILE ERROR"] == (f"MAX {report['drawing']['profile_max_error']:.2e} mm FROM THE PROFILE "
                                         f"NURBS (TOL. {report['spec']['drawing']['chord_tolerance']:g})")
    assert tb["PROFILE FIT ERROR"].startswith(f"{err:.3e} mm FROM THE EXACT OFFSET OF THE FITTED PITCH B-SPLINE")
    # the CLI's line on the drawing
    from cam_workbench.commands.dxf_cmd import describe

    line = describe(report["drawing"], "mm")
    assert not _unqualified(line, "exact") and "rational" not in line
    assert f"{err:.3g} mm" in line


def test_ph_claims_are_exact_where_true(default_design):
    """PH pitch: a roller's profile is the exact rational offset (degree 9), a knife edge's the
    PH pitch curve itself (polynomial degree 5) — said so in the DXF."""
    from cam_workbench.generators.checks.claims import profile_claim

    s = default_design.summary()
    c = profile_claim(s, True)
    assert c.exact and s["profile"]["degree"] == 9 and s["profile"]["rational"] is True
    assert c.text == "exact rational offset of the PH pitch curve (NURBS degree 9, rational)"
    knife = design_cam(default_spec().replace(**{"follower.kind": "knife"}))
    sk = knife.summary()
    ck = profile_claim(sk, False)
    assert ck.exact and sk["profile"]["degree"] == 5 and sk["profile"]["rational"] is False
    assert "rational" not in ck.text.replace("polynomial", "") and "exact" in ck.text
    doc, info = build_dxf(knife, sk)
    assert info.summary()["exact"] is False          # the default draws it as a cubic spline …
    texts = [t.dxf.text for t in doc.modelspace().query('TEXT[layer=="TITLE"]')]
    assert "THE PH PITCH CURVE, EXACT" in texts and f"B-SPLINE, DEGREE 5, {sk['profile']['poles']} POLES" in texts
    assert f"MAX {info.profile.max_error:.2e} mm FROM THE EXACT PROFILE (TOL. 0.001)" in texts
    assert not any("RATIONAL" in t for t in texts)
    exact = design_cam(knife.spec.replace(**{"drawing.curves": "spline"}))
    doc, info = build_dxf(exact, sk)
    assert info.summary()["exact"] is True           # … "spline" writes the exact curve itself
    texts = [t.dxf.text for t in doc.modelspace().query('TEXT[layer=="TITLE"]')]
    assert "SPLINE: THE NURBS ITSELF (ITS KNOTS, POLES, WEIGHTS)" in texts


# ---- the plots' limits -------------------------------------------------------------------------
def _figure_svg(html_text, key):
    i = html_text.index(f'id="fig-{key}"')
    return html_text[i:html_text.index("</figure>", i)]


def _axis_map(svg, key, axis):
    """Linear map from SVG coordinate to data value, fitted to the tick marks and their values."""
    pos, val = [], []
    for m in re.finditer(rf'<g id="{key}-p0-{axis}tick-\d+" data-value="([^"]+)"><line x1="([-\d.]+)" '
                         r'y1="([-\d.]+)"', svg):
        pos.append(float(m.group(2 if axis == "x" else 3)))
        val.append(float(m.group(1)))
    assert len(pos) >= 3
    a, b = np.polyfit(pos, val, 1)
    resid = np.max(np.abs(np.polyval([a, b], pos) - val))
    assert resid < 1e-4 * (max(val) - min(val))  # the ticks are evenly spaced: the map is linear
    return lambda p: a * p + b


def _hline_y(svg, gid):
    m = re.search(rf'<line id="{gid}" x1="([-\d.]+)" y1="([-\d.]+)" x2="([-\d.]+)" y2="([-\d.]+)"', svg)
    assert m, gid
    assert float(m.group(2)) == float(m.group(4))
    return float(m.group(2))


def _point(svg, gid):
    i = svg.index(f'<g id="{gid}"')
    m = re.search(r'<circle cx="([-\d.]+)" cy="([-\d.]+)"', svg[i:])
    return float(m.group(1)), float(m.group(2))


@requires_ocp
@pytest.mark.parametrize("cam", ["failing", "passing"])
def test_plot_limits_and_points_are_the_checks(cam, request):
    folder = request.getfixturevalue(cam)
    report = _report(folder)
    html_text = (folder / "report.html").read_text(encoding="utf-8")
    res = report["checks"]["results"]
    # pressure angle: ±limit dashed, |φ|max marked at its cam angle
    svg = _figure_svg(html_text, "pressure_angle")
    ymap, xmap = _axis_map(svg, "pressure_angle", "y"), _axis_map(svg, "pressure_angle", "x")
    lim = res["pressure_angle"]["limit"]
    tol = 2e-3 * lim  # SVG coordinates have 3 decimals of a point
    assert ymap(_hline_y(svg, "pressure_angle-limit-pressure_angle-upper")) == pytest.approx(lim, abs=tol)
    assert ymap(_hline_y(svg, "pressure_angle-limit-pressure_angle-lower")) == pytest.approx(-lim, abs=tol)
    x, y = _point(svg, "pressure_angle-point-pressure_angle")
    assert xmap(x) == pytest.approx(res["pressure_angle"]["at_deg"], abs=1e-3)
    assert abs(ymap(y)) == pytest.approx(res["pressure_angle"]["value"], abs=1e-3)
    at = res["pressure_angle"]["at_deg"]
    assert f"max |φ| = {res['pressure_angle']['value']:.2f}° at {at:.2f}°" in svg
    assert ("— FAILS" in svg) == (res["pressure_angle"]["status"] == "fail")
    assert f"limit |φ| ≤ {lim:g}° (checks.max_pressure_angle)" in svg
    # curvature: the check's limit (undercut_factor × roller radius) and value
    svg = _figure_svg(html_text, "curvature")
    ymap, xmap = _axis_map(svg, "curvature", "y"), _axis_map(svg, "curvature", "x")
    spec = report["spec"]
    lim = res["curvature"]["limit"]
    assert lim == pytest.approx(spec["checks"]["undercut_factor"] * spec["follower"]["roller_radius"])
    assert ymap(_hline_y(svg, "curvature-limit-curvature")) == pytest.approx(lim, abs=1e-4 * lim)
    assert ymap(_hline_y(svg, "curvature-limit-undercut")) == pytest.approx(spec["follower"]["roller_radius"],
                                                                           abs=1e-4 * lim)
    x, y = _point(svg, "curvature-point-curvature")
    assert xmap(x) == pytest.approx(res["curvature"]["at_deg"], abs=1e-3)
    assert ymap(y) == pytest.approx(res["curvature"]["value"], abs=1e-3)
    assert f"curvature limit: convex pitch ρ ≥ {lim:g} mm" in svg


# ---- DXF: dimension texts and the title block --------------------------------------------------
PACKAGING = {"cam.base_radius": 32.0, "follower.roller_radius": 8.0, "motion[1].lift": 15.0,
             "motion[3].lift": 15.0, "cam.speed_rpm": 300.0}
INCH = {"units": "in", "cam.thickness": 0.5, "cam.base_radius": 2.0, "follower.offset": 0.3,
        "follower.roller_radius": 0.25, "cam.bore_diameter": 0.5, "motion[1].lift": 0.8, "motion[3].lift": 0.8}
CAMS = {
    "default": {},
    "packaging_300rpm": PACKAGING,
    # these two put the old layout's "R38.486 MAX" text into its title block
    "packaging_long_dwell": {**PACKAGING, "motion[1].angle": 90.0, "motion[3].angle": 90.0, "motion[4].angle": 90.0},
    "packaging_cw": {**PACKAGING, "cam.direction": "cw", "motion[0].angle": 90.0, "motion[1].angle": 90.0,
                     "motion[3].angle": 90.0, "motion[4].angle": 30.0},
    "inch": INCH,
    "inch_large": {**INCH, "cam.base_radius": 8.0, "motion[1].lift": 1.5, "motion[3].lift": 1.5},
    "large_mm": {"cam.base_radius": 150.0, "follower.roller_radius": 20.0, "cam.bore_diameter": 40.0,
                 "motion[1].lift": 60.0, "motion[3].lift": 60.0},
    "small_mm": {"cam.base_radius": 12.0, "follower.roller_radius": 3.0, "follower.offset": 2.0,
                 "cam.bore_diameter": 4.0, "motion[1].lift": 5.0, "motion[3].lift": 5.0},
    "cw_knife": {"cam.direction": "cw", "follower.kind": "knife"},
    "big_text": {"drawing.text_height": 6.0},
}


def _overlap(a, b) -> bool:
    return a.extmin.x < b.extmax.x and b.extmin.x < a.extmax.x and a.extmin.y < b.extmax.y and b.extmin.y < a.extmax.y


@pytest.mark.parametrize("name", sorted(CAMS))
def test_dimension_texts_never_overlap_the_title_block(name, tmp_path):
    design = design_cam(default_spec().replace(**CAMS[name]))
    doc, _ = build_dxf(design)
    path = tmp_path / f"{name}.dxf"
    doc.saveas(str(path))
    doc = ezdxf.readfile(path)
    msp = doc.modelspace()
    title = bbox.extents(msp.query('TEXT LINE[layer=="TITLE"]'), fast=False)
    frame = bbox.extents(msp.query('LWPOLYLINE[layer=="TITLE"]'))
    assert title.has_data and frame.has_data
    dims = msp.query("DIMENSION")
    assert len(dims) == (3 if design.spec.cam.bore_diameter > 0 else 2)
    for dim in dims:
        block = doc.blocks.get(dim.dxf.geometry)
        texts = [e for e in block if e.dxftype() in ("MTEXT", "TEXT")]
        assert texts, dim.dxf.geometry
        box = bbox.extents(texts, fast=False)
        assert not _overlap(box, title), (name, [t.plain_text() if t.dxftype() == "MTEXT" else t.dxf.text
                                                 for t in texts], box, title)
        whole = bbox.extents(block, fast=False)
        assert frame.inside(whole.extmin) and frame.inside(whole.extmax)
    # nothing else (cam, circles, centre lines, notes) reaches into the title block either
    others = bbox.extents([e for e in msp if e.dxf.layer != "TITLE" and e.dxftype() != "DIMENSION"], fast=False)
    assert not _overlap(others, title)
    assert frame.inside(others.extmin) and frame.inside(others.extmax)
    assert frame.inside(title.extmin) and frame.inside(title.extmax)
    # the title block's texts stay inside its own border lines
    lines = bbox.extents(msp.query('LINE[layer=="TITLE"]'))
    texts = bbox.extents(msp.query('TEXT[layer=="TITLE"]'), fast=False)
    assert lines.extmin.x <= texts.extmin.x and texts.extmax.x <= lines.extmax.x

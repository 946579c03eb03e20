"""report.html: one self-contained file that parses, holds every plot (inline SVG, and the PNG
beside it), shows exactly report.json's numbers in its tables, grows the optional sections
only when their data is there, and renders in a real browser (headless Chromium) — the
screenshot is left in test-artifacts/ to be looked at."""
import json
import re
import os
import shutil
import subprocess
import sys
from html.parser import HTMLParser

import numpy as np
import pytest

from cam_workbench.exporters.report_cells import lookup
from cam_workbench.exporters.report_html import Series, render_report, report_plots
from cam_workbench.generators import default_spec, design_cam

from .conftest import ROOT, SAFETY_S, requires_ocp, paper_args

CLI = [sys.executable, "-m", "cam_workbench.cli"]
VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source", "track", "wbr"}


def run(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([*CLI, *paper_args(args)], capture_output=True, text=True, env=env)


class Page(HTMLParser):
    """A strict-enough parse: balanced tags, and what the tests look at."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.stack: list[str] = []
        self.errors: list[str] = []
        self.cells: list[tuple[dict, str]] = []      # (attrs, text) of td[data-key]
        self.figures: dict[str, int] = {}             # figure id → number of <svg> inside
        self.ids: list[str] = []
        self.resources: list[str] = []                # attributes that would load something
        self.tags: set[str] = set()
        self._cell: dict | None = None
        self._text: list[str] = []
        self._figure: str | None = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self.tags.add(tag)
        if "id" in a:
            self.ids.append(a["id"])
        for k in ("src", "href", "xlink:href", "data", "poster", "srcset"):
            v = a.get(k)
            if v is not None and not v.startswith("#"):
                self.resources.append(f"{tag} {k}={v[:60]}")
        if "url(" in (a.get("style") or "") and "url(#" not in a["style"]:
            self.resources.append(f"{tag} style url")
        if tag == "figure":
            self._figure = a.get("id")
            self.figures[self._figure] = 0
        if tag == "svg" and self._figure:
            self.figures[self._figure] += 1
        if tag == "td" and "data-key" in a:
            self._cell, self._text = a, []
        if tag not in VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag, attrs):
        self.tags.add(tag)
        a = dict(attrs)
        if "id" in a:
            self.ids.append(a["id"])

    def handle_endtag(self, tag):
        if tag in VOID:
            return
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"unexpected </{tag}> (open: {self.stack[-3:]})")
            return
        self.stack.pop()
        if tag == "td" and self._cell is not None:
            self.cells.append((self._cell, "".join(self._text).strip()))
            self._cell = None
        if tag == "figure":
            self._figure = None

    def handle_data(self, data):
        if self._cell is not None:
            self._text.append(data)


def parse(text: str) -> Page:
    page = Page()
    page.feed(text)
    page.close()
    return page


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """`cam-workbench build` of the default cam (what `make demo` does)."""
    out = tmp_path_factory.mktemp("demo") / "out"
    res = run("build", "-o", str(out))
    assert res.returncode == 0, res.stderr
    return out


pytestmark = requires_ocp


def test_build_writes_every_file(built):
    report = json.loads((built / "report.json").read_text())
    files = report["files"]
    assert files["dxf"] == "cam.dxf" and files["html"] == "report.html" and files["report"] == "report.json"
    listed = {v for v in files.values() if isinstance(v, str)}
    listed |= {x for v in files.values() if isinstance(v, list) for x in v}
    assert {"cam.step", "cam.dxf", "report.json", "report.html", "cam.nc", "commands.csv"} <= listed
    # report.json lists exactly what was written, beside the folder's manifest: no PNG without --plots
    assert {p.name for p in built.iterdir()} == listed | {".cam-workbench.json"}
    assert files["plots"] == [] and not list(built.glob("*.png"))
    # drawn as cubic splines within the tolerance (the default), so not the exact curve itself
    assert report["drawing"]["curves"] == "cubic" and report["drawing"]["exact"] is False
    assert 0 < report["drawing"]["profile_max_error"] <= report["drawing"]["chord_tolerance"]
    assert report["spec"]["cam"]["base_radius"] == pytest.approx(22.360679775)


def test_html_parses_and_is_self_contained(built):
    text = (built / "report.html").read_text(encoding="utf-8")
    page = parse(text)
    assert not page.errors, page.errors[:5]
    assert page.stack == [], page.stack
    assert text.startswith("<!DOCTYPE html>")
    assert not page.resources, page.resources[:5]
    assert not {"script", "link", "img", "iframe", "object"} & page.tags
    assert "@import" not in text
    assert len(page.ids) == len(set(page.ids)), "ids must be unique across the inlined SVGs"


FIGURES = ("cam", "kinematics", "pressure_angle", "curvature", "deviation",
           "interpolator_kinematics", "interpolator_deviation")


def test_every_plot_is_in_the_page(built):
    page = parse((built / "report.html").read_text(encoding="utf-8"))
    assert set(page.figures) == {f"fig-{key}" for key in FIGURES}
    for key in FIGURES:
        assert page.figures.get(f"fig-{key}") == 1, (key, page.figures)
    for section in ("cam", "spec", "motion", "pressure", "curvature", "accuracy", "drawing", "files"):
        assert section in page.ids


def test_table_numbers_equal_report_json(built):
    report = json.loads((built / "report.json").read_text())
    page = parse((built / "report.html").read_text(encoding="utf-8"))
    seen = set()
    assert len(page.cells) > 60
    for attrs, text in page.cells:
        key = attrs["data-key"]
        value = lookup(report, key)
        seen.add(key)
        if "data-value" not in attrs:  # text cells
            assert text == value, key
            continue
        raw = attrs["data-value"]
        if value is None:
            assert raw == "null" and text == "—", key
        elif isinstance(value, bool):
            assert raw == ("true" if value else "false") and text == ("yes" if value else "no"), key
        else:
            assert float(raw) == value, key                      # exactly the JSON number
            assert float(text) == pytest.approx(value, rel=5e-6, abs=0), key   # shown to 6 digits
    for key in ("pitch.max_deviation", "pitch.max_deviation_at_deg", "pressure_angle.max_deg",
                "pressure_angle.as_built.max_deg", "curvature.min_pitch_radius", "curvature.min_profile_radius",
                "motion.max_velocity", "motion.max_acceleration", "motion.max_jerk", "area", "volume",
                "solid.kernel_volume", "solid.cross_section_area", "profile.max_radius",
                "drawing.profile_max_error", "spec.cam.base_radius", "spec.motion.1.lift", "spec.motion.3.law",
                "pitch.newton_residual", "solid.volume_rel_diff", "solid.area_rel_diff"):
        assert key in seen, key


def _fake_extras():
    """Hand-written check results (report.json's checks format: DesignChecks.to_dict()) and
    optimiser history (these exercise the renderer only; the product never invents them)."""
    def res(kind, value, at, limit, unit, status):
        return {"description": "hand-written", "kind": kind, "value": value, "at_deg": at, "limit": limit,
                "unit": unit, "status": status, "passed": status != "fail", "note": ""}

    checks = {
        "passed": False, "failed": ["pressure_angle"], "sampling": "dense", "samples_per_segment": 1001,
        "points": 2008,
        "results": {
            "pressure_angle": res("max", 46.2, 282.8, 30.0, "deg", "fail"),
            "contact_stress": res("max", 812.5, 111.2, 1100.0, "MPa", "pass"),
            "separation": res("min", 35.0, 12.0, 0.0, "N", "pass"),
        },
        "extremes": {"force": {"value": 140.0, "at_deg": 80.0, "unit": "N"}},
    }
    history = [{"iteration": i, "objective": 2400.0 - 30 * i + i * i, "max_violation": 10.0 ** (-i)}
               for i in range(12)]
    return checks, {"objective": "area", "evaluations": 57, "history": history}


def test_optional_sections_only_with_their_data(tmp_path):
    design = design_cam(default_spec())
    report = json.loads(json.dumps({**design.summary(), "spec": design.spec.to_dict()}))
    report.pop("checks", None)  # the design-check section comes with its data (test below)
    base_keys = [p.key for p in report_plots(design, report)]
    assert base_keys == ["cam", "kinematics", "pressure_angle", "curvature", "deviation"]
    text, pngs = render_report(design, report)
    page = parse(text)
    for absent in ("checks", "optimise", "force", "drawing"):
        assert absent not in page.ids
    assert pngs == {} and set(page.figures) == {f"fig-{k}" for k in base_keys}

    checks, optimise = _fake_extras()
    report2 = dict(report, checks=checks, optimise=optimise)
    th = np.linspace(0, 360, 721)
    series = {"contact_force": Series(th, 100 + 20 * np.sin(np.deg2rad(th)), "contact force", "N", 150.0, "max"),
              "contact_stress": Series(th, 700 + 100 * np.cos(np.deg2rad(th)), "Hertz stress", "MPa", 1100.0, "max")}
    text2, pngs2 = render_report(design, report2, series, pngs=True)
    page2 = parse(text2)
    assert not page2.errors
    for present in ("checks", "optimise", "force", "fig-force_stress", "fig-convergence"):
        assert present in page2.ids
    assert sorted(pngs2) == sorted(f"plot_{k}.png" for k in (*base_keys, "force_stress", "convergence"))
    assert all(png[:8] == b"\x89PNG\r\n\x1a\n" for png in pngs2.values())
    assert text2.count('class="fail" data-key="checks.results.') == 1
    assert text2.count('class="pass" data-key="checks.results.') == 2
    assert "design checks FAILED: pressure_angle" in text2
    for attrs, cell in page2.cells:
        if attrs["data-key"].startswith(("checks.", "optimise.")) and "data-value" in attrs:
            assert float(attrs["data-value"]) == lookup(report2, attrs["data-key"])
    assert "optimise.evaluations" in {a["data-key"] for a, _ in page2.cells}
    (tmp_path / "r.html").write_text(text2)


def test_report_command_and_bad_input(tmp_path):
    out = tmp_path / "rep"
    res = run("report", "--plots", "--set", "drawing.title=Indexing cam", "-o", str(out))
    assert res.returncode == 0, res.stderr
    names = {p.name for p in out.iterdir()}
    report = json.loads((out / "report.json").read_text())
    assert {f"plot_{k}.png" for k in FIGURES} == set(report["files"]["plots"])
    assert {"report.html", "report.json", *report["files"]["plots"]} <= names and "cam.step" not in names
    for name in report["files"]["plots"]:          # each the page's figure rasterised: as wide as its SVG
        data = (out / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
        svg = re.search(rf'<figure id="fig-{name[5:-4]}"[^>]*><svg [^>]*viewBox="0 0 ([\d.]+) ',
                        (out / "report.html").read_text())
        assert int.from_bytes(data[16:20], "big") == round(float(svg.group(1)) * 1.6)
    assert "<h1>Indexing cam</h1>" in (out / "report.html").read_text()
    bad = run("report", "--set", "cam.thickness=0", "-o", str(tmp_path / "bad"))
    assert bad.returncode == 2 and "cam.thickness: must be > 0" in bad.stderr
    assert not (tmp_path / "bad").exists()


def test_inch_report_units(tmp_path):
    res = run("report", "--set", "units=in", "--set", "cam.thickness=0.5", "--set", "cam.base_radius=2.0",
              "--set", "follower.offset=0.3", "--set", "follower.roller_radius=0.25",
              "--set", "cam.bore_diameter=0.5", "--set", "motion[1].lift=0.8", "--set", "motion[3].lift=0.8",
              "-o", str(tmp_path / "in"))
    assert res.returncode == 0, res.stderr
    text = (tmp_path / "in" / "report.html").read_text()
    assert "in/s²" in text and "µin" in text and "mm/s" not in text


CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


@pytest.mark.skipif(CHROMIUM is None, reason="Debian package chromium is not installed (make test installs it as root)")
def test_renders_in_headless_chromium(built, artifacts, tmp_path):
    shot = artifacts / "report.png"
    if shot.exists():
        shot.unlink()
    base = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync"]
    uri = (built / "report.html").resolve().as_uri()
    cmd = [*base, f"--user-data-dir={tmp_path / 'profile'}", f"--screenshot={shot}", "--window-size=1280,4000",
           "--hide-scrollbars", uri]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=SAFETY_S)
    assert res.returncode == 0, res.stderr[-2000:]
    import matplotlib.pyplot as plt

    img = plt.imread(shot)
    assert img.shape[:2] == (4000, 1280)
    rgb = img[..., :3]
    assert rgb.std() > 0.1                                    # a page, not a blank
    # the page's white <main> column is there and drawn on (plots, tables: dark pixels)
    main = rgb[:, 200:1080]
    assert (main.mean(axis=2) < 0.4).mean() > 0.01
    # the DOM Chromium built has every figure with its SVG
    dom = subprocess.run([*base, f"--user-data-dir={tmp_path / 'profile2'}", "--dump-dom", uri],
                         capture_output=True, text=True, timeout=SAFETY_S)
    assert dom.returncode == 0
    report = json.loads((built / "report.json").read_text())
    for key in FIGURES:
        assert f'id="fig-{key}"' in dom.stdout
    assert dom.stdout.count("<svg") >= len(FIGURES) and report["files"]["plots"] == []


def test_interpolator_section_matches_report_json(built):
    """build's report.html has the rotational-interpolator section (paper Table 2 quantities)
    with the numbers of report.json and both interpolator figures."""
    report = json.loads((built / "report.json").read_text())
    page = parse((built / "report.html").read_text())
    assert "interpolator" in page.ids
    assert "fig-interpolator_kinematics" in page.ids and "fig-interpolator_deviation" in page.ids
    it = report["interpolator"]
    cells = {a["data-key"]: a.get("data-value") for a, _ in page.cells}
    for key in ("interpolator.max_deviation", "interpolator.acceleration.max", "interpolator.jerk.max"):
        value = key.split(".")
        expect = it
        for part in value[1:]:
            expect = expect[part]
        assert float(cells[key]) == expect
    assert report["files"]["plots"] == []


BUILD_WITHOUT_MATPLOTLIB = """
import runpy, sys
sys.argv = ["cam-workbench", "build", "--example", "{example}", "-o", {out!r}]
try:
    runpy.run_module("cam_workbench.cli", run_name="__main__")
except SystemExit as exc:
    assert exc.code in (0, None), exc.code
print(sorted(m for m in sys.modules if m.split(".")[0] in ("matplotlib", "cairosvg")))
"""


@pytest.mark.parametrize("example", ["default", "cylindrical"])
def test_build_draws_its_figures_without_matplotlib(tmp_path, example):
    """The report's figures are our own SVG: a build imports neither matplotlib nor CairoSVG."""
    out = tmp_path / "out"
    res = subprocess.run([sys.executable, "-c", BUILD_WITHOUT_MATPLOTLIB.format(example=example, out=str(out))],
                         capture_output=True, text=True, timeout=SAFETY_S, cwd=ROOT)
    assert res.returncode == 0, res.stderr[-2000:]
    assert res.stdout.strip().splitlines()[-1] == "[]"
    assert (out / "report.html").read_text(encoding="utf-8").count("<svg") >= 2


def test_plots_without_cairosvg_is_refused_before_anything_is_written(tmp_path):
    """--plots without CairoSVG: exit 2 naming the extra, nothing created (a blocker on import)."""
    block = tmp_path / "block"
    block.mkdir()
    (block / "cairosvg.py").write_text("raise ImportError('no cairosvg here')\n")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(block), str(ROOT)])}
    out = tmp_path / "out"
    res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "report", "--plots", "-o", str(out)],
                         capture_output=True, text=True, timeout=SAFETY_S, env=env)
    assert res.returncode == 2 and "Traceback" not in res.stderr, res.stderr
    assert "cam-workbench[png]" in res.stderr and not out.exists()

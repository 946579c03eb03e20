"""report.html of a parallel indexer (exporters/report_indexer.py): the page renders as one
self-contained file; every number it shows (the checks', the indexer's, the drive's) is exactly
report.json's; a failing check is shown as failing; each figure is in the page with its SVG (and
as a PNG with ``plots``); without a load the drive is left out; headless Chromium loads it without
a console message."""
import json
import shutil
import subprocess

import pytest

from cam_workbench.exporters.output_rule import Claim
from cam_workbench.exporters.report_cells import lookup
from cam_workbench.exporters.report_indexer import ParallelIndexerPage
from cam_workbench.exporters.report_pages import report_page
from cam_workbench.generators.checks.claims import checks_verdict
from cam_workbench.generators.spec.examples import PARALLEL_INDEXER_SPEC_DICT
from cam_workbench.generators.spec.model import CamSpec
from cam_workbench.pipeline import run_pipeline, write_outputs

from .conftest import SAFETY_S
from .test_report import parse

SPEC = CamSpec.from_dict(PARALLEL_INDEXER_SPEC_DICT)
DRIVE_KEYS = ("index_time_s", "dwell_time_s", "output_acceleration_peak_rad_s2", "output_velocity_peak_rad_s",
              "output_torque_peak_Nm", "input_torque_peak_Nm", "input_power_peak_W", "normal_force_peak_N",
              "contact_stress_peak_Pa", "l10_million_rev", "l10_hours",
              "characteristics.C_v", "characteristics.C_a", "characteristics.C_j")
INDEXER_KEYS = ("indexer.geometry.stations", "indexer.geometry.index_angle_deg", "indexer.geometry.centre_distance_mm",
                "indexer.geometry.pitch_radius_mm", "indexer.geometry.roller_radius_mm", "body.cams",
                "indexer.geometry.clearance_mm", "body.flank_fit_error.value",
                "indexer.motion_from_geometry.max_error_rad")


def _write(spec, folder, plots=False):
    """run_pipeline without the solid, machining and drawing, then report.json/report.html (and PNGs)."""
    out = run_pipeline(spec, solid=False, machining=False, drawing=False)
    page = report_page(out.design, out.summary)
    report = write_outputs(out, folder, Claim("test"), plots=plots)
    text = (folder / "report.html").read_text(encoding="utf-8")
    assert report == json.loads((folder / "report.json").read_text())
    return report, text, page


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    folder = tmp_path_factory.mktemp("indexer") / "r"
    plots = _has_png()
    report, text, page = _write(SPEC, folder, plots=plots)
    return folder, report, text, page, plots


def _has_png() -> bool:
    try:
        from cam_workbench.exporters.chart_png import require_png
        require_png()
        return True
    except Exception:
        return False


def _cells(page) -> dict[str, tuple[dict, str]]:
    return {attrs["data-key"]: (attrs, shown) for attrs, shown in page.cells}


def test_page_renders_self_contained(written):
    _, report, text, page, _ = written
    assert isinstance(page, ParallelIndexerPage)
    html = parse(text)
    assert not html.errors and html.stack == [], (html.errors[:5], html.stack)
    assert not html.resources, html.resources[:5]
    assert not {"script", "link", "iframe", "object"} & html.tags
    assert len(html.ids) == len(set(html.ids)), "ids must be unique across the inlined SVGs"
    for sid in ("checks", "indexer", "accuracy", "motion", "drive"):
        assert sid in html.ids, sid
    assert report["follower"]["label"] in text


def test_every_number_is_report_json(written):
    """Each td[data-key] holds exactly report.json's value (data-value) and shows it to 6 digits;
    the checks' and the drive's numbers are all there."""
    _, report, text, _, _ = written
    cells = _cells(parse(text))
    for key, (attrs, shown) in cells.items():
        value = lookup(report, key)
        if "data-value" in attrs:
            if value is None or isinstance(value, bool):
                assert attrs["data-value"] == json.dumps(value), key
            else:
                assert float(attrs["data-value"]) == value, key
                assert float(shown) == pytest.approx(value, rel=5e-6), key
        else:
            assert shown == str(value), key
    for name, r in report["checks"]["results"].items():
        for field in ("value", "limit", "at_deg", "status"):
            assert f"checks.results.{name}.{field}" in cells, (name, field)
        assert cells[f"checks.results.{name}.status"][1] == r["status"]
    drive = report["indexer"]["drive"]
    assert drive is not None
    for key in DRIVE_KEYS:
        assert lookup(drive, key) is not None and f"indexer.drive.{key}" in cells, key
    for key in INDEXER_KEYS:
        assert key in cells, key
    assert checks_verdict(report["checks"]) in text and "verdict pass" in text


def test_flanks_are_fitted_not_exact(written):
    _, report, text, _, _ = written
    html = parse(text)
    label = next(t for t in text.split("<tr>") if 'data-key="body.flank_fit_error.value"' in t)
    assert "fitted within" in label and "not exact" in label
    assert 'id="flank-claim" data-exact="false"' in text and "flank-claim" in html.ids
    assert report["body"]["flank_fit_error"]["value"] > 0


def test_failing_check_is_shown_failing(tmp_path):
    report, text, _ = _write(SPEC.replace(**{"indexer.max_pressure_angle": 50.0}), tmp_path / "fail")
    assert report["checks"]["passed"] is False and "pressure_angle" in report["checks"]["failed"]
    assert 'class="verdict fail"' in text and 'data-failed="pressure_angle"' in text
    assert checks_verdict(report["checks"]) in text
    assert 'class="check fail" data-check="pressure_angle" data-status="fail"' in text
    cells = _cells(parse(text))
    attrs, shown = cells["checks.results.pressure_angle.status"]
    assert shown == "fail" and attrs.get("class") == "fail"
    assert float(cells["checks.results.pressure_angle.limit"][0]["data-value"]) == 50.0
    assert float(cells["checks.results.pressure_angle.value"][0]["data-value"]) == \
        report["checks"]["results"]["pressure_angle"]["value"]
    for name in report["checks"]["results"]:     # the others as they are
        if name != "pressure_angle":
            assert f'data-check="{name}" data-status="fail"' not in text, name


def test_figures_present(written):
    folder, report, text, page, plots = written
    html = parse(text)
    assert len(page.figures) == 4
    shown = {k: n for k, n in html.figures.items() if k}
    assert len(shown) == len(page.figures) and text.count("<svg") == len(page.figures)
    for name in page.figures:
        assert shown.get(f"fig-{name[5:-4]}") == 1, name
        assert f'data-png="{name}"' in text
    if plots:
        assert report["files"]["plots"] == page.figures
        for name in page.figures:
            assert (folder / name).stat().st_size > 10000, name


def test_without_a_load_no_drive(tmp_path):
    report, text, page = _write(SPEC.replace(**{"indexer.output_inertia": None}), tmp_path / "noload")
    assert report["indexer"]["drive"] is None
    html = parse(text)
    assert not html.errors
    assert "plot_torque.png" not in page.figures and len(page.figures) == 3
    assert len([k for k in html.figures if k]) == 3 and text.count("<svg") == 3
    assert 'id="no-drive"' in text
    assert not any(a["data-key"].startswith("indexer.drive") for a, _ in html.cells)


def test_without_a_rating_no_life(tmp_path):
    report, text, _ = _write(SPEC.replace(**{"indexer.roller_rating": None}), tmp_path / "norating")
    drive = report["indexer"]["drive"]
    assert "l10_hours" not in drive and "l10_note" in drive
    keys = {a["data-key"] for a, _ in parse(text).cells}
    assert "indexer.drive.l10_hours" not in keys and "indexer.drive.output_torque_peak_Nm" in keys
    assert 'data-key="indexer.drive.l10_note"' in text


CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


@pytest.mark.skipif(CHROMIUM is None, reason="Debian package chromium is not installed (make test installs it as root)")
def test_loads_in_headless_chromium_without_console_messages(written, tmp_path):
    folder, _, _, page, _ = written
    res = subprocess.run([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                          "--disable-background-networking", "--disable-component-update", "--disable-sync",
                          f"--user-data-dir={tmp_path / 'profile'}", "--enable-logging=stderr", "--v=0",
                          "--dump-dom", (folder / "report.html").resolve().as_uri()],
                         capture_output=True, text=True, timeout=SAFETY_S)
    assert res.returncode == 0, res.stderr[-2000:]
    console = [ln for ln in res.stderr.splitlines() if ":CONSOLE" in ln]
    assert not console, console[:5]
    assert res.stdout.count("<svg") == len(page.figures)
    for name in page.figures:
        assert f'id="fig-{name[5:-4]}"' in res.stdout


def test_other_outputs_sections_show_report_json(written):
    """The solid's, the drawing's and the machining's sections (when their layers add them to
    report.json) are shown scalar by scalar, each cell report.json's value."""
    _, report, _, page, _ = written
    assert not {"solid", "drawing", "machining"} & set(report)      # not made here: no section
    extra = dict(report, drawing={"curves": "spline", "flank_error": {"value": 1.25e-5, "unit": "mm"}},
                 machining={"path_error": {"value": 2.5e-4, "cam": 0}})
    text, pngs = page.render(extra, None)
    assert pngs == {}
    html = parse(text)
    assert not html.errors and {"drawing", "machining"} <= set(html.ids) and "solid" not in html.ids
    cells = _cells(html)
    for key in ("drawing.flank_error.value", "machining.path_error.value", "machining.path_error.cam"):
        assert float(cells[key][0]["data-value"]) == lookup(extra, key), key
    assert cells["drawing.curves"][1] == "spline"

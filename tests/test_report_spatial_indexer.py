"""report.html of the spatial indexers (exporters/report_spatial_indexer.py), for the barrel and
the globoidal examples: the page renders as one self-contained file; every number it shows is
exactly report.json's, as the page formats it; the flanks are called fitted, never exact; the
pressure-angle figure draws the check against its limit; a failing check is shown failing; without
a load the drive is left out; the design's picture is registered for the API; headless Chromium
loads the page without a console message (the parallel indexer's test, reused)."""
import json
import math

import numpy as np
import pytest

from cam_workbench import Cam
from cam_workbench.exporters import chart_svg, plots
from cam_workbench.exporters.output_rule import Claim
from cam_workbench.exporters.report_cells import format_number, lookup
from cam_workbench.exporters.report_pages import report_page
from cam_workbench.exporters.report_spatial_indexer import SpatialIndexerPage, contacts_angle
from cam_workbench.generators.checks.claims import checks_verdict
from cam_workbench.pipeline import CamOutputs, summary_stage, write_outputs

from .test_report import parse
from .test_report_indexer import CHROMIUM, _cells, _has_png
from .test_report_indexer import test_loads_in_headless_chromium_without_console_messages as chromium_loads_cleanly

EXAMPLES = ("barrel_indexer", "globoidal_indexer")
GEO = "indexer.geometry"
CHECKS = ("pressure_angle", "pressure_angle_contacts", "undercut", "rib_thickness", "locking", "contact_stress")
DRIVE_KEYS = ("index_time_s", "dwell_time_s", "input_speed_rpm", "output_acceleration_peak_rad_s2",
              "output_velocity_peak_rad_s", "output_torque_peak_Nm", "input_torque_peak_Nm", "input_power_peak_W",
              "input_power_mean_index_W", "normal_force_peak_N", "contact_stress_peak_Pa", "l10_million_rev",
              "l10_hours", "characteristics.C_v", "characteristics.C_a", "characteristics.C_j")
GEOMETRY_KEYS = ("stations", "law", "index_angle_deg", "index_start_deg", "centre_distance", "roller_radius",
                 "roller_start", "roller_end", "root_radius", "cam_width", "locked",
                 "max_driving_pressure_angle.value_deg", "max_pressure_angle.value_deg",
                 "min_regularity_margin.value_1", "min_rib_thickness.value_mm", "windows.0.from_deg")
OWN_KEYS = {"barrel_indexer": ("pitch_radius", "outer_radius"), "globoidal_indexer": ("tip_radius",)}
OTHER_KEYS = ("body.flank_fit_error.value", "body.surfaces.tolerance_mm", "body.surfaces.flanks.0.max_error_mm",
              "body.surfaces.flanks.1.max_error_mm", "indexer.motion_from_geometry.max_error_rad",
              "indexer.motion_from_geometry.samples", "motion.advance_deg", "motion.max_velocity")


def _write(design, folder, plots=False):
    """design.summary() with the spec (the pipeline's summary_stage), then report.json/report.html
    (and PNGs) as the pipeline writes them."""
    summary = summary_stage(design)
    page = report_page(design, summary)
    report = write_outputs(CamOutputs(spec=design.spec, design=design, summary=summary), folder, Claim("test"),
                           plots=plots)
    text = (folder / "report.html").read_text(encoding="utf-8")
    assert report == json.loads((folder / "report.json").read_text())
    return report, text, page


@pytest.fixture(scope="module", params=EXAMPLES)
def written(request, tmp_path_factory):
    """(example name, design, folder, report, html text, page, plots) of each example."""
    design = Cam.example(request.param).design
    folder = tmp_path_factory.mktemp(request.param) / "r"
    with_png = _has_png()
    report, text, page = _write(design, folder, plots=with_png)
    return request.param, design, folder, report, text, page, with_png


def test_page_renders_self_contained(written):
    name, _, _, report, text, page, _ = written
    assert isinstance(page, SpatialIndexerPage)
    html = parse(text)
    assert not html.errors and html.stack == [], (html.errors[:5], html.stack)
    assert not html.resources, html.resources[:5]
    assert not {"script", "link", "iframe", "object"} & html.tags
    assert len(html.ids) == len(set(html.ids)), "ids must be unique across the inlined SVGs"
    for sid in ("checks", "indexer", "windows", "accuracy", "motion", "drive", "flank-claim", "recovered"):
        assert sid in html.ids, sid
    assert report["follower"]["label"] in text
    assert f"<h1>{name.split('_')[0].capitalize()} indexer — " in text


def test_every_number_is_report_json(written):
    """Each td[data-key] holds exactly report.json's value (data-value) and shows it as the page
    formats it; the checks', the geometry's, the flanks', the recovered motion's and the drive's
    numbers are all there."""
    name, _, _, report, text, _, _ = written
    cells = _cells(parse(text))
    for key, (attrs, shown) in cells.items():
        value = lookup(report, key)
        if "data-value" in attrs:
            if value is None or isinstance(value, bool):
                assert attrs["data-value"] == json.dumps(value), key
            else:
                assert float(attrs["data-value"]) == value, key
            assert shown == format_number(value), key
        else:
            assert shown == str(value), key
    assert set(report["checks"]["results"]) == set(CHECKS)
    for check, r in report["checks"]["results"].items():
        for field in ("value", "limit", "at_deg", "status"):
            assert f"checks.results.{check}.{field}" in cells, (check, field)
        assert cells[f"checks.results.{check}.status"][1] == r["status"]
    for key in (*GEOMETRY_KEYS, *OWN_KEYS[name]):
        assert f"{GEO}.{key}" in cells, key
    for key in OTHER_KEYS:
        assert key in cells, key
    for i, _ in enumerate(report[GEO.split(".")[0]]["geometry"]["windows"]):
        for field in ("roller_index", "side", "from_deg", "to_deg"):
            assert f"{GEO}.windows.{i}.{field}" in cells, (i, field)
    assert report["indexer"]["drive"] is not None
    for key in DRIVE_KEYS:
        assert lookup(report["indexer"]["drive"], key) is not None and f"indexer.drive.{key}" in cells, key
    assert checks_verdict(report["checks"]) in text and "verdict pass" in text


def test_flanks_are_fitted_not_exact(written):
    _, _, _, report, text, _, _ = written
    label = next(t for t in text.split("<tr>") if 'data-key="body.flank_fit_error.value"' in t)
    assert "fitted within" in label and "not exact" in label and "measured" in label
    assert 'id="flank-claim" data-exact="false"' in text and 'data-exact="true"' not in text
    assert 0 < report["body"]["flank_fit_error"]["value"] <= report["body"]["surfaces"]["tolerance_mm"]


def test_figures_present(written):
    _, _, folder, report, text, page, with_png = written
    html = parse(text)
    assert page.figures == ["plot_indexer.png", "plot_pressure_angle.png", "plot_motion.png", "plot_torque.png"]
    shown = {k: n for k, n in html.figures.items() if k}
    assert len(shown) == len(page.figures) and text.count("<svg") == len(page.figures)
    for name in page.figures:
        assert shown.get(f"fig-{name[5:-4]}") == 1, name
        assert f'data-png="{name}"' in text
    for ident in ('id="indexer-rib-p-', 'data-gid="turret-angle"', 'id="motion-psi"', 'id="motion-driving-angle"',
                  'id="torque-torque-out"', 'id="torque-contact-stress"'):
        assert ident in text, ident
    if with_png:
        assert report["files"]["plots"] == page.figures
        for name in page.figures:
            assert (folder / name).stat().st_size > 10000, name


def test_pressure_angle_figure_draws_the_check(written):
    """The driving contact's pressure angle over the index against the limit, the check's point,
    and the largest over every engaged contact — whose largest is the reported (unchecked) value."""
    _, design, _, report, text, _, _ = written
    fig = text[text.index('id="fig-pressure_angle"'):]
    fig = fig[:fig.index("</figure>")]
    for gid in ("driving-angle", "contacts-angle", "pressure-angle-limit", "pressure-angle-check"):
        assert f'id="pressure_angle-{gid}"' in fig, gid
    check = report["checks"]["results"]
    assert f"limit {check['pressure_angle']['limit']:g}°" in fig
    g = design.geometry
    assert math.degrees(np.nanmax(contacts_angle(g))) == pytest.approx(check["pressure_angle_contacts"]["value"],
                                                                       rel=1e-12)
    inside = slice(1, g.index_rows)
    assert math.degrees(np.nanmax(g.driving_angle[inside])) == pytest.approx(check["pressure_angle"]["value"],
                                                                            rel=1e-12)


def test_failing_check_is_shown_failing(tmp_path):
    design = Cam.example("barrel_indexer", **{"indexer.max_pressure_angle": 30.0}).design
    report, text, _ = _write(design, tmp_path / "fail")
    assert report["checks"]["passed"] is False and report["checks"]["failed"] == ["pressure_angle"]
    assert 'class="verdict fail"' in text and 'data-failed="pressure_angle"' in text
    assert checks_verdict(report["checks"]) in text
    assert 'class="check fail" data-check="pressure_angle" data-status="fail"' in text
    cells = _cells(parse(text))
    attrs, shown = cells["checks.results.pressure_angle.status"]
    assert shown == "fail" and attrs.get("class") == "fail"
    assert float(cells["checks.results.pressure_angle.limit"][0]["data-value"]) == 30.0
    assert float(cells["checks.results.pressure_angle.value"][0]["data-value"]) == \
        report["checks"]["results"]["pressure_angle"]["value"] > 30.0
    for name in report["checks"]["results"]:     # the others as they are
        if name != "pressure_angle":
            assert f'data-check="{name}" data-status="fail"' not in text, name
    assert "limit 30°" in text[text.index('id="fig-pressure_angle"'):]
    remedy = report["checks"]["results"]["pressure_angle"]["remedy"]      # the pipeline's summary_stage's
    assert 'data-key="checks.results.pressure_angle.remedy"' in text and remedy["text"][:20] in text


def test_without_a_load_no_drive(tmp_path):
    design = Cam.example("globoidal_indexer", **{"indexer.output_inertia": None}).design
    report, text, page = _write(design, tmp_path / "noload")
    assert report["indexer"]["drive"] is None and "contact_stress" not in report["checks"]["results"]
    html = parse(text)
    assert not html.errors
    assert "plot_torque.png" not in page.figures and len(page.figures) == 3
    assert len([k for k in html.figures if k]) == 3 and text.count("<svg") == 3
    assert 'id="no-drive"' in text
    assert not any(a["data-key"].startswith("indexer.drive") for a, _ in html.cells)


@pytest.mark.parametrize("name", EXAMPLES)
def test_picture_is_registered(name):
    """The API's picture (Jupyter's): the spatial picture of the geometry at the input angle asked."""
    cam = Cam.example(name)
    chart = plots.picture(cam.design, 200.0)
    svg = chart_svg.svg(chart, "cam")
    assert 'id="cam-rib-p-' in svg and 'data-gid="turret-angle"' in svg and "θ = 200.00°" in svg
    jupyter = cam._repr_svg_()
    assert jupyter is not None and "θ = 75.00°" in jupyter


@pytest.mark.skipif(CHROMIUM is None, reason="Debian package chromium is not installed (make test installs it as root)")
def test_loads_in_headless_chromium_without_console_messages(written, tmp_path):
    _, _, folder, report, text, page, _ = written
    chromium_loads_cleanly((folder, report, text, page, None), tmp_path)

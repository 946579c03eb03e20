"""Roughing from a round blank (``machining.blank_diameter``): the one XY program — roughing passes,
then the finishing contour — run through LinuxCNC's ``rs274`` and its canonical moves held against
the exact profile, computed here independently (the profile NURBS sampled densely):

* every rough pass stays ≥ its offset R + a + k·s (less the chord tolerance) from the profile,
  follows that offset wherever it is inside the blank circle, and runs on the circle
  r_blank + R elsewhere; the last pass is at R + a, the passes are s apart;
* no feed move leaves the circle r_blank + R + lead radius;
* every point of the blank outside the profile lies within R of a feed move at each level
  (all the stock is removed);
* the time estimate in the header is report.json's, and covers the roughing.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from matplotlib.path import Path as MplPath

from cam_workbench.exporters.gcode_roughing import roughing_xy_program
from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.machining import machining_plan
from cam_workbench.generators.machining.cutting_time import contour_time
from cam_workbench.generators.spec import default_spec
from cam_workbench.generators.spec.examples import example_spec

from .conftest import ROOT, requires_ocp
from .rs274 import PRINT_QUANTUM, polyline_distance, requires_rs274, run_rs274, sample_xy

PLATE_EXAMPLES = ("default", "paper", "oscillating", "flat", "packaging")


def profile_points(design, per_span: int = 400) -> np.ndarray:
    _, p = design.profile_ccw().sample(per_span)
    return p[:, 0] + 1j * p[:, 1]


def largest_profile_radius(design) -> float:
    return float(np.abs(profile_points(design, 50)).max())


def with_blank(spec, margin: float, **changes):
    """``spec`` with a blank ``margin`` larger in radius than its profile."""
    r = largest_profile_radius(design_cam(spec))
    return spec.replace(**{"machining.blank_diameter": round(2 * (r + margin), 3), **changes})


def check_program(spec, tmp_path, sample_step: float = 0.4) -> dict:
    design = design_cam(spec)
    plan = machining_plan(design)
    mc = spec.machining
    text, both = roughing_xy_program(design, plan)
    run = run_rs274(text, tmp_path, plan.tool_number, 2 * plan.tool_radius)
    assert run.units == spec.units
    R = plan.tool_radius
    a = mc.finish_allowance if mc.finish_allowance is not None else 0.2
    s = (mc.stepover if mc.stepover is not None else 0.5) * 2 * R
    r_blank = mc.blank_diameter / 2
    tol = plan.chord_tolerance + 2 * PRINT_QUANTUM
    profile = profile_points(design)
    inside_profile = MplPath(np.column_stack([profile.real, profile.imag]))

    # no roughing move at feed beyond the blank circle + R + the lead radius (the plunge point)
    feeds = [m for m in run.motions if m.kind != "traverse"]
    roughing = [m for m in feeds if m.tag.startswith(("roughing level", "in-feed", "rough pass", "step-in"))]
    reach = max(np.abs(sample_xy([m])).max() for m in roughing)
    assert reach <= r_blank + R + plan.lead_radius + PRINT_QUANTUM
    assert not any(m.kind == "traverse" and m.end[2] < 0 and m.start[2] < 0 for m in run.motions)

    levels = plan.z_levels
    measured = []
    for li, z in enumerate(levels):
        passes = [run.tagged(t) for t in dict.fromkeys(m.tag for m in run.motions if m.tag.startswith("rough pass"))]
        passes = [[m for m in p[li] if m.kind != "traverse"] for p in passes]      # without the retract
        offsets = []
        for k, motions in enumerate(passes):
            assert all(abs(m.end[2] - z) < 1e-9 for m in motions)
            pts = sample_xy(motions)
            assert abs(pts[-1] - pts[0]) <= 2 * PRINT_QUANTUM                 # closed
            dist = polyline_distance(pts, profile)
            d_k = R + a + (len(passes) - 1 - k) * s
            on_circle = np.abs(np.abs(pts) - (r_blank + R)) <= 2 * PRINT_QUANTUM
            off = ~on_circle
            assert off.any()
            # on the offset: at least d_k from the profile; on the circle (the tool only touches the
            # blank there) never into the allowance
            assert dist[off].min() >= d_k - tol, (k, dist[off].min(), d_k)
            assert dist.min() >= R + a - tol
            # on the offset inside the blank circle, on the circle elsewhere
            assert np.all(dist[off] <= d_k + tol), (k, dist[off].max(), d_k)
            assert np.all(np.abs(pts[off]) <= r_blank + R + tol)
            offsets.append(float(np.median(dist[off])))
            area = 0.5 * np.sum((np.conj(pts[:-1]) * pts[1:]).imag)
            assert (area < 0) == (plan.milling == "climb")
        # the last pass leaves the allowance; the passes are the step-over apart
        assert offsets[-1] == pytest.approx(R + a, abs=tol)
        assert np.allclose(-np.diff(offsets), s, atol=2 * tol)
        measured.append(offsets)
        # the stock: every point of the blank outside the profile lies within R of a feed move at this level
        cut = np.concatenate([sample_xy([m], 256) for m in feeds if abs(m.end[2] - z) < 1e-9
                              and abs(m.start[2] - z) < 1e-9])
        g = np.arange(-r_blank, r_blank + sample_step, sample_step)
        xy = (g[:, None] + 1j * g[None, :]).ravel()
        xy = xy[np.abs(xy) <= r_blank]
        xy = xy[~inside_profile.contains_points(np.column_stack([xy.real, xy.imag]))]
        gap = polyline_distance(xy, cut)
        assert gap.max() <= R + 1e-3, f"stock left at {xy[np.argmax(gap)]}: {gap.max():.4g} from the cuts"
    # the finishing contour runs after the roughing at R from the profile
    loops = run.tagged("contour")
    assert len(loops) == plan.passes
    first_contour = next(i for i, m in enumerate(run.motions) if m.tag == "contour")
    last_rough = max(i for i, m in enumerate(run.motions) if m.tag.startswith("rough pass"))
    assert last_rough < first_contour
    for loop in loops:
        dist = polyline_distance(sample_xy(loop), profile)
        assert np.all(np.abs(dist - R) <= tol)
    # the header's time estimate is the cutting-time model's, and it covers the roughing
    whole = contour_time(design, plan)
    assert f"whole program {whole.time:.1f} s" in text
    assert both.rough_time.time > 0 and whole.time == pytest.approx(
        both.rough_time.time + contour_time(design_cam(spec.replace(**{"machining.blank_diameter": None})),
                                            plan).time)
    return {"offsets": measured, "passes": len(measured[0])}


pytestmark = requires_rs274


@pytest.mark.parametrize("name", PLATE_EXAMPLES)
def test_roughing_program_of_each_plate_example(tmp_path, name):
    out = check_program(with_blank(example_spec(name), 6.0), tmp_path)
    assert out["passes"] >= 2


def test_two_levels_conventional_lines_allowance_zero(tmp_path):
    spec = with_blank(default_spec(), 10.0, **{"machining.passes": 2, "machining.milling": "conventional",
                                               "machining.contour": "lines", "machining.finish_allowance": 0.0,
                                               "machining.stepover": 0.8})
    out = check_program(spec, tmp_path)
    assert len(out["offsets"]) == 2


def test_swallowtails_of_a_concave_profile_are_trimmed(tmp_path):
    """A cam with concave flanks (35 mm lifts over 90°) and a blank 30 mm beyond it: the outer
    passes are farther out than the concave radius, so their raw offsets loop back on themselves
    (swallowtails); the passes keep the outermost crossing and still never come closer than their
    offset."""
    spec = with_blank(default_spec().replace(**{"motion[1].lift": 35.0, "motion[3].lift": 35.0,
                                                "motion[1].angle": 90.0, "motion[3].angle": 90.0,
                                                "motion[2].angle": 120.0}), 30.0)
    design = design_cam(spec)
    # the profile's smallest concave radius, from its dense samples (κ = Im(z̄'z'')/|z'|³, ccw: < 0 concave)
    _, p = design.profile_ccw().sample(400)
    z = p[:, 0] + 1j * p[:, 1]
    d1 = np.gradient(z)
    d2 = np.gradient(d1)
    kappa = (np.conj(d1) * d2).imag / np.abs(d1) ** 3
    concave = -1 / kappa[kappa < 0].min()
    out = check_program(spec, tmp_path, sample_step=0.6)
    assert out["offsets"][0][0] > concave + 1.0          # the outermost pass is beyond the concave radius


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(stepover=st.floats(0.05, 1.0), allowance=st.floats(0.0, 1.0), margin=st.floats(0.01, 12.0),
       tool=st.sampled_from([None, 4.0, 7.0]))
def test_roughing_over_the_fields_ranges(tmp_path, stepover, allowance, margin, tool):
    spec = with_blank(default_spec(), allowance + margin, **{"machining.stepover": stepover,
                                                             "machining.finish_allowance": allowance,
                                                             "machining.tool_radius": tool})
    check_program(spec, tmp_path, sample_step=1.5)


def test_blank_must_hold_the_cam():
    spec = with_blank(default_spec(), 0.1)          # 0.1 beyond the profile, less than the 0.2 allowance
    with pytest.raises(SpecError) as e:
        roughing_xy_program(design_cam(spec), machining_plan(design_cam(spec)))
    assert e.value.field == "machining.blank_diameter"


@pytest.mark.parametrize("changes, field", [
    ({"machining.stepover": 1.5}, "machining.stepover"),
    ({"machining.stepover": 0.0}, "machining.stepover"),
    ({"machining.finish_allowance": -0.1}, "machining.finish_allowance"),
    ({"machining.blank_diameter": 0.0}, "machining.blank_diameter"),
])
def test_bad_roughing_values_name_the_field(changes, field):
    with pytest.raises(SpecError) as e:
        default_spec().replace(**{"machining.blank_diameter": 120.0, **changes})
    assert e.value.field == field


def test_groove_and_conjugate_refuse_a_blank():
    for name in ("groove", "conjugate"):
        with pytest.raises(SpecError) as e:
            example_spec(name).replace(**{"machining.blank_diameter": 200.0})
        assert e.value.field == "machining.blank_diameter"


def _cli(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "cam_workbench.cli", *args], capture_output=True, text=True,
                          env=env)


@requires_ocp
def test_gcode_and_build_rough_from_the_blank(tmp_path):
    nc = tmp_path / "cam.nc"
    res = _cli("gcode", "--example", "default", "--set", "machining.blank_diameter=116", "-o", str(nc))
    assert res.returncode == 0, res.stderr
    text = nc.read_text()
    assert "(rough pass 1 of 4: 32.2 mm from the profile)" in text
    out = tmp_path / "out"
    res = _cli("build", "--example", "default", "--set", "machining.blank_diameter=116", "-o", str(out))
    assert res.returncode == 0, res.stderr
    assert (out / "cam.nc").read_text() == text
    rough = json.loads((out / "report.json").read_text())["machining"]["xy"]["roughing"]
    assert rough["offsets"] == pytest.approx([32.2, 24.2, 16.2, 8.2])
    assert f"roughing {rough['time_s']:.1f} s, whole program {rough['program_time_s']:.1f} s" in text


def test_bad_blank_exits_2_and_writes_nothing(tmp_path):
    nc = tmp_path / "cam.nc"
    res = _cli("gcode", "--example", "default", "--set", "machining.blank_diameter=100", "-o", str(nc))
    assert res.returncode == 2
    assert "machining.blank_diameter" in res.stderr and "Traceback" not in res.stderr
    assert not nc.exists()


def test_inch_cam_roughs_in_inches(tmp_path):
    """A G20 program: the allowance default is 0.008 in, and everything is held in inches."""
    from .conftest import paper_inch_dict
    from cam_workbench.generators.spec import CamSpec

    d = paper_inch_dict({"chord_tolerance": 0.0002})
    spec = with_blank(CamSpec.from_dict(d), 0.3, **{"machining.finish_allowance": None})
    design = design_cam(spec)
    text, both = roughing_xy_program(design, machining_plan(design))
    assert both.rough.allowance == 0.008
    # check_program reads an absent allowance as 0.2: give the inch default explicitly
    check_program(spec.replace(**{"machining.finish_allowance": 0.008}), tmp_path, sample_step=0.02)

"""2-axis wire EDM (``machining.program = "wire_edm"``): the program run through LinuxCNC's
``rs274`` and its canonical moves held against the exact profile, sampled densely here:

* path mode: the main cut, every skim and the tab cut at their offsets (wire radius + spark gap
  + the stock left) within the chord tolerance; skims reverse direction; the main cut leaves a tab
  of ``tab_width`` along the wire path, cut last after a program stop; no Z motion at all;
* controller mode: rs274 applies G41.1 itself, and the compensated path is at wire radius + gap;
* refusals name the field; the CLI exits 2 and writes nothing.
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

from cam_workbench.exporters.gcode_wire_edm import wire_edm_program
from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.machining import machining_plan
from cam_workbench.generators.machining.wire_edm import wire_edm_path
from cam_workbench.generators.spec import default_spec
from cam_workbench.generators.spec.examples import example_spec

from .conftest import ROOT, requires_ocp
from .rs274 import PRINT_QUANTUM, polyline_distance, requires_rs274, run_rs274, sample_xy

PLATE_EXAMPLES = ("default", "paper", "oscillating", "flat", "packaging")


def exact_offset(design, distance: float, per_span: int = 400) -> np.ndarray:
    """The profile moved outward along its own normal by ``distance`` (closed, ccw)."""
    prof = design.profile_ccw()
    lo, hi = prof.domain
    u = np.linspace(lo, hi, per_span * int(round(hi - lo)) + 1)
    p, d = prof.evaluate_with_derivative(u)
    t = d[:, 0] + 1j * d[:, 1]
    return p[:, 0] + 1j * p[:, 1] - 1j * distance * t / np.abs(t)


def length(pts: np.ndarray) -> float:
    return float(np.sum(np.abs(np.diff(pts))))


def signed_area(pts: np.ndarray) -> float:
    return float(0.5 * np.sum((np.conj(pts[:-1]) * pts[1:]).imag))


def check_program(spec, tmp_path) -> dict:
    design = design_cam(spec)
    plan = machining_plan(design)
    mc = spec.machining
    path = wire_edm_path(design, plan)
    text = wire_edm_program(design, plan, path)
    run = run_rs274(text, tmp_path)
    r_w = (mc.wire_diameter if mc.wire_diameter is not None else 0.25) / 2
    gap = mc.spark_gap if mc.spark_gap is not None else 0.02
    stock = mc.skim_stock if mc.skim_stock is not None else 0.03
    tab = mc.tab_width if mc.tab_width is not None else 2.0
    n = mc.skim_passes or 0
    tol = plan.chord_tolerance + 2 * PRINT_QUANTUM
    final = r_w + gap
    # 2 axes: nothing ever moves in Z
    assert all(m.start[2] == 0 and m.end[2] == 0 for m in run.motions)
    names = [c[0] for c in run.calls]
    assert "PROGRAM_STOP" in names and names.index("START_SPINDLE_CLOCKWISE") < names.index("PROGRAM_STOP")
    # the start hole lies outside the cam by the start distance beyond the main path
    hole = complex(*run.motions[0].end[:2])
    assert run.motions[0].kind == "traverse"
    main_off = final + n * stock
    hole_dist = mc.start_hole if mc.start_hole is not None else plan.lead_radius
    assert polyline_distance(np.array([hole]), exact_offset(design, 0.0)).min() == pytest.approx(
        main_off + hole_dist, abs=tol)
    controller = mc.wire_compensation == "controller"
    cuts = [("main cut", main_off)] + [(f"skim {j}", final + (n - j) * stock) for j in range(1, n + 1)]
    cuts.append(("tab", final))
    feeds_in_order = [m for m in run.motions if m.kind != "traverse"]
    out = {}
    prev_sense = None
    for tag, off in cuts:
        (motions,) = run.tagged(tag)
        pts = sample_xy(motions)
        exact = exact_offset(design, off)
        dist = polyline_distance(pts, exact)
        assert dist.max() <= tol, (tag, dist.max())
        if tag != "tab":
            sense = np.sign(signed_area(np.append(pts, 0)))
            if prev_sense is not None:
                assert sense == -prev_sense, f"{tag} runs the same way as the cut before it"
            prev_sense = sense
        out[tag] = (pts, exact)
    # the main cut runs clockwise and leaves the tab: its length is the path's less the tab width
    main_pts, main_exact = out["main cut"]
    assert signed_area(np.append(main_pts, 0)) < 0
    # (under G41.1 LinuxCNC ends the straight entry move where the entry line moved left by the
    # compensation radius meets the compensated contour: r_w + g downstream of the entry point, the
    # lead-in's kerf covering that stretch)
    uncut = tab + (final if controller else 0.0)
    assert length(main_exact) - length(main_pts) == pytest.approx(uncut, abs=1e-3 + 1e-5 * length(main_exact))
    # the tab is cut last, after the stop, across the gap the main cut left
    tab_pts, tab_exact = out["tab"]
    assert feeds_in_order[-1].tag == "tab"
    assert names.index("PROGRAM_STOP") < max(i for i, c in enumerate(run.calls) if c[0] in ("ARC_FEED",
                                                                                            "STRAIGHT_FEED"))
    scale = (1 + 1e-3)
    assert length(tab_pts) == pytest.approx(tab, rel=0.01 * scale)
    ends = {complex(round(p.real, 3), round(p.imag, 3)) for p in (tab_pts[0], tab_pts[-1])}
    assert len(ends) == 2
    if not controller:
        # the tab's ends are the main cut's ends, moved onto the final path
        gap_ends = np.array([main_pts[0], main_pts[-1]])
        for p in (tab_pts[0], tab_pts[-1]):
            assert np.abs(gap_ends - p).min() <= (main_off - final) + 2 * tol
    return {"main": main_pts, "tab": tab_pts}


pytestmark = requires_rs274


@pytest.mark.parametrize("name", PLATE_EXAMPLES)
def test_wire_edm_program_of_each_plate_example(tmp_path, name):
    check_program(example_spec(name).replace(**{"machining.program": "wire_edm", "machining.skim_passes": 2}),
                  tmp_path)


@pytest.mark.parametrize("name", PLATE_EXAMPLES)
def test_controller_compensation_applied_by_rs274(tmp_path, name):
    spec = example_spec(name).replace(**{"machining.program": "wire_edm", "machining.wire_compensation": "controller"})
    check_program(spec, tmp_path)
    text = wire_edm_program(design_cam(spec), machining_plan(design_cam(spec)),
                            wire_edm_path(design_cam(spec), machining_plan(design_cam(spec))))
    assert "G41.1 D0.29 G1" in text and "\nG40\n" in text


def test_inch_wire_program(tmp_path):
    from .conftest import paper_inch_dict
    from cam_workbench.generators.spec import CamSpec

    d = paper_inch_dict({"program": "wire_edm", "chord_tolerance": 0.0002, "wire_diameter": 0.01, "spark_gap": 0.0008,
                             "skim_passes": 1, "skim_stock": 0.0012, "tab_width": 0.08})
    spec = CamSpec.from_dict(d)
    check_program(spec, tmp_path)


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(wire=st.floats(0.02, 0.35), gap=st.floats(0.0, 0.05), skims=st.integers(0, 4), stock=st.floats(0.002, 0.05),
       tab=st.floats(0.3, 20.0), hole=st.one_of(st.none(), st.floats(1.0, 8.0)), lines=st.booleans())
def test_wire_edm_over_the_fields_ranges(tmp_path, wire, gap, skims, stock, tab, hole, lines):
    spec = default_spec().replace(**{
        "machining.program": "wire_edm", "machining.wire_diameter": wire, "machining.spark_gap": gap,
        "machining.skim_passes": skims, "machining.skim_stock": stock, "machining.tab_width": tab,
        "machining.start_hole": hole, "machining.contour": "lines" if lines else "arcs"})
    check_program(spec, tmp_path)


@pytest.mark.parametrize("changes, field", [
    ({"machining.wire_compensation": "controller", "machining.skim_passes": 1}, "machining.skim_passes"),
    ({"machining.skim_passes": 11}, "machining.skim_passes"),
    ({"machining.wire_diameter": 0.0}, "machining.wire_diameter"),
    ({"machining.spark_gap": -0.01}, "machining.spark_gap"),
    ({"machining.tab_width": 0.0}, "machining.tab_width"),
    ({"machining.wire_compensation": "left"}, "machining.wire_compensation"),
    ({"machining.dialect": "fanuc"}, "machining.dialect"),
])
def test_bad_wire_values_name_the_field(changes, field):
    with pytest.raises(SpecError) as e:
        default_spec().replace(**{"machining.program": "wire_edm", **changes})
    assert e.value.field == field


def test_a_tab_longer_than_half_the_path_is_refused():
    spec = default_spec().replace(**{"machining.program": "wire_edm", "machining.tab_width": 200.0})
    design = design_cam(spec)
    with pytest.raises(SpecError) as e:
        wire_edm_path(design, machining_plan(design))
    assert e.value.field == "machining.tab_width"


def test_groove_and_conjugate_refuse_wire_edm():
    for name in ("groove", "conjugate"):
        with pytest.raises(SpecError) as e:
            example_spec(name).replace(**{"machining.program": "wire_edm"})
        assert e.value.field == "machining.program"


def _cli(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "cam_workbench.cli", *args], capture_output=True, text=True,
                          env=env)


def test_cli_gcode_mode_wire_edm(tmp_path):
    nc = tmp_path / "edm.nc"
    res = _cli("gcode", "--example", "default", "--mode", "wire_edm", "--set", "machining.skim_passes=1",
               "-o", str(nc))
    assert res.returncode == 0, res.stderr
    text = nc.read_text()
    blocks = [line for line in text.splitlines() if not line.startswith("(")]
    assert "(skim 1)" in text and "M0" in blocks and not any("Z" in b for b in blocks)


def test_cli_bad_wire_value_exits_2_writes_nothing(tmp_path):
    nc = tmp_path / "edm.nc"
    for args in (("--set", "machining.tab_width=500"), ("--example", "groove")):
        res = _cli("gcode", *(("--example", "default") if args[0] != "--example" else ()), *args,
                   "--mode", "wire_edm", "-o", str(nc))
        assert res.returncode == 2, res.stderr
        assert "machining." in res.stderr and "Traceback" not in res.stderr
        assert not nc.exists()


@requires_ocp
def test_build_writes_the_wire_edm_program(tmp_path):
    out = tmp_path / "out"
    res = _cli("build", "--example", "paper", "--set", "machining.program=wire_edm", "--set",
               "machining.skim_passes=1", "-o", str(out))
    assert res.returncode == 0, res.stderr
    report = json.loads((out / "report.json").read_text())
    edm = report["machining"]["wire_edm"]
    assert edm["offsets"] == pytest.approx({"main": 0.175, "skim 1": 0.145, "tab": 0.145})
    text = (out / "cam.nc").read_text()
    nc = tmp_path / "edm.nc"
    assert _cli("gcode", "--example", "paper", "--mode", "wire_edm", "--set", "machining.skim_passes=1",
                "-o", str(nc)).returncode == 0
    assert nc.read_text().replace(report["spec_digest"], "") == text.replace(report["spec_digest"], "")

"""Programs on the part's contour under the control's cutter compensation
(machining.compensation = "controller"), held against the exact tool-centre path:

* LinuxCNC: its own ``rs274`` applies G41/G42 and prints the compensated moves;
* Fanuc and Sinumerik: the program is parsed with ``pygcode`` (tests/gcode_words.py) and the
  compensated path computed here — every programmed line and arc moved by the tool radius to the
  side G41 (left) / G42 (right) names.

Either is held two-sided to the exact profile moved along its normal by the tool radius
(tests/test_gcode_rs274.py), and the programmed contour itself to the exact profile.
"""
from __future__ import annotations

import dataclasses
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from cam_workbench.exporters.gcode import xy_program
from cam_workbench.exporters.machining_outputs import machining_outputs, second_cam_of
from cam_workbench.generators import design_cam
from cam_workbench.generators.machining import machining_plan
from cam_workbench.generators.spec.examples import example_spec

from .gcode_words import offset_moves, read_program
from .rs274 import PRINT_QUANTUM, RS274, polyline_distance, run_rs274, sample_xy
from .test_gcode_rs274 import exact_tool_path, profile_points, two_sided

ROUNDING = 2 * PRINT_QUANTUM
#: the standalone rs274's tool table is read in inches (its machine units), whatever the program's
MM_PER_TABLE_UNIT = 25.4


def held_to_exact(text: str, dialect: str, design, plan, tmp_path) -> None:
    """The compensated contour of ``text`` within the chord tolerance of the exact tool-centre path,
    the tool-centre lead arcs of radius lead_radius, and G41 for climb / G42 for conventional."""
    allowance = plan.chord_tolerance + ROUNDING
    exact = exact_tool_path(design, plan.tool_radius)
    side = "left" if plan.milling == "climb" else "right"
    prog = read_program(text) if dialect != "linuxcnc" else None
    if dialect == "linuxcnc":
        if RS274 is None:
            pytest.skip("LinuxCNC's rs274 is not installed")
        run = run_rs274(text, tmp_path, plan.tool_number, 2 * plan.tool_radius / MM_PER_TABLE_UNIT)
        assert f"cutter radius compensation on {side}" in run.stdout
        # with compensation on, the interpreter emits a move once it has read the next: a move
        # may appear under the following comment, so the loop is held one-sided and the whole
        # compensated run (lead-in, contour, lead-out) two-sided
        for k in range(plan.passes):
            loop = run.tagged("contour")[k]
            near = run.tagged("lead-in")[k] + loop + run.tagged("lead-out")[k]
            pts = sample_xy(loop)
            assert polyline_distance(pts, exact).max() <= allowance
            assert polyline_distance(exact, sample_xy(near, 512)).max() <= allowance
            lead = run.tagged("lead-in")[k][-1]
            assert lead.kind == "arc" and abs(abs(complex(*lead.end[:2]) - lead.centre) - plan.lead_radius) <= ROUNDING
        return
    comp = {c for m, c in zip(prog.moves, prog.compensation) if m.tag == "contour"}
    assert comp == {"G41" if side == "left" else "G42"}
    loop = prog.tagged("contour")
    assert len(loop) % plan.passes == 0
    n = len(loop) // plan.passes
    for k in range(plan.passes):
        moves = loop[k * n:(k + 1) * n]
        # the programmed contour is the part's exact profile
        assert two_sided(sample_xy(moves), profile_points(design)) <= allowance
        centre = offset_moves(moves, side, plan.tool_radius)
        assert two_sided(centre, exact) <= allowance
    lead = prog.tagged("lead-in")[0]
    assert abs(abs(complex(*lead.end[:2]) - lead.centre) - (plan.lead_radius + plan.tool_radius)) <= ROUNDING
    approach = prog.tagged("approach, cutter compensation on")[0]
    assert abs(complex(*approach.end[:2]) - complex(*approach.start[:2])) > plan.tool_radius


@pytest.mark.parametrize("dialect", ("linuxcnc", "fanuc", "sinumerik"))
@pytest.mark.parametrize("example", ("default", "conjugate"))
def test_compensated_program_per_example_and_dialect(tmp_path, example, dialect):
    spec = example_spec(example).replace(**{"machining.dialect": dialect, "machining.compensation": "controller"})
    design = design_cam(spec)
    plan = machining_plan(design)
    out = machining_outputs(design)
    assert out.machining_summary["compensation"] == "controller"
    header = out.gcode.lower()
    assert "part contour" in header and f"radius r = {plan.tool_radius:g} mm" in header
    held_to_exact(out.gcode, dialect, design, plan, tmp_path)
    if example == "conjugate":
        second = second_cam_of(design)
        held_to_exact(out.second_gcode, dialect, second, dataclasses.replace(
            plan, roller_radius=second.follower.profile_offset), tmp_path)


@pytest.mark.parametrize("args, field", [
    (["--example", "groove", "--compensation", "controller"], "machining.compensation"),
    (["--example", "default", "--mode", "xc", "--compensation", "controller"], "machining.compensation"),
    (["--example", "cylindrical", "--dialect", "fanuc"], "machining.dialect"),
    (["--example", "default", "--dialect", "heidenhain"], "machining.dialect"),
    (["--example", "default", "--dialect", "sinumerik", "--set", "machining.work_offset=G58"],
     "machining.work_offset"),
])
def test_bad_combinations_exit_2_naming_the_field(tmp_path, args, field):
    target = tmp_path / "cam.nc"
    res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "gcode", *args, "-o", str(target)],
                         capture_output=True, text=True)
    assert res.returncode == 2, res.stderr
    assert field in res.stderr and "Traceback" not in res.stderr
    assert not target.exists()


@pytest.fixture(scope="module")
def default_design():
    return design_cam(example_spec("default"))


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(dialect=st.sampled_from(("linuxcnc", "fanuc", "sinumerik")),
       compensation=st.sampled_from(("centre", "controller")),
       milling=st.sampled_from(("climb", "conventional")), contour=st.sampled_from(("arcs", "lines")),
       line_numbers=st.booleans(), coolant=st.booleans())
def test_every_combination_is_the_exact_path(tmp_path, default_design, dialect, compensation, milling, contour,
                                             line_numbers, coolant):
    design = default_design
    plan = dataclasses.replace(machining_plan(design), dialect=dialect, compensation=compensation, milling=milling,
                               contour=contour, line_numbers=line_numbers, coolant=coolant,
                               chord_tolerance=0.02 if contour == "lines" else 0.005)
    text, _ = xy_program(design, plan)
    blocks = [ln for ln in text.splitlines() if ln and ln[0] not in "%O(;"]
    assert all(b.startswith("N") for b in blocks) == line_numbers
    assert any(b.split()[-1] == "M8" for b in blocks) == coolant
    if compensation == "controller":
        held_to_exact(text, dialect, design, plan, tmp_path)
        return
    allowance = plan.chord_tolerance + ROUNDING
    exact = exact_tool_path(design, plan.tool_radius)
    if dialect == "linuxcnc":
        if RS274 is None:
            pytest.skip("LinuxCNC's rs274 is not installed")
        loop = run_rs274(text, tmp_path, plan.tool_number, 2 * plan.tool_radius).tagged("contour")[0]
    else:
        loop = read_program(text).tagged("contour")
    assert two_sided(sample_xy(loop), exact) <= allowance
    # climb milling runs the outside contour clockwise
    pts = sample_xy(loop)
    area = 0.5 * np.sum((np.conj(pts[:-1]) * pts[1:]).imag)
    assert (area < 0) == (milling == "climb")

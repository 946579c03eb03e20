"""Every G-code program through LinuxCNC's real standalone interpreter ``rs274``: it must run
without error, in the right units, and the canonical motions it prints (STRAIGHT_FEED /
ARC_FEED, arcs rebuilt from end, centre and rotation) must trace a closed path within the
chord tolerance of the exact tool-centre path everywhere (two-sided, dense).

The exact tool-centre path is computed here independently of ``cam_workbench.generators.machining.toolpath``: the
foundation's exact profile NURBS moved outward along its own normal by the tool radius
(the tool touches the profile).  rs274 prints 4 decimals, so the allowance is the chord
tolerance plus twice that print quantum.
"""
from __future__ import annotations

import numpy as np
import pytest

from cam_workbench.exporters.gcode import contour_program, rotary_program
from cam_workbench.generators import design_cam
from cam_workbench.generators.machining import machining_plan
from cam_workbench.generators.spec import default_spec
from cam_workbench.generators.machining.toolpath import contour_path, rotary_path

from cam_workbench.generators.spec.examples import example_spec

from .conftest import paper_case


def oscillating_flat():
    """An oscillating flat face 5 mm from the pivot (the default's motion as 12° of arm rotation)."""
    return example_spec("oscillating").replace(**{
        "follower.kind": "flat", "follower.arm_length": None, "follower.roller_radius": 0.0,
        "follower.face_offset": 5.0, "follower.pivot_distance": 70.0, "motion[1].lift": 12.0, "motion[3].lift": 12.0})
from .rs274 import PRINT_QUANTUM, polyline_distance, requires_rs274, run_rs274, sample_xy

pytestmark = requires_rs274


def exact_tool_path(design, tool_radius: float, per_span: int = 400) -> np.ndarray:
    """Tool centre touching the exact profile: profile point + R_t · outward unit normal."""
    prof = design.profile_ccw()
    lo, hi = prof.domain
    u = np.linspace(lo, hi, per_span * int(round(hi - lo)) + 1)
    p, d = prof.evaluate_with_derivative(u)
    z = p[:, 0] + 1j * p[:, 1]
    t = d[:, 0] + 1j * d[:, 1]
    return z - 1j * tool_radius * t / np.abs(t)      # ccw: outward is to the right


def profile_points(design, per_span: int = 400) -> np.ndarray:
    _, p = design.profile.sample(per_span)
    return p[:, 0] + 1j * p[:, 1]


def two_sided(a: np.ndarray, b: np.ndarray) -> float:
    return float(max(polyline_distance(a, b).max(), polyline_distance(b, a).max()))


XY_CASES = {
    # id: (spec, overrides)
    "default_arcs": (default_spec, {}),
    "default_lines_2passes_numbered": (default_spec, {"machining.contour": "lines", "machining.passes": 2,
                                                      "machining.line_numbers": True}),
    "loose_lines_big_tool_conventional": (default_spec, {"machining.chord_tolerance": 0.05,
                                                         "machining.contour": "lines",
                                                         "machining.tool_radius": 8.0,
                                                         "machining.milling": "conventional"}),
    "small_tool_cw_coolant": (default_spec, {"cam.direction": "cw", "machining.tool_radius": 3.0,
                                             "machining.coolant": True, "machining.work_offset": "G55"}),
    "knife_case3": (lambda: paper_case(3), {"machining.chord_tolerance": 0.02}),
    "oscillating_roller": (lambda: example_spec("oscillating"), {}),
    "oscillating_knife_cw": (lambda: example_spec("oscillating"), {"follower.kind": "knife",
                                                                   "cam.direction": "cw"}),
    "flat_face": (lambda: example_spec("flat"), {}),
    "oscillating_flat_face": (oscillating_flat, {"machining.contour": "lines"}),
}


@pytest.mark.parametrize("case", list(XY_CASES), ids=list(XY_CASES))
def test_xy_program_through_rs274(tmp_path, case):
    make, changes = XY_CASES[case]
    spec = make().replace(**changes) if changes else make()
    design = design_cam(spec)
    plan = machining_plan(design)
    path = contour_path(design, plan)
    run = run_rs274(contour_program(design, plan, path), tmp_path, plan.tool_number, 2 * plan.tool_radius)
    assert run.units == "mm"
    tol = plan.chord_tolerance
    allowance = tol + 2 * PRINT_QUANTUM
    exact = exact_tool_path(design, plan.tool_radius)
    profile = profile_points(design)
    loops = run.tagged("contour")
    assert len(loops) == plan.passes
    assert len(run.tagged("lead-in")) == len(run.tagged("lead-out")) == plan.passes
    for k, loop in enumerate(loops):
        z = plan.z_levels[k]
        assert all(abs(m.end[2] - z) < 1e-9 for m in loop)
        assert {m.kind for m in loop} <= ({"arc", "line"} if plan.contour == "arcs" else {"line"})
        pts = sample_xy(loop)
        assert abs(pts[-1] - pts[0]) <= 1e-12 + PRINT_QUANTUM       # closed
        dist = two_sided(pts, exact)
        assert dist <= allowance, f"pass {k}: {dist:.3g} > {allowance:.3g}"
        # what the interpreter does is what the tool path measured (up to the printed decimals)
        assert dist == pytest.approx(path.max_distance, abs=2 * PRINT_QUANTUM)
        # no gouge anywhere: the tool stays (tolerance) outside the profile
        assert polyline_distance(pts, profile).min() >= plan.tool_radius - allowance
        # turning sense: climb milling with M3 runs the outside contour clockwise
        area = 0.5 * np.sum((np.conj(pts[:-1]) * pts[1:]).imag)
        assert (area < 0) == (plan.milling == "climb")
    # lead arcs stay outside the contour and meet it tangentially at the entry
    lead_in = run.tagged("lead-in")[0][-1]
    assert lead_in.kind == "arc"
    entry = complex(lead_in.end[0], lead_in.end[1])
    assert abs(entry - complex(loops[0][0].start[0], loops[0][0].start[1])) < 1e-9
    lead_pts = sample_xy([lead_in])[:-4]
    assert polyline_distance(lead_pts, profile).min() >= plan.tool_radius - allowance
    if case == "loose_lines_big_tool_conventional":
        assert dist > 0.3 * tol  # the check has teeth: this path really uses its tolerance


XC_CASES = {
    "default_follower_line": (default_spec, {}),
    "default_axis_line": (default_spec, {"machining.rotary_line": "axis"}),
    "bigger_tool_cw_2passes": (default_spec, {"cam.direction": "cw", "machining.tool_radius": 9.0,
                                              "machining.passes": 2}),
    "knife_case2_period_2ms": (lambda: paper_case(2), {"machining.sample_period": 0.002,
                                                       "machining.rotary_speed_rpm": 30.0}),
    "non_whole_revolution": (default_spec, {"machining.sample_period": 0.0007}),
    "oscillating_roller_axis_line": (lambda: example_spec("oscillating"), {}),
    "oscillating_bigger_tool_cw": (lambda: example_spec("oscillating"), {"cam.direction": "cw",
                                                                         "machining.tool_radius": 10.0}),
    "flat_face_follower_line": (lambda: example_spec("flat"), {}),
    "oscillating_flat_face": (oscillating_flat, {}),
}


@pytest.mark.parametrize("case", list(XC_CASES), ids=list(XC_CASES))
def test_xc_program_through_rs274(tmp_path, case):
    make, changes = XC_CASES[case]
    spec = make().replace(**changes) if changes else make()
    design = design_cam(spec)
    plan = machining_plan(design)
    path = rotary_path(design, plan)
    run = run_rs274(rotary_program(design, plan, path), tmp_path, plan.tool_number, 2 * plan.tool_radius)
    assert run.units == "mm"
    revs = run.tagged("revolution")
    assert len(revs) == plan.passes
    exact = exact_tool_path(design, plan.tool_radius)
    allowance = plan.chord_tolerance + 2 * PRINT_QUANTUM
    sense = 1 if spec.cam.direction == "ccw" else -1
    dt = plan.sample_period
    omega = plan.rotary_speed_rpm * 2 * np.pi / 60
    for p, rev in enumerate(revs):
        start = np.array([m.start for m in rev])
        end = np.array([m.end for m in rev])
        assert all(m.kind == "line" for m in rev)
        # C runs one full turn in the cam's sense, continuing from the previous pass
        assert end[-1, 3] - start[0, 3] == pytest.approx(sense * 360.0, abs=1e-9)
        assert start[0, 3] == pytest.approx(sense * 360.0 * p, abs=1e-9)
        # each G93 block takes Δt: the interpreter's feed is length·F (XYZ length, else degrees)
        xyz = np.linalg.norm(end[:, :3] - start[:, :3], axis=1)
        length = np.where(xyz > 0, xyz, np.abs(end[:, 3] - start[:, 3]))
        minutes = length / np.array([m.feed for m in rev])
        full = minutes[:-1] * 60
        assert np.allclose(full, dt, rtol=1e-4), (full.min(), full.max())
        last = (2 * np.pi - (len(rev) - 1) * omega * dt) / omega
        assert minutes[-1] * 60 == pytest.approx(last, rel=1e-3)
        # the tool centre in the cam frame: fixed-frame point (−Y, X) turned back by C,
        # X and C linear within a block
        pos = np.vstack([start[:1], end])
        tau = np.arange(8) / 8
        xs = pos[:-1, 0:1] + np.diff(pos[:, 0])[:, None] * tau
        cs = np.deg2rad(pos[:-1, 3:4] + np.diff(pos[:, 3])[:, None] * tau)
        fixed = -pos[:-1, 1:2] + 1j * xs
        pts = np.append((np.exp(-1j * cs) * fixed).ravel(),
                        np.exp(-1j * np.deg2rad(pos[-1, 3])) * (-pos[-1, 1] + 1j * pos[-1, 0]))
        assert abs(pts[-1] - pts[0]) <= 2 * PRINT_QUANTUM                   # closed
        dist = two_sided(pts, exact)
        assert dist <= allowance, f"pass {p}: {dist:.3g} > {allowance:.3g}"
        assert all(abs(m.end[2] - plan.z_levels[p]) < 1e-9 for m in rev)
    # machine Y: the follower's line is at Y = −e, a line through the axis at Y = 0
    y = -spec.follower.offset if plan.rotary_line == "follower" else 0.0
    assert all(abs(m.end[1] - y) < 1e-9 for m in revs[0])


def test_inch_program_prints_inches(tmp_path):
    """A G20 program: rs274 works (and prints) in inches; the path matches the inch cam."""
    from .conftest import paper_inch_dict
    from cam_workbench.generators.spec import CamSpec

    d = paper_inch_dict({"chord_tolerance": 0.002, "contour": "lines"})
    design = design_cam(CamSpec.from_dict(d))
    plan = machining_plan(design)
    assert plan.safe_height == 0.2 and plan.feed_rate == 12.0
    program = contour_program(design, plan, contour_path(design, plan))
    assert "G20" in program.splitlines()[9] or "G20 G90" in program
    run = run_rs274(program, tmp_path, plan.tool_number, 2 * plan.tool_radius)
    assert run.units == "in"
    loop = run.tagged("contour")[0]
    pts = sample_xy(loop)
    exact = exact_tool_path(design, plan.tool_radius)
    assert two_sided(pts, exact) <= plan.chord_tolerance + 2 * PRINT_QUANTUM
    # the base circle of the inch cam: ≈ 0.88 in from the axis, not 22.4 (mm)
    assert np.abs(pts).min() == pytest.approx(22.3607 / 25.4, abs=0.01)
    xc = rotary_program(design, plan, rotary_path(design, plan))
    run_xc = run_rs274(xc, tmp_path, plan.tool_number, 2 * plan.tool_radius)
    assert run_xc.units == "in"

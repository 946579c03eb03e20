"""The `[machining]` section (every rule with its message), resolved defaults, the tool-fit
(gouge) check, the exact tool-centre path, the XY contour and the XC blocks, and the command
table — checked against independent computations (scipy root finding on the exact NURBS,
distances to the foundation's profile)."""
from __future__ import annotations

import copy
import csv
import io
import re

import numpy as np
import pytest
from scipy.optimize import brentq

from cam_workbench.exporters.commands_csv import commands_csv_text
from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import GeometryError, SpecError
from cam_workbench.generators.machining.interpolator import interpolate
from cam_workbench.generators.machining import machining_plan, smallest_concave_profile_radius
from cam_workbench.generators.spec.examples import PAPER_SPEC_DICT, example_spec
from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.curves.nurbs import NurbsCurve
from cam_workbench.generators.machining.toolpath import (OffsetLineSolver, check_lead_arcs, contour_path, outward_distance,
                                 rotary_path, tool_centre_curve)

from .conftest import paper_case


def with_machining(**fields):
    d = copy.deepcopy(PAPER_SPEC_DICT)
    d["machining"] = fields
    return d


RULES = [
    ("tool_radius_positive", {"tool_radius": 0.0}, "machining.tool_radius", "must be > 0"),
    ("tool_number_int", {"tool_number": 1.5}, "machining.tool_number", "must be an integer"),
    ("tool_number_min", {"tool_number": 0}, "machining.tool_number", "must be ≥ 1"),
    ("spindle", {"spindle_rpm": -5.0}, "machining.spindle_rpm", "must be > 0"),
    ("feed", {"feed_rate": 0.0}, "machining.feed_rate", "must be > 0"),
    ("plunge", {"plunge_rate": 0.0}, "machining.plunge_rate", "must be > 0"),
    ("period_positive", {"sample_period": 0.0}, "machining.sample_period", "must be > 0"),
    ("period_too_short", {"sample_period": 1e-6, "rotary_speed_rpm": 1.0}, "machining.sample_period",
     "commands per revolution"),
    ("period_rounds_to_nothing", {"sample_period": 1e-9}, "machining.sample_period", "must be ≥ 1e-06"),
    ("rotary_speed", {"rotary_speed_rpm": 0.0}, "machining.rotary_speed_rpm", "must be > 0"),
    ("depth", {"depth": -1.0}, "machining.depth", "must be > 0"),
    ("passes_min", {"passes": 0}, "machining.passes", "must be ≥ 1"),
    ("passes_max", {"passes": 5000}, "machining.passes", "must be ≤ 1000"),
    ("safe_height", {"safe_height": 0.0}, "machining.safe_height", "must be > 0"),
    ("chord_tolerance_positive", {"chord_tolerance": 0.0}, "machining.chord_tolerance", "must be > 0"),
    ("chord_tolerance_large", {"chord_tolerance": 0.5}, "machining.chord_tolerance", "1% of cam.base_radius"),
    ("contour", {"contour": "splines"}, "machining.contour", "must be one of"),
    ("lead_radius", {"lead_radius": -2.0}, "machining.lead_radius", "must be > 0"),
    ("milling", {"milling": "down"}, "machining.milling", "must be one of"),
    ("rotary_line", {"rotary_line": "tangent"}, "machining.rotary_line", "must be one of"),
    ("work_offset", {"work_offset": "G53"}, "machining.work_offset", "must be one of"),
    ("line_numbers_bool", {"line_numbers": 1}, "machining.line_numbers", "must be true or false"),
    ("coolant_bool", {"coolant": "yes"}, "machining.coolant", "must be true or false"),
    ("program", {"program": "xz"}, "machining.program", "must be one of"),
    ("dialect", {"dialect": "heidenhain"}, "machining.dialect", "must be one of"),
    ("unknown", {"toolradius": 3.0}, "machining.toolradius", "unknown field"),
]


@pytest.mark.parametrize("rule", RULES, ids=[r[0] for r in RULES])
def test_each_machining_rule(rule):
    _, fields, field, words = rule
    with pytest.raises(SpecError) as info:
        CamSpec.from_dict(with_machining(**fields))
    assert info.value.field == field, str(info.value)
    assert words in str(info.value)


def test_defaults_resolve_per_units_and_follower():
    plan = machining_plan(design_cam(example_spec("paper")))
    assert plan.tool_radius == 5.0 and plan.centre_offset == 0.0          # tool = roller
    assert (plan.feed_rate, plan.plunge_rate, plan.safe_height, plan.chord_tolerance) == (300.0, 100.0, 5.0, 0.005)
    assert plan.depth == 10.0 and plan.lead_radius == 5.0 and plan.rotary_speed_rpm == 60.0
    assert np.allclose(plan.z_levels, [-10.0])
    knife = machining_plan(design_cam(paper_case(2)))
    rho, _ = smallest_concave_profile_radius(design_cam(paper_case(2)))
    assert knife.tool_radius == pytest.approx(min(np.hypot(20, 10) / 10, rho / 2))
    two = machining_plan(design_cam(example_spec("paper").replace(**{"machining.passes": 4, "machining.depth": 12.0})))
    assert np.allclose(two.z_levels, [-3, -6, -9, -12])


def test_concave_radius_against_the_closed_form():
    """The profile's smallest concave radius is the as-built pitch curve's plus the roller
    radius (the tool cuts the built curve); the design intent's closed form (thesis Eq. 3.7)
    is 2.6 % tighter at M = 60 and converges to it as M grows (curvature error O(h²))."""
    d = design_cam(example_spec("paper"))
    rho, at = smallest_concave_profile_radius(d)
    c = d.summary()["curvature"]
    assert rho == pytest.approx(c["as_built"]["min_concave_pitch_radius"] + 5.0, rel=1e-12)
    exact = c["min_concave_pitch_radius"] + 5.0
    assert rho == pytest.approx(exact, rel=0.04)
    fine = design_cam(example_spec("paper").replace(**{"pitch.segments": 240}))
    assert smallest_concave_profile_radius(fine)[0] == pytest.approx(exact, rel=0.004)
    assert 40 < at < 80


def test_gouging_tool_is_a_geometry_error_with_the_cam_angle():
    d = design_cam(example_spec("paper").replace(**{"machining.tool_radius": 70.0}))
    with pytest.raises(GeometryError) as info:
        machining_plan(d)
    assert info.value.kind == "gouge" and 40 < info.value.angle_deg < 80
    assert "cam angle" in str(info.value) and "machining.tool_radius" in str(info.value)
    machining_plan(design_cam(example_spec("paper").replace(**{"machining.tool_radius": 60.0})))   # fits


@pytest.mark.parametrize("tool", [2.0, 5.0, 9.0])
def test_tool_centre_curve_is_at_the_tool_radius_from_the_profile(tool):
    """Independent: dense points of the tool-centre NURBS are at distance R_t from dense
    points of the profile (nearest point by k-d tree, refined on the polyline)."""
    from .rs274 import polyline_distance

    d = design_cam(example_spec("paper").replace(**{"machining.tool_radius": tool}))
    curve = tool_centre_curve(d, machining_plan(d))
    _, c = curve.sample(64)
    _, p = d.profile.sample(400)
    dist = polyline_distance(c[:, 0] + 1j * c[:, 1], p[:, 0] + 1j * p[:, 1])
    assert np.max(np.abs(dist - tool)) < 1e-6
    assert abs(curve.area()) > abs(d.profile.area())        # outside the cam


def test_offset_line_solver_against_brentq_on_the_nurbs():
    """The XC tool position (Eq. 13 on the offset curve) equals a bracketing root of
    Re(e^{iδθ}T(u)) = c found by brentq on the exact offset NURBS, for both lines."""
    d = design_cam(example_spec("paper").replace(**{"machining.tool_radius": 8.0, "cam.direction": "cw"}))
    pc = d.pitch
    dist = outward_distance(pc, 3.0)
    curve = tool_centre_curve(d, machining_plan(d))
    for line in (pc.geometry.offset, 0.0):
        solver = OffsetLineSolver(pc.spline, dist, line, pc.geometry.sense)
        th = np.linspace(0.0, 2 * np.pi, 23, endpoint=False)
        seg, xi, pts, y = solver.solve(th)
        for k in range(len(th)):
            rot = np.exp(1j * pc.geometry.sense * th[k])

            def g(u):
                q = curve.evaluate(np.array([u]))[0]
                return (rot * (q[0] + 1j * q[1])).real - line

            u = brentq(g, seg[k] - 1e-9 if seg[k] > 0 else 0.0, seg[k] + 1.0, xtol=1e-14)
            q = curve.evaluate(np.array([u]))[0]
            assert pts[k] == pytest.approx(q[0] + 1j * q[1], abs=1e-9)
            assert y[k] == pytest.approx((rot * (q[0] + 1j * q[1])).imag, abs=1e-9)


def test_xc_with_roller_sized_tool_is_the_followers_position():
    """Tool radius = roller radius on the follower's line: X_k = s₀ + s_actual(θ_k), the
    paper's commands; the general offset solver gives the same X."""
    d = design_cam(example_spec("paper"))
    plan = machining_plan(d)
    rp = rotary_path(d, plan)
    assert rp.from_commands and rp.y == -10.0
    cmds = rp.commands
    assert np.allclose(rp.x[:-1], d.pitch.geometry.s0 + cmds.s_actual, atol=1e-12)
    solver = OffsetLineSolver(d.pitch.spline, 0.0, 10.0, 1)
    assert np.max(np.abs(solver.solve(rp.theta)[3] - rp.x)) < 1e-11
    assert rp.c_deg[0] == 0.0 and rp.c_deg[-1] == 360.0
    assert np.allclose(rp.durations, 1e-3)
    cw = rotary_path(design_cam(example_spec("paper").replace(**{"cam.direction": "cw"})), plan)
    assert cw.c_deg[-1] == -360.0


def test_contour_loop_is_closed_tangent_entry_and_within_tolerance():
    d = design_cam(example_spec("paper").replace(**{"machining.chord_tolerance": 0.01}))
    plan = machining_plan(d)
    cp = contour_path(d, plan)
    loop = cp.loop
    assert abs(loop.end[-1] - loop.start[0]) < 1e-12 and np.all(np.abs(loop.end[:-1] - loop.start[1:]) < 1e-12)
    assert cp.max_distance <= 0.85 * plan.chord_tolerance
    assert cp.entry_angle_deg == pytest.approx(180.0)        # middle of the 60° dwell
    assert cp.lead_in.end[0] == loop.start[0] == cp.lead_out.start[0]
    # lead arcs: radius lead_radius, centre outside, tangent to the loop at the entry
    c = cp.lead_in.center[0]
    assert abs(cp.lead_in.start[0] - c) == pytest.approx(plan.lead_radius)
    assert abs(c) > abs(loop.start[0])
    t_loop = 1j * (loop.start[0] - loop.center[0]) * (1 if loop.ccw[0] else -1)
    t_lead = 1j * (cp.lead_in.end[0] - c) * (1 if cp.lead_in.ccw[0] else -1)
    assert abs(np.angle(t_loop / t_lead)) < 1e-6


def test_lead_arcs_that_cut_the_contour_are_rejected():
    """Entering a 4-wide notch of a (ccw) polygon at its bottom: lead arcs of radius 1 fit,
    radius 3 cut its walls.  (On a cam the entry is in a dwell, where the contour is convex,
    so lead arcs of any radius normally fit: the default cam accepts a 60 mm lead.)"""
    pts = np.array([-10 - 10j, 10 - 10j, 10 + 10j, 2 + 10j, 2 + 0j, -2 + 0j, -2 + 10j, -10 + 10j, -10 - 10j])
    n = len(pts)
    curve = NurbsCurve(1, np.concatenate([[0.0], np.arange(n), [n - 1.0]]),
                       np.column_stack([pts.real, pts.imag]), np.ones(n))
    entry, tangent = 0j, -1 + 0j
    outward = -1j * tangent
    for r, ok in ((1.0, True), (3.0, False)):
        centre = entry + r * outward
        ccw = bool((np.conj(-1j * outward) * tangent).real > 0)
        if ok:
            check_lead_arcs(curve, centre, r, entry, ccw)
        else:
            with pytest.raises(SpecError, match="machining.lead_radius"):
                check_lead_arcs(curve, centre, r, entry, ccw)
    spec = example_spec("paper").replace(**{"machining.lead_radius": 60.0})
    contour_path(design_cam(spec), machining_plan(design_cam(spec)))


def _xc_deviation(spec) -> float:
    """The XC blocks' deviation from the exact tool path, measured here: the blocks (X and C
    linear in time, 8 points each) against the tool-centre NURBS evaluated by scipy at 20 000
    parameters, brute force (the chords of that polygon lie within ~1 µm inside the curve)."""
    from .combinations.invariants import nurbs_points, polyline_distance

    d = design_cam(spec)
    plan = machining_plan(d)
    path = rotary_path(d, plan)
    return float(np.max(polyline_distance(path.cam_frame_points(8), nurbs_points(tool_centre_curve(d, plan)))))


@pytest.mark.parametrize("example,changes", [
    ("paper", {"machining.sample_period": 0.0025, "machining.chord_tolerance": 1e-4}),
    ("packaging", {"cam.speed_rpm": 300.0}),
    ("oscillating", {"machining.rotary_speed_rpm": 1000.0}),
])
def test_coarse_xc_blocks_are_refused_naming_the_speed_that_passes(example, changes):
    """Blocks too coarse for the chord tolerance are refused naming machining.rotary_speed_rpm
    (the C axis's speed: what a user changes) with a speed that passes and a sample period that
    passes: each applied here, its blocks measured independently within 0.85 × the tolerance, and
    the next 3-digit speed up refused."""
    spec = example_spec(example).replace(**{"machining.program": "xc", **changes})
    d = design_cam(spec)
    with pytest.raises(SpecError) as info:
        rotary_path(d, machining_plan(d))
    exc = info.value
    assert exc.field == "machining.rotary_speed_rpm", str(exc)
    m = re.search(r"machining\.rotary_speed_rpm = ([0-9.e+-]+) .* or machining\.sample_period = ([0-9.e+-]+): "
                  r"either passes$", exc.rule)
    assert m, exc.rule
    rpm, period = float(m.group(1)), float(m.group(2))
    given_rpm = spec.machining.rotary_speed_rpm or spec.cam.speed_rpm
    assert rpm < given_rpm and period < spec.machining.sample_period
    tol = spec.machining.chord_tolerance or 0.005
    for fix in ({"machining.rotary_speed_rpm": rpm}, {"machining.sample_period": period}):
        assert _xc_deviation(spec.replace(**fix)) <= 0.85 * tol + 2e-6, fix
    step = 10.0 ** (np.floor(np.log10(rpm)) - 2)
    faster = spec.replace(**{"machining.rotary_speed_rpm": float(f"{rpm + step:.3g}")})
    with pytest.raises(SpecError, match="machining.rotary_speed_rpm"):
        rotary_path(design_cam(faster), machining_plan(design_cam(faster)))


def test_command_table_csv():
    pc = design_cam(paper_case(2)).pitch
    cmds = interpolate(pc, 60.0, 1e-3)
    text = commands_csv_text(cmds, "mm")
    rows = list(csv.DictReader(io.StringIO(text)))
    assert len(rows) == 1000
    assert list(rows[0]) == ["k", "t_s", "theta_deg", "c_deg", "segment", "xi", "x_mm", "y_mm",
                             "s_actual_mm", "s_desired_mm"]
    data = np.genfromtxt(io.StringIO(text), delimiter=",", names=True)
    assert np.allclose(data["t_s"], np.arange(1000) * 1e-3)
    assert np.allclose(data["theta_deg"], np.arange(1000) * 0.36)
    seg = data["segment"].astype(int)
    pts = pc.spline.point(seg, data["xi"])
    assert np.max(np.abs(pts - (data["x_mm"] + 1j * data["y_mm"]))) < 1e-12
    assert np.max(np.abs(data["s_actual_mm"] - data["s_desired_mm"])) == pytest.approx(1.494e-4, rel=1e-3)

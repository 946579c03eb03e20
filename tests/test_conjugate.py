"""Conjugate cams (cam.body = "conjugate"), against computations written for the test.

* both rollers touch their cams at every angle: the roller centres computed here from the motion
  s(θ) and the yoke / arm-pair geometry (not through cam_workbench.generators.followers), their distance to
  each built profile (the NURBS evaluated by scipy, brute-force distance to a dense polyline) =
  that roller's radius, to the PH deviation — and a yoke 0.01 longer misses by 0.01;
* the distance error between the rollers: both lifts found here by intersecting the follower's
  path (line or circle) with dense polylines of the built pitch curves, their difference against
  report.json's number, bounded by the two curves' PH deviations;
* the second cam's checks: its pressure angle in closed form for the yoke
  (tan φ₂ = (s′ − δe)/(s₀ + s − D)), from numerical tangents of the arm geometry for the arm pair;
  its smallest convex pitch radius from finite differences;
* which cam drives: inertia only — the force changes sign where s″ does;
* volumes: both profiles' areas by the shoelace formula, bore with a DIN 6885-1 keyway, spacer,
  hub and holes from elementary formulas — against the body's exact volume, OCCT's solid and the
  STEP file read back;
* DXF audited and read back (both profiles on their own layers, exact SPLINE data);
* both G-code programs (cam.nc, cam2.nc; XY and XC) through LinuxCNC's rs274 with the checks of
  tests/test_gcode_rs274.py;
* bad input: every rule names its field (CLI: exit 2, one line, nothing written).
"""
from __future__ import annotations

import copy
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import GeometryError, SpecError
from cam_workbench.generators.motion import MotionProgram
from cam_workbench.generators.spec import DEFAULT_SPEC_DICT, CamSpec, dict_to_toml
from cam_workbench.generators.spec.examples import example_dict

from .combinations.invariants import nurbs_points, polyline_distance, shoelace
from .conftest import ROOT, requires_ocp

CLI = [sys.executable, "-m", "cam_workbench.cli"]
DEG = math.pi / 180


def yoke_dict(**changes):
    """A translating yoke: the default motion (20 mm cycloidal), R_b 40, offset 5, rollers 8 and 6
    106 apart, inertia only (0.5 kg), a 3 mm gap."""
    d = copy.deepcopy(DEFAULT_SPEC_DICT)
    d["cam"].update(body="conjugate", bore_diameter=12.0)
    d["follower"] = {"kind": "roller", "roller_radius": 8.0, "offset": 5.0, "mass": 0.5}
    d["conjugate"] = {"roller_distance": 106.0, "roller_radius": 6.0, "gap": 3.0}
    for k, v in changes.items():
        section, name = k.split(".")
        d.setdefault(section, {})[name] = v
    return d


def arm_dict(**changes):
    """An oscillating arm pair: the oscillating example (d 60, L 45, R_b 40, 15° cycloidal), the
    second arm 50 long at 120° from the first, roller 7."""
    d = example_dict("oscillating")
    d["cam"].update(body="conjugate", bore_diameter=12.0, direction="cw")
    d["conjugate"] = {"arm_angle": 120.0, "arm_length": 50.0, "roller_radius": 7.0, "gap": 2.0}
    for k, v in changes.items():
        section, name = k.split(".")
        d.setdefault(section, {})[name] = v
    return d


def mirror_arm_dict():
    """The arm pair mirrored about the line through the pivot and the axis at zero lift (γ = −2ψ₀),
    equal arms and rollers, ccw."""
    d = arm_dict(**{"cam.direction": "ccw"})
    psi0 = math.degrees(math.acos((40.0**2 - 60.0**2 - 45.0**2) / (2 * 60.0 * 45.0)))
    d["conjugate"] = {"arm_angle": -2 * psi0, "gap": 0.0}
    return d


CASES = {"yoke": yoke_dict, "yoke_cw_m48": lambda: yoke_dict(**{"cam.direction": "cw", "follower.offset": -7.0,
                                                                  "pitch.segments": 48}),
         "arm_cw": arm_dict, "arm_mirror_ccw": mirror_arm_dict}


_DESIGNS: dict = {}


def design_of(case):
    """The designed cam of a case (designed once per test session)."""
    if case not in _DESIGNS:
        _DESIGNS[case] = design_cam(CamSpec.from_dict(CASES[case]()))
    return _DESIGNS[case]


# ---- the geometry, written out here ---------------------------------------------------------
def roller_centres(spec, th):
    """(first, second) roller centres in the cam frame at cam angles ``th`` [rad], from the motion
    and the yoke / arm geometry (docs/followers.md's frames: fixed-frame point F → e^{−iδθ}F)."""
    s = MotionProgram.from_spec(spec).s(th)
    delta = 1 if spec.cam.direction == "ccw" else -1
    fol, c = spec.follower, spec.conjugate
    rb = spec.cam.base_radius
    if fol.motion == "translating":
        e = fol.offset
        s0 = math.sqrt(rb * rb - e * e)
        f1 = e + 1j * (s0 + s)
        f2 = e + 1j * (s0 + s - c.roller_distance)
    else:
        d, L = fol.pivot_distance, fol.arm_length
        L2 = c.arm_length or L
        psi0 = math.acos((rb * rb - d * d - L * L) / (2 * d * L))
        psi = psi0 - s * DEG
        f1 = d + L * np.exp(1j * psi)
        f2 = d + L2 * np.exp(1j * (psi + c.arm_angle * DEG))
    rot = np.exp(-1j * delta * th)
    return rot * f1, rot * f2


def radii(spec):
    c = spec.conjugate
    return spec.follower.roller_radius, c.roller_radius or spec.follower.roller_radius


def path_scale(spec):
    """|∂F/∂s| of each roller centre: 1 for the yoke, the arm's length in rad for an arm."""
    if spec.follower.motion == "translating":
        return 1.0, 1.0
    return spec.follower.arm_length * DEG, (spec.conjugate.arm_length or spec.follower.arm_length) * DEG


@pytest.mark.parametrize("case", list(CASES))
def test_both_rollers_touch_their_cams(case):
    design = design_of(case)
    spec = design.spec
    second = design.body.extra["second_cam"]
    th = np.linspace(0, 2 * np.pi, 1441)[:-1]
    c1, c2 = roller_centres(spec, th)
    r1, r2 = radii(spec)
    prof1, prof2 = nurbs_points(design.profile, 40000), nurbs_points(second.profile, 40000)
    d1 = polyline_distance(c1, prof1) - r1
    d2 = polyline_distance(c2, prof2) - r2
    # each pitch curve lies within its deviation (along the roller's path) of the true one; the profile is its
    # exact offset, so the roller stands off (or in) by at most that much; polyline chords: < 1e-6
    k1, k2 = path_scale(spec)
    dev1 = design.max_deviation[0] * k1
    dev2 = second.max_deviation[0] * k2
    assert np.max(np.abs(d1)) <= 1.05 * dev1 + 1e-6, (np.max(np.abs(d1)), dev1)
    assert np.max(np.abs(d2)) <= 1.05 * dev2 + 1e-6, (np.max(np.abs(d2)), dev2)
    assert max(dev1, dev2) < 5e-4                    # the PH deviation level of these cams (M = 48: 3e-4)
    # each roller outside its cam: its centre is farther from the axis than the profile along its ray
    for c, prof in ((c1, prof1), (c2, prof2)):
        ang = np.angle(prof)
        order = np.argsort(ang)
        r_prof = np.interp(np.angle(c), ang[order], np.abs(prof)[order], period=2 * np.pi)
        assert np.all(np.abs(c) > r_prof)
    # the check has teeth: a yoke 0.01 longer (an arm 0.01° further round) misses the second cam by ~0.01
    if spec.follower.motion == "translating":
        bad = roller_centres(spec.replace(**{"conjugate.roller_distance": spec.conjugate.roller_distance + 0.01}),
                             th)[1]
    else:
        bad = roller_centres(spec.replace(**{"conjugate.arm_angle": spec.conjugate.arm_angle + 0.01}), th)[1]
    miss = np.abs(polyline_distance(bad, prof2) - r2)
    assert np.min(miss) > 20 * (1.05 * dev2 + 1e-6)


def _line_lift(points, th, e, delta, below):
    """Where the line x = e meets the closed polyline ``points`` (cam frame) turned by θ: its y
    (the crossing above the axis, or below it), by linear interpolation."""
    out = np.empty(th.shape)
    for i, t in enumerate(th):
        q = np.exp(1j * delta * t) * points
        g = q.real - e
        a, b = q, np.roll(q, -1)
        ga, gb = g, np.roll(g, -1)
        cross = (ga * gb <= 0) & (ga != gb)
        x = a + (b - a) * (ga / np.where(cross, ga - gb, 1.0))
        y = x.imag[cross]
        out[i] = y.min() if below else y.max()
    return out


def _circle_angle(points, th, pivot, L, delta, below):
    """Where the circle |z − pivot| = L meets the polyline turned by θ (on the side below or
    above the x axis): the arm's angle arg(z − pivot)."""
    out = np.empty(th.shape)
    for i, t in enumerate(th):
        q = np.exp(1j * delta * t) * points
        g = np.abs(q - pivot) ** 2 - L * L
        a, b = q, np.roll(q, -1)
        ga, gb = g, np.roll(g, -1)
        cross = (ga * gb <= 0) & (ga != gb)
        x = (a + (b - a) * (ga / np.where(cross, ga - gb, 1.0)))[cross]
        x = x[x.imag < 0] if below else x[x.imag > 0]
        out[i] = np.angle(x[0] - pivot)
    return out


@pytest.mark.parametrize("case", list(CASES))
def test_distance_error_between_the_rollers(case):
    """The lifts both built pitch curves give the follower, found here by intersecting its path
    with dense polylines of the curves: their difference is report.json's distance error, and it
    stays within the sum of the two curves' PH deviations."""
    design = design_of(case)
    spec = design.spec
    second = design.body.extra["second_cam"]
    rep = design.body_report["roller_distance_error"]
    # units as the rest of report.json: the distance in the spec's unit, the lift error in the
    # follower's lift unit (an arm's degrees)
    assert rep["unit"] == spec.units
    assert rep["lift_unit"] == (spec.units if spec.follower.motion == "translating" else "deg")
    p1, p2 = nurbs_points(design.pitch_nurbs, 60000), nurbs_points(second.pitch_nurbs, 60000)
    delta = 1 if spec.cam.direction == "ccw" else -1
    th = np.append(np.linspace(0, 2 * np.pi, 181)[:-1], np.deg2rad(rep["at_deg"]))
    s = MotionProgram.from_spec(spec).s(th)
    fol, c = spec.follower, spec.conjugate
    if fol.motion == "translating":
        e, rb = fol.offset, spec.cam.base_radius
        s0 = math.sqrt(rb * rb - e * e)
        s1 = _line_lift(p1, th, e, delta, below=False) - s0
        s2 = _line_lift(p2, th, e, delta, below=True) - s0 + c.roller_distance
        dist = s1 - s2                                    # the yoke moves the second roller as the first
    else:
        d, L, L2 = fol.pivot_distance, fol.arm_length, c.arm_length or fol.arm_length
        psi0 = math.acos((spec.cam.base_radius**2 - d * d - L * L) / (2 * d * L))
        a1 = _circle_angle(p1, th, d, L, delta, below=False)
        a2 = _circle_angle(p2, th, d, L2, delta, below=True)
        s1 = (psi0 - a1) / DEG
        s2 = np.mod(psi0 + c.arm_angle * DEG - a2 + np.pi, 2 * np.pi) / DEG - 180.0
        dist = 2 * L2 * np.sin((s1 - s2) * DEG / 2)       # the chord the second roller moves
    # each lift is within the curve's deviation of the design's (polyline chords: ≲ 1e-7)
    assert np.max(np.abs(s1 - s)) <= design.max_deviation[0] * 1.01 + 1e-7
    assert np.max(np.abs(s2 - s)) <= second.max_deviation[0] * 1.01 + 1e-7
    # at the report's worst angle the independent difference is the report's number
    assert abs(abs(dist[-1]) - rep["max"]) <= 2e-7 + 1e-3 * rep["max"], (dist[-1], rep["max"])
    assert np.max(np.abs(dist)) <= rep["max"] + 2e-7
    # at the PH deviation level: bounded by the two curves' deviations, of their size
    k1, k2 = path_scale(spec)
    assert rep["lift_max"] <= rep["lift_bound"] + 1e-12
    assert rep["max"] <= k2 * rep["lift_bound"] * 1.0001 + 1e-12      # a chord ≤ its arc
    assert rep["first_cam_deviation"] == design.max_deviation[0]
    assert rep["second_cam_deviation"] == second.max_deviation[0]
    assert 0.05 * max(rep["first_cam_deviation"] * k1, rep["second_cam_deviation"] * k2) < rep["max"] < 5e-4


def test_second_cam_pressure_angle_and_curvature_yoke():
    """Yoke: the second roller at (e, s₀ + s − D) moves along +Y: tan φ₂ = (s′ − δe)/(s₀ + s − D) (the
    thesis' Eq. 3.4 with Y = s₀ + s − D); the smallest convex pitch radius of the second cam from
    finite differences of its design points."""
    for case in ("yoke", "yoke_cw_m48"):
        design = design_of(case)
        spec = design.spec
        delta = 1 if spec.cam.direction == "ccw" else -1
        th = np.linspace(0, 2 * np.pi, 360 * 400 + 1)
        k = MotionProgram.from_spec(spec).evaluate(th)
        e = spec.follower.offset
        s0 = math.sqrt(spec.cam.base_radius**2 - e * e)
        phi2 = np.degrees(np.arctan(np.abs(k.ds - delta * e) / (spec.conjugate.roller_distance - s0 - k.s)))
        check = design.checks["pressure_angle_cam2"]
        assert check.value == pytest.approx(float(phi2.max()), abs=2e-5)
        assert design.body_report["second_cam"]["pressure_angle"]["max_deg"] == pytest.approx(check.value, abs=1e-9)
        _check_curvature(design, th)


def test_second_cam_pressure_angle_and_curvature_arm():
    """Arm pair: the pressure angle between the second pitch curve's numerical tangent and the
    direction perpendicular to the second arm; curvature from finite differences."""
    for case in ("arm_cw", "arm_mirror_ccw"):
        design = design_of(case)
        spec = design.spec
        delta = 1 if spec.cam.direction == "ccw" else -1
        th = np.linspace(0, 2 * np.pi, 360 * 200 + 1)
        h = 1e-6
        _, cp = roller_centres(spec, th + h)
        _, cm = roller_centres(spec, th - h)
        _, c0 = roller_centres(spec, th)
        v = np.exp(1j * delta * th) * (cp - cm) / (2 * h)          # the tangent, turned into the fixed frame
        a2 = np.exp(1j * delta * th) * c0 - spec.follower.pivot_distance
        w = -1j * a2 / np.abs(a2)                                   # the second roller's direction of motion
        along = (np.conj(w) * v).real
        across = (np.conj(-1j * w) * v).real
        phi = np.degrees(np.arctan2(np.abs(along), np.abs(across)))
        assert design.checks["pressure_angle_cam2"].value == pytest.approx(float(phi.max()), abs=2e-4)
        _check_curvature(design, th)


def _check_curvature(design, th):
    spec = design.spec
    delta = 1 if spec.cam.direction == "ccw" else -1
    h = 1e-4
    _, cp = roller_centres(spec, th + h)
    _, cm = roller_centres(spec, th - h)
    _, c0 = roller_centres(spec, th)
    d1 = (cp - cm) / (2 * h)
    d2 = (cp - 2 * c0 + cm) / (h * h)
    rho = -delta * np.abs(d1) ** 3 / (np.conj(d1) * d2).imag       # + convex (a ccw cam's curve runs clockwise)
    convex = rho[rho > 0]
    check = design.checks["curvature_cam2"]
    assert check.value == pytest.approx(float(convex.min()), rel=1e-5)
    r2 = radii(spec)[1]
    assert design.checks["undercut_cam2"].value == pytest.approx(float(convex.min()) - r2, rel=1e-5)
    assert design.checks["curvature_cam2"].limit == pytest.approx(spec.checks.undercut_factor * r2)


def test_which_cam_drives_and_the_checks_per_cam():
    """Inertia only (0.5 kg): the force changes sign where s″ does — the middle and the ends of the
    cycloidal rise (30°–150°) and return (210°–330°); the second cam drives a third of the turn.
    No separation check (form closure); each cam has its own pressure angle, stress, curvature
    and undercut checks."""
    design = design_of("yoke")
    drive = design.body_report["drive"]
    assert np.allclose(drive["changes_at_deg"], [90.0, 150.0, 210.0, 270.0], atol=0.06)
    assert drive["second_cam_share"] == pytest.approx(120 / 360, abs=2e-3)
    assert drive["first_cam_share"] + drive["second_cam_share"] == pytest.approx(1.0)
    names = [r.name for r in design.checks.results]
    assert design.checks["separation"].status == "skipped"
    for n in ("pressure_angle", "contact_stress", "curvature", "undercut"):
        assert n in names and f"{n}_cam2" in names
    assert "separation_cam2" not in names and "oscillation_cam2" not in names
    # the stress of each cam where it drives: the second cam's where the first one's force is negative
    from cam_workbench.generators.checks.design import StateModel
    from cam_workbench.generators.followers import second_roller_of

    spec = design.spec
    th = np.deg2rad(np.array([60.0, 120.0]))            # the first cam drives at 60°, the second at 120°
    st1 = StateModel(spec).state(th)
    st2 = StateModel(spec, follower=second_roller_of(spec)).state(th)
    assert st1.force[0] > 0 > st1.force[1] and st2.force[1] > 0 > st2.force[0]
    assert st1.stress[1] == 0 and st2.stress[0] == 0 and st1.stress[0] > 0 and st2.stress[1] > 0
    # virtual work: F₂·cos φ₂ = −F₁·cos φ₁ (the same force along the line of motion)
    assert st2.force * np.cos(st2.pressure_angle) == pytest.approx(-st1.force * np.cos(st1.pressure_angle),
                                                                   rel=1e-12)


# ---- the solid, STEP, DXF -------------------------------------------------------------------
def _keyed_bore_area(r, b, t2):
    h = math.sqrt(r * r - (b / 2) ** 2)
    return math.pi * r * r + b * (r + t2 - h) - (r * r * math.asin(b / 2 / r) - (b / 2) * h)


#: the features of every body; the holes' circle clears the timing mark (at 82.8° for the yoke's offset 5) by
#: 0.5 mm — on a 36 mm circle the mark passed 0.01 from the first hole, and the sliver between them read back
#: from STEP as an invalid face (BRepCheck), though the solid written was valid
FEATURES = dict(keyway="DIN6885", hub_diameter=30.0, hub_length=8.0, mounting_holes=4, mounting_hole_diameter=4.0,
                mounting_circle_diameter=44.0, timing_mark=True)


@requires_ocp
@pytest.mark.parametrize("layout", ["spacer_round_the_holes", "spacer_inside_the_holes", "no_gap"])
def test_volume_solid_and_step(tmp_path, layout):
    from cam_workbench.kernel import solids as occ_build
    from cam_workbench.kernel.step import read_step, write_step

    d = yoke_dict()
    d["cam"].update(FEATURES)
    if layout == "spacer_inside_the_holes":
        d["conjugate"]["spacer_diameter"] = 30.0
    elif layout == "no_gap":
        d["conjugate"]["gap"] = 0.0
    design = design_cam(CamSpec.from_dict(d))
    second = design.body.extra["second_cam"]
    t, gap = 10.0, d["conjugate"]["gap"]
    bore = _keyed_bore_area(6.0, 4.0, 1.8)          # DIN 6885-1: a 12 mm bore (over 10 up to 12): b 4, t₂ 1.8
    hole = math.pi * 2.0**2
    a1 = shoelace(nurbs_points(design.profile, 40000))
    a2 = shoelace(nurbs_points(second.profile, 40000))
    mark = shoelace(design.body.prism("timing_mark").outer.points()) * 0.2
    hub = (math.pi * 15.0**2 - bore) * 8.0
    if layout == "no_gap":
        spacer = 0.0
        assert not design.body.has("spacer")
    else:
        r_sp = 0.9 * min(design.min_profile_radius, second.min_profile_radius) if layout == "spacer_round_the_holes" \
            else 15.0
        assert design.body_report["spacer_diameter"] == pytest.approx(2 * r_sp, rel=1e-12)
        holes_in_spacer = 4 * hole if 22.0 + 2.0 < r_sp else 0.0
        assert (holes_in_spacer > 0) == (layout == "spacer_round_the_holes")
        spacer = (math.pi * r_sp**2 - bore - holes_in_spacer) * gap
    expected = (a1 - bore - 4 * hole) * t + (a2 - bore - 4 * hole) * t + spacer + hub - mark
    assert design.volume == pytest.approx(expected, rel=2e-7)
    summary = design.summary()
    assert summary["volume"] == design.volume and summary["body"]["volume"] == design.volume
    # the top face: the first cam's profile minus bore, holes and the timing mark
    assert design.area == pytest.approx(a1 - bore - 4 * hole - mark / 0.2, rel=2e-7)
    solid = occ_build.cam_solid(design)
    assert occ_build.is_valid(solid) and occ_build.count_solids(solid) == 1
    assert occ_build.kernel_volume(solid) == pytest.approx(expected, rel=2e-5)
    # the first cam's top face is the cross-section OCCT finds at z = thickness
    assert occ_build.face_area_shoelace(occ_build.planar_face_at(solid, t)) == pytest.approx(design.area, rel=1e-6)
    path = tmp_path / "conj.step"
    write_step(solid, path, "mm")
    back = read_step(path, "mm")
    assert occ_build.count_solids(back) == 1 and occ_build.is_valid(back)
    assert occ_build.kernel_volume(back) == pytest.approx(expected, rel=2e-5)


def test_dxf_both_profiles_on_their_layers(tmp_path):
    import ezdxf

    from cam_workbench.exporters.dxf import build_dxf

    design = design_cam(design_of("arm_cw").spec.replace(**{"drawing.curves": "spline"}))   # the exact NURBS
    second = design.body.extra["second_cam"]
    doc, info = build_dxf(design, design.summary())
    doc.saveas(str(tmp_path / "c.dxf"))
    back = ezdxf.readfile(tmp_path / "c.dxf")
    assert not back.audit().has_errors
    msp = back.modelspace()

    def splines(layer):
        return [e for e in msp.query("SPLINE") if e.dxf.layer == layer]

    for layer, curve in (("PROFILE", design.profile_ccw()), ("PROFILE_2", second.profile_ccw())):
        (sp,) = splines(layer)
        assert np.allclose(np.array(sp.control_points)[:, :2], curve.poles, atol=1e-12, rtol=0)
        assert np.allclose(sp.weights, curve.weights, atol=1e-12, rtol=0)
        assert sp.dxf.degree == 9
    assert len(splines("PITCH_2")) == 1 and len(splines("PITCH")) == 1
    (spacer,) = [e for e in msp.query("CIRCLE") if e.dxf.layer == "SPACER"]
    assert spacer.dxf.radius == pytest.approx(design.body_report["spacer_diameter"] / 2)
    texts = " ".join(t.dxf.text for t in msp.query("TEXT"))
    assert "SECOND CAM" in texts and "ROLLER DISTANCE ERROR" in texts and "CONJUGATE CAM PAIR" in texts


# ---- G-code through rs274 --------------------------------------------------------------------
requires_rs274 = pytest.mark.skipif(subprocess.run(["which", "rs274"], capture_output=True).returncode != 0,
                                    reason="LinuxCNC's rs274 is not installed (Debian package linuxcnc-uspace)")


@requires_rs274
@pytest.mark.parametrize("case,program", [("yoke", "xy"), ("arm_cw", "xy"), ("yoke_cw_m48", "xc"),
                                          ("arm_mirror_ccw", "xc")])
def test_both_programs_through_rs274(tmp_path, case, program):
    """cam.nc cuts the first cam, cam2.nc the second (each as its own plate, Z0 on its top face):
    the path rs274 traces lies within the chord tolerance of each cam's exact tool-centre path
    (its profile moved out by the tool radius along its normal, computed here), never inside it."""
    from cam_workbench.exporters.machining_outputs import machining_outputs

    from .rs274 import PRINT_QUANTUM, polyline_distance as poly_dist, run_rs274, sample_xy
    from .test_gcode_rs274 import exact_tool_path, profile_points, two_sided

    base = design_of(case)
    spec = base.spec.replace(**{"machining.program": program, "machining.tool_radius": 5.0})
    design = design_cam(spec)
    second = design.body.extra["second_cam"]
    out = machining_outputs(design, summary=design.summary())
    assert out.files["gcode_second"] == "cam2.nc" and out.machining_summary["second_cam"]["file"] == "cam2.nc"
    plan = out.plan
    allowance = plan.chord_tolerance + 2 * PRINT_QUANTUM
    sense = 1 if spec.cam.direction == "ccw" else -1
    for cam, text in ((design, out.gcode), (second, out.second_gcode)):
        assert ("the second cam" in text) == (cam is second) and "conjugate cam" in text
        run = run_rs274(text, tmp_path, plan.tool_number, 2 * plan.tool_radius)
        assert run.units == "mm"
        exact = exact_tool_path(cam, plan.tool_radius)
        profile = profile_points(cam)
        if program == "xy":
            loops = run.tagged("contour")
            assert len(loops) == plan.passes
            for k, loop in enumerate(loops):
                assert all(abs(m.end[2] - plan.z_levels[k]) < 1e-9 for m in loop)
                pts = sample_xy(loop)
                assert abs(pts[-1] - pts[0]) <= 1e-12 + PRINT_QUANTUM
                assert two_sided(pts, exact) <= allowance
                assert poly_dist(pts, profile).min() >= plan.tool_radius - allowance
        else:
            revs = run.tagged("revolution")
            assert len(revs) == plan.passes
            for p, rev in enumerate(revs):
                start = np.array([m.start for m in rev])
                end = np.array([m.end for m in rev])
                assert end[-1, 3] - start[0, 3] == pytest.approx(sense * 360.0, abs=1e-9)
                pos = np.vstack([start[:1], end])
                tau = np.arange(8) / 8
                xs = pos[:-1, 0:1] + np.diff(pos[:, 0])[:, None] * tau
                cs = np.deg2rad(pos[:-1, 3:4] + np.diff(pos[:, 3])[:, None] * tau)
                # the tool centre in the cam frame (fixed-frame point (−Y, X) turned back by C), with
                # the revolution's last point: the path closes on its start
                pts = np.append((np.exp(-1j * cs) * (-pos[:-1, 1:2] + 1j * xs)).ravel(),
                                np.exp(-1j * np.deg2rad(pos[-1, 3])) * (-pos[-1, 1] + 1j * pos[-1, 0]))
                assert abs(pts[-1] - pts[0]) <= 2 * PRINT_QUANTUM
                assert two_sided(pts, exact) <= allowance
            # the second cam's tool runs on a line through the C axis (machine Y = 0)
            if cam is second:
                assert all(abs(m.end[1]) < 1e-9 for m in revs[0])


# ---- the command line -------------------------------------------------------------------------
def cli(*args, cwd=ROOT):
    return subprocess.run([*CLI, *args], capture_output=True, text=True, cwd=cwd, stdin=subprocess.DEVNULL,
                          timeout=900)


@requires_ocp
def test_cli_build_gcode_check(tmp_path):
    spec_file = tmp_path / "c.toml"
    spec_file.write_text(dict_to_toml(arm_dict()))
    b = cli("build", str(spec_file), "-o", str(tmp_path / "out"))
    assert b.returncode == 0, b.stderr
    out = tmp_path / "out"
    for name in ("cam.step", "cam.dxf", "cam.nc", "cam2.nc", "report.json", "report.html"):
        assert (out / name).stat().st_size > 0, name
    html_text = (out / "report.html").read_text(encoding="utf-8")
    assert 'id="fig-conjugate"' in html_text and 'id="fig-roller_distance"' in html_text
    rep = json.loads((out / "report.json").read_text())
    body = rep["body"]
    assert body["kind"] == "conjugate" and rep["files"]["gcode_second"] == "cam2.nc"
    assert body["second_cam"]["z"] == [-12.0, -2.0] and body["first_cam"]["z"] == [0.0, 10.0]
    assert body["roller_distance_error"]["max"] < 2.5e-4
    assert rep["machining"]["second_cam"]["file"] == "cam2.nc"
    assert "distance error between the rollers" in b.stdout
    html = (out / "report.html").read_text()
    assert 'id="conjugate"' in html and "fig-roller_distance" in html
    g = cli("gcode", str(spec_file), "--cam", "second", "-o", str(tmp_path / "second.nc"))
    assert g.returncode == 0, g.stderr
    assert (tmp_path / "second.nc").read_text() == (out / "cam2.nc").read_text()
    c = cli("check", str(spec_file), "-o", str(tmp_path / "check"))
    assert c.returncode == (0 if rep["checks"]["passed"] else 3), c.stderr
    checked = json.loads((tmp_path / "check" / "report.json").read_text())
    assert checked["checks"] == rep["checks"] and "pressure_angle_cam2" in checked["checks"]["results"]
    assert "pressure_angle_cam2" in c.stdout


# ---- bad input ---------------------------------------------------------------------------------
@pytest.mark.parametrize("make,field,words", [
    (lambda: yoke_dict(**{"conjugate.roller_distance": 70.0}), "conjugate.roller_distance",
     "the second roller does not fit"),
    (lambda: {**yoke_dict(), "conjugate": {"gap": 1.0}}, "conjugate.roller_distance", "is required"),
    (lambda: yoke_dict(**{"conjugate.arm_angle": 100.0}), "conjugate.arm_angle", "oscillating arm pair only"),
    (lambda: arm_dict(**{"conjugate.arm_angle": 10.0}), "conjugate.arm_angle", "other side of the line"),
    (lambda: arm_dict(**{"conjugate.arm_angle": None}), "conjugate.arm_angle", "is required"),
    (lambda: arm_dict(**{"conjugate.roller_distance": 90.0}), "conjugate.roller_distance", "translating yoke only"),
    (lambda: arm_dict(**{"conjugate.arm_angle": 71.8, "conjugate.arm_length": 60.0, "conjugate.roller_radius": 12.0}),
     "conjugate.arm_angle", "does not fit"),
    (lambda: yoke_dict(**{"follower.kind": "knife"}), "cam.body", "needs a roller follower"),
    # a spacer thinner than 0.01 mm (the fuzzer's 1.2e-38 mm crashed the kernel's prism)
    (lambda: yoke_dict(**{"conjugate.gap": 1.1754943508222875e-38}), "conjugate.gap", "at least 0.01 mm"),
    (lambda: {**yoke_dict(), "pitch": {"representation": "bspline"}}, "pitch.representation", '"ph"'),
    (lambda: {**copy.deepcopy(DEFAULT_SPEC_DICT), "conjugate": {"gap": 2.0}}, "conjugate.gap",
     "applies to conjugate cams only"),
    (lambda: {**copy.deepcopy(DEFAULT_SPEC_DICT), "conjugate": {"roller_distance": 100.0}},
     "conjugate.roller_distance", "applies to conjugate cams only"),
])
def test_bad_input_names_its_field(make, field, words):
    d = make()
    for k in [k for k, v in d.get("conjugate", {}).items() if v is None]:
        del d["conjugate"][k]
    with pytest.raises(SpecError) as info:
        CamSpec.from_dict(d)
    assert info.value.field == field and words in str(info.value), str(info.value)


def test_refusals_at_design_time():
    # a spacer wider than the cams, or one whose rim cuts the mounting holes
    d = yoke_dict(**{"conjugate.spacer_diameter": 70.0})
    with pytest.raises(SpecError, match="conjugate.spacer_diameter: must stay inside both cams"):
        design_cam(CamSpec.from_dict(d))
    d = yoke_dict(**{"conjugate.spacer_diameter": 38.0})
    d["cam"].update(mounting_holes=4, mounting_hole_diameter=4.0, mounting_circle_diameter=36.0)
    with pytest.raises(SpecError, match="conjugate.spacer_diameter: the spacer's rim"):
        design_cam(CamSpec.from_dict(d))
    # a 20 mm rise over 40°: the second roller's centre, 66 from the axis where the rise starts, turns
    # sharply under the rise's peak acceleration (s″ ≈ 258 mm/rad² at 40°): the second cam's smallest
    # convex pitch radius is about R₂²/(R₂ + s″) ≈ 14.4 there (the first cam's 12.1, > its 8 mm roller) — a
    # 15 mm second roller undercuts the second cam only: refused with its cam angle; a 14 mm one fits
    d = yoke_dict(**{"conjugate.roller_radius": 15.0})
    d["motion"][1]["angle"], d["motion"][2]["angle"] = 40.0, 140.0
    with pytest.raises(GeometryError) as info:
        design_cam(CamSpec.from_dict(d))
    assert info.value.kind == "undercut" and str(info.value).startswith("second cam: undercut at cam angle")
    assert info.value.angle_deg == pytest.approx(38.7, abs=1.0)
    d["conjugate"]["roller_radius"] = 14.0
    assert design_cam(CamSpec.from_dict(d)).checks["undercut_cam2"].value == pytest.approx(14.364 - 14.0, abs=1e-3)


def test_cli_refuses_with_exit_2_and_writes_nothing(tmp_path):
    spec_file = tmp_path / "c.toml"
    spec_file.write_text(dict_to_toml(yoke_dict()))
    r = cli("build", str(spec_file), "--set", "conjugate.roller_distance=60", "-o", str(tmp_path / "out"))
    assert r.returncode == 2 and r.stderr.startswith("error: conjugate.roller_distance: the second roller does not")
    assert "Traceback" not in r.stderr and len(r.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()
    plate = tmp_path / "p.toml"
    plate.write_text(dict_to_toml(copy.deepcopy(DEFAULT_SPEC_DICT)))
    g = cli("gcode", str(plate), "--cam", "second", "-o", str(tmp_path / "x.nc"))
    assert g.returncode == 2 and "cam.body: --cam second needs a conjugate pair" in g.stderr
    assert not (tmp_path / "x.nc").exists()

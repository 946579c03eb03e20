"""Spec rules of the B-spline law, [material], [checks] and the follower's load fields: every
rule fails with the field and the rule (the offending control point named), and the CLI
exits 2 on them writing nothing."""
import copy

import pytest

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec import CamSpec, load_spec, to_toml

from .test_bspline_law import ex5_spec_dict


def mutate(fn):
    d = copy.deepcopy(ex5_spec_dict())
    fn(d)
    return d


def rise(d):
    return d["motion"][0]


def ret(d):
    return d["motion"][2]


RULES = [
    ("control_x_missing", lambda d: rise(d).pop("control_x"), "motion[0].control_x",
     'is required for law = "bspline"'),
    ("control_y_missing", lambda d: ret(d).pop("control_y"), "motion[2].control_y",
     'is required for law = "bspline"'),
    ("fields_on_closed_form_law", lambda d: rise(d).update(law="cycloidal"), "motion[0].control_x",
     'must be absent unless law = "bspline"'),
    ("order_on_closed_form_law", lambda d: (ret(d).update(law="poly345", order=5),
                                            [ret(d).pop(k) for k in ("control_x", "control_y", "control_frame")]),
     "motion[2].order", 'must be absent unless law = "bspline"'),
    ("fields_on_dwell", lambda d: d["motion"][1].update(control_y=[0.5]), "motion[1].control_y",
     'must be absent unless law = "bspline"'),
    ("control_start_needs_absolute", lambda d: (rise(d).update(control_frame="relative_deg", control_start=0.0)),
     "motion[0].control_start", 'only used with control_frame = "absolute_rad"'),
    ("frame_choice", lambda d: rise(d).update(control_frame="degrees"), "motion[0].control_frame",
     "must be one of"),
    ("order_too_small", lambda d: rise(d).update(order=2), "motion[0].order", "must be ≥ 3"),
    ("order_too_large", lambda d: rise(d).update(order=11), "motion[0].order", "must be ≤ 10"),
    ("control_x_not_numbers", lambda d: rise(d).update(control_x=[0.3, "a", 1.0]), "motion[0].control_x[1]",
     "must be a number"),
    ("too_few_points", lambda d: rise(d).update(control_x=[0.3, 0.6, 1.0, 1.5, 2.0], control_y=[]),
     "motion[0].control_x", "order 5 needs at least 6"),
    ("y_count", lambda d: rise(d).update(control_y=[0.1, 0.5, 0.7, 0.9]), "motion[0].control_y",
     "has 4 values; with 11 control points of order 5 give the 3 free lifts (P4 … P6) or all 9"),
    ("fixed_y_contradicts_start", lambda d: rise(d).update(control_y=[0, 0.1, 0] + [0.1, 0.6, 0.9] + [1, 1, 1]),
     "motion[0].control_y[1]", "control point P2 must be at y = 0"),
    ("fixed_y_contradicts_end", lambda d: ret(d).update(control_y=[1, 1, 1] + [0.9, 0.2, 0.05] + [0, 0.02, 0]),
     "motion[2].control_y[7]", "control point P8 must be at y = 0"),
    ("theta_not_increasing", lambda d: rise(d)["control_x"].__setitem__(4, 0.6), "motion[0].control_x[4]",
     "θ(u) must increase, but control point P5 (0.6 rad) is not after P4 (1.2282 rad)"),
    ("first_point_before_start", lambda d: ret(d)["control_x"].__setitem__(0, 3.10), "motion[2].control_x[0]",
     "control point P1 (3.1 rad) is not after P0 (3.14159 rad) — P0 is the segment start"),
    ("last_point_after_end", lambda d: rise(d)["control_x"].__setitem__(8, 2.70), "motion[0].control_x[8]",
     "control point P9 (2.7 rad) is not before the segment end P10 (2.61799 rad)"),
    ("relative_frame_names_degrees", lambda d: (rise(d).pop("control_frame"),
                                                rise(d).update(control_x=[20, 25, 30, 70, 35, 110, 120, 130, 148])),
     "motion[0].control_x[4]", "control point P5 (35°) is not after P4 (70°)"),
    ("junctions_with_bspline_pitch", lambda d: ([m.update(junctions=10) for m in d["motion"]],
                                                d.update(pitch={"representation": "bspline"})),
     "motion[0].junctions", 'not used with pitch.representation = "bspline"'),
    # follower load, material and checks sections
    ("mass_negative", lambda d: d["follower"].update(mass=-0.01), "follower.mass", "must be ≥ 0"),
    ("preload_negative", lambda d: d["follower"].update(preload=-1.0), "follower.preload", "must be ≥ 0"),
    ("spring_negative", lambda d: d["follower"].update(spring_rate=-1.0), "follower.spring_rate", "must be ≥ 0"),
    ("roller_width", lambda d: d["follower"].update(roller_width=0.0), "follower.roller_width", "must be > 0"),
    ("modulus", lambda d: d.update(material={"cam_modulus": 0.0}), "material.cam_modulus", "must be > 0"),
    ("poisson", lambda d: d.update(material={"follower_poisson": 0.5}), "material.follower_poisson", "must be < 0.5"),
    ("allowable", lambda d: d.update(material={"allowable_stress": -5.0}), "material.allowable_stress", "must be > 0"),
    ("material_unknown", lambda d: d.update(material={"density": 7.8}), "material.density", "unknown field"),
    ("max_pressure_angle", lambda d: d.update(checks={"max_pressure_angle": 90.0}), "checks.max_pressure_angle",
     "must be < 90"),
    ("undercut_factor", lambda d: d.update(checks={"undercut_factor": 0.5}), "checks.undercut_factor", "must be ≥ 1"),
    ("sampling", lambda d: d.update(checks={"sampling": "sparse"}), "checks.sampling", "must be one of"),
    ("samples", lambda d: d.update(checks={"samples": 5}), "checks.samples", "must be ≥ 11"),
]


@pytest.mark.parametrize("rule", RULES, ids=[r[0] for r in RULES])
def test_each_rule_fails_with_field_and_rule(rule):
    _, fn, field, words = rule
    with pytest.raises(SpecError) as info:
        CamSpec.from_dict(mutate(fn))
    assert info.value.field == field, str(info.value)
    assert words in str(info.value), str(info.value)
    assert str(info.value).startswith(field + ":")


def test_nonmonotone_polygon_with_increasing_theta_is_accepted():
    """θ(u) can increase although one control step goes back (the B-spline averages it out):
    the rule is on θ(u), not on the polygon."""
    d = ex5_spec_dict()
    x = list(rise(d)["control_x"])
    x[4] = x[3] - 0.02          # P5 slightly before P4 (P4 = 1.2282 rad)
    rise(d)["control_x"] = x
    spec = CamSpec.from_dict(d)
    from cam_workbench.generators.motion import MotionProgram

    lift = MotionProgram.from_spec(spec).curves[0]
    assert min(lift.theta_derivative_coefficients()) < 0


def test_toml_round_trip_with_control_points(tmp_path):
    spec = CamSpec.from_dict(ex5_spec_dict()).replace(**{"follower.mass": 0.02, "material.allowable_stress": 2.5e5})
    p = tmp_path / "ex5.toml"
    p.write_text(to_toml(spec))
    assert load_spec(p) == spec
    assert "control_x = [0.3772, 0.4424" in p.read_text()


def test_cli_bad_control_polygon_exits_2_and_writes_nothing(tmp_path):
    from .test_cli import run

    p = tmp_path / "bad.toml"
    spec = CamSpec.from_dict(ex5_spec_dict())
    p.write_text(to_toml(spec).replace("1.5945", "0.6"))
    for cmd in ("build", "check"):
        out = tmp_path / f"out_{cmd}"
        res = run(cmd, str(p), "-o", str(out))
        assert res.returncode == 2, res.stderr
        assert "motion[0].control_x[4]: θ(u) must increase, but control point P5" in res.stderr
        assert "Traceback" not in res.stderr and not out.exists()

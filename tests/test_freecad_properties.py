"""The FreeCAD properties are generated from the spec declarations (no FreeCAD needed):
every declared field has exactly one property whose type, group, tooltip and constraints
come from its Param, and a field declared later appears without touching the workbench."""
from __future__ import annotations

from dataclasses import dataclass

import pytest

from cam_workbench.freecad import properties as props
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec.params import param, params_of
from cam_workbench.generators.spec import SECTIONS, CamSpec


def _declared() -> list[tuple[str, str, object, bool]]:
    out = [("", name, p, False) for name, p in params_of(CamSpec).items()]
    for section, (cls, is_list, _r) in SECTIONS.items():
        out += [(section, name, p, is_list) for name, p in params_of(cls).items()]
    return out


def test_every_declared_field_has_one_property():
    fps = props.field_properties()
    assert [(f.section, f.field) for f in fps] == [(s, n) for s, n, _p, _l in _declared()]
    assert len({f.name for f in fps}) == len(fps)
    for f in fps:
        assert f.param is (params_of(CamSpec) if not f.section else params_of(SECTIONS[f.section][0]))[f.field]
        assert f.group == (f.param.group or props.camel(f.section))
        tip = f.tooltip()
        assert tip.startswith(f.param.doc + ".")
        assert f"spec field {f.path}" in tip
        if f.param.rule_text():
            assert f.param.rule_text() in tip


@pytest.mark.parametrize("path, name, ptype", [
    ("cam.base_radius", "CamBaseRadius", "App::PropertyLength"),      # gt 0: non-negative length
    ("follower.offset", "FollowerOffset", "App::PropertyDistance"),   # signed length
    ("cam.direction", "CamDirection", "App::PropertyEnumeration"),
    ("cam.speed_rpm", "CamSpeedRpm", "App::PropertyFloatConstraint"),  # rpm: no FreeCAD quantity
    ("pitch.segments", "PitchSegments", "App::PropertyIntegerConstraint"),
    ("pitch.tolerance", "PitchTolerance", "App::PropertyLength"),
    ("units", "Units", "App::PropertyEnumeration"),
    ("motion[].angle", "MotionAngle", "App::PropertyFloatList"),
    ("motion[].law", "MotionLaw", "App::PropertyStringList"),
    ("motion[].junctions", "MotionJunctions", "App::PropertyIntegerList"),
])
def test_property_types_follow_kind_and_unit(path, name, ptype):
    fp = {f.path: f for f in props.field_properties()}[path]
    assert (fp.name, fp.type) == (name, ptype)


def test_absent_values():
    """Optional fields whose bounds exclude 0 store 0 / "" for "not given"; no flag needed."""
    fps = {f.path: f for f in props.field_properties()}
    assert fps["pitch.segments"].absent == 0 and fps["pitch.segments"].flag is None
    assert fps["pitch.tolerance"].absent == 0.0
    assert fps["motion[].lift"].absent == 0.0
    assert fps["motion[].law"].absent == ""
    assert "0 = not given" in fps["pitch.segments"].tooltip()
    # only optional fields for which 0 is a meaningful value need an "Enabled" flag: a flat
    # face's offset (0 = the face through the follower's axis), a segment's control start, the
    # end continuity and derivatives of a polynomial/table segment (absent = the neighbour's, 0 = 0)
    # and a table's start angle;
    assert [f.flag for f in fps.values() if f.flag] == [
        "FollowerFaceOffsetEnabled", "MotionControlStartEnabled", "MotionStartContinuityEnabled",
        "MotionEndContinuityEnabled", "MotionStartVelocityEnabled", "MotionEndVelocityEnabled",
        "MotionStartAccelerationEnabled", "MotionEndAccelerationEnabled", "MotionStartJerkEnabled",
        "MotionEndJerkEnabled", "MotionTableStartEnabled",
        # the SCCA family's fractions, a cruise fraction and the triple harmonic's amplitudes (0 is a member)
        "MotionSccaBEnabled", "MotionSccaCEnabled", "MotionSccaDEnabled", "MotionCruiseFractionEnabled",
        "MotionHarmonic1Enabled", "MotionHarmonic2Enabled",
        # a groove's clearance and smallest wall (0 = none, absent = the unit's default), a conjugate
        # arm pair's angle (0 is an angle)
        "GrooveClearanceEnabled", "GrooveMinWallEnabled", "ConjugateArmAngleEnabled",
        # the roughing's finish allowance, the wire EDM's spark gap and skim passes (0: none; absent: the defaults)
        "MachiningFinishAllowanceEnabled", "MachiningSparkGapEnabled", "MachiningSkimPassesEnabled",
        # the optimiser's lower bound of a groove's clearance (0: a groove as wide as the roller)
        "OptimiseClearanceMinEnabled",
        # an indexer's plate gap (0: face to face), output inertia and friction (0: none; absent: the defaults)
        "IndexerGapEnabled",
        # the rollers' cone angle (0: cylinders)
        "IndexerRollerConeAngleEnabled",
        "IndexerOutputInertiaEnabled", "IndexerFrictionTorqueEnabled",
        # a lever's signed ratio (negative: a reversing lever; 0 refused by its rule) and the linkage's
        # coordinates and angles that may be 0 (a pivot at the origin, a frame along x)
        "LinkageRatioEnabled", "LinkagePivotXEnabled", "LinkagePivotYEnabled", "LinkageDirectionEnabled",
        "LinkageFrameAngleEnabled", "LinkageCrankOffsetEnabled"]


@pytest.mark.parametrize("path, shown", [
    ("cam.base_radius", "CamBaseRadius (cam.base_radius)"),
    ("motion[3].angle", "MotionAngle[3] (motion[3].angle)"),
    ("motion[].junctions", "MotionJunctions (motion[].junctions)"),
    ("motion", "Motion (motion)"),
    ("units", "Units (units)"),
    ("nonsense.path.x", "nonsense.path.x"),
])
def test_describe_field(path, shown):
    assert props.describe_field(path) == shown


def _clear_tables() -> None:
    props.field_properties.cache_clear()
    props.properties_of_section.cache_clear()


def test_a_field_declared_later_becomes_a_property(monkeypatch, request):
    """A new section declared with ``param`` (as other issues will add [checks], [machining],
    …) appears as grouped, typed properties — and an optional field that may be 0 gets a
    companion flag, an optional section with required fields an enable flag."""

    @dataclass(frozen=True, kw_only=True)
    class ChecksSection:
        """`[checks]`: design limits."""

        max_pressure_angle: float = param("Largest allowed pressure angle", unit="angle", gt=0,
                                          le=90, default=30.0, group="Checks")
        min_clearance: float | None = param("Clearance that may be zero", unit="length", ge=0,
                                            optional=True, group="Checks")
        spring_rate: float = param("Return spring stiffness", unit="stiffness", gt=0, group="Checks")

    monkeypatch.setitem(SECTIONS, "checks", (ChecksSection, False, False))
    _clear_tables()           # the tables are made once from the declarations: this test changes them
    request.addfinalizer(_clear_tables)
    fps = {f.path: f for f in props.field_properties()}
    mpa = fps["checks.max_pressure_angle"]
    assert (mpa.name, mpa.type, mpa.group) == ("ChecksMaxPressureAngle", "App::PropertyAngle", "Checks")
    clr = fps["checks.min_clearance"]
    assert clr.type == "App::PropertyLength" and clr.flag == "ChecksMinClearanceEnabled"
    rate = fps["checks.spring_rate"]
    assert rate.type == "App::PropertyFloatConstraint"
    assert "N/mm for mm specs, lbf/in for inch specs" in rate.tooltip()
    assert props.section_flag("checks") == "ChecksEnabled"
    assert "ChecksEnabled" in set(props.iter_property_names())


# ---- round two: units of the new sections, list-of-floats fields, the control-point editor ----
@pytest.mark.parametrize("path, ptype, group", [
    ("follower.preload", "App::PropertyForce", "Follower load"),
    ("follower.mass", "App::PropertyFloatConstraint", "Follower load"),          # stored in kg
    ("follower.spring_rate", "App::PropertyFloatConstraint", "Follower load"),   # stored in N/mm
    ("follower.roller_width", "App::PropertyLength", "Follower"),
    # the follower kinds' fields: the arm's geometry, its load (torques, inertia: plain numbers
    # in N·mm, N·mm/rad, kg·mm²: FreeCAD 0.20 has no property type for them)
    ("follower.motion", "App::PropertyEnumeration", "Follower"),
    ("follower.face_width", "App::PropertyLength", "Follower"),
    ("follower.pivot_distance", "App::PropertyLength", "Follower arm"),
    ("follower.arm_length", "App::PropertyLength", "Follower arm"),
    ("follower.face_offset", "App::PropertyDistance", "Follower arm"),
    ("follower.arm_inertia", "App::PropertyFloatConstraint", "Follower load"),
    ("follower.preload_torque", "App::PropertyFloatConstraint", "Follower load"),
    ("follower.spring_torque_rate", "App::PropertyFloatConstraint", "Follower load"),
    ("material.allowable_stress", "App::PropertyPressure", "Material"),
    ("material.cam_poisson", "App::PropertyFloatConstraint", "Material"),
    ("checks.min_force", "App::PropertyForce", "Checks"),
    ("checks.max_pressure_angle", "App::PropertyAngle", "Checks"),
    ("checks.sampling", "App::PropertyEnumeration", "Checks"),
    ("machining.feed_rate", "App::PropertySpeed", "Machining"),
    ("machining.sample_period", "App::PropertyFloatConstraint", "Machining"),
    ("machining.coolant", "App::PropertyBool", "Machining"),
    ("machining.passes", "App::PropertyIntegerConstraint", "Machining"),
    ("drawing.title_block", "App::PropertyBool", "Drawing"),
    ("drawing.title", "App::PropertyString", "Drawing"),
    ("motion[].control_x", "App::PropertyStringList", "Motion"),
    ("motion[].control_y", "App::PropertyStringList", "Motion"),
    ("motion[].order", "App::PropertyIntegerList", "Motion"),
    ("motion[].control_frame", "App::PropertyStringList", "Motion"),
    ("motion[].control_start", "App::PropertyFloatList", "Motion"),
])
def test_new_sections_types_and_groups(path, ptype, group):
    fp = {f.path: f for f in props.field_properties()}[path]
    assert (fp.type, fp.group) == (ptype, group)


def test_storage_factors_are_the_defined_conversions():
    """Stored value per spec unit, against the definitions (NIST SP 811): 1 in = 25.4 mm,
    1 lbf = 4.4482216152605 N, 1 psi = 6894.757293168 Pa, 1 lbf·s²/in = 175.1268352 kg;
    FreeCAD's internal units are mm, mN (kg·mm/s²), kPa (kg/(mm·s²)), mm/s."""
    fps = {f.path: f for f in props.field_properties()}
    assert fps["follower.preload"].factor("mm") == 1000.0               # N → mN
    assert fps["follower.preload"].factor("in") == pytest.approx(4448.2216152605, rel=1e-15)
    assert fps["material.allowable_stress"].factor("mm") == 1000.0      # MPa → kPa
    assert fps["material.allowable_stress"].factor("in") == pytest.approx(6.894757293168, rel=1e-12)
    assert fps["follower.mass"].factor("in") == pytest.approx(175.1268352464764, rel=1e-12)
    assert fps["follower.spring_rate"].factor("in") == pytest.approx(4.4482216152605 / 25.4, rel=1e-15)
    assert fps["machining.feed_rate"].factor("mm") == pytest.approx(1 / 60)   # mm/min → mm/s
    assert fps["machining.feed_rate"].factor("in") == pytest.approx(25.4 / 60)
    assert fps["cam.base_radius"].factor("in") == 25.4
    for same in ("cam.speed_rpm", "machining.sample_period", "material.cam_poisson", "motion[].angle",
                 "motion[].control_x"):
        assert fps[same].factor("in") == fps[same].factor("mm") == 1.0, same
    tip = fps["follower.preload"].tooltip()
    assert "a FreeCAD quantity" in tip and "N for mm specs, lbf for inch specs" in tip
    assert "mass in kg" in fps["follower.mass"].tooltip()
    assert "numbers separated by commas" in fps["motion[].control_x"].tooltip()


def test_torque_and_inertia_storage_are_the_defined_conversions():
    """An oscillating arm's load is stored in N·mm, N·mm/rad and kg·mm² whatever ``Units`` says;
    the factors from the definitions: 1 lbf = 0.45359237 kg × 9.80665 m/s², 1 in = 25.4 mm, so
    1 lbf·in = 112.98482933… N·mm and 1 lbf·in·s² = (1 lbf)(0.0254 m)(1 s²) = 0.1129848… kg·m²."""
    fps = {f.path: f for f in props.field_properties()}
    lbf_n = 0.45359237 * 9.80665
    for path in ("follower.preload_torque", "follower.spring_torque_rate", "follower.arm_inertia"):
        assert fps[path].factor("mm") == 1.0, path
    assert fps["follower.preload_torque"].factor("in") == pytest.approx(lbf_n * 25.4, rel=1e-15)
    assert fps["follower.spring_torque_rate"].factor("in") == pytest.approx(lbf_n * 25.4, rel=1e-15)
    assert fps["follower.arm_inertia"].factor("in") == pytest.approx(lbf_n * 0.0254 * 1e6, rel=1e-14)
    assert "torque in N·mm; the spec gets N·mm for mm specs, lbf·in for inch specs" in \
        fps["follower.preload_torque"].tooltip()
    assert "torsional stiffness in N·mm/rad; the spec gets N·mm/rad for mm specs, lbf·in/rad for inch specs" \
        in fps["follower.spring_torque_rate"].tooltip()
    assert "inertia in kg·mm²; the spec gets kg·mm² for mm specs, lbf·in·s² for inch specs" in \
        fps["follower.arm_inertia"].tooltip()


def test_lifts_are_in_the_followers_lift_unit():
    """``motion[].lift`` and ``pitch.tolerance`` (``cam_workbench.generators.spec.LIFT_FIELDS``) are lengths for
    a translating follower and the arm's degrees for an oscillating one (the follower class's
    ``lift_unit``): degrees are stored as degrees whatever ``Units`` says, and the tolerance's
    property is then an angle."""
    from cam_workbench.generators.spec import LIFT_FIELDS

    fps = {f.path: f for f in props.field_properties()}
    assert sorted(f.path for f in fps.values() if f.is_lift) == sorted(LIFT_FIELDS)
    lift, tol = fps["motion[].lift"], fps["pitch.tolerance"]
    assert (lift.factor("in"), lift.factor("in", "angle"), tol.factor("in", "angle")) == (25.4, 1.0, 1.0)
    assert (tol.type_for("length"), tol.type_for("angle")) == ("App::PropertyLength", "App::PropertyAngle")
    assert lift.type_for("angle") == "App::PropertyFloatList"   # a list of plain numbers either way
    assert "degrees of arm rotation for an oscillating one" in lift.tooltip()
    assert "an angle in degrees for an oscillating one" in tol.tooltip()
    units = {(m, k): props.lift_unit(m, k) for m in ("translating", "oscillating")
             for k in ("roller", "knife", "flat")}
    assert units == {("translating", "roller"): "length", ("translating", "knife"): "length",
                     ("translating", "flat"): "length", ("oscillating", "roller"): "angle",
                     ("oscillating", "knife"): "angle", ("oscillating", "flat"): "angle"}
    assert props.lift_unit_of_data({"follower": {"kind": "flat", "motion": "oscillating"}}) == "angle"
    assert props.lift_unit_of_data(None) == "length"


@pytest.mark.parametrize("value", [340.0, 0.02, 250000.0, 12.7, 0.1 + 0.2, 1.0 / 3.0, 29.0e6, 1e-7])
@pytest.mark.parametrize("factor", [25.4, 4448.2216152605, 6.894757293168361, 1000.0, 1 / 60])
def test_unscale_returns_the_spec_value(value, factor):
    """Stored = value × factor; unscale gives the value back exactly (typed decimals and
    arbitrary doubles alike)."""
    assert props.unscale(value * factor, factor) == value


def test_parse_floats_names_the_entry():
    from cam_workbench.generators.errors import SpecError

    assert props.parse_floats("0.3772, 0.4424 0.5148;1", "motion[0].control_x") == (0.3772, 0.4424, 0.5148, 1.0)
    with pytest.raises(SpecError) as e:
        props.parse_floats("0.1, abc", "motion[2].control_x")
    assert str(e.value) == "motion[2].control_x[1]: must be a number, got 'abc'"
    assert props.format_floats((0.1, 2.0)) == "0.1, 2.0"


EX5_RISE = {"kind": "rise", "angle": 150.0, "lift": 1.0, "law": "bspline", "control_frame": "absolute_rad",
            "control_x": (0.3772, 0.4424, 0.5148, 1.2282, 1.5945, 1.9231, 2.1345, 2.2648, 2.5848),
            "control_y": (0.0772, 0.6242, 0.9094)}


def test_control_point_table_of_a_bspline_segment():
    """The thesis' Example 5 rise (order 5, 11 points): P1…P9 with x as given, the free lifts
    P4…P6 and the fixed end levels 0 (P1–P3) and 1 (P7–P9); writing the table back keeps the
    free-only format; the all-interior format is kept too."""
    from cam_workbench.freecad import motion_editor as M

    pts = M.control_points(EX5_RISE)
    assert [p.index for p in pts] == list(range(1, 10))
    assert [p.fixed for p in pts] == [True] * 3 + [False] * 3 + [True] * 3
    assert [p.y for p in pts] == [0.0] * 3 + [0.0772, 0.6242, 0.9094] + [1.0] * 3
    xs, ys = [p.x for p in pts], [p.y for p in pts]
    assert M.points_to_fields(EX5_RISE, xs, ys) == {"control_x": EX5_RISE["control_x"],
                                                   "control_y": EX5_RISE["control_y"]}
    ys[4] = 0.6
    xs.insert(5, 1.7)
    ys.insert(5, 0.7)  # one more point: 4 free lifts P4…P7
    assert M.points_to_fields(EX5_RISE, xs, ys)["control_y"] == (0.0772, 0.6, 0.7, 0.9094)
    full = dict(EX5_RISE, control_y=(0.0, 0.0, 0.0, 0.0772, 0.6242, 0.9094, 1.0, 1.0, 1.0))
    pts = M.control_points(full)
    assert M.points_to_fields(full, [p.x for p in pts], [p.y for p in pts])["control_y"] == full["control_y"]
    ret = M.control_points(dict(EX5_RISE, kind="return"))
    assert [p.y for p in ret][:3] == [1.0] * 3 and [p.y for p in ret][-3:] == [0.0] * 3


def test_default_polygon_is_a_valid_rise_and_return():
    from cam_workbench.freecad import motion_editor as M
    from cam_workbench.generators.spec import DEFAULT_SPEC_DICT, CamSpec

    data = {**DEFAULT_SPEC_DICT, "motion": [dict(r) for r in DEFAULT_SPEC_DICT["motion"]]}
    for i in (1, 3):
        data["motion"][i]["law"] = "bspline"
        data["motion"][i].update(M.default_polygon(data["motion"][i]))
    spec = CamSpec.from_dict(data)
    assert spec.motion[1].control_x[0] == pytest.approx(12.0) and spec.motion[3].control_y == (0.75, 0.5, 0.25)


@pytest.mark.parametrize("field, rows, text", [
    ("motion[0].control_x[3]", None, "row 1, control_x[3] (P4): must be a number"),
    ("motion[0].control_y[1]", [EX5_RISE], "row 1, control_y[1] (P5): must be a number"),
    ("motion[2].angle", None, "row 3, angle: must be a number"),
])
def test_row_messages_name_row_field_and_point(field, rows, text):
    from cam_workbench.freecad import motion_editor as M
    from cam_workbench.generators.errors import SpecError

    assert M.row_message(SpecError(field, "must be a number"), rows) == text


def test_validation_names_a_bad_control_point():
    """A control point that is not a number, or that breaks the B-spline rules, is named by
    row, field and point — the messages the editor shows."""
    from cam_workbench.freecad import motion_editor as M
    from cam_workbench.generators.errors import SpecError
    from cam_workbench.generators.spec import CamSpec, load_spec

    from .conftest import ROOT

    data = load_spec(ROOT / "tests/fixtures/thesis_ex5_final.toml").to_dict()
    rows = data["motion"]
    bad = [dict(r) for r in rows]
    bad[0]["control_x"] = list(bad[0]["control_x"])
    bad[0]["control_x"][4] = "abc"
    with pytest.raises(SpecError) as e:
        CamSpec.from_dict({**data, "motion": bad})
    assert M.row_message(e.value, bad) == "row 1, control_x[4] (P5): must be a number, got 'abc'"
    bad[0]["control_x"][4] = 0.2  # P5 before P4: θ(u) must increase
    with pytest.raises(SpecError) as e:
        CamSpec.from_dict({**data, "motion": bad})
    assert M.row_message(e.value, bad).startswith("row 1, control_x")


def test_points_fields_are_text_rows_with_the_lift_in_storage_units():
    """A list-of-pairs field (a polynomial's points, a motion table) is one text entry per motion row,
    "angle, lift; angle, lift", the lift column converted like the lift itself (mm stored)."""
    fps = {f.path: f for f in props.field_properties()}
    for path in ("motion[].points", "motion[].table"):
        fp = fps[path]
        assert fp.type == "App::PropertyStringList" and fp.absent == "" and fp.flag is None
        assert "separated by semicolons" in fp.tooltip()
    fp = fps["motion[].table"]
    rows = ((0.0, 0.0), (30.0, 0.5), (60.0, 1.0))
    text = props._stored_item(fp, rows, "in")
    assert text == "0.0, 0.0; 30.0, 12.7; 60.0, 25.4"
    assert props._read_item(fp, text, True, "in", "motion[1].table") == rows
    assert props._read_item(fp, "", True, "mm", "motion[1].table") is None
    with pytest.raises(SpecError, match=r"motion\[1\]\.table\[1\]"):
        props._read_item(fp, "0, 0; 30", True, "mm", "motion[1].table")
    assert fps["motion[].start_velocity"].factor("in") == 25.4


def test_motion_editor_reads_points_cells():
    from cam_workbench.freecad.motion_editor import _parse

    assert _parse("0, 0; 30, 2.5", "points") == [[0.0, 0.0], [30.0, 2.5]]
    assert _parse("0, 0; 30", "points") == "0, 0; 30"        # left for the spec's rule to name

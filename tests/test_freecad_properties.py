"""The FreeCAD properties are generated from the spec declarations (no FreeCAD needed):
every declared field has exactly one property whose type, group, tooltip and constraints
come from its Param, and a field declared later appears without touching the workbench."""
from __future__ import annotations

from dataclasses import dataclass

import pytest

from cam_workbench.freecad import properties as props
from generators.params import param, params_of
from generators.spec import SECTIONS, CamSpec


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
    # only optional fields for which 0 is a meaningful value need an "Enabled" flag
    assert [f.flag for f in fps.values() if f.flag] == ["MotionControlStartEnabled"]


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


def test_a_field_declared_later_becomes_a_property(monkeypatch):
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

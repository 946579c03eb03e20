"""The spec: loading from TOML / dict / keywords, every validation rule with its message,
unknown fields, defaults, TOML round trip, and the generated reference document."""
import copy
import math
from pathlib import Path

import pytest

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec.examples import PAPER_SPEC_DICT, example_spec
from cam_workbench.generators.spec import DEFAULT_SPEC_DICT, CamSpec, default_spec, load_spec, to_toml

ROOT = Path(__file__).resolve().parents[1]


def base():
    """The paper's Table 1 case-2 cam (these rule tests were written on its numbers)."""
    return copy.deepcopy(PAPER_SPEC_DICT)


def mutate(fn):
    d = base()
    fn(d)
    return d


# (id, mutation, expected field in the message, expected words of the rule)
RULES = [
    ("units", lambda d: d.update(units="cm"), "units", "must be one of"),
    ("base_radius_positive", lambda d: d["cam"].update(base_radius=-1.0), "cam.base_radius", "must be > 0"),
    ("base_radius_gt_offset", lambda d: d["cam"].update(base_radius=9.0), "follower.offset", "must be < cam.base_radius"),
    ("base_radius_gt_roller", lambda d: (d["follower"].update(offset=0.0, roller_radius=12.0),
                                         d["cam"].update(base_radius=11.0, bore_diameter=0.0)),
     "cam.base_radius", "must be > follower.roller_radius"),
    ("thickness", lambda d: d["cam"].update(thickness=0.0), "cam.thickness", "must be > 0"),
    ("bore_negative", lambda d: d["cam"].update(bore_diameter=-2.0), "cam.bore_diameter", "must be ≥ 0"),
    ("bore_too_big", lambda d: d["cam"].update(bore_diameter=40.0), "cam.bore_diameter", "smallest cam-surface radius"),
    ("direction", lambda d: d["cam"].update(direction="left"), "cam.direction", "must be one of"),
    ("speed", lambda d: d["cam"].update(speed_rpm=0.0), "cam.speed_rpm", "must be > 0"),
    ("follower_kind", lambda d: d["follower"].update(kind="flat_faced"), "follower.kind", "must be one of"),
    ("roller_radius_zero", lambda d: d["follower"].update(roller_radius=0.0), "follower.roller_radius", "must be > 0 for a roller"),
    ("offset_too_big", lambda d: d["follower"].update(offset=30.0), "follower.offset", "must be < cam.base_radius"),
    ("motion_kind", lambda d: d["motion"][0].update(kind="hold"), "motion[0].kind", "must be one of"),
    ("motion_angle_positive", lambda d: d["motion"][0].update(angle=0.0), "motion[0].angle",
     "must be ≥ 0.018 (360°/20000: the finest junction spacing of the pitch curve"),
    # a 1e-300° dwell sums to 360° with the others: refused by the span's minimum, naming the span
    ("span_below_minimum", lambda d: d["motion"].insert(0, {"kind": "dwell", "angle": 1e-300}), "motion[0].angle",
     "must be ≥ 0.018 (360°/20000: the finest junction spacing of the pitch curve; a shorter span can lie "
     "between two junctions), got 1e-300"),
    ("spans_sum", lambda d: d["motion"][4].update(angle=20.0), "motion[4].angle", "spans sum to 350°, must be 360°"),
    # the sum shown with the digits that differ from 360, the odd span named with the value that closes the cycle
    ("spans_sum_digits", lambda d: d["motion"][3].update(angle=119.99999999), "motion[3].angle",
     "spans sum to 359.99999999°, must be 360° (120 here makes them 360°)"),
    ("spans_sum_over", lambda d: d["motion"][2].update(angle=60.0000001), "motion[2].angle",
     "spans sum to 360.0000001°, must be 360° (60 here makes them 360°)"),
    ("lift_positive", lambda d: d["motion"][1].update(lift=-20.0), "motion[1].lift", "must be > 0"),
    ("lift_missing", lambda d: d["motion"][1].pop("lift"), "motion[1].lift", "is required for a rise"),
    ("lift_on_dwell", lambda d: d["motion"][0].update(lift=3.0), "motion[0].lift", "must be absent for a dwell"),
    ("law_on_dwell", lambda d: d["motion"][0].update(law="cycloidal"), "motion[0].law", "must be absent for a dwell"),
    ("law_missing", lambda d: d["motion"][3].pop("law"), "motion[3].law", "is required for a return"),
    ("law_unknown", lambda d: d["motion"][1].update(law="parabolic"), "motion[1].law", "must be one of"),
    ("not_closed", lambda d: d["motion"][3].update(lift=15.0), "motion", "does not close"),
    ("below_zero", lambda d: (d["motion"][1].update(kind="return", law="harmonic"),
                              d["motion"][3].update(kind="rise")), "motion[1].lift", "below zero"),
    ("junctions_partial", lambda d: (d["motion"][0].update(junctions=6), d["pitch"].pop("segments")),
     "motion[1].junctions", "is required on every segment"),
    ("junctions_int", lambda d: d["motion"][0].update(junctions=2.5), "motion[0].junctions", "must be an integer"),
    ("segments_min", lambda d: d["pitch"].update(segments=4), "pitch.segments", "must be ≥ 8"),
    ("tolerance_positive", lambda d: (d["pitch"].pop("segments"), d["pitch"].update(tolerance=0.0)),
     "pitch.tolerance", "must be > 0"),
    ("segments_and_tolerance", lambda d: d["pitch"].update(tolerance=1e-4), "pitch.tolerance", "exclusive with pitch.segments"),
    ("representation", lambda d: d["pitch"].update(representation="spline"), "pitch.representation", "must be one of"),
    ("unknown_field", lambda d: d["cam"].update(base_raduis=3.0), "cam.base_raduis", "unknown field"),
    ("unknown_section", lambda d: d.update(camm={}), "camm", "unknown field"),
    ("missing_section", lambda d: d.pop("follower"), "follower", "section is required"),
    ("missing_required", lambda d: d["cam"].pop("thickness"), "cam.thickness", "is required"),
    ("wrong_type", lambda d: d["cam"].update(thickness="ten"), "cam.thickness", "must be a number"),
    ("bool_not_number", lambda d: d["cam"].update(thickness=True), "cam.thickness", "must be a number"),
    ("nan", lambda d: d["cam"].update(thickness=float("nan")), "cam.thickness", "finite"),
    ("empty_motion", lambda d: d.update(motion=[]), "motion", "non-empty list"),
    ("no_rise", lambda d: d.update(motion=[{"kind": "dwell", "angle": 360.0}]), "motion", "at least one rise"),
]


@pytest.mark.parametrize("rule", RULES, ids=[r[0] for r in RULES])
def test_each_rule_fails_with_field_and_rule(rule):
    _, fn, field, words = rule
    with pytest.raises(SpecError) as info:
        CamSpec.from_dict(mutate(fn))
    assert info.value.field == field, str(info.value)
    assert words in str(info.value)
    assert str(info.value).startswith(field + ":")


def test_default_spec_is_the_papers_motion_on_a_passing_cam():
    s = default_spec()
    assert (s.cam.base_radius, s.follower.offset, s.follower.roller_radius) == (40.0, 0.0, 8.0)
    assert [m.angle for m in s.motion] == [30, 120, 60, 120, 30]
    assert [(m.lift, m.law) for m in s.motion if m.kind != "dwell"] == [(20.0, "cycloidal")] * 2


def test_paper_example_is_the_papers_case_2():
    s = example_spec("paper")
    assert s.cam.base_radius == pytest.approx(math.sqrt(500))
    assert (s.follower.kind, s.follower.offset, s.follower.roller_radius) == ("roller", 10.0, 5.0)
    assert (s.cam.thickness, s.cam.bore_diameter, s.pitch.segments) == (10.0, 10.0, 60)
    assert [m.angle for m in s.motion] == [30, 120, 60, 120, 30]


def test_defaults_fill_in():
    d = base()
    d["cam"] = {"base_radius": 30.0, "thickness": 5.0}
    d["follower"] = {"kind": "knife"}
    d.pop("pitch")
    s = CamSpec.from_dict(d)
    assert (s.cam.direction, s.cam.speed_rpm, s.cam.bore_diameter) == ("ccw", 60.0, 0.0)
    assert s.follower.offset == 0.0 and s.roller_radius == 0.0
    assert s.pitch.representation == "ph" and s.pitch.segments is None


def test_toml_roundtrip_and_sources(tmp_path):
    s = default_spec()
    text = to_toml(s)
    p = tmp_path / "cam.toml"
    p.write_text(text)
    assert load_spec(p) == s
    assert load_spec(text) == s
    assert CamSpec.from_kwargs(**copy.deepcopy(DEFAULT_SPEC_DICT)) == s


def test_contract_example_loads():
    """The example of the input contract, CAM_SPEC.md, verbatim: the contract is kept beside the
    repository (``../shared``, as CI checks it out), not in it; its example must always load."""
    text = (ROOT.parent / "shared" / "CAM_SPEC.md").read_text(encoding="utf-8")
    example = text.split("```toml", 1)[1].split("```", 1)[0]
    s = load_spec(example)
    assert s.cam.base_radius == 22.3607 and s.pitch.segments == 60


def test_conventions_example_loads():
    """The minimal spec of docs/conventions.md (the paper's Table 1 cam, case 2), verbatim."""
    text = (ROOT / "docs" / "conventions.md").read_text(encoding="utf-8")
    example = text.split("```toml", 1)[1].split("```", 1)[0]
    s = load_spec(example)
    assert s.cam.base_radius == 22.3607 and s.pitch.segments == 60


def test_replace_with_dotted_paths():
    s = default_spec().replace(**{"cam.base_radius": 30.0, "motion[1].law": "poly345"})
    assert s.cam.base_radius == 30.0 and s.motion[1].law == "poly345"
    with pytest.raises(SpecError, match="motion\\[9\\]"):
        default_spec().replace(**{"motion[9].angle": 3.0})


def test_bad_toml_and_missing_file(tmp_path):
    with pytest.raises(SpecError, match="not valid TOML"):
        load_spec("units = \n[cam\n")
    with pytest.raises(SpecError, match="file not found"):
        load_spec(tmp_path / "nope.toml")


def test_spec_reference_document_is_current():
    from cam_workbench.generators.spec.reference import render

    doc = (ROOT / "docs" / "spec.md").read_text(encoding="utf-8")
    assert doc == render(), "docs/spec.md is stale: run `make docs`"

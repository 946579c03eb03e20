"""Refusals name the field a user changes and never round a violated rule into an identity:
the number compared with a limit is printed with the digits that differ from it
(:func:`cam_workbench.generators.errors.fmt_apart`), for every declared bound and the cross-field rules; the
continuity note names what promised the order it misses; and no numpy warning reaches a user of
the command line (the edge specs below, each command's stderr)."""
from __future__ import annotations

import copy
import dataclasses
import re
import subprocess
import sys

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cam_workbench.generators.errors import SpecError, fmt_apart
from cam_workbench.generators.spec.examples import example_dict
from cam_workbench.generators.spec import DEFAULT_SPEC_DICT, CamSpec, dict_to_toml
from cam_workbench.generators.spec.model import SECTIONS
from cam_workbench.generators.spec.params import params_of

from .combinations.invariants import REFUSAL
from .combinations.test_cli_combinations import assert_clean
from .conftest import ROOT

CLI = [sys.executable, "-m", "cam_workbench.cli"]
FINITE = st.floats(allow_nan=False, allow_infinity=False, width=64)


@settings(max_examples=300, derandomize=True, deadline=None)
@given(FINITE, FINITE)
def test_fmt_apart_prints_different_numbers_differently_on_their_own_sides(a, b):
    """Two different numbers print differently at the same precision, each on its own side of
    the other (rounding is monotonic); equal numbers print alike."""
    ta, tb = fmt_apart(a, b), fmt_apart(b, a)
    if a == b:
        assert float(ta) == float(tb)              # (−0 and 0 keep their signs)
        return
    assert ta != tb and (float(ta) < float(tb)) == (a < b), (a, b, ta, tb)


@pytest.mark.parametrize("value,limit,text", [
    (359.99999999, 360.0, "359.99999999"), (360.0, 359.99999999, "360"), (0.50000001, 0.5, "0.50000001"),
    (1e-300, 0.018, "1e-300"), (8.0, 8.0, "8"), (1.0, 1.0000004, "1"), (1.0000004, 1.0, "1.0000004"),
    (0.00702823, 0.00425, "0.00702823"),
])
def test_fmt_apart_examples(value, limit, text):
    assert fmt_apart(value, limit) == text


def _bounds():
    """Every declared numeric bound of every spec section: (section class, field, op, bound)."""
    out = []
    for cls, _is_list, _required in [*SECTIONS.values(), (CamSpec, False, True)]:
        for name, p in params_of(cls).items():
            if p.kind not in ("float", "int"):
                continue
            for op in ("gt", "ge", "lt", "le"):
                bound = getattr(p, op)
                if bound is not None:
                    out.append((cls.__name__, name, p, op, bound))
    return out


@pytest.mark.parametrize("cls,name,p,op,bound", _bounds(), ids=[f"{b[0]}.{b[1]}:{b[3]}" for b in _bounds()])
def test_every_declared_bound_prints_a_violation_apart_from_its_limit(cls, name, p, op, bound):
    """A value a hair beyond a declared bound (1e-9 relative, and the next integer for integer
    fields) is refused with a message whose value differs from the bound as printed."""
    scale = max(abs(bound), 1.0)
    if p.kind == "int":
        value = {"gt": bound, "ge": bound - 1, "lt": bound, "le": bound + 1}[op]
    else:
        value = {"gt": bound - 1e-9 * scale, "ge": bound - 1e-9 * scale,
                 "lt": bound + 1e-9 * scale, "le": bound + 1e-9 * scale}[op]
        if abs(value) < 1e-9 and op in ("gt", "ge"):      # below a positive minimum: the minimum's own rule
            value = -1e-9
    with pytest.raises(SpecError) as info:
        p.check(name, value)
    m = re.search(r"must be (?:within ±|[<>≤≥] )(\S+?)(?: \(.*\))?, got (\S+)$", info.value.rule)
    assert m, info.value.rule
    assert m.group(1) != m.group(2), info.value.rule


def _with(d: dict, **changes) -> dict:
    d = copy.deepcopy(d)
    for path, v in changes.items():
        section, field = path.split(".")
        d.setdefault(section, {})[field] = v
    return d


# (spec dict, field, the rule's words with both numbers as they must print)
CROSS_FIELD = [
    (_with(DEFAULT_SPEC_DICT, **{"cam.base_radius": 8.0 - 1e-9, "cam.bore_diameter": 0.0}), "cam.base_radius",
     "must be > follower.roller_radius (8), got 7.999999999"),
    (_with(DEFAULT_SPEC_DICT, **{"follower.offset": -(40.0 + 4e-8)}), "follower.offset",
     "|offset| must be < cam.base_radius (40), got -40.00000004"),
    (_with(DEFAULT_SPEC_DICT, **{"cam.bore_diameter": 64.0 + 1e-8}), "cam.bore_diameter",
     "= 64, got 64.00000001"),
    (_with(example_dict("groove"), **{"groove.depth": 12.0 + 1e-8}), "groove.depth",
     "must be < cam.thickness (12), got 12.00000001"),
    (_with(example_dict("cylindrical"), **{"cam.base_radius": 40.0 + 1e-8}), "cam.base_radius",
     "give cam.cylinder_radius (40), got 40.00000001"),
    (_with(example_dict("conjugate"), **{"conjugate.gap": 0.01 - 1e-10}), "conjugate.gap",
     "at least 0.01 mm (a thinner spacer cannot be made), got 0.0099999999"),
    (_with(DEFAULT_SPEC_DICT, **{"optimise.base_radius_min": 30.0, "optimise.base_radius_max": 30.0 - 1e-9}),
     "optimise.base_radius_max", "must be > optimise.base_radius_min (30), got 29.999999999"),
    (_with(DEFAULT_SPEC_DICT, **{"machining.chord_tolerance": 0.4 + 1e-9}), "machining.chord_tolerance",
     "must be < 1% of cam.base_radius (0.4), got 0.400000001"),
]


@pytest.mark.parametrize("d,field,words", CROSS_FIELD, ids=[c[1] for c in CROSS_FIELD])
def test_cross_field_rules_print_the_digits_that_differ(d, field, words):
    with pytest.raises(SpecError) as info:
        CamSpec.from_dict(d)
    assert info.value.field == field and words in info.value.rule, str(info.value)


def _bspline_rise(**changes) -> dict:
    d = copy.deepcopy(DEFAULT_SPEC_DICT)
    d["motion"][1] = {"kind": "rise", "angle": 120.0, "lift": 20.0, "law": "bspline", "order": 5,
                      "control_x": [15.0 * j for j in range(1, 8)], "control_y": [0.5]}
    d["motion"][1].update(changes)
    return d


def _default_with(k: int, **changes) -> dict:
    d = copy.deepcopy(DEFAULT_SPEC_DICT)
    d["motion"][k].update(changes)
    return d


# refusals found by mutating valid specs that named another field than the one changed
NAMED = [
    # one control angle far out of order: it is named, not its neighbour
    (_bspline_rise(control_x=[15.0, 30.0, 300.0, 60.0, 75.0, 90.0, 105.0]), "motion[1].control_x[2]",
     "θ(u) must increase, but control point P3 (300°) is not before P4 (60°) nor P5 (75°)"),
    # a rise without its law, but with a law's field: the missing law is named first
    (_bspline_rise(law=None), "motion[1].law", "is required for a rise"),
    # the return that takes s below zero says what the segments before it left
    (_default_with(1, lift=20.0 - 1e-7), "motion[3].lift",
     "the follower would go 1e-07 below zero lift (s must stay ≥ 0): the segments before it leave it at "
     "19.9999999, this return falls 20"),
]


@pytest.mark.parametrize("d,field,words", NAMED, ids=[n[1] for n in NAMED])
def test_refusals_name_the_field_changed(d, field, words):
    d = copy.deepcopy(d)                                       # (a None value: the field left out)
    for seg in d["motion"]:
        for k in [k for k, v in seg.items() if v is None]:
            seg.pop(k)
    with pytest.raises(SpecError) as info:
        CamSpec.from_dict(d)
    assert info.value.field == field and words in info.value.rule, str(info.value)


def test_docs_quote_the_bound_message():
    """docs/spec.md's example of a value printed apart from its limit is the message itself."""
    text = (ROOT / "docs" / "spec.md").read_text(encoding="utf-8")
    assert "(`must be < 0.5, got 0.50000001`)" in text
    with pytest.raises(SpecError, match=r"^material\.cam_poisson: must be < 0\.5, got 0\.50000001$"):
        CamSpec.from_dict(_with(DEFAULT_SPEC_DICT, **{"material.cam_poisson": 0.50000001}))


def test_continuity_note_names_a_dwells_promise():
    """A junction short of a dwell's promise (C3: no limit of its own) names the dwell — the
    note once read "… C1, but  promise C3" with nothing before "promise"."""
    from cam_workbench.generators.checks.design import junction_text
    from cam_workbench.generators.motion.program import MotionProgram

    d = copy.deepcopy(DEFAULT_SPEC_DICT)
    d["motion"][0:1] = [{"kind": "dwell", "angle": 10.0}, {"kind": "dwell", "angle": 20.0}]
    program = MotionProgram.from_spec(CamSpec.from_dict(d))
    j = program.junctions()[1]                       # dwell → dwell at 10°
    assert (j.law_left, j.law_right, j.order, j.promised) == (None, None, 3, 3)
    text = junction_text(dataclasses.replace(j, order=1), program, {"acceleration": "mm/rad²",
                                                                      "reduced_acceleration": "mm/rad²"})
    assert text.endswith("C1, but a dwell promises C3"), text
    k = program.junctions()[2]                       # dwell → cycloidal rise: the rise's C2
    text = junction_text(dataclasses.replace(k, order=0), program, {"reduced_velocity": "mm/rad",
                                                                      "reduced_acceleration": "mm/rad²"})
    assert text.endswith("C0, but cycloidal promises C2"), text


# ---- the command line over edge specs: clean refusals, and no numpy warning on stderr ----------
def _tiny_dwell(angle: float) -> dict:
    d = copy.deepcopy(DEFAULT_SPEC_DICT)
    d["motion"][0]["angle"] = 30.0 - angle
    d["motion"].insert(1, {"kind": "dwell", "angle": angle})
    return d


EDGE = {
    # the spec: a 1e-300° dwell was accepted, then failed continuity with a RuntimeWarning
    "dwell_1e-300": (dict(copy.deepcopy(DEFAULT_SPEC_DICT), motion=[{"kind": "dwell", "angle": 1e-300},
                                                                   *DEFAULT_SPEC_DICT["motion"]]),
                     ("build",), 2, "error: motion[0].angle: must be ≥ 0.018 (360°/20000"),
    "span_identity": (_with(DEFAULT_SPEC_DICT), ("check", "--set", "motion[3].angle=119.99999999"), 2,
                      "error: motion[3].angle: spans sum to 359.99999999°, must be 360° (120 here makes them 360°)"),
    "dwell_at_minimum": (_tiny_dwell(0.018), ("check",), 0, None),
    "rise_at_minimum": (dict(copy.deepcopy(DEFAULT_SPEC_DICT), motion=[
        {"kind": "dwell", "angle": 29.982}, {"kind": "rise", "angle": 0.018, "lift": 1.0, "law": "cycloidal"},
        {"kind": "rise", "angle": 120.0, "lift": 19.0, "law": "cycloidal"}, *DEFAULT_SPEC_DICT["motion"][2:]]),
                        ("check",), (2, 3), None),
    "dynamics_dwell_at_minimum": (_with(_tiny_dwell(0.018), **{"dynamics.stiffness": 1000.0}),
                                  ("dynamics", "--no-sweep"), (0, 3), None),
    "xc_300rpm": (_with(example_dict("packaging"), **{"cam.speed_rpm": 300.0}), ("gcode", "--mode", "xc"), 2,
                  "error: machining.rotary_speed_rpm: at 300 rpm"),
}


@pytest.mark.parametrize("name", list(EDGE))
def test_cli_edge_specs_refuse_cleanly_and_print_no_warning(tmp_path, name):
    """Each command on an edge spec: its exit status (2: one line naming the field, nothing
    written), and no warning of numpy or Python on stderr."""
    d, args, status, first = EDGE[name]
    spec = tmp_path / "cam.toml"
    spec.write_text(dict_to_toml(d), encoding="utf-8")
    out = tmp_path / ("p.nc" if args[0] == "gcode" else "out")
    res = subprocess.run([*CLI, args[0], str(spec), *args[1:], "-o", str(out)], capture_output=True, text=True,
                         cwd=ROOT, stdin=subprocess.DEVNULL, timeout=600)
    assert "Warning" not in res.stderr, res.stderr
    assert_clean(res, status if isinstance(status, tuple) else (status,))
    if first is not None:
        assert res.stderr.startswith(first), res.stderr
    if res.returncode == 2:
        assert REFUSAL.search(res.stderr.strip()) and not out.exists()


def test_refusal_of_an_oscillating_flat_face_keeps_its_message():
    """Found by the API combinations (seed 13): an oscillating flat face without arm_length whose
    profile has a cusp.  Adding the remedy to the refusal raised a TypeError (the pivot's bounds
    read the optional arm_length), and then a neighbouring spec's SolveError in place of the
    user's own refusal; now the refusal is the cusp with its cam angle, and the remedy search
    counts a neighbour that cannot be solved as one that does not pass."""
    from cam_workbench.generators.cam_design import design_cam
    from cam_workbench.generators.errors import GeometryError
    from cam_workbench.generators.studies.remedies import with_remedy

    d = {"units": "mm", "cam": {"base_radius": 4.5, "thickness": 3.0},
         "follower": {"kind": "flat", "motion": "oscillating", "pivot_distance": 5.85, "face_offset": 0.0},
         "motion": [{"kind": "dwell", "angle": 15.126050420168067},
                    {"kind": "rise", "angle": 254.11764705882354, "lift": 9.960024889032013, "law": "cycloidal"},
                    {"kind": "dwell", "angle": 15.126050420168067},
                    {"kind": "return", "angle": 60.50420168067227, "lift": 9.960024889032013, "law": "cycloidal"},
                    {"kind": "dwell", "angle": 15.126050420168099}],
         "pitch": {"segments": 24}}
    spec = CamSpec.from_dict(d)
    with pytest.raises(GeometryError) as info:
        design_cam(spec)
    refused = with_remedy(spec, info.value)
    assert isinstance(refused, GeometryError) and refused.kind == "cusp"
    assert str(refused).startswith("cusp at cam angle 305.79"), str(refused)

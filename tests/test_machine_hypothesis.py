"""Random machines (issue 24): 2–3 cams with random phases, laws, lifts, offsets, optional lever or
four-bar linkages and optional [[clearance]] pairs, analysed through the API (``Machine``, design
only, no solids) and checked against what the test computes itself:

* every follower's s (or, with ``motion_at = "tool"``, its tool's) at machine angle θ is the closed
  form of its program's laws at θ − phase;
* the tool points of the cams without a linkage or with a lever, from the follower's geometry;
* each cam's torque is its rigid train's, T = (J·a + P + k·u)·u′, from the spec's load numbers and
  the timing's s, v, a; the machine's total is their sum;
* each clearance pair's minimum is at most the distance the test computes from the two tools'
  positions at every grid angle, and (for tools placed in closed form) within the error bound of a
  0.02° scan written here;
* a broken field raises SpecError naming it.

One more runs the ``machine`` command on a random machine file in a subprocess.
"""
from __future__ import annotations

import copy
import json
import math
import os
import subprocess
import sys
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from cam_workbench import Machine
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.machine.examples import GRIPPER
from cam_workbench.generators.spec.toml_io import dict_to_toml

from .conftest import ROOT, requires_ocp

LAWS = ("harmonic", "cycloidal", "poly345")
RPM = 90.0
W = RPM * 2 * math.pi / 60


def law(name: str, u: np.ndarray) -> np.ndarray:
    """The normalised law y(u), u in [0, 1], written out."""
    if name == "harmonic":
        return (1 - np.cos(np.pi * u)) / 2
    if name == "cycloidal":
        return u - np.sin(2 * np.pi * u) / (2 * np.pi)
    return 10 * u**3 - 15 * u**4 + 6 * u**5


def program_s(motion: list[dict[str, Any]], x_deg: np.ndarray) -> np.ndarray:
    """s at the cam's own angles [deg]: rise, dwell, return, dwell — the segments written out."""
    x = np.mod(x_deg, 360.0)
    s = np.zeros_like(x)
    start, level = 0.0, 0.0
    for seg in motion:
        end = start + seg["angle"]
        inside = (x >= start) & (x < end)
        if seg["kind"] == "dwell":
            s[inside] = level
        else:
            sign = 1.0 if seg["kind"] == "rise" else -1.0
            s[inside] = level + sign * seg["lift"] * law(seg["law"], (x[inside] - start) / seg["angle"])
            level += sign * seg["lift"]
        start = end
    return s


@st.composite
def motions(draw: Any, lift: tuple[float, float]) -> list[dict[str, Any]]:
    rise = draw(st.floats(40.0, 120.0))
    top = draw(st.floats(10.0, 100.0))
    back = draw(st.floats(40.0, 120.0))
    h = draw(st.floats(*lift))
    return [{"kind": "rise", "angle": rise, "lift": h, "law": draw(st.sampled_from(LAWS))},
            {"kind": "dwell", "angle": top},
            {"kind": "return", "angle": back, "lift": h, "law": draw(st.sampled_from(LAWS))},
            {"kind": "dwell", "angle": 360.0 - rise - top - back}]


@st.composite
def cams(draw: Any, name: str) -> dict[str, Any]:
    """One cam: a translating roller (its own point or a lever) or an oscillating roller driving the
    example's four-bar from the tool's motion; a circle tool."""
    kind = draw(st.sampled_from(("roller", "lever", "four_bar")))
    tool = {"circle": {"radius": draw(st.floats(1.0, 10.0))}}
    if kind == "four_bar":
        spec = copy.deepcopy(GRIPPER)
        spec["motion"] = draw(motions((3.0, 10.0)))
        spec["follower"]["arm_inertia"] = draw(st.floats(0.0, 3000.0))
    else:
        spec = {"units": "mm", "cam": {"base_radius": 50.0, "thickness": 10.0, "bore_diameter": 12.0},
                "follower": {"kind": "roller", "roller_radius": 6.0, "offset": draw(st.floats(-10.0, 10.0)),
                             "mass": draw(st.floats(0.0, 2.0)), "preload": draw(st.floats(0.0, 50.0)),
                             "spring_rate": draw(st.floats(0.0, 2.0))},
                "motion": draw(motions((2.0, 20.0)))}
        if kind == "lever":
            spec["linkage"] = {"kind": "lever", "ratio": draw(st.floats(0.5, 3.0)) * draw(st.sampled_from((1, -1))),
                               "pivot_x": draw(st.floats(-80.0, 80.0)), "pivot_y": draw(st.floats(40.0, 150.0)),
                               "direction": draw(st.floats(0.0, 180.0))}
    return {"name": name, "phase": draw(st.floats(0.0, 359.9)), "spec": spec, "tool": tool}


@st.composite
def machines(draw: Any) -> dict[str, Any]:
    n = draw(st.integers(2, 3))
    entries = [draw(cams(f"c{i}")) for i in range(n)]
    pairs = [(a, b) for a in range(n) for b in range(a + 1, n)]
    chosen = draw(st.lists(st.sampled_from(pairs), unique=True, max_size=len(pairs)))
    clearance = [{"between": [f"c{a}", f"c{b}"], "required": draw(st.floats(0.0, 5.0))} for a, b in chosen]
    data: dict[str, Any] = {"machine": {"name": "random", "speed_rpm": RPM}, "cam": entries}
    if clearance:
        data["clearance"] = clearance
    return data


def expected_tool(entry: dict[str, Any], s: np.ndarray) -> np.ndarray | None:
    """The tool point [mm] of a translating roller at lift s: the roller centre (e, √(R_b² − e²) + s)
    without a linkage, pivot + ratio·s·(cos, sin)(direction) through a lever; None for the four-bar."""
    spec = entry["spec"]
    link = spec.get("linkage")
    if link is None:
        e, rb = spec["follower"]["offset"], spec["cam"]["base_radius"]
        return np.c_[np.full_like(s, e), math.sqrt(rb * rb - e * e) + s]
    if link["kind"] == "lever":
        d = math.radians(link["direction"])
        p = link["ratio"] * s
        return np.c_[link["pivot_x"] + p * math.cos(d), link["pivot_y"] + p * math.sin(d)]
    return None


def expected_torque(entry: dict[str, Any], s: np.ndarray, v: np.ndarray, a: np.ndarray) -> np.ndarray:
    """T = (J·a + P + k·u)·u′ [N·mm]: u = s [mm] (J the mass [kg], kg·mm/s² = 10⁻³ N) or s·π/180 [rad]
    (J the arm inertia [kg·mm²], kg·mm²/s² = 10⁻³ N·mm); s, v, a the follower's on the grid."""
    f = entry["spec"]["follower"]
    if f.get("motion") == "oscillating":
        c = math.pi / 180
        return (1e-3 * f["arm_inertia"] * c * a + f["preload_torque"] + f["spring_torque_rate"] * c * s) * c * v / W
    return (1e-3 * f["mass"] * a + f["preload"] + f["spring_rate"] * s) * v / W


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=machines())
def test_random_machine_invariants(data):
    m = Machine(copy.deepcopy(data))
    r = m.analyse()
    deg = r.theta_deg
    for entry, t, torque in zip(data["cam"], r.timings, r.torques):
        given_s = program_s(entry["spec"]["motion"], deg - entry["phase"])
        tool_motion = entry["spec"].get("linkage", {}).get("motion_at") == "tool"
        # the phase: the given motion at machine angle θ is its law at θ − phase
        np.testing.assert_allclose(t.tool_s if tool_motion else t.s, given_s, rtol=0, atol=1e-9 * (1 + given_s.max()))
        tool = expected_tool(entry, t.s)
        if tool is not None:
            np.testing.assert_allclose(t.tool, tool, rtol=0, atol=1e-9)
        np.testing.assert_allclose(torque, expected_torque(entry, t.s, t.v, t.a), rtol=1e-9,
                                   atol=1e-9 * (1 + np.max(np.abs(torque))))
    np.testing.assert_allclose(r.total, np.sum([expected_torque(e, t.s, t.v, t.a) for e, t in zip(data["cam"], r.timings)],
                                               axis=0), rtol=1e-9, atol=1e-8 * (1 + np.max(np.abs(r.total))))
    summary = r.summary()
    assert summary["torque"]["max"] == pytest.approx(float(np.max(r.total)), rel=1e-12, abs=1e-12)
    by_name = {e["name"]: (e, t) for e, t in zip(data["cam"], r.timings)}
    for pair in data.get("clearance", []):
        row = next(p for p in summary["clearance"]["pairs"] if p["between"] == pair["between"])
        (ea, ta), (eb, tb) = (by_name[n] for n in pair["between"])
        ra, rb = ea["tool"]["circle"]["radius"], eb["tool"]["circle"]["radius"]
        sampled = np.hypot(*(ta.tool - tb.tool).T) - ra - rb
        assert row["distance"] <= float(sampled.min()) + 1e-9
        assert row["status"] == ("pass" if row["distance"] >= pair["required"] and not row["overlap"] else "fail")
        if expected_tool(ea, ta.s) is not None and expected_tool(eb, tb.s) is not None:
            fine = np.arange(18000) * 0.02
            pa = expected_tool(ea, program_s(ea["spec"]["motion"], fine - ea["phase"]))
            pb = expected_tool(eb, program_s(eb["spec"]["motion"], fine - eb["phase"]))
            dense = float(np.min(np.hypot(*(pa - pb).T) - ra - rb))
            assert dense - 1e-3 <= row["distance"] <= dense + row["error_bound"] + 1e-9


BREAKS = [
    (lambda d: d["cam"][0].__setitem__("phase", 400.0), "cam[0].phase"),
    (lambda d: d["cam"][1]["spec"]["motion"][0].__setitem__("lift", -1.0), "cam[1].spec.motion[0].lift"),
    (lambda d: d["cam"][1]["spec"]["motion"][1].__setitem__("angle", 5.0), "cam[1].spec.motion"),
    (lambda d: d["cam"][0]["spec"].setdefault("cam", {}).__setitem__("speed_rpm", 2 * RPM), "cam[0].spec.cam.speed_rpm"),
    (lambda d: d["cam"][1]["tool"]["circle"].__setitem__("radius", 0.0), "cam[1].tool.circle.radius"),
    (lambda d: d.__setitem__("clearance", [{"between": ["c0", "c1"], "required": -1.0}]), "clearance[0].required"),
    (lambda d: d["cam"][1].__setitem__("name", "C0"), "cam[1].name"),
]


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=machines(), k=st.integers(0, len(BREAKS) - 1))
def test_random_broken_machine_names_the_field(data, k):
    breaks, field = BREAKS[k]
    breaks(data)
    with pytest.raises(SpecError) as exc:
        Machine(data).analyse()
    assert exc.value.field.startswith(field), (exc.value.field, exc.value.rule)


def machine_toml(data: dict[str, Any], folder: Any) -> str:
    """``data`` as a machine file: each cam's spec in its own file beside it."""
    m = data["machine"]
    out = [f'[machine]\nname = "{m["name"]}"\nspeed_rpm = {float(m["speed_rpm"])!r}\n']
    for c in data["cam"]:
        (folder / f"{c['name']}.toml").write_text(dict_to_toml(c["spec"]), encoding="utf-8")
        out.append(f'[[cam]]\nname = "{c["name"]}"\nspec = "{c["name"]}.toml"\nphase = {float(c["phase"])!r}\n'
                   f'[cam.tool]\ncircle = {{ radius = {float(c["tool"]["circle"]["radius"])!r} }}\n')
    for p in data.get("clearance", []):
        out.append(f'[[clearance]]\nbetween = ["{p["between"][0]}", "{p["between"][1]}"]\n'
                   f'required = {float(p["required"])!r}\n')
    return "".join(out)


@requires_ocp
@settings(max_examples=2, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                               HealthCheck.function_scoped_fixture])
@given(data=machines())
def test_cli_on_a_random_machine_file(tmp_path_factory, data):
    """The command on a random machine file: exit 0 or 3 (a cam may fail its own checks), and
    machine.json's torque and clearances are the API's."""
    folder = tmp_path_factory.mktemp("random-machine")
    (folder / "m.toml").write_text(machine_toml(data, folder), encoding="utf-8")
    out = folder / "out"
    env = dict(os.environ, PYTHONPATH=str(ROOT), COLUMNS="250")
    res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "machine", str(folder / "m.toml"), "-o", str(out),
                          "--animation", "none"], capture_output=True, text=True, env=env)
    assert res.returncode in (0, 3), res.stderr
    report = json.loads((out / "machine.json").read_text(encoding="utf-8"))
    api = Machine(copy.deepcopy(data)).analyse().summary()
    assert report["torque"]["max"] == pytest.approx(api["torque"]["max"], rel=1e-12, abs=1e-12)
    assert report["flywheel"]["inertia_kg_m2"] == pytest.approx(api["flywheel"]["inertia_kg_m2"], rel=1e-12)
    if "clearance" in api:
        assert [p["distance"] for p in report["clearance"]["pairs"]] == \
            pytest.approx([p["distance"] for p in api["clearance"]["pairs"]], rel=1e-12)
    assert (res.returncode == 0) == report["checks"]["passed"]

"""Linkages between the follower and the tool (issue 24, part 3; docs/linkages.md).

Independent references written here: the four-bar's position from the roots of Freudenstein's
quadratic in tan(θ₄/2) (Norton, *Design of Machinery*, Eq. 4.10a), picked by the branch's side
and checked by the vector loop sum; derivatives by central finite differences; the transmission
angle by the law of cosines; toggles where the links are collinear."""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.linkage import LINKAGES, FourBar, Lever
from cam_workbench.generators.motion.program import MotionProgram
from cam_workbench.generators.spec.examples import OSCILLATING_SPEC_DICT
from cam_workbench.generators.spec.model import CamSpec

from .conftest import ROOT

DEG = math.pi / 180.0
FB = dict(ground=100.0, crank=40.0, coupler=90.0, rocker=60.0, crank_offset=60.0)


def osc_spec(**linkage: object) -> CamSpec:
    data = json.loads(json.dumps(OSCILLATING_SPEC_DICT))
    data["linkage"] = {"kind": "four_bar", **FB, **linkage}
    return CamSpec.from_dict(data)


def freudenstein_theta4(a: float, b: float, c: float, d: float, t2: np.ndarray, sigma: int) -> np.ndarray:
    """θ₄ from the quadratic A t² + B t + C = 0, t = tan(θ₄/2) (Norton Eq. 4.10a), with the
    root whose B lies on side ``sigma`` of the line O₄→A; loop closure checked by vector sums."""
    k1, k2, k3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c)
    out = np.empty_like(t2)
    for i, th in enumerate(t2):
        A = math.cos(th) - k1 - k2 * math.cos(th) + k3
        B = -2 * math.sin(th)
        C = k1 - (k2 + 1) * math.cos(th) + k3
        roots = np.roots([A, B, C]) if abs(A) > 1e-14 else np.array([-C / B])
        pa = a * complex(math.cos(th), math.sin(th))
        for r in roots:
            t4 = 2 * math.atan(r.real)
            pb = d + c * complex(math.cos(t4), math.sin(t4))
            if np.sign(((pa - d).conjugate() * (pb - d)).imag) == sigma:
                out[i] = t4
                # the vector loop: O₂A + AB − O₄B − O₂O₄ = 0 with |AB| = b
                assert abs(abs(pb - pa) - b) < 1e-9
                break
        else:
            raise AssertionError("no root on the branch")
    return out


def test_registry_names_the_kinds():
    assert LINKAGES == {"lever": Lever, "four_bar": FourBar}


@pytest.mark.parametrize("r, angular", [(2.5, False), (-0.4, True)])
def test_lever_is_exactly_r_times_the_follower(r: float, angular: bool):
    th = np.linspace(0, 2 * np.pi, 101)
    q = (np.sin(th), np.cos(th), -np.sin(th), -np.cos(th))
    lev = Lever(r, angular, (3.0, -1.0), 0.3, 20.0)
    p = lev.forward(*q)
    for a, b in zip(p, q):
        np.testing.assert_array_equal(a, r * b)
    back = lev.inverse(*p)
    for a, b in zip(back, q):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-15)
    tp = lev.tool_point(q[0])
    z = (3 - 1j) + (20 * np.exp(1j * (0.3 + r * q[0])) if angular else r * q[0] * np.exp(0.3j))
    np.testing.assert_allclose(tp[..., 0] + 1j * tp[..., 1], z, atol=1e-12)
    assert lev.transmission_angle(q[0]) is None and lev.toggles().size == 0


def test_four_bar_forward_is_freudenstein():
    fb = FourBar(100, 40, 90, 60, 60 * DEG, 1)
    q = np.linspace(-0.6, 0.6, 41)
    t2, t3, t4 = fb.angles(q)
    ref = freudenstein_theta4(40, 90, 60, 100, t2, 1)
    np.testing.assert_allclose(np.angle(np.exp(1j * (t4 - ref))), 0, atol=1e-12)
    k1, k2, k3 = 100 / 40, 100 / 60, (40**2 - 90**2 + 60**2 + 100**2) / (2 * 40 * 60)
    np.testing.assert_allclose(k1 * np.cos(t4) - k2 * np.cos(t2) + k3 - np.cos(t2 - t4), 0, atol=1e-12)
    # transmission angle by the law of cosines, e = |A − O₄|
    e2 = 40**2 + 100**2 - 2 * 40 * 100 * np.cos(t2)
    np.testing.assert_allclose(fb.transmission_angle(q), np.arccos((90**2 + 60**2 - e2) / (2 * 90 * 60)), atol=1e-12)


def test_four_bar_derivatives_by_finite_differences():
    fb = FourBar(100, 40, 90, 60, 60 * DEG, -1)
    th = np.linspace(0.1, 2.0, 9)
    qf = lambda t: 0.4 * np.sin(t) + 0.1 * t**2          # noqa: E731
    q = (qf(th), 0.4 * np.cos(th) + 0.2 * th, -0.4 * np.sin(th) + 0.2, -0.4 * np.cos(th))
    p = fb.forward(*q)
    pf = lambda t: freudenstein_theta4(40, 90, 60, 100, 60 * DEG - qf(t), -1)  # noqa: E731  θ₂ = offset − q
    h = 1e-3
    d1 = (pf(th + h) - pf(th - h)) / (2 * h)
    d2 = (pf(th + h) - 2 * pf(th) + pf(th - h)) / h**2
    d3 = (pf(th + 2 * h) - 2 * pf(th + h) + 2 * pf(th - h) - pf(th - 2 * h)) / (2 * h**3)
    np.testing.assert_allclose(p[1], d1, atol=1e-6 * np.max(np.abs(d1)))
    np.testing.assert_allclose(p[2], d2, atol=1e-5 * np.max(np.abs(d2)))
    np.testing.assert_allclose(p[3], d3, atol=1e-4 * np.max(np.abs(d3)))


def test_toggles_are_where_links_are_collinear():
    fb = FourBar(60, 50, 40, 70, 90 * DEG, 1)     # non-Grashof: 40 + 70 > 50 + 60 — the crank toggles
    tg = fb.toggles()
    assert tg.size
    for q in tg:
        pa = 50 * np.exp(1j * (90 * DEG - q))           # θ₂ = offset − q
        e = abs(pa - 60)
        assert min(abs(e - 110), abs(e - 30)) < 1e-9     # coupler and rocker collinear: e = b + c or |b − c|
    for p in fb.tool_toggles():
        pb = 60 + 70 * np.exp(1j * (p + fb.theta4_ref))
        assert min(abs(abs(pb) - 90), abs(abs(pb) - 10)) < 1e-9   # crank and coupler collinear


lengths = st.floats(10.0, 100.0)


@settings(max_examples=60, deadline=None)
@given(lengths, lengths, lengths, lengths, st.floats(-math.pi, math.pi), st.sampled_from([1, -1]))
def test_forward_then_inverse_is_identity(d, a, b, c, off, sigma):
    fb = FourBar(d, a, b, c, off, sigma)                  # Grashof and non-Grashof alike
    if not np.isfinite(fb.theta4_ref):
        return                                            # cannot assemble at q = 0
    q = np.linspace(-0.3, 0.3, 61)
    t2, t3, t4 = fb.angles(q)
    # stay away from both kinds of toggle (ill-conditioned there), on the connected piece of q = 0
    s_out = np.abs(np.sin(t4 - t3))
    s_in = np.abs(np.sin(t2 - t3))
    ok = np.isfinite(t4) & (s_out > 0.05) & (s_in > 0.05)
    keep = np.ones_like(ok)
    mid = 30
    if not ok[mid]:
        return
    keep[:mid] = np.cumprod(ok[:mid][::-1])[::-1].astype(bool)
    keep[mid:] = np.cumprod(ok[mid:]).astype(bool)
    q = q[keep]
    jet = (q, 0.5 + 0 * q, -0.2 + 0 * q, 0.3 + 0 * q)
    back = fb.inverse(*fb.forward(*jet))
    for x, y in zip(back, jet):
        np.testing.assert_allclose(x, y, atol=1e-7 * (1 + np.max(np.abs(y))))


def test_tool_motion_gives_the_specified_tool_motion():
    spec = osc_spec(motion_at="tool", branch="left")          # the branch whose derived lift is ≥ 0
    tool = MotionProgram.from_segments(spec.motion)      # the tool's motion as given
    follower = MotionProgram.from_spec(spec)             # derived through the inverse
    # the left branch (σ = +1: B left of O₄→A) turns the crank clockwise (the arm lifting) for this rise
    th = np.linspace(0, 2 * np.pi, 721)
    q = follower.evaluate(th)
    p = freudenstein_theta4(40, 90, 60, 100, 60 * DEG - q.s * DEG, 1)         # θ₂ = offset − q
    p0 = freudenstein_theta4(40, 90, 60, 100, np.array([60 * DEG]), 1)[0]
    np.testing.assert_allclose(np.angle(np.exp(1j * (p - p0))) / DEG, tool.evaluate(th).s, atol=1e-9)
    # derivatives: the test's forward map of the derived follower, by finite differences
    h = 1e-4
    f = lambda t: freudenstein_theta4(40, 90, 60, 100, 60 * DEG - follower.evaluate(t).s * DEG, 1) / DEG  # noqa
    inner = th[(np.abs(np.mod(th, np.pi / 6)) > 1e-2)]   # away from the segment ends (the jerk jumps)
    k = tool.evaluate(inner)
    np.testing.assert_allclose((f(inner + h) - f(inner - h)) / (2 * h), k.ds, atol=1e-6)
    np.testing.assert_allclose((f(inner + h) - 2 * f(inner) + f(inner - h)) / h**2, k.d2s, atol=1e-3)
    # the derived follower's own derivatives against its positions
    g = lambda t: follower.evaluate(t).s                      # noqa: E731
    kq = follower.evaluate(inner)
    np.testing.assert_allclose((g(inner + h) - g(inner - h)) / (2 * h), kq.ds, atol=1e-6)
    h3 = 2e-3
    d3 = (g(inner + 2 * h3) - 2 * g(inner + h3) + 2 * g(inner - h3) - g(inner - 2 * h3)) / (2 * h3**3)
    np.testing.assert_allclose(d3, kq.d3s, atol=1e-3 * np.max(np.abs(kq.d3s)))


def test_lever_tool_motion_divides_by_the_ratio():
    data = json.loads(json.dumps(OSCILLATING_SPEC_DICT))
    data["linkage"] = {"kind": "lever", "ratio": 1.5, "motion_at": "tool"}
    spec = CamSpec.from_dict(data)
    th = np.linspace(0, 2 * np.pi, 200)
    k, t = MotionProgram.from_spec(spec).evaluate(th), MotionProgram.from_segments(spec.motion).evaluate(th)
    for a, b in zip((k.s, k.ds, k.d2s, k.d3s), (t.s, t.ds, t.d2s, t.d3s)):
        np.testing.assert_allclose(1.5 * a, b, rtol=1e-15, atol=1e-13)


@pytest.mark.parametrize("change, field", [
    ({"ratio": 2.0}, "linkage.ratio"),                                 # not a four-bar's field
    ({"crank": None}, "linkage.crank"),                                # required
    ({"crank_offset": 0.0, "crank": 40.0, "coupler": 30.0, "rocker": 20.0}, "linkage.coupler"),  # cannot assemble
])
def test_bad_fields_name_the_field(change, field):
    data = json.loads(json.dumps(OSCILLATING_SPEC_DICT))
    data["linkage"] = {k: v for k, v in {"kind": "four_bar", **FB, **change}.items() if v is not None}
    with pytest.raises(SpecError) as exc:
        CamSpec.from_dict(data)
    assert exc.value.field == field


def test_a_toggle_within_the_motion_is_refused_with_its_cam_angle():
    # non-Grashof: the crank toggles; start just short of the toggle, the 15° rise passes it
    tgs = FourBar(60, 50, 40, 70, 0.0, 1).toggles()
    # the toggle with the linkage assembled 5° short of it (it closes the range from above)
    # (θ₂ = offset − q: with offset 0 the toggle's crank angle is −q_t; start 5° of lift short of it)
    q_t = next(t for t in tgs if np.isfinite(FourBar(60, 50, 40, 70, -t + 5 * DEG, 1).theta4_ref))
    with pytest.raises(SpecError) as exc:
        osc_spec(ground=60, crank=50, coupler=40, rocker=70, crank_offset=-math.degrees(q_t) + 5)
    assert exc.value.field == "linkage.crank_offset" and "cam angle" in exc.value.rule


def _cli(*args: str, cwd) -> subprocess.CompletedProcess:
    env = {**os.environ, "COLUMNS": "200"}                    # the table's rows unwrapped
    return subprocess.run([sys.executable, "-m", "cam_workbench.cli", *args], capture_output=True, text=True,
                          cwd=cwd, env=env)


def test_cli_check_with_tool_motion(tmp_path):
    spec = osc_spec(motion_at="tool", branch="left")          # the branch whose derived lift is ≥ 0
    from cam_workbench.generators.spec.toml_io import to_toml
    path = tmp_path / "cam.toml"
    path.write_text(to_toml(spec))
    res = _cli("check", str(path), "-o", str(tmp_path / "out"), cwd=ROOT)
    assert res.returncode in (0, 3), res.stderr
    assert "transmission_angle" in res.stdout
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    link = report["linkage"]
    r = report["checks"]["results"]["transmission_angle"]
    assert link["min_transmission_angle_deg"] == r["value"] and link["motion_at"] == "tool"
    assert abs(link["max_displacement"] - 15.0) < 1e-9            # the tool's rise as given
    # cycloidal rise of 15° over 120° at 60 rpm: v_max = 2h/β·ω
    assert abs(link["max_velocity"] - 2 * 15 / (120 * DEG) * 2 * math.pi) < 1e-6
    bad = path.read_text().replace('motion_at = "tool"', 'motion_at = "tools"')
    path.write_text(bad)
    res = _cli("check", str(path), "-o", str(tmp_path / "bad"), cwd=ROOT)
    assert res.returncode == 2 and "linkage.motion_at" in res.stderr and "Traceback" not in res.stderr
    assert not (tmp_path / "bad").exists()


def test_lever_bar_is_one_straight_bar_through_its_fulcrum():
    """A lever attached to a stem on x = 0 rising along +y (its point at (0, 58) at zero lift),
    the tool at (30, 90) at zero lift: the stem pushes at (0, 90 + q).  Ratio 2 along +y: the
    fulcrum is (−30, 90) (|FT| = 2·|FI|, the tool beyond the input); ratio −2 (or ratio 2 along
    −y): (10, 90), between them (|FT| = 2·|FI|).  Tool, forward and inverse are the unattached
    lever's.  Lines that cross: drawn pivot → tool as before; ratio 1 along the stem: no fulcrum."""
    q = np.linspace(-5.0, 25.0, 13)
    up, down = math.pi / 2, -math.pi / 2
    for ratio, direction, fulcrum in ((2.0, up, (-30.0, 90.0)), (-2.0, up, (10.0, 90.0)), (2.0, down, (10.0, 90.0))):
        bare = Lever(ratio, False, (30.0, 90.0), direction)
        lever = bare.on_follower((0.0, 58.0), up)
        j = lever.joints(q)
        assert set(j) == {"input", "fulcrum", "tool"}
        np.testing.assert_allclose(j["input"], np.stack([0 * q, 90.0 + q], axis=-1), atol=1e-12)
        np.testing.assert_allclose(j["fulcrum"], np.broadcast_to(fulcrum, (q.size, 2)), atol=1e-12)
        np.testing.assert_allclose(j["tool"], np.stack([30.0 + 0 * q, 90.0 + ratio * q * math.sin(direction)], axis=-1),
                                   atol=1e-12)
        np.testing.assert_allclose(j["tool"], bare.tool_point(q), atol=0)
        for a, b in zip(lever.forward(q, q, q, q), bare.forward(q, q, q, q)):
            np.testing.assert_array_equal(a, b)
        # collinear: the cross product of F→I and F→T vanishes at every q
        fi, ft = j["input"] - j["fulcrum"], j["tool"] - j["fulcrum"]
        np.testing.assert_allclose(fi[:, 0] * ft[:, 1] - fi[:, 1] * ft[:, 0], 0.0, atol=1e-9)
    crossing = Lever(2.0, False, (30.0, 90.0), 0.0).on_follower((0.0, 58.0), up).joints(q)
    assert set(crossing) == {"pivot", "tool"}
    rod = Lever(1.0, False, (30.0, 90.0), up).on_follower((0.0, 58.0), up).joints(q)
    assert set(rod) == {"input", "tool"}


def test_a_tool_motion_that_needs_the_follower_below_rest_is_refused():
    """The right branch turns the rocker the other way for the same crank turn: the tool's rise
    would need the arm to swing past its rest (a negative lift), refused naming the segment."""
    with pytest.raises(SpecError) as exc:
        osc_spec(motion_at="tool", branch="right")
    assert exc.value.field.startswith("motion[") and exc.value.field.endswith("].lift")
    assert "below zero" in exc.value.rule and "cam angle" in exc.value.rule and "linkage.branch" in exc.value.rule
    data = json.loads(json.dumps(OSCILLATING_SPEC_DICT))
    data["linkage"] = {"kind": "lever", "ratio": -1.5, "motion_at": "tool"}
    with pytest.raises(SpecError) as exc:
        CamSpec.from_dict(data)
    assert "linkage.ratio" in exc.value.rule

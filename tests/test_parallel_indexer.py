"""The parallel (plate-cam) indexer's geometry against constructions written here from the
module's documented conventions alone (frames, zero angles, signs): roller centres from the law,
distances to the built profile polylines, finite-difference normals and velocities.  mm, rad."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.bodies.indexing.parallel import (
    ParallelIndexer, design_parallel, output_angle_from_profile)
from cam_workbench.generators.motion.laws import LAW_FUNCTIONS, evaluate_law

TOUCH = 1e-3          # 1 µm in mm
N_THETA = 1441        # input angles over a turn (≥ 720)


@pytest.fixture(scope="module", params=[{}, {"cams": 3}, {"stations": 4, "law": "cycloidal"},
                                        {"index_angle": math.radians(270), "centre_distance": 70.0,
                                         "law": "poly4567", "index_start": 0.3}],
                ids=["default", "three_cams", "n4_cycloidal", "beta270_shifted"])
def design(request):
    return design_parallel(ParallelIndexer(**request.param))


# -- independent constructions (the module's docstring) -------------------------------------------

def law_psi(ix, theta):
    """ψ (clockwise) and ψ' from the law, continuous over turns."""
    t_st = 2 * math.pi / ix.stations
    rel = theta - ix.index_start
    turns = np.floor(rel / (2 * math.pi))
    u = (rel - 2 * math.pi * turns) / ix.index_angle
    f, f1, _, _ = evaluate_law(ix.law, np.clip(u, 0, 1))
    return t_st * (turns + f), np.where((u >= 0) & (u <= 1), t_st * f1 / ix.index_angle, 0.0)


def a_k(ix, k):
    return math.pi + (ix.cams - 1 - 2 * k) * math.pi / (ix.stations * ix.cams)


def centre_fixed(ix, k, j, theta):
    """Roller j of plane k, fixed frame."""
    psi, _ = law_psi(ix, theta)
    al = a_k(ix, k) + 2 * math.pi * j / ix.stations - psi
    return np.stack([ix.centre_distance + ix.pitch_radius * np.cos(al), ix.pitch_radius * np.sin(al)], -1)


def to_cam(theta, p):
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([c * p[..., 0] + s * p[..., 1], -s * p[..., 0] + c * p[..., 1]], -1)


def seg_distance(pts, poly):
    """Distance of points (n, 2) to the polyline (m, 2), in blocks."""
    a, d = poly[:-1], np.diff(poly, axis=0)
    dd = (d * d).sum(1)
    out = []
    for s in range(0, len(pts), 200):
        q = pts[s:s + 200, None, :] - a[None]
        t = np.clip((q * d).sum(-1) / dd, 0, 1)
        r = q - t[..., None] * d
        out.append(np.sqrt((r * r).sum(-1).min(1)))
    return np.concatenate(out)


def inside(pts, poly):
    """Even-odd ray casting (+x ray) against the closed polyline."""
    x0, y0, x1, y1 = poly[:-1, 0], poly[:-1, 1], poly[1:, 0], poly[1:, 1]
    res = []
    for s in range(0, len(pts), 200):
        px, py = pts[s:s + 200, 0:1], pts[s:s + 200, 1:2]
        straddle = (y0 > py) != (y1 > py)
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = x0 + (py - y0) * (x1 - x0) / (y1 - y0)
        res.append(((straddle & (xc > px)).sum(1) % 2) == 1)
    return np.concatenate(res)


# -- (a) the turret angle recovered from the profiles equals the law ------------------------------

def test_recovered_output_angle_equals_law(design):
    ix = design.indexer
    theta = ix.index_start + np.linspace(0, 2 * math.pi, N_THETA)
    rec = output_angle_from_profile(design, theta)
    psi, _ = law_psi(ix, theta)
    t_st = 2 * math.pi / ix.stations
    psi = np.where(theta >= ix.index_start + 2 * math.pi, psi - t_st, psi)   # the turn's own [0, T]
    err = np.abs(rec.psi - psi)
    assert np.all(np.isfinite(err))
    assert err.max() < 1e-6, (err.max(), theta[err.argmax()])
    assert np.abs(rec.slack).max() < 1e-6          # locked: the feasible turret angles are one point


# -- (b) the dwell: zero velocity, an exact circle about O -----------------------------------------

def test_dwell_is_still_and_a_circle_about_o(design):
    ix = design.indexer
    rel = design.theta - ix.index_start
    dwell = (rel > ix.index_angle) | (rel <= 0)
    assert np.all(design.dpsi[dwell] == 0.0) and np.all(design.d2psi[dwell] == 0.0)
    # from the profile too: the turret stands at T through the dwell
    theta = ix.index_start + np.linspace(ix.index_angle, 2 * math.pi, 400)[1:-1]
    rec = output_angle_from_profile(design, theta)
    assert np.abs(rec.psi - 2 * math.pi / ix.stations).max() < 1e-9
    for k, cam in enumerate(design.cams):
        al = a_k(ix, k)
        r_d = math.hypot(ix.centre_distance + ix.pitch_radius * math.cos(al), ix.pitch_radius * math.sin(al))
        assert cam.dwell_radius == pytest.approx(r_d, abs=1e-12)
        dw = cam.pieces[1]
        assert dw.role == "dwell"
        assert np.abs(np.hypot(*dw.points.T) - r_d).max() < 1e-9
        # its span: the cam-frame polar angles swept by the held roller over the dwell
        span = np.unwrap(np.arctan2(dw.points[:, 1], dw.points[:, 0]))
        assert abs(span[0] - span[-1]) == pytest.approx(2 * math.pi - ix.index_angle, abs=1e-9)
        on_arc = np.abs(cam.profile_radius - (r_d - ix.roller_radius)) < 1e-9
        assert np.abs(np.hypot(*cam.profile[on_arc].T) - (r_d - ix.roller_radius)).max() < 1e-9
        assert on_arc.sum() > 100


# -- (c) engaged rollers touch, no roller penetrates -----------------------------------------------

def test_contact_and_no_penetration_over_a_turn(design):
    ix = design.indexer
    theta = ix.index_start + np.linspace(0, 2 * math.pi, N_THETA)
    rr = ix.roller_radius
    worst_touch, worst_gap = 0.0, np.inf
    for k, cam in enumerate(design.cams):
        (o0, o1), (i0, i1) = cam.windows
        for j in range(ix.stations):
            q = to_cam(theta, centre_fixed(ix, k, j, theta))
            gap = seg_distance(q, cam.profile) - rr
            gap = np.where(inside(q, cam.profile), -gap - 2 * rr, gap)
            worst_gap = min(worst_gap, gap.min())
            engaged = np.zeros(theta.size, bool)
            if j == 0:
                engaged = (theta >= o0) & (theta <= o1)
            elif j == 1:
                engaged = (theta >= i0) & (theta <= i1)
            if engaged.any():
                worst_touch = max(worst_touch, np.abs(gap[engaged]).max())
    assert worst_touch < TOUCH, worst_touch
    assert worst_gap > -TOUCH, worst_gap
    assert design.clearance.gap > 0 and design.clearance.ok


# -- (d) pressure angle, (f) virtual work: from finite differences of positions computed here -------

def fd_contact(ix, k, j, theta, h=1e-6):
    """Fixed-frame centre p, contact normal n (⊥ the locus in the cam frame, outward: away from O
    on the dwell, continuously), and the pitch-circle tangent t (forward, clockwise)."""
    p = centre_fixed(ix, k, j, theta)
    lp = to_cam(theta + h, centre_fixed(ix, k, j, theta + h))
    lm = to_cam(theta - h, centre_fixed(ix, k, j, theta - h))
    d = (lp - lm) / (2 * h)                                        # cam-frame tangent, clockwise
    n_cam = np.stack([-d[:, 1], d[:, 0]], -1)                      # left of a clockwise run: outward
    c, s = np.cos(theta), np.sin(theta)
    n = np.stack([c * n_cam[:, 0] - s * n_cam[:, 1], s * n_cam[:, 0] + c * n_cam[:, 1]], -1)
    n /= np.hypot(*n.T)[:, None]
    rel = p - np.array([ix.centre_distance, 0.0])
    t = np.stack([rel[:, 1], -rel[:, 0]], -1) / ix.pitch_radius    # clockwise about P
    return p, n, t


def test_pressure_angle_against_finite_differences(design):
    ix = design.indexer
    for k, cam in enumerate(design.cams):
        for j in (0, 1):
            e = cam.engaged[:, j]
            th = design.theta[e]
            p, n, t = fd_contact(ix, k, j, th)
            # the normal points from the cam to the roller: outward from O at the dwell
            phi = np.arccos(np.clip(np.abs((n * t).sum(1)), 0, 1))
            assert np.abs(phi - cam.pressure_angle[e, j]).max() < 1e-5
    i = int(np.nanargmax(np.where(design.theta - ix.index_start <= ix.index_angle, design.driving_angle, np.nan)))
    s = design.summary()
    assert s["max_driving_pressure_angle_deg"] == pytest.approx(math.degrees(design.driving_angle[i]))
    assert s["max_driving_pressure_angle_deg"] < 90.0
    json.dumps(s)


def test_virtual_work_identity(design):
    ix = design.indexer
    for k, cam in enumerate(design.cams):
        for j in (0, 1):
            e = cam.engaged[:, j]
            th = design.theta[e]
            p, n, _ = fd_contact(ix, k, j, th)
            _, dpsi = law_psi(ix, th)
            rel = p - np.array([ix.centre_distance, 0.0])
            arm_p = -(rel[:, 0] * n[:, 1] - rel[:, 1] * n[:, 0])   # forward (clockwise) torque per unit force
            arm_o = p[:, 0] * n[:, 1] - p[:, 1] * n[:, 0]          # input torque per unit force
            force = 1000.0
            assert np.abs(force * arm_p * dpsi - force * arm_o).max() < 1e-3 * force * 1e-3
            assert np.abs(arm_p - cam.arm_p[e, j]).max() < 1e-5
            assert np.abs(arm_o - cam.arm_o[e, j]).max() < 1e-5


def test_locked_both_ways_and_dwell_rollers_straddle_op():
    d = design_parallel(ParallelIndexer())
    assert d.locked.ok and d.valid
    dwell = d.theta - d.indexer.index_start > d.indexer.index_angle
    arms = np.concatenate([c.arm_p for c in d.cams], axis=1)[dwell]
    assert np.all(np.nanmax(arms, axis=1) > 0) and np.all(np.nanmin(arms, axis=1) < 0)
    assert np.all(np.nan_to_num(np.concatenate([c.arm_o for c in d.cams], axis=1)[dwell]) == pytest.approx(0, abs=1e-9))


def test_crossover_is_where_the_loci_meet():
    ix = ParallelIndexer()
    d = design_parallel(ix)
    for k, cam in enumerate(d.cams):
        t_in, t_out = cam.crossover_tau
        a = to_cam(np.array([t_in]), centre_fixed(ix, k, 0, np.array([t_in])))[0]
        b = to_cam(np.array([t_out]), centre_fixed(ix, k, 0, np.array([t_out])))[0]
        assert np.hypot(*(a - b)) < 1e-9 and np.hypot(*(a - cam.crossover)) < 1e-9


# -- refusals --------------------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, field", [
    ({"stations": 1}, "indexer.stations"), ({"stations": 2.5}, "indexer.stations"),
    ({"index_angle": 0.0}, "indexer.index_angle"), ({"index_angle": 7.0}, "indexer.index_angle"),
    ({"law": "nope"}, "indexer.law"), ({"centre_distance": -1.0}, "indexer.centre_distance"),
    ({"pitch_radius": 130.0}, "indexer.pitch_radius"), ({"roller_radius": 25.0}, "indexer.roller_radius"),
    ({"cams": 1}, "indexer.cams"), ({"index_start": float("nan")}, "indexer.index_start")])
def test_bad_fields(kwargs, field):
    with pytest.raises(SpecError) as err:
        ParallelIndexer(**kwargs)
    assert err.value.field == field


def test_no_crossover_is_reported():
    with pytest.raises(SpecError) as err:
        design_parallel(ParallelIndexer(centre_distance=70.0))
    assert err.value.field == "indexer.centre_distance" and "no crossover" in str(err.value)


# -- (e) any spec: a design or a SpecError naming a field ------------------------------------------

@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(n=st.integers(3, 12), law=st.sampled_from(sorted(LAW_FUNCTIONS)), beta=st.floats(90.0, 330.0),
       ratio=st.floats(1.05, 3.5), rr=st.floats(0.02, 0.45), cams=st.sampled_from([2, 3]),
       start=st.floats(-3.0, 3.0))
def test_any_spec_designs_or_names_a_field(n, law, beta, ratio, rr, cams, start):
    rp = 40.0
    try:
        ix = ParallelIndexer(stations=n, index_angle=math.radians(beta), law=law, centre_distance=ratio * rp,
                             pitch_radius=rp, roller_radius=rr * rp * math.sin(math.pi / n) * 2, cams=cams,
                             index_start=start)
        d = design_parallel(ix, samples=181)
    except SpecError as err:
        assert err.field.startswith("indexer.")
        return
    assert d.valid
    assert np.isfinite(d.summary()["clearance_mm"])

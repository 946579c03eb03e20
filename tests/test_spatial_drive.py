"""The spatial (barrel, globoidal) indexer's drive sized from its built geometry
(``generators/bodies/indexing/spatial_drive.py``).

The contact points and normals are rebuilt here from :func:`contact_lines`' fixed-frame normals
and :mod:`.spatial`'s frames (p = a + t·d + r_r·n; the cam frame Rz(−θ)·p for the band), and the
moments about the two axes are computed here, not taken from the module."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from cam_workbench.generators.bodies.indexing.spatial import (
    BarrelIndexer, GloboidalIndexer, contact_lines, design_barrel, design_globoidal, roller_axis)
from cam_workbench.generators.bodies.indexing.spatial_drive import spatial_contacts, spatial_drive
from cam_workbench.generators.motion.laws import evaluate_law

CASES = {
    "barrel": (lambda: design_barrel(BarrelIndexer()), 18.0),
    "globoidal": (lambda: design_globoidal(GloboidalIndexer()), 22.0),
    "barrel_n8_cycloidal": (lambda: design_barrel(BarrelIndexer(
        stations=8, law="cycloidal", pitch_radius=80.0, centre_distance=80.0 * math.cos(math.pi / 8),
        roller_radius=12.0, index_start=0.4)), 18.0),
}
LOAD = {"input_speed": 60.0, "inertia": 2.0, "friction_torque": 5.0, "roller_rating": 20e3}


@pytest.fixture(scope="module", params=list(CASES), ids=list(CASES))
def case(request):
    build, width = CASES[request.param]
    d = build()
    return d, width, spatial_contacts(d), spatial_drive(d, roller_width=width, **LOAD)


def _rz_inv(theta, q):
    c, s = np.cos(theta)[..., None], np.sin(theta)[..., None]
    return np.stack([c[..., 0] * q[..., 0] + s[..., 0] * q[..., 1],
                     -s[..., 0] * q[..., 0] + c[..., 0] * q[..., 1], q[..., 2]], axis=-1)


def _loaded(d, c, s):
    """Per θ of the index: the loaded side, roller, and its rebuilt contact points (fixed frame),
    normals, band mask, and the moments of the unit force −n about the cam axis (+z) and about
    the turret axis in ψ's sense (about −y through P)."""
    ix = d.indexer
    back = s.torque_out < 0
    side = np.where(back, 1, -1)
    roller = np.where(back, c.holding.roller, c.forward.roller)
    theta = c.theta + float(ix.index_start)
    pts, nrm = [], []
    for sd in (-1, 1):
        cl = contact_lines(ix, roller, theta, c.t, sd)              # (S, K)
        ax = roller_axis(ix, roller, theta)
        n = cl.normals_fixed
        p = ax.a[:, None, :] + c.t[None, :, None] * ax.d[:, None, :] + float(ix.roller_radius) * n
        pts.append(p)
        nrm.append(n)
    sel = (side == 1)[:, None, None]
    p = np.where(sel, pts[1], pts[0])
    n = np.where(sel, nrm[1], nrm[0])
    band = ix.in_band(_rz_inv(np.broadcast_to(theta[:, None], p.shape[:2]), p))
    force = -n
    m_cam = np.cross(p, force)[..., 2]
    pc = np.array([float(ix.centre_distance), 0.0, 0.0])
    m_tur = -np.cross(p - pc, force)[..., 1]
    return side, roller, p, n, band, m_cam, m_tur


def _dpsi(ix, theta_from_start):
    """ψ' from the law directly."""
    beta = float(ix.index_angle)
    _, f1, _, _ = evaluate_law(ix.law, np.clip(theta_from_start / beta, 0.0, 1.0))
    return (2.0 * math.pi / int(ix.stations)) * f1 / beta


def _weights(t):
    w = np.full(t.size, (t[-1] - t[0]) / (t.size - 1))
    w[[0, -1]] *= 0.5
    return w


def test_virtual_work_is_the_meshing_condition(case):
    """(a) At every engaged point of the loaded line, the moment of the contact force about the cam
    axis is ψ' times its moment about the turret axis; so with the uniform line load
    F_n × (mean cam-axis moment) = T_in = T_out·ψ' (η = 1)."""
    d, _, c, s = case
    ix = d.indexer
    side, _, p, _, band, m_cam, m_tur = _loaded(d, c, s)
    dpsi = _dpsi(ix, c.theta)
    assert band.any(axis=1).all()
    scale = np.linalg.norm(p, axis=-1) * np.maximum(dpsi, 1e-3)[:, None]
    err = np.abs(m_cam - dpsi[:, None] * m_tur) / scale
    assert np.max(err[band]) < 1e-9
    w = np.where(band, _weights(c.t), 0.0)
    mean_cam = np.sum(w * np.where(band, m_cam, 0.0), axis=1) / w.sum(axis=1)
    arm = -side * np.sum(w * np.where(band, m_tur, 0.0), axis=1) / w.sum(axis=1)
    arm_used = np.where(side == 1, c.holding.arm, c.forward.arm)
    assert np.allclose(arm, arm_used, rtol=1e-12, atol=0.0)
    assert np.all(arm > 0)
    f_n = np.abs(s.torque_out) / (arm * 1e-3)
    lhs = f_n * mean_cam * 1e-3 * s.input_omega                     # N · m · rad/s
    p_in = s.torque_in * s.input_omega
    p_out = s.torque_out * s.omega_out
    tol = 1e-9 * np.max(np.abs(p_in))
    assert np.allclose(p_in, p_out, rtol=1e-9, atol=tol)
    assert np.allclose(lhs, p_in, rtol=1e-9, atol=tol)


def test_decelerating_output_is_held_by_the_holding_arm(case):
    """(b) Where T_out < 0 the normal force is |T_out| / (holding arm), where T_out ≥ 0 it is
    T_out / (forward arm); the two arms differ there, so the test tells them apart."""
    _, _, c, s = case
    back = s.torque_out < 0
    assert back.any() and (~back).any()
    assert np.allclose(s.normal_force[back], -s.torque_out[back] / (c.holding.arm[back] * 1e-3), rtol=1e-12)
    assert np.allclose(s.normal_force[~back], s.torque_out[~back] / (c.forward.arm[~back] * 1e-3), rtol=1e-12)
    assert np.max(np.abs(c.holding.arm[back] - c.forward.arm[back])) > 0.1     # mm


def test_finite_and_positive_over_the_index(case):
    """(c) No NaN, positive arms and lengths, finite peaks."""
    d, width, c, s = case
    for ln in (c.forward, c.holding):
        assert np.all(ln.roller >= d.rollers[0]) and np.all(ln.count >= 1)
        for a in (ln.arm, ln.length, ln.margin, ln.spin):
            assert np.all(np.isfinite(a))
        assert np.all(ln.arm > 0) and np.all(ln.length > 0) and np.all(ln.margin > 0)
        assert not np.any(np.isnan(ln.cam_radius)) and np.all(ln.cam_radius != 0)
    for a in (s.normal_force, s.contact_stress, s.torque_in, s.torque_out):
        assert np.all(np.isfinite(a))
    for v in (s.torque_out_peak, s.torque_in_peak, s.normal_force_peak, s.contact_stress_peak, s.l10_hours,
              s.roller_revolutions):
        assert math.isfinite(v) and v > 0


def test_summary_is_json_safe(case):
    """(d) Both summaries serialise as strict JSON."""
    _, _, c, s = case
    json.loads(json.dumps(s.summary(), allow_nan=False))
    json.loads(json.dumps(c.summary(), allow_nan=False))


def test_cam_radius_is_the_flank_section_curvature(case):
    """The Hertz radius r_c = r_r·μ/(1 − μ) is the flank's curvature in the plane normal to the
    roller's axis: the flank's section by that plane, traced by finite differences of the
    contact lines (t solved per input angle to stay in the plane), fitted by a quartic."""
    d, _, c, _ = case
    ix = d.indexer
    rr = float(ix.roller_radius)
    for ln in (c.forward, c.holding):
        i = int(np.argmin(np.abs(ln.cam_radius)))                   # the most curved section
        th0 = float(c.theta[i] + ix.index_start)
        j = int(ln.roller[i])
        # the engaged sample of smallest margin, as the module takes it
        cl = contact_lines(ix, j, np.array(th0), c.t, ln.side)
        inb = ix.in_band(cl.points)
        k = int(np.argmin(np.where(inb, cl.margin, np.inf)))
        t0, p0, n0 = c.t[k], cl.points[k], cl.normals[k]
        th_c = np.array(th0)
        d0 = _rz_inv(th_c, roller_axis(ix, j, th_c).d)

        def point(th, t):
            return contact_lines(ix, j, np.array(th), np.array([t]), ln.side).points[0]

        xs, ys = [], []
        for h in np.linspace(-2e-3, 2e-3, 9):
            t = t0
            for _ in range(20):
                f = (point(th0 + h, t) - p0) @ d0
                g = ((point(th0 + h, t + 1e-5) - p0) @ d0 - f) / 1e-5
                t -= f / g
            q = point(th0 + h, t) - p0
            xs.append(q @ np.cross(d0, n0))
            ys.append(q @ n0)
        curv = 2.0 * np.polyfit(xs, ys, 4)[-3]                       # + bends into the cam: convex
        assert curv == pytest.approx((1.0 - cl.margin[k]) / (rr * cl.margin[k]), rel=1e-6, abs=1e-9)
        assert 1.0 / curv == pytest.approx(ln.cam_radius[i], rel=1e-6)


def test_hertz_length_is_the_engaged_length(case):
    """A roller wider than every engaged length leaves the stress unchanged; a narrower one
    raises it by √(engaged length / width) where the engaged length is longer."""
    d, width, c, s = case
    wide = spatial_drive(d, roller_width=200.0, **LOAD)
    assert np.allclose(wide.contact_stress, s.contact_stress, rtol=1e-12)
    narrow = spatial_drive(d, roller_width=1.0, **LOAD)
    back = s.torque_out < 0
    length = np.where(back, c.holding.length, c.forward.length)
    ok = s.contact_stress > 0
    assert np.any(length > 1.0)
    assert np.allclose(narrow.contact_stress[ok] / s.contact_stress[ok],
                       np.sqrt(np.minimum(length[ok], width) / np.minimum(length[ok], 1.0)), rtol=1e-12)

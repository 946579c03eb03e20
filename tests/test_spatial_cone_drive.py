"""The spatial indexers' drive with CONICAL rollers (``generators/bodies/indexing/spatial_drive.py``),
their cone in report.json, the build's printout and report.html.

(a) The flank's curvature across the roller's generator, from finite differences of the envelope
    surface Σ(θ, t) (:func:`contact_lines`' cam-frame points over a grid of input angles θ and
    axis parameters t: its first and second fundamental forms), and the roller's own, from finite
    differences of the cone's surface about the same point: their sum (the relative normal
    curvature) is 1/(r(t)·μ) — not the roller's curvature cos γ/r over μ, which is short by
    1/cos γ — and the module's flank radius and Hertz roller radius are those numbers.
(b) The virtual-work identity: at the loaded line's engaged points, the contact force along the
    cone's normal N has ψ' times the moment about the turret axis that it has about the cam axis;
    the torques of the sizing follow from the module's arms (the points and normals rebuilt here
    from the cone's radius r(t) and the radial direction, not the module's points).
(c) ``cam-workbench build``'s cone numbers are report.json's.
(d) report.html shows the cone's rows with report.json's numbers.
"""
from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest

from cam_workbench.exporters.report_cells import format_number, quantity_table
from cam_workbench.exporters.report_spatial_indexer import _geometry_rows
from cam_workbench.generators.bodies.indexing.spatial import (
    BarrelIndexer, GloboidalIndexer, contact_lines, design_barrel, design_globoidal, roller_axis)
from cam_workbench.generators.bodies.indexing.spatial_drive import spatial_contacts, spatial_drive
from cam_workbench.generators.motion.laws import evaluate_law

from .conftest import ROOT, requires_ocp
from .test_report import parse
from .test_report_indexer import _cells

CASES = {
    # the globoid's cone with its apex at P: r(t) = t·12/85 over t = 74–96
    "globoidal_apex": lambda: design_globoidal(GloboidalIndexer(roller_cone_angle=math.atan(12.0 / 85.0))),
    "barrel_8deg": lambda: design_barrel(BarrelIndexer(roller_cone_angle=math.radians(8.0), index_start=1.0)),
}
LOAD = {"input_speed": 60.0, "inertia": 2.0, "friction_torque": 5.0, "roller_rating": 20e3}
WIDTH = 22.0


@pytest.fixture(scope="module", params=list(CASES), ids=list(CASES))
def case(request):
    d = CASES[request.param]()
    return d, spatial_contacts(d), spatial_drive(d, roller_width=WIDTH, **LOAD)


def _rz_inv(theta, q):
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([c * q[..., 0] + s * q[..., 1], -s * q[..., 0] + c * q[..., 1], q[..., 2]], axis=-1)


def _radius(ix, t):
    """The cone's radius r(t) = r_r + (t − (t0 + t1)/2)·tan γ, from the indexer's fields."""
    return ix.roller_radius + (np.asarray(t) - 0.5 * (ix.roller_start + ix.roller_end)) * math.tan(ix.roller_cone_angle)


# ---- (a) curvature by finite differences ---------------------------------------------------------
_D1 = np.array([1.0, -8.0, 0.0, 8.0, -1.0]) / 12.0            # f'(0)·h from f(−2h … 2h)
_D2 = np.array([-1.0, 16.0, -30.0, 16.0, -1.0]) / 12.0        # f''(0)·h²


def _normal_curvature(grid, hu, hv, normal, v):
    """Normal curvature, with respect to ``normal``, in the tangent direction ``v`` of a surface
    sampled as ``grid`` (5, 5, 3) at (u0 + i·hu, v0 + j·hv), i, j = −2 … 2: II(w)/I(w) for w the
    parameter direction whose image is along v (4th-order differences)."""
    su = np.einsum("i,ic->c", _D1, grid[:, 2]) / hu
    sv = np.einsum("j,jc->c", _D1, grid[2, :]) / hv
    suu = np.einsum("i,ic->c", _D2, grid[:, 2]) / hu**2
    svv = np.einsum("j,jc->c", _D2, grid[2, :]) / hv**2
    suv = np.einsum("i,j,ijc->c", _D1, _D1, grid) / (hu * hv)
    assert abs(np.dot(v, normal)) < 1e-6 * np.linalg.norm(v)
    a, b = np.linalg.solve(np.array([[su @ su, su @ sv], [su @ sv, sv @ sv]]), np.array([v @ su, v @ sv]))
    second = a * a * (suu @ normal) + 2 * a * b * (suv @ normal) + b * b * (svv @ normal)
    first = a * a * (su @ su) + 2 * a * b * (su @ sv) + b * b * (sv @ sv)
    return second / first


def _curvatures(ix, roller, th0, t0, side):
    """At the contact point of roller ``roller``'s side ``side`` at (θ0, t0): the flank's normal
    curvature across the roller's generator (+ convex: bending towards the roller), the roller's
    own there (+ convex), the point's r(t0), μ, and the roller's normal (cam frame)."""
    h, ht = 1e-3, 1e-2
    ths, ts = th0 + h * np.arange(-2, 3), t0 + ht * np.arange(-2, 3)
    cl = contact_lines(ix, roller, ths, ts, side)                  # (5, 5): the envelope Σ(θ, t), cam frame
    sigma = cl.points
    assert np.isfinite(sigma).all()
    # the normal from the envelope's own tangents, oriented as the roller's outward normal
    normal = np.cross(np.einsum("i,ic->c", _D1, sigma[:, 2]), np.einsum("j,jc->c", _D1, sigma[2, :]))
    normal /= np.linalg.norm(normal)
    normal *= np.sign(normal @ cl.normals[2, 2])
    assert normal @ cl.normals[2, 2] > 1 - 1e-8
    th = np.array(th0)
    ax = roller_axis(ix, roller, th)
    a, d = _rz_inv(th, ax.a), _rz_inv(th, ax.d)
    across = np.cross(d, normal)                                  # across the generator (d × n ∥ d × N)
    across /= np.linalg.norm(across)
    flank = _normal_curvature(sigma, h, ht, normal, across)
    # the roller's cone about the same point: s(φ, t) = a + t·d + r(t)·(cos φ·n0 + sin φ·e0)
    p0 = sigma[2, 2]
    n0 = p0 - a - ((p0 - a) @ d) * d
    n0 /= np.linalg.norm(n0)
    e0 = np.cross(d, n0)
    hp = 1e-3
    phis = hp * np.arange(-2, 3)
    cone = np.array([[a + t * d + _radius(ix, t) * (math.cos(f) * n0 + math.sin(f) * e0) for t in ts] for f in phis])
    assert np.linalg.norm(cone[2, 2] - p0) < 1e-9
    roller_k = -_normal_curvature(cone, hp, ht, normal, across)
    return flank, roller_k, float(_radius(ix, t0)), float(cl.margin[2, 2]), normal


def test_relative_curvature_is_one_over_r_mu(case):
    """(a) Over the index, both sides, three points along the roller: the roller's curvature across
    its generator is cos γ/r(t) (its normal-section radius r/cos γ), and the relative curvature
    κ_roller + κ_flank is 1/(r·μ) (to 1e-6), which the naive cos γ/(r·μ) misses by 1/cos γ."""
    d, _, _ = case
    ix = d.indexer
    g = ix.roller_cone_angle
    assert g != 0
    seen = 0
    for side in (1, -1):
        for x in (0.2, 0.5, 0.8):
            th0 = ix.index_start + x * ix.index_angle
            for t0 in np.linspace(ix.roller_start + 1.0, ix.roller_end - 1.0, 3):
                flank, roller_k, r, mu, _ = _curvatures(ix, 0, th0, t0, side)
                assert roller_k == pytest.approx(math.cos(g) / r, rel=1e-7)
                assert (roller_k + flank) * r * mu == pytest.approx(1.0, rel=1e-6)
                assert abs((roller_k + flank) * r * mu / math.cos(g) - 1.0) > 0.5 * (1.0 / math.cos(g) - 1.0)
                seen += 1
    assert seen == 18


def test_flank_radius_and_roller_radius_of_the_module(case):
    """(a) The module's flank radius of each loaded line (at its most curved θ) is the finite
    differences' 1/κ_flank at the engaged sample of smallest r·μ, and its Hertz roller radius is
    r/cos γ there: 1/roller + 1/flank = 1/(r·μ)."""
    d, c, _ = case
    ix = d.indexer
    g = ix.roller_cone_angle
    for ln in (c.forward, c.holding):
        i = int(np.argmin(np.abs(ln.cam_radius)))
        th0 = float(c.theta[i] + ix.index_start)
        j = int(ln.roller[i])
        cl = contact_lines(ix, j, np.array(th0), c.t, ln.side)
        inb = ix.in_band(_rz_inv(np.array(th0), cl.points_fixed))
        r = _radius(ix, c.t)
        k = int(np.argmin(np.where(inb, r * cl.margin, np.inf)))
        flank, roller_k, rk, mu, _ = _curvatures(ix, j, th0, float(c.t[k]), ln.side)
        assert 1.0 / flank == pytest.approx(ln.cam_radius[i], rel=1e-5)
        assert ln.roller_radius[i] == pytest.approx(rk / math.cos(g), rel=1e-12)
        assert 1.0 / ln.roller_radius[i] + 1.0 / ln.cam_radius[i] == pytest.approx(1.0 / (rk * mu), rel=1e-12)
        assert ln.margin[i] <= cl.margin[k]


def test_hertz_stress_uses_the_cone(case):
    """The Hertz stress is the parallel cylinders' with the loaded line's roller radius r/cos γ,
    its flank radius, and its engaged length along the generator (axial × √(1 + tan²γ))."""
    d, c, s = case
    ix = d.indexer
    back = s.torque_out < 0
    pick = lambda a, b: np.where(back, a, b)                      # noqa: E731
    k_rel = 1.0 / (pick(c.holding.roller_radius, c.forward.roller_radius) * 1e-3) + 1.0 / (
        pick(c.holding.cam_radius, c.forward.cam_radius) * 1e-3)
    length = np.minimum(pick(c.holding.length, c.forward.length), WIDTH) * 1e-3 / math.cos(ix.roller_cone_angle)
    load = s.load
    delta = (1 - load.nu_cam**2) / load.e_cam + (1 - load.nu_roller**2) / load.e_roller
    expect = np.sqrt(np.maximum(s.normal_force, 0.0) * k_rel / (math.pi * length * delta))
    assert np.allclose(s.contact_stress, expect, rtol=1e-9)


# ---- (b) virtual work -----------------------------------------------------------------------------
def test_virtual_work_with_cones(case):
    """(b) At every engaged point of the loaded line, the moment of the force −N about the cam
    axis is ψ' times its moment about the turret axis (N·V = 0); with the uniform line load
    F_n × (mean cam-axis moment) = T_in = T_out·ψ', and the module's arm is the mean turret moment."""
    d, c, s = case
    ix = d.indexer
    k = math.tan(ix.roller_cone_angle)
    back = s.torque_out < 0
    side = np.where(back, 1, -1)
    roller = np.where(back, c.holding.roller, c.forward.roller)
    theta = c.theta + ix.index_start
    ax = roller_axis(ix, roller, theta)
    r = _radius(ix, c.t)
    pts, nrm = [], []
    for sd in (-1, 1):
        cl = contact_lines(ix, roller, theta, c.t, sd)
        n = cl.radial                                               # the radial direction only
        assert np.allclose(np.einsum("...i,...i->...", n, ax.d[:, None, :]), 0.0, atol=1e-12)
        pts.append(ax.a[:, None, :] + c.t[None, :, None] * ax.d[:, None, :] + r[None, :, None] * n)
        nrm.append((n - k * ax.d[:, None, :]) / math.hypot(1.0, k))
        assert np.allclose(pts[-1], cl.points_fixed, atol=1e-9, equal_nan=True)
    sel = (side == 1)[:, None, None]
    p, n = np.where(sel, pts[1], pts[0]), np.where(sel, nrm[1], nrm[0])
    band = ix.in_band(_rz_inv(np.broadcast_to(theta[:, None], p.shape[:2]), p))
    assert band.any(axis=1).all()
    force = -n
    m_cam = np.cross(p, force)[..., 2]
    m_tur = -np.cross(p - np.array([ix.centre_distance, 0.0, 0.0]), force)[..., 1]
    beta = float(ix.index_angle)
    _, f1, _, _ = evaluate_law(ix.law, np.clip(c.theta / beta, 0.0, 1.0))
    dpsi = (2.0 * math.pi / ix.stations) * f1 / beta
    scale = np.linalg.norm(p, axis=-1) * np.maximum(dpsi, 1e-3)[:, None]
    assert np.max((np.abs(m_cam - dpsi[:, None] * m_tur) / scale)[band]) < 1e-9
    w = np.full(c.t.size, (c.t[-1] - c.t[0]) / (c.t.size - 1))
    w[[0, -1]] *= 0.5
    w = np.where(band, w, 0.0)
    mean_cam = np.sum(w * np.where(band, m_cam, 0.0), axis=1) / w.sum(axis=1)
    arm = -side * np.sum(w * np.where(band, m_tur, 0.0), axis=1) / w.sum(axis=1)
    assert np.allclose(arm, np.where(back, c.holding.arm, c.forward.arm), rtol=1e-10, atol=0.0)
    assert np.all(arm > 0)
    f_n = np.abs(s.torque_out) / (arm * 1e-3)
    p_in = s.torque_in * s.input_omega
    tol = 1e-9 * np.max(np.abs(p_in))
    assert np.allclose(p_in, s.torque_out * s.omega_out, rtol=1e-9, atol=tol)
    assert np.allclose(f_n * mean_cam * 1e-3 * s.input_omega, p_in, rtol=1e-9, atol=tol)


def test_spin_rolls_the_cone_without_slip(case):
    """The loaded line's spin is the load-weighted mean of the no-slip spins −e·w/r(t) − Ω·d: at
    each engaged point the roller's surface velocity relative to the cam, with that point's own
    spin, has no component along e = d × n (checked from the rigid motion directly)."""
    d, c, _ = case
    ix = d.indexer
    ln = c.forward
    theta = c.theta + ix.index_start
    ax = roller_axis(ix, ln.roller, theta)
    cl = contact_lines(ix, ln.roller, theta, c.t, ln.side)
    band = ix.in_band(cl.points)
    r = _radius(ix, c.t)
    n, dd = cl.radial, ax.d[:, None, :]
    e = np.cross(dd, n)
    kx = np.array([0.0, 0.0, 1.0])
    # relative velocity of the axis point: D(a + t·d) = (a' + t·d') − k × (a + t·d)
    w = (ax.da - np.cross(kx, ax.a))[:, None, :] + c.t[None, :, None] * (ax.dd - np.cross(kx, ax.d))[:, None, :]
    spin = -np.einsum("...i,...i->...", e, w) / r - np.einsum("...i,...i->...", ax.omega, ax.d)[:, None]
    v = w + np.cross(ax.omega[:, None, :] + spin[..., None] * dd, r[None, :, None] * n)
    assert np.max(np.abs(np.einsum("...i,...i->...", v, e))[band]) < 1e-9
    wt = np.full(c.t.size, (c.t[-1] - c.t[0]) / (c.t.size - 1))
    wt[[0, -1]] *= 0.5
    wb = np.where(band, wt, 0.0)
    assert np.allclose(np.sum(wb * np.where(band, spin, 0.0), axis=1) / wb.sum(axis=1), ln.spin, rtol=1e-10,
                       atol=1e-12)


def test_cylinder_is_unchanged():
    """γ = 0: the Hertz roller radius is r_r itself and the flank radius r_r·μ/(1 − μ) at the
    smallest μ, as before."""
    d = design_globoidal(GloboidalIndexer())
    c = spatial_contacts(d)
    for ln in (c.forward, c.holding):
        assert np.all(ln.roller_radius == 12.0)
        kappa = (1.0 - ln.margin) / (12.0 * ln.margin)
        assert np.array_equal(ln.cam_radius, np.where(np.abs(kappa) * 12.0 <= 1e-12, np.inf, 1.0 / kappa))


# ---- (c), (d) the build -----------------------------------------------------------------------------
@pytest.fixture(scope="module")
def built(tmp_path_factory):
    out = tmp_path_factory.mktemp("cone") / "glob8"
    env = dict(os.environ, PYTHONPATH=str(ROOT), COLUMNS="250")
    run = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "build", "--example", "globoidal_indexer",
                          "--set", "indexer.roller_cone_angle=8", "-o", str(out)],
                         capture_output=True, text=True, env=env)
    assert run.returncode == 0, run.stderr
    report = json.loads((out / "report.json").read_text())
    return run.stdout, report, (out / "report.html").read_text(encoding="utf-8")


@requires_ocp
def test_build_prints_report_jsons_cone(built):
    """(c) The turret line's cone numbers, and the rollers' words, are report.json's."""
    stdout, report, _ = built
    geo = report["indexer"]["geometry"]
    assert "roller_cone_angle" not in geo                       # the radian value is replaced
    assert geo["roller_cone_angle_deg"] == pytest.approx(8.0, rel=1e-12)
    t_m, k = 0.5 * (geo["roller_start"] + geo["roller_end"]), math.tan(math.radians(geo["roller_cone_angle_deg"]))
    assert geo["roller_radius_start"] == pytest.approx(geo["roller_radius"] + (geo["roller_start"] - t_m) * k)
    assert geo["roller_radius_end"] == pytest.approx(geo["roller_radius"] + (geo["roller_end"] - t_m) * k)
    assert geo["roller_cone_apex_t"] == pytest.approx(t_m - geo["roller_radius"] / k)
    line = next(x for x in stdout.splitlines() if x.startswith("  turret:"))
    num = r"([-+]?\d+(?:\.\d*)?(?:e[-+]?\d+)?)"
    m = re.search(rf"conical rollers r = {num}–{num} mm \(γ = {num}°, r_r = {num} mm at mid-length, apex at t = "
                  rf"{num} mm\) over t = {num}–{num} mm", line)
    assert m, line
    keys = ("roller_radius_start", "roller_radius_end", "roller_cone_angle_deg", "roller_radius", "roller_cone_apex_t",
            "roller_start", "roller_end")
    for printed, key in zip(m.groups(), keys):
        assert printed == f"{geo[key]:.6g}", (key, printed, geo[key])
    label = report["follower"]["label"]
    assert f"conical rollers r = {geo['roller_radius_start']:.4g}–{geo['roller_radius_end']:.4g} (γ 8°)" in label
    assert label in stdout


@requires_ocp
def test_report_page_shows_the_cone(built):
    """(d) report.html's geometry table has the cone angle and the radii rows, each cell holding
    report.json's value as the page formats it; a cylinder's table has the angle (0) only."""
    _, report, text = built
    cells = _cells(parse(text))
    for key in ("roller_cone_angle_deg", "roller_radius_start", "roller_radius_end", "roller_cone_apex_t"):
        attrs, shown = cells[f"indexer.geometry.{key}"]
        value = report["indexer"]["geometry"][key]
        assert float(attrs["data-value"]) == value and shown == format_number(value), key
    assert "half cone angle γ" in text
    cyl = json.loads(json.dumps(report))
    geo = cyl["indexer"]["geometry"]
    for key in ("roller_radius_start", "roller_radius_end", "roller_cone_apex_t"):
        del geo[key]
    geo["roller_cone_angle_deg"] = 0.0
    table = quantity_table(cyl, _geometry_rows(False))
    assert 'data-key="indexer.geometry.roller_cone_angle_deg"' in table
    assert "roller_radius_start" not in table and "roller_cone_apex_t" not in table

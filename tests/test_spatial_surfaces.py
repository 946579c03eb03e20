"""The spatial indexers' rib flanks as B-spline surfaces against constructions written here from
the documented conventions of ``generators/bodies/indexing/spatial.py`` alone: the turret angle
from the law, the roller axis in the fixed frame, the cam frame, the axis' relative velocity by
finite differences, the meshing normal and the contact point c + r_r·n; and scipy's B-spline
evaluator as an independent check of the surface evaluation.  mm, rad."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.interpolate import BSpline

from cam_workbench.generators.bodies.indexing.spatial import (
    BarrelIndexer, GloboidalIndexer, contact_lines, design_barrel, design_globoidal)
from cam_workbench.generators.bodies.indexing.spatial_surfaces import (
    BSplineSurface, flank_surfaces, flank_tau_range)
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.motion.laws import evaluate_law

TOL = 1e-3            # 1 µm in mm
H = 1e-5              # finite-difference step [rad]
RANDOM = 10_000       # random points per flank

CASES = {
    "barrel": (BarrelIndexer, design_barrel, {}),
    "barrel_n8_cycloidal": (BarrelIndexer, design_barrel,
                            {"stations": 8, "law": "cycloidal", "pitch_radius": 80.0,
                             "centre_distance": 80.0 * math.cos(math.pi / 8), "roller_radius": 12.0,
                             "index_start": 0.4}),
    "globoidal": (GloboidalIndexer, design_globoidal, {}),
    "globoidal_n8_poly4567": (GloboidalIndexer, design_globoidal,
                              {"stations": 8, "law": "poly4567", "index_angle": math.radians(180),
                               "cam_width": 70.0, "index_start": -0.2}),
}


@pytest.fixture(scope="module", params=list(CASES), ids=list(CASES))
def fitted(request):
    cls, fn, kw = CASES[request.param]
    design = fn(cls(**kw))
    return design, flank_surfaces(design)


# -- the exact envelope, from the conventions ------------------------------------------------------

def _psi(ix, theta):
    """ψ = T·(m + F(u)), m = ⌊(θ − θ_s)/2π⌋, u = clip((θ − θ_s − 2πm)/β, 0, 1)."""
    rel = theta - ix.index_start
    m = np.floor(rel / (2 * math.pi))
    u = np.clip((rel - 2 * math.pi * m) / ix.index_angle, 0.0, 1.0)
    return 2 * math.pi / ix.stations * (m + evaluate_law(ix.law, u)[0])


def _fixed_axis(ix, theta):
    """Roller 0's axis point a, direction d and path direction τ(α) in the fixed frame."""
    alpha = math.pi - 0.5 * 2 * math.pi / ix.stations + _psi(ix, theta)
    c, s, z = np.cos(alpha), np.sin(alpha), np.zeros_like(alpha)
    u = np.stack([c, z, s], axis=-1)
    tang = np.stack([-s, z, c], axis=-1)
    p = np.array([ix.centre_distance, 0.0, 0.0])
    if isinstance(ix, BarrelIndexer):
        return p + ix.pitch_radius * u, np.broadcast_to([0.0, 1.0, 0.0], u.shape), tang
    return np.broadcast_to(p, u.shape), u, tang


def _to_cam(theta, q):
    """Rz(−θ)·q."""
    c, s = np.cos(theta)[..., None], np.sin(theta)[..., None]
    return np.concatenate([c * q[..., :1] + s * q[..., 1:2], -s * q[..., :1] + c * q[..., 1:2], q[..., 2:]], axis=-1)


def _axis_cam(ix, theta, t):
    a, d, _ = _fixed_axis(ix, theta)
    return _to_cam(theta, a + t[..., None] * d)


def exact_envelope(ix, side, theta, t):
    """Cam-frame contact points and roller normals of roller 0's side ``side`` at scattered
    (θ, t): n = ±(d × w)/|d × w|, w the axis point's velocity relative to the cam (central
    differences), the sign making side·(n·τ) > 0; the point c + r_r·n."""
    theta, t = np.broadcast_arrays(np.asarray(theta, float), np.asarray(t, float))
    _, d, tang = _fixed_axis(ix, theta)
    w = (_axis_cam(ix, theta + H, t) - _axis_cam(ix, theta - H, t)) / (2 * H)
    m = np.cross(_to_cam(theta, d), w)
    n = m / np.linalg.norm(m, axis=-1, keepdims=True)
    n = n * np.sign(side * np.einsum("...i,...i->...", n, _to_cam(theta, tang)))[..., None]
    return _axis_cam(ix, theta, t) + ix.roller_radius * n, n


def _random_params(flank, rng, count):
    (u0, u1), (v0, v1) = flank.tau_range, flank.t_range
    return rng.uniform(u0, u1, count), rng.uniform(v0, v1, count)


# -- (a), (c): distance from the exact envelope at random points; the reports bound it ------------

def test_random_points_within_tolerance_and_reported_bounds(fitted):
    design, fs = fitted
    ix = design.indexer
    rng = np.random.default_rng(20261127)
    for flank in fs.flanks:
        tau, t = _random_params(flank, rng, RANDOM)
        exact, n = exact_envelope(ix, flank.side, tau, t)
        diff = flank.surface.evaluate(tau, t) - exact
        err = np.linalg.norm(diff, axis=-1)
        nerr = np.abs(np.einsum("...i,...i->...", diff, n))
        assert err.max() <= TOL, (flank.side, err.max())
        assert err.max() <= flank.max_error, (flank.side, err.max(), flank.max_error)
        assert nerr.max() <= flank.max_normal_error, (flank.side, nerr.max(), flank.max_normal_error)
        assert np.all(nerr <= err + 1e-15)
        assert flank.max_normal_error <= flank.max_error <= TOL
        # the reported location is inside the domain and the error there is the reported one (to the
        # accuracy of the quartic error model)
        at_tau, at_t = flank.max_error_at
        assert flank.tau_range[0] <= at_tau <= flank.tau_range[1] and flank.t_range[0] <= at_t <= flank.t_range[1]
        e_at = np.linalg.norm(flank.surface.evaluate(at_tau, at_t) - exact_envelope(ix, flank.side, at_tau, at_t)[0])
        assert e_at == pytest.approx(flank.max_error, rel=1e-2)


def _dense(nodes, cell, per_cell):
    """``per_cell`` even steps over each of the node cells cell − 1 … cell + 1 (those that exist)."""
    lo, hi = max(cell - 1, 0), min(cell + 1, nodes.size - 2)
    s = np.arange(per_cell + 1) / per_cell
    return np.unique((nodes[lo:hi + 1, None] + s * np.diff(nodes)[lo:hi + 1, None]).ravel())


def test_reported_maximum_matches_a_dense_exact_sampling(fitted):
    """64 × 64 exact samples per node cell around the reported worst point: their largest error
    is the reported maximum to 1e-3 (relative)."""
    design, fs = fitted
    for flank in fs.flanks:
        for value, (at_tau, at_t), normal in ((flank.max_error, flank.max_error_at, False),
                                              (flank.max_normal_error, flank.max_normal_error_at, True)):
            tn, vn = flank.tau_nodes, flank.t_nodes
            i = int(np.clip(np.searchsorted(tn, at_tau) - 1, 0, tn.size - 2))
            k = int(np.clip(np.searchsorted(vn, at_t) - 1, 0, vn.size - 2))
            tt, vv = np.meshgrid(_dense(tn, i, 64), _dense(vn, k, 64), indexing="ij")
            exact, n = exact_envelope(design.indexer, flank.side, tt, vv)
            diff = flank.surface.evaluate(tt, vv) - exact
            dense = np.abs(np.einsum("...i,...i->...", diff, n)) if normal else np.linalg.norm(diff, axis=-1)
            assert dense.max() == pytest.approx(value, rel=1e-3)


def test_the_construction_here_is_contact_lines(fitted):
    design, fs = fitted
    rng = np.random.default_rng(7)
    for flank in fs.flanks:
        tau, t = _random_params(flank, rng, 50)
        ours, n = exact_envelope(design.indexer, flank.side, tau[:, None], t[None, :])
        cl = contact_lines(design.indexer, 0, tau, t, flank.side)
        np.testing.assert_allclose(ours, cl.points, atol=1e-7)
        np.testing.assert_allclose(n, cl.normals, atol=1e-9)


# -- (b): interpolation at the nodes -----------------------------------------------------------

def test_surface_interpolates_the_exact_points_at_its_nodes(fitted):
    design, fs = fitted
    for flank in fs.flanks:
        tt, vv = np.meshgrid(flank.tau_nodes, flank.t_nodes, indexing="ij")
        s = flank.surface.evaluate(tt, vv)
        exact = contact_lines(design.indexer, 0, flank.tau_nodes, flank.t_nodes, flank.side).points
        assert np.abs(s - exact).max() <= 1e-9
        ours, _ = exact_envelope(design.indexer, flank.side, tt, vv)
        assert np.abs(s - ours).max() <= 1e-7


# -- (d): every design reaches 1 µm; the domain and the knots -------------------------------------

def test_reaches_one_micron_with_its_domain_and_knots(fitted):
    design, fs = fitted
    ix = design.indexer
    summary = fs.summary()
    json.dumps(summary, allow_nan=False)
    assert summary["tolerance_mm"] == TOL and len(summary["flanks"]) == 2
    period = 2 * math.pi * design.rollers.size
    for flank, sf in zip(fs.flanks, summary["flanks"]):
        assert flank.max_error <= TOL and sf["max_error_mm"] <= TOL
        assert sf["nodes_tau"] == flank.tau_nodes.size and sf["nodes_t"] == flank.t_nodes.size
        assert flank.fit_seconds > 0 and flank.passes >= 1
        # the domain holds every in-band row of the design's sheet (mod the locus' period) and its
        # ends are just out of the band
        sheet = design.sheet(flank.side)
        lo, hi = flank.tau_range
        rows = sheet.tau[sheet.in_band.any(axis=1)]
        shifted = lo + np.mod(rows - lo, period)
        assert np.all(shifted <= hi + 1e-9)
        ends = contact_lines(ix, 0, np.array([lo, hi]), design.t, flank.side).points
        assert not ix.in_band(ends).any()
        assert (lo, hi) == pytest.approx(flank_tau_range(design, flank.side))
        assert flank.t_range == (ix.roller_start, ix.roller_end)
        # clamped cubic knots; the law's ends are triple knots
        srf = flank.surface
        assert srf.degree_u == srf.degree_v == 3 and not srf.is_rational
        assert srf.knots_u.size == srf.shape[0] + 4 and srf.knots_v.size == srf.shape[1] + 4
        assert np.all(srf.knots_u[:4] == lo) and np.all(srf.knots_u[-4:] == hi)
        assert np.all(np.diff(srf.knots_u) >= 0) and np.all(np.diff(srf.knots_v) >= 0)
        u, mult, _, _ = srf.distinct_knots()
        for b in flank.breaks:
            assert mult[np.argmin(np.abs(u - b))] == 3
            phase = np.mod(b - ix.index_start, 2 * math.pi)
            assert min(phase, abs(phase - ix.index_angle), 2 * math.pi - phase) < 1e-9
        assert np.all(np.isin(mult[1:-1], [1, 3]))


# -- (e): an independent evaluator -------------------------------------------------------------

def test_evaluation_agrees_with_scipy(fitted):
    _, fs = fitted
    rng = np.random.default_rng(3)
    for flank in fs.flanks:
        srf = flank.surface
        (u0, u1), (v0, v1) = srf.domain
        u = np.concatenate([[u0, u1], flank.breaks, rng.uniform(u0, u1, 200)])
        v = np.concatenate([[v0, v1], rng.uniform(v0, v1, 30)])
        nu, nv = srf.shape
        hom = np.concatenate([srf.poles * srf.weights[..., None], srf.weights[..., None]], axis=-1)
        rows = BSpline(srf.knots_u, hom.reshape(nu, nv * 4), 3)(u).reshape(u.size, nv, 4)
        grid = BSpline(srf.knots_v, rows.transpose(1, 0, 2), 3)(v).transpose(1, 0, 2)   # (U, V, 4)
        ref = grid[..., :3] / grid[..., 3:]
        uu, vv = np.meshgrid(u, v, indexing="ij")
        np.testing.assert_allclose(srf.evaluate(uu, vv), ref, rtol=0, atol=1e-9)
        np.testing.assert_allclose(srf.evaluate_grid(u, v), ref, rtol=0, atol=1e-9)


def test_rational_evaluation():
    """A quarter circle (rational quadratic in u) swept along z: points on the cylinder."""
    w = math.sqrt(0.5)
    arc = np.array([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    poles = np.stack([np.concatenate([np.broadcast_to(arc, (2, 3, 2)).transpose(1, 0, 2),
                                      np.broadcast_to([[0.0], [5.0]], (3, 2, 1))], axis=-1)])[0]
    srf = BSplineSurface(2, 1, np.array([0, 0, 0, 1, 1, 1.0]), np.array([0, 0, 1, 1.0]), poles,
                         np.array([[1.0, 1.0], [w, w], [1.0, 1.0]]))
    u, v = np.random.default_rng(1).uniform(0, 1, (2, 500))
    p = srf.evaluate(u, v)
    np.testing.assert_allclose(np.hypot(p[:, 0], p[:, 1]), 1.0, atol=1e-14)
    np.testing.assert_allclose(p[:, 2], 5.0 * v, atol=1e-14)
    assert srf.is_rational


# -- errors --------------------------------------------------------------------------------------

@pytest.mark.parametrize("bad", [0.0, -1e-3, math.nan, True, "1"])
def test_bad_tolerance_is_a_spec_error(bad):
    d = design_globoidal(GloboidalIndexer(), samples=181, lengths=5)
    with pytest.raises(SpecError) as e:
        flank_surfaces(d, bad)
    assert e.value.field == "indexer.fit_tolerance"


def test_unreachable_tolerance_names_what_was_reached():
    d = design_globoidal(GloboidalIndexer())
    with pytest.raises(SpecError) as e:
        flank_surfaces(d, 1e-9)
    assert e.value.field == "indexer.fit_tolerance"
    assert "reached" in e.value.rule and "µm" in e.value.rule


def test_tighter_tolerance_refines():
    d = design_barrel(BarrelIndexer())
    coarse, fine = flank_surfaces(d), flank_surfaces(d, 1e-4)
    for a, b in zip(coarse.flanks, fine.flanks):
        assert b.max_error <= 1e-4 < a.max_error or b.max_error <= a.max_error
        assert b.tau_nodes.size >= a.tau_nodes.size and b.t_nodes.size >= a.t_nodes.size

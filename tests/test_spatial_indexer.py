"""The spatial (barrel and globoidal) indexers' flank surfaces against constructions written here
from the module's documented conventions alone (frames, zero angles, signs): roller axes from the
law, relative velocities and roller-centre velocities by finite differences, distances from the
rollers' axis segments to the sampled flank points.  mm, rad."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from cam_workbench.generators.bodies.indexing.spatial import (
    BarrelIndexer, GloboidalIndexer, design_barrel, design_globoidal, output_angle_from_surface)
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.motion.laws import LAW_FUNCTIONS, evaluate_law

TOUCH = 1e-3          # 1 µm in mm
H = 1e-5              # finite-difference step [rad]

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
    # conical rollers: the globoid's with the apex on the turret axis (pure rolling from the
    # turret's turn), the barrel's widening towards the cam axis's side
    "globoidal_cone_apex": (GloboidalIndexer, design_globoidal, {"roller_cone_angle": math.atan(12.0 / 85.0)}),
    "barrel_cone8": (BarrelIndexer, design_barrel, {"roller_cone_angle": math.radians(8.0), "index_start": 1.0}),
}


@pytest.fixture(scope="module", params=list(CASES), ids=list(CASES))
def design(request):
    cls, fn, kw = CASES[request.param]
    return fn(cls(**kw))


# -- independent constructions (the module's docstring) -------------------------------------------

def law_psi(ix, theta):
    """ψ from the law, continuous over turns."""
    t_st = 2 * math.pi / ix.stations
    rel = np.asarray(theta, dtype=float) - ix.index_start
    turns = np.floor(rel / (2 * math.pi))
    u = (rel - 2 * math.pi * turns) / ix.index_angle
    f, _, _, _ = evaluate_law(ix.law, np.clip(u, 0, 1))
    return t_st * (turns + f)


def axis_fixed(ix, j, theta):
    """Roller j's axis point a and unit direction d in the fixed frame (turret axis through
    (C, 0, 0) along +y, α_j = π + T(j − ½) + ψ, α from +x towards +z)."""
    al = np.pi + 2 * np.pi / ix.stations * (np.asarray(j, dtype=float) - 0.5) + law_psi(ix, theta)
    zero = np.zeros_like(al)
    if isinstance(ix, BarrelIndexer):
        a = np.stack([ix.centre_distance + ix.pitch_radius * np.cos(al), zero, ix.pitch_radius * np.sin(al)], -1)
        d = np.stack([zero, zero + 1.0, zero], -1)
    else:
        a = np.stack([zero + ix.centre_distance, zero, zero], -1)
        d = np.stack([np.cos(al), zero, np.sin(al)], -1)
    return a, d


def roller_radius(ix, s):
    """The roller's radius at axis parameter s: r_r + (s − t_m)·tan γ (t_m the working length's middle)."""
    return ix.roller_radius + (s - 0.5 * (ix.roller_start + ix.roller_end)) * math.tan(ix.roller_cone_angle)


def cone_gap(ix, rho, s):
    """Signed distance [mm] of a point at distance rho from the roller's axis and axial parameter
    s to the roller's side (the cone's generator; cos γ·(ρ − r(s)))."""
    return (rho - roller_radius(ix, s)) * math.cos(ix.roller_cone_angle)


def rz(theta, p):
    """Rz(θ)·p (cam frame → fixed frame)."""
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([c * p[..., 0] - s * p[..., 1], s * p[..., 0] + c * p[..., 1], p[..., 2]], -1)


def turret_rotate(ix, p, dpsi):
    """Turn fixed-frame points p with the turret by dpsi (α grows: about −y through (C, 0, 0))."""
    x, z = p[..., 0] - ix.centre_distance, p[..., 2]
    c, s = np.cos(dpsi), np.sin(dpsi)
    return np.stack([ix.centre_distance + c * x - s * z, p[..., 1], s * x + c * z], -1)


def sheet_rows(design):
    """(tau, points, normals, in_band, t) of each sheet, with row r = roller 0 at input angle τ_r."""
    return [(s.tau, s.points, s.normals, s.in_band) for s in design.sheets]


def interior_rows(design, tau):
    """Rows away from the law's ends (θ_s, θ_s + β), where ψ is smooth for the differences."""
    ix = design.indexer
    rel = np.mod(tau - ix.index_start, 2 * np.pi)
    return (np.abs(rel) > 3 * H) & (np.abs(rel - ix.index_angle) > 3 * H) & (np.abs(rel - 2 * np.pi) > 3 * H)


# -- (a) meshing: n · ∂s/∂θ = 0 with the relative velocity by finite differences -------------------

def test_meshing_condition_holds(design):
    ix = design.indexer
    worst = 0.0
    for tau, pts, nrm, band in sheet_rows(design):
        use = band & interior_rows(design, tau)[:, None]
        r, k = np.nonzero(use)
        th = tau[r]
        p_fix = rz(th, pts[r, k])
        psi0 = law_psi(ix, th)
        moved = []
        for sgn in (-1, 1):
            q = turret_rotate(ix, p_fix, law_psi(ix, th + sgn * H) - psi0)   # the material point, carried
            moved.append(rz(-(th + sgn * H), q))
        v = (moved[1] - moved[0]) / (2 * H)
        res = np.abs(np.einsum("ij,ij->i", v, nrm[r, k])) / np.linalg.norm(v, axis=1)
        worst = max(worst, float(res.max()))
    assert worst < 1e-6


# -- (b) the contact points are on the roller and their normals are its normals -------------------

def test_contacts_on_roller_surface(design):
    ix = design.indexer
    for tau, pts, nrm, band in sheet_rows(design):
        a, d = axis_fixed(ix, 0, tau)
        p = rz(tau[:, None], pts)                                     # fixed frame at θ = τ (roller 0)
        n = rz(tau[:, None], nrm)
        q = p - a[:, None, :]
        s = np.einsum("rki,ri->rk", q, d)
        perp = q - s[..., None] * d[:, None, :]
        dist = np.linalg.norm(perp, axis=-1)
        # a cone has no contact where the meshing has no root (NaN) — never in the band
        has = np.isfinite(dist)
        assert has[band].all() and (has.all() or ix.roller_cone_angle != 0)
        assert np.max(np.abs(dist - roller_radius(ix, s))[has]) < 1e-9
        assert np.max(np.abs(s - design.t[None, :])[has]) < 1e-9
        # the surface normal of the roller (the cone's: its radial direction tilted by −γ about d)
        g = ix.roller_cone_angle
        expect = math.cos(g) * perp / dist[..., None] - math.sin(g) * d[:, None, :]
        assert np.max(np.linalg.norm(expect - n, axis=-1)[has]) < 1e-9
        assert band.any()


# -- (c) no roller cuts the flanks; the engaged ones touch them -----------------------------------

def test_no_penetration_and_touch(design):
    ix = design.indexer
    pts = np.concatenate([s.points[s.in_band] for s in design.sheets])
    n = ix.stations
    theta = design.theta[:-1]
    assert theta.size >= 720
    psi = law_psi(ix, theta)
    worst, touch = np.inf, 0.0
    for i, th in enumerate(theta):
        pf = rz(th, pts)
        engaged_i = design.engaged[:, :, i].any(axis=1)
        for jj in range(n):
            j = int(design.rollers[jj])
            a, d = axis_fixed(ix, j, th)
            q = pf - a
            s = q @ d
            on = (s >= ix.roller_start - 1e-9) & (s <= ix.roller_end + 1e-9)
            if not on.any():
                continue
            gap = cone_gap(ix, np.linalg.norm(q[on] - s[on, None] * d, axis=1), s[on]).min()
            worst = min(worst, gap)
            if engaged_i[jj]:
                touch = max(touch, gap)
        assert abs(design.psi[i] - psi[i]) < 1e-12
    assert worst > -TOUCH
    assert touch < TOUCH


# -- (c2) the regularity margin: μ·q·f_φ = (Σ_θ × Σ_t)·N, the envelope's own derivatives ----------

def test_margin_is_the_envelopes_area_ratio(design):
    """Litvin: the envelope Σ(θ, t) is singular where the meshing function's φ-derivative times
    Σ_θ × Σ_t vanishes.  Σ's derivatives by differences of the contact lines; f_φ by turning the
    contact point about the roller's axis (its velocity relative to the cam by differences of the
    carried material point, as in (a)); μ as the module defines it (Δ/(q·f_φ²))."""
    from cam_workbench.generators.bodies.indexing.spatial import contact_lines
    ix = design.indexer
    g = ix.roller_cone_angle
    q = 1.0 / math.cos(g)
    th = ix.index_start + np.linspace(0.05, 0.95, 9) * ix.index_angle
    t = np.linspace(ix.roller_start, ix.roller_end, 5)
    h = 1e-5
    worst = 0.0
    for side in (1, -1):
        cl = contact_lines(ix, 0, th, t, side)
        pts = lambda a, b: contact_lines(ix, 0, a, b, side).points
        s_t = (pts(th, t + h) - pts(th, t - h)) / (2 * h)
        s_th = (pts(th + h, t) - pts(th - h, t)) / (2 * h)
        area = np.einsum("...i,...i->...", np.cross(s_th, s_t), cl.normals)
        a, d = axis_fixed(ix, 0, th)
        p_fix = rz(th[:, None], cl.points)
        axial = np.einsum("rki,ri->rk", p_fix - a[:, None, :], d)
        foot = a[:, None, :] + axial[..., None] * d[:, None, :]

        def f(phi):
            """N·V at the roller point turned by phi about the axis (fixed to the turret)."""
            v = p_fix - foot
            c, sn = math.cos(phi), math.sin(phi)
            dd = np.broadcast_to(d[:, None, :], v.shape)
            pt = foot + c * v + sn * np.cross(dd, v)
            radial = (pt - foot) / np.linalg.norm(pt - foot, axis=-1, keepdims=True)
            nrm = math.cos(g) * radial - math.sin(g) * dd
            psi0 = law_psi(ix, th)[:, None]
            moved = [rz(-(th[:, None] + e * h), turret_rotate(ix, pt, law_psi(ix, th + e * h)[:, None] - psi0))
                     for e in (-1, 1)]
            vel = rz(th[:, None], (moved[1] - moved[0]) / (2 * h))
            return np.einsum("...i,...i->...", nrm, vel)

        f_phi = (f(1e-4) - f(-1e-4)) / 2e-4
        mu = area / (q * f_phi)
        worst = max(worst, float(np.max(np.abs(mu - cl.margin))))
    assert worst < 1e-5


# -- (d) the turret angle from the surfaces alone --------------------------------------------------

def test_recovered_output_angle(design):
    ix = design.indexer
    rng = np.random.default_rng(7)
    theta = ix.index_start + np.sort(rng.uniform(-2 * np.pi, 4 * np.pi, 720))
    rec = output_angle_from_surface(design, theta)
    assert np.all(rec.count > 0)
    assert np.max(np.abs(rec.psi - law_psi(ix, theta))) < 1e-6


# -- (e) pressure angle against finite differences -------------------------------------------------

def test_pressure_angle(design):
    ix = design.indexer
    for (tau, pts, nrm, band), sheet in zip(sheet_rows(design), design.sheets):
        rel = np.mod(tau - ix.index_start, 2 * np.pi)
        use = band & (interior_rows(design, tau) & (rel < ix.index_angle))[:, None]
        r, k = np.nonzero(use)
        th, t = tau[r], design.t[k]
        pts_ax = []
        for sgn in (-1, 1):
            a, d = axis_fixed(ix, 0, th + sgn * H)
            pts_ax.append(a + t[:, None] * d)
        v = (pts_ax[1] - pts_ax[0]) / (2 * H)
        n = rz(th, nrm[r, k])
        speed = np.linalg.norm(v, axis=1)
        fast = speed > 1e-3 * speed.max()             # the differences lose digits where ψ' → 0
        cos = np.abs(np.einsum("ij,ij->i", n, v)) / speed
        # compared as cos and sin (arccos is ill-conditioned near 0)
        pa = sheet.pressure_angle[r, k]
        assert np.max(np.abs(cos - np.cos(pa))[fast]) < 1e-7
        assert np.max(np.abs(np.sqrt(np.clip(1 - cos**2, 0, 1)) - np.sin(pa))[fast]) < 1e-7
    assert 0 < design.max_pressure_angle.value < np.pi / 2


# -- (f) the dwell: ψ' = 0 and the flanks are surfaces of revolution about the cam axis ------------

def test_dwell_surfaces_of_revolution(design):
    ix = design.indexer
    rel = np.mod(design.theta - ix.index_start, 2 * np.pi)
    dwell = (rel > ix.index_angle + 1e-9) & (rel < 2 * np.pi - 1e-9)
    assert np.all(design.dpsi[dwell] == 0)
    m = design.theta.size - 1
    checked = 0
    for sheet in design.sheets:
        for jj in range(ix.stations):
            rows = jj * m + np.nonzero(dwell)[0]
            pts = sheet.points[rows]
            band = sheet.in_band[rows]
            for k in range(design.t.size):
                if band[:, k].all():
                    rho = np.hypot(pts[:, k, 0], pts[:, k, 1])
                    assert np.ptp(rho) < 1e-9 and np.ptp(pts[:, k, 2]) < 1e-9
                    checked += 1
    assert checked > 0


def test_summary_and_verdicts(design):
    s = design.summary()
    json.dumps(s, allow_nan=False)
    assert s["locked"] and s["engaged_per_angle"]["min"] >= 2
    assert s["min_regularity_margin"]["value_1"] > 0
    assert s["min_rib_thickness"]["value_mm"] > 0


def test_defaults_are_valid():
    for cls, fn in ((BarrelIndexer, design_barrel), (GloboidalIndexer, design_globoidal)):
        assert fn(cls()).locked


def test_bad_fields_name_the_field():
    with pytest.raises(SpecError) as e:
        BarrelIndexer(roller_radius=40.0)
    assert e.value.field == "indexer.roller_radius"
    with pytest.raises(SpecError) as e:
        GloboidalIndexer(root_radius=160.0)
    assert e.value.field == "indexer.root_radius"
    with pytest.raises(SpecError) as e:
        GloboidalIndexer(law="nope")
    assert e.value.field == "indexer.law"
    with pytest.raises(SpecError) as e:
        design_barrel(BarrelIndexer(roller_radius=25.0, pitch_radius=60.0))
    assert e.value.field.startswith("indexer.")
    with pytest.raises(SpecError) as e:
        GloboidalIndexer(roller_cone_angle=math.radians(50))
    assert e.value.field == "indexer.roller_cone_angle" and "45" in e.value.rule
    with pytest.raises(SpecError) as e:              # r(t0) = 8 − 11·tan 44° < 0: the cone closes inside
        GloboidalIndexer(roller_cone_angle=math.radians(44), roller_radius=8.0)
    assert e.value.field == "indexer.roller_cone_angle"
    with pytest.raises(SpecError) as e:              # r(t0) = 12 + 11·tan 40° = 21.2 > t0·sin 15° = 19.2
        GloboidalIndexer(roller_cone_angle=math.radians(-40))
    assert e.value.field == "indexer.roller_radius" and "t = 74" in e.value.rule


def test_cylinder_margin_is_litvins_limit_function():
    """For a cylinder (γ = 0) the margin is −r_r·Ψ/|m|² with Litvin's limit function
    Ψ = n·(D²a + t·D²d) − 2(d·w)(n·Dd) + r_r(n·Dd)² − |m|²/r_r, the derivatives by differences here."""
    from cam_workbench.generators.bodies.indexing.spatial import contact_lines
    for ix in (BarrelIndexer(), GloboidalIndexer()):
        th = ix.index_start + np.linspace(0.1, 0.9, 7) * ix.index_angle
        t = np.linspace(ix.roller_start, ix.roller_end, 4)
        h = 1e-4

        def cam_axis(x):
            a, d = axis_fixed(ix, 0, x)
            return rz(-x, a), rz(-x, d)              # the axis seen from the cam

        (a0, d0), (am, dm), (ap, dp) = cam_axis(th), cam_axis(th - h), cam_axis(th + h)
        da, dd = (ap - am) / (2 * h), (dp - dm) / (2 * h)
        d2a, d2d = (ap - 2 * a0 + am) / h**2, (dp - 2 * d0 + dm) / h**2
        for side in (1, -1):
            cl = contact_lines(ix, 0, th, t, side)
            n = cl.normals
            w = da[:, None, :] + t[None, :, None] * dd[:, None, :]
            dvec = np.broadcast_to(d0[:, None, :], w.shape)
            m2 = np.sum(np.cross(dvec, w) ** 2, axis=-1)
            ndd = np.einsum("...i,...i->...", n, np.broadcast_to(dd[:, None, :], w.shape))
            psi = (np.einsum("...i,...i->...", n, d2a[:, None, :] + t[None, :, None] * d2d[:, None, :])
                   - 2 * np.einsum("...i,...i->...", dvec, w) * ndd + ix.roller_radius * ndd**2
                   - m2 / ix.roller_radius)
            assert np.max(np.abs(-ix.roller_radius * psi / m2 - cl.margin)) < 1e-5


# -- (g) any input: a valid design or a SpecError naming an indexer field -------------------------

@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(n=st.integers(3, 16), law=st.sampled_from(sorted(LAW_FUNCTIONS)),
       beta=st.floats(math.radians(60), math.radians(300)), scale=st.floats(0.3, 3.0),
       rr=st.floats(0.05, 0.4), width=st.floats(0.3, 2.0), start=st.floats(-3.0, 3.0),
       globoid=st.booleans(), offset=st.floats(0.7, 1.2), cone=st.sampled_from([0.0, 0.0, 0.15, -0.15, 0.4]))
def test_any_input_valid_or_spec_error(n, law, beta, scale, rr, width, start, globoid, offset, cone):
    try:
        if globoid:
            ix = GloboidalIndexer(stations=n, law=law, index_angle=beta, index_start=start,
                                  centre_distance=150.0 * scale * offset, roller_radius=60.0 * rr * scale,
                                  roller_start=74.0 * scale, roller_end=96.0 * scale, tip_radius=76.0 * scale,
                                  root_radius=100.0 * scale, cam_width=56.0 * scale * width, roller_cone_angle=cone)
            d = design_globoidal(ix, samples=181, lengths=5)
        else:
            rp = 60.0 * scale
            ix = BarrelIndexer(stations=n, law=law, index_angle=beta, index_start=start,
                               centre_distance=rp * math.cos(math.pi / n) * offset, pitch_radius=rp,
                               roller_radius=rp * rr, roller_start=27.0 * scale, roller_end=45.0 * scale,
                               root_radius=25.0 * scale, outer_radius=40.0 * scale, cam_width=80.0 * scale * width,
                               roller_cone_angle=cone)
            d = design_barrel(ix, samples=181, lengths=5)
    except SpecError as e:
        assert e.field.startswith("indexer.")
        return
    json.dumps(d.summary(), allow_nan=False)
    assert d.min_margin.value > 0 and d.locked

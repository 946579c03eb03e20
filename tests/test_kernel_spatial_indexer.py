"""The spatial indexers' cams (barrel and globoidal) as one OCCT solid
(cam_workbench/kernel/spatial_indexer.py: ``spatial_solid``), for the default ``BarrelIndexer()``
and ``GloboidalIndexer()``, against constructions written here:

* one solid, valid by ``BRepCheck``, inside the cam's envelope (barrel ρ ≤ outer, globoid
  ρ ≤ C − √(tip² − (W/2)²), |z| ≤ W/2), its build time printed;
* its volume (OCCT's adaptive ``BRepGProp``, ε = 1e-6) against the core's closed form plus the rib's
  volume integrated here on a grid of the cam frame: the radial coordinate r (barrel ρ, globoid g —
  the distance from the circle P traces) by the midpoint rule, the cam angle φ on uniform columns,
  and along each column (barrel z, globoid the angle β about that circle) exactly between the
  crossings of the flanks.  The crossings come from the EXACT envelope
  (``spatial.contact_lines`` on a 0.1° × 0.1 mm grid of τ × t, read at r by linear interpolation
  along each contact line); each crossing's side is the roller normal n (into the rib) along the
  column's direction; below the roller's end (where no roller reaches: the rib's root side) the
  flank is the contact line's end point continued at constant (φ, z) / (φ, β) — the rule the solid
  uses.  With 60 levels of r and 720 columns the grid's rib volume differs from 120 × 1440's by
  8e-7 (barrel) and 4e-6 (globoid) of itself, and OCCT's cam volume from core + grid rib by +5e-7
  and −1.5e-6 of itself (measured); the tolerance is 2e-5 of the cam's volume;
* the solid's flank faces carry the fitted surfaces (``flank_surfaces``) unchanged: each side's
  face is a ``Geom_BSplineSurface`` whose poles contain the fitted ones exactly, continued beyond
  both ends of its τ range;
* the engaged rollers (design.engaged at input angles of the index and the dwell): their contact
  points in the band (``contact_lines`` of roller j at θ, ≥ 0.05 mm inside the band) lie within
  1 µm of the solid (``BRepExtrema_DistShapeShape``), the point 0.05 mm inside the roller is
  outside the solid and the point 0.05 mm into the rib inside it; the rim of each engaged roller's
  root-side end, 0.05 mm inside the roller, is outside the solid (the flank's continuation below
  the roller does not cut it);
* a STEP round trip (``cam_workbench.kernel.step.write_step``, OCP's ``STEPControl_Reader``)
  keeps one valid solid and its volume; a bore removes π·r_b²·W exactly.
"""
from __future__ import annotations

import dataclasses
import functools
import math
import time

import numpy as np
import pytest

from cam_workbench.generators.bodies.indexing.spatial import (TWO_PI, BarrelIndexer, GloboidalIndexer,
                                                              contact_lines, design_barrel, design_globoidal,
                                                              roller_axis, to_cam)
from cam_workbench.generators.bodies.indexing.spatial_surfaces import flank_surfaces, flank_tau_range

from .conftest import requires_ocp

pytestmark = requires_ocp

#: the designs' sampling (moderate: the surfaces are fitted to 1 µm whatever it is)
SAMPLES, LENGTHS = 361, 9
#: the rib's volume grid: levels of r, columns of φ; the exact envelope's grid (τ step, t step)
N_R, N_PHI = 60, 720
D_TAU, D_T = math.radians(0.1), 0.1
#: how far [rad] the test's envelope rows reach beyond the flank's fitted τ range
WIDEN = math.radians(20.0)
#: the volume's tolerance (relative to the cam's volume)
VOLUME_REL = 2e-5


def _band_margin(ix, q):
    """> 0 inside the rib's band (spatial.py's module docs), in mm."""
    rho = np.hypot(q[..., 0], q[..., 1])
    ends = 0.5 * ix.cam_width - np.abs(q[..., 2])
    if isinstance(ix, BarrelIndexer):
        return np.minimum.reduce([rho - ix.root_radius, ix.outer_radius - rho, ends])
    g = np.hypot(ix.centre_distance - rho, q[..., 2])
    return np.minimum.reduce([g - ix.tip_radius, ix.root_radius - g, ends])


def _coords(ix, q):
    """(r, φ, a) of cam-frame points: barrel (ρ, φ, z); globoid (g, φ, β), z = g·sin β, ρ = C − g·cos β."""
    rho = np.hypot(q[..., 0], q[..., 1])
    phi = np.arctan2(q[..., 1], q[..., 0])
    if isinstance(ix, BarrelIndexer):
        return rho, phi, q[..., 2]
    c = ix.centre_distance
    return np.hypot(c - rho, q[..., 2]), phi, np.arctan2(q[..., 2], c - rho)


def _axial(ix, q):
    """The unit vector of growing a at cam-frame points q (barrel e_z; globoid e_β)."""
    rho = np.hypot(q[..., 0], q[..., 1])
    er = np.stack([q[..., 0] / rho, q[..., 1] / rho, np.zeros_like(rho)], axis=-1)
    ez = np.broadcast_to(np.array([0.0, 0.0, 1.0]), er.shape)
    if isinstance(ix, BarrelIndexer):
        return ez
    b = np.arctan2(q[..., 2], ix.centre_distance - rho)
    return np.sin(b)[..., None] * er + np.cos(b)[..., None] * ez


def _traces(design, side, levels):
    """Per level r_k: the flank's trace on r = r_k as (φ unwrapped, a, sign of n along a) over the
    exact envelope's rows τ (the row's point where its contact line reaches r_k; beyond the
    contact line's root-side end, that end's φ and a)."""
    ix = design.indexer
    lo, hi = flank_tau_range(design, side)
    tau = np.arange(lo - WIDEN, hi + WIDEN, D_TAU)
    t = np.linspace(ix.roller_start, ix.roller_end, int(round((ix.roller_end - ix.roller_start) / D_T)) + 1)
    cl = contact_lines(ix, 0, tau, t, side)
    # the rows at both ends, with their continuation to the root, are outside the band
    r, phi, a = _coords(ix, cl.points)
    for row in (0, -1):
        assert _band_margin(ix, cl.points[row]).max() < 0
        if isinstance(ix, BarrelIndexer):
            assert abs(cl.points[row, 0, 2]) > 0.5 * ix.cam_width
        else:
            end = cl.points[row, -1]
            assert all(abs(g * math.sin(math.atan2(end[2], ix.centre_distance - math.hypot(end[0], end[1]))))
                       > 0.5 * ix.cam_width for g in (r[row, -1], ix.root_radius))
    sgn = np.sign(np.einsum("...i,...i->...", cl.normals, _axial(ix, cl.points)))
    phi = np.unwrap(phi, axis=0)
    phi = phi - TWO_PI * np.round((phi - phi[:, :1]) / TWO_PI)
    dr = np.diff(r, axis=1)
    assert (dr > 0).all(), "r grows along every contact line"
    root_low = isinstance(ix, BarrelIndexer)            # the root side: barrel small ρ, globoid large g
    rows = np.arange(tau.size)
    out = []
    for rk in levels:
        k = np.clip((r < rk).sum(axis=1), 1, t.size - 1)
        w = (rk - r[rows, k - 1]) / (r[rows, k] - r[rows, k - 1])
        below, above = w < 0, w > 1
        w = np.clip(w, 0.0, 1.0)
        ph = phi[rows, k - 1] + w * (phi[rows, k] - phi[rows, k - 1])
        aa = a[rows, k - 1] + w * (a[rows, k] - a[rows, k - 1])
        s = np.where(w < 0.5, sgn[rows, k - 1], sgn[rows, k])
        beyond_root = below if root_low else above
        beyond_top = above if root_low else below
        assert not beyond_top.any(), "every contact line reaches beyond the rib's top"
        end = 0 if root_low else -1
        ph = np.where(beyond_root, phi[:, end], ph)
        aa = np.where(beyond_root, a[:, end], aa)
        s = np.where(beyond_root, sgn[:, end], s)
        out.append((ph, aa, s))
    return out


def rib_volume(design, n_r: int = N_R, n_phi: int = N_PHI) -> float:
    """The rib's volume [mm³] on the grid of the module docs."""
    ix = design.indexer
    barrel = isinstance(ix, BarrelIndexer)
    r0, r1 = (ix.root_radius, ix.outer_radius) if barrel else (ix.tip_radius, ix.root_radius)
    half = 0.5 * ix.cam_width
    dr, dphi = (r1 - r0) / n_r, TWO_PI / n_phi
    levels = r0 + (np.arange(n_r) + 0.5) * dr
    phis = (np.arange(n_phi) + 0.5) * dphi
    traces = {s: _traces(design, s, levels) for s in (1, -1)}
    total = 0.0
    for k, rk in enumerate(levels):
        a_max = half if barrel else math.asin(half / rk)
        cross_a, cross_s = [], []
        for side in (1, -1):
            ph, aa, sg = traces[side][k]
            d = np.diff(ph)
            assert (d < 0).all() or (d > 0).all(), "a flank's trace is a graph over φ"
            if d[0] < 0:
                ph, aa, sg = ph[::-1], aa[::-1], sg[::-1]
            for m in range(math.floor((ph[0] - phis[-1]) / TWO_PI), math.ceil((ph[-1] - phis[0]) / TWO_PI) + 1):
                x = phis + TWO_PI * m
                inside = (x >= ph[0]) & (x <= ph[-1])
                cross_a.append(np.where(inside, np.interp(x, ph, aa), np.nan))
                cross_s.append(np.where(inside, sg[np.clip(np.searchsorted(ph, x), 1, ph.size - 1)], 0.0))
        big_a, big_s = np.stack(cross_a, axis=1), np.stack(cross_s, axis=1)
        big_a = np.where(np.abs(big_a) <= a_max, big_a, np.nan)
        for j in range(n_phi):
            keep = np.isfinite(big_a[j])
            order = np.argsort(big_a[j][keep])
            a, s = big_a[j][keep][order], big_s[j][keep][order]
            assert a.size > 0 and set(np.abs(s)) == {1.0} and (np.diff(s) != 0).all(), \
                f"the flanks' crossings alternate (r = {rk:.3f}, φ = {math.degrees(phis[j]):.2f}°)"
            ends = np.concatenate([[-a_max] if s[0] < 0 else [], a, [a_max] if s[-1] > 0 else []])
            lo, hi = ends[0::2], ends[1::2]
            if barrel:
                total += rk * dr * dphi * float(np.sum(hi - lo))
            else:                                   # ∫ ρ·g dβ, ρ = C − g·cos β
                c = ix.centre_distance
                total += dr * dphi * float(np.sum(rk * (c * (hi - lo) - rk * (np.sin(hi) - np.sin(lo)))))
    return total


def core_volume(ix, bore: float = 0.0) -> float:
    """The core's closed form [mm³] (less the bore)."""
    h = 0.5 * ix.cam_width
    if isinstance(ix, BarrelIndexer):
        return math.pi * (ix.root_radius**2 - bore**2) * 2 * h
    c, rr = ix.centre_distance, ix.root_radius

    def prim(z):          # ∫ π (C − √(R² − z²))² dz
        s = math.sqrt(rr**2 - z**2)
        return math.pi * ((c**2 + rr**2) * z - z**3 / 3 - c * (z * s + rr**2 * math.asin(z / rr)))

    return prim(h) - prim(-h) - math.pi * bore**2 * 2 * h


@functools.lru_cache(maxsize=None)
def _design(kind):
    ix = BarrelIndexer() if kind == "barrel" else GloboidalIndexer()
    fn = design_barrel if kind == "barrel" else design_globoidal
    design = fn(ix, samples=SAMPLES, lengths=LENGTHS)
    return design, flank_surfaces(design)


@functools.lru_cache(maxsize=None)
def _built(kind):
    """(kind, design, surfaces, the build's details, its wall time [s]) — built once."""
    from cam_workbench.kernel import ocp as occ
    from cam_workbench.kernel.spatial_indexer import build_spatial_solid

    design, surfaces = _design(kind)
    occ.BRepPrimAPI_MakeCylinder(occ.gp_Ax2(occ.gp_Pnt(0, 0, 0), occ.gp_Dir(0, 0, 1)), 1.0, 1.0).Shape()  # load OCP
    t = time.perf_counter()
    build = build_spatial_solid(design, surfaces)
    seconds = time.perf_counter() - t
    print(f"\n{kind}: built in {seconds:.2f} s {({k: round(v, 2) for k, v in build.seconds.items()})}")
    return kind, design, surfaces, build, seconds


@pytest.fixture(scope="module", params=["barrel", "globoidal"])
def built(request):
    return _built(request.param)


def test_one_valid_solid_inside_the_cam_envelope(built):
    from cam_workbench.kernel import ocp as occ
    from cam_workbench.kernel import solids

    kind, design, _, build, seconds = built
    shape = build.solid
    ix = design.indexer
    assert shape.ShapeType() == occ.TopAbs_SOLID
    assert solids.is_valid(shape) and solids.count_solids(shape) == 1
    assert build.rib_pieces == 1 and build.groove_pieces >= 1
    print(f"\n{kind}: the solid in {seconds:.1f} s")        # measured, not asserted (~4 s)
    box = occ.Bnd_Box()
    occ.add_to_box(shape, box, optimal=True)
    x0, y0, z0, x1, y1, z1 = occ.box_limits(box)
    half = 0.5 * ix.cam_width
    reach = ix.outer_radius if kind == "barrel" else ix.centre_distance - math.sqrt(ix.tip_radius**2 - half**2)
    # the optimal box is the exact geometry's enlarged by the edges' tolerances (~1e-6 after the booleans)
    assert reach - 0.5 <= max(-x0, -y0, x1, y1) <= reach + 1e-5
    assert (z0, z1) == pytest.approx((-half, half), abs=1e-5)
    # the flanks' τ continuations interpolate the exact envelope within 1 µm (at their cells' midpoints),
    # the skirts' far edges the projections of their near edges
    assert all(sheet.extension_error <= 1e-3 and sheet.skirt_error <= 1e-3 for sheet in build.sheets)


def test_flank_faces_hold_the_fitted_surfaces(built):
    from cam_workbench.kernel import ocp as occ
    from cam_workbench.kernel import solids

    _, _, surfaces, build, _ = built
    faces = {}
    for face in solids.faces_of(build.solid):
        adaptor = occ.BRepAdaptor_Surface(face)
        if adaptor.GetType() == occ.GeomAbs_BSplineSurface:
            bs = adaptor.BSpline()
            faces.setdefault((bs.NbUPoles(), bs.NbVPoles(), bs.VDegree()), []).append(bs)
    for sheet in build.sheets:
        # a face of the solid lies on OCCT's surface with exactly the sheet's poles
        shape = sheet.flank.poles.shape

        def poles(bs, shape=shape):
            return np.array([[(p.X(), p.Y(), p.Z()) for p in (bs.Pole(i + 1, j + 1) for j in range(shape[1]))]
                             for i in range(shape[0])])

        assert any(np.array_equal(poles(bs), sheet.flank.poles) for bs in faces[(shape[0], shape[1], 3)])
        fitted = surfaces.flank(sheet.side).surface
        n = fitted.poles.shape[0]
        k = np.flatnonzero(np.all(sheet.flank.poles[:, 0] == fitted.poles[0, 0], axis=1))
        assert k.size == 1
        assert np.array_equal(sheet.flank.poles[k[0]:k[0] + n], fitted.poles)
        u, v = np.linspace(*fitted.domain[0], 97), np.linspace(*fitted.domain[1], 9)
        assert np.abs(sheet.flank.evaluate_grid(u, v) - fitted.evaluate_grid(u, v)).max() <= 1e-9
        assert np.array_equal(sheet.flank.knots_v, fitted.knots_v)
        assert sheet.tau_range[0] < fitted.domain[0][0] and sheet.tau_range[1] > fitted.domain[0][1]


def test_volume_against_the_grid_integral(built):
    from cam_workbench.kernel import solids

    kind, design, _, build, _ = built
    volume = solids.kernel_volume(build.solid, solids.SURFACE_VOLUME_EPS)
    t = time.perf_counter()
    rib = rib_volume(design)
    core = core_volume(design.indexer)
    print(f"\n{kind}: OCCT {volume:.3f} mm³, core {core:.3f} + rib {rib:.3f} = {core + rib:.3f} mm³ "
          f"(rel {(volume - core - rib) / volume:.2e}; grid {time.perf_counter() - t:.1f} s)")
    assert volume == pytest.approx(core + rib, rel=VOLUME_REL)


def _rollers_at(design, i):
    """(θ, [(roller j, side)] engaged at the design's θ sample i)."""
    pairs = [(int(j), side) for ji, j in enumerate(design.rollers) for si, side in enumerate((1, -1))
             if design.engaged[ji, si, i]]
    return float(design.theta[i]), pairs


def test_engaged_rollers_touch_the_solid_and_do_not_penetrate(built):
    from cam_workbench.kernel import ocp as occ

    kind, design, _, build, _ = built
    ix, solid = design.indexer, build.solid
    n1, s = design.index_rows, design.theta.size
    classifier = occ.BRepClass3d_SolidClassifier(solid)

    def state(p):
        classifier.Perform(occ.gp_Pnt(*map(float, p)), 1e-7)
        return classifier.State()

    t = np.linspace(ix.roller_start, ix.roller_end, 37)
    worst, checked = 0.0, 0
    for i in (n1 // 4, (3 * n1) // 5, (n1 + s - 1) // 2):
        theta, pairs = _rollers_at(design, i)
        assert len(pairs) >= 2
        for j, side in pairs:
            cl = contact_lines(ix, j, theta, t, side)
            ok = np.flatnonzero(_band_margin(ix, cl.points) >= 0.05)
            assert ok.size >= 3
            for k in (ok[ok.size // 3], ok[(2 * ok.size) // 3]):
                p, n = cl.points[k], cl.normals[k]
                vertex = occ.BRepBuilderAPI_MakeVertex(occ.gp_Pnt(*map(float, p))).Vertex()
                dist = occ.BRepExtrema_DistShapeShape(vertex, solid)
                dist.Perform()
                assert dist.IsDone()
                worst = max(worst, dist.Value())
                assert state(p - 0.05 * n) != occ.TopAbs_IN, f"roller {j} (side {side:+d}) at θ = {theta:.4f}"
                assert state(p + 0.05 * n) == occ.TopAbs_IN
                checked += 1
    print(f"\n{kind}: {checked} contact points, farthest {worst:.2e} mm from the solid")
    assert worst <= 1e-3
    # the rim of the roller's root-side end (the flank's continuation lies below it)
    theta, pairs = _rollers_at(design, n1 // 2)
    rr = ix.roller_radius
    t_end = ix.roller_start if kind == "barrel" else ix.roller_end
    inward = 1.0 if kind == "barrel" else -1.0
    for j in sorted({j for j, _ in pairs}):
        ax = roller_axis(ix, j, theta)
        d = ax.d
        e1 = np.cross(d, [0.0, 0.0, 1.0]) if abs(d[2]) < 0.9 else np.cross(d, [1.0, 0.0, 0.0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(d, e1)
        om = np.linspace(0.0, TWO_PI, 12, endpoint=False)
        rim = (ax.a + (t_end + inward * 0.05) * d + (rr - 0.05) * (np.cos(om)[:, None] * e1 + np.sin(om)[:, None] * e2))
        rim = to_cam(theta, rim)
        for p in rim[_band_margin(ix, rim) > 0]:
            assert state(p) != occ.TopAbs_IN, f"roller {j}'s end at θ = {theta:.4f}"


def test_step_round_trip_keeps_the_volume(built, tmp_path):
    from cam_workbench.kernel import ocp as occ
    from cam_workbench.kernel import solids
    from cam_workbench.kernel.step import write_step

    kind, _, _, build, _ = built
    path = tmp_path / f"{kind}.step"
    write_step(build.solid, path, "mm", f"{kind} indexer cam")
    reader = occ.STEPControl_Reader()
    assert reader.ReadFile(str(path)) == occ.IFSelect_RetDone
    reader.TransferRoots()
    back = reader.OneShape()
    assert solids.is_valid(back) and solids.count_solids(back) == 1
    eps = solids.SURFACE_VOLUME_EPS
    assert solids.kernel_volume(back, eps) == pytest.approx(solids.kernel_volume(build.solid, eps), rel=1e-7)


def test_a_bore_removes_its_cylinder():
    from cam_workbench.kernel import solids
    from cam_workbench.kernel.spatial_indexer import spatial_solid

    _, design, surfaces, build, _ = _built("globoidal")
    plain = build.solid
    bored = spatial_solid(design, surfaces, bore_radius=20.0)
    assert solids.is_valid(bored) and solids.count_solids(bored) == 1
    eps = solids.SURFACE_VOLUME_EPS
    removed = math.pi * 20.0**2 * design.indexer.cam_width
    assert solids.kernel_volume(plain, eps) - solids.kernel_volume(bored, eps) == pytest.approx(removed, rel=1e-7)


def test_bad_arguments_are_refused():
    from cam_workbench.kernel.spatial_indexer import spatial_solid

    design, surfaces = _design("barrel")
    for bore in (-1.0, 25.0, math.nan):
        with pytest.raises(ValueError, match="bore_radius"):
            spatial_solid(design, surfaces, bore_radius=bore)
    other = design_barrel(BarrelIndexer(cam_width=70.0), samples=SAMPLES, lengths=LENGTHS)
    with pytest.raises(ValueError, match="another indexer"):
        spatial_solid(other, surfaces)


#: index starts [°] of the rotation check (the default's 0 built above); 60 and 300 made a wrong or no
#: solid when the band's and the core's seams were fixed at φ = 0
INDEX_STARTS = (60.0, 300.0, 137.0)


@pytest.mark.parametrize("kind", ["barrel", "globoidal"])
def test_the_index_start_turns_the_cam_and_keeps_its_volume(kind):
    """The index start only turns the cam about its axis: at other starts the solid is one valid
    solid of the default's volume (to 2e-6 — both OCCT's adaptive integration of fitted surfaces)."""
    from cam_workbench.kernel import solids
    from cam_workbench.kernel.spatial_indexer import build_spatial_solid

    _, design0, _, build0, _ = _built(kind)
    reference = solids.kernel_volume(build0.solid, 1e-6)
    for start in INDEX_STARTS:
        ix = dataclasses.replace(design0.indexer, index_start=math.radians(start))
        fn = design_barrel if kind == "barrel" else design_globoidal
        design = fn(ix, samples=SAMPLES, lengths=LENGTHS)
        t = time.perf_counter()
        build = build_spatial_solid(design, flank_surfaces(design))
        seconds = time.perf_counter() - t
        volume = solids.kernel_volume(build.solid, 1e-6)
        print(f"\n{kind} index start {start:g}°: {volume:.6f} mm³ ({volume / reference - 1:+.2e}), "
              f"seam {math.degrees(build.seam):g}°, built in {seconds:.2f} s")
        assert solids.is_valid(build.solid) and solids.count_solids(build.solid) == 1, start
        assert (build.rib_pieces, build.groove_pieces) == (build0.rib_pieces, build0.groove_pieces), start
        assert volume == pytest.approx(reference, rel=2e-6), start

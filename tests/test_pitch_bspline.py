"""pitch.representation = "bspline": the periodic B-spline against scipy, the least-squares fit
against a dense lstsq, exact clamping and Bézier form, the reported deviations against
independent measurements, valid kernel solids with OCCT's exact offset curve, STEP (and what
OCCT's STEP writer does with offset curves)."""
import math

import numpy as np
import pytest
from scipy.interpolate import BSpline

from cam_workbench.generators import default_spec, design_cam, load_spec
from cam_workbench.generators.pitch.bspline import (PeriodicBSpline, bezier_form, distance_to_true_profile,
                                      least_squares_periodic, offset_points)

from .conftest import ROOT, requires_ocp

EX5 = ROOT / "tests" / "fixtures" / "thesis_ex5_final.toml"


def random_periodic(n=13, seed=1):
    rng = np.random.default_rng(seed)
    b = np.r_[0, np.sort(rng.uniform(0, 2 * np.pi, n - 1)), 2 * np.pi]
    return PeriodicBSpline(5, b, rng.normal(size=n) + 1j * rng.normal(size=n))


def test_periodic_evaluation_matches_scipy_and_is_periodic():
    c = random_periodic()
    ref = BSpline(c.extended_knots, c.poles[np.arange(c.n_spans + 5) % c.n_spans], 5)
    u = np.linspace(0, 2 * np.pi, 2001)
    vals = c.evaluate(u, 3)
    for d in range(4):
        want = ref(u) if d == 0 else ref.derivative(d)(u)
        assert np.max(np.abs(vals[d] - want)) < 1e-9 * max(1, np.max(np.abs(want)))
    # C⁴ across the seam
    lo, hi = c.evaluate(np.array([1e-13]), 4), c.evaluate(np.array([2 * np.pi - 1e-13]), 4)
    for a, b in zip(lo, hi):
        assert abs(a[0] - b[0]) < 1e-6 * max(1, abs(a[0]))


def test_clamped_and_bezier_forms_are_the_same_curve():
    c = random_periodic()
    nb = c.to_nurbs(scale=3.0)
    assert nb.knots[0] == 0 and nb.knots[-1] == pytest.approx(6 * np.pi)
    assert np.all(np.diff(np.unique(nb.knots[6:-6], return_counts=True)[1]) == 0)   # simple inside
    u = np.linspace(0, 2 * np.pi, 3001)
    q = nb.evaluate(3.0 * u)
    assert np.max(np.abs(q[:, 0] + 1j * q[:, 1] - c.evaluate(u)[0])) < 1e-12
    bz = bezier_form(nb)
    assert len(bz.bezier_pieces()) == c.n_spans and bz.n_poles == 5 * c.n_spans + 1
    assert np.max(np.abs(bz.evaluate(3.0 * u) - q)) < 1e-12


def test_least_squares_fit_equals_a_dense_lstsq():
    """Our sparse normal equations against numpy's lstsq on scipy's design matrix with the
    periodic columns folded."""
    rng = np.random.default_rng(3)
    n = 17
    b = np.r_[0, np.sort(rng.uniform(0, 2 * np.pi, n - 1)), 2 * np.pi]
    u = np.sort(rng.uniform(0, 2 * np.pi, 400))
    data = np.exp(1j * u) * (3 + 0.3 * np.cos(3 * u)) + 0.01 * rng.normal(size=400)
    ours = least_squares_periodic(b, 5, u, data)
    t = PeriodicBSpline(5, b, np.zeros(n, complex)).extended_knots
    dm = BSpline.design_matrix(u, t, 5).toarray()           # (400, n + 5)
    folded = dm[:, :n].copy()
    folded[:, :5] += dm[:, n:]
    sol, *_ = np.linalg.lstsq(folded, np.column_stack([data.real, data.imag]), rcond=None)
    assert np.allclose(ours.poles, sol[:, 0] + 1j * sol[:, 1], rtol=0, atol=1e-10)


@pytest.fixture(scope="module")
def designs():
    out = {}
    for name, spec in {
        "default": default_spec(),
        "cw_negative_offset": default_spec().replace(**{"cam.direction": "cw", "follower.offset": -10.0}),
        "knife": default_spec().replace(**{"follower.kind": "knife", "cam.bore_diameter": 8.0}),
        "example5": load_spec(EX5),
    }.items():
        out[name] = design_cam(spec.replace(**{"pitch.representation": "bspline"}))
    return out


def test_deviation_is_the_papers_measure(designs):
    """max |s_actual − s| reported = an independent measurement: the follower line
    x = e meets the fitted curve, found by bisection on dense samples of the curve."""
    d = designs["default"]
    pc = d.pitch
    th = np.radians(np.arange(0, 360, 0.5))
    u = np.linspace(0, 2 * np.pi, 400_001)
    pts = pc.curve.evaluate(u)[0]
    s_act = []
    for t in th:
        z = np.exp(1j * pc.geometry.sense * t) * pts
        x = z.real - pc.geometry.offset
        cross = np.flatnonzero((x[:-1] <= 0) != (x[1:] <= 0) & (z.imag[:-1] > 0))
        cross = cross[z.imag[cross] > 0]
        j = cross[0]
        f = x[j] / (x[j] - x[j + 1])
        s_act.append(z.imag[j] + f * (z.imag[j + 1] - z.imag[j]) - pc.geometry.s0)
    dev = np.abs(np.array(s_act) - pc.program.s(th))
    assert np.max(dev) <= d.max_deviation[0] * (1 + 1e-3)
    assert np.max(dev) > 0.5 * d.max_deviation[0]
    assert d.summary()["pitch"]["max_deviation"] < 2e-4       # 60 spans, like the PH curve's 1.5e-4


def true_profile_polyline(d, n=720_000):
    """The true profile (the pitch curve offset by r_f), densely, from the closed-form motion."""
    th = np.linspace(0, 2 * np.pi, n, endpoint=False)
    g = d.geometry
    k = d.program.evaluate(th)
    dp = np.exp(-1j * g.sense * th) * (g.sense * (g.s0 + k.s) - 1j * g.sense * g.offset + 1j * k.ds)
    return g.pitch_points(th, k.s) - 1j * g.sense * d.spec.roller_radius * dp / np.abs(dp)


def test_profile_errors_against_an_independent_polyline(designs):
    d = designs["example5"]
    poly = true_profile_polyline(d)
    v, pts = d.profile.sample(8)
    z = pts[:, 0] + 1j * pts[:, 1]
    # nearest polyline vertex, then the distance to its two edges
    ang = np.mod(np.angle(z), 2 * np.pi)
    order = np.argsort(np.mod(np.angle(poly), 2 * np.pi))
    pa = np.mod(np.angle(poly), 2 * np.pi)[order]
    j = np.searchsorted(pa, ang) % len(order)
    best = np.full(z.shape, np.inf)
    for off in range(-40, 41):
        i = order[(j + off) % len(order)]
        a, b = poly[i], poly[(i + 1) % len(poly)]
        t = np.clip(((z - a) * np.conj(b - a)).real / np.abs(b - a) ** 2, 0, 1)
        best = np.minimum(best, np.abs(z - (a + t * (b - a))))
    reported = d.summary()["profile"]["max_error"]
    assert np.max(best) == pytest.approx(reported, rel=0.05)
    assert reported < 2e-4


@requires_ocp
@pytest.mark.parametrize("name", ["default", "cw_negative_offset", "knife", "example5"])
def test_kernel_solids_are_valid_with_exact_offset_curves(designs, name, tmp_path):
    from cam_workbench.kernel import solids as occ_build
    from cam_workbench.exporters.step import export_step
    from cam_workbench.kernel.step import has_offset_curves, read_step

    d = designs[name]
    exact = occ_build.cam_solid(d)
    fitted = occ_build.cam_solid(d, exact_offset=False)
    t = d.spec.cam.thickness
    for shape in (exact, fitted):
        assert occ_build.is_valid(shape) and occ_build.count_solids(shape) == 1
    assert has_offset_curves(exact) == d.spec.is_roller
    assert not has_offset_curves(fitted)
    # the fitted solid's volume is its profile's area (Green's theorem on the NURBS) × thickness
    assert occ_build.kernel_volume(fitted) == pytest.approx(d.area * t, rel=1e-9)
    if d.spec.is_roller:
        # the exact offset's area by Steiner's formula on the fitted pitch B-spline
        rr = d.spec.roller_radius
        steiner = abs(d.pitch_nurbs.area()) - rr * d.pitch.spline.arc_length + math.pi * rr * rr
        bore = math.pi * (d.spec.cam.bore_diameter / 2) ** 2
        top = occ_build.planar_face_at(exact, t)
        assert occ_build.face_area(top) == pytest.approx(steiner - bore, rel=1e-9)
        assert occ_build.kernel_volume(exact) == pytest.approx((steiner - bore) * t, rel=1e-8)
        # OCCT's own evaluation of the offset curve = our offset of the same B-spline
        from cam_workbench.kernel import ocp as occ

        ex = occ.TopExp_Explorer(top, occ.TopAbs_EDGE)
        worst = 0.0
        while ex.More():
            c = occ.BRepAdaptor_Curve(occ.topods_edge(ex.Current()))
            if c.GetType() == occ.GeomAbs_OffsetCurve:
                us = np.linspace(c.FirstParameter(), c.LastParameter(), 7)
                pts = np.array([(p.X() + 1j * p.Y()) for p in map(c.Value, us)])
                theta0 = np.radians(d.pitch.cam_angle_of_point(pts * (1 + rr / np.abs(pts))))
                worst = max(worst, float(np.max(distance_to_true_profile(
                    pts, theta0, d.program, d.geometry, rr))))
            ex.Next()
        assert worst <= d.bspline.errors.exact_offset * 1.05 + 1e-9
    # STEP holds the fitted solid; the exact one is refused (OCCT would write an empty model)
    path = export_step(fitted, tmp_path / "cam.step", d.spec.units)
    back = read_step(path, d.spec.units)
    assert occ_build.is_valid(back) and occ_build.kernel_volume(back) == pytest.approx(d.area * t, rel=1e-9)
    if d.spec.is_roller:
        with pytest.raises(ValueError, match="offset-curve edges"):
            export_step(exact, tmp_path / "exact.step", d.spec.units)
        assert not (tmp_path / "exact.step").exists()


@requires_ocp
@pytest.mark.parametrize("bore", [0.0, 10.0])
def test_occt_step_writer_drops_offset_curves(tmp_path, bore):
    """What OCCT's STEP writer does with an offset-curve solid (GeomToStep_MakeCurve has no case
    for Geom_OffsetCurve): it reports success and leaves out every face bounded by an offset
    curve — no geometry at all without a bore; with a bore only the bore's cylinder, which reads
    back as a "valid" shell of negative volume."""
    from cam_workbench.kernel import solids as occ_build
    from cam_workbench.kernel import ocp as occ
    from cam_workbench.kernel.step import read_step

    d = design_cam(default_spec().replace(**{"pitch.representation": "bspline", "cam.bore_diameter": bore}))
    writer = occ.STEPControl_Writer()
    assert writer.Transfer(occ_build.cam_solid(d), occ.STEPControl_AsIs) == occ.IFSelect_RetDone
    path = tmp_path / "raw.step"
    assert writer.Write(str(path)) == occ.IFSelect_RetDone
    text = path.read_text()
    assert "B_SPLINE" not in text and "OFFSET_CURVE" not in text and "PLANE(" not in text
    back = read_step(path)
    if bore == 0.0:
        # nothing to read: OCCT 7.9's reader returns a null shape, OCCT 8's an empty compound
        assert "MANIFOLD_SOLID_BREP" not in text
        assert back.IsNull() or not occ.TopExp_Explorer(back, occ.TopAbs_FACE).More()
    else:
        assert "CYLINDRICAL_SURFACE" in text
        # an open cylinder's divergence-theorem "volume": −⅓·r·(2πr h)
        assert occ_build.kernel_volume(back) == pytest.approx(-2 / 3 * math.pi * 5.0**2 * 10.0, rel=1e-9)


def test_tolerance_picks_the_fewest_spans():
    spec = default_spec().replace(**{"pitch.representation": "bspline", "pitch.segments": None,
                                     "pitch.tolerance": 1e-5})
    d = design_cam(spec)
    assert d.max_deviation[0] <= 1e-5
    fewer = design_cam(spec.replace(**{"pitch.tolerance": None, "pitch.segments": d.pitch.M - 1}))
    assert fewer.max_deviation[0] > 1e-5


def test_offset_points_direction():
    """d > 0 is the left of the travel direction: a counter-clockwise circle offset by −1 grows."""
    u = np.linspace(0, 2 * np.pi, 33)[:-1]
    circle = least_squares_periodic(np.linspace(0, 2 * np.pi, 25), 5, np.linspace(0, 2 * np.pi, 400,
                                                                                   endpoint=False),
                                    5 * np.exp(1j * np.linspace(0, 2 * np.pi, 400, endpoint=False)))
    assert np.allclose(np.abs(offset_points(circle, u, -1.0)), 6.0, atol=1e-6)

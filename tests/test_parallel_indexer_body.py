"""The parallel indexer's cams as a body (generators.bodies.indexing.parallel_body): the flanks'
fit held to exact offset points computed here from the documented conventions (roller centres
from the law, the normal from finite differences), the loops closed and counter-clockwise, and
the solid OCCT builds from the prisms — valid, one solid, its volume against the shoelace area of
exact points computed here, STEP written and read back."""
from __future__ import annotations

import math

import numpy as np
import pytest

from cam_workbench.generators.bodies.indexing.parallel import ParallelIndexer, design_parallel
from cam_workbench.generators.bodies.indexing.parallel_body import DEFAULT_TOLERANCE, indexer_body
from cam_workbench.generators.errors import SpecError

from .conftest import requires_ocp
from .test_parallel_indexer import a_k, law_psi

CASES = {"default": {}, "three_cams": {"cams": 3},
         "beta270_shifted": {"index_angle": math.radians(270), "centre_distance": 90.0, "law": "poly4567",
                             "index_start": 0.3}}


@pytest.fixture(scope="module", params=sorted(CASES))
def built(request):
    d = design_parallel(ParallelIndexer(**CASES[request.param]))
    return d, indexer_body(d, thickness=18.0, gap=4.0, bore_diameter=25.0)


def exact_offset(ix, k, tau, h=1e-5):
    """Q(τ) = L(τ) − r_r·n(τ): the roller-centre locus in the cam frame (the docstring's
    conventions), its outward normal J·L'/|L'| with L' by central differences."""
    def centre(t):
        psi, _ = law_psi(ix, t)
        al = a_k(ix, k) - psi
        p = np.stack([ix.centre_distance + ix.pitch_radius * np.cos(al), ix.pitch_radius * np.sin(al)], -1)
        c, s = np.cos(t), np.sin(t)
        return np.stack([c * p[..., 0] + s * p[..., 1], -s * p[..., 0] + c * p[..., 1]], -1)
    d = (centre(tau + h) - centre(tau - h)) / (2 * h)
    n = np.stack([-d[:, 1], d[:, 0]], -1) / np.hypot(d[:, 0], d[:, 1])[:, None]
    return centre(tau) - ix.roller_radius * n


def polyline_distance(pts, poly):
    a, d = poly[:-1], np.diff(poly, axis=0)
    q = pts[:, None, :] - a[None]
    t = np.clip((q * d).sum(-1) / (d * d).sum(1), 0, 1)
    r = q - t[..., None] * d
    return np.sqrt((r * r).sum(-1).min(1))


def test_flanks_are_within_the_tolerance_of_the_exact_offset(built):
    d, body = built
    ix = d.indexer
    rng = np.random.default_rng(3)
    for k, (f_in, f_out) in enumerate(body.fits):
        for fit in (f_in, f_out):
            lo, hi = fit.curve.domain
            tau = np.sort(rng.uniform(lo, hi, 400))
            exact = exact_offset(ix, k, tau)
            _, dense = fit.curve.sample(64)
            dist = polyline_distance(exact, dense)
            # the module's own measure and this one agree; both within the tolerance (+ the sampling's sag)
            assert dist.max() <= DEFAULT_TOLERANCE + 1e-6
            assert fit.error <= DEFAULT_TOLERANCE


def test_loops_are_closed_and_counter_clockwise(built):
    d, body = built
    ix = d.indexer
    for k, loop in enumerate(body.loops):
        assert loop.gap() < 1e-9
        assert loop.area > 0
        # the dwell piece: an arc about the input axis of the dwell radius less r_r, sweeping 2π − β
        arc = loop.pieces[1]
        assert abs(arc.centre) == 0 and abs(arc.a1 - arc.a0 - (2 * math.pi - ix.index_angle)) < 1e-12
        r_d = math.hypot(ix.centre_distance + ix.pitch_radius * math.cos(a_k(ix, k)),
                         ix.pitch_radius * math.sin(a_k(ix, k)))
        assert abs(arc.radius - (r_d - ix.roller_radius)) < 1e-9


def shoelace_area(ix, k, loop, n=20001):
    """The cam's area from exact points computed here: the flanks' exact offsets over their τ
    ranges (the ends from the loop's pieces), the dwell arc's closed-form segment."""
    out, arc, inc = loop.pieces
    pts = []
    for piece in (out, inc):
        lo, hi = piece.nurbs.domain
        tau = np.linspace(lo, hi, n)
        # the reversed curve's parameter runs the other way: map back to τ
        tau_fwd = lo + hi - tau
        pts.append(exact_offset(ix, k, tau_fwd))
    a = np.linspace(arc.a0, arc.a1, n)
    arc_pts = arc.radius * np.stack([np.cos(a), np.sin(a)], -1)
    poly = np.concatenate([pts[0], arc_pts, pts[1]])
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def test_the_exact_volume_against_an_independent_integral(built):
    d, body = built
    ix = d.indexer
    t, g, r_bore = 18.0, 4.0, 12.5
    area = sum(shoelace_area(ix, k, loop) for k, loop in enumerate(body.loops))
    n = len(body.loops)
    expect = area * t - n * math.pi * r_bore**2 * t + (n - 1) * (math.pi * (body.spacer_radius**2 - r_bore**2) * g)
    assert body.volume == pytest.approx(expect, rel=2e-7)


@requires_ocp
def test_the_kernel_builds_one_valid_solid_of_that_volume(built, tmp_path):
    from cam_workbench.kernel import solids
    from cam_workbench.kernel.step import read_step, write_step

    d, body = built
    shape = solids.prism_stack(body.geometry.prisms)
    assert solids.is_valid(shape) and solids.count_solids(shape) == 1
    assert solids.kernel_volume(shape) == pytest.approx(body.volume, rel=1e-7)
    path = tmp_path / "indexer.step"
    write_step(shape, path, "mm", "parallel indexer")
    back = read_step(path)
    assert solids.count_solids(back) == 1
    assert solids.kernel_volume(back) == pytest.approx(body.volume, rel=1e-7)


@pytest.mark.parametrize("kw, field", [({"thickness": 0.0}, "cam.thickness"), ({"gap": -1.0}, "indexer.gap"),
                                       ({"bore_diameter": 500.0}, "cam.bore_diameter"),
                                       ({"gap": 3.0, "spacer_radius": 1.0, "bore_diameter": 10.0},
                                        "indexer.spacer_diameter")])
def test_sizes_that_leave_no_material_are_refused(kw, field):
    d = design_parallel(ParallelIndexer())
    args = {"thickness": 10.0, **kw}
    with pytest.raises(SpecError) as e:
        indexer_body(d, **args)
    assert e.value.field == field

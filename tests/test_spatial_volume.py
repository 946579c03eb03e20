"""The spatial indexers' cam volume integrated on the exact envelope
(generators/bodies/indexing/spatial_volume.py: ``cam_volume``):

* closed forms: a bore removes exactly π·r_b²·W (the rib unchanged); the globoid's core against a
  numerical quadrature of its revolution; the rib lies strictly inside its band;
* invariance: the built-in examples differ from the default indexers only by ``index_start`` — a
  rotation of the cam about its axis —, so their volumes agree within the errors;
* the error estimate bounds the actual difference: against the same integral on a grid twice as
  fine in each direction (512 levels × 1440 columns), and against OCCT's adaptive volume
  (ε = 1e-6 per face) of ``spatial_solid`` for the default ``BarrelIndexer()``,
  ``GloboidalIndexer()`` and two other parameter sets;
* the estimate's size (≤ 2e-6 relative); its runtime is printed, not asserted (benchmarks/bench_indexing.py
  measures it: ~0.4 s).
"""
from __future__ import annotations

import functools
import math
import time

import numpy as np
import pytest

from cam_workbench.generators.bodies.indexing.spatial import (BarrelIndexer, GloboidalIndexer, design_barrel,
                                                              design_globoidal)
from cam_workbench.generators.bodies.indexing.spatial_volume import VolumeEstimate, cam_volume, core_volume

from .conftest import requires_ocp

SAMPLES, LENGTHS = 361, 9
#: the estimate's largest size (relative to the cam's volume)
ERROR_REL = 2e-6
#: OCCT's adaptive integration (ε per face) as a relative allowance on the whole solid
OCCT_REL = 1e-6

CASES = {
    "barrel": lambda: design_barrel(BarrelIndexer(), SAMPLES, LENGTHS, True),
    "globoidal": lambda: design_globoidal(GloboidalIndexer(), SAMPLES, LENGTHS, True),
    "barrel_cycloidal_270": lambda: design_barrel(
        BarrelIndexer(law="cycloidal", index_angle=math.radians(270.0), index_start=math.radians(25.0),
                      cam_width=90.0), SAMPLES, LENGTHS, True),
    "globoidal_poly345_150": lambda: design_globoidal(
        GloboidalIndexer(law="poly345", index_angle=math.radians(150.0), index_start=math.radians(30.0)),
        SAMPLES, LENGTHS, True),
}


@functools.lru_cache(maxsize=None)
def _design(name):
    return CASES[name]()


@functools.lru_cache(maxsize=None)
def _estimate(name):
    """(the estimate, its wall time [s]) — the second of two runs (the first loads the modules)."""
    design = _design(name)
    cam_volume(design)
    t = time.perf_counter()
    est = cam_volume(design)
    return est, time.perf_counter() - t


@functools.lru_cache(maxsize=None)
def _example(name):
    from cam_workbench.cam import Cam

    return Cam.example(name).design.geometry


@pytest.fixture(params=sorted(CASES))
def case(request):
    return request.param


def test_estimate_is_small_and_consistent(case):
    est, seconds = _estimate(case)
    print(f"\n{case}: {est.value:.4f} mm³ (core {est.core:.3f} + rib {est.rib:.4f}) ± {est.error:.3e} "
          f"({est.error / est.value:.2e}) in {seconds:.2f} s")
    assert isinstance(est, VolumeEstimate)
    assert est.value == est.core + est.rib
    assert 0.0 < est.error <= ERROR_REL * est.value
    assert "exact envelope" in est.what and "\n" not in est.what


def test_rib_lies_inside_its_band(case):
    est, _ = _estimate(case)
    ix = _design(case).indexer
    h = 0.5 * ix.cam_width
    if isinstance(ix, BarrelIndexer):
        band = math.pi * (ix.outer_radius**2 - ix.root_radius**2) * 2 * h
    else:                                  # the revolution of tip ≤ g ≤ root, |z| ≤ h about the cam axis
        c = ix.centre_distance
        z = np.linspace(-h, h, 20001)
        inner = c - np.sqrt(ix.root_radius**2 - z**2)
        outer = c - np.sqrt(ix.tip_radius**2 - z**2)
        band = float(np.trapezoid(math.pi * (outer**2 - inner**2), z))
    assert 0.2 * band < est.rib < 0.8 * band


def test_a_bore_removes_its_cylinder_exactly(case):
    design = _design(case)
    est, _ = _estimate(case)
    rb = 10.0
    bored = cam_volume(design, rb)
    removed = math.pi * rb**2 * design.indexer.cam_width
    assert bored.rib == est.rib and bored.error == est.error
    assert est.value - bored.value == pytest.approx(removed, rel=1e-12)
    assert bored.core == pytest.approx(core_volume(design.indexer) - removed, rel=1e-14)


def test_globoid_core_against_quadrature():
    ix = GloboidalIndexer()
    h, c, rr = 0.5 * ix.cam_width, ix.centre_distance, ix.root_radius
    x, w = np.polynomial.legendre.leggauss(64)
    z = h * x
    quad = float(h * np.sum(w * math.pi * (c - np.sqrt(rr**2 - z**2)) ** 2))
    assert core_volume(ix) == pytest.approx(quad, rel=1e-13)
    barrel = BarrelIndexer()
    assert core_volume(barrel, 5.0) == pytest.approx(math.pi * (25.0**2 - 5.0**2) * 80.0, rel=1e-14)


@pytest.mark.parametrize("kind", ["barrel", "globoidal"])
def test_error_bounds_the_difference_from_a_finer_grid(kind):
    """The default (256 × 1440) value against 512 × 1440-and-finer: within the reported error."""
    est, _ = _estimate(kind)
    finer = cam_volume(_design(kind), levels=256, columns=720)     # fine grid 512 × 1440
    diff = est.value - finer.value
    print(f"\n{kind}: default − finer = {diff:+.4f} mm³, error {est.error:.4f} (finer's {finer.error:.4f})")
    assert abs(diff) <= est.error
    assert finer.error < est.error


@pytest.mark.parametrize("example, kind", [("barrel_indexer", "barrel"), ("globoidal_indexer", "globoidal")])
def test_examples_are_the_defaults_turned(example, kind):
    """The examples are the default indexers with another ``index_start``: the same cam turned about
    its axis, so the same volume (within the two errors)."""
    geometry = _example(example)
    base = _design(kind).indexer
    assert geometry.indexer.index_start != base.index_start
    assert type(geometry.indexer)(**{**vars(geometry.indexer), "index_start": base.index_start}) == base
    est, ref = cam_volume(geometry), _estimate(kind)[0]
    assert abs(est.value - ref.value) <= est.error + ref.error


@requires_ocp
def test_error_bounds_the_difference_from_occt(case):
    from cam_workbench.generators.bodies.indexing.spatial_surfaces import flank_surfaces
    from cam_workbench.kernel import solids
    from cam_workbench.kernel.spatial_indexer import spatial_solid

    design = _design(case)
    est, _ = _estimate(case)
    volume = solids.kernel_volume(spatial_solid(design, flank_surfaces(design)), solids.SURFACE_VOLUME_EPS)
    rel = (volume - est.value) / est.value
    print(f"\n{case}: OCCT {volume:.4f} mm³, grid {est.value:.4f} ± {est.error:.4f}: {rel:+.2e}")
    # measured: +1.0e-7, −8e-9, +8.6e-8, +1.1e-7 — each below the grid's error alone
    assert abs(volume - est.value) <= est.error + OCCT_REL * est.value


@requires_ocp
def test_barrel_example_against_occt():
    """The barrel example (index_start = 60°): its OCCT solid was once +9.5 % off (the fuse of a rib
    sharing the core's root cylinder), the grid integral found it."""
    from cam_workbench.generators.bodies.indexing.spatial_surfaces import flank_surfaces
    from cam_workbench.kernel import solids
    from cam_workbench.kernel.spatial_indexer import spatial_solid

    geometry = _example("barrel_indexer")
    est = cam_volume(geometry)
    volume = solids.kernel_volume(spatial_solid(geometry, flank_surfaces(geometry)), solids.SURFACE_VOLUME_EPS)
    assert abs(volume - est.value) <= est.error + OCCT_REL * est.value


def test_bad_arguments_are_refused():
    design = _design("barrel")
    for bore in (-1.0, 25.0, math.nan):
        with pytest.raises(ValueError, match="bore_radius"):
            cam_volume(design, bore)
    with pytest.raises(ValueError, match="levels"):
        cam_volume(design, levels=2)
    with pytest.raises(TypeError, match="barrel or globoidal"):
        cam_volume(type("Other", (), {"indexer": object()})())

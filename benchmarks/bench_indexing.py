"""Indexing cams (issue 23): the parallel indexer's design, its cams as a body and their solid,
each beside a dense or per-point way of doing the same work.  CPU seconds, the smallest of a few
runs; prints Markdown tables.

* design: ``design_parallel`` (721 input angles) — the clearance's distances by a k-d tree and
  the two segments at the nearest vertex, beside every roller against every segment of the
  profile polyline (the per-point method);
* body: the flanks fitted as cubic B-splines within 0.1 µm of the exact offset, beside the
  design's own polylines of the profiles (1e-5 mm chord sag; their vertex count: what a drawing
  or a kernel would carry without the fit);
* solid: the kernel's prism stack sewn from the prisms' faces, beside extruding each prism and
  fusing them (booleans);
* the barrel and globoidal indexers' designs (721 input angles × 9 points along each roller × N
  rollers × 2 sides), and their contact lines in closed form over the whole grid at once, beside
  the same closed form called point by point;
* the built-in barrel and globoidal examples as bodies: the design with its flank surfaces, the
  poles those surfaces carry beside the dense grid of exact envelope points they replace, the
  OCCT solid, and the volume check — the grid integral of the exact envelope (two grids, for its
  error estimate) beside OCCT's adaptive integration of the built solid.

    .venv/bin/python benchmarks/bench_indexing.py
"""
from __future__ import annotations

import numpy as np

from _timing import cpu_best_of  # noqa: E402  (puts the project root on sys.path)

from cam_workbench.generators.bodies.indexing import parallel
from cam_workbench.generators.bodies.indexing.parallel import ParallelIndexer, design_parallel
from cam_workbench.generators.bodies.indexing.parallel_body import indexer_body
from cam_workbench.generators.bodies.indexing.spatial import (BarrelIndexer, GloboidalIndexer, contact_lines,
                                                             design_barrel, design_globoidal)


def all_segments(points: np.ndarray, poly: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The per-point method: every point against every segment of the polyline, in blocks."""
    a, d = poly[:-1], poly[1:] - poly[:-1]
    dd = np.einsum("ij,ij->i", d, d)
    out = np.empty(points.shape[0])
    seg = np.empty(points.shape[0], dtype=int)
    for s in range(0, points.shape[0], 96):
        q = points[s:s + 96, None, :] - a[None]
        t = np.clip(np.einsum("pij,ij->pi", q, d) / dd, 0.0, 1.0)
        r = q - t[..., None] * d
        dist = np.einsum("pij,pij->pi", r, r)
        seg[s:s + 96] = np.argmin(dist, axis=1)
        out[s:s + 96] = np.sqrt(dist[np.arange(dist.shape[0]), seg[s:s + 96]])
    return out, seg


def design_rows() -> list[str]:
    ix = ParallelIndexer()
    design_parallel(ix)                                  # imports and first-use costs out of the way
    fast = cpu_best_of(lambda: design_parallel(ix), 3)
    kd = parallel._distances
    parallel._distances = all_segments                   # the same design, the per-point distances
    try:
        slow = cpu_best_of(lambda: design_parallel(ix), 2)
    finally:
        parallel._distances = kd
    return ["| design (default, 721 input angles) | clearance distances | CPU [s] | ratio |", "|---|---|---:|---:|",
            f"| `design_parallel` | k-d tree, two segments | {fast:.3f} | 1× |",
            f"| | every segment (per point) | {slow:.3f} | {slow / fast:.1f}× |"]


def body_rows() -> list[str]:
    d = design_parallel(ParallelIndexer())
    t = cpu_best_of(lambda: indexer_body(d, thickness=18.0, gap=4.0, bore_diameter=25.0), 5)
    body = indexer_body(d, thickness=18.0, gap=4.0, bore_diameter=25.0)
    poles = sum(f.curve.n_poles for pair in body.fits for f in pair)
    vertices = sum(c.profile.shape[0] - 1 for c in d.cams)          # the design's own polylines, 1e-5 mm sag
    return ["| the cams' profiles (2 cams) | pieces | control points / vertices | fit error [mm] | CPU [s] |",
            "|---|---|---:|---:|---:|",
            f"| fitted flanks + exact dwell arcs | 4 B-splines, 2 arcs | {poles} | {body.fit_error:.2g} | {t:.3f} |",
            f"| polylines (the design's sampling) | 2 polylines | {vertices} | 1e-05 (chord sag) | — |",
            f"| ratio | | {vertices / poles:.0f}× fewer | | |"]


def solid_rows() -> list[str]:
    from cam_workbench.kernel import solids

    d = design_parallel(ParallelIndexer())
    body = indexer_body(d, thickness=18.0, gap=4.0, bore_diameter=25.0)
    prisms = body.geometry.prisms
    solids.prism_stack(prisms)                          # OCP's import out of the way

    def booleans():
        shape = None
        for p in prisms:
            s = solids.extrude(solids.region_face(p.outer, p.holes, p.z0), p.z0, p.z1)
            shape = s if shape is None else solids.boolean(solids.occ.BRepAlgoAPI_Fuse, shape, s)
        return shape

    sewn = cpu_best_of(lambda: solids.prism_stack(prisms), 3)
    fused = cpu_best_of(booleans, 3)
    return ["| solid (default, 2 cams, spacer, bore) | CPU [s] | ratio |", "|---|---:|---:|",
            f"| sewn from the prisms' faces (`prism_stack`) | {sewn:.3f} | 1× |",
            f"| each prism extruded and fused | {fused:.3f} | {fused / sewn:.1f}× |"]


def spatial_rows() -> list[str]:
    rows = ["| indexer (default) | design CPU [s] | contact lines, whole grid [s] | point by point [s] | ratio |",
            "|---|---:|---:|---:|---:|"]
    for name, ix, design in (("barrel (N = 6)", BarrelIndexer(), design_barrel),
                             ("globoidal (N = 12)", GloboidalIndexer(), design_globoidal)):
        design(ix)
        t_design = cpu_best_of(lambda: design(ix), 3)
        theta = np.linspace(0.0, 2 * np.pi, 721)
        t = np.linspace(ix.roller_start, ix.roller_end, 9)
        whole = cpu_best_of(lambda: contact_lines(ix, np.zeros(1), theta[:, None], t, 1), 5)
        sub = theta[::12]                                  # 61 angles by hand, scaled to the 721

        def by_point():
            for th in sub:
                for tk in t:
                    contact_lines(ix, np.zeros(1), np.array([th]), np.array([tk]), 1)
        per_point = cpu_best_of(by_point, 2) * theta.size / sub.size
        rows.append(f"| {name} | {t_design:.3f} | {whole:.4f} | {per_point:.3f} | {per_point / whole:.0f}× |")
    return rows


def spatial_body_rows() -> list[str]:
    from cam_workbench.generators.bodies.indexing import spatial_volume
    from cam_workbench.generators.cam_design import design_cam
    from cam_workbench.generators.spec.examples import example_spec
    from cam_workbench.kernel import solids
    from cam_workbench.kernel.spatial_indexer import SpatialSolids

    rows = ["| example | design + flank surfaces [s] | surface poles / dense envelope points | solid [s] | "
            "volume grid [s] | OCCT adaptive volume [s] | ratio |",
            "|---|---:|---:|---:|---:|---:|---:|"]
    for name in ("barrel_indexer", "globoidal_indexer"):
        spec = example_spec(name)
        design = design_cam(spec)
        t_design = cpu_best_of(lambda: design_cam(spec), 2)
        poles = sum(f.surface.shape[0] * f.surface.shape[1] for f in design.surfaces.flanks)
        g = design.geometry
        dense = 2 * int(g.theta.size) * int(g.indexer.stations) * int(g.t.size)
        shape = SpatialSolids.solid(design, True)
        t_solid = cpu_best_of(lambda: SpatialSolids.solid(design, True), 1)
        grid = cpu_best_of(lambda: spatial_volume.cam_volume(g), 2)
        occt = cpu_best_of(lambda: solids.kernel_volume(shape, solids.SURFACE_VOLUME_EPS), 2)
        rows.append(f"| {name} | {t_design:.2f} | {poles} / {dense} | {t_solid:.2f} | {grid:.2f} | {occt:.2f} | "
                    f"{occt / grid:.1f}× |")
    return rows


def main() -> None:
    print("### Parallel indexer: design\n")
    print("\n".join(design_rows()))
    print("\n### Parallel indexer: the cams' profiles\n")
    print("\n".join(body_rows()))
    print("\n### Parallel indexer: solid\n")
    print("\n".join(solid_rows()))
    print("\n### Barrel and globoidal indexers: design and contact lines (one roller side, 721 × 9 points)\n")
    print("\n".join(spatial_rows()))
    print("\n### Barrel and globoidal indexers: the examples as bodies\n")
    print("\n".join(spatial_body_rows()))


if __name__ == "__main__":
    main()

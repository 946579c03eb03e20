"""Draw docs/images/indexer_parallel.png, indexer_barrel.png and indexer_globoidal.png (the three
indexers' default designs in the fixed frame at an input angle in the middle of the index) with
:func:`cam_workbench.exporters.plots_indexer.indexer_picture` and
:func:`cam_workbench.exporters.plots_spatial_indexer.spatial_picture`, rasterised as the report's PNG
figures are (:mod:`cam_workbench.exporters.chart_png`):

    PYTHONPATH=. python docs/images/make_indexer_pictures.py
"""
from __future__ import annotations

from pathlib import Path

from cam_workbench.exporters.chart_png import png_bytes
from cam_workbench.exporters.plots_indexer import indexer_picture
from cam_workbench.exporters.plots_spatial_indexer import spatial_picture
from cam_workbench.generators.bodies.indexing.parallel import ParallelIndexer, design_parallel
from cam_workbench.generators.bodies.indexing.spatial import (BarrelIndexer, GloboidalIndexer, design_barrel,
                                                              design_globoidal)


def mid_index(ix) -> float:
    """The input angle [rad] half way through the index."""
    return float(ix.index_start) + 0.5 * float(ix.index_angle)


def main() -> list[Path]:
    """Write the pictures next to this script; returns their paths."""
    here = Path(__file__).parent
    parallel, barrel, globoidal = (design_parallel(ParallelIndexer()), design_barrel(BarrelIndexer()),
                                   design_globoidal(GloboidalIndexer()))
    charts = {"indexer_parallel": indexer_picture(parallel, mid_index(parallel.indexer)),
              "indexer_barrel": spatial_picture(barrel, mid_index(barrel.indexer)),
              "indexer_globoidal": spatial_picture(globoidal, mid_index(globoidal.indexer))}
    paths = []
    for name, chart in charts.items():
        path = here / f"{name}.png"
        path.write_bytes(png_bytes(chart, name))
        paths.append(path)
    return paths


if __name__ == "__main__":
    for p in main():
        print(p, p.stat().st_size)

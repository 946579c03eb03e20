"""Draw docs/images/cylindrical_cam.png (the README's and docs/bodies.md's picture of the built-in
cylindrical example) with :func:`cam_workbench.exporters.plots_cylindrical.cylindrical_figure`,
rasterised as the report's PNG figures are (:mod:`cam_workbench.exporters.chart_png`):

    PYTHONPATH=. python docs/images/make_cylindrical_cam.py
"""
from __future__ import annotations

from pathlib import Path

from cam_workbench.exporters.chart_png import png_bytes
from cam_workbench.exporters.plots_cylindrical import cylindrical_figure
from cam_workbench.generators import design_cam
from cam_workbench.generators.spec.examples import example_spec


def main() -> Path:
    """Write the picture next to this script; returns its path."""
    path = Path(__file__).with_name("cylindrical_cam.png")
    path.write_bytes(png_bytes(cylindrical_figure(design_cam(example_spec("cylindrical"))), "cylinder"))
    return path


if __name__ == "__main__":
    print(main())

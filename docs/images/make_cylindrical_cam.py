"""Draw docs/images/cylindrical_cam.png (the README's and docs/bodies.md's picture of the built-in
cylindrical example) with :func:`cam_workbench.exporters.plots.cylindrical_figure`:

    PYTHONPATH=. python docs/images/make_cylindrical_cam.py
"""
from __future__ import annotations

from pathlib import Path

from cam_workbench.exporters import plots
from cam_workbench.generators import design_cam
from cam_workbench.generators.spec.examples import example_spec


def main() -> Path:
    """Write the picture next to this script; returns its path."""
    fig = plots.cylindrical_figure(design_cam(example_spec("cylindrical")))
    try:
        return plots.save_figure(fig, Path(__file__).with_name("cylindrical_cam.png"), dpi=100)
    finally:
        plots.close(fig)


if __name__ == "__main__":
    print(main())

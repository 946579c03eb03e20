"""Make docs/images/tolerance_chart.png: the tolerance chart of the built-in default cam (radial
8 mm roller, R_b = 40 mm, 60 rpm) for an acceleration error ≤ 5 % of the designed peak, n = 1 … 200,
as ``cam-workbench tolerance --example default -o DIR`` draws it (docs/tolerances.md).

    .venv/bin/python docs/images/make_tolerance_chart.py
"""
from __future__ import annotations

from pathlib import Path

from cam_workbench.exporters.chart_png import png_bytes
from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.tolerance import tolerance_study

HERE = Path(__file__).resolve().parent


def main() -> None:
    """Write tolerance_chart.png beside this script."""
    study = tolerance_study(example_spec("default"), acceleration_limit=0.05, max_waves=200)
    (HERE / "tolerance_chart.png").write_bytes(png_bytes(study.svg()))


if __name__ == "__main__":
    main()

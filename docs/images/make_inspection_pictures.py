"""Make docs/examples/inspection_points.csv — a synthetic made part of the built-in default cam:
3000 points of its exact profile moved along the normal by a 3 µm wave, 5 waves per turn, and a
1.5 µm wave, 23 per turn, with 0.5 µm of noise and 2 % of the points 0.3 mm off (dust), put in a
measuring frame turned by 30° and shifted by (4, −2) mm — and the pictures of docs/inspection.md,
docs/images/inspection_map.png and docs/images/inspection_motion.png, as
``cam-workbench inspect docs/examples/inspection_points.csv --tolerance 0.02`` draws them.

    .venv/bin/python docs/images/make_inspection_pictures.py
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from cam_workbench.exporters.chart_png import png_bytes
from cam_workbench.exporters.chart_svg import svg
from cam_workbench.exporters.inspection_report import deviation_map_figure, motion_figure
from cam_workbench.generators import default_spec, design_cam
from cam_workbench.inspection import inspect_part

HERE = Path(__file__).resolve().parent
POINTS = HERE.parent / "examples" / "inspection_points.csv"


def made_part(seed: int = 25) -> np.ndarray:
    """The points of the synthetic part (see the module docstring), x and y in mm."""
    design = design_cam(default_spec())
    rng = np.random.default_rng(seed)
    prof = design.profile
    lo, hi = prof.domain
    u = np.sort(rng.uniform(lo, hi, 3000))
    p, d = prof.evaluate_with_derivative(u)
    z, dz = p[:, 0] + 1j * p[:, 1], d[:, 0] + 1j * d[:, 1]
    outward = (-1j if prof.area() > 0 else 1j) * dz / np.abs(dz)
    seg = np.minimum(np.floor(u).astype(int), design.pitch.M - 1)
    theta = np.deg2rad(design.pitch.cam_angle_at(seg, u - seg))
    delta = 3e-3 * np.cos(5 * theta) + 1.5e-3 * np.cos(23 * theta + 1.0) + rng.normal(0, 0.5e-3, u.size)
    delta += 0.3 * (rng.random(u.size) < 0.02)
    m = np.exp(-1j * np.deg2rad(30.0)) * (z + delta * outward - (4.0 - 2.0j))
    return np.column_stack([m.real, m.imag])


def main() -> None:
    """Write the points file and the two pictures."""
    pts = made_part()
    POINTS.write_text("x,y\n" + "".join(f"{x:.6f},{y:.6f}\n" for x, y in pts), encoding="utf-8")
    result = inspect_part(default_spec(), POINTS, tolerance=0.02)
    report = json.loads(json.dumps(result.summary()))
    (HERE / "inspection_map.png").write_bytes(png_bytes(svg(deviation_map_figure(result, report), "map")))
    (HERE / "inspection_motion.png").write_bytes(png_bytes(svg(motion_figure(result, report), "motion")))


if __name__ == "__main__":
    main()

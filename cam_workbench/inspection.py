"""Inspecting a made cam from Python (docs/inspection.md):

    from cam_workbench.inspection import inspect_part, read_points, write_inspection
    result = inspect_part("cam.toml", "measured.csv", tolerance=0.02, datum="bore")
    result.summary()["tolerance"]["verdict"]       # "pass", "pass_excluding_outliers" or "fail"
    result.summary()["harmonics"]["largest"]       # the deviation's largest harmonics and their δa
    write_inspection(result, "inspection")         # inspection.json, .html, CSVs, SVG (PNG) figures

The mathematics is :mod:`cam_workbench.generators.inspection`; the files
:mod:`cam_workbench.exporters.inspection_report`.  The points file is CSV: ``x,y`` or ``x,y,z`` on
every line (the spec's length unit), an optional header line naming those columns, blank lines
and lines starting with ``#`` skipped.
"""
from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from cam_workbench.exporters import inspection_report as files
from cam_workbench.exporters.atomic import OutputSet
from cam_workbench.exporters.chart_png import png_bytes, require_png
from cam_workbench.exporters.output_rule import Claim, spec_claim
from cam_workbench.generators.cam_design import design_cam
from cam_workbench.generators.errors import MissingDependency, SpecError
from cam_workbench.generators.inspection import DATUMS, InspectionResult, inspect_design
from cam_workbench.generators.inspection.measured_motion import DEFAULT_WAVELENGTH_DEG
from cam_workbench.generators.spec import CamSpec, load_spec

#: the header names a points file may start with
HEADERS = (("x", "y"), ("x", "y", "z"))


def read_points(path: str | os.PathLike[str]) -> np.ndarray:
    """The points of a CSV file as an (N, 2) or (N, 3) array (see the module docstring).

    Raises:
        SpecError: naming the file and line: unreadable, a header other than x,y[,z], a line with
            another number of columns than the first, a value that is not a finite number, fewer
            than 3 points.
    """
    name = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise SpecError(name, f"cannot be read as a text file ({exc})") from None
    rows: list[list[float]] = []
    width = 0
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        cells = [c.strip() for c in stripped.split(",")]
        if not rows and not width and not _numbers(cells):
            names = tuple(c.lower() for c in cells)
            if names not in HEADERS:
                raise SpecError(f"{name}: line {number}", f"a header must name the columns x,y or x,y,z, got {stripped!r}")
            width = len(names)
            continue
        if len(cells) not in (2, 3) or (width and len(cells) != width):
            want = width or (len(rows[0]) if rows else 0)
            rule = f"{want} columns as the first" if want else "2 or 3 columns: x,y or x,y,z"
            raise SpecError(f"{name}: line {number}", f"has {len(cells)} comma-separated columns, must have {rule}")
        values = _numbers(cells)
        if values is None:
            bad = next(c for c in cells if _number(c) is None)
            raise SpecError(f"{name}: line {number}", f"{bad!r} is not a finite number")
        width = width or len(values)
        rows.append(values)
    if len(rows) < 3:
        raise SpecError(name, f"holds {len(rows)} points: at least 3 are needed")
    return np.array(rows, dtype=float)


def _number(cell: str) -> float | None:
    try:
        v = float(cell)
    except ValueError:
        return None
    return v if math.isfinite(v) else None


def _numbers(cells: list[str]) -> list[float] | None:
    values = [_number(c) for c in cells]
    return None if any(v is None for v in values) else values  # type: ignore[return-value]


def inspect_part(spec: CamSpec | str | os.PathLike[str], points: np.ndarray | str | os.PathLike[str], *,
                 tolerance: float | None = None, datum: str = "none",
                 wavelength_deg: float = DEFAULT_WAVELENGTH_DEG,
                 acceleration_limit: float | None = None) -> InspectionResult:
    """Inspect a made cam: its spec (a :class:`CamSpec` or a TOML file) and the measured profile
    points (an (N, 2|3) array or a CSV file, spec units).

    Args:
        tolerance: the profile tolerance t (zone ±t/2 about the exact profile), or None.
        datum: "none" (best fit: rotation about the cam axis and shift), "bore" (the points' origin
            on the bore's axis: rotation only) or "bore_and_angle" (the points in the part's frame).
        wavelength_deg: the shortest wave of the deviation the follower's motion follows [deg].
        acceleration_limit: the allowed acceleration error, a fraction of the designed peak (0.05
            for 5 %): the harmonics section gains the tolerance study's chart at ``cam.speed_rpm``.

    Raises:
        SpecError: a bad spec, points file, datum, tolerance, wavelength or acceleration limit
            (naming it); a cam body without a plane profile.
        GeometryError: the spec's cam cannot be made.
    """
    if datum not in DATUMS:
        raise SpecError("datum", f"must be one of {', '.join(DATUMS)}, got {datum!r}")
    if not isinstance(spec, CamSpec):
        spec = load_spec(spec)
    if not isinstance(points, np.ndarray):
        points = read_points(points)
    return inspect_design(design_cam(spec), points, tolerance=tolerance, datum=datum, wavelength_deg=wavelength_deg,
                          acceleration_limit=acceleration_limit)


def inspection_files(result: InspectionResult) -> tuple[dict[str, Any], dict[str, str | bytes]]:
    """(inspection.json's dict as written, every file by name): the JSON, the HTML, the two CSVs and the
    figures as SVG — and as PNG when CairoSVG is installed."""
    summary = result.summary()
    charts = files.figures(result, summary)
    svgs = files.figure_svgs(charts)
    out: dict[str, str | bytes] = {f"{files.FIGURES[k]}.svg": v for k, v in svgs.items()}
    try:
        require_png()
        out |= {f"{files.FIGURES[k]}.png": png_bytes(svgs[k]) for k in svgs}
    except MissingDependency:
        pass
    out[files.POINTS_CSV] = files.deviations_csv(result)
    out[files.MOTION_CSV] = files.motion_csv(result)
    out[files.HTML_NAME] = files.inspection_html(summary, svgs)
    names = sorted([*out, files.JSON_NAME])
    text = files.inspection_json_text(summary, {n: n for n in names})
    out[files.JSON_NAME] = text
    return json.loads(text), out


def write_inspection(result: InspectionResult, folder: str | os.PathLike[str], claim: Claim | None = None
                     ) -> dict[str, Any]:
    """Write the inspection's files into ``folder`` as one set (:class:`OutputSet`: atomically,
    under the output rule of :mod:`cam_workbench.exporters.output_rule`); returns inspection.json's dict."""
    claim = claim or spec_claim(result.design.spec, "inspect_part", None, option="folder")
    report, out = inspection_files(result)
    with OutputSet(folder, claim) as o:
        for name, data in out.items():
            if isinstance(data, bytes):
                o.add_bytes(name, data)
            else:
                o.add_text(name, data)
    return report


__all__ = ["HEADERS", "inspect_part", "inspection_files", "read_points", "write_inspection"]

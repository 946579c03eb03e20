"""Inspection of a made cam against a ``Cam`` feature: measured profile points (a CSV file) held
against the feature's spec by :func:`cam_workbench.inspection.inspect_part` — the function
``cam-workbench inspect`` calls, so the numbers are inspection.json's (docs/inspection.md) — and the
points put into the document, coloured by their deviation, in the cam's frame.

:func:`inspect_feature` is headless (``freecadcmd``).  It adds one group, claimed by the cam in
the tree (``InspectedCam`` names it), holding

- one object per deviation class (the library's :data:`~cam_workbench.exporters.inspection_report.PALETTE`,
  classes of equal width out to the largest inlier |d|, or to t/2 when a tolerance is given and
  larger): the class's registered points as vertices, each with its *whisker* — an edge from its
  foot point on the exact profile along the outward normal, ``WhiskerScale`` × its deviation
  long (+ material left on: outward) — and the class's range as ``DeviationLow``/``DeviationHigh``;
- the outliers the robust fit flagged, as vertices (no whisker: they are far off).

Points lie in the part's frame (the registered pose applied: deviations.csv's ``x_part``,
``y_part``) at their measured z, or on the cam's top face (z = thickness) for x,y points, and
take the cam's ``Placement`` when made.  Bad input (the CSV, the tolerance, the datum) raises the
library's :class:`SpecError` before anything is added.
"""
from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import FreeCAD
import numpy as np
import Part

from cam_workbench.exporters.inspection_report import PALETTE, rows
from cam_workbench.exporters.output_rule import spec_claim
from cam_workbench.exporters.report_cells import format_number as fmt
from cam_workbench.exporters.report_cells import lookup
from cam_workbench.exporters.report_json import report_json_text
from cam_workbench.generators.inspection import InspectionResult
from cam_workbench.inspection import inspect_part, write_inspection

from . import properties as props

#: the group's property naming the inspected cam (its object Name)
CAM_PROPERTY = "InspectedCam"
#: the outliers' colour (the library's "fail" red)
OUTLIER_COLOR = "#d62728"
#: the longest whisker drawn, as a share of the cam's base radius (WhiskerScale is the largest
#: 1-2-5 number keeping the largest inlier's whisker within it)
WHISKER_SHARE = 0.1


@dataclass(frozen=True)
class Inspection:
    """One inspection of a feature.

    Attributes:
        report: inspection.json's numbers (``files`` too when written to a folder).
        result: the library's result.
        group: the document group holding the points.
    """

    report: dict[str, Any]
    result: InspectionResult
    group: Any


def whisker_scale(max_abs: float, base_radius: float) -> float:
    """The largest 1, 2, 5 × 10ᵏ not above ``WHISKER_SHARE``·R_b / max|d| (1 when nothing deviates)."""
    if max_abs <= 0.0:
        return 1.0
    raw = WHISKER_SHARE * base_radius / max_abs
    decade = 10.0 ** math.floor(math.log10(raw))
    return max(m * decade for m in (1.0, 2.0, 5.0) if m * decade <= raw * (1 + 1e-12))


def class_edges(result: InspectionResult) -> np.ndarray:
    """The edges of the colour classes (spec units): equal width over ±(largest inlier |d|, or t/2
    when a tolerance is given and larger)."""
    d = result.deviations
    inl = d.value[~d.outliers]
    limit = max(float(np.max(np.abs(inl))) if inl.size else 0.0,
                0.5 * result.tolerance if result.tolerance is not None else 0.0) or 1.0
    return np.linspace(-limit, limit, len(PALETTE) + 1)


def classes_of(result: InspectionResult, edges: np.ndarray) -> np.ndarray:
    """Each point's colour class (index into PALETTE; -1 for an outlier)."""
    d = result.deviations
    cls = np.clip(np.searchsorted(edges, d.value, side="right") - 1, 0, len(PALETTE) - 1)
    return np.where(d.outliers, -1, cls)


def report_cells(report: dict[str, Any]) -> list[tuple[str, str]]:
    """(quantity, value with unit and cam angle) of every row the report view and the dialog show:
    inspection.json's values as the CLI prints them (``rows`` of
    :mod:`cam_workbench.exporters.inspection_report`)."""
    out = []
    for label, key, unit, at in rows(report):
        where = "" if at is None else f" at {fmt(lookup(report, at))}°"
        out.append((label, f"{fmt(lookup(report, key))}{' ' + unit if unit else ''}{where}"))
    return out


def report_lines(report: dict[str, Any]) -> list[str]:
    """The report view's lines: "quantity: value" (:func:`report_cells`)."""
    return [f"{label}: {value}" for label, value in report_cells(report)]


def headline(report: dict[str, Any]) -> str:
    """One line: the verdict and the acceleration error."""
    tol = report.get("tolerance")
    a = report["motion"]["acceleration_error"]
    verdict = ("no profile tolerance: no verdict" if not tol else
               f"profile verdict {tol['verdict']} (zone ±{fmt(tol['zone'][1])} {report['units']})")
    return (f"{verdict}; {report['registration']['outliers']} outliers; largest acceleration error "
            f"{fmt(a['max_abs'])} {report['motion']['units']['acceleration']} "
            f"({fmt(100 * a['fraction_of_designed_peak'])} % of the designed peak) at {fmt(a['at_deg'])}°")


def inspect_feature(obj: Any, csv_path: str | os.PathLike[str], tolerance: float | None = None,
                    datum: str = "none", folder: str | os.PathLike[str] | None = None) -> Inspection:
    """Inspect the made part of the cam feature ``obj`` from the points of ``csv_path`` and add the
    points to the document (module docstring); the caller recomputes.

    Args:
        tolerance: the profile tolerance t (zone ±t/2, spec units), or None (no verdict).
        datum: "none", "bore" or "bore_and_angle" (docs/inspection.md).
        folder: also write inspection.json, .html, the CSVs and the figures there (the CLI's
            exporter, under the output rule), or None.

    Raises:
        SpecError: a bad points file (naming the file and line), tolerance, datum, a property, a
            body without a plane profile, or a refused folder — nothing added to the document.
        GeometryError: the cam cannot be made.
    """
    spec = props.spec_of(obj)
    result = inspect_part(spec, csv_path, tolerance=tolerance, datum=datum)
    if folder is None:
        report = json.loads(report_json_text(result.summary()))
    else:
        claim = spec_claim(spec, "inspect", f"freecad:{obj.Document.Name}#{obj.Name}", option="folder")
        report = write_inspection(result, folder, claim)
    group = add_points(obj, result, report, Path(csv_path).name)
    return Inspection(report, result, group)


def add_points(obj: Any, result: InspectionResult, report: dict[str, Any], name: str) -> Any:
    """Add the inspection's group and its objects to ``obj``'s document (module docstring)."""
    spec = result.design.spec
    scale = props.units_scale(obj)
    reg = result.registration
    pr = reg.projection
    n = len(reg.points)
    z = result.z if result.z is not None else np.full(n, spec.cam.thickness)
    pts = np.column_stack([reg.points.real, reg.points.imag, z]) * scale
    k = whisker_scale(float(np.max(np.abs(result.deviations.value[~result.deviations.outliers]), initial=0.0)),
                      spec.cam.base_radius)
    tip = pr.foot + k * pr.distance * pr.normal
    feet = np.column_stack([pr.foot.real, pr.foot.imag, z]) * scale
    tips = np.column_stack([tip.real, tip.imag, z]) * scale
    edges = class_edges(result)
    cls = classes_of(result, edges)
    doc = obj.Document
    group = doc.addObject("App::DocumentObjectGroup", f"{obj.Name}Inspection")
    group.Label = f"{obj.Label} inspection {name}"
    group.addProperty("App::PropertyString", CAM_PROPERTY, "Inspection", "Name of the inspected cam")
    group.addProperty("App::PropertyString", "Verdict", "Inspection", "Profile verdict (inspection.json)")
    group.addProperty("App::PropertyFloat", "WhiskerScale", "Inspection",
                      "Whisker length / deviation: each point's deviation drawn this many times longer")
    setattr(group, CAM_PROPERTY, obj.Name)
    group.Verdict = report["tolerance"]["verdict"] if report.get("tolerance") else "no tolerance given"
    group.WhiskerScale = k
    unit = report["units"]

    def vec(p: np.ndarray) -> Any:
        return FreeCAD.Vector(float(p[0]), float(p[1]), float(p[2]))

    parts = []
    for c, color in enumerate(PALETTE):
        on = np.flatnonzero(cls == c)
        if not on.size:
            continue
        shapes = [Part.Vertex(vec(p)) for p in pts[on]]
        shapes += [Part.LineSegment(vec(a), vec(b)).toShape() for a, b in zip(feet[on], tips[on])
                   if np.any(a != b)]
        part = doc.addObject("Part::Feature", f"{obj.Name}Deviation")
        part.Label = f"{fmt(edges[c])} … {fmt(edges[c + 1])} {unit}: {on.size} points"
        part.addProperty("App::PropertyFloat", "DeviationLow", "Inspection", f"Class's lowest deviation [{unit}]")
        part.addProperty("App::PropertyFloat", "DeviationHigh", "Inspection", f"Class's highest deviation [{unit}]")
        part.DeviationLow, part.DeviationHigh = float(edges[c]), float(edges[c + 1])
        part.Shape = Part.Compound(shapes)
        parts.append((part, color))
    out = np.flatnonzero(cls == -1)
    if out.size:
        part = doc.addObject("Part::Feature", f"{obj.Name}Outliers")
        part.Label = f"outliers: {out.size} points"
        part.Shape = Part.Compound([Part.Vertex(vec(p)) for p in pts[out]])
        parts.append((part, OUTLIER_COLOR))
    for part, color in parts:
        part.Placement = obj.Placement
        group.addObject(part)
        if FreeCAD.GuiUp and part.ViewObject is not None:
            rgb = tuple(int(color[i:i + 2], 16) / 255.0 for i in (1, 3, 5))
            part.ViewObject.PointColor = rgb
            part.ViewObject.LineColor = rgb
            part.ViewObject.PointSize = 4.0
    return group


def inspections_of(cam: Any) -> list[Any]:
    """The inspection groups of a cam (those whose ``InspectedCam`` names it)."""
    return [o for o in cam.Document.Objects
            if CAM_PROPERTY in o.PropertiesList and getattr(o, CAM_PROPERTY) == cam.Name]

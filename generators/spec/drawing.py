"""The spec's `[drawing]` table: :class:`DrawingSection` (the DXF drawing), ``DXF_VERSIONS`` and its
rules (chord tolerance, R12 without splines).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import SpecError, fmt_apart
from .params import param

if TYPE_CHECKING:  # types only: the spec's root imports this module
    from .model import CamSpec


#: DXF versions the drawing can be written as (ezdxf's names); R12 has no SPLINE entity.
DXF_VERSIONS = ("R12", "R2000", "R2004", "R2007", "R2010", "R2013", "R2018")


@dataclass(frozen=True, kw_only=True)
class DrawingSection:
    """`[drawing]`: the DXF manufacturing drawing (cam.dxf) and the report's title."""

    curves: str = param(
        "How the profile, pitch curve and the body's other curves are written: \"cubic\" a polynomial "
        "(non-rational) cubic SPLINE within chord_tolerance, which every DXF reader draws; \"spline\" the profile NURBS "
        "itself (for a PH pitch curve the exact rational offset, degree 9, which LibreCAD and many CAM and "
        "laser programs drop without a word); \"arcs\" tangent arcs (biarcs, ARC/LINE entities) or "
        "\"polyline\" one closed polyline within chord_tolerance, for machines that read no splines",
        kind="str", choices=("cubic", "spline", "arcs", "polyline"), default="cubic", group="Drawing")
    chord_tolerance: float = param(
        "Largest distance of the drawn curves from the NURBS they stand for (curves = cubic, arcs or "
        "polyline; measured and stated in the title block)",
        unit="length", gt=0, default=0.001, group="Drawing")
    dxf_version: str = param(
        "DXF version of cam.dxf; R12 (for old CAM software) needs curves = arcs or polyline",
        kind="str", choices=DXF_VERSIONS, default="R2010", group="Drawing")
    title: str | None = param("Drawing and report title; default: the body's name (\"Plate cam\", \"Groove "
                              "cam\", \"Conjugate cam pair\", \"Cylindrical cam\"), which the drawing's title "
                              "block adds to a title that does not say it", kind="str", optional=True,
                              group="Drawing")
    part_number: str = param("Part or drawing number in the title block", kind="str", default="",
                             group="Drawing")
    author: str = param("Drawn by (title block)", kind="str", default="", group="Drawing")
    material: str = param("Material and treatment note in the title block, e.g. \"AISI 1045, 50 HRC\"",
                          kind="str", default="", group="Drawing")
    title_block: bool = param("Draw the title block with the key parameters and the motion table",
                              kind="bool", default=True, group="Drawing")
    dimensions: bool = param("Draw dimensions: bore diameter, base-circle radius, largest radius, "
                             "thickness note", kind="bool", default=True, group="Drawing")
    text_height: float | None = param(
        "Height of the drawing's text and arrows; default: the largest profile diameter / 36",
        unit="length", gt=0, optional=True, group="Drawing")
    spline_closed_flag: bool = param(
        "Set the DXF 'closed' bit on the profile SPLINE (AutoCAD's habit for closed clamped "
        "splines); off by default because CadQuery's DXF importer reads that bit as 'periodic' "
        "and drops the spline. The curve is closed either way (first pole = last pole)",
        kind="bool", default=False, group="Drawing")


def validate_drawing(spec: CamSpec) -> None:
    dr = spec.drawing
    if dr.chord_tolerance is not None and dr.chord_tolerance < 1e-7 * spec.cam.base_radius:
        low = 1e-7 * spec.cam.base_radius
        raise SpecError("drawing.chord_tolerance", f"must be ≥ 1e-7 × cam.base_radius ({fmt_apart(low, dr.chord_tolerance)}), "
                                                   f"got {fmt_apart(dr.chord_tolerance, low)}")
    if dr.dxf_version == "R12" and dr.curves in ("cubic", "spline"):
        raise SpecError("drawing.dxf_version",
                        "R12 has no SPLINE entity: use drawing.curves = \"arcs\" or \"polyline\" with R12")

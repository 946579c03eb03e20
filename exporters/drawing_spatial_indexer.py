"""The barrel and globoidal indexers' drawing in the output pipeline (``cam.dxf``), registered in
:data:`cam_workbench.exporters.dxf.DRAWINGS` for
:class:`~cam_workbench.generators.bodies.indexing.spatial_kind.SpatialIndexerDesign`.

The drawing itself is :func:`cam_workbench.exporters.dxf_spatial_indexer.spatial_drawing` of the
design's geometry and flank surfaces (at input angle 0: the barrel's side and end views and its
developed views at the rib's top and root radii with the flank traces as cubic SPLINEs; the
globoid's contour section and end view; the rollers, the axes, the centre distance), with the bore
(``cam.bore_diameter``, which the library does not draw) added: a CIRCLE in the end view (layer
``BORE``), its generators in the barrel's side view (hidden, ``HIDDEN``) or the globoid's contour
section (``BORE``), and its diameter dimensioned in the end view.  The library's title block is
replaced by one quoting the ``summary`` the pipeline passes — the dict report.json holds — so that
the drawing and the report say the same numbers: the indexer's parameters
(``indexer.geometry``), the bore (``body.bore_diameter``), the pressure angles
(``pressure_angle``), the regularity margin and rib thickness, the flank surfaces' measured fit
error (``body.flank_fit_error``: fitted, NOT exact), the turret angle recovered from the flanks
(``indexer.motion_from_geometry``), the checks' verdict and the spec digest; and the drawing's own
measured numbers (report.json ``drawing``): the barrel's trace SPLINEs' error from the exact
envelope (``drawing.drawn_trace_error``: fitted, NOT exact) and where the turret is drawn
(``drawing.drawn_at``).  Measured errors are printed rounded UP to 4 significant digits (a quoted
bound stays a bound).

``[drawing]``: ``title``, ``part_number``, ``author``, ``material``, ``title_block`` and
``dimensions`` are honoured; ``chord_tolerance`` is honoured when the drawn traces' measured error
is within it (the globoid draws no fitted curve: every curve it draws is an exact circle, arc or
line); ``spline_closed_flag`` does not apply (no closed SPLINE is drawn).  Refused, naming the
field: a ``dxf_version`` other than R2010 and a ``text_height`` (the library sizes its text from
the indexer), ``curves`` other than "cubic" where flank traces are drawn (the barrel's: they are
polynomial cubic SPLINEs interpolating exact envelope points; there is no NURBS of the body's to
write, nor arcs or polylines), and a ``chord_tolerance`` below the traces' measured error.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from cam_workbench.generators.bodies.indexing.spatial import BarrelIndexer, GloboidalIndexer, turret_angle
from cam_workbench.generators.bodies.indexing.spatial_kind import SpatialIndexerDesign
from cam_workbench.generators.errors import SpecError

from .drawing_indexer import drop_library_annotations, finish_drawing, pressure_limit, title_head, title_tail
from .dxf import DIMSTYLE, DRAWINGS, LAYERS, title_line
from .dxf_indexer import dim_values, round_up
from .dxf_spatial_indexer import CHECKS, TRACE_TOLERANCE, SpatialDxfInfo, spatial_drawing

#: the DXF version :func:`~cam_workbench.exporters.dxf_spatial_indexer.spatial_drawing` writes
DXF_VERSION = "R2010"
#: significant digits of the quoted measured errors (rounded up)
ERROR_DIGITS = 4

#: indexer type → (the view showing the bore's generators, their layer): the barrel's side view
#: hides them, the globoid's contour view is a section through the cam axis
_BORE_VIEW: dict[type, tuple[str, str]] = {BarrelIndexer: ("side", "HIDDEN"), GloboidalIndexer: ("contour", "BORE")}


def _g(v: float) -> str:
    """A length or plain number, 6 significant digits."""
    return f"{float(v):.6g}"


def quoted_error(v: float) -> float:
    """A measured error [mm] as the title block prints it: rounded up to :data:`ERROR_DIGITS`
    significant digits (≥ ``v``)."""
    return round_up(float(v), ERROR_DIGITS)


def _e(v: float) -> str:
    """A measured error, printed rounded up (:func:`quoted_error`)."""
    return f"{quoted_error(v):.{ERROR_DIGITS - 1}e}"


def _deg(v: float) -> str:
    return f"{float(v):.4f}°"


def _finite(v: float) -> float | None:
    return float(v) if math.isfinite(v) else None


@dataclass(frozen=True)
class SpatialDrawingInfo:
    """What the pipeline's spatial indexer drawing holds (report.json's ``drawing`` section).

    Attributes:
        drawn: what :func:`~cam_workbench.exporters.dxf_spatial_indexer.spatial_drawing` drew (its
            measured errors: ``fit_error`` the flank surfaces', ``trace_error`` the barrel's trace
            SPLINEs' at :data:`~cam_workbench.exporters.dxf_spatial_indexer.CHECKS` points per span,
            NaN without traces).
        rows: the title block's (label, value) rows (empty without a title block).
        title: the title block's title.
        chord_tolerance: ``drawing.chord_tolerance`` [mm] (≥ the traces' measured error).
        dimensions: whether the centre distance and the bore are dimensioned.
        turret_angle_deg: the turret's angle ψ [deg] at input angle 0, where the drawing shows it.
        bore_diameter: the bore drawn [mm] (0: none).
        counts: entity type → how many the drawing holds (SPLINE, ARC, CIRCLE, LINE, LWPOLYLINE,
            DIMENSION, TEXT).
    """

    drawn: SpatialDxfInfo
    rows: tuple[tuple[str, str], ...]
    title: str
    chord_tolerance: float
    dimensions: bool
    turret_angle_deg: float
    bore_diameter: float
    counts: dict[str, int]

    def summary(self) -> dict[str, Any]:
        """report.json's ``drawing``: plain numbers, lengths in mm, angles in degrees."""
        d = self.drawn
        lib = d.summary()
        traced = bool(d.traces)
        layers = list(d.layers) + (["BORE"] if self.bore_diameter > 0 and "BORE" not in d.layers else [])
        return {
            "written": True, "file_version": DXF_VERSION, "insunits": d.insunits, "units": d.units,
            "kind": d.kind,
            # the traces are polynomial cubic SPLINEs interpolating exact envelope points: fitted;
            # without traces no curve is written as a spline (circles, arcs and lines only)
            "curves": "cubic" if traced else None, "exact": False,
            "profile_curve": ("flank traces in the developed views: polynomial cubic SPLINEs in τ interpolating exact "
                              "envelope points (fitted, not exact)" if traced else
                              "no flank curve drawn: the flanks are surfaces (their fit error quoted)"),
            "circles_arcs_lines": "exact",
            "chord_tolerance": self.chord_tolerance,
            "layers": layers, "splines": self.counts["SPLINE"], "arcs": self.counts["ARC"],
            "circles": self.counts["CIRCLE"], "rollers": d.rollers,
            "flank_fit_error": {"value": d.fit_error, "quoted": quoted_error(d.fit_error), "unit": d.units,
                                "what": "the bicubic B-spline flank surfaces vs the exact envelope of the rollers "
                                        "(report.json body.flank_fit_error)"},
            "drawn_trace_error": {"value": _finite(d.trace_error) if traced else None,
                                  "quoted": quoted_error(d.trace_error) if traced else None,
                                  "unit": d.units, "points_per_span": CHECKS, "target": TRACE_TOLERANCE,
                                  "what": f"the drawn trace SPLINEs vs the exact envelope on the cylinder, {CHECKS} "
                                          "points per span (parametric in τ: a bound on the distance)" if traced else
                                          "no flank traces drawn"},
            "traces": lib["traces"],
            "drawn_at": {"input_angle_deg": 0.0, "turret_angle_deg": self.turret_angle_deg,
                         "what": "the input angle the cam and the turret are drawn at, and the turret's angle there"},
            "bore_diameter": self.bore_diameter,
            "text_height": d.text_height,
            "title_block": bool(self.rows), "dimensions": self.dimensions,
            "phi_mid_deg": lib["phi_mid_deg"],
            "view_origins": lib["views"],
            "views": _VIEW_WORDS[d.kind],
        }


_VIEW_WORDS = {
    "barrel": ["side view (X = z, Y = y, the viewer on -x)", "end view along the cam axis (X = x, Y = y)",
               "developed views at the rib's top and root radii (X = R·(φ − φ_m), Y = z, seen from outside) with "
               "the flank traces"],
    "globoidal": ["contour view: the section in the turret's plane y = 0 (X = z, Y = x)",
                  "end view along the cam axis (X = x, Y = y)"],
}


def _refuse_unsupported(dr: Any) -> None:
    """The ``[drawing]`` settings no spatial indexer's drawing honours (SpecError naming the field)."""
    if dr.dxf_version != DXF_VERSION:
        raise SpecError("drawing.dxf_version", f"a barrel or globoidal indexer's drawing is written as {DXF_VERSION} "
                        f"only, got {dr.dxf_version}")
    if dr.text_height is not None:
        raise SpecError("drawing.text_height", "a barrel or globoidal indexer's drawing sizes its text from the "
                        "indexer (1/60 of the drawing's span): leave it out")


def _refuse_traces(dr: Any, drawn: SpatialDxfInfo) -> None:
    """What the drawn flank traces cannot honour (SpecError naming the field); nothing without traces."""
    if not drawn.traces:
        return
    if dr.curves != "cubic":
        raise SpecError("drawing.curves", f'"{dr.curves}" is not available for a barrel indexer\'s drawing: its flank '
                        'traces are written as polynomial cubic SPLINEs interpolating exact envelope points '
                        '("cubic")')
    if drawn.trace_error > dr.chord_tolerance:
        raise SpecError("drawing.chord_tolerance", f"the drawn flank traces are within {_e(drawn.trace_error)} mm "
                        f"of the exact envelope (measured; target {TRACE_TOLERANCE:g} mm): a chord_tolerance of "
                        f"{dr.chord_tolerance:g} mm asks for less")


def drawn_turret_angle(design: SpatialIndexerDesign) -> float:
    """The turret's angle ψ [deg] at input angle 0, where the drawing shows the turret (report.json
    ``drawing.drawn_at.turret_angle_deg``)."""
    return math.degrees(float(turret_angle(design.geometry.indexer, np.array([0.0]))[0][0]))


def _barrel_rows(geo: dict[str, Any]) -> list[tuple[str, str]]:
    return [("TURRET PITCH RADIUS R_p", f"{_g(geo['pitch_radius'])} mm"),
            ("RIB RADII", f"ROOT {_g(geo['root_radius'])} mm, TOP {_g(geo['outer_radius'])} mm")]


def _globoid_rows(geo: dict[str, Any]) -> list[tuple[str, str]]:
    return [("RIB GLOBOIDS", f"TIP {_g(geo['tip_radius'])} mm, ROOT {_g(geo['root_radius'])} mm ABOUT THE TURRET AXIS")]


#: indexer type → its own rows (the rib's radii)
_OWN_ROWS = {BarrelIndexer: _barrel_rows, GloboidalIndexer: _globoid_rows}


def title_rows(design: SpatialIndexerDesign, summary: dict[str, Any], trace_error: float | None,
               turret_angle_deg: float | None = None) -> list[tuple[str, str]]:
    """(label, value) rows of the title block: the numbers of ``summary`` (report.json's dict),
    ``trace_error`` [mm] (report.json ``drawing.drawn_trace_error``; None: no traces drawn) and
    ``turret_angle_deg`` (``drawing.drawn_at.turret_angle_deg``; :func:`drawn_turret_angle` when
    None); lengths in mm, angles in degrees, measured errors rounded up to 4 significant digits."""
    dr = design.spec.drawing
    ix = design.geometry.indexer
    geo = summary["indexer"]["geometry"]
    body = summary["body"]
    pa = summary["pressure_angle"]
    checks = summary.get("checks")
    psi0 = drawn_turret_angle(design) if turret_angle_deg is None else float(turret_angle_deg)
    limit = pressure_limit(checks)
    bore = float(body["bore_diameter"] or 0.0)
    margin, rib = geo["min_regularity_margin"], geo["min_rib_thickness"]
    fit = body["flank_fit_error"]
    motion = summary["indexer"]["motion_from_geometry"]
    rows = [
        *title_head(dr),
        ("TYPE", f"{str(summary['indexer']['type']).upper()} INDEXER"),
        ("STATIONS N", str(int(geo["stations"]))),
        ("INDEX ANGLE BETA", f"{_g(geo['index_angle_deg'])}°"),
        ("MOTION LAW", str(geo["law"]).upper()),
        ("INDEX START", f"{_g(geo['index_start_deg'])}° OF INPUT"),
        ("CENTRE DISTANCE C", f"{_g(geo['centre_distance'])} mm"),
        *_OWN_ROWS[type(ix)](geo),
        ("ROLLER RADIUS r_r", f"{_g(geo['roller_radius'])} mm" + (" AT THE MIDDLE" if "roller_radius_start" in geo
                                                                  else "")),
        *([("ROLLER CONE ANGLE", f"{_g(geo['roller_cone_angle_deg'])}°, RADIUS {_g(geo['roller_radius_start'])} mm AT "
                                 f"t = {_g(geo['roller_start'])} TO {_g(geo['roller_radius_end'])} mm AT "
                                 f"t = {_g(geo['roller_end'])}")] if "roller_radius_start" in geo else []),
        ("ROLLER LENGTH", f"{_g(geo['roller_end'] - geo['roller_start'])} mm, t = {_g(geo['roller_start'])} TO "
                          f"{_g(geo['roller_end'])} mm"),
        ("CAM WIDTH W", f"{_g(geo['cam_width'])} mm"),
        ("BORE", f"Ø{_g(bore)} mm" if bore > 0 else "NONE"),
        ("PRESSURE ANGLE (DRIVING)", f"{_deg(pa['max_deg'])} AT {_deg(pa['at_deg'])} OF INPUT{limit}"),
        ("PRESSURE ANGLE (ANY CONTACT)", f"{_deg(pa['contacts_max_deg'])} AT {_deg(pa['contacts_max_at_deg'])} "
                                         "OF INPUT (NOT CHECKED)"),
        ("MIN REGULARITY MARGIN", f"{margin['value_1']:.4f} AT {_deg(margin['at_deg'])} OF INPUT"),
        ("MIN RIB THICKNESS", f"{rib['value_mm']:.4f} mm AT {_deg(rib['at_deg'])} OF INPUT"),
        ("FLANK SURFACES", f"FITTED BICUBIC B-SPLINES, NOT EXACT: FIT ERROR {_e(fit['value'])} {fit['unit']} "
                           "FROM THE EXACT ENVELOPE (MEASURED)"),
    ]
    if trace_error is not None:
        rows += [("FLANK TRACES", f"FITTED CUBIC SPLINES, NOT EXACT: {_e(trace_error)} mm FROM THE EXACT ENVELOPE "
                                  f"(MEASURED, {CHECKS} POINTS PER SPAN)"),
                 ("ROOT TRACES", f"FLANKS CONTINUED BELOW THE ROLLERS' ENDS (t < {_g(geo['roller_start'])} mm)")]
    else:
        rows.append(("FLANK TRACES", "NOT DRAWN (THE FLANKS ARE SURFACES)"))
    rows += [
        ("CIRCLES, ARCS, LINES", "EXACT"),
        ("TURRET MOTION FROM FLANKS", f"{motion['max_error_rad']:.3e} rad FROM THE LAW ({int(motion['samples'])} "
                                      "INPUT ANGLES)"),
    ]
    return rows + title_tail(summary, f"INPUT ANGLE 0°, TURRET ANGLE {psi0:.4f}°")


def _add_bore(doc: Any, design: SpatialIndexerDesign, drawn: SpatialDxfInfo, diameter: float, dimensions: bool) -> None:
    """The bore of ``diameter`` [mm]: a circle in the end view, its generators (z = ±W/2) in the
    side or contour view, its diameter dimensioned in the end view when ``dimensions``."""
    msp = doc.modelspace()
    if not doc.layers.has_entry("BORE"):
        color, linetype, lw = LAYERS["BORE"]
        doc.layers.add("BORE", color=color, linetype=linetype).dxf.lineweight = lw
    ix = design.geometry.indexer
    rb, half, h = 0.5 * diameter, 0.5 * float(ix.cam_width), drawn.text_height
    xe, ye = drawn.views["end"]
    msp.add_circle((xe, ye), rb, dxfattribs={"layer": "BORE"})
    view, layer = _BORE_VIEW[type(ix)]
    x0, y0 = drawn.views[view]
    for y in (-rb, rb):
        msp.add_line((x0 - half, y0 + y), (x0 + half, y0 + y), dxfattribs={"layer": layer})
    if dimensions:
        msp.add_diameter_dim(center=(xe, ye), radius=rb, angle=135.0, dimstyle=DIMSTYLE,
                             override=dim_values(h), dxfattribs={"layer": "DIMENSIONS", "dimstyle": DIMSTYLE}).render()


_COUNTED = ("SPLINE", "ARC", "CIRCLE", "LINE", "LWPOLYLINE", "DIMENSION", "TEXT")


@DRAWINGS.register(SpatialIndexerDesign)
def build_spatial_indexer_dxf(design: SpatialIndexerDesign, summary: dict[str, Any] | None = None
                              ) -> tuple[Any, SpatialDrawingInfo]:
    """(ezdxf document, what it holds) of a barrel or globoidal indexer's drawing, its title block
    quoting ``summary`` (``design.summary()`` when None); nothing written; mm.

    Raises:
        SpecError: a ``[drawing]`` setting the drawing cannot honour (see the module docstring).
    """
    dr = design.spec.drawing
    _refuse_unsupported(dr)
    title = title_line(design.spec)
    doc, drawn = spatial_drawing(design.geometry, design.surfaces, title)
    _refuse_traces(dr, drawn)
    s = summary if summary is not None else design.summary()
    drop_library_annotations(doc, bool(dr.dimensions))
    bore = float(s["body"]["bore_diameter"] or 0.0)
    if bore > 0:
        _add_bore(doc, design, drawn, bore, bool(dr.dimensions))
    psi0 = drawn_turret_angle(design)
    rows: list[tuple[str, str]] = []
    reach = 0.0
    if dr.title_block:
        rows = title_rows(design, s, drawn.trace_error if drawn.traces else None, psi0)
        geo = s["indexer"]["geometry"]
        reach = float(geo["centre_distance"]) + float(geo["roller_end"])
    msp = doc.modelspace()
    finish_drawing(msp, title, rows, reach, drawn.text_height)
    counts = {kind: len(msp.query(kind)) for kind in _COUNTED}
    return doc, SpatialDrawingInfo(drawn, tuple(rows), title, float(dr.chord_tolerance), bool(dr.dimensions), psi0,
                                   bore, counts)


__all__ = ["DXF_VERSION", "ERROR_DIGITS", "SpatialDrawingInfo", "build_spatial_indexer_dxf", "drawn_turret_angle",
           "quoted_error", "title_rows"]

"""The parallel indexer's drawing in the output pipeline (``cam.dxf``), registered in
:data:`cam_workbench.exporters.dxf.DRAWINGS` for
:class:`~cam_workbench.generators.bodies.indexing.parallel_kind.ParallelIndexerDesign`.

The drawing itself is :func:`cam_workbench.exporters.dxf_indexer.indexer_drawing` of the design's
geometry and plates (each cam's loop: the dwell an exact ARC, each flank a SPLINE with the body's
own cubic B-spline, no refit; the bore, the turret and its rollers at input angle 0, the centre
distance).  Its title block is replaced by one quoting the ``summary`` the pipeline passes — the
dict report.json holds — so that the drawing and the report say the same numbers: the indexer's
parameters (``indexer.geometry``), the plates (``body``), the flanks' measured fit error
(``body.flank_fit_error``: fitted, NOT exact — only the dwell arcs are exact), the pressure
angles (``pressure_angle``), the volume, the checks' verdict, the spec digest and where the turret
is drawn (``drawing.drawn_at``: the input angle and the turret's angle there).

``[drawing]``: ``title``, ``part_number``, ``author``, ``material``, ``title_block`` and
``dimensions`` are honoured; ``curves`` "cubic" and "spline" both get the body's B-splines
themselves (polynomial cubics: what "cubic" asks for, and the NURBS itself); what the indexer's
drawing cannot do yet is refused naming the field (``curves`` "arcs"/"polyline", a
``dxf_version`` other than R2010, a ``text_height``).

The steps every indexer's drawing takes alike are public here for the barrel and globoidal
indexers' (:mod:`.drawing_spatial_indexer`): the library's annotations dropped
(:func:`drop_library_annotations`), the title block's first and last rows (:func:`title_head`,
:func:`pressure_limit`, :func:`title_tail`) and the title block placed (:func:`finish_drawing`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from cam_workbench.generators import __version__
from cam_workbench.generators.bodies.indexing.parallel import turret_angle
from cam_workbench.generators.bodies.indexing.parallel_kind import ParallelIndexerDesign
from cam_workbench.generators.errors import SpecError

from .dxf import DRAWINGS, checks_cell, extents, title_line
from .dxf_indexer import SPAN_SAMPLES, IndexerDxfInfo, title_block, indexer_drawing

#: the DXF version :func:`~cam_workbench.exporters.dxf_indexer.indexer_drawing` writes
DXF_VERSION = "R2010"


def _g(v: float) -> str:
    """A length or plain number, 6 significant digits."""
    return f"{float(v):.6g}"


def _e(v: float) -> str:
    """A measured error, 4 significant digits."""
    return f"{float(v):.3e}"


def _deg(v: float) -> str:
    return f"{float(v):.2f}°"


@dataclass(frozen=True)
class IndexerDrawingInfo:
    """What the pipeline's indexer drawing holds (report.json's ``drawing`` section).

    Attributes:
        drawn: what :func:`~cam_workbench.exporters.dxf_indexer.indexer_drawing` drew (its
            measured errors: ``fit_error`` the body's, ``drawn_error`` the SPLINEs' at
            :data:`~cam_workbench.exporters.dxf_indexer.SPAN_SAMPLES` points per knot span).
        rows: the title block's (label, value) rows (empty without a title block).
        title: the title block's title.
        chord_tolerance: ``drawing.chord_tolerance`` (the SPLINEs are the body's curves
            themselves: no approximation of them is drawn).
        dimensions: whether the centre distance is dimensioned.
        turret_angle_deg: the turret's angle ψ [deg] at input angle 0, where the drawing shows it
            (report.json ``drawing.drawn_at``; the title block's DRAWN AT row).
    """

    drawn: IndexerDxfInfo
    rows: tuple[tuple[str, str], ...]
    title: str
    chord_tolerance: float
    dimensions: bool
    turret_angle_deg: float = 0.0

    def summary(self) -> dict[str, Any]:
        d = self.drawn
        return {
            "written": True, "file_version": DXF_VERSION, "insunits": d.insunits, "units": d.units,
            # the SPLINEs are the body's own (polynomial cubic) B-splines: the NURBS itself
            "curves": "spline", "exact": False,
            "profile_curve": "cams' loops: exact dwell ARCs and the body's fitted cubic flank B-splines (not exact)",
            "chord_tolerance": self.chord_tolerance,
            "layers": list(d.layers), "cams": d.cams, "splines": d.splines, "arcs": d.arcs, "rollers": d.rollers,
            "dwell_arcs": "exact",
            "flank_fit_error": {"value": d.fit_error, "unit": d.units,
                                "what": "the body's flank B-splines vs the exact offset of the roller loci "
                                        "(report.json body.flank_fit_error)"},
            "drawn_flank_error": {"value": d.drawn_error, "unit": d.units,
                                  "points_per_span": SPAN_SAMPLES,
                                  "what": f"the drawn flank SPLINEs vs the exact offset, {SPAN_SAMPLES} points "
                                          "per knot span"},
            "drawn_at": {"input_angle_deg": 0.0, "turret_angle_deg": self.turret_angle_deg,
                         "what": "the input angle the cams and the turret are drawn at, and the turret's angle there"},
            "text_height": d.text_height,
            "title_block": bool(self.rows), "dimensions": self.dimensions,
            "views": ["top view of the cams in the cam frame at input angle 0 (= the fixed frame), the turret and "
                      "its rollers"],
        }


def _refuse_unsupported(dr: Any) -> None:
    if dr.curves not in ("cubic", "spline"):
        raise SpecError("drawing.curves", f'"{dr.curves}" is not available for a parallel indexer\'s drawing yet: '
                        'its flanks are written as the body\'s cubic B-splines ("cubic" or "spline")')
    if dr.dxf_version != DXF_VERSION:
        raise SpecError("drawing.dxf_version", f"a parallel indexer's drawing is written as {DXF_VERSION} only, "
                        f"got {dr.dxf_version}")
    if dr.text_height is not None:
        raise SpecError("drawing.text_height", "a parallel indexer's drawing sizes its text from the indexer "
                        "(1/60 of the drawing's width): leave it out")


def drawn_turret_angle(design: ParallelIndexerDesign) -> float:
    """The turret's angle ψ [deg] at input angle 0, where the drawing shows the turret (report.json
    ``drawing.drawn_at.turret_angle_deg``)."""
    return math.degrees(float(turret_angle(design.geometry.indexer, np.array([0.0]))[0][0]))


def title_head(dr: Any) -> list[tuple[str, str]]:
    """The title block's first rows: ``[drawing]``'s part number, material and author ("-" when not
    given)."""
    return [("PART NO.", dr.part_number or "-"), ("MATERIAL", dr.material or "-"), ("DRAWN BY", dr.author or "-")]


def pressure_limit(checks: Any) -> str:
    """The pressure angle's limit as the title block quotes it, ' (LIMIT φ°)', from report.json's
    ``checks`` (their ``pressure_angle`` row's limit [deg]); "" without that check or its limit."""
    if isinstance(checks, dict) and "pressure_angle" in (checks.get("results") or {}):
        lim = checks["results"]["pressure_angle"].get("limit")
        return "" if lim is None else f" (LIMIT {lim:g}°)"
    return ""


def title_tail(summary: dict[str, Any], drawn_at: str) -> list[tuple[str, str]]:
    """The title block's last rows: the checks' verdict (when ``summary``, report.json's dict, has
    them), DRAWN AT ``drawn_at``, the units and scale (mm, 1:1), the spec digest and the software."""
    checks = summary.get("checks")
    rows = [("DESIGN CHECKS", checks_cell(checks))] if isinstance(checks, dict) and "passed" in checks else []
    return rows + [
        ("DRAWN AT", drawn_at),
        ("UNITS / SCALE", "mm / 1:1"),
        ("SPEC DIGEST (SHA-256)", str(summary.get("spec_digest", "-"))),
        ("SOFTWARE", f"cam_workbench {__version__}"),
    ]


def title_rows(design: ParallelIndexerDesign, summary: dict[str, Any], drawn_error: float,
               turret_angle_deg: float | None = None) -> list[tuple[str, str]]:
    """(label, value) rows of the title block: the numbers of ``summary`` (report.json's dict),
    ``drawn_error`` (report.json ``drawing.drawn_flank_error``) and ``turret_angle_deg``
    (``drawing.drawn_at.turret_angle_deg``; :func:`drawn_turret_angle` when None); lengths in mm,
    angles in degrees."""
    dr = design.spec.drawing
    geo = summary["indexer"]["geometry"]
    body = summary["body"]
    pa = summary["pressure_angle"]
    checks = summary.get("checks")
    rr = float(geo["roller_radius_mm"])
    beta = float(geo["index_angle_deg"])
    psi0 = drawn_turret_angle(design) if turret_angle_deg is None else float(turret_angle_deg)
    limit = pressure_limit(checks)
    bore = float(body["bore_diameter"])
    arcs = " / ".join(_g(c["dwell_radius_mm"] - rr) for c in geo["per_cam"])
    fit = body["flank_fit_error"]
    rows = [
        *title_head(dr),
        ("STATIONS N", str(int(geo["stations"]))),
        ("INDEX ANGLE BETA", f"{_g(beta)}°"),
        ("MOTION LAW", str(geo["law"]).upper()),
        ("INDEX START", f"{_g(geo['index_start_deg'])}° OF INPUT"),
        ("CENTRE DISTANCE C", f"{_g(geo['centre_distance_mm'])} mm"),
        ("TURRET PITCH RADIUS R_p", f"{_g(geo['pitch_radius_mm'])} mm"),
        ("ROLLER RADIUS r_r", f"{_g(rr)} mm"),
        ("CAMS", f"{int(body['cams'])} PLATES {_g(body['plate_thickness'])} mm THICK, GAP {_g(body['gap'])} mm"),
        ("BORE", f"Ø{_g(bore)} mm" if bore > 0 else "NONE"),
        ("LARGEST CAM RADIUS", f"{_g(body['outer_radius'])} mm"),
        ("DWELL ARCS", f"EXACT ARCS R {arcs} mm, {_g(360.0 - beta)}° EACH"),
        ("FLANKS", f"FITTED CUBIC B-SPLINES, NOT EXACT: FIT ERROR {_e(fit['value'])} {fit['unit']} "
                   "FROM THE EXACT OFFSET (MEASURED)"),
        ("DRAWN FLANK SPLINES", f"THE BODY'S OWN (NO REFIT): {_e(drawn_error)} mm FROM THE EXACT OFFSET "
                                f"({SPAN_SAMPLES} POINTS PER SPAN)"),
        ("PRESSURE ANGLE (LOAD-CARRYING)", f"{_deg(pa['max_deg'])} AT {_deg(pa['at_deg'])} OF INPUT{limit}"),
        ("MAX DRIVING PRESSURE ANGLE", f"{_deg(pa['index_max_deg'])} AT {_deg(pa['index_max_at_deg'])} OF INPUT"),
        ("VOLUME", f"{summary['volume']:.6g} mm3"),
    ]
    return rows + title_tail(summary, f"INPUT ANGLE 0°, TURRET ANGLE {psi0:.4f}°; INPUT TURNS CCW, TURRET CW")


def delete_entities(msp: Any, query: str) -> None:
    """Delete every entity of the layout ``msp`` that the ezdxf entity ``query`` selects."""
    for e in list(msp.query(query)):
        msp.delete_entity(e)


def drop_library_annotations(doc: Any, dimensions: bool) -> None:
    """Delete the library drawing's title block (layer TITLE: it quotes the library's own numbers,
    replaced by one quoting report.json's) and, without ``dimensions``, every DIMENSION with its
    block."""
    msp = doc.modelspace()
    delete_entities(msp, '*[layer=="TITLE"]')
    if not dimensions:
        for dim in list(msp.query("DIMENSION")):
            block = dim.dxf.get("geometry")
            msp.delete_entity(dim)
            if block and block in doc.blocks:
                doc.blocks.delete_block(block, safe=False)


def finish_drawing(msp: Any, title: str, rows: list[tuple[str, str]], reach: float, h: float) -> None:
    """The title block of ``rows`` under ``title`` (none when ``rows`` is empty) right of everything
    drawn, a sheet border round it all (:func:`.dxf.extents` with ``reach`` [mm] the radius that
    bounds the drawing when ezdxf cannot measure; ``h`` the text height [mm]); then the initial view
    zoomed to the extents."""
    if rows:
        box = extents(msp, reach, h)
        title_block(msp, title, rows, box.x1 + 2 * h, box.y1 + h, h, (box.x0 - h, box.y0 - h))
    try:
        from ezdxf import zoom  # deferred: ezdxf, loaded when a drawing is made

        zoom.extents(msp, factor=1.05)
    except Exception:  # noqa: BLE001 - the initial view is a convenience only
        pass


@DRAWINGS.register(ParallelIndexerDesign)
def build_indexer_dxf(design: ParallelIndexerDesign, summary: dict[str, Any] | None = None
                      ) -> tuple[Any, IndexerDrawingInfo]:
    """(ezdxf document, what it holds) of a parallel indexer's drawing, its title block quoting
    ``summary`` (``design.summary()`` when None); nothing written.

    Raises:
        SpecError: a ``[drawing]`` setting the indexer's drawing cannot honour (see the module
            docstring).
    """
    dr = design.spec.drawing
    _refuse_unsupported(dr)
    s = summary if summary is not None else design.summary()
    title = title_line(design.spec)
    doc, drawn = indexer_drawing(design.geometry, design.cams_body, title)
    drop_library_annotations(doc, bool(dr.dimensions))
    psi0 = drawn_turret_angle(design)
    rows = title_rows(design, s, drawn.drawn_error, psi0) if dr.title_block else []
    finish_drawing(doc.modelspace(), title, rows, float(s["body"]["outer_radius"]) if rows else 0.0, drawn.text_height)
    return doc, IndexerDrawingInfo(drawn, tuple(rows), title, float(dr.chord_tolerance), bool(dr.dimensions), psi0)

"""DXF drawing of a parallel (plate-cam) indexer (ezdxf): the cams, the turret and its rollers, 1:1 in mm.

Drawn in the cam frame at input angle θ = 0, where it coincides with the fixed frame
(:mod:`cam_workbench.generators.bodies.indexing.parallel`): the input axis O at the origin, the turret
axis P = (C, 0).

==================  ==========================================================================
layer               content
==================  ==========================================================================
CAM_0, CAM_1, …     each cam's profile, the body's loop piece by piece: the dwell part an ARC
                    (exact: radius r_d − r_r about O, sweeping 360° − β), each flank a SPLINE
                    with the degree, knots and control points of the body's cubic B-spline (no
                    refit); the flanks are fitted to the exact offset, their measured distance
                    from it quoted in the title block
BORE                the bore
TURRET              the turret's centre mark at P and its roller pitch circle R_p
ROLLERS_0, …        plane k's N rollers (circles of r_r) where they are at θ = 0
CENTERLINES         the centre line O–P and O's centre mark
DIMENSIONS          the centre distance C (a linear DIMENSION)
TITLE               the title block (TEXT rows in a ruled box, right of the drawing)
==================  ==========================================================================
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Any

import numpy as np

from cam_workbench.generators import __version__
from cam_workbench.generators.bodies import Arc, Curve
from cam_workbench.generators.bodies.indexing.parallel import ParallelDesign, roller_state, turret_angle
from cam_workbench.generators.bodies.indexing.parallel_body import IndexerBody, offset_point

from .atomic import atomic_path
from .dxf import DIMSTYLE, LAYERS, add_closed_outline, add_nurbs_spline, text_width

#: ACI colours of the cams' (and their rollers') layers, cam k → _CAM_COLORS[k]
_CAM_COLORS = (7, 2, 6)
#: samples per knot span where the drawn flanks' distance from the exact offset is measured
SPAN_SAMPLES = 64
#: text heights of the title block [× the drawing's text height]: title, cells, row pitch, margin
_TITLE_H, _CELL_H, _ROW_H, _PAD = 1.4, 0.8, 1.8, 0.5
DEFAULT_TITLE = "PARALLEL INDEXER CAMS"


def indexer_layers(cams: int) -> dict[str, tuple[int, str, int]]:
    """Layer → (ACI colour, linetype, lineweight [1/100 mm]) of an indexer's drawing with ``cams`` cams."""
    out: dict[str, tuple[int, str, int]] = {}
    for k in range(cams):
        out[f"CAM_{k}"] = (_CAM_COLORS[k % len(_CAM_COLORS)], "Continuous", 50)
    out["BORE"] = LAYERS["BORE"]
    out["TURRET"] = (5, "PHANTOM", 18)
    for k in range(cams):
        out[f"ROLLERS_{k}"] = (_CAM_COLORS[k % len(_CAM_COLORS)], "Continuous", 25)
    for name in ("CENTERLINES", "DIMENSIONS", "TITLE"):
        out[name] = LAYERS[name]
    return out


@dataclass(frozen=True)
class IndexerDxfInfo:
    """What :func:`indexer_drawing` drew.

    Attributes:
        layers: the layer names; cams: n_c; splines, arcs: the profile entities (2 and 1 per cam);
        rollers: the roller circles (N per plane); fit_error: the body's flank fit error [mm]
        (measured at its check points); drawn_error: the drawn SPLINEs' largest distance from the
        exact offset [mm], measured at :data:`SPAN_SAMPLES` points per knot span; quoted_error:
        the number the title block quotes [mm], the larger of the two rounded up to 2 significant
        digits; text_height [mm]; rows: the title block's (label, value) rows.
    """

    layers: tuple[str, ...]
    cams: int
    splines: int
    arcs: int
    rollers: int
    fit_error: float
    drawn_error: float
    quoted_error: float
    text_height: float
    rows: tuple[tuple[str, str], ...]
    units: str = "mm"
    insunits: int = 4

    def summary(self) -> dict[str, Any]:
        """Plain numbers (lengths in mm)."""
        return {"units": self.units, "insunits": self.insunits, "layers": list(self.layers), "cams": self.cams,
                "splines": self.splines, "arcs": self.arcs, "rollers": self.rollers,
                "flank_fit_error_mm": self.fit_error, "drawn_flank_error_mm": self.drawn_error,
                "quoted_flank_error_mm": self.quoted_error, "dwell_arcs": "exact"}


def round_up(x: float, digits: int = 2) -> float:
    """``x`` ≥ 0 rounded up to ``digits`` significant digits (a quoted bound stays a bound)."""
    if not x > 0:
        return 0.0
    step = 10.0 ** (math.floor(math.log10(x)) - digits + 1)
    up = math.ceil(x / step * (1 - 1e-12)) * step
    return float(f"{up:.{digits - 1}e}")


def drawn_flank_error(design: ParallelDesign, body: IndexerBody) -> float:
    """Largest distance [mm] of the body's flank B-splines from the exact offset Q(τ), at
    :data:`SPAN_SAMPLES` points per knot span (the spline's parameter is τ)."""
    worst = 0.0
    for k, fits in enumerate(body.fits):
        for fit in fits:
            lo, hi = fit.curve.domain
            spans = max(len(np.unique(fit.curve.knots)) - 1, 1)
            tau = np.linspace(lo, hi, spans * SPAN_SAMPLES + 1)
            exact, _ = offset_point(design.indexer, k, tau)
            worst = max(worst, float(np.max(np.hypot(*(fit.curve.evaluate(tau) - exact).T))))
    return worst


def new_document(h: float) -> Any:
    """A new R2010 ezdxf document in mm with the standard linetypes and a dimension style."""
    import ezdxf  # deferred: ezdxf, loaded when a drawing is made

    doc = ezdxf.new("R2010", setup=True, units=4)
    doc.header["$LTSCALE"] = h
    doc.header["$LUPREC"] = 3
    ds = doc.dimstyles.new(DIMSTYLE)
    for key, value in dim_values(h).items():
        ds.dxf.set(key, value)
    doc.header["$DIMSTYLE"] = DIMSTYLE
    return doc


def dim_values(h: float) -> dict[str, Any]:
    return {"dimtxt": h, "dimasz": h, "dimgap": 0.3 * h, "dimexe": 0.5 * h, "dimexo": 0.5 * h, "dimdec": 3,
            "dimzin": 8, "dimclrd": 3, "dimclre": 3, "dimclrt": 3, "dimlfac": 1.0, "dimtih": 1, "dimtoh": 1}


def add_text(msp: Any, text: str, at: tuple[float, float], height: float, layer: str) -> Any:
    t = msp.add_text(text, height=height, dxfattribs={"layer": layer, "style": "Standard", "linetype": "Continuous"})
    t.set_placement(at)
    return t


def add_cross(msp: Any, x: float, y: float, size: float, layer: str) -> None:
    att = {"layer": layer}
    msp.add_line((x - size, y), (x + size, y), dxfattribs=att)
    msp.add_line((x, y - size), (x, y + size), dxfattribs=att)


def _bore_radius(body: IndexerBody) -> float:
    for prism in body.geometry.prisms:
        for hole in prism.holes:
            if hole.role == "bore" and hole.is_circle:
                return float(hole.pieces[0].radius)
    return 0.0


def _plates(body: IndexerBody) -> tuple[float, float]:
    """(thickness, gap) [mm] of the cam plates."""
    cams = [p for p in body.geometry.prisms if p.role.startswith("cam")]
    t = cams[0].z1 - cams[0].z0
    gap = cams[1].z0 - cams[0].z1 if len(cams) > 1 else 0.0
    return t, gap


def _g(v: float) -> str:
    return f"{v:.6g}"


def title_rows(design: ParallelDesign, body: IndexerBody, quoted_error: float) -> list[tuple[str, str]]:
    """(label, value) rows of the title block: the indexer's parameters, the plates, how the profile
    is drawn (dwell arcs exact, flanks within ``quoted_error`` [mm] of the exact offset), the worst
    driving pressure angle; angles in degrees, lengths in mm."""
    ix = design.indexer
    s = design.summary()
    t, gap = _plates(body)
    r_bore = _bore_radius(body)
    beta = math.degrees(float(ix.index_angle))
    psi0 = math.degrees(float(turret_angle(ix, np.array([0.0]))[0][0]))
    arcs = " / ".join(_g(c.dwell_radius - float(ix.roller_radius)) for c in design.cams)
    return [
        ("STATIONS N", str(int(ix.stations))),
        ("INDEX ANGLE BETA", f"{_g(beta)}°"),
        ("MOTION LAW", str(ix.law).upper()),
        ("INDEX START", f"{_g(math.degrees(float(ix.index_start)))}° OF INPUT"),
        ("CENTRE DISTANCE C", f"{_g(float(ix.centre_distance))} mm"),
        ("TURRET PITCH RADIUS R_p", f"{_g(float(ix.pitch_radius))} mm"),
        ("ROLLER RADIUS r_r", f"{_g(float(ix.roller_radius))} mm"),
        ("CAMS", f"{int(ix.cams)} PLATES {_g(t)} mm THICK, GAP {_g(gap)} mm"),
        ("BORE", f"Ø{_g(2 * r_bore)} mm" if r_bore > 0 else "NONE"),
        ("DWELL ARCS", f"EXACT ARCS R {arcs} mm, {_g(360.0 - beta)}° EACH"),
        ("FLANKS", f"CUBIC B-SPLINES WITHIN {quoted_error:.1e} mm OF THE EXACT OFFSET (MEASURED)"),
        ("MAX DRIVING PRESSURE ANGLE", f"{s['max_driving_pressure_angle_deg']:.2f}° AT "
                                       f"{s['max_driving_pressure_angle_at_deg']:.2f}° OF INPUT"),
        ("DRAWN AT", f"INPUT ANGLE 0°, TURRET ANGLE {psi0:.4f}°; INPUT TURNS CCW, TURRET CW"),
        ("UNITS / SCALE", "mm / 1:1"),
        ("SOFTWARE", f"cam_workbench {__version__}"),
    ]


def indexer_drawing(design: ParallelDesign, body: IndexerBody, title: str | None = None
                    ) -> tuple[Any, IndexerDxfInfo]:
    """(ezdxf document, what it holds) of the indexer's drawing, nothing written: ``body``'s cam
    profiles (:func:`~cam_workbench.generators.bodies.indexing.parallel_body.indexer_body` of
    ``design``), the bore, the turret and every roller at input angle 0, the centre distance
    dimensioned and a title block (``title``, default :data:`DEFAULT_TITLE`); mm, cam frame = fixed
    frame (see the module docstring)."""
    ix = design.indexer
    n_c, n = len(body.loops), int(ix.stations)
    c_dist, rp, rr = float(ix.centre_distance), float(ix.pitch_radius), float(ix.roller_radius)
    r_cam = max(float(np.max(np.hypot(*c.profile.T))) for c in design.cams)
    x_lo, x_hi = min(-r_cam, c_dist - rp - rr), max(r_cam, c_dist + rp + rr)
    y_hi = max(r_cam, rp + rr)
    h = float(f"{(x_hi - x_lo) / 60:.2g}")
    doc = new_document(h)
    layers = indexer_layers(n_c)
    for name, (color, linetype, lw) in layers.items():
        doc.layers.add(name, color=color, linetype=linetype).dxf.lineweight = lw
    msp = doc.modelspace()

    # the profiles: ARC for the dwell, SPLINE for each flank (the body's pieces as they are)
    splines = arcs = 0
    for k, loop in enumerate(body.loops):
        att = {"layer": f"CAM_{k}"}
        for piece in loop.pieces:
            if isinstance(piece, Curve):
                add_nurbs_spline(msp, piece.nurbs, att["layer"])
                splines += 1
            elif isinstance(piece, Arc):
                # DXF arcs run counter-clockwise from the start to the end angle, as the loop's do
                a0, a1 = sorted((piece.a0, piece.a1))
                msp.add_arc((piece.centre.real, piece.centre.imag), piece.radius, math.degrees(a0),
                            math.degrees(a1), dxfattribs=att)
                arcs += 1
            else:
                raise TypeError(f"unexpected piece {type(piece).__name__} in cam {k}'s loop")
    r_bore = _bore_radius(body)
    if r_bore > 0:
        msp.add_circle((0.0, 0.0), r_bore, dxfattribs={"layer": "BORE"})

    # the turret and the rollers at θ = 0 (fixed frame = cam frame there)
    add_cross(msp, c_dist, 0.0, rr, "TURRET")
    msp.add_circle((c_dist, 0.0), rp, dxfattribs={"layer": "TURRET"})
    for k in range(n_c):
        p, _, _ = roller_state(ix, k, np.arange(n), np.zeros(n))
        for x, y in p.tolist():
            msp.add_circle((x, y), rr, dxfattribs={"layer": f"ROLLERS_{k}"})
    add_cross(msp, 0.0, 0.0, rr, "CENTERLINES")
    ext = 1.5 * h
    msp.add_line((x_lo - ext, 0.0), (x_hi + ext, 0.0), dxfattribs={"layer": "CENTERLINES"})
    msp.add_line((0.0, -r_cam - ext), (0.0, r_cam + ext), dxfattribs={"layer": "CENTERLINES"})
    msp.add_line((c_dist, -rp - rr - ext), (c_dist, rp + rr + ext), dxfattribs={"layer": "CENTERLINES"})
    add_text(msp, "O: INPUT AXIS", (0.4 * h, r_cam + 0.6 * h), 0.7 * h, "CENTERLINES")
    add_text(msp, "P: TURRET AXIS", (c_dist + 0.4 * h, rp + rr + 0.6 * h), 0.7 * h, "CENTERLINES")

    # the centre distance, below everything
    y_dim = -y_hi - 4 * h
    msp.add_linear_dim(base=(0.5 * c_dist, y_dim), p1=(0.0, 0.0), p2=(c_dist, 0.0), angle=0.0, text="C = <>",
                       dimstyle=DIMSTYLE, override=dim_values(h),
                       dxfattribs={"layer": "DIMENSIONS", "dimstyle": DIMSTYLE}).render()

    drawn = drawn_flank_error(design, body)
    quoted = round_up(max(body.fit_error, drawn))
    rows = title_rows(design, body, quoted)
    title_block(msp, title or DEFAULT_TITLE, rows, x_hi + 3 * h, y_hi + 2 * h, h, (x_lo - 2 * h, y_dim - 3 * h))
    try:
        from ezdxf import zoom  # deferred: ezdxf, loaded when a drawing is made

        zoom.extents(msp, factor=1.05)
    except Exception:  # noqa: BLE001 - the initial view is a convenience only
        pass
    info = IndexerDxfInfo(tuple(layers), n_c, splines, arcs, n * n_c, float(body.fit_error), drawn, quoted, h,
                          tuple(rows))
    return doc, info


def title_block(msp: Any, title: str, rows: list[tuple[str, str]], x0: float, top: float, h: float,
                 sheet_corner: tuple[float, float]) -> None:
    """The ``rows`` in a ruled two-column box under ``title``, its top-left corner at (x0, top), each
    column as wide as :func:`~cam_workbench.exporters.dxf.text_width` bounds its texts; then a sheet
    border from ``sheet_corner`` (bottom left) round everything."""
    att = {"layer": "TITLE"}
    th = _CELL_H * h
    x1 = x0 + max(text_width(label, th) for label, _ in rows) + 2 * _PAD * h
    x2 = max(x1 + max(text_width(value, th) for _, value in rows) + 2 * _PAD * h,
             x0 + text_width(title, _TITLE_H * h) + 2 * _PAD * h)
    add_text(msp, title, (x0 + _PAD * h, top - 1.9 * h), _TITLE_H * h, "TITLE")
    y = top - 2.6 * h
    msp.add_line((x0, y), (x2, y), dxfattribs=att)
    for label, value in rows:
        add_text(msp, label, (x0 + _PAD * h, y - 1.35 * h), th, "TITLE")
        add_text(msp, value, (x1 + _PAD * h, y - 1.35 * h), th, "TITLE")
        y -= _ROW_H * h
        msp.add_line((x0, y), (x2, y), dxfattribs=att)
    msp.add_line((x1, top - 2.6 * h), (x1, y), dxfattribs=att)
    add_closed_outline(msp, [(x0, y), (x2, y), (x2, top), (x0, top)], att)
    left, bottom = sheet_corner
    bottom = min(bottom, y - 2 * h)
    add_closed_outline(msp, [(left, bottom), (x2 + 2 * h, bottom), (x2 + 2 * h, top + 2 * h), (left, top + 2 * h)],
                       att)


def write_indexer_dxf(design: ParallelDesign, body: IndexerBody, path: str | os.PathLike[str],
                      title: str | None = None) -> IndexerDxfInfo:
    """Write :func:`indexer_drawing` to ``path`` atomically (temporary file, then rename)."""
    doc, info = indexer_drawing(design, body, title)
    with atomic_path(path) as tmp:
        doc.saveas(str(tmp))
    return info


__all__ = ["DEFAULT_TITLE", "IndexerDxfInfo", "drawn_flank_error", "indexer_drawing", "indexer_layers", "round_up",
           "title_rows", "write_indexer_dxf"]

"""DXF manufacturing drawing of a plate cam (ezdxf), written atomically.

Model space, drawn 1:1 in the spec's units (``$INSUNITS`` says which):

========================  ==============================================================
layer                     content
========================  ==============================================================
PROFILE                   the cam profile, as ``drawing.curves`` says: "cubic" (the default) a
                          non-rational cubic SPLINE within ``chord_tolerance`` of the profile
                          NURBS (what every DXF reader draws: LibreCAD and many CAM and laser
                          programs drop rational or high-degree splines without a word);
                          "spline" a SPLINE with the degree, knots, control points and weights
                          of the profile NURBS itself (for a PH pitch curve the exact rational
                          offset, degree 9; for a B-spline pitch curve the fitted offset, whose
                          measured error the title block states — see
                          :mod:`cam_workbench.generators.checks.claims`); "arcs" / "polyline" tangent biarcs
                          (ARC/LINE) or one closed polyline within ``chord_tolerance``
PITCH                     the pitch curve, drawn as the profile is (the PH curve itself is a
                          polynomial SPLINE of degree 5)
BASE_CIRCLE, PRIME_CIRCLE the profile's base circle (report.json ``profile.base_circle_radius``: R_b −
                          roller radius; a groove's inner wall, less half the clearance) and R_b
BORE                      the central hole
CENTERLINES               axes through the rotation centre, the follower axis at θ = 0
DIMENSIONS                DIMENSION entities (bore Ø, base-circle R, largest R; rendered by
                          ezdxf's dimension machinery) and the thickness/profile note
PROFILE_2, PITCH_2        a conjugate pair's second cam (below the first): its profile (the exact
                          offset of its own PH pitch curve, drawn as PROFILE) and pitch curve
SPACER, HUB, HOLES, …     the body's other loops (groove walls, rim, hub, holes, timing mark)
TITLE                     the title block — the body's name (:func:`title_line`),
                          key parameters, the numbers and the checks verdict of the summary
                          dict that becomes report.json (spec digest, deviations, errors,
                          pressure angle, failed checks), how the curves are drawn with their
                          measured distance from the exact ones, and the motion table — placed
                          right of the extents of everything else (dimension texts included),
                          and a border round it all
========================  ==============================================================

The profile is written counter-clockwise (``CamDesign.profile_ccw``), as outer boundaries are in
CAM.  Cubic splines, arcs and polylines come from :mod:`cam_workbench.generators.curves.approx`; their distance
from the NURBS is measured two-sided on dense samples and returned.  Every text is placed in a
cell as wide as :func:`text_width`'s upper bound of its drawn width (the fonts readers substitute
for the Standard style differ by up to 20 %).
"""
from __future__ import annotations

import logging
import math
import os
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from cam_workbench.generators import __version__
from cam_workbench.generators.bodies import Arc, Curve, Line
from cam_workbench.generators.kinds import body_of, drawing_title
from cam_workbench.generators.kinds.by_class import ByClass
from cam_workbench.generators.curves.approx import Path2D, curve_distance, fit_biarcs, fit_cubic, flatten, max_distance, polyline_path
from cam_workbench.generators.cam_design import CamDesign
from cam_workbench.generators.checks.claims import ProfileClaim, checks_verdict, pitch_text, profile_claim
from cam_workbench.generators.curves.nurbs import NurbsCurve

from .atomic import atomic_path

#: layer → (ACI colour, linetype, lineweight [1/100 mm]); -3 = default lineweight
LAYERS: dict[str, tuple[int, str, int]] = {
    "PROFILE": (7, "Continuous", 50),
    "PITCH": (1, "Continuous", 18),             # thin and red: LibreCAD leaves out dashed short arcs
    "BASE_CIRCLE": (8, "DASHED2", 18),
    "PRIME_CIRCLE": (5, "PHANTOM", 18),
    "BORE": (7, "Continuous", 50),
    "CENTERLINES": (4, "CENTER", 18),
    "DIMENSIONS": (3, "Continuous", 18),
    "TITLE": (7, "Continuous", 25),
    "PROFILE_OUTER": (7, "Continuous", 50),     # a groove's outer wall
    "OUTLINE": (7, "Continuous", 50),           # a groove cam's rim
    "HOLES": (7, "Continuous", 35),
    "HUB": (8, "DASHED", 25),                   # below the plate (hidden line)
    "TIMING_MARK": (6, "Continuous", 18),
    "PROFILE_2": (2, "Continuous", 50),         # a conjugate pair's second cam (below the first)
    "PITCH_2": (1, "Continuous", 18),           # its pitch curve (the second roller's centre)
    "SPACER": (8, "DASHED", 25),                # between the cams (hidden line)
}

_INSUNITS = {"mm": 4, "in": 1}
_DECIMALS = {"mm": 3, "in": 4}


@dataclass(frozen=True)
class CurveExport:
    """How one curve went into the file."""

    layer: str
    curves: str               # "cubic", "spline", "arcs" or "polyline"
    entities: int             # DXF entities written for it
    arcs: int                 # ARC entities (arcs mode)
    lines: int                # LINE entities or polyline segments
    max_error: float          # two-sided distance from the curve's NURBS; 0 for the spline itself
    min_arc_radius: float | None
    poles: int = 0            # the SPLINE's control points (cubic, spline)


@dataclass(frozen=True)
class DxfInfo:
    """What :func:`write_dxf` wrote (the ``drawing`` section of report.json)."""

    version: str
    units: str
    insunits: int | None
    curves: str
    chord_tolerance: float | None
    profile: CurveExport
    pitch: CurveExport
    text_height: float
    claim: ProfileClaim | None = None
    pitch_curve: str = ""
    others: tuple[CurveExport, ...] = ()      # the body's further curves (groove wall, second cam)

    @property
    def curve_exports(self) -> tuple[CurveExport, ...]:
        """Every curve drawn from a NURBS: the profile, the pitch curve, the body's others."""
        return (self.profile, self.pitch, *self.others)

    def summary(self) -> dict[str, Any]:
        """The ``drawing`` section of report.json.  ``exact`` is true only when the PROFILE
        entity is the exact curve (a SPLINE of the exact offset of a PH pitch curve, or of the
        PH pitch curve itself for a knife edge); ``profile_max_error`` is the written entities'
        distance from the profile NURBS (0 for that NURBS itself), ``max_error_by_layer`` the
        same for every curve drawn from a NURBS, ``profile_fit_error`` (fitted profiles only)
        the NURBS's measured distance from the exact curve it was fitted to."""
        p = self.profile
        c = self.claim
        extra: dict[str, Any] = {}
        if c is not None:
            extra["profile_curve"] = c.text
            if not c.exact:
                extra["profile_fit_error"] = c.fit_error
        if self.pitch_curve:
            extra["pitch_curve"] = self.pitch_curve
        by_layer: dict[str, float] = {}
        for e in self.curve_exports:
            by_layer[e.layer] = max(by_layer.get(e.layer, 0.0), e.max_error)
        return {
            "file_version": self.version,
            "insunits": self.insunits,
            "curves": self.curves,
            "chord_tolerance": self.chord_tolerance,
            "profile_entities": p.entities,
            "profile_arcs": p.arcs,
            "profile_lines": p.lines,
            "profile_poles": p.poles,
            "profile_max_error": p.max_error,
            "profile_min_arc_radius": p.min_arc_radius,
            "pitch_max_error": self.pitch.max_error,
            "max_error_by_layer": by_layer,
            "exact": self.curves == "spline" and (c is None or c.exact),
            **extra,
        }


def _fmt(v: float, units: str) -> str:
    d = _DECIMALS[units]
    text = f"{v:.{d}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def default_text_height(design: CamDesign) -> float:
    """Text and arrow height when ``drawing.text_height`` is not given: largest profile
    diameter / 36 (2 mm on a 72 mm cam), rounded to 2 significant digits."""
    r_max = design.max_profile_radius()[0]
    h = 2 * r_max / 36
    return float(f"{h:.2g}")


# ---- curves ----------------------------------------------------------------------------
def approximate(curve: NurbsCurve, curves: str, tol: float) -> Path2D:
    """The lines/arcs of ``curve`` for the "arcs" or "polyline" options (within ``tol``)."""
    if curves == "arcs":
        return fit_biarcs(curve, tol)
    if curves == "polyline":
        u, pts = flatten(curve, tol)
        return polyline_path(u, pts)
    raise ValueError(f"curves must be 'arcs' or 'polyline', got {curves!r}")


def add_nurbs_spline(msp: Any, curve: NurbsCurve, layer: str, closed_flag: bool = False) -> Any:
    """A SPLINE entity with exactly the degree, knots, control points and weights of ``curve``.

    Flags: planar, rational when the weights differ, closed only on request (the curve
    itself is closed when its first and last poles coincide: a clamped knot vector)."""
    sp = msp.add_spline(dxfattribs={"layer": layer})
    sp.dxf.degree = int(curve.degree)
    sp.control_points = [(float(x), float(y), 0.0) for x, y in curve.poles.tolist()]
    sp.knots = [float(k) for k in curve.knots.tolist()]
    flags = sp.PLANAR
    if curve.is_rational:
        sp.weights = [float(w) for w in curve.weights.tolist()]
        flags |= sp.RATIONAL
    if closed_flag:
        flags |= sp.CLOSED
    sp.dxf.flags = flags
    return sp


def add_path(msp: Any, path: Path2D, layer: str, curves: str, r12: bool, closed: bool = True
             ) -> tuple[int, int, int]:
    """Write a :class:`Path2D` as ARC/LINE entities ("arcs") or one polyline ("polyline",
    closed or open); returns (entities, arcs, lines)."""
    attribs = {"layer": layer}
    if curves == "polyline":
        z = path.start if closed else np.append(path.start, path.end[-1])
        pts = np.column_stack([z.real, z.imag]).tolist()
        if r12:
            msp.add_polyline2d(pts, close=closed, dxfattribs=attribs)
        else:
            msp.add_lwpolyline(pts, close=closed, dxfattribs=attribs)
        return 1, 0, path.n
    arcs = lines = 0
    is_arc = path.is_arc
    radius = path.radius
    for k in range(path.n):  # one DXF entity per element: entity creation is per element anyway
        a, b = path.start[k], path.end[k]
        if is_arc[k]:
            c = path.center[k]
            a0 = math.degrees(math.atan2((a - c).imag, (a - c).real))
            a1 = math.degrees(math.atan2((b - c).imag, (b - c).real))
            if not path.ccw[k]:  # DXF arcs run counter-clockwise from start to end angle
                a0, a1 = a1, a0
            msp.add_arc((float(c.real), float(c.imag)), float(radius[k]), a0, a1, dxfattribs=attribs)
            arcs += 1
        else:
            msp.add_line((float(a.real), float(a.imag)), (float(b.real), float(b.imag)), dxfattribs=attribs)
            lines += 1
    return arcs + lines, arcs, lines


def _export_curve(msp: Any, curve: NurbsCurve, layer: str, curves: str, tol: float,
                  r12: bool, closed_flag: bool) -> CurveExport:
    if curves == "spline":
        add_nurbs_spline(msp, curve, layer, closed_flag)
        return CurveExport(layer, curves, 1, 0, 0, 0.0, None, curve.n_poles)
    if curves == "cubic":
        cubic = fit_cubic(curve, tol)
        add_nurbs_spline(msp, cubic, layer, closed_flag)
        return CurveExport(layer, curves, 1, 0, 0, curve_distance(cubic, curve), None, cubic.n_poles)
    path = approximate(curve, curves, tol)
    n, arcs, lines = add_path(msp, path, layer, curves, r12)
    err = max_distance(path, curve)
    rmin = float(np.min(path.radius[path.is_arc])) if arcs else None
    return CurveExport(layer, curves, n, arcs, lines, err, rmin)


# ---- the drawing -----------------------------------------------------------------------
#: design class → ``fn(design, summary) -> (ezdxf document, info)``: its body's drawing (the plane
#: cams' :func:`build_dxf` here; a body's own in its module, imported by :mod:`cam_workbench.exporters`)
DRAWINGS: ByClass[Callable[..., tuple[Any, Any]]] = ByClass("the cam drawing")


def cam_drawing(design: Any, summary: dict[str, Any] | None = None) -> tuple[Any, Any]:
    """(ezdxf document, its info: ``.summary()`` is report.json's ``drawing``) of the cam's drawing
    by its body's function in :data:`DRAWINGS`, the title block quoting ``summary``; nothing written.

    Raises:
        NotAvailable: the design's body registers no drawing.
    """
    return DRAWINGS.of(design)(design, summary)


@DRAWINGS.register(CamDesign)
def build_dxf(design: CamDesign, summary: dict[str, Any] | None = None) -> tuple[Any, DxfInfo]:
    """The ezdxf document of the drawing and what went into it (nothing written yet).

    ``summary`` is ``design.summary()`` — the dict that becomes report.json — (computed
    when not given): the title block quotes its numbers and its checks verdict."""

    spec = design.spec
    dr = spec.drawing
    units = spec.units
    s = summary if summary is not None else design.summary()
    r12 = dr.dxf_version == "R12"
    doc = _new_document(dr.dxf_version, _INSUNITS[units])
    h = dr.text_height or default_text_height(design)
    doc.header["$LTSCALE"] = h
    doc.header["$LUPREC"] = _DECIMALS[units]
    for name, (color, linetype, lw) in LAYERS.items():
        layer = doc.layers.add(name, color=color, linetype=linetype)
        if not r12:
            layer.dxf.lineweight = lw
    msp = doc.modelspace()

    rr = spec.roller_radius
    rb = spec.cam.base_radius
    r_max, p_max, _ = design.max_profile_radius()
    tol = dr.chord_tolerance
    profile = _export_curve(msp, design.profile_ccw(), "PROFILE", dr.curves, tol, r12,
                            dr.spline_closed_flag)
    pitch_ccw = design.pitch_nurbs if design.pitch_nurbs.area() > 0 else design.pitch_nurbs.reversed()
    pitch = _export_curve(msp, pitch_ccw, "PITCH", dr.curves, tol, r12, False)
    r_base = s["profile"]["base_circle_radius"]          # report.json's: the profile at zero lift
    msp.add_circle((0, 0), r_base, dxfattribs={"layer": "BASE_CIRCLE"})
    if rr > 0:
        msp.add_circle((0, 0), rb, dxfattribs={"layer": "PRIME_CIRCLE"})
    r_bore = spec.cam.bore_diameter / 2
    body = design.body
    others: list[CurveExport] = []
    if body is None:
        if r_bore > 0:
            msp.add_circle((0, 0), r_bore, dxfattribs={"layer": "BORE"})
    else:
        others += _body_loops(msp, body, dr.curves, tol, r12, dr.spline_closed_flag)
        others += [_export_curve(msp, curve if curve.area() > 0 else curve.reversed(), layer, dr.curves, tol, r12,
                                 False) for layer, curve in body.extra.get("drawing_curves", {}).items()]
    info = DxfInfo(dr.dxf_version, units, None if r12 else _INSUNITS[units], dr.curves,
                   None if dr.curves == "spline" else tol, profile, pitch, h,
                   profile_claim(s, spec.is_roller, units), pitch_text(s), tuple(others))
    _centerlines(msp, design, _drawn_radius(design, r_max), h)
    if dr.dimensions:
        _dimensions(msp, design, r_max, p_max, r_base, h, units)
    if dr.title_block:
        _title_block(msp, design, s, info, extents(msp, r_max, h), h)
    try:
        from ezdxf import zoom  # deferred: ezdxf, loaded when a drawing is made

        zoom.extents(msp, factor=1.05)
    except Exception:  # noqa: BLE001 - the initial view is a convenience only
        pass
    return doc, info


#: body loop role → DXF layer (the profile itself is drawn above, with its claim)
_ROLE_LAYERS = {"bore": "BORE", "rim": "OUTLINE", "groove_outer": "PROFILE_OUTER", "hole": "HOLES",
                "hub": "HUB", "timing_mark": "TIMING_MARK", "profile_2": "PROFILE_2", "spacer": "SPACER"}


def _drawn_radius(design: CamDesign, r_max: float) -> float:
    """The largest radius of anything the body draws (the profile's, or a rim's, a second cam's)."""
    if design.body is None:
        return r_max
    return max([r_max] + [float(np.max(np.abs(loop.points(16)))) for loop in design.body.loops()])


def _body_loops(msp: Any, body: Any, curves: str, tol: float, r12: bool, closed_flag: bool
                ) -> list[CurveExport]:
    """The body's loops besides the profile: circles as CIRCLE, arcs as ARC, lines as LINE, NURBS
    (a groove's outer wall, a second cam's profile) as the profile is drawn; returns their exports."""
    seen: set[tuple] = set()
    out: list[CurveExport] = []
    for loop in body.loops():
        layer = _ROLE_LAYERS.get(loop.role)
        if layer is None:
            continue
        for piece in loop.pieces:
            att = {"layer": layer}
            if isinstance(piece, Arc):
                c = piece.centre
                key = ("arc", round(c.real, 9), round(c.imag, 9), round(piece.radius, 9), round(piece.a0, 9))
                if key in seen:
                    continue            # the bore of the plate and of the hub: drawn once
                seen.add(key)
                if abs(abs(piece.a1 - piece.a0) - 2 * np.pi) < 1e-12:
                    msp.add_circle((c.real, c.imag), piece.radius, dxfattribs=att)
                else:
                    a0, a1 = (piece.a0, piece.a1) if piece.a1 > piece.a0 else (piece.a1, piece.a0)
                    msp.add_arc((c.real, c.imag), piece.radius, math.degrees(a0), math.degrees(a1), dxfattribs=att)
            elif isinstance(piece, Line):
                key = ("line", round(piece.start.real, 9), round(piece.start.imag, 9), round(piece.end.real, 9),
                       round(piece.end.imag, 9))
                if key in seen:
                    continue
                seen.add(key)
                msp.add_line((piece.start.real, piece.start.imag), (piece.end.real, piece.end.imag), dxfattribs=att)
            elif isinstance(piece, Curve):
                out.append(_export_curve(msp, piece.nurbs, layer, curves, tol, r12, closed_flag))
    return out


def _new_document(version: str, insunits: int) -> Any:
    """A new ezdxf document with the standard linetypes, text and dimension styles.
    R12 files cannot carry $INSUNITS (the title block states the units instead)."""
    import ezdxf  # deferred: ezdxf, loaded when a drawing is made

    log = logging.getLogger("ezdxf")
    level = log.level
    if version == "R12":
        log.setLevel(logging.ERROR)  # ezdxf warns that R12 drops $INSUNITS: known, stated
    try:
        return ezdxf.new(version, setup=True, units=insunits)
    finally:
        log.setLevel(level)


def _centerlines(msp: Any, design: CamDesign, r_max: float, h: float) -> None:
    ext = r_max + 2.5 * h
    att = {"layer": "CENTERLINES"}
    msp.add_line((-ext, 0), (ext, 0), dxfattribs=att)
    msp.add_line((0, -ext), (0, ext), dxfattribs=att)
    # the follower where the program starts (θ = 0): where the drawing's angles begin — its axis
    # (translating) or its arm and pivot (oscillating), drawn from the follower's own sketch
    fol = design.follower
    k0 = design.program.evaluate(np.array([0.0]))
    sk = fol.sketch(0.0, k0, ext + 2 * h - abs(fol.sketch(0.0, k0, 1.0).point))
    sense = "CCW" if design.spec.cam.direction == "ccw" else "CW"
    for a, b, role in sk.segments:
        msp.add_line((a.real, a.imag), (b.real, b.imag), dxfattribs=att)
    if sk.pivot is not None:
        msp.add_circle((sk.pivot.real, sk.pivot.imag), 0.5 * h, dxfattribs=att)
        _text(msp, f"PIVOT, FOLLOWER AT 0°, CAM TURNS {sense}", (sk.pivot.real + 0.8 * h, sk.pivot.imag), 0.7 * h,
              "CENTERLINES")
    else:
        top = max((b for _, b, role in sk.segments if role == "stem"), key=lambda z: z.imag, default=sk.point)
        _text(msp, f"FOLLOWER AXIS AT 0°, CAM TURNS {sense}", (top.real + 0.4 * h, top.imag - 0.8 * h), 0.7 * h,
              "CENTERLINES")


def _dim_override(h: float, units: str) -> dict[str, Any]:
    return {"dimtxt": h, "dimasz": h, "dimgap": 0.3 * h, "dimexe": 0.5 * h, "dimexo": 0.5 * h,
            "dimdec": _DECIMALS[units], "dimzin": 8, "dimtxsty": "Standard", "dimclrd": 3,
            "dimclre": 3, "dimclrt": 3, "dimlfac": 1.0, "dimtih": 1, "dimtoh": 1}


#: the drawing's dimension style: readers that draw DIMENSION entities themselves (LibreCAD) take
#: the style's table entry and the header, not ezdxf's per-entity overrides
DIMSTYLE = "CAM"


def _dimstyle(doc: Any, h: float, units: str) -> None:
    """The :data:`DIMSTYLE` table entry holding :func:`_dim_override`'s values, made current."""
    ds = doc.dimstyles.new(DIMSTYLE)
    for k, v in _dim_override(h, units).items():
        if k != "dimtxsty" and ds.dxf.is_supported(k):
            ds.dxf.set(k, v)
    doc.header["$DIMSTYLE"] = DIMSTYLE
    for k in ("dimtxt", "dimasz", "dimgap", "dimexe", "dimexo", "dimlfac"):
        doc.header[f"${k.upper()}"] = ds.dxf.get(k)


def _dimensions(msp: Any, design: CamDesign, r_max: float, p_max: complex, r_base: float, h: float,
                units: str) -> None:
    spec = design.spec
    _dimstyle(msp.doc, h, units)
    att = {"layer": "DIMENSIONS", "dimstyle": DIMSTYLE}
    ov = _dim_override(h, units)
    max_ang = math.degrees(math.atan2(p_max.imag, p_max.real))
    # base circle: dimensioned where the profile lies on it (lowest point of the profile)
    _, pts = design.profile.sample(32)
    k = int(np.argmin(np.hypot(pts[:, 0], pts[:, 1])))
    base_ang = math.degrees(math.atan2(pts[k, 1], pts[k, 0]))
    r_bore = spec.cam.bore_diameter / 2
    if r_bore > 0:
        ang = base_ang + 135.0
        loc = (1.6 * r_bore + 3 * h) * np.exp(1j * math.radians(ang))
        msp.add_diameter_dim((0, 0), radius=r_bore, angle=ang, location=(loc.real, loc.imag),
                             dimstyle=DIMSTYLE, override=ov, dxfattribs=att).render()
    loc = (r_base + 4 * h) * np.exp(1j * math.radians(base_ang))
    msp.add_radius_dim((0, 0), radius=r_base, angle=base_ang, location=(loc.real, loc.imag),
                       text="<> BASE CIRCLE", dimstyle=DIMSTYLE, override=ov, dxfattribs=att).render()
    loc = (r_max + 4 * h) * np.exp(1j * math.radians(max_ang))
    msp.add_radius_dim((0, 0), radius=r_max, location=(loc.real, loc.imag),
                       text="<> MAX", dimstyle=DIMSTYLE, override=ov, dxfattribs=att).render()
    u = spec.units
    note = [f"THICKNESS {_fmt(spec.cam.thickness, u)} {u}",
            f"PRIME CIRCLE R{_fmt(spec.cam.base_radius, u)} (ROLLER CENTRE AT ZERO LIFT)"
            if spec.roller_radius > 0 else
            ("FLAT-FACED FOLLOWER: PROFILE = CURVE THROUGH THE CONTACT POINTS"
             if design.follower.design_curve == "profile" else "KNIFE-EDGE FOLLOWER: PROFILE = PITCH CURVE")]
    for i, line in enumerate(note):
        _text(msp, line, (-r_max - 2.5 * h, -r_max - (6.0 + 1.6 * i) * h), h, "DIMENSIONS")


#: characters some CAD font draws wider than the text height (LibreCAD 2.2's standard font: "_"
#: 1.56 h, "W" and "%" 1.22 h; ezdxf's font metrics: "m" 1.24 h, "W" 1.26 h, "—" and "…" 1.28 h)
_WIDE_ADVANCE = {"_": 1.6, **dict.fromkeys("MWmw%@#Ø—…", 1.35)}


def text_width(text: str, height: float) -> float:
    """An upper bound of the drawn width of a one-line TEXT of the Standard style [drawing units]:
    each character's advance taken as the text height (:data:`_WIDE_ADVANCE` for the wider ones).
    Readers substitute their own fonts for it — LibreCAD 2.2 draws texts up to 17 % wider than
    ezdxf measures them, its advances 0.33 h to 1.56 h —; tests/test_dxf_librecad.py holds the
    drawn texts of every example in both against their cells."""
    return height * (len(text) + sum(_WIDE_ADVANCE.get(c, 1.0) - 1.0 for c in text))


def _text(msp: Any, text: str, at: tuple[float, float], height: float, layer: str) -> Any:
    # continuous whatever the layer's linetype: LibreCAD dashes the strokes of a text on a dashed layer
    t = msp.add_text(text, height=height, dxfattribs={"layer": layer, "style": "Standard",
                                                      "linetype": "Continuous"})
    t.set_placement(at)
    return t


def _motion_rows(design: CamDesign) -> list[list[str]]:
    u = design.spec.units
    rows = []
    start = 0.0
    for i, seg in enumerate(design.spec.motion):
        end = start + seg.angle
        rows.append([str(i), seg.kind.upper(), f"{start:g}", f"{end:g}",
                     _fmt(seg.lift, u) if seg.lift is not None else "-",
                     (seg.law or "-").upper()])
        start = end
    return rows


#: what the profile NURBS is, by :class:`ProfileClaim` kind (the title block's PROFILE row)
_CLAIM_WORDS = {"ph_offset": "EXACT OFFSET OF THE PH PITCH CURVE", "ph_pitch": "THE PH PITCH CURVE, EXACT",
                "bspline_offset_fit": "FITTED OFFSET, NOT EXACT",
                "bspline_pitch": "THE FITTED PITCH B-SPLINE, NOT EXACT",
                "ph_contact": "PH CURVE THROUGH THE FACE'S CONTACT POINTS, NOT EXACT",
                "bspline_contact": "B-SPLINE FITTED TO THE FACE'S CONTACT POINTS, NOT EXACT"}


def title_line(spec: Any) -> str:
    """The title block's title: :func:`~cam_workbench.generators.kinds.drawing_title` in capitals, followed by
    the body's name when a title given in the spec does not say it ("FEED CAM (GROOVE CAM)"): a
    drawing always names what is to be made."""
    title = drawing_title(spec).upper()
    body = body_of(spec).title.upper()
    return title if body in title else f"{title} ({body})"


def drawn_text(e: CurveExport) -> str:
    """How a curve went into the file, in the title block's words."""
    if e.curves == "spline":
        return "SPLINE: THE NURBS ITSELF (ITS KNOTS, POLES, WEIGHTS)"
    if e.curves == "cubic":
        return f"POLYNOMIAL CUBIC SPLINE, {e.poles} POLES"
    if e.curves == "arcs":
        return f"{e.arcs} ARCS" + (f" + {e.lines} LINES" if e.lines else "")
    return f"CLOSED POLYLINE OF {e.lines} LINES"


def _drawing_rows(info: DxfInfo, claim: ProfileClaim, u: str, tol: float) -> list[tuple[str, str]]:
    """How the profile and the other curves are drawn, and their measured distance from the
    NURBS they stand for ("exact" only where that NURBS is)."""
    p = info.profile
    rows = [("DRAWN AS (LAYER PROFILE)", drawn_text(p))]
    if p.curves == "spline":
        return rows
    ref = "THE EXACT PROFILE" if claim.exact else "THE PROFILE NURBS"
    rows.append(("DRAWN PROFILE ERROR", f"MAX {p.max_error:.2e} {u} FROM {ref} (TOL. {tol:g})"))
    rest = (info.pitch, *info.others)
    rows.append(("OTHER CURVES, DRAWN ALIKE", f"{', '.join(e.layer for e in rest)}: MAX "
                                              f"{max(e.max_error for e in rest):.2e} {u}"))
    return rows


def title_rows(design: CamDesign, summary: dict[str, Any], info: DxfInfo) -> list[tuple[str, str]]:
    """(label, value) rows of the title block (also used by tests): the cam's parameters, how
    its curves are drawn, and the numbers and checks verdict of ``summary`` (the dict that
    becomes report.json)."""
    spec = design.spec
    dr = spec.drawing
    u = spec.units
    f = lambda v: _fmt(v, u)  # noqa: E731
    follower = str(summary["follower"]["label"]).upper()
    lift_u = summary["motion"]["lift_unit"]
    claim = profile_claim(summary, spec.is_roller, u)
    prof = summary["profile"]
    pa = summary["pressure_angle"]
    cv = summary["curvature"]
    pt = summary["pitch"]
    checks = summary.get("checks")
    second = _second_cam_rows(summary, u, f)
    pa_limit = ""
    if isinstance(checks, dict) and isinstance(checks.get("results"), dict) and "pressure_angle" in checks["results"]:
        lim = checks["results"]["pressure_angle"].get("limit")
        pa_limit = "" if lim is None else f" (LIMIT {lim:g}°)"
    rows = [
        ("PART NO.", dr.part_number or "-"),
        ("MATERIAL", dr.material or "-"),
        ("THICKNESS", f"{f(spec.cam.thickness)} {u}"),
        ("UNITS / SCALE", f"{u} / 1:1"),
        ("DRAWN BY", dr.author or "-"),
        ("FOLLOWER", follower),
        ("BASE RADIUS R_b", f"{f(spec.cam.base_radius)} (BASE CIRCLE R{f(prof['base_circle_radius'])})"),
        ("BORE", f"Ø{f(spec.cam.bore_diameter)}" if spec.cam.bore_diameter > 0 else "NONE"),
        ("ROTATION", f"{spec.cam.direction.upper()}, {spec.cam.speed_rpm:g} RPM"),
        ("PITCH CURVE", pitch_text(summary).upper().replace("²", "2")),
        ("PROFILE", ("FIRST CAM: " if second else "") + _CLAIM_WORDS[claim.kind]),
        ("PROFILE NURBS", f"{'RATIONAL ' if prof['rational'] else ''}B-SPLINE, DEGREE {prof['degree']}, "
                          f"{prof['poles']} POLES"),
    ]
    if not claim.exact:
        rows.append(("PROFILE FIT ERROR", f"{claim.fit_error:.3e} {u} FROM THE EXACT "
                     + {"bspline_offset_fit": "OFFSET OF THE FITTED PITCH B-SPLINE",
                        "bspline_pitch": "DESIGN PITCH CURVE"}.get(claim.kind, "ENVELOPE OF THE FACE")))
    rows += _drawing_rows(info, claim, u, dr.chord_tolerance)
    rows += [
        ("PROFILE MAX ERROR", f"{prof['max_error']:.3e} {u} FROM THE DESIGN-INTENT PROFILE"),
        ("MAX FOLLOWER DEVIATION", f"{pt['max_deviation']:.3e} {'DEG' if lift_u == 'deg' else lift_u} AT {pt['max_deviation_at_deg']:.2f}°"),
        ("MAX PRESSURE ANGLE", f"{pa['max_deg']:.2f}° AT {pa['at_deg']:.2f}°{pa_limit}"),
        ("MIN PROFILE RADIUS OF CURV.", f"{f(cv['min_profile_radius'])} AT {cv['at_deg']:.2f}°"),
        ("LARGEST RADIUS", f"{f(prof['max_radius'])}"),
        ("AREA / VOLUME", f"{summary['area']:.6g} {u}2 / {summary['volume']:.6g} {u}3"),
    ]
    rows += second
    if isinstance(checks, dict) and "passed" in checks:
        rows.append(("DESIGN CHECKS", checks_cell(checks)))
    rows += [
        ("SPEC DIGEST (SHA-256)", str(summary.get("spec_digest", "-"))),
        ("SOFTWARE", f"cam_workbench {__version__}"),
    ]
    return rows


def _second_cam_rows(summary: dict[str, Any], u: str, f: Any) -> list[tuple[str, str]]:
    """A conjugate pair's rows: where the second cam is, its roller, profile and pressure angle,
    and the distance error between the rollers (report.json ``body``)."""
    body = summary.get("body")
    second = body.get("second_cam") if isinstance(body, dict) else None
    if not isinstance(second, dict):
        return []
    z0, z1 = second["z"]
    err = body["roller_distance_error"]
    lu = "DEG" if err["lift_unit"] == "deg" else u
    pa = second["pressure_angle"]
    return [
        ("SECOND CAM (LAYER PROFILE_2)", f"Z {f(z0)} TO {f(z1)}: {str(second['follower']['label']).upper()}"),
        ("SECOND CAM PROFILE", "EXACT OFFSET OF ITS PH PITCH CURVE"),
        ("SECOND CAM MAX ERROR", f"{second['profile']['max_error']:.3e} {u} FROM ITS DESIGN-INTENT PROFILE"),
        ("SECOND CAM LARGEST RADIUS", f(second['profile']['max_radius'])),
        ("SECOND CAM PRESSURE ANGLE", f"{pa['max_deg']:.2f}° AT {pa['at_deg']:.2f}°"),
        ("ROLLER DISTANCE ERROR", f"{err['max']:.3e} {u} AT {err['at_deg']:.2f}° (PH DEVIATIONS "
                                  f"{err['first_cam_deviation']:.2e} + {err['second_cam_deviation']:.2e} {lu})"),
    ]


def checks_cell(checks: dict[str, Any]) -> str:
    """checks.passed / checks.failed of the summary (failed names verbatim)."""
    if checks["passed"]:
        return checks_verdict(checks).removeprefix("design checks: ").upper()
    return "FAILED: " + ", ".join(str(n) for n in checks.get("failed") or [])


MOTION_HEADER = ["#", "KIND", "FROM °", "TO °", "LIFT", "LAW"]


@dataclass(frozen=True)
class Box:
    """An axis-aligned box [drawing units]."""

    x0: float
    y0: float
    x1: float
    y1: float


def extents(msp: Any, r_max: float, h: float) -> Box:
    """Extents of everything drawn so far, dimension blocks (their texts) included
    (``ezdxf.bbox`` renders DIMENSION and TEXT/MTEXT entities to measure them), each TEXT
    widened to :func:`text_width` (another reader's font may draw it wider); the circle of
    radius ``r_max`` when ezdxf cannot measure."""
    try:
        from ezdxf import bbox  # deferred: ezdxf, loaded when a drawing is made

        box = bbox.extents(msp, fast=False)
        if box.has_data:
            x1 = max([box.extmax.x] + [t.dxf.insert.x + text_width(t.dxf.text, t.dxf.height)
                                       for t in msp.query("TEXT")])
            return Box(box.extmin.x, box.extmin.y, x1, box.extmax.y)
    except Exception:  # noqa: BLE001 - fall back to the cam's own size
        pass
    return Box(-r_max - 2 * h, -r_max - 2 * h, r_max + 2 * h, r_max + 2 * h)


#: text heights of the title block [× the drawing's text height] and its margins
_TITLE_H, _CELL_H, _ROW_H, _PAD = 1.4, 0.8, 1.8, 0.5


def _title_block(msp: Any, design: CamDesign, summary: dict[str, Any], info: DxfInfo,
                 drawn: Box, h: float) -> Box:
    """The title block right of ``drawn`` (the extents of everything else, dimension texts
    included, so nothing overlaps it): the drawing's title (the body's name), the rows of
    :func:`title_rows` and the motion table, every column as wide as :func:`text_width` bounds
    its texts plus a margin each side; then the sheet border round both.  Returns the title
    block's box."""
    att = {"layer": "TITLE"}
    rows = title_rows(design, summary, info)
    th = _CELL_H * h
    x0 = drawn.x1 + 3 * h
    top = drawn.y1
    row_h = _ROW_H * h
    title = title_line(design.spec)
    caption = "MOTION PROGRAM (ANGLES IN CAM DEGREES FROM THE START)"
    header = [("LIFT °" if c == "LIFT" and design.follower.lift_unit == "angle" else c) for c in MOTION_HEADER]
    table = [header, *_motion_rows(design)]
    x1 = x0 + max(text_width(label, th) for label, _ in rows) + 2 * _PAD * h
    widths = np.array([max(text_width(cells[k], th) for cells in table) for k in range(len(header))]) + 2 * _PAD * h
    x2 = max(x1 + max(text_width(value, th) for _, value in rows) + 2 * _PAD * h,
             x0 + float(np.sum(widths)), x0 + text_width(title, _TITLE_H * h) + 2 * _PAD * h,
             x0 + text_width(caption, th) + 2 * _PAD * h)
    widths[-1] += x2 - x0 - float(np.sum(widths))        # the last column takes the slack
    _text(msp, title, (x0 + _PAD * h, top - 1.9 * h), _TITLE_H * h, "TITLE")
    y = top - 2.6 * h
    msp.add_line((x0, y), (x2, y), dxfattribs=att)
    for label, value in rows:
        _text(msp, label, (x0 + _PAD * h, y - 1.35 * h), th, "TITLE")
        _text(msp, value, (x1 + _PAD * h, y - 1.35 * h), th, "TITLE")
        y -= row_h
        msp.add_line((x0, y), (x2, y), dxfattribs=att)
    msp.add_line((x1, top - 2.6 * h), (x1, y), dxfattribs=att)
    # motion table
    y -= 0.8 * h
    _text(msp, caption, (x0 + _PAD * h, y - 1.35 * h), th, "TITLE")
    y -= row_h
    msp.add_line((x0, y), (x2, y), dxfattribs=att)
    xs = x0 + np.concatenate([[0.0], np.cumsum(widths)])
    table_top = y
    for cells in table:
        for x, cell in zip(xs, cells):
            _text(msp, cell, (float(x) + _PAD * h, y - 1.35 * h), th, "TITLE")
        y -= row_h
        msp.add_line((x0, y), (x2, y), dxfattribs=att)
    for x in xs[1:-1]:
        msp.add_line((float(x), table_top), (float(x), y), dxfattribs=att)
    # outer border of the title block and of the sheet
    for a, b in (((x0, top), (x2, top)), ((x0, top), (x0, y)), ((x2, top), (x2, y))):
        msp.add_line(a, b, dxfattribs=att)
    left, right = drawn.x0 - 2 * h, x2 + 2 * h
    bottom = min(y, drawn.y0) - 2 * h
    upper = max(top, drawn.y1) + 2 * h
    add_closed_outline(msp, [(left, bottom), (right, bottom), (right, upper), (left, upper)], att)
    return Box(x0, y, x2, top)


def add_closed_outline(msp: Any, points: list[tuple[float, float]], att: dict[str, Any]) -> None:
    """A closed outline: LWPOLYLINE, or POLYLINE in R12 (which has no LWPOLYLINE)."""
    if msp.doc.dxfversion == "AC1009":
        msp.add_polyline2d(points, close=True, dxfattribs=att)
    else:
        msp.add_lwpolyline(points, close=True, dxfattribs=att)


# ---- writing ---------------------------------------------------------------------------
def write_dxf(design: CamDesign, path: str | os.PathLike[str], summary: dict[str, Any] | None = None
              ) -> DxfInfo:
    """Write the drawing to ``path`` (not atomic: use :func:`export_dxf` or an OutputSet)."""
    doc, info = build_dxf(design, summary)
    doc.saveas(str(path))
    return info


def export_dxf(design: CamDesign, path: str | os.PathLike[str], summary: dict[str, Any] | None = None
               ) -> DxfInfo:
    """Write the drawing to ``path`` atomically (temporary file, then rename)."""
    with atomic_path(path) as tmp:
        info = write_dxf(design, tmp, summary)
    return info


def read_profile_path(path: str | os.PathLike[str], layer: str = "PROFILE") -> Path2D:
    """The ARC/LINE/polyline entities of a layer as one head-to-tail :class:`Path2D` (for
    checking spline-less drawings against the exact profile)."""
    import ezdxf  # deferred: ezdxf, loaded when a drawing is made

    doc = ezdxf.readfile(str(path))
    starts, ends, centers, ccws = [], [], [], []
    for e in doc.modelspace().query(f'*[layer=="{layer}"]'):
        kind = e.dxftype()
        if kind in ("LWPOLYLINE", "POLYLINE"):
            pts = [complex(p[0], p[1]) for p in (e.get_points("xy") if kind == "LWPOLYLINE"
                                                  else [v.dxf.location for v in e.vertices])]
            if (e.closed if kind == "LWPOLYLINE" else e.is_closed):
                pts.append(pts[0])
            for a, b in zip(pts[:-1], pts[1:]):
                starts.append(a), ends.append(b), centers.append(complex(np.nan, np.nan)), ccws.append(False)
        elif kind == "LINE":
            starts.append(complex(e.dxf.start.x, e.dxf.start.y))
            ends.append(complex(e.dxf.end.x, e.dxf.end.y))
            centers.append(complex(np.nan, np.nan))
            ccws.append(False)
        elif kind == "ARC":
            c = complex(e.dxf.center.x, e.dxf.center.y)
            r = e.dxf.radius
            starts.append(c + r * np.exp(1j * math.radians(e.dxf.start_angle)))
            ends.append(c + r * np.exp(1j * math.radians(e.dxf.end_angle)))
            centers.append(c)
            ccws.append(True)
    return _chain(np.array(starts), np.array(ends), np.array(centers), np.array(ccws, bool))


def _chain(start: np.ndarray, end: np.ndarray, center: np.ndarray, ccw: np.ndarray) -> Path2D:
    """Order elements head to tail (DXF arcs always run counter-clockwise, so an arc that the
    path traverses clockwise is read backwards and is turned round here)."""
    n = len(start)
    order, flip = [0], [False]
    used = np.zeros(n, bool)
    used[0] = True
    tip = end[0]
    for _ in range(n - 1):
        d_start = np.where(used, np.inf, np.abs(start - tip))
        d_end = np.where(used, np.inf, np.abs(end - tip))
        i, j = int(np.argmin(d_start)), int(np.argmin(d_end))
        k, rev = (i, False) if d_start[i] <= d_end[j] else (j, True)
        used[k] = True
        order.append(k)
        flip.append(rev)
        tip = start[k] if rev else end[k]
    idx = np.array(order)
    f = np.array(flip)
    s0, e0 = start[idx], end[idx]
    arc = ~np.isnan(center[idx].real)
    z = np.zeros(n)
    return Path2D(np.where(f, e0, s0), np.where(f, s0, e0), center[idx], np.where(f & arc, ~ccw[idx], ccw[idx]), z, z)


__all__ = ["DxfInfo", "CurveExport", "LAYERS", "build_dxf", "write_dxf", "export_dxf", "add_nurbs_spline",
           "approximate", "read_profile_path", "title_rows", "default_text_height", "drawn_text", "text_width", "title_line",
           "add_closed_outline"]

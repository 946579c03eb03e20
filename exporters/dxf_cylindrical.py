"""DXF drawing of a cylindrical (barrel) cam (ezdxf): three views, 1:1 in the spec's units.

* **Developed view** (the drawing's x = ρ·ψ, y = z: mm along the circumference at radius ρ, ψ the
  cam-frame polar angle unwrapped as ψ = φ(θ) = π/2 − δθ over one turn; z along the cam axis):
  the groove walls developed at the outer radius R_o — the offsets by ±w/2 of the developed centre
  line C_ρ(θ) = (ρ·φ(θ), z₀ + s(θ)) along its normal (δs′, ρ)/√(ρ² + s′²) (layers ``WALL_LOWER``,
  ``WALL_UPPER``) — and the pitch line C_{R_p} at the pitch radius (``PITCH``); the cylinder's
  developed outline at R_o (``OUTLINE``: z = 0, z = L and the seam lines).  These curves are not
  polynomial in general (the offsets divide by √(ρ² + s′²); the laws need not be polynomial), so
  each is a cubic SPLINE per motion segment interpolating exact points (not-a-knot, parameter θ);
  its error is MEASURED: the largest |spline(θ) − curve(θ)| at the midpoints between the nodes and
  at 8 points per span of a second check, an upper bound on the distance from the exact curve
  (report.json ``drawing.developed_fit_error``, the title block and ``cam-workbench dxf``'s output).
* **End view** (right of it, centred at the cam axis): the outer circle (``OUTLINE``), the bore
  (``BORE``) and the groove's bottom circle, dashed (``GROOVE_BOTTOM``), with centre lines.
* **Side view** (between the two, on the developed view's z rows): the outline, length × diameter
  (``OUTLINE``), the bore as hidden lines (``BORE_HIDDEN``) and the axis (``CENTERLINES``).

A title block (``TITLE``) names the body (:func:`cam_workbench.exporters.dxf.title_line`) and quotes
report.json's numbers.  The walls have no exact NURBS form: ``drawing.curves`` = "cubic" (the
default) and "spline" both write the cubic SPLINEs, refined until their measured error is within a
quarter of ``drawing.chord_tolerance``; "arcs" and "polyline" write biarcs (ARC/LINE) or a polyline
per curve within the rest of the tolerance of those splines, their distance from the exact curves
bounded by the sum of the two measured errors.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from cam_workbench.generators import __version__
from cam_workbench.generators.bodies.cylindrical import CylindricalDesign
from cam_workbench.generators.curves.approx import max_distance
from cam_workbench.generators.curves.nurbs import NurbsCurve

from .dxf import (DRAWINGS, _DECIMALS, _INSUNITS, LAYERS, _fmt, _new_document, _text, add_closed_outline, add_path,
                  approximate, text_width, title_line)

#: layer → (ACI colour, linetype, lineweight [1/100 mm]), in the plate drawing's style
CYL_LAYERS: dict[str, tuple[int, str, int]] = {
    "WALL_LOWER": LAYERS["PROFILE"],
    "WALL_UPPER": LAYERS["PROFILE_OUTER"],
    "PITCH": LAYERS["PITCH"],
    "OUTLINE": LAYERS["OUTLINE"],
    "BORE": LAYERS["BORE"],
    "BORE_HIDDEN": (8, "DASHED", 25),
    "GROOVE_BOTTOM": (8, "DASHED", 25),
    "CENTERLINES": LAYERS["CENTERLINES"],
    "TITLE": LAYERS["TITLE"],
}

#: cubic spline nodes per radian of cam angle (at least 8 per motion segment), doubled on a curve
#: until its measured error is within a quarter of drawing.chord_tolerance
NODES_PER_RAD = 120.0
DEGREE = 3


@dataclass(frozen=True)
class DevelopedCurve:
    """One developed curve of one motion segment as a clamped B-spline in the developed plane."""

    layer: str
    segment: int
    knots: np.ndarray           # full knot vector, parameter θ [rad]
    poles: np.ndarray           # (n, 2) developed (x, z)
    fit_error: float            # max |spline(θ) − exact(θ)| off the nodes [spec length unit]

    @property
    def nurbs(self) -> NurbsCurve:
        """The spline as a (polynomial) :class:`NurbsCurve`."""
        return NurbsCurve(DEGREE, self.knots, self.poles, np.ones(len(self.poles)))


def developed_curves(design: Any) -> tuple[DevelopedCurve, ...]:
    """The lower and upper walls at R_o and the pitch line at R_p, one cubic spline per motion
    segment each, with their measured fit errors (nodes doubled while an error exceeds a quarter of
    ``drawing.chord_tolerance``)."""
    lay = design.layout
    prog = design.program
    bounds = prog.boundaries
    goal = design.spec.drawing.chord_tolerance / 4
    out = []
    for layer, rho, side in (("WALL_LOWER", lay.outer_radius, -1), ("WALL_UPPER", lay.outer_radius, 1),
                             ("PITCH", lay.pitch_radius, 0)):
        for seg in range(len(prog.starts)):
            a, b = float(bounds[seg]), float(bounds[seg + 1])
            n = max(8, int(np.ceil((b - a) * NODES_PER_RAD)) + 1)
            curve = _segment_spline(design, layer, rho, side, seg, a, b, n)
            while curve.fit_error > goal and n < 2**16:
                n = 2 * n - 1
                curve = _segment_spline(design, layer, rho, side, seg, a, b, n)
            out.append(curve)
    return tuple(out)


def _segment_spline(design: Any, layer: str, rho: float, side: int, seg: int, a: float, b: float, n: int
                    ) -> DevelopedCurve:
    """The not-a-knot cubic through ``n`` exact points of one motion segment, its error measured off
    the nodes: at the span midpoints and 8 points inside every span."""
    from scipy.interpolate import make_interp_spline  # deferred: scipy.interpolate, a cylindrical cam's drawing alone

    th = np.linspace(a, b, n)
    sp = make_interp_spline(th, design.developed_points(rho, side, th, np.full(n, seg)), k=DEGREE)
    fr = np.linspace(0, 1, 10)[1:-1]
    tt = np.concatenate([(th[:-1] + th[1:]) / 2, (th[:-1, None] + fr[None, :] * np.diff(th)[:, None]).ravel()])
    err = float(np.max(np.hypot(*(sp(tt) - design.developed_points(rho, side, tt, np.full(tt.size, seg))).T)))
    return DevelopedCurve(layer, seg, np.asarray(sp.t), np.asarray(sp.c), err)


@dataclass(frozen=True)
class DrawnCurve:
    """How one developed curve went into the file."""

    curve: DevelopedCurve
    entities: int
    approx_error: float          # the arcs'/polyline's distance from the spline (0: the spline itself)

    @property
    def error(self) -> float:
        """Upper bound of the drawn entities' distance from the exact curve (triangle inequality)."""
        return self.curve.fit_error + self.approx_error


@dataclass(frozen=True)
class CylDxfInfo:
    """What the drawing holds (report.json's ``drawing`` section)."""

    version: str
    units: str
    curves_mode: str                       # "cubic", "arcs" or "polyline" (what was written)
    chord_tolerance: float
    drawn: tuple[DrawnCurve, ...]
    developed_offset_x: float

    @property
    def curves(self) -> tuple[DevelopedCurve, ...]:
        """The cubic splines of the developed curves (drawn as they are, or approximated)."""
        return tuple(d.curve for d in self.drawn)

    def summary(self) -> dict[str, Any]:
        walls = [d.error for d in self.drawn if d.curve.layer.startswith("WALL")]
        pitch = [d.error for d in self.drawn if d.curve.layer == "PITCH"]
        how = (f"cubic SPLINE per motion segment through exact points every {1 / NODES_PER_RAD:.4g} rad of cam "
               "angle or closer: max |spline(θ) − curve(θ)| off the nodes (an upper bound on the distance from the "
               "exact curve)")
        if self.curves_mode != "cubic":
            how += (f", plus the measured two-sided distance of the {self.curves_mode} from that spline (the sum "
                    "bounds their distance from the exact curve)")
        return {
            "written": True, "file_version": self.version,
            "insunits": None if self.version == "R12" else _INSUNITS[self.units],
            "curves": self.curves_mode, "chord_tolerance": self.chord_tolerance, "exact": False,
            "views": ["developed (x = ρ·ψ at R_o for the walls, at R_p for the pitch line; y = z)",
                      "end (outer circle, bore, groove bottom dashed)", "side (length × diameter)"],
            "developed_fit_error": {"value": max(walls), "pitch_line": max(pitch), "unit": self.units, "what": how},
            "splines": len(self.drawn) if self.curves_mode == "cubic" else 0,
            "entities": sum(d.entities for d in self.drawn),
        }


@DRAWINGS.register(CylindricalDesign)
def build_cylindrical_dxf(design: Any, summary: dict[str, Any] | None = None) -> tuple[Any, CylDxfInfo]:
    """The ezdxf document of a cylindrical cam's drawing and what went into it (nothing written)."""
    spec = design.spec
    dr = spec.drawing
    units = spec.units
    s = summary if summary is not None else design.summary()
    lay = design.layout
    r12 = dr.dxf_version == "R12"
    mode = "cubic" if dr.curves in ("cubic", "spline") else dr.curves
    doc = _new_document(dr.dxf_version, _INSUNITS[units])
    h = dr.text_height or max(lay.outer_radius / 20, 0.5 if units == "mm" else 0.02)
    doc.header["$LTSCALE"] = h
    doc.header["$LUPREC"] = _DECIMALS[units]
    for name, (color, linetype, lw) in CYL_LAYERS.items():
        layer = doc.layers.add(name, color=color, linetype=linetype)
        if not r12:
            layer.dxf.lineweight = lw
    msp = doc.modelspace()
    drawn = []
    for c in developed_curves(design):
        if mode == "cubic":
            sp = msp.add_spline(dxfattribs={"layer": c.layer})
            sp.dxf.degree = DEGREE
            sp.control_points = [(float(x), float(y), 0.0) for x, y in c.poles.tolist()]
            sp.knots = [float(k) for k in c.knots.tolist()]
            sp.dxf.flags = sp.PLANAR
            drawn.append(DrawnCurve(c, 1, 0.0))
        else:
            path = approximate(c.nurbs, mode, dr.chord_tolerance - c.fit_error)
            n, _, _ = add_path(msp, path, c.layer, mode, r12, closed=False)
            drawn.append(DrawnCurve(c, n, max_distance(path, c.nurbs)))
    ro, rb, length = lay.outer_radius, lay.bottom_radius, lay.length
    x_a, x_b = sorted((ro * float(lay.phi(0.0)), ro * float(lay.phi(2 * np.pi))))
    att = {"layer": "OUTLINE"}
    for a, b in (((x_a, 0.0), (x_b, 0.0)), ((x_a, length), (x_b, length)), ((x_a, 0.0), (x_a, length)),
                 ((x_b, 0.0), (x_b, length))):
        msp.add_line(a, b, dxfattribs=att)
    # side view: the cylinder's axis vertical (z rows shared with the developed view)
    gap = 4 * h
    xs = x_b + gap + ro
    add_closed_outline(msp, [(xs - ro, 0.0), (xs + ro, 0.0), (xs + ro, length), (xs - ro, length)], att)
    rbore = lay.bore_radius
    if rbore > 0:
        for x in (xs - rbore, xs + rbore):
            msp.add_line((x, 0.0), (x, length), dxfattribs={"layer": "BORE_HIDDEN"})
    msp.add_line((xs, -h), (xs, length + h), dxfattribs={"layer": "CENTERLINES"})
    # end view: the cam seen along its axis
    xe, ye = xs + ro + gap + ro, length / 2
    msp.add_circle((xe, ye), ro, dxfattribs=att)
    msp.add_circle((xe, ye), rb, dxfattribs={"layer": "GROOVE_BOTTOM"})
    if rbore > 0:
        msp.add_circle((xe, ye), rbore, dxfattribs={"layer": "BORE"})
    for a, b in (((xe - ro - h, ye), (xe + ro + h, ye)), ((xe, ye - ro - h), (xe, ye + ro + h))):
        msp.add_line(a, b, dxfattribs={"layer": "CENTERLINES"})
    info = CylDxfInfo(dr.dxf_version, units, mode, dr.chord_tolerance, tuple(drawn), 0.0)
    if dr.title_block:
        _title(msp, design, s, info, x_a, min(-h, ye - ro) - 3 * h, h)
    try:
        from ezdxf import zoom  # deferred: ezdxf, loaded when a drawing is made

        zoom.extents(msp, factor=1.05)
    except Exception:  # noqa: BLE001 - the initial view is a convenience only
        pass
    return doc, info


def title_rows(design: Any, summary: dict[str, Any], info: CylDxfInfo) -> list[tuple[str, str]]:
    """(label, value) rows of the title block: report.json's numbers."""
    spec = design.spec
    u = spec.units
    f = lambda v: _fmt(v, u)  # noqa: E731
    body = summary["body"]
    fit = info.summary()["developed_fit_error"]
    drawn = {"cubic": "CUBIC SPLINES", "arcs": "ARCS", "polyline": "POLYLINES"}[info.curves_mode]
    checks = summary.get("checks") or {}
    verdict = "ALL CHECKS PASS" if checks.get("passed") else "FAILED: " + ", ".join(checks.get("failed", [])).upper()
    pa = summary["pressure_angle"]
    return [
        ("CAM", f"CYLINDRICAL (BARREL), {spec.cam.direction.upper()}, {spec.cam.speed_rpm:g} RPM"),
        ("UNITS", f"{u.upper()}, SCALE 1:1"),
        ("PITCH / OUTER / GROOVE BOTTOM RADIUS", f"{f(body['pitch_radius'])} / {f(body['outer_radius'])} / "
                                                 f"{f(body['bottom_radius'])}"),
        ("LENGTH / BORE DIAMETER", f"{f(body['length'])} / {f(spec.cam.bore_diameter)}"),
        ("GROOVE WIDTH / DEPTH", f"{f(body['groove_width'])} / {f(body['groove_depth'])}"),
        ("LIFT RANGE Z", f"{f(body['lift_range'][0])} TO {f(body['lift_range'][1])}"),
        ("FOLLOWER", str(summary["follower"]["label"]).upper()),
        ("DEVELOPED VIEW", "X = RHO * PSI (WALLS AT R_O, PITCH LINE AT R_P), Y = Z"),
        ("WALLS (WALL_LOWER, WALL_UPPER)", f"{drawn}, NOT EXACT: FIT ERROR {fit['value']:.2e} {u}"),
        ("PITCH LINE (PITCH)", f"{drawn}, NOT EXACT: FIT ERROR {fit['pitch_line']:.2e} {u}"),
        ("PRESSURE ANGLE", f"{pa['max_deg']:.2f} DEG AT R_P, {pa['bottom_max_deg']:.2f} DEG AT R_B"),
        ("CHECKS", verdict),
        ("SPEC DIGEST", str(summary.get("spec_digest", ""))[:16]),
        ("CAM-WORKBENCH", __version__),
    ]


def _title(msp: Any, design: Any, summary: dict[str, Any], info: CylDxfInfo, x0: float, top: float, h: float) -> None:
    """The title block below the views: the drawing's title (the body's name) over a two-column
    table of :func:`title_rows`, each column as wide as :func:`~cam_workbench.exporters.dxf.text_width` bounds
    its texts plus half a text height each side."""
    att = {"layer": "TITLE"}
    rows = title_rows(design, summary, info)
    row_h = 1.8 * h
    th = 0.8 * h
    title = title_line(design.spec)
    _text(msp, title, (x0 + 0.5 * h, top - 1.9 * h), 1.4 * h, "TITLE")
    y = top - 2.6 * h
    x1 = x0 + max(text_width(a, th) for a, _ in rows) + h
    x2 = max(x1 + max(text_width(b, th) for _, b in rows) + h, x0 + text_width(title, 1.4 * h) + h)
    msp.add_line((x0, y), (x2, y), dxfattribs=att)
    for label, value in rows:
        _text(msp, label, (x0 + 0.5 * h, y - 1.35 * h), th, "TITLE")
        _text(msp, value, (x1 + 0.5 * h, y - 1.35 * h), th, "TITLE")
        y -= row_h
        msp.add_line((x0, y), (x2, y), dxfattribs=att)
    for x in (x0, x1, x2):
        msp.add_line((x, top - 2.6 * h), (x, y), dxfattribs=att)
    add_closed_outline(msp, [(x0, y), (x2, y), (x2, top), (x0, top)], att)

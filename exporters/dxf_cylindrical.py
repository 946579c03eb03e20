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

A title block (``TITLE``) quotes report.json's numbers.  Only ``drawing.curves = "spline"``: the
walls are splines (a SpecError otherwise, nothing written).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from generators import __version__
from generators.errors import SpecError

from .dxf import _DECIMALS, _INSUNITS, LAYERS, _fmt, _new_document, _text

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

#: cubic spline nodes per radian of cam angle (at least 8 per motion segment)
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


def developed_points(design: Any, rho: float, side: int, theta: np.ndarray, segment: np.ndarray | None = None
                     ) -> np.ndarray:
    """Exact developed points (x, z), (n, 2), of the centre line C_ρ at radius ρ offset by
    side·w/2 along its normal (side 0: the centre line, +1 the upper wall, −1 the lower)."""
    lay = design.layout
    c = lay.centre_line(design.program, theta, rho, segment)      # the follower's own path (translating or arm)
    x, z = c.offset(lay.sense, side * lay.half_width)
    return np.column_stack([x, z])


def developed_curves(design: Any) -> tuple[DevelopedCurve, ...]:
    """The lower and upper walls at R_o and the pitch line at R_p, one cubic spline per motion
    segment each, with their measured fit errors."""
    from scipy.interpolate import make_interp_spline

    lay = design.layout
    prog = design.program
    bounds = prog.boundaries
    out = []
    for layer, rho, side in (("WALL_LOWER", lay.outer_radius, -1), ("WALL_UPPER", lay.outer_radius, 1),
                             ("PITCH", lay.pitch_radius, 0)):
        for seg in range(len(prog.starts)):
            a, b = float(bounds[seg]), float(bounds[seg + 1])
            n = max(8, int(np.ceil((b - a) * NODES_PER_RAD)) + 1)
            th = np.linspace(a, b, n)
            pts = developed_points(design, rho, side, th, np.full(n, seg))
            sp = make_interp_spline(th, pts, k=DEGREE)
            # off the nodes: the span midpoints and 8 points inside every span
            fr = np.linspace(0, 1, 10)[1:-1]
            tt = np.concatenate([(th[:-1] + th[1:]) / 2, (th[:-1, None] + fr[None, :] * np.diff(th)[:, None]).ravel()])
            err = float(np.max(np.hypot(*(sp(tt) - developed_points(design, rho, side, tt, np.full(tt.size, seg))).T)))
            out.append(DevelopedCurve(layer, seg, np.asarray(sp.t), np.asarray(sp.c), err))
    return tuple(out)


@dataclass(frozen=True)
class CylDxfInfo:
    """What the drawing holds (report.json's ``drawing`` section)."""

    version: str
    units: str
    curves: tuple[DevelopedCurve, ...]
    developed_offset_x: float

    def summary(self) -> dict[str, Any]:
        walls = [c.fit_error for c in self.curves if c.layer.startswith("WALL")]
        pitch = [c.fit_error for c in self.curves if c.layer == "PITCH"]
        return {
            "written": True, "file_version": self.version, "insunits": _INSUNITS[self.units], "curves": "spline",
            "exact": False,
            "views": ["developed (x = ρ·ψ at R_o for the walls, at R_p for the pitch line; y = z)",
                      "end (outer circle, bore, groove bottom dashed)", "side (length × diameter)"],
            "developed_fit_error": {"value": max(walls), "pitch_line": max(pitch), "unit": self.units,
                                    "what": f"cubic SPLINE per motion segment through exact points every "
                                            f"{1 / NODES_PER_RAD:.4g} rad of cam angle: max |spline(θ) − curve(θ)| "
                                            "off the nodes (an upper bound on the distance from the exact curve)"},
            "splines": len(self.curves),
        }


def build_cylindrical_dxf(design: Any, summary: dict[str, Any] | None = None) -> tuple[Any, CylDxfInfo]:
    """The ezdxf document of a cylindrical cam's drawing and what went into it (nothing written).

    Raises:
        SpecError: ``drawing.curves`` other than "spline" (naming the field).
    """
    spec = design.spec
    dr = spec.drawing
    if dr.curves != "spline":
        raise SpecError("drawing.curves", f'a cylindrical cam\'s developed walls are drawn as SPLINEs only: give '
                        f'"spline", got "{dr.curves}"')
    units = spec.units
    s = summary if summary is not None else design.summary()
    lay = design.layout
    doc = _new_document(dr.dxf_version, _INSUNITS[units])
    h = dr.text_height or max(lay.outer_radius / 20, 0.5 if units == "mm" else 0.02)
    doc.header["$LTSCALE"] = h
    doc.header["$LUPREC"] = _DECIMALS[units]
    for name, (color, linetype, lw) in CYL_LAYERS.items():
        doc.layers.add(name, color=color, linetype=linetype).dxf.lineweight = lw
    msp = doc.modelspace()
    curves = developed_curves(design)
    for c in curves:
        sp = msp.add_spline(dxfattribs={"layer": c.layer})
        sp.dxf.degree = DEGREE
        sp.control_points = [(float(x), float(y), 0.0) for x, y in c.poles.tolist()]
        sp.knots = [float(k) for k in c.knots.tolist()]
        sp.dxf.flags = sp.PLANAR
    ro, rb, length = lay.outer_radius, lay.bottom_radius, lay.length
    x_a, x_b = sorted((ro * float(lay.phi(0.0)), ro * float(lay.phi(2 * np.pi))))
    att = {"layer": "OUTLINE"}
    for a, b in (((x_a, 0.0), (x_b, 0.0)), ((x_a, length), (x_b, length)), ((x_a, 0.0), (x_a, length)),
                 ((x_b, 0.0), (x_b, length))):
        msp.add_line(a, b, dxfattribs=att)
    # side view: the cylinder's axis vertical (z rows shared with the developed view)
    gap = 4 * h
    xs = x_b + gap + ro
    msp.add_lwpolyline([(xs - ro, 0.0), (xs + ro, 0.0), (xs + ro, length), (xs - ro, length)], close=True,
                       dxfattribs=att)
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
    info = CylDxfInfo(dr.dxf_version, units, curves, 0.0)
    if dr.title_block:
        _title(msp, design, s, info, x_a, min(-h, ye - ro) - 3 * h, h)
    try:
        from ezdxf import zoom

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
        ("WALLS (WALL_LOWER, WALL_UPPER)", f"CUBIC SPLINES, NOT EXACT: FIT ERROR {fit['value']:.2e} {u}"),
        ("PITCH LINE (PITCH)", f"CUBIC SPLINES, NOT EXACT: FIT ERROR {fit['pitch_line']:.2e} {u}"),
        ("PRESSURE ANGLE", f"{pa['max_deg']:.2f} DEG AT R_P, {pa['bottom_max_deg']:.2f} DEG AT R_B"),
        ("CHECKS", verdict),
        ("SPEC DIGEST", str(summary.get("spec_digest", ""))[:16]),
        ("CAM-WORKBENCH", __version__),
    ]


def _title(msp: Any, design: Any, summary: dict[str, Any], info: CylDxfInfo, x0: float, top: float, h: float) -> None:
    """The title block below the views: a two-column table of :func:`title_rows`."""
    att = {"layer": "TITLE"}
    rows = title_rows(design, summary, info)
    row_h = 1.8 * h
    title = design.spec.drawing.title
    _text(msp, ("Cylindrical cam" if title == "Plate cam" else title).upper(), (x0 + 0.5 * h, top - 1.9 * h), 1.4 * h, "TITLE")
    y = top - 2.6 * h
    x1 = x0 + 0.8 * h * 0.9 * max(len(a) for a, _ in rows) + 2 * h
    x2 = x1 + 0.8 * h * 0.9 * max(len(b) for _, b in rows) + 2 * h
    msp.add_line((x0, y), (x2, y), dxfattribs=att)
    for label, value in rows:
        _text(msp, label, (x0 + 0.5 * h, y - 1.35 * h), 0.8 * h, "TITLE")
        _text(msp, value, (x1 + 0.5 * h, y - 1.35 * h), 0.8 * h, "TITLE")
        y -= row_h
        msp.add_line((x0, y), (x2, y), dxfattribs=att)
    for x in (x0, x1, x2):
        msp.add_line((x, top - 2.6 * h), (x, y), dxfattribs=att)
    msp.add_lwpolyline([(x0, y), (x2, y), (x2, top), (x0, top)], close=True, dxfattribs=att)


def export_cylindrical_dxf(design: Any, path: Any, summary: dict[str, Any] | None = None) -> CylDxfInfo:
    """Write the drawing to ``path`` atomically (temporary file, then rename)."""
    from .atomic import atomic_path

    doc, info = build_cylindrical_dxf(design, summary)
    with atomic_path(path) as tmp:
        doc.saveas(str(tmp))
    return info

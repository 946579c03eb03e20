"""A CAD kernel's solid against the cam's exact numbers: how far the kernel's integrals may lie
from them, per integration rule (measured), and the refusal of a solid beyond that.

A solid the kernel calls valid, one solid, can still be the wrong solid — a cylindrical cam whose
wall shells did not close was cut by the whole annulus instead of its groove and lost 23 % of its
volume, valid and one solid.  What a wrong solid cannot hide is its volume and its top face, so
both are held to the body's exact numbers (``design.volume``, ``design.area``: closed forms and
Green's theorem on the exact loops) within what the kernel's integration of the right solid
allows (relative):

========================================  ================================  ========  ============================
rule                                      faces it integrates               allowed   measured (fuzzed specs)
========================================  ================================  ========  ============================
OCCT's fixed Gauss rule                   prisms of plane curves: every     1e-8      ≤ 7.5e-10 (volume),
                                          body but the cylindrical; the               ≤ 1.7e-10 (top face); 120
                                          top face of every body                      plate, groove, conjugate cams
OCCT's fixed Gauss rule (OCP's            a cylindrical cam's wall faces    5e-5 +    ≤ 1.4e-5, median ~1e-8 (at
``BRepGProp``, FreeCAD's                  (isoparametric patches of its     walls     most 0.26 of the allowance);
``Shape.Volume``)                         B-spline surfaces) and the                  200 cylindrical cams (OCP)
                                          cylinder faces between them
OCCT's adaptive rule, ε = 1e-6 per face   the same faces (0.15 s: neither   1e-9 +    ≤ 4e-12 beyond the walls'
                                          kernel's rule)                    walls     share; 100 cylindrical cams
========================================  ================================  ========  ============================

*The walls' share*: a surface body's B-spline walls lie within ``e`` of the exact walls (the larger
of the design's ``wall_fit_error`` and the built faces' ``wall_error``), so the volume between them
is at most A·e, A ≈ 2·V_groove/w the two walls' area over the groove's depth; the share allowed is
2·A·e / V.  A surface body's solid must also hold wall faces — at least one per wall surface the
design gives the kernel: finding none is a failure, not a comparison of nothing.

*The fitted offset's share*: with ``pitch.representation = "bspline"`` the OCP solid's profile is
OCCT's exact offset of the fitted pitch B-spline, while the exact numbers (and the STEP solid) are
those of the fitted offset B-spline ``design.profile``, within ``e = profile.fitted_vs_kernel_offset``
of it: the area between them is at most P·e (P the profile's length), allowed 2·P·e / A (and × the
thickness / V).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

from ..errors import GeometryError


@dataclass(frozen=True)
class IntegrationRule:
    """How a kernel integrates a solid's volume, and the relative disagreement with the exact
    volume (``volume``) and top-face area (``area``) that rule allows on the right solid."""

    text: str
    volume: float
    area: float
    #: a surface body's walls add their share (see the module docstring)
    walls: bool = False


GAUSS_PRISMS = IntegrationRule("OCCT's fixed Gauss rule on prisms of plane curves", 1e-8, 1e-8)
ADAPTIVE_SURFACES = IntegrationRule("OCCT's adaptive integration (ε = 1e-6 per face) of the B-spline wall faces",
                                    1e-9, 1e-8, walls=True)
GAUSS_SURFACES = IntegrationRule("OCCT's fixed Gauss rule on the B-spline wall faces", 5e-5, 1e-8, walls=True)


def surface_body(design: Any) -> bool:
    """Whether ``design``'s body has B-spline wall surfaces (not a stack of prisms alone)."""
    return design.body is not None and not design.body.prismatic


def integration_rule(design: Any, adaptive: bool) -> IntegrationRule:
    """The rule a kernel integrates ``design``'s solid with: prisms by the fixed Gauss rule; a surface
    body's walls by the fixed one too (both kernels) or, with ``adaptive``, OCCT's adaptive rule."""
    if not surface_body(design):
        return GAUSS_PRISMS
    return ADAPTIVE_SURFACES if adaptive else GAUSS_SURFACES


def walls_share(design: Any, wall_error: float | None = None) -> float:
    """The relative volume the B-spline walls may add or take (0 for prisms): 2·A·e / V, A = 2·V_groove/w,
    e the larger of the design's wall fit error and the built faces' ``wall_error``."""
    if not surface_body(design):
        return 0.0
    body = design.body
    e = max(design.body_report["wall_fit_error"]["value"], wall_error or 0.0)
    area = 2 * body.groove_volume / (2 * body.layout.half_width)
    return 2 * area * e / design.volume


def offset_share(design: Any) -> float:
    """The relative area the kernel's exact offset of a fitted pitch B-spline may add or take from the
    fitted offset ``design.profile`` (0 without one): 2·P·e / A (see the module docstring)."""
    if design.bspline is None:
        return 0.0
    _, pts = design.profile.sample(32)
    perimeter = float(np.sum(np.hypot(*np.diff(pts, axis=0).T)))
    return 2 * perimeter * design.bspline.errors.fitted_vs_exact_offset / design.area


def check_kernel_solid(design: Any, volume: float, area: float, *, kernel: str, adaptive: bool,
                       walls: Mapping[str, Any] | None = None, exact_offset: bool = False) -> dict[str, float]:
    """Refuse a kernel's solid whose ``volume`` or top-face ``area`` (spec units) disagree with the
    design's exact numbers beyond :func:`integration_rule`'s allowance, or a surface body's solid
    whose wall faces are missing (``walls``: report.json's ``solid.wall_error``, with ``faces`` and
    ``points``; None: not measured).  ``exact_offset``: the solid's profile is the kernel's exact
    offset of the fitted pitch B-spline (:func:`offset_share` allowed).  Returns the allowances used
    ({"volume": …, "area": …}).

    Raises:
        GeometryError: kind "kernel", naming the kernel, what disagrees, both numbers, the relative
            difference and the allowance.
    """
    rule = integration_rule(design, adaptive)
    u = design.spec.units
    if surface_body(design) and walls is not None:
        expected = len(design.body.walls)
        if walls["faces"] < expected or walls["points"] == 0:
            raise GeometryError("kernel", f"{kernel}'s solid of the cam holds {walls['faces']} groove wall faces "
                                f"({walls['points']} points inside the groove), expected at least {expected}: the "
                                f"groove was not cut between its walls")
    wall_error = walls["value"] if walls is not None else None
    fit = offset_share(design) if exact_offset else 0.0
    tol_v = rule.volume + (walls_share(design, wall_error) if rule.walls else 0.0) \
        + fit * design.area * design.spec.cam.thickness / design.volume
    tol_a = rule.area + fit
    for what, got, exact, tol, unit in (("volume", volume, design.volume, tol_v, f"{u}³"),
                                        ("top face area", area, design.area, tol_a, f"{u}²")):
        rel = got / exact - 1.0
        if not abs(rel) <= tol:
            raise GeometryError("kernel", f"{kernel}'s solid of the cam has the {what} {got:.10g} {unit}, the exact "
                                f"{what} is {exact:.10g} {unit}: {rel:+.3e} relative, beyond the {tol:.2g} "
                                f"{rule.text} allows — the solid is not the cam's")
    return {"volume": tol_v, "area": tol_a}

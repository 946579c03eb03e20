"""Exact rational offsets of PH quintic splines (Farouki & Neff; paper §1).

For a PH segment r(ξ) with r' = w², σ = |w|², the unit left normal is n = i·w²/σ,
so the offset at signed distance d (d > 0 to the left of the direction of travel)

    r_d(ξ) = r(ξ) + d·n(ξ) = (σ·r + i·d·w²) / σ

is a rational curve: numerator of degree 4 + 5 = 9, denominator σ of degree 4,
elevated to 9.  Each segment is therefore an exact rational Bézier curve of degree
9 with weights = Bernstein coefficients of σ; the segments join into one NURBS.
Nothing is sampled.
"""
from __future__ import annotations

import numpy as np

from . import bezier
from ..errors import GeometryError
from .nurbs import NurbsCurve, from_polynomial_beziers, from_rational_beziers
from .ph_spline import PHSpline, hodograph_coeffs, sigma_coeffs


def offset_bezier_segments(spline: PHSpline, distance: float) -> tuple[np.ndarray, np.ndarray]:
    """Weighted control points (S, 10) complex and weights (S, 10) of the offset segments."""
    sig4 = sigma_coeffs(spline.w)                     # degree 4, real
    hod4 = hodograph_coeffs(spline.w)                 # degree 4, complex (w²)
    num = bezier.product(sig4.astype(complex), spline.ctrl) + 1j * distance * bezier.elevate(hod4, 9)
    den = bezier.elevate(sig4, 9)
    return num, den


def offset_nurbs(spline: PHSpline, distance: float) -> NurbsCurve:
    """The exact offset of a closed PH spline at signed distance ``distance``
    (left of the direction of travel) as a degree-9 rational NURBS, one Bézier span
    per PH segment (parameter u ∈ [k, k+1] ↔ segment k, ξ = u − k).

    Raises:
        GeometryError: a weight is not positive (degenerate hodograph).
    """
    if distance == 0.0:
        return pitch_nurbs(spline)
    num, den = offset_bezier_segments(spline, distance)
    if not np.all(den > 0):
        k = int(np.argwhere(den <= 0)[0, 0])
        raise GeometryError("degenerate", f"PH segment {k} has a vanishing hodograph; cannot offset it")
    # scale weights to O(1): a common factor leaves the rational curve unchanged
    scale = 1.0 / float(np.max(den))
    return from_rational_beziers(num * scale, den * scale)


def pitch_nurbs(spline: PHSpline) -> NurbsCurve:
    """The PH spline itself as a (polynomial) degree-5 NURBS."""
    return from_polynomial_beziers(spline.ctrl)

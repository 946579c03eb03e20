"""Checks that decide whether a cam can be built at all: undercut, a self-intersecting
profile, a bore that cuts the profile.  Each failure is a :class:`GeometryError`
naming the cam angle where it happens.

Curvature sign convention: radii of curvature are positive where the pitch curve
is convex (seen from outside the cam), negative where it is concave.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import GeometryError, fmt_apart
from ..curves.nurbs import NurbsCurve
from ..pitch.ph import PitchCurve

SAMPLES_PER_SEGMENT = 64


@dataclass(frozen=True)
class CurvatureSamples:
    """As-built pitch curvature sampled on every PH segment."""

    seg: np.ndarray
    xi: np.ndarray
    point: np.ndarray
    radius: np.ndarray      # signed radius of curvature, + convex
    cam_angle_deg: np.ndarray


def pitch_curvature_samples(pitch: PitchCurve, per_segment: int = SAMPLES_PER_SEGMENT) -> CurvatureSamples:
    """Signed radius of curvature of the built PH pitch curve (ρ = −δ/κ, κ = 2Im(w̄w')/σ²),
    sampled ``per_segment`` times per PH segment (junctions included)."""
    m = pitch.M
    xi = np.tile(np.linspace(0.0, 1.0, per_segment), m)
    seg = np.repeat(np.arange(m), per_segment)
    kappa = pitch.spline.curvature(seg, xi)
    with np.errstate(divide="ignore"):
        radius = -pitch.geometry.sense / kappa
    pts = pitch.spline.point(seg, xi)
    return CurvatureSamples(seg, xi, pts, radius, pitch.cam_angle_at(seg, xi))


def check_undercut(pitch: PitchCurve, roller_radius: float, samples: CurvatureSamples | None = None) -> None:
    """Undercut: the roller radius reaches the smallest convex radius of curvature of the pitch curve.

    Raises:
        GeometryError: with the cam angle of the sharpest convex point.
    """
    if roller_radius <= 0:
        return
    cs = samples or pitch_curvature_samples(pitch)
    convex = cs.radius > 0
    if not convex.any():
        return
    rad = np.where(convex, cs.radius, np.inf)
    k = int(np.argmin(rad))
    if roller_radius >= rad[k]:
        raise GeometryError(
            "undercut",
            f"undercut at cam angle {cs.cam_angle_deg[k]:.2f}°: roller radius {fmt_apart(roller_radius, rad[k])} ≥ "
            f"smallest convex pitch radius of curvature {fmt_apart(rad[k], roller_radius, 4)} "
            "(use a smaller roller, a larger base radius or a gentler motion)",
            float(cs.cam_angle_deg[k]),
        )


def _segments_intersect(p: np.ndarray, q: np.ndarray) -> tuple[int, int] | None:
    """First pair (i, j), j > i+1, of intersecting polygon edges p_i→p_{i+1}, q = p rolled.

    Chunked O(N²) vectorised test; only called when the cheap star-shape test fails."""
    n = p.shape[0]
    a, b = p, q
    d = b - a
    chunk = max(1, 4_000_000 // max(n, 1))
    for i0 in range(0, n, chunk):
        i = np.arange(i0, min(n, i0 + chunk))[:, None]
        j = np.arange(n)[None, :]
        ai, di = a[i], d[i]
        aj, dj = a[j], d[j]
        den = (di.conj() * dj).imag
        w = aj - ai
        with np.errstate(divide="ignore", invalid="ignore"):
            s = (w.conj() * dj).imag / den
            t = (w.conj() * di).imag / den
        adjacent = (np.abs(i - j) <= 1) | (np.abs(i - j) == n - 1)
        hit = (den != 0) & (s > 0) & (s < 1) & (t > 0) & (t < 1) & ~adjacent
        if hit.any():
            ii, jj = np.argwhere(hit)[0]
            return int(i0 + ii), int(jj)
    return None


def check_self_intersection(profile: NurbsCurve, pitch: PitchCurve, per_span: int = 24) -> None:
    """A profile that crosses itself cannot bound a solid.

    First a cheap test: a profile whose polar angle about the cam axis is strictly
    monotonic cannot cross itself.  Otherwise every pair of edges of a dense polygon is
    tested.

    Raises:
        GeometryError: with the cam angle of the first crossing.
    """
    u, pts = profile.sample(per_span)
    z = pts[:-1, 0] + 1j * pts[:-1, 1]
    dang = np.angle(np.roll(z, -1) / z)
    if np.all(dang > 0) or np.all(dang < 0):
        return
    hit = _segments_intersect(z, np.roll(z, -1))
    if hit is None:
        return
    uu = u[hit[0]]
    seg = np.array([min(int(uu), pitch.M - 1)])
    ang = float(pitch.cam_angle_at(seg, np.array([uu - seg[0]]))[0])
    raise GeometryError(
        "self_intersection",
        f"the cam profile crosses itself near cam angle {ang:.2f}° "
        "(the pitch curve loops or the roller is too large for a concave region)",
        ang,
    )


def min_radius(profile: NurbsCurve, per_span: int = 64) -> tuple[float, float]:
    """(smallest distance of the profile from the cam axis, parameter u where it occurs),
    refined by golden-section search around the best sample."""
    u, pts = profile.sample(per_span)
    r = np.hypot(pts[:, 0], pts[:, 1])
    k = int(np.argmin(r))
    lo = u[max(k - 1, 0)]
    hi = u[min(k + 1, len(u) - 1)]
    g = (np.sqrt(5) - 1) / 2
    for _ in range(60):
        a = hi - g * (hi - lo)
        b = lo + g * (hi - lo)
        ra, rb = np.hypot(*profile.evaluate(np.array([a, b])).T)
        if ra < rb:
            hi = b
        else:
            lo = a
    um = 0.5 * (lo + hi)
    rm = float(np.hypot(*profile.evaluate(np.array([um]))[0]))
    return min(rm, float(r[k])), float(um)


def check_bore(profile: NurbsCurve, pitch: PitchCurve, bore_diameter: float) -> float:
    """The bore must stay inside the profile.  Returns the smallest profile radius.

    Raises:
        GeometryError: with the cam angle where the profile comes closest to the axis.
    """
    rmin, u = min_radius(profile)
    if bore_diameter > 0 and bore_diameter / 2 >= rmin:
        seg = np.array([min(int(u), pitch.M - 1)])
        ang = float(pitch.cam_angle_at(seg, np.array([u - seg[0]]))[0])
        raise GeometryError(
            "bore",
            f"the bore (radius {fmt_apart(bore_diameter / 2, rmin)}) cuts the profile at cam angle {ang:.2f}°, "
            f"where the profile is only {fmt_apart(rmin, bore_diameter / 2, 4)} from the axis",
            ang,
        )
    return rmin

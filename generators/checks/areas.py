"""Cam cross-section areas from the motion (design intent), next to the built profile's.

* :func:`thesis_area` — the thesis' cost function (Eq. 4.21–4.27):
  A = Σ ∫ ½ r² dθ with r = R₀ + s(θ) (Eq. 4.5): ½R₀²θ_b for the bottom dwell (Eq. 4.25),
  ½(R₀ + L)²θ_t for the top dwell (Eq. 4.24) and ∫ ½ r(u)² θ′(u) du over each B-spline rise
  and return (Eq. 4.26–4.27).  R₀ + s is the distance of the follower point (the roller
  centre) from the axis when e = 0, so this is the area inside the pitch (prime) curve — not
  inside the cam profile, which lies a roller radius further in.
* :func:`pitch_area` — the exact area inside the design curve C(θ) (the pitch curve of a knife
  edge or roller, the profile of a flat face): ½|∮ Im(C̄ C′) dθ|, with the follower's exact C′;
  for a translating follower ½∫ (e² + (s₀ + s)²) dθ (the ∫ e s′ dθ term vanishes over a closed
  cycle), equal to :func:`thesis_area` for e = 0.
* :func:`pitch_length` — ∫ |C′| dθ (translating: ∫ √((s₀ + s)² + (s′ − e)²) dθ).
* :func:`profile_area` — the area inside the true profile (the design curve offset inward by
  the roller radius r_f, 0 for a knife edge or a flat face): A − r_f·L + π r_f² (Steiner's
  formula for the inner parallel curve of a simple closed curve, valid while the offset is not
  undercut).

Integrals are Gauss–Legendre per motion segment; on a B-spline segment they run over the
parameter u per knot span, where ½ r² θ′ is a polynomial and the rule is exact (at least 16 nodes
per span, and at least 64 per segment, as a closed form gets).
"""
from __future__ import annotations

from typing import Any, Callable

import numpy as np

from ..kinds import follower_class_of, follower_of
from ..motion.program import MotionProgram
from ..spec.model import CamSpec

#: what each area of report.json is, in the words every printout uses: ``area`` (the built cross-section)
#: and the keys of ``areas`` (design intent) — so that no two areas are ever printed under one name
AREA_LABELS = {
    "area": "cross-section (top face)",
    "thesis_eq_4_21": "thesis Eq. 4.21 area ½∮(R_b + s)² dθ",
    "pitch_curve": "area inside the {curve}",
    "profile": "area inside the profile",
    "cross_section": "cross-section (profile − bore)",
}


def area_label(key: str, curve: str = "pitch curve") -> str:
    """The words for report.json's area ``key`` (``"area"`` or a key of ``areas``); ``curve``:
    report.json's ``follower.curve`` (the design curve: "pitch curve", a flat face's "contact curve")."""
    return AREA_LABELS[key].format(curve=curve)


GAUSS_CLOSED_FORM = 64     # nodes per closed-form motion segment (smooth integrands)
GAUSS_PER_KNOT_SPAN = 16   # nodes per B-spline knot span (exact for degree ≤ 31)


def _integrate(program: MotionProgram, integrand: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]
               ) -> float:
    """∫₀^{2π} integrand(θ, s, s′) dθ, segment by segment."""
    return _integrate_kin(program, lambda th, k: integrand(th, k.s, k.ds))


def _integrate_kin(program: MotionProgram, integrand: Callable[[np.ndarray, Any], np.ndarray]) -> float:
    """∫₀^{2π} integrand(θ, kinematics) dθ, segment by segment."""
    total = 0.0
    for k in range(len(program.starts)):
        a, beta = program.starts[k], program.spans[k]
        seg_idx = None
        curve = program.curves[k] if program.curves else None
        if curve is not None:
            br = np.unique(curve.knots)
            # a lift of few knot spans (a polynomial segment: one) gets as many nodes as a closed form
            nodes = max(GAUSS_PER_KNOT_SPAN, -(-GAUSS_CLOSED_FORM // (len(br) - 1)))
            xg, wg = np.polynomial.legendre.leggauss(nodes)
            lo, hi = br[:-1], br[1:]
            u = (0.5 * (hi - lo)[:, None] * (xg[None, :] + 1) + lo[:, None]).ravel()
            w = (0.5 * (hi - lo)[:, None] * wg[None, :]).ravel()
            th_u, _ = curve.parametric(u, 1)
            theta = a + th_u[0]
            seg_idx = np.full(theta.shape, k)
            kin = program.evaluate(theta, seg_idx)
            total += float(np.sum(integrand(theta, kin) * th_u[1] * w))
            continue
        n = GAUSS_CLOSED_FORM if program.laws[k] is not None else 2
        xg, wg = np.polynomial.legendre.leggauss(n)
        theta = a + 0.5 * beta * (xg + 1)
        kin = program.evaluate(theta, np.full(theta.shape, k))
        total += float(np.sum(integrand(theta, kin) * 0.5 * beta * wg))
    return total


def thesis_area(spec: CamSpec, program: MotionProgram | None = None) -> float:
    """Thesis Eq. 4.21–4.27: ∮ ½ (R₀ + s(θ))² dθ [length²] (the area inside the prime curve
    for e = 0; the thesis uses it whatever e is)."""
    program = program or MotionProgram.from_spec(spec)
    r0 = spec.cam.base_radius
    return _integrate(program, lambda th, s, ds: 0.5 * (r0 + s) ** 2)


def pitch_area(spec: CamSpec, program: MotionProgram | None = None) -> float:
    """Exact area inside the design curve: ½|∮ Im(C̄ C′) dθ| [length²]."""
    program = program or MotionProgram.from_spec(spec)
    fol = follower_of(spec)

    def integrand(th: np.ndarray, k: Any) -> np.ndarray:
        f = fol.fixed(k, 1)
        v = f[1] - 1j * fol.sense * f[0]
        return 0.5 * (np.conj(f[0]) * v).imag     # rotation-invariant: C̄C′ = F̄V

    return abs(_integrate_kin(program, integrand))


def pitch_length(spec: CamSpec, program: MotionProgram | None = None) -> float:
    """Arc length of the design curve: ∫ |C′| dθ [length]."""
    program = program or MotionProgram.from_spec(spec)
    fol = follower_of(spec)

    def integrand(th: np.ndarray, k: Any) -> np.ndarray:
        f = fol.fixed(k, 1)
        return np.abs(f[1] - 1j * fol.sense * f[0])

    return _integrate_kin(program, integrand)


def profile_area(spec: CamSpec, program: MotionProgram | None = None) -> float:
    """Area inside the true cam profile (no bore): A − r_f·L + π r_f² of the design curve."""
    program = program or MotionProgram.from_spec(spec)
    rr = spec.roller_radius
    return pitch_area(spec, program) - rr * pitch_length(spec, program) + np.pi * rr * rr


def area_summary(spec: CamSpec, program: MotionProgram | None = None) -> dict[str, float]:
    """The design-intent areas of report.json (length²)."""
    program = program or MotionProgram.from_spec(spec)
    bore = spec.cam.bore_diameter / 2
    prof = profile_area(spec, program)
    # the thesis' formula (R₀ + s)² is a translating follower's pitch curve
    kind = follower_class_of(spec)
    thesis = thesis_area(spec, program) if not kind.pivoted and kind.design_curve == "pitch" else None
    return {
        "thesis_eq_4_21": thesis,
        "pitch_curve": pitch_area(spec, program),
        "profile": prof,
        "cross_section": prof - np.pi * bore * bore,
    }

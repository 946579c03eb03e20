"""Contact loads: Hertz stress of two cylinders (thesis Eq. 3.6) and the factor that turns
the spec's mass units into force.

Units are the spec's: lengths mm or in, force N or lbf, mass kg or lbf·s²/in, stress MPa
or psi.  M_f·s″ω² is kg·mm/s² = 10⁻³ N in a mm spec and lbf·s²/in · in/s² = lbf in an
inch spec (the thesis' convention), so a mm spec and its inch equivalent give the same
physical forces and stresses; the same factor turns an arm's I·ψ̈ (kg·mm² / s² or
lbf·s²·in / s²) into N·mm or lbf·in.
"""
from __future__ import annotations

import numpy as np

#: Newtons per (mass unit × length unit / s²): kg·mm/s² = 1e-3 N; lbf·s²/in · in/s² = 1 lbf.
MASS_FORCE_FACTOR = {"mm": 1e-3, "in": 1.0}


def hertz_stress(force: np.ndarray, roller_radius: float, cam_radius: np.ndarray, length: float,
                 e_cam: float, nu_cam: float, e_roller: float, nu_roller: float) -> np.ndarray:
    """Largest Hertz contact pressure of two parallel cylinders (thesis Eq. 3.6):

        S² = F (r_c + r_f) / (π t r_f r_c Δ) = F (1/r_f + 1/r_c) / (π t Δ),
        Δ = (1 − ν_c²)/E_c + (1 − ν_f²)/E_f,

    with r_c signed (+ convex cam surface, − concave: the roller sits in a hollow of radius
    |r_c| > r_f) and r_c = ±inf for a flat; ``roller_radius`` = inf for a flat follower face
    (cylinder on a plane).  Where F ≤ 0 (no contact) the stress is 0; where
    1/r_f + 1/r_c ≤ 0 (the roller is larger than a concave hollow: undercut) it is inf."""
    force = np.asarray(force, dtype=float)
    with np.errstate(divide="ignore"):
        k_rel = 1.0 / roller_radius + 1.0 / np.asarray(cam_radius, dtype=float)
    delta = (1 - nu_cam**2) / e_cam + (1 - nu_roller**2) / e_roller
    with np.errstate(invalid="ignore"):
        s2 = np.maximum(force, 0.0) * k_rel / (np.pi * length * delta)
        return np.where(k_rel > 0, np.sqrt(np.maximum(s2, 0.0)), np.inf)

"""Asymmetric ("throw" or quick-return) rest-to-rest polynomial rises: the 3-4-5 and 4-5-6-7 laws
with the velocity peak moved to a fraction p of the rise (0 < p < 1).

The rise is the symmetric law F's accelerating half stretched over [0, p] and its decelerating half
over [p, 1], each scaled so that the velocity matches at the peak:

    x ≤ p:  f = 2p·F(x/(2p)),                 u = x/(2p) ∈ [0, ½]
    x ≥ p:  f = p + 2(1 − p)·(F(u) − ½),      u = ½ + (x − p)/(2(1 − p)) ∈ [½, 1]

so f′ = F′(u) on both sides (the peak velocity is F's, C_v unchanged), f″ = F″(u)/(2p) and
F″(u)/(2(1 − p)) (both 0 at the peak: f″ continuous), f‴ = F‴(u)/(4p²) and F‴(u)/(4(1 − p)²):
the jerk jumps at x = p unless p = ½, where the laws are F itself.  f′ ≥ 0 for every p (F′ ≥ 0);
the ends keep F's continuity against dwells.  The peak acceleration and jerk grow as 1/min(p, 1 − p)
and 1/min(p, 1 − p)²: C_a = C_a(F)/(2 min(p, 1 − p)).
"""
from __future__ import annotations

import numpy as np

from .laws import END_CONTINUITY, LAW_FUNCTIONS

Array = np.ndarray

#: the symmetric laws the asymmetric family is made of
FAMILIES = ("poly345", "poly4567")


class ThrowPolynomialLaw:
    """x ↦ f, f′, f″, f‴ of the asymmetric ``family`` law (``"poly345"`` or ``"poly4567"``) peaking
    at ``peak_at`` (a module-level callable, so a law made of it pickles).

    Raises:
        ValueError: an unknown family or ``peak_at`` outside (0, 1) (the spec's rules name the field
            first)."""

    def __init__(self, family: str, peak_at: float) -> None:
        if family not in FAMILIES or not 0.0 < float(peak_at) < 1.0:
            raise ValueError(f"needs a family of {FAMILIES} and 0 < peak_at < 1, got {family!r}, {peak_at!r}")
        self.family, self.peak_at = family, float(peak_at)

    @property
    def continuity(self) -> int:
        """The symmetric law's end continuity: 2 (3-4-5), 3 (4-5-6-7)."""
        return END_CONTINUITY[self.family]

    def __call__(self, x: Array) -> tuple[Array, Array, Array, Array]:
        x = np.asarray(x, dtype=float)
        p = self.peak_at
        first = x <= p
        span = np.where(first, 2 * p, 2 * (1 - p))                     # the stretched half's length
        u = np.where(first, x / (2 * p), 0.5 + (x - p) / (2 * (1 - p)))
        F, F1, F2, F3 = LAW_FUNCTIONS[self.family](u)
        f = np.where(first, span * F, p + span * (F - 0.5))
        return f, np.asarray(F1, dtype=float) * np.ones_like(x), F2 / span, F3 / span**2

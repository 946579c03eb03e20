"""The trade's characteristic values of a normalised rise law f(x), x ∈ [0, 1]
(Neklutin; Chen, *Mechanics and Design of Cam Mechanisms*, 1982; Rothbart, *Cam Design
Handbook*, 2004):

* C_v = max|f'|, C_a = max|f''|, C_j = max|f'''| — a rise of height h over an interval
  of duration T peaks at C_v·h/T, C_a·h/T², C_j·h/T³;
* the torque index C_v·C_a, and Q = max|f'·f''|: the peak of velocity × acceleration, which
  sets the peak dynamic torque (and power) that an output inertia reflects onto the input;
* the signed extremes max f'', min f'', max f''', min f''' (``C_a_max``, ``C_a_min``,
  ``C_j_max``, ``C_j_min``): MechDesigner's "Ca", "Cd" (deceleration), "Cj max", "Cj min", which
  differ from C_a and C_j for an asymmetric law (a quick return: C_a_max 4.583, C_a_min −6.667).

The maxima are found on a dense grid and refined (:func:`peak_abs`), vectorised.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from ..errors import SpecError
from .laws import CLOSED_FORM_LAWS, NormalisedLaw, as_law, end_continuity, evaluate_law, law_name

Array = np.ndarray

#: the golden section's shrink factor (√5 − 1)/2
_GOLD = (math.sqrt(5.0) - 1.0) / 2.0
#: grid samples of :func:`peak_abs`: 2¹⁴ intervals, so x = k/8 (the pieces' ends of the
#: modified laws) are grid points
_SAMPLES = 2**14 + 1


def peak_abs(fun: Callable[[Array], Array], derivative: Callable[[Array], Array] | None = None,
             samples: int = _SAMPLES) -> tuple[float, float]:
    """(max |fun(x)| over x ∈ [0, 1], the x where it is reached), ``fun`` vectorised over x.

    Every local maximum of |fun| on a grid of ``samples`` points is refined at once by a golden
    section over its two neighbouring intervals (the value to a few ulps: |fun| is flat at a
    smooth maximum, so the golden section finds x only to ~1e-8); where ``derivative``
    (d fun/dx) is given and changes sign there, x is then polished by bisection on it (to
    ~1e-15).  Ties (equal peaks within 1e-14, plateaus) give the smallest x.  Kinks and jumps
    of |fun| are fine as long as it is unimodal between the neighbours of a grid maximum."""
    x = np.linspace(0.0, 1.0, samples)
    g = np.abs(fun(x))
    padded = np.concatenate(([-np.inf], g, [-np.inf]))
    cand = np.flatnonzero((g >= padded[:-2]) & (g >= padded[2:]))
    lo, hi = x[np.maximum(cand - 1, 0)], x[np.minimum(cand + 1, samples - 1)]
    a, b = lo.copy(), hi.copy()
    for _ in range(64):  # bracket × 0.618⁶⁴ ≈ 1e-13·bracket < 1 ulp of x
        c, d = b - _GOLD * (b - a), a + _GOLD * (b - a)
        left = np.abs(fun(c)) >= np.abs(fun(d))
        a, b = np.where(left, a, c), np.where(left, d, b)
    xg = 0.5 * (a + b)
    bracketed = np.zeros(cand.shape, dtype=bool)
    if derivative is not None:
        def slope(t: Array) -> Array:
            return np.sign(fun(t)) * derivative(t)

        pa, pb = np.maximum(lo, xg - 1e-7), np.minimum(hi, xg + 1e-7)
        bracketed = (slope(pa) > 0) & (slope(pb) < 0)
        for _ in range(48):  # 2e-7 / 2⁴⁸ < 1e-21
            mid = 0.5 * (pa + pb)
            up = slope(mid) > 0
            pa, pb = np.where(up, mid, pa), np.where(up, pb, mid)
        xg = np.where(bracketed, 0.5 * (pa + pb), xg)
    # keep the grid point itself unless the refinement beats it by more than rounding (a peak
    # on the grid, a plateau, a jump at an end) or was polished on the derivative's root
    refined = np.abs(fun(xg))
    ulps = 4 * np.finfo(float).eps * g[cand]
    keep = (refined > g[cand] + ulps) | (bracketed & (refined >= g[cand] - ulps))
    refined = np.maximum(refined, np.where(keep, g[cand], 0.0))
    xs, vals = np.where(keep, xg, x[cand]), np.where(keep, refined, g[cand])
    # equal peaks (a symmetric law's) differ by rounding: the first within 1e-14 of the largest
    top = vals.max()
    best = int(np.flatnonzero(vals >= top * (1 - 1e-14))[0])
    return float(top), float(xs[best])


@dataclass(frozen=True)
class LawCharacteristics:
    """Characteristic values of a normalised rise law (dimensionless, per unit rise over a unit
    interval) and where they occur (x ∈ [0, 1]).

    ``C_j`` is ``math.inf`` for a law whose acceleration jumps at a rest end against a dwell
    (``END_CONTINUITY < 2``: the harmonic law; a :class:`~.laws.NormalisedLaw`'s ``continuity``),
    its jerk there being a Dirac impulse; ``x_j`` is
    then 0 (the start) and ``jerk_inside`` holds the largest jerk strictly inside the rise.  A
    quick-return law's turning end meets a reversing neighbour, not a dwell: its C_j is finite.
    Where a maximum is reached at several places (a plateau, a symmetric law) x is the first.
    ``C_j_max``, ``C_j_min`` are the signed extremes of f‴ over the rise (without the impulses
    where C_j is infinite)."""

    name: str
    C_v: float           #: max |f'|
    x_v: float
    C_a: float           #: max |f''|
    x_a: float
    C_j: float           #: max |f'''|, inf where f'' jumps at an end
    x_j: float
    jerk_inside: float   #: max |f'''| over the inside of the rise (= C_j where C_j is finite)
    torque_index: float  #: C_v·C_a
    Q: float             #: max |f'·f''|, the dynamic-torque characteristic
    x_Q: float
    C_a_max: float       #: max f'' (signed: the largest acceleration)
    C_a_min: float       #: min f'' (signed: the largest deceleration, ≤ 0)
    C_j_max: float       #: max f''' over the rise
    C_j_min: float       #: min f''' over the rise

    def summary(self) -> dict[str, Any]:
        """report.json's characteristic values (plain floats; an infinite C_j is None beside a
        ``C_j_note``)."""
        out: dict[str, Any] = {
            "law": self.name,
            "C_v": self.C_v, "x_v": self.x_v,
            "C_a": self.C_a, "x_a": self.x_a,
            "C_j": self.C_j if math.isfinite(self.C_j) else None, "x_j": self.x_j,
            "torque_index": self.torque_index,
            "Q": self.Q, "x_Q": self.x_Q,
            "C_a_max": self.C_a_max, "C_a_min": self.C_a_min,
            "C_j_max": self.C_j_max, "C_j_min": self.C_j_min,
        }
        if not math.isfinite(self.C_j):
            out["C_j_note"] = (f"infinite: the acceleration jumps at the ends "
                               f"(largest jerk inside the rise {self.jerk_inside:.6g})")
        return out


def law_characteristics(name: str | NormalisedLaw) -> LawCharacteristics:
    """C_v, C_a, C_j, C_v·C_a and Q of law ``name`` (a key of ``LAW_FUNCTIONS``, a
    :class:`~.laws.NormalisedLaw`: a motion program's rise, or a :class:`~.laws.LawName`: a
    parametric closed form), refined to ~1e-15 relative; cached per law (the characteristics'
    ``name`` is the law's name)."""
    return _characteristics(as_law(name))


@functools.lru_cache(maxsize=None)
def _characteristics(name: str | NormalisedLaw) -> LawCharacteristics:
    if not isinstance(name, NormalisedLaw) and name not in CLOSED_FORM_LAWS:
        raise SpecError("law", f"unknown law {name!r}; one of {', '.join(sorted(CLOSED_FORM_LAWS))}")

    def order(k: int) -> Callable[[Array], Array]:
        return lambda x: evaluate_law(name, x)[k]

    def vel_acc(x: Array) -> Array:
        _, v, a, _ = evaluate_law(name, x)
        return v * a

    def d_vel_acc(x: Array) -> Array:
        _, v, a, j = evaluate_law(name, x)
        return a * a + v * j

    c_v, x_v = peak_abs(order(1), order(2))
    c_a, x_a = peak_abs(order(2), order(3))
    jerk, x_j = peak_abs(order(3))
    q, x_q = peak_abs(vel_acc, d_vel_acc)
    a_max, a_min = _signed_peaks(order(2), order(3))
    j_max, j_min = _signed_peaks(order(3))
    if end_continuity(name) < 2:
        c_j, x_j = math.inf, 0.0
    else:
        c_j = jerk
    return LawCharacteristics(name=law_name(name), C_v=c_v, x_v=x_v, C_a=c_a, x_a=x_a, C_j=c_j, x_j=x_j,
                              jerk_inside=jerk, torque_index=c_v * c_a, Q=q, x_Q=x_q,
                              C_a_max=a_max, C_a_min=a_min, C_j_max=j_max, C_j_min=j_min)


def _signed_peaks(fun: Callable[[Array], Array], derivative: Callable[[Array], Array] | None = None
                  ) -> tuple[float, float]:
    """(max fun, min fun) over x ∈ [0, 1]: :func:`peak_abs` of its positive and negative parts
    (0 where it has none)."""
    top, _ = peak_abs(lambda x: np.maximum(fun(x), 0.0), derivative)
    bottom, _ = peak_abs(lambda x: np.minimum(fun(x), 0.0), derivative)
    return top, -bottom

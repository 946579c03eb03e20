"""Sample-then-refine extrema of smooth functions of one variable (vectorised sampling,
golden-section refinement of the best sample), so reported maxima are not sampling-limited."""
from __future__ import annotations

from typing import Callable

import numpy as np

_G = (np.sqrt(5.0) - 1.0) / 2.0


def refine_max(f: Callable[[np.ndarray], np.ndarray], x: np.ndarray, values: np.ndarray,
               iterations: int = 60) -> tuple[float, float]:
    """(x*, f(x*)) maximising ``f`` near the best of the samples ``values = f(x)``.

    The search stays between the neighbours of the best sample, so a maximum at a
    non-smooth point (a segment end) is returned as sampled."""
    k = int(np.argmax(values))
    lo = x[max(k - 1, 0)]
    hi = x[min(k + 1, len(x) - 1)]
    best_x, best_v = float(x[k]), float(values[k])
    a, b = lo, hi
    for _ in range(iterations):
        c = b - _G * (b - a)
        d = a + _G * (b - a)
        fc, fd = f(np.array([c, d]))
        if fc > fd:
            b = d
        else:
            a = c
    xm = 0.5 * (a + b)
    vm = float(f(np.array([xm]))[0])
    if vm > best_v:
        return xm, vm
    return best_x, best_v

"""The triple-harmonic rest-to-rest rise law: acceleration as the sum of the first three harmonics
of the rise interval,

    f″(x) = a₁ sin 2πx + a₂ sin 4πx + a₃ sin 6πx,   x ∈ [0, 1],

so f′ = Σ a_k (1 − cos 2πkx)/(2πk) and f = Σ a_k (x/(2πk) − sin 2πkx/(2πk)²): f′ and f″ vanish at
both ends for any amplitudes, f(1) = Σ a_k/(2πk) = 1 fixes a₃ = 6π(1 − a₁/(2π) − a₂/(4π)), and the
law is point-symmetric about x = ½.  a₁ = 2π, a₂ = 0 is the cycloidal law; the default a₁ = 9π/4,
a₂ = 0 (a₃ = −3π/4) also has zero jerk at both ends and at the crossover x = ½ (f‴ = 2π Σ k a_k
cos 2πkx), so it joins dwells with continuous jerk like the 4-5-6-7 polynomial.  Other amplitudes
approximate the modified trapezoid, modified sine and 3-4-5 laws (the parametrisation of
MotionDesigner's "Triple-Harmonic" law: first and second harmonic given, the third computed).
"""
from __future__ import annotations

import math

import numpy as np

Array = np.ndarray

#: the default amplitudes (a₁, a₂): zero jerk at the ends and the crossover
DEFAULT_HARMONICS = (9 * math.pi / 4, 0.0)


def third_harmonic(a1: float, a2: float) -> float:
    """a₃ making f(1) = 1 (per unit rise over a unit interval)."""
    return 6 * math.pi * (1.0 - a1 / (2 * math.pi) - a2 / (4 * math.pi))


class TripleHarmonicLaw:
    """x ↦ f, f′, f″, f‴ of the triple-harmonic law with acceleration amplitudes ``a1``, ``a2``
    (a₃ from f(1) = 1); a module-level callable, so a law made of it pickles."""

    def __init__(self, a1: float = DEFAULT_HARMONICS[0], a2: float = DEFAULT_HARMONICS[1]) -> None:
        self.amps = np.array([float(a1), float(a2), third_harmonic(a1, a2)])
        self.omegas = 2 * math.pi * np.arange(1, 4)

    @property
    def continuity(self) -> int:
        """3 when f‴(0) = 2π(a₁ + 2a₂ + 3a₃) vanishes (to 1e-12 of its scale), else 2."""
        j0 = float(np.dot(self.amps, self.omegas))
        return 3 if abs(j0) <= 1e-12 * float(np.dot(np.abs(self.amps), self.omegas)) else 2

    def __call__(self, x: Array) -> tuple[Array, Array, Array, Array]:
        x = np.asarray(x, dtype=float)
        arg = x[..., None] * self.omegas              # (…, 3): one column per harmonic
        s, c = np.sin(arg), np.cos(arg)
        a, w = self.amps, self.omegas
        return (np.sum(a * (x[..., None] / w - s / w**2), axis=-1), np.sum(a * (1 - c) / w, axis=-1),
                np.sum(a * s, axis=-1), np.sum(a * w * c, axis=-1))

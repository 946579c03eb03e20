"""The sine–constant–cosine–acceleration (SCCA) family of rest-to-rest rise laws, with an optional
constant-velocity middle (Norton, *Cam Design and Manufacturing Handbook*, 2nd ed. 2009, §3 "the
SCCA family"; Norton, *Design of Machinery*, §8.3).

The normalised acceleration f″(x) = C·α(x), x ∈ [0, 1], is built from five zones whose widths are
set by three fractions b, c, d ≥ 0 with b + c + d = 1:

====================  ==========================  ==========================================
zone                  x from … to                 α
====================  ==========================  ==========================================
1 sine ramp up        0 … b/2                     sin(πx/b)
2 constant            b/2 … (1 − d)/2             1
3 cosine              (1 − d)/2 … (1 + d)/2       cos(π(x − (1 − d)/2)/d)
4 constant            (1 + d)/2 … 1 − b/2         −1
5 sine ramp down      1 − b/2 … 1                 −sin(π(1 − x)/b)
====================  ==========================  ==========================================

so b is the sine-ramp fraction, c the constant-acceleration fraction and d the cosine fraction
(Norton's table of the family's members: constant acceleration b = 0, c = 1, d = 0; simple harmonic
b = 0, c = 0, d = 1; modified trapezoid b = ¼, c = ½, d = ¼; modified sine b = ¼, c = 0, d = ¾;
cycloidal b = ½, c = 0, d = ½).  C = C_a follows from f(1) = 1 (α peaks at 1).

A constant-velocity middle of fraction e (``cruise``, 0 ≤ e < 1) compresses the accelerating half
into x ∈ [0, (1 − e)/2] and the decelerating half into [(1 + e)/2, 1], with f″ = 0 between: the
modified sine or trapezoid "with constant velocity" of indexing drives.

Each zone is integrated in closed form (α = A·sin(ω(x − x₀) + φ) or a constant), the zones' start
values of f and f′ carried from zone to zone (a loop over ≤ 4 zones, never over samples), over the
first half only: the law is point-symmetric about (½, ½), f(x) = 1 − f(1 − x), which also keeps x
near 1 as exact as x near 0.  At x = ½ the derivatives are the right-hand ones.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

Array = np.ndarray

#: fractions below this count as 0
MIN_FRACTION = 1e-9

#: Norton's named members of the family: (b, c, d)
SCCA_MEMBERS: dict[str, tuple[float, float, float]] = {
    "constant_acceleration": (0.0, 1.0, 0.0),
    "harmonic": (0.0, 0.0, 1.0),
    "modified_trapezoid": (0.25, 0.5, 0.25),
    "modified_sine": (0.25, 0.0, 0.75),
    "cycloidal": (0.5, 0.0, 0.5),
}


@dataclass(frozen=True)
class _Zone:
    """α = amp·sin(omega·t + phase) (omega > 0) or α = amp (omega = 0), t = x − x0 ∈ [0, width]."""

    x0: float
    width: float
    amp: float
    omega: float = 0.0
    phase: float = 0.0

    def values(self, t: Array, f0: float, v0: float) -> tuple[Array, Array, Array, Array]:
        """f, f′, f″, f‴ (for C = 1) at t from the zone's start values f0, v0."""
        if self.omega == 0.0:
            return (f0 + v0 * t + 0.5 * self.amp * t * t, v0 + self.amp * t,
                    np.full_like(t, self.amp), np.zeros_like(t))
        w, p, a = self.omega, self.phase, self.amp
        arg = w * t + p
        s, c = np.sin(arg), np.cos(arg)
        cp, sp = math.cos(p), math.sin(p)
        return (f0 + v0 * t + a / w * (t * cp - (s - sp) / w), v0 + a / w * (cp - c), a * s, a * w * c)


class SCCALaw:
    """x ↦ f, f′, f″, f‴ of the SCCA member (b, c, d) with a constant-velocity fraction ``cruise``
    in the middle (a module-level callable: a law made of it pickles).

    Raises:
        ValueError: fractions out of range (the spec's rules name the fields first)."""

    def __init__(self, b: float, c: float, d: float, cruise: float = 0.0) -> None:
        b, c, d, e = float(b), float(c), float(d), float(cruise)
        if min(b, c, d) < 0 or abs(b + c + d - 1.0) > 1e-9 or not 0.0 <= e < 1.0:
            raise ValueError(f"SCCA needs b, c, d ≥ 0 with b + c + d = 1 and 0 ≤ cruise < 1, got "
                             f"{b:g}, {c:g}, {d:g}, {e:g}")
        # a fraction below MIN_FRACTION is 0 (its zone would be narrower than the rounding of x near
        # 1: a ramp that short is a jump); the largest of the three takes up the difference
        parts = [v if v >= MIN_FRACTION else 0.0 for v in (b, c, d)]
        big = int(np.argmax(parts))
        parts[big] = 1.0 - sum(v for i, v in enumerate(parts) if i != big)
        b, c, d = parts
        self.b, self.c, self.d, self.cruise = b, c, d, e
        w = 1.0 - e
        specs = [  # the first half, x ∈ [0, ½]: (width, omega, phase), amplitude 1
            (w * b / 2, math.pi / (w * b) if b else 0.0, 0.0),
            (w * c / 2, 0.0, 0.0),
            (w * d / 2, math.pi / (w * d) if d else 0.0, math.pi / 2),
        ]
        zones, x0 = [], 0.0
        for width, omega, phase in specs:
            if width > 0:
                zones.append(_Zone(x0, width, 1.0, omega, phase))
                x0 += width
        if e > 0:
            zones.append(_Zone(x0, 0.5 - x0, 0.0))           # half the cruise: f″ = 0
        self.zones = tuple(zones)
        starts, f0, v0 = [], 0.0, 0.0
        for z in self.zones:             # ≤ 4 zones: the start values carried across
            starts.append((f0, v0))
            f, v, _, _ = z.values(np.array([z.width]), f0, v0)
            f0, v0 = float(f[0]), float(v[0])
        self._starts = tuple(starts)
        #: C_a: the scale making f(½) = ½, so f(1) = 1 (α peaks at 1)
        self.scale = 0.5 / f0
        self._edges = np.array([z.x0 for z in self.zones])

    @property
    def continuity(self) -> int:
        """Derivatives continuous against dwells: 2 with sine ramps (b > 0), else 1 (f″ jumps)."""
        return 2 if self.b > 0 else 1

    def __call__(self, x: Array) -> tuple[Array, Array, Array, Array]:
        x = np.asarray(x, dtype=float)
        right = x >= 0.5                        # the second half mirrored: 1 − x is exact there
        xm = np.where(right, 1.0 - x, x)
        idx = np.clip(np.searchsorted(self._edges, xm, side="right") - 1, 0, len(self.zones) - 1)
        g = [np.empty(x.shape) for _ in range(4)]
        for k, z in enumerate(self.zones):
            m = idx == k
            if m.any():
                f0, v0 = self._starts[k]
                t = np.minimum(np.maximum(xm[m] - z.x0, 0.0), z.width)
                for o, val in zip(g, z.values(t, f0, v0)):
                    o[m] = self.scale * val
        # point symmetry about (½, ½): f(x) = 1 − g(1 − x), f′ = g′, f″ = −g″, f‴ = g‴
        return (np.where(right, 1.0 - g[0], g[0]), g[1], np.where(right, -g[2], g[2]), g[3])

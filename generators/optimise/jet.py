"""Forward-mode derivatives for the optimiser's local formulas: a :class:`Jet` carries values
(m,) and their exact partial derivatives (m, k) with respect to k seeded inputs through
+, −, ×, ÷, powers, √, sin, cos, arccos, arctan and :func:`where`.

The follower kinds' check formulas (:mod:`cam_workbench.generators.optimise.kinds`) are written once with the
functions below and run either on plain numpy arrays (values only: the dense window scans) or on
jets (values with their partials: the solver's Jacobian).  The derivatives are the chain rule
applied exactly, operation by operation — not differences — and every operation is analytic, so
the same code also accepts complex numbers: the tests check the jets' partials against
complex-step derivatives of the values (an independent, rounding-exact reference).
"""
from __future__ import annotations

from typing import Any

import numpy as np


class Jet:
    """Values ``v`` (m,) with partials ``d`` (m, k)."""

    __slots__ = ("v", "d")
    __array_ufunc__ = None             # numpy arrays and scalars defer to Jet's reflected operators

    def __init__(self, v: Any, d: np.ndarray):
        self.v = v
        self.d = d

    # ---- arithmetic ---------------------------------------------------------------------
    def __add__(self, o: Any) -> "Jet":
        if isinstance(o, Jet):
            return Jet(self.v + o.v, self.d + o.d)
        return Jet(self.v + o, self.d)

    __radd__ = __add__

    def __sub__(self, o: Any) -> "Jet":
        if isinstance(o, Jet):
            return Jet(self.v - o.v, self.d - o.d)
        return Jet(self.v - o, self.d)

    def __rsub__(self, o: Any) -> "Jet":
        return Jet(o - self.v, -self.d)

    def __neg__(self) -> "Jet":
        return Jet(-self.v, -self.d)

    def __mul__(self, o: Any) -> "Jet":
        if isinstance(o, Jet):
            return Jet(self.v * o.v, self.d * _col(o.v) + o.d * _col(self.v))
        return Jet(self.v * o, self.d * _col(o))

    __rmul__ = __mul__

    def __truediv__(self, o: Any) -> "Jet":
        if isinstance(o, Jet):
            q = self.v / o.v
            return Jet(q, (self.d - o.d * _col(q)) / _col(o.v))
        return Jet(self.v / o, self.d / _col(o))

    def __rtruediv__(self, o: Any) -> "Jet":
        q = o / self.v
        return Jet(q, -self.d * _col(q / self.v))

    def __pow__(self, n: float) -> "Jet":
        if isinstance(n, Jet):
            raise TypeError("Jet ** Jet is not needed here")
        return Jet(self.v**n, self.d * _col(n * self.v ** (n - 1)))

    @property
    def real(self) -> Any:
        """The real part of the values (for comparisons and branch choices)."""
        return np.real(self.v)


def _col(x: Any) -> Any:
    x = np.asarray(x)
    return x[..., None] if x.ndim else x


def value(x: Any) -> Any:
    """The value of a jet or a plain number/array."""
    return x.v if isinstance(x, Jet) else x


def real(x: Any) -> Any:
    """The real part of the value (for branch decisions: a complex step never changes a branch)."""
    return np.real(value(x))


def _unary(x: Any, f: Any, df: Any) -> Any:
    if isinstance(x, Jet):
        return Jet(f(x.v), x.d * _col(df(x.v)))
    return f(x)


def sqrt(x: Any) -> Any:
    return _unary(x, np.sqrt, lambda v: 0.5 / np.sqrt(v))


def sin(x: Any) -> Any:
    return _unary(x, np.sin, np.cos)


def cos(x: Any) -> Any:
    return _unary(x, np.cos, lambda v: -np.sin(v))


def arccos(x: Any) -> Any:
    return _unary(x, np.arccos, lambda v: -1.0 / np.sqrt(1.0 - v * v))


def arctan(x: Any) -> Any:
    return _unary(x, np.arctan, lambda v: 1.0 / (1.0 + v * v))


def where(cond: np.ndarray, a: Any, b: Any) -> Any:
    """Elementwise choice (``cond`` a boolean array decided on real parts)."""
    if not isinstance(a, Jet) and not isinstance(b, Jet):
        return np.where(cond, a, b)
    ja, jb = a if isinstance(a, Jet) else None, b if isinstance(b, Jet) else None
    ref = ja or jb
    k = ref.d.shape[-1]
    m = np.broadcast_shapes(np.shape(cond), np.shape(value(a)), np.shape(value(b)))
    da = ja.d if ja is not None else np.zeros(m + (k,), dtype=ref.d.dtype)
    db = jb.d if jb is not None else np.zeros(m + (k,), dtype=ref.d.dtype)
    return Jet(np.where(cond, value(a), value(b)), np.where(np.asarray(cond)[..., None], da, db))


def seed(values: list[Any], m: int, dtype: Any) -> list[Jet]:
    """Jets of the inputs ``values`` (scalars or (m,) arrays), the i-th with unit partial i."""
    k = len(values)
    out = []
    for i, v in enumerate(values):
        d = np.zeros((m, k), dtype=dtype)
        d[:, i] = 1.0
        out.append(Jet(np.broadcast_to(np.asarray(v, dtype=dtype), (m,)).copy(), d))
    return out


def unpack(x: Any, m: int, k: int, dtype: Any) -> tuple[np.ndarray, ...]:
    """(value, ∂/∂input₀, …, ∂/∂input_{k−1}) of a jet (or a constant) as (m,) arrays."""
    if isinstance(x, Jet):
        v = np.broadcast_to(x.v, (m,))
        d = np.broadcast_to(x.d, (m, k))
        return (v, *(d[:, i] for i in range(k)))
    z = np.zeros(m, dtype=dtype)
    return (np.broadcast_to(np.asarray(x, dtype=dtype), (m,)), *([z] * k))

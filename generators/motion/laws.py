"""Normalised rise laws f(x), x ∈ [0, 1], f(0) = 0, f(1) = 1, in closed form with
exact derivatives f', f'', f''' with respect to x (vectorised over x).

A rise of height h over β radians starting at θ₀ is s = h·f((θ−θ₀)/β); a return is
s = h·(1 − f(x)).  Derivatives with respect to θ are h·f⁽ⁿ⁾/βⁿ.

Two kinds: the rest-to-rest laws (:data:`LAW_FUNCTIONS`: f′ = 0 at both ends, joined to dwells)
and the quick-return laws (:data:`QUICK_RETURN_FUNCTIONS`: from rest into a reversal — f′ = 0,
f″ ≠ 0, the follower turns back — or out of one, for a rise running straight into a return with
the acceleration carried over the top).

Modified sine and modified trapezoid are built from their acceleration pieces
(Norton, *Cam Design and Manufacturing Handbook*, §3); the constants here are the
exact symbolic integrals (A = 4π²/(π+4) and 8π/(π+2)), which reproduce Norton's
decimals 0.43990085, 0.0350062, 0.31505577 and 0.28004957.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Hashable

import numpy as np

Array = np.ndarray
LawFn = Callable[[Array], tuple[Array, Array, Array, Array]]

_PI = np.pi
_TWO_PI = 2 * np.pi


def cycloidal(x: Array) -> tuple[Array, Array, Array, Array]:
    """Cycloidal: f = x − sin(2πx)/(2π) (paper Eq. 8 normalised)."""
    a = _TWO_PI * x
    return (x - np.sin(a) / _TWO_PI, 1 - np.cos(a), _TWO_PI * np.sin(a), _TWO_PI**2 * np.cos(a))


def harmonic(x: Array) -> tuple[Array, Array, Array, Array]:
    """Simple harmonic: f = (1 − cos πx)/2."""
    a = _PI * x
    return ((1 - np.cos(a)) / 2, _PI / 2 * np.sin(a), _PI**2 / 2 * np.cos(a), -(_PI**3) / 2 * np.sin(a))


def poly345(x: Array) -> tuple[Array, Array, Array, Array]:
    """3-4-5 polynomial: f = 10x³ − 15x⁴ + 6x⁵."""
    x2 = x * x
    return (
        x2 * x * (10 - 15 * x + 6 * x2),
        x2 * (30 - 60 * x + 30 * x2),
        x * (60 - 180 * x + 120 * x2),
        60 - 360 * x + 360 * x2,
    )


def poly4567(x: Array) -> tuple[Array, Array, Array, Array]:
    """4-5-6-7 polynomial: f = 35x⁴ − 84x⁵ + 70x⁶ − 20x⁷."""
    x2 = x * x
    x3 = x2 * x
    return (
        x3 * x * (35 - 84 * x + 70 * x2 - 20 * x3),
        x3 * (140 - 420 * x + 420 * x2 - 140 * x3),
        x2 * (420 - 1680 * x + 2100 * x2 - 840 * x3),
        x * (840 - 5040 * x + 8400 * x2 - 4200 * x3),
    )


def _sine_ramp(x: Array, amp: float, offset: float) -> tuple[Array, Array, Array, Array]:
    """A·(x/(4π) − sin(4πx)/(16π²)) + offset and derivatives: the 1/8-period sine
    ramps shared by modified sine and modified trapezoid."""
    k = 4 * _PI
    s, c = np.sin(k * x), np.cos(k * x)
    return (
        amp * (x / k - s / k**2) + offset,
        amp * (1 / k - c / k),
        amp * s,
        amp * k * c,
    )


def modified_sine(x: Array) -> tuple[Array, Array, Array, Array]:
    """Modified sine: sine acceleration pieces over [0,⅛], [⅛,⅞], [⅞,1]."""
    x = np.asarray(x, dtype=float)
    amp = 4 * _PI**2 / (_PI + 4)
    out = [np.empty_like(x) for _ in range(4)]
    m1 = x < 0.125
    m3 = x > 0.875
    m2 = ~(m1 | m3)
    for m, off in ((m1, 0.0), (m3, 1.0 / _PI**2)):
        if m.any():
            vals = _sine_ramp(x[m], amp, amp * off)
            for o, v in zip(out, vals):
                o[m] = v
    if m2.any():
        xm = x[m2]
        k = 4 * _PI / 3
        a = k * xm + _PI / 3
        s, c = np.sin(a), np.cos(a)
        out[0][m2] = amp * (xm / (4 * _PI) - 9 * s / (16 * _PI**2) + 1 / (2 * _PI**2))
        out[1][m2] = amp * (1 / (4 * _PI) - 9 * k * c / (16 * _PI**2))
        out[2][m2] = amp * (9 * k**2 * s / (16 * _PI**2))
        out[3][m2] = amp * (9 * k**3 * c / (16 * _PI**2))
    return tuple(out)  # type: ignore[return-value]


def modified_trapezoid(x: Array) -> tuple[Array, Array, Array, Array]:
    """Modified trapezoid: sine ramps of ⅛ joined by constant-acceleration pieces."""
    x = np.asarray(x, dtype=float)
    amp = 8 * _PI / (_PI + 2)
    k = 4 * _PI
    out = [np.empty_like(x) for _ in range(4)]
    edges = np.array([0.125, 0.375, 0.625, 0.875])
    piece = np.searchsorted(edges, x, side="right")
    # piece 0 and 4: sine ramps
    for idx, off in ((0, 0.0), (4, 0.125)):
        m = piece == idx
        if m.any():
            vals = _sine_ramp(x[m], amp, amp * off)
            for o, v in zip(out, vals):
                o[m] = v
    m = piece == 1  # constant +A
    if m.any():
        xm = x[m]
        out[0][m] = amp * (xm**2 / 2 - xm / 8 + xm / k - 1 / k**2 + 1 / 128)
        out[1][m] = amp * (xm - 1 / 8 + 1 / k)
        out[2][m] = amp
        out[3][m] = 0.0
    m = piece == 2  # cosine from +A to −A
    if m.any():
        xm = x[m]
        s, c = np.sin(k * xm), np.cos(k * xm)
        out[0][m] = amp * (xm / k + xm / 4 + s / k**2 - 1 / 16)
        out[1][m] = amp * (1 / k + 1 / 4 + c / k)
        out[2][m] = amp * (-s)
        out[3][m] = amp * (-k * c)
    m = piece == 3  # constant −A
    if m.any():
        xm = x[m]
        out[0][m] = amp * (-(xm**2) / 2 + xm / k + 7 * xm / 8 - 33 / 128 + 1 / k**2)
        out[1][m] = amp * (-xm + 1 / k + 7 / 8)
        out[2][m] = -amp
        out[3][m] = 0.0
    return tuple(out)  # type: ignore[return-value]


def quick_return_out(x: Array) -> tuple[Array, Array, Array, Array]:
    """Quick return, rest → reversal: f = (20x³ − 25x⁴ + 8x⁵)/3, the quintic with f = f′ = f″ = 0
    at x = 0 and f = 1, f′ = 0, f‴ = 0 at x = 1, where f″ = −20/3 (the turning point; MechDesigner's
    "Throw: Quick-Return 1" rise).  f′ = 20x²(1 − x)(3 − 2x)/3 ≥ 0, f‴ = 40(1 − x)(1 − 4x)."""
    x2 = x * x
    return (
        x2 * x * (20 - 25 * x + 8 * x2) / 3,
        x2 * (60 - 100 * x + 40 * x2) / 3,
        x * (120 - 300 * x + 160 * x2) / 3,
        40 - 200 * x + 160 * x2,
    )


def quick_return_in(x: Array) -> tuple[Array, Array, Array, Array]:
    """Quick return, reversal → rest: the mirror g(x) = 1 − f(1 − x) of :func:`quick_return_out`,
    expanded: g = (10x² − 15x⁴ + 8x⁵)/3 (g′(x) = f′(1 − x), g″(x) = −f″(1 − x), g‴(x) = f‴(1 − x)),
    so g′(0) = 0, g″(0) = 20/3, g‴(0) = 0 at the turning point and g = 1, g′ = g″ = 0 at x = 1."""
    x2 = x * x
    return (
        x2 * (10 - 15 * x2 + 8 * x2 * x) / 3,
        x * (20 - 60 * x2 + 40 * x2 * x) / 3,
        (20 - 180 * x2 + 160 * x2 * x) / 3,
        x * (160 * x - 120),
    )


LAW_FUNCTIONS: dict[str, LawFn] = {
    "cycloidal": cycloidal,
    "harmonic": harmonic,
    "modified_sine": modified_sine,
    "modified_trapezoid": modified_trapezoid,
    "poly345": poly345,
    "poly4567": poly4567,
}

#: Highest derivative of a rest-to-rest law that is continuous at the segment ends when joined to
#: dwells (velocity = 1, acceleration = 2, jerk = 3); used by the tests and the docs.
END_CONTINUITY: dict[str, int] = {
    "cycloidal": 2,
    "harmonic": 1,
    "modified_sine": 2,
    "modified_trapezoid": 2,
    "poly345": 2,
    "poly4567": 3,
}

#: The quick-return closed forms (VDI 2143 tasks rest → reversal and reversal → rest; MechDesigner's
#: "Throw: Quick-Return" made of two segments): a rise (or return) ending at its turning point
#: takes "quick_return_out", the return (or rise) starting there "quick_return_in".  Not in
#: :data:`LAW_FUNCTIONS`: they are no index laws (an indexer's turret rests after its index).
QUICK_RETURN_FUNCTIONS: dict[str, LawFn] = {
    "quick_return_out": quick_return_out,
    "quick_return_in": quick_return_in,
}
#: The end of each quick-return law at the turning point (0 the start, 1 the end)
TURNING_END: dict[str, int] = {"quick_return_out": 1, "quick_return_in": 0}
#: Continuity of a quick-return law's rest end against a dwell: f′ = f″ = 0 there, f‴ = ±40
QUICK_RETURN_REST_CONTINUITY = 2
#: Continuity a turning end promises: f′ = 0 and f″ = ∓20/3 carried into a neighbour that turns
#: with the same s″ = ∓(20/3)·h/β² (the mirror law over an equal h/β², or a polynomial taking it);
#: against a dwell, or the mirror over another h/β², the acceleration jumps there.
TURNING_CONTINUITY = 2


@dataclass(frozen=True, eq=False)
class NormalisedLaw:
    """A normalised rise law f(x), x ∈ [0, 1], f(0) = 0, f(1) = 1, as a value: ``name`` (what the
    summaries print: "modified_sine", "polynomial", "bspline" …), ``fn`` (x ↦ f and its first three
    derivatives, vectorised), ``continuity`` (the highest derivative continuous against dwells at
    its rest ends — both ends but a quick-return law's turning end —, as :data:`END_CONTINUITY`; 0
    when f′ ≠ 0 at an end), ``key`` (what makes two laws equal: hashable, by value) and
    ``turning_end`` (None, or the end, 0 or 1, at a quick-return law's turning point:
    :data:`TURNING_END`).  The closed forms are :data:`CLOSED_FORM_LAWS`; :meth:`from_segment`
    makes one of a motion program's rise (polynomial, bspline, constant_velocity, table)."""

    name: str
    fn: LawFn = field(repr=False)
    continuity: int = 2
    key: Hashable = None
    turning_end: int | None = None

    def __eq__(self, other: object) -> bool:
        return isinstance(other, NormalisedLaw) and (self.name, self.key) == (other.name, other.key)

    def __hash__(self) -> int:
        return hash((NormalisedLaw, self.name, self.key))

    def __str__(self) -> str:
        return self.name

    def evaluate(self, x: Array) -> tuple[Array, Array, Array, Array]:
        """f, f′, f″, f‴ at normalised positions ``x`` ∈ [0, 1] (arrays of x's shape)."""
        return evaluate_law(self, x)

    @property
    def promises(self) -> tuple[int, int]:
        """(start, end) order of continuity the law promises at its ends: ``continuity`` at a rest
        end, :data:`TURNING_CONTINUITY` at a turning end."""
        start, end = (TURNING_CONTINUITY if e == self.turning_end else self.continuity for e in (0, 1))
        return start, end

    @classmethod
    def from_segment(cls, program: Any, k: int) -> "NormalisedLaw":
        """Rise ``k`` of motion program ``program`` (a :class:`~.program.MotionProgram`) normalised:
        F(u) = (s(θ_k + β·u) − s(θ_k))/h, F⁽ⁿ⁾ = s⁽ⁿ⁾·βⁿ/h, evaluated by the program's own segment
        evaluation (one-sided at the ends); a closed-form segment gives its closed form.  Equal
        programs give equal laws (the key is the segment's solved curve, by value); the end
        continuity is measured (:func:`_measured_continuity`)."""
        law = program.laws[k]
        if isinstance(law, LawName):                 # a parametric closed form: the law itself
            return law.law
        if law in CLOSED_FORM_LAWS:
            return CLOSED_FORM_LAWS[law]
        beta, h = float(program.spans[k]), float(program.lifts[k])
        if not h:
            raise ValueError(f"segment {k} of the program is a dwell: no law")
        fn = _ProgramRise(program, k)
        curve = program.curves[k] if program.curves else None
        key: Hashable = (law, beta, h) if curve is None else (
            law, beta, h, int(curve.order), tuple(np.asarray(curve.x, float).tolist()),
            tuple(np.asarray(curve.y, float).tolist()), tuple(np.asarray(curve.knots, float).tolist()))
        return cls(str(law), fn, fn.continuity, key)


class _ProgramRise:
    """x ↦ F, F′, F″, F‴ of segment ``k`` of a motion program (a module-level callable, not a
    closure: a law made of it pickles with its program)."""

    def __init__(self, program: Any, k: int) -> None:
        self.program, self.k = program, int(k)
        self.continuity = 3
        self.continuity = _measured_continuity(self._raw)

    def _raw(self, x: Array) -> tuple[Array, Array, Array, Array]:
        prog, k = self.program, self.k
        start, beta, h, level = (float(prog.starts[k]), float(prog.spans[k]), float(prog.lifts[k]),
                                 float(prog.levels[k]))
        x = np.asarray(x, dtype=float)
        u = np.minimum(np.maximum(x, 0.0), 1.0).ravel()        # the program evaluates arrays (not 0-d)
        kin = prog.evaluate(start + beta * u, np.full(u.shape, k))
        return tuple(np.reshape(v, x.shape) for v in ((kin.s - level) / h, kin.ds * beta / h,  # type: ignore[return-value]
                                                         kin.d2s * beta**2 / h, kin.d3s * beta**3 / h))

    def __call__(self, x: Array) -> tuple[Array, Array, Array, Array]:
        # at the ends exactly: f = 0, 1 and the derivatives the law takes to rest exactly 0 (the
        # solved or fitted law's rounding there, ~1e-14, would otherwise read as motion)
        x = np.asarray(x, dtype=float)
        vals = [np.array(v, dtype=float) for v in self._raw(x)]
        lo, hi = x <= 0.0, x >= 1.0
        vals[0][lo], vals[0][hi] = 0.0, 1.0
        for n in range(1, self.continuity + 1):
            vals[n][lo | hi] = 0.0
        return tuple(vals)  # type: ignore[return-value]


def _measured_continuity(fn: LawFn) -> int:
    """The highest n ≤ 3 with f′ … f⁽ⁿ⁾ zero at both ends (within 1e-8 of their peak over the
    rise, at least 1e-8 absolute): 0 when f′ is not."""
    x = np.linspace(0.0, 1.0, 1025)
    vals = fn(x)
    order = 0
    for n in (1, 2, 3):
        d = np.asarray(vals[n], dtype=float)
        if max(abs(d[0]), abs(d[-1])) > 1e-8 * max(1.0, float(np.max(np.abs(d)))):
            break
        order = n
    return order


#: every closed-form law by name as a :class:`NormalisedLaw`: the rest-to-rest laws, then the
#: quick-return laws
CLOSED_FORM_LAWS: dict[str, NormalisedLaw] = {
    **{name: NormalisedLaw(name, fn, END_CONTINUITY[name], name) for name, fn in LAW_FUNCTIONS.items()},
    **{name: NormalisedLaw(name, fn, QUICK_RETURN_REST_CONTINUITY, name, TURNING_END[name])
       for name, fn in QUICK_RETURN_FUNCTIONS.items()},
}


class LawName(str):
    """A parametric closed-form law as a motion program carries it in ``MotionProgram.laws``: the
    law's name as a string (what summaries, messages and report.json print: "scca", …) that also
    holds the law itself, ``.law`` (a :class:`NormalisedLaw` with the segment's parameters), so
    every consumer that evaluates a program's law by name evaluates the parametric one.  Two are
    equal when their laws are (a plain string equals it by name only); it pickles with its law.
    Made by :func:`~.law_library.segment_law`."""

    law: NormalisedLaw

    def __new__(cls, law: NormalisedLaw) -> "LawName":
        obj = super().__new__(cls, law.name)
        obj.law = law
        return obj

    def __reduce__(self) -> tuple[Any, ...]:
        return (LawName, (self.law,))

    def __eq__(self, other: object) -> bool:
        if isinstance(other, LawName):
            return self.law == other.law
        return str.__eq__(self, other)

    def __ne__(self, other: object) -> bool:
        return not self == other

    def __hash__(self) -> int:
        return hash(self.law)


def as_law(law: "str | NormalisedLaw") -> "str | NormalisedLaw":
    """``law`` with a :class:`LawName` unwrapped to its :class:`NormalisedLaw` (else unchanged)."""
    return law.law if isinstance(law, LawName) else law


def is_law(law: Any) -> bool:
    """Whether an indexer's geometry takes ``law``: a key of ``LAW_FUNCTIONS`` (by name the
    rest-to-rest laws only), a :class:`NormalisedLaw` or a :class:`LawName`."""
    return isinstance(law, (NormalisedLaw, LawName)) or (isinstance(law, str) and law in LAW_FUNCTIONS)


def law_name(law: "str | NormalisedLaw") -> str:
    """The law's name ("modified_sine", "polynomial", …): what summaries and titles print."""
    return law.name if isinstance(law, NormalisedLaw) else str(law)


def end_continuity(law: "str | NormalisedLaw") -> int:
    """The continuity against dwells at the law's rest ends (:attr:`NormalisedLaw.continuity`) of a
    closed form by name (:data:`END_CONTINUITY` for the rest-to-rest laws), a
    :class:`NormalisedLaw`'s (or a :class:`LawName`'s) own."""
    law = as_law(law)
    return (law if isinstance(law, NormalisedLaw) else CLOSED_FORM_LAWS[law]).continuity


def evaluate_law(name: "str | NormalisedLaw", x: Array) -> tuple[Array, Array, Array, Array]:
    """f, f', f'', f''' of law ``name`` (a key of ``CLOSED_FORM_LAWS``, a :class:`NormalisedLaw` or a
    :class:`LawName`) at normalised positions ``x`` ∈ [0, 1]."""
    name = as_law(name)
    fn = (name if isinstance(name, NormalisedLaw) else CLOSED_FORM_LAWS[name]).fn
    x = np.asarray(x, dtype=float)
    # a law's terms are arrays of x's shape, or constants (a polynomial's last derivative) to spread
    return tuple(v if isinstance(v, np.ndarray) and v.shape == x.shape and v.dtype == float
                 else np.broadcast_to(v, x.shape).astype(float) for v in fn(x))  # type: ignore[return-value]

"""The parametric closed-form rise laws a motion segment may name, and how a segment's fields make
one (:func:`segment_law`):

* ``scca``: Norton's sine–constant–cosine–acceleration family (:mod:`.scca`), fractions ``scca_b``,
  ``scca_c``, ``scca_d`` (sum 1) and an optional constant-velocity middle ``cruise_fraction``;
* ``modified_sine_cv``, ``modified_trapezoid_cv``: the SCCA members modified sine (b, c, d =
  ¼, 0, ¾) and modified trapezoid (¼, ½, ¼) with a constant-velocity middle of ``cruise_fraction``;
* ``triple_harmonic``: acceleration as three harmonics (:mod:`.triple_harmonic`), amplitudes
  ``harmonic_1``, ``harmonic_2`` (default 9π/4, 0: zero jerk at the ends and the crossover);
* ``poly345_throw``, ``poly4567_throw``: the 3-4-5 and 4-5-6-7 laws with the velocity peak at
  ``velocity_peak_at`` (:mod:`.throw_polynomials`).

A program carries such a law as a :class:`~.laws.LawName` (its name, holding the law).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from ..errors import SpecError, fmt_apart
from .laws import CLOSED_FORM_LAWS, LawName, NormalisedLaw
from .scca import SCCA_MEMBERS, SCCALaw
from .throw_polynomials import ThrowPolynomialLaw
from .triple_harmonic import DEFAULT_HARMONICS, TripleHarmonicLaw, third_harmonic

#: |b + c + d − 1| allowed (the fractions are typed decimals)
SUM_TOL = 1e-9


@dataclass(frozen=True)
class ParametricLaw:
    """A parametric law: the segment ``fields`` it reads (``required`` ones among them) and
    ``build(values, path)`` making the :class:`~.laws.NormalisedLaw` (raising SpecError naming
    ``path.field``)."""

    name: str
    fields: tuple[str, ...]
    required: tuple[str, ...]
    build: Callable[[dict[str, Any], str], NormalisedLaw]


def _law(name: str, fn: Any, key: tuple[Any, ...]) -> NormalisedLaw:
    return NormalisedLaw(name, fn, fn.continuity, (name, *key))


def scca_law(b: float, c: float, d: float, cruise: float = 0.0, name: str = "scca") -> NormalisedLaw:
    """The SCCA member (b, c, d) with a constant-velocity middle fraction ``cruise`` as a law."""
    return _law(name, SCCALaw(b, c, d, cruise), (float(b), float(c), float(d), float(cruise)))


def _build_scca(v: dict[str, Any], path: str) -> NormalisedLaw:
    b, c, d = (float(v[k]) for k in ("scca_b", "scca_c", "scca_d"))
    total = b + c + d
    if abs(total - 1.0) > SUM_TOL:
        raise SpecError(f"{path}.scca_d", f"scca_b + scca_c + scca_d = {b:g} + {c:g} + {d:g} = "
                        f"{fmt_apart(total, 1.0)} must be 1 (the fractions of the rise's acceleration "
                        "shape: sine ramps, constant, cosine)")
    cruise = float(v.get("cruise_fraction") or 0.0)
    d = 1.0 - b - c if d else 0.0                   # the sum exactly 1
    return scca_law(b, c, max(d, 0.0), cruise)


def _preset(member: str, name: str) -> Callable[[dict[str, Any], str], NormalisedLaw]:
    def build(v: dict[str, Any], path: str) -> NormalisedLaw:
        return scca_law(*SCCA_MEMBERS[member], float(v["cruise_fraction"]), name=name)

    return build


def _build_triple(v: dict[str, Any], path: str) -> NormalisedLaw:
    a1 = DEFAULT_HARMONICS[0] if v.get("harmonic_1") is None else float(v["harmonic_1"])
    a2 = DEFAULT_HARMONICS[1] if v.get("harmonic_2") is None else float(v["harmonic_2"])
    fn = TripleHarmonicLaw(a1, a2)
    x = np.linspace(0.0, 1.0, 4097)
    f1 = fn(x)[1]
    if np.min(f1) < -1e-12:
        at = float(x[np.argmin(f1)])
        fld = "harmonic_2" if v.get("harmonic_2") is not None and v.get("harmonic_1") is None else "harmonic_1"
        raise SpecError(f"{path}.{fld}", f"harmonic_1 = {a1:.6g}, harmonic_2 = {a2:.6g} (so the third "
                        f"{third_harmonic(a1, a2):.6g}) make the velocity negative at x = {at:.4g} of the "
                        "segment: not a rise (f′ ≥ 0); e.g. harmonic_1 = 2π, harmonic_2 = 0 is the cycloidal law")
    return _law("triple_harmonic", fn, (a1, a2))


def _throw(family: str) -> Callable[[dict[str, Any], str], NormalisedLaw]:
    def build(v: dict[str, Any], path: str) -> NormalisedLaw:
        p = float(v["velocity_peak_at"])
        return _law(f"{family}_throw", ThrowPolynomialLaw(family, p), (p,))

    return build


PARAMETRIC_LAWS: dict[str, ParametricLaw] = {
    "scca": ParametricLaw("scca", ("scca_b", "scca_c", "scca_d", "cruise_fraction"),
                          ("scca_b", "scca_c", "scca_d"), _build_scca),
    "modified_sine_cv": ParametricLaw("modified_sine_cv", ("cruise_fraction",), ("cruise_fraction",),
                                      _preset("modified_sine", "modified_sine_cv")),
    "modified_trapezoid_cv": ParametricLaw("modified_trapezoid_cv", ("cruise_fraction",), ("cruise_fraction",),
                                           _preset("modified_trapezoid", "modified_trapezoid_cv")),
    "triple_harmonic": ParametricLaw("triple_harmonic", ("harmonic_1", "harmonic_2"), (), _build_triple),
    "poly345_throw": ParametricLaw("poly345_throw", ("velocity_peak_at",), ("velocity_peak_at",),
                                   _throw("poly345")),
    "poly4567_throw": ParametricLaw("poly4567_throw", ("velocity_peak_at",), ("velocity_peak_at",),
                                    _throw("poly4567")),
}


def parametric_law(name: str, values: dict[str, Any], path: str = "motion") -> NormalisedLaw:
    """The parametric law ``name`` with field ``values`` (absent fields None or missing).

    Raises:
        SpecError: a required field missing or a rule broken, naming ``path.field``."""
    spec = PARAMETRIC_LAWS[name]
    for fld in spec.required:
        if values.get(fld) is None:
            raise SpecError(f"{path}.{fld}", f'is required for law = "{name}"')
    return spec.build(values, path)


def segment_law(seg: Any, path: str = "motion") -> "str | LawName | None":
    """The law a motion program carries for segment ``seg`` (a ``MotionSegment``): None for a dwell,
    the name for the closed forms and the solved laws, a :class:`~.laws.LawName` for a parametric
    law (its fields read from the segment)."""
    law = seg.law
    if law not in PARAMETRIC_LAWS:
        return law
    fields = PARAMETRIC_LAWS[law].fields
    return LawName(parametric_law(law, {f: getattr(seg, f, None) for f in fields}, path))


def library_laws() -> dict[str, "str | NormalisedLaw"]:
    """Every closed-form law of the library with its default or a representative parameter set, by
    the label the docs' table prints: the fixed closed forms (the rest-to-rest laws and the quick
    returns), the SCCA members, the presets with a third at constant velocity, the triple harmonic
    and the throw laws peaking at 0.4."""
    out: dict[str, str | NormalisedLaw] = {n: n for n in CLOSED_FORM_LAWS}
    for member, (b, c, d) in SCCA_MEMBERS.items():
        out[f"scca b={b:g} c={c:g} d={d:g} ({member})"] = scca_law(b, c, d)
    out["modified_sine_cv cruise_fraction=1/3"] = scca_law(*SCCA_MEMBERS["modified_sine"], 1 / 3,
                                                          name="modified_sine_cv")
    out["modified_trapezoid_cv cruise_fraction=1/3"] = scca_law(*SCCA_MEMBERS["modified_trapezoid"], 1 / 3,
                                                               name="modified_trapezoid_cv")
    out["triple_harmonic (9π/4, 0)"] = parametric_law("triple_harmonic", {})
    out["triple_harmonic (2π, 0) = cycloidal"] = parametric_law("triple_harmonic", {"harmonic_1": 2 * math.pi})
    out["poly345_throw velocity_peak_at=0.4"] = parametric_law("poly345_throw", {"velocity_peak_at": 0.4})
    out["poly4567_throw velocity_peak_at=0.4"] = parametric_law("poly4567_throw", {"velocity_peak_at": 0.4})
    return out

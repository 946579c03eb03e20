"""The indexers' field rules shared by their parameter classes: a finite number, an integer with
its own rule — each refused with a :class:`SpecError` naming ``indexer.<field>``."""
from __future__ import annotations

import math
import operator
from typing import Any, Callable

import numpy as np

from ...errors import SpecError


def number(field_: str, value: Any) -> float:
    """``value`` as a float (SpecError unless a finite real number, booleans refused)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise SpecError(f"indexer.{field_}", f"must be a number, got {value!r}")
    if not math.isfinite(value):
        raise SpecError(f"indexer.{field_}", f"must be finite, got {value!r}")
    return float(value)


def integer(field_: str, value: Any, allowed: str, ok: Callable[[int], bool]) -> int:
    """``value`` as an int satisfying ``ok`` (SpecError saying ``allowed`` otherwise)."""
    try:
        n = operator.index(value)
    except TypeError:
        n = None
    if n is None or isinstance(value, bool) or not ok(n):
        raise SpecError(f"indexer.{field_}", f"must be {allowed}, got {value!r}")
    return n

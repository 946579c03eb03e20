"""How the golden test compares a new observation with the recorded one.

* **Numbers** (floats): equal within ``RTOL = 1e-12`` relative, with an absolute floor for values
  that are zero or at rounding-noise level: ``|new − old| ≤ max(1e-12 · max(|old|, |new|),
  1e-14 · scale)``, where ``scale`` is the largest magnitude of any number in the *record* that
  holds the value — the innermost JSON object around it (a report.json section such as
  ``motion.junctions[2].left``, one DXF entity, one solid's probes), read from the recording.
  ``FLOOR = 1e-14`` of the record's largest number is ~45 units in its last place: the rounding
  noise a value that is mathematically zero carries (a junction's acceleration of −7e-15 beside a
  jerk of 86 may become 0 or ±8.6e-13; a control point's x of −2.4e-16 beside y = 32 may become
  ±3.2e-13).  A value is held looser than 1e-12 of itself only when it is below 1 % of the largest
  number in its record.  NaN equals NaN.
* **Integers, booleans, null**: equal.  A number's JSON type may not change (``20`` is not ``20.0``
  in report.json).
* **Text** (every string, dictionary keys too): identical after :func:`names.normalise` — the
  renamed import names and class, dates, versions; the temporary folder was replaced by ``<tmp>``
  when observed.
* **Structure**: the same keys and list lengths; a key that appears or disappears is a mismatch.
"""
from __future__ import annotations

import difflib
import math
from dataclasses import dataclass
from typing import Any, Iterator

from .names import normalise

RTOL = 1e-12
#: the absolute floor, as a fraction of the largest magnitude in the value's record
FLOOR = 1e-14


@dataclass(frozen=True)
class Mismatch:
    """One difference: the output (e.g. ``cli build: report.json``), the path inside it
    (``checks.results.pressure_angle.value``), the recorded and the new value, and why."""
    output: str
    path: str
    recorded: Any
    new: Any
    why: str

    def __str__(self) -> str:
        where = f"{self.output}: {self.path}" if self.path else self.output
        return f"{where}: {self.why}\n    recorded: {_short(self.recorded)}\n    new:      {_short(self.new)}"


def _short(value: Any, limit: int = 300) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[:limit] + f"… ({len(text)} characters)"


def magnitude(value: Any) -> float:
    """The largest |x| of the numbers (not booleans) anywhere in ``value``; 0 if none."""
    if isinstance(value, bool):
        return 0.0
    if isinstance(value, (int, float)):
        return abs(value) if math.isfinite(value) else 0.0
    if isinstance(value, dict):
        return max((magnitude(v) for v in value.values()), default=0.0)
    if isinstance(value, list):
        return max((magnitude(v) for v in value), default=0.0)
    return 0.0


def _join(path: str, key: str | int) -> str:
    if isinstance(key, int):
        return f"{path}[{key}]"
    return f"{path}.{key}" if path else str(key)


def _text_diff(old: str, new: str) -> str:
    """Where two texts differ: the first differing line and how many lines differ."""
    a, b = old.splitlines(), new.splitlines()
    for i, (x, y) in enumerate(zip(a, b)):
        if x != y:
            first = f"line {i + 1} differs"
            break
    else:
        first = f"the texts differ in length ({len(a)} vs {len(b)} lines)" if len(a) != len(b) else \
            "the texts differ in line endings or trailing whitespace"
    changed = sum(1 for tag, i1, i2, j1, j2 in difflib.SequenceMatcher(None, a, b, autojunk=False).get_opcodes()
                  if tag != "equal" for _ in range(max(i2 - i1, j2 - j1)))
    return f"text differs: {first}; {changed} of {len(a)} lines changed"


def _first_lines(old: str, new: str) -> tuple[str, str]:
    """The first differing line of each text (what the message shows instead of whole files)."""
    a, b = old.splitlines(), new.splitlines()
    for x, y in zip(a, b):
        if x != y:
            return x, y
    return (a[len(b)] if len(a) > len(b) else ""), (b[len(a)] if len(b) > len(a) else "")


def compare(output: str, old: Any, new: Any, path: str = "", scale: float | None = None) -> Iterator[Mismatch]:
    """Every difference between a recorded value ``old`` and a new one ``new`` (the rules in the
    module docstring); ``scale``: the magnitude of the record holding them."""
    if isinstance(old, dict) and isinstance(new, dict):
        inner = magnitude(old)
        o = {normalise(k): v for k, v in old.items()}
        n = {normalise(k): v for k, v in new.items()}
        for k in o.keys() - n.keys():
            yield Mismatch(output, _join(path, k), o[k], None, "missing in the new output")
        for k in n.keys() - o.keys():
            yield Mismatch(output, _join(path, k), None, n[k], "new in the output, not recorded")
        for k in o.keys() & n.keys():
            yield from compare(output, o[k], n[k], _join(path, k), inner)
        return
    if isinstance(old, list) and isinstance(new, list):
        if len(old) != len(new):
            yield Mismatch(output, path, old, new, f"{len(old)} items recorded, {len(new)} now")
            return
        for i, (a, b) in enumerate(zip(old, new)):
            yield from compare(output, a, b, _join(path, i), scale)
        return
    if isinstance(old, str) and isinstance(new, str):
        a, b = normalise(old), normalise(new)
        if a != b:
            if "\n" in a or "\n" in b:
                la, lb = _first_lines(a, b)
                yield Mismatch(output, path, la, lb, _text_diff(a, b) + " (first differing line shown)")
            else:
                yield Mismatch(output, path, old, new, "text differs")
        return
    if type(old) is not type(new):
        yield Mismatch(output, path, old, new, f"type changed from {type(old).__name__} to {type(new).__name__}")
        return
    if isinstance(old, float):
        if old == new or (math.isnan(old) and math.isnan(new)):
            return
        record = abs(old) if scale is None else scale
        tol = max(RTOL * max(abs(old), abs(new)), FLOOR * record)
        diff = abs(new - old)
        if not diff <= tol:
            rel = diff / max(abs(old), abs(new))
            yield Mismatch(output, path, old, new,
                           f"differs by {diff:.3g} ({rel:.3g} relative) > {tol:.3g} "
                           f"(max(1e-12 × |value|, 1e-14 × {record:.3g}, the record's largest number))")
        return
    if old != new:
        yield Mismatch(output, path, old, new, "differs")


def compare_observations(recorded: dict[str, Any], new: dict[str, Any]) -> list[Mismatch]:
    """Every difference between two observations of one example, output by output."""
    old_out, new_out = recorded["outputs"], new["outputs"]
    found: list[Mismatch] = []
    for key in sorted(old_out.keys() - new_out.keys()):
        found.append(Mismatch(key, "", "(recorded)", None, "the output is no longer produced"))
    for key in sorted(new_out.keys() - old_out.keys()):
        found.append(Mismatch(key, "", None, "(new)", "a new output, not in the recording"))
    for key in sorted(old_out.keys() & new_out.keys()):
        found.extend(compare(key, old_out[key], new_out[key]))
    return found


def report(example: str, mismatches: list[Mismatch], per_output: int = 8) -> str:
    """The failure message: for each output, how many differences and the first few."""
    by_output: dict[str, list[Mismatch]] = {}
    for m in mismatches:
        by_output.setdefault(m.output, []).append(m)
    lines = [f"example {example!r}: {len(mismatches)} difference(s) from the recording in "
             f"{len(by_output)} output(s) (tests/golden/README.md: re-record only a deliberate, reviewed change)"]
    for output, ms in by_output.items():
        lines.append(f"- {output}: {len(ms)} difference(s)")
        lines += ["    " + str(m).replace("\n", "\n    ") for m in ms[:per_output]]
        if len(ms) > per_output:
            lines.append(f"    … and {len(ms) - per_output} more in {output}")
    return "\n".join(lines)

"""What each G-code dialect writes differently: one :class:`Dialect` per control, in
:data:`DIALECTS` (the choices of the spec's ``machining.dialect``).  The writer
(:mod:`cam_workbench.exporters.gcode`) asks the dialect for every word that differs and writes the
rest — the moves, feeds, the order of the blocks — the same for all.

======================  =====================  ==========================  =========================
                        linuxcnc               fanuc                       sinumerik
======================  =====================  ==========================  =========================
start / end of file     ``%`` … ``%``          ``%``, ``O1000`` … ``%``    (none)
comments                ``(text)``             ``(TEXT)`` upper case       ``; text``
units                   G21 / G20              G21 / G20                   G71 / G70
modal reset             G90 G17 G40 G49 G80    G90 G17 G40 G49 G80 G94     G90 G17 G40 G94
                        G94 G91.1
path blending           ``G64 P`` tolerance    (none: G64 is the default   ``G64`` (no tolerance)
                                               cutting mode)
tool                    ``T1 M6``, ``G43 H1``  ``T1 M6``, ``G43 H1``       ``T1 M6``, ``D1``
cutter compensation     ``G41 D1`` / ``G42``   ``G41 D1`` / ``G42 D1``     ``G41`` / ``G42`` (D1
                                                                           active since the tool)
numbers                 ``X10``                ``X10.`` (a decimal point   ``X10``
                                               on every coordinate)
arc centre I, J         incremental (G91.1)    incremental (always)        incremental (default)
inverse time (XC)       G93 … G94              G93 … G94 (an option)       G93 … G94
======================  =====================  ==========================  =========================

Fanuc reads a coordinate without a decimal point as a count of the least input increment
(``X10`` = 0.010 mm), so its coordinates always carry one.  Its S word is a whole number.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from cam_workbench.generators.spec.machining import DIALECTS as DIALECT_NAMES


def fmt(value: float, decimals: int) -> str:
    """A G-code number: fixed decimals, trailing zeros and a negative zero removed."""
    text = f"{value:.{decimals}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def fmt_point(value: float, decimals: int) -> str:
    """:func:`fmt` with a decimal point always (Fanuc: ``10.``, ``0.``)."""
    text = fmt(value, decimals)
    return text if "." in text else text + "."


def _ascii(text: str) -> str:
    """ASCII without parentheses (a comment in parentheses ends at the first ')')."""
    repl = {"°": " deg", "≤": "<=", "≥": ">=", "−": "-", "×": "x", "Δ": "d", "θ": "theta", "µ": "u",
            "(": "[", ")": "]", "–": "-", "²": "^2", "³": "^3"}
    out = "".join(repl.get(ch, ch) for ch in text)
    return out.encode("ascii", "replace").decode("ascii")


def linuxcnc_comment(text: str) -> str:
    """A LinuxCNC comment block: ASCII in parentheses, never one of its (MSG, (DEBUG, … commands."""
    out = _ascii(text)
    if out.split(",")[0].strip().upper() in ("MSG", "DEBUG", "PRINT", "LOG", "LOGOPEN", "LOGAPPEND",
                                             "LOGCLOSE", "PROBEOPEN", "PROBECLOSE", "ABORT"):
        out = "- " + out
    return f"({out})"


def fanuc_comment(text: str) -> str:
    """A Fanuc comment: upper-case ASCII in parentheses (many Fanuc controls show upper case only),
    without ``;`` (Fanuc's end-of-block character: ``,`` instead)."""
    return f"({_ascii(text).upper().replace(';', ',')})"


def sinumerik_comment(text: str) -> str:
    """A Sinumerik comment: ``;`` to the end of the block."""
    return f"; {_ascii(text)}"


@dataclass(frozen=True)
class Dialect:
    """The words of one control's G-code (see the table in the module docstring).

    Attributes:
        name: the ``machining.dialect`` choice.
        label: how the header names the control.
        tape_marks: ``%`` first and last.
        program_number: the program starts with an ``O`` word (the plan's program number).
        comment: comment text → one comment block.
        number: (value, decimals) → a coordinate or feed word's number.
        units: spec units → the units word.
        modal: the modal reset after the units word.
        blending: (path-blending tolerance, decimals) → its block, or None for none.
        tool: tool number → the tool change and length-offset blocks.
        compensation: ("left"/"right", tool number) → the word switching cutter compensation on.
        spindle: rpm → the S word's number.
        notes: header comments on what the dialect's program assumes of the control.
    """

    name: str
    label: str
    tape_marks: bool
    program_number: bool
    comment: Callable[[str], str]
    number: Callable[[float, int], str]
    units: dict[str, str]
    modal: str
    blending: Callable[[float, int], str | None]
    tool: Callable[[int], tuple[str, ...]]
    compensation: Callable[[str, int], str]
    spindle: Callable[[float], str]
    notes: tuple[str, ...]


_SIDE = {"left": "G41", "right": "G42"}

LINUXCNC = Dialect(
    name="linuxcnc", label="LinuxCNC", tape_marks=True, program_number=False, comment=linuxcnc_comment,
    number=fmt, units={"mm": "G21", "in": "G20"}, modal="G90 G17 G40 G49 G80 G94 G91.1",
    blending=lambda tol, d: f"G64 P{fmt(tol, d)}",
    tool=lambda t: (f"T{t} M6", f"G43 H{t}"),
    compensation=lambda side, t: f"{_SIDE[side]} D{t}",
    spindle=lambda rpm: fmt(rpm, 1), notes=())

FANUC = Dialect(
    name="fanuc", label="Fanuc", tape_marks=True, program_number=True, comment=fanuc_comment,
    number=fmt_point, units={"mm": "G21", "in": "G20"}, modal="G90 G17 G40 G49 G80 G94",
    blending=lambda tol, d: None,
    tool=lambda t: (f"T{t} M6", f"G43 H{t}"),
    compensation=lambda side, t: f"{_SIDE[side]} D{t}",
    spindle=lambda rpm: f"{round(rpm):d}",
    notes=("Fanuc dialect: I/J incremental from the arc start, a decimal point on every coordinate, S in whole "
           "rpm; path blending left to the control [G64 cutting mode, or its AI contour control]; the XC "
           "program needs the inverse-time feed option G93",))

SINUMERIK = Dialect(
    name="sinumerik", label="Siemens Sinumerik", tape_marks=False, program_number=False,
    comment=sinumerik_comment, number=fmt, units={"mm": "G71", "in": "G70"}, modal="G90 G17 G40 G94",
    blending=lambda tol, d: "G64",
    tool=lambda t: (f"T{t} M6", f"D{t}"),
    compensation=lambda side, t: _SIDE[side],
    spindle=lambda rpm: fmt(rpm, 1),
    notes=("Siemens Sinumerik dialect: I/J incremental from the arc start, G64 continuous-path mode, tool "
           "offsets D of the active tool; G93 inverse-time feed in the XC program",))

#: ``machining.dialect`` → its :class:`Dialect`
DIALECTS: dict[str, Dialect] = {d.name: d for d in (LINUXCNC, FANUC, SINUMERIK)}
assert tuple(DIALECTS) == DIALECT_NAMES, "every spec choice has its Dialect"


def dialect_of(name: str) -> Dialect:
    """The :class:`Dialect` of a ``machining.dialect`` choice."""
    return DIALECTS[name]

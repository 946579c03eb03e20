"""Reading a Fanuc-style or Sinumerik program back with an existing G-code parser, ``pygcode``
(PyPI; its ``Line`` parses a block into words and its comment, ``(…)`` or ``; …``), into the
moves the control makes: the position is tracked from the parsed words (absolute G90), an arc's
centre is its start plus the incremental I, J (Fanuc and Sinumerik both take I, J incremental from
the arc's start by default), and each move carries the last comment before it (its tag, lower
case) and the cutter compensation in force (G40/G41/G42).

The moves are :class:`tests.rs274.Motion` objects, so :func:`tests.rs274.sample_xy` samples them.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pytest

from .rs274 import Motion

pygcode = pytest.importorskip("pygcode", reason="pygcode (the test extra) is not installed")

_MOTION = {0: "traverse", 1: "line", 2: "arc", 3: "arc"}


@dataclass
class Program:
    """The moves of a program and what its blocks said."""

    moves: list[Motion] = field(default_factory=list)
    #: cutter compensation ("G40", "G41", "G42") in force on each move
    compensation: list[str] = field(default_factory=list)
    #: G words seen (numbers, e.g. 21.0, 93.0)
    g_words: set[float] = field(default_factory=set)
    #: the O word, if any
    program_number: int | None = None
    comments: list[str] = field(default_factory=list)

    def tagged(self, tag: str) -> list[Motion]:
        return [m for m in self.moves if m.tag == tag]

    def compensated(self, tag: str) -> list[tuple[Motion, str]]:
        return [(m, c) for m, c in zip(self.moves, self.compensation) if m.tag == tag]


def read_program(text: str) -> Program:
    """Parse ``text`` block by block with pygcode and rebuild its moves."""
    prog = Program()
    pos = np.zeros(4)                       # x, y, z, c
    motion = None
    comp = "G40"
    tag = ""
    for raw in text.splitlines():
        line = pygcode.Line(raw)
        if line.comment is not None:
            tag = line.comment.text.strip().lower()
            prog.comments.append(tag)
        words: dict[str, float] = {}
        for word in line.block.words:
            letter, value = word.letter, float(word.value)
            if letter == "G":
                prog.g_words.add(value)
                if value in (0, 1, 2, 3):
                    motion = int(value)
                elif value in (40, 41, 42):
                    comp = f"G{int(value)}"
            elif letter == "O":
                prog.program_number = int(value)
            else:
                words[letter] = value
        axes = {"X": 0, "Y": 1, "Z": 2, "C": 3}
        if motion is None or not any(a in words for a in axes):
            continue
        end = pos.copy()
        for letter, k in axes.items():
            if letter in words:
                end[k] = words[letter]
        centre = None
        if motion in (2, 3):
            centre = complex(pos[0] + words.get("I", 0.0), pos[1] + words.get("J", 0.0))
        prog.moves.append(Motion(_MOTION[motion], pos.copy(), end, centre=centre,
                                 rotation=1 if motion == 3 else -1 if motion == 2 else 0,
                                 feed=words.get("F", 0.0), tag=tag))
        prog.compensation.append(comp)
        pos = end
    return prog


def offset_moves(moves: list[Motion], side: str, radius: float, per_move: int = 64) -> np.ndarray:
    """Dense points of the tool centre under cutter compensation: each programmed line shifted by
    ``radius`` to the ``side`` ("left" G41 / "right" G42) of its direction of travel, each arc
    about the same centre with its radius changed by ``radius`` (out of the arc when the tool is on
    its outer side).  Computed here from the programmed geometry alone.  Each piece's first point
    is left out (the previous piece's last is within the print quantum of it), so that the points
    form one polyline without back-steps at the junctions (where the control joins the pieces)."""
    sgn = 1.0 if side == "left" else -1.0
    pts = []
    t = np.arange(1, per_move + 1) / per_move
    for m in moves:
        a, b = complex(m.start[0], m.start[1]), complex(m.end[0], m.end[1])
        if m.kind != "arc":
            n = 1j * (b - a) / abs(b - a) * sgn           # left normal × side
            pts.append(a + n * radius + (b - a) * t)
            continue
        c = m.centre
        a0, a1 = np.angle(a - c), np.angle(b - c)
        sweep = np.mod(a1 - a0, 2 * np.pi) if m.rotation > 0 else np.mod(a1 - a0, 2 * np.pi) - 2 * np.pi
        r = abs(a - c)
        # travelling ccw, the centre is on the left: a tool on the left is inside the arc
        inside = (m.rotation > 0) == (side == "left")
        rt = r - radius if inside else r + radius
        pts.append(c + rt * np.exp(1j * (a0 + sweep * t)))
    return np.concatenate(pts)[np.r_[-1, :sum(len(q) for q in pts)]]      # closed: last point first too

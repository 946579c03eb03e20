"""Figures as data: a :class:`Chart` is panels of curves, filled loops, lines, shaded spans and
notes in data coordinates, drawn by :mod:`.chart_svg` (the report's inline SVG, the API's
picture) and rasterised from that SVG for PNG files (:mod:`.chart_png`).

A figure function builds a chart from the design's numbers and draws nothing itself, so a test
can hold a figure's marks against report.json without reading pixels, and the same figure is
the same drawing in the report, in Jupyter and as a PNG.

Styles are matplotlib's words where there is one: dashes ``"-"``, ``"--"``, ``":"``, ``"-."``;
markers ``"o"`` (circle), ``"."`` (dot), ``"|"`` (tick), ``"+"``; colours as CSS (``"#1f3b5c"``,
``"0.45"`` — a grey level as matplotlib writes it — and the letters ``"k"``, ``"w"`` are accepted
and converted).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence, Union

import numpy as np


_LETTERS = {"k": "#000000", "w": "#ffffff", "r": "#ff0000", "g": "#008000", "b": "#0000ff"}


def css_color(c: str) -> str:
    """A CSS colour from a colour as the figures write it (a grey level "0.45" → "#737373", a
    matplotlib letter "k" → black)."""
    if c in _LETTERS:
        return _LETTERS[c]
    try:
        g = float(c)
    except ValueError:
        return c
    v = int(round(255 * min(max(g, 0.0), 1.0)))
    return f"#{v:02x}{v:02x}{v:02x}"


@dataclass(frozen=True)
class Curve:
    """A polyline (NaN in ``y`` or ``x`` breaks it) and/or markers at its points.

    ``width`` is the line width in points as matplotlib's ``lw``; ``size`` the marker size in
    points (matplotlib's ``ms``); ``face`` the marker fill (None: ``color``; "none": hollow),
    ``edge``/``edge_width`` its outline.
    """

    x: np.ndarray
    y: np.ndarray
    color: str = "#1f3b5c"
    width: float = 1.0
    dash: str = "-"
    marker: str | None = None
    line: bool = True
    size: float = 4.0
    face: str | None = None
    edge: str | None = None
    edge_width: float = 0.8
    alpha: float = 1.0
    label: str | None = None
    gid: str | None = None


@dataclass(frozen=True)
class Area:
    """Filled closed loops (N×2 points each; the even-odd rule makes inner loops holes) with an
    optional outline."""

    loops: Sequence[np.ndarray]
    fill: str = "#b8c7d9"
    edge: str | None = None
    width: float = 1.0
    alpha: float = 1.0
    label: str | None = None
    gid: str | None = None


@dataclass(frozen=True)
class Rule:
    """A horizontal (``axis="y"``: y = ``at``) or vertical (``axis="x"``: x = ``at``) line across
    the panel; ``text`` is written at its start (left end, or top)."""

    axis: str
    at: float
    color: str = "#b03a2e"
    width: float = 1.0
    dash: str = "--"
    label: str | None = None
    text: str | None = None
    gid: str | None = None


@dataclass(frozen=True)
class Shade:
    """Vertical bands over the whole panel height at the x spans ``spans`` ((x0, x1) each)."""

    spans: Sequence[tuple[float, float]]
    color: str = "#c0392b"
    alpha: float = 0.12
    label: str | None = None
    gid: str | None = None


@dataclass(frozen=True)
class Note:
    """Text at a data point, offset by (``dx``, ``dy``) points (+y up), aligned by ``anchor``
    ("start", "middle", "end") and ``valign`` ("top", "middle", "bottom"); ``boxed`` puts a white
    box behind it."""

    x: float
    y: float
    text: str
    color: str = "#1c2833"
    size: float = 8.0
    dx: float = 8.0
    dy: float = 0.0
    anchor: str = "start"
    valign: str = "middle"
    bold: bool = False
    boxed: bool = False
    gid: str | None = None


Mark = Union[Curve, Area, Rule, Shade, Note]


@dataclass
class Panel:
    """One set of axes.

    ``xlim``/``ylim`` None: the marks' extent (with a margin); ``xticks`` None: chosen;
    ``equal``: one unit is as long on both axes (a drawing: the data ranges are widened to fill
    the panel); ``axes`` False: no frame, ticks or grid (a pictorial view); ``logy``: a log y axis;
    ``top_labels``: (x, text) written above the panel (the motion segments' kinds);
    ``legend``: where the labelled marks are listed ("upper left", "upper right", "lower left",
    "lower right", "below", "right", or None); ``height``: the panel's plot height [pt].
    """

    marks: list[Mark] = field(default_factory=list)
    xlabel: str = ""
    ylabel: str = ""
    title: str = ""
    xlim: tuple[float, float] | None = None
    ylim: tuple[float, float] | None = None
    xticks: Sequence[float] | None = None
    xticklabels: bool = True
    equal: bool = False
    axes: bool = True
    logy: bool = False
    grid: bool = True
    top_labels: Sequence[tuple[float, str]] = ()
    legend: str | None = None
    legend_columns: int = 1
    height: float = 180.0

    def add(self, *marks: Mark) -> "Panel":
        self.marks.extend(marks)
        return self


@dataclass
class Chart:
    """A figure: columns of stacked panels (``columns[i]`` top to bottom), column widths in the
    ratio ``widths``, ``width`` points wide in all, under an optional ``title``."""

    columns: list[list[Panel]]
    width: float = 640.0
    widths: Sequence[float] = ()
    title: str = ""

    @classmethod
    def stack(cls, panels: Sequence[Panel], width: float = 640.0, title: str = "") -> "Chart":
        """One column of panels."""
        return cls([list(panels)], width=width, title=title)

    @property
    def panels(self) -> list[Panel]:
        """Every panel, column by column."""
        return [p for col in self.columns for p in col]

    def marks(self, gid: str) -> list[Mark]:
        """The marks with the SVG id ``gid`` (for tests and readers of the figure)."""
        return [m for p in self.panels for m in p.marks if m.gid == gid]


def segment_marks(boundaries_deg: np.ndarray, kinds: Sequence[str] | None = None) -> tuple[list[Rule], list]:
    """Thin grey rules at the inner motion-segment boundaries and (with ``kinds``) the
    segments' kinds to write above the panel (for :attr:`Panel.top_labels`)."""
    b = np.asarray(boundaries_deg, dtype=float)
    rules = [Rule("x", float(x), color="#bfbfbf", width=0.6, dash="-") for x in b[1:-1]]
    labels = [] if kinds is None else [(0.5 * (b[k] + b[k + 1]), str(kind)) for k, kind in enumerate(kinds)]
    return rules, labels


def angle_panel(**kw: object) -> Panel:
    """A panel over the cam cycle: x from 0 to 360° with a tick every 30°."""
    kw.setdefault("xlim", (0.0, 360.0))
    kw.setdefault("xticks", list(np.arange(0.0, 361.0, 30.0)))
    return Panel(**kw)  # type: ignore[arg-type]


__all__ = ["Area", "Chart", "Curve", "Mark", "Note", "Panel", "Rule", "Shade", "angle_panel", "css_color",
           "segment_marks"]

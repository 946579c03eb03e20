"""A :class:`~.chart.Chart` as SVG text: one self-contained ``<svg>`` element (no scripts, no fonts
to load, no external references), scalable (a ``viewBox`` in points), ready to inline in an HTML
page several times (every id starts with the figure's ``prefix``).

Readers of the SVG can recover the data: each panel's tick marks are ``<g id="{prefix}-p{i}-xtick-{k}"
data-value="…">`` (and ``ytick``) with the tick's position in the line's coordinates; a mark with a
``gid`` is the element ``id="{prefix}-{gid}"`` — a rule a ``<line>``, a few markers ``<circle>``\\ s,
a curve a ``<path>``.  Coordinates are written to 3 decimals of a point (bulk curves to 2).

Marks are drawn in the order given (shades first, notes last); a panel's marks are clipped to its
plot area.  Text widths are estimated (0.58 em a character): the layout reserves room for tick
labels, legends and titles without measuring fonts.
"""
from __future__ import annotations

import html
import math
from typing import Iterable, Sequence

import numpy as np

from .chart import Area, Chart, Curve, Mark, Note, Panel, Rule, Shade, css_color

FONT = 'font-family="DejaVu Sans,Helvetica,Arial,sans-serif"'
TICK = 7.0          # tick label size [pt]
LABEL = 8.0         # axis label size [pt]
TITLE = 9.0         # panel title size [pt]
LEGEND = 7.0        # legend text size [pt]
EM = 0.58           # estimated character width [em]
GAP = 8.0           # between stacked panels and columns [pt]

_DASH = {"-": None, "--": (3.7, 1.6), ":": (1.0, 1.65), "-.": (6.4, 1.6, 1.0, 1.6)}


def text_width(text: str, size: float) -> float:
    """Estimated width [pt] of one line of text at ``size`` pt."""
    return EM * size * len(text)


def _esc(s: str) -> str:
    return html.escape(s, quote=True)


def _fmt(v: float) -> str:
    return f"{v:.3f}".rstrip("0").rstrip(".") if math.isfinite(v) else "0"


# ---- ticks ---------------------------------------------------------------------------------------
def nice_ticks(lo: float, hi: float, target: int = 6) -> np.ndarray:
    """Evenly spaced round values (1, 2, 2.5 or 5 × 10^k apart) in [lo, hi]."""
    span = hi - lo
    if not span > 0:
        return np.array([lo])
    raw = span / max(target, 1)
    mag = 10.0 ** math.floor(math.log10(raw))
    step = mag * next(m for m in (1.0, 2.0, 2.5, 5.0, 10.0) if m * mag >= raw * 0.999)
    first = math.ceil(lo / step - 1e-9)
    last = math.floor(hi / step + 1e-9)
    return np.arange(first, last + 1) * step


def tick_labels(ticks: Sequence[float]) -> list[str]:
    """The ticks as text with as many decimals as their spacing needs (− for minus)."""
    t = np.asarray(ticks, dtype=float)
    if t.size == 0:
        return []
    big = float(np.max(np.abs(t)))
    step = float(np.min(np.diff(t))) if t.size > 1 else max(big, 1.0)
    dec = max(0, -math.floor(math.log10(step) + 1e-9)) if step > 0 else 0
    if step > 0 and abs(step / 10.0 ** -dec - round(step / 10.0 ** -dec)) > 1e-6:
        dec += 1
    if big >= 1e5 or (0 < big < 1e-3):
        # mantissa digits down to the step's last digit
        digits = max(0, math.floor(math.log10(big)) - math.floor(math.log10(step) + 1e-9)) if step > 0 else 2
        digits += dec > 0 and abs(step / 10.0 ** math.floor(math.log10(step) + 1e-9) - 2.5) < 1e-9
        return [f"{v:.{digits}e}".replace("-", "−") for v in t]
    return [f"{(0.0 if abs(v) < step * 1e-9 else v):.{dec}f}".replace("-", "−") for v in t]


def log_ticks(lo: float, hi: float) -> np.ndarray:
    """The powers of ten in [lo, hi] (log10 values)."""
    return np.arange(math.ceil(lo - 1e-9), math.floor(hi + 1e-9) + 1, dtype=float)


# ---- data ranges ---------------------------------------------------------------------------------
def _extent(marks: Iterable[Mark], axis: int, logy: bool = False) -> tuple[float, float] | None:
    vals: list[np.ndarray] = []
    for m in marks:
        if isinstance(m, Curve):
            vals.append(np.asarray(m.x if axis == 0 else m.y, dtype=float).ravel())
        elif isinstance(m, Area):
            vals.extend(np.asarray(lp, dtype=float)[:, axis] for lp in m.loops)
        elif isinstance(m, Rule) and (m.axis == "x") == (axis == 0):
            vals.append(np.array([m.at], dtype=float))
        elif isinstance(m, Shade) and axis == 0:
            vals.extend(np.asarray(sp, dtype=float) for sp in m.spans)
    if not vals:
        return None
    v = np.concatenate(vals)
    v = v[np.isfinite(v)]
    if logy:
        v = np.log10(v[v > 0])
    if v.size == 0:
        return None
    return float(v.min()), float(v.max())


def _padded(ext: tuple[float, float] | None, margin: float = 0.05) -> tuple[float, float]:
    if ext is None:
        return 0.0, 1.0
    lo, hi = ext
    if hi - lo <= 1e-12 * max(abs(lo), abs(hi), 1e-300):
        d = 0.1 * abs(lo) if lo != 0 else 1.0
        return lo - d, hi + d
    d = margin * (hi - lo)
    return lo - d, hi + d


class _Frame:
    """A panel's plot area [pt] and the data ranges mapped onto it."""

    def __init__(self, panel: Panel, x: float, y: float, w: float, h: float) -> None:
        self.panel, self.x, self.y, self.w, self.h = panel, x, y, w, h
        self.xlim = panel.xlim if panel.xlim is not None else _padded(_extent(panel.marks, 0))
        if panel.logy:
            ext = _extent(panel.marks, 1, logy=True)
            lo, hi = (panel.ylim if panel.ylim is not None and panel.ylim[0] > 0 else (None, None))
            self.ylim = ((math.log10(lo), math.log10(hi)) if lo is not None
                         else _padded(ext if ext is None else (math.floor(ext[0]), math.ceil(ext[1])), 0.0))
        else:
            self.ylim = panel.ylim if panel.ylim is not None else _padded(_extent(panel.marks, 1))
        if panel.equal:
            self._equal()

    def _equal(self) -> None:
        (x0, x1), (y0, y1) = self.xlim, self.ylim
        sx, sy = (x1 - x0) / self.w, (y1 - y0) / self.h
        s = max(sx, sy)
        cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        self.xlim = (cx - 0.5 * s * self.w, cx + 0.5 * s * self.w)
        self.ylim = (cy - 0.5 * s * self.h, cy + 0.5 * s * self.h)

    def px(self, x: np.ndarray) -> np.ndarray:
        x0, x1 = self.xlim
        return self.x + (np.asarray(x, dtype=float) - x0) * (self.w / (x1 - x0))

    def py(self, y: np.ndarray) -> np.ndarray:
        y = np.asarray(y, dtype=float)
        if self.panel.logy:
            with np.errstate(divide="ignore", invalid="ignore"):
                y = np.where(y > 0, np.log10(np.where(y > 0, y, 1.0)), np.nan)
        y0, y1 = self.ylim
        return self.y + self.h - (y - y0) * (self.h / (y1 - y0))

    def xticks(self) -> np.ndarray:
        t = np.asarray(self.panel.xticks, dtype=float) if self.panel.xticks is not None else \
            nice_ticks(*self.xlim, target=max(3, int(self.w / 60)))
        lo, hi = sorted(self.xlim)
        return t[(t >= lo - 1e-9 * abs(hi - lo)) & (t <= hi + 1e-9 * abs(hi - lo))]

    def yticks(self) -> tuple[np.ndarray, list[str]]:
        if self.panel.logy:
            k = log_ticks(*self.ylim)
            return 10.0 ** k, [f"1e{int(v)}".replace("-", "−") for v in k]
        t = nice_ticks(*self.ylim, target=max(3, int(self.h / 30)))
        return t, tick_labels(t)


# ---- layout --------------------------------------------------------------------------------------
def _legend_items(panel: Panel) -> list[Mark]:
    return [m for m in panel.marks if not isinstance(m, Note) and m.label]


def _legend_size(panel: Panel, width: float) -> tuple[float, float]:
    items = _legend_items(panel)
    if not items or panel.legend is None:
        return 0.0, 0.0
    longest = max(text_width(m.label or "", LEGEND) for m in items) + 26.0
    if panel.legend == "below":
        cols = max(1, min(panel.legend_columns, int(width // longest) or 1))
        rows = math.ceil(len(items) / cols)
        return width, rows * (LEGEND + 4.0) + 6.0
    return longest + 8.0, len(items) * (LEGEND + 4.0) + 6.0


def _lines(text: str) -> list[str]:
    return text.split("\n") if text else []


def _y_label_room(panel: Panel, ticks: Sequence[str]) -> float:
    if not panel.axes:
        return 8.0
    widest = max((text_width(t, TICK) for t in ticks), default=0.0)
    return 6.0 + widest + 4.0 + (LABEL + 3.0) * len(_lines(panel.ylabel)) + 4.0


def _heights(panel: Panel, last: bool) -> tuple[float, float]:
    top = 4.0 + (TITLE + 3.0) * len(_lines(panel.title)) + (TICK + 5.0 if panel.top_labels else 0.0)
    bottom = 4.0
    if panel.xticklabels and (last or panel.xlabel):
        bottom += TICK + 6.0
    if panel.xlabel:
        bottom += LABEL + 4.0
    return top, bottom


def svg(chart: Chart, prefix: str) -> str:
    """The chart as an ``<svg>`` element (class "plot"), ids prefixed with ``prefix``."""
    out: list[str] = []
    W = chart.width
    y_top = 6.0
    if chart.title:
        for ln in _lines(chart.title):
            y_top += TITLE + 2.0
            out.append(f'<text x="{_fmt(W / 2)}" y="{_fmt(y_top)}" font-size="{TITLE + 1}" text-anchor="middle" fill="#1c2833">'
                       f"{_esc(ln)}</text>")
        y_top += 4.0
    ratios = list(chart.widths) or [1.0] * len(chart.columns)
    total = sum(ratios)
    x = 0.0
    bottom = y_top
    k = 0
    for col, r in zip(chart.columns, ratios):
        cw = W * r / total
        # one left and one right margin for the column: its panels' x axes line up
        left = max(_y_label_room(p, _Frame(p, 0.0, 0.0, max(cw - 80.0, 50.0), p.height).yticks()[1]) for p in col)
        legends = [_legend_size(p, cw - left - 8.0) for p in col]
        right = 8.0 + max((lw + 6.0 for p, (lw, _) in zip(col, legends) if p.legend == "right"), default=0.0)
        plot_w = max(cw - left - right, 40.0)
        y = y_top
        for i, (panel, (lw, lh)) in enumerate(zip(col, legends)):
            last = i == len(col) - 1
            shown_axis = panel.xticklabels and (last or bool(panel.xlabel))
            top, below = _heights(panel, last)
            frame = _Frame(panel, x + left, y + top, plot_w, panel.height)
            leg_h = lh if panel.legend == "below" else 0.0
            out.append(_panel(frame, prefix, k, shown_axis, below))
            if lw:
                out.append(_legend(frame, lw, lh, below))
            y += top + panel.height + below + leg_h + GAP
            k += 1
        bottom = max(bottom, y)
        x += cw
    H = bottom - GAP + 4.0
    return (f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {_fmt(W)} {_fmt(H)}" class="plot" role="img" '
            f'{FONT} fill="none" stroke-linejoin="round">'
            f'<rect width="100%" height="100%" fill="#ffffff"/>' + "".join(out) + "</svg>")


# ---- a panel -------------------------------------------------------------------------------------
def _panel(f: _Frame, prefix: str, k: int, shown_axis: bool, below: float) -> str:
    p = f.panel
    pid = f"{prefix}-p{k}"
    o: list[str] = [f'<g id="{pid}">', f'<clipPath id="{pid}-clip"><rect x="{_fmt(f.x)}" y="{_fmt(f.y)}" '
                    f'width="{_fmt(f.w)}" height="{_fmt(f.h)}"/></clipPath>']
    xt = f.xticks() if p.axes else np.zeros(0)
    yt, ylabels = f.yticks() if p.axes else (np.zeros(0), [])
    xlabels = tick_labels(xt)
    yb = f.y + f.h
    if p.grid and p.axes:
        d = "".join(f"M{_fmt(v)} {_fmt(f.y)}V{_fmt(yb)}" for v in f.px(xt))
        d += "".join(f"M{_fmt(f.x)} {_fmt(v)}H{_fmt(f.x + f.w)}" for v in f.py(yt))
        o.append(f'<path d="{d}" stroke="#e3e3e3" stroke-width="0.6"/>')
    for kk, (v, pos) in enumerate(zip(xt, f.px(xt))):
        o.append(f'<g id="{pid}-xtick-{kk}" data-value="{float(v)!r}"><line x1="{_fmt(pos)}" y1="{_fmt(yb)}" '
                 f'x2="{_fmt(pos)}" y2="{_fmt(yb + 3.5)}" stroke="#333" stroke-width="0.6"/>'
                 + (f'<text x="{_fmt(pos)}" y="{_fmt(yb + 4 + TICK)}" font-size="{TICK}" text-anchor="middle" '
                    f'fill="#333">{_esc(xlabels[kk])}</text>' if shown_axis else "") + "</g>")
    for kk, (v, pos) in enumerate(zip(yt, f.py(yt))):
        o.append(f'<g id="{pid}-ytick-{kk}" data-value="{float(v)!r}"><line x1="{_fmt(f.x - 3.5)}" '
                 f'y1="{_fmt(pos)}" x2="{_fmt(f.x)}" y2="{_fmt(pos)}" stroke="#333" stroke-width="0.6"/>'
                 f'<text x="{_fmt(f.x - 5)}" y="{_fmt(pos + TICK * 0.35)}" font-size="{TICK}" text-anchor="end" '
                 f'fill="#333">{_esc(ylabels[kk])}</text></g>')
    body = sorted(p.marks, key=lambda m: 0 if isinstance(m, Shade) else 2 if isinstance(m, Note) else 1)
    o.append(f'<g clip-path="url(#{pid}-clip)">')
    o.extend(_mark(f, m, prefix) for m in body if not isinstance(m, Note))
    o.append("</g>")
    o.extend(_note(f, m) for m in body if isinstance(m, Note))
    if p.axes:
        o.append(f'<rect x="{_fmt(f.x)}" y="{_fmt(f.y)}" width="{_fmt(f.w)}" height="{_fmt(f.h)}" '
                 'stroke="#333" stroke-width="0.8"/>')
    for x, text in p.top_labels:
        px = float(f.px(np.array([x]))[0])
        if f.x <= px <= f.x + f.w:
            o.append(f'<text x="{_fmt(px)}" y="{_fmt(f.y - 3)}" font-size="{TICK}" text-anchor="middle" '
                     f'fill="#595959">{_esc(text)}</text>')
    ty = f.y - 4.0 - (TICK + 5.0 if p.top_labels else 0.0)
    for i, ln in enumerate(reversed(_lines(p.title))):
        o.append(f'<text x="{_fmt(f.x + f.w / 2)}" y="{_fmt(ty - i * (TITLE + 3.0))}" font-size="{TITLE}" '
                 f'text-anchor="middle" fill="#1c2833">{_esc(ln)}</text>')
    if p.xlabel:
        o.append(f'<text x="{_fmt(f.x + f.w / 2)}" y="{_fmt(yb + (TICK + 6.0 if shown_axis else 0) + LABEL + 3)}" '
                 f'font-size="{LABEL}" text-anchor="middle" fill="#1c2833">{_esc(p.xlabel)}</text>')
    if p.ylabel:
        widest = max((text_width(t, TICK) for t in ylabels), default=0.0)
        lines = _lines(p.ylabel)
        for i, ln in enumerate(lines):
            xx = f.x - 6.0 - widest - 4.0 - (len(lines) - 1 - i) * (LABEL + 3.0) - 2.0
            yy = f.y + f.h / 2
            o.append(f'<text transform="translate({_fmt(xx)} {_fmt(yy)}) rotate(-90)" font-size="{LABEL}" '
                     f'text-anchor="middle" fill="#1c2833">{_esc(ln)}</text>')
    o.append("</g>")
    return "".join(o)


def _dash(dash: str, width: float) -> str:
    pattern = _DASH.get(dash)
    if pattern is None:
        return ""
    w = max(width, 0.5)
    return f' stroke-dasharray="{" ".join(_fmt(v * w) for v in pattern)}"'


def _ident(m: Mark, prefix: str) -> str:
    return "" if m.gid is None else f' id="{prefix}-{m.gid}"'


def _polyline(px: np.ndarray, py: np.ndarray) -> str:
    """An SVG path through the points, broken where a coordinate is not finite."""
    ok = np.isfinite(px) & np.isfinite(py)
    if not ok.any():
        return ""
    # a new sub-path starts at every finite point whose predecessor is not
    start = ok & ~np.concatenate([[False], ok[:-1]])
    cmd = np.where(start, "M", "L")[ok]
    xs, ys = np.round(px[ok], 2), np.round(py[ok], 2)
    # Python's floats and strings: formatting numpy's scalars one by one costs five times as much
    return "".join(map("{}{:.2f} {:.2f}".format, cmd.tolist(), xs.tolist(), ys.tolist()))


def _markers(m: Curve, px: np.ndarray, py: np.ndarray, ident: str) -> str:
    ok = np.isfinite(px) & np.isfinite(py)
    px, py = px[ok], py[ok]
    color = css_color(m.color)
    s = m.size
    alpha = f' opacity="{_fmt(m.alpha)}"' if m.alpha < 1 else ""
    if m.marker in ("o", "."):
        r = 0.5 * s if m.marker == "o" else max(0.35 * s, 0.6)
        face = color if m.face is None else ("none" if m.face == "none" else css_color(m.face))
        edge = css_color(m.edge) if m.edge is not None else color
        paint = f'fill="{face}" stroke="{edge}" stroke-width="{_fmt(m.edge_width if m.marker == "o" else 0)}"{alpha}'
        if px.size <= 50:
            return (f"<g{ident} {paint}>" + "".join(
                f'<circle cx="{a:.3f}" cy="{b:.3f}" r="{_fmt(r)}"/>' for a, b in zip(px, py)) + "</g>")
        d = "".join(map(("M{:.2f} {:.2f}" + f"a{_fmt(r)} {_fmt(r)} 0 1 0 {_fmt(2 * r)} 0"
                         + f"a{_fmt(r)} {_fmt(r)} 0 1 0 {_fmt(-2 * r)} 0").format, np.round(px - r, 2).tolist(),
                        np.round(py, 2).tolist()))
        return f'<path{ident} d="{d}" {paint}/>'
    if m.marker == "|":
        d = "".join(map(f"M{{:.2f}} {{:.2f}}v{_fmt(s)}".format, np.round(px, 2).tolist(),
                        np.round(py - s / 2, 2).tolist()))
    else:   # "+"
        d = "".join(map(f"M{{:.2f}} {{:.2f}}h{_fmt(s)}m{_fmt(-s / 2)} {_fmt(-s / 2)}v{_fmt(s)}".format,
                        np.round(px - s / 2, 2).tolist(), np.round(py, 2).tolist()))
    return f'<path{ident} d="{d}" stroke="{color}" stroke-width="{_fmt(max(m.width, 0.8))}"{alpha}/>'


def _mark(f: _Frame, m: Mark, prefix: str) -> str:
    ident = _ident(m, prefix)
    if isinstance(m, Shade):
        return "".join(
            f'<rect{ident} x="{_fmt(min(a, b))}" y="{_fmt(f.y)}" width="{_fmt(abs(b - a))}" height="{_fmt(f.h)}" '
            f'fill="{css_color(m.color)}" opacity="{_fmt(m.alpha)}"/>'
            for a, b in (tuple(f.px(np.asarray(sp, dtype=float))) for sp in m.spans))
    if isinstance(m, Rule):
        if m.axis == "y":
            v = float(f.py(np.array([m.at]))[0])
            x1, y1, x2, y2 = f.x, v, f.x + f.w, v
        else:
            v = float(f.px(np.array([m.at]))[0])
            x1, y1, x2, y2 = v, f.y, v, f.y + f.h
        line = (f'<line{ident} x1="{x1:.3f}" y1="{y1:.3f}" x2="{x2:.3f}" y2="{y2:.3f}" '
                f'stroke="{css_color(m.color)}" stroke-width="{_fmt(m.width)}"{_dash(m.dash, m.width)}/>')
        if m.text:
            if m.axis == "y":
                line += (f'<text x="{_fmt(f.x + 3)}" y="{_fmt(v - 2)}" font-size="{TICK}" '
                         f'fill="{css_color(m.color)}" stroke="none">{_esc(m.text)}</text>')
            else:
                line += (f'<text x="{_fmt(v + 2)}" y="{_fmt(f.y + TICK + 2)}" font-size="{TICK}" '
                         f'fill="{css_color(m.color)}" stroke="none">{_esc(m.text)}</text>')
        return line
    if isinstance(m, Area):
        d = ""
        for lp in m.loops:
            lp = np.asarray(lp, dtype=float)
            d += _polyline(f.px(lp[:, 0]), f.py(lp[:, 1])) + "Z"
        edge = (f' stroke="{css_color(m.edge)}" stroke-width="{_fmt(m.width)}"' if m.edge else "")
        alpha = f' fill-opacity="{_fmt(m.alpha)}"' if m.alpha < 1 else ""
        return f'<path{ident} d="{d}" fill="{css_color(m.fill)}" fill-rule="evenodd"{alpha}{edge}/>'
    assert isinstance(m, Curve)
    px, py = f.px(m.x), f.py(m.y)
    parts = []
    if m.line and m.marker not in (".",) and len(px) > 1:
        alpha = f' stroke-opacity="{_fmt(m.alpha)}"' if m.alpha < 1 else ""
        parts.append(f'<path{"" if m.marker else ident} d="{_polyline(px, py)}" stroke="{css_color(m.color)}" '
                     f'stroke-width="{_fmt(m.width)}"{_dash(m.dash, m.width)}{alpha} stroke-linecap="round"/>')
    if m.marker:
        parts.append(_markers(m, px, py, ident))
    return "".join(parts)


def _note(f: _Frame, n: Note) -> str:
    x = float(f.px(np.array([n.x]))[0]) + n.dx
    y = float(f.py(np.array([n.y]))[0]) - n.dy
    base = {"top": n.size * 0.8, "middle": n.size * 0.35, "bottom": 0.0}[n.valign]
    lines = _lines(n.text)
    color = css_color(n.color)
    anchor = n.anchor
    wide = max(text_width(ln, n.size) for ln in lines)
    if anchor == "start" and x + wide > f.x + f.w:       # would leave the panel: write it to the left
        x, anchor = x - 2 * n.dx, "end"
    elif anchor == "end" and x - wide < f.x:
        x, anchor = x - 2 * n.dx, "start"
    out = []
    if n.boxed:
        w = wide + 4
        h = len(lines) * (n.size + 2) + 2
        x0 = {"start": x - 2, "middle": x - w / 2, "end": x - w + 2}[anchor]
        out.append(f'<rect x="{_fmt(x0)}" y="{_fmt(y + base - n.size - 1)}" width="{_fmt(w)}" height="{_fmt(h)}" '
                   'rx="2" fill="#ffffff" fill-opacity="0.85"/>')
    weight = ' font-weight="bold"' if n.bold else ""
    ident = "" if n.gid is None else f' data-gid="{_esc(n.gid)}"'
    for i, ln in enumerate(lines):
        out.append(f'<text{ident} x="{_fmt(x)}" y="{_fmt(y + base + i * (n.size + 2))}" font-size="{_fmt(n.size)}" '
                   f'text-anchor="{anchor}" fill="{color}"{weight}>{_esc(ln)}</text>')
    return "".join(out)


# ---- legend --------------------------------------------------------------------------------------
def _sample(m: Mark, x: float, y: float) -> str:
    if isinstance(m, (Area, Shade)):
        fill = css_color(m.fill if isinstance(m, Area) else m.color)
        edge = css_color(m.edge) if isinstance(m, Area) and m.edge else "none"
        op = m.alpha if isinstance(m, Area) else max(m.alpha, 0.3)
        return (f'<rect x="{_fmt(x)}" y="{_fmt(y - 3.5)}" width="16" height="7" fill="{fill}" '
                f'fill-opacity="{_fmt(op)}" stroke="{edge}" stroke-width="0.8"/>')
    if isinstance(m, Rule):
        return (f'<line x1="{_fmt(x)}" y1="{_fmt(y)}" x2="{_fmt(x + 16)}" y2="{_fmt(y)}" stroke="{css_color(m.color)}" '
                f'stroke-width="{_fmt(m.width)}"{_dash(m.dash, m.width)}/>')
    assert isinstance(m, Curve)
    out = ""
    if m.line and m.marker != ".":
        out += (f'<line x1="{_fmt(x)}" y1="{_fmt(y)}" x2="{_fmt(x + 16)}" y2="{_fmt(y)}" '
                f'stroke="{css_color(m.color)}" stroke-width="{_fmt(min(m.width, 3.0))}"{_dash(m.dash, m.width)}/>')
    if m.marker:
        out += _markers(m, np.array([x + 8.0]), np.array([y]), "")
    return out


def _legend(f: _Frame, lw: float, lh: float, below: float) -> str:
    p = f.panel
    items = _legend_items(p)
    step = LEGEND + 4.0
    if p.legend == "below":
        longest = max(text_width(m.label or "", LEGEND) for m in items) + 26.0
        cols = max(1, min(p.legend_columns, int(lw // longest) or 1))
        colw = f.w / cols
        x0, y0 = f.x, f.y + f.h + below + 2.0
        pos = [(x0 + (i % cols) * colw, y0 + (i // cols) * step + step / 2) for i in range(len(items))]
        box = ""
    else:
        x0 = {"upper left": f.x + 6, "lower left": f.x + 6, "upper right": f.x + f.w - lw - 6,
              "lower right": f.x + f.w - lw - 6, "right": f.x + f.w + 8}.get(p.legend or "", f.x + 6)
        y0 = (f.y + f.h - lh - 6) if (p.legend or "").startswith("lower") else f.y + 6
        pos = [(x0 + 4, y0 + 3 + i * step + step / 2) for i in range(len(items))]
        box = (f'<rect x="{_fmt(x0)}" y="{_fmt(y0)}" width="{_fmt(lw)}" height="{_fmt(lh)}" rx="2" '
               'fill="#ffffff" fill-opacity="0.9" stroke="#cccccc" stroke-width="0.6"/>')
    out = [box]
    for m, (x, y) in zip(items, pos):
        out.append(_sample(m, x, y))
        out.append(f'<text x="{_fmt(x + 21)}" y="{_fmt(y + LEGEND * 0.35)}" font-size="{LEGEND}" fill="#1c2833">'
                   f"{_esc(m.label or '')}</text>")
    return "".join(out)


__all__ = ["nice_ticks", "svg", "text_width", "tick_labels"]

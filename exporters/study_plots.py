"""The sizing chart: the smallest base radius over a grid, in the form of the cam handbooks'
nomograms — R_b,min over one varied field (the x axis, e.g. the rise angle β), one line per
value of another (e.g. the lift h), one panel per value of a categorical field (the motion law),
panels sharing their y axis so that the laws compare at a glance.

:func:`sizing_chart` takes the table of a sizing sweep
(:func:`cam_workbench.generators.studies.sweep.run_sweep` with ``sizing``) and chooses the layout from its grid
columns unless told: x = the first numeric axis, lines = the next numeric axis (or the
categorical one), panels = whatever categorical axis is left (several left: one panel per
combination).  A point without a radius (none passes) leaves a gap and is counted in the panel.

The chart is a matplotlib figure (Agg backend): :func:`figure_bytes` gives it as PNG or SVG bytes,
:func:`save_figure` writes it atomically and :func:`close` frees it.
"""
from __future__ import annotations

import io
import itertools
import os
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from cam_workbench.generators.checks.design import limit_sign
from cam_workbench.generators.studies.table import StudyTable

from .atomic import atomic_path
from .plots import SERIES_COLORS

LINE_COLORS = SERIES_COLORS + ("#e67e22", "#00838f", "#8a6212", "#ad1457", "#546e7a")
MAX_PANELS = 12
#: the checks whose value must stay at or below their limit (the others: at or above)
MAX_CHECKS = ("pressure_angle", "contact_stress", "face_width")
CHECK_UNITS = {"pressure_angle": "°"}


# ---- matplotlib (the sweep charts draw with it; the report's figures are charts of .chart) -------
def _plt() -> Any:
    import matplotlib  # deferred: matplotlib, loaded when a figure is drawn

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # deferred: matplotlib, loaded when a figure is drawn

    return plt


def save_figure(fig: Any, path: str | os.PathLike[str], dpi: int = 150) -> Path:
    """Save a figure atomically; the format follows the suffix (.png, .svg, .pdf)."""
    target = Path(path)
    with atomic_path(target) as tmp:
        fig.savefig(tmp, dpi=dpi, format=target.suffix.lstrip(".") or "png", bbox_inches="tight")
    _plt().close(fig)
    return target


def figure_bytes(fig: Any, fmt: str, dpi: int = 150) -> bytes:
    """The figure as PNG or SVG bytes (SVG text keeps glyphs as paths: no font files needed)."""
    import matplotlib  # deferred: matplotlib, loaded when a figure is drawn

    buf = io.BytesIO()
    with matplotlib.rc_context({"svg.fonttype": "path", "svg.hashsalt": "cam_workbench"}):
        fig.savefig(buf, format=fmt, dpi=dpi, bbox_inches="tight", metadata=_metadata(fmt))
    return buf.getvalue()


def close(fig: Any) -> None:
    _plt().close(fig)


def _metadata(fmt: str) -> dict[str, Any]:
    # no creation dates: the same design gives the same files
    if fmt == "svg":
        return {"Date": None, "Creator": "cam_workbench"}
    if fmt == "png":
        return {"Software": "cam_workbench"}
    return {}


def _numeric(values: Sequence[Any]) -> bool:
    vals = [v for v in values if v is not None]
    return bool(vals) and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in vals)


def _label(field: str, units: str) -> str:
    words = {"angle": "deg", "lift": units, "base_radius": units, "roller_radius": units, "offset": units}
    last = field.rsplit(".", 1)[-1]
    unit = words.get(last)
    return f"{field} [{unit}]" if unit else field


def criteria(table: StudyTable) -> str:
    """What the radius meets, in words with the limits: "pressure_angle ≤ 30°, curvature ≥ 12 mm"
    (the limits of the first row that has them), or "every design check"."""
    checks = table.meta.get("checks", "all")
    if checks == "all" or not checks:
        return "every design check"
    units = table.meta.get("units", "mm")
    parts = []
    for name in checks:
        limit = next((r.get(f"check_{name}_limit") for r in table.rows
                      if r.get(f"check_{name}_limit") is not None), None)
        if limit is None:
            parts.append(name)
            continue
        sign = limit_sign(name, "max" if name in MAX_CHECKS else "min")
        unit = CHECK_UNITS.get(name, f" {units}" if name in ("curvature", "undercut", "cusp", "face_width") else "")
        parts.append(f"{name} {sign} {limit:g}{unit}")
    return ", ".join(parts)


def _value_label(field: str, value: Any, units: str) -> str:
    name = field.rsplit(".", 1)[-1]
    unit = {"angle": "°", "lift": f" {units}", "roller_radius": f" {units}", "offset": f" {units}"}.get(name, "")
    return f"{name} = {value:g}{unit}" if isinstance(value, (int, float)) and not isinstance(value, bool) \
        else f"{name} = {value}"


def chart_layout(table: StudyTable, axes: Sequence[str], x: str | None = None, lines: str | None = None,
                 panels: Sequence[str] | None = None) -> tuple[str, str | None, list[str]]:
    """(x, lines, panels): the columns that go on the x axis, make the lines and the panels."""
    numeric = [a for a in axes if _numeric(table.column(a))]
    if x is None:
        if not numeric:
            raise ValueError("a sizing chart needs a numeric --vary axis for its x axis")
        x = numeric[0]
    rest = [a for a in axes if a != x]
    if lines is None and rest:
        more_numeric = [a for a in rest if a in numeric]
        lines = more_numeric[0] if more_numeric else rest[0]
    rest = [a for a in rest if a != lines]
    return x, lines, list(panels) if panels is not None else rest


def sizing_chart(table: StudyTable, axes: Sequence[str] | None = None, *, x: str | None = None,
                 lines: str | None = None, panels: Sequence[str] | None = None,
                 value: str = "min_base_radius", title: str | None = None) -> Any:
    """The sizing chart of ``table`` as a matplotlib figure (see the module's docstring)."""
    plt = _plt()
    meta = table.meta
    units = meta.get("units", "mm")
    if axes is None:
        axes = [c for c in table.columns if c not in ("status", "error", value)][: len(meta.get("axes", [])) or 1]
    x, lines, panel_cols = chart_layout(table, axes, x, lines, panels)
    panel_values = [list(dict.fromkeys(table.column(c))) for c in panel_cols]
    combos = list(itertools.product(*panel_values)) or [()]
    if len(combos) > MAX_PANELS:
        raise ValueError(f"the chart would have {len(combos)} panels (at most {MAX_PANELS}): "
                         "give fewer values to the categorical --vary axes")
    line_values = list(dict.fromkeys(table.column(lines))) if lines else [None]
    ncol = min(len(combos), 3)
    nrow = -(-len(combos) // ncol)
    fig, axs = plt.subplots(nrow, ncol, figsize=(4.6 * ncol + 0.4, 3.9 * nrow + 0.6), sharey=True,
                            squeeze=False)
    for ax in axs.flat[len(combos):]:
        ax.set_visible(False)
    for ax, combo in zip(axs.flat, combos):
        sel = [r for r in table.rows if all(r.get(c) == v for c, v in zip(panel_cols, combo))]
        gaps = 0
        for k, lv in enumerate(line_values):
            pts = sorted(((r[x], r.get(value)) for r in sel if lines is None or r.get(lines) == lv),
                         key=lambda t: t[0])
            if not pts:
                continue
            xs = np.array([p[0] for p in pts], dtype=float)
            ys = np.array([np.nan if p[1] is None else p[1] for p in pts], dtype=float)
            gaps += int(np.count_nonzero(np.isnan(ys)))
            label = None if lines is None else _value_label(lines, lv, units)
            ax.plot(xs, ys, "-o", ms=3.5, lw=1.6, color=LINE_COLORS[k % len(LINE_COLORS)], label=label)
        floors = sorted({r["failing_radius"] for r in sel if str(r.get("binding_checks", "")).startswith("spec rule")
                         and r.get("failing_radius") is not None})
        for f in floors[:1]:
            ax.axhline(f, color="#7f7f7f", lw=1.0, ls="--", zorder=0)
            ax.annotate("smallest the spec allows (roller + bore)", (0.02, f), xycoords=("axes fraction", "data"),
                        xytext=(0, 3), textcoords="offset points", fontsize=7, color="#555555")
        head = ", ".join(_value_label(c, v, units) for c, v in zip(panel_cols, combo))
        if gaps:
            head += f"  ({gaps} without a radius)"
        if head:
            ax.set_title(head, fontsize=10)
        ax.grid(True, which="major", color="#b0b0b0", lw=0.6)
        ax.minorticks_on()
        ax.grid(True, which="minor", color="#e0e0e0", lw=0.4)
        ax.set_xlabel(_label(x, units))
        if lines is not None and len(line_values) > 1:
            ax.legend(fontsize=8, loc="best")
    for ax in axs[:, 0]:
        ax.set_ylabel(f"smallest base radius R_b [{units}]")
    what = criteria(table)
    tol = meta.get("tolerance")
    fig.suptitle(title or f"Smallest base radius meeting {what}" + (f" (bisection to {tol:g} {units})"
                                                                    if tol is not None else ""), fontsize=11)
    fig.tight_layout()
    return fig

"""A chart's PNG: its SVG (:mod:`.chart_svg`) rasterised by CairoSVG, so a PNG file is the same
drawing as the report's inline figure.  PNGs are written on request (``--plots``); CairoSVG is
the ``png`` extra (``pip install 'cam-workbench[png]'``, and the system's cairo library)."""
from __future__ import annotations

from typing import Any

from cam_workbench.generators.errors import MissingDependency

from .chart import Chart
from .chart_svg import svg

#: PNG width [px] of a chart 640 pt wide (1.6 px a point, about matplotlib's 130 dpi figures)
SCALE = 1.6


def require_png() -> Any:
    """The CairoSVG module.

    Raises:
        MissingDependency: CairoSVG (or the cairo library it loads) is missing.
    """
    try:
        import cairosvg  # deferred: cairosvg and the cairo library, loaded when a PNG is asked for
    except (ImportError, OSError) as exc:
        raise MissingDependency(
            "PNG plot files (--plots) need CairoSVG and the cairo library: pip install 'cam-workbench[png]' "
            f"(and the system's libcairo2); the report's figures are in report.html without it ({exc})") from exc
    return cairosvg


def png_bytes(chart: Chart | str, prefix: str = "fig") -> bytes:
    """The PNG of ``chart`` (a :class:`Chart`, or its SVG text) at :data:`SCALE` px a point.

    Raises:
        MissingDependency: CairoSVG (or the cairo library it loads) is missing.
    """
    cairosvg = require_png()
    text = chart if isinstance(chart, str) else svg(chart, prefix)
    return cairosvg.svg2png(bytestring=text.encode("utf-8"), scale=SCALE)


__all__ = ["SCALE", "png_bytes", "require_png"]

"""``cam-workbench tolerance``: the largest profile tolerance per number of waves per turn that
keeps the follower's acceleration error within a share of the designed peak at the cam's speed
(docs/tolerances.md) — printed as a table and, with ``-o``, written as tolerance.json, tolerance.svg
and tolerance.png (when CairoSVG imports)."""
from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from cam_workbench.exporters.atomic import OutputSet
from cam_workbench.exporters.chart_png import png_bytes, require_png
from cam_workbench.exporters.report_cells import format_number as fmt
from cam_workbench.exporters.report_json import report_json_text
from cam_workbench.generators.errors import MissingDependency, SpecError

from ..tolerance import tolerance_study
from .common import admit_output, design_for, output_claim, spec_from_args
from .parsers import TOLERANCE_FILES

JSON_NAME, SVG_NAME, PNG_NAME = TOLERANCE_FILES


def check_options(args: argparse.Namespace) -> None:
    """The command's own options, before any work (exit 2 naming the option, nothing written)."""
    pct = args.acceleration_limit
    if not (math.isfinite(pct) and 0.0 < pct <= 100.0):
        raise SpecError("--acceleration-limit", f"must be a percentage in (0, 100] of the designed peak acceleration, "
                        f"got {pct:g}")
    if not 1 <= args.max_waves <= 10000:
        raise SpecError("--max-waves", f"must be a whole number of waves per turn in 1 … 10000, got {args.max_waves}")
    if args.speed is not None and not (math.isfinite(args.speed) and args.speed > 0):
        raise SpecError("--speed", f"must be a cam speed > 0 rpm, got {args.speed:g}")


def run(args: argparse.Namespace) -> int:
    check_options(args)
    spec = spec_from_args(args)
    png = _png_available()
    names = (JSON_NAME, SVG_NAME) + ((PNG_NAME,) if png else ())
    if args.output is not None:
        admit_output(args, spec, "tolerance", names)
    study = tolerance_study(spec, args.acceleration_limit / 100.0, args.max_waves, args.speed,
                            design=design_for(spec))
    summary = json.loads(report_json_text(study.summary()))      # the numbers tolerance.json holds
    out = None if args.output is None else Path(args.output)
    if out is not None:
        svg = study.svg()
        with OutputSet(out, output_claim(args, spec, "tolerance")) as o:
            o.add_text(JSON_NAME, report_json_text(study.summary()))
            o.add_text(SVG_NAME, svg + "\n")
            if png:
                o.add_bytes(PNG_NAME, png_bytes(svg))
    print_table(summary, out, names)
    return 0


def _png_available() -> bool:
    try:
        require_png()
    except MissingDependency:
        return False
    return True


def print_table(d: dict[str, Any], out: Path | None, names: tuple[str, ...]) -> None:
    """tolerance.json's numbers as a table — the values printed are tolerance.json's own."""
    con = Console(soft_wrap=True)
    u, au = d["units"], d["acceleration_unit"]
    con.print(escape(f"{d['cam']}"))
    con.print(escape(f"acceleration error ≤ {fmt(100 * d['acceleration_limit'])} % of the designed peak "
                     f"{fmt(d['designed_peak_acceleration'])} {au} = {fmt(d['allowed_acceleration_error'])} {au} "
                     f"at {fmt(d['speed_rpm'])} rpm; follower gain ∂s/∂e {fmt(d['gain']['min'])} … "
                     f"{fmt(d['gain']['max'])} {d['gain']['unit']}; contact radius "
                     f"{'—' if d['contact_radius'] is None else fmt(d['contact_radius'])}"))
    table = Table(title=escape(f"largest profile tolerance t (zone ±t/2, worst wave phase) [{u}]"))
    for col in ("waves per turn", "tolerance t", "acceleration limit t_a", "contact limit t_c", "governed by"):
        table.add_column(col, justify="right")
    for r in d["table"]:
        table.add_row(str(r["waves"]), fmt(r["tolerance"]), fmt(r["acceleration_tolerance"]),
                      fmt(r["contact_tolerance"]), r["governed_by"])
    con.print(table)
    t = d["tightest"]
    con.print(escape(f"tightest: t = {fmt(t['tolerance'])} {u} at {t['waves']} waves per turn "
                     f"({t['governed_by']})")
              + ("" if out is None else escape(f" — written to {out}/: {', '.join(names)}")))

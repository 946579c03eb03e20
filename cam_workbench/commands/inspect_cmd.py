"""``cam-workbench inspect SPEC POINTS.csv``: measured profile points against the design — the
registration, every point's normal deviation, the profile-tolerance verdict and the follower's
motion on the measured part, the deviation's harmonics and the acceleration error each predicts —
printed as tables (inspection.json's numbers) and, with ``-o``,
written as inspection.json, inspection.html, deviations.csv, motion.csv and the figures.  Exit
status 3 when the verdict is "fail"."""
from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any, Mapping

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from cam_workbench.exporters.inspection_report import harmonic_columns, rows
from cam_workbench.exporters.report_cells import format_number as fmt
from cam_workbench.exporters.report_cells import lookup
from cam_workbench.exporters.report_json import report_json_text
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.inspection import inspect_design

from ..inspection import read_points, write_inspection
from .common import admit_output, design_for, output_claim, spec_from_args

EXIT_OUT_OF_TOLERANCE = 3


def check_options(args: argparse.Namespace) -> None:
    """The command's own options, before any work (exit 2 naming the option, nothing written)."""
    pct = args.acceleration_limit
    if pct is not None and not (math.isfinite(pct) and 0.0 < pct <= 100.0):
        raise SpecError("--acceleration-limit", f"must be a percentage in (0, 100] of the designed peak acceleration, "
                        f"got {pct:g}")


def run(args: argparse.Namespace) -> int:
    check_options(args)
    spec = spec_from_args(args)
    points = read_points(args.points)                 # bad file: exit 2 naming file, line and rule
    if args.output is not None:
        admit_output(args, spec, "inspect")
    design = design_for(spec)
    result = inspect_design(design, points, tolerance=args.tolerance, datum=args.datum,
                            wavelength_deg=args.wavelength,
                            acceleration_limit=None if args.acceleration_limit is None else args.acceleration_limit / 100.0)
    if args.output is None:
        report = json.loads(report_json_text(result.summary()))     # the numbers inspection.json would hold
    else:
        report = write_inspection(result, args.output, output_claim(args, spec, "inspect"))
    failed = bool(report.get("tolerance")) and report["tolerance"]["verdict"] == "fail"
    args.status = EXIT_OUT_OF_TOLERANCE if failed else 0
    print_table(report, None if args.output is None else Path(args.output))
    return args.status


def print_table(report: Mapping[str, Any], out: Path | None) -> None:
    """inspection.json's numbers as one table — the values printed are inspection.json's own."""
    con = Console(soft_wrap=True)
    table = Table(title=f"inspection: {report['cam']}")
    for col in ("quantity", "value", "unit", "at cam angle"):
        table.add_column(col, justify="left" if col == "quantity" else "right")
    for label, key, unit, at in rows(report):
        where = "—" if at is None else f"{fmt(lookup(report, at))}°"
        table.add_row(escape(label), escape(fmt(lookup(report, key))), escape(unit), where)
    con.print(table)
    columns = harmonic_columns(report)
    harmonics = Table(title="the deviation's largest harmonics: e = A·cos(nθ + φ), θ the cam angle of contact")
    for head, _key, unit in columns:
        harmonics.add_column(escape(f"{head} [{unit}]" if unit else head), justify="right", overflow="fold")
    for h in report["harmonics"]["largest"]:
        harmonics.add_row(*(escape(fmt(h[k])) if k in h else "—" for _h, k, _u in columns))
    con.print(harmonics)
    tol = report.get("tolerance")
    line = ("no profile tolerance given (--tolerance T): no verdict" if not tol else
            f"profile verdict: {tol['verdict']} (zone ±{fmt(tol['zone'][1])} {report['units']})")
    if out is not None:
        line += f" — written to {out}/: {', '.join(sorted(report['files']))}"
    con.print(escape(line))

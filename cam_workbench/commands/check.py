"""``cam-workbench check``: the design checks (thesis Ch. 3) as a table and as the ``checks``
section of report.json; exit status 3 when a check fails, so scripts can gate on it."""
from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from exporters.atomic import OutputSet
from exporters.report_json import report_json_text
from generators.cam_area import area_summary
from generators.design_checks import DesignChecks, format_value, run_checks
from generators.spec import CamSpec, spec_digest

from .common import add_spec_arguments, spec_from_args

EXIT_CHECK_FAILED = 3


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "check", help="run the design checks: a table, and the checks section of report.json",
        description="Evaluate the design checks of the spec's cam — pressure angle, separation "
                    "(driving force), oscillation, Hertz contact stress, radius of curvature with the "
                    "undercut safety factor, and the true roller-envelope undercut (thesis Ch. 3) — "
                    "print them as a table and write them as the `checks` section of report.json in the "
                    "output folder (merged into a report.json that `build` wrote for the same spec). "
                    "Limits and sampling come from the spec's [checks], [material] and [follower].",
        epilog="exit status: 0 every check passes, 3 a check failed, 2 bad input (nothing written).",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    p.add_argument("-o", "--output", default="out", metavar="OUT",
                   help="output folder for report.json (created if needed; default: out)")
    p.add_argument("--sampling", choices=("dense", "thesis71"),
                   help="override checks.sampling: dense sampling, or the thesis' 71 nodes per rise/return")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    spec = spec_from_args(args)
    if args.sampling:
        spec = spec.replace(**{"checks.sampling": args.sampling})
    checks = run_checks(spec)
    out = Path(args.output)
    report = merged_report(out / "report.json", spec, checks)
    with OutputSet(out) as o:
        o.add_text("report.json", report_json_text(report))
    print_table(checks, spec, out, report["areas"])
    return 0 if checks.passed else EXIT_CHECK_FAILED


def merged_report(path: Path, spec: CamSpec, checks: DesignChecks) -> dict[str, Any]:
    """report.json with a fresh ``checks`` section: merged into the existing report when that
    report was written for the same spec (same ``spec_digest``), else a new report."""
    digest = spec_digest(spec)
    base: dict[str, Any] = {}
    if path.exists():
        try:
            old = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            old = None
        if isinstance(old, dict) and old.get("spec_digest") == digest:
            base = old
    if not base:
        base = {"units": spec.units, "spec_digest": digest, "areas": area_summary(spec)}
    base["checks"] = checks.to_dict()
    return base


def print_table(checks: DesignChecks, spec: CamSpec, out: Path, areas: dict[str, float]) -> None:
    """The checks as a rich table, then the extremes (the thesis' "Maximum Values")."""
    from rich.console import Console
    from rich.table import Table

    console = Console()
    mode = ("the thesis' 71 nodes per rise/return" if checks.sampling == "thesis71"
            else f"{checks.samples} samples per rise/return, refined extrema")
    table = Table(title=f"design checks ({mode})")
    for col in ("check", "value", "at", "limit", "status"):
        table.add_column(col, justify="left" if col in ("check", "status") else "right")
    style = {"pass": "green", "fail": "bold red", "skipped": "yellow"}
    for r in checks.results:
        op = "≤" if r.kind == "max" else ("≥" if r.name in ("oscillation", "curvature") else ">")
        limit = "—" if r.limit is None else f"{op} {format_value(r.limit, r.unit)}"
        at = "—" if r.at_deg is None else f"{r.at_deg:.3f}°"
        status = f"[{style[r.status]}]{r.status}[/]" + (f" ({r.note})" if r.note and r.status != "pass" else "")
        table.add_row(f"{r.name} ({r.kind})", format_value(r.value, r.unit), at, limit, status)
    console.print(table)
    ext = Table(title="extremes (largest magnitude, signed)")
    for col in ("quantity", "value", "at"):
        ext.add_column(col, justify="left" if col == "quantity" else "right")
    for name, e in checks.extremes.items():
        ext.add_row(name.replace("_", " "), format_value(e["value"], e["unit"]), f"{e['at_deg']:.3f}°")
    console.print(ext)
    u = spec.units
    console.print(f"area (thesis Eq. 4.21–4.27, inside the pitch curve): {areas['thesis_eq_4_21']:.6g} {u}²; "
                  f"cam cross-section: {areas.get('built_cross_section', areas['cross_section']):.6g} {u}²")
    verdict = "[green]all checks pass[/]" if checks.passed else f"[bold red]failed: {', '.join(checks.failed)}[/]"
    console.print(f"{verdict} — checks written to {out}/report.json")

"""``cam-workbench batch``: many specs built as ``build`` builds one, each into its own subfolder,
with a summary table (CSV, Parquet) of every cam's key numbers and checks; on Dask or here."""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.markup import escape

from cam_workbench.generators.errors import SpecError

from . import EXIT_CHECK_FAILED
from ..studies import batch, collect_specs
from .common import check_parallel_arguments, count_progress, note, parse_value, require_ocp

EXIT_SOME_FAILED = 4


def run(args: argparse.Namespace) -> int:
    check_parallel_arguments(args)
    require_ocp("batch")
    changes: dict[str, Any] = {}
    for item in args.overrides:
        if "=" not in item:
            raise SpecError(item, "--set needs FIELD=VALUE")
        key, value = item.split("=", 1)
        changes[key.strip()] = parse_value(value, key.strip())
    jobs = collect_specs(args.specs)                 # no spec at all: exit 2 before any work
    bar, cb = count_progress(len(jobs), "building", "cams")
    with bar:
        table = batch(args.specs, args.output, changes=changes or None, workers=args.workers,
                      scheduler=args.scheduler, progress=cb, note=note, replace=args.replace, option="-o")
    return _report(table, Path(args.output))


def _report(table: Any, out: Path) -> int:
    con = Console(soft_wrap=True)
    rows = table.rows
    ok = [r for r in rows if r["status"] == "ok"]
    bad = [r for r in rows if r["status"] != "ok"]
    failing = [r for r in ok if not r.get("checks_passed")]
    for r in bad:
        con.print(escape(f"{r['name']}: {r['status']}: {r['error']}"), style="red")
    for r in failing:
        con.print(escape(f"{r['name']}: fails {r['failed_checks'].replace(';', ', ')}"), style="yellow")
    m = table.meta
    con.print(escape(f"{len(ok)} of {len(rows)} cams built into {out}/ ({len(failing)} failing a design check, "
                     f"{len(bad)} not built) in {m['time_s']:.1f} s on {m['workers']} worker"
                     f"{'s' if m['workers'] != 1 else ''}; summary: {out}/summary.csv"
                     + (", summary.parquet" if (out / "summary.parquet").exists() else "")))
    if bad:
        return EXIT_SOME_FAILED
    return EXIT_CHECK_FAILED if failing else 0

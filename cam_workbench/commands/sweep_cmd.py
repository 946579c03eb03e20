"""``cam-workbench sweep``: a grid of spec fields evaluated (designed and checked, no solid),
sized (the smallest base radius meeting the checks: a sizing chart) or built; on Dask or here."""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from cam_workbench.exporters.output_rule import admit
from cam_workbench.generators.studies.grid import Grid
from cam_workbench.generators.studies.sizing import digits_of

from ..studies import grid_columns, make_grid, sweep, sweep_claim, write_study
from .common import check_parallel_arguments, count_progress, note, require_ocp, source_of, spec_from_args

EXIT_SOME_FAILED = 4


def run(args: argparse.Namespace) -> int:
    check_parallel_arguments(args)
    spec = spec_from_args(args)
    grid: Grid = make_grid(args.vary, args.balance)
    grid.check(spec, fixed=("cam.base_radius",) if args.size else ())
    if args.build:
        require_ocp("sweep --build")
    out = Path(args.output)
    source = source_of(args)
    admit(out, sweep_claim(spec, grid, size=bool(args.size), checks=args.size_checks, tol=args.tol, build=args.build,
                           source=source, replace=args.replace, option="-o"))    # before any work
    bar, cb = count_progress(grid.size, "sizing" if args.size else "building" if args.build else "evaluating",
                             "points")
    with bar:
        table = sweep(spec, grid.axes, balance=grid.balance, size=bool(args.size), checks=args.size_checks,
                      tol=args.tol, build=out if args.build else None, workers=args.workers,
                      scheduler=args.scheduler, progress=cb, note=note, source=source, replace=args.replace,
                      option="-o")
    files = {} if args.build else write_study(table, out, replace=args.replace, option="-o")
    _print(table, out, files)
    return 0 if table.ok else EXIT_SOME_FAILED


def _print(table: Any, out: Path, files: dict[str, str]) -> None:
    con = Console(soft_wrap=True)
    rows = table.rows
    bad = [r for r in rows if r["status"] not in ("ok", "no radius")]
    meta = table.meta
    cols = grid_columns(table)
    if meta.get("kind") == "sizing":
        # the radius with the digits the bisection's tolerance supports (on its grid: sizing.TolGrid)
        digits = digits_of(meta["tolerance"])
        t = Table(*cols, "smallest R_b", "binding check", title=f"smallest base radius ({meta['units']}, "
                  f"to {meta['tolerance']:g})")
        for r in rows[:40]:
            val = r.get("min_base_radius")
            t.add_row(*(escape(_fmt(r.get(c))) for c in cols),
                      "—" if val is None else f"{val:.{digits}f}",
                      escape(r.get("binding_checks") or r.get("error") or r["status"]))
        con.print(t)
        if len(rows) > 40:
            con.print(f"… {len(rows) - 40} more rows in the table")
    for r in bad[:10]:
        con.print(escape(", ".join(f"{c}={_fmt(r.get(c))}" for c in cols) + f": {r['status']}: {r['error']}"),
                  style="red")
    if len(bad) > 10:
        con.print(f"… {len(bad) - 10} more points not evaluated (see the table)", style="red")
    names = ", ".join(files.values()) if files else "summary.csv, summary.parquet, point-*/"
    con.print(escape(f"{len(rows) - len(bad)} of {len(rows)} points evaluated in {meta['time_s']:.1f} s on "
                     f"{meta['workers']} worker{'s' if meta['workers'] != 1 else ''}; written to {out}/: {names}"))


def _fmt(v: Any) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)

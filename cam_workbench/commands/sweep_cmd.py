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

from . import add_command
from ..studies import grid_columns, make_grid, sweep, sweep_claim, write_study
from .common import (add_output_arguments, add_parallel_arguments, add_spec_arguments, check_parallel_arguments,
                     count_progress, note, require_ocp, source_of, spec_from_args)

EXIT_SOME_FAILED = 4


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "sweep",
        description="Vary spec fields over a grid and evaluate every point: design and check the cam (no "
                    "solid; --build: every file as `build` writes them, one subfolder per point), or, with "
                    "--size base_radius, find the smallest cam.base_radius that passes the design checks "
                    "(bisection with the dense checks, to --tol) and draw the sizing chart: that radius over "
                    "the first numeric axis, one line per value of the next, one panel per value of a "
                    "categorical axis (the handbook nomogram). Writes sweep.csv/sweep.parquet (or "
                    "sizing.csv/sizing.parquet and sizing_chart.png) and study.json into OUT. A point whose "
                    "spec breaks a rule is a row saying why.",
        epilog="examples:\n"
               "  cam-workbench sweep --vary motion[1].lift,motion[3].lift=10:30:5 "
               "--vary motion[1].law,motion[3].law=cycloidal,harmonic -o lifts\n"
               "  cam-workbench sweep --vary motion[1].angle,motion[3].angle=60:150:10 --balance "
               "motion[2].angle \\\n      --vary motion[1].law,motion[3].law=cycloidal,harmonic,poly345 "
               "--size base_radius --size-checks pressure_angle,curvature -o chart\n\n"
               "exit status: 0 the table is written (rows of points that fail a check are results); 4 some "
               "points could not be evaluated (bad input, cannot be made: their rows say why; the table is "
               "written); 2 bad command line (nothing written); 130 interrupted (nothing written; with "
               "--build the points done stay).",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    p.add_argument("--vary", action="append", default=[], metavar="FIELD=START:STOP:COUNT",
                   help="an axis of the grid: FIELD=START:STOP:COUNT (COUNT values, ends included) or "
                        "FIELD=V1,V2,… (numbers or words, e.g. motion[1].law=cycloidal,harmonic); "
                        "FIELD1,FIELD2=… sets several fields to the same value (a rise and its return). "
                        "Repeatable: the grid is every combination")
    p.add_argument("--balance", metavar="FIELD",
                   help="a dwell's motion[k].angle that takes up the rest of 360° at every point "
                        "(so a rise's angle can vary)")
    p.add_argument("--size", metavar="FIELD", choices=("base_radius", "cam.base_radius"),
                   help="size FIELD (base_radius): its smallest value that passes the checks, per point")
    p.add_argument("--size-checks", metavar="LIST", default=None,
                   help="the checks --size must pass, e.g. pressure_angle,curvature (default: every check)")
    p.add_argument("--tol", type=float, metavar="T", default=None,
                   help="--size: bisection tolerance on the radius, in the spec's unit (default 0.01 mm, "
                        "0.0005 in)")
    p.add_argument("--build", action="store_true",
                   help="build every point's cam with all of `build`'s files (OUT/point-NNN/)")
    add_parallel_arguments(p, "the points")
    add_output_arguments(p, "sweep")
    p.set_defaults(run=run)


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

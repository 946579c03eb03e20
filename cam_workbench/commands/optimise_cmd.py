"""``cam-workbench optimise``: minimise the cam area, a machining time or a peak over base radius,
the follower's position (offset; pivot distance and arm length of an oscillating follower),
B-spline control points (and the blank orientation) with every design check of the follower kind
as a constraint (thesis Ch. 5–7, nlopt); writes the optimised spec, report.json with an ``optimise``
section, report.html with the convergence figure, and with ``--plots`` the figures as PNG files."""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.markup import escape
from rich.progress import BarColumn, Progress as Bar, TextColumn, TimeElapsedColumn

from cam_workbench.generators.checks.areas import area_label
from cam_workbench.generators.optimise import Progress, optimise
from cam_workbench.generators.spec import to_toml

from . import EXIT_CHECK_FAILED
from ..pipeline import plot_count, run_pipeline, write_outputs
from ..studies import executor_scope
from .common import (admit_output, check_parallel_arguments, note, on_terminal, output_claim, plot_progress,
                     require_ocp, require_png, spec_from_args)
from .parsers import OPTIMISED_SPEC as SPEC_NAME



def _progress_bar(budget: int) -> tuple[Any, Any]:
    bar = Bar(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total} evaluations"),
              TimeElapsedColumn(), transient=True, disable=not on_terminal())
    task = bar.add_task("optimising", total=budget)

    def callback(p: Progress) -> bool:
        best = "—" if p.best is None else f"{p.best:.6g}"
        bar.update(task, completed=p.evaluations, total=max(p.budget, p.evaluations),
                   description=f"{p.phase}: best {best}, violation {p.max_violation:+.2e}")
        return True

    return bar, callback


def run(args: argparse.Namespace) -> int:
    check_parallel_arguments(args)
    spec = spec_from_args(args)
    require_ocp("optimise")
    if args.plots:
        require_png()
    changes: dict[str, Any] = {}
    for name in ("max_evaluations", "multistart", "seed"):
        if getattr(args, name) is not None:
            changes[name] = getattr(args, name)
    # validate the overrides before any work (bad input: exit 2, nothing written)
    over = {f"optimise.{k}": v for k, v in (("objective", args.objective), ("variables", args.variables),
                                               ("algorithm", args.algorithm)) if v is not None}
    over.update({f"optimise.{k}": v for k, v in changes.items()})
    if over:
        spec = spec.replace(**over)
    admit_output(args, spec, "optimise")
    cfg = spec.optimise
    budget = cfg.max_evaluations * (1 + cfg.multistart)
    bar, cb = _progress_bar(budget)
    # the starts on Dask (the same result as one after another); a single start runs here
    with executor_scope(None, args.workers, args.scheduler, tasks=1 + cfg.multistart, note=note) as ex, bar:
        result = optimise(spec, progress=cb, executor=ex)
    # the optimised cam through the one pipeline: the folder holds its full set of files
    outputs = run_pipeline(result.spec)
    outputs.summary["optimise"] = result.report()
    out = Path(args.output)
    prog, pcb = plot_progress(plot_count(outputs))
    with prog:
        report = write_outputs(outputs, out, output_claim(args, result.spec, "optimise"),
                               extra_texts={SPEC_NAME: to_toml(result.spec)}, progress=pcb, plots=args.plots)
    _print(result, out, report)
    return 0 if result.feasible else EXIT_CHECK_FAILED


def _print(result: Any, out: Path, report: dict[str, Any]) -> None:
    """The run's summary, every figure and verdict taken from report.json's ``optimise`` section:
    its status and message exactly as written there, and whether the start was feasible."""
    con = Console(soft_wrap=True)         # no wrapping: the lines are report.json's own text
    opt = report["optimise"]
    unit = opt["objective_unit"]
    red = opt["reduction_percent"]
    key = f", report.json {opt['objective_key']}" if opt["objective_key"] else ""
    change = "" if red is None else f" ({red:.2f} % smaller)" if red >= 0 else f" ({-red:.2f} % larger)"
    con.print(escape(f"objective {opt['objective']} ({opt['objective_label']}{key}): {opt['initial_value']:.6g} → "
                     f"{opt['final_value']:.6g} {unit}{change} in {opt['evaluations']} evaluations, "
                     f"{opt['time_s']:.2f} s"))
    if "areas" in report:           # a plane cam: its cross-section is not the objective's area
        con.print(escape(f"the optimised cam's {area_label('area')}: {report['area']:.6g} {report['units']}² "
                         "(report.json area)"))
    con.print(escape(f"status: {opt['status_text']}"))
    con.print(escape(f"message: {opt['message']}"))
    if not opt["initial_feasible"]:
        for v in opt["initial_violations"]:
            unit_v = f" {v['unit']}" if v["unit"] else ""
            at = f" at {v['at_deg']:.2f}°" if v["at_deg"] is not None else ""
            con.print(escape(f"start infeasible: {v['name']} = {v['value']:.6g}{unit_v}{at} "
                             f"(limit {v['limit']:.6g}{unit_v})"))
    for v in opt["variables"]:
        con.print(escape(f"  {v['name']:28s} {v['initial']:12.6g} → {v['final']:12.6g}"))
    w = opt["worst_constraint"]
    if w:
        con.print(escape(f"  closest to its limit: {w['name']} = {w['value']:.6g} {w['unit']} at {w['at_deg']:.2f}° "
                         f"(limit {w['limit']:.6g})"))
    if opt["feasible"]:
        con.print("[green]every design check passes (dense re-check)[/]")
    else:
        con.print(f"[bold red]the result FAILS the dense check: {escape(opt['failed_checks'])}[/]")
    names = [v for k, v in report["files"].items() if isinstance(v, str)]
    plots = report["files"]["plots"]
    con.print(escape(f"written to {out}/: {', '.join(names)}" + (f", {len(plots)} plots" if plots else "")))

"""Helpers shared by the CLI commands when they run: reading the spec, ``--set`` overrides, the output
folder's claim, progress, the run that ``build`` and ``report`` share (their arguments: :mod:`.parsers`)."""
from __future__ import annotations

import argparse
import contextlib
import sys
from pathlib import Path
from typing import Any, Callable

from rich.console import Console
from rich.progress import BarColumn, Progress, SpinnerColumn, TextColumn, TimeElapsedColumn, TimeRemainingColumn

from cam_workbench.exporters.chart_png import require_png
from cam_workbench.exporters.output_rule import Claim, admit, file_source, spec_claim
from cam_workbench.generators.cam_design import CamDesign, design_cam
from cam_workbench.generators.errors import GeometryError, SpecError
from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.generators.spec import CamSpec, load_spec
from cam_workbench.generators.studies.remedies import with_remedy

from ..kernel.ocp import require
from ..parallel import import_distributed
from ..pipeline import plot_count, run_pipeline, write_outputs

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib  # type: ignore[no-redef]


def source_of(args: argparse.Namespace) -> str:
    """The cam the run is for: ``--source``, SPEC's resolved path, or ``example:NAME``."""
    if args.source:
        return str(args.source)
    return file_source(args.spec) if args.spec else f"example:{args.example or 'default'}"


def output_claim(args: argparse.Namespace, spec: CamSpec, command: str) -> Claim:
    """The claim of ``command`` writing the files of ``spec``'s cam into ``-o``."""
    return spec_claim(spec, command, source_of(args), replace=args.replace)


def admit_output(args: argparse.Namespace, spec: CamSpec, command: str, names: tuple[str, ...] | None = None) -> None:
    """Before any work: refuse ``-o`` where ``command`` may not write the files ``names`` (None:
    not known yet — then only what no run could write into; the full rule is applied again when
    the files are written) — exit 2, nothing written."""
    admit(args.output, output_claim(args, spec, command), names)


def parse_value(text: str, field: str = "--set") -> Any:
    """A ``--set`` value: true/false, a [list], integer, number, or text."""
    low = text.strip().lower()
    if low in ("true", "false"):
        return low == "true"
    if low.startswith("["):            # a list, e.g. --set "motion[1].control_y=[0.1, 0.6, 0.9]"
        try:
            return tomllib.loads(f"v = {text.strip()}")["v"]
        except tomllib.TOMLDecodeError:
            raise SpecError(field, f"{text!r} is not a valid list (write it as in TOML: [1.0, 2.5])") from None
    for conv in (int, float):
        try:
            return conv(text)
        except ValueError:
            pass
    return text.strip().strip('"')


def spec_from_args(args: argparse.Namespace, options: dict[str, Any] | None = None) -> CamSpec:
    """The spec named on the command line (or the default) with ``--set`` overrides applied, and
    then the command's own ``options`` (dotted field → value, e.g. ``gcode --mode``), in one change:
    the spec's rules see the combination asked for, not a half-made one."""
    if args.spec and args.example:
        raise SpecError("--example", "give a SPEC file or --example, not both")
    spec = load_spec(args.spec) if args.spec else example_spec(args.example or "default")
    changes = {}
    for item in args.overrides:
        key, eq, value = item.partition("=")
        if not eq or not key.strip():
            # the message names --set: there is no field to name (and an odd item is no field name)
            raise SpecError("--set", f"needs FIELD=VALUE, e.g. cam.base_radius=30, got {item!r}")
        changes[key.strip()] = parse_value(value, key.strip())
    changes.update(options or {})
    return spec.replace(**changes) if changes else spec


def require_ocp(command: str) -> None:
    """Before any work: the commands that build the solid (build, report, optimise) need OCP;
    without it they exit 2 with one line naming the extras that bring it (nothing written)."""
    require(f"cam-workbench {command} (the solid, its checks and cam.step)")


def design_for(spec: CamSpec, remedy: bool = True) -> CamDesign:
    """``design_cam(spec)``, with a progress display while ``pitch.tolerance`` chooses M; a cam that
    cannot be made is refused with the change that would make it (``remedy``:
    :func:`cam_workbench.generators.studies.remedies.with_remedy`)."""
    try:
        if spec.pitch.tolerance is None:
            return design_cam(spec)
        prog, cb = progress_reporter("choosing M for pitch.tolerance")
        with prog:
            return design_cam(spec, progress=cb)
    except GeometryError as exc:
        if not remedy:
            raise
        raise with_remedy(spec, exc) from None


def write_cam(args: argparse.Namespace, command: str, *, report_only: bool = False) -> tuple[dict[str, Any], Path]:
    """The run ``build`` and ``report`` share: the spec, OCP and the ``-o`` folder checked before
    any work, the design (with its progress), every stage of the pipeline (the dynamics with a
    progress bar when the spec asks), then the files written as one set with a progress bar over
    the figures.  ``report_only``: of the files, only the report's (report.json, report.html, with
    ``--plots`` the PNG figures) — its numbers are still ``build``'s.  Returns (the report as written, the folder)."""
    spec = spec_from_args(args)
    require_ocp(command)
    if args.plots:
        require_png()
    admit_output(args, spec, command)
    design = design_for(spec)
    bar, dcb = dynamics_progress(spec)
    with bar:
        outputs = run_pipeline(spec, design=design, dynamics_progress=dcb)
    if report_only:
        outputs.step_shape = outputs.machining = outputs.dxf = None
    out = Path(args.output)
    prog, cb = plot_progress(plot_count(outputs))
    with prog:
        report = write_outputs(outputs, out, output_claim(args, spec, command), progress=cb, plots=args.plots)
    return report, out


def on_terminal() -> bool:
    """Whether standard output is a terminal: progress displays are drawn there only, so that a
    redirected output holds the command's result alone (``gcode`` writes its program there)."""
    return Console().is_terminal


def progress_reporter(description: str) -> tuple[Any, Callable[[int, float], None]]:
    """A rich progress display (context manager) and a callback for the tolerance search."""
    prog = Progress(SpinnerColumn(), TextColumn("{task.description}"), TimeElapsedColumn(),
                    transient=True, disable=not on_terminal())
    task = prog.add_task(description, total=None)

    def callback(m: int, dev: float) -> None:
        prog.update(task, description=f"{description}: M = {m}, deviation {dev:.3g}")

    return prog, callback


def plot_progress(total: int) -> tuple[Any, Callable[[str], None]]:
    """A rich progress bar over the report's figures, and its callback."""
    prog = Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
                    TimeElapsedColumn(), transient=True, disable=not on_terminal())
    task = prog.add_task("report", total=total)
    started = [False]

    def callback(title: str) -> None:
        if started[0]:
            prog.advance(task)
        started[0] = True
        prog.update(task, description=f"plotting: {title}")

    return prog, callback


def sweep_progress() -> tuple[Any, Any]:
    """A rich progress bar over the jump-speed sweep and bisection, and its callback."""
    bar = Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
                   TimeElapsedColumn(), transient=True, disable=not on_terminal())
    task = bar.add_task("jump-speed sweep", total=None)

    def callback(done: int, total: int, what: str) -> None:
        bar.update(task, completed=done, total=total, description=what)

    return bar, callback


def dynamics_progress(spec: CamSpec) -> tuple[Any, Callable[[int, int, str], None] | None]:
    """A rich progress bar over the jump-speed sweep when the spec asks for its dynamics
    (``dynamics.enabled``), else a no-op context and no callback."""
    if not (spec.dynamics.enabled and spec.dynamics.sweep_points > 0):
        return contextlib.nullcontext(), None
    return sweep_progress()


def check_parallel_arguments(args: argparse.Namespace) -> None:
    """Refuse bad ``--workers``/``--scheduler`` before any work (exit 2)."""
    if args.workers is not None and args.workers < 0:
        raise SpecError("--workers", f"must be ≥ 0, got {args.workers}")
    if args.scheduler is not None and args.workers not in (None,):
        raise SpecError("--scheduler", "give --workers or --scheduler, not both")
    if args.scheduler is not None or (args.workers or 0) >= 1:
        import_distributed(f"--{'scheduler' if args.scheduler else 'workers'}")


def note(text: str) -> None:
    """One line on standard error (a note, not an error)."""
    print(f"note: {text}", file=sys.stderr)


def count_progress(total: int, description: str, unit: str) -> tuple[Any, Callable[[int, int], None]]:
    """A rich progress bar over ``total`` items (designs, cams, points) and its callback
    ``(done, total)``."""
    prog = Progress(TextColumn("{task.description}"), BarColumn(),
                    TextColumn("{task.completed}/{task.total} " + unit), TimeElapsedColumn(),
                    TextColumn("eta"), TimeRemainingColumn(), transient=True, disable=not on_terminal())
    task = prog.add_task(description, total=total)

    def callback(done: int, n: int) -> None:
        prog.update(task, completed=done, total=n)

    return prog, callback

"""Running a command: its module loaded — that command's alone, by :data:`RUNNERS` — and run,
with the exit statuses and one-line messages of :mod:`cam_workbench.cli`, which parses the
arguments with :mod:`.parsers` (loading no command) and loads this module only when a command is
to run."""
from __future__ import annotations

import argparse
import sys
from typing import Callable

from rich.console import Console

from cam_workbench.generators.errors import CamError

from . import EXIT_BAD_INPUT, EXIT_INTERNAL, EXIT_OK, silence_stdout

#: a command's ``run(args)``: its exit status
Runner = Callable[[argparse.Namespace], int]


def _build() -> Runner:
    from . import build  # deferred: the command's module (numpy, scipy, the generators, the exporters)

    return build.run


def _check() -> Runner:
    from . import check  # deferred: the command's module (numpy, scipy, the generators)

    return check.run


def _gcode() -> Runner:
    from . import gcode  # deferred: the command's module (numpy, scipy, the generators)

    return gcode.run


def _dxf() -> Runner:
    from . import dxf_cmd  # deferred: the command's module (numpy, scipy, the generators)

    return dxf_cmd.run


def _report() -> Runner:
    from . import report_cmd  # deferred: the command's module (numpy, scipy, the generators, the exporters)

    return report_cmd.run


def _dynamics() -> Runner:
    from . import dynamics_cmd  # deferred: the command's module (numpy, scipy, the generators)

    return dynamics_cmd.run


def _ecam() -> Runner:
    from . import ecam_cmd  # deferred: the command's module (numpy, scipy, the generators)

    return ecam_cmd.run


def _optimise() -> Runner:
    from . import optimise_cmd  # deferred: the command's module (numpy, scipy, the generators, the optimiser)

    return optimise_cmd.run


def _batch() -> Runner:
    from . import batch_cmd  # deferred: the command's module (the studies)

    return batch_cmd.run


def _sweep() -> Runner:
    from . import sweep_cmd  # deferred: the command's module (the studies)

    return sweep_cmd.run


def _machine() -> Runner:
    from . import machine_cmd  # deferred: the command's module (the generators, the exporters, the pipeline)

    return machine_cmd.run


def _spec() -> Runner:
    from . import spec_cmd  # deferred: the command's module (the spec's declarations)

    return spec_cmd.run


def _tolerance() -> Runner:
    from . import tolerance_cmd  # deferred: the command's module (numpy, scipy, the generators)

    return tolerance_cmd.run


def _inspect() -> Runner:
    from . import inspect_cmd  # deferred: the command's module (numpy, scipy, the generators, the exporters)

    return inspect_cmd.run


def _freecad() -> Runner:
    from . import freecad_cmd  # deferred: the command's module (the workbench's installer)

    return freecad_cmd.run


#: command (``command_id``, :mod:`.parsers`) → its runner, loading the command's module when called
RUNNERS: dict[str, Callable[[], Runner]] = {
    "build": _build, "check": _check, "gcode": _gcode, "dxf": _dxf, "report": _report, "dynamics": _dynamics,
    "ecam": _ecam, "optimise": _optimise, "batch": _batch, "sweep": _sweep, "machine": _machine, "spec": _spec,
    "freecad": _freecad, "tolerance": _tolerance, "inspect": _inspect,
}


def run(args: argparse.Namespace) -> int:
    """Run the command ``args`` names (``args.command_id``, parsed by :func:`.parsers.parser`);
    returns the exit status."""
    args.status = EXIT_OK          # a command sets it before it prints its last tables
    _broken_pipe_raises()
    try:
        return int(RUNNERS[args.command_id]()(args) or 0)
    except BrokenPipeError:
        # the reader of stdout went away (`… | head`): not an error of ours — the files are
        # written; stop printing and keep the command's status
        silence_stdout()
        return int(args.status)
    except CamError as exc:
        print(f"error: {_one_line(str(exc))}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt as exc:
        # one line: what was kept, when the command says (batch, sweep --build)
        print(f"interrupted: {exc}" if str(exc) else "interrupted", file=sys.stderr)
        return 130
    except (MemoryError, RecursionError) as exc:
        print(f"error: input too large to process ({type(exc).__name__}); nothing was written", file=sys.stderr)
        return EXIT_BAD_INPUT
    except OSError as exc:
        where = exc.filename or getattr(args, "output", None) or "output"
        print(f"error: {where}: {exc.strerror or exc}; nothing was written", file=sys.stderr)
        return EXIT_BAD_INPUT
    except Exception as exc:  # noqa: BLE001 - last-resort report, never a bare traceback
        if args.debug:
            raise
        print(f"internal error: {type(exc).__name__}: {exc} (run with --debug for details)",
              file=sys.stderr)
        return EXIT_INTERNAL


def _one_line(text: str) -> str:
    """A message on one line (a spec value may carry newlines)."""
    return " ".join(text.split())


def _broken_pipe_raises() -> None:
    """rich ends the process with exit 1 when stdout's reader goes away; let it raise
    BrokenPipeError instead, which :func:`run` turns into the command's own status."""

    def on_broken_pipe(self: Console) -> None:
        raise BrokenPipeError(32, "Broken pipe")

    Console.on_broken_pipe = on_broken_pipe  # type: ignore[method-assign]

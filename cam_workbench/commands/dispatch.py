"""Running a command: the full parser (every command's module, :data:`COMMANDS`) and the run,
with the exit statuses and one-line messages of :mod:`cam_workbench.cli` (which loads this module
only when a command is to run)."""
from __future__ import annotations

import argparse
import sys
from typing import Sequence

from rich.console import Console

from cam_workbench.generators.errors import CamError

from . import (batch_cmd, build, check, dxf_cmd, dynamics_cmd, ecam_cmd, freecad_cmd, gcode, optimise_cmd,
               report_cmd, spec_cmd, sweep_cmd)
from . import EXIT_BAD_INPUT, EXIT_INTERNAL, EXIT_OK, root_parser, silence_stdout

#: every command's module, in the order of :data:`cam_workbench.commands.CATALOGUE`
COMMANDS = [build, check, gcode, dxf_cmd, report_cmd, dynamics_cmd, ecam_cmd, optimise_cmd, batch_cmd, sweep_cmd,
            spec_cmd, freecad_cmd]


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every registered command."""
    parser, sub = root_parser()
    for module in COMMANDS:
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Parse ``argv`` and run the command; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    args.status = EXIT_OK          # a command sets it before it prints its last tables
    _broken_pipe_raises()
    try:
        return int(args.run(args) or 0)
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
    BrokenPipeError instead, which :func:`main` turns into the command's own status."""

    def on_broken_pipe(self: Console) -> None:
        raise BrokenPipeError(32, "Broken pipe")

    Console.on_broken_pipe = on_broken_pipe  # type: ignore[method-assign]

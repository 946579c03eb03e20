"""``cam-workbench``: the command line.

Every command reads a spec (TOML) or the built-in default, and writes its files
atomically into an output folder or the file named (``check`` and ``dynamics`` only with ``-o``),
never over another cam's files or the user's (docs/cli.md, "Output folders and your files").
Exit status: 0 success, 2 bad input, a cam that cannot be made or a refused output (message
names the field/rule, the cam angle or ``-o``; nothing is written), 3 a design check failed
(``check``), 4 some specs or grid points of a ``batch`` or ``sweep`` could not be built (the
table says why; the others are written), 1 an internal error.
"""
from __future__ import annotations

import argparse
import os
import sys
from typing import Sequence

from rich.console import Console

from cam_workbench.generators import __version__
from cam_workbench.generators.errors import CamError

from .commands import COMMANDS

EXIT_OK, EXIT_INTERNAL, EXIT_BAD_INPUT, EXIT_CHECK_FAILED = 0, 1, 2, 3

DESCRIPTION = """\
Exact plate cams from a follower-motion program: the pitch curve as a closed C² PH
quintic spline, the profile as its exact rational offset (NURBS), STEP solids and
design reports.

Run a command with --help for its options; `cam-workbench spec` prints every spec
field with its unit, default and rule.
"""

EPILOG = """\
examples:
  cam-workbench build                       # the built-in default cam into ./out
  cam-workbench build cam.toml -o out/cam1  # your spec
  cam-workbench build --set cam.base_radius=30 --set follower.roller_radius=6
  cam-workbench spec --default > cam.toml   # a spec to start from
  cam-workbench check cam.toml              # design checks as a table, exit 3 on a failure
  cam-workbench check cam.toml -o out/cam1  # ... and report.json (kept beside a build of the same spec)
  cam-workbench batch specs/ -o many        # every spec built, with summary.csv/.parquet
  cam-workbench sweep --vary "motion[1].lift,motion[3].lift=10:30:5" --size base_radius -o chart

exit status: 0 ok, 2 bad input, impossible geometry or a refused -o (nothing written),
3 a design check failed, 4 batch/sweep: some specs or points failed (their rows
say why), 130 interrupted, 1 internal error.
"""


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every registered command."""
    parser = argparse.ArgumentParser(
        prog="cam-workbench", description=DESCRIPTION, epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks of internal errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module in COMMANDS:
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``cam-workbench`` console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    args.status = EXIT_OK          # a command sets it before it prints its last tables
    _broken_pipe_raises()
    try:
        return int(args.run(args) or 0)
    except BrokenPipeError:
        # the reader of stdout went away (`… | head`): not an error of ours — the files are
        # written; stop printing and keep the command's status
        _silence_stdout()
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


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that Python's flush at exit does not raise again
    (see the Python docs' note on SIGPIPE)."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass


def run() -> None:
    """Console-script wrapper."""
    code = main()
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        _silence_stdout()
    sys.exit(code)


if __name__ == "__main__":
    run()

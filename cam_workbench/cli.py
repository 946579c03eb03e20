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
import sys
from typing import Sequence


from .commands import CATALOGUE, root_parser, silence_stdout

def top_level_parser() -> argparse.ArgumentParser:
    """The parser of the top-level options alone, each command a name and its help
    (:data:`cam_workbench.commands.CATALOGUE`): ``--help``, ``--version`` and a missing command
    are answered by it without loading any command (numpy, the generators).  Its help is the full
    parser's (``tests/test_cli.py``)."""
    parser, sub = root_parser()
    for name, (aliases, help_text) in CATALOGUE.items():
        sub.add_parser(name, aliases=list(aliases), help=help_text, add_help=False)
    return parser


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every registered command (loads every command's module)."""
    from .commands import dispatch  # deferred: every command's module (numpy, scipy, the generators)

    return dispatch.build_parser()


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``cam-workbench`` console script; returns the exit status.  The
    top-level options (``--help``, ``--version``, no command) are answered before any command
    loads; a command runs through :func:`cam_workbench.commands.dispatch.main`."""
    args = list(sys.argv[1:] if argv is None else argv)
    if not args or args[0] in ("-h", "--help", "--version"):
        try:
            top_level_parser().parse_args(args)
        except SystemExit as exc:           # argparse printed the help, the version or the error
            return int(exc.code or 0)
    from .commands import dispatch  # deferred: every command's module (numpy, scipy, the generators)

    return dispatch.main(args)


def run() -> None:
    """Console-script wrapper."""
    code = main()
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        silence_stdout()
    sys.exit(code)




if __name__ == "__main__":
    run()

"""CLI commands: each command's arguments in :mod:`.parsers` (argparse alone: ``--help`` and an
argument error load no command, no numpy), its run in a module of its own (``run(args)``), which
:mod:`.dispatch` loads when the command is to run.

:data:`CATALOGUE` holds each command's name, aliases and one-line help, in the order ``--help``
lists them; each command's parser takes its help from it.  A new command is a module here, an
entry in :data:`CATALOGUE`, one in :data:`.parsers.PARSERS` and one in :data:`.dispatch.RUNNERS`.
"""
from __future__ import annotations

import argparse
import os
import sys
from typing import Any

from cam_workbench import __version__

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

#: command → (aliases, one-line help), in the order of ``cam-workbench --help``
CATALOGUE: dict[str, tuple[tuple[str, ...], str]] = {
    'build': ((), 'build the cam: cam.step, cam.dxf, cam.nc, commands.csv, report.json, report.html, plots'),
    'check': ((), 'run the design checks: a table, and the checks section of report.json'),
    'gcode': ((), 'write one machining program: XY contour, XC rotary or the command table'),
    'dxf': ((), 'write the DXF drawing: the profile as a cubic SPLINE, the exact NURBS, arcs or a polyline'),
    'report': ((), 'write the design report: report.html, plot PNGs, report.json'),
    'dynamics': ((), 'follower dynamics at speed: contact force, separation, jump speed, camshaft torque'),
    'ecam': ((), 'write an electronic-cam table: CSV, CODESYS, Beckhoff or Lenze'),
    'optimise': (('optimize',), 'optimise the cam: area, machining time or smoothness under every design check'),
    'batch': ((), 'build many specs, each into its own subfolder, with a summary table (CSV, Parquet)'),
    'sweep': ((), 'evaluate a grid of spec fields, or size the base radius over it (a sizing chart)'),
    'machine': ((), 'many cams on one camshaft: every cam built, the timing diagram, camshaft torque, flywheel'),
    'spec': ((), 'print the spec reference or the default spec'),
    'freecad': ((), 'install or uninstall the FreeCAD workbench'),
    'tolerance': ((), 'the largest profile tolerance per number of waves that keeps the acceleration error within a limit'),
    'inspect': ((), 'inspect a made cam: measured points registered to the design, deviations, profile verdict, the follower\'s motion'),
}


def root_parser() -> tuple[argparse.ArgumentParser, Any]:
    """(the ``cam-workbench`` parser with the top-level options, its command subparsers to add
    the commands to): the start of :func:`.parsers.parser`."""
    parser = argparse.ArgumentParser(
        prog="cam-workbench", description=DESCRIPTION, epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks of internal errors")
    return parser, parser.add_subparsers(dest="command", metavar="COMMAND", required=True)


def add_command(sub: Any, name: str, **kwargs: Any) -> argparse.ArgumentParser:
    """``sub.add_parser(name, …)`` with the command's aliases and help from :data:`CATALOGUE`."""
    aliases, help_text = CATALOGUE[name]
    return sub.add_parser(name, aliases=list(aliases), help=help_text, **kwargs)


def silence_stdout() -> None:
    """Point stdout at /dev/null so that Python's flush at exit does not raise again after its
    reader went away (see the Python docs' note on SIGPIPE)."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass


__all__ = ["CATALOGUE", "DESCRIPTION", "EPILOG", "EXIT_BAD_INPUT", "EXIT_CHECK_FAILED", "EXIT_INTERNAL", "EXIT_OK",
           "add_command", "root_parser", "silence_stdout"]

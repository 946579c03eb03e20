"""``cam-workbench gcode``: one machining program of a cam — XY contour milling, XC rotary
(G93 inverse time) or the interpolator's raw command table (CSV)."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from cam_workbench.exporters.atomic import write_text_atomic
from cam_workbench.exporters.output_rule import check_output_file
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec import spec_digest

from . import add_command
from ..pipeline import run_pipeline
from .common import add_spec_arguments, design_for, spec_from_args

MODES = ("xy", "xc", "csv")


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "gcode",
        description="Design the cam and write one machining program for it ([machining] section of the "
                    "spec: tool, feeds, passes, sample period; `cam-workbench spec` lists the fields):\n"
                    "  xy   contour milling: the exact tool-centre path as G02/G03 biarcs or G01 chords\n"
                    "       within machining.chord_tolerance, tangent lead arcs, depth passes\n"
                    "  xc   rotary: C axis + X, one G93 inverse-time block per interpolator command\n"
                    "       (each block takes machining.sample_period)\n"
                    "  csv  the rotational interpolator's raw commands (paper Eq. 15) as CSV\n"
                    "Nothing is written if the spec is bad or the cam cannot be made or cut.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    p.add_argument("--mode", choices=MODES, default="xy", help="program to write (default: xy)")
    p.add_argument("--cam", choices=("first", "second"), default="first",
                   help="a conjugate pair (cam.body = \"conjugate\"): the program of the first cam (default) or "
                        "of the second (build writes both: cam.nc and cam2.nc); the command table is the "
                        "follower's, one for both")
    p.add_argument("-o", "--output", metavar="OUT",
                   help="output file (written atomically, replacing a file of that name); omitted: standard output")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    spec = spec_from_args(args)
    if args.mode in ("xy", "xc"):
        spec = spec.replace(**{"machining.program": args.mode})
    if args.output:
        check_output_file(args.output, digest=spec_digest(spec))
    # the same machining stage `build` runs: cam.nc and commands.csv are these texts
    outputs = run_pipeline(spec, solid=False, machining=True, drawing=False, design=design_for(spec))
    if args.mode == "csv":
        text = outputs.machining.commands_csv
    elif args.cam == "second":
        text = outputs.machining.second_gcode
        if text is None:
            raise SpecError("cam.body", f'--cam second needs a conjugate pair (cam.body = "conjugate"), got '
                            f'"{spec.cam.body}"')
    else:
        text = outputs.machining.gcode
    if args.output:
        write_text_atomic(Path(args.output), text)
        print(f"{args.mode} program written to {args.output}", file=sys.stderr)
    else:
        sys.stdout.write(text)
    return 0

"""``cam-workbench gcode``: one machining program of a cam — XY contour milling, XC rotary
(G93 inverse time) or the interpolator's raw command table (CSV) — in the spec's G-code dialect and
cutter compensation, or those of ``--dialect`` / ``--compensation``."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from cam_workbench.exporters.atomic import write_text_atomic
from cam_workbench.exporters.output_rule import check_output_file
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec import spec_digest

from ..pipeline import run_pipeline
from .common import design_for, spec_from_args


def run(args: argparse.Namespace) -> int:
    # the options override the spec's fields (and --set's), checked by their declarations (a bad one names
    # the field) together with the rest: `--mode xy --set machining.compensation=controller` on an XC spec
    # is an XY program under compensation, not a refused XC one
    options = {"machining.program": args.mode} if args.mode in ("xy", "xc", "wire_edm") else {}
    options.update({f"machining.{name}": value for name, value in
                    (("dialect", args.dialect), ("compensation", args.compensation)) if value is not None})
    spec = spec_from_args(args, options)
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
        print(f"{outputs.summary['machining']['program']} program written to {args.output}", file=sys.stderr)
    else:
        sys.stdout.write(text)
    return 0

"""``cam-workbench ecam``: the electronic-cam table of the spec's motion for a servo motion
controller — a CSV of θ, s, s′, s″, s‴, CODESYS SoftMotion (XYVA points or CamBuilder Poly5
segments), Beckhoff TwinCAT NC Camming (motion function or position table) or a Lenze Cam Loader
point table — with the deviation of the table's own interpolation from the exact motion."""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from cam_workbench.exporters.ecam import ecam_table
from cam_workbench.exporters.output_rule import check_output_file
from cam_workbench.generators.spec import spec_digest

from .common import spec_from_args


def run(args: argparse.Namespace) -> int:
    spec = spec_from_args(args)         # any body: the table is the motion's alone
    if args.output:
        check_output_file(args.output, digest=spec_digest(spec))
    table = ecam_table(spec, args.format, table=args.table, step=args.step,
                       boundaries=False if args.no_boundaries else None, name=args.name)
    summary = table.summary()
    text = json.dumps(summary, indent=2) if args.json else describe(summary)
    if args.output:
        table.write(Path(args.output))
        print(text)
        if not args.json:
            print(f"written to {args.output}")
    else:
        sys.stdout.write(table.text)
        print(text, file=sys.stderr)
    return 0


def describe(s: dict) -> str:
    """The summary in words: what was written and each interpolation's deviation (the numbers are
    the summary's, to the digits the file's comment states)."""
    lu = s["lift_unit"]
    lines = [f"{s['format']} {s['table']}: {s['points']} points, step {s['step_deg']:g}°, "
             f"{'equidistant' if s['equidistant'] else 'not equidistant'}"]
    for kind, d in s["deviation"].items():
        acc = ("" if d["max_acceleration_error"] is None else
               f"; Y'' {d['max_acceleration_error']:.3g} {lu}/deg^2 at {d['acceleration_at_deg']:.4f} deg")
        own = " (the controller's)" if kind == s["interpolation"] else ""
        lines.append(f"  {kind} interpolation{own}: max deviation {d['max_error']:.3g} {lu} at {d['at_deg']:.4f} deg; "
                     f"Y' {d['max_velocity_error']:.3g} {lu}/deg at {d['velocity_at_deg']:.4f} deg{acc}")
    lines += [f"  note: {n}" for n in s["notes"]]
    return "\n".join(lines)

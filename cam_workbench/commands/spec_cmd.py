"""``cam-workbench spec``: the spec reference (from the declarations) or the default spec."""
from __future__ import annotations

import argparse

from cam_workbench.generators.spec.examples import EXAMPLES, example_spec
from cam_workbench.generators.spec import default_spec, to_toml
from cam_workbench.generators.spec.reference import render

from . import add_command


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "spec",
                    description="Print every spec field with its unit, default and rule "
                                "(the same text as docs/spec.md), or the built-in default spec as TOML.")
    p.add_argument("--default", action="store_true", help="print the built-in default spec as TOML")
    p.add_argument("--example", metavar="NAME",
                   help=f"print a built-in example spec as TOML: one of {', '.join(EXAMPLES)} (docs/spec.md "
                        "describes each)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    if args.example:
        print(to_toml(example_spec(args.example)), end="")
    else:
        print(to_toml(default_spec()) if args.default else render(), end="")
    return 0

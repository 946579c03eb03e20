"""``cam-workbench spec``: the spec reference (from the declarations) or the default spec."""
from __future__ import annotations

import argparse

from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.generators.spec import default_spec, to_toml
from cam_workbench.generators.spec.reference import render


def run(args: argparse.Namespace) -> int:
    if args.example:
        print(to_toml(example_spec(args.example)), end="")
    else:
        print(to_toml(default_spec()) if args.default else render(), end="")
    return 0

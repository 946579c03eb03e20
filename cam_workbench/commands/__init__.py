"""CLI commands: each module has ``register(subparsers)`` that adds its parser and sets
``run``.  A new command is a module here and an entry in :data:`COMMANDS`."""
from . import (batch_cmd, build, check, dxf_cmd, dynamics_cmd, ecam_cmd, freecad_cmd, gcode, optimise_cmd,
               report_cmd, spec_cmd, sweep_cmd)

COMMANDS = [build, check, gcode, dxf_cmd, report_cmd, dynamics_cmd, ecam_cmd, optimise_cmd, batch_cmd, sweep_cmd,
            spec_cmd, freecad_cmd]

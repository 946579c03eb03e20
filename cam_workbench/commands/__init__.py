"""CLI commands: each module has ``register(subparsers)`` that adds its parser and sets
``run``.  A new command is a module here and an entry in :data:`COMMANDS`."""
from . import build, gcode, spec_cmd

COMMANDS = [build, spec_cmd, gcode]

"""The command line, imported once, run as a fresh process per command: a server that forks
a child for each request and there runs ``python -m cam_workbench.cli ARGS`` (``runpy``, as
``-m`` does) — in its own folder, with its own stdout and stderr files, and the exit status
Python's ``-m`` gives.  Each child starts from the state right after the import, so no command
sees another's; what is saved is the ~0.8 s each of the recording's 126 commands (14 an
example) would spend importing numpy, scipy and the project (observe.py; ``CAM_GOLDEN_FORK=0``
runs plain ``subprocess`` commands instead, which record the same bytes).

Protocol: one JSON object a line on stdin, ``{"args": [...], "cwd": ..., "stdout": FILE,
"stderr": FILE}``; one line back on stdout, ``{"exit": STATUS}``.  Ends at the end of stdin.
"""
from __future__ import annotations

import json
import os
import signal
import sys
from typing import Any

from .names import WHERE, where
from .observe import SAFETY_S


def _exit_status(code: Any) -> int:
    """The status ``sys.exit(code)`` ends a Python process with (a message: printed, 1)."""
    if code is None:
        return 0
    if isinstance(code, int):
        return code & 0xFF
    print(code, file=sys.stderr)
    return 1


def _child(request: dict[str, Any]) -> None:
    """Run one command in this (forked) process and end it with the command's status."""
    import atexit
    import runpy
    import traceback

    status = 1
    try:
        signal.alarm(int(SAFETY_S))          # a hung command ends (SIGALRM) instead of the recording
        os.chdir(request["cwd"])
        for fd, name in ((1, "stdout"), (2, "stderr")):
            target = os.open(request[name], os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
            os.dup2(target, fd)
            os.close(target)
        devnull = os.open(os.devnull, os.O_RDONLY)
        os.dup2(devnull, 0)
        try:
            sys.argv = ["-m", *request["args"]]        # runpy puts the module's file in argv[0]
            runpy.run_module(WHERE["cli"], run_name="__main__", alter_sys=True)
            status = 0
        except SystemExit as exc:
            status = _exit_status(exc.code)
        except BaseException:  # noqa: BLE001 - as Python reports an uncaught exception
            traceback.print_exc()
            status = 1
        atexit._run_exitfuncs()
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
    finally:
        os._exit(status)


def main() -> int:
    import importlib

    cli = importlib.import_module(WHERE["cli"])
    cli.build_parser()
    for load in where("commands").values():  # every command's module, as each run imports its own
        load()
    # as before ``python -m``: the package and what the command line imports are loaded, the
    # command line itself is not (runpy runs it as __main__)
    del sys.modules[WHERE["cli"]]
    package, _, module = WHERE["cli"].rpartition(".")
    if package and hasattr(sys.modules[package], module):
        delattr(sys.modules[package], module)
    for line in sys.stdin:
        request = json.loads(line)
        sys.stdout.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:
            _child(request)
        _, wait_status = os.waitpid(pid, 0)
        sys.stdout.write(json.dumps({"exit": os.waitstatus_to_exitcode(wait_status)}) + "\n")
        sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())

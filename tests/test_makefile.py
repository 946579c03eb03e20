"""The Makefile's install (``make demo``, ``make test``): it says what it does, one line per
step, and shows pip's own progress when make runs on a terminal, while a log (CI) gets pip
quiet.  Read from GNU make's own dry run (``make -n``) of a venv that does not exist yet; the
whole ``make demo`` from a fresh clone runs in tests/test_readme.py."""
from __future__ import annotations

import os
import pty
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from .conftest import ROOT, SAFETY_S

pytestmark = pytest.mark.skipif(shutil.which("make") is None, reason="GNU make is not installed")


def dry_run(venv: Path, *, terminal: bool, extra: tuple[str, ...] = ()) -> list[str]:
    """The commands ``make demo`` would run for a new ``venv``; make's stderr a terminal or not."""
    env = {k: v for k, v in os.environ.items() if k not in ("PIP_QUIET", "MAKEFLAGS")}
    if not terminal:
        res = subprocess.run(["make", "-n", "demo", f"VENV={venv}", *extra], cwd=ROOT, env=env,
                             capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=SAFETY_S)
    else:
        master, slave = pty.openpty()
        try:
            res = subprocess.run(["make", "-n", "demo", f"VENV={venv}", *extra], cwd=ROOT, env=env,
                                 stdout=subprocess.PIPE, stderr=slave, text=True, stdin=subprocess.DEVNULL,
                                 timeout=SAFETY_S)
        finally:
            os.close(slave)
            os.close(master)
    assert res.returncode == 0, res.stderr
    return res.stdout.splitlines()


def test_every_install_step_is_announced(tmp_path):
    lines = dry_run(tmp_path / "venv", terminal=False)
    said = [i for i, line in enumerate(lines) if line.startswith('echo "== ')]
    assert [re.match(r'echo "== (\d)/4', lines[i]).group(1) for i in said] == ["1", "2", "3", "4"], lines
    # each announcement comes just before its command: the venv, pip, the project, the OCP check
    commands = [lines[i + 1] for i in said]
    assert commands[0].endswith(f"-m venv {tmp_path / 'venv'}")
    assert "pip install" in commands[1] and "--upgrade pip" in commands[1]
    assert "pip install" in commands[2] and "-e '.[" in commands[2]
    assert "kernel.ocp import main" in commands[3]
    assert "a few minutes the first time" in lines[said[2]]


def test_pip_shows_its_progress_on_a_terminal_and_is_quiet_in_a_log(tmp_path):
    logged = [line for line in dry_run(tmp_path / "venv", terminal=False) if "pip install" in line]
    shown = [line for line in dry_run(tmp_path / "venv", terminal=True) if "pip install" in line]
    assert len(logged) == len(shown) == 2
    assert all("--quiet" in line for line in logged), logged
    assert not any("--quiet" in line for line in shown), shown
    # and either way on request
    forced = [line for line in dry_run(tmp_path / "venv", terminal=False, extra=("PIP_QUIET=",))
              if "pip install" in line]
    assert not any("--quiet" in line for line in forced), forced

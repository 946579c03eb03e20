"""The README's examples run as written (the Python block and the CLI lines)."""
import os
import re
import subprocess
import sys

import pytest

from .conftest import ROOT, requires_ocp

README = (ROOT / "README.md").read_text(encoding="utf-8")


@requires_ocp
def test_readme_cadquery_example_runs(tmp_path):
    block = re.search(r"## From a CadQuery script\s+```python\n(.*?)```", README, re.S).group(1)
    assert len(block.strip().splitlines()) <= 12
    spec = re.search(r"A minimal spec:\s+```toml\n(.*?)```", README, re.S).group(1)
    (tmp_path / "cam.toml").write_text(spec)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    res = subprocess.run([sys.executable, "-c", block], cwd=tmp_path, capture_output=True, text=True, env=env)
    assert res.returncode == 0, res.stderr
    assert "max_deg" in res.stdout
    assert (tmp_path / "cam_keyed.step").stat().st_size > 10_000


def test_readme_gives_the_two_commands():
    assert "make demo" in README and "make test" in README

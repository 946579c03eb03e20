"""Clean virtual environments with this checkout's wheel installed the ways users install it
(issue 12; docs/install.md).  Used by tests/test_install_envs.py, and by the tests that need
build123d or OCP 8, which the dev venv does not have (its CAD stack is CadQuery's).

Each scenario is a fresh ``python -m venv`` in which pip installs, from PyPI (through the pip
cache ``$PIP_CACHE_DIR``, which the Makefile sets to ``.cache/pip``, so re-runs download nothing):
first what the user already had (``pip install build123d`` …), then this project's wheel (or
sdist) with an extra.  Nothing is mocked and nothing is skipped: without the network the install
fails, and so does the test, with pip's own message.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: the pip cache shared by every environment (Makefile: $(CACHE)/pip)
PIP_CACHE = Path(os.environ.get("PIP_CACHE_DIR") or ROOT / ".cache" / "pip")
#: PyPI distributions that install the ``OCP`` package
OCP_DISTS = ("cadquery-ocp", "cadquery-ocp-novtk")
#: what a user had and must keep: never downgraded, never doubled
WATCHED = ("build123d", "cadquery", *OCP_DISTS)
#: left out of the copy of the checkout that the wheel and the sdist are built from
IGNORE = shutil.ignore_patterns(".git", ".venv", ".cache", "out", "test-artifacts", "__pycache__",
                                ".pytest_cache", "*.egg-info", "build", "dist")
PIP_TIMEOUT_S = 1800
#: unrelated PyPI projects whose import names were once ours (issue 21): installed beside the wheel
FOREIGN = ("generators==2020.4.27", "exporters==0.7.0")


@dataclass(frozen=True)
class Scenario:
    """One way a user installs the project."""

    name: str
    first: tuple[str, ...]        # what the user installed before (pip arguments), or ()
    extra: str | None             # the project's extra, or None for the core alone
    library: str | None           # "cadquery", "build123d" or None: the CAD library the user scripts in
    ocp: bool                     # an OCP is expected in the end
    source: str = "wheel"         # "wheel" or "sdist"
    title: str = ""


SCENARIOS: dict[str, Scenario] = {s.name: s for s in (
    Scenario("build123d-first", ("build123d",), "build123d", "build123d", True,
             title="(a) pip install build123d, then cam-workbench[build123d]"),
    Scenario("cadquery-first", ("cadquery",), "cadquery", "cadquery", True,
             title="(b) pip install cadquery, then cam-workbench[cadquery]"),
    Scenario("cadquery-extra", (), "cadquery", "cadquery", True,
             title="(c) cam-workbench[cadquery] alone"),
    Scenario("build123d-extra", (), "build123d", "build123d", True,
             title="(d) cam-workbench[build123d] alone"),
    Scenario("ocp-extra", (), "ocp", None, True,
             title="(e) cam-workbench[ocp]: the command line"),
    Scenario("core-only", (), None, None, False, source="sdist",
             title="(f) cam-workbench alone, from the sdist: no OCP"),
    Scenario("build123d-0.12-first", ("build123d==0.12.0",), "build123d", "build123d", True,
             title="(g) pip install build123d==0.12.0 (OCP 7.9 without VTK), then cam-workbench[build123d]"),
    Scenario("foreign-names", FOREIGN, "ocp", None, True,
             title="(h) PyPI's generators and exporters first, then cam-workbench[ocp]: one import name each"),
)}


def pip_env() -> dict[str, str]:
    """The environment pip and the venv's programs run with: this process's, without its venv,
    with the shared pip cache."""
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("PYTHON", "VIRTUAL_ENV", "CAM_WORKBENCH", "PYTEST"))}
    env.update(PIP_CACHE_DIR=str(PIP_CACHE), PIP_DISABLE_PIP_VERSION_CHECK="1", PYTHONNOUSERSITE="1")
    return env


def run(argv: list[str], *, cwd: Path | None = None, env: dict[str, str] | None = None,
        timeout: float = PIP_TIMEOUT_S) -> subprocess.CompletedProcess:
    return subprocess.run([str(a) for a in argv], capture_output=True, text=True, stdin=subprocess.DEVNULL,
                          cwd=cwd, env=env if env is not None else pip_env(), timeout=timeout)


def _ok(res: subprocess.CompletedProcess, what: str) -> subprocess.CompletedProcess:
    if res.returncode != 0:
        raise AssertionError(f"{what}: exit {res.returncode}\n{res.stdout[-4000:]}\n{res.stderr[-4000:]}")
    return res


@dataclass(frozen=True)
class Dist:
    wheel: Path
    sdist: Path
    seconds: float


def build_dist(out: Path) -> Dist:
    """``python -m build`` (sdist, then the wheel from it) of a clean copy of the checkout."""
    src = out / "src"
    shutil.copytree(ROOT, src, ignore=IGNORE, symlinks=True)
    t0 = time.perf_counter()
    _ok(run([sys.executable, "-m", "build", "--outdir", out / "dist", src]), "python -m build")
    wheels = sorted((out / "dist").glob("cam_workbench-*.whl"))
    sdists = sorted((out / "dist").glob("cam_workbench-*.tar.gz"))
    assert len(wheels) == 1 and len(sdists) == 1, sorted(p.name for p in (out / "dist").iterdir())
    return Dist(wheels[0], sdists[0], time.perf_counter() - t0)


@dataclass
class Env:
    """A clean venv after one scenario's installs."""

    scenario: Scenario
    path: Path
    before: dict[str, str] = field(default_factory=dict)   # pip list after the user's own install
    after: dict[str, str] = field(default_factory=dict)    # pip list after installing the project
    seconds: dict[str, float] = field(default_factory=dict)
    pip_output: str = ""

    @property
    def bin(self) -> Path:
        return self.path / "bin"

    @property
    def python(self) -> Path:
        return self.bin / "python"

    def pip(self, *args: str, what: str = "pip") -> subprocess.CompletedProcess:
        return _ok(run([self.python, "-m", "pip", *args]), f"{self.scenario.name}: {what}")

    def pip_list(self) -> dict[str, str]:
        res = self.pip("list", "--format=json", what="pip list")
        return {_canon(d["name"]): d["version"] for d in json.loads(res.stdout)}

    def ocp_dists(self) -> list[str]:
        return [n for n in OCP_DISTS if n in self.after]

    def run_python(self, code: str, cwd: Path, timeout: float = 900) -> subprocess.CompletedProcess:
        """``code`` in the venv's Python, in ``cwd`` (not the checkout: the installed wheel runs)."""
        return run([self.python, "-c", code], cwd=cwd, timeout=timeout)

    def record(self) -> dict:
        return {"scenario": self.scenario.title, "before": self.before, "after": self.after,
                "seconds": {k: round(v, 1) for k, v in self.seconds.items()},
                "pip_cache": str(PIP_CACHE)}


def _canon(name: str) -> str:
    return name.lower().replace("_", "-").replace(".", "-")


def make_env(scenario: Scenario, where: Path, dist: Dist) -> Env:
    """A fresh venv at ``where`` with the scenario's installs done and recorded."""
    env = Env(scenario, where)
    t0 = time.perf_counter()
    _ok(run([sys.executable, "-m", "venv", where]), "python -m venv")
    env.seconds["venv"] = time.perf_counter() - t0
    if scenario.first:
        t0 = time.perf_counter()
        env.pip_output += env.pip("install", *scenario.first, what=f"pip install {' '.join(scenario.first)}").stdout
        env.seconds["first"] = time.perf_counter() - t0
    env.before = env.pip_list()
    target = str(dist.wheel if scenario.source == "wheel" else dist.sdist)
    if scenario.extra:
        target += f"[{scenario.extra}]"
    t0 = time.perf_counter()
    env.pip_output += env.pip("install", target, what=f"pip install {target}").stdout
    env.seconds["project"] = time.perf_counter() - t0
    env.after = env.pip_list()
    return env


class EnvFactory:
    """Builds the dist once and each scenario's venv once per test session (tests share them)."""

    def __init__(self, root: Path):
        self.root = root
        self._dist: Dist | None = None
        self._envs: dict[str, Env] = {}

    @property
    def dist(self) -> Dist:
        if self._dist is None:
            self._dist = build_dist(self.root / "build")
        return self._dist

    def get(self, name: str) -> Env:
        if name not in self._envs:
            self._envs[name] = make_env(SCENARIOS[name], self.root / name, self.dist)
        return self._envs[name]

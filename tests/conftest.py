"""Shared fixtures: specs of the paper's cases and a few built designs (built once)."""
from __future__ import annotations

import copy
import math
import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from cam_workbench.generators.spec.examples import PAPER_SPEC_DICT  # noqa: E402
from cam_workbench.generators.spec import CamSpec  # noqa: E402

ARTIFACTS = ROOT / "test-artifacts"
#: The longest any test waits for a process to end or a condition to come true [s]: a safety net
#: that turns a hang into a failure, never a window the product must beat.  Tests wait on events
#: (a process ending, a progress signal, a widget or a file appearing); a busy machine makes them
#: slower, not wrong (half an hour: the slowest GUI session takes minutes on a loaded machine).
SAFETY_S = 1800.0


def paper_case_dict(case: int, knife: bool = True) -> dict:
    """The paper's Table 1 cam: case 1 (e = 0, M = 60), 2 (e = 10, M = 60), 3 (e = 10, M = 64)."""
    d = copy.deepcopy(PAPER_SPEC_DICT)
    e = 0.0 if case == 1 else 10.0
    d["cam"]["base_radius"] = math.hypot(20.0, e)  # h' = 20 mm (paper Eq. 7)
    d["cam"]["bore_diameter"] = 0.0
    d["follower"] = {"kind": "knife", "offset": e} if knife else {"kind": "roller", "offset": e, "roller_radius": 5.0}
    if case == 3:
        d["pitch"] = {"representation": "ph"}
        for seg, j in zip(d["motion"], [6, 20, 12, 20, 6]):  # 5° in dwells, 6° in rise/return
            seg["junctions"] = j
    return d


def paper_inch_dict(machining: dict) -> dict:
    """The paper's Table 1 case-2 roller cam in inches (base radius, offset and lifts ÷ 25.4, a 0.4 in
    thick cam, a 0.2 in roller) with the ``[machining]`` table ``machining``."""
    d = paper_case_dict(2, knife=False)
    scale = 1 / 25.4
    d["units"] = "in"
    d["cam"]["base_radius"] *= scale
    d["cam"]["thickness"] = 0.4
    d["follower"]["offset"] *= scale
    d["follower"]["roller_radius"] = 0.2
    for m in d["motion"]:
        if "lift" in m:
            m["lift"] *= scale
    d["machining"] = dict(machining)
    return d


def paper_case(case: int, knife: bool = True) -> CamSpec:
    return CamSpec.from_dict(paper_case_dict(case, knife))


@pytest.fixture(scope="session")
def artifacts() -> Path:
    """Where tests leave files for a person to look at; a run with another FreeCAD
    (``$CAM_FREECAD_ROOT``, e.g. ``.cache/freecad-roots/unstable``) gets a subfolder of its own
    (``test-artifacts/unstable``), so its screenshots do not overwrite the host FreeCAD's."""
    root = os.environ.get("CAM_FREECAD_ROOT")
    folder = ARTIFACTS / Path(root).name if root else ARTIFACTS
    folder.mkdir(parents=True, exist_ok=True)
    return folder


@pytest.fixture(scope="session")
def default_design():
    from cam_workbench.generators import default_spec, design_cam

    return design_cam(default_spec())


SPEC_COMMANDS = {"build", "report", "check", "gcode", "dxf", "optimise", "optimize"}


def paper_args(args: tuple[str, ...]) -> list[str]:
    """CLI arguments with ``--example paper`` added when they name no spec: the tests that use
    this were written on (and check numbers of) the paper's Table 1 case-2 cam, the built-in
    default before the default became a cam that passes its checks."""
    args = list(args)
    if (args and args[0] in SPEC_COMMANDS and "--example" not in args
            and not any(str(a).endswith(".toml") for a in args[1:])):
        args[1:1] = ["--example", "paper"]
    return args


def snapshot(root: Path) -> dict[str, tuple[bytes, int] | None]:
    """Every file under ``root`` (its bytes and mtime in ns) and every folder (None), by relative path."""
    out: dict[str, tuple[bytes, int] | None] = {}
    for p in sorted(root.rglob("*")):
        out[p.relative_to(root).as_posix()] = None if p.is_dir() else (p.read_bytes(), p.stat().st_mtime_ns)
    return out


def assert_unchanged(root: Path, before: dict[str, tuple[bytes, int] | None]) -> None:
    """Nothing under ``root`` created, removed or changed (bytes and mtime) since ``before``."""
    after = snapshot(root)
    assert sorted(after) == sorted(before), sorted(set(after) ^ set(before))
    for name, was in before.items():
        assert after[name] == was, f"{name} changed"


def has_module(name: str) -> bool:
    import importlib.util

    return importlib.util.find_spec(name) is not None


requires_ocp = pytest.mark.skipif(not has_module("OCP"), reason="OCP (cadquery-ocp) is not installed")


@pytest.fixture(scope="session")
def install_envs(tmp_path_factory):
    """Clean venvs with this checkout's wheel installed as users do (tests/install_envs.py),
    each built once per session on first use."""
    from .install_envs import EnvFactory

    return EnvFactory(tmp_path_factory.mktemp("install-envs"))

"""Installing the project into the CAD ecosystem as it is on PyPI today (issue 12, docs/install.md).

This checkout's wheel and sdist (``python -m build``) go into clean venvs the ways users install
them (:data:`tests.install_envs.SCENARIOS`): (a) ``pip install build123d`` first, then
``cam-workbench[build123d]``; (b) ``pip install cadquery`` first, then ``cam-workbench[cadquery]``;
(c) ``[cadquery]`` alone; (d) ``[build123d]`` alone; (e) ``[ocp]`` alone, for the command line;
(f) the sdist with no extra (no OCP); (g) build123d 0.12 (OCP 7.9 without VTK) first, then
``cam-workbench[build123d]``; (h) PyPI's unrelated ``generators`` and ``exporters`` first, then
``cam-workbench[ocp]`` (issue 21: the wheel owns one import name, ``cam_workbench``).  In each:

* ``pip check`` passes, and ``pip list`` shows at most one OCP distribution (exactly one where an
  OCP is expected) and every package the user had before, at the version they had;
* the CAD library imports (``import cadquery`` is what two OCP builds break), the README's example
  for that library runs as written with the README test's checks, and the solid is valid
  (``BRepCheck_Analyzer``, through the adaptor);
* ``cam-workbench build -o out`` writes the full set, and cam.step reads back valid; without OCP it
  exits 2 with one line naming the extras and writes nothing, while ``generators`` and the commands
  that need no solid (check, gcode, dxf) work;
* the API of a library that is not installed raises MissingDependency naming its extra.

Finally the tests of the solids, STEP and the adaptor run under OCP 8 with build123d in the env
of (a) (the dev venv has CadQuery's OCP 7.9; the build123d tests skip there).

Versions and timings of every environment: ``test-artifacts/install_envs.json``.  Slow (a few
minutes; the pip cache under ``.cache/pip`` saves the downloads where the index allows caching);
needs PyPI, and fails — never skips — without it.
"""
from __future__ import annotations

import json
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from .conftest import ARTIFACTS, ROOT
from .install_envs import OCP_DISTS, SCENARIOS, WATCHED, Env, run
from .test_readme import BLOCKS, BUILD_FILES, EPILOGUES

pytestmark = pytest.mark.install_envs

NAMES = list(SCENARIOS)
README_SECTION = {"cadquery": "From a CadQuery script", "build123d": "From a build123d script"}
#: the README example's solid, for the independent validity check
README_SOLID = {"cadquery": "body.val().wrapped", "build123d": "part.wrapped"}
_RECORDS: dict[str, dict] = {}


@pytest.fixture(scope="module", autouse=True)
def _write_records(install_envs):
    """The versions pip resolved and the timings, into test-artifacts/install_envs.json."""
    yield
    if _RECORDS:
        ARTIFACTS.mkdir(exist_ok=True)
        dist = install_envs._dist
        (ARTIFACTS / "install_envs.json").write_text(json.dumps(
            {"dist_seconds": round(dist.seconds, 1) if dist else None, "envs": _RECORDS}, indent=2) + "\n")


@pytest.fixture(scope="module", params=NAMES)
def env(request, install_envs) -> Env:
    e = install_envs.get(request.param)
    _RECORDS.setdefault(request.param, {}).update(e.record())
    return e


def test_dist_has_the_package_data(install_envs):
    """The wheel holds one package, ``cam_workbench`` (its subpackages ``generators`` and
    ``exporters`` inside), and the FreeCAD icons; its metadata names the extras and no OCP,
    CadQuery or build123d among the requirements; the sdist holds the sources."""
    import tarfile
    import zipfile

    dist = install_envs.dist
    names = zipfile.ZipFile(dist.wheel).namelist()
    for pkg in ("cam_workbench/__init__.py", "cam_workbench/kernel/ocp.py", "cam_workbench/kernel/step.py",
                "cam_workbench/generators/__init__.py", "cam_workbench/generators/spec/model.py",
                "cam_workbench/exporters/step.py"):
        assert pkg in names, pkg
    assert {n.split("/")[0] for n in names if not n.split("/")[0].endswith(".dist-info")} == {"cam_workbench"}
    assert any(n.startswith("cam_workbench/freecad/icons/") and n.endswith(".svg") for n in names)
    meta = next(n for n in names if n.endswith(".dist-info/METADATA"))
    text = zipfile.ZipFile(dist.wheel).read(meta).decode()
    requires = re.findall(r"^Requires-Dist: (.*)$", text, re.M)
    core = [r for r in requires if "extra ==" not in r]
    assert not [r for r in core if re.match(r"(cadquery|build123d|OCP)", r, re.I)], core
    assert {"cadquery", "build123d", "ocp"} <= set(re.findall(r"^Provides-Extra: (.*)$", text, re.M))
    extras = {m.group(2): m.group(1) for m in re.finditer(r"^Requires-Dist: (\S+).*extra == \"(\w+)\"", text, re.M)}
    assert extras["cadquery"].startswith("cadquery>=") and extras["build123d"].startswith("build123d>=")
    assert extras["ocp"].startswith("cadquery-ocp-novtk>=")
    assert not [r for r in requires if "<" in r and re.match(r"(cadquery|build123d)", r)], "upper bound"
    members = tarfile.open(dist.sdist).getnames()
    assert any(m.endswith("cam_workbench/kernel/ocp.py") for m in members)
    assert any(m.endswith("/pyproject.toml") for m in members)


def test_pip_check_and_one_ocp(env: Env):
    """Consistent requirements; exactly one OCP distribution (none for the core alone)."""
    res = run([env.python, "-m", "pip", "check"])
    assert res.returncode == 0, res.stdout + res.stderr
    ocps = env.ocp_dists()
    assert len(ocps) == (1 if env.scenario.ocp else 0), {n: env.after[n] for n in ocps}
    if env.scenario.library == "cadquery":
        assert ocps == ["cadquery-ocp"]                 # CadQuery's own build, with VTK
    elif env.scenario.library == "build123d" or env.scenario.extra == "ocp":
        assert ocps == ["cadquery-ocp-novtk"]
    assert env.after.get("cam-workbench") == "0.1.0"


def test_nothing_the_user_had_changed(env: Env):
    """Every package of the user's environment before cam-workbench is still there at its
    version: no downgrade of build123d, CadQuery or OCP (nor of anything else)."""
    changed = {n: (v, env.after.get(n)) for n, v in env.before.items() if env.after.get(n) != v}
    assert not changed, changed
    if env.scenario.first and env.scenario.library:
        assert env.scenario.library in env.before             # the user's library was there


def test_library_imports_and_readme_example_runs(env: Env, tmp_path):
    """``import cadquery`` / ``import build123d`` works; the README's example for the library
    runs as written, its checks pass and its solid passes BRepCheck."""
    lib = env.scenario.library
    if lib is None:
        res = env.run_python("import cadquery", tmp_path)
        assert res.returncode != 0 and "No module named 'cadquery'" in res.stderr
        return
    section = README_SECTION[lib]
    code = "\n".join(b.text for b in BLOCKS if b.section == section and b.lang == "python" and not b.freecad)
    assert code.strip(), f"README has no python block under {section!r}"
    check = (f"\nfrom cam_workbench.kernel import ocp as occ\n"
             f"assert occ.is_valid({README_SOLID[lib]}) and occ.is_valid(cam.shape)\n"
             f"import {lib}\nprint('VERSIONS', {lib}.__version__, occ.describe())\n")
    script = tmp_path / "readme_example.py"
    script.write_text(code + EPILOGUES[section] + check, encoding="utf-8")
    res = run([env.python, script], cwd=tmp_path, timeout=900)
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    line = next(x for x in res.stdout.splitlines() if x.startswith("VERSIONS"))
    assert env.after[lib] in line                          # the library pip list names ran it
    _RECORDS.setdefault(env.scenario.name, {})["readme_example"] = line


_MISSING = """
import json
from cam_workbench import PlateCam
from cam_workbench.generators.errors import MissingDependency
cam = PlateCam()
out = {}
for name in ("workplane", "solid", "part", "shape"):
    try:
        attr = getattr(cam, name)
        attr() if callable(attr) else attr
        out[name] = None
    except MissingDependency as exc:
        out[name] = str(exc)
print(json.dumps(out))
"""


def test_missing_extras_are_named(env: Env, tmp_path):
    """The API of a library that is not installed raises MissingDependency (an ImportError)
    naming the extra that brings it; the solid itself needs only OCP."""
    res = env.run_python(_MISSING, tmp_path)
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout.strip().splitlines()[-1])
    lib = env.scenario.library
    for name, extra in (("workplane", "cadquery"), ("solid", "cadquery"), ("part", "build123d")):
        if lib == extra:
            assert out[name] is None, out[name]
        else:
            assert f'pip install "cam-workbench[{extra}]"' in out[name], out[name]
            assert out[name].startswith(f"PlateCam.{name}() needs "), out[name]
    if env.scenario.ocp:
        assert out["shape"] is None, out["shape"]
    else:
        for extra in ("cadquery", "build123d", "ocp"):
            assert f'"cam-workbench[{extra}]"' in out["shape"], out["shape"]


def test_cli_build(env: Env, tmp_path):
    """``cam-workbench build -o out``: the full set, cam.step valid on re-reading; without OCP:
    exit 2, one line naming the extras, nothing written — and the rest of the CLI works."""
    cli = env.bin / "cam-workbench"
    res = run([cli, "build", "-o", "out"], cwd=tmp_path, timeout=900)
    if env.scenario.ocp:
        assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
        names = {p.name for p in (tmp_path / "out").iterdir()}
        assert set(BUILD_FILES) <= names, sorted(set(BUILD_FILES) - names)
        back = env.run_python("from cam_workbench.kernel.step import read_step\nfrom cam_workbench.kernel import ocp as occ\n"
                              "s = read_step('out/cam.step')\nprint(occ.is_valid(s), occ.describe())", tmp_path)
        assert back.returncode == 0 and back.stdout.startswith("True"), back.stdout + back.stderr
        return
    assert res.returncode == 2, res.stdout + res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: cam-workbench build "), res.stderr
    for extra in ("cadquery", "build123d", "ocp"):
        assert f'"cam-workbench[{extra}]"' in lines[0], lines[0]
    assert not (tmp_path / "out").exists()
    # what needs no solid works without OCP
    for args in (["check", "-o", "chk"], ["gcode", "-o", "cam.nc"], ["dxf", "-o", "cam.dxf"],
                 ["spec", "--example", "paper"]):
        res = run([cli, *args], cwd=tmp_path, timeout=900)
        assert res.returncode == 0, (args, res.stderr)
    assert (tmp_path / "cam.nc").stat().st_size > 1000 and (tmp_path / "cam.dxf").stat().st_size > 1000
    res = env.run_python("import sys\nfrom cam_workbench.generators import default_spec, design_cam\n"
                         "d = design_cam(default_spec())\nprint(d.area, 'OCP' in sys.modules)", tmp_path)
    assert res.returncode == 0 and res.stdout.split()[1] == "False", res.stdout + res.stderr


_FOREIGN = """
import base64, csv, hashlib, importlib.metadata as md, json, sys
from pathlib import Path
out = {"changed": [], "ours": {}}
for dist in ("generators", "exporters"):
    d = md.distribution(dist)
    for f in d.files:
        if f.hash and f.hash.mode == "sha256":
            digest = base64.urlsafe_b64encode(hashlib.sha256(Path(f.locate()).read_bytes()).digest()).rstrip(b"=").decode()
            if digest != f.hash.value:
                out["changed"].append(str(f))
    out[dist + "_files"] = len(d.files)
from importlib import import_module   # the foreign packages, by their import names
out["generators"] = import_module("generators").__file__
try:
    out["exporters"] = import_module("exporters").__file__
except Exception as exc:  # its own code: Python 2 syntax
    out["exporters"] = f"{type(exc).__name__}: {getattr(exc, 'filename', '')}"
import cam_workbench.generators as g, cam_workbench.exporters as e
from cam_workbench import PlateCam
cam = PlateCam()
out["ours"] = {"generators": g.__file__, "exporters": e.__file__, "volume": cam.volume}
print(json.dumps(out))
"""


def test_foreign_generators_and_exporters_are_left_whole(install_envs, tmp_path):
    """(h): after ``pip install cam-workbench[ocp]`` beside PyPI's ``generators`` 2020.4.27 and
    ``exporters`` 0.7.0, every file of theirs has the hash their RECORD gives (none overwritten);
    ``import generators`` is theirs, ``import exporters`` fails with a SyntaxError in their own
    file (their package is Python 2 code, on any Python 3), and ``cam_workbench.generators`` and
    ``cam_workbench.exporters`` are ours and build the default cam."""
    env = install_envs.get("foreign-names")
    res = env.run_python(_FOREIGN, tmp_path)
    assert res.returncode == 0, res.stderr[-3000:]
    out = json.loads(res.stdout.strip().splitlines()[-1])
    site = str(env.path)
    assert out["changed"] == [] and out["generators_files"] > 0 and out["exporters_files"] > 0, out
    assert out["generators"].startswith(site) and "/site-packages/generators/" in out["generators"]
    assert out["exporters"].startswith("SyntaxError: ")
    assert "/site-packages/exporters/" in out["exporters"]
    assert out["ours"]["generators"].endswith("/site-packages/cam_workbench/generators/__init__.py")
    assert out["ours"]["exporters"].endswith("/site-packages/cam_workbench/exporters/__init__.py")
    assert out["ours"]["volume"] > 0
    _RECORDS.setdefault("foreign-names", {})["foreign"] = out


def test_suite_under_ocp8_with_build123d(install_envs, tmp_path):
    """The tests of the adaptor, the solids (with build123d's objects) and STEP, run by pytest
    inside the env of (a) — build123d 0.13 on OCP 8 — on this checkout's code."""
    env = install_envs.get("build123d-first")
    assert env.ocp_dists() == ["cadquery-ocp-novtk"]
    assert env.after["cadquery-ocp-novtk"].startswith("8."), env.after["cadquery-ocp-novtk"]
    if not (env.path / ".test-tools").exists():          # after the scenario's own record
        env.pip("install", "pytest>=7", "hypothesis>=6.80", what="pip install pytest hypothesis")
        (env.path / ".test-tools").touch()
    xml = tmp_path / "junit.xml"
    files = ["tests/test_ocp_compat.py", "tests/test_solids.py", "tests/test_step_units.py",
             "tests/test_pitch_bspline.py"]
    res = run([env.python, "-m", "pytest", "-q", "-p", "no:cacheprovider", f"--junitxml={xml}",
               "-m", "not install_envs", *files], cwd=ROOT, timeout=1800)
    assert res.returncode == 0, res.stdout[-5000:] + res.stderr[-2000:]
    cases = {f"{c.get('classname')}.{c.get('name')}": c for c in ET.parse(xml).getroot().iter("testcase")}
    skipped = {k for k, c in cases.items() if c.find("skipped") is not None}
    ran = set(cases) - skipped
    assert any(k.endswith("test_build123d_objects") for k in ran), sorted(skipped)
    assert any("test_ocp_compat" in k for k in ran)
    _RECORDS.setdefault("build123d-first", {})["suite_under_ocp8"] = (
        f"{len(ran)} passed, {len(skipped)} skipped: {', '.join(sorted(skipped))}")


def test_scenarios_cover_the_issue():
    """(a)–(e) of issue 12 and the core alone, each installing the extra of its library."""
    firsts = {s.first for s in SCENARIOS.values()}
    assert {("build123d",), ("cadquery",)} <= firsts
    assert {s.extra for s in SCENARIOS.values()} == {"cadquery", "build123d", "ocp", None}
    assert set(WATCHED) >= set(OCP_DISTS)
    assert Path(ROOT / "docs" / "install.md").is_file()

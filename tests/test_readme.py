"""Every code block of README.md runs as written, in the order a reader meets it.

The reader is simulated as closely as the test machine allows, and nothing of the project's own
environment is changed.  There are two readers, because CadQuery and build123d bring different
OCP builds that cannot share an environment (docs/install.md): a CadQuery reader, who runs every
block, and a build123d reader, who runs the ``pip install "cam-workbench[build123d]"`` line of the
install block (its lines are alternatives, one per library) and the "From a build123d script"
section (:data:`SECTION_READER`).  Each reader has

* a fresh virtual environment (``python -m venv``) whose ``site-packages`` sees the installed
  dependencies of an environment that has the reader's library (symlinked, without cam-workbench
  itself, pip or setuptools) — for CadQuery the project's dev venv, for build123d the clean venv
  where ``pip install build123d`` put today's build123d (tests/install_envs.py, scenario (a)) —
  and a wheel of this checkout as the only ``cam-workbench`` pip can find (``PIP_NO_INDEX``,
  ``PIP_FIND_LINKS``): the README's ``pip install`` lines install it, and must find the library
  and its one OCP already there;
* ``sh`` blocks run through ``bash -e -o pipefail`` (a failing line fails the block) with that
  environment's ``bin`` first on PATH, HOME a fresh folder, in the reader's work folder — or, for
  ``make`` lines, in a copy of the checkout whose ``.venv`` is that environment;
* ``python`` blocks of one README section run in one process of that environment's Python, in
  the work folder, followed by a short epilogue (:data:`EPILOGUES`) that checks their results —
  valid solids, the figures the comments quote;
* a ``python`` block preceded by ``<!-- freecad -->`` runs in ``freecadcmd`` for the HOME where
  the README's ``cam-workbench freecad install`` put the workbench;
* ``toml`` blocks are loaded by :func:`cam_workbench.generators.spec.load_spec`.

A block in any other language fails :func:`test_every_block_has_a_runner`, so nothing goes
untested.  ``make test`` cannot run inside the suite, so the README names it only in prose.
"""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import sysconfig
from dataclasses import dataclass
from pathlib import Path

import pytest

from cam_workbench.generators.spec import load_spec

from .conftest import ROOT, SAFETY_S
from .freecad_support import FREECADCMD, run_freecadcmd

README = ROOT / "README.md"
TEXT = README.read_text(encoding="utf-8")
RUNNERS = ("sh", "python", "toml")
FREECAD_MARK = "<!-- freecad -->"
#: left out of the copies of the checkout (the wheel's source and the `make demo` folder)
IGNORE = shutil.ignore_patterns(".git", ".venv", ".cache", "out", "test-artifacts", "__pycache__", ".pytest_cache",
                                "*.egg-info", "build", "dist")
#: what the reader's environment must not see from the project's own site-packages
NOT_SHARED = ("cam_workbench", "__editable__", "pip", "setuptools", "_distutils_hack", "pkg_resources")
#: the files `make demo` and `cam-workbench build` write (README "From a checkout")
BUILD_FILES = ("cam.step", "cam.dxf", "cam.nc", "commands.csv", "report.json", "report.html",
               ".cam-workbench.json")
#: the reader who runs a section's blocks (every other section: the CadQuery reader)
SECTION_READER = {"From a build123d script": "build123d"}
#: an install line for one library's reader: ``pip install "cam-workbench[build123d]"``
INSTALL_LINE = re.compile(r"^\s*pip\s+install\s+.*cam-workbench\[(\w+)\]", re.M)
READERS = ("cadquery", "build123d")


@dataclass(frozen=True)
class Block:
    line: int          # of the opening fence, 1-based
    section: str       # the ``##`` heading it is under
    lang: str
    text: str
    freecad: bool      # marked by <!-- freecad --> on the line before the fence (blank lines skipped)


def parse(text: str) -> list[Block]:
    """The fenced code blocks of ``text`` in order."""
    out: list[Block] = []
    lines = text.split("\n")
    section = ""
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("## "):
            section = line[3:].strip()
        m = re.match(r"^```(\S*)\s*$", line)
        if m:
            j = i + 1
            while j < len(lines) and not lines[j].startswith("```"):
                j += 1
            k = i - 1
            while k >= 0 and not lines[k].strip():
                k -= 1
            marked = k >= 0 and lines[k].strip() == FREECAD_MARK
            out.append(Block(i + 1, section, m.group(1), "\n".join(lines[i + 1:j]) + "\n", marked))
            i = j + 1
            continue
        i += 1
    return out


BLOCKS = parse(TEXT)


@dataclass(frozen=True)
class Unit:
    """What one test runs: one sh, toml or FreeCAD block, or every python block of a section."""

    kind: str          # "sh", "toml", "freecad", "python"
    section: str
    line: int
    text: str

    @property
    def id(self) -> str:
        slug = re.sub(r"[^a-z0-9]+", "-", self.section.lower()).strip("-")
        return f"L{self.line}-{self.kind}-{slug}"


def units(blocks: list[Block]) -> list[Unit]:
    out: list[Unit] = []
    for b in blocks:
        if b.lang == "python" and not b.freecad:
            prev = out[-1] if out else None
            if prev and prev.kind == "python" and prev.section == b.section:
                out[-1] = Unit("python", b.section, prev.line, prev.text + "\n" + b.text)
                continue
            out.append(Unit("python", b.section, b.line, b.text))
        elif b.lang == "python":
            out.append(Unit("freecad", b.section, b.line, b.text))
        elif b.lang in ("sh", "toml"):
            out.append(Unit(b.lang, b.section, b.line, b.text))
    return out


UNITS = units(BLOCKS)

#: Checks appended to a section's python blocks (same process): the results are valid solids and
#: the figures the README's comments quote are the code's.
EPILOGUES = {
    "From a CadQuery script": """
import os
assert body.val().isValid() and len(body.solids().vals()) == 1
assert 0 < body.val().Volume() < cam.volume                  # the keyway took material away
assert os.path.getsize("cam_keyed.step") > 10_000
assert round(cam.report()["pressure_angle"]["max_deg"], 1) == 21.2
assert paper.is_valid() and paper.report()["checks"]["failed"] == ["pressure_angle"]
assert round(paper.report()["pressure_angle"]["max_deg"], 1) == 46.2
""",
    "Followers: translating, oscillating, flat-faced": """
assert arm.is_valid() and face.is_valid()
rep = arm.report()
assert rep["follower"]["motion"] == "oscillating" and rep["motion"]["lift_unit"] == "deg"
assert f"{rep['pitch']['max_deviation']:.1e}" == "9.0e-05" and rep["checks"]["passed"]
fw = face.report()["checks"]["results"]["face_width"]
assert round(fw["value"], 1) == 38.2 and fw["status"] == "pass"
""",
    "From a build123d script": """
import math, os
assert part.is_valid and len(part.solids()) == 1
# the hub ring, r 6…14 mm, 8 mm high, on the cam (the 12 mm bore is the cam's own)
assert abs(part.volume - (cam.volume + math.pi * (14 ** 2 - 6 ** 2) * 8)) < 1e-6 * part.volume
assert os.path.getsize("cam_hub.step") > 10_000
""",
    "Cam bodies: plate, groove, conjugate": """
assert groove.is_valid() and pair.is_valid()
assert round(body["rim_wall"]["value"], 2) == 6.95 and body["groove_width"] == 16.1
assert [round(a) for a in body["drive"]["changes_at_deg"]] == [90, 150, 210, 270]
rde = pair.report()["body"]["roller_distance_error"]
assert f"{rde['max']:.1e}" == "9.9e-05" and rde["max"] <= rde["lift_bound"]
""",
    "Cylindrical (barrel) cams": """
import ezdxf
assert round(barrel.checks()["results"]["pressure_angle"]["value"], 1) == 25.5
assert [round(a) for a in d["contact"]["drive"]["rigid"]["changes_at_deg"]] == [90, 150, 210, 270]
assert d["contact"]["kept"] and "jump_speed" not in d
assert not ezdxf.readfile("barrel.dxf").audit().has_errors
""",
    "Motion design: polynomials, constant-velocity strokes, tables": """
assert round(rep["segments"][2]["velocity"], 1) == 10.5 and [j["order"] for j in rep["junctions"]] == [2] * 6
assert pack.report()["checks"]["passed"]
""",
    "Follower dynamics and electronic cams": """
assert round(d["jump_speed"]["rpm"], 1) == 487.5 and round(d["jump_speed"]["rigid_rpm"], 1) == 492.1
assert round(d["contact"]["min_force"], 2) == 19.99 and d["contact"]["kept"]
assert f"{table.deviation.max_error:.2e}" == "1.09e-03"
""",
    "Design studies: batches, sweeps, sizing charts": """
rb = [r["min_base_radius"] for r in table.rows]
assert len(rb) == 5 and all(b2 > b1 for b1, b2 in zip(rb, rb[1:]))   # more lift, a larger cam
""",
    "Optimise": """
rep = res.report()
assert res.feasible and smaller.is_valid()
assert (rep["status"], rep["message"]) == (res.status, res.message)
assert [v["name"] for v in rep["initial_violations"]] == ["pressure_angle"]
assert round(rep["initial_violations"][0]["value"], 1) == 46.2
assert smaller.report()["checks"]["failed"] == []
""",
}


# ---- the reader's machine ----------------------------------------------------------------------
@dataclass
class Reader:
    library: str        # "cadquery" or "build123d": what the reader scripts in
    root: Path
    venv: Path
    wheelhouse: Path
    work: Path          # where the reader types the commands
    home: Path
    repo: Path          # a copy of the checkout, for `make`

    @property
    def bin(self) -> Path:
        return self.venv / "bin"

    @property
    def python(self) -> Path:
        return self.bin / "python"

    def env(self) -> dict[str, str]:
        env = {k: v for k, v in os.environ.items()
               if not k.startswith(("PYTHON", "VIRTUAL_ENV", "PIP_", "XDG_", "CAM_WORKBENCH"))}
        env.update(PATH=f"{self.bin}{os.pathsep}{os.environ.get('PATH', '')}", HOME=str(self.home),
                   VIRTUAL_ENV=str(self.venv), PIP_NO_INDEX="1", PIP_FIND_LINKS=str(self.wheelhouse),
                   PIP_DISABLE_PIP_VERSION_CHECK="1")
        return env


def _run(argv, **kw) -> subprocess.CompletedProcess:
    return subprocess.run(argv, capture_output=True, text=True, stdin=subprocess.DEVNULL, **kw)


def _site_packages(python: Path | str) -> Path:
    res = _run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"], timeout=SAFETY_S)
    assert res.returncode == 0, res.stderr
    return Path(res.stdout.strip())


def make_reader(library: str, root: Path, wheelhouse: Path, deps: Path) -> Reader:
    """A reader of ``library`` at ``root``: a fresh venv sharing the packages of the site-packages
    ``deps`` (not cam-workbench), with HOME, work folder and a copy of the checkout of its own."""
    root.mkdir(parents=True)
    venv = root / "venv"
    res = _run([sys.executable, "-m", "venv", str(venv)], timeout=900)
    assert res.returncode == 0, res.stdout + res.stderr
    # the library's environment, shared read-only through symlinks (not cam-workbench)
    shared = root / "shared-site-packages"
    shared.mkdir()
    for entry in deps.iterdir():
        if entry.name.startswith(NOT_SHARED) or entry.suffix == ".pth":
            continue
        (shared / entry.name).symlink_to(entry)
    (_site_packages(venv / "bin" / "python") / "_reader_shared_dependencies.pth").write_text(f"{shared}\n")
    work, home = root / "work", root / "home"
    work.mkdir()
    home.mkdir()
    repo = root / "repo"
    shutil.copytree(ROOT, repo, ignore=IGNORE, symlinks=True)
    (repo / ".venv").symlink_to(venv, target_is_directory=True)
    return Reader(library, root, venv, wheelhouse, work, home, repo)


class Readers:
    """The two readers, each made when first needed (the build123d one needs the clean build123d
    venv of tests/install_envs.py, made once per session)."""

    def __init__(self, root: Path, install_envs):
        self.root = root
        self.install_envs = install_envs
        self._readers: dict[str, Reader] = {}
        self._wheelhouse: Path | None = None

    @property
    def wheelhouse(self) -> Path:
        if self._wheelhouse is None:
            src = self.root / "src"
            shutil.copytree(ROOT, src, ignore=IGNORE, symlinks=True)
            self._wheelhouse = self.root / "wheelhouse"
            res = _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", str(src), "-w",
                        str(self._wheelhouse)], timeout=900)
            assert res.returncode == 0, res.stdout + res.stderr
        return self._wheelhouse

    def __getitem__(self, library: str) -> Reader:
        if library not in self._readers:
            if library == "cadquery":          # the dev venv: CadQuery and its OCP (Makefile)
                deps = Path(sysconfig.get_paths()["purelib"])
            else:
                deps = _site_packages(self.install_envs.get("build123d-first").python)
            self._readers[library] = make_reader(library, self.root / library, self.wheelhouse, deps)
        return self._readers[library]


@pytest.fixture(scope="module")
def readers(tmp_path_factory, install_envs) -> Readers:
    return Readers(tmp_path_factory.mktemp("reader"), install_envs)


def sh_parts(unit: Unit) -> list[tuple[str, str]]:
    """(reader, text) pieces of an sh block in order: an install line naming another library's
    extra goes to that library's reader; the rest to the section's reader."""
    default = SECTION_READER.get(unit.section, "cadquery")
    parts: list[tuple[str, str]] = []
    for line in unit.text.splitlines(keepends=True):
        m = INSTALL_LINE.match(line)
        who = m.group(1) if m and m.group(1) in READERS else default
        if parts and parts[-1][0] == who:
            parts[-1] = (who, parts[-1][1] + line)
        else:
            parts.append((who, line))
    return parts


# ---- the blocks -------------------------------------------------------------------------------
def test_every_block_has_a_runner():
    """Nothing goes untested: every block is sh, python or toml."""
    assert BLOCKS, "README.md has no code blocks"
    other = [(b.line, b.lang) for b in BLOCKS if b.lang not in RUNNERS]
    assert not other, f"README blocks the tests cannot run (line, language): {other}"


def test_make_test_is_named_in_prose_only():
    """`make test` would run this very suite: it is mentioned in prose, never in a block."""
    assert "`make test`" in TEXT
    assert not [b.line for b in BLOCKS if re.search(r"\bmake\s+test\b", b.text)]


def test_freecad_mark_is_on_a_python_block():
    marked = [b for b in BLOCKS if b.freecad]
    assert len(marked) == TEXT.count(FREECAD_MARK) == 1 and marked[0].lang == "python"


def test_relative_links_exist():
    """Every relative link and picture of README.md and docs/*.md names a file of the checkout
    (docs/_readme_*.md are pieces of the README: their links are the README's)."""
    missing = []
    for page in [README, *sorted((ROOT / "docs").glob("*.md"))]:
        base = ROOT if page.name.startswith("_readme_") else page.parent
        for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", page.read_text(encoding="utf-8")):
            if re.match(r"[a-z]+:", target):
                continue
            if not (base / target).exists():
                missing.append(f"{page.relative_to(ROOT)} → {target}")
    assert not missing, missing


def _check_build_folder(folder: Path) -> None:
    names = {p.name for p in folder.iterdir()}
    assert set(BUILD_FILES) <= names, sorted(set(BUILD_FILES) - names)
    assert 'id="fig-cam"' in (folder / "report.html").read_text(encoding="utf-8")
    report = json.loads((folder / "report.json").read_text())
    assert report["checks"]["passed"] in (True, False)


def _after_sh(text: str, reader: Reader, res: subprocess.CompletedProcess) -> None:
    """What the README says the commands leave behind."""
    def runs(command: str) -> bool:          # a line of the block starts with it (not a comment)
        return re.search(rf"^\s*{re.escape(command)}\b", text, re.M) is not None

    if runs("pip install"):
        said = res.stdout + res.stderr
        assert "does not provide the extra" not in said, said
        code = (f"import cam_workbench, {reader.library}\nfrom cam_workbench.kernel import ocp as ocp_compat\n"
                f"print(cam_workbench.__file__)\nprint([n for n, v in ocp_compat.distributions()])")
        where = _run([str(reader.python), "-c", code], env=reader.env(), cwd=reader.work, timeout=SAFETY_S)
        assert where.returncode == 0, where.stderr
        path, dists = where.stdout.strip().splitlines()[-2:]
        assert path.startswith(str(reader.venv)), path          # the wheel, not the checkout
        # the library's own OCP build, and no second one
        assert dists == str(["cadquery-ocp" if reader.library == "cadquery" else "cadquery-ocp-novtk"]), dists
    if runs("make demo"):
        _check_build_folder(reader.repo / "out")
    if runs("cam-workbench build -o out"):
        _check_build_folder(reader.work / "out")
        _check_build_folder(reader.work / "paper")
        assert (reader.work / "paper_xc.nc").read_text().count("G93") >= 1
        assert (reader.work / "paper_opt" / "optimised.toml").is_file()
    if runs("cam-workbench freecad install"):
        assert list(reader.home.rglob("CamWorkbench/InitGui.py")), "no workbench under the reader's HOME"


def test_install_lines_name_the_readers():
    """Every extra the README's install lines name is one of pyproject's extras, and each reader's
    library has its line (what the two-reader set-up relies on)."""
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib  # type: ignore[no-redef]

    extras = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"])
    named = {m.group(1) for u in UNITS if u.kind == "sh" for m in INSTALL_LINE.finditer(u.text)}
    assert set(READERS) <= named <= extras, (named, extras)


@pytest.mark.parametrize("unit", UNITS, ids=[u.id for u in UNITS])
def test_readme_block_runs(unit: Unit, readers: Readers):
    """The README's blocks in order (one test each; a later one may use what an earlier one made)."""
    if unit.kind == "toml":
        load_spec(unit.text)
        return
    if unit.kind == "sh":
        if "freecad install" in unit.text and FREECADCMD is None:
            pytest.skip("freecadcmd is not installed (Debian package freecad-python3; `make test` installs it)")
        for who, text in sh_parts(unit):
            reader = readers[who]
            cwd = reader.work
            if re.search(r"^\s*make\b", text, re.M):
                cwd = reader.repo
                (reader.venv / ".installed").touch()        # the environment is ready: make need not rebuild it
            res = _run(["bash", "-e", "-o", "pipefail", "-c", text], cwd=cwd, env=reader.env(), timeout=1800)
            assert res.returncode == 0, (f"README line {unit.line} ({who} reader): exit {res.returncode}\n"
                                         f"{res.stdout[-3000:]}\n{res.stderr[-3000:]}")
            _after_sh(text, reader, res)
        return
    reader = readers[SECTION_READER.get(unit.section, "cadquery")]
    if unit.kind == "python":
        script = reader.root / f"readme_{unit.line}.py"
        script.write_text(unit.text + EPILOGUES.get(unit.section, ""), encoding="utf-8")
        res = _run([str(reader.python), str(script)], cwd=reader.work, env=reader.env(), timeout=1800)
        assert res.returncode == 0, f"README line {unit.line} ({unit.section}):\n{res.stdout[-3000:]}\n{res.stderr[-3000:]}"
        return
    assert unit.kind == "freecad"
    if FREECADCMD is None:
        pytest.skip("freecadcmd is not installed (Debian package freecad-python3; `make test` installs it)")
    body = unit.text + "\nimport os\nRESULT['cwd'] = os.getcwd()\n"
    run = run_freecadcmd(body, reader.work, reader.home).check()
    assert run.result["cwd"] == str(reader.work)
    made = reader.work / "cam_xc.nc"
    ref = reader.root / "ref_xc.nc"
    res = _run([str(reader.bin / "cam-workbench"), "gcode", "--mode", "xc", "-o", str(ref)], cwd=reader.root,
               env=reader.env(), timeout=900)
    assert res.returncode == 0, res.stderr
    assert made.read_bytes() == ref.read_bytes()      # the CLI's own program, written where FreeCAD runs

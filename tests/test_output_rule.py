"""Issue 20, item 1: no command removes or changes a file it did not write in this run, unless the
user asked (docs/cli.md, "Output folders and your files").

Every command — build, report, check, gcode, dxf, dynamics, ecam, optimise, sweep, batch — is run
(i) without ``-o`` after another command wrote into the same working folder, (ii) into a folder
holding another cam's set, (iii) into a folder of the user's own files, (iv) with ``-o`` naming a
file; every file that was there before must be byte-identical with its mtime unchanged, and
nothing created where the run is refused (exit 2, one line ``error: -o: …``).  Then the runs the
rule allows (the identical spec, the same cam written whole, ``--replace``) and the Python API
(``Cam.export``, the studies' ``batch``/``sweep``/``write_study``).

The commands run in this process (``cam_workbench.cli.main``, as the console script does) in a
fresh working folder each; the one set they meet is a real ``build`` of the paper's cam, made
once per module.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from cam_workbench.exporters.atomic import MANIFEST, read_manifest
from cam_workbench.generators.errors import SpecError

from .conftest import ROOT, assert_unchanged, requires_ocp, snapshot

pytestmark = requires_ocp

#: each command's arguments for the built-in default cam (light settings: the optimiser's
#: smallest budget, dynamics without the jump-speed sweep, studies in this process)
COMMANDS = {
    "build": ["build"],
    "report": ["report"],
    "check": ["check"],
    "gcode": ["gcode"],
    "dxf": ["dxf"],
    "dynamics": ["dynamics", "--no-sweep", "--set", "dynamics.stiffness=2000"],
    "ecam": ["ecam"],
    "optimise": ["optimise", "--max-evaluations", "10", "--workers", "0"],
    "sweep": ["sweep", "--vary", "cam.base_radius=40,45", "--workers", "0"],
    "batch": ["batch", "{default_toml}", "--workers", "0"],
}
#: where each command writes without -o (None: nothing, stdout for gcode/ecam)
DEFAULT_FOLDER = {"build": "out", "report": "out", "dxf": "out", "optimise": "out", "sweep": "sweep",
                  "batch": "batch", "check": None, "dynamics": None, "gcode": None, "ecam": None}
FOLDER_COMMANDS = [c for c in COMMANDS if c not in ("gcode", "ecam")]
FILE_COMMANDS = ["gcode", "ecam"]


@pytest.fixture(scope="module")
def made(tmp_path_factory) -> Path:
    """A working folder where `build mine.toml` (the paper's cam) ran without -o: ./out."""
    home = tmp_path_factory.mktemp("made")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    spec = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "spec", "--example", "paper"],
                          capture_output=True, text=True, env=env, check=True).stdout
    (home / "mine.toml").write_text(spec, encoding="utf-8")
    default = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "spec", "--default"],
                             capture_output=True, text=True, env=env, check=True).stdout
    (home / "default.toml").write_text(default, encoding="utf-8")
    res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", "build", "mine.toml"], cwd=home, env=env,
                         capture_output=True, text=True, stdin=subprocess.DEVNULL)
    assert res.returncode == 0, res.stderr
    assert (home / "out" / "cam.step").is_file()
    return home.resolve()


def run(cwd: Path, args: list[str], made: Path, capsys, monkeypatch) -> tuple[int, str, str]:
    """The command line in this process, in the working folder ``cwd``."""
    from cam_workbench.cli import main

    args = [a.format(default_toml=made / "default.toml") for a in args]
    monkeypatch.chdir(cwd)
    capsys.readouterr()
    code = main(args)
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def assert_refused(code: int, err: str, *words: str) -> None:
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    assert code == 2, err
    assert len(lines) == 1 and lines[0].startswith("error: -o: "), err
    assert "Traceback" not in err
    for w in words:
        assert w in lines[0], (w, lines[0])


def their_set(made: Path, where: Path) -> Path:
    """A copy of the paper cam's set (another cam than the default)."""
    shutil.copytree(made / "out", where)
    return where


# ---- (i) no -o, after another command wrote into the working folder ----------------------------
@pytest.mark.parametrize("command", list(COMMANDS))
def test_no_output_option_after_another_command(command, made, tmp_path, capsys, monkeypatch):
    folder = DEFAULT_FOLDER[command] or "out"
    their_set(made, tmp_path / folder)            # what `build mine.toml -o <folder>` left there
    before = snapshot(tmp_path)
    code, out, err = run(tmp_path, COMMANDS[command], made, capsys, monkeypatch)
    if DEFAULT_FOLDER[command] is None:           # inspects or prints: writes nothing
        assert code in (0, 3), err
        assert out.strip()
        if command in ("check", "dynamics"):
            assert "written" not in out
    else:
        assert_refused(code, err, "another cam's set", str(made / "mine.toml"), "--replace")
    assert_unchanged(tmp_path, before)


# ---- (ii) a folder holding another cam's set ------------------------------------------------------
@pytest.mark.parametrize("command", list(COMMANDS))
def test_a_folder_of_another_cam(command, made, tmp_path, capsys, monkeypatch):
    their_set(made, tmp_path / "theirs")
    before = snapshot(tmp_path)
    code, _out, err = run(tmp_path, [*COMMANDS[command], "-o", "theirs"], made, capsys, monkeypatch)
    if command in FILE_COMMANDS:
        assert_refused(code, err, "is a folder")
    else:
        # what the folder holds: the command, the cam, how many files, when, how its spec differs
        m = read_manifest(tmp_path / "theirs")
        assert_refused(code, err, "another cam's set", "`build`", str(made / "mine.toml"),
                       f"({len(m['files'])} files, {m['written']})", "--replace")
        if command not in ("batch", "sweep"):          # a cam's spec (a study's is another kind)
            assert "cam.base_radius 22.360679774997898 → 40" in err
    assert_unchanged(tmp_path, before)


# ---- (iii) a folder of the user's own files --------------------------------------------------------
@pytest.mark.parametrize("command, replace", [(c, False) for c in COMMANDS] + [(c, True) for c in FOLDER_COMMANDS])
def test_a_folder_of_the_users_files(command, replace, made, tmp_path, capsys, monkeypatch):
    mine = tmp_path / "mine"
    (mine / "drawings").mkdir(parents=True)
    (mine / "notes.txt").write_text("keep me")
    (mine / "drawings" / "old.dxf").write_text("0\nEOF\n")
    before = snapshot(tmp_path)
    args = [*COMMANDS[command], "-o", "mine"] + (["--replace"] if replace else [])
    code, _out, err = run(tmp_path, args, made, capsys, monkeypatch)
    if command in FILE_COMMANDS:
        assert_refused(code, err, "is a folder")
    else:
        assert_refused(code, err, "notes.txt", "drawings", "choose an empty or new folder")
    assert_unchanged(tmp_path, before)


def test_a_set_with_a_file_of_the_users_added_is_refused_even_with_replace(made, tmp_path, capsys, monkeypatch):
    out = their_set(made, tmp_path / "out")
    (out / "my_notes.txt").write_text("mine")
    before = snapshot(tmp_path)
    code, _o, err = run(tmp_path, ["check", str(made / "mine.toml"), "-o", "out", "--replace"], made, capsys,
                        monkeypatch)
    assert_refused(code, err, "my_notes.txt")
    assert_unchanged(tmp_path, before)


# ---- (iv) -o naming a file ------------------------------------------------------------------------
@pytest.mark.parametrize("command", list(COMMANDS))
def test_output_option_naming_a_file(command, made, tmp_path, capsys, monkeypatch):
    (tmp_path / "mine.txt").write_text("the user's file")
    before = snapshot(tmp_path)
    # a path under a file: refused by every command
    code, _o, err = run(tmp_path, [*COMMANDS[command], "-o", "mine.txt/x.nc"], made, capsys, monkeypatch)
    assert_refused(code, err, "mine.txt")
    assert_unchanged(tmp_path, before)
    code, out, err = run(tmp_path, [*COMMANDS[command], "-o", "mine.txt"], made, capsys, monkeypatch)
    if command in FILE_COMMANDS:
        # the user named the file: it is written (atomically), nothing else is touched
        assert code == 0, err
        assert (tmp_path / "mine.txt").read_text() != "the user's file"
        assert sorted(snapshot(tmp_path)) == sorted(before)
    else:
        assert_refused(code, err, "is a file")
        assert_unchanged(tmp_path, before)


def test_dxf_to_a_named_file_replaces_it_and_refuses_a_folder_of_that_name(made, tmp_path, capsys, monkeypatch):
    (tmp_path / "cam.dxf").write_text("the user's drawing")
    (tmp_path / "folder.dxf").mkdir()
    before = snapshot(tmp_path)
    code, _o, err = run(tmp_path, ["dxf", "-o", "folder.dxf"], made, capsys, monkeypatch)
    assert_refused(code, err, "is a folder")
    assert_unchanged(tmp_path, before)
    code, _o, err = run(tmp_path, ["dxf", "-o", "cam.dxf"], made, capsys, monkeypatch)
    assert code == 0, err
    assert (tmp_path / "cam.dxf").read_text().startswith("  0\nSECTION")
    assert sorted(snapshot(tmp_path)) == sorted(before)


@pytest.mark.parametrize("args", [["gcode", "--mode", "xc"], ["dxf", "--curves", "arcs"]])
def test_a_named_file_of_a_set_from_another_spec_is_refused(args, made, tmp_path, capsys, monkeypatch):
    """`gcode -o out/cam.nc` over a build's cam.nc of another spec would leave a set whose files
    contradict each other: refused; of the same spec the file agrees and is written."""
    their_set(made, tmp_path / "out")
    before = snapshot(tmp_path)
    name = "out/cam.nc" if args[0] == "gcode" else "out/cam.dxf"
    code, _o, err = run(tmp_path, [*args, str(made / "mine.toml"), "-o", name], made, capsys, monkeypatch)
    assert_refused(code, err, "is a file of the set `build` wrote", "name a file outside")
    assert_unchanged(tmp_path, before)
    same = ["gcode"] if args[0] == "gcode" else ["dxf"]
    code, _o, err = run(tmp_path, [*same, str(made / "mine.toml"), "-o", name], made, capsys, monkeypatch)
    assert code == 0, err
    if args[0] == "gcode":
        assert (tmp_path / name).read_bytes() == before[name][0]     # the same spec: the same program


# ---- the runs the rule allows -------------------------------------------------------------------
def test_the_issue_scenario_check_and_dynamics_without_o_keep_the_build(made, tmp_path):
    """The issue's report, as a user types it: `build mine.toml`, then `check mine.toml --set
    cam.thickness=13` and `dynamics … --no-sweep` without -o: ./out keeps the build's 13 files."""
    their_set(made, tmp_path / "out")
    shutil.copy(made / "mine.toml", tmp_path / "mine.toml")
    before = snapshot(tmp_path)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    for args in (["check", "mine.toml", "--set", "cam.thickness=13"],
                 ["dynamics", "mine.toml", "--set", "dynamics.stiffness=2000", "--set", "dynamics.mass=1", "--no-sweep"]):
        res = subprocess.run([sys.executable, "-m", "cam_workbench.cli", *args], cwd=tmp_path, env=env,
                             capture_output=True, text=True, stdin=subprocess.DEVNULL)
        assert res.returncode in (0, 3), res.stderr
        assert "Traceback" not in res.stderr and "written" not in res.stdout
    assert_unchanged(tmp_path, before)


def test_check_of_the_identical_spec_keeps_the_builds_other_files(made, tmp_path, capsys, monkeypatch):
    """(a) the identical spec — from the same file, or the built-in example it equals: the run's
    report.json replaces its namesake, every other file stays as it was."""
    out = their_set(made, tmp_path / "out")
    before = snapshot(tmp_path)
    for args in (["check", str(made / "mine.toml")], ["check", "--example", "paper", "--sampling", "thesis71"]):
        code, out_text, err = run(tmp_path, [*args, "-o", "out"], made, capsys, monkeypatch)
        assert code == 3, err                   # the paper's cam fails its pressure angle
        assert "checks written to out/report.json" in out_text
    after = snapshot(tmp_path)
    assert sorted(after) == sorted(before)
    changed = sorted(k for k in before if after[k] != before[k])
    assert changed == ["out/.cam-workbench.json", "out/report.json"]
    report = json.loads((out / "report.json").read_text())
    manifest = read_manifest(out)
    assert report["spec_digest"] == manifest["spec_digest"] == json.loads(before["out/report.json"][0])["spec_digest"]
    assert report["checks"]["sampling"] == "thesis71"
    # the set is still mine.toml's cam (a later build of the edited file may replace it)
    assert manifest["commands"] == ["build", "check"] and manifest["source"] == str(made / "mine.toml")
    assert sorted(manifest["files"]) == sorted(k[4:] for k in before if k.startswith("out/") and k != "out/" + MANIFEST)


def test_the_same_cam_of_another_spec_is_refused_when_files_would_be_left(made, tmp_path, capsys, monkeypatch):
    """(b)/(c) the same cam (the same spec file), another spec: `check` writes report.json only and
    would leave the build's 5 other files contradicting it (no PNG figures without --plots) —
    refused, naming what differs."""
    their_set(made, tmp_path / "out")
    before = snapshot(tmp_path)
    code, _o, err = run(tmp_path, ["check", str(made / "mine.toml"), "--set", "cam.thickness=13", "-o", "out"],
                        made, capsys, monkeypatch)
    assert_refused(code, err, "made from another spec (cam.thickness 10 → 13)", "would leave 5",
                   "choose another folder, or --replace")
    assert_unchanged(tmp_path, before)
    # docs/cli.md quotes this message: the same words, for its file and time
    docs = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    quoted = next(ln.strip() for ln in docs.splitlines() if ln.strip().startswith("error: -o: out holds the set"))
    written = read_manifest(tmp_path / "out")["written"]
    assert quoted.replace("/home/me/mine.toml", str(made / "mine.toml")).replace(
        "2026-11-27T03:36:30+0000", written) == err.strip()


def test_rebuilding_the_same_cam_after_an_edit_replaces_the_set(made, tmp_path, capsys, monkeypatch):
    """(b) `build mine.toml -o out` again after editing mine.toml: every file of the set is
    written again, so the set is replaced; the manifest and report.json name the new spec."""
    out = their_set(made, tmp_path / "out")
    before = snapshot(tmp_path)
    code, _o, err = run(tmp_path, ["build", str(made / "mine.toml"), "--set", "cam.thickness=13", "-o", "out"],
                        made, capsys, monkeypatch)
    assert code == 0, err
    manifest = read_manifest(out)
    report = json.loads((out / "report.json").read_text())
    assert report["spec"]["cam"]["thickness"] == 13 and report["spec_digest"] == manifest["spec_digest"]
    assert manifest["commands"] == ["build"] and manifest["spec"]["cam"]["thickness"] == 13
    assert sorted(p.name for p in out.iterdir()) == sorted([*manifest["files"], MANIFEST])
    after = snapshot(tmp_path)
    assert all(after.get(k) != v for k, v in before.items() if k.startswith("out/"))


def test_replace_replaces_another_cams_set_whole(made, tmp_path, capsys, monkeypatch):
    out = their_set(made, tmp_path / "out")
    code, _o, err = run(tmp_path, ["check", "-o", "out", "--replace"], made, capsys, monkeypatch)
    assert code == 0, err
    assert sorted(p.name for p in out.iterdir()) == [MANIFEST, "report.json"]
    manifest = read_manifest(out)
    assert manifest["source"] == "example:default" and manifest["files"] == ["report.json"]
    assert json.loads((out / "report.json").read_text())["spec_digest"] == manifest["spec_digest"]


def test_a_study_is_refused_over_another_study_and_replaces_its_own_tables(made, tmp_path, capsys, monkeypatch):
    """Study folders: a re-run of the same sweep replaces its tables; a sizing of the same spec
    would leave the sweep's table beside its own — refused unless --replace."""
    base = ["sweep", str(made / "mine.toml"), "--workers", "0", "-o", "s"]
    code, _o, err = run(tmp_path, [*base, "--vary", "cam.base_radius=40,45"], made, capsys, monkeypatch)
    assert code == 0, err
    code, _o, err = run(tmp_path, [*base, "--vary", "cam.base_radius=40,50"], made, capsys, monkeypatch)
    assert code == 0, err                       # the same spec's sweep: every table written again
    assert "50" in (tmp_path / "s" / "sweep.csv").read_text()
    before = snapshot(tmp_path)
    sizing = [*base, "--vary", "motion[1].law=cycloidal,harmonic", "--size", "base_radius", "--tol", "1"]
    code, _o, err = run(tmp_path, sizing, made, capsys, monkeypatch)
    assert_refused(code, err, "`sweep`", "would leave 2 that do not match (sweep.csv, sweep.parquet)")
    assert_unchanged(tmp_path, before)
    code, _o, err = run(tmp_path, [*sizing, "--replace"], made, capsys, monkeypatch)
    assert code == 0, err
    assert not (tmp_path / "s" / "sweep.csv").exists() and (tmp_path / "s" / "sizing.csv").is_file()


# ---- the Python API -------------------------------------------------------------------------------
def test_cam_export_follows_the_rule(made, tmp_path):
    from cam_workbench import Cam

    theirs = their_set(made, tmp_path / "theirs")
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("keep me")
    before = snapshot(tmp_path)
    cam = Cam.example("default")
    assert cam.source == "example:default"
    with pytest.raises(SpecError) as err:
        cam.export(theirs)
    assert err.value.field == "folder" and "another cam's set" in str(err.value) and "replace=True" in str(err.value)
    for replace in (False, True):
        with pytest.raises(SpecError, match="notes.txt"):
            cam.export(tmp_path / "mine", replace=replace)
    (tmp_path / "a.txt").write_text("x")
    with pytest.raises(SpecError, match="is a file"):
        cam.export(tmp_path / "a.txt")
    (tmp_path / "a.txt").unlink()
    assert_unchanged(tmp_path, before)
    # the same spec file's cam, edited: the export writes every file again, so it replaces the set
    edited = Cam(made / "mine.toml", **{"cam.thickness": 12})
    assert edited.source == str(made / "mine.toml")
    report = edited.export(theirs)
    manifest = read_manifest(theirs)
    assert manifest["command"] == "Cam.export" and manifest["spec_digest"] == report["spec_digest"]
    assert sorted(p.name for p in theirs.iterdir()) == sorted([*manifest["files"], MANIFEST])


def test_the_studies_api_follows_the_rule(made, tmp_path):
    from cam_workbench.studies import batch, sweep, write_study
    from cam_workbench.generators.spec.examples import example_spec

    theirs = their_set(made, tmp_path / "theirs")
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("keep me")
    before = snapshot(tmp_path)
    spec = example_spec("default")
    for out in (theirs, tmp_path / "mine"):
        with pytest.raises(SpecError) as err:
            batch([made / "default.toml"], out, workers=0)
        assert err.value.field == "out"
        with pytest.raises(SpecError) as err:
            sweep(spec, ["cam.base_radius=40,45"], build=out, workers=0)
        assert err.value.field == "build"
    table = sweep(spec, ["cam.base_radius=40,45"], workers=0)
    for out in (theirs, tmp_path / "mine"):
        with pytest.raises(SpecError) as err:
            write_study(table, out)
        assert err.value.field == "out"
    with pytest.raises(SpecError, match="notes.txt"):
        write_study(table, tmp_path / "mine", replace=True)
    assert_unchanged(tmp_path, before)
    files = write_study(table, theirs, replace=True)
    assert sorted(p.name for p in theirs.iterdir()) == sorted([*files.values(), MANIFEST])
    assert read_manifest(theirs)["source"].startswith("python")


def test_a_batch_run_again_replaces_its_own_entries(made, tmp_path, capsys, monkeypatch):
    """The same study (the same spec files) run again after an edit: its entries are made again
    and replace the earlier ones; another study into that folder is refused."""
    spec = tmp_path / "specs" / "cam.toml"
    spec.parent.mkdir()
    shutil.copy(made / "mine.toml", spec)
    args = ["batch", str(spec.parent), "--workers", "0", "-o", "b"]
    assert run(tmp_path, args, made, capsys, monkeypatch)[0] == 3            # the paper's cam fails a check
    spec.write_text(spec.read_text().replace("thickness = 10.0", "thickness = 12.0"))
    code, _o, err = run(tmp_path, args, made, capsys, monkeypatch)
    assert code == 3, err
    entry = read_manifest(tmp_path / "b" / "cam")
    assert entry["spec"]["cam"]["thickness"] == 12 and entry["source"] == str(spec.resolve())
    assert json.loads((tmp_path / "b" / "cam" / "report.json").read_text())["spec_digest"] == entry["spec_digest"]
    top = read_manifest(tmp_path / "b")
    assert top["command"] == "batch" and sorted(top["files"]) == ["cam", "study.json", "summary.csv", "summary.parquet"]
    before = snapshot(tmp_path)
    code, _o, err = run(tmp_path, ["batch", str(made / "default.toml"), "--workers", "0", "-o", "b"], made,
                        capsys, monkeypatch)
    assert_refused(code, err, "another cam's set", "`batch`", str(spec.parent.resolve()), "--replace")
    assert_unchanged(tmp_path, before)

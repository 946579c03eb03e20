"""An output folder holds one spec's consistent set: replaced whole or kept beside the identical
spec's files, never mixed — also when the process is killed while committing; foreign folders and
files refused; stdout's reader going away is not an error.  (Which folder a run may write into:
tests/test_output_rule.py.)"""
from __future__ import annotations

import json
import os
import random
import signal
import subprocess
import sys
import time

import pytest

from cam_workbench.exporters.atomic import MANIFEST, STAGING_TAG, OutputSet, read_manifest
from cam_workbench.exporters.output_rule import Claim
from cam_workbench.generators.errors import SpecError

from .conftest import ROOT, requires_ocp

CLI = [sys.executable, "-m", "cam_workbench.cli"]


def cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([*CLI, *args], capture_output=True, text=True, cwd=ROOT, stdin=subprocess.DEVNULL)


def _listing(folder) -> set[str]:
    return {p.name for p in folder.iterdir()}


def test_replace_replaces_the_earlier_set_whole(tmp_path):
    out = tmp_path / "out"
    with OutputSet(out, Claim("t", "one", digest="a")) as o:
        o.add_text("x.txt", "1")
        o.add_text("y.txt", "1")
    assert _listing(out) == {"x.txt", "y.txt", MANIFEST}
    with pytest.raises(SpecError, match="another cam's set"):
        with OutputSet(out, Claim("t", "two", digest="b")) as o:
            o.add_text("x.txt", "2")
    with OutputSet(out, Claim("t", "two", digest="b", replace=True)) as o:
        o.add_text("x.txt", "2")
    assert _listing(out) == {"x.txt", MANIFEST}
    assert (out / "x.txt").read_text() == "2" and read_manifest(out)["spec_digest"] == "b"


def test_the_other_files_stay_only_for_the_same_digest(tmp_path):
    out = tmp_path / "out"
    with OutputSet(out, Claim("build", "cam", digest="a")) as o:
        o.add_text("cam.step", "s")
        o.add_text("report.json", "{}")
    with OutputSet(out, Claim("check", "elsewhere", digest="a")) as o:
        o.add_text("report.json", '{"n": 1}')
    assert _listing(out) == {"cam.step", "report.json", MANIFEST}
    m = read_manifest(out)
    assert m["files"] == ["cam.step", "report.json"] and m["commands"] == ["build", "check"] and m["source"] == "cam"
    # the same cam, another spec, writing one of the two files: refused (cam.step would contradict it)
    with pytest.raises(SpecError, match=r"would leave 1 that do not match \(cam.step\)"):
        with OutputSet(out, Claim("check", "cam", digest="other")) as o:
            o.add_text("report.json", '{"n": 2}')
    assert _listing(out) == {"cam.step", "report.json", MANIFEST}
    # the same cam, another spec, writing both: replaced
    with OutputSet(out, Claim("build", "cam", digest="other")) as o:
        o.add_text("report.json", '{"n": 2}')
        o.add_text("cam.step", "t")
    assert read_manifest(out)["spec_digest"] == "other" and (out / "cam.step").read_text() == "t"


def test_an_error_leaves_the_earlier_set_untouched(tmp_path):
    out = tmp_path / "out"
    with OutputSet(out, Claim("t", "cam", digest="a")) as o:
        o.add_text("x.txt", "1")
    with pytest.raises(RuntimeError):
        with OutputSet(out, Claim("t", "cam", digest="b")) as o:
            o.add_text("x.txt", "2")
            raise RuntimeError("boom")
    assert (out / "x.txt").read_text() == "1" and _listing(out) == {"x.txt", MANIFEST}
    assert not [p for p in tmp_path.iterdir() if STAGING_TAG in p.name]


def test_foreign_files_and_file_paths_are_refused(tmp_path):
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("keep me")
    for replace in (False, True):
        with pytest.raises(SpecError, match="notes.txt"):
            with OutputSet(tmp_path / "mine", Claim("t", replace=replace)) as o:
                o.add_text("x.txt", "1")
    assert _listing(tmp_path / "mine") == {"notes.txt"}
    (tmp_path / "f").write_text("a file")
    for target in (tmp_path / "f", tmp_path / "f" / "sub"):
        with pytest.raises(SpecError, match="is a file"):
            OutputSet(target, Claim("t")).__enter__()


@requires_ocp
def test_cli_refusals_exit_2_and_change_nothing(tmp_path):
    (tmp_path / "f").write_text("a file")
    for target in (tmp_path / "f", tmp_path / "f" / "x"):
        r = cli("build", "-o", str(target))
        assert r.returncode == 2 and r.stderr.startswith("error: -o:") and "Traceback" not in r.stderr
    assert (tmp_path / "f").read_text() == "a file"
    (tmp_path / "d").mkdir()
    (tmp_path / "d" / "notes.txt").write_text("x")
    r = cli("check", "-o", str(tmp_path / "d"))
    assert r.returncode == 2 and "notes.txt" in r.stderr
    assert _listing(tmp_path / "d") == {"notes.txt"}


@requires_ocp
def test_second_build_and_check_of_another_cam_leave_no_mix(tmp_path):
    out = tmp_path / "out"
    assert cli("build", "--plots", "-o", str(out)).returncode == 0  # default: loaded follower
    first = _listing(out)
    assert "plot_force_stress.png" in first
    # another cam: --replace (no load: no force plot)
    assert cli("build", "--example", "paper", "-o", str(out), "--replace").returncode == 0
    second = _listing(out)
    assert "plot_force_stress.png" not in second
    assert second == set(read_manifest(out)["files"]) | {MANIFEST}
    rep = json.loads((out / "report.json").read_text())
    assert rep["spec_digest"] == read_manifest(out)["spec_digest"]
    assert cli("check", "-o", str(out), "--replace").returncode == 0          # another cam: its report only
    assert _listing(out) == {"report.json", MANIFEST}


@requires_ocp
def test_killed_builds_never_leave_a_mixed_folder(tmp_path):
    """Builds of two different cams into one folder, killed (SIGKILL) at random moments: the
    folder always holds one complete set (its manifest's files, all present, report.json of the
    manifest's digest), and the next run removes what the killed ones left."""
    out = tmp_path / "out"
    assert cli("build", "-o", str(out)).returncode == 0
    rng = random.Random(7)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    for i in range(10):
        example = "paper" if i % 2 else "default"
        p = subprocess.Popen([*CLI, "build", "--example", example, "-o", str(out), "--replace"], cwd=ROOT, env=env,
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, stdin=subprocess.DEVNULL)
        time.sleep(rng.uniform(1.0, 6.0))
        p.send_signal(signal.SIGKILL)
        p.wait()
        m = read_manifest(out)
        assert m is not None
        assert _listing(out) == set(m["files"]) | {MANIFEST}
        assert json.loads((out / "report.json").read_text())["spec_digest"] == m["spec_digest"]
    assert cli("build", "-o", str(out), "--replace").returncode == 0
    assert not [p for p in tmp_path.iterdir() if STAGING_TAG in p.name]
    assert not [p for p in out.iterdir() if p.name.endswith(".tmp")]


def test_broken_pipe_keeps_the_commands_status(tmp_path):
    r = subprocess.run(["bash", "-c", f"set -o pipefail; {sys.executable} -m cam_workbench.cli check --example paper "
                                      f"-o {tmp_path / 'o'} | head -1 >/dev/null; echo ${{PIPESTATUS[0]}}"],
                       capture_output=True, text=True, cwd=ROOT, stdin=subprocess.DEVNULL,
                       env=dict(os.environ, PYTHONPATH=str(ROOT)))
    assert r.stdout.strip() == "3"
    assert "Traceback" not in r.stderr and "BrokenPipe" not in r.stderr and "Exception ignored" not in r.stderr

"""``cam-workbench batch`` and ``sweep`` (issue 16), and ``optimise --workers``, as a user runs
them: real processes, a real local Dask cluster (``--workers 2``), a real scheduler with two
workers on the loopback address (``--scheduler``), Ctrl-C as SIGINT.  Exit statuses as
docs/cli.md gives them; bad input exits 2 with one line naming the option and writes nothing."""
from __future__ import annotations

import csv
import json
import math
import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from cam_workbench.generators.spec.examples import example_dict
from cam_workbench.generators.spec import dict_to_toml

from .conftest import ROOT, SAFETY_S, requires_ocp
from .dask_cluster import loopback_cluster

CLI = [sys.executable, "-m", "cam_workbench.cli"]
ENV = dict(os.environ, PYTHONPATH=str(ROOT))
needs_dask = pytest.mark.skipif(not __import__("importlib").util.find_spec("distributed"),
                                reason="Dask is not installed")


def run(*args, cwd=None, timeout=900):
    return subprocess.run([*CLI, *map(str, args)], capture_output=True, text=True, cwd=cwd, env=ENV,
                          timeout=timeout)


def rows(path: Path) -> list[dict[str, str]]:
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="module")
def specs(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("specs")
    for name in ("default", "flat", "paper"):
        (folder / f"{name}.toml").write_text(dict_to_toml(example_dict(name)))
    (folder / "broken.toml").write_text("[cam]\nbase_radius = 40\n")       # no follower, no motion
    return folder


@pytest.fixture(scope="module")
def scheduler(tmp_path_factory):
    yield from loopback_cluster(tmp_path_factory.mktemp("dask-cluster"))


# ---- batch ------------------------------------------------------------------------------------
@requires_ocp
@needs_dask
def test_batch_builds_each_spec_reports_the_bad_one_and_runs_on_a_local_cluster(specs, tmp_path):
    missing = tmp_path / "nowhere.toml"
    out0, out2 = tmp_path / "b0", tmp_path / "b2"
    res0 = run("batch", specs, missing, "-o", out0, "--workers", 0)
    res2 = run("batch", specs, missing, "-o", out2, "--workers", 2)
    for res in (res0, res2):
        assert res.returncode == 4, res.stdout + res.stderr          # some specs could not be built
        assert "broken: bad input: cam.thickness: is required" in res.stdout
    assert (out0 / "summary.csv").read_text() == (out2 / "summary.csv").read_text()
    table = rows(out0 / "summary.csv")
    assert [r["name"] for r in table] == ["broken", "default", "flat", "paper", "nowhere"]
    status = {r["name"]: r["status"] for r in table}
    assert status == {"broken": "bad input", "default": "ok", "flat": "ok", "paper": "ok", "nowhere": "bad input"}
    by = {r["name"]: r for r in table}
    assert "file not found" in by["nowhere"]["error"]
    assert by["default"]["checks_passed"] == "true" and by["paper"]["checks_passed"] == "false"
    assert by["paper"]["failed_checks"] == "pressure_angle"
    assert float(by["paper"]["check_pressure_angle"]) > 30.0
    assert by["flat"]["follower"] == "translating flat-faced" and by["flat"]["check_cusp_status"] == "pass"
    # every built cam's folder is the output set `build` writes, and its numbers are the table's
    for name in ("default", "flat", "paper"):
        report = json.loads((out0 / name / "report.json").read_text())
        assert (out0 / name / "cam.step").read_text().startswith("ISO-10303-21")
        assert report["solid"]["valid"] and by[name]["solid_valid"] == "true"
        assert float(by[name]["area"]) == report["area"] and float(by[name]["volume"]) == report["volume"]
        assert float(by[name]["pressure_angle_deg"]) == report["pressure_angle"]["max_deg"]
        assert float(by[name]["base_radius"]) == report["spec"]["cam"]["base_radius"]
    assert not (out0 / "broken").exists() and not (out0 / "nowhere").exists()
    pq = pytest.importorskip("pyarrow.parquet")
    pt = pq.read_table(out0 / "summary.parquet")
    assert pt.column_names == list(table[0]) and pt.column("area").to_pylist()[1] == float(by["default"]["area"])
    meta = json.loads((out2 / "study.json").read_text())
    assert meta["workers"] == 2 and meta["built"] == 3 and json.loads((out0 / "study.json").read_text())["workers"] == 1
    manifest = json.loads((out0 / ".cam-workbench.json").read_text())
    assert manifest["command"] == "batch"
    assert sorted(manifest["files"]) == ["default", "flat", "paper", "study.json", "summary.csv", "summary.parquet"]

    # again into the same folder, another study (one cam): refused, nothing changed; with
    # --replace exit 0 and the earlier run's other cams are gone
    res = run("batch", specs / "default.toml", "-o", out0, "--workers", 0)
    assert res.returncode == 2 and res.stderr.startswith("error: -o: ") and "--replace" in res.stderr
    assert sorted(p.name for p in out0.iterdir()) == [".cam-workbench.json", "default", "flat", "paper",
                                                     "study.json", "summary.csv", "summary.parquet"]
    res = run("batch", specs / "default.toml", "-o", out0, "--workers", 0, "--replace")
    assert res.returncode == 0, res.stdout + res.stderr
    assert sorted(p.name for p in out0.iterdir()) == [".cam-workbench.json", "default", "study.json",
                                                     "summary.csv", "summary.parquet"]
    # a cam failing a design check: exit 3
    res = run("batch", specs / "paper.toml", "-o", tmp_path / "b3", "--workers", 0)
    assert res.returncode == 3 and "paper: fails pressure_angle" in res.stdout


@pytest.mark.parametrize("args, words", [
    (["batch", "{empty}"], "folder holds no *.toml spec files"),
    (["batch", "{spec}", "-o", "{file}"], "is a file"),
    (["batch", "{spec}", "-o", "{foreign}"], "holds files that are not a cam-workbench output"),
    (["batch", "{spec}", "--workers", "-1"], "--workers: must be ≥ 0"),
    (["batch", "{spec}", "--workers", "2", "--scheduler", "tcp://127.0.0.1:9"], "--scheduler: give --workers or"),
    (["sweep", "--vary", "motion[1].lift"], "--vary: 'motion[1].lift': write FIELD=START:STOP:COUNT"),
    (["sweep", "--vary", "motion[7].lift=1:2:3"], "index 7 is out of range"),
    (["sweep", "--vary", "cam.radius=1:2:3"], "unknown field"),
    (["sweep", "--vary", "cam.base_radius=30:40:3", "--size", "base_radius"], "what the study sets itself"),
    (["sweep", "--vary", "motion[1].law=harmonic", "--size", "base_radius", "--size-checks", "bogus"],
     "--size-checks: unknown check 'bogus'"),
    (["sweep", "--vary", "motion[1].law=harmonic", "--size", "base_radius", "--size-checks", "cusp"],
     "--size-checks: cusp is not a check of this follower"),
    (["sweep", "--vary", "motion[1].law=harmonic", "--size", "base_radius", "--tol", "0"], "--tol: must be > 0"),
    (["sweep", "--vary", "motion[1].law=harmonic", "--size", "base_radius", "--build"], "--build"),
    (["sweep"], "--vary: give at least one"),
])
def test_bad_input_exits_2_and_writes_nothing(args, words, specs, tmp_path):
    (tmp_path / "empty").mkdir()
    (tmp_path / "file").write_text("x")
    (tmp_path / "foreign").mkdir()
    (tmp_path / "foreign" / "mine.txt").write_text("mine")
    subs = {"{empty}": tmp_path / "empty", "{spec}": specs / "default.toml", "{file}": tmp_path / "file",
            "{foreign}": tmp_path / "foreign"}
    args = [str(subs.get(a, a)) for a in args]
    if "-o" not in args:
        args += ["-o", str(tmp_path / "out")]
    before = sorted(str(p) for p in tmp_path.rglob("*"))
    res = run(*args)
    assert res.returncode == 2, res.stdout + res.stderr
    assert words in res.stderr and len(res.stderr.strip().splitlines()) == 1, res.stderr
    assert sorted(str(p) for p in tmp_path.rglob("*")) == before


# ---- sweep ------------------------------------------------------------------------------------
FLAT = """units = "mm"
[cam]
base_radius = 40.0
thickness = 10.0
bore_diameter = 12.0
[follower]
kind = "flat"
face_width = 400.0
[[motion]]
kind = "rise"
angle = 60.0
lift = 20.0
law = "harmonic"
[[motion]]
kind = "dwell"
angle = 120.0
[[motion]]
kind = "return"
angle = 60.0
lift = 20.0
law = "harmonic"
[[motion]]
kind = "dwell"
angle = 120.0
"""
SIZE_ARGS = ["--vary", "motion[0].angle,motion[2].angle=60:90:4", "--balance", "motion[1].angle",
             "--vary", "motion[0].lift,motion[2].lift=10,20", "--size", "base_radius", "--size-checks", "cusp"]


@needs_dask
def test_sizing_sweep_writes_the_table_and_the_chart_on_the_scheduler(tmp_path, scheduler):
    """A flat face's cusp-free radius h(π²/(2β²) − 1) over β × h: the table (with --workers 0, and
    with --scheduler on the loopback cluster: the same bytes), the Parquet copy, the chart."""
    spec = tmp_path / "flat.toml"
    spec.write_text(FLAT)
    res = run("sweep", spec, *SIZE_ARGS, "-o", tmp_path / "s0", "--workers", 0)
    assert res.returncode == 0, res.stdout + res.stderr
    res2 = run("sweep", spec, *SIZE_ARGS, "-o", tmp_path / "s2", "--scheduler", scheduler)
    assert res2.returncode == 0, res2.stdout + res2.stderr
    assert (tmp_path / "s0" / "sizing.csv").read_bytes() == (tmp_path / "s2" / "sizing.csv").read_bytes()
    table = rows(tmp_path / "s0" / "sizing.csv")
    assert len(table) == 8
    for r in table:
        b, h = math.radians(float(r["motion[0].angle"])), float(r["motion[0].lift"])
        expected = h * (math.pi**2 / (2 * b * b) - 1)
        assert r["status"] == "ok" and r["binding_checks"] in ("cusp", "") or r["binding_checks"].startswith("spec")
        if expected > 6.0 + 0.01:                # above the bore's floor (R_b > 6 mm)
            assert expected < float(r["min_base_radius"]) <= expected + 0.01 + 1e-9
            assert r["binding_checks"] == "cusp"
    png = (tmp_path / "s0" / "sizing_chart.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    meta = json.loads((tmp_path / "s2" / "study.json").read_text())
    assert meta["kind"] == "sizing" and meta["workers"] == 2 and meta["tolerance"] == 0.01
    assert meta["checks"] == ["cusp"]
    assert "smallest R_b" in res.stdout and "8 of 8 points evaluated" in res.stdout


def test_evaluate_sweep_exit_4_when_points_are_bad(tmp_path):
    out = tmp_path / "ev"
    res = run("sweep", "--vary", "motion[1].lift=15,20", "--vary", "motion[1].law=harmonic,cycloidal", "-o", out,
              "--workers", 0)
    assert res.returncode == 4, res.stdout + res.stderr
    table = rows(out / "sweep.csv")
    assert [(r["motion[1].lift"], r["motion[1].law"], r["status"]) for r in table] == [
        ("15", "harmonic", "bad input"), ("15", "cycloidal", "bad input"),
        ("20", "harmonic", "ok"), ("20", "cycloidal", "ok")]
    assert "motion[3].lift: the follower would go 5 below zero lift" in table[0]["error"]
    assert sorted(p.name for p in out.iterdir()) == [".cam-workbench.json", "study.json", "sweep.csv",
                                                    "sweep.parquet"]


@requires_ocp
def test_sweep_build_writes_every_point(tmp_path):
    out = tmp_path / "built"
    res = run("sweep", "--vary", "motion[1].law,motion[3].law=harmonic,poly345", "--build", "-o", out,
              "--workers", 0)
    assert res.returncode == 0, res.stdout + res.stderr
    table = rows(out / "summary.csv")
    assert [(r["name"], r["motion[1].law"], r["folder"], r["status"]) for r in table] == [
        ("point-1", "harmonic", "point-1", "ok"), ("point-2", "poly345", "point-2", "ok")]
    for r in table:
        report = json.loads((out / r["folder"] / "report.json").read_text())
        assert report["spec"]["motion"][1]["law"] == r["motion[1].law"] == report["spec"]["motion"][3]["law"]
        assert float(r["pressure_angle_deg"]) == report["pressure_angle"]["max_deg"]


# ---- optimise --workers -----------------------------------------------------------------------
@requires_ocp
@needs_dask
def test_optimise_multistart_on_a_local_cluster_writes_the_sequential_result(tmp_path):
    args = ["optimise", "--example", "paper", "--variables", "base_radius,offset", "--multistart", 5, "--seed", 4]
    a = run(*args, "-o", tmp_path / "o0", "--workers", 0)
    b = run(*args, "-o", tmp_path / "o2", "--workers", 2)
    assert a.returncode == b.returncode == 0, a.stderr + b.stderr
    assert (tmp_path / "o0" / "optimised.toml").read_text() == (tmp_path / "o2" / "optimised.toml").read_text()
    ra = json.loads((tmp_path / "o0" / "report.json").read_text())["optimise"]
    rb = json.loads((tmp_path / "o2" / "report.json").read_text())["optimise"]
    for key in ("final_value", "status", "message", "evaluations", "history", "variables"):
        assert ra[key] == rb[key], key
    assert (ra["workers"], rb["workers"]) == (1, 2)


# ---- Ctrl-C ----------------------------------------------------------------------------------
# The command runs in a terminal of its own (a pseudo-terminal, as a user's shell gives it), and
# Ctrl-C is the character ^C typed into that terminal: the kernel sends SIGINT to every process of
# the foreground group — the command and the local cluster's worker processes — as it does for a
# user.  The test waits on the run's own progress bar (drawn on the terminal) showing a finished
# item, never on a time; the only time limit is the safety net SAFETY_S that turns a hang into a
# failure.
# a session of its own with the terminal on stdin as its controlling terminal, then the command
#: the command as a shell starts a foreground job: its own session with the terminal as its
#: controlling terminal, SIGINT at its default disposition and unblocked (a pytest process that
#: inherited or was left with SIGINT ignored would otherwise pass that on through exec)
_IN_TERMINAL = ("import fcntl, os, signal, sys, termios; os.setsid(); fcntl.ioctl(0, termios.TIOCSCTTY, 0); "
                "signal.signal(signal.SIGINT, signal.SIG_DFL); "
                "signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT}); "
                "os.execv(sys.executable, [sys.executable, *sys.argv[1:]])")
_ANSI = re.compile(r"\x1b\[[0-9;?]*[A-Za-z]")


class TerminalRun:
    """The CLI running in a pseudo-terminal (stdout; stderr is a pipe), its screen read as it comes."""

    def __init__(self, *args: str):
        import fcntl
        import pty
        import struct
        import termios

        self.master, slave = pty.openpty()
        fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 50, 200, 0, 0))    # 200 columns
        env = dict(ENV, TERM="xterm", COLUMNS="200")
        self.p = subprocess.Popen([sys.executable, "-c", _IN_TERMINAL, "-m", "cam_workbench.cli", *args],
                                  stdin=slave, stdout=slave, stderr=subprocess.PIPE, text=True, env=env,
                                  cwd=ROOT)
        os.close(slave)
        self.screen = ""
        self._changed = threading.Condition()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        while True:
            try:
                data = os.read(self.master, 4096)
            except OSError:               # EIO: the terminal's last process closed it
                data = b""
            with self._changed:
                if not data:
                    self.screen += "\0"   # the end
                    self._changed.notify_all()
                    return
                self.screen += _ANSI.sub("", data.decode("utf-8", "replace"))
                self._changed.notify_all()

    def wait_for_progress(self, unit: str) -> int:
        """Block until the progress bar shows at least one ``unit`` done; returns that count."""
        pattern = re.compile(rf"(\d+)/\d+ {unit}")
        end = time.monotonic() + SAFETY_S
        with self._changed:
            while True:
                done = [int(m.group(1)) for m in pattern.finditer(self.screen)]
                if done and max(done) >= 1:
                    return max(done)
                assert "\0" not in self.screen, (self.screen[-2000:], self.p.stderr.read())
                assert time.monotonic() < end, f"no progress within the safety limit: {self.screen[-2000:]}"
                self._changed.wait(end - time.monotonic())

    def ctrl_c(self) -> None:
        os.write(self.master, b"\x03")

    def finish(self) -> tuple[int, str]:
        try:
            _, stderr = self.p.communicate(timeout=SAFETY_S)
        finally:
            if self.p.poll() is None:
                os.killpg(self.p.pid, signal.SIGKILL)
                self.p.wait()
            self._reader.join(SAFETY_S)
            os.close(self.master)
        return self.p.returncode, stderr


def _session(sid: int) -> list:
    """The processes alive in session ``sid`` (the command's: everything it started, orphans too)."""
    import psutil

    found = []
    for proc in psutil.process_iter():
        try:
            if os.getsid(proc.pid) == sid and proc.status() != psutil.STATUS_ZOMBIE:
                found.append(proc)
        except (psutil.NoSuchProcess, ProcessLookupError, PermissionError):
            pass
    return found


def _complete_sets(out: Path) -> list[str]:
    """The cam subfolders of a batch/sweep --build folder, each checked to be a whole output set:
    exactly the files its manifest lists, report.json readable; no staging folder anywhere."""
    assert not [q for q in out.parent.iterdir() if ".cam-workbench-staging-" in q.name]
    names = []
    for sub in sorted(q for q in out.iterdir() if q.is_dir()):
        assert ".cam-workbench-staging-" not in sub.name
        manifest = json.loads((sub / ".cam-workbench.json").read_text())
        assert sorted(q.name for q in sub.iterdir()) == sorted([".cam-workbench.json", *manifest["files"]])
        assert json.loads((sub / "report.json").read_text())["solid"]["valid"]
        names.append(sub.name)
    return names


CTRL_C_RUNS = {
    "batch": (["batch", "{many}", "--workers", "2"], "cams"),
    "sweep": (["sweep", "--vary", "motion[1].angle,motion[3].angle=60:140:200", "--balance", "motion[2].angle",
               "--vary", "motion[1].law,motion[3].law=cycloidal,harmonic", "--size", "base_radius", "--tol", "1e-4",
               "--workers", "2"], "points"),
    "optimise": (["optimise", "--example", "paper", "--variables", "base_radius,offset", "--multistart", "9",
                  "--seed", "4", "--workers", "2"], "evaluations"),
}


@requires_ocp
@needs_dask
@pytest.mark.parametrize("command", list(CTRL_C_RUNS))
def test_ctrl_c_on_a_local_cluster_prints_one_line_and_stops_every_process(command, tmp_path):
    """Ctrl-C in the terminal once the run's progress shows an item done: exactly one line on
    stderr, exit 130, no process of the command's session left (the workers, the scheduler's and
    the nannies' threads live in the command's process), and the output folder holds only whole
    output sets: batch keeps the cams done (summary.csv marks the rest cancelled), sweep and
    optimise write nothing."""
    psutil = pytest.importorskip("psutil")
    many = tmp_path / "many"
    many.mkdir()
    for k in range(8):
        (many / f"cam{k}.toml").write_text(dict_to_toml(example_dict("default" if k % 2 else "flat")))
    out = tmp_path / "out"
    args, unit = CTRL_C_RUNS[command]
    run_ = TerminalRun(*[str(many) if a == "{many}" else a for a in args], "-o", str(out))
    try:
        run_.wait_for_progress(unit)
        workers = [c for c in psutil.Process(run_.p.pid).children(recursive=True)
                   if "--multiprocessing-fork" in c.cmdline()]
        assert len(workers) == 2, [c.cmdline() for c in workers]      # the local cluster's workers
        run_.ctrl_c()
    finally:
        status, stderr = run_.finish()
    assert status == 130, run_.screen[-2000:] + stderr
    lines = stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("interrupted"), stderr
    # the workers end with the command; what is left of its session (the multiprocessing resource
    # tracker ends on its pipe's end, just after) is waited for, as an event
    gone, alive = psutil.wait_procs([*workers, *_session(run_.p.pid)], timeout=SAFETY_S)
    assert not alive and _session(run_.p.pid) == []
    if command != "batch":
        assert not out.exists() and sorted(q.name for q in tmp_path.iterdir()) == ["many"]
        return
    table = rows(out / "summary.csv")
    done = [r["name"] for r in table if r["status"] == "ok"]
    assert done and len(done) < 8 and all(r["status"] in ("ok", "cancelled") for r in table)
    assert lines == [f"interrupted: {len(done)} of 8 cams written; summary.csv marks the rest cancelled"]
    assert _complete_sets(out) == sorted(done)
    assert sorted(q.name for q in out.iterdir() if q.is_file()) == [".cam-workbench.json", "study.json",
                                                                     "summary.csv", "summary.parquet"]

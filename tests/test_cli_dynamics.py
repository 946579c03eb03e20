"""`cam-workbench dynamics` and `cam-workbench ecam` from the command line, and the dynamics in
`build`'s outputs, read back as a user's tools would: report.json's ``dynamics`` section is what the
HTML's cells show (data-value, and the text to 6 digits), what the `dynamics` command prints (each
table row), and what the figures mark; bad input exits 2 with one line naming the field and
writes nothing; the dynamics stage runs only when asked for.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from html.parser import HTMLParser

import pytest

from cam_workbench.exporters.report_cells import format_number, lookup

from .conftest import ROOT, requires_ocp

CLI = [sys.executable, "-m", "cam_workbench.cli"]
STIFF = ["--set", "dynamics.stiffness=2000", "--set", "follower.spring_rate=3"]


def run(*args, cwd=None):
    env = dict(os.environ, PYTHONPATH=str(ROOT), COLUMNS="250")
    return subprocess.run([*CLI, *args], capture_output=True, text=True, cwd=cwd, env=env)


# ---- the dynamics command --------------------------------------------------------------------------
@pytest.fixture(scope="module")
def below(tmp_path_factory):
    out = tmp_path_factory.mktemp("below") / "out"
    res = run("dynamics", *STIFF, "-o", str(out))
    return out, res


@pytest.fixture(scope="module")
def above(tmp_path_factory):
    out = tmp_path_factory.mktemp("above") / "out"
    res = run("dynamics", *STIFF, "--speed", "700", "-o", str(out))
    return out, res


#: the printed table's rows → report.json's dynamics keys (value, cam angle)
ROWS = {
    "natural frequency of the train": ("model.natural_frequency_hz", None),
    "natural frequency / cam frequency": ("model.frequency_ratio", None),
    "smallest contact force (dynamic)": ("contact.min_force", "contact.min_force_at_deg"),
    "largest contact force (dynamic)": ("contact.max_force", "contact.max_force_at_deg"),
    "smallest contact force (rigid)": ("contact.rigid_min_force", "contact.rigid_min_force_at_deg"),
    "largest contact force (rigid)": ("contact.rigid_max_force", "contact.rigid_max_force_at_deg"),
    "largest displacement error |q − s|": ("error.max", "error.at_deg"),
    "largest vibration": ("error.max_vibration", "error.vibration_at_deg"),
    "camshaft torque max (rigid)": ("torque.rigid.max", "torque.rigid.max_at_deg"),
    "camshaft torque max (dynamic)": ("torque.dynamic.max", "torque.dynamic.max_at_deg"),
    "camshaft torque RMS (dynamic)": ("torque.dynamic.rms", None),
    "work per revolution (dynamic)": ("torque.dynamic.work_per_revolution", None),
    "off the cam": ("contact.off_cam_deg", None),
    "largest gap": ("contact.max_gap", "contact.max_gap_at_deg"),
    "largest landing speed": ("contact.max_landing_speed", None),
}


def _printed_rows(stdout):
    rows = {}
    for line in stdout.splitlines():
        if line.startswith("│"):
            cells = [c.strip() for c in line.strip("│").split("│")]
            if len(cells) == 4:
                rows[cells[0]] = cells[1:]
    return rows


@pytest.mark.parametrize("case", ["below", "above"])
def test_dynamics_command_prints_report_json(case, request):
    out, res = request.getfixturevalue(case)
    assert res.returncode == (0 if case == "below" else 3), res.stderr
    d = json.loads((out / "report.json").read_text())["dynamics"]
    assert sorted(p.name for p in out.iterdir()) == [".cam-workbench.json", "dynamics.csv", "plot_dynamics.png",
                                                     "plot_jump_speed.png", "report.json"]
    rows = _printed_rows(res.stdout)
    seen = 0
    for label, (key, at) in ROWS.items():
        if label not in rows:
            assert case == "below" and key.startswith("contact.") and "force" not in key, label
            continue
        value, _unit, angle = rows[label]
        assert value == format_number(lookup(d, key)), label
        assert angle == ("—" if at is None else f"{format_number(lookup(d, at))}°"), label
        seen += 1
    assert seen >= 12
    jp = d["jump_speed"]
    assert f"jump speed: {format_number(jp['rpm'])} rpm ({format_number(jp['ratio_to_speed'])} × the analysis speed)" \
        in res.stdout
    assert d["contact"]["kept"] is (case == "below")
    assert ("LEAVES the cam" in res.stdout) is (case == "above")
    if case == "below":
        for i, r in enumerate(d["residual_vibration"]):
            assert f"{format_number(r['amplitude'])} mm" in res.stdout
    # the CSV's series: its force column's smallest value is near the reported one (the grid's)
    lines = (out / "dynamics.csv").read_text().splitlines()
    head = lines[0].split(",")
    force = [float(ln.split(",")[head.index("force [N]")]) for ln in lines[1:]]
    assert len(force) == d["model"]["samples"]
    assert min(force) == pytest.approx(d["contact"]["min_force"], abs=1e-3 * max(force))


def test_dynamics_figures_mark_report_json_numbers(above):
    """The figures' marks sit at report.json's numbers (the figure objects' own line data)."""
    from cam_workbench.generators.dynamics import analyse_dynamics
    from cam_workbench.generators.spec import default_spec

    from cam_workbench.exporters import plots_dynamics

    out, _res = above
    d = json.loads((out / "report.json").read_text())["dynamics"]
    spec = default_spec().replace(**{"dynamics.stiffness": 2000.0, "follower.spring_rate": 3.0,
                                     "dynamics.speed_rpm": 700.0})
    result = analyse_dynamics(spec)
    gids = plots_dynamics.DYNAMICS_GIDS
    chart = plots_dynamics.jump_speed_figure(result, d)
    for key, value in (("jump", d["jump_speed"]["rpm"]), ("speed", d["speed_rpm"]),
                       ("rigid_jump", d["jump_speed"]["rigid_rpm"])):
        [rule] = chart.marks(gids[key])
        assert rule.axis == "x" and rule.at == value
    chart = plots_dynamics.dynamics_figure(result, d)
    [mark] = chart.marks(gids["min_force"])
    assert (mark.x[0], mark.y[0]) == (d["contact"]["min_force_at_deg"], d["contact"]["min_force"])


@pytest.mark.parametrize("args, field", [
    ([], "dynamics.stiffness"),
    (["--set", "dynamics.stiffness=2000", "--speed", "-5"], "dynamics.speed_rpm"),
    (["--example", "oscillating", "--set", "dynamics.stiffness=2000"], "dynamics.stiffness"),
    (["--example", "oscillating", "--set", "follower.arm_inertia=0", "--set", "dynamics.torsional_stiffness=1e6"],
     "dynamics.arm_inertia"),
    (["--set", "dynamics.stiffness=2000", "--set", "dynamics.damping_ratio=1.5"], "dynamics.damping_ratio"),
    (["--set", "dynamics.stiffness=2000", "--set", "dynamics.sweep_max_rpm=10", "--set", "dynamics.sweep_min_rpm=20"],
     "dynamics.sweep_max_rpm"),
])
def test_dynamics_bad_input_exits_2_writes_nothing(tmp_path, args, field):
    out = tmp_path / "out"
    res = run("dynamics", *args, "-o", str(out))
    assert res.returncode == 2, res.stdout + res.stderr
    assert res.stderr.startswith(f"error: {field}:") and res.stderr.count("\n") == 1, res.stderr
    assert "Traceback" not in res.stderr and not out.exists()


# ---- build with the dynamics: report.json = HTML ---------------------------------------------------
class Cells(HTMLParser):
    """data-key cells (and spans) of the HTML: key → (data-value, text)."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.cells, self._key, self._attrs, self._text = {}, None, None, []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "data-key" in a and tag in ("td", "span"):
            self._key, self._attrs, self._text = a["data-key"], a, []

    def handle_endtag(self, tag):
        if self._key is not None and tag in ("td", "span"):
            self.cells[self._key] = (self._attrs.get("data-value"), "".join(self._text))
            self._key = None

    def handle_data(self, data):
        if self._key is not None:
            self._text.append(data)


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    out = tmp_path_factory.mktemp("built") / "out"
    res = run("build", "--plots", "--set", "dynamics.enabled=true", *STIFF, "--set", "dynamics.speed_rpm=700",
              "-o", str(out))
    assert res.returncode == 0, res.stderr
    return out, res


@requires_ocp
def test_build_report_html_shows_report_json_dynamics(built):
    out, res = built
    report = json.loads((out / "report.json").read_text())
    d = report["dynamics"]
    assert "plot_dynamics.png" in report["files"]["plots"] and "plot_jump_speed.png" in report["files"]["plots"]
    p = Cells()
    p.feed((out / "report.html").read_text(encoding="utf-8"))
    keys = [k for k in p.cells if k.startswith("dynamics.")]
    assert len(keys) >= 40
    for key in keys:
        value, text = p.cells[key]
        want = lookup(report, key)
        if key == "dynamics.contact.kept":
            assert value == "false" and "LEAVES the cam at 700 rpm" in text
            continue
        if isinstance(want, str):
            assert text == want, key
            continue
        assert value == ("null" if want is None else "true" if want is True else "false" if want is False
                         else repr(want)), key
        assert text == format_number(want), key
    for must in ("dynamics.contact.max_gap", "dynamics.contact.off_cam_deg", "dynamics.jump_speed.rpm",
                 "dynamics.torque.dynamic.work_per_revolution", "dynamics.residual_vibration.0.amplitude"):
        assert must in keys
    # build's own summary line says the same
    assert f"the follower LEAVES the cam for {d['contact']['off_cam_deg']:.4g}°" in res.stdout
    assert f"jump speed {d['jump_speed']['rpm']:.5g} rpm" in res.stdout


@requires_ocp
def test_dynamics_command_merges_into_a_build_of_the_same_cam(built, tmp_path):
    import shutil

    src, _res = built
    out = tmp_path / "out"
    shutil.copytree(src, out)
    before = json.loads((out / "report.json").read_text())
    res = run("dynamics", *STIFF, "--speed", "650", "-o", str(out))
    assert res.returncode == 0, res.stderr                   # below the jump speed
    after = json.loads((out / "report.json").read_text())
    assert after["pitch"] == before["pitch"] and after["files"] == before["files"]
    assert after["dynamics"]["speed_rpm"] == pytest.approx(650.0) and after["dynamics"]["contact"]["kept"]
    names = {p.name for p in out.iterdir()}
    assert {"cam.step", "report.html", "dynamics.csv", "plot_dynamics.png"} <= names


def test_the_dynamics_stage_runs_only_when_asked(monkeypatch):
    import cam_workbench.generators.dynamics as dyn
    from cam_workbench.pipeline import run_pipeline
    from cam_workbench.generators.spec import default_spec

    def boom(*a, **k):
        raise AssertionError("dynamics analysed though not asked for")

    monkeypatch.setattr(dyn, "analyse_dynamics", boom)
    out = run_pipeline(default_spec().replace(**{"dynamics.stiffness": 100.0}), solid=False, machining=False,
                       drawing=False)
    assert "dynamics" not in out.summary and "dynamics" not in out.extra


# ---- the ecam command -----------------------------------------------------------------------------
@pytest.mark.parametrize("fmt, table, suffix", [("csv", "points", ".csv"), ("codesys", "xyva", ".st"),
                                                ("codesys", "poly5", ".st"), ("beckhoff", "motion_function", ".st"),
                                                ("beckhoff", "position_table", ".st"), ("lenze", "points", ".txt")])
def test_ecam_command_writes_the_table_and_prints_its_deviation(tmp_path, fmt, table, suffix):
    from cam_workbench.exporters.ecam import ecam_table
    from cam_workbench.generators.spec import default_spec

    from cam_workbench.commands.ecam_cmd import describe

    path = tmp_path / f"cam{suffix}"
    res = run("ecam", "--format", fmt, "--table", table, "--step", "2.5", "-o", str(path))
    assert res.returncode == 0, res.stderr
    api = ecam_table(default_spec(), fmt, table=table, step=2.5)
    assert path.read_text() == api.text
    assert res.stdout == describe(api.summary()) + f"\nwritten to {path}\n"
    res = run("ecam", "--format", fmt, "--table", table, "--step", "2.5", "--json")
    assert res.returncode == 0 and res.stdout == api.text
    assert json.loads(res.stderr) == json.loads(json.dumps(api.summary()))


@pytest.mark.parametrize("args, field", [
    (["--format", "csv", "--table", "poly5"], "ecam.table"),
    (["--format", "codesys", "--step", "0"], "ecam.step"),
    (["--format", "codesys", "--step", "0.005"], "ecam.step"),
    (["--format", "beckhoff", "--name", "two words"], "ecam.name"),
    (["--set", "ecam.boundaries=maybe"], "ecam.boundaries"),
])
def test_ecam_bad_input_exits_2_writes_nothing(tmp_path, args, field):
    path = tmp_path / "sub" / "cam.st"
    res = run("ecam", *args, "-o", str(path))
    assert res.returncode == 2, res.stdout + res.stderr
    assert res.stderr.startswith(f"error: {field}:") and res.stderr.count("\n") == 1, res.stderr
    assert not path.exists() and not path.parent.exists()

"""The command line for machining: `build` also writes cam.nc, commands.csv and the
interpolator plots (one all-or-nothing output set) and the `interpolator` section of
report.json; `gcode --mode xy|xc|csv` writes one program; bad machining input exits 2 with
the field or the cam angle and writes nothing."""
import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest

from .conftest import ROOT, requires_ocp, paper_args

CLI = [sys.executable, "-m", "cam_workbench.cli"]


def run(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([*CLI, *paper_args(args)], capture_output=True, text=True, env=env)


@requires_ocp
def test_build_writes_machining_files_and_report(tmp_path):
    out = tmp_path / "out"
    res = run("build", "--plots", "-o", str(out), "--set", "machining.program=xc")
    assert res.returncode == 0, res.stderr
    names = sorted(p.name for p in out.iterdir())
    assert {"cam.step", "cam.dxf", "report.json", "report.html", "cam.nc", "commands.csv",
            "plot_interpolator_deviation.png", "plot_interpolator_kinematics.png"} <= set(names)
    report = json.loads((out / "report.json").read_text())
    listed = [v for v in report["files"].values() if isinstance(v, str)]
    listed += [x for v in report["files"].values() if isinstance(v, list) for x in v]
    # report.json lists exactly the files written, beside the folder's manifest
    assert sorted(listed + [".cam-workbench.json"]) == names
    it = report["interpolator"]
    assert it["commands"] == 1000 and it["sample_period"] == 0.001 and it["differencing"] == "backward"
    assert it["max_deviation"] == pytest.approx(1.494e-4, rel=1e-3)          # default cam = paper case 2
    assert it["acceleration"]["max"] == pytest.approx(1144.2, abs=0.1)
    assert it["jerk"]["max"] == pytest.approx(23681, abs=1)
    m = report["machining"]
    assert m["program"] == "xc" and m["xc"]["blocks"] == 1000 and m["xc"]["x_from_commands"]
    assert report["files"]["gcode"] == "cam.nc" and report["files"]["commands"] == "commands.csv"
    nc = (out / "cam.nc").read_text()
    assert nc.startswith("%\n") and nc.endswith("M30\n%\n") and "G93" in nc
    rows = (out / "commands.csv").read_text().splitlines()
    assert len(rows) == 1001
    for png in ("plot_interpolator_deviation.png", "plot_interpolator_kinematics.png"):
        assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("mode,marker", [("xy", "G2 X"), ("xc", "G93"), ("csv", "k,t_s,theta_deg")])
def test_gcode_command_to_stdout(mode, marker):
    res = run("gcode", "--mode", mode)
    assert res.returncode == 0, res.stderr
    assert marker in res.stdout


def test_gcode_command_to_file_with_spec_and_overrides(tmp_path):
    spec = tmp_path / "cam.toml"
    spec.write_text(run("spec", "--default").stdout)
    out = tmp_path / "cam_xc.nc"
    res = run("gcode", str(spec), "--mode", "xc", "-o", str(out), "--set", "machining.line_numbers=true",
              "--set", "machining.rotary_line=axis")
    assert res.returncode == 0, res.stderr
    text = out.read_text()
    assert "N10 " in text and "G93" in text and " Y" not in text.split("G93", 1)[1]


BAD = [
    (["--set", "machining.tool_radius=70"], "would gouge the profile at cam angle"),
    (["--set", "machining.sample_period=1e-10"], "machining.sample_period: must be ≥ 1e-06"),
    (["--set", "machining.sample_period=1e-6", "--set", "cam.speed_rpm=1"],
     "machining.sample_period: gives 6e+07 commands per revolution"),
    (["--set", "machining.contour=spline"], "machining.contour: must be one of"),
    (["--set", "machining.chord_tolerance=0.00001", "--set", "machining.sample_period=0.0025",
      "--set", "machining.program=xc"], "machining.rotary_speed_rpm: at 60 rpm (cam.speed_rpm; "
                                        "machining.rotary_speed_rpm is not given) and machining.sample_period 0.0025 s "
                                        "the XC blocks of 0.9° deviate"),
]


@pytest.mark.parametrize("args,message", BAD)
def test_bad_machining_input_exit_2_writes_nothing(tmp_path, args, message):
    out = tmp_path / "out"
    res = run("build", *args, "-o", str(out))
    assert res.returncode == 2, res.stderr
    assert message in res.stderr and "Traceback" not in res.stderr
    assert not out.exists()
    f = tmp_path / "x.nc"
    mode = "xc" if "machining.program=xc" in args else "xy"
    res = run("gcode", "--mode", mode, *args, "-o", str(f))
    assert res.returncode == 2 and message in res.stderr
    assert not f.exists()


def test_gcode_help_lists_the_modes():
    res = run("gcode", "--help")
    assert res.returncode == 0
    for word in ("xy", "xc", "csv", "G93", "chord_tolerance"):
        assert word in res.stdout
    assert np.all([w in run("--help").stdout for w in ("build", "gcode", "spec")])


def test_docs_machining_commands_run(tmp_path):
    """The `cam-workbench gcode` lines of docs/machining.md run as written."""
    import re

    section = (ROOT / "docs" / "machining.md").read_text(encoding="utf-8")
    lines = [ln.split("#")[0].strip() for ln in section.splitlines() if ln.startswith("cam-workbench gcode")]
    assert len(lines) == 3
    (tmp_path / "cam.toml").write_text(run("spec", "--default").stdout)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    for line in lines:
        cmd = re.sub(r"^cam-workbench", f"{sys.executable} -m cam_workbench.cli", line)
        res = subprocess.run(cmd, shell=True, cwd=tmp_path, capture_output=True, text=True, env=env)
        assert res.returncode == 0, (line, res.stderr)
    assert (tmp_path / "cam_xy.nc").exists() and (tmp_path / "cam_xc.nc").exists()
    assert (tmp_path / "commands.csv").read_text().startswith("k,t_s,")


def test_xc_refusal_names_the_speed_that_passes(tmp_path):
    """An XC program of the packaging example at 300 rpm is refused naming
    machining.rotary_speed_rpm (exit 2, one line, nothing written) with a speed and a period
    that pass: with either set, the same command writes the program.  docs/machining.md quotes the
    message as it is."""
    from .combinations.test_cli_combinations import assert_clean

    out = tmp_path / "out"
    res = run("build", "--example", "packaging", "--set", "cam.speed_rpm=300", "--set", "machining.program=xc",
              "-o", str(out))
    assert_clean(res, (2,))
    assert not out.exists()
    message = res.stderr.strip()
    assert message.startswith("error: machining.rotary_speed_rpm: at 300 rpm (cam.speed_rpm;"), message
    assert message[len("error: "):] in (ROOT / "docs" / "machining.md").read_text(encoding="utf-8").replace("\n", " ")
    m = re.search(r"machining\.rotary_speed_rpm = ([0-9.]+) .* or machining\.sample_period = ([0-9.e-]+): either "
                  r"passes$", message)
    assert m, message
    for fix in (f"machining.rotary_speed_rpm={m.group(1)}", f"machining.sample_period={m.group(2)}"):
        f = tmp_path / f"{fix.split('=')[0]}.nc"
        ok = run("gcode", "--example", "packaging", "--set", "cam.speed_rpm=300", "--mode", "xc", "--set", fix,
                 "-o", str(f))
        assert ok.returncode == 0 and "G93" in f.read_text(), (fix, ok.stderr)

"""`cam-workbench check`: the table, report.json's checks section (merged into a build's report
of the same spec), exit 3 on a failed check, 0 when all pass, 2 on bad input with nothing
written; `build` includes the checks and the areas too."""
import json

import pytest

from .conftest import ROOT, requires_ocp
from .test_cli import run

EX5 = str(ROOT / "tests" / "fixtures" / "thesis_ex5_final.toml")


def test_check_fails_with_exit_3_and_writes_the_section(tmp_path):
    out = tmp_path / "out"
    res = run("check", EX5, "-o", str(out))
    assert res.returncode == 3, res.stderr
    for word in ("pressure_angle", "separation", "oscillation", "contact_stress", "curvature", "undercut",
                 "fail", "-1.162 lbf", "120.464°", "55.4806 in²"):
        assert word in res.stdout, word
    report = json.loads((out / "report.json").read_text())
    ck = report["checks"]
    assert ck["passed"] is False and ck["failed"] == ["separation"]
    assert ck["results"]["separation"]["value"] == pytest.approx(-1.162, abs=2e-3)
    assert ck["results"]["pressure_angle"]["limit"] == 18.0
    assert ck["sampling"] == "dense" and ck["samples_per_segment"] == 1001
    assert report["areas"]["thesis_eq_4_21"] == pytest.approx(55.4806, abs=1e-4)
    assert sorted(p.name for p in out.iterdir()) == [".cam-workbench.json", "report.json"]  # + the manifest


def test_check_passes_with_exit_0_and_thesis_nodes(tmp_path):
    out = tmp_path / "out"
    res = run("check", EX5, "--set", "follower.preload=345", "--sampling", "thesis71", "-o", str(out))
    assert res.returncode == 0, res.stdout + res.stderr
    assert "all checks pass" in res.stdout and "71 nodes" in res.stdout
    ck = json.loads((out / "report.json").read_text())["checks"]
    assert ck["passed"] and ck["sampling"] == "thesis71"
    assert ck["extremes"]["reduced_velocity"]["at_deg"] == pytest.approx(88.806, abs=1e-3)


@requires_ocp
def test_build_includes_checks_and_check_merges_into_it(tmp_path):
    out = tmp_path / "out"
    res = run("build", EX5, "-o", str(out))
    assert res.returncode == 0, res.stderr          # a failed design check does not stop a build
    assert "design checks: FAILED separation" in res.stdout
    built = json.loads((out / "report.json").read_text())
    assert built["checks"]["failed"] == ["separation"]
    assert built["areas"]["thesis_eq_4_21"] == pytest.approx(55.4806, abs=1e-4)
    assert built["areas"]["built_cross_section"] == pytest.approx(built["solid"]["cross_section_area"], rel=1e-9)
    assert built["solid"]["cross_section_area"] == pytest.approx(built["areas"]["cross_section"], rel=2e-5)
    # check with the same spec keeps the build's report and replaces its checks
    res = run("check", EX5, "--sampling", "thesis71", "-o", str(out))
    assert res.returncode == 3
    merged = json.loads((out / "report.json").read_text())
    assert merged["pitch"] == built["pitch"] and merged["files"] == built["files"]
    assert merged["checks"]["sampling"] == "thesis71"
    # a different spec of the same file: report.json alone would contradict the build's other
    # files — refused, nothing changed; with --replace a fresh report of that cam (the numbers
    # `build` would give it), and the folder holds that cam's set only, never mixed
    res = run("check", EX5, "--set", "follower.preload=345", "-o", str(out))
    assert res.returncode == 2 and "follower.preload" in res.stderr and "--replace" in res.stderr
    assert json.loads((out / "report.json").read_text()) == merged and (out / "cam.step").exists()
    res = run("check", EX5, "--set", "follower.preload=345", "-o", str(out), "--replace")
    assert res.returncode == 0
    fresh = json.loads((out / "report.json").read_text())
    assert fresh["spec_digest"] != built["spec_digest"] and fresh["checks"]["passed"]
    assert fresh["pitch"] == built["pitch"]          # the preload does not change the geometry
    assert not (out / "cam.step").exists()


@pytest.mark.parametrize("args,message", [
    (["--set", "checks.sampling=sparse"], "checks.sampling: must be one of"),
    (["--set", "material.allowable_stress=-1"], "material.allowable_stress: must be > 0"),
    (["--set", "motion[0].control_y=0.5"], "motion[0].control_y: must be a list of numbers"),
])
def test_check_bad_input_exit_2_writes_nothing(tmp_path, args, message):
    out = tmp_path / "out"
    res = run("check", EX5, *args, "-o", str(out))
    assert res.returncode == 2 and message in res.stderr, res.stderr
    assert "Traceback" not in res.stderr and not out.exists()


def test_check_leaves_an_existing_report_untouched_on_bad_input(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.json").write_text('{"keep": true}')
    res = run("check", EX5, "--set", "checks.samples=3", "-o", str(out))
    assert res.returncode == 2 and "checks.samples: must be ≥ 11" in res.stderr
    assert (out / "report.json").read_text() == '{"keep": true}'


def test_help_lists_check():
    res = run("--help")
    assert "check" in res.stdout
    res = run("check", "--help")
    assert res.returncode == 0 and "exit status" in res.stdout and "--sampling" in res.stdout


def test_set_accepts_lists(tmp_path):
    out = tmp_path / "out"
    res = run("check", EX5, "--set", "motion[0].control_y=[0.0772, 0.6242, 0.95]", "-o", str(out))
    assert res.returncode in (0, 3), res.stderr
    res = run("check", EX5, "--set", "motion[0].control_y=[0.1, 0.6", "-o", str(out / "x"))
    assert res.returncode == 2 and "motion[0].control_y: '[0.1, 0.6' is not a valid list" in res.stderr


def test_check_loads_no_solid_drawing_or_plot_library(tmp_path):
    """`check` designs and checks the cam with numpy and scipy: it loads neither OCP, ezdxf,
    matplotlib nor CairoSVG (issue 22 item 3), with and without -o, nor another command's module."""
    import subprocess
    import sys

    code = ("import contextlib, io, json, sys\nfrom cam_workbench.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n    status = main(json.loads(sys.argv[1]))\n"
            "print(json.dumps([status, sorted(m for m in ('OCP', 'ezdxf', 'matplotlib', 'cairosvg', "
            "'cam_workbench.commands.build', 'cam_workbench.commands.dxf_cmd') if m in sys.modules)]))\n")
    for args in (["check"], ["check", "--example", "groove", "-o", str(tmp_path / "out")]):
        res = subprocess.run([sys.executable, "-c", code, json.dumps(args)], capture_output=True, text=True, cwd=ROOT)
        assert res.returncode == 0, res.stderr
        assert json.loads(res.stdout.strip().splitlines()[-1]) == [0, []], args
    assert json.loads((tmp_path / "out" / "report.json").read_text())["checks"]["passed"] is True

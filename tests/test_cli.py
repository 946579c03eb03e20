"""The command line: build writes STEP and report.json; bad input exits 2 with a message,
no traceback, and writes nothing (no folder created, existing files untouched)."""
import json
import re
import os
import subprocess
import sys
from pathlib import Path

import pytest

from .conftest import ROOT, requires_ocp, paper_args
from .test_spec import RULES as SPEC_RULES

CLI = [sys.executable, "-m", "cam_workbench.cli"]


def run(*args, cwd=None):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([*CLI, *paper_args(args)], capture_output=True, text=True, cwd=cwd, env=env)


@requires_ocp
def test_build_default(tmp_path):
    out = tmp_path / "out"
    res = run("build", "-o", str(out))
    assert res.returncode == 0, res.stderr
    report = json.loads((out / "report.json").read_text())
    for key in ("units", "pitch", "pressure_angle", "curvature", "area", "volume", "files"):
        assert key in report
    assert report["pitch"]["segments"] == 60 and report["pitch"]["representation"] == "ph"
    assert report["pitch"]["max_deviation"] < 2e-4
    assert report["files"]["step"] == "cam.step"
    assert (out / "cam.step").read_text().startswith("ISO-10303-21")
    assert report["solid"]["valid"] and report["solid"]["solids"] == 1
    assert report["solid"]["cross_section_area"] == pytest.approx(report["area"], rel=1e-9)
    assert report["volume"] == pytest.approx(report["area"] * 10.0)


def test_help_reads_well():
    res = run("--help")
    assert res.returncode == 0 and "build" in res.stdout and "exit status" in res.stdout
    res = run("build", "--help")
    assert res.returncode == 0 and "--set" in res.stdout and "SPEC" in res.stdout


def test_spec_command_prints_reference_and_default(tmp_path):
    res = run("spec")
    assert "cam.base_radius" in res.stdout or "`base_radius`" in res.stdout
    res = run("spec", "--default")
    p = tmp_path / "d.toml"
    p.write_text(res.stdout)
    from cam_workbench.generators import default_spec, load_spec

    assert load_spec(p) == default_spec()


BAD = [
    (["--set", "cam.base_radius=5"], "follower.offset"),
    (["--set", "motion[4].angle=20"], "motion[4].angle: spans sum to 350°, must be 360°"),
    (["--set", "cam.colour=red"], "cam.colour: unknown field"),
    (["--set", "follower.roller_radius=25"], "cam.base_radius"),
    (["--set", "cam.bore_diameter=35"], "cam.bore_diameter: must be < 2 × smallest cam-surface radius"),
    # passes the spec rule (< 2·17.360680) but the built profile dips 0.04 µm inside the
    # base circle in the dwell (PH interpolation), so the bore would cut it
    (["--set", "cam.bore_diameter=34.72135"], "the bore (radius 17.3607) cuts the profile at cam angle"),
]


@pytest.mark.parametrize("args,message", BAD)
def test_bad_input_exit_2_writes_nothing(tmp_path, args, message):
    out = tmp_path / "out"
    res = run("build", *args, "-o", str(out))
    assert res.returncode == 2
    assert message in res.stderr
    assert "Traceback" not in res.stderr
    assert not out.exists()


def test_bad_input_leaves_existing_files_untouched(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "cam.step").write_text("previous")
    (out / "report.json").write_text("{}")
    bad = tmp_path / "bad.toml"
    bad.write_text('units = "mm"\n[cam]\nbase_radius = 30\nthickness = 5\n[follower]\nkind = "knife"\n'
                   '[[motion]]\nkind = "rise"\nangle = 180\nlift = 5\nlaw = "cycloidal"\n'
                   '[[motion]]\nkind = "return"\nangle = 170\nlift = 5\nlaw = "cycloidal"\n')
    res = run("build", str(bad), "-o", str(out))
    assert res.returncode == 2 and "motion[1].angle: spans sum to 350°" in res.stderr
    assert (out / "cam.step").read_text() == "previous"
    assert (out / "report.json").read_text() == "{}"
    assert sorted(p.name for p in out.iterdir()) == ["cam.step", "report.json"]


def test_missing_spec_file(tmp_path):
    res = run("build", str(tmp_path / "none.toml"), "-o", str(tmp_path / "o"))
    assert res.returncode == 2 and "file not found" in res.stderr


def test_undercut_reported_with_cam_angle(tmp_path):
    """The default cam's smallest convex pitch radius is 21.06 mm, at the end of the rise
    (≈111°–114°), so a 22 mm roller undercuts there."""
    res = run("build", "--set", "follower.roller_radius=22", "--set", "cam.bore_diameter=0",
              "-o", str(tmp_path / "o"))
    assert res.returncode == 2
    m = re.search(r"undercut at cam angle ([0-9.]+)°", res.stderr)
    assert m, res.stderr
    assert 105 < float(m.group(1)) < 120
    assert "Traceback" not in res.stderr
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("rule", SPEC_RULES, ids=[r[0] for r in SPEC_RULES])
def test_every_spec_rule_through_the_cli(tmp_path, capsys, rule):
    """Each validation rule of test_spec.RULES, written as a TOML file and given to
    `cam-workbench build`: exit 2, `field: rule` on stderr, no traceback, nothing written."""
    from cam_workbench.cli import main
    from cam_workbench.generators.spec import dict_to_toml

    from .test_spec import mutate

    _, fn, field, words = rule
    spec_path = tmp_path / "bad.toml"
    spec_path.write_text(dict_to_toml(mutate(fn)))
    out = tmp_path / "out"
    rc = main(["build", str(spec_path), "-o", str(out)])
    err = capsys.readouterr().err
    assert rc == 2
    assert f"{field}:" in err and words in err
    assert "Traceback" not in err
    assert not out.exists()


#: what a parse loads before a command runs: nothing of these (issue 22 item 3)
HEAVY = ("numpy", "scipy", "rich", "cam_workbench.generators", "cam_workbench.exporters",
         "cam_workbench.commands.dispatch", "cam_workbench.commands.common", "cam_workbench.commands.build")


def _parse_only(arg_lists: list[list[str]]) -> list[tuple[int, list[str], str]]:
    """(exit status, the HEAVY modules loaded, what was printed) of ``main(args)`` for each
    argument list, each in a fresh interpreter."""
    code = ("import contextlib, io, json, sys\nfrom cam_workbench.cli import main\nout = io.StringIO()\n"
            "with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):\n"
            "    status = main(json.loads(sys.argv[1]))\n"
            f"loaded = [m for m in {HEAVY!r} if m in sys.modules]\n"
            "print(json.dumps([status, loaded, out.getvalue()]))\n")
    found = []
    for args in arg_lists:
        res = subprocess.run([sys.executable, "-c", code, json.dumps(args)], capture_output=True, text=True,
                             cwd=ROOT)
        assert res.returncode == 0, res.stderr
        status, loaded, text = json.loads(res.stdout.strip().splitlines()[-1])
        found.append((status, loaded, text))
    return found


def test_help_and_argument_errors_load_no_command():
    """``--help``, ``--version``, a missing command, every command's ``--help`` and an argument
    error (an unknown option, a missing value, a choice not offered, a missing sub-action) are
    answered by the parser alone (issue 22 item 3): neither numpy, scipy, rich nor any module of
    the generators or of a command is loaded; the statuses are argparse's (0 help, 2 error)."""
    from cam_workbench.commands import CATALOGUE

    cases = [(["--help"], 0, "usage: cam-workbench"), (["--version"], 0, "cam-workbench 0.1.0"),
             ([], 2, "required: COMMAND"), (["nosuch"], 2, "invalid choice: 'nosuch'")]
    cases += [([name, "--help"], 0, f"usage: cam-workbench {name}") for name in CATALOGUE]
    cases += [(["optimize", "--help"], 0, "usage: cam-workbench optimise"),
              (["freecad", "install", "--help"], 0, "--mod-dir"),
              (["check", "--bogus"], 2, "unrecognized arguments: --bogus"),
              (["build", "-o"], 2, "argument -o/--output: expected one argument"),
              (["build", "--set"], 2, "argument --set: expected one argument"),
              (["ecam", "--format", "nope"], 2, "argument --format: invalid choice: 'nope'"),
              (["dxf", "--curves", "bezier"], 2, "argument --curves: invalid choice: 'bezier'"),
              (["gcode", "--mode", "xz"], 2, "argument --mode: invalid choice: 'xz'"),
              (["dynamics", "--speed", "fast"], 2, "argument --speed: invalid float value: 'fast'"),
              (["optimise", "--objective", "beauty"], 2, "argument --objective: invalid choice: 'beauty'"),
              (["sweep", "--size", "thickness"], 2, "argument --size: invalid choice: 'thickness'"),
              (["freecad"], 2, "required: {install,uninstall}")]
    for (args, status, text), (got, loaded, printed) in zip(cases, _parse_only([c[0] for c in cases])):
        assert (got, loaded) == (status, []), (args, printed)
        assert text in printed, (args, printed)


def test_the_parsers_choices_are_the_specs():
    """The choices and texts the parser holds without loading the generators
    (:mod:`cam_workbench.commands.parsers`) are the spec's declarations: the examples and their
    descriptions, the e-cam formats and tables, the optimiser's objectives and algorithms, the
    drawing's fields that ``dxf`` overrides."""
    from cam_workbench.cli import build_parser
    from cam_workbench.generators.spec import (DrawingSection, ECAM_TABLES, OBJECTIVES, OPTIMISE_ALGORITHMS,
                                               params_of)
    from cam_workbench.generators.spec.examples import DESCRIPTIONS, EXAMPLES

    commands = next(a for a in build_parser()._actions if a.dest == "command").choices

    def option(command: str, flag: str):
        return next(a for a in commands[command]._actions if flag in a.option_strings)

    for name in ("build", "check", "gcode", "dxf", "report", "dynamics", "ecam", "optimise", "sweep"):
        help_text = option(name, "--example").help
        assert all(f"'{n}' ({d})" in help_text for n, d in DESCRIPTIONS.items()), name
    assert f"one of {', '.join(EXAMPLES)} (" in option("spec", "--example").help
    assert option("ecam", "--format").choices == tuple(ECAM_TABLES)
    assert option("ecam", "--table").choices == ("auto", *sorted({t for ts in ECAM_TABLES.values() for t in ts}))
    assert option("optimise", "--objective").choices == OBJECTIVES
    assert option("optimise", "--algorithm").choices == OPTIMISE_ALGORITHMS
    drawing = params_of(DrawingSection)
    for flag, field in (("--curves", "curves"), ("--tolerance", "chord_tolerance"), ("--dxf-version", "dxf_version")):
        assert option("dxf", flag).choices == drawing[field].choices, flag
        assert option("dxf", flag).help.startswith(drawing[field].doc), flag
        assert f"the spec's drawing.{field})" in option("dxf", flag).help, flag


def test_a_command_loads_its_own_module_alone():
    """Every command of the catalogue has its parser and its runner, in the catalogue's order;
    a command runs with its own module loaded, not every command's: ``spec --default`` loads
    neither ``build``'s nor the studies' modules."""
    from cam_workbench.commands import CATALOGUE, dispatch, parsers

    assert list(parsers.PARSERS) == list(dispatch.RUNNERS) == list(CATALOGUE)
    code = ("import contextlib, io, sys\nfrom cam_workbench.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n    status = main(['spec', '--default'])\n"
            "print(status, sorted(m for m in sys.modules if m.startswith('cam_workbench.commands.')))\n")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip().splitlines()[-1] == (
        "0 ['cam_workbench.commands.dispatch', 'cam_workbench.commands.parsers', 'cam_workbench.commands.spec_cmd']")


def test_the_package_version_is_the_generators():
    """``cam-workbench --version`` reads ``cam_workbench.__version__`` (light); the report and the
    drawings quote the generators' — one version."""
    import cam_workbench
    from cam_workbench.generators import __version__

    assert cam_workbench.__version__ == __version__

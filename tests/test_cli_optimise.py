"""``cam-workbench optimise``: the optimised spec, report.json's optimise section (the shape the
HTML report draws its convergence figure from), report.html, exit statuses 0 / 2 / 3."""
import json
from html.parser import HTMLParser

import pytest

from cam_workbench.generators import load_spec
from cam_workbench.generators.checks.areas import thesis_area

from .conftest import ROOT, requires_ocp
from .test_cli import run

EX5 = str(ROOT / "tests" / "fixtures" / "thesis_ex5_initial.toml")


def _paper_spec(folder) -> str:
    """The paper's Table 1 cam, case 2, as a spec file (independent of the built-in default)."""
    from .test_optimiser import PAPER_CASE_2

    from cam_workbench.generators.spec import to_toml
    path = folder / "paper.toml"
    path.write_text(to_toml(load_spec(PAPER_CASE_2)))
    return str(path)


def _assert_prints_the_reports_status(stdout: str, opt: dict) -> None:
    """The status and message lines are report.json's own text; the status says in words whether
    every check passes, then how the run ended (nlopt's own words)."""
    lines = stdout.splitlines()
    assert f"status: {opt['status_text']}" in lines
    assert f"message: {opt['message']}" in lines
    verdict = "every check passes — " if opt["feasible"] else f"the result FAILS {opt['failed_checks']} — "
    assert opt["status_text"].startswith(verdict)
    how = opt["status_text"][len(verdict):]
    assert how.startswith({"converged": "converged", "stopped": "nlopt stopped: ", "infeasible": "nlopt: ",
                           "budget exhausted": "the budget of", "cancelled": "cancelled"}[opt["status"]])
    assert opt["solver_status"] in how
    assert "converged" not in stdout or opt["status"] == "converged"


class _Ids(HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids = set()

    def handle_starttag(self, tag, attrs):
        d = dict(attrs)
        if "id" in d:
            self.ids.add(d["id"])


@requires_ocp
def test_optimise_example5_writes_spec_report_and_plots(tmp_path):
    out = tmp_path / "opt"
    res = run("optimise", EX5, "--plots", "--set", "checks.convex=true", "-o", str(out))
    assert res.returncode == 0, res.stderr
    names = {p.name for p in out.iterdir()}
    assert {"optimised.toml", "report.json", "report.html", "plot_convergence.png", "plot_cam.png"} <= names
    spec = load_spec(out / "optimised.toml")
    rep = json.loads((out / "report.json").read_text())
    opt = rep["optimise"]
    assert opt["objective"] == "area" and opt["feasible"] is True
    # SLSQP ends this run "roundoff limited" at its best point (nlopt's own words): an honest
    # "stopped", never relabelled "converged" — and a result that passes every check says so first
    assert opt["status"] == "converged" or (opt["status"] == "stopped" and "roundoff limited" in opt["message"])
    if opt["status"] == "stopped":
        assert opt["status_text"] == f"every check passes — nlopt stopped: {opt['solver_status']}"
        assert "roundoff limited" in opt["status_text"]
    assert "follower.offset" not in [v["name"] for v in opt["variables"]]     # "auto" holds the offset
    assert opt["final_value"] == pytest.approx(thesis_area(spec), rel=1e-12)
    assert opt["final_value"] < 55.48 < opt["initial_value"]
    assert rep["areas"]["thesis_eq_4_21"] == pytest.approx(opt["final_value"], rel=1e-9)
    hist = opt["history"]
    assert hist and all({"iteration", "objective", "max_violation"} <= set(h) for h in hist)
    assert rep["checks"]["passed"] is True
    assert rep["files"]["spec"] == "optimised.toml"
    page = _Ids()
    page.feed((out / "report.html").read_text())
    assert {"optimise", "fig-convergence", "checks"} <= page.ids
    assert ("objective area (thesis Eq. 4.21 area ½∮(R_b + s)² dθ, report.json areas.thesis_eq_4_21): 78.1477 → 21.3"
            in res.stdout and "every design check passes" in res.stdout)
    _assert_prints_the_reports_status(res.stdout, opt)
    # the thesis' initial design lets the follower leave the cam (separation −696 lbf)
    assert opt["initial_feasible"] is False and [v["name"] for v in opt["initial_violations"]] == ["separation"]
    sep = opt["initial_violations"][0]
    assert f"start infeasible: separation = {sep['value']:.6g} lbf at {sep['at_deg']:.2f}° (limit 0 lbf)" in res.stdout


def test_bad_settings_exit_2_and_write_nothing(tmp_path):
    out = tmp_path / "never"
    res = run("optimise", EX5, "--variables", "radius", "-o", str(out))
    assert res.returncode == 2
    assert "optimise.variables: unknown design variable 'radius'" in res.stderr
    assert "Traceback" not in res.stderr and not out.exists()
    res = run("optimise", "--objective", "machining_time", "--algorithm", "slsqp", "-o", str(out))
    assert res.returncode == 2 and "optimise.algorithm" in res.stderr and not out.exists()


@requires_ocp
def test_infeasible_result_exit_3_with_the_report(tmp_path):
    """R_b capped below what a 30° pressure angle needs (42.8 mm): the best design still fails;
    the files are written and say so, the exit status is 3."""
    out = tmp_path / "inf"
    paper = _paper_spec(tmp_path)
    res = run("optimise", paper, "--variables", "base_radius", "--set", "optimise.base_radius_max=35",
              "-o", str(out))
    assert res.returncode == 3, res.stderr
    rep = json.loads((out / "report.json").read_text())
    assert rep["optimise"]["feasible"] is False and "pressure_angle" in rep["optimise"]["failed_checks"]
    assert rep["optimise"]["status"] == "infeasible"
    assert load_spec(out / "optimised.toml").cam.base_radius == pytest.approx(35.0)
    assert "FAILS the dense check: pressure_angle" in res.stdout


@requires_ocp
def test_infeasible_start_is_kept_and_said(tmp_path):
    """The user's e = 10 mm is the start (not clipped to a default bound), the run says the start
    was infeasible with the check, value and limit, and prints report.json's status and message."""
    out = tmp_path / "opt"
    res = run("optimise", _paper_spec(tmp_path), "--variables", "base_radius,offset", "-o", str(out))
    assert res.returncode == 0, res.stderr
    opt = json.loads((out / "report.json").read_text())["optimise"]
    assert opt["variables"][1] == {"name": "follower.offset", "initial": 10.0, "final": opt["variables"][1]["final"]}
    _assert_prints_the_reports_status(res.stdout, opt)
    (v,) = opt["initial_violations"]
    assert v["name"] == "pressure_angle" and 46.2 < v["value"] < 46.3
    assert f"start infeasible: pressure_angle = {v['value']:.6g} deg at {v['at_deg']:.2f}° (limit 30 deg)" in res.stdout


def test_a_bound_that_excludes_the_start_is_refused(tmp_path):
    out = tmp_path / "never"
    res = run("optimise", _paper_spec(tmp_path), "--variables", "base_radius,offset",
              "--set", "optimise.offset_max=5", "-o", str(out))
    assert res.returncode == 2
    assert "optimise.offset_max: must be ≥ |follower.offset| of the starting design (10 mm), got 5" in res.stderr
    assert "Traceback" not in res.stderr and not out.exists()


# ---- other follower kinds (issue 13) -------------------------------------------------------------
def _oscillating_spec(folder) -> str:
    """An oscillating roller (pivot 60 mm, arm 45 mm, 15° cycloidal lifts) as a spec file."""
    from cam_workbench.generators.spec import CamSpec, to_toml

    from .test_optimiser_followers import oscillating_roller

    path = folder / "osc.toml"
    path.write_text(to_toml(CamSpec.from_dict(oscillating_roller())))
    return str(path)


@requires_ocp
def test_optimise_an_oscillating_roller(tmp_path):
    """R_b, pivot distance and arm length (named: "auto" holds the arm): exit 0, every number printed
    is report.json's, the objective is the exact area inside the pitch curve (report.json's
    areas.pitch_curve), the optimised spec holds the final design and passes the checks."""
    out = tmp_path / "opt"
    res = run("optimise", _oscillating_spec(tmp_path), "--variables", "base_radius,pivot_distance,arm_length",
              "-o", str(out))
    assert res.returncode == 0, res.stderr
    rep = json.loads((out / "report.json").read_text())
    opt = rep["optimise"]
    _assert_prints_the_reports_status(res.stdout, opt)
    assert opt["feasible"] is True and rep["checks"]["passed"] is True
    assert "design curve" in opt["objective_description"]
    assert opt["objective_key"] == "areas.pitch_curve" and opt["objective_label"] == "area inside the pitch curve"
    assert (f"objective area (area inside the pitch curve, report.json areas.pitch_curve): {opt['initial_value']:.6g} → "
            f"{opt['final_value']:.6g} mm²") in res.stdout
    assert opt["final_value"] < opt["initial_value"]
    assert rep["areas"]["pitch_curve"] == pytest.approx(opt["final_value"], rel=1e-9)
    assert rep["areas"]["thesis_eq_4_21"] is None
    spec = load_spec(out / "optimised.toml")
    got = {"cam.base_radius": spec.cam.base_radius, "follower.pivot_distance": spec.follower.pivot_distance,
           "follower.arm_length": spec.follower.arm_length}
    assert [v["name"] for v in opt["variables"]] == list(got)
    for v in opt["variables"]:
        assert v["final"] == got[v["name"]]
        assert f"  {v['name']:28s} {v['initial']:12.6g} → {v['final']:12.6g}" in res.stdout
    w = opt["worst_constraint"]
    assert (f"closest to its limit: {w['name']} = {w['value']:.6g} {w['unit']} at {w['at_deg']:.2f}° "
            f"(limit {w['limit']:.6g})") in res.stdout


@pytest.mark.parametrize("args, field, words", [
    (["--variables", "base_radius,offset"], "optimise.variables", "offset applies to translating followers only"),
    (["--variables", "face_offset"], "optimise.variables", "face_offset applies to oscillating flat faces only"),
    (["--objective", "machining_time"], "optimise.objective", "use gcode_time"),
    (["--variables", "base_radius,arm_length", "--set", "optimise.arm_length_max=40"], "optimise.arm_length_max",
     "must be ≥ follower.arm_length of the starting design (45 mm), got 40"),
])
def test_bad_variables_for_an_oscillating_follower_exit_2(tmp_path, args, field, words):
    out = tmp_path / "never"
    res = run("optimise", _oscillating_spec(tmp_path), *args, "-o", str(out))
    assert res.returncode == 2, res.stdout
    assert f"{field}: " in res.stderr and words in res.stderr
    assert "Traceback" not in res.stderr and not out.exists()


def test_oscillating_variables_on_a_translating_follower_exit_2(tmp_path):
    out = tmp_path / "never"
    res = run("optimise", _paper_spec(tmp_path), "--variables", "base_radius,pivot_distance", "-o", str(out))
    assert res.returncode == 2
    assert "optimise.variables: pivot_distance applies to oscillating followers only" in res.stderr
    assert "Traceback" not in res.stderr and not out.exists()

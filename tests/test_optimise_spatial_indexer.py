"""The barrel and globoidal indexers' optimiser (generators/optimise/spatial_indexer.py) through the
library entry the CLI uses: objective "size" on each example returns a spec whose design (designed
again here by the body) passes every check and whose cam is smaller than the start's, its variables
within the bounds and the turret's lengths scaled with its size; ``cam-workbench optimise --example
barrel_indexer`` exits 0 and writes the optimised spec, report.json (its optimise section) and the
cam's files; settings that do not apply exit 2 naming the field.  Small budgets keep it short.

Measured (this budget): barrel 40 → 20 mm (the bounds stop it: R_p = 0.5·R_p₀), globoid 79.35 →
≈ 36–40 mm (the pressure angle and the contact stress stop it)."""
from __future__ import annotations

import json
import math

import pytest

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.kinds import body_of, own_optimiser
from cam_workbench.generators.optimise import optimise
from cam_workbench.generators.optimise import spatial_indexer
from cam_workbench.generators.spec.examples import BARREL_INDEXER_SPEC_DICT, GLOBOIDAL_INDEXER_SPEC_DICT
from cam_workbench.generators.spec.model import CamSpec

from .conftest import requires_ocp
from .test_cli import run

BUDGET = {"barrel_indexer": 12, "globoidal_indexer": 14}
EXAMPLES = {"barrel_indexer": BARREL_INDEXER_SPEC_DICT, "globoidal_indexer": GLOBOIDAL_INDEXER_SPEC_DICT}
TURRET = {"barrel_indexer": "indexer.pitch_radius", "globoidal_indexer": "indexer.roller_end"}
#: the turret's lengths that scale with its size
SCALED = {"barrel_indexer": ("indexer.roller_start", "indexer.roller_end", "indexer.root_radius",
                             "indexer.outer_radius", "cam.thickness"),
          "globoidal_indexer": ("indexer.roller_start", "indexer.tip_radius", "indexer.root_radius", "cam.thickness")}


def _get(spec: CamSpec, path: str) -> float:
    section, name = path.split(".")
    return float(getattr(getattr(spec, section), name))


def _outer_radius(spec: CamSpec) -> float:
    """The cam's outer radius from the spec alone (the module's definition, recomputed here)."""
    if spec.cam.body == "barrel_indexer":
        return float(spec.indexer.outer_radius)
    h = 0.5 * spec.cam.thickness
    return spec.indexer.centre_distance - math.sqrt(spec.indexer.tip_radius ** 2 - h * h)


@pytest.fixture(scope="module", params=sorted(EXAMPLES))
def case(request):
    spec = CamSpec.from_dict(EXAMPLES[request.param])
    return spec, optimise(spec, objective="size", max_evaluations=BUDGET[request.param])


def test_both_bodies_have_their_own_optimiser() -> None:
    for body in EXAMPLES:
        spec = CamSpec.from_dict(EXAMPLES[body])
        assert own_optimiser(spec) is spatial_indexer.optimise_spatial_indexer
        assert body_of(spec).optimise_objectives == ("size", "normal_force")


def test_size_gives_a_checked_design_smaller_than_the_start(case) -> None:
    spec, res = case
    start = body_of(spec).design(spec)
    final = body_of(res.spec).design(res.spec)
    assert start.checks_report["passed"]
    assert final.checks_report["passed"], final.checks_report["failed"]
    assert res.feasible and res.status != "infeasible" and res.checks.passed
    r0, r1 = _outer_radius(spec), _outer_radius(res.spec)
    assert res.initial_value == pytest.approx(r0, rel=1e-12)
    assert res.value == pytest.approx(r1, rel=1e-12)
    assert r1 < 0.8 * r0, (r0, r1)               # measured: barrel 40 → 20, globoid 79.3 → ≈ 36–40 mm
    assert 1 <= res.evaluations <= BUDGET[spec.cam.body]
    paths = tuple(spatial_indexer.spatial_paths(spec).values())
    assert tuple(res.variables) == paths == ("indexer.centre_distance", TURRET[spec.cam.body],
                                             "follower.roller_radius")
    assert tuple(map(float, res.design)) == pytest.approx(tuple(_get(res.spec, p) for p in paths), rel=1e-12)
    for path, (lo, hi) in res.details["bounds"].items():
        assert lo * (1 - 1e-12) <= _get(res.spec, path) <= hi * (1 + 1e-12), path
    # the turret's other lengths follow its size as fixed fractions
    k = _get(res.spec, TURRET[spec.cam.body]) / _get(spec, TURRET[spec.cam.body])
    for path in SCALED[spec.cam.body]:
        assert _get(res.spec, path) == pytest.approx(k * _get(spec, path), rel=1e-9), path
    # both objectives of the start and of the result, as the parallel indexer's report holds them
    m = res.details["measures"]
    assert m["size"]["initial"] == pytest.approx(r0) and m["size"]["final"] == pytest.approx(r1)
    assert m["normal_force"]["final"] == pytest.approx(float(final.drive.normal_force_peak), rel=1e-12)


def test_size_report_is_plain_and_names_the_objective(case) -> None:
    spec, res = case
    rep = res.report()
    json.dumps(rep, allow_nan=False)
    assert rep["objective"] == "size" and rep["objective_unit"] == "mm"
    assert rep["objective_key"] == ("indexer.geometry.outer_radius" if spec.cam.body == "barrel_indexer" else None)
    assert "outer radius" in rep["objective_label"]
    assert rep["feasible"] and rep["failed_checks"] == "none"
    assert rep["final_value"] < rep["initial_value"]
    assert all(h["objective"] is None or math.isfinite(h["objective"]) for h in rep["history"])


@pytest.mark.parametrize("body", sorted(EXAMPLES))
@pytest.mark.parametrize("changes, field", [({"optimise.objective": "profile_area"}, "optimise.objective"),
                                            ({"optimise.variables": "base_radius"}, "optimise.variables"),
                                            ({"optimise.algorithm": "slsqp"}, "optimise.algorithm"),
                                            ({"optimise.base_radius_min": 5.0}, "optimise.base_radius_min"),
                                            ({"indexer.output_inertia": None, "optimise.objective": "normal_force"},
                                             "indexer.output_inertia")])
def test_settings_that_do_not_apply_are_refused_before_any_design(body: str, changes: dict, field: str) -> None:
    spec = CamSpec.from_dict(EXAMPLES[body])
    with pytest.raises(SpecError) as exc:
        optimise(spec.replace(**changes), max_evaluations=10)
    assert exc.value.field == field


@requires_ocp
def test_cli_optimise_barrel_writes_the_optimised_cam(tmp_path) -> None:
    out = tmp_path / "opt"
    res = run("optimise", "--example", "barrel_indexer", "--max-evaluations", "10", "-o", str(out))
    assert res.returncode == 0, res.stderr
    names = {p.name for p in out.iterdir()}
    assert {"optimised.toml", "report.json", "report.html", "cam.step"} <= names
    rep = json.loads((out / "report.json").read_text())
    opt = rep["optimise"]
    assert opt["objective"] == "size" and opt["feasible"] is True and rep["checks"]["passed"] is True
    assert opt["final_value"] < opt["initial_value"] == pytest.approx(40.0)
    assert rep["indexer"]["geometry"]["outer_radius"] == pytest.approx(opt["final_value"], rel=1e-12)
    assert [v["name"] for v in opt["variables"]] == ["indexer.centre_distance", "indexer.pitch_radius",
                                                     "follower.roller_radius"]
    assert rep["files"]["spec"] == "optimised.toml"
    assert "every design check passes" in res.stdout


@pytest.mark.parametrize("args, field", [(("--objective", "profile_area"), "optimise.objective"),
                                         (("--set", "optimise.base_radius_min=5"), "optimise.base_radius_min")])
def test_cli_bad_settings_exit_2_naming_the_field(tmp_path, args: tuple, field: str) -> None:
    out = tmp_path / "never"
    res = run("optimise", "--example", "globoidal_indexer", *args, "-o", str(out))
    assert res.returncode == 2, (res.stdout, res.stderr)
    assert field in res.stderr and "Traceback" not in res.stderr and not out.exists()

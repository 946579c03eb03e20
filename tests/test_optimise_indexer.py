"""The parallel indexer's optimiser (generators/optimise/indexer.py) through the library entry the CLI
uses (:func:`cam_workbench.generators.optimise.optimise`): objective "size" on the example returns a
spec whose design (designed again here) passes every check, no larger than the start and with its
variables within the bounds; "normal_force" without a load is refused naming indexer.output_inertia;
the indexer's objectives are refused on a plane cam.  A small evaluation budget keeps it short."""
from __future__ import annotations

import json
import math

import pytest

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.kinds import body_of
from cam_workbench.generators.optimise import optimise
from cam_workbench.generators.spec.examples import DEFAULT_SPEC_DICT, PARALLEL_INDEXER_SPEC_DICT
from cam_workbench.generators.spec.model import CamSpec

#: the solver's designs at most (the spec's smallest allowed budget is 10)
BUDGET = 20
PATHS = ("indexer.centre_distance", "indexer.pitch_radius", "follower.roller_radius")
#: optimise_parallel's default bounds as factors of the start (C, R_p, r_r)
FACTORS = ((0.5, 2.0), (0.5, 2.0), (0.5, 1.5))


def _variables(spec: CamSpec) -> tuple[float, float, float]:
    return (spec.indexer.centre_distance, spec.indexer.pitch_radius, spec.follower.roller_radius)


@pytest.fixture(scope="module")
def spec() -> CamSpec:
    return CamSpec.from_dict(PARALLEL_INDEXER_SPEC_DICT)


@pytest.fixture(scope="module")
def size_result(spec: CamSpec):
    return optimise(spec, objective="size", max_evaluations=BUDGET)


def test_size_gives_a_checked_design_no_larger_than_the_start(spec: CamSpec, size_result) -> None:
    res = size_result
    start = body_of(spec).design(spec).summary()
    final = body_of(res.spec).design(res.spec).summary()
    assert start["checks"]["passed"]
    assert final["checks"]["passed"], final["checks"]["failed"]
    assert res.feasible and res.status != "infeasible"
    r0, r1 = start["body"]["outer_radius"], final["body"]["outer_radius"]
    assert r1 <= r0
    # the result's numbers are the designs' own
    assert res.objective == "size"
    assert res.initial_value == pytest.approx(r0, rel=1e-12)
    assert res.value == pytest.approx(r1, rel=1e-12)
    assert 1 <= res.evaluations <= BUDGET
    # its variables are the optimised spec's, the start's those of the spec given
    assert tuple(res.variables) == PATHS
    assert tuple(map(float, res.design)) == pytest.approx(_variables(res.spec), rel=1e-12)
    assert tuple(map(float, res.initial_design)) == pytest.approx(_variables(spec), rel=1e-12)
    # everything else of the spec is the start's (with the call's [optimise] settings); cam.base_radius
    # derived again from the new size
    assert res.initial_spec.to_dict() == spec.replace(**{"optimise.objective": "size",
                                                         "optimise.max_evaluations": BUDGET}).to_dict()
    rest = res.spec.replace(**dict(zip(PATHS, _variables(spec))))
    assert rest.to_dict() == res.initial_spec.to_dict()


def test_size_variables_lie_within_the_bounds(spec: CamSpec, size_result) -> None:
    bounds = size_result.details["bounds"]
    assert tuple(bounds) == PATHS
    for path, x0, x, (lo_f, hi_f) in zip(PATHS, _variables(spec), _variables(size_result.spec), FACTORS):
        lo, hi = bounds[path]
        assert (lo, hi) == pytest.approx((lo_f * x0, hi_f * x0), rel=1e-12), path
        assert lo <= x <= hi, (path, x, lo, hi)


def test_size_report_names_the_indexer_objective(spec: CamSpec, size_result) -> None:
    rep = size_result.report()
    json.dumps(rep, allow_nan=False)          # report.json's optimise section: plain, finite numbers
    assert rep["objective"] == "size" and rep["objective_unit"] == "mm"
    assert rep["objective_key"] == "body.outer_radius"
    assert rep["feasible"] and rep["failed_checks"] == "none"
    assert [v["name"] for v in rep["variables"]] == list(PATHS)
    assert rep["final_value"] <= rep["initial_value"]
    assert all(h["objective"] is None or math.isfinite(h["objective"]) for h in rep["history"])


def test_normal_force_without_a_load_is_refused_naming_the_inertia(spec: CamSpec) -> None:
    no_load = spec.replace(**{"indexer.output_inertia": None, "indexer.friction_torque": 0.0})
    with pytest.raises(SpecError) as exc:
        optimise(no_load, objective="normal_force", max_evaluations=BUDGET)
    assert exc.value.field == "indexer.output_inertia"
    assert "indexer.output_inertia" in str(exc.value)


def test_the_indexer_objectives_are_refused_on_a_plane_cam() -> None:
    with pytest.raises(SpecError) as exc:
        CamSpec.from_dict({**DEFAULT_SPEC_DICT, "optimise": {"objective": "size"}})
    assert exc.value.field == "optimise.objective"


@pytest.mark.parametrize("setting, field", [({"algorithm": "slsqp"}, "optimise.algorithm"),
                                            ({"objective": "profile_area"}, "optimise.objective"),
                                            ({"multistart": 1}, "optimise.multistart")])
def test_settings_that_do_not_apply_are_refused(spec: CamSpec, setting: dict, field: str) -> None:
    with pytest.raises(SpecError) as exc:
        optimise(spec, max_evaluations=BUDGET, **setting)
    assert exc.value.field == field

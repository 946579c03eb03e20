"""The parallel indexer's optimiser against checks written here: feasibility re-derived from a fresh
design's arrays at the returned variables, a brute-force grid over the same bounds, the drive's
peaks from parallel_drive, and the verdicts and argument errors.  mm, rad."""
from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest

from cam_workbench.generators.bodies.indexing.parallel import ParallelIndexer, design_parallel
from cam_workbench.generators.bodies.indexing.parallel_drive import parallel_drive
from cam_workbench.generators.optimise.parallel_indexer import optimise_parallel
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.motion.laws import evaluate_law

S = 181                                  # input angles per design
LOAD = {"input_speed": 60.0, "inertia": 2.0, "roller_width": 12.0, "roller_rating": 8000.0}
VARS = ("centre_distance", "pitch_radius", "roller_radius")


def redesign(variables, **base):
    ix = ParallelIndexer(**base, **{k: variables[k] for k in VARS})
    return design_parallel(ix, S, strict=False)


def index_pressure_angle(d):
    """Largest driving pressure angle over θ_s + [0, β] (NaN = no forward contact = 90°)."""
    ix = d.indexer
    rel = d.theta - ix.index_start
    a = d.driving_angle[(rel >= 0) & (rel <= ix.index_angle)]
    return float(np.max(np.where(np.isfinite(a), a, math.pi / 2)))


def loaded_pressure_angle(d, frac=0.05):
    """The load-carrying contact's angle (driving where ψ'' ≥ 0, holding where < 0) where
    |ψ''| > frac·peak, ψ'' from the law (no friction: T_out ∝ ψ'')."""
    ix = d.indexer
    rel = d.theta - ix.index_start
    inside = (rel >= 0) & (rel <= ix.index_angle)
    _, _, f2, _ = evaluate_law(ix.law, np.clip(rel / ix.index_angle, 0, 1))
    f2 = np.where(inside, f2, 0.0)
    mask = np.abs(f2) > frac * np.abs(f2).max()
    a = np.where(f2 >= 0, d.driving_angle, d.holding_angle)[mask]
    return float(np.max(np.where(np.isfinite(a), a, math.pi / 2)))


def outer(d):
    return max(float(np.hypot(*c.profile.T).max()) for c in d.cams)


def feasible(d, limit, clearance, measure=index_pressure_angle):
    return (measure(d) <= limit and d.clearance.gap >= clearance and d.clearance.ok and d.locked.ok)


# -- (a) an unmet limit becomes a feasible design --------------------------------------------------

def test_unmet_limit_found_feasible():
    limit = math.radians(68.0)
    start = design_parallel(ParallelIndexer(), S, strict=False)
    assert index_pressure_angle(start) > limit             # the start cannot meet it
    seen = []
    r = optimise_parallel(ParallelIndexer(), max_pressure_angle=limit, samples=S, max_evaluations=120,
                          progress=seen.append)
    assert r.verdict in ("converged", "max evaluations"), r.solver_status
    assert r.feasible and r.blocking == ""
    d = redesign(r.variables)
    assert feasible(d, limit, 1.0)
    assert index_pressure_angle(d) == pytest.approx(r.constraints["pressure_angle"], abs=1e-12)
    assert outer(d) == pytest.approx(r.value, rel=1e-12)
    assert len(seen) == r.evaluations and seen[-1].evaluations == r.evaluations
    assert all(math.isfinite(p.max_violation) for p in seen)
    s = r.summary()
    json.dumps(s, allow_nan=False)
    assert s["verdict"] == r.verdict and s["design"]["valid"] is True
    assert s["variables_mm"] == r.variables


def test_loaded_measure_is_the_carrying_contacts():
    limit = math.radians(68.0)
    r = optimise_parallel(ParallelIndexer(), max_pressure_angle=limit, pressure_where="loaded", samples=S,
                          max_evaluations=60)
    assert r.feasible
    d = redesign(r.variables)
    assert loaded_pressure_angle(d) == pytest.approx(r.constraints["pressure_angle"], abs=1e-12)
    assert feasible(d, limit, 1.0, loaded_pressure_angle)
    # the loaded measure leaves the ends out: never above the index's own
    assert loaded_pressure_angle(d) <= index_pressure_angle(d) + 1e-12


# -- (b) no worse than brute force ----------------------------------------------------------------

def test_size_beats_a_grid_search():
    limit = math.radians(68.0)
    bounds = {"centre_distance": (80.0, 130.0), "pitch_radius": (35.0, 60.0), "roller_radius": (10.0, 10.0)}
    best = math.inf
    for c, rp in itertools.product(np.linspace(80, 130, 8), np.linspace(35, 60, 8)):
        try:
            d = redesign({"centre_distance": c, "pitch_radius": rp, "roller_radius": 10.0})
        except SpecError:
            continue
        if feasible(d, limit, 1.0):
            best = min(best, outer(d))
    assert math.isfinite(best)
    r = optimise_parallel(ParallelIndexer(), max_pressure_angle=limit, bounds=bounds, samples=S,
                          max_evaluations=100)
    assert r.feasible and r.variables["roller_radius"] == 10.0
    for k, (lo, hi) in bounds.items():
        assert lo <= r.variables[k] <= hi
    d = redesign(r.variables)
    assert feasible(d, limit, 1.0)
    assert outer(d) <= best * (1 + 1e-3)


# -- (c) the load objectives ----------------------------------------------------------------------

def test_normal_force_lowered_and_the_input_torque_no_objective():
    ix = ParallelIndexer()
    start = parallel_drive(design_parallel(ix, S, strict=False), **LOAD)
    r = optimise_parallel(ix, objective="normal_force", load=LOAD, max_pressure_angle=math.radians(75),
                          samples=S, max_evaluations=60)
    assert r.feasible
    after = parallel_drive(redesign(r.variables), **LOAD)
    assert after.normal_force_peak == pytest.approx(r.value, rel=1e-12)
    assert after.normal_force_peak < 0.95 * start.normal_force_peak
    # the peak input torque is T_out·ψ'/η: the same at any geometry (so its optimum is the start's)
    other = parallel_drive(redesign({"centre_distance": 100.0, "pitch_radius": 45.0, "roller_radius": 8.0}), **LOAD)
    assert other.torque_in_peak == pytest.approx(start.torque_in_peak, rel=1e-12)
    with pytest.raises(SpecError) as e:
        optimise_parallel(ix, objective="input_torque", load=LOAD)
    assert e.value.field == "optimise.objective"


# -- (d) no feasible point ------------------------------------------------------------------------

@pytest.mark.parametrize("kw, blocking", [
    ({"max_pressure_angle": math.radians(40.0)}, "pressure_angle"),
    ({"min_clearance": 500.0}, "clearance"),
    # R_p fixed at 50 and C ≤ 1.1·R_p: the rollers' loci never cross (no trial builds)
    ({"bounds": {"pitch_radius": (50.0, 50.0), "centre_distance": (52.0, 55.0)}}, "geometry"),
], ids=["pressure_angle", "clearance", "geometry"])
def test_impossible_limit_gives_a_verdict(kw, blocking):
    r = optimise_parallel(ParallelIndexer(), samples=S, max_evaluations=30, **kw)
    assert r.verdict == "no feasible point"
    assert r.blocking == blocking
    assert r.design is None and r.least_violated is not None
    assert r.least_violated.blocking == blocking
    if blocking == "geometry":
        assert "indexer." in r.least_violated.failure
    s = r.summary()
    json.dumps(s, allow_nan=False)
    assert s["blocking"] == blocking and s["optimum"] is None and s["least_violated"]["most_violated"] == blocking


def test_cancel_keeps_the_best_so_far():
    calls = []

    def stop(p):
        calls.append(p)
        return len(calls) < 4

    r = optimise_parallel(ParallelIndexer(), max_pressure_angle=math.radians(75), samples=S, progress=stop)
    assert r.verdict == "cancelled" and len(calls) == 4 and r.evaluations == 4
    assert r.feasible                       # the start meets 75°


# -- (e) arguments --------------------------------------------------------------------------------

@pytest.mark.parametrize("kw, field", [
    ({"objective": "mass"}, "optimise.objective"),
    ({"max_pressure_angle": 2.0}, "optimise.max_pressure_angle"),
    ({"max_pressure_angle": "45"}, "optimise.max_pressure_angle"),
    ({"min_clearance": -1.0}, "optimise.min_clearance"),
    ({"pressure_where": "ends"}, "optimise.pressure_where"),
    ({"load_fraction": 1.0}, "optimise.load_fraction"),
    ({"bounds": {"centre_distance": (130.0, 100.0)}}, "optimise.bounds.centre_distance"),
    ({"bounds": {"pitch_radius": (-1.0, 10.0)}}, "optimise.bounds.pitch_radius"),
    ({"bounds": {"roller_radius": 5.0}}, "optimise.bounds.roller_radius"),
    ({"bounds": {"stations": (4, 8)}}, "optimise.bounds.stations"),
    ({"samples": 4}, "optimise.samples"),
    ({"algorithm": "SLSQP"}, "optimise.algorithm"),
    ({"max_evaluations": 0}, "optimise.max_evaluations"),
    ({"objective": "normal_force"}, "optimise.load"),
    ({"objective": "normal_force", "load": {**LOAD, "inertia": -1.0}}, "optimise.load.inertia"),
    ({"objective": "normal_force", "load": {k: v for k, v in LOAD.items() if k != "roller_rating"}},
     "optimise.load.roller_rating"),
    ({"objective": "normal_force", "load": {**LOAD, "torque": 1.0}}, "optimise.load.torque"),
])
def test_bad_arguments_name_the_field(kw, field):
    with pytest.raises(SpecError) as err:
        optimise_parallel(ParallelIndexer(), **kw)
    assert err.value.field == field

"""The optimiser of a parallel indexer (``cam.body = "parallel_indexer"``): the spec's ``[optimise]``
settings mapped onto :func:`~cam_workbench.generators.optimise.parallel_indexer.optimise_parallel`,
its optimum re-checked by the body's own design, an :class:`OptimiseResult` as the CLI expects (its
``report()`` the shared one: the objectives' words, units and report.json keys are
:mod:`~cam_workbench.generators.optimise.objectives`' tables, as the plane cam's are).

Variables x = (C, R_p, r_r): ``indexer.centre_distance``, ``indexer.pitch_radius`` and
``follower.roller_radius`` (all three: ``optimise.variables = "auto"``; the stations, the index, the law and
the number of cams are the spec's).  Their bounds are ``optimise_parallel``'s defaults from the start:
C ∈ [0.5, 2]·C₀, R_p ∈ [0.5, 2]·R_p₀, r_r ∈ [0.5, 1.5]·r_r₀ (report.json ``optimise.bounds``).

The settings:

* ``optimise.objective``: ``"size"`` (the cams' outer radius, report.json ``body.outer_radius``) or
  ``"normal_force"`` (the peak roller load, ``indexer.drive.normal_force_peak_N``; it needs the load:
  ``indexer.output_inertia``); ``"area"``, the spec's default, is taken as ``"size"``;
* ``optimise.algorithm``: auto or cobyla → COBYLA, bobyqa → BOBYQA (in nlopt's augmented
  Lagrangian); the gradient methods and ISRES are refused (every trial is a full design, its checks
  maxima over samples);
* ``optimise.max_evaluations``: the solver's designs at most;
* ``optimise.constraint_margin``: the pressure-angle limit ``indexer.max_pressure_angle`` imposed as
  φ ≤ (1 − margin)·φ_max;
* the load: ``from_spec.load_arguments(spec)`` (it also shapes where the pressure angle counts: the
  carrying contact where |T_out| > 5 % of its peak, as the body's ``pressure_angle`` check takes it);
* ``multistart`` and the plane cam's bounds (``base_radius_min`` …) do not apply and are refused
  when given; ``xtol_rel``/``ftol_rel`` are the solver's own (``optimise_parallel``).

The solver's constraints (pressure angle, the idle rollers' clearance ≥ 1 mm, hand-over, locking,
a design that builds) hold at ``SAMPLES`` input angles; the body's own checks go further (the
undercut factor × r_r, the contact stress against ``material.allowable_stress``, the bore inside
the cams, 721 input angles).  So the optimum is designed again as the body designs it; when that
design fails a check (and the start passes them all), the result is pulled back along the straight
line from the start to the optimum in log units, x(t) = x₀·(x*/x₀)^t, bisecting t to 1/2⁸ for the
design furthest along it that passes every check — the result is always a design the body built and
checked, never larger (for ``"normal_force"``: never a larger load) than the start.

report.json's ``optimise`` section names the objective as :mod:`~cam_workbench.generators.optimise.objectives`
names every objective, and beside the solver's details (``bounds``, ``solver_optimum``, ``pulled_back`` …)
holds ``measures``: both objectives (the outer radius, the peak roller load or None without a load) of the
start and of the result, whichever was minimised.
"""
from __future__ import annotations

import math
import time
from typing import Any, Callable, Protocol, TypeVar

import numpy as np

from ..bodies.indexing import from_spec
from ..bodies.indexing.parallel_kind import ParallelIndexerBody, ParallelIndexerDesign, indexer_of
from ..bodies.indexing.parallel_kind import LOAD_FRACTION
from ..spec.indexer import indexer_value
from .parallel_indexer import DEFAULT_BOUNDS, VARIABLES, optimise_parallel, outer_radius
from ..checks.design import CheckResult, DesignChecks
from ..errors import SpecError
from ..kinds import register_optimiser
from ..spec.model import CamSpec
from .result import OptimiseResult, Progress

#: spec path of each design variable, in the solver's order (C, R_p, r_r)
PATHS = {"centre_distance": "indexer.centre_distance", "pitch_radius": "indexer.pitch_radius",
         "roller_radius": "follower.roller_radius"}
#: input angles per solver trial (the body's own design re-checks at its 721)
SAMPLES = 361
#: the idle rollers' least gap to the cams while solving [mm] (the body's check: > 0)
MIN_CLEARANCE = 1.0
#: bisections of the pull-back (t to 1/2^8 of the way from the start to the optimum)
PULL_BACK_STEPS = 8
#: spec algorithm → optimise_parallel's
ALGORITHMS = {"auto": "COBYLA", "cobyla": "COBYLA", "bobyqa": "BOBYQA"}
#: the plane cam's bounds in [optimise], which an indexer does not have
PLANE_BOUNDS = ("base_radius_min", "base_radius_max", "offset_max", "pivot_distance_min", "pivot_distance_max",
                 "arm_length_min", "arm_length_max", "face_offset_max", "outer_diameter_min", "outer_diameter_max",
                 "clearance_min", "clearance_max", "point_shift_max")


def indexer_objective(spec: CamSpec) -> str:
    """The indexer's objective of ``spec``'s ``optimise.objective`` ("area", the default, is "size").

    Raises:
        SpecError: an objective the indexer does not have (``optimise.objective``).
    """
    name = spec.optimise.objective
    if name == "area":
        return "size"
    if name not in ParallelIndexerBody.optimise_objectives:
        raise SpecError("optimise.objective", f"a parallel indexer is optimised for "
                        f"{' or '.join(ParallelIndexerBody.optimise_objectives)} (\"area\", the default, is size), "
                        f"got {name!r}")
    return name


def indexer_arguments(spec: CamSpec) -> dict[str, Any]:
    """``optimise_parallel``'s keyword arguments from ``spec``'s ``[optimise]`` and ``[indexer]``
    (module docstring); SpecError naming the spec's field for a setting that does not apply."""
    cfg = spec.optimise
    objective = indexer_objective(spec)
    if cfg.variables.strip() != "auto":
        raise SpecError("optimise.variables", "a parallel indexer's design variables are "
                        f"{', '.join(PATHS.values())}, all three: \"auto\", got {cfg.variables!r}")
    if cfg.algorithm not in ALGORITHMS:
        raise SpecError("optimise.algorithm", f"a parallel indexer's trials are full designs whose checks are maxima "
                        f"over samples: {', '.join(ALGORITHMS)} (derivative-free), got {cfg.algorithm!r}")
    if cfg.multistart:
        raise SpecError("optimise.multistart", f"a parallel indexer's optimiser runs from the spec's design alone "
                        f"(restarted from its best trial while it gains): 0, got {cfg.multistart}")
    for name in PLANE_BOUNDS:
        if getattr(cfg, name) is not None:
            raise SpecError(f"optimise.{name}", "does not apply to a parallel indexer (its variables' bounds are "
                            "0.5–2 × the start's C and R_p, 0.5–1.5 × its r_r)")
    load = from_spec.load_arguments(spec)
    if objective == "normal_force" and load is None:
        raise SpecError("indexer.output_inertia", "objective normal_force (the peak roller load) needs the output's "
                        "load: give indexer.output_inertia [kg·mm²] (and indexer.friction_torque [N·mm])")
    return {"objective": objective, "load": load, "algorithm": ALGORITHMS[cfg.algorithm],
            "max_pressure_angle": math.radians(indexer_value(spec, "max_pressure_angle")) * (1.0 - cfg.constraint_margin),
            "min_clearance": MIN_CLEARANCE, "pressure_where": "loaded", "load_fraction": LOAD_FRACTION,
            "samples": SAMPLES, "max_evaluations": int(cfg.max_evaluations)}


def indexer_bounds(spec: CamSpec) -> dict[str, tuple[float, float]]:
    """The bounds the optimiser gives each design variable of ``spec`` (spec path → (lo, hi) [mm]):
    ``optimise_parallel``'s defaults from the start (report.json ``optimise.bounds`` after a run)."""
    return {PATHS[v]: (DEFAULT_BOUNDS[v][0] * float(x), DEFAULT_BOUNDS[v][1] * float(x))
            for v, x in zip(VARIABLES, _variables(spec))}


def _spec_at(spec: CamSpec, x: np.ndarray) -> CamSpec:
    return spec.replace(**{PATHS[v]: float(a) for v, a in zip(VARIABLES, x)})


def _variables(spec: CamSpec) -> np.ndarray:
    return np.array([float(spec.indexer.centre_distance), float(spec.indexer.pitch_radius),
                     float(spec.follower.roller_radius)])


def design_checks(report: dict[str, Any], units: str) -> DesignChecks:
    """report.json's ``checks`` of an indexer's design as the :class:`DesignChecks` an
    :class:`OptimiseResult` holds."""
    rows = [CheckResult(k, r["description"], r["kind"], r["value"], r["at_deg"], r["limit"], r["unit"], r["status"],
                        str(r.get("note") or "")) for k, r in report["results"].items()]
    return DesignChecks(tuple(rows), {}, "per_turn", int(report.get("samples_per_turn") or 0), units, None)


class Designed(Protocol):
    """What :func:`pull_back` reads of a design the body built (or why not)."""

    x: np.ndarray          #: the design variables, in the solver's order [mm]
    value: float           #: the objective's value (NaN without one)
    failure: str           #: why the body refused the spec ("" when it built)
    design: Any            #: the body's design (None when refused), its ``checks_report`` read

    @property
    def passed(self) -> bool: ...


_D = TypeVar("_D", bound=Designed)


def pull_back(start: _D, x_opt: np.ndarray, candidate: Callable[[np.ndarray], _D],
              history: list[dict[str, Any]], stop: Callable[[], bool]) -> tuple[_D, float | None, int, list[str]]:
    """The result of the solver's optimum ``x_opt`` (≠ ``start.x``; the design variables in the
    solver's order [mm]) by the body's own design and checks, ``candidate(x)`` designing the body at x:

    * the optimum when it passes, unless the start passes too and the optimum's value is not ≤ the
      start's (the start then);
    * no checked start: the optimum when the body built it, else the start;
    * else the pull-back along x(t) = x₀·(x*/x₀)^t (log units), t bisected :data:`PULL_BACK_STEPS`
      times (to 1/2⁸; lower after a failing design, higher after a passing one): the smallest
      passing design (the least objective value) when it is below the start's, else the start.  Each of its designs is
      appended to ``history`` (phase "pull back", max_violation 0 passed / 1 failed); ``stop()``
      true ends it early.

    Returns (the chosen design, the pull-back's t of it — 0 for the start, None without a
    pull-back —, the designs built, the messages for the result).
    """
    cand = candidate(x_opt)
    chosen, designs = start, 1
    pulled: float | None = None
    messages: list[str] = []
    if cand.passed:
        chosen = cand
        if start.passed and not cand.value <= start.value:
            chosen = start
            messages.append("the solver's optimum is no better than the start by the body's own design: the "
                            "start kept")
    elif not start.passed:          # no checked design to pull back to: the optimum as it is
        chosen = cand if cand.design is not None else start
    else:                           # pull back toward the start until the body's checks pass
        why = cand.failure or ", ".join(cand.design.checks_report["failed"])
        lo, hi, t_best = 0.0, 1.0, 0.0
        for _ in range(PULL_BACK_STEPS):
            if stop():
                break
            t = 0.5 * (lo + hi)
            trial = candidate(start.x * (x_opt / start.x) ** t)
            designs += 1
            history.append({"iteration": len(history) + 1, "objective": trial.value if trial.passed else None,
                            "max_violation": 0.0 if trial.passed else 1.0, "phase": "pull back"})
            if trial.passed:
                lo = t
                if trial.value < chosen.value:
                    chosen, t_best = trial, t
            else:
                hi = t
        pulled = t_best
        messages.append(f"the solver's optimum fails the body's check ({why}): "
                        + (f"pulled back to {t_best:.4g} of the way from the start (log units)" if t_best > 0
                           else "no design along the way from the start passes and is smaller: the start kept"))
    return chosen, pulled, designs, messages


class _Candidate:
    """A design the body built (or why not): its spec, design, checks and objective value."""

    def __init__(self, spec: CamSpec, objective: str, x: np.ndarray | None = None):
        self.x = _variables(spec) if x is None else np.asarray(x, dtype=float)
        self.spec: CamSpec | None = None
        self.design: ParallelIndexerDesign | None = None
        self.failure = ""
        self.value = math.nan
        #: both objectives of the design (None where it has none: no design, normal_force without a load)
        self.measures: dict[str, float | None] = dict.fromkeys(ParallelIndexerBody.optimise_objectives)
        try:
            self.spec = spec if x is None else _spec_at(spec, self.x)
            self.design = ParallelIndexerBody.design(self.spec)
        except SpecError as exc:
            self.failure = str(exc)
            return
        self.measures = {"size": outer_radius(self.design.geometry),
                         "normal_force": None if self.design.drive is None
                         else float(self.design.drive.normal_force_peak)}
        if self.measures[objective] is not None:
            self.value = self.measures[objective]

    @property
    def passed(self) -> bool:
        return self.design is not None and bool(self.design.checks_report["passed"]) and math.isfinite(self.value)

    def checks(self, units: str) -> DesignChecks:
        if self.design is not None:
            return design_checks(self.design.checks_report, units)
        report = None
        if self.spec is not None:
            try:                       # the checks without refusing (a turret not held, a roller that hits)
                report = ParallelIndexerBody.own_checks(self.spec)
            except SpecError:
                report = None
        if report is not None:
            return design_checks(report, units)
        row = CheckResult("geometry", f"the design builds ({self.failure})", "max", None, None, None, "", "fail")
        return DesignChecks((row,), {}, "per_turn", 0, units, None)


@register_optimiser(ParallelIndexerBody.kind)
def optimise_indexer(spec: CamSpec, progress: Callable[[Any], Any] | None = None, cancel: Any = None) -> Any:
    """Optimise a parallel indexer's C, R_p and r_r with :func:`optimise_parallel` (module docstring);
    an :class:`OptimiseResult` whose ``spec`` is the optimised spec, re-checked by the body's design.

    Raises:
        SpecError: a setting that does not apply (``optimise.*``), or objective normal_force without
            ``indexer.output_inertia``.
    """
    t0 = time.perf_counter()
    args = indexer_arguments(spec)
    objective = args["objective"]
    ix = indexer_of(spec)
    budget = args["max_evaluations"]
    history: list[dict[str, Any]] = []
    stopped = [False]

    def on_trial(p: Progress) -> bool:
        value = float(p.objective) if math.isfinite(p.objective) else None
        history.append({"iteration": len(history) + 1, "objective": value, "max_violation": float(p.max_violation)})
        if progress is not None and progress(Progress(p.evaluations, budget, p.phase.lower(), p.objective,
                                                      p.max_violation, p.best)) is False:
            stopped[0] = True
        if cancel is not None and cancel.is_set():
            stopped[0] = True
        return not stopped[0]

    best = optimise_parallel(ix, progress=on_trial, **args)
    start = _Candidate(spec, objective)
    x_opt = np.array([best.variables[v] for v in VARIABLES])
    chosen = start
    messages = [f"{best.algorithm}: {best.verdict}" + (f" (blocking: {best.blocking})" if best.blocking else "")]
    pulled: float | None = None
    designs = 1
    if not np.allclose(x_opt, start.x, rtol=1e-12, atol=0.0):
        chosen, pulled, built, notes = pull_back(
            start, x_opt, lambda x: _Candidate(spec, objective, x), history,
            lambda: stopped[0] or (cancel is not None and cancel.is_set()))
        designs += built
        messages += notes
    final_spec = chosen.spec if chosen.spec is not None else spec
    checks, initial_checks = chosen.checks(spec.units), start.checks(spec.units)
    cancelled = best.verdict == "cancelled" or stopped[0]
    if cancelled:
        status = "cancelled"
    elif not checks.passed:
        status = "infeasible"
    elif best.verdict == "max evaluations":
        status = "budget exhausted"
    elif best.verdict != "converged":
        status = "stopped"
    else:
        status = "converged"
    if not checks.passed:
        messages.append(f"the final design FAILS the body's check: {', '.join(checks.failed)}")
    initial_value = start.value if math.isfinite(start.value) else float(best.start_value)
    value = chosen.value if math.isfinite(chosen.value) else float(best.value)
    details = {
        "solver": f"nlopt {best.algorithm} (derivative-free) on optimise_parallel's trials ({SAMPLES} input angles "
                  "each), the result designed and checked by the body",
        "bounds": {PATHS[k]: [float(a), float(b)] for k, (a, b) in best.bounds.items()},
        "max_pressure_angle_deg": math.degrees(best.max_pressure_angle),
        "pressure_where": best.pressure_where, "min_clearance": best.min_clearance, "samples": SAMPLES,
        "constraint_margin": spec.optimise.constraint_margin,
        "solver_optimum": {"verdict": best.verdict, "evaluations": best.evaluations,
                           "variables": {PATHS[k]: float(v) for k, v in best.variables.items()},
                           "value": float(best.value) if math.isfinite(best.value) else None},
        "pulled_back": pulled, "body_designs": designs,   # the start, the optimum and the pull-back's
        # both objectives of the start and the result, whichever was minimised (report.json's
        # body.outer_radius and indexer.drive.normal_force_peak_N of each)
        "measures": {name: {"initial": start.measures[name], "final": chosen.measures[name]}
                     for name in ParallelIndexerBody.optimise_objectives},
    }
    return OptimiseResult(
        spec=final_spec, initial_spec=spec, objective=objective, algorithm=spec.optimise.algorithm,
        initial_value=initial_value, value=value, variables=tuple(PATHS.values()), initial_design=start.x,
        design=chosen.x, history=history, evaluations=best.evaluations,
        time_s=time.perf_counter() - t0, status=status, message="; ".join(messages), checks=checks,
        initial_checks=initial_checks, details=details, solver_status=best.solver_status)

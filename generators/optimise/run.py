"""The optimiser: :func:`optimise` (thesis Ch. 5–7 with nlopt).

Problem (thesis Eq. 5.1–5.13): minimise an objective over the design vector of
:mod:`~cam_workbench.generators.optimise.space` subject to every design check as the window maxima of
:mod:`~cam_workbench.generators.optimise.model` (g ≤ −margin), the linear polygon constraints, and bounds.
The solver sees scaled variables z ∈ [0, 1] and the objective divided by its initial value.

Algorithms (``optimise.algorithm``, nlopt imported lazily — ``import generators`` never loads it):

* ``slsqp`` / ``mma`` / ``ccsaq``: gradient-based, with the exact sensitivities of the model;
* ``cobyla``: derivative-free with the constraints as they are;
* ``bobyqa``: derivative-free on the thesis' exterior penalty function (Eq. 5.14–5.15)
  Ω = F/F₀ + r_p Σ max(0, g)², r_p = ``penalty`` × 10^k for k = 0 … ``penalty_rounds`` − 1, each
  round started from the last (SUMT, thesis §5.4);
* ``isres``: global evolution strategy (seeded by ``optimise.seed``), then polished locally;
* ``auto``: SLSQP for smooth objectives; for ``machining_time``/``gcode_time`` SLSQP on a smooth
  size stand-in, then (for machining_time) a 1° scan of the blank orientation over a quarter turn,
  then BOBYQA with the exterior penalty on the true time.

Constraints are the largest value of every check in each parameter window of every rise/return
(:meth:`~cam_workbench.generators.optimise.model.SmoothModel.window_max`), so the solver works on the dense maxima.
After a solve, the independent :func:`cam_workbench.generators.checks.design.run_checks` (θ-sampled, refined
extrema) re-checks the design; while it fails, the solve is repeated with twice the windows (at most
``refine_rounds`` times).  ``multistart`` adds local runs from random designs (seeded); the best
feasible result wins.

Cancelling (for GUIs): pass ``progress`` returning False, or a ``threading.Event`` as
``cancel``; both are looked at after every evaluation (a few ms apart), and the run stops with
status "cancelled", returning the best design found so far (checked like any other result).  The
library holds no global state except nlopt's random seed (set for ISRES and the random starts),
so run one optimisation per process at a time when that matters.  nlopt runs in the calling
thread; call :func:`optimise` from a worker thread to keep a GUI responsive (the callback runs in
that worker thread too: post updates to the GUI thread from it).

This module holds :func:`optimise`, which applies the settings, draws the starts and picks the result;
the parts: :mod:`.settings` (solver constants), :mod:`.problem` (the scaled problem, the tracker),
:mod:`.driver` (the nlopt and penalty runs, a start's phases), :mod:`.multistart` (the starts as jobs)
and :mod:`.result` (:class:`~.result.OptimiseResult`, :func:`~.result.final_value`).
"""
from __future__ import annotations

import threading
import time
from typing import Any, Callable

import numpy as np

from ..checks.areas import area_summary
from ..checks.design import run_checks
from ..errors import CamError, SpecError
from ..kinds import own_optimiser
from ..machining.cutting_time import thesis_cutting_time
from ..spec.model import CamSpec
from ..studies.executor import NOT_RUN, Executor, SerialExecutor
from .driver import objective_value, polish
from .model import SmoothModel
from .multistart import StartJob, StartOutcome, StartsProgress, random_start, run_start
from .objectives import TIME, make_objective
from .result import OptimiseResult, Progress, final_value
from .space import DesignSpace


def optimise(spec: CamSpec, objective: str | None = None, variables: str | None = None,
             algorithm: str | None = None, *, progress: Callable[[Progress], Any] | None = None,
             cancel: threading.Event | None = None, executor: Executor | None = None,
             **settings: Any) -> OptimiseResult:
    """Optimise ``spec`` (thesis Ch. 5): returns the optimised spec, history and report.

    Args:
        spec: the starting design; its ``[optimise]`` section gives the settings.
        objective, variables, algorithm: override ``optimise.objective`` / ``variables`` /
            ``algorithm``; ``settings`` override any other ``optimise.*`` field by name
            (e.g. ``max_evaluations=500``, ``multistart=4``).
        progress: called after every evaluation with a :class:`Progress`; return False to cancel.
            With a parallel executor it is called in this thread, a few times a second per
            running start, with the evaluations of all starts together.
        cancel: a ``threading.Event``; setting it cancels the run (from any thread).
        executor: where the starts run (:mod:`cam_workbench.generators.studies.executor`); None runs them one
            after another in this process.  ``multistart``'s random starts are drawn here, before
            any run, and the best result is picked by the same rule whatever ran where, so the
            result is the same as without an executor (e.g. Dask's:
            ``cam_workbench.parallel.dask_executor(workers=4)``).

    Raises:
        SpecError: a bad setting (field and rule named).
    """
    t_start = time.perf_counter()
    spec = _with_settings(spec, objective, variables, algorithm, settings)
    own = own_optimiser(spec)
    if own is not None:          # a body with an optimiser of its own (the cylindrical cam's)
        return own(spec, progress=progress, cancel=cancel)
    cfg = spec.optimise
    space = DesignSpace(spec)
    space.check_start()
    model = SmoothModel(space)
    obj = make_objective(cfg.objective, model)
    runs = 1 + cfg.multistart
    budget = cfg.max_evaluations * runs * (2 if cfg.objective in TIME and cfg.algorithm == "auto" else 1)
    details: dict[str, Any] = {}
    p_init = space.p0.copy()
    f_init_model = objective_value(obj, space, p_init)
    # the start's objective, independently: a start that cannot be built (gcode_time builds the cam)
    # is refused here, before any solver work, by the CamError that says why
    v0 = final_value(cfg.objective, spec)

    jobs, skipped = _start_jobs(space, spec, budget)
    agg = StartsProgress(budget, progress, cancel)
    ran = (executor or SerialExecutor()).run(run_start, jobs, on_progress=agg.on_progress,
                                             should_stop=agg.should_stop)
    outcomes: dict[int, StartOutcome] = {o.index: o for o in ran if o is not NOT_RUN}
    cancelled = len(outcomes) < len(jobs) or any(o.cancelled for o in outcomes.values())
    messages, history, evaluations = _merged_runs(outcomes, skipped, runs)
    if cancelled:
        status = "cancelled"
        solver_status, solver_ok = "cancelled (forced stop after the evaluation in progress)", False
        p_best = _best_so_far(space, outcomes, p_init)
        chosen = outcomes.get(0)
    else:
        status = "converged"
        chosen = _best_start(outcomes)
        p_best, solver_status, solver_ok = chosen.p, chosen.solver_status, chosen.solver_ok
    if chosen is not None and chosen.windows is not None:
        details["windows"] = chosen.windows
    final_spec = space.spec_at(p_best)
    try:
        v1 = final_value(cfg.objective, final_spec)
    except CamError as exc:        # gcode_time: the result cannot be built — the start is kept
        messages.append(f"the result cannot be built ({exc}): the starting design kept")
        p_best, final_spec, v1 = p_init, spec, v0
        solver_ok = False
    checks = run_checks(final_spec)
    details.update(_details(spec, final_spec, f_init_model))
    details["workers"] = int(executor.workers) if executor is not None else 1
    if status != "cancelled":
        if not checks.passed:
            status = "infeasible"
        elif evaluations >= budget:
            status = "budget exhausted"
        elif not solver_ok:
            status = "stopped"            # the solver's own text says why (e.g. roundoff limited)
    message = "; ".join(messages)
    if not checks.passed:
        message += ("; " if message else "") + f"the final design FAILS the dense check: {', '.join(checks.failed)}"
    return OptimiseResult(
        spec=final_spec, initial_spec=spec, objective=cfg.objective, algorithm=cfg.algorithm,
        initial_value=v0, value=v1, variables=space.labels, initial_design=p_init, design=p_best,
        history=history, evaluations=evaluations, time_s=time.perf_counter() - t_start,
        status=status, message=message, checks=checks, initial_checks=run_checks(spec), details=details,
        solver_status=solver_status)


def _with_settings(spec: CamSpec, objective: str | None, variables: str | None, algorithm: str | None,
                   settings: dict[str, Any]) -> CamSpec:
    """``spec`` with the call's optimiser settings (SpecError naming an unknown one)."""
    changes = {f"optimise.{k}": v for k, v in settings.items()}
    for name, value in (("objective", objective), ("variables", variables), ("algorithm", algorithm)):
        if value is not None:
            changes[f"optimise.{name}"] = value
    for key in changes:
        if key.split(".", 1)[1] not in spec.optimise.__dataclass_fields__:
            raise SpecError(key, "unknown optimiser setting")
    return spec.replace(**changes) if changes else spec


def _start_jobs(space: DesignSpace, spec: CamSpec, budget: int) -> tuple[list[StartJob], dict[int, str]]:
    """Every start's job, its random numbers drawn first, in start order (the runs may then go
    anywhere), and the words of each random start skipped because no random design builds."""
    jobs = [StartJob(0, spec, None, budget)]
    skipped: dict[int, str] = {}
    rng = np.random.default_rng(spec.optimise.seed)
    for i in range(spec.optimise.multistart):
        z_rand = random_start(space, rng)
        if z_rand is None:
            skipped[i + 1] = f"start {i + 2}: no random design of the box builds (skipped)"
        else:
            jobs.append(StartJob(i + 1, spec, z_rand, budget))
    return jobs, skipped


def _merged_runs(outcomes: dict[int, StartOutcome], skipped: dict[int, str], runs: int
                 ) -> tuple[list[str], list[dict[str, Any]], int]:
    """(messages, history, evaluations) of the starts together, in start order (the history's
    iterations counted on from one start to the next)."""
    messages: list[str] = []
    history: list[dict[str, Any]] = []
    evaluations = 0
    for k in range(runs):
        if k in skipped:
            messages.append(skipped[k])
        if k in outcomes:
            o = outcomes[k]
            messages.extend(o.messages)
            history.extend({**h, "iteration": evaluations + h["iteration"]} for h in o.history)
            evaluations += o.evaluations
    return messages, history, evaluations


def _best_start(outcomes: dict[int, StartOutcome]) -> StartOutcome:
    """The finished run's result: the first best start in start order (the first start when none
    has a key)."""
    best: tuple[tuple[bool, float], int] | None = None
    for k in sorted(outcomes):
        key = outcomes[k].key
        if key is not None and (best is None or key < best[0]):
            best = (key, k)
    return outcomes[best[1] if best is not None else 0]


def _best_so_far(space: DesignSpace, outcomes: dict[int, StartOutcome], p_init: np.ndarray) -> np.ndarray:
    """A cancelled run's design: the best feasible design any start met (else the least violating),
    as one tracker over the starts in order would see them, polished; the start if that is not valid."""
    best_feasible: tuple[float, np.ndarray] | None = None
    best_any: tuple[float, float, np.ndarray] | None = None
    for k in sorted(outcomes):
        o = outcomes[k]
        if o.best_feasible is not None and (best_feasible is None or o.best_feasible[0] < best_feasible[0]):
            best_feasible = o.best_feasible
        if o.best_any is not None and (best_any is None or (max(o.best_any[0], 0), o.best_any[1])
                                       < (max(best_any[0], 0), best_any[1])):
            best_any = o.best_any
    p_best = p_init
    if best_feasible is not None:
        p_best = best_feasible[1]
    elif best_any is not None:
        p_best = best_any[2]
    p_best = polish(space, p_best)
    return p_best if space.is_valid(p_best) else p_init


def _details(spec: CamSpec, final_spec: CamSpec, f_init_model: float) -> dict[str, Any]:
    """The result's ``details``: areas before and after, the thesis' cutting time (objective
    ``machining_time``), the constraint margin and the model's objective at the start."""
    out: dict[str, Any] = {"areas": {"initial": area_summary(spec), "final": area_summary(final_spec)}}
    if spec.optimise.objective == "machining_time":
        out["cutting_time"] = {"initial": thesis_cutting_time(spec).summary(),
                               "final": thesis_cutting_time(final_spec).summary()}
    out["constraint_margin"] = spec.optimise.constraint_margin
    out["model_objective_initial"] = f_init_model
    return out

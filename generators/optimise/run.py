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
"""
from __future__ import annotations

import dataclasses
import math
import threading
import time
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from ..checks.areas import area_summary, pitch_area, profile_area, thesis_area
from ..checks.design import DesignChecks, run_checks
from ..errors import CamError, SpecError
from ..machining.cutting_time import thesis_cutting_time
from ..cam_design import design_cam
from ..machining.cutting_time import contour_time
from ..kinds import own_optimiser
from ..spec.model import CamSpec
from ..studies.executor import NOT_RUN, Executor, SerialExecutor, TaskContext
from .kinds import force_reference, kind_model
from .model import SmoothModel
from .objectives import PEAK, SURROGATE, TIME, UNITS, Objective, describe, make_objective, report_key
from .objectives import label as objective_label
from .space import DesignSpace

LOCAL_GRADIENT = {"slsqp": "LD_SLSQP", "mma": "LD_MMA", "ccsaq": "LD_CCSAQ"}
#: Most windows per rise/return for MMA and CCSAQ.  nlopt's CCSA methods solve a dual problem
#: in the constraints at every step, and its cost climbs steeply with their number (thesis
#: Example 5, measured: 33 ms per evaluation with 8 windows, 60 ms with 16, 880 ms with 32, ≈1.5 s
#: with the default 80 — a 10-minute run).  The window maxima stay exact maxima with fewer,
#: wider windows, and the final dense check still decides.
CCSA_WINDOWS = 8
NLOPT_RESULTS = {1: "success", 2: "stopval reached", 3: "ftol reached", 4: "xtol reached",
                 5: "maxeval reached", 6: "maxtime reached", -1: "failure", -2: "invalid arguments",
                 -3: "out of memory", -4: "roundoff limited", -5: "forced stop"}
#: nlopt results that mean the solver met one of its stopping tolerances (the others — roundoff
#: limited, failure, the evaluation budget — do not make a run "converged").
NLOPT_CONVERGED = {1, 2, 3, 4}
HISTORY_MAX = 400
#: A point whose normalised constraints exceed 0 by less than this counts as feasible while
#: solving (the solvers' own tolerance); the margin keeps the checks' values below their limits,
#: and :func:`_polish` removes such round-off from the linear rows.
FEASIBLE_TOL = 1e-6


@dataclass(frozen=True)
class Progress:
    """What the progress callback receives after every evaluation."""

    evaluations: int          # so far, all phases
    budget: int               # planned most (the bar's total; a run may stop earlier)
    phase: str                # e.g. "slsqp", "orientation scan", "bobyqa r_p=100", "refine 2"
    objective: float          # this evaluation's objective (physical units; NaN if not computed)
    max_violation: float      # largest normalised constraint value (≤ 0 feasible)
    best: float | None        # best feasible objective so far


class Cancelled(Exception):
    """Raised inside the solver's callback to stop it."""


class _Stalled(Exception):
    """A run stops making progress (raised in the callback; the run's best point is kept)."""


@dataclass
class OptimiseResult:
    """An optimisation's outcome.  ``spec`` is the optimised spec (write it with
    :func:`cam_workbench.generators.spec.to_toml`); ``report()`` is report.json's ``optimise`` section."""

    spec: CamSpec
    initial_spec: CamSpec
    objective: str
    algorithm: str
    initial_value: float
    value: float
    variables: tuple[str, ...]
    initial_design: np.ndarray
    design: np.ndarray
    history: list[dict[str, Any]]
    evaluations: int
    time_s: float
    status: str
    message: str
    checks: DesignChecks
    initial_checks: DesignChecks
    details: dict[str, Any] = field(default_factory=dict)
    solver_status: str = ""        # the solver's own status text of the run that gave the result

    @property
    def initial_feasible(self) -> bool:
        """The starting design passes every design check (dense)."""
        return self.initial_checks.passed

    def initial_worst_constraint(self) -> dict[str, Any]:
        """The starting design's check closest to (or furthest past) its limit."""
        return worst_constraint(self.initial_checks, self.initial_spec)

    def initial_violations(self) -> list[dict[str, Any]]:
        """Every check the starting design fails: name, value, limit, unit, cam angle."""
        return [{"name": r.name, "value": r.value, "limit": r.limit, "unit": r.unit, "at_deg": r.at_deg}
                for r in self.initial_checks.results if r.status == "fail"]

    @property
    def feasible(self) -> bool:
        """Every design check passes on the final dense re-check."""
        return self.checks.passed

    def worst_constraint(self) -> dict[str, Any]:
        """The final design's check closest to (or furthest past) its limit, relative to the limit."""
        return worst_constraint(self.checks, self.spec)

    @property
    def status_text(self) -> str:
        """The status in words: first whether the result passes every check (the dense re-check),
        then how the run ended — e.g. "every check passes — nlopt stopped: roundoff limited"."""
        verdict = ("every check passes" if self.feasible
                   else f"the result FAILS {', '.join(self.checks.failed)}")
        solver = self.solver_status
        how = {"converged": f"converged (nlopt: {solver})" if solver else "converged",
               "stopped": f"nlopt stopped: {solver}",
               "budget exhausted": f"the budget of {self.evaluations} evaluations is spent"
                                   + (f" (nlopt: {solver})" if solver else ""),
               "cancelled": "cancelled: the best design found so far",
               "infeasible": f"nlopt: {solver}" if solver else "infeasible"}.get(self.status, self.status)
        return f"{verdict} — {how}"

    def report(self, max_history: int = HISTORY_MAX) -> dict[str, Any]:
        """report.json's ``optimise`` section (scalars, the design variables and the history)."""
        hist = _thin(self.history, max_history)
        red = 100.0 * (1.0 - self.value / self.initial_value) if self.initial_value else None
        out: dict[str, Any] = {
            "objective": self.objective,
            "objective_description": describe(self.objective, self.spec),
            "objective_label": objective_label(self.objective, self.spec),
            "objective_key": report_key(self.objective, self.spec),
            "objective_unit": UNITS[self.objective].replace("length", self.spec.units),
            "algorithm": self.algorithm,
            "status": self.status,
            "status_text": self.status_text,
            "message": self.message,
            "feasible": self.feasible,
            "failed_checks": ", ".join(self.checks.failed) if self.checks.failed else "none",
            "initial_value": self.initial_value,
            "final_value": self.value,
            "reduction_percent": red,
            "evaluations": self.evaluations,
            "time_s": self.time_s,
            "solver_status": self.solver_status,
            "initial_feasible": self.initial_feasible,
            "initial_violations": self.initial_violations(),
            "initial_worst_constraint": self.initial_worst_constraint(),
            "worst_constraint": self.worst_constraint(),
            "variables": [{"name": n, "initial": float(a), "final": float(b)}
                          for n, a, b in zip(self.variables, self.initial_design, self.design)],
            "history": hist,
        }
        out.update(self.details)
        return out


def worst_constraint(checks: DesignChecks, spec: CamSpec) -> dict[str, Any]:
    """The check of ``checks`` (of ``spec``) closest to (or furthest past) its limit, relative to
    the limit (separation: to the preload); {} when no check has a value and a limit."""
    best: dict[str, Any] = {}
    worst = -math.inf
    for r in checks.results:
        if r.value is None or r.limit is None or r.status == "skipped":
            continue
        if r.name in ("oscillation", "continuity"):
            # oscillation is zero at every flat stretch, continuity an order the motion fixes (the
            # design variables do not move it): neither is a margin
            continue
        scale = max(abs(r.limit), 1e-12) if r.name != "separation" else force_reference(spec)
        margin = (r.value - r.limit) / scale if r.kind == "max" else (r.limit - r.value) / scale
        if margin > worst:
            worst = margin
            best = {"name": r.name, "value": r.value, "limit": r.limit, "unit": r.unit,
                    "at_deg": r.at_deg, "relative_margin": -margin, "status": r.status}
    return best


def _thin(history: list[dict[str, Any]], limit: int) -> list[dict[str, Any]]:
    if len(history) <= limit:
        return list(history)
    idx = np.unique(np.round(np.linspace(0, len(history) - 1, limit)).astype(int))
    return [history[i] for i in idx]


# ---- the scaled problem ----------------------------------------------------------------------
class ScaledProblem:
    """Objective and constraints in scaled variables z (plus the epigraph variable t of a
    peak objective), with a cache so that nlopt's separate objective and constraint calls at
    the same point cost one evaluation.  Constraint rows: the linear polygon rows, then every
    check's window maxima (:meth:`SmoothModel.window_max`) + margin, then the epigraph rows."""

    def __init__(self, space: DesignSpace, model: SmoothModel, objective: Objective, margin: float,
                 f0: float, windows: int):
        self.space = space
        self.model = model
        self.obj = objective
        self.margin = margin
        self.windows = windows
        self.f0 = f0 if f0 and math.isfinite(f0) else 1.0
        self.epigraph = objective.name in PEAK
        self.n = space.n + (1 if self.epigraph else 0)
        self.peak_channels: tuple[tuple[str, float], ...] = ()
        if self.epigraph:
            name = "a" if objective.name == "peak_acceleration" else "phi"
            q, _ = model.window_max(space.p0, ((name, 1.0), (name, -1.0)), False, windows)
            self.q_ref = max(float(np.max(q)), 1e-12)
            self.peak_channels = ((name, 1.0 / self.q_ref), (name, -1.0 / self.q_ref))
        self._key: bytes | None = None
        self._val: tuple | None = None

    def p_of(self, z: np.ndarray) -> np.ndarray:
        return self.space.to_p(z[: self.space.n])

    def t0(self, p: np.ndarray) -> float:
        """The epigraph variable's starting value: the peak at p (scaled)."""
        q, _ = self.model.window_max(p, self.peak_channels, False, self.windows)
        return float(np.max(q))

    def evaluate(self, z: np.ndarray, grad: bool) -> tuple[float, np.ndarray | None, np.ndarray, np.ndarray | None, float, float]:
        """(F scaled, dF/dz, G (≤ 0 required), dG/dz, F physical, max violation without margin)."""
        key = z.tobytes()
        if key == self._key and self._val is not None and (self._val[3] is not None or not grad):
            return self._val
        sp = self.space
        p = self.p_of(z)
        scale = sp.scale
        pad = self.n - sp.n
        rows, jacs = [], []
        viol = -math.inf
        lin_ok = True
        if sp.linear_A.shape[0]:
            lv, _ = _finite_rows(sp.linear_values(p), None)       # a NaN step of the solver: violated
            viol = max(viol, float(np.max(lv)))
            lin_ok = float(np.max(lv)) < 0.5
            rows.append(lv)
            if grad:
                jacs.append(np.hstack([sp.linear_A * scale[None, :], np.zeros((lv.size, pad))]))
        with np.errstate(all="ignore"):
            cv, cjac, qv, qjac = self.model.check_rows(p, grad, self.windows, self.peak_channels)
        # an invalid control polygon (θ′ ≤ 0) or an arm at the line through the pivot, far outside
        # the feasible set: a violated row without a gradient (the geometry rows have theirs)
        cv, cjac = _finite_rows(cv, cjac)
        qv, qjac = _finite_rows(qv, qjac)
        nc = cv.size
        if nc:
            viol = max(viol, float(np.max(cv)))
            rows.append(cv + self.margin)
            if grad:
                jacs.append(np.hstack([cjac * scale[None, :], np.zeros((nc, pad))]))
        if self.epigraph:
            t = z[-1]
            rows.append(qv - t)
            if grad:
                jacs.append(np.hstack([qjac * scale[None, :], -np.ones((qv.size, 1))]))
            f_phys = float(np.max(qv)) * self.q_ref
            f_s = float(t)
            df = None
            if grad:
                df = np.zeros(self.n)
                df[-1] = 1.0
        else:
            try:
                with np.errstate(all="ignore"):     # NaN where θ′ ≤ 0: handled below
                    f_phys, dfp = (self.obj.value(p, grad and self.obj.smooth) if lin_ok
                                   else (float("nan"), None))
            except (CamError, FloatingPointError, ValueError, ZeroDivisionError):
                f_phys, dfp = float("nan"), None
            f_s = f_phys / self.f0
            df = None if dfp is None else dfp * scale / self.f0
            if grad and self.obj.smooth and (df is None or not math.isfinite(f_s) or not np.all(np.isfinite(df))):
                # not defined here (an invalid control polygon: θ′ ≤ 0): the solver sees 1e6 (see
                # _run_nlopt) with a zero gradient, never NaN (nlopt's SLSQP fails on NaN)
                df = np.zeros(self.n)
        g = np.concatenate(rows)
        out = (f_s, df, g, np.vstack(jacs) if grad else None, f_phys, viol)
        self._key, self._val = key, out
        return out


#: Normalised constraint values beyond ±ROW_SQUASH are compressed logarithmically (see _finite_rows).
ROW_SQUASH = 100.0


def _finite_rows(vals: np.ndarray, jac: np.ndarray | None) -> tuple[np.ndarray, np.ndarray | None]:
    """Rows the solvers can digest: non-finite ones become 10 (violated) with a zero gradient, and
    |g| > G = :data:`ROW_SQUASH` becomes ±G(1 + ln(|g|/G)) (value and slope continuous at G, the
    sign and so the feasible set unchanged).  Far from the feasible set a check can reach 1e14 and
    more — s″ grows as 1/θ′³ where a control polygon collapses — and nlopt's SLSQP then fails."""
    bad = ~np.isfinite(vals)
    if bad.any():
        vals = np.where(bad, 10.0, vals)
    if jac is not None:
        jac = np.nan_to_num(np.where(bad[:, None], 0.0, jac), nan=0.0, posinf=0.0, neginf=0.0)
    big = np.abs(vals) > ROW_SQUASH
    if big.any():
        mag = np.abs(vals[big])
        if jac is not None:
            jac = jac.copy()
            jac[big] *= (ROW_SQUASH / mag)[:, None]
        vals = vals.copy()
        vals[big] = np.sign(vals[big]) * ROW_SQUASH * (1.0 + np.log(mag / ROW_SQUASH))
    return vals, jac


class Tracker:
    """Counts evaluations, keeps the history and the best feasible design, reports progress
    and raises :class:`Cancelled` when asked to stop."""

    def __init__(self, budget: int, progress: Callable[[Progress], Any] | None, cancel: threading.Event | None):
        self.budget = budget
        self.progress = progress
        self.cancel = cancel
        self.evaluations = 0
        self.history: list[dict[str, Any]] = []
        self.phase = ""
        self.best_feasible: tuple[float, np.ndarray] | None = None   # (F physical, p)
        self.best_any: tuple[float, float, np.ndarray] | None = None  # (violation, F, p)
        self.cancelled = False

    def new_objective(self) -> None:
        """Forget the best points (a new phase minimises another objective)."""
        self.best_feasible = None
        self.best_any = None

    def record(self, p: np.ndarray, f_phys: float, viol: float) -> None:
        self.evaluations += 1
        self.history.append({"iteration": self.evaluations, "objective": f_phys if math.isfinite(f_phys) else None,
                             "max_violation": viol, "phase": self.phase})
        if math.isfinite(f_phys):
            if viol <= -1e-8 and (self.best_feasible is None or f_phys < self.best_feasible[0]):
                self.best_feasible = (f_phys, p.copy())
            if self.best_any is None or (max(viol, 0), f_phys) < (max(self.best_any[0], 0), self.best_any[1]):
                self.best_any = (viol, f_phys, p.copy())
        stop = False
        if self.progress is not None:
            best = self.best_feasible[0] if self.best_feasible else None
            stop = self.progress(Progress(self.evaluations, self.budget, self.phase, f_phys, viol, best)) is False
        stop = stop or (self.cancel is not None and self.cancel.is_set())
        if stop:
            self.cancelled = True
            raise Cancelled()


# ---- nlopt runs -------------------------------------------------------------------------------
def _nlopt():
    import nlopt  # noqa: PLC0415 - lazily: only the optimiser needs nlopt

    return nlopt


def _failures(nlopt: Any) -> tuple[type, ...]:
    """nlopt's exception for its generic failure: ``nlopt.runtime_error`` (pip's nlopt 2.8+, not a
    RuntimeError) or RuntimeError (Debian's nlopt 2.7)."""
    return tuple({RuntimeError, getattr(nlopt, "runtime_error", RuntimeError)})


def _bounds(prob: ScaledProblem) -> tuple[np.ndarray, np.ndarray]:
    lo = np.zeros(prob.n)
    hi = np.ones(prob.n)
    if prob.epigraph:
        hi[-1] = 10.0
    return lo, hi


def _run_nlopt(prob: ScaledProblem, algo: str, z0: np.ndarray, opt_cfg: Any, maxeval: int,
               tracker: Tracker) -> tuple[np.ndarray, str, bool]:
    """One nlopt run of ``algo`` (slsqp, mma, ccsaq, cobyla, isres) from z0; returns (z, the
    solver's status text, whether it met a stopping tolerance)."""
    nlopt = _nlopt()
    name = {"cobyla": "LN_COBYLA", "isres": "GN_ISRES", **LOCAL_GRADIENT}[algo]
    o = nlopt.opt(getattr(nlopt, name), prob.n)
    lo, hi = _bounds(prob)
    o.set_lower_bounds(lo)
    o.set_upper_bounds(hi)
    needs_grad = algo in LOCAL_GRADIENT
    seen: list[tuple[tuple[bool, float], np.ndarray]] = []     # this run's best point

    stall = max(50, 5 * prob.n)          # evaluations without a relative improvement of ftol_rel
    last_gain = [0, math.inf]            # (evaluation count of the last gain, best feasible F)

    def f(z: np.ndarray, grad: np.ndarray) -> float:
        fs, df, g, _j, fp, viol = prob.evaluate(z, needs_grad and grad.size > 0)
        gmax = float(np.max(g))
        if not np.all(np.isfinite(z)):   # a failed step of the solver (NaN): never the run's best
            gmax = math.inf
        # feasible points by objective; infeasible ones by their violation
        key = (True, gmax) if gmax > FEASIBLE_TOL else (False, fs if math.isfinite(fs) else math.inf)
        if not seen or key < seen[0][0]:
            seen[:] = [(key, z.copy())]
        tracker.record(prob.p_of(z), fp, viol)
        count = len(tracker.history)
        if not key[0] and key[1] < last_gain[1] - opt_cfg.ftol_rel * abs(last_gain[1] if math.isfinite(last_gain[1]) else 0):
            last_gain[:] = [count, key[1]]
        elif math.isfinite(last_gain[1]) and count - last_gain[0] > stall:
            raise _Stalled()
        if grad.size > 0:
            grad[:] = df
        return fs if math.isfinite(fs) else 1e6

    m = prob.evaluate(z0, False)[2].size

    def c(result: np.ndarray, z: np.ndarray, grad: np.ndarray) -> None:
        _fs, _df, g, jac, _fp, _v = prob.evaluate(z, needs_grad and grad.size > 0)
        result[:] = g
        if grad.size > 0:
            grad[:] = jac

    o.set_min_objective(f)
    o.add_inequality_mconstraint(c, np.zeros(m))
    o.set_xtol_rel(opt_cfg.xtol_rel)
    o.set_ftol_rel(opt_cfg.ftol_rel)
    o.set_maxeval(int(maxeval))
    if algo == "cobyla":
        o.set_initial_step(np.full(prob.n, 0.02))
    if algo == "isres":
        nlopt.srand(int(opt_cfg.seed))
    z = np.clip(z0, lo, hi)
    try:
        z = o.optimize(z)
        code = o.last_optimize_result()
        msg = NLOPT_RESULTS.get(code, str(code))
        ok = code in NLOPT_CONVERGED
    except nlopt.RoundoffLimited:
        msg = "roundoff limited (stopped; best point of the run kept)"
        z = seen[0][1] if seen else z
        ok = False
    except _failures(nlopt) as exc:      # nlopt's generic failure (NLOPT_FAILURE), e.g. SLSQP's LSQ
        msg = f"failure: {exc or 'nlopt failure'} (stopped; best point of the run kept)"
        z = seen[0][1] if seen else z
        ok = False
    except _Stalled:                     # the project's own ftol criterion over many evaluations
        msg = f"no gain of ftol_rel in {stall} evaluations (best point of the run kept)"
        z = seen[0][1]
        ok = True
    fz, _d, gz, _j, _p, _v = prob.evaluate(np.asarray(z, float), False)
    gz_max = float(np.max(gz))
    end_key = (True, gz_max) if gz_max > FEASIBLE_TOL else (False, fz)
    if seen and seen[0][0] < end_key:
        z = seen[0][1]
    return np.asarray(z, dtype=float), f"{algo}: {msg}", ok


def _run_penalty(prob: ScaledProblem, z0: np.ndarray, opt_cfg: Any, maxeval: int, tracker: Tracker
                 ) -> tuple[np.ndarray, str, bool]:
    """The thesis' exterior penalty method (Eq. 5.14–5.15) with BOBYQA as the unconstrained
    minimiser; r_p grows ×10 per round."""
    nlopt = _nlopt()
    lo, hi = _bounds(prob)
    z = np.clip(z0, lo, hi)
    rp = opt_cfg.penalty
    msg = "no round run (budget too small)"
    ok = False
    stall = 10 * prob.n
    used0 = tracker.evaluations
    base_phase = tracker.phase
    for k in range(opt_cfg.penalty_rounds):
        left = maxeval - (tracker.evaluations - used0)
        if left < 2 * prob.n + 3:
            break
        tracker.phase = f"{base_phase} r_p={rp:g}"

        best: list[Any] = [math.inf, 0, z]   # best Ω of the round, evaluations since, its point

        def omega(zz: np.ndarray, grad: np.ndarray, rp=rp, best=best) -> float:
            fs, _df, g, _j, fp, viol = prob.evaluate(zz, False)
            tracker.record(prob.p_of(zz), fp, viol)
            pen = float(np.sum(np.maximum(g, 0.0) ** 2))               # Eq. 5.15
            base = fs if math.isfinite(fs) else 10.0
            val = base + rp * pen                                        # Eq. 5.14
            if val < best[0]:
                gain = best[0] - val > 1e-7 * abs(val) or not math.isfinite(best[0])
                best[0], best[2] = val, zz.copy()
                if gain:
                    best[1] = 0
            else:
                best[1] += 1
                if best[1] > stall:
                    raise _Stalled()
            return val

        o = nlopt.opt(nlopt.LN_BOBYQA, prob.n)
        o.set_lower_bounds(lo)
        o.set_upper_bounds(hi)
        o.set_min_objective(omega)
        # the times jump by whole turns: tolerances near the rounding of the path make no sense
        o.set_xtol_rel(max(opt_cfg.xtol_rel, 1e-5))
        o.set_ftol_rel(max(opt_cfg.ftol_rel, 1e-7))
        o.set_maxeval(int(left))
        o.set_initial_step(np.full(prob.n, 0.02 if k == 0 else 0.005))
        try:
            z = np.asarray(o.optimize(z), dtype=float)
            code = o.last_optimize_result()
            msg = NLOPT_RESULTS.get(code, str(code))
            ok = code in NLOPT_CONVERGED
        except nlopt.RoundoffLimited:
            msg = "roundoff limited"
            ok = False
        except _failures(nlopt) as exc:
            msg = f"failure: {exc or 'nlopt failure'}"
            z = best[2]
            ok = False
        except _Stalled:
            msg = f"no gain in {stall} evaluations"
            z = best[2]
            ok = True
        g = prob.evaluate(z, False)[2]
        if k >= 1 and float(np.max(g)) <= 0.0:
            break
        rp *= 10.0
    tracker.phase = base_phase
    return z, f"bobyqa + exterior penalty (last r_p = {rp:g}): {msg}", ok


# ---- the driver ---------------------------------------------------------------------------
@dataclass(frozen=True)
class StartJob:
    """One local run of an optimisation, as :func:`run_start` takes it: plain values, so that it
    can run in another process or on another machine with the same result.

    ``index`` 0 is the run from the spec's own design (with the objective's phases: the size
    stand-in and the orientation scan of a machining time, ISRES first for ``isres``); index k ≥ 1
    is ``multistart``'s random start k + 1 from ``z`` (scaled variables, drawn by
    :func:`optimise` before any run, in start order)."""

    index: int
    spec: CamSpec                  # the settings applied
    z: np.ndarray | None           # the random start (scaled); None for index 0
    budget: int                    # the whole optimisation's budget (the progress bar's total)


@dataclass
class StartOutcome:
    """What one :class:`StartJob` gave: its result (None when it was cancelled), the key
    :func:`optimise` picks the best result by, and its evaluations, history and best points."""

    index: int
    p: np.ndarray | None
    key: tuple[bool, float] | None     # (fails the dense check or no finite value, final value); None: not valid
    solver_status: str
    solver_ok: bool
    messages: list[str]
    evaluations: int
    history: list[dict[str, Any]]
    best_feasible: tuple[float, np.ndarray] | None
    best_any: tuple[float, float, np.ndarray] | None
    windows: int | None
    cancelled: bool


class _CancelFlag:
    """The tracker's ``cancel`` for a job: asks the executor's task context."""

    def __init__(self, ctx: TaskContext):
        self._ctx = ctx

    def is_set(self) -> bool:
        return self._ctx.cancelled()


class _StartRunner:
    """The solver phases of one start (what :func:`optimise` did in one process before the
    starts could run anywhere)."""

    def __init__(self, spec: CamSpec, tracker: Tracker):
        self.cfg = spec.optimise
        self.space = DesignSpace(spec)
        self.model = SmoothModel(self.space)
        self.obj = make_objective(self.cfg.objective, self.model)
        self.tracker = tracker
        self.messages: list[str] = []
        self.last: tuple[str, bool] = ("", False)     # the latest solver run: (status text, converged)
        self.windows: int | None = None
        algo = self.cfg.algorithm
        if self.cfg.objective in TIME:
            self.local = "bobyqa" if algo in ("auto", "isres") else algo
        else:
            self.local = "slsqp" if algo in ("auto", "isres") else algo

    def solve_local(self, prob: ScaledProblem, z0: np.ndarray, local_algo: str, maxeval: int) -> np.ndarray:
        if local_algo in LOCAL_GRADIENT or local_algo in ("cobyla", "isres"):
            z, msg, ok = _run_nlopt(prob, local_algo, z0, self.cfg, maxeval, self.tracker)
        else:
            z, msg, ok = _run_penalty(prob, z0, self.cfg, maxeval, self.tracker)
        self.messages.append(msg)
        self.last = (msg, ok)
        return z

    def solve_phase(self, o: Objective, local_algo: str, p0: np.ndarray, phase: str, global_first: bool = False,
                    final: bool = True) -> np.ndarray:
        """Solve; while the independent dense check fails, re-solve from there with twice the
        windows (at most ``refine_rounds`` times)."""
        cfg, space, tracker = self.cfg, self.space, self.tracker
        p = p0
        windows = min(cfg.windows, CCSA_WINDOWS) if local_algo in ("mma", "ccsaq") else cfg.windows
        rounds = cfg.refine_rounds if local_algo not in ("mma", "ccsaq") else min(cfg.refine_rounds, 1)
        for rnd in range(rounds + 1 if final else 1):
            tracker.phase = phase if rnd == 0 else f"{phase} ({windows} windows)"
            prob = ScaledProblem(space, self.model, o, cfg.constraint_margin, _objective_value(o, space, p), windows)
            z0 = space.to_z(p)
            if prob.epigraph:
                z0 = np.append(z0, prob.t0(p))
            if global_first and rnd == 0:
                z0 = self.solve_local(prob, z0, "isres", cfg.max_evaluations)
            z = self.solve_local(prob, z0, local_algo, cfg.max_evaluations)
            p_prev = p
            p = _polish(space, prob.p_of(z))
            bf = tracker.best_feasible
            if bf is not None and bf[0] < _objective_value(o, space, p) * (1 - 1e-12):
                p = _polish(space, bf[1])          # derivative-free runs end near, not at, their best
            if not space.is_valid(p):
                # a run that ended outside the follower's geometry (the arm cannot reach the prime
                # circle, …) — only possible when it stopped early and infeasible: keep its start
                self.messages.append(f"{tracker.phase}: the run ended outside the follower's geometry "
                                     f"({space.invalid_reason(p)}); its starting design kept")
                p = p_prev
            self.windows = windows
            if not final or (space.is_valid(p) and run_checks(space.spec_at(p)).passed):
                break
            windows *= 2
        return p

    def first(self) -> np.ndarray:
        """The run from the spec's own design, with the objective's phases."""
        cfg, space, tracker = self.cfg, self.space, self.tracker
        algo = cfg.algorithm
        p = space.p0.copy()
        phase = "isres + " + self.local if algo == "isres" else self.local
        if cfg.objective in TIME and algo == "auto":
            sur = make_objective(SURROGATE[cfg.objective], self.model)
            p = self.solve_phase(sur, "slsqp", p, f"slsqp on {sur.name}", final=False)
            tracker.new_objective()
            if space.b_index is not None:
                tracker.phase = "orientation scan"
                p = _orientation_scan(self.obj, space, self.model, p, tracker)
        return self.solve_phase(self.obj, self.local, p, phase, global_first=(algo == "isres"))


def run_start(job: StartJob, ctx: TaskContext) -> StartOutcome:
    """Run one start of an optimisation (the task :func:`optimise` hands its executor): every
    evaluation reports a :class:`Progress` (as a dict) through ``ctx.report``, and the run stops
    with its best points when ``ctx.cancelled()`` says so.  Its result does not depend on the
    process it runs in."""
    tracker = Tracker(job.budget, lambda p: ctx.report(dataclasses.asdict(p)), _CancelFlag(ctx))
    runner = _StartRunner(job.spec, tracker)
    space = runner.space
    p: np.ndarray | None = None
    key: tuple[bool, float] | None = None
    cancelled = False
    try:
        if job.index == 0:
            p = runner.first()
        else:
            tracker.phase = f"start {job.index + 1}"
            p = runner.solve_phase(runner.obj, runner.local, space.to_p(np.asarray(job.z, dtype=float)),
                                   f"start {job.index + 1}")
        key = _pick_key(runner.cfg.objective, space, p)
    except Cancelled:
        p, key, cancelled = None, None, True
    return StartOutcome(index=job.index, p=p, key=key, solver_status=runner.last[0], solver_ok=runner.last[1],
                        messages=runner.messages, evaluations=tracker.evaluations, history=tracker.history,
                        best_feasible=tracker.best_feasible, best_any=tracker.best_any, windows=runner.windows,
                        cancelled=cancelled)


class _Progress:
    """The progress of every start together, for the caller's callback (called in the caller's
    thread): evaluations summed over the starts, the best feasible objective of any start."""

    def __init__(self, budget: int, progress: Callable[[Progress], Any] | None, cancel: threading.Event | None):
        self.budget = budget
        self.progress = progress
        self.cancel = cancel
        self.counts: dict[int, int] = {}
        self.bests: dict[int, float] = {}
        self.stop = False

    def on_progress(self, index: int, info: dict[str, Any]) -> None:
        self.counts[index] = int(info["evaluations"])
        if info["best"] is None:
            self.bests.pop(index, None)
        else:
            self.bests[index] = float(info["best"])
        if self.progress is None:
            return
        best = min(self.bests.values()) if self.bests else None
        if self.progress(Progress(sum(self.counts.values()), self.budget, info["phase"], info["objective"],
                                  info["max_violation"], best)) is False:
            self.stop = True

    def should_stop(self) -> bool:
        return self.stop or (self.cancel is not None and self.cancel.is_set())


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
    changes = {f"optimise.{k}": v for k, v in settings.items()}
    if objective is not None:
        changes["optimise.objective"] = objective
    if variables is not None:
        changes["optimise.variables"] = variables
    if algorithm is not None:
        changes["optimise.algorithm"] = algorithm
    for key in changes:
        if key.split(".", 1)[1] not in spec.optimise.__dataclass_fields__:
            raise SpecError(key, "unknown optimiser setting")
    spec = spec.replace(**changes) if changes else spec
    own = own_optimiser(spec)
    if own is not None:          # a body with an optimiser of its own (the cylindrical cam's)
        return own(spec, progress=progress, cancel=cancel)
    cfg = spec.optimise
    space = DesignSpace(spec)
    space.check_start()
    model = SmoothModel(space)
    obj = make_objective(cfg.objective, model)
    algo = cfg.algorithm
    runs = 1 + cfg.multistart
    budget = cfg.max_evaluations * runs * (2 if cfg.objective in TIME and algo == "auto" else 1)
    details: dict[str, Any] = {}
    p_init = space.p0.copy()
    f_init_model = _objective_value(obj, space, p_init)
    # the start's objective, independently: a start that cannot be built (gcode_time builds the cam)
    # is refused here, before any solver work, by the CamError that says why
    v0 = final_value(cfg.objective, spec)

    # every start's random numbers first, in start order: the runs may then go anywhere
    jobs = [StartJob(0, spec, None, budget)]
    skipped: dict[int, str] = {}
    rng = np.random.default_rng(cfg.seed)
    for i in range(cfg.multistart):
        z_rand = _random_start(space, rng)
        if z_rand is None:
            skipped[i + 1] = f"start {i + 2}: no random design of the box builds (skipped)"
        else:
            jobs.append(StartJob(i + 1, spec, z_rand, budget))
    agg = _Progress(budget, progress, cancel)
    ran = (executor or SerialExecutor()).run(run_start, jobs, on_progress=agg.on_progress,
                                             should_stop=agg.should_stop)
    outcomes: dict[int, StartOutcome] = {o.index: o for o in ran if o is not NOT_RUN}
    cancelled = len(outcomes) < len(jobs) or any(o.cancelled for o in outcomes.values())
    messages: list[str] = []
    history: list[dict[str, Any]] = []
    evaluations = 0
    for k in range(runs):
        if k in skipped:
            messages.append(skipped[k])
        if k in outcomes:
            o = outcomes[k]
            messages.extend(o.messages)
            for h in o.history:
                history.append({**h, "iteration": evaluations + h["iteration"]})
            evaluations += o.evaluations
    status = "converged"
    if not cancelled:
        best: tuple[tuple[bool, float], int] | None = None
        for k in sorted(outcomes):          # the first best in start order
            key = outcomes[k].key
            if key is not None and (best is None or key < best[0]):
                best = (key, k)
        chosen = outcomes[best[1] if best is not None else 0]
        p_best = chosen.p
        solver_status, solver_ok = chosen.solver_status, chosen.solver_ok
        if chosen.windows is not None:
            details["windows"] = chosen.windows
    else:
        status = "cancelled"
        solver_status, solver_ok = "cancelled (forced stop after the evaluation in progress)", False
        best_feasible: tuple[float, np.ndarray] | None = None
        best_any: tuple[float, float, np.ndarray] | None = None
        for k in sorted(outcomes):          # as one tracker over the starts in order would see them
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
        p_best = _polish(space, p_best)
        if not space.is_valid(p_best):
            p_best = p_init
        if 0 in outcomes and outcomes[0].windows is not None:
            details["windows"] = outcomes[0].windows
    final_spec = space.spec_at(p_best)
    try:
        v1 = final_value(cfg.objective, final_spec)
    except CamError as exc:        # gcode_time: the result cannot be built — the start is kept
        messages.append(f"the result cannot be built ({exc}): the starting design kept")
        p_best, final_spec, v1 = p_init, spec, v0
        solver_ok = False
    checks = run_checks(final_spec)
    initial_checks = run_checks(spec)
    details["areas"] = {"initial": area_summary(spec), "final": area_summary(final_spec)}
    if cfg.objective == "machining_time":
        details["cutting_time"] = {"initial": thesis_cutting_time(spec).summary(),
                                   "final": thesis_cutting_time(final_spec).summary()}
    details["constraint_margin"] = cfg.constraint_margin
    details["model_objective_initial"] = f_init_model
    details["workers"] = int(getattr(executor, "workers", 1)) if executor is not None else 1
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
        spec=final_spec, initial_spec=spec, objective=cfg.objective, algorithm=algo,
        initial_value=v0, value=v1, variables=space.labels, initial_design=p_init, design=p_best,
        history=history, evaluations=evaluations, time_s=time.perf_counter() - t_start,
        status=status, message=message, checks=checks, initial_checks=initial_checks, details=details,
        solver_status=solver_status)


def final_value(objective: str, spec: CamSpec) -> float:
    """The objective of ``spec`` computed independently of the optimiser's model: exact areas
    (:mod:`cam_workbench.generators.checks.areas`), the cutting times at full resolution, and the dense, refined
    extrema of the design checks for the peak objectives."""
    if objective == "area":
        return thesis_area(spec) if area_is_thesis(spec) else pitch_area(spec)
    if objective == "profile_area":
        return profile_area(spec)
    if objective == "machining_time":
        return thesis_cutting_time(spec).time
    if objective == "gcode_time":
        return contour_time(design_cam(spec)).time
    if objective == "outer_diameter":
        return float(spec.cam.outer_diameter)
    ext = run_checks(spec).extremes
    if objective == "peak_acceleration":
        return abs(float(ext["reduced_acceleration"]["value"]))
    return abs(float(ext["pressure_angle"]["value"]))


def area_is_thesis(spec: CamSpec) -> bool:
    """True when the objective "area" of ``spec`` is the thesis' Eq. 4.21 (a translating knife
    edge or roller), False when it is the area inside the design curve (every other follower:
    the pitch curve of an oscillating knife/roller, the profile of a flat face)."""
    return kind_model(spec).area_integral == "thesis_area"


def _objective_value(obj: Objective, space: DesignSpace, p: np.ndarray) -> float:
    try:
        v = obj.value(p, False)[0]
    except (CamError, ValueError, FloatingPointError):
        return float("nan")
    return float(v)


def _polish(space: DesignSpace, p: np.ndarray) -> np.ndarray:
    """Remove the solver's round-off violations of the linear constraints (≤ 1e-6): lifts made
    exactly monotonic, control angles at least the gap apart."""
    p = np.clip(np.asarray(p, dtype=float).copy(), space.lower, space.upper)
    for blk in space.blocks:
        x, y = blk.arrays(p)
        if blk.y_cols.size:
            y2 = np.maximum.accumulate(y) if blk.kind == "rise" else np.minimum.accumulate(y)
            if np.max(np.abs(y2 - y)) <= 1e-6:
                p[blk.y_cols] = y2[blk.y_free]
        if blk.x_cols.size:
            x2 = x.copy()
            for i in range(1, x.size - 1):
                x2[i] = max(x2[i], x2[i - 1] + space.gap)
            if np.max(np.abs(x2 - x)) <= 1e-6 and x2[-2] <= x2[-1] - space.gap * 0.999:
                p[blk.x_cols] = x2[1:-1]
    return p


def _orientation_scan(obj: Objective, space: DesignSpace, model: SmoothModel, p: np.ndarray,
                      tracker: Tracker) -> np.ndarray:
    """The blank orientation at 1° steps over a quarter turn (the thesis' path repeats after 90°)."""
    best = (math.inf, p)
    b0 = p[space.b_index]
    cons = model.check_rows(p, False)[0]
    viol = float(np.max(cons)) if cons.size else -1.0        # the orientation changes no check
    if space.linear_A.shape[0]:
        viol = max(viol, float(np.max(space.linear_values(p))))
    for d in np.arange(-45.0, 45.0, 1.0):
        q = p.copy()
        q[space.b_index] = np.clip(b0 + math.radians(d), space.lower[space.b_index], space.upper[space.b_index])
        f = _objective_value(obj, space, q)
        tracker.record(q, f, viol)
        if f < best[0]:
            best = (f, q)
    return best[1]


def _random_start(space: DesignSpace, rng: np.random.Generator, tries: int = 200) -> np.ndarray | None:
    """A random design in the box with valid control polygons (sorted angles, monotonic lifts)
    that is a valid spec (an oscillating arm reaches the prime circle: redrawn up to ``tries``
    times; None if none does)."""
    for _ in range(tries):
        z = _random_point(space, rng)
        if space.is_valid(space.to_p(z)):
            return z
    return None


def _random_point(space: DesignSpace, rng: np.random.Generator) -> np.ndarray:
    z = rng.uniform(0.0, 1.0, space.n)
    p = space.to_p(z)
    for blk in space.blocks:
        if blk.x_cols.size:
            m = blk.x_cols.size
            inc = rng.dirichlet(np.ones(m + 1))
            usable = blk.span - (m + 1) * space.gap
            p[blk.x_cols] = space.gap * np.arange(1, m + 1) + usable * np.cumsum(inc)[:-1]
        if blk.y_cols.size:
            ys = np.sort(rng.uniform(0.0, 1.0, blk.y_cols.size))
            p[blk.y_cols] = ys if blk.kind == "rise" else ys[::-1]
    return space.to_z(np.clip(p, space.lower, space.upper))


def _pick_key(objective: str, space: DesignSpace, p: np.ndarray) -> tuple[bool, float] | None:
    """How :func:`optimise` ranks a start's result: (fails the dense check or has no finite
    objective, the objective) — smaller is better; None for a design outside the follower's
    geometry (never picked)."""
    if not space.is_valid(p):
        return None
    spec = space.spec_at(p)
    try:
        value = final_value(objective, spec)
    except CamError:           # gcode_time: a candidate that cannot be built comes last
        value = math.inf
    return (not run_checks(spec).passed or not math.isfinite(value), value)


def _pick(objective: str, space: DesignSpace, candidates: list[np.ndarray]) -> int:
    """The index of the best candidate: passing the dense check first, then the smallest objective."""
    best = None
    for i, p in enumerate(candidates):
        key = _pick_key(objective, space, p)
        if key is not None and (best is None or key < best[0]):
            best = (key, i)
    return best[1]

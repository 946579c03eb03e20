"""The solver runs: nlopt (imported lazily) and the exterior-penalty rounds, the phases of one start
(:class:`StartRunner`: the size stand-in, the orientation scan, ISRES, the re-solves with more
windows), and the clean-up of a solver's point (:func:`polish`).
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..checks.design import run_checks
from ..errors import CamError
from ..spec.model import CamSpec
from .model import SmoothModel
from .objectives import SURROGATE, TIME, Objective, make_objective
from .problem import ScaledProblem, Stalled, Tracker
from .settings import CCSA_WINDOWS, FEASIBLE_TOL, LOCAL_GRADIENT, NLOPT_CONVERGED, NLOPT_RESULTS
from .space import DesignSpace


# ---- nlopt runs -------------------------------------------------------------------------------
def load_nlopt():
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
    nlopt = load_nlopt()
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
            raise Stalled()
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
    except Stalled:                     # the project's own ftol criterion over many evaluations
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
    nlopt = load_nlopt()
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
                    raise Stalled()
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
        except Stalled:
            msg = f"no gain in {stall} evaluations"
            z = best[2]
            ok = True
        g = prob.evaluate(z, False)[2]
        if k >= 1 and float(np.max(g)) <= 0.0:
            break
        rp *= 10.0
    tracker.phase = base_phase
    return z, f"bobyqa + exterior penalty (last r_p = {rp:g}): {msg}", ok


class StartRunner:
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
            prob = ScaledProblem(space, self.model, o, cfg.constraint_margin, objective_value(o, space, p), windows)
            z0 = space.to_z(p)
            if prob.epigraph:
                z0 = np.append(z0, prob.t0(p))
            if global_first and rnd == 0:
                z0 = self.solve_local(prob, z0, "isres", cfg.max_evaluations)
            z = self.solve_local(prob, z0, local_algo, cfg.max_evaluations)
            p_prev = p
            p = polish(space, prob.p_of(z))
            bf = tracker.best_feasible
            if bf is not None and bf[0] < objective_value(o, space, p) * (1 - 1e-12):
                p = polish(space, bf[1])          # derivative-free runs end near, not at, their best
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


def objective_value(obj: Objective, space: DesignSpace, p: np.ndarray) -> float:
    try:
        v = obj.value(p, False)[0]
    except (CamError, ValueError, FloatingPointError):
        return float("nan")
    return float(v)


def polish(space: DesignSpace, p: np.ndarray) -> np.ndarray:
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
        f = objective_value(obj, space, q)
        tracker.record(q, f, viol)
        if f < best[0]:
            best = (f, q)
    return best[1]

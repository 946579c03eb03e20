"""The problem nlopt sees: :class:`ScaledProblem` (objective and constraints in scaled variables, with
the epigraph of a peak objective), the compression of huge constraint values, and :class:`Tracker`,
which counts the evaluations, keeps the best points and reports progress and cancellation.
"""
from __future__ import annotations

import math
import threading
from typing import Any, Callable

import numpy as np

from ..errors import CamError
from .model import SmoothModel
from .objectives import PEAK, Objective
from .result import Progress
from .space import DesignSpace


class Cancelled(Exception):
    """Raised inside the solver's callback to stop it."""


class Stalled(Exception):
    """A run stops making progress (raised in the callback; the run's best point is kept)."""


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

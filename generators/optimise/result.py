"""What an optimisation reports: :class:`Progress` (after every evaluation), :class:`OptimiseResult`
(report.json's ``optimise`` section), the worst constraint of a design, and :func:`final_value`, the
objective computed independently of the optimiser's model.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..cam_design import design_cam
from ..checks.areas import pitch_area, profile_area, thesis_area
from ..checks.design import DesignChecks, run_checks
from ..machining.cutting_time import contour_time, thesis_cutting_time
from ..spec.model import CamSpec
from .kinds import force_reference, kind_model
from .objectives import UNITS, describe, label as objective_label, report_key


HISTORY_MAX = 400


@dataclass(frozen=True)
class Progress:
    """What the progress callback receives after every evaluation."""

    evaluations: int          # so far, all phases
    budget: int               # planned most (the bar's total; a run may stop earlier)
    phase: str                # e.g. "slsqp", "orientation scan", "bobyqa r_p=100", "refine 2"
    objective: float          # this evaluation's objective (physical units; NaN if not computed)
    max_violation: float      # largest normalised constraint value (≤ 0 feasible)
    best: float | None        # best feasible objective so far


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

"""The optimiser of the spatial indexers (``cam.body = "barrel_indexer"``, ``"globoidal_indexer"``): the
spec's ``[optimise]`` settings as the parallel indexer's optimiser takes them
(:mod:`cam_workbench.generators.optimise.indexer`: its algorithms, refusals, pull-back and report), the
nlopt search of :func:`cam_workbench.generators.optimise.parallel_indexer.run_restarts` on the geometry and
the drive at the body's own :data:`SAMPLES` input angles (without the flank surfaces), the optimum designed
again and checked by the body.

Design variables x = (C, s, r_r), spec paths :func:`spatial_paths`:

* ``indexer.centre_distance`` C;
* the turret's size s — barrel: ``indexer.pitch_radius`` R_p (the rollers' circle); globoid:
  ``indexer.roller_end`` t1 (how far the rollers reach from the turret axis).  The turret's other
  lengths follow s as fixed fractions of it, their start's (k = s/s₀ scales them): barrel
  ``roller_start``, ``roller_end``, ``root_radius``, ``outer_radius`` and ``cam.thickness``; globoid
  ``roller_start``, ``tip_radius``, ``root_radius`` and ``cam.thickness`` (the rib globoids are
  distances from the turret's axis circle, so C moves the cam's radii and s the turret's); and
  ``follower.roller_width`` when given.  So the rib stays under the rollers and the cam's length
  holds the same engaged rollers whatever s: every geometry rule that holds at the start holds
  at any k, and the shape changes only through the ratios C/s and r_r/s;
* ``follower.roller_radius`` r_r.

Bounds (report.json ``optimise.bounds``), the parallel indexer's factors of the start
(:data:`~cam_workbench.generators.optimise.parallel_indexer.DEFAULT_BOUNDS`): C ∈ [0.5, 2]·C₀,
s ∈ [0.5, 2]·s₀, r_r ∈ [0.5, 1.5]·r_r₀.

Objectives (``optimise.objective``; "area", the spec's default, is taken as "size"):

* ``"size"`` — the cam's outer radius [mm]: barrel the rib's top cylinder ``indexer.outer_radius``
  (report.json ``indexer.geometry.outer_radius``); globoid the tip globoid's largest radius, at the
  cam's end faces, C − √(tip_radius² − (W/2)²) (W = ``cam.thickness``; the blank's outer radius);
* ``"normal_force"`` — the peak roller load [N] of the design's drive
  (``indexer.drive.normal_force_peak_N``), which needs the load ``indexer.output_inertia``.  (The peak
  input torque is no objective here, as for the parallel indexer: by virtual work it depends on the
  law and the load alone.)

The pressure angle, the undercut margin and the locking are invariant under a uniform scaling of
(C, s, r_r) (the turret's lengths follow s): "size" shrinks the drive until the contact stress
(``material.allowable_stress``, with a load), the bore (``cam.bore_diameter`` inside the core) or a
lower bound stops it; "normal_force" grows the turret (a longer arm) until an upper bound or a
check stops it.

The solver's constraints (g ≤ 0, :data:`CONSTRAINTS`), at :data:`SAMPLES` input angles and
:data:`LENGTHS` points along each roller: the geometry builds; the driving contact's pressure angle
≤ (1 − ``optimise.constraint_margin``)·``indexer.max_pressure_angle``; the regularity margin ≥
:data:`MIN_MARGIN`; the rib thickness ≥ :data:`MIN_RIB` mm; each way at least one engaged contact
(positive drive); the peak contact stress ≤ :data:`STRESS_FRACTION` × ``material.allowable_stress`` (with
a load and a limit); the bore radius below the core's least radius.  The body's own checks then decide: a solver optimum that fails one is pulled
back toward the start along x(t) = x₀·(x*/x₀)^t (t bisected to 1/2⁸), as the parallel indexer's is
(:func:`cam_workbench.generators.optimise.indexer.pull_back`).
"""
from __future__ import annotations

import dataclasses
import math
import time
from typing import Any, Callable

import numpy as np

from ..bodies.indexing import from_spec
from ..bodies.indexing.spatial import BarrelIndexer
from ..bodies.indexing.spatial_drive import spatial_drive
from ..bodies.indexing.spatial_kind import LENGTHS as BODY_LENGTHS, SAMPLES as BODY_SAMPLES
from ..bodies.indexing.spatial_kind import BarrelIndexerBody, GloboidalIndexerBody, SpatialIndexerDesign
from ..errors import SpecError
from ..kinds import register_optimiser
from ..spec.indexer import indexer_value
from ..spec.model import CamSpec
from .indexer import ALGORITHMS, PLANE_BOUNDS, design_checks, pull_back
from .parallel_indexer import DEFAULT_BOUNDS, run_restarts
from .result import OptimiseResult, Progress
from .settings import NLOPT_CONVERGED
from ..checks.design import CheckResult, DesignChecks

BODIES = {BarrelIndexerBody.kind: BarrelIndexerBody, GloboidalIndexerBody.kind: GloboidalIndexerBody}
#: the solver's variables (C, the turret's size s, r_r) and their bound factors (the parallel indexer's)
VARIABLES = ("centre_distance", "turret", "roller_radius")
BOUND_FACTORS = (DEFAULT_BOUNDS["centre_distance"], DEFAULT_BOUNDS["pitch_radius"], DEFAULT_BOUNDS["roller_radius"])
#: the geometry field that is the turret's size, per body
TURRET = {BarrelIndexerBody.kind: "pitch_radius", GloboidalIndexerBody.kind: "roller_end"}
#: the geometry's lengths that follow the turret's size (fixed fractions of it), per body
FOLLOWERS = {BarrelIndexerBody.kind: ("roller_start", "roller_end", "root_radius", "outer_radius", "cam_width"),
             GloboidalIndexerBody.kind: ("roller_start", "tip_radius", "root_radius", "cam_width")}
#: the solver's constraints, in the order of a trial's g
CONSTRAINTS = ("geometry", "pressure_angle", "undercut", "rib_thickness", "locking", "contact_stress", "bore")
#: input angles and points along each roller per solver trial: the body's own (its drive's peak contact stress
#: jumps with the grid — whether a sample falls in the short window where a roller's engaged length is least:
#: measured on one globoid 1296 MPa at 361 and 541 input angles, 2544 MPa at 481, 721 and 1441 — so a
#: coarser grid misleads the solver)
SAMPLES, LENGTHS = BODY_SAMPLES, BODY_LENGTHS
#: the solver's least regularity margin and rib thickness [mm] (the body's checks: > 0)
MIN_MARGIN, MIN_RIB = 0.05, 1.0
#: the solver's contact-stress limit as a fraction of material.allowable_stress
STRESS_FRACTION = 0.99
#: what "size" is, per body (report.json's objective_label / _description / _key of the result)
SIZE_WORDS = {
    BarrelIndexerBody.kind: ("outer radius of the barrel (the rib's top cylinder)",
                       "the barrel cam's outer radius: the rib's top cylinder indexer.outer_radius",
                       "indexer.geometry.outer_radius"),
    GloboidalIndexerBody.kind: ("outer radius of the globoidal cam (its tip globoid at the end faces)",
                          "the globoidal cam's outer radius: C - sqrt(tip_radius^2 - (W/2)^2), the tip globoid "
                          "at the end faces |z| = W/2 (W = cam.thickness)", None),
}


def _spec_path(name: str) -> str:
    return "cam.thickness" if name == "cam_width" else "follower.roller_radius" if name == "roller_radius" \
        else f"indexer.{name}"


def spatial_paths(spec: CamSpec) -> dict[str, str]:
    """The spec path of each design variable (C, the turret's size s, r_r) of ``spec``'s body."""
    return {"centre_distance": "indexer.centre_distance", "turret": f"indexer.{TURRET[spec.cam.body]}",
            "roller_radius": "follower.roller_radius"}


def spatial_objective(spec: CamSpec) -> str:
    """The objective of ``spec``'s ``optimise.objective`` ("area", the default, is "size")."""
    name = spec.optimise.objective
    if name == "area":
        return "size"
    body = BODIES[spec.cam.body]
    if name not in body.optimise_objectives:
        raise SpecError("optimise.objective", f"a {body.title.lower()} is optimised for "
                        f"{' or '.join(body.optimise_objectives)} (\"area\", the default, is size), got {name!r}")
    return name


def spatial_arguments(spec: CamSpec) -> dict[str, Any]:
    """The run's settings from ``spec``'s ``[optimise]`` and ``[indexer]`` (module docstring);
    SpecError naming the spec's field for a setting that does not apply."""
    cfg = spec.optimise
    title = BODIES[spec.cam.body].title.lower()
    objective = spatial_objective(spec)
    if cfg.variables.strip() != "auto":
        raise SpecError("optimise.variables", f"a {title}'s design variables are "
                        f"{', '.join(spatial_paths(spec).values())}, all three: \"auto\", got {cfg.variables!r}")
    if cfg.algorithm not in ALGORITHMS:
        raise SpecError("optimise.algorithm", f"a {title}'s trials are full designs whose checks are maxima over "
                        f"samples: {', '.join(ALGORITHMS)} (derivative-free), got {cfg.algorithm!r}")
    if cfg.multistart:
        raise SpecError("optimise.multistart", f"a {title}'s optimiser runs from the spec's design alone "
                        f"(restarted from its best trial while it gains): 0, got {cfg.multistart}")
    for name in PLANE_BOUNDS:
        if getattr(cfg, name) is not None:
            raise SpecError(f"optimise.{name}", f"does not apply to a {title} (its variables' bounds are 0.5–2 × "
                            "the start's C and turret size, 0.5–1.5 × its r_r)")
    load = _load(spec)
    if objective == "normal_force" and load is None:
        raise SpecError("indexer.output_inertia", "objective normal_force (the peak roller load) needs the output's "
                        "load: give indexer.output_inertia [kg·mm²] (and indexer.friction_torque [N·mm])")
    return {"objective": objective, "load": load, "algorithm": ALGORITHMS[cfg.algorithm],
            "max_pressure_angle": math.radians(indexer_value(spec, "max_pressure_angle")) * (1.0 - cfg.constraint_margin),
            "allowable_stress": spec.material.allowable_stress, "max_evaluations": int(cfg.max_evaluations)}


def spatial_bounds(spec: CamSpec) -> dict[str, tuple[float, float]]:
    """The bounds of each design variable of ``spec`` (spec path → (lo, hi) [mm]): the factors of the
    start (report.json ``optimise.bounds`` after a run)."""
    return {path: (f[0] * float(x), f[1] * float(x))
            for path, x, f in zip(spatial_paths(spec).values(), _variables(spec), BOUND_FACTORS)}


def _load(spec: CamSpec) -> dict[str, float] | None:
    ix = spec.indexer
    return from_spec.load_arguments(spec, default_width=float(ix.roller_end) - float(ix.roller_start))


def _variables(spec: CamSpec) -> np.ndarray:
    return np.array([float(spec.indexer.centre_distance), float(getattr(spec.indexer, TURRET[spec.cam.body])),
                     float(spec.follower.roller_radius)])


def spec_at(spec: CamSpec, x: np.ndarray) -> CamSpec:
    """``spec`` with the design variables ``x`` (C, s, r_r): the turret's other lengths (and a given
    ``follower.roller_width``) scaled by s/s₀ (module docstring); ``cam.base_radius`` derived again."""
    x0 = _variables(spec)
    k = float(x[1]) / float(x0[1])
    ix0 = BODIES[spec.cam.body].make(spec)
    changes = {path: float(v) for path, v in zip(spatial_paths(spec).values(), x)}
    changes.update({_spec_path(n): float(getattr(ix0, n)) * k for n in FOLLOWERS[spec.cam.body]})
    if spec.follower.roller_width is not None:
        changes["follower.roller_width"] = float(spec.follower.roller_width) * k
    return spec.replace(**changes)


def outer_radius(ix: Any) -> float:
    """The cam's outer radius [mm] ("size"): the barrel's rib top, the globoid's tip globoid at its end faces."""
    if isinstance(ix, BarrelIndexer):
        return float(ix.outer_radius)
    h = 0.5 * float(ix.cam_width)
    tip = float(ix.tip_radius)
    return float(ix.centre_distance) - math.sqrt(max(tip * tip - h * h, 0.0))


def core_radius(ix: Any) -> float:
    """The core's least radius [mm] (``cam.base_radius``): the barrel's root, the globoid's waist C − root."""
    if isinstance(ix, BarrelIndexer):
        return float(ix.root_radius)
    return float(ix.centre_distance) - float(ix.root_radius)


@dataclasses.dataclass(frozen=True)
class SpatialTrial:
    """One solver trial: ``variables`` (C, s, r_r) [mm], ``value`` (NaN when it failed), ``g`` the
    normalised constraints (order :data:`CONSTRAINTS`, ≤ 0 satisfied), ``values`` the physical ones,
    ``design`` the geometry (None when it failed) and ``failure`` (why)."""

    variables: np.ndarray
    value: float
    g: np.ndarray
    values: dict[str, float]
    design: Any
    failure: str = ""

    @property
    def feasible(self) -> bool:
        return self.design is not None and bool(np.all(self.g <= 0.0))

    @property
    def violation(self) -> float:
        return float(np.max(self.g))

    @property
    def blocking(self) -> str:
        return CONSTRAINTS[int(np.argmax(self.g))]


class _Problem:
    """The trials (one design per distinct point, cached), the best feasible and the least violated."""

    def __init__(self, spec: CamSpec, args: dict[str, Any]):
        body = BODIES[spec.cam.body]
        self.ix0 = body.make(spec)
        self.designer = body.designer
        self.x0 = _variables(spec)
        self.kind = spec.cam.body
        self.objective, self.load = args["objective"], args["load"]
        self.max_pa = args["max_pressure_angle"]
        self.stress = args["allowable_stress"]
        self.bore = 0.5 * float(spec.cam.bore_diameter or 0.0)
        self.scale = 0.01 * float(self.x0[0])
        self.cache: dict[bytes, SpatialTrial] = {}
        self.best: SpatialTrial | None = None
        self.least: SpatialTrial | None = None

    def indexer_at(self, x: np.ndarray) -> Any:
        k = float(x[1]) / float(self.x0[1])
        fields = {n: float(getattr(self.ix0, n)) * k for n in FOLLOWERS[self.kind]}
        fields.update({"centre_distance": float(x[0]), TURRET[self.kind]: float(x[1]), "roller_radius": float(x[2])})
        return dataclasses.replace(self.ix0, **fields)

    def trial(self, x: np.ndarray) -> SpatialTrial:
        x = np.asarray(x, dtype=float)
        key = x.tobytes()
        if key in self.cache:
            return self.cache[key]
        t = self._evaluate(x)
        self.cache[key] = t
        if t.feasible and (self.best is None or t.value < self.best.value):
            self.best = t
        rank = (t.design is None, t.violation)
        if self.least is None or rank < (self.least.design is None, self.least.violation):
            self.least = t
        return t

    def _evaluate(self, x: np.ndarray) -> SpatialTrial:
        nan = math.nan
        failed = dict.fromkeys(("pressure_angle", "margin", "rib_thickness", "locking", "contact_stress"), nan)
        g = np.zeros(len(CONSTRAINTS))
        g[0] = 1.0
        try:
            ix = self.indexer_at(x)
            geo = self.designer(ix, SAMPLES, LENGTHS, False)
            load = None
            if self.load is not None:
                load = dict(self.load, roller_width=float(self.load["roller_width"]) * float(x[1]) / float(self.x0[1]))
            drive = None if load is None else spatial_drive(geo, **load)
        except SpecError as exc:
            return SpatialTrial(x, nan, g, failed, None, str(exc))
        except Exception as exc:  # noqa: BLE001 - a solver's trial must never end the run
            return SpatialTrial(x, nan, g, failed, None, f"{type(exc).__name__}: {exc}")
        pa = float(geo.max_driving_angle.value)
        margin, rib = float(geo.min_margin.value), float(geo.min_rib_thickness.value)
        fewest = float(geo.engaged.sum(axis=0).min())
        sigma = math.nan if drive is None else float(drive.contact_stress_peak) / 1e6
        s = self.scale
        g = np.array([
            -1.0,
            (pa - self.max_pa) / self.max_pa,
            MIN_MARGIN - margin,
            (MIN_RIB - rib) / s,
            1.0 - fewest,
            sigma / (STRESS_FRACTION * self.stress) - 1.0 if drive is not None and self.stress else -1.0,
            (self.bore - core_radius(ix)) / s + 1e-9,
        ])
        g = np.clip(np.nan_to_num(g, nan=1.0), -10.0, 10.0)
        values = {"pressure_angle": pa, "margin": margin, "rib_thickness": rib, "locking": fewest,
                  "contact_stress": sigma}
        value = outer_radius(ix) if self.objective == "size" else (
            float(drive.normal_force_peak) if drive is not None else nan)
        if not math.isfinite(value):
            g[0] = 1.0
            return SpatialTrial(x, nan, g, values, None, f"the objective is not finite ({value!r})")
        return SpatialTrial(x, value, g, values, geo)


class _Candidate:
    """A design the body built (or why not): its spec, design, checks and both objectives."""

    def __init__(self, spec: CamSpec, objective: str, x: np.ndarray | None = None):
        self.body = BODIES[spec.cam.body]
        self.x = _variables(spec) if x is None else np.asarray(x, dtype=float)
        self.spec: CamSpec | None = None
        self.design: SpatialIndexerDesign | None = None
        self.failure = ""
        self.value = math.nan
        self.measures: dict[str, float | None] = dict.fromkeys(self.body.optimise_objectives)
        try:
            self.spec = spec if x is None else spec_at(spec, self.x)
            self.design = self.body.design(self.spec)
        except SpecError as exc:
            self.failure = str(exc)
            return
        self.measures = {"size": outer_radius(self.design.geometry.indexer),
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
            try:
                report = self.body.own_checks(self.spec)
            except SpecError:
                report = None
        if report is not None:
            return design_checks(report, units)
        row = CheckResult("geometry", f"the design builds ({self.failure})", "max", None, None, None, "", "fail")
        return DesignChecks((row,), {}, "per_turn", 0, units, None)


def _solve(spec: CamSpec, args: dict[str, Any], on_trial: Callable[[Progress], bool]) -> dict[str, Any]:
    """The nlopt search (``run_restarts``) from the spec's design: the best trial and the solver's words."""
    prob = _Problem(spec, args)
    x0 = prob.x0
    lo = np.array([f[0] for f in BOUND_FACTORS]) * x0
    hi = np.array([f[1] for f in BOUND_FACTORS]) * x0
    algo = args["algorithm"]
    budget = args["max_evaluations"]
    count = [1]
    start = prob.trial(x0)

    def report(t: SpatialTrial) -> bool:
        best = prob.best.value if prob.best is not None else None
        return on_trial(Progress(count[0], budget, algo, t.value, t.violation, best)) is not False

    cancelled = not report(start)
    status, code = "", 0
    f_ref = start.value if start.design is not None and start.value > 0 else float(x0[0])
    if not cancelled and budget > 1:
        status, code, cancelled = run_restarts(prob, algo, x0, lo, hi, np.ones(3, dtype=bool), f_ref, budget, count,
                                               report, n_constraints=len(CONSTRAINTS))
    best = prob.best
    if best is not None:
        verdict = ("cancelled" if cancelled else "max evaluations" if code == 5 or count[0] >= budget
                   else "converged" if code in NLOPT_CONVERGED else "stopped")
        chosen, blocking = best, ""
    else:
        verdict = "cancelled" if cancelled else "no feasible point"
        chosen, blocking = prob.least, prob.least.blocking
    return {"verdict": verdict, "algorithm": algo, "x": chosen.variables, "value": best.value if best else math.nan,
            "start_value": start.value, "evaluations": len(prob.cache), "solver_status": status,
            "blocking": blocking, "bounds": (lo, hi), "constraints": dict(chosen.values)}


def optimise_spatial_indexer(spec: CamSpec, progress: Callable[[Any], Any] | None = None, cancel: Any = None) -> Any:
    """Optimise a barrel or globoidal indexer's C, turret size and r_r (module docstring): an
    :class:`OptimiseResult` whose ``spec`` is the optimised spec, designed and checked by the body.

    Raises:
        SpecError: a setting that does not apply (``optimise.*``), or objective normal_force without
            ``indexer.output_inertia``.
    """
    t0 = time.perf_counter()
    args = spatial_arguments(spec)
    objective = args["objective"]
    body = BODIES[spec.cam.body]
    paths = spatial_paths(spec)
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

    best = _solve(spec, args, on_trial)
    start = _Candidate(spec, objective)
    x_opt = np.asarray(best["x"], dtype=float)
    chosen = start
    messages = [f"{best['algorithm']}: {best['verdict']}" + (f" (blocking: {best['blocking']})" if best["blocking"]
                                                             else "")]
    pulled: float | None = None
    designs = 1
    if best["verdict"] != "no feasible point" and not np.allclose(x_opt, start.x, rtol=1e-12, atol=0.0):
        chosen, pulled, built, notes = pull_back(
            start, x_opt, lambda x: _Candidate(spec, objective, x), history,
            lambda: stopped[0] or (cancel is not None and cancel.is_set()))
        designs += built
        messages += notes
    final_spec = chosen.spec if chosen.spec is not None else spec
    checks, initial_checks = chosen.checks(spec.units), start.checks(spec.units)
    cancelled = best["verdict"] == "cancelled" or stopped[0]
    if cancelled:
        status = "cancelled"
    elif not checks.passed:
        status = "infeasible"
    elif best["verdict"] == "max evaluations":
        status = "budget exhausted"
    elif best["verdict"] != "converged":
        status = "stopped"
    else:
        status = "converged"
    if not checks.passed:
        messages.append(f"the final design FAILS the body's check: {', '.join(checks.failed)}")
    initial_value = start.value if math.isfinite(start.value) else float(best["start_value"])
    value = chosen.value if math.isfinite(chosen.value) else float(best["value"])
    lo_b, hi_b = best["bounds"]
    follow = [_spec_path(n) for n in FOLLOWERS[spec.cam.body]] + (
        ["follower.roller_width"] if spec.follower.roller_width is not None else [])
    details: dict[str, Any] = {
        "solver": f"nlopt {best['algorithm']} (derivative-free) on designs at {SAMPLES} input angles × {LENGTHS} "
                  "points per roller, the result designed and checked by the body",
        "bounds": {path: [float(a), float(b)] for path, a, b in zip(paths.values(), lo_b, hi_b)},
        "turret_scaled": {"variable": paths["turret"], "with_it": follow,
                          "what": f"fixed fractions of {paths['turret']} (the start's): they scale with it"},
        "max_pressure_angle_deg": math.degrees(args["max_pressure_angle"]), "samples": SAMPLES,
        "min_regularity_margin": MIN_MARGIN, "min_rib_thickness": MIN_RIB, "stress_fraction": STRESS_FRACTION,
        "constraint_margin": spec.optimise.constraint_margin,
        "solver_optimum": {"verdict": best["verdict"], "evaluations": best["evaluations"],
                           "variables": {p: float(v) for p, v in zip(paths.values(), x_opt)},
                           "value": float(best["value"]) if math.isfinite(best["value"]) else None},
        "pulled_back": pulled, "body_designs": designs,
        "measures": {name: {"initial": start.measures[name], "final": chosen.measures[name]}
                     for name in body.optimise_objectives},
    }
    if objective == "size":             # what "size" is on this body (objectives.py's words are the parallel's)
        label, description, key = SIZE_WORDS[spec.cam.body]
        details.update({"objective_label": label, "objective_description": description, "objective_key": key})
    return OptimiseResult(
        spec=final_spec, initial_spec=spec, objective=objective, algorithm=spec.optimise.algorithm,
        initial_value=initial_value, value=value, variables=tuple(paths.values()), initial_design=start.x,
        design=chosen.x, history=history, evaluations=best["evaluations"],
        time_s=time.perf_counter() - t0, status=status, message="; ".join(messages), checks=checks,
        initial_checks=initial_checks, details=details, solver_status=best["solver_status"])


for _kind in BODIES:
    register_optimiser(_kind)(optimise_spatial_indexer)

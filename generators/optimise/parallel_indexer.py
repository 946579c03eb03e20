"""A parallel indexer's geometry optimised with nlopt: :func:`optimise_parallel` chooses the centre
distance C, the turret's pitch radius R_p and the roller radius r_r (N, β, the law and the cams
fixed) for the smallest cam or the lightest load, subject to a pressure-angle limit, a clearance,
positive locking and a cam that can be built (no undercut, cusp or missing crossover).

Units: lengths in mm, angles in radians (degrees only in :meth:`ParallelOptimum.summary`), the
load in the units of :func:`cam_workbench.generators.bodies.indexing.parallel_drive.parallel_drive` (rev/min, kg·m², N·m, mm, N).

The problem (every trial is a full :func:`cam_workbench.generators.bodies.indexing.parallel.design_parallel` on ``samples`` input angles):

* variables x = (C, R_p, r_r) (x₀ the start, clipped into the bounds; a variable whose bounds are
  equal is fixed), seen by the solver in log units relative to the start, w = log(x/x₀) (a step of
  0.1 is 10 %), and with R_p free as y = (w_Rp, w_C − w_Rp, w_rr − w_Rp): the scale and the ratios
  C/R_p, r_r/R_p.  The pressure angles, the locking and whether the cam builds depend on the
  ratios alone and the size and the clearance scale with R_p, so the solver's axes separate what
  it trades; the bounds of C and r_r are then linear constraints in y;
* objective (divided by its reference, the start's value or a load-only one):

  - ``"size"``: the cam's outer radius [mm], the largest profile radius over the cams;
  - ``"normal_force"``: ``parallel_drive(design, **load).normal_force_peak`` [N], the peak roller
    load |T_out|/arm_P of the contact that carries it — the load objective the geometry moves.
    (Not the peak input torque: by virtual work T_in = T_out·ψ'/η depends on the law and the load
    alone, not on C, R_p or r_r, so it is no objective for this geometry.);

* the solver: nlopt from the start with an initial step of 10 % (a quarter of a narrower box),
  restarted from the best trial so far with a fresh step while a run gains (≥ 0.01 % of the best
  value, or of the least violation while none is feasible) — the unbuildable region is a wall the
  solver only sees as a failed trial, and one run tends to stall along it; the returned design
  is always an evaluated trial, so its constraints hold exactly at ``samples`` input angles;
* constraints g ≤ 0 (normalised; the names the verdict uses):

  - ``geometry``: the indexer validates and its design builds (a :class:`SpecError` of the
    geometry — no crossover, undercut, cusp, a profile that is not simple — or of the drive
    sizing makes the trial infeasible: g = +1; never an exception out of the solver);
  - ``pressure_angle``: φ_max ≤ ``max_pressure_angle``; with ``pressure_where="index"`` φ_max is
    the largest driving pressure angle over the index (the design summary's
    ``max_driving_pressure_angle``).  At the index's ends that angle is pure geometry: the dwell
    contact's force line passes through the input axis, cos φ = C·sin(π/(N·n_c))/|p| ≈ 71° for the
    default design, whatever the law.  With ``pressure_where="loaded"`` φ_max is the pressure angle
    of the contact that carries the load (the driving one where T_out ≥ 0, the holding-back one
    where T_out < 0, as :func:`cam_workbench.generators.bodies.indexing.parallel_drive.parallel_drive` loads them) where
    |T_out| > ``load_fraction`` × its peak, T_out = J·ψ''·ω² + T_f·sign ψ' (the load's, else ψ''):
    the ends, where a law that starts at rest carries no torque, drop out;
  - ``clearance``: the idle rollers' gap ≥ ``min_clearance`` [mm];
  - ``handover``: the tip hand-over gap ≥ −10⁻⁶ mm (the design's own rule);
  - ``locking``: positive drive, the worst forward/backward locking angle < 90°.

Measured (N = 8, β = 120°, modified sine, two cams, samples = 181): the pressure angle depends on
C/R_p (and little on r_r) and falls as C/R_p falls, to ≈ 65.4° at C/R_p ≈ 1.8 where the crossover
disappears ("index" and "loaded" within 0.2°: the modified sine's torque reaches 5 % of its peak
within 0.5° of the ends, and the carrying contact stays near 70° for the first ~18° of the index).
Other floors of the same scan: three cams 60.8°, β = 180° 56°, β = 270° 47°, N = 4 51°, N = 4 and
β = 270° 36°.  The default limit, 60° (the normal force twice the zero-angle one), is a trade:
45°, usual for plate cams with a rotating follower, no catalogue-like indexer with β ≤ 180° and
N ≥ 6 reaches; pass the limit of the application.

The pressure angle and the locking are invariant under a uniform scaling of (C, R_p, r_r): the
"size" optimum shrinks the drive until a lower bound or the clearance (in mm) stops it — set the
lower bounds of R_p and r_r from the rollers the load needs (their bearing rating, the Hertz
stress of :func:`cam_workbench.generators.bodies.indexing.parallel_drive.parallel_drive`).

Default bounds (from the start x₀): C ∈ [0.5, 2]·C₀, R_p ∈ [0.5, 2]·R_p₀, r_r ∈ [0.5, 1.5]·r_r₀.

nlopt is imported only when a run starts (:func:`..optimise.driver.load_nlopt`).  ``"COBYLA"``
handles the constraints itself; ``"BOBYQA"``, ``"NELDERMEAD"``, ``"SBPLX"`` (no constraints of
their own) run inside nlopt's augmented Lagrangian (``LN_AUGLAG``).
"""
from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from ..bodies.indexing.parallel import ParallelDesign, ParallelIndexer, design_parallel
from ..bodies.indexing.parallel_drive import MM, output_torque, parallel_drive
from ..bodies.indexing.sizing import IndexLoad
from ..errors import SpecError
from .driver import load_nlopt
from .problem import Cancelled
from .result import Progress
from .settings import NLOPT_CONVERGED, NLOPT_RESULTS

Array = np.ndarray

OBJECTIVES = {"size": "mm", "normal_force": "N"}
VARIABLES = ("centre_distance", "pitch_radius", "roller_radius")
CONSTRAINTS = ("geometry", "pressure_angle", "clearance", "handover", "locking")
WHERE = ("index", "loaded")
#: nlopt's derivative-free local algorithms: COBYLA with the constraints, the others in LN_AUGLAG
ALGORITHMS = {"COBYLA": "LN_COBYLA", "BOBYQA": "LN_BOBYQA", "NELDERMEAD": "LN_NELDERMEAD", "SBPLX": "LN_SBPLX"}
#: default bounds as factors of the start's variables
DEFAULT_BOUNDS = {"centre_distance": (0.5, 2.0), "pitch_radius": (0.5, 2.0), "roller_radius": (0.5, 1.5)}
DEFAULT_MAX_PRESSURE_ANGLE = math.radians(60.0)
#: keys of ``load``: parallel_drive's own and IndexLoad's that it passes on
_LOAD_REQUIRED = ("input_speed", "inertia", "roller_width", "roller_rating")
_LOAD_SET = ("stations", "index_angle", "law", "pitch_radius", "roller_radius")
_HANDOVER_TOL = 1e-6          # mm, the design's own
_XTOL_REL, _FTOL_REL = 1e-4, 1e-7
#: restarts at most, and the relative gain of the best value (or fall of the least violation) that earns one
_RESTARTS, _GAIN = 20, 1e-4


@dataclass(frozen=True)
class Trial:
    """One evaluated design: ``variables`` [mm] (C, R_p, r_r), ``value`` the objective in its unit
    (NaN when it failed), ``g`` the normalised constraints (≤ 0 satisfied, order
    :data:`CONSTRAINTS`), ``values`` the physical ones (``pressure_angle`` [rad], ``clearance``,
    ``handover_gap`` [mm], ``locking_angle`` [rad]), ``design`` (None when it failed) and
    ``failure``: the SpecError's field and rule when it failed."""

    variables: Array
    value: float
    g: Array
    values: dict[str, float]
    design: ParallelDesign | None
    failure: str = ""

    @property
    def feasible(self) -> bool:
        """Built, and every constraint ≤ 0."""
        return self.design is not None and bool(np.all(self.g <= 0.0))

    @property
    def violation(self) -> float:
        """The largest normalised constraint value (≤ 0 feasible)."""
        return float(np.max(self.g))

    @property
    def blocking(self) -> str:
        """The name of the most violated (or closest) constraint."""
        return CONSTRAINTS[int(np.argmax(self.g))]


@dataclass(frozen=True)
class ParallelOptimum:
    """What :func:`optimise_parallel` found.

    Attributes:
        verdict: "converged", "max evaluations", "stopped" (nlopt's roundoff/failure: best kept),
            "cancelled" (the progress callback returned False) or "no feasible point".
        indexer, design: the best feasible design (None with "no feasible point").
        variables: its C, R_p, r_r [mm] by name (the least-violated trial's without a feasible one).
        value: its objective (objective's unit); start_value the start's (NaN if it failed).
        constraints: its physical constraint values (:class:`Trial`); start: the start's trial.
        best: the returned trial; least_violated: the least-violated trial (None if any feasible);
        blocking: the constraint that blocked (its name) with "no feasible point", else "".
        evaluations, time_s: designs evaluated, wall time [s]; solver_status: nlopt's words.
    """

    objective: str
    algorithm: str
    pressure_where: str
    max_pressure_angle: float
    min_clearance: float
    bounds: dict[str, tuple[float, float]]
    verdict: str
    indexer: ParallelIndexer | None
    design: ParallelDesign | None
    variables: dict[str, float]
    value: float
    start_value: float
    constraints: dict[str, float]
    start: Trial
    best: Trial
    least_violated: Trial | None
    blocking: str
    evaluations: int
    time_s: float
    solver_status: str

    @property
    def feasible(self) -> bool:
        """A feasible design was found."""
        return self.design is not None

    def summary(self) -> dict[str, Any]:
        """JSON-safe plain numbers (angles in degrees ``*_deg``, lengths ``*_mm``; a non-finite
        number is None)."""
        out: dict[str, Any] = {
            "objective": self.objective,
            "objective_unit": OBJECTIVES[self.objective],
            "algorithm": self.algorithm,
            "pressure_where": self.pressure_where,
            "max_pressure_angle_deg": math.degrees(self.max_pressure_angle),
            "min_clearance_mm": self.min_clearance,
            "bounds_mm": {k: [float(a), float(b)] for k, a, b in ((k, *v) for k, v in self.bounds.items())},
            "verdict": self.verdict,
            "solver_status": self.solver_status,
            "feasible": self.feasible,
            "blocking": self.blocking or None,
            "evaluations": self.evaluations,
            "time_s": self.time_s,
            "start": _trial_summary(self.start),
            "start_value": self.start_value,
            "value": self.value,
            "variables_mm": dict(self.variables),
            "constraints": _values_summary(self.constraints),
            "optimum": _trial_summary(self.best) if self.feasible else None,
            "least_violated": _trial_summary(self.least_violated) if self.least_violated is not None else None,
            "design": self.design.summary() if self.design is not None else None,
        }
        return _json_safe(out)


def _values_summary(values: dict[str, float]) -> dict[str, float]:
    out = {}
    for k, v in values.items():
        out[f"{k}_deg" if k.endswith("angle") else f"{k}_mm"] = math.degrees(v) if k.endswith("angle") else v
    return out


def _trial_summary(t: Trial) -> dict[str, Any]:
    return {"variables_mm": dict(zip(VARIABLES, map(float, t.variables))), "value": t.value,
            "constraints": _values_summary(t.values), "normalised": dict(zip(CONSTRAINTS, map(float, t.g))),
            "feasible": t.feasible, "most_violated": t.blocking, "failure": t.failure or None}


def _json_safe(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {k: _json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_json_safe(v) for v in obj]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(obj) else None
    return obj


# ---------------------------------------------------------------------------------------------
# arguments

def _real(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) \
            or not math.isfinite(value):
        raise SpecError(name, f"must be a finite number, got {value!r}")
    return float(value)


def _bounds(ix: ParallelIndexer, bounds: dict[str, Any] | None) -> tuple[Array, Array]:
    x0 = np.array([float(getattr(ix, v)) for v in VARIABLES])
    lo = np.array([DEFAULT_BOUNDS[v][0] for v in VARIABLES]) * x0
    hi = np.array([DEFAULT_BOUNDS[v][1] for v in VARIABLES]) * x0
    if bounds is None:
        return lo, hi
    if not isinstance(bounds, dict):
        raise SpecError("optimise.bounds", f"must be a dict of (lo, hi) by variable, got {bounds!r}")
    for key, pair in bounds.items():
        if key not in VARIABLES:
            raise SpecError(f"optimise.bounds.{key}", f"unknown variable; one of {', '.join(VARIABLES)}")
        name = f"optimise.bounds.{key}"
        if not isinstance(pair, (tuple, list)) or len(pair) != 2:
            raise SpecError(name, f"must be a pair (lo, hi) [mm], got {pair!r}")
        a, b = _real(name, pair[0]), _real(name, pair[1])
        if not 0 < a <= b:
            raise SpecError(name, f"must satisfy 0 < lo ≤ hi [mm], got ({a!r}, {b!r})")
        i = VARIABLES.index(key)
        lo[i], hi[i] = a, b
    return lo, hi


def _load(ix: ParallelIndexer, objective: str, load: dict[str, Any] | None) -> dict[str, float] | None:
    """The load, checked by building :class:`.sizing.IndexLoad` at the start's geometry."""
    if load is None:
        if objective != "size":
            raise SpecError("optimise.load", f"objective {objective!r} needs the load (parallel_drive's keyword "
                                             f"arguments: {', '.join(_LOAD_REQUIRED)}, …)")
        return None
    if not isinstance(load, dict):
        raise SpecError("optimise.load", f"must be a dict of parallel_drive's keyword arguments, got {load!r}")
    allowed = set(_LOAD_REQUIRED) | {f.name for f in dataclasses.fields(IndexLoad)} - set(_LOAD_SET)
    for key in load:
        if key not in allowed:
            raise SpecError(f"optimise.load.{key}", f"unknown; one of {', '.join(sorted(allowed))}")
    for key in _LOAD_REQUIRED:
        if key not in load:
            raise SpecError(f"optimise.load.{key}", "required")
    more = {k: v for k, v in load.items() if k != "roller_width"}
    more.setdefault("friction_torque", 0.0)
    try:
        IndexLoad(stations=int(ix.stations), index_angle=float(ix.index_angle), law=ix.law,
                  pitch_radius=float(ix.pitch_radius) * MM, roller_radius=float(ix.roller_radius) * MM,
                  roller_width=_real("optimise.load.roller_width", load["roller_width"]) * MM, **more)
    except SpecError as exc:
        raise SpecError(exc.field.replace("indexer.", "optimise.load.", 1), exc.rule) from None
    except TypeError as exc:
        raise SpecError("optimise.load", str(exc)) from None
    return dict(load)


# ---------------------------------------------------------------------------------------------
# the evaluation

def pressure_angle(design: ParallelDesign, where: str = "index", load: dict[str, float] | None = None,
                   load_fraction: float = 0.05) -> float:
    """The constrained pressure angle [rad] of ``design`` (module docs): ``"index"`` the largest
    driving pressure angle over the index; ``"loaded"`` the load-carrying contact's where
    |T_out| > ``load_fraction`` × peak.  π/2 where the contact is missing."""
    ix = design.indexer
    rel = design.theta - float(ix.index_start)
    idx = (rel >= 0) & (rel <= float(ix.index_angle))
    half = math.pi / 2
    if where == "index":
        ang = design.driving_angle
        mask = idx
    else:
        t_out = output_torque(ix, design.theta, load)
        peak = float(np.max(np.abs(t_out[idx]))) if idx.any() else 0.0
        mask = idx & (np.abs(t_out) > load_fraction * peak)
        ang = np.where(t_out >= 0, design.driving_angle, design.holding_angle)
    if not mask.any():
        return 0.0
    return float(np.max(np.where(np.isfinite(ang[mask]), ang[mask], half)))


def outer_radius(design: ParallelDesign) -> float:
    """The cam's outer radius [mm]: the largest profile radius over the cams."""
    return max(float(np.max(np.hypot(c.profile[:, 0], c.profile[:, 1]))) for c in design.cams)


class _Problem:
    """The trials: one design per distinct point (cached), the best feasible and least violated."""

    def __init__(self, ix: ParallelIndexer, objective: str, load: dict[str, float] | None, where: str,
                 load_fraction: float, max_pa: float, min_clear: float, samples: int, c_scale: float):
        self.ix, self.objective, self.load, self.where = ix, objective, load, where
        self.load_fraction, self.max_pa, self.min_clear, self.samples = load_fraction, max_pa, min_clear, samples
        self.c_scale = c_scale
        self.cache: dict[bytes, Trial] = {}
        self.best: Trial | None = None
        self.least: Trial | None = None

    def trial(self, x: Array) -> Trial:
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

    def _evaluate(self, x: Array) -> Trial:
        nan = math.nan
        failed = {"pressure_angle": nan, "clearance": nan, "handover_gap": nan, "locking_angle": nan}
        try:
            ix = dataclasses.replace(self.ix, **dict(zip(VARIABLES, map(float, x))))
            d = design_parallel(ix, self.samples, strict=False)
            value = self._objective(d)
            pa = pressure_angle(d, self.where, self.load, self.load_fraction)
        except SpecError as exc:
            g = np.zeros(len(CONSTRAINTS))
            g[0] = 1.0
            return Trial(x, nan, g, failed, None, str(exc))
        except Exception as exc:  # noqa: BLE001 - a solver's trial must never end the run
            g = np.zeros(len(CONSTRAINTS))
            g[0] = 1.0
            return Trial(x, nan, g, failed, None, f"{type(exc).__name__}: {exc}")
        cl, lk = d.clearance, d.locked
        hand = cl.handover_gap if math.isfinite(cl.handover_gap) else math.inf
        lock = max(lk.forward_angle, lk.backward_angle)
        s = self.c_scale
        g = np.array([-1.0, (pa - self.max_pa) / self.max_pa, (self.min_clear - cl.gap) / s,
                      max((-_HANDOVER_TOL - hand) / s, -1.0), (lock - math.pi / 2 * (1 - 1e-9)) / (math.pi / 2)])
        g = np.clip(np.nan_to_num(g, nan=1.0), -10.0, 10.0)
        values = {"pressure_angle": pa, "clearance": cl.gap, "handover_gap": cl.handover_gap, "locking_angle": lock}
        if not math.isfinite(value):
            g[0] = 1.0
            return Trial(x, nan, g, values, None, f"the objective is not finite ({value!r})")
        return Trial(x, value, g, values, d)

    def _objective(self, d: ParallelDesign) -> float:
        if self.objective == "size":
            return outer_radius(d)
        drive = parallel_drive(d, **self.load)
        return float(drive.normal_force_peak)


def _reference(ix: ParallelIndexer, objective: str, load: dict[str, float] | None, start: Trial) -> float:
    """The objective's scale: the start's value, else a load-only one (the peak at zero pressure angle)."""
    if start.design is not None and start.value > 0:
        return start.value
    if objective == "size":
        return float(ix.centre_distance)
    t_out = output_torque(ix, float(ix.index_start) + np.linspace(0, float(ix.index_angle), 1025), load)
    peak = float(np.max(np.abs(t_out)))
    ref = peak / (float(ix.pitch_radius) * MM)
    return ref if ref > 0 and math.isfinite(ref) else 1.0


# ---------------------------------------------------------------------------------------------

def optimise_parallel(ix: ParallelIndexer, *, objective: str = "size",
                      max_pressure_angle: float = DEFAULT_MAX_PRESSURE_ANGLE,
                      min_clearance: float = 1.0, pressure_where: str = "index", load_fraction: float = 0.05,
                      bounds: dict[str, tuple[float, float]] | None = None,
                      load: dict[str, float] | None = None, samples: int = 361, algorithm: str = "COBYLA",
                      max_evaluations: int = 200,
                      progress: Callable[[Progress], Any] | None = None) -> ParallelOptimum:
    """Optimise ``ix``'s centre distance, pitch radius and roller radius [mm] (module docs).

    Args:
        objective: "size" (outer radius [mm]) or "normal_force" [N] (peak roller load, from
            :func:`cam_workbench.generators.bodies.indexing.parallel_drive.parallel_drive` at ``load``).
        max_pressure_angle: [rad] in (0, π/2), default 60°; ``pressure_where`` "index" or
            "loaded" (with ``load_fraction`` of the peak output torque) says where it is taken.
        min_clearance: [mm] ≥ 0, the idle rollers' least gap to the cams.
        bounds: {variable: (lo, hi)} [mm] for any of ``centre_distance``, ``pitch_radius``,
            ``roller_radius`` (others default to the module's factors of the start; lo = hi fixes one).
        load: parallel_drive's keyword arguments (required for the load objectives; for "size" it
            only shapes T_out of ``pressure_where="loaded"``).
        samples: input angles per design (≥ 8); algorithm: COBYLA, BOBYQA, NELDERMEAD, SBPLX.
        max_evaluations: designs at most (≥ 1); progress: called with a :class:`Progress` after
            every evaluation, return False to cancel (the best design so far is returned).

    Raises SpecError naming ``optimise.<field>`` for a bad argument; an infeasible or unbuildable
    trial never raises (the verdict "no feasible point" names the blocking constraint)."""
    t0 = time.perf_counter()
    if not isinstance(ix, ParallelIndexer):
        raise SpecError("optimise.indexer", f"must be a ParallelIndexer, got {type(ix).__name__}")
    if not isinstance(objective, str) or objective not in OBJECTIVES:
        raise SpecError("optimise.objective", f"unknown objective {objective!r}; one of {', '.join(OBJECTIVES)}")
    pa_max = _real("optimise.max_pressure_angle", max_pressure_angle)
    if not 0 < pa_max < math.pi / 2:
        raise SpecError("optimise.max_pressure_angle", f"must be in (0, π/2) rad, got {pa_max!r}")
    clear = _real("optimise.min_clearance", min_clearance)
    if clear < 0:
        raise SpecError("optimise.min_clearance", f"must be ≥ 0 mm, got {clear!r}")
    if not isinstance(pressure_where, str) or pressure_where not in WHERE:
        raise SpecError("optimise.pressure_where", f"must be one of {', '.join(WHERE)}, got {pressure_where!r}")
    frac = _real("optimise.load_fraction", load_fraction)
    if not 0 <= frac < 1:
        raise SpecError("optimise.load_fraction", f"must be in [0, 1), got {frac!r}")
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 8:
        raise SpecError("optimise.samples", f"must be an integer ≥ 8, got {samples!r}")
    algo = str(algorithm).upper().removeprefix("LN_") if isinstance(algorithm, str) else ""
    if algo not in ALGORITHMS:
        raise SpecError("optimise.algorithm", f"must be an nlopt derivative-free local algorithm, one of "
                                              f"{', '.join(ALGORITHMS)}, got {algorithm!r}")
    if isinstance(max_evaluations, bool) or not isinstance(max_evaluations, (int, np.integer)) or max_evaluations < 1:
        raise SpecError("optimise.max_evaluations", f"must be an integer ≥ 1, got {max_evaluations!r}")
    if progress is not None and not callable(progress):
        raise SpecError("optimise.progress", "must be callable or None")
    lo, hi = _bounds(ix, bounds)
    ld = _load(ix, objective, load)

    x0 = np.clip([float(getattr(ix, v)) for v in VARIABLES], lo, hi)
    prob = _Problem(ix, objective, ld, pressure_where, frac, pa_max, clear, int(samples),
                    max(clear, 0.01 * float(x0[0])))
    free = lo < hi
    start = prob.trial(x0)
    f_ref = _reference(ix, objective, ld, start)
    budget = int(max_evaluations)
    count = [1]

    def report(t: Trial) -> bool:
        if progress is None:
            return True
        best = prob.best.value if prob.best is not None else None
        return progress(Progress(count[0], budget, algo, t.value, t.violation, best)) is not False

    cancelled = not report(start)
    status, code = "", 0
    if not cancelled and free.any() and budget > 1:
        status, code, cancelled = run_restarts(prob, algo, x0, lo, hi, free, f_ref, budget, count, report)
    elif not free.any():
        status = "every variable fixed by its bounds: the start evaluated alone"
        code = 1

    best, least = prob.best, prob.least
    if best is not None:
        verdict = ("cancelled" if cancelled else "max evaluations" if code == 5 or count[0] >= budget
                   else "converged" if code in NLOPT_CONVERGED else "stopped")
        chosen, least_out, blocking = best, None, ""
    else:
        verdict = "cancelled" if cancelled else "no feasible point"
        chosen, least_out = least, least
        blocking = least.blocking
    return ParallelOptimum(
        objective=objective, algorithm=algo, pressure_where=pressure_where, max_pressure_angle=pa_max,
        min_clearance=clear, bounds={v: (float(a), float(b)) for v, a, b in zip(VARIABLES, lo, hi)},
        verdict=verdict, indexer=best.design.indexer if best is not None else None,
        design=best.design if best is not None else None,
        variables=dict(zip(VARIABLES, map(float, chosen.variables))),
        value=best.value if best is not None else math.nan, start_value=start.value,
        constraints=dict(chosen.values), start=start, best=chosen, least_violated=least_out,
        blocking=blocking, evaluations=len(prob.cache), time_s=time.perf_counter() - t0, solver_status=status)


def run_restarts(prob: Any, algo: str, x0: Array, lo: Array, hi: Array, free: Array, f_ref: float, budget: int,
                 count: list[int], report: Callable[[Any], bool],
                 n_constraints: int = len(CONSTRAINTS)) -> tuple[str, int, bool]:
    """nlopt runs over the free variables scaled to the start, each restarted from the best trial
    so far (the best feasible, else the least violated) with a fresh initial step while a run gains
    (module docs); returns (the runs' status text, the last nlopt code, cancelled).

    ``prob`` is the trials' cache (this module's ``_Problem`` or one like it:
    :mod:`cam_workbench.generators.optimise.spatial_indexer`'s): ``trial(x)`` returns a trial with
    ``variables``, ``value``, ``g`` (``n_constraints`` normalised constraints, ≤ 0 satisfied) and
    ``design`` (None when it failed); ``cache`` (by ``x.tobytes()``), ``best``, ``least``.  The
    variable at index 1 is the scale (the others run as log ratios to it when it is free)."""
    nlopt = load_nlopt()
    fi = np.flatnonzero(free)
    n = fi.size
    a, b = np.log(lo[fi] / x0[fi]), np.log(hi[fi] / x0[fi])     # bounds of w = log(x/x0), free ones
    # y → w: with R_p free, y = (log R_p/R_p0, the others' log ratios to R_p) — the pressure angles
    # and the buildability depend on the ratios alone, the size on the scale y_Rp
    m = np.eye(n)
    j = int(np.flatnonzero(fi == 1)[0]) if free[1] else -1
    if j >= 0:
        m[:, j] = 1.0
    m_inv = np.linalg.inv(m)
    ratio = [i for i in range(n) if i != j] if j >= 0 else []
    y_lo, y_hi = a.copy(), b.copy()
    for i in ratio:
        y_lo[i], y_hi[i] = a[i] - b[j], b[i] - a[j]
    step = np.minimum(0.1, 0.25 * (y_hi - y_lo))
    failures = tuple({RuntimeError, getattr(nlopt, "runtime_error", RuntimeError)})

    def x_of(y: Array) -> Array:
        x = x0.copy()
        x[fi] = np.clip(x0[fi] * np.exp(m @ np.clip(np.asarray(y, dtype=float), y_lo, y_hi)), lo[fi], hi[fi])
        return x

    def y_of(x: Array) -> Array:
        return m_inv @ np.log(x[fi] / x0[fi])

    def box_rows(y: Array) -> Array:
        """The bounds of the variables given by ratios: a ≤ w ≤ b (log units)."""
        w = m @ np.asarray(y, dtype=float)
        return np.concatenate([[a[i] - w[i], w[i] - b[i]] for i in ratio]) if ratio else np.zeros(0)

    def at(z: Array) -> Trial:
        x = x_of(z)
        new = x.tobytes() not in prob.cache
        if new and count[0] >= budget:
            raise _Budget()
        t = prob.trial(x)
        if new:
            count[0] += 1
            if not report(t):
                raise Cancelled()
        return t

    def f(z: Array, grad: Array) -> float:
        t = at(z)
        return t.value / f_ref if t.design is not None else 2.0

    def c(result: Array, z: Array, grad: Array) -> None:
        result[:] = np.concatenate([at(z).g, box_rows(z)])

    def standing() -> tuple[bool, float]:
        """(no feasible point yet, the best value or the least violation) of the trials so far."""
        return (True, prob.least.violation) if prob.best is None else (False, prob.best.value / f_ref)

    texts: list[str] = []
    code = 0
    z = np.zeros(n)
    for _ in range(_RESTARTS):
        before = standing()
        if algo == "COBYLA":
            o = nlopt.opt(nlopt.LN_COBYLA, n)
        else:
            o = nlopt.opt(nlopt.LN_AUGLAG, n)
            sub = nlopt.opt(getattr(nlopt, ALGORITHMS[algo]), n)
            sub.set_xtol_rel(_XTOL_REL)
            sub.set_ftol_rel(_FTOL_REL)
            o.set_local_optimizer(sub)
        o.set_lower_bounds(y_lo)
        o.set_upper_bounds(y_hi)
        o.set_min_objective(f)
        o.add_inequality_mconstraint(c, np.full(n_constraints + 2 * len(ratio), 1e-9))
        o.set_xtol_rel(_XTOL_REL)
        o.set_ftol_rel(_FTOL_REL)
        o.set_initial_step(step)
        try:
            o.optimize(z)
            code = int(o.last_optimize_result())
            texts.append(NLOPT_RESULTS.get(code, str(code)))
        except Cancelled:
            texts.append("cancelled by the progress callback")
            return f"{algo}: {'; '.join(texts)}", -5, True
        except _Budget:
            code = 5
            texts.append(NLOPT_RESULTS[5])
        except nlopt.RoundoffLimited:
            code = -4
            texts.append("roundoff limited (best point kept)")
        except failures as exc:
            code = -1
            texts.append(f"failure: {exc or 'nlopt failure'} (best point kept)")
        after = standing()
        gained = after[0] < before[0] or after[1] < before[1] - _GAIN * max(abs(before[1]), 1.0)
        if code == 5 or count[0] >= budget or not gained:
            break
        best = prob.best if prob.best is not None else prob.least
        z = np.clip(y_of(best.variables), y_lo, y_hi)
    runs = f" ({len(texts)} runs: {'; '.join(texts)})" if len(texts) > 1 else ""
    return f"{algo}: {texts[-1]}{runs}", code, False



class _Budget(Exception):
    """The evaluation budget is spent (raised in the callback, before a new design)."""

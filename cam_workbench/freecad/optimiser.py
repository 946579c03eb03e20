"""The optimiser inside FreeCAD: choices, the threaded run, before/after figures, apply.

Everything here is headless (the Qt panel is :mod:`.optimiser_panel`) and is what the panel
calls, so scripts and tests drive the same code:

- :func:`objective_choices` / :func:`algorithm_choices` — the objectives and algorithms the
  cam's optimiser serves (an indexer: size and normal_force, derivative-free algorithms);
- :func:`variable_choices` — the design variables that mean something for a cam (base
  radius and offset always; the control angles and free lifts of each ``law = "bspline"``
  rise/return; the interior points' lifts of each ``law = "polynomial"`` rise/return that has
  points; the blank orientation only for ``machining_time``; an indexer's C, turret size and r_r,
  *fixed*: its optimiser varies all three together, ``optimise.variables = "auto"``), and
  :func:`variables_text` / :func:`selected_tokens` to and from ``optimise.variables``;
- :func:`settings_of` / :func:`default_bounds` — the panel's starting values: the feature's
  ``Optimise`` properties (the spec's ``[optimise]`` section), the bounds the library takes when
  none are given (an indexer has no R_b/e bounds: its variables' bounds are its
  optimiser's own, :func:`own_bounds_note` says them);
- :func:`run_spec` — the spec with the panel's choices as its ``[optimise]`` section
  (validated: a bad choice raises ``SpecError`` naming the field);
- :class:`OptimiseJob` — :func:`cam_workbench.generators.optimise.optimise` in a worker thread, its progress
  (evaluations, objective, violation, history) readable from the GUI thread, and
  :meth:`OptimiseJob.cancel` (the library's ``threading.Event``: the run stops at the next
  evaluation with status ``"cancelled"``);
- :func:`figures` / :func:`check_comparison` — the before/after numbers and every design check
  before and after (the Check design table's rows; an indexer's figures are its objective,
  C, its turret's size, r_r, a spatial indexer's lengths scaled with its turret and its other objective);
- :func:`apply_result` — writes ``OptimiseResult.spec`` (the optimised design AND the
  ``[optimise]`` settings it was run with) into the feature's properties and recomputes, as ONE
  undo step.  A result that fails the dense re-check is refused unless ``allow_failing``
  (the panel asks the user first); a feature changed since the run started is refused.

The optimiser runs in FreeCAD's own Python (nlopt from Debian's ``python3-nlopt``), in a
thread of the FreeCAD process: the objects are plain numpy data, the document is only read
before the run (in the GUI thread) and written by :func:`apply_result` (in the GUI thread).
"""
from __future__ import annotations

import dataclasses
import threading
import time
import traceback
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from cam_workbench.generators.checks.areas import area_label
from cam_workbench.generators.errors import CamError, SpecError
from cam_workbench.generators.kinds import body_of, follower_class_of, follower_of, own_optimiser
from cam_workbench.generators.motion import MotionProgram
from cam_workbench.generators.motion.bspline_law import fixed_end_points
from cam_workbench.generators.optimise import indexer as indexer_optimiser
from cam_workbench.generators.optimise import spatial_indexer
from cam_workbench.generators.optimise import optimise, worst_constraint
from cam_workbench.generators.optimise.objectives import UNITS
from cam_workbench.generators.optimise.objectives import label as objective_label
from cam_workbench.generators.optimise.space import DesignSpace
from cam_workbench.generators.spec import (OBJECTIVES, OPTIMISE_ALGORITHMS, CamSpec, OptimiseSection,
                                           optimise_control_rows, optimise_variables)
from cam_workbench.generators.spec.optimise import (
    BODY_OBJECTIVES, FOLLOWER_VARIABLES, body_variable_rule, follower_variable_rule,
)

from . import properties as props
from .check_design import check_rows, fmt_value

TRANSACTION = "Optimise cam"
#: What each objective is, for the panel's list (the declaration says more in its tooltip).
OBJECTIVE_LABELS = {
    "area": "Cam area (thesis Eq. 4.21 ½∮(R_b + s)² dθ; other followers: inside the design curve)",
    "profile_area": "Profile area (true cross-section inside the roller profile)",
    "machining_time": "Machining time (the thesis' cutting-time model, Eq. 4.20)",
    "gcode_time": "G-code time (this project's XY contour program)",
    "peak_acceleration": "Peak acceleration (largest |s″|)",
    "peak_pressure_angle": "Peak pressure angle (largest |φ|)",
    "outer_diameter": "Outer diameter (a groove cam's disc, rim wall ≥ groove.min_wall)",
    "size": "Size (an indexer: its cam's or cams' outer radius)",
    "normal_force": "Peak roller load (an indexer, at indexer.output_inertia)",
}
ALGORITHM_LABELS = {
    "auto": "auto: SLSQP with exact gradients (times: SLSQP on a stand-in, then BOBYQA)",
    "slsqp": "SLSQP — gradient, exact sensitivities",
    "mma": "MMA — gradient, exact sensitivities",
    "ccsaq": "CCSAQ — gradient, exact sensitivities",
    "cobyla": "COBYLA — derivative-free, constraints as they are",
    "bobyqa": "BOBYQA — derivative-free, thesis' exterior penalty",
    "isres": "ISRES — global (seeded), then a local polish",
}
#: an indexer's algorithms (:data:`cam_workbench.generators.optimise.indexer.ALGORITHMS`, the spatial indexers'
#: too: the trials are full designs whose checks are maxima over samples, so derivative-free ones only)
INDEXER_ALGORITHM_LABELS = {
    "auto": "auto: COBYLA — derivative-free, every trial a full design",
    "cobyla": "COBYLA — derivative-free, constraints as they are",
    "bobyqa": "BOBYQA — derivative-free, in nlopt's augmented Lagrangian",
}
#: an indexer's design variables (spec paths: the parallel indexer's
#: :data:`cam_workbench.generators.optimise.indexer.PATHS`, a spatial indexer's
#: :func:`cam_workbench.generators.optimise.spatial_indexer.spatial_paths`); the labels of one spec:
#: :func:`indexer_variable_labels`
INDEXER_VARIABLE_LABELS = {"indexer.centre_distance": "Centre distance C",
                           "indexer.pitch_radius": "Turret pitch radius R_p",
                           "indexer.roller_end": "Rollers' outer end t1 (turret size)",
                           "follower.roller_radius": "Roller radius r_r"}
#: a body's own label of a variable, where it differs (the barrel's turret size is its pitch radius)
BODY_VARIABLE_LABELS = {("barrel_indexer", "indexer.pitch_radius"): "Turret pitch radius R_p (turret size)"}
#: each variable's symbol, as the bounds note names it
INDEXER_VARIABLE_SYMBOLS = {"indexer.centre_distance": "C", "indexer.pitch_radius": "R_p",
                            "indexer.roller_end": "t1", "follower.roller_radius": "r_r"}


@dataclass(frozen=True)
class IndexerOptimiser:
    """What the panel needs of an indexer's own optimiser (registered with
    ``cam_workbench.generators.kinds.register_optimiser``): its design variables' spec paths, its
    rules before a run (raises ``SpecError``), its bounds, the checks that hold its result and
    the lengths that follow its variables."""

    paths: Callable[[CamSpec], dict[str, str]]        # solver's name → spec path, in the solver's order
    arguments: Callable[[CamSpec], dict[str, Any]]    # the optimiser's own rules (SpecError naming the field)
    bounds: Callable[[CamSpec], dict[str, tuple[float, float]]]
    factors: str                                      # the bounds as factors of the start, in words
    checks: str                                       # the design checks that hold the result
    keeps: str                                        # what stays as it is
    scaled: Callable[[CamSpec], tuple[str, ...]] = lambda spec: ()   # spec paths that scale with a variable


def _turret_scaled(spec: CamSpec) -> tuple[str, ...]:
    """The spec paths of a spatial indexer's lengths that scale with its turret's size (its
    optimiser's ``FOLLOWERS``; ``follower.roller_width`` when given)."""
    paths = tuple("cam.thickness" if n == "cam_width" else f"indexer.{n}"
                  for n in spatial_indexer.FOLLOWERS[spec.cam.body])
    return paths + (("follower.roller_width",) if spec.follower.roller_width is not None else ())


#: the indexers' optimisers (the function ``own_optimiser`` returns → its helpers)
INDEXER_OPTIMISERS: dict[Callable[..., Any], IndexerOptimiser] = {
    indexer_optimiser.optimise_indexer: IndexerOptimiser(
        paths=lambda spec: dict(indexer_optimiser.PATHS), arguments=indexer_optimiser.indexer_arguments,
        bounds=indexer_optimiser.indexer_bounds, factors="0.5–2 × the start's C and R_p, 0.5–1.5 × its r_r",
        checks="pressure angle, undercut, clearance, locking, contact stress",
        keeps="the stations, the index, the law and the plates"),
    spatial_indexer.optimise_spatial_indexer: IndexerOptimiser(
        paths=spatial_indexer.spatial_paths, arguments=spatial_indexer.spatial_arguments,
        bounds=spatial_indexer.spatial_bounds, factors="0.5–2 × the start's C and turret size, 0.5–1.5 × its r_r",
        checks="pressure angle, undercut, rib thickness, locking, contact stress, bore",
        keeps="the stations, the index and the law", scaled=_turret_scaled),
}
GRADIENT_ALGORITHMS = ("slsqp", "mma", "ccsaq")
NON_SMOOTH = ("machining_time", "gcode_time")
assert set(OBJECTIVE_LABELS) == set(OBJECTIVES) | set(BODY_OBJECTIVES)
assert set(ALGORITHM_LABELS) == set(OPTIMISE_ALGORITHMS)
assert set(INDEXER_ALGORITHM_LABELS) == set(indexer_optimiser.ALGORITHMS)
assert set(INDEXER_VARIABLE_LABELS) == set(INDEXER_VARIABLE_SYMBOLS)
assert set(indexer_optimiser.PATHS.values()) <= set(INDEXER_VARIABLE_LABELS)
assert {f"indexer.{t}" for t in spatial_indexer.TURRET.values()} <= set(INDEXER_VARIABLE_LABELS)
assert {path for _, path in BODY_VARIABLE_LABELS} <= set(INDEXER_VARIABLE_LABELS)


def objective_choices(spec: CamSpec) -> tuple[str, ...]:
    """The objectives the panel offers for ``spec``: those its body's optimiser serves
    (``Body.optimise_objectives``: every one, outer_diameter only for a groove cam's disc; a
    cylindrical cam: outer_diameter alone; an indexer: size and normal_force)."""
    return body_of(spec).optimise_objectives


def indexer_optimiser_of(spec: CamSpec) -> IndexerOptimiser | None:
    """The helpers of ``spec``'s indexer optimiser (:data:`INDEXER_OPTIMISERS`), None when its body's
    optimiser is no indexer's (a plane cam's, a cylindrical cam's)."""
    fn = own_optimiser(spec)
    return None if fn is None else INDEXER_OPTIMISERS.get(fn)


def indexer_optimised(spec: CamSpec) -> bool:
    """True when ``spec``'s optimiser is an indexer's (:data:`INDEXER_OPTIMISERS`: the parallel
    indexer's :func:`~cam_workbench.generators.optimise.indexer.optimise_indexer`, the barrel and globoidal
    indexers' :func:`~cam_workbench.generators.optimise.spatial_indexer.optimise_spatial_indexer`): it varies
    C, the turret's size and r_r together within bounds of its own, derivative-free, without restarts."""
    return indexer_optimiser_of(spec) is not None


def indexer_variable_labels(spec: CamSpec) -> dict[str, str]:
    """{spec path: label} of the design variables of ``spec``'s indexer optimiser, in its order ({}
    for any other cam): C, the turret's size (a parallel or barrel indexer's R_p, a globoid's t1), r_r."""
    own = indexer_optimiser_of(spec)
    if own is None:
        return {}
    return {path: BODY_VARIABLE_LABELS.get((spec.cam.body, path), INDEXER_VARIABLE_LABELS[path])
            for path in own.paths(spec).values()}


def _an(title: str) -> str:
    return f"{'an' if title[:1].lower() in 'aeiou' else 'a'} {title.lower()}"


def algorithm_choices(spec: CamSpec) -> tuple[str, ...]:
    """The algorithms the panel offers for ``spec`` (an indexer: auto, cobyla, bobyqa; every
    other cam every one, the gradient ones disabled for a machining time)."""
    if indexer_optimised(spec):
        return tuple(INDEXER_ALGORITHM_LABELS)
    return OPTIMISE_ALGORITHMS


def algorithm_label(spec: CamSpec, name: str) -> str:
    """The algorithm ``name`` as the panel lists it for ``spec``."""
    return (INDEXER_ALGORITHM_LABELS if indexer_optimised(spec) else ALGORITHM_LABELS)[name]


def multistart_offered(spec: CamSpec) -> bool:
    """Random restarts apply (an indexer's optimiser runs from the spec's design alone)."""
    return not indexer_optimised(spec)


def fixed_variables_note(spec: CamSpec) -> str:
    """What the panel says of design variables it cannot choose ("" when every one is a choice): an
    indexer's optimiser varies C, the turret's size and r_r together."""
    own = indexer_optimiser_of(spec)
    if own is None:
        return ""
    text = (f"{_an(body_of(spec).title).capitalize()}'s optimiser varies all three together "
            f"(optimise.variables = \"auto\"); {own.keeps} stay as they are")
    scaled = own.scaled(spec)
    if scaled:
        text += f"; the turret's other lengths ({', '.join(scaled)}) scale with its size"
    return text + "."


def own_bounds_note(spec: CamSpec) -> str:
    """The bounds of the design variables in words, where the cam's optimiser sets them itself and
    the panel has no bound to enter ("" otherwise): an indexer's C, turret size and r_r (a spatial
    indexer's turret lengths scaling with its size)."""
    own = indexer_optimiser_of(spec)
    if own is None:
        return ""
    u = spec.units
    bounds = ", ".join(f"{INDEXER_VARIABLE_SYMBOLS[path]} ∈ [{lo:.6g}, {hi:.6g}] {u}"
                       for path, (lo, hi) in own.bounds(spec).items())
    text = f"The optimiser's own bounds: {bounds} ({own.factors}). "
    scaled = own.scaled(spec)
    if scaled:
        text += f"The turret's other lengths ({', '.join(scaled)}) scale with its size. "
    return text + f"The design checks ({own.checks}) hold the result."


class ApplyError(CamError):
    """The result cannot be applied (the cam changed, or it fails a check and was not confirmed)."""


# ---- design variables -------------------------------------------------------------------------
@dataclass(frozen=True)
class VariableChoice:
    """One check box of the panel: a token of ``optimise.variables``."""

    token: str             # "base_radius", "offset", "motion[0].control_x", "orientation" …
    label: str
    count: int             # scalar design variables it adds
    enabled: bool
    reason: str = ""       # why it is disabled (or, fixed, why it is always varied)
    fixed: bool = False    # always varied: the box is checked and cannot be unchecked


def _bspline_rows(spec: CamSpec) -> list[int]:
    return [k for k, seg in enumerate(spec.motion) if seg.law == "bspline"]


def variable_choices(spec: CamSpec, objective: str | None = None) -> list[VariableChoice]:
    """The design variables the panel offers for ``spec`` (and ``objective``, default the spec's)."""
    objective = objective or spec.optimise.objective
    u = spec.units
    labels = indexer_variable_labels(spec)
    if labels:                                   # C, the turret's size and r_r, all three always
        names = [INDEXER_VARIABLE_SYMBOLS[path] for path in labels]
        symbols = f"{', '.join(names[:-1])} and {names[-1]}" if len(names) > 1 else names[0]
        why = (f"{_an(body_of(spec).title)}'s optimiser varies {symbols} together "
               "(optimise.variables = \"auto\")")
        return [VariableChoice(path, f"{name} [{u}] ({path})", 1, True, why, fixed=True)
                for path, name in labels.items()]
    if own_optimiser(spec) is not None:          # its own optimiser: the body's own variables only
        own = {"cylinder_radius": f"Pitch radius R_p [{u}]", "outer_diameter": f"Cylinder outer diameter [{u}]",
               "clearance": f"Groove clearance [{u}]"}
        return [VariableChoice(n, own[n], 1, True) for n in body_of(spec).optimise_variables]
    out = [VariableChoice("base_radius", f"Base radius R_b [{u}]", 1, True)]
    # the follower's position: offset (translating), pivot distance and arm length (oscillating),
    # the face's offset from the pivot (oscillating flat face) — only those its kind has
    labels = {"offset": f"Follower offset e [{u}]", "pivot_distance": f"Pivot distance d [{u}]",
              "arm_length": f"Arm length L [{u}]", "face_offset": f"Face offset from the pivot [{u}]"}
    for name in FOLLOWER_VARIABLES:
        rule = follower_variable_rule(spec, name)
        if rule is None:
            out.append(VariableChoice(name, labels[name], 1, True))
        elif follower_class_of(spec).pivoted and name == "arm_length":
            out.append(VariableChoice(name, labels[name], 1, False, rule))
    program = MotionProgram.from_spec(spec)
    for k in _bspline_rows(spec):
        curve = program.curves[k]
        n = curve.n_points - 1
        nfix = fixed_end_points(curve.order)
        what = f"row {k + 1} ({spec.motion[k].kind})"
        out.append(VariableChoice(f"motion[{k}].control_x", f"{what}: control angles P1x … P{n - 1}x",
                                  n - 1, True))
        free = n - 2 * nfix + 1
        out.append(VariableChoice(f"motion[{k}].control_y",
                                  f"{what}: free lifts P{nfix}y … P{n - nfix}y", free, free > 0,
                                  "" if free > 0 else "no free lift at this order"))
    # a polynomial rise/return's interior points: their lifts (the angles stay)
    for k, seg in enumerate(spec.motion):
        if seg.law == "polynomial" and seg.points:
            angles = ", ".join(f"{a:g}°" for a, _s in seg.points)
            out.append(VariableChoice(f"motion[{k}].points",
                                      f"row {k + 1} ({seg.kind}): polynomial point lifts at {angles} [{u}]",
                                      len(seg.points), True))
    # a groove cam's disc and groove
    body_labels = {"outer_diameter": f"Disc outer diameter [{u}]", "clearance": f"Groove clearance [{u}]"}
    for name, label in body_labels.items():
        if body_variable_rule(spec, name) is None:
            out.append(VariableChoice(name, label, 1, True))
    orient = objective == "machining_time"
    out.append(VariableChoice("orientation", "Blank orientation on the NC table", 1, orient,
                              "" if orient else "only changes the machining time (thesis model)"))
    return out


def selected_tokens(spec: CamSpec) -> set[str]:
    """The tokens of :func:`variable_choices` that ``spec.optimise.variables`` selects (an
    indexer's: its three, always)."""
    if indexer_optimised(spec):
        return set(indexer_variable_labels(spec))
    kinds = optimise_variables(spec)
    rows = optimise_control_rows(spec)
    out = {k for k in ("base_radius", "offset", "pivot_distance", "arm_length", "face_offset", "outer_diameter",
                       "clearance", "cylinder_radius", "orientation") if k in kinds}
    for kind, ks in rows.items():
        out |= {f"motion[{k}].{kind}" for k in ks}
    return out


def variables_text(spec: CamSpec, tokens: set[str] | list[str], objective: str | None = None) -> str:
    """``optimise.variables`` for the chosen tokens (only enabled ones): the plain names, and
    ``control_points`` when every B-spline row's angles and lifts are chosen; an indexer's
    three (its fixed choices): "auto"."""
    choices = {c.token: c for c in variable_choices(spec, objective) if c.enabled}
    chosen = [c for c in choices if c in set(tokens)]
    fixed = [t for t, c in choices.items() if c.fixed]
    if fixed and all(t in chosen for t in fixed):
        chosen = ["auto"] + [t for t in chosen if t not in fixed]
    ctrl = [t for t in choices if t.startswith("motion[") and ".control_" in t]
    if ctrl and all(t in chosen for t in ctrl):
        rest = [t for t in chosen if t.startswith("motion[") and t not in ctrl]
        chosen = [t for t in chosen if not t.startswith("motion[")]
        chosen.append("control_points")
        chosen = [t for t in ("base_radius", "offset", "pivot_distance", "arm_length", "face_offset",
                              "control_points", "outer_diameter", "clearance", "orientation") if t in chosen] + rest
    return ", ".join(chosen)


# ---- settings ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class Settings:
    """What the panel chooses: fields of the ``[optimise]`` section (lengths in spec units)."""

    objective: str
    variables: str
    algorithm: str
    max_evaluations: int
    multistart: int
    seed: int
    #: None where the cam's optimiser takes no R_b bounds (an indexer): none shown or written
    base_radius_min: float | None
    base_radius_max: float | None
    #: None where the follower has no offset (an oscillating arm, an indexer's turret): no
    #: bound shown or written
    offset_max: float | None

    def changes(self) -> dict[str, Any]:
        bounds = ("base_radius_min", "base_radius_max", "offset_max")
        return {f"optimise.{f.name}": getattr(self, f.name) for f in dataclasses.fields(self)
                if not (f.name in bounds and getattr(self, f.name) is None)}


def default_bounds(spec: CamSpec) -> tuple[float | None, float | None, float | None]:
    """(R_b lower, R_b upper, |e| upper): the ones ``[optimise]`` gives, and for those it leaves
    out the library's defaults (``cam_workbench.generators.optimise.space.DesignSpace``: ½ × and 2 × the
    initial R_b, the lower at least 1.05 × (roller radius + bore radius); |e| ≤ ½ × the R_b lower
    bound or |e₀|; default bounds always contain the starting design, which is never moved).
    A given bound is shown as given even when it excludes the start: the run then refuses it
    with the library's message naming the field.  An indexer: (None, None, None) — its
    optimiser's variables are C, the turret's size and r_r, their bounds its own (:func:`own_bounds_note`)."""
    if indexer_optimised(spec):
        return None, None, None
    translating = not follower_class_of(spec).pivoted       # only a translating follower has an offset
    probe = spec.replace(**{"optimise.variables": "base_radius, offset" if translating else "base_radius",
                            "optimise.objective": "area", "optimise.algorithm": "auto"})
    space = DesignSpace(probe)
    opt = spec.optimise
    found = (float(space.lower[space.r_index]), float(space.upper[space.r_index]),
             float(space.upper[space.e_index]) if translating else None)
    given = (opt.base_radius_min, opt.base_radius_max, opt.offset_max if translating else None)
    return tuple(float(g) if g is not None else f for g, f in zip(given, found))  # type: ignore[return-value]


def settings_of(spec: CamSpec) -> Settings:
    """The panel's starting values: the spec's ``[optimise]`` section, the bounds it leaves out
    filled with the library's defaults (:func:`default_bounds`).  An objective the cam's optimiser
    does not offer (the spec's default "area" on an indexer, which takes it as "size") is
    shown as the first it offers; an algorithm it does not offer as "auto"; no restarts where
    none apply (:func:`multistart_offered`)."""
    opt = spec.optimise
    r_lo, r_hi, e_max = default_bounds(spec)
    objectives = objective_choices(spec)
    objective = opt.objective if opt.objective in objectives else objectives[0]
    algorithm = opt.algorithm if opt.algorithm in algorithm_choices(spec) else "auto"
    return Settings(objective=objective, variables=opt.variables, algorithm=algorithm,
                    max_evaluations=opt.max_evaluations,
                    multistart=opt.multistart if multistart_offered(spec) else 0, seed=opt.seed,
                    base_radius_min=r_lo, base_radius_max=r_hi, offset_max=e_max)


def bound_is_default(spec: CamSpec) -> bool:
    """True when ``optimise.base_radius_min`` is not given: the lower bound is only the
    library's guess (½ × the initial R_b), not the shaft/hub/bore limit of the design."""
    return spec.optimise.base_radius_min is None


def run_spec(spec: CamSpec, settings: Settings) -> CamSpec:
    """``spec`` with the panel's settings as its ``[optimise]`` section.

    Raises:
        SpecError: a setting breaks a rule (the field is named, e.g. optimise.offset_max; an
            indexer's own rules too: objective normal_force without indexer.output_inertia …).
    """
    out = spec.replace(**settings.changes())
    own = indexer_optimiser_of(out)
    if own is not None:
        own.arguments(out)      # its optimiser's own rules, before the run
    return out


# ---- the threaded run ---------------------------------------------------------------------------
class OptimiseJob:
    """One run of :func:`cam_workbench.generators.optimise.optimise` in a worker thread.

    The worker only touches plain data; read :attr:`latest`, :attr:`history` (a list the worker
    appends to), :attr:`done`, :attr:`result` and :attr:`error` from any thread.
    :meth:`cancel` sets the library's ``threading.Event``: the run stops after the evaluation in
    progress (a few ms), re-checks the best design so far and ends with status "cancelled"."""

    def __init__(self, spec: CamSpec):
        self.spec = spec
        self.latest: Any = None            # the last cam_workbench.generators.optimise.Progress
        self.history: list[tuple[int, float, float, str]] = []  # (evaluation, objective, violation, phase)
        self.result: Any = None
        self.error: str | None = None
        self.cancel_event = threading.Event()
        self.started = self.finished = 0.0
        self.cancel_requested_at: float | None = None
        self._thread: threading.Thread | None = None

    @property
    def running(self) -> bool:
        return self._thread is not None and self._thread.is_alive()

    @property
    def done(self) -> bool:
        return self._thread is not None and not self._thread.is_alive()

    def _progress(self, p: Any) -> bool:
        self.latest = p
        self.history.append((p.evaluations, p.objective, p.max_violation, p.phase))
        return True

    def _work(self) -> None:
        try:
            self.result = optimise(self.spec, progress=self._progress, cancel=self.cancel_event)
        except CamError as exc:
            self.error = f"{props.describe_field(exc.field)}: {exc.rule}" if isinstance(exc, SpecError) else str(exc)
        except Exception as exc:  # noqa: BLE001 - shown by the panel, never raised in a thread
            self.error = f"{type(exc).__name__}: {exc}"
            self.traceback = traceback.format_exc()
        finally:
            self.finished = time.perf_counter()

    def start(self) -> "OptimiseJob":
        self.started = time.perf_counter()
        self._thread = threading.Thread(target=self._work, name="cam-workbench optimise", daemon=True)
        self._thread.start()
        return self

    def cancel(self) -> None:
        if self.cancel_requested_at is None:
            self.cancel_requested_at = time.perf_counter()
        self.cancel_event.set()

    def wait(self, timeout: float | None = None) -> bool:
        """Join the worker; True when it has finished."""
        if self._thread is not None:
            self._thread.join(timeout)
        return self.done


def run(spec: CamSpec) -> Any:
    """Optimise ``spec`` in the calling thread (scripts; the panel uses :class:`OptimiseJob`)."""
    job = OptimiseJob(spec).start()
    job.wait()
    if job.error is not None:
        raise CamError(job.error)
    return job.result


# ---- before / after -----------------------------------------------------------------------------
@dataclass(frozen=True)
class Figure:
    """One before/after row: a quantity, its values and its unit."""

    name: str
    before: float | str | None
    after: float | str | None
    unit: str = ""

    def cells(self) -> list[str]:
        """[quantity, before, after] with the unit on the values."""
        return [self.name, _fmt(self.before, self.unit), _fmt(self.after, self.unit)]


def _fmt(v: Any, unit: str = "") -> str:
    if v is None:
        return "—"
    if isinstance(v, str):
        return v
    text = "0" if v == 0 else f"{v:.6g}"
    return f"{text} {unit}" if unit and unit != "°" else f"{text}{unit}"


def _worst_text(w: dict[str, Any]) -> str:
    if not w:
        return "—"
    where = f" at {w['at_deg']:.1f}°" if w.get("at_deg") is not None else ""
    fail = " FAILS" if w["status"] == "fail" else ""
    return f"{w['name'].replace('_', ' ')} {fmt_value(w['value'], w['unit'])}{where}{fail}"


def result_objective_label(result: Any) -> str:
    """The result's objective in a few words, as its report names it: the words its optimiser gave
    (``details["objective_label"]``: a spatial indexer's "size" is its own cam's outer radius), else
    :func:`cam_workbench.generators.optimise.objectives.label`'s."""
    return result.details.get("objective_label") or objective_label(result.objective, result.initial_spec)


def figures(result: Any) -> list[Figure]:
    """The before/after figures of a result: objective (computed independently of the solver's
    model: :func:`cam_workbench.generators.optimise.final_value`), areas, R_b, e, the worst constraint (the
    check closest to or furthest past its limit), the design checks' verdict.  An indexer's: its
    objective (the body's own design of the start and the result; named as the result's report
    names it: a spatial indexer's "size" is its own outer radius), C, the turret's size and r_r, a
    spatial indexer's turret lengths that scale with its size, its other objective (report.json
    ``optimise.measures``), the worst constraint and the verdict."""
    a, b = result.initial_spec, result.spec
    u = a.units
    unit = UNITS[result.objective].replace("length", u)
    areas = result.details.get("areas", {})
    ia, fa = areas.get("initial", {}), areas.get("final", {})
    what = result_objective_label(result)
    rows = [Figure(f"objective: {result.objective} ({what})", result.initial_value, result.value, unit)]
    if indexer_optimised(a):
        labels = indexer_variable_labels(a)
        for path, x0, x1 in zip(result.variables, result.initial_design, result.design):
            name = labels.get(path, path)
            rows.append(Figure(f"{name[:1].lower()}{name[1:]} ({path})", float(x0), float(x1), u))
        own = indexer_optimiser_of(a)
        for path in own.scaled(a) if own is not None else ():
            rows.append(Figure(f"scales with the turret ({path})", _spec_value(a, path), _spec_value(b, path), u))
        for name, m in result.details.get("measures", {}).items():
            if name != result.objective:
                rows.append(Figure(f"{name} ({objective_label(name, a)})", m["initial"], m["final"],
                                   UNITS[name].replace("length", u)))
        rows.append(Figure("worst constraint", _worst_text(worst_constraint(result.initial_checks, a)),
                           _worst_text(worst_constraint(result.checks, b))))
        rows.append(Figure("design checks", _verdict(result.initial_checks), _verdict(result.checks)))
        return rows
    for key, name in area_keys(a, b, ia, fa):
        rows.append(Figure(name, ia[key], fa.get(key), f"{u}²"))
    ct = result.details.get("cutting_time")
    if ct:
        rows.append(Figure("thesis cutting time", ct["initial"].get("time_s"), ct["final"].get("time_s"), "s"))
        rows.append(Figure("thesis tool-path turns", ct["initial"].get("turns"), ct["final"].get("turns")))
    rows += [Figure("base radius R_b", a.cam.base_radius, b.cam.base_radius, u),
             Figure("follower offset e", a.follower.offset, b.follower.offset, u)]
    if "optimise.blank_orientation" in result.variables:
        rows.append(Figure("blank orientation", a.optimise.blank_orientation, b.optimise.blank_orientation, "°"))
    rows.append(Figure("worst constraint", _worst_text(worst_constraint(result.initial_checks, a)),
                       _worst_text(worst_constraint(result.checks, b))))
    rows.append(Figure("design checks", _verdict(result.initial_checks), _verdict(result.checks)))
    return rows


def _spec_value(spec: CamSpec, path: str) -> float | None:
    """The value of ``spec``'s field ``path`` ("section.field"), None where the spec leaves it out."""
    section, field = path.split(".", 1)
    v = getattr(getattr(spec, section), field)
    return None if v is None else float(v)


def area_keys(spec: CamSpec, final_spec: CamSpec, initial: dict[str, Any], final: dict[str, Any]
              ) -> list[tuple[str, str]]:
    """(key of report.json's ``areas``, row name) of the areas the result shows — those that
    exist for the follower: the thesis' Eq. 4.21 area (a translating knife edge or roller's;
    ``None`` for every other follower: ``cam_workbench.generators.checks.areas.area_summary``), else the exact
    area inside the design curve (the pitch curve, or a flat face's contact curve); the area
    inside the profile unless it is that same area (a knife edge or a flat face: offset 0); the
    cross-section minus the bore when there is a bore."""
    curve = follower_of(spec).describe()["curve"]
    keys = []
    first = "thesis_eq_4_21"
    if initial.get(first) is None and final.get(first) is None:
        first = "pitch_curve"
    keys.append(first)
    if "profile" in initial and not (first == "pitch_curve" and initial["profile"] == initial[first]
                                     and final.get("profile") == final.get(first)):
        keys.append("profile")
    if spec.cam.bore_diameter > 0 or final_spec.cam.bore_diameter > 0:
        keys.append("cross_section")
    return [(k, area_label(k, curve)) for k in keys if k in initial]


def _verdict(checks: Any) -> str:
    return "all pass" if checks.passed else "FAIL: " + ", ".join(n.replace("_", " ") for n in checks.failed)


@dataclass(frozen=True)
class CheckChange:
    """One design check before and after (the Check design table's rows, side by side)."""

    before: Any   # check_design.CheckRow
    after: Any

    def cells(self) -> list[str]:
        b, a = self.before.cells(), self.after.cells()
        # check, limit, before value, at, status, after value, at, status
        return [b[0], a[3], b[1], b[2], b[4], a[1], a[2], a[4]]


CHECK_HEADERS = ["check", "limit", "before", "at", "status", "after", "at", "status"]


def _results(checks: Any) -> dict[str, Any]:
    """report.json's ``checks.results`` of a ``DesignChecks`` (a body's own optimiser re-checks with
    its own design, so its checks have no plane-cam state to sample: ``to_dict()`` needs one)."""
    return {"results": {r.name: r.to_dict() for r in checks.results}}


def check_comparison(result: Any) -> list[CheckChange]:
    """Every design check of the starting and the optimised design (dense, refined re-check)."""
    before = {r.name: r for r in check_rows(_results(result.initial_checks))}
    after = check_rows(_results(result.checks))
    return [CheckChange(before[r.name], r) for r in after if r.name in before]


def history_arrays(history: list[tuple[int, float, float, str]]) -> dict[str, Any]:
    """The run's history by phase: {phase: (evaluations, objective, violation)} as numpy arrays."""
    out: dict[str, Any] = {}
    for phase in dict.fromkeys(h[3] for h in history):
        sel = [h for h in history if h[3] == phase]
        out[phase] = (np.array([h[0] for h in sel]), np.array([h[1] for h in sel], dtype=float),
                      np.array([h[2] for h in sel], dtype=float))
    return out


# ---- apply ----------------------------------------------------------------------------------------
def _design_part(spec: CamSpec) -> CamSpec:
    """The spec without its [optimise] section (how to optimise, not what the cam is)."""
    return dataclasses.replace(spec, optimise=OptimiseSection())


def changed_since(obj: Any, start: Any) -> str | None:
    """Why the feature no longer holds the design ``start`` (a CamSpec, or an OptimiseResult:
    its initial spec) — None if it does.  The ``[optimise]`` settings do not count."""
    spec = getattr(start, "initial_spec", start)
    try:
        current = props.spec_of(obj)
    except SpecError as exc:
        return f"{props.describe_field(exc.field)}: {exc.rule}"
    if _design_part(current) != _design_part(spec):
        return "the cam's properties changed"
    return None


def apply_result(obj: Any, result: Any, allow_failing: bool = False) -> None:
    """Write ``result.spec`` into ``obj``'s properties and recompute, as ONE undo step
    ("Optimise cam").  The written spec is the optimised design with the ``[optimise]``
    section the run used (objective, variables, algorithm, bounds, budget): the panel's choices
    are stored only here, never on Close.

    Raises:
        ApplyError: the result fails the dense re-check and ``allow_failing`` is False, or the
            feature changed since the run started; the new shape could not be built (the
            transaction is aborted: nothing changes).
    """
    if not result.feasible and not allow_failing:
        raise ApplyError(f"the optimised design fails the dense re-check ({', '.join(result.checks.failed)}); "
                         "apply it only after confirming")
    why = changed_since(obj, result)
    if why is not None:
        raise ApplyError(f"not applied: {why} since the run started; run the optimiser again")
    doc = obj.Document
    doc.openTransaction(TRANSACTION)
    try:
        props.write_spec(obj, result.spec)
        doc.recompute()
        if not str(obj.Status).startswith("ok"):
            raise ApplyError(f"the optimised cam could not be built: {obj.Status}")
    except Exception:
        doc.abortTransaction()
        raise
    doc.commitTransaction()


__all__ = ["ALGORITHM_LABELS", "ApplyError", "BODY_VARIABLE_LABELS", "CHECK_HEADERS", "CheckChange", "Figure",
           "INDEXER_ALGORITHM_LABELS", "INDEXER_OPTIMISERS", "INDEXER_VARIABLE_LABELS", "INDEXER_VARIABLE_SYMBOLS",
           "IndexerOptimiser", "OBJECTIVE_LABELS", "OptimiseJob", "Settings", "VariableChoice",
           "algorithm_choices", "algorithm_label", "apply_result", "bound_is_default", "changed_since",
           "check_comparison", "default_bounds", "figures", "fixed_variables_note", "history_arrays",
           "indexer_optimised", "indexer_optimiser_of", "indexer_variable_labels", "multistart_offered",
           "objective_choices", "own_bounds_note", "result_objective_label", "run", "run_spec",
           "selected_tokens", "settings_of", "variable_choices", "variables_text"]

"""What makes a failing check pass: the nearest change of one spec field with everything else held
(report.json's ``checks.results[name].remedy``, the messages of a cam that cannot be made).

Each failing check is mapped to the fields that move it (:func:`plans`):

* the cam's size — ``cam.base_radius`` for a plate, groove or conjugate cam on a translating
  follower (pressure angle, curvature, undercut, convexity, cusp, contact stress, a groove's bore
  wall and outer-wall undercut), ``cam.outer_diameter`` for a groove's rim wall,
  ``cam.cylinder_radius`` for a cylindrical cam, ``conjugate.roller_distance`` for the second cam
  of a yoke pair: the smallest value that passes, by the bisection of ``sweep --size``
  (:func:`cam_workbench.generators.studies.sizing.smallest_value`);
* a translating follower's ``follower.offset`` for its pressure angle (the offset whose sign lowers
  the binding φ), an oscillating arm's ``follower.pivot_distance`` and its ``cam.base_radius``
  (passing is not monotonic in them): the nearest value that passes on either side
  (:func:`cam_workbench.generators.studies.sizing.nearest_value`);
* ``follower.face_width``: the width the contact needs;
* what no single size fixes (separation, oscillation, continuity, a conjugate arm pair's second
  cam) in words.

A search first asks every check to pass; when a check no field of it moves also fails (or nothing
passes every check) it asks only the checks the field is searched for, and says which still fail.
The design checks are searched with :func:`~cam_workbench.generators.checks.design.run_checks` (a groove's walls
with the whole design, :func:`~cam_workbench.generators.cam_design.design_cam`, whose refusal names its failing
walls; a cylindrical cam with its own checks).  The value found is rounded to the tolerance's digits
towards the passing side (then the smallest such value that passes: a value one digit nearer the
spec's own fails), and the spec at that value is checked again, buildability and walls included:
what still fails there is named.  It costs about 15–50 check runs per field (a wall's: designs), so
:func:`add_remedies` is called only when a check fails.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence

from ..cam_design import design_cam
from ..checks.design import CAM_SUFFIXES, base_check_name
from ..errors import CamError, GeometryError, SpecError
from ..kinds import body_of, follower_class_of
from ..spec.model import CamSpec
from .plan import Plan
from .sizing import (SIZED_FIELDS, Evaluate, SizingSettings, design_checks_evaluation, digits_of, nearest_value,
                     smallest_value)

#: the checks a larger cam passes (for a translating follower: a larger base radius)
SIZE_CHECKS = ("pressure_angle", "curvature", "undercut", "convexity", "cusp", "contact_stress")
#: the checks of a groove cam's walls (GeometryError.checks) → the field that moves each
WALL_FIELDS = {"rim_wall": "cam.outer_diameter", "bore_wall": "cam.base_radius",
               "outer_wall_undercut": "cam.base_radius"}
#: what to change, in words, where no single size passes
WORDS = {
    "separation": "no size of the cam makes it pass: the follower's load must hold it on the cam — a larger "
                  "{preload} or {spring}, a lighter {mass} or a lower cam.speed_rpm, or a groove or conjugate body "
                  "(cam.body: positive drive)",
    "oscillation": "the motion's own: no size or position changes it — a law whose velocity keeps its sign over the "
                   "rise or return there (motion[k].law), or a smaller lift",
    "continuity": "the motion's own: no size or position changes it — laws that match their neighbours at the "
                  "junction (see the note), or checks.min_continuity",
    "contact_stress": "a thicker cam (cam.thickness), a larger roller, or a stronger material "
                      "(material.allowable_stress)",
    "second_arm": "the second arm's geometry: conjugate.arm_length or conjugate.arm_angle (the pair's second cam "
                  "follows from them)",
}


@dataclass(frozen=True)
class Remedy:
    """The nearest change that passes (``field`` None: none; ``text`` says what to change)."""

    field: str | None
    text: str
    value: float | None = None
    unit: str = ""
    current: float | None = None
    search: str = "words"
    tolerance: float | None = None
    changes: dict[str, float] = field(default_factory=dict)
    digits: int = 0
    passes: tuple[str, ...] = ()            # the checks that pass at the value
    fails: tuple[str, ...] = ()             # the checks that still fail there
    evaluations: int = 0

    @property
    def command(self) -> str | None:
        """The ``--set`` options that apply it (None: no single field)."""
        if not self.changes:
            return None
        return " ".join(f"--set {k}={_fmt(v, self.digits)}" for k, v in self.changes.items())

    def to_dict(self) -> dict[str, Any]:
        return {"field": self.field, "value": self.value, "unit": self.unit, "current": self.current,
                "search": self.search, "tolerance": self.tolerance, "changes": dict(self.changes),
                "passes": list(self.passes), "fails": list(self.fails), "passes_all": not self.fails
                and self.field is not None, "command": self.command, "text": self.text,
                "evaluations": self.evaluations}


def _fmt(v: float, digits: int) -> str:
    text = f"{v:.{digits}f}"
    return "0" if text.strip("-0.") == "" else text


# ---- which field moves which check ------------------------------------------------------------
def plans(spec: CamSpec, name: str) -> list[Plan]:
    """The fields to search for the failing check ``name`` of ``spec`` (its body's wall checks
    included), first the one to show; [] when no single field moves it."""
    base = base_check_name(name)
    if base != name:                                        # a further cam's own check: a conjugate pair's
        if "cam2" in CAM_SUFFIXES and not follower_class_of(spec).pivoted and base in SIZE_CHECKS:
            return [Plan("conjugate.roller_distance", "smallest")]
        return []
    if name in WALL_FIELDS:
        return [Plan(WALL_FIELDS[name], "smallest", "design")]
    own = body_of(spec).remedy_plans(spec, base)
    if own is not None:                                     # a body that sizes itself (its own checks)
        return own
    if name == "face_width":                                # a flat face's own check
        return [Plan("follower.face_width", "needed")]
    if base not in SIZE_CHECKS:
        return []
    return follower_class_of(spec).remedy_plans(spec, base)


def words(spec: CamSpec, name: str) -> str:
    """What to change, in words, for a check no single field passes."""
    base = base_check_name(name)
    if base != name:                    # a further cam's check that no field moves (an arm pair's second cam)
        return WORDS["second_arm"]
    own = body_of(spec).remedy_words(spec, base)
    if own is not None:                 # the body's own words (a cylindrical cam's corner)
        return own
    osc = follower_class_of(spec).pivoted
    text = WORDS.get(base, "no single field of the spec moves it")
    return text.format(preload="follower.preload_torque" if osc else "follower.preload",
                       spring="follower.spring_torque_rate" if osc else "follower.spring_rate",
                       mass="follower.arm_inertia" if osc else "follower.mass")


# ---- evaluations ---------------------------------------------------------------------------------
def evaluation(spec: CamSpec, kind: str) -> Evaluate:
    """The evaluation a plan searches with: the dense design checks, the whole design (a groove's
    walls: a refused body names its failing checks), or the body's own checks (``Body.own_checks``:
    a cylindrical cam's)."""
    if kind == "checks":
        return design_checks_evaluation(spec)
    if kind == "body":
        own_checks = body_of(spec).own_checks

        def body(s: CamSpec) -> tuple[tuple[str, ...], Any]:
            try:
                d = own_checks(s)
            except GeometryError as exc:
                return exc.checks or (exc.kind,), None
            return tuple(d["failed"]), d

        return body

    def design(s: CamSpec) -> tuple[tuple[str, ...], Any]:
        try:
            d = design_cam(s)
        except GeometryError as exc:
            return exc.checks or (exc.kind,), None
        except CamError as exc:
            return (f"spec rule: {exc}",), None
        return tuple(d.design_checks.failed), d.design_checks

    return design


def _current(spec: CamSpec, dotted: str) -> float | None:
    section, _, name = dotted.partition(".")
    v = getattr(getattr(spec, section), name)
    return None if v is None else float(v)


def _set(spec: CamSpec, dotted: str, value: float) -> dict[str, float]:
    sized = SIZED_FIELDS.get(dotted)
    return sized.set(spec, value) if sized is not None else {dotted: float(value)}


# ---- the search ------------------------------------------------------------------------------------
def _search(spec: CamSpec, plan: Plan, targets: tuple[str, ...] | None, tol: float, checks_result: Any
            ) -> tuple[float | None, int, int]:
    """(the passing value found — None: none —, the side it lies on (+1 above the spec's value, −1
    below), evaluations)."""
    ev = evaluation(spec, plan.evaluation)
    if plan.search == "smallest":
        sz = smallest_value(spec, plan.field, SizingSettings(checks=targets), ev)
        return sz.value, 1, sz.evaluations
    if plan.search == "needed":
        return float(checks_result["value"]), 1, 0
    best: tuple[float, int] | None = None
    count = 0
    current = _current(spec, plan.field) or 0.0
    for direction, bound in ((1, plan.bounds[1]), (-1, plan.bounds[0])):
        n = nearest_value(spec, plan.field, direction, bound, tol=tol, evaluate=ev, checks=targets)
        count += n.evaluations
        if n.value is not None and (best is None or abs(n.value - current) < abs(best[0] - current)):
            best = (n.value, direction)
    return (None, 1, count) if best is None else (best[0], best[1], count)


def _on_grid(spec: CamSpec, plan: Plan, value: float, side: int, tol: float, test: Callable[[float], bool]
             ) -> float:
    """``value`` rounded to the tolerance's digits away from the spec's value, then moved back a
    digit at a time while that still passes (at most tol/digit steps): the smallest such value."""
    q = 10.0 ** -digits_of(tol)
    grid = (math.ceil(value / q - 1e-9) if side > 0 else math.floor(value / q + 1e-9)) * q
    grid = round(grid, digits_of(tol))
    if not test(grid):            # not monotonic within a digit: the bisection's own end
        return value
    for _ in range(int(round(tol / q))):
        nearer = round(grid - side * q, digits_of(tol))
        if not test(nearer):
            break
        grid = nearer
    return grid


def remedy_for(spec: CamSpec, plan: Plan, targets: tuple[str, ...], all_checks: bool, checks_result: Any = None
               ) -> Remedy:
    """The remedy ``plan`` finds for the failing checks ``targets``: every check passing when
    ``all_checks`` (and when one does), else only ``targets``."""
    tol = SizingSettings().tolerance(spec.units)
    digits = digits_of(tol)
    unit = spec.units
    current = _current(spec, plan.field)
    ev = evaluation(spec, plan.evaluation)
    count = [0]

    def failures(v: float) -> tuple[str, ...] | None:
        try:
            s = spec.replace(**_set(spec, plan.field, v))
        except SpecError:
            return None
        count[0] += 1
        try:
            return ev(s)[0]
        except CamError:                 # a cam that cannot be solved there does not pass
            return None

    def passes(v: float, names: tuple[str, ...] | None) -> bool:
        f = failures(v)
        return f is not None and not [n for n in f if names is None or n in names]

    found, side, n = None, 1, 0
    names: tuple[str, ...] | None = None
    if all_checks:
        found, side, n = _search(spec, plan, None, tol, checks_result)
    if found is None:
        names = targets
        found, side, n2 = _search(spec, plan, targets, tol, checks_result)
        n += n2
    if found is not None:
        value = _on_grid(spec, plan, found, side, tol, lambda v: passes(v, names))
        changes = {k: round(v, digits) for k, v in _set(spec, plan.field, value).items()}
        final = spec.replace(**changes)
        try:
            fails = tuple(ev(final)[0]) if plan.evaluation != "checks" else _design_failures(final)
        except CamError:                 # its cam passes the checks but cannot be solved: no remedy
            found = None
    if found is None:
        where = "either side of" if plan.search == "nearest" else "above"
        return Remedy(None, f"no {plan.field} {where} {current or 0.0:g} {unit} passes "
                      f"{', '.join(targets)} (everything else held)", unit=unit, current=current,
                      search=plan.search, tolerance=tol, evaluations=n)
    count[0] += 1
    how = {"smallest": f"the smallest that does, by bisection to {tol:g} {unit}",
           "nearest": f"the nearest to {current or 0.0:g} {unit} that does, to {tol:g} {unit}",
           "needed": "the width the contact needs"}[plan.search]
    what = ("every check" if not fails else ", ".join(t for t in targets if t not in fails))
    text = f"{plan.field} = {_fmt(value, digits)} {unit} passes {what} ({how}; the rest held)"
    if plan.field == "follower.offset" and current and value * current < 0:
        text += "; the offset's other sign lowers the binding pressure angle"
    if len(changes) > 1:
        text += "; with " + ", ".join(f"{k} = {_fmt(v, digits)}" for k, v in changes.items() if k != plan.field)
    if fails:
        text += f"; {', '.join(fails)} still fail{'s' if len(fails) == 1 else ''} there"
    pas = tuple(t for t in targets if t not in fails)
    return Remedy(plan.field, text, value, unit, current, plan.search, tol, changes, digits, pas, fails,
                  n + count[0])


def _design_failures(spec: CamSpec) -> tuple[str, ...]:
    """The checks ``spec`` fails, buildability included (a refusal names its checks)."""
    try:
        return tuple(design_cam(spec).design_checks.failed)
    except GeometryError as exc:
        return exc.checks or (exc.kind,)


# ---- for the report and the messages -----------------------------------------------------------------
def remedies(spec: CamSpec, failed: Sequence[str], results: Mapping[str, Any] | None = None
             ) -> dict[str, dict[str, Any]]:
    """The remedy of each failing check of ``spec`` (name → :meth:`Remedy.to_dict`, the first plan's
    with the others as ``alternatives``); ``results``: report.json's ``checks.results`` (the
    check's own value, for the face width)."""
    results = results or {}
    planned = {name: plans(spec, name) for name in failed}
    unmoved = [n for n, p in planned.items() if not p]
    groups: dict[Plan, list[str]] = {}
    for name, ps in planned.items():
        for p in ps:
            groups.setdefault(p, []).append(name)
    found: dict[Plan, Remedy] = {}
    for plan, names in groups.items():
        found[plan] = remedy_for(spec, plan, tuple(names), all_checks=not unmoved, checks_result=results.get(names[0]))
    out: dict[str, dict[str, Any]] = {}
    for name, ps in planned.items():
        if not ps:
            out[name] = Remedy(None, words(spec, name), unit=spec.units).to_dict()
            continue
        first, *others = [found[p].to_dict() for p in ps]
        # an alternative only where it passes (every check, when the first does)
        first["alternatives"] = [o for o in others if o["field"] is not None
                                 and (o["passes_all"] or not first["passes_all"])]
        out[name] = first
    return out


def add_remedies(checks: dict[str, Any], spec: CamSpec) -> dict[str, Any]:
    """report.json's ``checks`` section with a ``remedy`` in every failing result (in place; only
    when a check fails)."""
    failed = list(checks.get("failed") or [])
    if failed:
        for name, r in remedies(spec, failed, checks.get("results")).items():
            checks["results"][name]["remedy"] = r
    return checks


def remedy_lines(checks: Mapping[str, Any]) -> list[str]:
    """One line per failing check that has a remedy: "name: text → command" (the remedy's own
    text, as report.json holds it)."""
    lines = []
    for name, r in (checks.get("results") or {}).items():
        rem = r.get("remedy") if isinstance(r, Mapping) else None
        if not rem:
            continue
        lines.append(remedy_line(name, rem))
    return lines


def remedy_line(name: str, rem: Mapping[str, Any]) -> str:
    """One remedy (and its alternatives) as a line of text."""
    parts = [_one(rem)] + [_one(a) for a in rem.get("alternatives") or []]
    return f"{name}: " + "; or ".join(parts)


def _one(rem: Mapping[str, Any]) -> str:
    cmd = rem.get("command")
    return rem["text"] + (f" → {cmd}" if cmd else "")


def refusal_remedies(spec: CamSpec, exc: GeometryError) -> dict[str, dict[str, Any]]:
    """The remedies of a cam that cannot be made: one per failing body check the refusal names
    (a groove's walls), or for its own kind (an undercut, a cusp); {} when no field moves it."""
    names = exc.checks or (exc.kind,)
    names = tuple(n for n in names if plans(spec, n))
    return remedies(spec, names) if names else {}


def with_remedy(spec: CamSpec, exc: GeometryError) -> GeometryError:
    """``exc`` with the remedies of :func:`refusal_remedies` added to its message (itself when
    there are none)."""
    found = refusal_remedies(spec, exc)
    if not found:
        return exc
    text = f"{exc} — " + "; ".join(remedy_line(n, r) for n, r in found.items())
    out = GeometryError(exc.kind, text, exc.angle_deg, exc.checks)
    out.__cause__ = exc
    return out

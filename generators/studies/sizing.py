"""The smallest value of a spec field that meets the design checks (a sizing chart's value at one
point; a failing check's remedy).

:func:`smallest_value` bisects on one field — ``cam.base_radius`` for ``sweep --size`` and
:func:`smallest_base_radius`, or another of :data:`SIZED_FIELDS` (a groove's disc diameter, a
cylindrical cam's cylinder radius, a conjugate pair's roller distance) — with an evaluation of the
spec (default: the dense design checks, :func:`cam_workbench.generators.checks.design.run_checks`: 1001 samples
per rise/return, extrema refined):

1. ``lo`` = the largest value the spec's rules refuse whatever the motion (for R_b: R_b ≤ |offset|,
   or R_b − roller radius ≤ bore radius): it fails;
2. ``hi`` = the spec's own value, doubled until it passes (at most ``max_doublings`` times; if none
   passes, or the spec's rules refuse a larger value — an oscillating arm's pivot_distance +
   arm_length —, the point has no value and the row says which check still fails, and where);
3. halve [lo, hi] keeping ``lo`` failing and ``hi`` passing until hi − lo ≤ ``tol``.

Every value tried is on the grid of the tolerance's digits (:class:`TolGrid`: multiples of 0.01 for
0.01 mm), so the answer is a round number that was itself evaluated, and every output — the table
``sweep`` prints, the CSV, the chart, a remedy's ``--set`` — shows it as it is (41.78, not 41.7753).
The answer is ``hi``: it passes, and a value at most ``tol`` smaller fails (or is refused), so the
true boundary lies in (hi − tol, hi].  Default tolerance: 0.01 mm, 0.0005 in.  That is the
smallest value only if passing is monotonic in it — a larger cam never fails a check a smaller
one passes.  For R_b that holds for the pressure angle (|φ| falls as R_b grows), the curvature,
undercut and cusp checks (the pitch curve's radius of curvature grows with R_b) and the Hertz
stress; the separation, oscillation and face-width checks do not depend on R_b for a translating
follower (they pass everywhere or nowhere).  ``checks`` restricts the sizing to some checks (e.g.
only ``pressure_angle`` and ``curvature``, the classic nomogram); the others are then ignored.

:func:`nearest_value` searches a field in which passing is not monotonic (a translating follower's
offset, an oscillating arm's pivot distance) from the spec's own value in one direction — steps
doubling from ``tol`` until one passes — and bisects the last step the same way.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

from ..checks.design import DesignChecks, run_checks
from ..errors import CamError, SpecError
from ..motion.program import MotionProgram
from ..spec.model import CamSpec
from .table import checks_row

#: every check :func:`run_checks` may report (which ones a spec gets depends on its follower)
KNOWN_CHECKS = ("pressure_angle", "separation", "oscillation", "contact_stress", "curvature", "convexity",
                "undercut", "cusp", "face_width")
#: default bisection tolerance on a length, per spec unit
DEFAULT_TOL = {"mm": 0.01, "in": 0.0005}
SIZED_FIELD = "cam.base_radius"

#: an evaluation of a spec: (the names of the checks it fails, what to keep of the passing one)
Evaluate = Callable[[CamSpec], "tuple[tuple[str, ...], Any]"]


def digits_of(tol: float) -> int:
    """Decimals that show a tolerance's size: 0.01 → 2, 0.0005 → 4."""
    return max(0, -math.floor(math.log10(tol) + 1e-9))


@dataclass(frozen=True)
class TolGrid:
    """The values a bisection to ``tol`` tries: multiples of 10^−d, d = :func:`digits_of` (tol),
    rounded to d decimals — so that a value prints, and reads back from a CSV, as it is."""

    tol: float

    @property
    def digits(self) -> int:
        return digits_of(self.tol)

    @property
    def step(self) -> float:
        return 10.0 ** -self.digits

    def _value(self, k: int) -> float:
        return round(k * self.step, self.digits)

    def up(self, x: float) -> float:
        """The smallest grid value ≥ x."""
        return self._value(math.ceil(x / self.step - 1e-9))

    def down(self, x: float) -> float:
        """The largest grid value ≤ x."""
        return self._value(math.floor(x / self.step + 1e-9))

    def middle(self, a: float, b: float) -> float | None:
        """A grid value halfway between the grid values ``a`` and ``b`` (either order); None when
        they are at most ``tol`` apart (the bisection is done)."""
        i, j = sorted((round(a / self.step), round(b / self.step)))
        if (j - i) * self.step <= self.tol * (1 + 1e-9):
            return None
        return self._value((i + j) // 2)


def geometric_lower_bound(spec: CamSpec) -> float:
    """The largest R_b the spec's rules refuse whatever the motion: |offset| (R_b > |e|) or the
    roller radius plus the bore radius (the bore inside the base circle of the cam surface)."""
    return max(abs(spec.follower.offset), spec.roller_radius + 0.5 * spec.cam.bore_diameter, 0.0)


def _same_offset_from_pitch(spec: CamSpec, value: float) -> dict[str, float]:
    """A cylindrical cam's radius with its outer diameter, when given, moved along (the groove's
    depth about the pitch radius kept)."""
    cam = spec.cam
    changes = {"cam.cylinder_radius": float(value)}
    if cam.outer_diameter is not None:
        changes["cam.outer_diameter"] = cam.outer_diameter + 2.0 * (float(value) - cam.cylinder_radius)
    return changes


@dataclass(frozen=True)
class SizedField:
    """A spec field that :func:`smallest_value` can size: its dotted name, the symbol its messages
    use, the largest value the spec's rules refuse whatever the motion, and the changes that set it
    (fields that move with it)."""

    name: str
    symbol: str
    lower_bound: Callable[[CamSpec], float] = lambda spec: 0.0
    changes: Callable[[CamSpec, float], dict[str, float]] | None = None
    #: what the spec's rules at ``lower_bound`` are, for the binding-check column
    refused: str = ""

    def current(self, spec: CamSpec) -> float:
        section, _, name = self.name.partition(".")
        return float(getattr(getattr(spec, section), name))

    def set(self, spec: CamSpec, value: float) -> dict[str, float]:
        """The spec changes that give the field ``value``."""
        return self.changes(spec, value) if self.changes is not None else {self.name: float(value)}


#: the fields :func:`smallest_value` sizes (each larger value makes a larger cam)
SIZED_FIELDS = {f.name: f for f in (
    SizedField("cam.base_radius", "R_b", geometric_lower_bound, refused="offset, roller and bore"),
    SizedField("cam.outer_diameter", "the disc diameter", refused="the disc's rules"),
    SizedField("cam.cylinder_radius", "R_p", changes=_same_offset_from_pitch, refused="the cylinder's rules"),
    SizedField("conjugate.roller_distance", "the roller distance", refused="the pair's rules"),
)}


@dataclass(frozen=True)
class SizingSettings:
    """What :func:`smallest_value` sizes against: ``checks`` (None: every check), the absolute
    tolerance in the spec's unit (None: :data:`DEFAULT_TOL`), and how often the spec's value may
    be doubled looking for one that passes."""

    checks: tuple[str, ...] | None = None
    tol: float | None = None
    max_doublings: int = 12

    def tolerance(self, units: str) -> float:
        return float(self.tol) if self.tol is not None else DEFAULT_TOL[units]


@dataclass(frozen=True)
class Sizing:
    """The outcome at one point."""

    value: float | None             # the smallest value found that passes (None: no value)
    below: float                    # a value that fails or is refused, value − below ≤ tol
    tol: float
    status: str                     # "ok" or "no radius"
    reason: str                     # "no radius": why; "ok": ""
    binding: tuple[str, ...]        # the checks failing at ``below`` ("spec rule: …" where refused)
    evaluations: int                # evaluations of the spec (design-check runs)
    checks: Any                     # what the evaluation kept at ``value`` (the DesignChecks)
    field: str = SIZED_FIELD


def check_names(names: Sequence[str] | str | None, option: str = "--size-checks") -> tuple[str, ...] | None:
    """Parse and check a list of check names (None/"all": every check).

    Raises:
        SpecError: an unknown name (the known ones listed).
    """
    if names is None:
        return None
    if isinstance(names, str):
        if names.strip() in ("", "all"):
            return None
        names = [n.strip() for n in names.split(",") if n.strip()]
    out = tuple(dict.fromkeys(names))
    bad = [n for n in out if n not in KNOWN_CHECKS]
    if bad:
        raise SpecError(option, f"unknown check {bad[0]!r} (checks: {', '.join(KNOWN_CHECKS)})")
    return out or None


def design_checks_evaluation(spec: CamSpec) -> Evaluate:
    """The dense design checks of a spec with ``spec``'s motion (it does not depend on the sized
    fields): (failed check names, the :class:`DesignChecks`)."""
    program = MotionProgram.from_spec(spec)

    def evaluate(s: CamSpec) -> tuple[tuple[str, ...], DesignChecks]:
        dc = run_checks(s, program=program)
        return tuple(dc.failed), dc

    return evaluate


class _Tester:
    """Sets the field, evaluates, counts; a value the spec's rules refuse fails as "spec rule: …",
    one whose cam cannot be made or solved as "cannot be made: …"."""

    def __init__(self, spec: CamSpec, sized: SizedField, evaluate: Evaluate, names: tuple[str, ...] | None):
        self.spec, self.sized, self.evaluate, self.names = spec, sized, evaluate, names
        self.count = 0

    def __call__(self, value: float) -> tuple[bool, tuple[str, ...], Any]:
        try:
            s = self.spec.replace(**self.sized.set(self.spec, float(value)))
        except SpecError as exc:
            return False, (f"spec rule: {exc}",), None
        self.count += 1
        try:
            failed, kept = self.evaluate(s)
        except CamError as exc:          # a value whose cam cannot be made or solved does not pass
            return False, (f"cannot be made: {exc}",), None
        failed = tuple(n for n in failed if self.names is None or n in self.names)
        return not failed, failed, kept


def bisect(test: Callable[[float], "tuple[bool, tuple[str, ...], Any]"], failing: float, passing: float,
           tol: float, failed: tuple[str, ...], kept: Any, grid: TolGrid | None = None
           ) -> tuple[float, float, tuple[str, ...], Any]:
    """Halve [failing, passing] (either order) keeping one end failing and the other passing until
    they are ``tol`` apart: (passing end, failing end, the checks failing there, what the passing
    end's evaluation kept).  With ``grid`` (ends on it) every value tried is on it too."""
    n_steps = max(0, math.ceil(math.log2(max(abs(passing - failing), tol) / tol))) + 1
    for _ in range(n_steps):
        if grid is not None:
            mid = grid.middle(failing, passing)
            if mid is None:
                break
        elif abs(passing - failing) <= tol:
            break
        else:
            mid = 0.5 * (failing + passing)
        ok, f, k = test(mid)
        if ok:
            passing, kept = mid, k
        else:
            failing, failed = mid, f
    return passing, failing, failed, kept


def smallest_value(spec: CamSpec, field: str = SIZED_FIELD, settings: SizingSettings | None = None,
                   evaluate: Evaluate | None = None) -> Sizing:
    """The smallest value of ``field`` (one of :data:`SIZED_FIELDS`; everything else as it is)
    that passes ``evaluate`` (default: the dense design checks) restricted to the checks of
    ``settings`` (see the module's docstring for the bisection).

    Raises:
        SpecError: ``--tol`` not positive.
    """
    settings = settings or SizingSettings()
    sized = SIZED_FIELDS[field]
    tol = settings.tolerance(spec.units)
    if not tol > 0:
        raise SpecError("--tol", f"must be > 0, got {tol:g}")
    test = _Tester(spec, sized, evaluate or design_checks_evaluation(spec), settings.checks)
    sym = sized.symbol
    current = sized.current(spec)

    grid = TolGrid(tol)
    bound = sized.lower_bound(spec)
    lo = grid.down(bound)
    lo_failed: tuple[str, ...] = (f"spec rule: {sym} ≤ {bound:.6g} is refused ({sized.refused})",)
    hi = grid.up(max(current, lo + tol))
    ok, failed, kept = test(hi)
    doublings = 0
    while not ok:
        if failed and failed[0].startswith("spec rule") and hi > current:
            return Sizing(None, hi, tol, "no radius", f"at {sym} = {hi:.6g}: {failed[0][len('spec rule: '):]}",
                          failed, test.count, None, field)
        if doublings >= settings.max_doublings:
            where = "; ".join(_failure_text(kept, n) for n in failed) if isinstance(kept, DesignChecks) else failed[0]
            return Sizing(None, hi, tol, "no radius", f"no {sym} up to {hi:.6g} passes: {where}", failed,
                          test.count, None, field)
        if failed and not failed[0].startswith("spec rule"):
            lo, lo_failed = hi, failed
        hi = grid.up(2.0 * hi)
        doublings += 1
        ok, failed, kept = test(hi)
    hi, lo, lo_failed, best = bisect(test, lo, hi, tol, lo_failed, kept, grid)
    return Sizing(hi, lo, tol, "ok", "", lo_failed, test.count, best, field)


def smallest_base_radius(spec: CamSpec, settings: SizingSettings | None = None) -> Sizing:
    """The smallest ``cam.base_radius`` of ``spec`` (everything else as it is) that passes the
    design checks of ``settings`` (see the module's docstring for the bisection)."""
    return smallest_value(spec, SIZED_FIELD, settings)


@dataclass(frozen=True)
class Nearest:
    """The outcome of :func:`nearest_value`: the passing value nearest the spec's own in one
    direction (None: none before ``bound``), the failing value within ``tol`` of it, and why."""

    value: float | None
    failing: float
    binding: tuple[str, ...]
    evaluations: int
    kept: Any = field(default=None, repr=False)


def nearest_value(spec: CamSpec, field_name: str, direction: int, bound: float, *, tol: float,
                  evaluate: Evaluate | None = None, checks: tuple[str, ...] | None = None) -> Nearest:
    """The value of ``field_name`` nearest the spec's own, in ``direction`` (+1 up, −1 down) and
    short of ``bound``, that passes ``evaluate`` restricted to ``checks``: steps of ``tol``·2^k
    from the spec's value until one passes (or the spec's rules refuse it, or ``bound`` is
    reached), then the bisection of :func:`smallest_value` on the last step.  For a field in which
    passing is not monotonic a passing stretch narrower than a step can be stepped over."""
    sized = SizedField(field_name, field_name)
    test = _Tester(spec, sized, evaluate or design_checks_evaluation(spec), checks)
    x0 = sized.current(spec)
    failing, failed = x0, ()
    step = tol
    while True:
        x = x0 + direction * step
        if (bound - x) * direction <= 0:
            x = bound - direction * tol
            if (x - failing) * direction <= 0:
                return Nearest(None, failing, failed, test.count)
        ok, f, kept = test(x)
        if ok:
            value, below, failed, kept = bisect(test, failing, x, tol, failed, kept)
            return Nearest(value, below, failed, test.count, kept)
        if f and f[0].startswith("spec rule"):
            return Nearest(None, x, f, test.count)
        failing, failed = x, f
        if x == bound - direction * tol:
            return Nearest(None, failing, failed, test.count)
        step *= 2.0


def _failure_text(dc: DesignChecks, name: str) -> str:
    r = dc[name]
    unit = f" {r.unit}" if r.unit else ""
    at = f" at {r.at_deg:.1f}°" if r.at_deg is not None else ""
    value = "—" if r.value is None else f"{r.value:.4g}"
    limit = "—" if r.limit is None else f"{r.limit:.4g}"
    return f"{name} = {value}{unit}{at} (limit {limit}{unit})"


def sizing_row(sz: Sizing) -> dict[str, Any]:
    """A sizing outcome as table columns: ``min_base_radius``, the bracket, the binding checks,
    and the design checks at the radius found."""
    row: dict[str, Any] = {
        "status": sz.status,
        "error": sz.reason,
        "min_base_radius": sz.value,
        "failing_radius": sz.below,
        "tolerance": sz.tol,
        "binding_checks": ";".join(sz.binding) if sz.value is not None else "",
        "check_runs": sz.evaluations,
    }
    if sz.checks is not None:
        d = sz.checks.to_dict()
        row["pressure_angle_deg"] = d["results"]["pressure_angle"]["value"]
        row.update(checks_row(d))
    return row

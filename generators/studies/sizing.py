"""The smallest base radius that meets the design checks (a sizing chart's value at one point).

:func:`smallest_base_radius` bisects on R_b = ``cam.base_radius`` with the dense design checks
(:func:`generators.checks.design.run_checks`: 1001 samples per rise/return, extrema refined):

1. ``lo`` = the largest radius the spec's rules refuse whatever the motion (R_b ≤ |offset|, or
   R_b − roller radius ≤ bore radius): it fails;
2. ``hi`` = the spec's own R_b, doubled until it passes (at most ``max_doublings`` times; if none
   passes, or the spec's rules refuse a larger radius — an oscillating arm's pivot_distance +
   arm_length —, the point has no radius and the row says which check still fails, and where);
3. halve [lo, hi] keeping ``lo`` failing and ``hi`` passing until hi − lo = ``tol``.

Every radius tried is a multiple of ``tol`` (:class:`TolGrid`), written with the decimals of
``tol``.  The answer is ``hi``: it passes, and the radius ``tol`` smaller fails (or is refused), so
the true boundary R* lies in (hi − tol, hi] — and ``hi`` is printed, tabulated and charted with
exactly the digits that statement supports (41.78 for 0.01 mm).  Default tolerance: 0.01 mm, 0.0005 in.  That is the
smallest radius only if passing is monotonic in R_b — a larger cam never fails a check a smaller
one passes.  That holds for the pressure angle (|φ| falls as R_b grows), the curvature, undercut and
cusp checks (the pitch curve's radius of curvature grows with R_b) and the Hertz stress; the
separation, oscillation and face-width checks do not depend on R_b for a translating follower
(they pass everywhere or nowhere).  ``checks`` restricts the sizing to some checks (e.g. only
``pressure_angle`` and ``curvature``, the classic nomogram); the others are then ignored.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

from ..checks.design import DesignChecks, run_checks
from ..errors import SpecError
from ..motion.program import MotionProgram
from ..spec.model import CamSpec

#: every check :func:`run_checks` may report (which ones a spec gets depends on its follower)
KNOWN_CHECKS = ("pressure_angle", "separation", "oscillation", "contact_stress", "curvature", "convexity",
                "undercut", "cusp", "face_width")
#: default bisection tolerance on R_b, per spec unit
DEFAULT_TOL = {"mm": 0.01, "in": 0.0005}
SIZED_FIELD = "cam.base_radius"


@dataclass(frozen=True)
class SizingSettings:
    """What :func:`smallest_base_radius` sizes against: ``checks`` (None: every check), the
    absolute tolerance on R_b in the spec's unit (None: :data:`DEFAULT_TOL`), and how often the
    spec's radius may be doubled looking for one that passes."""

    checks: tuple[str, ...] | None = None
    tol: float | None = None
    max_doublings: int = 12

    def tolerance(self, units: str) -> float:
        return float(self.tol) if self.tol is not None else DEFAULT_TOL[units]


@dataclass(frozen=True)
class Sizing:
    """The outcome at one point."""

    radius: float | None            # the smallest R_b found that passes (None: no radius)
    below: float                    # a radius that fails or is refused, radius − below ≤ tol
    tol: float
    status: str                     # "ok" or "no radius"
    reason: str                     # "no radius": why; "ok": ""
    binding: tuple[str, ...]        # the checks failing at ``below`` ("spec rule: …" where refused)
    evaluations: int                # design-check runs
    checks: DesignChecks | None     # the checks at ``radius``


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


@dataclass(frozen=True)
class TolGrid:
    """The radii a bisection to ``tol`` tries: k·tol, rounded to the decimals ``tol`` is written with
    (0.01 → 2, 0.0005 → 4, 0.25 → 2), so that a radius prints, and reads back from CSV, as it is."""

    tol: float

    @property
    def decimals(self) -> int:
        """The decimals of ``tol`` (at most 12)."""
        return decimals_of(self.tol)

    def value(self, k: int) -> float:
        return round(k * self.tol, self.decimals)

    def up(self, x: float) -> float:
        """The smallest grid radius ≥ x."""
        return self.value(math.ceil(x / self.tol - 1e-9))

    def down(self, x: float) -> float:
        """The largest grid radius ≤ x."""
        return self.value(math.floor(x / self.tol + 1e-9))

    def middle(self, lo: float, hi: float) -> float | None:
        """A grid radius halfway between the grid radii ``lo`` < ``hi`` (None when they are neighbours)."""
        a, b = round(lo / self.tol), round(hi / self.tol)
        return None if b - a <= 1 else self.value((a + b) // 2)


def decimals_of(tol: float) -> int:
    """The decimals ``tol`` is written with: the fewest d ≤ 12 with round(tol, d) == tol (0.01 → 2)."""
    for d in range(13):
        if abs(round(tol, d) - tol) <= 1e-12 * max(abs(tol), 1.0):
            return d
    return 12


def geometric_lower_bound(spec: CamSpec) -> float:
    """The largest R_b the spec's rules refuse whatever the motion: |offset| (R_b > |e|) or the
    roller radius plus the bore radius (the bore inside the base circle of the cam surface)."""
    return max(abs(spec.follower.offset), spec.roller_radius + 0.5 * spec.cam.bore_diameter, 0.0)


def smallest_base_radius(spec: CamSpec, settings: SizingSettings | None = None) -> Sizing:
    """The smallest ``cam.base_radius`` of ``spec`` (everything else as it is) that passes the
    design checks of ``settings`` (see the module's docstring for the bisection)."""
    settings = settings or SizingSettings()
    names = settings.checks
    tol = settings.tolerance(spec.units)
    if not tol > 0:
        raise SpecError("--tol", f"must be > 0, got {tol:g}")
    program = MotionProgram.from_spec(spec)        # the motion does not depend on R_b
    count = [0]

    def test(radius: float) -> tuple[bool, tuple[str, ...], DesignChecks | None]:
        try:
            s = spec.replace(**{SIZED_FIELD: float(radius)})
        except SpecError as exc:
            return False, (f"spec rule: {exc}",), None
        count[0] += 1
        dc = run_checks(s, program=program)
        failed = tuple(r.name for r in dc.results if r.status == "fail" and (names is None or r.name in names))
        return not failed, failed, dc

    # every radius tried is a multiple of tol, written with tol's decimals: the answer is a round number
    # that was itself checked, and every output (table, CSV, chart) shows it as it is
    grid = TolGrid(tol)
    bound = geometric_lower_bound(spec)
    lo = grid.down(bound)
    lo_failed: tuple[str, ...] = (f"spec rule: R_b ≤ {bound:.6g} is refused (offset, roller and bore)",)
    hi = grid.up(max(spec.cam.base_radius, lo + tol))
    ok, failed, dc = test(hi)
    doublings = 0
    while not ok:
        if failed and failed[0].startswith("spec rule") and hi > spec.cam.base_radius:
            return Sizing(None, hi, tol, "no radius", f"at R_b = {hi:.6g}: {failed[0][len('spec rule: '):]}",
                          failed, count[0], None)
        if doublings >= settings.max_doublings:
            where = "; ".join(_failure_text(dc, n) for n in failed) if dc is not None else failed[0]
            return Sizing(None, hi, tol, "no radius", f"no R_b up to {hi:.6g} passes: {where}", failed,
                          count[0], None)
        if failed and not failed[0].startswith("spec rule"):
            lo, lo_failed = hi, failed
        hi = grid.up(2.0 * hi)
        doublings += 1
        ok, failed, dc = test(hi)
    best = dc
    n_steps = max(0, math.ceil(math.log2(max(hi - lo, tol) / tol)))
    for _ in range(n_steps):
        mid = grid.middle(lo, hi)
        if mid is None:               # lo and hi are neighbours on the grid: hi − lo = tol
            break
        ok, failed, dc = test(mid)
        if ok:
            hi, best = mid, dc
        else:
            lo, lo_failed = mid, failed
    return Sizing(hi, lo, tol, "ok", "", lo_failed, count[0], best)


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
    from .table import checks_row

    row: dict[str, Any] = {
        "status": sz.status,
        "error": sz.reason,
        "min_base_radius": sz.radius,
        "failing_radius": sz.below,
        "tolerance": sz.tol,
        "binding_checks": ";".join(sz.binding) if sz.radius is not None else "",
        "check_runs": sz.evaluations,
    }
    if sz.checks is not None:
        d = sz.checks.to_dict()
        row["pressure_angle_deg"] = d["results"]["pressure_angle"]["value"]
        row.update(checks_row(d))
    return row

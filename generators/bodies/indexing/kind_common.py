"""What the indexer bodies' kinds share (:mod:`.parallel_kind`, :mod:`.spatial_kind`): a check's
entry of report.json, a geometry refusal in the spec's words, the turret-angle error modulo a
station, the drive's summary as report.json holds it, and the body members that do not depend on
the indexer's shape (:class:`IndexerBodyCommon`)."""
from __future__ import annotations

from typing import Any

import numpy as np

from ...checks.status import limited_status
from ...errors import SpecError
from . import from_spec
from .sizing import DriveSizing
from .turret_train import turret_follower


def result(description: str, kind: str, value: float, at: float | None, limit: float | None, unit: str,
            no_limit: str = "", note: str = "") -> dict[str, Any]:
    """A check's entry of report.json's ``checks.results`` (``kind`` "max" or "min" against ``limit``;
    without a limit reported, not passed: ``no_limit`` says why)."""
    status = limited_status(None if limit is None else (value <= limit if kind == "max" else value >= limit))
    return {"description": description, "kind": kind, "value": value, "at_deg": at, "limit": limit, "unit": unit,
            "status": status, "passed": status != "fail", "note": no_limit if limit is None else note}


def in_spec_words(spec: Any, exc: SpecError) -> SpecError:
    """A geometry refusal in the spec's words (:func:`.from_spec.spec_field`): β is ``motion[i].angle``
    there, the roller's radius ``follower.roller_radius``."""
    field = from_spec.spec_field(spec, exc.field)
    rule = exc.rule
    for name in from_spec.GEOMETRY_NAMES:
        rule = rule.replace(name, from_spec.spec_field(spec, name))
    return SpecError(field, rule)


def turn_error(diff: np.ndarray, step: float) -> float:
    """Largest |difference| of turret angles modulo the station angle ``step`` [rad] (the recovered
    angle is placed in one turn's [0, T]; the law's counts turns)."""
    return float(np.max(np.abs(np.mod(diff + step / 2, step) - step / 2)))


def drive_summary(spec: Any, drive: DriveSizing) -> dict[str, Any]:
    """The drive's summary; the roller's rating life only where ``indexer.roller_rating`` is given."""
    out = drive.summary()
    if spec.indexer.roller_rating is None:
        for key in ("l10_million_rev", "l10_hours", "l10_million_rev_note", "l10_hours_note"):
            out.pop(key, None)
        out["l10_note"] = "no indexer.roller_rating given: the roller's rating life is not computed"
    return out


class IndexerBodyCommon:
    """The members every indexer body (parallel, barrel, globoidal) has alike: a turret driven by
    rollers, the turret's angle the lift (the turret train the dynamics' follower), no profile
    inset, no further followers, no searched remedies.  Each body still declares its capabilities
    in its own class (tests/test_kinds.py)."""

    @staticmethod
    def profile_inset(spec: Any) -> float:
        return 0.0

    @staticmethod
    def further_followers(spec: Any) -> tuple:
        return ()

    @staticmethod
    def dynamics_follower(spec: Any) -> Any:
        """The turret: the output's inertia on the turret shaft's torsional stiffness (docs/indexing.md)."""
        return turret_follower(spec)

    @staticmethod
    def refuse_foreign(spec: Any) -> None:
        from_spec.refuse_foreign(spec)

    @staticmethod
    def lift_unit(spec: Any) -> str:
        """The turret's angle."""
        return "angle"

    @staticmethod
    def motion_advance(spec: Any) -> float:
        return from_spec.motion_advance(spec)

    @staticmethod
    def remedy_plans(spec: Any, check: str) -> list:
        return []

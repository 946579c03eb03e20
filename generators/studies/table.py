"""A study's result table (plain rows; the files are written by :mod:`cam_workbench.exporters.study_table`)
and the key numbers of one cam as a row: the same columns for a batch, a sweep and a sizing chart.

Row columns (lengths in the spec's ``units``, angles in degrees):

==========================  ================================================================
column                      what
==========================  ================================================================
status                      ``ok``; ``bad input`` (the spec breaks a rule), ``cannot be made``
                            (geometry), ``no radius`` (sizing: none passes), ``error``
                            (internal), ``cancelled``
error                       why, when the status is not ``ok`` (the one-line message)
units, follower             the spec's length unit; the follower kind
base_radius                 ``cam.base_radius`` (sizing: the smallest that passes)
max_lift                    largest follower lift (mm/in, or degrees of an oscillating arm)
pressure_angle_deg, …_at    largest |pressure angle| and the cam angle where it occurs
min_pitch_radius            smallest convex radius of curvature of the pitch (design) curve
min_profile_radius          … of the profile (pitch radius − roller radius)
max_profile_radius          largest distance of the profile from the axis
area, volume                cross-section (profile minus bore) and solid volume
checks_passed               every design check passes
failed_checks               the failed checks, ``;``-separated
check_<name>                each check's extreme value, with ``check_<name>_limit`` and
                            ``check_<name>_status`` (pass, fail, skipped)
==========================  ================================================================
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping, Sequence

from ..kinds import body_named


@dataclass
class StudyTable:
    """Rows (dicts) with their column order, and what produced them (``meta``: the kind of
    study, the grid, the settings — written beside the table)."""

    columns: list[str]
    rows: list[dict[str, Any]]
    meta: dict[str, Any] = field(default_factory=dict)

    @classmethod
    def from_rows(cls, rows: Sequence[Mapping[str, Any]], first: Sequence[str] = (),
                  meta: Mapping[str, Any] | None = None) -> "StudyTable":
        """A table whose columns are ``first``, then every other key in the order rows bring them."""
        return cls(columns_of(rows, first), [dict(r) for r in rows], dict(meta or {}))

    def column(self, name: str) -> list[Any]:
        """One column's values (None where a row has none)."""
        return [r.get(name) for r in self.rows]

    def __len__(self) -> int:
        return len(self.rows)

    @property
    def ok(self) -> bool:
        """Every row has status ok (a sizing row's ``no radius`` is a result, not an error)."""
        return all(r.get("status") in ("ok", "no radius") for r in self.rows)


def columns_of(rows: Iterable[Mapping[str, Any]], first: Sequence[str] = ()) -> list[str]:
    cols = list(dict.fromkeys(first))
    seen = set(cols)
    for r in rows:
        for k in r:
            if k not in seen:
                seen.add(k)
                cols.append(k)
    return cols


def checks_row(checks: Mapping[str, Any]) -> dict[str, Any]:
    """The ``checks`` section of report.json (``DesignChecks.to_dict()``) as row columns."""
    row: dict[str, Any] = {"checks_passed": bool(checks["passed"]), "failed_checks": ";".join(checks["failed"])}
    for name, r in checks["results"].items():
        row[f"check_{name}"] = r.get("value")
        row[f"check_{name}_limit"] = r.get("limit")
        row[f"check_{name}_status"] = r.get("status")
    return row


def summary_row(summary: Mapping[str, Any], base_radius: float) -> dict[str, Any]:
    """The key numbers of one designed cam from its summary (``CamDesign.summary()`` or
    report.json)."""
    pa, mo = summary["pressure_angle"], summary["motion"]
    body = summary.get("body") or {}
    own = body_named(body["kind"]).study_row(summary, base_radius) if body.get("kind") else None
    if own is not None:      # a body with numbers of its own (no plane profile)
        return own
    cv = summary["curvature"]
    row: dict[str, Any] = {
        "units": summary["units"],
        "follower": summary["follower"]["name"],
        "base_radius": float(base_radius),
        "max_lift": mo["max_lift"],
        "pressure_angle_deg": pa["max_deg"],
        "pressure_angle_at_deg": pa["at_deg"],
        "min_pitch_radius": cv["min_pitch_radius"],
        "min_profile_radius": cv["min_profile_radius"],
        "max_profile_radius": summary["profile"]["max_radius"],
        "area": summary["area"],
        "volume": summary["volume"],
    }
    row.update(checks_row(summary["checks"]))
    return row


def error_row(status: str, exc: BaseException | str) -> dict[str, Any]:
    """A row that says why there are no numbers (the message on one line)."""
    return {"status": status, "error": " ".join(str(exc).split())}

"""``cam-workbench check``: the design checks (thesis Ch. 3) as a table and, with ``-o``, as the
``checks`` section of report.json; exit status 3 when a check fails, so scripts can gate on it."""
from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from cam_workbench.exporters.atomic import OutputSet
from cam_workbench.exporters.report_json import report_json_text
from cam_workbench.generators.checks.areas import area_label, area_summary
from cam_workbench.generators.checks.design import format_value, limit_sign
from cam_workbench.generators.checks.status import sampling_words
from cam_workbench.generators.kinds import body_of
from cam_workbench.generators.errors import GeometryError
from cam_workbench.generators.studies.remedies import add_remedies, remedy_lines, with_remedy
from cam_workbench.generators.motion import MotionProgram
from cam_workbench.generators.spec import CamSpec, spec_digest

from . import EXIT_CHECK_FAILED
from ..pipeline import run_pipeline
from .common import admit_output, design_for, output_claim, spec_from_args


def run(args: argparse.Namespace) -> int:
    spec = spec_from_args(args)
    if args.sampling:
        spec = spec.replace(**{"checks.sampling": args.sampling})
    if args.output is not None:
        admit_output(args, spec, "check", ("report.json",))
    try:
        # the numbers `build` reports for the same spec (one pipeline), without solid or files
        summary = run_pipeline(spec, solid=False, machining=False, drawing=False,
                               design=design_for(spec, remedy=False)).summary
        error = None
    except GeometryError as exc:
        body = body_of(spec)
        checks_dict = body.own_checks(spec)
        # a plane cam's areas; a body with surfaces of its own has no plane profile to measure
        areas = area_summary(spec) if body.plane else None
        if checks_dict["passed"]:
            # a cam that cannot be made though its checks pass: exit 2, nothing written
            raise with_remedy(spec, exc) from None
        add_remedies(checks_dict, spec)
        error = exc
        summary = {"units": spec.units, "spec_digest": spec_digest(spec),
                   **({"areas": areas} if areas is not None else {}),
                   "motion": MotionProgram.from_spec(spec).report(),
                   "checks": checks_dict, "spec": spec.to_dict(),
                   "buildable": {"ok": False, "message": str(exc), "at_deg": exc.angle_deg}}
    out = None if args.output is None else Path(args.output)
    report = summary if out is None else merged_report(out / "report.json", spec, summary)
    if out is not None:
        # a set of the same spec keeps its other files (its numbers are these): cam_workbench.exporters.output_rule
        with OutputSet(out, output_claim(args, spec, "check")) as o:
            o.add_text("report.json", report_json_text(report))
    checks = report["checks"]
    args.status = 0 if checks["passed"] else EXIT_CHECK_FAILED      # kept if stdout's reader goes away
    motion = report.get("motion") or {}
    print_table(checks, spec, out, report.get("areas"), motion.get("junctions"),
                (report.get("follower") or {}).get("curve", "pitch curve"), motion.get("lift_unit"))
    if error is not None:
        print(f"the cam cannot be made: {error}")
    return 0 if checks["passed"] else EXIT_CHECK_FAILED


def merged_report(path: Path, spec: CamSpec, summary: dict[str, Any]) -> dict[str, Any]:
    """report.json with the fresh ``checks`` section: merged into the existing report when that
    report was written for the same spec (same ``spec_digest``: its numbers are the ones
    ``summary`` holds), else ``summary`` itself."""
    digest = spec_digest(spec)
    if path.exists():
        try:
            old = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            old = None
        if isinstance(old, dict) and old.get("spec_digest") == digest:
            old["checks"] = summary["checks"]
            if isinstance(summary.get("motion"), dict):     # the same cam: refresh what older reports lack
                old.setdefault("motion", {}).update(
                    {k: summary["motion"][k] for k in ("segments", "junctions") if k in summary["motion"]})
            return old
    return summary


def print_table(checks: dict[str, Any], spec: CamSpec, out: Path | None, areas: dict[str, float] | None,
                junctions: list[dict[str, Any]] | None = None, follower_curve: str = "pitch curve",
                lift_unit: str | None = None) -> None:
    """report.json's ``checks`` section as a rich table, then the extremes (the thesis' "Maximum
    Values") and the segment junctions (``motion.junctions``, in report.json's ``motion.lift_unit``;
    None: the follower's) — the values printed are report.json's own."""
    console = Console()
    mode = sampling_words(checks)
    table = Table(title=f"design checks ({mode})")
    for col in ("check", "value", "at", "limit", "status"):
        # the check's name is never cut: a second cam's "pressure_angle_cam2" must not read as the first's
        table.add_column(col, justify="left" if col in ("check", "status") else "right",
                         overflow="fold", min_width=7 if col == "status" else None)
    style = {"pass": "green", "fail": "bold red", "skipped": "yellow"}
    for name, r in checks["results"].items():
        limit = "—" if r["limit"] is None else f"{limit_sign(name, r['kind'])} {format_value(r['limit'], r['unit'])}"
        at = "—" if r["at_deg"] is None else f"{r['at_deg']:.3f}°"
        status = f"[{style[r['status']]}]{r['status']}[/]" + (
            f" ({r['note']})" if r["note"] and r["status"] != "pass" else "")
        table.add_row(f"{name} ({r['kind']})", format_value(r["value"], r["unit"]), at, limit, status)
    console.print(table)
    for line in remedy_lines(checks):          # report.json's checks.results[name].remedy
        console.print(f"[bold]remedy[/] {escape(line)}")
    ext = Table(title="extremes (largest magnitude, signed)")
    for col in ("quantity", "value", "at"):
        ext.add_column(col, justify="left" if col == "quantity" else "right")
    for name, e in checks["extremes"].items():
        ext.add_row(name.replace("_", " "), format_value(e["value"], e["unit"]), f"{e['at_deg']:.3f}°")
    if checks["extremes"]:
        console.print(ext)
    if junctions:
        if lift_unit is None:
            lift_unit = spec.units if body_of(spec).lift_unit(spec) == "length" else "deg"
        console.print(junction_table(junctions, lift_unit))
    if areas is not None:       # a cylindrical cam has no plane cross-section
        console.print(escape(area_line(areas, spec.units, follower_curve)))
    verdict = ("[green]all checks pass[/]" if checks["passed"]
               else f"[bold red]failed: {', '.join(checks['failed'])}[/]")
    console.print(verdict + ("" if out is None else f" — checks written to {out}/report.json"))


_JUMP_NAMES = ("s", "velocity", "acceleration", "jerk")


def area_line(areas: dict[str, Any], units: str, curve: str = "pitch curve") -> str:
    """report.json's ``areas`` named as report.json names them: the thesis' Eq. 4.21 area (or,
    for a follower without one, the area inside its design curve ``curve``) and the cam's
    cross-section (the built one, report.json ``area``, when the solid's numbers are there)."""
    key = "thesis_eq_4_21" if areas.get("thesis_eq_4_21") is not None else "pitch_curve"
    built = "built_cross_section" if areas.get("built_cross_section") is not None else "cross_section"
    return (f"{area_label(key, curve)}: {areas[key]:.6g} {units}² (report.json areas.{key}); "
            f"{area_label('cross_section')}: {areas[built]:.6g} {units}² (areas.{built})")


def junction_table(junctions: list[dict[str, Any]], lift_unit: str) -> Any:
    """report.json's ``motion.junctions`` as a rich table: where, which laws, the order of
    continuity reached (C0 … C3) against the order promised, and the first jump."""
    lab = {"velocity": f" {lift_unit}/rad", "acceleration": f" {lift_unit}/rad²", "jerk": f" {lift_unit}/rad³",
           "s": f" {lift_unit}"}
    t = Table(title="segment junctions (continuity of s, s′, s″, s‴)")
    for col in ("at", "from → to", "reached", "promised", "first jump"):
        t.add_column(col, justify="right" if col in ("at",) else "left")
    for j in junctions:
        order = int(j["order"])
        first = _JUMP_NAMES[order + 1] if order < 3 else None
        jump = "—" if first is None else f"{first} {j['jumps'][first]:+.4g}{lab[first]}"
        mark = "[green]" if j["ok"] else "[bold red]"
        t.add_row(f"{j['at_deg']:.3f}°", f"motion[{j['from']}] {j['from_law']} → motion[{j['to']}] {j['to_law']}",
                  f"{mark}C{max(order, 0) if order >= 0 else '-1'}[/]", f"C{j['promised']}", jump)
    return t

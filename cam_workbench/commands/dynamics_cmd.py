"""``cam-workbench dynamics``: the follower train at speed — dynamic contact force, separation,
the jump speed (a sweep with a progress bar and a bisection), residual vibration and the camshaft
torque — printed as tables and, with ``-o``, written as report.json's ``dynamics`` section (merged
into a report.json of the same cam, as ``check`` merges its checks), ``dynamics.csv`` (the θ-series)
and the two figures.  Exit status 3 when the follower leaves the cam at the analysis speed."""
from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import numpy as np
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from cam_workbench.exporters import plots_dynamics
from cam_workbench.exporters.chart_png import png_bytes
from cam_workbench.exporters.atomic import OutputSet
from cam_workbench.exporters.report_cells import format_number as fmt
from cam_workbench.exporters.report_json import report_json_text
from cam_workbench.generators.kinds import body_of
from cam_workbench.generators.dynamics import analyse_dynamics, validate_dynamics
from cam_workbench.generators.motion.program import MotionProgram
from cam_workbench.generators.spec import CamSpec, spec_digest
from cam_workbench.generators.spec.params import unit_name

from .common import admit_output, output_claim, require_png, spec_from_args, sweep_progress
from .parsers import DYNAMICS_CSV as CSV_NAME, DYNAMICS_PLOTS as PLOTS

EXIT_CONTACT_LOST = 3


def run(args: argparse.Namespace) -> int:
    spec = spec_from_args(args)
    changes: dict[str, Any] = {}
    if args.speed is not None:
        changes["dynamics.speed_rpm"] = args.speed
    if args.no_sweep:
        changes["dynamics.sweep_points"] = 0
    if changes:
        spec = spec.replace(**changes)
    validate_dynamics(spec, required=True)          # bad input: exit 2 naming the field, nothing written
    if args.output is not None:
        require_png()
        admit_output(args, spec, "dynamics")
    program = MotionProgram.from_spec(spec)
    bar, cb = sweep_progress()
    with bar:
        result = analyse_dynamics(spec, program, progress=cb)
    section = result.summary()
    out = None if args.output is None else Path(args.output)
    if out is None:
        report = json.loads(report_json_text({"dynamics": section}))     # the numbers report.json would hold
    else:
        report = merged_report(out / "report.json", spec, section)
        figures = _figures(result, section)
        with OutputSet(out, output_claim(args, spec, "dynamics")) as o:
            o.add_text("report.json", report_json_text(report))
            o.add_text(CSV_NAME, series_csv(result))
            for name, data in figures.items():
                o.add_bytes(name, data)
    kept = report["dynamics"]["contact"]["kept"]
    args.status = 0 if kept else EXIT_CONTACT_LOST
    print_tables(report["dynamics"], out)
    return 0 if kept else EXIT_CONTACT_LOST


def merged_report(path: Path, spec: CamSpec, section: dict[str, Any]) -> dict[str, Any]:
    """report.json with the fresh ``dynamics`` section: merged into the existing report when it
    was written for the same cam (same ``spec_digest``), else the cam's follower and spec with it."""
    digest = spec_digest(spec)
    if path.exists():
        try:
            old = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            old = None
        if isinstance(old, dict) and old.get("spec_digest") == digest:
            old["dynamics"] = section
            return json.loads(report_json_text(old))
    return json.loads(report_json_text({"units": spec.units, "spec_digest": digest,
                                        "follower": train_follower(spec).describe(), "dynamics": section,
                                        "spec": spec.to_dict()}))


def train_follower(spec: CamSpec) -> Any:
    """The follower the dynamics drive: the body's own (a cylindrical cam's roller along its axis)
    or the spec's."""
    return body_of(spec).dynamics_follower(spec)


def series_csv(result: Any) -> str:
    """The θ-series of one steady-state revolution as CSV (spec units; angles in degrees)."""
    s = result.series()
    lu = "deg" if result.lift_unit == "angle" else result.units

    fu, tu = unit_name("force", result.units), unit_name("torque", result.units)
    head = [("theta [deg]", "theta_deg"), (f"s [{lu}]", "lift"), (f"q [{lu}]", "position"),
            (f"q - s [{lu}]", "error"), (f"vibration [{lu}]", "vibration"),
            (f"rigid force [{fu}]", "rigid_force"), (f"force [{fu}]", "force"),
            (f"rigid torque [{tu}]", "rigid_torque"), (f"torque [{tu}]", "torque"), ("on cam", "on_cam")]
    cols = np.column_stack([s[k] for _h, k in head])
    lines = [",".join(h for h, _k in head)]
    lines += [",".join(repr(float(v)) for v in row) for row in cols]
    return "\n".join(lines) + "\n"


def _figures(result: Any, section: dict[str, Any]) -> dict[str, bytes]:
    out = {PLOTS[0]: png_bytes(plots_dynamics.dynamics_figure(result, section), "dynamics")}
    if "jump_speed" in section:
        out[PLOTS[1]] = png_bytes(plots_dynamics.jump_speed_figure(result, section), "jump_speed")
    return out


def print_tables(d: dict[str, Any], out: Path | None) -> None:
    """report.json's ``dynamics`` section as tables — the values printed are report.json's own."""
    con = Console(soft_wrap=True)
    c, m, e, tq = d["contact"], d["model"], d["error"], d["torque"]
    lu, fu, tu = e["unit"], c["unit"], tq["unit"]
    turret = d.get("turret")
    what = "shaft torque" if turret else "contact force"
    table = Table(title=f"{'output train' if turret else 'follower'} dynamics at {fmt(d['speed_rpm'])} rpm")
    for col in ("quantity", "value", "unit", "at"):
        table.add_column(col, justify="left" if col == "quantity" else "right")
    rows = [
        ("natural frequency of the train", m["natural_frequency_hz"], "Hz", None),
        ("natural frequency / cam frequency", m["frequency_ratio"], "", None),
        (f"smallest {what} (dynamic)", c["min_force"], fu, c["min_force_at_deg"]),
        (f"largest {what} (dynamic)", c["max_force"], fu, c["max_force_at_deg"]),
        (f"smallest {what} (rigid)", c["rigid_min_force"], fu, c["rigid_min_force_at_deg"]),
        (f"largest {what} (rigid)", c["rigid_max_force"], fu, c["rigid_max_force_at_deg"]),
        ("largest angle error |φ − ψ|" if turret else "largest displacement error |q − s|", e["max"], lu, e["at_deg"]),
        ("largest vibration", e["max_vibration"], lu, e["vibration_at_deg"]),
        ("camshaft torque max (rigid)", tq["rigid"]["max"], tu, tq["rigid"]["max_at_deg"]),
        ("camshaft torque max (dynamic)", tq["dynamic"]["max"], tu, tq["dynamic"]["max_at_deg"]),
        ("camshaft torque RMS (dynamic)", tq["dynamic"]["rms"], tu, None),
        ("work per revolution (dynamic)", tq["dynamic"]["work_per_revolution"], tu, None),
    ]
    if not c["kept"]:
        rows += [("off the cam", c["off_cam_deg"], "deg", None), ("largest gap", c["max_gap"], lu, c["max_gap_at_deg"]),
                 ("largest landing speed", c["max_landing_speed"], c["landing_speed_unit"], None)]
    for label, v, unit, at in rows:
        table.add_row(label, fmt(v), unit, "—" if at is None else f"{fmt(at)}°")
    con.print(table)
    if turret:
        _print_turret(con, turret)
    res = d["residual_vibration"]
    if res:
        rt = Table(title="residual vibration")
        for col in ("after", "into", "largest vibration", "at"):
            rt.add_column(col, justify="left" if col in ("after", "into") else "right")
        for r in res:
            rt.add_row(f"motion[{r['after']}] {r['kind']}", f"motion[{r['next']}] {r['next_kind']}",
                       f"{fmt(r['amplitude'])} {lu}", f"{fmt(r['at_deg'])}°")
        con.print(rt)
    jp = d.get("jump_speed")
    if jp is not None:
        rigid = "—" if jp["rigid_rpm"] is None else fmt(jp["rigid_rpm"])
        if jp["rpm"] is not None:
            con.print(escape(f"jump speed: {fmt(jp['rpm'])} rpm ({fmt(jp['ratio_to_speed'])} × the analysis speed); "
                             f"rigid follower: {rigid} rpm; sweep {fmt(jp['sweep_from_rpm'])}–{fmt(jp['sweep_to_rpm'])} "
                             f"rpm, {jp['sweep_points']} speeds"))
        else:
            con.print(escape(f"jump speed: not found — {jp['note']}; rigid follower: {rigid} rpm"))
    st = d["steady_state"]
    con.print(escape(f"steady state: {st['method']}" + (f", {st['revolutions']} revolutions" if st["revolutions"] else "")
                     + ("" if st["periodic"] else " — NOT periodic yet" + (f" ({st['note']})" if st.get("note") else ""))))
    drive = c.get("drive")
    if drive is not None:
        at = ", ".join(f"{fmt(a)}°" for a in drive["changes_at_deg"]) or "nowhere"
        con.print(escape(f"form closure: the load changes wall at {at} (dynamic force; positive share "
                         f"{fmt(drive['positive_share'])}, negative share {fmt(drive['negative_share'])})"))
    verdict = ("[green]the rollers hold the turret both ways[/]" if turret else
               "[green]the follower stays on the cam[/]" if c["kept"] else
               f"[bold red]the follower LEAVES the cam ({escape(fmt(c['off_cam_deg']))}° of the revolution)[/]")
    con.print(verdict + ("" if out is None else f" — written to {escape(str(out))}/: report.json, {CSV_NAME}, "
                                               f"{', '.join(PLOTS[:1 + ('jump_speed' in d)])}"))


def _print_turret(con: Console, t: dict[str, Any]) -> None:
    """report.json's ``dynamics.turret`` (an indexer's output train) as a table."""
    table = Table(title="indexer output train (the output's inertia on the turret shaft)")
    for col in ("quantity", "value", "unit", "at"):
        table.add_column(col, justify="left" if col == "quantity" else "right")
    dfl, sq, rv = t["deflection"], t["shaft_torque"], t["residual_vibration"]
    rows = [
        ("index time t_i", t["index_time_s"], "s", None),
        ("natural frequency f_n", t["natural_frequency_hz"], "Hz", None),
        ("f_n·t_i", t["fn_ti"], "", None),
        ("peak torsional deflection |ψ − φ|", dfl["max_arcmin"], "arcmin", dfl["at_deg"]),
        ("peak shaft torque (dynamic)", sq["max"], sq["unit"], sq["at_deg"]),
        ("peak shaft torque (rigid J·ψ̈)", sq["rigid_max"], sq["unit"], sq["rigid_max_at_deg"]),
        ("residual vibration entering the dwell", rv["amplitude_arcmin"], "arcmin", None),
    ]
    rows += [(f"dwell {fmt(w['from_deg'])}°–{fmt(w['to_deg'])}°: amplitude at its end", w["amplitude_at_end_arcmin"],
              "arcmin", None) for w in rv["dwells"]]
    for label, v, unit, at in rows:
        table.add_row(escape(label), fmt(v), unit, "—" if at is None else f"{fmt(at)}°")
    con.print(table)

"""``cam-workbench machine``: many cams on one camshaft — every cam built as ``build`` builds it,
and the machine's timing diagram, camshaft torque, flywheel and report (:mod:`cam_workbench.machine`).
Every number printed is machine.json's (:func:`summary_lines`)."""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any, Mapping

from cam_workbench.generators.errors import SpecError

from . import EXIT_CHECK_FAILED
from ..machine import Machine, check_animation, progress_total
from .common import count_progress, require_ocp


def run(args: argparse.Namespace) -> int:
    if args.machine and args.example:
        raise SpecError("--example", "give a machine FILE or --example, not both")
    if not args.machine and not args.example:
        raise SpecError("FILE", "give a machine file, or --example three_cams")
    chosen = args.animation             # None: not given (no cam drawn, or no matplotlib: a note, not a refusal)
    animation = chosen or "gif"
    check_animation(animation, chosen is not None)   # mp4 without ffmpeg: refused before any work
    machine = Machine(args.machine) if args.machine else Machine.example(args.example)
    require_ocp("machine")
    bar, cb = count_progress(progress_total(machine.spec, animation), "machine", "steps")

    def progress(done: int, total: int, what: str) -> None:
        cb(done, total)
        bar.update(bar.task_ids[0], description=what)

    with bar:
        report = machine.build(args.output, replace=args.replace, option="-o", progress=progress,
                               phase_sweep=args.phase_sweep, animation=animation,
                               require_animation=chosen is not None)
    for line in summary_lines(report, Path(args.output)):
        print(line)
    return 0 if report["checks"]["passed"] else EXIT_CHECK_FAILED


def summary_lines(r: Mapping[str, Any], out: Path) -> list[str]:
    """The printout: each number from machine.json's dict ``r`` (6 significant digits, as the
    report's cells show them)."""
    m, tq, fw = r["machine"], r["torque"], r["flywheel"]
    u = tq["unit"]
    f = r["files"]
    written = [f[k] for k in ("machine_json", "machine_html", "timing_svg", "timing_png", "torque_svg", "torque_png",
                              "animation") if k in f]
    lines = [f"machine {m['name']!r} written to {out}/: " + ", ".join([c["folder"] for c in r["cams"]] + written),
             f"  camshaft {_n(m['speed_rpm'])} rpm (ω {_n(m['omega_rad_s'])} rad/s), grid {_n(m['grid_step_deg'])}°",
             f"  torque [{u}]: max {_n(tq['max'])} at {_n(tq['max_at_deg'])}°, min {_n(tq['min'])} at "
             f"{_n(tq['min_at_deg'])}°, mean {_n(tq['mean'])}, RMS {_n(tq['rms'])}",
             f"  flywheel: energy fluctuation {_n(fw['energy_fluctuation_J'])} J (E max at "
             f"{_n(fw['energy_max_at_deg'])}°, min at {_n(fw['energy_min_at_deg'])}°); inertia "
             f"{_n(fw['inertia_kg_m2'])} kg·m² for C_s {_n(fw['speed_fluctuation'])}"]
    for c in r["cams"]:
        t = c["torque"]
        ck = c.get("checks") or {}
        verdict = "all pass" if ck.get("passed") else "FAILED " + ", ".join(ck.get("failed") or [])
        events = "; ".join(f"{e['label']} {_n(e['start_deg'])}–{_n(e['end_deg'])}°" for e in c["events"])
        lines.append(f"  {c['folder']}/ phase {_n(c['phase_deg'])}°: {events}; torque max {_n(t['max'])}, min "
                     f"{_n(t['min'])}, RMS {_n(t['rms'])} {u}; checks {verdict}")
        lk = c.get("linkage")
        if lk:
            tm = lk["tool_motion"]
            lines.append(f"    tool through the {lk['kind']} (motion given at the {lk['motion_at']}): "
                         f"{_n(tm['min_displacement'])} to {_n(tm['max_displacement'])} {lk['tool_unit']}, |v| max "
                         f"{_n(tm['max_velocity'])} {lk['tool_unit']}/s, |a| max {_n(tm['max_acceleration'])} "
                         f"{lk['tool_unit']}/s²")
    fig = r["figures"]
    lines.append(f"  figures: {', '.join(x.upper() for x in fig['formats'])}" + (f" ({fig['note']})" if fig["note"] else ""))
    an = r.get("animation")
    if an:
        lines.append(f"  animation {an['file']}: {an['frames']} frames, {_n(an['step_deg'])}° apart, {an['fps']} per s"
                     + (f"; {an['note']}" if an["note"] else "") if an.get("file") else f"  animation: {an['note']}")
    cl = r.get("clearance")
    if cl:
        for p in cl["pairs"]:
            status = "pass" if p["status"] == "pass" else "FAIL"
            line = (f"  clearance {p['name']}: {_n(p['distance'])} {cl['unit']} at {_n(p['at_deg'])}° (required "
                    f"{_n(p['required'])} {cl['unit']}, margin {_n(p['margin'])}): {status}")
            if p.get("remedy"):
                rm = p["remedy"]
                line += (f"; move {rm['moves']}'s tool {_n(rm['shift'])} {rm['unit']} along "
                         f"({_n(rm['direction'][0])}, {_n(rm['direction'][1])}) at {_n(rm['at_deg'])}°")
            lines.append(line)
    ps = r.get("phase_sweep")
    if ps:
        ranges = ", ".join(f"{_n(a)}–{_n(b)}°" for a, b in ps["intervals"]) or "none"
        lines.append(f"  phase sweep of {ps['cam']} (now {_n(ps['phase_deg'])}°, "
                     f"{'passes' if ps['current_phase_passes'] else 'FAILS'}): phases keeping every clearance: "
                     f"{ranges}")
        lines += shortest_cycle_lines(ps, r["machine"]["speed_rpm"])
    return lines


def shortest_cycle_lines(ps: Mapping[str, Any], rpm: float) -> list[str]:
    """The phase sweep's shortest cycle (machine.json ``phase_sweep.shortest_cycle``), printed."""
    sc = ps["shortest_cycle"]
    if sc["note"]:
        return [f"  shortest cycle: {sc['note']}"]
    f, mo = sc["follows"], sc["motion"]
    why = ("clearance " + ", ".join(sc["binding_pairs"])) if sc["limited_by"] == "clearance" else \
        f"order: it would start before {f['event']}"
    dwell = (f"the whole machine's longest dwell {_n(sc['machine_dwell_deg'])}° → {_n(sc['machine_dwell_at_phase_deg'])}°"
             + ("" if sc["assumption_holds"] else f", it grows by {_n(sc['dwell_gained_deg'])}° only: the assumption "
                                                  "does not hold"))
    return [f"  shortest cycle: {mo['event']} (now at {_n(mo['start_deg'])}°, following {f['event']} "
            f"{_n(f['start_deg'])}–{_n(f['end_deg'])}°) can start {_n(sc['saved_deg'])}° earlier, phase "
            f"{_n(sc['phase_deg'])}° (limited by {why}); overlap {_n(sc['current_overlap_deg'])}° → "
            f"{_n(sc['overlap_deg'])}°; smallest clearance there "
            + ", ".join(f"{c['name']} {_n(c['distance'])} {ps['unit']}" for c in sc["clearance_at_phase"]),
            f"    cycle {_n(sc['cycle_time_s'])} s → {_n(sc['shortest_cycle_time_s'])} s at {_n(rpm)} rpm "
            f"({_n(sc['cycles_per_min'])} cycles/min) if the saved {_n(sc['saved_deg'])}° go to a dwell of the "
            f"whole machine ({dwell})"]


def _n(v: float) -> str:
    """A machine.json number as printed: 6 significant digits."""
    return f"{v:.6g}"

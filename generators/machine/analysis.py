"""One machine analysed: every follower's timing, every cam's torque on the common machine-angle
grid, their sum, the flywheel — and :meth:`MachineResult.summary`, machine.json's numbers (every
number the machine command prints or the report shows comes from it).

The clearances (:func:`clearance_section`): for every ``[[clearance]]`` pair the smallest signed
distance between the two tools' outlines over the turn (:func:`.clearance.min_clearance`, sampled
on the machine grid and refined between the samples with the tools' pose functions), checked
against the pair's ``required`` (:func:`.clearance.clearance_check`).  :func:`phase_sweep_section`:
the phases of one cam that keep every clearance it takes part in (:func:`.clearance.phase_sweep`).

Each cam's design checks are not recomputed here: the caller hands each cam's report.json
``checks`` section to :meth:`MachineResult.summary` (the command builds every cam as ``build``
does and reads its report).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Mapping, Sequence

import numpy as np

from ..errors import SpecError
from ..motion.program import MotionProgram
from ..spec.params import unit_name
from .clearance import clearance_check, min_clearance, phase_sweep
from .spec import ClearancePair, MachineSpec
from .timing import FollowerTiming, follower_timing
from .tools import outline_of
from .torque import Flywheel, cam_angles, cam_torque, flywheel, machine_grid, torque_summary


@dataclass(frozen=True)
class MachineResult:
    """The machine's numbers on the grid ``theta`` [rad].

    Attributes:
        machine: the machine.
        theta: machine angles [rad] (one turn, equal steps, the end left out).
        timings: each follower's timing, in the machine's cam order.
        torques: each cam's camshaft torque at ``theta`` [torque unit], same order.
        total: the sum [torque unit].
        flywheel: the flywheel for ``total``.
        clearance: machine.json's ``clearance`` section (:func:`clearance_section`), None
            without ``[[clearance]]`` pairs.
        phase_sweep: machine.json's ``phase_sweep`` section (:func:`phase_sweep_section`), None
            unless asked for.
    """

    machine: MachineSpec
    theta: np.ndarray
    timings: tuple[FollowerTiming, ...]
    torques: tuple[np.ndarray, ...]
    total: np.ndarray
    flywheel: Flywheel
    clearance: dict[str, Any] | None = None
    phase_sweep: dict[str, Any] | None = None

    @property
    def theta_deg(self) -> np.ndarray:
        return np.degrees(self.theta)

    @property
    def torque_unit(self) -> str:
        return unit_name("torque", self.machine.units)

    def summary(self, checks: Mapping[str, Mapping[str, Any]] | None = None) -> dict[str, Any]:
        """machine.json (without ``files``): the camshaft, every cam (phase, events, torque, and
        ``checks[name]`` — its report.json ``checks`` section — as ``checks``), the total torque,
        the flywheel and the machine's verdict (``checks.failed``: "<cam>.<check>")."""
        m = self.machine.machine
        checks = checks or {}
        cams = []
        failed: list[str] = []
        for cam, timing, torque in zip(self.machine.cams, self.timings, self.torques):
            entry: dict[str, Any] = {
                "name": cam.name, "folder": cam.name, "phase_deg": cam.phase, "spec_source": cam.source,
                "lift_unit": timing.lift_unit,
                "events": [e.to_dict() for e in timing.events],
                "motion": {"max_displacement": float(np.max(timing.s)), "max_velocity": float(np.max(np.abs(timing.v))),
                           "max_acceleration": float(np.max(np.abs(timing.a)))},
                "torque": torque_summary(self.theta, torque),
                "tool": cam.tool.to_dict() if cam.tool is not None else None,
                "tool_path": _tool_path(timing),
            }
            if timing.linked:
                entry["linkage"] = _linkage_entry(timing)
            ck = checks.get(cam.name)
            if ck is not None:
                entry["checks"] = {"passed": bool(ck.get("passed")), "failed": list(ck.get("failed") or []),
                                   "results": {k: _check_row(v) for k, v in (ck.get("results") or {}).items()}}
                failed.extend(f"{cam.name}.{name}" for name in entry["checks"]["failed"])
            cams.append(entry)
        out: dict[str, Any] = {
            "machine": {"name": m.name, "speed_rpm": m.speed_rpm, "omega_rad_s": self.machine.omega,
                        "speed_fluctuation": m.speed_fluctuation, "grid_step_deg": m.grid_step,
                        "samples": int(self.theta.size), "cams": len(cams)},
            "units": self.machine.units,
            "cams": cams,
            "torque": {"unit": self.torque_unit, **torque_summary(self.theta, self.total)},
            "flywheel": self.flywheel.summary(),
            "checks": {"passed": not failed, "failed": failed},
        }
        if self.clearance is not None:
            out["clearance"] = self.clearance
            failed.extend(f"clearance.{name}" for name in self.clearance["failed"])
            out["checks"]["passed"] = not failed
        if self.phase_sweep is not None:
            out["phase_sweep"] = self.phase_sweep
        return out


def _tool_path(t: FollowerTiming) -> dict[str, Any]:
    """machine.json's ``cams[i].tool_path``: what moves the tool point and its extent in the
    machine plane [length]."""
    assert t.tool is not None and t.drive is not None
    x, y = t.tool[:, 0], t.tool[:, 1]
    return {"driven_by": "linkage" if t.drive.linked else "follower", "rotates": t.drive.angular,
            "x_min": float(np.min(x)), "x_max": float(np.max(x)), "y_min": float(np.min(y)),
            "y_max": float(np.max(y))}


def _linkage_entry(t: FollowerTiming) -> dict[str, Any]:
    """machine.json's ``cams[i].linkage``: the linkage's summary, where the motion is given, and the
    tool's motion on the grid (lift unit; velocity per s, acceleration per s²)."""
    assert t.drive is not None and t.tool_s is not None and t.tool_v is not None and t.tool_a is not None
    return {**t.drive.linkage.summary(), "motion_at": t.drive.motion_at, "tool_unit": t.lift_unit,
            "tool_motion": {"min_displacement": float(np.min(t.tool_s)), "max_displacement": float(np.max(t.tool_s)),
                            "max_velocity": float(np.max(np.abs(t.tool_v))),
                            "max_acceleration": float(np.max(np.abs(t.tool_a)))}}


def _check_row(result: Any) -> dict[str, Any]:
    """A check's row of the machine's one table: status, value, limit, unit, cam angle (as its
    report.json says)."""
    r = result if isinstance(result, Mapping) else {}
    return {k: r.get(k) for k in ("status", "value", "limit", "unit", "at_deg")}


def analyse_machine(machine: MachineSpec, programs: Sequence[MotionProgram] | None = None, *,
                    sweep: str | None = None) -> MachineResult:
    """Every follower's timing and tool, its torque on the machine grid, their total, the
    flywheel and the clearances; with ``sweep`` (a cam's name) the phase sweep of that cam.
    ``programs``: the followers' programs (default :meth:`MotionProgram.from_spec`: the follower's,
    also when a linkage is driven from the tool).

    Raises:
        SpecError: a cam whose body cannot give its follower's load (naming ``cam[i].spec.…``), or
            ``sweep`` names no cam of a clearance pair (naming ``--phase-sweep``).
    """
    if sweep is not None:
        check_sweep(machine, sweep)
    theta = machine_grid(machine.samples)
    omega = machine.omega
    timings, torques = [], []
    for i, cam in enumerate(machine.cams):
        program = programs[i] if programs is not None else MotionProgram.from_spec(cam.spec)
        try:
            timings.append(follower_timing(cam.name, cam.spec, cam.phase, theta, omega, program, cam.tool))
            torques.append(cam_torque(cam.spec, cam_angles(theta, cam.phase), omega, program))
        except SpecError as exc:
            raise SpecError(f"cam[{i}].spec.{exc.field}", exc.rule) from None
    total = np.sum(torques, axis=0)
    fw = flywheel(theta, total, omega, machine.machine.speed_fluctuation, machine.units)
    result = MachineResult(machine, theta, tuple(timings), tuple(torques), total, fw)
    result = replace(result, clearance=clearance_section(machine, result))
    if sweep is not None:
        result = replace(result, phase_sweep=phase_sweep_section(machine, result, sweep))
    return result


def _pair_timings(machine: MachineSpec, result: MachineResult, pair: ClearancePair
                  ) -> tuple[FollowerTiming, FollowerTiming]:
    index = {c.name: i for i, c in enumerate(machine.cams)}
    return result.timings[index[pair.a]], result.timings[index[pair.b]]


def clearance_section(machine: MachineSpec, result: MachineResult) -> dict[str, Any] | None:
    """machine.json's ``clearance`` section (None without ``[[clearance]]`` pairs): for each pair
    (tool A = ``between[0]``, B = ``between[1]``) the smallest signed distance [length] between
    their outlines over the turn — :func:`.clearance.min_clearance` on the machine grid (closed at
    360°) with the tools' poses, refined between the samples with their pose functions to
    ``tol`` = 1e-6 — and the check against ``required``: ``status``, and for a failing pair the
    ``remedy`` (the machine angle and the shift of tool B along ``direction`` that would pass there).
    ``failed``: the failing pairs' names "a/b"."""
    if not machine.clearances:
        return None
    unit = unit_name("length", machine.units)
    deg = np.append(result.theta_deg, 360.0)
    pairs, rows = {}, []
    for pair in machine.clearances:
        ta, tb = _pair_timings(machine, result, pair)
        assert ta.drive is not None and tb.drive is not None
        ca, cb = machine.cam(pair.a), machine.cam(pair.b)
        assert ca.tool is not None and cb.tool is not None
        pa = (np.vstack([ta.tool, ta.tool[:1]]), np.append(ta.tool_angle, ta.tool_angle[:1]))
        pb = (np.vstack([tb.tool, tb.tool[:1]]), np.append(tb.tool_angle, tb.tool_angle[:1]))
        pairs[pair.name] = min_clearance(outline_of(ca.tool), pa, outline_of(cb.tool), pb, deg,
                                         motion_a=ta.drive.at_machine, motion_b=tb.drive.at_machine)
    checks = clearance_check(pairs, {p.name: p.required for p in machine.clearances})
    for pair, check in zip(machine.clearances, checks):
        c = pairs[pair.name]
        remedy = None
        if check.remedy is not None:
            r = check.remedy
            remedy = {"at_deg": r["at_deg"], "shift": r["shift"], "direction": list(r["direction"]), "unit": unit,
                      "moves": pair.b,
                      "text": f"move {pair.b}'s tool {r['shift']:.6g} {unit} along ({r['direction'][0]:.4g}, "
                              f"{r['direction'][1]:.4g}) at machine angle {r['at_deg']:.6g}° (or change the phases: "
                              "--phase-sweep)"}
        rows.append({"name": pair.name, "between": [pair.a, pair.b], "required": pair.required,
                     "distance": c.distance, "at_deg": c.angle_deg % 360.0, "status": check.status,
                     "margin": c.distance - pair.required, "overlap": c.overlap, "exact_depth": c.exact_depth,
                     "refined": c.refined, "error_bound": c.error_bound, "point_a": c.point_a.tolist(),
                     "point_b": c.point_b.tolist(), "direction": c.direction.tolist(), "note": check.note,
                     "remedy": remedy})
    failed = [r["name"] for r in rows if r["status"] == "fail"]
    return {"unit": unit, "passed": not failed, "failed": failed, "pairs": rows}


def check_sweep(machine: MachineSpec, cam: str) -> None:
    """``--phase-sweep CAM``'s rule: CAM is a cam of the machine in at least one [[clearance]] pair.

    Raises:
        SpecError: naming ``--phase-sweep``.
    """
    names = [c.name for c in machine.cams]
    if cam not in names:
        raise SpecError("--phase-sweep", f"{cam!r} is not a cam of this machine (its cams: {', '.join(names)})")
    if not any(cam in (p.a, p.b) for p in machine.clearances):
        raise SpecError("--phase-sweep", f"cam {cam!r} is in no [[clearance]] pair: there is nothing to sweep")


def phase_sweep_section(machine: MachineSpec, result: MachineResult, cam: str, *, phases: int = 360,
                        samples: int = 720) -> dict[str, Any]:
    """machine.json's ``phase_sweep`` section: the phases φ [deg] of cam ``cam`` (the other cams
    where they are) that keep every ``[[clearance]]`` it takes part in.  Per pair,
    :func:`.clearance.phase_sweep` with the other tool as tool A (its poses at the machine angle,
    its phase fixed) and ``cam``'s tool as B at its own angle (B's phase = φ): the feasible
    ``intervals`` [(start, end) deg, end may pass 360 when it wraps] and the sampled clearance's
    ``error_bound``; ``intervals`` at the top: their intersection, ``current_phase_passes`` whether
    the cam's own phase lies in it.

    Raises:
        SpecError: ``cam`` is not in a pair (naming ``--phase-sweep``).
    """
    check_sweep(machine, cam)
    me = machine.cam(cam)
    assert me.tool is not None
    mine = result.timings[[c.name for c in machine.cams].index(cam)].drive
    assert mine is not None
    rows = []
    feasible: list[tuple[float, float]] = [(0.0, 360.0)]
    for pair in machine.clearances:
        if cam not in (pair.a, pair.b):
            continue
        other_name = pair.b if pair.a == cam else pair.a
        other = machine.cam(other_name)
        assert other.tool is not None
        ot = result.timings[[c.name for c in machine.cams].index(other_name)].drive
        assert ot is not None
        sw = phase_sweep(outline_of(other.tool), ot.at_machine, outline_of(me.tool), mine.at_own, pair.required,
                         phases=phases, samples=samples)
        rows.append({"name": pair.name, "other": other_name, "required": pair.required,
                     "intervals": [[a, b] for a, b in sw.intervals], "error_bound": sw.error_bound,
                     "min_clearance": float(np.min(sw.clearance)), "max_clearance": float(np.max(sw.clearance))})
        feasible = _intersect(feasible, list(sw.intervals))
    current = any(a <= me.phase <= b or a <= me.phase + 360.0 <= b for a, b in feasible)
    return {"cam": cam, "phase_deg": me.phase, "unit": unit_name("length", machine.units), "phases": int(phases),
            "samples": int(samples), "pairs": rows, "intervals": [[a, b] for a, b in feasible],
            "current_phase_passes": current,
            "shortest_cycle": shortest_cycle_section(machine, result, cam, feasible,
                                                     {r["name"]: r["intervals"] for r in rows})}


#: machine.json ``phase_sweep.shortest_cycle.assumption``: what the cycle time assumes
CYCLE_ASSUMPTION = ("the saved machine angle is taken out of a dwell of the whole machine (every cam at rest), each "
                    "cam's program redrawn over the shorter cycle with its motions' durations kept: cycle time = "
                    "60/rpm × (360 − saved)/360 s. It holds when the whole machine's longest dwell grows by the "
                    "saved angle (machine_dwell_deg → machine_dwell_at_phase_deg)")


def shortest_cycle_section(machine: MachineSpec, result: MachineResult, cam: str,
                           feasible: Sequence[tuple[float, float]], pair_intervals: Mapping[str, Sequence[Sequence[float]]]
                           ) -> dict[str, Any]:
    """machine.json's ``phase_sweep.shortest_cycle``: how much earlier cam ``cam``'s motion can start
    keeping every clearance (docs/clearance.md, "The shortest cycle of a machine").

    Its motion starts with its program's first rise or return (machine angle phase + its start).  The
    motion it *follows* is the rise or return of a cam it shares a ``[[clearance]]`` pair with that
    started last before it (the least d = its start − that motion's start, mod 360, in [0, 360)).  Moving
    the phase down from φ_c keeps every clearance down to the lower end of the feasible interval
    holding φ_c (``feasible``: the sweep's intersection), and keeps the order down to φ_c − d (both
    starting together): ``saved_deg`` = the smaller, φ* = φ_c − saved (``limited_by`` "clearance",
    naming ``binding_pairs``, or "order").  ``overlap_deg`` = the followed motion's end − this motion's
    start at φ* (``current_overlap_deg`` at φ_c; negative: a gap).  ``clearance_at_phase``: each pair's
    smallest distance at φ*, refined (:func:`.clearance.min_clearance`): φ* is a boundary of the
    sweep's sampled clearance, so a clearance-limited one sits at ``required`` to within the sweep's
    error bound.  The cycle times at the machine speed assume :data:`CYCLE_ASSUMPTION`;
    ``machine_dwell_deg`` and ``machine_dwell_at_phase_deg`` are the whole machine's longest dwell
    (no cam moving) at φ_c and at φ*, ``assumption_holds`` whether it grew by at least ``saved_deg``.  With the current phase failing, or no motion to follow, the
    numbers are None and ``note`` says why."""
    names = [c.name for c in machine.cams]
    me = machine.cam(cam)
    mine = result.timings[names.index(cam)]
    rpm = machine.machine.speed_rpm
    cycle = 60.0 / rpm
    partners = [p.b if p.a == cam else p.a for p in machine.clearances if cam in (p.a, p.b)]
    out: dict[str, Any] = {"follows": None, "motion": None, "phase_deg": None, "saved_deg": None,
                           "limited_by": None, "binding_pairs": [], "overlap_deg": None, "current_overlap_deg": None,
                           "clearance_at_phase": [], "cycle_time_s": cycle, "shortest_cycle_time_s": None,
                           "cycles_per_min": None, "machine_dwell_deg": _machine_dwell(result, cam, 0.0),
                           "machine_dwell_at_phase_deg": None, "dwell_gained_deg": None, "assumption_holds": None,
                           "assumption": CYCLE_ASSUMPTION, "note": None}
    followed = [(e, p) for p in dict.fromkeys(partners) for e in result.timings[names.index(p)].events]
    if not mine.events or not followed:
        out["note"] = f"{cam if not mine.events else 'no cam it shares a pair with'} has no rise or return: no motion to follow"
        return out
    first = mine.events[0]
    d_of = [_ccw(first.start_deg - e.start_deg) for e, _p in followed]
    k = int(np.argmin(d_of))
    (ev, owner), d_now = followed[k], d_of[k]
    span = _ccw(ev.end_deg - ev.start_deg) or 360.0
    out["follows"] = {"cam": owner, "event": ev.label, "start_deg": ev.start_deg, "end_deg": ev.end_deg,
                      "span_deg": span}
    out["motion"] = {"event": first.label, "start_deg": first.start_deg}
    out["current_overlap_deg"] = span - d_now
    room = _room(feasible, me.phase)
    if room is None:
        out["note"] = (f"{cam}'s phase {me.phase:g}° does not keep every clearance: move it into one of the phase "
                       "ranges first")
        return out
    saved = min(room, d_now)
    phase = (me.phase - saved) % 360.0
    rooms = {name: _room([tuple(iv) for iv in ivs], me.phase) for name, ivs in pair_intervals.items()}
    limited = "order" if d_now <= room else "clearance"
    out.update({"phase_deg": phase, "saved_deg": saved, "limited_by": limited,
                "binding_pairs": [n for n, r in rooms.items() if limited == "clearance" and r is not None
                                  and abs(r - room) <= 1e-9],
                "overlap_deg": span - (d_now - saved),
                "clearance_at_phase": _clearance_at_phase(machine, result, cam, phase),
                "shortest_cycle_time_s": cycle * (360.0 - saved) / 360.0,
                "cycles_per_min": rpm * 360.0 / (360.0 - saved),               # saved ≤ d < 360
                "machine_dwell_at_phase_deg": _machine_dwell(result, cam, saved)})
    out["dwell_gained_deg"] = out["machine_dwell_at_phase_deg"] - out["machine_dwell_deg"]
    out["assumption_holds"] = bool(out["dwell_gained_deg"] >= saved - 1e-9)
    return out


def _ccw(angle: float) -> float:
    """``angle`` [deg] in [0, 360), a value within 1e-9 below 360 taken as 0."""
    a = float(angle) % 360.0
    return 0.0 if a > 360.0 - 1e-9 else a


def _room(intervals: Sequence[tuple[float, float]], phase: float) -> float | None:
    """How far [deg] ``phase`` can move down staying inside the circular interval that holds it
    (``math.inf`` on the whole circle); None when no interval holds it."""
    best = None
    for a, b in intervals:
        if b - a >= 360.0:
            return math.inf
        for p in (phase, phase + 360.0):
            if a <= p <= b:
                best = p - a if best is None else max(best, p - a)
    return best


def _machine_dwell(result: MachineResult, cam: str, earlier: float) -> float:
    """The whole machine's longest dwell [deg of machine angle]: the longest arc where no cam rises or
    returns, with cam ``cam``'s motions ``earlier`` degrees earlier."""
    pieces = []
    for t in result.timings:
        shift = earlier if t.name == cam else 0.0
        for e in t.events:
            start, span = (e.start_deg - shift) % 360.0, _ccw(e.end_deg - e.start_deg) or 360.0
            if span >= 360.0:
                return 0.0
            pieces += [(start, min(start + span, 360.0))] + ([(0.0, start + span - 360.0)] if start + span > 360.0 else [])
    if not pieces:
        return 360.0
    pieces.sort()
    gaps, reach = [], pieces[0][1]
    for a, b in pieces[1:]:
        gaps.append(a - reach)
        reach = max(reach, b)
    gaps.append(pieces[0][0] + 360.0 - reach)
    return float(max(0.0, max(gaps)))


def _clearance_at_phase(machine: MachineSpec, result: MachineResult, cam: str, phase: float) -> list[dict[str, Any]]:
    """Each pair with cam ``cam``, its smallest distance over the turn with the cam at ``phase`` [deg]
    (:func:`.clearance.min_clearance` on the machine grid, refined with the pose functions)."""
    names = [c.name for c in machine.cams]
    deg = np.append(result.theta_deg, 360.0)
    rows = []
    for pair in machine.clearances:
        if cam not in (pair.a, pair.b):
            continue
        drives = []
        for n in (pair.a, pair.b):
            d = result.timings[names.index(n)].drive
            assert d is not None
            drives.append(replace(d, phase=phase) if n == cam else d)
        ca, cb = machine.cam(pair.a), machine.cam(pair.b)
        assert ca.tool is not None and cb.tool is not None
        pa, pb = drives[0].at_machine(deg), drives[1].at_machine(deg)
        c = min_clearance(outline_of(ca.tool), pa, outline_of(cb.tool), pb, deg, motion_a=drives[0].at_machine,
                          motion_b=drives[1].at_machine)
        rows.append({"name": pair.name, "required": pair.required, "distance": c.distance,
                     "margin": c.distance - pair.required, "at_deg": c.angle_deg % 360.0, "error_bound": c.error_bound})
    return rows


def _pieces(intervals: Sequence[tuple[float, float]]) -> list[tuple[float, float]]:
    """Circular intervals [deg] (start in [0, 360), end > start, ≤ start + 360) as pieces within [0, 360]."""
    out = []
    for a, b in intervals:
        if b > 360.0:
            out += [(a, 360.0), (0.0, b - 360.0)]
        else:
            out.append((a, b))
    return out


def _intersect(x: Sequence[tuple[float, float]], y: Sequence[tuple[float, float]]) -> list[tuple[float, float]]:
    """The intersection of two sets of circular phase intervals [deg], in the same form (a piece
    ending at 360 and one starting at 0 joined into one that wraps)."""
    got = sorted((max(a, c), min(b, d)) for a, b in _pieces(x) for c, d in _pieces(y) if max(a, c) < min(b, d))
    if len(got) == 1 and got[0] == (0.0, 360.0):
        return got
    if len(got) > 1 and got[0][0] == 0.0 and math.isclose(got[-1][1], 360.0):
        first = got.pop(0)
        got[-1] = (got[-1][0], 360.0 + first[1])
    return got


__all__ = ["CYCLE_ASSUMPTION", "MachineResult", "analyse_machine", "check_sweep", "clearance_section",
           "phase_sweep_section", "shortest_cycle_section"]

"""``cam-workbench build``'s summary lines of a parallel indexer: every number a value of report.json
(``follower.label``, ``indexer.geometry``, ``pressure_angle``, ``body.flank_fit_error``,
``indexer.motion_from_geometry``, ``indexer.drive``, ``machining.plates``).

:mod:`cam_workbench.commands.build` registers its printer for :data:`BODY` in its ``SUMMARIES``
table and prints these lines around the files line and the checks' verdict (this module imports
nothing of it: no import cycle).
"""
from __future__ import annotations

from cam_workbench.generators.bodies.indexing.parallel_kind import ParallelIndexerBody

#: the body class whose summary these lines are
BODY = ParallelIndexerBody


def body_lines(s: dict) -> list[str]:
    """The body and its turret, the pressure angles, the clearance, the fitted flanks, the turret
    angle recovered from the built profiles, the volume and the drive (when report.json has it)."""
    u = s["units"]
    b = s["body"]
    ix = s["indexer"]
    geo = ix["geometry"]
    pa = s["pressure_angle"]
    limit = ((s["checks"].get("results") or {}).get("pressure_angle") or {}).get("limit")
    fit = b["flank_fit_error"]
    lines = [
        f"  {b['kind']} (lengths in {u}): {s['follower']['label']}",
        f"  turret: {geo['stations']} stations, C = {geo['centre_distance_mm']:.6g} {u}, "
        f"R_p = {geo['pitch_radius_mm']:.6g} {u}, r_r = {geo['roller_radius_mm']:.6g} {u}; "
        f"{b['cams']} plates {b['plate_thickness']:.6g} {u} thick, gap {b['gap']:.6g} {u}; "
        f"{geo['law']} index over {geo['index_angle_deg']:.6g}° of input from {geo['index_start_deg']:.6g}°",
        f"  pressure angle: max {pa['max_deg']:.2f}° at {pa['at_deg']:.2f}° (the contact carrying the output torque"
        + ("" if limit is None else f", limit {limit:.6g}°")
        + f"); over the whole index {pa['index_max_deg']:.2f}° at {pa['index_max_at_deg']:.2f}°",
        f"  clearance: smallest gap of an idle roller to a cam {geo['clearance_mm']:.4g} {u} "
        f"(cam {geo['clearance_cam']}, roller {geo['clearance_roller']})",
        # the flanks are fitted B-splines: their measured error, never "exact"
        f"  flanks: cubic B-splines fitted within {fit['value']:.3g} {fit['unit']} of the offset of the roller loci "
        f"(measured, not exact; the dwell arcs are exact arcs); largest cam radius {b['outer_radius']:.6g} {u}",
    ]
    mg = ix.get("motion_from_geometry")
    if mg:
        lines.append(f"  turret angle recovered from the built profiles: max error {mg['max_error_rad']:.3g} rad from "
                     f"the law ({mg['samples']} input angles, {mg['undetermined_samples']} where the profiles alone "
                     "do not fix it)")
    sol = s.get("solid") or {}
    kernel = (f" (kernel {sol['volume_rel_diff']:+.2e} relative)"
              if isinstance(sol.get("volume_rel_diff"), (int, float)) else "")
    lines.append(f"  volume {s['volume']:.6g} {u}³{kernel}")
    d = ix.get("drive")
    if d:
        life = "" if d.get("l10_hours") is None else f", roller life L10 {d['l10_hours']:.4g} h"
        lines.append(f"  drive at {d['input_speed_rpm']:.6g} rpm: index {d['index_time_s']:.4g} s, peak output "
                     f"acceleration {d['output_acceleration_peak_rad_s2']:.4g} rad/s², peak input torque "
                     f"{d['input_torque_peak_Nm']:.4g} N·m, peak normal force {d['normal_force_peak_N']:.4g} N, peak "
                     f"Hertz stress {d['contact_stress_peak_Pa'] / 1e6:.4g} MPa{life}")
    return lines


def program_lines(s: dict) -> list[str]:
    """A line per plate's program (report.json ``machining.plates``)."""
    u = s["units"]
    return [f"  {p['file']}: XY contour of cam {p['cam']}, tool radius {p['tool_radius_mm']:g} {u}, "
            f"{p['gcode_lines']} lines, within {p['path_error_mm']:.3g} {u} of the exact tool-centre path"
            for p in (s.get("machining") or {}).get("plates") or []]

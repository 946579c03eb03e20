"""``cam-workbench build``'s summary lines of a barrel or globoidal indexer: every number a value of
report.json (``follower.label``, ``indexer.geometry``, ``pressure_angle``, ``body.flank_fit_error``,
``indexer.motion_from_geometry``, ``volume``, ``solid``, ``indexer.drive``, ``machining``).

:mod:`cam_workbench.commands.build` registers its printer for :data:`BODY` (the base of both
bodies) in its ``SUMMARIES`` table (this module imports nothing of it: no import cycle).
"""
from __future__ import annotations

from cam_workbench.generators.bodies.indexing.spatial_kind import SpatialIndexerBody

#: the body class whose summary these lines are (the barrel's and the globoid's base)
BODY = SpatialIndexerBody


def _rib_words(geo: dict, u: str) -> str:
    if geo["type"] == "BarrelIndexer":
        return (f"R_p = {geo['pitch_radius']:.6g} {u}; rib between the cylinders {geo['root_radius']:.6g}–"
                f"{geo['outer_radius']:.6g} {u}")
    return f"rib between the globoids {geo['tip_radius']:.6g}–{geo['root_radius']:.6g} {u}"


def _roller_words(geo: dict, u: str) -> str:
    """The rollers: "r_r = 12 mm", or for conical rollers (``roller_radius_start`` present, γ ≠ 0)
    their radii at t0 and t1, the cone angle, the middle's radius and the apex's t."""
    if geo.get("roller_radius_start") is None:
        return f"r_r = {geo['roller_radius']:.6g} {u}"
    return (f"conical rollers r = {geo['roller_radius_start']:.6g}–{geo['roller_radius_end']:.6g} {u} (γ = "
            f"{geo['roller_cone_angle_deg']:.6g}°, r_r = {geo['roller_radius']:.6g} {u} at mid-length, apex at t = "
            f"{geo['roller_cone_apex_t']:.6g} {u})")


def body_lines(s: dict) -> list[str]:
    """The body and its turret, the pressure angles, the rib, the fitted flanks, the turret angle
    recovered from the flanks, the volume and the drive (when report.json has it)."""
    u = s["units"]
    b = s["body"]
    ix = s["indexer"]
    geo = ix["geometry"]
    pa = s["pressure_angle"]
    limit = ((s["checks"].get("results") or {}).get("pressure_angle") or {}).get("limit")
    fit = b["flank_fit_error"]
    rib = geo["min_rib_thickness"]
    mu = geo["min_regularity_margin"]
    lines = [
        f"  {b['kind']} (lengths in {u}): {s['follower']['label']}",
        f"  turret: {geo['stations']} stations, C = {geo['centre_distance']:.6g} {u}, {_roller_words(geo, u)} over "
        f"t = {geo['roller_start']:.6g}–{geo['roller_end']:.6g} {u}; {_rib_words(geo, u)}, cam "
        f"{geo['cam_width']:.6g} {u} long; {geo['law']} index over {geo['index_angle_deg']:.6g}° of input from "
        f"{geo['index_start_deg']:.6g}°",
        f"  pressure angle: max {pa['max_deg']:.2f}° at {pa['at_deg']:.2f}° (the driving contact line"
        + ("" if limit is None else f", limit {limit:.6g}°")
        + f"); over every engaged contact {pa['contacts_max_deg']:.2f}° at {pa['contacts_max_at_deg']:.2f}°",
        f"  rib: thinnest {rib['value_mm']:.4g} {u} at {rib['at_deg']:.2f}°; flank regularity margin at least "
        f"{mu['value_1']:.3g} (at {mu['at_deg']:.2f}°)",
        # the flanks are fitted B-spline surfaces: their measured error, never "exact"
        f"  flanks: bicubic B-spline surfaces fitted within {fit['value']:.3g} {fit['unit']} of the rollers' exact "
        "envelope (measured, not exact)",
    ]
    mg = ix.get("motion_from_geometry")
    if mg:
        lines.append(f"  turret angle recovered from the flank surfaces: max error {mg['max_error_rad']:.3g} rad from "
                     f"the law ({mg['samples']} input angles)")
    sol = s.get("solid") or {}
    kernel = (f" (OCCT {sol['volume_rel_diff']:+.2e} relative)"
              if isinstance(sol.get("volume_rel_diff"), (int, float)) else "")
    lines.append(f"  volume {s['volume']:.6g} {u}³ by a grid of the exact envelope{kernel}")
    d = ix.get("drive")
    if d:
        life = "" if d.get("l10_hours") is None else f", roller life L10 {d['l10_hours']:.4g} h"
        lines.append(f"  drive at {d['input_speed_rpm']:.6g} rpm: index {d['index_time_s']:.4g} s, peak output "
                     f"acceleration {d['output_acceleration_peak_rad_s2']:.4g} rad/s², peak input torque "
                     f"{d['input_torque_peak_Nm']:.4g} N·m, peak normal force {d['normal_force_peak_N']:.4g} N, peak "
                     f"Hertz stress {d['contact_stress_peak_Pa'] / 1e6:.4g} MPa{life}")
    return lines


def program_lines(s: dict) -> list[str]:
    """The generating program's line (report.json ``machining``), when there is one."""
    m = s.get("machining") or {}
    if not m:
        return []
    u = s["units"]
    pe = m["path_error"]
    cone = m["generating"]["tool_cone_angle_deg"]
    tool = (f"tool radius {m['tool_radius']:g} {u}" if cone == 0 else
            f"tapered tool (half angle {cone:g}°) radius {m['tool_radius']:g} {u} at the roller's middle")
    return [f"  {m['file']}: {m['program']} program (LinuxCNC XYZAC), {tool}, "
            f"{m['passes']} depth levels, {m['gcode_lines']} lines, the cutter's axis within {pe['value']:.3g} {u} "
            "of the roller's exact axis"]

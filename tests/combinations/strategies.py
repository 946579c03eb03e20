"""Valid specs over every documented option (as TOML-structure dicts), and mutations of them.

Cams are drawn mostly buildable (base radius well above lift + roller) with a share of
borderline ones (small base radius: undercut, large pressure angles), which must end in a clean
refusal or a result whose checks fail — never an internal error."""
from __future__ import annotations

import math
from typing import Any

from hypothesis import strategies as st

LAWS = ("cycloidal", "harmonic", "modified_sine", "modified_trapezoid", "poly345", "poly4567", "bspline",
        "polynomial", "constant_velocity", "table")
DXF_VERSIONS = ("R12", "R2000", "R2004", "R2007", "R2010", "R2013", "R2018")


def _segment(kind: str, angle: float, lift: float | None, law: str | None, y: float, level: float = 0.0,
             variant: int = 0) -> dict[str, Any]:
    """One segment; ``level`` is s at its start (a table's points are absolute lifts), ``variant``
    (0–5) picks among a law's options (continuity, interior points, blends)."""
    seg: dict[str, Any] = {"kind": kind, "angle": angle}
    if kind != "dwell":
        seg.update(lift=lift, law=law)
        if law == "bspline":
            seg.update(order=5, control_x=[angle * j / 8 for j in range(1, 8)], control_y=[y])
        sign = 1.0 if kind == "rise" else -1.0
        if law == "polynomial":
            if variant in (1, 4):
                seg.update(start_continuity=3, end_continuity=3)          # 4-5-6-7 between dwells
            if variant in (2, 4):                                         # a point on the 3-4-5 curve moved by y
                x = 0.5
                seg["points"] = [[angle * x, level + sign * lift * (0.5 + 0.2 * (y - 0.5))]]
            if variant == 3:
                seg["end_continuity"] = 1                                  # acceleration free at the end
        elif law == "constant_velocity":
            blends = {0: (0.2, 0.2), 1: (0.3, 0.1), 2: (0.15, None), 3: (None, 0.15), 4: (0.25, 0.25), 5: (0.2, 0.2)}
            b0, b1 = blends[variant]
            if b0:
                seg["start_blend"] = angle * b0
            if b1:
                seg["end_blend"] = angle * b1
            if variant == 5:
                seg.update(start_continuity=3, end_continuity=3)
        elif law == "table":                                            # a sampled cycloid, every 3°
            n = max(8, int(angle / 3.0))
            xs = [j / n for j in range(n + 1)]
            f = [x - math.sin(2 * math.pi * x) / (2 * math.pi) for x in xs]
            seg["table"] = [[angle * x, level + sign * lift * fx] for x, fx in zip(xs, f)]
            if variant in (1, 3):
                seg["order"] = 6
            if variant == 2:
                seg["table_tolerance"] = lift * 1e-2
    return seg


@st.composite
def motion_programs(draw: Any, lift: float) -> list[dict[str, Any]]:
    """Dwell–rise–dwell–return programs, rise–return without dwells, and two-level programs
    (rise, dwell, rise, dwell, return); angles summing to 360° exactly."""
    shape = draw(st.sampled_from(["drdrd", "rr", "rdrdr", "drdr"]))
    kinds = {"drdrd": ["dwell", "rise", "dwell", "return", "dwell"], "rr": ["rise", "return"],
             "rdrdr": ["rise", "dwell", "rise", "dwell", "return"], "drdr": ["dwell", "rise", "dwell", "return"]}[shape]
    weights = [draw(st.integers(20, 100)) if k != "dwell" else draw(st.integers(5, 60)) for k in kinds]
    total = sum(weights)
    angles = [360.0 * w / total for w in weights]
    angles[-1] = 360.0 - sum(angles[:-1])
    rises = [i for i, k in enumerate(kinds) if k == "rise"]
    parts = [lift / len(rises)] * len(rises)
    segs = []
    level = 0.0
    for i, k in enumerate(kinds):
        law = draw(st.sampled_from(LAWS)) if k != "dwell" else None
        h = None if k == "dwell" else (parts[rises.index(i)] if k == "rise" else lift)
        segs.append(_segment(k, angles[i], h, law, draw(st.floats(0.3, 0.7)), level,
                             draw(st.integers(0, 5)) if law in ("polynomial", "constant_velocity", "table") else 0))
        level += 0.0 if h is None else (h if k == "rise" else -h)
    return segs


@st.composite
def specs(draw: Any, borderline: bool = True, body: str | None = None) -> dict[str, Any]:
    """A valid spec dict over the documented options; ``body`` ("plate", "groove", "conjugate"):
    only that body (a groove or a conjugate pair has a roller), else any."""
    units = draw(st.sampled_from(["mm", "in"]))
    u = 1.0 if units == "mm" else 1 / 25.4
    motion = draw(st.sampled_from(["translating", "translating", "oscillating"]))
    kind = draw(st.sampled_from(["roller", "knife", "flat"])) if body in (None, "plate") else "roller"
    lift_len = draw(st.floats(5.0, 25.0)) * u
    roller = draw(st.floats(2.0, 10.0)) * u if kind == "roller" else 0.0
    tight = borderline and draw(st.integers(0, 9)) == 0
    base = (roller + lift_len) * (draw(st.floats(0.9, 1.4)) if tight else draw(st.floats(2.0, 4.0)))
    base = max(base, roller + 1.0 * u)
    bore = draw(st.sampled_from([0.0, 0.2])) * (base - roller)
    follower: dict[str, Any] = {"kind": kind, **({"roller_radius": roller} if kind == "roller" else {})}
    if motion == "translating":
        lift = lift_len
        follower["offset"] = draw(st.sampled_from([0.0, 0.15, -0.15])) * base
    else:
        # an arm that reaches the prime circle, turning through arm degrees well below ψ₀ (β₀)
        d = base * draw(st.floats(1.3, 2.2))
        follower.update(motion="oscillating", pivot_distance=d)
        if kind == "flat":
            f = draw(st.sampled_from([0.0, 0.1, -0.1])) * base
            follower["face_offset"] = f
            if draw(st.booleans()):
                follower["arm_length"] = d * draw(st.floats(0.5, 0.9))
        else:
            follower["arm_length"] = d - base * draw(st.floats(0.1, 0.9))   # |d − L| < R_b < d + L
        lift = draw(st.floats(4.0, 18.0))
    spec: dict[str, Any] = {
        "units": units,
        "cam": {"base_radius": base, "thickness": draw(st.floats(3.0, 20.0)) * u, "bore_diameter": bore,
                "direction": draw(st.sampled_from(["ccw", "cw"])), "speed_rpm": draw(st.sampled_from([30.0, 60.0, 300.0]))},
        "follower": follower,
        "motion": draw(motion_programs(lift)),
    }
    if draw(st.booleans()):
        if motion == "translating":
            spec["follower"].update(mass=draw(st.floats(0.05, 2.0)) * (1.0 if units == "mm" else 0.0057),
                                    preload=draw(st.floats(5.0, 50.0)) * (1.0 if units == "mm" else 0.2248),
                                    spring_rate=draw(st.floats(0.0, 2.0)) * (1.0 if units == "mm" else 5.71))
        else:   # kg·mm², N·mm, N·mm/rad (lbf·in·s², lbf·in, lbf·in/rad)
            spec["follower"].update(
                arm_inertia=draw(st.floats(100.0, 5000.0)) * (1.0 if units == "mm" else 8.85e-6),
                preload_torque=draw(st.floats(200.0, 2000.0)) * (1.0 if units == "mm" else 8.85e-3),
                spring_torque_rate=draw(st.floats(0.0, 2000.0)) * (1.0 if units == "mm" else 8.85e-3))
    if kind == "flat" and draw(st.booleans()):
        spec["follower"]["face_width"] = base * draw(st.floats(0.3, 2.0))
    rep = draw(st.sampled_from(["ph", "bspline"]))
    junctions = draw(st.sampled_from(["segments", "tolerance", "per_segment"]))
    if rep == "bspline" and junctions == "per_segment":
        junctions = "segments"
    if junctions == "segments":
        spec["pitch"] = {"representation": rep, "segments": draw(st.integers(24, 120))}
    elif junctions == "tolerance":
        spec["pitch"] = {"representation": rep,
                         "tolerance": draw(st.sampled_from([2e-3, 5e-4])) * (1.0 if motion == "oscillating" else u)}
    else:
        spec["pitch"] = {"representation": rep}
        for seg in spec["motion"]:
            seg["junctions"] = max(2, round(seg["angle"] / 6.0))
    spec["machining"] = {"program": draw(st.sampled_from(["xy", "xc"])),
                         "contour": draw(st.sampled_from(["arcs", "lines"])),
                         "milling": draw(st.sampled_from(["climb", "conventional"])),
                         "passes": draw(st.integers(1, 3))}
    line = draw(st.sampled_from(["follower", "axis", None]))
    if line is not None and not (line == "follower" and motion == "oscillating"):
        spec["machining"]["rotary_line"] = line
    if draw(st.booleans()):
        spec["machining"]["tool_radius"] = (roller or 3.0 * u) * draw(st.sampled_from([0.6, 1.0, 1.5]))
    if spec["machining"]["program"] == "xc":
        spec["machining"]["sample_period"] = 0.0005
    curves = draw(st.sampled_from(["cubic", "spline", "arcs", "polyline"]))
    version = draw(st.sampled_from(DXF_VERSIONS))
    if version == "R12" and curves in ("cubic", "spline"):
        curves = "arcs"
    spec["drawing"] = {"curves": curves, "dxf_version": version, "title": draw(st.sampled_from(["Cam", "Nocken Ø40 — Typ A"])),
                       "dimensions": draw(st.booleans()), "title_block": draw(st.booleans())}
    spec["checks"] = {"sampling": draw(st.sampled_from(["dense", "thesis71"]))}
    _body(draw, spec, kind, base, roller, lift_len if motion == "translating" else 0.0, u, body)
    return spec


def _body(draw: Any, spec: dict[str, Any], kind: str, base: float, roller: float, lift: float, u: float,
          body: str | None = None) -> None:
    """The body (``body``, else any the follower allows) and its features: a groove cam (a roller
    only: the XY program), a conjugate pair or the plate; a keyway by a standard or explicit, a
    hub, mounting holes between the bore and the profile, a timing mark — sized from the cam so
    that most draws fit and some do not (a clean refusal)."""
    cam = spec["cam"]
    bore = cam["bore_diameter"]
    if body in ("groove", "conjugate"):
        pick = 0 if body == "groove" else 1
    else:                                    # 2…5: the plate
        pick = draw(st.integers(0 if body is None else 2, 5)) if kind == "roller" else 5
    if pick == 1:
        _conjugate(draw, spec, roller, u)
    if pick == 0:
        cam["body"] = "groove"
        reach = base + lift + roller + 0.5 * u
        cam["outer_diameter"] = 2 * reach + 2 * draw(st.floats(3.0, 15.0)) * u
        spec["groove"] = {"depth": cam["thickness"] * draw(st.floats(0.3, 0.8))}
        spec["machining"]["program"] = "xy"
        spec["machining"].pop("tool_radius", None)
        inner = base - roller
    else:
        inner = base - roller
    if bore > 0 and draw(st.booleans()):
        # the standards' tables cover DIN 6885-1: 6 < d ≤ 230 mm, ANSI B17.1: 5/16 < d ≤ 6 1/2 in
        # (outside them the spec is refused: tests/test_bodies.py); explicit sizes elsewhere
        in_table = 6.0 < bore <= 230.0 if spec["units"] == "mm" else 0.3125 < bore <= 6.5
        if not in_table or draw(st.booleans()):
            cam["keyway_width"], cam["keyway_depth"] = 0.25 * bore, 0.12 * bore
        else:
            cam["keyway"] = "DIN6885" if spec["units"] == "mm" else "ANSI"
    if draw(st.booleans()):
        cam["hub_diameter"] = max(bore, 2.0 * u) * draw(st.floats(1.6, 2.5)) + 2.0 * u
        cam["hub_length"] = cam["thickness"] * draw(st.floats(0.5, 1.5))
    if draw(st.booleans()):
        n = draw(st.integers(2, 6))
        r_in, r_out = bore / 2 + 0.15 * inner, 0.9 * inner
        cam.update(mounting_holes=n, mounting_circle_diameter=r_in + r_out,
                   mounting_hole_diameter=max((r_out - r_in) * draw(st.floats(0.2, 0.6)), 0.5 * u))
    cam["timing_mark"] = draw(st.booleans())


def _conjugate(draw: Any, spec: dict[str, Any], roller: float, u: float) -> None:
    """A conjugate pair (PH pitch curves): a translating yoke's second roller a little beyond the
    cam's far side, or an oscillating arm pair's second arm on the other side of the line through
    the pivot and the axis (some draws do not fit: a clean refusal naming the field)."""
    import math

    from cam_workbench.generators.followers.oscillating import zero_lift_arm_angle

    cam, fol = spec["cam"], spec["follower"]
    cam["body"] = "conjugate"
    spec["pitch"]["representation"] = "ph"
    r2 = roller * draw(st.sampled_from([1.0, 0.6, 1.3]))
    spec["conjugate"] = {"roller_radius": r2, "gap": draw(st.sampled_from([0.0, 0.5, 3.0])) * u}
    clear = r2 + cam["bore_diameter"] / 2
    h = max(m.get("lift") or 0.0 for m in spec["motion"])          # the return's lift: the largest
    if fol.get("motion", "translating") == "translating":
        e, base = fol.get("offset", 0.0), cam["base_radius"]
        s0 = math.sqrt(max(base * base - e * e, 0.0))
        # the second roller about as far from the axis at the top of the lift as the first at the
        # bottom (a second cam of about the first's size), sometimes closer (undercut: a refusal)
        far = max(s0 * draw(st.sampled_from([1.0, 1.0, 0.7, 0.4])), clear + abs(e) + 0.5 * u)
        spec["conjugate"]["roller_distance"] = s0 + h + far
    else:
        psi0 = math.degrees(zero_lift_arm_angle(cam["base_radius"], fol["pivot_distance"], fol["arm_length"]))
        psi2 = -180.0 + h + (180.0 - h) * draw(st.floats(0.3, 0.7))
        spec["conjugate"]["arm_angle"] = (psi2 - psi0 + 180.0) % 360.0 - 180.0


@st.composite
def cylindrical_specs(draw: Any) -> dict[str, Any]:
    """A cylindrical (barrel) cam over its options: a translating roller along the cam axis or an
    oscillating arm about a radial pivot, every motion program, mm or inch, ccw or cw, an outer
    diameter or the default, a bore, the groove's clearance, the 4-axis program's passes and tool —
    sized so that most draws build and some are refused (undercut, pressure angle, length)."""
    units = draw(st.sampled_from(["mm", "in"]))
    u = 1.0 if units == "mm" else 1 / 25.4
    motion = draw(st.sampled_from(["translating", "translating", "oscillating"]))
    rp = draw(st.floats(25.0, 60.0)) * u
    roller = draw(st.floats(3.0, 8.0)) * u
    depth = roller * draw(st.floats(0.8, 1.6))
    clearance = draw(st.sampled_from([None, 0.02, 0.1])) 
    w = 2 * roller + (clearance if clearance is not None else 0.05) * u
    follower: dict[str, Any] = {"kind": "roller", "roller_radius": roller}
    if motion == "translating":
        lift = draw(st.floats(5.0, 25.0)) * u
        travel = lift
    else:
        arm = draw(st.floats(30.0, 80.0)) * u
        d = arm * draw(st.floats(0.8, 1.0))
        lift = draw(st.floats(10.0, 35.0))                                  # arm degrees
        follower.update(motion="oscillating", arm_length=arm, pivot_distance=d)
        travel = 2 * arm * math.sin(math.radians(lift) / 2)
    length = travel + w + 2 * 3.0 * u + draw(st.floats(1.0, 20.0)) * u
    cam: dict[str, Any] = {"body": "cylindrical", "cylinder_radius": rp, "length": length,
                           "bore_diameter": draw(st.sampled_from([0.0, 0.3, 0.6])) * rp,
                           "direction": draw(st.sampled_from(["ccw", "cw"])),
                           "speed_rpm": draw(st.sampled_from([30.0, 60.0, 300.0]))}
    if draw(st.booleans()):
        cam["outer_diameter"] = 2 * (rp + depth * draw(st.floats(0.1, 0.9)))
    groove: dict[str, Any] = {"depth": depth}
    if clearance is not None:
        groove["clearance"] = clearance * u
    spec: dict[str, Any] = {"units": units, "cam": cam, "follower": follower, "motion": draw(motion_programs(lift)),
                            "groove": groove, "machining": {"passes": draw(st.integers(1, 3))}}
    if draw(st.booleans()):
        spec["machining"]["tool_radius"] = roller * draw(st.sampled_from([0.5, 0.8]))
    return spec

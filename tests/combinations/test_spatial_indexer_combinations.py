"""The barrel and globoidal indexers (``cam.body`` = "barrel_indexer", "globoidal_indexer";
generators/bodies/indexing/spatial_kind.py, docs/indexing.md) over every option against every other,
through the Python API (``Cam``) and the CLI (``build`` and ``check``): a design whose checks agree
with their values and limits and whose contact lines lie on the rollers placed here from the
documented frames and the law — or a clean refusal, a SpecError or GeometryError naming a field the
spec has (the CLI: exit 2, one line naming it, nothing written) — never another exception.

The draws (sized around BARREL_INDEXER_SPEC_DICT and GLOBOIDAL_INDEXER_SPEC_DICT,
generators/spec/examples.py, and the catalogue rules of generators/bodies/indexing/spatial.py's
docstring): N = 3–16 stations, β = 60°–300° with the leading dwell anywhere in the rest of the
turn (lift 360/N), the six closed-form laws; barrel: R_p, C ≈ R_p·cos(π/N), rollers a fraction of
R_p·sin(π/N), the rollers' working length, the rib's root and top cylinders and the cam's length
each scaled; globoidal: the rollers' working length, r_r a fraction of t0·sin(π/N), the tip and root
globoids, C and the cam's width about the band that holds the dwell's rollers; the bore; the load
or none; the pressure-angle limit, the stress limit, the continuity order; the 4-axis program's
[machining] options (and, in one draw in eight, one it refuses); in one draw in ten a field an
indexer refuses (another body's, the follower's pivot, a hub, the dynamics).  Many cannot be built
(an undercut, no rib left, an unlocked turret, a bore through the core): those must be refused
naming the field.

Solids take seconds each: the design-level tests draw many, the solid (API) and CLI tests few
(``examples(ci, fuzz)``, tests/combinations/conftest.py: ``make test`` small and derandomised,
``make fuzz`` large and random).  The last section holds what these draws found, each as a
reproducer of its own."""
from __future__ import annotations

import json
import math
from typing import Any

import numpy as np
import pytest
from hypothesis import event, example, given, settings
from hypothesis import strategies as st

from cam_workbench.generators.errors import GeometryError, SpecError

from ..conftest import requires_ocp
from .conftest import examples
from .invariants import check_solid
from .test_indexer_combinations import (INDEXER_LAWS, NO_SHRINK, PEAK_ACCELERATION, _field_exists, _given,
                                        assert_clean, assert_refusal, assert_statuses, cli)

BODIES = ("barrel_indexer", "globoidal_indexer")
#: [machining] settings the 4-axis program refuses (exporters/machining_spatial_indexer.py's docstring)
REFUSED_MACHINING = (("program", "xc"), ("depth", 10.0), ("lead_radius", 3.0), ("milling", "conventional"),
                     ("work_offset", "G55"), ("line_numbers", True), ("coolant", True), ("rotary_line", "axis"),
                     ("rotary_speed_rpm", 30.0), ("sample_period", 0.002))
#: fields an indexer refuses (another body's, the follower's own geometry, the features, the dynamics),
#: per body: (section, name, value)
FOREIGN = {
    "barrel_indexer": (("indexer", "tip_radius", 30.0), ("indexer", "cams", 2), ("indexer", "gap", 1.0),
                       ("indexer", "spacer_diameter", 10.0)),
    "globoidal_indexer": (("indexer", "pitch_radius", 60.0), ("indexer", "outer_radius", 40.0),
                          ("indexer", "cams", 3), ("indexer", "spacer_diameter", 10.0)),
    "both": (("follower", "offset", 5.0), ("follower", "pivot_distance", 100.0), ("follower", "arm_length", 40.0),
             ("follower", "kind", "flat"), ("cam", "hub_diameter", 200.0), ("cam", "keyway", "DIN6885"),
             ("units", None, "in")),
}
#: what an indexer derives (cam.base_radius: the root radius, the globoid's waist): a refusal may name
#: it only when the spec gives it
DERIVED = ("cam.base_radius",)


def _motion(draw: Any, n: int, law: str, beta: float) -> list[dict[str, Any]]:
    """One rise of 360/N over β with the leading dwell anywhere in the rest of the turn."""
    rest = 360.0 - beta
    split = draw(st.integers(0, 1000))
    motion: list[dict[str, Any]] = []
    if split > 0:
        motion.append({"kind": "dwell", "angle": rest * split / 1000.0})
    motion.append({"kind": "rise", "angle": beta, "lift": 360.0 / n, "law": law})
    if split < 1000:
        motion.append({"kind": "dwell", "angle": rest * (1000 - split) / 1000.0})
    return motion


def _barrel(draw: Any, n: int, near: bool) -> tuple[dict[str, Any], float, float, float]:
    """A barrel's [indexer] geometry, the roller radius, the cam's length, its core radius (mm).
    The example: N = 6, R_p 60, C 52 ≈ R_p·cos(π/N), r_r 12 = 0.4·R_p·sin(π/N), t 27–45, rib 25–40,
    length 80 ≈ 2·(R_p·sin(π/N) + r_r)."""
    spread = 0.4 if near else 1.0
    f = lambda lo, hi: draw(st.floats(1 - (1 - lo) * spread, 1 + (hi - 1) * spread))  # noqa: E731
    s = f(0.5, 2.5)
    rp = 60.0 * s * f(0.8, 1.25)
    c = rp * math.cos(math.pi / n) * f(0.85, 1.15)
    rr = rp * math.sin(math.pi / n) * 0.4 * (f(0.4, 2.1) if draw(st.integers(0, 11)) else 2.6)
    root = 25.0 * s * f(0.6, 1.4)
    t0 = root + 2.0 * s * (f(0.1, 2.0) if draw(st.integers(0, 15)) else -0.3)
    outer = root + 15.0 * s * f(0.4, 1.6)
    t1 = outer + 5.0 * s * (f(0.05, 2.0) if draw(st.integers(0, 15)) else -0.3)
    width = 2.0 * (rp * math.sin(math.pi / n) + rr) * f(0.6, 1.8) * 80.0 / 84.0
    ix = {"stations": n, "centre_distance": c, "pitch_radius": rp, "roller_start": t0, "roller_end": t1,
          "root_radius": root, "outer_radius": outer}
    return ix, rr, width, root


def _globoidal(draw: Any, n: int, near: bool) -> tuple[dict[str, Any], float, float, float]:
    """A globoid's [indexer] geometry, the roller radius, the cam's width, its core (waist) radius (mm).
    The example: N = 12, t 74–96, r_r 12 ≈ 0.63·t0·sin(π/N), tip 76 (t0 + 0.09 of the length), root 100
    ≈ 1.034·√(t1² + r_r²), C 150 = 1.5 × root, and W/2 = 28 inside the band that holds the dwell's two
    rollers' inner sides and leaves their outer sides out (t1·sin(T/2) − r_r·cos(T/2), t0·sin(T/2) +
    r_r·cos(T/2))."""
    spread = 0.4 if near else 1.0
    f = lambda lo, hi: draw(st.floats(1 - (1 - lo) * spread, 1 + (hi - 1) * spread))  # noqa: E731
    s = f(0.5, 2.0)
    t0 = 74.0 * s * f(0.7, 1.3)
    t1 = t0 + 22.0 * s * f(0.3, 1.5)
    rr = t0 * math.sin(math.pi / n) * 0.63 * (f(0.3, 1.35) if draw(st.integers(0, 11)) else 1.7)
    tip = t0 + (t1 - t0) * 0.09 * (f(0.0, 4.0) if draw(st.integers(0, 15)) else -0.5)
    root = math.hypot(t1, rr) * 1.034 * (f(0.975, 1.12) if draw(st.integers(0, 15)) else 0.96)
    c = root * 1.5 * (f(0.7, 1.35) if draw(st.integers(0, 15)) else 0.6)
    half = math.pi / n
    lo = t1 * math.sin(half) - rr * math.cos(half)
    hi = t0 * math.sin(half) + rr * math.cos(half)
    width = 2.0 * max(lo + (hi - lo) * draw(st.floats(-0.2, 2.0) if not near else st.floats(0.3, 0.9)), 1.0)
    ix = {"stations": n, "centre_distance": c, "roller_start": t0, "roller_end": t1, "tip_radius": tip,
          "root_radius": root}
    return ix, rr, width, c - root


@st.composite
def spatial_specs(draw: Any, body: str | None = None, near: bool = False) -> dict[str, Any]:
    """A barrel or globoidal indexer's spec dict (the TOML structure) over the documented options;
    ``near``: the geometry within about ±40 % of the example's proportions and no foreign or refused
    field (mostly buildable: for the solid and CLI tests)."""
    body = body or draw(st.sampled_from(BODIES))
    n = draw(st.integers(3, 16))
    beta = draw(st.floats(60.0, 300.0))
    law = draw(st.sampled_from(INDEXER_LAWS))
    ix, rr, width, core = (_barrel if body == "barrel_indexer" else _globoidal)(draw, n, near)
    bore = draw(st.sampled_from([0.0, 0.0, 0.3, 0.6] + ([] if near else [1.1]))) * 2 * max(core, 0.0)
    cam: dict[str, Any] = {"body": body, "thickness": width, "bore_diameter": bore,
                           "speed_rpm": draw(st.sampled_from([20.0, 60.0, 300.0]))}
    length = ix["roller_end"] - ix["roller_start"]
    if draw(st.integers(0, 7)) == 0:               # cam.base_radius is derived: given, it must agree
        cam["base_radius"] = core * (1.0 if near or draw(st.booleans()) else 1.1)
    if draw(st.booleans()):
        ix["max_pressure_angle"] = draw(st.floats(30.0, 85.0))
    if draw(st.booleans()):                        # the load: kg·mm², N·mm, N
        ix["output_inertia"] = draw(st.floats(1e3, 1e6))
        if draw(st.booleans()):
            ix["friction_torque"] = draw(st.floats(0.0, 5000.0))
        if draw(st.booleans()):
            ix["roller_rating"] = draw(st.floats(2e3, 5e4))
        if draw(st.booleans()):
            ix["efficiency"] = draw(st.floats(0.5, 1.0))
        if draw(st.booleans()):
            ix["life_exponent"] = draw(st.sampled_from([3.0, 10.0 / 3.0, draw(st.floats(1.0, 10.0))]))
    follower: dict[str, Any] = {"kind": "roller", "roller_radius": rr}
    if draw(st.booleans()):
        follower["roller_width"] = length * draw(st.floats(0.5, 1.5))
    spec: dict[str, Any] = {"units": "mm", "cam": cam, "follower": follower,
                            "motion": _motion(draw, n, law, beta), "indexer": ix}
    if draw(st.booleans()):
        spec["material"] = {"allowable_stress": draw(st.floats(200.0, 3000.0))}
    if draw(st.integers(0, 3)) == 0:
        spec["checks"] = {"min_continuity": draw(st.integers(1, 3))}
    mc: dict[str, Any] = {}
    if draw(st.booleans()):
        mc["tool_radius"] = rr * draw(st.sampled_from([0.3, 0.6, 1.0] + ([] if near else [1.5])))
    if draw(st.booleans()):
        mc["feed_rate"] = draw(st.floats(50.0, 2000.0))
    if draw(st.booleans()):
        mc["chord_tolerance"] = draw(st.sampled_from([2e-3, 5e-3, 2e-2] + ([] if near else [5e-4, 2e-5])))
    if draw(st.integers(0, 3)) == 0:
        mc.update(passes=draw(st.sampled_from([1, 2, 3, 5])), safe_height=draw(st.sampled_from([2.0, 10.0])),
                  plunge_rate=draw(st.floats(20.0, 500.0)), spindle_rpm=draw(st.sampled_from([800.0, 6000.0])),
                  tool_number=draw(st.integers(1, 20)), contour=draw(st.sampled_from(["arcs", "lines"])),
                  milling="climb", work_offset="G54")
    if not near and draw(st.integers(0, 7)) == 0:  # one setting the program cannot honour: refused
        key, value = draw(st.sampled_from(REFUSED_MACHINING))
        mc[key] = value
    if mc:
        spec["machining"] = mc
    if not near and draw(st.integers(0, 9)) == 0:  # one field an indexer refuses
        section, name, value = draw(st.sampled_from(FOREIGN[body] + FOREIGN["both"]))
        if name is None:
            spec[section] = value
        else:
            spec.setdefault(section, {})[name] = value
    return spec


# ---- helpers --------------------------------------------------------------------------------------

def _refused_field(d: dict[str, Any], exc: Exception) -> str:
    """The field a clean refusal of ``d`` names, strictly: one the spec has, not one the indexer
    derives while ``d`` leaves it out (assert_refusal of the parallel indexer's tests)."""
    field = assert_refusal(d, exc, strict=True)
    assert field not in DERIVED or _given(d, field), (field, str(exc))
    return field


def design_api(d: dict[str, Any]) -> tuple[Any, str | None]:
    """(cam, None) for a spec the indexer designs, (None, refused field) for one it refuses; any
    other exception propagates (the defect)."""
    from cam_workbench import Cam

    try:
        return Cam(d), None
    except (SpecError, GeometryError) as exc:
        return None, _refused_field(d, exc)


def _law_turret(ix_spec: dict[str, Any], motion: list[dict[str, Any]], theta: np.ndarray) -> np.ndarray:
    """ψ(θ) [rad] from the spec alone (spatial.py's docstring: T·(m + F(u)), u over the rise)."""
    from cam_workbench.generators.motion.laws import evaluate_law

    n = ix_spec["stations"]
    start = 0.0
    for seg in motion:
        if seg["kind"] == "rise":
            break
        start += seg["angle"]
    rise = next(s for s in motion if s["kind"] == "rise")
    ts, beta = math.radians(start), math.radians(rise["angle"])
    rel = theta - ts
    m = np.floor(rel / (2 * math.pi))
    u = np.clip((rel - 2 * math.pi * m) / beta, 0.0, 1.0)
    return 2 * math.pi / n * (m + evaluate_law(rise["law"], u)[0])


def _roller_axis(d: dict[str, Any], theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(a, d, τ) of roller 0's axis c = a + t·d and the direction of its path at input angles θ, in
    the fixed frame, from the spec and spatial.py's docstring: α = π − T/2 + ψ, P = (C, 0, 0);
    barrel a = P + R_p·u(α), d = +y; globoidal a = P, d = u(α); u = (cos α, 0, sin α)."""
    ix = d["indexer"]
    n = ix["stations"]
    alpha = math.pi - math.pi / n + _law_turret(ix, d["motion"], theta)
    u = np.stack([np.cos(alpha), np.zeros_like(alpha), np.sin(alpha)], axis=-1)
    tau = np.stack([-np.sin(alpha), np.zeros_like(alpha), np.cos(alpha)], axis=-1)
    p = np.array([ix["centre_distance"], 0.0, 0.0])
    if d["cam"]["body"] == "barrel_indexer":
        return p + ix["pitch_radius"] * u, np.broadcast_to(np.array([0.0, 1.0, 0.0]), u.shape), tau
    return np.broadcast_to(p, u.shape), u, tau


def _rz(theta: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Rz(θ)·q (the cam frame → the fixed frame)."""
    c, s = np.cos(theta)[..., None], np.sin(theta)[..., None]
    return np.concatenate([c * q[..., :1] - s * q[..., 1:2], s * q[..., :1] + c * q[..., 1:2], q[..., 2:]], axis=-1)


def _band(d: dict[str, Any], q: np.ndarray, slack: float) -> np.ndarray:
    """Whether cam-frame points lie in the rib's extent grown by ``slack`` mm (spatial.py's docstring)."""
    ix, half = d["indexer"], 0.5 * d["cam"]["thickness"]
    rho = np.hypot(q[..., 0], q[..., 1])
    axial = np.abs(q[..., 2]) <= half + slack
    if d["cam"]["body"] == "barrel_indexer":
        return (rho >= ix["root_radius"] - slack) & (rho <= ix["outer_radius"] + slack) & axial
    g = np.hypot(ix["centre_distance"] - rho, q[..., 2])
    return (rho < ix["centre_distance"] + slack) & (g >= ix["tip_radius"] - slack) & (g <= ix["root_radius"] + slack) & axial


def assert_contacts_on_rollers(d: dict[str, Any], design: Any) -> float:
    """Every engaged flank point of ``design`` is on roller 0's surface at the law's turret angle
    (axis placed here from the spec), within its working length, the normal square to the axis and
    to the axis point's motion relative to the cam (the meshing equation, by central differences),
    its side the documented one (n·τ ≥ 0 on side +1), in the rib's extent; the pressure angles are
    arccos|n·τ|.  Returns the largest pressure angle of an engaged contact [deg]."""
    g = design.geometry
    ix = d["indexer"]
    rr = d["follower"]["roller_radius"]
    t0, t1 = ix["roller_start"], ix["roller_end"]
    worst_pa = 0.0
    h = 1e-6
    for sheet in g.sheets:
        band = sheet.in_band
        rows = np.nonzero(band.any(axis=1))[0]
        if rows.size == 0:
            continue
        tau_in = sheet.tau[rows]
        q = sheet.points[rows]                                     # (R, K, 3) cam frame
        a, ax_d, path = _roller_axis(d, tau_in)
        s = _rz(tau_in[:, None], q)                               # fixed frame
        rel = s - a[:, None, :]
        t = np.einsum("rki,ri->rk", rel, ax_d)
        radial = rel - t[..., None] * ax_d[:, None, :]
        dist = np.linalg.norm(radial, axis=-1)
        on = band[rows]
        assert np.max(np.abs(dist - rr)[on]) <= 1e-7 * max(1.0, rr), ("off the roller", np.max(np.abs(dist - rr)[on]))
        assert np.all((t[on] >= t0 - 1e-7) & (t[on] <= t1 + 1e-7)), "beyond the roller's working length"
        n = radial / dist[..., None]
        # the side: n·τ ≥ 0 on side +1 (facing roller j + 1), ≤ 0 on side −1
        cos_drive = np.einsum("rki,ri->rk", n, path)
        assert np.all(sheet.side * cos_drive[on] >= -1e-9), "a contact on the wrong side of its roller"
        # the meshing equation: the axis point's velocity relative to the cam ⟂ n (central differences)
        def cam_axis_point(th: np.ndarray) -> np.ndarray:
            aa, dd, _ = _roller_axis(d, th)
            c = aa[:, None, :] + t[..., None] * dd[:, None, :]
            return _rz(-th[:, None], c)

        v = (cam_axis_point(tau_in + h) - cam_axis_point(tau_in - h)) / (2 * h)
        n_cam = _rz(-tau_in[:, None], n)
        resid = np.abs(np.einsum("rki,rki->rk", n_cam, v)) / np.maximum(np.linalg.norm(v, axis=-1), 1e-12)
        assert np.max(resid[on]) <= 1e-5, ("meshing residual |n·v|/|v|", float(np.max(resid[on])))
        # the extent: the design's engaged points are in the band (within 1e-7 mm), and the band's
        # points are its (at least 1e-7 mm inside)
        assert np.all(_band(d, q[on], 1e-7)), "an engaged point outside the rib's extent"
        assert np.all(on[_band(d, q, -1e-7)]), "a point inside the rib's extent not counted engaged"
        # compared as cosines (arccos is ill-conditioned near 0°)
        assert np.max(np.abs(np.abs(cos_drive) - np.cos(sheet.pressure_angle[rows]))[on]) <= 1e-9
        pa = np.degrees(np.arccos(np.clip(np.abs(cos_drive), 0.0, 1.0)))
        worst_pa = max(worst_pa, float(np.max(pa[on])))
    return worst_pa


def _locking(design: Any) -> float:
    """The fewest engaged roller sides holding the turret each way over the turn, counted from the
    sheets' engaged points (the row of roller j at θ_i is (j − j_lo)·(S − 1) + i)."""
    g = design.geometry
    s, n = g.theta.size, len(g.rollers)
    rows = np.arange(n)[:, None] * (s - 1) + np.arange(s)[None, :]
    counts = [sheet.in_band.any(axis=1)[rows].sum(axis=0) for sheet in g.sheets]
    return float(np.min(np.minimum(*counts)))


def assert_design(d: dict[str, Any], cam: Any) -> dict[str, Any]:
    """The invariants of a designed spatial indexer (no solid): its checks, the contacts on the rollers,
    the locking count, the derived size, the drive; returns the design's summary."""
    from cam_workbench.generators.spec.indexer import indexer_size

    ix = d["indexer"]
    summary = cam.design.summary()
    checks = summary["checks"]
    assert cam.checks() == checks
    assert_statuses(checks)
    res = checks["results"]
    assert ("contact_stress" in res) == bool(ix.get("output_inertia")), sorted(res)
    assert res["pressure_angle"]["limit"] == ix.get("max_pressure_angle", 60.0)
    for name in ("pressure_angle", "pressure_angle_contacts", "undercut", "rib_thickness", "locking"):
        assert math.isfinite(res[name]["value"]), (name, res[name])
    # the design refuses what is not a cam: these hold on every design it makes
    assert res["undercut"]["value"] > 0 and res["rib_thickness"]["value"] > 0 and res["locking"]["value"] >= 1
    assert res["pressure_angle"]["value"] <= res["pressure_angle_contacts"]["value"] + 1e-9
    worst = assert_contacts_on_rollers(d, cam.design)
    assert abs(worst - res["pressure_angle_contacts"]["value"]) <= 1e-4, (worst, res["pressure_angle_contacts"])
    assert _locking(cam.design) == res["locking"]["value"]
    assert math.isclose(cam.spec.cam.base_radius, indexer_size(d["cam"]["body"], ix), rel_tol=1e-12)
    rec = summary["indexer"]["motion_from_geometry"]
    assert rec["max_error_rad"] <= 1e-6, rec
    drive = summary["indexer"]["drive"]
    if not ix.get("output_inertia"):
        assert drive is None
    else:
        rise = next(s for s in d["motion"] if s["kind"] == "rise")
        t_i = rise["angle"] / 360.0 * 60.0 / d["cam"]["speed_rpm"]
        assert math.isclose(drive["index_time_s"], t_i, rel_tol=1e-9), (drive["index_time_s"], t_i)
        c_a = drive["characteristics"]["C_a"]
        assert math.isclose(c_a, PEAK_ACCELERATION[rise["law"]], rel_tol=1e-9), (rise["law"], c_a)
        expect = c_a * (2 * math.pi / ix["stations"]) / t_i ** 2
        assert math.isclose(drive["output_acceleration_peak_rad_s2"], expect, rel_tol=1e-9)
        assert ("l10_million_rev" in drive) == ("roller_rating" in ix)
        stress = res["contact_stress"]
        assert stress["limit"] == d.get("material", {}).get("allowable_stress"), stress
        assert math.isfinite(stress["value"]) and stress["value"] > 0, stress
    fit = summary["body"]["flank_fit_error"]
    assert fit["unit"] == "mm" and 0 <= fit["value"] <= 1e-3, fit
    return summary


def assert_machining(d: dict[str, Any], mach: dict[str, Any]) -> None:
    """report.json's ``machining`` of the 4-axis program against the spec's [machining]."""
    mc, rr = d.get("machining", {}), d["follower"]["roller_radius"]
    tool = mc.get("tool_radius", rr)
    assert math.isclose(mach["tool_radius"], tool, rel_tol=1e-12), (mach["tool_radius"], tool)
    assert math.isclose(mach["roller_radius"], rr, rel_tol=1e-12)
    assert math.isclose(mach["feed_rate"], mc.get("feed_rate", 150.0), rel_tol=1e-12)
    assert math.isclose(mach["chord_tolerance"], mc.get("chord_tolerance", 0.005), rel_tol=1e-12)
    if mc.get("passes", 1) > 1:
        assert mach["passes"] == mc["passes"], (mach["passes"], mc["passes"])
    err = mach["path_error"]
    assert 0 <= err["value"] <= err["limit"] <= err["tolerance"], err


def _example_with(name: str, **changes: Any) -> dict[str, Any]:
    """The example ``name`` ("barrel_indexer", "globoidal_indexer") with ``section__field=value`` changes."""
    from cam_workbench.generators.spec.examples import example_dict

    d = example_dict(name)
    for path, value in changes.items():
        section, field = path.split("__")
        d[section][field] = value
    return d


#: what the draws below found (reproducers of their own at the end of the module): specs Cam(d) once designed while no report could be made of them (design.summary()'s volume raised
#: RuntimeError from generators/bodies/indexing/spatial_volume.py, and OCCT's solid failed with a
#: GeometryError naming no field): each now refused by the design, naming the field to change
RIB_REFUSED = {
    # a barrel whose rib is 0.10 mm thin between large rollers (r_r = 0.8·R_p·sin(π/N)): continued
    # below the rollers to the root along its normal it closes up ("the flanks' crossings do not
    # alternate (r = 21.4958 mm, φ = 0.25°)"; OCCT: "a piece of the band touches no flank face");
    # r_r = 8 mm builds (rib 1.54 mm)
    "barrel_rib_closes_below_rollers": (
        {"units": "mm", "cam": {"body": "barrel_indexer", "thickness": 52.55997653215574, "bore_diameter": 0.0,
                                "speed_rpm": 300.0},
         "follower": {"kind": "roller", "roller_radius": 11.466586477825352},
         "motion": [{"kind": "dwell", "angle": 73.08}, {"kind": "rise", "angle": 180.0, "lift": 45.0, "law": "poly345"},
                    {"kind": "dwell", "angle": 106.92}],
         "indexer": {"stations": 8, "centre_distance": 31.967602341261145, "pitch_radius": 37.45435579191818,
                     "roller_start": 23.939375379969928, "roller_end": 38.26291967374888,
                     "root_radius": 21.4506365440782, "outer_radius": 33.02242923620813}},
        "follower.roller_radius"),
    # a globoid whose width is the catalogue's least, W/2 = t1·sin(π/N) − r_r·cos(π/N): the dwell
    # rollers' inner sides leave the end faces at their outer ends, and beyond them no flank crosses
    # the band ("no flank crosses the column r = 150.735 mm, φ = 0.25°"); W/2 at 0.3 of the way to
    # t0·sin(π/N) + r_r·cos(π/N) builds
    "globoid_width_at_least": (
        {"units": "mm", "cam": {"body": "globoidal_indexer", "thickness": 101.79902710775836, "bore_diameter": 0.0,
                                "speed_rpm": 60.0},
         "follower": {"kind": "roller", "roller_radius": 15.651308978024783},
         "motion": [{"kind": "dwell", "angle": 61.3607329147463},
                    {"kind": "rise", "angle": 226.89645788558286, "lift": 360.0 / 7, "law": "modified_trapezoid"},
                    {"kind": "dwell", "angle": 71.74280919967084}],
         "indexer": {"stations": 7, "centre_distance": 165.78815363507454, "roller_start": 113.17773764824338,
                     "roller_end": 149.81168876529287, "tip_radius": 113.19422292624606,
                     "root_radius": 157.89347965245196}},
        "cam.thickness"),
    # a globoid wider than its tip globoid's diameter: cam_volume's ValueError ("the globoid's half
    # width must be below its tip radius"); now the spec rule cam.thickness < 2·indexer.tip_radius
    "globoid_wider_than_tip": (_example_with("globoidal_indexer", cam__thickness=160.0), "cam.thickness"),
}


# ---- the Python API: the design (cheap) -------------------------------------------------------------

@settings(max_examples=examples(20, 1500), phases=NO_SHRINK)
@given(spatial_specs())
@example(d=RIB_REFUSED["barrel_rib_closes_below_rollers"][0])
@example(d=RIB_REFUSED["globoid_width_at_least"][0])
def test_spatial_refusals_name_the_spec_field(d):
    """Cam(d) designs the indexer, or refuses it naming the field the user changes: a field of the
    spec (``follower.roller_radius``, ``cam.thickness``, ``motion[i].angle`` — not the geometry's own
    ``indexer.roller_radius``, ``indexer.cam_width``, ``indexer.index_angle``), never one the indexer
    derives and the spec leaves out (``cam.base_radius``).  The design only (no solid): many draws."""
    cam, refused = design_api(d)
    if refused is not None:
        event(f"refused: {refused}")
        return
    event(f"{d['cam']['body']}: designed")
    checks = cam.checks()
    assert_statuses(checks)


@settings(max_examples=examples(8, 400), phases=NO_SHRINK)
@given(spatial_specs())
def test_spatial_design_any_valid_spec(d):
    """A designed indexer's numbers agree with each other and with geometry placed here: the engaged
    contact lines on roller 0 at the law's turret angle (meshing, sides, extent, pressure angles), the
    locking count from the engaged sheets, the turret angle recovered from the flanks, the drive's
    peak acceleration C_a·(2π/N)/t_i²; its report without the solid (the 4-axis program, the drawing)
    agrees with [machining] — or a clean refusal naming the field."""
    from cam_workbench.pipeline import run_pipeline

    cam, refused = design_api(d)
    if refused is not None:
        event(f"refused: {refused}")
        return
    assert_design(d, cam)
    try:
        out = run_pipeline(cam.spec, solid=False, design=cam.design)
    except (SpecError, GeometryError) as exc:        # the program's and the drawing's refusals
        event(f"refused (program/drawing): {_refused_field(d, exc)}")
        return
    event(f"{d['cam']['body']}: checks " + ("pass" if out.summary["checks"]["passed"] else "fail"))
    assert out.summary["interpolator"] is None
    assert_machining(d, out.summary["machining"])
    assert out.machining.gcode.count("\n") == out.summary["machining"]["gcode_lines"]


# ---- the Python API: the solid (seconds each) -------------------------------------------------------

@requires_ocp
@settings(max_examples=examples(2, 60), phases=NO_SHRINK)
@given(spatial_specs(near=True))
def test_spatial_api_solid(d):
    """cam.report(): one valid OCCT solid whose volume is the report's (the grid integral of the exact
    envelope) within the error the report states, the checks the design's — or a refusal naming a spec
    field (a GeometryError of the kernel naming none is the defect)."""
    from cam_workbench.kernel.solids import SURFACE_VOLUME_EPS, kernel_volume

    cam, refused = design_api(d)
    if refused is not None:
        event(f"refused: {refused}")
        return
    try:
        report = cam.report()
    except (SpecError, GeometryError) as exc:
        event(f"refused (stage): {_refused_field(d, exc)}")
        return
    event(f"{d['cam']['body']}: built")
    assert report["checks"] == cam.checks()
    assert report["solid"]["valid"] and report["solid"]["solids"] == 1
    check_solid(cam.shape)
    # OCCT's adaptive rule (its fixed rule is ~1e-3 off on these faces) against the grid integral, allowed
    # the integral's error, the flank surfaces' fit error over a bound of their area (two flanks, each
    # at most the band's depth times twice its circumference) and the adaptive rule's ε per face
    vol = report["body"]["volume"]
    kv = kernel_volume(cam.shape, SURFACE_VOLUME_EPS)
    ix = d["indexer"]
    barrel = d["cam"]["body"] == "barrel_indexer"
    depth = ix["outer_radius"] - ix["root_radius"] if barrel else ix["root_radius"] - ix["tip_radius"]
    reach = ix["outer_radius"] if barrel else ix["centre_distance"] - ix["tip_radius"]
    area = 2 * depth * 2 * math.pi * reach * 2
    allowed = 2 * vol["error"] + area * report["body"]["flank_fit_error"]["value"] + 4 * SURFACE_VOLUME_EPS * kv
    assert abs(kv - report["volume"]) <= allowed, (kv, report["volume"], allowed)
    assert_machining(d, report["machining"])


# ---- the command line ------------------------------------------------------------------------------

@requires_ocp
@settings(max_examples=examples(1, 40), phases=NO_SHRINK)
@given(spatial_specs(near=True))
@example(d=_example_with("globoidal_indexer", cam__bore_diameter=0.0))
def test_spatial_cli_build_and_check(tmp_path_factory, d):
    """``build`` and ``check`` on the spec dict written as TOML (docs/cli.md): a spec the API designs
    builds (exit 0: cam.step, cam.dxf, cam.nc, report.json, report.html; report.json's checks the API's)
    and checks (exit 0, or 3 when a check fails, as the verdict says); a spec the API refuses exits 2
    naming the same field in one line, and nothing is written."""
    from cam_workbench.generators.spec.toml_io import dict_to_toml

    tmp = tmp_path_factory.mktemp("spatial_cli")
    (tmp / "ix.toml").write_text(dict_to_toml(d), encoding="utf-8")
    cam, refused = design_api(d)
    b = cli("build", str(tmp / "ix.toml"), "-o", str(tmp / "build"))
    b_line = assert_clean(b, (0, 2))
    c = cli("check", str(tmp / "ix.toml"), "-o", str(tmp / "check"))
    c_line = assert_clean(c, (0, 2, 3))
    if refused is None and b.returncode == 2:         # a later stage's refusal: the API's is the same
        try:
            cam.report()
        except (SpecError, GeometryError) as exc:
            refused = _refused_field(d, exc)
        assert refused is not None, ("build refused what the API builds", b_line)
    if refused is not None:
        event(f"refused: {refused}")
        assert b.returncode == 2 and not (tmp / "build").exists(), (b.returncode, b.stdout[-2000:])
        assert refused in b_line, (refused, b_line)
        if cam is None:
            assert c.returncode == 2 and not (tmp / "check").exists(), (c.returncode, c.stdout[-2000:])
            assert refused in c_line, (refused, c_line)
        else:
            assert c.returncode in (0, 3), c.stderr
        return
    api = json.loads(json.dumps(cam.checks()))
    event(f"{d['cam']['body']}: built, checks " + ("pass" if api["passed"] else "fail"))
    names = {p.name for p in (tmp / "build").iterdir()}
    assert {"cam.step", "cam.dxf", "cam.nc", "report.json", "report.html"} <= names, names
    built = json.loads((tmp / "build" / "report.json").read_text(encoding="utf-8"))
    checked = json.loads((tmp / "check" / "report.json").read_text(encoding="utf-8"))
    assert built["checks"] == api and checked["checks"] == api
    assert c.returncode == (0 if api["passed"] else 3), (c.returncode, api["failed"])
    assert built["files"]["gcode"] == "cam.nc"
    assert_machining(d, built["machining"])


# ---- what the draws above found: each reproducer on its own ---------------------------------------

@pytest.mark.parametrize("name", sorted(RIB_REFUSED))
def test_spatial_rib_refused_naming_the_field(name):
    """Each spec above is refused by Cam(d) with a SpecError naming the field (no RuntimeError later)."""
    from cam_workbench import Cam

    d, field = RIB_REFUSED[name]
    with pytest.raises(SpecError) as info:
        Cam(d)
    assert info.value.field == field, str(info.value)
    assert _field_exists(info.value.field) and "\n" not in str(info.value)


#: a globoid whose root globoid reaches past the cam axis (C − root_radius ≤ 0) is refused naming
#: indexer.root_radius (it once said "cam.base_radius: is required", a field the indexer derives)
def test_globoid_root_beyond_centre_distance_names_root_radius():
    from cam_workbench import Cam

    d = _example_with("globoidal_indexer", indexer__root_radius=160.0)     # C = 150
    with pytest.raises(SpecError) as info:
        Cam(d)
    assert info.value.field == "indexer.root_radius", str(info.value)

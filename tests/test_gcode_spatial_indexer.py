"""The spatial indexers' generating programs (exporters.gcode_spatial_indexer) run through LinuxCNC's
own interpreter ``rs274`` (tests/rs274.py), and the canonical motions it prints — X, Y, Z and the
rotary A, C — turned back into the cutter's pose relative to the cam with the machine mapping of
the exporter's docstring, written again here:

* the program's origin is the STEP solid's (the cam spans 0 ≤ X ≤ W, W = ``cam_width`` =
  ``cam.thickness``), the design's frame of spatial.py is centred on the cam's middle plane: fixed
  frame (x, y, z) = machine (Y, Z, X − W/2) (X along the cam axis, Z up along the turret axis);
* the cam turned by θ = A [deg → rad] about the cam axis: a fixed-frame point p is the cam-frame
  point Rz(−θ)·p;
* X, Y, Z the tool tip; the tool's axis along d(C): barrel +y, globoidal u(α) = (cos α, 0, sin α)
  with α = π − T/2 + C (C = the turret angle, rad), T = 2π/N;
* the cutter's axis point at parameter t is tip + (t − t_k)·d, t_k the tip's parameter (the depth
  level).

and held to the exact roller axis of spatial.py at the same input angle: the input angle θ = A
reduced to one turn, θ = A − 2πj with j = ⌊(A − θ_s)/2π⌋, and roller j (roller j at θ has roller 0's
pose at θ + 2πj): ``roller_axis(ix, j, θ)``.  The moves are followed as LinuxCNC (trivkins)
interpolates them, every word linear along the move."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from cam_workbench.exporters.gcode_spatial_indexer import spatial_program, write_spatial_program
from cam_workbench.generators.bodies.indexing.spatial import (BarrelIndexer, GloboidalIndexer, design_barrel,
                                                             design_globoidal, roller_axis, turret_angle)
from cam_workbench.generators.errors import SpecError

from .rs274 import requires_rs274, run_rs274

pytestmark = requires_rs274

TOL = 5e-3
BLEND = 0.1                    # share of the tolerance left to G64 P
QUANTUM_DEG = 0.5e-4           # half a unit of the 4th decimal, deg (rs274 prints 4 decimals)
CASES = {"barrel": (design_barrel, BarrelIndexer), "globoidal": (design_globoidal, GloboidalIndexer),
         # conical rollers, the apex on the turret axis: the tapered cutter follows the same axis path
         "globoidal_cone": (design_globoidal, lambda: GloboidalIndexer(roller_cone_angle=math.atan(12.0 / 85.0)))}
_CALL = re.compile(r"^\s*\d+\s+N\S*\s+([A-Z_0-9]+)\((.*)\)\s*$")


# ---- rs274's output, all six coordinates -----------------------------------------------------------
class Move:
    def __init__(self, kind, start, end, tag):
        self.kind, self.start, self.end, self.tag = kind, start, end, tag


def interpreted(stdout):
    """Canonical STRAIGHT_TRAVERSE / STRAIGHT_FEED (x, y, z, a, b, c) with the last program comment."""
    moves, pos, tag = [], np.zeros(6), ""
    for line in stdout.splitlines():
        m = _CALL.match(line)
        if not m:
            continue
        name, args = m.groups()
        if name == "COMMENT":
            text = args.strip().strip('"')
            if not text.startswith("interpreter:") and not text.startswith("  "):
                tag = text
        elif name in ("STRAIGHT_FEED", "STRAIGHT_TRAVERSE"):
            end = np.array([float(v) for v in args.split(",")])
            moves.append(Move("feed" if name == "STRAIGHT_FEED" else "rapid", pos, end, tag))
            pos = end
    return moves


# ---- the mapping, written again ------------------------------------------------------------------
def is_barrel(ix):
    return isinstance(ix, BarrelIndexer)


def fixed_tip(ix, w):
    """The tool tip in the design's fixed frame (centred on the cam's middle plane) for machine words
    w (..., ≥ 3) = X Y Z …: (x, y, z) = (Y, Z, X − W/2), the program's X0 being the STEP solid's z = 0."""
    w = np.asarray(w, dtype=float)
    return np.stack([w[..., 1], w[..., 2], w[..., 0] - 0.5 * ix.cam_width], axis=-1)


def tool_direction(ix, c_deg):
    """d(C) in the fixed frame."""
    alpha = math.pi - math.pi / ix.stations + np.radians(c_deg)
    if is_barrel(ix):
        return np.broadcast_to(np.array([0.0, 1.0, 0.0]), np.shape(alpha) + (3,))
    return np.stack([np.cos(alpha), np.zeros_like(alpha), np.sin(alpha)], axis=-1)


def rz_minus(theta, p):
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([c * p[..., 0] + s * p[..., 1], -s * p[..., 0] + c * p[..., 1], p[..., 2]], axis=-1)


def cutter_points(ix, w, tip_t, t):
    """Cam-frame points of the cutter's axis at parameters t (K,) for words w (..., 6) = x y z a b c."""
    tip = fixed_tip(ix, w)
    d = tool_direction(ix, w[..., 5])
    p = tip[..., None, :] + (np.asarray(t) - tip_t)[:, None] * d[..., None, :]
    return rz_minus(np.radians(w[..., 3])[..., None], p)


def reduced(ix, a_deg):
    """(roller j, input angle θ in θ_s + [0, 2π)) of machine A."""
    tau = np.radians(a_deg)
    j = np.floor((tau - ix.index_start) / (2 * math.pi))
    return j, tau - 2 * math.pi * j


def roller_points(ix, a_deg, t):
    """Cam-frame points of the exact roller axis (roller j at θ) at parameters t (K,)."""
    j, theta = reduced(ix, np.asarray(a_deg, dtype=float))
    ax = roller_axis(ix, j, theta)
    p = ax.a[..., None, :] + np.asarray(t)[:, None] * ax.d[..., None, :]
    return rz_minus(theta[..., None], p), ax


def tip_parameter(ix, w):
    """The tool tip's parameter along the exact roller axis, and its distance from that line."""
    _, ax = roller_points(ix, w[..., 3], np.zeros(1))
    tip = fixed_tip(ix, w)
    q = tip - ax.a
    s = np.einsum("...i,...i->...", q, ax.d)
    return s, np.linalg.norm(q - s[..., None] * ax.d, axis=-1)


def reach(ix, rt):
    if is_barrel(ix):
        final, top = ix.root_radius, ix.outer_radius
    else:
        final, top = math.sqrt(ix.root_radius ** 2 - rt ** 2), math.sqrt(ix.tip_radius ** 2 - rt ** 2)
    return min(ix.roller_start, final, top), max(ix.roller_end, final, top), final, top


def in_blank(ix, q):
    """The cam's blank (the rib's band without its root): barrel ρ ≤ R_top, globoidal g ≥ R_tip, |z| ≤ W/2."""
    rho = np.hypot(q[..., 0], q[..., 1])
    inside = np.abs(q[..., 2]) <= ix.cam_width / 2
    if is_barrel(ix):
        return inside & (rho <= ix.outer_radius)
    g = np.hypot(ix.centre_distance - rho, q[..., 2])
    return inside & (rho < ix.centre_distance) & (g >= ix.tip_radius)


def cutter_solid_points(ix, w, tip_t, rt, length=60.0):
    """Points filling the cutter (radius rt, from its tip back ``length`` mm towards its spindle)."""
    d = tool_direction(ix, w[5])
    e1 = np.cross(d, [0.0, 0.0, 1.0]) if not is_barrel(ix) else np.array([1.0, 0.0, 0.0])
    e1 = e1 / np.linalg.norm(e1)
    e2 = np.cross(d, e1)
    tip = fixed_tip(ix, w)
    back = -1.0 if not is_barrel(ix) else 1.0                   # spindle side: barrel +d, globoidal −d
    s, r, phi = np.meshgrid(np.linspace(0.0, length, 241), np.linspace(0.0, rt, 7),
                            np.linspace(0.0, 2 * math.pi, 96, endpoint=False), indexing="ij")
    p = (tip + back * s[..., None] * d + (r * np.cos(phi))[..., None] * e1 + (r * np.sin(phi))[..., None] * e2)
    return rz_minus(math.radians(w[3]), p.reshape(-1, 3))


def header(text):
    """The leading comments, continuation lines joined."""
    out = []
    for line in text.splitlines()[1:]:
        if not line.startswith("("):
            break
        body = line[1:-1]
        if body.startswith("  ") and out:
            out[-1] += " " + body.strip()
        else:
            out.append(body)
    return out


# ---- the programs ----------------------------------------------------------------------------------
@pytest.fixture(scope="module", params=sorted(CASES))
def cut(request, tmp_path_factory):
    make, kind = CASES[request.param]
    d = make(kind(), samples=181, lengths=5)
    p = spatial_program(d, tolerance=TOL)
    run = run_rs274(p.text, tmp_path_factory.mktemp(request.param), 1, 2 * d.indexer.roller_radius)
    return request.param, d, p, run


def sweep_moves(moves):
    return [m for m in moves if m.kind == "feed" and m.start[3] != m.end[3]]


def test_every_line_is_interpreted(cut):
    name, d, p, run = cut
    assert run.units == "mm"
    blocks = [line for line in p.text.splitlines() if line[:3] in ("G0 ", "G1 ")]
    moves = interpreted(run.stdout)
    assert len(moves) == len(blocks) and len(blocks) > 1000
    assert sum(m.kind == "feed" for m in moves) == sum(b.startswith("G1 ") for b in blocks)
    comments = [line for line in p.text.splitlines() if line.startswith("(")]
    assert sum(1 for c, _ in run.calls if c == "COMMENT") >= len(comments)
    assert max(len(line) for line in p.text.splitlines()) <= 255          # LinuxCNC's line length
    for word in ("G21", "G90", "G94", "G93", "T1 M6", "M3", "M5", "M2"):
        assert re.search(rf"(^|\s){word}(\s|$)", p.text, re.M), word
    assert ("G43 H1" in p.text) == (name == "barrel")
    assert all(abs(m.end[4]) == 0 for m in moves)                          # no B word
    assert p.lines == p.text.count("\n")


def test_the_cutter_follows_the_roller_axis_relative_to_the_cam(cut):
    """At every interpreted point and in between (the words interpolated linearly as LinuxCNC
    does), the cutter's axis — rebuilt from X Y Z A C with the docstring's mapping — is within the
    tolerance of the exact roller axis at θ = A, over the axis' reach; the turret angle C = ψ(θ)
    + j·T to the printed digits; the error is the one the program returns and its header quotes."""
    name, d, p, run = cut
    ix = d.indexer
    rt = ix.roller_radius
    t_lo, t_hi, final, top = reach(ix, rt)
    assert p.reach == pytest.approx((t_lo, t_hi), abs=1e-12)
    moves = sweep_moves(interpreted(run.stdout))
    assert len(moves) == p.moves
    start = np.array([m.start for m in moves])
    end = np.array([m.end for m in moves])
    # the depth level of each move: the tip's parameter along the exact axis, on the axis
    s0, off0 = tip_parameter(ix, start)
    s1, off1 = tip_parameter(ix, end)
    assert max(off0.max(), off1.max()) <= 2e-4                             # the tip on the roller's axis
    levels = np.array(p.levels)
    k = np.argmin(np.abs(s1[:, None] - levels[None, :]), axis=1)
    assert np.abs(s0 - levels[k]).max() <= 2e-4 and np.abs(s1 - levels[k]).max() <= 2e-4
    assert sorted(set(k.tolist())) == list(range(levels.size))              # every level swept
    tip_t = levels[k]
    t = np.array([t_lo, t_hi])

    def errors(n, shift_a=0.0, c_sign=1.0):
        """Per move: the largest distance, at λ = k/n, between the cutter's axis points (words
        interpolated linearly; A shifted by ``shift_a``, C's sense ``c_sign``) and the roller's."""
        lam = np.linspace(0.0, 1.0, n + 1)
        w = start[:, None, :] + lam[None, :, None] * (end - start)[:, None, :]
        want, _ = roller_points(ix, w[..., 3], t)
        w = w.copy()
        w[..., 3] += shift_a
        w[..., 5] *= c_sign
        tip = fixed_tip(ix, w)
        got = tip[..., None, :] + (t[None, None, :] - tip_t[:, None, None])[..., None] \
            * tool_direction(ix, w[..., 5])[..., None, :]
        got = rz_minus(np.radians(w[..., 3])[..., None], got)
        return np.linalg.norm(got - want, axis=-1).max(axis=(1, 2))

    e16 = errors(16)
    assert e16.max() <= (1 - BLEND) * TOL
    assert e16.max() == pytest.approx(p.chord_error, abs=1e-6)
    e64 = errors(64)
    assert e64.max() <= TOL and e64.max() <= 1.01 * (1 - BLEND) * TOL
    assert errors(1).max() <= 3e-4                                        # the interpreted points: rounding
    # the check has teeth: the cam a hundredth of a degree off, or (globoidal) C turning the other way
    assert errors(2, shift_a=0.01).max() > TOL
    if name == "globoidal":
        assert errors(2, c_sign=-1.0).max() > TOL
    # the turret angle at every interpreted point: C = ψ(θ) + j·T to the printed digits
    pts = np.array([m.end for m in interpreted(run.stdout)])
    j, theta = reduced(ix, pts[:, 3])
    psi, _, _ = turret_angle(ix, theta)
    dc = np.radians(pts[:, 5]) - (psi + j * 2 * math.pi / ix.stations)
    assert np.abs(dc).max() <= math.radians(QUANTUM_DEG) + 1e-12
    assert np.abs(dc).max() <= 1e-6                                       # rad: 1e-6·R mm at radius R
    # the header quotes what the function returns
    head = " ".join(header(p.text))
    assert f"measured chord error {p.chord_error:.3g} mm" in head
    assert f"{p.moves} G1 moves in {len(p.sweeps)} sweeps" in head
    assert f"tolerance {TOL:g} mm" in head and f"limit {p.budget:.3g} mm" in head
    assert f"over t = {t_lo:.4f}-{t_hi:.4f} mm" in head
    assert "depth levels: tip at t = " + ", ".join(f"{v:.4f}" for v in p.levels) + " mm" in head
    if ix.roller_cone_angle == 0:
        assert f"radius {rt:g} mm = the roller's radius" in head
    else:
        # the tapered cutter: r(t) = r_r + (t − t_m)·tan γ, its tip at the final depth (here t_final = levels[-1])
        tip_r = rt + (p.levels[-1] - 85.0) * 12.0 / 85.0
        assert (f"tapered end mill, half angle {math.degrees(ix.roller_cone_angle):.6g} deg, radius {rt:g} mm at the "
                f"roller's middle t = 85 mm, {tip_r:.6g} mm at its tip at the final depth [the roller's cone]") in head
    assert f"A runs over {p.a_range[0]:.4f} to {p.a_range[1]:.4f}" in head
    assert f"C over {p.c_range[0]:.4f} to {p.c_range[1]:.4f}" in head
    assert all("not exact" in line for line in header(p.text) if "exact" in line.lower())
    assert pts[:, 3].min() == pytest.approx(p.a_range[0]) and pts[:, 3].max() == pytest.approx(p.a_range[1])


def test_depth_levels_finishing_sweeps_and_safety(cut):
    name, d, p, run = cut
    ix = d.indexer
    rt = ix.roller_radius
    _, _, final, top = reach(ix, rt)
    levels = np.array(p.levels)
    # from the rib's top to the final depth in equal steps of at most the stepdown (3 mm)
    assert levels[-1] == pytest.approx(final, abs=1e-12)
    steps = np.abs(np.diff(np.concatenate([[top], levels])))
    assert steps.max() <= 3.0 + 1e-9 and np.ptp(steps) < 1e-9
    moves = interpreted(run.stdout)
    tips = np.array([m.end for m in moves[1:]])
    # never below the root: barrel Z ≥ R_root; globoidal the cutter's corner within the root globoid
    if name == "barrel":
        assert tips[:, 2].min() >= ix.root_radius - 1e-4
    else:
        reach_p = np.hypot(tips[:, 1] - ix.centre_distance, tips[:, 0] - 0.5 * ix.cam_width)
        assert np.hypot(reach_p, rt).max() <= ix.root_radius + 1e-4
        assert np.abs(tips[:, 2]).max() == 0
    # the roughing sweeps are entered and left with the cutter clear of the blank (at the final depth)
    rough = [m for m in sweep_moves(moves) if m.tag.startswith("roughing")]
    for w in (rough[0].start, rough[-1].end):
        assert not in_blank(ix, cutter_solid_points(ix, w, final, rt)).any()
    # rapids: retracts along the tool's axis (A, C fixed) or moves between safe poses, where the
    # whole cutter is clear of the blank for any A (barrel: above it; the approach's first G0 Z too)
    rapids = [m for m in moves if m.kind == "rapid"]

    def safe(w):
        if name == "barrel":                      # the vertical tool's tip above the blank: anywhere
            assert w[2] == pytest.approx(p.safe_t, abs=1e-9) and p.safe_t > ix.outer_radius
        else:                                     # on the roller's axis, retracted towards the turret axis
            s0, off0 = tip_parameter(ix, w)
            assert off0 <= 2e-4 and s0 == pytest.approx(p.safe_t, abs=2e-4)
        for a in (0.0, 90.0, 180.0, 270.0):
            ww = w.copy()
            ww[3] = a
            assert not in_blank(ix, cutter_solid_points(ix, ww, p.safe_t, rt)).any()

    for m in rapids:
        safe(m.end)
        if m is rapids[0]:
            continue                              # from wherever the tool starts
        if m.start[3] == m.end[3] and m.start[5] == m.end[5]:
            _, off0 = tip_parameter(ix, m.start)
            _, off1 = tip_parameter(ix, m.end)
            assert max(off0, off1) <= 2e-4        # a retract along the tool's axis
        else:
            safe(m.start)
    # plunges: along the tool's axis at a fixed A and C
    plunges = [m for m in moves if m.kind == "feed" and m.start[3] == m.end[3]]
    assert len(plunges) == p.plunges >= len(p.levels)
    for m in plunges:
        assert m.start[5] == m.end[5]
        _, off0 = tip_parameter(ix, m.start)
        _, off1 = tip_parameter(ix, m.end)
        assert max(off0, off1) <= 2e-4
    # one finishing sweep per side, at the final depth, over every window in which that side is engaged
    fin = [s for s in p.sweeps if s.role == "finishing"]
    assert sorted(s.side for s in fin) == [-1, 1]
    for sw in fin:
        lo, hi = sorted((sw.a_from, sw.a_to))
        assert sw.tip_t == final
        for j, side, a, b in d.windows:
            if side == sw.side:
                assert lo <= math.degrees(a) + 360 * j and math.degrees(b) + 360 * j <= hi, (j, side)
        tagged = [m for m in sweep_moves(moves) if m.tag.startswith(f"finishing side {sw.side:+d}")]
        assert len(tagged) == sw.moves
        assert tagged[0].start[3] == pytest.approx(sw.a_from) and tagged[-1].end[3] == pytest.approx(sw.a_to)
        assert (tagged[-1].end[3] > tagged[0].start[3]) == sw.forward
        # climb milling with M3 for its side, recomputed here: the contact normal n (⟂ the axis and
        # the axis point's velocity w relative to the cam, on the side whose n·τ(α) has the side's
        # sign), the spindle → tip direction e, the sweep's velocity v = ±w: n·(e × v) > 0
        sheet = d.sheet(sw.side)
        rows = np.nonzero(sheet.in_band.any(axis=1))[0]
        tau = sheet.tau[rows]
        h = 1e-6
        c0, ax = roller_points(ix, np.degrees(tau), d.t)
        cp, _ = roller_points(ix, np.degrees(tau + h), d.t)
        cm, _ = roller_points(ix, np.degrees(tau - h), d.t)
        w_cam = (cp - cm) / (2 * h)
        c, s = np.cos(tau)[:, None], np.sin(tau)[:, None]                   # back to the fixed frame
        w = np.stack([c * w_cam[..., 0] - s * w_cam[..., 1], s * w_cam[..., 0] + c * w_cam[..., 1],
                      w_cam[..., 2]], axis=-1)
        dvec = np.broadcast_to(ax.d[:, None, :], w.shape)
        n = np.cross(dvec, w)
        n /= np.linalg.norm(n, axis=-1, keepdims=True)
        tau_dir = np.broadcast_to(ax.tau[:, None, :], w.shape)
        n *= np.sign(np.einsum("...i,...i->...", n, tau_dir) * sw.side)[..., None]
        e = -dvec if name == "barrel" else dvec
        v = w if sw.forward else -w
        climb = np.einsum("...i,...i->...", n, np.cross(e, v)) > 0
        share = np.count_nonzero(climb & sheet.in_band[rows]) / np.count_nonzero(sheet.in_band[rows])
        assert share == pytest.approx(sw.climb, abs=1e-9) and share > 0.99


def test_inverse_time_feeds(cut):
    """Every G1 of a sweep is timed so that the cutter's axis ends travel relative to the cam at the
    feed: F·(their longer cam-frame travel, measured here) = feed."""
    name, d, p, run = cut
    ix = d.indexer
    t_lo, t_hi, _, _ = reach(ix, ix.roller_radius)
    moves = interpreted(run.stdout)
    g1 = [line for line in p.text.splitlines() if line.startswith("G1 ")]
    feeds = [m for m in moves if m.kind == "feed"]
    assert len(g1) == len(feeds)
    lines = p.text.splitlines()
    first_g1 = next(i for i, line in enumerate(lines) if line.startswith("G1 "))
    last_g1 = max(i for i, line in enumerate(lines) if line.startswith("G1 "))
    assert lines.index("G93") < first_g1 and last_g1 < lines.index("G94", first_g1)     # G93 on every G1
    ratio = []
    for line, m in zip(g1, feeds):
        f = float(re.search(r"F(\S+)", line).group(1))
        if m.start[3] == m.end[3]:
            length = np.linalg.norm(m.end[:3] - m.start[:3])
            ratio.append(f * length / p.plunge_feed)
            continue
        s, _ = tip_parameter(ix, m.end)
        lam = np.linspace(0.0, 1.0, 17)
        w = m.start + lam[:, None] * (m.end - m.start)
        pts = cutter_points(ix, w, float(s), np.array([t_lo, t_hi]))
        travel = np.linalg.norm(np.diff(pts, axis=0), axis=-1).sum(axis=0).max()
        ratio.append(f * travel / p.feed)
    assert np.abs(np.array(ratio) - 1.0).max() < 2e-3


def test_refinement_other_tools_and_refusals(tmp_path):
    """A coarse start step is refined until the moves are within the tolerance (measured here
    again through rs274); a smaller cutter leaves stock and reaches the globoid's root at its own
    corner; a larger one and a too fine tolerance are refused."""
    d = design_globoidal(GloboidalIndexer(), samples=181, lengths=5)
    ix = d.indexer
    p = spatial_program(d, tolerance=2e-3, step_deg=6.0, passes=1)
    assert p.step_deg[0] < 6.0 / 2 and p.step_deg[1] <= 6.0
    assert p.chord_error <= 0.9 * 2e-3 and len(p.levels) == 1
    run = run_rs274(p.text, tmp_path, 1, 24.0)
    moves = sweep_moves(interpreted(run.stdout))
    start, end = np.array([m.start for m in moves]), np.array([m.end for m in moves])
    lam = np.linspace(0, 1, 33)
    w = start[:, None, :] + lam[None, :, None] * (end - start)[:, None, :]
    t = np.array(p.reach)
    got = cutter_points(ix, w, p.levels[0], t)
    want, _ = roller_points(ix, w[..., 3], t)
    assert np.linalg.norm(got - want, axis=-1).max() <= 2e-3
    small = spatial_program(d, tool_radius=10.0, passes=2)
    assert small.stock == pytest.approx(2.0) and small.levels[-1] == pytest.approx(math.sqrt(100.0 ** 2 - 10.0 ** 2))
    assert "stock 2 mm left on every flank" in " ".join(header(small.text))
    with pytest.raises(SpecError) as err:
        spatial_program(d, tool_radius=12.5)
    assert err.value.field == "machining.tool_radius"
    with pytest.raises(SpecError) as err:
        spatial_program(d, tolerance=1e-4)
    assert err.value.field == "machining.chord_tolerance"
    with pytest.raises(SpecError):
        spatial_program(d, step_deg=120.0)
    written = write_spatial_program(d, tmp_path / "cam.ngc", passes=1)
    assert (tmp_path / "cam.ngc").read_text() == written.text

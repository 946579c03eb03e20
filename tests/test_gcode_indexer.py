"""The parallel indexer's cam-plate programs (exporters.gcode_indexer) run through LinuxCNC's own
interpreter ``rs274`` (tests/rs274.py) and the canonical motions it prints held to a tool-centre
path computed here from the documented conventions (generators/bodies/indexing/parallel.py's
docstring), not from the exporter's geometry: roller centre L(τ) = Rot(−τ)·(P + R_p·e(a_k − ψ(τ))),
ψ from the law, its outward normal n = J·L'/|L'| by central differences; the profile Q = L − r_r·n;
the tool centre the profile offset OUTWARD by the tool radius R_t — on a flank Q + R_t·n, on the
dwell the circle of radius r_d − r_r + R_t about O, and at the lobe tip X' (the flanks' corner) the
arc of radius R_t about X' between the two flanks' normals.

The programs are written with 4 decimals and rs274 prints 4, so the numbers it prints are the
program's own: the interpreted path must stay within the tolerance (+ 1e-6 mm of measuring) of the
tool-centre path everywhere, two-sided, and match the error the program's header quotes."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from cam_workbench.exporters.gcode_indexer import indexer_programs, write_indexer_programs
from cam_workbench.generators.bodies.indexing.parallel import ParallelIndexer, design_parallel
from cam_workbench.generators.bodies.indexing.parallel_body import indexer_body
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.motion.laws import evaluate_law

from .rs274 import PRINT_QUANTUM, polyline_distance, requires_rs274, run_rs274, sample_xy

pytestmark = requires_rs274

TOL = 1e-3
#: case → (indexer fields, tool radius [mm]): a tool smaller than the roller and one larger
CASES = {"default": ({}, 6.0), "three_cams": ({"cams": 3}, 12.0)}
STEP = 2.5e-3          # spacing [mm] of the dense samples of both paths


@pytest.fixture(scope="module", params=sorted(CASES))
def cut(request, tmp_path_factory):
    fields, rt = CASES[request.param]
    d = design_parallel(ParallelIndexer(**fields))
    body = indexer_body(d, thickness=18.0, gap=4.0, bore_diameter=25.0)
    programs = indexer_programs(d, body, rt, tolerance=TOL)
    runs = [run_rs274(p.text, tmp_path_factory.mktemp(f"{request.param}_cam{p.cam}"), 1, 2 * rt) for p in programs]
    return d, body, rt, programs, runs


# ---- the conventions, recomputed -----------------------------------------------------------------
def law_psi(ix, theta):
    t_st = 2 * math.pi / ix.stations
    rel = np.asarray(theta, dtype=float) - ix.index_start
    turns = np.floor(rel / (2 * math.pi))
    f, _, _, _ = evaluate_law(ix.law, np.clip((rel - 2 * math.pi * turns) / ix.index_angle, 0, 1))
    return t_st * (turns + f)


def a_k(ix, k):
    return math.pi + (ix.cams - 1 - 2 * k) * math.pi / (ix.stations * ix.cams)


def roller_locus(ix, k, tau):
    """L(τ) (complex) in the cam frame."""
    al = a_k(ix, k) - law_psi(ix, tau)
    p = ix.centre_distance + ix.pitch_radius * np.exp(1j * al)
    return np.exp(-1j * np.asarray(tau)) * p


def locus_and_normal(ix, k, tau, h=1e-5):
    d = (roller_locus(ix, k, tau + h) - roller_locus(ix, k, tau - h)) / (2 * h)
    return roller_locus(ix, k, tau), 1j * d / np.abs(d)


def dwell_radius(ix, k):
    return abs(ix.centre_distance + ix.pitch_radius * np.exp(1j * a_k(ix, k)))


def arc(c, r, a0, a1):
    n = int(math.ceil(abs(a1 - a0) * r / STEP)) + 1
    return c + r * np.exp(1j * np.linspace(a0, a1, n))


def exact_paths(d, k, rt):
    """(tool-centre path, profile) as dense closed polylines, clockwise from the dwell's middle,
    and the tip X'."""
    ix = d.indexer
    ts, beta, rr = ix.index_start, ix.index_angle, ix.roller_radius
    t_in, t_out = d.cams[k].tip_tau                            # where the flanks are trimmed
    flanks = []
    for lo, hi in ((ts, t_out), (t_in, ts - 2 * math.pi + beta)):
        tau = np.linspace(lo, hi, 60001)
        loc, n = locus_and_normal(ix, k, tau)
        flanks.append((loc - rr * n, n))
    (q_out, n_out), (q_in, n_in) = flanks
    assert abs(q_out[-1] - q_in[0]) < 1e-7                     # the flanks do meet at τ'_in, τ'_out
    tip = 0.5 * (q_out[-1] + q_in[0])
    a0 = float(np.angle(q_out[0]))
    a1, am = a0 + 2 * math.pi - beta, a0 + math.pi - beta / 2
    b0, b1 = float(np.angle(n_out[-1])), float(np.angle(n_in[0]))
    b1 = b0 - (b0 - b1) % (2 * math.pi)                         # clockwise round the tip
    r_dw = dwell_radius(ix, k) - rr
    tool = np.concatenate([arc(0, r_dw + rt, am, a0), q_out + rt * n_out, arc(tip, rt, b0, b1), q_in + rt * n_in,
                           arc(0, r_dw + rt, a1, am)])
    profile = np.concatenate([arc(0, r_dw, am, a0), q_out, q_in, arc(0, r_dw, a1, am)])
    return simple(tool), simple(profile), tip


def dense(motions):
    """The interpreted motions sampled about STEP apart (LinuxCNC's arcs: tests/rs274.sample_xy)."""
    parts = []
    for m in motions:
        a, b = complex(*m.start[:2]), complex(*m.end[:2])
        length = abs(b - a)
        if m.kind == "arc":
            turn = (np.angle(b - m.centre) - np.angle(a - m.centre)) * m.rotation % (2 * math.pi)
            length = turn * abs(a - m.centre)
        parts.append(sample_xy([m], max(int(length / STEP), 8))[:-1])
    parts.append(np.array([complex(*motions[-1].end[:2])]))
    return np.concatenate(parts)


def simple(poly):
    """``poly`` without repeated consecutive vertices (the nearest-vertex distance needs real
    segments on both sides of a vertex)."""
    return poly[np.append(True, np.abs(np.diff(poly)) > 1e-12)]


def two_sided(a, b):
    a, b = simple(a), simple(b)
    return float(max(polyline_distance(a, b).max(), polyline_distance(b, a).max()))


def contour(run):
    return [m for m in run.motions if m.tag.startswith("contour:")]


# ---- through rs274 -------------------------------------------------------------------------------
def test_each_plate_program_runs_and_follows_the_tool_centre_path(cut):
    d, body, rt, programs, runs = cut
    assert len(programs) == len(runs) == d.indexer.cams
    for k, (p, run) in enumerate(zip(programs, runs)):
        assert (p.cam, p.name) == (k, f"cam{k}.nc")
        assert run.units == "mm"
        moves = contour(run)
        assert {m.kind for m in moves} <= {"arc", "line"} and len(moves) == p.loop.n
        assert all(abs(m.end[2] + 18.0) < 1e-9 for m in moves)                   # depth = the plate
        pts = dense(moves)
        assert (moves[-1].end == moves[0].start).all() and abs(pts[-1] - pts[0]) < 1e-9      # closed
        area = 0.5 * np.sum((np.conj(pts[:-1]) * pts[1:]).imag)
        assert area < 0                                                           # climb: clockwise
        tool, profile, _ = exact_paths(d, k, rt)
        dist = two_sided(pts, tool)
        assert dist <= TOL + 1e-6, f"cam {k}: {dist:.3g} mm"
        # the interpreter does what the program's header says it measured
        assert dist == pytest.approx(p.path_error, abs=2e-6)
        assert re.search(rf"max distance {p.path_error:.3g} mm from the analytic tool-centre path", p.text)
        # no gouge: the tool centre stays a tool radius off the profile
        # (a coarser profile, 8·STEP apart: its chords' sag is below 1e-6 mm, and a k-d tree is slow
        # to answer points a tool radius off a dense curve)
        assert polyline_distance(pts[::4], profile[::8]).min() >= rt - TOL - 1e-6
        # the check has teeth: a path off by three tolerances fails it
        wrong, _, _ = exact_paths(d, k, rt + 3 * TOL)
        assert two_sided(pts, wrong) > TOL


def test_the_lobe_tip_is_rolled_round_on_an_arc_of_the_tool_radius(cut):
    d, body, rt, programs, runs = cut
    for k, run in enumerate(runs):
        (tip_moves,) = run.tagged("contour: lobe tip")
        assert len(tip_moves) == 1 and tip_moves[0].kind == "arc" and tip_moves[0].rotation == -1
        m = tip_moves[0]
        _, _, tip = exact_paths(d, k, rt)
        assert abs(m.centre - tip) <= 2 * PRINT_QUANTUM
        for end in (m.start, m.end):
            assert abs(abs(complex(*end[:2]) - m.centre) - rt) <= 2 * PRINT_QUANTUM
        # a convex corner: the arc turns the way the contour does, by the angle between the flanks' normals
        a0, a1 = np.angle(complex(*m.start[:2]) - m.centre), np.angle(complex(*m.end[:2]) - m.centre)
        assert 0 < (a0 - a1) % (2 * math.pi) < math.pi


def test_the_dwell_is_one_arc_about_the_input_axis(cut):
    d, body, rt, programs, runs = cut
    ix = d.indexer
    for k, run in enumerate(runs):
        pieces = run.tagged("contour: dwell arc")
        assert [len(p) for p in pieces] == [1, 1]
        r = dwell_radius(ix, k) - ix.roller_radius + rt
        for (m,) in pieces:
            assert m.kind == "arc" and m.rotation == -1 and abs(m.centre) <= PRINT_QUANTUM
            assert abs(abs(complex(*m.start[:2])) - r) <= 2 * PRINT_QUANTUM
            assert abs(abs(complex(*m.end[:2])) - r) <= 2 * PRINT_QUANTUM
        assert programs[k].dwell_radius == pytest.approx(r, abs=1e-9)


def test_leads_safe_moves_and_words(cut):
    d, body, rt, programs, runs = cut
    for k, (p, run) in enumerate(zip(programs, runs)):
        (lead_in,), lead_out = run.tagged("lead-in")[0], run.tagged("lead-out")[0][0]
        moves = contour(run)
        entry = complex(*moves[0].start[:2])
        assert lead_in.kind == lead_out.kind == "arc"
        assert complex(*lead_in.end[:2]) == entry == complex(*lead_out.start[:2]) == complex(*moves[-1].end[:2])
        for m in (lead_in, lead_out):
            assert abs(abs(complex(*m.start[:2]) - m.centre) - rt) <= 2 * PRINT_QUANTUM     # lead radius = R_t
            # tangent to the dwell at the entry: the lead's centre on the entry's radial line, outside
            assert abs(abs(m.centre) - (abs(entry) + rt)) <= 3 * PRINT_QUANTUM
        _, profile, _ = exact_paths(d, k, rt)
        leads = np.concatenate([sample_xy([lead_in]), sample_xy([lead_out])])
        assert polyline_distance(leads, profile[::8]).min() >= rt - TOL
        # XY travel only at the safe height; the plunge outside the contour; feed words
        travel = [m for m in run.motions if m.kind == "traverse"]
        assert all(m.end[2] == 5.0 for m in travel if (m.start[:2] != m.end[:2]).any())
        plunge = run.motions[run.motions.index(lead_in) - 1]
        assert plunge.kind == "line" and plunge.end[2] == -18.0 and plunge.feed == 100.0
        assert lead_in.feed == 300.0 and all(m.feed == 300.0 for m in moves)
        for word in ("G21", "G64 P0.0001", "S3000 M3", "T1 M6", "G43 H1", "M5", "M30"):
            assert word in p.text
        assert run.motions[-1].kind == "traverse" and run.motions[-1].end[2] == 5.0


def test_the_header_quotes_the_indexer_tool_and_measured_errors(cut):
    d, body, rt, programs, runs = cut
    ix = d.indexer
    for k, p in enumerate(programs):
        head = [line for line in p.text.splitlines() if line.startswith("(")]
        text = "\n".join(head)
        assert f"cam {k} of {ix.cams}" in text
        for piece in (f"N = {ix.stations}", "beta = 120 deg", f"law {ix.law}", f"C = {ix.centre_distance:g} mm",
                      f"R_p = {ix.pitch_radius:g} mm", f"r_r = {ix.roller_radius:g} mm", f"radius {rt:g} mm",
                      f"biarc error {p.biarc_error:.3g} mm against the analytic tool-centre offset",
                      f"flank fit error {p.flank_fit_error:.3g} mm"):
            assert piece in text, piece
        assert 0 < p.biarc_error <= TOL and 0 < p.path_error <= 0.9 * TOL
        assert p.flank_fit_error == max(f.error for f in body.fits[k])
        # "exact" is claimed for the dwell arc alone
        assert [line for line in head if "exact" in line.lower()] == [line for line in head if "dwell:" in line]
        assert "exact arc" in text


def test_a_tool_too_large_for_a_concave_flank_is_refused(cut):
    d, body, rt, programs, runs = cut
    # the profile's smallest concave radius of curvature (signed radii, convex +), over the cams
    concave = min(float(np.min(np.where(c.profile_radius < 0, -c.profile_radius, np.inf))) for c in d.cams)
    assert math.isfinite(concave)
    with pytest.raises(SpecError) as err:
        indexer_programs(d, body, concave + 0.5)
    assert err.value.field == "machining.tool_radius" and "concave" in err.value.rule
    with pytest.raises(SpecError) as err:
        indexer_programs(d, body, 0.0)
    assert err.value.field == "machining.tool_radius"


def test_the_files_are_written_atomically(cut, tmp_path):
    d, body, rt, programs, runs = cut
    written = write_indexer_programs(d, body, tmp_path / "nc", rt, tolerance=TOL)
    names = sorted(f.name for f in (tmp_path / "nc").iterdir())
    assert names == [f"cam{k}.nc" for k in range(d.indexer.cams)]                  # no temporary files left
    for p, q in zip(written, programs):
        assert (tmp_path / "nc" / p.name).read_text() == p.text == q.text


def test_a_conventional_program_at_a_loose_tolerance(tmp_path):
    """Conventional milling (counter-clockwise), another depth, tool and tolerance: within it
    through rs274, the tip arc now turning counter-clockwise."""
    d = design_parallel(ParallelIndexer())
    body = indexer_body(d, thickness=10.0)
    tol, rt = 0.02, 8.0
    p = indexer_programs(d, body, rt, tolerance=tol, climb=False, depth=12.0)[1]
    run = run_rs274(p.text, tmp_path, 1, 2 * rt)
    moves = contour(run)
    assert all(abs(m.end[2] + 12.0) < 1e-9 for m in moves)
    pts = dense(moves)
    assert 0.5 * np.sum((np.conj(pts[:-1]) * pts[1:]).imag) > 0
    tool, _, tip = exact_paths(d, 1, rt)
    dist = two_sided(pts, tool)
    assert dist <= tol + 1e-6
    assert dist == pytest.approx(p.path_error, abs=2e-6)
    (m,), = run.tagged("contour: lobe tip")
    assert m.rotation == 1 and abs(m.centre - tip) <= 2 * PRINT_QUANTUM
    assert abs(abs(complex(*m.end[:2]) - m.centre) - rt) <= 2 * PRINT_QUANTUM

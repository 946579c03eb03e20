"""The G-code dialects (machining.dialect): a program per dialect for each built-in plate, groove
and conjugate example, held against the exact geometry through an existing interpreter or parser —
LinuxCNC's own ``rs274`` for "linuxcnc", the ``pygcode`` parser (tests/gcode_words.py) for "fanuc" and
"sinumerik" — and each dialect's own words checked in the text.

The exact tool-centre paths are computed here: a plate cam's (and each cam of a conjugate pair)
as the exact profile moved along its normal by the tool radius (tests/test_gcode_rs274.py), a
groove pass's as the exact pitch curve moved along its normal by the pass's offset.  Programs print
4 decimals, so the allowance is the chord tolerance plus 2e-4.
"""
from __future__ import annotations

import re
from functools import lru_cache

import numpy as np
import pytest

from cam_workbench.exporters.machining_outputs import machining_outputs, second_cam_of
from cam_workbench.generators import design_cam
from cam_workbench.generators.machining import machining_plan
from cam_workbench.generators.spec.examples import example_spec

from .gcode_words import read_program
from .rs274 import PRINT_QUANTUM, RS274, run_rs274, sample_xy
from .test_gcode_rs274 import exact_tool_path, two_sided

ALLOWANCE_ROUNDING = 2 * PRINT_QUANTUM
DIALECTS = ("linuxcnc", "fanuc", "sinumerik")
EXAMPLES = ("default", "groove", "conjugate")


@lru_cache(maxsize=None)
def outputs(example: str, dialect: str, compensation: str = "centre"):
    spec = example_spec(example).replace(**{"machining.dialect": dialect, "machining.compensation": compensation})
    design = design_cam(spec)
    return design, machining_plan(design), machining_outputs(design)


def exact_offset_of_pitch(design, offset: float, per_span: int = 400) -> np.ndarray:
    """The pitch curve moved outward (away from the cam axis) along its normal by ``offset``."""
    pitch = design.pitch_nurbs
    lo, hi = pitch.domain
    u = np.linspace(lo, hi, per_span * int(round(hi - lo)) + 1)
    p, d = pitch.evaluate_with_derivative(u)
    z = p[:, 0] + 1j * p[:, 1]
    t = d[:, 0] + 1j * d[:, 1]
    n = -1j * t / np.abs(t)                         # right normal: outward for a ccw curve
    if pitch.area() < 0:
        n = -n
    return z + offset * n


def moves_of(text: str, dialect: str, tmp_path, plan):
    """(tag → list of cutting moves) through the dialect's interpreter or parser."""
    if dialect == "linuxcnc":
        if RS274 is None:
            pytest.skip("LinuxCNC's rs274 is not installed")
        run = run_rs274(text, tmp_path, plan.tool_number, 2 * plan.tool_radius)
        assert run.units == ("mm" if plan.units == "mm" else "in")
        moves = run.motions
    else:
        moves = read_program(text).moves
    out: dict[str, list] = {}
    for m in moves:
        if m.kind in ("line", "arc"):
            out.setdefault(m.tag.lower(), []).append(m)
    return out


def check_dialect_words(text: str, dialect: str, plan) -> None:
    """What each dialect's text must and must not hold (docs/machining.md's table)."""
    lines = text.splitlines()
    blocks = [ln for ln in lines if ln and not ln.startswith(("(", ";", "%"))]
    if dialect == "linuxcnc":
        assert lines[0] == "%" and lines[-1] == "%" and "G91.1" in text and re.search(r"^G64 P", text, re.M)
    elif dialect == "fanuc":
        assert lines[0] == "%" and lines[1] == f"O{plan.program_number:04d}" and lines[-1] == "%"
        assert not any("G64" in b or "G91.1" in b for b in blocks) and "G21 G90 G17 G40 G49 G80 G94" in lines
        # every coordinate carries a decimal point (Fanuc reads X10 as 10 increments)
        words = re.findall(r"\b([XYZIJC])(-?[\d.]+)", "\n".join(blocks))
        assert words and all("." in v for _, v in words), [w for w in words if "." not in w[1]][:5]
        comments = [ln for ln in lines if ln.startswith("(")]
        assert comments and all(c == c.upper() and c.endswith(")") and ";" not in c for c in comments)
        assert f"T{plan.tool_number} M6" in lines and f"G43 H{plan.tool_number}" in lines
    else:
        assert not any(ln.startswith(("%", "(")) for ln in lines)
        assert "G71 G90 G17 G40 G94" in lines and "G64" in lines and not any("G91.1" in b for b in blocks)
        assert not any("G49" in b or "G43" in b for b in blocks) and f"T{plan.tool_number} M6" in lines and f"D{plan.tool_number}" in lines
        assert any(ln.startswith("; ") for ln in lines)
    assert blocks[-1] == "M30" and "M5" in blocks


@pytest.mark.parametrize("dialect", DIALECTS)
@pytest.mark.parametrize("example", EXAMPLES)
def test_each_example_in_each_dialect_is_the_exact_path(tmp_path, example, dialect):
    design, plan, out = outputs(example, dialect)
    assert out.machining_summary["dialect"] == dialect
    assert out.machining_summary["compensation"] == "centre"
    allowance = plan.chord_tolerance + ALLOWANCE_ROUNDING
    programs = [(out.gcode, design)]
    if out.second_gcode is not None:
        programs.append((out.second_gcode, second_cam_of(design)))
    assert (out.second_gcode is not None) == (example == "conjugate")
    for k, (text, cam) in enumerate(programs):
        check_dialect_words(text, dialect, plan)
        tagged = moves_of(text, dialect, tmp_path, plan)
        if example == "groove":
            for p, pas in enumerate(out.machining_summary["xy"]["offsets"], start=1):
                tag = next(t for t in tagged if t.startswith(f"level 1, pass {p}:"))
                cut = [m for m in tagged[tag] if abs(m.end[2] - plan.z_levels[0]) < 1e-9]
                exact = exact_offset_of_pitch(cam, pas)
                assert two_sided(sample_xy(cut[1:]), exact) <= allowance
        else:
            loop = tagged["contour"]
            assert len(loop) == out.machining_summary["xy"]["moves"] * plan.passes
            dist = two_sided(sample_xy(loop), exact_tool_path(cam, plan.tool_radius))
            assert dist <= allowance, f"program {k}: {dist:.3g} > {allowance:.3g}"


@pytest.mark.parametrize("dialect", ("fanuc", "sinumerik"))
def test_xc_program_in_g93_inverse_time(dialect):
    """The XC program: G93 blocks whose F is 1/(block time in minutes), in the dialect's words; the
    parsed X–C blocks are the exact tool-centre path seen from the cam (within the chord tolerance)."""
    spec = example_spec("default").replace(**{"machining.dialect": dialect, "machining.program": "xc"})
    design = design_cam(spec)
    plan = machining_plan(design)
    out = machining_outputs(design)
    check_dialect_words(out.gcode, dialect, plan)
    prog = read_program(out.gcode)
    assert {93.0, 94.0} <= prog.g_words
    rev = [m for m in prog.moves if m.tag == "revolution"]
    assert len(rev) == out.machining_summary["xc"]["blocks"] * plan.passes
    feeds = np.array([m.feed for m in rev])
    # F = 1/(block time in minutes) = 60/dt (the last block of a turn is shorter)
    assert np.allclose(feeds[:-1], 60.0 / plan.sample_period, rtol=1e-6)
    # the tool centre in the cam frame: machine point (line offset, X) turned back by C, X and C
    # linear in time within a block
    tau = np.arange(8) / 8
    x0, x1 = np.array([m.start[0] for m in rev]), np.array([m.end[0] for m in rev])
    c0, c1 = np.deg2rad([m.start[3] for m in rev]), np.deg2rad([m.end[3] for m in rev])
    xs = (x0[:, None] + (x1 - x0)[:, None] * tau).ravel()
    cs = (c0[:, None] + (c1 - c0)[:, None] * tau).ravel()
    line = -out.machining_summary["xc"]["machine_y"]
    pts = np.append(np.exp(-1j * cs) * (line + 1j * xs), np.exp(-1j * c1[-1]) * (line + 1j * x1[-1]))
    exact = exact_tool_path(design, plan.tool_radius)
    assert two_sided(pts, exact) <= plan.chord_tolerance + ALLOWANCE_ROUNDING


def test_fanuc_program_number_is_the_o_word():
    spec = example_spec("default").replace(**{"machining.dialect": "fanuc", "machining.program_number": 42})
    out = machining_outputs(design_cam(spec))
    assert out.gcode.startswith("%\nO0042\n")
    assert read_program(out.gcode).program_number == 42


def test_default_dialect_is_linuxcnc():
    design, plan, out = outputs("default", "linuxcnc")
    assert example_spec("default").machining.dialect == "linuxcnc" and plan.compensation == "centre"
    assert "program_number" not in example_spec("default").to_dict()["machining"]

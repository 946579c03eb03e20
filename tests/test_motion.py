"""Motion programs: levels, continuity between segments, derivatives, multi-level programs."""
import numpy as np
import pytest

from cam_workbench.generators.motion import MotionProgram
from cam_workbench.generators.spec import CamSpec, default_spec


def multi_level_spec():
    return CamSpec.from_dict({
        "cam": {"base_radius": 40.0, "thickness": 5.0},
        "follower": {"kind": "roller", "offset": 0.0, "roller_radius": 4.0},
        "motion": [
            {"kind": "rise", "angle": 60, "lift": 5, "law": "poly345"},
            {"kind": "dwell", "angle": 30},
            {"kind": "rise", "angle": 60, "lift": 7, "law": "modified_sine"},
            {"kind": "dwell", "angle": 40},
            {"kind": "return", "angle": 50, "lift": 4, "law": "poly4567"},
            {"kind": "dwell", "angle": 20},
            {"kind": "return", "angle": 100, "lift": 8, "law": "modified_trapezoid"},
        ],
    })


def test_levels_and_continuity():
    prog = MotionProgram.from_spec(multi_level_spec())
    b = prog.boundaries
    eps = 1e-11
    s_lo = prog.s(b[1:-1] - eps)
    s_hi = prog.s(b[1:-1] + eps)
    assert np.allclose(s_lo, s_hi, atol=1e-9)
    assert np.allclose(prog.s(b[1:-1] + eps), [5, 5, 12, 12, 8, 8], atol=1e-9)
    assert prog.s(np.array([0.0]))[0] == 0.0
    assert prog.s(np.array([2 * np.pi - 1e-12]))[0] == pytest.approx(0.0, abs=1e-9)
    assert multi_level_spec().max_lift == 12


def test_derivatives_of_program_match_finite_differences():
    prog = MotionProgram.from_spec(multi_level_spec())
    th = np.linspace(0.01, 2 * np.pi - 0.01, 4001)
    k = prog.evaluate(th)
    h = 1e-6
    kp, km = prog.evaluate(th + h), prog.evaluate(th - h)
    near_boundary = np.min(np.abs(th[:, None] - prog.boundaries[None, :]), axis=1) < 3 * h
    for a, b in ((k.ds, (kp.s - km.s)), (k.d2s, (kp.ds - km.ds)), (k.d3s, (kp.d2s - km.d2s))):
        num = b / (2 * h)
        scale = max(1.0, np.max(np.abs(a)))
        assert np.max(np.abs(num - a)[~near_boundary]) / scale < 1e-5


def test_paper_desired_maxima():
    """Paper §4.2: desired max velocity 120 mm/s, acceleration 1130.9 mm/s², jerk 21318.3 mm/s³."""
    prog = MotionProgram.from_spec(default_spec())
    m = prog.maxima(omega=2 * np.pi)
    assert m["velocity"] == pytest.approx(120.0, rel=1e-9)
    assert m["acceleration"] == pytest.approx(1130.9, abs=0.1)
    assert m["jerk"] == pytest.approx(21318.3, abs=0.1)


def test_vectorised_any_shape_and_periodic():
    prog = MotionProgram.from_spec(default_spec())
    th = np.linspace(0, 2 * np.pi, 12).reshape(3, 4)
    assert prog.s(th).shape == (3, 4)
    assert np.allclose(prog.s(th), prog.s(th + 2 * np.pi))

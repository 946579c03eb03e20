"""Motion laws: closed forms against numerical differentiation, end conditions, and the
peak coefficients published in Norton, *Design of Machinery* (Table 8-3)."""
import numpy as np
import pytest

from cam_workbench.generators.motion.laws import END_CONTINUITY, LAW_FUNCTIONS, evaluate_law

LAWS = sorted(LAW_FUNCTIONS)

# (max |f'|, max |f''|) for a unit rise over a unit interval; Norton Table 8-3 and the
# modified laws' published factors (Cv, Ca).
PUBLISHED = {
    "cycloidal": (2.0, 6.2832),
    "harmonic": (1.5708, 4.9348),
    "modified_sine": (1.7596, 5.5280),
    "modified_trapezoid": (2.0000, 4.8881),
    "poly345": (1.8750, 5.7735),
    "poly4567": (2.1875, 7.5132),
}


@pytest.mark.parametrize("law", LAWS)
def test_end_values(law):
    f = evaluate_law(law, np.array([0.0, 1.0]))
    assert f[0][0] == pytest.approx(0.0, abs=1e-15)
    assert f[0][1] == pytest.approx(1.0, abs=1e-14)
    # every law has zero velocity at both ends; higher orders as the law promises
    for order in range(1, END_CONTINUITY[law] + 1):
        assert np.allclose(f[order], 0.0, atol=1e-12), (law, order, f[order])


@pytest.mark.parametrize("law", LAWS)
def test_derivatives_match_numerical_differentiation(law):
    x = np.linspace(0.003, 0.997, 997)
    h = 1e-5
    f = evaluate_law(law, x)
    fp = evaluate_law(law, x + h)
    fm = evaluate_law(law, x - h)
    for order in range(3):
        numeric = (fp[order] - fm[order]) / (2 * h)
        scale = max(1.0, float(np.max(np.abs(f[order + 1]))))
        # skip points within h of a piece boundary (jerk of modified trapezoid jumps there)
        ok = np.ones_like(x, dtype=bool)
        for b in (0.125, 0.375, 0.625, 0.875):
            ok &= np.abs(x - b) > 2 * h
        err = np.max(np.abs(numeric - f[order + 1])[ok]) / scale
        assert err < 1e-7, (law, order + 1, err)


@pytest.mark.parametrize("law", ["modified_sine", "modified_trapezoid"])
def test_piecewise_laws_are_continuous_inside(law):
    eps = 1e-12
    for b in (0.125, 0.375, 0.625, 0.875):
        lo = evaluate_law(law, np.array([b - eps]))
        hi = evaluate_law(law, np.array([b + eps]))
        for order in range(4):  # s, v, a and jerk are continuous inside both laws
            assert abs(lo[order][0] - hi[order][0]) < 1e-9 * max(1, abs(hi[order][0])), (law, b, order)


@pytest.mark.parametrize("law", LAWS)
def test_published_peak_coefficients(law):
    x = np.linspace(0, 1, 200001)
    _, f1, f2, _ = evaluate_law(law, x)
    cv, ca = PUBLISHED[law]
    assert np.max(np.abs(f1)) == pytest.approx(cv, abs=6e-4)
    assert np.max(np.abs(f2)) == pytest.approx(ca, abs=6e-4)


@pytest.mark.parametrize("law", LAWS)
def test_monotonic_rise(law):
    x = np.linspace(0, 1, 10001)
    f = evaluate_law(law, x)[0]
    assert np.all(np.diff(f) >= -1e-15)

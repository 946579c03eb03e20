"""Electronic-cam tables (cam_workbench.exporters.ecam, cam_workbench.generators.ecam), each file read back here the way its
controller would read it and interpolated here with the controller's own rule — straight lines
(np.interp) for point tables; for XYVA points, CamBuilder Poly5 segments and Beckhoff POLYNOM5_MM
motion functions each segment's own fifth-degree polynomial, solved here from its six boundary
conditions by numpy.linalg.solve — then held against the exact motion (the cycloidal laws written
out in tests/test_dynamics.py) and against the deviation the file states:

* linear interpolation of a cycloidal rise errs by h²/8·s″ (h the step in rad) at the steepest
  acceleration, to O(h⁴);
* the file's structure is the documented one (CODESYS's generated GVL, MC_CAM_REF fields, IEC real
  literals; Beckhoff's MC_MotionFunctionPoint fields and table types; Lenze's "x y // comment").
"""
from __future__ import annotations

import csv
import io
import math
import re

import numpy as np
import pytest

from cam_workbench.exporters.ecam import ecam_table, iec_real
from cam_workbench.generators.motion.program import MotionProgram
from cam_workbench.generators.spec import CamSpec, default_spec
from cam_workbench.generators.spec.examples import example_dict

from .test_dynamics import cycloidal

DEG = math.pi / 180
NUM = r"(-?\d+\.\d+(?:E-?\d+)?)"
IEC_REAL = re.compile(r"^-?\d+\.\d+(E-?\d+)?$")


def exact(master_deg):
    s, v, a = cycloidal(np.radians(master_deg))
    return s, v * DEG, a * DEG**2                # per master degree


def dense(x):
    """Masters between the table's points (and the points themselves)."""
    t = np.linspace(0, 1, 41)
    return np.unique(np.concatenate([x[:-1, None] + np.outer(np.diff(x), t)]).ravel())


def quintic_segments(x, y, v, a, xs):
    """Each interval's own quintic p(x) = Σ c_k (x − x0)^k from p, p′, p″ at both ends, solved here."""
    out = np.empty_like(xs)
    idx = np.clip(np.searchsorted(x, xs, side="right") - 1, 0, x.size - 2)
    for i in range(x.size - 1):
        h = x[i + 1] - x[i]
        m = np.array([[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 2, 0, 0, 0],
                      [1, h, h**2, h**3, h**4, h**5], [0, 1, 2 * h, 3 * h**2, 4 * h**3, 5 * h**4],
                      [0, 0, 2, 6 * h, 12 * h**2, 20 * h**3]])
        c = np.linalg.solve(m, [y[i], v[i], a[i], y[i + 1], v[i + 1], a[i + 1]])
        sel = idx == i
        out[sel] = np.polyval(c[::-1], xs[sel] - x[i])
    return out


def stated(text, kind):
    """The deviation a file states for ``kind`` interpolation: (value, at_deg)."""
    m = re.search(kind + r" interpolation \([^)]*\): largest deviation from the exact motion ([0-9.e+-]+) \w+ at "
                  r"([0-9.]+) deg", text)
    assert m, text[:800]
    return float(m.group(1)), float(m.group(2))


@pytest.fixture(scope="module")
def spec():
    return default_spec()


def test_csv_columns_are_the_exact_motion_per_radian(spec):
    t = ecam_table(spec, "csv", step=0.5)
    rows = list(csv.reader(io.StringIO(t.text)))
    assert rows[0] == ["theta [deg]", "s [mm]", "s' [mm/rad]", "s'' [mm/rad^2]", "s''' [mm/rad^3]"]
    data = np.array(rows[1:], float)
    assert data.shape == (721, 5)
    assert data[0, 0] == 0.0 and data[-1, 0] == 360.0 and np.all(np.diff(data[:, 0]) > 0)
    s, v, a = cycloidal(np.radians(data[:, 0]))
    assert np.max(np.abs(data[:, 1] - s)) < 1e-12 and np.max(np.abs(data[:, 2] - v)) < 1e-11
    assert np.max(np.abs(data[:, 3] - a)) < 1e-10
    # both readings a CSV can get, each as stated
    xs = dense(data[:, 0])
    lin = np.abs(np.interp(xs, data[:, 0], data[:, 1]) - exact(xs)[0])
    assert t.deviations["linear"].max_error == pytest.approx(lin.max(), rel=2e-3)
    assert t.deviations["linear"].max_error >= lin.max() * (1 - 1e-12)


def test_codesys_xyva_is_the_documented_gvl_and_its_quintics_are_as_stated(spec):
    t = ecam_table(spec, "codesys", step=2.0)
    text = t.text
    assert text.startswith("{attribute 'linkalways'}\nVAR_GLOBAL\n") and text.rstrip().endswith("END_VAR")
    rows = re.findall(r"\(dX := ([^,]+), dY := ([^,]+), dV := ([^,]+), dA := ([^)]+)\)", text)
    assert len(rows) == 181
    for row in rows:
        for literal in row:
            assert IEC_REAL.match(literal), literal
    x, y, v, a = (np.array(c, float) for c in zip(*rows))
    ref = re.search(r"Cam: MC_CAM_REF := \(nElements := (\d+), byType := 3, xStart := ([^,]+), xEnd := ([^,]+), "
                    r"nTappets := 0, strCAMName := 'Cam', pce := ADR\(Cam_A\), xPartofLM := TRUE\);", text)
    assert ref and int(ref.group(1)) == 181 and float(ref.group(2)) == 0.0 and float(ref.group(3)) == 360.0
    assert "Cam_A: ARRAY[0..180] OF SMC_CAMXYVA := [" in text
    ey, ev, ea = exact(x)
    assert np.max(np.abs(y - ey)) < 1e-12 and np.max(np.abs(v - ev)) < 1e-14 and np.max(np.abs(a - ea)) < 1e-15
    xs = dense(x)
    err = np.abs(quintic_segments(x, y, v, a, xs) - exact(xs)[0])
    value, _at = stated(text, "quintic")
    assert value == pytest.approx(t.deviation.max_error, rel=2e-3)            # the comment's 3 digits
    assert t.deviation.max_error == pytest.approx(err.max(), rel=0.05)
    assert t.deviation.max_error >= err.max() * (1 - 1e-9)
    assert 1e-12 < err.max() < 1e-9                                            # 2° steps


def test_codesys_poly5_segments_are_the_cambuilder_calls(spec):
    t = ecam_table(spec, "codesys", table="poly5", step=5.0, name="Lift")
    text = t.text
    calls = re.findall(r"camBuilder\.Append\(SMCB\.Poly5\((SMCB\.BoundImplicit\(\)|SMCB\.Bound\([^)]*\)), "
                       r"SMCB\.Bound\(([^)]*)\)\)\);", text)
    assert len(calls) == 72
    first = re.fullmatch(r"SMCB\.Bound\(([^)]*)\)", calls[0][0])
    assert first, "the first segment starts from an explicit bound"
    assert all(c[0] == "SMCB.BoundImplicit()" for c in calls[1:])
    pts = [np.array(first.group(1).split(", "), float)] + [np.array(c[1].split(", "), float) for c in calls]
    x, y, v, a = np.array(pts).T
    assert x[0] == 0.0 and x[-1] == 360.0
    assert "PROGRAM Lift_Build" in text and "aCamSegments : ARRAY[1..72] OF SMC_CAM_SEGMENT;" in text
    assert "SMCB.InitCamRef(camRef, ADR(aCamSegments), XSIZEOF(aCamSegments));\n    camBuilder.Write(camRef);" in text
    xs = dense(x)
    err = np.abs(quintic_segments(x, y, v, a, xs) - exact(xs)[0])
    assert t.deviation.max_error == pytest.approx(err.max(), rel=0.05) and t.deviation.max_error >= err.max() * (1 - 1e-9)
    assert any("MAX_CAM_SEGMENT_COUNT" in n for n in t.notes)


def test_beckhoff_motion_function_points(spec):
    t = ecam_table(spec, "beckhoff", step=3.0)
    rows = re.findall(r"\(PointIndex := (\d+), FunctionType := MOTIONFUNCTYPE_POLYNOM5_MM, "
                      r"PointType := MOTIONPOINTTYPE_MOTION, RelIndexNextPoint := 1, MasterPos := ([^,]+), "
                      r"SlavePos := ([^,]+), SlaveVelo := ([^,]+), SlaveAcc := ([^,]+), SlaveJerk := ([^)]+)\)", t.text)
    assert [int(r[0]) for r in rows] == list(range(1, 122))
    x, y, v, a, j = (np.array(c, float) for c in list(zip(*rows))[1:])
    assert "Cam : MC_CAM_REF := (TableType := MC_TABLETYPE_MOTIONFUNCTION, NoOfRows := 121, NoOfColumns := 1);" in t.text
    assert "Cam.pArray := ADR(Cam_Points); Cam.ArraySize := SIZEOF(Cam_Points);" in t.text
    xs = dense(x)
    err = np.abs(quintic_segments(x, y, v, a, xs) - exact(xs)[0])
    assert t.deviation.max_error == pytest.approx(err.max(), rel=0.05) and t.deviation.max_error >= err.max() * (1 - 1e-9)


def test_beckhoff_position_table_is_linear_and_as_stated(spec):
    t = ecam_table(spec, "beckhoff", table="position_table", step=1.0)
    body = re.search(r"Cam_Table : ARRAY\[0\.\.360, 0\.\.1\] OF LREAL := \[\n(.*?)\];", t.text, re.S).group(1)
    vals = np.array(re.findall(NUM, body), float).reshape(-1, 2)    # row by row: master, slave
    assert vals.shape == (361, 2)
    x, y = vals.T
    assert "TableType := MC_TABLETYPE_EQUIDISTANT, NoOfRows := 361, NoOfColumns := 2" in t.text
    xs = dense(x)
    err = np.abs(np.interp(xs, x, y) - exact(xs)[0])
    # h²/8·s″ at the steepest acceleration of the cycloidal rise (20 mm over 120°)
    h = math.radians(1.0)
    assert err.max() == pytest.approx(h * h / 8 * 2 * math.pi * 20 / math.radians(120) ** 2, rel=1e-3)
    assert t.deviation.max_error == pytest.approx(err.max(), rel=1e-4)
    value, at = stated(t.text, "linear")
    assert value == pytest.approx(t.deviation.max_error, rel=2e-3) and at == pytest.approx(t.deviation.at_deg, abs=1e-4)


def test_beckhoff_position_table_off_the_step_is_not_equidistant(spec):
    t = ecam_table(spec, "beckhoff", table="position_table", step=7.0)
    assert not t.points.equidistant and "MC_TABLETYPE_NONEQUIDISTANT" in t.text
    assert set(np.round([30, 150, 210, 330, 360], 9)) <= set(t.points.master)


def test_lenze_point_file(spec):
    t = ecam_table(spec, "lenze", step=1.5)
    assert t.suffix == ".txt"
    lines = t.text.splitlines()
    first, comment = lines[0].split(" // ", 1)
    assert "linear interpolation" in comment and "\n" not in comment
    pts = [first] + lines[1:]
    data = np.array([ln.split() for ln in pts], float)
    for ln in pts:
        assert re.fullmatch(r"-?\d+\.\d{9} -?\d+\.\d{9}", ln), ln
    x, y = data.T
    assert np.all(np.diff(x) > 0) and x[0] == 0 and x[-1] == 360
    xs = dense(x)
    err = np.abs(np.interp(xs, x, y) - exact(xs)[0])
    assert t.deviation.max_error == pytest.approx(err.max(), rel=1e-4)


def test_oscillating_lifts_are_arm_degrees():
    spec = CamSpec.from_dict(example_dict("oscillating"))
    t = ecam_table(spec, "codesys", step=1.0)
    assert t.lift_unit == "deg" and "slave Y = follower lift [deg]" in t.text
    assert t.points.slave.max() == pytest.approx(15.0, abs=1e-12)


def test_segment_boundaries_are_points_unless_left_out():
    """With a 7° step the cycloidal laws' ends at 30°, 150° and 330° fall inside intervals, where the
    jerk jumps: a quintic across the jump errs far more than the quintics on either side of it."""
    spec = default_spec()
    prog = MotionProgram.from_spec(spec)
    with_b = ecam_table(spec, "codesys", step=7.0, program=prog)
    without = ecam_table(spec, "codesys", step=7.0, boundaries=False, program=prog)
    assert {30.0, 150.0, 330.0} <= set(with_b.points.master)
    assert not {30.0, 150.0, 330.0} & set(without.points.master)
    assert without.deviation.max_error > 10 * with_b.deviation.max_error


def test_an_acceleration_jump_at_a_point_is_measured_not_hidden():
    """The harmonic law's acceleration jumps at its ends; a table holds one Y″ per point (the
    segment's that starts there), so the quintic beside it errs — and the deviation says so."""
    spec = default_spec().replace(**{"motion[1].law": "harmonic", "motion[3].law": "harmonic"})
    t = ecam_table(spec, "codesys", step=1.0)
    x, y, v, a = t.points.master, t.points.slave, t.points.velocity, t.points.acceleration
    xs = dense(x)
    k = MotionProgram.from_spec(spec).evaluate(np.radians(xs))
    err = np.abs(quintic_segments(x, y, v, a, xs) - k.s)
    assert t.deviation.max_error == pytest.approx(err.max(), rel=0.05) and err.max() > 1e-5


def test_iec_real_literals_round_trip():
    for v in (0.0, 1.0, -2.5, 1e-5, 6.6821129435070766e-18, 123456789.125, 1e22, -0.0):
        text = iec_real(v)
        assert IEC_REAL.match(text), text
        assert float(text) == v


@pytest.mark.parametrize("options, field", [
    ({"format": "csv", "table": "poly5"}, "ecam.table"),
    ({"format": "codesys", "table": "position_table"}, "ecam.table"),
    ({"format": "codesys", "step": 0.0}, "ecam.step"),
    ({"format": "codesys", "step": 0.01}, "ecam.step"),           # 36 001 points: more than an INT counts
    ({"format": "beckhoff", "name": "bad name"}, "ecam.name"),
    ({"format": "lenze", "name": "a__b"}, "ecam.name"),
])
def test_bad_options_name_the_field(options, field):
    from cam_workbench.generators.errors import SpecError

    with pytest.raises(SpecError) as err:
        ecam_table(default_spec(), **options)
    assert str(err.value).startswith(field + ":")


def test_a_bspline_lift_law_in_inches():
    """The thesis' Example 5 (B-spline rise and return, inches): the linear table's error is
    h²/8·max|s″| to the step's O(h²) and the quintic table's far below it; lifts in inches."""
    from cam_workbench.generators.spec import load_spec

    from .conftest import ROOT

    spec = load_spec(ROOT / "tests" / "fixtures" / "thesis_ex5_final.toml")
    prog = MotionProgram.from_spec(spec)
    lin = ecam_table(spec, "lenze", step=0.5, program=prog)
    quin = ecam_table(spec, "codesys", step=0.5, program=prog)
    th = np.linspace(0, 2 * np.pi, 200001)
    a = np.max(np.abs(prog.evaluate(th).d2s))
    h = math.radians(0.5)
    assert lin.lift_unit == "in" and "y = follower lift [in]" in lin.text
    assert lin.deviation.max_error == pytest.approx(h * h / 8 * a, rel=0.02)
    assert quin.deviation.max_error < 1e-3 * lin.deviation.max_error

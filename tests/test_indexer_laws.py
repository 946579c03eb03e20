"""An indexer's index under any rest-to-rest rise law of the project (issue 23): the motion program's
laws ("polynomial", "bspline", …) normalised as :class:`NormalisedLaw` values drive the three
indexers' geometry and sizing.

* a "polynomial" rise with continuity 3 at both ends is the 4-5-6-7 law: every indexer designs to
  the same numbers as with the closed form ``poly4567`` (turret angle, pressure-angle maxima, drive
  torques, law characteristics) to 1e-9;
* a "bspline" rise (rest-to-rest control points) designs, and the turret angle recovered from the
  built geometry matches the program's s(θ) (degrees of turret) as closely as the closed forms' do;
* a law that does not run rest to rest is refused naming the field; the CLI checks a polynomial
  parallel indexer."""
from __future__ import annotations

import copy
import math
import subprocess
import sys

import numpy as np
import pytest

from cam_workbench.generators.bodies.indexing import from_spec
from cam_workbench.generators.bodies.indexing.kind_common import turn_error
from cam_workbench.generators.bodies.indexing.parallel import turret_angle as parallel_turret_angle
from cam_workbench.generators.bodies.indexing.spatial import turret_angle as spatial_turret_angle
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.kinds import body_of
from cam_workbench.generators.motion.characteristics import law_characteristics
from cam_workbench.generators.motion.laws import CLOSED_FORM_LAWS, NormalisedLaw, evaluate_law
from cam_workbench.generators.motion.program import MotionProgram
from cam_workbench.generators.spec.examples import EXAMPLES
from cam_workbench.generators.spec.model import CamSpec
from cam_workbench.generators.spec.toml_io import dict_to_toml

from .conftest import ROOT

CLI = [sys.executable, "-m", "cam_workbench.cli"]
BODIES = ("parallel_indexer", "barrel_indexer", "globoidal_indexer")
TOL = 1e-9
POLY4567 = {"law": "polynomial", "start_continuity": 3, "end_continuity": 3}


def with_law(body: str, **law) -> dict:
    """The body's example with its index (motion[1]) under ``law`` (the law's own fields)."""
    data = copy.deepcopy(EXAMPLES[body])
    rise = data["motion"][1]
    assert rise["kind"] == "rise"
    data["motion"][1] = {k: v for k, v in rise.items() if k != "law"} | law
    return data


def bspline(body: str) -> dict:
    """Order 5 (the default), 11 control points: the first and last four at the end levels, so the
    rise starts and ends at rest (velocity, acceleration and jerk 0); the fixed ones close to the
    ends, so the rise spreads over the index (evenly spaced, the barrel's flank would undercut)."""
    span = EXAMPLES[body]["motion"][1]["angle"]
    return {"law": "bspline", "control_x": tuple(f * span for f in (0.04, 0.08, 0.13, 0.3, 0.5, 0.7, 0.87, 0.92, 0.96)),
            "control_y": (0.2, 0.5, 0.8)}


def turret(design, theta):
    ix = design.geometry.indexer
    fn = parallel_turret_angle if design.spec.cam.body == "parallel_indexer" else spatial_turret_angle
    return fn(ix, theta)


@pytest.fixture(scope="module", params=BODIES)
def pair(request):
    """(closed form poly4567, "polynomial" of continuity 3) designs of one body."""
    out = []
    for law in ({"law": "poly4567"}, POLY4567):
        spec = CamSpec.from_dict(with_law(request.param, **law))
        out.append(body_of(spec).design(spec))
    return tuple(out)


def test_the_polynomial_rise_is_a_normalised_law_equal_to_4567():
    spec = CamSpec.from_dict(with_law("parallel_indexer", **POLY4567))
    law = from_spec.index_law(spec, MotionProgram.from_spec(spec))
    assert isinstance(law, NormalisedLaw) and law.name == "polynomial" and str(law) == "polynomial"
    assert law.continuity == 3
    # a value: equal and hashed alike when made again from an equal program, usable as a cache key
    again = NormalisedLaw.from_segment(MotionProgram.from_spec(CamSpec.from_dict(with_law("parallel_indexer",
                                                                                            **POLY4567))), 1)
    assert again == law and hash(again) == hash(law) and again != CLOSED_FORM_LAWS["poly4567"]
    x = np.linspace(0.0, 1.0, 4001)
    for a, b in zip(evaluate_law(law, x), evaluate_law("poly4567", x)):
        assert np.max(np.abs(a - b)) < TOL * max(1.0, float(np.max(np.abs(b))))
    # the law's characteristic values as the closed form's, under the law's own name
    c, ref = law_characteristics(law), law_characteristics("poly4567")
    assert c.name == "polynomial"
    for key in ("C_v", "C_a", "C_j", "Q"):
        assert getattr(c, key) == pytest.approx(getattr(ref, key), rel=TOL)
    # the closed forms as values evaluate as their names
    assert np.array_equal(evaluate_law(CLOSED_FORM_LAWS["modified_sine"], x)[2], evaluate_law("modified_sine", x)[2])


def test_a_polynomial_index_designs_as_the_4567_closed_form(pair):
    closed, poly = pair
    assert poly.geometry.indexer.law == from_spec.index_law(poly.spec, MotionProgram.from_spec(poly.spec))
    assert closed.geometry.indexer.law == "poly4567"
    theta = np.linspace(0.0, 4 * math.pi, 3001)
    for a, b in zip(turret(closed, theta), turret(poly, theta)):
        assert np.max(np.abs(a - b)) < TOL
    sa, sb = closed.summary(), poly.summary()
    assert sb["indexer"]["geometry"]["law"] == "polynomial" and sb["indexer"]["drive"]["law"] == "polynomial"
    pa = ("max_deg", "index_max_deg") if poly.spec.cam.body == "parallel_indexer" else ("max_deg", "contacts_max_deg")
    for key in pa:
        assert sb["pressure_angle"][key] == pytest.approx(sa["pressure_angle"][key], rel=TOL, abs=TOL)
    da, db = sa["indexer"]["drive"], sb["indexer"]["drive"]
    for key in ("output_torque_peak_Nm", "input_torque_peak_Nm", "input_power_peak_W", "input_power_mean_index_W",
                "normal_force_peak_N", "output_velocity_peak_rad_s", "output_acceleration_peak_rad_s2"):
        assert db[key] == pytest.approx(da[key], rel=TOL), key
    for key in ("C_v", "C_a", "C_j", "Q"):
        assert db["characteristics"][key] == pytest.approx(da["characteristics"][key], rel=TOL)
    # and the turret angle recovered from the built geometry agrees as well as the closed form's
    err_a = sa["indexer"]["motion_from_geometry"]["max_error_rad"]
    err_b = sb["indexer"]["motion_from_geometry"]["max_error_rad"]
    assert err_b < max(10 * err_a, 1e-10)


@pytest.mark.parametrize("body", BODIES)
def test_a_bspline_index_designs_and_its_geometry_holds_the_program(body):
    closed = CamSpec.from_dict(EXAMPLES[body])
    spec = CamSpec.from_dict(with_law(body, **bspline(body)))
    law = from_spec.index_law(spec, MotionProgram.from_spec(spec))
    assert isinstance(law, NormalisedLaw) and law.name == "bspline" and law.continuity == 3
    errors = []
    for s in (closed, spec):
        design = body_of(s).design(s)
        rec = design.recovered
        ok = np.isfinite(rec.psi)
        if hasattr(rec, "slack"):                  # the parallel profiles' undetermined angles
            ok &= rec.slack >= -1e-6
        assert ok.sum() > 0.9 * ok.size
        prog = MotionProgram.from_spec(s)          # s in degrees of turret rotation
        step = design.geometry.indexer.station_angle
        errors.append(turn_error(rec.psi[ok] - np.radians(prog.s(rec.theta[ok])), step))
    assert design.summary()["indexer"]["geometry"]["law"] == "bspline"
    # the B-spline index's geometry holds the program as closely as the closed form's holds its law
    assert errors[1] < max(10 * errors[0], 1e-10), errors


@pytest.mark.parametrize("law,field", [
    ({"law": "polynomial", "start_velocity": 1.0}, "motion[1].start_velocity"),
    ({"law": "polynomial", "end_velocity": -2.0}, "motion[1].end_velocity"),
    ({"law": "polynomial", "start_continuity": 0}, "motion[1].start_continuity"),
    ({"law": "constant_velocity"}, "motion[1].start_blend"),
])
def test_a_law_that_does_not_run_rest_to_rest_is_refused_naming_the_field(law, field):
    with pytest.raises(SpecError) as exc:
        CamSpec.from_dict(with_law("parallel_indexer", **law))
    assert exc.value.field == field, str(exc.value)
    assert "rest to rest" in exc.value.rule


def test_a_blended_constant_velocity_index_is_accepted():
    spec = CamSpec.from_dict(with_law("parallel_indexer", law="constant_velocity", start_blend=30.0, end_blend=30.0))
    law = from_spec.index_law(spec, MotionProgram.from_spec(spec))
    assert law.name == "constant_velocity" and law.continuity >= 1
    ix = body_of(spec).design(spec).geometry.indexer
    psi, dpsi, _ = parallel_turret_angle(ix, np.array([ix.index_start, ix.index_start + ix.index_angle]))
    assert np.all(dpsi == 0.0) and psi[1] - psi[0] == pytest.approx(ix.station_angle, rel=1e-12)


def test_the_cli_checks_a_polynomial_parallel_indexer(tmp_path):
    spec_file = tmp_path / "ix.toml"
    spec_file.write_text(dict_to_toml(with_law("parallel_indexer", **POLY4567)))
    r = subprocess.run([*CLI, "check", str(spec_file)], capture_output=True, text=True, cwd=ROOT,
                       stdin=subprocess.DEVNULL)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "Traceback" not in r.stderr


def test_a_program_law_pickles_and_keeps_its_value():
    import pickle

    spec = CamSpec.from_dict(with_law("parallel_indexer", **POLY4567))
    law = from_spec.index_law(spec, MotionProgram.from_spec(spec))
    back = pickle.loads(pickle.dumps(law))
    assert back == law and back.continuity == law.continuity
    x = np.linspace(0.0, 1.0, 101)
    assert all(np.array_equal(a, b) for a, b in zip(evaluate_law(back, x), evaluate_law(law, x)))

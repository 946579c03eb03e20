"""The parallel indexer as a spec (``cam.body = "parallel_indexer"``, the ``[indexer]`` table): its
rules through the library and the CLI (field named, exit status 2, nothing written), the turret's
advancing motion program against the modified sine's closed form written here, and the design's
report numbers against independent computations from the geometry."""
from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.kinds import body_of
from cam_workbench.generators.motion.program import MotionProgram
from cam_workbench.generators.spec.examples import PARALLEL_INDEXER_SPEC_DICT, example_dict
from cam_workbench.generators.spec.model import CamSpec
from cam_workbench.generators.spec.toml_io import dict_to_toml

from .conftest import ROOT

CLI = [sys.executable, "-m", "cam_workbench.cli"]


@pytest.fixture(scope="module")
def spec() -> CamSpec:
    return CamSpec.from_dict(PARALLEL_INDEXER_SPEC_DICT)


@pytest.fixture(scope="module")
def design(spec):
    return body_of(spec).design(spec)


def modified_sine(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """F(u), F'(u) of the modified sine (Neklutin): sine acceleration pieces over u ∈ [0, ⅛], [⅛, ⅞],
    [⅞, 1], written here from the piecewise closed form (not the project's law table)."""
    k = 1.0 / (4.0 + math.pi)
    u = np.asarray(u, dtype=float)
    f = np.where(u <= 0.125, k * (math.pi * u - 0.25 * np.sin(4 * math.pi * u)),
                 np.where(u <= 0.875, k * (2.0 + math.pi * u - 9.0 / 4.0 * np.sin(4 * math.pi / 3 * u + math.pi / 3)),
                          k * (4.0 + math.pi * u - 0.25 * np.sin(4 * math.pi * u))))
    df = np.where(u <= 0.125, k * (math.pi - math.pi * np.cos(4 * math.pi * u)),
                  np.where(u <= 0.875, k * (math.pi - 3 * math.pi * np.cos(4 * math.pi / 3 * u + math.pi / 3)),
                           k * (math.pi - math.pi * np.cos(4 * math.pi * u))))
    return f, df


def test_the_turret_program_advances_by_one_station_and_matches_the_law(spec):
    prog = MotionProgram.from_spec(spec)
    assert prog.advance == pytest.approx(45.0)
    th = np.linspace(0.0, 2 * math.pi, 2001, endpoint=False)     # 2π is the next turn's 0
    k = prog.evaluate(th)
    u = np.clip((th - math.radians(120.0)) / math.radians(120.0), 0.0, 1.0)
    f, df = modified_sine(u)
    assert np.max(np.abs(k.s - 45.0 * f)) < 1e-9
    inside = (u > 0) & (u < 1)
    assert np.max(np.abs(k.ds[inside] - 45.0 * df[inside] / math.radians(120.0))) < 1e-8
    dwell = (th < math.radians(120.0)) | (th > math.radians(240.0))
    assert np.all(k.ds[dwell] == 0.0)                    # dwell velocity exactly zero
    # the wrap is no jump once the advance is taken off: every junction reaches what the laws promise
    assert all(j.order >= j.promised for j in prog.junctions())
    assert prog.junctions()[0].order == 3


def test_the_report_numbers_come_from_the_geometry(spec, design):
    s = design.summary()
    g = design.geometry
    assert s["body"]["kind"] == "parallel_indexer"
    assert s["indexer"]["motion_from_geometry"]["max_error_rad"] < 1e-6
    assert s["body"]["flank_fit_error"]["value"] < 1e-4
    # the clearance check is the geometry's own verdict
    assert s["checks"]["results"]["clearance"]["value"] == pytest.approx(g.clearance.gap)
    # the derived size: the smallest dwell radius |P + R_p e(a_k)| computed here
    c, rp, n = 120.0, 50.0, 8
    a = [math.pi + (1 - 2 * k) * math.pi / (2 * n) for k in range(2)]
    rd = min(math.hypot(c + rp * math.cos(x), rp * math.sin(x)) for x in a)
    assert spec.cam.base_radius == pytest.approx(rd, rel=1e-12)
    # the top face: the last plate's profile less the bore, by a shoelace of its exact points
    top = design.body.prisms[-1]
    pts = np.concatenate([p.points(4001) for p in top.outer.pieces])
    shoelace = 0.5 * abs(np.sum(pts.real * np.roll(pts.imag, -1) - pts.imag * np.roll(pts.real, -1)))
    assert s["area"] == pytest.approx(shoelace - math.pi * 15.0 ** 2, rel=1e-6)
    # the contact-stress check's cam angle is the drive's peak shifted by the index start (120°)
    drive = s["indexer"]["drive"]
    assert s["checks"]["results"]["contact_stress"]["at_deg"] == pytest.approx(
        (drive["contact_stress_peak_at_deg"] + 120.0) % 360.0)
    assert drive["output_acceleration_peak_rad_s2"] == pytest.approx(
        drive["characteristics"]["C_a"] * (2 * math.pi / 8) / drive["index_time_s"] ** 2, rel=1e-9)


def test_a_lower_pressure_angle_limit_fails_with_words(spec):
    low = spec.replace(**{"indexer.max_pressure_angle": 50.0})
    checks = body_of(low).own_checks(low)
    assert checks["failed"] == ["pressure_angle"]
    r = checks["results"]["pressure_angle"]
    assert r["status"] == "fail" and r["value"] > 50.0


BAD = [
    ({"motion[1].lift": 40.0}, "motion"),
    ({"indexer.stations": 1}, "indexer.stations"),
    ({"indexer.stations": None}, "indexer.stations"),
    ({"indexer.pitch_radius": 130.0}, "indexer.pitch_radius"),
    ({"indexer.centre_distance": None}, "indexer.centre_distance"),
    ({"follower.roller_radius": 25.0}, "follower.roller_radius"),
    ({"follower.kind": "knife"}, "follower.kind"),
    ({"follower.offset": 3.0}, "follower.offset"),
    ({"cam.base_radius": 50.0}, "cam.base_radius"),
    ({"cam.keyway": "DIN6885"}, "cam.keyway"),
    ({"units": "in"}, "units"),
    ({"motion[1].law": "bspline"}, "motion[1]"),
    ({"motion[1].kind": "return"}, "motion[1]"),
    ({"dynamics.enabled": True}, "dynamics.torsional_stiffness"),      # the output train's (docs/indexing.md)
    ({"indexer.cams": 4}, "indexer.cams"),
]


@pytest.mark.parametrize("change,field", BAD, ids=[next(iter(c)) for c, _ in BAD])
def test_each_rule_names_its_field(change, field):
    spec = CamSpec.from_dict(PARALLEL_INDEXER_SPEC_DICT)
    with pytest.raises(SpecError) as exc:
        spec.replace(**change)
    assert exc.value.field.startswith(field), str(exc.value)


def test_indexer_fields_on_another_body_are_refused():
    data = example_dict("default")
    data["indexer"] = {"stations": 8}
    with pytest.raises(SpecError) as exc:
        CamSpec.from_dict(data)
    assert exc.value.field == "indexer.stations"


@pytest.mark.parametrize("change,field", [BAD[0], BAD[3], BAD[8]], ids=["advance", "pitch_radius", "base_radius"])
def test_the_cli_refuses_with_status_2_and_writes_nothing(tmp_path, change, field):
    spec_file = tmp_path / "ix.toml"
    spec_file.write_text(dict_to_toml(PARALLEL_INDEXER_SPEC_DICT))
    out = tmp_path / "out"
    key, value = next(iter(change.items()))
    for command in ("check", "build"):
        r = subprocess.run([*CLI, command, str(spec_file), "-o", str(out), "--set", f"{key}={value}"],
                           capture_output=True, text=True, cwd=ROOT, stdin=subprocess.DEVNULL)
        assert r.returncode == 2, r.stderr
        assert field in r.stderr and "Traceback" not in r.stderr
        assert not out.exists()

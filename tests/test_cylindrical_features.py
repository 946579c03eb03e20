"""A cylindrical cam's hub, keyway, mounting holes and timing mark, against closed forms written here:

* the keyed bore: the bore circle plus the keyway, ∫_{−b/2}^{b/2} (r + t₂ − √(r² − x²)) dx =
  b(r + t₂) − (a√(r² − a²) + r² asin(a/r)), a = b/2 (DIN 6885-1 for a 20 mm bore: b = 6, t₂ = 2.8,
  the table's row, written here);
* the hub: π(R_h² − r²) × its length less the keyway's area × its length (the keyway runs through);
* the holes: n π r_h² L; the timing mark: its width × its length (the longest stretch of the ray
  of θ = 0 kept a mark's width clear of the first hole, worked out here) × its depth;
* the groove: w ∫ℓ(ρ)dρ by scipy.integrate.quad (as tests/test_cylindrical.py does);

the OCCT solid valid, one solid, its volume within 1e-6 relative of that closed form, its end face's
area, its z extent, STEP written and re-read; the refusals through the CLI (exit 2, the field named,
nothing written).
"""
from __future__ import annotations

import copy
import json
import math
import subprocess
import sys

import numpy as np
import pytest
from scipy import integrate

from cam_workbench.generators import design_cam
from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.spec.examples import EXAMPLES

from .conftest import ROOT, requires_ocp
from .test_cylindrical import RB, RO, W2, L, lift

R = 10.0                       # bore radius
B, T2 = 6.0, 2.8               # DIN 6885-1, bore over 17 up to 22 mm
HUB_D, HUB_L = 36.0, 15.0
N_HOLES, HOLE_D, CIRCLE_D = 4, 5.0, 46.0
MARK_W, MARK_D = 0.5, 0.2      # the mm defaults


def featured(**cam) -> dict:
    d = copy.deepcopy(EXAMPLES["cylindrical"])
    d["cam"].update(keyway="DIN6885", hub_diameter=HUB_D, hub_length=HUB_L, mounting_holes=N_HOLES,
                    mounting_hole_diameter=HOLE_D, mounting_circle_diameter=CIRCLE_D, timing_mark=True)
    for k, v in cam.items():
        if v is None:
            d["cam"].pop(k, None)
        else:
            d["cam"][k] = v
    return d


def keyway_area() -> float:
    a = B / 2
    return B * (R + T2) - (a * math.sqrt(R * R - a * a) + R * R * math.asin(a / R))


def mark_length() -> float:
    """The mark's ray from the keyway's corner + 1.5 w to R_o − 1.5 w, less the stretch within
    r_h + w of the first hole (on the same ray, at the mounting circle's radius): the longer piece."""
    r_in = math.hypot(R + T2, B / 2) + 1.5 * MARK_W
    r_out = RO - 1.5 * MARK_W
    lo, hi = CIRCLE_D / 2 - HOLE_D / 2 - MARK_W, CIRCLE_D / 2 + HOLE_D / 2 + MARK_W
    return max(lo - r_in, r_out - hi)


def groove_volume() -> float:
    def ell(rho):
        return sum(integrate.quad(lambda t: math.hypot(rho, float(lift(t)[1])), math.radians(a), math.radians(b),
                                  epsabs=1e-12, epsrel=1e-13)[0] for a, b in ((30, 150), (210, 330))) \
            + rho * math.radians(120)
    return 2 * W2 * integrate.quad(ell, RB, RO, epsabs=1e-10, epsrel=1e-12)[0]


def end_face_area() -> float:
    return math.pi * (RO ** 2 - R ** 2) - keyway_area() - N_HOLES * math.pi * (HOLE_D / 2) ** 2 \
        - MARK_W * mark_length()


def closed_form_volume() -> float:
    keyed = math.pi * R * R + keyway_area()
    cylinder = (math.pi * RO ** 2 - keyed) * L
    hub = (math.pi * (HUB_D / 2) ** 2 - keyed) * HUB_L
    holes = N_HOLES * math.pi * (HOLE_D / 2) ** 2 * L
    mark = MARK_W * mark_length() * MARK_D
    return cylinder + hub - holes - mark - groove_volume()


@pytest.fixture(scope="module")
def design():
    return design_cam(CamSpec.from_dict(featured()))


def test_features_described(design):
    roles = [p.role for p in design.body.stack]
    assert roles == ["cylinder", "hub", "hole0", "hole1", "hole2", "hole3", "timing_mark"]
    assert design.body.z_range == (-HUB_L, L)
    f = design.body_report["features"]
    assert f["bore_extent"] == pytest.approx(math.hypot(R + T2, B / 2), abs=1e-12)
    assert f["hole_ligaments"]["to_outer"] == pytest.approx(RB - 3.0 - CIRCLE_D / 2 - HOLE_D / 2, abs=1e-12)


def test_exact_volume_and_end_face_closed_form(design):
    assert design.volume == pytest.approx(closed_form_volume(), rel=1e-10)
    assert design.area == pytest.approx(end_face_area(), rel=1e-12)


@requires_ocp
def test_solid_volume_face_extent_and_step(design, tmp_path):
    from cam_workbench.kernel import solids as occ_build
    from cam_workbench.kernel import cylindrical as occ_cyl
    from cam_workbench.kernel import ocp as occ
    from cam_workbench.kernel.step import read_step, write_step

    shape = occ_build.cam_solid(design)
    assert occ_build.is_valid(shape) and occ_build.count_solids(shape) == 1
    rel = occ_build.kernel_volume(shape) / closed_form_volume() - 1
    print(f"OCCT volume vs closed form: {rel:.3e} relative")
    assert abs(rel) <= 1e-6
    top = occ_build.planar_face_at(shape, L)
    assert occ_build.face_area(top) == pytest.approx(end_face_area(), rel=1e-9)
    box = occ.Bnd_Box()
    occ.add_to_box(shape, box, optimal=True)
    assert np.allclose(occ.box_limits(box), (-RO, -RO, -HUB_L, RO, RO, L), atol=1e-5)
    wall = occ_cyl.cylindrical_wall_error(design, shape)
    assert wall["value"] <= 1e-6
    path = tmp_path / "cyl.step"
    write_step(shape, path, "mm")
    back = read_step(path, "mm")
    assert occ_build.is_valid(back) and occ_build.count_solids(back) == 1
    assert occ_build.kernel_volume(back) == pytest.approx(occ_build.kernel_volume(shape), rel=1e-7)


def _cli(tmp_path, d):
    from cam_workbench.generators.spec import dict_to_toml

    (tmp_path / "c.toml").write_text(dict_to_toml(d))
    return subprocess.run([sys.executable, "-m", "cam_workbench.cli", "build", str(tmp_path / "c.toml"), "-o",
                           str(tmp_path / "out")], capture_output=True, text=True, cwd=ROOT)


@requires_ocp
def test_cli_build_with_features(tmp_path):
    res = _cli(tmp_path, featured())
    assert res.returncode == 0, res.stderr
    rep = json.loads((tmp_path / "out" / "report.json").read_text())
    assert rep["volume"] == pytest.approx(closed_form_volume(), rel=1e-10)
    assert rep["solid"]["valid"] and abs(rep["solid"]["volume_rel_diff"]) <= 1e-6
    assert abs(rep["solid"]["area_rel_diff"]) <= 1e-9
    assert rep["body"]["wall_error"]["value"] <= 1e-6


@pytest.mark.parametrize("changes, message", [
    ({"mounting_circle_diameter": 64.0}, "cam.mounting_circle_diameter: the mounting holes (diameter 5 on a circle "
                                         "of 64) must stay inside the groove's bottom radius 36"),
    ({"mounting_circle_diameter": 30.0}, "cam.mounting_circle_diameter: the mounting holes (diameter 5 on a circle "
                                         "of 30) must clear the bore and keyway"),
    ({"mounting_holes": 16, "mounting_hole_diameter": 10.0}, "must not run into each other"),
    ({"keyway": None, "keyway_width": 6.0, "keyway_depth": 24.0}, "cam.keyway_depth: the keyway reaches"),
    ({"bore_diameter": 60.0, "keyway": "DIN6885", "mounting_holes": 0, "mounting_hole_diameter": None,
      "mounting_circle_diameter": None, "hub_diameter": 80.0}, "cam.keyway: the keyway reaches"),
    ({"timing_mark_depth": 16.0}, "cam.timing_mark_depth: must be < the groove's distance from the end face"),
    ({"timing_mark_width": 6.0}, "cam.timing_mark: no room"),
    ({"hub_length": None}, "cam.hub_length: is required"),
])
def test_refusals_through_the_cli(tmp_path, changes, message):
    res = _cli(tmp_path, featured(**changes))
    assert res.returncode == 2, res.stderr
    assert message in res.stderr, res.stderr
    assert "Traceback" not in res.stderr and not (tmp_path / "out").exists()

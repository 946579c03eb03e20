"""The cylindrical cam's solid sewn from its faces, without a boolean (issue 22 item 1:
``cam_workbench.kernel.cylindrical.sewn_groove_solid``), against computations written here:

* its faces: one B-spline face per wall surface, each the surface's patch between the groove's
  bottom and top radii (its parameter range read back from OCCT: θ over the motion segment, ρ from
  R_b to R_o exactly); one face on the cylinder R_b (the groove's bottom) and two on R_o (the outer
  face below and above the groove), the stack's other faces as they were;
* the walls' traces — the edges of the cylinder faces that are not circles — on their cylinders
  (their radius, OCCT's evaluator, within 1e-6 of R_b or R_o);
* its volume, by OCCT's adaptive integration (ε = 1e-12), against the closed forms of
  tests/test_cylindrical.py (the example) and tests/test_cylindrical_features.py (hub, keyway,
  holes, timing mark) to 1e-9; and the boolean construction it replaced
  (``boolean_groove_solid``, still the fallback) bounding the same volume;
* report.json's ``solid.volume_rule``: the rule OCCT's volume was measured by (its fixed Gauss
  rule) and the allowance, 5e-5 + 2·A·e/V with A = 2·V_groove/w (recomputed here from the report's
  numbers), which the measured difference keeps.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from cam_workbench.generators import design_cam
from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.spec.examples import EXAMPLES

from .conftest import requires_ocp
from .test_cylindrical import BORE, L, RB, RO, W2, lift
from .test_cylindrical_features import closed_form_volume, featured

pytestmark = requires_ocp

SPECS = {"example": EXAMPLES["cylindrical"], "featured": featured(),
         "oscillating": EXAMPLES["cylindrical_oscillating"]}


@pytest.fixture(scope="module", params=sorted(SPECS))
def built(request):
    """(name, design, the sewn solid, what cam_solid builds)."""
    from cam_workbench.kernel import cylindrical as occ_cyl
    from cam_workbench.kernel import solids as occ_build

    design = design_cam(CamSpec.from_dict(SPECS[request.param]))
    return request.param, design, occ_cyl.sewn_groove_solid(design), occ_build.cam_solid(design)


def _faces(shape):
    from cam_workbench.kernel.solids import faces_of

    return faces_of(shape)


def test_sewn_is_the_solid_valid_and_one(built):
    from cam_workbench.kernel import solids as occ_build

    name, design, sewn, solid = built
    assert sewn is not None, f"{name}: the groove's faces did not close (the boolean fallback ran)"
    assert occ_build.is_valid(sewn) and occ_build.count_solids(sewn) == 1
    assert len(_faces(solid)) == len(_faces(sewn))
    assert occ_build.kernel_volume(solid) == occ_build.kernel_volume(sewn)


def test_wall_faces_are_patches_and_three_cylinder_faces(built):
    from cam_workbench.kernel import ocp as occ

    name, design, sewn, _ = built
    lay = design.layout
    patches, radii = [], []
    for face in _faces(sewn):
        surf = occ.BRepAdaptor_Surface(face)
        if surf.GetType() == occ.GeomAbs_BSplineSurface:
            patches.append((surf.FirstUParameter(), surf.LastUParameter(), surf.FirstVParameter(),
                            surf.LastVParameter()))
        elif surf.GetType() == occ.GeomAbs_Cylinder:
            radii.append(surf.Cylinder().Radius())
    assert len(patches) == len(design.body.walls)
    want = sorted((*w.u_range, lay.bottom_radius, lay.outer_radius) for w in design.body.walls)
    np.testing.assert_allclose(sorted(patches), want, rtol=0, atol=1e-12)
    n_rb = sum(abs(r - lay.bottom_radius) < 1e-12 for r in radii)
    n_ro = sum(abs(r - lay.outer_radius) < 1e-12 for r in radii)
    assert (n_rb, n_ro) == (1, 2), (name, radii)


def test_traces_lie_on_their_cylinders(built):
    from cam_workbench.kernel import ocp as occ

    name, design, sewn, _ = built
    lay = design.layout
    worst, edges = 0.0, 0
    for face in _faces(sewn):
        surf = occ.BRepAdaptor_Surface(face)
        if surf.GetType() != occ.GeomAbs_Cylinder or surf.Cylinder().Radius() > lay.outer_radius + 1e-9:
            continue
        radius = surf.Cylinder().Radius()
        if radius < lay.bottom_radius - 1e-9:
            continue                                       # the bore
        ex = occ.TopExp_Explorer(face, occ.TopAbs_EDGE)
        while ex.More():
            curve = occ.BRepAdaptor_Curve(occ.topods_edge(ex.Current()))
            if curve.GetType() == occ.GeomAbs_BSplineCurve:
                for t in np.linspace(curve.FirstParameter(), curve.LastParameter(), 41):
                    p = curve.Value(float(t))
                    worst = max(worst, abs(math.hypot(p.X(), p.Y()) - radius))
                edges += 1
            ex.Next()
    assert edges >= 2 * len(design.body.walls), (name, edges)
    assert worst <= 1e-6, (name, worst)


def _example_volume() -> float:
    """π(R_o² − r²)L − w∫ℓ(ρ)dρ of the example, ℓ by quad on the lift of tests/test_cylindrical.py."""
    def ell(rho):
        return sum(integrate.quad(lambda t: math.hypot(rho, float(lift(t)[1])), math.radians(a), math.radians(b),
                                  epsabs=1e-12, epsrel=1e-13)[0] for a, b in ((30, 150), (210, 330))) \
            + rho * math.radians(120)
    return math.pi * (RO ** 2 - BORE ** 2) * L - 2 * W2 * integrate.quad(ell, RB, RO, epsabs=1e-10, epsrel=1e-12)[0]


@pytest.mark.parametrize("name", ["example", "featured"])
def test_sewn_volume_is_the_closed_form(name):
    from cam_workbench.kernel import cylindrical as occ_cyl
    from cam_workbench.kernel import solids as occ_build

    design = design_cam(CamSpec.from_dict(SPECS[name]))
    exact = _example_volume() if name == "example" else closed_form_volume()
    sewn = occ_cyl.sewn_groove_solid(design)
    rel = occ_build.kernel_volume(sewn, 1e-12) / exact - 1
    print(f"{name}: sewn solid vs the closed form {rel:.2e} (OCCT's adaptive rule, ε = 1e-12)")
    assert abs(rel) <= 1e-9


def test_the_boolean_fallback_bounds_the_same_solid():
    """The construction kept for faces that do not close: valid, one solid, the closed form's volume."""
    from cam_workbench.kernel import cylindrical as occ_cyl
    from cam_workbench.kernel import solids as occ_build

    design = design_cam(CamSpec.from_dict(SPECS["example"]))
    cut = occ_cyl.boolean_groove_solid(design)
    assert occ_build.is_valid(cut) and occ_build.count_solids(cut) == 1
    exact = _example_volume()
    assert abs(occ_build.kernel_volume(cut, 1e-6) / exact - 1) <= 1e-9
    assert occ_cyl.cylindrical_wall_error(design, cut)["faces"] >= len(design.body.walls)


@pytest.mark.parametrize("name", ["example", "oscillating"])
def test_report_states_the_volume_rule(name):
    from cam_workbench import Cam

    rep = Cam(SPECS[name]).report()
    solid, body = rep["solid"], rep["body"]
    rule = solid["volume_rule"]
    assert "fixed Gauss rule" in rule["what"]
    e = max(body["wall_fit_error"]["value"], body["wall_error"]["value"])
    area = 2 * body["groove_volume"] / body["groove_width"]
    assert rule["allowed"] == pytest.approx(5e-5 + 2 * area * e / rep["volume"], rel=1e-12)
    assert abs(solid["volume_rel_diff"]) <= rule["allowed"]
    assert solid["volume_rel_diff"] == pytest.approx(solid["kernel_volume"] / rep["volume"] - 1, abs=1e-15)

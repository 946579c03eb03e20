"""Solids through OCP: valid (BRepCheck), one solid, volume = cross-section × thickness,
STEP re-imported with the same volume, both rotation directions, both offset signs,
knife and roller, inch units; CadQuery and build123d objects."""
import math

import numpy as np
import pytest

from .conftest import requires_ocp

pytestmark = requires_ocp

VARIANTS = {
    "default": {},
    "cw": {"cam.direction": "cw"},
    "negative_offset": {"follower.offset": -10.0},
    "cw_negative_offset": {"cam.direction": "cw", "follower.offset": -10.0},
    "knife": {"follower.kind": "knife", "cam.bore_diameter": 8.0},
    "no_bore": {"cam.bore_diameter": 0.0},
    "inch": {"units": "in", "cam.thickness": 0.5, "cam.base_radius": 2.0, "follower.offset": 0.3,
             "follower.roller_radius": 0.25, "cam.bore_diameter": 0.5, "motion[1].lift": 0.8,
             "motion[3].lift": 0.8},
    # the other follower kinds (arm degrees for the oscillating ones)
    "oscillating_roller": {"follower.motion": "oscillating", "follower.pivot_distance": 60.0,
                           "follower.arm_length": 45.0, "follower.mass": 0.0, "follower.preload": 0.0,
                           "follower.spring_rate": 0.0, "motion[1].lift": 15.0, "motion[3].lift": 15.0},
    "oscillating_knife_cw": {"follower.motion": "oscillating", "follower.kind": "knife", "cam.direction": "cw",
                             "follower.pivot_distance": 55.0, "follower.arm_length": 40.0, "follower.mass": 0.0,
                             "follower.preload": 0.0, "follower.spring_rate": 0.0, "motion[1].lift": 12.0,
                             "motion[3].lift": 12.0},
    "flat": {"follower.kind": "flat"},
    "oscillating_flat": {"follower.motion": "oscillating", "follower.kind": "flat", "follower.pivot_distance": 70.0,
                         "follower.face_offset": 5.0, "follower.mass": 0.0, "follower.preload": 0.0,
                         "follower.spring_rate": 0.0, "motion[1].lift": 12.0, "motion[3].lift": 12.0},
}


@pytest.fixture(scope="module", params=sorted(VARIANTS))
def cam(request):
    from cam_workbench import PlateCam

    return PlateCam(**VARIANTS[request.param])


def test_valid_single_solid(cam):
    from cam_workbench.kernel import solids as occ_build

    assert occ_build.is_valid(cam.shape)
    assert occ_build.count_solids(cam.shape) == 1


def test_volume_equals_cross_section_times_thickness(cam):
    from cam_workbench.kernel import solids as occ_build

    d = cam.design
    # independent cross-section: OCCT's own evaluation of the edges, shoelace
    top = occ_build.planar_face_at(cam.shape, cam.spec.cam.thickness)
    assert occ_build.face_area_shoelace(top) == pytest.approx(d.area, rel=2e-6)
    # kernel volume (exact on Bézier edges) against Green's theorem × thickness
    assert occ_build.kernel_volume(cam.shape) == pytest.approx(d.area * cam.spec.cam.thickness, rel=1e-9)


def test_solid_dimensions(cam):
    from cam_workbench.kernel import solids as occ_build
    from cam_workbench.kernel import ocp as occ

    box = occ.Bnd_Box()
    occ.add_to_box(cam.shape, box, optimal=True)
    xmin, ymin, zmin, xmax, ymax, zmax = occ.box_limits(box)
    assert zmin == pytest.approx(0.0, abs=2e-7) and zmax == pytest.approx(cam.spec.cam.thickness, abs=2e-7)
    u, pts = cam.design.profile.sample(64)
    rmax = np.max(np.hypot(pts[:, 0], pts[:, 1]))
    assert max(abs(xmin), abs(xmax), abs(ymin), abs(ymax)) <= rmax * (1 + 1e-6)
    del occ_build


def test_step_roundtrip_same_volume(cam, tmp_path):
    from cam_workbench.kernel import solids as occ_build
    from cam_workbench.kernel.step import read_step

    path = cam.export_step(tmp_path / "cam.step")
    units = cam.spec.units
    back = read_step(path, units)
    assert occ_build.is_valid(back)
    assert occ_build.kernel_volume(back) == pytest.approx(cam.volume, rel=1e-9)
    if units == "in":  # the file declares inches: read in mm it is 25.4³ larger
        in_mm = read_step(path, "mm")
        assert occ_build.kernel_volume(in_mm) == pytest.approx(cam.volume * 25.4**3, rel=1e-9)
        assert "'INCH'" in path.read_text()


def test_profile_is_at_roller_distance_from_pitch(cam):
    d = cam.design
    u, pts = d.profile.sample(9)
    seg = np.minimum(u.astype(int), d.pitch.M - 1)
    p = d.pitch.spline.point(seg, u - seg)
    dist = np.abs(pts[:, 0] + 1j * pts[:, 1] - p)
    assert np.allclose(dist, cam.spec.roller_radius, rtol=0, atol=1e-9 * max(1.0, cam.spec.roller_radius))


#: where the tests of one CAD library run when this environment lacks it (each brings its own OCP
#: build, so the dev venv has CadQuery's; tests/test_install_envs.py runs this file under build123d)
ELSEWHERE = "not installed here; runs in the build123d environment of tests/test_install_envs.py"


def test_build123d_objects():
    bd = pytest.importorskip("build123d", reason=f"build123d {ELSEWHERE}")
    from cam_workbench import PlateCam
    from cam_workbench.kernel import ocp as occ

    cam = PlateCam()
    part = cam.part()
    assert isinstance(part, bd.Part) and part.volume == pytest.approx(cam.volume, rel=1e-9)
    assert occ.is_valid(part.wrapped) and len(part.solids()) == 1
    # ordinary build123d on the result: a hub on top, the bore through
    hub = bd.Pos(0, 0, 10) * bd.Cylinder(14, 8, align=(bd.Align.CENTER, bd.Align.CENTER, bd.Align.MIN))
    body = part + hub - bd.Cylinder(6, 40)
    assert occ.is_valid(body.wrapped)
    assert body.volume == pytest.approx(cam.volume + math.pi * (14**2 - 6**2) * 8, rel=1e-6)


def test_cadquery_objects():
    cq = pytest.importorskip("cadquery", reason="CadQuery is not installed here (the [cadquery] extra)")
    from cam_workbench import PlateCam, plate_cam, register

    cam = PlateCam()
    assert isinstance(cam.solid(), cq.Solid) and cam.solid().isValid()
    wp = cam.workplane()
    assert isinstance(wp, cq.Workplane)
    assert wp.val().Volume() == pytest.approx(cam.volume, rel=1e-9)
    # plain function and the opt-in Workplane method
    assert plate_cam().val().Volume() == pytest.approx(cam.volume, rel=1e-9)
    register()
    placed = cq.Workplane("XY").workplane(offset=5).plateCam()
    bb = placed.val().BoundingBox()
    assert bb.zmin == pytest.approx(5.0, abs=1e-6) and bb.zmax == pytest.approx(15.0, abs=1e-6)
    # a keyway cut with ordinary CadQuery works on the result
    keyed = wp.cut(cq.Workplane("XY").center(0, 5).rect(3, 4).extrude(10))
    assert keyed.val().isValid() and keyed.val().Volume() < cam.volume
    assert cam.profile_edge().geomType() == "BSPLINE"

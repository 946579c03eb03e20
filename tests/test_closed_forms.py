"""Closed forms: a radial follower with a simple-harmonic rise over 180° and return over 180°
has the limaçon pitch curve r(θ) = R_b + h/2·(1 − cos θ).  Its pressure angle,
radius of curvature and area are known in closed form; both the design-intent formulas
(from s(θ)) and the built PH curve must reproduce them."""
import numpy as np
import pytest
from scipy.integrate import quad

from cam_workbench.generators import design_cam
from cam_workbench.generators.followers.translating import FollowerGeometry
from cam_workbench.generators.spec import CamSpec

RB, H, RR = 30.0, 12.0, 4.0


def limacon_spec(kind="roller", direction="ccw", segments=180):
    return CamSpec.from_dict({
        "cam": {"base_radius": RB, "thickness": 8.0, "direction": direction},
        "follower": {"kind": kind, "offset": 0.0, "roller_radius": RR},
        "motion": [{"kind": "rise", "angle": 180, "lift": H, "law": "harmonic"},
                   {"kind": "return", "angle": 180, "lift": H, "law": "harmonic"}],
        "pitch": {"segments": segments},
    })


def r(t):
    return RB + H / 2 * (1 - np.cos(t))


def r1(t):
    return H / 2 * np.sin(t)


def r2(t):
    return H / 2 * np.cos(t)


def pressure_angle(t):
    return np.arctan2(r1(t), r(t))  # radial follower: tan φ = r'/r


def radius_of_curvature(t):
    return (r(t) ** 2 + r1(t) ** 2) ** 1.5 / (r(t) ** 2 + 2 * r1(t) ** 2 - r(t) * r2(t))


@pytest.mark.parametrize("direction", ["ccw", "cw"])
def test_design_intent_formulas(direction):
    spec = limacon_spec(direction=direction)
    d = design_cam(spec)
    th, k = d.design_kinematics()
    geo = FollowerGeometry.from_spec(spec)
    sign = 1 if direction == "ccw" else 1  # radial follower: the same in both directions
    assert np.allclose(geo.pressure_angle(k), sign * pressure_angle(th), atol=1e-13)
    assert np.allclose(geo.pitch_radius_of_curvature(k), radius_of_curvature(th), rtol=1e-12)


@pytest.mark.parametrize("direction", ["ccw", "cw"])
def test_built_ph_curve_matches_the_limacon(direction):
    d = design_cam(limacon_spec(direction=direction))
    cs = d.curvature_samples
    th = np.deg2rad(cs.cam_angle_deg)
    # built curve radius at each sample against r(θ) at the sample's cam angle
    assert np.max(np.abs(np.abs(cs.point) - r(th))) < 2e-7  # PH interpolation error at M = 180
    assert np.allclose(cs.radius, radius_of_curvature(th), rtol=1e-4)
    s = d.summary()
    phi_max = np.rad2deg(np.max(pressure_angle(np.linspace(0, np.pi, 200001))))
    assert s["pressure_angle"]["max_deg"] == pytest.approx(phi_max, abs=1e-6)
    assert s["pressure_angle"]["as_built"]["max_deg"] == pytest.approx(phi_max, abs=1e-4)
    rho_min = radius_of_curvature(np.linspace(0, 2 * np.pi, 400001)).min()
    assert s["curvature"]["min_pitch_radius"] == pytest.approx(rho_min, rel=1e-9)
    assert s["curvature"]["min_profile_radius"] == pytest.approx(rho_min - RR, rel=1e-9)


def test_areas_against_closed_forms():
    """Limaçon area π(a² + b²/2), a = R_b + h/2, b = h/2; the roller profile (inner offset)
    by Steiner's formula A − L·r + π r² with L the limaçon's perimeter by quadrature."""
    a, b = RB + H / 2, H / 2
    area_pitch = np.pi * (a * a + b * b / 2)
    perimeter = quad(lambda t: np.hypot(r(t), r1(t)), 0, 2 * np.pi, epsabs=0, epsrel=1e-13, limit=200)[0]
    knife = design_cam(limacon_spec(kind="knife", segments=360))
    assert knife.area == pytest.approx(area_pitch, rel=1e-10)
    roller = design_cam(limacon_spec(segments=360))
    assert roller.area == pytest.approx(area_pitch - perimeter * RR + np.pi * RR**2, rel=1e-10)
    assert roller.pitch.spline.arc_length == pytest.approx(perimeter, rel=1e-10)


def test_convergence_orders():
    """Doubling M divides the position error by ~16 (O(h⁴)) and the curvature error by ~4 (O(h²))."""
    pos, curv = [], []
    for m in (180, 360, 720):
        cs = design_cam(limacon_spec(segments=m)).curvature_samples
        th = np.deg2rad(cs.cam_angle_deg)
        pos.append(np.max(np.abs(np.abs(cs.point) - r(th))))
        curv.append(np.max(np.abs(cs.radius / radius_of_curvature(th) - 1)))
    assert pos[0] / pos[1] > 12 and pos[1] / pos[2] > 12
    assert curv[0] / curv[1] > 3.5 and curv[1] / curv[2] > 3.5

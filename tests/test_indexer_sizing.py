"""An indexer drive's sizing (generators.bodies.indexing.sizing) against computations written here: the
peak-acceleration identity, the cycloidal law's torque and power in closed form, virtual work,
ISO 281's life and equivalent load, Hertz's cylinder on a plane (Johnson's constants), and
random valid loads with hypothesis.

No published worked indexer example is checked: none with printed numbers was at hand."""
from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest
from hypothesis import example, given, settings, strategies as st

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.bodies.indexing import IndexLoad, drive_sizing, equivalent_load, rating_life
from cam_workbench.generators.motion.laws import LAW_FUNCTIONS

PI = math.pi
LAWS = sorted(LAW_FUNCTIONS)
#: C_a = max|f''| in closed form (derived in tests/test_law_characteristics.py)
C_A = {"cycloidal": 2 * PI, "harmonic": PI**2 / 2, "poly345": 10 / math.sqrt(3),
       "poly4567": 84 * math.sqrt(5) / 25, "modified_sine": 4 * PI**2 / (PI + 4),
       "modified_trapezoid": 8 * PI / (PI + 2)}


def make_load(**kw) -> IndexLoad:
    base = dict(stations=8, index_angle=math.radians(120), input_speed=100.0, inertia=0.5,
                friction_torque=0.0, law="cycloidal", pitch_radius=0.1, roller_radius=0.015,
                roller_width=0.012, roller_rating=20_000.0)
    base.update(kw)
    return IndexLoad(**base)


def times(load: IndexLoad) -> tuple[float, float, float]:
    """(step h [rad], ω_in [rad/s], index time t_i [s]) computed here."""
    h = 2 * PI / load.stations
    w = 2 * PI * load.input_speed / 60
    t_i = (load.index_angle / (2 * PI)) * 60 / load.input_speed
    return h, w, t_i


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("stations, beta_deg, rpm", [(4, 90, 60), (8, 120, 100), (24, 270, 300)])
def test_peak_acceleration_identity(law, stations, beta_deg, rpm):
    load = make_load(law=law, stations=stations, index_angle=math.radians(beta_deg), input_speed=rpm)
    d = drive_sizing(load, theta=np.linspace(0, load.index_angle, 20001))
    h, w, t_i = times(load)
    assert d.index_time == pytest.approx(t_i, rel=1e-15)
    assert d.dwell_time == pytest.approx(60 / rpm - t_i, rel=1e-13)
    peak = C_A[law] * h / t_i**2
    assert d.alpha_out_peak == pytest.approx(peak, rel=1e-13)
    # the sampled acceleration reaches it (to the grid's resolution) and never exceeds it
    assert np.abs(d.alpha_out).max() <= peak * (1 + 1e-13)
    assert np.abs(d.alpha_out).max() == pytest.approx(peak, rel=1e-7)
    # and, with no friction, the output torque's peak is J times it
    assert d.torque_out_peak == pytest.approx(load.inertia * peak, rel=1e-13)


@pytest.mark.parametrize("t_f", [0.0, 3.0])
def test_cycloidal_torque_and_power_in_closed_form(t_f):
    load = make_load(friction_torque=t_f, inertia=0.8, input_speed=150.0, index_angle=math.radians(100))
    theta = np.linspace(0.0, load.index_angle, 3001)
    d = drive_sizing(load, theta=theta)
    h, w, t_i = times(load)
    beta, J = load.index_angle, load.inertia
    phi = 2 * PI * theta / beta
    # ψ = h(θ/β − sin φ/2π); ω_out = (h/t_i)(1 − cos φ); α_out = (2πh/t_i²) sin φ
    omega = h / t_i * (1 - np.cos(phi))
    alpha = 2 * PI * h / t_i**2 * np.sin(phi)
    friction = np.where((phi > 0) & (phi < 2 * PI), t_f, 0.0)
    t_out = J * alpha + friction
    t_in = t_out * h / beta * (1 - np.cos(phi))
    scale = J * 2 * PI * h / t_i**2 + t_f
    np.testing.assert_allclose(d.psi, h * (theta / beta - np.sin(phi) / (2 * PI)), atol=1e-15)
    np.testing.assert_allclose(d.omega_out, omega, rtol=0, atol=1e-13 * h / t_i)
    np.testing.assert_allclose(d.alpha_out, alpha, rtol=0, atol=1e-13 * h / t_i**2)
    np.testing.assert_allclose(d.torque_out, t_out, rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(d.torque_in, t_in, rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(d.power_in, t_in * w, rtol=0, atol=1e-13 * scale * w)
    if t_f == 0:
        # T_in = J(2πh/t_i²)(h/β)(1 − cos φ) sin φ, largest at φ = 2π/3 (θ = β/3): × 3√3/4
        peak = J * 2 * PI * h / t_i**2 * h / beta * 3 * math.sqrt(3) / 4
        assert d.torque_in_peak == pytest.approx(peak, rel=1e-13)
        assert d.torque_in_peak_at == pytest.approx(beta / 3, rel=1e-7)
        assert d.power_in_peak == pytest.approx(J * 2 * PI * h**2 / t_i**3 * 3 * math.sqrt(3) / 4, rel=1e-13)
    else:
        # the closed form's largest value on a fine grid (its maximum has no neat closed form)
        fine = np.linspace(0.0, 2 * PI, 2_000_001)
        t_in_fine = (J * 2 * PI * h / t_i**2 * np.sin(fine) + t_f) * h / beta * (1 - np.cos(fine))
        assert d.torque_in_peak >= np.abs(t_in_fine).max() * (1 - 1e-15)
        assert d.torque_in_peak == pytest.approx(np.abs(t_in_fine).max(), rel=1e-11)
    # the energy balance: over the index the kinetic energy returns to 0, friction's work remains
    assert d.power_in_mean == pytest.approx(t_f * h / t_i, rel=1e-9, abs=1e-9 * J * h**2 / t_i**3)


def test_cycloidal_mean_power_with_an_efficiency():
    """η < 1: ÷η while the cam drives, ×η while the output drives back; integrated by hand."""
    eta, t_f = 0.8, 2.0
    load = make_load(friction_torque=t_f, efficiency=eta)
    d = drive_sizing(load)
    h, w, t_i = times(load)
    A = load.inertia * 2 * PI * h / t_i**2  # amplitude of J·α_out
    # T_out·ψ' = (h/β)(1 − cos φ)(A sin φ + T_f): negative for φ ∈ (π + asin(T_f/A), 2π − asin(T_f/A))
    assert t_f < A
    p1, p2 = PI + math.asin(t_f / A), 2 * PI - math.asin(t_f / A)

    def G(p):  # ∫(1 − cos φ)(A sin φ + T_f) dφ
        return -A * math.cos(p) - A / 2 * math.sin(p) ** 2 + t_f * (p - math.sin(p))

    integral = (G(p1) - G(0)) / eta + eta * (G(p2) - G(p1)) + (G(2 * PI) - G(p2)) / eta
    mean_t_in = h / load.index_angle * integral / (2 * PI)  # mean over φ ∈ [0, 2π]
    assert d.power_in_mean == pytest.approx(mean_t_in * w, rel=1e-8)
    assert d.power_in_mean > t_f * h / t_i  # the losses cost power


@settings(max_examples=60, deadline=None)
@example(law="cycloidal", stations=2, beta=1.0, rpm=3.0, inertia=3.0, t_f=0.0, r_p=0.5, roller=0.25,
         width=0.03125, rating=1000.0, eta=1.0, p=3.0)
@given(law=st.sampled_from(LAWS), stations=st.integers(2, 36), beta=st.floats(0.2, 6.0),
       rpm=st.floats(1.0, 1000.0), inertia=st.floats(1e-4, 100.0), t_f=st.floats(0.0, 50.0),
       r_p=st.floats(0.02, 0.5), roller=st.floats(0.05, 0.3), width=st.floats(0.004, 0.05),
       rating=st.floats(1e3, 1e6), eta=st.floats(0.5, 1.0), p=st.sampled_from([3.0, 10.0 / 3.0]))
def test_hypothesis_random_loads(law, stations, beta, rpm, inertia, t_f, r_p, roller, width, rating, eta, p):
    load = make_load(law=law, stations=stations, index_angle=beta, input_speed=rpm, inertia=inertia,
                     friction_torque=t_f, pitch_radius=r_p, roller_radius=roller * r_p, roller_width=width,
                     roller_rating=rating, efficiency=eta, life_exponent=p)
    theta = np.concatenate([np.linspace(0.0, beta, 801), np.linspace(beta, 2 * PI, 202)[1:]])
    d = drive_sizing(load, theta=theta)
    arrays = [d.psi, d.dpsi, d.ddpsi, d.omega_out, d.alpha_out, d.torque_out, d.torque_in, d.power_in,
              d.normal_force, d.contact_stress]
    assert all(np.all(np.isfinite(a)) for a in arrays)
    scalars = [d.index_time, d.dwell_time, d.omega_out_peak, d.alpha_out_peak, d.torque_out_peak,
               d.torque_in_peak, d.power_in_peak, d.normal_force_peak,
               d.contact_stress_peak, d.equivalent_load, d.l10, d.l10_hours]
    assert all(math.isfinite(s) and s >= 0 for s in scalars)
    # the mean input power is the friction's (≥ 0); without friction the kinetic energy given to
    # the output over the index comes back: 0 to rounding of the peak (found: −7.4e-16 W at a peak of 7.5 W)
    assert math.isfinite(d.power_in_mean) and d.power_in_mean >= -1e-12 * d.power_in_peak
    h, w, t_i = times(load)
    index, dwell = theta <= beta, theta > beta
    first, second = index & (theta < beta / 2), index & (theta > beta / 2)
    # the inertia's torque accelerates then decelerates (every law is antisymmetric in f'')
    inertial = d.torque_out - t_f * np.sign(d.omega_out)
    tiny = 1e-12 * (inertia * d.alpha_out_peak + t_f)  # rounding of J·α + T_f − T_f
    assert np.all(inertial[first] >= -tiny) and np.all(inertial[second] <= tiny)
    assert np.all(d.torque_out[first] >= -tiny)
    # friction acts only while the output moves, and then fully
    assert np.all(d.omega_out[index] >= 0)
    np.testing.assert_array_equal(np.sign(d.omega_out) * t_f, np.where(d.omega_out > 0, t_f, 0.0))
    # the camshaft torque has the output torque's sign (ψ' ≥ 0)
    assert np.all(d.torque_in * d.torque_out >= 0)
    # the dwell: the output at rest at 2π/N, nothing loaded
    assert np.all(d.psi[dwell] == h)
    for a in (d.dpsi, d.ddpsi, d.omega_out, d.alpha_out, d.torque_out, d.torque_in, d.power_in,
              d.normal_force, d.contact_stress):
        assert np.all(a[dwell] == 0)
    assert d.psi[0] == 0 and d.psi[index][-1] == pytest.approx(h, rel=1e-14)
    # peaks: the refined ones are never below the samples
    assert d.torque_out_peak >= np.abs(d.torque_out).max() * (1 - 1e-14)
    assert d.torque_in_peak >= np.abs(d.torque_in).max() * (1 - 1e-14)
    assert d.normal_force_peak == np.abs(d.normal_force).max()
    # virtual work with η = 1
    d1 = drive_sizing(dataclasses.replace(load, efficiency=1.0), theta=theta)
    np.testing.assert_allclose(d1.torque_in * d1.input_omega, d1.torque_out * d1.omega_out,
                               rtol=1e-13, atol=1e-13 * d1.torque_out_peak * d1.omega_out_peak)
    json.dumps(d.summary(), allow_nan=False)


@pytest.mark.parametrize("law", LAWS)
def test_virtual_work_at_every_theta(law):
    load = make_load(law=law, friction_torque=1.5)
    d = drive_sizing(load)
    # T_in·ω_in = T_out·ω_out, ω_out = ψ'·ω_in: the power through a lossless contact
    np.testing.assert_allclose(d.power_in, d.torque_out * d.omega_out, rtol=1e-14,
                               atol=1e-14 * d.torque_out_peak * d.omega_out_peak)


def test_life_of_a_constant_load_is_the_rating_ratio_to_the_p():
    for p in (3.0, 10.0 / 3.0):
        for f in (123.0, 4567.0):
            p_eq = equivalent_load(np.full(7, f), np.array([0.1, 2, 3, 0.5, 1, 1, 9]), p)
            assert p_eq == pytest.approx(f, rel=1e-15)
            assert rating_life(25_000.0, p_eq, p) == pytest.approx((25_000.0 / f) ** p, rel=1e-14)
    assert rating_life(1e4, 0.0, 3.0) == math.inf


def test_equivalent_load_of_two_levels_by_hand():
    # 1000 N for 3 revolutions, 2000 N for 1: P = ((3·1000³ + 1·2000³)/4)^(1/3) = (2.75e9)^(1/3)
    assert equivalent_load(np.array([1000.0, 2000.0]), np.array([3.0, 1.0]), 3.0) == pytest.approx(
        (2.75e9) ** (1 / 3), rel=1e-15)
    # p = 10/3: the same mean of F^(10/3)
    p = 10 / 3
    ref = ((3 * 1000.0**p + 2000.0**p) / 4) ** (1 / p)
    assert equivalent_load(np.array([1000.0, 2000.0]), np.array([3.0, 1.0]), p) == pytest.approx(ref, rel=1e-15)
    assert equivalent_load(np.array([5.0]), np.array([0.0]), 3.0) == 0.0


def test_life_of_a_friction_only_load_through_the_drive():
    """J → 0: the roller carries T_f/R_p while the output moves; the roller turns R_p·h/(2π r_r)
    per index (the documented rolling assumption), one index per input turn."""
    load = make_load(inertia=1e-30, friction_torque=20.0, law="poly345", life_exponent=10 / 3)
    d = drive_sizing(load)
    f = load.friction_torque / load.pitch_radius
    assert d.equivalent_load == pytest.approx(f, rel=1e-9)
    l10 = (load.roller_rating / f) ** (10 / 3)
    assert d.l10 == pytest.approx(l10, rel=1e-8)
    revs = load.pitch_radius * (2 * PI / load.stations) / (2 * PI * load.roller_radius)
    assert d.roller_revolutions == pytest.approx(revs, rel=1e-14)
    assert d.l10_hours == pytest.approx(l10 * 1e6 / (revs * load.input_speed * 60), rel=1e-8)


def test_contact_arc_replaces_the_rolling_assumption():
    load = make_load(inertia=1e-30, friction_torque=20.0)
    theta = np.linspace(0.0, load.index_angle, 1001)
    arc = 0.3 * theta  # e.g. a contact travelling 0.3 m per radian of input
    d = drive_sizing(load, theta=theta, contact_arc=arc)
    assert d.roller_revolutions == pytest.approx(0.3 * load.index_angle / (2 * PI * load.roller_radius), rel=1e-14)
    assert "contact path" in d.rolling_note


def _hertz_line_contact(force, r1, r2, length, e1, nu1, e2, nu2):
    """Johnson, *Contact Mechanics* (1985) §4.3: two parallel cylinders, load P' = F/L per unit
    length, 1/R = 1/R₁ + 1/R₂, 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂; half-width a = √(4P'R/(πE*)),
    peak pressure p₀ = 2P'/(πa) — which is √(P'E*/(πR))."""
    e_star = 1 / ((1 - nu1**2) / e1 + (1 - nu2**2) / e2)
    inv_r = 1 / r1 + (0.0 if math.isinf(r2) else 1 / r2)
    p_line = force / length
    a = np.sqrt(4 * p_line / (PI * e_star * inv_r))
    p0 = np.where(force > 0, 2 * p_line / (PI * np.where(a > 0, a, 1.0)), 0.0)
    np.testing.assert_allclose(p0, np.sqrt(p_line * e_star * inv_r / PI), rtol=1e-13)
    return p0


@pytest.mark.parametrize("cam_radius", [math.inf, 0.05, -0.2])
def test_hertz_stress_cylinder_on_plane_and_on_cylinders(cam_radius):
    load = make_load(law="modified_sine", friction_torque=1.0, e_cam=210e9, nu_cam=0.29,
                     e_roller=200e9, nu_roller=0.31)
    d = drive_sizing(load, cam_radius=None if math.isinf(cam_radius) else cam_radius)
    ref = _hertz_line_contact(d.normal_force, load.roller_radius, cam_radius, load.roller_width,
                              load.e_cam, load.nu_cam, load.e_roller, load.nu_roller)
    np.testing.assert_allclose(d.contact_stress, ref, rtol=1e-13, atol=1e-9)
    assert d.contact_stress_peak == pytest.approx(ref.max(), rel=1e-15)
    # F_n = |T_out|/R_p by default, and the peak stress sits at the peak force
    np.testing.assert_allclose(d.normal_force, np.abs(d.torque_out) / load.pitch_radius, rtol=1e-15)
    assert d.contact_stress_peak_at == d.normal_force_peak_at


def test_moment_arm_scales_the_normal_force():
    load = make_load()
    theta = np.linspace(0.0, load.index_angle, 501)
    arm = 0.1 * (1 + 0.3 * np.sin(theta))
    d = drive_sizing(load, theta=theta, arm=arm)
    np.testing.assert_allclose(d.normal_force, np.abs(d.torque_out) / arm, rtol=1e-15)


def test_the_holding_contact_carries_the_decelerating_load():
    """A form-closed drive: where the output decelerates (T_out < 0) the holding-back contact's arm
    and radius carry the load, the driving one's elsewhere; the torque computed here."""
    load = make_load()
    h, w, t_i = times(load)
    theta = np.linspace(0.0, load.index_angle, 801)
    x = theta / load.index_angle
    torque = load.inertia * h * 2 * PI * np.sin(2 * PI * x) * (w / load.index_angle) ** 2  # cycloidal J·α
    arm, back = np.full_like(theta, 0.08), np.full_like(theta, 0.05)
    d = drive_sizing(load, theta=theta, arm=arm, arm_back=back, cam_radius=0.2, cam_radius_back=-0.04)
    expect = np.abs(torque) / np.where(torque < 0, back, arm)
    np.testing.assert_allclose(d.normal_force, expect, rtol=1e-9, atol=1e-9 * np.abs(expect).max())
    # the concave holding contact (radius −0.04 m) raises the stress where it carries the load
    e_star = 1 / (2 * (1 - 0.3**2) / 206e9)
    k = np.where(torque < 0, 1 / load.roller_radius - 1 / 0.04, 1 / load.roller_radius + 1 / 0.2)
    np.testing.assert_allclose(d.contact_stress, np.sqrt(expect * e_star * k / (PI * load.roller_width)), rtol=1e-9)


def test_undercut_stress_is_infinite_and_summarised_as_none():
    load = make_load()
    d = drive_sizing(load, cam_radius=-0.5 * load.roller_radius)  # a hollow smaller than the roller
    assert d.contact_stress_peak == math.inf
    s = d.summary()
    assert s["contact_stress_peak_Pa"] is None and "infinite" in s["contact_stress_peak_Pa_note"]


def test_summary_is_plain_json():
    d = drive_sizing(make_load(law="harmonic", friction_torque=2.0, efficiency=0.9))
    s = d.summary()

    def plain(v):
        if isinstance(v, dict):
            return all(isinstance(k, str) and plain(x) for k, x in v.items())
        return v is None or type(v) in (int, float, str)

    assert plain(s)
    text = json.dumps(s, allow_nan=False)
    assert '"C_j": null' in text and "C_j_note" in text
    h, w, t_i = times(d.load)
    assert s["index_time_s"] == pytest.approx(t_i) and s["stations"] == 8
    assert s["output_acceleration_peak_rad_s2"] == pytest.approx(PI**2 / 2 * h / t_i**2, rel=1e-13)
    for key in ("input_torque_peak_Nm", "input_power_peak_W", "input_power_mean_index_W", "normal_force_peak_N",
                "contact_stress_peak_Pa", "l10_million_rev", "l10_hours", "roller_equivalent_load_N"):
        assert isinstance(s[key], float)


@pytest.mark.parametrize("field, value", [
    ("stations", 1), ("stations", 2.5), ("stations", True), ("stations", "6"),
    ("index_angle", 0.0), ("index_angle", 2 * PI), ("index_angle", float("nan")), ("index_angle", -1.0),
    ("input_speed", 0.0), ("input_speed", float("inf")), ("inertia", -1.0), ("inertia", 0.0),
    ("friction_torque", -0.1), ("friction_torque", float("nan")), ("law", "parabolic"),
    ("pitch_radius", 0.0), ("roller_radius", -0.01), ("roller_width", 0.0), ("roller_rating", 0.0),
    ("e_cam", 0.0), ("e_roller", -2e11), ("nu_cam", 0.6), ("nu_roller", -1.0),
    ("life_exponent", 0.0), ("efficiency", 0.0), ("efficiency", 1.2),
])
def test_bad_inputs_are_refused_by_field(field, value):
    with pytest.raises(SpecError) as err:
        make_load(**{field: value})
    assert err.value.field == f"indexer.{field}"


def test_numpy_integer_stations_are_accepted():
    assert drive_sizing(make_load(stations=np.int64(6))).summary()["stations"] == 6


@pytest.mark.parametrize("kw, field", [
    (dict(theta=np.array([0.0, 0.5, 0.4])), "indexer.theta"),
    (dict(theta=np.array([-0.1, 0.5])), "indexer.theta"),
    (dict(theta=np.array([0.0, 7.0])), "indexer.theta"),
    (dict(theta=np.array([1.0])), "indexer.theta"),
    (dict(arm=0.0), "indexer.arm"),
    (dict(arm=np.array([0.1, 0.2])), "indexer.arm"),
    (dict(cam_radius=0.0), "indexer.cam_radius"),
    (dict(contact_arc=np.linspace(1.0, 0.0, 4097)), "indexer.contact_arc"),
])
def test_bad_arrays_are_refused_by_field(kw, field):
    with pytest.raises(SpecError) as err:
        drive_sizing(make_load(), **kw)
    assert err.value.field == field


def test_a_parallel_indexers_drive_balances_the_contact_force_about_the_input_axis():
    """parallel_drive: the input torque by virtual work equals the carrying contact's normal force
    times its own moment arm about the INPUT axis (the design's arm_O, which the sizing does not
    read), at every input angle of the index."""
    from cam_workbench.generators.bodies.indexing.parallel import ParallelIndexer, design_parallel
    from cam_workbench.generators.bodies.indexing.parallel_drive import parallel_drive

    d = design_parallel(ParallelIndexer())
    s = parallel_drive(d, input_speed=60, inertia=2.0, friction_torque=5.0, roller_width=12.0,
                       roller_rating=12_000.0)
    ix = d.indexer
    over = d.theta - ix.index_start <= ix.index_angle * (1 + 1e-12)
    arm_p = np.concatenate([c.arm_p for c in d.cams], axis=1)[over]
    arm_o = np.concatenate([c.arm_o for c in d.cams], axis=1)[over]
    fwd = np.where(np.isfinite(arm_p) & (arm_p > 0), arm_p, -np.inf)
    bwd = np.where(np.isfinite(arm_p) & (arm_p < 0), -arm_p, -np.inf)
    rows = np.arange(arm_p.shape[0])
    pick = np.where(s.torque_out >= 0, np.argmax(fwd, axis=1), np.argmax(bwd, axis=1))
    expect = s.normal_force * np.abs(arm_o[rows, pick]) * 1e-3
    moving = s.normal_force > 1e-9 * s.normal_force.max()
    np.testing.assert_allclose(np.abs(s.torque_in[moving]), expect[moving], rtol=1e-9,
                               atol=1e-9 * np.abs(s.torque_in).max())

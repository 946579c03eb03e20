"""The follower-train dynamics (cam_workbench.generators.dynamics) held against computations written here:

* the closed-form steady state of a mass–spring–damper driven through a spring and damper by a
  single harmonic — the eccentric cam (harmonic 180° rise + 180° return is s = h/2·(1 − cos θ)),
  damped and undamped, translating and oscillating (arm radians);
* a second solver: scipy's DOP853 from rest until the transient has died, and a second-order
  finite-difference periodic solve (a sparse cyclic system), on the cycloidal default motion, its
  laws written out here;
* the run off the cam against an event-driven DOP853 integration of the same contact law;
* the camshaft torque against the moment of the normal contact force about the cam axis
  (geometry by finite differences of the cam-frame curve), and the work per revolution against
  the energy the damper takes (∮T dθ = ∮c(u̇ − q̇)² dt);
* the jump speed of the eccentric cam by hand: Q = Q₀ + |Q₁(ω)| cos(θ + ψ) reaches 0 where
  Q₀ = |Q₁(ω)|, and the rigid follower's ω² = (P + 2k a)/(J a);
* residual vibration: in a dwell the vibration is free, its peaks fall by the logarithmic
  decrement e^{−2πζ/√(1−ζ²)}.
"""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from scipy.sparse import diags
from scipy.sparse.linalg import spsolve

from cam_workbench.generators.dynamics import analyse_dynamics, cam_input, min_force_vs_speed, periodic_response, train_model
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.followers import follower_of
from cam_workbench.generators.motion.program import MotionProgram
from cam_workbench.generators.spec import CamSpec, default_spec
from cam_workbench.generators.spec.examples import example_dict

RPM = 2 * math.pi / 60


def eccentric(d: dict, lift: float) -> dict:
    d = copy.deepcopy(d)
    d["motion"] = [{"kind": "rise", "angle": 180.0, "lift": lift, "law": "harmonic"},
                   {"kind": "return", "angle": 180.0, "lift": lift, "law": "harmonic"}]
    return d


def closed_form(J, kf, ks, P, c, a, w, theta):
    """Steady state of J q̈ + c q̇ + (kf + ks) q = kf u + c u̇ − P with u = a(1 − cos ωt), written
    out: (q, q̇, Q = kf(u − q) + c(u̇ − q̇)) at cam angles θ = ωt."""
    K = kf + ks
    x0 = (kf * a - P) / K
    X = (kf + 1j * c * w) * (-a) / (K - J * w * w + 1j * c * w)
    e = np.exp(1j * theta)
    q = x0 + (X * e).real
    qd = (1j * w * X * e).real
    u, ud = a * (1 - np.cos(theta)), a * w * np.sin(theta)
    return q, qd, kf * (u - q) + c * (ud - qd)


@pytest.mark.parametrize("zeta", [0.05, 0.0])
@pytest.mark.parametrize("kind", ["roller", "flat"])
def test_eccentric_cam_translating_matches_the_closed_form(zeta, kind):
    d = eccentric(default_spec().to_dict(), 20.0)
    if kind == "flat":
        d["follower"] = {"kind": "flat", "mass": 0.5, "preload": 200.0, "spring_rate": 1.0}
    else:
        d["follower"]["preload"] = 200.0
    d["dynamics"] = {"stiffness": 20.0, "damping_ratio": zeta, "sweep_points": 0}
    spec = CamSpec.from_dict(d)
    rpm = 900.0                                             # ω/ω_n = 0.46: well inside the dynamic range
    r = analyse_dynamics(spec, speed_rpm=rpm)
    J, kf, ks, P = 0.5e-3, 20.0, 1.0, 200.0                # kg → N·s²/mm; N/mm; N
    c = 2 * zeta * math.sqrt(J * (kf + ks))
    q, _qd, Q = closed_form(J, kf, ks, P, c, 10.0, rpm * RPM, r.theta)
    assert r.contact_kept
    assert np.max(np.abs(r.position - q)) < 1e-10 * 20
    assert np.max(np.abs(r.periodic.load - Q)) < 1e-10 * np.max(np.abs(Q))
    # a real dynamic effect, not the rigid limit: the load swings 20 % more than the rigid follower's
    rigid = J * 10.0 * np.cos(r.theta) * (rpm * RPM) ** 2 + P + ks * 10.0 * (1 - np.cos(r.theta))
    assert np.ptp(Q) > 1.2 * np.ptp(rigid)
    if kind == "flat":                                      # φ = 0: the normal force is the load itself
        assert np.max(np.abs(r.force - Q)) < 1e-10 * np.max(np.abs(Q))


def test_eccentric_cam_oscillating_arm_in_radians():
    d = eccentric(example_dict("oscillating"), 15.0)       # 15° of arm swing
    d["dynamics"] = {"torsional_stiffness": 2.0e5, "damping_ratio": 0.03, "sweep_points": 0}
    spec = CamSpec.from_dict(d)
    rpm = 400.0
    r = analyse_dynamics(spec, speed_rpm=rpm)
    J, kf, ks, P = 2000.0e-3, 2.0e5, 500.0, 800.0          # kg·mm² → N·mm·s²/rad; N·mm/rad; N·mm
    c = 2 * 0.03 * math.sqrt(J * (kf + ks))
    a = math.radians(7.5)
    q, _qd, Q = closed_form(J, kf, ks, P, c, a, rpm * RPM, r.theta)
    assert r.contact_kept
    assert np.max(np.abs(np.radians(r.position) - q)) < 1e-12
    assert np.max(np.abs(r.periodic.load - Q)) < 1e-10 * np.max(np.abs(Q))
    s = r.summary()
    assert s["model"]["coordinate"] == "arm angle" and s["error"]["unit"] == "deg"
    assert s["model"]["natural_frequency_hz"] == pytest.approx(math.sqrt((kf + ks) / J) / (2 * math.pi), rel=1e-12)


# ---- the default motion (cycloidal rise and return), its laws written out ---------------------
SEGMENTS = [(0, 30, 0.0, 0.0), (30, 120, 0.0, 20.0), (150, 60, 20.0, 20.0), (210, 120, 20.0, -20.0), (330, 30, 0.0, 0.0)]


def cycloidal(theta):
    """(s, s′, s″) of the default program at cam angles [rad] (cycloidal rise and return)."""
    deg = np.degrees(np.mod(theta, 2 * np.pi))
    s, v, a = np.zeros_like(deg), np.zeros_like(deg), np.zeros_like(deg)
    for start, span, level, lift in SEGMENTS:
        m = (deg >= start) & (deg < start + span)
        if lift == 0 and level == 0 or span == 60:
            s[m] = level
            continue
        b = math.radians(span)
        x = (deg[m] - start) / span
        s[m] = level + lift * (x - np.sin(2 * np.pi * x) / (2 * np.pi))
        v[m] = lift / b * (1 - np.cos(2 * np.pi * x))
        a[m] = lift / b**2 * 2 * np.pi * np.sin(2 * np.pi * x)
    return s, v, a


def cyc_scalar(theta):
    deg = math.degrees(theta % (2 * math.pi))
    for start, span, level, lift in SEGMENTS:
        if start <= deg < start + span:
            if span == 60 or lift == 0:
                return level, 0.0
            b = math.radians(span)
            x = (deg - start) / span
            return (level + lift * (x - math.sin(2 * math.pi * x) / (2 * math.pi)),
                    lift / b * (1 - math.cos(2 * math.pi * x)))
    return 0.0, 0.0


def soft_default(**dyn):
    return default_spec().replace(**{"dynamics.stiffness": 20.0, "dynamics.sweep_points": 0,
                                     **{f"dynamics.{k}": v for k, v in dyn.items()}})


def test_the_program_written_out_is_the_default_one():
    spec = default_spec()
    th = np.linspace(0, 2 * np.pi, 997, endpoint=False)
    k = MotionProgram.from_spec(spec).evaluate(th)
    s, v, a = cycloidal(th)
    assert np.max(np.abs(k.s - s)) < 1e-12 and np.max(np.abs(k.ds - v)) < 1e-12 and np.max(np.abs(k.d2s - a)) < 1e-11


def test_periodic_solve_against_dop853_from_rest():
    """From the static equilibrium at rest, DOP853 (tight tolerances) runs until the train's own
    vibration has died (ζω_n·t ≈ 40); its last revolution is the periodic solve's."""
    spec = soft_default(damping_ratio=0.05)
    rpm = 200.0
    r = analyse_dynamics(spec, speed_rpm=rpm)
    J, kf, ks, P = 0.5e-3, 20.0, 1.0, 20.0
    K = kf + ks
    c = 2 * 0.05 * math.sqrt(J * K)
    w = rpm * RPM

    def rhs(t, z):
        u, du = cyc_scalar(w * t)
        return [z[1], (kf * (u - z[0]) + c * (du * w - z[1]) - P - ks * z[0]) / J]

    T = 2 * math.pi / w
    revs = math.ceil(40 / (0.05 * math.sqrt(K / J)) / T) + 1
    sol = solve_ivp(rhs, (0, revs * T), [-P / K, 0.0], method="DOP853", rtol=1e-11, atol=1e-13,
                    max_step=T / 200, dense_output=True)
    assert sol.success
    q = sol.sol((revs - 1) * T + r.theta / w)[0]
    assert np.max(np.abs(q - r.position)) < 1e-8 * 20


def test_periodic_solve_against_a_finite_difference_periodic_solve():
    """Central differences on a periodic grid (second order), the cyclic banded system solved
    sparsely: agrees to the O(h²) of the differences."""
    spec = soft_default(damping_ratio=0.1)
    rpm = 250.0
    r = analyse_dynamics(spec, speed_rpm=rpm)
    J, kf, ks, P = 0.5e-3, 20.0, 1.0, 20.0
    K, w = kf + ks, rpm * RPM
    c = 2 * 0.1 * math.sqrt(J * K)
    n = 1 << 15
    h = 2 * math.pi / n
    th = h * np.arange(n)
    u, du, _ = cycloidal(th)
    lo, mid, hi = J * w * w / h**2 - c * w / (2 * h), -2 * J * w * w / h**2 + K, J * w * w / h**2 + c * w / (2 * h)
    A = diags([np.full(n - 1, lo), np.full(n, mid), np.full(n - 1, hi), [hi], [lo]], [-1, 0, 1, -(n - 1), n - 1],
              format="csc")
    q = spsolve(A, kf * u + c * w * du - P)
    step = n // r.theta.size
    assert r.theta.size * step == n
    assert np.max(np.abs(q[::step] - r.position)) < 2e-5 * np.max(np.abs(r.error))
    assert np.max(np.abs(q[::step] - r.position)) > 0          # two different discretisations


def test_off_the_cam_against_an_event_driven_dop853_run():
    """Above the jump speed: the same contact law (Q = max(0, k_f δ + c δ̇) while δ = u − q > 0)
    integrated phase by phase with DOP853 and events, from the same state, over the same revolutions."""
    spec = default_spec().replace(**{"dynamics.stiffness": 2000.0, "follower.spring_rate": 3.0,
                                     "dynamics.sweep_points": 0})
    rpm = 700.0
    r = analyse_dynamics(spec, speed_rpm=rpm)
    assert not r.contact_kept and r.separated.periodic
    J, kf, ks, P = 0.5e-3, 2000.0, 3.0, 20.0
    c = 2 * 0.05 * math.sqrt(J * (kf + ks))
    w = rpm * RPM
    T = 2 * math.pi / w

    def drive(t):
        u, du = cyc_scalar(w * t)
        return u, du * w

    def contact(t, z):
        u, du = drive(t)
        return [z[1], (kf * (u - z[0]) + c * (du - z[1]) - P - ks * z[0]) / J]

    def flight(t, z):
        return [z[1], (-P - ks * z[0]) / J]

    def load(t, z):
        u, du = drive(t)
        return kf * (u - z[0]) + c * (du - z[1])

    def lands(t, z):
        u, _ = drive(t)
        return min(kf * (u - z[0]), load(t, z))

    load.terminal, load.direction = True, -1
    lands.terminal, lands.direction = True, 1
    revs = r.separated.revolutions
    grid = (revs - 1) * T + r.theta / w                     # the library's last revolution
    got = np.full(r.theta.size, np.nan)
    t, z, on = 0.0, [r.periodic.q[0], r.periodic.velocity[0]], True
    for _phase in range(1000):
        sol = solve_ivp(contact if on else flight, (t, revs * T), z, method="DOP853", rtol=1e-12, atol=1e-14,
                        max_step=T / 3000, events=load if on else lands, dense_output=True)
        sel = (grid >= t) & (grid <= sol.t[-1])
        if sel.any():
            got[sel] = sol.sol(grid[sel])[0]
        t, z, on = sol.t[-1], list(sol.y[:, -1]), not on
        if sol.status == 0:
            break
    assert not np.isnan(got).any()
    assert np.max(np.abs(got - r.position)) < 1e-6 * 20
    # where it flies, the gap is real: tens of µm
    assert r.summary()["contact"]["max_gap"] > 0.01


# ---- torque ------------------------------------------------------------------------------------
def _geometric_normal(spec, theta, point):
    """(P, n̂, δ): the follower point P(θ) in the fixed frame, the cam's outward normal there (the
    cam-frame curve Rot(−δθ)·P(θ) differentiated numerically, turned back) and δ = ±1 (ccw/cw)."""
    delta = 1 if spec.cam.direction == "ccw" else -1
    h = 1e-5

    def cam_frame(t):
        return np.exp(-1j * delta * t) * point(t)

    P = point(theta)
    V = np.exp(1j * delta * theta) * (cam_frame(theta + h) - cam_frame(theta - h)) / (2 * h)
    n = 1j * V / np.abs(V)
    return P, np.where((np.conj(P) * n).real > 0, n, -n), delta


def test_torque_is_the_moment_of_the_contact_force_translating_roller_with_offset():
    spec = CamSpec.from_dict({**example_dict("paper"),
                              "follower": {"kind": "roller", "offset": 10.0, "roller_radius": 5.0, "mass": 0.4,
                                           "preload": 30.0, "spring_rate": 2.0},
                              "dynamics": {"stiffness": 5000.0, "sweep_points": 0}})
    rpm = 150.0
    r = analyse_dynamics(spec, speed_rpm=rpm)
    e, s0 = 10.0, math.sqrt(spec.cam.base_radius**2 - 100.0)

    def point(t):
        s, _v, _a = cycloidal(t)
        return e + 1j * (s0 + s)

    P, n, delta = _geometric_normal(spec, r.theta, point)
    s, v, a = cycloidal(r.theta)
    w = rpm * RPM
    Q = 0.4e-3 * a * w * w + 30.0 + 2.0 * s                  # the rigid load, written out
    cos_phi = np.abs(n.imag)                                  # the normal against the line of motion (+y)
    F = Q / cos_phi
    assert np.max(np.abs(r.rigid_force - F)) < 1e-6 * np.max(np.abs(F))
    T_geo = delta * F * (np.conj(P) * n).imag
    assert np.max(np.abs(r.rigid_torque - T_geo)) < 1e-6 * np.max(np.abs(T_geo))
    assert np.max(np.abs(r.rigid_torque - Q * v)) < 1e-9 * np.max(np.abs(T_geo))   # virtual work, pointwise


def test_torque_is_the_moment_of_the_contact_force_oscillating_roller():
    d = example_dict("oscillating")
    d["cam"]["direction"] = "cw"
    d["dynamics"] = {"torsional_stiffness": 1.0e6, "sweep_points": 0}
    spec = CamSpec.from_dict(d)
    rpm = 120.0
    r = analyse_dynamics(spec, speed_rpm=rpm)
    D, L, Rb = 60.0, 45.0, 40.0
    psi0 = math.acos((Rb**2 - D**2 - L**2) / (2 * D * L))

    def point(t):
        s, _v, _a = cycloidal(t)                  # the default motion with 15° lifts: scale 20 → 15
        return D + L * np.exp(1j * (psi0 - np.radians(s * 0.75)))

    P, n, delta = _geometric_normal(spec, r.theta, point)
    s, v, a = cycloidal(r.theta)
    s, v, a = np.radians(0.75 * s), np.radians(0.75 * v), np.radians(0.75 * a)   # arm radians
    w = rpm * RPM
    T_arm = 2000.0e-3 * a * w * w + 800.0 + 500.0 * s
    wdir = -1j * (P - D) / np.abs(P - D)                    # the roller centre's motion as the lift grows
    F = T_arm / (L * np.abs((np.conj(wdir) * n).real))
    assert np.max(np.abs(r.rigid_force - F)) < 1e-6 * np.max(np.abs(F))
    T_geo = delta * F * (np.conj(P) * n).imag
    assert np.max(np.abs(r.rigid_torque - T_geo)) < 1e-6 * np.max(np.abs(T_geo))


def test_torque_of_a_translating_flat_face():
    d = example_dict("flat")
    d["dynamics"] = {"stiffness": 3000.0, "sweep_points": 0}
    spec = CamSpec.from_dict(d)
    rpm = 200.0
    r = analyse_dynamics(spec, speed_rpm=rpm)
    s, v, a = cycloidal(r.theta)
    w = rpm * RPM
    Q = 0.5e-3 * a * w * w + 20.0 + 1.0 * s
    # the face touches s′ along it from the centre line (Shigley & Uicker), its normal the line of motion
    T_geo = Q * v
    assert np.max(np.abs(r.rigid_force - Q)) < 1e-9 * np.max(Q)
    assert np.max(np.abs(r.rigid_torque - T_geo)) < 1e-9 * np.max(np.abs(T_geo))


def test_work_per_revolution_is_what_the_damper_takes():
    """∮T dθ = ∮ Q u̇ dt: zero for the rigid (conservative) train; for the damped one the energy
    the damper takes, ∮ c (u̇ − q̇)² dt, with q̇ differentiated here spectrally from the positions."""
    spec = soft_default(damping_ratio=0.08)
    rpm = 250.0
    r = analyse_dynamics(spec, speed_rpm=rpm)
    s = r.summary()["torque"]
    w = rpm * RPM
    J, K = 0.5e-3, 21.0
    c = 2 * 0.08 * math.sqrt(J * K)
    n = r.theta.size
    k = np.fft.rfftfreq(n, 1.0 / n)
    qd = np.fft.irfft(1j * k * np.fft.rfft(r.position), n) * w
    _s, v, _a = cycloidal(r.theta)
    ud = v * w
    dissipated = np.sum(c * (ud - qd) ** 2) * (2 * math.pi / w) / n
    assert dissipated > 0
    assert s["dynamic"]["work_per_revolution"] == pytest.approx(dissipated, rel=1e-6)
    assert abs(s["rigid"]["work_per_revolution"]) < 1e-9 * s["rigid"]["rms"]


# ---- jump speed --------------------------------------------------------------------------------
def test_jump_speed_of_the_eccentric_cam_by_hand():
    d = eccentric(example_dict("flat"), 20.0)
    d["dynamics"] = {"stiffness": 200.0, "damping_ratio": 0.05, "sweep_points": 60}
    spec = CamSpec.from_dict(d)
    r = analyse_dynamics(spec)
    J, kf, ks, P, a = 0.5e-3, 200.0, 1.0, 20.0, 10.0
    K = kf + ks
    c = 2 * 0.05 * math.sqrt(J * K)

    def margin(w):                     # Q₀ − |Q₁|: the smallest load over a revolution
        q0 = kf * (ks * a + P) / K
        q1 = a * abs(kf + 1j * c * w) * abs(ks - J * w * w) / abs(K - J * w * w + 1j * c * w)
        return q0 - q1

    rigid = math.sqrt((P + 2 * ks * a) / (J * a))
    hand = brentq(margin, 0.5 * rigid, rigid * 1.5)
    assert r.jump.rigid_rpm == pytest.approx(rigid / RPM, rel=1e-9)
    assert r.jump.rpm == pytest.approx(hand / RPM, rel=1e-7)
    assert abs(hand - rigid) > 1e-3 * rigid                   # the train's compliance moves it
    assert r.summary()["jump_speed"]["rpm"] == r.jump.rpm


def test_the_sweep_solves_each_speed_as_the_single_solve():
    spec = soft_default()
    fol = follower_of(spec)
    model = train_model(spec, fol)
    inp = cam_input(MotionProgram.from_spec(spec), fol, 4096)
    speeds = np.linspace(20.0, 60.0, 7)
    swept = min_force_vs_speed(model, inp, speeds)
    fine = cam_input(MotionProgram.from_spec(spec), fol, 16 * 4096)
    for w, f in zip(speeds, swept):
        single = periodic_response(model, inp, w).load * inp.lever
        dense = periodic_response(model, fine, w).load * fine.lever     # 16× the samples: the true minimum
        assert f <= np.min(single) + 1e-12
        assert f == pytest.approx(np.min(dense), abs=1e-7 * np.ptp(dense))


# ---- residual vibration ------------------------------------------------------------------------
def test_residual_vibration_in_a_dwell_decays_by_the_log_decrement():
    zeta = 0.02
    spec = default_spec().replace(**{"motion[1].law": "harmonic", "motion[3].law": "harmonic",
                                     "dynamics.stiffness": 500.0, "dynamics.damping_ratio": zeta,
                                     "dynamics.sweep_points": 0, "dynamics.samples": 1 << 16})
    r = analyse_dynamics(spec, speed_rpm=200.0)
    deg = r.theta_deg
    dwell = (deg > 150.0) & (deg < 210.0)
    v = np.where(dwell, r.vibration, np.nan)
    inner = np.flatnonzero(dwell[1:-1] & (v[1:-1] > v[:-2]) & (v[1:-1] > v[2:])) + 1
    peaks = v[inner]
    assert peaks.size >= 4
    wn = math.sqrt(501.0 / 0.5e-3)
    assert peaks[1:] / peaks[:-1] == pytest.approx(math.exp(-2 * math.pi * zeta / math.sqrt(1 - zeta**2)), rel=2e-3)
    period = 2 * math.pi / (wn * math.sqrt(1 - zeta**2)) * (200.0 * RPM)   # in cam radians
    assert np.diff(r.theta[inner]) == pytest.approx(period, abs=2 * (r.theta[1] - r.theta[0]))
    res = r.summary()["residual_vibration"]
    assert [x["after"] for x in res] == [1, 3]
    assert res[0]["amplitude"] == pytest.approx(np.nanmax(np.abs(v)), rel=1e-12)


# ---- bad input ---------------------------------------------------------------------------------
@pytest.mark.parametrize("changes, field", [
    ({"dynamics.enabled": True}, "dynamics.stiffness"),
    ({"dynamics.enabled": True, "dynamics.stiffness": 100.0, "follower.mass": 0.0}, "dynamics.mass"),
    ({"dynamics.torsional_stiffness": 100.0}, "dynamics.torsional_stiffness"),
    ({"dynamics.sweep_min_rpm": 100.0, "dynamics.sweep_max_rpm": 50.0}, "dynamics.sweep_max_rpm"),
    ({"dynamics.damping_ratio": 1.0}, "dynamics.damping_ratio"),
    ({"dynamics.speed_rpm": -3.0}, "dynamics.speed_rpm"),
])
def test_bad_dynamics_input_names_the_field(changes, field):
    with pytest.raises(SpecError) as err:
        default_spec().replace(**changes)
    assert str(err.value).startswith(field + ":")


def test_analysing_without_a_stiffness_names_it():
    with pytest.raises(SpecError, match=r"^dynamics\.arm_inertia|^dynamics\.torsional_stiffness"):
        analyse_dynamics(CamSpec.from_dict(example_dict("oscillating")))


def test_dynamics_are_not_in_the_digest():
    spec = default_spec()
    from cam_workbench.generators.spec import spec_digest

    assert spec_digest(spec) == spec_digest(spec.replace(**{"dynamics.stiffness": 10.0, "ecam.step": 2.0}))


# ---- motions and trains beyond the examples ---------------------------------------------------
def _other(kind: str, motion: str, laws: tuple[str, str], direction: str = "ccw") -> CamSpec:
    d = example_dict("oscillating" if motion == "oscillating" else "default")
    d["cam"]["direction"] = direction
    if motion == "translating":
        d["follower"] = {"kind": kind, "mass": 0.8, "preload": 40.0, "spring_rate": 2.0}
        if kind == "roller":
            d["follower"].update(roller_radius=6.0, offset=-5.0)
        d["dynamics"] = {"stiffness": 800.0, "damping_ratio": 0.1, "sweep_points": 30}
    else:
        d["follower"]["kind"] = kind
        if kind == "flat":
            for f in ("arm_length", "roller_radius"):
                d["follower"].pop(f, None)
            d["follower"]["face_offset"] = 5.0
        elif kind == "knife":
            d["follower"].pop("roller_radius")
        d["dynamics"] = {"torsional_stiffness": 5.0e5, "damping_ratio": 0.1, "sweep_points": 30}
    lift = 12.0 if motion == "oscillating" else 20.0
    d["motion"] = [{"kind": "dwell", "angle": 20.0}, {"kind": "rise", "angle": 100.0, "lift": lift, "law": laws[0]},
                   {"kind": "dwell", "angle": 40.0}, {"kind": "rise", "angle": 60.0, "lift": lift / 2, "law": laws[1]},
                   {"kind": "return", "angle": 120.0, "lift": 1.5 * lift, "law": laws[0]},
                   {"kind": "dwell", "angle": 20.0}]
    return CamSpec.from_dict(d)


OTHER = [("roller", "translating", ("poly345", "modified_trapezoid"), "cw"),
         ("knife", "translating", ("modified_sine", "poly4567"), "ccw"),
         ("flat", "translating", ("cycloidal", "harmonic"), "ccw"),
         ("knife", "oscillating", ("poly4567", "poly345"), "cw"),
         ("flat", "oscillating", ("modified_sine", "cycloidal"), "ccw")]


@pytest.mark.parametrize("kind, motion, laws, direction", OTHER)
def test_other_trains_obey_their_equation_of_motion(kind, motion, laws, direction):
    """Multi-level programs, other laws, knives and faces, cw cams: the periodic solution satisfies
    J q̈ = Q − P − k_s q with q̈ differentiated here spectrally from the positions; the rigid train
    does no work over a revolution; the torque is Q·u′; the jump speed lies below the rigid one's
    second bracket of the sweep, and the follower keeps contact below it."""
    spec = _other(kind, motion, laws, direction)
    fol = follower_of(spec)
    r0 = analyse_dynamics(spec)
    rpm = 0.6 * r0.jump.rpm
    r = analyse_dynamics(spec, speed_rpm=rpm, sweep=False)
    assert r.contact_kept
    m = train_model(spec, fol)
    w = rpm * RPM
    n = r.theta.size
    k = np.fft.rfftfreq(n, 1.0 / n)
    q = np.radians(r.position) if motion == "oscillating" else r.position
    qdd = np.fft.irfft(-(k * w) ** 2 * np.fft.rfft(q), n)
    Q = r.periodic.load
    resid = m.inertia * qdd - (Q - m.preload - m.spring_rate * q)
    assert np.max(np.abs(resid)) < 1e-6 * np.max(np.abs(Q))
    s = r.summary()
    # (the mean of equal samples: exact for smooth integrands, O(h²) where a law's acceleration or
    # jerk jumps, as here)
    assert abs(s["torque"]["rigid"]["work_per_revolution"]) < 1e-6 * s["torque"]["rigid"]["rms"]
    assert np.max(np.abs(r.torque - Q * r.inp.du)) < 1e-12 * np.max(np.abs(r.torque))
    assert r0.jump.rigid_rpm is not None and 0.5 * r0.jump.rigid_rpm < r0.jump.rpm < 1.5 * r0.jump.rigid_rpm
    assert analyse_dynamics(spec, speed_rpm=1.02 * r0.jump.rpm, sweep=False).separated is not None


def test_an_inch_spec_gives_the_same_physics():
    """The default cam in inches (lbf, lbf·s²/in, lbf/in): the same forces in lbf, the same jump
    speed and natural frequency."""
    N_PER_LBF, MM = 4.4482216152605, 25.4
    mm = default_spec().replace(**{"dynamics.stiffness": 2000.0, "dynamics.sweep_points": 40})
    d = mm.to_dict()
    d["units"] = "in"
    d["cam"].update(base_radius=40.0 / MM, thickness=10.0 / MM, bore_diameter=12.0 / MM)
    # kg·mm/s² = 1e-3 N, so 0.5 kg pulls 0.5e-3 N per mm/s²: 0.5e-3·25.4 / 4.448 lbf per in/s²
    d["follower"].update(roller_radius=8.0 / MM, mass=0.5e-3 * MM / N_PER_LBF, preload=20.0 / N_PER_LBF,
                         spring_rate=1.0 * MM / N_PER_LBF)
    d["dynamics"]["stiffness"] = 2000.0 * MM / N_PER_LBF
    for seg in d["motion"]:
        if "lift" in seg:
            seg["lift"] = 20.0 / MM
    d.pop("material", None)
    d.pop("machining", None)
    d.pop("drawing", None)
    inch = CamSpec.from_dict(d)
    a, b = analyse_dynamics(mm, speed_rpm=300.0).summary(), analyse_dynamics(inch, speed_rpm=300.0).summary()
    assert b["model"]["natural_frequency_hz"] == pytest.approx(a["model"]["natural_frequency_hz"], rel=1e-12)
    assert b["contact"]["min_force"] * N_PER_LBF == pytest.approx(a["contact"]["min_force"], rel=1e-9)
    assert b["torque"]["dynamic"]["max"] * N_PER_LBF * MM == pytest.approx(a["torque"]["dynamic"]["max"], rel=1e-9)
    assert b["error"]["max"] * MM == pytest.approx(a["error"]["max"], rel=1e-9)
    assert b["jump_speed"]["rpm"] == pytest.approx(a["jump_speed"]["rpm"], rel=1e-9)
    assert b["contact"]["unit"] == "lbf" and b["torque"]["unit"] == "lbf·in" and b["error"]["unit"] == "in"


@pytest.mark.parametrize("name, sides", [("groove", "the inner wall"), ("conjugate", "the first cam")])
def test_positive_drive_bodies_hold_the_follower_both_ways(name, sides):
    """A groove and a conjugate pair hold the roller both ways (form closure, as the design checks
    say): the dynamics never report it leaving the cam nor a jump speed, whatever its spring; the
    load changes side where the cycloid's rigid inertia force m·s″·ω² does — at mid-rise (90°), into
    the dwells at 150° and 330° (a zero force counts as positive) and at mid-return (270°)."""
    spec = CamSpec.from_dict(example_dict(name)).replace(**{"dynamics.stiffness": 2000.0})
    res = analyse_dynamics(spec, MotionProgram.from_spec(spec), sweep=True)
    c = res.summary()["contact"]
    assert c["kept"] and c["closure"] == "form" and "separations" not in c
    assert res.jump is None and "jump_speed" not in res.summary()
    assert sides in c["drive"]["note"]
    # the closed form: the cycloid's s″ changes sign at mid-rise and mid-return; dwells are zero
    np.testing.assert_allclose(c["drive"]["rigid"]["changes_at_deg"], [90.0, 150.0, 210.0, 270.0], atol=0.05)
    # the dynamic force's residual vibration in a dwell (|F| ≪ the peak) chooses no side
    dyn = c["drive"]["changes_at_deg"]
    f = np.abs(res.force)
    assert len(dyn) < 100
    quiet = (res.theta_deg > 20.0) & (res.theta_deg < 29.0)   # late in the last dwell
    assert np.max(f[quiet]) < 1e-3 * np.max(f)
    assert not [a for a in dyn if 20.0 < a < 29.0]

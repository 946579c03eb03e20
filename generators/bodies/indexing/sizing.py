"""An indexing drive's sizing from its load: the index and dwell times, the output motion, the
output and input torques and the input power, the driving roller's normal load, its Hertz
contact stress and the roller bearing's basic rating life (ISO 281).

SI units throughout (m, kg, s, N, N·m, W, Pa, rad) except the input speed [rev/min].  θ is the
input (camshaft) angle from the start of the index, [0, β] the index and (β, 2π) the dwell;
the output turns by h = 2π/N during the index: ψ(θ) = h·F(θ/β), F the normalised law of
:mod:`..motion.laws`.  One index per input turn (a single-lead cam).
"""
from __future__ import annotations

import math
import operator
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...errors import SpecError, fmt_apart
from ...followers.load import hertz_stress
from ...motion.characteristics import LawCharacteristics, law_characteristics, peak_abs
from ...motion.laws import LAW_FUNCTIONS, NormalisedLaw, evaluate_law, is_law, law_name

Array = np.ndarray
TWO_PI = 2.0 * math.pi
#: samples of the default θ over the index
_THETA_SAMPLES = 4097
#: Simpson samples of the mean input power (odd)
_MEAN_SAMPLES = 2**14 + 1


@dataclass(frozen=True)
class IndexLoad:
    """What an indexer drives, and its driving roller (validated on construction: a bad field
    raises :class:`SpecError` named ``indexer.<field>``).

    Attributes:
        stations: N, the output's stops per turn (integer ≥ 2); it turns by 2π/N per index.
        index_angle: β [rad], the input angle of the index, 0 < β < 2π.
        input_speed: n_in [rev/min], the input shaft's constant speed.
        inertia: J [kg·m²], the output's (turret and load) inertia about its axis.
        friction_torque: T_f [N·m] ≥ 0, against the output's motion, only while it moves.
        law: the index's motion law, a key of ``LAW_FUNCTIONS`` or a
            :class:`~cam_workbench.generators.motion.laws.NormalisedLaw` (a motion program's rise).
        pitch_radius: R_p [m], the turret's roller pitch radius.
        roller_radius: r_r [m], the roller's radius.
        roller_width: L [m], the roller's contact length.
        roller_rating: C_dyn [N], the roller bearing's basic dynamic load rating.
        e_cam, nu_cam, e_roller, nu_roller: Young's moduli [Pa] and Poisson ratios (steel).
        life_exponent: p of ISO 281, 10/3 for roller and needle track rollers, 3 for ball.
        efficiency: η ∈ (0, 1] of the cam–roller contact.
    """

    stations: int
    index_angle: float
    input_speed: float
    inertia: float
    friction_torque: float
    law: str | NormalisedLaw
    pitch_radius: float
    roller_radius: float
    roller_width: float
    roller_rating: float
    e_cam: float = 206e9
    nu_cam: float = 0.3
    e_roller: float = 206e9
    nu_roller: float = 0.3
    life_exponent: float = 10.0 / 3.0
    efficiency: float = 1.0

    def __post_init__(self) -> None:
        _validate(self)


def _real(field: str, value: Any) -> float:
    """``value`` as a float; SpecError unless it is a finite real number."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) \
            or not math.isfinite(value):
        raise SpecError(f"indexer.{field}", f"must be a finite number, got {value!r}")
    return float(value)


def _validate(load: IndexLoad) -> None:
    """The rules of :class:`IndexLoad` (SpecError naming the first field that breaks one)."""
    try:
        n = operator.index(load.stations)
    except TypeError:
        n = None
    if n is None or isinstance(load.stations, bool) or n < 2:
        raise SpecError("indexer.stations", f"must be an integer ≥ 2, got {load.stations!r}")
    beta = _real("index_angle", load.index_angle)
    if not 0 < beta < TWO_PI:
        raise SpecError("indexer.index_angle", f"must be in (0, 2π) rad, got {fmt_apart(beta, TWO_PI)}")
    for field, unit in (("input_speed", " rev/min"), ("inertia", " kg·m²"), ("pitch_radius", " m"),
                        ("roller_radius", " m"), ("roller_width", " m"), ("roller_rating", " N"),
                        ("e_cam", " Pa"), ("e_roller", " Pa"), ("life_exponent", ""), ("efficiency", "")):
        value = _real(field, getattr(load, field))
        if not value > 0:
            raise SpecError(f"indexer.{field}", f"must be > 0{unit}, got {fmt_apart(value, 0)}")
    if not load.efficiency <= 1:
        raise SpecError("indexer.efficiency", f"must be ≤ 1, got {fmt_apart(load.efficiency, 1)}")
    if not _real("friction_torque", load.friction_torque) >= 0:
        raise SpecError("indexer.friction_torque", f"must be ≥ 0 N·m, got {fmt_apart(load.friction_torque, 0)}")
    for field in ("nu_cam", "nu_roller"):
        if not -1 < _real(field, getattr(load, field)) <= 0.5:
            raise SpecError(f"indexer.{field}", f"must be a Poisson ratio in (−1, 0.5], got {getattr(load, field)!r}")
    if not is_law(load.law):
        raise SpecError("indexer.law", f"unknown law {load.law!r}; one of {', '.join(sorted(LAW_FUNCTIONS))} "
                        "or a NormalisedLaw (a motion program's rise)")


def equivalent_load(loads: Array, revolutions: Array, exponent: float) -> float:
    """ISO 281's equivalent load of a load spectrum [N]: the ``exponent``-th power mean of
    ``loads`` [N] weighted by the ``revolutions`` (any unit) each acts for,
    P = (Σ N_i F_i^p / Σ N_i)^(1/p).  0 when no revolutions are made."""
    loads = np.abs(np.asarray(loads, dtype=float))
    revolutions = np.asarray(revolutions, dtype=float)
    total = float(np.sum(revolutions))
    if total <= 0:
        return 0.0
    # scaled by the largest load so that F^p stays in range for any p
    top = float(loads.max(initial=0.0))
    if top == 0:
        return 0.0
    return top * float(np.sum(revolutions * (loads / top) ** exponent) / total) ** (1.0 / exponent)


def rating_life(rating: float, load: float, exponent: float) -> float:
    """ISO 281's basic rating life L10 = (C/P)^p [million revolutions] of a bearing of basic
    dynamic load rating C [N] under the equivalent load P [N]; inf for P = 0."""
    return math.inf if load <= 0 else (rating / load) ** exponent


@dataclass(frozen=True, eq=False)
class DriveSizing:
    """An indexer's drive over the input angle θ (arrays, the shape of ``theta``) and its
    scalars.  Peaks are of magnitudes; "at" is the input angle θ [rad] of a peak.

    The law-only peaks (output motion, torques, power) are refined over the continuous index
    (:func:`peak_abs`); the normal force, the stress and the life, which depend on the sampled
    moment arm and cam radius, are over the samples θ."""

    load: IndexLoad
    characteristics: LawCharacteristics
    theta: Array          #: input angle θ [rad]
    psi: Array            #: output angle ψ [rad], 0 → 2π/N over the index
    dpsi: Array           #: ψ' = dψ/dθ [rad/rad]
    ddpsi: Array          #: ψ'' = d²ψ/dθ² [rad/rad²]
    omega_out: Array      #: ω_out = ψ'·ω_in [rad/s]
    alpha_out: Array      #: α_out = ψ''·ω_in² [rad/s²]
    torque_out: Array     #: T_out = J·α_out + T_f·sign(ω_out) [N·m], the torque the cam applies to the output
    torque_in: Array      #: camshaft torque by virtual work [N·m]
    power_in: Array       #: T_in·ω_in [W]
    normal_force: Array   #: F_n = |T_out|/arm [N]
    contact_stress: Array  #: Hertz contact pressure [Pa]
    input_omega: float    #: ω_in [rad/s]
    index_time: float     #: t_i [s]
    dwell_time: float     #: [s]
    omega_out_peak: float    #: C_v·(2π/N)/t_i [rad/s]
    alpha_out_peak: float    #: C_a·(2π/N)/t_i² [rad/s²]
    torque_out_peak: float   #: [N·m]
    torque_out_peak_at: float
    torque_in_peak: float    #: [N·m]
    torque_in_peak_at: float
    power_in_peak: float     #: [W]
    power_in_mean: float     #: mean input power over the index [W]
    normal_force_peak: float  #: [N]
    normal_force_peak_at: float
    contact_stress_peak: float  #: [Pa]; inf where the roller does not fit a concave cam
    contact_stress_peak_at: float
    equivalent_load: float   #: the roller bearing's equivalent load P [N]
    roller_revolutions: float  #: the roller's revolutions per index
    l10: float               #: basic rating life [million roller revolutions]
    l10_hours: float         #: [h] at the input speed, one index per input turn
    rolling_note: str        #: how the roller's rolling was counted

    def summary(self) -> dict[str, Any]:
        """report.json's ``indexer`` section: plain Python scalars, units in the keys (angles in
        degrees, input angle θ from the start of the index); an infinite value is None with a
        ``<key>_note``."""
        ld = self.load
        out: dict[str, Any] = {
            "law": law_name(ld.law),
            "stations": int(ld.stations),
            "index_step_deg": 360.0 / int(ld.stations),
            "index_angle_deg": math.degrees(ld.index_angle),
            "input_speed_rpm": float(ld.input_speed),
            "efficiency": float(ld.efficiency),
            "index_time_s": self.index_time,
            "dwell_time_s": self.dwell_time,
            "output_velocity_peak_rad_s": self.omega_out_peak,
            "output_acceleration_peak_rad_s2": self.alpha_out_peak,
            "output_torque_peak_Nm": self.torque_out_peak,
            "output_torque_peak_at_deg": math.degrees(self.torque_out_peak_at),
            "input_torque_peak_Nm": self.torque_in_peak,
            "input_torque_peak_at_deg": math.degrees(self.torque_in_peak_at),
            "input_power_peak_W": self.power_in_peak,
            "input_power_mean_index_W": self.power_in_mean,
            "normal_force_peak_N": self.normal_force_peak,
            "normal_force_peak_at_deg": math.degrees(self.normal_force_peak_at),
            "contact_stress_peak_Pa": self.contact_stress_peak,
            "contact_stress_peak_at_deg": math.degrees(self.contact_stress_peak_at),
            "roller_equivalent_load_N": self.equivalent_load,
            "roller_revolutions_per_index": self.roller_revolutions,
            "roller_life_exponent": float(ld.life_exponent),
            "l10_million_rev": self.l10,
            "l10_hours": self.l10_hours,
            "roller_rolling": self.rolling_note,
            "characteristics": self.characteristics.summary(),
        }
        notes = {"contact_stress_peak_Pa": "infinite: the roller is larger than a concave hollow of the cam",
                 "l10_million_rev": "infinite: the roller carries no load",
                 "l10_hours": "infinite: the roller carries no load"}
        for key, note in notes.items():
            if not math.isfinite(out[key]):
                out[key] = None
                out[f"{key}_note"] = note
        return out


def _as_samples(field: str, value: Any, theta: Array) -> Array:
    """An optional per-sample array (or scalar) broadcast to θ's shape, as floats."""
    try:
        arr = np.asarray(value, dtype=float)
        return np.broadcast_to(arr, theta.shape).astype(float)
    except (TypeError, ValueError):
        raise SpecError(f"indexer.{field}", f"must be a number or an array of θ's shape {theta.shape}") from None


def drive_sizing(load: IndexLoad, theta: Array | None = None, arm: Array | None = None,
                 cam_radius: Array | None = None, contact_arc: Array | None = None,
                 arm_back: Array | None = None, cam_radius_back: Array | None = None) -> DriveSizing:
    """The drive's sizing over the input angle θ [rad] (default: 4097 samples over the index
    [0, β]; any increasing samples of [0, 2π], those past β in the dwell).

    Optional arrays over θ (or scalars):

    * ``arm`` [m] > 0: the moment arm of the contact normal about the turret axis (default R_p,
      zero pressure angle): F_n = |T_out|/arm;
    * ``cam_radius`` [m]: the cam's signed radius of curvature at the contact, + convex,
      − concave, ±inf flat (default +inf: cylinder on a plane), for the Hertz stress of
      :func:`..followers.load.hertz_stress` (parallel cylinders of length L);
    * ``arm_back``, ``cam_radius_back``: the same of the contact that holds the output back (a
      form-closed drive: the cam that carries the load where the output decelerates, T_out < 0);
      default ``arm`` and ``cam_radius``.  The load is taken by the forward contact where
      T_out ≥ 0 and by this one where T_out < 0;
    * ``contact_arc`` [m]: the cumulative arc length the contact point has travelled on the
      cam, non-decreasing.  The roller rolls without slip, so it turns by (arc)/r_r.  Without
      it the rolling is taken as R_p·|dψ|, the roller centre's path on the turret (an
      assumption: the real contact path is longer where the cam surface also slides past the
      roller along its rolling direction).

    Input torque by virtual work: T_in = T_out·ψ'/η where the cam drives the output
    (T_out·ψ' ≥ 0), T_out·ψ'·η where the decelerating output drives the cam back (the contact's
    loss is then taken from the returned power); for η = 1 both are T_out·ψ', and
    T_in·ω_in = T_out·ω_out.

    Roller life (ISO 281): L10 = (C_dyn/P)^p million revolutions, P the p-th power mean of F_n
    over the roller's revolutions during the index (it is loaded only while it drives; each
    sample interval carries the p-mean of its two ends).  L10 in hours counts one index per input
    turn for this roller (conservative: in a turret whose N rollers take turns, each drives one
    index in N and lasts N times longer)."""
    beta = float(load.index_angle)
    n_st = int(load.stations)
    h = TWO_PI / n_st
    w_in = TWO_PI * float(load.input_speed) / 60.0
    t_index = beta / w_in
    t_dwell = (TWO_PI - beta) / w_in
    J, t_f, eta, p = float(load.inertia), float(load.friction_torque), float(load.efficiency), float(load.life_exponent)

    if theta is None:
        theta = np.linspace(0.0, beta, _THETA_SAMPLES)
    else:
        theta = np.asarray(theta, dtype=float)
        if theta.ndim != 1 or theta.size < 2 or not np.all(np.isfinite(theta)):
            raise SpecError("indexer.theta", "must be a 1-D array of at least 2 finite angles [rad]")
        if not (np.all(np.diff(theta) > 0) and theta[0] >= 0 and theta[-1] <= TWO_PI):
            raise SpecError("indexer.theta", "must increase strictly within [0, 2π] rad")
    arm_s = _as_samples("arm", load.pitch_radius if arm is None else arm, theta)
    if not np.all(np.isfinite(arm_s) & (arm_s > 0)):
        raise SpecError("indexer.arm", "must be finite and > 0 m at every θ")
    rho = _as_samples("cam_radius", math.inf if cam_radius is None else cam_radius, theta)
    if np.any(np.isnan(rho) | (rho == 0)):
        raise SpecError("indexer.cam_radius", "must be a nonzero signed radius [m] (±inf for a flat) at every θ")
    arm_b = arm_s if arm_back is None else _as_samples("arm_back", arm_back, theta)
    rho_b = rho if cam_radius_back is None else _as_samples("cam_radius_back", cam_radius_back, theta)

    # the output's motion: the law over the index, at rest (ψ = h) in the dwell
    moving = theta <= beta
    f, f1, f2, _ = evaluate_law(load.law, np.clip(theta / beta, 0.0, 1.0))
    psi = np.where(moving, h * f, h)
    dpsi = np.where(moving, h * f1 / beta, 0.0)
    ddpsi = np.where(moving, h * f2 / beta**2, 0.0)
    omega_out = dpsi * w_in
    alpha_out = ddpsi * w_in**2
    torque_out = J * alpha_out + t_f * np.sign(omega_out)
    torque_in = _input_torque(torque_out, dpsi, eta)
    power_in = torque_in * w_in
    back = torque_out < 0
    if not np.all(np.isfinite(arm_b[back]) & (arm_b[back] > 0)):
        raise SpecError("indexer.arm_back", "must be finite and > 0 m wherever the output decelerates")
    if np.any(np.isnan(rho_b[back]) | (rho_b[back] == 0)):
        raise SpecError("indexer.cam_radius_back", "must be a nonzero signed radius [m] wherever the output decelerates")
    normal_force = np.abs(torque_out) / np.where(back, arm_b, arm_s)
    stress = hertz_stress(normal_force, float(load.roller_radius), np.where(back, rho_b, rho), float(load.roller_width),
                          float(load.e_cam), float(load.nu_cam), float(load.e_roller), float(load.nu_roller))

    # the law-only peaks, refined over x = θ/β ∈ [0, 1]
    law = law_characteristics(load.law)

    def out_torque_x(x: Array) -> Array:
        _, g1, g2, _ = evaluate_law(load.law, x)
        return J * h * g2 * (w_in / beta) ** 2 + t_f * np.sign(g1)

    def in_torque_x(x: Array) -> Array:
        _, g1, _, _ = evaluate_law(load.law, x)
        return _input_torque(out_torque_x(x), h * g1 / beta, eta)

    t_out_peak, x_out = peak_abs(out_torque_x)
    t_in_peak, x_in = peak_abs(in_torque_x)
    # mean input power over the index: (1/β)∫P_in dθ = ω_in ∫₀¹ T_in dx (composite Simpson)
    xs = np.linspace(0.0, 1.0, _MEAN_SAMPLES)
    weights = np.ones(_MEAN_SAMPLES)
    weights[1:-1:2], weights[2:-1:2] = 4.0, 2.0
    power_mean = w_in * float(np.dot(weights, in_torque_x(xs))) / (3.0 * (_MEAN_SAMPLES - 1))

    # the roller's rolling and its equivalent load over the sample intervals
    if contact_arc is None:
        arc = float(load.pitch_radius) * psi
        rolling_note = "assumed: the roller rolls R_p·|dψ| (no contact path given)"
    else:
        arc = _as_samples("contact_arc", contact_arc, theta)
        if not (np.all(np.isfinite(arc)) and np.all(np.diff(arc) >= 0)):
            raise SpecError("indexer.contact_arc", "must be a finite, non-decreasing cumulative arc length [m]")
        rolling_note = "from the contact path on the cam (rolling without slip)"
    revs = np.diff(arc) / (TWO_PI * float(load.roller_radius))
    top = float(normal_force.max(initial=0.0))
    scale = top if top > 0 else 1.0
    bin_load = scale * (0.5 * ((normal_force[:-1] / scale) ** p + (normal_force[1:] / scale) ** p)) ** (1.0 / p)
    p_eq = equivalent_load(bin_load, revs, p)
    roller_revs = float(np.sum(revs))
    l10 = rating_life(float(load.roller_rating), p_eq, p)
    revs_per_hour = roller_revs * 60.0 * float(load.input_speed)
    l10_hours = l10 * 1e6 / revs_per_hour if revs_per_hour > 0 else math.inf

    i_force = int(np.argmax(normal_force))
    i_stress = int(np.argmax(stress))
    return DriveSizing(
        load=load, characteristics=law, theta=theta, psi=psi, dpsi=dpsi, ddpsi=ddpsi,
        omega_out=omega_out, alpha_out=alpha_out, torque_out=torque_out, torque_in=torque_in,
        power_in=power_in, normal_force=normal_force, contact_stress=stress,
        input_omega=w_in, index_time=t_index, dwell_time=t_dwell,
        omega_out_peak=law.C_v * h / t_index, alpha_out_peak=law.C_a * h / t_index**2,
        torque_out_peak=t_out_peak, torque_out_peak_at=x_out * beta,
        torque_in_peak=t_in_peak, torque_in_peak_at=x_in * beta,
        power_in_peak=t_in_peak * w_in, power_in_mean=power_mean,
        normal_force_peak=float(normal_force[i_force]), normal_force_peak_at=float(theta[i_force]),
        contact_stress_peak=float(stress[i_stress]), contact_stress_peak_at=float(theta[i_stress]),
        equivalent_load=p_eq, roller_revolutions=roller_revs, l10=l10, l10_hours=l10_hours,
        rolling_note=rolling_note,
    )


def _input_torque(torque_out: Array, dpsi: Array, eta: float) -> Array:
    """Camshaft torque [N·m] from the output torque and ψ' by virtual work, the efficiency η
    against the flow of power (÷η where the cam drives, ×η where the output drives back)."""
    ideal = torque_out * dpsi
    return np.where(ideal >= 0, ideal / eta, ideal * eta)


"""The dynamics of a spec's follower train at its speed: one call, :func:`analyse_dynamics`, and
its plain result (:class:`DynamicsResult`), whose :meth:`~DynamicsResult.summary` is report.json's
``dynamics`` section.

Quantities (docs/dynamics.md):

* the dynamic displacement error q − u (the mass's lift minus the cam's, lift units: mm or arm
  degrees) and its vibration about the quasi-static deflection −(J ü + P + k_s u)/K;
* the normal contact force F = Q·lever, rigid (Q = J ü + P + k_s u) and dynamic, its extremes and
  where the follower leaves the cam (F = 0), with the largest gap and the landing speeds;
* residual vibration: the largest vibration in the segment after each rise and return;
* the camshaft torque T = Q·u′ (virtual work, no friction), rigid and dynamic, its extremes, RMS
  and the work per revolution (0 for the rigid, conservative train; the damper's and the impacts'
  losses for the dynamic one);
* the jump speed (:mod:`.jump`) and the rigid follower's.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from ..followers.base import Follower
from ..kinds import body_of
from ..motion.program import MotionProgram
from ..spec.dynamics import SWEEP_LOW_FRACTION
from ..spec.model import CamSpec
from ..spec.params import unit_name
from .contact import SeparatedResponse, separated_response
from .jump import RPM, SWEEP_MAX_SAMPLES, JumpSpeed, find_jump_speed, rigid_jump_speed, sweep_range
from .model import TrainModel, analysis_rpm, train_model
from .model import rigid_load as rigid_load_of
from .periodic import CamInput, PeriodicResponse, cam_input, parabolic_min, periodic_response, sample_count
from .turret import turret_summary

TWO_PI = 2.0 * math.pi

#: progress callback: (done, total, what)
Progress = Callable[[int, int, str], None]


@dataclass
class DynamicsResult:
    """The dynamics at one speed (arrays over the N samples of one revolution, the steady state).

    Attributes:
        model: the train.
        omega: cam speed [rad/s].
        theta: cam angles [rad].
        lift: the cam's lift s [spec lift unit].
        position: the mass's lift q/lift_scale [spec lift unit].
        error: position − lift.
        vibration: error minus the quasi-static deflection.
        force, rigid_force: normal contact force [force unit].
        torque, rigid_torque: camshaft torque [torque unit].
        on_cam: the follower touches the cam.
        periodic: the harmonic solution (on the cam everywhere, or the start of the run).
        separated: the run off the cam, or None when the follower stays on it.
        jump: the jump-speed sweep, or None.
        inp: the cam's drive at the samples.
        segment_kinds: the motion program's segment kinds and laws (residual vibration).
        units: the spec's units.
        lift_unit: "length" or "angle".
    """

    model: TrainModel
    omega: float
    #: the cam speed of the analysis [rpm] as given (ω is computed from it, never the other way round)
    speed_rpm: float
    theta: np.ndarray
    lift: np.ndarray
    position: np.ndarray
    error: np.ndarray
    vibration: np.ndarray
    force: np.ndarray
    rigid_force: np.ndarray
    torque: np.ndarray
    rigid_torque: np.ndarray
    on_cam: np.ndarray
    periodic: PeriodicResponse
    separated: SeparatedResponse | None
    jump: JumpSpeed | None
    inp: CamInput = field(repr=False)
    program: MotionProgram = field(repr=False)
    units: str = "mm"
    lift_unit: str = "length"
    #: the body holds the follower both ways (a groove, a conjugate pair, a cylindrical cam's
    #: groove): no separation, the load changes side where the contact force changes sign
    form_closed: bool = False
    #: the body's words for which side drives (``Body.drive_note``)
    drive_note: str = ""
    #: an indexer's output train (:mod:`.turret`): the "contact force" is the shaft torque, and the
    #: summary holds the ``turret`` subsection
    turret: bool = False

    @property
    def theta_deg(self) -> np.ndarray:
        return np.rad2deg(self.theta)

    @property
    def contact_kept(self) -> bool:
        return self.separated is None

    def residual_vibration(self) -> list[dict[str, Any]]:
        """Per rise/return: the largest |vibration| in the segment that follows it (a dwell's
        free vibration after the motion), with its cam angle."""
        prog = self.program
        out = []
        n_seg = len(prog.starts)
        seg = self.inp.segment
        for k in range(n_seg):
            if prog.laws[k] is None:
                continue
            nxt = (k + 1) % n_seg
            mask = seg == nxt
            if not mask.any():
                continue
            v = np.where(mask, np.abs(self.vibration), -np.inf)
            j = int(np.argmax(v))
            out.append({"after": k, "kind": prog.kinds[k], "next": nxt, "next_kind": prog.kinds[nxt],
                        "amplitude": float(v[j]), "at_deg": _deg(self.theta[j])})
        return out

    def summary(self) -> dict[str, Any]:
        """report.json's ``dynamics`` section (spec units; angles in degrees; speeds in rpm)."""
        m = self.model
        u = self.units
        angle = self.lift_unit == "angle"
        lift_u = "deg" if angle else u
        torque_u = unit_name("torque", u)
        force_u = torque_u if self.turret else unit_name("force", u)
        fmin, fmin_at = _extreme(self.force, self.theta, "min")
        fmax, fmax_at = _extreme(self.force, self.theta, "max")
        rmin, rmin_at = _extreme(self.rigid_force, self.theta, "min")
        rmax, rmax_at = _extreme(self.rigid_force, self.theta, "max")
        emax, emax_at = _extreme(np.abs(self.error), self.theta, "max")
        vmax, vmax_at = _extreme(np.abs(self.vibration), self.theta, "max")
        f_n = m.natural_frequency / TWO_PI
        contact: dict[str, Any] = {
            "kept": self.contact_kept,
            "min_force": fmin, "min_force_at_deg": fmin_at,
            "max_force": fmax, "max_force_at_deg": fmax_at,
            "rigid_min_force": rmin, "rigid_min_force_at_deg": rmin_at,
            "rigid_max_force": rmax, "rigid_max_force_at_deg": rmax_at,
            "unit": force_u,
        }
        if self.form_closed:
            contact["closure"] = "form"
            contact["drive"] = {
                **sign_changes(self.force, self.theta),
                "rigid": sign_changes(self.rigid_force, self.theta),
                "note": f"form closure: {self.drive_note}"}
        steady: dict[str, Any]
        if self.separated is None:
            steady = {"method": "periodic solve (harmonic balance, exact for the linear train on the cam)",
                      "revolutions": 0, "periodic": True,
                      "spectral_tail": self.periodic.spectral_tail()}
        else:
            sep = self.separated
            gap = np.where(self.on_cam, -np.inf, self.error)
            j = int(np.argmax(gap))
            contact.update({
                "separations": [[_deg_unwrapped(a), _deg_unwrapped(b)] for a, b in sep.flights],
                "off_cam_deg": float(np.count_nonzero(~self.on_cam) * 360.0 / self.theta.size),
                "max_gap": float(gap[j]) if np.isfinite(gap[j]) else 0.0,
                "max_gap_at_deg": _deg(self.theta[j]),
                "max_landing_speed": (max(abs(v) for v in sep.impact_speeds) / m.lift_scale
                                      if sep.impact_speeds else None),
                "landing_speed_unit": f"{lift_u}/s",
            })
            steady = {"method": "exact piecewise solution, revolution after revolution from the periodic solve's state",
                      "revolutions": sep.revolutions, "periodic": sep.periodic, "change": sep.change,
                      "contact_changes": sep.phases - 1}
            if sep.note:
                steady["note"] = sep.note
        out: dict[str, Any] = {
            "speed_rpm": self.speed_rpm,
            "model": {
                "coordinate": "turret angle" if self.turret else "arm angle" if angle else "lift",
                "mass": m.spec_inertia, "mass_unit": unit_name("inertia" if angle else "mass", u),
                "stiffness": m.stiffness,
                "stiffness_unit": unit_name("torsional_stiffness" if angle else "stiffness", u),
                "spring_rate": m.spring_rate, "preload": m.preload,
                "preload_unit": torque_u if angle else force_u,
                "damping_ratio": m.damping_ratio,
                "natural_frequency_hz": f_n,
                "frequency_ratio": f_n / (self.omega / TWO_PI),
                "samples": int(self.theta.size),
            },
            "contact": contact,
            "error": {"max": emax, "at_deg": emax_at, "max_vibration": vmax, "vibration_at_deg": vmax_at,
                      "unit": lift_u},
            "residual_vibration": self.residual_vibration(),
            "torque": {"rigid": _torque_summary(self.rigid_torque, self.theta),
                       "dynamic": _torque_summary(self.torque, self.theta),
                       "unit": torque_u},
            "steady_state": steady,
        }
        if self.turret:
            contact["meaning"] = "the turret shaft's torque k_t(ψ − φ) + c(ψ̇ − φ̇) (lever 1)"
            out["turret"] = turret_summary(self)
        if self.jump is not None:
            jp = self.jump
            out["jump_speed"] = {
                "rpm": jp.rpm, "rigid_rpm": jp.rigid_rpm,
                "ratio_to_speed": None if jp.rpm is None else jp.rpm / self.speed_rpm,
                "sweep_from_rpm": float(jp.speeds_rpm[0]), "sweep_to_rpm": float(jp.speeds_rpm[-1]),
                "sweep_points": int(jp.speeds_rpm.size), "samples": jp.samples, "note": jp.note,
                "sweep": {"speeds_rpm": [float(x) for x in jp.speeds_rpm],
                          "min_force": [float(x) for x in jp.min_force]},
            }
        return out

    def series(self) -> dict[str, np.ndarray]:
        """The θ-series (for CSV and plots): angles [deg], lift, position, error, forces, torques."""
        return {"theta_deg": self.theta_deg, "lift": self.lift, "position": self.position, "error": self.error,
                "vibration": self.vibration, "rigid_force": self.rigid_force, "force": self.force,
                "rigid_torque": self.rigid_torque, "torque": self.torque,
                "on_cam": self.on_cam.astype(float)}


#: a force within this fraction of the largest |F| counts as positive, as a zero does: the residual
#: vibration of a dwell (|F| ~ 1e-7 of the peak in the examples) chooses no wall
SIDE_TOLERANCE = 1e-3


def sign_changes(force: np.ndarray, theta: np.ndarray) -> dict[str, Any]:
    """Where a periodic force sampled at equal angles ``theta`` [rad] changes sign: the cam angles
    [deg] where it crosses −tol (linear between samples, the last sample joined to the first), and
    the share of the turn it is positive and negative; a force above −tol, tol =
    :data:`SIDE_TOLERANCE` × max |F|, counts as positive (a zero does)."""
    f = np.asarray(force, float)
    tol = SIDE_TOLERANCE * float(np.max(np.abs(f))) if f.size else 0.0
    g = np.roll(f, -1)
    t1 = np.append(theta[1:], theta[0] + TWO_PI)
    sign = np.where(f < -tol, -1, 1)
    flips = np.nonzero(sign != np.roll(sign, -1))[0]
    at = theta[flips] + (-tol - f[flips]) * (t1[flips] - theta[flips]) / (g[flips] - f[flips])
    deg = np.mod(np.rad2deg(at), 360.0)
    return {"changes_at_deg": [float(a) for a in np.sort(deg)],
            "positive_share": float(np.mean(sign > 0)), "negative_share": float(np.mean(sign < 0))}


def _deg(theta: float) -> float:
    d = float(np.rad2deg(theta)) % 360.0
    return 0.0 if abs(d - 360.0) < 1e-9 else d


def _deg_unwrapped(theta: float) -> float | None:
    return None if not np.isfinite(theta) else float(np.rad2deg(theta))


def _extreme(values: np.ndarray, theta: np.ndarray, kind: str) -> tuple[float, float]:
    """(min or max of periodic samples refined by a parabola, its cam angle [deg])."""
    sign = 1.0 if kind == "min" else -1.0
    v, pos = parabolic_min(sign * np.asarray(values, float))
    return float(sign * v), _deg(float(pos) * TWO_PI / theta.size)


def _torque_summary(torque: np.ndarray, theta: np.ndarray) -> dict[str, float]:
    tmax, tmax_at = _extreme(torque, theta, "max")
    tmin, tmin_at = _extreme(torque, theta, "min")
    return {"max": tmax, "max_at_deg": tmax_at, "min": tmin, "min_at_deg": tmin_at,
            "rms": float(np.sqrt(np.mean(torque * torque))),
            # ∮T dθ: the mean of a periodic function on equal samples (exact for its harmonics < N/2)
            "work_per_revolution": float(np.mean(torque) * TWO_PI)}


def analyse_dynamics(spec: CamSpec, program: MotionProgram | None = None, *, speed_rpm: float | None = None,
                     sweep: bool | None = None, progress: Progress | None = None,
                     follower: Follower | None = None) -> DynamicsResult:
    """The dynamics of ``spec``'s follower train at ``speed_rpm`` (default: dynamics.speed_rpm or
    cam.speed_rpm), with the jump-speed sweep unless ``sweep`` is False (default: when
    dynamics.sweep_points > 0); ``progress(done, total, what)`` reports the sweep.

    Raises:
        SpecError: the spec lacks the train's data (naming the field).
        SolveError: an undamped train resonates exactly.
    """
    body = body_of(spec)
    fol = follower or body.dynamics_follower(spec)
    form_closed = body.closure == "form"
    model = train_model(spec, fol)
    program = program or MotionProgram.from_spec(spec)
    dy = spec.dynamics
    rpm = speed_rpm if speed_rpm is not None else analysis_rpm(spec)
    omega = rpm / RPM
    n = sample_count(model, omega, dy.samples)
    inp = cam_input(program, fol, n)
    per = periodic_response(model, inp, omega)
    c = model.lift_scale
    rigid_load = rigid_load_of(model, inp.u, inp.d2u, omega)
    fmin = float(np.min(per.load * inp.lever))
    separated = None
    if fmin <= 0 and not form_closed:
        separated = separated_response(model, inp, per, program, omega, dy.revolutions)
        q, load, on_cam = separated.q, separated.load, separated.on_cam
    else:
        q, load, on_cam = per.q, per.load, np.ones(n, dtype=bool)
    quasi_static = -rigid_load / model.total_stiffness
    err = q - inp.u
    jump = None
    do_sweep = dy.sweep_points > 0 if sweep is None else sweep
    if do_sweep and dy.sweep_points > 0 and not form_closed:     # form closure: no jump
        rigid = rigid_jump_speed(model, program, inp)
        lo, hi = sweep_range(model, omega, rigid, dy.sweep_min_rpm, dy.sweep_max_rpm, SWEEP_LOW_FRACTION)
        n_sweep = min(sample_count(model, lo, dy.samples), max(SWEEP_MAX_SAMPLES, n if dy.samples else 0))
        sweep_inp = inp if n_sweep == n else cam_input(program, fol, n_sweep)
        speeds = np.linspace(lo, hi, dy.sweep_points)
        jump = find_jump_speed(model, sweep_inp, speeds, rigid, progress)
    return DynamicsResult(
        model=model, omega=omega, speed_rpm=float(rpm), theta=inp.theta, lift=inp.u / c, position=q / c, error=err / c,
        vibration=(err - quasi_static) / c, force=load * inp.lever, rigid_force=rigid_load * inp.lever,
        torque=load * inp.du, rigid_torque=rigid_load * inp.du, on_cam=on_cam, periodic=per,
        separated=separated, jump=jump, inp=inp, program=program, units=spec.units,
        lift_unit=fol.lift_unit, form_closed=form_closed,
        drive_note=body.drive_note, turret=fol.turret)

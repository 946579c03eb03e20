"""The follower train when it leaves the cam: exact piecewise solution, revolution by revolution.

Above the jump speed the periodic solution of :mod:`.periodic` asks the cam to pull (Q < 0), which
a force-closed follower cannot do.  The motion then alternates between two linear phases, each
solved in closed form (no time-stepping error):

* **on the cam** (Q > 0): q = q_p + q_h — the periodic solution of :mod:`.periodic` plus the free,
  damped vibration of the train that makes up the state at the phase's start
  (e^{−στ}[a cos ω_d τ + (b + σa) sin ω_d τ/ω_d], σ = ζω_n, ω_d = ω_n√(1 − ζ²));
* **off the cam**: the mass on its return spring alone, J q̈ = −P − k_s q
  (q = q₀ cos Ωτ + q̇₀ sin Ωτ/Ω − (P/J)(1 − cos Ωτ)/Ω², Ω = √(k_s/J); a parabola when k_s = 0).

The contact end of the train is massless: the contact load is Q = max(0, k_f δ + c δ̇) while the
train is compressed, δ = u − q > 0, and 0 otherwise.  A phase on the cam ends where Q falls to 0;
the follower lands again where δ > 0 and k_f δ + c δ̇ > 0.  Each phase is evaluated on the
revolution's sample grid (vectorised), the first sign change found there and refined by Brent's
method on the closed forms.  The Python loop runs over phases — a few per revolution — never over
samples.  Revolutions follow one another from the periodic solution's state at θ = 0 until one
revolution ends where the one before ended (the steady state) or ``revolutions`` are done.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from ..motion.program import MotionProgram
from .model import TrainModel
from .periodic import CamInput, PeriodicResponse, fourier_eval

TWO_PI = 2.0 * math.pi
#: a revolution repeats the one before when its end state differs by less than this, relative to
#: the range of u (and of u̇ for the velocity)
PERIODIC_TOLERANCE = 1e-9
#: most phases per revolution before the run is called chatter and stopped
MAX_PHASES_PER_REV = 2000
FIRST_WINDOW = 256


@dataclass
class SeparatedResponse:
    """The last revolution of the run (arrays over the N samples) and how the run went.

    Attributes:
        q, velocity, load: as :class:`PeriodicResponse` (load 0 off the cam).
        on_cam: True where the follower touches the cam.
        flights: (θ_off, θ_on) [rad, unwrapped from the revolution's start] of each flight that
            overlaps the last revolution.
        impact_speeds: the closing speed δ̇ [coordinate/s] at each landing in the last revolution.
        revolutions: revolutions run.
        periodic: the last revolution repeated the one before.
        change: the largest change of (q, q̇) over the last revolution, relative (see
            :data:`PERIODIC_TOLERANCE`).
        phases: phases in the last revolution.
        note: why the run stopped early, if it did.
    """

    q: np.ndarray
    velocity: np.ndarray
    load: np.ndarray
    on_cam: np.ndarray
    flights: list[tuple[float, float]] = field(default_factory=list)
    impact_speeds: list[float] = field(default_factory=list)
    revolutions: int = 0
    periodic: bool = False
    change: float = float("nan")
    phases: int = 0
    note: str = ""


class _Phases:
    """Closed forms of the two phases at the model's numbers."""

    def __init__(self, model: TrainModel, inp: CamInput, periodic: PeriodicResponse, program: MotionProgram,
                 omega: float):
        self.m, self.inp, self.p, self.program, self.omega = model, inp, periodic, program, omega
        self.n = inp.n
        self.dt = TWO_PI / self.n / omega
        zeta, wn = model.damping_ratio, model.natural_frequency
        self.sigma = zeta * wn
        self.wd = wn * np.sqrt(complex(1.0 - zeta * zeta))
        self.wn2 = wn * wn
        self.flight_w = model.flight_frequency
        k = np.arange(periodic.error_spectrum.size)
        # q_p = u + e: e and ė as Fourier series (u from the program itself)
        self.err_k = periodic.error_spectrum
        self.derr_k = 1j * k * periodic.error_spectrum

    # ---- the drive and the particular solution at any time ---------------------------------
    def drive(self, t: float) -> tuple[float, float]:
        th = np.array([self.omega * t])
        k = self.program.evaluate(th)
        c = self.m.lift_scale
        return c * float(k.s[0]), c * float(k.ds[0]) * self.omega

    def particular(self, t: float) -> tuple[float, float]:
        u, du = self.drive(t)
        th = self.omega * t
        e = float(fourier_eval(self.err_k, th, self.n)[0])
        de = float(fourier_eval(self.err_k, th, self.n, 1)[0]) * self.omega
        return u + e, du + de

    # ---- the phases' closed forms at grid indices or at one time ---------------------------
    def contact(self, tau: np.ndarray, a: float, b: float) -> tuple[np.ndarray, np.ndarray]:
        """The homogeneous part (q_h, q̇_h) after τ from (a, b)."""
        e = np.exp(-self.sigma * tau)
        wd = self.wd
        cos = np.cos(wd * tau).real
        s = (tau * np.sinc(wd * tau / np.pi)).real
        return e * (a * cos + (b + self.sigma * a) * s), e * (b * cos - (self.sigma * b + self.wn2 * a) * s)

    def flight(self, tau: np.ndarray, q0: float, v0: float) -> tuple[np.ndarray, np.ndarray]:
        w = self.flight_w
        cos = np.cos(w * tau)
        s = tau * np.sinc(w * tau / np.pi)
        one_minus_cos = 0.5 * tau * tau * np.sinc(w * tau / TWO_PI) ** 2
        pj = self.m.preload / self.m.inertia
        return q0 * cos + v0 * s - pj * one_minus_cos, -q0 * w * w * s + v0 * cos - pj * s

    def load(self, u, du, q, v):
        return self.m.stiffness * (u - q) + self.m.damping * (du - v)


def separated_response(model: TrainModel, inp: CamInput, periodic: PeriodicResponse, program: MotionProgram,
                       omega: float, revolutions: int) -> SeparatedResponse:
    """Run the train over up to ``revolutions`` revolutions at ``omega`` [rad/s] from the
    periodic solution's state at θ = 0, letting it leave the cam; return the last revolution."""
    ph = _Phases(model, inp, periodic, program, omega)
    n, dt = ph.n, ph.dt
    u_grid, du_grid = inp.u, inp.du * omega
    qp_grid, vp_grid = periodic.q, periodic.velocity
    q_out, v_out, load_out = np.empty(n), np.empty(n), np.empty(n)
    on_out = np.empty(n, dtype=bool)
    scale_q = max(float(np.ptp(u_grid)), abs(float(np.mean(periodic.error))), 1e-300)
    scale_v = max(float(np.ptp(du_grid)), 1e-300)

    t0 = 0.0
    z = (float(qp_grid[0]), float(vp_grid[0]))
    on_cam = bool(periodic.load[0] > 0)
    anchor = ph.particular(t0)
    start_state = z
    result = SeparatedResponse(q_out, v_out, load_out, on_out)
    for rev in range(revolutions):
        flights: list[tuple[float, float]] = []
        impacts: list[float] = []
        phases = 1
        t_rev = rev * n * dt
        j = 0                      # the next grid index of this revolution to record
        while j < n:
            # the phase (on_cam) began at t0 in state z: evaluate it at grid j, j+1, … (windows)
            j_hit = None
            w = FIRST_WINDOW
            while j < n:
                idx = np.arange(j, min(j + w, n))
                tau = t_rev + idx * dt - t0
                u, du = u_grid[idx], du_grid[idx]
                if on_cam:
                    qh, vh = ph.contact(tau, z[0] - anchor[0], z[1] - anchor[1])
                    q, v = qp_grid[idx] + qh, vp_grid[idx] + vh
                    g = ph.load(u, du, q, v)
                    stop = g <= 0
                else:
                    q, v = ph.flight(tau, *z)
                    g = ph.load(u, du, q, v)
                    stop = (u - q > 0) & (g > 0)
                stop &= tau > 0
                hit = np.flatnonzero(stop)
                upto = int(hit[0]) if hit.size else idx.size
                q_out[idx[:upto]] = q[:upto]
                v_out[idx[:upto]] = v[:upto]
                load_out[idx[:upto]] = np.maximum(g[:upto], 0.0) if on_cam else 0.0
                on_out[idx[:upto]] = on_cam
                if hit.size:
                    j_hit = int(idx[hit[0]])
                    break
                j = int(idx[-1]) + 1
                w *= 2
            if j_hit is None:
                break                                  # the phase lasts to the revolution's end
            # refine the switch between the phase's last grid time before it (or its start) and t_hit
            t_hi = t_rev + j_hit * dt
            t_lo = max(t0, t_hi - dt)
            f = _switch_function(ph, on_cam, t0, z, anchor)
            f_lo, f_hi = f(t_lo), f(t_hi)
            t_sw = (brentq(f, t_lo, t_hi, xtol=1e-14 * (1.0 + abs(t_hi)), rtol=4 * np.finfo(float).eps)
                    if f_lo > 0 > f_hi else t_hi)
            z = _state(ph, on_cam, t0, z, anchor, t_sw)
            if on_cam:
                flights.append((omega * (t_sw - t_rev), math.nan))
            else:
                _u, du_sw = ph.drive(t_sw)
                impacts.append(du_sw - z[1])
                if flights and math.isnan(flights[-1][1]):
                    flights[-1] = (flights[-1][0], omega * (t_sw - t_rev))
                else:
                    flights.append((-math.inf, omega * (t_sw - t_rev)))     # left in the revolution before
            on_cam = not on_cam
            t0 = t_sw
            anchor = ph.particular(t0)
            j = j_hit
            phases += 1
            if phases > MAX_PHASES_PER_REV:
                result.note = (f"chatter: more than {MAX_PHASES_PER_REV} contact changes in revolution {rev + 1}; "
                               "stopped there")
                break
        # the revolution's end: the state at its last instant, the next phase anchored there
        t_end = t_rev + n * dt
        z = _state(ph, on_cam, t0, z, anchor, t_end)
        t0 = t_end
        anchor = ph.particular(t0)
        if flights and math.isnan(flights[-1][1]):
            flights[-1] = (flights[-1][0], math.inf)                            # lasts into the next
        change = max(abs(z[0] - start_state[0]) / scale_q, abs(z[1] - start_state[1]) / scale_v)
        start_state = z
        result.flights, result.impact_speeds = flights, impacts
        result.revolutions, result.change, result.phases = rev + 1, change, phases
        if result.note:
            break
        if change < PERIODIC_TOLERANCE:
            result.periodic = True
            break
    return result


def _state(ph: _Phases, on_cam: bool, t0: float, z: tuple[float, float], anchor: tuple[float, float],
           t: float) -> tuple[float, float]:
    """(q, q̇) at time t of the phase that began at t0 in state z (``anchor``: the periodic
    solution at t0)."""
    tau = np.array([t - t0])
    if on_cam:
        qh, vh = ph.contact(tau, z[0] - anchor[0], z[1] - anchor[1])
        qp, vp = ph.particular(t)
        return qp + float(qh[0]), vp + float(vh[0])
    q, v = ph.flight(tau, *z)
    return float(q[0]), float(v[0])


def _switch_function(ph: _Phases, on_cam: bool, t0: float, z: tuple[float, float], anchor: tuple[float, float]):
    """The function whose sign change from + to − ends the phase: the load on the cam; off the
    cam −min(k_f δ, load), which turns negative once the follower lands."""
    def f(t: float) -> float:
        q, v = _state(ph, on_cam, t0, z, anchor, t)
        u, du = ph.drive(t)
        g = ph.load(u, du, q, v)
        return g if on_cam else -min(ph.m.stiffness * (u - q), g)

    return f

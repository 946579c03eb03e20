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

from ..motion.program import MotionProgram
from .model import TrainModel
from .periodic import CamInput, PeriodicResponse

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
        # q_p = u + e between samples: e and e′ as Fourier series (u from the program itself), the
        # harmonics summed only as far as they count: the rest bounds the error by 1e-14 of e's range
        spec = periodic.error_spectrum
        k = np.arange(spec.size)
        tail = np.cumsum((np.abs(spec) * (1.0 + k))[::-1])[::-1]
        scale = max(float(np.ptp(periodic.error)), float(np.max(np.abs(periodic.error))), 1e-300)
        keep = int(np.searchsorted(-tail, -1e-14 * scale)) + 1
        self.k = k[:keep]
        self.err_k = spec[:keep] * np.where(self.k == 0, 1.0, 2.0)

    # ---- the drive and the particular solution at any time ---------------------------------
    def drive(self, t: float) -> tuple[float, float]:
        th = np.array([self.omega * t])
        k = self.program.evaluate(th)
        c = self.m.lift_scale
        return c * float(k.s[0]), c * float(k.ds[0]) * self.omega

    def particular(self, t: float, drive: tuple[float, float] | None = None) -> tuple[float, float]:
        u, du = self.drive(t) if drive is None else drive
        z = np.exp(1j * (self.omega * t) * self.k) * self.err_k
        return u + float(z.real.sum()), du + float((1j * self.k * z).real.sum()) * self.omega

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
    from scipy.optimize import brentq  # deferred: scipy.optimize, a follower leaving the cam alone

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
            f = _switch_function(ph, on_cam, t0, z, anchor, j_hit, t_rev)
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
           t: float, drive: tuple[float, float] | None = None) -> tuple[float, float]:
    """(q, q̇) at time t of the phase that began at t0 in state z (``anchor``: the periodic
    solution at t0; ``drive``: (u, u̇) at t when already known)."""
    tau = np.array([t - t0])
    if on_cam:
        qh, vh = ph.contact(tau, z[0] - anchor[0], z[1] - anchor[1])
        qp, vp = ph.particular(t, drive)
        return qp + float(qh[0]), vp + float(vh[0])
    q, v = ph.flight(tau, *z)
    return float(q[0]), float(v[0])


def _hermite5(y0: float, v0: float, a0: float, y1: float, v1: float, a1: float, h: float):
    """The quintic on [0, h] with value, slope and curvature y, v, a at both ends: (value, slope) at τ."""
    d = y1 - y0
    V0, V1, A0, A1 = v0 * h, v1 * h, a0 * h * h, a1 * h * h
    c = (y0, V0, 0.5 * A0, 10 * d - 6 * V0 - 4 * V1 - 1.5 * A0 + 0.5 * A1,
         -15 * d + 8 * V0 + 7 * V1 + 1.5 * A0 - A1, 6 * d - 3 * V0 - 3 * V1 - 0.5 * A0 + 0.5 * A1)

    def at(tau: float) -> tuple[float, float]:
        s = tau / h
        y = c[0] + s * (c[1] + s * (c[2] + s * (c[3] + s * (c[4] + s * c[5]))))
        dy = c[1] + s * (2 * c[2] + s * (3 * c[3] + s * (4 * c[4] + s * 5 * c[5])))
        return y, dy / h

    return at


def _local_drive(ph: _Phases, j: int):
    """(u, u̇) and the periodic solution (q_p, q̇_p) between grid times j − 1 and j as quintics
    through their values and first two time derivatives at both ends (q̈_p from the equation of
    motion) — exact to ~(ω_n Δt)⁶/46 080 of the vibration with 16 samples per natural period —
    or None when a motion segment ends inside (its derivatives jump there)."""
    n, inp, per, w = ph.n, ph.inp, ph.p, ph.omega
    i0, i1 = (j - 1) % n, j % n
    if inp.segment[i0] != inp.segment[i1]:
        return None
    m = ph.m
    u = [inp.u[i0], inp.u[i1]]
    du = [w * inp.du[i0], w * inp.du[i1]]
    ddu = [w * w * inp.d2u[i0], w * w * inp.d2u[i1]]
    qp = [per.q[i0], per.q[i1]]
    vp = [per.velocity[i0], per.velocity[i1]]
    ap = [(m.stiffness * (u[k] - qp[k]) + m.damping * (du[k] - vp[k]) - m.preload - m.spring_rate * qp[k]) / m.inertia
          for k in (0, 1)]
    return (_hermite5(u[0], du[0], ddu[0], u[1], du[1], ddu[1], ph.dt),
            _hermite5(qp[0], vp[0], ap[0], qp[1], vp[1], ap[1], ph.dt))


def _switch_function(ph: _Phases, on_cam: bool, t0: float, z: tuple[float, float], anchor: tuple[float, float],
                     j: int, t_rev: float):
    """The function whose sign change from + to − ends the phase between grid times j − 1 and j:
    the load on the cam; off the cam −min(k_f δ, load), which turns negative once the follower
    lands.  Inside one motion segment the drive and the periodic solution come from their local
    quintics (no program or Fourier evaluation per call), else exactly."""
    local = _local_drive(ph, j)
    t_left = t_rev + (j - 1) * ph.dt

    def f(t: float) -> float:
        if local is None:
            u, du = ph.drive(t)
            q, v = _state(ph, on_cam, t0, z, anchor, t, (u, du))
        else:
            u, du = local[0](t - t_left)
            tau = np.array([t - t0])
            if on_cam:
                qh, vh = ph.contact(tau, z[0] - anchor[0], z[1] - anchor[1])
                qp, vp = local[1](t - t_left)
                q, v = qp + float(qh[0]), vp + float(vh[0])
            else:
                qf, vf = ph.flight(tau, *z)
                q, v = float(qf[0]), float(vf[0])
        g = ph.load(u, du, q, v)
        return g if on_cam else -min(ph.m.stiffness * (u - q), g)

    return f

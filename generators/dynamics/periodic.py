"""The steady state of the follower train on the cam, solved as a periodic problem.

While the follower stays on the cam the train is linear and the cam turns at a constant ω, so the
steady state is the periodic solution of (θ = ωt, ′ = d/dθ)

    J ω² q″ + c ω q′ + K q = k_f u + c ω u′ − P,        K = k_f + k_s.

With u(θ) = Σ U_k e^{ikθ} its harmonics solve one by one (D_k = K − J ω²k² + i c ω k):

    contact load  Q_k = (k_f + i c ω k)(k_s − J ω²k²)/D_k · U_k   (+ k_f P/K at k = 0)
    error q − u   E_k = −(k_s − J ω²k²)/D_k · U_k                 (− P/K at k = 0)

— no time stepping, no transient to wait for, and no cancellation (Q is not formed as a
difference of nearly equal q and u).  The U_k are the FFT of u sampled at N equal angles: the
motion laws are C² or smoother, so U_k falls as k⁻³…k⁻⁴ and the aliasing of the sampled spectrum
is far below the rounding of u; N is chosen so that harmonics up to 8 ω_n are kept (16 samples
per natural period) and the discarded tail is reported (``spectral_tail``).

Everything is vectorised over the samples and, for the jump-speed sweep, over the speeds (one 2-D
inverse FFT per chunk of speeds).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..errors import SolveError
from ..followers import Follower
from ..motion.program import Kinematics, MotionProgram
from .model import TrainModel

TWO_PI = 2.0 * math.pi
MIN_SAMPLES = 4096
MAX_SAMPLES = 1 << 20
#: samples per natural period of the train
SAMPLES_PER_PERIOD = 16
#: complex values per chunk of the speed sweep (memory bound)
SWEEP_CHUNK_VALUES = 1 << 21


def sample_count(model: TrainModel, omega: float, requested: int | None = None) -> int:
    """Samples per revolution: ``requested``, else the power of two ≥ 16 ω_n/ω (≥ 4096)."""
    if requested is not None:
        return int(requested)
    need = SAMPLES_PER_PERIOD * model.natural_frequency / omega
    n = MIN_SAMPLES
    while n < need and n < MAX_SAMPLES:
        n *= 2
    return n


@dataclass(frozen=True)
class CamInput:
    """The cam's drive of the train at N equal cam angles θ_j = 2πj/N.

    Attributes:
        theta: the angles [rad].
        kin: the motion's kinematics there (spec lift units, per rad).
        u, du, d2u: u = lift_scale·s and its θ-derivatives (the follower's coordinate).
        lever: normal contact force per unit generalised load (:meth:`Follower.force_per_load`).
        spectrum: U_k, k = 0 … N/2: u(θ) = Re Σ w_k U_k e^{ikθ} (w = 1 at 0 and N/2, else 2); of an
            advancing program (an indexer's turret), of u minus its mean advance (:mod:`.turret`).
        segment: motion segment of each sample.
    """

    theta: np.ndarray
    kin: Kinematics
    u: np.ndarray
    du: np.ndarray
    d2u: np.ndarray
    lever: np.ndarray
    spectrum: np.ndarray
    segment: np.ndarray

    @property
    def n(self) -> int:
        return int(self.theta.shape[0])


def cam_input(program: MotionProgram, follower: Follower, n: int) -> CamInput:
    """Sample the motion program and the follower's force lever at ``n`` equal angles."""
    theta = TWO_PI * np.arange(n) / n
    seg = program.segment_of(theta)
    kin = program.evaluate(theta, seg)
    c = follower.lift_scale
    u = c * np.asarray(kin.s, float)
    # an advancing program (an indexer's turret, s(2π) = s(0) + advance): the spectrum is its periodic
    # part's, u minus the mean advance — the ramp has no acceleration (with no return spring it moves
    # the train rigidly: no error, no load; :mod:`.turret`)
    periodic_u = u - (c * program.advance / TWO_PI) * theta if program.advance else u
    return CamInput(theta, kin, u, c * np.asarray(kin.ds, float), c * np.asarray(kin.d2s, float),
                    follower.force_per_load(kin), np.fft.rfft(periodic_u) / n, seg)


@dataclass(frozen=True)
class Harmonics:
    """Transfer of u's harmonics to the contact load and the error at one or more speeds."""

    load: np.ndarray       # Q_k
    error: np.ndarray      # E_k = (q − u)_k


def harmonics(model: TrainModel, spectrum: np.ndarray, omega: np.ndarray | float) -> Harmonics:
    """Q_k and E_k for the speeds ``omega`` [rad/s] (shape (S,) → arrays (S, N/2 + 1))."""
    om = np.atleast_1d(np.asarray(omega, float))[:, None]
    k = np.arange(spectrum.shape[-1])[None, :]
    wk = om * k
    J, kf, ks, c, K = model.inertia, model.stiffness, model.spring_rate, model.damping, model.total_stiffness
    rest = ks - J * wk * wk
    d = K - J * wk * wk + 1j * c * wk
    with np.errstate(divide="ignore", invalid="ignore"):
        load = (kf + 1j * c * wk) * rest / d * spectrum
        error = -rest / d * spectrum
    if not (np.all(np.isfinite(load)) and np.all(np.isfinite(error))):
        raise SolveError("dynamics.damping_ratio",
                         "an undamped train resonates: a harmonic of the cam speed hits its natural frequency "
                         "exactly (give a damping ratio > 0 or another speed)")
    load[:, 0] += kf * model.preload / K
    error[:, 0] -= model.preload / K
    return Harmonics(load, error)


@dataclass(frozen=True)
class PeriodicResponse:
    """The steady state on the cam at one speed (arrays over the N samples).

    Attributes:
        omega: cam speed [rad/s].
        q: the lumped mass's position (follower coordinate).
        velocity: q̇ [coordinate/s].
        load: Q, the generalised contact load (≤ 0 where the follower would leave the cam).
        error: q − u.
        load_spectrum, error_spectrum: their harmonics (for evaluation between samples).
    """

    omega: float
    q: np.ndarray
    velocity: np.ndarray
    load: np.ndarray
    error: np.ndarray
    load_spectrum: np.ndarray
    error_spectrum: np.ndarray

    def spectral_tail(self) -> float:
        """Σ w_k|Q_k| over the top quarter of the kept harmonics: a bound on how much the discarded
        ones (above N/2), which fall faster still, can move the load."""
        m = self.load_spectrum.shape[-1]
        tail = self.load_spectrum[3 * m // 4:]
        return float(2.0 * np.sum(np.abs(tail)))


def periodic_response(model: TrainModel, inp: CamInput, omega: float) -> PeriodicResponse:
    """The periodic steady state of the train on the cam at ``omega`` [rad/s] (valid where the
    load stays > 0; :mod:`.contact` continues it where it does not)."""
    n = inp.n
    h = harmonics(model, inp.spectrum, omega)
    load_k, err_k = h.load[0], h.error[0]
    load = np.fft.irfft(load_k * n, n)
    error = np.fft.irfft(err_k * n, n)
    k = np.arange(err_k.size)
    derr = np.fft.irfft(1j * k * err_k * n, n)
    q = inp.u + error
    velocity = omega * (inp.du + derr)
    return PeriodicResponse(float(omega), q, velocity, load, error, load_k, err_k)


def parabolic_min(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(minimum, index + fractional offset) along the last axis of periodic samples, refined by
    the parabola through the smallest sample and its neighbours where the samples around it are
    smooth (their second differences agree within a half: no kink or jump, as at a contact change
    or where a law's acceleration jumps); vectorised over leading axes."""
    v = np.asarray(values, float)
    j = np.argmin(v, axis=-1)
    take = lambda o: np.take_along_axis(v, ((j + o) % v.shape[-1])[..., None], axis=-1)[..., 0]  # noqa: E731
    a2, a, b, c, c2 = take(-2), take(-1), take(0), take(1), take(2)
    den = a - 2 * b + c
    smooth = (den > 0) & (np.abs(a2 - 2 * a + b - den) <= 0.5 * den) & (np.abs(b - 2 * c + c2 - den) <= 0.5 * den)
    with np.errstate(divide="ignore", invalid="ignore"):
        off = np.where(smooth, 0.5 * (a - c) / np.where(smooth, den, 1.0), 0.0)
    off = np.clip(off, -0.5, 0.5)
    return b - 0.25 * (a - c) * off, j + off


def min_force_vs_speed(model: TrainModel, inp: CamInput, omegas: np.ndarray,
                       progress: Callable[[int, int], None] | None = None) -> np.ndarray:
    """The smallest normal contact force over the cycle, min_θ Q(θ)·lever(θ), of the periodic
    steady state at each speed of ``omegas`` [rad/s] — vectorised over the speeds in chunks
    (one 2-D inverse FFT each); ``progress(done, total)`` after each chunk."""
    omegas = np.asarray(omegas, float)
    n = inp.n
    chunk = max(1, SWEEP_CHUNK_VALUES // n)
    out = np.empty(omegas.shape)
    for a in range(0, omegas.size, chunk):
        om = omegas[a:a + chunk]
        h = harmonics(model, inp.spectrum, om)
        force = np.fft.irfft(h.load * n, n, axis=-1) * inp.lever[None, :]
        out[a:a + chunk] = parabolic_min(force)[0]
        if progress is not None:
            progress(min(a + chunk, omegas.size), omegas.size)
    return out

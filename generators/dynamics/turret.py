"""An indexer's output train as one degree of freedom: the turret shaft's torsional stiffness
between the cam-driven turret and the output's inertia (docs/indexing.md, "Dynamics").

The cam drives the turret through its rollers (taken as stiff) along the turret angle ψ(θ) — the
motion program, in degrees, advancing 360°/N per turn instead of closing.  The output (the
turret's load, ``indexer.output_inertia`` J) sits on the turret shaft, a torsional spring k_t
(``dynamics.torsional_stiffness``) with a damper c = 2ζ√(J k_t) (``dynamics.damping_ratio``)::

        cam ── ψ ── turret ──[ k_t ‖ c ]── φ: J

    J φ̈ = T,     T = k_t (ψ − φ) + c (ψ̇ − φ̇)      (the shaft torque)

It is the follower train of :mod:`.model` with no return spring and no preload, held both ways
(form closure: the rollers never leave the cam), so :func:`.analysis.analyse_dynamics` solves it
with the same periodic solve.  The input is not periodic — ψ(θ + 2π) = ψ(θ) + 360°/N — but the
error e = φ − ψ is: J ë + c ė + k_t e = −J ψ̈, and ψ̈ is periodic.  The solve therefore works on
ψ minus its mean advance, ψ − (360°/N)·θ/2π (:func:`.periodic.cam_input`): the ramp has no
acceleration, and with no return spring its steady error and shaft torque are zero.

:class:`cam_workbench.generators.bodies.indexing.turret_train.TurretFollower` (``Body.dynamics_follower``
of the indexers) is what the dynamics read of the turret (its coordinate in degrees, its
inertia, a lever of 1: the "contact load" is the shaft torque); :func:`turret_summary` is the
``turret`` subsection of report.json's ``dynamics`` section — the output's angle error, the shaft's
peak torsional deflection and torque, the residual vibration at the station (each dwell's
amplitude when it starts and when it ends) and the natural frequency against the index time.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from .periodic import parabolic_min

TWO_PI = 2.0 * math.pi
ARCMIN_PER_DEG = 60.0

def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """The cyclic runs of True in ``mask``: (first, last) sample indices (last may be < first when
    the run wraps round the end of the turn); [] when all or none are True."""
    if mask.all() or not mask.any():
        return []
    starts = np.flatnonzero(mask & ~np.roll(mask, 1))
    ends = np.flatnonzero(mask & ~np.roll(mask, -1))
    # each run ends at the first end at or after its start, else (wrapping round) at the first end
    return [(int(s), int(ends[ends >= s][0]) if np.any(ends >= s) else int(ends[0])) for s in starts]


def envelope(error: np.ndarray, rate: np.ndarray, omega_n: float, zeta: float) -> np.ndarray:
    """The free vibration's amplitude A = √(e² + ((ė + ζω_n e)/ω_d)²) of e(t) = A e^{−ζω_n t}
    cos(ω_d t + ϕ) — exact wherever the output vibrates freely (ψ̈ = 0: a dwell); same unit as e."""
    omega_d = omega_n * math.sqrt(1.0 - zeta * zeta)
    return np.hypot(error, (rate + zeta * omega_n * error) / omega_d)


def _extreme(values: np.ndarray, theta: np.ndarray, kind: str) -> tuple[float, float]:
    """(min or max of periodic samples refined by a parabola, its cam angle [deg in 0…360))."""
    sign = 1.0 if kind == "min" else -1.0
    v, pos = parabolic_min(sign * np.asarray(values, float))
    deg = math.degrees(float(pos) * TWO_PI / theta.size) % 360.0
    return float(sign * v), 0.0 if abs(deg - 360.0) < 1e-9 else deg


def error_rate(result: Any) -> np.ndarray:
    """ė = φ̇ − ψ̇ [rad/s] at the samples: the output's velocity from its spectrum Φ_k = U_k + E_k
    (which falls as k⁻² faster than U_k: the train filters the cam's high harmonics) and the
    turret's exactly (ψ′ of the motion law) — not the error's spectral derivative, whose aliasing
    of the law's high harmonics (a cycloid's jerk jumps: U_k ~ k⁻⁴) costs 1e-5 of the amplitude at
    4096 samples."""
    per, inp = result.periodic, result.inp
    n = inp.n
    k = np.arange(inp.spectrum.size)
    dphi = np.fft.irfft(1j * k * (inp.spectrum + per.error_spectrum) * n, n)
    ramp = result.model.lift_scale * result.program.advance / TWO_PI
    return result.omega * (dphi + ramp - inp.du)


def turret_summary(result: Any) -> dict[str, Any]:
    """report.json's ``dynamics.turret``: the output train's numbers (angles in degrees and
    arc-minutes, torques in N·mm, times in seconds); ``result`` a
    :class:`cam_workbench.generators.dynamics.DynamicsResult` of an indexer's turret."""
    m = result.model
    prog = result.program
    theta = result.theta
    omega = result.omega
    c = m.lift_scale
    n = theta.size
    err = result.error                                  # φ − ψ [deg]
    rate = error_rate(result) / c                       # ė [deg/s]
    omega_n = m.natural_frequency
    f_n = omega_n / TWO_PI
    deflection = -err                                   # ψ − φ: the shaft's twist [deg]
    dmax, dmax_at = _extreme(np.abs(deflection), theta, "max")
    dpos, dpos_at = _extreme(deflection, theta, "max")
    dneg, dneg_at = _extreme(deflection, theta, "min")
    tq, tq_at = _extreme(np.abs(result.force), theta, "max")
    rq, rq_at = _extreme(np.abs(result.rigid_force), theta, "max")
    motion = np.array([law is not None for law in prog.laws])[result.inp.segment]
    amp = envelope(err, rate, omega_n, m.damping_ratio)
    dwells = []
    for first, last in _runs(~motion):
        idx = np.arange(first, last + 1) if last >= first else np.r_[np.arange(first, n), np.arange(0, last + 1)]
        j = idx[int(np.argmax(np.abs(err[idx])))]
        dwells.append({
            "from_deg": float(np.rad2deg(theta[first])), "to_deg": float(np.rad2deg(theta[last])),
            "time_s": float(idx.size * TWO_PI / n / omega),
            "amplitude_at_start": float(amp[first]), "amplitude_at_end": float(amp[last]),
            "amplitude_at_start_arcmin": float(amp[first] * ARCMIN_PER_DEG),
            "amplitude_at_end_arcmin": float(amp[last] * ARCMIN_PER_DEG),
            "max_error": float(abs(err[j])), "max_error_at_deg": float(np.rad2deg(theta[j])),
        })
    index_angle = float(sum(span for span, law in zip(prog.spans, prog.laws) if law is not None))
    t_i = index_angle / omega
    emax, emax_at = _extreme(np.abs(err), theta, "max")
    residual = max((d["amplitude_at_start"] for d in dwells), default=0.0)
    return {
        "model": "the output's inertia J on the turret shaft's torsional stiffness k_t, damper c = 2ζ√(J k_t); the "
                 "cam drives the turret through stiff rollers; steady state in the error φ − ψ (periodic: ψ advances "
                 "360°/N per turn); no friction",
        "output_inertia": m.spec_inertia, "inertia_unit": "kg·mm²",
        "torsional_stiffness": m.stiffness, "stiffness_unit": "N·mm/rad",
        "damping_ratio": m.damping_ratio,
        "natural_frequency_hz": f_n,
        "index_angle_deg": float(np.rad2deg(index_angle)),
        "index_time_s": t_i,
        "fn_ti": f_n * t_i,
        "fn_ti_note": "f_n·t_i, the output's natural frequency times the index time: the residual vibration at the "
                      "station falls as it grows",
        "angle_error": {"max": emax, "at_deg": emax_at, "max_arcmin": emax * ARCMIN_PER_DEG, "unit": "deg",
                        "meaning": "φ − ψ: the output's angle minus the turret's (the cam's)"},
        "deflection": {"max": dmax, "at_deg": dmax_at, "max_arcmin": dmax * ARCMIN_PER_DEG,
                       "max_positive": dpos, "max_positive_at_deg": dpos_at,
                       "max_negative": dneg, "max_negative_at_deg": dneg_at, "unit": "deg",
                       "meaning": "ψ − φ: the shaft's twist (positive: the turret leads the output)"},
        "shaft_torque": {"max": tq, "at_deg": tq_at, "rigid_max": rq, "rigid_max_at_deg": rq_at,
                         "dynamic_factor": tq / rq if rq > 0 else None, "unit": "N·mm",
                         "meaning": "k_t(ψ − φ) + c(ψ̇ − φ̇) = J φ̈; rigid: J ψ̈"},
        "residual_vibration": {"amplitude": residual, "amplitude_arcmin": residual * ARCMIN_PER_DEG, "unit": "deg",
                               "dwells": dwells,
                               "meaning": "the free vibration's amplitude √(e² + ((ė + ζω_n e)/ω_d)²) of e = φ − ψ "
                                          "in each dwell, when it starts and when it ends (the station's settling)"},
    }

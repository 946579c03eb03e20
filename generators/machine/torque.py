"""The camshaft's torque: each cam's, the machine's sum, and the flywheel that holds the speed.

Each cam's torque is the project's camshaft torque of the rigid follower train — the dynamics'
``rigid_torque``, computed by the same functions (``dynamics.model.rigid_train``, ``rigid_load``) (:func:`cam_workbench.generators.dynamics.analysis.analyse_dynamics`, report.json's
``dynamics.torque.rigid``): by virtual work with frictionless contact, T·ω = Q·u̇, so

    T(x) = Q(x)·u′(x),    Q = J·ω²·u″ + P + k_s·u,    u = lift_scale·s(x)

with x the cam's own angle, J the train's mass (or arm inertia) × the unit factor, P the preload
and k_s the return spring (docs/dynamics.md).  The rigid train needs no stiffness, so the machine
evaluates it for every cam — ``[dynamics]`` or not — at exactly the machine-grid angles
x = θ − phase (no interpolation).  Torques are in the spec's torque unit (N·mm or lbf·in).

The flywheel: with E(θ) = ∫₀^θ (T − T_mean) dθ, the energy fluctuation is ΔE = max E − min E and
the flywheel inertia I = ΔE / (C_s·ω²) [kg·m²] (ΔE in J) keeps (ω_max − ω_min)/ω_mean at C_s.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..dynamics.model import RigidTrain, rigid_load
from ..dynamics.model import rigid_train as dynamics_rigid_train
from ..kinds import body_of
from ..motion.program import MotionProgram, wrap_angle
from ..spec.model import CamSpec

TWO_PI = 2.0 * math.pi
#: joules per (torque unit × rad): N·mm → J, lbf·in → J
JOULES_PER_TORQUE_RAD = {"mm": 1.0e-3, "in": 0.1129848290276167}


def rigid_train(spec: CamSpec) -> RigidTrain:
    """The rigid train of ``spec``'s follower as the dynamics read it (the body's dynamics
    follower): :func:`cam_workbench.generators.dynamics.model.rigid_train`."""
    return dynamics_rigid_train(spec, body_of(spec).dynamics_follower(spec))


def cam_torque(spec: CamSpec, cam_angle: np.ndarray, omega: float,
               program: MotionProgram | None = None) -> np.ndarray:
    """The cam's camshaft torque T = Q·u′ [torque unit] at its own angles ``cam_angle`` [rad]
    (any, reduced mod 2π) at camshaft speed ``omega`` [rad/s]: the rigid torque of the dynamics
    (:func:`cam_workbench.generators.dynamics.model.rigid_load` times u′); ``program``: the
    follower's (default :meth:`MotionProgram.from_spec`, the follower's also with a linkage
    driven from the tool)."""
    train = rigid_train(spec)
    program = program or MotionProgram.from_spec(spec)
    kin = program.evaluate(wrap_angle(cam_angle))
    c = train.lift_scale
    u, du, d2u = c * np.asarray(kin.s, float), c * np.asarray(kin.ds, float), c * np.asarray(kin.d2s, float)
    return rigid_load(train, u, d2u, omega) * du


def machine_grid(samples: int) -> np.ndarray:
    """The machine angles θ_k = 2πk/N [rad], k = 0 … N−1 (one turn, the end left out)."""
    return TWO_PI * np.arange(samples) / samples


def cam_angles(theta: np.ndarray, phase_deg: float) -> np.ndarray:
    """A cam's own angle x = θ − phase [rad] (reduced to [0, 2π)) at machine angles ``theta``."""
    return wrap_angle(np.asarray(theta, float) - math.radians(phase_deg))


def energy_curve(theta: np.ndarray, torque: np.ndarray) -> np.ndarray:
    """E(θ) = ∫₀^θ (T − T_mean) dθ [torque unit × rad] on the periodic grid ``theta`` (equal steps
    over one turn, end left out), by the trapezoid rule; T_mean = ∮T dθ / 2π the same rule's."""
    t = np.asarray(torque, float)
    h = TWO_PI / t.size
    closed = np.append(t, t[0])
    steps = 0.5 * h * (closed[1:] + closed[:-1])
    mean = steps.sum() / TWO_PI
    return np.concatenate([[0.0], np.cumsum(steps - mean * h)[:-1]])


@dataclass(frozen=True)
class Flywheel:
    """The flywheel that keeps the camshaft's speed fluctuation at C_s.

    Attributes:
        energy: E(θ) over the grid [torque unit × rad].
        fluctuation: ΔE = max E − min E [J].
        at_max_deg, at_min_deg: machine angles of E's maximum and minimum.
        coefficient: C_s.
        omega: camshaft speed [rad/s].
        inertia: I = ΔE / (C_s·ω²) [kg·m²].
    """

    energy: np.ndarray
    fluctuation: float
    at_max_deg: float
    at_min_deg: float
    coefficient: float
    omega: float
    inertia: float

    def summary(self) -> dict[str, Any]:
        """machine.json's ``flywheel`` section."""
        return {"energy_fluctuation_J": self.fluctuation, "energy_max_at_deg": self.at_max_deg,
                "energy_min_at_deg": self.at_min_deg, "speed_fluctuation": self.coefficient,
                "omega_rad_s": self.omega, "inertia_kg_m2": self.inertia}


def flywheel(theta: np.ndarray, torque: np.ndarray, omega: float, coefficient: float, units: str = "mm") -> Flywheel:
    """The flywheel for the camshaft torque ``torque`` [torque unit of ``units``] sampled on the
    periodic grid ``theta`` [rad] at speed ``omega`` [rad/s] and speed fluctuation ``coefficient``."""
    e = energy_curve(theta, torque)
    j_max, j_min = int(np.argmax(e)), int(np.argmin(e))
    delta = float(e[j_max] - e[j_min]) * JOULES_PER_TORQUE_RAD[units]
    return Flywheel(e, delta, float(np.degrees(theta[j_max])), float(np.degrees(theta[j_min])), coefficient, omega,
                    delta / (coefficient * omega**2))


def torque_summary(theta: np.ndarray, torque: np.ndarray) -> dict[str, float]:
    """max, min (with their machine angles [deg]), the largest |T|, the mean (work per turn / 2π)
    and the RMS of a torque on the periodic grid ``theta`` [rad]."""
    t = np.asarray(torque, float)
    j_max, j_min = int(np.argmax(t)), int(np.argmin(t))
    return {"max": float(t[j_max]), "max_at_deg": float(np.degrees(theta[j_max])),
            "min": float(t[j_min]), "min_at_deg": float(np.degrees(theta[j_min])),
            "peak": float(np.max(np.abs(t))), "mean": float(np.mean(t)),
            "rms": float(np.sqrt(np.mean(t * t))), "work_per_turn": float(np.mean(t) * TWO_PI)}


__all__ = ["Flywheel", "JOULES_PER_TORQUE_RAD", "RigidTrain", "cam_angles", "cam_torque", "energy_curve",
           "flywheel", "machine_grid", "rigid_train", "torque_summary"]

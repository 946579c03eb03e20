"""The follower train as one degree of freedom: its numbers, read from the spec through the
follower interface, and the spec's rules for them.

The coordinate q is the follower's own: the lift along the line of motion for a translating
follower (spec length), the arm's rotation in **radians** for an oscillating one
(``Follower.lift_scale`` turns the spec's lift into q).  The cam drives the contact end of the train
along u(θ) = lift_scale·s(θ); the lumped mass (or inertia) sits at q::

        cam ── u ──[ k_f ‖ c ]── q: J ── return spring k_s, preload P ── frame

    J q̈ = Q − P − k_s q,       Q = k_f (u − q) + c (u̇ − q̇)       while Q > 0 (contact),
    J q̈ =   − P − k_s q,       Q = 0                               while the follower is off the cam.

Q is the generalised contact load (a force along the line of motion, a torque about the pivot);
the normal contact force is Q times :meth:`Follower.force_per_load` (1/cos φ, 1/(L·cos φ), …), and
the camshaft torque is T = Q·u′ (virtual work: T·ω = Q·u̇, no friction).  With k_f → ∞ the
model is the rigid follower of the design checks: Q → J ü + P + k_s u (thesis Eq. 3.5).

J = mass × ``LoadSpec.mass_force`` (kg·mm/s² = 10⁻³ N), so forces come out in the spec's force
unit and torques in its torque unit; c = 2ζ·√(J·(k_f + k_s)).

An indexer's output train (:mod:`.turret`) is this train with k_s = P = 0: u the turret angle, k_f
the turret shaft's ``dynamics.torsional_stiffness``, J ``indexer.output_inertia`` (the
:class:`~cam_workbench.generators.bodies.indexing.turret_train.TurretFollower`'s ``load.inertia``), Q the shaft torque.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..followers.base import Follower
from ..kinds import follower_of
from ..spec.model import CamSpec
from ..spec.train import TRAIN_FIELDS, validate_dynamics


@dataclass(frozen=True)
class TrainModel:
    """The single-degree-of-freedom follower train in the follower's coordinate q.

    Attributes:
        inertia: J [force·s² per unit of q] (mass or moment of inertia × mass_force).
        stiffness: k_f, the train between the cam contact and the mass [force per unit of q].
        spring_rate: k_s, the return spring [force per unit of q].
        preload: P, the return spring's load at q = 0 [force].
        damping_ratio: ζ; the damper c = 2ζ√(J(k_f + k_s)) sits beside k_f.
        lift_scale: spec lift unit → q (1 for lengths, π/180 for arm degrees).
        coordinate: "length" or "angle".
        mass_force: the factor that turned the spec's mass into J (to report it back).
    """

    inertia: float
    stiffness: float
    spring_rate: float
    preload: float
    damping_ratio: float
    lift_scale: float = 1.0
    coordinate: str = "length"
    mass_force: float = 1.0

    @property
    def total_stiffness(self) -> float:
        """K = k_f + k_s: the stiffness the mass sees while the follower is on the cam."""
        return self.stiffness + self.spring_rate

    @property
    def natural_frequency(self) -> float:
        """ω_n = √(K/J) [rad/s] of the train on the cam."""
        return math.sqrt(self.total_stiffness / self.inertia)

    @property
    def damping(self) -> float:
        """c = 2ζ√(J K) [force·s per unit of q]."""
        return 2.0 * self.damping_ratio * math.sqrt(self.inertia * self.total_stiffness)

    @property
    def flight_frequency(self) -> float:
        """Ω = √(k_s/J) [rad/s]: the mass on its return spring alone, off the cam."""
        return math.sqrt(self.spring_rate / self.inertia)

    @property
    def spec_inertia(self) -> float:
        """J in the spec's mass (or inertia) unit."""
        return self.inertia / self.mass_force


@dataclass(frozen=True)
class RigidTrain:
    """The rigid follower train (k_f → ∞) in the follower's coordinate u = lift_scale·s.

    Attributes:
        inertia: J [force·s² per unit of u] (mass or arm inertia × mass_force).
        preload: P [force, or torque for an arm].
        spring_rate: k_s [force (torque) per unit of u].
        lift_scale: spec lift unit → u (1 for lengths, π/180 for arm degrees).
    """

    inertia: float
    preload: float
    spring_rate: float
    lift_scale: float


def rigid_train(spec: CamSpec, follower: Follower | None = None) -> RigidTrain:
    """The rigid train of ``spec``'s follower (``follower``: the body's dynamics follower, default
    the spec's): J is ``dynamics.mass`` (``dynamics.arm_inertia``) or else the follower's, an
    indexer turret's its output inertia, × the load's unit factor; P and k_s the follower's load.
    Needs no stiffness: valid with or without a ``[dynamics]`` table."""
    fol = follower or follower_of(spec)
    ld = fol.load
    inertia_field, _stiffness, follower_field = TRAIN_FIELDS[fol.lift_unit]
    # an indexer's turret (:mod:`.turret`): the output's inertia, indexer.output_inertia
    inertia = ld.inertia if fol.turret else (getattr(spec.dynamics, inertia_field)
                                             or getattr(spec.follower, follower_field))
    return RigidTrain(inertia * ld.mass_force, ld.preload, ld.rate, fol.lift_scale)


def rigid_load(train: Any, u: Any, d2u: Any, omega: float) -> np.ndarray:
    """The rigid train's generalised contact load Q = J·ü + P + k_s·u = J·u″·ω² + P + k_s·u
    [force, or torque for an arm] at the cam input u (units of the follower coordinate) and its
    second derivative per rad² u″, at camshaft speed ``omega`` [rad/s]; ``train``: a
    :class:`RigidTrain` or :class:`TrainModel` (anything with ``inertia``, ``preload``,
    ``spring_rate``).  The camshaft torque is Q·u′ (virtual work), the normal force Q·lever."""
    return train.inertia * d2u * omega**2 + train.preload + train.spring_rate * u


def train_model(spec: CamSpec, follower: Follower | None = None) -> TrainModel:
    """The follower train of ``spec``: the follower's load (preload, return spring, its unit
    factor) and ``[dynamics]``'s inertia, stiffness and damping.

    Raises:
        SpecError: the dynamics lack their data (naming the field).
    """
    validate_dynamics(spec, required=True)
    fol = follower or follower_of(spec)
    _inertia, stiffness_field, _follower = TRAIN_FIELDS[fol.lift_unit]
    dy = spec.dynamics
    ld = fol.load
    rigid = rigid_train(spec, fol)
    return TrainModel(inertia=rigid.inertia, stiffness=float(getattr(dy, stiffness_field)),
                      spring_rate=ld.rate, preload=ld.preload, damping_ratio=dy.damping_ratio,
                      lift_scale=fol.lift_scale, coordinate=fol.lift_unit, mass_force=ld.mass_force)


def analysis_rpm(spec: CamSpec) -> float:
    """The cam speed of the analysis [rpm]: ``dynamics.speed_rpm`` or ``cam.speed_rpm``."""
    return spec.dynamics.speed_rpm if spec.dynamics.speed_rpm is not None else spec.cam.speed_rpm

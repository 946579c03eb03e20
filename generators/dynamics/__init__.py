"""Follower-train dynamics: a single-degree-of-freedom spring–mass–damper driven by
the cam, for every follower kind through the follower interface.

* :mod:`.model` — the train's numbers from the spec (mass or arm inertia, stiffness, damping,
  return spring and preload) and the rules of ``[dynamics]``;
* :mod:`.periodic` — the steady state on the cam as a periodic (harmonic) solve, vectorised over
  the samples and over speeds;
* :mod:`.contact` — the exact piecewise solution when the follower leaves the cam;
* :mod:`.jump` — the jump-speed sweep and bisection, the rigid follower's jump speed;
* :mod:`.analysis` — :func:`analyse_dynamics`: everything at one speed, report.json's section;
* :mod:`.turret` — an indexer's output train (the output's inertia on the turret shaft), the same
  model in the periodic error of an advancing turret, and report.json's ``dynamics.turret``.
"""
from .analysis import DynamicsResult, analyse_dynamics
from .jump import JumpSpeed, find_jump_speed, rigid_jump_speed
from .model import RigidTrain, TrainModel, rigid_load, rigid_train, train_model, validate_dynamics
from .periodic import CamInput, PeriodicResponse, cam_input, min_force_vs_speed, periodic_response

__all__ = ["CamInput", "DynamicsResult", "JumpSpeed", "PeriodicResponse", "RigidTrain", "TrainModel",
           "analyse_dynamics", "cam_input", "find_jump_speed", "min_force_vs_speed", "periodic_response",
           "rigid_jump_speed", "rigid_load", "rigid_train", "train_model", "validate_dynamics"]

"""An indexer's turret as the follower dynamics see it (``Body.dynamics_follower`` of the three
indexers): the output train — the output's inertia ``indexer.output_inertia`` on the turret
shaft's ``dynamics.torsional_stiffness`` — in the turret's angle.  The model and report.json's
``dynamics.turret`` are :mod:`cam_workbench.generators.dynamics.turret`'s (docs/indexing.md,
"Dynamics")."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...followers.base import LoadSpec
from ...followers.load import MASS_FORCE_FACTOR

DEG = math.pi / 180.0


@dataclass(frozen=True)
class TurretFollower:
    """An indexer's turret as the dynamics see it: the coordinate is the turret angle (spec lift in
    degrees, q in radians), ``load.inertia`` the output's inertia J [kg·mm²] (no return spring, no
    preload), and the generalised load — the shaft torque — is its own "contact force" (lever 1)."""

    stations: int
    load: LoadSpec
    lift_scale: float = DEG
    lift_unit: str = "angle"
    motion: str = "turret"
    kind: str = "roller"
    pivoted: bool = False
    #: the train is the turret shaft: :func:`cam_workbench.generators.dynamics.model.train_model` reads J from ``load``
    turret: bool = True

    def force_per_load(self, k: Any) -> np.ndarray:
        """1 at every sample: the load Q is the shaft torque itself."""
        return np.ones(np.shape(k.s))

    def label(self) -> str:
        return (f"turret of {self.stations} stations: the output (J = {self.load.inertia:g} kg·mm²) on the turret "
                "shaft's torsional stiffness")

    def describe(self) -> dict[str, Any]:
        return {"kind": self.kind, "motion": self.motion, "lift_unit": self.lift_unit, "label": self.label()}


def turret_follower(spec: Any) -> TurretFollower:
    """The turret of an indexer's spec (the inertia 0 when ``indexer.output_inertia`` is absent:
    :func:`cam_workbench.generators.spec.train.validate_dynamics` names it when the dynamics run)."""
    load = LoadSpec(inertia=float(spec.indexer.output_inertia or 0.0), mass_force=MASS_FORCE_FACTOR[spec.units])
    return TurretFollower(int(spec.indexer.stations), load)

"""A parallel indexer's drive sized from its built geometry (and the torque its load asks, :func:`output_torque`): :func:`.sizing.drive_sizing` over the
index with the moment arms and cam radii of the contacts that carry the load (the driving one while
the output accelerates, the holding-back one while it decelerates: :class:`.parallel.ParallelDesign`),
the geometry's millimetres turned into the sizing's metres."""
from __future__ import annotations

import math

import numpy as np

from ...motion.laws import evaluate_law
from .parallel import ParallelDesign, ParallelIndexer
from .sizing import DriveSizing, IndexLoad, drive_sizing

MM = 1e-3
Array = np.ndarray


def parallel_drive(design: ParallelDesign, *, input_speed: float, inertia: float, roller_width: float,
                   roller_rating: float, friction_torque: float = 0.0, **more: float) -> DriveSizing:
    """The drive of ``design`` at ``input_speed`` [rev/min] turning an output of ``inertia``
    [kg·m²] against ``friction_torque`` [N·m], the rollers ``roller_width`` [mm] wide on bearings
    of dynamic rating ``roller_rating`` [N]; ``more``: the other fields of :class:`.sizing.IndexLoad`
    (moduli, Poisson ratios, ``life_exponent``, ``efficiency``).  Over the design's input angles in
    the index."""
    ix = design.indexer
    load = IndexLoad(stations=int(ix.stations), index_angle=float(ix.index_angle), input_speed=input_speed,
                     inertia=inertia, friction_torque=friction_torque, law=ix.law,
                     pitch_radius=float(ix.pitch_radius) * MM, roller_radius=float(ix.roller_radius) * MM,
                     roller_width=roller_width * MM, roller_rating=roller_rating, **more)
    theta = design.theta - float(ix.index_start)
    over = theta <= float(ix.index_angle) * (1 + 1e-12)
    return drive_sizing(load, theta=np.minimum(theta[over], float(ix.index_angle)),
                        arm=design.driving_arm[over] * MM, cam_radius=design.driving_radius[over] * MM,
                        arm_back=design.holding_arm[over] * MM, cam_radius_back=design.holding_radius[over] * MM)


def output_torque(ix: ParallelIndexer, theta: Array, load: dict[str, float] | None) -> Array:
    """T_out [N·m] the cam applies to the output at input angles ``theta`` [rad]:
    J·ψ''·ω_in² + T_f·sign ψ' (:mod:`.sizing`'s), 0 in the dwell; without a load ψ'' alone."""
    beta = float(ix.index_angle)
    rel = np.asarray(theta, dtype=float) - float(ix.index_start)
    inside = (rel >= 0) & (rel <= beta)
    _, f1, f2, _ = evaluate_law(ix.law, np.clip(rel / beta, 0.0, 1.0))
    h = ix.station_angle
    if load is None:
        return np.where(inside, h * f2 / beta**2, 0.0)
    w = 2.0 * math.pi * float(load["input_speed"]) / 60.0
    t = float(load["inertia"]) * h * f2 / beta**2 * w**2 + float(load.get("friction_torque", 0.0)) * np.sign(f1)
    return np.where(inside, t, 0.0)

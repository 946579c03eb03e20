"""The spec's `[dynamics]` table: :class:`DynamicsSection` (the follower train at speed); its rules are
:mod:`cam_workbench.generators.spec.train`'s.
"""
from __future__ import annotations

from dataclasses import dataclass

from .params import param


#: Where the jump-speed sweep starts by default: this fraction of its top speed.
SWEEP_LOW_FRACTION = 0.05


@dataclass(frozen=True, kw_only=True)
class DynamicsSection:
    """`[dynamics]`: the follower train as a spring–mass–damper at speed — dynamic contact force, separation, the jump speed, residual vibration and the camshaft torque (docs/dynamics.md)."""

    enabled: bool = param(
        "Analyse the dynamics in build, report, check and Cam.report() (report.json's dynamics section, the "
        "report's figures); `cam-workbench dynamics` analyses them whatever this says",
        kind="bool", default=False, group="Dynamics")
    speed_rpm: float | None = param("Cam speed of the analysis (default cam.speed_rpm)", unit="speed", gt=0,
                                    optional=True, group="Dynamics")
    mass: float | None = param(
        "Translating: effective mass of the follower train (default follower.mass); count about a third of the "
        "return spring's own mass", unit="mass", gt=0, optional=True, group="Dynamics")
    arm_inertia: float | None = param(
        "Oscillating: effective moment of inertia of the arm train about the pivot (default follower.arm_inertia)",
        unit="inertia", gt=0, optional=True, group="Dynamics")
    stiffness: float | None = param(
        "Translating: stiffness k_f of the follower train between the cam contact and the lumped mass (roller, "
        "pin, stem, rocker); required for the dynamics of a translating follower",
        unit="stiffness", gt=0, optional=True, group="Dynamics")
    torsional_stiffness: float | None = param(
        "Oscillating: torsional stiffness of the arm train about the pivot between the cam contact and the lumped "
        "inertia; required for the dynamics of an oscillating follower. Indexer: the turret shaft's torsional "
        "stiffness between the cam-driven turret and the output's inertia (indexer.output_inertia); required for "
        "its dynamics",
        unit="torsional_stiffness", gt=0, optional=True, group="Dynamics")
    damping_ratio: float = param(
        "Damping ratio ζ of the follower train: a damper c = 2ζ·√(m·(k_f + k)) beside the train's spring",
        ge=0, lt=1, default=0.05, group="Dynamics")
    revolutions: int = param(
        "Most cam revolutions of the time integration when the follower leaves the cam (it stops as soon as one "
        "revolution repeats the one before)", kind="int", ge=1, le=1000, default=40, group="Dynamics")
    samples: int | None = param(
        "Samples per cam revolution of the periodic solve (default: 16 per natural period, at least 4096)",
        kind="int", ge=256, le=1048576, optional=True, group="Dynamics")
    sweep_min_rpm: float | None = param(
        f"Lowest cam speed of the jump-speed sweep (default {SWEEP_LOW_FRACTION:g} × sweep_max_rpm)",
        unit="speed", gt=0, optional=True, group="Dynamics")
    sweep_max_rpm: float | None = param(
        "Highest cam speed of the jump-speed sweep (default twice the rigid follower's jump speed, at least "
        "twice the analysis speed)", unit="speed", gt=0, optional=True, group="Dynamics")
    sweep_points: int = param("Cam speeds of the jump-speed sweep (0: no sweep)", kind="int", ge=0, le=10000,
                              default=100, group="Dynamics")

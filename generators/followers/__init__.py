"""Follower kinds: each one module behind the interface of :mod:`.base` —
:mod:`.translating` (knife edge, roller), :mod:`.oscillating` (knife edge, roller on an arm) and
:mod:`.flat` (flat faces, translating and oscillating); :mod:`.conjugate` the second roller of a
conjugate pair.  Each kind registers its class with the kinds registry
(:mod:`cam_workbench.generators.kinds`), the one place that maps a spec's ``follower.motion`` and
``follower.kind`` to its class; everything above reads the interface.
"""
from __future__ import annotations

import math

from ..kinds import follower_class, follower_of
from .base import Follower, LoadSpec, ToolMount
from .conjugate import ArmPairRoller, SecondRoller, YokeRoller, second_roller_of
from .flat import OscillatingFlatFollower, TranslatingFlatFollower
from .oscillating import OscillatingFollower
from .translating import FollowerGeometry, TranslatingFollower


def force_reference(spec) -> float:
    """The force that normalises the separation constraint: the preload's contact force (P_L;
    an oscillating arm's T_L over its lever: the arm length, or the pivot distance for a flat face),
    else the spring's or the inertia's over the largest lift."""
    fol = follower_of(spec)
    ld = fol.load
    omega = spec.cam.speed_rpm * 2.0 * math.pi / 60.0
    lever = fol.load_lever
    scale = fol.lift_scale
    if ld.preload > 0:
        return ld.preload / lever
    lifts = spec.max_lift * scale
    other = max(ld.rate * lifts, ld.inertia * ld.mass_force * omega**2 * lifts)
    return max(other / lever, 1e-12)


__all__ = ["ArmPairRoller", "Follower", "FollowerGeometry", "LoadSpec", "OscillatingFlatFollower", "OscillatingFollower",
           "SecondRoller", "ToolMount", "TranslatingFlatFollower", "TranslatingFollower", "YokeRoller", "follower_class", "follower_of",
           "force_reference", "second_roller_of"]

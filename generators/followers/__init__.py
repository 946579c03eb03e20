"""Follower kinds: each one module behind the interface of :mod:`.base` —
:mod:`.translating` (knife edge, roller), :mod:`.oscillating` (knife edge, roller on an arm) and
:mod:`.flat` (flat faces, translating and oscillating).  :func:`follower_of` is the one place that
maps a spec's ``follower.motion`` and ``follower.kind`` to its class; everything above reads the
interface.
"""
from __future__ import annotations

import math
from typing import Callable

from .base import Follower, LoadSpec
from .conjugate import ArmPairRoller, SecondRoller, YokeRoller, second_roller_of
from .flat import OscillatingFlatFollower, TranslatingFlatFollower
from .oscillating import OscillatingFollower
from .translating import FollowerGeometry, TranslatingFollower

#: (follower.motion, follower.kind) → the class that builds it from a spec
KINDS: dict[tuple[str, str], Callable] = {
    ("translating", "knife"): TranslatingFollower.from_spec,
    ("translating", "roller"): TranslatingFollower.from_spec,
    ("translating", "flat"): TranslatingFlatFollower.from_spec,
    ("oscillating", "knife"): OscillatingFollower.from_spec,
    ("oscillating", "roller"): OscillatingFollower.from_spec,
    ("oscillating", "flat"): OscillatingFlatFollower.from_spec,
}


def follower_of(spec) -> Follower:
    """The follower of a validated spec."""
    return KINDS[(spec.follower.motion, spec.follower.kind)](spec)


def force_reference(spec) -> float:
    """The force that normalises the separation constraint: the preload's contact force (P_L;
    an oscillating arm's T_L over its lever: the arm length, or the pivot distance for a flat face),
    else the spring's or the inertia's over the largest lift."""
    fol = follower_of(spec)
    ld = fol.load
    omega = spec.cam.speed_rpm * 2.0 * math.pi / 60.0
    lever = 1.0
    scale = fol.lift_scale
    if fol.motion == "oscillating":
        f = spec.follower
        lever = f.arm_length if f.arm_length and fol.contact != "flat" else f.pivot_distance
    if ld.preload > 0:
        return ld.preload / lever
    lifts = spec.max_lift * scale
    other = max(ld.rate * lifts, ld.inertia * ld.mass_force * omega**2 * lifts)
    return max(other / lever, 1e-12)
def follower_class(motion: str, kind: str) -> type[Follower]:
    """The class of a follower kind, for what it says before there is a spec (its class
    attributes: ``lift_unit``, ``design_curve``, ``lift_scale``) — e.g. the unit in which the
    FreeCAD properties store the lifts while a user edits them."""
    return KINDS[(motion, kind)].__self__  # type: ignore[attr-defined]


def validate_follower(spec) -> None:
    """The geometric rules of the spec's follower kind (called by the spec's validation, after
    the motion program's): an oscillating arm must reach the prime circle and must not turn
    onto the line through the pivot and the cam axis within the lift.

    Raises:
        SpecError: naming the field and the rule.
    """
    from ..errors import SpecError, fmt_apart

    fol = spec.follower
    if fol.motion != "oscillating" or spec.cam.body == "cylindrical":    # the cylinder's arm: its body's rules
        return
    d, rb = fol.pivot_distance, spec.cam.base_radius
    if fol.kind == "flat":
        f = fol.face_offset or 0.0
        if not abs(rb + f) < d:
            raise SpecError("follower.pivot_distance",
                            f"the face at face_offset {f:g} from the pivot cannot touch the base circle: needs "
                            f"|cam.base_radius + face_offset| = {fmt_apart(abs(rb + f), d)} < pivot_distance, got "
                            f"{fmt_apart(d, abs(rb + f))}")
        extent = OscillatingFlatFollower.from_spec(spec).lift_extent()
        what = "face"
    else:
        L = fol.arm_length
        if not abs(d - L) < rb < d + L:
            raise SpecError("follower.arm_length",
                            f"the arm cannot reach the prime circle: needs |pivot_distance − arm_length| < "
                            f"cam.base_radius < pivot_distance + arm_length (|d − L| = {fmt_apart(abs(d - L), rb)}, "
                            f"d + L = {fmt_apart(d + L, rb)}, R_b = {fmt_apart(rb, abs(d - L) if rb <= abs(d - L) else d + L)})")
        extent = OscillatingFollower.from_spec(spec).lift_extent()
        what = "arm"
    level, top, at = 0.0, 0.0, 0
    for i, seg in enumerate(spec.motion):
        level += (seg.lift or 0.0) * (1 if seg.kind == "rise" else -1 if seg.kind == "return" else 0)
        if level > top:
            top, at = level, i
    if not top < extent:
        raise SpecError(f"motion[{at}].lift",
                        f"the {what} would turn {fmt_apart(top, extent)}° and reach the line through the pivot and the "
                        f"cam axis at {fmt_apart(extent, top, 4)}°: the lift must stay below it (a smaller lift, or move "
                        "the pivot)")


__all__ = ["ArmPairRoller", "Follower", "FollowerGeometry", "KINDS", "LoadSpec", "OscillatingFlatFollower", "OscillatingFollower",
           "SecondRoller", "TranslatingFlatFollower", "TranslatingFollower", "YokeRoller", "follower_class", "follower_of",
           "force_reference", "second_roller_of"]

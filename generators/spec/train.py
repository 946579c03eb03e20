"""The rules of ``[dynamics]``: the follower train's fields for the follower's coordinate (a
length or an arm's angle, ``Follower.lift_unit``) and, when the dynamics run, its data.  The
body decides whether its dynamics can drive the spec's follower (``Body.dynamics_follower``); an
indexer's body (``Body.dynamics_train = "turret"``) drives its output train instead: the output's
inertia on the turret shaft's torsional stiffness (:func:`_validate_turret`)."""
from __future__ import annotations

from typing import Any

from ..errors import SpecError, fmt_apart
from ..kinds import body_of, follower_class_of

#: the [dynamics] fields of each coordinate kind: (inertia, stiffness), and the follower field
#: the inertia defaults to
TRAIN_FIELDS = {"length": ("mass", "stiffness", "mass"),
                "angle": ("arm_inertia", "torsional_stiffness", "arm_inertia")}


def validate_dynamics(spec: Any, required: bool = False) -> None:
    """The rules of ``[dynamics]``: fields of the other follower motion are refused, the sweep's
    range must be a range, and — when ``dynamics.enabled`` or ``required`` (``cam-workbench
    dynamics``) — the train must have its stiffness and a mass.

    Raises:
        SpecError: naming the field and the rule.
    """
    dy = spec.dynamics
    body = body_of(spec)
    if dy.enabled or required:
        # first: the body's refusal of a follower its dynamics cannot drive (naming the option);
        # no field of [dynamics] would make that work
        body.dynamics_follower(spec)
    if body.dynamics_train == "turret":
        _validate_turret(spec, dy.enabled or required)
        return
    coordinate = follower_class_of(spec).lift_unit
    mine = TRAIN_FIELDS[coordinate]
    other = TRAIN_FIELDS["length" if coordinate == "angle" else "angle"]
    motion = spec.follower.motion
    article = "an" if motion[:1] in "aeiou" else "a"
    for name in other[:2]:
        if getattr(dy, name) is not None:
            raise SpecError(f"dynamics.{name}", f"does not apply to {article} {motion} "
                            f"follower: give dynamics.{mine[other.index(name)]}")
    lo, hi = dy.sweep_min_rpm, dy.sweep_max_rpm
    if lo is not None and hi is not None and not lo < hi:
        raise SpecError("dynamics.sweep_max_rpm", f"must be > dynamics.sweep_min_rpm ({fmt_apart(lo, hi)}), got "
                        f"{fmt_apart(hi, lo)}")
    if not (dy.enabled or required):
        return
    inertia_field, stiffness_field, follower_field = mine
    if getattr(dy, stiffness_field) is None:
        raise SpecError(f"dynamics.{stiffness_field}",
                        f"is required for the dynamics of {article} {motion} follower (the follower train's stiffness "
                        "between the cam contact and the lumped mass)")
    if not (getattr(dy, inertia_field) or getattr(spec.follower, follower_field)):
        raise SpecError(f"dynamics.{inertia_field}",
                        f"the follower train needs a {inertia_field.replace('_', ' ')} > 0 for the dynamics: give "
                        f"dynamics.{inertia_field} or follower.{follower_field}")


#: an indexer's output train (generators/dynamics/turret.py): the [dynamics] fields that do not apply
TURRET_FOREIGN = ("mass", "stiffness", "arm_inertia")


def _validate_turret(spec: Any, running: bool) -> None:
    """The rules of ``[dynamics]`` for an indexer's output train (the output's inertia
    ``indexer.output_inertia`` on the turret shaft's ``dynamics.torsional_stiffness``)."""
    dy = spec.dynamics
    for name in TURRET_FOREIGN:
        if getattr(dy, name) is not None:
            raise SpecError(f"dynamics.{name}", "does not apply to an indexer: its output train is the output's "
                            "inertia (indexer.output_inertia) on the turret shaft's torsional stiffness "
                            "(dynamics.torsional_stiffness)")
    lo, hi = dy.sweep_min_rpm, dy.sweep_max_rpm
    if lo is not None and hi is not None and not lo < hi:
        raise SpecError("dynamics.sweep_max_rpm", f"must be > dynamics.sweep_min_rpm ({fmt_apart(lo, hi)}), got "
                        f"{fmt_apart(hi, lo)}")
    if not running:
        return
    if dy.torsional_stiffness is None:
        raise SpecError("dynamics.torsional_stiffness", "is required for the dynamics of an indexer (the turret "
                        "shaft's torsional stiffness between the cam-driven turret and the output's inertia)")
    if not spec.indexer.output_inertia:
        raise SpecError("indexer.output_inertia", "the output train needs an inertia > 0 for the dynamics (the "
                        "turret and its load about the turret axis)")

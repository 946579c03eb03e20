"""The spec's `[follower]` table: :class:`FollowerSection` and the rules of the follower's motion
(the fields only a translating or only an oscillating follower may have, the flat face's width).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import SpecError
from .params import param

if TYPE_CHECKING:  # types only: the spec's root imports this module
    from .model import CamSpec


@dataclass(frozen=True, kw_only=True)
class FollowerSection:
    """`[follower]`: a translating follower whose line of motion is parallel to +Y at x = offset."""

    kind: str = param("Follower contact: a roller, a knife edge or a flat face", kind="str",
                      choices=("roller", "knife", "flat"), group="Follower")
    motion: str = param(
        "How the follower moves: along a straight line (translating) or turning about a pivot on an arm "
        "(oscillating; motion[].lift is then the arm's rotation in degrees)", kind="str",
        choices=("translating", "oscillating"), default="translating", group="Follower")
    offset: float = param("Follower offset e (signed, translating followers): its line of motion is x = e",
                          unit="length", default=0.0, group="Follower")
    roller_radius: float = param("Roller radius (roller followers; ignored for a knife edge)",
                                 unit="length", ge=0, default=0.0, group="Follower")
    roller_width: float | None = param(
        "Roller width in contact with the cam; the Hertz contact length is the smaller of this "
        "and cam.thickness (default: cam.thickness)",
        unit="length", gt=0, optional=True, group="Follower")
    mass: float = param(
        "Mass M_f of the follower train moving with the follower (thesis Eq. 3.5; the thesis' "
        "\"0.02 slugs\" is 0.02 lbf·s²/in)", unit="mass", ge=0, default=0.0, group="Follower load")
    preload: float = param(
        "Force P_L pressing the follower onto the cam at zero lift (spring preload, load, "
        "friction: thesis Eq. 3.5)", unit="force", ge=0, default=0.0, group="Follower load")
    spring_rate: float = param(
        "Return-spring rate k: the load is P_L + k·s at lift s (0: constant load, as the thesis)",
        unit="stiffness", ge=0, default=0.0, group="Follower load")
    # ---- oscillating followers (CAM_SPEC.md "Follower motion and kinds") ----
    pivot_distance: float | None = param(
        "Oscillating: distance d from the cam axis to the arm's pivot, which sits at (d, 0) in the fixed frame; "
        "cylindrical cam: the radial pivot's distance along the circumference (developed at the pitch radius) "
        "from the +Y generator, where the roller centre is at mid-lift (pivot upstream of the roller)",
        unit="length", gt=0, optional=True, group="Follower arm")
    arm_length: float | None = param(
        "Oscillating: arm length L from the pivot to the roller centre / knife tip; for a flat face the "
        "position of the face's centre along it (default: the middle of the contact's travel); cylindrical "
        "cam: ≥ pivot_distance, the arm's arc in the developed pitch plane",
        unit="length", gt=0, optional=True, group="Follower arm")
    face_offset: float | None = param(
        "Oscillating flat face: distance from the pivot to the face line, positive with the face between "
        "the pivot and the cam (default 0: the face passes through the pivot)",
        unit="length", optional=True, group="Follower arm")
    face_width: float | None = param(
        "Flat face: its width, centred on the stem (translating) or on arm_length (oscillating); "
        "checked against the width the contact needs (absent: the width needed is reported, the face_width "
        "check skipped)", unit="length", gt=0, optional=True, group="Follower")
    arm_inertia: float = param(
        "Oscillating: moment of inertia I of the arm and everything turning with it about the pivot",
        unit="inertia", ge=0, default=0.0, group="Follower load")
    preload_torque: float = param(
        "Oscillating: torque T_L pressing the arm onto the cam at zero lift (spring preload)",
        unit="torque", ge=0, default=0.0, group="Follower load")
    spring_torque_rate: float = param(
        "Oscillating: return-spring torque rate k_t: the torque is T_L + k_t·s at arm rotation s [rad]",
        unit="torsional_stiffness", ge=0, default=0.0, group="Follower load")


#: fields that only one follower motion may have (a typo or a leftover must not be ignored)
TRANSLATING_ONLY = {"mass": "arm_inertia", "preload": "preload_torque", "spring_rate": "spring_torque_rate"}
OSCILLATING_ONLY = ("pivot_distance", "arm_length", "face_offset", "arm_inertia", "preload_torque",
                    "spring_torque_rate")


def validate_follower_motion(spec: CamSpec) -> None:
    fol = spec.follower
    if fol.motion == "translating":
        for name in OSCILLATING_ONLY:
            v = getattr(fol, name)
            if v is not None and v != 0:
                raise SpecError(f"follower.{name}", 'applies to oscillating followers only (follower.motion = '
                                '"oscillating")')
        return
    if fol.offset != 0:
        raise SpecError("follower.offset", "applies to translating followers only: an oscillating follower's "
                        "position is follower.pivot_distance and follower.arm_length")
    for name, instead in TRANSLATING_ONLY.items():
        if getattr(fol, name) != 0:
            raise SpecError(f"follower.{name}", f"applies to translating followers only: for an oscillating "
                            f"arm give follower.{instead}")
    if fol.pivot_distance is None:
        raise SpecError("follower.pivot_distance", "is required for an oscillating follower")
    if fol.kind != "flat" and fol.arm_length is None:
        raise SpecError("follower.arm_length", f"is required for an oscillating {fol.kind} follower")
    if fol.kind != "flat" and fol.face_offset is not None:
        raise SpecError("follower.face_offset", "applies to flat-faced followers only")


def validate_face(spec: CamSpec) -> None:
    if spec.follower.kind != "flat" and spec.follower.face_width is not None:
        raise SpecError("follower.face_width", "applies to flat-faced followers only")

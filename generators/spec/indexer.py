"""The spec's `[indexer]` table: :class:`IndexerSection` (the turret of an indexing cam: a parallel,
``cam.body`` = "parallel_indexer", "barrel_indexer" or "globoidal_indexer"),
and :func:`indexer_size`, the cam size ``cam.base_radius`` stands for on an indexer.

How an indexer's spec reads the other tables (docs/indexing.md, "The spec"):

* ``[[motion]]`` is the turret's motion over one input turn, in degrees of turret rotation: one
  ``rise`` of ``lift = 360/stations`` over the index angle β (its law), dwells before and after;
  the program advances by 360°/N instead of closing.
* ``follower.kind = "roller"`` and ``follower.roller_radius`` are the turret's rollers,
  ``follower.roller_width`` their contact length.
* ``cam.thickness`` is each plate's thickness (parallel) or the cam's length along its axis
  (barrel, globoidal); ``cam.speed_rpm`` the input shaft's speed; ``cam.base_radius`` is derived
  (:func:`indexer_size`) and, when given, must agree.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

from .params import param


@dataclass(frozen=True, kw_only=True)
class IndexerSection:
    """`[indexer]`: the turret and its load (the indexing bodies only)."""

    stations: int | None = param(
        "Stations N: the turret's stops per turn; it turns 360/N degrees per index (the rise's lift)",
        kind="int", ge=2, le=64, optional=True, group="Indexer")
    centre_distance: float | None = param(
        "Distance C between the input (cam) axis and the turret axis (parallel to it)", unit="length", gt=0,
        optional=True,
        group="Indexer")
    pitch_radius: float | None = param(
        "The radius R_p of the circle of roller centres about the turret axis", unit="length", gt=0,
        optional=True, group="Indexer")
    cams: int | None = param("Parallel: the cam plates on the input shaft (2 or 3), each driving its own plane of N "
                             "rollers (default 2)", kind="int", ge=2, le=3, optional=True, group="Indexer")
    gap: float | None = param("Parallel: the axial gap between neighbouring plates, filled by a spacer that joins "
                              "them: 0 (face to face, the default) or at least 0.01 mm", unit="length", ge=0, optional=True,
                              group="Indexer")
    spacer_diameter: float | None = param(
        "Parallel: the spacer's diameter (default: 90 % of the plates' smallest profile diameter)",
        unit="length", gt=0, optional=True, group="Indexer")
    roller_start: float | None = param(
        "Barrel and globoidal: where the roller's working length starts — its height above the plane through "
        "the cam axis (barrel) or its distance from the turret axis (globoidal)", unit="length", gt=0,
        optional=True, group="Indexer")
    roller_end: float | None = param(
        "Barrel and globoidal: where the roller's working length ends (> roller_start)", unit="length", gt=0,
        optional=True, group="Indexer")
    root_radius: float | None = param(
        "Barrel: the rib's root cylinder radius; globoidal: the rib's root globoid, its distance from the "
        "circle the turret axis's foot traces about the cam axis", unit="length", gt=0, optional=True,
        group="Indexer")
    outer_radius: float | None = param("Barrel: the rib's top cylinder radius (> root_radius)", unit="length",
                                       gt=0, optional=True, group="Indexer")
    tip_radius: float | None = param("Globoidal: the rib's tip globoid (< root_radius)", unit="length", gt=0,
                                     optional=True, group="Indexer")
    roller_cone_angle: float | None = param(
        "Barrel and globoidal: the rollers' half cone angle γ (0, the default: cylindrical rollers; γ > 0 widens "
        "them away from the turret axis, follower.roller_radius then the radius at the middle of the working "
        "length; on a globoidal turret atan(roller_radius / middle length) puts the apex on the turret axis)",
        unit="angle", gt=-45, lt=45, optional=True, group="Indexer")
    max_pressure_angle: float | None = param(
        "Largest allowed pressure angle of the contact that carries the output's torque (an indexer's "
        "checks.max_pressure_angle; default 60°: the normal force twice the torque's tangential force)",
        unit="angle", gt=0, lt=90, optional=True, group="Indexer")
    output_inertia: float | None = param(
        "The output's (turret and load) moment of inertia about the turret axis (absent or 0: the drive is not "
        "sized)", unit="inertia", ge=0, optional=True, group="Indexer load")
    friction_torque: float | None = param("Friction torque on the output while it moves (default 0)",
                                          unit="torque", ge=0, optional=True, group="Indexer load")
    roller_rating: float | None = param(
        "The cam roller bearing's basic dynamic load rating C (ISO 281) for its rating life L10 (absent: no "
        "life reported)", unit="force", gt=0, optional=True, group="Indexer load")
    life_exponent: float | None = param(
        "ISO 281 life exponent p: 10/3 for roller and needle track rollers (the default), 3 for ball",
        kind="float", gt=0, le=10, optional=True, group="Indexer load")
    efficiency: float | None = param("Efficiency η of the cam–roller contact (input torque = output power / η; "
                                     "default 1)", kind="float", gt=0, le=1, optional=True, group="Indexer load")


#: the value an absent [indexer] field takes (spec units: mm, degrees, N·mm)
DEFAULTS: dict[str, float] = {"cams": 2, "gap": 0.0, "roller_cone_angle": 0.0, "max_pressure_angle": 60.0, "friction_torque": 0.0,
                              "life_exponent": 10.0 / 3.0, "efficiency": 1.0}


def indexer_value(spec: Any, name: str) -> Any:
    """``spec.indexer.<name>``, or its default (:data:`DEFAULTS`) when absent."""
    v = getattr(spec.indexer, name)
    return DEFAULTS[name] if v is None else v


#: the bodies this table serves, and the fields each reads (any other given field is an error)
INDEXER_FIELDS: dict[str, tuple[str, ...]] = {
    "parallel_indexer": ("stations", "centre_distance", "pitch_radius", "cams", "gap", "spacer_diameter"),
    "barrel_indexer": ("stations", "centre_distance", "pitch_radius", "roller_start", "roller_end",
                       "root_radius", "outer_radius", "roller_cone_angle"),
    "globoidal_indexer": ("stations", "centre_distance", "roller_start", "roller_end", "root_radius",
                          "tip_radius", "roller_cone_angle"),
}
#: the fields :func:`indexer_size` reads, per body
INDEXER_SIZE_FIELDS: dict[str, tuple[str, ...]] = {"parallel_indexer": ("stations", "centre_distance", "pitch_radius"),
                                                   "barrel_indexer": ("root_radius",),
                                                   "globoidal_indexer": ("centre_distance", "root_radius")}
#: the bodies whose roller must be smaller than the derived size (a plate's dwell radius holds the roller's
#: centre), in words; a spatial indexer's rollers do not stand on its core: no such rule
INDEXER_ROLLER_BOUND: dict[str, str] = {
    "parallel_indexer": "the plates' smallest dwell radius (the held roller's centre from the input axis)"}
LOAD_FIELDS = ("max_pressure_angle", "output_inertia", "friction_torque", "roller_rating", "life_exponent", "efficiency")


def indexer_size(body: str, indexer: Mapping[str, Any]) -> float | None:
    """What ``cam.base_radius`` stands for on an indexer (spec lengths), from the ``[indexer]``
    table as given (None when a field it needs is missing: the body's rules name it):

    * parallel: the smallest dwell radius min_k |P + R_p·e(a_k)| = min_k √(C² + R_p² + 2·C·R_p·cos a_k),
      a_k = π + (n_c − 1 − 2k)·π/(N·n_c) the held rollers' angles (docs/indexing.md);
    * barrel: the rib's root radius;
    * globoidal: the cam's waist radius C − root_radius.
    """
    try:
        if body == "parallel_indexer":
            c, rp, n = float(indexer["centre_distance"]), float(indexer["pitch_radius"]), int(indexer["stations"])
            nc = int(indexer.get("cams", 2))
            return min(math.sqrt(c * c + rp * rp + 2 * c * rp * math.cos(math.pi + (nc - 1 - 2 * k) * math.pi / (n * nc)))
                       for k in range(nc))
        if body == "barrel_indexer":
            return float(indexer["root_radius"])
        if body == "globoidal_indexer":
            return float(indexer["centre_distance"]) - float(indexer["root_radius"])
    except (KeyError, TypeError, ValueError):
        return None
    return None

"""The plate cam: the exact profile extruded by the thickness, with the bore (and keyway), a hub,
mounting holes and a timing mark when the spec asks for them."""
from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import SpecError, fmt_apart
from ..kinds import register_body
from ..spec.optimise import OBJECTIVES
from .base import BodyGeometry, Loop, Prism
from .features import bore_extent, bore_loop, hole_ligaments, plate_features
from .plane import PlaneCamBody


@register_body
class PlateBody(PlaneCamBody):
    """The outside profile; a spring (or gravity) keeps the follower on it."""

    kind = "plate"
    #: a stack of prisms of plane loops, with a pitch curve and a profile
    plane = True
    roller_within_base = True
    dynamics_train = "follower"
    #: the field that sizes the cam
    size_field = "cam.base_radius"
    #: the legend of the body's first added region in the cam drawing (None: the profile's)
    drawing_label = None
    #: the objectives its optimiser serves (optimise.objective; outer_diameter: a groove's disc)
    optimise_objectives = tuple(o for o in OBJECTIVES if o != "outer_diameter")
    #: the optimiser's design variables this body adds (optimise.variables)
    optimise_variables = ()
    #: the [cam] fields only this body reads
    own_fields = ()
    #: further modules of the body (beyond this one)
    modules = ()
    #: the body's name in drawing and report titles
    title = "Plate cam"
    #: a spring (force closure) keeps the follower on the cam: it can leave it (separation)
    closure = "force"
    #: no side to tell: the spring holds the follower on the one profile
    drive_note = ""

    @staticmethod
    def profile_inset(spec) -> float:
        """Extra inward offset of the profile beyond the roller radius (none for a plate)."""
        return 0.0

    @staticmethod
    def machining_defaults(spec) -> dict[str, float | None]:
        """Defaults of ``[machining]`` the body decides: the cut's depth (the whole plate) and the
        tool radius (None: the plate's own rule, the roller's size)."""
        return {"depth": spec.cam.thickness, "tool_radius": None}

    @staticmethod
    def label(spec) -> str:
        """The numbers that identify a plate cam (spec lengths, no unit): R_b and the thickness."""
        return f"R_b = {spec.cam.base_radius:g}, thickness {spec.cam.thickness:g}"

    @staticmethod
    def geometry(design) -> BodyGeometry:
        spec = design.spec
        t = spec.cam.thickness
        bore = bore_loop(spec)
        prisms = [Prism(Loop.nurbs(design.profile, "profile"), (bore,) if bore else (), 0.0, t, "add", "plate")]
        prisms += plate_features(design, t)
        return BodyGeometry("plate", tuple(prisms))

    @staticmethod
    def check(design, geometry: BodyGeometry) -> dict[str, Any]:
        """Material around the features; GeometryError naming the field when it is not there."""
        return feature_checks(design, lambda a: profile_radius_along(design.profile, a), "profile")


def profile_radius_along(curve, angles: np.ndarray, per_span: int = 64) -> np.ndarray:
    """Radius of a star-shaped closed curve along rays at polar ``angles`` [rad]: the dense
    samples' polar radius interpolated in angle (the curves here are star-shaped about the axis)."""
    _, pts = curve.sample(per_span)
    z = pts[:, 0] + 1j * pts[:, 1]
    ang = np.unwrap(np.angle(z))
    order = np.argsort(ang)
    a, r = ang[order], np.abs(z)[order]
    a = np.concatenate([a - 2 * np.pi, a, a + 2 * np.pi])
    r = np.concatenate([r, r, r])
    base = ang[order][0]
    q = np.mod(np.asarray(angles) - base, 2 * np.pi) + base
    return np.interp(q, a, r)


def feature_checks(design, boundary_radius, boundary: str) -> dict[str, Any]:
    """The bore (with its keyway) and the mounting holes must leave material: keyway inside the
    boundary, holes clear of the bore, of each other and of the boundary (``boundary_radius(angle)``).

    Raises:
        SpecError: naming the field (a feature that does not fit the cam is bad input).
    """
    spec = design.spec
    cam = spec.cam
    out: dict[str, Any] = {"bore_extent": bore_extent(spec)}
    rb = bore_extent(spec)
    if rb > 0 and (cam.keyway is not None or cam.keyway_width is not None):
        margin = float(np.min(boundary_radius(np.array([np.pi / 2])))) - rb
        out["keyway_ligament"] = margin
        if margin <= 0:
            field = "cam.keyway_depth" if cam.keyway_width is not None else "cam.keyway"
            raise SpecError(field, f"the keyway reaches {fmt_apart(rb, rb + margin, 4)} from the axis, through the "
                            f"{boundary} ({fmt_apart(rb + margin, rb, 4)} there)")
    if cam.mounting_holes:
        lig = hole_ligaments(spec, boundary_radius, rb)
        out["hole_ligaments"] = lig
        worst = min(lig, key=lig.get)
        if lig[worst] <= 0:
            what = {"to_bore": "the bore", "to_outer": f"the {boundary}", "between": "each other"}[worst]
            raise SpecError("cam.mounting_circle_diameter", f"the mounting holes run into {what} "
                            f"({lig[worst]:.4g} of material left)")
    return out

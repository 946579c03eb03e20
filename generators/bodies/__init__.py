"""Cam bodies: which curves bound which faces, as plain data (:mod:`.base`), one module per body —
:mod:`.plate` (the outside profile), :mod:`.groove` (a groove in a disc's face) and :mod:`.conjugate`
(two plate cams driving one follower through two rollers) and :mod:`.cylindrical` (a groove around a
cylinder, the follower moving along the cam axis; not a stack of prisms) — with the
features every body can carry (:mod:`.features`: bore and keyway, hub, mounting holes, timing
mark).  :func:`body_of` is the one place that maps ``cam.body`` to its class."""
from __future__ import annotations

from .base import Arc, BodyGeometry, Curve, Line, Loop, Prism
from .conjugate import ConjugateBody, refuse_stray_fields, validate_conjugate
from .cylindrical import CylindricalBody, validate_cylindrical
from .groove import GrooveBody, validate_groove
from .plate import PlateBody

#: cam.body → the body
BODY_KINDS = {"plate": PlateBody, "groove": GrooveBody, "conjugate": ConjugateBody, "cylindrical": CylindricalBody}
#: cam.body → its own spec rules (beyond the fields' declarations)
BODY_RULES = {"groove": validate_groove, "conjugate": validate_conjugate, "cylindrical": validate_cylindrical}
#: cam.body → the [cam] fields only it reads (an error on any other body)
BODY_FIELDS = {"groove": ("outer_diameter",), "cylindrical": ("outer_diameter", "cylinder_radius", "length")}


def body_of(spec):
    """The body class of a spec."""
    return BODY_KINDS[spec.cam.body]


def drawing_title(spec) -> str:
    """The title of the spec's drawing and report: ``drawing.title`` when given, else the body's
    name ("Plate cam", "Groove cam", "Conjugate cam pair", "Cylindrical cam")."""
    return (spec.drawing.title or "").strip() or body_of(spec).title


def validate_body(spec) -> None:
    """The rules of the spec's body and of the features every body shares.

    Raises:
        SpecError: naming the field and the rule.
    """
    from ..errors import SpecError, fmt_apart

    cam = spec.cam
    rule = BODY_RULES.get(cam.body)
    if rule is not None:
        rule(spec)
    if cam.body != "conjugate":
        refuse_stray_fields(spec)
    for name in sorted({n for names in BODY_FIELDS.values() for n in names}):
        owners = [b for b, names in BODY_FIELDS.items() if name in names]
        if cam.body not in owners and getattr(cam, name) is not None:
            which = " and ".join(owners)
            raise SpecError(f"cam.{name}", f"applies to {which} cams only (cam.body = "
                            + " or ".join(f'"{b}"' for b in owners) + ")")
    if (cam.keyway is not None or cam.keyway_width is not None) and cam.bore_diameter <= 0:
        raise SpecError("cam.keyway" if cam.keyway is not None else "cam.keyway_width",
                        "needs a bore: cam.bore_diameter > 0")
    if cam.keyway is not None and (cam.keyway_width is not None or cam.keyway_depth is not None):
        raise SpecError("cam.keyway", "give a standard or keyway_width and keyway_depth, not both")
    if (cam.keyway_width is None) != (cam.keyway_depth is None):
        missing = "cam.keyway_depth" if cam.keyway_depth is None else "cam.keyway_width"
        raise SpecError(missing, "is required with the other explicit keyway dimension")
    if cam.keyway_width is not None and not cam.keyway_width < cam.bore_diameter:
        raise SpecError("cam.keyway_width", f"must be < cam.bore_diameter ({fmt_apart(cam.bore_diameter, cam.keyway_width)}), "
                        f"got {fmt_apart(cam.keyway_width, cam.bore_diameter)}")
    if (cam.hub_diameter is None) != (cam.hub_length is None):
        missing = "cam.hub_length" if cam.hub_length is None else "cam.hub_diameter"
        raise SpecError(missing, "is required with the other hub dimension")
    if cam.hub_diameter is not None:
        from .features import bore_extent

        if not cam.hub_diameter / 2 > bore_extent(spec):
            reach = bore_extent(spec)
            raise SpecError("cam.hub_diameter", f"must leave material around the bore and keyway (they reach "
                            f"{fmt_apart(reach, cam.hub_diameter / 2, 4)} from the axis), got "
                            f"{fmt_apart(cam.hub_diameter, 2 * reach)}")
    if cam.mounting_holes:
        for name in ("mounting_hole_diameter", "mounting_circle_diameter"):
            if getattr(cam, name) is None:
                raise SpecError(f"cam.{name}", "is required with cam.mounting_holes")
    from .features import resolved

    if cam.timing_mark and not resolved(spec, "cam", "timing_mark_depth") < cam.thickness:
        depth = resolved(spec, "cam", "timing_mark_depth")
        raise SpecError("cam.timing_mark_depth", f"must be < cam.thickness ({fmt_apart(cam.thickness, depth)}), got "
                        f"{fmt_apart(depth, cam.thickness)}")


__all__ = ["Arc", "BODY_KINDS", "BodyGeometry", "ConjugateBody", "Curve", "CylindricalBody", "GrooveBody", "Line", "Loop", "PlateBody", "Prism",
           "body_of", "drawing_title", "validate_body"]

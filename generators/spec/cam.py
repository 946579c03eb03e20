"""The spec's `[cam]` table: :class:`CamSection` (the body, its size, rotation and features) and the
choices it declares (``BODIES``, ``KEYWAYS``).
"""
from __future__ import annotations

from dataclasses import dataclass

from .params import param


#: cam bodies (CAM_SPEC.md "Cam bodies") and keyway standards
BODIES = ("plate", "groove", "conjugate", "cylindrical", "parallel_indexer", "barrel_indexer", "globoidal_indexer")
KEYWAYS = ("DIN6885", "ANSI")


@dataclass(frozen=True, kw_only=True)
class CamSection:
    """`[cam]`: the cam body and its rotation."""

    base_radius: float = param(
        "Base radius R_b: radius of the circle traced by the follower point (knife tip or roller centre) at zero lift",
        unit="length", gt=0, group="Cam",
    )
    thickness: float = param("Extrusion depth of the plate (solid from z = 0 to z = thickness)",
                             unit="length", gt=0, group="Cam")
    bore_diameter: float = param("Diameter of the central hole; 0 for a solid disc",
                                 unit="length", ge=0, default=0.0, group="Cam")
    direction: str = param("Rotation direction of the cam viewed from +Z",
                           kind="str", choices=("ccw", "cw"), default="ccw", group="Cam")
    speed_rpm: float = param("Constant angular speed of the cam", unit="speed", gt=0,
                             default=60.0, group="Cam")
    # ---- the body and its features (CAM_SPEC.md "Cam bodies") ----
    body: str = param(
        "The cam body: \"plate\" (the outside profile, a spring keeps the follower on it), \"groove\" (a "
        "disc with the roller running in a groove cut into its top face: positive drive) or \"conjugate\" (two "
        "plate cams on one shaft driving one follower through two rollers: positive drive, see [conjugate]) or "
        "\"cylindrical\" (a barrel cam: a groove around a cylinder, the follower moving along the cam axis or "
        "swinging on an arm about a radial pivot; "
        "see cam.cylinder_radius, cam.length and [groove]), or an indexer turning a turret 360°/N per input "
        "turn: \"parallel_indexer\" (two or three plate cams), \"barrel_indexer\" (a rib on a cylinder) or "
        "\"globoidal_indexer\" (a rib on a globoid); see [indexer]",
        kind="str",
        choices=BODIES, default="plate", group="Cam")
    outer_diameter: float | None = param(
        "Groove cam: diameter of the disc; cylindrical cam: the cylinder's outer diameter (default: the pitch "
        "radius at mid-depth of the groove, 2·cylinder_radius + groove.depth)", unit="length", gt=0, optional=True,
        group="Cam")
    cylinder_radius: float | None = param(
        "Cylindrical cam: pitch radius R_p of the groove on the cylinder (the pressure angle tan φ = s′/R_p is "
        "checked there); cam.base_radius takes this value", unit="length", gt=0, optional=True, group="Cam")
    length: float | None = param(
        "Cylindrical cam: axial length of the cylinder (0 ≤ z ≤ length); cam.thickness takes this value",
        unit="length", gt=0, optional=True, group="Cam")
    hub_diameter: float | None = param("Hub diameter (the hub stands below the plate, bored as it is)",
                                       unit="length", gt=0, optional=True, group="Cam")
    hub_length: float | None = param("Hub length along the cam axis", unit="length", gt=0, optional=True,
                                     group="Cam")
    keyway: str | None = param(
        "Keyway in the bore sized from the bore diameter by a standard: \"DIN6885\" (DIN 6885-1 parallel "
        "key) or \"ANSI\" (ANSI B17.1 square key); or give keyway_width and keyway_depth", kind="str",
        choices=KEYWAYS, optional=True, group="Cam")
    keyway_width: float | None = param("Keyway width (explicit keyway)", unit="length", gt=0, optional=True,
                                       group="Cam")
    keyway_depth: float | None = param("Keyway depth from the bore at its centre line (explicit keyway)",
                                       unit="length", gt=0, optional=True, group="Cam")
    mounting_holes: int = param("Number of mounting holes on the mounting circle (0: none)", kind="int", ge=0,
                                le=64, default=0, group="Cam")
    mounting_hole_diameter: float | None = param("Mounting hole diameter", unit="length", gt=0, optional=True,
                                                 group="Cam")
    mounting_circle_diameter: float | None = param("Diameter of the circle the mounting holes' centres lie on",
                                                   unit="length", gt=0, optional=True, group="Cam")
    timing_mark: bool = param("Engrave a radial timing mark on the top face where the follower is at θ = 0",
                              kind="bool", default=False, group="Cam")
    timing_mark_width: float | None = param("Width of the timing mark (default 0.5 mm, 0.02 in)", unit="length", gt=0,
                                            optional=True, group="Cam")
    timing_mark_depth: float | None = param("Depth of the timing mark (default 0.2 mm, 0.008 in)", unit="length",
                                            gt=0, optional=True, group="Cam")

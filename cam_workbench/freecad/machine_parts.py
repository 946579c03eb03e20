"""What each cam of a machine moves, as FreeCAD parts (issue 24; docs/machine.md "In FreeCAD"): its
follower, its linkage and its tool, drawn from the animation's own data
(:func:`cam_workbench.generators.machine.frames.cam_frames` at one machine angle) — the same follower
point, joints and tool pose that the animation draws and the clearance check uses, never computed again.

The machine plane (frames.py "Conventions") is the document's XY plane — every cam's axis is the document's
Z axis — and a cam's parts stand in its slot on the shaft, z₀ ≤ z ≤ z₀ + t (t the cam's thickness),
lengths turned from the spec's unit into mm (the cam's ``scale``):

* **follower** — the roller, a cylinder of the roller's radius about the follower point over the cam's
  thickness; the stem or arm, a rod of radius :data:`ROD` · t on the slot's mid-plane z₀ + t/2; a flat
  face, the face's segment as a plane face over the thickness; an arm's pivot, a pin of radius
  :data:`PIN` · t over the thickness;
* **linkage** — every link of frames.py's ``links`` a rod on the mid-plane between its two joints (a
  lever one bar through its fulcrum; a four-bar its ground, crank, coupler and rocker), a pin at every
  joint (each point once);
* **tool** — the ``[cam.tool]`` outline (a true circle, or the polygon) in the tool's frame, a plate
  :data:`TOOL_PLATE` · t thick centred on the mid-plane, placed at the tool point and turned by the tool
  frame's rotation: its ``Placement`` is (tool point, rotation about Z).

Each part is a ``Part::Feature`` linked to its cam (``Cam``), its ``Role`` one of :data:`ROLES`; a tool
part keeps its ``[cam.tool]`` table (``Outline``, JSON as the machine file has it), which places the
tool of a cam without a linkage.  App side: FreeCAD's ``Part`` only, no Gui module.
"""
from __future__ import annotations

import json
import math
from typing import Any, Callable

import FreeCAD
import Part
import numpy as np

from cam_workbench.generators.kinds import body_of
from cam_workbench.generators.machine import MachineCam, ToolOutline
from cam_workbench.generators.machine.frames import CamFrames, cam_frames, tool_polygon

#: The parts a cam may have, in the order they are made.
ROLES = ("follower", "linkage", "tool")
#: Each part's colour (RGB 0–1): the animation's follower, link and tool colours
#: (exporters/plots.py ``COLORS["follower"]`` #8a6212, exporters/machine_animation.py #2e7d32, #6a1b9a).
COLOURS = {"follower": (0.541, 0.384, 0.071), "linkage": (0.180, 0.490, 0.196), "tool": (0.416, 0.106, 0.604)}
#: Rod radius (stems, arms, links), pin radius (pivots, joints) and the tool plate's thickness, as
#: fractions of the cam's thickness.
ROD = 0.1
PIN = 0.2
TOOL_PLATE = 0.25
#: Links shorter than this [mm] (a joint that is also the tool point) are not drawn.
MIN_LINK_MM = 1e-9
_READONLY = 1
_Z = FreeCAD.Vector(0, 0, 1)


def roles_of(cam: MachineCam) -> tuple[str, ...]:
    """The parts drawn for ``cam``: a follower (a plane cam: one with a profile in the machine plane), a
    linkage (with a ``[linkage]``), a tool (with a ``[cam.tool]`` outline); none for a cam that is not a
    plane cam (its follower has no place in the machine plane)."""
    if not body_of(cam.spec).plane:
        return ()
    has = {"follower": True, "linkage": cam.spec.linkage.kind is not None, "tool": cam.tool is not None}
    return tuple(r for r in ROLES if has[r])


def add_part(doc: Any, name: str, cam_obj: Any, role: str, tool: ToolOutline | None) -> Any:
    """A ``Part::Feature`` for ``role`` of the cam feature ``cam_obj`` (labelled after the cam, coloured when
    the GUI is up); its shape is set by :func:`update_parts`."""
    part = doc.addObject("Part::Feature", name)
    part.addProperty("App::PropertyLink", "Cam", "Machine", "The cam that moves this part", _READONLY)
    part.addProperty("App::PropertyString", "Role", "Machine", f"Which part: {', '.join(ROLES)}", _READONLY)
    part.Cam = cam_obj
    part.Role = role
    label = f"{cam_obj.Label} {role}"
    if tool is not None:
        part.addProperty("App::PropertyString", "Outline", "Machine",
                         "The tool's [cam.tool] table (JSON, as in the machine file): its outline in the tool's "
                         "frame and, without a linkage, its origin/direction", _READONLY)
        part.Outline = json.dumps(tool.to_dict())
        label += f" ({tool.label})" if tool.label else ""
    part.Label = label
    view = part.ViewObject  # None headless
    if view is not None:
        view.ShapeColor = COLOURS[role]
        view.LineColor = COLOURS[role]
    return part


def outline_of_part(part: Any) -> ToolOutline:
    """The ``[cam.tool]`` a tool part keeps (``Outline``, :meth:`ToolOutline.to_dict`'s JSON)."""
    d = json.loads(part.Outline)
    return ToolOutline(d["label"], radius=d["circle"]["radius"] if "circle" in d else None,
                       polygon=tuple(tuple(p) for p in d["polygon"]) if "polygon" in d else None,
                       origin=tuple(d["origin"]) if "origin" in d else None, direction=d.get("direction"))


# ---- shapes ---------------------------------------------------------------------------------------
def _at(p: np.ndarray, z: float) -> Any:
    return FreeCAD.Vector(float(p[0]), float(p[1]), float(z))


def _rod(a: np.ndarray, b: np.ndarray, z: float, r: float) -> Any:
    d = b - a
    length = float(np.hypot(d[0], d[1]))
    if length <= MIN_LINK_MM:
        return None
    return Part.makeCylinder(r, length, _at(a, z), FreeCAD.Vector(float(d[0]), float(d[1]), 0.0))


def _pin(p: np.ndarray, z0: float, t: float) -> Any:
    return Part.makeCylinder(PIN * t, t, _at(p, z0))


def _face(a: np.ndarray, b: np.ndarray, z0: float, t: float) -> Any:
    return Part.Face(Part.makePolygon([_at(a, z0), _at(b, z0), _at(b, z0 + t), _at(a, z0 + t), _at(a, z0)]))


def _compound(shapes: list[Any]) -> Any:
    return Part.makeCompound([s for s in shapes if s is not None])


def follower_shape(f: CamFrames, tool: ToolOutline | None, z0: float, t: float, scale: float) -> Any:
    """The follower of frame 0 of ``f`` (spec lengths × ``scale`` = mm) in the slot z₀ … z₀ + t [mm]."""
    mid = z0 + t / 2
    out = []
    if f.roller_radius > 0:
        out.append(Part.makeCylinder(f.roller_radius * scale, t, _at(f.point[0] * scale, z0)))
    for (a, b), role in zip(f.segments[0] * scale, f.roles):
        out.append(_face(a, b, z0, t) if role == "face" else _rod(a, b, mid, ROD * t))
    if f.pivot is not None:
        out.append(_pin(f.pivot[0] * scale, z0, t))
    return _compound(out)


def linkage_shape(f: CamFrames, tool: ToolOutline | None, z0: float, t: float, scale: float) -> Any:
    """The linkage of frame 0 of ``f``: a rod per link on the mid-plane, a pin per distinct joint [mm]."""
    joints = {n: p[0] * scale for n, p in f.joints.items()}
    out = [_rod(joints[a], joints[b], z0 + t / 2, ROD * t) for a, b in f.links]
    drawn: list[np.ndarray] = []
    for p in joints.values():
        if all(np.hypot(*(p - q)) > MIN_LINK_MM for q in drawn):
            drawn.append(p)
            out.append(_pin(p, z0, t))
    return _compound(out)


def tool_shape(f: CamFrames, tool: ToolOutline | None, z0: float, t: float, scale: float) -> Any:
    """The tool's outline as a plate in its frame, placed at frame 0's tool point and turned by its
    rotation (the shape's ``Placement``) [mm]."""
    assert tool is not None and f.tool_point is not None and f.tool_angle is not None
    if tool.radius is not None:
        wire = Part.Wire(Part.makeCircle(tool.radius * scale))
    else:
        wire = Part.makePolygon([_at(p * scale, 0.0) for p in tool_polygon(tool)])
    h = TOOL_PLATE * t
    shape = Part.Face(wire).extrude(FreeCAD.Vector(0, 0, h))
    shape.Placement = FreeCAD.Placement(_at(f.tool_point[0] * scale, z0 + (t - h) / 2),
                                        FreeCAD.Rotation(_Z, math.degrees(float(f.tool_angle[0]))))
    return shape


SHAPES: dict[str, Callable[[CamFrames, ToolOutline | None, float, float, float], Any]] = {
    "follower": follower_shape, "linkage": linkage_shape, "tool": tool_shape}


def update_parts(cam_obj: Any, parts: list[Any], phase: float, machine_angle: float, z0: float, t: float) -> None:
    """Set the shapes of ``parts`` (of the cam feature ``cam_obj``, at ``phase`` [deg], in its slot
    z₀ … z₀ + t [mm]) for the machine angle [deg] from frames.py's data and the cam's cached design.  The
    caller makes sure the cam has one.

    Raises:
        SpecError: the cam is not a plane cam (frames.py's message, naming ``cam.body``).
    """
    tools = [outline_of_part(p) for p in parts if p.Role == "tool"]
    tool = tools[0] if tools else None
    f = cam_frames(cam_obj.Label, cam_obj.Proxy.design, phase, tool, np.array([machine_angle], dtype=float))
    for part in parts:
        part.Shape = SHAPES[part.Role](f, tool, z0, t, cam_obj.Proxy.scale)


__all__ = ["COLOURS", "PIN", "ROD", "ROLES", "SHAPES", "TOOL_PLATE", "add_part", "follower_shape", "linkage_shape",
           "outline_of_part", "roles_of", "tool_shape", "update_parts"]

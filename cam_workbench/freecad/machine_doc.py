"""A machine in a FreeCAD document: every cam of a machine file on one camshaft (issue 24; docs/machine.md,
docs/freecad.md "Machines").

:func:`open_machine` reads a machine file (or its TOML structure) with the library's loader
(:func:`cam_workbench.generators.machine.load_machine`, :func:`~cam_workbench.generators.machine.machine_from_dict`:
a bad file raises its :class:`~cam_workbench.generators.errors.SpecError`, naming the field, and adds nothing)
and adds one ``Cam`` feature per cam (:func:`.feature.create`, the spec's own body and follower) to a machine
group (``App::DocumentObjectGroupPython``, proxy :class:`MachineGroup`), with a shaft cylinder through the bores.

The shaft is the cams' common axis: every cam's own axis (its frame's Z axis) on the document's Z axis.  Cam i
sits at z_i = Σ_{j<i} (t_j + gap) — t_j the cam's thickness (``CamThickness``), ``CamGap`` between
neighbours — so cam i spans z_i ≤ z ≤ z_i + t_i, in file order, and no two overlap.  The group's
``MachineAngle`` φ [deg] turns the camshaft: cam i stands at its cam angle θ_i = (φ − phase_i) mod 360
(``Phases``, the file's ``phase``), its placement the rotation Rot(δ_i·θ_i) about the shaft (δ = +1 for a
ccw cam, −1 for cw: the cam frame is turned by the cam angle, docs/followers.md "Conventions"), and its
drawn follower at ``FollowerAngle`` = θ_i — in the cam's frame, so placed with the cam it stands where it is
in the fixed frame.  Changing ``MachineAngle``, ``Phases`` or ``CamGap`` sets the cams' placements and
follower angles at once; a recompute rebuilds them.  :func:`step_machine` (what the GUI's *Play* timer
calls) does the same and redraws the followers from each cam's cached design, without rebuilding its solid.

What each cam moves — its follower, its linkage, its tool (:mod:`.machine_parts`: ``Part::Feature`` objects
drawn from the animation's frame data at φ, the tool where the clearance check puts it) — sits with the cam
in the cam's folder (``App::DocumentObjectGroup`` "<cam> mechanism") and is listed in the group's ``Parts``;
the parts move with ``MachineAngle``: set at once from the cams' cached designs, and after a recompute (the
group's ``execute`` runs after its cams are built) from the fresh ones.

App side: nothing here imports FreeCADGui or Qt at module level; the *Play* task panel
(:func:`open_play_panel`) imports them when the GUI opens it.
"""
from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any, Mapping

import FreeCAD

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.machine import MachineSpec, load_machine, machine_from_dict

from .feature import FOLLOWER_ANGLE, create, reference_of, references_of, update_reference
from .machine_parts import add_part, roles_of, update_parts
from .stateless import Stateless

#: The group's angle property: the camshaft's angle φ [deg].
MACHINE_ANGLE = "MachineAngle"
#: Default gap between neighbouring cams along the shaft [mm].
DEFAULT_GAP_MM = 5.0
#: The shaft's radius as a fraction of the smallest bore's (a hair inside, so it does not share the bores' faces).
SHAFT_FIT = 0.98
#: Properties whose change re-places the cams.
_DRIVING = (MACHINE_ANGLE, "Phases", "CamGap")
_PROP_READONLY = 1


def _restoring(obj: Any) -> bool:
    doc = getattr(obj, "Document", None)
    return bool(getattr(doc, "Restoring", False)) or "Restore" in getattr(obj, "State", ())


def value_of(q: Any) -> float:
    """A FreeCAD quantity's (or a plain number's) value [mm, deg]."""
    return float(getattr(q, "Value", q))


class MachineGroup(Stateless):
    """Proxy of the machine group: its ``MachineAngle`` drives every cam's rotation and follower."""

    def __init__(self, obj: Any):
        obj.Proxy = self
        obj.addProperty("App::PropertyAngle", MACHINE_ANGLE, "Machine",
                        "Camshaft angle φ: each cam stands at its cam angle φ − phase (mod 360°)")
        obj.addProperty("App::PropertyLinkList", "Cams", "Machine", "The machine's cams, in the file's order")
        obj.addProperty("App::PropertyFloatList", "Phases", "Machine",
                        "Each cam's phase [deg]: the machine angle at which its cam angle is 0 (one per cam)")
        obj.addProperty("App::PropertyLength", "CamGap", "Machine",
                        "Gap between neighbouring cams along the shaft")
        obj.addProperty("App::PropertyLinkList", "Parts", "Machine",
                        "What the cams move: each cam's follower, linkage and tool (Part features, each linked "
                        "to its Cam)")
        obj.addProperty("App::PropertyLink", "Shaft", "Machine", "The shaft cylinder through the bores (or none)")
        obj.addProperty("App::PropertyFloat", "SpeedRpm", "Machine", "Camshaft speed [rpm] (from the file)",
                        _PROP_READONLY)
        obj.addProperty("App::PropertyString", "Source", "Machine", "The machine file it was opened from",
                        _PROP_READONLY)
        obj.CamGap = DEFAULT_GAP_MM

    def execute(self, obj: Any) -> None:
        place_parts(obj)  # the cams build themselves (before this: the group depends on them); onChanged places them

    def onChanged(self, obj: Any, prop: str) -> None:
        if prop in _DRIVING and not _restoring(obj) and "Shaft" in obj.PropertiesList:
            place_cams(obj)


def is_machine(obj: Any) -> bool:
    """Whether ``obj`` is a machine group."""
    return isinstance(getattr(obj, "Proxy", None), MachineGroup)


def machines_of(doc: Any) -> list[Any]:
    """The machine groups of ``doc`` (none for no document)."""
    return [o for o in doc.Objects if is_machine(o)] if doc is not None else []


def _as_machine(source: Any) -> tuple[MachineSpec, str]:
    """(validated machine, where it came from) from a path, a TOML structure or a MachineSpec."""
    if isinstance(source, MachineSpec):
        return source, ""
    if isinstance(source, Mapping):
        return machine_from_dict(source), ""
    if isinstance(source, (str, os.PathLike)):
        return load_machine(source), str(Path(source))
    raise TypeError(f"a machine is a file's path, a TOML structure or a MachineSpec, not {type(source).__name__}")


def _object_name(text: str) -> str:
    name = "".join(c if c.isalnum() or c == "_" else "_" for c in text)
    return name if name[:1].isalpha() else f"C{name}"


def open_machine(doc: Any, path_or_dict: Any, *, gap: float = DEFAULT_GAP_MM, shaft: bool = True) -> Any:
    """Add a machine — its cams on one shaft, a ``MachineAngle`` turning them — to ``doc`` and recompute.

    Args:
        doc: the document; None: the active one (a new one if there is none).
        path_or_dict: a machine file (TOML, spec paths relative to it), its TOML structure, or a MachineSpec.
        gap: gap between neighbouring cams along the shaft [mm].
        shaft: also add a shaft cylinder through the bores (when every cam has a bore).

    Returns:
        The machine group.

    Raises:
        SpecError: the machine file is bad, naming the field (nothing is added to the document).
    """
    machine, source = _as_machine(path_or_dict)
    if doc is None:
        doc = FreeCAD.ActiveDocument or FreeCAD.newDocument()
    base = _object_name(machine.machine.name)
    group = doc.addObject("App::DocumentObjectGroupPython", f"Machine_{base}")
    MachineGroup(group)
    group.Label = machine.machine.name
    group.SpeedRpm = float(machine.machine.speed_rpm)
    group.Source = source
    group.CamGap = float(gap)
    cams, parts = [], []
    for cam in machine.cams:
        name = f"{base}_{_object_name(cam.name)}"
        obj = create(doc, cam.spec, name=name)
        obj.Label = cam.name
        folder = doc.addObject("App::DocumentObjectGroup", f"{name}_Mechanism")
        folder.Label = f"{cam.name} mechanism"
        group.addObject(folder)
        folder.addObject(obj)
        for role in roles_of(cam):
            part = add_part(doc, f"{name}_{role.capitalize()}", obj, role, cam.tool if role == "tool" else None)
            folder.addObject(part)
            parts.append(part)
        cams.append(obj)
    group.Cams = cams
    group.Parts = parts
    group.Phases = [float(c.phase) for c in machine.cams]
    if shaft:
        group.Shaft = _add_shaft(doc, group, base)
    place_cams(group)
    doc.recompute()
    return group


def _add_shaft(doc: Any, group: Any, base: str) -> Any:
    bores = [value_of(getattr(c, "CamBoreDiameter", 0.0)) for c in group.Cams]
    if not bores or min(bores) <= 0:
        FreeCAD.Console.PrintMessage(f"{group.Label}: no shaft drawn (a cam has no bore)\n")
        return None
    shaft = doc.addObject("Part::Cylinder", f"{base}_Shaft")
    shaft.Label = f"{group.Label} shaft"
    shaft.Radius = SHAFT_FIT * min(bores) / 2.0
    group.addObject(shaft)
    return shaft


def shaft_layout(group: Any) -> list[tuple[float, float]]:
    """Each cam's (z_start, thickness) along the shaft [mm]: z_i = Σ_{j<i} (t_j + CamGap)."""
    gap = value_of(group.CamGap)
    out, z = [], 0.0
    for cam in group.Cams:
        t = value_of(cam.CamThickness)
        out.append((z, t))
        z += t + gap
    return out


def cam_angle(machine_angle: float, phase: float) -> float:
    """A cam's angle θ = (φ − phase) mod 360 [deg] at the machine angle φ."""
    theta = math.fmod(machine_angle - phase, 360.0)
    return theta + 360.0 if theta < 0 else theta


def place_cams(group: Any) -> None:
    """Set every cam's placement (its slot on the shaft, turned by δ·θ) and its follower's angle θ from the
    group's ``MachineAngle`` and ``Phases``, and the cams' parts (:func:`place_parts`); the shaft's length
    spans the cams.  The caller recomputes."""
    cams = list(group.Cams)
    phases = list(group.Phases)
    if len(phases) != len(cams):
        FreeCAD.Console.PrintError(f"{group.Label}: Phases has {len(phases)} values for {len(cams)} cams: "
                                   "one phase per cam\n")
        return
    phi = value_of(group.MachineAngle)
    layout = shaft_layout(group)
    axis = FreeCAD.Vector(0, 0, 1)
    for cam, phase, (z, _t) in zip(cams, phases, layout):
        theta = cam_angle(phi, phase)
        sense = -1.0 if getattr(cam, "CamDirection", "ccw") == "cw" else 1.0
        cam.Placement = FreeCAD.Placement(FreeCAD.Vector(0, 0, z), FreeCAD.Rotation(axis, sense * theta))
        follower = reference_of(cam, "follower")
        if follower is not None and abs(value_of(getattr(follower, FOLLOWER_ANGLE)) - theta) > 1e-12:
            setattr(follower, FOLLOWER_ANGLE, theta)
    shaft = group.Shaft
    if shaft is not None and layout:
        gap = value_of(group.CamGap)
        end = layout[-1][0] + layout[-1][1]
        margin = max(gap, 1.0)
        if abs(value_of(shaft.Height) - (end + 2 * margin)) > 1e-9:
            shaft.Height = end + 2 * margin
        if abs(shaft.Placement.Base.z + margin) > 1e-9:
            shaft.Placement = FreeCAD.Placement(FreeCAD.Vector(0, 0, -margin), FreeCAD.Rotation())
    place_parts(group)


def place_parts(group: Any) -> None:
    """Set every cam's parts (follower, linkage, tool) for the group's ``MachineAngle``, in the cam's slot,
    from the cam's cached design: a cam without one (not built yet) keeps them where they are — the
    recompute that builds it places them (:meth:`MachineGroup.execute`).  The parts are outputs: they are
    left untouched (nothing to recompute)."""
    cams, phases, parts = list(group.Cams), list(group.Phases), list(group.Parts)
    if not parts or len(phases) != len(cams):
        return  # place_cams reports a Phases list that does not fit
    phi = value_of(group.MachineAngle)
    for cam, phase, (z, t) in zip(cams, phases, shaft_layout(group)):
        mine = [p for p in parts if p.Cam is not None and p.Cam.Name == cam.Name]
        if not mine or cam.Proxy.design is None:
            continue
        try:
            update_parts(cam, mine, phase, phi, z, t)
        except SpecError as exc:
            FreeCAD.Console.PrintError(f"{cam.Label}: its follower, linkage and tool are not drawn: {exc}\n")
        for part in mine:
            part.purgeTouched()


def step_machine(group: Any, angle: float) -> None:
    """Turn the machine to ``angle`` [deg] (what the *Play* timer calls): the cams turn, their followers are
    redrawn and their parts move (:func:`place_parts`) from each cam's cached design — a cam without one (not
    built yet, or in error) is recomputed."""
    group.MachineAngle = float(angle)  # onChanged places the cams and their parts
    stale = False
    for cam in group.Cams:
        proxy = cam.Proxy
        if proxy.design is None or not str(cam.Status).startswith("ok"):
            stale = True
            continue
        for ref in references_of(cam):
            update_reference(ref, proxy.design, proxy.scale, cam.Placement)
            ref.purgeTouched()
        cam.purgeTouched()  # its shape moved with its placement; the design is unchanged
    group.purgeTouched()
    if stale:
        group.Document.recompute()

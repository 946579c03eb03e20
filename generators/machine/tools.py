"""Each cam's tool in the machine plane (issue 24; docs/machine.md, "The tool").

Every cam's axis is at the origin of the machine plane (the cams sit on one shaft); the plane is
each cam's *fixed frame* (docs/followers.md), lengths in the spec's unit.  A cam's **tool point**:

* through the cam's ``[linkage]`` (docs/linkages.md): ``Linkage.tool_point(q)`` of the follower
  coordinate q = lift_scale·s(x), s the follower's program (with ``motion_at = "tool"`` the one the
  inverse linkage derives), x the cam's own angle; the tool coordinate p = ``forward(q, …)``;
* without a linkage, by default the follower's own point where the cam's design puts it
  (:meth:`Follower.tool_mount <cam_workbench.generators.followers.base.Follower.tool_mount>`): a
  translating follower's point (the roller centre, the knife tip, the flat face's foot on its stem)
  at (e, s₀ + s), sliding along +y; an oscillating follower's point on its arm (the roller centre
  at the arm length; a flat face's centre) turning about the pivot (d, 0) with the arm, ψ = ψ₀ − s;
* without a linkage but with the machine file's ``[cam.tool]`` ``origin`` [length] or
  ``direction`` [deg] (the other defaulting to (0, 0) or 90°): a translating follower's point slides
  along the line through ``origin`` at ``direction``, at ``origin + s·(cos, sin)(direction)``; an
  oscillating follower's point on its arm (at the load lever, the arm length of a roller arm) turns
  about ``origin``: ``origin + L·(cos, sin)(direction + s·π/180)``;
* a cam whose body is not a plane cam (cylindrical, indexing) has no follower point in the machine
  plane: without origin/direction it is placed as if ``origin`` (0, 0), ``direction`` 90°; an
  indexer's tool rides its turret, the tool frame's origin on the turret's axis at ``origin``,
  turning by the turret's angle s.

Each placement is a :class:`~cam_workbench.generators.linkage.Lever` (ratio 1, or −1 for an arm's
ψ₀ − s), which is how it is computed.

The **tool frame** (the frame of a ``[cam.tool]`` outline) has its origin at the tool point; it
keeps the machine's axes on a sliding tool and turns with a rotating one by the tool's rotation p
[rad] from its position at zero lift (a four-bar's rocker, an arm).  The animation
(:mod:`.frames`) draws these same poses.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..kinds import body_of
from ..linkage import Lever, Linkage
from ..linkage.base import Jet
from ..motion.program import MotionProgram, wrap_angle
from ..spec.linkage import linkage_of
from ..spec.model import CamSpec
from .clearance import Circle, Polygon, Poses
from .spec import ToolOutline

#: [deg] a tool placed by [cam.tool] origin without direction (or of a cam that is not a plane cam)
#: slides (or its arm points) along +y of the machine plane
DEFAULT_TOOL_DIRECTION = 90.0


@dataclass(frozen=True)
class ToolDrive:
    """How one cam moves its tool.

    Attributes:
        name: the cam's name.
        phase: [deg] the machine angle of the cam's angle 0.
        program: the follower's program (lift units).
        linkage: the cam's linkage, or the follower's own point as a lever (``linked`` False): the
            follower's :meth:`~cam_workbench.generators.followers.base.Follower.tool_mount`, or
            ratio 1 placed by ``[cam.tool]`` origin/direction.
        scale: lift unit → linkage unit (π/180 for degrees, 1 for lengths).
        angular: the tool coordinate p is a rotation [rad] (else a displacement [length]).
        linked: a ``[linkage]`` drives the tool.
        motion_at: where the spec's [[motion]] is given ("follower" or "tool"); None without a linkage.
    """

    name: str
    phase: float
    program: MotionProgram
    linkage: Linkage
    scale: float
    angular: bool
    linked: bool
    motion_at: str | None

    def follower_jet(self, cam_angle: Any) -> Jet:
        """(q, q′, q″, q‴) in linkage units at the cam's own angles [rad] (derivatives per rad)."""
        k = self.program.evaluate(wrap_angle(np.asarray(cam_angle, float)))
        c = self.scale
        return c * np.asarray(k.s, float), c * np.asarray(k.ds, float), c * np.asarray(k.d2s, float), \
            c * np.asarray(k.d3s, float)

    def tool_jet(self, cam_angle: Any) -> Jet:
        """(p, p′, p″, p‴) in linkage units: the tool coordinate and its derivatives per rad."""
        return self.linkage.forward(*self.follower_jet(cam_angle))

    def poses(self, cam_angle: Any) -> Poses:
        """The tool frame's poses at the cam's own angles [rad]: the tool point [length] and the
        frame's rotation [rad] (p on a rotating tool, 0 on a sliding one)."""
        q = self.follower_jet(cam_angle)[0]
        p = self.linkage.forward(q, 0 * q, 0 * q, 0 * q)[0]
        return Poses(self.linkage.tool_point(q).reshape(-1, 2), p.reshape(-1) if self.angular else None)

    def at_machine(self, machine_deg: Any) -> Poses:
        """The poses at machine angles [deg] (the cam at its angle machine − phase)."""
        return self.poses(np.radians(np.asarray(machine_deg, float) - self.phase))

    def at_own(self, cam_deg: Any) -> Poses:
        """The poses at the cam's own angles [deg] (for a phase sweep)."""
        return self.poses(np.radians(np.asarray(cam_deg, float)))


def tool_drive(name: str, spec: CamSpec, phase: float = 0.0, program: MotionProgram | None = None,
               tool: ToolOutline | None = None) -> ToolDrive:
    """The tool of cam ``name`` (``spec`` at ``phase`` [deg]; ``program`` the follower's, default
    :meth:`MotionProgram.from_spec` — the follower's also when the linkage is driven from the tool;
    ``tool`` the machine file's ``[cam.tool]``).  Without a linkage the tool rides the follower's own
    point, or the point ``[cam.tool]`` ``origin``/``direction`` place (the module docstring)."""
    program = program or MotionProgram.from_spec(spec)
    drive = linkage_of(spec)
    body = body_of(spec)
    fol = body.dynamics_follower(spec)
    angular = fol.lift_unit == "angle"
    if drive is not None:
        return ToolDrive(name, phase, program, drive.linkage, drive.scale, angular, True, drive.motion_at)
    placed = tool is not None and (tool.origin is not None or tool.direction is not None)
    if body.plane and not placed:
        m = fol.tool_mount()
        own = Lever(float(m.ratio), angular, (float(m.origin[0]), float(m.origin[1])), float(m.direction),
                    float(m.radius))
    else:
        origin = tool.origin if tool is not None and tool.origin is not None else (0.0, 0.0)
        direction = tool.direction if tool is not None and tool.direction is not None else DEFAULT_TOOL_DIRECTION
        # an arm's tool point sits at its load lever; a spatial cam's turning output (an indexer's
        # turret) carries its tool frame on its axis at ``origin``
        own = Lever(1.0, angular, (float(origin[0]), float(origin[1])), float(np.radians(direction)),
                    float(fol.load_lever) if angular and body.plane else 0.0)
    return ToolDrive(name, phase, program, own, fol.lift_scale, angular, False, None)


def outline_of(tool: ToolOutline) -> Circle | Polygon:
    """The ``[cam.tool]`` outline as a clearance outline (tool frame, spec length unit)."""
    return Circle(tool.radius) if tool.radius is not None else Polygon(np.asarray(tool.polygon, float))


__all__ = ["DEFAULT_TOOL_DIRECTION", "ToolDrive", "outline_of", "tool_drive"]

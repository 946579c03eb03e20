"""The timing diagram's numbers: every follower's displacement, velocity and acceleration
against the machine angle, and each motion segment's start and end as a labelled event.

A cam with phase φ has its angle x = θ − φ at machine angle θ, so its follower at θ = φ + x is
at s(x).  Velocity and acceleration are per second at the camshaft's speed ω: v = s′·ω,
a = s″·ω² (lift units: the spec's length, or degrees of arm rotation for an oscillating follower).

Each cam's tool (:mod:`.tools`) rides along: its point in the machine plane at every grid angle,
the tool frame's rotation, and — for a cam with a ``[linkage]`` — the tool's own displacement,
velocity and acceleration p/scale, p′·ω/scale, p″·ω²/scale (the same lift unit), from the
follower's program through ``Linkage.forward``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..motion.program import MotionProgram
from ..spec.model import CamSpec
from ..spec.params import unit_name
from .spec import ToolOutline
from .tools import ToolDrive, tool_drive
from .torque import cam_angles


@dataclass(frozen=True)
class Event:
    """One motion segment on the machine's clock: its label ("pusher rise"), the segment's index
    and kind, and its start and end machine angles [deg, 0 … 360) (an end may be below its start:
    the segment runs through 0°)."""

    label: str
    segment: int
    kind: str
    start_deg: float
    end_deg: float

    def to_dict(self) -> dict[str, Any]:
        return {"label": self.label, "segment": self.segment, "kind": self.kind,
                "start_deg": self.start_deg, "end_deg": self.end_deg}


@dataclass(frozen=True)
class FollowerTiming:
    """One follower on the machine-angle grid.

    Attributes:
        name: the cam's name.
        phase: [deg].
        theta: machine angles [rad].
        s, v, a: displacement [lift unit], velocity [lift unit/s], acceleration [lift unit/s²].
        lift_unit: "mm", "in" or "deg".
        events: the program's rises and returns (dwells are what lies between).
        tool: the tool point's path (N×2, spec length unit, machine plane; :func:`tool_path`).
        tool_angle: the tool frame's rotation (N,) [rad] (0 on a sliding tool).
        tool_s, tool_v, tool_a: the tool's displacement [lift unit], velocity [/s], acceleration
            [/s²] when a ``[linkage]`` drives it, else None.
        drive: how the cam moves its tool (pose functions for the clearances).
    """

    name: str
    phase: float
    theta: np.ndarray
    s: np.ndarray
    v: np.ndarray
    a: np.ndarray
    lift_unit: str
    events: tuple[Event, ...]
    tool: np.ndarray | None = None
    tool_angle: np.ndarray | None = None
    tool_s: np.ndarray | None = None
    tool_v: np.ndarray | None = None
    tool_a: np.ndarray | None = None
    drive: ToolDrive | None = None

    @property
    def linked(self) -> bool:
        """A ``[linkage]`` drives the tool (its s, v, a are drawn and reported)."""
        return self.tool_s is not None


def follower_timing(name: str, spec: CamSpec, phase: float, theta: np.ndarray, omega: float,
                    program: MotionProgram | None = None, tool: ToolOutline | None = None) -> FollowerTiming:
    """The follower of cam ``name`` (``spec``, ``phase`` [deg]) at machine angles ``theta`` [rad]
    and camshaft speed ``omega`` [rad/s], with its tool (``tool``: the machine file's
    ``[cam.tool]``, which places a tool without a linkage); ``program``: the follower's (default
    :meth:`MotionProgram.from_spec`, the follower's also when the linkage is driven from the tool)."""
    program = program or MotionProgram.from_spec(spec)
    x = cam_angles(theta, phase)
    kin = program.evaluate(x)
    drive = tool_drive(name, spec, phase, program, tool)
    poses = drive.poses(x)
    tool_s = tool_v = tool_a = None
    if drive.linked:
        p = drive.tool_jet(x)
        c = drive.scale
        tool_s, tool_v, tool_a = p[0] / c, p[1] * omega / c, p[2] * omega**2 / c
    return FollowerTiming(name, phase, np.asarray(theta, float), np.asarray(kin.s, float),
                          np.asarray(kin.ds, float) * omega, np.asarray(kin.d2s, float) * omega**2,
                          "deg" if drive.angular else unit_name("length", spec.units), segment_events(name, program, phase),
                          poses.positions, poses.angles, tool_s, tool_v, tool_a, drive)


def segment_events(name: str, program: MotionProgram, phase: float) -> tuple[Event, ...]:
    """The program's rises and returns as events on the machine's clock, labelled "<name> <kind>"
    (numbered when a kind comes more than once: "lifter rise 1", "lifter rise 2")."""
    moving = [k for k, law in enumerate(program.laws) if law is not None]
    counts: dict[str, int] = {}
    for k in moving:
        counts[program.kinds[k]] = counts.get(program.kinds[k], 0) + 1
    seen: dict[str, int] = {}
    out = []
    for k in moving:
        kind = program.kinds[k]
        seen[kind] = seen.get(kind, 0) + 1
        label = f"{name} {kind}" + (f" {seen[kind]}" if counts[kind] > 1 else "")
        start = (phase + math.degrees(program.starts[k])) % 360.0
        end = (phase + math.degrees(program.starts[k] + program.spans[k])) % 360.0
        out.append(Event(label, k, kind, start, end))
    return tuple(out)


def tool_path(spec: CamSpec, cam_angle: np.ndarray, program: MotionProgram | None = None,
              tool: ToolOutline | None = None) -> np.ndarray:
    """The tool point's path [N×2, spec length unit, machine plane] at the cam's own angles
    ``cam_angle`` [rad]: through the spec's ``[linkage]`` (``Linkage.tool_point`` of the follower
    coordinate q = lift_scale·s from the follower's ``program``), or without one the follower's own
    point placed by ``tool``'s ``origin``/``direction`` (:mod:`.tools`)."""
    return tool_drive("", spec, 0.0, program, tool).poses(np.asarray(cam_angle, float)).positions


__all__ = ["Event", "FollowerTiming", "follower_timing", "segment_events", "tool_path"]

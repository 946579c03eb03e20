"""The mechanism in motion, as plain data (issue 24 item 5; docs/animation.md): every cam of a
machine turned to each machine angle, its follower where the program puts it, the linkage's
joints and links, and the tool's outline at the tool point — one picture per machine angle, the
cams side by side.  :func:`machine_frames` computes it; the drawing is
:mod:`cam_workbench.exporters.machine_animation`.

Conventions (docs/followers.md, docs/machine.md):

* **Cam frame and fixed frame.** Each cam's spec puts its axis at the origin of its own *fixed
  frame*; the profile (``design.profile``) is given in the *cam frame*, which turns with the cam.
  A cam with sense δ (+1 ``cam.direction = "ccw"``, −1 ``"cw"``) at cam angle x shows its profile
  in the fixed frame turned by Rot(δ·x): a fixed point F is Rot(−δx)·F in the cam frame
  (``Follower.points``).  At machine angle φ the cam angle is x = φ − phase.
* **Follower.** Where the follower's own drawing (:meth:`Follower.sketch`) puts it, in the fixed
  frame: the roller centre / knife tip / flat face's contact point is ``Follower.fixed(k)`` at
  the program's kinematics k(x); the stem, arm or face are the sketch's segments.
* **Machine plane.** Every cam's axis is at the origin of the machine plane (the cams are on one
  shaft), and the plane is each cam's fixed frame: the clearances (:mod:`.clearance`) are computed
  so.  The spec's ``[linkage]`` coordinates (``pivot_x``, ``pivot_y``) are measured from the
  cam's axis.  The follower coordinate is q = ``lift_scale``·s(x) (mm, or rad of arm rotation);
  the drawn joints are ``joints(q)`` — a lever on a translating follower attached first to the
  follower's line (:meth:`Lever.on_follower
  <cam_workbench.generators.linkage.lever.Lever.on_follower>` at ``Follower.tool_mount()``), so it is
  drawn as one bar from the input point on the stem through its fulcrum to the tool.
* **Tool.** One model with the clearance check: the tool point and the tool frame's rotation are
  :func:`cam_workbench.generators.machine.tools.tool_drive`'s poses at the cam angle x — through the
  linkage (``tool_point(q)``, turned by p when the output is a rotation), or without one the
  follower's own point (by default where the follower is drawn: the roller centre or knife tip,
  a flat face's foot on its stem or its centre on an arm) or the point ``[cam.tool]``
  ``origin``/``direction`` place.  The ``[cam.tool]`` outline (its own frame) is carried there; a
  circle is drawn as a polygon of :data:`CIRCLE_POINTS` vertices.
* **Placement.** The picture shows the cams side by side: each cam's whole group — cam,
  follower, linkage, tool — is shifted from the machine plane by its display offset (its axis's
  place in the picture): ``positions`` when given (one (x, y) per cam), else in a row along x,
  left to right in the machine's cam order, each cam's box (everything drawn for it over all
  frames) a gap of :data:`GAP` × the tallest box's height from its neighbour's, the axes on
  y = 0.  ``CamFrames.centre`` is that offset: a drawn tool point minus ``centre`` is the
  clearance check's.

Lengths are the spec's unit; angles in the results are degrees.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from ..errors import SpecError
from ..linkage import Lever
from ..motion.program import Kinematics
from ..spec.linkage import linkage_of
from .spec import MachineSpec, ToolOutline
from .tools import tool_drive

#: vertices of a circle drawn as a polygon (roller outlines are drawn as circles by the exporter)
CIRCLE_POINTS = 48
#: gap between neighbouring cams of the default row, as a fraction of the tallest cam's box
GAP = 0.15
#: profile samples per knot span of the profile NURBS
PROFILE_PER_SPAN = 8
#: link pairs (joint names) drawn between a linkage's joints, where both joints exist: a lever attached
#: to its follower (one bar: input → fulcrum → tool, or input → tool without a fulcrum), a lever
#: not attached (pivot → tool), a four-bar's ground, crank, coupler, rocker and the rocker's
#: extension to the tool point
LINK_PAIRS: tuple[tuple[str, str], ...] = (
    ("input", "fulcrum"), ("fulcrum", "tool"), ("pivot", "tool"),
    ("crank_pivot", "rocker_pivot"), ("crank_pivot", "crank_joint"), ("crank_joint", "rocker_joint"),
    ("rocker_pivot", "rocker_joint"), ("rocker_joint", "tool"),
)


@dataclass(frozen=True, eq=False)
class CamFrames:
    """One cam and everything it moves, at N machine angles, in the picture's frame (its axis at
    ``centre``, the display offset of its group from the machine plane; spec lengths).

    Attributes:
        name: the cam's name.
        phase: [deg].
        sense: +1 (ccw) or −1 (cw): the cam's outline at cam angle x is its profile turned by δ·x.
        centre: (2,) the cam's axis in the picture.
        cam_angle: (N,) x = φ − phase [deg, 0 … 360).
        lift: (N,) s(x) [lift unit: the spec's length, or degrees of arm rotation].
        profile: (P, 2) the profile in the cam frame (cam angle 0), closed (last = first).
        outline: (N, P, 2) the profile turned to each cam angle and placed at ``centre``.
        bore_radius: the bore's radius (0: none); the bore is a circle about ``centre``.
        mark: (N, 2, 2) a radial line turning with the cam (cam-frame +x, from the axis to half
            the base radius): shows the rotation.
        point: (N, 2) the follower point — roller centre, knife tip or flat face's contact point.
        roller_radius: the roller's radius about ``point`` (0: no roller).
        segments: (N, K, 2, 2) the follower's stem, arm or face: (start, end) points.
        roles: the K segments' roles ("stem", "arm", "face").
        pivot: (N, 2) the follower arm's pivot, or None (translating).
        joints: the linkage's joints by name, each (N, 2) (empty without a linkage).
        links: the linkage's links as pairs of joint names.
        tool_point: (N, 2) where the tool's frame sits — the clearance check's tool point
            (:func:`~cam_workbench.generators.machine.tools.tool_drive`) plus ``centre`` — or None
            (no tool and no linkage).
        tool_angle: (N,) the tool frame's rotation [rad, counter-clockwise], or None.
        tool_outline: (N, V, 2) the tool's outline, closed, or None (no ``[cam.tool]``).
        tool_label: the tool's label ("" when none).
        lift_unit: "length" or "angle".
    """

    name: str
    phase: float
    sense: int
    centre: np.ndarray
    cam_angle: np.ndarray
    lift: np.ndarray
    profile: np.ndarray
    outline: np.ndarray
    bore_radius: float
    mark: np.ndarray
    point: np.ndarray
    roller_radius: float
    segments: np.ndarray
    roles: tuple[str, ...]
    pivot: np.ndarray | None
    joints: dict[str, np.ndarray]
    links: tuple[tuple[str, str], ...]
    tool_point: np.ndarray | None
    tool_angle: np.ndarray | None
    tool_outline: np.ndarray | None
    tool_label: str
    lift_unit: str

    def points_at(self, i: int) -> np.ndarray:
        """Every point drawn for this cam in frame ``i`` (M, 2), roller and bore circles as their
        bounding squares: for bounds."""
        parts = [self.outline[i], self.mark[i], self.segments[i].reshape(-1, 2), self.point[i][None]]
        r = self.roller_radius
        if r > 0:
            parts.append(self.point[i] + np.array([[-r, -r], [r, r]]))
        if self.pivot is not None:
            parts.append(self.pivot[i][None])
        parts.extend(j[i][None] for j in self.joints.values())
        if self.tool_outline is not None:
            parts.append(self.tool_outline[i])
        if self.tool_point is not None:
            parts.append(self.tool_point[i][None])
        return np.concatenate(parts, axis=0)

    def box(self) -> np.ndarray:
        """(xmin, ymin, xmax, ymax) of everything drawn for this cam over all frames."""
        pts = np.concatenate([self.points_at(i) for i in range(self.cam_angle.size)], axis=0)
        return np.concatenate([pts.min(axis=0), pts.max(axis=0)])

    def shifted(self, by: np.ndarray) -> "CamFrames":
        """The same cam moved by ``by`` (2,) in the picture."""
        d = np.asarray(by, dtype=float)
        move = (lambda a: None if a is None else a + d)  # noqa: E731
        return CamFrames(self.name, self.phase, self.sense, self.centre + d, self.cam_angle, self.lift, self.profile,
                         self.outline + d, self.bore_radius, self.mark + d, self.point + d, self.roller_radius,
                         self.segments + d, self.roles, move(self.pivot), {k: v + d for k, v in self.joints.items()},
                         self.links, move(self.tool_point), self.tool_angle, move(self.tool_outline),
                         self.tool_label, self.lift_unit)


@dataclass(frozen=True, eq=False)
class MachineFrames:
    """The whole mechanism at N machine angles (plain data for drawing).

    Attributes:
        name: the machine's name.
        units: the spec length unit ("mm" or "in").
        machine_angle: (N,) the machine angles φ [deg] as given.
        cams: each cam's :class:`CamFrames`, in the machine's cam order.
        bounds: (xmin, ymin, xmax, ymax) of everything drawn over all frames, with a margin of
            5 % of the larger side: fixed axes for every frame.
    """

    name: str
    units: str
    machine_angle: np.ndarray
    cams: tuple[CamFrames, ...]
    bounds: tuple[float, float, float, float]

    def __len__(self) -> int:
        return int(self.machine_angle.size)


# ---- helpers --------------------------------------------------------------------------------
def rotate(points: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """``points`` (..., P, 2) turned counter-clockwise about the origin by ``angle`` (N,) [rad]:
    (N, P, 2) (``points`` (P, 2) broadcast over the angles)."""
    a = np.asarray(angle, dtype=float).reshape(-1)
    c, s = np.cos(a)[:, None], np.sin(a)[:, None]
    x, y = points[..., 0], points[..., 1]
    return np.stack([c * x - s * y, s * x + c * y], axis=-1)


def _xy(z: np.ndarray) -> np.ndarray:
    z = np.asarray(z, dtype=complex)
    return np.stack([z.real, z.imag], axis=-1)


def circle_polygon(radius: float, n: int = CIRCLE_POINTS) -> np.ndarray:
    """A circle of ``radius`` about the origin as a closed polygon (n + 1, 2)."""
    t = np.linspace(0.0, 2.0 * math.pi, n + 1)
    return radius * np.stack([np.cos(t), np.sin(t)], axis=-1)


def tool_polygon(tool: ToolOutline) -> np.ndarray:
    """The ``[cam.tool]`` outline in the tool's frame as a closed polygon (V + 1, 2)."""
    if tool.polygon is not None:
        v = np.asarray(tool.polygon, dtype=float)
        return np.vstack([v, v[:1]])
    return circle_polygon(float(tool.radius or 0.0))


def _slice(k: Kinematics, i: int) -> Kinematics:
    return Kinematics(*(np.asarray(getattr(k, f))[i:i + 1] for f in ("theta", "s", "ds", "d2s", "d3s")))


# ---- one cam ----------------------------------------------------------------------------------
def cam_frames(name: str, design: Any, phase: float, tool: ToolOutline | None, machine_angle_deg: np.ndarray
               ) -> CamFrames:
    """One cam (its ``design``, ``phase`` [deg], ``tool``) at the machine angles ``machine_angle_deg``
    (N,) [deg], its axis at the origin (the module docstring's conventions).

    Raises:
        SpecError: the design has no plane profile (naming ``cam.body``).
    """
    if not design.plane:
        raise SpecError("cam.body", f"{design.spec.cam.body!r} cams are not drawn in motion: the animation draws "
                                    "plane cams (a profile in the cam's plane) "
                                    f"{design.instead_of_plane_curves}".rstrip())
    spec = design.spec
    fol = design.follower
    sense = int(fol.sense)
    phi = np.asarray(machine_angle_deg, dtype=float).reshape(-1)
    x_deg = np.mod(phi - phase, 360.0)
    x = np.deg2rad(x_deg)
    k = design.program.evaluate(x)
    # the cam: its profile turned by δ·x
    _, prof = design.profile.sample(PROFILE_PER_SPAN)
    prof = np.asarray(prof, dtype=float)[:, :2]
    if np.hypot(*(prof[-1] - prof[0])) > 0:
        prof = np.vstack([prof, prof[:1]])
    turn = sense * x
    outline = rotate(prof, turn)
    rb = float(spec.cam.base_radius)
    mark = rotate(np.array([[0.0, 0.0], [0.5 * (rb - fol.profile_offset), 0.0]]), turn)
    # the follower, in the fixed frame: the point vectorised, the sketch's segments frame by frame
    point = _xy(fol.fixed(k, 0)[0])
    lift_len = spec.max_lift * (rb * fol.lift_scale if fol.lift_unit == "angle" else 1.0)
    size = lift_len + 2 * max(fol.profile_offset, 0.1 * rb)
    face = spec.follower.face_width
    sketches = [fol.sketch(0.0, _slice(k, i), size, face) for i in range(x.size)]
    roles = tuple(role for _, _, role in sketches[0].segments)
    segments = np.array([[[[a.real, a.imag], [b.real, b.imag]] for a, b, _ in sk.segments] for sk in sketches],
                        dtype=float).reshape(x.size, len(roles), 2, 2)
    roller = float(sketches[0].circles[0][1]) if sketches[0].circles else 0.0
    pivot = None if sketches[0].pivot is None else _xy(np.array([sk.pivot for sk in sketches]))
    # the linkage and the tool: the tool's poses are the clearance check's (tools.tool_drive)
    q = fol.lift_scale * np.asarray(k.s, dtype=float)
    drive = linkage_of(spec)
    joints: dict[str, np.ndarray] = {}
    links: tuple[tuple[str, str], ...] = ()
    tool_point = tool_angle = None
    if drive is not None:
        linkage = drive.linkage
        if isinstance(linkage, Lever) and fol.lift_unit != "angle":
            m = fol.tool_mount()
            linkage = linkage.on_follower((float(m.origin[0]), float(m.origin[1])), float(m.direction))
        joints = {n: np.asarray(v, dtype=float).reshape(x.size, 2) for n, v in linkage.joints(q).items()}
        links = tuple(pair for pair in LINK_PAIRS if pair[0] in joints and pair[1] in joints)
        if "fulcrum" not in joints and "input" in joints:
            links = (("input", "tool"),)
    if drive is not None or tool is not None:
        poses = tool_drive(name, spec, phase, design.program, tool).poses(x)
        tool_point = np.asarray(poses.positions, dtype=float).reshape(x.size, 2)
        tool_angle = np.zeros(x.size) if poses.angles is None else np.asarray(poses.angles, dtype=float).reshape(-1)
    tool_outline = None
    if tool is not None:
        assert tool_point is not None and tool_angle is not None
        tool_outline = rotate(tool_polygon(tool), tool_angle) + tool_point[:, None, :]
    return CamFrames(name, float(phase), sense, np.zeros(2), x_deg, np.asarray(k.s, dtype=float), prof, outline,
                     float(spec.cam.bore_diameter) / 2.0, mark, point, roller, segments, roles, pivot, joints, links,
                     tool_point, tool_angle, tool_outline, tool.label if tool is not None else "", fol.lift_unit)


# ---- the machine ------------------------------------------------------------------------------
def row_positions(boxes: Sequence[np.ndarray], gap: float = GAP) -> np.ndarray:
    """Axis positions (n, 2) of cams laid out in a row along x on y = 0: each cam's ``box``
    (xmin, ymin, xmax, ymax, about its own axis) ``gap`` × the tallest box's height right of the
    previous one's."""
    b = np.asarray(boxes, dtype=float).reshape(-1, 4)
    space = gap * float(np.max(b[:, 3] - b[:, 1])) if b.size else 0.0
    out = np.zeros((b.shape[0], 2))
    right = 0.0
    for i, (xmin, _, xmax, _) in enumerate(b):
        out[i, 0] = 0.0 if i == 0 else right + space - xmin
        right = out[i, 0] + xmax
    return out


def machine_frames(machine: MachineSpec, designs: Sequence[Any], angles_deg: Any,
                   positions: Sequence[Sequence[float]] | None = None) -> MachineFrames:
    """The whole mechanism at the machine angles ``angles_deg`` (N,) [deg]: every cam of
    ``machine`` (``designs[i]`` its design, e.g. ``design_cam(cam.spec)`` or the pipeline's) turned
    to its cam angle φ − phase, its follower, linkage and tool (see the module docstring).

    ``positions``: each cam's axis (x, y) in the picture [spec length]; default a row along x
    spaced by the cams' sizes (:func:`row_positions`).

    Raises:
        SpecError: ``designs``/``positions`` not one per cam, no angles or non-finite ones, or a cam
            that is not a plane cam (naming ``cam[i].spec.cam.body``).
    """
    n = len(machine.cams)
    if len(designs) != n:
        raise SpecError("designs", f"has {len(designs)} designs, the machine has {n} cams: give one per cam")
    phi = np.asarray(angles_deg, dtype=float).reshape(-1)
    if phi.size == 0 or not np.all(np.isfinite(phi)):
        raise SpecError("angles_deg", "must be one or more finite machine angles [deg]")
    cams = []
    for i, (cam, design) in enumerate(zip(machine.cams, designs)):
        try:
            cams.append(cam_frames(cam.name, design, cam.phase, cam.tool, phi))
        except SpecError as exc:
            raise SpecError(f"cam[{i}].spec.{exc.field}", exc.rule) from None
    if positions is None:
        at = row_positions([c.box() for c in cams])
    else:
        at = np.asarray(positions, dtype=float)
        if at.shape != (n, 2) or not np.all(np.isfinite(at)):
            raise SpecError("positions", f"has shape {at.shape}, must be one finite (x, y) per cam ({n}, 2)")
    placed = tuple(c.shifted(p) for c, p in zip(cams, at))
    boxes = np.array([c.box() for c in placed])
    lo, hi = boxes[:, :2].min(axis=0), boxes[:, 2:].max(axis=0)
    margin = 0.05 * float(np.max(hi - lo))
    bounds = (float(lo[0] - margin), float(lo[1] - margin), float(hi[0] + margin), float(hi[1] + margin))
    return MachineFrames(machine.machine.name, machine.units, phi, placed, bounds)


def turn_angles(step_deg: float = 5.0) -> np.ndarray:
    """Machine angles over one turn [deg]: 0, step, …, 360 − step (``step_deg`` must divide 360)."""
    steps = 360.0 / step_deg
    if not (math.isfinite(steps) and step_deg > 0 and abs(steps - round(steps)) <= 1e-9 * steps):
        raise SpecError("step_deg", f"is {step_deg!r}, must be > 0 and divide 360")
    return np.arange(int(round(steps))) * float(step_deg)


__all__ = ["CIRCLE_POINTS", "CamFrames", "GAP", "LINK_PAIRS", "MachineFrames", "cam_frames", "circle_polygon",
           "machine_frames", "rotate", "row_positions", "tool_polygon", "turn_angles"]

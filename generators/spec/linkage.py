"""The spec's `[linkage]` table: :class:`LinkageSection` — a lever or a four-bar between the
follower and the tool (docs/linkages.md) — its rules (:func:`validate_linkage`: the fields of the
kind, a four-bar that assembles and passes no toggle over the motion's range, naming the cam angle)
and the one place the spec becomes linkage values (:func:`linkage_of`).

``motion_at = "tool"``: the [[motion]] table is the tool's motion (lifts in the follower's lift
unit: mm for a lever on a translating follower, degrees of tool rotation otherwise); the follower's
program is derived through the inverse linkage, exactly (:meth:`LinkageSection.program_of`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import SpecError
from ..kinds import body_of, follower_class_of
from ..linkage import LINKAGES, FourBar, Lever, Linkage
from ..linkage.drive import LinkedProgram, tool_report
from ..motion.program import MotionProgram
from .params import param

if TYPE_CHECKING:  # types only: the spec's root imports this module
    from .model import CamSpec

#: default of linkage.min_transmission_angle [deg] (Norton, Design of Machinery §3.3: 40° or more)
DEFAULT_MIN_TRANSMISSION = 40.0
DEFAULT_MOTION_AT = "follower"


@dataclass(frozen=True, kw_only=True)
class LinkageSection:
    """`[linkage]`: the lever or four-bar from the follower to the tool (absent: none)."""

    kind: str | None = param("The linkage from the follower to the tool: a lever (tool = ratio × follower) or a "
                             "four-bar (the follower's arm is the crank, the tool the output rocker); absent: none",
                             kind="str", choices=tuple(LINKAGES), optional=True, group="Linkage")
    motion_at: str | None = param(
        "Where [[motion]] is given: \"follower\" (the default) or \"tool\" (the follower's motion is derived "
        "through the inverse linkage, exactly)", kind="str", choices=("follower", "tool"), optional=True,
        group="Linkage")
    ratio: float | None = param(
        "Lever: tool = ratio × follower (displacement on a translating follower, rotation on an oscillating one); "
        "negative reverses", optional=True, group="Linkage")
    pivot_x: float | None = param("Lever pivot, or the four-bar's crank pivot O₂: x in the machine plane "
                                  "(default 0)", unit="length", optional=True, group="Linkage")
    pivot_y: float | None = param("Lever pivot, or the four-bar's crank pivot O₂: y in the machine plane "
                                  "(default 0)", unit="length", optional=True, group="Linkage")
    direction: float | None = param(
        "Lever: the tool's line of travel (translating follower) or its arm at zero lift (oscillating), from the "
        "machine x axis, counter-clockwise (default 0)", unit="angle", ge=-360, le=360, optional=True,
        group="Linkage")
    ground: float | None = param("Four-bar: ground link d, from the crank pivot O₂ to the rocker pivot O₄",
                                 unit="length", gt=0, optional=True, group="Linkage")
    frame_angle: float | None = param("Four-bar: direction of the ground link O₂→O₄ from the machine x axis, "
                                      "counter-clockwise (default 0)", unit="angle", ge=-360, le=360, optional=True,
                                      group="Linkage")
    crank: float | None = param("Four-bar: input crank a (O₂ to the coupler joint A), turned by the follower's arm",
                                unit="length", gt=0, optional=True, group="Linkage")
    coupler: float | None = param("Four-bar: coupler b (A to the rocker joint B)", unit="length", gt=0,
                                  optional=True, group="Linkage")
    rocker: float | None = param("Four-bar: output rocker c (O₄ to B); its rotation is the tool's motion",
                                 unit="length", gt=0, optional=True, group="Linkage")
    crank_offset: float | None = param(
        "Four-bar: the crank's angle from the ground link at zero follower lift; the crank turns with the lift "
        "(θ₂ = crank_offset − lift: the crank is the arm, turning clockwise as the follower lifts; default 0)", unit="angle", ge=-360, le=360,
        optional=True, group="Linkage")
    branch: str | None = param(
        "Four-bar: the assembly — the side of the line from O₄ to A on which the rocker joint B lies (\"left\": "
        "counter-clockwise about O₄, the default)", kind="str", choices=("left", "right"), optional=True,
        group="Linkage")
    tool_radius: float | None = param("Four-bar: the tool point's distance from O₄ along the rocker (default: the "
                                      "rocker length, the joint B)", unit="length", gt=0, optional=True,
                                      group="Linkage")
    min_transmission_angle: float | None = param(
        "Four-bar: smallest allowed transmission angle min(μ, 180° − μ) between coupler and rocker "
        f"(default {DEFAULT_MIN_TRANSMISSION:g}°)", unit="angle", gt=0, le=90, optional=True, group="Linkage")

    def program_of(self, spec: CamSpec, program: MotionProgram) -> MotionProgram:
        """The follower's program: ``program`` itself, or with ``motion_at = "tool"`` the program the
        inverse linkage derives from it (``program`` is then the tool's)."""
        drive = linkage_of(spec)
        if drive is None or drive.motion_at != "tool":
            return program
        return LinkedProgram.compose(program, drive.linkage, drive.scale)


#: the fields each kind reads (besides kind, motion_at); the others are refused
KIND_FIELDS: dict[str, tuple[str, ...]] = {
    "lever": ("ratio", "pivot_x", "pivot_y", "direction"),
    "four_bar": ("ground", "frame_angle", "crank", "coupler", "rocker", "crank_offset", "branch", "tool_radius",
                 "pivot_x", "pivot_y", "min_transmission_angle"),
}
REQUIRED_FIELDS: dict[str, tuple[str, ...]] = {"lever": ("ratio",), "four_bar": ("ground", "crank", "coupler", "rocker")}


@dataclass(frozen=True)
class Drive:
    """The spec's linkage as values: the linkage, ``scale`` (program lift unit → linkage unit: π/180
    for degrees, 1 for lengths), where the motion is given, the transmission-angle limit [deg] and
    the lift unit kind ("length" or "angle")."""

    linkage: Linkage
    scale: float
    motion_at: str
    min_transmission_deg: float
    lift_unit: str


def linkage_of(spec: CamSpec) -> Drive | None:
    """The spec's linkage (None without a ``[linkage]`` kind)."""
    t = spec.linkage
    if t.kind is None:
        return None
    fol = follower_class_of(spec)
    deg = math.pi / 180.0
    pivot = (t.pivot_x or 0.0, t.pivot_y or 0.0)
    linkage: Linkage
    if LINKAGES[t.kind] is Lever:
        linkage = Lever(float(t.ratio or 0.0), fol.lift_unit == "angle", pivot, (t.direction or 0.0) * deg)
    else:
        linkage = FourBar(t.ground, t.crank, t.coupler, t.rocker, (t.crank_offset or 0.0) * deg,  # type: ignore[arg-type]
                          1 if (t.branch or "left") == "left" else -1, pivot, (t.frame_angle or 0.0) * deg,
                          t.tool_radius)
    return Drive(linkage, fol.lift_scale, t.motion_at or DEFAULT_MOTION_AT,
                 DEFAULT_MIN_TRANSMISSION if t.min_transmission_angle is None else t.min_transmission_angle,
                 fol.lift_unit)


def validate_linkage(spec: CamSpec) -> None:
    """The [linkage] rules: the fields of its kind; a lever's ratio ≠ 0; a four-bar on an oscillating
    follower that assembles at zero lift and passes no toggle over the motion (SpecError naming the
    field and the cam angle)."""
    t = spec.linkage
    given = [f for f in KIND_FIELDS["four_bar"] + KIND_FIELDS["lever"] + ("motion_at",) if getattr(t, f) is not None]
    if t.kind is None:
        if given:
            raise SpecError(f"linkage.{given[0]}", "needs linkage.kind (\"lever\" or \"four_bar\")")
        return
    for f in given:
        if f != "motion_at" and f not in KIND_FIELDS[t.kind]:
            raise SpecError(f"linkage.{f}", f"is not a field of linkage.kind = {t.kind!r} (its fields: "
                            f"{', '.join(KIND_FIELDS[t.kind])})")
    for f in REQUIRED_FIELDS[t.kind]:
        if getattr(t, f) is None:
            raise SpecError(f"linkage.{f}", f"is required for linkage.kind = {t.kind!r}")
    if t.ratio is not None and t.ratio == 0:
        raise SpecError("linkage.ratio", "must not be 0 (the tool would not move)")
    if LINKAGES[t.kind].angular_input_only and follower_class_of(spec).lift_unit != "angle":
        raise SpecError("linkage.kind", f"{t.kind!r} is driven by the follower's arm: it needs an oscillating "
                        "follower (follower.motion = \"oscillating\"); use a lever on a translating follower")
    if body_of(spec).motion_advance(spec) != 0:
        raise SpecError("linkage.kind", "an indexer's motion is its turret's: it has no follower to drive a linkage")
    drive = linkage_of(spec)
    assert drive is not None
    if isinstance(drive.linkage, FourBar):
        _validate_range(spec, drive.linkage, drive)
    if drive.motion_at == "tool":
        _validate_derived_lift(spec, drive)


def _validate_derived_lift(spec: CamSpec, drive: Drive) -> None:
    """With the motion given at the tool, the follower's derived lift stays ≥ 0 (a follower below its
    zero-lift position would need the cam inside its base circle, or the arm past its rest)."""
    prog = MotionProgram.from_segments(spec.motion)
    th = prog.dense_angles()
    x = drive.scale * prog.evaluate(th).s
    q = drive.linkage.inverse(x, 0 * x, 0 * x, 0 * x)[0] / drive.scale
    low = int(np.argmin(q))
    if q[low] < -1e-9 * max(1.0, float(np.max(np.abs(q)))):
        unit = "°" if drive.lift_unit == "angle" else f" {spec.units}"
        seg = int(prog.segment_of(th[low]))
        raise SpecError(f"motion[{seg}].lift", f"the follower's lift derived from the tool's motion goes below zero "
                        f"(to {q[low]:.6g}{unit}) at cam angle {float(np.rad2deg(th[low]) % 360.0):.3f}°: the tool's "
                        "motion needs the follower below its rest — reverse the tool's motion, or "
                        + ("choose the other linkage.branch" if isinstance(drive.linkage, FourBar)
                           else "change the sign of linkage.ratio"))


def _validate_range(spec: CamSpec, fb: FourBar, drive: Drive) -> None:
    """A four-bar assembles at zero lift and passes no toggle over the motion's range."""
    if not np.isfinite(fb.theta4_ref):
        raise SpecError("linkage.coupler", "the four-bar cannot assemble at zero lift (cam angle 0°): "
                        f"|A − O₄| must lie between |coupler − rocker| and coupler + rocker (crank at "
                        f"{math.degrees(fb.crank_offset):g}° from the ground link)")
    prog = MotionProgram.from_segments(spec.motion)
    th = prog.dense_angles()
    x = drive.scale * prog.evaluate(th).s
    tool = drive.motion_at == "tool"
    toggles = fb.tool_toggles() if tool else fb.toggles()
    unit = "°" if drive.lift_unit == "angle" else f" {spec.units}"
    for tg in toggles:
        side = np.sign(x - tg)
        hit = np.nonzero((side != side[0]) | (side == 0))[0]
        if not hit.size:
            continue
        at = float(np.rad2deg(th[hit[0]]) % 360.0)
        where = f"{tg / drive.scale:.6g}{unit}"
        if tool:
            seg = int(prog.segment_of(th[hit[0]]))
            raise SpecError(f"motion[{seg}].lift", f"the tool would pass the four-bar's limit position (crank and "
                            f"coupler collinear) at cam angle {at:.3f}° (tool at {where}): driven from the tool it "
                            "cannot; a smaller lift, or other linkage lengths")
        raise SpecError("linkage.crank_offset", f"the four-bar passes a toggle (coupler and rocker collinear) at cam "
                        f"angle {at:.3f}° (follower at {where}): it cannot be driven past it; another crank_offset "
                        "or other linkage lengths")
    mapped = fb.inverse(x, 0 * x, 0 * x, 0 * x)[0] if tool else fb.forward(x, 0 * x, 0 * x, 0 * x)[0]
    bad = np.nonzero(~np.isfinite(mapped))[0]
    if bad.size:
        raise SpecError("linkage.coupler", f"the four-bar cannot assemble at cam angle "
                        f"{float(np.rad2deg(th[bad[0]]) % 360.0):.3f}°")


def linkage_report(spec: CamSpec, program: MotionProgram, checks: dict[str, Any] | None = None
                   ) -> dict[str, Any] | None:
    """report.json's ``linkage`` section of the follower's ``program`` (None without a linkage);
    the smallest transmission angle is the ``transmission_angle`` check's own (``checks``: the
    ``checks`` section) so that the two agree."""
    drive = linkage_of(spec)
    if drive is None:
        return None
    out = tool_report(drive.linkage, program, drive.scale, spec.cam.speed_rpm * 2.0 * math.pi / 60.0,
                      drive.motion_at, drive.min_transmission_deg, drive.lift_unit)
    check = ((checks or {}).get("results") or {}).get("transmission_angle")
    if check is not None:
        out["min_transmission_angle_deg"] = check["value"]
        out["min_transmission_angle_at_deg"] = check["at_deg"]
    return out


__all__ = ["LinkageSection", "Drive", "linkage_of", "linkage_report", "validate_linkage", "DEFAULT_MIN_TRANSMISSION"]

"""The machine file: many cams on one camshaft (issue 24, docs/machine.md).

A machine is a TOML file in the cam spec's style::

    [machine]
    name = "three cams"
    speed_rpm = 120.0            # the camshaft's speed
    speed_fluctuation = 0.02     # C_s = (ω_max − ω_min)/ω_mean the flywheel is sized for

    [[cam]]
    name = "pusher"              # its output folder's name
    spec = "pusher.toml"         # a cam spec file, relative to this file — or an inline [cam.spec]
    phase = 0.0                  # deg: the machine angle at which this cam's angle 0 is
    [cam.tool]                   # optional: the tool's outline, for clearances
    label = "push plate"
    circle = { radius = 6.0 }    # or polygon = [[x, y], ...] (spec length units, the tool's frame)
    origin = [0.0, 0.0]          # without a [linkage]: where the follower's point is at zero lift
    direction = 90.0             # deg: its line of travel (or its arm at zero lift)

    [[clearance]]                # optional, repeatable: two tools that share space
    between = ["pusher", "gripper"]
    required = 2.0               # the least distance between their outlines over the turn

:func:`load_machine` reads a file, :func:`machine_from_dict` the TOML structure.  Every rule that
fails raises :class:`~cam_workbench.generators.errors.SpecError` naming the field — a cam spec's
own fields as ``cam[2].spec.cam.speed_rpm`` — and the rule.  Fields are declared once, with
:func:`~cam_workbench.generators.spec.params.param` (unit, default, bounds, one line of doc): the
loader checks against these declarations and docs/machine.md lists them.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib  # type: ignore[no-redef]

from ..errors import SpecError, fmt_apart
from ..kinds import body_of
from ..spec.model import CamSpec
from ..spec.params import REQUIRED, param, params_of
from ..spec.toml_io import MAX_SPEC_BYTES
from .clearance import Polygon

#: a machine file larger than this is refused before it is read (its cams' specs inline)
MAX_MACHINE_BYTES = 16 * MAX_SPEC_BYTES
#: most cams on one camshaft
MAX_CAMS = 64
#: most vertices of a tool's polygon
MAX_POLYGON_POINTS = 10000
#: most [[clearance]] pairs
MAX_CLEARANCES = 256
#: a cam's name: a folder name on every system (letters, digits, ".", "_", "-"; not starting with "." or "-")
NAME_PATTERN = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9._-]{0,63}$")
#: names a cam may not take: the machine's own files in its output folder
RESERVED_NAMES = frozenset({"machine.json", "machine.html", "timing.svg", "timing.png", "torque.svg",
                            "torque.png", "machine.gif", "machine.mp4", ".cam-workbench.json"})


@dataclass(frozen=True, kw_only=True)
class MachineSection:
    """`[machine]`: the camshaft every cam is keyed to."""

    name: str = param("The machine's name (the report's title)", kind="str", group="Machine")
    speed_rpm: float = param("Camshaft speed: every cam turns at it (a cam spec's cam.speed_rpm is absent or "
                             "equal)", unit="speed", gt=0, group="Machine")
    speed_fluctuation: float = param(
        "Coefficient of speed fluctuation C_s = (ω_max − ω_min)/ω_mean the flywheel is sized for",
        gt=0, lt=1, default=0.02, group="Machine")
    grid_step: float = param(
        "Step of the machine-angle grid on which the cams' torques are summed and the timing diagram is "
        "drawn; must divide 360", unit="angle", gt=0, le=5, default=0.5, group="Machine")


@dataclass(frozen=True, kw_only=True)
class CamEntryFields:
    """The scalar fields of one `[[cam]]` entry (its spec and tool are read apart)."""

    name: str = param("The cam's name: its output folder DIR/<name>/ (letters, digits, '.', '_', '-')",
                      kind="str", group="Cam")
    phase: float = param("Machine angle at which this cam's angle 0 is (its program's start)", unit="angle",
                         ge=0, lt=360, default=0.0, group="Cam")


@dataclass(frozen=True)
class ToolOutline:
    """A tool's outline for clearances, in the tool's frame (the spec's length unit): a circle of
    ``radius`` about the tool point, or a closed simple ``polygon`` (vertices, counter-clockwise or
    not); ``origin`` [length] and ``direction`` [deg] place the tool of a cam without a
    ``[linkage]`` in the machine plane (:func:`cam_workbench.generators.machine.tools.tool_drive`;
    both None: the follower's own point; one None: (0, 0) or 90°)."""

    label: str = ""
    radius: float | None = None
    polygon: tuple[tuple[float, float], ...] | None = None
    origin: tuple[float, float] | None = None
    direction: float | None = None

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {"label": self.label}
        if self.radius is not None:
            out["circle"] = {"radius": self.radius}
        if self.polygon is not None:
            out["polygon"] = [list(p) for p in self.polygon]
        if self.origin is not None:
            out["origin"] = list(self.origin)
        if self.direction is not None:
            out["direction"] = self.direction
        return out


@dataclass(frozen=True)
class ClearancePair:
    """`[[clearance]]`: two cams' tools (``a``, ``b``: cam names, B the one a remedy moves) that must
    keep ``required`` [spec length] between their outlines at every machine angle."""

    a: str
    b: str
    required: float

    @property
    def name(self) -> str:
        """"<a>/<b>": the pair's name in machine.json's verdict."""
        return f"{self.a}/{self.b}"

    def to_dict(self) -> dict[str, Any]:
        return {"between": [self.a, self.b], "required": self.required}


@dataclass(frozen=True)
class MachineCam:
    """One cam on the camshaft: its name, validated spec (speed set to the machine's), phase
    [deg], tool outline (or None) and where its spec came from (a file's resolved path, or
    ``inline``)."""

    name: str
    spec: CamSpec
    phase: float = 0.0
    tool: ToolOutline | None = None
    source: str = "inline"

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {"name": self.name, "phase": self.phase, "spec": self.spec.to_dict()}
        if self.tool is not None:
            out["tool"] = self.tool.to_dict()
        return out


@dataclass(frozen=True)
class MachineSpec:
    """A validated machine: the camshaft (:class:`MachineSection`) and its cams, in file order."""

    machine: MachineSection
    cams: tuple[MachineCam, ...] = field(default_factory=tuple)
    clearances: tuple[ClearancePair, ...] = field(default_factory=tuple)

    @property
    def units(self) -> str:
        """The length unit every cam of the machine shares."""
        return self.cams[0].spec.units

    @property
    def omega(self) -> float:
        """Camshaft speed [rad/s]."""
        return self.machine.speed_rpm * 2.0 * math.pi / 60.0

    @property
    def samples(self) -> int:
        """Points of the machine-angle grid over one turn."""
        return int(round(360.0 / self.machine.grid_step))

    def to_dict(self) -> dict[str, Any]:
        """The machine as the TOML structure, every cam's spec inline (what the output's digest is of)."""
        m = {f: getattr(self.machine, f) for f in params_of(MachineSection)}
        out: dict[str, Any] = {"machine": m, "cam": [c.to_dict() for c in self.cams]}
        if self.clearances:
            out["clearance"] = [c.to_dict() for c in self.clearances]
        return out

    def cam(self, name: str) -> MachineCam:
        """The cam named ``name`` (KeyError when none is)."""
        for c in self.cams:
            if c.name == name:
                return c
        raise KeyError(name)


# ---- loading -------------------------------------------------------------------------------
def load_machine(path: str | Path) -> MachineSpec:
    """Read and validate a machine file (cam spec paths relative to its folder).

    Raises:
        SpecError: the file cannot be read, is not TOML, or a rule is broken (naming the field).
    """
    p = Path(path)
    data = _read_toml(p, str(path), MAX_MACHINE_BYTES, "machine file")
    return machine_from_dict(data, base_dir=p.parent)


def machine_from_dict(data: Mapping[str, Any], *, base_dir: str | Path | None = None) -> MachineSpec:
    """Validate the TOML structure of a machine (``base_dir``: the folder spec paths are relative
    to; default the working directory).

    Raises:
        SpecError: naming the field and the rule.
    """
    if not isinstance(data, Mapping):
        raise SpecError("machine file", f"must be a table, got {type(data).__name__}")
    _reject_unknown("", data, {"machine", "cam", "clearance"})
    if "machine" not in data:
        raise SpecError("machine", "section is required")
    machine = _load_fields(MachineSection, data["machine"], "machine")
    steps = 360.0 / machine.grid_step
    if abs(steps - round(steps)) > 1e-9 * steps:
        raise SpecError("machine.grid_step", f"must divide 360 (360/{machine.grid_step:g} = {steps:.6g} is not whole)")
    raw = data.get("cam")
    if raw is None:
        raise SpecError("cam", "a machine needs at least one [[cam]] entry")
    if not isinstance(raw, list) or not raw:
        raise SpecError("cam", "must be a non-empty list of [[cam]] tables")
    if len(raw) > MAX_CAMS:
        raise SpecError("cam", f"at most {MAX_CAMS} cams on one camshaft, got {len(raw)}")
    base = Path(base_dir) if base_dir is not None else Path(".")
    cams: list[MachineCam] = []
    seen: dict[str, int] = {}
    for i, entry in enumerate(raw):
        cam = _load_cam(entry, f"cam[{i}]", machine, base)
        key = cam.name.lower()
        if key in seen:
            raise SpecError(f"cam[{i}].name", f"{cam.name!r} is cam[{seen[key]}]'s name too: each cam needs its own "
                                              "name (its output folder; names differing in case only collide)")
        seen[key] = i
        if cams and cam.spec.units != cams[0].spec.units:
            raise SpecError(f"cam[{i}].spec.units", f"is {cam.spec.units!r}, cam[0]'s is {cams[0].spec.units!r}: "
                                                    "the cams of one machine share their units")
        cams.append(cam)
    return MachineSpec(machine, tuple(cams), _load_clearances(data.get("clearance"), cams))


def _load_clearances(raw: Any, cams: list[MachineCam]) -> tuple[ClearancePair, ...]:
    """The [[clearance]] pairs: each names two different cams that have a [cam.tool] outline, once."""
    if raw is None:
        return ()
    if not isinstance(raw, list):
        raise SpecError("clearance", "must be a list of [[clearance]] tables")
    if len(raw) > MAX_CLEARANCES:
        raise SpecError("clearance", f"at most {MAX_CLEARANCES} pairs, got {len(raw)}")
    by_name = {c.name: c for c in cams}
    out: list[ClearancePair] = []
    seen: dict[frozenset[str], int] = {}
    for k, entry in enumerate(raw):
        path = f"clearance[{k}]"
        if not isinstance(entry, Mapping):
            raise SpecError(path, f"must be a [[clearance]] table, got {type(entry).__name__}")
        _reject_unknown(path, entry, {"between", "required"})
        for key in ("between", "required"):
            if key not in entry:
                raise SpecError(f"{path}.{key}", "is required")
        between = entry["between"]
        if (not isinstance(between, list) or len(between) != 2
                or not all(isinstance(n, str) for n in between)):
            raise SpecError(f"{path}.between", f"must be two cam names, [\"a\", \"b\"], got {between!r}")
        for n in between:
            if n not in by_name:
                raise SpecError(f"{path}.between", f"{n!r} is not a cam of this machine (its cams: "
                                                   f"{', '.join(by_name)})")
            if by_name[n].tool is None:
                raise SpecError(f"{path}.between", f"cam {n!r} has no [cam.tool] outline to keep clear")
            spec = by_name[n].spec
            advance = body_of(spec).motion_advance(spec)
            if advance != 0.0:
                raise SpecError(f"{path}.between", f"cam {n!r} is an indexer (cam.body = {spec.cam.body!r}): its "
                                                   f"turret advances {advance:g}° a turn, so its tool is not back in "
                                                   "its place after one turn and a clearance over the turn is not "
                                                   "defined; keep indexers out of [[clearance]] pairs")
        if between[0] == between[1]:
            raise SpecError(f"{path}.between", f"names {between[0]!r} twice: a pair is two different cams")
        key2 = frozenset(between)
        if key2 in seen:
            raise SpecError(f"{path}.between", f"repeats clearance[{seen[key2]}]'s pair")
        seen[key2] = k
        req = entry["required"]
        if isinstance(req, bool) or not isinstance(req, (int, float)) or not math.isfinite(float(req)) or req < 0:
            raise SpecError(f"{path}.required", f"must be a number >= 0 (spec length unit), got {req!r}")
        out.append(ClearancePair(between[0], between[1], float(req)))
    return tuple(out)


def _load_cam(entry: Any, path: str, machine: MachineSection, base: Path) -> MachineCam:
    if not isinstance(entry, Mapping):
        raise SpecError(path, f"must be a [[cam]] table, got {type(entry).__name__}")
    _reject_unknown(path, entry, {"name", "spec", "phase", "tool"})
    fields = _load_fields(CamEntryFields, {k: v for k, v in entry.items() if k in ("name", "phase")}, path)
    if not NAME_PATTERN.match(fields.name) or fields.name.lower() in RESERVED_NAMES or fields.name in (".", ".."):
        raise SpecError(f"{path}.name", f"{fields.name!r} is not a folder name: letters, digits, '.', '_' and '-', "
                                        "at most 64, not starting with '.' or '-', and not one of the machine's own "
                                        "files")
    if "spec" not in entry:
        raise SpecError(f"{path}.spec", "is required: a cam spec file (relative to the machine file) or an inline "
                                        "[cam.spec] table")
    raw_spec = entry["spec"]
    spec_path = f"{path}.spec"
    if isinstance(raw_spec, str):
        file = base / raw_spec
        spec_data = _read_toml(file, spec_path, MAX_SPEC_BYTES, "cam spec")
        spec_base, source = file.parent, str(file.expanduser().resolve())
    elif isinstance(raw_spec, Mapping):
        spec_data, spec_base, source = raw_spec, base, "inline"
    else:
        raise SpecError(spec_path, f"must be a spec file's path or a [cam.spec] table, got {type(raw_spec).__name__}")
    spec = _cam_spec(spec_data, spec_path, spec_base, machine.speed_rpm)
    tool = _load_tool(entry["tool"], f"{path}.tool") if "tool" in entry else None
    if tool is not None and spec.linkage.kind is not None:
        for key in ("origin", "direction"):
            if getattr(tool, key) is not None:
                raise SpecError(f"{path}.tool.{key}", "the cam's [linkage] places its tool (linkage.pivot_x, "
                                                      "pivot_y, direction, frame_angle): leave it out")
    return MachineCam(fields.name, spec, fields.phase, tool, source)


def _cam_spec(data: Mapping[str, Any], path: str, base: Path, speed_rpm: float) -> CamSpec:
    """The cam's spec at the machine's speed: ``cam.speed_rpm`` absent (set to the machine's) or equal."""
    if not isinstance(data, Mapping):
        raise SpecError(path, f"must be a table of sections, got {type(data).__name__}")
    cam = data.get("cam")
    own = cam.get("speed_rpm") if isinstance(cam, Mapping) else None
    if own is not None:
        ok = isinstance(own, (int, float)) and not isinstance(own, bool) and math.isfinite(float(own))
        if not ok or abs(float(own) - speed_rpm) > 1e-9 * speed_rpm:
            shown = fmt_apart(float(own), speed_rpm) if ok else repr(own)
            raise SpecError(f"{path}.cam.speed_rpm", f"is {shown} rpm, the machine's speed_rpm is "
                                                     f"{fmt_apart(speed_rpm, float(own) if ok else 0.0)}: a cam on the "
                                                     "camshaft turns at the machine's speed (leave it out or make it equal)")
    elif isinstance(cam, Mapping):
        data = {**data, "cam": {**cam, "speed_rpm": speed_rpm}}
    try:
        return CamSpec.from_dict(data, base_dir=base)
    except SpecError as exc:
        raise SpecError(f"{path}.{exc.field}", exc.rule) from None


def _load_tool(raw: Any, path: str) -> ToolOutline:
    if not isinstance(raw, Mapping):
        raise SpecError(path, f"must be a table, got {type(raw).__name__}")
    _reject_unknown(path, raw, {"label", "circle", "polygon", "origin", "direction"})
    label = raw.get("label", "")
    if not isinstance(label, str) or any(ord(c) < 32 for c in label):
        raise SpecError(f"{path}.label", f"must be a line of text, got {label!r}")
    origin = None
    if "origin" in raw:
        o = raw["origin"]
        if (not isinstance(o, list) or len(o) != 2
                or any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v))
                       for v in o)):
            raise SpecError(f"{path}.origin", f"must be an [x, y] pair of numbers (spec length unit), got {o!r}")
        origin = (float(o[0]), float(o[1]))
    direction = None
    if "direction" in raw:
        d = raw["direction"]
        if isinstance(d, bool) or not isinstance(d, (int, float)) or not math.isfinite(float(d)) or abs(d) > 360:
            raise SpecError(f"{path}.direction", f"must be an angle in [-360, 360] degrees, got {d!r}")
        direction = float(d)
    place = {"origin": origin, "direction": direction}
    shapes = [k for k in ("circle", "polygon") if k in raw]
    if len(shapes) != 1:
        raise SpecError(path, "give the outline as circle = {radius = …} or polygon = [[x, y], …] (one of them)")
    if shapes[0] == "circle":
        circle = raw["circle"]
        if not isinstance(circle, Mapping):
            raise SpecError(f"{path}.circle", "must be a table: circle = { radius = 5.0 }")
        _reject_unknown(f"{path}.circle", circle, {"radius"})
        if "radius" not in circle:
            raise SpecError(f"{path}.circle.radius", "is required")
        r = circle["radius"]
        if isinstance(r, bool) or not isinstance(r, (int, float)) or not math.isfinite(float(r)) or r <= 0:
            raise SpecError(f"{path}.circle.radius", f"must be a number > 0, got {r!r}")
        return ToolOutline(label, radius=float(r), **place)
    poly = raw["polygon"]
    where = f"{path}.polygon"
    if not isinstance(poly, list) or not 3 <= len(poly) <= MAX_POLYGON_POINTS:
        raise SpecError(where, f"must be a list of 3 to {MAX_POLYGON_POINTS} [x, y] points")
    pts = []
    for k, row in enumerate(poly):
        if (not isinstance(row, list) or len(row) != 2
                or any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v))
                       for v in row)):
            raise SpecError(f"{where}[{k}]", f"must be an [x, y] pair of numbers, got {row!r}")
        pts.append((float(row[0]), float(row[1])))
    xs = [p[0] for p in pts]
    ys = [p[1] for p in pts]
    area = 0.5 * sum(xs[k] * ys[(k + 1) % len(pts)] - xs[(k + 1) % len(pts)] * ys[k] for k in range(len(pts)))
    size = max(max(xs) - min(xs), max(ys) - min(ys))
    if size == 0.0 or abs(area) <= 1e-12 * size * size:
        raise SpecError(where, "encloses no area: give the outline's corners")
    try:
        Polygon(pts)
    except SpecError as exc:
        raise SpecError(where, exc.rule) from None
    return ToolOutline(label, polygon=tuple(pts), **place)


# ---- helpers -------------------------------------------------------------------------------
def _read_toml(p: Path, where: str, limit: int, what: str) -> dict[str, Any]:
    """A TOML file's structure; every failure a SpecError naming ``where``."""
    try:
        if p.stat().st_size > limit:
            raise SpecError(where, f"{p} is larger than {limit // 1000} kB: not a {what}")
        raw = p.read_bytes()
    except FileNotFoundError:
        raise SpecError(where, f"{p}: file not found") from None
    except IsADirectoryError:
        raise SpecError(where, f"{p} is a folder: name a {what} file") from None
    except OSError as exc:
        raise SpecError(where, f"{p} cannot be read ({exc.strerror})") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SpecError(where, f"{p} is not UTF-8 text (byte {exc.start})") from None
    if "\x00" in text:
        raise SpecError(where, f"{p} holds NUL bytes: not a TOML text")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(where, f"{p} is not valid TOML ({exc})") from None
    except RecursionError:
        raise SpecError(where, f"{p} is nested too deeply to be a {what}") from None


def _reject_unknown(prefix: str, data: Mapping[str, Any], known: set[str]) -> None:
    for key in data:
        if key not in known:
            where = f"{prefix}.{key}" if prefix else str(key)
            raise SpecError(where, f"unknown field (known fields: {', '.join(sorted(known))})")


def _load_fields(cls: type, data: Any, path: str) -> Any:
    """A table's declared fields, each checked against its declaration."""
    if not isinstance(data, Mapping):
        raise SpecError(path, f"must be a table, got {data!r}")
    decl = params_of(cls)
    _reject_unknown(path, data, set(decl))
    values = {}
    for name, p in decl.items():
        if name in data:
            values[name] = p.check(f"{path}.{name}", data[name])
        elif p.default is REQUIRED:
            raise SpecError(f"{path}.{name}", "is required")
    return cls(**values)


__all__ = ["CamEntryFields", "ClearancePair", "MachineCam", "MachineSection", "MachineSpec", "ToolOutline", "load_machine",
           "machine_from_dict"]

"""Which output folder (or file) a run may write into, and what it keeps there.

The rule (docs/cli.md, "Output folders and your files"): no run removes or changes a file it did
not write, unless the user asked.  An output folder may be

* absent or empty;
* a cam-workbench set (its manifest, :data:`MANIFEST`, lists its files), and then

  a. made from the identical spec (the same spec digest): this run's files replace their
     namesakes and the set's other files are kept (they agree with them);
  b. made for the same cam (the same *source*: a spec file's resolved path, ``example:NAME``,
     ``python:<script>``, ``freecad:<document>#<object>``) by a run that writes every file the
     set holds: replaced whole (nothing of the earlier set would be left beside the new files);
  c. anything else: refused, unless the user asks to replace that set (``--replace``,
     ``replace=True``).

A folder holding files that no manifest lists (the user's own) is always refused.  A refusal is a
:class:`~cam_workbench.generators.errors.SpecError` naming how the user named the folder (``-o``), what the
folder holds (command, source, file count, when written, the spec fields that differ) and the way
out; nothing is created or changed.
"""
from __future__ import annotations

import hashlib
import json
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Collection, Mapping

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec import spec_digest

MANIFEST = ".cam-workbench.json"
STAGING_TAG = ".cam-workbench-staging-"
#: the way out of a refusal, after "choose another folder" (an entry point without a replace
#: option, the FreeCAD export, shows the message without it)
REPLACE_HINT = ", or {option} to replace that set"
_SHOWN_FIELDS = 3


@dataclass(frozen=True)
class Claim:
    """What a run writes into an output folder, and how the user named things (for messages).

    Attributes:
        command: the command or function writing ("build", "check", "PlateCam.export", …).
        source: the cam the files are made for: a spec file's resolved path, ``example:NAME``,
            ``python:<script>``, ``freecad:<document>#<object>``, a study's sources; None: unknown.
        digest: the spec digest (:func:`cam_workbench.generators.spec.spec_digest`) or a study's digest.
        spec: the spec (or study) as a dict, recorded so that a refusal can name the fields
            that differ.
        replace: the user asked to replace a cam-workbench set whole.
        option: how the user named the output: "-o" on the command line, the argument's name in
            Python ("folder", "out").
    """

    command: str
    source: str | None = None
    digest: str | None = None
    spec: Mapping[str, Any] | None = None
    replace: bool = False
    option: str = "-o"

    @property
    def replace_option(self) -> str:
        """How the user asks for ``replace``: ``--replace`` on the command line, else ``replace=True``."""
        return "--replace" if self.option.startswith("-") else "replace=True"

    def manifest(self, files: Collection[str], earlier: Mapping[str, Any] | None = None,
                 digest: bool = True) -> dict[str, Any]:
        """The manifest recording ``files``; ``earlier``: the manifest of the set whose files
        this run kept (the identical spec: the set stays that source's, its commands listed
        before this one); ``digest`` False: none recorded (a study's plan, before its entries
        are made)."""
        commands = list(earlier.get("commands") or [earlier.get("command")]) if earlier else []
        commands = [c for c in commands if isinstance(c, str) and c != self.command] + [self.command]
        source = (earlier.get("source") if earlier else None) or self.source
        return {"tool": "cam-workbench", "command": self.command, "commands": commands,
                "source": source, "spec_digest": self.digest if digest else None,
                "spec": dict(self.spec) if self.spec is not None else None,
                "files": sorted(files), "written": time.strftime("%Y-%m-%dT%H:%M:%S%z")}


def read_manifest(folder: str | os.PathLike[str]) -> dict | None:
    """The manifest of an output folder (None when there is none or it is unreadable)."""
    try:
        data = json.loads((Path(folder) / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) and isinstance(data.get("files"), list) else None


def script_source() -> str:
    """The source of a cam made in Python from no file: ``python:<path of __main__>``, or
    ``python`` in an interactive session."""
    main = sys.modules.get("__main__")
    path = main.__dict__.get("__file__") if main is not None else None
    return f"python:{Path(path).resolve()}" if isinstance(path, str) else "python"


def file_source(path: str | os.PathLike[str]) -> str:
    """The source of a cam read from a spec file: its resolved path."""
    return str(Path(path).expanduser().resolve())


def _under_a_file(target: Path, option: str, what: str) -> None:
    for parent in [target, *target.parents]:
        if parent.exists() and not parent.is_dir():
            where = "is a file" if parent == target else f"is under {parent}, which is a file"
            raise SpecError(option, f"{target} {where}: {what}")
        if parent.exists():
            return


def check_output_file(path: str | os.PathLike[str], *, option: str = "-o", digest: str | None = None) -> Path:
    """``path`` if a run may write the file the user named there (atomically; an existing file
    is replaced — the user named it): not a folder, not under a file, and not a file of a
    cam-workbench set made from another spec than ``digest`` (the set would then contradict
    itself).

    Raises:
        SpecError: naming ``option``.
    """
    target = Path(path)
    if target.is_dir():
        raise SpecError(option, f"{target} is a folder: name a file")
    if not target.is_file():
        _under_a_file(target, option, "name a file in a folder")
    folder = target.parent if str(target.parent) else Path(".")
    held = read_manifest(folder) if folder.is_dir() else None
    if held is not None and target.name in held["files"] and (digest is None or held.get("spec_digest") != digest):
        raise SpecError(option, f"{target} is a file of {_describe(held, folder)}, made from another spec: "
                                f"name a file outside {folder}")
    return target


def admit(folder: str | os.PathLike[str], claim: Claim, names: Collection[str] | None = None) -> list[str]:
    """Whether ``claim`` may write the files ``names`` (top-level names; None: not known yet,
    only what is refused whatever they are) into ``folder``; returns the earlier set's files
    that stay beside them (case a of the module's rule), in the manifest's order.

    Raises:
        SpecError: naming ``claim.option``: the folder is a file or under one, holds files that
            no manifest lists, or holds a set this run may not replace (the message says which,
            and the way out).
    """
    target = Path(folder)
    _under_a_file(target, claim.option, "name a folder for the outputs")
    if not target.exists():
        return []
    entries = sorted(p.name for p in target.iterdir() if p.name != MANIFEST and STAGING_TAG not in p.name)
    if not entries:
        return []
    held = read_manifest(target)
    listed = {f.split("/")[0] for f in held["files"]} if held else set()
    foreign = [e for e in entries if e not in listed]
    if foreign or held is None:
        shown = ", ".join(foreign[:5]) + (f" and {len(foreign) - 5} more" if len(foreign) > 5 else "")
        raise SpecError(claim.option, f"{target} holds files that are not a cam-workbench output ({shown}); "
                                      "choose an empty or new folder")
    if claim.replace:
        return []
    present = [f for f in held["files"] if (target / f).exists()]
    new = set(names) if names is not None else set()
    if claim.digest is not None and held.get("spec_digest") == claim.digest:
        return [f for f in present if f.split("/")[0] not in new]
    way_out = "choose another folder" + REPLACE_HINT.format(option=claim.replace_option)
    if claim.source is not None and held.get("source") == claim.source:
        if names is None:
            return []                   # decided when the files are known (nothing kept then)
        left = [f for f in present if f.split("/")[0] not in new]
        if not left:
            return []
        diff = _differences(held, claim.spec)
        raise SpecError(claim.option, f"{target} holds {_describe(held, None)}, made from another spec"
                                      + (f" ({diff})" if diff else "")
                                      + f"; this run writes {len(present) - len(left)} of its files and would leave "
                                        f"{len(left)} that do not match ({_names(left)}): {way_out}")
    diff = _differences(held, claim.spec)
    raise SpecError(claim.option, f"{target} holds another cam's set: {_describe(held, None)}"
                                  + (f"; its spec differs from this one in {diff}" if diff else "") + f": {way_out}")


def _names(files: list[str]) -> str:
    return ", ".join(files[:3]) + (f" and {len(files) - 3} more" if len(files) > 3 else "")


def _describe(held: Mapping[str, Any], folder: Path | None) -> str:
    """"the set `build` wrote for example:paper (15 files, 2025-01-02T10:00:00+0000)"."""
    commands = held.get("commands") or [held.get("command") or "an earlier version"]
    who = ", ".join(f"`{c}`" for c in commands if isinstance(c, str)) or "cam-workbench"
    source = held.get("source")
    n = len(held["files"])
    when = held.get("written")
    return (f"the set {who} wrote" + (f" in {folder}" if folder is not None else "")
            + (f" for {source}" if source else "")
            + f" ({n} file{'s' if n != 1 else ''}" + (f", {when}" if when else "") + ")")


def _differences(held: Mapping[str, Any], spec: Mapping[str, Any] | None) -> str:
    """"cam.thickness 10 → 13, …": the fields where the spec the manifest records differs from
    ``spec`` (empty when either is unknown)."""
    old = held.get("spec")
    if not isinstance(old, Mapping) or spec is None:
        return ""
    shared = set(old) & set(spec)          # a cam's spec and a study's definition share no section
    a = _flat({k: v for k, v in old.items() if k in shared})
    b = _flat({k: v for k, v in spec.items() if k in shared})
    diff = [f"{k} {_show(a.get(k))} → {_show(b.get(k))}" for k in sorted(set(a) | set(b), key=_order(a, b))
            if a.get(k, _ABSENT) != b.get(k, _ABSENT)]
    if not diff:
        return ""
    more = f" and {len(diff) - _SHOWN_FIELDS} more" if len(diff) > _SHOWN_FIELDS else ""
    return f"{', '.join(diff[:_SHOWN_FIELDS])}{more}"


_ABSENT = object()


def _order(a: Mapping[str, Any], b: Mapping[str, Any]) -> Any:
    keys = list(a) + [k for k in b if k not in a]
    pos = {k: i for i, k in enumerate(keys)}
    return lambda k: pos[k]


def _flat(data: Any, prefix: str = "") -> dict[str, Any]:
    """A nested dict/list as dotted fields, the way ``--set`` names them (``motion[1].lift``)."""
    out: dict[str, Any] = {}
    if isinstance(data, Mapping):
        for k, v in data.items():
            out.update(_flat(v, f"{prefix}.{k}" if prefix else str(k)))
    elif isinstance(data, list) and any(isinstance(v, (Mapping, list)) for v in data):
        for i, v in enumerate(data):
            out.update(_flat(v, f"{prefix}[{i}]"))
    else:
        out[prefix] = data
    return out


def _show(v: Any) -> str:
    """A value as the user wrote it, every digit kept (10.0 → "10", 0.1 + 0.2 → "0.30000000000000004")."""
    if v is None:
        return "(none)"
    if isinstance(v, float) and v.is_integer():
        return str(int(v))
    if isinstance(v, (str, list)):
        return json.dumps(v, ensure_ascii=False)
    return repr(v) if isinstance(v, float) else str(v)


def spec_claim(spec: Any, command: str, source: str | None, *, replace: bool = False, option: str = "-o") -> Claim:
    """The claim of a run writing the files of one cam made from ``spec`` (a CamSpec)."""
    return Claim(command, source, spec_digest(spec), spec.to_dict(), replace, option)


def study_digest(definition: Mapping[str, Any]) -> str:
    """SHA-256 of a study's definition (JSON, keys sorted): names the study a folder was made by."""
    return hashlib.sha256(json.dumps(definition, sort_keys=True, default=str).encode("utf-8")).hexdigest()

"""The spec as TOML text: :func:`load_spec` (a file, TOML text or a dict), the writer
(:func:`to_toml`, :func:`dict_to_toml`) and :func:`spec_digest`, the hash that names the cam a report
was made from.
"""
from __future__ import annotations

import hashlib
import math
from pathlib import Path
from typing import Any, Mapping

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib  # type: ignore[no-redef]

from ..errors import SpecError
from .model import CamSpec


# ---- loading ---------------------------------------------------------------------
def load_spec(source: str | Path | Mapping[str, Any]) -> CamSpec:
    """Load a spec from a TOML file path, TOML text, or a dict.

    Raises:
        SpecError: a rule is broken; the message names the field and the rule.
    """
    if isinstance(source, Mapping):
        return CamSpec.from_dict(source)
    text: str
    p = Path(source) if not (isinstance(source, str) and "\n" in source) else None
    if p is not None:
        try:
            if p.stat().st_size > MAX_SPEC_BYTES:
                raise SpecError(str(source), f"is larger than {MAX_SPEC_BYTES // 1000} kB: not a cam spec")
            raw = p.read_bytes()
        except FileNotFoundError:
            raise SpecError(str(source), "file not found") from None
        except OSError as exc:
            raise SpecError(str(source), f"cannot be read ({exc.strerror})") from None
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise SpecError(str(source), f"is not UTF-8 text (byte {exc.start}): a TOML spec is UTF-8") from None
    else:
        text = str(source)
    where = str(p) if p else "spec"
    if "\x00" in text:
        raise SpecError(where, "holds NUL bytes: not a TOML text")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(where, f"is not valid TOML ({exc})") from None
    except RecursionError:
        raise SpecError(where, "is nested too deeply to be a cam spec") from None
    return CamSpec.from_dict(data, base_dir=p.parent if p is not None else None)


#: A spec file larger than this is refused before it is read.
MAX_SPEC_BYTES = 1_000_000


def to_toml(spec: CamSpec) -> str:
    """Serialise a spec as TOML text (readable by :func:`load_spec`)."""
    return dict_to_toml(spec.to_dict())


def dict_to_toml(data: Mapping[str, Any]) -> str:
    """A small TOML writer for the spec's structure: scalars, lists, tables, arrays of tables."""
    lines: list[str] = []
    scalars = {k: v for k, v in data.items() if not isinstance(v, (Mapping, list)) or
               (isinstance(v, list) and not (v and isinstance(v[0], Mapping)))}
    for k, v in scalars.items():
        lines.append(f"{k} = {_toml_value(v)}")
    for k, v in data.items():
        if k in scalars:
            continue
        if isinstance(v, Mapping):
            lines.append("")
            lines.append(f"[{k}]")
            lines.extend(_toml_table_body(v, k))
        else:
            for item in v:
                lines.append("")
                lines.append(f"[[{k}]]")
                lines.extend(_toml_table_body(item, k))
    return "\n".join(lines).lstrip("\n") + "\n"


def _toml_table_body(table: Mapping[str, Any], prefix: str) -> list[str]:
    out, subs = [], []
    for k, v in table.items():
        if isinstance(v, Mapping):
            subs.append((k, v))
        else:
            out.append(f"{k} = {_toml_value(v)}")
    for k, v in subs:
        out.append("")
        out.append(f"[{prefix}.{k}]")
        out.extend(_toml_table_body(v, f"{prefix}.{k}"))
    return out


def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v) if math.isfinite(v) else ("inf" if v > 0 else "-inf" if v < 0 else "nan")
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {v!r} as TOML")


def spec_digest(spec: CamSpec) -> str:
    """SHA-256 of the spec's canonical TOML without ``[checks]``, ``[optimise]``, ``[dynamics]`` and
    ``[ecam]`` (how to check, optimise, analyse or export, not what):
    names the cam a report was made from."""
    data = spec.to_dict()
    for how in ("checks", "optimise", "dynamics", "ecam"):
        data.pop(how, None)
    return hashlib.sha256(dict_to_toml(data).encode("utf-8")).hexdigest()

"""The golden test's one table of names: what a deliberate rename may change in the recorded
outputs, what changes from run to run, and where the recorder finds the project.

The restructuring of issue 21 moves every module and renames the public class; when it renames
something a user sees *on purpose*, it edits :data:`RENAMED` (and :data:`WHERE` when a module
the recorder imports moves) — nothing else in ``tests/golden`` or ``tests/test_golden.py``.

Both sides of a comparison, the recorded text and the new one, go through :func:`normalise`:
first :data:`RENAMED` (old name → new name: a new output that already says the new name is left
as it is), then :data:`VOLATILE` (dates, times, versions, temporary folders → a placeholder).
"""
from __future__ import annotations

import re

#: Names a user sees that the restructuring renames on purpose: (regular expression of the old
#: name, the new name).  Applied to every string of both the recording and the new outputs.
RENAMED: tuple[tuple[str, str], ...] = (
    # the import names: one top-level package, cam_workbench (issue 21, item 1)
    (r"(?<![\w.])generators\.", "cam_workbench.generators."),
    (r"(?<![\w.])exporters\.", "cam_workbench.exporters."),
    # the public class of every body (item 2; PlateCam stays as an alias)
    (r"\bPlateCam\b", "Cam"),
    # the FreeCAD workbench's name, "Plate Cam" → "Cam Workbench" (item 2: "a name that fits every
    # body"; `cam-workbench freecad install` says it)
    (r"\bPlate Cam\b", "Cam Workbench"),
)

#: What differs from run to run or from release to release: (regular expression, placeholder).
VOLATILE: tuple[tuple[str, str], ...] = (
    # ISO dates and times (2025-11-27T05:22:10.123+00:00, 2025-11-27 05:22)
    (r"\b\d{4}-\d{2}-\d{2}(?:[T ]\d{2}:\d{2}(?::\d{2}(?:\.\d+)?)?(?:Z|[+-]\d{2}:?\d{2})?)?\b", "<date>"),
    # the program's version where it names itself (G-code header, DXF title block, --version)
    (r"\b(cam[_-]workbench)(,? v?)\d+(?:\.\d+)+(?:[.+-]?(?:dev|a|b|rc|post)\d*)*(?:\+[\w.]+)?", r"\1\2<version>"),
)

#: The recorder's temporary folder, as it appears in the outputs (paths printed by the CLI):
#: replaced by this before anything is stored or compared (:func:`without_tmp`).
TMP = "<tmp>"

#: Where the recorder finds the project: the command line (run as ``python -m``), the loaders of
#: its commands' modules (the server preloads them, cli_server.py), the public class, the OCP
#: adaptor (the one module that imports OCP, tests/test_layering.py) and the spec module's lists
#: of the built-in examples and of the e-cam formats' tables.
WHERE: dict[str, str] = {
    "cli": "cam_workbench.cli",
    "commands": "cam_workbench.commands.dispatch:RUNNERS",
    "api": "cam_workbench:Cam",
    "ocp": "cam_workbench.kernel.ocp",
    "examples": "cam_workbench.generators.spec.examples:EXAMPLES",
    "ecam_tables": "cam_workbench.generators.spec:ECAM_TABLES",
}

_RENAMED = tuple((re.compile(p), r) for p, r in RENAMED)
_VOLATILE = tuple((re.compile(p), r) for p, r in VOLATILE)


def normalise(text: str) -> str:
    """``text`` with the renamed names in their new spelling and the volatile parts replaced."""
    for pattern, new in _RENAMED:
        text = pattern.sub(new, text)
    for pattern, placeholder in _VOLATILE:
        text = pattern.sub(placeholder, text)
    return text


def without_tmp(text: str, *folders: str) -> str:
    """``text`` with each of ``folders`` (the run's temporary folder, as given and resolved)
    replaced by :data:`TMP` — longest first, so a resolved path inside a given one goes whole."""
    for folder in sorted({f for f in folders if f}, key=len, reverse=True):
        text = text.replace(folder, TMP)
    return text


def where(key: str) -> object:
    """The object :data:`WHERE` names: ``"module"`` or ``"module:attribute"``."""
    import importlib

    module, _, attr = WHERE[key].partition(":")
    obj = importlib.import_module(module)
    return getattr(obj, attr) if attr else obj

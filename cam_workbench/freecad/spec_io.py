"""The feature's spec as a TOML file (for the ``cam-workbench`` CLI and the Python API)."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import FreeCAD

from cam_workbench.exporters.atomic import write_text_atomic
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec import load_spec, to_toml

from . import properties as props
from .feature import create


def export_spec(obj: Any, path: str | os.PathLike[str]) -> Path:
    """Write the feature's (validated) spec as TOML, atomically.

    Raises:
        SpecError: a property breaks a rule (nothing is written).
    """
    return write_text_atomic(path, to_toml(props.spec_of(obj)))


# ---- FreeCAD import hooks (registered by Init.py: File > Open / Import of a *.toml spec; in the
# GUI through :mod:`.spec_io_gui`, which registers the view providers first) ----
def open(filename: str) -> Any:  # noqa: A001 - FreeCAD's importer protocol
    """Open a spec file as a new document holding one cam (no document on a bad spec)."""
    try:
        load_spec(filename)
    except SpecError as exc:
        FreeCAD.Console.PrintError(f"{filename}: {exc}\n")
        return None
    name = "".join(c if c.isalnum() else "_" for c in Path(filename).stem) or "Cam"
    doc = FreeCAD.newDocument(name)
    return insert(filename, doc.Name)


def insert(filename: str, docname: str) -> Any:
    """Add a cam built from a spec file to the document ``docname`` ("" — as
    ``FreeCAD.loadFile(path)`` passes it — the active document, else a new one)."""
    if not docname:
        doc = FreeCAD.ActiveDocument or FreeCAD.newDocument(
            "".join(c if c.isalnum() else "_" for c in Path(filename).stem) or "Cam")
    else:
        doc = FreeCAD.getDocument(docname)
    try:
        obj = create(doc, Path(filename))
    except SpecError as exc:
        FreeCAD.Console.PrintError(f"{filename}: {exc}\n")
        return None
    doc.recompute()
    return obj

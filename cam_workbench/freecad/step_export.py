"""Export STEP from FreeCAD: the cam solid through FreeCAD's own ``Part`` (never OCP).

The file is written atomically (temporary file beside the target, then rename —
``cam_workbench.exporters.atomic``): an error leaves no half-written or clobbered file.  Lengths are
FreeCAD's millimetres, whatever the spec's ``Units``.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import FreeCAD

from cam_workbench.exporters.atomic import atomic_path


def export_step(obj: Any, path: str | os.PathLike[str]) -> Path:
    """Write ``obj``'s solid (with its placement) as STEP.

    Raises:
        ValueError: the object has no valid solid to export.
    """
    shape = obj.Shape
    if shape.isNull() or not shape.Solids:
        raise ValueError(f"{obj.Label} has no solid to export (recompute it first)")
    if not shape.isValid():
        raise ValueError(f"{obj.Label}: FreeCAD reports its solid as invalid; not exported")
    with atomic_path(path) as tmp:
        shape.exportStep(str(tmp))
        if tmp.stat().st_size == 0:
            raise RuntimeError("FreeCAD wrote an empty STEP file")
    return Path(path)


def export_step_dialog(obj: Any) -> Path | None:
    """Ask for a file name and export; report the result in the report view."""
    import FreeCADGui  # deferred: FreeCADGui (the dialog only; this module is App side)
    from PySide import QtGui  # deferred: PySide (the dialog only)

    start = os.path.join(os.path.dirname(obj.Document.FileName or "") or os.getcwd(), f"{obj.Label}.step")
    name, _filt = QtGui.QFileDialog.getSaveFileName(FreeCADGui.getMainWindow(), "Export STEP", start,
                                                    "STEP (*.step *.stp)")
    if not name:
        return None
    if not name.lower().endswith((".step", ".stp")):
        name += ".step"
    try:
        out = export_step(obj, name)
    except (ValueError, OSError, RuntimeError) as exc:
        FreeCAD.Console.PrintError(f"{obj.Label}: STEP export failed: {exc}\n")
        QtGui.QMessageBox.warning(FreeCADGui.getMainWindow(), "Export STEP", str(exc))
        return None
    FreeCAD.Console.PrintMessage(f"{obj.Label}: STEP written to {out}\n")
    return out

"""STEP export of a solid through OCP (OCCT's STEPControl_Writer), atomically.

The model's numbers are in the spec's units; the file declares the same unit, so
a CAD system reading it gets the right size (an inch cam stays 2.5 in, not 2.5 mm).

Every OCP name comes from the OCP adaptor :mod:`cam_workbench.kernel.ocp` (the one module of
``cam_workbench`` that ``exporters`` may import: it imports no other project module), imported
when a function runs, so that the DXF and G-code exporters never need OCP.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from cam_workbench.exporters.atomic import atomic_path

_OCC_UNIT = {"mm": "MM", "in": "INCH"}


def _topods(shape: Any) -> Any:
    """Accept a TopoDS_Shape, a cadquery Shape/Workplane or a build123d shape."""
    if hasattr(shape, "val") and callable(shape.val):  # cq.Workplane
        shape = shape.val()
    return getattr(shape, "wrapped", shape)


def write_step(shape: Any, path: str | os.PathLike[str], units: str = "mm",
               product_name: str = "plate cam") -> None:
    """Write ``shape`` to ``path`` (not atomic; see :func:`export_step`)."""
    from cam_workbench.kernel import ocp as occ

    occ.require("STEP export")
    if units not in _OCC_UNIT:
        raise ValueError(f"units must be 'mm' or 'in', got {units!r}")
    if has_offset_curves(_topods(shape)):
        raise ValueError("the shape has offset-curve edges, which OCCT's STEP writer cannot map "
                         "(it silently writes an empty model): export a B-spline approximation")
    _set_static({"xstep.cascade.unit": _OCC_UNIT[units], "write.step.unit": _OCC_UNIT[units],
                 "write.step.schema": "AP214IS", "write.step.product.name": product_name})
    _quiet_occt()
    writer = occ.STEPControl_Writer()
    status = writer.Transfer(_topods(shape), occ.STEPControl_AsIs)
    if status != occ.IFSelect_RetDone:
        raise RuntimeError("OCCT could not transfer the shape to STEP")
    if writer.Write(str(path)) != occ.IFSelect_RetDone:
        raise OSError(f"OCCT could not write {path}")
    occ.static_set("xstep.cascade.unit", "MM")


def _set_static(values: dict[str, str]) -> None:
    """Set OCCT's STEP translator parameters, after making sure they exist: in a fresh process
    they are declared only when the STEP controller is initialised (the first writer or reader
    does it) — set before that, OCCT refuses them and the file silently declares millimetres.

    Raises:
        RuntimeError: OCCT refuses a value (the file would not say what it holds)."""
    from cam_workbench.kernel import ocp as occ

    occ.init_step()
    for name, value in values.items():
        if not occ.static_set(name, value) or occ.static_get(name) != value:
            raise RuntimeError(f"OCCT refused the STEP parameter {name} = {value!r}")


def has_offset_curves(shape: Any) -> bool:
    """True when an edge of ``shape`` lies on an offset curve (``GeomAbs_OffsetCurve``)."""
    from cam_workbench.kernel import ocp as occ

    ex = occ.TopExp_Explorer(shape, occ.TopAbs_EDGE)
    while ex.More():
        if occ.BRepAdaptor_Curve(occ.topods_edge(ex.Current())).GetType() == occ.GeomAbs_OffsetCurve:
            return True
        ex.Next()
    return False


def _quiet_occt() -> None:
    """Stop OCCT's translators printing transfer statistics on stdout."""
    from cam_workbench.kernel import ocp as occ

    for printer in occ.message_printers():
        printer.SetTraceLevel(occ.Message_Gravity.Message_Fail)


def export_step(shape: Any, path: str | os.PathLike[str], units: str = "mm") -> Path:
    """Write ``shape`` as STEP (AP214) to ``path`` atomically, declaring ``units`` ("mm"/"in")."""
    with atomic_path(path) as tmp:
        write_step(shape, tmp, units)
    return Path(path)


def read_step(path: str | os.PathLike[str], units: str = "mm") -> Any:
    """Read a STEP file into one TopoDS_Shape, converted to ``units`` (for checks and tests)."""
    from cam_workbench.kernel import ocp as occ

    occ.require("reading STEP")
    _set_static({"xstep.cascade.unit": _OCC_UNIT[units]})
    _quiet_occt()
    reader = occ.STEPControl_Reader()
    try:
        if reader.ReadFile(str(path)) != occ.IFSelect_RetDone:
            raise OSError(f"cannot read STEP file {path}")
        reader.TransferRoots()
        return reader.OneShape()
    finally:
        occ.static_set("xstep.cascade.unit", "MM")

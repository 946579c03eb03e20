"""STEP through OCP (OCCT's STEPControl_Writer and Reader): a solid written under a product name,
a file read back.

The model's numbers are in the spec's units; the file declares the same unit, so
a CAD system reading it gets the right size (an inch cam stays 2.5 in, not 2.5 mm).

Every OCP name comes from the OCP adaptor :mod:`cam_workbench.kernel.ocp`, which resolves it
when a function first uses it: importing this module loads no OCP.  The atomic file output is
the exporters' (:func:`cam_workbench.exporters.step.export_step`).
"""
from __future__ import annotations

import os
from typing import Any

from . import ocp as occ

_OCC_UNIT = {"mm": "MM", "in": "INCH"}


def _topods(shape: Any) -> Any:
    """Accept a TopoDS_Shape, a cadquery Shape/Workplane or a build123d shape."""
    if hasattr(shape, "val") and callable(shape.val):  # cq.Workplane
        shape = shape.val()
    return getattr(shape, "wrapped", shape)


def write_step(shape: Any, path: str | os.PathLike[str], units: str = "mm", product_name: str = "cam") -> None:
    """Write ``shape`` to ``path`` as STEP (AP214) declaring ``units`` ("mm"/"in"); ``product_name``
    names the product a CAD system shows (the body's name: "Plate cam", "Groove cam", …).  Not
    atomic: :func:`cam_workbench.exporters.step.export_step` is."""
    occ.require("STEP export")
    if units not in _OCC_UNIT:
        raise ValueError(f"units must be 'mm' or 'in', got {units!r}")
    if has_offset_curves(_topods(shape)):
        raise ValueError("the shape has offset-curve edges, which OCCT's STEP writer cannot map "
                         "(it silently writes an empty model): export a B-spline approximation")
    _set_static({"xstep.cascade.unit": _OCC_UNIT[units], "write.step.unit": _OCC_UNIT[units],
                 "write.step.schema": "AP214IS"})
    _quiet_occt()
    writer = occ.STEPControl_Writer()
    status = writer.Transfer(_topods(shape), occ.STEPControl_AsIs)
    if status != occ.IFSelect_RetDone:
        raise RuntimeError("OCCT could not transfer the shape to STEP")
    _name_products(writer.Model(), product_name)
    if writer.Write(str(path)) != occ.IFSelect_RetDone:
        raise OSError(f"OCCT could not write {path}")
    occ.static_set("xstep.cascade.unit", "MM")


def _name_products(model: Any, name: str) -> None:
    """Give every PRODUCT of the STEP model ``name`` as its id and name (OCCT's own is its
    translator's name, or ``write.step.product.name`` with a counter appended: "name 1")."""
    text = occ.TCollection_HAsciiString(name)
    for i in range(1, model.NbEntities() + 1):
        entity = model.Value(i)
        if isinstance(entity, occ.StepBasic_Product):
            entity.SetId(text)
            entity.SetName(text)


def _set_static(values: dict[str, str]) -> None:
    """Set OCCT's STEP translator parameters, after making sure they exist: in a fresh process
    they are declared only when the STEP controller is initialised (the first writer or reader
    does it) — set before that, OCCT refuses them and the file silently declares millimetres.

    Raises:
        RuntimeError: OCCT refuses a value (the file would not say what it holds)."""
    occ.init_step()
    for name, value in values.items():
        if not occ.static_set(name, value) or occ.static_get(name) != value:
            raise RuntimeError(f"OCCT refused the STEP parameter {name} = {value!r}")


def has_offset_curves(shape: Any) -> bool:
    """True when an edge of ``shape`` lies on an offset curve (``GeomAbs_OffsetCurve``)."""
    ex = occ.TopExp_Explorer(shape, occ.TopAbs_EDGE)
    while ex.More():
        if occ.BRepAdaptor_Curve(occ.topods_edge(ex.Current())).GetType() == occ.GeomAbs_OffsetCurve:
            return True
        ex.Next()
    return False


def _quiet_occt() -> None:
    """Stop OCCT's translators printing transfer statistics on stdout."""
    for printer in occ.message_printers():
        printer.SetTraceLevel(occ.Message_Gravity.Message_Fail)


def read_step(path: str | os.PathLike[str], units: str = "mm") -> Any:
    """Read a STEP file into one TopoDS_Shape, converted to ``units`` (for checks and tests)."""
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

"""STEP export of a solid through OCP (OCCT's STEPControl_Writer), atomically.

The model's numbers are in the spec's units; the file declares the same unit, so
a CAD system reading it gets the right size (an inch cam stays 2.5 in, not 2.5 mm).
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from .atomic import atomic_path

_OCC_UNIT = {"mm": "MM", "in": "INCH"}


def _topods(shape: Any) -> Any:
    """Accept a TopoDS_Shape, a cadquery Shape/Workplane or a build123d shape."""
    if hasattr(shape, "val") and callable(shape.val):  # cq.Workplane
        shape = shape.val()
    return getattr(shape, "wrapped", shape)


def write_step(shape: Any, path: str | os.PathLike[str], units: str = "mm",
               product_name: str = "plate cam") -> None:
    """Write ``shape`` to ``path`` (not atomic; see :func:`export_step`)."""
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.Interface import Interface_Static
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

    if units not in _OCC_UNIT:
        raise ValueError(f"units must be 'mm' or 'in', got {units!r}")
    if has_offset_curves(_topods(shape)):
        raise ValueError("the shape has offset-curve edges, which OCCT's STEP writer cannot map "
                         "(it silently writes an empty model): export a B-spline approximation")
    _set_static({"xstep.cascade.unit": _OCC_UNIT[units], "write.step.unit": _OCC_UNIT[units],
                 "write.step.schema": "AP214IS", "write.step.product.name": product_name})
    _quiet_occt()
    writer = STEPControl_Writer()
    status = writer.Transfer(_topods(shape), STEPControl_AsIs)
    if status != IFSelect_RetDone:
        raise RuntimeError("OCCT could not transfer the shape to STEP")
    if writer.Write(str(path)) != IFSelect_RetDone:
        raise OSError(f"OCCT could not write {path}")
    Interface_Static.SetCVal_s("xstep.cascade.unit", "MM")


def _set_static(values: dict[str, str]) -> None:
    """Set OCCT's STEP translator parameters, after making sure they exist: in a fresh process
    they are declared only when the STEP controller is initialised (the first writer or reader
    does it) — set before that, OCCT refuses them and the file silently declares millimetres.

    Raises:
        RuntimeError: OCCT refuses a value (the file would not say what it holds)."""
    from OCP.Interface import Interface_Static
    from OCP.STEPControl import STEPControl_Controller

    STEPControl_Controller.Init_s()
    for name, value in values.items():
        if not Interface_Static.SetCVal_s(name, value) or Interface_Static.CVal_s(name) != value:
            raise RuntimeError(f"OCCT refused the STEP parameter {name} = {value!r}")


def has_offset_curves(shape: Any) -> bool:
    """True when an edge of ``shape`` lies on an offset curve (``GeomAbs_OffsetCurve``)."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.GeomAbs import GeomAbs_OffsetCurve
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    ex = TopExp_Explorer(shape, TopAbs_EDGE)
    while ex.More():
        if BRepAdaptor_Curve(TopoDS.Edge_s(ex.Current())).GetType() == GeomAbs_OffsetCurve:
            return True
        ex.Next()
    return False


def _quiet_occt() -> None:
    """Stop OCCT's translators printing transfer statistics on stdout."""
    from OCP.Message import Message, Message_Gravity

    for printer in Message.DefaultMessenger_s().Printers():
        printer.SetTraceLevel(Message_Gravity.Message_Fail)


def export_step(shape: Any, path: str | os.PathLike[str], units: str = "mm") -> Path:
    """Write ``shape`` as STEP (AP214) to ``path`` atomically, declaring ``units`` ("mm"/"in")."""
    with atomic_path(path) as tmp:
        write_step(shape, tmp, units)
    return Path(path)


def read_step(path: str | os.PathLike[str], units: str = "mm") -> Any:
    """Read a STEP file into one TopoDS_Shape, converted to ``units`` (for checks and tests)."""
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.Interface import Interface_Static
    from OCP.STEPControl import STEPControl_Reader

    _set_static({"xstep.cascade.unit": _OCC_UNIT[units]})
    _quiet_occt()
    reader = STEPControl_Reader()
    try:
        if reader.ReadFile(str(path)) != IFSelect_RetDone:
            raise OSError(f"cannot read STEP file {path}")
        reader.TransferRoots()
        return reader.OneShape()
    finally:
        Interface_Static.SetCVal_s("xstep.cascade.unit", "MM")

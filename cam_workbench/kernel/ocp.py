"""The OCP adaptor: the one module that imports OCP (OpenCascade's Python bindings), and the
only one that knows that OCP's versions differ.

Every OCP class, enum and static method the project uses is taken from here, by a name that is
the same for every supported OCP:

    from cam_workbench.kernel import ocp as occ
    occ.require("cam-workbench build")         # MissingDependency naming the extras, when absent
    poles = occ.pnt_array([occ.gp_Pnt(x, y, 0) for x, y in xy])
    curve = occ.Geom_BSplineCurve(poles, occ.real_array(w), …)
    occ.volume_properties(solid, props)

Supported: OCP 7.9 (``cadquery-ocp`` / ``cadquery-ocp-novtk`` 7.9.3: CadQuery 2.8, build123d
0.12) and OCP 8.0 (``cadquery-ocp-novtk`` 8.0.1: build123d 0.13).  What differs, as far as the
project is concerned (checked against both builds and build123d 0.13's own imports):

* OCP 8 moved OCCT's collection classes out of their packages into ``OCP.collections`` under
  template-style names: ``TColgp_Array1OfPnt`` → ``Array1_gp_Pnt``, ``TColgp_Array1OfPnt2d`` →
  ``Array1_gp_Pnt2d``, ``TColStd_Array1OfReal`` → ``Array1_double``, ``TColStd_Array1OfInteger``
  → ``Array1_int`` (the old names are gone).  :data:`RENAMED` lists where each lives; the first
  place that has it wins, so the choice is made by what the installed OCP has, not by its
  version number.
* OCCT 8 made ``TopoDS`` a namespace: its casts are ``TopoDS.Edge(shape)`` in OCP 8 where OCP
  7.9 has the static ``TopoDS.Edge_s(shape)`` (there ``TopoDS.Edge`` is an instance method).
  Every static method is therefore called through :func:`_static` (``X_s`` where OCP has it,
  else ``X``) and wrapped here as a plain function (:func:`topods_edge`,
  :func:`volume_properties`, :func:`static_set`, …).
* OCP 8 cannot convert ``Bnd_Box.Get()``'s result (``Bnd_Box::Limits``, unregistered): the box
  is read through its corners (:func:`box_limits`).
* Everything else the project calls is the same in both: the ``_s`` statics of
  ``BRepGProp.VolumeProperties_s``, ``Interface_Static.SetCVal_s``/``CVal_s``,
  ``STEPControl_Controller.Init_s``, ``Message.DefaultMessenger_s``, ``BRepBndLib.Add_s``;
  ``STEPControl_Writer``/``Reader``, ``BRepCheck_Analyzer``, the ``BRepBuilderAPI_*`` makers,
  ``Geom_BSplineCurve`` and ``Geom_OffsetCurve`` (their constructors take either generation's
  arrays), the ``GeomAbs``/``TopAbs`` enums (``tests/test_ocp_compat.py`` checks every name on
  the installed OCP).

Importing this module does not import OCP: a name is resolved when it is first used, so that
``generators``, the DXF/G-code commands and the FreeCAD workbench never load it.  Without an
importable OCP, the first use raises :class:`~cam_workbench.generators.errors.MissingDependency` with the
``pip install`` lines that bring one (:data:`INSTALL_HINT`).
"""
from __future__ import annotations

import importlib
import sys
import warnings
from importlib import metadata
from typing import Any, Iterable, Sequence

from cam_workbench.generators.errors import MissingDependency

#: the extras of cam-workbench that bring an OCP (docs/install.md)
INSTALL_HINT = ('pip install "cam-workbench[cadquery]" (CadQuery users), "cam-workbench[build123d]" '
                '(build123d users) or "cam-workbench[ocp]" (the command line only)')

#: PyPI distributions that install the ``OCP`` package (they overwrite each other's files)
OCP_DISTRIBUTIONS = ("cadquery-ocp", "cadquery-ocp-novtk")

#: neutral name → the places it is found, newest OCP first
RENAMED: dict[str, tuple[tuple[str, str], ...]] = {
    "Array1OfReal": (("OCP.collections", "Array1_double"), ("OCP.TColStd", "TColStd_Array1OfReal")),
    "Array1OfInteger": (("OCP.collections", "Array1_int"), ("OCP.TColStd", "TColStd_Array1OfInteger")),
    "Array1OfPnt": (("OCP.collections", "Array1_gp_Pnt"), ("OCP.TColgp", "TColgp_Array1OfPnt")),
    "Array1OfPnt2d": (("OCP.collections", "Array1_gp_Pnt2d"), ("OCP.TColgp", "TColgp_Array1OfPnt2d")),
    "Array2OfPnt": (("OCP.collections", "Array2_gp_Pnt"), ("OCP.TColgp", "TColgp_Array2OfPnt")),
    "ListOfShape": (("OCP.collections", "List_TopoDS_Shape"), ("OCP.TopTools", "TopTools_ListOfShape")),
}

#: OCP names that are the same in every supported version; each lives in the OCP module named
#: by its prefix (``BRepBuilderAPI_MakeEdge`` in ``OCP.BRepBuilderAPI``, ``gp_Pnt`` in ``OCP.gp``)
SAME: tuple[str, ...] = (
    "BRep_Builder", "BRepAdaptor_Curve", "BRepAlgoAPI_Cut", "BRepAlgoAPI_Fuse", "BRepAdaptor_Surface", "BRepBndLib",
    "BRepBuilderAPI_MakeEdge", "BRepBuilderAPI_MakeFace", "BRepBuilderAPI_MakeVertex", "BRepBuilderAPI_MakeWire",
    "BRepExtrema_DistShapeShape",
    "BRepCheck_Analyzer", "BRepGProp", "BRepPrimAPI_MakePrism", "Bnd_Box", "GProp_GProps",
    "BRepAlgoAPI_Splitter", "BRepBuilderAPI_MakeSolid", "BRepBuilderAPI_Sewing", "BRepLib", "BRepClass3d_SolidClassifier", "BRepPrimAPI_MakeCylinder",
    "Geom_BSplineSurface", "TopAbs_IN", "TopAbs_SHELL", "BRepTools", "TopoDS_Compound", "TopoDS_Shape",
    "Geom_BSplineCurve", "Geom_OffsetCurve", "Geom2d_BSplineCurve", "Geom2d_OffsetCurve",
    "GeomAbs_BSplineCurve", "GeomAbs_BSplineSurface", "GeomAbs_OffsetCurve", "GeomAbs_Plane",
    "IFSelect_RetDone", "Interface_Static", "Message", "Message_Gravity",
    "STEPControl_AsIs", "STEPControl_Controller", "STEPControl_Reader", "STEPControl_Writer",
    "StepBasic_Product", "TCollection_HAsciiString", "TopAbs_EDGE", "TopAbs_FACE", "TopAbs_REVERSED", "TopAbs_SOLID", "TopExp_Explorer", "TopoDS",
    "gp_Ax2", "gp_Ax3", "gp_Circ", "gp_Dir", "gp_Pln", "gp_Pnt", "gp_Pnt2d", "gp_Vec",
    "Geom_CylindricalSurface", "GeomAbs_Circle", "GeomAbs_Cylinder", "ShapeFix_Face",
    "BRepPrimAPI_MakeRevol", "ShapeUpgrade_UnifySameDomain", "gp_Ax1", "gp_Trsf", "BRepBuilderAPI_Transform",
)

__all__ = sorted({*RENAMED, *SAME, "INSTALL_HINT", "OCP_DISTRIBUTIONS", "available", "require",
                  "version", "distributions", "describe", "real_array", "int_array", "pnt_array", "pnt_array2",
                  "pnt2d_array", "topods_edge", "topods_wire", "topods_face", "topods_solid", "topods_shell",
                  "orient_closed_solid",
                  "volume_properties", "surface_properties", "read_brep", "add_to_box", "box_limits", "is_valid", "main",
                  "init_step", "static_set", "static_get", "message_printers"})


# ---- availability --------------------------------------------------------------------------
def _import_ocp(what: str | None = None) -> Any:
    """``import OCP``, or MissingDependency saying what needs it and how to install it."""
    need = f"{what} needs" if what else "this needs"
    try:
        import OCP  # deferred: OCP, an extra (importing this module loads no OCP)
    except ModuleNotFoundError as exc:
        if exc.name != "OCP":
            raise _broken(need, exc) from exc
        raise MissingDependency(f"{need} OCP (OpenCascade's Python bindings), which is not "
                                f"installed: {INSTALL_HINT}") from exc
    except ImportError as exc:
        raise _broken(need, exc) from exc
    _warn_two_distributions()
    return OCP


_WARNED = []


def _warn_two_distributions() -> None:
    """Once per process: a RuntimeWarning when both OCP distributions are installed (OCP may
    import and still be a mixture of the two builds; CadQuery breaks when the VTK-less one won)."""
    if _WARNED:
        return
    _WARNED.append(True)
    note = two_distributions_note()
    if note:
        warnings.warn(f"broken environment{note}", RuntimeWarning, stacklevel=3)


def _broken(need: str, exc: BaseException) -> MissingDependency:
    return MissingDependency(f"{need} OCP, which is installed but fails to import "
                             f"({type(exc).__name__}: {exc}){two_distributions_note()}")


def available() -> bool:
    """True when OCP imports."""
    try:
        _import_ocp()
    except MissingDependency:
        return False
    return True


def require(what: str | None = None) -> None:
    """Raise :class:`MissingDependency` naming ``what`` (e.g. "cam-workbench build") and the
    extras that bring OCP, unless OCP imports."""
    _import_ocp(what)


def version() -> str:
    """OCP's version (``OCP.__version__``, e.g. "7.9.3.1" or "8.0.1.1")."""
    return str(getattr(_import_ocp(), "__version__", "unknown"))


def distributions() -> list[tuple[str, str]]:
    """The installed distributions that provide ``OCP`` (name, version); more than one is a
    broken environment (each overwrites the other's files).  Does not import OCP."""
    found = []
    for name in OCP_DISTRIBUTIONS:
        try:
            found.append((name, metadata.version(name)))
        except metadata.PackageNotFoundError:
            pass
    return found


def two_distributions_note() -> str:
    """A sentence for error messages when both OCP distributions are installed, else ''."""
    dists = distributions()
    if len(dists) < 2:
        return ""
    listed = " and ".join(f"{n} {v}" for n, v in dists)
    return (f"; {listed} are both installed and overwrite each other's OCP files: uninstall both "
            f"and install the one your CAD library needs (docs/install.md)")


def describe() -> str:
    """One line: which OCP is in use and where it comes from (for reports and bug reports)."""
    dists = ", ".join(f"{n} {v}" for n, v in distributions()) or "no PyPI distribution"
    return f"OCP {version()} ({dists})"


# ---- names -----------------------------------------------------------------------------------
def _resolve(name: str) -> Any:
    _import_ocp()
    if name in RENAMED:
        for module, attr in RENAMED[name]:
            try:
                return getattr(importlib.import_module(module), attr)
            except (ImportError, AttributeError):
                continue
        raise MissingDependency(f"OCP {version()} has none of "
                                f"{', '.join(f'{m}.{a}' for m, a in RENAMED[name])}: cam-workbench "
                                f"supports OCP 7.9 and 8.x ({INSTALL_HINT})")
    return getattr(importlib.import_module("OCP." + name.split("_")[0]), name)


def __getattr__(name: str) -> Any:
    if name in RENAMED or name in SAME:
        value = _resolve(name)
        globals()[name] = value            # resolved once
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _ns() -> Any:
    """This module, for resolving names lazily from the helpers below."""
    return sys.modules[__name__]


# ---- arrays (OCCT's 1-based Array1 collections) ------------------------------------------------
def _array1(cls: Any, values: Sequence[Any]) -> Any:
    arr = cls(1, len(values))
    for i, v in enumerate(values, start=1):
        arr.SetValue(i, v)
    return arr


def pnt_array2(grid: Any) -> Any:
    """``TColgp_Array2OfPnt`` / ``Array2_gp_Pnt`` (1-based rows and columns) of the points
    ``grid[i][j] = (x, y, z)``."""
    rows, cols = len(grid), len(grid[0])
    arr = _ns().Array2OfPnt(1, rows, 1, cols)
    for i, row in enumerate(grid, start=1):
        for j, (x, y, z) in enumerate(row, start=1):
            arr.SetValue(i, j, _ns().gp_Pnt(float(x), float(y), float(z)))
    return arr


def real_array(values: Iterable[float]) -> Any:
    """``TColStd_Array1OfReal`` / ``Array1_double`` holding ``values`` (1-based)."""
    return _array1(_ns().Array1OfReal, [float(v) for v in values])


def int_array(values: Iterable[int]) -> Any:
    """``TColStd_Array1OfInteger`` / ``Array1_int`` holding ``values`` (1-based)."""
    return _array1(_ns().Array1OfInteger, [int(v) for v in values])


def pnt_array(points: Iterable[Any]) -> Any:
    """``TColgp_Array1OfPnt`` / ``Array1_gp_Pnt`` holding the ``gp_Pnt`` ``points`` (1-based)."""
    return _array1(_ns().Array1OfPnt, list(points))


def pnt2d_array(points: Iterable[Any]) -> Any:
    """``TColgp_Array1OfPnt2d`` / ``Array1_gp_Pnt2d`` holding the ``gp_Pnt2d`` ``points``."""
    return _array1(_ns().Array1OfPnt2d, list(points))


# ---- static methods ---------------------------------------------------------------------------
def _static(cls: Any, name: str) -> Any:
    """A static method of an OCP class: OCP binds them with an ``_s`` suffix (``Init_s``), except
    where OCCT itself made the class a namespace — OCP 8's ``TopoDS``, whose casts are plain
    ``TopoDS.Edge`` (in OCP 7.9 ``TopoDS.Edge`` is the instance method, ``Edge_s`` the cast)."""
    method = getattr(cls, name + "_s", None)
    return method if method is not None else getattr(cls, name)


def topods_edge(shape: Any) -> Any:
    """``TopoDS.Edge_s`` (OCP 7.9) / ``TopoDS.Edge`` (OCP 8): the shape as a ``TopoDS_Edge``."""
    return _static(_ns().TopoDS, "Edge")(shape)


def topods_wire(shape: Any) -> Any:
    """The shape as a ``TopoDS_Wire`` (see :func:`topods_edge`)."""
    return _static(_ns().TopoDS, "Wire")(shape)


def topods_face(shape: Any) -> Any:
    """The shape as a ``TopoDS_Face`` (see :func:`topods_edge`)."""
    return _static(_ns().TopoDS, "Face")(shape)


def topods_solid(shape: Any) -> Any:
    """The shape as a ``TopoDS_Solid`` (see :func:`topods_edge`)."""
    return _static(_ns().TopoDS, "Solid")(shape)


def topods_shell(shape: Any) -> Any:
    """The shape as a ``TopoDS_Shell`` (see :func:`topods_edge`)."""
    return _static(_ns().TopoDS, "Shell")(shape)


def orient_closed_solid(solid: Any) -> bool:
    """``BRepLib::OrientClosedSolid``: turn a closed solid's shells so that its material is inside."""
    return bool(_static(_ns().BRepLib, "OrientClosedSolid")(solid))


def volume_properties(shape: Any, props: Any, eps: float | None = None) -> None:
    """``BRepGProp.VolumeProperties_s(shape, props)``; with ``eps`` the adaptive integration to
    that relative error (``(shape, props, eps, OnlyClosed=False)``)."""
    fn = _static(_ns().BRepGProp, "VolumeProperties")
    if eps is None:
        fn(shape, props)
    else:
        fn(shape, props, eps, False)


def read_brep(path: str) -> Any:
    """The shape of an OCCT BREP file (``BRepTools.Read_s``; FreeCAD's ``Shape.exportBrep``)."""
    ns = _ns()
    shape = ns.TopoDS_Shape()
    if not _static(ns.BRepTools, "Read")(shape, str(path), ns.BRep_Builder()):
        raise OSError(f"OCCT could not read the BREP file {path}")
    return shape


def surface_properties(shape: Any, props: Any) -> None:
    """``BRepGProp.SurfaceProperties_s(shape, props)``."""
    _static(_ns().BRepGProp, "SurfaceProperties")(shape, props)


def add_to_box(shape: Any, box: Any, optimal: bool = False) -> None:
    """Enlarge the bounding box by the shape: ``BRepBndLib.Add_s(shape, box)``, or with
    ``optimal`` the tight box of ``BRepBndLib.AddOptimal_s(shape, box, False, False)`` (exact
    geometry, not the triangulation; no enlargement by tolerances)."""
    if optimal:
        _static(_ns().BRepBndLib, "AddOptimal")(shape, box, False, False)
    else:
        _static(_ns().BRepBndLib, "Add")(shape, box)


def box_limits(box: Any) -> tuple[float, float, float, float, float, float]:
    """(xmin, ymin, zmin, xmax, ymax, zmax) of a ``Bnd_Box``: its corners (OCP 8 cannot return
    ``Bnd_Box.Get()``'s ``Bnd_Box::Limits``; OCP 7.9 returned the tuple)."""
    lo, hi = box.CornerMin(), box.CornerMax()
    return lo.X(), lo.Y(), lo.Z(), hi.X(), hi.Y(), hi.Z()


def is_valid(shape: Any) -> bool:
    """OCCT's full topological and geometric check (``BRepCheck_Analyzer``)."""
    return bool(_ns().BRepCheck_Analyzer(shape).IsValid())


def init_step() -> None:
    """``STEPControl_Controller.Init_s()``: declare the STEP translator's parameters."""
    _static(_ns().STEPControl_Controller, "Init")()


def static_set(name: str, value: str) -> bool:
    """``Interface_Static.SetCVal_s``: set a translator parameter; False when OCCT refuses it."""
    return bool(_static(_ns().Interface_Static, "SetCVal")(name, value))


def static_get(name: str) -> str:
    """``Interface_Static.CVal_s``: a translator parameter's value."""
    return str(_static(_ns().Interface_Static, "CVal")(name))


def message_printers() -> list[Any]:
    """The default messenger's printers (``Message.DefaultMessenger_s().Printers()``)."""
    return list(_static(_ns().Message, "DefaultMessenger")().Printers())


def main(argv: Sequence[str] | None = None) -> int:
    """Say which OCP this environment has; 1 unless exactly one OCP distribution is installed and
    OCP imports (the Makefile checks its venv so: ``python -c "from cam_workbench.kernel.ocp
    import main; raise SystemExit(main())"``)."""
    dists = distributions()
    try:
        print(describe())
    except MissingDependency as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    if len(dists) != 1:
        print(f"error: {len(dists)} OCP distributions installed{two_distributions_note()}", file=sys.stderr)
        return 1
    return 0

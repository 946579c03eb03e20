"""cam_workbench: exact cams (plate, groove, conjugate, cylindrical) as CadQuery/build123d solids,
STEP, DXF, G-code, reports, a CLI and a FreeCAD workbench.

    from cam_workbench import Cam
    cam = Cam()                      # the built-in default cam (PlateCam: the same class)
    cam.workplane()                  # cadquery.Workplane

One import name: the mathematics is :mod:`cam_workbench.generators`, the writers are
:mod:`cam_workbench.exporters`.  A wheel installs them inside this package (pyproject's
``package-dir``); in a source tree — a checkout, or a clone in FreeCAD's Mod folder — they are
the folders ``generators/`` and ``exporters/`` beside this one, found through ``__path__``.
"""
import os as _os

_here = _os.path.dirname(_os.path.abspath(__file__))
if not _os.path.isdir(_os.path.join(_here, "generators")):
    # the source tree: the subpackages are this folder's siblings
    __path__.append(_os.path.dirname(_here))  # noqa: F821 (a package's __path__)

_API = ("Cam", "PlateCam", "plate_cam", "register")
_SPEC = ("CamSpec", "GeometryError", "SpecError", "default_spec", "load_spec")
_INSPECTION = ("inspect_part",)


def __getattr__(name: str):
    """The API (:mod:`cam_workbench.cam`) and the spec's names (:mod:`cam_workbench.generators`)
    load when first asked for: importing :mod:`cam_workbench.generators` — inside FreeCAD's Python
    too — loads numpy and scipy only, and ``cam-workbench --help`` nothing of ours but the
    command line's catalogue."""
    if name in _API:
        from . import cam  # deferred: the API layer (OCP adaptor, solid builders)

        return getattr(cam, name)
    if name == "Machine":
        from . import machine  # deferred: the API layer (the pipeline, the machine's outputs)

        return machine.Machine
    if name in _INSPECTION:
        from . import inspection  # deferred: the API layer (the inspection, its files)

        return getattr(inspection, name)
    if name in _SPEC:
        from . import generators  # deferred: the mathematics (numpy, scipy)

        return getattr(generators, name)
    raise AttributeError(f"module 'cam_workbench' has no attribute {name!r}")


__all__ = ["Cam", "CamSpec", "GeometryError", "Machine", "PlateCam", "SpecError", "default_spec", "inspect_part",
           "load_spec", "plate_cam", "register"]
__version__ = "0.1.0"

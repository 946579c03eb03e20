"""cam_workbench.generators — the mathematics: spec, motion laws, PH pitch curves, exact offsets, checks.

Imports only numpy, scipy and the standard library (no CAD kernel, no file format
beyond TOML), so it runs inside FreeCAD's own Python as well as beside CadQuery.
"""
from .cam_design import CamDesign, design_cam
from .errors import CamError, GeometryError, NotAvailable, SolveError, SpecError
from .curves.nurbs import NurbsCurve
from .spec.default import default_spec
from .spec.model import CamSpec
from .spec.toml_io import load_spec, to_toml
from .kinds import builtin  # noqa: F401,E402  (the built-in bodies and followers register themselves)

__all__ = [
    "CamDesign", "CamError", "CamSpec", "GeometryError", "NotAvailable", "NurbsCurve", "SolveError", "SpecError",
    "default_spec", "design_cam", "load_spec", "to_toml",
]
__version__ = "0.1.0"

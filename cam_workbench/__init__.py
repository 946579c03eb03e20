"""cam_workbench: exact plate cams as CadQuery/build123d solids, STEP, CLI and a FreeCAD workbench.

    from cam_workbench import PlateCam
    cam = PlateCam()                 # the built-in default cam
    cam.workplane()                  # cadquery.Workplane
"""
from generators import CamSpec, GeometryError, SpecError, default_spec, load_spec

from .platecam import PlateCam, plate_cam, register

__all__ = ["CamSpec", "GeometryError", "PlateCam", "SpecError", "default_spec", "load_spec",
           "plate_cam", "register"]
__version__ = "0.1.0"

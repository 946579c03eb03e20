# cam_workbench: FreeCAD runs this file at GUI start-up.  It defines the workbench without
# importing the package (start-up stays cheap); commands load when the workbench is first
# activated.  FreeCAD executes this file with exec(), so names defined here are not visible
# inside the class: everything the methods need is imported in them.
import importlib.util
import os
import sys

import FreeCAD
import FreeCADGui


class CamWorkbench(FreeCADGui.Workbench):
    """Exact cams — plate, groove, conjugate, cylindrical: PH quintic pitch curves, rational
    offset profiles, design checks."""

    MenuText = "Cam Workbench"
    ToolTip = ("Exact cams (plate, groove, conjugate, cylindrical): C² PH quintic pitch curves, exact "
               "rational (NURBS) profiles, design checks, an optimiser, STEP, DXF and G-code export")
    Icon = ""

    def Initialize(self):
        # deferred: the workbench's commands, to its first activation (start-up stays cheap)
        from cam_workbench.freecad import commands

        commands.register()
        self.appendToolbar("Cam", commands.TOOLBAR)
        self.appendMenu("Cam", commands.LAYOUT)

    def Activated(self):
        return None

    def Deactivated(self):
        return None

    def GetClassName(self):
        return "Gui::PythonWorkbench"


for _camwb_dir in list(sys.path):  # a clone in the Mod folder: its root (see Init.py)
    _camwb_dir = os.path.normpath(str(_camwb_dir))
    if _camwb_dir.endswith(os.path.join("cam_workbench", "freecad", "mod")):
        _camwb_root = os.path.dirname(os.path.dirname(os.path.dirname(_camwb_dir)))
        if (os.path.isfile(os.path.join(_camwb_root, "generators", "__init__.py"))
                and _camwb_root not in [os.path.normpath(str(p)) for p in sys.path]):
            sys.path.insert(0, _camwb_root)
        break

_cam_spec = importlib.util.find_spec("cam_workbench")  # finds the package without importing it
if _cam_spec is None or not _cam_spec.submodule_search_locations:
    FreeCAD.Console.PrintError(
        "Cam Workbench: the cam_workbench package is not on FreeCAD's Python path "
        "(was the checkout moved or the package uninstalled?). Run `cam-workbench freecad install` "
        "again.\n")
else:
    CamWorkbench.Icon = os.path.join(list(_cam_spec.submodule_search_locations)[0], "freecad",
                                     "icons", "CamWorkbench.svg")
    FreeCADGui.addWorkbench(CamWorkbench())
    # File > Open of a spec in the GUI: the importer that also gives the cam its view providers
    # (Init.py registered the App-side one under the same filter)
    FreeCAD.changeImportModule("Cam spec (*.toml)", "cam_workbench.freecad.spec_io",
                               "cam_workbench.freecad.spec_io_gui")

# cam_workbench: FreeCAD runs this file at start-up, headless (freecadcmd) and with the GUI.
# It must stay cheap: it only makes the packages importable and registers the spec importer
# (the module loads when a file is opened).  The packages generators/, exporters/ and
# cam_workbench/ are found on sys.path: beside this file (installed by `cam-workbench freecad
# install`), or at the root of a clone of the repository in the Mod folder (`git clone`, or the
# Addon Manager): package.xml there names this folder (<clone>/cam_workbench/freecad/mod) as the
# workbench's subdirectory, which FreeCAD puts on sys.path and runs this file from; the clone's
# root, three folders up, is put on sys.path here (FreeCAD 0.20 adds it itself, 1.x may not).
# FreeCAD executes this file with exec() inside a function: no def may use the names below.
import os
import sys

import FreeCAD

for _camwb_dir in list(sys.path):
    _camwb_dir = os.path.normpath(str(_camwb_dir))
    if _camwb_dir.endswith(os.path.join("cam_workbench", "freecad", "mod")):
        _camwb_root = os.path.dirname(os.path.dirname(os.path.dirname(_camwb_dir)))
        if (os.path.isfile(os.path.join(_camwb_root, "generators", "__init__.py"))
                and _camwb_root not in [os.path.normpath(str(p)) for p in sys.path]):
            sys.path.insert(0, _camwb_root)
        break

# InitGui.py hands this filter to the GUI's importer (the same text there)
FreeCAD.addImportType("Cam spec (*.toml)", "cam_workbench.freecad.spec_io")

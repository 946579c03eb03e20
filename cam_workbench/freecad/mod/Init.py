# cam_workbench: FreeCAD runs this file at start-up, headless (freecadcmd) and with the GUI.
# It must stay cheap: it only registers the spec importer (the module loads when a file
# is opened).  The packages generators/, exporters/ and cam_workbench/ are found on
# sys.path: beside this file (installed by `cam-workbench freecad install`) or at the
# root of the Addon Manager's clone (package.xml points here).
import FreeCAD

FreeCAD.addImportType("Plate cam spec (*.toml)", "cam_workbench.freecad.spec_io")

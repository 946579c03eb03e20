"""The workbench's commands and its menu/toolbar layout.

Importing this module is cheap (FreeCAD, FreeCADGui, PySide, os): every command imports what it
needs (numpy, scipy, generators, matplotlib) only when it runs.  A new command is a
:class:`Command` subclass registered in :data:`COMMANDS` and placed in :data:`LAYOUT`.
"""
from __future__ import annotations

import os
import traceback
from typing import Any

import FreeCAD
import FreeCADGui
from PySide import QtGui  # FreeCAD's PySide shim (PySide2 in 0.20, PySide6 in 1.x)

ICON_DIR = os.path.join(os.path.dirname(__file__), "icons")
#: The proxies' class names (restored documents hold these classes whatever name they stored)
PROXY_CLASS = "CamFeature"
REFERENCE_CLASS = "CamReference"


def is_cam(obj: Any) -> bool:
    """Cheap test (no import of the feature module)."""
    return type(getattr(obj, "Proxy", None)).__name__ == PROXY_CLASS


def cams_of(doc: Any) -> list[Any]:
    """The cam features of ``doc`` (none for no document)."""
    return [o for o in doc.Objects if is_cam(o)] if doc is not None else []


def target_cam() -> Any:
    """The cam a command acts on: the selected one (or the cam of a selected reference
    curve), else the only cam of the active document; None (with a message) otherwise."""
    for obj in FreeCADGui.Selection.getSelection():
        if is_cam(obj):
            return obj
        if type(getattr(obj, "Proxy", None)).__name__ == REFERENCE_CLASS:
            cams = [o for o in obj.InList if is_cam(o)]
            if cams:
                return cams[0]
    cams = cams_of(FreeCAD.ActiveDocument)
    if len(cams) == 1:
        return cams[0]
    FreeCAD.Console.PrintError("Select a cam first" + (" (the document has several)" if cams
                                                        else " (the document has none)") + "\n")
    return None


class Command:
    """Base: resources from class attributes; ``run()`` does the work; errors are reported
    in the report view as one line (the traceback goes to the log only)."""

    menu_text = ""
    tooltip = ""
    icon = "CamWorkbench.svg"
    needs_cam = True

    def GetResources(self) -> dict[str, str]:
        return {"Pixmap": os.path.join(ICON_DIR, self.icon), "MenuText": self.menu_text,
                "ToolTip": self.tooltip}

    def IsActive(self) -> bool:
        doc = FreeCAD.ActiveDocument
        if not self.needs_cam:
            return True
        return doc is not None and any(is_cam(o) for o in doc.Objects)

    def Activated(self) -> None:
        try:
            # registered before a command may make a cam; activating the workbench stays cheap:
            from . import view_providers  # deferred: numpy, scipy, the generators

            view_providers.register()
            self.run()
        except Exception as exc:  # noqa: BLE001 - one clear line, not a traceback
            FreeCAD.Console.PrintLog(traceback.format_exc())
            FreeCAD.Console.PrintError(f"{self.menu_text}: {type(exc).__name__}: {exc}\n")

    def run(self) -> None:
        raise NotImplementedError


class NewCam(Command):
    menu_text = "New cam"
    tooltip = ("Add a parametric cam (the built-in default: a plate cam with a radial 8 mm roller on "
               "the paper's motion program); edit its properties and its motion program, or start "
               "from a spec of any body")
    icon = "Cam.svg"
    needs_cam = False

    def run(self) -> None:
        doc = FreeCAD.ActiveDocument or FreeCAD.newDocument()
        doc.openTransaction("New cam")
        FreeCADGui.doCommand("from cam_workbench.freecad.feature import create")
        FreeCADGui.doCommand(f"create(App.getDocument({doc.Name!r}))")
        FreeCADGui.doCommand(f"App.getDocument({doc.Name!r}).recompute()")
        doc.commitTransaction()
        _fit_view()


def _open_toml(title: str, load: Any, transaction: str, lines: Any) -> None:
    """Ask for a TOML file, check it with the library's ``load`` (its SpecError shown, nothing
    added), then run ``lines(doc_name, path)`` — the Python lines that add it — in one undo step."""
    name, _f = QtGui.QFileDialog.getOpenFileName(FreeCADGui.getMainWindow(), title, "", f"{title} (*.toml)")
    if not name:
        return
    from cam_workbench.generators.errors import SpecError  # deferred: the generators load numpy, scipy

    try:
        load(name)
    except SpecError as exc:
        FreeCAD.Console.PrintError(f"{name}: {exc}\n")
        QtGui.QMessageBox.warning(FreeCADGui.getMainWindow(), title, str(exc))
        return
    doc = FreeCAD.ActiveDocument or FreeCAD.newDocument()
    doc.openTransaction(transaction)
    for line in lines(doc.Name, name):
        FreeCADGui.doCommand(line)
    doc.commitTransaction()
    _fit_view()


class NewCamFromSpec(Command):
    menu_text = "New cam from spec…"
    tooltip = ("Add a cam from a spec file (TOML, as the cam-workbench CLI reads): a plate, groove, "
               "conjugate or cylindrical cam")
    icon = "CamFromSpec.svg"
    needs_cam = False

    def run(self) -> None:
        from cam_workbench.generators.spec import load_spec  # deferred: the generators load numpy, scipy

        _open_toml("Cam spec", load_spec, "New cam", lambda doc, path: [
            "from cam_workbench.freecad.feature import create", f"create(App.getDocument({doc!r}), {path!r})",
            f"App.getDocument({doc!r}).recompute()"])


class OpenMachine(Command):
    menu_text = "Open machine…"
    tooltip = ("Open a machine file (TOML, as `cam-workbench machine` reads): every cam on one shaft, one "
               "behind the other, turned by its phase; the group's MachineAngle turns them all")
    icon = "CamFromSpec.svg"
    needs_cam = False

    def run(self) -> None:
        from cam_workbench.generators.machine import load_machine  # deferred: the generators load numpy, scipy

        _open_toml("Machine", load_machine, "Open machine", lambda doc, path: [
            "from cam_workbench.freecad.machine_doc import open_machine",
            f"open_machine(App.getDocument({doc!r}), {path!r})"])


class PlayMachine(Command):
    menu_text = "Play machine"
    tooltip = ("Turn the machine: a task panel with a MachineAngle slider and Play/Stop, which steps the "
               "camshaft through 0–360° and shows every cam and follower where they stand")
    icon = "Plots.svg"

    def IsActive(self) -> bool:
        doc = FreeCAD.ActiveDocument
        return doc is not None and any(type(getattr(o, "Proxy", None)).__name__ == "MachineGroup"
                                       for o in doc.Objects)

    def run(self) -> None:
        from .machine_panel import open_play_panel, target_machine  # deferred: numpy, scipy, the generators

        group = target_machine()
        if group is not None:
            open_play_panel(group)


class EditMotion(Command):
    menu_text = "Edit motion program"
    tooltip = "Edit the cam's motion segments (dwell / rise / return) in a table; also a double-click on the cam"
    icon = "EditMotion.svg"

    def run(self) -> None:
        cam = target_cam()
        if cam is not None:
            from .motion_editor import open_editor  # deferred: numpy, scipy, the generators

            open_editor(cam)


class Optimise(Command):
    menu_text = "Optimise"
    tooltip = ("Optimise the cam (thesis Ch. 5–7, nlopt): minimise its area, machining time or peak "
               "acceleration / pressure angle over base radius, offset and B-spline control points, with "
               "every design check as a constraint; run, watch, cancel, compare before/after, apply")
    icon = "Optimise.svg"

    def run(self) -> None:
        cam = target_cam()
        if cam is not None:
            from .optimiser_panel import open_panel  # deferred: numpy, scipy, the generators

            open_panel(cam)


class CheckDesign(Command):
    menu_text = "Check design"
    tooltip = ("Design checks of the cam (thesis Ch. 3): pressure angle, separation, oscillation, "
               "contact stress, curvature and undercut — value, cam angle, limit, pass/fail — the "
               "extremes, the buildability checks and FreeCAD's solid check, and with DynamicsEnabled the "
               "follower dynamics (contact at speed, jump speed, contact force, camshaft torque)")
    icon = "CheckDesign.svg"

    def run(self) -> None:
        cam = target_cam()
        if cam is not None:
            from .check_design import show_report  # deferred: numpy, scipy, the generators

            show_report(cam)


class ToleranceStudy(Command):
    menu_text = "Tolerance study…"
    tooltip = ("The largest profile tolerance (ISO 1101 profile of a line, worst wave phase) per number of "
               "waves per turn that keeps the follower's acceleration error within 5 % of the designed peak at "
               "the cam's speed, and where the follower stops following the waves: chart and table "
               "(cam-workbench tolerance, docs/tolerances.md)")
    icon = "CheckDesign.svg"

    def run(self) -> None:
        cam = target_cam()
        if cam is not None:
            from .tolerance_panel import show_tolerance  # deferred: numpy, scipy, the generators

            show_tolerance(cam)


class InspectPart(Command):
    menu_text = "Inspect part…"
    tooltip = ("Hold a made cam against its design: measured profile points (CSV x,y[,z]) registered to the "
               "exact profile, every point's normal deviation, the profile-tolerance verdict, the outliers and the "
               "follower's acceleration error on the part; the points added under the cam, coloured by deviation "
               "(cam-workbench inspect, docs/inspection.md)")
    icon = "CheckDesign.svg"

    def run(self) -> None:
        cam = target_cam()
        if cam is not None:
            from .inspection_panel import open_inspection  # deferred: numpy, scipy, the generators

            open_inspection(cam)


class ShowPlots(Command):
    menu_text = "Show kinematics plots"
    tooltip = ("Plot displacement, velocity, acceleration, jerk and pressure angle against cam angle, "
               "and the displacement error of the built pitch curve")
    icon = "Plots.svg"

    def run(self) -> None:
        cam = target_cam()
        if cam is not None:
            from .plots import show_plots  # deferred: numpy, scipy, the generators

            show_plots(cam)


class ExportStep(Command):
    menu_text = "Export STEP…"
    tooltip = "Write the cam solid as a STEP file (FreeCAD's own exporter, millimetres)"
    icon = "ExportStep.svg"

    def run(self) -> None:
        cam = target_cam()
        if cam is not None:
            from .step_export import export_step_dialog  # deferred: numpy, scipy, the generators

            export_step_dialog(cam)


class ExportSpec(Command):
    menu_text = "Export spec (TOML)…"
    tooltip = "Write the cam's spec as TOML, for the cam-workbench command line and the Python API"
    icon = "ExportSpec.svg"

    def run(self) -> None:
        cam = target_cam()
        if cam is None:
            return
        # deferred: numpy, scipy, the generators
        from cam_workbench.generators.errors import SpecError

        from .properties import describe_field  # deferred: numpy, scipy, the generators
        from .spec_io import export_spec  # deferred: numpy, scipy, the generators

        name, _f = QtGui.QFileDialog.getSaveFileName(FreeCADGui.getMainWindow(), "Export spec",
                                                     f"{cam.Label}.toml", "Cam spec (*.toml)")
        if not name:
            return
        try:
            out = export_spec(cam, name)
        except SpecError as exc:
            FreeCAD.Console.PrintError(f"{cam.Label}: spec not written: "
                                       f"{describe_field(exc.field)}: {exc.rule}\n")
            return
        FreeCAD.Console.PrintMessage(f"{cam.Label}: spec written to {out}\n")


class _Export(Command):
    """Opens the export dialog of :data:`group` (``export_dialog.GROUPS``)."""

    group = ""

    def run(self) -> None:
        cam = target_cam()
        if cam is not None:
            from .export_dialog import open_export_dialog  # deferred: numpy, scipy, the generators

            open_export_dialog(cam, self.group)


class ExportDxf(_Export):
    menu_text = "Export DXF…"
    tooltip = ("Write the manufacturing drawing as DXF: the profile as a cubic SPLINE within the Drawing tolerance "
               "(or the exact NURBS, arcs or a polyline: Drawing Curves), pitch curve, circles, dimensions, title block")
    icon = "ExportDxf.svg"
    group = "dxf"


class ExportGcode(_Export):
    menu_text = "Export G-code…"
    tooltip = ("Write a machining program: XY contour milling (roughing from a blank when "
               "MachiningBlankDiameter is set), XC rotary (C axis + X, G93) or 2-axis wire EDM, in the "
               "Machining properties' dialect and cutter compensation")
    icon = "ExportGcode.svg"
    group = "gcode"


class ExportCommandTable(_Export):
    menu_text = "Export command table (CSV)…"
    tooltip = ("Write the rotational interpolator's commands (paper Eq. 15) as CSV: time, cam angle, "
               "command point, follower displacement, one row per sample period")
    icon = "ExportCsv.svg"
    group = "csv"


class ExportEcam(_Export):
    menu_text = "Export e-cam table…"
    tooltip = ("Write the motion as an electronic-cam table for a servo motion controller: CSV (θ, s, s′, s″, s‴), "
               "CODESYS SoftMotion (XYVA points or Poly5 segments), Beckhoff TwinCAT (motion function or position "
               "table) or Lenze Cam Loader points, with the Ecam properties (step, boundaries, name); shows the "
               "measured deviation of the table's interpolation from the exact motion")
    icon = "ExportEcam.svg"
    group = "ecam"


class DesignReport(_Export):
    menu_text = "Design report (HTML)…"
    tooltip = ("Write the design report into a folder: report.html (self-contained: spec, plots of "
               "motion, pressure angle, curvature, interpolation error, design checks), report.json, PNGs")
    icon = "DesignReport.svg"
    group = "report"


#: Command name → command class, in menu order.
COMMANDS: dict[str, type[Command]] = {
    "CamWorkbench_NewCam": NewCam,
    "CamWorkbench_NewCamFromSpec": NewCamFromSpec,
    "CamWorkbench_OpenMachine": OpenMachine,
    "CamWorkbench_PlayMachine": PlayMachine,
    "CamWorkbench_EditMotion": EditMotion,
    "CamWorkbench_Optimise": Optimise,
    "CamWorkbench_CheckDesign": CheckDesign,
    "CamWorkbench_ToleranceStudy": ToleranceStudy,
    "CamWorkbench_InspectPart": InspectPart,
    "CamWorkbench_ShowPlots": ShowPlots,
    "CamWorkbench_ExportStep": ExportStep,
    "CamWorkbench_ExportDxf": ExportDxf,
    "CamWorkbench_ExportGcode": ExportGcode,
    "CamWorkbench_ExportCommandTable": ExportCommandTable,
    "CamWorkbench_ExportEcam": ExportEcam,
    "CamWorkbench_DesignReport": DesignReport,
    "CamWorkbench_ExportSpec": ExportSpec,
}
#: Menu layout ("Separator" between groups): create, machines, edit and optimise, check, export.
LAYOUT = ["CamWorkbench_NewCam", "CamWorkbench_NewCamFromSpec", "Separator",
          "CamWorkbench_OpenMachine", "CamWorkbench_PlayMachine", "Separator",
          "CamWorkbench_EditMotion", "CamWorkbench_Optimise", "Separator",
          "CamWorkbench_CheckDesign", "CamWorkbench_ToleranceStudy", "CamWorkbench_InspectPart",
          "CamWorkbench_ShowPlots", "Separator",
          "CamWorkbench_ExportStep", "CamWorkbench_ExportDxf", "CamWorkbench_ExportGcode",
          "CamWorkbench_ExportCommandTable", "CamWorkbench_ExportEcam", "Separator",
          "CamWorkbench_DesignReport", "CamWorkbench_ExportSpec"]
#: Toolbar: the everyday commands.
TOOLBAR = ["CamWorkbench_NewCam", "CamWorkbench_EditMotion", "CamWorkbench_Optimise",
           "CamWorkbench_CheckDesign",
           "CamWorkbench_ShowPlots", "CamWorkbench_ExportStep", "CamWorkbench_ExportDxf",
           "CamWorkbench_ExportGcode", "CamWorkbench_DesignReport"]


def register() -> None:
    """Register every command with FreeCAD (idempotent)."""
    known = set(FreeCADGui.listCommands())
    for name, cls in COMMANDS.items():
        if name not in known:
            FreeCADGui.addCommand(name, cls())


def _fit_view() -> None:
    gdoc = FreeCADGui.ActiveDocument
    if gdoc is not None and gdoc.ActiveView is not None and hasattr(gdoc.ActiveView, "viewIsometric"):
        gdoc.ActiveView.viewIsometric()
        gdoc.ActiveView.fitAll()

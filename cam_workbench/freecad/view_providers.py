"""View providers of the ``Cam`` feature and its reference curves (GUI only).

The cam claims its reference curves (and its inspections' groups) as children in the tree, opens the motion editor
on double-click (edit mode 0) and deletes its children with it.  Class names are stored
in saved documents (``GuiDocument.xml``) and must not change; documents saved before feature
version 5 store ``ViewProviderPlateCam``, which stays bound to :class:`ViewProviderCam`.

:func:`register` hands :func:`attach` to the App side's :mod:`.view_hook`, so that the
features :func:`.feature.create` makes get their view providers.
"""
from __future__ import annotations

import os
from typing import Any

import FreeCAD
import FreeCADGui
from PySide import QtGui  # FreeCAD's PySide shim (PySide2 in 0.20, PySide6 in 1.x)

from . import view_hook
from .feature import CamFeature, CamReference, is_cam, references_of
from .inspection_doc import inspections_of
from .motion_editor import MotionEditorPanel
from .stateless import Stateless

ICON_DIR = os.path.join(os.path.dirname(__file__), "icons")


def icon(name: str) -> str:
    """Path of one of the workbench's SVG icons."""
    return os.path.join(ICON_DIR, name)


class ViewProviderCam(Stateless):
    """View provider of a ``Cam`` feature."""

    def __init__(self, vobj: Any):
        vobj.Proxy = self
        self.Object = vobj.Object
        self.panel: Any = None

    def attach(self, vobj: Any) -> None:
        self.Object = vobj.Object
        self.panel = None

    def getIcon(self) -> str:
        return icon("Cam.svg")

    def claimChildren(self) -> list[Any]:
        obj = getattr(self, "Object", None)
        return references_of(obj) + inspections_of(obj) if obj is not None else []

    def setEdit(self, vobj: Any, mode: int = 0) -> bool:
        if mode != 0:
            return False  # e.g. the Transform dragger: FreeCAD's default
        self.panel = MotionEditorPanel(vobj.Object)
        FreeCADGui.Control.showDialog(self.panel)
        return True

    def unsetEdit(self, vobj: Any, mode: int = 0) -> bool:
        if mode != 0:
            return False
        self.panel = None
        FreeCADGui.Control.closeDialog()
        return True

    def doubleClicked(self, vobj: Any) -> bool:
        FreeCADGui.getDocument(vobj.Object.Document.Name).setEdit(vobj.Object, 0)
        return True

    def setupContextMenu(self, vobj: Any, menu: Any) -> None:
        action = QtGui.QAction(QtGui.QIcon(icon("EditMotion.svg")), "Edit motion program", menu)
        action.triggered.connect(lambda: self.doubleClicked(vobj))
        menu.addAction(action)

    def onDelete(self, vobj: Any, subelements: Any) -> bool:
        doc = vobj.Object.Document
        for ref in references_of(vobj.Object):
            doc.removeObject(ref.Name)
        return True


#: How each reference child is drawn: line colour, draw style, line width, point size, icon.
#: The follower is drawn in the colour the report's drawing gives it, with its pivot and the
#: follower point as points.
REFERENCE_STYLES = {
    "pitch curve": ((0.10, 0.35, 0.85), "Dashed", 2.0, 1.0, "PitchCurve.svg"),
    "base circle": ((0.85, 0.45, 0.05), "Dotted", 2.0, 1.0, "BaseCircle.svg"),
    "follower": ((0.54, 0.38, 0.07), "Solid", 3.0, 7.0, "Follower.svg"),
}


class ViewProviderReference(Stateless):
    """View provider of a reference child: a thin coloured line (the pitch curve dashed, the
    base circle dotted), the follower solid and thicker with its points shown."""

    def __init__(self, vobj: Any):
        vobj.Proxy = self
        colour, style, width, points, _icon = REFERENCE_STYLES.get(vobj.Object.Kind,
                                                                   REFERENCE_STYLES["base circle"])
        vobj.LineColor = colour
        vobj.DrawStyle = style
        vobj.LineWidth = width
        vobj.PointSize = points
        vobj.PointColor = colour

    def attach(self, vobj: Any) -> None:
        self.Object = vobj.Object

    def getIcon(self) -> str:
        kind = getattr(getattr(self, "Object", None), "Kind", "pitch curve")
        return icon(REFERENCE_STYLES.get(kind, REFERENCE_STYLES["base circle"])[4])


# a document saved before feature version 5 names the cam's view provider so (GuiDocument.xml);
# FreeCAD restores it as this class, and a save stores the new name
ViewProviderPlateCam = ViewProviderCam


def attach(obj: Any) -> None:
    """Give a cam feature or one of its reference children (by its proxy) its view provider."""
    if isinstance(obj.Proxy, CamFeature):
        ViewProviderCam(obj.ViewObject)
    elif isinstance(obj.Proxy, CamReference):
        ViewProviderReference(obj.ViewObject)


def register() -> None:
    """Register :func:`attach` with the App side (:mod:`.view_hook`; idempotent), and give the
    cams of open documents made before — by the API in the Python console, with the workbench
    not yet active — the view providers they lack."""
    view_hook.set_attacher(attach)
    for doc in FreeCAD.listDocuments().values():
        for cam in filter(is_cam, doc.Objects):
            for obj in (cam, *references_of(cam)):
                if obj.ViewObject.Proxy is None:
                    attach(obj)

"""View providers of the ``PlateCam`` feature and its reference curves (GUI only).

The cam claims its reference curves as children in the tree, opens the motion editor
on double-click (edit mode 0) and deletes its children with it.  Class names are stored
in saved documents and must not change.
"""
from __future__ import annotations

import os
from typing import Any

from .stateless import Stateless

ICON_DIR = os.path.join(os.path.dirname(__file__), "icons")


def icon(name: str) -> str:
    """Path of one of the workbench's SVG icons."""
    return os.path.join(ICON_DIR, name)


class ViewProviderPlateCam(Stateless):
    """View provider of a ``PlateCam`` feature."""

    def __init__(self, vobj: Any):
        vobj.Proxy = self
        self.Object = vobj.Object
        self.panel: Any = None

    def attach(self, vobj: Any) -> None:
        self.Object = vobj.Object
        self.panel = None

    def getIcon(self) -> str:
        return icon("PlateCam.svg")

    def claimChildren(self) -> list[Any]:
        from .feature import references_of

        obj = getattr(self, "Object", None)
        return references_of(obj) if obj is not None else []

    def setEdit(self, vobj: Any, mode: int = 0) -> bool:
        if mode != 0:
            return False  # e.g. the Transform dragger: FreeCAD's default
        import FreeCADGui

        from .motion_editor import MotionEditorPanel

        self.panel = MotionEditorPanel(vobj.Object)
        FreeCADGui.Control.showDialog(self.panel)
        return True

    def unsetEdit(self, vobj: Any, mode: int = 0) -> bool:
        if mode != 0:
            return False
        import FreeCADGui

        self.panel = None
        FreeCADGui.Control.closeDialog()
        return True

    def doubleClicked(self, vobj: Any) -> bool:
        import FreeCADGui

        FreeCADGui.getDocument(vobj.Object.Document.Name).setEdit(vobj.Object, 0)
        return True

    def setupContextMenu(self, vobj: Any, menu: Any) -> None:
        from PySide import QtGui

        action = QtGui.QAction(QtGui.QIcon(icon("EditMotion.svg")), "Edit motion program", menu)
        action.triggered.connect(lambda: self.doubleClicked(vobj))
        menu.addAction(action)

    def onDelete(self, vobj: Any, subelements: Any) -> bool:
        from .feature import references_of

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

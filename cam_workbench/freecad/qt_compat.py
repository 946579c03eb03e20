"""What differs between the Qt bindings of the FreeCAD versions the workbench runs in.

FreeCAD 0.20 and 1.0 (Debian) use PySide2, FreeCAD 1.1 PySide6; both are imported as
``PySide``.  PySide6 (6.4 and newer) makes Qt's enums Python ``enum`` members: a flag such as
``QDialogButtonBox.Ok | QDialogButtonBox.Cancel`` is no longer an ``int`` (``int()`` of it
raises TypeError) and a ``Qt.CheckState`` compares equal only to another ``Qt.CheckState``,
never to the number 2.  These helpers give one answer on both.

They import ``PySide`` when called: :mod:`.motion_editor`, whose logic runs in any Python,
imports this module.
"""
from __future__ import annotations

from typing import Any


def enum_int(value: Any) -> int:
    """The integer of a Qt enum or flags value: ``int(value)`` on PySide2, ``value.value`` on
    PySide6."""
    try:
        return int(value)
    except TypeError:
        return int(value.value)


def standard_buttons(*names: str) -> int:
    """``QDialogButtonBox`` standard buttons by name ("Ok", "Cancel", "Close"), or-ed, as the
    integer FreeCAD's task dialogs take from ``getStandardButtons`` (every FreeCAD version
    converts the returned value with ``int()``-like semantics)."""
    from PySide import QtGui  # deferred: PySide (see the module docstring)

    flags = 0
    for name in names:
        flags |= enum_int(getattr(QtGui.QDialogButtonBox, name))
    return flags


def fit_task_width(widget: Any, contents: int = 14) -> None:
    """Let a task panel be as narrow as FreeCAD's task area: every combo box sized to
    ``contents`` characters (its list still shows the whole text) and every label word-wrapped,
    so that no line of text sets the panel's minimum width (FreeCAD 1.1's Tasks dock is far
    narrower than 0.20's Combo View)."""
    from PySide import QtGui  # deferred: PySide (see the module docstring)

    for combo in widget.findChildren(QtGui.QComboBox):
        combo.setSizeAdjustPolicy(QtGui.QComboBox.AdjustToMinimumContentsLengthWithIcon)
        combo.setMinimumContentsLength(contents)
    for label in widget.findChildren(QtGui.QLabel):
        label.setWordWrap(True)

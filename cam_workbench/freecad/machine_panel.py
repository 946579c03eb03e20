"""The *Play* task panel of a machine (GUI side): a slider for the machine group's
``MachineAngle`` and Play/Stop, a QTimer stepping it through 0→360° with
:func:`cam_workbench.freecad.machine_doc.step_machine`; and the machine the *Play* command acts on.
The machine itself (its group, cams on one shaft, the angle rule) is the App side's
:mod:`cam_workbench.freecad.machine_doc`."""
from __future__ import annotations

from typing import Any

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from .machine_doc import is_machine, machines_of, step_machine, value_of
from .qt_compat import standard_buttons

#: Timer period [ms] and machine-angle step [deg] of *Play*.
PLAY_PERIOD_MS = 40
PLAY_STEP_DEG = 2.0


def open_play_panel(group: Any) -> Any:
    """Show the *Play* task panel of ``group``: a slider for ``MachineAngle`` and Play/Stop (a QTimer stepping
    it by :data:`PLAY_STEP_DEG` through 0→360°, :func:`step_machine`)."""
    class PlayPanel:
        """The task panel: slider, angle read-out, Play/Stop."""

        def __init__(self) -> None:
            self.form = QtGui.QWidget()
            self.form.setWindowTitle(f"Play {group.Label}")
            lay = QtGui.QVBoxLayout(self.form)
            self.label = QtGui.QLabel()
            self.slider = QtGui.QSlider(getattr(QtCore.Qt, "Orientation", QtCore.Qt).Horizontal)
            self.slider.setRange(0, 359)
            self.slider.setValue(int(round(value_of(group.MachineAngle))) % 360)
            self.button = QtGui.QPushButton("Play")
            lay.addWidget(self.label)
            lay.addWidget(self.slider)
            lay.addWidget(self.button)
            self.angle = value_of(group.MachineAngle) % 360.0
            self.timer = QtCore.QTimer(self.form)
            self.timer.setInterval(PLAY_PERIOD_MS)
            self.timer.timeout.connect(self.tick)
            self.slider.valueChanged.connect(self.slid)
            self.button.clicked.connect(self.toggle)
            self.show()

        def show(self) -> None:
            self.label.setText(f"MachineAngle φ = {self.angle:.1f}°")

        def go(self, angle: float) -> None:
            self.angle = angle % 360.0
            step_machine(group, self.angle)
            self.show()
            FreeCADGui.updateGui()

        def slid(self, value: int) -> None:
            if not self.timer.isActive():
                self.go(float(value))

        def tick(self) -> None:
            self.go(self.angle + PLAY_STEP_DEG)
            self.slider.blockSignals(True)
            self.slider.setValue(int(self.angle))
            self.slider.blockSignals(False)

        def toggle(self) -> None:
            if self.timer.isActive():
                self.timer.stop()
                self.button.setText("Play")
            else:
                self.timer.start()
                self.button.setText("Stop")

        def accept(self) -> bool:
            self.timer.stop()
            FreeCADGui.Control.closeDialog()
            return True

        def reject(self) -> bool:
            return self.accept()

        def getStandardButtons(self) -> int:
            return standard_buttons("Close")

    panel = PlayPanel()
    FreeCADGui.Control.showDialog(panel)
    return panel


def target_machine() -> Any:
    """The machine the *Play* command acts on: the selected one (or the machine of a selected cam, cam folder or
    part — follower, linkage, tool), else the only machine of the active document; None (with a message)
    otherwise."""

    for obj in FreeCADGui.Selection.getSelection():
        if is_machine(obj):
            return obj
        for parent in obj.InList:  # the machine links its cams (Cams), parts (Parts) and folders (Group)
            if is_machine(parent):
                return parent
    machines = machines_of(FreeCAD.ActiveDocument)
    if len(machines) == 1:
        return machines[0]
    FreeCAD.Console.PrintError("Select a machine first" + (" (the document has several)" if machines
                                                            else " (the document has none: Open machine…)") + "\n")
    return None

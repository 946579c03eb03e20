"""The "Inspect part…" dialog: asks for the points file (CSV), the profile tolerance, the datum and
an optional folder for the inspection's files, runs :func:`.inspection_doc.inspect_feature` in one
undo step and shows inspection.json's numbers in the report view and in a dialog.  A bad file
shows the library's message (file and line) and adds nothing."""
from __future__ import annotations

from typing import Any

import FreeCAD
import FreeCADGui
from PySide import QtGui  # FreeCAD's PySide shim (PySide2 in 0.20, PySide6 in 1.x)

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.inspection import DATUMS

from . import properties as props
from .inspection_doc import headline, inspect_feature, report_cells, report_lines

#: the dialogs kept alive while shown
_DIALOGS: list[Any] = []
TITLE = "Inspect part"


class InspectionForm(QtGui.QDialog):
    """The inputs of an inspection: points file, tolerance, datum, output folder."""

    def __init__(self, cam: Any):
        super().__init__(FreeCADGui.getMainWindow())
        self.setObjectName("CamWorkbenchInspectionForm")
        self.setWindowTitle(f"{TITLE} — {cam.Label}")
        units = props.units_of(cam)
        form = QtGui.QFormLayout(self)
        self.points = QtGui.QLineEdit()
        self.points.setObjectName("points")
        form.addRow(f"Measured points (CSV: x,y[,z] in {units})", self._with_browse(self.points, self._pick_points))
        self.use_tolerance = QtGui.QCheckBox("Profile tolerance t (zone ±t/2)")
        self.tolerance = QtGui.QDoubleSpinBox()
        self.tolerance.setObjectName("tolerance")
        self.tolerance.setDecimals(6)
        self.tolerance.setRange(1e-6, 1e3)
        self.tolerance.setValue(0.02 if units == "mm" else 0.001)
        self.tolerance.setSuffix(f" {units}")
        self.use_tolerance.setChecked(True)
        self.use_tolerance.toggled.connect(self.tolerance.setEnabled)
        form.addRow(self.use_tolerance, self.tolerance)
        self.datum = QtGui.QComboBox()
        self.datum.setObjectName("datum")
        self.datum.addItems(list(DATUMS))
        self.datum.setToolTip("none: points in any frame (rotation and shift fitted); bore: origin on the bore's "
                              "axis (rotation fitted); bore_and_angle: points in the part's frame")
        form.addRow("Datum", self.datum)
        self.use_folder = QtGui.QCheckBox("Also write inspection.json, .html, CSVs, figures to")
        self.folder = QtGui.QLineEdit()
        self.folder.setObjectName("folder")
        self.folder.setEnabled(False)
        self.use_folder.toggled.connect(self.folder.setEnabled)
        form.addRow(self.use_folder, self._with_browse(self.folder, self._pick_folder))
        buttons = QtGui.QDialogButtonBox(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        form.addRow(buttons)

    def _with_browse(self, edit: Any, pick: Any) -> Any:
        row = QtGui.QWidget()
        lay = QtGui.QHBoxLayout(row)
        lay.setContentsMargins(0, 0, 0, 0)
        lay.addWidget(edit)
        browse = QtGui.QPushButton("Browse…")
        browse.clicked.connect(pick)
        lay.addWidget(browse)
        return row

    def _pick_points(self) -> None:
        name, _f = QtGui.QFileDialog.getOpenFileName(self, "Measured points", "", "Points (*.csv *.txt);;All files (*)")
        if name:
            self.points.setText(name)

    def _pick_folder(self) -> None:
        name = QtGui.QFileDialog.getExistingDirectory(self, "Folder for the inspection's files")
        if name:
            self.folder.setText(name)
            self.use_folder.setChecked(True)

    def values(self) -> tuple[str, float | None, str, str | None]:
        """(points file, tolerance or None, datum, folder or None)."""
        return (self.points.text().strip(), self.tolerance.value() if self.use_tolerance.isChecked() else None,
                self.datum.currentText(), self.folder.text().strip() or None if self.use_folder.isChecked() else None)


def open_inspection(cam: Any) -> None:
    """Ask for the inputs (:class:`InspectionForm`) and inspect (:func:`run_inspection`)."""
    form = InspectionForm(cam)
    if form.exec_() != QtGui.QDialog.Accepted:
        return
    run_inspection(cam, *form.values())


def run_inspection(cam: Any, csv_path: str, tolerance: float | None, datum: str, folder: str | None) -> Any:
    """Inspect in one undo step, print the numbers and show them; a SpecError is shown and nothing
    is added.  Returns the :class:`.inspection_doc.Inspection`, or None when refused."""
    doc = cam.Document
    doc.openTransaction(TITLE)
    try:
        found = inspect_feature(cam, csv_path, tolerance, datum, folder)
    except SpecError as exc:
        doc.abortTransaction()
        FreeCAD.Console.PrintError(f"{cam.Label}: {TITLE}: {exc}\n")
        QtGui.QMessageBox.warning(FreeCADGui.getMainWindow(), TITLE, str(exc))
        return None
    doc.commitTransaction()
    cam.touch()  # the tree asks the cam for its children again: the new group
    doc.recompute()
    report = found.report
    lines = report_lines(report)
    written = f"\nwritten to {folder}: {', '.join(sorted(report['files']))}" if folder else ""
    FreeCAD.Console.PrintMessage(f"{cam.Label}: inspection of {csv_path}: {headline(report)}\n"
                                 + "".join(f"  {line}\n" for line in lines) + (written + "\n" if written else ""))
    show_numbers(cam, report, found.group.WhiskerScale, written)
    return found


def show_numbers(cam: Any, report: dict[str, Any], whisker: float, written: str) -> None:
    """inspection.json's numbers in a non-modal dialog."""
    dlg = QtGui.QDialog(FreeCADGui.getMainWindow())
    dlg.setObjectName("CamWorkbenchInspection")
    dlg.setWindowTitle(f"{TITLE} — {cam.Label}")
    layout = QtGui.QVBoxLayout(dlg)
    head = QtGui.QLabel(f"{report['cam']}\n{headline(report)}\nPoints in the document coloured by deviation, "
                        f"whiskers ×{whisker:g} along the normal; outliers apart (docs/inspection.md){written}")
    head.setWordWrap(True)
    layout.addWidget(head)
    cells = report_cells(report)
    table = QtGui.QTableWidget(len(cells), 2)
    table.setObjectName("inspection")
    table.setHorizontalHeaderLabels(["quantity", "value"])
    for i, (label, value) in enumerate(cells):
        table.setItem(i, 0, QtGui.QTableWidgetItem(label))
        table.setItem(i, 1, QtGui.QTableWidgetItem(value))
    table.resizeColumnsToContents()
    layout.addWidget(table)
    close = QtGui.QPushButton("Close")
    close.clicked.connect(dlg.accept)
    layout.addWidget(close)
    dlg.resize(640, 760)
    dlg.setModal(False)
    dlg.show()
    _DIALOGS.append(dlg)
    dlg.finished.connect(lambda *_: _DIALOGS.remove(dlg) if dlg in _DIALOGS else None)

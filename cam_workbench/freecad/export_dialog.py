"""The export dialog (GUI only): DXF, G-code (XY, XC or wire EDM), command table, e-cam tables, design report.

A small non-modal dialog: what will be written, the feature's properties it uses (the
``[drawing]`` or ``[machining]`` values — change them in the property editor), the output
file (or folder, for the report), and an Export button.  The export itself is
:func:`cam_workbench.freecad.exports.export` — the same function the headless tests call —
run in a worker thread so FreeCAD's window stays responsive while the command line works
(the design report takes a few seconds); the result or the CLI's message is shown in the
dialog and printed to the report view.
"""
from __future__ import annotations

import threading
from typing import Any

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui  # FreeCAD's PySide shim (PySide2 in 0.20, PySide6 in 1.x)

from . import exports

#: Command → the export kinds its dialog offers (more than one: radio buttons).
GROUPS: dict[str, tuple[str, ...]] = {
    "dxf": ("dxf",),
    "gcode": ("gcode_xy", "gcode_xc", "gcode_wire_edm"),
    "csv": ("csv",),
    "report": ("report", "report_plots"),
    "ecam": ("ecam_csv", "ecam_codesys_xyva", "ecam_codesys_poly5", "ecam_beckhoff_motion_function",
             "ecam_beckhoff_position_table", "ecam_lenze"),
}
#: The dialog's title and its choice box's title for a group of several kinds.
GROUP_TITLES: dict[str, tuple[str, str]] = {
    "gcode": ("Export G-code", "Program"),
    "ecam": ("Export e-cam table", "Table"),
    "report": ("Design report", "Files"),
}
_GREEN, _RED = "#1a7f37", "#c62828"
_DIALOGS: list[Any] = []  # keep non-modal dialogs alive until closed


class ExportDialog:
    """One export dialog for a cam; ``kinds`` are keys of :data:`exports.KINDS`."""

    def __init__(self, obj: Any, kinds: tuple[str, ...]):
        self.obj, self.kinds = obj, kinds
        self.result: exports.ExportResult | None = None
        self.error: str | None = None
        self._thread: threading.Thread | None = None
        self._outcome: dict[str, Any] = {}
        first = exports.KINDS[kinds[0]]
        group = next((g for g, ks in GROUPS.items() if ks == kinds), "")
        title, box_title = GROUP_TITLES.get(group, (first.title, "Export"))
        self.title = title
        dlg = self.dialog = QtGui.QDialog(FreeCADGui.getMainWindow())
        dlg.setObjectName("CamWorkbenchExport")
        dlg.setWindowTitle(f"{title} — {obj.Label}")
        layout = QtGui.QVBoxLayout(dlg)
        self.radios: dict[str, Any] = {}
        if len(kinds) > 1:
            box = QtGui.QGroupBox(box_title)
            bl = QtGui.QVBoxLayout(box)
            current = _current_kind(obj, kinds)
            for k in kinds:
                kind = exports.KINDS[k]
                short = kind.title.split('(')[-1].rstrip(')')
                # the e-cam tables: a short label (six of them), the description as tooltip
                rb = QtGui.QRadioButton(short if group == "ecam" else f"{short}: {kind.description}")
                rb.setToolTip(kind.description)
                rb.setChecked(k == (current if current in kinds else kinds[0]))
                rb.toggled.connect(lambda on, k=k: on and self._kind_changed(k))
                bl.addWidget(rb)
                self.radios[k] = rb
            layout.addWidget(box)
        else:
            about = QtGui.QLabel(first.description[:1].upper() + first.description[1:] + ".")
            about.setWordWrap(True)
            layout.addWidget(about)
        layout.addWidget(QtGui.QLabel("Made by the cam-workbench command line from the cam's "
                                      "properties (change them in the property editor):"))
        self.values = QtGui.QTableWidget(0, 2)
        self.values.setHorizontalHeaderLabels(["property", "value"])
        self.values.setObjectName("values")
        self.values.verticalHeader().setVisible(False)
        self.values.horizontalHeader().setStretchLastSection(True)
        self.values.setEditTriggers(QtGui.QAbstractItemView.NoEditTriggers)
        self.values.verticalHeader().setDefaultSectionSize(self.values.fontMetrics().height() + 8)
        layout.addWidget(self.values, 1)
        row = QtGui.QHBoxLayout()
        self.path_label = QtGui.QLabel()
        row.addWidget(self.path_label)
        self.path = QtGui.QLineEdit()
        row.addWidget(self.path, 1)
        browse = QtGui.QPushButton("Browse…")
        browse.clicked.connect(self.browse)
        row.addWidget(browse)
        layout.addLayout(row)
        self.busy = QtGui.QProgressBar()
        self.busy.setRange(0, 0)
        self.busy.setVisible(False)
        layout.addWidget(self.busy)
        self.status = QtGui.QLabel()
        self.status.setWordWrap(True)
        self.status.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        layout.addWidget(self.status)
        # what the command line reported about the file (an e-cam table: its measured deviation)
        self.details = QtGui.QTableWidget(0, 2)
        self.details.setObjectName("details")
        self.details.setHorizontalHeaderLabels(["written", "the command line's numbers"])
        self.details.verticalHeader().setVisible(False)
        self.details.horizontalHeader().setStretchLastSection(True)
        self.details.setEditTriggers(QtGui.QAbstractItemView.NoEditTriggers)
        self.details.setVisible(False)
        layout.addWidget(self.details, 1)
        buttons = QtGui.QDialogButtonBox()
        self.export_button = buttons.addButton("Export", QtGui.QDialogButtonBox.AcceptRole)
        self.close_button = buttons.addButton("Close", QtGui.QDialogButtonBox.RejectRole)
        self.export_button.clicked.connect(self.start)
        self.close_button.clicked.connect(dlg.reject)
        layout.addWidget(buttons)
        self._suggested = ""
        self.kind = next((k for k, rb in self.radios.items() if rb.isChecked()), kinds[0])
        self._kind_changed(self.kind)
        dlg.resize(720, 520)
        self._timer = QtCore.QTimer(dlg)
        self._timer.setInterval(100)
        self._timer.timeout.connect(self._poll)

    # -- contents
    def _kind_changed(self, kind: str) -> None:
        self.kind = kind
        k = exports.KINDS[kind]
        self.path_label.setText("Folder:" if not k.suffix else "File:")
        proposal = str(exports.suggested(self.obj, kind))
        if not self.path.text() or self.path.text() == self._suggested:
            self.path.setText(proposal)
        self._suggested = proposal
        rows = exports.summary_rows(self.obj, kind)
        self.values.setRowCount(len(rows))
        for r, (name, value) in enumerate(rows):
            self.values.setItem(r, 0, QtGui.QTableWidgetItem(name))
            self.values.setItem(r, 1, QtGui.QTableWidgetItem(value))
        header = self.values.horizontalHeader()
        header.setSectionResizeMode(0, QtGui.QHeaderView.ResizeToContents)
        header.setSectionResizeMode(1, QtGui.QHeaderView.Stretch)

    def browse(self) -> None:
        k = exports.KINDS[self.kind]
        if not k.suffix:
            name = QtGui.QFileDialog.getExistingDirectory(self.dialog, k.title, self.path.text())
        else:
            name, _f = QtGui.QFileDialog.getSaveFileName(self.dialog, k.title, self.path.text(),
                                                         k.file_filter)
        if name:
            self.path.setText(name)

    # -- running
    @property
    def running(self) -> bool:
        return self._thread is not None and self._thread.is_alive()

    def start(self) -> None:
        """Run the export in a worker thread (the CLI is a separate process)."""
        if self.running:
            return
        target = self.path.text().strip()
        if not target:
            self._show_error("choose a file to write")
            return
        self.result, self.error = None, None
        self._outcome = {}
        self.details.setVisible(False)
        self.export_button.setEnabled(False)
        self.busy.setVisible(True)
        self.status.setStyleSheet("")
        self.status.setText(f"running the cam-workbench command line: {exports.KINDS[self.kind].title} …")
        kind, obj = self.kind, self.obj
        cli = None
        try:
            cli = exports.find_cli()
        except exports.ExportError as exc:
            self._finish(error=str(exc))
            return

        def work() -> None:
            try:
                self._outcome["result"] = exports.export(obj, kind, target, cli=cli)
            except exports.ExportError as exc:
                self._outcome["error"] = str(exc)
            except Exception as exc:  # noqa: BLE001 - shown, not raised in a thread
                self._outcome["error"] = f"{type(exc).__name__}: {exc}"

        self._thread = threading.Thread(target=work, name="cam-workbench export", daemon=True)
        self._thread.start()
        self._timer.start()

    def _poll(self) -> None:
        if self.running:
            return
        self._timer.stop()
        self._finish(**self._outcome)

    def _finish(self, result: exports.ExportResult | None = None, error: str | None = None) -> None:
        self.busy.setVisible(False)
        self.export_button.setEnabled(True)
        title = exports.KINDS[self.kind].title
        if error is not None:
            self._show_error(error)
            FreeCAD.Console.PrintError(f"{self.obj.Label}: {title}: {error}. Nothing was written.\n")
            return
        assert result is not None
        self.result = result
        where = result.path
        files = "" if len(result.files) == 1 else " (" + ", ".join(result.files) + ")"
        self.status.setStyleSheet(f"color: {_GREEN}")
        self.status.setText(f"Written: {where}{files}")
        FreeCAD.Console.PrintMessage(f"{self.obj.Label}: {title}: written {where}{files}\n")
        if result.details:
            self._show_details(result.details)
            FreeCAD.Console.PrintMessage("".join(f"  {k}: {v}\n" for k, v in result.details))

    def _show_details(self, rows: tuple[tuple[str, str], ...]) -> None:
        self.details.setRowCount(len(rows))
        for r, (name, value) in enumerate(rows):
            self.details.setItem(r, 0, QtGui.QTableWidgetItem(name))
            self.details.setItem(r, 1, QtGui.QTableWidgetItem(value))
        self.details.resizeColumnsToContents()
        self.details.horizontalHeader().setStretchLastSection(True)
        self.details.setVisible(True)
        if self.dialog.height() < 680:
            self.dialog.resize(self.dialog.width(), 680)

    def _show_error(self, text: str) -> None:
        self.error = text
        self.status.setStyleSheet(f"color: {_RED}")
        self.status.setText(f"Not written: {text}")

    def show(self) -> None:
        self.dialog.setModal(False)
        self.dialog.show()
        _DIALOGS.append(self)
        self.dialog.finished.connect(lambda *_: _DIALOGS.remove(self) if self in _DIALOGS else None)


def _current_kind(obj: Any, kinds: tuple[str, ...]) -> str | None:
    """The kind the feature's properties choose (MachiningProgram; EcamFormat and EcamTable)."""
    if "gcode_xy" in kinds:
        program = str(obj.MachiningProgram)   # the program the kind's --mode writes
        return next((k for k in kinds if exports.KINDS[k].args[1:] == ("--mode", program)), None)
    fmt, table = str(getattr(obj, "EcamFormat", "")), str(getattr(obj, "EcamTable", "auto"))
    for k in kinds:
        a = exports.KINDS[k].args
        if "--format" in a and a[a.index("--format") + 1] == fmt and (
                table == "auto" or a[a.index("--table") + 1] == table):
            return k  # the first table of the format for "auto", as the CLI picks it
    return None


def open_export_dialog(obj: Any, group: str) -> ExportDialog:
    """Show the export dialog of ``group`` (a key of :data:`GROUPS`) for the cam ``obj``."""
    dlg = ExportDialog(obj, GROUPS[group])
    dlg.show()
    return dlg


def active_dialogs() -> list[ExportDialog]:
    """The open export dialogs (for tests and scripts)."""
    return list(_DIALOGS)

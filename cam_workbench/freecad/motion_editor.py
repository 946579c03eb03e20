"""The motion-program editor: a task panel with the ``[[motion]]`` segments as a table.

The logic (:func:`validate_rows`, :func:`apply_rows`) works headless; the Qt panel
(:class:`MotionEditorPanel`) is only built in the GUI.  Applying writes every motion
list of the feature and recomputes inside ONE transaction, so a single Undo restores
the previous program (and shape).  Nothing is written unless the program passes the
spec rules and the cam can be made.
"""
from __future__ import annotations

import re
from typing import Any

from generators.errors import CamError, SpecError
from generators.params import params_of, unit_name
from generators.spec import CamSpec, MotionSegment

from . import properties as props

SECTION = "motion"
TRANSACTION = "Edit motion program"
_ROW_PATH = re.compile(r"^motion\[(\d+)\]\.(\w+)$")


def columns() -> list[tuple[str, Any]]:
    """(field, Param) of a motion segment, in declaration order: the table's columns."""
    return list(params_of(MotionSegment).items())


def read_rows(obj: Any) -> list[dict[str, Any]]:
    """The feature's motion segments as spec dicts (lengths in the spec's units)."""
    return props.read_rows(obj, SECTION)


def row_message(exc: SpecError) -> str:
    """A spec error worded for the table: ``motion[3].angle`` → ``row 4, angle``."""
    m = _ROW_PATH.match(exc.field)
    if m:
        return f"row {int(m.group(1)) + 1}, {m.group(2)}: {exc.rule}"
    return f"{exc.field}: {exc.rule}"


def spec_with_rows(obj: Any, rows: list[dict[str, Any]]) -> CamSpec:
    """The feature's spec with its motion program replaced by ``rows`` (validated).

    Raises:
        SpecError: the program (or another property) breaks a rule.
    """
    data = props.spec_dict(obj)
    data[SECTION] = [dict(r) for r in rows]
    return CamSpec.from_dict(data)


def validate_rows(obj: Any, rows: list[dict[str, Any]], design: bool = False) -> str | None:
    """None if ``rows`` make a valid program for this cam, else the message.

    Args:
        design: also design the cam (undercut, self-intersection, bore checks; ~0.1–0.5 s).
    """
    try:
        spec = spec_with_rows(obj, rows)
        if design:
            from generators.cam_design import design_cam

            design_cam(spec)
    except SpecError as exc:
        return row_message(exc)
    except CamError as exc:
        return f"the cam cannot be made: {exc}"
    return None


def apply_rows(obj: Any, rows: list[dict[str, Any]]) -> None:
    """Write ``rows`` into the feature and recompute, as one undo step.

    Raises:
        SpecError: the rows break a rule (nothing is written).
    """
    spec_with_rows(obj, rows)  # validate first: nothing is written on error
    doc = obj.Document
    doc.openTransaction(TRANSACTION)
    try:
        props.write_rows(obj, SECTION, rows)
        doc.recompute()
    except Exception:
        doc.abortTransaction()
        raise
    doc.commitTransaction()


# ---- the Qt task panel (GUI only) -----------------------------------------------------------
class MotionEditorPanel:
    """Task panel: one table row per motion segment, add/remove/move rows, live validation."""

    def __init__(self, obj: Any):
        from PySide import QtGui  # FreeCAD's PySide shim (PySide2 in 0.20, PySide6 in 1.x)

        self.obj = obj
        self.units = getattr(obj, "Units", "mm")
        self.cols = columns()
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("Motion program")
        layout = QtGui.QVBoxLayout(self.form)
        self.table = QtGui.QTableWidget(0, len(self.cols))
        self.table.setHorizontalHeaderLabels([self._header(f, p) for f, p in self.cols])
        for i, (_f, p) in enumerate(self.cols):
            self.table.horizontalHeaderItem(i).setToolTip(p.doc)
        self.table.horizontalHeader().setStretchLastSection(True)
        layout.addWidget(self.table)
        buttons = QtGui.QHBoxLayout()
        for text, slot in (("Add", self.add_row), ("Remove", self.remove_row),
                           ("Up", lambda: self.move_row(-1)), ("Down", lambda: self.move_row(1))):
            b = QtGui.QPushButton(text)
            b.clicked.connect(slot)
            buttons.addWidget(b)
        layout.addLayout(buttons)
        self.total = QtGui.QLabel()
        self.status = QtGui.QLabel()
        self.status.setWordWrap(True)
        layout.addWidget(self.total)
        layout.addWidget(self.status)
        self._filling = False
        self.set_rows(read_rows(obj))
        self.table.itemChanged.connect(lambda *_: self.refresh())

    def _header(self, field: str, p: Any) -> str:
        unit = "°" if p.unit == "angle" else unit_name(p.unit, self.units)
        return f"{field} [{unit}]" if unit else field

    # -- table <-> rows
    def set_rows(self, rows: list[dict[str, Any]]) -> None:
        self._filling = True
        self.table.setRowCount(0)
        for row in rows:
            self._insert(self.table.rowCount(), row)
        self._filling = False
        self.refresh()

    def _insert(self, r: int, row: dict[str, Any]) -> None:
        from PySide import QtGui

        self.table.insertRow(r)
        for c, (field, p) in enumerate(self.cols):
            value = row.get(field)
            if p.kind == "str" and p.choices:
                combo = QtGui.QComboBox()
                choices = ([""] if p.optional else []) + list(p.choices)
                combo.addItems(choices)
                combo.setCurrentIndex(choices.index(value) if value in choices else 0)
                combo.currentIndexChanged.connect(lambda *_: self.refresh())
                self.table.setCellWidget(r, c, combo)
            else:
                text = "" if value is None else (f"{value:.12g}" if isinstance(value, float) else str(value))
                self.table.setItem(r, c, QtGui.QTableWidgetItem(text))

    def rows(self) -> list[dict[str, Any]]:
        """The table as spec dicts; a cell that is not a number is passed on as text so that
        validation names it."""
        out = []
        for r in range(self.table.rowCount()):
            row: dict[str, Any] = {}
            for c, (field, p) in enumerate(self.cols):
                widget = self.table.cellWidget(r, c)
                if widget is not None:
                    text = widget.currentText()
                else:
                    item = self.table.item(r, c)
                    text = item.text().strip() if item is not None else ""
                if text == "":
                    continue
                row[field] = _parse(text, p.kind)
            out.append(row)
        return out

    # -- buttons
    def add_row(self) -> None:
        r = self.table.currentRow()
        r = self.table.rowCount() if r < 0 else r + 1
        self._filling = True
        self._insert(r, {"kind": "dwell", "angle": 10.0})
        self._filling = False
        self.table.setCurrentCell(r, 0)
        self.refresh()

    def remove_row(self) -> None:
        r = self.table.currentRow()
        if r >= 0:
            self.table.removeRow(r)
            self.refresh()

    def move_row(self, step: int) -> None:
        r = self.table.currentRow()
        rows = self.rows()
        t = r + step
        if r < 0 or not 0 <= t < len(rows):
            return
        rows[r], rows[t] = rows[t], rows[r]
        self.set_rows(rows)
        self.table.setCurrentCell(t, 0)

    def refresh(self) -> None:
        if self._filling:
            return
        rows = self.rows()
        total = sum(r["angle"] for r in rows if isinstance(r.get("angle"), float))
        self.total.setText(f"{len(rows)} segments, angles sum to {total:g}° (must be 360°)")
        msg = validate_rows(self.obj, rows)
        self.status.setText("OK" if msg is None else msg)
        self.status.setStyleSheet("color: #1a7f37" if msg is None else "color: #c62828")

    # -- task dialog protocol
    def getStandardButtons(self) -> int:
        from PySide import QtGui

        return int(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel)

    def accept(self) -> bool:
        rows = self.rows()
        msg = validate_rows(self.obj, rows, design=True)
        if msg is not None:
            self.status.setText(msg)
            self.status.setStyleSheet("color: #c62828")
            import FreeCAD

            FreeCAD.Console.PrintError(f"{self.obj.Label}: motion program not applied: {msg}\n")
            return False
        apply_rows(self.obj, rows)
        self._leave()
        return True

    def reject(self) -> bool:
        self._leave()
        return True

    def _leave(self) -> None:
        """End editing: through the document's edit mode when the panel came from
        ``setEdit`` (the view provider's ``unsetEdit`` closes the panel), else directly."""
        import FreeCADGui

        gdoc = FreeCADGui.getDocument(self.obj.Document.Name)
        if gdoc is not None and gdoc.getInEdit() is not None:
            gdoc.resetEdit()
        else:
            FreeCADGui.Control.closeDialog()


def _parse(text: str, kind: str) -> Any:
    if kind == "float":
        try:
            return float(text)
        except ValueError:
            return text
    if kind == "int":
        try:
            return int(text)
        except ValueError:
            try:
                return float(text)
            except ValueError:
                return text
    return text


def open_editor(obj: Any) -> None:
    """Edit ``obj``'s motion program: enters edit mode, whose view provider shows the panel
    (the same path as a double-click in the tree)."""
    import FreeCADGui

    if FreeCADGui.Control.activeDialog():
        FreeCADGui.Control.closeDialog()
    FreeCADGui.getDocument(obj.Document.Name).setEdit(obj, 0)

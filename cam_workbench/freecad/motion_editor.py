"""The motion-program editor: a task panel with the ``[[motion]]`` segments as a table.

The segments are the table's rows (one column per declared field but the control points);
a ``law = "bspline"`` segment's control polygon is edited in a second table below it, one
row per interior control point P1 … P(n−1) with its cam angle x (in the segment's
``control_frame``) and normalised lift y — the first and last k − 1 points sit at the end
levels and are shown greyed (thesis §2.7).  The logic (:func:`validate_rows`,
:func:`apply_rows`, :func:`control_points`, :func:`points_to_fields`) works headless; the Qt
panel (:class:`MotionEditorPanel`) is only built in the GUI.  Applying writes every motion
list of the feature and recomputes inside ONE transaction, so a single Undo restores
the previous program (and shape).  Nothing is written unless the program passes the
spec rules and the cam can be made; messages name the row, the field and the control point
(``row 1, control_x[3] (P4): must be a number, got 'abc'``).

FreeCAD and Qt are imported inside the panel's methods: the logic imports in any Python
(``tests/test_freecad_properties.py`` runs it without FreeCAD).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

from cam_workbench.generators.cam_design import design_cam
from cam_workbench.generators.errors import CamError, SpecError
from cam_workbench.generators.motion.bspline_law import DEFAULT_ORDER, DEFAULT_POINTS
from cam_workbench.generators.spec.params import params_of, unit_name
from cam_workbench.generators.spec import LIFT_FIELDS, CamSpec, MotionSegment

from . import properties as props
from .qt_compat import fit_task_width, standard_buttons

SECTION = "motion"
TRANSACTION = "Edit motion program"
#: The control polygon's fields: edited in the control-point table, not as columns.
POINT_FIELDS = ("control_x", "control_y")
_ROW_PATH = re.compile(r"^motion\[(\d+)\]\.(\w+)(?:\[(\d+)\])?$")


def columns() -> list[tuple[str, Any]]:
    """(field, Param) of a motion segment, in declaration order: the table's columns (the
    control points have their own table)."""
    return [(f, p) for f, p in params_of(MotionSegment).items() if f not in POINT_FIELDS]


# ---- B-spline control polygons (thesis §2.5–2.7) ----------------------------------------------
@dataclass(frozen=True)
class ControlPoint:
    """An interior control point P_i (1 ≤ i ≤ n − 1) of a B-spline segment."""

    index: int
    x: Any                 # cam angle in the segment's control_frame (float, or text to be named)
    y: Any                 # normalised lift
    fixed: bool            # at an end level (the first / last k − 1 points): y is not free


def _order(row: dict[str, Any]) -> int:
    k = row.get("order")
    return k if isinstance(k, int) and 3 <= k <= 10 else DEFAULT_ORDER


def _levels(row: dict[str, Any]) -> tuple[float, float]:
    return (1.0, 0.0) if row.get("kind") == "return" else (0.0, 1.0)


def control_points(row: dict[str, Any]) -> list[ControlPoint]:
    """The interior control points of a ``law = "bspline"`` row as a table: x from
    ``control_x``; y from ``control_y`` given either for the free points P(k−1) … P(n−k+1)
    only (the thesis' way) or for all interior points.  Fixed points show their end level.
    A ``control_y`` whose length fits neither is shown as far as it goes (validation names it)."""
    xs = list(row.get("control_x") or ())
    ys = list(row.get("control_y") or ())
    n = len(xs) + 1
    nfix = _order(row) - 1
    y0, y1 = _levels(row)
    n_free = max(n + 1 - 2 * nfix, 0)
    all_given = len(ys) == n - 1 and len(ys) != n_free
    out = []
    for i in range(1, n):
        fixed = i < nfix or i > n - nfix
        if all_given:
            y = ys[i - 1]
        elif fixed:
            y = y0 if i < nfix else y1
        else:
            j = i - nfix
            y = ys[j] if 0 <= j < len(ys) else None
        out.append(ControlPoint(i, xs[i - 1], y, fixed))
    return out


def points_to_fields(row: dict[str, Any], xs: list[Any], ys: list[Any]) -> dict[str, Any]:
    """``control_x`` and ``control_y`` of a row from the table's columns (all interior points):
    ``control_y`` keeps the row's format — all interior points if it had them, else the free
    ones only."""
    n = len(xs) + 1
    nfix = _order(row) - 1
    old_y = list(row.get("control_y") or ())
    old_n = len(row.get("control_x") or ()) + 1
    old_free = max(old_n + 1 - 2 * nfix, 0)
    keep_all = len(old_y) == old_n - 1 and len(old_y) != old_free
    if keep_all:
        cy = list(ys)
    else:
        cy = [ys[i - 1] for i in range(1, n) if not (i < nfix or i > n - nfix)]
    return {"control_x": tuple(xs), "control_y": tuple(cy)}


def default_polygon(row: dict[str, Any]) -> dict[str, Any]:
    """A starting polygon for a row switched to ``law = "bspline"``: the thesis' order 5 with
    11 control points, equally spaced in θ (degrees from the segment start), the free lifts
    P4 … P6 at ¼, ½, ¾ of the way — a smooth, valid rise or return to shape from."""
    angle = row.get("angle") if isinstance(row.get("angle"), float) else 90.0
    n = DEFAULT_POINTS - 1
    xs = tuple(round(angle * i / n, 9) for i in range(1, n))
    ys = (0.25, 0.5, 0.75) if row.get("kind") != "return" else (0.75, 0.5, 0.25)
    assert n + 1 - 2 * (DEFAULT_ORDER - 1) == len(ys)
    return {"control_x": xs, "control_y": ys}


def read_rows(obj: Any) -> list[dict[str, Any]]:
    """The feature's motion segments as spec dicts (lengths in the spec's units)."""
    return props.read_rows(obj, SECTION)


def row_message(exc: SpecError, rows: list[dict[str, Any]] | None = None) -> str:
    """A spec error worded for the table: ``motion[3].angle`` → ``row 4, angle``;
    ``motion[0].control_x[3]`` → ``row 1, control_x[3] (P4)``."""
    m = _ROW_PATH.match(exc.field)
    if not m:
        return f"{exc.field}: {exc.rule}"
    r, field, idx = int(m.group(1)), m.group(2), m.group(3)
    where = f"row {r + 1}, {field}"
    if idx is not None:
        j = int(idx)
        where += f"[{j}]"
        point = None
        if field == "control_x":
            point = j + 1
        elif field == "control_y" and rows is not None and r < len(rows):
            pts = control_points(rows[r])
            free = [p.index for p in pts if not p.fixed]
            given = rows[r].get("control_y") or ()
            if len(given) == len(pts) and len(given) != len(free):
                point = j + 1
            elif j < len(free):
                point = free[j]
        if point is not None:
            where += f" (P{point})"
    return f"{where}: {exc.rule}"


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
            design_cam(spec)
    except SpecError as exc:
        return row_message(exc, rows)
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
    """Task panel: one table row per motion segment (add/remove/move rows) and, for the
    selected B-spline segment, its control points; live validation."""

    def __init__(self, obj: Any):
        # deferred: PySide, FreeCAD's shim: PySide2 in 0.20, PySide6 in 1.x (see the module docstring)
        from PySide import QtGui

        self.obj = obj
        self.units = getattr(obj, "Units", "mm")
        self.lift = props.lift_unit_of(obj)   # lifts: the spec's length, or an arm's degrees
        self.cols = columns()
        self.extra: list[dict[str, Any]] = []   # control_x / control_y of each row
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("Motion program")
        layout = QtGui.QVBoxLayout(self.form)
        self.table = QtGui.QTableWidget(0, len(self.cols))
        self.table.setHorizontalHeaderLabels([self._header(f, p) for f, p in self.cols])
        for i, (_f, p) in enumerate(self.cols):
            self.table.horizontalHeaderItem(i).setToolTip(p.doc)
        self.table.horizontalHeader().setStretchLastSection(True)
        self.table.setSelectionBehavior(QtGui.QAbstractItemView.SelectRows)
        layout.addWidget(self.table, 3)
        buttons = QtGui.QHBoxLayout()
        for text, slot in (("Add", self.add_row), ("Remove", self.remove_row),
                           ("Up", lambda: self.move_row(-1)), ("Down", lambda: self.move_row(1))):
            b = QtGui.QPushButton(text)
            b.clicked.connect(slot)
            buttons.addWidget(b)
        layout.addLayout(buttons)
        # the selected B-spline segment's control polygon
        self.points_box = QtGui.QGroupBox("B-spline control points")
        pl = QtGui.QVBoxLayout(self.points_box)
        self.points_note = QtGui.QLabel()
        self.points_note.setWordWrap(True)
        pl.addWidget(self.points_note)
        self.points = QtGui.QTableWidget(0, 2)
        self.points.horizontalHeader().setSectionResizeMode(QtGui.QHeaderView.Stretch)
        self.points.verticalHeader().setDefaultSectionSize(self.points.fontMetrics().height() + 8)
        params = params_of(MotionSegment)
        pl.addWidget(self.points)
        pb = QtGui.QHBoxLayout()
        for text, slot in (("Add point", self.add_point), ("Remove point", self.remove_point)):
            b = QtGui.QPushButton(text)
            b.clicked.connect(slot)
            pb.addWidget(b)
        pl.addLayout(pb)
        self._x_doc, self._y_doc = params["control_x"].doc, params["control_y"].doc
        layout.addWidget(self.points_box, 2)
        self.total = QtGui.QLabel()
        self.status = QtGui.QLabel()
        self.status.setWordWrap(True)
        layout.addWidget(self.total)
        layout.addWidget(self.status)

        fit_task_width(self.form)
        self._filling = False
        self._points_row = -1
        self.set_rows(read_rows(obj))
        self.table.itemChanged.connect(lambda *_: self.refresh())
        self.points.itemChanged.connect(lambda *_: self._points_edited())
        self.table.currentCellChanged.connect(lambda *_: self.show_points())
        first = next((i for i, r in enumerate(self.rows()) if r.get("law") == "bspline"), 0)
        if self.table.rowCount():
            self.table.setCurrentCell(first, 0)
        self.show_points()

    def _header(self, field: str, p: Any) -> str:
        lift_angle = self.lift == "angle" and f"{SECTION}[].{field}" in LIFT_FIELDS
        # an arm's lifts are degrees: its derivatives per radian of cam rotation °/rad, °/rad², °/rad³
        per_rad = {"reduced_velocity": "/rad", "reduced_acceleration": "/rad²", "reduced_jerk": "/rad³"}
        unit = ("°" + per_rad.get(p.unit, "") if lift_angle else
                "°" if p.unit == "angle" else unit_name(p.unit, self.units))
        return f"{field} [{unit}]" if unit else field

    # -- table <-> rows
    def set_rows(self, rows: list[dict[str, Any]]) -> None:
        self._filling = True
        self.table.setRowCount(0)
        self.extra = []
        for row in rows:
            self._insert(self.table.rowCount(), row)
        self._filling = False
        self.refresh()

    def _insert(self, r: int, row: dict[str, Any]) -> None:
        from PySide import QtGui  # deferred: PySide (see the module docstring)

        self.table.insertRow(r)
        self.extra.insert(r, {f: row[f] for f in POINT_FIELDS if f in row})
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
                text = "" if value is None else (f"{value:.12g}" if isinstance(value, float) else
                                                 props.format_points(value) if p.kind == "points" else str(value))
                self.table.setItem(r, c, QtGui.QTableWidgetItem(text))

    def _table_row(self, r: int) -> dict[str, Any]:
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
        return row

    def rows(self) -> list[dict[str, Any]]:
        """The table as spec dicts; a cell that is not a number is passed on as text so that
        validation names it.  Control points are kept only on B-spline rows."""
        out = []
        for r in range(self.table.rowCount()):
            row = self._table_row(r)
            if row.get("law") == "bspline":
                row.update(self.extra[r])
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
            self._filling = True
            self.table.removeRow(r)
            del self.extra[r]
            self._filling = False
            self.refresh()

    def move_row(self, step: int) -> None:
        r = self.table.currentRow()
        rows = [dict(self._table_row(i), **self.extra[i]) for i in range(self.table.rowCount())]
        t = r + step
        if r < 0 or not 0 <= t < len(rows):
            return
        rows[r], rows[t] = rows[t], rows[r]
        self.set_rows(rows)
        self.table.setCurrentCell(t, 0)

    # -- control points of the selected row
    def _frame_label(self, row: dict[str, Any]) -> str:
        if row.get("control_frame") == "absolute_rad":
            return "x [rad, cam angle]"
        return "x [° from segment start]"

    def show_points(self) -> None:
        """Fill the control-point table from the selected row (disabled for other laws)."""
        from PySide import QtCore, QtGui  # deferred: PySide (see the module docstring)

        r = self.table.currentRow()
        self._points_row = r
        row = self._table_row(r) if r >= 0 else {}
        is_bspline = row.get("law") == "bspline"
        self._filling = True
        self.points.setRowCount(0)
        self.points_box.setEnabled(is_bspline)
        if not is_bspline:
            self.points_box.setTitle("B-spline control points")
            self.points_note.setText("Select a row with law = bspline to edit its control points."
                                     if r < 0 or not row.get("law") else
                                     f"Row {r + 1} uses the {row.get('law')} law: no control points.")
            self._filling = False
            return
        row.update(self.extra[r])
        pts = control_points(row)
        k = _order(row)
        self.points_box.setTitle(f"B-spline control points of row {r + 1} ({row.get('kind', '?')})")
        self.points_note.setText(
            f"Order {k}, {len(pts) + 2} points P0 … P{len(pts) + 1}: P0 and P{len(pts) + 1} sit at the "
            f"segment's ends; the first and last {k - 1} are at the end levels (grey y).")
        self.points.setColumnCount(2)
        self.points.setHorizontalHeaderLabels([self._frame_label(row), "y (normalised lift)"])
        self.points.horizontalHeaderItem(0).setToolTip(self._x_doc)
        self.points.horizontalHeaderItem(1).setToolTip(self._y_doc)
        self.points.setVerticalHeaderLabels([])
        self.points.setRowCount(len(pts))
        self.points.setVerticalHeaderLabels([f"P{p.index}" for p in pts])
        grey = QtGui.QBrush(QtGui.QColor(150, 150, 150))
        for i, p in enumerate(pts):
            for c, v in enumerate((p.x, p.y)):
                text = "" if v is None else (f"{v:.12g}" if isinstance(v, float) else str(v))
                item = QtGui.QTableWidgetItem(text)
                if c == 1 and p.fixed:
                    item.setFlags(item.flags() & ~QtCore.Qt.ItemIsEditable)
                    item.setForeground(grey)
                    item.setToolTip("at the end level: fixed by the order (thesis §2.7)")
                self.points.setItem(i, c, item)
        self._filling = False

    def _point_columns(self) -> tuple[list[Any], list[Any]]:
        xs, ys = [], []
        for i in range(self.points.rowCount()):
            for c, out in ((0, xs), (1, ys)):
                item = self.points.item(i, c)
                text = item.text().strip() if item is not None else ""
                out.append(_parse(text, "float") if text else None)
        return xs, ys

    def _points_edited(self) -> None:
        if self._filling or self._points_row < 0:
            return
        r = self._points_row
        row = dict(self._table_row(r), **self.extra[r])
        xs, ys = self._point_columns()
        self.extra[r] = points_to_fields(row, xs, ys)
        self.refresh()

    def _end_x(self, row: dict[str, Any], r: int) -> tuple[float, float]:
        """P0's and Pn's x in the row's control frame."""
        angle = row.get("angle") if isinstance(row.get("angle"), float) else 0.0
        if row.get("control_frame") != "absolute_rad":
            return 0.0, angle
        before = sum(rr.get("angle", 0.0) for rr in (self._table_row(i) for i in range(r))
                     if isinstance(rr.get("angle"), float))
        start = row.get("control_start") if isinstance(row.get("control_start"), float) else before
        return math.radians(start), math.radians(start + angle)

    def add_point(self) -> None:
        """Insert a control point after the selected one (halfway to the next)."""
        r = self._points_row
        if r < 0:
            return
        row = dict(self._table_row(r), **self.extra[r])
        xs, ys = self._point_columns()
        i = self.points.currentRow()
        i = len(xs) - 1 if i < 0 else i
        x0, xn = self._end_x(row, r)
        fx = [x0] + xs + [xn]
        fy = [_levels(row)[0]] + ys + [_levels(row)[1]]
        a, b = i + 1, i + 2                     # the new point goes between full indices a and b
        try:
            x_new = (float(fx[a]) + float(fx[b])) / 2
            y_new = (float(fy[a]) + float(fy[b])) / 2
        except (TypeError, ValueError):
            return
        xs.insert(i + 1, round(x_new, 9))
        ys.insert(i + 1, round(y_new, 9))
        self.extra[r] = points_to_fields(row, xs, ys)
        self.refresh()
        self.points.setCurrentCell(i + 1, 0)

    def remove_point(self) -> None:
        r = self._points_row
        i = self.points.currentRow()
        if r < 0 or i < 0:
            return
        row = dict(self._table_row(r), **self.extra[r])
        xs, ys = self._point_columns()
        del xs[i], ys[i]
        self.extra[r] = points_to_fields(row, xs, ys)
        self.refresh()

    def refresh(self) -> None:
        if self._filling:
            return
        for r in range(self.table.rowCount()):
            row = self._table_row(r)
            if row.get("law") == "bspline" and not self.extra[r].get("control_x"):
                self.extra[r] = default_polygon(row)
        rows = self.rows()
        total = sum(r["angle"] for r in rows if isinstance(r.get("angle"), float))
        self.total.setText(f"{len(rows)} segments, angles sum to {total:g}° (must be 360°)")
        msg = validate_rows(self.obj, rows)
        self.status.setText("OK" if msg is None else msg)
        self.status.setStyleSheet("color: #1a7f37" if msg is None else "color: #c62828")
        current = (self.points.currentRow(), self.points.currentColumn())
        self.show_points()
        if current[0] >= 0 and current[0] < self.points.rowCount():
            self.points.setCurrentCell(*current)

    # -- task dialog protocol
    def getStandardButtons(self) -> int:
        return standard_buttons("Ok", "Cancel")

    def accept(self) -> bool:
        rows = self.rows()
        msg = validate_rows(self.obj, rows, design=True)
        if msg is not None:
            self.status.setText(msg)
            self.status.setStyleSheet("color: #c62828")
            import FreeCAD  # deferred: FreeCAD (see the module docstring)

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
        import FreeCADGui  # deferred: FreeCADGui (see the module docstring)

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
    if kind == "points":         # "angle, lift; angle, lift" (a polynomial's points, a motion table)
        try:
            return [list(r) for r in props.parse_points(text, "")]
        except SpecError:
            return text           # the spec's validation names the row
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
    import FreeCADGui  # deferred: FreeCADGui (see the module docstring)

    if FreeCADGui.Control.activeDialog():
        FreeCADGui.Control.closeDialog()
    FreeCADGui.getDocument(obj.Document.Name).setEdit(obj, 0)

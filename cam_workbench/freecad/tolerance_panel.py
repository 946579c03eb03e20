"""Tolerance study of a ``Cam`` feature: the largest profile tolerance per number of waves per turn
that keeps the follower's acceleration error within a share of the designed peak at the feature's
``SpeedRpm`` — :func:`cam_workbench.tolerance.tolerance_study`, the function ``cam-workbench
tolerance`` calls, so the rows are tolerance.json's (docs/tolerances.md).

:func:`tolerance_report` is headless (``freecadcmd``); :func:`show_tolerance` prints the table to
the report view and shows it with the chart in a dialog.
"""
from __future__ import annotations

from typing import Any

from cam_workbench.exporters.report_cells import format_number as fmt
from cam_workbench.tolerance import tolerance_study

from . import properties as props

#: the dialogs kept alive while shown
_DIALOGS: list[Any] = []
HEADERS = ["waves per turn", "tolerance t", "acceleration limit t_a", "contact limit t_c", "governed by"]


def tolerance_report(obj: Any, acceleration_limit: float = 0.05, max_waves: int = 200) -> dict[str, Any]:
    """The feature's tolerance study as tolerance.json's numbers (``summary()``).

    Raises:
        SpecError: a property breaks a rule, or the body is not a plane cam.
        GeometryError: the cam cannot be made.
    """
    return tolerance_study(props.spec_of(obj), acceleration_limit, max_waves).summary()


def table_rows(d: dict[str, Any]) -> list[list[str]]:
    """The rows the dialog and the report view show (the CLI's table: tolerance.json's ``table``)."""
    return [[str(r["waves"]), fmt(r["tolerance"]), fmt(r["acceleration_tolerance"]), fmt(r["contact_tolerance"]),
             r["governed_by"]] for r in d["table"]]


def headline(d: dict[str, Any]) -> str:
    """One line: the target and the tightest tolerance."""
    t = d["tightest"]
    return (f"acceleration error ≤ {fmt(100 * d['acceleration_limit'])} % of the designed peak "
            f"{fmt(d['designed_peak_acceleration'])} {d['acceleration_unit']} at {fmt(d['speed_rpm'])} rpm: "
            f"tightest t = {fmt(t['tolerance'])} {d['units']} at {t['waves']} waves per turn ({t['governed_by']})")


def show_tolerance(obj: Any) -> dict[str, Any]:
    """Run the study on ``obj``, print it to the report view and show the table and the chart."""
    import FreeCAD  # deferred: FreeCAD (the dialog only: the study runs in any Python)
    import FreeCADGui  # deferred: FreeCADGui (the GUI's; this module is App side)
    from PySide import QtCore, QtGui  # deferred: PySide (the dialog only)

    QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
    try:
        study = tolerance_study(props.spec_of(obj))
        d, svg_text = study.summary(), study.svg()
    finally:
        QtGui.QApplication.restoreOverrideCursor()
    rows = table_rows(d)
    FreeCAD.Console.PrintMessage(f"{obj.Label}: tolerance study: {headline(d)}\n"
                                 + "".join(" | ".join(r) + "\n" for r in [HEADERS] + rows))
    dlg = QtGui.QDialog(FreeCADGui.getMainWindow())
    dlg.setObjectName("CamWorkbenchTolerance")
    dlg.setWindowTitle(f"Tolerance study — {obj.Label}")
    layout = QtGui.QVBoxLayout(dlg)
    head = QtGui.QLabel(f"{d['cam']}\n{headline(d)}\nProfile tolerance t [{d['units']}]: ISO 1101 profile of a "
                        "line, zone ±t/2 along the normal, worst phase of a wave of n waves per turn (docs/tolerances.md)")
    head.setWordWrap(True)
    layout.addWidget(head)
    try:
        from PySide import QtSvg  # deferred: PySide (the chart, when the binding has QtSvg)

        chart = QtSvg.QSvgWidget()
        chart.load(QtCore.QByteArray(svg_text.encode("utf-8")))
        chart.setMinimumHeight(360)
        layout.addWidget(chart, 3)
    except ImportError:
        pass
    table = QtGui.QTableWidget(len(rows), len(HEADERS))
    table.setObjectName("tolerance")
    table.setHorizontalHeaderLabels(HEADERS)
    for i, row in enumerate(rows):
        for j, cell in enumerate(row):
            table.setItem(i, j, QtGui.QTableWidgetItem(cell))
    table.resizeColumnsToContents()
    layout.addWidget(table, 2)
    close = QtGui.QPushButton("Close")
    close.clicked.connect(dlg.accept)
    layout.addWidget(close)
    dlg.resize(820, 720)
    dlg.setModal(False)
    dlg.show()
    _DIALOGS.append(dlg)
    dlg.finished.connect(lambda *_: _DIALOGS.remove(dlg) if dlg in _DIALOGS else None)
    return d

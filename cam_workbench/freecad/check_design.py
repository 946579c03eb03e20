"""Check design: the buildability checks and the design numbers of a ``PlateCam`` feature.

What exists today: ``generators.design_cam`` (undercut, self-intersection and bore checks,
which raise with the cam angle) and ``CamDesign.summary()`` (the numbers of report.json),
plus FreeCAD's own verdict on the built solid.  :func:`design_report` is headless; the
dialog (:func:`show_report`) only renders it.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from generators.errors import CamError, GeometryError, SpecError

from . import properties as props


@dataclass
class DesignReport:
    """Rows of (group, item, value, status); status is "pass", "FAIL" or "" (information)."""

    ok: bool
    error: str | None = None
    rows: list[tuple[str, str, str, str]] = field(default_factory=list)

    def text(self) -> str:
        lines = [f"{'PASS' if self.ok else 'FAIL'}" + (f": {self.error}" if self.error else "")]
        for group, item, value, status in self.rows:
            lines.append(f"  {group:<15} {item:<34} {value:<28} {status}")
        return "\n".join(lines)


def _deg(v: float | None) -> str:
    return "—" if v is None else f"{v:.3f}°"


def design_report(obj: Any) -> DesignReport:
    """Design the feature's cam and collect the checks and numbers (no shape is changed)."""
    from generators.cam_design import design_cam

    try:
        spec = props.spec_of(obj)
    except SpecError as exc:
        return DesignReport(False, f"{props.describe_field(exc.field)}: {exc.rule}")
    try:
        design = design_cam(spec)
    except GeometryError as exc:
        where = f" at cam angle {exc.angle_deg:.2f}°" if exc.angle_deg is not None else ""
        return DesignReport(False, f"the cam cannot be made ({exc.kind}{where}): {exc}",
                            [("Buildability", exc.kind.replace("_", " "), str(exc), "FAIL")])
    except CamError as exc:
        return DesignReport(False, f"the cam cannot be made: {exc}")
    s = design.summary()
    u = s["units"]
    rows: list[tuple[str, str, str, str]] = [
        ("Buildability", "undercut (roller vs. convex curvature)", "none", "pass"),
        ("Buildability", "profile self-intersection", "none", "pass"),
        ("Buildability", "bore inside the profile",
         f"min profile radius {s['profile']['min_radius']:.4g} {u}", "pass"),
    ]
    p = s["pitch"]
    rows += [
        ("Pitch curve", "PH quintic segments M", str(p["segments"]), ""),
        ("Pitch curve", "max follower deviation",
         f"{p['max_deviation']:.3g} {u} at {p['max_deviation_at_deg']:.2f}°",
         "" if p["tolerance"] is None else ("pass" if p["max_deviation"] <= p["tolerance"] else "FAIL")),
        ("Pitch curve", "arc length", f"{p['arc_length']:.6g} {u}", ""),
    ]
    pa = s["pressure_angle"]
    rows += [
        ("Pressure angle", "max |φ| (design)", f"{pa['max_deg']:.3f}° at {pa['at_deg']:.2f}°", ""),
        ("Pressure angle", "max |φ| (as built)",
         f"{pa['as_built']['max_deg']:.3f}° at {pa['as_built']['at_deg']:.2f}°", ""),
    ]
    c = s["curvature"]
    rows += [
        ("Curvature", "min convex pitch radius", f"{c['min_pitch_radius']:.4g} {u} at {c['at_deg']:.2f}°", ""),
        ("Curvature", "min convex profile radius", f"{c['min_profile_radius']:.4g} {u}", ""),
        ("Curvature", "min concave pitch radius",
         "—" if c["min_concave_pitch_radius"] is None else f"{c['min_concave_pitch_radius']:.4g} {u}", ""),
    ]
    m = s["motion"]
    rows += [
        ("Motion", "max lift", f"{m['max_lift']:.6g} {u}", ""),
        ("Motion", "max velocity", f"{m['max_velocity']:.6g} {u}/s", ""),
        ("Motion", "max acceleration", f"{m['max_acceleration']:.6g} {u}/s²", ""),
        ("Motion", "max jerk", f"{m['max_jerk']:.6g} {u}/s³", ""),
    ]
    pr = s["profile"]
    rows += [
        ("Profile", "NURBS", f"degree {pr['degree']}, {pr['poles']} poles, "
                             f"{'rational' if pr['rational'] else 'polynomial'}", ""),
        ("Profile", "cross-section area", f"{s['area']:.8g} {u}²", ""),
        ("Profile", "volume", f"{s['volume']:.8g} {u}³", ""),
    ]
    rows += _kernel_rows(obj, design)
    ok = all(r[3] != "FAIL" for r in rows)
    return DesignReport(ok, None, rows)


def _kernel_rows(obj: Any, design: Any) -> list[tuple[str, str, str, str]]:
    """FreeCAD's verdict on the feature's current solid (if it is built from this design)."""
    shape = getattr(obj, "Shape", None)
    if shape is None or shape.isNull() or not str(getattr(obj, "Status", "")).startswith("ok"):
        return [("FreeCAD solid", "state", "not built from the current properties", "")]
    scale = props.units_scale(obj)
    exact = design.volume * scale**3
    rel = abs(shape.Volume - exact) / exact
    valid = shape.isValid() and len(shape.Solids) == 1
    return [
        ("FreeCAD solid", "valid, one solid", "yes" if valid else "no", "pass" if valid else "FAIL"),
        ("FreeCAD solid", "kernel volume vs exact", f"{rel:.2e} relative", ""),
    ]


def show_report(obj: Any) -> DesignReport:
    """Print the report to the report view and show it in a dialog."""
    import FreeCAD
    import FreeCADGui
    from PySide import QtGui

    report = design_report(obj)
    (FreeCAD.Console.PrintMessage if report.ok else FreeCAD.Console.PrintError)(
        f"{obj.Label}: check design: {report.text()}\n")
    dlg = QtGui.QDialog(FreeCADGui.getMainWindow())
    dlg.setWindowTitle(f"Check design — {obj.Label}")
    layout = QtGui.QVBoxLayout(dlg)
    head = QtGui.QLabel(("All checks pass" if report.ok else "Check FAILED") +
                        (f": {report.error}" if report.error else ""))
    head.setWordWrap(True)
    head.setStyleSheet("font-weight: bold; color: " + ("#1a7f37" if report.ok else "#c62828"))
    layout.addWidget(head)
    table = QtGui.QTableWidget(len(report.rows), 4)
    table.setHorizontalHeaderLabels(["Group", "Check / quantity", "Value", "Status"])
    for r, row in enumerate(report.rows):
        for c, text in enumerate(row):
            table.setItem(r, c, QtGui.QTableWidgetItem(text))
    table.resizeColumnsToContents()
    table.horizontalHeader().setStretchLastSection(True)
    layout.addWidget(table)
    note = QtGui.QLabel("Limits on pressure angle, curvature, force and stress come with the "
                        "[checks] section of the spec (not in this version).")
    note.setWordWrap(True)
    layout.addWidget(note)
    close = QtGui.QPushButton("Close")
    close.clicked.connect(dlg.accept)
    layout.addWidget(close)
    dlg.resize(820, 560)
    dlg.setModal(False)
    dlg.show()
    _DIALOGS.append(dlg)
    dlg.finished.connect(lambda *_: _DIALOGS.remove(dlg) if dlg in _DIALOGS else None)
    return report


_DIALOGS: list[Any] = []  # keep non-modal dialogs alive until closed

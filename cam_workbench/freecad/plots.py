"""Kinematics plots of a ``Cam`` feature (matplotlib, shown in a FreeCAD dialog).

:func:`kinematics_figure` builds a ``matplotlib.figure.Figure`` without pyplot (so it
works headless and in FreeCAD's Qt alike); :func:`show_plots` embeds it in a dialog with
matplotlib's toolbar (zoom, save as PNG/SVG/PDF).  Debian's ``freecad-python3`` depends on
``python3-matplotlib``; where FreeCAD's Python has no matplotlib the command says so.
"""
from __future__ import annotations

from typing import Any

import FreeCAD
import numpy as np

from cam_workbench.generators.errors import CamError

from . import properties as props
from .feature import build


def kinematics_data(design: Any, samples_per_segment: int = 721) -> dict[str, np.ndarray]:
    """Cam angle [deg] and the follower's s, v, a, j per second at the spec's speed, the
    pressure angle [deg] (design intent) and the built pitch curve's displacement error."""
    spec = design.spec
    omega = spec.cam.speed_rpm * 2 * np.pi / 60
    prog = design.program
    # every segment sampled on its own closed interval and evaluated from inside it (one-sided
    # limits at the ends), so jumps of a, j at the boundaries are drawn as jumps, not ramps
    x = np.linspace(0.0, 1.0, samples_per_segment)
    inside = 1e-12 + (1 - 2e-12) * x
    th = (prog.starts[:, None] + prog.spans[:, None] * x[None, :]).ravel()
    k = prog.evaluate((prog.starts[:, None] + prog.spans[:, None] * inside[None, :]).ravel())
    phi = np.rad2deg(design.geometry.pressure_angle(k))
    th_err = np.linspace(0.0, 2 * np.pi, 3601)
    err = design.pitch.actual_displacement(th_err) - design.program.s(th_err)
    return {
        "theta_deg": np.rad2deg(th), "s": k.s, "v": k.ds * omega, "a": k.d2s * omega**2,
        "j": k.d3s * omega**3, "phi_deg": phi,
        "theta_err_deg": np.rad2deg(th_err), "deviation": err,
        "boundaries_deg": np.rad2deg(design.program.boundaries),
    }


def kinematics_figure(design: Any, title: str = "") -> Any:
    """A matplotlib Figure: displacement, velocity, acceleration, jerk, pressure angle and
    the displacement error of the built PH pitch curve against cam angle — lifts in the
    follower's lift unit (the spec's length, or degrees of an oscillating arm's rotation)."""
    from matplotlib.figure import Figure  # deferred: matplotlib (optional in FreeCAD's Python; slow)

    d = kinematics_data(design)
    fol = design.follower
    desc = fol.describe()
    u = "deg" if fol.lift_unit == "angle" else design.spec.units
    fig = Figure(figsize=(8.5, 10.5), dpi=100, layout="constrained")  # re-laid out on resize
    axes = fig.subplots(6, 1, sharex=True)
    panels = [
        ("s", f"s [{u}]", "displacement"),
        ("v", f"v [{u}/s]", "velocity"),
        ("a", f"a [{u}/s²]", "acceleration"),
        ("j", f"j [{u}/s³]", "jerk"),
        ("phi_deg", "φ [°]", "pressure angle"),
    ]
    for ax, (key, ylabel, name) in zip(axes, panels):
        ax.plot(d["theta_deg"], d[key], lw=1.2, color="#1f5fbf")
        ax.set_ylabel(ylabel)
        ax.set_title(name, fontsize=9, loc="left")
    ax = axes[-1]
    ax.plot(d["theta_err_deg"], d["deviation"], lw=1.0, color="#c0392b")
    ax.set_ylabel(f"Δs [{u}]")
    ax.set_title(f"built {desc['curve']}: s_actual − s (M = {design.pitch.M})", fontsize=9, loc="left")
    for ax in axes:
        for b in d["boundaries_deg"]:
            ax.axvline(b, color="0.8", lw=0.6, zorder=0)
        ax.grid(True, lw=0.3, alpha=0.6)
        ax.axhline(0.0, color="0.5", lw=0.5)
    axes[-1].set_xlabel("cam angle θ [°]")
    axes[-1].set_xlim(0, 360)
    axes[-1].set_xticks(np.arange(0, 361, 30))
    spec = design.spec
    fig.suptitle(title or f"Follower kinematics at {spec.cam.speed_rpm:g} rpm "
                          f"({desc['label']} {spec.units})", fontsize=11)
    return fig


def save_figure(fig: Any, path: str) -> None:
    """Write the figure as PNG (Agg canvas; no GUI needed)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg  # deferred: matplotlib (optional; slow)

    FigureCanvasAgg(fig)
    fig.savefig(path)


_DIALOGS: list[Any] = []


def show_plots(obj: Any) -> Any:
    """Show the kinematics of ``obj``'s cam in a dialog; report why if it cannot."""
    import FreeCADGui  # deferred: FreeCADGui (the dialog only; this module is App side)
    from PySide import QtGui  # deferred: PySide (the dialog only)

    try:
        # deferred: matplotlib (optional in FreeCAD's Python: missing, the dialog says so; slow)
        import matplotlib  # noqa: F401 - deferred: matplotlib
        from matplotlib.backends.backend_qtagg import FigureCanvasQTAgg, NavigationToolbar2QT
    except ImportError:
        try:
            # deferred: matplotlib (older matplotlib: the Qt5 backend)
            from matplotlib.backends.backend_qt5agg import FigureCanvasQTAgg, NavigationToolbar2QT
        except ImportError as exc:
            msg = (f"Kinematics plots need matplotlib in FreeCAD's Python, which is missing "
                   f"({exc}). On Debian/Ubuntu: apt install python3-matplotlib.")
            FreeCAD.Console.PrintError(msg + "\n")
            QtGui.QMessageBox.warning(FreeCADGui.getMainWindow(), "Kinematics plots", msg)
            return None
    try:
        design, _scale, _ = build(obj, solid=False)
    except CamError as exc:
        field = getattr(exc, "field", None)
        text = f"{props.describe_field(field)}: {exc.rule}" if field else str(exc)  # type: ignore[attr-defined]
        FreeCAD.Console.PrintError(f"{obj.Label}: cannot plot: {text}\n")
        QtGui.QMessageBox.warning(FreeCADGui.getMainWindow(), "Kinematics plots", text)
        return None
    fig = kinematics_figure(design, f"{obj.Label}: follower kinematics at {design.spec.cam.speed_rpm:g} rpm\n"
                                    f"{design.follower.label()} {design.spec.units}")
    dlg = QtGui.QDialog(FreeCADGui.getMainWindow())
    dlg.setWindowTitle(f"Kinematics — {obj.Label}")
    layout = QtGui.QVBoxLayout(dlg)
    canvas = FigureCanvasQTAgg(fig)
    layout.addWidget(NavigationToolbar2QT(canvas, dlg))
    layout.addWidget(canvas)
    avail = QtGui.QGuiApplication.primaryScreen().availableGeometry()
    dlg.resize(min(900, avail.width() - 40), min(1000, avail.height() - 60))
    dlg.show()
    _DIALOGS.append(dlg)
    dlg.finished.connect(lambda *_: _DIALOGS.remove(dlg) if dlg in _DIALOGS else None)
    return dlg

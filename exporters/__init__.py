"""cam_workbench.exporters — the files made from a designed cam: STEP, DXF, G-code, report.json and
the HTML report, plots, e-cam tables and the study tables.

Each exporter is a plain function ``export_x(thing, path, ...)`` that writes atomically.
"""
from .atomic import OutputSet, atomic_path, write_text_atomic

__all__ = ["OutputSet", "atomic_path", "write_text_atomic"]

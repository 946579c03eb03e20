"""cam_workbench.exporters — the files made from a designed cam: STEP, DXF, G-code, report.json and
the HTML report, plots, e-cam tables and the study tables.

Each writer makes its file's content from the designed cam and its numbers (G-code and CSV text,
an ezdxf document, an OCCT STEP writer, figures); the commands and the API put them on disk
atomically (:mod:`.atomic`: one file by temporary file and rename, one cam's set of files all or nothing).
"""
from .atomic import OutputSet, atomic_path, write_text_atomic

__all__ = ["OutputSet", "atomic_path", "write_text_atomic"]

"""Files made from a designed cam: STEP, report JSON (and later DXF, G-code, HTML).

Each exporter is a plain function ``export_x(thing, path, ...)`` that writes atomically.
"""
from .atomic import OutputSet, atomic_path, write_text_atomic

__all__ = ["OutputSet", "atomic_path", "write_text_atomic"]

"""cam_workbench.exporters — the files made from a designed cam: STEP, DXF, G-code, report.json and
the HTML report, plots, e-cam tables and the study tables.

Each writer makes its file's content from the designed cam and its numbers (G-code and CSV text,
an ezdxf document, an OCCT STEP writer, figures); the commands and the API put them on disk
atomically (:mod:`.atomic`: one file by temporary file and rename, one cam's set of files all or nothing).

What differs by body is registered per design class
(:class:`cam_workbench.generators.kinds.by_class.ByClass`): the drawing
(:data:`.dxf.DRAWINGS`), the machining program (:data:`.machining_outputs.PROGRAMS`) and the report
page (:data:`.report_pages.REPORT_PAGES`) and its picture (:data:`.plots.PICTURES`) — the plane cams' in those modules, a body's own in its
modules, which this package imports when it loads (below) so that the tables are full.
"""
from .atomic import OutputSet, atomic_path, write_text_atomic

__all__ = ["OutputSet", "atomic_path", "write_text_atomic"]

# the bodies' own outputs register themselves (the plane cams' come with the tables' modules)
from . import dxf_cylindrical, machining_cylindrical, plots_cylindrical, report_cylindrical  # noqa: F401,E402
from . import drawing_indexer  # noqa: F401,E402
from . import machining_indexer  # noqa: F401,E402
from . import report_indexer  # noqa: F401,E402
from . import machining_spatial_indexer  # noqa: F401,E402
from . import drawing_spatial_indexer  # noqa: F401,E402
from . import report_spatial_indexer  # noqa: F401,E402

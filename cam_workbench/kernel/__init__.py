"""The CAD kernel: the only package that imports OCP (OpenCascade's Python bindings).

:mod:`.ocp` is the OCP adaptor (the one module that imports OCP and knows its versions),
:mod:`.solids` turns the generators' plain NURBS and body data into OCCT edges, faces and the cam
solid — the plane cams' prisms there, a body with surfaces of its own in its module
(:mod:`.cylindrical`), each registered in :data:`.solids.SOLIDS` for its design class —,
:mod:`.step` writes and reads STEP.  The exporters and the API sit above it; it imports,
of the project, only :mod:`cam_workbench.generators`.  Importing it loads no OCP.
"""

from . import cylindrical  # noqa: F401,E402  (registers the cylindrical cam's solid)
from . import indexer  # noqa: F401,E402  (registers the parallel indexer's solid)
from . import spatial_indexer  # noqa: F401,E402  (registers the barrel and globoidal indexers' solid)

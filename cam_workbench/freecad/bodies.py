"""Every body's FreeCAD builder (:class:`.part_build.FreeCADBody`), registered for its design class:
the plane cams' in :mod:`.part_build`, each other body's in its own module, imported here so that
the table is full wherever the feature or the Check design dialog asks it.
"""
from __future__ import annotations

from typing import Any

from . import part_cylindrical  # noqa: F401  (registers the cylindrical cam's builder)
from . import part_indexer  # noqa: F401  (registers the parallel indexer's builder)
from . import part_spatial_indexer  # noqa: F401  (registers the barrel and globoidal indexers' builder)
from .part_build import FREECAD_BODIES, FreeCADBody


def builder_for(design: Any) -> type[FreeCADBody]:
    """The FreeCAD builder of ``design``'s body.

    Raises:
        NotAvailable: the body registers none.
    """
    return FREECAD_BODIES.of(design)


__all__ = ["builder_for"]

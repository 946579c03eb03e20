"""File > Open / Import of a spec (``*.toml``) in the GUI: :mod:`.spec_io`'s importer with the
cam's view providers registered first (:func:`.view_providers.register`), so that the cam it
makes is drawn and edited as the command's are, also before the workbench was ever activated.
``mod/InitGui.py`` hands FreeCAD's ``*.toml`` filter from :mod:`.spec_io` to this module
(``FreeCAD.changeImportModule``, as FreeCAD's own ImportGui does for STEP)."""
from __future__ import annotations

from typing import Any

from . import spec_io, view_providers


def open(filename: str) -> Any:  # noqa: A001 - FreeCAD's importer protocol
    """:func:`.spec_io.open`, in the GUI."""
    view_providers.register()
    return spec_io.open(filename)


def insert(filename: str, docname: str) -> Any:
    """:func:`.spec_io.insert`, in the GUI."""
    view_providers.register()
    return spec_io.insert(filename, docname)

"""Base of the workbench's FreeCAD proxies (features and view providers), which keep nothing
outside their properties.  FreeCAD 0.20 pickles a proxy with ``__getstate__``/``__setstate__``,
FreeCAD 1.x with ``dumps``/``loads``; all four save nothing and restore nothing here.  The
proxies' own class names are what documents store, so this base can change freely."""
from __future__ import annotations

from typing import Any


class Stateless:
    """A proxy with no pickled state; subclasses override :meth:`loads` to reset caches."""

    def dumps(self) -> None:
        return None

    def loads(self, state: Any) -> None:
        return None

    def __getstate__(self) -> None:
        return self.dumps()

    def __setstate__(self, state: Any) -> None:
        self.loads(state)

"""Linkages between a cam's follower and the tool (pure math; docs/linkages.md): the
:class:`~.base.Linkage` protocol, :class:`~.lever.Lever` and :class:`~.four_bar.FourBar`, registered
once by name (``linkage.kind``) in :data:`LINKAGES`."""
from __future__ import annotations

from .base import Linkage, compose3, wrap_pi
from .four_bar import FourBar
from .lever import Lever

#: linkage.kind → class (each consumer looks the class up here, never by its name)
LINKAGES: dict[str, type] = {cls.kind: cls for cls in (Lever, FourBar)}

__all__ = ["LINKAGES", "FourBar", "Lever", "Linkage", "compose3", "wrap_pi"]

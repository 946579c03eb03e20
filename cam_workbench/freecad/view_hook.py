"""Where the App side meets the GUI: how a new cam object gets its view provider.

App-side modules (:mod:`.feature` and what it serves) import no Gui-side module.  The GUI
registers its attacher here — :func:`cam_workbench.freecad.view_providers.register`, run when
the workbench is first activated and by the GUI's spec importer (:mod:`.spec_io_gui`) — and
:func:`.feature.create` hands every object it makes to :func:`attach_view`.  Headless
(``freecadcmd``) nothing is registered and nothing is attached.
"""
from __future__ import annotations

from typing import Any, Callable

#: The registered attacher (at most one); empty headless, or before the GUI registers one.
_ATTACHER: list[Callable[[Any], None]] = []


def set_attacher(attach: Callable[[Any], None]) -> None:
    """Register the GUI's view-provider attacher (replacing an earlier one)."""
    _ATTACHER[:] = [attach]


def attach_view(obj: Any) -> None:
    """Give ``obj`` — a cam or one of its reference children, its proxy already set — its view
    provider through the registered attacher; nothing when none is registered."""
    for attach in _ATTACHER:
        attach(obj)

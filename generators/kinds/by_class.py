"""One consumer's implementation per class: how a consumer serves a kind without asking its name
— the layers above the generators (the CAD kernel, the exporters, the FreeCAD workbench) per design
class, the optimiser per follower class.

A body's design has a class of its own (:class:`cam_workbench.generators.cam_design.CamDesign`
for the plane cams, :class:`cam_workbench.generators.bodies.cylindrical.CylindricalDesign` for the
cylindrical cam, …).  A consumer that builds something differently per body — the kernel's solid,
the drawing, the machining program, the report page, the FreeCAD feature's shapes — holds one
:class:`ByClass` table, and each body's own module in that layer registers its implementation
for its design class.  A design whose class (or a base class) nothing registered is refused with
:class:`~cam_workbench.generators.errors.NotAvailable` naming what is missing and the body: a new
3D body is never routed into another body's outputs.
"""
from __future__ import annotations

from typing import Any, Callable, Generic, TypeVar

from ..errors import NotAvailable

T = TypeVar("T")


class ByClass(Generic[T]):
    """A table design class → implementation (a function or a class of the consumer's protocol).

    The key may be any class a consumer dispatches on: a design class; a body class where only the
    spec is at hand, or a follower class (:meth:`for_class`).

    ``what`` names the thing served, in words ("the cam drawing", "the FreeCAD feature's shapes");
    it begins the refusal for a design nothing serves."""

    def __init__(self, what: str) -> None:
        self.what = what
        self._table: dict[type, T] = {}

    def register(self, design_class: type) -> Callable[[T], T]:
        """Decorator: the implementation serving designs of ``design_class`` (and its subclasses)."""
        def deco(impl: T) -> T:
            held = self._table.get(design_class)
            if held is not None and held is not impl:
                raise ValueError(f"{self.what} of {design_class.__name__} is registered twice")
            self._table[design_class] = impl
            return impl
        return deco

    def of(self, design: Any) -> T:
        """The implementation registered for ``design``'s class or its nearest base class.

        Raises:
            NotAvailable: nothing is registered for it (the message names ``what`` and the body).
        """
        impl = self.for_class(type(design))
        if impl is not None:
            return impl
        raise NotAvailable(f"{self.what} is not available for a {design.spec.cam.body} cam "
                           f"({type(design).__name__}): its body registers none "
                           f"(docs/adding-a-kind.md lists what a body provides)")

    def for_class(self, cls: type) -> T | None:
        """The implementation registered for ``cls`` or its nearest base class, or None."""
        for c in cls.__mro__:
            impl = self._table.get(c)
            if impl is not None:
                return impl
        return None

    def classes(self) -> tuple[type, ...]:
        """The design classes served (registration order)."""
        return tuple(self._table)


__all__ = ["ByClass"]

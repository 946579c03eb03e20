"""Cam bodies: which curves bound which faces, as plain data (:mod:`.base`), one module per body —
:mod:`.plate` (the outside profile), :mod:`.groove` (a groove in a disc's face) and :mod:`.conjugate`
(two plate cams driving one follower through two rollers) and :mod:`.cylindrical` (a groove around a
cylinder, the follower moving along the cam axis; not a stack of prisms) — with the
features every body can carry (:mod:`.features`: bore and keyway, hub, mounting holes, timing
mark).  Each body registers its class with the kinds registry
(:mod:`cam_workbench.generators.kinds`: ``body_of``), the one place that maps ``cam.body`` to its
class; the package re-exports the plain data only (the bodies sit above the plane-cam design they
build on)."""
from __future__ import annotations

from .base import Arc, BodyGeometry, Curve, Line, Loop, Prism

__all__ = ["Arc", "BodyGeometry", "Curve", "Line", "Loop", "Prism"]

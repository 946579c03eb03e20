"""What the plane-cam bodies (plate, groove, conjugate) share behind the body protocol
(:class:`cam_workbench.generators.kinds.protocols.Body`): the plane-cam design (a pitch curve, its
profile, prisms of plane loops), no rules of their own unless they add them, and the spec's own
follower in the dynamics."""
from __future__ import annotations

from typing import Any, Callable

from ..cam_design import design_plane
from ..followers.base import Follower
from ..kinds import follower_of


class PlaneCamBody:
    """The members a plane-cam body inherits (each body still declares its capabilities)."""

    @staticmethod
    def validate(spec: Any) -> None:
        """The body's own spec rules: none beyond the features every body shares."""

    @staticmethod
    def refuse_foreign(spec: Any) -> None:
        """Rules this body puts on the specs of other bodies (its own sections left empty): none."""

    @staticmethod
    def design(spec: Any, progress: Callable[[int, float], None] | None = None) -> Any:
        """The plane cam of ``spec`` (:func:`cam_workbench.generators.cam_design.design_plane`)."""
        return design_plane(spec, progress=progress)

    @staticmethod
    def dynamics_follower(spec: Any) -> Follower:
        """The follower the dynamics drive: the spec's own."""
        return follower_of(spec)

    @staticmethod
    def further_followers(spec: Any) -> tuple:
        """(suffix, follower) of every further cam's roller the design checks cover: none."""
        return ()

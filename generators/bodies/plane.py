"""What the plane-cam bodies (plate, groove, conjugate) share behind the body protocol
(:class:`cam_workbench.generators.kinds.protocols.Body`): the plane-cam design (a pitch curve, its
profile, prisms of plane loops), no rules of their own unless they add them, and the spec's own
follower in the dynamics."""
from __future__ import annotations

from typing import Any, Callable

from ..cam_design import design_plane
from ..checks.design import run_checks
from ..followers.base import Follower
from ..kinds import follower_class_of, follower_of
from ..studies.plan import Plan


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
    def check(design: Any, geometry: Any) -> dict[str, Any]:
        """The body's checks, run with the design (refusing, GeometryError or SpecError, what
        cannot be made): what they measured, for report.json's ``body``; none by default."""
        return {}

    @staticmethod
    def report(design: Any, geometry: Any) -> dict[str, Any]:
        """Further numbers of report.json's ``body`` that refuse nothing, computed when the
        summary first asks (``CamDesign.body_report``); none by default."""
        return {}

    @staticmethod
    def dynamics_follower(spec: Any) -> Follower:
        """The follower the dynamics drive: the spec's own."""
        return follower_of(spec)

    @staticmethod
    def study_row(summary: Any, base_radius: float) -> dict[str, Any] | None:
        """A study's table row of its own: None, the plane cam's row."""
        return None

    @staticmethod
    def own_checks(spec: Any) -> dict[str, Any]:
        """The design checks of the design intent (report.json's ``checks`` section), refusing nothing."""
        return run_checks(spec).to_dict()

    @staticmethod
    def remedy_plans(spec: Any, check: str) -> list[Plan] | None:
        """The fields that move the failing ``check`` of this body: None, the follower's fields
        (``Follower.remedy_plans``) and the plane cam's size."""
        return None

    @staticmethod
    def remedy_words(spec: Any, check: str) -> str | None:
        """What to change, in words, for a ``check`` no field passes: None, the common words."""
        return None

    @staticmethod
    def further_followers(spec: Any) -> tuple:
        """(suffix, follower) of every further cam's roller the design checks cover: none."""
        return ()

    @staticmethod
    def lift_unit(spec) -> str:
        """The follower's (``Follower.lift_unit``)."""
        return follower_class_of(spec).lift_unit

    @staticmethod
    def motion_advance(spec: Any) -> float:
        """The follower's program closes: 0."""
        return 0.0

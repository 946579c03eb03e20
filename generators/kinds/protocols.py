"""What every body kind and every design answers: the members consumers read instead of asking a
kind's name.

A body class (one module per body under :mod:`cam_workbench.generators.bodies`) is registered
with :func:`cam_workbench.generators.kinds.register_body` and satisfies :class:`Body`; its design
(:class:`cam_workbench.generators.cam_design.CamDesign` for the plane cams, the body's own class
otherwise) satisfies :class:`Design`.  The follower protocol is
:class:`cam_workbench.generators.followers.base.Follower`.

Capabilities are attributes every class defines explicitly (no defaults read with ``getattr``):

* ``plane`` — the body is a stack of prisms of plane loops, its design has a pitch curve and a
  profile in the cam's plane (what the plane-cam members read: the API's ``pitch_edge()``, the
  plane areas, the base-radius sizing, the follower kinds that need a plane cam); False for a body
  with surfaces of its own (the cylindrical cam's walls).  Which solid, drawing, program, report
  page and FreeCAD builder a design gets is not asked here: each layer looks its design class up
  (:mod:`.by_class`).
* ``closure`` — "force" (a spring holds the follower on the cam: it can separate) or "form"
  (the cam holds the follower both ways: the driving side changes where the force changes sign).
"""
from __future__ import annotations

from typing import Any, ClassVar, Protocol, runtime_checkable


@runtime_checkable
class Body(Protocol):
    """A body kind (``cam.body``): its declarations, validation, design, checks and shape."""

    #: the value of cam.body
    kind: ClassVar[str]
    #: its name in drawing and report titles ("Plate cam", …)
    title: ClassVar[str]
    #: "force" or "form" (see the module docstring)
    closure: ClassVar[str]
    #: which side drives where the contact force changes sign ("" for force closure)
    drive_note: ClassVar[str]
    #: a plane cam: prisms of plane loops, a pitch curve and a profile (see the module docstring)
    plane: ClassVar[bool]
    #: the rules cam.base_radius > follower.roller_radius and the bore inside base radius − roller
    #: radius hold (the roller's centre keeps cam.base_radius from the cam axis); a spatial
    #: indexer's rollers do not stand on its core, its bore rule is its own
    roller_within_base: ClassVar[bool]
    #: what the follower dynamics drive: "follower" (the follower train, [dynamics]) or "turret" (an
    #: indexer's output train on the turret shaft: dynamics.torsional_stiffness, indexer.output_inertia)
    dynamics_train: ClassVar[str]
    #: the [cam] fields only this body reads (an error on any other body)
    own_fields: ClassVar[tuple[str, ...]]
    #: the field that sizes the cam (cam.base_radius; a cylindrical cam's pitch radius)
    size_field: ClassVar[str]
    #: the objectives and the design variables its optimiser serves
    optimise_objectives: ClassVar[tuple[str, ...]]
    optimise_variables: ClassVar[tuple[str, ...]]
    #: the legend of its first added region in the cam drawing (None: the profile's)
    drawing_label: ClassVar[str | None]
    #: further modules of this kind (beyond the class's own), dotted names
    modules: ClassVar[tuple[str, ...]]

    @staticmethod
    def validate(spec: Any) -> None:
        """The body's own spec rules (SpecError naming the field)."""

    @staticmethod
    def design(spec: Any) -> Any:
        """The designed cam of ``spec`` (a :class:`Design`)."""

    @staticmethod
    def label(spec: Any) -> str:
        """The numbers that identify the cam (spec lengths, no unit)."""

    @staticmethod
    def profile_inset(spec: Any) -> float:
        """Extra inward offset of the profile beyond the roller radius."""

    @staticmethod
    def further_followers(spec: Any) -> tuple:
        """(suffix, follower) of every further cam's roller the design checks cover."""

    @staticmethod
    def dynamics_follower(spec: Any) -> Any:
        """The follower the dynamics drive (SpecError naming the option the body's dynamics lack)."""

    @staticmethod
    def refuse_foreign(spec: Any) -> None:
        """Rules this body puts on the specs of other bodies (its own sections left empty)."""

    @staticmethod
    def own_checks(spec: Any) -> dict[str, Any]:
        """The design checks of the spec (report.json's ``checks`` section), refusing nothing."""

    @staticmethod
    def remedy_plans(spec: Any, check: str) -> list | None:
        """The fields that move a failing ``check`` (None: the follower's and the plane cam's size)."""

    @staticmethod
    def remedy_words(spec: Any, check: str) -> str | None:
        """What to change, in words, for a check no field passes (None: the common words)."""

    @staticmethod
    def study_row(summary: Any, base_radius: float) -> dict[str, Any] | None:
        """A study table's row of its own (None: the plane cam's row)."""

    @staticmethod
    def lift_unit(spec: Any) -> str:
        """The motion program's unit kind: "length" or "angle" (an oscillating follower's arm, an
        indexer's turret)."""

    @staticmethod
    def motion_advance(spec: Any) -> float:
        """s(360°) − s(0°) of the motion program, lift units: 0 (the program closes) for a cam's
        follower; an indexer's turret advances by 360°/N per input turn."""


@runtime_checkable
class Design(Protocol):
    """A designed cam, as every consumer reads it: the spec, the motion program, the follower,
    its numbers, and its capabilities."""

    spec: Any
    #: the body's capability (see :class:`Body`): a plane cam
    plane: ClassVar[bool]
    #: where ``plane`` is False, what stands for the pitch curve and the profile, in words naming
    #: what to use instead (the Python API's refusal, docs/python.md); "" for a plane cam
    instead_of_plane_curves: ClassVar[str]

    @property
    def program(self) -> Any: ...

    @property
    def follower(self) -> Any: ...

    @property
    def volume(self) -> float: ...

    def label(self) -> str: ...

    def summary(self) -> dict[str, Any]: ...

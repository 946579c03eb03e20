"""The kinds registry: each body kind (``cam.body``) and each follower kind (``follower.motion``,
``follower.kind``) registered once, by its own module, and looked up here by every consumer.

A body registers its class with :func:`register_body` (the class declares ``kind``, the value of
``cam.body``), a follower kind with :func:`register_follower` (the class declares ``kinds``, the
``(follower.motion, follower.kind)`` pairs it serves).  This module imports no kind: it sits
below them all, so that the spec's validation, the design, the checks and the dynamics can ask it
without importing a kind's module; :mod:`cam_workbench.generators` imports the built-in kinds
(:mod:`.builtin`) when it loads, so the tables are full before anything is designed.

What a body and a follower answer is declared by :class:`.protocols.Body` and
:class:`cam_workbench.generators.followers.base.Follower`; the capabilities consumers ask
(``plane``, ``closure``, ``pivoted``, ``lift_unit``, …) are attributes every class defines
explicitly.  A consumer that cannot serve a kind refuses through the protocol, naming the option
(e.g. ``Body.dynamics_follower`` raises a SpecError naming ``follower.motion``).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Callable, Iterator, TypeVar

from ..errors import SpecError

if TYPE_CHECKING:  # the protocols, for the type checker only
    from ..followers.base import Follower
    from .protocols import Body

_BODIES: dict[str, "type[Body]"] = {}
_FOLLOWERS: dict[tuple[str, str], "type[Follower]"] = {}
_OPTIMISERS: dict[str, Callable[..., Any]] = {}
_PITCHES: dict[str, type] = {}
_TOOL_PATHS: dict[str, Callable[..., Any]] = {}

B = TypeVar("B")


def register_body(cls: B) -> B:
    """Class decorator: ``cls`` serves ``cam.body = cls.kind`` (each name registered once)."""
    name = cls.kind  # type: ignore[attr-defined]
    if name in _BODIES and _BODIES[name] is not cls:
        raise ValueError(f"cam.body {name!r} is registered twice ({_BODIES[name].__name__}, {cls.__name__})")
    _BODIES[name] = cls  # type: ignore[assignment]
    return cls


def register_follower(cls: B) -> B:
    """Class decorator: ``cls`` serves each (follower.motion, follower.kind) of ``cls.kinds``."""
    for key in cls.kinds:  # type: ignore[attr-defined]
        if key in _FOLLOWERS and _FOLLOWERS[key] is not cls:
            raise ValueError(f"follower {key} is registered twice ({_FOLLOWERS[key].__name__}, {cls.__name__})")
        _FOLLOWERS[key] = cls  # type: ignore[assignment]
    return cls


def body_named(name: str) -> "type[Body]":
    """The body class registered as ``cam.body = name`` (SpecError naming cam.body when none is)."""
    try:
        return _BODIES[name]
    except KeyError:
        raise SpecError("cam.body", f"no body {name!r} is registered (one of {', '.join(sorted(_BODIES))})") from None


def body_of(spec: Any) -> "type[Body]":
    """The body class of a spec."""
    return body_named(spec.cam.body)


def drawing_title(spec: Any) -> str:
    """The title of the spec's drawing and report: ``drawing.title`` when given, else the body's
    name ("Plate cam", "Groove cam", "Conjugate cam pair", "Cylindrical cam")."""
    return (spec.drawing.title or "").strip() or body_of(spec).title


def bodies() -> dict[str, "type[Body]"]:
    """cam.body → body class, every registered body (a copy)."""
    return dict(_BODIES)


def follower_class(motion: str, kind: str) -> "type[Follower]":
    """The class of a follower kind, for what it says before there is a spec (its class
    attributes: ``lift_unit``, ``design_curve``, ``lift_scale``, ``pivoted``) — e.g. the unit in
    which the FreeCAD properties store the lifts while a user edits them."""
    try:
        return _FOLLOWERS[(motion, kind)]
    except KeyError:
        raise SpecError("follower.kind", f"no {motion} {kind} follower is registered") from None


def follower_class_of(spec: Any) -> "type[Follower]":
    """The follower class of a spec (``follower.motion``, ``follower.kind``)."""
    return follower_class(spec.follower.motion, spec.follower.kind)


def follower_of(spec: Any) -> "Follower":
    """The follower of a validated spec."""
    return follower_class_of(spec).from_spec(spec)


def followers() -> dict[tuple[str, str], "type[Follower]"]:
    """(motion, kind) → follower class, every registered follower kind (a copy)."""
    return dict(_FOLLOWERS)


def register_pitch(cls: B) -> B:
    """Class decorator: the pitch-curve class of ``pitch.representation = cls.representation``; it
    declares ``exact`` (the curve has exact rational offsets: the profile is its offset, not a fit)
    and ``words`` (the representation in words: "PH quintic spline", "periodic B-spline")."""
    name = cls.representation  # type: ignore[attr-defined]
    if name in _PITCHES and _PITCHES[name] is not cls:
        raise ValueError(f"pitch.representation {name!r} is registered twice")
    _PITCHES[name] = cls  # type: ignore[assignment]
    return cls


def pitch_named(representation: str) -> type:
    """The pitch-curve class registered for ``pitch.representation`` (as report.json names it)."""
    try:
        return _PITCHES[representation]
    except KeyError:
        raise SpecError("pitch.representation", f"no pitch curve {representation!r} is registered") from None


def pitch_of(spec: Any) -> type:
    """The pitch-curve class of a spec (``pitch.representation``)."""
    return pitch_named(spec.pitch.representation)


def register_optimiser(body: str) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Function decorator: the body ``body`` (its ``kind``) has an optimiser of its own,
    ``fn(spec, progress=…, cancel=…) -> OptimiseResult``, in place of the plane-cam optimiser."""
    def deco(fn: Callable[..., Any]) -> Callable[..., Any]:
        if body in _OPTIMISERS and _OPTIMISERS[body] is not fn:
            raise ValueError(f"the optimiser of cam.body {body!r} is registered twice")
        _OPTIMISERS[body] = fn
        return fn
    return deco


def own_optimiser(spec: Any) -> Callable[..., Any] | None:
    """The optimiser the spec's body registered for itself, or None: the plane-cam optimiser
    (:func:`cam_workbench.generators.optimise.run.optimise`) serves it."""
    return _OPTIMISERS.get(spec.cam.body)


def register_tool_path(body: str) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Function decorator: the body ``body`` (its ``kind``) is machined along a path of its own,
    ``fn(design, plan) -> path``, in place of the plane cam's outside contour."""
    def deco(fn: Callable[..., Any]) -> Callable[..., Any]:
        if body in _TOOL_PATHS and _TOOL_PATHS[body] is not fn:
            raise ValueError(f"the tool path of cam.body {body!r} is registered twice")
        _TOOL_PATHS[body] = fn
        return fn
    return deco


def own_tool_path(spec: Any) -> Callable[..., Any] | None:
    """The tool path the spec's body registered for itself, or None: the plane cam's contour
    (:func:`cam_workbench.generators.machining.toolpath.contour_path`) serves it."""
    return _TOOL_PATHS.get(spec.cam.body)


def own_modules() -> Iterator[tuple[frozenset[str], tuple[str, ...]]]:
    """(the kind names a class owns, its module and the further modules it declares in ``modules``)
    of every registered kind: where a kind may name itself (tests/test_kind_literals.py)."""
    for name, body in _BODIES.items():
        yield frozenset({name}), (body.__module__, *body.modules)
    owners: dict[type, set[str]] = {}
    for key, cls in _FOLLOWERS.items():
        owners.setdefault(cls, set()).update(key)
    for cls, names in owners.items():
        yield frozenset(names), (cls.__module__, *cls.modules)
    for name, pitch in _PITCHES.items():
        yield frozenset({name}), (pitch.__module__,)


__all__ = ["bodies", "body_named", "body_of", "drawing_title", "follower_class", "follower_class_of", "follower_of", "followers",
           "own_modules", "own_optimiser", "own_tool_path", "pitch_named", "pitch_of", "register_body", "register_follower",
           "register_optimiser", "register_pitch", "register_tool_path"]

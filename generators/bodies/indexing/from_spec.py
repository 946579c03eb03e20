"""An indexer's spec (``cam.body`` = "parallel_indexer", "barrel_indexer", "globoidal_indexer") read
into the geometry's parameter classes, and the rules the three bodies share (docs/indexing.md,
"The spec"; :mod:`cam_workbench.generators.spec.indexer` declares the ``[indexer]`` fields).

* ``[[motion]]`` is the turret's motion over one input turn in degrees of turret rotation: exactly
  one ``rise`` of ``lift`` = 360/N (the index: its ``angle`` is β, its start θ_s, its ``law`` any
  rise law that runs rest to rest — a closed form, or "polynomial", "bspline", "constant_velocity"
  (blended), "table" normalised from the motion program: :func:`index_law`) between dwells; the
  program advances by 360°/N per turn.
* ``follower.kind = "roller"``: the rollers (``roller_radius``; ``roller_width`` their contact length,
  default ``cam.thickness``); the turret's own geometry is in ``[indexer]`` (the follower's other
  fields do not apply).
* lengths in mm (``units = "mm"``), ``cam.speed_rpm`` the input speed, ``cam.base_radius`` derived
  (:func:`cam_workbench.generators.spec.indexer.indexer_size`).
"""
from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np

from ...errors import SpecError, fmt_apart
from ...kinds import follower_class_of
from ...motion.laws import LAW_FUNCTIONS, NormalisedLaw
from ...spec.indexer import DEFAULTS, INDEXER_FIELDS, LOAD_FIELDS, IndexerSection, indexer_size, indexer_value

INDEXER_BODIES = tuple(INDEXER_FIELDS)
#: every body-specific [indexer] field, once
_ALL_FIELDS = tuple(dict.fromkeys(f for names in INDEXER_FIELDS.values() for f in names))
#: the follower fields an indexer reads (the turret's own geometry is [indexer]'s)
_FOLLOWER_FIELDS = ("kind", "motion", "roller_radius", "roller_width")
#: the thinnest gap between plates [mm] (as conjugate.gap's)
MIN_GAP = 0.01
#: [cam] features the indexers do not build (yet)
_FEATURES = ("hub_diameter", "keyway", "keyway_width", "mounting_holes", "timing_mark")
#: the geometry's own rule names → the spec field that holds the value
_RENAMED = {"indexer.index_angle": "motion[{i}].angle", "indexer.law": "motion[{i}].law",
            "indexer.index_start": "motion[{i}].angle", "indexer.roller_radius": "follower.roller_radius"}
_DEFAULTS = IndexerSection()
#: the geometry's names that are other fields in the spec (:func:`spec_field`)
GEOMETRY_NAMES = tuple(_RENAMED)
#: [indexer] fields a body reads that may be left out (a default derived from the others)
_OPTIONAL = ("spacer_diameter",)


def index_segment(spec: Any) -> tuple[int, float, float]:
    """(i, θ_s, β): the index (the one ``rise``) — its segment number, start angle and span [rad]."""
    start = 0.0
    for i, seg in enumerate(spec.motion):
        if seg.kind == "rise":
            return i, math.radians(start), math.radians(seg.angle)
        start += seg.angle
    raise SpecError("motion", "an indexer's program needs one rise (the index)")


def motion_advance(spec: Any) -> float:
    """360/N degrees: the turret's turn per input turn (SpecError naming ``indexer.stations`` when absent)."""
    n = spec.indexer.stations
    if n is None:
        raise SpecError("indexer.stations", f'is required for an indexer (cam.body = "{spec.cam.body}")')
    return 360.0 / n


def refuse_foreign(spec: Any) -> None:
    """``[indexer]`` fields on a body that is no indexer are an error."""
    if spec.cam.body in INDEXER_BODIES:
        return
    for name in _ALL_FIELDS + LOAD_FIELDS:
        if getattr(spec.indexer, name) != getattr(_DEFAULTS, name):
            raise SpecError(f"indexer.{name}", "applies to indexers only (cam.body = "
                            + " or ".join(f'"{b}"' for b in INDEXER_BODIES) + ")")


def validate_common(spec: Any, make: Callable[[Any], Any], program: Any) -> Any:
    """The rules every indexer shares, then its parameter class built by ``make(spec)`` (its own
    rules, SpecError naming the spec field); returns it.  ``program``: the spec's motion program
    (the index's law, :func:`index_law`)."""
    body = spec.cam.body
    if spec.units != "mm":
        raise SpecError("units", f'an indexer is designed in millimetres: units = "mm", got "{spec.units}"')
    fol = spec.follower
    if not spec.is_roller:
        raise SpecError("follower.kind", f'an indexer\'s turret carries rollers: kind = "roller", got "{fol.kind}"')
    if follower_class_of(spec).pivoted:
        raise SpecError("follower.motion", "does not apply to an indexer: the turret's geometry is [indexer]'s "
                        "(leave follower.motion out)")
    if fol.offset != 0:
        raise SpecError("follower.offset", "does not apply to an indexer (the turret's geometry is [indexer]'s)")
    for name in ("pivot_distance", "arm_length", "face_offset", "face_width"):
        if getattr(fol, name) is not None:
            raise SpecError(f"follower.{name}", "does not apply to an indexer (the turret's geometry is "
                            "[indexer]'s)")
    for name in _FEATURES:
        if getattr(spec.cam, name) not in (None, 0, False):
            raise SpecError(f"cam.{name}", "an indexer is built with its bore only (hubs, keyways, holes and "
                            "marks are not built on indexers yet)")
    own = INDEXER_FIELDS[body]
    for name in _ALL_FIELDS:
        given = getattr(spec.indexer, name) != getattr(_DEFAULTS, name)
        if name in own and getattr(spec.indexer, name) is None and name not in _OPTIONAL and name not in DEFAULTS:
            raise SpecError(f"indexer.{name}", f'is required for cam.body = "{body}"')
        if name not in own and given:
            owners = [b for b in INDEXER_BODIES if name in INDEXER_FIELDS[b]]
            raise SpecError(f"indexer.{name}", "applies to " + " and ".join(f'"{b}"' for b in owners) + " only")
    gap = spec.indexer.gap
    if gap is not None and 0 < gap < MIN_GAP:
        raise SpecError("indexer.gap", f"must be 0 (the plates face to face) or at least {MIN_GAP:g} mm (a thinner "
                        f"spacer is no part), got {gap!r}")
    _validate_motion(spec, program)
    size = indexer_size(body, {k: getattr(spec.indexer, k) for k in own})
    if size is not None and not math.isclose(spec.cam.base_radius, size, rel_tol=1e-9, abs_tol=1e-12):
        raise SpecError("cam.base_radius", f"is derived for an indexer ({size_words(body)} = {size:.10g} mm): "
                        f"leave it out, got {fmt_apart(spec.cam.base_radius, size)}")
    try:
        return make(spec)
    except SpecError as exc:
        if exc.field not in _RENAMED:
            raise
        raise SpecError(spec_field(spec, exc.field), exc.rule) from None


def spec_field(spec: Any, name: str) -> str:
    """The spec's field for a name the geometry's classes use (``indexer.index_angle`` is the rise's
    ``motion[i].angle``, ``indexer.roller_radius`` the ``follower.roller_radius``); others unchanged."""
    renamed = _RENAMED.get(name)
    return name if renamed is None else renamed.format(i=index_segment(spec)[0])


def size_words(body: str) -> str:
    """What ``cam.base_radius`` stands for on the indexer body ``body``, in words."""
    return {"parallel_indexer": "the plates' smallest dwell radius", "barrel_indexer": "indexer.root_radius",
            "globoidal_indexer": "the waist radius indexer.centre_distance − indexer.root_radius"}[body]


def _validate_motion(spec: Any, program: Any) -> None:
    """One rise (the index) with lift 360/N running rest to rest (:func:`index_law`), no return."""
    rises = [i for i, seg in enumerate(spec.motion) if seg.kind == "rise"]
    for i, seg in enumerate(spec.motion):
        if seg.kind == "return":
            raise SpecError(f"motion[{i}].kind", "an indexer's turret only advances: one rise (the index) between "
                            "dwells, no return")
    if len(rises) != 1:
        raise SpecError(f"motion[{rises[1]}].kind" if rises else "motion",
                        f"an indexer indexes once per input turn: exactly one rise, got {len(rises)}")
    i = rises[0]
    seg = spec.motion[i]
    step = 360.0 / spec.indexer.stations
    if not math.isclose(seg.lift, step, rel_tol=1e-9):
        raise SpecError(f"motion[{i}].lift", f"the index turns the turret by 360°/indexer.stations = {step:.10g}°, "
                        f"got {fmt_apart(seg.lift, step)}")
    index_law(spec, program)


#: |F′| at an end of the normalised index above which it does not start or end at rest
_REST_TOL = 1e-9


def index_law(spec: Any, program: Any) -> str | NormalisedLaw:
    """The index's law for the geometry: a closed form's name, else the rise normalised from the
    spec's motion program (:meth:`NormalisedLaw.from_segment`: F(u) = s(θ_s + β·u)/(360/N)).

    Raises:
        SpecError: a law that does not run rest to rest (F′ ≠ 0 at an end), naming the field that
            sets that velocity (``motion[i].start_velocity`` …, a continuity below 1, a constant
            velocity's missing blend, else the law)."""
    i = index_segment(spec)[0]
    seg = spec.motion[i]
    if seg.law in LAW_FUNCTIONS:
        return seg.law
    law = NormalisedLaw.from_segment(program, i)
    f1 = law.evaluate(np.array([0.0, 1.0]))[1]
    for e, end in enumerate(("start", "end")):
        if abs(f1[e]) <= _REST_TOL:
            continue
        given, cont = getattr(seg, f"{end}_velocity"), getattr(seg, f"{end}_continuity")
        if given is not None and given != 0:
            name = f"{end}_velocity"
        elif cont is not None and cont < 1:
            name = f"{end}_continuity"
        elif seg.law == "constant_velocity" and not getattr(seg, f"{end}_blend"):
            name = f"{end}_blend"
        else:
            name = "law"
        raise SpecError(f"motion[{i}].{name}", f"an indexer's index runs rest to rest: the turret's velocity at "
                        f"the index's {end} must be 0 (the dwell's), got {f1[e] * law_scale(spec):.6g}°/rad "
                        f"(law {seg.law!r})")
    return law


def law_scale(spec: Any) -> float:
    """h/β [° of turret per rad of input]: a normalised law's F′ in the spec's units."""
    _, _, span = index_segment(spec)
    return 360.0 / spec.indexer.stations / span


def geometry_fields(spec: Any, program: Any) -> dict[str, Any]:
    """The fields every indexer's parameter class takes from the spec (mm, rad); ``program`` is the
    spec's :class:`~cam_workbench.generators.motion.program.MotionProgram` (the index's law when it
    is not a closed form: :func:`index_law`)."""
    _, start, span = index_segment(spec)
    return {"stations": int(spec.indexer.stations), "index_angle": span, "law": index_law(spec, program),
            "centre_distance": float(spec.indexer.centre_distance), "roller_radius": float(spec.follower.roller_radius),
            "index_start": start}


def roller_width(spec: Any, default: float | None = None) -> float:
    """The rollers' contact length [mm]: ``follower.roller_width``, default ``default`` (the spatial
    rollers' working length) or ``cam.thickness`` (a parallel indexer's plate)."""
    w = spec.follower.roller_width
    if w is not None:
        return float(w)
    return float(spec.cam.thickness if default is None else default)


def load_arguments(spec: Any, default_width: float | None = None) -> dict[str, float] | None:
    """The drive sizing's load (:func:`.parallel_drive.parallel_drive`, :func:`.spatial_drive.spatial_drive`:
    rev/min, kg·m², N·m, mm, N) from the spec (kg·mm², N·mm); None without ``indexer.output_inertia``;
    ``default_width``: the rollers' contact length when ``follower.roller_width`` is absent (see
    :func:`roller_width`)."""
    ix = spec.indexer
    if not ix.output_inertia:
        return None
    return {"input_speed": float(spec.cam.speed_rpm), "inertia": float(ix.output_inertia) * 1e-6,
            "friction_torque": float(indexer_value(spec, "friction_torque")) * 1e-3,
            "roller_width": roller_width(spec, default_width),
            # no rating given: a unit rating, the life left out of the report (lives scale as C^p)
            "roller_rating": float(ix.roller_rating) if ix.roller_rating is not None else 1.0,
            "life_exponent": float(indexer_value(spec, "life_exponent")),
            "efficiency": float(indexer_value(spec, "efficiency"))}

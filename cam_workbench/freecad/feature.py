"""The ``Cam`` feature (``Part::FeaturePython``) of every body, its reference geometry and :func:`create`.

The feature holds the spec as properties (:mod:`.properties`); ``execute()`` turns them
into a :class:`~cam_workbench.generators.spec.CamSpec`, designs the cam with ``cam_workbench.generators.design_cam``
and builds the solid with FreeCAD's ``Part`` (:mod:`.part_build`).  A bad value is
reported in the report view (the property, the spec field and the rule) and the last good
shape is kept: never a traceback, never an empty shape where there was a cam.

Three child features show the reference geometry: the pitch curve (path of the follower
point, exact degree-5 PH segments), the base circle R_b and the follower itself where it stands
at its ``FollowerAngle`` of cam rotation, drawn from its own sketch
(``Follower.sketch``: roller, stem, arm and pivot, or face).  They follow the cam.

Document compatibility: a saved document stores each proxy's module and class name
(``cam_workbench.freecad.feature`` and ``CamFeature``, ``CamReference``); the module and the
classes keep those names.  Documents saved before feature version 5 name them
``PlateCamFeature`` and ``PlateCamReference``: those names stay bound to the same classes
(end of this module), so such a proxy is restored as a ``CamFeature`` and the next save
stores the new name.  Each feature has a ``Version``; ``onDocumentRestored`` adds the
properties of spec fields declared since the file was saved (with the value an absent
field has, so the cam does not change) and runs the migrations in :data:`MIGRATIONS`.

App side: this module imports no Gui-side module.  A feature made while the GUI is up gets
its view provider through :mod:`.view_hook`, where the GUI registers the attacher.
"""
from __future__ import annotations

import os
import traceback
from typing import Any, Callable, Mapping

import FreeCAD

from cam_workbench.generators.cam_design import design_cam
from cam_workbench.generators.errors import CamError, GeometryError, SpecError
from cam_workbench.generators.followers import follower_of
from cam_workbench.generators.spec import CamSpec, default_spec, load_spec

from .bodies import builder_for
from . import properties as props
from . import view_hook
from .stateless import Stateless

#: Schema version of the features written by this code.  1: issue 6 round one (forces,
#: stresses, feeds, masses, spring rates as plain numbers in the spec's units); 2: those as
#: FreeCAD quantities / fixed storage units (:data:`properties.UNIT_STORAGE`); 3: follower
#: kinds — choice fields that became optional (``machining.rotary_line``) offer "" (absent);
#: 4: every follower kind — torques, torsional rates, arm inertias in fixed units, an
#: oscillating follower's lifts in degrees whatever ``Units`` says (``PitchTolerance`` an angle),
#: ``MaxDeviation`` in the lift's unit, the follower's groups, and a drawn follower child;
#: 5: the feature of every body is a ``Cam`` (proxies ``CamFeature``, ``CamReference``, view
#: provider ``ViewProviderCam``; before: ``PlateCam…``), its properties unchanged.
VERSION = 5
#: Migrations of a feature from version v to v + 1, run in order on restore BEFORE the
#: properties of newer fields are added (so a migration only sees what the file had).
#: Fields added to the spec need none: :func:`properties.ensure_properties` adds them.
MIGRATIONS: dict[int, Callable[[Any], Any]] = {1: props.migrate_plain_numbers,
                                               2: props.migrate_optional_choices,
                                               3: props.migrate_lift_and_torque_units}
#: The feature version since which the proxies are ``CamFeature``/``CamReference``.
_CAM_VERSION = 5
#: What each migration converts, for the upgrade message.
_MIGRATED = {1: "force, stress, feed, mass and spring-rate", 3: "lift, torque and arm-inertia"}

#: Read-only output properties: name → (type, tooltip).
RESULT_PROPERTIES = {
    "Status": ("App::PropertyString", "ok, or the error of the last recompute (the shape is then "
                                      "the last good one)"),
    "JunctionCount": ("App::PropertyInteger", "Number M of PH quintic segments of the pitch curve"),
    "MaxDeviation": ("App::PropertyLength", "Largest |s_actual − s| of the built pitch (or contact) "
                                            "curve: the follower's displacement error, a length — or "
                                            "the arm's angle error of an oscillating follower, an angle"),
    "CrossSectionArea": ("App::PropertyArea", "Cross-section area: profile minus bore (exact, "
                                              "Green's theorem on the NURBS profile)"),
}
#: Result properties holding a lift (or a lift's error): their type follows the follower's lift
#: unit (``Follower.lift_unit``) — a length, or an angle for an oscillating follower.
RESULT_LIFTS = ("MaxDeviation",)
_LIFT_TYPES = {"length": "App::PropertyLength", "angle": "App::PropertyAngle"}
_RESULT_GROUP = "Result"
_PROP_READONLY, _PROP_OUTPUT = 1, 8
ICON_DIR = os.path.join(os.path.dirname(__file__), "icons")


def _console() -> Any:
    return FreeCAD.Console


#: FreeCAD's console cuts one message at about 4 000 characters (ending it "..."): longer text goes
#: out in pieces of this size, one line all the same
_CONSOLE_PIECE = 2000


def _print_message(text: str) -> None:
    """``text`` on FreeCAD's console, whole however long (in pieces, see :data:`_CONSOLE_PIECE`)."""
    for i in range(0, len(text), _CONSOLE_PIECE):
        _console().PrintMessage(text[i:i + _CONSOLE_PIECE])


def _ensure_bookkeeping(obj: Any) -> list[str]:
    added = []
    if "Version" not in obj.PropertiesList:
        obj.addProperty("App::PropertyInteger", "Version", "Base",
                        "Schema version of this feature (cam_workbench)", _PROP_READONLY)
        obj.Version = 0
        added.append("Version")
    if _REFERENCES not in obj.PropertiesList:
        obj.addProperty("App::PropertyLinkList", _REFERENCES, "Base",
                        "Reference curves of this cam (pitch curve, base circle)")
        obj.setEditorMode(_REFERENCES, 2)
        added.append(_REFERENCES)
    for name, (ptype, doc) in RESULT_PROPERTIES.items():
        if name not in obj.PropertiesList:
            obj.addProperty(ptype, name, _RESULT_GROUP, doc, _PROP_READONLY | _PROP_OUTPUT)
            added.append(name)
    return added


def upgrade(obj: Any) -> list[str]:
    """Bring a feature restored from a file up to :data:`VERSION`; return the properties added."""
    added = _ensure_bookkeeping(obj)
    version = int(obj.Version)
    if version > VERSION:
        added += props.ensure_properties(obj, None)
        _console().PrintWarning(
            f"{obj.Label}: saved by a newer cam_workbench (feature version {version} > {VERSION}); "
            "properties this version does not know are ignored\n")
        return added
    converted: dict[int, list[str]] = {}
    for v in range(version, VERSION):
        if v in MIGRATIONS:
            converted[v] = MIGRATIONS[v](obj) or []
    added += props.ensure_properties(obj, None)
    if version < VERSION:
        props.refresh_tooltips(obj)
        set_lift_results(obj, props.lift_unit_of(obj))
    obj.Version = VERSION
    if added or any(converted.values()):
        what = [f"added {', '.join(added)}"] if added else []
        what += [f"{len(names)} {_MIGRATED[v]} properties now in fixed units, the spec unchanged"
                 for v, names in converted.items() if names]
        _print_message(f"{obj.Label}: upgraded from feature version {version} ({'; '.join(what)})\n")
    if version < _CAM_VERSION:
        _console().PrintMessage(f"{obj.Label}: a PlateCamFeature is now a CamFeature, the feature of "
                                f"every body; saved, the document needs feature version {_CAM_VERSION} "
                                "or later\n")
    return added


class CamFeature(Stateless):
    """Proxy of the ``Cam`` feature (a ``Part::FeaturePython``): a cam of any body."""

    def __init__(self, obj: Any, spec: Any = None):
        obj.Proxy = self
        self.design: Any = None
        self.scale = 1.0
        obj.addExtension("Part::AttachExtensionPython")
        _ensure_bookkeeping(obj)
        obj.Version = VERSION
        data = spec.to_dict() if spec is not None else None
        if data is None:
            data = default_spec().to_dict()
        props.ensure_properties(obj, data)
        set_lift_results(obj, props.lift_unit_of(obj))
        obj.Status = "not built yet"

    # ---- FreeCAD callbacks --------------------------------------------------------------
    def execute(self, obj: Any) -> None:
        if hasattr(obj, "positionBySupport"):
            obj.positionBySupport()
        try:
            design, scale, shape = build(obj)
        except SpecError as exc:
            self._fail(obj, f"{props.describe_field(exc.field)}: {exc.rule}" + _unit_note(obj))
            return
        except CamError as exc:
            self._fail(obj, f"the cam cannot be made: {exc}" + _unit_note(obj))
            return
        except Exception as exc:  # noqa: BLE001 - report, never a traceback in the report view
            _console().PrintLog(traceback.format_exc())
            self._fail(obj, f"internal error: {type(exc).__name__}: {exc}")
            return
        shape.Placement = obj.Placement
        obj.Shape = shape
        self.design, self.scale = design, scale
        for ref in references_of(obj):
            update_reference(ref, design, scale, obj.Placement)
        obj.Status = "ok"
        area = builder_for(design).cross_section_area(design)
        obj.CrossSectionArea = 0.0 if area is None else area * scale * scale
        junctions, lift, deviation = builder_for(design).results(design, scale)
        obj.JunctionCount = junctions
        set_lift_results(obj, lift)
        obj.MaxDeviation = deviation

    def _fail(self, obj: Any, text: str) -> None:
        kept = "no shape yet" if obj.Shape.isNull() else "The last good shape is kept"
        _console().PrintError(f"{obj.Label}: {text}. {kept}.\n")
        obj.Status = f"error: {text}"

    def onDocumentRestored(self, obj: Any) -> None:
        self.design, self.scale = None, 1.0
        upgrade(obj)

    def onChanged(self, obj: Any, prop: str) -> None:
        # the lift fields' property types follow the follower (a length, or the arm's degrees)
        if prop in ("FollowerMotion", "FollowerKind") and not _restoring(obj):
            if "PitchTolerance" in obj.PropertiesList and "FollowerKind" in obj.PropertiesList:
                props.sync_lift_unit(obj)

    def loads(self, state: Any) -> None:
        self.design, self.scale = None, 1.0     # caches only; everything else is in properties


def build(obj: Any, solid: bool = True) -> tuple[Any, float, Any]:
    """(design, scale, solid) from the feature's properties.

    Raises:
        SpecError, GeometryError, SolveError: bad input or a cam that cannot be made — or a solid
            FreeCAD calls invalid, or whose volume or top face disagrees with the design's numbers
            beyond its integration's allowance, or that lacks its groove wall faces (its builder's
            ``verify``).
    """
    spec = props.spec_of(obj)
    design = design_cam(spec)
    scale = props.units_scale(obj)
    if not solid:
        return design, scale, None
    builder = builder_for(design)
    built = builder.solid(design, scale)
    if not built.valid:
        raise GeometryError("kernel", f"FreeCAD's kernel reports the cam solid as invalid ({built.measured})")
    builder.verify(design, built, scale)
    return design, scale, built.shape


def _restoring(obj: Any) -> bool:
    doc = getattr(obj, "Document", None)
    return bool(getattr(doc, "Restoring", False)) or "Restore" in getattr(obj, "State", ())


def set_lift_results(obj: Any, lift: str) -> None:
    """Give the result properties that hold a lift (:data:`RESULT_LIFTS`) the type of the lift
    unit ``lift`` ("length" or "angle"); a property whose type changes restarts at 0 (it is an
    output: the next recompute sets it)."""
    scale = props.units_scale(obj)
    for name in RESULT_LIFTS:
        want = _LIFT_TYPES[lift]
        if name in obj.PropertiesList and obj.getTypeIdOfProperty(name) == want:
            continue
        value = 0.0
        if name in obj.PropertiesList:
            # the same lift error in the other unit's storage: mm ↔ spec units (the arm's
            # degrees were stored as if they were the spec's lengths)
            old = float(getattr(getattr(obj, name), "Value", getattr(obj, name)))
            value = old / scale if want == _LIFT_TYPES["angle"] else old * scale
            obj.removeProperty(name)
        obj.addProperty(want, name, _RESULT_GROUP, RESULT_PROPERTIES[name][1], _PROP_READONLY | _PROP_OUTPUT)
        setattr(obj, name, value)


def _unit_note(obj: Any) -> str:
    return " (values in inches: Units = in)" if getattr(obj, "Units", "mm") == "in" else ""


# ---- reference geometry ---------------------------------------------------------------------
REFERENCE_KINDS = {
    "pitch curve": "Pitch curve: the path of the follower point (exact PH quintic segments)",
    "base circle": "Base circle R_b: traced by the follower point at zero lift",
    "follower": "The follower where it stands at FollowerAngle of cam rotation, in the cam's frame, "
                "as it draws itself (roller, stem, arm and pivot, or face)",
}
#: (object-name suffix, label) of each reference child that :func:`create` adds
REFERENCE_NAMES = {"pitch curve": "PitchCurve", "base circle": "BaseCircle", "follower": "Follower"}
_REFERENCES = "References"
#: The follower child's angle property: the cam angle at which the follower is drawn.
FOLLOWER_ANGLE = "FollowerAngle"


class CamReference(Stateless):
    """Proxy of a reference child of a cam (pitch curve, base circle, the drawn follower).

    The cam links its reference children (``Cam.References``) and sets their shapes in its
    own ``execute``; their ``Shape`` and ``Placement`` have FreeCAD's *Output* status, so this
    does not touch them (no recompute loop).  The link points from the cam to the children, so
    deleting the cam does not warn about them — its view provider deletes them with it; and a
    changed child (the follower's ``FollowerAngle``) recomputes the cam, which redraws it."""

    def __init__(self, obj: Any, kind: str):
        obj.Proxy = self
        obj.addProperty("App::PropertyEnumeration", "Kind", "Reference", "Which reference geometry")
        obj.addProperty("App::PropertyInteger", "Version", "Base",
                        "Schema version of this feature (cam_workbench)", _PROP_READONLY)
        obj.Kind = list(REFERENCE_KINDS)
        obj.Kind = kind
        obj.setEditorMode("Kind", 1)
        if kind == "follower":
            obj.addProperty("App::PropertyAngle", FOLLOWER_ANGLE, "Reference",
                            "Cam angle θ at which the follower is drawn (degrees of cam rotation from "
                            "the start of the motion program; the cam stays, the follower is drawn "
                            "where it stands then, seen from the cam)")
        obj.Version = VERSION
        _output_status(obj)

    def execute(self, obj: Any) -> None:
        return None  # the cam sets the shape (update_reference)

    def onDocumentRestored(self, obj: Any) -> None:
        _output_status(obj)
        obj.Version = VERSION


def _output_status(obj: Any) -> None:
    for name in ("Shape", "Placement"):
        if "Output" not in obj.getPropertyStatus(name):
            obj.setPropertyStatus(name, "Output")
    obj.setEditorMode("Placement", 1)  # follows the cam


def update_reference(ref: Any, design: Any, scale: float, placement: Any) -> None:
    """Set a reference curve's shape from the cam's design (called by the cam's execute)."""
    builder = builder_for(design)
    if ref.Kind == "pitch curve":
        wire = builder.pitch_wire(design, scale)
    elif ref.Kind == "follower":
        angle = getattr(ref, FOLLOWER_ANGLE, None)
        wire = builder.follower_shape(design, scale, float(angle.Value) if angle is not None else 0.0)
    else:
        wire = builder.base_circle_wire(design, scale)
    wire.Placement = placement
    ref.Shape = wire


def references_of(cam: Any) -> list[Any]:
    """The reference children of a cam."""
    links = getattr(cam, _REFERENCES, None) or []
    return [o for o in links if isinstance(getattr(o, "Proxy", None), CamReference)]


def reference_of(cam: Any, kind: str) -> Any:
    """The cam's reference child of ``kind`` ("pitch curve", "base circle", "follower"), or None."""
    return next((o for o in references_of(cam) if o.Kind == kind), None)


def add_reference(cam: Any, kind: str) -> Any:
    """Add a reference child of ``kind`` to ``cam`` (and link it); e.g. the drawn follower for
    a cam of a document saved before feature version 4, which has none.  The caller
    recomputes.  Returns the existing child when the cam has one."""
    have = reference_of(cam, kind)
    if have is not None:
        return have
    doc = cam.Document
    ref = doc.addObject("Part::FeaturePython", f"{cam.Name}{REFERENCE_NAMES[kind]}")
    CamReference(ref, kind)
    ref.Label = f"{cam.Label} {kind}"
    cam.References = list(cam.References) + [ref]
    view_hook.attach_view(ref)
    cam.touch()
    return ref


def is_cam(obj: Any) -> bool:
    """Whether ``obj`` is a cam feature (of any body)."""
    return isinstance(getattr(obj, "Proxy", None), CamFeature)


# ---- creation -------------------------------------------------------------------------------
def _as_spec(spec: Any) -> Any:
    if spec is None:
        return default_spec()
    if isinstance(spec, CamSpec):
        return spec
    if isinstance(spec, (str, os.PathLike, Mapping)):
        return load_spec(spec)  # type: ignore[arg-type]
    raise TypeError(f"spec must be a CamSpec, a TOML path or text, a dict or None, not {type(spec).__name__}")


def create(doc: Any = None, spec: Any = None, name: str = "Cam", reference: bool = True) -> Any:
    """Add a ``Cam`` feature (and its reference curves) to ``doc``, of the spec's body; used by
    the GUI command and headless alike (in the GUI, the objects get their view providers through
    :mod:`.view_hook`).  The caller recomputes.

    Args:
        doc: the document; default the active one (a new one if there is none).
        spec: a CamSpec, a TOML path or text, a dict in the spec's structure, or None for
            the built-in default (``default_spec()``: the paper's motion program on a 40 mm
            base radius with a radial 8 mm roller, a plate cam).
        name: object name of the feature.
        reference: also add the pitch-curve, base-circle and follower children.

    Raises:
        SpecError: ``spec`` is bad (nothing is added to the document).
    """
    spec = _as_spec(spec)
    if doc is None:
        doc = FreeCAD.ActiveDocument or FreeCAD.newDocument()
    obj = doc.addObject("Part::FeaturePython", name)
    CamFeature(obj, spec)
    refs = []
    if reference:
        # a flat face's design curve is its contact curve (the profile), not a pitch curve
        curve = follower_of(spec).describe()["curve"]
        for kind, suffix in REFERENCE_NAMES.items():
            ref = doc.addObject("Part::FeaturePython", f"{name}{suffix}")
            CamReference(ref, kind)
            ref.Label = f"{obj.Label} {curve if kind == 'pitch curve' else kind}"
            refs.append(ref)
        obj.References = refs
    for new in [obj, *refs]:
        view_hook.attach_view(new)
    return obj


# ---- the names documents saved before feature version 5 store ---------------------------------
# FreeCAD looks a stored class name up in this module and restores the proxy without calling
# __init__; these names give the new classes, and a save stores a proxy's own class name.
PlateCamFeature = CamFeature
PlateCamReference = CamReference

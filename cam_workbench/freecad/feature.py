"""The ``PlateCam`` feature (``Part::FeaturePython``), its reference geometry and :func:`create`.

The feature holds the spec as properties (:mod:`.properties`); ``execute()`` turns them
into a :class:`~generators.spec.CamSpec`, designs the cam with ``generators.design_cam``
and builds the solid with FreeCAD's ``Part`` (:mod:`.part_build`).  A bad value is
reported in the report view (the property, the spec field and the rule) and the last good
shape is kept: never a traceback, never an empty shape where there was a cam.

Two child features show the reference geometry: the pitch curve (path of the follower
point, exact degree-5 PH segments) and the base circle R_b.  They follow the cam.

Document compatibility: the class and module names below are stored in saved documents
and must not change.  Each feature has a ``Version``; ``onDocumentRestored`` adds the
properties of spec fields declared since the file was saved (with the value an absent
field has, so the cam does not change) and runs the migrations in :data:`MIGRATIONS`.
"""
from __future__ import annotations

import os
import traceback
from typing import Any, Callable, Mapping

from generators.errors import CamError, GeometryError, SpecError

from . import properties as props
from .stateless import Stateless

#: Schema version of the features written by this code.  1: issue 6 round one (forces,
#: stresses, feeds, masses, spring rates as plain numbers in the spec's units); 2: those as
#: FreeCAD quantities / fixed storage units (:data:`properties.UNIT_STORAGE`); 3: follower
#: kinds — choice fields that became optional (``machining.rotary_line``) offer "" (absent).
VERSION = 3
#: Migrations of a feature from version v to v + 1, run in order on restore BEFORE the
#: properties of newer fields are added (so a migration only sees what the file had).
#: Fields added to the spec need none: :func:`properties.ensure_properties` adds them.
MIGRATIONS: dict[int, Callable[[Any], Any]] = {1: props.migrate_plain_numbers,
                                               2: props.migrate_optional_choices}

#: Read-only output properties: name → (type, tooltip).
RESULT_PROPERTIES = {
    "Status": ("App::PropertyString", "ok, or the error of the last recompute (the shape is then "
                                      "the last good one)"),
    "JunctionCount": ("App::PropertyInteger", "Number M of PH quintic segments of the pitch curve"),
    "MaxDeviation": ("App::PropertyLength", "Largest |s_actual − s| of the built pitch curve "
                                            "(follower displacement error)"),
    "CrossSectionArea": ("App::PropertyArea", "Cross-section area: profile minus bore (exact, "
                                              "Green's theorem on the NURBS profile)"),
}
_RESULT_GROUP = "Result"
_PROP_READONLY, _PROP_OUTPUT = 1, 8
ICON_DIR = os.path.join(os.path.dirname(__file__), "icons")


def _console() -> Any:
    import FreeCAD

    return FreeCAD.Console


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
    converted: list[str] = []
    for v in range(version, VERSION):
        if v in MIGRATIONS:
            converted += MIGRATIONS[v](obj) or []
    added += props.ensure_properties(obj, None)
    if version < VERSION:
        props.refresh_tooltips(obj)
    obj.Version = VERSION
    if added or converted:
        what = [f"added {', '.join(added)}"] if added else []
        what += [f"{len(converted)} force, stress, feed, mass and spring-rate properties now in "
                 f"fixed units, the spec unchanged"] if converted else []
        _console().PrintMessage(f"{obj.Label}: upgraded from feature version {version} "
                                f"({'; '.join(what)})\n")
    return added


class PlateCamFeature(Stateless):
    """Proxy of the ``PlateCam`` feature (a ``Part::FeaturePython``)."""

    def __init__(self, obj: Any, spec: Any = None):
        obj.Proxy = self
        self.design: Any = None
        self.scale = 1.0
        obj.addExtension("Part::AttachExtensionPython")
        _ensure_bookkeeping(obj)
        obj.Version = VERSION
        data = spec.to_dict() if spec is not None else None
        if data is None:
            from generators.spec import default_spec

            data = default_spec().to_dict()
        props.ensure_properties(obj, data)
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
        obj.JunctionCount = int(design.pitch.M)
        obj.MaxDeviation = float(design.max_deviation[0]) * scale
        obj.CrossSectionArea = float(design.area) * scale * scale

    def _fail(self, obj: Any, text: str) -> None:
        kept = "no shape yet" if obj.Shape.isNull() else "The last good shape is kept"
        _console().PrintError(f"{obj.Label}: {text}. {kept}.\n")
        obj.Status = f"error: {text}"

    def onDocumentRestored(self, obj: Any) -> None:
        self.design, self.scale = None, 1.0
        upgrade(obj)

    def loads(self, state: Any) -> None:
        self.design, self.scale = None, 1.0     # caches only; everything else is in properties


def build(obj: Any, solid: bool = True) -> tuple[Any, float, Any]:
    """(design, scale, solid) from the feature's properties.

    Raises:
        SpecError, GeometryError, SolveError: bad input or a cam that cannot be made.
    """
    from generators.cam_design import design_cam

    from . import part_build

    spec = props.spec_of(obj)
    design = design_cam(spec)
    scale = props.units_scale(obj)
    if not solid:
        return design, scale, None
    shape = part_build.cam_solid(design, scale)
    if not shape.isValid() or len(shape.Solids) != 1:
        raise GeometryError("kernel", "FreeCAD's kernel reports the cam solid as invalid")
    return design, scale, shape


def _unit_note(obj: Any) -> str:
    return " (values in inches: Units = in)" if getattr(obj, "Units", "mm") == "in" else ""


# ---- reference geometry ---------------------------------------------------------------------
REFERENCE_KINDS = {
    "pitch curve": "Pitch curve: the path of the follower point (exact PH quintic segments)",
    "base circle": "Base circle R_b: traced by the follower point at zero lift",
}
_REFERENCES = "References"


class PlateCamReference(Stateless):
    """Proxy of a reference curve of a cam (pitch curve or base circle).

    The cam links its reference curves (``PlateCam.References``) and sets their shapes in its
    own ``execute``; their ``Shape`` and ``Placement`` have FreeCAD's *Output* status, so this
    does not touch them (no recompute loop).  The link points from the cam to the curves, so
    deleting the cam does not warn about them — its view provider deletes them with it."""

    def __init__(self, obj: Any, kind: str):
        obj.Proxy = self
        obj.addProperty("App::PropertyEnumeration", "Kind", "Reference", "Which reference curve")
        obj.addProperty("App::PropertyInteger", "Version", "Base",
                        "Schema version of this feature (cam_workbench)", _PROP_READONLY)
        obj.Kind = list(REFERENCE_KINDS)
        obj.Kind = kind
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
    from . import part_build

    if ref.Kind == "pitch curve":
        wire = part_build.pitch_wire(design, scale)
    else:
        wire = part_build.base_circle_wire(design, scale)
    wire.Placement = placement
    ref.Shape = wire


def references_of(cam: Any) -> list[Any]:
    """The reference-curve children of a cam."""
    links = getattr(cam, _REFERENCES, None) or []
    return [o for o in links if isinstance(getattr(o, "Proxy", None), PlateCamReference)]


def cam_of(ref: Any) -> Any:
    """The cam a reference curve belongs to (None if it was deleted)."""
    cams = [o for o in ref.InList if is_plate_cam(o)]
    return cams[0] if cams else None


def is_plate_cam(obj: Any) -> bool:
    return isinstance(getattr(obj, "Proxy", None), PlateCamFeature)


# ---- creation -------------------------------------------------------------------------------
def _as_spec(spec: Any) -> Any:
    from generators.spec import CamSpec, default_spec, load_spec

    if spec is None:
        return default_spec()
    if isinstance(spec, CamSpec):
        return spec
    if isinstance(spec, (str, os.PathLike, Mapping)):
        return load_spec(spec)  # type: ignore[arg-type]
    raise TypeError(f"spec must be a CamSpec, a TOML path or text, a dict or None, not {type(spec).__name__}")


def create(doc: Any = None, spec: Any = None, name: str = "PlateCam", reference: bool = True) -> Any:
    """Add a ``PlateCam`` feature (and its reference curves) to ``doc``; used by the GUI
    command and headless alike.  The caller recomputes.

    Args:
        doc: the document; default the active one (a new one if there is none).
        spec: a CamSpec, a TOML path or text, a dict in the spec's structure, or None for
            the built-in default (the paper's Table 1, case 2, with a 5 mm roller).
        name: object name of the feature.
        reference: also add the pitch-curve and base-circle children.

    Raises:
        SpecError: ``spec`` is bad (nothing is added to the document).
    """
    import FreeCAD

    spec = _as_spec(spec)
    if doc is None:
        doc = FreeCAD.ActiveDocument or FreeCAD.newDocument()
    obj = doc.addObject("Part::FeaturePython", name)
    PlateCamFeature(obj, spec)
    refs = []
    if reference:
        for kind, label in (("pitch curve", "PitchCurve"), ("base circle", "BaseCircle")):
            ref = doc.addObject("Part::FeaturePython", f"{name}{label}")
            PlateCamReference(ref, kind)
            ref.Label = f"{obj.Label} {kind}"
            refs.append(ref)
        obj.References = refs
    if FreeCAD.GuiUp:
        from . import view_providers

        view_providers.ViewProviderPlateCam(obj.ViewObject)
        for ref in refs:
            view_providers.ViewProviderReference(ref.ViewObject)
    return obj

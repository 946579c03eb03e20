"""The kinds registry (issue 21 item 3): every body, follower kind and pitch representation the spec
declares is registered once, answers its protocol, and declares its capabilities itself (no
default read with getattr); consumers reach a kind only through the registry."""
from __future__ import annotations

import pytest

from cam_workbench.generators import kinds
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.kinds.protocols import Body
from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.generators.spec.cam import CamSection
from cam_workbench.generators.spec.follower import FollowerSection
from cam_workbench.generators.spec.pitch import PitchSection
from cam_workbench.generators.spec.params import params_of

#: what a body class must declare in its own class body (capabilities consumers ask)
BODY_CAPABILITIES = ("kind", "title", "plane", "closure", "drive_note", "own_fields", "size_field",
                     "optimise_objectives", "optimise_variables", "drawing_label", "modules")


def test_every_declared_kind_is_registered_once():
    bodies = kinds.bodies()
    assert tuple(bodies) == params_of(CamSection)["body"].choices
    fol = params_of(FollowerSection)
    assert set(kinds.followers()) == {(m, k) for m in fol["motion"].choices for k in fol["kind"].choices}
    for rep in params_of(PitchSection)["representation"].choices:
        assert kinds.pitch_named(rep).representation == rep


@pytest.mark.parametrize("name", params_of(CamSection)["body"].choices)
def test_each_body_answers_the_protocol_and_declares_its_capabilities(name):
    body = kinds.body_named(name)
    assert isinstance(body, Body)          # every protocol member present (runtime_checkable)
    missing = [c for c in BODY_CAPABILITIES if c not in vars(body)]
    assert not missing, f"{body.__name__} does not declare {missing} itself"
    assert body.kind == name
    assert body.closure in ("force", "form")
    assert isinstance(body.plane, bool)
    assert set(body.optimise_variables) <= set(params_of(CamSection)) | {"clearance"}


@pytest.mark.parametrize("key", sorted(kinds.followers()))
def test_each_follower_kind_declares_its_capabilities(key):
    cls = kinds.follower_class(*key)
    assert key in vars(cls)["kinds"]
    assert isinstance(vars(cls)["pivoted"], bool)
    assert cls.motion == key[0]
    # a pivoted follower's lift is the arm's angle, and only a pivoted one's
    assert (cls.lift_unit == "angle") == cls.pivoted


def test_pitch_representations_declare_whether_their_offsets_are_exact():
    exact = {rep: kinds.pitch_named(rep).exact for rep in params_of(PitchSection)["representation"].choices}
    assert exact == {"ph": True, "bspline": False}     # the PH spline's offsets are rational (exact)


@pytest.mark.parametrize("example", ["default", "flat", "oscillating", "groove", "conjugate", "cylindrical",
                                     "cylindrical_oscillating"])
def test_the_registry_gives_each_example_its_kinds(example):
    spec = example_spec(example)
    body = kinds.body_of(spec)
    assert body.kind == spec.cam.body
    fol = kinds.follower_of(spec)
    assert isinstance(fol, kinds.follower_class_of(spec))
    assert (fol.motion, fol.contact) == (spec.follower.motion, spec.follower.kind)
    assert fol.pivoted == (spec.follower.motion == "oscillating")


def test_an_unknown_kind_is_refused_naming_the_field():
    with pytest.raises(SpecError) as exc:
        kinds.body_named("barrel")
    assert exc.value.field == "cam.body"
    with pytest.raises(SpecError) as exc:
        kinds.follower_class("translating", "mushroom")
    assert exc.value.field == "follower.kind"


def test_a_name_is_registered_once():
    plate = kinds.body_named("plate")

    class Impostor:
        kind = "plate"

    with pytest.raises(ValueError, match="registered twice"):
        kinds.register_body(Impostor)
    assert kinds.body_named("plate") is plate
    assert kinds.register_body(plate) is plate          # the same class again: no change


def test_the_plane_question_has_one_answer():
    """The design and its body agree on ``plane`` (the capability the pipeline asks)."""
    from cam_workbench.generators import design_cam

    spec = example_spec("default")
    d = design_cam(spec)
    assert d.plane is kinds.body_of(spec).plane is True
    assert d.body.prismatic is True
    from cam_workbench.generators.bodies.cylindrical import CylindricalDesign, CylindricalGeometry

    assert CylindricalDesign.plane is kinds.body_named("cylindrical").plane is False
    assert CylindricalGeometry.prismatic is False


def test_a_consumer_that_cannot_serve_a_kind_refuses_naming_the_option():
    """The cylindrical body's dynamics drive a translating roller only: its protocol refuses the
    oscillating arm naming follower.motion (the dynamics command asks the protocol)."""
    spec = example_spec("cylindrical_oscillating")
    with pytest.raises(SpecError) as exc:
        kinds.body_of(spec).dynamics_follower(spec)
    assert exc.value.field == "follower.motion"


def _per_design_tables():
    """Every consumer's table design class → implementation, above the generators (each layer's
    registrations loaded by importing it)."""
    from cam_workbench.exporters.dxf import DRAWINGS
    from cam_workbench.exporters.machining_outputs import PROGRAMS
    from cam_workbench.exporters.report_pages import REPORT_PAGES
    from cam_workbench.freecad.bodies import FREECAD_BODIES
    from cam_workbench.kernel.solids import SOLIDS

    return {"kernel solid": SOLIDS, "drawing": DRAWINGS, "machining": PROGRAMS, "report page": REPORT_PAGES,
            "FreeCAD builder": FREECAD_BODIES}


@pytest.mark.parametrize("example", ["default", "groove", "conjugate", "cylindrical", "cylindrical_oscillating"])
def test_every_consumer_serves_every_built_in_body(example):
    """Each layer's table holds an implementation for the design of every built-in example."""
    from cam_workbench.generators import design_cam

    design = design_cam(example_spec(example))
    for what, table in _per_design_tables().items():
        assert table.of(design) is not None, what


def test_a_new_body_is_refused_by_every_consumer_never_routed_to_another_body():
    """A design class nothing registered (a new 3D body, say) is refused by each consumer with
    NotAvailable naming what is missing and the body — not served by the plane cams' or the
    cylindrical cam's outputs (issue 21: "a new 3D body would be routed silently into the
    cylindrical outputs")."""
    from dataclasses import dataclass

    from cam_workbench.generators.errors import NotAvailable

    @dataclass(frozen=True)
    class GloboidDesign:          # a stand-in for a body with surfaces of its own
        spec: object
        plane = False

    design = GloboidDesign(example_spec("cylindrical").replace(**{"cam.body": "cylindrical"}))
    for what, table in _per_design_tables().items():
        with pytest.raises(NotAvailable) as exc:
            table.of(design)
        assert table.what in str(exc.value) and "cylindrical cam" in str(exc.value) and "GloboidDesign" in str(exc.value), what

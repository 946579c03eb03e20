"""A prism body built without booleans (issue 22 item 1): :mod:`cam_workbench.generators.bodies.levels`
tells the caps and sides from the loops' nesting alone, and both kernels sew them into the solid.

Held against closed forms written here (areas of circles and annuli × heights) and against the
booleans the kernels applied before (the same volume; the same boundary: distances from probe
points)."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cam_workbench.generators import design_cam
from cam_workbench.generators.bodies.base import Loop, Prism
from cam_workbench.generators.bodies.levels import CapFace, CapXor, level_stack
from cam_workbench.generators.spec.examples import example_spec

from .conftest import requires_ocp


def _circle(r: float, c: complex = 0j, role: str = "") -> Loop:
    return Loop.circle(r, c, role)


def _roles(caps) -> list[tuple[float, str, list[str]]]:
    return [(c.z, c.outer.role, sorted(h.role for h in c.holes)) for c in caps if isinstance(c, CapFace)]


def test_a_disc_with_a_hole_and_a_hub_has_its_caps_and_sides():
    """Disc R = 50 with bore 10 over 0…12, a hub R = 20 over −10…0 with the same bore, a groove
    annulus 30…40 cut over 4…12: five caps, the bore one side over −10…12."""
    bore, rim, hub = _circle(5, role="bore"), _circle(50, role="rim"), _circle(20, role="hub")
    go, gi = _circle(40, role="groove_outer"), _circle(30, role="groove_inner")
    prisms = [Prism(rim, (bore,), 0.0, 12.0, "add", "disc"), Prism(go, (gi,), 4.0, 12.0, "cut", "groove"),
              Prism(hub, (bore,), -10.0, 0.0, "add", "hub")]
    s = level_stack(prisms)
    assert s is not None
    assert _roles(s.caps) == [(-10.0, "hub", ["bore"]), (0.0, "rim", ["hub"]), (4.0, "groove_outer", ["groove_inner"]),
                              (12.0, "rim", ["groove_outer"]), (12.0, "groove_inner", ["bore"])]
    assert sorted((x.loop.role, x.z0, x.z1) for x in s.sides) == [
        ("bore", -10.0, 12.0), ("groove_inner", 4.0, 12.0), ("groove_outer", 4.0, 12.0), ("hub", -10.0, 0.0),
        ("rim", 0.0, 12.0)]
    pi = math.pi
    exact = pi * (50**2 - 5**2) * 12 - pi * (40**2 - 30**2) * 8 + pi * (20**2 - 5**2) * 10
    assert s.volume == pytest.approx(exact, rel=1e-13)


def test_crossing_loops_of_one_level_need_booleans():
    """Two holes that overlap in one level: no cells — None (the kernels apply the booleans)."""
    prisms = [Prism(_circle(50), (), 0.0, 10.0, "add", "disc"), Prism(_circle(10, 5 + 0j), (), 0.0, 10.0, "cut", "a"),
              Prism(_circle(10, -5 + 0j), (), 0.0, 10.0, "cut", "b")]
    assert level_stack(prisms) is None


def test_loops_crossing_across_a_cap_are_a_planar_boolean_there():
    """Holes that open onto a hub's shoulder (the groove example): the cap between the hub and the
    disc is left to planar booleans, every other cap is direct."""
    s = level_stack(design_cam(example_spec("groove")).body.prisms)
    xor = [c for c in s.caps if isinstance(c, CapXor)]
    assert [c.z for c in xor] == [0.0]
    assert {f.outer.role for f in xor[0].below} == {"hub"} and {f.outer.role for f in xor[0].above} == {"rim"}


@pytest.mark.parametrize("example", ["default", "groove", "conjugate", "packaging"])
def test_the_stack_volume_is_the_bodys_exact_volume(example):
    d = design_cam(example_spec(example))
    assert level_stack(d.body.prisms).volume == pytest.approx(d.volume, rel=1e-13)


# ---- random bodies: nested circles, each kernel's sewn solid against the closed form ----------------
@st.composite
def _bodies(draw):
    """A disc (radius 40…60) with a bore, 0–4 holes on a ring that stay clear of each other, an
    optional annular groove cut from the top and an optional hub below: loops that never cross."""
    R = draw(st.floats(40, 60))
    bore = draw(st.floats(3, 8))
    t = draw(st.floats(5, 20))
    prisms = [Prism(_circle(R, role="rim"), (_circle(bore, role="bore"),), 0.0, t, "add", "disc")]
    exact = math.pi * (R**2 - bore**2) * t
    n = draw(st.integers(0, 4))
    ring, r_hole = bore + 8, draw(st.floats(1, 2.5))
    for k in range(n):
        c = ring * complex(math.cos(2 * math.pi * k / max(n, 1)), math.sin(2 * math.pi * k / max(n, 1)))
        prisms.append(Prism(_circle(r_hole, c, role="hole"), (), 0.0, t, "cut", f"hole{k}"))
        exact -= math.pi * r_hole**2 * t
    if draw(st.booleans()):
        gi = draw(st.floats(ring + 4, R - 12))
        go = gi + draw(st.floats(2, 8))
        depth = draw(st.floats(0.2, 0.9)) * t
        prisms.append(Prism(_circle(go, role="groove_outer"), (_circle(gi, role="groove_inner"),), t - depth, t,
                            "cut", "groove"))
        exact -= math.pi * (go**2 - gi**2) * depth
    if draw(st.booleans()):
        h = draw(st.floats(bore + 2, ring - r_hole - 1))
        hl = draw(st.floats(2, 15))
        prisms.append(Prism(_circle(h, role="hub"), (_circle(bore, role="bore"),), -hl, 0.0, "add", "hub"))
        exact += math.pi * (h**2 - bore**2) * hl
    return prisms, exact


@settings(max_examples=25, deadline=None)
@given(_bodies())
def test_random_nested_bodies_have_the_closed_form_volume(body):
    prisms, exact = body
    s = level_stack(prisms)
    assert s is not None and s.volume == pytest.approx(exact, rel=1e-12)


@requires_ocp
@settings(max_examples=12, deadline=None)
@given(_bodies())
def test_ocp_sews_random_bodies_into_one_valid_solid(body):
    """The OCP kernel's solid from the caps and sides: valid, one solid, OCCT's volume the closed
    form's, and no farther from the booleans' solid than the sewing tolerance (probe distances)."""
    from cam_workbench.kernel import ocp as occ
    from cam_workbench.kernel import solids

    prisms, exact = body
    sewn = solids.sewn_levels(level_stack(prisms))
    assert sewn is not None and solids.is_valid(sewn) and solids.count_solids(sewn) == 1
    assert solids.kernel_volume(sewn) == pytest.approx(exact, rel=1e-9)
    booleans = None
    for p in prisms:
        piece = solids.extrude(solids.region_face(p.outer, p.holes, p.z0), p.z0, p.z1)
        booleans = piece if booleans is None else solids.boolean(
            occ.BRepAlgoAPI_Fuse if p.op == "add" else occ.BRepAlgoAPI_Cut, booleans, piece)
    faces = [_faces(sewn), _faces(booleans)]     # the boundaries (a solid's distance is 0 inside it)
    rng = np.random.default_rng(0)
    for x, y, z in rng.uniform(-70, 70, (20, 3)):
        v = occ.BRepBuilderAPI_MakeVertex(occ.gp_Pnt(x, y, z)).Vertex()
        d1, d2 = (occ.BRepExtrema_DistShapeShape(v, f).Value() for f in faces)
        assert abs(d1 - d2) <= 1e-6
        inside = [occ.BRepClass3d_SolidClassifier(sh, occ.gp_Pnt(x, y, z), 1e-7).State() == occ.TopAbs_IN
                  for sh in (sewn, booleans)]
        assert inside[0] == inside[1]


def _faces(shape):
    """A compound of the faces of ``shape``."""
    from cam_workbench.kernel import ocp as occ

    comp = occ.TopoDS_Compound()
    builder = occ.BRep_Builder()
    builder.MakeCompound(comp)
    exp = occ.TopExp_Explorer(shape, occ.TopAbs_FACE)
    while exp.More():
        builder.Add(comp, exp.Current())
        exp.Next()
    return comp

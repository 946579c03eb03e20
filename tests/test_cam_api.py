"""``Cam``, the public class of every body: every public member, found by ``inspect`` (a new
member is tested as soon as it exists — and fails here until :data:`MEMBERS` says how to call
it), on every built-in example and on random specs of every body, returns a value that agrees
with facts computed here, or raises the refusal docs/python.md tables ("What each body serves")
— never AttributeError, TypeError or KeyError.  Real OCP, CadQuery, ezdxf and matplotlib."""
from __future__ import annotations

import inspect
import json
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings

from cam_workbench.generators.errors import CamError, GeometryError, MissingDependency, NotAvailable, SolveError, SpecError
from cam_workbench.generators.spec import to_toml
from cam_workbench.generators.spec.examples import EXAMPLES

from .combinations.strategies import cylindrical_specs, specs
from .conftest import ROOT, requires_ocp

pytestmark = requires_ocp

DOC = ROOT / "docs" / "python.md"
BODIES = ("plate", "groove", "conjugate", "cylindrical", "parallel_indexer", "barrel_indexer", "globoidal_indexer")


@dataclass
class Case:
    """One cam under test: the cam, a folder of its own, the example it is (None: a random spec)."""

    cam: Any
    tmp: Path
    example: str | None


# ---- independent facts ---------------------------------------------------------------------------
def _shoelace(points: np.ndarray) -> float:
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _edge_area(edge: Any, n: int = 4000) -> float:
    """Signed area inside a closed cadquery.Edge, by a shoelace over OCCT's points (not the NURBS
    the project integrates by Green's theorem)."""
    assert edge.IsClosed()
    pts = np.array([tuple(edge.positionAt(t, mode="parameter"))
                    for t in np.linspace(edge.paramAt(0), edge.paramAt(1), n, endpoint=False)])
    assert np.allclose(pts[:, 2], 0.0, atol=1e-9), "not in the XY plane"
    return _shoelace(pts)


def _same_cam(a: Any, b: Any) -> None:
    assert type(a) is type(b)
    assert repr(a) == repr(b)
    assert b.volume == pytest.approx(a.volume, rel=1e-12)


def _is_solid(v: Any) -> None:
    from cam_workbench.kernel import ocp as occ
    from cam_workbench.kernel.solids import count_solids, is_valid

    assert isinstance(v, occ.TopoDS_Shape) and count_solids(v) == 1 and is_valid(v)


# ---- how each public member is called, and what its value must be -----------------------------
def _example(c: Case) -> None:
    name = c.example or "default"
    again = type(c.cam).example(name)
    assert again.source == f"example:{name}"
    if c.example:
        _same_cam(c.cam, again)


def _from_toml(c: Case) -> None:
    path = c.tmp / "spec.toml"
    path.write_text(to_toml(c.cam.spec), encoding="utf-8")
    _same_cam(c.cam, type(c.cam).from_toml(path))


def _from_dict(c: Case) -> None:
    _same_cam(c.cam, type(c.cam).from_dict(c.cam.spec.to_dict()))


def _spec(c: Case) -> None:
    assert c.cam.spec.cam.body in BODIES


def _design(c: Case) -> None:
    assert c.cam.design.spec is c.cam.spec


def _source(c: Case) -> None:
    if c.example:
        assert c.cam.source == f"example:{c.example}"
    else:                               # made from a dict: the running script
        assert c.cam.source.startswith("python")


def _solid(c: Case) -> None:
    s = c.cam.solid()
    assert s.isValid()
    # OCCT's adaptive integral (its fixed Gauss rule, cadquery's Volume(), is 1.2e-2 off on the barrel
    # indexer's long B-spline flank faces)
    from cam_workbench.kernel.solids import SURFACE_VOLUME_EPS, kernel_volume

    assert kernel_volume(s.wrapped, SURFACE_VOLUME_EPS) == pytest.approx(c.cam.volume, rel=1e-4)


def _workplane(c: Case) -> None:
    wp = c.cam.workplane()
    assert len(wp.solids().vals()) == 1


def _part(c: Case) -> None:
    p = c.cam.part()
    assert p.volume == pytest.approx(c.cam.volume, rel=1e-3)


def _profile_edge(c: Case) -> None:
    area = _edge_area(c.cam.profile_edge())
    assert area > 0, "not counter-clockwise"
    assert area == pytest.approx(c.cam.design.profile_area, rel=1e-5)


def _pitch_edge(c: Case) -> None:
    area = abs(_edge_area(c.cam.pitch_edge()))
    # the profile lies inside the pitch curve, by the roller (and half a groove's clearance)
    assert area >= c.cam.design.profile_area * (1 - 1e-6)
    if c.cam.design.profile_inset == 0:
        assert area == pytest.approx(c.cam.design.profile_area, rel=1e-5)


def _export_step(c: Case) -> None:
    path = c.cam.export_step(c.tmp / "cam.step")
    assert path.read_text(encoding="ascii", errors="replace").startswith("ISO-10303-21;")


def _export_dxf(c: Case) -> None:
    import ezdxf

    path = c.cam.export_dxf(c.tmp / "cam.dxf")
    doc = ezdxf.readfile(path)
    assert len(doc.modelspace()) > 0
    assert not doc.audit().has_errors


def _outputs(c: Case) -> None:
    out = c.cam.outputs()
    assert out.summary is c.cam.report() and out.design is c.cam.design


def _report(c: Case) -> None:
    r = c.cam.report()
    assert r["units"] == c.cam.spec.units
    assert r["volume"] == c.cam.volume
    if "area" in r:                      # a barrel or globoidal indexer has no exact top face (Cam.area refuses)
        assert r["area"] == c.cam.area
    else:
        with pytest.raises(NotAvailable):
            c.cam.area
    assert abs(r["solid"]["volume_rel_diff"]) < 1e-4          # OCCT's volume of the solid vs the exact one


def _checks(c: Case) -> None:
    assert json.dumps(c.cam.checks(), sort_keys=True) == json.dumps(c.cam.report()["checks"], sort_keys=True)


def _export(c: Case) -> None:
    written = c.cam.export(c.tmp / "set", plots=True)
    on_disk = json.loads((c.tmp / "set" / "report.json").read_text(encoding="utf-8"))
    assert on_disk == written
    assert written["volume"] == c.cam.volume
    for name in ("step", "dxf", "html"):
        assert (c.tmp / "set" / written["files"][name]).stat().st_size > 0
    # with plots=True every figure of the page is a PNG file, and only those
    page = (c.tmp / "set" / written["files"]["html"]).read_text(encoding="utf-8")
    figures = set(re.findall(r'<figure id="fig-([a-z_]+)"', page))
    assert figures and {f"plot_{k}.png" for k in figures} == set(written["files"]["plots"])
    for name in written["files"]["plots"]:
        assert (c.tmp / "set" / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def _dynamics(c: Case) -> None:
    # the train's data, by the follower's motion (docs/dynamics.md)
    # an indexer's output train: the output's inertia (indexer.output_inertia) on the turret shaft's torsional
    # stiffness (docs/indexing.md)
    indexer = c.cam.spec.cam.body.endswith("_indexer")
    train = ({"torsional_stiffness": 1e8} if indexer else
             {"torsional_stiffness": 2e6, "arm_inertia": 500.0} if c.cam.spec.follower.motion == "oscillating"
             else {"stiffness": 2000.0, "mass": 0.5})
    d = c.cam.dynamics(sweep=False, **train).summary()
    assert d["speed_rpm"] == c.cam.spec.cam.speed_rpm
    if indexer:
        assert d["turret"]["natural_frequency_hz"] == d["model"]["natural_frequency_hz"] > 0


def _ecam(c: Case) -> None:
    path = c.tmp / "cam.csv"
    t = c.cam.ecam("csv", path)
    assert path.read_text(encoding="utf-8") == t.text
    # the master runs over one turn; the slave stays within the spec's lift and reaches most of it
    pts = t.points
    assert pts.master[0] == 0.0 and pts.master[-1] == pytest.approx(360.0)
    lift = c.cam.spec.max_lift
    assert pts.slave.max() <= lift * (1 + 1e-9) + 1e-12 and pts.slave.max() > 0.5 * lift


def _area(c: Case) -> None:
    assert np.isfinite(c.cam.area) and c.cam.area > 0


def _volume(c: Case) -> None:
    assert np.isfinite(c.cam.volume) and c.cam.volume > 0


def _is_valid(c: Case) -> None:
    assert c.cam.is_valid() is True


def _shape(c: Case) -> None:
    _is_solid(c.cam.shape)


def _step_shape(c: Case) -> None:
    _is_solid(c.cam.step_shape)


_FOLLOWER = {"roller": "roller", "knife": "knife", "flat": "flat face"}


def _repr(c: Case) -> None:
    text = repr(c.cam)
    spec = c.cam.spec
    assert text.startswith("Cam(") and text.endswith(")")
    assert f"{spec.cam.body} cam" in text and f"lengths in {spec.units}" in text
    # the follower as report.json describes it (an indexer's is its turret)
    follower = c.cam.design.summary()["follower"]
    assert follower["motion"] in text and _FOLLOWER[follower["kind"]] in text


def _repr_svg(c: Case) -> None:
    svg = c.cam._repr_svg_()
    root = ET.fromstring(svg)
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    assert root.find(".//{http://www.w3.org/2000/svg}path") is not None


#: every public member of Cam (and its two Jupyter faces) → how the test calls and checks it
MEMBERS: dict[str, Callable[[Case], None]] = {
    "example": _example, "from_toml": _from_toml, "from_dict": _from_dict,
    "spec": _spec, "design": _design, "source": _source,
    "shape": _shape, "step_shape": _step_shape, "solid": _solid, "workplane": _workplane, "part": _part,
    "is_valid": _is_valid, "profile_edge": _profile_edge, "pitch_edge": _pitch_edge,
    "export_step": _export_step, "export_dxf": _export_dxf, "export": _export,
    "outputs": _outputs, "report": _report, "checks": _checks, "dynamics": _dynamics, "ecam": _ecam,
    "area": _area, "volume": _volume, "repr": _repr, "_repr_svg_": _repr_svg,
}


def public_members(cam: Any) -> set[str]:
    """The public members of the class and of an instance (attributes set in ``__init__``), and
    the two faces Jupyter and the console show."""
    from cam_workbench import Cam

    names = {n for n, _ in inspect.getmembers(Cam) if not n.startswith("_")}
    names |= {n for n in vars(cam) if not n.startswith("_")}
    return names | {"repr", "_repr_svg_"}


# ---- docs/python.md's table ---------------------------------------------------------------------
def cells(member: str) -> dict[str, str]:
    """The row of ``member`` in "What each body serves": body → the cell's text."""
    return doc_table(raw=True)[member]


def doc_table(raw: bool = False) -> dict[str, dict[str, str]]:
    """"What each body serves": member → body → "yes" or "refuses" (``raw``: the cell's text)."""
    text = DOC.read_text(encoding="utf-8")
    lines = text.split("### What each body serves", 1)[1].split("| member |", 1)[1].splitlines()
    header = [h.strip() for h in lines[0].strip(" |").split("|")]
    rows = []
    for line in lines[2:]:              # the table: its lines up to the first that is not a row
        if not line.startswith("| `"):
            break
        rows.append(line)
    assert tuple(header) == BODIES, header
    table: dict[str, dict[str, str]] = {}
    for row in rows:
        parts = [c.strip() for c in row.strip(" |").split("|")]
        for name in re.findall(r"`([\w]+)(?:\(\))?`", parts[0]):
            table[name] = {b: v if raw else "refuses" if v.startswith("refuses") else "yes" if v.startswith("yes") else v
                           for b, v in zip(BODIES, parts[1:])}
    return table


def doc_refusals() -> set[str]:
    text = DOC.read_text(encoding="utf-8")
    return set(re.findall(r"^- `(Cam\.[^`]+)`$", text.split("The refusals, word for word:", 1)[1], re.M))


def exercise(case: Case, random_spec: bool = False) -> dict[str, str]:
    """Every public member on ``case.cam``: member → "yes" (returned, its value checked),
    "refuses" (NotAvailable, documented word for word), "missing" (an extra not installed:
    MissingDependency naming it), or — for a random spec only — "cannot" (GeometryError/SolveError:
    OCCT or the machining refuses that cam, in one line)."""
    members = public_members(case.cam)
    assert members == set(MEMBERS), (f"public members without a row in MEMBERS: {sorted(members - set(MEMBERS))}; "
                                     f"rows of no member: {sorted(set(MEMBERS) - members)}")
    outcome: dict[str, str] = {}
    for name in sorted(MEMBERS):
        try:
            MEMBERS[name](case)
            outcome[name] = "yes"
        except NotAvailable as exc:
            body = case.cam.spec.cam.body
            assert f"a {body} cam" in str(exc) and "instead" in str(exc), str(exc)
            assert str(exc) in doc_refusals(), f"not documented word for word in docs/python.md: {exc}"
            outcome[name] = "refuses"
        except MissingDependency as exc:
            assert "pip install" in str(exc), str(exc)
            outcome[name] = "missing"
        except SpecError as exc:            # a combination the member does not model, naming the option
            assert str(exc).startswith(f"{exc.field}: "), str(exc)
            outcome[name] = f"SpecError naming {exc.field}"
        except (GeometryError, SolveError) as exc:
            if not random_spec:
                raise
            assert str(exc).strip() and "\n" not in str(exc).strip(), str(exc)
            outcome[name] = "cannot"
    return outcome


def agrees_with_doc(body: str, outcome: dict[str, str]) -> None:
    table = doc_table()
    assert set(table) == set(MEMBERS), (sorted(set(MEMBERS) - set(table)), sorted(set(table) - set(MEMBERS)))
    for name, got in outcome.items():
        if got in ("missing", "cannot"):
            continue
        if got.startswith("SpecError naming "):          # documented in the body's cell
            field = got.removeprefix("SpecError naming ")
            assert f"`SpecError` naming `{field}`" in cells(name)[body], f"{name} on a {body} cam: {got}, undocumented"
            continue
        assert got == table[name][body], f"{name} on a {body} cam: {got}, docs/python.md says {table[name][body]}"


# ---- the tests -------------------------------------------------------------------------------------
def test_one_class_two_names_loaded_lazily():
    """``Cam`` and ``PlateCam`` are one class in ``cam_workbench.cam``, loaded when first asked for."""
    code = ("import sys, cam_workbench\n"
            "assert 'cam_workbench.cam' not in sys.modules\n"
            "from cam_workbench import Cam, PlateCam\n"
            "assert Cam is PlateCam and Cam.__module__ == 'cam_workbench.cam' and Cam.__name__ == 'Cam'\n"
            "print('ok')\n")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0 and res.stdout.strip() == "ok", res.stderr


def test_doc_table_lists_every_member():
    from cam_workbench import Cam

    table = doc_table()
    assert set(table) == set(MEMBERS)
    assert all(set(v.values()) <= {"yes", "refuses"} for v in table.values()), table
    # a refusal documented for each member a body refuses
    refused = {name for name, row in table.items() if "refuses" in row.values()}
    assert {r.split("(")[0].split(":")[0].removeprefix("Cam.") for r in doc_refusals()} == refused
    assert Cam.profile_edge.__doc__ and "NotAvailable" in Cam.profile_edge.__doc__


@pytest.mark.parametrize("name", list(EXAMPLES))
def test_every_member_on_every_example(name, tmp_path):
    from cam_workbench import Cam

    cam = Cam.example(name)
    outcome = exercise(Case(cam, tmp_path, name))
    agrees_with_doc(cam.spec.cam.body, outcome)


def test_the_examples_cover_every_body():
    from cam_workbench.generators.spec.examples import example_spec

    assert {example_spec(n).cam.body for n in EXAMPLES} == set(BODIES)


_FEW = settings(max_examples=2, derandomize=True, deadline=None, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much,
                                       HealthCheck.function_scoped_fixture])


def _random_case(tmp_path_factory, d: dict, body: str) -> None:
    from cam_workbench import Cam

    try:
        cam = Cam(d)
    except (SpecError, GeometryError, SolveError):
        assume(False)                   # a spec that cannot be made: another draw
        return
    assert cam.spec.cam.body == body
    outcome = exercise(Case(cam, tmp_path_factory.mktemp(body), None), random_spec=True)
    agrees_with_doc(body, outcome)


@pytest.mark.parametrize("body", ["plate", "groove", "conjugate"])
def test_every_member_on_random_plane_cams(tmp_path_factory, body):
    @_FEW
    @given(specs(body=body))
    def run(d):
        _random_case(tmp_path_factory, d, body)

    run()


@_FEW
@given(cylindrical_specs())
def test_every_member_on_random_cylindrical_cams(tmp_path_factory, d):
    _random_case(tmp_path_factory, d, "cylindrical")


def test_refusal_is_a_cam_error_not_an_attribute_error():
    """The refusal reaches a script as a CamError (the CLI's one-line message), not as a missing
    attribute: ``hasattr`` sees the member on every cam."""
    from cam_workbench import Cam

    cam = Cam.example("cylindrical")
    assert hasattr(cam, "pitch_edge") and hasattr(cam, "profile_edge")
    with pytest.raises(NotAvailable) as err:
        cam.pitch_edge()
    assert isinstance(err.value, CamError) and not isinstance(err.value, AttributeError)


def test_picture_needs_no_matplotlib(tmp_path):
    """``_repr_svg_`` is the report's own SVG chart: it works where importing matplotlib fails (a
    ``matplotlib`` that raises ImportError first on the path), for a plane and a cylindrical cam."""
    fake = tmp_path / "matplotlib"
    fake.mkdir()
    (fake / "__init__.py").write_text("raise ImportError('no matplotlib here')\n", encoding="utf-8")
    code = ("import xml.etree.ElementTree as ET\n"
            "from cam_workbench import Cam\n"
            "for name in ('default', 'cylindrical'):\n"
            "    svg = Cam.example(name)._repr_svg_()\n"
            "    print(ET.fromstring(svg).tag.endswith('svg'), svg.count('<path') > 5)\n")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                         env={**__import__("os").environ, "PYTHONPATH": f"{tmp_path}:{ROOT}"})
    assert res.returncode == 0, res.stderr
    assert res.stdout.split() == ["True"] * 4

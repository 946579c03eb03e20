"""A groove cam's body as optimiser design variables (cam.outer_diameter, groove.clearance) and
the objective outer_diameter: gradients by complex step, the smallest disc against the rim wall
computed here from the exact pitch curve, the groove body's own check on the result, bounds,
refusals, CLI = API."""
import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from cam_workbench.generators import load_spec, to_toml
from cam_workbench.generators.cam_design import design_cam
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.optimise import optimise
from cam_workbench.generators.optimise.model import SmoothModel
from cam_workbench.generators.optimise.space import DesignSpace
from cam_workbench.generators.spec import CamSpec

from .conftest import requires_ocp
from .test_cli import run

H, R_F, WALL = 10.0, 5.0, 3.0        # lift, roller radius, groove.min_wall (the mm default) [mm]


def groove(offset=4.0, body="groove", bore=20.0, **opt):
    """A translating roller in a groove: cycloidal rise and return of 10 mm over 120°, dwells 60°."""
    cam = {"base_radius": 40.0, "thickness": 10.0, "body": body, "bore_diameter": bore}
    if body == "groove":
        cam["outer_diameter"] = 130.0
    return CamSpec.from_dict({
        "cam": cam, "follower": {"kind": "roller", "roller_radius": R_F, "offset": offset},
        "motion": [{"kind": "rise", "angle": 120, "lift": H, "law": "cycloidal"}, {"kind": "dwell", "angle": 60},
                   {"kind": "return", "angle": 120, "lift": H, "law": "cycloidal"}, {"kind": "dwell", "angle": 60}],
        "optimise": opt})


def smallest_disc(rb, e, clearance):
    """The smallest outer diameter leaving groove.min_wall to the rim: the outer wall's largest radius
    is the pitch curve's largest, √(e² + (√(R_b² − e²) + h)²), plus half the groove width r + c/2."""
    return 2 * (math.hypot(e, math.sqrt(rb * rb - e * e) + H) + R_F + clearance / 2 + WALL)


def test_groove_rows_gradients_exact():
    spec = groove(variables="base_radius, offset, outer_diameter, clearance", objective="outer_diameter")
    space = DesignSpace(spec)
    assert space.labels == ("cam.base_radius", "follower.offset", "cam.outer_diameter", "groove.clearance")
    model = SmoothModel(space)
    p = space.p0 * np.array([0.9, 1.1, 0.7, 2.0])
    vals, jac, _, _ = model.check_rows(p, True, 20)
    cs = []
    for i in range(p.size):
        pc = p.astype(complex)
        pc[i] += 1e-30j
        cs.append(model.check_rows(pc, False, 20)[0].imag / 1e-30)
    cs = np.array(cs).T
    assert np.max(np.abs(jac - cs)) / np.max(np.abs(cs)) < 1e-12
    assert np.all(np.abs(jac[:, 2:]).max(axis=0) > 0)          # D and c move rows


def test_smallest_outer_diameter_leaves_min_wall_to_the_rim():
    res = optimise(groove(variables="outer_diameter", objective="outer_diameter"))
    expect = smallest_disc(40.0, 4.0, 0.05)
    # the rows' margin (1e-4 of the disc radius) keeps the wall just above min_wall
    assert expect <= res.value <= expect * (1 + 2e-4)
    assert res.spec.cam.outer_diameter == res.value and res.checks.passed
    rep = design_cam(res.spec).body_report
    assert WALL <= rep["rim_wall"]["value"] <= WALL + 0.02
    # the body's own check, sampled, agrees with the exact rim wall to its sampling
    assert rep["rim_wall"]["value"] == pytest.approx(res.value / 2 - (expect / 2 - WALL), abs=1e-4)


@pytest.mark.parametrize("bore", [20.0, 6.0])
def test_clearance_goes_to_its_lower_bound_and_base_radius_to_its_limit(bore):
    """With R_b, D and c free (e = 0): the disc is smallest at the smallest clearance and the smallest
    R_b that both keeps the pressure angle ≤ 30° (root-finding the cycloid's closed form here) and leaves
    min_wall to the bore (R_b − r − c/2 − bore/2): the bore limits the 20 mm bore, the pressure angle
    the 6 mm one."""
    res = optimise(groove(offset=0.0, bore=bore, variables="base_radius, outer_diameter, clearance",
                          objective="outer_diameter", clearance_min=0.1, clearance_max=0.4, base_radius_min=6.0, outer_diameter_min=40.0
                          ).replace(**{"groove.clearance": 0.3}))
    beta = math.radians(120)
    x = np.linspace(0, 1, 200001)
    s = H * (x - np.sin(2 * np.pi * x) / (2 * np.pi))
    v = H * (1 - np.cos(2 * np.pi * x)) / beta
    rb = brentq(lambda r: np.max(np.arctan(v / (r + s))) - math.radians(30), 6, 80, xtol=1e-12)
    design = dict(zip(res.variables, res.design))
    assert design["groove.clearance"] == pytest.approx(0.1, abs=1e-9)
    assert design["cam.base_radius"] == pytest.approx(max(rb, bore / 2 + WALL + R_F + 0.1 / 2), rel=3e-4)
    from .conftest import ROOT

    doc = " ".join((ROOT / "docs" / "optimiser.md").read_text(encoding="utf-8").split())
    assert f"30° pressure-angle limit ({rb:.3f} mm, root-found there)" in doc
    assert res.value == pytest.approx(smallest_disc(design["cam.base_radius"], 0.0, 0.1), rel=2e-4)
    assert res.checks.passed
    rep = design_cam(res.spec).body_report
    assert rep["rim_wall"]["value"] >= WALL and rep["bore_wall"]["value"] >= WALL


def test_given_bounds_are_kept_and_checked():
    space = DesignSpace(groove(variables="outer_diameter, clearance", objective="outer_diameter",
                               outer_diameter_min=100.0, outer_diameter_max=140.0, clearance_max=0.2))
    assert np.allclose(space.lower, [100.0, 0.0]) and np.allclose(space.upper, [140.0, 0.2])
    with pytest.raises(SpecError) as exc:
        DesignSpace(groove(variables="outer_diameter", outer_diameter_max=120.0)).check_start()
    assert exc.value.field == "optimise.outer_diameter_max"
    with pytest.raises(SpecError) as exc:
        groove(variables="outer_diameter", outer_diameter_min=120.0, outer_diameter_max=110.0)
    assert exc.value.field == "optimise.outer_diameter_max"


@pytest.mark.parametrize("body, variables, objective, field, says", [
    ("plate", "base_radius, outer_diameter", "area", "optimise.variables", 'this cam\'s body is "plate", which has none'),
    ("plate", "clearance", "area", "optimise.variables", "groove cam's"),
    ("plate", "base_radius", "outer_diameter", "optimise.objective", "outer_diameter is a groove cam's disc"),
    ("groove", "base_radius", "outer_diameter", "optimise.variables", "needs outer_diameter among the variables"),
])
def test_refusals_name_the_field(body, variables, objective, field, says):
    with pytest.raises(SpecError) as exc:
        groove(body=body, variables=variables, objective=objective)
    assert exc.value.field == field and says in exc.value.rule


@requires_ocp
def test_cli_and_api_give_the_same_disc(tmp_path):
    path = tmp_path / "groove.toml"
    path.write_text(to_toml(groove()))
    out = tmp_path / "opt"
    res = run("optimise", str(path), "--variables", "outer_diameter", "--objective", "outer_diameter",
              "-o", str(out))
    assert res.returncode == 0, res.stderr
    rep = json.loads((out / "report.json").read_text())
    api = optimise(groove(variables="outer_diameter", objective="outer_diameter"))
    assert rep["optimise"]["final_value"] == pytest.approx(api.value, rel=1e-12)
    assert load_spec(out / "optimised.toml").cam.outer_diameter == pytest.approx(api.value, rel=1e-12)
    plate = tmp_path / "plate.toml"
    plate.write_text(to_toml(groove(body="plate")))
    bad = run("optimise", str(plate), "--variables", "outer_diameter", "--objective", "area",
              "-o", str(tmp_path / "never"))
    assert bad.returncode == 2 and "optimise.variables" in bad.stderr and not (tmp_path / "never").exists()
    assert "Traceback" not in bad.stderr


def test_panel_offers_the_body_variables_of_a_groove_cam_only():
    from cam_workbench.freecad import optimiser as O

    tokens = [c.token for c in O.variable_choices(groove(variables="outer_diameter", objective="outer_diameter"))]
    assert "outer_diameter" in tokens and "clearance" in tokens
    plain = [c.token for c in O.variable_choices(groove(body="plate", variables="base_radius"))]
    assert "outer_diameter" not in plain and "clearance" not in plain
    spec = groove(variables="base_radius, outer_diameter, clearance", objective="outer_diameter")
    assert O.selected_tokens(spec) >= {"base_radius", "outer_diameter", "clearance"}
    assert O.variables_text(spec, ["outer_diameter", "base_radius", "clearance"]) == "base_radius, outer_diameter, clearance"


# ---- cylindrical cams: their own design, COBYLA on the body's checks ----------------------------
def test_cylindrical_smallest_cylinder_is_the_pressure_angle_limit():
    """The example barrel cam (cycloidal rise of 20 mm over 120°): the pressure angle at the pitch
    radius, tan φ = s′/R_p, is largest where s′ = 2h/β, so the smallest R_p for 30° is
    (2h/β)/tan 30° and the smallest cylinder has R_o = R_p (the pitch radius within the groove)."""
    from cam_workbench.generators.spec.examples import example_spec

    res = optimise(example_spec("cylindrical"), objective="outer_diameter",
                   variables="cylinder_radius, outer_diameter")
    rp = (2 * 20.0 / math.radians(120)) / math.tan(math.radians(30))
    design = dict(zip(res.variables, res.design))
    assert design["cam.cylinder_radius"] == pytest.approx(rp, rel=3e-4)
    assert res.value == pytest.approx(2 * rp, rel=3e-4) and res.value >= 2 * rp
    assert res.checks.passed and res.status == "converged"
    assert res.spec.cam.base_radius == res.spec.cam.cylinder_radius
    from cam_workbench.generators.bodies.cylindrical import CylindricalBody

    rep = CylindricalBody.design(res.spec).checks_report["checks"]
    assert rep["passed"] and rep["results"]["pressure_angle"]["value"] <= 30.0


@pytest.mark.parametrize("changes, field, says", [
    ({"objective": "area"}, "optimise.objective", "optimised for outer_diameter"),
    ({"objective": "outer_diameter", "variables": "base_radius, outer_diameter"}, "optimise.variables",
     "a cylindrical cam's design variables are cylinder_radius, outer_diameter, clearance"),
    ({"objective": "outer_diameter", "variables": "cylinder_radius"}, "optimise.variables",
     "needs outer_diameter among the variables"),
    ({"objective": "outer_diameter", "algorithm": "slsqp"}, "optimise.algorithm", "cobyla"),
])
def test_cylindrical_refusals(changes, field, says):
    from cam_workbench.generators.spec.examples import example_spec

    with pytest.raises(SpecError) as exc:
        optimise(example_spec("cylindrical"), **changes)
    assert exc.value.field == field and says in exc.value.rule


def test_cylinder_radius_is_a_cylindrical_cams_only():
    with pytest.raises(SpecError) as exc:
        groove(variables="cylinder_radius")
    assert exc.value.field == "optimise.variables" and "cylinder_radius is a cylindrical cam's" in exc.value.rule


@requires_ocp
def test_cylindrical_cli_and_api_agree(tmp_path):
    from cam_workbench.generators.spec.examples import example_spec

    out = tmp_path / "cyl"
    res = run("optimise", "--example", "cylindrical", "--objective", "outer_diameter", "--variables",
              "cylinder_radius,outer_diameter", "-o", str(out))
    assert res.returncode == 0, res.stderr
    rep = json.loads((out / "report.json").read_text())["optimise"]
    api = optimise(example_spec("cylindrical"), objective="outer_diameter", variables="cylinder_radius, outer_diameter")
    assert rep["final_value"] == pytest.approx(api.value, rel=1e-12) and rep["feasible"] is True
    assert load_spec(out / "optimised.toml").cam.cylinder_radius == pytest.approx(api.spec.cam.cylinder_radius, rel=1e-12)
    assert (f"objective outer_diameter (outer diameter (cam.outer_diameter), report.json spec.cam.outer_diameter): "
            f"{rep['initial_value']:.6g} → {rep['final_value']:.6g} mm") in res.stdout
    bad = run("optimise", "--example", "cylindrical", "-o", str(tmp_path / "never"))
    assert bad.returncode == 2 and "optimise.objective" in bad.stderr and not (tmp_path / "never").exists()


def test_docs_quote_the_cylindrical_run():
    from cam_workbench.generators.spec.examples import example_spec

    from .conftest import ROOT

    res = optimise(example_spec("cylindrical"), objective="outer_diameter")
    doc = " ".join((ROOT / "docs" / "optimiser.md").read_text(encoding="utf-8").split())
    assert f"outer diameter {res.initial_value:.4g} → {res.value:.4g} mm in {res.evaluations} evaluations" in doc


def test_panel_offers_outer_diameter_for_a_groove_cam_only():
    from cam_workbench.freecad import optimiser as O

    assert "outer_diameter" in O.objective_choices(groove(variables="outer_diameter"))
    assert "outer_diameter" not in O.objective_choices(groove(body="plate", variables="base_radius"))


def test_cylindrical_oscillating_arm_ends_at_its_pressure_angle_limit():
    """The oscillating-arm barrel cam: the result passes the body's own checks with the pressure
    angle at its 30° limit (to the margin), and a pitch radius 0.1 % smaller fails that check —
    the body's own check function decides, not the optimiser's copy of it."""
    from cam_workbench.generators.bodies.cylindrical import CylindricalBody
    from cam_workbench.generators.spec.examples import example_spec

    res = optimise(example_spec("cylindrical_oscillating"), objective="outer_diameter")
    rep = CylindricalBody.design(res.spec).checks_report["checks"]
    assert rep["passed"] and res.status == "converged"
    assert rep["results"]["pressure_angle"]["value"] == pytest.approx(30.0, rel=2e-4)
    rp = res.spec.cam.cylinder_radius
    smaller = res.spec.replace(**{"cam.cylinder_radius": rp * 0.999, "cam.base_radius": rp * 0.999})
    assert CylindricalBody.design(smaller).checks_report["checks"]["results"]["pressure_angle"]["status"] == "fail"


def test_panel_offers_a_cylindrical_cams_own_variables():
    from cam_workbench.freecad import optimiser as O
    from cam_workbench.generators.spec.examples import example_spec

    spec = example_spec("cylindrical")
    assert [c.token for c in O.variable_choices(spec)] == ["cylinder_radius", "outer_diameter", "clearance"]
    assert O.objective_choices(spec) == ("outer_diameter",)

"""Every documented option against every other through the Python API (Cam): a valid
solid whose numbers pass the independent invariants, or a clean refusal (SpecError naming a
field, GeometryError with a cam angle) — never another exception."""
from __future__ import annotations

import json

import pytest
from hypothesis import given, settings

from cam_workbench.generators.errors import GeometryError, SpecError, SolveError

from ..conftest import requires_ocp
from .conftest import examples
from .invariants import check_design, check_solid, cylindrical_volume
from .strategies import cylindrical_specs, specs


@requires_ocp
@settings(max_examples=examples(24, 600))
@given(specs())
def test_cam_any_valid_spec(tmp_path_factory, d):
    from cam_workbench import Cam

    try:
        cam = Cam(d)
    except SpecError as exc:
        assert exc.field and str(exc).startswith(exc.field), str(exc)
        return
    except (GeometryError, SolveError) as exc:
        assert "°" in str(exc) or getattr(exc, "angle_deg", None) is not None or getattr(exc, "kind", None) == "kernel", str(exc)
        return
    try:
        report = cam.report()
    except (GeometryError, SpecError, SolveError) as exc:     # machining / kernel refusals
        assert str(exc).strip() and "\n" not in str(exc).strip(), str(exc)
        return
    check_solid(cam.shape)
    check_design(cam.design, report)
    from cam_workbench.kernel.solids import kernel_volume

    # the kernel's solid (its integrals good to ~1e-5 on B-spline faces) has the body's exact volume
    assert abs(kernel_volume(cam.shape) / report["volume"] - 1) < 5e-5, (kernel_volume(cam.shape), report["volume"])
    assert json.loads(json.dumps(report)) is not None            # report.json can hold it
    out = tmp_path_factory.mktemp("api")
    written = cam.export(out / "set")
    assert written["checks"] == json.loads(json.dumps(report["checks"]))
    assert (out / "set" / "cam.step").stat().st_size > 0


@requires_ocp
@settings(max_examples=examples(8, 200))
@given(cylindrical_specs())
def test_cylindrical_any_valid_spec(tmp_path_factory, d):
    """Cylindrical cams over their options: a valid solid with the volume computed here from the
    groove's definition, walls within their reported error of the exact walls, a STEP file that
    reads back — or a clean refusal."""
    from cam_workbench import Cam
    from cam_workbench.kernel.solids import kernel_volume

    try:
        cam = Cam(d)
        report = cam.report()
    except SpecError as exc:
        assert exc.field and str(exc).startswith(exc.field), str(exc)
        return
    except (GeometryError, SolveError) as exc:
        assert "°" in str(exc) or getattr(exc, "angle_deg", None) is not None, str(exc)
        return
    check_solid(cam.shape)
    v = cylindrical_volume(cam.spec)
    assert abs(report["volume"] / v - 1) < 1e-6, (report["volume"], v)
    kv = kernel_volume(cam.shape, 1e-6)             # OCCT's adaptive integration of the wall faces
    assert abs(kv / v - 1) < 1e-6, (kv, v)
    # report.json's: OCCT's fixed Gauss rule (≤ 1.4e-5 measured on B-spline walls), within what the report allows
    assert abs(report["solid"]["volume_rel_diff"]) <= 5e-5 <= report["solid"]["volume_rule"]["allowed"], report["solid"]
    wall = report["body"]["wall_error"]
    scale = cam.spec.cam.cylinder_radius
    assert wall["value"] <= 1e-5 * scale, wall
    out = tmp_path_factory.mktemp("cyl")
    written = cam.export(out / "set")
    assert written["checks"] == json.loads(json.dumps(report["checks"]))
    assert (out / "set" / "cam.step").stat().st_size > 0

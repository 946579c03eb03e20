"""The spatial indexers' machining outputs through the pipeline's registry
(exporters/machining_spatial_indexer.py: ``machining_outputs(design, summary)`` for the built-in
"barrel_indexer" and "globoidal_indexer" examples): one generating program ``cam.nc``, its
``[machining]`` mapping and refusals, report.json's ``machining`` section held to
``SpatialProgram.summary()``, the header's report lines held to the summary, and the program run
through LinuxCNC's ``rs274`` (tests/rs274.py) with the cutter's axis rebuilt from the interpreted
moves by tests/test_gcode_spatial_indexer.py's helpers and held to the exact roller axis."""
from __future__ import annotations

import dataclasses
import inspect
import json
import math
import time

import numpy as np
import pytest

from cam_workbench import Cam
from cam_workbench.exporters import machining_spatial_indexer as msi
from cam_workbench.exporters.atomic import OutputSet
from cam_workbench.exporters.gcode_spatial_indexer import spatial_program
from cam_workbench.exporters.machining_outputs import PROGRAMS, machining_outputs
from cam_workbench.exporters.output_rule import MANIFEST, spec_claim
from cam_workbench.generators.checks.claims import checks_verdict
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.kinds import body_of
from cam_workbench.pipeline import summary_stage

from .conftest import requires_ocp
from .rs274 import requires_rs274, run_rs274
from .test_gcode_spatial_indexer import (fixed_tip, header, interpreted, is_barrel, roller_points, rz_minus,
                                         sweep_moves, tip_parameter, tool_direction)

NAMES = ("barrel_indexer", "globoidal_indexer")
REPORT_LINES = 3           # pressure angle, checks verdict, spec digest


@dataclasses.dataclass
class Made:
    name: str
    design: object
    summary: dict
    out: msi.SpatialMachiningOutputs
    seconds: float


@pytest.fixture(scope="module", params=NAMES)
def made(request):
    design = Cam.example(request.param).design
    summary = summary_stage(design)
    t0 = time.perf_counter()
    out = machining_outputs(design, summary)
    seconds = time.perf_counter() - t0
    print(f"\n{request.param}: machining_outputs {seconds:.2f} s, path error "
          f"{out.machining_summary['path_error']['value']:.3g} mm (tolerance "
          f"{out.machining_summary['chord_tolerance']:g} mm), {out.machining_summary['gcode_lines']} lines")
    return Made(request.param, design, summary, out, seconds)


def report_free(text):
    """``text`` without the header's report lines (what spatial_program wrote)."""
    drop = ("(pressure angle: ", "(design checks", "(spec digest: ")
    return "\n".join(line for line in text.split("\n") if not line.startswith(drop))


# ---- the registry and report.json's section ------------------------------------------------------
def test_one_program_registered_for_the_design(made):
    out = made.out
    assert PROGRAMS.of(made.design) is msi.spatial_indexer_outputs
    assert isinstance(out, msi.SpatialMachiningOutputs)
    assert out.files == {"gcode": "cam.nc"} and out.second_gcode is None and out.interpolator_summary is None
    with pytest.raises(SpecError) as err:
        out.commands_csv
    assert err.value.field == "--mode"
    assert out.gcode.startswith("%\n") and out.gcode.endswith("%\n")
    assert max(len(line) for line in out.gcode.splitlines()) <= 255          # LinuxCNC's line length


def test_the_machining_section_is_the_programs_own_numbers(made):
    """Every number of report.json's ``machining`` is SpatialProgram.summary()'s (the program made
    again here from the spec's defaults), and the text is spatial_program's with the report lines."""
    ix = made.design.geometry.indexer
    p = spatial_program(made.design.geometry, tolerance=0.005, spindle_rpm=3000.0)   # the defaults (passes = 1: 3 mm levels)
    s = made.out.machining_summary
    want = p.summary()
    lines = want.pop("lines")
    assert s["generating"] == want
    assert made.out.program.summary() == {**want, "lines": lines}
    assert (s["program"], s["dialect"], s["file"]) == ("generating 4-axis", "linuxcnc", "cam.nc")
    assert (s["tool_radius"], s["roller_radius"], s["stock"]) == (p.tool_radius, p.roller_radius, p.stock) \
        == (ix.roller_radius, ix.roller_radius, 0.0)
    assert (s["feed_rate"], s["plunge_rate"], s["chord_tolerance"], s["g64_p"]) == (p.feed, p.plunge_feed,
                                                                                     p.tolerance, p.blend)
    assert (s["feed_rate"], s["plunge_rate"], s["tool_number"], s["spindle_rpm"], s["safe_height"], s["passes"],
            s["step_deg"], s["milling"]) == (150.0, 50.0, 1, 3000.0, 5.0, len(p.levels), 1.0, "climb")
    assert len(p.levels) > 1            # passes = 1 (the default): the program's own 3 mm levels
    pe = s["path_error"]
    assert (pe["value"], pe["tolerance"], pe["limit"], pe["unit"]) == (p.chord_error, p.tolerance, p.budget, "mm")
    assert 0 < pe["value"] <= pe["limit"] < pe["tolerance"]
    assert report_free(made.out.gcode) == p.text
    assert s["gcode_lines"] == made.out.gcode.count("\n") == p.lines + REPORT_LINES
    json.dumps(s)                                                                  # plain values


def test_the_module_defaults_are_the_generating_programs():
    sig = inspect.signature(spatial_program).parameters
    assert (msi.DEFAULT_FEED, msi.DEFAULT_SAFE_HEIGHT, msi.DEFAULT_TOLERANCE, msi.STEP_DEG) == (
        sig["feed"].default, sig["safe_height"].default, sig["tolerance"].default, sig["step_deg"].default)


def test_the_header_quotes_the_summary(made):
    s = made.summary
    head = header(made.out.gcode)
    pa = s["pressure_angle"]
    limit = s["checks"]["results"]["pressure_angle"]["limit"]
    assert f"pressure angle: max {pa['max_deg']:.2f} deg at {pa['at_deg']:.2f} deg [limit {limit:g} deg]" in head
    assert checks_verdict(s["checks"]).replace("(", "[").replace(")", "]") in head
    assert f"spec digest: {s['spec_digest']}" in head
    bare = msi.spatial_indexer_outputs(made.design).gcode                    # no summary: nothing quoted
    assert "design checks: not stated [program written without the report summary]" in header(bare)
    assert not any(line.startswith(("pressure angle", "spec digest")) for line in header(bare))
    assert report_free(bare) == report_free(made.out.gcode)


# ---- through LinuxCNC's interpreter --------------------------------------------------------------
def axis_errors(ix, moves, levels, reach, n=16):
    """Per sweep move: the largest distance, at λ = k/n, between the cutter's axis (the interpreted
    words interpolated linearly, the tip at its depth level) and roller 0's exact axis at θ = A,
    at both ends of the axis' reach (test_gcode_spatial_indexer's mapping)."""
    start = np.array([m.start for m in moves])
    end = np.array([m.end for m in moves])
    s1, off = tip_parameter(ix, end)
    assert off.max() <= 2e-4                                                     # the tip on the roller's axis
    levels = np.asarray(levels)
    tip_t = levels[np.argmin(np.abs(s1[:, None] - levels[None, :]), axis=1)]
    t = np.asarray(reach)
    lam = np.linspace(0.0, 1.0, n + 1)
    w = start[:, None, :] + lam[None, :, None] * (end - start)[:, None, :]
    want, _ = roller_points(ix, w[..., 3], t)
    tip = fixed_tip(ix, w)
    got = tip[..., None, :] + (t[None, None, :] - tip_t[:, None, None])[..., None] \
        * tool_direction(ix, w[..., 5])[..., None, :]
    got = rz_minus(np.radians(w[..., 3])[..., None], got)
    return np.linalg.norm(got - want, axis=-1).max(axis=(1, 2))


def check_in_rs274(design, out, folder, tool_number, tool_radius):
    """Run ``out.gcode`` through rs274; every block interpreted, the cutter's axis within the path
    error of the exact roller axis; returns the measured error [mm]."""
    ix = design.geometry.indexer
    g = out.machining_summary["generating"]
    run = run_rs274(out.gcode, folder, tool_number, 2 * tool_radius)
    assert run.units == "mm"
    moves = interpreted(run.stdout)
    blocks = [line for line in out.gcode.splitlines() if line[:3] in ("G0 ", "G1 ")]
    assert len(moves) == len(blocks)
    assert sum(m.kind == "feed" for m in moves) == sum(b.startswith("G1 ") for b in blocks)
    cutting = sweep_moves(moves)
    assert len(cutting) == g["moves"]
    err = axis_errors(ix, cutting, g["levels_t_mm"], g["reach_t_mm"])
    pe = out.machining_summary["path_error"]
    assert err.max() == pytest.approx(pe["value"], abs=1e-6)
    assert err.max() <= pe["limit"]
    return float(err.max())


@requires_rs274
def test_the_program_runs_in_rs274_within_its_tolerance(made, tmp_path):
    err = check_in_rs274(made.design, made.out, tmp_path, 1, made.design.geometry.indexer.roller_radius)
    print(f"\n{made.name}: rs274 cutter axis vs roller axis {err:.3g} mm")
    text = made.out.gcode
    for word in ("T1 M6", "S3000 M3", "G54", "G64 P0.0005", "G93", "M2"):
        assert word in text, word


@requires_rs274
@pytest.mark.parametrize("name", NAMES)
def test_the_machining_section_is_respected(name, tmp_path):
    """Every mapped ``[machining]`` field reaches the program: a smaller tool leaves stock, three
    depth levels, the feeds, the tolerance, the safe height, the tool and the spindle."""
    spec = Cam.example(name).design.spec
    mc = {"machining.tool_radius": 10.0, "machining.tool_number": 3, "machining.spindle_rpm": 5000.0,
          "machining.feed_rate": 240.0, "machining.plunge_rate": 60.0, "machining.passes": 3,
          "machining.chord_tolerance": 0.01, "machining.safe_height": 8.0, "machining.contour": "lines"}
    spec2 = spec.replace(**mc)
    design = body_of(spec2).design(spec2)
    out = machining_outputs(design, summary_stage(design))
    s = out.machining_summary
    assert (s["tool_radius"], s["tool_number"], s["spindle_rpm"], s["feed_rate"], s["plunge_rate"], s["passes"],
            s["chord_tolerance"], s["safe_height"], s["stock"]) == (10.0, 3, 5000.0, 240.0, 60.0, 3, 0.01, 8.0, 2.0)
    g = s["generating"]
    assert len(g["levels_t_mm"]) == 3 and g["tolerance_mm"] == 0.01 and g["g64_p_mm"] == pytest.approx(0.001)
    assert s["path_error"]["value"] <= 0.9 * 0.01
    for word in ("T3 M6", "S5000 M3", "G64 P0.001", "F = 240 mm/min", "plunges 60 mm/min", "stock 2 mm"):
        assert word in out.gcode, word
    assert ("G43 H3" in out.gcode) == (name == "barrel_indexer")
    check_in_rs274(design, out, tmp_path, 3, 10.0)


@requires_ocp
@requires_rs274
def test_the_programs_origin_is_the_step_solids(made, tmp_path):
    """cam.nc and cam.step have one origin: cam.step (written by the public API, read back through
    OCP) spans 0 ≤ z ≤ cam.thickness about the cam axis, and the program's words run through rs274,
    taken as cam.step's coordinates renamed with no shift — the cam-frame point Rz(−A)·(Y, Z, X) —
    put the finishing cutter (the roller's size) in the solid's groove: at poses inside each
    finishing sweep, points 0.05 mm inside the cutter along the roller's length are not in the solid,
    and points 0.3 mm outside it reach the solid (the flank it finishes).  The finishing tips' X range
    is centred on the solid's z band (X = z: read from the cam's middle plane it is off by W/2)."""
    from cam_workbench.kernel import ocp as occ
    from cam_workbench.kernel.step import read_step

    spec = made.design.spec
    ix = made.design.geometry.indexer
    shape = read_step(Cam.example(made.name).export_step(tmp_path / "cam.step"))
    box = occ.Bnd_Box()
    occ.add_to_box(shape, box, optimal=True)
    x0, y0, z0, x1, y1, z1 = occ.box_limits(box)
    assert (z0, z1) == pytest.approx((0.0, spec.cam.thickness), abs=1e-5)                  # the STEP's z band
    assert x0 < 0 < x1 and y0 < 0 < y1                                                   # about the cam axis
    rr = ix.roller_radius
    run = run_rs274(made.out.gcode, tmp_path, 1, 2 * rr)
    moves = sweep_moves(interpreted(run.stdout))
    fin = {side: [m for m in moves if m.tag.startswith(f"finishing side {side:+d}")] for side in (1, -1)}
    tips_x = np.array([m.end[0] for side in fin for m in fin[side]])
    middle = 0.5 * (z0 + z1)
    # centred on the band (X0 in the cam's middle plane would put it W/2 = 10 times this bound off)
    assert abs(0.5 * (tips_x.min() + tips_x.max()) - middle) <= 0.05 * (z1 - z0)
    assert tips_x.min() < z0 + rr and tips_x.max() > z1 - rr                              # across the band
    classifier = occ.BRepClass3d_SolidClassifier(shape)

    def in_solid(p):
        classifier.Perform(occ.gp_Pnt(*map(float, p)), 1e-7)
        return classifier.State() == occ.TopAbs_IN

    t_tip = ix.root_radius if is_barrel(ix) else math.sqrt(ix.root_radius ** 2 - rr ** 2)  # the final depth
    t = ix.roller_start + np.array([0.25, 0.75]) * (ix.roller_end - ix.roller_start)      # along the roller
    om = np.linspace(0.0, 2 * math.pi, 8, endpoint=False)
    for side, sweep in fin.items():
        for m in (sweep[int(f * (len(sweep) - 1))] for f in (0.25, 0.5, 0.75)):
            w = m.end
            d = tool_direction(ix, w[5])
            e1 = np.array([1.0, 0.0, 0.0]) if is_barrel(ix) else np.cross(d, [0.0, 0.0, 1.0])
            e1 /= np.linalg.norm(e1)
            e2 = np.cross(d, e1)
            tip = np.array([w[1], w[2], w[0]])                       # cam.step's (x, y, z) at A = 0: no shift

            def ring(r, tip=tip, d=d, e1=e1, e2=e2, a=w[3]):
                p = tip + (t[:, None, None] - t_tip) * d + r * (np.cos(om)[None, :, None] * e1
                                                               + np.sin(om)[None, :, None] * e2)
                return rz_minus(math.radians(a), p.reshape(-1, 3))

            assert not any(in_solid(p) for p in ring(rr - 0.05)), (side, w[3])
            assert any(in_solid(p) for p in ring(rr + 0.3)), (side, w[3])


# ---- refusals ------------------------------------------------------------------------------------
REFUSED = (("machining.program", "xc"), ("machining.depth", 10.0), ("machining.lead_radius", 4.0),
           ("machining.milling", "conventional"), ("machining.work_offset", "G55"),
           ("machining.line_numbers", True), ("machining.coolant", True), ("machining.rotary_line", "axis"),
           ("machining.rotary_speed_rpm", 30.0), ("machining.sample_period", 0.002),
           ("machining.tool_radius", 12.5), ("machining.chord_tolerance", 1e-4))


@pytest.mark.parametrize("field,value", REFUSED, ids=[f for f, _ in REFUSED])
def test_settings_the_program_cannot_honour_are_refused_by_name(made, field, value):
    """A ``[machining]`` setting the program cannot honour is a SpecError naming it (the spec's
    machining fields do not enter the geometry: the design is the example's with the spec replaced)."""
    bad = dataclasses.replace(made.design, spec=made.design.spec.replace(**{field: value}))
    with pytest.raises(SpecError) as err:
        machining_outputs(bad)
    assert err.value.field == field


# ---- written with the other outputs ----------------------------------------------------------------
def test_write_adds_the_program_to_the_output_set(made, tmp_path):
    folder = tmp_path / "out"
    with OutputSet(folder, spec_claim(made.design.spec, "build", f"example:{made.name}")) as o:
        made.out.write(o)
        assert o.names == ["cam.nc"]
    assert (folder / "cam.nc").read_text(encoding="utf-8") == made.out.gcode
    assert "cam.nc" in json.loads((folder / MANIFEST).read_text())["files"]
    assert sorted(p.name for p in folder.iterdir()) == sorted(["cam.nc", MANIFEST])

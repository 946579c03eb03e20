"""The three indexers' dynamics in a real FreeCAD (``freecadcmd``): Check design's table with
``DynamicsEnabled`` on is the output train's (docs/indexing.md, "Dynamics").

For an indexer (``cam.body`` parallel, barrel or globoidal indexer) report.json's ``dynamics``
section is the turret train's: the output's inertia on the turret shaft's torsional stiffness,
its "contact force" the shaft torque (N·mm), its error the output's angle error φ − ψ (degrees),
and a ``turret`` subsection.  One FreeCAD run creates each built-in example with
``dynamics.enabled`` and ``dynamics.torsional_stiffness = 1e8`` (the doc's table) and runs
``design_report``; here, each is compared with report.json's ``dynamics`` section that
``cam-workbench build`` writes for the spec FreeCAD exports (``cam_workbench.pipeline.run_pipeline``,
the function ``build`` calls, and ``report_json_text``, its JSON):

* every row's number is the section's own at the keys the row names (FreeCAD's numpy/scipy
  against the virtual environment's: 1e-9 of the quantity's scale), its cam angle too, and its
  unit is the one the section gives for that key;
* no row speaks of a follower, a lift or a contact force: the first row and the verdict say the
  rollers hold the turret both ways, the loads are the shaft torque, the error the angle error;
* a bad field — a ``DynamicsMass`` (a follower's, not an indexer's), no
  ``DynamicsTorsionalStiffness``, or no ``IndexerOutputInertia`` — shows the library's message naming the property and the field, and
  the cam itself is still checked.
"""
from __future__ import annotations

import json
import re

import pytest

from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.spec.examples import example_dict

from .freecad_support import fc_home, requires_freecadcmd, run_freecadcmd  # noqa: F401

pytestmark = requires_freecadcmd

INDEXERS = ("parallel_indexer", "barrel_indexer", "globoidal_indexer")
#: N·mm/rad: docs/indexing.md's table (a steel shaft of about 40 mm over 200 mm)
STIFFNESS = 1e8


def dyn_spec(name: str) -> dict:
    d = example_dict(name)
    d.setdefault("dynamics", {}).update(enabled=True, torsional_stiffness=STIFFNESS)
    return d


SCRIPT = """
import FreeCAD, os
from cam_workbench.freecad.feature import create
from cam_workbench.freecad.check_design import design_report
from cam_workbench.freecad.spec_io import export_spec
specs = json.loads(SPECS)
doc = FreeCAD.newDocument("idyn")

def dump(rep):
    return {"ok": rep.ok, "verdict": rep.verdict(), "dynamics_verdict": rep.dynamics_verdict(),
            "enabled": rep.dynamics_enabled, "error": rep.dynamics_error, "kept": rep.contact_kept,
            "title": rep.dynamics_title, "n_checks": len(rep.checks), "checks_error": rep.checks_error,
            "n_rows": len(rep.rows), "text": rep.text(), "section": rep.dynamics_dict,
            "rows": [{"cells": r.cells(), "value": r.value, "at": r.at_deg, "path": r.path, "at_path": r.at_path,
                      "unit": r.unit, "status": r.status} for r in rep.dynamics]}

for name, spec in specs.items():
    cam = create(doc, spec, name=name)
    RESULT[name] = dump(design_report(cam))
    export_spec(cam, os.path.join(OUT, name + ".toml"))

# bad [dynamics] input, as a user gives it in the property editor
bad = create(doc, specs["barrel_indexer"], name="WithMass")
bad.DynamicsMass = 3.0                # a follower's mass: not an indexer's
RESULT["mass"] = dump(design_report(bad))
plain = create(doc, EXAMPLES["globoidal_indexer"], name="NoStiffness")
RESULT["plain"] = dump(design_report(plain))
plain.DynamicsEnabled = True          # switched on, no DynamicsTorsionalStiffness given
RESULT["nostiff"] = dump(design_report(plain))
noj = create(doc, specs["parallel_indexer"], name="NoInertia")
noj.IndexerOutputInertia = 0.0
RESULT["noinertia"] = dump(design_report(noj))
"""


@pytest.fixture(scope="module")
def fc(tmp_path_factory, fc_home):  # noqa: F811
    out = tmp_path_factory.mktemp("idyn_out")
    specs = {n: dyn_spec(n) for n in INDEXERS}
    head = (f"SPECS = {json.dumps(json.dumps(specs))}\nOUT = {str(out)!r}\n"
            f"EXAMPLES = json.loads({json.dumps(json.dumps({n: example_dict(n) for n in INDEXERS}))})\n")
    run = run_freecadcmd(head + SCRIPT, tmp_path_factory.mktemp("idyn_run"), fc_home).check()
    assert "Traceback" not in run.console, run.console[-3000:]
    return run.result, out


def report_dynamics(spec: CamSpec) -> dict:
    """report.json's ``dynamics`` section as ``cam-workbench build`` writes it for ``spec``: the
    pipeline's stages (no solid, machining or drawing: they add other sections) and its JSON text."""
    from cam_workbench.exporters.report_json import report_json_text
    from cam_workbench.pipeline import run_pipeline

    out = run_pipeline(spec, solid=False, machining=False, drawing=False)
    return json.loads(report_json_text(out.summary))["dynamics"]


def _at(d, path):
    for k in path:
        d = d[k]
    return d


def expected_unit(d: dict, path: list) -> str:
    """The unit report.json's ``dynamics`` section gives the number at ``path``."""
    head, key = path[0], path[-1]
    if head == "speed_rpm":
        return "rpm"
    if head == "model":
        return {"natural_frequency_hz": "Hz"}[key]
    if head == "contact":
        return d["contact"]["unit"]
    if head in ("error", "residual_vibration"):
        return d["error"]["unit"]
    if head == "torque":
        return d["torque"]["unit"]
    assert head == "turret", path
    t = d["turret"]
    if key.endswith("_arcmin"):
        return "arcmin"
    if key.endswith("_deg"):
        return "deg"
    if key.endswith("_s"):
        return "s"
    fixed = {"output_inertia": t["inertia_unit"], "torsional_stiffness": t["stiffness_unit"], "fn_ti": "",
             "dynamic_factor": ""}
    if key in fixed:
        return fixed[key]
    return _at(t, path[1:2])["unit"]      # shaft_torque.max, deflection.max_positive, …dwells[i].max_error


def scales(d: dict) -> dict[str, float]:
    """Each unit's scale (the largest magnitude of the section in it): 1e-9 of it is round-off."""
    t = d["turret"]
    emax = d["error"]["max"]
    return {d["contact"]["unit"]: max(abs(d["contact"]["max_force"]), abs(d["contact"]["min_force"])),
            d["error"]["unit"]: emax, "arcmin": 60.0 * emax,
            d["torque"]["unit"]: max(abs(d["torque"]["dynamic"]["max"]), abs(d["torque"]["dynamic"]["min"]),
                                     t["shaft_torque"]["max"])}


def _keys(d):
    """The section's shape: every key path (lists by index)."""
    if isinstance(d, dict):
        return {(k, *rest) for k, v in d.items() for rest in (_keys(v) or {()})}
    if isinstance(d, list):
        return {(i, *rest) for i, v in enumerate(d) for rest in (_keys(v) or {()})}
    return set()


#: words of a follower train that an output train's row must not use
FOLLOWER_WORDS = re.compile(r"follower|contact force|displacement|\blift\b|on the cam|\|q − s\||jump", re.I)


@pytest.mark.parametrize("name", INDEXERS)
def test_indexer_dynamics_rows_equal_report_json(fc, name):
    """Every number of the indexer's dynamics table is report.json's (``build``'s pipeline on the
    spec FreeCAD exports), at the keys its row names, with the section's unit and cam angle; the
    rows are the output train's, labelled as such."""
    from cam_workbench.freecad.check_design import fmt_number
    from cam_workbench.generators.spec import load_spec

    r, out = fc
    exported = load_spec(out / f"{name}.toml")
    assert exported.to_dict() == CamSpec.from_dict(dyn_spec(name)).to_dict()   # properties → spec lose nothing
    d = report_dynamics(exported)
    got = r[name]
    assert got["enabled"] and got["error"] is None and got["checks_error"] is None, got
    assert got["kept"] is True and got["ok"] is True and got["n_checks"] > 3 and got["n_rows"] > 5
    assert got["title"] == "Output train dynamics"
    # the dialog's dict is report.json's section: the same keys (its numbers are the rows' below)
    assert _keys(got["section"]) == _keys(d)
    assert got["section"]["model"]["coordinate"] == d["model"]["coordinate"] == "turret angle"
    assert d["contact"]["unit"] == "N·mm" and d["error"]["unit"] == "deg" and "jump_speed" not in d

    rows = got["rows"]
    scale = scales(d)
    # (unit, value, cam angle) of every peak of the section that a row names with its angle
    peaks = [(row["unit"], _at(d, row["path"]), _at(d, row["at_path"])) for row in rows if row["at_path"]]
    numbers = set()
    for row in rows:
        label, shown, unit = row["cells"][0], row["cells"][1], row["cells"][2]
        assert not FOLLOWER_WORDS.search(label), label
        assert row["path"] is not None, row
        ref = _at(d, row["path"])
        assert unit == row["unit"] == expected_unit(d, row["path"]), row
        assert row["value"] == pytest.approx(ref, rel=1e-9, abs=1e-9 * scale.get(unit, 0.0)), (row, ref)
        if row["path"] != ["speed_rpm"]:
            assert shown in {fmt_number(ref * (1 + t)) for t in (-1e-9, 0.0, 1e-9)}, (row, ref)
        if row["at_path"] is not None:
            at = _at(d, row["at_path"])
            if row["at"] != pytest.approx(at, abs=1e-6):
                # a tie: a symmetric index's equal and opposite peaks (|J ψ̈| at 135° and 225°), the
                # round-off choosing the other — then the section has that magnitude at that angle
                assert any(u == unit and abs(v) == pytest.approx(abs(row["value"]), rel=1e-9)
                           and a == pytest.approx(row["at"], abs=1e-6) for u, v, a in peaks), (row, at)
            assert row["cells"][3] == f"{row['at']:.3f}°"
        numbers.add(tuple(row["path"]))

    first = rows[0]
    assert first["path"] == ["speed_rpm"] and first["value"] == d["speed_rpm"]
    assert first["cells"] == [f"output train at {fmt_number(d['speed_rpm'])} rpm (the analysis speed)",
                              "rollers hold the turret both ways", "rpm", "—", "pass"]
    assert got["dynamics_verdict"] == (f"the rollers hold the turret both ways at {fmt_number(d['speed_rpm'])} rpm "
                                       "(output train: no separation)")
    assert got["verdict"] == "all checks pass"
    assert "output train dynamics: the rollers hold the turret both ways" in got["text"]
    assert "follower dynamics" not in got["text"]
    by = {row["cells"][0]: row for row in rows}
    for label in ("smallest shaft torque (dynamic)", "largest shaft torque (rigid)"):
        assert by[label]["cells"][2] == "N·mm", label
    assert by["largest angle error |φ − ψ| (output − turret)"]["path"] == ["error", "max"]
    assert by["largest angle error |φ − ψ| (output − turret)"]["cells"][2] == "deg"
    # every number the section has for the turret train (and each dwell, each residual vibration)
    t = d["turret"]
    want = {("speed_rpm",), ("model", "natural_frequency_hz"),
            ("contact", "min_force"), ("contact", "max_force"), ("contact", "rigid_min_force"),
            ("contact", "rigid_max_force"), ("error", "max"), ("error", "max_vibration"),
            ("torque", "dynamic", "work_per_revolution"),
            *(("torque", w, k) for w in ("rigid", "dynamic") for k in ("max", "min", "rms")),
            *(("residual_vibration", i, "amplitude") for i in range(len(d["residual_vibration"]))),
            ("turret", "output_inertia"), ("turret", "torsional_stiffness"), ("turret", "index_angle_deg"),
            ("turret", "index_time_s"), ("turret", "fn_ti"), ("turret", "angle_error", "max_arcmin"),
            ("turret", "deflection", "max_arcmin"), ("turret", "deflection", "max_positive"),
            ("turret", "deflection", "max_negative"), ("turret", "shaft_torque", "max"),
            ("turret", "shaft_torque", "rigid_max"), ("turret", "shaft_torque", "dynamic_factor"),
            ("turret", "residual_vibration", "amplitude_arcmin"),
            *(("turret", "residual_vibration", "dwells", i, k) for i in range(len(t["residual_vibration"]["dwells"]))
              for k in ("amplitude_at_start_arcmin", "amplitude_at_end_arcmin", "max_error"))}
    assert numbers == want, numbers ^ want
    assert len(t["residual_vibration"]["dwells"]) >= 1 and len(d["residual_vibration"]) >= 1


def test_the_examples_numbers(fc):
    """docs/indexing.md's table at k_t = 1e8 N·mm/rad, read from the rows FreeCAD shows."""
    r, _out = fc
    doc = {"parallel_indexer": ("25.99", "0.569", "16556", "16281", "0.0422"),
           "barrel_indexer": ("75.03", "0.0896", "2607", "2605", "0.00238"),
           "globoidal_indexer": ("23.73", "0.464", "13511", "13025", "0.0383")}
    for name, (fn_ti, twist, torque, rigid, residual) in doc.items():
        by = {tuple(row["path"]): row["value"] for row in r[name]["rows"]}
        assert f"{by[('turret', 'fn_ti')]:.4g}" == fn_ti, name
        assert f"{by[('turret', 'deflection', 'max_arcmin')]:.3g}" == twist, name
        assert f"{by[('turret', 'shaft_torque', 'max')]:.0f}" == torque, name
        assert f"{by[('turret', 'shaft_torque', 'rigid_max')]:.0f}" == rigid, name
        assert f"{by[('turret', 'residual_vibration', 'amplitude_arcmin')]:.3g}" == residual, name


@pytest.mark.parametrize("case, message", [
    ("mass", "DynamicsMass (dynamics.mass): does not apply to an indexer: its output train is the output's "
             "inertia (indexer.output_inertia) on the turret shaft's torsional stiffness"),
    ("nostiff", "DynamicsTorsionalStiffness (dynamics.torsional_stiffness): is required for the dynamics of an "
                "indexer"),
    ("noinertia", "IndexerOutputInertia (indexer.output_inertia): the output train needs an inertia > 0 for the "
                  "dynamics"),
])
def test_bad_dynamics_input_names_the_field(fc, case, message):
    """A bad field shows the library's message (the spec's own rule) naming the property and the
    field, no table and no traceback; the cam itself is still checked and the verdict says why the
    dynamics were not analysed."""
    r, _out = fc
    got = r[case]
    assert got["enabled"] and got["kept"] is None and got["rows"] == [] and got["ok"] is False, got
    assert got["error"].startswith(message), got["error"]
    assert got["checks_error"] is None and got["n_checks"] > 3 and got["n_rows"] > 5
    assert got["dynamics_verdict"] == "output train dynamics not analysed: " + got["error"]
    assert got["title"] == "Output train dynamics"
    assert got["verdict"] == got["dynamics_verdict"]        # the cam's own checks pass
    # the library's rule, word for word
    field = re.search(r"\(([a-z_.]+)\): ", got["error"]).group(1)
    spec = dyn_spec({"mass": "barrel_indexer", "nostiff": "globoidal_indexer",
                     "noinertia": "parallel_indexer"}[case])
    if case == "mass":
        spec["dynamics"]["mass"] = 3.0
    elif case == "nostiff":
        del spec["dynamics"]["torsional_stiffness"]
    else:
        del spec["indexer"]["output_inertia"]
    from cam_workbench.generators.errors import SpecError

    with pytest.raises(SpecError) as exc:
        CamSpec.from_dict(spec)
    assert exc.value.field == field and got["error"].endswith(": " + exc.value.rule)


def test_no_table_without_dynamics_enabled(fc):
    r, _out = fc
    got = r["plain"]
    assert got["enabled"] is False and got["rows"] == [] and got["error"] is None and got["ok"] is True
    assert "dynamics" not in got["text"] and got["title"] == "Output train dynamics"

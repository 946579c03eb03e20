"""Nothing changes for users but the names (issue 21, item 6): every built-in example's outputs
through the command line and the Python API — report.json, the DXF drawings' entities, G-code,
the command table, the e-cam tables, the check table, the STEP solids' volume, faces and distances
from fixed probe points — are the recorded ones (tests/golden/data, made by ``make golden``
before the restructuring moved anything).

This is a guard against unintended change, not a test of correctness (the other tests hold the
numbers to closed forms and independent computations).  The comparison rules are in
tests/golden/compare.py (numbers to 1e-12 relative, with a floor scaled by the record's
magnitude; text identical); the one table of names a deliberate rename edits is
tests/golden/names.py (``RENAMED``, and ``WHERE`` for the modules the recorder imports).
Re-recording: tests/golden/README.md.
"""
from __future__ import annotations

import pytest

from .conftest import requires_ocp
from .golden.compare import compare_observations, report
from .golden.names import normalise, where
from .golden.observe import DATA, Observer, about
from .golden.record import load

RECORDED = sorted(p.name.removesuffix(".json.gz") for p in DATA.glob("*.json.gz"))


@pytest.fixture(scope="session")
def observer(request, tmp_path_factory):
    """One observer for the session: the command-line runs of every selected example start at
    once (in a thread pool), so that they run while the API part of an earlier one runs here."""
    obs = Observer(tmp_path_factory.mktemp("golden"))
    selected = [item.callspec.params["name"] for item in request.session.items
                if getattr(item, "originalname", None) == "test_outputs_are_the_recorded_ones"]
    for name in selected:
        obs.start(name)
    yield obs
    obs.close()


def test_every_example_is_recorded():
    """The recording covers exactly the built-in examples (a new example is recorded by ``make
    golden``; a removed one is a change users see)."""
    assert RECORDED == sorted(where("examples")), "re-record: tests/golden/README.md"  # type: ignore[call-overload]


def _obs(outputs: dict) -> dict:
    return {"format": 1, "example": "x", "outputs": outputs}


def test_the_comparison_finds_what_changed_and_says_where():
    """The rules of tests/golden/compare.py on a made-up recording: what passes, what fails, and a
    message naming the example, the output, the path inside it and both values."""
    old = {"report": {"max_deg": 21.223026201189022, "at_deg": 274.952353491022,
                      "left": {"acceleration": -7.016709298534876e-15, "jerk": 85.94366926962351},
                      "points": [[-2.4410598047010856e-16, 32.0, 0.0]], "n": 60, "ok": True},
           "gcode": "%\n(cam_workbench 0.1.0: plate cam)\nG0 Z5\n", "stdout": "see generators.examples"}
    same = {"report": {"max_deg": 21.223026201189022 * (1 + 9e-13), "at_deg": 274.952353491022,
                       "left": {"acceleration": 8e-13, "jerk": 85.94366926962351},
                       "points": [[0.0, 32.0, 0.0]], "n": 60, "ok": True},
            "gcode": "%\n(cam_workbench 0.2.0: plate cam)\nG0 Z5\n", "stdout": "see cam_workbench.generators.examples"}
    assert compare_observations(_obs(old), _obs(same)) == []
    changed = {"report": {"max_deg": 21.223026201189022 * (1 + 2e-12), "at_deg": 274.952353491022,
                          "left": {"acceleration": 1e-12, "jerk": 85.94366926962351},
                          "points": [[0.0, 32.0]], "n": 60.0, "ok": True, "new": 1},
               "gcode": "%\n(cam_workbench 0.1.0: plate cam)\nG0 Z6\n", "stdout": "see PlateCam"}
    found = {(m.output, m.path): m for m in compare_observations(_obs(old), _obs(changed))}
    assert set(found) == {("report", "max_deg"), ("report", "left.acceleration"), ("report", "points[0]"),
                          ("report", "n"), ("report", "new"), ("gcode", ""), ("stdout", "")}
    message = report("x", list(found.values()))
    assert "example 'x': 7 difference(s)" in message
    assert "report: left.acceleration: differs by 1.01e-12" in message and "recorded: -7.016709298534876e-15" in message
    assert "gcode: text differs: line 3 differs" in message
    assert "recorded: 'G0 Z5'" in message and "new:      'G0 Z6'" in message
    assert "type changed from int to float" in message and "3 items recorded, 2 now" in message


def test_the_names_table_renames_and_hides_what_varies():
    assert normalise("generators.spec and exporters.dxf, PlateCam") == \
        "cam_workbench.generators.spec and cam_workbench.exporters.dxf, Cam"
    assert normalise("cam_workbench.generators.spec, Cam") == "cam_workbench.generators.spec, Cam"
    assert normalise("(cam_workbench 0.1.0: plate cam) cam-workbench 1.2.3.dev4 2025-11-27T05:22:10Z") == \
        "(cam_workbench <version>: plate cam) cam-workbench <version> <date>"


@requires_ocp
@pytest.mark.parametrize("name", RECORDED)
def test_outputs_are_the_recorded_ones(name, observer):
    recorded = load(name)
    new = observer.observe(name, recorded)
    mismatches = compare_observations(recorded, new)
    if mismatches:
        then, now = recorded.get("about", {}), about()
        libraries = [f"{k} {then.get(k)} → {now.get(k)}" for k in sorted(then.keys() | now.keys())
                     if then.get(k) != now.get(k)]
        note = f"\n(recorded with other libraries than these: {', '.join(libraries)})" if libraries else ""
        pytest.fail(report(name, mismatches) + note, pytrace=False)

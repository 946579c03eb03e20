"""The same combinations through every CLI command: exit 0 (or 3: a design check failed) with
outputs that agree with each other, or a clean refusal (exit 2, one line naming a field or a
cam angle, nothing written) — never an internal error.  G-code runs through LinuxCNC's rs274.
Two commands run into one folder leave it consistent (docs/cli.md, "Output folders and your
files")."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cam_workbench.exporters.atomic import MANIFEST, read_manifest
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec import CamSpec, to_toml

from ..conftest import ROOT, SAFETY_S, assert_unchanged, requires_ocp, snapshot
from ..rs274 import RS274
from .conftest import examples
from .invariants import REFUSAL
from .strategies import cylindrical_specs, specs

CLI = [sys.executable, "-m", "cam_workbench.cli"]
EXTRA = ("gcode_xy", "gcode_xc", "gcode_csv", "dxf", "report", "optimise")


def cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([*CLI, *args], capture_output=True, text=True, cwd=ROOT, stdin=subprocess.DEVNULL,
                          timeout=SAFETY_S)


def assert_clean(res: subprocess.CompletedProcess, allowed=(0, 2, 3)) -> None:
    assert "Traceback" not in res.stderr and "internal error" not in res.stderr, res.stderr[-2000:]
    assert res.returncode in allowed, (res.returncode, res.stderr[-2000:])
    if res.returncode == 2:
        lines = [ln for ln in res.stderr.strip().splitlines() if ln.strip()]
        assert len(lines) == 1 and REFUSAL.search(lines[0]), res.stderr


def build_and_check(tmp, d) -> tuple[CamSpec, dict, dict, int] | None:
    """The spec ``d`` written as TOML, then ``build`` and ``check``: (spec, built report.json,
    checked report.json, check's exit status), or None after a clean refusal (a spec rule, or
    build's exit 2 with nothing written)."""
    try:
        spec = CamSpec.from_dict(d)
    except SpecError as exc:
        # a drawn program the spec's rules refuse (a polynomial segment that dips below s = 0):
        # a clean refusal naming the field, as the API combinations check
        assert exc.field and str(exc).startswith(exc.field), str(exc)
        return None
    (tmp / "cam.toml").write_text(to_toml(spec), encoding="utf-8")
    b = cli("build", str(tmp / "cam.toml"), "-o", str(tmp / "build"))
    assert_clean(b, (0, 2))
    c = cli("check", str(tmp / "cam.toml"), "-o", str(tmp / "check"))
    assert_clean(c, (0, 2, 3))
    if b.returncode == 2:
        assert not (tmp / "build").exists()
        return None
    built = json.loads((tmp / "build" / "report.json").read_text())
    checked = json.loads((tmp / "check" / "report.json").read_text())
    assert c.returncode == (0 if built["checks"]["passed"] else 3)
    return spec, built, checked, c.returncode


@requires_ocp
@settings(max_examples=examples(8, 300))
@given(specs(), st.sampled_from(EXTRA))
def test_cli_commands_agree(tmp_path_factory, d, extra):
    tmp = tmp_path_factory.mktemp("cli")
    done = build_and_check(tmp, d)
    if done is None:
        return
    spec, built, checked, _ = done
    for key in ("pitch", "pressure_angle", "curvature", "profile", "checks", "areas"):
        assert checked[key] == built[key], key
    html = (tmp / "build" / "report.html").read_text()
    # the checks' verdict says what report.json says (and nothing else on the page says "verdict pass")
    assert ("verdict pass" in html) == built["checks"]["passed"]
    assert ("verdict fail" in html) == (not built["checks"]["passed"])
    if extra.startswith("gcode"):
        mode = extra.split("_")[1]
        g = cli("gcode", str(tmp / "cam.toml"), "--mode", mode, "-o", str(tmp / f"p.{mode}"))
        assert_clean(g, (0, 2))
        if g.returncode == 0 and mode != "csv" and RS274 is not None:
            from ..rs274 import run_rs274

            m = spec.machining
            tool = m.tool_radius if m.tool_radius is not None else (spec.roller_radius or None)
            run = run_rs274((tmp / f"p.{mode}").read_text(), tmp, tool_diameter=2 * (tool or 3.0))
            assert run.motions and run.units == spec.units
    elif extra == "dxf":
        r = cli("dxf", str(tmp / "cam.toml"), "-o", str(tmp / "d.dxf"))
        assert_clean(r, (0,))
        import ezdxf

        doc = ezdxf.readfile(tmp / "d.dxf")
        assert not doc.audit().has_errors
    elif extra == "report":
        r = cli("report", str(tmp / "cam.toml"), "-o", str(tmp / "rep"))
        assert_clean(r, (0,))
        rep = json.loads((tmp / "rep" / "report.json").read_text())
        assert {k: v for k, v in rep.items() if k != "files"} == {k: v for k, v in built.items() if k != "files"}
    else:
        r = cli("optimise", str(tmp / "cam.toml"), "--max-evaluations", "10", "-o", str(tmp / "opt"))
        assert_clean(r, (0, 2, 3))


CYL_EXTRA = ("gcode", "dxf", "report", "dynamics", "ecam")


@requires_ocp
@settings(max_examples=examples(6, 150))
@given(cylindrical_specs(), st.sampled_from(CYL_EXTRA))
def test_cli_cylindrical_commands_agree(tmp_path_factory, d, extra):
    """Cylindrical cams through `build`, `check` and one more command: exit 0/3 with outputs that
    agree with report.json, or a clean refusal (exit 2, nothing written); the 4-axis program
    through rs274, the DXF audited."""
    tmp = tmp_path_factory.mktemp("cli_cyl")
    done = build_and_check(tmp, d)
    if done is None:
        return
    spec, built, checked, _ = done
    assert checked["checks"] == built["checks"]
    if extra == "gcode":
        g = cli("gcode", str(tmp / "cam.toml"), "-o", str(tmp / "p.nc"))
        assert_clean(g, (0, 2))
        if g.returncode == 0 and RS274 is not None:
            from ..rs274 import run_rs274

            m = spec.machining
            tool = m.tool_radius if m.tool_radius is not None else spec.roller_radius
            run = run_rs274((tmp / "p.nc").read_text(), tmp, tool_diameter=2 * tool)
            assert run.motions and run.units == spec.units
    elif extra == "dxf":
        r = cli("dxf", str(tmp / "cam.toml"), "-o", str(tmp / "d.dxf"))
        assert_clean(r, (0,))
        import ezdxf

        assert not ezdxf.readfile(tmp / "d.dxf").audit().has_errors
    elif extra == "report":
        r = cli("report", str(tmp / "cam.toml"), "-o", str(tmp / "rep"))
        assert_clean(r, (0,))
        rep = json.loads((tmp / "rep" / "report.json").read_text())
        assert {k: v for k, v in rep.items() if k != "files"} == {k: v for k, v in built.items() if k != "files"}
    elif extra == "dynamics":
        train = (["--set", "dynamics.mass=1.0", "--set", "dynamics.stiffness=1000"]
                 if spec.follower.motion == "translating" else [])
        r = cli("dynamics", str(tmp / "cam.toml"), *train, "--no-sweep",
                "-o", str(tmp / "dyn"))
        assert_clean(r, (0, 2, 3))
        if r.returncode == 2:
            assert spec.follower.motion == "oscillating" and "follower.motion" in r.stderr
    else:
        r = cli("ecam", str(tmp / "cam.toml"), "-o", str(tmp / "e.csv"))
        assert_clean(r, (0,))


#: commands that write into a folder (gcode: a file named inside it), the second run's relation to
#: the first: the same spec file, that file edited, an identical copy elsewhere, another cam
INTO = ("build", "report", "check", "dxf", "dynamics", "gcode")
RELATIONS = ("same", "edited", "copy", "other")


def _into(command: str, spec: Path, out: Path, replace: bool) -> list[str]:
    if command == "gcode":
        return ["gcode", str(spec), "-o", str(out / "cam.nc")]
    extra = (["--set", "dynamics.stiffness=2000", "--set", "dynamics.mass=1", "--no-sweep"]
             if command == "dynamics" else [])
    return [command, str(spec), *extra, "-o", str(out)] + (["--replace"] if replace else [])


@requires_ocp
@settings(max_examples=examples(5, 150))
@given(specs(), st.sampled_from(INTO[:-1]), st.sampled_from(INTO), st.sampled_from(RELATIONS), st.booleans(),
       st.data())
def test_two_commands_into_one_folder(tmp_path_factory, d, first, second, relation, replace, data):
    """Two commands into one folder in sequence: the second is refused (exit 2 naming -o, nothing
    changed), or the folder afterwards holds one spec's files — its manifest lists exactly what is
    there, report.json names the manifest's spec, and a file kept from the first run was made
    from that same spec.  An identical spec is never refused; another cam without --replace
    always is."""
    tmp = tmp_path_factory.mktemp("two")
    try:
        spec = CamSpec.from_dict(d)
    except SpecError:
        return
    a, b, out = tmp / "a.toml", tmp / "b.toml", tmp / "out"
    a.write_text(to_toml(spec), encoding="utf-8")
    assert_clean(cli(*_into(first, a, out, False)))
    held = read_manifest(out) if out.is_dir() else None
    target = a
    if relation == "edited":
        try:
            a.write_text(to_toml(spec.replace(**{"cam.thickness": spec.cam.thickness * 1.25})), encoding="utf-8")
        except SpecError:
            pass
    elif relation == "copy":
        b.write_text(a.read_text(encoding="utf-8"), encoding="utf-8")
        target = b
    elif relation == "other":
        try:
            other = CamSpec.from_dict(data.draw(specs(borderline=False)))
        except SpecError:
            return
        b.write_text(to_toml(other), encoding="utf-8")
        target = b
    before = snapshot(tmp / "out") if out.is_dir() else {}
    res = cli(*_into(second, target, out, replace))
    assert_clean(res)
    refused_o = res.returncode == 2 and res.stderr.startswith("error: -o: ")
    if relation in ("same", "copy"):
        assert not refused_o, res.stderr                   # the identical spec: never refused
    if relation == "other" and held is not None and not replace:
        assert res.returncode == 2, res.stdout             # another cam's set (or its own refusal)
    if res.returncode == 2:
        if out.is_dir():
            assert_unchanged(out, before)
        else:
            assert not before
        return
    m = read_manifest(out)
    assert m is not None
    assert {p.name for p in out.iterdir()} == set(m["files"]) | {MANIFEST}
    if (out / "report.json").is_file():
        assert json.loads((out / "report.json").read_text())["spec_digest"] == m["spec_digest"]
    after = snapshot(out)
    kept = [n for n, v in before.items() if n != MANIFEST and after.get(n) == v]
    if kept:                                               # files of the first run stay only beside their spec
        assert held is not None and held["spec_digest"] == m["spec_digest"], kept

"""Every `[machining]` option against every other, through every entry point (issue 25).

A hypothesis test draws a cam (the built-in plate examples, the groove, the conjugate pair and an
inch cam), the dialect, the cutter compensation, the program (XY, XY roughing from a round blank,
XC, wire EDM), milling, arcs or lines, line numbers, coolant and the roughing and wire fields in
their declared ranges.  Each draw is either

* refused: the API raises :class:`SpecError` (or :class:`GeometryError`: a cam that cannot be cut)
  naming a ``machining.*`` or ``cam.body`` field; then ``cam-workbench gcode`` exits 2 naming that
  field, prints no traceback and writes no file; or
* made: ``Cam(spec).outputs().machining.gcode`` is the very text ``cam-workbench gcode -o`` writes
  (a conjugate pair's second program too, ``--cam second``); a LinuxCNC program runs through
  LinuxCNC's own ``rs274``; a Fanuc or Sinumerik program parses with ``pygcode``
  (tests/gcode_words.py) and every arc's end lies on the circle through its start about its centre
  within the print quantum (a wrong I/J convention fails this); every word is a finite number.

``build``'s cam.nc (and cam2.nc) is compared with the API's text for a few combinations only (it
also makes the solid and the drawing).  Any other exception is a defect on valid input.
"""
from __future__ import annotations

import math
import re
import tempfile
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, event, example, given, settings
from hypothesis import strategies as st

from cam_workbench.cam import Cam
from cam_workbench.cli import main
from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import GeometryError, SpecError
from cam_workbench.generators.spec import CamSpec, dict_to_toml
from cam_workbench.generators.spec.examples import example_spec

from .conftest import paper_inch_dict, requires_ocp
from .gcode_words import read_program
from .rs274 import RS274, run_rs274

PLATES = ("default", "paper", "oscillating", "flat", "packaging")
#: "inch": a G20 cam, the paper's case-2 cam in inches (no built-in example is in inches)
EXAMPLES = (*PLATES, "groove", "conjugate", "inch")
DIALECTS = ("linuxcnc", "fanuc", "sinumerik")
PROGRAMS = ("xy", "xy+blank", "xc", "wire_edm")
INCH = 1 / 25.4
#: the decimals of a coordinate word (exporters/gcode.py prints 4 in mm, 5 in inches)
DECIMALS = {"mm": 4, "in": 5}
#: a word of a block: a letter and a finite number (never "nan", "inf" or an empty value)
WORD = re.compile(r"^[A-Z](-?(\d+\.?\d*|\.\d+))$")


def inch_dict() -> dict:
    """The paper's Table 1 case-2 roller cam in inches (as tests/test_roughing.py's inch cam)."""
    return paper_inch_dict({"chord_tolerance": 0.0002})


@lru_cache(maxsize=None)
def base_spec(name: str) -> CamSpec:
    return CamSpec.from_dict(inch_dict()) if name == "inch" else example_spec(name)


@lru_cache(maxsize=None)
def largest_profile_radius(name: str) -> float:
    """The largest distance of the exact profile from the cam axis (sampled densely here)."""
    _, p = design_cam(base_spec(name)).profile_ccw().sample(400)
    return float(np.hypot(p[:, 0], p[:, 1]).max())


@dataclass(frozen=True)
class Case:
    """One draw: the cam, ``gcode --mode`` (with "xy+blank": XY from a blank), ``--dialect``,
    ``--compensation`` (None: not given) and the ``--set`` fields."""

    example: str
    program: str
    dialect: str
    compensation: str | None
    fields: tuple[tuple[str, object], ...] = field(default=())
    #: the CLI reads a spec file whose machining.program is this (None: ``--example``), which
    #: ``--mode`` overrides
    file_program: str | None = None

    @property
    def mode(self) -> str:
        return "xy" if self.program == "xy+blank" else self.program

    def changes(self) -> dict[str, object]:
        out = {f"machining.{k}": v for k, v in self.fields}
        out["machining.program"] = self.mode
        out["machining.dialect"] = self.dialect
        if self.compensation is not None:
            out["machining.compensation"] = self.compensation
        return out

    def cli_args(self, folder: Path) -> list[str]:
        if self.example == "inch" or self.file_program is not None:
            d = base_spec(self.example).to_dict()
            if self.file_program is not None:
                d["machining"]["program"] = self.file_program
            spec_file = folder / "cam.toml"
            spec_file.write_text(dict_to_toml(d))
            args = ["gcode", str(spec_file)]
        else:
            args = ["gcode", "--example", self.example]
        args += ["--mode", self.mode, "--dialect", self.dialect]
        if self.compensation is not None:
            args += ["--compensation", self.compensation]
        for k, v in self.fields:
            args += ["--set", f"machining.{k}={str(v).lower() if isinstance(v, bool) else v}"]
        return args


def _length(draw, lo: float, hi: float, scale: float) -> float:
    """A length in [lo, hi] mm in the cam's units, 4 significant digits (a readable ``--set``)."""
    return float(f"{draw(st.floats(lo, hi)) * scale:.4g}")


@st.composite
def cases(draw) -> Case:
    example = draw(st.sampled_from(EXAMPLES))
    program = draw(st.sampled_from(PROGRAMS))
    scale = INCH if example == "inch" else 1.0
    fields: dict[str, object] = {
        "milling": draw(st.sampled_from(("climb", "conventional"))),
        "contour": draw(st.sampled_from(("arcs", "lines"))),
        "line_numbers": draw(st.booleans()),
        "coolant": draw(st.booleans()),
    }
    if fields["contour"] == "lines" and example != "inch":
        fields["chord_tolerance"] = 0.02          # a coarser tolerance: fewer chords, the same rules
    if draw(st.booleans()):
        fields["program_number"] = draw(st.integers(1, 9999))
    if program == "xy+blank":
        # margin beyond the profile: below the allowance the blank cannot hold the cam (a refusal)
        margin = _length(draw, -0.5, 15.0, scale)
        r = largest_profile_radius(example) if example not in ("groove", "conjugate") else 75.0
        fields["blank_diameter"] = float(f"{2 * (r + margin):.6g}")
        if draw(st.booleans()):
            fields["stepover"] = float(f"{draw(st.floats(0.05, 1.0)):.3g}")
        if draw(st.booleans()):
            fields["finish_allowance"] = _length(draw, 0.0, 1.0, scale)
    if program == "wire_edm":
        fields["wire_diameter"] = _length(draw, 0.02, 0.35, scale)
        fields["spark_gap"] = _length(draw, 0.0, 0.05, scale)
        fields["skim_passes"] = draw(st.integers(0, 4))
        fields["skim_stock"] = _length(draw, 0.002, 0.05, scale)
        fields["tab_width"] = _length(draw, 0.3, 20.0, scale)
        if draw(st.booleans()):
            fields["start_hole"] = _length(draw, 1.0, 8.0, scale)
        fields["wire_compensation"] = draw(st.sampled_from(("path", "controller")))
    compensation = draw(st.sampled_from((None, "centre", "controller")))
    if compensation is not None and draw(st.booleans()):
        fields["compensation"] = compensation           # as --set machining.compensation, not --compensation
        compensation = None
    return Case(example, program, draw(st.sampled_from(DIALECTS)), compensation, tuple(fields.items()),
                # (a spec file must be valid by itself: a groove's or conjugate's holds no wire EDM program)
                draw(st.sampled_from((None, "xy", "xc") + (("wire_edm",) if example in PLATES else ()))))


def api_programs(case: Case) -> tuple[list[str], object] | Exception:
    """The programs the API makes (the first cam's, then a conjugate pair's second), and the plan;
    or the refusal."""
    try:
        out = Cam(base_spec(case.example).replace(**case.changes())).outputs().machining
    except (SpecError, GeometryError) as exc:
        return exc
    texts = [out.gcode] + ([out.second_gcode] if out.second_gcode is not None else [])
    return texts, out.plan


def cli(args: list[str], capsys) -> tuple[int, str]:
    """``cam-workbench ARGS`` in this process: (exit status, standard error)."""
    capsys.readouterr()
    code = main(args)
    return code, capsys.readouterr().err


def check_words(text: str) -> None:
    """Every word of every block is a letter and a finite number (comments aside)."""
    for raw in text.splitlines():
        block = re.sub(r"\(.*?\)|;.*$", "", raw).strip()
        if not block or block == "%":
            continue
        bad = [w for w in block.split() if not WORD.match(w)]
        assert not bad, f"{raw!r}: {bad}"


def check_arcs_on_their_circles(text: str, units: str) -> int:
    """Parse with pygcode; every arc's end is on its circle: | |end − c| − |start − c| | within the
    print quantum's worst case.  Start, end and I, J are each rounded by ≤ q/2 per axis (q = 10^−d),
    so |start − c| = |I, J| is off by ≤ q/√2 and |end − c| (end − start − IJ) by ≤ 3q/√2: their
    difference by ≤ 4q/√2 = 2√2·q.  Returns the number of arcs."""
    q = 10.0 ** -DECIMALS[units]
    arcs = [m for m in read_program(text).moves if m.kind == "arc"]
    for m in arcs:
        r0 = abs(complex(m.start[0], m.start[1]) - m.centre)
        r1 = abs(complex(m.end[0], m.end[1]) - m.centre)
        assert abs(r1 - r0) <= 2 * math.sqrt(2) * q * (1 + 1e-9) + 1e-12, (m.tag, m.start, m.end, m.centre, r0, r1)
    return len(arcs)


def check_case(case: Case, folder: Path, capsys) -> str:
    """Check one draw (module docstring); returns what became of it (hypothesis' statistics)."""
    target = folder / "cam.nc"
    made = api_programs(case)
    code, err = cli([*case.cli_args(folder), "-o", str(target)], capsys)
    if isinstance(made, Exception):
        name = made.field if isinstance(made, SpecError) else "cam angle"
        if isinstance(made, SpecError):
            assert name.startswith("machining.") or name == "cam.body", made
        assert code == 2, (made, err)
        assert name in err and "Traceback" not in err, (str(made), err)
        assert not target.exists()
        return f"refused: {name}"
    texts, plan = made
    assert code == 0, err
    assert target.read_text() == texts[0]
    if len(texts) > 1:                             # a conjugate pair's second program: --cam second
        second = folder / "cam2.nc"
        code, err = cli([*case.cli_args(folder), "--cam", "second", "-o", str(second)], capsys)
        assert code == 0, err
        assert second.read_text() == texts[1]
    units = base_spec(case.example).units
    for text in texts:
        check_words(text)
        if case.dialect == "linuxcnc":
            if RS274 is None:
                pytest.skip("LinuxCNC's rs274 is not installed")
            # the standalone rs274 reads its tool table in inches, whatever the program's units
            table_diameter = 2 * plan.tool_radius * (INCH if units == "mm" else 1.0)
            run = run_rs274(text, folder, plan.tool_number, table_diameter)
            assert run.units == units and run.motions
        else:
            assert check_arcs_on_their_circles(text, units) or case.program == "xc" or plan.contour == "lines"
    return f"made: {case.program}, {case.dialect}"


@settings(max_examples=100, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(case=cases())
# `gcode FILE --mode xy --set machining.compensation=controller` on a spec file whose program is "xc"
# was refused (the --set fields were checked before --mode applied): an XY program under compensation
@example(case=Case("default", "xy", "linuxcnc", None, (("compensation", "controller"),), file_program="xc"))
@example(case=Case("packaging", "xy", "fanuc", None, (("compensation", "controller"), ("milling", "conventional")),
                   file_program="wire_edm"))
# two faults: the CLI named the one the half-made spec met first (skim_passes), the API the spec's first
# rule (dialect)
@example(case=Case("default", "wire_edm", "fanuc", None, (("skim_passes", 1), ("wire_compensation", "controller"))))
def test_every_combination_through_api_and_cli(tmp_path, capsys, case):
    event(check_case(case, Path(tempfile.mkdtemp(dir=tmp_path)), capsys))


# ---- build: cam.nc (and cam2.nc) are the API's texts -----------------------------------------
BUILD_CASES = [
    Case("default", "xy+blank", "fanuc", "centre", (("blank_diameter", 116.0), ("line_numbers", True))),
    Case("conjugate", "xy", "sinumerik", "controller", (("coolant", True), ("contour", "lines"))),
    Case("paper", "wire_edm", "linuxcnc", None, (("skim_passes", 2), ("tab_width", 3.0))),
    Case("packaging", "xc", "sinumerik", None, (("program_number", 7),)),
]


@requires_ocp
@pytest.mark.parametrize("case", BUILD_CASES, ids=lambda c: f"{c.example}-{c.program}-{c.dialect}")
def test_build_writes_the_api_programs(tmp_path, capsys, case):
    texts, _ = api_programs(case)
    out = tmp_path / "out"
    args = case.cli_args(tmp_path)
    code, err = cli(["build", *args[1:args.index("--mode")], *_set_args(case), "-o", str(out)], capsys)
    assert code == 0, err
    assert (out / "cam.nc").read_text() == texts[0]
    assert (out / "cam2.nc").is_file() == (len(texts) > 1)
    if len(texts) > 1:
        assert (out / "cam2.nc").read_text() == texts[1]


def _set_args(case: Case) -> list[str]:
    """``build`` has no --mode/--dialect/--compensation: the same choices as ``--set``."""
    args = []
    for k, v in case.changes().items():
        args += ["--set", f"{k}={str(v).lower() if isinstance(v, bool) else v}"]
    return args

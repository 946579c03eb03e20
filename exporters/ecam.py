"""Electronic-cam tables for servo motion controllers, from the motion program
(:mod:`cam_workbench.generators.ecam`), in the formats their vendors document:

``csv`` — θ [deg], s, s′, s″, s‴ (per radian, the project's convention) at every table point, one
    header row naming the columns and their units.

``codesys`` — CODESYS SoftMotion (SM3_Basic, SM3_CamBuilder):

    * ``xyva``: a global variable list holding an ``ARRAY OF SMC_CAMXYVA`` (dX master position, dY
      slave position, dV = dY/dX, dA = d²Y/dX²) and the ``MC_CAM_REF`` that points at it
      (byType 3 = XYVA), laid out exactly as CODESYS's own "Display Generated Code" shows a cam:
      https://content.helpme-codesys.com/en/CODESYS%20SoftMotion/_sm_cmd_cam_display_generated_code.html
      (fields: https://content.helpme-codesys.com/en/libs/SM3_Basic/Current/SM3_Basic/DataTypes/CAM/MC_CAM_REF.html,
      SMC_CAM_TYPE: .../SM3_Basic/DataTypes/CAM/SMC_CAM_TYPE.html; dV and dA as derivatives with
      respect to the master — "slave velocity/acceleration at constant master velocity 1" — per the
      SMC_CAMXYVA description in Lenze's PLC Designer SoftMotion manual, §5.7.2, CODESYS-based);
    * ``poly5``: a PROGRAM that builds the same cam with the CamBuilder (SoftMotion ≥ 4.17):
      ``camBuilder.Append(SMCB.Poly5(left, right))`` per interval, ``SMCB.BoundImplicit()`` on the
      left after the first, then ``SMCB.InitCamRef`` and ``camBuilder.Write`` as in
      https://content.helpme-codesys.com/en/CODESYS%20SoftMotion/_sm_basic_cam_programmatic_creation.html
      (``SMCB.Bound(x, y, v, a)``: the page shows Bound(X, Y, V) with A left at its default 0 for the
      documented X, Y, V, A table; the fourth argument here is A in that order).

    Between two points both are the 5th-degree polynomial through Y, V, A at both ends.

``beckhoff`` — TwinCAT 3 NC Camming (TF5050, Tc2_MC2_Camming):

    * ``motion_function``: an ``ARRAY OF MC_MotionFunctionPoint`` (PointIndex from 1, FunctionType
      MOTIONFUNCTYPE_POLYNOM5_MM = 15, "polynom with order 5 (motion <-> motion)", PointType
      MOTIONPOINTTYPE_MOTION, RelIndexNextPoint 1, MasterPos X, SlavePos Y, SlaveVelo Y′, SlaveAcc
      Y″, SlaveJerk Y‴ — the struct's own comments name them X, Y, Y′, Y″, Y‴) and an MC_CAM_REF of
      TableType MC_TABLETYPE_MOTIONFUNCTION (22):
      https://infosys.beckhoff.com/content/1033/tf5050_tc3_nc_camming/1003721995.html,
      .../1003744011.html (MC_MotionFunctionType), .../1003758987.html (MC_MotionPointType),
      .../1003794571.html (MC_TableType);
    * ``position_table``: the two-column ``ARRAY[0..n, 0..1] OF LREAL`` of master and slave
      positions (MC_TABLETYPE_EQUIDISTANT or NONEQUIDISTANT), for MC_INTERPOLATIONTYPE_LINEAR:
      https://infosys.beckhoff.com/content/1033/tcplclibmc2_camming/460439563.html (MC_CAM_REF),
      .../tf5050_tc3_nc_camming/1003709323.html (MC_InterpolationType).  The array is initialised
      row by row (IEC 61131-3: the rightmost subscript varies fastest).  pArray and ArraySize are
      set in code (ADR, SIZEOF) as Beckhoff's example does; the file says how.

``lenze`` — the motion-profile import file of Lenze's Global Drive Cam Loader (manual 1.1 EN
    05/2005, §4.2.1: an ASCII *.txt, one "x y" pair per line, ascending x, separated by spaces,
    comments after "//", at least two points): written with a point as the decimal sign and nine
    decimals.  Lenze documents linear interpolation between grid points for its characteristics
    (9400 function library, L_CamCurve); the pages found do not say how a drive interpolates a motion
    profile, so the deviation reported is the linear interpolation's.

Not written because no vendor documentation of them was found: CODESYS's cam-editor import files,
Beckhoff's TwinCAT Cam Design Tool files and Beckhoff's spline interpolation of position tables
(MC_INTERPOLATIONTYPE_SPLINE: "tangential or cyclic depending on table", not specified far enough
to reproduce its deviation).

Every file states, in its comments, the deviation of its own interpolation from the exact motion,
measured on the numbers as written (:func:`cam_workbench.generators.ecam.interpolation_deviation`).
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from cam_workbench.generators import __version__
from cam_workbench.generators.kinds import body_of
from cam_workbench.generators.ecam import Deviation, TablePoints, interpolation_deviation, table_points
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.motion.program import MotionProgram
from cam_workbench.generators.spec import ECAM_TABLES, CamSpec

from .atomic import write_text_atomic

DEG = math.pi / 180.0
#: the table → (interpolation the controller applies, file suffix)
TABLE_KINDS: dict[str, tuple[str | None, str]] = {
    "points": (None, ".csv"), "xyva": ("quintic", ".st"), "poly5": ("quintic", ".st"),
    "motion_function": ("quintic", ".st"), "position_table": ("linear", ".st"),
}
CODESYS_MAX_ELEMENTS = 32767
SOURCES = {
    "xyva": "https://content.helpme-codesys.com/en/CODESYS%20SoftMotion/_sm_cmd_cam_display_generated_code.html",
    "poly5": "https://content.helpme-codesys.com/en/CODESYS%20SoftMotion/_sm_basic_cam_programmatic_creation.html",
    "motion_function": "https://infosys.beckhoff.com/content/1033/tf5050_tc3_nc_camming/1003721995.html",
    "position_table": "https://infosys.beckhoff.com/content/1033/tcplclibmc2_camming/460439563.html",
    "lenze": "Lenze Global Drive Cam Loader manual 1.1 EN 05/2005, section 4.2.1 (motion profile data)",
}


@dataclass
class EcamTable:
    """One electronic-cam table of a spec's motion.

    Attributes:
        format, table: what was written ("codesys", "xyva", …).
        text: the file's content.
        points: the table's points as the file holds them (values parsed back from the text).
        deviations: interpolation → its deviation from the exact motion (the table's own; a CSV gets
            both linear and quintic).
        interpolation: the controller's interpolation of this table (None for the CSV).
        lift_unit: "mm", "in" or "deg" (arm degrees).
        suffix: the file suffix this format wants.
    """

    format: str
    table: str
    text: str
    points: TablePoints
    deviations: dict[str, Deviation]
    interpolation: str | None
    lift_unit: str
    suffix: str
    step: float
    name: str
    notes: list[str] = field(default_factory=list)

    @property
    def deviation(self) -> Deviation:
        """The deviation of the table's own interpolation (the quintic for a CSV)."""
        return self.deviations[self.interpolation or "quintic"]

    def summary(self) -> dict[str, Any]:
        """Plain numbers: what was written and its deviations (what ``cam-workbench ecam`` prints)."""
        return {"format": self.format, "table": self.table, "points": self.points.count,
                "equidistant": self.points.equidistant, "step_deg": self.step, "name": self.name,
                "lift_unit": self.lift_unit, "interpolation": self.interpolation,
                "deviation": {k: d.to_dict() for k, d in self.deviations.items()}, "notes": list(self.notes)}

    def write(self, path: str | os.PathLike[str]) -> Path:
        """Write the file atomically."""
        return write_text_atomic(Path(path), self.text)


def resolve_options(spec: CamSpec, format: str | None = None, *, table: str | None = None,
                    step: float | None = None, boundaries: bool | None = None, name: str | None = None) -> CamSpec:
    """``spec`` with the given ``[ecam]`` fields replaced (validated: a bad value is a SpecError
    naming ``ecam.<field>``)."""
    changes = {f"ecam.{k}": v for k, v in (("format", format), ("table", table), ("step", step),
                                             ("boundaries", boundaries), ("name", name)) if v is not None}
    if format is not None and table is None:
        changes["ecam.table"] = "auto"
    return spec.replace(**changes) if changes else spec


def ecam_table(spec: CamSpec, format: str | None = None, *, table: str | None = None, step: float | None = None,
               boundaries: bool | None = None, name: str | None = None,
               program: MotionProgram | None = None) -> EcamTable:
    """The e-cam table of ``spec``'s motion in ``format`` (default: the spec's ``[ecam]``).

    Raises:
        SpecError: a bad option, naming ``ecam.<field>``.
    """
    spec = resolve_options(spec, format, table=table, step=step, boundaries=boundaries, name=name)
    ec = spec.ecam
    tab = ECAM_TABLES[ec.format][0] if ec.table == "auto" else ec.table
    program = program or MotionProgram.from_spec(spec)
    exact = table_points(program, ec.step, ec.boundaries)
    if ec.format == "codesys" and exact.count > CODESYS_MAX_ELEMENTS:
        raise SpecError("ecam.step", f"gives {exact.count} points; CODESYS counts a cam's elements in an INT: at "
                        f"most {CODESYS_MAX_ELEMENTS}")
    lift_unit = "deg" if body_of(spec).lift_unit(spec) == "angle" else spec.units
    writer = _WRITERS[(ec.format, tab)]
    text, written = writer(exact, ec.name, lift_unit)
    kinds = ("linear", "quintic") if ec.format == "csv" else (TABLE_KINDS[tab][0] if ec.format != "lenze" else "linear",)
    deviations = {k: interpolation_deviation(program, written, k) for k in kinds}
    interpolation = None if ec.format == "csv" else kinds[0]
    suffix = ".txt" if ec.format == "lenze" else TABLE_KINDS[tab][1]
    notes = []
    if tab == "poly5":
        notes.append(f"{exact.count - 1} Poly5 segments: the CamBuilder's library parameter MAX_CAM_SEGMENT_COUNT "
                     "must allow them")
    text = _fill_deviation(text, _deviation_text(deviations, lift_unit))
    return EcamTable(ec.format, tab, text, written, deviations, interpolation, lift_unit, suffix, ec.step, ec.name,
                     notes)


# ---- numbers as the files hold them -------------------------------------------------------
def iec_real(v: float) -> str:
    """An IEC 61131-3 real literal with every bit of the double (digits '.' digits [E exponent])."""
    v = float(v)
    if not math.isfinite(v):
        raise ValueError(f"cannot write {v!r} as a PLC real")
    text = repr(v)
    mant, _, exp = text.partition("e")
    if "." not in mant:
        mant += ".0"
    return mant + (f"E{int(exp)}" if exp else "")


def _parsed(values: np.ndarray, fmt) -> tuple[list[str], np.ndarray]:
    texts = [fmt(v) for v in values]
    return texts, np.array([float(t) for t in texts])


def _deviation_text(deviations: dict[str, Deviation], lift_unit: str) -> str:
    lines = []
    for kind, d in deviations.items():
        what = ("the 5th-degree polynomial through Y, Y', Y'' at both ends" if kind == "quintic"
                else "straight lines between the points")
        acc = ("" if d.max_acceleration_error is None else
               f"; Y'' {d.max_acceleration_error:.3g} {lift_unit}/deg^2 at {d.acceleration_at_deg:.4f} deg")
        lines.append(f"{kind} interpolation ({what}): largest deviation from the exact motion "
                     f"{d.max_error:.3g} {lift_unit} at {d.at_deg:.4f} deg; Y' {d.max_velocity_error:.3g} "
                     f"{lift_unit}/deg at {d.velocity_at_deg:.4f} deg{acc}")
    return "\n".join(lines)


def _fill_deviation(text: str, deviation: str) -> str:
    """Put the deviation lines where the writer left ``@DEVIATION@``: on the placeholder's line and
    below it with the same indentation, or on that one line (joined by "; ") when it carries data
    before the placeholder (Lenze's comment after the first point)."""
    at = text.find("@DEVIATION@")
    if at < 0:
        return text
    line_start = text.rfind("\n", 0, at) + 1
    lead = text[line_start:at]
    joined = deviation.replace("\n", "; ") if lead.strip() else deviation.replace("\n", "\n" + lead)
    return text[:at] + joined + text[at + len("@DEVIATION@"):]


def _header(points: TablePoints, lift_unit: str, what: str, source: str) -> list[str]:
    return [f"cam_workbench {__version__}: {what}",
            f"{points.count} points, master X = cam angle [deg] 0 ... 360 "
            f"({'equidistant' if points.equidistant else 'not equidistant: the motion segments boundaries are points'}), "
            f"slave Y = follower lift [{lift_unit}], Y' = dY/dX [{lift_unit}/deg], Y'' = d2Y/dX2 [{lift_unit}/deg^2]",
            "@DEVIATION@",
            f"Format: {source}"]


def _st_comment(lines: list[str]) -> str:
    body = "\n".join("   " + ln for ln in "\n".join(lines).splitlines())
    return "(*\n" + body.replace("*)", "* )") + "\n*)"


# ---- writers: (points, name, lift unit) → (text, points as written) ----------------------------
def _csv(p: TablePoints, name: str, lu: str) -> tuple[str, TablePoints]:
    cols = [("theta [deg]", p.master), (f"s [{lu}]", p.slave), (f"s' [{lu}/rad]", p.velocity / DEG),
            (f"s'' [{lu}/rad^2]", p.acceleration / DEG**2), (f"s''' [{lu}/rad^3]", p.jerk / DEG**3)]
    texts, vals = zip(*(_parsed(v, lambda z: repr(float(z))) for _h, v in cols))
    lines = [",".join(h for h, _v in cols)]
    lines += [",".join(row) for row in zip(*texts)]
    written = p.replaced(master=vals[0], slave=vals[1], velocity=vals[2] * DEG, acceleration=vals[3] * DEG**2,
                         jerk=vals[4] * DEG**3)
    return "\n".join(lines) + "\n", written


def _codesys_xyva(p: TablePoints, name: str, lu: str) -> tuple[str, TablePoints]:
    (x, xv), (y, yv), (v, vv), (a, av) = (_parsed(c, iec_real) for c in (p.master, p.slave, p.velocity, p.acceleration))
    rows = [f"        (dX := {x[i]}, dY := {y[i]}, dV := {v[i]}, dA := {a[i]})" for i in range(p.count)]
    comment = _st_comment(_header(p, lu, f'electronic cam "{name}": CODESYS SoftMotion XYVA cam table '
                                  "(MC_CAM_REF byType 3 = SMC_CAM_TYPE.XYVA), a global variable list",
                                  SOURCES["xyva"]) +
                          [f"Use: MC_CamTableSelect(CamTable := {name}, ...), then MC_CamIn."])
    text = (f"{{attribute 'linkalways'}}\nVAR_GLOBAL\n{_indent(comment)}\n"
            f"    {name}_A: ARRAY[0..{p.count - 1}] OF SMC_CAMXYVA := [\n" + ",\n".join(rows) + "];\n"
            f"    {name}: MC_CAM_REF := (nElements := {p.count}, byType := 3, xStart := {x[0]}, xEnd := {x[-1]}, "
            f"nTappets := 0, strCAMName := '{name}', pce := ADR({name}_A), xPartofLM := TRUE);\nEND_VAR\n")
    return text, p.replaced(master=xv, slave=yv, velocity=vv, acceleration=av)


def _codesys_poly5(p: TablePoints, name: str, lu: str) -> tuple[str, TablePoints]:
    (x, xv), (y, yv), (v, vv), (a, av) = (_parsed(c, iec_real) for c in (p.master, p.slave, p.velocity, p.acceleration))
    bound = [f"SMCB.Bound({x[i]}, {y[i]}, {v[i]}, {a[i]})" for i in range(p.count)]
    appends = [f"    camBuilder.Append(SMCB.Poly5({bound[0]}, {bound[1]}));"]
    appends += [f"    camBuilder.Append(SMCB.Poly5(SMCB.BoundImplicit(), {bound[i]}));" for i in range(2, p.count)]
    n = p.count - 1
    comment = _st_comment(_header(p, lu, f'electronic cam "{name}": CODESYS SoftMotion CamBuilder (SM3_CamBuilder, '
                                  f"SoftMotion >= 4.17), {n} Poly5 segments; SMCB.Bound(X, Y, V, A)", SOURCES["poly5"]) +
                          [f"Call this program once in the bus task; then MC_CamTableSelect(CamTable := {name}_Build.camRef, ...).",
                           f"The library parameter MAX_CAM_SEGMENT_COUNT must allow {n} segments."])
    text = (f"{comment}\nPROGRAM {name}_Build\nVAR\n    camBuilder : SMCB.CamBuilder;\n    camRef : MC_CAM_REF;\n"
            f"    aCamSegments : ARRAY[1..{n}] OF SMC_CAM_SEGMENT;\n    xBuilt : BOOL;\nEND_VAR\n"
            "(* ---- implementation ---- *)\nIF NOT xBuilt THEN\n    camBuilder.Init();\n" + "\n".join(appends) +
            "\n    SMCB.InitCamRef(camRef, ADR(aCamSegments), XSIZEOF(aCamSegments));\n    camBuilder.Write(camRef);\n"
            "    xBuilt := TRUE;\nEND_IF\n")
    return text, p.replaced(master=xv, slave=yv, velocity=vv, acceleration=av)


def _beckhoff_motion_function(p: TablePoints, name: str, lu: str) -> tuple[str, TablePoints]:
    cols = [_parsed(c, iec_real) for c in (p.master, p.slave, p.velocity, p.acceleration, p.jerk)]
    (x, xv), (y, yv), (v, vv), (a, av), (j, jv) = cols
    rows = [f"        (PointIndex := {i + 1}, FunctionType := MOTIONFUNCTYPE_POLYNOM5_MM, "
            f"PointType := MOTIONPOINTTYPE_MOTION, RelIndexNextPoint := 1, MasterPos := {x[i]}, SlavePos := {y[i]}, "
            f"SlaveVelo := {v[i]}, SlaveAcc := {a[i]}, SlaveJerk := {j[i]})" for i in range(p.count)]
    comment = _st_comment(_header(p, lu, f'electronic cam "{name}": Beckhoff TwinCAT 3 NC Camming (TF5050) motion '
                                  "function, MC_MotionFunctionPoint with MOTIONFUNCTYPE_POLYNOM5_MM (motion <-> motion)",
                                  SOURCES["motion_function"]) +
                          [f"Before MC_CamTableSelect: {name}.pArray := ADR({name}_Points); "
                           f"{name}.ArraySize := SIZEOF({name}_Points);"])
    text = (f"VAR_GLOBAL\n{_indent(comment)}\n    {name}_Points : ARRAY[1..{p.count}] OF MC_MotionFunctionPoint := [\n"
            + ",\n".join(rows) + "];\n"
            f"    {name} : MC_CAM_REF := (TableType := MC_TABLETYPE_MOTIONFUNCTION, NoOfRows := {p.count}, "
            "NoOfColumns := 1);\nEND_VAR\n")
    return text, p.replaced(master=xv, slave=yv, velocity=vv, acceleration=av, jerk=jv)


def _beckhoff_position_table(p: TablePoints, name: str, lu: str) -> tuple[str, TablePoints]:
    (x, xv), (y, yv) = (_parsed(c, iec_real) for c in (p.master, p.slave))
    kind = "MC_TABLETYPE_EQUIDISTANT" if p.equidistant else "MC_TABLETYPE_NONEQUIDISTANT"
    rows = [f"        {x[i]}, {y[i]}" for i in range(p.count)]
    comment = _st_comment(_header(p, lu, f'electronic cam "{name}": Beckhoff TwinCAT 3 NC Camming (TF5050) position '
                                  f"table ({kind}, rows of master and slave position), for "
                                  "MC_INTERPOLATIONTYPE_LINEAR", SOURCES["position_table"]) +
                          [f"Before MC_CamTableSelect: {name}.pArray := ADR({name}_Table); "
                           f"{name}.ArraySize := SIZEOF({name}_Table);"])
    text = (f"VAR_GLOBAL\n{_indent(comment)}\n    {name}_Table : ARRAY[0..{p.count - 1}, 0..1] OF LREAL := [\n"
            + ",\n".join(rows) + "];\n"
            f"    {name} : MC_CAM_REF := (TableType := {kind}, NoOfRows := {p.count}, NoOfColumns := 2);\nEND_VAR\n")
    return text, p.replaced(master=xv, slave=yv)


def _lenze(p: TablePoints, name: str, lu: str) -> tuple[str, TablePoints]:
    fmt = lambda v: f"{v:.9f}"  # noqa: E731
    (x, xv), (y, yv) = (_parsed(c, fmt) for c in (p.master, p.slave))
    lines = [f"{x[i]} {y[i]}" for i in range(p.count)]
    lines[0] += (f" // cam_workbench {__version__}: {name}, x = cam angle [deg], y = follower lift [{lu}], "
                 f"{p.count} points; @DEVIATION@")
    return "\n".join(lines) + "\n", p.replaced(master=xv, slave=yv)


def _indent(text: str) -> str:
    return "\n".join("    " + ln for ln in text.splitlines())


_WRITERS = {
    ("csv", "points"): _csv,
    ("codesys", "xyva"): _codesys_xyva,
    ("codesys", "poly5"): _codesys_poly5,
    ("beckhoff", "motion_function"): _beckhoff_motion_function,
    ("beckhoff", "position_table"): _beckhoff_position_table,
    ("lenze", "points"): _lenze,
}

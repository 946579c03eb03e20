"""DXF, G-code, command-table, e-cam-table and design-report exports from FreeCAD, made by the CLI.

FreeCAD's own Python cannot make all of these files as the CLI does (measured on Debian's
FreeCAD 0.20.2, Python 3.11, numpy 1.24, scipy 1.10 — docs/freecad.md):

- the design report checks the solid with OCP's kernel (never imported inside FreeCAD) and
  draws with the virtual environment's matplotlib;
- the DXF needs ezdxf, which FreeCAD does not bring (Debian's ``python3-ezdxf`` 0.18.1 does
  write the same entities, but the SPLINE poles differ from the CLI's by up to 2.5e-14 mm,
  because FreeCAD's numpy/scipy solve the PH spline with other round-off);
- the command table (full double precision) differs from the CLI's by up to 1.1e-13 mm (3e-14
  in ξ) for the same reason; only the G-code (4 decimals) came out byte-identical.

So each export runs the ``cam-workbench`` command line of the installation the workbench was
installed from, with the feature's spec as a TOML file: the files are the CLI's own, written
atomically by it (nothing is written when it fails), and its message is shown on failure
(exit 2: bad input or a cam that cannot be made or cut, naming the field or the cam angle).
Which CLI (:func:`find_cli`): ``$CAM_WORKBENCH_CLI``, the FreeCAD parameter
``BaseApp/Preferences/Mod/CamWorkbench/CliPath``, the Python recorded by ``cam-workbench
freecad install`` (its marker file), ``cam-workbench`` on PATH.

The output folder of the report follows the command line's rule (docs/cli.md, "Output folders
and your files"), the cam named by its document and object (``--source
freecad:<document>#<object>``): the same cam's earlier report there is replaced, another cam's
set or a folder of the user's files is refused and the message says so.
"""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cam_workbench
from cam_workbench.exporters.output_rule import REPLACE_HINT
from cam_workbench.generators.errors import CamError, SpecError
from cam_workbench.generators.spec import to_toml
from cam_workbench.generators.spec.params import unit_name

from . import properties as props

ENV_CLI = "CAM_WORKBENCH_CLI"
PARAM_PATH = "User parameter:BaseApp/Preferences/Mod/CamWorkbench"
MARKER = ".cam-workbench-install.json"   # written by install.install_into
TIMEOUT_S = 900.0


class ExportError(CamError):
    """An export could not be made; the message says why (the CLI's own message when it ran)."""


@dataclass(frozen=True)
class ExportKind:
    """One export: the CLI arguments, what it writes and how the file dialog offers it."""

    key: str
    title: str
    args: tuple[str, ...]          # after the spec path
    suffix: str                    # of the output file; "" = the output is a folder
    file_filter: str
    default_name: str              # suggested file (or folder) name, from the cam's label
    description: str


KINDS: dict[str, ExportKind] = {k.key: k for k in (
    ExportKind("dxf", "Export DXF", ("dxf",), ".dxf", "DXF drawing (*.dxf)", "{label}.dxf",
               "the manufacturing drawing: the profile as a cubic SPLINE within the Drawing tolerance, which "
               "every DXF reader draws (or the exact NURBS, arcs or a polyline: Drawing Curves), pitch curve, "
               "circles, bore, dimensions, title block"),
    ExportKind("gcode_xy", "Export G-code (XY contour)", ("gcode", "--mode", "xy"), ".nc",
               "G-code (*.nc *.ngc *.tap)", "{label}_xy.nc",
               "milling the outside contour: the exact tool-centre path as G02/G03 biarcs or G01 "
               "chords, tangent lead arcs, depth passes"),
    ExportKind("gcode_xc", "Export G-code (XC rotary)", ("gcode", "--mode", "xc"), ".nc",
               "G-code (*.nc *.ngc *.tap)", "{label}_xc.nc",
               "C axis + X: one G93 inverse-time block per command of the rotational interpolator"),
    ExportKind("gcode_wire_edm", "Export G-code (wire EDM)", ("gcode", "--mode", "wire_edm"), ".nc",
               "G-code (*.nc *.ngc *.tap)", "{label}_wire_edm.nc",
               "2-axis wire EDM of a plate cam: start hole, main cut leaving a holding tab, skims, the tab "
               "cut last"),
    ExportKind("csv", "Export command table (CSV)", ("gcode", "--mode", "csv"), ".csv",
               "Command table (*.csv)", "{label}_commands.csv",
               "the rotational interpolator's raw commands (paper Eq. 15), one row per sample period"),
    # electronic-cam tables (`cam-workbench ecam`, docs/ecam.md): one kind per format and table; the
    # step, boundaries and PLC name are the Ecam properties; --json: the CLI's deviation summary
    ExportKind("ecam_csv", "Export e-cam table (CSV)", ("ecam", "--format", "csv", "--table", "points", "--json"),
               ".csv", "E-cam table (*.csv)", "{label}_ecam.csv",
               "the electronic-cam table as CSV: θ [deg], s, s′, s″, s‴ (per radian) at every point"),
    ExportKind("ecam_codesys_xyva", "Export e-cam table (CODESYS XYVA)",
               ("ecam", "--format", "codesys", "--table", "xyva", "--json"), ".st", "Structured Text (*.st)",
               "{label}_codesys_xyva.st",
               "CODESYS SoftMotion: a global variable list with SMC_CAMXYVA points and their MC_CAM_REF "
               "(5th-degree polynomials between the points)"),
    ExportKind("ecam_codesys_poly5", "Export e-cam table (CODESYS Poly5)",
               ("ecam", "--format", "codesys", "--table", "poly5", "--json"), ".st", "Structured Text (*.st)",
               "{label}_codesys_poly5.st",
               "CODESYS SoftMotion: a PROGRAM building the cam with the CamBuilder's Poly5 segments"),
    ExportKind("ecam_beckhoff_motion_function", "Export e-cam table (Beckhoff motion function)",
               ("ecam", "--format", "beckhoff", "--table", "motion_function", "--json"), ".st",
               "Structured Text (*.st)", "{label}_beckhoff_mf.st",
               "Beckhoff TwinCAT NC Camming: MC_MotionFunctionPoint array, 5th-order polynomials, and its MC_CAM_REF"),
    ExportKind("ecam_beckhoff_position_table", "Export e-cam table (Beckhoff position table)",
               ("ecam", "--format", "beckhoff", "--table", "position_table", "--json"), ".st",
               "Structured Text (*.st)", "{label}_beckhoff_table.st",
               "Beckhoff TwinCAT: a master/slave position table (linear interpolation) and its MC_CAM_REF"),
    ExportKind("ecam_lenze", "Export e-cam table (Lenze)", ("ecam", "--format", "lenze", "--table", "points", "--json"),
               ".txt", "Lenze Cam Loader points (*.txt)", "{label}_lenze.txt",
               "Lenze Global Drive Cam Loader: one x y point per line (linear interpolation)"),
    ExportKind("report", "Design report (HTML)", ("report",), "", "", "{label}_report",
               "the design report: report.html (self-contained, its figures inline) and report.json, "
               "into a folder"),
    ExportKind("report_plots", "Design report (HTML and PNG figures)", ("report", "--plots"), "", "",
               "{label}_report", "the design report: report.html, report.json and each figure as a PNG file "
               "(needs CairoSVG in the command line's Python), into a folder"),
)}


@dataclass(frozen=True)
class Cli:
    """How to start the command line: an argv prefix, where it was found, and what its
    environment needs (``PYTHONPATH`` naming the installation the workbench was installed from)."""

    argv: tuple[str, ...]
    source: str
    env: tuple[tuple[str, str], ...] = ()


@dataclass(frozen=True)
class ExportResult:
    path: Path                     # the file, or the folder for the report
    files: tuple[str, ...]         # what was written (names)
    message: str                   # the CLI's own summary
    argv: tuple[str, ...]
    #: (item, value) rows of what the CLI reported (an e-cam table: points and measured deviations)
    details: tuple[tuple[str, str], ...] = ()


def _python_cli(python: str) -> tuple[str, ...]:
    return (python, "-m", "cam_workbench.cli")


def _as_cli(value: str, source: str) -> Cli:
    """A configured path: a ``cam-workbench`` executable, or a Python that has the package."""
    path = Path(value).expanduser()
    if not path.exists():
        raise ExportError(f"{source} names {value}, which does not exist")
    if re.match(r"python[\d.]*(\.exe)?$", path.name):
        return Cli(_python_cli(str(path)), source)
    return Cli((str(path),), source)


def _marker_files() -> list[Path]:
    seen, out = set(), []
    candidates = [Path(cam_workbench.__file__).parent.parent] + [Path(p) for p in sys.path if p]
    for folder in candidates:
        m = folder / MARKER
        if m not in seen and m.is_file():
            seen.add(m)
            out.append(m)
    return out


def find_cli() -> Cli:
    """The ``cam-workbench`` command line to run.

    Raises:
        ExportError: none found (the message says how to provide one).
    """
    env = os.environ.get(ENV_CLI)
    if env:
        return _as_cli(env, f"${ENV_CLI}")
    try:
        import FreeCAD  # deferred: FreeCAD (this module runs in any Python; outside FreeCAD no parameter)

        configured = FreeCAD.ParamGet(PARAM_PATH).GetString("CliPath", "")
    except ImportError:
        configured = ""
    if configured:
        return _as_cli(configured, "the FreeCAD parameter CamWorkbench/CliPath")
    for marker in _marker_files():
        try:
            recorded = json.loads(marker.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        python, source = recorded.get("installed_with", ""), recorded.get("source", "")
        if python and Path(python).exists():
            # the packages the workbench links to come first: the command line is then the same
            # code as the workbench even where that Python would import another copy (a second
            # checkout beside an editable install)
            env = ((("PYTHONPATH", source),) if source and (Path(source) / "cam_workbench" / "cli.py").is_file()
                   else ())
            return Cli(_python_cli(python), f"the installation recorded in {marker}", env)
    exe = shutil.which("cam-workbench")
    if exe:
        return Cli((exe,), "cam-workbench on PATH")
    raise ExportError(
        "this export needs the cam-workbench command line (with CadQuery and ezdxf), and none was "
        "found: install the package (`make demo`, or pip install into a virtual environment) and run "
        f"`cam-workbench freecad install` from it, or set ${ENV_CLI} to its cam-workbench executable")


def _cli_env() -> dict[str, str]:
    """FreeCAD's environment without what would make another Python pick FreeCAD's modules."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONHOME", "PYTHONPATH", "PYTHONSTARTUP", "PYTHONEXECUTABLE")}
    if "APPDIR" in env or "APPIMAGE" in env:  # FreeCAD's AppImage: its libraries are not ours
        env.pop("LD_LIBRARY_PATH", None)
    env["PYTHONIOENCODING"] = "utf-8"
    env["COLUMNS"] = "200"  # rich wraps the CLI's messages at the terminal width
    return env


_CLI_ERROR = re.compile(r"^error: ([A-Za-z_][\w.\[\]]*): (.*)$", re.S)


def cli_message(text: str) -> str:
    """The CLI's error line with the spec field shown as the property that holds it:
    ``error: machining.sample_period: …`` → ``MachiningSamplePeriod (machining.sample_period): …``;
    a refused output (``error: -o: …``) as "Output: …", without the command line's ``--replace``
    (the dialog has none: another folder is the way out)."""
    text = text.strip()
    if text.startswith("error: -o: "):
        return "Output: " + text[len("error: -o: "):].replace(REPLACE_HINT.format(option="--replace"), "")
    m = _CLI_ERROR.match(text)
    if m:
        shown = props.describe_field(m.group(1))
        return f"{shown}: {m.group(2).strip()}"
    return text[7:] if text.startswith("error: ") else text


def command_line(kind: str, spec_path: str | os.PathLike[str], target: str | os.PathLike[str],
                 cli: Cli | None = None, source: str | None = None) -> list[str]:
    """The argv that makes ``kind`` from a spec file into ``target``; ``source`` names the cam
    in an output folder's manifest (folder kinds only: :func:`cam_source`)."""
    k = KINDS[kind]
    cli = cli or find_cli()
    named = ["--source", source] if source is not None and not k.suffix else []
    return [*cli.argv, k.args[0], str(spec_path), *k.args[1:], *named, "-o", str(target)]


def cam_source(obj: Any) -> str:
    """The cam's source in an output folder's manifest: ``freecad:<document>#<object>`` (the
    document's file, or its name while unsaved), so that exporting the same feature again after
    an edit replaces its earlier report."""
    return f"freecad:{obj.Document.FileName or obj.Document.Name}#{obj.Name}"


def target_path(kind: str, target: str | os.PathLike[str]) -> Path:
    """The output path as the CLI will use it: absolute — a relative ``target`` is resolved
    against this (FreeCAD's) process's working folder, since the CLI runs in another one — and
    a file gets the kind's suffix if it has none that the CLI accepts."""
    k = KINDS[kind]
    p = Path(os.path.abspath(Path(target).expanduser()))
    if k.suffix == ".dxf" and p.suffix.lower() != ".dxf":
        p = p.with_name(p.name + ".dxf")  # the CLI takes -o without .dxf as a folder
    elif k.suffix and not p.suffix:
        p = p.with_name(p.name + k.suffix)
    return p


def export(obj: Any, kind: str, target: str | os.PathLike[str], cli: Cli | None = None,
           timeout: float = TIMEOUT_S) -> ExportResult:
    """Make the ``kind`` export (a key of :data:`KINDS`) of the feature ``obj`` into
    ``target`` (a file; a folder for the report) with the CLI; used by the GUI and headless.

    Raises:
        ExportError: a property breaks a rule, no CLI, or the CLI refused (its message); no file
            is written or changed then.
    """
    if kind not in KINDS:
        raise ExportError(f"unknown export {kind!r}; one of {', '.join(KINDS)}")
    try:
        spec = props.spec_of(obj)
    except SpecError as exc:
        raise ExportError(f"{props.describe_field(exc.field)}: {exc.rule}") from None

    cli = cli or find_cli()
    out = target_path(kind, target)
    with tempfile.TemporaryDirectory(prefix="camwb_export_") as tmp:
        spec_file = Path(tmp) / "spec.toml"
        spec_file.write_text(to_toml(spec), encoding="utf-8")
        argv = command_line(kind, spec_file, out, cli, cam_source(obj))
        try:
            res = subprocess.run(argv, capture_output=True, text=True, timeout=timeout, cwd=tmp,
                                 env={**_cli_env(), **dict(cli.env)}, stdin=subprocess.DEVNULL,
                                 encoding="utf-8", errors="replace")
        except FileNotFoundError:
            raise ExportError(f"cannot start the command line {argv[0]} (from {cli.source})") from None
        except subprocess.TimeoutExpired:
            raise ExportError(f"the command line did not finish within {timeout:g} s") from None
    said = (res.stdout + "\n" + res.stderr).strip()
    if res.returncode == 2:
        raise ExportError(cli_message(res.stderr or res.stdout))
    if res.returncode != 0:
        tail = " | ".join(said.splitlines()[-4:])
        raise ExportError(f"the command line failed (exit {res.returncode}, {cli.source}): {tail}")
    if is_report(kind):
        try:
            listed = json.loads((out / "report.json").read_text(encoding="utf-8"))["files"]
        except (OSError, ValueError, KeyError):
            raise ExportError(f"the command line reported success but {out}/report.json is "
                              "missing or unreadable") from None
        files = (listed["html"], listed["report"], *listed.get("plots", []))
    else:
        if not out.is_file():
            raise ExportError(f"the command line reported success but {out} is missing")
        files = (out.name,)
    details: tuple[tuple[str, str], ...] = ()
    if is_ecam(kind):
        try:
            details = tuple(ecam_rows(json.loads(res.stdout)))
        except (ValueError, KeyError, TypeError):
            raise ExportError(f"the command line wrote {out} but its summary is unreadable: "
                              f"{' | '.join(said.splitlines()[-4:])}") from None
    return ExportResult(out, files, said, tuple(argv), details)


def is_report(kind: str) -> bool:
    """A design-report kind (``cam-workbench report``): a folder, its files listed in report.json."""
    return KINDS[kind].args[0] == "report"


def is_ecam(kind: str) -> bool:
    """An electronic-cam table kind (``cam-workbench ecam``)."""
    return KINDS[kind].args[0] == "ecam"


def ecam_rows(summary: dict[str, Any]) -> list[tuple[str, str]]:
    """(item, value) rows of ``cam-workbench ecam --json``'s summary (``EcamTable.summary()``):
    the table written and the measured deviation of each interpolation from the exact motion,
    with its cam angle — the CLI's own numbers, shown to the digits it prints them."""
    lu = summary["lift_unit"]
    rows = [("table", f"{summary['format']} {summary['table']}"),
            ("points", f"{summary['points']}, step {summary['step_deg']:g}°, "
                       f"{'equidistant' if summary['equidistant'] else 'not equidistant'}")]
    for interp, d in summary["deviation"].items():
        own = " (the controller's)" if interp == summary["interpolation"] else ""
        rows.append((f"{interp} interpolation{own}: max deviation",
                     f"{d['max_error']:.3g} {lu} at {d['at_deg']:.4f}°"))
        rows.append((f"{interp} interpolation: max slope error Y′",
                     f"{d['max_velocity_error']:.3g} {lu}/deg at {d['velocity_at_deg']:.4f}°"))
        if d.get("max_acceleration_error") is not None:
            rows.append((f"{interp} interpolation: max Y″ error",
                         f"{d['max_acceleration_error']:.3g} {lu}/deg² at {d['acceleration_at_deg']:.4f}°"))
    rows += [("note", n) for n in summary.get("notes", [])]
    return rows


def summary_rows(obj: Any, kind: str) -> list[tuple[str, str]]:
    """(property, value) pairs the export dialog shows: the values the command line gets, in
    the spec's units ("default" where the property leaves the field to the spec's default)."""
    sections = {"dxf": ("drawing",), "gcode_xy": ("machining",), "gcode_xc": ("machining",),
                "gcode_wire_edm": ("machining",), "csv": ("machining",), "report": ("checks", "material"),
                "report_plots": ("checks", "material")}.get(kind, ("ecam",))
    only = {"csv": ("rotary_speed_rpm", "sample_period")}.get(kind)
    if is_ecam(kind):   # the format and table are the kind's own
        only = ("step", "boundaries", "name")
    data = props.spec_dict(obj)
    units = props.units_of(obj)
    rows = [("Units", units)]
    if is_ecam(kind):
        a = KINDS[kind].args
        rows.append(("Table (this export)", f"{a[a.index('--format') + 1]} {a[a.index('--table') + 1]}"))
    for fp in props.field_properties():
        if fp.section not in sections or (only and fp.field not in only):
            continue
        if fp.section == "machining" and fp.field == "program":   # the kind's own (--mode)
            continue
        value = data.get(fp.section, {}).get(fp.field)
        if value is None:
            text = "default"
        elif isinstance(value, float):
            text = f"{value:.10g} {unit_name(fp.param.unit, units)}".strip()
        else:
            text = str(value)
        rows.append((fp.name, text))
    return rows


def suggested(obj: Any, kind: str) -> Path:
    """Where the dialog proposes to write: beside the document (else the working folder)."""
    folder = os.path.dirname(obj.Document.FileName or "") or os.getcwd()
    label = re.sub(r"[^\w.-]+", "_", obj.Label) or "Cam"
    return Path(folder) / KINDS[kind].default_name.format(label=label)


__all__ = ["Cli", "ExportError", "ExportKind", "ExportResult", "KINDS", "cam_source", "cli_message", "command_line",
           "ecam_rows", "export", "find_cli", "is_ecam", "suggested", "summary_rows", "target_path"]


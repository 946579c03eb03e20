"""Every command's arguments, declared without loading any command (argparse and the standard
library only): ``cam-workbench COMMAND --help`` and an argument error (a bad option, a missing
value, a choice not offered) are answered before numpy, scipy or the generators load (issue 22
item 3).  :func:`parser` is the command line's one parser; each command's parser sets
``command_id`` (its name in :data:`cam_workbench.commands.CATALOGUE`), by which
:mod:`.dispatch` loads the command's module to run it.

A few choices and texts are the spec's own, which live in :mod:`cam_workbench.generators`
(loading it loads numpy and scipy): the built-in examples (:data:`EXAMPLES`), the e-cam formats
and tables, the optimiser's objectives and algorithms, the drawing's curve kinds and DXF versions.
They are written here once more, and ``tests/test_cli.py`` holds each to the spec's declaration.
"""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any, Callable

from . import add_command, root_parser

#: the built-in examples in one line each, in their order
#: (:data:`cam_workbench.generators.spec.examples.DESCRIPTIONS`)
EXAMPLES: tuple[tuple[str, str], ...] = (
    ("default", "the paper's motion program (cycloidal 20 mm rise and return over 120°) on R_b = 40 mm with a "
                "radial 8 mm roller; passes every design check"),
    ("paper", "Jahanpour & Dolatabadi (2014), Table 1 case 2: e = 10 mm, R_b = √(20² + 10²), M = 60, a 5 mm roller; "
              "fails the 30° pressure-angle limit (46.2°)"),
    ("oscillating", "the default's motion as a 15° arm rotation: an 8 mm roller on a 45 mm arm pivoted 60 mm from "
                    "the cam axis"),
    ("flat", "the default's motion with a translating flat-faced follower, face 40 mm wide"),
    ("packaging", "a 22 mm constant-velocity working stroke entered and left through polynomial rises, on "
                  "R_b = 60 mm; every junction C²"),
    ("groove", "the default's motion in a groove (face) cam: a 150 mm disc 12 mm thick, keyway, hub, four holes "
               "and a timing mark"),
    ("conjugate", "the default's motion on a conjugate pair: a yoke's 8 mm roller on the first cam, a 6 mm roller "
                  "106 mm away on the second"),
    ("cylindrical", "a cylindrical (barrel) cam: a groove around a 40 mm pitch-radius cylinder 60 mm long, a 5 mm "
                    "roller along the cam axis"),
    ("cylindrical_oscillating", "a cylindrical cam driving an oscillating 5 mm roller on a 50 mm arm pivoted 50 mm "
                                "away (30° arm rise over 150°)"),
    ("parallel_indexer", "an 8-station parallel indexer: two plates 16 mm thick, modified sine over a 120° index, "
                         "C = 120 mm, R_p = 50 mm, 10 mm rollers, sized for a 0.15 kg·m² output at 100 rpm"),
    ("barrel_indexer", "a 6-station barrel indexer: a rib on an 80 mm cylinder, 12 mm rollers on the turret's face "
                       "60 mm out, modified sine over a 240° index, sized for a 0.2 kg·m² output at 60 rpm"),
    ("globoidal_indexer", "a 12-station globoidal indexer: a rib on a 56 mm globoid, C = 150 mm, 12 mm radial "
                          "rollers 74–96 mm out, modified sine over a 120° index, sized for a 0.5 kg·m² output at "
                          "60 rpm"),
)
#: the e-cam formats, each with its tables (the first its default):
#: :data:`cam_workbench.generators.spec.ECAM_TABLES`
ECAM_FORMATS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("csv", ("points",)), ("codesys", ("xyva", "poly5")), ("beckhoff", ("motion_function", "position_table")),
    ("lenze", ("points",)))
#: the optimiser's objectives and algorithms (:data:`cam_workbench.generators.spec.OBJECTIVES`,
#: :data:`~cam_workbench.generators.spec.OPTIMISE_ALGORITHMS`)
OBJECTIVES = ("area", "profile_area", "machining_time", "gcode_time", "peak_acceleration", "peak_pressure_angle",
              "outer_diameter")
OPTIMISE_ALGORITHMS = ("auto", "slsqp", "mma", "ccsaq", "cobyla", "bobyqa", "isres")
#: the drawing's fields that ``dxf`` overrides: option → (the field of the spec's [drawing], its
#: choices or None, its description) — :class:`cam_workbench.generators.spec.DrawingSection`
DRAWING_FIELDS: dict[str, tuple[str, tuple[str, ...] | None, str]] = {
    "--curves": ("curves", ("cubic", "spline", "arcs", "polyline"),
                 "How the profile, pitch curve and the body's other curves are written: \"cubic\" a polynomial "
                 "(non-rational) cubic SPLINE within chord_tolerance, which every DXF reader draws; \"spline\" the "
                 "profile NURBS itself (for a PH pitch curve the exact rational offset, degree 9, which LibreCAD and "
                 "many CAM and laser programs drop without a word); \"arcs\" tangent arcs (biarcs, ARC/LINE "
                 "entities) or \"polyline\" one closed polyline within chord_tolerance, for machines that read no "
                 "splines"),
    "--tolerance": ("chord_tolerance", None,
                    "Largest distance of the drawn curves from the NURBS they stand for (curves = cubic, arcs or "
                    "polyline; measured and stated in the title block)"),
    "--dxf-version": ("dxf_version", ("R12", "R2000", "R2004", "R2007", "R2010", "R2013", "R2018"),
                      "DXF version of cam.dxf; R12 (for old CAM software) needs curves = arcs or polyline"),
}

#: ``gcode --mode``: the programs it writes
GCODE_MODES = ("xy", "xc", "wire_edm", "csv")
#: the files ``dynamics -o`` writes beside report.json
DYNAMICS_CSV = "dynamics.csv"
DYNAMICS_PLOTS = ("plot_dynamics.png", "plot_jump_speed.png")
#: ``inspect --datum``: :data:`cam_workbench.generators.inspection.DATUMS`
INSPECTION_DATUMS = ("none", "bore", "bore_and_angle")
#: the optimised spec ``optimise`` writes
OPTIMISED_SPEC = "optimised.toml"
#: the files ``tolerance -o`` writes (the PNG when CairoSVG imports)
TOLERANCE_FILES = ("tolerance.json", "tolerance.svg", "tolerance.png")


def add_spec_arguments(p: argparse.ArgumentParser) -> None:
    """SPEC positional (optional: the built-in default) and repeatable ``--set FIELD=VALUE``."""
    p.add_argument("spec", nargs="?", metavar="SPEC",
                   help="cam spec (TOML); omitted: the built-in example named by --example")
    p.add_argument("--example", metavar="NAME", default=None,
                   help="a built-in cam instead of SPEC (default: 'default'): "
                        + "; ".join(f"'{n}' ({d})" for n, d in EXAMPLES))
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="FIELD=VALUE",
                   help="override a spec field, e.g. --set cam.base_radius=30 or "
                        "--set motion[1].law=poly345 (repeatable; `cam-workbench spec` lists fields)")


def add_output_arguments(p: argparse.ArgumentParser, default: str | None, what: str = "output folder",
                         source: bool = True) -> None:
    """``-o OUT`` (a folder: ``default``, or None: no folder, nothing written), ``--replace`` and,
    with ``source``, ``--source NAME`` (the rule: docs/cli.md, "Output folders and your files")."""
    where = f"default: {default}" if default else "omitted: nothing is written"
    p.add_argument("-o", "--output", default=default, metavar="OUT",
                   help=f"{what} (created if needed; {where}); it may hold the set of the same spec, or "
                        "of the same cam when this run writes every file of it; another cam's set only with "
                        "--replace; never files of yours (docs/cli.md)")
    p.add_argument("--replace", action="store_true",
                   help="replace the cam-workbench set the folder holds, whatever cam it is of (a folder "
                        "holding files of yours is still refused)")
    if source:
        p.add_argument("--source", metavar="NAME", default=None,
                       help="the cam's name recorded in the folder's manifest (default: SPEC's resolved path, "
                            "or example:NAME); a later run for the same name may replace the set")


def add_plots_argument(p: argparse.ArgumentParser) -> None:
    """``--plots``: the report's figures also as PNG files (they are always in report.html)."""
    p.add_argument("--plots", action="store_true",
                   help="also write each of the report's figures as a PNG file (plot_*.png, the SVG of "
                        "report.html rasterised; needs CairoSVG: pip install 'cam-workbench[png]')")


def add_parallel_arguments(p: argparse.ArgumentParser, what: str) -> None:
    """``--workers N`` and ``--scheduler ADDRESS``: where ``what`` runs (Dask, docs/studies.md)."""
    p.add_argument("--workers", type=int, metavar="N", default=None,
                   help=f"run {what} on a local Dask cluster of N worker processes (default: one per CPU, "
                        "no more than there are tasks; in this process when that is one or Dask is not "
                        "installed); 0: in this process, without Dask")
    p.add_argument("--scheduler", metavar="ADDRESS", default=None,
                   help=f"run {what} on an existing Dask cluster, e.g. tcp://10.0.0.5:8786 (its workers "
                        "must have the same cam-workbench installed)")


def _drawing_argument(p: argparse.ArgumentParser, option: str, **kwargs: Any) -> None:
    field, choices, doc = DRAWING_FIELDS[option]
    sep = ", in the spec's units (default" if choices is None else " (default"
    p.add_argument(option, choices=choices, default=None,
                   help=f"{doc}{sep}: the spec's drawing.{field})", **kwargs)


def _build(sub: Any) -> None:
    p = add_command(sub, "build",
        description="Design the cam (PH pitch curve, exact profile, design checks) and write "
                    "cam.step (the solid, in the spec's units), cam.dxf (the drawing, see [drawing]), "
                    "cam.nc (machining.program: xy — roughing first with machining.blank_diameter — xc or "
                    "wire_edm), commands.csv (the interpolator's commands), "
                    "report.json and report.html (its figures inline; as PNG files too with --plots) into the output folder. "
                    "Nothing is written if the spec is bad or the cam cannot be made.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    add_output_arguments(p, "out")
    add_plots_argument(p)
    p.set_defaults(command_id="build")


def _check(sub: Any) -> None:
    p = add_command(sub, "check",
        description="Evaluate the design checks of the spec's cam — pressure angle, separation "
                    "(driving force), oscillation, Hertz contact stress, radius of curvature with the "
                    "undercut safety factor, and the true roller-envelope undercut (thesis Ch. 3) — "
                    "print them as a table; with -o, write them as the `checks` section of report.json in "
                    "that folder (merged into a report.json that `build` wrote for the same spec). "
                    "Writes nothing without -o. "
                    "Limits and sampling come from the spec's [checks], [material] and [follower].",
        epilog="exit status: 0 every check passes, 3 a check failed, 2 bad input (nothing written).",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    add_output_arguments(p, None, "output folder for report.json")
    p.add_argument("--sampling", choices=("dense", "thesis71"),
                   help="override checks.sampling: dense sampling, or the thesis' 71 nodes per rise/return")
    p.set_defaults(command_id="check")


def _gcode(sub: Any) -> None:
    p = add_command(sub, "gcode",
        description="Design the cam and write one machining program for it ([machining] section of the "
                    "spec: tool, feeds, passes, sample period; `cam-workbench spec` lists the fields):\n"
                    "  xy   contour milling: the exact tool-centre path as G02/G03 biarcs or G01 chords\n"
                    "       within machining.chord_tolerance, tangent lead arcs, depth passes; with\n"
                    "       machining.blank_diameter roughing passes from the round blank first\n"
                    "  xc   rotary: C axis + X, one G93 inverse-time block per interpolator command\n"
                    "       (each block takes machining.sample_period)\n"
                    "  wire_edm  2-axis wire EDM of a plate cam: start hole, main cut leaving a holding\n"
                    "       tab, skims, the tab cut last (machining.wire_diameter, spark_gap, skim_passes, …)\n"
                    "  csv  the rotational interpolator's raw commands (paper Eq. 15) as CSV\n"
                    "Nothing is written if the spec is bad or the cam cannot be made or cut.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    p.add_argument("--mode", choices=GCODE_MODES, default="xy", help="program to write (default: xy)")
    p.add_argument("--dialect", metavar="NAME", default=None,
                   help="G-code dialect (linuxcnc, fanuc, sinumerik: the choices of machining.dialect, which it "
                        "overrides; docs/machining.md lists the differences)")
    p.add_argument("--compensation", metavar="WHERE", default=None,
                   help="XY program on the tool centre (centre) or on the part under the control's cutter "
                        "compensation G41/G42 (controller): overrides machining.compensation")
    p.add_argument("--cam", choices=("first", "second"), default="first",
                   help="a conjugate pair (cam.body = \"conjugate\"): the program of the first cam (default) or "
                        "of the second (build writes both: cam.nc and cam2.nc); the command table is the "
                        "follower's, one for both. A parallel indexer: its first or second plate's program "
                        "(build writes every plate's: cam0.nc, cam1.nc, cam2.nc)")
    p.add_argument("-o", "--output", metavar="OUT",
                   help="output file (written atomically, replacing a file of that name); omitted: standard output")
    p.set_defaults(command_id="gcode")


def _dxf(sub: Any) -> None:
    p = add_command(sub, "dxf",
        description="Design the cam and write its manufacturing drawing as DXF: the profile (layer PROFILE) "
                    "as a polynomial cubic SPLINE within drawing.chord_tolerance of the profile NURBS, which "
                    "every DXF reader draws (the default, --curves cubic); as that NURBS itself (--curves "
                    "spline: the exact rational offset, degree 9, for a PH pitch curve, which LibreCAD and "
                    "many CAM programs drop; for pitch.representation = \"bspline\" a fitted B-spline, its "
                    "measured error printed); or as arcs or a polyline within the tolerance for machines "
                    "that read no splines. The measured distance is printed and stated in the title block. "
                    "Also the pitch curve, base and prime circles, bore, centre lines, dimensions and a "
                    "title block with the motion table. The spec's [drawing] section sets the defaults.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    _drawing_argument(p, "--curves")
    _drawing_argument(p, "--tolerance", type=float, metavar="TOL")
    _drawing_argument(p, "--dxf-version")
    add_output_arguments(p, "out", "a .dxf file name (written, replacing a file of that name), or a folder "
                                   "to write cam.dxf into")
    p.set_defaults(command_id="dxf")


def _report(sub: Any) -> None:
    p = add_command(sub, "report",
        description="Design the cam and write its report: report.html (one self-contained file: the spec, "
                    "the cam with its follower, s/v/a/j, pressure angle, radius of curvature, interpolation "
                    "error, accuracy figures) and report.json, whose numbers the HTML tables show; with --plots "
                    "the figures as PNG files too. Nothing is written if the spec is bad or the cam cannot be made.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    add_output_arguments(p, "out")
    add_plots_argument(p)
    p.set_defaults(command_id="report")


def _dynamics(sub: Any) -> None:
    p = add_command(sub, "dynamics",
        description="Model the follower train as a spring–mass–damper (effective mass, train stiffness, damping "
                    "ratio, return spring and preload: the spec's [dynamics] and [follower]) driven by the cam at "
                    "its speed, solve its steady state (a periodic solve on the cam; revolution after revolution "
                    "when the follower leaves it) and print the dynamic contact force, where the follower leaves the "
                    "cam, the displacement error, the residual vibration after each rise and return, the camshaft "
                    "torque (rigid and dynamic) and the jump speed (a sweep of cam speeds with a progress bar, then "
                    "a bisection). With -o, writes report.json's dynamics section (merged into a report.json of the "
                    f"same cam), {DYNAMICS_CSV} and the figures {', '.join(DYNAMICS_PLOTS)} into that folder; "
                    "writes nothing without -o. docs/dynamics.md",
        epilog="exit status: 0 the follower stays on the cam, 3 it leaves the cam at the analysis speed (the files "
               "are written), 2 bad input (nothing written).",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    p.add_argument("--speed", type=float, metavar="RPM", help="cam speed of the analysis (dynamics.speed_rpm)")
    p.add_argument("--no-sweep", action="store_true", help="skip the jump-speed sweep (dynamics.sweep_points = 0)")
    add_output_arguments(p, None)
    p.set_defaults(command_id="dynamics")


def _ecam(sub: Any) -> None:
    p = add_command(sub, "ecam",
        description="Sample the motion program as the cam table a servo motion controller reads and write it:\n"
                    "  csv       θ [deg], s, s', s'', s''' (per radian) at every point\n"
                    "  codesys   --table xyva: a GVL with SMC_CAMXYVA points and their MC_CAM_REF;\n"
                    "            --table poly5: a PROGRAM building the cam with the CamBuilder's Poly5 segments\n"
                    "  beckhoff  --table motion_function: MC_MotionFunctionPoint, 5th-order polynomials;\n"
                    "            --table position_table: master/slave rows for linear interpolation\n"
                    "  lenze     the Global Drive Cam Loader's x y point file\n"
                    "Master = cam angle [deg] 0 ... 360, slave = follower lift (mm, in, or arm degrees). The "
                    "deviation of the table's own interpolation from the exact motion is measured on the numbers "
                    "as written, printed and stated in the file. Defaults come from the spec's [ecam]. "
                    "Nothing is written on bad input. docs/ecam.md",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    p.add_argument("--format", choices=tuple(f for f, _tables in ECAM_FORMATS), help="table format (ecam.format)")
    p.add_argument("--table", choices=("auto", *sorted({t for _f, tables in ECAM_FORMATS for t in tables})),
                   help="which table of the format (ecam.table)")
    p.add_argument("--step", type=float, metavar="DEG", help="master step between points in cam degrees (ecam.step)")
    p.add_argument("--no-boundaries", action="store_true",
                   help="no extra points at the motion segments' boundaries (ecam.boundaries = false)")
    p.add_argument("--name", metavar="NAME", help="the cam's name in the PLC code (ecam.name)")
    p.add_argument("--json", action="store_true", help="print the deviation summary as JSON")
    p.add_argument("-o", "--output", metavar="FILE",
                   help="output file (written atomically, replacing a file of that name); omitted: standard output, "
                        "the summary on standard error")
    p.set_defaults(command_id="ecam")


def _optimise(sub: Any) -> None:
    p = add_command(sub, "optimise",
        description="Minimise the spec's [optimise] objective over its design variables (base radius, "
                    "the follower's position: offset, or pivot distance and arm length of an oscillating "
                    "follower; the free B-spline control points, polynomial point lifts, the blank orientation; a groove "
                    "cam's disc and groove; a cylindrical cam's cylinder, by COBYLA on its own checks) subject to "
                    "every design check of the follower kind, evaluated densely (thesis Ch. 5-7, with nlopt). Writes the optimised "
                    f"spec ({OPTIMISED_SPEC}), report.json (with an `optimise` section: objective, history, "
                    "evaluations, time, the final dense checks), report.html with the convergence figure (its "
                    "figures as PNG files too with --plots) and the optimised cam's own cam.step, cam.dxf, cam.nc and commands.csv (as `build` "
                    "writes them) into the output folder. Settings: the [optimise] section (`cam-workbench spec`).",
        epilog="exit status: 0 optimised and every check passes, 3 the result fails a dense check (files are "
               "still written, report.json says which), 2 bad input (nothing written).",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    p.add_argument("--objective", choices=OBJECTIVES, help="override optimise.objective")
    p.add_argument("--variables", metavar="LIST",
                   help="override optimise.variables, e.g. 'base_radius,offset', "
                        "'base_radius,pivot_distance,arm_length', 'control_points' or 'motion[1].points'")
    p.add_argument("--algorithm", choices=OPTIMISE_ALGORITHMS, help="override optimise.algorithm")
    p.add_argument("--max-evaluations", type=int, metavar="N", help="override optimise.max_evaluations")
    p.add_argument("--multistart", type=int, metavar="N", help="override optimise.multistart (extra random starts)")
    p.add_argument("--seed", type=int, metavar="N", help="override optimise.seed")
    add_parallel_arguments(p, "the multistart's starts")
    add_output_arguments(p, "out")
    add_plots_argument(p)
    p.set_defaults(command_id="optimise")


def _batch(sub: Any) -> None:
    p = add_command(sub, "batch",
        description="Build every spec (TOML files, and the *.toml files of folders, sorted by name) with the "
                    "same pipeline as `build`: OUT/<name>/ gets cam.step, cam.dxf, cam.nc, commands.csv, "
                    "report.json, report.html and the plots (<name>: the file's name without .toml; -2, -3 "
                    "for repeats). OUT/summary.csv and OUT/summary.parquet hold one row per spec: its status "
                    "(ok, bad input, cannot be made, error, cancelled) and message, and its key numbers and "
                    "checks (base radius, pressure angle, radii of curvature, area, volume, every check's "
                    "value, limit and status); OUT/study.json says how it ran. A bad spec is a row saying "
                    "why and does not stop the others. The cams are built in parallel on Dask (--workers, "
                    "--scheduler), each folder written as its cam is done.",
        epilog="exit status: 0 every cam built and passing every design check; 3 every cam built, some "
               "failing a design check (the table says which); 4 some specs could not be built (bad input, "
               "cannot be made, internal error: their rows say why; the others are written); 2 bad command "
               "line or OUT refused (files of yours, another study's or cam's set: nothing written); 130 "
               "interrupted (Ctrl-C: the cams done "
               "stay, the summary marks the rest cancelled).",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("specs", nargs="+", metavar="SPEC", help="spec files (TOML) and folders of them")
    add_output_arguments(p, "batch", source=False)
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="FIELD=VALUE",
                   help="override a field of every spec, e.g. --set cam.thickness=12 (repeatable)")
    add_parallel_arguments(p, "the builds")
    p.set_defaults(command_id="batch")


def _sweep(sub: Any) -> None:
    p = add_command(sub, "sweep",
        description="Vary spec fields over a grid and evaluate every point: design and check the cam (no "
                    "solid; --build: every file as `build` writes them, one subfolder per point), or, with "
                    "--size base_radius, find the smallest cam.base_radius that passes the design checks "
                    "(bisection with the dense checks, to --tol) and draw the sizing chart: that radius over "
                    "the first numeric axis, one line per value of the next, one panel per value of a "
                    "categorical axis (the handbook nomogram). Writes sweep.csv/sweep.parquet (or "
                    "sizing.csv/sizing.parquet and sizing_chart.png) and study.json into OUT. A point whose "
                    "spec breaks a rule is a row saying why.",
        epilog="examples:\n"
               "  cam-workbench sweep --vary motion[1].lift,motion[3].lift=10:30:5 "
               "--vary motion[1].law,motion[3].law=cycloidal,harmonic -o lifts\n"
               "  cam-workbench sweep --vary motion[1].angle,motion[3].angle=60:150:10 --balance "
               "motion[2].angle \\\n      --vary motion[1].law,motion[3].law=cycloidal,harmonic,poly345 "
               "--size base_radius --size-checks pressure_angle,curvature -o chart\n\n"
               "exit status: 0 the table is written (rows of points that fail a check are results); 4 some "
               "points could not be evaluated (bad input, cannot be made: their rows say why; the table is "
               "written); 2 bad command line (nothing written); 130 interrupted (nothing written; with "
               "--build the points done stay).",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    p.add_argument("--vary", action="append", default=[], metavar="FIELD=START:STOP:COUNT",
                   help="an axis of the grid: FIELD=START:STOP:COUNT (COUNT values, ends included) or "
                        "FIELD=V1,V2,… (numbers or words, e.g. motion[1].law=cycloidal,harmonic); "
                        "FIELD1,FIELD2=… sets several fields to the same value (a rise and its return). "
                        "Repeatable: the grid is every combination")
    p.add_argument("--balance", metavar="FIELD",
                   help="a dwell's motion[k].angle that takes up the rest of 360° at every point "
                        "(so a rise's angle can vary)")
    p.add_argument("--size", metavar="FIELD", choices=("base_radius", "cam.base_radius"),
                   help="size FIELD (base_radius): its smallest value that passes the checks, per point")
    p.add_argument("--size-checks", metavar="LIST", default=None,
                   help="the checks --size must pass, e.g. pressure_angle,curvature (default: every check)")
    p.add_argument("--tol", type=float, metavar="T", default=None,
                   help="--size: bisection tolerance on the radius, in the spec's unit (default 0.01 mm, "
                        "0.0005 in)")
    p.add_argument("--build", action="store_true",
                   help="build every point's cam with all of `build`'s files (OUT/point-NNN/)")
    add_parallel_arguments(p, "the points")
    add_output_arguments(p, "sweep")
    p.set_defaults(command_id="sweep")


#: the built-in machines (:data:`cam_workbench.generators.machine.MACHINES`)
MACHINE_EXAMPLES = ("three_cams",)


def _machine(sub: Any) -> None:
    p = add_command(sub, "machine",
        description="Build a machine — many cams on one camshaft (a machine file: [machine] name, speed_rpm, "
                    "speed_fluctuation; [[cam]] entries: name, spec (a file or an inline [cam.spec]), phase, "
                    "[cam.tool]; [[clearance]] pairs: between, required; docs/machine.md). Every cam is built as `build` builds it into OUT/<name>/; "
                    "OUT gets machine.json (every number), machine.html (the timing diagram, the torque, the "
                    "flywheel, one table of every cam's checks), timing.svg (displacement, velocity, "
                    "acceleration of every follower against the machine angle), torque.svg (each cam's "
                    "camshaft torque and their sum) — each also as .png when CairoSVG is installed "
                    "(pip install 'cam-workbench[png]') — and machine.gif (the mechanism in motion, 72 frames; "
                    "--animation). Nothing is written if the machine file or a cam is bad.",
        epilog="exit status: 0 every cam passes its design checks and every [[clearance]] pair keeps its "
               "clearance, 3 a cam fails a check or a pair its clearance (the files are written), 2 bad input "
               "(nothing written).",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("machine", nargs="?", metavar="FILE", help="machine file (TOML); omitted: --example")
    p.add_argument("--example", choices=MACHINE_EXAMPLES, default=None,
                   help="a built-in machine instead of FILE: 'three_cams' (a pusher, a gripper arm and a lifter "
                        "at 120 rpm)")
    p.add_argument("--phase-sweep", metavar="CAM", default=None,
                   help="also find the phases of cam CAM (the others kept) that keep every [[clearance]] it is in, "
                        "and the shortest cycle: how much earlier CAM's motion can start keeping them "
                        "(docs/clearance.md): machine.json's phase_sweep, printed and in machine.html")
    p.add_argument("--animation", choices=("gif", "mp4", "none"), default=None,
                   help="the mechanism in motion over one turn (72 frames, 5° apart, 12 per second; "
                        "docs/animation.md): machine.gif (default), machine.mp4 (needs ffmpeg on the PATH, "
                        "else exit 2 before anything is written) or none. A cam that is not drawn (cylindrical, "
                        "indexing) is left out of it with a note; a machine with no cam drawn, or without "
                        "matplotlib, gets no animation and a note by default, and exit 2 when --animation is given")
    add_output_arguments(p, "machine", source=False)
    p.set_defaults(command_id="machine")


def _inspect(sub: Any) -> None:
    p = add_command(sub, "inspect",
        description="Inspect a made cam from measured profile points (POINTS: a CSV file of x,y or x,y,z in the "
                    "spec's units, from a CMM or a scanner, an optional header line x,y[,z]): register them to the "
                    "exact profile (best fit of the rotation about the cam axis and an in-plane shift, or held by the "
                    "bore as datum; robust to outliers, which are reported), give every point's normal deviation "
                    "(+ material outside), the profile-of-a-line verdict (ISO 1101: every point within ±t/2) and what "
                    "the follower does on this part: its s, v, a through a smoothing fit of the deviation and the "
                    "design's contact solve, the acceleration error at cam.speed_rpm; and the deviation's harmonics over the "
                    "cam angle, each one's acceleration error to first order and their sum's (the tolerance study's "
                    "reverse). Prints tables; with -o, writes "
                    "inspection.json, inspection.html, deviations.csv, motion.csv and the figures (SVG; PNG too when "
                    "CairoSVG is installed). Nothing is written on bad input. docs/inspection.md",
        epilog="exit status: 0 inspected (within tolerance, or no --tolerance), 3 an inlier lies outside the "
               "tolerance zone (the files are written), 2 bad input (nothing written).",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    p.add_argument("points", metavar="POINTS", help="measured profile points: CSV, x,y[,z] per line (spec units)")
    p.add_argument("--tolerance", type=float, metavar="T",
                   help="profile tolerance t in the spec's units (zone ±t/2 about the exact profile); omitted: no verdict")
    p.add_argument("--datum", choices=INSPECTION_DATUMS, default="none",
                   help="none: best fit of rotation and shift (the points in any frame; default); bore: the points' "
                        "origin is the bore's axis, the rotation fitted; bore_and_angle: the points are in the part's "
                        "frame (bore and an angular datum), nothing fitted")
    p.add_argument("--wavelength", type=float, metavar="DEG", default=6.0,
                   help="the shortest wave of the deviation the follower's motion follows, in cam degrees (default 6)")
    p.add_argument("--acceleration-limit", type=float, metavar="PCT", default=None,
                   help="allowed acceleration error, percent of the designed peak: the harmonics section adds the "
                        "tolerance study's t(n) at cam.speed_rpm for each listed harmonic and the tightest "
                        "(docs/tolerances.md); omitted: no tolerance")
    add_output_arguments(p, None)
    p.set_defaults(command_id="inspect")


def _spec(sub: Any) -> None:
    p = add_command(sub, "spec",
                    description="Print every spec field with its unit, default and rule "
                                "(the same text as docs/spec.md), or the built-in default spec as TOML.")
    p.add_argument("--default", action="store_true", help="print the built-in default spec as TOML")
    p.add_argument("--example", metavar="NAME",
                   help="print a built-in example spec as TOML: one of "
                        f"{', '.join(n for n, _d in EXAMPLES)} (docs/spec.md "
                        "describes each)")
    p.set_defaults(command_id="spec")


def _tolerance(sub: Any) -> None:
    p = add_command(sub, "tolerance",
        description="For an acceleration error of the follower within --acceleration-limit percent of the designed "
                    "peak at the cam's speed (cam.speed_rpm, or --speed), the largest profile tolerance t (ISO 1101 "
                    "profile of a line: a zone ±t/2 along the profile normal; the worst phase of a wave of n waves "
                    "per turn) for n = 1 … --max-waves: the acceleration limit (first order: δs = g·e, δa = ω²·"
                    "d²δs/dθ²) and the contact limit (the amplitude at which the follower stops following the "
                    f"waves). Prints a table; with -o writes {', '.join(TOLERANCE_FILES)} (the PNG when CairoSVG "
                    "imports). docs/tolerances.md",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    add_spec_arguments(p)
    p.add_argument("--acceleration-limit", type=float, default=5.0, metavar="PCT",
                   help="allowed acceleration error, percent of the designed peak acceleration (default 5)")
    p.add_argument("--max-waves", type=int, default=200, metavar="N",
                   help="the chart's largest number of waves per turn (default 200)")
    p.add_argument("--speed", type=float, metavar="RPM", default=None,
                   help="cam speed of the study (default: the spec's cam.speed_rpm)")
    add_output_arguments(p, None)
    p.set_defaults(command_id="tolerance")


def _freecad(sub: Any) -> None:
    p = add_command(sub, "freecad",
        description="Register the Cam Workbench with your FreeCAD (a CamWorkbench folder in "
                    "FreeCAD's per-user Mod folder, linking this installation's packages), or "
                    "remove it. The Mod folder is asked from every FreeCAD found (freecadcmd on "
                    "PATH, or --freecad), so FreeCAD 0.20, 1.0 and 1.1's versioned folders are "
                    "all right; restart FreeCAD afterwards.")
    p.set_defaults(command_id="freecad")
    actions = p.add_subparsers(dest="action", metavar="{install,uninstall}", required=True)
    for name, help_text in (("install", "add the workbench to FreeCAD (again: replaces our own copy)"),
                            ("uninstall", "remove the workbench from FreeCAD")):
        a = actions.add_parser(name, help=help_text, description=help_text)
        a.add_argument("--mod-dir", type=Path, metavar="DIR",
                       help="use this Mod folder instead of asking FreeCAD (e.g. for tests or a "
                            "portable FreeCAD)")
        a.add_argument("--freecad", metavar="EXE",
                       help="the headless FreeCAD to ask for its Mod folder (default: freecadcmd / "
                            "FreeCADCmd on PATH)")
        if name == "install":
            a.add_argument("--copy", action="store_true",
                           help="copy the packages instead of linking them (re-run after upgrades)")
            a.add_argument("--no-verify", action="store_true",
                           help="do not start FreeCAD to check that the workbench loads")


#: command → the function adding its parser, in the order of :data:`cam_workbench.commands.CATALOGUE`
PARSERS: dict[str, Callable[[Any], None]] = {
    "build": _build, "check": _check, "gcode": _gcode, "dxf": _dxf, "report": _report, "dynamics": _dynamics,
    "ecam": _ecam, "optimise": _optimise, "batch": _batch, "sweep": _sweep, "machine": _machine, "spec": _spec,
    "freecad": _freecad, "tolerance": _tolerance, "inspect": _inspect,
}


def parser() -> argparse.ArgumentParser:
    """The command line's parser: the top-level options and every command's arguments (loads no
    command: argparse and the standard library only)."""
    top, sub = root_parser()
    for add in PARSERS.values():
        add(sub)
    return top

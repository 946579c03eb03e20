"""Every output of a built-in example, through the command line and the Python API, as plain
JSON data: what ``tests/golden/record.py`` stores and ``tests/test_golden.py`` compares.

An *observation* of one example is ``{"example": NAME, "outputs": {KEY: VALUE}}``; each KEY
names one output the way a user gets it:

* ``cli build`` — ``build --plots --example NAME`` (every file build writes): exit status, stdout, stderr; ``cli build: report.json``
  (all of it, ``files`` included), ``cli build: cam.dxf`` (:func:`dxf_record`), ``cli build: cam.nc``,
  ``cam2.nc`` (a conjugate pair), ``commands.csv`` (text), ``cli build: cam.step`` (:func:`step_record`);
* ``cli ecam --format F --table T`` — every table of every format: the table (stdout), the
  deviation summary (stderr), the exit status;
* ``cli gcode --mode xc`` and ``cli gcode --mode xc --cam second`` (a conjugate pair's second
  program; for a single cam, the refusal), ``cli check`` (its table
  and exit status), ``cli dxf --curves C`` for every ``drawing.curves`` value (the drawing and
  what the command prints);
* ``api report()``, ``api checks()``, ``api area``, ``api volume`` of ``Cam.example(NAME)``,
  and ``api export_step(): cam.step``.

Not observed: report.html and the plots (PNG), which a later issue redraws.

The command-line runs are processes of ``python -m cam_workbench.cli`` (this checkout first on
``PYTHONPATH``, a fixed terminal width), forked from a server that has imported the command line
once (cli_server.py; ``CAM_GOLDEN_FORK=0``: plain subprocesses), each in a folder of its own under
a temporary folder whose path is replaced by ``<tmp>`` in everything observed; they run in a
thread pool while the API part runs in this process.
"""
from __future__ import annotations

import concurrent.futures as cf
import json
import math
import os
import subprocess
import sys
import threading
from pathlib import Path
from typing import Any, Callable

from cam_workbench.generators.errors import NotAvailable

from ..conftest import SAFETY_S
from .names import WHERE, where, without_tmp

ROOT = Path(__file__).resolve().parents[2]
DATA = Path(__file__).resolve().parent / "data"
#: the recording's layout; a recording of another format is refused, not misread
FORMAT = 1
#: the drawing.curves values (`dxf --curves`)
CURVES = ("cubic", "spline", "arcs", "polyline")
#: the files of a build that are observed (report.html and plot_*.png are not)
BUILD_TEXT_FILES = ("cam.nc", "cam2.nc", "commands.csv")
#: probe grid per solid: points along x, y, z over its bounding box grown by 10 % on each side
PROBE_GRID = (7, 7, 7)
#: command-line runs at a time, at most (a build peaks at ~0.6 GB: four fit any test machine)
MAX_WORKERS = 4
#: header variables of the DXF that are observed (the dates and the handle seed are not)
DXF_HEADER = ("$ACADVER", "$INSUNITS", "$MEASUREMENT", "$LUNITS", "$AUNITS")
#: DXF attributes that are bookkeeping, not drawing: handles and owners
_DXF_SKIP = {"handle", "owner"}


# ---- plain JSON --------------------------------------------------------------------------
def plain(value: Any) -> Any:
    """``value`` as JSON data (dicts with str keys, lists, str, int, float, bool, None); numpy
    scalars and arrays become Python numbers and lists; anything else is an error (the recording
    would silently lose it)."""
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, int):
        return int(value)
    if isinstance(value, float):
        return float(value)
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if hasattr(value, "tolist"):                    # numpy arrays and scalars
        return plain(value.tolist())
    raise TypeError(f"not JSON data: {type(value).__name__} {value!r:.80}")


def _texts(value: Any, fn: Callable[[str], str]) -> Any:
    """``value`` with ``fn`` applied to every string in it (keys too)."""
    if isinstance(value, str):
        return fn(value)
    if isinstance(value, dict):
        return {fn(k): _texts(v, fn) for k, v in value.items()}
    if isinstance(value, list):
        return [_texts(v, fn) for v in value]
    return value


# ---- DXF -----------------------------------------------------------------------------------
def _dxf_value(v: Any) -> Any:
    """A DXF value as JSON data: ezdxf's Vec2/Vec3 and numpy arrays (a SPLINE's control points)
    as lists of floats; anything else unknown is an error (:func:`plain`)."""
    if hasattr(v, "x") and hasattr(v, "y") and not hasattr(v, "tolist"):     # ezdxf Vec2/Vec3
        return [float(c) for c in v]
    if isinstance(v, (list, tuple)):
        return [_dxf_value(c) for c in v]
    return plain(v)


def dxf_entity(e: Any) -> dict[str, Any]:
    """One DXF entity: its type, layer and every DXF attribute (points as [x, y, z]) but handles,
    with the geometry ezdxf keeps outside the attributes: a SPLINE's degree, knots, control points,
    weights and fit points, a polyline's vertices and bulges, an MTEXT's text."""
    rec: dict[str, Any] = {"type": e.dxftype()}
    for k, v in sorted(e.dxf.all_existing_dxf_attribs().items()):
        if k not in _DXF_SKIP and not k.endswith("_handle"):
            rec[k] = _dxf_value(v)
    kind = rec["type"]
    if kind == "SPLINE":
        rec["knots"] = [float(k) for k in e.knots]
        rec["control_points"] = [_dxf_value(p) for p in e.control_points]
        rec["weights"] = [float(w) for w in e.weights]
        rec["fit_points"] = [_dxf_value(p) for p in e.fit_points]
    elif kind == "LWPOLYLINE":
        rec["points"] = [[float(c) for c in p] for p in e.get_points("xyseb")]
        rec["closed"] = bool(e.closed)
    elif kind == "POLYLINE":
        rec["vertices"] = [dxf_entity(v) for v in e.vertices]
        rec["closed"] = bool(e.is_closed)
    elif kind == "MTEXT":
        rec["text"] = e.text
    elif kind == "INSERT":
        rec["attribs"] = [dxf_entity(a) for a in e.attribs]
    return rec


def dxf_record(path: Path) -> dict[str, Any]:
    """A DXF drawing read by ezdxf: its version and unit header variables, its layers, line types
    and text styles, every model-space entity in file order (:func:`dxf_entity`) and the entities
    of every block (the dimensions' blocks, the arrow heads)."""
    import ezdxf

    doc = ezdxf.readfile(str(path))

    def table(entries: Any) -> list[dict[str, Any]]:
        return [{k: _dxf_value(v) for k, v in sorted(t.dxf.all_existing_dxf_attribs().items())
                 if k not in _DXF_SKIP and not k.endswith("_handle")} for t in entries]

    blocks = {b.name: {"base_point": _dxf_value(b.block.dxf.base_point), "entities": [dxf_entity(e) for e in b]}
              for b in doc.blocks if not b.is_any_layout}
    return {
        "version": doc.dxfversion,
        "header": {k: _dxf_value(doc.header.get(k)) for k in DXF_HEADER if k in doc.header},
        "layers": table(doc.layers),
        "linetypes": sorted(lt.dxf.name for lt in doc.linetypes),
        "styles": table(doc.styles),
        "entities": [dxf_entity(e) for e in doc.modelspace()],
        "blocks": blocks,
    }


# ---- STEP ----------------------------------------------------------------------------------
def _occ() -> Any:
    return where("ocp")


def _subshapes(occ: Any, shape: Any, kind: Any) -> list[Any]:
    """The distinct sub-shapes of ``shape`` of ``kind`` (each once, however many faces share it)."""
    ex = occ.TopExp_Explorer(shape, kind)
    seen: dict[int, list[Any]] = {}
    out = []
    while ex.More():
        s = ex.Current()
        same = seen.setdefault(hash(s), [])
        if not any(s.IsSame(t) for t in same):
            same.append(s)
            out.append(s)
        ex.Next()
    return out


def _bbox(occ: Any, shape: Any) -> list[float]:
    box = occ.Bnd_Box()
    occ.add_to_box(shape, box, optimal=True)
    return list(occ.box_limits(box))


def probe_points(box: list[float], grid: tuple[int, int, int] = PROBE_GRID) -> list[tuple[float, float, float]]:
    """The probe points of a solid whose bounding box is ``box`` (xmin, ymin, zmin, xmax, ymax,
    zmax): a grid over the box grown by 10 % of its size on each side, shifted by 1.23 % of a
    cell so that no probe lies on a symmetry plane or a face of a prism."""
    lo, hi = box[:3], box[3:]
    axes = [[lo[a] + (hi[a] - lo[a]) * (-0.1 + 1.2 * ((i + 0.5) / n + 0.0123 / n)) for i in range(n)]
            for a, n in enumerate(grid)]
    return [(x, y, z) for x in axes[0] for y in axes[1] for z in axes[2]]


def boundary_distances(occ: Any, solid: Any, points: list[tuple[float, float, float]]) -> list[float]:
    """OCCT's distance (``BRepExtrema_DistShapeShape``) from each point to the boundary of
    ``solid`` (its shells): a measure of the surface that does not depend on how it is split into
    faces or parametrised.  To the boundary, not the solid: the distance to a solid is 0 inside
    it (no information) and costs OCCT a point classification each (~6 times slower)."""
    shells = _subshapes(occ, solid, occ.TopAbs_SHELL)
    calcs = []
    for shell in shells:
        calc = occ.BRepExtrema_DistShapeShape()
        calc.LoadS1(shell)
        calcs.append(calc)
    out = []
    for p in points:
        vertex = occ.BRepBuilderAPI_MakeVertex(occ.gp_Pnt(*p)).Vertex()
        best = math.inf
        for calc in calcs:
            calc.LoadS2(vertex)
            calc.Perform()
            if not calc.IsDone():
                raise RuntimeError(f"OCCT's distance from {p} to the solid failed")
            best = min(best, calc.Value())
        out.append(best)
    return out


def step_record(path: Path, probe_boxes: list[list[float]] | None = None) -> dict[str, Any]:
    """A STEP file read back by OCCT (millimetres): its solids, shells, faces and edges (each
    counted once), OCCT's volume and surface area, and per solid the same with its bounding box
    and :func:`boundary_distances` from :func:`probe_points`.  ``probe_boxes``: the boxes whose
    probe points to use, solid by solid (the recording's, so that a changed solid is probed where
    the old one was); default: each solid's own."""
    occ = _occ()
    occ.require("the golden recording's STEP geometry")
    occ.init_step()
    occ.static_set("xstep.cascade.unit", "MM")
    reader = occ.STEPControl_Reader()
    if reader.ReadFile(str(path)) != occ.IFSelect_RetDone:
        raise OSError(f"OCCT cannot read {path}")
    reader.TransferRoots()
    shape = reader.OneShape()

    def measures(s: Any) -> dict[str, Any]:
        vol, area = occ.GProp_GProps(), occ.GProp_GProps()
        occ.volume_properties(s, vol)
        occ.surface_properties(s, area)
        return {"volume": vol.Mass(), "area": area.Mass(),
                "shells": len(_subshapes(occ, s, occ.TopAbs_SHELL)),
                "faces": len(_subshapes(occ, s, occ.TopAbs_FACE)),
                "edges": len(_subshapes(occ, s, occ.TopAbs_EDGE)),
                "bbox": _bbox(occ, s)}

    solids = [occ.topods_solid(s) for s in _subshapes(occ, shape, occ.TopAbs_SOLID)]
    per_solid = []
    for i, solid in enumerate(solids):
        rec = measures(solid)
        box = probe_boxes[i] if probe_boxes is not None and i < len(probe_boxes) else rec["bbox"]
        rec["probes"] = {"box": box, "grid": list(PROBE_GRID),
                         "distances": boundary_distances(occ, solid, probe_points(box))}
        per_solid.append(rec)
    return {"solids": len(solids), **measures(shape), "per_solid": per_solid}


def recorded_probe_boxes(record: dict[str, Any] | None) -> list[list[float]] | None:
    """The probe boxes of a recorded :func:`step_record`, solid by solid."""
    if not isinstance(record, dict):
        return None
    return [s["probes"]["box"] for s in record.get("per_solid", [])]


# ---- the command line ----------------------------------------------------------------------
def cli_env() -> dict[str, str]:
    """The environment of every command: this checkout first on PYTHONPATH (so the commands run
    the code under test, as the shared venv's own tests do), a fixed terminal width for the
    tables, no colour."""
    env = {k: v for k, v in os.environ.items() if k not in ("FORCE_COLOR", "CLICOLOR_FORCE")}
    path = env.get("PYTHONPATH", "")
    env.update(PYTHONPATH=str(ROOT) + (os.pathsep + path if path else ""), COLUMNS="100", LINES="50",
               NO_COLOR="1", TERM="dumb", PYTHONHASHSEED="0", PYTHONIOENCODING="utf-8")
    return env


class _Server:
    """One pre-imported command line (tests/golden/cli_server.py) that forks a process per
    command, used by one thread at a time."""

    def __init__(self, folder: Path):
        self.proc = subprocess.Popen([sys.executable, "-m", "tests.golden.cli_server"], cwd=folder,
                                     env=cli_env(), stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     text=True, encoding="utf-8")

    def run(self, args: list[str], cwd: Path) -> int:
        out, err = _streams(cwd)
        assert self.proc.stdin is not None and self.proc.stdout is not None
        self.proc.stdin.write(json.dumps({"args": args, "cwd": str(cwd), "stdout": str(out),
                                          "stderr": str(err)}) + "\n")
        self.proc.stdin.flush()
        reply = self.proc.stdout.readline()
        if not reply:
            raise RuntimeError(f"the command-line server ended (status {self.proc.wait()}) running {args}")
        return int(json.loads(reply)["exit"])

    def close(self) -> None:
        if self.proc.stdin is not None:
            self.proc.stdin.close()
        self.proc.wait(timeout=SAFETY_S)


#: ``CAM_GOLDEN_FORK=0``: every command a plain ``python -m`` subprocess (slower: each imports
#: numpy, scipy and the project anew); otherwise forked from a pre-imported server per thread
FORK = os.environ.get("CAM_GOLDEN_FORK", "1") != "0"
_local = threading.local()
_servers: list[_Server] = []
_servers_lock = threading.Lock()


def _server(folder: Path) -> _Server:
    server = getattr(_local, "server", None)
    if server is None:
        server = _local.server = _Server(folder)
        with _servers_lock:
            _servers.append(server)
    return server


def close_servers() -> None:
    """End every command-line server this process started."""
    with _servers_lock:
        while _servers:
            _servers.pop().close()


def _streams(cwd: Path) -> tuple[Path, Path]:
    """Where a forked command's stdout and stderr go: beside its folder, not in it."""
    return cwd.parent / f"{cwd.name}.stdout", cwd.parent / f"{cwd.name}.stderr"


def _run(args: list[str], cwd: Path) -> dict[str, Any]:
    cwd.mkdir(parents=True, exist_ok=True)
    if FORK:
        status = _server(cwd.parent).run(args, cwd)
        out, err = _streams(cwd)
        run = {"args": args, "exit": status, "stdout": out.read_text(encoding="utf-8"),
               "stderr": err.read_text(encoding="utf-8")}
        out.unlink()
        err.unlink()
        return run
    res = subprocess.run([sys.executable, "-m", WHERE["cli"], *args], cwd=cwd, env=cli_env(),
                         capture_output=True, text=True, encoding="utf-8", timeout=SAFETY_S)
    return {"args": args, "exit": res.returncode, "stdout": res.stdout, "stderr": res.stderr}


def _build(name: str, cwd: Path) -> dict[str, Any]:
    # --plots: the figures as PNG files, which build wrote by default when the outputs were recorded
    run = _run(["build", "--plots", "--example", name, "-o", "build"], cwd)
    out = cwd / "build"
    got: dict[str, Any] = {"cli build": run}
    if (out / "report.json").exists():
        got["cli build: report.json"] = json.loads((out / "report.json").read_text(encoding="utf-8"))
    if (out / "cam.dxf").exists():
        got["cli build: cam.dxf"] = dxf_record(out / "cam.dxf")
    for f in BUILD_TEXT_FILES:
        if (out / f).exists():
            got[f"cli build: {f}"] = (out / f).read_text(encoding="utf-8")
    return got


def _dxf(name: str, curves: str, cwd: Path) -> dict[str, Any]:
    run = _run(["dxf", "--example", name, "--curves", curves, "-o", "drawing.dxf"], cwd)
    if (cwd / "drawing.dxf").exists():
        run["dxf"] = dxf_record(cwd / "drawing.dxf")
    return {f"cli dxf --curves {curves}": run}


def _plain_run(key: str, args: list[str], cwd: Path) -> dict[str, Any]:
    return {key: _run(args, cwd)}


def cli_jobs(name: str, folder: Path) -> list[Callable[[], dict[str, Any]]]:
    """The command-line runs of example ``name``, each with its own folder under ``folder``: each
    a function returning its outputs by key.  The build first (the longest)."""
    jobs: list[Callable[[], dict[str, Any]]] = [lambda: _build(name, folder / "build")]
    tables: dict[str, tuple[str, ...]] = where("ecam_tables")  # type: ignore[assignment]
    for fmt, names in tables.items():
        for table in names:
            key = f"cli ecam --format {fmt} --table {table}"
            args = ["ecam", "--example", name, "--format", fmt, "--table", table]
            jobs.append(lambda k=key, a=args, d=folder / f"ecam-{fmt}-{table}": _plain_run(k, a, d))
    # --cam second for every example: a pair's second program, a single cam's refusal
    for i, extra in enumerate(([], ["--cam", "second"])):
        key = " ".join(["cli gcode --mode xc", *extra])
        args = ["gcode", "--example", name, "--mode", "xc", *extra]
        jobs.append(lambda k=key, a=args, d=folder / f"gcode-xc-{i}": _plain_run(k, a, d))
    jobs.append(lambda: _plain_run("cli check", ["check", "--example", name], folder / "check"))
    for curves in CURVES:
        jobs.append(lambda c=curves: _dxf(name, c, folder / f"dxf-{c}"))
    return jobs


# ---- the API -------------------------------------------------------------------------------
def api_outputs(name: str, folder: Path, probe_boxes: list[list[float]] | None = None) -> dict[str, Any]:
    """``Cam.example(name)``'s report(), checks(), area, volume and its export_step() read
    back (:func:`step_record`)."""
    cls: Any = where("api")
    cam = cls.example(name)
    folder.mkdir(parents=True, exist_ok=True)
    try:
        area: Any = plain(cam.area)
    except NotAvailable as exc:         # a barrel or globoidal indexer: no exact top face
        area = {"refused": str(exc)}
    got: dict[str, Any] = {"api report()": plain(cam.report()), "api checks()": plain(cam.checks()),
                           "api area": area, "api volume": plain(cam.volume)}
    cam.export_step(folder / "cam.step")
    got["api export_step(): cam.step"] = step_record(folder / "cam.step", probe_boxes)
    return got


# ---- one example, many examples --------------------------------------------------------------
class Observer:
    """Observes examples: their command-line runs go to a thread pool as soon as
    :meth:`start` is called (so that they run while the API part of an earlier example runs
    here); :meth:`observe` waits for them and adds the API part."""

    def __init__(self, folder: Path, workers: int | None = None):
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.pool = cf.ThreadPoolExecutor(max_workers=workers or max(1, min(MAX_WORKERS, os.cpu_count() or 1)))
        self.pending: dict[str, list[cf.Future[dict[str, Any]]]] = {}

    def start(self, name: str) -> None:
        if name not in self.pending:
            self.pending[name] = [self.pool.submit(fn) for fn in cli_jobs(name, self.folder / name / "cli")]

    def observe(self, name: str, recorded: dict[str, Any] | None = None) -> dict[str, Any]:
        """The observation of ``name``; with ``recorded`` (an earlier observation), the STEP files
        are probed at the recording's points."""
        self.start(name)
        old = (recorded or {}).get("outputs", {})
        outputs: dict[str, Any] = {}
        outputs.update(api_outputs(name, self.folder / name / "api",
                                   recorded_probe_boxes(old.get("api export_step(): cam.step"))))
        for fut in self.pending.pop(name):
            outputs.update(fut.result())
        step = self.folder / name / "cli" / "build" / "build" / "cam.step"
        if step.exists():
            outputs["cli build: cam.step"] = step_record(step, recorded_probe_boxes(old.get("cli build: cam.step")))
        tmp = (str(self.folder), str(self.folder.resolve()))
        outputs = {k: _texts(plain(v), lambda s: without_tmp(s, *tmp)) for k, v in sorted(outputs.items())}
        return {"format": FORMAT, "example": name, "outputs": outputs}

    def close(self) -> None:
        self.pool.shutdown(wait=True, cancel_futures=True)
        close_servers()


def about() -> dict[str, Any]:
    """The libraries the recording was made with (kept beside it, not compared: a mismatch after
    an upgrade of one of them is that library's)."""
    import platform
    from importlib import metadata

    versions = {}
    for dist in ("numpy", "scipy", "ezdxf", "cadquery-ocp", "cadquery-ocp-novtk", "rich"):
        try:
            versions[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            pass
    return {"python": platform.python_version(), "machine": platform.machine(), **versions}

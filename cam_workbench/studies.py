"""Design studies from Python and the command line: a batch of specs built into one folder each,
sweeps over a grid of spec fields, sizing charts — on Dask or in this process.

    from cam_workbench.studies import batch, sweep, write_study
    from cam_workbench.generators.spec.examples import example_spec

    table = sweep(example_spec("default"),
                  ["motion[1].angle,motion[3].angle=60:150:10",
                   "motion[1].law,motion[3].law=cycloidal,harmonic,poly345"],
                  balance="motion[2].angle", size=True, checks="pressure_angle,curvature",
                  workers=2)                                # a local Dask cluster of 2 processes
    write_study(table, "chart")                             # sizing.csv/.parquet, sizing_chart.png

    batch(["specs/", "extra.toml"], "out/batch")            # each spec's files in out/batch/<name>/

``workers``: None — a local Dask cluster with one process per CPU (no more than there are tasks;
in this process when that is one, or when Dask is not installed); 0 — this process, no Dask;
N — a local cluster of N processes; ``scheduler="tcp://host:8786"`` — an existing cluster.
``executor`` — any executor of :mod:`cam_workbench.generators.studies.executor` (e.g. one ``dask_executor``
shared by several studies).  Results never depend on where they ran.

An output folder follows :mod:`cam_workbench.exporters.output_rule`: a re-run of the same study (the same
sources; for a sweep, the same base spec's source) replaces its own entries, another study's or
command's folder is refused unless ``replace=True``, a folder holding files of yours always.

The mathematics (grids, evaluation, the radius bisection) is :mod:`cam_workbench.generators.studies`; this
module adds what needs the upper layers: the full build of each cam (the solid, STEP, DXF,
G-code, the report — :mod:`cam_workbench.pipeline`, as ``build``), and the files.
"""
from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterator, Mapping, Sequence

from cam_workbench.exporters.atomic import OutputSet, write_bytes_atomic, write_text_atomic
from cam_workbench.exporters.output_rule import (MANIFEST, Claim, admit, file_source, read_manifest, script_source, spec_claim,
                                   study_digest)
from cam_workbench.exporters.study_plots import close, figure_bytes
from cam_workbench.exporters.study_plots import sizing_chart
from cam_workbench.exporters.study_table import csv_text, have_parquet, meta_text, parquet_bytes
from cam_workbench.generators.checks.design import run_checks
from cam_workbench.generators.errors import CamError, SpecError
from cam_workbench.generators.kinds import body_of
from cam_workbench.generators.spec import CamSpec, load_spec, spec_digest
from cam_workbench.generators.studies.executor import Executor, SerialExecutor, TaskContext
from cam_workbench.generators.studies.grid import Axis, Grid, parse_vary
from cam_workbench.generators.studies.sizing import SizingSettings, check_names
from cam_workbench.generators.studies.sweep import Counter, run_sweep
from cam_workbench.generators.studies.table import StudyTable, error_row, summary_row

from .parallel import dask_available, dask_executor, default_workers
from .pipeline import run_pipeline, write_outputs

SUMMARY_CSV = "summary.csv"
SUMMARY_PARQUET = "summary.parquet"
STUDY_JSON = "study.json"
SWEEP_NAMES = {"sweep": ("sweep.csv", "sweep.parquet"), "sizing": ("sizing.csv", "sizing.parquet")}
CHART_PNG = "sizing_chart.png"
BATCH_FIRST = ("name", "spec", "folder", "status", "error")


# ---- choosing where the work runs ------------------------------------------------------------
@contextlib.contextmanager
def executor_scope(executor: Executor | None = None, workers: int | None = None, scheduler: str | None = None,
                   tasks: int | None = None, note: Callable[[str], Any] | None = None) -> Iterator[Executor]:
    """The executor a study runs on (see the module's docstring for ``workers``/``scheduler``);
    a local cluster made here is shut down when the block ends.  ``note`` receives one line when
    ``workers`` None falls back to this process because Dask is not installed."""
    if executor is not None:
        yield executor
        return
    if scheduler is None and workers == 0:
        yield SerialExecutor()
        return
    if scheduler is None and workers is None:
        n = default_workers() if tasks is None else min(default_workers(), max(tasks, 1))
        if n <= 1:
            yield SerialExecutor()
            return
        if not dask_available():
            if note is not None:
                note('Dask is not installed: running in this process (pip install "cam-workbench[dask]" '
                     'to run on a local cluster)')
            yield SerialExecutor()
            return
        workers = n

    with dask_executor(workers, scheduler) as ex:
        yield ex


# ---- building one cam (a task: runs on any worker) ----------------------------------------
@dataclass(frozen=True)
class BuildJob:
    """One cam to build: its subfolder's name, the spec (None: ``error`` says why there is none),
    the columns its row starts with and the cam's source (recorded in its set's manifest)."""

    name: str
    spec: CamSpec | None
    row: dict[str, Any] = field(default_factory=dict)
    error: tuple[str, str] | None = None      # (status, message) for a spec that could not be read
    source: str | None = None


@dataclass
class BuildOutcome:
    name: str
    row: dict[str, Any]
    files: dict[str, bytes] | None             # the output set's files (None: nothing to write)
    digest: str | None


def build_task(job: BuildJob, ctx: TaskContext) -> BuildOutcome:
    """The full ``build`` pipeline for one spec, written into a private temporary folder and
    returned as bytes (so that the caller writes the output set, wherever this ran); a spec that
    cannot be made, or any error, is a row saying why."""
    row = dict(job.row)
    if job.spec is None:
        status, msg = job.error or ("bad input", "no spec")
        return BuildOutcome(job.name, {**row, **error_row(status, msg)}, None, None)
    spec = job.spec
    try:
        outputs = run_pipeline(spec)
        with tempfile.TemporaryDirectory(prefix="cam-workbench-build-") as tmp:
            folder = Path(tmp) / "cam"
            report = write_outputs(outputs, folder, Claim("build"))
            manifest = read_manifest(folder) or {"files": []}
            files = {name: (folder / name).read_bytes() for name in manifest["files"]}
    except CamError as exc:
        status = "bad input" if isinstance(exc, SpecError) else "cannot be made"
        return BuildOutcome(job.name, {**row, **error_row(status, exc)}, None, None)
    except Exception as exc:  # noqa: BLE001 - one spec's internal error must not stop the others
        return BuildOutcome(job.name, {**row, **error_row("error", f"{type(exc).__name__}: {exc}")}, None, None)
    numbers = summary_row(report, spec.cam.base_radius)
    numbers["solid_valid"] = bool(report.get("solid", {}).get("valid"))
    return BuildOutcome(job.name, {**row, "status": "ok", "error": "", **numbers}, files,
                        report.get("spec_digest"))


# ---- a folder of output sets ------------------------------------------------------------------
class SetsFolder:
    """An output folder holding one subfolder per cam (each an atomic output set, written as its
    cam is done) and the study's tables; its manifest lists them.  Whether a run may write there
    is :func:`cam_workbench.exporters.output_rule.admit`'s rule for the study's ``claim`` (checked when made,
    before any work, and with the entries' names in :meth:`plan`): a re-run of the same study
    replaces its entries; nothing a manifest does not list is ever touched."""

    def __init__(self, folder: str | os.PathLike[str], claim: Claim):
        admit(folder, claim)
        self.folder = Path(folder)
        self.claim = claim
        self.earlier: dict[str, Any] | None = None
        self.kept: list[str] = []

    def plan(self, names: Sequence[str], tables: Sequence[str]) -> None:
        """Claim the entries before any is written (a killed run leaves a folder the next run of
        the study accepts).

        Raises:
            SpecError: the folder may not take these entries (nothing written).
        """
        entries = list(dict.fromkeys([*tables, *names]))
        self.kept = admit(self.folder, self.claim, entries)
        for name in names:               # a subfolder holding files of the user's: refused now, not midway
            if (self.folder / name).is_dir():
                admit(self.folder / name, Claim(self.claim.command, replace=True, option=self.claim.option))
        self.earlier = read_manifest(self.folder)
        held = self.earlier["files"] if self.earlier else []
        self._manifest(sorted(set(entries) | set(held)), final=False)

    def _manifest(self, files: list[str], final: bool = True) -> None:
        self.folder.mkdir(parents=True, exist_ok=True)
        manifest = self.claim.manifest(files, self.earlier if self.kept else None, digest=final)
        write_text_atomic(self.folder / MANIFEST, json.dumps(manifest, indent=1) + "\n")

    def write_set(self, name: str, files: Mapping[str, bytes], claim: Claim) -> None:
        """One cam's set into its subfolder (an earlier set there is this study's: replaced)."""
        with OutputSet(self.folder / name, claim) as o:
            for fname, data in files.items():
                o.add_bytes(fname, data)

    def write_file(self, name: str, data: bytes) -> None:
        write_bytes_atomic(self.folder / name, data)

    def finish(self, written: Sequence[str]) -> None:
        """The manifest lists what this run made and the earlier files it kept; the earlier
        set's other entries are removed — its manifest listed them, and this run was admitted
        to replace them (the same study making them again, a cam that now fails among them, or
        ``replace``)."""
        keep = set(written) | set(self.kept)
        for name in (self.earlier or {}).get("files", []):
            if name not in keep and "/" not in name and name not in ("", ".", ".."):
                p = self.folder / name
                if p.is_dir():
                    shutil.rmtree(p, ignore_errors=True)
                elif p.exists():
                    p.unlink()
        self._manifest(sorted(keep))


def _table_files(table: StudyTable, csv_name: str, parquet_name: str) -> dict[str, bytes]:
    files = {csv_name: csv_text(table).encode("utf-8"), STUDY_JSON: meta_text(table).encode("utf-8")}
    if have_parquet():
        files[parquet_name] = parquet_bytes(table)
    return files


def _run_builds(jobs: list[BuildJob], out: str | os.PathLike[str], claim: Claim, first: Sequence[str],
                meta: dict[str, Any], executor: Executor | None, workers: int | None, scheduler: str | None,
                progress: Callable[[int, int], Any] | None, cancel: threading.Event | None,
                note: Callable[[str], Any] | None) -> StudyTable:
    t0 = time.perf_counter()
    target = SetsFolder(out, claim)
    names = [j.name for j in jobs]
    target.plan([j.name for j in jobs if j.spec is not None], [SUMMARY_CSV, SUMMARY_PARQUET, STUDY_JSON])
    rows: list[dict[str, Any] | None] = [None] * len(jobs)
    written: list[str] = []
    counter = Counter(len(jobs), progress, cancel)

    def on_result(i: int, res: BuildOutcome) -> None:
        row = dict(res.row)
        job = jobs[i]
        if res.files is not None and job.spec is not None:
            entry = spec_claim(job.spec, claim.command, job.source or claim.source, replace=True, option=claim.option)
            try:
                target.write_set(res.name, res.files, entry)
                written.append(res.name)
                row["folder"] = res.name
            except (OSError, CamError) as exc:
                row.update(error_row("error", f"writing {res.name}/: {exc}"))
        rows[i] = row
        counter.finished(i, 1)

    interrupted = False
    n_workers = 1
    try:
        with executor_scope(executor, workers, scheduler, tasks=sum(j.spec is not None for j in jobs),
                            note=note) as ex:
            n_workers = ex.workers
            ex.run(build_task, jobs, on_result=on_result, should_stop=counter.should_stop)
    except KeyboardInterrupt:          # Ctrl-C: what is built stays, the table says the rest
        interrupted = True
    full = [r if r is not None else {**jobs[i].row, "name": names[i], "status": "cancelled",
                                     "error": "the run was stopped before this cam was built"}
            for i, r in enumerate(rows)]
    meta = {**meta, "specs": len(jobs), "built": len(written), "workers": n_workers,
            "time_s": time.perf_counter() - t0, "cancelled": any(r is None for r in rows)}
    table = StudyTable.from_rows(full, first, meta)
    files = _table_files(table, SUMMARY_CSV, SUMMARY_PARQUET)
    for name, data in files.items():
        target.write_file(name, data)
    target.finish([*files, *written])
    if interrupted:
        raise KeyboardInterrupt(f"{len(written)} of {len(jobs)} cams written; {SUMMARY_CSV} marks the rest cancelled")
    return table


# ---- batch -------------------------------------------------------------------------------------
def _folder_name(stem: str, taken: set[str]) -> str:
    base = re.sub(r"[^A-Za-z0-9._-]+", "_", stem).strip("._") or "cam"
    if base in (SUMMARY_CSV, SUMMARY_PARQUET, STUDY_JSON, MANIFEST):
        base = f"cam_{base}"
    name, k = base, 2
    while name in taken:
        name, k = f"{base}-{k}", k + 1
    taken.add(name)
    return name


def collect_specs(sources: Sequence[str | os.PathLike[str] | CamSpec]) -> list[BuildJob]:
    """The batch's cams: spec files, folders (their ``*.toml`` files, sorted by name, not
    recursive) and CamSpec objects, each with its subfolder name (the file's stem; ``-2``, ``-3``
    for repeats).  A file that cannot be read or breaks a rule gives a job without a spec whose
    row says why.

    Raises:
        SpecError: no sources, or a folder without any ``*.toml``.
    """
    if not sources:
        raise SpecError("SPECS", "give at least one spec file or folder")
    taken: set[str] = set()
    jobs: list[BuildJob] = []
    for k, src in enumerate(sources):
        if isinstance(src, CamSpec):
            name = _folder_name(f"spec{k + 1}", taken)
            jobs.append(BuildJob(name, src, {"name": name, "spec": f"<spec {k + 1}>"}, source=script_source()))
            continue
        path = Path(src)
        files = sorted(p for p in path.glob("*.toml") if p.is_file()) if path.is_dir() else [path]
        if path.is_dir() and not files:
            raise SpecError(str(path), "folder holds no *.toml spec files")
        for f in files:
            name = _folder_name(f.stem, taken)
            row = {"name": name, "spec": str(f)}
            try:
                jobs.append(BuildJob(name, load_spec(f), row, source=file_source(f)))
            except CamError as exc:
                jobs.append(BuildJob(name, None, row, ("bad input", str(exc))))
    return jobs


def batch_claim(sources: Sequence[str | os.PathLike[str] | CamSpec], jobs: Sequence[BuildJob],
                changes: Mapping[str, Any] | None = None, *, replace: bool = False, option: str = "out") -> Claim:
    """The claim of a batch on its output folder: its source is the sources given (files and
    folders resolved; ``python:<script>`` for CamSpec objects), its digest that of every job's
    name and spec, and ``changes``."""
    named = [script_source() if isinstance(s, CamSpec) else file_source(s) for s in sources]
    definition = {"sources": list(dict.fromkeys(named)), "set": dict(changes or {})}
    made = [[j.name, spec_digest(j.spec) if j.spec is not None else j.error] for j in jobs]
    return Claim("batch", ", ".join(definition["sources"]), study_digest({**definition, "jobs": made}),
                 definition, replace, option)


def batch(sources: Sequence[str | os.PathLike[str] | CamSpec], out: str | os.PathLike[str], *,
          changes: Mapping[str, Any] | None = None, executor: Executor | None = None,
          workers: int | None = None, scheduler: str | None = None,
          progress: Callable[[int, int], Any] | None = None, cancel: threading.Event | None = None,
          note: Callable[[str], Any] | None = None, replace: bool = False, option: str = "out") -> StudyTable:
    """Build every spec of ``sources`` (files, folders, CamSpec objects) with the full ``build``
    pipeline into ``out/<name>/`` (one atomic output set each, written as it is done) and write
    ``out/summary.csv``, ``summary.parquet`` (with pyarrow) and ``study.json``.

    A bad spec (unreadable, a broken rule, a cam that cannot be made) is a row with its status
    and message, and the others go on.  ``changes`` (dotted fields) apply to every spec.  Returns
    the summary table (rows in the order of the sources).  On Ctrl-C the cams already built stay,
    the table is written with the rest ``cancelled``, and KeyboardInterrupt is raised again, its
    message saying how many cams were written.

    ``out`` follows :mod:`cam_workbench.exporters.output_rule` (the module's docstring): ``replace=True``
    replaces another study's or cam's set there; ``option`` is how messages name ``out`` (the
    command line passes "-o").

    Raises:
        SpecError: no spec found, or ``out`` refused (files that are not cam-workbench output,
            another study's or cam's set) — before any work.
    """
    jobs = collect_specs(sources)
    if changes:
        jobs = [_with_changes(j, changes) for j in jobs]
    claim = batch_claim(sources, jobs, changes, replace=replace, option=option)
    return _run_builds(jobs, out, claim, BATCH_FIRST, {"kind": "batch"}, executor, workers, scheduler,
                       progress, cancel, note)


def _with_changes(job: BuildJob, changes: Mapping[str, Any]) -> BuildJob:
    if job.spec is None:
        return job
    try:
        return BuildJob(job.name, job.spec.replace(**changes), job.row, source=job.source)
    except CamError as exc:
        return BuildJob(job.name, None, job.row, ("bad input", str(exc)), job.source)


# ---- sweeps ------------------------------------------------------------------------------------
def make_grid(vary: Sequence[str | Axis] | Mapping[str, Any], balance: str | None = None) -> Grid:
    """A :class:`Grid` from ``--vary`` texts, Axis objects, or a mapping FIELD[,FIELD…] → values
    (a list, or a ``"START:STOP:COUNT"`` / ``"V1,V2"`` text)."""
    axes: list[Axis] = []
    if isinstance(vary, Mapping):
        for k, v in vary.items():
            if isinstance(v, str):
                axes.append(parse_vary(f"{k}={v}"))
            else:
                axes.append(Axis(tuple(f.strip() for f in k.split(",")), tuple(v)))
    else:
        for item in vary:
            axes.append(item if isinstance(item, Axis) else parse_vary(str(item)))
    return Grid(tuple(axes), balance)


def sweep(spec: CamSpec, vary: Sequence[str | Axis] | Mapping[str, Any], *, balance: str | None = None,
          size: bool = False, checks: str | Sequence[str] | None = None, tol: float | None = None,
          build: str | os.PathLike[str] | None = None, executor: Executor | None = None,
          workers: int | None = None, scheduler: str | None = None,
          progress: Callable[[int, int], Any] | None = None, cancel: threading.Event | None = None,
          note: Callable[[str], Any] | None = None, source: str | None = None, replace: bool = False,
          option: str = "build") -> StudyTable:
    """Every point of the grid ``vary`` on ``spec``: designed and checked without a solid
    (default), sized (``size``: the smallest ``cam.base_radius`` meeting ``checks`` — all, or
    a list — by bisection to ``tol``, :mod:`cam_workbench.generators.studies.sizing`), or built with every file
    into ``build/point-NNN/`` (with ``build/summary.csv`` …).  Returns the table (grid order);
    its ``meta`` records the study and ``source`` (the spec's: a file's path, ``example:NAME``;
    default ``python:<script>``) for :func:`write_study`.  ``build`` follows
    :mod:`cam_workbench.exporters.output_rule` as :func:`batch`'s ``out`` does (``replace``, ``option``).

    Raises:
        SpecError: a bad grid, check name or option, or ``build`` refused (before any work).
    """
    grid = make_grid(vary, balance)
    sizing = None
    body = body_of(spec)
    if size and not body.plane:          # the sizing searches a plane cam's base radius
        raise SpecError("--size", f"sizes cam.base_radius of a plane cam; a {body.title.lower()}'s pitch radius is "
                                  f"{body.size_field}: sweep it with --vary {body.size_field}=…")
    if size:
        if build is not None:
            raise SpecError("--build", "builds the grid's cams as they are; it cannot be combined with --size")
        sizing = SizingSettings(checks=check_names(checks), tol=tol)
        if sizing.checks:
            available = {r.name for r in _checks_of(spec)}
            missing = [c for c in sizing.checks if c not in available]
            if missing:
                raise SpecError("--size-checks", f"{missing[0]} is not a check of this follower "
                                                 f"(its checks: {', '.join(sorted(available))})")
        if tol is not None and not tol > 0:
            raise SpecError("--tol", f"must be > 0, got {tol:g}")
    claim = sweep_claim(spec, grid, size=size, checks=checks, tol=tol, build=build is not None,
                        source=source, replace=replace, option=option)
    if build is None:
        grid.check(spec, fixed=("cam.base_radius",) if sizing else ())
        n_tasks = grid.size
        with executor_scope(executor, workers, scheduler, tasks=n_tasks, note=note) as ex:
            table = run_sweep(spec, grid, sizing=sizing, executor=ex, progress=progress, cancel=cancel)
        table.meta.update(source=claim.source, study=claim.spec)
        return table
    grid.check(spec)
    points = grid.points()
    width = len(str(len(points)))
    jobs = []
    for i, pt in enumerate(points):
        name = f"point-{i + 1:0{width}d}"
        row = {"name": name, **pt}
        try:
            jobs.append(BuildJob(name, grid.spec_at(spec, pt), row, source=claim.source))
        except SpecError as exc:
            jobs.append(BuildJob(name, None, row, ("bad input", str(exc)), claim.source))
    meta = {"kind": "sweep", "build": True, "axes": [a.text() for a in grid.axes], "balance": grid.balance,
            "points": len(points), "units": spec.units, "source": claim.source, "study": claim.spec}
    return _run_builds(jobs, build, claim, ("name", *grid.columns, "folder", "status", "error"), meta,
                       executor, workers, scheduler, progress, cancel, note)


def sweep_claim(spec: CamSpec, grid: Grid, *, size: bool = False, checks: str | Sequence[str] | None = None,
                tol: float | None = None, build: bool = False, source: str | None = None, replace: bool = False,
                option: str = "out") -> Claim:
    """The claim of a sweep on its output folder (its table's, or ``build``'s): the study is the
    base spec, the grid and the sizing settings; its source the spec's (default
    ``python:<script>``)."""
    definition = {"kind": "sizing" if size else "sweep", "build": build, "spec": spec.to_dict(),
                  "vary": [a.text() for a in grid.axes], "balance": grid.balance,
                  "checks": list(check_names(checks) or ()) if size else None, "tol": tol if size else None}
    return Claim("sweep", source or script_source(), study_digest(definition), definition, replace, option)


def _checks_of(spec: CamSpec) -> Any:
    return run_checks(spec).results


def write_study(table: StudyTable, out: str | os.PathLike[str], *, chart: bool = True, replace: bool = False,
                option: str = "out") -> dict[str, Any]:
    """Write a sweep's or sizing's table into ``out`` as one output set (all or nothing):
    ``sweep.csv``/``sweep.parquet`` or ``sizing.csv``/``sizing.parquet`` (Parquet with pyarrow),
    ``study.json`` and, for a sizing with a numeric axis, ``sizing_chart.png``.  ``out`` follows
    :mod:`cam_workbench.exporters.output_rule` for the study and source :func:`sweep` recorded in the table's
    ``meta`` (``replace``, ``option`` as for :func:`batch`).  Returns {file kind: name}.

    Raises:
        SpecError: ``out`` refused (nothing written).
    """
    kind = table.meta.get("kind", "sweep")
    csv_name, parquet_name = SWEEP_NAMES["sizing" if kind == "sizing" else "sweep"]
    files = _table_files(table, csv_name, parquet_name)
    if kind == "sizing" and chart:
        png = sizing_chart_png(table)
        if png is not None:
            files[CHART_PNG] = png
    study = table.meta.get("study")
    claim = Claim("sweep", table.meta.get("source") or script_source(),
                  study_digest(study) if study is not None else None, study, replace, option)
    with OutputSet(Path(out), claim) as o:
        for name, data in files.items():
            o.add_bytes(name, data)
    return {("csv" if n.endswith(".csv") else "parquet" if n.endswith(".parquet") else
             "chart" if n.endswith(".png") else "meta"): n for n in files}


def grid_columns(table: StudyTable) -> list[str]:
    """The grid's columns of a sweep table (before ``status``)."""
    cols = []
    for c in table.columns:
        if c in ("status", "name"):
            if c == "status":
                break
            continue
        cols.append(c)
    return cols


def sizing_chart_png(table: StudyTable, **layout: Any) -> bytes | None:
    """The sizing chart of ``table`` as PNG bytes (None when no axis is numeric)."""
    try:
        fig = sizing_chart(table, grid_columns(table), **layout)
    except ValueError:
        return None
    try:
        return figure_bytes(fig, "png")
    finally:
        close(fig)

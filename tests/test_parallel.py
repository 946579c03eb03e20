"""The studies and the optimiser's multistart on Dask (issue 16): a real ``dask scheduler`` with two
``dask worker`` processes on the loopback address (:mod:`tests.dask_cluster`), and a local cluster
of processes (``dask_executor(workers=2)``).  Whatever ran where, the results are the same as the
run in this process, exactly: the optimised design and its history, every table row, every file a
batch writes.  Progress reaches the caller's thread and a stop (the progress callback returning
False, or a ``threading.Event``) ends the running starts early on the workers."""
from __future__ import annotations

import math
import signal
import threading
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("distributed")

from cam_workbench.parallel import dask_executor  # noqa: E402
from cam_workbench.studies import batch  # noqa: E402
from cam_workbench.generators import load_spec, to_toml  # noqa: E402
from cam_workbench.generators.spec.examples import example_spec  # noqa: E402
from cam_workbench.generators.optimise import optimise  # noqa: E402
from cam_workbench.generators.studies.grid import Grid, parse_vary  # noqa: E402
from cam_workbench.generators.studies.sizing import SizingSettings  # noqa: E402
from cam_workbench.generators.studies.sweep import run_sweep  # noqa: E402

from .conftest import ROOT, SAFETY_S  # noqa: E402
from .dask_cluster import loopback_cluster  # noqa: E402

PAPER_MULTI = dict(objective="area", variables="base_radius,offset", multistart=5, seed=11)
EX5 = ROOT / "tests" / "fixtures" / "thesis_ex5_initial.toml"
EX5_MULTI = dict(multistart=3, seed=5, max_evaluations=60)


@pytest.fixture(scope="module")
def scheduler(tmp_path_factory):
    """The address of a scheduler with two workers, all on 127.0.0.1 (stopped after the module)."""
    yield from loopback_cluster(tmp_path_factory.mktemp("dask-cluster"))


@pytest.fixture(scope="module")
def remote(scheduler):
    with dask_executor(scheduler=scheduler) as ex:
        yield ex


@pytest.fixture(scope="module")
def local():
    with dask_executor(workers=2) as ex:
        yield ex


def _same_history(a: list[dict], b: list[dict]) -> bool:
    if len(a) != len(b):
        return False
    for x, y in zip(a, b):
        if x.keys() != y.keys():
            return False
        for k in x:
            u, v = x[k], y[k]
            if isinstance(u, float) and isinstance(v, float) and math.isnan(u) and math.isnan(v):
                continue
            if u != v:
                return False
    return True


def assert_same_result(a, b):
    assert np.array_equal(a.design, b.design)
    assert a.value == b.value and a.initial_value == b.initial_value
    assert (a.status, a.message, a.solver_status, a.evaluations) == (b.status, b.message, b.solver_status,
                                                                     b.evaluations)
    assert _same_history(a.history, b.history)
    assert to_toml(a.spec) == to_toml(b.spec)
    assert a.checks.to_dict()["results"] == b.checks.to_dict()["results"]


@pytest.fixture(scope="module")
def sequential():
    """The runs in this process, one start after another (the reference)."""
    return {"paper": optimise(example_spec("paper"), **PAPER_MULTI),
            "ex5": optimise(load_spec(EX5), **EX5_MULTI)}


# ---- the optimiser's multistart -----------------------------------------------------------------
@pytest.mark.parametrize("where", ["remote", "local"])
@pytest.mark.parametrize("case", ["paper", "ex5"])
def test_multistart_on_dask_is_the_sequential_run(where, case, sequential, request):
    ex = request.getfixturevalue(where)
    seen_threads = set()
    counts = []

    def progress(p):
        seen_threads.add(threading.get_ident())
        counts.append(p.evaluations)

    spec = example_spec("paper") if case == "paper" else load_spec(EX5)
    kw = PAPER_MULTI if case == "paper" else EX5_MULTI
    res = optimise(spec, executor=ex, progress=progress, **kw)
    assert_same_result(res, sequential[case])
    assert res.details["workers"] == 2
    # progress arrived, in the calling thread, never going backwards, never beyond the run's count
    assert seen_threads == {threading.get_ident()}
    assert counts and counts == sorted(counts) and counts[-1] <= res.evaluations


@pytest.mark.parametrize("where", ["remote", "local"])
def test_cancel_on_dask_stops_the_running_starts(where, sequential, request):
    """The progress callback returning False stops every start on the workers: the run ends
    ``cancelled`` with the best design seen (checked like any result), after far fewer
    evaluations than the whole run; the workers are free again afterwards."""
    ex = request.getfixturevalue(where)
    full = sequential["ex5"]
    res = optimise(load_spec(EX5), executor=ex, progress=lambda p: p.evaluations < 25, **EX5_MULTI)
    assert res.status == "cancelled"
    assert 25 <= res.evaluations < full.evaluations / 2
    assert res.checks.to_dict()["results"]            # the result was re-checked densely
    again = optimise(example_spec("paper"), executor=ex, **PAPER_MULTI)
    assert again.status == sequential["paper"].status and np.array_equal(again.design, sequential["paper"].design)


def test_cancel_event_from_another_thread(remote):
    stop = threading.Event()
    first = threading.Event()

    def progress(p):
        first.set()

    timer = threading.Thread(target=lambda: (first.wait(SAFETY_S), stop.set()))
    timer.start()
    res = optimise(load_spec(EX5), executor=remote, progress=progress, cancel=stop, **EX5_MULTI)
    timer.join(SAFETY_S)
    assert res.status == "cancelled" and stop.is_set()


# ---- sweeps -----------------------------------------------------------------------------------
SWEEP_GRID = Grid((parse_vary("motion[1].lift=10:30:5"), parse_vary("motion[3].lift=15,20"),   # unequal: bad rows
                   parse_vary("motion[1].law,motion[3].law=cycloidal,harmonic,poly345,modified_sine")))
SIZING_GRID = Grid((parse_vary("motion[1].angle,motion[3].angle=70:130:4"),
                    parse_vary("motion[1].law,motion[3].law=cycloidal,harmonic")), balance="motion[2].angle")


@pytest.fixture(scope="module")
def sweep_reference():
    spec = example_spec("default")
    return {"evaluate": run_sweep(spec, SWEEP_GRID),
            "size": run_sweep(spec, SIZING_GRID, sizing=SizingSettings(checks=("pressure_angle", "curvature")))}


@pytest.mark.parametrize("where", ["remote", "local"])
@pytest.mark.parametrize("mode", ["evaluate", "size"])
def test_sweep_on_dask_is_the_sequential_sweep(where, mode, sweep_reference, request):
    ex = request.getfixturevalue(where)
    ref = sweep_reference[mode]
    seen = []
    table = run_sweep(example_spec("default"), SWEEP_GRID if mode == "evaluate" else SIZING_GRID,
                      sizing=SizingSettings(checks=("pressure_angle", "curvature")) if mode == "size" else None,
                      executor=ex, progress=lambda d, n: seen.append((d, n)))
    assert table.columns == ref.columns and table.rows == ref.rows
    assert {r["status"] for r in table.rows} == ({"ok", "bad input"} if mode == "evaluate" else {"ok"})
    assert seen[-1] == (len(ref), len(ref)) and [d for d, _ in seen] == sorted(d for d, _ in seen)
    assert table.meta["workers"] == 2


def _blocked_signals() -> set[int]:
    """The signals this thread blocks, read from the kernel (Linux)."""
    status = Path(f"/proc/self/task/{threading.get_native_id()}/status").read_text()
    mask = int(next(ln.split()[1] for ln in status.splitlines() if ln.startswith("SigBlk:")), 16)
    return {k + 1 for k in range(64) if mask >> k & 1}


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads the signal mask from Linux's /proc")
def test_local_workers_block_sigint(local):
    """A terminal's Ctrl-C reaches every process of the foreground group; the local cluster's
    workers block it (the command shuts them down), while this thread, after the cluster started,
    does not (test_cli_studies: the command's Ctrl-C as a user types it)."""
    masks = local.client.run(_blocked_signals)
    assert len(masks) == 2 and all(signal.SIGINT in m for m in masks.values())
    assert signal.SIGINT not in _blocked_signals()


def test_ctrl_c_while_the_cluster_starts_is_held():
    """A SIGINT that arrives while the local cluster starts is neither lost nor raised inside
    Dask's start-up: it is held (dask_executor raises KeyboardInterrupt once the cluster can be
    shut down), and the handler that was there is back afterwards."""
    from cam_workbench.parallel import _sigint_held

    before = signal.getsignal(signal.SIGINT)
    with _sigint_held() as held:
        signal.pthread_kill(threading.main_thread().ident, signal.SIGINT)
        went_on = True
    assert went_on and held == [signal.SIGINT]
    assert signal.getsignal(signal.SIGINT) is before


def test_worker_memory_is_reported(local):
    mem = local.worker_memory()
    assert len(mem) == 2
    for m in mem.values():
        assert 20 < m["rss_mib"] <= m["peak_rss_mib"] + 1


# ---- batch ------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def batch_sources(tmp_path_factory):
    folder = tmp_path_factory.mktemp("specs")
    from cam_workbench.generators.spec.examples import example_dict
    from cam_workbench.generators.spec import dict_to_toml

    for name in ("default", "flat", "paper"):
        (folder / f"{name}.toml").write_text(dict_to_toml(example_dict(name)))
    (folder / "broken.toml").write_text("[cam]\nbase_radius = -3\n")
    return folder


def test_batch_on_the_scheduler_writes_what_the_sequential_batch_writes(scheduler, batch_sources, tmp_path):
    pytest.importorskip("OCP")
    seq = batch([batch_sources], tmp_path / "seq", workers=0)
    par = batch([batch_sources], tmp_path / "par", scheduler=scheduler)
    assert par.columns == seq.columns and par.rows == seq.rows
    assert [r["status"] for r in seq.rows] == ["bad input", "ok", "ok", "ok"]     # broken, default, flat, paper
    assert seq.rows[0]["name"] == "broken" and "cam.base_radius" in seq.rows[0]["error"]
    for name in ("default", "flat", "paper"):
        a, b = tmp_path / "seq" / name, tmp_path / "par" / name
        names = sorted(p.name for p in a.iterdir() if p.name != ".cam-workbench.json")
        assert names == sorted(p.name for p in b.iterdir() if p.name != ".cam-workbench.json")
        # every file byte for byte, but the two that carry their creation time (and the DXF its
        # GUIDs) even when made twice in one process
        for n in names:
            if n not in ("cam.dxf", "cam.step"):
                assert (a / n).read_bytes() == (b / n).read_bytes(), (name, n)
    assert par.meta["workers"] == 2 and seq.meta["workers"] == 1

"""Design studies (issue 16), in this process: grids of spec fields, sweeps evaluated against the
limaçon's closed forms, the smallest base radius (sizing) against closed forms and an independent
brentq, the tables written as CSV and Parquet and read back, the sizing chart.

Every expected number here is computed independently of the code under test: the motion laws
written out, scipy's optimisers and root finders, the limaçon's area π(a² + b²/2)."""
from __future__ import annotations

import csv
import io
import math

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec.examples import example_spec
from cam_workbench.generators.spec import CamSpec
from cam_workbench.generators.studies.executor import NOT_RUN, SerialExecutor, chunks
from cam_workbench.generators.studies.grid import Grid, apply_changes, parse_vary
from cam_workbench.generators.studies.sizing import SizingSettings, smallest_base_radius
from cam_workbench.generators.studies.sweep import run_sweep

# ---- the motion laws, written out (rise of h over β, θ from the rise's start) -------------------


def harmonic(t, h, b):
    """s, s′, s″ of the simple-harmonic rise."""
    k = math.pi / b
    return h / 2 * (1 - np.cos(k * t)), h / 2 * k * np.sin(k * t), h / 2 * k * k * np.cos(k * t)


def cycloidal(t, h, b):
    """s, s′, s″ of the cycloidal rise."""
    w = 2 * math.pi / b
    return h * (t / b - np.sin(w * t) / (2 * math.pi)), h / b * (1 - np.cos(w * t)), h / b * w * np.sin(w * t)


LAWS = {"harmonic": harmonic, "cycloidal": cycloidal}


def rise_return_spec(kind: str, law: str, lift: float, angle: float, **follower) -> CamSpec:
    """A rise and a return of the same law, lift and angle, with dwells taking up the rest."""
    dwell = (360.0 - 2 * angle) / 2
    return CamSpec.from_dict({
        "cam": {"base_radius": 40.0, "thickness": 10.0, "bore_diameter": 12.0},
        "follower": {"kind": kind, **follower},
        "motion": [{"kind": "rise", "angle": angle, "lift": lift, "law": law},
                   {"kind": "dwell", "angle": dwell},
                   {"kind": "return", "angle": angle, "lift": lift, "law": law},
                   {"kind": "dwell", "angle": dwell}],
    })


# ---- grids ------------------------------------------------------------------------------------
def test_parse_vary_ranges_lists_and_linked_fields():
    a = parse_vary("motion[1].lift,motion[3].lift=5:30:6")
    assert a.fields == ("motion[1].lift", "motion[3].lift")
    assert a.values == (5, 10, 15, 20, 25, 30) and all(isinstance(v, int) for v in a.values)
    b = parse_vary("motion[1].angle=60.0:90:4")
    assert b.values == pytest.approx((60.0, 70.0, 80.0, 90.0)) and all(isinstance(v, float) for v in b.values)
    c = parse_vary("motion[1].law=cycloidal, harmonic")
    assert c.values == ("cycloidal", "harmonic") and not c.numeric
    assert parse_vary("follower.roller_radius=4,6.5").values == (4, 6.5)
    assert parse_vary("cam.base_radius=30:40:1").values == (30,)


@pytest.mark.parametrize("text, words", [
    ("motion[1].lift", "FIELD=START:STOP:COUNT"),
    ("=1:2:3", "no field"),
    ("motion[1].lift=5:30:0", "COUNT must be ≥ 1"),
    ("motion[1].lift=5:30:2.5", "whole COUNT"),
    ("motion[1].lift=5,,6", "empty value"),
    ("motion[1].lift,motion[1].lift=5", "named twice"),
])
def test_parse_vary_refuses_bad_text(text, words):
    with pytest.raises(SpecError) as info:
        parse_vary(text)
    assert info.value.field == "--vary" and words in info.value.rule


@pytest.mark.parametrize("vary, balance, field, words", [
    (["motion[9].lift=5"], None, "--vary", "out of range"),
    (["motion.lift=5"], None, "--vary", "list of tables"),
    (["cam.radius=5"], None, "--vary", "unknown field"),
    (["gear.teeth=5"], None, "--vary", "no section"),
    (["motion[1].lift=5", "motion[1].lift=6"], None, "--vary", "varied twice"),
    (["motion[1].angle=100"], "motion[1].angle", "--balance", "not a dwell"),
    (["motion[1].angle=100"], "motion[2].lift", "--balance", "dwell's angle"),
    (["motion[2].angle=100"], "motion[2].angle", "--balance", "also varied"),
])
def test_grid_check_refuses_before_any_work(vary, balance, field, words):
    grid = Grid(tuple(parse_vary(v) for v in vary), balance)
    with pytest.raises(SpecError) as info:
        run_sweep(example_spec("default"), grid)
    assert info.value.field == field and words in info.value.rule


def test_grid_points_order_and_balance():
    grid = Grid((parse_vary("motion[1].angle,motion[3].angle=90:110:3"), parse_vary("motion[1].law=harmonic,poly345")),
                balance="motion[2].angle")
    pts = grid.points()
    assert [(p["motion[1].angle"], p["motion[1].law"]) for p in pts] == [
        (90, "harmonic"), (90, "poly345"), (100, "harmonic"), (100, "poly345"), (110, "harmonic"), (110, "poly345")]
    spec = grid.spec_at(example_spec("default"), pts[4])
    assert [m.angle for m in spec.motion] == [30.0, 110.0, 360 - 30 - 110 - 110 - 30, 110.0, 30.0]
    assert spec.motion[1].law == "harmonic" and spec.motion[3].law == "cycloidal"
    with pytest.raises(SpecError) as info:
        apply_changes(example_spec("default"), {"motion[1].angle": 150, "motion[3].angle": 150}, "motion[2].angle")
    assert info.value.field == "motion[2].angle"


def test_chunks_cover_every_item_once_in_order():
    for n in (0, 1, 7, 200):
        for w in (1, 2, 5):
            pieces = chunks(n, w)
            assert [i for r in pieces for i in r] == list(range(n))
            assert len(pieces) <= max(n, 0) and (n == 0 or len(pieces) >= min(n, w))


# ---- sweeps -----------------------------------------------------------------------------------
def test_sweep_rows_against_the_limacon():
    """A radial knife edge with harmonic rise and return over 180° each traces the limaçon
    r = R_b + h/2 (1 − cos θ): area π(a² + b²/2) − bore, a = R_b + h/2, b = h/2, largest pressure angle
    max atan(r′/r) — over a grid of R_b and h, every row against the closed form."""
    base = CamSpec.from_dict({
        "cam": {"base_radius": 30.0, "thickness": 8.0, "bore_diameter": 10.0},
        "follower": {"kind": "knife"},
        "motion": [{"kind": "rise", "angle": 180, "lift": 12.0, "law": "harmonic"},
                   {"kind": "return", "angle": 180, "lift": 12.0, "law": "harmonic"}],
        "pitch": {"segments": 360}})
    grid = Grid((parse_vary("cam.base_radius=25:35:3"), parse_vary("motion[0].lift,motion[1].lift=6,12")))
    table = run_sweep(base, grid)
    assert len(table) == 6 and [r["status"] for r in table.rows] == ["ok"] * 6
    t = np.linspace(0, np.pi, 400001)
    for row in table.rows:
        rb, h = row["cam.base_radius"], row["motion[0].lift"]
        a, b = rb + h / 2, h / 2
        assert row["base_radius"] == rb
        assert row["area"] == pytest.approx(math.pi * (a * a + b * b / 2) - math.pi * 5.0**2, rel=1e-9)
        assert row["volume"] == pytest.approx(row["area"] * 8.0, rel=1e-12)
        phi = np.degrees(np.max(np.arctan2(h / 2 * np.sin(t), rb + h / 2 * (1 - np.cos(t)))))
        assert row["pressure_angle_deg"] == pytest.approx(phi, abs=1e-6)
        assert row["check_pressure_angle"] == pytest.approx(phi, abs=1e-6)
        assert row["checks_passed"] is bool(phi <= 30.0)


def test_a_bad_point_is_a_row_and_the_others_go_on():
    """A lift the program cannot close (rise ≠ return) is a row naming the field; the rest are ok."""
    grid = Grid((parse_vary("motion[1].lift=10,20,30"),))
    table = run_sweep(example_spec("default"), grid)
    status = [r["status"] for r in table.rows]
    assert status == ["bad input", "ok", "bad input"]
    assert table.rows[0]["error"].startswith("motion[3].lift: the follower would go 10 below zero lift")
    assert table.rows[2]["error"].startswith("motion: program does not close")
    assert table.rows[1]["pressure_angle_deg"] > 0
    assert not table.ok


def test_progress_and_stop_in_this_process():
    grid = Grid((parse_vary("motion[1].lift,motion[3].lift=10:20:6"),))
    seen = []

    def progress(done, total):
        seen.append((done, total))
        return done < 2                       # stop after the second point

    table = run_sweep(example_spec("default"), grid, progress=progress)
    assert seen[:2] == [(1, 6), (2, 6)]
    assert [r["status"] for r in table.rows] == ["ok", "ok"] + ["cancelled"] * 4
    assert table.meta["cancelled"] is True


def test_serial_executor_contract():
    calls = []

    def fn(item, ctx):
        ctx.report(item)
        return item * 2

    ex = SerialExecutor()
    assert ex.run(fn, [1, 2, 3], on_progress=lambda i, x: calls.append((i, x))) == [2, 4, 6]
    assert calls == [(0, 1), (1, 2), (2, 3)]
    done = []
    out = ex.run(fn, [1, 2, 3], on_result=lambda i, r: done.append((i, r)), should_stop=lambda: len(done) >= 1)
    assert out == [2, NOT_RUN, NOT_RUN] and done == [(0, 2)]


# ---- sizing against closed forms --------------------------------------------------------------
def flat_cusp_radius(law: str, h: float, beta_deg: float) -> float:
    """The smallest cusp-free base radius of a translating flat face: max −(s + s″) over the rise
    and the return (the return is the rise mirrored: s(β − t), s″(β − t)), by a dense grid and
    scipy's bounded minimiser around its best sample."""
    b = math.radians(beta_deg)
    f = LAWS[law]

    def g(t):
        s, _, s2 = f(t, h, b)
        return s + s2

    t = np.linspace(0, b, 20001)
    k = int(np.argmin(g(t)))
    lo, hi = t[max(k - 1, 0)], t[min(k + 1, t.size - 1)]
    best = min(float(g(t[k])), float(minimize_scalar(g, bounds=(lo, hi), method="bounded",
                                                     options={"xatol": 1e-12}).fun))
    return -best


@pytest.mark.parametrize("law, h, beta", [("harmonic", 20.0, 60.0), ("harmonic", 10.0, 90.0),
                                          ("cycloidal", 20.0, 60.0), ("cycloidal", 30.0, 100.0)])
def test_flat_face_cusp_radius_closed_form(law, h, beta):
    """Translating flat face, sized on the cusp check only: R* = max −(s + s″); for the harmonic
    law h(π²/(2β²) − 1) exactly (70 mm for 20 mm over 60°)."""
    spec = rise_return_spec("flat", law, h, beta, face_width=200.0)
    expected = flat_cusp_radius(law, h, beta)
    if law == "harmonic":
        assert expected == pytest.approx(h * (math.pi**2 / (2 * math.radians(beta) ** 2) - 1), rel=1e-12)
    sz = smallest_base_radius(spec, SizingSettings(checks=("cusp",), tol=1e-3))
    assert sz.status == "ok" and sz.binding == ("cusp",)
    assert expected < sz.value <= expected + 1e-3 + 1e-9
    assert sz.below <= expected and sz.value - sz.below <= 1e-3 + 1e-9   # grid values, decimal
    assert sz.checks["cusp"].value > 0


def roller_pressure_radius(law: str, h: float, beta_deg: float, e: float, limit_deg: float) -> float:
    """The base radius at which the largest |pressure angle| of a translating roller reaches
    ``limit_deg``: tan φ = (s′ − e)/(√(R² − e²) + s) on the rise and (−s′ − e)/(…) on the return
    (the rise mirrored), maximised over θ by a dense grid and scipy's bounded minimiser, then
    brentq on R."""
    b = math.radians(beta_deg)
    f = LAWS[law]

    def peak(radius: float) -> float:
        s0 = math.sqrt(radius * radius - e * e)
        best = 0.0
        for sign in (1.0, -1.0):
            def phi(t):
                s, s1, _ = f(t, h, b)
                return -abs(np.arctan((sign * s1 - e) / (s0 + s)))

            t = np.linspace(0, b, 20001)
            k = int(np.argmin(phi(t)))
            lo, hi = t[max(k - 1, 0)], t[min(k + 1, t.size - 1)]
            res = minimize_scalar(phi, bounds=(lo, hi), method="bounded", options={"xatol": 1e-13})
            best = max(best, -float(phi(t[k])), -float(res.fun))
        return math.degrees(best)

    return brentq(lambda r: peak(r) - limit_deg, abs(e) + 1.0, 500.0, xtol=1e-10)


@pytest.mark.parametrize("law, h, beta, e", [("cycloidal", 20.0, 120.0, 0.0), ("harmonic", 20.0, 60.0, 0.0),
                                             ("cycloidal", 30.0, 90.0, 5.0), ("harmonic", 15.0, 100.0, -4.0)])
def test_roller_pressure_angle_radius_by_brentq(law, h, beta, e):
    """Translating roller sized on the pressure angle only (30°): the bisection's radius brackets
    the root brentq finds on the pressure angle written out, within the tolerance."""
    spec = rise_return_spec("roller", law, h, beta, roller_radius=2.0, offset=e)
    expected = roller_pressure_radius(law, h, beta, e, 30.0)
    sz = smallest_base_radius(spec, SizingSettings(checks=("pressure_angle",), tol=1e-3))
    assert sz.status == "ok" and sz.binding == ("pressure_angle",)
    assert expected - 1e-7 < sz.value <= expected + 1e-3 + 1e-7
    assert sz.below <= expected + 1e-7
    assert sz.checks["pressure_angle"].value <= 30.0


def test_sizing_sweep_rows_against_the_closed_form():
    """A sizing sweep over lift × angle of the harmonic flat face: every row's radius against
    h(π²/(2β²) − 1); the default tolerance 0.01 mm is in the table."""
    spec = rise_return_spec("flat", "harmonic", 20.0, 60.0, face_width=400.0)
    grid = Grid((parse_vary("motion[0].angle,motion[2].angle=60,75,90"),
                 parse_vary("motion[0].lift,motion[2].lift=10:30:3")), balance="motion[1].angle")
    table = run_sweep(spec, grid, sizing=SizingSettings(checks=("cusp",)))
    assert table.meta["kind"] == "sizing" and table.meta["tolerance"] == 0.01
    for row in table.rows:
        b, h = math.radians(row["motion[0].angle"]), row["motion[0].lift"]
        expected = h * (math.pi**2 / (2 * b * b) - 1)
        assert row["status"] == "ok" and row["tolerance"] == 0.01
        assert expected < row["min_base_radius"] <= expected + 0.01 + 1e-9
        assert row["failing_radius"] <= expected


def test_no_radius_when_a_check_does_not_depend_on_it():
    """Separation of the default roller made impossible (no spring, a heavy follower at high
    speed): no base radius passes; the row says which check and where."""
    spec = example_spec("default").replace(**{"follower.spring_rate": 0.0, "follower.preload": 0.0,
                                               "follower.mass": 5.0, "cam.speed_rpm": 3000.0})
    sz = smallest_base_radius(spec, SizingSettings(max_doublings=3))
    assert sz.status == "no radius" and sz.value is None
    assert "separation" in sz.reason and "no R_b up to 320" in sz.reason


def test_sizing_refuses_the_sized_field_on_an_axis():
    grid = Grid((parse_vary("cam.base_radius=30,40"),))
    with pytest.raises(SpecError) as info:
        run_sweep(example_spec("default"), grid, sizing=SizingSettings())
    assert "what the study sets itself" in info.value.rule


# ---- files ------------------------------------------------------------------------------------
def test_csv_and_parquet_hold_the_same_table(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    from cam_workbench.exporters.study_table import csv_text, parquet_bytes

    grid = Grid((parse_vary("motion[1].lift=10,20"), parse_vary("motion[1].law=harmonic,poly345")))
    table = run_sweep(example_spec("default"), grid)       # the lift of 10 cannot close: bad rows
    text = csv_text(table)
    rows = list(csv.DictReader(io.StringIO(text)))
    assert list(rows[0]) == table.columns and len(rows) == 4
    path = tmp_path / "t.parquet"
    path.write_bytes(parquet_bytes(table))
    pt = pq.read_table(path)
    assert pt.column_names == table.columns
    for name in table.columns:
        got = pt.column(name).to_pylist()
        want = table.column(name)
        assert got == want, name
        # the CSV cell is the value written exactly (floats by repr: read back bit for bit)
        for cell, v in zip((r[name] for r in rows), want):
            if isinstance(v, bool):
                assert cell == ("true" if v else "false")
            elif isinstance(v, float):
                assert float(cell) == v
            elif v is None:
                assert cell == ""
            else:
                assert cell == str(v)
    import json

    meta = json.loads(pt.schema.metadata[b"cam_workbench"])
    assert meta["kind"] == "sweep" and meta["points"] == 4


def test_sizing_chart_draws_one_panel_per_law():
    from cam_workbench.exporters.study_plots import chart_layout, sizing_chart

    spec = example_spec("default")
    grid = Grid((parse_vary("motion[1].angle,motion[3].angle=80:120:3"),
                 parse_vary("motion[1].lift,motion[3].lift=15,25"),
                 parse_vary("motion[1].law,motion[3].law=cycloidal,harmonic")), balance="motion[2].angle")
    table = run_sweep(spec, grid, sizing=SizingSettings(checks=("pressure_angle",), tol=0.05))
    cols = ["motion[1].angle", "motion[1].lift", "motion[1].law"]
    assert chart_layout(table, cols) == ("motion[1].angle", "motion[1].lift", ["motion[1].law"])
    fig = sizing_chart(table, cols)
    axes = [ax for ax in fig.axes if ax.get_visible()]
    assert [ax.get_title() for ax in axes] == ["law = cycloidal", "law = harmonic"]
    for ax, law in zip(axes, ("cycloidal", "harmonic")):
        for line, lift in zip(ax.get_lines(), (15, 25)):
            want = [r["min_base_radius"] for r in table.rows
                    if r["motion[1].law"] == law and r["motion[1].lift"] == lift]
            assert list(line.get_ydata()) == want
            assert list(line.get_xdata()) == [80, 100, 120]
    assert "pressure_angle ≤ 30°" in fig._suptitle.get_text()
    import matplotlib.pyplot as plt

    plt.close(fig)

"""Every built-in example's drawing, with every ``drawing.curves`` value, drawn by a reader that is
not ezdxf: LibreCAD 2.2 (Debian's ``librecad``, ``librecad dxf2pdf``), read back from its PDF
(tests/librecad.py) and held against the exact curves.

* Each file is drawn the way ``build`` and ``dxf`` draw it (:func:`cam_workbench.pipeline.drawing_stage`)
  and printed twice, from copies in which only colours, the sheet and (the first) the texts
  change — one test checks that colours change nothing LibreCAD draws:
  - the curves: each curve layer's entities get a colour of their own (true colour), the texts and
    dimensions are left out, and the sheet is made so large that one device unit of the PDF is
    1/20 of ``drawing.chord_tolerance`` (1/6 with arcs, which LibreCAD strokes finer the larger
    they are drawn, taking seconds);
  - the texts: each title-block TEXT gets a colour of its own, on the file's own sheet.
* The page is registered to the drawing by its concentric circles (base, prime, bore, rim; the end
  view's outer, groove-bottom and bore circles), whose centres and radii the DXF states; a
  parallel indexer's by the circles it draws at input angle 0, computed here from the design: the
  bore, the turret's pitch circle and every roller (equal radii: matched by where they are).
* Each curve layer (profile, pitch curve, groove wall, second cam, developed walls): every point
  LibreCAD drew lies within the layer's stated error (report.json ``drawing.max_error_by_layer``,
  the cylindrical walls' ``developed_fit_error``) plus the page's resolution of the exact curve,
  and every point of the exact curve (dense samples) lies within that plus the sag of LibreCAD's
  own chords of the drawn curve — so a dropped or partly dropped curve fails; the stated error is
  within ``drawing.chord_tolerance``.  ``curves = "spline"`` writes the exact NURBS (degree 9
  rational, or 5): LibreCAD 2.2 draws nothing of it — the reason it is not the default.
* A parallel indexer's plates (CAM_0, CAM_1, …: an exact dwell ARC and the body's own cubic flank
  SPLINEs, for ``curves`` "cubic" and "spline" alike, which LibreCAD draws): held against the exact
  offset Q(τ) of the roller locus over the whole profile, the stated error the larger of
  report.json ``drawing.drawn_flank_error`` and ``drawing.flank_fit_error`` (the arcs are exact).
  ``curves`` "arcs" and "polyline" its drawing refuses: SpecError naming ``drawing.curves``.
* A barrel indexer's developed views (TRACE_TOP_P, TRACE_TOP_M, TRACE_ROOT_P, TRACE_ROOT_M: the flank
  traces as cubic SPLINEs in τ, ``curves`` "cubic" only — the others it refuses, naming
  ``drawing.curves``, before anything is written): held against the exact traces of
  tests/test_dxf_spatial_indexer.py's independent construction (``exact_trace``) over each drawn
  piece's τ range, in the developed coordinates X = x0 + ρ·(φ − φ_m) (the turn that puts the piece
  in its window), Y = y0 + z, φ_m recomputed here (roller 0's side −1 contact at mid-index), the
  stated error report.json ``drawing.drawn_trace_error``.  Its exact circles, arcs and lines (and a
  globoidal indexer's, which draws no trace and takes every ``curves`` value) are registration
  marks or unchecked here: no curve layer of theirs is compared.
* Every title-block text LibreCAD drew lies inside its cell (the rectangle of the title block's
  lines round its insertion point).
"""
from __future__ import annotations

import subprocess

import numpy as np
import pytest

from cam_workbench.generators import design_cam
from cam_workbench.generators.errors import SpecError
from cam_workbench.generators.spec.examples import EXAMPLES, example_spec

from .librecad import (Registration, _drawn_circle, distance_to_segments, dxf2pdf, enlarge_paper, read_pdf_paths,
                       register, requires_librecad, title_cells)

ezdxf = pytest.importorskip("ezdxf")
pytestmark = requires_librecad

CURVES = ("cubic", "spline", "arcs", "polyline")
#: layers whose CIRCLEs are concentric registration marks (plate: about the cam axis; cylindrical:
#: the end view's)
MARK_LAYERS = ("BASE_CIRCLE", "PRIME_CIRCLE", "BORE", "OUTLINE", "GROOVE_BOTTOM")
CURVE_LAYERS = ("PROFILE", "PITCH", "PROFILE_OUTER", "PROFILE_2", "PITCH_2", "WALL_LOWER", "WALL_UPPER",
                "CAM_0", "CAM_1", "CAM_2", "TRACE_TOP_P", "TRACE_TOP_M", "TRACE_ROOT_P", "TRACE_ROOT_M")
#: the ``drawing.curves`` values a parallel indexer's drawing draws (its flanks are the body's own
#: cubic B-splines); the others it refuses, naming the field
INDEXER_CURVES = ("cubic", "spline")
#: the spatial indexers' bodies; the barrel's drawing draws its flank traces as cubic SPLINEs and
#: refuses every other ``drawing.curves`` value, the globoid's draws no trace (any value)
SPATIAL_BODIES = ("barrel_indexer", "globoidal_indexer")
BARREL_CURVES = ("cubic",)
TRACE_LAYERS = ("TRACE_TOP_P", "TRACE_TOP_M", "TRACE_ROOT_P", "TRACE_ROOT_M")


def _is_indexer(spec) -> bool:
    return spec.cam.body == "parallel_indexer"


def _is_spatial(spec) -> bool:
    return spec.cam.body in SPATIAL_BODIES


def _refused(spec, curves: str) -> bool:
    """Whether the drawing refuses ``drawing.curves = curves`` (SpecError naming the field)."""
    if _is_indexer(spec):
        return curves not in INDEXER_CURVES
    return spec.cam.body == "barrel_indexer" and curves not in BARREL_CURVES


def _librecad_version() -> str:
    out = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "librecad"], capture_output=True, text=True)
    return out.stdout.strip()


def _tag(i: int) -> tuple[int, int, int]:
    """A true colour no layer has (ACI colours have blue 0, 128, 192 or 255)."""
    return (i // 200, 20 + i % 200, 77)


def _drawing(name: str, curves: str, folder):
    """(design, report.json's drawing section, the DXF as build writes it)."""
    from cam_workbench.pipeline import drawing_stage

    design = design_cam(example_spec(name).replace(**{"drawing.curves": curves}))
    summary = design.summary()
    doc, info = drawing_stage(design, summary)
    path = folder / f"{name}_{curves}.dxf"
    doc.saveas(str(path))
    return design, summary["drawing"], info, path


def _render_tagged(path, folder, what: str, paper: float = 1.0, circles=None):
    """LibreCAD's drawing of a colour-tagged copy of ``path``: (page, registration, {key: tag}),
    registered by ``circles`` [(centre, radius)] (:func:`_register_by_position`), or when None by the
    concentric CIRCLEs of the MARK_LAYERS the DXF states.

    ``what`` = "curves": each curve layer's entities get a colour, the texts and dimensions are left
    out (LibreCAD strokes a text's glyphs finer the larger the sheet: on a sheet ``paper`` times the
    drawing they would be millions of segments); "texts": each title-block TEXT gets a colour,
    keyed by its handle, on the sheet the file has."""
    doc = ezdxf.readfile(path)
    msp = doc.modelspace()
    tags = {}
    if what == "curves":
        for e in list(msp.query("TEXT MTEXT DIMENSION")):
            msp.delete_entity(e)
        for layer in CURVE_LAYERS:
            ents = msp.query(f'*[layer=="{layer}"]')
            if len(ents):
                tags[layer] = _tag(len(tags))
                for e in ents:
                    e.rgb = tags[layer]
    else:
        for t in msp.query('TEXT[layer=="TITLE"]'):
            tags[t.dxf.handle] = _tag(len(tags))
            t.rgb = tags[t.dxf.handle]
    marks = {}
    for c in msp.query("CIRCLE"):
        if c.dxf.layer in MARK_LAYERS:
            marks.setdefault(round(c.dxf.radius, 9), complex(c.dxf.center.x, c.dxf.center.y))
    if paper != 1.0:
        enlarge_paper(doc, paper)
    tagged = folder / f"{path.stem}_{what}.dxf"
    doc.saveas(tagged)
    pdf = tagged.with_suffix(".pdf")
    dxf2pdf(tagged, pdf)
    page = read_pdf_paths(pdf)
    if circles is not None:
        return page, _register_by_position(page, circles), tags
    return page, register(page, [(c, r) for r, c in marks.items()]), tags


def _register_by_position(page, circles: list[tuple[complex, float]]) -> Registration:
    """The page ← drawing map from known circles some of which share a radius (an indexer's
    rollers): :func:`register` by the circles whose radius no other known circle has, then
    every known circle matched to the drawn circle of its radius nearest where that map puts it and
    the map fitted again to all of them as :func:`register` fits it (scale: least-squares ratio of
    the radii; offset: mean of the centres'), its residual the largest misfit of any."""
    radii = [round(r, 9) for _, r in circles]
    unique = [(c, r) for c, r in circles if radii.count(round(r, 9)) == 1]
    first = register(page, unique)
    drawn = [c for c in map(_drawn_circle, page.strokes) if c is not None]
    pairs, used = [], set()
    for kc, kr in circles:
        at, size = first.scale * kc + first.offset, first.scale * kr
        near = [(abs(dc - at), i) for i, (dc, dr) in enumerate(drawn)
                if abs(dr - size) <= 1e-5 * size + 2 * page.unit]
        assert near, f"the known circle ({kc}, {kr}) is not drawn"
        miss, i = min(near)
        assert miss <= 1e-5 * size + 2 * page.unit + 2 * first.residual * first.scale and i not in used, \
            ((kc, kr), miss / first.scale)
        used.add(i)
        pairs.append(((kc, kr), drawn[i]))
    known_r = np.array([k[1] for k, _ in pairs])
    drawn_r = np.array([d[1] for _, d in pairs])
    scale = float(np.dot(known_r, drawn_r) / np.dot(known_r, known_r))
    offset = complex(np.mean([d[0] - scale * k[0] for k, d in pairs]))
    residual = max(max(abs(d[0] - (scale * k[0] + offset)), abs(d[1] - scale * k[1])) for k, d in pairs) / scale
    return Registration(scale, offset, residual, page.unit / scale)


def _known_circles(design) -> list[tuple[complex, float]] | None:
    """The circles a parallel indexer's drawing draws at input angle 0, from the design: the bore
    about O, the turret's pitch circle R_p about P = (C, 0) and each plane's N rollers of radius
    ``follower.roller_radius`` where the turret holds them at θ = 0; None for the other bodies
    (registered by the concentric circles their DXF states)."""
    if not _is_indexer(design.spec):
        return None
    from cam_workbench.generators.bodies.indexing.parallel import roller_state

    ix = design.geometry.indexer
    rr = float(design.spec.follower.roller_radius)
    assert rr == float(ix.roller_radius)
    circles = [(complex(float(ix.centre_distance), 0.0), float(ix.pitch_radius))]
    if design.spec.cam.bore_diameter > 0:
        circles.append((0j, 0.5 * float(design.spec.cam.bore_diameter)))
    n = int(ix.stations)
    for k in range(int(ix.cams)):
        p, _, _ = roller_state(ix, k, np.arange(n), np.zeros(n))
        circles += [(complex(x, y), rr) for x, y in p.tolist()]
    return circles


def _paper(design, resolution: float) -> float:
    """The sheet, in drawing extents, on which one device unit (0.06 pt: Qt's 1200 dpi) is about
    ``resolution`` drawing units: ``dxf2pdf -a`` scales the drawing by about the sheet's size."""
    pt_per_unit = 72.0 / 25.4 if design.spec.units == "mm" else 72.0
    return 0.06 / (pt_per_unit * resolution)


def _strokes(page, reg, tag):
    return [reg.to_drawing(s.points) for s in page.strokes if tuple(round(c * 255) for c in s.colour) == tag]


def _exact_curves(design, section=None, info=None) -> dict[str, list[np.ndarray]]:
    """Dense points of the exact curves of each layer (complex): the NURBS of a plate drawing
    (the exact rational offsets and PH curves, tests/test_dxf.py holds them against the closed
    forms), the developed walls' exact points of a cylindrical one, a barrel indexer's exact flank
    traces in its developed views (:func:`_barrel_exact_traces`; a globoid's: none)."""
    from cam_workbench.generators.bodies.cylindrical import CylindricalDesign

    if _is_spatial(design.spec):
        return _barrel_exact_traces(design, section, info) if design.spec.cam.body == "barrel_indexer" else {}
    if _is_indexer(design.spec):
        return _indexer_exact_curves(design)
    if isinstance(design, CylindricalDesign):
        lay, prog = design.layout, design.program
        out = {}
        for layer, rho, side in (("WALL_LOWER", lay.outer_radius, -1), ("WALL_UPPER", lay.outer_radius, 1),
                                 ("PITCH", lay.pitch_radius, 0)):
            pieces = []
            for seg in range(len(prog.starts)):
                th = np.linspace(prog.boundaries[seg], prog.boundaries[seg + 1], 20001)
                p = design.developed_points(rho, side, th, np.full(th.size, seg))
                pieces.append(p[:, 0] + 1j * p[:, 1])
            out[layer] = pieces
        return out
    curves = {"PROFILE": [design.profile], "PITCH": [design.pitch_nurbs]}
    if design.body is not None:
        from cam_workbench.generators.bodies import Curve

        roles = {"groove_outer": "PROFILE_OUTER", "profile_2": "PROFILE_2"}
        for loop in design.body.loops():
            if loop.role in roles:
                curves.setdefault(roles[loop.role], []).extend(p.nurbs for p in loop.pieces if isinstance(p, Curve))
        for layer, c in design.body.extra.get("drawing_curves", {}).items():
            curves.setdefault(layer, []).append(c)
    out = {}
    for layer, cs in curves.items():
        pts = [c.sample(400)[1] for c in cs]
        out[layer] = [p[:, 0] + 1j * p[:, 1] for p in pts]
    return out


def _indexer_exact_curves(design) -> dict[str, list[np.ndarray]]:
    """Each plate's exact profile (layer CAM_k): the offset Q(τ) of the roller locus, dense over
    the incoming flank, the dwell (where Q is the circle r_d − r_r about O) and the outgoing
    flank, from tip X' round to X' (:func:`~cam_workbench.generators.bodies.indexing.parallel_body.offset_point`)."""
    from cam_workbench.generators.bodies.indexing.parallel import TWO_PI
    from cam_workbench.generators.bodies.indexing.parallel_body import offset_point

    ix = design.geometry.indexer
    ts, beta = float(ix.index_start), float(ix.index_angle)
    out = {}
    for k, cam in enumerate(design.geometry.cams):
        ends = (float(cam.tip_tau[0]), ts - TWO_PI + beta, ts, float(cam.tip_tau[1]))
        pieces = []
        for lo, hi in zip(ends[:-1], ends[1:]):
            q, _ = offset_point(ix, k, np.linspace(lo, hi, 40001))
            pieces.append(q[:, 0] + 1j * q[:, 1])
        dwell = np.abs(pieces[1])
        assert np.ptp(dwell) < 1e-9 and abs(dwell[0] - (cam.dwell_radius - ix.roller_radius)) < 1e-9
        out[f"CAM_{k}"] = pieces
    return out


#: a barrel trace's exact samples: at most this far apart along τ [rad] (their chords' sag is added
#: to the margins: :func:`_sample_sag`)
TRACE_STEP = 2e-4


def _barrel_exact_traces(design, section, info) -> dict[str, list[np.ndarray]]:
    """A barrel indexer's exact flank traces (layers TRACE_TOP_P, …) in the drawing: over each drawn
    piece's τ range (the pieces are cut at the law's ends and the windows' seams), the exact trace
    points of tests/test_dxf_spatial_indexer.py (``exact_trace``: the conventions recomputed, the
    contact found by bisection) at X = x0 + ρ·(φ − φ_m − 2πk), Y = y0 + z, φ continuous along the
    piece and k the turn that puts the piece's middle in the window |X − x0| ≤ πρ; φ_m (roller 0's
    side −1 contact at mid-index, mid-roller) recomputed here and held to report.json's; (x0, y0)
    report.json ``drawing.view_origins``."""
    from .test_dxf_spatial_indexer import contact, exact_trace

    ix = design.geometry.indexer
    q = contact(ix, -1, np.array([ix.index_start + ix.index_angle / 2]),
                np.array([(ix.roller_start + ix.roller_end) / 2]))
    phi_m = float(np.arctan2(q[0, 1], q[0, 0]))
    assert abs(np.degrees(phi_m) - section["phi_mid_deg"]) < 1e-6, (np.degrees(phi_m), section["phi_mid_deg"])
    views = {"TOP": ("developed_top", float(ix.outer_radius)), "ROOT": ("developed_root", float(ix.root_radius))}
    out: dict[str, list[np.ndarray]] = {}
    for tr in info.drawn.traces:
        _, where, sign = tr.layer.split("_")
        view, rho = views[where]
        assert tr.radius == rho and tr.side == {"P": 1, "M": -1}[sign], tr
        x0, y0 = section["view_origins"][view]
        lo, hi = tr.tau_range
        tau = np.linspace(lo, hi, max(3, int(np.ceil((hi - lo) / TRACE_STEP)) + 1))
        phi, z = exact_trace(ix, tr.side, rho, tau)
        x = rho * (np.unwrap(phi) - phi_m)
        mid = x[x.size // 2]
        x = x - 2 * np.pi * rho * np.round(mid / (2 * np.pi * rho))
        out.setdefault(tr.layer, []).append((x0 + x) + 1j * (y0 + z))
    assert set(out) == set(TRACE_LAYERS), sorted(out)
    assert sum(map(len, out.values())) == section["splines"]     # every SPLINE the file has is a piece
    return out


def _sample_sag(pieces: list[np.ndarray]) -> float:
    """The exact samples' own chords' sag: largest curvature × longest step² / 8."""
    step = max(float(np.max(np.abs(np.diff(p)))) for p in pieces)
    return _curvature_bound(pieces) * step**2 / 8


def _stated_errors(section, info) -> dict[str, float]:
    if section.get("kind") in ("barrel", "globoidal"):
        # a spatial indexer: the barrel's flank traces, cubic SPLINEs within their measured error
        err = (section["drawn_trace_error"] or {}).get("value")
        return {layer: err for layer in TRACE_LAYERS} if err is not None else {}
    if "drawn_flank_error" in section:
        # an indexer's plates: exact dwell arcs, the flanks the body's B-splines as they are
        err = max(section["drawn_flank_error"]["value"], section["flank_fit_error"]["value"])
        return {layer: err for layer in section["layers"] if layer.startswith("CAM_")}
    if "developed_fit_error" in section:
        errs: dict[str, float] = {}
        for d in info.drawn:
            errs[d.curve.layer] = max(errs.get(d.curve.layer, 0.0), d.error)
        return errs
    return section["max_error_by_layer"]


def _curvature_bound(pieces: list[np.ndarray]) -> float:
    """Largest curvature of the exact curves (circle through three consecutive dense samples)."""
    k = 0.0
    for z in pieces:
        a, b, c = z[:-2], z[1:-1], z[2:]
        cross = np.abs(((b - a) * np.conj(c - a)).imag)
        with np.errstate(divide="ignore", invalid="ignore"):
            kk = 2 * cross / (np.abs(b - a) * np.abs(c - b) * np.abs(c - a))
        k = max(k, float(np.nanmax(kk)))
    return k


CASES = [(n, c) for n in EXAMPLES for c in CURVES]


@pytest.mark.parametrize("name,curves", CASES, ids=[f"{n}-{c}" for n, c in CASES])
def test_librecad_draws_the_curves_within_the_stated_error(name, curves, tmp_path, artifacts):
    spec = example_spec(name)
    if _refused(spec, curves):
        # refused, naming the field, before anything is drawn
        with pytest.raises(SpecError) as refusal:
            _drawing(name, curves, tmp_path)
        assert refusal.value.field == "drawing.curves", refusal.value
        if _is_indexer(spec):
            assert f'"{curves}" is not available for a parallel indexer' in refusal.value.rule, refusal.value
            assert all(f'"{c}"' in refusal.value.rule for c in INDEXER_CURVES), refusal.value
        assert not list(tmp_path.glob("*.dxf"))
        return
    design, section, info, path = _drawing(name, curves, tmp_path)
    circles = _known_circles(design)
    if _is_spatial(spec) and spec.cam.body != "barrel_indexer":
        # a globoid: exact circles, arcs and lines only, whatever ``curves`` says — no trace, no
        # SPLINE, nothing to hold against an exact curve; its title block below
        assert section["kind"] == "globoidal" and section["curves"] is None and section["splines"] == 0, section
        assert not ezdxf.readfile(path).modelspace().query("SPLINE")
        _check_title_block(path, tmp_path, circles)
        return
    tol = design.spec.drawing.chord_tolerance
    # LibreCAD strokes an ARC finer the larger it is drawn: arcs on a sheet resolving tol/6, the
    # rest tol/20 (a few seconds each)
    goal = tol / 6 if curves == "arcs" else tol / 20
    page, reg, layer_tags = _render_tagged(path, tmp_path, "curves", _paper(design, goal), circles)
    res = reg.resolution
    assert res < 1.5 * goal, (res, goal)           # the page resolves the tolerance
    exact = _exact_curves(design, section, info)
    stated = _stated_errors(section, info)
    assert set(exact) <= set(layer_tags)
    if _is_spatial(design.spec):                     # the barrel: its four trace layers, all compared
        assert set(exact) == set(TRACE_LAYERS) == set(stated), (sorted(exact), sorted(stated))
    # (an indexer's "spline" is the body's cubic B-splines, as its "cubic": LibreCAD draws them)
    dropped_by_librecad = curves == "spline" and not hasattr(design, "layout") and not _is_indexer(design.spec)
    for layer, pieces in exact.items():
        drawn = _strokes(page, reg, layer_tags[layer])
        if dropped_by_librecad:
            # the exact NURBS (degree 9 rational, or degree 5): LibreCAD 2.2 draws none of it
            assert _librecad_version().startswith("2.2") and drawn == [], (layer, len(drawn))
            continue
        assert drawn, f"{layer}: LibreCAD drew nothing"
        err = stated[layer]
        assert err <= tol, (layer, err, tol)
        pts = np.concatenate(drawn)
        size = max(float(np.max(np.abs(p))) for p in pieces)
        dense = 1e-8 * size                          # the exact samples' own chords
        if _is_spatial(design.spec):                 # (a barrel's traces: sampled less densely)
            dense = max(dense, _sample_sag(pieces))
        # every drawn point on the exact curve, within the stated error
        to_exact = float(np.max(distance_to_segments(pts, pieces)))
        assert to_exact <= err + res + dense, (layer, to_exact, err, res)
        # every point of the exact curve drawn, within the stated error and LibreCAD's chords' sag
        longest = max(float(np.max(np.abs(np.diff(d)))) for d in drawn if d.size > 1)
        sag = _curvature_bound(pieces) * longest**2 / 8
        samples = np.concatenate(pieces)
        to_drawn = float(np.max(distance_to_segments(samples, drawn)))
        assert to_drawn <= err + res + sag + dense, (layer, to_drawn, err, res, sag)
    page = _check_title_block(path, tmp_path, circles)
    if name in ("default", "cylindrical", "parallel_indexer"):
        _save_png(page, artifacts / f"librecad_{name}_{curves}.png")


def _check_title_block(path, folder, circles):
    """The title block's texts inside their cells, as LibreCAD draws them; LibreCAD's page."""
    page, reg, text_tags = _render_tagged(path, folder, "texts", circles=circles)
    res = reg.resolution
    for handle, (text, box) in title_cells(ezdxf.readfile(path)).items():
        drawn = _strokes(page, reg, text_tags[handle])
        if not drawn:
            assert not text.strip(" "), text
            continue
        pts = np.concatenate(drawn)
        x0, y0, x1, y1 = box
        assert (x0 - res <= pts.real.min() and pts.real.max() <= x1 + res
                and y0 - res <= pts.imag.min() and pts.imag.max() <= y1 + res), (text, box, pts.real.min(),
                                                                                pts.real.max())
    return page


def _save_png(page, target) -> None:
    """What LibreCAD drew, for a person to look at (test-artifacts/)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from matplotlib.collections import LineCollection

    fig = plt.figure(figsize=(16, 11))
    ax = fig.add_axes([0, 0, 1, 1])
    ax.set_aspect("equal")
    ax.axis("off")
    ax.add_collection(LineCollection([np.column_stack([s.points.real, s.points.imag]) for s in page.strokes],
                                     colors=[s.colour for s in page.strokes], linewidths=0.4))
    ax.autoscale()
    fig.savefig(target, dpi=110)
    plt.close(fig)


def test_the_colour_tags_change_nothing_librecad_draws(tmp_path):
    """The same file with and without the tests' colours: LibreCAD draws the same strokes."""
    _, _, _, path = _drawing("conjugate", "cubic", tmp_path)
    pages = []
    for tagged in (False, True):
        doc = ezdxf.readfile(path)
        if tagged:
            for i, e in enumerate(doc.modelspace()):
                e.rgb = _tag(i)
        enlarge_paper(doc, 10.0)
        p = tmp_path / f"t{int(tagged)}.dxf"
        doc.saveas(p)
        dxf2pdf(p, p.with_suffix(".pdf"))
        pages.append(read_pdf_paths(p.with_suffix(".pdf")))
    a, b = ([s.points for s in pg.strokes] for pg in pages)
    assert len(a) == len(b) > 1000
    assert all(np.array_equal(x, y) for x, y in zip(a, b))


def test_the_exact_spline_of_the_default_cam_is_what_librecad_drops(tmp_path):
    """The user's report, reproduced: with ``curves = "spline"`` the default cam's drawing shows
    circles, centre lines and the title block in LibreCAD and no cam; the default draws it."""
    counts = {}
    for curves in ("spline", "cubic"):
        _, _, _, path = _drawing("default", curves, tmp_path)
        page, reg, layer_tags = _render_tagged(path, tmp_path, "curves")
        counts[curves] = {layer: len(_strokes(page, reg, layer_tags[layer])) for layer in ("PROFILE", "PITCH")}
    assert counts["spline"] == {"PROFILE": 0, "PITCH": 0}
    assert min(counts["cubic"].values()) > 100

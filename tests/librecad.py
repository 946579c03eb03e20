"""Drawing a DXF with LibreCAD (Debian package ``librecad``, 2.2) and reading back what it drew.

``librecad dxf2pdf`` prints a DXF headless (Qt's ``offscreen`` platform) to a one-page PDF, the
drawing fitted to the sheet (the paper-space layout's limits).  Qt writes every drawn entity as a
stroked vector path in the page's content stream — LibreCAD draws its text with its own stroke
fonts, so text is lines too — and nothing else: ``m``/``l``/``c``/``h`` with ``SCN`` (stroke
colour), ``w`` and ``d`` before each entity, under one ``cm`` (device units of 1/1200 in → points).
:func:`read_pdf_paths` interprets that stream (no PDF library: Flate-decoded content, the few
operators Qt emits) into polylines in page points, Bézier segments flattened finely, each with its
on-curve points and its stroke colour.

:func:`register` maps page points back to drawing units by known circles (Qt draws a CIRCLE as four
Bézier quarters from points on it), :func:`enlarge_paper` makes the sheet — and so the drawing on
the page — larger, so a device unit is a small part of a drawing unit; :func:`distance_to_segments`
and :func:`title_cells` measure what was drawn.  Entities LibreCAD cannot draw (SPLINEs of degree
> 3; it ignores a SPLINE's weights) leave nothing in the PDF.
"""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import zlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

LIBRECAD = shutil.which("librecad")
requires_librecad = pytest.mark.skipif(
    LIBRECAD is None, reason="LibreCAD is not installed (Debian package librecad; `make test` installs it when "
                             "run as root)")

#: Bézier segments are flattened into this many chords (sag ≪ 1e-6 of a segment's size)
BEZIER_CHORDS = 64


@dataclass(frozen=True)
class Stroke:
    """One stroked subpath as LibreCAD drew it: its points (complex, page points; Bézier segments
    flattened), its on-curve points (the ends of its lines and Bézier segments), its style."""

    points: np.ndarray
    nodes: np.ndarray
    colour: tuple[float, float, float]
    width: float
    dashed: bool


@dataclass(frozen=True)
class Page:
    """What a PDF page holds: its strokes and the size of one device unit [points] (the coordinates
    of its content stream are whole device units, so a drawn point is rounded by up to half one)."""

    strokes: list[Stroke]
    unit: float


def dxf2pdf(dxf: Path, pdf: Path) -> subprocess.CompletedProcess:
    """Print ``dxf`` to ``pdf`` with ``librecad dxf2pdf -a`` (fitted to the sheet, headless).

    LibreCAD 2.2's ``-o`` takes no value (its PDF is named after the DXF, in ``-t``'s folder): it
    prints into a folder of its own, then the PDF is moved to ``pdf``.  LibreCAD keeps settings
    under $HOME and needs $XDG_RUNTIME_DIR: both point into that folder, so the run leaves
    nothing elsewhere."""
    work = pdf.parent / f".librecad-{pdf.stem}"
    runtime = work / "run"
    runtime.mkdir(parents=True, exist_ok=True)
    runtime.chmod(0o700)
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen", HOME=str(work), XDG_RUNTIME_DIR=str(runtime),
               XDG_CONFIG_HOME=str(work / "config"))
    res = subprocess.run([LIBRECAD, "dxf2pdf", "-a", "-t", str(work), str(dxf)], capture_output=True, text=True,
                         env=env, timeout=600)
    made = work / (Path(dxf).stem + ".pdf")
    if res.returncode != 0 or not made.exists():
        raise RuntimeError(f"librecad dxf2pdf failed ({res.returncode}): {res.stdout[-800:]} {res.stderr[-800:]}")
    made.replace(pdf)
    shutil.rmtree(work)
    return res


_TOKEN = re.compile(rb"\[[^\]]*\]|[-+]?(?:\d+\.?\d*|\.\d+)|/[^\s/\[\]()<>]+|[A-Za-z*'\"]+")


def _content_streams(data: bytes) -> list[bytes]:
    out = []
    for m in re.finditer(rb"<<(?:(?!>>).)*?>>\s*stream\r?\n", data, re.S):
        start = m.end()
        end = data.index(b"endstream", start)
        raw = data[start:end]
        if b"/FlateDecode" in m.group(0):
            raw = zlib.decompressobj().decompress(raw)
        out.append(raw)
    return out


def _bezier(p0: complex, p1: complex, p2: complex, p3: complex) -> np.ndarray:
    t = np.linspace(0.0, 1.0, BEZIER_CHORDS + 1)[1:]
    s = 1 - t
    return s**3 * p0 + 3 * s * s * t * p1 + 3 * s * t * t * p2 + t**3 * p3


def read_pdf_paths(pdf: Path) -> Page:
    """Every stroked subpath of the PDF's pages, in page points (y up), with its style.

    Qt writes one operator per line for path construction (``x y m``, ``x y l``, ``… c``): those
    lines take a fast path; every other line is read token by token.  Points are kept in the
    coordinates they are written in and mapped by the CTM when the path is stroked (Qt sets the
    CTM once, before any path)."""
    strokes: list[Stroke] = []
    unit = np.inf
    for stream in _content_streams(Path(pdf).read_bytes()):
        ctm = np.eye(3)
        stack: list[tuple[np.ndarray, tuple, float, bool]] = []
        colour: tuple = (0.0, 0.0, 0.0)
        width, dashed = 1.0, False
        subpaths: list[tuple[list[complex], list[complex]]] = []
        cur: list[complex] = []
        nodes: list[complex] = []

        def close_subpath() -> None:
            if len(cur) > 1:
                subpaths.append((cur, nodes))

        def mapped(z: list[complex]) -> np.ndarray:
            a = np.asarray(z)
            return (ctm[0, 0] * a.real + ctm[1, 0] * a.imag + ctm[2, 0]) + 1j * (
                ctm[0, 1] * a.real + ctm[1, 1] * a.imag + ctm[2, 1])

        for line in stream.splitlines():
            if line.endswith(b" l") or line.endswith(b" m"):
                x, y, op = line.split()
                if op == b"m":
                    close_subpath()
                    cur, nodes = [], []
                cur.append(complex(float(x), float(y)))
                nodes.append(cur[-1])
                continue
            if line.endswith(b" c"):
                v = [float(t) for t in line.split()[:6]]
                p1, p2, p3 = complex(v[0], v[1]), complex(v[2], v[3]), complex(v[4], v[5])
                cur.extend(_bezier(cur[-1], p1, p2, p3).tolist())
                nodes.append(p3)
                continue
            args: list[bytes] = []
            for tok in _TOKEN.findall(line):
                c0 = tok[:1]
                if c0.isdigit() or c0 in b"+-." or c0 in b"[/":
                    args.append(tok)
                    continue
                op = tok
                nums = [float(a) for a in args if a[:1] not in b"[/"]
                if op == b"cm":
                    a, b, c, d, e, f = nums[-6:]
                    ctm = np.array([[a, b, 0], [c, d, 0], [e, f, 1]]) @ ctm
                    unit = min(unit, float(np.sqrt(abs(np.linalg.det(ctm[:2, :2])))))
                elif op == b"q":
                    stack.append((ctm.copy(), colour, width, dashed))
                elif op == b"Q":
                    ctm, colour, width, dashed = stack.pop()
                elif op == b"re":
                    x, y, w, h = nums[-4:]
                    close_subpath()
                    cur = [complex(x, y), complex(x + w, y), complex(x + w, y + h), complex(x, y + h), complex(x, y)]
                    nodes = list(cur)
                elif op == b"h":
                    if cur:
                        cur.append(cur[0])
                        nodes.append(cur[0])
                elif op in (b"S", b"s", b"B", b"B*", b"b", b"b*"):
                    if op in (b"s", b"b", b"b*") and cur:
                        cur.append(cur[0])
                        nodes.append(cur[0])
                    close_subpath()
                    scale = float(np.sqrt(abs(np.linalg.det(ctm[:2, :2]))))
                    strokes.extend(Stroke(mapped(p), mapped(n), colour, width * scale, dashed) for p, n in subpaths)
                    subpaths, cur, nodes = [], [], []
                elif op in (b"n", b"f", b"F", b"f*"):
                    subpaths, cur, nodes = [], [], []
                elif op in (b"SCN", b"SC", b"RG"):
                    if len(nums) >= 3:
                        colour = tuple(nums[-3:])
                elif op == b"G":
                    colour = (nums[-1],) * 3
                elif op == b"w":
                    width = nums[-1]
                elif op == b"d":
                    dashed = any(a[:1] == b"[" and len(a.strip(b"[] ")) > 0 for a in args)
                args = []
    return Page(strokes, float(unit))


@dataclass(frozen=True)
class Registration:
    """page point = scale·(drawing point) + offset (complex), fitted to known circles."""

    scale: float
    offset: complex
    residual: float            # largest misfit of the circles it was fitted to [drawing units]
    unit: float                # one device unit of the page [drawing units]

    @property
    def resolution(self) -> float:
        """How far a drawn point may lie from where the reader put it, on the page read back
        [drawing units]: a device unit (coordinates are whole units) plus the registration's misfit."""
        return self.unit + self.residual

    def to_drawing(self, page: np.ndarray) -> np.ndarray:
        return (page - self.offset) / self.scale


def _drawn_circle(s: Stroke) -> tuple[complex, float] | None:
    """(centre, radius) of a stroke that is a full circle as Qt draws one — four Bézier quarters
    from the circle's 0°, 90°, 180° and 270° points, which lie on it exactly — else None."""
    n = s.nodes
    if n.size < 5 or s.points.size not in (4 * BEZIER_CHORDS + 1, 4 * BEZIER_CHORDS + 2):
        return None
    ring = n[:4]                                   # the start and three Bézier ends; the rest close it
    if np.max(np.abs(n[4:] - n[0])) > 1e-9 * np.max(np.abs(n)):
        return None
    c = complex(np.mean(ring))
    r = np.abs(ring - c)
    if np.ptp(r) > 1e-6 * np.mean(r):
        return None
    return c, float(np.mean(r))


def register(page: Page, circles: list[tuple[complex, float]]) -> Registration:
    """The page ← drawing map from drawn full circles: each known circle (centre, radius in drawing
    units; radii distinct) is matched to the drawn circle with the same radius ratio to the largest;
    the scale is the least-squares ratio of the matched radii, the offset the mean of the centres'."""
    drawn = [c for c in map(_drawn_circle, page.strokes) if c is not None]
    known = sorted(circles, key=lambda kc: -kc[1])
    if len(drawn) < len(known) or len(known) < 2:
        raise AssertionError(f"known circles {known}, drawn {drawn}: nothing to register the page by")
    best = None
    for c0, r0 in drawn:                      # try each drawn circle as the largest known one
        scale = r0 / known[0][1]
        pairs = []
        for kc, kr in known:
            err, dc, dr = min(((abs(r - scale * kr), c, r) for c, r in drawn), key=lambda t: t[0])
            if err > 1e-5 * scale * kr + 2 * page.unit:
                break
            pairs.append(((kc, kr), (dc, dr)))
        if len(pairs) == len(known):
            best = pairs
            break
    if best is None:
        raise AssertionError(f"the known circles {known} are not all drawn (drawn radii "
                             f"{sorted(round(r, 3) for _, r in drawn)} pt)")
    known_r = np.array([k[1] for k, _ in best])
    drawn_r = np.array([d[1] for _, d in best])
    scale = float(np.dot(known_r, drawn_r) / np.dot(known_r, known_r))
    offset = complex(np.mean([d[0] - scale * k[0] for k, d in best]))
    residual = max(max(abs(d[0] - (scale * k[0] + offset)), abs(d[1] - scale * k[1])) for k, d in best) / scale
    return Registration(scale, offset, residual, page.unit / scale)


def enlarge_paper(doc, factor: float) -> None:
    """Make the sheet ``factor`` times the drawing's extents: ``dxf2pdf -a`` fits the drawing to the
    sheet (the layout's limits; LibreCAD 2.2's own ``-p``/``-r`` options take no value), so a
    larger sheet draws it larger and a device unit is a smaller part of a drawing unit.  Only the
    paper changes: no entity is touched."""
    from ezdxf import bbox

    box = bbox.extents(doc.modelspace(), fast=True)
    size = box.extmax - box.extmin
    layout = doc.paperspace().dxf_layout
    layout.dxf.limmin = (0.0, 0.0)
    layout.dxf.limmax = (factor * size.x, factor * size.y)


def distance_to_segments(x: np.ndarray, polylines: list[np.ndarray], k: int = 8) -> np.ndarray:
    """Distance of points ``x`` (complex) from the union of the segments of ``polylines`` (each a
    complex array of consecutive points): the segments of the ``k`` nearest segment midpoints and
    ends are measured exactly (a miss can only overstate the distance)."""
    from scipy.spatial import cKDTree

    a = np.concatenate([p[:-1] for p in polylines if p.size > 1])
    b = np.concatenate([p[1:] for p in polylines if p.size > 1])
    keys = np.concatenate([a, b, (a + b) / 2])
    tree = cKDTree(np.column_stack([keys.real, keys.imag]))
    _, idx = tree.query(np.column_stack([x.real, x.imag]), k=min(k, keys.size))
    seg = np.atleast_2d(idx) % a.size
    aa, bb = a[seg], b[seg]
    ab = bb - aa
    den = np.where(np.abs(ab) > 0, np.abs(ab) ** 2, 1.0)
    t = np.clip(((x[:, None] - aa) * np.conj(ab)).real / den, 0.0, 1.0)
    return np.min(np.abs(x[:, None] - (aa + t * ab)), axis=1)


def title_cells(doc) -> dict[str, tuple[str, tuple[float, float, float, float]]]:
    """{TEXT handle: (text, cell (x0, y0, x1, y1))} of the title block: the cell of a text is bounded
    by the nearest of the title block's lines (LINE entities and polyline edges on TITLE) above and
    below its insertion point and left and right of it that reach across it."""
    msp = doc.modelspace()
    segs = []
    for e in msp.query('*[layer=="TITLE"]'):
        if e.dxftype() == "LINE":
            segs.append((complex(e.dxf.start.x, e.dxf.start.y), complex(e.dxf.end.x, e.dxf.end.y)))
        elif e.dxftype() in ("LWPOLYLINE", "POLYLINE"):
            pts = [complex(p[0], p[1]) for p in (e.get_points("xy") if e.dxftype() == "LWPOLYLINE"
                                                 else [v.dxf.location for v in e.vertices])]
            pts.append(pts[0])
            segs += list(zip(pts[:-1], pts[1:]))
    horiz = [(min(a.real, b.real), max(a.real, b.real), a.imag) for a, b in segs if abs(a.imag - b.imag) < 1e-9]
    vert = [(min(a.imag, b.imag), max(a.imag, b.imag), a.real) for a, b in segs if abs(a.real - b.real) < 1e-9]
    out = {}
    for t in msp.query('TEXT[layer=="TITLE"]'):
        x, y, h = t.dxf.insert.x, t.dxf.insert.y, t.dxf.height
        ym = y + 0.4 * h
        above = min(yy for a, b, yy in horiz if a <= x <= b and yy > ym)
        below = max(yy for a, b, yy in horiz if a <= x <= b and yy < ym)
        left = max(xx for a, b, xx in vert if a <= ym <= b and xx < x)
        right = min(xx for a, b, xx in vert if a <= ym <= b and xx > x)
        out[t.dxf.handle] = (t.dxf.text, (left, below, right, above))
    return out

"""Drawing a DXF with LibreCAD (Debian package ``librecad``, 2.2) and reading back what it drew.

``librecad dxf2pdf`` prints a DXF headless (Qt's ``offscreen`` platform) to a one-page PDF.  Qt
writes every drawn entity as a stroked vector path in the page's content stream — LibreCAD draws
its text with its own stroke fonts, so text is lines too — and nothing else: a path operator
stream of ``m``/``l``/``c``/``h`` with ``SCN`` (stroke colour), ``w`` (line width) and ``d`` (dash)
before each entity, under one ``cm`` (device units → points).  :func:`read_pdf_paths` interprets
that stream (no PDF library involved: Flate-decoded content, the handful of operators Qt emits)
into polylines in page points, Bézier segments flattened finely, each with its stroke colour,
width and dash.

:func:`register` maps page points back to drawing units from known features of the drawing (circles
whose centres and radii the test knows), so a test can hold what LibreCAD drew against the exact
curves.  Entities LibreCAD cannot draw (e.g. SPLINEs of degree > 3) leave nothing in the PDF.
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
    """One stroked subpath as LibreCAD drew it: points (complex, page points), style."""

    points: np.ndarray
    colour: tuple[float, float, float]
    width: float
    dashed: bool


def dxf2pdf(dxf: Path, pdf: Path, paper: str | None = None) -> subprocess.CompletedProcess:
    """Print ``dxf`` to ``pdf`` with ``librecad dxf2pdf`` (fitted to the page, headless).

    LibreCAD keeps settings under $HOME and needs $XDG_RUNTIME_DIR: both point into the PDF's
    folder, so the run leaves nothing elsewhere."""
    home = pdf.parent / ".librecad-home"
    runtime = home / "run"
    runtime.mkdir(parents=True, exist_ok=True)
    runtime.chmod(0o700)
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen", HOME=str(home), XDG_RUNTIME_DIR=str(runtime),
               XDG_CONFIG_HOME=str(home / "config"))
    cmd = [LIBRECAD, "dxf2pdf", "-a", "-o", str(pdf)]
    if paper:
        cmd += ["-p", paper]
    res = subprocess.run([*cmd, str(dxf)], capture_output=True, text=True, env=env, timeout=300)
    if res.returncode != 0 or not pdf.exists():
        raise RuntimeError(f"librecad dxf2pdf failed ({res.returncode}): {res.stdout[-800:]} {res.stderr[-800:]}")
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


def read_pdf_paths(pdf: Path) -> list[Stroke]:
    """Every stroked subpath of the PDF's pages, in page points (y up), with its style."""
    strokes: list[Stroke] = []
    for stream in _content_streams(Path(pdf).read_bytes()):
        ctm = np.eye(3)
        stack: list[tuple[np.ndarray, tuple, float, bool]] = []
        colour: tuple = (0.0, 0.0, 0.0)
        width, dashed = 1.0, False
        args: list[bytes] = []
        subpaths: list[list[complex]] = []
        cur: list[complex] = []

        def pt(x: float, y: float) -> complex:
            v = ctm.T @ np.array([x, y, 1.0])
            return complex(v[0], v[1])

        for tok in _TOKEN.findall(stream):
            c0 = tok[:1]
            if c0.isdigit() or c0 in b"+-." or c0 in b"[/":
                args.append(tok)
                continue
            op = tok
            nums = [float(a) for a in args if a[:1] not in b"[/"]
            if op == b"cm":
                a, b, c, d, e, f = nums[-6:]
                ctm = np.array([[a, b, 0], [c, d, 0], [e, f, 1]]) @ ctm
            elif op == b"q":
                stack.append((ctm.copy(), colour, width, dashed))
            elif op == b"Q":
                ctm, colour, width, dashed = stack.pop()
            elif op == b"m":
                if len(cur) > 1:
                    subpaths.append(cur)
                cur = [pt(*nums[-2:])]
            elif op == b"l":
                cur.append(pt(*nums[-2:]))
            elif op == b"c":
                x1, y1, x2, y2, x3, y3 = nums[-6:]
                cur.extend(_bezier(cur[-1], pt(x1, y1), pt(x2, y2), pt(x3, y3)).tolist())
            elif op == b"re":
                x, y, w, h = nums[-4:]
                cur = [pt(x, y), pt(x + w, y), pt(x + w, y + h), pt(x, y + h), pt(x, y)]
            elif op == b"h":
                if cur:
                    cur.append(cur[0])
            elif op in (b"S", b"s", b"B", b"B*", b"b", b"b*"):
                if op in (b"s", b"b", b"b*") and cur:
                    cur.append(cur[0])
                if len(cur) > 1:
                    subpaths.append(cur)
                scale = float(np.sqrt(abs(np.linalg.det(ctm[:2, :2]))))
                strokes.extend(Stroke(np.array(s), colour, width * scale, dashed) for s in subpaths)
                subpaths, cur = [], []
            elif op in (b"n", b"f", b"F", b"f*"):
                subpaths, cur = [], []
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
    return strokes


@dataclass(frozen=True)
class Registration:
    """page point = scale·(drawing point) + offset (complex), fitted to known circles."""

    scale: float
    offset: complex
    residual: float            # largest misfit of the features used [drawing units]

    def to_drawing(self, page: np.ndarray) -> np.ndarray:
        return (page - self.offset) / self.scale


def _circle_fit(z: np.ndarray) -> tuple[complex, float, float]:
    """Least-squares circle (Kåsa) through points: centre, radius, largest residual."""
    a = np.column_stack([z.real, z.imag, np.ones(z.size)])
    b = np.abs(z) ** 2
    (p, q, r), *_ = np.linalg.lstsq(a, b, rcond=None)
    c = complex(p / 2, q / 2)
    rad = float(np.sqrt(r + abs(c) ** 2))
    return c, rad, float(np.max(np.abs(np.abs(z - c) - rad)))


def register(strokes: list[Stroke], circles: list[tuple[complex, float]]) -> Registration:
    """The page ← drawing map from drawn full circles: each known circle (centre, radius in drawing
    units) is matched to the drawn closed stroke that is a circle with the right radius ratio; the
    scale and offset are the least-squares fit of the matched centres and radii.  LibreCAD draws a
    CIRCLE as four Bézier quarters (exact to ~3e-4 of the radius: Qt's standard approximation)."""
    drawn = []
    for s in strokes:
        z = s.points
        if z.size < 4 * BEZIER_CHORDS or abs(z[-1] - z[0]) > 1e-6 * np.max(np.abs(z - z.mean())):
            continue
        c, r, res = _circle_fit(z)
        if res <= 1e-3 * r:
            drawn.append((c, r))
    if not drawn:
        raise AssertionError("no circle drawn: nothing to register the page by")
    radii = np.array([r for _, r in circles])
    # the scale from the largest known circle, matched against every drawn circle's radius ratio
    best = None
    for c0, r0 in drawn:
        scale = r0 / radii.max()
        matched = []
        for (cc, rr) in circles:
            cand = [(abs(r - scale * rr), c, r) for c, r in drawn]
            err, c, r = min(cand, key=lambda t: t[0])
            if err <= 1e-3 * scale * rr:
                matched.append(((cc, rr), (c, r)))
        if len(matched) == len(circles) and (best is None or len(matched) > len(best)):
            best = matched
    if best is None:
        raise AssertionError(f"the known circles {circles} are not all drawn (drawn radii "
                             f"{sorted(round(r, 3) for _, r in drawn)} pt)")
    known_r = np.array([k[1] for k, _ in best])
    drawn_r = np.array([d[1] for _, d in best])
    scale = float(np.dot(known_r, drawn_r) / np.dot(known_r, known_r))
    offset = complex(np.mean([d[0] - scale * k[0] for k, d in best]))
    residual = max(max(abs(d[0] - (scale * k[0] + offset)), abs(d[1] - scale * k[1])) for k, d in best) / scale
    return Registration(scale, offset, residual)

"""Running G-code through LinuxCNC's standalone interpreter ``rs274`` (Debian package
``linuxcnc-uspace``) and reading back the canonical machining calls it prints.

rs274 prints one canonical call per line, e.g.::

    37 N180   STRAIGHT_FEED(-6.3620, -46.0634, -5.0000, 0.0000, 0.0000, 0.0000)
    40 N200   ARC_FEED(-10.0000, -40.0000, -11.2127, -44.8507, 1, -5.0000, 0.0000, 0.0000, 0.0000)

STRAIGHT_FEED/STRAIGHT_TRAVERSE(x, y, z, a, b, c); ARC_FEED(first_end, second_end,
first_axis, second_axis, rotation, axis_end_point, a, b, c) in the XY plane: end (x, y),
centre (x, y), rotation +1 counter-clockwise / −1 clockwise, z at the end.  Numbers are
printed with 4 decimals in the program's units (USE_LENGTH_UNITS tells which); C in
degrees.  Under G93 the interpreter turns F into a units-per-minute SET_FEED_RATE of
length·F (XYZ length, or the rotary length in degrees for a rotary-only move).
"""
from __future__ import annotations

import re
import shutil
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

from .conftest import SAFETY_S

RS274 = shutil.which("rs274")
requires_rs274 = pytest.mark.skipif(
    RS274 is None, reason="LinuxCNC's rs274 is not installed (Debian package linuxcnc-uspace; `make test` "
                          "installs it when run as root)")

#: rs274 prints 4 decimals: a printed coordinate is within half a unit of the 4th decimal.
PRINT_QUANTUM = 1e-4

_CALL = re.compile(r"^\s*\d+\s+N\S*\s+([A-Z_]+)\((.*)\)\s*$")


@dataclass
class Motion:
    """One canonical motion: kind "traverse", "line" or "arc"; start and end (x, y, z, c)."""

    kind: str
    start: np.ndarray
    end: np.ndarray
    centre: complex | None = None
    rotation: int = 0
    feed: float = 0.0          # units/min as the interpreter set it
    tag: str = ""             # the last COMMENT before the motion


@dataclass
class Run:
    units: str
    motions: list[Motion] = field(default_factory=list)
    calls: list[tuple[str, str]] = field(default_factory=list)
    stdout: str = ""

    def tagged(self, tag: str) -> list[list[Motion]]:
        """Runs of consecutive motions under the comment ``tag``."""
        out: list[list[Motion]] = []
        prev = None
        for m in self.motions:
            if m.tag == tag:
                if prev != tag:
                    out.append([])
                out[-1].append(m)
            prev = m.tag
        return out


def run_rs274(program: str, folder: Path, tool_number: int = 1, tool_diameter: float = 10.0) -> Run:
    """Run ``program`` through rs274 (with a one-tool table) and parse its output.

    Fails the test if rs274 reports an error or exits non-zero."""
    ngc = folder / "program.ngc"
    ngc.write_text(program)
    tbl = folder / "tool.tbl"
    tbl.write_text(f"T{tool_number} P{tool_number} D{tool_diameter:.6f} Z0 ;cam tool\n")
    res = subprocess.run([RS274, "-g", str(ngc), "-t", str(tbl)], capture_output=True, text=True,
                         timeout=SAFETY_S, stdin=subprocess.DEVNULL)
    text = res.stdout + res.stderr
    assert res.returncode == 0, f"rs274 exit {res.returncode}:\n{text[-3000:]}"
    assert "PROGRAM_END()" in res.stdout, text[-3000:]
    return parse(res.stdout)


def parse(stdout: str) -> Run:
    """Canonical calls → motions (positions tracked from the initial origin)."""
    run = Run(units="", stdout=stdout)
    pos = np.zeros(4)      # x, y, z, c
    feed = 0.0
    tag = ""
    for line in stdout.splitlines():
        m = _CALL.match(line)
        if not m:
            continue
        name, args = m.group(1), m.group(2)
        run.calls.append((name, args))
        if name == "USE_LENGTH_UNITS":
            run.units = "in" if "INCHES" in args else "mm" if "MM" in args else args
        elif name == "COMMENT":
            text = args.strip().strip('"')
            if not text.startswith("interpreter:"):   # the interpreter's own notes are not tags
                tag = text
        elif name == "SET_FEED_RATE":
            feed = float(args)
        elif name in ("STRAIGHT_FEED", "STRAIGHT_TRAVERSE"):
            v = [float(a) for a in args.split(",")]
            end = np.array([v[0], v[1], v[2], v[5]])
            run.motions.append(Motion("line" if name == "STRAIGHT_FEED" else "traverse", pos.copy(), end,
                                      feed=feed, tag=tag))
            pos = end
        elif name == "ARC_FEED":
            v = [float(a) for a in args.split(",")]
            end = np.array([v[0], v[1], v[5], v[8]])
            run.motions.append(Motion("arc", pos.copy(), end, centre=complex(v[2], v[3]),
                                      rotation=int(v[4]), feed=feed, tag=tag))
            pos = end
    return run


def sample_xy(motions: list[Motion], per_motion: int = 64) -> np.ndarray:
    """Dense XY points (complex) along lines and arcs; an arc whose printed end radius differs
    from its start radius is followed as LinuxCNC does, as a spiral (radius linear in angle)."""
    pts = []
    t = np.arange(per_motion) / per_motion
    for m in motions:
        a = complex(m.start[0], m.start[1])
        b = complex(m.end[0], m.end[1])
        if m.kind != "arc":
            pts.append(a + (b - a) * t)
            continue
        c = m.centre
        a0, a1 = np.angle(a - c), np.angle(b - c)
        sweep = np.mod(a1 - a0, 2 * np.pi) if m.rotation > 0 else np.mod(a1 - a0, 2 * np.pi) - 2 * np.pi
        if m.rotation > 0 and sweep == 0:
            sweep = 2 * np.pi
        r = abs(a - c) + (abs(b - c) - abs(a - c)) * t
        pts.append(c + r * np.exp(1j * (a0 + sweep * t)))
    last = motions[-1].end
    pts.append(np.array([complex(last[0], last[1])]))
    return np.concatenate(pts)


def polyline_distance(x: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Distance of points x to a polyline (both complex), exact per segment (k-d tree for the
    nearest vertex, then its two segments: fine for dense polylines).  A closed polyline
    (last point = first) wraps around, so the repeated end point has both neighbours."""
    from scipy.spatial import cKDTree

    closed = len(poly) > 2 and abs(poly[-1] - poly[0]) <= 1e-9 * max(1.0, float(np.abs(poly).max()))
    if closed:
        ring = poly[:-1]
        tree = cKDTree(np.column_stack([ring.real, ring.imag]))
        _, k = tree.query(np.column_stack([x.real, x.imag]))
        n = len(ring)
        lo, hi = (k - 1) % n, (k + 1) % n
        return np.minimum(_seg(x, ring[lo], ring[k]), _seg(x, ring[k], ring[hi]))
    tree = cKDTree(np.column_stack([poly.real, poly.imag]))
    _, k = tree.query(np.column_stack([x.real, x.imag]))

    lo = np.clip(k - 1, 0, len(poly) - 1)
    hi = np.clip(k + 1, 0, len(poly) - 1)
    return np.minimum(_seg(x, poly[lo], poly[k]), _seg(x, poly[k], poly[hi]))


def _seg(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ab = b - a
    den = np.where(np.abs(ab) > 0, np.abs(ab) ** 2, 1.0)
    s = np.clip(((p - a) * np.conj(ab)).real / den, 0, 1)
    return np.abs(p - (a + s * ab))

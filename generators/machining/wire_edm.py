"""2-axis wire EDM of a plate cam's outside profile (``machining.program = "wire_edm"``), as plain
geometry (the program text is made in ``cam_workbench.exporters.gcode_wire_edm``).

The wire (radius r_w = ``wire_diameter``/2) cuts with a spark gap g around it, so the wire centre
runs at **r_w + g from the profile** for the last cut: the exact offset of the pitch curve outward
by r_w + g − r (:func:`cam_workbench.generators.machining.toolpath.tool_centre_curve`), fitted as
biarcs (or chords) within 0.85 × ``chord_tolerance``.  With n = ``skim_passes`` the main cut runs
n·``skim_stock`` farther out and skim j at (n − j)·``skim_stock``, the last one at r_w + g.

The sequence (cam frame = machine XY, work origin on the cam axis):

1. the wire is threaded in the **start hole**, ``start_hole`` (default ``lead_radius``) outside
   the main cut's path on its outward normal at the entry point (the middle of the longest dwell);
2. a straight **lead-in** along that normal to the entry point E;
3. the **main cut**, clockwise seen from +Z, from E around the cam to T, the point ``tab_width``
   (measured along the wire path) before E: the stretch from T to E is the **holding tab** that
   keeps the part in the plate;
4. each **skim** over the cut stretch only, in the direction opposite to the cut before it
   (skim 1 from T back to E, skim 2 from E to T, …), each entered by a short move from the point
   the wire is at to the same place on its own path;
5. a **program stop** (M00): the operator secures the part (magnet or clamp) so it cannot drop
   onto the wire when the tab is cut;
6. the **tab cut** on the final path (r_w + g) from the end the wire is at across the tab.

``wire_compensation = "controller"``: the program carries the part contour itself (the profile)
and LinuxCNC's G41.1/G42.1 with D = 2(r_w + g) offsets it; skims then need ``"path"``.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..cam_design import CamDesign
from ..curves.approx import Path2D
from ..errors import SpecError, fmt_apart
from .plan import MachiningPlan, smallest_concave_profile_radius
from .toolpath import entry_junction, fit_contour, points_inside, reverse_path, tool_centre_curve

#: defaults per unit system
WIRE_DEFAULTS = {"mm": {"wire_diameter": 0.25, "spark_gap": 0.02, "skim_stock": 0.03, "tab_width": 2.0},
                 "in": {"wire_diameter": 0.01, "spark_gap": 0.0008, "skim_stock": 0.0012, "tab_width": 0.08}}


@dataclass(frozen=True)
class WireCut:
    """One cut of the wire.

    Attributes:
        role: "main", "skim 1", …, "tab".
        offset: wire-centre distance from the profile.
        moves: the programmed moves in order (the wire centre; the part contour under
            ``"controller"`` compensation).
        link: the short move onto this cut's path from where the wire is (None: it is there).
    """

    role: str
    offset: float
    moves: Path2D
    link: complex | None


@dataclass(frozen=True)
class WireEdmPath:
    """The wire EDM program's geometry (spec units).

    Attributes:
        wire_radius, spark_gap, skim_stock, tab_width: the resolved settings.
        compensation: "path" or "controller".
        start_hole: where the wire is threaded (a wire-centre position).
        entry: the lead-in's end, E on the main cut's programmed path.
        cuts: main, skims, tab, in order.
        main_length: length of the main cut's closed wire path (cut + tab).
        max_distance: largest measured two-sided distance of the fitted paths from their exact offsets.
        tolerance: the chord tolerance.
        entry_angle_deg: cam angle of the entry point.
    """

    wire_radius: float
    spark_gap: float
    skim_stock: float
    tab_width: float
    compensation: str
    start_hole: complex
    entry: complex
    cuts: tuple[WireCut, ...]
    main_length: float
    max_distance: float
    tolerance: float
    entry_angle_deg: float

    @property
    def final_offset(self) -> float:
        """r_w + g: the last path's distance from the profile."""
        return self.wire_radius + self.spark_gap

    def summary(self) -> dict[str, Any]:
        """Numbers for report.json (spec units, degrees)."""
        return {"wire_diameter": 2 * self.wire_radius, "spark_gap": self.spark_gap,
                "wire_compensation": self.compensation, "skim_passes": len(self.cuts) - 2,
                "skim_stock": self.skim_stock, "tab_width": self.tab_width,
                "offsets": {c.role: c.offset for c in self.cuts},
                "moves": {c.role: c.moves.n for c in self.cuts},
                "start_hole": [self.start_hole.real, self.start_hole.imag], "entry_at_deg": self.entry_angle_deg,
                "main_path_length": self.main_length, "max_distance": self.max_distance,
                "chord_tolerance": self.tolerance}


def _setting(value: float | None, units: str, name: str) -> float:
    """A wire setting or its default (:data:`WIRE_DEFAULTS`)."""
    return float(value if value is not None else WIRE_DEFAULTS[units][name])


def wire_edm_path(design: CamDesign, plan: MachiningPlan) -> WireEdmPath:
    """The wire EDM geometry of ``design`` (module docstring).

    Raises:
        SpecError: ``machining.wire_diameter`` — the main cut's offset reaches the smallest
            concave radius of the profile; ``machining.tab_width`` — not shorter than half the
            path; ``machining.start_hole`` — the lead-in would cross the part.
    """
    mc = design.spec.machining
    u = design.spec.units
    r_w = 0.5 * _setting(mc.wire_diameter, u, "wire_diameter")
    gap = _setting(mc.spark_gap, u, "spark_gap")
    stock = _setting(mc.skim_stock, u, "skim_stock")
    tab = _setting(mc.tab_width, u, "tab_width")
    n = mc.skim_passes or 0
    final = r_w + gap
    offsets = [final + (n - j) * stock for j in range(n + 1)]        # main, skim 1 … skim n
    rho, at = smallest_concave_profile_radius(design)
    if offsets[0] >= rho:
        raise SpecError("machining.wire_diameter",
                        f"the main cut runs {fmt_apart(offsets[0], rho)} {u} from the profile (wire radius + spark gap"
                        f" + skim stock), not below the profile's smallest concave radius {fmt_apart(rho, offsets[0])}"
                        f" {u} at cam angle {at:.2f}°: the wire would cut into the cam")
    compensation = mc.wire_compensation or "path"
    controller = compensation == "controller"
    tol = plan.chord_tolerance
    k = entry_junction(design.pitch)
    u_entry = float(design.pitch.junction_parameters[k])
    loops, entries, dist = [], [], 0.0
    for off in offsets + ([0.0] if controller else []):
        loop, entry, d = _loop(design, plan, off, u_entry)
        loops.append(loop)
        entries.append(entry)
        dist = max(dist, d)
    main = loops[0]
    if not tab < 0.5 * main.length:
        raise SpecError("machining.tab_width", f"must be < half the wire path ({fmt_apart(0.5 * main.length, tab)} "
                                               f"{u}), got {fmt_apart(tab, 0.5 * main.length)}")
    cut_main, _ = split_at_length(main, main.length - tab)
    tab_start = cut_main.end[-1]
    outward = entries[0] - entries[-1] if controller else _outward(design, plan, u_entry, offsets[0])
    outward /= abs(outward)
    hole = mc.start_hole if mc.start_hole is not None else plan.lead_radius
    start = entries[0] + hole * outward
    _check_lead_in(main, start, entries[0])
    if controller:
        # the part contour, split where the wire path's tab starts
        part = loops[-1]
        head, tail = split_at_point(part, _nearest_on(part, tab_start))
        cuts = (WireCut("main", final, head, None), WireCut("tab", final, tail, None))
        programmed_entry = entries[-1]
    else:
        cuts_l = [WireCut("main", offsets[0], cut_main, None)]
        at = tab_start                            # where the wire is
        at_tab_end = True
        for j, (off, loop) in enumerate(zip(offsets[1:], loops[1:]), start=1):
            head, _ = split_at_point(loop, _nearest_on(loop, tab_start))
            moves = reverse_path(head) if at_tab_end else head
            link = moves.start[0]
            cuts_l.append(WireCut(f"skim {j}", off, moves, None if abs(link - at) == 0 else link))
            at = moves.end[-1]
            at_tab_end = not at_tab_end
        last = loops[-1]
        head, tail = split_at_point(last, _nearest_on(last, tab_start))
        moves = tail if at_tab_end else reverse_path(tail)
        link = moves.start[0]
        cuts_l.append(WireCut("tab", final, moves, None if abs(link - at) == 0 else link))
        cuts = tuple(cuts_l)
        programmed_entry = entries[0]
    return WireEdmPath(wire_radius=r_w, spark_gap=gap, skim_stock=stock, tab_width=tab,
                       compensation=compensation, start_hole=start, entry=programmed_entry, cuts=cuts,
                       main_length=main.length, max_distance=dist, tolerance=tol,
                       entry_angle_deg=float(np.rad2deg(design.pitch.angles[k])))


def _loop(design: CamDesign, plan: MachiningPlan, offset: float, u_entry: float
          ) -> tuple[Path2D, complex, float]:
    """(closed clockwise path at ``offset`` from the profile starting at its entry point, that
    point, its measured distance from the exact offset)."""
    curve = tool_centre_curve(design, dataclasses.replace(plan, tool_radius=offset))
    path, dist = fit_contour(curve, plan.chord_tolerance, arcs=plan.contour == "arcs")
    if curve.area() > 0:
        path = reverse_path(path)
    p = curve.evaluate(np.array([u_entry]))
    entry = complex(p[0, 0], p[0, 1])
    first = int(np.argmin(np.abs(path.start - entry)))
    path = Path2D(*(np.roll(v, -first) for v in (path.start, path.end, path.center, path.ccw, path.u0, path.u1)))
    return path, complex(path.start[0]), dist


def _outward(design: CamDesign, plan: MachiningPlan, u_entry: float, offset: float) -> complex:
    """Outward unit normal of the path at ``offset`` at the entry parameter (path mode)."""
    curve = tool_centre_curve(design, dataclasses.replace(plan, tool_radius=offset))
    p, d = curve.evaluate_with_derivative(np.array([u_entry]))
    t = complex(d[0, 0], d[0, 1])
    return -1j * t if curve.area() > 0 else 1j * t     # ccw curve: outward is to the right


def _check_lead_in(loop: Path2D, start: complex, entry: complex) -> None:
    """The straight lead-in from the start hole to the entry point must stay outside the part.

    Raises:
        SpecError: ``machining.start_hole``.
    """
    t = np.linspace(0.0, 0.98, 50)
    pts = start + (entry - start) * t
    inside = points_inside(pts, loop.sample(8))
    if inside.any():
        raise SpecError("machining.start_hole", "the straight lead-in from the start hole crosses the cam's wire "
                                                "path; a smaller machining.start_hole")


def element_point(path: Path2D, i: int, frac: float) -> complex:
    """The point a fraction ``frac`` of the way along element ``i``."""
    if not path.is_arc[i]:
        return complex(path.start[i] + frac * (path.end[i] - path.start[i]))
    c = path.center[i]
    return complex(c + (path.start[i] - c) * np.exp(1j * frac * path.sweep()[i]))


def split_at_point(path: Path2D, at: tuple[int, complex]) -> tuple[Path2D, Path2D]:
    """(the elements before the point, the ones after): element ``at[0]`` is cut at ``at[1]``
    (a point on it); a cut at an element's end leaves no empty element."""
    i, p = at
    s, e, c, ccw, u0, u1 = (v.copy() for v in (path.start, path.end, path.center, path.ccw, path.u0, path.u1))
    head = Path2D(np.append(s[:i], s[i]), np.append(e[:i], p), np.append(c[:i], c[i]),
                  np.append(ccw[:i], ccw[i]), np.append(u0[:i], u0[i]), np.append(u1[:i], u1[i]))
    tail = Path2D(np.append(p, s[i + 1:]), np.append(e[i], e[i + 1:]), np.append(c[i], c[i + 1:]),
                  np.append(ccw[i], ccw[i + 1:]), np.append(u0[i], u0[i + 1:]), np.append(u1[i], u1[i + 1:]))
    return _drop_empty(head), _drop_empty(tail)


def _drop_empty(path: Path2D) -> Path2D:
    keep = np.abs(path.end - path.start) > 1e-12 * max(1.0, float(np.max(np.abs(path.start))))
    return Path2D(*(v[keep] for v in (path.start, path.end, path.center, path.ccw, path.u0, path.u1)))


def split_at_length(path: Path2D, length: float) -> tuple[Path2D, Path2D]:
    """``path`` cut at ``length`` along it."""
    cum = np.cumsum(path.lengths())
    i = int(np.searchsorted(cum, length))
    before = cum[i - 1] if i > 0 else 0.0
    frac = (length - before) / (cum[i] - before)
    return split_at_point(path, (i, element_point(path, i, float(frac))))


def _nearest_on(path: Path2D, point: complex) -> tuple[int, complex]:
    """(element, point on it) of ``path`` nearest to ``point`` (exact per element)."""
    a, b = path.start, path.end
    ab = b - a
    s = np.clip(((point - a) * np.conj(ab)).real / np.maximum(np.abs(ab) ** 2, 1e-300), 0.0, 1.0)
    on_line = a + s * ab
    arc = path.is_arc
    c = np.where(arc, path.center, 0)
    r = np.where(arc, path.radius, 0.0)
    a0 = np.angle(a - c)
    sweep = path.sweep()
    rel = np.angle((point - c) * np.exp(-1j * a0))             # angle from the start, in (−π, π]
    rel = np.where(sweep >= 0, np.mod(rel, 2 * np.pi), -np.mod(-rel, 2 * np.pi))
    inside = np.abs(rel) <= np.abs(sweep)
    radial = c + r * np.exp(1j * (a0 + rel))
    ends = np.where(np.abs(point - a) <= np.abs(point - b), a, b)
    on_arc = np.where(inside, radial, ends)
    cand = np.where(arc, on_arc, on_line)
    i = int(np.argmin(np.abs(cand - point)))
    return i, complex(cand[i])

"""A prism body as levels: where the loops do not cross, the body is known without booleans.

A body (:class:`.base.BodyGeometry`) is a list of prisms added and cut in order.  Where no two
distinct loops of its prisms cross or touch (each lies wholly inside or wholly outside another —
the usual case: a disc with its bore, holes, a groove between two closed walls, a hub), the plane is
cut by the loops into **cells** — the inside of a loop minus the insides of the loops directly in
it — and nesting alone says which cells a prism covers: its outer loop's cells and their
descendants' but not its holes'.  Between two consecutive heights where a prism starts or ends
(a **level**), a cell belongs to the body by the prisms' operations applied in order to that
one cell.  The body's boundary then is, exactly:

* **caps** — at each such height z, the planar region whose cells belong to the level below or to
  the level above but not to both (the bottom and top faces, a groove's floor, a hub's shoulder),
  each face one outer loop and the loops of the cells it leaves out as holes;
* **sides** — each loop swept along z over every run of levels where the cells on its two sides
  differ (one loop's side is one face over its whole run, not one per prism).

The kernels (``cam_workbench.kernel.solids``, ``cam_workbench.freecad.part_build``) make these faces
and sew them into one solid: no boolean operation.  :func:`level_stack` returns None where loops
cross (the kernels then apply the prisms' booleans in order, as before).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .base import Arc, Curve, Loop, Prism

#: samples of a circular arc and of a NURBS span for the nesting test: a full circle's 96-gon
#: is within 5.4e-4 of its radius; a span of a profile is far flatter than its samples' spacing
_ARC_SAMPLES, _SPAN_SAMPLES = 96, 8


@dataclass(frozen=True)
class CapFace:
    """A planar face at height ``z``: inside ``outer``, outside every loop of ``holes``."""

    z: float
    outer: Loop
    holes: tuple[Loop, ...]


@dataclass(frozen=True)
class Side:
    """A loop swept from ``z0`` to ``z1`` (z0 < z1): part of the body's boundary."""

    loop: Loop
    z0: float
    z1: float


@dataclass(frozen=True)
class CapXor:
    """A cap where loops of the level below cross loops of the level above (say mounting holes
    that open onto a hub's shoulder): the region of ``below`` or ``above`` but not both, at height
    ``z``, which the kernel makes by planar booleans of the two levels' faces."""

    z: float
    below: tuple[CapFace, ...]
    above: tuple[CapFace, ...]


@dataclass(frozen=True)
class LevelStack:
    """The boundary of a prism body whose loops do not cross within a level: its caps (direct,
    or by planar booleans where two levels' loops cross) and its sides."""

    caps: tuple[CapFace | CapXor, ...]
    sides: tuple[Side, ...]
    #: the body's exact volume: Σ over levels of its faces' areas (Green's theorem) × the height
    volume: float


def level_stack(prisms: tuple[Prism, ...] | list[Prism]) -> LevelStack | None:
    """The caps and sides of the body made by ``prisms`` in order, or None where two distinct
    loops of one level cross or touch (then only booleans make the body)."""
    loops, owner = _distinct_loops(prisms)
    polys = [_samples(lp) for lp in loops]
    box = np.array([[p.real.min(), p.imag.min(), p.real.max(), p.imag.max()] for p in polys])
    n = len(loops)
    inside = np.zeros((n, n), dtype=bool)          # inside[i, j]: loop i lies inside loop j
    cross = np.zeros((n, n), dtype=bool)           # loops i and j cross or touch
    for j in range(n):
        for i in range(n):
            apart = (box[i, 0] > box[j, 2]) | (box[i, 2] < box[j, 0]) | (box[i, 1] > box[j, 3]) | (box[i, 3] < box[j, 1])
            if i != j and not apart:
                hit = _in_polygon(polys[i], polys[j])
                inside[i, j], cross[i, j] = hit.all(), hit.any() and not hit.all()
    cross |= cross.T
    areas = np.array([abs(lp.area) for lp in loops])
    heights = sorted({z for p in prisms for z in (p.z0, p.z1)})
    levels = []                                     # per level: (its loops, their parents, member cells)
    volume = 0.0
    for z0, z1 in zip(heights[:-1], heights[1:]):
        active = [(p, o) for p, o in zip(prisms, owner) if p.z0 <= z0 and z1 <= p.z1]
        used = sorted({i for _, (outer, holes) in active for i in (outer, *holes)})
        if cross[np.ix_(used, used)].any():
            return None
        levels.append(_level(active, used, inside, areas, n))
        volume += (z1 - z0) * sum(areas[o] - sum(areas[h] for h in hs) for o, hs in _faces(levels[-1][2], levels[-1][1]))
    caps: list[CapFace | CapXor] = []
    for k, z in enumerate(heights):
        below = levels[k - 1] if k > 0 else None
        above = levels[k] if k < len(levels) else None
        caps += _cap(z, below, above, cross, inside, areas, loops, n)
    sides: list[Side] = []
    runs: dict[int, float] = {}                     # loop → where its current run of sides began
    for k in range(len(levels) + 1):
        bounding = set(levels[k][3]) if k < len(levels) else set()
        for i in list(runs):
            if i not in bounding:
                sides.append(Side(loops[i], runs.pop(i), heights[k]))
        for i in sorted(bounding):
            runs.setdefault(i, heights[k])
    return LevelStack(tuple(caps), tuple(sides), float(volume))


def _parents(used: list[int], inside: np.ndarray, areas: np.ndarray, n: int) -> np.ndarray:
    """Each loop's nearest enclosing loop among ``used`` (−1: none; loops not used: −1)."""
    parent = np.full(n, -1)
    for i in used:
        outer = [j for j in used if inside[i, j]]
        if outer:
            parent[i] = min(outer, key=lambda j: areas[j])
    return parent


def _level(active, used, inside, areas, n):
    """(used loops, their parents, the member cells, the loops bounding the level) of a level
    made by the ``active`` prisms (prism, (outer, holes)) in order."""
    parent = _parents(used, inside, areas, n)
    within = inside | np.eye(n, dtype=bool)         # within[i, j]: cell i lies inside loop j
    m = np.zeros(n, dtype=bool)
    for p, (outer, holes) in active:
        covered = within[:, outer] & ~within[:, list(holes)].any(axis=1) if holes else within[:, outer].copy()
        m = m | covered if p.op == "add" else m & ~covered
    m[[i for i in range(n) if i not in used]] = False
    bounding = [i for i in used if m[i] != (m[parent[i]] if parent[i] >= 0 else False)]
    return used, parent, m, bounding


def _cap(z, below, above, cross, inside, areas, loops, n) -> list[CapFace | CapXor]:
    """The cap faces at height ``z`` between two levels (None: nothing there)."""
    def faces(level):
        if level is None:
            return ()
        used, parent, m, _ = level
        return tuple(CapFace(z, loops[o], tuple(loops[h] for h in hs)) for o, hs in _faces(m, parent))

    used = sorted(set(below[0] if below else ()) | set(above[0] if above else ()))
    if cross[np.ix_(used, used)].any():
        return [CapXor(z, faces(below), faces(above))]
    parent = _parents(used, inside, areas, n)
    mb = below[2] if below else np.zeros(n, dtype=bool)
    ma = above[2] if above else np.zeros(n, dtype=bool)
    # a cell's membership in a level it has no loop of is its nearest used ancestor's there
    member = _spread(mb, below, parent, used) ^ _spread(ma, above, parent, used)
    return [CapFace(z, loops[o], tuple(loops[h] for h in hs)) for o, hs in _faces(member, parent)]


def _spread(m, level, parent, used):
    """Membership of the cells of ``used`` in a level whose own loops are a subset of them: a
    loop the level does not have takes its parent's membership (nearest first)."""
    out = np.zeros_like(m)
    own = set(level[0]) if level else set()
    order = sorted(used, key=lambda i: _depth(i, parent))
    for i in order:
        if i in own:
            out[i] = m[i]
        else:
            out[i] = out[parent[i]] if parent[i] >= 0 else False
    return out


def _depth(i: int, parent: np.ndarray) -> int:
    d = 0
    while parent[i] >= 0:
        i, d = int(parent[i]), d + 1
    return d


def _distinct_loops(prisms) -> tuple[list[Loop], list[tuple[int, tuple[int, ...]]]]:
    """The prisms' distinct loops (a loop given by two prisms, e.g. the bore of a disc and of its
    hub, once) and each prism's (outer, holes) as indices into them."""
    loops: list[Loop] = []
    keys: dict[bytes, int] = {}
    owner = []

    def index(loop: Loop) -> int:
        key = np.round(_samples(loop), 9).tobytes()
        if key not in keys:
            keys[key] = len(loops)
            loops.append(loop)
        return keys[key]

    for p in prisms:
        owner.append((index(p.outer), tuple(index(h) for h in p.holes)))
    return loops, owner


def _samples(loop: Loop) -> np.ndarray:
    """Points along ``loop`` (complex) for the nesting test: arcs by :data:`_ARC_SAMPLES` per turn."""
    parts = []
    for piece in loop.pieces:
        if isinstance(piece, Arc):
            parts.append(piece.points(max(8, int(np.ceil(_ARC_SAMPLES * abs(piece.a1 - piece.a0) / (2 * np.pi))))))
        elif isinstance(piece, Curve):
            parts.append(piece.points(_SPAN_SAMPLES))
        else:
            parts.append(piece.points(2))
    return np.concatenate(parts)


def _in_polygon(points: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Whether each complex point lies inside the closed polygon ``poly`` (complex vertices),
    by the even-odd rule (points on an edge count as either)."""
    x, y = points.real[:, None], points.imag[:, None]
    a, b = poly, np.roll(poly, -1)
    ax, ay, bx, by = a.real[None, :], a.imag[None, :], b.real[None, :], b.imag[None, :]
    crosses = (ay > y) != (by > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xint = ax + (y - ay) * (bx - ax) / (by - ay)
    return (crosses & (x < xint)).sum(axis=1) % 2 == 1


def _faces(member: np.ndarray, parent: np.ndarray) -> list[tuple[int, list[int]]]:
    """(outer loop, hole loops) of each face of the region made of the ``member`` cells: a member
    cell whose parent cell is not a member starts a face; its member children's cells join it; its
    other children are its holes."""
    children: dict[int, list[int]] = {}
    for i, p in enumerate(parent):
        children.setdefault(int(p), []).append(i)
    out = []
    for i in np.flatnonzero(member):
        if parent[i] >= 0 and member[parent[i]]:
            continue
        holes, todo = [], [int(i)]
        while todo:
            c = todo.pop()
            for ch in children.get(c, []):
                (todo if member[ch] else holes).append(ch)
        out.append((int(i), holes))
    return out


__all__ = ["CapFace", "CapXor", "LevelStack", "Side", "level_stack"]

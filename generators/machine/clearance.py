"""Clearances between the moving tools of a machine: several cams on one shaft, each driving a
tool; tools whose paths share space must keep a clearance (issue 24, part 4).

Conventions (see docs/clearance.md):

* an outline is given in the tool's own frame [mm]: :class:`Circle` or :class:`Polygon`;
* a pose maps it to the machine frame: ``world = R(angle) @ p + position`` with ``angle`` [rad]
  counter-clockwise positive; :class:`Poses` holds N of them;
* machine and cam angles are in degrees;
* the signed distance is the Euclidean distance between the outlines when they are apart and
  ``-depth`` when they overlap; ``depth`` is the penetration depth (the shortest translation that
  separates them) for circles and convex polygons, and a lower bound on it (the deepest vertex or
  circle point inside the other outline) when a polygon is not convex;
* the minimum over a cycle is either sampled (:attr:`Clearance.error_bound` bounds how far the true
  minimum between the samples can lie below it: Lipschitz bound from the tools' speeds), or, when
  pose functions are given, refined by a Lipschitz branch and bound between the samples.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence, Union

import numpy as np
from scipy.optimize import minimize_scalar

from ..errors import SpecError

__all__ = ["Circle", "Polygon", "Poses", "Clearance", "ClearanceResult", "PhaseSweep", "ShortestCycle",
           "signed_distance", "min_clearance", "clearance_check", "phase_sweep", "shortest_cycle"]


# ---- outlines and poses -----------------------------------------------------------------------
@dataclass(frozen=True)
class Circle:
    """A circular tool outline: ``radius`` [mm] > 0 around ``centre`` [mm] in the tool frame."""

    radius: float
    centre: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        r = float(self.radius)
        if not math.isfinite(r) or r <= 0.0:
            raise SpecError("radius", f"is {self.radius!r}, must be a finite number > 0 mm")
        c = tuple(float(v) for v in np.asarray(self.centre, dtype=float).reshape(-1))
        if len(c) != 2 or not all(math.isfinite(v) for v in c):
            raise SpecError("centre", f"is {self.centre!r}, must be two finite coordinates [mm]")
        object.__setattr__(self, "radius", r)
        object.__setattr__(self, "centre", c)

    @property
    def reach(self) -> float:
        """Largest distance [mm] of an outline point from the tool frame's origin."""
        return math.hypot(*self.centre) + self.radius


@dataclass(frozen=True, eq=False)
class Polygon:
    """A polygonal tool outline: ``vertices`` (V, 2) [mm] in the tool frame, V ≥ 3, simple (no two
    edges cross), convex or not, either orientation (stored counter-clockwise)."""

    vertices: np.ndarray
    convex: bool = field(init=False)

    def __post_init__(self) -> None:
        try:
            v = np.array(self.vertices, dtype=float)
        except (TypeError, ValueError):
            raise SpecError("vertices", "must be an array of (x, y) coordinates [mm]") from None
        if v.ndim != 2 or v.shape[1] != 2 or v.shape[0] < 3:
            raise SpecError("vertices", f"has shape {v.shape}, must be (V, 2) with V >= 3")
        if not np.all(np.isfinite(v)):
            raise SpecError("vertices", "must be finite numbers [mm]")
        e = np.roll(v, -1, axis=0) - v
        length = np.hypot(e[:, 0], e[:, 1])
        scale = float(np.max(np.abs(v))) or 1.0
        if np.any(length <= 1e-12 * scale):
            k = int(np.argmin(length))
            raise SpecError("vertices", f"vertex {k} repeats vertex {(k + 1) % len(v)}: edges must have length > 0")
        _check_simple(v)
        area2 = float(np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1]))
        if abs(area2) <= 1e-12 * scale * scale:
            raise SpecError("vertices", "encloses no area: the polygon must have area > 0")
        if area2 < 0.0:
            v = v[::-1].copy()
            e = np.roll(v, -1, axis=0) - v
        turn = e[:, 0] * np.roll(e[:, 1], -1) - e[:, 1] * np.roll(e[:, 0], -1)
        v.setflags(write=False)
        object.__setattr__(self, "vertices", v)
        object.__setattr__(self, "convex", bool(np.all(turn >= -1e-12 * scale * scale)))

    @property
    def reach(self) -> float:
        """Largest distance [mm] of an outline point from the tool frame's origin."""
        return float(np.max(np.hypot(self.vertices[:, 0], self.vertices[:, 1])))


Outline = Union[Circle, Polygon]


def _check_simple(v: np.ndarray) -> None:
    """SpecError naming two crossing edges when the (counter-clockwise) polygon ``v`` is not simple."""
    n = len(v)
    a0, a1 = v, np.roll(v, -1, axis=0)
    i, j = np.triu_indices(n, k=2)
    keep = ~((i == 0) & (j == n - 1))                       # the last and first edges share vertex 0
    i, j = i[keep], j[keep]
    hit = _segments_cross(a0[i], a1[i], a0[j], a1[j], touching=True)
    if np.any(hit):
        k = int(np.argmax(hit))
        raise SpecError("vertices", f"edges {i[k]} and {j[k]} cross: the polygon must be simple")


@dataclass(frozen=True, eq=False)
class Poses:
    """N poses of a tool [machine frame]: ``positions`` (N, 2) [mm] of the tool frame's origin and
    ``angles`` (N,) [rad] of its rotation, counter-clockwise (None: no rotation)."""

    positions: np.ndarray
    angles: np.ndarray | None = None

    def __post_init__(self) -> None:
        p = np.array(self.positions, dtype=float)
        if p.ndim == 1 and p.shape[0] == 2:
            p = p[None, :]
        if p.ndim != 2 or p.shape[1] != 2:
            raise SpecError("positions", f"has shape {p.shape}, must be (N, 2) [mm]")
        if not np.all(np.isfinite(p)):
            raise SpecError("positions", "must be finite numbers [mm]")
        a = np.zeros(len(p)) if self.angles is None else np.array(self.angles, dtype=float).reshape(-1)
        if a.shape != (len(p),):
            raise SpecError("angles", f"has {a.shape[0]} values, must have one per position ({len(p)})")
        if not np.all(np.isfinite(a)):
            raise SpecError("angles", "must be finite numbers [rad]")
        object.__setattr__(self, "positions", p)
        object.__setattr__(self, "angles", a)

    def __len__(self) -> int:
        return len(self.positions)


PoseLike = Union[Poses, np.ndarray, Sequence[Any]]
#: a tool's pose as a function of an angle [deg] (machine angle, or the tool's own cam angle):
#: it takes an array (M,) and returns Poses (or positions (M, 2), or (positions, angles))
Motion = Callable[[np.ndarray], PoseLike]


def _as_poses(value: Any, name: str, n: int | None = None) -> Poses:
    """``value`` as :class:`Poses` (a Poses, positions (N, 2), or a (positions, angles) pair);
    SpecError naming ``name`` when it is not, or does not have ``n`` poses."""
    try:
        if isinstance(value, Poses):
            poses = value
        elif isinstance(value, tuple) and len(value) == 2 and np.ndim(value[0]) == 2:
            poses = Poses(value[0], value[1])
        else:
            poses = Poses(value)
    except SpecError as exc:
        raise SpecError(f"{name}.{exc.field}", exc.rule) from None
    if n is not None and len(poses) != n:
        raise SpecError(name, f"has {len(poses)} poses, must have one per machine angle ({n})")
    return poses


def _check_outline(value: Any, name: str) -> Outline:
    if not isinstance(value, (Circle, Polygon)):
        raise SpecError(name, f"is a {type(value).__name__}, must be a Circle or a Polygon")
    return value


# ---- vectorised geometry ----------------------------------------------------------------------
def _cross(u: np.ndarray, w: np.ndarray) -> np.ndarray:
    return u[..., 0] * w[..., 1] - u[..., 1] * w[..., 0]


def _segments_cross(a0: np.ndarray, a1: np.ndarray, b0: np.ndarray, b1: np.ndarray,
                    touching: bool = False) -> np.ndarray:
    """Whether segments a0a1 and b0b1 cross (broadcast over leading axes); ``touching`` counts a
    shared point too (an endpoint on the other segment, collinear overlap)."""
    da, db = a1 - a0, b1 - b0
    o1, o2 = _cross(da, b0 - a0), _cross(da, b1 - a0)
    o3, o4 = _cross(db, a0 - b0), _cross(db, a1 - b0)
    proper = (o1 * o2 < 0) & (o3 * o4 < 0)
    if not touching:
        return proper
    return proper | (_point_segment(a0, b0, b1)[0] == 0) | (_point_segment(a1, b0, b1)[0] == 0) \
        | (_point_segment(b0, a0, a1)[0] == 0) | (_point_segment(b1, a0, a1)[0] == 0)


def _point_segment(p: np.ndarray, s0: np.ndarray, s1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(distance, closest point) from points ``p`` to segments s0s1 (broadcast over leading axes)."""
    d = s1 - s0
    dd = np.sum(d * d, axis=-1)
    t = np.clip(np.sum((p - s0) * d, axis=-1) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
    q = s0 + t[..., None] * d
    return np.hypot(p[..., 0] - q[..., 0], p[..., 1] - q[..., 1]), q


def _inside(p: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Whether points ``p`` (N, M, 2) lie inside the polygons ``w`` (N, V, 2) (crossing number; a
    point on the boundary may count either way — its distance is 0 there)."""
    e0 = w[:, None, :, :]
    e1 = np.roll(w, -1, axis=1)[:, None, :, :]
    px, py = p[:, :, None, 0], p[:, :, None, 1]
    straddle = (e0[..., 1] > py) != (e1[..., 1] > py)
    dy = e1[..., 1] - e0[..., 1]
    x = e0[..., 0] + (py - e0[..., 1]) * (e1[..., 0] - e0[..., 0]) / np.where(straddle, dy, 1.0)
    return (np.count_nonzero(straddle & (px < x), axis=-1) % 2) == 1


def _world(outline: Outline, poses: Poses) -> np.ndarray:
    """The outline's points in the machine frame: the circle centres (N, 2) or the polygon
    vertices (N, V, 2)."""
    c, s = np.cos(poses.angles), np.sin(poses.angles)
    pts = np.asarray(outline.centre, dtype=float)[None, :] if isinstance(outline, Circle) else outline.vertices
    x = c[:, None] * pts[None, :, 0] - s[:, None] * pts[None, :, 1] + poses.positions[:, None, 0]
    y = s[:, None] * pts[None, :, 0] + c[:, None] * pts[None, :, 1] + poses.positions[:, None, 1]
    w = np.stack([x, y], axis=-1)
    return w[:, 0, :] if isinstance(outline, Circle) else w


def _unit(v: np.ndarray, fallback: np.ndarray | None = None) -> np.ndarray:
    n = np.hypot(v[..., 0], v[..., 1])
    out = v / np.where(n > 0, n, 1.0)[..., None]
    if fallback is not None:
        out = np.where((n > 0)[..., None], out, fallback)
    return out


@dataclass(frozen=True)
class _Signed:
    """Per-pose signed distance and its witnesses (arrays over M poses)."""

    d: np.ndarray           # (M,) signed distance [mm]
    pa: np.ndarray          # (M, 2) point of A
    pb: np.ndarray          # (M, 2) point of B
    n: np.ndarray           # (M, 2) unit direction moving B away from A increases d
    exact: np.ndarray       # (M,) False where an overlap's depth is only a lower bound


def _circle_circle(ca: np.ndarray, ra: float, cb: np.ndarray, rb: float) -> _Signed:
    u = _unit(cb - ca, np.array([1.0, 0.0]))
    d = np.hypot(*(cb - ca).T) - ra - rb
    return _Signed(d, ca + ra * u, cb - rb * u, u, np.ones(len(d), bool))


def _circle_polygon(c: np.ndarray, r: float, w: np.ndarray, convex: bool) -> _Signed:
    """Circle (centres c (M, 2), radius r) against polygons w (M, V, 2); ``n`` moves the polygon
    away from the circle, ``pa`` is on the circle, ``pb`` on the polygon."""
    m = np.arange(len(c))
    dist, q = _point_segment(c[:, None, :], w, np.roll(w, -1, axis=1))
    k = np.argmin(dist, axis=1)
    e, q = dist[m, k], q[m, k]
    inside = _inside(c[:, None, :], w)[:, 0]
    # the polygon's nearest boundary point q: outside, the circle's witness faces it; inside, it is
    # the opposite point of the circle (the polygon must move by r + e to clear it)
    toward = _unit(q - c, np.array([1.0, 0.0]))
    n = np.where(inside[:, None], -toward, toward)
    d = np.where(inside, -e, e) - r
    pa = c + r * np.where(inside[:, None], -toward, toward)
    exact = np.full(len(c), convex) | (d >= 0)
    return _Signed(d, pa, q, n, exact)


def _polygon_polygon(wa: np.ndarray, wb: np.ndarray, convex: bool) -> _Signed:
    """Polygons wa (M, Va, 2) and wb (M, Vb, 2); SAT penetration when both are convex."""
    m = np.arange(len(wa))
    va, vb = wa.shape[1], wb.shape[1]
    ea1, eb1 = np.roll(wa, -1, axis=1), np.roll(wb, -1, axis=1)
    # vertex of A to edge of B (M, Va, Vb) and vertex of B to edge of A (M, Vb, Va)
    dab, qab = _point_segment(wa[:, :, None, :], wb[:, None, :, :], eb1[:, None, :, :])
    dba, qba = _point_segment(wb[:, :, None, :], wa[:, None, :, :], ea1[:, None, :, :])
    fa, fb = dab.reshape(len(wa), -1), dba.reshape(len(wa), -1)
    ka, kb = np.argmin(fa, axis=1), np.argmin(fb, axis=1)
    use_a = fa[m, ka] <= fb[m, kb]
    dist = np.where(use_a, fa[m, ka], fb[m, kb])
    ia, ja = np.divmod(ka, vb)
    ib, jb = np.divmod(kb, va)
    pa = np.where(use_a[:, None], wa[m, ia], qba[m, ib, jb])
    pb = np.where(use_a[:, None], qab[m, ia, ja], wb[m, ib])
    n = _unit(pb - pa, np.array([1.0, 0.0]))
    if convex:
        # separating axes: the edge normals of both polygons; the largest separation over them
        # is the signed distance's lower bound, exact (= -depth) when they overlap
        ea, eb = ea1 - wa, eb1 - wb
        axes = _unit(np.concatenate([np.stack([ea[..., 1], -ea[..., 0]], -1),
                                     np.stack([eb[..., 1], -eb[..., 0]], -1)], axis=1))
        proj_a = np.einsum("mkd,mvd->mkv", axes, wa)
        proj_b = np.einsum("mkd,mvd->mkv", axes, wb)
        ab = proj_b.min(axis=2) - proj_a.max(axis=2)            # B beyond A along +axis
        ba = proj_a.min(axis=2) - proj_b.max(axis=2)            # B beyond A along -axis
        sep = np.maximum(ab, ba)
        k = np.argmax(sep, axis=1)
        s = sep[m, k]
        over = s < 0
        sign = np.where(ab[m, k] >= ba[m, k], 1.0, -1.0)
        ax = axes[m, k] * sign[:, None]
        depth = -s
        # the deepest vertex of the polygon that does not own the axis, and where it leaves the other
        deep_b = wb[m, np.argmin(np.einsum("md,mvd->mv", ax, wb), axis=1)]
        deep_a = wa[m, np.argmax(np.einsum("md,mvd->mv", ax, wa), axis=1)]
        a_axis = (k < va)[:, None]
        opa = np.where(a_axis, deep_b + depth[:, None] * ax, deep_a)
        opb = np.where(a_axis, deep_b, deep_a - depth[:, None] * ax)
        d = np.where(over, s, dist)
        return _Signed(d, np.where(over[:, None], opa, pa), np.where(over[:, None], opb, pb),
                       np.where(over[:, None], ax, n), np.ones(len(wa), bool))
    # not convex: overlap when edges cross or a vertex of one lies inside the other; its depth is
    # the deepest such vertex's distance to the other's boundary (a lower bound of the true depth)
    crossing = _segments_cross(wa[:, :, None, :], ea1[:, :, None, :], wb[:, None, :, :], eb1[:, None, :, :])
    a_in = _inside(wa, wb)                                     # (M, Va)
    b_in = _inside(wb, wa)                                     # (M, Vb)
    da_in = np.where(a_in, dab.min(axis=2), -1.0)
    db_in = np.where(b_in, dba.min(axis=2), -1.0)
    ka_in, kb_in = np.argmax(da_in, axis=1), np.argmax(db_in, axis=1)
    depth_a, depth_b = da_in[m, ka_in], db_in[m, kb_in]
    over = np.any(crossing, axis=(1, 2)) | np.any(a_in, axis=1) | np.any(b_in, axis=1)
    depth = np.maximum(np.maximum(depth_a, depth_b), 0.0)
    # witnesses of an overlap: the deepest vertex and its nearest point on the other's boundary
    jqa = np.argmin(dab[m, ka_in], axis=1)
    jqb = np.argmin(dba[m, kb_in], axis=1)
    a_deeper = (depth_a >= depth_b)[:, None]
    opa = np.where(a_deeper, wa[m, ka_in], qba[m, kb_in, jqb])
    opb = np.where(a_deeper, qab[m, ka_in, jqa], wb[m, kb_in])
    # crossing without a vertex inside: the crossing point, depth 0 (a lower bound)
    none_in = (np.maximum(depth_a, depth_b) < 0)
    if np.any(over & none_in):
        flat = crossing.reshape(len(wa), -1)
        kc = np.argmax(flat, axis=1)
        ic, jc = np.divmod(kc, vb)
        a0, da = wa[m, ic], ea1[m, ic] - wa[m, ic]
        b0, db = wb[m, jc], eb1[m, jc] - wb[m, jc]
        den = _cross(da, db)
        t = _cross(b0 - a0, db) / np.where(den != 0, den, 1.0)
        x = a0 + t[:, None] * da
        sel = (over & none_in)[:, None]
        opa, opb = np.where(sel, x, opa), np.where(sel, x, opb)
    o_n = _unit(opa - opb, np.array([1.0, 0.0]))
    d = np.where(over, -depth, dist)
    return _Signed(d, np.where(over[:, None], opa, pa), np.where(over[:, None], opb, pb),
                   np.where(over[:, None], o_n, n), ~over)


def _signed(outline_a: Outline, poses_a: Poses, outline_b: Outline, poses_b: Poses) -> _Signed:
    wa, wb = _world(outline_a, poses_a), _world(outline_b, poses_b)
    if isinstance(outline_a, Circle) and isinstance(outline_b, Circle):
        return _circle_circle(wa, outline_a.radius, wb, outline_b.radius)
    if isinstance(outline_a, Circle):
        return _circle_polygon(wa, outline_a.radius, wb, outline_b.convex)
    if isinstance(outline_b, Circle):
        s = _circle_polygon(wb, outline_b.radius, wa, outline_a.convex)
        return _Signed(s.d, s.pb, s.pa, -s.n, s.exact)
    return _polygon_polygon(wa, wb, outline_a.convex and outline_b.convex)


def signed_distance(outline_a: Outline, poses_a: PoseLike, outline_b: Outline, poses_b: PoseLike) -> np.ndarray:
    """Signed distance [mm] between two tool outlines at each of N pose pairs (N,): the distance
    when apart, minus the penetration depth when they overlap (minus a lower bound of it when a
    polygon is not convex)."""
    oa, ob = _check_outline(outline_a, "outline_a"), _check_outline(outline_b, "outline_b")
    pa = _as_poses(poses_a, "poses_a")
    pb = _as_poses(poses_b, "poses_b", len(pa))
    return _signed(oa, pa, ob, pb).d


# ---- the minimum over a cycle -----------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Clearance:
    """The smallest signed distance between two tools over a cycle.

    Attributes:
        distance: signed minimum [mm]: < 0 overlap (minus the penetration depth).
        angle_deg: machine angle [deg] where it occurs.
        point_a, point_b: the closest points (for an overlap: the deepest point of one outline and
            where it leaves the other) [mm, machine frame].
        direction: unit vector [machine frame] along which moving tool B increases the distance.
        overlap: the outlines overlap there.
        exact_depth: False when ``overlap`` and a polygon is not convex (the depth is a lower bound).
        refined: True when searched between the samples with pose functions.
        error_bound: how far the true minimum can lie below ``distance`` [mm] (true ≥ distance −
            error_bound), from the tools' speeds (see docs/clearance.md).
        samples: the machine angles given; evaluations: poses evaluated in all.
    """

    distance: float
    angle_deg: float
    point_a: np.ndarray
    point_b: np.ndarray
    direction: np.ndarray
    overlap: bool
    exact_depth: bool
    refined: bool
    error_bound: float
    samples: int
    evaluations: int

    def to_dict(self) -> dict[str, Any]:
        """Plain values (report JSON)."""
        return {"distance": self.distance, "angle_deg": self.angle_deg, "point_a": self.point_a.tolist(),
                "point_b": self.point_b.tolist(), "direction": self.direction.tolist(), "overlap": self.overlap,
                "exact_depth": self.exact_depth, "refined": self.refined, "error_bound": self.error_bound,
                "samples": self.samples, "evaluations": self.evaluations}


def _wrap(a: np.ndarray) -> np.ndarray:
    return (a + np.pi) % (2.0 * np.pi) - np.pi


def _speeds(t: np.ndarray, pa: Poses, pb: Poses, reach_a: float, reach_b: float) -> np.ndarray:
    """Lipschitz constant [mm/deg] of the signed distance on each interval of the rows of ``t``
    (shape (..., S + 1), poses flattened in the same order): the chord speed of B relative to A
    (translation, plus each tool's rotation times its reach), each interval taking the larger of
    itself and its neighbours (shape (..., S))."""
    shape = t.shape
    h = np.diff(t, axis=-1)
    pos_a, pos_b = pa.positions.reshape(shape + (2,)), pb.positions.reshape(shape + (2,))
    ang_a, ang_b = pa.angles.reshape(shape), pb.angles.reshape(shape)
    # the distance depends on the relative pose only: B's translation relative to A's, plus
    # each tool's rotation times its reach (a point moves at most |Δangle|·reach)
    move = (np.hypot(*np.moveaxis(np.diff(pos_b - pos_a, axis=-2), -1, 0))
            + np.abs(_wrap(np.diff(ang_a, axis=-1))) * reach_a
            + np.abs(_wrap(np.diff(ang_b, axis=-1))) * reach_b)
    speed = move / np.where(h > 0, h, 1.0)
    out = speed.copy()
    out[..., 1:] = np.maximum(out[..., 1:], speed[..., :-1])
    out[..., :-1] = np.maximum(out[..., :-1], speed[..., 1:])
    return out


def _lower_bounds(d_lo: np.ndarray, d_hi: np.ndarray, lip: np.ndarray, width: np.ndarray) -> np.ndarray:
    """The smallest value an L-Lipschitz function through (lo, d_lo), (hi, d_hi) can take between."""
    return 0.5 * (d_lo + d_hi) - 0.5 * lip * width


def _check_angles(machine_angle: Any, name: str = "machine_angle") -> np.ndarray:
    t = np.array(machine_angle, dtype=float).reshape(-1)
    if t.shape[0] < 2:
        raise SpecError(name, f"has {t.shape[0]} values, must have at least 2 [deg]")
    if not np.all(np.isfinite(t)):
        raise SpecError(name, "must be finite numbers [deg]")
    if np.any(np.diff(t) <= 0):
        k = int(np.argmax(np.diff(t) <= 0))
        raise SpecError(name, f"value {k + 1} ({t[k + 1]:g}°) does not exceed value {k} ({t[k]:g}°): "
                              "must increase strictly")
    return t


def min_clearance(outline_a: Outline, poses_a: PoseLike, outline_b: Outline, poses_b: PoseLike,
                  machine_angle: Any, *, motion_a: Motion | None = None, motion_b: Motion | None = None,
                  tol: float = 1e-6, subdivisions: int = 8, max_rounds: int = 60,
                  max_intervals: int = 4096) -> Clearance:
    """The smallest signed distance [mm] between two tools over the machine angles
    ``machine_angle`` (N,) [deg, increasing; include the closing angle to cover the wrap], with
    ``poses_a``/``poses_b`` the tools' N poses there.

    Sampled unless both ``motion_a`` and ``motion_b`` are given (pose functions of the machine
    angle [deg]): then every interval between the samples where the minimum could lie more than
    ``tol`` [mm] below the best value found is split into ``subdivisions`` and searched again
    (Lipschitz branch and bound, vectorised over the intervals, at most ``max_intervals`` kept per
    round and ``max_rounds`` rounds), and the best point is polished by a bounded scalar search.
    ``error_bound`` says how far below ``distance`` the true minimum can lie in either case."""
    oa, ob = _check_outline(outline_a, "outline_a"), _check_outline(outline_b, "outline_b")
    t = _check_angles(machine_angle)
    pa = _as_poses(poses_a, "poses_a", len(t))
    pb = _as_poses(poses_b, "poses_b", len(t))
    if (motion_a is None) != (motion_b is None):
        raise SpecError("motion_b" if motion_b is None else "motion_a",
                        "is missing: refining needs both pose functions (or neither, for a sampled result)")
    for name, v in (("tol", tol),):
        if not (math.isfinite(v) and v > 0):
            raise SpecError(name, f"is {v!r}, must be a finite number > 0 mm")
    if subdivisions < 2:
        raise SpecError("subdivisions", f"is {subdivisions}, must be at least 2")
    ra, rb = oa.reach, ob.reach
    s = _signed(oa, pa, ob, pb)
    lip = _speeds(t, pa, pb, ra, rb)
    lb = _lower_bounds(s.d[:-1], s.d[1:], lip, np.diff(t))
    j = int(np.argmin(s.d))
    best = float(s.d[j])
    evaluations = len(t)
    refined = motion_a is not None
    where = (float(t[j]), s, j)
    if not refined:
        error = max(0.0, best - float(lb.min()))
    else:
        def evaluate(x: np.ndarray) -> tuple[_Signed, Poses, Poses]:
            qa = _as_poses(motion_a(x), "motion_a", len(x))
            qb = _as_poses(motion_b(x), "motion_b", len(x))
            return _signed(oa, qa, ob, qb), qa, qb

        lo, hi, d_lo, d_hi, lk = t[:-1], t[1:], s.d[:-1], s.d[1:], lip
        lower = math.inf
        best_w = float(np.max(np.diff(t)))
        frac = np.linspace(0.0, 1.0, subdivisions + 1)
        for _ in range(max_rounds):
            lb = _lower_bounds(d_lo, d_hi, lk, hi - lo)
            # an interval narrower than the angles can resolve is settled at its bound
            keep = (lb < best - tol) & ((hi - lo) > 1e-12 * max(1.0, float(np.max(np.abs(t)))))
            if np.any(~keep):
                lower = min(lower, float(lb[~keep].min()))
            if not np.any(keep):
                break
            lo, hi, lb = lo[keep], hi[keep], lb[keep]
            if len(lo) > max_intervals:
                order = np.argsort(lb, kind="stable")
                lower = min(lower, float(lb[order[max_intervals:]].min()))
                lo, hi = lo[order[:max_intervals]], hi[order[:max_intervals]]
            grid = lo[:, None] + (hi - lo)[:, None] * frac[None, :]
            sg, qa, qb = evaluate(grid.reshape(-1))
            evaluations += grid.size
            dg = sg.d.reshape(grid.shape)
            k = int(np.argmin(sg.d))
            if sg.d[k] < best:
                best = float(sg.d[k])
                where = (float(grid.reshape(-1)[k]), sg, k)
                best_w = float((hi - lo)[k // (subdivisions + 1)] / subdivisions)
            lk = _speeds(grid, qa, qb, ra, rb).reshape(-1)
            lo, hi = grid[:, :-1].reshape(-1), grid[:, 1:].reshape(-1)
            d_lo, d_hi = dg[:, :-1].reshape(-1), dg[:, 1:].reshape(-1)
        else:
            lower = min(lower, float(_lower_bounds(d_lo, d_hi, lk, hi - lo).min()))
        # polish the best point between its neighbours (the distance is piecewise smooth)
        x0 = where[0]
        span = (max(x0 - best_w, t[0]), min(x0 + best_w, t[-1]))
        if span[1] > span[0]:
            res = minimize_scalar(lambda x: float(evaluate(np.array([x]))[0].d[0]), bounds=span,
                                  method="bounded", options={"xatol": 1e-12 * max(1.0, abs(x0))})
            evaluations += int(res.nfev)
            if res.fun < best:
                best = float(res.fun)
                sg = evaluate(np.array([float(res.x)]))[0]
                where = (float(res.x), sg, 0)
        error = max(0.0, best - lower)
    angle, sw, k = where
    return Clearance(distance=float(sw.d[k]), angle_deg=angle, point_a=sw.pa[k].copy(), point_b=sw.pb[k].copy(),
                     direction=sw.n[k].copy(), overlap=bool(sw.d[k] < 0) or not bool(sw.exact[k]),
                     exact_depth=bool(sw.exact[k]),
                     refined=refined, error_bound=float(error), samples=len(t), evaluations=evaluations)


# ---- the check --------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class ClearanceResult:
    """One pair's clearance against the required one, in the shape of the design checks'
    results (value, where, limit, status) with a ``remedy`` when it fails."""

    name: str
    value: float
    at_deg: float
    limit: float
    unit: str
    status: str                             # "pass" or "fail"
    remedy: dict[str, Any] | None
    note: str = ""

    @property
    def passed(self) -> bool:
        return self.status != "fail"

    def to_dict(self) -> dict[str, Any]:
        """report.json's form of the result."""
        return {"description": "clearance between moving tools", "kind": "min", "value": self.value,
                "at_deg": self.at_deg, "limit": self.limit, "unit": self.unit, "status": self.status,
                "passed": self.passed, "note": self.note, "remedy": self.remedy}


def clearance_check(pairs: Mapping[str, Clearance], required: float | Mapping[str, float]
                    ) -> tuple[ClearanceResult, ...]:
    """Each pair's clearance (``pairs``: pair name → :func:`min_clearance` result) against the
    required clearance [mm] (one for all, or one per pair name), in the order given.

    A pair passes when its minimum distance is at least ``required`` and the outlines do not
    overlap. A failing pair's ``remedy`` gives the machine angle [deg] and the shift [mm] of
    tool B along ``direction`` (machine frame) that restores the required clearance at that angle,
    the sampling error bound included: ``shift = required − distance + error_bound``. Other
    angles may need it too: check again after the change, or move the phase (:func:`phase_sweep`)."""
    if not isinstance(pairs, Mapping):
        raise SpecError("pairs", f"is a {type(pairs).__name__}, must map pair names to Clearance results")
    if not isinstance(required, Mapping):
        _check_required(required)
    out = []
    for name, c in pairs.items():
        if not isinstance(c, Clearance):
            raise SpecError(f"pairs.{name}", f"is a {type(c).__name__}, must be a Clearance (min_clearance)")
        if isinstance(required, Mapping):
            if name not in required:
                raise SpecError(f"required.{name}", "is missing: every pair needs a required clearance [mm]")
            req, field_name = required[name], f"required.{name}"
        else:
            req, field_name = required, "required"
        try:
            req = float(req)
        except (TypeError, ValueError):
            raise SpecError(field_name, f"is {req!r}, must be a number [mm]") from None
        if not math.isfinite(req) or req < 0:
            raise SpecError(field_name, f"is {req!r}, must be a finite number >= 0 mm")
        fails = c.distance < req or c.overlap
        note = ""
        if not fails and c.distance - c.error_bound < req:
            note = (f"within the sampling error: the minimum may lie up to {c.error_bound:.3g} mm below "
                    f"{c.distance:.6g} mm between the samples (sample finer or give pose functions)")
        if c.overlap and not c.exact_depth:
            note = "overlap depth of a non-convex outline: a lower bound of the penetration"
        remedy = None
        if fails:
            shift = req - c.distance + c.error_bound
            dx, dy = (float(v) for v in c.direction)
            remedy = {"at_deg": c.angle_deg, "shift": shift, "direction": [dx, dy], "unit": "mm",
                      "text": (f"{'overlap' if c.overlap else 'clearance'} {c.distance:.6g} mm at {c.angle_deg:.6g}°: "
                               f"move tool B {shift:.6g} mm along ({dx:.4g}, {dy:.4g}) there, "
                               "or change the cams' phase (phase_sweep)")}
        out.append(ClearanceResult(name=str(name), value=c.distance, at_deg=c.angle_deg, limit=req, unit="mm",
                                   status="fail" if fails else "pass", remedy=remedy, note=note))
    return tuple(out)


# ---- phase sweep and the shortest cycle -------------------------------------------------------
@dataclass(frozen=True, eq=False)
class PhaseSweep:
    """The clearance as a function of the phase φ [deg] of tool B's cam behind tool A's (B's cam
    angle = machine angle − φ; A's cam angle = machine angle).

    Attributes:
        phases: the grid of φ [deg] in [0, 360).
        clearance: the sampled minimum signed distance [mm] over a turn at each phase.
        error_bound: how far the true minimum can lie below ``clearance`` [mm] (largest over the grid).
        required: the required clearance [mm].
        intervals: the phase intervals (start, end) [deg] keeping it, boundaries bisected,
            start in [0, 360), end > start (end may exceed 360: the interval wraps).
    """

    phases: np.ndarray
    clearance: np.ndarray
    error_bound: float
    required: float
    intervals: tuple[tuple[float, float], ...]

    def feasible(self, phase: float) -> bool:
        """Whether ``phase`` [deg] lies in a feasible interval."""
        p = float(phase) % 360.0
        return any(a <= p <= b or a <= p + 360.0 <= b for a, b in self.intervals)


def _phase_clearance(oa: Outline, ob: Outline, qa: Poses, psi: np.ndarray, motion_b: Motion, phases: np.ndarray,
                     reach: tuple[float, float], chunk: int) -> tuple[np.ndarray, np.ndarray]:
    """(sampled minimum, its Lipschitz lower bound) over the periodic machine-angle grid ``psi``
    for each phase; ``qa`` are tool A's poses at psi and psi[0] + 360."""
    n = len(psi) - 1
    mins, lows = np.empty(len(phases)), np.empty(len(phases))
    for start in range(0, len(phases), chunk):
        ph = phases[start:start + chunk]
        theta_b = (psi[None, :] - ph[:, None]) % 360.0
        qb = _as_poses(motion_b(theta_b.reshape(-1)), "motion_b", theta_b.size)
        pa_rep = Poses(np.tile(qa.positions, (len(ph), 1)), np.tile(qa.angles, len(ph)))
        d = _signed(oa, pa_rep, ob, qb).d.reshape(len(ph), n + 1)
        grid = np.broadcast_to(psi, d.shape)
        lip = _speeds(grid, pa_rep, qb, *reach)
        lb = _lower_bounds(d[:, :-1], d[:, 1:], lip, np.diff(psi)[None, :])
        mins[start:start + chunk] = d[:, :-1].min(axis=1)
        lows[start:start + chunk] = lb.min(axis=1)
    return mins, lows


def phase_sweep(outline_a: Outline, motion_a: Motion, outline_b: Outline, motion_b: Motion, required: float, *,
                phases: int = 360, samples: int = 720, bisections: int = 50) -> PhaseSweep:
    """The phases φ [deg] of tool B's cam behind tool A's that keep the required clearance [mm].

    ``motion_a``/``motion_b`` give each tool's poses as functions of its OWN cam angle [deg]
    (360-periodic: called with angles in [0, 360)); at machine angle ψ tool A is at
    motion_a(ψ) and tool B at motion_b(ψ − φ). The clearance c(φ) is the minimum signed
    distance over ``samples`` machine angles of a turn, scanned on ``phases`` phases in [0, 360)
    (vectorised), and each change of feasibility between grid neighbours is bisected
    ``bisections`` times (one crossing between neighbours is assumed: refine the grid if not)."""
    oa, ob = _check_outline(outline_a, "outline_a"), _check_outline(outline_b, "outline_b")
    req = _check_required(required)
    for name, v, least in (("phases", phases, 4), ("samples", samples, 8), ("bisections", bisections, 0)):
        if int(v) != v or v < least:
            raise SpecError(name, f"is {v!r}, must be an integer >= {least}")
    psi = np.linspace(0.0, 360.0, int(samples) + 1)
    own = psi % 360.0
    qa = _as_poses(motion_a(own), "motion_a", len(psi))
    reach = (oa.reach, ob.reach)
    size = (ob.vertices.shape[0] if isinstance(ob, Polygon) else 1) * \
           (oa.vertices.shape[0] if isinstance(oa, Polygon) else 1)
    chunk = max(1, int(4e6 // (len(psi) * size)))
    phi = np.arange(int(phases)) * (360.0 / int(phases))
    c, low = _phase_clearance(oa, ob, qa, psi, motion_b, phi, reach, chunk)
    ok = c >= req
    intervals: list[tuple[float, float]] = []
    err = float(np.max(c - low))
    if np.all(ok):
        intervals = [(0.0, 360.0)]
    elif np.any(ok):
        nxt = np.roll(ok, -1)
        k = np.nonzero(ok != nxt)[0]                        # change between phi[k] and phi[k] + step
        lo = phi[k].copy()
        hi = lo + 360.0 / int(phases)
        rising = ~ok[k]                                      # infeasible → feasible: a start
        for _ in range(int(bisections)):
            mid = 0.5 * (lo + hi)
            cm, lm = _phase_clearance(oa, ob, qa, psi, motion_b, mid % 360.0, reach, chunk)
            err = max(err, float(np.max(cm - lm)))
            good = cm >= req
            # keep the feasible end on the feasible side
            move_lo = np.where(rising, ~good, good)
            lo, hi = np.where(move_lo, mid, lo), np.where(move_lo, hi, mid)
        edge = np.where(rising, hi, lo)
        starts, ends = np.sort(edge[rising] % 360.0), np.sort(edge[~rising] % 360.0)
        for a in starts:
            later = ends[ends >= a]
            b = float(later[0]) if len(later) else float(ends[0]) + 360.0
            intervals.append((float(a), b))
    return PhaseSweep(phases=phi, clearance=c, error_bound=err, required=req, intervals=tuple(intervals))


def _check_required(required: Any) -> float:
    try:
        req = float(required)
    except (TypeError, ValueError):
        raise SpecError("required", f"is {required!r}, must be a number [mm]") from None
    if not math.isfinite(req) or req < 0:
        raise SpecError("required", f"is {required!r}, must be a finite number >= 0 mm")
    return req


@dataclass(frozen=True)
class ShortestCycle:
    """How far tool B's motion can overlap tool A's (MechDesigner's overlapped motions).

    Attributes:
        sequential_phase: φ0 = end_a − start_b [deg]: B's motion starts as A's ends.
        phase: the smallest feasible phase ≤ φ0 of the feasible interval holding φ0 (or, when φ0
            does not keep the clearance, the next feasible phase above it) [deg]; None: none.
        overlap: φ0 − phase [deg]: how many degrees B's motion can start before A's ends
            (negative: B must wait that long after A ends); at most A's span (B starting with A).
        combined_span: the machine angle from A's motion start to B's motion end at ``phase``
            [deg] = span_a + span_b − overlap.
        limited_by: "clearance", "span" (the overlap reached A's whole span) or "none" (no
            phase keeps the clearance).
        sweep: the phase sweep it came from.
    """

    sequential_phase: float
    phase: float | None
    overlap: float | None
    combined_span: float | None
    limited_by: str
    sweep: PhaseSweep


def shortest_cycle(outline_a: Outline, motion_a: Motion, span_a: tuple[float, float], outline_b: Outline,
                   motion_b: Motion, span_b: tuple[float, float], required: float, *, phases: int = 360,
                   samples: int = 720, bisections: int = 50) -> ShortestCycle:
    """The overlap [deg] tool B's motion can take on tool A's keeping the required clearance [mm].

    ``span_a``/``span_b`` = (start, end) [deg] of each tool's motion on its own cam angle (it
    dwells outside). At phase φ (B's cam angle = machine angle − φ) B's motion starts at machine
    angle start_b + φ; sequentially, at φ0 = end_a − start_b. The overlap is φ0 − φ* with φ* the
    lower end of the feasible phase interval holding φ0 (:func:`phase_sweep`), capped at A's span
    (φ* ≥ start_a − start_b: B starting before A would reverse the order); when φ0 itself fails,
    φ* is the next feasible phase above φ0 and the overlap is negative."""
    spans = []
    for name, sp in (("span_a", span_a), ("span_b", span_b)):
        try:
            a, b = (float(v) for v in sp)
        except (TypeError, ValueError):
            raise SpecError(name, f"is {sp!r}, must be (start, end) [deg]") from None
        if not (math.isfinite(a) and math.isfinite(b)) or not 0 < b - a <= 360:
            raise SpecError(name, f"is ({a:g}, {b:g}), must have start < end <= start + 360 [deg]")
        spans.append((a, b))
    (sa, ea), (sb, eb) = spans
    sweep = phase_sweep(outline_a, motion_a, outline_b, motion_b, required, phases=phases, samples=samples,
                        bisections=bisections)
    phi0 = ea - sb
    cap = ea - sa
    if not sweep.intervals:
        return ShortestCycle(phi0, None, None, None, "none", sweep)
    p0 = phi0 % 360.0
    start = None
    for a, b in sweep.intervals:
        for shift in (0.0, 360.0):
            if a <= p0 + shift <= b:
                start = a if (a, b) != (0.0, 360.0) else -math.inf
                base = p0 + shift
    if start is not None:
        overlap = base - start
        limited = "clearance"
        if overlap >= cap:
            overlap, limited = cap, "span"
    else:                                          # φ0 fails: the next feasible start above it
        ups = [(a - p0) % 360.0 for a, _ in sweep.intervals]
        overlap, limited = -min(ups), "clearance"
    phase = phi0 - overlap
    return ShortestCycle(phi0, phase, overlap, (ea - sa) + (eb - sb) - overlap, limited, sweep)

"""The design variables of the optimiser (thesis §5.1, Eq. 5.1): base radius, follower offset,
the free control-point coordinates of each B-spline rise/return, and the blank's orientation —
their bounds, their scaling, the linear constraints that keep a control polygon valid, and the
way back to a spec.

Physical vector p (spec units, radians):

    [R_b] [e] [for each B-spline rise/return: P1x … P(n−1)x, P(k−1)y … P(n−k+1)y] [b]

control x are cam angles from the segment start (P0 = 0 and Pn = the span are fixed), control y
the normalised lifts whose first and last k − 1 sit at the end levels (thesis §2.7: those are
fixed by the boundary conditions, as the thesis' B(k) list).  The solver sees

    z = (p − lower) / (upper − lower) ∈ [0, 1]

so that every variable has the same magnitude.  Linear constraints A·p ≤ c (normalised, so a
unit of violation is comparable with the other constraints):

* ordering (θ(u) increasing, thesis §2.7): x_{i+1} − x_i ≥ ``optimise.control_gap``;
* monotonic lift (oscillation, thesis §3.3, Eq. 5.2–5.4): y_{i+1} ≥ y_i on a rise, ≤ on a
  return.  y(u) is then a combination of non-negative B-splines of the polygon's differences,
  so s′ keeps its sign everywhere (the convex-hull property): a sufficient condition, exact
  between any nodes, that every thesis design (initial and final) satisfies.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..bodies.features import resolved
from ..motion.bspline_law import BSplineLift, fixed_end_points
from ..errors import SpecError, fmt_apart
from ..motion.program import MotionProgram
from ..spec.model import CamSpec
from ..spec.optimise import BODY_VARIABLES, follower_variable_rule, optimise_control_rows, optimise_variables
from .kinds import GEOMETRY_PATHS, kind_model
from .points import ControlPolygon, PointBlock, curve_at, point_block, point_bounds


#: spec path of each body design variable (a groove cam)
BODY_PATHS = {"outer_diameter": "cam.outer_diameter", "clearance": "groove.clearance"}


@dataclass(frozen=True)
class LiftBlock(ControlPolygon):
    """One B-spline rise/return and where its free coordinates sit in p."""

    motion_index: int
    kind: str                  # "rise" or "return"
    order: int
    x: np.ndarray              # (n+1,) initial control angles from the segment start [rad]
    y: np.ndarray              # (n+1,) initial normalised lifts
    x_cols: np.ndarray         # positions in p of x[1 … n−1] (empty if not varied)
    y_free: np.ndarray         # indices into y of the free lifts k−1 … n−k+1
    y_cols: np.ndarray         # positions in p of y[y_free] (empty if not varied)

    @property
    def y_jac(self) -> np.ndarray:
        """(n+1, len(y_cols)): ∂y/∂(the block's lift variables), a selection of the free lifts."""
        out = np.zeros((self.n_points, self.y_cols.size))
        if self.y_cols.size:
            out[self.y_free, np.arange(self.y_free.size)] = 1.0
        return out

    def arrays(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The full control x and y (n+1 each) at design ``p`` (any dtype: complex for tests)."""
        x = self.x.astype(p.dtype)
        y = self.y.astype(p.dtype)
        if self.x_cols.size:
            x[1:-1] = p[self.x_cols]
        if self.y_cols.size:
            y[self.y_free] = p[self.y_cols]
        return x, y


class DesignSpace:
    """The design vector of a spec (see the module docstring)."""

    def __init__(self, spec: CamSpec, program: MotionProgram | None = None):
        self.spec = spec
        self.program = program or MotionProgram.from_spec(spec)
        self.kinds = optimise_variables(spec)
        rows = optimise_control_rows(spec)
        opt = spec.optimise
        labels: list[str] = []
        p0: list[float] = []
        lo: list[float] = []
        hi: list[float] = []
        #: the follower kind's optimiser model (:mod:`cam_workbench.generators.optimise.kinds`)
        self.kind = kind_model(spec)
        #: the kind's geometric scalars (R_b and the follower's position), in order
        self.geometry_names = self.kind.geometry
        start_geo = dict(zip(self.geometry_names, self.kind.start_geometry()))
        r0 = spec.cam.base_radius
        rr = spec.roller_radius
        bore = spec.cam.bore_diameter / 2
        e0 = spec.follower.offset
        # default bounds always contain the start (a user-given one that does not is refused by
        # :meth:`check_start`): R_b ∈ [½, 2] × the initial (the lower at least 1.05 × (roller +
        # bore radius)), |e| ≤ ½ × the R_b lower bound or |e₀|, the R_b lower bound above that;
        # d, L ∈ [½, 2] × the initial; |f| ≤ ½ × the R_b lower bound or |f₀|
        r_lo = opt.base_radius_min if opt.base_radius_min is not None else min(
            max(0.5 * r0, 1.05 * (rr + bore) + 1e-9), r0)
        r_hi = opt.base_radius_max if opt.base_radius_max is not None else 2.0 * r0
        with_r = "base_radius" in self.kinds
        e_max = opt.offset_max if opt.offset_max is not None else max(0.5 * (r_lo if with_r else r0), abs(e0))
        if with_r and "offset" in self.kinds and opt.base_radius_min is None and not e_max < r_lo:
            r_lo = 0.5 * (e_max + r0)       # every design in the box keeps R_b > |e|
        bounds = {"base_radius": (r_lo, max(r_hi, r_lo * 1.01)), "offset": (-e_max, e_max)}
        for name in ("pivot_distance", "arm_length"):
            v0 = start_geo.get(name) or 0.0
            lo_b, hi_b = getattr(opt, f"{name}_min"), getattr(opt, f"{name}_max")
            bounds[name] = (lo_b if lo_b is not None else 0.5 * v0, hi_b if hi_b is not None else 2.0 * v0)
        f0 = start_geo.get("face_offset", 0.0)
        f_max = opt.face_offset_max if opt.face_offset_max is not None else max(
            0.5 * (r_lo if with_r else r0), abs(f0))
        bounds["face_offset"] = (-f_max, f_max)
        self.r_index = self.e_index = self.b_index = None
        cols: dict[str, int] = {}
        for name in self.geometry_names:
            if name not in self.kinds:
                continue
            cols[name] = len(p0)
            labels.append(GEOMETRY_PATHS[name])
            p0.append(start_geo[name]), lo.append(bounds[name][0]), hi.append(bounds[name][1])
        self.r_index = cols.get("base_radius")
        self.e_index = cols.get("offset")
        #: position in p of each geometric scalar (None: fixed at the spec's value)
        self.geometry_cols = tuple(cols.get(name) for name in self.geometry_names)
        self._geometry_start = tuple(start_geo[name] for name in self.geometry_names)
        gap = math.radians(opt.control_gap)
        blocks: list[LiftBlock] = []
        for k, curve in enumerate(self.program.curves):
            if curve is None:
                continue
            n = curve.n_points - 1
            nfix = fixed_end_points(curve.order)
            y_free = np.arange(nfix, n - nfix + 1)
            xc = np.array([], dtype=int)
            yc = np.array([], dtype=int)
            if k in rows["control_x"]:
                xc = np.arange(len(p0), len(p0) + n - 1)
                for i in range(1, n):
                    labels.append(f"motion[{k}].P{i}x")
                    p0.append(float(curve.x[i])), lo.append(gap), hi.append(curve.span - gap)
            if k in rows["control_y"]:
                yc = np.arange(len(p0), len(p0) + y_free.size)
                for i in y_free:
                    labels.append(f"motion[{k}].P{i}y")
                    p0.append(float(curve.y[i])), lo.append(0.0), hi.append(1.0)
            kind = "rise" if self.program.lifts[k] > 0 else "return"
            blocks.append(LiftBlock(k, kind, curve.order, curve.x.copy(), curve.y.copy(), xc, y_free, yc))
        point_blocks: list[PointBlock] = []
        for k in rows["points"]:
            pb = point_block(spec, self.program, k, len(p0))
            plo, phi = point_bounds(pb, opt.point_shift_max)
            for i, a in enumerate(pb.angles_deg):
                labels.append(f"motion[{k}].points[{i}]")
                p0.append(float(pb.s0[i])), lo.append(float(plo[i])), hi.append(float(phi[i]))
            point_blocks.append(pb)
        #: polynomial rows whose interior points' lifts are variables (:mod:`.points`)
        self.point_blocks = tuple(point_blocks)
        #: a groove cam's body variables (cam.outer_diameter, groove.clearance): their columns in p
        self.body_cols: dict[str, int] = {}
        for name in BODY_VARIABLES:
            if name not in self.kinds:
                continue
            v0 = self.body_start(name)
            lo_b, hi_b = getattr(opt, f"{name}_min"), getattr(opt, f"{name}_max")
            default_lo = 0.5 * v0 if name == "outer_diameter" else 0.0
            default_hi = 2.0 * v0 if v0 > 0 else 2.0 * spec.roller_radius
            self.body_cols[name] = len(p0)
            labels.append(BODY_PATHS[name])
            p0.append(v0), lo.append(lo_b if lo_b is not None else default_lo)
            hi.append(hi_b if hi_b is not None else default_hi)
        if "orientation" in self.kinds:
            self.b_index = len(p0)
            b0 = math.radians(opt.blank_orientation)
            labels.append("optimise.blank_orientation")
            # the thesis' path is the same after a quarter turn of the blank: ±90° covers every case
            p0.append(b0), lo.append(b0 - math.pi / 2), hi.append(b0 + math.pi / 2)
        self.blocks = tuple(blocks)
        self.labels = tuple(labels)
        self.lower = np.array(lo, dtype=float)
        self.upper = np.array(hi, dtype=float)
        #: the user's starting design, never moved: default bounds are widened to contain it, and a
        #: bound the spec gives that excludes it is refused by :meth:`check_start`
        self.start = np.array(p0, dtype=float)
        if self.start.size:
            self.lower = np.minimum(self.lower, self.start)
            self.upper = np.maximum(self.upper, self.start)
        self.p0 = self.start.copy()
        self.scale = self.upper - self.lower
        # a lift bound collapsed onto its start (point_shift_max tiny): keep the scaling finite
        self.scale = np.where(self.scale > 0, self.scale, 1e-9 * np.maximum(1.0, np.abs(self.start)))
        self.gap = gap
        self.linear_A, self.linear_c = self._linear_constraints()

    def body_start(self, name: str) -> float:
        """The spec's cam.outer_diameter or groove.clearance (its default when absent)."""
        if name == "outer_diameter":
            return float(self.spec.cam.outer_diameter)
        return float(resolved(self.spec, "groove", "clearance"))

    def body_value(self, p: np.ndarray, name: str) -> Any:
        """outer_diameter or clearance at design p (the spec's when not a variable)."""
        c = self.body_cols.get(name)
        return p[c] if c is not None else self.body_start(name)

    def check_start(self) -> None:
        """Refuse a starting design outside the bounds the spec gives (the default bounds
        always contain it), rather than silently moving it.

        Raises:
            SpecError: naming the bound (``optimise.offset_max``, ``optimise.base_radius_min`` or
                ``optimise.base_radius_max``) and the start value.
        """
        opt = self.spec.optimise
        units = self.spec.units
        if self.e_index is not None and opt.offset_max is not None:
            e0 = float(self.start[self.e_index])
            if abs(e0) > opt.offset_max:
                raise SpecError("optimise.offset_max",
                                f"must be ≥ |follower.offset| of the starting design ({fmt_apart(abs(e0), opt.offset_max)} "
                                f"{units}), got {fmt_apart(opt.offset_max, abs(e0))}")
        if self.r_index is not None:
            r0 = float(self.start[self.r_index])
            if opt.base_radius_min is not None and r0 < opt.base_radius_min:
                raise SpecError("optimise.base_radius_min",
                                f"must be ≤ cam.base_radius of the starting design ({fmt_apart(r0, opt.base_radius_min)} "
                                f"{units}), got {fmt_apart(opt.base_radius_min, r0)}")
            if opt.base_radius_max is not None and r0 > opt.base_radius_max:
                raise SpecError("optimise.base_radius_max",
                                f"must be ≥ cam.base_radius of the starting design ({fmt_apart(r0, opt.base_radius_max)} "
                                f"{units}), got {fmt_apart(opt.base_radius_max, r0)}")
        for name, c in self.body_cols.items():
            v0 = float(self.start[c])
            lo_b, hi_b = getattr(opt, f"{name}_min"), getattr(opt, f"{name}_max")
            if lo_b is not None and v0 < lo_b:
                raise SpecError(f"optimise.{name}_min",
                                f"must be ≤ {BODY_PATHS[name]} of the starting design ({fmt_apart(v0, lo_b)} {units}), "
                                f"got {fmt_apart(lo_b, v0)}")
            if hi_b is not None and v0 > hi_b:
                raise SpecError(f"optimise.{name}_max",
                                f"must be ≥ {BODY_PATHS[name]} of the starting design ({fmt_apart(v0, hi_b)} {units}), "
                                f"got {fmt_apart(hi_b, v0)}")
        for name, c in zip(self.geometry_names, self.geometry_cols):
            if c is None or name not in ("pivot_distance", "arm_length", "face_offset"):
                continue
            v0 = float(self.start[c])
            if name == "face_offset":
                if opt.face_offset_max is not None and abs(v0) > opt.face_offset_max:
                    raise SpecError("optimise.face_offset_max",
                                    f"must be ≥ |follower.face_offset| of the starting design "
                                    f"({fmt_apart(abs(v0), opt.face_offset_max)} {units}), got "
                                    f"{fmt_apart(opt.face_offset_max, abs(v0))}")
                continue
            lo_b, hi_b = getattr(opt, f"{name}_min"), getattr(opt, f"{name}_max")
            if lo_b is not None and v0 < lo_b:
                raise SpecError(f"optimise.{name}_min",
                                f"must be ≤ follower.{name} of the starting design ({fmt_apart(v0, lo_b)} {units}), "
                                f"got {fmt_apart(lo_b, v0)}")
            if hi_b is not None and v0 > hi_b:
                raise SpecError(f"optimise.{name}_max",
                                f"must be ≥ follower.{name} of the starting design ({fmt_apart(v0, hi_b)} {units}), "
                                f"got {fmt_apart(hi_b, v0)}")

    # ---- sizes and scaling ----------------------------------------------------------------
    @property
    def n(self) -> int:
        return int(self.p0.shape[0])

    def to_z(self, p: np.ndarray) -> np.ndarray:
        return (p - self.lower) / self.scale

    def to_p(self, z: np.ndarray) -> np.ndarray:
        return self.lower + self.scale * z


    # ---- the design at p ----------------------------------------------------------------------
    def base_radius(self, p: np.ndarray) -> Any:
        return p[self.r_index] if self.r_index is not None else self.spec.cam.base_radius

    def offset(self, p: np.ndarray) -> Any:
        return p[self.e_index] if self.e_index is not None else self.spec.follower.offset

    def geometry(self, p: np.ndarray) -> tuple[Any, ...]:
        """The follower kind's geometric scalars at design p (:attr:`geometry_names`): the
        variables from p, the others the spec's."""
        return tuple(p[c] if c is not None else v for c, v in zip(self.geometry_cols, self._geometry_start))

    def orientation(self, p: np.ndarray) -> float:
        return float(p[self.b_index]) if self.b_index is not None else math.radians(self.spec.optimise.blank_orientation)

    def program_at(self, p: np.ndarray) -> MotionProgram:
        """The motion program of design ``p`` (new B-spline lifts; spans and lifts unchanged)."""
        curves = list(self.program.curves)
        for blk in self.blocks:
            x, y = blk.arrays(np.asarray(p, dtype=float))
            curves[blk.motion_index] = BSplineLift(blk.order, x, y)
        for pb in self.point_blocks:
            curves[pb.motion_index] = curve_at(pb, p)
        prog = self.program
        return MotionProgram(prog.starts, prog.spans, prog.levels, prog.lifts, prog.laws, prog.kinds, tuple(curves))

    def spec_at(self, p: np.ndarray) -> CamSpec:
        """The spec of design ``p``: control points written in each segment's own control_frame
        (and control_y in its own form: free lifts only, or all interior ones)."""
        p = np.asarray(p, dtype=float)
        changes: dict[str, Any] = {}
        for name, c in zip(self.geometry_names, self.geometry_cols):
            if c is not None:
                changes[GEOMETRY_PATHS[name]] = float(p[c])
        if self.b_index is not None:
            deg = math.degrees(p[self.b_index]) % 90.0
            changes["optimise.blank_orientation"] = float(deg)
        for blk in self.blocks:
            seg = self.spec.motion[blk.motion_index]
            x, y = blk.arrays(p)
            k = blk.motion_index
            if blk.x_cols.size:
                if (seg.control_frame or "relative_deg") == "relative_deg":
                    cx = np.degrees(x[1:-1])
                else:
                    origin = (math.radians(seg.control_start) if seg.control_start is not None
                              else float(self.program.starts[k]))
                    cx = x[1:-1] + origin
                changes[f"motion[{k}].control_x"] = [float(v) for v in cx]
            if blk.y_cols.size:
                n = blk.n_points - 1
                full = seg.control_y is not None and len(seg.control_y) == n - 1
                cy = y[1:-1] if full else y[blk.y_free]
                changes[f"motion[{k}].control_y"] = [float(v) for v in cy]
        for name, c in self.body_cols.items():
            changes[BODY_PATHS[name]] = float(p[c])
        for pb in self.point_blocks:
            changes[f"motion[{pb.motion_index}].points"] = [[float(a), float(s)]
                                                            for a, s in zip(pb.angles_deg, pb.lifts(p))]
        return self.spec.replace(**changes) if changes else self.spec

    def is_valid(self, p: np.ndarray) -> bool:
        """True when design p is a valid spec (every rule of the spec, e.g. the arm reaches the
        prime circle); the solver's geometry rows keep it so, this is the final guard."""
        return self.invalid_reason(p) is None

    def invalid_reason(self, p: np.ndarray) -> str | None:
        """The spec rule design p breaks (``field: rule``), or None."""
        try:
            self.spec_at(p)
        except SpecError as exc:
            return str(exc)
        return None

    # ---- linear constraints -----------------------------------------------------------------
    def _linear_constraints(self) -> tuple[np.ndarray, np.ndarray]:
        rows: list[np.ndarray] = []
        rhs: list[float] = []
        for blk in self.blocks:
            n = blk.n_points - 1
            if blk.x_cols.size:
                scale = blk.span / n
                col = {i: int(blk.x_cols[i - 1]) for i in range(1, n)}
                for i in range(n):                      # x_i − x_{i+1} ≤ −gap
                    a = np.zeros(self.n)
                    c = -self.gap
                    if i in col:
                        a[col[i]] += 1.0
                    else:
                        c -= blk.x[i]
                    if i + 1 in col:
                        a[col[i + 1]] -= 1.0
                    else:
                        c += blk.x[i + 1]
                    rows.append(a / scale)
                    rhs.append(c / scale)
            if blk.y_cols.size:
                sgn = 1.0 if blk.kind == "rise" else -1.0
                col = {int(i): int(c) for i, c in zip(blk.y_free, blk.y_cols)}
                for i in range(n):                      # sgn·(y_i − y_{i+1}) ≤ 0
                    if i not in col and i + 1 not in col:
                        continue
                    a = np.zeros(self.n)
                    c = 0.0
                    if i in col:
                        a[col[i]] += sgn
                    else:
                        c -= sgn * blk.y[i]
                    if i + 1 in col:
                        a[col[i + 1]] -= sgn
                    else:
                        c += sgn * blk.y[i + 1]
                    rows.append(a)
                    rhs.append(c)
        for pb in self.point_blocks:
            a, c = pb.monotonic_rows(self.n)
            rows.extend(a)
            rhs.extend(c)
        if not rows:
            return np.zeros((0, self.n)), np.zeros(0)
        return np.array(rows), np.array(rhs)

    def linear_values(self, p: np.ndarray) -> np.ndarray:
        """A·p − c (≤ 0 when the polygons are valid)."""
        return self.linear_A @ p - self.linear_c


def geometry_bounds(spec: CamSpec) -> dict[str, tuple[float, float]]:
    """The bounds (lower, upper) of every geometric design variable of ``spec``'s follower kind
    as the optimiser takes them — the ``[optimise]`` bounds given, the defaults for the others,
    widened to contain the start — by name: base_radius and offset (translating followers),
    pivot_distance and arm_length (oscillating), face_offset (an oscillating flat face; its
    arm_length when given).  For a GUI that shows the bounds before a run."""
    names = [n for n in kind_model(spec).geometry if n == "base_radius" or follower_variable_rule(spec, n) is None]
    probe = spec.replace(**{"optimise.variables": ", ".join(names), "optimise.objective": "area",
                            "optimise.algorithm": "auto"})
    space = DesignSpace(probe)
    return {n: (float(space.lower[c]), float(space.upper[c]))
            for n, c in zip(space.geometry_names, space.geometry_cols) if c is not None}

"""The optimiser of a cylindrical (barrel) cam: its own design, not the plane cams' model.

A cylindrical cam (:mod:`cam_workbench.generators.bodies.cylindrical`) keeps its motion; its size is the pitch
radius R_p (``cam.cylinder_radius``), the cylinder's outer radius R_o (``cam.outer_diameter``/2) and
the groove's ``groove.clearance`` c (width w = 2r + c).  Objective ``outer_diameter``: the smallest
cylinder, 2R_o.  Constraints, normalised g ≤ −``optimise.constraint_margin``, all from the design's
own check functions on its dense angles (``program.dense_angles(2001)``, as
:func:`~cam_workbench.generators.bodies.cylindrical.check_cylinder`):

* pressure angle at R_p, tan φ = s′/R_p:            max |φ|/φ_max − 1
* undercut of the developed centre line over the groove's depth (5 radii, R_o − depth … R_o):
                                                     1 − min ρ_c/(undercut_factor · w/2)
* R_p within the groove: R_o − depth ≤ R_p ≤ R_o;  the groove's bottom leaves ``groove.min_wall`` to
  the bore;  the groove leaves min_wall to both ends of the cylinder (the roller's path, translating or
  an oscillating arm's, is the spec's: the length is not varied).

The check values are maxima over samples (not differentiable in the usual sense), so the solver is
nlopt's derivative-free COBYLA on the scaled variables (z ∈ [0, 1]); a handful of variables, some
hundred evaluations of a few milliseconds.  The result is re-checked by the body's own
:func:`check_cylinder` (its report's ``checks``).
"""
from __future__ import annotations

import time
from dataclasses import replace
from typing import Any, Callable

import numpy as np

from ..bodies.cylindrical import CylinderLayout, CylindricalBody, check_cylinder, developed_curvature_radius, pressure_angles
from ..bodies.features import resolved
from ..checks.design import CheckResult, DesignChecks
from ..errors import CamError, SpecError
from ..motion.program import MotionProgram
from ..kinds import register_optimiser
from ..spec.model import CamSpec
from ..spec.optimise import CYLINDER_VARIABLES
from .driver import load_nlopt
from .result import OptimiseResult, Progress

#: spec path of each design variable
PATHS = {"cylinder_radius": "cam.cylinder_radius", "outer_diameter": "cam.outer_diameter",
         "clearance": "groove.clearance"}
#: dense samples per segment (as check_cylinder)
SAMPLES = 2001


def cylinder_variables(spec: CamSpec) -> tuple[str, ...]:
    """The design variables of a cylindrical ``spec``'s ``optimise.variables`` ("auto":
    cylinder_radius and outer_diameter).

    Raises:
        SpecError: ``optimise.variables`` naming a variable a cylindrical cam does not have.
    """
    text = spec.optimise.variables.strip()
    if text == "auto":
        return ("cylinder_radius", "outer_diameter")
    names = [t.strip() for t in text.replace(";", ",").split(",") if t.strip()]
    for n in names:
        if n not in CYLINDER_VARIABLES:
            raise SpecError("optimise.variables",
                            f"{n}: a cylindrical cam's design variables are {', '.join(CYLINDER_VARIABLES)} "
                            "(its motion and follower are not varied)")
    return tuple(n for n in CYLINDER_VARIABLES if n in names)


def _start(spec: CamSpec) -> dict[str, float]:
    lay = CylinderLayout.of(spec)
    return {"cylinder_radius": lay.pitch_radius, "outer_diameter": 2 * lay.outer_radius,
            "clearance": float(resolved(spec, "groove", "clearance"))}


def _bounds(spec: CamSpec, names: tuple[str, ...], start: dict[str, float]) -> tuple[np.ndarray, np.ndarray]:
    """[½, 2] × the start (clearance [0, 2 × the start]); the [optimise] bounds given override
    outer_diameter and clearance; widened to contain the start."""
    opt = spec.optimise
    lo, hi = [], []
    for n in names:
        v0 = start[n]
        a, b = (0.5 * v0, 2.0 * v0) if n != "clearance" else (0.0, 2.0 * v0 if v0 > 0 else spec.roller_radius)
        if n in ("outer_diameter", "clearance"):
            a = getattr(opt, f"{n}_min") if getattr(opt, f"{n}_min") is not None else a
            b = getattr(opt, f"{n}_max") if getattr(opt, f"{n}_max") is not None else b
        lo.append(min(a, v0)), hi.append(max(b, v0))
    return np.array(lo), np.array(hi)


def cylinder_constraints(spec: CamSpec, program: MotionProgram, values: dict[str, float]) -> dict[str, float]:
    """The normalised constraints g (≤ 0 feasible) of the cylindrical cam with ``values``
    (cylinder_radius, outer_diameter, clearance) — see the module docstring.  The roller's path
    (translating, or an oscillating arm's) is the spec's: the cylinder's length does not change."""
    rp, ro, c = values["cylinder_radius"], values["outer_diameter"] / 2, values["clearance"]
    depth = spec.groove.depth
    w2 = spec.roller_radius + c / 2
    wall = resolved(spec, "groove", "min_wall")
    th = program.dense_angles(SAMPLES)
    lay = replace(CylinderLayout.of(spec), pitch_radius=rp, outer_radius=ro, bottom_radius=ro - depth, half_width=w2)
    phi = float(np.max(np.abs(pressure_angles(lay, program, rp, th))))
    rc = min(float(np.min(developed_curvature_radius(lay, program, r, th)))
             for r in np.linspace(max(ro - depth, 1e-9), ro, 5))
    zlo, zhi = lay.path.z_range()
    length = spec.cam.length
    return {"pressure_angle": phi / spec.checks.max_pressure_angle - 1.0,
            "undercut": 1.0 - rc / (spec.checks.undercut_factor * w2),
            "pitch_below_outer": (rp - ro) / rp,
            "pitch_above_bottom": (ro - depth - rp) / rp,
            "bore_wall": (spec.cam.bore_diameter / 2 + wall - (ro - depth)) / rp,
            "bottom_end": (wall - (zlo - w2)) / length,
            "top_end": (wall - (length - zhi - w2)) / length}


def cylinder_checks(spec: CamSpec) -> DesignChecks:
    """The body's own dense checks (:func:`check_cylinder`, an undercut a failing ``undercut`` row)
    as :class:`DesignChecks`."""
    program = MotionProgram.from_spec(spec)
    rep = check_cylinder(spec, program, CylinderLayout.of(spec), refuse=False)["checks"]["results"]
    rows = [CheckResult(k, r["description"], r["kind"], r["value"], r["at_deg"], r["limit"], r["unit"],
                        r["status"]) for k, r in rep.items()]
    return DesignChecks(tuple(rows), {}, "dense", SAMPLES, spec.units, None)


@register_optimiser(CylindricalBody.kind)
def optimise_cylindrical(spec: CamSpec, progress: Callable[[Any], Any] | None = None,
                         cancel: Any = None) -> Any:
    """Minimise a cylindrical cam's outer diameter over cylinder_radius, outer_diameter and
    clearance with COBYLA (module docstring); an :class:`~cam_workbench.generators.optimise.result.OptimiseResult`.

    Raises:
        SpecError: ``optimise.objective`` other than outer_diameter, ``optimise.variables`` naming
            another variable or without outer_diameter, or ``optimise.algorithm`` other than auto
            or cobyla.
    """
    t0 = time.perf_counter()
    cfg = spec.optimise
    if cfg.objective != "outer_diameter":
        raise SpecError("optimise.objective", f"a cylindrical cam is optimised for outer_diameter (its cylinder), "
                                              f"got {cfg.objective!r}")
    if cfg.algorithm not in ("auto", "cobyla"):
        raise SpecError("optimise.algorithm", f"a cylindrical cam's checks are maxima over samples: auto or cobyla "
                                              f"(derivative-free), got {cfg.algorithm!r}")
    names = cylinder_variables(spec)
    if "outer_diameter" not in names:
        raise SpecError("optimise.variables", "objective outer_diameter needs outer_diameter among the variables")
    program = MotionProgram.from_spec(spec)
    start = _start(spec)
    lo, hi = _bounds(spec, names, start)
    scale = hi - lo
    p0 = np.array([start[n] for n in names])
    margin = cfg.constraint_margin
    history: list[dict[str, Any]] = []
    best: list[Any] = [None]

    def values_of(p: np.ndarray) -> dict[str, float]:
        return {**start, **dict(zip(names, (float(v) for v in p)))}

    def evaluate(z: np.ndarray) -> tuple[float, np.ndarray]:
        p = lo + scale * z
        g = np.array(list(cylinder_constraints(spec, program, values_of(p)).values()))
        f = values_of(p)["outer_diameter"]
        viol = float(np.max(g))
        history.append({"iteration": len(history) + 1, "objective": f, "max_violation": viol})
        if viol <= 0 and (best[0] is None or f < best[0][0]):
            best[0] = (f, p.copy())
        if progress is not None and progress(Progress(len(history), cfg.max_evaluations, "cobyla", f, viol,
                                                      best[0][0] if best[0] else None)) is False:
            raise _Stop
        if cancel is not None and cancel.is_set():
            raise _Stop
        return f, g

    nlopt = load_nlopt()
    n = len(names)
    ncons = len(cylinder_constraints(spec, program, start))
    opt = nlopt.opt(nlopt.LN_COBYLA, n)
    opt.set_lower_bounds(np.zeros(n))
    opt.set_upper_bounds(np.ones(n))
    opt.set_min_objective(lambda z, grad: evaluate(z)[0] / start["outer_diameter"])
    opt.add_inequality_mconstraint(lambda res, z, grad: res.__setitem__(slice(None), evaluate(z)[1] + margin),
                                   [0.0] * ncons)
    opt.set_maxeval(cfg.max_evaluations)
    opt.set_xtol_rel(cfg.xtol_rel)
    opt.set_ftol_rel(cfg.ftol_rel)
    status, solver_ok = "converged", True
    solver = "cobyla"
    try:
        opt.optimize((p0 - lo) / scale)
        solver = f"cobyla: {nlopt_result(opt.last_optimize_result())}"
    except _Stop:
        status, solver_ok, solver = "cancelled", False, "cobyla: cancelled"
    except (RuntimeError, ValueError, nlopt.RoundoffLimited) as exc:
        solver_ok, solver = False, f"cobyla: {exc}"
    p_best = best[0][1] if best[0] is not None else p0
    changes = {PATHS[k]: float(v) for k, v in zip(names, p_best)}
    if "cam.cylinder_radius" in changes:                 # cam.base_radius is the pitch radius here
        changes["cam.base_radius"] = changes["cam.cylinder_radius"]
    final = spec.replace(**changes)
    checks, initial_checks = cylinder_checks(final), cylinder_checks(spec)
    if status != "cancelled":
        if not checks.passed:
            status = "infeasible"
        elif len(history) >= cfg.max_evaluations:
            status = "budget exhausted"
        elif not solver_ok:
            status = "stopped"
    message = solver + ("" if checks.passed else f"; the final design FAILS the dense check: {', '.join(checks.failed)}")
    return OptimiseResult(
        spec=final, initial_spec=spec, objective="outer_diameter", algorithm=cfg.algorithm,
        initial_value=start["outer_diameter"], value=float(final.cam.outer_diameter), variables=tuple(PATHS[k] for k in names),
        initial_design=p0, design=p_best, history=history, evaluations=len(history), time_s=time.perf_counter() - t0,
        status=status, message=message, checks=checks, initial_checks=initial_checks,
        details={"constraint_margin": margin, "solver": "nlopt COBYLA (derivative-free) on the body's own checks"},
        solver_status=solver)


class _Stop(CamError):
    """Cancelled from the progress callback or the event."""


def nlopt_result(code: int) -> str:
    """nlopt's result code in words."""
    return {1: "success", 2: "stopval reached", 3: "ftol reached", 4: "xtol reached",
            5: "maxeval reached", 6: "maxtime reached"}.get(int(code), f"result {code}")


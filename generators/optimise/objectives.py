"""Objectives (thesis §5.2) on a :class:`~cam_workbench.generators.optimise.space.DesignSpace`.

Smooth ones return exact gradients (:class:`~cam_workbench.generators.optimise.model.SmoothModel`); the
machining times are piecewise constant in whole turns/blocks and return values only.

==================  ========================================================  ==========
objective           value                                                     gradient
==================  ========================================================  ==========
area                translating knife/roller: ½∮(R_b + s)² dθ, thesis Eq.     exact
                    4.21–4.27 (inside the pitch curve when e = 0; the thesis'
                    formula whatever e is); every other follower: the area
                    inside its design curve (an oscillating knife/roller's
                    pitch curve, a flat face's profile), ½|∮ F × V dθ|
profile_area        area inside the cam profile, A_pitch − r_f L + π r_f²     exact
                    (a flat face: its profile's area)
peak_acceleration   max |s″| over the nodes (epigraph: min t, ±s″/ref ≤ t)     exact
peak_pressure_angle max |φ| (epigraph)                                        exact
machining_time      thesis Eq. 4.20 on its staircase path                     none
gcode_time          the XY contour program's time (:func:`contour_time`)      none
size                a parallel indexer's cams' outer radius (the largest      none
                    profile radius over the plates; report.json
                    ``body.outer_radius``)
normal_force        a parallel indexer's peak roller load [N] (the contact    none
                    that carries the output's torque; report.json
                    ``indexer.drive.normal_force_peak_N``)
==================  ========================================================  ==========

``size`` and ``normal_force`` are a parallel indexer's (``cam.body = "parallel_indexer"``), minimised by
its own optimiser (:mod:`cam_workbench.generators.optimise.indexer`): every trial is a full design, so
:func:`make_objective` has no model of them; this module names them (:func:`describe`, :func:`label`,
:func:`report_key`, :data:`UNITS`) for :meth:`~cam_workbench.generators.optimise.result.OptimiseResult.report`
and the printouts as it names the plane cam's.

Smooth stand-ins used to reach a small feasible design before a machining time is polished
(``algorithm = "auto"``): the length of the thesis' curve r = R_b + s (machining_time) and the
pitch curve's length (gcode_time: the tool-centre path is its offset).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from ..cam_design import design_cam
from ..checks.areas import area_label
from ..errors import CamError
from ..kinds import follower_class_of
from ..machining.cutting_time import DEFAULT_TOLERANCE, contour_time, staircase_moves
from .kinds import kind_model
from .model import SmoothModel

PEAK = ("peak_acceleration", "peak_pressure_angle")
TIME = ("machining_time", "gcode_time")
SURROGATE = {"machining_time": "thesis_length", "gcode_time": "pitch_length"}

DESCRIPTIONS = {
    "area": "cam area, thesis Eq. 4.21-4.27: 1/2 int (R_b + s)^2 dtheta (inside the pitch curve for e = 0)",
    "profile_area": "area inside the roller profile (true cam cross-section without the bore)",
    "machining_time": "thesis cutting time, Eq. 4.20: S/feed + turn time x turns of its staircase path",
    "gcode_time": "time of the XY G-code contour: length/feed + block time x blocks",
    "peak_acceleration": "largest |s''| (reduced acceleration, per rad^2)",
    "peak_pressure_angle": "largest |pressure angle| [deg]",
    "thesis_length": "length of the thesis' machining curve r = R_b + s (smooth stand-in for machining_time)",
    "pitch_length": "pitch-curve length (smooth stand-in for gcode_time)",
    "outer_diameter": "groove cam's disc diameter cam.outer_diameter (rim wall >= groove.min_wall a constraint)",
    "size": "the cams' outer radius: the largest profile radius over the plates",
    "normal_force": "the peak roller load |T_out|/arm of the contact that carries the output's torque "
                    "(parallel_drive at indexer.output_inertia, indexer.friction_torque)",
}
#: "area" for every follower but the translating knife/roller (whose "area" is the thesis' Eq. 4.21)
AREA_DESIGN_CURVE = ("cam area: the exact area inside the design curve, 1/2 |int F x V dtheta| (an oscillating "
                     "knife/roller's pitch curve, a flat face's profile)")


def describe(name: str, spec: Any) -> str:
    """The objective ``name`` of ``spec`` in words (report.json's ``objective_description``)."""
    if name == "area" and kind_model(spec).area_integral != "thesis_area":
        return AREA_DESIGN_CURVE
    return DESCRIPTIONS[name]


#: each objective in a few words, as printouts name it beside its value (``area`` and
#: ``profile_area`` as report.json's ``areas`` names them: :data:`cam_workbench.generators.checks.areas.AREA_LABELS`)
LABELS = {
    "profile_area": "area inside the profile",
    "machining_time": "thesis cutting time (Eq. 4.20)",
    "gcode_time": "time of the XY G-code contour",
    "peak_acceleration": "largest |s″|",
    "peak_pressure_angle": "largest |pressure angle|",
    "thesis_length": "length of the thesis' curve r = R_b + s",
    "pitch_length": "pitch-curve length",
    "outer_diameter": "outer diameter (cam.outer_diameter)",
    "size": "outer radius of the cams",
    "normal_force": "peak roller load",
}
#: the report.json path (of the cam the objective is evaluated on) that holds each objective's value,
#: None where report.json holds no such number (a peak over the optimiser's nodes, a machining time)
REPORT_KEYS = {"profile_area": "areas.profile", "outer_diameter": "spec.cam.outer_diameter",
               "size": "body.outer_radius", "normal_force": "indexer.drive.normal_force_peak_N"}


def label(name: str, spec: Any) -> str:
    """The objective ``name`` of ``spec`` in a few words (report.json's ``objective_label``): "area"
    is the thesis' Eq. 4.21 area for a translating knife edge or roller, else the area inside the
    follower's design curve."""
    if name == "area":
        key = report_key(name, spec).removeprefix("areas.")
        return area_label(key, "pitch curve" if follower_class_of(spec).design_curve == "pitch" else "contact curve")
    return LABELS[name]


def report_key(name: str, spec: Any) -> str | None:
    """The path in report.json where the objective ``name`` of ``spec`` is (report.json's
    ``objective_key``): "area" → ``areas.thesis_eq_4_21`` (thesis Eq. 4.21) or ``areas.pitch_curve``
    (the area inside the design curve); None when report.json has no such number."""
    if name == "area":
        return "areas.thesis_eq_4_21" if kind_model(spec).area_integral == "thesis_area" else "areas.pitch_curve"
    return REPORT_KEYS.get(name)


#: each objective's unit ("length" is the spec's units)
UNITS = {"area": "length²", "profile_area": "length²", "machining_time": "s", "gcode_time": "s",
         "peak_acceleration": "length/rad²", "peak_pressure_angle": "deg", "thesis_length": "length",
         "pitch_length": "length", "outer_diameter": "length",
         # a parallel indexer's (designed in mm; its loads in N whatever the units)
         "size": "length", "normal_force": "N"}


@dataclass
class Objective:
    """One objective: ``value(p, grad)`` → (F, dF/dp or None) in physical units."""

    name: str
    model: SmoothModel
    value: Callable[[np.ndarray, bool], tuple[float, np.ndarray | None]]
    smooth: bool
    peak: Callable[[Any, Any], np.ndarray] | None = None   # (geometry, kin) → q, for the epigraph

    @property
    def description(self) -> str:
        return DESCRIPTIONS[self.name]


def make_objective(name: str, model: SmoothModel) -> Objective:
    """The objective ``name`` on ``model``'s design space."""
    sp = model.space
    spec = model.spec
    if name == "area":
        which = model.kind.area_integral
        return Objective(name, model, lambda p, g: model.integral(p, which, g), True)
    if name in ("thesis_length", "pitch_length"):
        return Objective(name, model, lambda p, g: model.integral(p, name, g), True)
    if name == "profile_area":
        return Objective(name, model, lambda p, g: model.profile_area(p, g), True)
    if name == "peak_acceleration":
        return Objective(name, model, _peak_value(model, "a"), True, peak=lambda geo, kin: kin.a)
    if name == "peak_pressure_angle":
        return Objective(name, model, _peak_value(model, "phi"), True,
                         peak=lambda geo, kin: np.rad2deg(model.local(geo, kin.s, kin.v, kin.a, False)["phi"][0]))
    if name == "outer_diameter":
        col = sp.body_cols["outer_diameter"]

        def diameter(p: np.ndarray, grad: bool) -> tuple[Any, np.ndarray | None]:
            g = np.zeros(sp.n) if grad else None
            if grad:
                g[col] = 1.0
            return p[col], g

        return Objective(name, model, diameter, True)
    if name == "machining_time":
        opt = spec.optimise
        eps = opt.machining_tolerance or DEFAULT_TOLERANCE[spec.units]
        per_min = spec.machining.feed_rate if spec.machining.feed_rate is not None else {"in": 12.0, "mm": 300.0}[spec.units]
        feed = per_min / 60.0

        def mtime(p: np.ndarray, grad: bool) -> tuple[float, None]:
            prog = sp.program_at(p)
            _, turns, length = staircase_moves(prog, float(sp.base_radius(p)), sp.orientation(p), eps, 2000)
            return length / feed + opt.turn_time * turns, None

        return Objective(name, model, mtime, False)
    if name == "gcode_time":
        def gtime(p: np.ndarray, grad: bool) -> tuple[float, None]:
            try:
                return contour_time(design_cam(sp.spec_at(p))).time, None
            except CamError:
                return float("nan"), None

        return Objective(name, model, gtime, False)
    if name in ("size", "normal_force"):
        raise ValueError(f"objective {name!r} is a parallel indexer's: its own optimiser minimises it "
                         "(cam_workbench.generators.optimise.indexer), not the plane cam's model")
    raise ValueError(f"unknown objective {name!r}")


def _peak_value(model: SmoothModel, which: str) -> Callable[[np.ndarray, bool], tuple[float, None]]:
    """max |q| over the nodes (the reported value; the solver minimises its epigraph)."""

    def f(p: np.ndarray, grad: bool) -> tuple[float, None]:
        geo = model.design_scalars(p)
        vals = []
        for sn in model.segments:
            kin = model.kinematics(sn, sn.params, p, False, key="nodes")
            if which == "a":
                vals.append(np.abs(kin.a))
            else:
                vals.append(np.abs(np.rad2deg(model.local(geo, kin.s, kin.v, kin.a, False)["phi"][0])))
        return float(np.max(np.concatenate([np.broadcast_to(v, (np.size(v),)) for v in vals]))), None

    return f

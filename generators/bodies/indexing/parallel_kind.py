"""The parallel indexer as a body kind (``cam.body = "parallel_indexer"``): its spec rules, its design
(:class:`ParallelIndexerDesign`: the geometry of :mod:`.parallel`, the plates of :mod:`.parallel_body`,
the drive of :mod:`.parallel_drive`) and its checks, the numbers report.json holds.

The checks (report.json ``checks.results``):

* ``pressure_angle`` — the pressure angle of the contact that carries the output's torque (the
  driving one where T_out ≥ 0, the holding-back one where it decelerates), over the index where
  |T_out| exceeds 5 % of its peak (T_out = J·ψ''·ω² + T_f·sign ψ', or ψ'' without a load), against
  ``indexer.max_pressure_angle``; the largest driving pressure angle over the whole index (pure
  geometry at its ends) is reported beside it (``pressure_angle_index``, no limit);
* ``undercut`` — the cams' smallest convex pitch radius of curvature against
  ``checks.undercut_factor`` × the roller radius;
* ``clearance`` — the idle rollers' smallest gap to any cam (> 0: none touches a cam it is not
  engaged with);
* ``locking`` — the worst pressure angle of the best forward- and backward-holding contact over the
  turn (< 90°: positive drive, the turret held both ways at every input angle);
* ``contact_stress`` — the carrying contact's peak Hertz stress against ``material.allowable_stress``
  (with a load: ``indexer.output_inertia``);
* ``continuity`` — the program's junctions (:func:`cam_workbench.generators.checks.design.continuity_check`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ...checks.design import continuity_check, unit_labels
from ...checks.status import NO_LIMIT
from ...errors import SpecError
from ...kinds import register_body
from ...motion.program import MotionProgram
from ...spec.indexer import indexer_value
from ...spec.toml_io import spec_digest
from ...studies.table import checks_row
from ..base import BodyGeometry
from . import from_spec
from .parallel import ParallelDesign, ParallelIndexer, design_parallel, output_angle_from_profile, turret_angle
from .parallel_body import IndexerBody, indexer_body
from .parallel_drive import output_torque, parallel_drive
from .kind_common import IndexerBodyCommon, drive_summary, in_spec_words, result, turn_error
from .sizing import DriveSizing
from .turret_train import turret_follower

#: input angles the design samples over the turn, and the output angle's check from the profiles
SAMPLES, RECOVERY_SAMPLES = 721, 721
#: the overlap of blocked turret angles [rad] beyond which the profiles do not fix ψ (see _recovery_summary)
UNDETERMINED_SLACK = 1e-6
#: the share of the peak output torque above which the carrying contact's pressure angle counts
LOAD_FRACTION = 0.05


def indexer_of(spec: Any) -> ParallelIndexer:
    """The :class:`.parallel.ParallelIndexer` of a spec (SpecError naming the spec's field)."""
    fields = from_spec.geometry_fields(spec, MotionProgram.from_spec(spec))
    return ParallelIndexer(**fields, pitch_radius=float(spec.indexer.pitch_radius),
                           cams=int(indexer_value(spec, "cams")))


def _design_geometry(spec: Any, strict: bool) -> ParallelDesign:
    try:
        return design_parallel(indexer_of(spec), SAMPLES, strict=strict)
    except SpecError as exc:
        raise in_spec_words(spec, exc) from None


@dataclass(frozen=True)
class ParallelIndexerDesign:
    """A designed parallel indexer (plain values; no CAD kernel): the spec, the turret's motion
    program, the geometry (:class:`.parallel.ParallelDesign`), the plates (``cams_body``, whose
    ``geometry`` is ``body``), the drive (None without a load) and the checks."""

    spec: Any
    program: MotionProgram
    geometry: ParallelDesign
    cams_body: IndexerBody
    drive: DriveSizing | None
    checks_report: dict
    #: not a plane cam of one pitch curve: two or three plates, each its own profile
    plane = False
    instead_of_plane_curves = ("it has one profile per plate: use design.cams_body.loops for each plate's exact "
                               "dwell arc and fitted flanks, design.geometry.cams[k].profile for exact profile "
                               "points, solid() for the plates, or export_dxf() for the drawing instead")
    bspline = None

    @property
    def body(self) -> BodyGeometry:
        """The plates and spacers as prisms (the kernel's and the drawing's plain data)."""
        return self.cams_body.geometry

    @property
    def follower(self) -> Any:
        """The train the dynamics drive: the turret (:class:`.turret_train.TurretFollower`)."""
        return turret_follower(self.spec)

    @property
    def volume(self) -> float:
        return self.body.volume

    @property
    def area(self) -> float:
        """The top face's area (the last plate at z = cam.thickness) [mm²]."""
        return self.body.face_area_at(self.spec.cam.thickness)

    @cached_property
    def recovered(self) -> Any:
        """The turret angle recovered from the built profiles at RECOVERY_SAMPLES input angles."""
        ix = self.geometry.indexer
        theta = float(ix.index_start) + np.linspace(0.0, 2 * math.pi, RECOVERY_SAMPLES)
        return output_angle_from_profile(self.geometry, theta)

    def label(self) -> str:
        """One line that identifies the indexer: its body, its turret and its numbers (mm)."""
        return (f"parallel_indexer cam, lengths in mm: {self._turret_label()}; "
                f"{ParallelIndexerBody.label(self.spec)}")

    def _turret_label(self) -> str:
        ix = self.geometry.indexer
        return (f"turret of {int(ix.stations)} stations × {int(ix.cams)} planes, rollers r = "
                f"{float(ix.roller_radius):g} on R_p = {float(ix.pitch_radius):g}, C = {float(ix.centre_distance):g}")

    def summary(self) -> dict[str, Any]:
        spec, g = self.spec, self.geometry
        ix = g.indexer
        res = self.checks_report["results"]
        rec = self.recovered
        maxima = self.program.maxima(spec.cam.speed_rpm * 2 * np.pi / 60)
        pa = res["pressure_angle"]
        geometry = g.summary()
        body = {"kind": "parallel_indexer", "closure": "form", "cams": int(ix.cams),
                "plate_thickness": spec.cam.thickness, "gap": indexer_value(spec, "gap"),
                "spacer_radius": self.cams_body.spacer_radius, "bore_diameter": spec.cam.bore_diameter,
                "z_range": list(self.body.z_range),
                "outer_radius": max(float(np.max(np.hypot(*c.profile.T))) for c in g.cams),
                "flank_fit_error": {"value": self.cams_body.fit_error, "unit": "mm",
                                    "what": "fitted flank B-splines vs the exact offset of the roller loci, "
                                            "31 points per knot span"},
                "approximation": "dwell parts exact arcs; flanks clamped cubic B-splines fitted to the exact "
                                 "offset (not rational curves for these laws), error measured",
                "flank_nodes": self.cams_body.geometry.extra["flank_nodes"]}
        out = {
            "units": spec.units,
            "spec_digest": spec_digest(spec),
            "pressure_angle": {"max_deg": pa["value"], "at_deg": pa["at_deg"],
                               "formula": "cos φ = |arm_P|/R_p, the contact carrying the output torque (arm_P its "
                                          "moment arm about the turret axis)",
                               "index_max_deg": res["pressure_angle_index"]["value"],
                               "index_max_at_deg": res["pressure_angle_index"]["at_deg"]},
            "follower": {"kind": "roller", "motion": "turret", "roller_radius": float(ix.roller_radius),
                         "label": self._turret_label()},
            "motion": {"lift_unit": "deg", "advance_deg": self.program.advance,
                       "max_lift": self.program.advance, "max_velocity": maxima["velocity"],
                       "max_acceleration": maxima["acceleration"], "max_jerk": maxima["jerk"],
                       **self.program.report()},
            "area": self.area,
            "volume": self.volume,
            "checks": self.checks_report,
            "body": {**body, "volume": self.volume, "top_face_area": self.area},
            "indexer": {
                "type": "parallel",
                "geometry": geometry,
                "motion_from_geometry": _recovery_summary(rec, ix),
                "drive": None if self.drive is None else drive_summary(spec, self.drive),
            },
        }
        return out


def _recovery_summary(rec: Any, ix: ParallelIndexer) -> dict[str, Any]:
    """report.json's ``indexer.motion_from_geometry``: the turret angle recovered from the built
    profiles against the law, where the profiles determine it.  Where an engaged roller runs almost
    along its profile (a pressure angle near 90°) the profile polylines' chord sag (1e-5 mm) blocks
    a band of turret angles wider than the feasible one (the slack < 0): there the profiles alone
    do not fix ψ, and those input angles are counted, not compared."""
    determined = rec.slack >= -UNDETERMINED_SLACK
    err = rec.psi - turret_angle(ix, rec.theta)[0]
    return {"max_error_rad": turn_error(err[determined], ix.station_angle) if determined.any() else None,
            "samples": RECOVERY_SAMPLES, "undetermined_samples": int(np.count_nonzero(~determined)),
            "least_slack_rad": float(np.min(rec.slack)), "max_slack_rad": float(np.max(rec.slack)),
            "what": "the turret angle recovered from the built profiles (a contact solve on the profiles alone) "
                    "against the law, at the input angles where the profiles fix it (slack ≥ "
                    f"−{UNDETERMINED_SLACK:g} rad)"}


def parallel_checks(spec: Any, g: ParallelDesign, drive: DriveSizing | None) -> dict[str, Any]:
    """report.json's ``checks`` of a parallel indexer (see the module docstring)."""
    ix = g.indexer
    deg = math.degrees
    rel = g.theta - float(ix.index_start)
    idx = (rel >= 0) & (rel <= float(ix.index_angle))
    load = from_spec.load_arguments(spec)
    t_out = output_torque(ix, g.theta, load)
    peak = float(np.max(np.abs(t_out[idx]))) if idx.any() else 0.0
    mask = idx & (np.abs(t_out) > LOAD_FRACTION * peak)
    carried = np.where(t_out >= 0, g.driving_angle, g.holding_angle)
    carried = np.where(mask, np.where(np.isfinite(carried), carried, math.pi / 2), -np.inf)
    i_c = int(np.argmax(carried))
    index_pa = np.where(idx, np.where(np.isfinite(g.driving_angle), g.driving_angle, math.pi / 2), -np.inf)
    i_i = int(np.argmax(index_pa))
    limit = indexer_value(spec, "max_pressure_angle")
    results: dict[str, Any] = {
        "pressure_angle": result(
            f"Pressure angle of the contact carrying the output torque, where |T_out| > {LOAD_FRACTION:.0%} of "
            "its peak over the index", "max", deg(float(carried[i_c])), deg(float(g.theta[i_c])) % 360.0, limit,
            "deg", note="indexer.max_pressure_angle is the limit"),
        "pressure_angle_index": result(
            "Largest driving pressure angle over the whole index (at its ends the dwell contact's geometry, "
            "whatever the law)", "max", deg(float(index_pa[i_i])), deg(float(g.theta[i_i])) % 360.0, None, "deg",
            no_limit="reported, not checked: at the index's ends no torque is carried"),
    }
    best = (math.inf, 0.0)
    for c in g.cams:
        r = c.profile_radius + float(ix.roller_radius)
        ok = np.isfinite(c.profile_radius) & (c.profile_radius > -float(ix.roller_radius)) & (r > 0)
        if ok.any():
            k = int(np.argmin(np.where(ok, r, np.inf)))
            if r[k] < best[0]:
                best = (float(r[k]), deg(float(c.profile_tau[k])) % 360.0)
    factor = spec.checks.undercut_factor
    results["undercut"] = result(
        "Smallest convex radius of curvature of the cams' pitch curves, against undercut_factor × roller radius",
        "min", best[0], best[1], factor * float(ix.roller_radius), "mm")
    clear = g.clearance
    results["clearance"] = result(
        "Smallest gap between a roller that is not engaged and any cam of its plane", "min", float(clear.gap),
        deg(clear.theta) % 360.0, 0.0, "mm", note=f"cam {clear.cam}, roller {clear.roller}")
    lock = g.locked
    worst = max(lock.forward_angle, lock.backward_angle)
    at = lock.forward_theta if lock.forward_angle >= lock.backward_angle else lock.backward_theta
    results["locking"] = result(
        "Worst pressure angle of the best contact holding the turret each way (positive drive below 90°)",
        "max", deg(worst), deg(at) % 360.0, 90.0 - 1e-9, "deg")
    if drive is not None:
        allow = spec.material.allowable_stress
        stress = drive.contact_stress_peak / 1e6
        results["contact_stress"] = result(
            "Peak Hertz contact stress of the contact carrying the output torque", "max", stress,
            deg(drive.contact_stress_peak_at + float(ix.index_start)) % 360.0 if math.isfinite(stress) else None,
            allow, "MPa",
            no_limit=NO_LIMIT.format(field="material.allowable_stress"))
    cont = continuity_check(g_program(spec), spec.checks.min_continuity, unit_labels(spec.units, "angle"))
    if cont is not None:
        results["continuity"] = cont.to_dict()
    failed = [k for k, r in results.items() if r["status"] == "fail"]
    return {"passed": not failed, "failed": failed, "sampling": "per_turn", "samples_per_turn": SAMPLES,
            "points": SAMPLES, "results": results, "extremes": {}}


def g_program(spec: Any) -> MotionProgram:
    """The turret's motion program (advancing by 360°/N)."""
    return MotionProgram.from_spec(spec)


def _drive(spec: Any, g: ParallelDesign) -> DriveSizing | None:
    load = from_spec.load_arguments(spec)
    return None if load is None else parallel_drive(g, **load)


@register_body
class ParallelIndexerBody(IndexerBodyCommon):
    """A parallel indexer: two or three plate cams on the input shaft driving a turret."""

    kind = "parallel_indexer"
    title = "Parallel indexer"
    plane = False
    roller_within_base = True
    closure = "form"
    #: the dynamics drive the output train (generators/dynamics/turret.py), not a follower
    dynamics_train = "turret"
    drive_note = ("the plates hold the turret both ways: one roller drives it on while another holds it back "
                  "(the contact that carries the torque changes where the output starts to decelerate)")
    own_fields = ()
    size_field = "indexer.centre_distance"
    optimise_objectives = ("size", "normal_force")
    optimise_variables = ()
    drawing_label = None
    modules = ("cam_workbench.generators.bodies.indexing.parallel", "cam_workbench.generators.bodies.indexing.from_spec",
               "cam_workbench.generators.bodies.indexing.parallel_body")

    @staticmethod
    def validate(spec: Any) -> None:
        from_spec.validate_common(spec, indexer_of, MotionProgram.from_spec(spec))

    @staticmethod
    def design(spec: Any, progress: Any = None) -> ParallelIndexerDesign:
        """The parallel indexer of ``spec`` (SpecError naming the field when it cannot be built)."""
        g = _design_geometry(spec, strict=True)
        try:
            cams = indexer_body(g, spec.cam.thickness, indexer_value(spec, "gap"), spec.cam.bore_diameter,
                                None if spec.indexer.spacer_diameter is None else spec.indexer.spacer_diameter / 2)
        except SpecError as exc:
            raise in_spec_words(spec, exc) from None
        drive = _drive(spec, g)
        return ParallelIndexerDesign(spec, g_program(spec), g, cams, drive, parallel_checks(spec, g, drive))

    @staticmethod
    def label(spec: Any) -> str:
        ix = spec.indexer
        step = from_spec.index_segment(spec)
        return (f"{ix.stations} stations, index {math.degrees(step[2]):g}°, C {ix.centre_distance:g}, R_p "
                f"{ix.pitch_radius:g}, {ix.cams} plates {spec.cam.thickness:g} thick")

    @staticmethod
    def own_checks(spec: Any) -> dict[str, Any]:
        """The checks without refusing a turret that is not held or a roller that hits a cam (they fail)."""
        g = _design_geometry(spec, strict=False)
        return parallel_checks(spec, g, _drive(spec, g))

    @staticmethod
    def remedy_words(spec: Any, check: str) -> str | None:
        return REMEDY_WORDS.get(check)

    @staticmethod
    def study_row(summary: Any, base_radius: float) -> dict[str, Any]:
        geo = summary["indexer"]["geometry"]
        row = {"units": summary["units"], "follower": summary["follower"]["label"], "base_radius": float(base_radius),
               "stations": geo["stations"], "centre_distance": geo["centre_distance_mm"],
               "pressure_angle_deg": summary["pressure_angle"]["max_deg"],
               "pressure_angle_at_deg": summary["pressure_angle"]["at_deg"],
               "clearance": geo["clearance_mm"], "outer_radius": summary["body"]["outer_radius"],
               "area": summary["area"], "volume": summary["volume"]}
        row.update(checks_row(summary["checks"]))
        return row


#: what moves each failing check of an indexer, in words (no single field is searched yet)
REMEDY_WORDS = {
    "pressure_angle": "a larger indexer.centre_distance relative to indexer.pitch_radius, a longer index "
                      "(the rise's angle), fewer stations or a third plate (indexer.cams = 3); "
                      "`cam-workbench optimise` searches C, R_p and r_r",
    "undercut": "a smaller follower.roller_radius or a larger indexer.pitch_radius and indexer.centre_distance",
    "clearance": "a smaller follower.roller_radius or a larger indexer.centre_distance",
    "locking": "a larger indexer.centre_distance or a longer index (the rise's angle)",
    "contact_stress": "a wider roller (follower.roller_width), a larger roller or turret, a stronger material "
                      "(material.allowable_stress), or a lighter output (indexer.output_inertia)",
}

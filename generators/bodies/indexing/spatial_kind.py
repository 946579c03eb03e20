"""The barrel and globoidal indexers as body kinds (``cam.body`` = "barrel_indexer",
"globoidal_indexer"): their spec rules, their design (:class:`SpatialIndexerDesign`: the geometry of
:mod:`.spatial`, the flank surfaces of :mod:`.spatial_surfaces`, the drive of :mod:`.spatial_drive`)
and their checks, the numbers report.json holds.

The spec (docs/indexing.md, "The spec"): ``[indexer]`` holds the turret (``stations``,
``centre_distance``, the barrel's ``pitch_radius``, ``roller_start``/``roller_end`` the rollers'
working length) and the rib (the barrel's ``root_radius``/``outer_radius`` cylinders, the globoid's
``tip_radius``/``root_radius`` globoids); ``cam.thickness`` is the cam's length along its axis (the
geometry's ``cam_width``, centred on z = 0); ``follower.roller_width`` defaults to the working
length.

The checks (report.json ``checks.results``, over the design's input angles):

* ``pressure_angle`` — the driving contact's: at each input angle of the index the engaged driving
  contact line whose largest pressure angle along its length is least, that angle; its largest over
  the index, against ``indexer.max_pressure_angle``; the largest over every engaged contact
  (``pressure_angle_contacts``: a leaving roller's last contact reaches high angles while another
  drives) is reported beside it, not checked;
* ``undercut`` — the envelope's regularity margin μ (> 0: a regular flank, ≤ 0 an undercut; 1 −
  r_r/ρ for a roller inside a plane path of radius ρ), its smallest over every engaged contact;
* ``rib_thickness`` — the rib's smallest thickness between its flanks (> 0);
* ``locking`` — the fewest engaged contacts holding the turret each way at any input angle
  (≥ 1: positive drive);
* ``contact_stress`` — the carrying contact's peak Hertz stress (with a load) against
  ``material.allowable_stress``;
* ``continuity`` — the program's junctions.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ...checks.design import continuity_check, unit_labels
from ...checks.status import NO_LIMIT
from ...errors import NotAvailable, SpecError
from ...kinds import register_body
from ...motion.program import MotionProgram
from ...spec.indexer import indexer_value
from ...spec.toml_io import spec_digest
from ...studies.table import checks_row
from . import from_spec
from .kind_common import IndexerBodyCommon, drive_summary, in_spec_words, result, turn_error
from .sizing import DriveSizing
from .spatial import (BarrelIndexer, GloboidalIndexer, SpatialDesign, design_barrel, design_globoidal,
                      output_angle_from_surface, turret_angle)
from .spatial_drive import spatial_drive
from .spatial_surfaces import FlankSurfaces, flank_surfaces
from .spatial_volume import RibNotBounded, VolumeEstimate, cam_volume
from .turret_train import turret_follower

#: input angles over the turn, points along each roller, and the output angle's check from the flanks
SAMPLES, LENGTHS, RECOVERY_SAMPLES = 721, 9, 361


def barrel_of(spec: Any) -> BarrelIndexer:
    """The :class:`.spatial.BarrelIndexer` of a spec (SpecError naming the spec's field)."""
    ix = spec.indexer
    fields = from_spec.geometry_fields(spec, MotionProgram.from_spec(spec))
    return BarrelIndexer(**fields, pitch_radius=float(ix.pitch_radius),
                         roller_start=float(ix.roller_start), roller_end=float(ix.roller_end),
                         root_radius=float(ix.root_radius), outer_radius=float(ix.outer_radius),
                         cam_width=float(spec.cam.thickness),
                         roller_cone_angle=math.radians(float(indexer_value(spec, "roller_cone_angle"))))


def globoidal_of(spec: Any) -> GloboidalIndexer:
    """The :class:`.spatial.GloboidalIndexer` of a spec (SpecError naming the spec's field)."""
    ix = spec.indexer
    fields = from_spec.geometry_fields(spec, MotionProgram.from_spec(spec))
    return GloboidalIndexer(**fields, roller_start=float(ix.roller_start),
                            roller_end=float(ix.roller_end), tip_radius=float(ix.tip_radius),
                            root_radius=float(ix.root_radius), cam_width=float(spec.cam.thickness),
                            roller_cone_angle=math.radians(float(indexer_value(spec, "roller_cone_angle"))))


def geometry_summary(g: SpatialDesign) -> dict[str, Any]:
    """report.json's ``indexer.geometry``: :meth:`.spatial.SpatialDesign.summary` (its
    ``roller_cone_angle_deg`` γ among the indexer's fields) with :func:`cone_geometry`'s entries."""
    return {**g.summary(), **cone_geometry(g.indexer)}


def cone_geometry(ix: BarrelIndexer | GloboidalIndexer) -> dict[str, Any]:
    """report.json's ``indexer.geometry`` entries of the rollers' cone: for γ ≠ 0 the roller's radii r(t0), r(t1) (``roller_radius_start``,
    ``roller_radius_end`` [mm]; ``roller_radius`` r_r is the middle's) and the cone apex's axis
    parameter ``roller_cone_apex_t`` = t_m − r_r/tan γ [mm] (t_m = (t0 + t1)/2)."""
    out: dict[str, Any] = {}
    if ix.taper != 0.0:
        t0, t1 = float(ix.roller_start), float(ix.roller_end)
        out["roller_radius_start"] = float(ix.radius_at(t0))
        out["roller_radius_end"] = float(ix.radius_at(t1))
        out["roller_cone_apex_t"] = 0.5 * (t0 + t1) - float(ix.roller_radius) / ix.taper
    return out


def roller_words(ix: BarrelIndexer | GloboidalIndexer) -> str:
    """The rollers in words: "rollers r = 12 over t = 74–96", or for a cone "conical rollers
    r = 10.59–13.41 (γ 8°) over t = 74–96" (its radii at t0 and t1)."""
    span = f"over t = {float(ix.roller_start):g}–{float(ix.roller_end):g}"
    gamma = float(ix.roller_cone_angle)
    if gamma == 0.0:
        return f"rollers r = {float(ix.roller_radius):g} {span}"
    r0, r1 = (float(ix.radius_at(float(t))) for t in (ix.roller_start, ix.roller_end))
    return f"conical rollers r = {r0:.4g}–{r1:.4g} (γ {math.degrees(gamma):.4g}°) {span}"


def _spec_field(exc: SpecError) -> SpecError:
    """The geometry's ``indexer.cam_width`` is the spec's ``cam.thickness``."""
    if exc.field == "indexer.cam_width":
        return SpecError("cam.thickness", exc.rule.replace("indexer.cam_width", "cam.thickness"))
    return exc


@dataclass(frozen=True)
class SpatialIndexerDesign:
    """A designed barrel or globoidal indexer (plain values; no CAD kernel): the spec, the turret's
    motion program, the geometry (:class:`.spatial.SpatialDesign`), the flank surfaces, the drive
    (None without a load) and the checks."""

    spec: Any
    program: MotionProgram
    geometry: SpatialDesign
    surfaces: FlankSurfaces
    drive: DriveSizing | None
    checks_report: dict
    #: not a plane cam: a rib of B-spline flank surfaces
    plane = False
    instead_of_plane_curves = ("its rib's flanks are surfaces: use design.surfaces (B-spline surfaces within "
                               "1 µm of the exact envelope), design.geometry.sheets (exact contact-line points), "
                               "or export_dxf() for the drawing instead")
    bspline = None
    #: no prisms: the kernel builds the rib from its surfaces
    body = None

    @property
    def follower(self) -> Any:
        """The train the dynamics drive: the turret (:class:`.turret_train.TurretFollower`)."""
        return turret_follower(self.spec)

    @property
    def fit_error(self) -> float:
        """The flank surfaces' largest distance from the exact envelope [mm] (measured)."""
        return max(float(f.summary()["max_error_mm"]) for f in self.surfaces.flanks)

    @cached_property
    def volume_estimate(self) -> VolumeEstimate:
        """The cam's volume [mm³]: the core in closed form (less the bore) plus the rib integrated on a
        grid of the exact envelope, with its error estimate (:mod:`.spatial_volume`)."""
        return cam_volume(self.geometry, 0.5 * float(self.spec.cam.bore_diameter))

    @property
    def volume(self) -> float:
        """The cam's volume [mm³] (:attr:`volume_estimate`: not exact, its error estimated)."""
        return self.volume_estimate.value

    @property
    def area(self) -> float:
        """No exact end-face area: NotAvailable (the end planes cut the rib's fitted flanks)."""
        raise NotAvailable(f"Cam.area: a {self.spec.cam.body} cam has no exact top-face area — its end faces cut "
                           "the rib's fitted flank surfaces: use volume (the grid integral of the exact envelope, "
                           "its error in report.json body.volume) or solid() instead")

    @cached_property
    def recovered(self) -> Any:
        """The turret angle recovered from the sampled flanks at RECOVERY_SAMPLES input angles."""
        ix = self.geometry.indexer
        theta = float(ix.index_start) + np.linspace(0.0, 2 * math.pi, RECOVERY_SAMPLES)
        return output_angle_from_surface(self.geometry, theta)

    def label(self) -> str:
        ix = self.geometry.indexer
        return (f"{self.spec.cam.body} cam, lengths in mm: turret of {int(ix.stations)} stations, "
                f"{roller_words(ix)}; {body_of_design(self).label(self.spec)}")

    def summary(self) -> dict[str, Any]:
        spec, g = self.spec, self.geometry
        ix = g.indexer
        res = self.checks_report["results"]
        rec = self.recovered
        maxima = self.program.maxima(spec.cam.speed_rpm * 2 * np.pi / 60)
        pa = res["pressure_angle"]
        ok = np.isfinite(rec.psi)
        body = {"kind": spec.cam.body, "closure": "form", "cam_width": spec.cam.thickness,
                "bore_diameter": spec.cam.bore_diameter,
                "flank_fit_error": {"value": self.fit_error, "unit": "mm",
                                    "what": "bicubic B-spline flank surfaces vs the exact envelope of the rollers, "
                                            "measured between their nodes"},
                "approximation": "flanks: the rollers' envelope (contact lines in closed form) interpolated by "
                                 "bicubic B-spline surfaces, error measured",
                "surfaces": self.surfaces.summary(),
                "volume": {"value": self.volume_estimate.value, "core": self.volume_estimate.core,
                           "rib": self.volume_estimate.rib, "error": self.volume_estimate.error, "unit": "mm³",
                           "what": self.volume_estimate.what}}
        return {
            "units": spec.units,
            "volume": self.volume,
            "spec_digest": spec_digest(spec),
            "pressure_angle": {"max_deg": pa["value"], "at_deg": pa["at_deg"],
                               "contacts_max_deg": res["pressure_angle_contacts"]["value"],
                               "contacts_max_at_deg": res["pressure_angle_contacts"]["at_deg"],
                               "formula": "cos φ = |n·τ|: the contact normal against the roller axis point's path "
                                          "about the turret axis"},
            "follower": {"kind": "roller", "motion": "turret", "roller_radius": float(ix.roller_radius),
                         "label": f"turret of {int(ix.stations)} stations, {roller_words(ix)}, "
                                  f"C = {float(ix.centre_distance):g}"},
            "motion": {"lift_unit": "deg", "advance_deg": self.program.advance,
                       "max_lift": self.program.advance, "max_velocity": maxima["velocity"],
                       "max_acceleration": maxima["acceleration"], "max_jerk": maxima["jerk"],
                       **self.program.report()},
            "checks": self.checks_report,
            "body": body,
            "indexer": {
                "type": "barrel" if isinstance(ix, BarrelIndexer) else "globoidal",
                "geometry": geometry_summary(g),
                "motion_from_geometry": {
                    "max_error_rad": turn_error(rec.psi[ok] - turret_angle(ix, rec.theta[ok])[0], ix.station_angle),
                    "samples": int(np.count_nonzero(ok)),
                    "what": "the turret angle recovered from the sampled flank surfaces (the roller "
                            f"{'cylinder' if float(ix.roller_cone_angle) == 0.0 else 'cone'} tangent to them) "
                            "against the law"},
                "drive": None if self.drive is None else drive_summary(spec, self.drive),
            },
        }


def spatial_checks(spec: Any, g: SpatialDesign, drive: DriveSizing | None) -> dict[str, Any]:
    """report.json's ``checks`` of a barrel or globoidal indexer (see the module docstring)."""
    deg = math.degrees
    ix = g.indexer

    def at(e: Any) -> float | None:
        return deg(e.theta) % 360.0 if math.isfinite(e.theta) else None

    drv, every = g.max_driving_angle, g.max_pressure_angle
    results: dict[str, Any] = {
        "pressure_angle": result(
            "Pressure angle of the driving contact over the index (the engaged driving line whose largest angle "
            "along it is least)", "max", deg(drv.value), at(drv), indexer_value(spec, "max_pressure_angle"), "deg",
            note="indexer.max_pressure_angle is the limit"),
        "pressure_angle_contacts": result(
            "Largest pressure angle over every engaged contact (a leaving roller's last contact)", "max",
            deg(every.value), at(every), None, "deg",
            no_limit="reported, not checked: another contact drives where it is largest"),
        "undercut": result(
            "Smallest regularity margin of the flank envelope (> 0: regular; 1 − r_r/ρ for a plane path)",
            "min", float(g.min_margin.value), at(g.min_margin), 0.0, ""),
        "rib_thickness": result("Smallest thickness of the rib between its flanks", "min",
                                float(g.min_rib_thickness.value), at(g.min_rib_thickness), 0.0, "mm"),
    }
    counts = g.engaged.sum(axis=0)                  # (2, S): engaged contacts of side +1 (holding), −1 (driving)
    fewest = counts.min(axis=0)
    i = int(np.argmin(fewest))
    results["locking"] = result("Fewest engaged contacts holding the turret each way (positive drive: ≥ 1)", "min",
                                float(fewest[i]), deg(float(g.theta[i])) % 360.0, 1.0, "contacts")
    if drive is not None:
        stress = drive.contact_stress_peak / 1e6
        results["contact_stress"] = result(
            "Peak Hertz contact stress of the contact carrying the output torque", "max", stress,
            deg(drive.contact_stress_peak_at + float(ix.index_start)) % 360.0 if math.isfinite(stress) else None,
            spec.material.allowable_stress, "MPa", no_limit=NO_LIMIT.format(field="material.allowable_stress"))
    cont = continuity_check(MotionProgram.from_spec(spec), spec.checks.min_continuity, unit_labels(spec.units, "angle"))
    if cont is not None:
        results["continuity"] = cont.to_dict()
    failed = [k for k, r in results.items() if r["status"] == "fail"]
    return {"passed": not failed, "failed": failed, "sampling": "per_turn", "samples_per_turn": SAMPLES,
            "points": SAMPLES * LENGTHS, "results": results, "extremes": {}}


class SpatialIndexerBody(IndexerBodyCommon):
    """What the barrel and globoidal indexers share; each declares its own capabilities."""

    #: a flank that leaves the cam before the root: the field to change and how (each body's own)
    rib_escape: tuple[str, str]
    closure = "form"
    #: the dynamics drive the output train (generators/dynamics/turret.py), not a follower
    dynamics_train = "turret"
    drive_note = ("the rib holds the turret both ways: one roller side drives it on while another holds it back")
    own_fields = ()
    size_field = "indexer.centre_distance"
    optimise_objectives = ()
    optimise_variables = ()
    drawing_label = None
    plane = False
    roller_within_base = False

    @staticmethod
    def make(spec: Any) -> Any:
        """The geometry's parameter class of ``spec``."""
        raise NotImplementedError

    @staticmethod
    def designer(ix: Any, samples: int, lengths: int, strict: bool) -> SpatialDesign:
        raise NotImplementedError

    @classmethod
    def _geometry(cls, spec: Any, strict: bool) -> SpatialDesign:
        try:
            return cls.designer(cls.make(spec), SAMPLES, LENGTHS, strict)
        except SpecError as exc:
            raise in_spec_words(spec, _spec_field(exc)) from None

    @classmethod
    def validate(cls, spec: Any) -> None:
        try:
            from_spec.validate_common(spec, cls.make, MotionProgram.from_spec(spec))
        except SpecError as exc:
            raise _spec_field(exc) from None
        core = float(spec.cam.base_radius)      # the core's least radius: the root cylinder, the globoid's waist
        if not spec.cam.bore_diameter < 2 * core:
            raise SpecError("cam.bore_diameter", f"must be < 2 × the core's least radius ({from_spec.size_words(spec.cam.body)} "
                            f"{core:g}) = {2 * core:g}, got {spec.cam.bore_diameter:g}")
        tip = spec.indexer.tip_radius
        if spec.cam.body == "globoidal_indexer" and tip is not None and not spec.cam.thickness < 2 * tip:
            # the rib's end faces must cut the tip globoid (a sphere of radius tip about the turret's foot)
            raise SpecError("cam.thickness", f"must be < 2 × indexer.tip_radius = {2 * tip:g} (the globoid's end faces "
                            f"cut its tip globoid), got {spec.cam.thickness:g}")

    @classmethod
    def design(cls, spec: Any, progress: Any = None) -> SpatialIndexerDesign:
        """The indexer of ``spec`` (SpecError naming the field when it cannot be built)."""
        g = cls._geometry(spec, strict=True)
        surfaces = flank_surfaces(g)
        drive = _drive(spec, g)
        design = SpatialIndexerDesign(spec, MotionProgram.from_spec(spec), g, surfaces, drive,
                                      spatial_checks(spec, g, drive))
        try:        # the rib the report's volume and the solid are made of (every report needs it)
            design.volume_estimate
        except RibNotBounded as exc:
            raise _rib_refusal(cls, exc) from None
        return design

    @classmethod
    def own_checks(cls, spec: Any) -> dict[str, Any]:
        """The checks without refusing a flank that is not regular or a turret that is not held."""
        g = cls._geometry(spec, strict=False)
        return spatial_checks(spec, g, _drive(spec, g))

    @staticmethod
    def remedy_words(spec: Any, check: str) -> str | None:
        return REMEDY_WORDS.get(check)

    @staticmethod
    def study_row(summary: Any, base_radius: float) -> dict[str, Any]:
        geo = summary["indexer"]["geometry"]
        row = {"units": summary["units"], "follower": summary["follower"]["label"], "base_radius": float(base_radius),
               "stations": geo["stations"], "centre_distance": geo["centre_distance"],
               "pressure_angle_deg": summary["pressure_angle"]["max_deg"],
               "pressure_angle_at_deg": summary["pressure_angle"]["at_deg"],
               "rib_thickness": geo["min_rib_thickness"]["value_mm"],
               "flank_fit_error": summary["body"]["flank_fit_error"]["value"]}
        row.update(checks_row(summary["checks"]))
        return row


def _rib_refusal(body: type["SpatialIndexerBody"], exc: RibNotBounded) -> SpecError:
    """The volume's refusal (:func:`.spatial_volume.cam_volume`: the flanks, continued below the rollers
    to the root, do not bound a rib) in the spec's words, naming the field to change: flanks crossing
    out of order are a rib that closes up between neighbouring rollers (below them, where only the
    continuation along the root's normal bounds it); otherwise a flank leaves the cam before it
    reaches the root (the body's ``rib_escape``)."""
    why = str(exc).strip().replace("\n", " ")
    if exc.closes:
        return SpecError("follower.roller_radius", f"the rib closes up between neighbouring rollers' flanks ({why}) — "
                         "reduce follower.roller_radius, bring indexer.roller_start nearer indexer.root_radius, or "
                         "use fewer indexer.stations")
    field, remedy = body.rib_escape
    return SpecError(field, f"the rib's flanks, continued beyond the rollers' ends to the root, leave the cam ({why}) "
                     f"— {remedy}")


def _drive(spec: Any, g: SpatialDesign) -> DriveSizing | None:
    ix = g.indexer
    load = from_spec.load_arguments(spec, default_width=float(ix.roller_end) - float(ix.roller_start))
    return None if load is None else spatial_drive(g, **load)


@register_body
class BarrelIndexerBody(SpatialIndexerBody):
    """A barrel indexer: a rib on a cylinder, the turret's axis at right angles to the cam's."""

    kind = "barrel_indexer"
    title = "Barrel indexer"
    #: a flank that leaves the cam before the root: the field to change and how
    rib_escape = ("cam.thickness", "change cam.thickness or the rib's radii (indexer.root_radius, "
                  "indexer.outer_radius)")
    plane = False
    roller_within_base = False
    closure = "form"
    drive_note = SpatialIndexerBody.drive_note
    own_fields = ()
    size_field = "indexer.centre_distance"
    #: its own optimiser's (cam_workbench.generators.optimise.spatial_indexer): the cam's outer radius, the peak
    #: roller load; its variables (C, the turret's size, r_r) are spec paths beyond [cam]: none declared here
    optimise_objectives = ("size", "normal_force")
    optimise_variables = ()
    drawing_label = None
    modules = ("cam_workbench.generators.bodies.indexing.spatial", "cam_workbench.generators.bodies.indexing.from_spec",
               "cam_workbench.generators.bodies.indexing.spatial_surfaces")

    @staticmethod
    def make(spec: Any) -> BarrelIndexer:
        return barrel_of(spec)

    @staticmethod
    def designer(ix: Any, samples: int, lengths: int, strict: bool) -> SpatialDesign:
        return design_barrel(ix, samples, lengths, strict)

    @staticmethod
    def label(spec: Any) -> str:
        ix = spec.indexer
        return (f"{ix.stations} stations, index {math.degrees(from_spec.index_segment(spec)[2]):g}°, C "
                f"{ix.centre_distance:g}, R_p {ix.pitch_radius:g}, rib radii {ix.root_radius:g}–{ix.outer_radius:g}, "
                f"length {spec.cam.thickness:g}")


@register_body
class GloboidalIndexerBody(SpatialIndexerBody):
    """A globoidal (roller-gear) indexer: a rib on a globoid, the turret's radial rollers."""

    kind = "globoidal_indexer"
    title = "Globoidal indexer"
    #: a flank that leaves the cam's end faces before the root globoid (its continuation at a constant
    #: angle about the turret's foot grows in z: a width at the catalogue's least,
    #: 2·(t1·sin(π/N) − r_r·cos(π/N)), or a root far beyond the rollers' ends)
    rib_escape = ("cam.thickness", "widen cam.thickness (the dwell rollers' inner sides held within the end faces "
                  "down to the root) or bring indexer.root_radius nearer the rollers' ends")
    plane = False
    roller_within_base = False
    closure = "form"
    drive_note = SpatialIndexerBody.drive_note
    own_fields = ()
    size_field = "indexer.centre_distance"
    #: its own optimiser's (cam_workbench.generators.optimise.spatial_indexer): the cam's outer radius, the peak
    #: roller load; its variables (C, the turret's size, r_r) are spec paths beyond [cam]: none declared here
    optimise_objectives = ("size", "normal_force")
    optimise_variables = ()
    drawing_label = None
    modules = ("cam_workbench.generators.bodies.indexing.spatial", "cam_workbench.generators.bodies.indexing.from_spec",
               "cam_workbench.generators.bodies.indexing.spatial_surfaces")

    @staticmethod
    def make(spec: Any) -> GloboidalIndexer:
        return globoidal_of(spec)

    @staticmethod
    def designer(ix: Any, samples: int, lengths: int, strict: bool) -> SpatialDesign:
        return design_globoidal(ix, samples, lengths, strict)

    @staticmethod
    def label(spec: Any) -> str:
        ix = spec.indexer
        return (f"{ix.stations} stations, index {math.degrees(from_spec.index_segment(spec)[2]):g}°, C "
                f"{ix.centre_distance:g}, rib globoids {ix.tip_radius:g}–{ix.root_radius:g}, "
                f"width {spec.cam.thickness:g}")


def body_of_design(design: SpatialIndexerDesign) -> type[SpatialIndexerBody]:
    """The body class of a design (by its spec's ``cam.body``)."""
    return BarrelIndexerBody if isinstance(design.geometry.indexer, BarrelIndexer) else GloboidalIndexerBody


#: what moves each failing check of a spatial indexer, in words (no single field is searched yet)
REMEDY_WORDS = {
    "pressure_angle": "a longer index (the rise's angle), fewer stations, or a larger turret (indexer.pitch_radius "
                      "or the rollers' distance from the turret axis)",
    "undercut": "a smaller follower.roller_radius, or a rib nearer the turret's pitch (indexer.root_radius, "
                "indexer.outer_radius / indexer.tip_radius)",
    "rib_thickness": "fewer stations, smaller rollers (follower.roller_radius) or a longer index",
    "locking": "a wider cam (cam.thickness) or rollers that reach further into the rib (indexer.roller_start, "
               "indexer.roller_end)",
    "contact_stress": "a longer roller (follower.roller_width, indexer.roller_end), a larger roller, a stronger "
                      "material (material.allowable_stress) or a lighter output (indexer.output_inertia)",
}

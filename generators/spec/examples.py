"""Built-in example cams, by name: the spec dicts behind ``--example NAME`` and
:func:`example_spec`.

* ``default`` — the cam ``make demo`` builds (:data:`cam_workbench.generators.spec.DEFAULT_SPEC_DICT`): the
  paper's motion program (cycloidal 20 mm rise and return over 120°) on a 40 mm base radius
  with a radial 8 mm roller, a spring-loaded follower and a 1000 MPa contact-stress limit; it
  passes every design check.
* ``paper`` — Jahanpour & Dolatabadi (2014), Table 1 case 2: e = 10 mm, R_b = √(20² + 10²),
  M = 60, with a 5 mm roller, 10 mm thick, 10 mm bore.  Its return has a 46.2° pressure angle:
  it fails the default 30° limit (as designed in the paper, which checks no pressure angle).
* ``oscillating`` — the default's motion program as arm rotation (15° rise and return) of an
  oscillating 8 mm roller on a 45 mm arm pivoted 60 mm from the cam axis, held by a 800 N·mm
  preload torque and a 500 N·mm/rad spring, arm inertia 2000 kg·mm²; it passes every check.
* ``flat`` — the default's motion program with a translating flat-faced follower (face 40 mm
  wide), the valve-train follower; it passes every check (its smallest ρ = R_b + s + s″ is 29.3 mm).
* ``packaging`` — a packaging machine's working stroke: a 22 mm constant-velocity rise over 120°
  entered and left through polynomial rises that take its velocity (Norton's SVAJ method), then a
  polynomial return; every junction is C², and it passes every check.
* ``groove`` — the default's motion in a groove (face) cam: a 150 mm disc, 12 mm thick, the
  8 mm roller running in an 8 mm deep groove 16.1 mm wide (clearance 0.1 mm), a 16 mm bore keyed
  by DIN 6885-1 (5 × 2.3 mm), a 36 mm hub 10 mm long, four 5 mm holes on a 34 mm circle and a
  timing mark; positive drive: no return spring.
* ``conjugate`` — the default's motion on a conjugate pair: a translating yoke (offset 5 mm) with
  its 8 mm roller on the first cam and a 6 mm roller 106 mm away on the other side of the axis on
  the second, 3 mm below it; both rollers touch at every angle, no spring.
* ``cylindrical`` — a cylindrical (barrel) cam: the default's motion as a groove around a 40 mm
  pitch-radius cylinder 60 mm long, a 5 mm roller moving along the cam axis.
* ``cylindrical_oscillating`` — a cylindrical cam driving an oscillating 5 mm roller on a 50 mm arm
  pivoted 50 mm away: 30° arm rise and return over 150°.
* ``parallel_indexer`` — an 8-station parallel indexer (docs/indexing.md): two plates 16 mm thick
  4 mm apart, the turret's 10 mm rollers on R_p = 50 mm at C = 120 mm, modified sine over a 120°
  index, sized for a 0.15 kg·m² output with 2 N·m friction at 100 rpm.

:data:`DESCRIPTIONS` says the same in one line each: the CLI's ``--example`` help, ``cam-workbench
spec --example`` and the examples table of docs/spec.md read it.
"""
from __future__ import annotations

import copy
import math
from typing import Any

from ..errors import SpecError
from .default import DEFAULT_SPEC_DICT
from .model import CamSpec

PAPER_SPEC_DICT: dict[str, Any] = {
    "units": "mm",
    "cam": {"base_radius": math.sqrt(20.0**2 + 10.0**2), "thickness": 10.0, "bore_diameter": 10.0,
            "direction": "ccw", "speed_rpm": 60.0},
    "follower": {"kind": "roller", "offset": 10.0, "roller_radius": 5.0},
    "motion": copy.deepcopy(DEFAULT_SPEC_DICT["motion"]),
    "pitch": {"representation": "ph", "segments": 60},
}

def _with_follower(follower: dict[str, Any], lift: float | None = None) -> dict[str, Any]:
    d = copy.deepcopy(DEFAULT_SPEC_DICT)
    d["follower"] = follower
    if lift is not None:
        for seg in d["motion"]:
            if "lift" in seg:
                seg["lift"] = lift
    return d


OSCILLATING_SPEC_DICT: dict[str, Any] = _with_follower(
    {"kind": "roller", "motion": "oscillating", "pivot_distance": 60.0, "arm_length": 45.0, "roller_radius": 8.0,
     "arm_inertia": 2000.0, "preload_torque": 800.0, "spring_torque_rate": 500.0}, lift=15.0)
FLAT_SPEC_DICT: dict[str, Any] = _with_follower(
    {"kind": "flat", "face_width": 40.0, "mass": 0.5, "preload": 20.0, "spring_rate": 1.0})

PACKAGING_SPEC_DICT: dict[str, Any] = {
    "units": "mm",
    "cam": {"base_radius": 60.0, "thickness": 12.0, "bore_diameter": 16.0, "speed_rpm": 60.0},
    "follower": {"kind": "roller", "roller_radius": 8.0, "mass": 0.5, "preload": 30.0, "spring_rate": 1.0},
    "motion": [
        {"kind": "dwell", "angle": 25.0},
        # from rest into the working stroke: the polynomial takes the stroke's velocity at its end
        {"kind": "rise", "angle": 45.0, "lift": 4.0, "law": "polynomial"},
        {"kind": "rise", "angle": 120.0, "lift": 22.0, "law": "constant_velocity"},
        {"kind": "rise", "angle": 45.0, "lift": 4.0, "law": "polynomial"},
        {"kind": "dwell", "angle": 25.0},
        {"kind": "return", "angle": 100.0, "lift": 30.0, "law": "polynomial"},
    ],
    "pitch": {"tolerance": 1e-4},
    "material": {"allowable_stress": 1000.0},
}

GROOVE_SPEC_DICT: dict[str, Any] = {
    **copy.deepcopy({k: v for k, v in DEFAULT_SPEC_DICT.items() if k not in ("cam", "follower")}),
    "cam": {**DEFAULT_SPEC_DICT["cam"], "body": "groove", "outer_diameter": 150.0, "thickness": 12.0,
            "bore_diameter": 16.0, "keyway": "DIN6885", "hub_diameter": 36.0, "hub_length": 10.0,
            "mounting_holes": 4, "mounting_hole_diameter": 5.0, "mounting_circle_diameter": 34.0,
            "timing_mark": True},
    "follower": {"kind": "roller", "roller_radius": 8.0, "mass": 0.5},
    "groove": {"depth": 8.0, "clearance": 0.1, "min_wall": 3.0},
}

CONJUGATE_SPEC_DICT: dict[str, Any] = {
    **copy.deepcopy({k: v for k, v in DEFAULT_SPEC_DICT.items() if k not in ("cam", "follower")}),
    "cam": {**DEFAULT_SPEC_DICT["cam"], "body": "conjugate", "bore_diameter": 12.0},
    "follower": {"kind": "roller", "roller_radius": 8.0, "offset": 5.0, "mass": 0.5},
    "conjugate": {"roller_distance": 106.0, "roller_radius": 6.0, "gap": 3.0},
}

#: a cylindrical (barrel) cam: a groove around a cylinder, the roller's axis radial, the follower moving
#: along the cam axis (docs/bodies.md)
CYLINDRICAL_SPEC_DICT: dict[str, Any] = {
    "units": "mm",
    "cam": {"body": "cylindrical", "cylinder_radius": 40.0, "length": 60.0, "bore_diameter": 20.0,
            "speed_rpm": 60.0},
    "follower": {"kind": "roller", "roller_radius": 5.0},
    "motion": [
        {"kind": "dwell", "angle": 30.0},
        {"kind": "rise", "angle": 120.0, "lift": 20.0, "law": "cycloidal"},
        {"kind": "dwell", "angle": 60.0},
        {"kind": "return", "angle": 120.0, "lift": 20.0, "law": "cycloidal"},
        {"kind": "dwell", "angle": 30.0},
    ],
    "groove": {"depth": 8.0, "clearance": 0.05, "min_wall": 3.0},
    "machining": {"passes": 2},
}

#: a cylindrical cam driving an oscillating roller: the arm's pivot axis radial, the arm swinging in the
#: developed pitch plane (generators/bodies/cylinder_path.py, docs/bodies.md); the lift is the arm's angle
CYLINDRICAL_OSCILLATING_SPEC_DICT: dict[str, Any] = {
    "units": "mm",
    "cam": {"body": "cylindrical", "cylinder_radius": 40.0, "length": 50.0, "bore_diameter": 20.0,
            "speed_rpm": 60.0},
    "follower": {"kind": "roller", "roller_radius": 5.0, "motion": "oscillating", "pivot_distance": 50.0,
                 "arm_length": 50.0},
    "motion": [
        {"kind": "dwell", "angle": 30.0},
        {"kind": "rise", "angle": 150.0, "lift": 30.0, "law": "cycloidal"},
        {"kind": "dwell", "angle": 30.0},
        {"kind": "return", "angle": 150.0, "lift": 30.0, "law": "cycloidal"},
    ],
    "groove": {"depth": 8.0, "clearance": 0.05, "min_wall": 3.0},
    "machining": {"passes": 2},
}

#: an 8-station parallel indexer: two plates on the input shaft, the turret's rollers alternating
#: between their planes; modified sine over a 120° index (docs/indexing.md).  The carrying contact's
#: pressure angle reaches ~71° at the index's ends, where friction alone is carried: the limit is
#: this application's 75° (the default 60° no N = 8, β = 120° drive reaches, docs/indexing.md)
PARALLEL_INDEXER_SPEC_DICT: dict[str, Any] = {
    "units": "mm",
    "cam": {"body": "parallel_indexer", "thickness": 16.0, "bore_diameter": 30.0, "speed_rpm": 100.0},
    "follower": {"kind": "roller", "roller_radius": 10.0, "roller_width": 12.0},
    "motion": [
        {"kind": "dwell", "angle": 120.0},
        {"kind": "rise", "angle": 120.0, "lift": 45.0, "law": "modified_sine"},
        {"kind": "dwell", "angle": 120.0},
    ],
    "indexer": {"stations": 8, "centre_distance": 120.0, "pitch_radius": 50.0, "cams": 2, "gap": 4.0,
                "max_pressure_angle": 75.0, "output_inertia": 150000.0, "friction_torque": 2000.0,
                "roller_rating": 12000.0},
    "material": {"allowable_stress": 1500.0},
}

#: a 6-station barrel indexer: a rib on an 80 mm long cylinder, the turret's rollers on its face 60 mm from
#: its axis, which crosses the cam axis at right angles 52 mm away; modified sine over a 240° index
BARREL_INDEXER_SPEC_DICT: dict[str, Any] = {
    "units": "mm",
    "cam": {"body": "barrel_indexer", "thickness": 80.0, "bore_diameter": 20.0, "speed_rpm": 60.0},
    "follower": {"kind": "roller", "roller_radius": 12.0},
    "motion": [
        {"kind": "dwell", "angle": 60.0},
        {"kind": "rise", "angle": 240.0, "lift": 60.0, "law": "modified_sine"},
        {"kind": "dwell", "angle": 60.0},
    ],
    "indexer": {"stations": 6, "centre_distance": 52.0, "pitch_radius": 60.0, "roller_start": 27.0,
                "roller_end": 45.0, "root_radius": 25.0, "outer_radius": 40.0, "output_inertia": 200000.0,
                "friction_torque": 3000.0, "roller_rating": 30000.0},
    "material": {"allowable_stress": 1500.0},
}

#: a 12-station globoidal (roller-gear) indexer: a rib on a globoid 56 mm wide, the turret's radial
#: rollers 74–96 mm from its axis, 150 mm from the cam axis; modified sine over a 120° index
GLOBOIDAL_INDEXER_SPEC_DICT: dict[str, Any] = {
    "units": "mm",
    "cam": {"body": "globoidal_indexer", "thickness": 56.0, "bore_diameter": 30.0, "speed_rpm": 60.0},
    "follower": {"kind": "roller", "roller_radius": 12.0},
    "motion": [
        {"kind": "dwell", "angle": 120.0},
        {"kind": "rise", "angle": 120.0, "lift": 30.0, "law": "modified_sine"},
        {"kind": "dwell", "angle": 120.0},
    ],
    "indexer": {"stations": 12, "centre_distance": 150.0, "roller_start": 74.0, "roller_end": 96.0,
                "tip_radius": 76.0, "root_radius": 100.0, "output_inertia": 500000.0, "friction_torque": 5000.0,
                "roller_rating": 30000.0},
    "material": {"allowable_stress": 1500.0},
}

EXAMPLES: dict[str, dict[str, Any]] = {"default": DEFAULT_SPEC_DICT, "paper": PAPER_SPEC_DICT,
                                       "oscillating": OSCILLATING_SPEC_DICT, "flat": FLAT_SPEC_DICT,
                                       "packaging": PACKAGING_SPEC_DICT, "groove": GROOVE_SPEC_DICT,
                                       "conjugate": CONJUGATE_SPEC_DICT, "cylindrical": CYLINDRICAL_SPEC_DICT,
                                       "cylindrical_oscillating": CYLINDRICAL_OSCILLATING_SPEC_DICT,
                                       "parallel_indexer": PARALLEL_INDEXER_SPEC_DICT,
                                       "barrel_indexer": BARREL_INDEXER_SPEC_DICT,
                                       "globoidal_indexer": GLOBOIDAL_INDEXER_SPEC_DICT}


#: every example in one line (the ``--example`` help and docs/spec.md's table read this)
DESCRIPTIONS: dict[str, str] = {
    "default": "the paper's motion program (cycloidal 20 mm rise and return over 120°) on R_b = 40 mm with a "
               "radial 8 mm roller; passes every design check",
    "paper": "Jahanpour & Dolatabadi (2014), Table 1 case 2: e = 10 mm, R_b = √(20² + 10²), M = 60, a 5 mm roller; "
             "fails the 30° pressure-angle limit (46.2°)",
    "oscillating": "the default's motion as a 15° arm rotation: an 8 mm roller on a 45 mm arm pivoted 60 mm from "
                   "the cam axis",
    "flat": "the default's motion with a translating flat-faced follower, face 40 mm wide",
    "packaging": "a 22 mm constant-velocity working stroke entered and left through polynomial rises, on "
                 "R_b = 60 mm; every junction C²",
    "groove": "the default's motion in a groove (face) cam: a 150 mm disc 12 mm thick, keyway, hub, four holes "
              "and a timing mark",
    "conjugate": "the default's motion on a conjugate pair: a yoke's 8 mm roller on the first cam, a 6 mm roller "
                 "106 mm away on the second",
    "cylindrical": "a cylindrical (barrel) cam: a groove around a 40 mm pitch-radius cylinder 60 mm long, a 5 mm "
                   "roller along the cam axis",
    "cylindrical_oscillating": "a cylindrical cam driving an oscillating 5 mm roller on a 50 mm arm pivoted 50 mm "
                               "away (30° arm rise over 150°)",
    "parallel_indexer": "an 8-station parallel indexer: two plates 16 mm thick, modified sine over a 120° index, "
                        "C = 120 mm, R_p = 50 mm, 10 mm rollers, sized for a 0.15 kg·m² output at 100 rpm",
    "barrel_indexer": "a 6-station barrel indexer: a rib on an 80 mm cylinder, 12 mm rollers on the turret's face "
                      "60 mm out, modified sine over a 240° index, sized for a 0.2 kg·m² output at 60 rpm",
    "globoidal_indexer": "a 12-station globoidal indexer: a rib on a 56 mm globoid, C = 150 mm, 12 mm radial rollers "
                         "74–96 mm out, modified sine over a 120° index, sized for a 0.5 kg·m² output at 60 rpm",
}
assert set(DESCRIPTIONS) == set(EXAMPLES)


def example_dict(name: str) -> dict[str, Any]:
    """A copy of the spec dict of example ``name`` (see :data:`EXAMPLES`)."""
    try:
        return copy.deepcopy(EXAMPLES[name])
    except KeyError:
        raise SpecError("--example", f"unknown example {name!r} (examples: {', '.join(EXAMPLES)})") from None


def example_spec(name: str = "default") -> CamSpec:
    """The validated spec of example ``name``."""
    return CamSpec.from_dict(example_dict(name))

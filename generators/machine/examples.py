"""Built-in machines, by name: the dicts behind ``cam-workbench machine --example NAME``
(docs/examples/machine_three_cams.toml is ``three_cams`` as a file).

* ``three_cams`` — a transfer station at 120 rpm (issue 24), every cam's axis at the machine
  plane's origin: a PUSHER (translating roller, stem on x = 0) drives its push plate through a
  LEVER of ratio 2 pushed by the stem at (0, 90), its fulcrum at (−30, 90), the plate at (30, 90)
  at zero lift (25 mm of lift → 50 mm of stroke along +y), pushing the part in over machine angles
  0–100° and back over 250–350°; a GRIPPER (oscillating roller arm about (60, 0), phase 100°)
  drives its jaw through a FOUR-BAR whose crank is the arm (crank pivot at the arm's pivot, ground
  90 mm at frame_angle 95°, the crank along the arm at zero lift: frame_angle + crank_offset = ψ₀ =
  138.19°, the left branch: the jaw closes as the arm lifts) and whose motion is
  given at the tool (``motion_at = "tool"``: the rocker closes 10° over 100–160° and opens over
  280–340°, the arm's motion derived); a LIFTER (translating flat face, phase 170°, no linkage: its
  pad rests on the face, placed by ``[cam.tool]`` ``origin`` (0, 55) = the face's foot (0, 45) +
  the pad's radius, rising along +y) lifts over 170–260° and returns over 340–70°.  The push
  plate's edge and the jaw's tip come within about 3.9 mm while the plate returns and the jaw
  opens: the ``[[clearance]]`` pair requires 2 mm.  Every cam passes its design checks and the
  clearance passes.
"""
from __future__ import annotations

import copy
from typing import Any

from ..errors import SpecError

PUSHER: dict[str, Any] = {
    "units": "mm",
    "cam": {"base_radius": 50.0, "thickness": 12.0, "bore_diameter": 16.0},
    "follower": {"kind": "roller", "roller_radius": 8.0, "mass": 0.8, "preload": 30.0, "spring_rate": 1.0},
    "linkage": {"kind": "lever", "ratio": 2.0, "pivot_x": 30.0, "pivot_y": 90.0, "direction": 90.0},
    "motion": [
        {"kind": "rise", "angle": 100.0, "lift": 25.0, "law": "cycloidal"},
        {"kind": "dwell", "angle": 150.0},
        {"kind": "return", "angle": 100.0, "lift": 25.0, "law": "cycloidal"},
        {"kind": "dwell", "angle": 10.0},
    ],
    "pitch": {"segments": 72},
    "material": {"allowable_stress": 1000.0},
}

GRIPPER: dict[str, Any] = {
    "units": "mm",
    "cam": {"base_radius": 40.0, "thickness": 10.0, "bore_diameter": 16.0},
    "follower": {"kind": "roller", "motion": "oscillating", "pivot_distance": 60.0, "arm_length": 45.0,
                 "roller_radius": 8.0, "arm_inertia": 2000.0, "preload_torque": 800.0, "spring_torque_rate": 500.0},
    "linkage": {"kind": "four_bar", "motion_at": "tool", "ground": 90.0, "crank": 35.0, "coupler": 80.0,
                "rocker": 30.0, "frame_angle": 95.0, "crank_offset": 43.19, "branch": "left", "pivot_x": 60.0,
                "pivot_y": 0.0},
    "motion": [
        {"kind": "rise", "angle": 60.0, "lift": 10.0, "law": "modified_sine"},
        {"kind": "dwell", "angle": 120.0},
        {"kind": "return", "angle": 60.0, "lift": 10.0, "law": "modified_sine"},
        {"kind": "dwell", "angle": 120.0},
    ],
    "pitch": {"segments": 72},
    "material": {"allowable_stress": 1000.0},
}

LIFTER: dict[str, Any] = {
    "units": "mm",
    "cam": {"base_radius": 45.0, "thickness": 12.0, "bore_diameter": 16.0},
    "follower": {"kind": "flat", "face_width": 50.0, "mass": 1.2, "preload": 40.0, "spring_rate": 1.5},
    "motion": [
        {"kind": "rise", "angle": 90.0, "lift": 15.0, "law": "poly345"},
        {"kind": "dwell", "angle": 80.0},
        {"kind": "return", "angle": 90.0, "lift": 15.0, "law": "poly345"},
        {"kind": "dwell", "angle": 100.0},
    ],
    "pitch": {"segments": 72},
    "material": {"allowable_stress": 1000.0},
}

THREE_CAMS: dict[str, Any] = {
    "machine": {"name": "transfer station", "speed_rpm": 120.0, "speed_fluctuation": 0.02},
    "cam": [
        {"name": "pusher", "phase": 0.0, "spec": PUSHER,
         "tool": {"label": "push plate", "polygon": [[-10.0, -4.0], [10.0, -4.0], [10.0, 4.0], [-10.0, 4.0]]}},
        {"name": "gripper", "phase": 100.0, "spec": GRIPPER,
         "tool": {"label": "gripper jaw", "polygon": [[-38.0, -6.0], [0.0, -6.0], [0.0, 6.0], [-38.0, 6.0]]}},
        {"name": "lifter", "phase": 170.0, "spec": LIFTER,
         "tool": {"label": "lifting pad", "circle": {"radius": 10.0}, "origin": [0.0, 55.0], "direction": 90.0}},
    ],
    "clearance": [{"between": ["pusher", "gripper"], "required": 2.0}],
}

MACHINES: dict[str, dict[str, Any]] = {"three_cams": THREE_CAMS}


def example_machine_dict(name: str) -> dict[str, Any]:
    """A copy of the built-in machine ``name``'s TOML structure.

    Raises:
        SpecError: no such example (naming ``--example`` and the names there are).
    """
    if name not in MACHINES:
        raise SpecError("--example", f"no built-in machine {name!r} (there are: {', '.join(MACHINES)})")
    return copy.deepcopy(MACHINES[name])


__all__ = ["MACHINES", "THREE_CAMS", "example_machine_dict"]

"""The built-in default cam: :func:`default_spec` and its TOML structure ``DEFAULT_SPEC_DICT``.
"""
from __future__ import annotations

from typing import Any

from .model import CamSpec


def default_spec() -> CamSpec:
    """The built-in default cam (``make demo``'s): the paper's motion program — cycloidal 20 mm
    rise and return over 120° with 30°/60°/30° dwells (Jahanpour & Dolatabadi 2014, Table 1) —
    on a 40 mm base radius with a radial 8 mm roller, 10 mm thick, 12 mm bore, a follower of
    0.5 kg held by a 20 N preload and a 1 N/mm spring, at 60 rpm, contact stress limited to
    1000 MPa.  It passes every design check.  The paper's own case-2 cam (e = 10 mm, which
    fails the 30° pressure-angle limit) is ``cam_workbench.generators.spec.examples.example_spec("paper")``."""
    return CamSpec.from_dict(DEFAULT_SPEC_DICT)


DEFAULT_SPEC_DICT: dict[str, Any] = {
    "units": "mm",
    "cam": {"base_radius": 40.0, "thickness": 10.0, "bore_diameter": 12.0,
            "direction": "ccw", "speed_rpm": 60.0},
    "follower": {"kind": "roller", "offset": 0.0, "roller_radius": 8.0,
                 "mass": 0.5, "preload": 20.0, "spring_rate": 1.0},
    "motion": [
        {"kind": "dwell", "angle": 30.0},
        {"kind": "rise", "angle": 120.0, "lift": 20.0, "law": "cycloidal"},
        {"kind": "dwell", "angle": 60.0},
        {"kind": "return", "angle": 120.0, "lift": 20.0, "law": "cycloidal"},
        {"kind": "dwell", "angle": 30.0},
    ],
    "pitch": {"representation": "ph", "segments": 60},
    "material": {"allowable_stress": 1000.0},
}

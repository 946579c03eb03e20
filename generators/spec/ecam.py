"""The spec's `[ecam]` table: :class:`EcamSection` (electronic-cam tables), the formats and tables
``ECAM_TABLES``, and its rules (the table of the format, the PLC name, the most points).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import SpecError
from .params import param

if TYPE_CHECKING:  # types only: the spec's root imports this module
    from .model import CamSpec


#: Formats of `cam-workbench ecam` and the tables each can write (the first is its default).
ECAM_TABLES: dict[str, tuple[str, ...]] = {
    "csv": ("points",),
    "codesys": ("xyva", "poly5"),
    "beckhoff": ("motion_function", "position_table"),
    "lenze": ("points",),
}


@dataclass(frozen=True, kw_only=True)
class EcamSection:
    """`[ecam]`: electronic-cam tables for servo motion controllers, written by `cam-workbench ecam` (docs/ecam.md)."""

    format: str = param("Table format: a CSV of θ, s, s′, s″, s‴; CODESYS SoftMotion; Beckhoff TwinCAT NC Camming; "
                        "Lenze Global Drive Cam Loader", kind="str", choices=tuple(ECAM_TABLES), default="csv",
                        group="Ecam")
    table: str = param(
        "Which table of the format: codesys \"xyva\" (SMC_CAMXYVA points) or \"poly5\" (CamBuilder Poly5 "
        "segments); beckhoff \"motion_function\" (MC_MotionFunctionPoint, 5th-order polynomials) or "
        "\"position_table\" (master/slave positions); csv and lenze \"points\"; \"auto\": the format's first",
        kind="str", choices=("auto", "points", "xyva", "poly5", "motion_function", "position_table"),
        default="auto", group="Ecam")
    step: float = param("Master step between table points in cam degrees", unit="angle", ge=0.001, le=90,
                        default=1.0, group="Ecam")
    boundaries: bool = param(
        "Also put a point at every motion-segment boundary (where a law's acceleration or jerk may jump); the "
        "table is then not equidistant unless the boundaries fall on the step", kind="bool", default=True,
        group="Ecam")
    name: str = param("Name of the cam in the PLC code (an IEC 61131-3 identifier)", kind="str", default="Cam",
                      group="Ecam")


#: The most points an e-cam table may have (CODESYS counts its elements in an INT).
MAX_ECAM_POINTS = 200_000
_IEC_IDENTIFIER = re.compile(r"^[A-Za-z_][A-Za-z0-9_]{0,63}$")


def validate_ecam(spec: CamSpec) -> None:
    ec = spec.ecam
    if ec.table != "auto" and ec.table not in ECAM_TABLES[ec.format]:
        raise SpecError("ecam.table", f"{ec.table!r} is not a table of ecam.format = {ec.format!r} (its tables: "
                        f"{', '.join(ECAM_TABLES[ec.format])})")
    if not _IEC_IDENTIFIER.match(ec.name) or "__" in ec.name:
        raise SpecError("ecam.name", f"must be an IEC 61131-3 identifier (a letter or _, then letters, digits, "
                        f"single underscores; at most 64 characters), got {ec.name!r}")
    points = math.ceil(360.0 / ec.step - 1e-9) + 1
    if points > MAX_ECAM_POINTS:
        raise SpecError("ecam.step", f"gives {points} table points; at most {MAX_ECAM_POINTS}")

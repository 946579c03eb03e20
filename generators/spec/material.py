"""The spec's `[material]` table: :class:`MaterialSection` (elastic constants for the Hertz contact
stress) and the steel default ``STEEL_MODULUS``.
"""
from __future__ import annotations

from dataclasses import dataclass

from .params import param


#: Young's modulus used when [material] gives none: steel, the thesis' 29×10⁶ psi (Ch. 7,
#: SAE 1010) = 199 948 MPa, in the spec's stress unit.
STEEL_MODULUS = {"in": 29.0e6, "mm": 29.0e6 * 6.894757293168361e-3}


@dataclass(frozen=True, kw_only=True)
class MaterialSection:
    """`[material]`: elastic constants of cam and follower for the Hertz contact stress (thesis Eq. 3.6)."""

    cam_modulus: float | None = param(
        "Young's modulus E_c of the cam (default: steel, 29×10⁶ psi = 199 948 MPa)",
        unit="stress", gt=0, optional=True, group="Material")
    cam_poisson: float = param("Poisson's ratio ν_c of the cam (thesis: 0.29, SAE 1010)",
                               ge=0, lt=0.5, default=0.29, group="Material")
    follower_modulus: float | None = param(
        "Young's modulus E_f of the roller (default: steel, 29×10⁶ psi = 199 948 MPa)",
        unit="stress", gt=0, optional=True, group="Material")
    follower_poisson: float = param("Poisson's ratio ν_f of the roller", ge=0, lt=0.5,
                                    default=0.29, group="Material")
    allowable_stress: float | None = param(
        "Allowable Hertz contact stress S_d (thesis Eq. 5.13; its examples: 250 000 psi); "
        "absent: the stress is reported, and the contact_stress check is skipped (not passed)",
        unit="stress", gt=0, optional=True, group="Material")

    def modulus(self, which: str, units: str) -> float:
        """E of "cam" or "follower" in the spec's stress unit (steel when not given)."""
        v = self.cam_modulus if which == "cam" else self.follower_modulus
        return STEEL_MODULUS[units] if v is None else v

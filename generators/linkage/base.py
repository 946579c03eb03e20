"""The :class:`Linkage` protocol (a lever or a four-bar between the cam's follower and the tool)
and the exact derivative algebra every linkage shares.

Coordinates: the follower coordinate ``q`` is the follower's lift in linkage units — mm for a
translating follower, rad of arm rotation for an oscillating one (the program's degrees times
π/180); the tool coordinate ``p`` is the tool's displacement from where it is at ``q = 0`` (mm,
or rad of tool rotation).  Derivatives ``q1, q2, q3`` / ``p1, p2, p3`` are per rad of cam angle
(the program's reduced derivatives).  Both maps send 0 to 0.
"""
from __future__ import annotations

from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np

Jet = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


@runtime_checkable
class Linkage(Protocol):
    """A one-degree-of-freedom linkage from the follower coordinate q to the tool coordinate p."""

    #: the registry name (the value of ``linkage.kind``)
    kind: ClassVar[str]
    #: the input must be an angle (a four-bar's crank): an oscillating follower
    angular_input_only: ClassVar[bool]

    def forward(self, q: Any, q1: Any, q2: Any, q3: Any) -> Jet:
        """(p, p′, p″, p‴) of the follower jet (q, q′, q″, q‴) (derivatives per rad of cam)."""
        ...

    def inverse(self, p: Any, p1: Any, p2: Any, p3: Any) -> Jet:
        """(q, q′, q″, q‴) of the tool jet: the exact inverse of :meth:`forward`."""
        ...

    def tool_point(self, q: Any) -> np.ndarray:
        """The tool's point in the machine plane [mm], shape ``q.shape + (2,)``."""
        ...

    def joints(self, q: Any) -> dict[str, np.ndarray]:
        """Named points of the linkage in the machine plane [mm] (each ``q.shape + (2,)``)."""
        ...

    def transmission_angle(self, q: Any) -> np.ndarray | None:
        """The transmission angle [rad] in [0, π] at each q, or None (no coupler)."""
        ...

    def toggles(self) -> np.ndarray:
        """Follower coordinates q where the linkage toggles (links collinear), sorted; empty when none."""
        ...

    def summary(self) -> dict[str, Any]:
        """The linkage's own numbers for report.json (lengths in mm, angles in degrees)."""
        ...


def compose3(g1: Any, g2: Any, g3: Any, x1: Any, x2: Any, x3: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Faà di Bruno to third order: the θ-derivatives of y(x(θ)) from dy/dx = g1, d²y/dx² = g2,
    d³y/dx³ = g3 and x′, x″, x‴:  y′ = g1 x′, y″ = g2 x′² + g1 x″, y‴ = g3 x′³ + 3 g2 x′ x″ + g1 x‴."""
    g1, g2, g3, x1, x2, x3 = (np.asarray(v, dtype=float) for v in (g1, g2, g3, x1, x2, x3))
    return g1 * x1, g2 * x1 * x1 + g1 * x2, g3 * x1 ** 3 + 3.0 * g2 * x1 * x2 + g1 * x3


def wrap_pi(a: Any) -> np.ndarray:
    """Angles [rad] reduced to [−π, π)."""
    return np.mod(np.asarray(a, dtype=float) + np.pi, 2.0 * np.pi) - np.pi


def points(z: Any) -> np.ndarray:
    """Complex points as an array of shape ``z.shape + (2,)`` (x, y)."""
    z = np.asarray(z, dtype=complex)
    return np.stack([z.real, z.imag], axis=-1)

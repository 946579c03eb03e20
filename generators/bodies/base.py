"""What a cam body is made of, as plain data: closed plane loops (exact NURBS pieces, circular
arcs, straight lines) swept along the cam axis into prisms that are added or cut in order.

Every kernel adaptor (OCP in ``cam_workbench.kernel.solids``, FreeCAD's Part in
``cam_workbench.freecad.part_build``) and the DXF drawing read this description; the exact
volume and cross-section come from it too: a prism's volume is its region's area (Green's theorem
on the exact pieces: the NURBS by Gauss quadrature, arcs and lines in closed form) times its
height, and a body's volume is the sum over its prisms, + added, − cut.  That sum is the true
volume when every cut lies inside material added before it and cuts do not overlap — which the
bodies guarantee with their checks (walls, ligaments), so the tests can hold the kernel's solid
against it.

Conventions: cam frame (CAM_SPEC.md), lengths in the spec's unit, loops counter-clockwise;
the plate occupies 0 ≤ z ≤ cam.thickness, a hub sits below it (−hub_length ≤ z ≤ 0).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Union

import numpy as np

from ..curves.nurbs import NurbsCurve


@dataclass(frozen=True)
class Line:
    """A straight piece from ``start`` to ``end`` (complex points)."""

    start: complex
    end: complex

    def area_term(self) -> float:
        """½∫(x dy − y dx) along the piece (Green's theorem)."""
        return 0.5 * float((np.conj(self.start) * self.end).imag)

    def points(self, n: int = 2) -> np.ndarray:
        t = np.linspace(0.0, 1.0, n)
        return self.start + (self.end - self.start) * t


@dataclass(frozen=True)
class Arc:
    """A circular arc about ``centre`` of ``radius`` from angle ``a0`` to ``a1`` [rad] (a1 > a0:
    counter-clockwise, a1 < a0: clockwise)."""

    centre: complex
    radius: float
    a0: float
    a1: float

    @property
    def start(self) -> complex:
        return self.centre + self.radius * np.exp(1j * self.a0)

    @property
    def end(self) -> complex:
        return self.centre + self.radius * np.exp(1j * self.a1)

    def area_term(self) -> float:
        # ½∫(x dy − y dx) with x = cx + r cos a, y = cy + r sin a: ½[r²Δa + r(cx(sin a1 − sin a0) − cy(cos a1 − cos a0))]
        c, r = self.centre, self.radius
        da = self.a1 - self.a0
        return 0.5 * (r * r * da + r * (c.real * (np.sin(self.a1) - np.sin(self.a0))
                                         + c.imag * (np.cos(self.a1) - np.cos(self.a0)) * -1.0))

    def points(self, n: int = 64) -> np.ndarray:
        a = np.linspace(self.a0, self.a1, n)
        return self.centre + self.radius * np.exp(1j * a)


@dataclass(frozen=True)
class Curve:
    """An exact NURBS piece (a profile, a groove wall)."""

    nurbs: NurbsCurve

    @property
    def start(self) -> complex:
        p = self.nurbs.poles[0]
        return complex(p[0], p[1])

    @property
    def end(self) -> complex:
        p = self.nurbs.poles[-1]
        return complex(p[0], p[1])

    def area_term(self) -> float:
        return float(self.nurbs.area())

    def points(self, n: int = 32) -> np.ndarray:
        _, p = self.nurbs.sample(n)
        return p[:, 0] + 1j * p[:, 1]


Piece = Union[Line, Arc, Curve]


@dataclass(frozen=True)
class Loop:
    """A closed boundary: pieces end to end, counter-clockwise; ``role`` names it for drawings
    and tests ("profile", "bore", "rim", "groove_outer", "groove_inner", "hub", "hole", …)."""

    pieces: tuple[Piece, ...]
    role: str = ""

    @staticmethod
    def circle(radius: float, centre: complex = 0j, role: str = "") -> "Loop":
        return Loop((Arc(centre, radius, 0.0, 2 * np.pi),), role)

    @staticmethod
    def nurbs(curve: NurbsCurve, role: str = "") -> "Loop":
        """The closed NURBS ``curve`` as a counter-clockwise loop."""
        return Loop((Curve(curve if curve.area() > 0 else curve.reversed()),), role)

    @cached_property
    def area(self) -> float:
        """Enclosed area (positive for a counter-clockwise loop); computed once (a loop is immutable)."""
        return float(sum(p.area_term() for p in self.pieces))

    @property
    def is_circle(self) -> bool:
        return len(self.pieces) == 1 and isinstance(self.pieces[0], Arc)

    def points(self, per_piece: int = 64) -> np.ndarray:
        """Points along the loop (complex), each piece sampled."""
        return np.concatenate([p.points(per_piece if not isinstance(p, Line) else 2) for p in self.pieces])

    def gap(self) -> float:
        """Largest distance between a piece's end and the next piece's start (0 when closed)."""
        return max(abs(a.end - b.start) for a, b in zip(self.pieces, self.pieces[1:] + self.pieces[:1]))


@dataclass(frozen=True)
class Prism:
    """A plane region — ``outer`` minus ``holes`` — swept from z0 to z1, added to or cut from
    the body (``op`` "add" or "cut")."""

    outer: Loop
    holes: tuple[Loop, ...] = ()
    z0: float = 0.0
    z1: float = 1.0
    op: str = "add"
    role: str = ""

    @cached_property
    def area(self) -> float:
        return abs(self.outer.area) - sum(abs(h.area) for h in self.holes)

    @property
    def volume(self) -> float:
        return self.area * (self.z1 - self.z0)


@dataclass(frozen=True)
class BodyGeometry:
    """A cam body: prisms applied in order (each "add" fused, each "cut" removed).

    Attributes:
        kind: the body ("plate", "groove", …).
        prisms: the prisms.
        extra: plain numbers the body reports (walls, feature sizes), for report.json.
    """

    kind: str
    prisms: tuple[Prism, ...]
    extra: dict = field(default_factory=dict)
    #: a stack of prisms alone (the cylindrical body's geometry, with wall surfaces, is not)
    prismatic = True

    @cached_property
    def volume(self) -> float:
        """Exact volume: Σ ± prism volumes (see the module docstring for when this is the solid's)."""
        return float(sum(p.volume if p.op == "add" else -p.volume for p in self.prisms))

    def face_area_at(self, z: float) -> float:
        """Area of the body's planar face at height ``z`` seen from above: the regions of the
        prisms whose top (z0 < z ≤ z1) reaches it, + added, − cut."""
        return float(sum((p.area if p.op == "add" else -p.area) for p in self.prisms if p.z0 < z <= p.z1 + 1e-12))

    def prism(self, role: str) -> Prism:
        for p in self.prisms:
            if p.role == role:
                return p
        raise KeyError(role)

    def has(self, role: str) -> bool:
        return any(p.role == role for p in self.prisms)

    @property
    def plain_plate(self) -> bool:
        """One plate prism (role "plate": the profile) with round holes only — the profile face
        extruded, nothing fused or cut."""
        return (len(self.prisms) == 1 and self.prisms[0].role == "plate"
                and all(h.is_circle for h in self.prisms[0].holes))

    def loops(self) -> list[Loop]:
        """Every loop of every prism (for drawings)."""
        out = []
        for p in self.prisms:
            out.append(p.outer)
            out.extend(p.holes)
        return out

    @property
    def z_range(self) -> tuple[float, float]:
        return min(p.z0 for p in self.prisms), max(p.z1 for p in self.prisms)

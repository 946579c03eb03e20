"""Features every cam body can carry: the bore with a keyway, a hub, mounting holes on a pitch
circle and a timing mark at θ = 0 — as loops and prisms (:mod:`cam_workbench.generators.bodies.base`).

Keyways are sized from the bore by a standard or given explicitly:

* **DIN 6885-1** (parallel keys, normal form): width b and hub keyway depth t₂ by shaft
  diameter; the keyway's bottom lies d/2 + t₂ from the axis (the standard's "d + t₂" measured
  across the bore).  Table of DIN 6885-1:1968; the rows from 38 mm on agree with Siemens'
  reproduction (catalogue MD 31.1, 2016, p. 7/3).
* **ANSI B17.1** (square parallel keys, inch): key width W by shaft diameter; the hub keyseat
  is W/2 deep measured at the side of the keyway (the standard's convention), so its bottom lies
  √(r² − (W/2)²) + W/2 from the axis.
* explicit ``cam.keyway_width`` / ``cam.keyway_depth``: depth from the bore at the keyway's
  centre line (as DIN's t₂).

The keyway points along +Y of the cam frame: where a translating follower on the cam's centre
line touches at θ = 0, so the key, the timing mark and the program start line up.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import SpecError, fmt_apart
from ..kinds import bodies, body_of
from .base import Arc, Line, Loop, Prism

#: DIN 6885-1: (shaft diameter over, up to [mm], key width b, hub keyway depth t₂ [mm])
DIN6885 = (
    (6, 8, 2, 1.0), (8, 10, 3, 1.4), (10, 12, 4, 1.8), (12, 17, 5, 2.3), (17, 22, 6, 2.8),
    (22, 30, 8, 3.3), (30, 38, 10, 3.3), (38, 44, 12, 3.3), (44, 50, 14, 3.8), (50, 58, 16, 4.3),
    (58, 65, 18, 4.4), (65, 75, 20, 4.9), (75, 85, 22, 5.4), (85, 95, 25, 5.4), (95, 110, 28, 6.4),
    (110, 130, 32, 7.4), (130, 150, 36, 8.4), (150, 170, 40, 9.4), (170, 200, 45, 10.4),
    (200, 230, 50, 11.4),
)
#: ANSI B17.1 square keys: (shaft diameter over, up to [in], key width W [in])
ANSI_B17_1 = (
    (5 / 16, 7 / 16, 3 / 32), (7 / 16, 9 / 16, 1 / 8), (9 / 16, 7 / 8, 3 / 16), (7 / 8, 1.25, 1 / 4),
    (1.25, 1.375, 5 / 16), (1.375, 1.75, 3 / 8), (1.75, 2.25, 1 / 2), (2.25, 2.75, 5 / 8),
    (2.75, 3.25, 3 / 4), (3.25, 3.75, 7 / 8), (3.75, 4.5, 1.0), (4.5, 5.5, 1.25), (5.5, 6.5, 1.5),
)
MM_PER_IN = 25.4
#: the +Y direction of the cam frame
KEY_ANGLE = math.pi / 2
#: defaults that depend on the spec's units (a value of the field overrides them)
UNIT_DEFAULTS = {
    "mm": {"timing_mark_width": 0.5, "timing_mark_depth": 0.2, "clearance": 0.05, "min_wall": 3.0},
    "in": {"timing_mark_width": 0.02, "timing_mark_depth": 0.008, "clearance": 0.002, "min_wall": 0.12},
}


def resolved(spec, section: str, name: str) -> float:
    """``spec.<section>.<name>``, or its default in the spec's units."""
    v = getattr(getattr(spec, section), name)
    return UNIT_DEFAULTS[spec.units][name] if v is None else v


def keyway_size(spec) -> tuple[float, float] | None:
    """(width, depth from the bore at the keyway's centre line) [spec lengths], or None."""
    cam = spec.cam
    if cam.keyway_width is not None:
        return cam.keyway_width, cam.keyway_depth
    if not cam.keyway:
        return None
    d = cam.bore_diameter
    to_mm = MM_PER_IN if spec.units == "in" else 1.0
    if cam.keyway == "DIN6885":
        dm = d * to_mm
        for lo, hi, b, t2 in DIN6885:
            if lo < dm <= hi:
                return b / to_mm, t2 / to_mm
        raise SpecError("cam.keyway", f"DIN 6885-1 covers bores over 6 up to 230 mm; cam.bore_diameter is "
                        f"{dm:g} mm")
    di = d * to_mm / MM_PER_IN
    for lo, hi, w in ANSI_B17_1:
        if lo < di <= hi:
            w_u = w * MM_PER_IN / to_mm
            r = d / 2
            # keyseat W/2 deep at its side: bottom at √(r² − (W/2)²) + W/2 from the axis
            bottom = math.sqrt(r * r - (w_u / 2) ** 2) + w_u / 2
            return w_u, bottom - r
    raise SpecError("cam.keyway", f"ANSI B17.1 covers bores over 5/16 up to 6 1/2 in; cam.bore_diameter is "
                    f"{di:g} in")


def bore_loop(spec) -> Loop | None:
    """The bore, with its keyway when the spec asks for one (counter-clockwise), or None."""
    r = spec.cam.bore_diameter / 2
    if r <= 0:
        return None
    key = keyway_size(spec)
    if key is None:
        return Loop.circle(r, role="bore")
    w, depth = key
    half = math.asin(min(w / 2 / r, 1.0))
    a = KEY_ANGLE
    u, n = np.exp(1j * a), np.exp(1j * (a + np.pi / 2))        # along the key, across it
    top = r + depth
    p_left = r * np.exp(1j * (a + half))                       # where the keyway meets the bore
    p_right = r * np.exp(1j * (a - half))
    return Loop((Arc(0j, r, a + half, a - half + 2 * np.pi),   # the bore, the long way round
                 Line(p_right, top * u - w / 2 * n),
                 Line(top * u - w / 2 * n, top * u + w / 2 * n),
                 Line(top * u + w / 2 * n, p_left)), role="bore")


def bore_extent(spec) -> float:
    """The largest distance of the bore (and keyway) from the axis."""
    r = spec.cam.bore_diameter / 2
    key = keyway_size(spec) if r > 0 else None
    if key is None:
        return r
    w, depth = key
    return math.hypot(r + depth, w / 2)


def hub_prism(spec, z_top: float = 0.0) -> Prism | None:
    """The hub below the plate (z_top − hub_length ≤ z ≤ z_top; z_top = 0: under the plate's
    bottom face), bored as the plate."""
    cam = spec.cam
    if not cam.hub_diameter or not cam.hub_length:
        return None
    bore = bore_loop(spec)
    return Prism(Loop.circle(cam.hub_diameter / 2, role="hub"), (bore,) if bore else (), z_top - cam.hub_length,
                 z_top, "add", "hub")


def mounting_holes(spec, z0: float, z1: float) -> list[Prism]:
    """The mounting holes: ``cam.mounting_holes`` circles of ``mounting_hole_diameter`` equally
    spaced on ``mounting_circle_diameter``, the first at +Y (with the keyway), through z0..z1."""
    cam = spec.cam
    n = cam.mounting_holes or 0
    if n <= 0:
        return []
    rc, rh = cam.mounting_circle_diameter / 2, cam.mounting_hole_diameter / 2
    angles = KEY_ANGLE + 2 * np.pi * np.arange(n) / n
    return [Prism(Loop.circle(rh, complex(rc * np.exp(1j * a)), role="hole"), (), z0, z1, "cut", f"hole{k}")
            for k, a in enumerate(angles)]


def timing_mark(spec, angle: float, r_in: float, r_out: float, z_top: float) -> Prism | None:
    """An engraved radial line on the top face at cam-frame angle ``angle`` [rad], from r_in to
    r_out, ``cam.timing_mark_width`` wide and ``cam.timing_mark_depth`` deep."""
    cam = spec.cam
    if not cam.timing_mark:
        return None
    w, d = resolved(spec, "cam", "timing_mark_width"), resolved(spec, "cam", "timing_mark_depth")
    r_in, r_out = _clear_of_holes(spec, angle, r_in, r_out, w)
    u, n = np.exp(1j * angle), np.exp(1j * (angle + np.pi / 2))
    pts = [r_in * u - w / 2 * n, r_out * u - w / 2 * n, r_out * u + w / 2 * n, r_in * u + w / 2 * n]
    loop = Loop(tuple(Line(complex(a), complex(b)) for a, b in zip(pts, pts[1:] + pts[:1])), role="timing_mark")
    return Prism(loop, (), z_top - d, z_top, "cut", "timing_mark")


def _clear_of_holes(spec, angle: float, r_in: float, r_out: float, w: float) -> tuple[float, float]:
    """The longest stretch of the mark's ray [r_in, r_out] that keeps w clear of every mounting
    hole (the first hole sits at +Y, where a radial follower's mark runs): a mark crossing a hole
    would cut material the hole already removed, and the body's volume (Σ ± prisms) counts cuts
    that do not overlap.

    Raises:
        SpecError: no stretch of at least 2·w is left (``cam.timing_mark``)."""
    cam = spec.cam
    n = cam.mounting_holes or 0
    pieces = [(r_in, r_out)]
    if n > 0:
        rc, rh = cam.mounting_circle_diameter / 2, cam.mounting_hole_diameter / 2
        for a in KEY_ANGLE + 2 * np.pi * np.arange(n) / n:
            along, across = rc * math.cos(a - angle), abs(rc * math.sin(a - angle))
            if across >= rh + w or along <= 0:
                continue
            # every point of the strip with |r − along| ≥ rh + w is more than rh from the centre
            lo, hi = along - (rh + w), along + (rh + w)
            pieces = [q for a0, a1 in pieces for q in ((a0, min(a1, lo)), (max(a0, hi), a1)) if q[1] > q[0]]
    best = max(pieces, key=lambda q: q[1] - q[0], default=None)
    if best is None or best[1] - best[0] < 2 * w:
        raise SpecError("cam.timing_mark", f"no room for a {w:g} wide mark along the follower's line at θ = 0 "
                        "between the bore, the mounting holes and the profile (leave it out, or move the holes)")
    return best


def hole_ligaments(spec, inner_radius_at, bore: float) -> dict:
    """Material left around the mounting holes: (to the bore, to the nearest outer boundary,
    between neighbouring holes) [spec lengths]; ``inner_radius_at(angle)`` gives the radius of the
    boundary the holes must stay inside (the profile, or a groove's inner wall) along a ray."""
    cam = spec.cam
    n = cam.mounting_holes or 0
    rc, rh = cam.mounting_circle_diameter / 2, cam.mounting_hole_diameter / 2
    angles = KEY_ANGLE + 2 * np.pi * np.arange(n) / n
    # the boundary radius over the hole's angular width, a small margin of rays
    span = np.arcsin(min(rh / rc, 1.0))
    rays = angles[:, None] + np.linspace(-span, span, 9)[None, :]
    outer = float(np.min(inner_radius_at(rays.ravel()))) - (rc + rh)
    between = 2 * rc * math.sin(math.pi / n) - 2 * rh if n > 1 else float("inf")
    return {"to_bore": rc - rh - bore, "to_outer": outer, "between": between}


def zero_angle(design) -> float:
    """Cam-frame polar angle [rad] of the follower's contact at θ = 0 (where the timing mark goes)."""
    k = design.program.evaluate(np.array([0.0]))
    p = design.follower.points(np.array([0.0]), k)[0]
    return float(np.angle(p))


def plate_features(design, t: float) -> list[Prism]:
    """The features of a body whose top face is the plate's (0 ≤ z ≤ t): the hub below it, the
    mounting holes through it and the timing mark from the bore (and keyway) to the profile."""
    spec = design.spec
    out = [p for p in (hub_prism(spec),) if p is not None]
    out += mounting_holes(spec, 0.0, t)
    mw = resolved(spec, "cam", "timing_mark_width")
    mark = timing_mark(spec, zero_angle(design), bore_extent(spec) + 1.5 * mw,
                       design.min_profile_radius - 1.5 * mw, t)
    return out + ([mark] if mark is not None else [])


def validate_features(spec) -> None:
    """The rules every body shares (called by the spec's validation after the body's own): no
    field another body owns (its ``own_fields``, its ``refuse_foreign`` rules), and a bore, keyway,
    hub, mounting holes and timing mark that fit.

    Raises:
        SpecError: naming the field and the rule.
    """
    cam = spec.cam
    mine = body_of(spec)
    for other in bodies().values():
        if other is not mine:
            other.refuse_foreign(spec)
    owned = {b.kind: b.own_fields for b in bodies().values() if b.own_fields}
    for name in sorted({n for names in owned.values() for n in names}):
        owners = [b for b, names in owned.items() if name in names]
        if name not in mine.own_fields and getattr(cam, name) is not None:
            which = " and ".join(owners)
            raise SpecError(f"cam.{name}", f"applies to {which} cams only (cam.body = "
                            + " or ".join(f'"{b}"' for b in owners) + ")")
    if (cam.keyway is not None or cam.keyway_width is not None) and cam.bore_diameter <= 0:
        raise SpecError("cam.keyway" if cam.keyway is not None else "cam.keyway_width",
                        "needs a bore: cam.bore_diameter > 0")
    if cam.keyway is not None and (cam.keyway_width is not None or cam.keyway_depth is not None):
        raise SpecError("cam.keyway", "give a standard or keyway_width and keyway_depth, not both")
    if (cam.keyway_width is None) != (cam.keyway_depth is None):
        missing = "cam.keyway_depth" if cam.keyway_depth is None else "cam.keyway_width"
        raise SpecError(missing, "is required with the other explicit keyway dimension")
    if cam.keyway_width is not None and not cam.keyway_width < cam.bore_diameter:
        raise SpecError("cam.keyway_width", f"must be < cam.bore_diameter ({fmt_apart(cam.bore_diameter, cam.keyway_width)}), "
                        f"got {fmt_apart(cam.keyway_width, cam.bore_diameter)}")
    if (cam.hub_diameter is None) != (cam.hub_length is None):
        missing = "cam.hub_length" if cam.hub_length is None else "cam.hub_diameter"
        raise SpecError(missing, "is required with the other hub dimension")
    if cam.hub_diameter is not None:
        if not cam.hub_diameter / 2 > bore_extent(spec):
            reach = bore_extent(spec)
            raise SpecError("cam.hub_diameter", f"must leave material around the bore and keyway (they reach "
                            f"{fmt_apart(reach, cam.hub_diameter / 2, 4)} from the axis), got "
                            f"{fmt_apart(cam.hub_diameter, 2 * reach)}")
    if cam.mounting_holes:
        for name in ("mounting_hole_diameter", "mounting_circle_diameter"):
            if getattr(cam, name) is None:
                raise SpecError(f"cam.{name}", "is required with cam.mounting_holes")
    if cam.timing_mark and not resolved(spec, "cam", "timing_mark_depth") < cam.thickness:
        depth = resolved(spec, "cam", "timing_mark_depth")
        raise SpecError("cam.timing_mark_depth", f"must be < cam.thickness ({fmt_apart(cam.thickness, depth)}), got "
                        f"{fmt_apart(depth, cam.thickness)}")


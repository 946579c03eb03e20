"""Figures of a cylindrical (barrel) cam as :class:`~.chart.Chart` s: the cylinder with its groove
beside the developed view (its picture, registered in :data:`cam_workbench.exporters.plots.PICTURES`),
and the pressure angle at the pitch and the bottom radius (the report's figures).

The cylinder is drawn in an orthographic projection computed here (:func:`project`, the view of
matplotlib's ``view_init(elev=18, azim=20)``): lines on the far side of the cylinder are drawn faint."""
from __future__ import annotations

import numpy as np

from cam_workbench.generators.bodies.cylindrical import CylindricalDesign, pressure_angles

from .chart import Area, Chart, Curve, Panel, Rule, angle_panel, css_color
from .plots import PICTURES

#: the view of the cylinder: elevation and azimuth [deg] of the viewing direction (matplotlib's view_init)
ELEVATION_DEG = 18.0
AZIMUTH_DEG = 20.0

_LINE = "#1f3a5f"
_FILL = "#b4c7dc"
_HIDDEN_ALPHA = 0.25


def project(points: np.ndarray, elev_deg: float = ELEVATION_DEG, azim_deg: float = AZIMUTH_DEG) -> np.ndarray:
    """Orthographic projection of 3D points (..., 3) seen from the direction at elevation ``elev_deg``
    and azimuth ``azim_deg`` (the z axis up on the screen): their screen points (..., 2)."""
    e, a = np.deg2rad(elev_deg), np.deg2rad(azim_deg)
    view = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    right = np.array([-np.sin(a), np.cos(a), 0.0])
    up = np.cross(view, right)
    p = np.asarray(points, dtype=float)
    return np.stack([p @ right, p @ up], axis=-1)


def _on_front(points: np.ndarray, azim_deg: float = AZIMUTH_DEG) -> np.ndarray:
    """Points on (or in a groove of) the cylinder's mantle that face the viewer."""
    a = np.deg2rad(azim_deg)
    return points[..., 0] * np.cos(a) + points[..., 1] * np.sin(a) >= 0.0


def _seen_and_hidden(points: np.ndarray, seen: np.ndarray, color: str, width: float, alpha: float = 1.0
                     ) -> list[Curve]:
    """A projected 3D polyline as two curves: the part where ``seen`` (solid) and the rest (faint);
    each part runs one point into the other so that they meet."""
    xy = project(points)
    near = seen | np.r_[seen[1:], False] | np.r_[False, seen[:-1]]
    far = ~seen | np.r_[~seen[1:], False] | np.r_[False, ~seen[:-1]]
    out = []
    for mask, a in ((far, alpha * _HIDDEN_ALPHA), (near, alpha)):
        if mask.any():
            out.append(Curve(np.where(mask, xy[:, 0], np.nan), np.where(mask, xy[:, 1], np.nan), color=color,
                             width=width, alpha=a))
    return out


def _circle(radius: float, z: float, psi: np.ndarray) -> np.ndarray:
    return np.column_stack([radius * np.cos(psi), radius * np.sin(psi), np.full_like(psi, z)])


def _cylinder_panel(design: CylindricalDesign, follower_angle_deg: float) -> Panel:
    """The cylinder (outline, end circles, bore, silhouette lines), its groove's walls at R_o and R_b
    and the roller with its stem, projected (:func:`project`)."""
    lay = design.layout
    u = design.spec.units
    ro, rb, length = lay.outer_radius, lay.bottom_radius, lay.length
    ax = Panel(equal=True, axes=False, xlabel="", ylabel="", height=300.0,
               title=f"cylindrical cam: R_p = {lay.pitch_radius:g}, R_o = {ro:g}, L = {length:g} {u}\n"
                     f"groove {2 * lay.half_width:g} wide, {ro - rb:g} deep; roller at θ = {follower_angle_deg:g}°")
    a = np.deg2rad(AZIMUTH_DEG)
    # the outline: the near half of the bottom circle, the far half of the top one; the bore a hole
    front = np.linspace(a - np.pi / 2, a + np.pi / 2, 91)
    outline = np.vstack([_circle(ro, 0.0, front), _circle(ro, length, front + np.pi)])
    psi = np.linspace(0, 2 * np.pi, 181)
    ax.add(Area([project(outline), project(_circle(lay.bore_radius, length, psi))], fill=_FILL, alpha=0.35))
    # the end circles and the bore (the bottom's far half and its bore are behind the cylinder)
    top = np.ones_like(psi, dtype=bool)
    for z, rim_seen, bore_seen in ((0.0, _on_front(_circle(ro, 0.0, psi)), ~top), (length, top, top)):
        ax.add(*_seen_and_hidden(_circle(ro, z, psi), rim_seen, _LINE, 0.8))
        ax.add(*_seen_and_hidden(_circle(lay.bore_radius, z, psi), bore_seen, _LINE, 0.6))
    # the silhouette: the two generators whose surface normals are square to the view
    for g in (a - np.pi / 2, a + np.pi / 2):
        xy = project(np.array([[ro * np.cos(g), ro * np.sin(g), 0.0], [ro * np.cos(g), ro * np.sin(g), length]]))
        ax.add(Curve(xy[:, 0], xy[:, 1], color=_LINE, width=0.8))
    # the groove's walls: exact points at the outer radius and at the bottom
    th = np.linspace(0, 2 * np.pi, 1441)
    for side in (-1, 1):
        for rho, lw, alpha in ((ro, 1.4, 1.0), (rb, 0.8, 0.6)):
            p = design.wall_points(side, th, rho)
            ax.add(*_seen_and_hidden(p, _on_front(p), _LINE, lw, alpha))
    # the roller (its axis radial through the pitch point) in the cylinder's tangent plane at R_o, and its stem
    cx, cy, zc = lay.centre_point(design.program, float(np.deg2rad(follower_angle_deg)))
    phi0 = float(np.arctan2(cy, cx))
    t = np.linspace(0, 2 * np.pi, 61)
    r = design.spec.roller_radius
    radial, tangent = np.array([np.cos(phi0), np.sin(phi0), 0.0]), np.array([-np.sin(phi0), np.cos(phi0), 0.0])
    roller = ro * radial + np.outer(r * np.cos(t), tangent) + np.outer(zc + r * np.sin(t), [0.0, 0.0, 1.0])
    stem = np.array([ro * radial + [0.0, 0.0, zc], (ro + 2.5 * r) * radial + [0.0, 0.0, zc]])
    for pts, color, lw in ((roller, "#c8871e", 2.0), (stem, "#8b5e14", 3.0)):
        xy = project(pts)
        ax.add(Curve(xy[:, 0], xy[:, 1], color=color, width=lw))
    return ax


def _developed_panel(design: CylindricalDesign) -> Panel:
    """The developed view (x = ρ·ψ, z): the walls at R_o, the pitch line at R_p, the cylinder's
    developed outline."""
    lay = design.layout
    u = design.spec.units
    ro, length = lay.outer_radius, lay.length
    ax = Panel(equal=True, xlabel=f"x = ρ·ψ [{u}] along the circumference", ylabel=f"z [{u}] along the cam axis",
               title="developed view (the DXF's view)", legend="below", legend_columns=3, height=110.0)
    th = np.linspace(0, 2 * np.pi, 1441)
    for side in (-1, 1):
        p = design.developed_points(ro, side, th)
        ax.add(Curve(p[:, 0], p[:, 1], color=_LINE, width=1.2, label="walls at R_o (±w/2)" if side == -1 else None))
    p = design.developed_points(lay.pitch_radius, 0, th)
    ax.add(Curve(p[:, 0], p[:, 1], color="#c0392b", width=1.0, dash="--", label="pitch line at R_p"))
    x0, x1 = sorted((ro * float(lay.phi(0.0)), ro * float(lay.phi(2 * np.pi))))
    ax.add(Curve(np.array([x0, x1, x1, x0, x0]), np.array([0.0, 0.0, length, length, 0.0]), color=css_color("0.3"),
                 width=0.8, label="cylinder, developed at R_o"))
    return ax


@PICTURES.register(CylindricalDesign)
def cylindrical_figure(design: CylindricalDesign, follower_angle_deg: float = 75.0) -> Chart:
    """A cylindrical (barrel) cam: a view of the cylinder with its groove (the walls at the outer
    radius and at the groove's bottom, the exact wall points of
    :func:`cam_workbench.generators.bodies.cylindrical.wall_points`) and the roller at ``follower_angle_deg``,
    beside the developed view (x = ρ·ψ [length], z): the walls at R_o, the pitch line at R_p."""
    return Chart([[_cylinder_panel(design, follower_angle_deg)], [_developed_panel(design)]], width=800.0,
                 widths=(1.0, 1.0))


def cylindrical_pressure_angle_figure(design: CylindricalDesign, limit_deg: float | None) -> Chart:
    """A cylindrical cam's pressure angle [deg] at R_p and R_b against the cam angle, with the
    check's limit (±``limit_deg``, report.json's)."""
    lay = design.layout
    th = design.program.dense_angles(721)
    deg = np.rad2deg(th)
    ax = angle_panel(xlabel="cam angle θ [deg]", ylabel="pressure angle φ [deg]", legend="below",
                     legend_columns=2, height=200.0)
    ax.add(Curve(deg, pressure_angles(lay, design.program, lay.pitch_radius, th), color=_LINE,
                 width=1.5, label=f"at the pitch radius R_p = {lay.pitch_radius:g}"))
    ax.add(Curve(deg, pressure_angles(lay, design.program, lay.bottom_radius, th), color="#c8871e", width=1.5,
                 dash="--", label=f"at the groove's bottom R_b = {lay.bottom_radius:.4g}"))
    if limit_deg is not None:
        for sgn in (1, -1):
            ax.add(Rule("y", sgn * limit_deg, color="#c0392b", width=0.8, dash=":",
                        label="limit" if sgn == 1 else None))
    return Chart.stack([ax], width=560.0)

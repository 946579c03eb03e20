"""Matplotlib figures of a cylindrical (barrel) cam: the cylinder with its groove beside the
developed view (its picture, registered in :data:`cam_workbench.exporters.plots.PICTURES`), and the
pressure angle at the pitch and the bottom radius (the report's figures)."""
from __future__ import annotations

from typing import Any

import numpy as np

from cam_workbench.generators.bodies.cylindrical import CylindricalDesign, pressure_angles

from .plots import PICTURES, _plt


@PICTURES.register(CylindricalDesign)
def cylindrical_figure(design: Any, follower_angle_deg: float = 75.0) -> Any:
    """A cylindrical (barrel) cam: a 3D view of the cylinder with its groove (the walls at the outer
    radius and at the groove's bottom, the exact wall points of
    :func:`cam_workbench.generators.bodies.cylindrical.wall_points`) and the roller at ``follower_angle_deg``,
    beside the developed view (x = ρ·ψ [length], z): the walls at R_o, the pitch line at R_p."""
    plt = _plt()
    lay = design.layout
    u = design.spec.units
    fig = plt.figure(figsize=(11, 5))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    ro, rb, length = lay.outer_radius, lay.bottom_radius, lay.length
    psi = np.linspace(0, 2 * np.pi, 121)
    zz = np.linspace(0, length, 2)
    P, Z = np.meshgrid(psi, zz)
    ax.plot_surface(ro * np.cos(P), ro * np.sin(P), Z, color="#b4c7dc", alpha=0.35, linewidth=0)
    for z in (0.0, length):
        ax.plot(ro * np.cos(psi), ro * np.sin(psi), z, color="#1f3a5f", lw=0.8)
        ax.plot(lay.bore_radius * np.cos(psi), lay.bore_radius * np.sin(psi), z, color="#1f3a5f", lw=0.6)
    th = np.linspace(0, 2 * np.pi, 1441)
    for side in (-1, 1):
        for rho, lw, alpha in ((ro, 1.4, 1.0), (rb, 0.8, 0.6)):
            p = design.wall_points(side, th, rho)
            ax.plot(p[:, 0], p[:, 1], p[:, 2], color="#1f3a5f", lw=lw, alpha=alpha)
    t0 = np.deg2rad(follower_angle_deg)
    cx, cy, zc = lay.centre_point(design.program, float(t0))      # the roller centre on the pitch cylinder
    phi0 = float(np.arctan2(cy, cx))
    a = np.linspace(0, 2 * np.pi, 61)
    r = design.spec.roller_radius
    # the roller (its axis radial through the pitch point) in the cylinder's tangent plane, at R_o
    tx, ty = -np.sin(phi0), np.cos(phi0)
    ax.plot(ro * np.cos(phi0) + r * np.cos(a) * tx, ro * np.sin(phi0) + r * np.cos(a) * ty, zc + r * np.sin(a),
            color="#c8871e", lw=2.0)
    ax.plot([ro * np.cos(phi0), (ro + 2.5 * r) * np.cos(phi0)], [ro * np.sin(phi0), (ro + 2.5 * r) * np.sin(phi0)],
            [zc, zc], color="#8b5e14", lw=3)
    ax.set_box_aspect((1, 1, length / (2 * ro)))
    ax.set_xlabel(f"x [{u}]", fontsize=8)
    ax.set_ylabel(f"y [{u}]", fontsize=8)
    ax.set_zlabel(f"z [{u}]", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.view_init(elev=18, azim=20)
    ax.set_title(f"cylindrical cam: R_p = {lay.pitch_radius:g}, R_o = {ro:g}, L = {length:g} {u}\n"
                 f"groove {2 * lay.half_width:g} wide, {ro - rb:g} deep; roller at θ = {follower_angle_deg:g}°",
                 fontsize=9)
    ad = fig.add_subplot(1, 2, 2)
    for side in (-1, 1):
        p = design.developed_points(ro, side, th)
        ad.plot(p[:, 0], p[:, 1], color="#1f3a5f", lw=1.2, label="walls at R_o (±w/2)" if side == -1 else None)
    p = design.developed_points(lay.pitch_radius, 0, th)
    ad.plot(p[:, 0], p[:, 1], "--", color="#c0392b", lw=1.0, label="pitch line at R_p")
    x0, x1 = sorted((ro * float(lay.phi(0.0)), ro * float(lay.phi(2 * np.pi))))
    ad.plot([x0, x1, x1, x0, x0], [0, 0, length, length, 0], color="0.3", lw=0.8, label="cylinder, developed at R_o")
    ad.set_aspect("equal")
    ad.set_xlabel(f"x = ρ·ψ [{u}] along the circumference", fontsize=8)
    ad.set_ylabel(f"z [{u}] along the cam axis", fontsize=8)
    ad.tick_params(labelsize=7)
    ad.grid(alpha=0.25)
    ad.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.3), ncol=3)
    ad.set_title("developed view (the DXF's view)", fontsize=9)
    fig.tight_layout()
    return fig


def cylindrical_pressure_angle_figure(design: Any, limit_deg: float | None) -> Any:
    """A cylindrical cam's pressure angle [deg] at R_p and R_b against the cam angle, with the
    check's limit (±``limit_deg``, report.json's)."""
    lay = design.layout
    th = design.program.dense_angles(721)
    deg = np.rad2deg(th)
    fig, ax = _plt().subplots(figsize=(7.0, 3.2))
    ax.plot(deg, pressure_angles(lay, design.program, lay.pitch_radius, th), color="#1f3a5f",
            label=f"at the pitch radius R_p = {lay.pitch_radius:g}")
    ax.plot(deg, pressure_angles(lay, design.program, lay.bottom_radius, th), "--", color="#c8871e",
            label=f"at the groove's bottom R_b = {lay.bottom_radius:.4g}")
    if limit_deg is not None:
        for sgn in (1, -1):
            ax.axhline(sgn * limit_deg, color="#c0392b", lw=0.8, ls=":", label="limit" if sgn == 1 else None)
    ax.set_xlabel("cam angle θ [deg]")
    ax.set_ylabel("pressure angle φ [deg]")
    ax.set_xlim(0, 360)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig

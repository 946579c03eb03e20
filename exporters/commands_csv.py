"""``commands.csv``: the rotational interpolator's raw commands (paper Eq. 15), one row per
sample period, for an open-architecture controller.

Columns (length unit in the header names): ``k`` command index; ``t_s`` time [s];
``theta_deg`` cam angle turned since the start [deg, ≥ 0]; ``c_deg`` the same angle
signed by the turning sense (the C axis: + counter-clockwise seen from +Z);
``segment`` PH segment (0-based); ``xi`` its parameter; ``x_<u>``, ``y_<u>`` the command
point r(ξ) in the cam frame (X_com, Y_com); ``s_actual_<u>`` the follower displacement
the command produces; ``s_desired_<u>`` the motion program's s(θ).
"""
from __future__ import annotations

import io

import numpy as np

from cam_workbench.generators.machining.interpolator import Commands


def commands_csv_text(cmds: Commands, units: str = "mm") -> str:
    """The command table as CSV text (full double precision, '.' decimal point)."""
    cols = ["k", "t_s", "theta_deg", "c_deg", "segment", "xi", f"x_{units}", f"y_{units}",
            f"s_actual_{units}", f"s_desired_{units}"]
    theta = np.rad2deg(cmds.theta)
    data = np.column_stack([np.arange(cmds.n), cmds.t, theta, cmds.sense * theta, cmds.seg, cmds.xi,
                            cmds.x, cmds.y, cmds.s_actual, cmds.s_desired])
    buf = io.StringIO()
    buf.write(",".join(cols) + "\n")
    np.savetxt(buf, data, delimiter=",",
               fmt=["%d", "%.9g", "%.12g", "%.12g", "%d", "%.17g", "%.17g", "%.17g", "%.17g", "%.17g"])
    return buf.getvalue()

"""The tolerance chart: the largest profile tolerance against the number of waves per turn
(``tolerance.json``'s ``chart``), as a :class:`~.chart.Chart` drawn by :mod:`.chart_svg`."""
from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from .chart import Chart, Curve, Panel
from .report_cells import format_number as fmt


def tolerance_figure(study: Mapping[str, Any]) -> Chart:
    """The chart of ``study`` (tolerance.json's numbers): the tolerance t(n) (solid), the
    acceleration limit's t_a(n) (dashed) and the contact limit's t_c(n) (dotted), log scale."""
    c = study["chart"]
    n = np.asarray(c["waves"], dtype=float)
    unit = study["units"]

    def values(key: str) -> np.ndarray:
        return np.array([np.nan if v is None else v for v in c[key]], dtype=float)

    panel = Panel(xlabel="waves per turn n", ylabel=f"profile tolerance t [{unit}]", logy=True,
                  xlim=(0.0, float(n[-1])), legend="upper right", height=240.0)
    panel.add(Curve(n, values("acceleration_tolerance"), color="#2e86c1", dash="--", width=1.0,
                    label="acceleration limit t_a", gid="acceleration_tolerance"),
              Curve(n, values("contact_tolerance"), color="#b03a2e", dash=":", width=1.2,
                    label="contact limit t_c (the follower leaves the waves)", gid="contact_tolerance"),
              Curve(n, values("tolerance"), color="#1f3b5c", width=1.8, label="tolerance t = min(t_a, t_c)",
                    gid="tolerance"))
    title = (f"Profile tolerance (ISO 1101 profile of a line, zone ±t/2, worst wave phase)\nfor an acceleration "
             f"error ≤ {fmt(100 * study['acceleration_limit'])} % of the designed peak "
             f"({fmt(study['designed_peak_acceleration'])} {study['acceleration_unit']}) at "
             f"{fmt(study['speed_rpm'])} rpm\n{study['cam']}")
    return Chart.stack([panel], width=720.0, title=title)


__all__ = ["tolerance_figure"]

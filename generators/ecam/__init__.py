"""Electronic-cam tables: the motion program sampled as the points a servo
controller's cam table holds, and the deviation of the table's own interpolation from the exact
motion.  The files themselves (CSV, CODESYS, Beckhoff, Lenze) are written by :mod:`cam_workbench.exporters.ecam`.
"""
from .tables import (INTERPOLATIONS, Deviation, TablePoints, interpolate, interpolation_deviation,
                     quintic_coefficients, table_points)

__all__ = ["INTERPOLATIONS", "Deviation", "TablePoints", "interpolate", "interpolation_deviation",
           "quintic_coefficients", "table_points"]

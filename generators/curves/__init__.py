"""Cam-agnostic curves: Bézier, banded solves, extrema, the PH spline, NURBS data, exact
offsets, arcs and lines within a tolerance.
"""

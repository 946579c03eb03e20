"""Checks of a designed cam: buildability, the design checks, areas, and what the outputs may claim.
"""

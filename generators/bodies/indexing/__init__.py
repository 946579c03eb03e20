"""Indexing cams (rotary indexers): a cam on a continuously turning input shaft turns an output
turret by 360°/N during the input's index angle β and holds it still for the rest of the turn.

* :mod:`.parallel` — the parallel (plate-cam) indexer's geometry: roller loci, the cams' pitch
  curves and profiles, engagement, pressure angles, locking and clearance, the turret angle
  recovered from the built profiles;
* :mod:`.parallel_body` — the parallel indexer's cams as prisms of loops (exact dwell arcs, fitted flanks);
* :mod:`cam_workbench.generators.optimise.parallel_indexer` (the optimise stage) — its centre distance,
  pitch radius and roller radius optimised (nlopt);
* :mod:`.spatial` — the barrel and globoidal indexers: the rib flanks as envelopes of the rollers
  (contact lines in closed form from the meshing equation), pressure angles, the envelope's
  regularity, rib thickness, the turret angle recovered from the flank points;
* :mod:`.spatial_surfaces` — the spatial flanks as bicubic B-spline surfaces within a tolerance of
  the exact envelope (measured);
* :mod:`.spatial_sheets` — the spatial flanks' sheets for the cam's solid: each fitted surface
  continued along the exact envelope until it cuts through the rib's band, with its skirt beyond
  the root (plain B-spline data, which the kernel and the FreeCAD workbench make into faces), and
  the seam angle of the band and the core;
* :mod:`.parallel_drive` — the parallel indexer's drive sized from its built geometry;
* :mod:`.spatial_drive` — the barrel and globoidal indexers' drive sized from their contact lines
  (a uniform line load, the cam radius from the envelope's regularity margin);
* :mod:`.fields` — the field rules the indexers' parameter classes share;
* :mod:`.sizing` — the drive's sizing from the load: times, output motion, torques and power,
  the driving roller's normal load, Hertz stress and bearing life.
"""
from .sizing import DriveSizing, IndexLoad, drive_sizing, equivalent_load, rating_life

__all__ = ["DriveSizing", "IndexLoad", "drive_sizing", "equivalent_load", "rating_life"]

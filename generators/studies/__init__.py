"""Design studies: many designs at once — grids of spec fields, the smallest base
radius per grid point (sizing charts) — and the executor interface through which they, a batch
and the optimiser's multistart hand out independent tasks.  Pure: numpy, scipy and the standard
library; a parallel engine (Dask) is passed in from the layer above as an executor."""

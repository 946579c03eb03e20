"""The built-in kinds, imported so that each registers itself with :mod:`cam_workbench.generators.kinds`
(:mod:`cam_workbench.generators` imports this module when it loads): the bodies in the order
their names are listed (plate, groove, conjugate, cylindrical, the indexers), the follower kinds.  A body's own
optimiser or tool path registers with its stage's package (:mod:`cam_workbench.generators.optimise`,
:mod:`cam_workbench.generators.machining`), which any use of that stage imports."""
from __future__ import annotations

from ..bodies import plate, groove, conjugate, cylindrical  # noqa: F401  (each registers its body)
from ..bodies.indexing import parallel_kind  # noqa: F401  (registers the parallel indexer)
from ..bodies.indexing import spatial_kind  # noqa: F401  (registers the barrel and globoidal indexers)
from ..followers import translating, oscillating, flat  # noqa: F401  (each registers its follower kinds)

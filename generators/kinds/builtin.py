"""The built-in kinds, imported so that each registers itself with :mod:`cam_workbench.generators.kinds`
(:mod:`cam_workbench.generators` imports this module when it loads): the bodies in the order
their names are listed (plate, groove, conjugate, cylindrical), the follower kinds."""
from __future__ import annotations

from ..bodies import plate, groove, conjugate, cylindrical  # noqa: F401  (each registers its body)
from ..followers import translating, oscillating, flat  # noqa: F401  (each registers its follower kinds)
from ..optimise import cylindrical as _cylinder_optimiser  # noqa: F401  (registers the cylindrical cam's optimiser)
from ..machining import groove as _groove_path  # noqa: F401  (registers the groove's tool path)

"""The optimiser (thesis Ch. 5–7): design variables, constraints with exact sensitivities,
objectives, and the nlopt drivers.  ``from cam_workbench.generators.optimise import optimise``.

nlopt is imported only when a solver runs (:mod:`cam_workbench.generators.optimise.driver`), so importing this
package — and ``generators`` — never loads it.
"""
from .problem import Cancelled
from .result import OptimiseResult, Progress, final_value, worst_constraint
from .run import optimise
from . import cylindrical as _cylinder_optimiser  # noqa: F401,E402  (registers the cylindrical cam's optimiser)
from . import indexer as _indexer_optimiser  # noqa: F401,E402  (registers the parallel indexer's optimiser)
from . import spatial_indexer as _spatial_optimiser  # noqa: F401,E402  (registers the barrel and globoidal indexers')

__all__ = ["Cancelled", "OptimiseResult", "Progress", "final_value", "optimise", "worst_constraint"]

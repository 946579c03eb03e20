"""The optimiser (thesis Ch. 5–7): design variables, constraints with exact sensitivities,
objectives, and the nlopt drivers.  ``from cam_workbench.generators.optimise import optimise``.

nlopt is imported only when a solver runs (:mod:`cam_workbench.generators.optimise.run`), so importing this
package — and ``generators`` — never loads it.
"""
from .run import Cancelled, OptimiseResult, Progress, final_value, optimise, worst_constraint

__all__ = ["Cancelled", "OptimiseResult", "Progress", "final_value", "optimise", "worst_constraint"]

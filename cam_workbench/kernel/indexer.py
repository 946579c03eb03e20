"""The parallel indexer's solid through OCP: its plates (each profile a loop of exact dwell arcs and
fitted B-spline flanks), the spacer discs between them and the bore, all prisms of the body
(:attr:`~cam_workbench.generators.bodies.indexing.parallel_kind.ParallelIndexerDesign.body`), as one
solid by :func:`~.solids.prism_stack` — sewn from the stack's caps and sides, booleans only where
that does not close — or, where the sewn solid is not valid (plates face to face, ``indexer.gap``
0, whose outlines cross in their common plane at grazing angles), by booleans alone
(:func:`~.solids.fused_prisms`).  Registered in :data:`cam_workbench.kernel.solids.SOLIDS` for
:class:`~cam_workbench.generators.bodies.indexing.parallel_kind.ParallelIndexerDesign`.
"""
from __future__ import annotations

from typing import Any

from cam_workbench.generators.bodies.indexing.parallel_kind import ParallelIndexerDesign

from .solids import SOLIDS, count_solids, fused_prisms, is_valid, prism_stack, verify_exact


@SOLIDS.register(ParallelIndexerDesign)
class IndexerSolids:
    """The parallel indexer's solid (its body's prisms stacked) and the number of plates it stacks."""

    verify = staticmethod(verify_exact)

    @staticmethod
    def solid(design: Any, exact_offset: bool) -> Any:
        """The plates and spacers as one ``TopoDS_Solid``; ``exact_offset`` is ignored (the flanks are
        fitted B-splines already, no kernel offset is taken, so the STEP solid is this one)."""
        prisms = design.body.prisms
        solid = prism_stack(prisms)
        if is_valid(solid) and count_solids(solid) == 1:
            return solid
        return fused_prisms(prisms)

    @staticmethod
    def measures(design: Any, shape: Any) -> dict[str, Any]:
        """The number of plates the solid stacks (its volume and top face are checked by the solid stage)."""
        return {"plates": sum(1 for p in design.body.prisms if p.role.startswith("cam"))}

"""The solver settings of :func:`~cam_workbench.generators.optimise.run.optimise` that are not spec fields: the
nlopt algorithm names, the window limit of MMA/CCSAQ, nlopt's result codes and which of them mean
converged, and the feasibility tolerance while solving.
"""
from __future__ import annotations


LOCAL_GRADIENT = {"slsqp": "LD_SLSQP", "mma": "LD_MMA", "ccsaq": "LD_CCSAQ"}
#: Most windows per rise/return for MMA and CCSAQ.  nlopt's CCSA methods solve a dual problem
#: in the constraints at every step, and its cost climbs steeply with their number (thesis
#: Example 5, measured: 33 ms per evaluation with 8 windows, 60 ms with 16, 880 ms with 32, ≈1.5 s
#: with the default 80 — a 10-minute run).  The window maxima stay exact maxima with fewer,
#: wider windows, and the final dense check still decides.
CCSA_WINDOWS = 8
NLOPT_RESULTS = {1: "success", 2: "stopval reached", 3: "ftol reached", 4: "xtol reached",
                 5: "maxeval reached", 6: "maxtime reached", -1: "failure", -2: "invalid arguments",
                 -3: "out of memory", -4: "roundoff limited", -5: "forced stop"}
#: nlopt results that mean the solver met one of its stopping tolerances (the others — roundoff
#: limited, failure, the evaluation budget — do not make a run "converged").
NLOPT_CONVERGED = {1, 2, 3, 4}
#: A point whose normalised constraints exceed 0 by less than this counts as feasible while
#: solving (the solvers' own tolerance); the margin keeps the checks' values below their limits,
#: and :func:`polish` removes such round-off from the linear rows.
FEASIBLE_TOL = 1e-6

"""Pitch curves: the C² PH quintic spline (:mod:`.ph`), the periodic B-spline (:mod:`.bspline`),
what both answer alike — lift, deviation, contact angles (:mod:`.queries`) — and the
follower-path contact solve (:mod:`.contact`, below the followers: they hand it their contact
residuals).  Import the modules themselves (the package re-exports nothing, so that the
followers can use the contact solve while the pitch curves use the followers).
"""

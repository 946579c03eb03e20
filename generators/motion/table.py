"""Motion segments given as a table of (cam angle, lift) points, fitted by the B-spline lift law.

A ``law = "table"`` rise or return is the least-squares B-spline s(θ) of order k (default 5:
quartic, C³ inside) on uniform clamped knots, with θ(u) linear (control angles at the Greville
abscissae), so the fit is a :class:`~cam_workbench.generators.motion.bspline_law.BSplineLift` like the thesis'
lifts.  Its ends are held exactly: s at the segment's start and end levels, and the derivatives
the program gives the ends (the neighbours' to the segment's continuity, or the spec's values) as
equality constraints.  The number of knot spans is the fewest (by doubling, then bisection) whose
largest point error max |s_fit − s_i| is within the tolerance — at most one free control value per
two points, so the result is a fit, never an interpolation of noise.

The normal equations are banded (k non-zero basis functions per point); with the end constraints
they are solved as one sparse KKT system (scipy), with a vanishing second-difference term
(1e-12 of the diagonal) so that a knot span holding no point does not make them singular.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..curves.basis import basis_derivatives, basis_matrix
from .bspline_law import BSplineLift, clamped_uniform_knots

#: Most rows of a table (inline or CSV).
MAX_ROWS = 20000
#: Largest CSV file read.
MAX_CSV_BYTES = 5_000_000
#: Most knot spans of a fit.
MAX_SPANS = 4000
DEFAULT_TABLE_ORDER = 5
#: Default tolerance: this fraction of the segment's lift.
DEFAULT_TOLERANCE_FRACTION = 1e-3


class TableError(ValueError):
    """A table that cannot be read or fitted (message; the field to name, e.g. ``table[3]``)."""

    def __init__(self, where: str, message: str):
        super().__init__(message)
        self.where = where


def read_csv(path: Path) -> tuple[tuple[float, float], ...]:
    """(angle, lift) rows of a CSV file: two numbers per line separated by a comma, semicolon,
    tab or spaces; blank lines and lines starting with ``#`` are skipped, and so is a first line
    that does not start with a number (a header).  Extra columns are an error.

    Raises:
        TableError: naming ``file:line`` and what is wrong.
    """
    try:
        size = path.stat().st_size
    except FileNotFoundError:
        raise TableError("", f"{path}: file not found") from None
    except OSError as exc:
        raise TableError("", f"{path}: cannot be read ({exc.strerror})") from None
    if size > MAX_CSV_BYTES:
        raise TableError("", f"{path}: larger than {MAX_CSV_BYTES // 1_000_000} MB: not a motion table")
    try:
        text = path.read_bytes().decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise TableError("", f"{path}: not UTF-8 text (byte {exc.start})") from None
    except OSError as exc:
        raise TableError("", f"{path}: cannot be read ({exc.strerror})") from None
    rows: list[tuple[float, float]] = []
    first = True
    for no, line in enumerate(text.splitlines(), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        items = [t for t in re.split(r"[,;\s]+", line) if t]
        if first and not _is_number(items[0]):
            first = False
            continue               # a header line
        first = False
        if len(items) != 2:
            raise TableError("", f"{path.name}:{no}: expected 2 columns (cam angle, lift), got {len(items)}")
        try:
            a, s = float(items[0]), float(items[1])
        except ValueError:
            raise TableError("", f"{path.name}:{no}: not a number: {line[:40]!r}") from None
        if not (math.isfinite(a) and math.isfinite(s)):
            raise TableError("", f"{path.name}:{no}: not a finite number: {line[:40]!r}")
        rows.append((a, s))
        if len(rows) > MAX_ROWS:
            raise TableError("", f"{path.name}: more than {MAX_ROWS} rows")
    if not rows:
        raise TableError("", f"{path.name}: holds no (angle, lift) rows")
    return tuple(rows)


def _is_number(text: str) -> bool:
    try:
        float(text)
        return True
    except ValueError:
        return False


@dataclass(frozen=True)
class TableFit:
    """A fitted table segment.

    Attributes:
        lift: the B-spline lift (normalised y, θ from the segment start [rad]).
        spans: knot spans used.
        order: B-spline order k.
        points: number of table points fitted.
        max_error: max |s_fit − s_i| [lift units].
        at: cam angle of that point [rad from the segment start].
        rms_error: root mean square of the point errors.
        tolerance: the limit max_error met.
    """

    lift: BSplineLift
    spans: int
    order: int
    points: int
    max_error: float
    at: float
    rms_error: float
    tolerance: float


def fit_table(theta: np.ndarray, s: np.ndarray, span: float, low: float, height: float, order: int,
              constraints: list[tuple[float, int, float]], tolerance: float) -> TableFit:
    """Fit s(θ) to the points (θ [rad from the segment start], s) with the end ``constraints``
    [(x ∈ {0, 1}, derivative order, value per rad^order)], using the fewest uniform knot spans
    whose max point error is ≤ ``tolerance``.

    Raises:
        TableError: no span count meets the tolerance (naming "table_tolerance" with the best
            error reached and its angle), or the points cannot carry the constraints.
    """
    theta = np.asarray(theta, dtype=float)
    s = np.asarray(s, dtype=float)
    ncons = len(constraints)
    # at least one free control value beyond the constraints, at most one per two points: a fit,
    # never an interpolation (noise above the tolerance is an error, not a wiggle through the points)
    lo_spans = max(1, ncons + 2 - order)
    hi_spans = min(MAX_SPANS, max(lo_spans, theta.shape[0] // 2 + ncons - order + 1))
    cache: dict[int, tuple[np.ndarray, float, int]] = {}

    def attempt(n: int) -> tuple[np.ndarray, float, int]:
        if n not in cache:
            cache[n] = _solve(theta, s, span, order, n, constraints)
        return cache[n]

    n = lo_spans
    best = None
    while True:
        coef, err, at = attempt(n)
        if best is None or err < best[1]:
            best = (n, err, at)
        if err <= tolerance or n >= hi_spans:
            break
        n = min(2 * n, hi_spans)
    if err > tolerance:
        bn, berr, bat = best
        raise TableError("table_tolerance",
                         f"the table's B-spline fit misses its points by up to {berr:.4g} (at the point at "
                         f"{math.degrees(theta[bat]):.4g}° from the segment start, with {bn} knot spans of order "
                         f"{order}), more than the tolerance {tolerance:.4g}: a larger table_tolerance, a smoother "
                         "table, or lower start/end continuity")
    # bisection for the fewest spans within the tolerance (the error falls roughly with n)
    lo, hi = n // 2, n
    while hi - lo > 1 and lo >= lo_spans:
        mid = (lo + hi) // 2
        if attempt(mid)[1] <= tolerance:
            hi = mid
        else:
            lo = mid
    coef, err, at = attempt(hi)
    resid = _design(theta, order, hi, span) @ coef - s
    knots = clamped_uniform_knots(hi + order - 1, order)
    grev = np.array([knots[i + 1:i + order].mean() for i in range(hi + order - 1)])
    lift = BSplineLift(order, grev * span / hi, (coef - low) / height)
    return TableFit(lift, hi, order, int(theta.shape[0]), err, float(theta[at]),
                    float(np.sqrt(np.mean(resid**2))), tolerance)


def _design(theta: np.ndarray, order: int, spans: int, span: float):
    """The sparse (points × control values) collocation matrix."""
    import scipy.sparse as sparse  # deferred: scipy.sparse, a tabulated law's fit alone

    n_ctrl = spans + order - 1
    knots = clamped_uniform_knots(n_ctrl, order)
    u = np.clip(theta / span * spans, 0.0, float(spans))
    idx, ders = basis_derivatives(knots, order - 1, u, 0)
    rows = np.repeat(np.arange(u.shape[0]), order)
    cols = (idx[:, None] - (order - 1) + np.arange(order)[None, :]).ravel()
    return sparse.csr_matrix((ders[:, 0, :].ravel(), (rows, cols)), shape=(u.shape[0], n_ctrl))


def _solve(theta: np.ndarray, s: np.ndarray, span: float, order: int, spans: int,
           constraints: list[tuple[float, int, float]]) -> tuple[np.ndarray, float, int]:
    """(control values, max |error|, index of that point) of the constrained least-squares fit."""
    import scipy.sparse as sparse  # deferred: scipy.sparse, a tabulated law's fit alone
    from scipy.sparse.linalg import spsolve  # deferred: scipy.sparse

    n_ctrl = spans + order - 1
    knots = clamped_uniform_knots(n_ctrl, order)
    a = _design(theta, order, spans, span)
    ata = (a.T @ a).tocsr()
    diag = ata.diagonal()
    reg = 1e-12 * max(float(diag.mean()), 1e-300)
    if n_ctrl >= 3:
        d2 = sparse.diags([np.ones(n_ctrl - 2), -2 * np.ones(n_ctrl - 2), np.ones(n_ctrl - 2)], [0, 1, 2],
                          shape=(n_ctrl - 2, n_ctrl))
        ata = ata + reg * (d2.T @ d2)
    rhs = a.T @ s
    crow = np.zeros((len(constraints), n_ctrl))
    cval = np.zeros(len(constraints))
    for i, (x, k, v) in enumerate(constraints):
        crow[i] = basis_matrix(knots, order - 1, n_ctrl, np.array([x * spans]), k)[0] * (spans / span) ** k
        cval[i] = v
    # equilibrate the constraint rows (derivative rows grow like (spans/span)^k)
    sc = np.max(np.abs(crow), axis=1)
    sc[sc == 0] = 1.0
    crow /= sc[:, None]
    cval /= sc
    kkt = sparse.bmat([[ata, sparse.csr_matrix(crow.T)], [sparse.csr_matrix(crow), None]], format="csc")
    sol = spsolve(kkt, np.concatenate([rhs, cval]))
    coef = np.asarray(sol[:n_ctrl])
    if not np.all(np.isfinite(coef)):
        return coef, math.inf, 0
    err = np.abs(a @ coef - s)
    j = int(np.argmax(err))
    return coef, float(err[j]), j

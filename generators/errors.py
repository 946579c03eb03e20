"""Error types shared by every layer.

All user-facing errors derive from :class:`CamError`; the CLI turns them into a
one-line message and exit status 2 (bad input or impossible geometry).
"""
from __future__ import annotations


def fmt_apart(value: float, other: float, digits: int = 6) -> str:
    """``value`` with ``digits`` significant digits, or as many more as it takes to print it
    differently from ``other`` at the same precision — for rule messages that compare a value
    with a limit, so that a violated rule never reads as an identity ("spans sum to
    359.99999999°, must be 360°", not "… to 360°, must be 360°").

    The rule is symmetric: ``fmt_apart(limit, value)`` prints the limit at the same precision.
    Equal numbers print with ``digits``; rounding is monotonic, so the printed value stays on
    its side of the printed limit."""
    value, other = float(value), float(other)
    for d in range(digits, 18):
        text = f"{value:.{d}g}"
        if text != f"{other:.{d}g}":
            return text
    return f"{value:.{digits}g}"


class CamError(Exception):
    """Base class of every error the product reports to a user."""


class SpecError(CamError, ValueError):
    """A spec field breaks a rule.

    Attributes:
        field: dotted path of the offending field, e.g. ``motion[3].angle``.
        rule: the rule, in words, e.g. ``spans sum to 350°, must be 360°``.
    """

    def __init__(self, field: str, rule: str):
        self.field = field
        self.rule = rule
        super().__init__(f"{field}: {rule}")


class GeometryError(CamError):
    """A cam that cannot be made (undercut, self-intersection, bore through the profile).

    Attributes:
        kind: short machine-readable name ("undercut", "self_intersection", "bore", ...).
        angle_deg: cam angle in degrees where the problem happens (None if global).
        checks: the body's checks that fail (e.g. ``("rim_wall", "bore_wall")`` of a groove; the
            message is the first one's), for a remedy to search against; () when not a body check.
    """

    def __init__(self, kind: str, message: str, angle_deg: float | None = None, checks: tuple[str, ...] = ()):
        self.kind = kind
        self.angle_deg = angle_deg
        self.checks = tuple(checks)
        super().__init__(message)


class SolveError(CamError, RuntimeError):
    """A numerical solve (PH spline Newton, follower-line root) did not converge."""


class NotAvailable(CamError):
    """A member of the Python API that the cam's body does not have (a cylindrical cam's plane
    pitch curve): the message names the member, the body and what to use instead.

    Not an AttributeError: the member exists on every cam; this body refuses it."""


class MissingDependency(CamError, ImportError):
    """A feature needs a package that is not installed, or that is installed but fails to
    import; the message names the feature and the ``pip install`` (extra) that brings it.

    The CLI reports it as bad input (exit 2, one line); in Python it is also an ImportError."""

"""What the outputs may say about a designed cam, read from its summary dict (the numbers
of report.json): one wording for the HTML report, the DXF title block, the G-code header,
the CLI and FreeCAD's Check design dialog, so they cannot disagree with report.json or
with each other.

"Exact" is said only where it is true:

========================  =================================================================
``pitch.representation``  the profile NURBS is
========================  =================================================================
"ph", roller              the exact rational offset of the PH pitch curve (degree 9)
"ph", knife edge          the PH pitch curve itself (exact; polynomial, degree 5)
"bspline", roller         a B-spline fitted to the offset of the fitted pitch B-spline:
                          its measured error is ``profile.fitted_vs_kernel_offset``
"bspline", knife edge     the fitted pitch B-spline itself (not exact: its distance from the
                          design-intent pitch curve is ``profile.max_error``)
flat face (either)        the PH spline (or fitted B-spline) through the face's exact contact
                          points: not the envelope itself; ``profile.max_error`` from it
========================  =================================================================

In every case ``profile.max_error`` is the built profile's distance from the design-intent
profile (the roller offset of the pitch curve the motion program defines), i.e. it includes
the pitch curve's interpolation error.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

from ..kinds import pitch_named


@dataclass(frozen=True)
class ProfileClaim:
    """What the profile NURBS is.

    Attributes:
        exact: True when it is exactly the curve it stands for (the offset of the pitch
            curve, or the pitch curve for a knife edge).
        kind: "ph_offset", "ph_pitch", "bspline_offset_fit" or "bspline_pitch".
        text: one line, e.g. "exact rational offset of the PH pitch curve (NURBS degree 9)".
        fit_error: for a fitted curve, its measured largest distance from the exact curve
            it approximates [length]; None when exact.
        design_error: ``profile.max_error``: distance from the design-intent profile [length].
    """

    exact: bool
    kind: str
    text: str
    fit_error: float | None
    design_error: float | None


def _nurbs_words(profile: Mapping[str, Any]) -> str:
    rational = "rational" if profile.get("rational") else "polynomial"
    return f"NURBS degree {profile.get('degree')}, {rational}"


def profile_claim(summary: Mapping[str, Any], is_roller: bool, units: str | None = None) -> ProfileClaim:
    """The claim about ``summary["profile"]`` (``design.summary()`` / report.json).

    Args:
        summary: the summary dict (needs ``pitch.representation`` and ``profile``).
        is_roller: the follower has a roller (else knife edge: profile = pitch curve).
        units: length unit for the text (default ``summary["units"]``).
    """
    u = units or summary.get("units", "")
    prof = summary["profile"]
    exact = pitch_named(summary.get("pitch", {}).get("representation", "ph")).exact
    design_error = prof.get("max_error")
    words = _nurbs_words(prof)
    if summary.get("follower", {}).get("design_curve") == "profile":
        # a flat face: the profile is the curve through the face's exact contact points, not the
        # envelope itself — its distance from the envelope is measured
        curve = "PH quintic spline" if exact else "periodic B-spline fitted"
        text = (f"{curve} through the exact contact points of the face ({words}), max error "
                f"{_g(design_error)} {u} from the true envelope")
        return ProfileClaim(False, "ph_contact" if exact else "bspline_contact", text, design_error,
                            design_error)
    if exact:
        if is_roller:
            text = f"exact offset of the PH pitch curve ({words})"
            if prof.get("rational"):
                text = "exact rational offset of the PH pitch curve " + f"({words})"
            return ProfileClaim(True, "ph_offset", text, None, design_error)
        return ProfileClaim(True, "ph_pitch", f"PH pitch curve itself, exact ({words})", None, design_error)
    if is_roller:
        err = prof.get("fitted_vs_kernel_offset")
        text = (f"fitted offset B-spline ({words}), max error {_g(err)} {u} from the exact offset of the "
                "fitted pitch B-spline")
        return ProfileClaim(False, "bspline_offset_fit", text, err, design_error)
    text = (f"fitted pitch B-spline itself ({words}), max error {_g(design_error)} {u} from the "
            "design pitch curve")
    return ProfileClaim(False, "bspline_pitch", text, design_error, design_error)


def pitch_text(summary: Mapping[str, Any]) -> str:
    """The pitch curve in words: "C² PH quintic spline, M = 60 segments" or "periodic B-spline
    (degree 5) fitted to the design pitch curve, 60 knot spans"."""
    p = summary["pitch"]
    flat = summary.get("follower", {}).get("design_curve") == "profile"
    if pitch_named(p.get("representation", "ph")).exact:
        return f"C² PH quintic spline, M = {p['segments']} segments" + (
            " through the face's contact points" if flat else "")
    return (f"periodic B-spline (degree {p.get('degree')}) fitted to the design "
            f"{'contact curve' if flat else 'pitch curve'}, {p['segments']} knot spans")


def checks_verdict(checks: Mapping[str, Any]) -> str:
    """The verdict of report.json's ``checks`` section, from its ``passed`` and ``failed``
    (names verbatim): "design checks: all pass (4 checked, 2 skipped)" or "design checks
    FAILED: pressure_angle"."""
    results = checks.get("results", {})
    statuses = [r.get("status") for r in results.values()] if isinstance(results, Mapping) else []
    if checks.get("passed"):
        done = sum(1 for s in statuses if s == "pass")
        skipped = sum(1 for s in statuses if s == "skipped")
        return f"design checks: all pass ({done} checked" + (f", {skipped} skipped)" if skipped else ")")
    failed = list(checks.get("failed") or [])
    return "design checks FAILED: " + ", ".join(failed)


def _g(v: Any) -> str:
    return "—" if v is None else f"{float(v):.3g}"

"""A design check's status, one rule for every body: "pass", "fail", or "skipped" when the check
cannot be decided (no load to check, a positive drive, no limit given).  A check without a limit
is reported with its value and is not passed: its status is "skipped" and its note names the
field that would give the limit."""
from __future__ import annotations

#: the note of a check whose limit is not given (``field``: the spec field that gives it)
NO_LIMIT = "no limit: {field} not given, so not checked"


def limited_status(within: bool | None) -> str:
    """The status from whether the value is within its limit: "pass", "fail", or "skipped" when
    there is no limit (``within`` None)."""
    return "skipped" if within is None else "pass" if within else "fail"


def sampling_words(checks: dict) -> str:
    """How report.json's ``checks`` section sampled, in words (the CLI table, the HTML report and
    the FreeCAD dialog print this): the thesis' nodes, samples per rise/return, or an indexer's
    input angles over the turn."""
    if checks.get("sampling") == "thesis71":
        return "the thesis' 71 nodes per rise/return"
    if checks.get("sampling") == "per_turn":
        return f"{checks.get('samples_per_turn')} input angles over the turn"
    return f"{checks.get('samples_per_segment')} samples per rise/return, refined extrema"

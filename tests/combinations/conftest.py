"""Hypothesis profiles of the combination and fuzz suites.

* ``ci`` (default, `make test`): derandomised — the same cases every run — and a few minutes in all.
* ``fuzz`` (`make fuzz`, or ``CAM_FUZZ=1``): thousands of cases, random.
"""
import os

from hypothesis import HealthCheck, settings

_COMMON = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                                     HealthCheck.filter_too_much], print_blob=True)
settings.register_profile("ci", derandomize=True, **_COMMON)
settings.register_profile("fuzz", derandomize=False, **_COMMON)
PROFILE = "fuzz" if os.environ.get("CAM_FUZZ") else os.environ.get("CAM_HYPOTHESIS_PROFILE", "ci")
settings.load_profile(PROFILE)


def examples(ci: int, fuzz: int) -> int:
    """Case count of a test in the active profile (``CAM_FUZZ_SCALE`` scales the fuzz counts, e.g.
    0.5 for half a long run)."""
    return max(1, round(fuzz * float(os.environ.get("CAM_FUZZ_SCALE", "1")))) if PROFILE == "fuzz" else ci

"""Hypothesis profiles for the whole suite.

``ci`` (the default) is derandomized: every run draws the same examples, so a test fails
or passes for a reason, not by luck; every failure a search has found is kept as an
``@example`` on its test. ``random`` (``make test-random``, or
``HYPOTHESIS_PROFILE=random``) draws new examples each run, ten times as many, to look
for new failures.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

#: Examples per property test in CI (tests do not set their own count, so the profiles
#: scale them all).
CI_EXAMPLES = 200

settings.register_profile(
    "ci",
    max_examples=CI_EXAMPLES,
    derandomize=True,
    deadline=None,
    print_blob=True,
)
settings.register_profile(
    "random",
    max_examples=10 * CI_EXAMPLES,
    derandomize=False,
    deadline=None,
    print_blob=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

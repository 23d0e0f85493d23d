"""Hypothesis profiles for the whole suite, and helpers shared by its folders.

``ci`` (the default) is derandomized: every run draws the same examples, so a test fails
or passes for a reason, not by luck; every failure a search has found is kept as an
``@example`` on its test. ``random`` (``make test-random``, or
``HYPOTHESIS_PROFILE=random``) draws new examples each run, ten times as many, to look
for new failures.
"""

from __future__ import annotations

import asyncio
import os
from concurrent.futures import ThreadPoolExecutor

import pytest
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


@pytest.fixture
def run_async():
    """Run ``coroutine_function()`` to completion in a fresh event loop on its own thread
    (the browser tests leave an event loop running on the main thread when they run
    first, and ``asyncio.run`` refuses to start inside one)."""

    def run(coroutine_function):
        with ThreadPoolExecutor(max_workers=1) as pool:
            return pool.submit(lambda: asyncio.run(coroutine_function())).result()

    return run

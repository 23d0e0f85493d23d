"""Shared helpers of the deployment tests."""

from __future__ import annotations

import asyncio
from concurrent.futures import ThreadPoolExecutor

import pytest


@pytest.fixture
def run_async():
    """Run ``coroutine_function()`` to completion in a fresh event loop on its own thread
    (the browser tests leave an event loop running on the main thread when they run
    first, and ``asyncio.run`` refuses to start inside one)."""

    def run(coroutine_function):
        with ThreadPoolExecutor(max_workers=1) as pool:
            return pool.submit(lambda: asyncio.run(coroutine_function())).result()

    return run

"""benchmarks/load.py measures how long a class's closed sessions live on: the time from
the close until the server's count of live sessions is back to where it was.

Before, the harness waited for the count without timing it, with a session lifetime (3 s)
shorter than the classroom's (scripts/serve.sh's 7 s, checked every 3 s).
"""

from __future__ import annotations

import asyncio
import importlib.util
import re
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _harness():
    spec = importlib.util.spec_from_file_location("load_harness", ROOT / "benchmarks" / "load.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


class Counts:
    """A server whose ``live`` sessions drop to ``after`` once ``drop_s`` have passed."""

    def __init__(self, live: int, after: int, drop_s: float | None) -> None:
        self.live, self.after, self.drop_s = live, after, drop_s
        self.t0 = time.perf_counter()

    async def __call__(self) -> int:
        passed = time.perf_counter() - self.t0
        return self.after if self.drop_s is not None and passed >= self.drop_s else self.live


def test_the_time_until_closed_sessions_are_gone_is_measured():
    load = _harness()
    poll = 0.05
    counts = Counts(live=13, after=1, drop_s=0.4)
    gone, live = asyncio.run(load.wait_gone(counts, live0=1, limit_s=5.0, poll_s=poll))
    assert live == 1
    # Seen at the first poll after the drop: late by at most one poll interval (and the
    # loop's own lateness, a fraction of it on a busy machine: 0.1 s allowed).
    assert 0.4 <= gone <= 0.4 + poll + 0.1


def test_sessions_never_gone_are_reported_as_such():
    load = _harness()
    gone, live = asyncio.run(load.wait_gone(Counts(live=5, after=0, drop_s=None), live0=0,
                                            limit_s=0.3, poll_s=0.05))
    assert gone is None and live == 5


def test_the_harness_serves_with_the_classroom_s_session_lifetime():
    """By default the started server discards closed sessions as scripts/serve.sh does."""
    load = _harness()
    args = load.parse_args([])
    serve = (ROOT / "scripts" / "serve.sh").read_text()
    lifetime = int(re.search(r"SESSION_LIFETIME_MS=\$\{SESSION_LIFETIME_MS:-(\d+)\}", serve)[1])
    check = int(re.search(r"CHECK_UNUSED_MS=\$\{CHECK_UNUSED_MS:-(\d+)\}", serve)[1])
    assert (args.session_lifetime_ms, args.check_unused_ms) == (lifetime, check)
    assert args.gone_limit_s == 10.0  # the goal: a closed tab's session gone within 10 s


def test_a_move_without_new_data_ends_after_its_quiet_time_not_at_the_deadline():
    # Before, such a move waited for another patch until --move-timeout (30 s): a session
    # stalled there, and a round of 5 sessions x 40 moves timed out at 137 of 200 moves.
    wait = _harness().settle_wait
    quiet, deadline = 0.3, 40.0
    # Text patches at 10 s, none with data: over 2 s after the last, whatever the deadline.
    assert wait([(10.0, False)], 10.5, deadline, quiet) == pytest.approx(1.5)
    assert wait([(10.0, False)], 12.0, deadline, quiet) is None
    # The data patch at 10 s: over after the quiet time; a later patch restarts it.
    assert wait([(9.0, False), (10.0, True)], 10.1, deadline, quiet) == pytest.approx(0.2)
    assert wait([(10.0, True)], 10.3, deadline, quiet) is None
    assert wait([(10.0, True), (10.2, False)], 10.3, deadline, quiet) == pytest.approx(0.2)
    # Nothing yet: wait up to the deadline, and never past it.
    assert wait([], 10.0, deadline, quiet) == pytest.approx(30.0)
    assert wait([(39.9, False)], 39.95, deadline, quiet) == pytest.approx(0.05)
    assert wait([(10.0, True)], 40.0, deadline, quiet) is None

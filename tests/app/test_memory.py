"""The server's garbage-collector policy (app.memory): frozen objects are skipped by full
collections, and ended sessions' reference cycles are freed, in batches."""

from __future__ import annotations

import asyncio
import gc
import weakref
from types import SimpleNamespace

import pytest

from app import memory


class _Node:
    """An object in a reference cycle (freed only by the cycle collector)."""

    def __init__(self) -> None:
        self.me = self


def _context(live: int) -> SimpleNamespace:
    """A session context as Bokeh passes it to a session-end hook: ``live`` sessions
    still open in the process."""
    return SimpleNamespace(server_context=SimpleNamespace(sessions=[object()] * live))


@pytest.fixture(autouse=True)
def _unfrozen():
    gc.unfreeze()
    memory.cancel_collection()
    yield
    memory.cancel_collection()  # a test's loop may have ended before the collection
    gc.unfreeze()


def test_freeze_leaves_nothing_for_a_full_collection_to_scan():
    memory.freeze_live_objects()
    assert gc.get_freeze_count() > 0
    # A handful of objects made by the test itself may be tracked; the ~100,000 of the
    # imports are not.
    assert len(gc.get_objects()) < 1000


def test_a_cycle_dropped_while_frozen_is_freed_by_the_collection_of_ended_sessions():
    node = _Node()
    ref = weakref.ref(node)
    memory.freeze_live_objects()
    del node
    gc.collect()
    assert ref() is not None  # frozen: the collector does not look at it
    memory.collect_ended_sessions()
    assert ref() is None
    assert gc.get_freeze_count() > 0  # and what lives is frozen again


def test_a_cycle_made_after_the_freeze_is_collected_as_usual():
    memory.freeze_live_objects()
    node = _Node()
    ref = weakref.ref(node)
    del node
    gc.collect()
    assert ref() is None


def test_a_page_loading_after_a_session_ended_does_not_keep_its_cycles(
        monkeypatch, run_async):
    # A class arriving as another leaves: the last session of a process ends and a page
    # loads before the collection. Before, the page's freeze kept the ended session's
    # cycles for good while sessions kept ending and starting.
    monkeypatch.setattr(memory, "COLLECT_DELAY_S", 0.05)

    async def run() -> tuple[bool, bool]:
        node = _Node()
        ref = weakref.ref(node)
        memory.freeze_live_objects()  # the session's page loaded
        del node  # the session ended and let its objects go
        memory.session_ended(_context(live=0))
        memory.freeze_live_objects()  # another page loads
        kept_meanwhile = ref() is not None
        await asyncio.sleep(0.3)
        return kept_meanwhile, ref() is None

    kept_meanwhile, freed = run_async(run)
    assert kept_meanwhile
    assert freed


def test_ended_sessions_are_collected_in_batches_while_others_stay(monkeypatch, run_async):
    # Each collection scans every live session's objects: one per student who leaves
    # would stall the whole class each time.
    monkeypatch.setattr(memory, "COLLECT_DELAY_S", 0.05)
    live = 4 * memory.COLLECT_AFTER_ENDS + 8  # a quarter of them is more than the minimum
    batch = live // 4

    async def run() -> list[bool]:
        node = _Node()
        ref = weakref.ref(node)
        memory.freeze_live_objects()
        del node
        freed = []
        for _ in range(batch):
            await asyncio.sleep(0.1)
            freed.append(ref() is None)
            memory.session_ended(_context(live))  # others arrive as these leave
        await asyncio.sleep(0.3)
        freed.append(ref() is None)
        return freed

    freed = run_async(run)
    assert not any(freed[:-1])  # kept through the first batch - 1 ends
    assert freed[-1]  # freed after the batch's last


def test_a_burst_of_session_ends_schedules_one_collection(monkeypatch, run_async):
    monkeypatch.setattr(memory, "COLLECT_DELAY_S", 0.05)
    full = []

    def count(phase, info):
        if phase == "stop" and info["generation"] == 2:
            full.append(1)

    async def run() -> tuple[bool, int]:
        for live in (2, 1, 0):  # a class leaving
            memory.session_ended(_context(live))
        pending = memory.collection_scheduled()
        n = len(full)
        await asyncio.sleep(0.3)
        return pending, len(full) - n

    gc.callbacks.append(count)
    try:
        pending, collections = run_async(run)
    finally:
        gc.callbacks.remove(count)
    assert pending
    assert collections == 1
    assert not memory.collection_scheduled()
    assert memory.ended_since_collection() == 0
    assert gc.get_freeze_count() > 0


def test_bokeh_accepts_the_session_end_callback():
    # Bokeh checks the exact signature, func(session_context), when the page registers it.
    from bokeh.document import Document

    Document().on_session_destroyed(memory.session_ended)


def test_the_live_sessions_come_from_bokeh_s_server_context():
    from bokeh.server.contexts import BokehServerContext

    assert isinstance(BokehServerContext.sessions, property)
    assert memory.live_sessions(_context(3)) == 3
    assert memory.live_sessions(None) is None


def test_freed_memory_goes_back_to_the_system():
    """Freed heap memory in the middle of the heap stays in the process until trimmed:
    the server stayed at its peak after a class left."""
    from app.memory import give_back_freed_memory

    def rss_kib() -> int:
        with open("/proc/self/status") as f:
            return next(int(line.split()[1]) for line in f if line.startswith("VmRSS:"))

    # 64 MiB in 100 KiB blocks (below glibc's mmap threshold: from the heap), one in ten
    # kept so that the freed ones lie between live ones and the heap's top stays in use.
    blocks = [bytearray(100 * 1024) for _ in range(640)]
    kept = blocks[::10]
    before = rss_kib()
    del blocks
    freed = rss_kib()
    assert give_back_freed_memory()
    after = rss_kib()
    # Most of the 57.6 MiB freed was still counted before the trim; after it, at least
    # half of it is gone (pages that share a live block stay).
    assert before - freed < 16 * 1024 and freed - after > 28 * 1024, (before, freed, after)
    assert len(kept) == 64


_SMALL_OBJECTS = """
import json
from app import memory

def rss_kib():
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS:"))

# ~140 MiB of small objects (the size of a page's models and their dicts), one in a hundred
# kept: the survivors a class leaves behind, spread over everything it allocated.
objects = [{"x": i, "y": (i, i)} for i in range(600_000)]
kept = objects[::100]
del objects
freed = rss_kib()
given = memory.give_back_freed_memory()
print(json.dumps({"heap": memory.HEAP, "given": given, "freed": freed, "after": rss_kib(),
                  "kept": len(kept)}))
"""


def _small_objects_freed(**env: str) -> dict:
    """Run :data:`_SMALL_OBJECTS` in a fresh interpreter with ``env``."""
    import json
    import os
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    out = subprocess.run([sys.executable, "-c", _SMALL_OBJECTS], capture_output=True,
                         text=True, timeout=120, cwd=root, check=True,
                         env={**os.environ, "PYTHONPATH": str(root), **env})
    return json.loads(out.stdout)


def test_a_class_s_small_objects_go_back_to_the_system_with_jemalloc_only():
    """The server's allocator (scripts/serve.sh, ALLOCATOR=jemalloc): small objects freed
    around a few survivors come back to the system when the ended sessions are collected;
    with Python's own allocator each survivor keeps its 1 MiB arena."""
    import glob

    libs = glob.glob("/usr/lib/*/libjemalloc.so.2") + glob.glob("/usr/lib/libjemalloc.so.2")
    assert libs, "jemalloc is not installed: make jemalloc (apt-get install -y libjemalloc2)"
    je = _small_objects_freed(PYTHONMALLOC="malloc", LD_PRELOAD=libs[0])
    py = _small_objects_freed(PYTHONMALLOC="pymalloc")
    assert (je["heap"], py["heap"]) == ("jemalloc", "glibc")
    assert je["given"] and py["given"]
    # About 140 MiB of objects were freed, still counted in the RSS before the call (276 and
    # 243 MiB then, measured): jemalloc gave 127 MiB back (pages with a survivor stay),
    # pymalloc 0.1 MiB (every 1 MiB arena keeps a survivor). The bounds sit midway.
    assert je["freed"] - je["after"] > 64 * 1024, je
    assert py["freed"] - py["after"] < 16 * 1024, py
    assert je["kept"] == py["kept"] == 6000

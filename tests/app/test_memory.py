"""The server's garbage-collector policy (app.memory): frozen objects are skipped by full
collections, and a session's end makes its reference cycles collectable again."""

from __future__ import annotations

import asyncio
import gc
import weakref

import pytest

from app import memory


class _Node:
    """An object in a reference cycle (freed only by the cycle collector)."""

    def __init__(self) -> None:
        self.me = self


@pytest.fixture(autouse=True)
def _unfrozen():
    memory.unfreeze_objects(None)
    yield
    if memory._refreeze["handle"] is not None:  # a test's loop ended before its refreeze
        memory._refreeze["handle"].cancel()
        memory._refreeze["handle"] = None
    memory.unfreeze_objects(None)


def _cycle() -> weakref.ref:
    node = _Node()
    return weakref.ref(node)


def test_freeze_leaves_nothing_for_a_full_collection_to_scan():
    memory.freeze_live_objects()
    assert gc.get_freeze_count() > 0
    # A handful of objects made by the test itself may be tracked; the ~100,000 of the
    # imports are not.
    assert len(gc.get_objects()) < 1000
    memory.unfreeze_objects(None)
    assert gc.get_freeze_count() == 0


def test_a_cycle_dropped_while_frozen_is_freed_after_the_unfreeze():
    node = _Node()
    ref = weakref.ref(node)
    memory.freeze_live_objects()
    del node
    gc.collect()
    assert ref() is not None  # frozen: the collector does not look at it
    memory.unfreeze_objects(None)
    gc.collect()
    assert ref() is None


def test_a_cycle_made_after_the_freeze_is_collected_as_usual():
    memory.freeze_live_objects()
    ref = _cycle()
    gc.collect()
    assert ref() is None


def test_a_burst_of_session_ends_schedules_one_refreeze(monkeypatch, run_async):
    monkeypatch.setattr(memory, "REFREEZE_DELAY_S", 0.05)

    async def run() -> tuple[int, int]:
        for _ in range(3):
            memory.unfreeze_objects(None)
        pending = sum(h is not None for h in memory._refreeze.values())
        await asyncio.sleep(0.2)
        return pending, gc.get_freeze_count()

    pending, frozen = run_async(run)
    assert pending == 1
    assert frozen > 0
    assert memory._refreeze["handle"] is None


def test_a_page_loading_before_an_ended_session_is_collected_does_not_keep_its_cycles(
        monkeypatch, run_async):
    # A class arriving as another leaves: a page loads between a session's end and the
    # collection that frees that session's cycles. Frozen then, they were never freed.
    monkeypatch.setattr(memory, "REFREEZE_DELAY_S", 0.05)

    async def run() -> tuple[bool, bool, int]:
        node = _Node()
        ref = weakref.ref(node)
        memory.freeze_live_objects()  # the session's page loaded
        memory.unfreeze_objects(None)  # the session ended ...
        del node  # ... and its objects were let go
        memory.freeze_live_objects()  # another page loads
        kept_meanwhile = ref() is not None
        await asyncio.sleep(0.2)  # the refreeze
        return kept_meanwhile, ref() is None, gc.get_freeze_count()

    kept_meanwhile, freed, frozen = run_async(run)
    assert kept_meanwhile  # nothing collected it yet: only the refreeze's collection may
    assert freed
    assert frozen > 0  # and the live objects are frozen again


def test_a_refreeze_after_a_full_collection_does_not_collect_again(monkeypatch, run_async):
    monkeypatch.setattr(memory, "REFREEZE_DELAY_S", 0.05)
    full = []

    def count(phase, info):
        if phase == "stop" and info["generation"] == 2:
            full.append(1)

    async def run() -> int:
        memory.unfreeze_objects(None)
        gc.collect()  # Panel's own collection after the session's end
        n = len(full)
        await asyncio.sleep(0.2)
        return len(full) - n

    gc.callbacks.append(count)
    try:
        extra = run_async(run)
    finally:
        gc.callbacks.remove(count)
    assert extra == 0
    assert gc.get_freeze_count() > 0


def test_bokeh_accepts_the_session_end_callback():
    # Bokeh checks the exact signature, func(session_context), when the page registers it.
    from bokeh.document import Document

    Document().on_session_destroyed(memory.unfreeze_objects)

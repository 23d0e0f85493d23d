"""Answers computed in worker threads reach a session through its event loop: a worker
thread never adds a callback to the document itself (app/session_loop.py)."""

from __future__ import annotations

import asyncio
import threading
from types import SimpleNamespace

from app.session_loop import from_any_thread


class _Doc:
    """What :func:`from_any_thread` uses of a session's document; records the thread that
    adds each callback."""

    def __init__(self) -> None:
        self.session_context = SimpleNamespace(destroyed=False)
        self.added: list[tuple[str, object]] = []

    def add_next_tick_callback(self, fn) -> None:
        self.added.append((threading.current_thread().name, fn))


def _trigger_from_a_worker(doc: _Doc, fn) -> str:
    """Make the trigger on a running loop, call it from a worker thread, let the loop run;
    returns the loop thread's name."""

    async def page() -> str:
        trigger = from_any_thread(doc, fn)
        worker = threading.Thread(target=trigger, name="worker")
        worker.start()
        worker.join()
        for _ in range(100):  # the loop runs what the worker asked for
            await asyncio.sleep(0)
        return threading.current_thread().name

    return asyncio.run(page())


def test_a_worker_thread_asks_the_loop_to_add_the_callback():
    doc, fn = _Doc(), lambda: None
    loop_thread = _trigger_from_a_worker(doc, fn)
    assert doc.added == [(loop_thread, fn)]


def test_nothing_is_added_to_a_destroyed_session():
    doc = _Doc()
    doc.session_context.destroyed = True
    _trigger_from_a_worker(doc, lambda: None)
    assert doc.added == []


def test_without_a_running_loop_the_caller_adds_it():
    doc, fn = _Doc(), lambda: None
    from_any_thread(doc, fn)()
    assert doc.added == [(threading.current_thread().name, fn)]


def test_a_closed_loop_is_not_an_error():
    doc = _Doc()

    async def make():
        return from_any_thread(doc, lambda: None)

    trigger = asyncio.run(make())  # asyncio.run closes its loop
    trigger()
    assert doc.added == []

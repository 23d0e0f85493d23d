"""A sweep computed chunk by chunk in the worker pool, each answer handed to the session's loop."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Mapping
from concurrent.futures import Future
from typing import Any

import numpy as np
import panel as pn
from panel.io.state import set_curdoc

from app.session_loop import from_any_thread
from app.solve import process as solve_process
from app.solve.pool import executor_for

#: closed form, plus a worker process where it integrates (measured ~1 s each
#: in the served page at load 8, so such chunks are longer).
CHUNK_SECONDS = {"closed": 0.25, "integrated": 2.0}
#: Points of a sweep's first chunk, closed form and integrated (a deformable stop or a
#: numerical method costs 10-1000 ms per point).
FIRST_CHUNK = {"closed": 1000, "integrated": 2}
#: Most points in one chunk.
MAX_CHUNK = 50_000


class ChunkedSweep:
    """One session's sweep, computed chunk by chunk in the worker pool.

    :meth:`start` cancels the running sweep and submits the first chunk; each chunk's
    answer comes back on the session's event loop (:func:`app.session_loop.from_any_thread`)
    and goes to ``on_chunk(done, total, part)``; the next chunk is submitted then, sized to
    take about ``target_s`` (:data:`CHUNK_SECONDS`). :meth:`cancel` (or a new
    :meth:`start`) drops the answer of the chunk that runs and submits no other. Without a
    server session (scripts, tests) the chunks run one after the other before
    :meth:`start` returns. A sweep with a budget stops at it with the values it has: no
    chunk is submitted past it, each is sized to end before it, and one in a solver process
    still running a chunk's aim past it is stopped; ``on_cut(done, total)`` says so.

    Parameters
    ----------
    work : callable(task, items, cancelled) -> part
        Computes one chunk (in a worker thread); ``cancelled`` is a
        :class:`threading.Event` set when the sweep is cancelled (a chunk run in a child
        process, :func:`run_core`, is stopped by it).
    on_chunk : callable(done, total, part)
    on_failed : callable(Exception)
    on_cut : callable(done, total), optional
    """

    def __init__(self, work: Callable[[Any, np.ndarray, threading.Event], Any],
                 on_chunk: Callable[[int, int, Any], None],
                 on_failed: Callable[[Exception], None],
                 on_cut: Callable[[int, int], None] | None = None) -> None:
        self.work, self.on_chunk, self.on_failed = work, on_chunk, on_failed
        self.on_cut = on_cut
        self._token = 0
        self._lock = threading.Lock()
        #: Chunks submitted since this object was made (tests count them).
        self.submitted = 0
        self.running = False
        self._cancelled = threading.Event()
        self._deadline: solve_process.Deadline | None = None

    def cancel(self) -> None:
        """Stop: the running chunk's answer is dropped (a chunk in a child process is
        stopped), no further chunk is submitted."""
        with self._lock:
            self._token += 1
            self._cancelled.set()
        self.running = False

    def start(self, task: Any, items: np.ndarray, first: int, pool_values: Mapping[str, Any],
              target_s: float = CHUNK_SECONDS["closed"], budget_s: float | None = None
              ) -> None:
        """Compute ``work(task, chunk)`` over ``items`` (along the first axis), in the pool
        that solves ``pool_values`` (:func:`app.solve.pool.executor_for`), within ``budget_s``
        seconds (``None``: no budget)."""
        self.cancel()
        with self._lock:
            token = self._token
            self._cancelled = threading.Event()
        self.running = True
        self._target_s = target_s
        self._deadline = None if budget_s is None else solve_process.Deadline(budget_s)
        doc = pn.state.curdoc
        if doc is not None and doc.session_context is None:
            doc = None
        self._next(token, doc, executor_for(pool_values), task, items, 0, first)

    def _next(self, token: int, doc, pool, task, items, done: int, size: int) -> None:
        total = len(items)
        chunk = items[done:done + size]
        self.submitted += 1
        started = time.perf_counter()
        stop: Any = self._cancelled
        if self._deadline is not None:  # a chunk in a solver process ends by the deadline
            stop = solve_process.Deadline(self._deadline.left() + self._target_s, stop)
        future: Future = pool.submit(self.work, task, chunk, stop)

        def answered() -> None:
            if token != self._token:
                return
            try:
                part = future.result()
            except solve_process.Abandoned as exc:
                if self._over():
                    self._cut(token, done, total)
                else:
                    self._fail(token, exc)
                return
            except Exception as exc:  # noqa: BLE001 - any failure is shown, the page lives
                self._fail(token, exc)
                return
            elapsed = max(time.perf_counter() - started, 1e-4)
            now = done + len(chunk)
            if now >= total:
                self.running = False
            self.on_chunk(now, total, part)
            if now < total and token == self._token:
                if self._over():
                    self._cut(token, now, total)
                    return
                aim = self._target_s if self._deadline is None else min(
                    self._target_s, self._deadline.left())
                nxt = int(min(max(len(chunk) / elapsed * aim, 1), MAX_CHUNK))
                self._next(token, doc, pool, task, items, now, nxt)

        if doc is None:
            future.exception()  # waits for the chunk
            answered()
            return

        def on_loop() -> None:
            with set_curdoc(doc):
                answered()

        answer = from_any_thread(doc, on_loop)
        future.add_done_callback(lambda _: answer())

    def _fail(self, token: int, exc: Exception) -> None:
        if token == self._token:
            self.running = False
            self.on_failed(exc)

    def _over(self) -> bool:
        """The budget has run out."""
        return self._deadline is not None and self._deadline.left() <= 0.0

    def _cut(self, token: int, done: int, total: int) -> None:
        if token == self._token:
            self.running = False
            if self.on_cut is not None:
                self.on_cut(done, total)

"""Back to a session from a worker thread: answers computed off the event loop reach the
page through :func:`from_any_thread`.

Bokeh calls ``Document.add_next_tick_callback`` its thread-safe door into a session, but
called from a worker thread it can lose the callback: the event that tells the session
about a new callback is appended to the document's list of held events while the event
loop hands that list out (``Document.unhold``, run on every ``pn.io.hold`` the page
takes), and the session never schedules it. The page then waits for an answer that was
computed (``benchmarks/next_tick_race.py`` counts the lost events). So a worker thread
only asks the event loop, through asyncio's thread-safe ``call_soon_threadsafe``, to add
the callback itself: on the loop, no hold is handed out at the same time.
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import Any


def from_any_thread(doc: Any, fn: Callable[[], None]) -> Callable[[], None]:
    """A trigger, safe to call from any thread, that runs ``fn`` as a next-tick callback of
    ``doc``'s session (with its document lock and ``fn``'s document current).

    Call this on the session's event loop (a page's callbacks run there). Without a running
    loop in the calling thread the trigger adds the callback from the thread that calls it,
    as Bokeh documents. Nothing runs once the session has been destroyed or its loop closed.
    """
    try:
        loop = asyncio.get_running_loop()
    except RuntimeError:
        loop = None

    def add() -> None:
        context = doc.session_context
        if context is not None and not context.destroyed:
            doc.add_next_tick_callback(fn)

    if loop is None:
        return add

    def trigger() -> None:
        try:
            loop.call_soon_threadsafe(add)
        except RuntimeError:  # the loop is closed: the server stops, no page waits
            pass

    return trigger

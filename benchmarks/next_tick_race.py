"""Next-tick callbacks a worker thread adds to a Bokeh document while its event loop holds
and releases it, and how many of them the session would never hear of.

A session learns of a new next-tick callback through the document's ``SessionCallbackAdded``
event. The event loop here does what a page does on every redraw: hold the document, change
many models, release it (``Document.unhold``). A worker thread adds callbacks meanwhile,
either to the document itself (``worker``) or by asking the loop to add them
(``loop``, :func:`app.session_loop.from_any_thread`'s way). Lost = added - events heard.

    PYTHONPATH=. python benchmarks/next_tick_race.py [seconds per way]
"""

from __future__ import annotations

import asyncio
import sys
import threading
import time

import bokeh
from bokeh.document import Document
from bokeh.document.events import SessionCallbackAdded
from bokeh.models import ColumnDataSource

#: Models changed under each hold (a redraw of the page changes a few hundred).
MODELS = 200


def _document() -> tuple[Document, list[ColumnDataSource], list[int]]:
    doc = Document()
    sources = [ColumnDataSource(data={"x": [0]}) for _ in range(MODELS)]
    for source in sources:
        doc.add_root(source)
    heard = [0]

    def count(event) -> None:
        if isinstance(event, SessionCallbackAdded):
            heard[0] += 1

    doc.callbacks.on_change(count)
    return doc, sources, heard


def _redraw(doc: Document, sources: list[ColumnDataSource], i: int) -> None:
    doc.hold("combine")
    for source in sources:
        source.data = {"x": [i]}
    doc.unhold()


def run(way: str, seconds: float) -> tuple[int, int]:
    """Added callbacks and the events heard, ``way`` 'worker' or 'loop'."""
    doc, sources, heard = _document()
    stop, added = threading.Event(), [0]

    def noop() -> None:
        pass

    async def loop_side() -> None:
        loop = asyncio.get_running_loop()

        def worker() -> None:
            while not stop.is_set():
                if way == "worker":
                    doc.add_next_tick_callback(noop)
                else:
                    loop.call_soon_threadsafe(doc.add_next_tick_callback, noop)
                added[0] += 1

        thread = threading.Thread(target=worker)
        thread.start()
        end, i = time.monotonic() + seconds, 0
        while time.monotonic() < end:
            _redraw(doc, sources, i)
            i += 1
            await asyncio.sleep(0)  # the loop runs what the worker asked for
        stop.set()
        thread.join()
        for _ in range(10_000):  # the last requests
            if len(doc.session_callbacks) >= added[0]:
                break
            await asyncio.sleep(0)

    asyncio.run(loop_side())
    return added[0], heard[0]


def main(seconds: float = 10.0) -> None:
    print(f"bokeh {bokeh.__version__}, python {sys.version.split()[0]}, "
          f"{seconds:g} s per way, {MODELS} models changed per hold")
    print("| way | callbacks added | events heard | lost |")
    print("|---|---|---|---|")
    for way in ("worker", "loop"):
        added, heard = run(way, seconds)
        print(f"| {way} | {added} | {heard} | {added - heard} |")


if __name__ == "__main__":
    main(*(float(a) for a in sys.argv[1:2]))

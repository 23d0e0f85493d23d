"""The session's websocket: messages leave at once, and updates wait for writes under way.

Two delays stood between a slider's release and the new picture, both in how messages are
written to the browser, not in computing them:

* **Nagle's algorithm.** A Bokeh message is several websocket frames (header, metadata,
  content, one pair per binary buffer). Neither Bokeh nor Panel sets ``TCP_NODELAY`` on the
  socket, so the kernel held each frame after the first until the browser acknowledged
  that one, and browsers delay acknowledgements: the update reached the browser 25-40 ms
  after it was written. :func:`send_without_delay` turns the algorithm off for the
  session's sockets once its page has loaded.
* **A write under way.** See :func:`writes_done`.
"""

from __future__ import annotations

from typing import Any

import panel as pn


def _sockets(doc: Any) -> list[Any]:
    """The websocket handlers (``bokeh.server.views.ws.WSHandler``) of a session."""
    context = getattr(doc, "session_context", None)
    session = getattr(context, "session", None)
    return [conn._socket for conn in list(getattr(session, "_subscribed_connections", ()))
            if getattr(conn, "_socket", None) is not None]


def send_without_delay(doc: Any) -> int:
    """Set ``TCP_NODELAY`` on the session's open websockets; returns how many."""
    done = 0
    for socket in _sockets(doc):
        if getattr(socket, "ws_connection", None) is not None:
            socket.set_nodelay(True)
            done += 1
    return done


def send_without_delay_once_loaded() -> None:
    """Call :func:`send_without_delay` when this session's page has loaded (call while the
    page is built)."""
    pn.state.onload(lambda: send_without_delay(pn.state.curdoc))


async def writes_done(doc: Any) -> None:
    """Wait until no Bokeh message is being written to the session's websockets.

    The server answers each message from the browser (here: a slider's new value) with an
    acknowledgement, written under the socket's write lock over a few turns of the event
    loop. An update made meanwhile cannot be written at once: Panel serialises it and
    retries every 10 ms (``panel.io.document._dispatch_msgs``), which delayed each
    release's new picture by about 10 ms. Waiting for the lock first lets the update be
    written as soon as it is made.
    """
    for socket in _sockets(doc):
        lock = getattr(socket, "write_lock", None)
        if lock is not None:
            async with lock:
                pass

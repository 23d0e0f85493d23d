"""The check of the shared server's log (``conftest.no_server_faults``) finds a handler's
exception and passes over a page closed while the server wrote to it."""

from __future__ import annotations

from uipage import server_faults

LOG = """\
2026-11-29 19:41:21,024 Exception in callback functools.partial(...)
Traceback (most recent call last):
  File "/x/panel/io/server.py", line 252, in wrapped
    return await func(*args, **kw)
RuntimeError: _pending_writes should be non-None when we have a document lock
2026-11-29 19:41:22,000 WebSocket connection closed: code=1001, reason=None
Traceback (most recent call last):
  File "/x/tornado/websocket.py", line 1140, in wrapper
    raise WebSocketClosedError()
tornado.websocket.WebSocketClosedError
"""


def test_a_handler_s_exception_is_a_fault_and_a_closed_page_is_not():
    assert server_faults(LOG) == [
        "RuntimeError: _pending_writes should be non-None when we have a document lock"]
    assert server_faults(LOG.split("2026-11-29 19:41:22")[1]) == []

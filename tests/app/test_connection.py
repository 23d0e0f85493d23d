"""The session's websocket settings (app.connection), on stand-ins for Bokeh's objects."""

from __future__ import annotations

import asyncio
from types import SimpleNamespace

from tornado.locks import Lock

from app import connection


class _Socket:
    def __init__(self, open_: bool = True) -> None:
        self.ws_connection = object() if open_ else None
        self.nodelay = None
        self.write_lock = Lock()

    def set_nodelay(self, value: bool) -> None:
        self.nodelay = value


def _doc(*sockets):
    conns = [SimpleNamespace(_socket=s) for s in sockets]
    session = SimpleNamespace(_subscribed_connections=conns)
    return SimpleNamespace(session_context=SimpleNamespace(session=session))


def test_nodelay_is_set_on_every_open_socket():
    open_, closed = _Socket(), _Socket(open_=False)
    assert connection.send_without_delay(_doc(open_, closed)) == 1
    assert open_.nodelay is True
    assert closed.nodelay is None


def test_a_document_without_a_session_has_no_sockets():
    assert connection.send_without_delay(SimpleNamespace(session_context=None)) == 0


def test_writes_done_waits_for_the_write_lock():
    socket = _Socket()

    async def run() -> list[str]:
        order: list[str] = []
        await socket.write_lock.acquire()

        async def writer() -> None:
            await asyncio.sleep(0.05)
            order.append("write finished")
            socket.write_lock.release()

        task = asyncio.ensure_future(writer())
        await connection.writes_done(_doc(socket))
        order.append("update")
        await task
        return order

    assert asyncio.run(run()) == ["write finished", "update"]

"""The session's websocket settings (app.connection), on stand-ins for Bokeh's objects."""

from __future__ import annotations

import asyncio
import importlib
import re
from types import SimpleNamespace

import numpy as np
from bokeh.document import Document
from bokeh.models import ColumnDataSource
from bokeh.protocol import Protocol
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


def test_writes_done_waits_for_the_write_lock(run_async):
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

    assert run_async(run) == ["write finished", "update"]


def _patch_events(doc, source, data):
    events = []
    doc.on_change(lambda event: events.append(event))
    source.data = data
    return events


def test_arrays_travel_inside_the_message(monkeypatch):
    """After send_arrays_inline an update is three frames whatever its arrays, and a copy
    of the document that applies it holds the same values (Bokeh decodes the base64)."""
    patch_doc = importlib.import_module("bokeh.protocol.messages.patch_doc").patch_doc
    # Bokeh's own create for the first message (whatever ran before), restored after.
    monkeypatch.setattr(patch_doc, "create",
                        connection._bokeh_create or patch_doc.__dict__["create"])
    monkeypatch.setattr(connection, "_bokeh_create", None)
    doc = Document()
    source = ColumnDataSource({"x": np.zeros(3, dtype=np.float32), "y": np.zeros(3)})
    doc.add_root(source)
    copy = Document.from_json(doc.to_json())
    new = {"x": np.linspace(0, 1, 500, dtype=np.float32), "y": np.arange(500.0)}
    events = _patch_events(doc, source, new)
    protocol = Protocol()
    assert len(protocol.create("PATCH-DOC", events).buffers) == 2  # Bokeh's default

    connection.send_arrays_inline()
    connection.send_arrays_inline()  # idempotent
    msg = protocol.create("PATCH-DOC", events)
    assert msg.buffers == []
    msg.apply_to_document(copy)
    got = copy.get_model_by_id(source.id).data
    np.testing.assert_array_equal(got["x"], new["x"])
    np.testing.assert_array_equal(got["y"], new["y"])
    assert np.asarray(got["x"]).dtype == np.float32



def test_lazy_references_encode_like_bokeh():
    """The serializer that looks references up lazily gives Bokeh's encoding: a model the
    browser has is a reference, a model new in this message is sent in full, and the new
    models the message carried are no longer new after it."""
    from bokeh.core.serialization import Serializer
    from bokeh.models import Range1d

    def encoded(make_serializer):
        doc = Document()
        source = ColumnDataSource({"x": np.zeros(3, dtype=np.float32)})
        rng = Range1d(0, 1)
        doc.add_root(source)
        doc.add_root(rng)
        doc.models.flush_synced()  # the browser has both
        events = []
        doc.on_change(lambda event: events.append(event))
        source.data = {"x": np.arange(4, dtype=np.float32)}
        new = ColumnDataSource({"y": [1.0]})
        rng.tags = [new, source]  # one model new to the browser, one it has
        serializer = make_serializer(doc)
        content = serializer.encode(events)
        doc.models.flush_synced(lambda model: not serializer.has_ref(model))
        text = repr(content).replace(source.id, "SOURCE").replace(new.id, "NEW")
        # The two documents' other ids differ: number them in order of appearance.
        ids = dict.fromkeys(re.findall(r"'(p\d+)'", text))
        for k, old in enumerate(ids):
            text = text.replace(f"'{old}'", f"'M{k}'")
        return text, len(doc.models._new_models)

    bokeh = encoded(lambda doc: Serializer(references=doc.models.synced_references,
                                           deferred=False))
    lazy = encoded(lambda doc: connection._SyncedRefSerializer(doc, deferred=False))
    assert lazy == bokeh
    text = bokeh[0]
    assert "{'id': 'SOURCE'}" in text  # the known model as a reference
    assert "'name': 'ColumnDataSource', 'id': 'NEW', 'attributes'" in text  # new: in full
    assert bokeh[1] == 0  # sent, so no longer new

"""The websocket patches (app.perf.websocket), on stand-ins for Bokeh's objects, and the
version window and switch that gate them (app.perf)."""

from __future__ import annotations

import asyncio
import importlib
from types import SimpleNamespace

import numpy as np
import pytest
from bokeh.document import Document
from bokeh.models import ColumnDataSource
from bokeh.protocol import Protocol
from tornado.locks import Lock

import app.perf as perf
from app.perf import websocket as connection


@pytest.fixture(autouse=True)
def patches_on(monkeypatch):
    """These tests are of the patches themselves: switched on whatever the environment."""
    monkeypatch.setenv(perf.SWITCH, "on")


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
                        connection.BOKEH_CREATE or patch_doc.__dict__["create"])
    monkeypatch.setattr(connection, "BOKEH_CREATE", None)
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


def test_a_patch_outside_its_version_window_is_not_applied(monkeypatch, caplog):
    """Bokeh 3.9's PATCH-DOC is left alone when the window names other versions, and the
    log says why."""
    patch_doc = importlib.import_module("bokeh.protocol.messages.patch_doc").patch_doc
    bokeh_create = connection.BOKEH_CREATE or patch_doc.__dict__["create"]
    monkeypatch.setattr(patch_doc, "create", bokeh_create)
    monkeypatch.setattr(connection, "BOKEH_CREATE", None)
    old = perf.Patch("inline-arrays", "bokeh", "3.4", "3.5", "for an older Bokeh")
    monkeypatch.setitem(perf.PATCHES, "inline-arrays", old)
    perf.say_once.cache_clear()
    with caplog.at_level("WARNING", logger="app.perf"):
        connection.send_arrays_inline()
    assert patch_doc.__dict__["create"] is bokeh_create
    assert "'inline-arrays' not applied: it was written for bokeh >=3.4,<3.5" in caplog.text
    assert not perf.report()["inline-arrays"] and perf.report()["tcp-nodelay"]


def test_the_switch_turns_every_python_patch_off(monkeypatch):
    monkeypatch.setenv(perf.SWITCH, "off")
    assert perf.report() == dict.fromkeys(perf.PATCHES, False)
    socket = _Socket()
    assert connection.send_without_delay(_doc(socket)) == 0 and socket.nodelay is None
    monkeypatch.setenv(perf.SWITCH, "on")
    assert all(perf.report().values())  # the installed versions are inside every window


def test_the_windows_hold_the_installed_versions_and_no_others():
    for patch in perf.PATCHES.values():
        assert patch.in_window(patch.low)
        assert not patch.in_window(patch.high)


def test_the_forked_create_is_bokehs_own_with_the_recorded_edits():
    """``patch_doc_inline`` is a copy of the installed Bokeh's ``patch_doc.create``: its
    body hashes to the one recorded, and the recorded edits turn it into the copy. A Bokeh
    release that changes ``create`` fails here (and the server leaves the patch out)."""
    import hashlib

    patch_doc = importlib.import_module("bokeh.protocol.messages.patch_doc").patch_doc
    original = (connection.BOKEH_CREATE or patch_doc.__dict__["create"]).__func__
    bokeh_body = connection.normalised_body(original)
    assert hashlib.sha256(bokeh_body.encode()).hexdigest() == connection.FORKED_FROM, (
        "Bokeh's patch_doc.create changed:\n" + bokeh_body)
    edited = bokeh_body
    for old, new in connection.FORK_EDITS:
        assert edited.count(old) == 1, old
        edited = edited.replace(old, new)
    assert edited == connection.normalised_body(connection.patch_doc_inline)
    assert connection.fork_matches()


def test_a_changed_bokeh_create_leaves_the_copy_out(monkeypatch, caplog):
    """Inside its window, the patch is still left out where Bokeh's body is not the one
    copied."""
    patch_doc = importlib.import_module("bokeh.protocol.messages.patch_doc").patch_doc
    bokeh_create = connection.BOKEH_CREATE or patch_doc.__dict__["create"]
    monkeypatch.setattr(patch_doc, "create", bokeh_create)
    monkeypatch.setattr(connection, "BOKEH_CREATE", None)
    monkeypatch.setattr(connection, "FORKED_FROM", "0" * 64)
    connection.fork_matches.cache_clear()
    try:
        with caplog.at_level("WARNING", logger="app.perf.websocket"):
            connection.send_arrays_inline()
        assert patch_doc.__dict__["create"] is bokeh_create
        assert "'inline-arrays' not applied" in caplog.text
    finally:
        connection.fork_matches.cache_clear()

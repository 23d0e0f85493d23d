"""Patches of Bokeh's server (3.9): messages leave at once, in few frames, and updates wait
for writes under way.

Three delays stood between a slider's release and the new picture, all in how messages are
written to the browser, not in computing them:

* **Nagle's algorithm.** A Bokeh message is several websocket frames (header, metadata,
  content, one pair per binary buffer). Neither Bokeh nor Panel sets ``TCP_NODELAY`` on the
  socket, so the kernel held each frame after the first until the browser acknowledged
  that one, and browsers delay acknowledgements: the update reached the browser 25-40 ms
  after it was written. :func:`send_without_delay` turns the algorithm off for the
  session's sockets once its page has loaded.
* **Many frames.** Bokeh sends each array of an update as two frames of its own; a slider
  release updates about 25 arrays, so the update was about 50 frames, each written by the
  server and received by the browser as a separate event (~8 ms from the first to the
  last). :func:`send_arrays_inline` puts the arrays into the message's content instead.
* **A write under way.** See :func:`writes_done`.

Each is a patch of Bokeh internals (the server's connection objects, the websocket's write
lock, the PATCH-DOC message's ``create``) and is applied only where :mod:`app.perf` says so
(names ``tcp-nodelay``, ``write-lock``, ``inline-arrays``).

Left out after measuring: a serializer that looked up the document's references lazily
(Bokeh's lists a reference for every model of the document on each message, ~1.5 ms for
~900 models; below the 5 ms a patch must buy).
"""

from __future__ import annotations

import ast
import hashlib
import importlib
import inspect
import logging
import textwrap
from functools import cache
from typing import Any

import panel as pn
from bokeh.core.serialization import Serializer
from bokeh.document.json import PatchJson

from app.perf import applies

log = logging.getLogger(__name__)


def _sockets(doc: Any) -> list[Any]:
    """The websocket handlers (``bokeh.server.views.ws.WSHandler``) of a session."""
    context = getattr(doc, "session_context", None)
    session = getattr(context, "session", None)
    return [conn._socket for conn in list(getattr(session, "_subscribed_connections", ()))
            if getattr(conn, "_socket", None) is not None]


def send_without_delay(doc: Any) -> int:
    """Set ``TCP_NODELAY`` on the session's open websockets; returns how many."""
    done = 0
    if not applies("tcp-nodelay"):
        return done
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
    if not applies("write-lock"):
        return
    for socket in _sockets(doc):
        lock = getattr(socket, "write_lock", None)
        if lock is not None:
            async with lock:
                pass


#: Bokeh's own ``patch_doc.create``, once :func:`send_arrays_inline` has replaced it.
BOKEH_CREATE: Any = None

#: SHA-256 of the body of Bokeh 3.9's ``patch_doc.create`` (:func:`normalised_body`) that
#: :func:`patch_doc_inline` copies; a Bokeh whose body differs gets no patch.
FORKED_FROM = "0fa626f6840e482801611efc13688261f949f82042f2c10fe1f5167118468864"
#: What the copy changes in that body (:func:`normalised_body` text): the arrays are
#: encoded inline, so the message has no buffers to add.
FORK_EDITS = (
    ("Serializer(references=doc.models.synced_references)",
     "Serializer(references=doc.models.synced_references, deferred=False)"),
    ("msg = cls(header, metadata, patch_json)\nmsg.add_buffers(*serializer.buffers)\n"
     "return msg", "return cls(header, metadata, patch_json)"),
)


def normalised_body(function: Any) -> str:
    """The statements of ``function``'s body as :func:`ast.unparse` writes them, without
    its docstring: layout, comments and the signature's annotations do not count."""
    tree = ast.parse(textwrap.dedent(inspect.getsource(function)))
    body = tree.body[0].body
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
        body = body[1:]
    return "\n".join(ast.unparse(statement) for statement in body)


def _bokeh_patch_doc() -> Any:
    # The package exports the class under the module's name: fetch the module itself.
    return importlib.import_module("bokeh.protocol.messages.patch_doc").patch_doc


@cache
def fork_matches() -> bool:
    """Whether the installed Bokeh's ``patch_doc.create`` is the one the copy was made from."""
    original = BOKEH_CREATE or _bokeh_patch_doc().__dict__["create"]
    try:
        body = normalised_body(original.__func__)
    except (OSError, TypeError):  # no source installed
        return False
    return hashlib.sha256(body.encode()).hexdigest() == FORKED_FROM


def patch_doc_inline(cls, events: list[Any], **metadata: Any) -> Any:
    """Bokeh's ``patch_doc.create`` (3.9), with the arrays encoded into the content.

    The message is three frames (header, metadata, content) whatever the number of arrays.
    Each array is then gzip-compressed and base64-encoded (Bokeh's own inline form, which
    BokehJS reads as well as binary frames): for the explorer's smooth float32 columns
    about half the bytes of the binary frames (~45 instead of ~80 kB per release of scene
    5b), for ~1 ms more of encoding in the server and of decoding in the browser.
    """
    header = cls.create_header()
    if not events:
        raise ValueError("PATCH-DOC message requires at least one event")
    docs = {event.document for event in events}
    if len(docs) != 1:
        raise ValueError("PATCH-DOC message configured with events for more than one document")
    [doc] = docs
    serializer = Serializer(references=doc.models.synced_references, deferred=False)
    patch_json = PatchJson(events=serializer.encode(events))
    doc.models.flush_synced(lambda model: not serializer.has_ref(model))
    return cls(header, metadata, patch_json)


def send_arrays_inline() -> None:
    """Make every document update of this server one message of three frames (see the
    module's docstring); idempotent. Nothing is changed where the patch does not apply."""
    global BOKEH_CREATE
    if not applies("inline-arrays"):
        return
    if not fork_matches():
        log.warning("perf patch 'inline-arrays' not applied: the installed Bokeh's "
                    "patch_doc.create is not the one it copies")
        return
    patch_doc = _bokeh_patch_doc()
    if getattr(patch_doc.create, "__func__", None) is not patch_doc_inline:
        BOKEH_CREATE = patch_doc.__dict__["create"]
        patch_doc.create = classmethod(patch_doc_inline)

"""Values of a type a property cannot hold, sent by the browser: one quiet line, the browser set
back.

Bokeh's server checks each change of a ``PATCH-DOC`` message against the property's type
before any widget sees it: a script's ``null`` for a slider's value is refused there, and
``bokeh.server.protocol_handler`` logged it as ERROR with the message and a full traceback,
while the browser kept showing ``null``. A filter on that logger (the public ``logging``
API: no library code is replaced) says such a refusal in one WARNING line, rate-limited with
the widgets' own refusals (:mod:`app.perf.browser_values`), and sends the browser the value
in use of each property the refused message named, in every page served by this process.

Examples
--------
>>> QuietRefusals().filter(logging.makeLogRecord({"msg": "another record"}))
True
"""

from __future__ import annotations

import logging
from typing import Any
from weakref import WeakSet

from bokeh.document import Document

from app.perf.browser_values import say_refused

#: The logger of Bokeh's server that reports a message it could not apply.
LOGGER = "bokeh.server.protocol_handler"

#: The documents of this process's pages (a refused change is looked up in them).
_documents: WeakSet[Document] = WeakSet()


class QuietRefusals(logging.Filter):
    """Replaces the record of a ``PATCH-DOC`` message that Bokeh refused (a ``ValueError``
    of a property's type) by one line of :func:`~app.perf.browser_values.say_refused`, and
    sets the browser back; any other record passes unchanged."""

    def filter(self, record: logging.LogRecord) -> bool:
        args = record.args if isinstance(record.args, tuple) else ()
        if not (len(args) == 2 and getattr(args[0], "msgtype", None) == "PATCH-DOC"
                and isinstance(args[1], ValueError)):
            return True
        message, error = args
        say_refused(f"refused from the browser: {error}")
        for event in _changes(message.content):
            _send_back(event["model"]["id"], event["attr"])
        return False


def _changes(content: Any) -> list[dict[str, Any]]:
    """The model changes of a message's content (the others are left alone)."""
    events = content.get("events", []) if isinstance(content, dict) else []
    return [e for e in events if isinstance(e, dict) and e.get("kind") == "ModelChanged"
            and isinstance(e.get("model"), dict) and isinstance(e.get("attr"), str)]


def _send_back(model_id: Any, attr: str) -> None:
    """Send the browser the value in use of ``attr`` of model ``model_id`` (on the
    session's loop, which holds the document's lock)."""
    for doc in list(_documents):
        model = doc.get_model_by_id(model_id) if isinstance(model_id, str) else None
        if model is not None and attr in model.properties():
            def resend(model=model) -> None:
                value = getattr(model, attr)
                model.trigger(attr, value, value)
            doc.add_next_tick_callback(resend)


def watch(doc: Document) -> None:
    """Set back the browser of page ``doc`` after a refused change, and say refusals
    quietly (the filter is added once per process)."""
    _documents.add(doc)
    logger = logging.getLogger(LOGGER)
    if not any(isinstance(f, QuietRefusals) for f in logger.filters):
        logger.addFilter(QuietRefusals())

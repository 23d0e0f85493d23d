"""Values of a type a property cannot hold, sent by the browser: one quiet line in the log.

Bokeh's server checks each change of a ``PATCH-DOC`` message against the property's type
before any widget sees it: a script's ``null`` for a slider's value is refused there, and
``bokeh.server.protocol_handler`` logged it as ERROR with the message and a full traceback.
A filter on that logger (the public ``logging`` API: no library code is replaced) says such
a refusal in one WARNING line, rate-limited with the widgets' own refusals
(:mod:`app.perf.browser_values`).

The browser that sent it keeps showing the refused value (Bokeh answers it with an error):
the record names neither the session nor its document, and model ids repeat from one
session's document to the next, so the filter cannot tell which page to set back.

Examples
--------
>>> QuietRefusals().filter(logging.makeLogRecord({"msg": "another record"}))
True
"""

from __future__ import annotations

import logging

from app.perf.browser_values import say_refused

#: The logger of Bokeh's server that reports a message it could not apply.
LOGGER = "bokeh.server.protocol_handler"


class QuietRefusals(logging.Filter):
    """Replaces the record of a ``PATCH-DOC`` message that Bokeh refused (a ``ValueError``
    of a property's type) by one line of :func:`~app.perf.browser_values.say_refused`; any
    other record passes unchanged."""

    def filter(self, record: logging.LogRecord) -> bool:
        args = record.args if isinstance(record.args, tuple) else ()
        if not (len(args) == 2 and getattr(args[0], "msgtype", None) == "PATCH-DOC"
                and isinstance(args[1], ValueError)):
            return True
        say_refused(f"refused from the browser: {args[1]}")
        return False


def quiet_refusals() -> None:
    """Say Bokeh's refusals of a browser's values quietly (the filter is added once per
    process)."""
    logger = logging.getLogger(LOGGER)
    if not any(isinstance(f, QuietRefusals) for f in logger.filters):
        logger.addFilter(QuietRefusals())

"""Calls run later on a session's event loop, which can be cancelled before they run."""

from __future__ import annotations

from collections.abc import Callable

import panel as pn
from panel.io.state import set_curdoc


class Deferred:
    """A call that can be cancelled before it runs."""

    def __init__(self, fn: Callable[[], None]) -> None:
        self._fn: Callable[[], None] | None = fn

    def cancel(self) -> None:
        self._fn = None

    def __call__(self) -> None:
        fn, self._fn = self._fn, None
        if fn is not None:
            fn()


def later(fn: Callable[[], None], delay_ms: float) -> Deferred:
    """Run ``fn`` after ``delay_ms`` on the session's event loop (at once without a server
    session, e.g. in tests); the returned call can be cancelled until then."""
    call = Deferred(fn)
    doc = pn.state.curdoc
    if doc is None or doc.session_context is None:
        call()
    else:
        def run() -> None:
            with set_curdoc(doc):
                call()
        doc.add_timeout_callback(run, delay_ms)
    return call

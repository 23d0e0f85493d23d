"""Patches of Panel's widget synchronisation (1.9): a slider's release is handled at once,
and not counted as busy work.

Panel waits its debounce (``Syncable._debounce``, 50 ms) before it processes a value from the
browser, so that a drag's many values collapse into the latest. It honours a priority
change (``_priority_changes``, here ``value_throttled``) only when nothing is pending, so a
release arriving while the drag's last value waits out its debounce waited too, up to 50 ms.
:class:`ReleaseAtOnce` processes the pending changes with the release, after the
acknowledgement of the value has been written (:func:`app.perf.websocket.writes_done`).

:func:`keep_released_value` keeps the Bokeh model's read-only ``value_throttled`` in step
with a value set on the server; ``static/perf/release_hold.js`` sends every release. With
them off, releasing a slider exactly where it was last released, after a value was typed,
scene loaded or map tapped in between, is not applied (the typed value stays).

Both go through :func:`app.perf.applies` (name ``slider-release``).

:class:`NotCountedBusy` keeps a slider's values out of Panel's busy counter
(``Syncable._busy__ignore``, name ``slider-not-busy``). Panel counts every change from the
browser as busy work, for a busy indicator; the page shows none (the template's
``busy_indicator=None``), yet each release paid for the count: two list copies and a
parameter's watchers on the way in and out (measured in
benchmarks/results/2026-11-29-switch-interval.md).
"""

from __future__ import annotations

import uuid
from functools import partial
from typing import Any

from panel.io.state import set_curdoc, state

from app.perf import applies
from app.perf.websocket import writes_done


class ReleaseAtOnce:
    """Mixin for a Panel slider: its release is processed at once (see the module)."""

    _priority_changes = ["value_throttled"]
    #: Called as soon as a release arrives, before Panel processes it.
    on_release = None

    def _server_change(self, doc, ref, subpath, attr, old, new) -> None:
        if attr == "value_throttled" and self.on_release is not None:
            self.on_release()
        pending = bool(self._events) and attr in self._priority_changes
        super()._server_change(doc, ref, subpath, attr, old, new)
        if pending and self._events and doc.session_context:
            event_id = uuid.uuid4().hex
            callback = partial(self._change_coroutine, doc, event_id=event_id)
            state._change_callbacks.setdefault(doc, {})[event_id] = callback
            with set_curdoc(doc):
                state.execute(callback, schedule=True)

    async def _change_coroutine(self, doc, event_id: str | None = None) -> None:
        await writes_done(doc)
        await super()._change_coroutine(doc, event_id=event_id)


class NotCountedBusy:
    """Mixin for a Panel slider: its values are not counted as busy work (see the
    module)."""

    _busy__ignore = ["value", "value_throttled"]


def release_bases() -> tuple[type, ...]:
    """The mixins of the patches that apply, of :class:`ReleaseAtOnce` and
    :class:`NotCountedBusy` (for a slider class's bases)."""
    return ((ReleaseAtOnce,) if applies("slider-release") else ()) + (
        (NotCountedBusy,) if applies("slider-not-busy") else ())


def keep_released_value(widget: Any, value: float) -> None:
    """Store ``value`` as the released value of the Bokeh models behind ``widget`` (Bokeh's
    ``value_throttled`` is read-only: its stored value is replaced in place)."""
    if not applies("slider-release"):
        return
    for model, _ in widget._models.values():
        stored = getattr(model, "_property_values", None)
        if isinstance(stored, dict):
            stored["value_throttled"] = value

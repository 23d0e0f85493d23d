"""Patch of Panel's widget synchronisation (1.9): a value from the browser that no user can
give is refused at the widget, quietly, and the browser is put back in step.

Panel applies what the browser sends in ``Syncable._process_events``: it maps the Bokeh
properties to the widget's parameters (``_process_property_change``, the hook Panel's
docstring asks widgets to override) and sets them. A value a script sends over the websocket
— a slider's value outside its range, a select's value outside its options, a radio group's
index outside its buttons — failed there (a select's ``'x' not in list``, an index's
``IndexError``) or in the explorer's watchers (the state's bounds); Panel logged each as
ERROR with a full traceback and raised it again (a second traceback), so that a script could
flood the log, and the browser kept showing the refused value. An index of -1 was not even
refused: Python's indexing picked the last option, ``precise``.

The mixins here check each property before Panel maps it: only the properties a user
changes in the browser (:attr:`RefuseMalformed.from_browser`), of a widget shown and
enabled, and only values the widget can hold. A refused change is dropped, said in one
WARNING line at most every :data:`LOG_INTERVAL_S` (with the count of those not said), and
the widget's Bokeh models are set back to the value in use, which the browser then shows.

Applied through :func:`app.perf.applies` (name ``browser-values``); with it off, Panel's
own handling (an ERROR and a traceback per refusal) is back.
"""

from __future__ import annotations

import logging
import math
import time
from typing import Any, ClassVar

from app.perf import applies

log = logging.getLogger(__name__)

#: Seconds between two log lines about refused values (a script can send thousands).
LOG_INTERVAL_S = 10.0
#: Characters of a refused value shown in the log.
SHOWN_CHARS = 40


class _Limited:
    """One log line per :data:`LOG_INTERVAL_S` at most, counting those left out."""

    def __init__(self) -> None:
        self.last = -math.inf
        self.left_out = 0

    def warning(self, message: str) -> None:
        now = time.monotonic()
        if now - self.last < LOG_INTERVAL_S:
            self.left_out += 1
            return
        if self.left_out:
            message += f" ({self.left_out} more refused since the last such line)"
        self.last, self.left_out = now, 0
        log.warning(message)


_said = _Limited()


def say_refused(message: str) -> None:
    """Log ``message`` about a refused value from the browser, rate-limited."""
    _said.warning(message)


def restart_rate_limit() -> None:
    """Say the next refused value at once, as after the server's start (those not said
    since the last line are no longer counted)."""
    global _said
    _said = _Limited()


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= SHOWN_CHARS else text[:SHOWN_CHARS] + "…"


class RefuseMalformed:
    """Mixin for a Panel widget: a change from the browser that no user can make is refused
    (see the module); subclasses say which properties a user changes and which values
    the widget holds."""

    #: Bokeh properties a user changes in the browser; a change of any other is refused.
    from_browser: ClassVar[tuple[str, ...]] = ()

    def accepts(self, prop: str, value: Any) -> bool:
        """Whether the widget can hold ``value`` of Bokeh property ``prop``."""
        return True

    def _process_property_change(self, props: dict[str, Any]) -> dict[str, Any]:
        # A hidden or disabled widget takes nothing: no user can change it.
        usable = self.visible and not self.disabled
        refused = {prop: value for prop, value in props.items()
                   if not usable or prop not in self.from_browser
                   or not self.accepts(prop, value)}
        if refused:
            say_refused(
                f"refused from the browser: {type(self).__name__} {self.name!r} "
                + ", ".join(f"{prop}={_short(value)}" for prop, value in refused.items()))
            props = {prop: value for prop, value in props.items() if prop not in refused}
            self._back_in_step(refused)
        return super()._process_property_change(props)

    def _back_in_step(self, refused: dict[str, Any]) -> None:
        """Set the Bokeh models' ``refused`` properties back to the values in use (the
        browser follows; a read-only one, such as a slider's released value, is left)."""
        names = {prop: name for name, prop in self._property_mapping.items()}
        current = self._process_param_change(
            {names.get(prop, prop): getattr(self, names.get(prop, prop))
             for prop in refused if names.get(prop, prop) in self.param})
        for model, _ in self._models.values():
            model.update(**{prop: value for prop, value in current.items()
                            if prop in refused and not model.lookup(prop).property.readonly})


class SliderValues(RefuseMalformed):
    """A float slider: a finite number inside ``[start, end]``."""

    from_browser = ("value", "value_throttled")

    def accepts(self, prop: str, value: Any) -> bool:
        return (isinstance(value, int | float) and not isinstance(value, bool)
                and math.isfinite(value) and self.start <= value <= self.end)


class SelectValues(RefuseMalformed):
    """A select: one of its options (as Panel's select maps them: value or label)."""

    from_browser = ("value",)

    def accepts(self, prop: str, value: Any) -> bool:
        return isinstance(value, str) and (value in self.unicode_values
                                           or value in self.labels)


class RadioValues(RefuseMalformed):
    """A radio button group: the index of one of its buttons."""

    from_browser = ("active",)

    def accepts(self, prop: str, value: Any) -> bool:
        return (isinstance(value, int) and not isinstance(value, bool)
                and 0 <= value < len(self.values))


class CheckboxValues(RefuseMalformed):
    """A checkbox: ticked or not."""

    from_browser = ("active",)

    def accepts(self, prop: str, value: Any) -> bool:
        return isinstance(value, bool)


def refusing(mixin: type[RefuseMalformed]) -> tuple[type, ...]:
    """``(mixin,)`` where the patch applies, else ``()`` (for a class's bases)."""
    return (mixin,) if applies("browser-values") else ()

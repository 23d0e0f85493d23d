"""A slider with typed entry, built from two plain widgets and synced on the server.

Panel's ``EditableFloatSlider`` does the same with a JavaScript link per instance; every such
link makes Bokeh re-walk the whole document while a session's page is built, which for the
explorer's eighteen sliders costs seconds per page load. This composite keeps the two
widgets in step in Python instead.
"""

from __future__ import annotations

from collections.abc import Callable

import panel as pn
import param

from app.perf.slider import keep_released_value, release_bases

#: Width of the typed-entry box [px].
INPUT_WIDTH = 96


def set_changed(obj: param.Parameterized, **values) -> None:
    """Set those of ``obj``'s parameters whose value differs, in one update.

    The explorer shows its whole state in the widgets after every change; an assignment of
    an equal value triggers nothing, but param's checks of it cost ~30 µs per widget
    parameter, on the critical path of every slider release.
    """
    changed = {k: v for k, v in values.items() if getattr(obj, k) != v}
    if changed:
        obj.param.update(**changed)


class _Slider(*release_bases(), pn.widgets.FloatSlider):
    """A float slider whose release, where :mod:`app.perf.slider` applies, is handled as
    soon as it arrives instead of after the drag's debounce."""

    #: Called as soon as a release arrives from the browser, before Panel processes it
    #: (where :mod:`app.perf.slider` applies; else the release's commit comes first).
    on_release: Callable[[], None] | None = None

    def expect_release_from(self, value: float) -> None:
        """Make ``value`` the last released value, on the server's side of the link.

        A value set on the server (typed, a scene, a URL, a map tap) leaves the released
        value where the last release put it; a release at that old value then changed
        nothing on the server and was dropped before it reached Panel
        (:func:`app.perf.slider.keep_released_value`).
        """
        with param.edit_constant(self):
            self.value_throttled = value
        keep_released_value(self, value)


class TypedSlider:
    """A labelled slider (soft range) and a number box (hard bounds) for one value.

    Parameters
    ----------
    label : str
    value, step : float
    soft : (float, float)
        The slider's range; a typed value outside it widens the slider.
    bounds : (float, float)
        Hard limits of the typed entry (the browser clamps to them).
    on_drag : callable(float)
        Called with each value while the slider is dragged.
    on_commit : callable(float)
        Called with the final value: slider released, or a number typed.
    on_release : callable(), optional
        Called when a release arrives from the browser, before its value is processed
        (a drag's preview still waiting to be drawn is stale from then on).
    width : int
        Width in pixels.
    css_class : str
        Class of the whole widget (the browser tests find it by this).
    """

    def __init__(self, label: str, value: float, step: float, soft: tuple[float, float],
                 bounds: tuple[float, float], on_drag: Callable[[float], None],
                 on_commit: Callable[[float], None], width: int, css_class: str,
                 on_release: Callable[[], None] | None = None) -> None:
        self.step = step
        self.bounds = bounds
        self._on_drag, self._on_commit = on_drag, on_commit
        self._quiet = False
        start, end = min(soft[0], value), max(soft[1], value)
        if end <= start:
            end = start + step
        self.label = pn.widgets.StaticText(value=label, margin=(6, 4, 0, 10))
        self.input = pn.widgets.FloatInput(
            value=value, step=step, start=bounds[0], end=bounds[1], width=INPUT_WIDTH,
            margin=(0, 10, 0, 0), css_classes=["fie-input"], format="0[.]0000",
        )
        self.slider = _Slider(
            value=value, start=start, end=end, step=step, show_value=False,
            width=width - 20, margin=(0, 10, 4, 10), css_classes=["fie-slider"],
        )
        self.slider.on_release = on_release
        self.slider.param.watch(self._moved, ["value", "value_throttled"])
        self.input.param.watch(self._typed, "value")
        self.layout = pn.Column(
            pn.Row(self.label, pn.Spacer(), self.input, width=width, margin=0),
            self.slider, width=width, margin=(2, 0), css_classes=["fie-typed", css_class],
        )

    # --- state ---------------------------------------------------------------------------

    @property
    def value(self) -> float:
        """The number shown (the slider's value)."""
        return self.slider.value

    @property
    def visible(self) -> bool:
        return self.layout.visible

    @visible.setter
    def visible(self, show: bool) -> None:
        set_changed(self.layout, visible=show)

    def set_label(self, label: str) -> None:
        set_changed(self.label, value=label)

    def set(self, value: float, *, soft_end: float | None = None,
            hard_end: float | None = None) -> None:
        """Show ``value`` without calling back; optionally move the upper ends."""
        start, end = self.slider.start, self.slider.end
        if soft_end is not None:
            end = soft_end
        start, end = min(start, value), max(end, value)
        if end <= start:
            start = min(start, value - self.step)
        if ((start, end, value) == (self.slider.start, self.slider.end, self.slider.value)
                and value == self.input.value == self.slider.value_throttled
                and hard_end in (None, self.bounds[1])):
            return  # nothing to change (this runs for several sliders on every release)
        self._quiet = True
        try:
            if hard_end is not None:
                self.bounds = (self.bounds[0], hard_end)
                self.input.end = hard_end
            self.slider.param.update(start=start, end=end, value=value)
            self.slider.expect_release_from(value)
            if self.input.value != value:
                self.input.value = value
        finally:
            self._quiet = False

    # --- callbacks -----------------------------------------------------------------------

    def _moved(self, *events) -> None:
        """A drag step, or the release (which may arrive with the drag's last step: then
        only the release counts, so no preview is solved and drawn just to be replaced)."""
        if self._quiet:
            return
        by_name = {e.name: e for e in events}
        if "value_throttled" not in by_name:
            self._on_drag(by_name["value"].new)
            return
        value = by_name["value_throttled"].new
        # One message for the typed-entry box and whatever the commit redraws: a message of
        # its own for the box cost ~3 ms (Bokeh's per-message overhead) before the solve.
        with pn.io.hold():
            self._on_commit(value)
            self._quiet = True
            try:
                self.input.value = value
            finally:
                self._quiet = False

    def _typed(self, event) -> None:
        if self._quiet or event.new is None:
            return
        value = min(max(event.new, self.bounds[0]), self.bounds[1])
        self.set(value)
        self._on_commit(value)

    def __panel__(self) -> pn.Column:
        return self.layout

"""A slider with typed entry, built from two plain widgets and synced on the server.

Panel's ``EditableFloatSlider`` does the same with a JavaScript link per instance; every such
link makes Bokeh re-walk the whole document while a session's page is built, which for the
explorer's eighteen sliders costs seconds per page load. This composite keeps the two
widgets in step in Python instead.
"""

from __future__ import annotations

import html
import math
from collections.abc import Callable
from typing import Any

import panel as pn
import param

from app.perf.browser_values import (
    CheckboxValues,
    RadioValues,
    SelectValues,
    SliderValues,
    refusing,
)
from app.perf.slider import keep_released_value, release_bases
from core import check_range


def set_changed(obj: param.Parameterized, **values) -> None:
    """Set those of ``obj``'s parameters whose value differs, in one update.

    The explorer shows its whole state in the widgets after every change; an assignment of
    an equal value triggers nothing, but param's checks of it cost ~30 µs per widget
    parameter, on the critical path of every slider release.
    """
    changed = {k: v for k, v in values.items() if getattr(obj, k) != v}
    if changed:
        obj.param.update(**changed)


def on_click(button: Any, handler: Callable[[Any], None]) -> None:
    """Call ``handler(event)`` on each click of ``button`` (a Panel ``Button`` or
    ``MenuButton``) with the page's changes held (``pn.io.hold``): sent in one message.

    Why held: a click that reaches the server while a change of another widget is still due
    is run by Panel after that change from a coroutine of its own, outside the Bokeh
    document's lock (Panel 1.9's ``Reactive._server_event``). A handler that then sets a
    property of a Bokeh model itself (a figure's font, a data source) makes Bokeh raise
    ("_pending_writes should be non-None") and the rest of the handler never runs: the page
    stays as it was (a presentation that did not leave on Exit). Changes made under a hold
    are collected and written by Panel, with or without the lock.
    """
    def held(event: Any) -> None:
        with pn.io.hold():
            handler(event)

    button.on_click(held)


class ShownLater(pn.Column):
    """A column whose contents join the page the first time it is shown.

    Hidden widgets still cost a new session their Bokeh models (built and sent with the
    page): a rigid-stop scene in dimensionless units never shows the deformable stop's or
    the SI sliders, 13 of the 22. A :class:`TypedSlider` made with ``lazy=True`` and put
    here waits too: its widgets are made when the column is first shown.

    Parameters
    ----------
    *objects
        The contents, added on the first :meth:`show`.
    **params
        Passed to :class:`panel.Column` (hidden until shown).
    """

    def __init__(self, *objects, **params) -> None:
        params.setdefault("margin", 0)
        super().__init__(visible=False, **params)
        self._later = list(objects)

    def show(self, visible: bool) -> None:
        """Show (adding the contents if still waiting) or hide the column."""
        if visible and self._later:
            contents, self._later = [pn.panel(obj) for obj in self._later], []
            set_changed(self, objects=contents, visible=True)
        else:
            set_changed(self, visible=visible)

    @property
    def built(self) -> bool:
        """Whether the contents are in the page."""
        return not self._later


class Select(*refusing(SelectValues), pn.widgets.Select):
    """A select that refuses a value outside its options from the browser quietly and
    shows the value in use again (:mod:`app.perf.browser_values`)."""


class RadioButtonGroup(*refusing(RadioValues), pn.widgets.RadioButtonGroup):
    """A radio button group that refuses an index outside its buttons (-1 included) from
    the browser quietly and shows the button in use again (:mod:`app.perf.browser_values`)."""


class Checkbox(*refusing(CheckboxValues), pn.widgets.Checkbox):
    """A checkbox that takes only ticked or not from the browser
    (:mod:`app.perf.browser_values`)."""


class _Slider(*release_bases(), *refusing(SliderValues), pn.widgets.FloatSlider):
    """A float slider whose release, where :mod:`app.perf.slider` applies, is handled as
    soon as it arrives instead of after the drag's debounce and is not counted as busy
    work, and which refuses a value outside its range from the browser quietly
    (:mod:`app.perf.browser_values`)."""

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
    """A labelled number box (hard bounds) and a slider (soft range) for one value.

    The box takes any text: a value that is not a number, or that ``validate`` refuses,
    is said below the box in red, and the box shows the value in use again; the message
    stays until a valid value replaces it; nothing is committed meanwhile. The label is
    the box's own (its accessible name), with a tooltip naming the symbol and its allowed
    range.

    Parameters
    ----------
    label : str
    value, step : float
        ``step`` is the finest step of the slider; its keyboard step is coarser, so that
        the arrow keys cross the range in about :data:`KEY_PRESSES` presses.
    soft : (float, float)
        The slider's range; a typed value outside it widens the slider.
    bounds : (float, float)
        Hard limits of the typed entry.
    on_drag : callable(float)
        Called with each value while the slider is dragged.
    on_commit : callable(float)
        Called with the final value: slider released, or a valid number typed.
    on_release : callable(), optional
        Called when a release arrives from the browser, before its value is processed
        (a drag's preview still waiting to be drawn is stale from then on).
    width : int
        Width in pixels.
    css_class : str
        Class of the whole widget (the browser tests find it by this).
    name : str
        The parameter's name in messages (``mu_k must lie in ...``).
    validate : callable(float) -> str or None, optional
        The reason a typed value is refused (naming the parameter, the allowed range and
        the value), or None; by default the hard bounds are checked.
    tooltip : str
        What the symbol means; the allowed range is added.
    ceiling : str
        What bounds the value from above when that moves with another value (``static
        friction μₛ`` for μₖ): the tooltip names it instead of its number, so that moving
        the other value does not replace the tooltip (a new Bokeh model each time, after
        which Bokeh walks the whole document again, on the release's critical path).
    lazy : bool
        Make the widgets when first needed (:attr:`layout`, :attr:`input`,
        :attr:`slider`, a message), for a slider that a new page does not show
        (:class:`ShownLater`); until then the slider keeps its values itself.
    """

    def __init__(self, label: str, value: float, step: float, soft: tuple[float, float],
                 bounds: tuple[float, float], on_drag: Callable[[float], None],
                 on_commit: Callable[[float], None], width: int, css_class: str,
                 on_release: Callable[[], None] | None = None, name: str = "",
                 validate: Callable[[float], str | None] | None = None,
                 tooltip: str = "", lazy: bool = False, ceiling: str = "") -> None:
        self.step = step
        self.bounds = bounds
        self.name = name or label
        self._on_drag, self._on_commit = on_drag, on_commit
        self._on_release = on_release
        self._validate = validate
        self._tooltip = tooltip
        self._ceiling = ceiling
        self._quiet = False
        #: The released value being committed, while it is (None otherwise).
        self._releasing: float | None = None
        #: True while a refused entry is said below the box.
        self.invalid = False
        start, end = min(soft[0], value), max(soft[1], value)
        if end <= start:
            end = start + step
        self._width = width
        self._css_class = css_class
        #: The message below the box (:attr:`message`), made when first needed.
        self._message: pn.pane.HTML | None = None
        #: The widgets' values until they are made (a lazy slider), else None.
        self._pending: dict[str, _Values] | None = {
            "input": _Values(label=label, value=format_number(value), description=self._describe(),
                             css_classes=["fie-input"]),
            "slider": _Values(label=label, value=value, start=start, end=end,
                              step=key_step(start, end, step), value_throttled=value),
            "layout": _Values(visible=True),
        }
        if not lazy:
            self._build()

    def _build(self) -> None:
        """Make the widgets from the values kept so far (once)."""
        pending, self._pending = self._pending, None
        if pending is None:
            return
        into, slid, laid = pending["input"], pending["slider"], pending["layout"]
        width = self._width
        self._input = pn.widgets.TextInput(
            label=into.label, value=into.value, width=width, margin=(2, 10, 0, 10),
            css_classes=into.css_classes, stylesheets=[INPUT_CSS],
            description=into.description,
        )
        # The slider's title is its handle's accessible name (static/a11y.js), not shown:
        # the box above it carries the visible label.
        self._slider = _Slider(
            label=slid.label, value=slid.value, start=slid.start, end=slid.end,
            step=slid.step, show_value=False, width=width - 20, margin=(0, 10, 4, 10),
            css_classes=["fie-slider"], stylesheets=[SLIDER_CSS],
        )
        if slid.value_throttled != self._slider.value_throttled:
            self._slider.expect_release_from(slid.value_throttled)
        self._slider.on_release = self._on_release
        self._slider.param.watch(self._moved, ["value", "value_throttled"])
        self._input.param.watch(self._typed, "value")
        # The message joins the layout when first needed (a model less per slider shown).
        self._layout = pn.Column(
            self._input, self._slider, width=width, margin=(2, 0),
            css_classes=["fie-typed", self._css_class], visible=laid.visible,
        )

    @property
    def built(self) -> bool:
        """Whether the widgets are made."""
        return self._pending is None

    @property
    def layout(self) -> pn.Column:
        """The box, the slider and the message, in one column (made on first use)."""
        self._build()
        return self._layout

    @property
    def input(self) -> pn.widgets.TextInput:
        """The number box (made on first use)."""
        self._build()
        return self._input

    @property
    def slider(self) -> pn.widgets.FloatSlider:
        """The slider (made on first use)."""
        self._build()
        return self._slider

    def _part(self, name: str) -> Any:
        """The widget ``name`` (input, slider, layout), or its kept values if not made."""
        if self._pending is not None:
            return self._pending[name]
        return getattr(self, f"_{name}")

    # --- state ---------------------------------------------------------------------------

    @property
    def message(self) -> pn.pane.HTML:
        """The message below the box, hidden until :meth:`note` shows one; made on first
        use (a pane per slider was ~1 ms of every new page, and most never say anything)."""
        if self._message is None:
            self._build()
            self._message = pn.pane.HTML(
                "", visible=False, width=self._width - 20, margin=(0, 10, 2, 10),
                css_classes=["fie-input-message"], stylesheets=[MESSAGE_CSS])
        return self._message

    @property
    def noting(self) -> bool:
        """Whether a message is shown below the box."""
        return self._message is not None and self._message.visible

    @property
    def value(self) -> float:
        """The number shown (the slider's value)."""
        return self._part("slider").value

    @property
    def end(self) -> float:
        """The upper end of the slider's range."""
        return self._part("slider").end

    @property
    def label(self) -> str:
        return self._part("input").label

    @property
    def visible(self) -> bool:
        return self._part("layout").visible

    @visible.setter
    def visible(self, show: bool) -> None:
        set_changed(self._part("layout"), visible=show)

    def set_label(self, label: str) -> None:
        set_changed(self._part("input"), label=label)
        set_changed(self._part("slider"), label=label)

    def _describe(self) -> str:
        low, high = self.bounds
        top = self._ceiling or format_number(high)
        return (f"{self._tooltip} " if self._tooltip else "") + (
            f"Allowed: {format_number(low)} to {top}.")

    def set(self, value: float, *, soft_end: float | None = None,
            hard_end: float | None = None, soft_start: float | None = None) -> None:
        """Show ``value`` without calling back; optionally move the upper ends (and the
        slider's lower end).

        A refused entry's message stays while the value it would have replaced is
        unchanged; a new value replaces it.
        """
        slider, box = self._part("slider"), self._part("input")
        start, end = slider.start, slider.end
        if soft_end is not None:
            end = soft_end
        if soft_start is not None:
            start = soft_start
        start, end = min(start, value), max(end, value)
        if end <= start:
            start = min(start, value - self.step)
        shown = self.invalid or box.value == format_number(value)
        if ((start, end, value) == (slider.start, slider.end, slider.value)
                and shown and value == slider.value_throttled
                and hard_end in (None, self.bounds[1])):
            return  # nothing to change (this runs for several sliders on every release)
        self._quiet = True
        try:
            if hard_end is not None and hard_end != self.bounds[1]:
                self.bounds = (self.bounds[0], hard_end)
                if not self._ceiling:
                    box.description = self._describe()
            step = key_step(start, end, self.step)
            slider.param.update(start=start, end=end, value=value, step=step)
            slider.expect_release_from(value)
            if value != slider.value_throttled or not self.invalid:
                self._show(value)
        finally:
            self._quiet = False

    def set_bounds(self, bounds: tuple[float, float]) -> None:
        """Move the hard bounds (those of an SI box follow m and k) and say them in the
        box's tooltip."""
        if bounds != self.bounds:
            self.bounds = bounds
            set_changed(self._part("input"), description=self._describe())

    def _show(self, value: float) -> None:
        self.invalid = False
        set_changed(self._part("input"), value=format_number(value), css_classes=["fie-input"])
        self.note("")

    def note(self, text: str, error: bool = False) -> None:
        """Show ``text`` below the box (as text; red with the box when ``error``), or hide
        the message when empty."""
        if not text and self._message is None:
            return  # nothing shown, nothing to hide
        body = (f"<div class='fie-msg{' fie-msg-error' if error else ''}' role='status'>"
                f"{html.escape(text)}</div>") if text else ""
        if text and self.message not in self.layout.objects:
            self.layout.insert(1, self.message)
        set_changed(self.message, object=body, visible=bool(text))

    def refuse(self, message: str) -> None:
        """Say ``message`` below the box (red) and put the value in use back in the box:
        a refused entry left there (or a box left empty) said another value than the one
        the page runs with."""
        self.invalid = True
        in_use = format_number(self.value)
        self._quiet = True
        try:
            set_changed(self.input, value=in_use, css_classes=["fie-input"])
        finally:
            self._quiet = False
        self.note(f"{message}; the value in use stays {in_use}", error=True)

    def clear(self) -> None:
        """Forget a refused entry and any note: the box shows the slider's value."""
        self._quiet = True
        try:
            self._show(self.value)
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
            self._quiet = True
            try:
                if self.invalid or self.noting:
                    self._show(value)
                else:
                    set_changed(self.input, value=format_number(value))
            finally:
                self._quiet = False
            self._releasing = value
            try:
                self._on_commit(value)
            finally:
                self._releasing = None

    def moved_on_from(self, value: float) -> bool:
        """Whether ``value`` is this slider's own release being committed while the slider
        has already moved on (a key pressed again, or a drag begun, before the server
        handled the release: Panel may hand it the newer position with the older release).
        Set back there, the handle jumped to the older value under the user's hand; the
        newer position's own release follows."""
        return (self._releasing is not None and value == self._releasing
                and self.built and self._slider.value != value)

    def _typed(self, event) -> None:
        if self._quiet or event.new is None:
            return
        text = str(event.new).strip()
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not math.isfinite(value):
            self.refuse(f"{self.name} must be a number; got {shown_text(text)}")
            return
        reason = (self._validate(value) if self._validate is not None
                  else bounds_reason(self.name, value, self.bounds))
        if reason:
            self.refuse(reason)
            return
        with pn.io.hold():
            self.set(value)
            self._quiet = True
            try:
                self._show(value)
            finally:
                self._quiet = False
            self._on_commit(value)

    def __panel__(self) -> pn.Column:
        return self.layout


class _Values:
    """The parameter values of a widget not made yet, read and set as the widget's
    (``obj.name``, ``obj.param.update(...)``, :meth:`_Slider.expect_release_from`)."""

    def __init__(self, **values: Any) -> None:
        self.__dict__.update(values)

    @property
    def param(self) -> _Values:
        return self

    def update(self, **values: Any) -> None:
        self.__dict__.update(values)

    def expect_release_from(self, value: float) -> None:
        self.value_throttled = value


#: Arrow-key presses that cross a slider's range (PageUp/PageDown move five steps).
KEY_PRESSES = 100
#: The box beside its label, on one line.
INPUT_CSS = """
.bk-input-group { flex-direction: row; align-items: center; gap: 6px; }
.bk-input-group > label { flex: 1; margin: 0; }
.bk-input-group > .bk-input { flex: 0 0 96px; width: 96px; }
.bk-input:focus-visible { outline: 3px solid #1f6feb; outline-offset: 1px; }
"""
#: A visible focus ring on the slider's handle (the keyboard moves it); the title (the
#: handle's accessible name) is not shown. On a phone (app.page_style.PHONE_MAX_WIDTH) the
#: handle is drawn at 24 px and takes touches over 44 x 44 px (the usual smallest touch
#: target), through a transparent ring around it.
SLIDER_CSS = """
.bk-slider-title { display: none; }
.noUi-handle:focus-visible, .noUi-handle:focus { outline: 3px solid #1f6feb;
                                                 outline-offset: 2px; }
@media (max-width: 700px) {
  :host(.fie-slider) { --handle-width: 24px; --handle-height: 24px; }
  .noUi-horizontal .noUi-handle::after { display: block; content: ""; position: absolute;
    background: transparent; width: 44px; height: 44px; left: -10px; top: -10px; }
}
"""
#: The message below a box.
MESSAGE_CSS = """
.fie-msg { font-size: 12px; line-height: 1.3; color: #444; overflow-wrap: anywhere; }
.fie-msg-error { color: #a61b0f; }
"""


def key_step(start: float, end: float, finest: float) -> float:
    """A round slider step (1, 2 or 5 times a power of ten, at least ``finest``) that
    crosses ``[start, end]`` in about :data:`KEY_PRESSES` presses of an arrow key.

    >>> key_step(0.0, 0.6, 0.001), key_step(0.0, 1.0, 0.005), key_step(1.0, 300.0, 1.0)
    (0.005, 0.01, 2.0)
    """
    raw = (end - start) / KEY_PRESSES
    if not raw > 0:
        return finest
    power = 10.0 ** math.floor(math.log10(raw))
    step = min((m * power for m in (1.0, 2.0, 5.0, 10.0)),
               key=lambda c: abs(math.log(c / raw)))
    return max(float(f"{step:.3g}"), finest)


def format_number(value: float) -> str:
    """A value as the box shows it (six significant digits).

    >>> format_number(0.1), format_number(400.0), format_number(1e-6)
    ('0.1', '400', '1e-06')
    """
    return f"{value:.6g}"


def shown_text(text: str, limit: int = 40) -> str:
    """A received entry for a message, quoted and cut at ``limit`` characters."""
    return repr(text if len(text) <= limit else text[:limit] + "…")


def bounds_reason(name: str, value: float, bounds: tuple[float, float]) -> str | None:
    """The core's message for ``value`` outside ``bounds``, or None.

    >>> bounds_reason("restitution", 1.5, (0.0, 1.0))
    'restitution must lie in [0, 1]; got 1.5'
    """
    try:
        check_range(name, value, *bounds)
    except ValueError as exc:
        return str(exc)
    return None

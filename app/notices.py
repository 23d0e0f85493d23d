"""The page's notices: the alert line that says what was not applied or not solved, and the
offer to solve again with more time.

One :class:`Notices` per page, watching its :class:`~app.state.ExplorerState`: a new run on
screen hides the alert, except the alert of a permalink's refused values, which stays while
the run drawn is the one the page opened with.
"""

from __future__ import annotations

import html
from collections.abc import Callable, Mapping
from typing import Any

import panel as pn
import param

from app.state import ExplorerState
from app.widgets import on_click, set_changed

#: The house stylesheet (served by ``--static-dirs assets=static``); panes render in shadow
#: DOMs, so each pane that uses the house classes links it itself.
STYLESHEET = "assets/explorer.css"
#: What the alert says after a message, unless told otherwise.
KEPT_PICTURE = "The plots still show the last valid parameters."


class Notices(pn.viewable.Viewer):
    """The alert and the retry button of one page (the button is built the first time it
    is offered: a new page carries no model for it)."""

    state = param.ClassSelector(class_=ExplorerState, constant=True)

    def __init__(self, **params: Any) -> None:
        super().__init__(**params)
        # An HTML pane whose text is always escaped (a Markdown alert rendered the HTML of a
        # URL's value: a shared link could run script in the page).
        self.alert = pn.pane.HTML("", visible=False, sizing_mode="stretch_width",
                                  css_classes=["fie-alert"], stylesheets=[STYLESHEET])
        #: The last message shown (None before any).
        self.error: str | None = None
        #: The alert kept while the run drawn has these solve values (a link's refusals).
        self._kept: tuple[str, dict[str, Any]] | None = None
        self.retry: pn.widgets.Button | None = None
        self._on_retry: Callable[[], None] | None = None
        self._budget = 0.0
        self._column = pn.Column(self.alert, sizing_mode="stretch_width", margin=0)
        # After the plots' draw (one message all the same: the page waits for its figures).
        self.state.param.watch(self._solution_shown, "solution", precedence=1)

    def __panel__(self) -> pn.viewable.Viewable:
        return self._column

    def show(self, message: str, lead: str = "Input not applied:",
             tail: str = KEPT_PICTURE) -> None:
        """Show ``message`` as text (it may echo a URL's or a user's value), after ``lead``
        and before ``tail``."""
        self.error = message
        with pn.io.hold():
            self.alert.object = (
                f"<div class='fie-alert-box' role='alert'><b>{html.escape(lead)}</b> "
                f"{html.escape(message)}<br>{html.escape(tail)}</div>")
            self.alert.visible = True

    def keep_while(self, values: Mapping[str, Any]) -> None:
        """Keep the alert shown now while the run drawn has solve ``values``."""
        self._kept = (self.alert.object, dict(values))

    def hide(self, message: str | None = None) -> None:
        """Hide the alert (only if it shows ``message``, when given)."""
        if message is None or (self.alert.visible and self.error == message):
            set_changed(self.alert, visible=False)

    def _solution_shown(self, event: param.parameterized.Event) -> None:
        sol = event.new
        self.error = None
        if sol is not None and self._kept != (self.alert.object, dict(sol.values)):
            set_changed(self.alert, visible=False)

    def offer_retry(self, budget: float | None, retry: Callable[[], None] | None = None,
                    description: str = "") -> None:
        """Show the retry button (``budget`` [s] the retry would take), calling
        ``retry``; hide it with ``budget`` None."""
        if budget is None:
            if self.retry is not None:
                set_changed(self.retry, visible=False)
            return
        self._on_retry = retry or self._on_retry
        if self.retry is None:
            self.retry = pn.widgets.Button(
                label="Retry with more time", color="primary", css_classes=["fie-retry"],
                visible=False, margin=(0, 10, 8, 10))
            on_click(self.retry, self._retry_clicked)
            self._column.append(self.retry)
        self._budget = budget
        self.retry.param.update(visible=True, disabled=False, label="Retry with more time",
                                description=description)

    def _retry_clicked(self, event: Any = None) -> None:
        self.retry.param.update(disabled=True, label=f"Solving (up to {self._budget:g} s)…")
        if self._on_retry is not None:
            self._on_retry()

"""The open lesson's step where the presentation strip shows it: its number and title, and
buttons for the step before and the next.

The lesson player (:class:`~app.lessons.player.LessonPlayer`) alone knows which step is
shown and alone steps: it writes :class:`LessonPosition` each time it shows a step (or none),
and the strip's :class:`StripStepper` shows that and asks the player to step, as the
player's own buttons and its ←/→ keys do (:meth:`~app.lessons.player.LessonPlayer.step`).
"""

from __future__ import annotations

from collections.abc import Callable

import panel as pn
import param

from app.lessons.text import plain_math
from app.widgets import on_click

#: Font of the step's line [px]: the strip's (app.present_strip.STRIP_FONT_PX).
FONT_PX = 18
#: Width [px] of the step's line below which the word "Step" and the title go ("Step 14 / 14"
#: takes some 115 px in the strip's 18 px font).
WORD_PX = 130
#: Width [px] of the step's line the strip gives first, and the least ("14 / 14": ~64 px).
LABEL_BASIS_PX, LABEL_MIN_PX = 420, 68
#: Width [px] of the Back and Next buttons (an arrow each).
BUTTON_PX = 34
#: The step's line: one line, "Step K / N" kept whole and the title cut with an ellipsis
#: where the strip is narrow; on a 4:3 projector's 1024 px, "K / N" alone (a container
#: query on the line's own width).
LABEL_CSS = f""":host {{ container-type: inline-size; overflow: hidden; }}
.fie-present-step-text {{ display: flex; font-size: {FONT_PX}px; line-height: 36px;
                          white-space: nowrap; color: #1f3b5f; }}
.fie-step-number {{ flex: none; }}
.fie-step-title {{ min-width: 0; overflow: hidden; text-overflow: ellipsis; }}
@container (max-width: {WORD_PX}px) {{ .fie-step-word, .fie-step-title {{ display: none; }} }}
"""
#: The buttons: the strip's font, a touch's height.
BUTTON_CSS = f""".bk-btn {{ font-size: {FONT_PX}px !important; min-height: 36px;
                          padding: 0; }}"""


class LessonPosition(param.Parameterized):
    """The step of the open lesson on screen, as the lesson player shows it."""

    number = param.Integer(default=0, bounds=(0, None), doc="1-based; 0: no step shown")
    count = param.Integer(default=0, bounds=(0, None), doc="steps of the lesson")
    title = param.String(default="", doc="the step's title (may hold $...$)")


class StripStepper:
    """The Back and Next buttons and the step's line of the presentation strip, hidden when
    no lesson step is shown.

    Parameters
    ----------
    position : LessonPosition
        The step shown (written by the lesson player).
    step : callable(int)
        Steps the lesson by ``delta`` steps (the player's :meth:`step`).
    """

    def __init__(self, position: LessonPosition, step: Callable[[int], None]) -> None:
        self.position = position
        self.back = pn.widgets.Button(label="◀", width=BUTTON_PX, margin=(6, 2),
                                      stylesheets=[BUTTON_CSS],
                                      css_classes=["fie-present-step-back"],
                                      description="The step before (key ←)")
        self.next = pn.widgets.Button(label="▶", width=BUTTON_PX, margin=(6, 2), color="primary",
                                      stylesheets=[BUTTON_CSS],
                                      css_classes=["fie-present-step-next"],
                                      description="The next step (key →)")
        on_click(self.back, lambda event: step(-1))
        on_click(self.next, lambda event: step(1))
        # The line takes its basis before the sliders grow, and gives it up first.
        self.label = pn.pane.HTML("", disable_math=False, margin=(6, 2),
                                  min_width=LABEL_MIN_PX, max_width=2 * LABEL_BASIS_PX,
                                  sizing_mode="stretch_width", stylesheets=[LABEL_CSS],
                                  css_classes=["fie-present-step"],
                                  styles={"flex": f"1 1 {LABEL_BASIS_PX}px"})
        self.layout = pn.Row(self.back, self.next, self.label, margin=0, visible=False,
                             sizing_mode="stretch_width",
                             styles={"flex": f"1 1 {LABEL_BASIS_PX}px"},
                             css_classes=["fie-present-stepper"])
        position.param.watch(lambda *events: self.show(), ["number", "count", "title"])
        self.show()

    def show(self) -> None:
        """Show the position: "Step K / N: title", the ends' buttons disabled."""
        pos = self.position
        self.layout.visible = pos.number > 0
        if pos.number == 0:
            return
        self.label.object = (
            '<div class="fie-present-step-text"><span class="fie-step-number">'
            f'<span class="fie-step-word">Step </span>{pos.number} / {pos.count}</span>'
            f'<span class="fie-step-title">: {plain_math(pos.title)}</span></div>')
        self.back.disabled = pos.number <= 1
        self.next.disabled = pos.number >= pos.count

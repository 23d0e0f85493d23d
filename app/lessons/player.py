"""The lesson player: the list of lessons, and one lesson stepped through on the live page.

Each step loads its state through the page's own permalink reading
(:class:`~app.lessons.driver.PageDriver`) and leaves the page as it is: the student drags,
types and pins as on any page, and "Back to this step" loads the step's state again. The
address carries ``lesson=`` and ``step=`` (:func:`~app.lessons.driver.with_lesson`), so a
copied address reopens the step. A step with a question hides the plots, the caption and
the readout until the student answers; the answer lives in the page alone.
"""

from __future__ import annotations

import html
import urllib.parse
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import panel as pn

from app.lessons.driver import LESSON_KEY, STEP_KEY, PageDriver, step_link, step_query, with_lesson
from app.lessons.format import Lesson, LessonError, Question, Step, lesson_files, read_lesson
from app.lessons.keys import ArrowKeys
from app.lessons.stepper import LessonPosition
from app.lessons.text import lesson_html, plain_math
from app.links import parse_number
from app.scenes import PLOT_TITLES
from app.state import URL_KEYS
from app.widgets import on_click

#: The player's look (its panes render in shadow DOMs: each carries it).
CSS = """
:host { --fie-ink: #1f3b5f; }
.fie-lesson-head { color: #555; font-size: 0.9em; }
.fie-lesson-title { margin: 2px 0 4px 0; font-size: 1.25em; font-weight: 600;
                    color: var(--fie-ink); }
.fie-lesson-text { font-size: 1.02em; line-height: 1.5; max-width: 60em; }
.fie-lesson-text p { margin: 0.3em 0; }
.fie-lesson-look { background: #fff8e1; border-left: 4px solid #f0b400; padding: 4px 10px; }
.fie-lesson-answer { background: #e8f3ea; border-left: 4px solid #2e7d32; padding: 4px 10px; }
.fie-lesson-wrong { background: #fdecea; border-left: 4px solid #c62828; padding: 4px 10px; }
.fie-lesson-alert { background: #f8d7da; color: #58151c; border: 1px solid #f1aeb5;
                    padding: 4px 10px; border-radius: 4px; }
.fie-lesson-item { margin: 2px 0; }
.fie-lesson-display { display: block; text-align: center; margin: 0.4em 0; }
"""
#: The style that hides a pane of the page while a question waits for its answer (a pane's
#: style sheets, once shown, are not sent again when they change: Panel 1.9's HTML pane).
HIDDEN_STYLE = {"display": "none"}
#: The box around the player.
BOX_STYLES = {"border": "1px solid #c9d3e0", "border-radius": "6px", "background": "#f7f9fc",
              "padding": "4px 10px"}


def _html(text: str = "", css: str = "", **kwargs: Any) -> pn.pane.HTML:
    """An HTML pane of the player whose ``\\(...\\)`` the page typesets."""
    options = {"margin": (2, 5), "sizing_mode": "stretch_width", **kwargs}
    return pn.pane.HTML(text, disable_math=False, stylesheets=[CSS],
                        css_classes=[css] if css else [], **options)


class QuestionView:
    """A step's question: asked, then answered with the theory's reason."""

    def __init__(self, on_answered) -> None:
        self.on_answered = on_answered
        self.question: Question | None = None
        #: The answer is shown (the question no longer waits).
        self.revealed = False
        self.ask = _html(css="fie-lesson-ask")
        self.choices = pn.widgets.RadioBoxGroup(options=[], inline=False,
                                                css_classes=["fie-lesson-choices"])
        self.check = pn.widgets.Button(label="Check my answer", color="primary",
                                       css_classes=["fie-lesson-check"], width=160)
        on_click(self.check, lambda event: self.on_answered())
        self.answer = _html(css="fie-lesson-answer-pane", visible=False)
        self.layout = pn.Column(self.ask, self.choices, self.check, self.answer,
                                visible=False, sizing_mode="stretch_width", margin=0,
                                css_classes=["fie-lesson-question"])

    def show(self, question: Question | None) -> None:
        """Ask ``question`` (``None``: no question)."""
        self.question = question
        self.layout.visible = question is not None
        if question is None:
            return
        self.ask.object = (f"<b>Predict, then see.</b> {plain_math(question.ask)}"
                           '<br><span class="fie-lesson-head">The plots, the caption and the '
                           "readout come with the answer.</span>")
        self.choices.options = list(question.choices)
        self.choices.value = None
        self.choices.visible = bool(question.choices)
        self.check.visible = True
        self.answer.visible = self.revealed = False

    @property
    def waiting(self) -> bool:
        """A question is asked and not answered yet."""
        return self.question is not None and not self.revealed

    def answered(self, answer: float | None) -> None:
        """Say whether ``answer`` is right, and why (``None``: none given yet)."""
        q = self.question
        if q is None:
            return
        self.answer.visible = True
        if answer is None:
            self.answer.object = ('<div class="fie-lesson-wrong"><b>Choose an answer first.'
                                  "</b></div>")
            return
        verdict, css = (("Right.", "fie-lesson-answer") if q.right(answer) else
                        ("Not quite.", "fie-lesson-wrong"))
        right = (f"The answer: {html.escape(q.choices[q.correct - 1])}." if q.choices else
                 f"The answer: between {q.low:g} and {q.high:g}.")
        self.answer.object = (f'<div class="{css}"><b>{verdict}</b> {right} '
                              f"{plain_math(q.reason)}</div>")
        self.revealed = True
        self.check.visible = False

    def choice(self) -> int | None:
        """The 1-based number of the choice made, or None."""
        options = self.choices.options
        value = self.choices.value
        return options.index(value) + 1 if value in options else None


class LessonPlayer:
    """The lessons of ``folder`` on the page ``driver``, the address in ``location``; the
    panes of ``hidden`` are hidden while a step asks its question. The step shown is
    written to ``position`` (what the presentation strip shows, :mod:`app.lessons.stepper`).

    While the page presents (:meth:`present`) the strip shows the step and steps it: the
    player's box is hidden, so that the plots fill the screen, except for the list of
    lessons and a step's question (asked, then answered with its reason).
    """

    def __init__(self, driver: PageDriver, folder: Path, location: Any,
                 hidden: Sequence[Any], position: LessonPosition | None = None) -> None:
        self.driver, self.folder, self.location, self.hidden = driver, folder, location, hidden
        self.position = position if position is not None else LessonPosition()
        self.lesson: Lesson | None = None
        self.index = 0
        self.presenting = False
        self.head = _html(css="fie-lesson-head-pane")
        self.close = pn.widgets.Button(label="Close lessons", width=120,
                                       css_classes=["fie-lesson-close"])
        on_click(self.close, lambda event: self.leave())
        self.message = _html(css="fie-lesson-message", visible=False)
        self.catalogue = pn.Column(sizing_mode="stretch_width", margin=0,
                                   css_classes=["fie-lesson-list"])
        self.title = _html(css="fie-lesson-step-title")
        self.text = _html(css="fie-lesson-text-pane")
        self.look = _html(css="fie-lesson-look-pane", visible=False)
        self.question = QuestionView(self._answered)
        self.back = pn.widgets.Button(label="← Back", width=90, css_classes=["fie-lesson-back"])
        self.next = pn.widgets.Button(label="Next →", width=90, color="primary",
                                      css_classes=["fie-lesson-next"])
        self.restore = pn.widgets.Button(label="Back to this step", width=150,
                                         css_classes=["fie-lesson-restore"],
                                         description="Load this step's state again")
        self.link = _html(css="fie-lesson-link", width=160, sizing_mode="fixed",
                          margin=(14, 5, 2, 5))
        self.keys = ArrowKeys(width=0, height=0, margin=0)
        on_click(self.back, lambda event: self.step(-1))
        on_click(self.next, lambda event: self.step(1))
        on_click(self.restore, lambda event: self.apply_step())
        self.keys.param.watch(lambda event: self.step(-1), "back")
        self.keys.param.watch(lambda event: self.step(1), "forward")
        self.step_view = pn.Column(
            self.title, self.question.layout, self.text, self.look,
            pn.Row(self.back, self.next, self.restore, self.link, self.keys, margin=0),
            sizing_mode="stretch_width", margin=0, visible=False,
            css_classes=["fie-lesson-step"])
        self.layout = pn.Column(
            pn.Row(self.head, self.close, sizing_mode="stretch_width", margin=0),
            self.message, self.catalogue, self.step_view,
            sizing_mode="stretch_width", margin=(4, 8), styles=BOX_STYLES,
            css_classes=["fie-lesson-player"])

    # --- the list ----------------------------------------------------------------------

    def lessons(self) -> list[Lesson | LessonError]:
        """Every lesson file of the folder, read (a refused one as its error)."""
        out: list[Lesson | LessonError] = []
        for path in lesson_files(self.folder):
            try:
                out.append(read_lesson(path))
            except LessonError as exc:
                out.append(exc)
        return out

    def show_list(self) -> None:
        """List the lessons, each with a button that starts it."""
        rows: list[Any] = []
        for lesson in self.lessons():
            if isinstance(lesson, LessonError):
                rows.append(_html(f'<div class="fie-lesson-alert">{html.escape(str(lesson))}'
                                  "</div>"))
                continue
            start = pn.widgets.Button(label="Start", width=80,
                                      css_classes=[f"fie-lesson-start-{lesson.name}"])
            on_click(start, lambda event, name=lesson.name: self.open(name, 1))
            rows.append(pn.Row(start, _html(
                f"<b>{html.escape(lesson.title)}</b> ({len(lesson.steps)} steps): "
                f"{plain_math(lesson.summary)}", css="fie-lesson-item"), margin=0,
                sizing_mode="stretch_width"))
        self.catalogue.objects = rows
        self.head.object = '<div class="fie-lesson-head"><b>Lessons</b>: guided steps on ' \
                           "this page; every step leaves the page live.</div>"
        self.catalogue.visible, self.step_view.visible = True, False
        self.position.param.update(number=0, count=0, title="")
        self._say()
        self._ask(None)
        self._write_address("")

    # --- one lesson --------------------------------------------------------------------

    def open_address(self, pairs: Sequence[tuple[str, str]], apply_state: bool = True) -> None:
        """Open the lesson and step an address's ``pairs`` name (``lesson=NAME&step=K``)."""
        given = dict(pairs)
        name, text = given.get(LESSON_KEY, ""), given.get(STEP_KEY, "1")
        names = [p.stem for p in lesson_files(self.folder)]
        if name not in names:
            self.show_list()
            if name:
                self._say(f"{LESSON_KEY}: unknown lesson {name!r} (lessons: "
                          f"{', '.join(names)})")
            return
        self.open(name, 1, apply_state=False)
        if self.lesson is None:
            return
        n = len(self.lesson.steps)
        try:
            number = parse_number(text)
        except ValueError:
            number = 0
        ok = number == int(number) and 1 <= number <= n
        self.go(int(number) - 1 if ok else 0, apply_state=apply_state)
        if not ok:  # said after the step shown, which clears the messages before it
            self._say(f"{STEP_KEY} must be a whole number in [1, {n}]; got {text!r}")

    def open(self, name: str, number: int, apply_state: bool = True) -> None:
        """Open step ``number`` (1-based) of lesson ``name``."""
        try:
            self.lesson = read_lesson(self.folder / f"{name}.md")
        except LessonError as exc:
            self.lesson = None
            self.show_list()
            self._say(str(exc))
            return
        self.catalogue.visible, self.step_view.visible = False, True
        self._show_box()
        self.go(number - 1, apply_state=apply_state)

    def go(self, index: int, apply_state: bool = True) -> None:
        """Show step ``index`` (0-based) and load its state; out of the lesson, nothing."""
        lesson = self.lesson
        if lesson is None or not self.step_view.visible or not 0 <= index < len(lesson.steps):
            return
        self.index = index
        step = lesson.steps[index]
        n = len(lesson.steps)
        self.head.object = (f'<div class="fie-lesson-head"><b>{html.escape(lesson.title)}'
                            f"</b> · step {index + 1} of {n}</div>")
        self.title.object = f'<div class="fie-lesson-title">{plain_math(step.title)}</div>'
        self.text.object = f'<div class="fie-lesson-text">{lesson_html(step.text)}</div>'
        self.look.object = self._look_html(step)
        link = step_link(lesson.name, index + 1)
        self.link.object = (f'<a href="{html.escape(link)}" title="A link to this step">'
                            "Link to this step</a>")
        self.back.disabled, self.next.disabled = index == 0, index == n - 1
        self._say()
        self._ask(step.question)
        if apply_state:
            self.apply_step()
        self._write_address(lesson.name, index + 1)
        self.position.param.update(number=index + 1, count=n, title=step.title)

    def step(self, delta: int) -> None:
        """Show the step ``delta`` steps from the one shown (the buttons', the keys' and the
        presentation strip's stepping); out of the lesson, nothing."""
        self.go(self.index + delta)

    def present(self, on: bool) -> None:
        """The page presents (``on``) or not: the player's box shown for it."""
        self.presenting = on
        self._show_box()

    def apply_step(self) -> None:
        """Load the step's state (again): the page's refusals are named with the file and
        the step."""
        if self.lesson is None:
            return
        step = self.lesson.steps[self.index]
        refused = self.driver.apply_query(step_query(step))
        self._say(str(LessonError(f"{self.lesson.name}.md", self.index + 1,
                                  "state: " + "; ".join(refused))) if refused else "")

    def leave(self) -> None:
        """Close the lessons: the page stays as it is, the plots shown."""
        self.lesson = None
        self.catalogue.visible = self.step_view.visible = False
        self.position.param.update(number=0, count=0, title="")
        self._ask(None)
        self._write_address(None)

    # --- pieces ------------------------------------------------------------------------

    def _look_html(self, step: Step) -> str:
        names = [f"the {PLOT_TITLES[p].lower()}" for p in step.plots]
        plots = ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else "".join(names)
        if step.highlight:
            what = plain_math(step.highlight) + (f" (in {plots})" if plots else "")
        else:
            what = plots
        return f'<div class="fie-lesson-look"><b>Look at</b> {what}.</div>'

    def _ask(self, question: Question | None) -> None:
        """Ask ``question`` with the panes of :attr:`hidden` hidden (``None``: show them)."""
        self.question.show(question)
        self.hide_while_asking()
        self._show_box()

    def _show_box(self) -> None:
        """The player's box: shown with the list or a step; while presenting, only with
        the list or a step's question (the strip shows the step, the plots the rest)."""
        listed, stepping = self.catalogue.visible, self.step_view.visible
        asking = stepping and self.question.question is not None
        self.layout.visible = (listed or asking) if self.presenting else (listed or stepping)

    def hide_while_asking(self) -> None:
        """Hide the panes of :attr:`hidden` while a question waits for its answer: by a
        style of their own (``display: none``), as their ``visible`` belongs to the page
        (the presentation mode hides the readout)."""
        # A question step's text and pointers say the answer: shown with it.
        step = self.lesson.steps[self.index] if self.lesson is not None else None
        self.text.visible = not self.question.waiting
        self.look.visible = (not self.question.waiting and step is not None
                             and bool(step.highlight or step.plots))
        for pane in self.hidden:
            # An empty display gives the pane back its own (the browser drops the style;
            # a style left out of the dict would stay as it was).
            display = HIDDEN_STYLE["display"] if self.question.waiting else ""
            if pane.styles.get("display", "") != display:
                pane.styles = {**pane.styles, "display": display}

    def _answered(self) -> None:
        q = self.question.question
        if q is None:
            return
        answer = self.question.choice() if q.choices else self._guessed(q.guess)
        self.question.answered(answer)
        self.hide_while_asking()

    def _guessed(self, key: str) -> float | None:
        """The page's value of permalink key ``key`` (a number)."""
        names = {**{name: name for name in URL_KEYS}, **{k: n for n, k in URL_KEYS.items()}}
        values = dict(urllib.parse.parse_qsl(self.driver.query))
        try:
            return parse_number(values[URL_KEYS[names[key]]])
        except (KeyError, ValueError):
            return None

    def _say(self, message: str = "") -> None:
        self.message.object = (f'<div class="fie-lesson-alert">{html.escape(message)}</div>'
                               if message else "")
        self.message.visible = bool(message)

    def _write_address(self, name: str | None, number: int = 1) -> None:
        loc = self.location
        if loc is not None:
            search = with_lesson(loc.search, name, number)
            if search != loc.search:
                loc.search = search

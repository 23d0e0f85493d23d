"""The lesson's step in the presentation strip, without a browser: the strip shows the step
the player shows and steps it through the player (one current step, whichever of the
strip's buttons, the player's buttons or its keys stepped), the address follows, and the
player's box makes way for the plots while presenting except for a question
(tests/ui/test_presentation_lesson_ui.py drives it in Chromium)."""

from __future__ import annotations

import re
import urllib.parse

import pytest
from panel.io.location import Location

from app.explorer import Explorer
from app.lessons.format import read_lesson
from app.lessons.mount import LESSONS_DIR
from app.lessons.stepper import LessonPosition, StripStepper

LESSON = read_lesson(LESSONS_DIR / "paper.md")
N = len(LESSON.steps)


def _page(search: str) -> tuple[Explorer, Location]:
    page = Explorer()
    page.main()
    location = Location(search=search)
    page.sync_url(location)
    return page, location


def _step_in_address(location: Location) -> str | None:
    return dict(urllib.parse.parse_qsl(location.search.removeprefix("?"))).get("step")


def _line(stepper: StripStepper) -> str:
    """The step's line as read (its markup dropped)."""
    return re.sub(r"<[^>]+>", "", stepper.label.object)


def _scene(k: int) -> str:
    return dict(urllib.parse.parse_qsl(LESSON.steps[k - 1].state))["scene"]


def test_the_strip_and_the_player_step_one_and_the_same_lesson():
    page, location = _page("?lesson=paper&step=6&present=1")
    player, stepper = page.lessons.player, page.presentation.strip.stepper
    assert stepper.layout.visible
    assert _line(stepper) == f"Step 6 / {N}: {LESSON.steps[5].title}"
    stepper.next.clicks += 1  # the strip's ▶
    assert player.index == 6 and _step_in_address(location) == "7"
    assert page.state.scene == _scene(7) != _scene(6)
    assert _line(stepper).startswith(f"Step 7 / {N}: ")
    player.next.clicks += 1  # the player's own Next
    assert _line(stepper).startswith(f"Step 8 / {N}: ") and _step_in_address(location) == "8"
    player.keys.back += 1  # the ← key
    stepper.back.clicks += 1  # the strip's ◀
    assert player.index == 5 and _step_in_address(location) == "6"
    assert page.state.scene == _scene(6) and _line(stepper).startswith("Step 6 /")


@pytest.mark.parametrize("k, back, forward", [(1, False, True), (N, True, False)])
def test_the_strip_s_buttons_stop_at_the_lesson_s_ends(k, back, forward):
    page, _ = _page(f"?lesson=paper&step={k}&present=1")
    stepper = page.presentation.strip.stepper
    assert (not stepper.back.disabled, not stepper.next.disabled) == (back, forward)
    (stepper.back if k == 1 else stepper.next).clicks += 1  # out of the lesson: nothing
    assert page.lessons.player.index == k - 1


def test_without_a_lesson_step_the_stepper_is_hidden():
    page, _ = _page("?scene=7c&present=1")
    assert not page.presentation.strip.stepper.layout.visible
    page, _ = _page("?lesson=paper&step=2&present=1")
    stepper = page.presentation.strip.stepper
    page.lessons.player.leave()
    assert not stepper.layout.visible
    page, _ = _page("?lesson=&present=1")  # the list of lessons: no step yet
    assert not page.presentation.strip.stepper.layout.visible


def test_the_position_is_the_player_s_and_only_the_player_writes_it():
    page, _ = _page("?lesson=paper&step=4")
    position = page.lessons.position
    assert isinstance(position, LessonPosition) and position is page.lessons.player.position
    assert (position.number, position.count, position.title) == (4, N, LESSON.steps[3].title)
    page.lessons.step(2)
    assert position.number == 6 and page.lessons.player.index == 5


def test_while_presenting_the_player_shows_only_a_question():
    """The strip shows the step: the player's box would push the plots below the window
    (a step's text is ~200 px high), except where a step asks (the plots are hidden then)."""
    page, _ = _page("?lesson=paper&step=4")
    player, state = page.lessons.player, page.state
    assert player.layout.visible
    state.present = "1"
    assert not player.layout.visible
    player.go(2)  # "A faster belt" asks
    assert player.layout.visible
    player.question.choices.value = player.question.choices.options[0]
    player.question.check.clicks += 1
    assert player.layout.visible  # the answer and its reason stay in view
    player.go(3)
    assert not player.layout.visible
    state.present = ""
    assert player.layout.visible


def test_a_page_opened_presenting_with_a_lesson_hides_the_player():
    page, _ = _page("?lesson=paper&step=4&present=4")
    assert not page.lessons.player.layout.visible
    assert page.presentation.strip.stepper.layout.visible

"""The paper's lesson walked end to end in Chromium: every step loads its state, the address
carries lesson= and step=, the arrow keys step, a slider moved mid-step changes the plots and
"Back to this step" restores them, a predict step hides the plots until it is answered, and
the lesson's mathematics is typeset by the page's own MathJax (no other host is asked)."""

from __future__ import annotations

import re
import urllib.parse

import numpy as np
import pytest
from uipage import PAGE_TIMEOUT_MS, Page

from app.lessons.format import read_lesson
from app.lessons.mount import LESSONS_DIR
from app.scenes import SCENES

pytestmark = pytest.mark.ui

LESSON = read_lesson(LESSONS_DIR / "paper.md")
N = len(LESSON.steps)
#: Mean absolute pixel change that counts as "the picture changed" (0-255 scale), and the
#: most a picture drawn again from the same state may differ (antialiasing of the same
#: curves: none expected, a little allowed).
MIN_CHANGE, SAME = 0.5, 0.05
#: JavaScript: a new page (after the lessons button opened one) is ready.
JS_READY_AGAIN = """() => window.Bokeh && Bokeh.documents.length > 0 &&
  Bokeh.documents[0].is_idle === true"""
#: JavaScript: the number of typeset formulas in the lesson's text (in its shadow root).
JS_FORMULAS = """() => {
  let n = 0;
  function walk(root) {
    for (const el of root.querySelectorAll("*")) {
      if (el.shadowRoot) walk(el.shadowRoot);
      if (el.tagName === "MJX-CONTAINER" || el.tagName === "mjx-container") n += 1;
    }
  }
  walk(document);
  return n;
}"""


def _scene(step) -> tuple[str, bool]:
    """The step's scene and whether its state is that scene's alone."""
    pairs = dict(urllib.parse.parse_qsl(step.state))
    physics = set(pairs) - {"scene", "method", "acc"}
    return pairs["scene"], not physics


@pytest.fixture(scope="module")
def page(browser, server):
    p = Page(browser, f"{server}?lesson=paper&step=1")
    hosts = []
    p.page.on("request", lambda r: hosts.append(urllib.parse.urlsplit(r.url).netloc))
    p.hosts = hosts
    yield p
    p.close()


def _wait_step(p: Page, k: int) -> None:
    p.page.wait_for_function(
        "k => location.search.includes('lesson=paper') && "
        "new URLSearchParams(location.search).get('step') === String(k)", arg=k,
        timeout=PAGE_TIMEOUT_MS)
    p.page.wait_for_function("() => Bokeh.documents[0].is_idle", timeout=PAGE_TIMEOUT_MS)
    assert f"step {k} of {N}" in p.text(".fie-lesson-head-pane")
    p.settle()


def _scene_label(p: Page) -> str:
    return p.page.locator(".fie-scene select").evaluate("s => s.options[s.selectedIndex].text")


def _plots_shown(p: Page) -> bool:
    """Whether the plots are shown; the caption and the readout are shown with them."""
    shown = [p.page.locator(css).first.is_visible()
             for css in (".fie-plots", ".fie-caption", ".fie-readout-pane")]
    assert len(set(shown)) == 1, shown
    return shown[0]


def _answer(p: Page, step) -> None:
    """Answer the step's question (the right choice, or the guess as the step leaves it)
    and wait for the plots."""
    q = step.question
    if q.choices:
        p.page.get_by_text(q.choices[q.correct - 1], exact=True).click()
    p.page.locator(".fie-lesson-check button").click()
    p.page.wait_for_function("() => Bokeh.documents[0].is_idle", timeout=PAGE_TIMEOUT_MS)
    p.page.locator(".fie-plots").first.wait_for(state="visible", timeout=PAGE_TIMEOUT_MS)
    verdict = p.text(".fie-lesson-answer-pane")
    assert ("Right." if q.choices else "Not quite.") in verdict


def _press(p: Page, key: str) -> None:
    # The keys go to the lesson when no control has the keyboard: the text is clicked first.
    p.page.locator(".fie-lesson-text-pane").first.click()
    p.page.keyboard.press(key)


def test_the_paper_lesson_walked_end_to_end(page, shots):
    p = page
    for k, step in enumerate(LESSON.steps, start=1):
        _wait_step(p, k)
        scene, alone = _scene(step)
        assert _scene_label(p) == (SCENES[scene].title if alone else "custom"), k
        if step.question is not None:
            assert not _plots_shown(p), f"step {k} shows its plots before the answer"
            p.page.screenshot(path=shots / f"lesson-paper-{k}-asked.png")
            _answer(p, step)
        assert _plots_shown(p)
        if k in (1, 4, 9):
            p.page.screenshot(path=shots / f"lesson-paper-{k}.png")
        if k < N:
            _press(p, "ArrowRight")
    _press(p, "ArrowLeft")
    _wait_step(p, N - 1)
    assert p.page.evaluate(JS_FORMULAS) > 0  # the text's $...$, typeset
    assert set(p.hosts) <= {urllib.parse.urlsplit(p.page.url).netloc}  # no CDN


def test_a_slider_moved_mid_step_changes_the_plots_and_back_to_this_step_restores_them(page):
    p = page
    p.page.goto(re.sub(r"\?.*", "?lesson=paper&step=4", p.page.url))
    p.page.wait_for_function("() => window.Bokeh && Bokeh.documents.length > 0 && "
                             "Bokeh.documents[0].is_idle", timeout=PAGE_TIMEOUT_MS)
    p.wait_plots()
    _wait_step(p, 4)
    before = p.pixels(".fie-plot-phase")
    old = p.text(".fie-readout-pane")
    p.drag_slider("clearance", 40)
    p.wait_text_change(".fie-readout-pane", old)
    moved = p.pixels(".fie-plot-phase")
    assert np.abs(moved - before).mean() > MIN_CHANGE
    assert _scene_label(p) == "custom" and "step=4" in p.page.url
    old = p.text(".fie-readout-pane")
    p.page.locator(".fie-lesson-restore button").click()
    p.wait_text_change(".fie-readout-pane", old)
    p.page.wait_for_function("() => Bokeh.documents[0].is_idle", timeout=PAGE_TIMEOUT_MS)
    p.settle()
    assert _scene_label(p) == SCENES["5a"].title
    assert np.abs(p.pixels(".fie-plot-phase") - before).mean() < SAME


def test_the_lessons_button_lists_the_lessons_on_the_page_s_own_state(browser, server):
    p = Page(browser, f"{server}?scene=7c&r=0.5")
    try:
        p.page.wait_for_function("() => location.search.includes('tend=')",
                                 timeout=PAGE_TIMEOUT_MS)  # the page wrote its state
        p.page.locator(".fie-open-lessons button").click()
        p.page.wait_for_function("() => location.search.includes('lesson=')",
                                 timeout=PAGE_TIMEOUT_MS)
        p.page.wait_for_function(JS_READY_AGAIN, timeout=PAGE_TIMEOUT_MS)
        p.page.locator(".fie-lesson-list").first.wait_for(state="visible")
        assert LESSON.title in p.text(".fie-lesson-list")
        params = urllib.parse.parse_qs(urllib.parse.urlsplit(p.page.url).query)
        assert params["r"] == ["0.5"] and params["scene"] == ["custom"]
        assert p.page.locator(".fie-w-restitution input").first.input_value() == "0.5"
        p.page.locator(".fie-lesson-start-paper button").click()
        _wait_step(p, 1)
    finally:
        p.close()

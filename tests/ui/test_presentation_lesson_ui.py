"""A lesson stepped from the presentation strip in Chromium: P presents, → and ← (and the
strip's ▶ and ◀) step the lesson, the step's line, the address, the scene and the plots
following; an arrow key on a focused slider of the strip moves the slider and steps
nothing; the strip keeps one line and the plots fill the window at 1920x1080 and 1024x768
with the stepper in it."""

from __future__ import annotations

import urllib.parse

import pytest
from test_presentation_strip_ui import (
    FILL,
    JS_PHASE_DATA,
    JS_PLOT_BOXES,
    SCREENS,
    _wait_mode,
    union_area,
)
from uipage import JS_READY, PAGE_TIMEOUT_MS, Page

from app.lessons.format import read_lesson
from app.lessons.mount import LESSONS_DIR
from app.present_strip import STRIP_HEIGHT_PX
from app.presentation import PLOT_COUNT
from app.scenes import SCENES

pytestmark = pytest.mark.ui

LESSON = read_lesson(LESSONS_DIR / "paper.md")
N = len(LESSON.steps)
#: Steps without a question whose scenes differ: stepping between them redraws the plots.
FIRST, SECOND = 6, 7
#: JavaScript: the boxes [x, y, w, h] of the strip's visible widgets (its row's children).
JS_STRIP_BOXES = """() => {
  const out = [];
  const part = /^fie-present-(stepper|scene|slider|layouts|fullscreen|exit|help)$/;
  const walk = (root) => {
    for (const el of root.querySelectorAll("*")) {
      if ([...el.classList].some(c => part.test(c))) {
        const r = el.getBoundingClientRect();
        if (r.width > 0) out.push([r.x, r.y, r.width, r.height]);
      }
      if (el.shadowRoot) walk(el.shadowRoot);
    }
  };
  walk(document);
  return out;
}"""

#: JavaScript: every figure on screen draws data (a renderer's source has a row): the
#: step's run reached each plot of the layout.
JS_ALL_DRAWN = """() => Bokeh.index.query(v => v.model.type === "Figure").every(v => {
  const r = v.el.getBoundingClientRect();
  if (r.width === 0 || !v.el.isConnected) return true;
  return v.model.renderers.some(g => g.data_source && g.data_source.get_length() > 0);
})"""


def _read(text: str) -> str:
    """The step's line as read (the deep text puts a space after each of its parts)."""
    return text.replace(" :", ":")


def _line(p: Page) -> str:
    return _read(p.text(".fie-present-step"))


def _scene(k: int) -> str:
    return dict(urllib.parse.parse_qsl(LESSON.steps[k - 1].state))["scene"]


def _strip_scene(p: Page) -> str:
    return p.page.locator(".fie-present-scene select").evaluate(
        "s => s.options[s.selectedIndex].text")


def _address(p: Page, key: str) -> str | None:
    return urllib.parse.parse_qs(urllib.parse.urlsplit(p.page.url).query).get(key, [None])[0]


def _wait_step(p: Page, k: int, arrived: str) -> None:
    """Wait for step ``k`` in the strip's line and the address, and for the run of its
    state (``arrived``: the count of runs before the step)."""
    p.wait_text(".fie-present-step", lambda t: _read(t).startswith(f"Step {k} / {N}: "),
                f"the strip does not show step {k}")
    p.page.wait_for_function(
        "k => new URLSearchParams(location.search).get('step') === String(k)", arg=k,
        timeout=PAGE_TIMEOUT_MS)
    p.wait_text(".fie-solution-arrived", lambda t: t != arrived, "no run of the step arrived")
    p.still()
    assert _line(p) == f"Step {k} / {N}: {LESSON.steps[k - 1].title}"
    assert _strip_scene(p) == SCENES[_scene(k)].title


def _step(p: Page, do, k: int) -> None:
    """Step to ``k`` by ``do()`` and check that the plots were drawn again."""
    before, arrived = p.page.evaluate(JS_PHASE_DATA), p.text(".fie-solution-arrived")
    do()
    _wait_step(p, k, arrived)
    assert p.page.evaluate(JS_PHASE_DATA) != before, f"the plots of step {k} did not change"


def test_the_strip_steps_the_lesson_by_keys_and_buttons(browser, server, shots):
    p = Page(browser, f"{server}?lesson=paper&step={FIRST}", viewport=SCREENS["1080p"])
    try:
        assert not p.page.locator(".fie-present-step").first.is_visible()
        p.page.locator("body").first.focus()
        p.page.keyboard.press("p")
        _wait_mode(p, "1")
        assert _line(p) == f"Step {FIRST} / {N}: {LESSON.steps[FIRST - 1].title}"
        assert not p.page.locator(".fie-lesson-player").first.is_visible()  # made way
        p.page.screenshot(path=shots / "present-lesson-step-1080p.png")
        keys = p.page.keyboard
        _step(p, lambda: keys.press("ArrowRight"), SECOND)
        _step(p, lambda: keys.press("ArrowLeft"), FIRST)
        _step(p, lambda: p.page.locator(".fie-present-step-next button").click(), SECOND)
        _step(p, lambda: p.page.locator(".fie-present-step-back button").click(), FIRST)
        # The "?" help lists the arrows with the other keys.
        keys.press("?")
        assert "lesson steps" in p.text(".fie-present-keys")
        keys.press("?")
        # Leaving, the player is back at the step the strip showed.
        keys.press("p")
        _wait_mode(p, "")
        assert f"step {FIRST} of {N}" in p.text(".fie-lesson-head-pane")
        assert p.errors == []
    finally:
        p.close()


def test_arrows_on_a_focused_slider_move_it_and_do_not_step(browser, server):
    p = Page(browser, f"{server}?lesson=paper&step={FIRST}&present=1",
             viewport=SCREENS["1080p"])
    try:
        p.wait_text(".fie-present-step", lambda t: t.startswith(f"Step {FIRST} /"),
                    "the strip does not show the step")
        handle = p.page.locator(".fie-present-w-clearance .noUi-handle").first
        # The page writes its whole state into the address a moment after it loads (the
        # lesson's link names no clearance): read the address as the browser has it.
        xbar = "() => new URLSearchParams(location.search).get('xbar')"
        p.page.wait_for_function(f"() => ({xbar})() !== null", timeout=PAGE_TIMEOUT_MS)
        for key in ("ArrowRight", "ArrowLeft", "ArrowLeft"):
            old, arrived = p.page.evaluate(xbar), p.text(".fie-solution-arrived")
            handle.focus()
            p.page.keyboard.press(key)
            # The slider's new value is the state's (the address) and its run arrives; a
            # step, sent with it, would have come by then.
            p.page.wait_for_function(
                "old => new URLSearchParams(location.search).get('xbar') !== old", arg=old,
                timeout=PAGE_TIMEOUT_MS)
            p.wait_text(".fie-solution-arrived", lambda t, a=arrived: t != a,
                        "no run of the slider's value arrived")
            p.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
            moved = float(p.page.evaluate(xbar))
            assert (moved > float(old)) == (key == "ArrowRight"), (key, old, moved)
            assert _address(p, "step") == str(FIRST)
            assert _line(p).startswith(f"Step {FIRST} / {N}: ")
        assert p.errors == []
    finally:
        p.close()


@pytest.mark.parametrize("screen, mode", [("1080p", "1"), ("1080p", "4"), ("xga", "1"),
                                          ("xga", "4")])
def test_the_strip_with_a_lesson_keeps_one_line_and_the_plots_fill(browser, server, shots,
                                                                   screen, mode):
    size = SCREENS[screen]
    p = Page(browser, f"{server}?lesson=paper&step={N}&present={mode}", viewport=size)
    try:
        _wait_mode(p, mode)
        p.wait_text(".fie-present-step", lambda t: t.startswith(f"{N} / {N}") or
                    t.startswith(f"Step {N} / {N}"), "the strip does not show the step")
        p.page.wait_for_function(JS_ALL_DRAWN, timeout=PAGE_TIMEOUT_MS)
        p.still()
        p.page.screenshot(path=shots / f"present-lesson-{mode}-{screen}.png")
        strip = p.page.evaluate(JS_STRIP_BOXES)
        assert len(strip) == 9  # stepper, scene, 3 sliders, layouts, fullscreen, exit, help
        # One line: every widget within the strip's height and the window's width.
        for x, y, w, h in strip:
            assert y >= 0 and y + h <= STRIP_HEIGHT_PX + 1 and 0 <= x and x + w <= size["width"]
        # The step's number whole, never under the next widget.
        number = p.page.locator(".fie-step-number").first.bounding_box()
        scene = p.page.locator(".fie-present-scene").first.bounding_box()
        assert number["x"] + number["width"] <= scene["x"]
        boxes = p.page.evaluate(JS_PLOT_BOXES)
        assert len(boxes) == PLOT_COUNT[mode]
        fill = union_area(boxes, size["width"], size["height"]) / (
            size["width"] * size["height"])
        print(f"{screen} present={mode}, lesson step {N}: plots cover {fill:.1%}")
        assert fill >= FILL, fill
        assert p.errors == []
    finally:
        p.close()

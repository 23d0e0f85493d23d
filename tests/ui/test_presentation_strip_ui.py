"""Presentation you can drive, in a real browser: entering and leaving by the Present button
and the strip's Exit, and by the P key; the strip's sliders change the plots; the layouts of
one to four plots (keys 1-4) fill a 1920x1080 and a 1024x768 window."""

from __future__ import annotations

import pytest
from playwright.sync_api import TimeoutError as PlaywrightTimeout
from uipage import JS_READY, PAGE_TIMEOUT_MS, Page

from app.presentation import MODES, PLOT_COUNT

pytestmark = pytest.mark.ui

#: A 16:9 and a 4:3 screen.
SCREENS = {"1080p": {"width": 1920, "height": 1080}, "xga": {"width": 1024, "height": 768}}
#: Share of the window the plots' boxes cover at least (the rest: the control strip, one
#: slim row, and the plots' margins).
FILL = 0.9
#: JavaScript: the boxes [x, y, w, h] of the plots shown (their panes, shadow roots entered).
JS_PLOT_BOXES = """() => {
  const out = [];
  const plot = /^fie-plot-(phase|time|anim|force|loop|friction|energy|map)$/;
  const walk = (root) => {
    for (const el of root.querySelectorAll("*")) {
      if ([...el.classList].some(c => plot.test(c))) {
        const r = el.getBoundingClientRect();
        if (r.width > 0 && r.height > 0) out.push([r.x, r.y, r.width, r.height]);
      }
      if (el.shadowRoot) walk(el.shadowRoot);
    }
  };
  walk(document);
  return out;
}"""
#: JavaScript: a fingerprint of the phase portrait's drawn data (every column's length and
#: sum of the data sources of its renderers).
JS_PHASE_DATA = """() => {
  const fig = [...Bokeh.documents[0].all_models].find(
    m => m.type === "Figure" && m.title && m.title.text.startsWith("Phase portrait"));
  let s = 0, n = 0;
  for (const r of fig.renderers) {
    const data = r.data_source && r.data_source.data;
    if (!data) continue;
    for (const col of (data instanceof Map ? data.values() : Object.values(data))) {
      for (const v of col) { if (typeof v === "number" && isFinite(v)) { s += v; n += 1; } }
    }
  }
  return [n, s];
}"""


def union_area(boxes: list[list[float]], width: float, height: float) -> float:
    """Area of the union of the boxes ``[x, y, w, h]`` clipped to the window (coordinate
    compression: exact for any overlap)."""
    clipped = [(max(0.0, x), max(0.0, y), min(width, x + w), min(height, y + h))
               for x, y, w, h in boxes]
    clipped = [b for b in clipped if b[2] > b[0] and b[3] > b[1]]
    xs = sorted({v for b in clipped for v in (b[0], b[2])})
    ys = sorted({v for b in clipped for v in (b[1], b[3])})
    area = 0.0
    for x0, x1 in zip(xs, xs[1:], strict=False):
        for y0, y1 in zip(ys, ys[1:], strict=False):
            if any(b[0] <= x0 and x1 <= b[2] and b[1] <= y0 and y1 <= b[3] for b in clipped):
                area += (x1 - x0) * (y1 - y0)
    return area


def test_union_area_counts_an_overlap_once():
    assert union_area([[0, 0, 10, 10], [5, 5, 10, 10]], 100, 100) == 175
    assert union_area([[-5, 0, 10, 10]], 100, 100) == 50  # clipped to the window


def _wait_mode(p: Page, mode: str) -> None:
    on = "true" if mode else "false"
    try:
        p.page.wait_for_function(
            f"() => document.body.classList.contains('fie-present') === {on} && "
            f"new URLSearchParams(location.search).get('present') === '{mode or '0'}'",
            timeout=PAGE_TIMEOUT_MS)
    except PlaywrightTimeout:
        # What the page said and shows, for a cause to be found from a failed run.
        raise AssertionError(
            f"present={mode or '0'} not reached: address {p.page.url}, body classes "
            f"{p.page.evaluate('document.body.className')!r}, page errors {p.errors}") from None
    p.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
    p.wait_plots()
    p.still()
    p.settle()


def test_enter_and_leave_by_button_and_by_p(browser, server, shots):
    p = Page(browser, server + "?scene=7c", viewport=SCREENS["1080p"])
    try:
        strip = p.page.locator(".fie-present-strip").first
        assert strip.count() == 0  # built on the first entry only
        p.page.locator(".fie-present-button button").first.click()
        _wait_mode(p, "1")
        assert strip.is_visible()
        assert not p.page.locator("#sidebar").first.is_visible()
        p.page.locator(".fie-present-exit button").first.click()
        _wait_mode(p, "")
        assert p.page.locator("#sidebar").first.is_visible()
        assert not strip.is_visible()
        # The keyboard: P presents, 4 picks the 2x2 grid, P leaves.
        p.page.locator("body").first.focus()
        p.page.keyboard.press("p")
        _wait_mode(p, "1")
        p.page.keyboard.press("4")
        _wait_mode(p, "4")
        p.page.screenshot(path=shots / "present-strip-keys-4.png")
        p.page.keyboard.press("P")
        _wait_mode(p, "")
        # Not while typing: a P typed into a number box stays there.
        box = p.page.locator(".fie-w-restitution input").first
        box.click()
        p.page.keyboard.press("p")
        p.settle()
        assert "present=1" not in p.page.url
        assert p.errors == []
    finally:
        p.close()


def test_strip_slider_changes_the_plots(browser, server):
    p = Page(browser, server + "?scene=7c&present=1", viewport=SCREENS["1080p"])
    try:
        before = p.page.evaluate(JS_PHASE_DATA)
        arrived = p.text(".fie-solution-arrived")
        handle = p.page.locator(".fie-present-w-restitution .noUi-handle").first
        box = handle.bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        p.page.mouse.move(x, y)
        p.page.mouse.down()
        p.page.mouse.move(x + 60, y, steps=6)
        p.page.mouse.up()
        p.page.wait_for_function("() => new URLSearchParams(location.search).get('r') !== null",
                                 timeout=PAGE_TIMEOUT_MS)  # the new r is the state's
        p.wait_text(".fie-solution-arrived", lambda t: t != arrived, "no new run arrived")
        p.still()
        after = p.page.evaluate(JS_PHASE_DATA)
        assert after != before
        assert p.errors == []
    finally:
        p.close()


#: JavaScript: in one task, move the slider of the widget with CSS class ``slider`` by a
#: step and click the button of the widget with class ``button``: the click reaches the
#: server while the slider's change is still due (a lecturer drags, then presses P at once).
JS_SLIDE_AND_CLICK = """([slider, button]) => {
  const has = (m, cls) => m.css_classes != null && m.css_classes.includes(cls);
  // The slider: the model with the class, or the first one with a step inside it.
  const find = (m) => m.type === "Slider" ? m :
    (m.children || []).map(find).find(c => c != null);
  const model = [...Bokeh.documents[0].all_models].filter(m => has(m, slider)).map(find)
    .find(m => m != null);
  const view = [...Bokeh.index.query(v => v.model != null && has(v.model, button) &&
                                          v.el.isConnected)][0];
  model.value = model.value + model.step;
  (view.shadow_el || view.el.shadowRoot).querySelector("button").click();
}"""


def test_enter_and_leave_while_a_slider_change_is_on_its_way(browser, server):
    # Panel runs such a click outside the document's lock: the mode's restyling of the
    # figures raised on the server and the page stayed as it was (app.widgets.on_click).
    p = Page(browser, server + "?scene=7c", viewport=SCREENS["1080p"])
    try:
        p.page.evaluate(JS_SLIDE_AND_CLICK, ["fie-w-restitution", "fie-present-button"])
        _wait_mode(p, "1")
        p.page.keyboard.press("4")
        _wait_mode(p, "4")
        p.page.evaluate(JS_SLIDE_AND_CLICK, ["fie-present-w-restitution", "fie-present-exit"])
        _wait_mode(p, "")
        assert p.errors == []
    finally:
        p.close()


@pytest.mark.parametrize("screen", list(SCREENS))
def test_each_layout_fills_the_window(browser, server, shots, screen):
    size = SCREENS[screen]
    p = Page(browser, server + "?scene=10&present=1", viewport=size)
    try:
        for mode in MODES:
            p.page.keyboard.press(mode)
            _wait_mode(p, mode)
            p.page.screenshot(path=shots / f"present-layout-{mode}-{screen}.png")
            boxes = p.page.evaluate(JS_PLOT_BOXES)
            assert len(boxes) == PLOT_COUNT[mode], mode
            # Every plot of the layout is drawn (none waits, empty, for the browser's report).
            assert p.page.locator(".fie-plot-pending").count() == 0, mode
            fill = union_area(boxes, size["width"], size["height"]) / (
                size["width"] * size["height"])
            print(f"{screen} present={mode}: plots cover {fill:.1%} of the window")
            assert fill >= FILL, (mode, fill)
            # Nothing below the window: the page does not scroll.
            assert all(y + h <= size["height"] + 1 for _, y, _, h in boxes), (mode, boxes)
        assert p.errors == []
    finally:
        p.close()

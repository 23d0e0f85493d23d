"""What only a browser shows of the pictures: the phase portrait's aspect on the laid-out
frame, and plots that fit the window."""

from __future__ import annotations

import pytest

from tests.ui.uipage import JS_READY, PAGE_TIMEOUT_MS

#: JavaScript: the phase portrait's frame [px] and ranges as BokehJS laid them out.
JS_PHASE_VIEW = """() => {
  const doc = Bokeh.documents[0];
  for (const m of doc.all_models) {
    if (m.title && m.title.text && m.title.text.startsWith("Phase portrait")) {
      return {w: m.inner_width, h: m.inner_height, x0: m.x_range.start, x1: m.x_range.end,
              y0: m.y_range.start, y1: m.y_range.end, scale: m.aspect_scale};
    }
  }
  return null;
}"""
#: JavaScript: the right edge [px] of every canvas and plot legend on the page, shadow
#: roots included, and the smallest axis label font of the figures.
JS_EXTENTS = """() => {
  const rights = [], lefts = [];
  function walk(n) {
    if (n.shadowRoot) walk(n.shadowRoot);
    for (const c of n.children || []) {
      const box = c.getBoundingClientRect();
      if (c.tagName === "CANVAS" && box.width > 50 && box.height > 50) {
        rights.push(box.right);
        lefts.push(box.left);
      }
      walk(c);
    }
  }
  walk(document.body);
  let font = 1e9;
  for (const m of Bokeh.documents[0].all_models) {
    if (m.axis_label_text_font_size && m.visible !== false && m.axis_label) {
      font = Math.min(font, parseFloat(m.axis_label_text_font_size));
    }
  }
  return {rights, lefts, font};
}"""


def _open(browser, url: str, width: int, height: int):
    page = browser.new_page(viewport={"width": width, "height": height})
    page.goto(url, timeout=PAGE_TIMEOUT_MS)
    page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
    page.wait_for_function(f"({JS_PHASE_VIEW})() && ({JS_PHASE_VIEW})().w > 0 && "
                           f"isFinite(({JS_PHASE_VIEW})().x0)", timeout=PAGE_TIMEOUT_MS)
    page.evaluate("() => new Promise(r => requestAnimationFrame(() => "
                  "requestAnimationFrame(r)))")
    return page


@pytest.mark.parametrize("width, height", [(1280, 800), (800, 900), (1920, 1080)])
@pytest.mark.parametrize("units", ["dimensionless", "SI"])
def test_circles_are_circles(browser, server, shots, width, height, units):
    """One pixel is the same length of x and of x' (of x'/omega in SI) in the laid-out
    frame: a slip circle (paper Eq. 7) is drawn round. The unequal scales drew them as
    ellipses 1.7-2.5 times as wide as high. Tolerance 1 %: a pixel of rounding of the
    frame's size in ~400."""
    page = _open(browser, f"{server}?scene=5a&units={units}", width, height)
    try:
        view = page.evaluate(JS_PHASE_VIEW)
        per_px_x = (view["x1"] - view["x0"]) / view["w"]
        per_px_v = (view["y1"] - view["y0"]) / view["scale"] / view["h"]
        assert per_px_x == pytest.approx(per_px_v, rel=0.01)
        if units == "SI":
            assert view["scale"] != 1.0
        page.screenshot(path=str(shots / f"pictures-aspect-{units}-{width}.png"))
    finally:
        page.close()


@pytest.mark.parametrize("width, height", [(800, 900), (1280, 800), (1920, 1080)])
def test_plots_fill_the_window_and_read_from_a_room(browser, server, shots, width, height):
    """The plots use the width they are given and no more: none is cut at the window's
    right edge, and they span at least 80 % of the width right of the sidebar (they were
    540 px whatever the window: at 1920 px 40 % of it stayed empty). Axis labels are at
    least 12 px."""
    page = _open(browser, f"{server}?scene=7c", width, height)
    try:
        ext = page.evaluate(JS_EXTENTS)
        assert ext["rights"], "no plot canvas found"
        left, right = min(ext["lefts"]), max(ext["rights"])
        assert right <= width + 0.5
        assert right - left >= 0.8 * (width - left)
        assert ext["font"] >= 12
        page.screenshot(path=str(shots / f"pictures-fit-{width}.png"), full_page=True)
    finally:
        page.close()

"""On a phone (390 x 844 CSS px) the page is one column that fits the screen's width, opens
on the phase portrait with the controls in a closed drawer, writes no text under 14 px,
and takes touches on a slider's handle over 44 px; the phase portrait keeps its equal
aspect. A desktop window keeps its sidebar beside the plots."""

from __future__ import annotations

import pytest
from uipage import Page

from app.page_style import PHONE_MAX_WIDTH, VIEWPORT

pytestmark = pytest.mark.ui

#: A phone's window in CSS pixels (a common 6.1" phone).
PHONE = {"width": 390, "height": 844}
#: Smallest text [px] on a phone.
MIN_TEXT_PX = 14
#: Smallest touch target [px] of a slider's handle (the usual guideline of 44 x 44).
TOUCH_PX = 44

#: JavaScript: visible elements (shadow roots included) whose own text is smaller than
#: ``px``: [tag, class, text, size].
JS_SMALL_TEXT = """px => {
  const out = [];
  function walk(root) {
    for (const el of root.querySelectorAll("*")) {
      if (el.shadowRoot) walk(el.shadowRoot);
      if (["STYLE", "SCRIPT", "LINK"].includes(el.tagName)) continue;
      let own = "";
      for (const c of el.childNodes) if (c.nodeType === 3) own += c.textContent;
      own = own.trim();
      if (!own) continue;
      const r = el.getBoundingClientRect();
      const cs = getComputedStyle(el);
      if (r.width === 0 || r.height === 0 || cs.visibility === "hidden") continue;
      const size = parseFloat(cs.fontSize);
      if (size < px) out.push([el.tagName, String(el.className), own.slice(0, 40), size]);
    }
  }
  walk(document.body);
  return out;
}"""
#: JavaScript: the right edge of each plot (shadow roots included) and the page's and the
#: main area's widths.
JS_WIDTHS = """() => {
  const main = document.getElementById("main");
  const plots = [];
  (function walk(root) {
    for (const el of root.querySelectorAll("*")) {
      if (el.shadowRoot) walk(el.shadowRoot);
      const r = el.getBoundingClientRect();
      if (el.classList.contains("fie-plot") && r.width > 0) plots.push(r.right);
    }
  })(main);
  return {page: document.scrollingElement.scrollWidth, window: window.innerWidth,
          main: main.scrollWidth, mainClient: main.clientWidth, plots};
}"""
#: JavaScript: the phase portrait's frame [px] and ranges (its BokehJS view).
JS_PHASE_FRAME = """() => {
  const seen = new Set();
  function walk(v) {
    if (v == null || seen.has(v)) return null;
    seen.add(v);
    if (v.frame && v.model.title && v.model.title.text.startsWith("Phase portrait")) {
      const m = v.model;
      return {width: v.frame.bbox.width, height: v.frame.bbox.height,
              dx: m.x_range.end - m.x_range.start, dy: m.y_range.end - m.y_range.start,
              scale: m.aspect_scale};
    }
    if (typeof v.children === "function")
      for (const c of v.children()) { const f = walk(c); if (f) return f; }
    return null;
  }
  for (const r of Bokeh.index.roots) { const f = walk(r); if (f) return f; }
  return null;
}"""
#: JavaScript: whether the point (x, y) of the window falls on ``handle`` (or inside it),
#: through the shadow roots on the way.
JS_HITS = """([handle, x, y]) => {
  let el = document.elementFromPoint(x, y);
  while (el && el.shadowRoot) {
    const inner = el.shadowRoot.elementFromPoint(x, y);
    if (inner == null || inner === el) break;
    el = inner;
  }
  return el != null && (el === handle || handle.contains(el));
}"""


@pytest.fixture(scope="module")
def phone(browser, server):
    p = Page(browser, server, viewport=PHONE)
    yield p
    p.close()


def _drawer(page: Page, show: bool) -> None:
    """Open or close the controls' drawer with the header's toggle."""
    sidebar = page.page.locator("#sidebar")
    if sidebar.is_visible() != show:
        page.page.locator("#sidebar-toggle").click()
    page.page.wait_for_function(
        f"() => !document.getElementById('sidebar').classList.contains('collapsing') && "
        f"document.getElementById('sidebar').classList.contains('show') === {str(show).lower()}")
    page.settle()


def test_the_page_lays_out_at_the_phone_width(phone):
    content = phone.page.locator("meta[name=viewport]").get_attribute("content")
    assert content == VIEWPORT
    assert PHONE["width"] < PHONE_MAX_WIDTH


def test_the_phone_opens_on_the_phase_portrait_with_the_drawer_closed(phone, shots):
    assert not phone.page.locator("#sidebar").is_visible()
    toggle = phone.page.locator("#sidebar-toggle")
    assert toggle.get_attribute("aria-expanded") == "false"
    assert toggle.get_attribute("aria-label") == "Show or hide the controls"
    box = phone.page.locator(".fie-plot-phase").first.bounding_box()
    assert box is not None and box["width"] > 0
    # The whole phase portrait (with its legend) in the first screen.
    assert 0 <= box["y"] and box["y"] + box["height"] <= PHONE["height"], box
    phone.page.screenshot(path=str(shots / "phone-390x844.png"))


def test_no_horizontal_scroll_on_a_phone(phone):
    for show in (False, True):
        _drawer(phone, show)
        w = phone.page.evaluate(JS_WIDTHS)
        assert w["page"] <= w["window"], w
        assert w["main"] <= w["mainClient"], w  # nothing cut at the main area's edge
        assert w["plots"] and max(w["plots"]) <= w["window"], w
    _drawer(phone, False)


def test_text_on_a_phone_is_at_least_14px(phone, shots):
    _drawer(phone, False)
    assert phone.page.evaluate(JS_SMALL_TEXT, MIN_TEXT_PX) == []
    _drawer(phone, True)  # the controls too
    phone.page.screenshot(path=str(shots / "phone-390x844-drawer.png"))
    assert phone.page.evaluate(JS_SMALL_TEXT, MIN_TEXT_PX) == []
    _drawer(phone, False)


def test_slider_handles_take_touches_over_44px(phone):
    _drawer(phone, True)
    handle = phone.page.locator(".fie-w-restitution .noUi-handle").first
    box = handle.bounding_box()
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    # A point just inside each side of a 44 x 44 square centred on the handle.
    reach = TOUCH_PX / 2 - 1
    for dx, dy in ((-reach, 0), (reach, 0), (0, -reach), (0, reach), (0, 0)):
        assert phone.page.evaluate(JS_HITS, [handle.element_handle(), x + dx, y + dy]), (dx, dy)
    _drawer(phone, False)


def test_the_phase_portrait_keeps_equal_aspect_on_a_phone(phone):
    f = phone.page.evaluate(JS_PHASE_FRAME)
    assert f is not None and f["width"] < PHONE["width"]
    # Equal aspect: the same data length per pixel on both axes (times aspect_scale);
    # 2 %: the frame is whole pixels and each range is fitted to them (~1/280 each).
    assert f["dx"] / f["width"] == pytest.approx(f["scale"] * f["dy"] / f["height"], rel=0.02)
    assert phone.errors == []


@pytest.mark.parametrize("size", [(1280, 800), (1920, 1080), (800, 1000)])
def test_a_wider_window_keeps_the_sidebar_beside_the_plots(browser, server, shots, size):
    width, height = size
    p = Page(browser, server, viewport={"width": width, "height": height})
    try:
        sidebar = p.page.locator("#sidebar").bounding_box()
        main = p.page.locator("#main").bounding_box()
        assert p.page.locator("#sidebar").is_visible()
        assert p.page.locator("#sidebar").evaluate("el => getComputedStyle(el).position") \
            == "static"
        assert sidebar["x"] + sidebar["width"] <= main["x"] + 1  # beside, not over
        # Desktop text as before (the readout's 13 px table; phones get 14 px).
        assert p.page.locator(".fie-readout-pane").first.evaluate(
            "el => getComputedStyle(el.shadowRoot.querySelector('.fie-readout')).fontSize"
        ) == "13px"
        p.page.screenshot(path=str(shots / f"phone-desktop-{width}x{height}.png"))
        assert p.errors == []
    finally:
        p.close()

"""Every control of the page is reached by Tab, named, and ringed while it has the focus;
a slider's aria values are the value shown; a box's "?" help opens from the keyboard."""

from __future__ import annotations

import pytest
from playwright.sync_api import expect
from uipage import Page

from app.control_specs import TOOLTIPS
from app.perf import applies

pytestmark = pytest.mark.ui

#: Smallest outline [px] that reads as a focus ring (the page draws 3 px; browsers' own
#: thin rings and Bootstrap's faint shadows are what the page replaced).
RING_PX = 2
#: Tab presses allowed per control before the walk gives up (a control skipped or a trap).
PRESSES_PER_CONTROL = 3

#: JavaScript: numbers every visible control of the header and the sidebar (shadow roots
#: included; the inputs' help icons with ``help``) in ``data-fie-control`` and returns how
#: many there are.
JS_MARK = """help => {
  const css = "button, select, input:not([type=hidden]), a[href], .noUi-handle" +
              (help ? ", .bk-description" : "");
  let n = 0;
  function walk(root) {
    for (const el of root.querySelectorAll("*")) {
      if (el.shadowRoot) walk(el.shadowRoot);
      if (!el.matches(css)) continue;
      const r = el.getBoundingClientRect();
      if (r.width === 0 || r.height === 0) continue;
      el.dataset.fieControl = String(n++);
    }
  }
  walk(document.getElementById("header"));
  walk(document.getElementById("sidebar"));
  return n;
}"""
#: JavaScript: the control with the keyboard's focus (through shadow roots): its number,
#: its accessible name as a screen reader would read it here (aria-label, the element it
#: is labelled by, its label, its text, its title) and its outline.
JS_FOCUSED = """() => {
  let el = document.activeElement;
  while (el && el.shadowRoot && el.shadowRoot.activeElement) el = el.shadowRoot.activeElement;
  if (el == null || el === document.body) return null;
  const label = el.closest("label");
  const by = el.getAttribute("aria-labelledby");
  const named = by ? el.getRootNode().getElementById(by) : null;
  const name = el.getAttribute("aria-label") || (named ? named.textContent : "") ||
    (el.labels && el.labels.length ? el.labels[0].textContent : "") ||
    (label ? label.textContent : "") || el.textContent || el.title || "";
  const cs = getComputedStyle(el);
  return {control: el.dataset.fieControl ?? null, name: name.trim(),
          tag: el.tagName, unnamed_by_bokeh: el.type === "checkbox" ||
            el.classList.contains("bk-dropdown-toggle"), outline: cs.outlineStyle,
          width: parseFloat(cs.outlineWidth), shadow: cs.boxShadow};
}"""


@pytest.fixture(scope="module")
def page(browser, server):
    p = Page(browser, server, viewport={"width": 1280, "height": 800})
    yield p
    p.close()


def test_tab_reaches_every_control_named_and_ringed(page):
    # Without static/a11y.js's patches (app.perf switched off) the help icons are out of
    # reach and a checkbox and a menu's arrow unnamed, as BokehJS draws them.
    help_keys, names = applies("help-keys"), applies("control-names")
    count = page.page.evaluate(JS_MARK, help_keys)
    assert count >= (40 if help_keys else 30)  # the header's two, the sidebar's controls
    page.page.evaluate("() => document.activeElement && document.activeElement.blur()")
    reached: dict[str, dict] = {}
    for _ in range(count * PRESSES_PER_CONTROL):
        page.page.keyboard.press("Tab")
        focused = page.page.evaluate(JS_FOCUSED)
        if focused is None or focused["control"] is None:
            if reached:
                break  # past the sidebar: into the plots
            continue
        reached[focused["control"]] = focused
    missed = sorted(set(map(str, range(count))) - set(reached), key=int)
    assert not missed, f"controls Tab does not reach: {missed}"
    unnamed = [f for f in reached.values()
               if not f["name"] and (names or not f["unnamed_by_bokeh"])]
    assert not unnamed, unnamed
    unringed = [f for f in reached.values()
                if not (f["outline"] != "none" and f["width"] >= RING_PX)]
    assert not unringed, unringed
    assert page.errors == []


def test_the_arrow_beside_pin_is_named(page):
    arrow = page.page.locator(".fie-compare-menu .bk-dropdown-toggle").first
    if not applies("control-names"):  # static/a11y.js's patch switched off (app.perf)
        assert arrow.get_attribute("aria-label") is None  # BokehJS names it nowhere
        return
    assert arrow.get_attribute("aria-label") == "Pin this run: more choices"


def test_aria_values_are_the_value_shown_after_key_presses(page):
    """Five ArrowLeft presses on r = 1 (steps of 0.01) show 0.95; a screen reader is told
    0.95 (noUiSlider alone said 0.9: it rounds to one decimal)."""
    handle = page.page.locator(".fie-w-restitution .noUi-handle").first
    box = page.page.locator(".fie-w-restitution input").first
    assert float(box.input_value()) == 1.0
    handle.focus()
    for _ in range(5):
        handle.press("ArrowLeft")
    expect(box).to_have_value("0.95", timeout=30_000)
    if not applies("slider-aria-values"):  # static/a11y.js's patch switched off (app.perf)
        # noUiSlider's own rounding: one decimal (the defect the patch mends).
        assert len(handle.get_attribute("aria-valuenow").partition(".")[2]) <= 1
        return
    page.page.wait_for_function("h => h.getAttribute('aria-valuenow') === '0.95'",
                                arg=handle.element_handle(), timeout=30_000)
    slider = handle.evaluate("el => el.closest('.noUi-target').noUiSlider.get(true)")
    assert float(handle.get_attribute("aria-valuenow")) == pytest.approx(slider, rel=1e-12)
    assert handle.get_attribute("aria-valuetext") == "0.95"
    low, high = handle.evaluate(
        "el => { const r = el.closest('.noUi-target').noUiSlider.options.range;"
        " return [r.min, r.max].map(v => Array.isArray(v) ? v[0] : v); }")
    # Exact limits (the slider of mu_s starts at 0.005, which one decimal made 0.0).
    assert float(handle.get_attribute("aria-valuemin")) == pytest.approx(low, rel=1e-12)
    assert float(handle.get_attribute("aria-valuemax")) == pytest.approx(high, rel=1e-12)
    mu_s = page.page.locator(".fie-w-mu_s .noUi-handle").first
    start = mu_s.evaluate("el => [].concat(el.closest('.noUi-target').noUiSlider"
                          ".options.range.min)[0]")
    assert start > 0 and float(mu_s.get_attribute("aria-valuemin")) == pytest.approx(start)


#: JavaScript: whether a tooltip (BokehJS's Tooltip, in its shadow root) shows ``needle``.
JS_TOOLTIP_SHOWN = """needle => {
  function walk(root) {
    for (const el of root.querySelectorAll("*")) {
      if (el.shadowRoot && walk(el.shadowRoot)) return true;
      if (el.tagName === "STYLE" || !el.textContent.includes(needle)) continue;
      let host = el;
      while (host.getRootNode().host) host = host.getRootNode().host;
      const r = el.getBoundingClientRect();
      if (host.classList.contains("bk-Tooltip") && r.width > 0 && r.height > 0) return true;
    }
    return false;
  }
  return walk(document);
}"""
#: Milliseconds for a tooltip to show or hide (it follows the key at once; generous for a
#: loaded machine).
TOOLTIP_MS = 5_000


def _shown(page, text: str, shown: bool = True) -> None:
    page.page.wait_for_function(f"t => ({JS_TOOLTIP_SHOWN})(t) === {str(shown).lower()}",
                                arg=text, timeout=TOOLTIP_MS)


def test_help_opens_from_the_keyboard(page):
    help_icon = page.page.locator(".fie-w-clearance .bk-description").first
    if not applies("help-keys"):  # static/a11y.js's patch switched off (app.perf)
        assert help_icon.get_attribute("tabindex") is None  # BokehJS's icon: no key reaches it
        return
    # The tooltip's own words, before the link to the glossary (app.teach.glossary).
    text = TOOLTIPS["clearance"].split("<a ")[0].strip()
    assert help_icon.get_attribute("aria-label") == "Help on clearance x̄"
    assert help_icon.get_attribute("aria-description").startswith(text)
    assert not page.page.evaluate(JS_TOOLTIP_SHOWN, text)
    help_icon.focus()  # as Tab reaches it (test_tab_reaches_every_control_named_and_ringed)
    _shown(page, text)
    page.page.keyboard.press("Enter")  # kept: it stays when the focus moves on
    page.page.keyboard.press("Tab")
    _shown(page, text)
    page.page.keyboard.press("Shift+Tab")
    page.page.keyboard.press("Escape")
    _shown(page, text, shown=False)

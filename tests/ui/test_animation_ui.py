"""The animation's clock is drawn inside its frame, and the animation can be stepped and
scrubbed (in the browser only: nothing goes to the server)."""

from __future__ import annotations

import numpy as np
import pytest
from uipage import Page

pytestmark = pytest.mark.ui

#: JavaScript: the animation time and the clock label (text, y, the figure's y range).
JS_CLOCK = """() => {
  const st = Object.values(window.__fie_anim || {})[0];
  for (const m of Bokeh.documents[0].all_models) {
    if (m.type === "Label" && String(m.text).startsWith("t = ")) {
      let fig = null;
      for (const f of Bokeh.documents[0].all_models) {
        if (f.type === "Figure" && f.center && f.center.includes(m)) fig = f;
      }
      return {t: st ? st.t : null, text: m.text, y: m.y, y_units: m.y_units,
              y0: fig.y_range.start, y1: fig.y_range.end};
    }
  }
  return null;
}"""


def test_animation_steps_and_scrubs_with_its_clock_in_the_frame(browser, server, shots):
    p = Page(browser, f"{server}?scene=5a")  # t_end = 60
    try:
        anim = ".fie-plot-anim"
        p.page.locator(anim).first.scroll_into_view_if_needed()
        p.wait_plots()
        first = p.pixels(anim)
        for _ in range(5):
            p.page.locator(".fie-anim-forward button").first.click()
        p.settle()
        clock = p.page.evaluate(JS_CLOCK)
        # Five steps of t_end / 200 (app.animation.STEPS).
        assert clock["t"] == pytest.approx(5 * 60.0 / 200)
        assert clock["text"] == "t = 1.50 of 60.00"
        assert clock["y_units"] == "data" and clock["y0"] < clock["y"] < clock["y1"]
        assert np.abs(p.pixels(anim) - first).mean() > 0.1  # the mass moved
        p.page.locator(".fie-anim-back button").first.click()
        p.settle()
        assert p.page.evaluate(JS_CLOCK)["t"] == pytest.approx(4 * 60.0 / 200)
        handle = p.page.locator(".fie-anim-scrub .noUi-handle").first
        handle.focus()
        handle.press("End")  # scrub to the end of the run
        p.settle()
        assert p.page.evaluate(JS_CLOCK)["t"] == pytest.approx(60.0)
        p.page.locator(anim).first.screenshot(path=shots / "animation-scrubbed.png")
        assert p.errors == []
    finally:
        p.close()

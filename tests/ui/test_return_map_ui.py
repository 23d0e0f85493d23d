"""The return map in the browser: a release that changes its axes' ticks does not lay the
figure, or the page, out again."""

from __future__ import annotations

import math

import pytest
from uipage import PAGE_TIMEOUT_MS, Page

pytestmark = pytest.mark.ui

#: JavaScript: the return map's frame [px] as the browser laid it out, the size its axes
#: need [px] (BokehJS lays the figure out again when it changes), the decades its x axis
#: spans, and how many full solutions the page has drawn (app.plots_host's counter).
JS_RETURN = """() => {
  const out = {frame: null, axes: null, decades: null, arrived: null};
  function* views(v) { yield v; for (const c of (v.child_views || [])) yield* views(c); }
  for (const m of Bokeh.documents[0].all_models) {
    const title = m.title && m.title.text !== undefined ? String(m.title.text) : "";
    if (title.startsWith("Return map")) {
      out.frame = [m.inner_width, m.inner_height];
      out.decades = Math.log10(m.x_range.end / m.x_range.start);
      for (const root of Object.values(Bokeh.index))
        for (const v of views(root))
          if (v.model === m)
            out.axes = [...m.below, ...m.left].map(a => {
              const size = v.renderer_views.get(a).get_size();
              return size.height;
            });
    }
    if (Array.isArray(m.css_classes) && m.css_classes.includes("fie-solution-arrived"))
      out.arrived = Number(m.text);
  }
  return out;
}"""
#: Drag length [px] of the clearance slider: in scene 7c each drag to the right gives a
#: periodic run (its points within a few percent: half a decade shown), each back a
#: grazing one (several decades).
DRAG_PX = 12


def test_a_release_keeps_the_return_map_s_frame_and_axes(browser, server):
    """The return map's log axes labelled a span under two decades in plain numbers and a
    wider one in powers of ten (taller), and the vertical axis was as wide as its labels:
    on every other release of scene 7c the axes changed size, BokehJS laid the figure out
    again (20-35 ms) and, as the frame lost or got back 4 px, the page, repainting every
    figure once more (9 repaints where 7 did)."""
    p = Page(browser, f"{server}?scene=7c")
    try:
        p.page.locator(".fie-plot-return").first.scroll_into_view_if_needed()
        p.wait_plots()
        p.still()
        seen = []
        for i in range(4):
            before = p.page.evaluate(JS_RETURN)["arrived"]
            p.drag_slider("clearance", DRAG_PX if i % 2 == 0 else -DRAG_PX, steps=4)
            p.page.wait_for_function(f"() => ({JS_RETURN})().arrived > {before}",
                                     timeout=PAGE_TIMEOUT_MS)
            p.still()
            seen.append(p.page.evaluate(JS_RETURN))
        spans = [s["decades"] for s in seen]
        # Spans under and over two decades: both kinds of BokehJS log ticks (else the
        # test shows nothing).
        assert min(spans) < 2.0 < max(spans), spans
        assert all(math.isfinite(s) for s in spans)
        assert len({tuple(s["frame"]) for s in seen}) == 1, seen
        assert len({tuple(s["axes"]) for s in seen}) == 1, seen
        assert p.errors == []
    finally:
        p.close()

"""The readout in the browser: rows wrap instead of being cut, the pane fits its rows
without a gap, and a release that keeps the rows does not move the plots."""

from __future__ import annotations

import pytest
from uipage import Page

pytestmark = pytest.mark.ui

#: JavaScript: for the readout table (in its pane's shadow root): cells whose text is cut
#: (wider than their box, or drawn with an ellipsis), and the gap [px] between the table's
#: bottom and the pane's bottom (negative: rows out of view).
JS_READOUT = """el => {
  const root = el.shadowRoot || el;
  const table = root.querySelector("table.fie-readout");
  const cut = [];
  for (const c of table.querySelectorAll("th, td")) {
    const s = getComputedStyle(c);
    if (c.scrollWidth > c.clientWidth + 1 || s.textOverflow === "ellipsis" &&
        s.overflow === "hidden") cut.push(c.textContent.slice(0, 40));
  }
  const pane = el.getBoundingClientRect(), t = table.getBoundingClientRect();
  return {cut: cut, gap: pane.bottom - t.bottom, rows: table.rows.length};
}"""
#: Largest empty band [px] below the last row: the pane's padding and one spare line
#: (app.explorer.READOUT_SPARE_LINES x READOUT_ROW_PX + READOUT_PAD_PX = 28 px).
MAX_GAP_PX = 32


@pytest.mark.parametrize(("scene", "width"), [("10", 800), ("7c", 1280), ("6a", 800)])
def test_readout_rows_wrap_and_fit(browser, server, shots, scene, width):
    p = Page(browser, f"{server}?scene={scene}")
    try:
        p.page.set_viewport_size({"width": width, "height": 900})
        p.still()  # the readout's rows wrap to the new width
        p.settle()
        p.page.screenshot(path=shots / f"readout-{scene}-{width}.png")
        info = p.page.locator(".fie-readout-pane").first.evaluate(JS_READOUT)
        assert info["cut"] == []
        assert 0 <= info["gap"] <= MAX_GAP_PX, info
        assert p.errors == []
    finally:
        p.close()


def test_release_with_the_same_rows_keeps_the_plots_in_place(browser, server):
    p = Page(browser, f"{server}?scene=7c")
    try:
        phase = p.page.locator(".fie-plot-phase").first
        top = phase.bounding_box()["y"]
        for value in ("0.071", "0.072", "0.0705"):
            readout = p.text(".fie-readout-pane")
            box = p.page.locator(".fie-w-belt_speed input").first
            box.fill(value)
            box.press("Enter")
            p.wait_text_change(".fie-readout-pane", readout)
            assert phase.bounding_box()["y"] == top
    finally:
        p.close()


#: JavaScript: the opacity of the readout's table (greyed while a drag previews).
JS_OPACITY = """el => {
  const root = el.shadowRoot || el;
  return Number(getComputedStyle(root.querySelector("table.fie-readout")).opacity);
}"""


def test_a_drag_s_preview_is_marked_in_the_readout(browser, server, shots):
    """While r was dragged the phase portrait drew the new value's draft but the readout
    showed the old run's rows, unmarked. They are greyed under "Preview of r —
    release to solve" (in the line the readout keeps spare: the plots do not move), and
    the release's run replaces them."""
    p = Page(browser, f"{server}?scene=5a", viewport={"width": 1280, "height": 800})
    try:
        pane = p.page.locator(".fie-readout-pane").first
        phase = p.page.locator(".fie-plot-phase").first
        top = phase.bounding_box()["y"]
        assert pane.evaluate(JS_OPACITY) == 1.0
        handle = p.page.locator(".fie-w-restitution .noUi-handle").first
        box = handle.bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        p.page.mouse.move(x, y)
        p.page.mouse.down()
        p.page.mouse.move(x - 80, y, steps=8)  # r = 1 is the right end: left is lower
        shown = p.wait_text(".fie-readout-pane", lambda t: "release to solve" in t,
                            "the readout never marked the drag's preview")
        assert "Preview of r — release to solve" in shown and "x*" not in shown  # r = 1
        assert pane.evaluate(JS_OPACITY) < 0.6
        assert phase.bounding_box()["y"] == top
        p.page.screenshot(path=shots / "readout-drag-preview.png")
        p.page.mouse.up()
        shown = p.wait_text(".fie-readout-pane",
                            lambda t: "Preview" not in t and "Not shown yet" not in t,
                            "the release's run never replaced the preview")
        assert "x*" in shown  # r < 1: Eq. 35's x*
        assert pane.evaluate(JS_OPACITY) == 1.0
        assert p.errors == []
    finally:
        p.close()

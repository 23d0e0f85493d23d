"""The bifurcation diagram in a real browser: it appears, it is drawn, a tap loads its value.

The time from the click on "Bifurcation diagram" to the whole diagram of 1,000 belt speeds
on the page is printed; its target (2 s) is tracked by ``benchmarks/bifurcation_page.py``,
not asserted here.
"""

from __future__ import annotations

import time

import numpy as np
import pytest
from playwright.sync_api import expect
from uipage import Page, count_color

from app.bifurcation import LABEL_COLORS

pytestmark = pytest.mark.ui

#: A generous bound [s]: the page must not hang. On this shared 2-core machine at load
#: average 8.5 the click took 4.4-11 s (benchmarks/results/bifurcation_page_2026-11-23.md),
#: nearly all of it building, sending and laying out the card (the sweep: < 0.2 s).
APPEARS_WITHIN_S = 20.0
#: Pixels of the periodic colour a drawn diagram of 1,000 points leaves at least (3 px
#: markers; an empty figure has none).
MIN_DIAGRAM_PIXELS = 300


def open_diagram(p: Page) -> float:
    """Click the sweep button; seconds until the diagram's 1,000 values are drawn."""
    start = time.perf_counter()
    p.page.locator(".fie-open-sweeps button").first.click()
    p.wait_text(".fie-bif-status", lambda text: "1000 of 1000" in text,
                "the diagram was not drawn", 60_000)
    p.page.wait_for_function("() => Bokeh.documents[0].is_idle")
    p.settle()
    return time.perf_counter() - start


def test_diagram_of_scene_5a_appears_and_a_tap_loads_the_belt_speed(browser, server, shots):
    p = Page(browser, server + "?scene=5a")
    try:
        seconds = open_diagram(p)
        print(f"\nbifurcation diagram, scene 5a, 1000 belt speeds: {seconds:.2f} s "
              "from the click to the drawn diagram")
        assert seconds < APPEARS_WITHIN_S
        card = p.page.locator(".fie-bifurcation").first
        card.scroll_into_view_if_needed()
        p.settle()
        card.screenshot(path=shots / "bifurcation-5a.png")
        assert count_color(p.pixels(".fie-bifurcation"), LABEL_COLORS["periodic"]) \
            > MIN_DIAGRAM_PIXELS

        lo = float(p.page.locator(".fie-bif-lo input").first.input_value())
        hi = float(p.page.locator(".fie-bif-hi input").first.input_value())
        box = p.page.locator(".fie-w-belt_speed input").first
        before = box.input_value()
        canvas = card.locator("canvas").first
        bb = canvas.bounding_box()
        p.page.mouse.click(bb["x"] + 0.35 * bb["width"], bb["y"] + 0.5 * bb["height"])
        # The tap loads a belt speed.
        expect(box).not_to_have_value(before, timeout=20_000)
        loaded = float(box.input_value())
        grid = np.linspace(lo, hi, 1000)
        # The box shows the value to its display precision (4 significant digits).
        assert np.min(np.abs(grid - loaded)) <= 1e-3 * abs(loaded)
        # A third of the way across the canvas (frame and axis) lies in the range's
        # first half.
        assert lo < loaded < lo + 0.5 * (hi - lo)
        p.page.wait_for_function("() => Bokeh.documents[0].is_idle")
        p.settle()
        card.screenshot(path=shots / "bifurcation-5a-tapped.png")
        assert not p.errors, p.errors
    finally:
        p.close()

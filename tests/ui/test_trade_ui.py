"""'Measure the trade' in the browser: every method at every preset, timed now and compared
with a reference, and the switch model's change of verdict at scene 10 shown as such."""

from __future__ import annotations

import pytest
from uipage import Page

pytestmark = pytest.mark.ui


def test_measure_the_trade_for_the_run_on_screen(browser, server, shots):
    p = Page(browser, f"{server}?scene=10")
    try:
        assert not p.page.locator(".fie-trade-pane").first.is_visible()
        p.page.locator(".fie-measure button").first.click()
        p.page.locator(".fie-trade-pane").first.wait_for(state="visible", timeout=120_000)
        p.settle()
        p.page.screenshot(path=shots / "trade-10.png")
        rows = p.page.locator(".fie-trade tr").all_inner_texts()[1:]
        cells = [r.split("\t") for r in rows]
        assert [(c[0], c[1]) for c in cells] == [
            (m, a) for m in ("exact", "event", "switch") for a in ("draft", "standard",
                                                                  "precise")]
        assert all(c[2].endswith("ms") for c in cells)
        # Scene 10 grazes the stop; the switch model at draft calls it periodic, and says so.
        switch_draft = cells[6]
        assert switch_draft[4] == "periodic" and "verdict differs" in switch_draft[5]
        assert cells[2][4] == "grazing"  # the exact method at precise
        # (The deep text puts a space after each element: "switch : The paper's ...".)
        text = p.text(".fie-trade-pane").replace(" :", ":")
        assert "switch: The paper's switch model" in text
        # Another run: the table no longer describes the picture and goes.
        box = p.page.locator(".fie-w-belt_speed input").first
        box.fill("0.06")
        box.press("Enter")
        p.page.locator(".fie-trade-pane").first.wait_for(state="hidden", timeout=30_000)
        assert p.errors == []
    finally:
        p.close()

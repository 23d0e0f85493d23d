"""A deformable stop's contact law is chosen in the page (paper / passive), said in the
readout, explained in a tooltip and kept in the permalink."""

from __future__ import annotations

import pytest
from playwright.sync_api import TimeoutError as PlaywrightTimeout
from uipage import Page

pytestmark = pytest.mark.ui


def _law_row(p: Page) -> str:
    text = p.text(".fie-readout-pane")
    return text.split("Contact law", 1)[1].split("Status")[0].split("Solve")[0]


def _wait_for_url(p: Page, part: str, timeout_s: float = 30.0) -> str:
    try:
        p.page.wait_for_function("part => location.href.includes(part)", arg=part,
                                 timeout=timeout_s * 1000)
    except PlaywrightTimeout:
        raise AssertionError(f"the address never had {part!r}: {p.page.url}") from None
    return p.page.url


def test_contact_law_is_chosen_said_and_kept_in_the_link(browser, server, shots):
    p = Page(browser, server + "?scene=10")
    try:
        group = p.page.locator(".fie-contact-law").first
        assert group.is_visible()
        assert "paper's reading" in _law_row(p)
        assert group.locator("select").first.input_value() == "paper"
        # The tooltip says what each reading means.
        group.locator(".bk-description").first.hover()
        tip = p.page.locator(".bk-tooltip-content", has_text="no closed overlap program").first
        tip.wait_for(state="visible", timeout=5_000)
        assert "reproduces Fig. 2b" in tip.inner_text()
        readout = p.text(".fie-readout-pane")
        group.locator("select").first.select_option("passive")
        p.wait_text_change(".fie-readout-pane", readout)
        p.page.screenshot(path=shots / "contact-law-passive.png")
        assert "passive reading" in _law_row(p)
        url = _wait_for_url(p, "law=passive")
        # Resetting to the figure returns to the paper's reading (the scenes use it).
        readout = p.text(".fie-readout-pane")
        p.page.locator(".fie-reset button").first.click()
        p.wait_text_change(".fie-readout-pane", readout)
        assert "paper's reading" in _law_row(p)
        assert group.locator("select").first.input_value() == "paper"
        assert p.errors == []
    finally:
        p.close()
    # The permalink opens the same run: the passive law, selected and said.
    q = Page(browser, url)
    try:
        assert "passive reading" in _law_row(q)
        assert q.page.locator(".fie-contact-law select").first.input_value() == "passive"
        assert q.errors == []
    finally:
        q.close()

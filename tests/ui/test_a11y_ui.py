"""Every slider has an accessible name that says which parameter it moves, and the keyboard
moves it in steps that cross its range in about a hundred presses (five per PageUp)."""

from __future__ import annotations

import re

import pytest
from playwright.sync_api import expect
from uipage import Page

from app.perf import applies

pytestmark = pytest.mark.ui


@pytest.fixture(scope="module")
def page(browser, server):
    p = Page(browser, server + "?scene=10&all=true")  # a deformable stop: its sliders too
    yield p
    p.close()


def test_every_slider_has_an_accessible_name(page):
    from app.explorer import SLIDERS

    sliders = page.page.get_by_role("slider")
    named = page.page.get_by_role("slider", name=re.compile(r"\w"))
    count = sliders.count()
    # The deformable stop's, the friction, start and horizon sliders, and the animation's.
    assert count >= 12
    if not applies("slider-handle-names"):  # static/a11y.js switched off (app.perf)
        assert named.count() == 0
        return
    assert named.count() == count
    shown = [label for name, (label, _) in SLIDERS.items()
             if page.page.locator(f".fie-w-{name}").first.is_visible()]
    assert "compression stiffness k_c0/k" in shown and "restitution r" not in shown
    for label in shown:
        assert page.page.get_by_role("slider", name=label, exact=True).count() == 1, label


def test_a_named_slider_steps_by_keyboard(page):
    handle = page.page.locator(".fie-w-mu_s .noUi-handle").first

    def value() -> float:
        return float(handle.evaluate("el => el.closest('.noUi-target').noUiSlider.get(true)"))

    low, high = (float(handle.get_attribute(a)) for a in ("aria-valuemin", "aria-valuemax"))
    readout = page.text(".fie-readout-pane")
    start = value()
    handle.focus()
    handle.press("ArrowLeft")
    step = start - value()
    # About a hundred presses per range: steps are 1, 2 or 5 times a power of ten.
    assert step > 0 and 50 <= (high - low) / step <= 250
    handle.press("PageDown")
    assert start - step - value() == pytest.approx(5 * step, rel=1e-6)
    # A key press is a release: the page solves the new value. Two presses are two
    # releases, and the readout may change first with the answer to the first one: the
    # box must come to the slider's value, not hold it at once.
    page.wait_text_change(".fie-readout-pane", readout)
    expect(page.page.locator(".fie-w-mu_s input").first).to_have_value(
        f"{value():.6g}", timeout=30_000)
    assert page.errors == []

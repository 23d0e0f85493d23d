"""Typed entries answer in the browser: a refused value is said next to its box (in red,
until corrected) and the box shows the value in use again; a coupled bound says what it
moved; the overlap program is a visible toggle; the reset button returns to the figure;
every box has a tooltip with its range; the slider's arrow keys cross its range in about a
hundred presses."""

from __future__ import annotations

import pytest
from playwright.sync_api import expect
from uipage import Page

pytestmark = pytest.mark.ui

#: The red of a refusal's message (widgets.MESSAGE_CSS, #a61b0f).
RED_TEXT = "rgb(166, 27, 15)"


@pytest.fixture(scope="module")
def page(browser, server):
    p = Page(browser, server + "?scene=5a")
    yield p
    p.close()


def _type(p: Page, name: str, text: str) -> None:
    box = p.page.locator(f".fie-w-{name} input").first
    box.fill(text)
    box.press("Enter")


def _message(p: Page, name: str) -> str:
    loc = p.page.locator(f".fie-w-{name} .fie-input-message").first
    loc.wait_for(state="visible", timeout=30_000)
    return p.text(f".fie-w-{name} .fie-input-message")


#: (box, typed text, what the message must say: the parameter, its range, the value).
REFUSED = [
    ("mu_k", "0.5", "mu_k must lie in [0, 0.3]; got 0.5"),
    ("mu_s", "0", "mu_s must lie in [0.005, 5]; got 0"),
    ("mu_s", "-0.2", "mu_s must lie in"),
    ("restitution", "1.5", "restitution must lie in [0, 1]; got 1.5"),
    ("belt_speed", "1e6", "belt_speed must lie in [0, 10]; got 1e+06"),
    ("t_end", "0", "t_end must lie in [0.1, 5000]; got 0"),
    ("u_s", "0", "u_s must lie in [1e-06, 100]; got 0"),
    ("belt_speed", "abc", "belt_speed must be a number; got 'abc'"),
]


@pytest.mark.parametrize(("name", "text", "said"), REFUSED,
                         ids=[f"{n}={t}" for n, t, _ in REFUSED])
def test_refused_entry_is_said_and_the_value_in_use_shown(page, shots, name, text, said):
    """A refused entry stayed in its box, red ("abc", or an empty box), while the page ran
    with the value before it: the box now shows that value again, the message says what
    was refused and which value stays."""
    readout = page.text(".fie-readout-pane")
    box = page.page.locator(f".fie-w-{name} input").first
    in_use = box.input_value()
    _type(page, name, text)
    message = _message(page, name)
    page.settle()
    page.page.screenshot(path=shots / f"refused-{name}-{text}.png")
    assert said in message and f"the value in use stays {in_use}" in message
    color = page.page.locator(f".fie-w-{name} .fie-msg").first.evaluate(
        "el => getComputedStyle(el).color")
    assert color == RED_TEXT
    expect(box).to_have_value(in_use, timeout=30_000)
    # Nothing was applied, and the message stays after another change.
    assert page.text(".fie-readout-pane").split("Solve")[0] == readout.split("Solve")[0]
    other = "x0" if name != "x0" else "v0"
    _type(page, other, "-0.01")
    page.wait_text_change(".fie-readout-pane", readout)
    assert "the value in use stays" in _message(page, name)
    assert box.input_value() == in_use
    # The reset clears it.
    page.page.locator(".fie-reset button").first.click()
    page.page.wait_for_function("() => Bokeh.documents[0].is_idle")
    page.page.locator(f".fie-w-{name} .fie-input-message").first.wait_for(
        state="hidden", timeout=30_000)
    _wait_for_text(page, ".fie-caption", "Fig. 5a")
    assert page.errors == []


def _wait_for_text(p: Page, css: str, text: str, timeout_s: float = 30.0) -> None:
    p.wait_text(css, lambda shown: text in shown, f"{css} never showed {text!r}",
                timeout_s * 1000)


def test_valid_entry_clears_the_refusal(page):
    _type(page, "restitution", "2")
    _message(page, "restitution")
    readout = page.text(".fie-readout-pane")
    _type(page, "restitution", "0.5")
    page.wait_text_change(".fie-readout-pane", readout)
    page.page.locator(".fie-w-restitution .fie-input-message").first.wait_for(
        state="hidden", timeout=30_000)
    assert "x*" in page.text(".fie-readout-pane")  # r < 1: the readout shows Eq. 35's x*
    page.page.locator(".fie-reset button").first.click()


def test_coupled_bound_says_what_it_did(page, shots):
    page.page.locator(".fie-reset button").first.click()
    page.page.wait_for_function("() => Bokeh.documents[0].is_idle")
    _type(page, "mu_s", "0.1")  # below mu_k = 0.2
    note = _message(page, "mu_k")
    page.page.screenshot(path=shots / "coupled-mu_k.png")
    assert "mu_k lowered from 0.2 to 0.1 to stay ≤ mu_s" in note
    assert page.page.locator(".fie-w-mu_k input").first.input_value() == "0.1"
    page.page.locator(".fie-reset button").first.click()
    page.page.locator(".fie-w-mu_k .fie-input-message").first.wait_for(
        state="hidden", timeout=30_000)
    _wait_for_value(page, "mu_k", "0.2")


def _wait_for_value(p: Page, name: str, text: str, timeout_s: float = 30.0) -> None:
    expect(p.page.locator(f".fie-w-{name} input").first).to_have_value(
        text, timeout=timeout_s * 1000)


def test_every_box_has_a_tooltip_with_its_range(page):
    icon = page.page.locator(".fie-w-restitution .bk-description").first
    icon.hover()
    tip = page.page.locator(".bk-tooltip-content", has_text="rebound speed").first
    tip.wait_for(state="visible", timeout=5_000)
    text = tip.inner_text()
    assert "rebound speed" in text and "Allowed: 0 to 1" in text
    assert page.page.locator(".fie-w-restitution input").first.evaluate(
        "el => el.labels.length && el.labels[0].textContent") .startswith("restitution r")


def test_overlap_program_is_a_visible_toggle(page, shots):
    from app.scenes import SCENES
    old = page.text(".fie-caption")
    page.page.locator(".fie-scene select").select_option(label=SCENES["2b"].title)
    page.wait_text_change(".fie-caption", old)
    toggle = page.page.locator(".fie-program input").first
    assert toggle.is_visible() and toggle.is_checked()
    assert "overlap program" in page.text(".fie-program")
    page.page.screenshot(path=shots / "program-toggle.png")
    # Leaving it: the oscillator against the same stop.
    readout = page.text(".fie-readout-pane")
    toggle.uncheck()
    page.wait_text_change(".fie-readout-pane", readout)
    assert page.page.locator(".fie-plot-phase").first.is_visible()
    toggle.check()
    page.page.wait_for_function("() => Bokeh.documents[0].is_idle")
    page.page.locator(".fie-plot-phase").first.wait_for(state="hidden", timeout=30_000)
    # A rigid stop ends the program (it drives a deformable stop only) and hides the toggle.
    page.page.locator(".fie-stop-type button", has_text="rigid").first.click()
    page.page.locator(".fie-plot-phase").first.wait_for(state="visible", timeout=30_000)
    assert not page.page.locator(".fie-program").first.is_visible()
    page.page.locator(".fie-stop-type button", has_text="hysteretic").first.click()
    page.page.locator(".fie-program").first.wait_for(state="visible", timeout=30_000)
    assert not page.page.locator(".fie-program input").first.is_checked()
    assert page.page.locator(".fie-plot-phase").first.is_visible()
    assert page.errors == []


@pytest.mark.parametrize("name", ["belt_speed", "mu_s", "t_end", "k_c0"])
def test_arrow_keys_cross_the_slider_in_about_100_presses(page, name):
    if name == "k_c0":
        old = page.text(".fie-caption")
        from app.scenes import SCENES
        page.page.locator(".fie-scene select").select_option(label=SCENES["10"].title)
        page.wait_text_change(".fie-caption", old)
    handle = page.page.locator(f".fie-w-{name} .noUi-handle").first

    def value() -> float:
        return float(handle.evaluate("el => el.closest('.noUi-target').noUiSlider.get(true)"))

    low = float(handle.get_attribute("aria-valuemin"))
    high = float(handle.get_attribute("aria-valuemax"))
    start = value()
    handle.focus()
    ring = handle.evaluate("el => getComputedStyle(el).outlineStyle + ' ' + "
                           "getComputedStyle(el).outlineWidth")
    assert ring.startswith("solid") and not ring.endswith(" 0px")
    key = "ArrowRight" if start < (low + high) / 2 else "ArrowLeft"
    handle.press(key)
    step = abs(value() - start)
    # About a hundred presses: steps are 1, 2 or 5 times a power of ten (between 50 and
    # 250 presses per range).
    assert step > 0 and 50 <= (high - low) / step <= 250
    # The arrow's value goes to the server, which answers with the solve it started: the
    # page settles before the next key (in one CI run without the perf patches, a PageUp
    # pressed while that answer was on its way read no change).
    page.page.wait_for_function("() => Bokeh.documents[0].is_idle")
    before = value()
    handle.press("PageUp" if key == "ArrowRight" else "PageDown")
    assert abs(value() - before) >= 4.9 * step
    page.page.locator(".fie-reset button").first.click()

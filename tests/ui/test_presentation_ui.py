"""Presentation mode and figures for slides in a real browser: the plots fill a projector's
screen (1920x1080 and 1280x720) in one large plot or a 2x2 grid, the sidebar collapsed, the
theory's points named as in the paper; a figure's save button downloads an SVG or a 3x PNG
named after the scene, with a caption line that states the scene and its parameters."""

from __future__ import annotations

import io

import pytest
from uipage import JS_READY, PAGE_TIMEOUT_MS, Page

from app.presentation import PNG_SCALE

pytestmark = pytest.mark.ui

#: Projector screens.
SCREENS = {"1080p": {"width": 1920, "height": 1080}, "720p": {"width": 1280, "height": 720}}
#: Share of the screen's height the one large plot fills at least (the rest: the header,
#: the scene's title, the legend).
LARGE_FILL = 0.6
#: Slack [px] of a plot's bottom edge below the screen's (a margin's rounding).
EDGE_PX = 4
#: The text field of the theory points' labels: the paper's names in presentation mode.
JS_LABEL_FIELD = """() => {
  const doc = Bokeh.documents[0];
  const sets = [...doc.all_models].filter(m => m.type === "LabelSet");
  return sets.map(m => m.text.field);
}"""


def _open(browser, url: str, size: dict) -> Page:
    p = Page.__new__(Page)
    p.page = browser.new_page(viewport=size, accept_downloads=True)
    p.errors = []
    p.page.on("console", p._console)
    p.page.on("pageerror", lambda exc: p.errors.append(f"pageerror: {exc}"))
    p.page.goto(url, timeout=PAGE_TIMEOUT_MS)
    p.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
    p.page.wait_for_timeout(1000)  # the layout settles once the plots are filled
    p.settle()
    return p


def _shown_plots(p: Page) -> dict[str, dict]:
    out = {}
    for name in ("phase", "time", "anim", "force", "loop", "friction", "energy", "map"):
        loc = p.page.locator(f".fie-plot-{name}").first
        if loc.count() and loc.is_visible():
            out[name] = loc.bounding_box()
    return out


@pytest.mark.parametrize("screen", list(SCREENS))
def test_one_large_plot_fills_the_screen(browser, server, shots, screen):
    size = SCREENS[screen]
    p = _open(browser, server + "?scene=5a&present=1", size)
    try:
        p.page.screenshot(path=shots / f"present-large-{screen}.png")
        assert not p.page.locator("#sidebar").first.is_visible()
        plots = _shown_plots(p)
        assert list(plots) == ["phase"]
        box = plots["phase"]
        assert box["height"] >= LARGE_FILL * size["height"]
        assert box["y"] + box["height"] <= size["height"] + EDGE_PX
        assert box["width"] >= 0.9 * size["width"]  # no sidebar, no width cap
        assert p.page.evaluate(JS_LABEL_FIELD) == ["paper"]
        assert not p.page.locator(".fie-readout-pane").first.is_visible()
        assert p.errors == []
    finally:
        p.close()


@pytest.mark.parametrize("screen", list(SCREENS))
def test_two_by_two_from_the_menu_and_back(browser, server, shots, screen):
    size = SCREENS[screen]
    p = _open(browser, server + "?scene=10", size)
    try:
        assert p.page.locator("#sidebar").first.is_visible()
        p.page.locator(".fie-compare-menu button").nth(1).click()
        p.page.get_by_text("Presentation: 2×2 plots").first.click()
        p.page.wait_for_function("() => location.search.includes('present=4')")
        p.page.wait_for_function("() => document.body.classList.contains('fie-present-4')")
        p.page.wait_for_timeout(1000)
        p.settle()
        p.page.screenshot(path=shots / f"present-grid-{screen}.png")
        plots = _shown_plots(p)
        assert list(plots) == ["phase", "time", "force", "loop"]
        for box in plots.values():
            assert box["y"] + box["height"] <= size["height"] + EDGE_PX
            assert box["width"] >= 0.4 * size["width"]
        # Two rows of two.
        assert len({round(b["y"]) for b in plots.values()}) == 2
        assert p.page.evaluate(JS_LABEL_FIELD) == ["paper"]
        # Leave it (the menu is in the collapsed sidebar: its address does it too).
        p.page.goto(p.page.url.replace("present=4", "present=0"))
        p.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
        p.settle()
        assert p.page.locator("#sidebar").first.is_visible()
        assert p.page.evaluate(JS_LABEL_FIELD) == ["name"]
        assert p.errors == []
    finally:
        p.close()


def _save(p: Page, plot: str):
    with p.page.expect_download(timeout=30_000) as info:
        p.page.locator(f".fie-plot-{plot} .bk-tool-icon-save").first.click()
    download = info.value
    return download.suggested_filename, open(download.path(), "rb").read()


def test_svg_and_png_for_slides_name_the_scene(browser, server, shots):
    from PIL import Image

    p = _open(browser, server + "?scene=7c", SCREENS["1080p"])
    try:
        p.page.locator(".fie-compare-menu button").nth(1).click()
        p.page.get_by_text("Figures for slides: SVG").first.click()
        p.page.wait_for_function("() => location.search.includes('slides=svg')")
        p.page.wait_for_timeout(500)
        name, data = _save(p, "phase")
        assert name == "fie_7c_phase.svg"
        svg = data.decode()
        assert svg.startswith("<svg")
        assert "Fig. 7c, rigid stop: v = 0.07, x_bar = 0.24, r = 0.3" in svg
        (shots / name).write_bytes(data)
        # PNG at 3x: the file has three pixels per CSS pixel of the figure.
        q = _open(browser, p.page.url.replace("slides=svg", "slides=png"), SCREENS["1080p"])
        try:
            name, data = _save(q, "phase")
            assert name == "fie_7c_phase.png"
            width = Image.open(io.BytesIO(data)).size[0]
            pane = q.page.locator(".fie-plot-phase").first.bounding_box()["width"]
            assert 0.85 * pane <= width / PNG_SCALE <= pane
            (shots / name).write_bytes(data)
            assert q.errors == []
        finally:
            q.close()
        assert p.errors == []
    finally:
        p.close()

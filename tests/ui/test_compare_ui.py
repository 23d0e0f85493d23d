"""Pinned runs in a real browser: a ghost stays drawn while the parameters change, pins go
one by one or all at once, the permalink brings them back, and a preset loads one of the
paper's pairs."""

from __future__ import annotations

import re

import pytest
from uipage import Page, count_color

from app.compare import GHOST_STYLE, PIN_COLORS

pytestmark = pytest.mark.ui

#: The first pin's colour as painted: its line alpha over the white plot area.
GHOST = "#" + "".join(
    f"{round(GHOST_STYLE['line_alpha'] * int(PIN_COLORS[0][i:i + 2], 16) + (1 - GHOST_STYLE['line_alpha']) * 255):02x}"  # noqa: E501
    for i in (1, 3, 5))
#: Tolerance per channel [0-255]: anti-aliased line edges.
GHOST_TOL = 24
#: Ghost pixels a drawn pin adds at least to the time histories (a dashed 2 px line across
#: some 1000 px). A page without a pin has a few pixels near the colour too (anti-aliased
#: edges of the black curve over the slip band): counts are compared with that baseline.
MIN_GHOST_PIXELS = 150


def _menu(p: Page, text: str) -> None:
    """Open the split button's menu and pick the entry that starts with ``text``."""
    p.page.locator(".fie-compare-menu button").nth(1).click()
    p.page.get_by_text(text).first.click()


def _pin(p: Page) -> None:
    p.page.locator(".fie-compare-menu button").first.click()


def _wait_readout(p: Page, words: str, present: bool = True) -> str:
    try:
        text = p.wait_text(".fie-readout-pane", lambda text: (words in text) == present,
                           f"readout {'lacks' if present else 'still has'} {words!r}")
    except AssertionError as exc:
        alert = p.text(".fie-alert") if p.page.locator(".fie-alert").count() else ""
        raise AssertionError(f"{exc}\nalert: {alert or '(none)'}") from None
    p.page.wait_for_function("() => Bokeh.documents[0].is_idle")
    p.settle()
    return text


#: The comparison table's restitution row (a cell may hold "first / last").
RESTITUTION_ROW = "restitution, first / last contact"


def _cells(text: str, row: str) -> list[str]:
    """The cells of the comparison table's ``row`` in the readout's text."""
    rest = text.split(row)[1]
    return re.findall(r"[-\d.e]+(?: / [-\d.e]+)?|—", rest)


def _ghost_pixels(p: Page) -> int:
    return count_color(p.pixels(".fie-plot-time"), GHOST, GHOST_TOL)


def _set(p: Page, name: str, value: str) -> None:
    box = p.page.locator(f".fie-w-{name} input").first
    box.fill(value)
    box.press("Enter")


def test_pin_change_unpin_and_permalink(browser, server, shots):
    p = Page(browser, server + "?scene=5a")
    try:
        baseline = _ghost_pixels(p)
        _pin(p)
        text = _wait_readout(p, "compared")
        assert "5a: same parameters" in text
        # (Its ghost lies under the current run, drawn on top: it shows once they differ.)
        # A new restitution: the ghost stays, the current run differs (the table says how).
        _set(p, "restitution", "0.5")
        text = _wait_readout(p, "5a: r 1")
        assert _ghost_pixels(p) > baseline + MIN_GHOST_PIXELS
        row = _cells(text, RESTITUTION_ROW)
        assert float(row[0]) == pytest.approx(0.5, rel=1e-9)  # this run: Newton's r
        assert float(row[1]) == pytest.approx(1.0, rel=1e-9)  # the pinned elastic run
        p.page.screenshot(path=shots / "compare-pinned.png", full_page=True)
        # A second pin, then the permalink round trip: both pins come back, solved again.
        _pin(p)
        _wait_readout(p, "custom: same parameters")
        p.page.wait_for_function("() => location.search.includes('pins=5a%7Ccustom')")
        q = Page(browser, p.page.url)
        try:
            text = _wait_readout(q, "custom: same parameters")
            assert "5a: r 1" in text
            assert _ghost_pixels(q) > baseline + MIN_GHOST_PIXELS
            assert q.errors == []
        finally:
            q.close()
        # Unpin the first: the elastic ghost goes, the second pin stays.
        _menu(p, "Unpin 1")
        text = _wait_readout(p, "5a: r 1", present=False)
        assert "custom: same parameters" in text
        assert _ghost_pixels(p) < baseline + MIN_GHOST_PIXELS / 3
        _menu(p, "Unpin all")
        _wait_readout(p, "compared", present=False)
        p.page.wait_for_function("() => !location.search.includes('pins=5a')")
        assert p.errors == []
    finally:
        p.close()


def test_preset_7c_vs_10(browser, server, shots):
    p = Page(browser, server + "?scene=10")
    try:
        baseline = _ghost_pixels(p)
        _menu(p, "Compare 7c vs 10")
        text = _wait_readout(p, "7c: stop rigid")
        assert "Fig. 10" in p.text(".fie-caption")
        # The pinned rigid stop's restitution is Newton's r = 0.3 of scene 7c.
        row = _cells(text, RESTITUTION_ROW)
        assert row[0] == "0.399 / 0.969"  # the deformable stop's first and last contact
        assert float(row[1]) == pytest.approx(0.3, rel=1e-9)
        assert _ghost_pixels(p) > baseline + MIN_GHOST_PIXELS
        # 7c's impulses are not drawn on 10's axis of contact force.
        force = count_color(p.pixels(".fie-plot-force"), GHOST, GHOST_TOL)
        assert force < MIN_GHOST_PIXELS / 3, force
        p.page.screenshot(path=shots / "compare-7c-vs-10.png", full_page=True)
        assert p.errors == []
    finally:
        p.close()


#: JavaScript: per figure drawing a ghost of the first pin, whether its ranges (as the
#: browser fitted them) hold every finite point of that ghost.
JS_GHOST_IN_VIEW = """color => {
  const doc = Bokeh.documents[0];
  const out = {};
  for (const fig of [...doc.all_models].filter(m => m.type === "Figure")) {
    for (const r of fig.renderers) {
      const g = r.glyph;
      // A scalar colour is stored as a value spec: {value: "#..."}.
      const c = g == null ? null : g.line_color;
      if (g == null || g.type !== "Line" || (c && c.value !== undefined ? c.value : c) !== color)
        continue;
      const data = r.data_source.data;
      const fin = a => a.filter(Number.isFinite);
      const xs = fin([...data[g.x.field]]), ys = fin([...data[g.y.field]]);
      if (xs.length === 0) continue;  // nothing of this run on that figure (no contact force)
      const inside = (rng, a) => a.length > 0 && rng.start <= Math.min(...a)
        && Math.max(...a) <= rng.end;
      out[fig.title.text] = inside(fig.x_range, xs) && inside(fig.y_range, ys);
    }
  }
  return out;
}"""


def test_a_far_off_pin_is_not_clipped(browser, server, shots):
    # Scene 5a beside a run three times its size (FAR_PIN of tests/app/test_compare.py).
    p = Page(browser, server + "?scene=5a&pins=5a,us=3.0,xbar=2.0,v=0.3,tend=120.0")
    try:
        _wait_readout(p, "compared")
        p.still()  # the portrait's ranges are fitted in a paint
        shown = p.page.evaluate(JS_GHOST_IN_VIEW, PIN_COLORS[0])
        assert set(shown) >= {"Phase portrait (x, x′)", "Displacement x(t)",
                              "Velocity x′(t)"}, shown
        assert all(shown.values()), shown
        p.page.screenshot(path=shots / "compare-far-off-pin.png", full_page=True)
        assert p.errors == []
    finally:
        p.close()


#: JavaScript: the contact-force figure's y range, the largest impulse of the run's own stems
#: and the texts of its titles.
JS_FORCE_AXIS = """() => {
  const doc = Bokeh.documents[0];
  const fig = [...doc.all_models].find(m => m.type === "Figure"
                                            && m.title.text.startsWith("Contact force"));
  const stems = fig.renderers.find(r => r.glyph.type === "Segment").data_source.data;
  return {end: fig.y_range.end, j: Math.max(...stems.j), title: fig.title.text};
}"""


def test_a_deformable_pin_does_not_flatten_rigid_impulses(browser, server, shots):
    """/main?scene=7c&units=SI&pins=10 drew scene 10's contact force (up to 175 N) on the
    axis of 7c's impulses (at most 0.91 N s): the impulses were a flat line at zero."""
    p = Page(browser, server + "?scene=7c&units=SI&pins=10")
    try:
        _wait_readout(p, "compared")
        p.still()
        axis = p.page.evaluate(JS_FORCE_AXIS)
        assert axis["j"] <= axis["end"] < 2 * axis["j"], axis
        assert axis["title"].endswith(
            "\n10: contact force, not comparable with impulses: not drawn"), axis
        force = count_color(p.pixels(".fie-plot-force"), GHOST, GHOST_TOL)
        assert force < MIN_GHOST_PIXELS / 3, force
        p.page.locator(".fie-plot-force").first.screenshot(
            path=shots / "compare-7c-pin-10-force.png")
        assert p.errors == []
    finally:
        p.close()

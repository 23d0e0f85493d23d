"""The explorer in a real browser: every scene draws, sliders repaint, errors show.

Screenshots of every scene and of the interactions are written to the folder printed at the
end of the run (``artifacts/screenshots`` unless ``$SCREENSHOT_DIR`` says otherwise).
"""

from __future__ import annotations

import numpy as np
import pytest
from uipage import JS_READY, Page, count_color

from app.perf import applies
from app.perf import enabled as perf_enabled
from app.plots import MODE_COLORS
from app.scenes import SCENES
from core import Mode

pytestmark = pytest.mark.ui

SLIP, STICK, CONTACT = (MODE_COLORS[int(m)] for m in (Mode.SLIP, Mode.STICK, Mode.CONTACT))
#: Pixels of a mode colour that a drawn trajectory leaves at least (a 2 px line over a few
#: hundred pixels of plot; an empty or failed plot has none).
MIN_TRAJECTORY_PIXELS = 150
#: Mean absolute pixel change that counts as "the picture changed" (0-255 scale).
MIN_CHANGE = 0.5


@pytest.fixture(scope="module")
def page(browser, server):
    p = Page(browser, server)
    yield p
    p.close()


def _select_scene(p: Page, key: str) -> None:
    old = p.text(".fie-caption")
    if SCENES[key].title in old:
        return
    p.page.locator(".fie-scene select").select_option(label=SCENES[key].title)
    p.wait_text_change(".fie-caption", old)
    p.page.wait_for_function("() => Bokeh.documents[0].is_idle")
    p.settle()


@pytest.mark.parametrize("key", list(SCENES))
def test_scene_draws(page, shots, key):
    _select_scene(page, key)
    page.page.screenshot(path=shots / f"scene-{key}.png", full_page=True)
    assert f"Fig. {key}" in page.text(".fie-caption")
    readout = page.text(".fie-readout-pane")
    if key == "2b":
        loop = page.pixels(".fie-plot-loop")
        assert count_color(loop, CONTACT) > MIN_TRAJECTORY_PIXELS
        assert "prescribed overlap" in readout
        assert not page.page.locator(".fie-plot-phase").first.is_visible()
    else:
        assert "Steady state found" in readout and "Regime" in readout
        phase = page.pixels(".fie-plot-phase")
        assert count_color(phase, SLIP) > MIN_TRAJECTORY_PIXELS
        impactless = SCENES[key].values["stop_type"] == "none"
        assert page.page.locator(".fie-plot-force").first.is_visible() is not impactless
        if key in ("10", "11"):
            assert count_color(page.pixels(".fie-plot-loop"), CONTACT) > 50
        elif not impactless:
            assert count_color(page.pixels(".fie-plot-force"), CONTACT) > 50
    assert page.errors == []


def test_slider_drag_repaints(page, shots):
    _select_scene(page, "7b")
    before = page.pixels(".fie-plot-phase")
    readout = page.text(".fie-readout-pane")
    box = page.page.locator(".fie-w-clearance input").first
    typed = float(box.input_value())
    page.drag_slider("clearance", 40)
    after_text = page.wait_text_change(".fie-readout-pane", readout)
    page.still()
    page.settle()
    after = page.pixels(".fie-plot-phase")
    page.page.screenshot(path=shots / "slider-moved.png", full_page=True)
    assert np.abs(after - before).mean() > MIN_CHANGE
    assert "custom" in page.page.locator(".fie-scene select").first.input_value()
    assert after_text != readout
    assert "xbar=" in page.page.url  # the permalink follows
    # The typed-entry box follows the released slider (sent with the new picture): the
    # drag moved right, so the clearance grew.
    assert float(box.input_value()) > typed
    # Every repaint shortcut found the BokehJS internal it replaces (static/perf/), where
    # the server applies them (app.perf: none with EXPLORER_PERF_PATCHES=off).
    assert page.page.evaluate("() => window.__fie_paint") == ([
        "stylesheet", "css-variables", "font-size", "glyph-position", "one-data-update",
        "mask-visuals", "marker-mask", "range-fit-paint"] if applies("paint-shortcuts") else [])
    assert page.errors == []


@pytest.mark.parametrize("key", ["5b", "7c", "10"])
def test_paint_shortcuts_change_no_pixel(browser, server, key):
    """static/perf/bokeh_paint.js makes BokehJS paint faster, never differently: the figures of a
    scene are the same pixels with and without it, when the scene has loaded and after a drag of a
    slider (its preview, the release's hold and the full solution)."""
    seen = {}
    for flag in ("", "&paint_shortcuts=off"):
        p = Page(browser, f"{server}?scene={key}{flag}")
        try:
            p.wait_plots(everywhere=True)  # the screenshot of the plots scrolls past all
            p.still()  # any late repaint lands first
            p.settle()
            loaded = p.pixels(".fie-plots"), _legend_line_ends(p)
            readout = p.text(".fie-readout-pane")
            p.drag_slider("clearance", 30)
            p.wait_text_change(".fie-readout-pane", readout)
            p.still()
            p.settle()
            dragged = p.pixels(".fie-plots"), _legend_line_ends(p)
            seen[flag] = (loaded, dragged, p.page.evaluate("() => window.__fie_paint"),
                          p.errors)
        finally:
            p.close()
    ((on, ends_loaded), (on_dragged, ends_dragged), applied, errors_on), (
        (off, _), (off_dragged, _), none, errors_off) = seen.values()
    assert (len(applied) >= 7) == applies("paint-shortcuts") and none == []
    assert on.shape == off.shape == on_dragged.shape == off_dragged.shape
    # One kind of pixel may differ: the left end of a legend entry's line. BokehJS redraws
    # an entry's small canvas at each paint after clearing it offset by half a pixel, so
    # that end darkens with every repaint, and the shortcuts change how many repaints there
    # are. Every other pixel must be the same. (The drag can show or hide entries, which
    # moves the others.)
    for with_patches, without, ends in ((on, off, ends_loaded),
                                        (on_dragged, off_dragged, ends_dragged)):
        differs = np.abs(with_patches - without).max(axis=2) > 0
        assert not (differs & ~ends).any(), np.argwhere(differs & ~ends)[:10]
    assert not np.array_equal(on, on_dragged)  # the drag changed the picture
    assert errors_on == errors_off == []


#: JavaScript: what release_hold.js does when a slider's release is answered, with a stale
#: preview's paint requested just before: the hold starts, every figure asks for a paint
#: (and, without the hold, BokehJS's 60 fps throttle would take it as a paint), and in that
#: same animation frame the full solution's marker arrives. Returns, per figure, how many
#: animation frames after the marker's it painted.
JS_RELEASE_FRAMES = """async () => {
  const hold = window.__fie_hold;
  const PlotView = Bokeh.require("models/plots/plot_canvas").PlotView;
  const views = [...Bokeh.index.query((v) => v instanceof PlotView)];
  const marker = [...Bokeh.documents[0].all_models].find(
    (m) => Array.isArray(m.css_classes) && m.css_classes.includes("fie-solution-arrived"));
  const frames = [];  // the timestamps of the animation frames seen
  const raf = window.requestAnimationFrame;
  window.requestAnimationFrame = (cb) => raf((ts) => {
    if (frames[frames.length - 1] !== ts) frames.push(ts);
    cb(ts);
  });
  let ticking = true;
  const tick = () => { if (ticking) window.requestAnimationFrame(tick); };
  tick();
  const painted = new Map();
  const proto = PlotView.prototype, paint = proto._actual_paint;
  proto._actual_paint = function (...args) {
    if (!painted.has(this)) painted.set(this, frames.length - 1);
    return paint.apply(this, args);
  };
  let arrived = null;
  try {
    hold.active = true;
    hold.released = new Promise((resolve) => { hold.release = resolve; });
    for (const view of views) view.request_paint();
    await new Promise((resolve) => window.requestAnimationFrame(() => {
      painted.clear();
      arrived = frames.length - 1;
      marker.properties.text.change.emit();
      resolve();
    }));
    await new Promise((resolve) => setTimeout(resolve, 300));
  } finally {
    ticking = false;
    proto._actual_paint = paint;
    window.requestAnimationFrame = raf;
  }
  return views.map((v) => painted.has(v) ? painted.get(v) - arrived : null);
}"""


def test_a_release_paints_every_figure_in_the_next_frame(browser, server, shots):
    """After a slider's release the figures wait for the full solution, then all paint in
    the next animation frame, even those whose stale preview asked for a paint just before
    (release_hold.js holds the request before BokehJS's 60 fps throttle counts it as a
    paint: it used to put those figures one or two frames behind the others, 5 releases in
    40 of scene 7c, the picture showing two states meanwhile)."""
    p = Page(browser, f"{server}?scene=7c")
    try:
        if not applies("release-hold"):  # release_hold.js's patch switched off (app.perf)
            p.still()
            assert "release-hold" not in p.page.evaluate("window.__fie_patches || []")
            return
        p.still()
        p.settle()
        frames = p.page.evaluate(JS_RELEASE_FRAMES)
        p.page.screenshot(path=shots / "release-one-frame.png", full_page=True)
        assert len(frames) >= 6  # phase, x(t), x'(t), force, mechanism, regime map
        assert frames == [1] * len(frames), frames
        assert p.errors == []
    finally:
        p.close()


#: JavaScript: counts, from now on, the changes of the document that the server sends.
JS_COUNT_SERVER_CHANGES = """() => {
  window.__fie_server_changes = 0;
  if (window.__fie_counting) return;
  window.__fie_counting = true;
  Bokeh.documents[0].on_change((event) => {
    if (event.sync === false) window.__fie_server_changes += 1;  // applied from the server
  });
}"""


def test_a_release_after_a_typed_value_is_applied(page, shots):
    """Drag the clearance and release it, type another clearance, then drag the handle back
    to where it was released: that release applies (BokehJS alone sent nothing, as the
    released value had not changed, and the typed value stayed under a draft picture)."""
    _select_scene(page, "5b")
    handle = page.page.locator(".fie-w-clearance .noUi-handle").first
    box = page.page.locator(".fie-w-clearance input").first
    readout = page.text(".fie-readout-pane")
    page.drag_slider("clearance", 30)
    readout = page.wait_text_change(".fie-readout-pane", readout)
    page.settle()
    released = float(box.input_value())
    spot = handle.bounding_box()
    box.fill(f"{released + 0.03:.4f}")
    box.press("Enter")
    readout = page.wait_text_change(".fie-readout-pane", readout)
    page.settle()
    moved = handle.bounding_box()
    assert moved["x"] > spot["x"] + 5  # the handle followed the typed value
    page.page.mouse.move(moved["x"] + moved["width"] / 2, moved["y"] + moved["height"] / 2)
    # Counted from the drag's start: its draft (or the readout's note of it) may come back
    # before the handle is let go.
    page.page.evaluate(JS_COUNT_SERVER_CHANGES)
    page.page.mouse.down()
    page.page.mouse.move(spot["x"] + spot["width"] / 2, spot["y"] + spot["height"] / 2,
                         steps=8)
    page.page.mouse.up()
    if perf_enabled():
        page.wait_text_change(".fie-readout-pane", readout)
    else:
        # The readout will not change: wait for the server's answer to the drag (its
        # draft picture), which comes after any release the browser sent.
        page.page.wait_for_function("() => window.__fie_server_changes > 0", timeout=30_000)
        page.page.wait_for_function(JS_READY, timeout=30_000)
    page.settle()
    page.page.screenshot(path=shots / "release-after-typing.png", full_page=True)
    # Without the Python patches (app.perf.slider) that release is not applied: the typed
    # value stays.
    assert float(box.input_value()) == (released if perf_enabled() else
                                        pytest.approx(released + 0.03))
    assert page.errors == []


def _legend_line_ends(p: Page) -> np.ndarray:
    """Mask of the pixels in the first column of each legend entry's canvas, in the
    coordinates of ``p.pixels(".fie-plots")``."""
    plots = p.page.locator(".fie-plots").first.bounding_box()
    shape = p.pixels(".fie-plots").shape[:2]
    mask = np.zeros(shape, dtype=bool)
    for box in (g.bounding_box() for g in p.page.locator(".fie-plots .bk-glyph").all()):
        if box is None:  # an entry that is not shown
            continue
        x, y = box["x"] - plots["x"], box["y"] - plots["y"]
        rows = slice(max(int(np.floor(y)), 0), int(np.ceil(y + box["height"])))
        mask[rows, max(int(np.floor(x)), 0):int(np.ceil(x)) + 1] = True
    return mask


def test_invalid_input_keeps_the_picture(page, shots):
    _select_scene(page, "5b")
    before = page.pixels(".fie-plot-phase")
    box = page.page.locator(".fie-w-clearance input").first
    box.fill("-0.5")
    box.press("Enter")
    message = page.page.locator(".fie-w-clearance .fie-input-message").first
    message.wait_for(state="visible", timeout=30_000)
    page.settle()
    page.page.screenshot(path=shots / "invalid-input.png", full_page=True)
    assert "ahead of the start" in page.text(".fie-w-clearance .fie-input-message")
    after = page.pixels(".fie-plot-phase")
    assert np.abs(after - before).mean() < MIN_CHANGE
    assert page.errors == []


def test_permalink_reopens_the_same_view(browser, server, shots):
    p = Page(browser, server + "?scene=11")  # a numeric scene name (was misread)
    try:
        assert "Fig. 11" in p.text(".fie-caption")
        assert not p.page.locator(".fie-alert").first.is_visible()
        history = p.page.evaluate("() => history.length")
        readout = p.text(".fie-readout-pane")
        p.page.locator(".fie-w-belt_speed input").first.fill("0.08")
        p.page.locator(".fie-w-belt_speed input").first.press("Enter")
        readout = p.wait_text_change(".fie-readout-pane", readout)
        # The URL follows once the state is still (app.explorer.URL_DELAY_MS).
        p.page.wait_for_function("() => location.search.includes('v=0.08') && "
                                 "location.search.includes('scene=custom')", timeout=10_000)
        url = p.page.url
        # ... in place: no history entry per change (static/url_history.js), where the
        # page applies that patch (app.perf: off with EXPLORER_PERF_PATCHES=off).
        entries = p.page.evaluate("() => history.length")
        assert entries == history if applies("address-in-place") else entries > history
    finally:
        p.close()
    q = Page(browser, url)
    try:
        q.page.screenshot(path=shots / "permalink.png", full_page=True)
        assert float(q.page.locator(".fie-w-belt_speed input").first.input_value()) == 0.08
        assert q.text(".fie-readout-pane").split("Solve")[0] == readout.split("Solve")[0]
        assert q.errors == []
    finally:
        q.close()


#: JavaScript: the animation's time, read from its clock's text ("t = 1.23 of 100").
JS_CLOCK = """() => {
  const clock = [...Bokeh.documents[0].all_models].find(
    (m) => typeof m.text === "string" && m.text.startsWith("t = "));
  return clock == null ? NaN : parseFloat(clock.text.slice(4));
}"""
#: Animation time [dimensionless] between two pictures compared: about a second of play
#: (app.animation.TIME_PER_SECOND), a visible move of the mass.
ANIM_STEP = 2.0


def _clock(page) -> float:
    return page.page.evaluate(JS_CLOCK)


def test_animation_plays_in_the_browser(page, shots):
    _select_scene(page, "5a")
    anim = ".fie-plot-anim"
    first = page.pixels(anim)
    page.page.locator(f"{anim} button").first.click()
    at = _clock(page)
    page.page.wait_for_function(f"old => Math.abs(({JS_CLOCK})() - old) >= {ANIM_STEP}",
                                arg=at, timeout=30_000)
    page.settle()
    second = page.pixels(anim)
    at = _clock(page)
    page.page.wait_for_function(f"old => Math.abs(({JS_CLOCK})() - old) >= {ANIM_STEP}",
                                arg=at, timeout=30_000)
    page.settle()
    third = page.pixels(anim)
    page.page.screenshot(path=shots / "animation.png", full_page=True)
    page.page.locator(f"{anim} button").first.click()  # pause
    assert np.abs(second - first).mean() > 0.1
    assert np.abs(third - second).mean() > 0.1
    assert page.errors == []


def test_si_units_take_seconds_and_metres_per_second(browser, server, shots):
    """In SI mode the horizon is typed in seconds and the start velocity in m/s; the state
    holds their dimensionless values (default m = 0.5 kg, k = 200 N/m: omega = 20 rad/s) and
    the permalink what the boxes say (README, "Links")."""
    p = Page(browser, f"{server}?scene=5b&units=SI")
    try:
        seconds = p.page.locator(".fie-w-t_end_si input").first
        assert seconds.is_visible()
        assert not p.page.locator(".fie-w-t_end input").first.is_visible()
        assert "t_end (s)" in p.text(".fie-w-t_end_si")
        seconds.fill("3")
        seconds.press("Enter")
        p.page.wait_for_function("() => location.search.includes('tend=3.0')",
                                 timeout=30_000)
        speed = p.page.locator(".fie-w-v0_si input").first
        speed.fill("0.5")
        speed.press("Enter")
        p.page.wait_for_function("() => location.search.includes('v0=0.5')", timeout=30_000)
        p.page.wait_for_function("() => Bokeh.documents[0].is_idle")
        p.settle()
        p.page.screenshot(path=shots / "si-units.png", full_page=True)
        assert count_color(p.pixels(".fie-plot-phase"), SLIP) > MIN_TRAJECTORY_PIXELS
        assert not p.page.locator(".fie-alert").first.is_visible()
        assert p.errors == []
    finally:
        p.close()


def test_a_plot_below_the_fold_is_built_when_scrolled_into_view(browser, server, shots):
    """Lazy plots (app.explorer, static/lazy_plots.js): on a 1280 x 800 window, scene 5a's
    regime map waits, empty and of its own height, until it is scrolled into view; then it
    is drawn (its colours appear) without a reload and with no error."""
    p = Page(browser, f"{server}?scene=5a", viewport={"width": 1280, "height": 800})
    try:
        waiting = p.page.locator(".fie-plot-map.fie-plot-pending")
        assert waiting.count() == 1
        assert waiting.first.bounding_box()["height"] > 300  # its place is kept
        figures = "() => [...Bokeh.documents[0].all_models].filter(m => m.type === 'Figure')" \
                  ".map(m => m.title.text)"
        assert not any("Regime map" in t for t in p.page.evaluate(figures))
        p.page.locator(".fie-plot-map").first.scroll_into_view_if_needed()
        p.wait_plots()
        p.still()
        p.settle()
        assert p.page.locator(".fie-plot-pending").count() == 0
        assert any("Regime map" in t for t in p.page.evaluate(figures))
        rgb = p.pixels(".fie-plot-map")
        p.page.locator(".fie-plot-map").first.screenshot(path=shots / "lazy-map-drawn.png")
        assert len(np.unique(rgb.reshape(-1, 3), axis=0)) > 20  # a map, not an empty pane
        assert p.errors == []
    finally:
        p.close()

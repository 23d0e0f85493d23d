"""Long runs in the browser: the window of the last periods, the overview's brush, the
return map's points, and the scene's caption over a longer horizon."""

from __future__ import annotations

import pytest
from uipage import PAGE_TIMEOUT_MS, Page

from app.plots.window import LONG_RUN_PERIODS, WINDOW_PERIODS
from app.state import core_inputs, scene_values
from core import TransitionKind, simulate

pytestmark = pytest.mark.ui

#: The size the views are looked at (a laptop).
LAPTOP = {"width": 1280, "height": 800}
#: Float32 times of up to 5000 (2.4e-4 each) and the range's own arithmetic.
T_TOL = 1e-3

#: JavaScript: the x range of the figure titled ``title``, and the return map's points.
JS_FIGURES = """() => {
  const out = {time: null, force: null, overview: null, points: null, brush: null};
  for (const m of Bokeh.documents[0].all_models) {
    if (m.type === "Figure" || m.type === "figure") {
      const title = m.title && m.title.text !== undefined ? String(m.title.text) : "";
      if (title.startsWith("Displacement x(t)"))
        out.time = [m.x_range.start, m.x_range.end];
      else if (title.startsWith("Impulses") || title.startsWith("Contact force"))
        out.force = [m.x_range.start, m.x_range.end];
      else if (title.startsWith("Whole run"))
        out.overview = {visible: m.visible, x: [m.x_range.start, m.x_range.end]};
      else if (title.startsWith("Return map")) {
        out.return_title = title;
        for (const r of m.renderers)
          if (r.data_source && r.data_source.data.n !== undefined)
            out.points = r.data_source.data.x.length;
      }
    }
    if (m.type === "RangeTool") out.brush = true;
  }
  return out;
}"""
#: JavaScript: brush the overview to ``[lo, hi]`` (what a drag of its box sets: the time
#: figures' shared range, through the RangeTool's model).
JS_BRUSH = """([lo, hi]) => {
  for (const m of Bokeh.documents[0].all_models)
    if (m.type === "RangeTool") { m.x_range.setv({start: lo, end: hi}); return true; }
  return false;
}"""
#: JavaScript: samples of the trajectory between ``lo`` and ``hi``.
JS_SAMPLES_IN = """([lo, hi]) => {
  for (const m of Bokeh.documents[0].all_models)
    if (m.type === "ColumnDataSource" && m.data.mode !== undefined && m.data.t !== undefined) {
      let n = 0;
      for (const t of m.data.t) if (t >= lo && t <= hi) n += 1;
      return n;
    }
  return -1;
}"""


def _run(scene: str, t_end: float | None):
    values = scene_values(scene)
    osc, stop, x0, v0, horizon = core_inputs(values)
    return simulate(osc, stop, t_end or horizon, x0, v0)


def _impacts(res) -> tuple[int, int]:
    """The run's impacts: those core stored (a long grazing run lists those above the
    numbers' resolution, docs/physics.md) and all it counted."""
    kinds = (TransitionKind.IMPACT, TransitionKind.STICK_IMPACT)
    stored = sum(tr.kind in kinds for tr in res.transitions)
    return stored, sum(res.transition_counts.get(k.value, 0) for k in kinds)


@pytest.mark.parametrize(("scene", "t_end"), [("5a", 5000.0), ("7c", 2000.0)])
def test_a_long_run_shows_a_window_an_overview_and_a_return_map(browser, server, shots,
                                                                scene, t_end):
    res = _run(scene, t_end)
    period = res.steady.period
    assert t_end > LONG_RUN_PERIODS * period
    p = Page(browser, f"{server}?scene={scene}&tend={t_end:g}", viewport=LAPTOP)
    try:
        assert f"Fig. {scene}" in p.text(".fie-caption")  # the scene stays
        p.page.wait_for_function(f"() => ({JS_FIGURES})().overview !== null",
                                 timeout=PAGE_TIMEOUT_MS)
        p.still()
        fig = p.page.evaluate(JS_FIGURES)
        lo, hi = fig["time"]
        assert (hi - lo) / period == pytest.approx(WINDOW_PERIODS, abs=T_TOL)
        assert hi == pytest.approx(t_end, abs=T_TOL)
        assert fig["overview"]["visible"] and fig["brush"]
        assert fig["overview"]["x"][1] == pytest.approx(t_end, abs=T_TOL)
        _shoot(p, ".fie-plot-time", shots / f"long-run-{scene}-tend{t_end:g}-window.png")
        # Brushing the overview moves the time figures, and the server samples the new
        # window (its samples fill it as densely as the first window's).
        dense = p.page.evaluate(JS_SAMPLES_IN, [lo, hi])
        new = (0.3 * t_end, 0.3 * t_end + 3 * period)
        sparse = p.page.evaluate(JS_SAMPLES_IN, list(new))
        assert p.page.evaluate(JS_BRUSH, list(new))
        p.page.wait_for_function(f"w => ({JS_SAMPLES_IN})(w) > {max(sparse, dense // 4)}",
                                 arg=list(new), timeout=PAGE_TIMEOUT_MS)
        p.still()
        fig = p.page.evaluate(JS_FIGURES)
        assert fig["time"] == [pytest.approx(new[0], abs=T_TOL), pytest.approx(new[1], abs=T_TOL)]
        _shoot(p, ".fie-plot-time", shots / f"long-run-{scene}-tend{t_end:g}-brushed.png")
        # The contact force, built when scrolled to, shows the same window.
        p.page.locator(".fie-plot-force").first.scroll_into_view_if_needed()
        p.wait_plots()
        p.page.wait_for_function(
            f"w => {{ const f = ({JS_FIGURES})().force; "
            f"return f !== null && Math.abs(f[0] - w[0]) < {T_TOL}; }}", arg=list(new),
            timeout=PAGE_TIMEOUT_MS)
        _check_return_map(p, res, shots / f"long-run-{scene}-tend{t_end:g}-return-map.png")
        assert not p.errors
    finally:
        p.close()


def _shoot(p: Page, css: str, path) -> None:
    """A screenshot of the 1280 x 800 window scrolled to the plot ``css``."""
    p.page.locator(css).first.scroll_into_view_if_needed()
    p.settle()
    p.page.screenshot(path=path)


def _check_return_map(p: Page, res, path) -> None:
    """The return map, scrolled to: one point per pair of successive impacts stored, and
    the title says how many there were in all."""
    p.page.locator(".fie-plot-return").first.scroll_into_view_if_needed()
    p.wait_plots()
    stored, total = _impacts(res)
    n = stored - 1
    p.page.wait_for_function(f"() => ({JS_FIGURES})().points === {n}",
                             timeout=PAGE_TIMEOUT_MS)
    p.still()
    title = p.page.evaluate(JS_FIGURES)["return_title"]
    assert f"({n} points" in title
    assert (f"of {total} impacts" in title) == (total > stored)
    _shoot(p, ".fie-plot-return", path)


def test_scene_7c_keeps_its_caption_when_only_the_horizon_changes(browser, server, shots):
    """Scene 7c as the paper draws it (the whole run, no overview) and its return map of
    the r^h grazing sequence; typing a longer horizon keeps the scene and its caption, and
    opens the window."""
    p = Page(browser, f"{server}?scene=7c", viewport=LAPTOP)
    try:
        res = _run("7c", None)
        fig = p.page.evaluate(JS_FIGURES)
        assert fig["overview"] is None and fig["time"][0] == 0.0
        _check_return_map(p, res, shots / "long-run-7c-return-map.png")
        _shoot(p, ".fie-plot-time", shots / "long-run-7c.png")
        box = p.page.locator(".fie-w-t_end input").first
        box.scroll_into_view_if_needed()
        box.fill("2000")
        box.press("Enter")
        p.page.wait_for_function(f"() => ({JS_FIGURES})().overview !== null",
                                 timeout=PAGE_TIMEOUT_MS)
        assert "Fig. 7c" in p.text(".fie-caption")
        assert not p.errors
    finally:
        p.close()


#: JavaScript: the time figures' window [start, end] once it spans ``width`` (within T_TOL).
JS_WINDOW_WIDTH = f"""w => {{
  const t = ({JS_FIGURES})().time;
  return t !== null && Math.abs((t[1] - t[0]) - w) < {T_TOL};
}}"""

#: JavaScript: the title of the "last N periods" box's model.
JS_BOX_TITLE = """() => [...Bokeh.documents[0].all_models].find(
  m => m.type === "NumericInput" && m.css_classes.includes("fie-last-periods")).title"""

#: JavaScript: the value of the "last N periods" box's model.
JS_BOX_VALUE = """() => [...Bokeh.documents[0].all_models].find(
  m => m.type === "NumericInput" && m.css_classes.includes("fie-last-periods")).value"""


def test_typing_n_shows_the_last_n_periods_and_the_brush_still_moves_the_window(
        browser, server, shots):
    t_end = 2000.0
    res = _run("5a", t_end)
    period = res.steady.period
    count = int(t_end // period)
    p = Page(browser, f"{server}?scene=5a&tend={t_end:g}", viewport=LAPTOP)
    try:
        p.page.wait_for_function(f"() => ({JS_FIGURES})().overview !== null",
                                 timeout=PAGE_TIMEOUT_MS)
        box = p.page.locator(".fie-last-periods input").first
        box.scroll_into_view_if_needed()
        assert box.input_value() == str(WINDOW_PERIODS)
        assert f"(1–{count})" in p.text(".fie-last-periods")
        for n in (12, 1, count):
            box.fill(str(n))
            box.press("Enter")
            p.page.wait_for_function(JS_WINDOW_WIDTH, arg=n * period, timeout=PAGE_TIMEOUT_MS)
            p.still()
            lo, hi = p.page.evaluate(JS_FIGURES)["time"]
            assert hi == pytest.approx(t_end, abs=T_TOL)
            if n == 12:
                # The server sampled the new window (as densely per period as the first).
                assert p.page.evaluate(JS_SAMPLES_IN, [lo, hi]) >= 40 * n
                _shoot(p, ".fie-plot-time", shots / "long-run-5a-last-12-periods.png")
        # A number out of the run is refused in the box's title, and N is shown again
        # (the window unchanged): -2 and 0 were clamped to 1 in the browser, without a word,
        # and where N was 1 already the box kept showing what was typed.
        for bad in ("-2", "0", str(count + 1)):
            box.fill(bad)
            box.press("Enter")
            p.page.wait_for_function(f"t => ({JS_BOX_TITLE})().includes(t)", arg=f"got {bad}",
                                     timeout=PAGE_TIMEOUT_MS)
            p.still()
            assert box.input_value() == str(count)
            assert f"N must be from 1 to {count}; got {bad}" in p.text(".fie-last-periods")
            assert p.page.evaluate(JS_FIGURES)["time"][1] == pytest.approx(t_end, abs=T_TOL)
        # The brush still moves the window; the box is emptied (no "last N" any more).
        new = (0.3 * t_end, 0.3 * t_end + 3 * period)
        assert p.page.evaluate(JS_BRUSH, list(new))
        p.page.wait_for_function(JS_WINDOW_WIDTH, arg=3 * period, timeout=PAGE_TIMEOUT_MS)
        p.page.wait_for_function(f"() => ({JS_BOX_VALUE})() === null", timeout=PAGE_TIMEOUT_MS)
        p.still()
        fig = p.page.evaluate(JS_FIGURES)
        assert fig["time"] == [pytest.approx(new[0], abs=T_TOL), pytest.approx(new[1], abs=T_TOL)]
        # A number after the brush sets the last periods again.
        box.fill("4")
        box.press("Enter")
        p.page.wait_for_function(JS_WINDOW_WIDTH, arg=4 * period, timeout=PAGE_TIMEOUT_MS)
        assert p.page.evaluate(JS_FIGURES)["time"][1] == pytest.approx(t_end, abs=T_TOL)
        assert not p.errors
    finally:
        p.close()

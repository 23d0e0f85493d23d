"""The browser's placement of the theory points' labels (static/point_labels.js), run in
Chromium on the points of the paper's scenes, on a frame where nothing else competes: each
label takes the corner that faces away from the curves through its point."""

from __future__ import annotations

import pytest

from app.plots import PLACE_LABELS_JS, data_bounds, reference_columns
from app.solve.pool import solve
from app.state import scene_values

pytestmark = pytest.mark.ui

#: A frame [px] large enough that no two labels of a scene meet: only the corners'
#: order decides.
FRAME = (2400, 1400)
#: Padding of the frame's ranges around the points (as the portrait's, ample).
PADDING = 0.5

#: Runs the placement as BokehJS would run its ``CustomJS``, on stand-ins of the label set,
#: the figure (no renderers: no marker or curve to avoid) and the stop line; returns the
#: columns it wrote.
JS_PLACE = """async ({code, data, frame, xr, yr, stop}) => {
  const labels = {source: {data}, text: {field: "name"}, text_font_size: "12px",
                  text_font_style: "normal", text_font: "helvetica", change: {emit() {}}};
  const fig = {inner_width: frame[0], inner_height: frame[1], renderers: [],
               x_range: {start: xr[0], end: xr[1]}, y_range: {start: yr[0], end: yr[1]}};
  const line = {visible: stop !== null, location: stop ?? 0, line_width: 3};
  new Function("cb_obj", "labels", "fig", "stop", code)(null, labels, fig, line);
  await new Promise((done) => setTimeout(done, 0));  // the queued placement has run
  return {align: data.align, baseline: data.baseline, name: data.name};
}"""


def _placed(browser, key: str) -> dict[str, tuple[str, str]]:
    sol = solve(scene_values(key))
    pts = reference_columns(sol)["points"]
    page = browser.new_page()
    try:
        out = page.evaluate(JS_PLACE, {
            "code": PLACE_LABELS_JS.read_text(encoding="utf-8"), "data": pts, "frame": FRAME,
            "xr": data_bounds((pts["x"], [sol.stop.clearance]), PADDING),
            "yr": data_bounds((pts["v"],), PADDING), "stop": sol.stop.clearance})
    finally:
        page.close()
    return {n: (a, b) for n, a, b in zip(out["name"], out["align"], out["baseline"],
                                         strict=True)}


@pytest.mark.parametrize("key", ["5b", "7b"])
def test_the_two_ends_of_the_stick_line_label_away_from_each_other(browser, key):
    """The stick starts left of the stop and ends at it, both at x' = v: "stick start" is
    written rightwards above its point, the stop's label leftwards and below its point
    (the two ran into each other when the stick is short)."""
    placed = _placed(browser, key)
    stop_label = next(name for name in placed if name.startswith("stick end"))
    assert placed["stick start"] == ("left", "bottom")
    assert placed[stop_label] == ("right", "top")


@pytest.mark.parametrize("key, align", [("6b", "right"), ("7c", "left")])
def test_the_limit_point_is_labelled_away_from_its_circle(browser, key, align):
    """The limit point on the x axis is labelled above it, on the side away from the
    circle's centre (a, 0): left of the stop in Fig. 6b (the pure slip circle lies beyond
    it), right of it in Fig. 7c (the grazing circle lies short of it)."""
    placed = _placed(browser, key)
    assert placed["limit"] == (align, "bottom")

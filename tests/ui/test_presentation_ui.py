"""Presentation mode and figures for slides in a real browser: the plots fill a projector's
screen (1920x1080 and 1280x720) in one large plot or a 2x2 grid, the sidebar collapsed, the
theory's points named as in the paper; a figure's save button downloads an SVG or a 3x PNG
named after the scene, with a caption line that states the scene and its parameters."""

from __future__ import annotations

import io
import math

import pytest
from uipage import JS_READY, PAGE_TIMEOUT_MS, Page

from app.perf import applies
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
#: Scenes whose point labels and ticks are measured (a stick line and its stop, a limit
#: point short of the slip circle's centre and beyond it, a hysteretic stop).
LABEL_SCENES = ("5a", "6b", "7c", "10")
#: The same in the 2x2 layout, whose portrait is ~130 px high on a 720p screen, and more
#: scenes: four labels round a short stick line and its stop (5a, 5d, 7a, 7b), a stick line
#: short beside a far start (3a, 8a, 8b, 9a, 9b: the labels of its two ends, of the
#: stick->contact and contact->slip points, ran into each other or onto the other end's
#: marker), a limit point inside thin circles (6b).
GRID_LABEL_SCENES = ("3a", "5a", "5d", "6b", "7a", "7b", "7c", "8a", "8b", "9a", "9b", "10")
#: Gap [px] at least between a point's label and a marker, the stop line or another label,
#: and between two neighbouring tick labels.
CLEAR_PX = 1.0
#: JavaScript: on the screen [px], the box of every theory point's label (LabelSet draws on
#: the canvas: its text boxes are made as its view makes them), of its figure's frame, of
#: every marker of that figure (the diamonds of the theory points and the other scatter
#: markers: half widths from size and line width), of the stop line, and of every tick
#: label of the visible axes (recorded while each axis repaints).
JS_LABEL_BOXES = """async () => {
  const frames = () => new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)));
  const {TextBox} = Bokeh.require("core/graphics");
  const models = [...Bokeh.documents[0].all_models];
  const shown = v => {
    const b = v.plot_view.el.getBoundingClientRect();
    return b.width > 0 && b.height > 0;
  };
  const box = (l, t, r, b) => ({l, t, r, b});
  const out = {labels: [], markers: [], stops: [], frames: [], ticks: []};
  for (const lv of Bokeh.index.query(v => v.model.type === "LabelSet")) {
    if (!shown(lv)) continue;
    const m = lv.model, pv = lv.plot_view, {x_scale, y_scale} = lv.coordinates;
    const f = pv.frame.bbox;
    out.frames.push(box(f.left, f.top, f.right, f.bottom));
    for (const r of models.filter(r => r.type === "GlyphRenderer" && r.glyph.type === "Scatter"
                                     && pv.model.renderers.includes(r) && r.glyph.size.value > 0)) {
      const rad = r.glyph.size.value / 2, lw = r.glyph.line_width.value;
      const theory = r.data_source === m.source;
      const hw = (theory ? rad / 1.5 : rad) + lw / 2, hh = rad + lw / 2;
      const xs = r.data_source.data.x, ys = r.data_source.data.v;
      for (let i = 0; i < xs.length; i++) {
        const sx = x_scale.compute(xs[i]), sy = y_scale.compute(ys[i]);
        out.markers.push({theory, i, ...box(sx - hw, sy - hh, sx + hw, sy + hh)});
      }
    }
    const spans = pv.model.center.filter(a => a.type === "Span" && a.dimension === "height");
    for (const s of spans.filter(a => a.visible)) {
      const sx = x_scale.compute(s.location), w = s.line_width / 2;
      out.stops.push(box(sx - w, f.top, sx + w, f.bottom));
    }
    for (let i = 0; i < lv.text.length; i++) {
      const g = new TextBox({text: `${lv.text.get(i)}`});
      g.angle = lv.angle.get(i);
      g.position = {sx: lv.sx[i] + lv.x_offset.get(i), sy: lv.sy[i] - lv.y_offset.get(i)};
      g.visuals = lv.visuals.text.values(i);
      const {p0, p1, p2, p3} = g.rect();
      const xx = [p0.x, p1.x, p2.x, p3.x], yy = [p0.y, p1.y, p2.y, p3.y];
      out.labels.push({text: `${lv.text.get(i)}`, i, frame: out.frames.length - 1,
                       ...box(Math.min(...xx), Math.min(...yy), Math.max(...xx), Math.max(...yy))});
    }
  }
  const axes = [...Bokeh.index.query(v => v.model.type === "LinearAxis")]
    .filter(v => shown(v) && v.model.visible);
  const seen = new Map();
  for (const av of axes) {
    const draw = av._draw_oriented_labels;
    av._draw_oriented_labels = function(ctx, labels, ...rest) {
      draw.call(this, ctx, labels, ...rest);
      seen.set(this, labels.items.map(l => { const b = l.bbox();
        return box(b.left, b.top, b.right, b.bottom); }));
    };
    av.plot_view.request_paint(av);
  }
  await frames();
  await frames();
  for (const av of axes) {
    delete av._draw_oriented_labels;
    out.ticks.push({plot: av.plot_view.model.title.text, axis: av.model.axis_label,
                    dim: av.dimension, labels: seen.get(av) || []});
  }
  return out;
}"""


def _open(browser, url: str, size: dict) -> Page:
    p = Page.__new__(Page)
    p.page = browser.new_page(viewport=size, accept_downloads=True)
    p.errors = []
    p.page.on("console", p._console)
    p.page.on("pageerror", lambda exc: p.errors.append(f"pageerror: {exc}"))
    p.page.goto(url, timeout=PAGE_TIMEOUT_MS)
    p.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
    p.still()  # the layout settles once the plots are filled
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
        p.still()
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
        p.still()
        name, data = _save(p, "phase")
        assert name == "fie_7c_phase.svg"
        svg = data.decode()
        assert svg.startswith("<svg")
        assert "Fig. 7c, rigid stop: v = 0.07, x̄ = 0.24, r = 0.3" in svg
        (shots / name).write_bytes(data)
        # PNG at 3x: the file has three pixels per CSS pixel of the figure.
        q = _open(browser, p.page.url.replace("slides=svg", "slides=png"), SCREENS["1080p"])
        try:
            name, data = _save(q, "phase")
            assert name == "fie_7c_phase.png"
            width = Image.open(io.BytesIO(data)).size[0]
            pane = q.page.locator(".fie-plot-phase").first.bounding_box()["width"]
            # Where the page applies slide-pixel-ratio (app.perf; Chromium's own ratio is 1).
            scale = PNG_SCALE if applies("slide-pixel-ratio") else 1
            assert 0.85 * pane <= width / scale <= pane
            (shots / name).write_bytes(data)
            assert q.errors == []
        finally:
            q.close()
        assert p.errors == []
    finally:
        p.close()


def _hit(a: dict, b: dict, gap: float = CLEAR_PX) -> bool:
    return (a["l"] < b["r"] + gap and b["l"] < a["r"] + gap
            and a["t"] < b["b"] + gap and b["t"] < a["b"] + gap)


def _gap(a: dict, b: dict) -> float:
    """Distance [px] between two boxes along the axis that separates them most (negative:
    they overlap)."""
    return max(b["l"] - a["r"], a["l"] - b["r"], b["t"] - a["b"], a["t"] - b["b"])


def _margin(label: dict, frame: dict) -> float:
    """Distance [px] of a label's box inside its frame's edges (negative: it sticks out)."""
    return min(label["l"] - frame["l"], frame["r"] - label["r"], label["t"] - frame["t"],
               frame["b"] - label["b"])


def _gaps(found: dict) -> tuple[float, float, float]:
    """The least gaps [px] of the labels from :data:`JS_LABEL_BOXES`: to a marker, to
    another label, and to the frame's edge."""
    labels = found["labels"]
    return (min((_gap(a, m) for a in labels for m in found["markers"]), default=math.inf),
            min((_gap(a, b) for k, a in enumerate(labels) for b in labels[k + 1:]),
                default=math.inf),
            min((_margin(a, found["frames"][a["frame"]]) for a in labels), default=math.inf))


def _crowding(found: dict) -> list[str]:
    """What a label or a tick label touches or where it leaves its frame, from
    :data:`JS_LABEL_BOXES`."""
    out = []
    for k, label in enumerate(found["labels"]):
        for marker in found["markers"]:
            if _hit(label, marker):
                kind = "its point" if marker["theory"] and marker["i"] == label["i"] else (
                    "a theory point" if marker["theory"] else "a marker")
                out.append(f"{label['text']} on {kind}")
        out += [f"{label['text']} on the stop" for stop in found["stops"] if _hit(label, stop)]
        out += [f"{label['text']} on {other['text']}" for other in found["labels"][k + 1:]
                if _hit(label, other)]
        if _margin(label, found["frames"][label["frame"]]) < 0:
            out.append(f"{label['text']} out of the frame")
    for axis in found["ticks"]:
        key = "l" if axis["dim"] == 0 else "t"
        boxes = sorted(axis["labels"], key=lambda b: b[key])
        for a, b in zip(boxes, boxes[1:], strict=False):
            gap = b["l"] - a["r"] if axis["dim"] == 0 else b["t"] - a["b"]
            if gap < CLEAR_PX:
                out.append(f"ticks of {axis['plot']} / {axis['axis']} {gap:.1f} px apart")
    return out


@pytest.mark.parametrize("screen", list(SCREENS))
def test_point_labels_clear_their_points_and_tick_labels_do_not_touch(browser, server, shots,
                                                                       screen):
    """The paper's point names sit off their markers (any marker of the portrait: the
    start point, contact markers), off the stop line and off each other, inside the
    portrait's frame, at the presentation's fonts and the page's; no two tick labels of an
    axis touch (the 2x2 layout's stacked x(t), x'(t) plots are ~60 px high on a 720p
    screen)."""
    size = SCREENS[screen]
    p = _open(browser, server + "?scene=5a", size)
    try:
        found = {}
        runs = [(mode, scene) for mode in ("0", "1") for scene in LABEL_SCENES]
        runs += [("4", scene) for scene in GRID_LABEL_SCENES]
        for mode, scene in runs:
            p.page.goto(f"{server}?scene={scene}&present={mode}", timeout=PAGE_TIMEOUT_MS)
            p.page.wait_for_function(JS_READY, timeout=PAGE_TIMEOUT_MS)
            p.still()  # the layout settles once the plots are filled
            p.settle()
            boxes = p.page.evaluate(JS_LABEL_BOXES)
            assert boxes["labels"], (scene, mode)
            found[f"{scene} present={mode}"] = _crowding(boxes)
            marker, label, frame = _gaps(boxes)
            print(f"{screen} {scene} present={mode}: least gap of a label to a marker "
                  f"{marker:.1f} px, to a label {label:.1f} px, to the frame {frame:.1f} px")
            if mode == "4":
                p.page.screenshot(path=shots / f"present-labels-{scene}-{screen}.png")
        assert {k: v for k, v in found.items() if v} == {}
        assert p.errors == []
    finally:
        p.close()
